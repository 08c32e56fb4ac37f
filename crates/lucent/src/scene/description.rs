//! The scene file format, as Rust types. A TOML or JSON scene file
//! deserialises into [`SceneDescription`]; every key is documented in
//! `docs/scene-format.md`. Unknown keys are errors.
//!
//! Values with a range (a radius, a field of view, a colour) are checked as
//! they are read, so an error points at the offending value in the file.

use serde::{
    de::{Error as _, Visitor},
    Deserialize, Deserializer,
};
use std::collections::BTreeMap;
use std::fmt;

/// Reads any number (integer or float). A value of another type is reported
/// as "invalid type: ..., expected WHAT", naming what is accepted.
struct NumberVisitor(&'static str);

impl Visitor<'_> for NumberVisitor {
    type Value = f64;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
    fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<f64, E> {
        Ok(v)
    }
    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<f64, E> {
        Ok(v as f64)
    }
    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<f64, E> {
        Ok(v as f64)
    }
}

/// Reads a whole number for a count in `1..=max`; a value of another type
/// (a fraction, a string) is reported with the accepted range.
struct CountVisitor {
    what: &'static str,
    max: u32,
}

impl Visitor<'_> for CountVisitor {
    type Value = i64;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: a whole number from 1 to {}", self.what, self.max)
    }
    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<i64, E> {
        Ok(v)
    }
    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<i64, E> {
        Ok(i64::try_from(v).unwrap_or(i64::MAX))
    }
}

macro_rules! checked_f32 {
    ($(#[$doc:meta])* $name:ident, $ok:expr, $what:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct $name(f32);

        impl $name {
            /// The value.
            pub fn get(self) -> f32 {
                self.0
            }
        }

        impl TryFrom<f32> for $name {
            type Error = String;
            fn try_from(v: f32) -> Result<Self, String> {
                let ok: fn(f32) -> bool = $ok;
                if v.is_finite() && ok(v) {
                    Ok(Self(v))
                } else {
                    Err(format!(concat!("expected ", $what, ", got {}"), v))
                }
            }
        }

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let v = d.deserialize_f64(NumberVisitor($what))?;
                if v.is_finite() && !(v as f32).is_finite() {
                    return Err(D::Error::custom(format!(
                        concat!("expected ", $what, ", got {:e}, which is too large (at most about 3.4e38)"),
                        v
                    )));
                }
                Self::try_from(v as f32).map_err(D::Error::custom)
            }
        }
    };
}

checked_f32!(
    /// A finite number > 0.
    Positive, |v| v > 0.0, "a number > 0"
);
checked_f32!(
    /// A finite number ≥ 0.
    NonNegative, |v| v >= 0.0, "a number ≥ 0"
);
checked_f32!(
    /// A field of view in degrees, strictly between 0 and 180.
    FieldOfView, |v| v > 0.0 && v < 180.0, "a field of view strictly between 0 and 180 degrees"
);
checked_f32!(
    /// Any finite number.
    Finite, |_| true, "a finite number"
);

/// Three finite numbers: a point or a free vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vec3Desc(pub [f32; 3]);

impl<'de> Deserialize<'de> for Vec3Desc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(Self(<[Finite; 3]>::deserialize(d)?.map(Finite::get)))
    }
}

impl fmt::Display for Vec3Desc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [x, y, z] = self.0;
        write!(f, "[{x}, {y}, {z}]")
    }
}

impl From<Vec3Desc> for glam::Vec3 {
    fn from(v: Vec3Desc) -> Self {
        glam::Vec3::from_array(v.0)
    }
}

/// Three finite numbers, not all zero: a direction or a normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Direction(pub [f32; 3]);

impl<'de> Deserialize<'de> for Direction {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec3Desc::deserialize(d)?.0;
        if v.iter().all(|&c| c == 0.0) {
            Err(D::Error::custom("a direction or normal must not be [0, 0, 0]"))
        } else {
            Ok(Self(v))
        }
    }
}

impl From<Direction> for glam::Vec3 {
    fn from(v: Direction) -> Self {
        glam::Vec3::from_array(v.0)
    }
}

/// A linear RGB colour: three finite numbers ≥ 0 (values above 1 are
/// allowed: they are radiance, not display values).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rgb(pub [f32; 3]);

impl<'de> Deserialize<'de> for Rgb {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = <[Finite; 3]>::deserialize(d)?.map(Finite::get);
        if v.iter().all(|c| *c >= 0.0) {
            Ok(Self(v))
        } else {
            Err(D::Error::custom("expected a colour [r, g, b] of finite numbers ≥ 0"))
        }
    }
}

impl From<Rgb> for glam::Vec3 {
    fn from(v: Rgb) -> Self {
        glam::Vec3::from_array(v.0)
    }
}

/// An image dimension: 1 to 65,536 pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageDimension(pub u32);

impl<'de> Deserialize<'de> for ImageDimension {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = d.deserialize_i64(CountVisitor { what: "an image size in pixels", max: crate::film::MAX_DIMENSION })?;
        if (1..=crate::film::MAX_DIMENSION as i64).contains(&v) {
            Ok(Self(v as u32))
        } else {
            Err(D::Error::custom(format!(
                "expected an image size from 1 to {} pixels, got {v}",
                crate::film::MAX_DIMENSION
            )))
        }
    }
}

/// Samples per pixel: at least 1, at most 1,048,576.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleCount(pub u32);

/// Largest samples-per-pixel count accepted.
pub const MAX_SPP: u32 = 1 << 20;

impl<'de> Deserialize<'de> for SampleCount {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = d.deserialize_i64(CountVisitor { what: "samples per pixel", max: MAX_SPP })?;
        if (1..=MAX_SPP as i64).contains(&v) {
            Ok(Self(v as u32))
        } else {
            Err(D::Error::custom(format!("expected samples per pixel from 1 to {MAX_SPP}, got {v}")))
        }
    }
}

/// Most mirror bounces: 0 to 10,000.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MaxDepth(pub u32);

/// Largest `max_depth` accepted. Deeper chains add nothing visible: each
/// bounce multiplies by a reflectivity below 1.
pub const MAX_DEPTH: u32 = 10_000;

impl<'de> Deserialize<'de> for MaxDepth {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = d.deserialize_i64(CountVisitor { what: "a bounce count", max: MAX_DEPTH })?;
        if (0..=MAX_DEPTH as i64).contains(&v) {
            Ok(Self(v as u32))
        } else {
            Err(D::Error::custom(format!("expected max_depth from 0 to {MAX_DEPTH}, got {v}")))
        }
    }
}

/// A whole scene file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDescription {
    /// The camera.
    pub camera: CameraDesc,
    /// Image and sampling settings.
    #[serde(default)]
    pub render: RenderDesc,
    /// Environment light (path integrator).
    #[serde(default)]
    pub environment: Option<EnvironmentDesc>,
    /// Ambient light.
    #[serde(default)]
    pub ambient: Option<AmbientDesc>,
    /// Named materials.
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialDesc>,
    /// Point lights.
    #[serde(default)]
    pub point_light: Vec<PointLightDesc>,
    /// Spot lights.
    #[serde(default)]
    pub spot_light: Vec<SpotLightDesc>,
    /// Directional lights.
    #[serde(default)]
    pub directional_light: Vec<DirectionalLightDesc>,
    /// Spheres.
    #[serde(default)]
    pub sphere: Vec<SphereDesc>,
    /// Planes.
    #[serde(default)]
    pub plane: Vec<PlaneDesc>,
    /// Triangles.
    #[serde(default)]
    pub triangle: Vec<TriangleDesc>,
    /// Quadrilaterals.
    #[serde(default)]
    pub quad: Vec<QuadDesc>,
    /// Groups of objects with a shared transform.
    #[serde(default)]
    pub group: Vec<GroupDesc>,
    /// Named mesh files, loaded once and placed by `[[mesh]] mesh = "NAME"`.
    #[serde(default)]
    pub meshes: BTreeMap<String, MeshFileDesc>,
    /// Placed meshes.
    #[serde(default)]
    pub mesh: Vec<MeshDesc>,
    /// Named groups defined once and placed by `[[instance]]`.
    #[serde(default)]
    pub prototypes: BTreeMap<String, GroupDesc>,
    /// Placements of prototypes.
    #[serde(default)]
    pub instance: Vec<InstanceDesc>,
}

/// The `[camera]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye position.
    pub eye: Vec3Desc,
    /// The point looked at (the centre of the image).
    pub look_at: Vec3Desc,
    /// Up direction (default `[0, 1, 0]`).
    #[serde(default = "default_up")]
    pub up: Direction,
    /// Horizontal field of view in degrees (default 60).
    #[serde(default = "default_fov")]
    pub fov: FieldOfView,
    /// Lens radius for depth of field (default 0: a pinhole).
    #[serde(default)]
    pub lens_radius: Option<NonNegative>,
    /// Distance to the plane of focus (default: eye to look_at).
    #[serde(default)]
    pub focal_distance: Option<Positive>,
}

fn default_up() -> Direction {
    Direction([0.0, 1.0, 0.0])
}
fn default_fov() -> FieldOfView {
    FieldOfView(60.0)
}

/// Tone-mapping operators, as named in scene files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ToneMapDesc {
    /// Divide by the largest channel when it exceeds 1.
    #[default]
    Classic,
    /// Clamp each channel.
    Clamp,
    /// Reinhard on luminance.
    Reinhard,
    /// ACES filmic fit.
    Aces,
}

/// The `[render]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderDesc {
    /// Image width in pixels (default 640).
    #[serde(default = "default_width")]
    pub width: ImageDimension,
    /// Image height in pixels (default 480).
    #[serde(default = "default_height")]
    pub height: ImageDimension,
    /// Samples per pixel (default 16).
    #[serde(default = "default_spp")]
    pub spp: SampleCount,
    /// Most bounces (default 5 for `whitted`, 64 for `path`).
    #[serde(default)]
    pub max_depth: Option<MaxDepth>,
    /// Background radiance (default black).
    #[serde(default = "default_background")]
    pub background: Rgb,
    /// Tone mapping for 8-bit output (default `classic`).
    #[serde(default)]
    pub tone_map: ToneMapDesc,
    /// sRGB-encode 8-bit output (default true).
    #[serde(default = "default_true")]
    pub srgb: bool,
    /// Random seed (default 0).
    #[serde(default)]
    pub seed: u64,
    /// Light transport algorithm (default `whitted`).
    #[serde(default)]
    pub integrator: IntegratorDesc,
    /// Sample sequence of the path integrator (default `sobol`).
    #[serde(default)]
    pub sampler: SamplerDesc,
    /// Pixel filter of the path integrator (default: a box over the pixel).
    #[serde(default)]
    pub filter: Option<FilterDesc>,
}

/// The integrators, as named in scene files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorDesc {
    /// Classic ray tracing.
    #[default]
    Whitted,
    /// Path tracing.
    Path,
}

/// The samplers, as named in scene files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SamplerDesc {
    /// Owen-scrambled Sobol.
    #[default]
    Sobol,
    /// Independent uniform random numbers.
    Independent,
}

/// Filter kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FilterKindDesc {
    /// Box.
    Box,
    /// Tent (triangle).
    Tent,
    /// Gaussian.
    Gaussian,
    /// Mitchell–Netravali.
    Mitchell,
}

/// `filter = { kind = "...", radius = ... }` in `[render]`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FilterDesc {
    /// Which filter.
    pub kind: FilterKindDesc,
    /// Radius in pixels (defaults: box 0.5, tent 1, gaussian 1.5, mitchell 2).
    #[serde(default)]
    pub radius: Option<Positive>,
    /// Gaussian standard deviation (default 0.5).
    #[serde(default)]
    pub sigma: Option<Positive>,
    /// Mitchell B (default 1/3).
    #[serde(default)]
    pub b: Option<Finite>,
    /// Mitchell C (default 1/3).
    #[serde(default)]
    pub c: Option<Finite>,
}

/// The `[environment]` table: light from infinitely far away, for the path
/// integrator.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentDesc {
    /// A constant colour (default white, unless `file` is given).
    #[serde(default)]
    pub color: Option<Rgb>,
    /// An equirectangular (latitude–longitude) `.hdr` or `.exr` image,
    /// relative to the scene file.
    #[serde(default)]
    pub file: Option<String>,
    /// Multiplier (default 1).
    #[serde(default = "one")]
    pub intensity: NonNegative,
    /// Rotation of the image about +y, in degrees (default 0).
    #[serde(default)]
    pub rotation: Option<Finite>,
}

fn default_width() -> ImageDimension {
    ImageDimension(640)
}
fn default_height() -> ImageDimension {
    ImageDimension(480)
}
fn default_spp() -> SampleCount {
    SampleCount(16)
}
fn default_background() -> Rgb {
    Rgb([0.0; 3])
}
fn default_true() -> bool {
    true
}

impl Default for RenderDesc {
    fn default() -> Self {
        Self {
            width: default_width(),
            height: default_height(),
            spp: default_spp(),
            max_depth: None,
            background: default_background(),
            tone_map: ToneMapDesc::default(),
            srgb: true,
            seed: 0,
            integrator: IntegratorDesc::default(),
            sampler: SamplerDesc::default(),
            filter: None,
        }
    }
}

/// The `[ambient]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AmbientDesc {
    /// Colour (default white).
    #[serde(default = "white")]
    pub color: Rgb,
    /// Multiplier (default 1).
    #[serde(default = "one")]
    pub intensity: NonNegative,
}

fn white() -> Rgb {
    Rgb([1.0; 3])
}
fn one() -> NonNegative {
    NonNegative(1.0)
}

/// A checkerboard colour.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckerDesc {
    /// Colour of the square at the origin.
    pub even: Rgb,
    /// The other colour.
    pub odd: Rgb,
    /// Side of a square in texture units (default 1).
    #[serde(default = "positive_one")]
    pub scale: Positive,
}

fn positive_one() -> Positive {
    Positive(1.0)
}

/// A material: `[materials.NAME.matte]` or `[materials.NAME.phong]`.
#[derive(Clone, Debug)]
pub enum MaterialDesc {
    /// Lambertian.
    Matte(MatteDesc),
    /// Phong with mirror reflection.
    Phong(PhongDesc),
    /// Lambertian (path integrator).
    Diffuse(DiffuseDesc),
    /// Metal.
    Conductor(ConductorDesc),
    /// Glass.
    Dielectric(DielectricDesc),
    /// Diffuse under a clear coat.
    Plastic(PlasticDesc),
}

/// Keys of a diffuse material.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiffuseDesc {
    /// Albedo, each channel ≤ 1 (default white), or give `checker`.
    #[serde(default)]
    pub color: Option<Rgb>,
    /// A checkerboard albedo.
    #[serde(default)]
    pub checker: Option<CheckerDesc>,
}

/// Named conductors with measured complex indices of refraction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MetalDesc {
    /// Gold.
    Gold,
    /// Silver.
    Silver,
    /// Copper.
    Copper,
    /// Aluminium.
    Aluminium,
}

/// Keys of a conductor: give `color`, or `eta` and `k`, or `metal`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConductorDesc {
    /// Reflectance at normal incidence (Schlick's approximation).
    #[serde(default)]
    pub color: Option<Rgb>,
    /// Real part of the complex index of refraction, per channel.
    #[serde(default)]
    pub eta: Option<Rgb>,
    /// Imaginary part (absorption), per channel.
    #[serde(default)]
    pub k: Option<Rgb>,
    /// A named metal.
    #[serde(default)]
    pub metal: Option<MetalDesc>,
    /// GGX roughness α from 0 (mirror) to 1 (default 0).
    #[serde(default)]
    pub roughness: Option<NonNegative>,
}

/// Keys of a dielectric.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DielectricDesc {
    /// Index of refraction (default 1.5).
    #[serde(default)]
    pub eta: Option<Positive>,
    /// GGX roughness α from 0 (smooth) to 1 (default 0).
    #[serde(default)]
    pub roughness: Option<NonNegative>,
    /// Colour of transmitted light (default white).
    #[serde(default)]
    pub tint: Option<Rgb>,
}

/// Keys of a plastic.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlasticDesc {
    /// Albedo of the diffuse base (default white), or give `checker`.
    #[serde(default)]
    pub color: Option<Rgb>,
    /// A checkerboard albedo.
    #[serde(default)]
    pub checker: Option<CheckerDesc>,
    /// Index of refraction of the coat (default 1.5).
    #[serde(default)]
    pub eta: Option<Positive>,
    /// GGX roughness α of the coat from 0 (smooth) to 1 (default 0).
    #[serde(default)]
    pub roughness: Option<NonNegative>,
}

/// A material is a table with exactly one key, its kind. Written by hand
/// (rather than derived) so that a second kind or a missing kind gets a
/// message that says so.
impl<'de> Deserialize<'de> for MaterialDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct KindVisitor;
        const KINDS: &[&str] = &["matte", "phong", "diffuse", "conductor", "dielectric", "plastic"];
        impl<'de> Visitor<'de> for KindVisitor {
            type Value = MaterialDesc;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a material table with one kind: `matte`, `phong`, `diffuse`, `conductor`, `dielectric` or `plastic`")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<MaterialDesc, A::Error> {
                let Some(kind) = map.next_key::<String>()? else {
                    return Err(A::Error::custom(
                        "a material needs a kind: `matte`, `phong`, `diffuse`, `conductor`, `dielectric` or `plastic`",
                    ));
                };
                let material = match kind.as_str() {
                    "matte" => MaterialDesc::Matte(map.next_value()?),
                    "phong" => MaterialDesc::Phong(map.next_value()?),
                    "diffuse" => MaterialDesc::Diffuse(map.next_value()?),
                    "conductor" => MaterialDesc::Conductor(map.next_value()?),
                    "dielectric" => MaterialDesc::Dielectric(map.next_value()?),
                    "plastic" => MaterialDesc::Plastic(map.next_value()?),
                    _ => return Err(A::Error::unknown_variant(&kind, KINDS)),
                };
                if let Some(second) = map.next_key::<String>()? {
                    return Err(A::Error::custom(format!(
                        "a material has exactly one kind, but `{second}` follows `{kind}`; give each kind its own material name"
                    )));
                }
                Ok(material)
            }
        }
        d.deserialize_map(KindVisitor)
    }
}

/// Keys of a matte material.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MatteDesc {
    /// Colour (default white); or use `checker`.
    #[serde(default)]
    pub color: Option<Rgb>,
    /// A checkerboard instead of a plain colour.
    #[serde(default)]
    pub checker: Option<CheckerDesc>,
    /// Diffuse coefficient (default 1).
    #[serde(default = "one")]
    pub kd: NonNegative,
    /// Ambient coefficient (default: kd).
    #[serde(default)]
    pub ka: Option<NonNegative>,
}

/// Keys of a Phong material.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhongDesc {
    /// Colour (default white); or use `checker`.
    #[serde(default)]
    pub color: Option<Rgb>,
    /// A checkerboard instead of a plain colour.
    #[serde(default)]
    pub checker: Option<CheckerDesc>,
    /// Diffuse coefficient (default 1).
    #[serde(default = "one")]
    pub kd: NonNegative,
    /// Ambient coefficient (default: kd).
    #[serde(default)]
    pub ka: Option<NonNegative>,
    /// Specular coefficient (default 0.5).
    #[serde(default = "half")]
    pub ks: NonNegative,
    /// Phong exponent (default 20).
    #[serde(default = "twenty")]
    pub exponent: NonNegative,
    /// Mirror reflectivity (default 0).
    #[serde(default)]
    pub kr: Option<NonNegative>,
}

fn half() -> NonNegative {
    NonNegative(0.5)
}
fn twenty() -> NonNegative {
    NonNegative(20.0)
}

/// Distance falloff of point and spot lights.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FalloffDesc {
    /// Constant.
    None,
    /// `1/d²`.
    InverseSquare,
}

/// A `[[point_light]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointLightDesc {
    /// Position.
    pub position: Vec3Desc,
    /// Colour (default white).
    #[serde(default = "white")]
    pub color: Rgb,
    /// Intensity (default 1).
    #[serde(default = "one")]
    pub intensity: NonNegative,
    /// Falloff (default `none`).
    #[serde(default)]
    pub falloff: Option<FalloffDesc>,
}

/// A `[[spot_light]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpotLightDesc {
    /// Position.
    pub position: Vec3Desc,
    /// Axis of the cone.
    pub direction: Direction,
    /// Colour (default white).
    #[serde(default = "white")]
    pub color: Rgb,
    /// Intensity on the axis (default 1).
    #[serde(default = "one")]
    pub intensity: NonNegative,
    /// Cone half-angle in degrees (default 30).
    #[serde(default = "thirty")]
    pub angle: Positive,
    /// Width of the smooth edge, degrees (default: 5, or `angle` if that is
    /// smaller; at most `angle`).
    #[serde(default)]
    pub cone_delta: Option<NonNegative>,
    /// Falloff (default `inverse_square`).
    #[serde(default)]
    pub falloff: Option<FalloffDesc>,
}

fn thirty() -> Positive {
    Positive(30.0)
}

/// A `[[directional_light]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DirectionalLightDesc {
    /// The direction the light travels.
    pub direction: Direction,
    /// Colour (default white).
    #[serde(default = "white")]
    pub color: Rgb,
    /// Intensity (default 1).
    #[serde(default = "one")]
    pub intensity: NonNegative,
}

/// One step of a transform list; the list is applied in the order written.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TransformOp {
    /// Move by `[x, y, z]`.
    Translate(Vec3Desc),
    /// Scale by `[x, y, z]` (no zero components).
    Scale(#[serde(deserialize_with = "nonzero_scale")] Vec3Desc),
    /// Rotate about x, degrees.
    RotateX(Finite),
    /// Rotate about y, degrees.
    RotateY(Finite),
    /// Rotate about z, degrees.
    RotateZ(Finite),
    /// Rotate about an axis.
    Rotate(AxisAngle),
    /// A general affine matrix, four rows of four, acting on column vectors.
    Matrix(#[serde(deserialize_with = "affine_matrix")] [[f32; 4]; 4]),
}

// Transforms and triangles are checked as they are read, like other values,
// so that the error points at the offending value even inside a group.

fn nonzero_scale<'de, D: Deserializer<'de>>(d: D) -> Result<Vec3Desc, D::Error> {
    let v = Vec3Desc::deserialize(d)?;
    if v.0.contains(&0.0) {
        return Err(D::Error::custom(format!(
            "scale {v} has a zero component: the transform would be singular (it flattens the object, which \
             cannot be undone); use non-zero factors"
        )));
    }
    Ok(v)
}

fn affine_matrix<'de, D: Deserializer<'de>>(d: D) -> Result<[[f32; 4]; 4], D::Error> {
    let rows = <[[Finite; 4]; 4]>::deserialize(d)?.map(|r| r.map(Finite::get));
    crate::geometry::Transform::from_matrix(glam::Mat4::from_cols_array_2d(&rows).transpose())
        .map_err(|e| D::Error::custom(transform_error_message(&e)))?;
    Ok(rows)
}

/// A user-facing message for a transform that cannot be used.
pub(crate) fn transform_error_message(e: &crate::geometry::TransformError) -> String {
    match e {
        crate::geometry::TransformError::Singular(det) => format!(
            "the transform is singular (determinant {det}): it collapses an axis, which cannot be undone; \
             scale factors must be non-zero and matrix columns independent"
        ),
        other => other.to_string(),
    }
}

fn triangle_corners<'de, D: Deserializer<'de>>(d: D) -> Result<[Vec3Desc; 3], D::Error> {
    let v = <[Vec3Desc; 3]>::deserialize(d)?;
    crate::shapes::Triangle::new(v.map(glam::Vec3::from), None).map_err(D::Error::custom)?;
    Ok(v)
}

/// Axis and angle of a general rotation.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisAngle {
    /// Rotation axis.
    pub axis: Direction,
    /// Angle in degrees (right-handed about the axis).
    pub angle: Finite,
}

/// A `[[sphere]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereDesc {
    /// Optional name for messages.
    #[serde(default)]
    pub name: Option<String>,
    /// Centre (default origin).
    #[serde(default = "origin")]
    pub center: Vec3Desc,
    /// Radius (default 1).
    #[serde(default = "positive_one")]
    pub radius: Positive,
    /// Material name (default: the enclosing group's).
    #[serde(default)]
    pub material: Option<String>,
    /// Emitted radiance: the surface becomes an area light (path
    /// integrator).
    #[serde(default)]
    pub emission: Option<Rgb>,
    /// Whether an emitting surface emits from both sides (default: front
    /// only).
    #[serde(default)]
    pub two_sided: bool,
    /// Object transform.
    #[serde(default)]
    pub transform: Vec<TransformOp>,
}

fn origin() -> Vec3Desc {
    Vec3Desc([0.0; 3])
}

/// A `[[plane]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneDesc {
    /// Optional name for messages.
    #[serde(default)]
    pub name: Option<String>,
    /// A point on the plane (default origin).
    #[serde(default = "origin")]
    pub point: Vec3Desc,
    /// Normal (default `[0, 1, 0]`).
    #[serde(default = "default_up")]
    pub normal: Direction,
    /// Material name.
    #[serde(default)]
    pub material: Option<String>,
    /// Object transform.
    #[serde(default)]
    pub transform: Vec<TransformOp>,
}

/// A `[[triangle]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TriangleDesc {
    /// Optional name for messages.
    #[serde(default)]
    pub name: Option<String>,
    /// The three corners, counter-clockwise seen from the front.
    #[serde(deserialize_with = "triangle_corners")]
    pub vertices: [Vec3Desc; 3],
    /// Per-corner normals for smooth shading.
    #[serde(default)]
    pub normals: Option<[Direction; 3]>,
    /// Material name.
    #[serde(default)]
    pub material: Option<String>,
    /// Emitted radiance: the surface becomes an area light (path
    /// integrator).
    #[serde(default)]
    pub emission: Option<Rgb>,
    /// Whether an emitting surface emits from both sides (default: front
    /// only).
    #[serde(default)]
    pub two_sided: bool,
    /// Object transform.
    #[serde(default)]
    pub transform: Vec<TransformOp>,
}

/// A `[[quad]]`: a planar quadrilateral, made of the two triangles
/// (v0, v1, v2) and (v0, v2, v3).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuadDesc {
    /// Optional name for messages.
    #[serde(default)]
    pub name: Option<String>,
    /// The four corners in order around the quad, counter-clockwise seen
    /// from the front.
    pub vertices: [Vec3Desc; 4],
    /// Material name.
    #[serde(default)]
    pub material: Option<String>,
    /// Emitted radiance: the surface becomes an area light (path
    /// integrator).
    #[serde(default)]
    pub emission: Option<Rgb>,
    /// Whether an emitting surface emits from both sides (default: front
    /// only).
    #[serde(default)]
    pub two_sided: bool,
    /// Object transform.
    #[serde(default)]
    pub transform: Vec<TransformOp>,
}

/// A `[[group]]`: objects (and groups) sharing a transform.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupDesc {
    /// Optional name for messages.
    #[serde(default)]
    pub name: Option<String>,
    /// Applied to every member, after the member's own transform.
    #[serde(default)]
    pub transform: Vec<TransformOp>,
    /// Default material of members that name none.
    #[serde(default)]
    pub material: Option<String>,
    /// Member spheres.
    #[serde(default)]
    pub sphere: Vec<SphereDesc>,
    /// Member planes.
    #[serde(default)]
    pub plane: Vec<PlaneDesc>,
    /// Member triangles.
    #[serde(default)]
    pub triangle: Vec<TriangleDesc>,
    /// Member quads.
    #[serde(default)]
    pub quad: Vec<QuadDesc>,
    /// Nested groups.
    #[serde(default)]
    pub group: Vec<GroupDesc>,
    /// Member meshes.
    #[serde(default)]
    pub mesh: Vec<MeshDesc>,
    /// Member placements of prototypes.
    #[serde(default)]
    pub instance: Vec<InstanceDesc>,
}

/// How a mesh gets its shading normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum NormalsDesc {
    /// The file's vertex normals if it has them, else flat shading.
    #[default]
    File,
    /// Computed smooth normals (angle-weighted), whatever the file has.
    Smooth,
    /// Flat shading: the geometric normal of each triangle.
    Flat,
}

/// A `[meshes.NAME]` table: a mesh file loaded once.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshFileDesc {
    /// Path of a `.ply` or `.obj` file, relative to the scene file.
    pub file: String,
    /// Shading normals (default `file`).
    #[serde(default)]
    pub normals: NormalsDesc,
}

/// A `[[mesh]]`: a mesh placed in the scene.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshDesc {
    /// Optional name for messages.
    #[serde(default)]
    pub name: Option<String>,
    /// A mesh defined under `[meshes]`; or give `file`.
    #[serde(default)]
    pub mesh: Option<String>,
    /// A mesh file (relative to the scene file); or give `mesh`.
    #[serde(default)]
    pub file: Option<String>,
    /// Shading normals, with `file` (default `file`).
    #[serde(default)]
    pub normals: Option<NormalsDesc>,
    /// Material of every face; without it, an OBJ's own materials are used,
    /// else the group's material.
    #[serde(default)]
    pub material: Option<String>,
    /// Emitted radiance: the surface becomes an area light (path
    /// integrator).
    #[serde(default)]
    pub emission: Option<Rgb>,
    /// Whether an emitting surface emits from both sides (default: front
    /// only).
    #[serde(default)]
    pub two_sided: bool,
    /// Object transform.
    #[serde(default)]
    pub transform: Vec<TransformOp>,
}

/// An `[[instance]]`: a prototype placed with its own transform.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstanceDesc {
    /// Optional name for messages.
    #[serde(default)]
    pub name: Option<String>,
    /// The prototype, a name under `[prototypes]`.
    pub prototype: String,
    /// Replaces the material of every member, when given.
    #[serde(default)]
    pub material: Option<String>,
    /// Applied after the prototype's own transform.
    #[serde(default)]
    pub transform: Vec<TransformOp>,
}
