//! Environment lights: radiance arriving from infinitely far away.
//!
//! An [`Environment::Image`] is an image covering the whole sphere of
//! directions in one of two ways ([`EnvironmentMapping`]): the
//! latitude–longitude (equirectangular) mapping below, `+y` up, or pbrt-v4's
//! square equal-area octahedral mapping ([`super::equal_area`]), `+z` up.
//! Either is placed in the world by a rotation (the map's own "light space"
//! to world), possibly with a mirror: see [`MapOptions`].
//!
//! # The equirectangular (latitude–longitude) mapping
//!
//! A `width × height` image (usually `width = 2 height`). `+y` is up.
//! A unit direction `d = (x, y, z)` in the environment's own frame (before
//! its rotation, see below) has
//!
//! * polar angle `θ = acos(y)` from `+y`, and `v = θ / π`: `v = 0` (the top
//!   row) is the zenith `+y`, `v = 1/2` the horizon, `v = 1` (the bottom
//!   row) the nadir `−y`;
//! * azimuth `φ = atan2(x, −z)` in `(−π, π]`, and `u = 1/2 + φ / (2π)`:
//!   **the image centre (`u = 1/2`) looks towards `−z`**, `u` grows towards
//!   `+x` (`u = 3/4` is `+x`, `u = 1/4` is `−x`) and the left and right edges
//!   (`u = 0`, `u = 1`) are both `+z`.
//!
//! Conversely `d = (sin θ sin φ, cos θ, −sin θ cos φ)` with `θ = π v`,
//! `φ = 2π (u − 1/2)`. A camera at the origin looking along `−z` with `+y`
//! up therefore sees the middle of the image, the right way round (not
//! mirrored). Pixel `(i, j)` (column `i` from the left, row `j` from the top)
//! covers `u ∈ [i/w, (i+1)/w)`, `v ∈ [j/h, (j+1)/h)`.
//!
//! A rotation of `R` degrees ([`EnvironmentMap::new`],
//! [`Environment::from_file`]) turns the environment about `+y`
//! counter-clockwise seen from above (the right-hand rule): what the image
//! centre shows moves from `−z` to `(−sin R, 0, −cos R)`.
//!
//! # The equal-area mapping
//!
//! A square image; pixel `(i, j)` (row `j` from the top of the file) covers
//! `u ∈ [i/w, (i+1)/w)`, `v ∈ [j/h, (j+1)/h)` of
//! [`equal_area_square_to_sphere`] (pbrt-v4's `ImageInfiniteLight`, whose
//! images index `(x, y)` the same way, `y = 0` the first row of the file).
//! The centre is the light-space zenith `+z`, the corners the nadir. Every
//! pixel covers the same solid angle `4π / (w h)`.
//!
//! # Lookup and sampling
//!
//! **Lookup** is nearest-pixel (as pbrt-v4's `ImageInfiniteLight::ImageLe`;
//! the equal-area map folds indices across its edges with
//! [`wrap_octahedral_pixel`]): the radiance is piecewise constant over the
//! pixels, exactly the function the importance-sampling distribution is
//! built from, so sampling is consistent with [`Environment::le`].
//!
//! **Importance sampling** (PBRT 4th ed., §12.5.2): a
//! [`PiecewiseConstant2D`] over `(u, v)`, so that directions are chosen by
//! the energy they carry. For the equal-area map its values are the pixel
//! luminances and the solid-angle density is `p(ω) = p(u, v) / (4π)`. For
//! the lat-long map (in the form of PBRT 3rd ed. §14.2.4) they are
//! `luminance · sin θ` (θ at the pixel's centre row); since
//! `dω = sin θ dθ dφ = 2π² sin θ du dv`, `p(ω) = p(u, v) / (2π² sin θ)`.

use super::emitter::{LiSample, LightSampleContext};
use super::equal_area::{equal_area_sphere_to_square, equal_area_square_to_sphere, wrap_octahedral_pixel};
use super::equirect::{
    equirect_direction, equirect_direction_lanes, equirect_direction_sin, equirect_solid_angle_pdf, equirect_uv,
    equirect_uv_lanes, equirect_uv_sin,
};
use crate::color::{luminance, Color};
use crate::geometry::{Transform, Vec2, Vec3, Vec3Lanes, LANES};
use crate::sampling::{uniform_sphere, PiecewiseConstant2D};
use crate::texels::{check_image_size, ImageSizeError, TexelGrid};
use crate::texture::{read_image, ColorEncoding, ImageError, TextureImage};
use glam::Mat3;
use std::f32::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Light from every direction at infinity.
#[derive(Clone, Debug)]
pub enum Environment {
    /// The same radiance from every direction.
    Constant(Color),
    /// An image, lat-long or equal-area (see the module docs for the
    /// mappings).
    Image(Arc<EnvironmentMap>),
}

/// How an environment image covers the sphere of directions (see the
/// module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EnvironmentMapping {
    /// Latitude–longitude, `+y` up, the image centre towards `−z`
    /// ([`equirect_direction`]): lucent's own scene files.
    #[default]
    Equirectangular,
    /// pbrt-v4's square equal-area octahedral map, `+z` up, the image
    /// centre the zenith ([`equal_area_square_to_sphere`]).
    EqualArea,
}

impl EnvironmentMapping {
    /// The map's zenith in its own frame: `+y` for lat-long, `+z` for
    /// equal-area.
    pub fn up(self) -> Vec3 {
        match self {
            EnvironmentMapping::Equirectangular => Vec3::Y,
            EnvironmentMapping::EqualArea => Vec3::Z,
        }
    }

    /// The unit direction, in the map's own frame, at `uv ∈ [0, 1]²`.
    pub fn direction(self, uv: Vec2) -> Vec3 {
        match self {
            EnvironmentMapping::Equirectangular => equirect_direction(uv),
            EnvironmentMapping::EqualArea => equal_area_square_to_sphere(uv),
        }
    }

    /// The `uv ∈ [0, 1]²` of unit direction `d` in the map's own frame.
    pub fn uv(self, d: Vec3) -> Vec2 {
        match self {
            EnvironmentMapping::Equirectangular => equirect_uv(d),
            EnvironmentMapping::EqualArea => equal_area_sphere_to_square(d),
        }
    }
}

/// How an environment image is placed and scaled (pbrt-v4's `infinite`
/// light with a `filename`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapOptions {
    /// The mapping of the image.
    pub mapping: EnvironmentMapping,
    /// The map's own frame to world (pbrt-v4: the CTM at the
    /// `LightSource`). Its linear part must be a rotation, possibly with a
    /// mirror and a uniform scale (both allowed, the scale ignored); the
    /// translation is ignored.
    pub light_to_world: Transform,
    /// Multiplies the radiance.
    pub scale: f32,
    /// When given (and > 0), the radiance is also scaled so that the
    /// illuminance (luminance) on a surface facing the map's zenith (its
    /// [`EnvironmentMapping::up`], carried to the world) is this value,
    /// times `scale` (pbrt-v4's `illuminance`; `None` or a value ≤ 0: no
    /// normalisation, as pbrt's default `-1`).
    pub illuminance: Option<f32>,
}

impl Default for MapOptions {
    /// pbrt-v4's defaults: an equal-area map, not rotated, scale 1.
    fn default() -> Self {
        Self {
            mapping: EnvironmentMapping::EqualArea,
            light_to_world: Transform::IDENTITY,
            scale: 1.0,
            illuminance: None,
        }
    }
}

/// Why an environment image cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum EnvironmentError {
    /// The file cannot be read or decoded (any format
    /// [`read_image`](crate::texture::read_image) reads: EXR, HDR, PFM, PNG,
    /// JPEG, TGA, BMP, QOI).
    #[error("cannot read the environment map: {0}")]
    Image(#[from] ImageError),
    /// The image is empty or too large.
    #[error("environment map '{path}': {source}")]
    Size {
        /// The file (or `<memory>`).
        path: PathBuf,
        /// What is wrong with the size.
        source: ImageSizeError,
    },
    /// The pixel buffer does not have `width × height` entries.
    #[error("environment map '{path}': {len} pixels given for a {width}×{height} image")]
    PixelCount {
        /// The file (or `<memory>`).
        path: PathBuf,
        /// Width.
        width: u32,
        /// Height.
        height: u32,
        /// Pixels given.
        len: usize,
    },
    /// A pixel is NaN or infinite.
    #[error("environment map '{path}': pixel ({x}, {y}) is not a finite colour")]
    NonFinite {
        /// The file (or `<memory>`).
        path: PathBuf,
        /// Column.
        x: u32,
        /// Row from the top.
        y: u32,
    },
    /// The scale is negative or not finite.
    #[error("environment map scale must be a finite number ≥ 0, got {0}")]
    Scale(f32),
    /// The rotation is not finite.
    #[error("environment map rotation must be a finite number of degrees, got {0}")]
    Rotation(f32),
    /// The transform is not a rotation (with perhaps a mirror and a uniform
    /// scale).
    #[error("an environment map's transform must be a rotation (possibly mirrored, with a uniform scale); it cannot shear or stretch the sphere of directions")]
    Transform,
    /// An equal-area map must be square.
    #[error("environment map '{path}': an equal-area (octahedral) map must be square, got {width}×{height} (a lat-long map is usually 2:1: use the equirectangular mapping)")]
    NotSquare {
        /// The file (or `<memory>`).
        path: PathBuf,
        /// Width.
        width: u32,
        /// Height.
        height: u32,
    },
    /// A uniform radiance is negative or not finite.
    #[error("environment radiance must be finite and ≥ 0 in every channel")]
    Radiance,
    /// The illuminance is not finite.
    #[error("environment map illuminance must be a finite number, got {0}")]
    Illuminance(f32),
    /// An illuminance was asked for, but the map sends no light onto a
    /// surface facing its zenith.
    #[error("environment map '{path}': cannot scale to an illuminance, the map's upper hemisphere is black")]
    BlackHemisphere {
        /// The file (or `<memory>`).
        path: PathBuf,
    },
}

/// An environment image with its mapping, placement and sampling
/// distribution.
#[derive(Clone)]
pub struct EnvironmentMap {
    /// Radiance, scale applied, row by row from the top (`v = 0`).
    texels: TexelGrid,
    mapping: EnvironmentMapping,
    /// The map's own frame to world: orthogonal (a rotation, perhaps
    /// mirrored).
    to_world: Mat3,
    /// World to the map's frame: the transpose of `to_world`.
    to_local: Mat3,
    distribution: PiecewiseConstant2D,
    /// The file it was read from (`None` for an image made in memory).
    source: Option<PathBuf>,
    /// The factor applied to the file's pixels (`scale`, times the
    /// illuminance normalisation).
    factor: f32,
}

impl std::fmt::Debug for EnvironmentMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EnvironmentMap")
            .field("width", &self.width())
            .field("height", &self.height())
            .field("mapping", &self.mapping)
            .field("to_world", &self.to_world)
            .finish_non_exhaustive()
    }
}

/// The name of an image made in memory, in messages.
const MEMORY: &str = "<memory>";

/// `pdf`, or 0 where it is infinite or NaN.
#[inline]
fn finite_or_zero(pdf: f32) -> f32 {
    if pdf.is_finite() {
        pdf
    } else {
        0.0
    }
}

/// The orthogonal matrix of a transform that rotates (perhaps with a mirror)
/// and scales uniformly: its linear part divided by the scale.
fn orthogonal_part(t: &Transform) -> Result<Mat3, EnvironmentError> {
    let m = Mat3::from_mat4(t.matrix());
    let s2 = m.x_axis.length_squared();
    if !(s2 > 0.0 && s2.is_finite()) {
        return Err(EnvironmentError::Transform);
    }
    let q = m * (1.0 / s2.sqrt());
    let gram = q.transpose() * q;
    let off = (gram - Mat3::IDENTITY).to_cols_array().iter().fold(0.0f32, |a, v| a.max(v.abs()));
    if off > 1e-4 {
        return Err(EnvironmentError::Transform);
    }
    Ok(q)
}

/// Illuminance (luminance) on a surface facing the map's zenith, in the
/// map's own frame, of the raw `pixels`: `E = Σ_i lum(L_i) ∫_{pixel i}
/// max(0, cos θ) dω`.
///
/// For the lat-long map the integral is exact per row (rows wholly above
/// or below the horizon, and one straddling it when `h` is odd): `∫ cos θ
/// sin θ dθ dφ = (Δφ/2)(sin² θ₁ − sin² θ₀)`. For the equal-area map, whose
/// pixels all cover `4π / (w h)`, the cosine is averaged over up to 8 × 8
/// points of each pixel (pbrt-v4's `infinite` light takes it at the pixel
/// centre only, and weighs each pixel by `2π / (w h)`, half its solid angle,
/// so pbrt-v4's maps come out twice as bright as the illuminance asked for;
/// lucent uses the solid angle).
fn upper_illuminance(mapping: EnvironmentMapping, width: u32, height: u32, pixels: &[Color]) -> f64 {
    let (w, h) = (width as usize, height as usize);
    let mut sum = 0.0f64;
    match mapping {
        EnvironmentMapping::Equirectangular => {
            let dphi = 2.0 * std::f64::consts::PI / w as f64;
            for y in 0..h {
                let t0 = std::f64::consts::PI * y as f64 / h as f64;
                let t1 = (std::f64::consts::PI * (y + 1) as f64 / h as f64).min(std::f64::consts::FRAC_PI_2);
                if t1 <= t0 {
                    break;
                }
                let weight = 0.5 * dphi * (t1.sin().powi(2) - t0.sin().powi(2));
                let row: f64 = pixels[y * w..(y + 1) * w].iter().map(|&c| luminance(c) as f64).sum();
                sum += weight * row;
            }
        }
        EnvironmentMapping::EqualArea => {
            // k × k midpoints per pixel, fewer for large maps (at most about
            // 4 million cosines): the pixels that straddle the horizon
            // make the centre rule alone a few tenths of a percent off.
            let k = ((4.0e6 / (w * h) as f64).sqrt() as usize).clamp(1, 8);
            let omega = 4.0 * std::f64::consts::PI / (w * h * k * k) as f64;
            for (i, &c) in pixels.iter().enumerate() {
                let lum = luminance(c) as f64;
                if lum == 0.0 {
                    continue;
                }
                let (x, y) = ((i % w) as f32, (i / w) as f32);
                let mut cos_sum = 0.0f64;
                for j in 0..k {
                    for l in 0..k {
                        let uv = Vec2::new(
                            (x + (l as f32 + 0.5) / k as f32) / w as f32,
                            (y + (j as f32 + 0.5) / k as f32) / h as f32,
                        );
                        cos_sum += equal_area_square_to_sphere(uv).z.max(0.0) as f64;
                    }
                }
                sum += omega * cos_sum * lum;
            }
        }
    }
    sum
}

impl EnvironmentMap {
    /// A lat-long map from `pixels` (linear RGB, row by row from the top),
    /// multiplied by `scale` and turned by `rotation` degrees about `+y`.
    /// Negative components are clamped to zero; non-finite ones are refused.
    pub fn new(
        width: u32,
        height: u32,
        pixels: Vec<Color>,
        scale: f32,
        rotation: f32,
    ) -> Result<Self, EnvironmentError> {
        if !rotation.is_finite() {
            return Err(EnvironmentError::Rotation(rotation));
        }
        let q = Mat3::from_rotation_y(rotation.to_radians());
        Self::build(Path::new(MEMORY), width, height, pixels, EnvironmentMapping::Equirectangular, q, scale, None)
    }

    /// A map from `pixels` (linear RGB, row by row from the top), with the
    /// mapping, placement and scale of `options`. An equal-area map must be
    /// square. Negative components are clamped to zero; non-finite ones are
    /// refused.
    pub fn with_options(
        width: u32,
        height: u32,
        pixels: Vec<Color>,
        options: &MapOptions,
    ) -> Result<Self, EnvironmentError> {
        Self::from_options(Path::new(MEMORY), width, height, pixels, options)
    }

    fn from_options(
        path: &Path,
        width: u32,
        height: u32,
        pixels: Vec<Color>,
        options: &MapOptions,
    ) -> Result<Self, EnvironmentError> {
        let q = orthogonal_part(&options.light_to_world)?;
        Self::build(path, width, height, pixels, options.mapping, q, options.scale, options.illuminance)
    }

    #[allow(clippy::too_many_arguments)]
    fn build(
        path: &Path,
        width: u32,
        height: u32,
        pixels: Vec<Color>,
        mapping: EnvironmentMapping,
        to_world: Mat3,
        scale: f32,
        illuminance: Option<f32>,
    ) -> Result<Self, EnvironmentError> {
        if !(scale >= 0.0 && scale.is_finite()) {
            return Err(EnvironmentError::Scale(scale));
        }
        if let Some(e) = illuminance {
            if !e.is_finite() {
                return Err(EnvironmentError::Illuminance(e));
            }
        }
        check_image_size(width, height).map_err(|source| EnvironmentError::Size { path: path.to_owned(), source })?;
        if mapping == EnvironmentMapping::EqualArea && width != height {
            return Err(EnvironmentError::NotSquare { path: path.to_owned(), width, height });
        }
        let len = pixels.len();
        let mut texels = TexelGrid::from_pixels(width, height, pixels).ok_or_else(|| EnvironmentError::PixelCount {
            path: path.to_owned(),
            width,
            height,
            len,
        })?;
        for (i, c) in texels.pixels_mut().iter_mut().enumerate() {
            if !c.is_finite() {
                let (x, y) = ((i % width as usize) as u32, (i / width as usize) as u32);
                return Err(EnvironmentError::NonFinite { path: path.to_owned(), x, y });
            }
            *c = c.max(Color::ZERO);
        }
        // pbrt-v4: scale ← scale · E_v / E(map), with E(map) measured on the
        // unscaled image.
        let mut factor = scale;
        if let Some(e_v) = illuminance.filter(|&e| e > 0.0) {
            let e_map = upper_illuminance(mapping, width, height, texels.pixels());
            if !(e_map > 0.0 && e_map.is_finite()) {
                return Err(EnvironmentError::BlackHemisphere { path: path.to_owned() });
            }
            factor = (scale as f64 * e_v as f64 / e_map) as f32;
        }
        if factor != 1.0 {
            for c in texels.pixels_mut() {
                *c *= factor;
            }
        }
        let (w, h) = (width as usize, height as usize);
        let weights: Vec<f32> = match mapping {
            EnvironmentMapping::Equirectangular => {
                // sin θ at each row's centre.
                let sin: Vec<f32> = (0..h).map(|y| (PI * (y as f32 + 0.5) / h as f32).sin()).collect();
                texels.pixels().iter().enumerate().map(|(i, &c)| luminance(c) * sin[i / w]).collect()
            }
            // Equal-area: every pixel covers the same solid angle.
            EnvironmentMapping::EqualArea => texels.pixels().iter().map(|&c| luminance(c)).collect(),
        };
        let distribution = PiecewiseConstant2D::new(&weights, w, h);
        let source = (path != Path::new(MEMORY)).then(|| path.to_owned());
        Ok(Self { texels, mapping, to_world, to_local: to_world.transpose(), distribution, source, factor })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.texels.width()
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.texels.height()
    }

    /// The mapping of the image.
    pub fn mapping(&self) -> EnvironmentMapping {
        self.mapping
    }

    /// The radiance of pixel `(x, y)` (scale applied; row 0 at the top).
    pub fn pixel(&self, x: u32, y: u32) -> Color {
        self.texels.pixel(x, y)
    }

    /// The radiance, scale applied, as a grid.
    pub fn texels(&self) -> &TexelGrid {
        &self.texels
    }

    /// The file the image was read from, if it was read from one.
    pub fn source(&self) -> Option<&Path> {
        self.source.as_deref()
    }

    /// The factor the file's pixels were multiplied by: `scale`, times the
    /// illuminance normalisation if one was asked for. Reading the file
    /// again with this scale, no illuminance and [`EnvironmentMap::light_to_world`]
    /// gives the same map.
    pub fn scale(&self) -> f32 {
        self.factor
    }

    /// The map's own frame to world (orthogonal).
    pub fn light_to_world(&self) -> Mat3 {
        self.to_world
    }

    /// The map's zenith ([`EnvironmentMapping::up`]) in world space.
    pub fn up(&self) -> Vec3 {
        self.to_world * self.mapping.up()
    }

    /// Illuminance (luminance) on a surface facing [`EnvironmentMap::up`]
    /// (see [`MapOptions::illuminance`]; for an equal-area map the cosine is
    /// averaged over a few points of each pixel).
    pub fn illuminance(&self) -> f32 {
        upper_illuminance(self.mapping, self.width(), self.height(), self.texels.pixels()) as f32
    }

    /// World direction → the map's own frame.
    #[inline]
    fn to_local(&self, d: Vec3) -> Vec3 {
        self.to_local * d
    }

    /// The map's own frame → world.
    #[inline]
    fn to_world(&self, d: Vec3) -> Vec3 {
        self.to_world * d
    }

    /// The pixel at `(u, v)`.
    #[inline]
    fn lookup(&self, uv: Vec2) -> Color {
        let (x, y) = self.pixel_at(uv);
        self.pixel(x, y)
    }

    /// The column and row of the pixel at `(u, v)`.
    #[inline]
    fn pixel_at(&self, uv: Vec2) -> (u32, u32) {
        let (w, h) = (self.width(), self.height());
        match self.mapping {
            EnvironmentMapping::Equirectangular => {
                (((uv.x * w as f32) as u32).min(w - 1), ((uv.y * h as f32) as u32).min(h - 1))
            }
            // uv = 1 reaches index w: fold it across the edge.
            EnvironmentMapping::EqualArea => {
                wrap_octahedral_pixel((uv.x * w as f32) as i64, (uv.y * h as f32) as i64, w, h)
            }
        }
    }

    /// Radiance seen along world direction `dir`.
    pub fn le(&self, dir: Vec3) -> Color {
        self.lookup(self.uv_of(dir))
    }

    /// The `uv` of world direction `dir` (any length).
    #[inline]
    fn uv_of(&self, dir: Vec3) -> Vec2 {
        self.uv_sin_of(dir).0
    }

    /// The `uv` of world direction `dir` (any length), with what
    /// [`EnvironmentMap::solid_angle_pdf`] needs of it: `sin θ` of a
    /// lat-long map (1 for an equal-area one, which does not use it).
    #[inline]
    fn uv_sin_of(&self, dir: Vec3) -> (Vec2, f32) {
        let d = self.to_local(dir);
        match self.mapping {
            EnvironmentMapping::Equirectangular => equirect_uv_sin(d),
            EnvironmentMapping::EqualArea => (equal_area_sphere_to_square(d.normalize_or_zero()), 1.0),
        }
    }

    /// `Σ_i lum(L_i) Ω_i` over the pixels, `Ω_i` the solid angle of pixel
    /// `i`: `(2π / w)(cos θ₀ − cos θ₁)` for a lat-long row, `4π / (w h)` for
    /// an equal-area map.
    fn fluence(&self) -> f64 {
        let (w, h) = (self.width() as usize, self.height() as usize);
        let pixels = self.texels.pixels();
        match self.mapping {
            EnvironmentMapping::Equirectangular => {
                let mut sum = 0.0f64;
                for y in 0..h {
                    let t0 = PI as f64 * y as f64 / h as f64;
                    let t1 = PI as f64 * (y + 1) as f64 / h as f64;
                    let omega = 2.0 * std::f64::consts::PI / w as f64 * (t0.cos() - t1.cos());
                    let row: f64 = pixels[y * w..(y + 1) * w].iter().map(|&c| luminance(c) as f64).sum();
                    sum += row * omega;
                }
                sum
            }
            EnvironmentMapping::EqualArea => {
                let total: f64 = pixels.iter().map(|&c| luminance(c) as f64).sum();
                total * 4.0 * std::f64::consts::PI / (w * h) as f64
            }
        }
    }

    /// Total radiant power (luminance) falling on a disk of radius `r`:
    /// `Φ = π r² Σ L_i Ω_i`, with `Ω_i` the solid angle of pixel `i` (PBRT
    /// 4th ed., §12.5.2).
    pub fn power(&self, r: f32) -> f32 {
        (std::f64::consts::PI * (r as f64) * (r as f64) * self.fluence()) as f32
    }

    /// The solid-angle density of a direction whose square density is
    /// `pdf_uv`, given the `sin θ` of [`EnvironmentMap::uv_sin_of`]; 0
    /// where the mapping degenerates.
    #[inline]
    fn solid_angle_pdf(&self, sin_theta: f32, pdf_uv: f32) -> f32 {
        finite_or_zero(match self.mapping {
            EnvironmentMapping::Equirectangular => equirect_solid_angle_pdf(sin_theta, pdf_uv),
            EnvironmentMapping::EqualArea => pdf_uv / (4.0 * PI),
        })
    }

    fn sample_li(&self, u: Vec2) -> Option<LiSample> {
        let (uv, pdf_uv) = self.distribution.sample(u);
        self.sample_li_at(uv, pdf_uv)
    }

    /// The light sample at `uv`, a point the distribution drew with
    /// density `pdf_uv`.
    #[inline]
    fn sample_li_at(&self, uv: Vec2, pdf_uv: f32) -> Option<LiSample> {
        if pdf_uv.is_nan() || pdf_uv <= 0.0 {
            return None;
        }
        // (A lat-long map's direction and density share one sin θ.)
        let (d, pdf) = match self.mapping {
            EnvironmentMapping::Equirectangular => {
                let (d, sin_theta) = equirect_direction_sin(uv);
                (d, equirect_solid_angle_pdf(sin_theta, pdf_uv))
            }
            EnvironmentMapping::EqualArea => (equal_area_square_to_sphere(uv), pdf_uv / (4.0 * PI)),
        };
        self.sample_li_of(self.lookup(uv), d, pdf)
    }

    /// The light sample of radiance `l` whose direction in the map's frame
    /// is `d` and whose solid-angle density is `pdf`.
    #[inline(always)]
    fn sample_li_of(&self, l: Color, d: Vec3, pdf: f32) -> Option<LiSample> {
        let pdf = finite_or_zero(pdf);
        if pdf <= 0.0 {
            return None;
        }
        let wi = self.to_world(d);
        (l != Color::ZERO).then_some(LiSample { l, wi, pdf, p_light: None })
    }

    /// [`EnvironmentMap::sample_li`] of each point of `u`, into `out`: the
    /// distribution's samples taken together
    /// ([`PiecewiseConstant2D::sample_many`]), their pixels read in a loop
    /// of loads that do not wait on each other (each likely a cache miss),
    /// then a lat-long map's directions across vector lanes
    /// ([`equirect_direction_lanes`]) while the pixels arrive.
    fn sample_li_many(&self, u: &[Vec2], out: &mut [Option<LiSample>]) {
        for (u, out) in u.chunks(LANES).zip(out.chunks_mut(LANES)) {
            let n = u.len();
            let mut s = [(Vec2::ZERO, 0.0); LANES];
            self.distribution.sample_many(u, &mut s[..n]);
            if self.mapping == EnvironmentMapping::Equirectangular {
                let mut l = [Color::ZERO; LANES];
                for (l, &(uv, _)) in l.iter_mut().zip(&s[..n]) {
                    *l = self.lookup(uv);
                }
                let (mut uu, mut vv) = ([0.0; LANES], [0.0; LANES]);
                for (k, &(uv, _)) in s[..n].iter().enumerate() {
                    (uu[k], vv[k]) = (uv.x, uv.y);
                }
                let (mut d, mut sin_theta) = (Vec3Lanes::ZERO, [0.0; LANES]);
                equirect_direction_lanes(&uu, &vv, n, &mut d, &mut sin_theta);
                for (k, (out, &(_, pdf_uv))) in out.iter_mut().zip(&s).enumerate() {
                    *out = if pdf_uv.is_nan() || pdf_uv <= 0.0 {
                        None
                    } else {
                        self.sample_li_of(l[k], d.get(k), equirect_solid_angle_pdf(sin_theta[k], pdf_uv))
                    };
                }
            } else {
                for (out, &(uv, pdf_uv)) in out.iter_mut().zip(&s) {
                    *out = self.sample_li_at(uv, pdf_uv);
                }
            }
        }
    }

    fn pdf_li(&self, wi: Vec3) -> f32 {
        let (uv, sin_theta) = self.uv_sin_of(wi);
        self.solid_angle_pdf(sin_theta, self.distribution.pdf(uv))
    }

    /// [`EnvironmentMap::le`] and [`EnvironmentMap::pdf_li`] of one
    /// direction, with its `uv` (two `atan2`s) found once.
    fn le_pdf(&self, dir: Vec3) -> (Color, f32) {
        let (uv, sin_theta) = self.uv_sin_of(dir);
        (self.lookup(uv), self.solid_angle_pdf(sin_theta, self.distribution.pdf(uv)))
    }

    /// [`EnvironmentMap::le_pdf`] of every direction of `dirs`, into
    /// `out`. The directions are first mapped to their pixel and cell (a
    /// lat-long map's across vector lanes: [`equirect_uv_lanes`]), and
    /// only then are the pixels and densities read, in a loop of loads that
    /// do not wait on each other: a direction's pixel is anywhere in the
    /// image, so each read is likely a cache miss, and this way the misses
    /// of many directions overlap instead of following one another.
    fn le_pdf_many(&self, dirs: &[Vec3], out: &mut [(Color, f32)]) {
        for (dirs, out) in dirs.chunks(LANES).zip(out.chunks_mut(LANES)) {
            let mut uv = [(Vec2::ZERO, 0.0); LANES];
            if self.mapping == EnvironmentMapping::Equirectangular {
                let mut d = Vec3Lanes::ZERO;
                for (k, &dir) in dirs.iter().enumerate() {
                    d.set(k, self.to_local(dir));
                }
                let (mut u, mut v, mut sin_theta) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
                equirect_uv_lanes(&d, dirs.len(), &mut u, &mut v, &mut sin_theta);
                for (k, uv) in uv[..dirs.len()].iter_mut().enumerate() {
                    *uv = (Vec2::new(u[k], v[k]), sin_theta[k]);
                }
            } else {
                for (uv, &dir) in uv.iter_mut().zip(dirs) {
                    *uv = self.uv_sin_of(dir);
                }
            }
            let mut at = [((0u32, 0u32), 0usize); LANES];
            for (at, &(uv, _)) in at.iter_mut().zip(&uv[..dirs.len()]) {
                *at = (self.pixel_at(uv), self.distribution.cell(uv));
            }
            for (out, &((x, y), cell)) in out.iter_mut().zip(&at) {
                *out = (self.pixel(x, y), self.distribution.cell_pdf(cell));
            }
            for (out, &(_, sin_theta)) in out.iter_mut().zip(&uv) {
                out.1 = self.solid_angle_pdf(sin_theta, out.1);
            }
        }
    }
}

impl Environment {
    /// A lat-long environment image read from a file
    /// ([`read_environment_image`]: EXR, HDR, PFM or an 8-bit format),
    /// multiplied by `scale` and turned by `rotation` degrees about `+y`
    /// (see the module docs).
    pub fn from_file(path: impl AsRef<Path>, scale: f32, rotation: f32) -> Result<Self, EnvironmentError> {
        let path = path.as_ref();
        if !(scale >= 0.0 && scale.is_finite()) {
            return Err(EnvironmentError::Scale(scale));
        }
        if !rotation.is_finite() {
            return Err(EnvironmentError::Rotation(rotation));
        }
        let (width, height, pixels) = environment_pixels(&read_environment_image(path)?);
        let q = Mat3::from_rotation_y(rotation.to_radians());
        let map =
            EnvironmentMap::build(path, width, height, pixels, EnvironmentMapping::Equirectangular, q, scale, None)?;
        Ok(Environment::Image(Arc::new(map)))
    }

    /// An environment image read from a file ([`read_environment_image`]),
    /// with the mapping, placement and scale of `options` (pbrt-v4's
    /// `infinite` light with a `filename`: use [`MapOptions::default`], the
    /// equal-area mapping, and set the transform, scale and illuminance). A
    /// non-square image given as an equal-area map is refused
    /// ([`EnvironmentError::NotSquare`]).
    pub fn from_file_with(path: impl AsRef<Path>, options: &MapOptions) -> Result<Self, EnvironmentError> {
        let path = path.as_ref();
        if !(options.scale >= 0.0 && options.scale.is_finite()) {
            return Err(EnvironmentError::Scale(options.scale));
        }
        orthogonal_part(&options.light_to_world)?;
        Self::from_image_with(path, &read_environment_image(path)?, options)
    }

    /// An environment from an image already read from `source` (with
    /// [`read_environment_image`]; `source` names it in messages and in
    /// [`EnvironmentMap::source`]), with the mapping, placement and scale of
    /// `options`. For a caller that looks at the image before it picks the
    /// mapping, as pbrt-v4's importer does (a square image is equal-area).
    pub fn from_image_with(
        source: &Path,
        image: &TextureImage,
        options: &MapOptions,
    ) -> Result<Self, EnvironmentError> {
        let (width, height, pixels) = environment_pixels(image);
        Ok(Environment::Image(Arc::new(EnvironmentMap::from_options(source, width, height, pixels, options)?)))
    }

    /// pbrt-v4's `infinite` light without an image: radiance `l · scale`
    /// from every direction or, with `illuminance` `E` (when > 0), scaled so
    /// that a surface facing up receives `E · scale`: since a uniform
    /// radiance `L` gives `E = π lum(L)` on any surface, the radiance becomes
    /// `l · scale · E / (π lum(l))`. (A rotation does not change a uniform
    /// environment.)
    pub fn uniform(l: Color, scale: f32, illuminance: Option<f32>) -> Result<Self, EnvironmentError> {
        if !(scale >= 0.0 && scale.is_finite()) {
            return Err(EnvironmentError::Scale(scale));
        }
        if !(l.is_finite() && l.min_element() >= 0.0) {
            return Err(EnvironmentError::Radiance);
        }
        let mut c = l * scale;
        if let Some(e) = illuminance {
            if !e.is_finite() {
                return Err(EnvironmentError::Illuminance(e));
            }
            let lum = luminance(l);
            if e > 0.0 && lum > 0.0 {
                c *= e / (PI * lum);
            }
        }
        Ok(Environment::Constant(c))
    }

    /// Radiance arriving from direction `-dir`, i.e. seen by a ray
    /// travelling along unit `dir` that escapes the scene.
    pub fn le(&self, dir: Vec3) -> Color {
        match self {
            Environment::Constant(c) => *c,
            Environment::Image(map) => map.le(dir),
        }
    }

    /// Sample an incident direction with uniform `u` in `[0, 1)²`: uniform
    /// over the sphere (pdf `1/4π`) for a constant environment, by the
    /// image's luminance for an image. `None` when nothing arrives.
    pub fn sample_li(&self, ctx: &LightSampleContext, u: Vec2) -> Option<LiSample> {
        let _ = ctx;
        match self {
            Environment::Constant(c) => {
                if *c == Color::ZERO {
                    return None;
                }
                Some(LiSample { l: *c, wi: uniform_sphere(u), pdf: 1.0 / (4.0 * PI), p_light: None })
            }
            Environment::Image(map) => map.sample_li(u),
        }
    }

    /// Whether this is an image (whose sampling reads large tables).
    #[inline]
    pub fn is_image(&self) -> bool {
        matches!(self, Environment::Image(_))
    }

    /// [`Environment::sample_li`] of each point of `u`, into `out` (of the
    /// same length), bit for bit, for a caller with many samples to take
    /// (the context does not change an environment's samples). An image's
    /// sampling tables and pixels are read at random, usually from beyond
    /// the caches: here the reads of many samples overlap
    /// ([`PiecewiseConstant2D::sample_many`]), and a lat-long map's
    /// directions are found across vector lanes.
    ///
    /// ```
    /// use lucent::color::Color;
    /// use lucent::geometry::{Vec2, Vec3};
    /// use lucent::light::{Environment, EnvironmentMap, LightSampleContext};
    /// use std::sync::Arc;
    ///
    /// let pixels = (0..32).map(|i| Color::splat(i as f32)).collect();
    /// let env = Environment::Image(Arc::new(EnvironmentMap::new(8, 4, pixels, 1.0, 0.0).unwrap()));
    /// let u = [Vec2::new(0.3, 0.7), Vec2::new(0.9, 0.1)];
    /// let mut out = [None; 2];
    /// env.sample_li_many(&u, &mut out);
    /// let ctx = LightSampleContext { p: Vec3::ZERO, n: Vec3::Y };
    /// assert_eq!(out, [env.sample_li(&ctx, u[0]), env.sample_li(&ctx, u[1])]);
    /// ```
    ///
    /// # Panics
    /// If `out` and `u` differ in length.
    pub fn sample_li_many(&self, u: &[Vec2], out: &mut [Option<LiSample>]) {
        assert_eq!(u.len(), out.len(), "one sample per point");
        match self {
            Environment::Image(map) => map.sample_li_many(u, out),
            Environment::Constant(_) => {
                let ctx = LightSampleContext { p: Vec3::ZERO, n: Vec3::ZERO };
                for (out, &u) in out.iter_mut().zip(u) {
                    *out = self.sample_li(&ctx, u);
                }
            }
        }
    }

    /// The solid-angle pdf with which [`Environment::sample_li`] picks the
    /// world direction `wi`.
    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        match self {
            Environment::Constant(_) => 1.0 / (4.0 * PI),
            Environment::Image(map) => map.pdf_li(wi),
        }
    }

    /// `(le(dir), pdf_li(dir))`, bit for bit, for a ray that escapes along
    /// `dir` after a BSDF sample (what MIS needs): an image's direction is
    /// mapped to the image once instead of twice.
    ///
    /// ```
    /// use lucent::color::Color;
    /// use lucent::geometry::Vec3;
    /// use lucent::light::Environment;
    ///
    /// let env = Environment::uniform(Color::ONE, 2.0, None).unwrap();
    /// let dir = Vec3::new(0.3, 0.8, -0.2);
    /// assert_eq!(env.le_pdf(dir), (env.le(dir), env.pdf_li(dir)));
    /// ```
    pub fn le_pdf(&self, dir: Vec3) -> (Color, f32) {
        match self {
            Environment::Constant(c) => (*c, 1.0 / (4.0 * PI)),
            Environment::Image(map) => map.le_pdf(dir),
        }
    }

    /// [`Environment::le_pdf`] of each direction of `dirs`, into `out` (of
    /// the same length), bit for bit; for an image, the pixel reads of all
    /// the directions overlap in memory.
    ///
    /// # Panics
    /// If `out` and `dirs` differ in length.
    pub fn le_pdf_many(&self, dirs: &[Vec3], out: &mut [(Color, f32)]) {
        assert_eq!(dirs.len(), out.len(), "one result per direction");
        match self {
            Environment::Constant(c) => out.fill((*c, 1.0 / (4.0 * PI))),
            Environment::Image(map) => map.le_pdf_many(dirs, out),
        }
    }

    /// Power (luminance) delivered into a scene of bounding-sphere radius
    /// `r`: PBRT 4th ed. §12.5.1 takes the radiance through a disk of area
    /// `π r²` from every direction, `Φ = π r² · 4π · lum(L)` for a constant
    /// environment.
    pub fn power(&self, r: f32) -> f32 {
        match self {
            Environment::Constant(c) => PI * r * r * 4.0 * PI * luminance(*c),
            Environment::Image(map) => map.power(r),
        }
    }
}

/// Read an environment image with the one image reader that textures use
/// too ([`read_image`]): OpenEXR, Radiance HDR and PFM are linear radiance;
/// PNG, JPEG, TGA, BMP and QOI are decoded from sRGB, as pbrt-v4's
/// `Image::Read` does for an `infinite` light (module table of
/// [`crate::texture`]). The format is found from the file's contents (PFM
/// also from its extension), and the size is checked before any texel is
/// decoded.
pub fn read_environment_image(path: &Path) -> Result<TextureImage, EnvironmentError> {
    Ok(read_image(path, ColorEncoding::pbrt_default_for(path))?)
}

/// An image's texels as RGB radiance, row by row from the top: a grey image
/// gives equal channels, an alpha channel is left out (radiance has none).
fn environment_pixels(image: &TextureImage) -> (u32, u32, Vec<Color>) {
    let c = image.channels();
    let pixels = image
        .data()
        .chunks_exact(c)
        .map(|t| if c == 1 { Color::splat(t[0]) } else { Color::new(t[0], t[1], t[2]) })
        .collect();
    (image.width(), image.height(), pixels)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::{Film, PendingImage, ToneMap};
    use crate::sampling::Pcg32;

    const W: u32 = 64;
    const H: u32 = 32;

    /// A dim background with a bright patch and a coloured band.
    fn synthetic() -> Vec<Color> {
        let mut px = vec![Color::new(0.1, 0.12, 0.15); (W * H) as usize];
        for y in 6..10 {
            for x in 40..46 {
                px[(y * W + x) as usize] = Color::new(50.0, 40.0, 30.0);
            }
        }
        for x in 0..W {
            px[(20 * W + x) as usize] = Color::new(0.0, 2.0, 0.0);
        }
        px
    }

    /// `Σ_i L_i ∫_{pixel i} g(ω) dω`, integrating `g` over each pixel with
    /// an 8 × 8 midpoint rule in `(u, v)` (`dω = 2π² sin θ du dv`).
    fn pixel_sum(map: &EnvironmentMap, g: impl Fn(Vec3) -> f32) -> Vec3 {
        let (w, h) = (map.width(), map.height());
        let k = 8;
        let mut total = glam::DVec3::ZERO;
        for y in 0..h {
            for x in 0..w {
                let mut acc = 0.0f64;
                for j in 0..k {
                    for i in 0..k {
                        let uv = Vec2::new(
                            (x as f32 + (i as f32 + 0.5) / k as f32) / w as f32,
                            (y as f32 + (j as f32 + 0.5) / k as f32) / h as f32,
                        );
                        let d = map.to_world(equirect_direction(uv));
                        let jac = 2.0 * PI * PI * (PI * uv.y).sin() / (w * h) as f32 / (k * k) as f32;
                        acc += (g(d) * jac) as f64;
                    }
                }
                total += map.pixel(x, y).as_dvec3() * acc;
            }
        }
        total.as_vec3a()
    }

    /// MC estimate of `∫ Le g dω` with `sample_li`: (mean, standard error of
    /// the first channel). Checks `pdf_li` against every sample's pdf.
    fn estimate(env: &Environment, g: impl Fn(Vec3) -> f32, m: usize) -> (Vec3, f32) {
        let ctx = LightSampleContext { p: Vec3::ZERO, n: Vec3::ZERO };
        let mut rng = Pcg32::new(17, 3);
        let mut sum = glam::DVec3::ZERO;
        let mut sum2 = 0.0f64;
        let mut dirs = Vec::new();
        for _ in 0..m {
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let sample = env.sample_li(&ctx, u);
            if let Some(s) = sample {
                assert!(s.p_light.is_none());
                let pdf = env.pdf_li(s.wi);
                assert!((pdf - s.pdf).abs() <= 2e-3 * s.pdf, "pdf_li {pdf} vs sample {}", s.pdf);
                assert_eq!(env.le(s.wi), s.l);
                assert_eq!(env.le_pdf(s.wi), (s.l, pdf), "le_pdf is le and pdf_li");
                dirs.push(s.wi);
                // And anywhere else, any length.
                let d = uniform_sphere(Vec2::new(rng.uniform(), rng.uniform())) * (0.5 + rng.uniform());
                let (le, pdf) = env.le_pdf(d);
                assert_eq!((le, pdf.to_bits()), (env.le(d), env.pdf_li(d).to_bits()));
                let x = (s.l * g(s.wi) / s.pdf).as_dvec3();
                sum += x;
                sum2 += x.x * x.x;
            }
        }
        // The batched lookup gives each direction's le_pdf, bit for bit,
        // over many chunks (and a few directions that are not unit length).
        dirs.extend((0..300).map(|i| uniform_sphere(Vec2::new(rng.uniform(), rng.uniform())) * (0.25 + i as f32)));
        let mut found = vec![(Color::ZERO, 0.0); dirs.len()];
        env.le_pdf_many(&dirs, &mut found);
        for (&d, &(le, pdf)) in dirs.iter().zip(&found) {
            let (want_le, want_pdf) = env.le_pdf(d);
            assert_eq!((le, pdf.to_bits()), (want_le, want_pdf.to_bits()), "{d}");
        }
        let mean = sum / m as f64;
        let var = (sum2 / m as f64 - mean.x * mean.x).max(0.0);
        (mean.as_vec3a(), (var / m as f64).sqrt() as f32)
    }

    #[test]
    fn image_sampling_estimates_integrals_of_the_pixels() {
        let env = Environment::Image(Arc::new(EnvironmentMap::new(W, H, synthetic(), 1.5, 30.0).unwrap()));
        let Environment::Image(map) = &env else { unreachable!() };
        // ∫ Le dω: importance sampling by luminance makes this nearly exact.
        let want = pixel_sum(map, |_| 1.0);
        let (got, se) = estimate(&env, |_| 1.0, 100_000);
        assert!((got - want).abs().max_element() <= 5.0 * se + 0.01 * want.max_element(), "{got} vs {want}");
        // Irradiance at a tilted normal.
        let n = Vec3::new(0.3, 0.8, -0.5).normalize();
        let want = pixel_sum(map, |d| d.dot(n).max(0.0));
        let (got, se) = estimate(&env, |d| d.dot(n).max(0.0), 100_000);
        assert!((got - want).abs().max_element() <= 5.0 * se + 0.01 * want.max_element(), "{got} vs {want}");
        // Total power: the same pixel integral through a unit disk.
        let phi = pixel_sum(map, |_| 1.0);
        assert!((map.power(1.0) - PI * luminance(phi)).abs() < 1e-3 * map.power(1.0));
    }

    #[test]
    fn image_pdf_integrates_to_one() {
        let env = Environment::Image(Arc::new(EnvironmentMap::new(W, H, synthetic(), 1.0, -75.0).unwrap()));
        // Midpoint rule in (u, v) on a grid finer than the pixels.
        let (nu, nv) = (512, 256);
        let mut sum = 0.0f64;
        for j in 0..nv {
            for i in 0..nu {
                let uv = Vec2::new((i as f32 + 0.5) / nu as f32, (j as f32 + 0.5) / nv as f32);
                let d = equirect_direction(uv);
                let jac = 2.0 * PI * PI * (PI * uv.y).sin();
                // Any rotation: integrate over world directions.
                sum += (env.pdf_li(d) * jac) as f64;
            }
        }
        let integral = sum / (nu * nv) as f64;
        assert!((integral - 1.0).abs() < 2e-3, "{integral}");
    }

    #[test]
    fn le_follows_the_documented_mapping() {
        let px = synthetic();
        let map = EnvironmentMap::new(W, H, px.clone(), 1.0, 0.0).unwrap();
        // Every pixel centre round-trips.
        for y in 0..H {
            for x in 0..W {
                let uv = Vec2::new((x as f32 + 0.5) / W as f32, (y as f32 + 0.5) / H as f32);
                let d = equirect_direction(uv);
                assert!((equirect_uv(d) - uv).length() < 1e-5, "{uv} -> {d} -> {}", equirect_uv(d));
                assert_eq!(map.le(d), px[(y * W + x) as usize]);
            }
        }
        // The named directions.
        let uv = |d: Vec3| equirect_uv(d.normalize());
        assert!((uv(-Vec3::Z) - Vec2::new(0.5, 0.5)).length() < 1e-6, "image centre looks at -z");
        assert!((uv(Vec3::X) - Vec2::new(0.75, 0.5)).length() < 1e-6, "u grows towards +x");
        assert!((uv(-Vec3::X) - Vec2::new(0.25, 0.5)).length() < 1e-6);
        assert_eq!(uv(Vec3::Y).y, 0.0, "v = 0 is the zenith");
        assert_eq!(uv(-Vec3::Y).y, 1.0);
        assert!(uv(Vec3::new(0.0, 0.5, -1.0)).y < 0.5, "above the horizon is the upper half");
        // Rotation by R turns what the centre shows to (−sin R, 0, −cos R).
        let mut marked = vec![Color::ZERO; (W * H) as usize];
        marked[((H / 2) * W + W / 2) as usize] = Color::ONE;
        let rot = EnvironmentMap::new(W, H, marked, 1.0, 90.0).unwrap();
        let a = 0.5f32 * PI / W as f32; // inside the pixel right of centre
                                        // Local azimuth a maps to world (sin(a − R), ·, −cos(a − R)).
        let probe = |a: f32| Vec3::new((a - 90f32.to_radians()).sin(), -0.01, -(a - 90f32.to_radians()).cos());
        assert_eq!(rot.le(probe(a)), Color::ONE);
        assert!((probe(0.0) - Vec3::new(-1.0, -0.01, 0.0)).length() < 1e-6);
        assert_eq!(rot.le(-Vec3::Z - 0.01 * Vec3::Y), Color::ZERO);
    }

    #[test]
    fn constant_environment_samples_the_sphere_uniformly() {
        let env = Environment::Constant(Color::new(1.0, 2.0, 3.0));
        let (got, se) = estimate(&env, |_| 1.0, 10_000);
        assert!((got.x - 4.0 * PI).abs() <= 5.0 * se + 1e-3, "{got}");
        assert_eq!(env.pdf_li(Vec3::X), 1.0 / (4.0 * PI));
        let lum = luminance(Color::new(1.0, 2.0, 3.0));
        assert!((env.power(2.0) - PI * 4.0 * 4.0 * PI * lum).abs() < 1e-3);
        let ctx = LightSampleContext { p: Vec3::ZERO, n: Vec3::Y };
        assert!(Environment::Constant(Color::ZERO).sample_li(&ctx, Vec2::splat(0.5)).is_none());
    }

    #[test]
    fn black_image_gives_no_samples_and_no_power() {
        let map = EnvironmentMap::new(8, 4, vec![Color::ZERO; 32], 1.0, 0.0).unwrap();
        let env = Environment::Image(Arc::new(map));
        let ctx = LightSampleContext { p: Vec3::ZERO, n: Vec3::Y };
        assert!(env.sample_li(&ctx, Vec2::splat(0.3)).is_none());
        assert_eq!(env.power(1.0), 0.0);
    }

    #[test]
    fn files_written_by_lucent_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let mut film = Film::new(W, H).unwrap();
        film.pixels_mut().copy_from_slice(&synthetic());
        for ext in ["exr", "hdr"] {
            let path = dir.path().join(format!("env.{ext}"));
            PendingImage::create(&path).unwrap().write(&film, ToneMap::default(), false).unwrap();
            let Environment::Image(map) = Environment::from_file(&path, 2.0, 0.0).unwrap() else {
                panic!("an image environment")
            };
            assert_eq!((map.width(), map.height()), (W, H));
            for (i, &want) in film.pixels().iter().enumerate() {
                let got = map.pixel(i as u32 % W, i as u32 / W) / 2.0;
                // EXR is exact; RGBE keeps 8 bits of mantissa.
                let tol = if ext == "exr" { 0.0 } else { 0.01 * want.max_element() };
                assert!((got - want).abs().max_element() <= tol, "{ext} pixel {i}: {got} vs {want}");
            }
        }
    }

    /// A PFM file (little-endian, rows bottom to top) of `pixels` given
    /// row by row from the top.
    fn pfm_file(path: &Path, width: u32, height: u32, pixels: &[Color]) {
        let mut bytes = format!("PF\n{width} {height}\n-1.0\n").into_bytes();
        for row in pixels.chunks_exact(width as usize).rev() {
            for c in row {
                for v in [c.x, c.y, c.z] {
                    bytes.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
        std::fs::write(path, bytes).unwrap();
    }

    #[test]
    fn pfm_maps_read_exactly_through_the_texture_reader() {
        let dir = tempfile::tempdir().unwrap();
        let px = synthetic();
        let path = dir.path().join("env.pfm");
        pfm_file(&path, W, H, &px);
        let Environment::Image(map) = Environment::from_file(&path, 2.0, 0.0).unwrap() else {
            panic!("an image environment")
        };
        assert_eq!((map.width(), map.height()), (W, H));
        assert_eq!(map.source(), Some(path.as_path()));
        for (i, &want) in px.iter().enumerate() {
            assert_eq!(map.pixel(i as u32 % W, i as u32 / W), want * 2.0, "pixel {i}");
        }
        // The same file as a square equal-area map, and a grey PFM.
        let sq = dir.path().join("sq.pfm");
        let px: Vec<Color> = (0..16).map(|i| Color::new(i as f32, 0.5, 0.25)).collect();
        pfm_file(&sq, 4, 4, &px);
        let options = MapOptions { mapping: EnvironmentMapping::EqualArea, ..MapOptions::default() };
        let Environment::Image(map) = Environment::from_file_with(&sq, &options).unwrap() else { panic!() };
        assert_eq!(map.mapping(), EnvironmentMapping::EqualArea);
        assert_eq!(map.pixel(1, 0), Color::new(1.0, 0.5, 0.25));
        assert_eq!(map.pixel(2, 3), Color::new(14.0, 0.5, 0.25));
        let grey = dir.path().join("grey.pfm");
        let mut bytes = b"Pf\n2 1\n-1\n".to_vec();
        bytes.extend([0.5f32, 3.0].iter().flat_map(|v| v.to_le_bytes()));
        std::fs::write(&grey, bytes).unwrap();
        let Environment::Image(map) = Environment::from_file(&grey, 1.0, 0.0).unwrap() else { panic!() };
        assert_eq!((map.pixel(0, 0), map.pixel(1, 0)), (Color::splat(0.5), Color::splat(3.0)));
    }

    #[test]
    fn eight_bit_maps_are_decoded_from_srgb() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("env.png");
        image::RgbImage::from_raw(2, 1, vec![255, 0, 188, 0, 0, 0]).unwrap().save(&path).unwrap();
        let Environment::Image(map) = Environment::from_file(&path, 1.0, 0.0).unwrap() else { panic!() };
        let c = map.pixel(0, 0);
        // sRGB 188/255 = 0.737 decodes to ((0.737 + 0.055) / 1.055)^2.4 = 0.502.
        assert_eq!((c.x, c.y), (1.0, 0.0));
        assert!((c.z - 0.5029).abs() < 1e-3, "{c}");
    }

    #[test]
    fn bad_files_give_clear_errors() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.hdr");
        let e = Environment::from_file(&missing, 1.0, 0.0).unwrap_err();
        assert!(matches!(e, EnvironmentError::Image(_)), "{e:?}");
        assert!(e.to_string().contains("missing.hdr") && e.to_string().contains("cannot read"), "{e}");
        let txt = dir.path().join("env.txt");
        std::fs::write(&txt, b"x").unwrap();
        let e = Environment::from_file(&txt, 1.0, 0.0).unwrap_err();
        assert!(e.to_string().contains("unknown image format (not PNG, JPEG, TGA, BMP, QOI, EXR, HDR or PFM)"), "{e}");
        for name in ["garbage.hdr", "garbage.exr", "garbage.pfm"] {
            let p = dir.path().join(name);
            std::fs::write(&p, b"#?RADIANCE\nthis is not an image\n").unwrap();
            let e = Environment::from_file(&p, 1.0, 0.0).unwrap_err();
            assert!(matches!(e, EnvironmentError::Image(_)), "{name}: {e:?}");
            assert!(e.to_string().contains(name), "{e}");
        }
        // A header claiming a huge image is refused before allocating.
        for (name, bytes) in [
            ("huge.hdr", &b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n"[..]),
            ("huge.pfm", &b"PF\n100000 100000\n-1\n\0\0\0\0"[..]),
        ] {
            let huge = dir.path().join(name);
            std::fs::write(&huge, bytes).unwrap();
            let e = Environment::from_file(&huge, 1.0, 0.0).unwrap_err();
            assert!(e.to_string().contains("too large") || e.to_string().contains("cannot decode"), "{e}");
        }
        assert!(matches!(Environment::from_file(&missing, -1.0, 0.0), Err(EnvironmentError::Scale(_))));
        assert!(matches!(Environment::from_file(&missing, 1.0, f32::NAN), Err(EnvironmentError::Rotation(_))));
        let mut px = vec![Color::ONE; 8];
        px[5] = Color::new(f32::NAN, 0.0, 0.0);
        let e = EnvironmentMap::new(4, 2, px, 1.0, 0.0).unwrap_err();
        assert!(e.to_string().contains("pixel (1, 1)"), "{e}");
        assert!(matches!(
            EnvironmentMap::new(4, 2, vec![Color::ONE; 7], 1.0, 0.0),
            Err(EnvironmentError::PixelCount { .. })
        ));
    }

    /// Samples taken together ([`Environment::sample_li_many`]) are
    /// [`Environment::sample_li`]'s bit for bit: lat-long maps (turned, with
    /// black pixels and a bright patch, whose samples crowd into few bins),
    /// an equal-area map, and a constant environment, in batches of every
    /// length around the lane count.
    #[test]
    fn samples_together_equal_samples_one_at_a_time() {
        let mut rng = Pcg32::new(41, 9);
        let (w, h) = (64, 32);
        let mut px: Vec<Color> = (0..w * h).map(|_| Color::new(rng.uniform(), rng.uniform(), 0.5)).collect();
        for p in px.iter_mut().skip(100).step_by(7) {
            *p = Color::ZERO;
        }
        px[w * 5 + 40] = Color::splat(1e5);
        let maps = [
            Environment::Image(Arc::new(EnvironmentMap::new(w as u32, h as u32, px.clone(), 2.0, 0.0).unwrap())),
            Environment::Image(Arc::new(EnvironmentMap::new(w as u32, h as u32, px, 1.0, 37.0).unwrap())),
            Environment::Image(Arc::new(equal_area(square(), Transform::rotate_x(30.0)))),
            Environment::uniform(Color::new(0.5, 1.0, 2.0), 1.0, None).unwrap(),
        ];
        let ctx = LightSampleContext { p: Vec3::ZERO, n: Vec3::ZERO };
        let bits = |s: &Option<LiSample>| {
            s.map(|s| (s.l.to_array().map(f32::to_bits), s.wi.to_array().map(f32::to_bits), s.pdf.to_bits()))
        };
        for env in &maps {
            let mut us: Vec<Vec2> = (0..5000).map(|_| Vec2::new(rng.uniform(), rng.uniform())).collect();
            us.extend([Vec2::ZERO, Vec2::splat(1.0f32.next_down()), Vec2::new(0.5, 0.0), Vec2::new(0.0, 0.5)]);
            let want: Vec<Option<LiSample>> = us.iter().map(|&u| env.sample_li(&ctx, u)).collect();
            for batch in [1, 3, LANES - 1, LANES, LANES + 1, 2 * LANES + 5] {
                for (us, want) in us.chunks(batch).zip(want.chunks(batch)) {
                    let mut got = vec![None; us.len()];
                    env.sample_li_many(us, &mut got);
                    for ((u, g), w) in us.iter().zip(&got).zip(want) {
                        assert_eq!(bits(g), bits(w), "{env:?}, batch {batch}, {u}");
                    }
                }
            }
        }
    }

    // ---- Equal-area maps and general placements ----

    const N: u32 = 32;

    /// A square map: dim, with a bright patch off the zenith and a band.
    fn square() -> Vec<Color> {
        let mut px = vec![Color::new(0.1, 0.12, 0.15); (N * N) as usize];
        for y in 5..9 {
            for x in 20..25 {
                px[(y * N + x) as usize] = Color::new(40.0, 30.0, 20.0);
            }
        }
        for x in 0..N {
            px[(27 * N + x) as usize] = Color::new(0.0, 3.0, 0.0);
        }
        px
    }

    fn equal_area(px: Vec<Color>, light_to_world: Transform) -> EnvironmentMap {
        let options = MapOptions { light_to_world, ..MapOptions::default() };
        EnvironmentMap::with_options(N, N, px, &options).unwrap()
    }

    /// `Σ_i L_i ∫_{pixel i} g(ω) dω` for an equal-area map: each pixel is
    /// `4π / N²`, integrated by a k × k midpoint rule on the square.
    fn equal_area_sum(map: &EnvironmentMap, g: impl Fn(Vec3) -> f32) -> Vec3 {
        let k = 6;
        let mut total = glam::DVec3::ZERO;
        for y in 0..N {
            for x in 0..N {
                let mut acc = 0.0f64;
                for j in 0..k {
                    for i in 0..k {
                        let uv = Vec2::new(
                            (x as f32 + (i as f32 + 0.5) / k as f32) / N as f32,
                            (y as f32 + (j as f32 + 0.5) / k as f32) / N as f32,
                        );
                        let d = map.to_world(equal_area_square_to_sphere(uv));
                        acc += g(d) as f64;
                    }
                }
                let omega = 4.0 * std::f64::consts::PI / (N * N) as f64 / (k * k) as f64;
                total += map.pixel(x, y).as_dvec3() * acc * omega;
            }
        }
        total.as_vec3a()
    }

    #[test]
    fn constant_equal_area_map_has_the_uniform_pdf() {
        let env =
            Environment::Image(Arc::new(equal_area(vec![Color::splat(2.0); (N * N) as usize], Transform::IDENTITY)));
        let ctx = LightSampleContext { p: Vec3::ZERO, n: Vec3::Y };
        let mut rng = Pcg32::new(3, 3);
        let uniform = 1.0 / (4.0 * PI);
        for _ in 0..2000 {
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let s = env.sample_li(&ctx, u).unwrap();
            assert!((s.pdf - uniform).abs() < 1e-5 * uniform, "{}", s.pdf);
            assert!((s.wi.length() - 1.0).abs() < 1e-5);
            assert_eq!(s.l, Color::splat(2.0));
            let d = uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            assert!((env.pdf_li(d) - uniform).abs() < 1e-5 * uniform);
        }
        // Power through a unit disk: π · 4π · lum(L).
        assert!((env.power(1.0) - PI * 4.0 * PI * 2.0).abs() < 1e-3);
    }

    #[test]
    fn equal_area_sampling_estimates_integrals_of_the_pixels() {
        let t = Transform::rotate(Vec3::new(1.0, 2.0, -0.5), 70.0).unwrap();
        let env = Environment::Image(Arc::new(equal_area(square(), t)));
        let Environment::Image(map) = &env else { unreachable!() };
        let want = equal_area_sum(map, |_| 1.0);
        let (got, se) = estimate(&env, |_| 1.0, 100_000);
        assert!((got - want).abs().max_element() <= 5.0 * se + 0.01 * want.max_element(), "{got} vs {want}");
        let n = Vec3::new(-0.4, 0.3, 0.8).normalize();
        let want = equal_area_sum(map, |d| d.dot(n).max(0.0));
        let (got, se) = estimate(&env, |d| d.dot(n).max(0.0), 100_000);
        assert!((got - want).abs().max_element() <= 5.0 * se + 0.01 * want.max_element(), "{got} vs {want}");
        let phi = equal_area_sum(map, |_| 1.0);
        assert!((map.power(1.0) - PI * luminance(phi)).abs() < 1e-3 * map.power(1.0));
    }

    #[test]
    fn equal_area_pdf_integrates_to_one() {
        let t = Transform::rotate_y(-35.0).then(&Transform::scale(Vec3::new(-2.0, 2.0, 2.0)).unwrap());
        let env = Environment::Image(Arc::new(equal_area(square(), t)));
        // The mapping is equal-area: a uniform grid on the square is a
        // uniform grid of solid angle 4π / n².
        let n = 256;
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let uv = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                sum += env.pdf_li(equal_area_square_to_sphere(uv)) as f64;
            }
        }
        let integral = sum * 4.0 * std::f64::consts::PI / (n * n) as f64;
        assert!((integral - 1.0).abs() < 2e-3, "{integral}");
    }

    #[test]
    fn a_rotated_map_looks_up_the_rotated_direction() {
        let px = square();
        let rotations = [
            Transform::rotate_x(-90.0),
            Transform::rotate(Vec3::new(0.3, -1.0, 2.0), 123.0).unwrap(),
            // A mirror with a uniform scale and a translation (ignored).
            Transform::scale(Vec3::new(-3.0, 3.0, 3.0)).unwrap().then(&Transform::translate(Vec3::splat(5.0))),
        ];
        for t in rotations {
            let map = equal_area(px.clone(), t);
            let q = Mat3::from_mat4(t.matrix());
            for y in 0..N {
                for x in 0..N {
                    let uv = Vec2::new((x as f32 + 0.5) / N as f32, (y as f32 + 0.5) / N as f32);
                    let local = equal_area_square_to_sphere(uv);
                    assert_eq!(map.le(q * local), px[(y * N + x) as usize], "pixel ({x}, {y})");
                }
            }
        }
        // pbrt's light space is z-up: with the usual `Rotate -90 1 0 0`
        // the map's centre (its zenith) becomes world +y.
        let mut marked = vec![Color::ZERO; (N * N) as usize];
        marked[((N / 2) * N + N / 2) as usize] = Color::ONE;
        let map = equal_area(marked, Transform::rotate_x(-90.0));
        assert_eq!(map.le(Vec3::Y), Color::ONE);
        assert_eq!(map.le(Vec3::Z), Color::ZERO);
        assert!((map.up() - Vec3::Y).length() < 1e-6);
        // A lat-long map placed by a general transform: its zenith (+y)
        // turned 90° about z is −x.
        let ll = EnvironmentMap::with_options(
            W,
            H,
            synthetic(),
            &MapOptions {
                mapping: EnvironmentMapping::Equirectangular,
                light_to_world: Transform::rotate_z(90.0),
                ..MapOptions::default()
            },
        )
        .unwrap();
        assert!((ll.up() + Vec3::X).length() < 1e-6);
        assert_eq!(ll.le(-Vec3::X), ll.pixel(0, 0));
        // The legacy rotation about +y is a transform like any other.
        let a = EnvironmentMap::new(W, H, synthetic(), 1.0, 40.0).unwrap();
        let b = EnvironmentMap::with_options(
            W,
            H,
            synthetic(),
            &MapOptions {
                mapping: EnvironmentMapping::Equirectangular,
                light_to_world: Transform::rotate_y(40.0),
                ..MapOptions::default()
            },
        )
        .unwrap();
        let mut rng = Pcg32::new(1, 1);
        for _ in 0..1000 {
            let d = uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            assert_eq!(a.le(d), b.le(d));
        }
    }

    #[test]
    fn lookups_on_the_edge_fold_across_it() {
        // uv = 1 lies on the fold: the pixel there is the last column (or
        // row), mirrored about the middle of the edge.
        let px: Vec<Color> = (0..N * N).map(|i| Color::splat(i as f32)).collect();
        let map = equal_area(px, Transform::IDENTITY);
        assert_eq!(map.lookup(Vec2::new(1.0, 0.2)), map.pixel(N - 1, N - 1 - (0.2 * N as f32) as u32));
        assert_eq!(map.lookup(Vec2::new(0.3, 1.0)), map.pixel(N - 1 - (0.3 * N as f32) as u32, N - 1));
        assert_eq!(map.lookup(Vec2::new(0.3, 0.6)), map.pixel((0.3 * N as f32) as u32, (0.6 * N as f32) as u32));
    }

    #[test]
    fn illuminance_normalises_the_upward_irradiance() {
        // Uniform equal-area map: E = π L on any surface; the centre rule
        // is close to exact.
        let options = MapOptions { scale: 2.0, illuminance: Some(10.0), ..MapOptions::default() };
        let map =
            EnvironmentMap::with_options(N, N, vec![Color::new(1.0, 2.0, 3.0); (N * N) as usize], &options).unwrap();
        assert!((map.illuminance() - 20.0).abs() < 1e-4 * 20.0, "{}", map.illuminance());
        let want_l = 20.0 / PI;
        assert!(
            (luminance(map.pixel(3, 7)) - want_l).abs() < 2e-3 * want_l,
            "{} vs {want_l}",
            luminance(map.pixel(3, 7))
        );
        // A lat-long map, rotated: the irradiance on a surface facing its
        // (rotated) zenith, estimated by sampling, is the value asked for.
        let t = Transform::rotate_x(90.0);
        let options = MapOptions {
            mapping: EnvironmentMapping::Equirectangular,
            light_to_world: t,
            scale: 1.0,
            illuminance: Some(3.0),
        };
        let map = EnvironmentMap::with_options(W, H, synthetic(), &options).unwrap();
        assert!((map.up() - Vec3::Z).length() < 1e-6);
        assert!((map.illuminance() - 3.0).abs() < 1e-4);
        let env = Environment::Image(Arc::new(map));
        let lum = |c: Vec3| luminance(c);
        let (got, se) = estimate(&env, |d| d.dot(Vec3::Z).max(0.0), 200_000);
        assert!((lum(got) - 3.0).abs() < 5.0 * se + 0.01 * 3.0, "{got}");
        // The equal-area map with structure: estimate against the value.
        let options =
            MapOptions { illuminance: Some(5.0), light_to_world: Transform::rotate_x(-90.0), ..MapOptions::default() };
        let map = EnvironmentMap::with_options(N, N, square(), &options).unwrap();
        let Environment::Image(m) = Environment::Image(Arc::new(map.clone())) else { unreachable!() };
        let exact = luminance(equal_area_sum(&m, |d| d.dot(Vec3::Y).max(0.0)));
        assert!((exact - 5.0).abs() < 0.02 * 5.0, "{exact}");
        // A black upper hemisphere cannot be normalised.
        let mut px = vec![Color::ZERO; (W * H) as usize];
        px[((H - 1) * W) as usize] = Color::ONE;
        let options = MapOptions {
            mapping: EnvironmentMapping::Equirectangular,
            illuminance: Some(1.0),
            ..MapOptions::default()
        };
        assert!(matches!(
            EnvironmentMap::with_options(W, H, px, &options),
            Err(EnvironmentError::BlackHemisphere { .. })
        ));
    }

    #[test]
    fn uniform_light_with_illuminance() {
        let Environment::Constant(c) = Environment::uniform(Color::new(1.0, 0.5, 0.2), 2.0, Some(6.0)).unwrap() else {
            panic!("a constant environment")
        };
        // E = π lum(L) = scale · illuminance.
        assert!((PI * luminance(c) - 12.0).abs() < 1e-4);
        assert!((c.x / c.y - 2.0).abs() < 1e-6);
        let Environment::Constant(c) = Environment::uniform(Color::ONE, 0.5, None).unwrap() else { panic!() };
        assert_eq!(c, Color::splat(0.5));
        assert!(matches!(Environment::uniform(Color::ONE, -1.0, None), Err(EnvironmentError::Scale(_))));
        assert!(matches!(Environment::uniform(-Color::ONE, 1.0, None), Err(EnvironmentError::Radiance)));
    }

    #[test]
    fn equal_area_maps_must_be_square_and_rotations_rigid() {
        let e = EnvironmentMap::with_options(W, H, synthetic(), &MapOptions::default()).unwrap_err();
        assert!(matches!(e, EnvironmentError::NotSquare { width: W, height: H, .. }), "{e:?}");
        assert!(e.to_string().contains("must be square"), "{e}");
        let shear = Transform::scale(Vec3::new(1.0, 2.0, 1.0)).unwrap();
        let options = MapOptions { light_to_world: shear, ..MapOptions::default() };
        assert!(matches!(EnvironmentMap::with_options(N, N, square(), &options), Err(EnvironmentError::Transform)));
        // From a file too, read through the image crate.
        let dir = tempfile::tempdir().unwrap();
        let mut film = Film::new(W, H).unwrap();
        film.pixels_mut().copy_from_slice(&synthetic());
        let path = dir.path().join("wide.exr");
        PendingImage::create(&path).unwrap().write(&film, ToneMap::default(), false).unwrap();
        let e = Environment::from_file_with(&path, &MapOptions::default()).unwrap_err();
        assert!(e.to_string().contains("wide.exr") && e.to_string().contains("32"), "{e}");
        let mut film = Film::new(N, N).unwrap();
        film.pixels_mut().copy_from_slice(&square());
        let path = dir.path().join("square.exr");
        PendingImage::create(&path).unwrap().write(&film, ToneMap::default(), false).unwrap();
        let Environment::Image(map) =
            Environment::from_file_with(&path, &MapOptions { scale: 2.0, ..MapOptions::default() }).unwrap()
        else {
            panic!("an image environment")
        };
        assert_eq!(map.mapping(), EnvironmentMapping::EqualArea);
        assert_eq!(map.pixel(21, 6), Color::new(80.0, 60.0, 40.0));
    }
}
