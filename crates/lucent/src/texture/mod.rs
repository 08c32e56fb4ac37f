//! Textures: colours ([`Texture`]) and numbers ([`FloatTexture`]) that
//! vary over a surface, evaluated at a [`TextureContext`].
//!
//! The classes are pbrt-v4's (book §10.3–10.4, `textures.h`), for both
//! value types:
//!
//! | pbrt-v4 | constructor | value |
//! |---|---|---|
//! | `constant` | [`Texture::Constant`], `From<Color>` / `From<f32>` | the value |
//! | `imagemap` | [`Texture::image`] with an [`ImageTexture`] | a filtered image lookup |
//! | `scale` | [`Texture::scale`] | `tex × scale` (`scale` a float texture) |
//! | `mix` | [`Texture::mix`] | `(1 − amount)·tex1 + amount·tex2` (`amount` a float texture) |
//! | `directionmix` | [`Texture::direction_mix`] | `a·tex1 + (1 − a)·tex2`, `a = |n · dir|` |
//! | `checkerboard` | [`Texture::checkerboard`], [`Texture::checkerboard_3d`] | `tex1` on even squares, `tex2` on odd ones |
//! | `bilerp` | [`Texture::bilerp`] | bilinear in `(s, t)` between four corner values |
//!
//! Three more are lucent's own, for glTF's materials and meshes with vertex
//! colours: [`Texture::VertexColor`] and [`FloatTexture::VertexAlpha`] read
//! the interpolated vertex colour of a mesh ([`VertexAttributes`]), and
//! [`Texture::product`] multiplies two colour textures channel by channel.
//!
//! Nested textures are held by [`Arc`]: a texture named once in a scene file
//! and used by several textures or materials is stored once. Every
//! constructor that takes a nested texture accepts a texture or an `Arc` of
//! one (`impl Into<Arc<_>>`).
//!
//! Image files go through an [`ImageCache`] (one per scene load), which
//! returns a shared [`MipMap`] per file and encoding; an [`ImageTexture`]
//! adds a [`TextureMapping`] and the lookup parameters
//! ([`ImageTextureParams`]).
//!
//! Filtering needs a footprint: [`TextureContext`] carries pbrt-v4's screen
//! differentials (`dpdx`, `dpdy`, `dudx` …). Without ray differentials they
//! stay zero (every lookup reads the finest MIP level and checkerboards
//! are point-sampled), or the caller sets an estimate with
//! [`TextureContext::with_footprint`].

mod cache;
mod image;
mod imagemap;
mod mapping;
mod mipmap;

use std::sync::Arc;

pub use self::image::{decode_image, read_image, read_pfm, ColorEncoding, ImageError, TextureImage};
pub use cache::ImageCache;
pub use imagemap::{ImageTexture, ImageTextureParams};
pub use mapping::{TexCoord2D, TextureMapping};
pub use mipmap::{FilterFunction, ImageSource, MipFilterOptions, MipMap, TexelValue, WrapMode, WrapModes};

use crate::color::Color;
use crate::geometry::{Transform, Vec2, Vec3};
use crate::mesh::VertexAttributes;

/// Where a texture is looked up: the shading point's world-space position
/// and normal, its surface coordinates, and how these change from one
/// pixel to the next (pbrt-v4's `TextureEvalContext`; `faceIndex`, used
/// only by Ptex, is left out).
///
/// The differentials are zero unless set ([`TextureContext::with_differentials`]
/// or [`TextureContext::with_footprint`]); zero means "no footprint": the
/// finest MIP level, an unfiltered checkerboard.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TextureContext {
    /// World-space position.
    pub p: Vec3,
    /// Unit geometric normal, world space.
    pub n: Vec3,
    /// Surface (texture) coordinates.
    pub uv: Vec2,
    /// A mesh's second uv set and vertex colour
    /// ([`VertexAttributes::plain`] of `uv` where there are none).
    pub attributes: VertexAttributes,
    /// ∂p/∂x: change of the position to the next pixel in x.
    pub dpdx: Vec3,
    /// ∂p/∂y.
    pub dpdy: Vec3,
    /// ∂u/∂x.
    pub dudx: f32,
    /// ∂u/∂y.
    pub dudy: f32,
    /// ∂v/∂x.
    pub dvdx: f32,
    /// ∂v/∂y.
    pub dvdy: f32,
}

impl TextureContext {
    /// A context that knows only surface coordinates (position and normal
    /// zero): enough for textures mapped by `uv`.
    pub fn from_uv(uv: Vec2) -> Self {
        Self { uv, attributes: VertexAttributes::plain(uv), ..Self::default() }
    }

    /// A context at world-space point `p` with unit normal `n` and surface
    /// coordinates `uv`, without differentials.
    pub fn new(p: Vec3, n: Vec3, uv: Vec2) -> Self {
        Self { p, n, uv, attributes: VertexAttributes::plain(uv), ..Self::default() }
    }

    /// The same context with a mesh's vertex attributes.
    #[inline]
    pub fn with_attributes(self, attributes: VertexAttributes) -> Self {
        Self { attributes, ..self }
    }

    /// The same context with pbrt-v4's screen-space differentials (from
    /// ray differentials: pbrt-v4 §10.1).
    pub fn with_differentials(self, dpdx: Vec3, dpdy: Vec3, dudx: f32, dudy: f32, dvdx: f32, dvdy: f32) -> Self {
        Self { dpdx, dpdy, dudx, dudy, dvdx, dvdy, ..self }
    }

    /// The same context with an isotropic footprint `width` in `(u, v)`
    /// units, for renderers without ray differentials: as if one pixel step
    /// moved by `width` along `u` in x and along `v` in y, so
    /// `∂u/∂x = ∂v/∂y = width`, `∂p/∂x = width·∂p/∂u`, `∂p/∂y = width·∂p/∂v`
    /// (`dpdu`, `dpdv`: the surface's tangents at the hit). Zero is no
    /// footprint.
    pub fn with_footprint(self, width: f32, dpdu: Vec3, dpdv: Vec3) -> Self {
        self.with_differentials(dpdu * width, dpdv * width, width, 0.0, 0.0, width)
    }
}

/// The direction of pbrt-v4's `directionmix`: `dir` given in texture space,
/// taken to world space by the CTM and normalised
/// (`FloatDirectionMixTexture::Create`).
fn world_direction(dir: Vec3, world_from_texture: &Transform) -> Result<Vec3, String> {
    let d = world_from_texture.vector(dir);
    let len = d.length();
    if !(len.is_finite() && len > 0.0) {
        return Err(format!(
            "directionmix direction must be finite and non-zero, got [{}, {}, {}]",
            dir.x, dir.y, dir.z
        ));
    }
    Ok(d / len)
}

/// Where the squares of a checkerboard lie.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CheckerboardMapping {
    /// Unit squares in the `(s, t)` of a 2D mapping (pbrt `dimension 2`).
    Planar(TextureMapping),
    /// Unit cubes in texture space (pbrt `dimension 3`); the transform maps
    /// world (render) space to texture space.
    Solid(Transform),
}

/// pbrt-v4's checkerboard: `tex1` where `⌊s⌋ + ⌊t⌋` (or `⌊x⌋ + ⌊y⌋ + ⌊z⌋`)
/// is even, `tex2` where it is odd, filtered over the footprint.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkerboard<T> {
    /// The squares.
    pub mapping: CheckerboardMapping,
    /// The even squares' texture.
    pub tex1: Arc<T>,
    /// The odd squares' texture.
    pub tex2: Arc<T>,
}

impl<T> Checkerboard<T> {
    /// The weight of `tex2` at `ctx`: 0 on even squares, 1 on odd ones, in
    /// between where the footprint straddles an edge (pbrt-v4 `Checkerboard`:
    /// the closed-form convolution of the 1D square wave with a triangle
    /// filter of half-width 1.5 × the largest derivative, §10.5.1).
    pub fn weight(&self, ctx: &TextureContext) -> f32 {
        // The second antiderivative of the square wave (+1 on [0, 1), −1 on
        // [1, 2), periodic): x²/2 on [0, 1).
        let d = |x: f32| {
            let y = x / 2.0 - (x / 2.0).floor() - 0.5;
            x / 2.0 + y * (1.0 - 2.0 * y.abs())
        };
        // The filtered wave, a second difference of `d` over ±r: ±1 inside
        // a square, smooth across edges.
        let bf = |x: f32, r: f32| -> f32 {
            if (x - r).floor() == (x + r).floor() {
                1.0 - 2.0 * ((x.floor() as i64).rem_euclid(2) as f32)
            } else {
                (d(x + r) - 2.0 * d(x) + d(x - r)) / (r * r)
            }
        };
        match &self.mapping {
            CheckerboardMapping::Planar(m) => {
                let c = m.map(ctx);
                let ds = 1.5 * c.dsdx.abs().max(c.dsdy.abs());
                let dt = 1.5 * c.dtdx.abs().max(c.dtdy.abs());
                0.5 - bf(c.st.x, ds) * bf(c.st.y, dt) / 2.0
            }
            CheckerboardMapping::Solid(t) => {
                let p = t.point(ctx.p);
                let (dx, dy) = (t.vector(ctx.dpdx).abs(), t.vector(ctx.dpdy).abs());
                let r = 1.5 * dx.max(dy);
                0.5 - 0.5 * bf(p.x, r.x) * bf(p.y, r.y) * bf(p.z, r.z)
            }
        }
    }
}

/// pbrt-v4's `bilerp`: `(1−s)(1−t)·v00 + s(1−t)·v10 + (1−s)t·v01 + st·v11`
/// at the mapping's `(s, t)` (not clamped: outside the unit square it
/// extrapolates, as in pbrt).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bilerp<V> {
    /// The mapping giving `(s, t)`.
    pub mapping: TextureMapping,
    /// The value at `(0, 0)`.
    pub v00: V,
    /// The value at `(0, 1)`.
    pub v01: V,
    /// The value at `(1, 0)`.
    pub v10: V,
    /// The value at `(1, 1)`.
    pub v11: V,
}

impl<V: TexelValue> Bilerp<V> {
    /// The interpolated value at `ctx`.
    pub fn evaluate(&self, ctx: &TextureContext) -> V {
        let Vec2 { x: s, y: t } = self.mapping.map(ctx).st;
        self.v00 * ((1.0 - s) * (1.0 - t))
            + self.v10 * (s * (1.0 - t))
            + self.v01 * ((1.0 - s) * t)
            + self.v11 * (s * t)
    }
}

/// `(1 − w)·a + w·b`, evaluating a side only when its weight is non-zero
/// (pbrt-v4's mix and checkerboard textures skip the unused side).
#[inline]
fn blend<V: TexelValue>(w: f32, a: impl FnOnce() -> V, b: impl FnOnce() -> V) -> V {
    let a = if w != 1.0 { a() } else { V::default() };
    let b = if w != 0.0 { b() } else { V::default() };
    a * (1.0 - w) + b * w
}

/// `a·t1 + (1 − a)·t2`, evaluating a side only when its weight is non-zero
/// (pbrt-v4's direction-mix textures).
#[inline]
fn direction_blend<V: TexelValue>(a: f32, t1: impl FnOnce() -> V, t2: impl FnOnce() -> V) -> V {
    let t1 = if a != 0.0 { t1() } else { V::default() };
    let t2 = if a != 1.0 { t2() } else { V::default() };
    t1 * a + t2 * (1.0 - a)
}

/// A colour that may vary over a surface (pbrt-v4's `SpectrumTexture`, in
/// linear RGB). Build the pbrt classes with the constructors (see the
/// module table); the variants are public for matching.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    /// One colour everywhere.
    Constant(Color),
    /// A checkerboard in texture space: squares of side `scale` alternate
    /// between `even` and `odd`. What a texture unit is depends on the shape:
    /// world units on a plane, fractions of the circumference on a sphere
    /// (`u` around, `v` pole to pole), barycentric coordinates on a triangle.
    /// (lucent's own; pbrt's is [`Texture::Checkerboard`].)
    Checker {
        /// Colour of the square containing the origin.
        even: Color,
        /// The other colour.
        odd: Color,
        /// Side of a square in texture units (> 0).
        scale: f32,
    },
    /// An image (pbrt `imagemap`).
    Image(Arc<ImageTexture>),
    /// `tex × scale` (pbrt `scale`).
    Scale {
        /// The scaled texture.
        tex: Arc<Texture>,
        /// The factor.
        scale: Arc<FloatTexture>,
    },
    /// `(1 − amount)·tex1 + amount·tex2` (pbrt `mix`).
    Mix {
        /// Where `amount` is 0.
        tex1: Arc<Texture>,
        /// Where `amount` is 1.
        tex2: Arc<Texture>,
        /// The blend weight.
        amount: Arc<FloatTexture>,
    },
    /// `a·tex1 + (1 − a)·tex2` with `a = |n · dir|` (pbrt `directionmix`).
    DirectionMix {
        /// Where the normal is along `dir`.
        tex1: Arc<Texture>,
        /// Where the normal is perpendicular to `dir`.
        tex2: Arc<Texture>,
        /// Unit direction, world space.
        dir: Vec3,
    },
    /// pbrt's `checkerboard`.
    Checkerboard(Arc<Checkerboard<Texture>>),
    /// pbrt's `bilerp`.
    Bilerp(Arc<Bilerp<Color>>),
    /// The RGB of the mesh's interpolated vertex colour (glTF's `COLOR_0`,
    /// PLY's `red`, `green`, `blue`); white on surfaces without one.
    VertexColor,
    /// `tex1 × tex2`, channel by channel (glTF's base colour texture times
    /// the vertex colour).
    Product {
        /// The first factor.
        tex1: Arc<Texture>,
        /// The second factor.
        tex2: Arc<Texture>,
    },
}

impl Texture {
    /// `tex1 × tex2`, channel by channel. A constant white factor returns
    /// the other texture and two constants make a constant.
    pub fn product(tex1: impl Into<Arc<Texture>>, tex2: impl Into<Arc<Texture>>) -> Self {
        let (tex1, tex2) = (tex1.into(), tex2.into());
        match (tex1.as_constant(), tex2.as_constant()) {
            (Some(a), Some(b)) => Texture::Constant(a * b),
            (Some(a), None) if a == Color::ONE => (*tex2).clone(),
            (None, Some(b)) if b == Color::ONE => (*tex1).clone(),
            _ => Texture::Product { tex1, tex2 },
        }
    }

    /// pbrt `imagemap`: the colour of an image texture.
    pub fn image(tex: impl Into<Arc<ImageTexture>>) -> Self {
        Texture::Image(tex.into())
    }

    /// pbrt `scale`: `tex × scale`. As pbrt-v4's `SpectrumScaledTexture::Create`
    /// does, a constant scale of 1 returns `tex` itself and a constant
    /// scale of an image texture is folded into the image's `scale`; a
    /// constant times a constant is a constant.
    pub fn scale(tex: impl Into<Arc<Texture>>, scale: impl Into<Arc<FloatTexture>>) -> Self {
        let (tex, scale) = (tex.into(), scale.into());
        if let FloatTexture::Constant(s) = *scale {
            match &*tex {
                _ if s == 1.0 => return (*tex).clone(),
                Texture::Image(im) => return Texture::Image(Arc::new(im.scaled(s))),
                Texture::Constant(c) => return Texture::Constant(*c * s),
                _ => {}
            }
        }
        Texture::Scale { tex, scale }
    }

    /// pbrt `mix`: `(1 − amount)·tex1 + amount·tex2` (pbrt defaults: `tex1`
    /// 0, `tex2` 1, `amount` 0.5).
    pub fn mix(
        tex1: impl Into<Arc<Texture>>,
        tex2: impl Into<Arc<Texture>>,
        amount: impl Into<Arc<FloatTexture>>,
    ) -> Self {
        Texture::Mix { tex1: tex1.into(), tex2: tex2.into(), amount: amount.into() }
    }

    /// pbrt `directionmix`: `a·tex1 + (1 − a)·tex2` with `a = |n · d|`,
    /// where `d` is `dir` (texture space, pbrt default `(0, 1, 0)`) taken to
    /// world space by `world_from_texture` (the CTM at the texture's
    /// definition) and normalised. Errors if `dir` is zero or not finite.
    pub fn direction_mix(
        tex1: impl Into<Arc<Texture>>,
        tex2: impl Into<Arc<Texture>>,
        dir: Vec3,
        world_from_texture: &Transform,
    ) -> Result<Self, String> {
        Ok(Texture::DirectionMix {
            tex1: tex1.into(),
            tex2: tex2.into(),
            dir: world_direction(dir, world_from_texture)?,
        })
    }

    /// pbrt `checkerboard` with `dimension 2`: unit squares in the
    /// mapping's `(s, t)` (use the mapping's `uscale`/`vscale` to size
    /// them); `tex1` (pbrt default 1) on the square containing `(0.5, 0.5)`.
    pub fn checkerboard(mapping: TextureMapping, tex1: impl Into<Arc<Texture>>, tex2: impl Into<Arc<Texture>>) -> Self {
        let c = Checkerboard { mapping: CheckerboardMapping::Planar(mapping), tex1: tex1.into(), tex2: tex2.into() };
        Texture::Checkerboard(Arc::new(c))
    }

    /// pbrt `checkerboard` with `dimension 3`: unit cubes in texture space,
    /// `world_from_texture` being the CTM at the texture's definition.
    pub fn checkerboard_3d(
        world_from_texture: &Transform,
        tex1: impl Into<Arc<Texture>>,
        tex2: impl Into<Arc<Texture>>,
    ) -> Self {
        let mapping = CheckerboardMapping::Solid(world_from_texture.inverse());
        Texture::Checkerboard(Arc::new(Checkerboard { mapping, tex1: tex1.into(), tex2: tex2.into() }))
    }

    /// pbrt `bilerp` (pbrt defaults: `v00` 0, `v01` 1, `v10` 0, `v11` 1).
    pub fn bilerp(mapping: TextureMapping, v00: Color, v01: Color, v10: Color, v11: Color) -> Self {
        Texture::Bilerp(Arc::new(Bilerp { mapping, v00, v01, v10, v11 }))
    }

    /// The colour, if it is the same everywhere.
    pub fn as_constant(&self) -> Option<Color> {
        match self {
            Texture::Constant(c) => Some(*c),
            _ => None,
        }
    }

    /// The colour at `ctx`.
    #[inline]
    pub fn evaluate(&self, ctx: &TextureContext) -> Color {
        // The common constant is read in place; the rest out of line.
        match self {
            Texture::Constant(c) => *c,
            _ => self.evaluate_varying(ctx),
        }
    }

    /// [`Texture::evaluate`] for every kind of texture.
    fn evaluate_varying(&self, ctx: &TextureContext) -> Color {
        match self {
            Texture::Constant(c) => *c,
            Texture::Checker { even, odd, scale } => {
                let uv = ctx.uv;
                let i = (uv.x / scale).floor() as i64 + (uv.y / scale).floor() as i64;
                if i.rem_euclid(2) == 0 {
                    *even
                } else {
                    *odd
                }
            }
            Texture::Image(im) => im.evaluate_rgb(ctx),
            Texture::Scale { tex, scale } => {
                let s = scale.evaluate(ctx);
                if s == 0.0 {
                    Color::ZERO
                } else {
                    tex.evaluate(ctx) * s
                }
            }
            Texture::Mix { tex1, tex2, amount } => {
                blend(amount.evaluate(ctx), || tex1.evaluate(ctx), || tex2.evaluate(ctx))
            }
            Texture::DirectionMix { tex1, tex2, dir } => {
                direction_blend(ctx.n.dot(*dir).abs(), || tex1.evaluate(ctx), || tex2.evaluate(ctx))
            }
            Texture::Checkerboard(c) => blend(c.weight(ctx), || c.tex1.evaluate(ctx), || c.tex2.evaluate(ctx)),
            Texture::Bilerp(b) => b.evaluate(ctx),
            Texture::VertexColor => ctx.attributes.color,
            Texture::Product { tex1, tex2 } => {
                let a = tex1.evaluate(ctx);
                if a == Color::ZERO {
                    a
                } else {
                    a * tex2.evaluate(ctx)
                }
            }
        }
    }
}

/// A number that may vary over a surface (roughness, a mix amount, an
/// alpha mask, a bump height): pbrt-v4's `FloatTexture`. Build the pbrt
/// classes with the constructors (see the module table).
#[derive(Clone, Debug, PartialEq)]
pub enum FloatTexture {
    /// One value everywhere.
    Constant(f32),
    /// An image (pbrt `imagemap`); see [`ImageTexture::evaluate_float`] for
    /// how colour images become numbers.
    Image(Arc<ImageTexture>),
    /// `tex × scale` (pbrt `scale`).
    Scale {
        /// The scaled texture.
        tex: Arc<FloatTexture>,
        /// The factor.
        scale: Arc<FloatTexture>,
    },
    /// `(1 − amount)·tex1 + amount·tex2` (pbrt `mix`).
    Mix {
        /// Where `amount` is 0.
        tex1: Arc<FloatTexture>,
        /// Where `amount` is 1.
        tex2: Arc<FloatTexture>,
        /// The blend weight.
        amount: Arc<FloatTexture>,
    },
    /// `a·tex1 + (1 − a)·tex2` with `a = |n · dir|` (pbrt `directionmix`).
    DirectionMix {
        /// Where the normal is along `dir`.
        tex1: Arc<FloatTexture>,
        /// Where the normal is perpendicular to `dir`.
        tex2: Arc<FloatTexture>,
        /// Unit direction, world space.
        dir: Vec3,
    },
    /// pbrt's `checkerboard`.
    Checkerboard(Arc<Checkerboard<FloatTexture>>),
    /// pbrt's `bilerp`.
    Bilerp(Arc<Bilerp<f32>>),
    /// 1 where `texture ≥ threshold`, else 0: glTF's alpha cut-off
    /// (`alphaMode` `MASK` with `alphaCutoff`, glTF 2.0 §3.9.5).
    Step {
        /// The texture compared.
        texture: Arc<FloatTexture>,
        /// The cut-off.
        threshold: f32,
    },
    /// The alpha of the mesh's interpolated vertex colour (glTF's
    /// `COLOR_0.a`, PLY's `alpha`); 1 on surfaces without one.
    VertexAlpha,
}

impl FloatTexture {
    /// pbrt `imagemap`: the number of an image texture.
    pub fn image(tex: impl Into<Arc<ImageTexture>>) -> Self {
        FloatTexture::Image(tex.into())
    }

    /// pbrt `scale`: `tex × scale`. As pbrt-v4's `FloatScaledTexture::Create`
    /// does, with either operand a constant: 1 returns the other, a
    /// constant times an image texture folds into the image's `scale`; a
    /// constant times a constant is a constant.
    pub fn scale(tex: impl Into<Arc<FloatTexture>>, scale: impl Into<Arc<FloatTexture>>) -> Self {
        let (tex, scale) = (tex.into(), scale.into());
        for (a, b) in [(&tex, &scale), (&scale, &tex)] {
            if let FloatTexture::Constant(s) = **b {
                match &**a {
                    _ if s == 1.0 => return (**a).clone(),
                    FloatTexture::Image(im) => return FloatTexture::Image(Arc::new(im.scaled(s))),
                    FloatTexture::Constant(c) => return FloatTexture::Constant(c * s),
                    _ => {}
                }
            }
        }
        FloatTexture::Scale { tex, scale }
    }

    /// pbrt `mix`: `(1 − amount)·tex1 + amount·tex2` (pbrt defaults: `tex1`
    /// 0, `tex2` 1, `amount` 0.5).
    pub fn mix(
        tex1: impl Into<Arc<FloatTexture>>,
        tex2: impl Into<Arc<FloatTexture>>,
        amount: impl Into<Arc<FloatTexture>>,
    ) -> Self {
        FloatTexture::Mix { tex1: tex1.into(), tex2: tex2.into(), amount: amount.into() }
    }

    /// pbrt `directionmix`; see [`Texture::direction_mix`].
    pub fn direction_mix(
        tex1: impl Into<Arc<FloatTexture>>,
        tex2: impl Into<Arc<FloatTexture>>,
        dir: Vec3,
        world_from_texture: &Transform,
    ) -> Result<Self, String> {
        let dir = world_direction(dir, world_from_texture)?;
        Ok(FloatTexture::DirectionMix { tex1: tex1.into(), tex2: tex2.into(), dir })
    }

    /// pbrt `checkerboard`, `dimension 2`; see [`Texture::checkerboard`].
    pub fn checkerboard(
        mapping: TextureMapping,
        tex1: impl Into<Arc<FloatTexture>>,
        tex2: impl Into<Arc<FloatTexture>>,
    ) -> Self {
        let c = Checkerboard { mapping: CheckerboardMapping::Planar(mapping), tex1: tex1.into(), tex2: tex2.into() };
        FloatTexture::Checkerboard(Arc::new(c))
    }

    /// pbrt `checkerboard`, `dimension 3`; see [`Texture::checkerboard_3d`].
    pub fn checkerboard_3d(
        world_from_texture: &Transform,
        tex1: impl Into<Arc<FloatTexture>>,
        tex2: impl Into<Arc<FloatTexture>>,
    ) -> Self {
        let mapping = CheckerboardMapping::Solid(world_from_texture.inverse());
        FloatTexture::Checkerboard(Arc::new(Checkerboard { mapping, tex1: tex1.into(), tex2: tex2.into() }))
    }

    /// pbrt `bilerp` (pbrt defaults: `v00` 0, `v01` 1, `v10` 0, `v11` 1).
    pub fn bilerp(mapping: TextureMapping, v00: f32, v01: f32, v10: f32, v11: f32) -> Self {
        FloatTexture::Bilerp(Arc::new(Bilerp { mapping, v00, v01, v10, v11 }))
    }

    /// The value, if it is the same everywhere.
    pub fn as_constant(&self) -> Option<f32> {
        match self {
            FloatTexture::Constant(v) => Some(*v),
            _ => None,
        }
    }

    /// The value at `ctx`.
    #[inline]
    pub fn evaluate(&self, ctx: &TextureContext) -> f32 {
        match self {
            FloatTexture::Constant(v) => *v,
            FloatTexture::Image(im) => im.evaluate_float(ctx),
            FloatTexture::Scale { tex, scale } => {
                let s = scale.evaluate(ctx);
                if s == 0.0 {
                    0.0
                } else {
                    tex.evaluate(ctx) * s
                }
            }
            FloatTexture::Mix { tex1, tex2, amount } => {
                blend(amount.evaluate(ctx), || tex1.evaluate(ctx), || tex2.evaluate(ctx))
            }
            FloatTexture::DirectionMix { tex1, tex2, dir } => {
                direction_blend(ctx.n.dot(*dir).abs(), || tex1.evaluate(ctx), || tex2.evaluate(ctx))
            }
            FloatTexture::Checkerboard(c) => blend(c.weight(ctx), || c.tex1.evaluate(ctx), || c.tex2.evaluate(ctx)),
            FloatTexture::Bilerp(b) => b.evaluate(ctx),
            FloatTexture::Step { texture, threshold } => {
                if texture.evaluate(ctx) >= *threshold {
                    1.0
                } else {
                    0.0
                }
            }
            FloatTexture::VertexAlpha => ctx.attributes.alpha,
        }
    }
}

impl From<f32> for FloatTexture {
    fn from(v: f32) -> Self {
        FloatTexture::Constant(v)
    }
}

impl From<Color> for Texture {
    fn from(c: Color) -> Self {
        Texture::Constant(c)
    }
}

#[cfg(test)]
mod tests;
