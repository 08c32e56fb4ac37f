//! pbrt-v4's `imagemap` texture: a MIP-mapped image looked up through a
//! texture mapping (pbrt-v4 §10.4.2, `SpectrumImageTexture` and
//! `FloatImageTexture`).

use std::sync::Arc;

use super::mapping::TextureMapping;
use super::mipmap::{FilterFunction, MipFilterOptions, MipMap, WrapMode, WrapModes};
use super::TextureContext;
use crate::color::Color;
use crate::geometry::Vec2;

/// The lookup parameters of an image texture, with pbrt-v4's defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageTextureParams {
    /// `filter` (default `"bilinear"`).
    pub filter: FilterFunction,
    /// `maxanisotropy` (default 8; used by EWA only).
    pub max_anisotropy: f32,
    /// `wrap` (default `"repeat"`), per axis.
    pub wrap: WrapModes,
    /// `scale`: multiplies every value (default 1).
    pub scale: f32,
    /// `invert`: `1 − value`, clamped at 0 (default false).
    pub invert: bool,
    /// For a float texture: the one channel it reads (0 red, 1 green, 2
    /// blue, 3 alpha; grey images have grey in 0–2 and alpha 1), as glTF
    /// reads roughness from green and metallic from blue. `None` (the
    /// default) is pbrt-v4's rule (see
    /// [`TexelValue`](super::mipmap::TexelValue)).
    pub channel: Option<u8>,
}

impl Default for ImageTextureParams {
    fn default() -> Self {
        Self {
            filter: FilterFunction::Bilinear,
            max_anisotropy: 8.0,
            wrap: WrapModes::from(WrapMode::Repeat),
            scale: 1.0,
            invert: false,
            channel: None,
        }
    }
}

/// An image texture: a shared [`MipMap`] (from an
/// [`ImageCache`](super::ImageCache)) with its own mapping and parameters.
/// The same value serves colour ([`Texture::image`](super::Texture::image))
/// and float ([`FloatTexture::image`](super::FloatTexture::image))
/// textures.
///
/// Texture space has `t` pointing up, images have row 0 at the top, so the
/// lookup is at `(s, 1 − t)` (pbrt-v4: `c.st[1] = 1 - c.st[1]`): `(0, 0)`
/// is the image's *bottom-left* corner, `(0, 1)` its top-left.
///
/// The filter footprint is the mapping's derivatives, from the
/// [`TextureContext`]'s differentials; without them (all zero, as from
/// [`TextureContext::from_uv`]) every filter reads the finest level.
#[derive(Clone, Debug)]
pub struct ImageTexture {
    mapping: TextureMapping,
    mipmap: Arc<MipMap>,
    params: ImageTextureParams,
}

impl PartialEq for ImageTexture {
    fn eq(&self, other: &Self) -> bool {
        self.mapping == other.mapping
            && self.params == other.params
            && (Arc::ptr_eq(&self.mipmap, &other.mipmap) || self.mipmap == other.mipmap)
    }
}

impl ImageTexture {
    /// An image texture over `mipmap`.
    pub fn new(mapping: TextureMapping, mipmap: Arc<MipMap>, params: ImageTextureParams) -> Self {
        Self { mapping, mipmap, params }
    }

    /// The mapping.
    pub fn mapping(&self) -> &TextureMapping {
        &self.mapping
    }

    /// The shared pyramid.
    pub fn mipmap(&self) -> &Arc<MipMap> {
        &self.mipmap
    }

    /// The image file this texture reads, if it was read from one (through
    /// an [`ImageCache`](super::ImageCache)); `None` for an image made in
    /// memory.
    pub fn source(&self) -> Option<&std::path::Path> {
        self.mipmap.source().map(|s| s.path.as_path())
    }

    /// The lookup parameters.
    pub fn params(&self) -> &ImageTextureParams {
        &self.params
    }

    /// The same texture with its `scale` multiplied by `s` (how pbrt-v4
    /// folds a constant `scale` texture into an image texture).
    pub fn scaled(&self, s: f32) -> Self {
        let mut t = self.clone();
        t.params.scale *= s;
        t
    }

    /// The image coordinates and footprint of `ctx`: `t` flipped, and its
    /// derivatives with it.
    fn lookup<T: super::mipmap::TexelValue>(&self, ctx: &TextureContext) -> T {
        let c = self.mapping.map(ctx);
        let st = Vec2::new(c.st.x, 1.0 - c.st.y);
        // pbrt-v4 keeps the sign of ∂t; negating it with t keeps an EWA
        // ellipse's orientation right (the widths are the same).
        let dst0 = Vec2::new(c.dsdx, -c.dtdx);
        let dst1 = Vec2::new(c.dsdy, -c.dtdy);
        let opts = MipFilterOptions { filter: self.params.filter, max_anisotropy: self.params.max_anisotropy };
        self.mipmap.filter(st, dst0, dst1, &opts, self.params.wrap)
    }

    /// The colour at `ctx`: `scale ×` the filtered texel, then `1 − ·` if
    /// inverted, clamped at zero (pbrt-v4 `SpectrumImageTexture`). Grey
    /// images give grey colours.
    pub fn evaluate_rgb(&self, ctx: &TextureContext) -> Color {
        let rgb = self.params.scale * self.lookup::<Color>(ctx);
        let rgb = if self.params.invert { Color::ONE - rgb } else { rgb };
        rgb.max(Color::ZERO)
    }

    /// The number at `ctx`: `scale ×` the filtered texel (its `channel` if
    /// one is set, else the grey value, mean of RGB, or alpha of an RGBA
    /// image with real alpha; see
    /// [`TexelValue`](super::mipmap::TexelValue)), then `max(0, 1 − ·)` if
    /// inverted (pbrt-v4 `FloatImageTexture`: not clamped otherwise).
    pub fn evaluate_float(&self, ctx: &TextureContext) -> f32 {
        let v = match self.params.channel {
            None => self.lookup::<f32>(ctx),
            Some(c) => self.lookup::<super::mipmap::Texel4>(ctx).0[usize::from(c.min(3))],
        };
        let v = self.params.scale * v;
        if self.params.invert {
            (1.0 - v).max(0.0)
        } else {
            v
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::image::TextureImage;

    /// 2×2 RGB: top row red, green; bottom row blue, white.
    fn quad() -> Arc<MipMap> {
        #[rustfmt::skip]
        let data = vec![
            1.0, 0.0, 0.0,   0.0, 1.0, 0.0,
            0.0, 0.0, 1.0,   1.0, 1.0, 1.0,
        ];
        Arc::new(MipMap::new(TextureImage::new(2, 2, 3, data).unwrap()).unwrap())
    }

    fn uv(u: f32, v: f32) -> TextureContext {
        TextureContext::from_uv(Vec2::new(u, v))
    }

    #[test]
    fn t_is_flipped_uv_origin_is_the_bottom_left() {
        let t = ImageTexture::new(TextureMapping::default(), quad(), ImageTextureParams::default());
        // (u, v) = (¼, ¼): bottom-left texel (blue); (¼, ¾): top-left (red).
        assert_eq!(t.evaluate_rgb(&uv(0.25, 0.25)), Color::new(0.0, 0.0, 1.0));
        assert_eq!(t.evaluate_rgb(&uv(0.25, 0.75)), Color::new(1.0, 0.0, 0.0));
        assert_eq!(t.evaluate_rgb(&uv(0.75, 0.75)), Color::new(0.0, 1.0, 0.0));
        assert_eq!(t.evaluate_rgb(&uv(0.75, 0.25)), Color::ONE);
        // Float: the channel mean.
        assert!((t.evaluate_float(&uv(0.25, 0.75)) - 1.0 / 3.0).abs() < 1e-7);
        assert_eq!(t.evaluate_float(&uv(0.75, 0.25)), 1.0);
    }

    #[test]
    fn scale_and_invert() {
        let p = ImageTextureParams { scale: 0.5, ..Default::default() };
        let t = ImageTexture::new(TextureMapping::default(), quad(), p);
        assert_eq!(t.evaluate_rgb(&uv(0.75, 0.25)), Color::splat(0.5));
        let p = ImageTextureParams { scale: 0.5, invert: true, ..Default::default() };
        let t = ImageTexture::new(TextureMapping::default(), quad(), p);
        // 1 − 0.5·(0, 0, 1) = (1, 1, 0.5).
        assert_eq!(t.evaluate_rgb(&uv(0.25, 0.25)), Color::new(1.0, 1.0, 0.5));
        assert!((t.evaluate_float(&uv(0.25, 0.25)) - (1.0 - 0.5 / 3.0)).abs() < 1e-6);
        // Inversion clamps at zero: scale 3 on white → 1 − 3 → 0.
        let p = ImageTextureParams { scale: 3.0, invert: true, ..Default::default() };
        let t = ImageTexture::new(TextureMapping::default(), quad(), p);
        assert_eq!(t.evaluate_rgb(&uv(0.75, 0.25)), Color::ZERO);
        assert_eq!(t.evaluate_float(&uv(0.75, 0.25)), 0.0);
        assert_eq!(t.scaled(2.0).params().scale, 6.0);
    }

    #[test]
    fn wrap_and_mapping_apply() {
        let p = ImageTextureParams { wrap: WrapMode::Black.into(), ..Default::default() };
        let t = ImageTexture::new(TextureMapping::default(), quad(), p);
        assert_eq!(t.evaluate_rgb(&uv(1.25, 0.25)), Color::ZERO);
        let t = ImageTexture::new(TextureMapping::default(), quad(), ImageTextureParams::default());
        assert_eq!(t.evaluate_rgb(&uv(1.25, 0.25)), Color::new(0.0, 0.0, 1.0));
        // uscale 2: u = 0.375 → s = 0.75.
        let t = ImageTexture::new(TextureMapping::uv(2.0, 1.0, 0.0, 0.0), quad(), ImageTextureParams::default());
        assert_eq!(t.evaluate_rgb(&uv(0.375, 0.25)), Color::ONE);
    }

    #[test]
    fn a_footprint_selects_a_coarser_level() {
        let p = ImageTextureParams { filter: FilterFunction::Trilinear, ..Default::default() };
        let t = ImageTexture::new(TextureMapping::default(), quad(), p);
        // Footprint of the whole image: the 1×1 average (½, ½, ½).
        let ctx = uv(0.25, 0.25).with_footprint(1.0, crate::geometry::Vec3::X, crate::geometry::Vec3::Y);
        assert_eq!(t.evaluate_rgb(&ctx), Color::splat(0.5));
    }
}
