//! MIP maps: an image and its successively halved copies, and the filtered
//! lookups that pick among them by the size of a lookup's footprint
//! (pbrt-v4 §10.4.3–10.4.4, `util/mipmap.cpp`; Williams, "Pyramidal
//! Parametrics", SIGGRAPH 1983; Heckbert's EWA filter, 1989).
//!
//! Coordinates: a lookup point `st` is in [0, 1]² over the image with
//! `(0, 0)` at the *top-left* corner (image row 0). Texel `(x, y)` of a level
//! `w × h` covers `[x/w, (x+1)/w] × [y/h, (y+1)/h]`, its centre at
//! `((x + ½)/w, (y + ½)/h)`. (Image textures flip `t` before looking up:
//! see [`ImageTexture`](super::ImageTexture).)
//!
//! Differences from pbrt-v4, all documented where they occur:
//! - the pyramid is built by area-weighted box downsampling of the image as
//!   it is (each level `max(1, ⌊w/2⌋) × max(1, ⌊h/2⌋)`), exactly pbrt's 2×2
//!   average for power-of-two sizes; pbrt first resamples other sizes up to
//!   the next power of two with a windowed sinc;
//! - levels are chosen with `log2(width · max(w₀, h₀))`, which equals pbrt's
//!   `levels − 1 + log2(width)` for power-of-two sizes;
//! - trilinear filtering interpolates between levels 0 and 1 too (pbrt-v4
//!   returns level 0 unblended for levels in [0, 1));
//! - all levels stay `f32` (pbrt re-quantises levels of 8-bit images);
//! - the EWA Gaussian `e^{−2r²} − e^{−2}` is evaluated, not tabulated.

use std::ops::{Add, Mul};

use std::path::PathBuf;

use super::image::{ColorEncoding, TextureImage};
use crate::color::Color;
use crate::geometry::Vec2;

/// What a lookup outside [0, 1]² reads (pbrt-v4's `WrapMode`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum WrapMode {
    /// The image tiles the plane.
    #[default]
    Repeat,
    /// The edge texels extend outwards.
    Clamp,
    /// Zero outside the image.
    Black,
    /// The image tiles the plane mirrored every other time, so that edges
    /// meet their own reflection (glTF's `MIRRORED_REPEAT`).
    MirroredRepeat,
}

/// The wrap modes of the two image axes: `s` (across) and `t` (down the
/// rows). pbrt-v4 has one mode for both (`From<WrapMode>`); glTF samplers
/// set `wrapS` and `wrapT` apart.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct WrapModes {
    /// Across the image.
    pub s: WrapMode,
    /// Down the image.
    pub t: WrapMode,
}

impl From<WrapMode> for WrapModes {
    /// The same mode on both axes.
    fn from(mode: WrapMode) -> Self {
        Self { s: mode, t: mode }
    }
}

impl WrapMode {
    /// Parse pbrt-v4's `wrap` parameter: `"repeat"`, `"clamp"` or
    /// `"black"`. (`"octahedralsphere"`, used by pbrt's environment maps,
    /// is not supported for textures.)
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "repeat" => Ok(Self::Repeat),
            "clamp" => Ok(Self::Clamp),
            "black" => Ok(Self::Black),
            _ => Err(format!("unknown wrap mode \"{s}\": expected \"repeat\", \"clamp\" or \"black\"")),
        }
    }

    /// The texel index for `i` in a row of `n`, or `None` (black).
    #[inline]
    fn remap(self, i: i64, n: u32) -> Option<u32> {
        let n = n as i64;
        match self {
            Self::Repeat => Some(i.rem_euclid(n) as u32),
            Self::Clamp => Some(i.clamp(0, n - 1) as u32),
            Self::Black => (0..n).contains(&i).then_some(i as u32),
            Self::MirroredRepeat => {
                // Period 2n: i, then n − 1 − (i − n) back down.
                let j = i.rem_euclid(2 * n);
                Some(if j < n { j } else { 2 * n - 1 - j } as u32)
            }
        }
    }
}

/// How a MIP map is filtered (pbrt-v4's `FilterFunction`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FilterFunction {
    /// The nearest texel of the level the footprint selects.
    Point,
    /// Bilinear interpolation in the level the footprint selects (level 0
    /// for a zero footprint). pbrt-v4's default for image textures.
    #[default]
    Bilinear,
    /// Bilinear in the two levels around the footprint, blended linearly.
    Trilinear,
    /// Elliptically weighted average (Heckbert 1989; pbrt-v4 §10.4.4) over
    /// the anisotropic footprint, blended between two levels.
    Ewa,
}

impl FilterFunction {
    /// Parse pbrt-v4's `filter` parameter: `"point"`, `"bilinear"`,
    /// `"trilinear"`, `"ewa"` (or `"EWA"`).
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "point" => Ok(Self::Point),
            "bilinear" => Ok(Self::Bilinear),
            "trilinear" => Ok(Self::Trilinear),
            "ewa" | "EWA" => Ok(Self::Ewa),
            _ => Err(format!("unknown filter \"{s}\": expected \"point\", \"bilinear\", \"trilinear\" or \"ewa\"")),
        }
    }
}

/// A value a texel can be read as: a colour or a number.
///
/// As a colour, a grey texel is `(v, v, v)` and RGB(A) texels give their
/// RGB. As a number (pbrt-v4's `FloatImageTexture`), a grey texel is its
/// value, an RGB texel the *average* of its channels (pbrt's bilinear
/// path), and an RGBA texel (alpha not 1 everywhere) its alpha, which makes
/// alpha masks work. pbrt-v4's point and EWA paths read channel 0 of an RGB
/// image instead; we average consistently.
pub trait TexelValue: Copy + Default + Add<Output = Self> + Mul<f32, Output = Self> {
    /// The value of a texel's channels (1, 3 or 4 of them).
    fn from_channels(t: &[f32]) -> Self;
}

impl TexelValue for Color {
    #[inline]
    fn from_channels(t: &[f32]) -> Self {
        match t.len() {
            1 => Color::splat(t[0]),
            _ => Color::new(t[0], t[1], t[2]),
        }
    }
}

impl TexelValue for f32 {
    #[inline]
    fn from_channels(t: &[f32]) -> Self {
        match t.len() {
            1 => t[0],
            3 => (t[0] + t[1] + t[2]) / 3.0,
            _ => t[3],
        }
    }
}

/// All four channels of a texel, for reading one of them
/// ([`ImageTexture::evaluate_float`](super::ImageTexture::evaluate_float)
/// with a `channel`): a grey texel is `(v, v, v, 1)`, an RGB texel has
/// alpha 1.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Texel4(pub [f32; 4]);

impl Add for Texel4 {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self(std::array::from_fn(|i| self.0[i] + o.0[i]))
    }
}

impl Mul<f32> for Texel4 {
    type Output = Self;
    #[inline]
    fn mul(self, k: f32) -> Self {
        Self(self.0.map(|v| v * k))
    }
}

impl TexelValue for Texel4 {
    #[inline]
    fn from_channels(t: &[f32]) -> Self {
        match t.len() {
            1 => Self([t[0], t[0], t[0], 1.0]),
            3 => Self([t[0], t[1], t[2], 1.0]),
            _ => Self([t[0], t[1], t[2], t[3]]),
        }
    }
}

/// Filter settings of a lookup.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MipFilterOptions {
    /// The filter.
    pub filter: FilterFunction,
    /// The largest ratio of the EWA ellipse's axes; a longer ellipse is
    /// widened (pbrt-v4 default 8). Values below 1 act as 1, above 64 as 64.
    pub max_anisotropy: f32,
}

impl Default for MipFilterOptions {
    /// pbrt-v4's image-texture defaults: bilinear, anisotropy 8.
    fn default() -> Self {
        Self { filter: FilterFunction::Bilinear, max_anisotropy: 8.0 }
    }
}

/// Where a MIP map's image came from: the file (canonical path) and the
/// colour encoding it was decoded with. Kept so that a scene can be written
/// back out (the TOML exporter names the file instead of the pixels).
#[derive(Clone, Debug, PartialEq)]
pub struct ImageSource {
    /// The image file, canonical (absolute, links resolved).
    pub path: PathBuf,
    /// How its 8-bit values were decoded.
    pub encoding: ColorEncoding,
}

/// An image pyramid: level 0 is the image, each further level half the size
/// (rounded down, at least 1) of the one before, down to 1 × 1.
///
/// Two MIP maps are equal when their pixels are; where they were read from
/// ([`MipMap::source`]) does not count.
#[derive(Clone)]
pub struct MipMap {
    levels: Vec<TextureImage>,
    source: Option<ImageSource>,
}

impl PartialEq for MipMap {
    fn eq(&self, other: &Self) -> bool {
        self.levels == other.levels
    }
}

impl std::fmt::Debug for MipMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MipMap")
            .field("width", &self.levels[0].width())
            .field("height", &self.levels[0].height())
            .field("channels", &self.levels[0].channels())
            .field("levels", &self.levels.len())
            .finish()
    }
}

/// For downsampling a row of `n` to `m = max(1, ⌊n/2⌋)`: output `o`
/// averages the source interval `[o·n/m, (o+1)·n/m)`, each source texel
/// weighted by how much of it lies inside (a box filter; two texels of
/// weight ½ when `n` is even).
fn box_weights(n: u32, m: u32) -> Vec<Vec<(u32, f32)>> {
    let ratio = n as f64 / m as f64;
    (0..m)
        .map(|o| {
            let (a, b) = (o as f64 * ratio, (o + 1) as f64 * ratio);
            let mut w = Vec::new();
            let mut i = a.floor() as u32;
            while (i as f64) < b && i < n {
                let overlap = (b.min(i as f64 + 1.0) - a.max(i as f64)) / ratio;
                if overlap > 0.0 {
                    w.push((i, overlap as f32));
                }
                i += 1;
            }
            w
        })
        .collect()
}

/// The next level of `im`: box-downsampled to half size, separably.
fn downsample(im: &TextureImage) -> Result<TextureImage, String> {
    let (w, h, c) = (im.width(), im.height(), im.channels());
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let (wx, wy) = (box_weights(w, nw), box_weights(h, nh));
    let oom = || format!("not enough memory for a {nw}×{nh} MIP level");
    // Horizontal pass: nw × h.
    let mut tmp: Vec<f32> = Vec::new();
    tmp.try_reserve_exact(nw as usize * h as usize * c).map_err(|_| oom())?;
    let src = im.data();
    for y in 0..h as usize {
        let row = &src[y * w as usize * c..(y + 1) * w as usize * c];
        for ws in &wx {
            for ch in 0..c {
                tmp.push(ws.iter().map(|&(i, wt)| wt * row[i as usize * c + ch]).sum());
            }
        }
    }
    // Vertical pass: nw × nh.
    let mut out = Vec::new();
    out.try_reserve_exact(nw as usize * nh as usize * c).map_err(|_| oom())?;
    let stride = nw as usize * c;
    for ws in &wy {
        for k in 0..stride {
            out.push(ws.iter().map(|&(j, wt)| wt * tmp[j as usize * stride + k]).sum());
        }
    }
    TextureImage::new(nw, nh, c, out)
}

impl MipMap {
    /// The pyramid of `image` (which becomes level 0).
    pub fn new(image: TextureImage) -> Result<Self, String> {
        let mut levels = vec![image];
        loop {
            let last = levels.last().expect("level 0 exists");
            if last.width() == 1 && last.height() == 1 {
                break;
            }
            let next = downsample(last)?;
            levels.push(next);
        }
        Ok(Self { levels, source: None })
    }

    /// The same pyramid, remembering that it was read from `source` (the
    /// [`ImageCache`](super::ImageCache) sets this).
    pub fn with_source(mut self, source: ImageSource) -> Self {
        self.source = Some(source);
        self
    }

    /// The file and encoding the image was read from; `None` for an image
    /// made in memory.
    pub fn source(&self) -> Option<&ImageSource> {
        self.source.as_ref()
    }

    /// Number of levels: `1 + ⌊log2 max(w, h)⌋`.
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// Level `i` (0 = the full image).
    pub fn level(&self, i: usize) -> Option<&TextureImage> {
        self.levels.get(i)
    }

    /// Channels per texel (1, 3 or 4).
    pub fn channels(&self) -> usize {
        self.levels[0].channels()
    }

    /// Texel `(x, y)` of `level` after wrapping (zero where `Black` wraps to
    /// nothing).
    pub fn texel<T: TexelValue>(&self, level: usize, x: i64, y: i64, wrap: impl Into<WrapModes>) -> T {
        let wrap = wrap.into();
        let im = &self.levels[level.min(self.levels.len() - 1)];
        match (wrap.s.remap(x, im.width()), wrap.t.remap(y, im.height())) {
            (Some(x), Some(y)) => T::from_channels(im.texel(x, y).expect("wrapped inside")),
            _ => T::default(),
        }
    }

    /// Bilinear interpolation of the four texels around `st` in `level`
    /// (weights from the distances to the texel centres).
    pub fn bilerp<T: TexelValue>(&self, level: usize, st: Vec2, wrap: impl Into<WrapModes>) -> T {
        let wrap = wrap.into();
        let im = &self.levels[level.min(self.levels.len() - 1)];
        let x = st.x * im.width() as f32 - 0.5;
        let y = st.y * im.height() as f32 - 0.5;
        let (xf, yf) = (x.floor(), y.floor());
        let (dx, dy) = (x - xf, y - yf);
        let (xi, yi) = (xf as i64, yf as i64);
        let t = |i: i64, j: i64| self.texel::<T>(level, i, j, wrap);
        t(xi, yi) * ((1.0 - dx) * (1.0 - dy))
            + t(xi.saturating_add(1), yi) * (dx * (1.0 - dy))
            + t(xi, yi.saturating_add(1)) * ((1.0 - dx) * dy)
            + t(xi.saturating_add(1), yi.saturating_add(1)) * (dx * dy)
    }

    /// The continuous level whose texels are `width` wide (in `st` units):
    /// `log2(width · max(w₀, h₀))`.
    fn level_for_width(&self, width: f32) -> f32 {
        let res = self.levels[0].width().max(self.levels[0].height()) as f32;
        (width.max(1e-8) * res).log2()
    }

    /// The filtered value at `st` for a footprint whose axes are `dst0` and
    /// `dst1` (the changes of `st` from one pixel to the next in x and y;
    /// zero for the finest level). pbrt-v4's `MIPMap::Filter`.
    pub fn filter<T: TexelValue>(
        &self,
        st: Vec2,
        dst0: Vec2,
        dst1: Vec2,
        options: &MipFilterOptions,
        wrap: impl Into<WrapModes>,
    ) -> T {
        let wrap = wrap.into();
        let top = self.levels.len() - 1;
        if options.filter != FilterFunction::Ewa {
            // An isotropic footprint as wide as the largest differential.
            let width = 2.0 * dst0.abs().max_element().max(dst1.abs().max_element());
            let level = self.level_for_width(width);
            if level.is_nan() || level >= top as f32 {
                return self.texel(top, 0, 0, wrap);
            }
            let i = level.floor().max(0.0) as usize;
            return match options.filter {
                FilterFunction::Point => {
                    let im = &self.levels[i];
                    let x = (st.x * im.width() as f32 - 0.5).round() as i64;
                    let y = (st.y * im.height() as f32 - 0.5).round() as i64;
                    self.texel(i, x, y, wrap)
                }
                FilterFunction::Bilinear => self.bilerp(i, st, wrap),
                _ => {
                    if level <= 0.0 {
                        self.bilerp(0, st, wrap)
                    } else {
                        let f = level - i as f32;
                        self.bilerp::<T>(i, st, wrap) * (1.0 - f) + self.bilerp::<T>(i + 1, st, wrap) * f
                    }
                }
            };
        }
        // EWA: the longer axis first; limit the eccentricity by widening the
        // shorter axis (which also bounds the texels visited).
        let (mut major, mut minor) = (dst0, dst1);
        if major.length_squared() < minor.length_squared() {
            std::mem::swap(&mut major, &mut minor);
        }
        let max_aniso = options.max_anisotropy.clamp(1.0, 64.0);
        let longer = major.length();
        let mut shorter = minor.length();
        if shorter * max_aniso < longer && shorter > 0.0 {
            let s = longer / (shorter * max_aniso);
            minor *= s;
            shorter *= s;
        }
        if shorter == 0.0 || !shorter.is_finite() || !longer.is_finite() {
            return self.bilerp(0, st, wrap);
        }
        // The level where the shorter axis spans about one texel.
        let lod = self.level_for_width(shorter).max(0.0);
        let il = lod.floor();
        let f = lod - il;
        let il = il as usize;
        self.ewa::<T>(il, st, major, minor, wrap) * (1.0 - f) + self.ewa::<T>(il + 1, st, major, minor, wrap) * f
    }

    /// The colour at `st` (see [`MipMap::filter`]).
    pub fn filter_rgb(
        &self,
        st: Vec2,
        dst0: Vec2,
        dst1: Vec2,
        options: &MipFilterOptions,
        wrap: impl Into<WrapModes>,
    ) -> Color {
        self.filter(st, dst0, dst1, options, wrap)
    }

    /// The number at `st` (see [`MipMap::filter`] and [`TexelValue`]).
    pub fn filter_float(
        &self,
        st: Vec2,
        dst0: Vec2,
        dst1: Vec2,
        options: &MipFilterOptions,
        wrap: impl Into<WrapModes>,
    ) -> f32 {
        self.filter(st, dst0, dst1, options, wrap)
    }

    /// The EWA filter over one level (pbrt-v4 §10.4.4): texels inside the
    /// ellipse `A s² + B s t + C t² < 1` spanned by the axes (in texel units,
    /// each widened by one texel so that it covers at least a texel),
    /// weighted by the Gaussian `e^{−2r²} − e^{−2}` of their radius.
    fn ewa<T: TexelValue>(&self, level: usize, st: Vec2, d0: Vec2, d1: Vec2, wrap: WrapModes) -> T {
        if level >= self.levels.len() {
            return self.texel(self.levels.len() - 1, 0, 0, wrap);
        }
        let im = &self.levels[level];
        let res = Vec2::new(im.width() as f32, im.height() as f32);
        let c = st * res - Vec2::splat(0.5);
        let (d0, d1) = (d0 * res, d1 * res);
        let mut a = d0.y * d0.y + d1.y * d1.y + 1.0;
        let mut b = -2.0 * (d0.x * d0.y + d1.x * d1.y);
        let mut cc = d0.x * d0.x + d1.x * d1.x + 1.0;
        let inv_f = 1.0 / (a * cc - b * b * 0.25);
        a *= inv_f;
        b *= inv_f;
        cc *= inv_f;
        // The ellipse's bounding box.
        let det = -b * b + 4.0 * a * cc;
        let inv_det = 1.0 / det;
        let u = (det * cc).max(0.0).sqrt();
        let v = (a * det).max(0.0).sqrt();
        let s0 = (c.x - 2.0 * inv_det * u).ceil() as i64;
        let s1 = (c.x + 2.0 * inv_det * u).floor() as i64;
        let t0 = (c.y - 2.0 * inv_det * v).ceil() as i64;
        let t1 = (c.y + 2.0 * inv_det * v).floor() as i64;
        let floor_weight = (-2.0f32).exp();
        let mut sum = T::default();
        let mut sum_w = 0.0f32;
        for it in t0..=t1 {
            let tt = it as f32 - c.y;
            for is in s0..=s1 {
                let ss = is as f32 - c.x;
                let r2 = a * ss * ss + b * ss * tt + cc * tt * tt;
                if r2 < 1.0 {
                    let w = (-2.0 * r2).exp() - floor_weight;
                    sum = sum + self.texel::<T>(level, is, it, wrap) * w;
                    sum_w += w;
                }
            }
        }
        if sum_w > 0.0 {
            sum * (1.0 / sum_w)
        } else {
            self.bilerp(level, st, wrap)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, c: usize, data: &[f32]) -> TextureImage {
        TextureImage::new(w, h, c, data.to_vec()).unwrap()
    }

    /// The 2×2 grey image  [1 2]
    ///                     [3 4]  (row 0 on top).
    fn two_by_two() -> MipMap {
        MipMap::new(image(2, 2, 1, &[1.0, 2.0, 3.0, 4.0])).unwrap()
    }

    fn bilerp(m: &MipMap, s: f32, t: f32, wrap: WrapMode) -> f32 {
        m.bilerp::<f32>(0, Vec2::new(s, t), wrap)
    }

    #[test]
    fn bilinear_at_and_between_texel_centres() {
        let m = two_by_two();
        // Centres at 0.25 and 0.75.
        assert_eq!(bilerp(&m, 0.25, 0.25, WrapMode::Clamp), 1.0);
        assert_eq!(bilerp(&m, 0.75, 0.25, WrapMode::Clamp), 2.0);
        assert_eq!(bilerp(&m, 0.25, 0.75, WrapMode::Clamp), 3.0);
        assert_eq!(bilerp(&m, 0.75, 0.75, WrapMode::Clamp), 4.0);
        // Halfway: the mean of all four; a quarter of the way across in s.
        assert_eq!(bilerp(&m, 0.5, 0.5, WrapMode::Clamp), 2.5);
        assert_eq!(bilerp(&m, 0.375, 0.25, WrapMode::Clamp), 1.25);
        // s 0.375 (¼ of the way), t 0.625 (¾ of the way):
        // ¾·¼·1 + ¼·¼·2 + ¾·¾·3 + ¼·¾·4 = (3 + 2 + 27 + 12)/16.
        assert_eq!(bilerp(&m, 0.375, 0.625, WrapMode::Clamp), 44.0 / 16.0);
    }

    #[test]
    fn wrap_modes_at_minus_a_quarter_and_one_and_a_quarter() {
        let m = two_by_two();
        // s = −0.25 → x = −1 exactly (a texel centre); s = 1.25 → x = 2.
        // Repeat: column −1 is column 1, column 2 is column 0.
        assert_eq!(bilerp(&m, -0.25, 0.25, WrapMode::Repeat), 2.0);
        assert_eq!(bilerp(&m, 1.25, 0.25, WrapMode::Repeat), 1.0);
        // Clamp: the edge columns.
        assert_eq!(bilerp(&m, -0.25, 0.25, WrapMode::Clamp), 1.0);
        assert_eq!(bilerp(&m, 1.25, 0.25, WrapMode::Clamp), 2.0);
        // Black: zero outside.
        assert_eq!(bilerp(&m, -0.25, 0.25, WrapMode::Black), 0.0);
        assert_eq!(bilerp(&m, 1.25, 0.75, WrapMode::Black), 0.0);
        // Between the last texel centre and the edge: half black.
        assert_eq!(bilerp(&m, 1.0, 0.25, WrapMode::Black), 1.0);
        assert_eq!(bilerp(&m, 1.0, 0.25, WrapMode::Repeat), 1.5);
        // In t too.
        assert_eq!(bilerp(&m, 0.25, -0.25, WrapMode::Repeat), 3.0);
        assert_eq!(bilerp(&m, 0.25, 1.25, WrapMode::Clamp), 3.0);
        assert_eq!(WrapMode::parse("clamp").unwrap(), WrapMode::Clamp);
        assert!(WrapMode::parse("mirror").is_err());
    }

    #[test]
    fn levels_are_box_averages() {
        let data: Vec<f32> = (0..16).map(|i| i as f32).collect();
        let m = MipMap::new(image(4, 4, 1, &data)).unwrap();
        assert_eq!(m.levels(), 3);
        let l1 = m.level(1).unwrap();
        assert_eq!((l1.width(), l1.height()), (2, 2));
        // Top-left 2×2 block: 0 1 4 5 → 2.5; then 4.5, 10.5, 12.5.
        assert_eq!(l1.data(), &[2.5, 4.5, 10.5, 12.5]);
        assert_eq!(m.level(2).unwrap().data(), &[7.5]);
    }

    #[test]
    fn odd_and_non_square_sizes_keep_the_mean() {
        // 3×1 → 1×1: the mean.
        let m = MipMap::new(image(3, 1, 1, &[1.0, 2.0, 6.0])).unwrap();
        assert_eq!(m.levels(), 2);
        assert!((m.level(1).unwrap().data()[0] - 3.0).abs() < 1e-6);
        // 5×2 → 2×1: [0, 2.5) and [2.5, 5) of each row, averaged over rows.
        let m = MipMap::new(image(5, 2, 1, &[1.0, 1.0, 1.0, 3.0, 3.0, 1.0, 1.0, 1.0, 3.0, 3.0])).unwrap();
        let l1 = m.level(1).unwrap();
        assert_eq!((l1.width(), l1.height()), (2, 1));
        assert!((l1.data()[0] - 1.0).abs() < 1e-6);
        assert!((l1.data()[1] - (0.5 + 2.0 * 3.0) / 2.5).abs() < 1e-6);
        assert_eq!(m.levels(), 3);
        // RGB channels stay apart.
        let m = MipMap::new(image(2, 1, 3, &[1.0, 0.0, 2.0, 3.0, 4.0, 0.0])).unwrap();
        assert_eq!(m.level(1).unwrap().data(), &[2.0, 2.0, 1.0]);
    }

    #[test]
    fn trilinear_halfway_between_levels() {
        // 4×4 with a left half of 0 and a right half of 1 in level 0 at
        // one point; constant levels make the blend weight visible.
        let data: Vec<f32> = (0..16).map(|i| if i % 4 < 2 { 0.0 } else { 4.0 }).collect();
        let m = MipMap::new(image(4, 4, 1, &data)).unwrap();
        let opts = MipFilterOptions { filter: FilterFunction::Trilinear, max_anisotropy: 8.0 };
        let st = Vec2::new(0.125, 0.5); // level 0: 0; level 1: 0; level 2: 2
                                        // width = 2·d; level = log2(width · 4). d = 1/4 → width ½ → level 1;
                                        // d = 2^-1.5 → level 1.5: halfway between level 1 (0) and level 2 (2).
        let d = |d: f32| Vec2::new(d, 0.0);
        assert_eq!(m.filter_float(st, d(0.0), d(0.0), &opts, WrapMode::Clamp), 0.0);
        assert!((m.filter_float(st, d(0.25), d(0.0), &opts, WrapMode::Clamp) - 0.0).abs() < 1e-6);
        let half = m.filter_float(st, d(2f32.powf(-1.5)), d(0.0), &opts, WrapMode::Clamp);
        assert!((half - 1.0).abs() < 1e-5, "{half}");
        // Between levels 0 and 1 as well: at s = 0.375 level 0 is 0, level
        // 1 is 1 (its texel centres 0.25 → 0, 0.75 → 4: bilinear gives 1).
        let st = Vec2::new(0.375, 0.5);
        let half01 = m.filter_float(st, d(2f32.powf(-2.5)), d(0.0), &opts, WrapMode::Clamp);
        assert!((half01 - 0.5).abs() < 1e-5, "{half01}");
        // A footprint wider than the image: the 1×1 top level.
        assert_eq!(m.filter_float(st, d(4.0), d(0.0), &opts, WrapMode::Clamp), 2.0);
    }

    #[test]
    fn point_and_bilinear_choose_a_level() {
        let data: Vec<f32> = (0..16).map(|i| i as f32).collect();
        let m = MipMap::new(image(4, 4, 1, &data)).unwrap();
        let point = MipFilterOptions { filter: FilterFunction::Point, max_anisotropy: 8.0 };
        let bil = MipFilterOptions::default();
        let z = Vec2::ZERO;
        // Point, level 0: the texel containing st.
        assert_eq!(m.filter_float(Vec2::new(0.3, 0.6), z, z, &point, WrapMode::Clamp), 9.0);
        // Footprint ¼ → level 1: texel (0, 1) of level 1 = 10.5.
        let d = Vec2::new(0.25, 0.0);
        assert_eq!(m.filter_float(Vec2::new(0.3, 0.6), d, z, &point, WrapMode::Clamp), 10.5);
        assert_eq!(m.filter_float(Vec2::new(0.25, 0.75), d, z, &bil, WrapMode::Clamp), 10.5);
        assert_eq!(FilterFunction::parse("EWA").unwrap(), FilterFunction::Ewa);
        assert!(FilterFunction::parse("box").is_err());
    }

    #[test]
    fn ewa_of_a_constant_is_the_constant_and_zero_footprint_is_bilinear() {
        let m = MipMap::new(image(8, 8, 3, &[0.5; 8 * 8 * 3])).unwrap();
        let opts = MipFilterOptions { filter: FilterFunction::Ewa, max_anisotropy: 8.0 };
        let c =
            m.filter_rgb(Vec2::new(0.3, 0.7), Vec2::new(0.1, 0.02), Vec2::new(-0.01, 0.03), &opts, WrapMode::Repeat);
        assert!((c - Color::splat(0.5)).abs().max_element() < 1e-5, "{c}");
        let m = two_by_two();
        let st = Vec2::new(0.375, 0.625);
        assert_eq!(m.filter_float(st, Vec2::ZERO, Vec2::ZERO, &opts, WrapMode::Clamp), 44.0 / 16.0);
    }

    #[test]
    fn ewa_weights_follow_the_ellipse() {
        // A vertical stripe pattern (columns alternate 0, 1) of 16×16: a
        // footprint stretched along s averages the stripes to ½; one
        // stretched along t (thin in s) keeps the stripe at a texel centre
        // mostly intact.
        let data: Vec<f32> = (0..256).map(|i| (i % 2) as f32).collect();
        let m = MipMap::new(image(16, 16, 1, &data)).unwrap();
        let opts = MipFilterOptions { filter: FilterFunction::Ewa, max_anisotropy: 8.0 };
        let st = Vec2::new(1.5 / 16.0, 0.5); // centre of column 1 (value 1)
        let along_s = m.filter_float(st, Vec2::new(0.25, 0.0), Vec2::new(0.0, 1.0 / 256.0), &opts, WrapMode::Repeat);
        assert!((along_s - 0.5).abs() < 0.05, "{along_s}");
        let along_t = m.filter_float(st, Vec2::new(0.0, 0.25), Vec2::new(1.0 / 256.0, 0.0), &opts, WrapMode::Repeat);
        assert!(along_t > 0.75, "{along_t}");
    }

    #[test]
    fn float_reads_of_rgb_and_rgba() {
        assert_eq!(f32::from_channels(&[0.25, 0.5, 0.75]), 0.5);
        assert_eq!(f32::from_channels(&[0.3, 0.6, 0.9, 0.25]), 0.25);
        assert_eq!(Color::from_channels(&[0.5]), Color::splat(0.5));
        assert_eq!(Color::from_channels(&[0.1, 0.2, 0.3, 0.0]), Color::new(0.1, 0.2, 0.3));
    }

    #[test]
    fn huge_and_nan_coordinates_do_not_panic() {
        let m = two_by_two();
        for wrap in [WrapMode::Repeat, WrapMode::Clamp, WrapMode::Black] {
            for s in [f32::NAN, f32::INFINITY, -1e30, 1e30] {
                for filter in
                    [FilterFunction::Point, FilterFunction::Bilinear, FilterFunction::Trilinear, FilterFunction::Ewa]
                {
                    let o = MipFilterOptions { filter, max_anisotropy: 8.0 };
                    let _ = m.filter_float(Vec2::new(s, 0.5), Vec2::new(s, 0.1), Vec2::new(0.1, s), &o, wrap);
                }
            }
        }
    }
}
