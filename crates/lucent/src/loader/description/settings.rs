//! The `[camera]`, `[render]`, `[environment]` and `[ambient]` tables.

use super::super::values::*;
use super::TransformOp;
use super::{default_up, one, white};
use crate::film::Aov;
use serde::{Deserialize, Serialize};

/// The `[camera]` table.
///
/// Without `projection`, lucent's classic pinhole or thin-lens camera:
/// `eye`, `look_at`, `up`, a horizontal `fov`. With `projection`, pbrt-v4's
/// cameras (`perspective`, `orthographic`, `spherical`), placed by a
/// camera-to-world `transform` (camera space looks down `+z`, `+y` up on the
/// image, `+x` to the right) or by `eye`/`look_at`/`up`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye position.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eye: Option<Vec3Desc>,
    /// The point looked at (the centre of the image).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub look_at: Option<Vec3Desc>,
    /// Up direction (default `[0, 1, 0]`).
    #[serde(default = "default_up")]
    pub up: Direction,
    /// Field of view in degrees: horizontal for the classic camera (default
    /// 60); for `projection = "perspective"`, that of the screen window's
    /// `[-1, 1]`, the shorter image axis unless `screen_window` says
    /// otherwise (pbrt-v4's `fov`, default 90).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov: Option<FieldOfView>,
    /// Lens radius for depth of field (default 0: a pinhole).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lens_radius: Option<NonNegative>,
    /// Distance to the plane of focus (default: eye to look_at; with
    /// `projection`, 10⁶ as pbrt-v4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focal_distance: Option<Positive>,
    /// pbrt-v4's camera model, when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub projection: Option<ProjectionDesc>,
    /// Camera to world, with `projection` (instead of `eye` and `look_at`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub transform: Vec<TransformOp>,
    /// With `projection`: `[xmin, xmax, ymin, ymax]` of the screen window
    /// (default: `[-a, a, -1, 1]` for an image wider than tall by `a`,
    /// `[-1, 1, -1/a, 1/a]` otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub screen_window: Option<[Finite; 4]>,
    /// With `projection`: replaces `width / height` in the default screen
    /// window.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame_aspect_ratio: Option<Positive>,
    /// With `projection = "spherical"`: how the image covers the sphere
    /// (default `equal_area`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mapping: Option<SphericalMappingDesc>,
    /// The medium the camera is in (a name under `[media]`; default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub medium: Option<String>,
}

/// pbrt-v4's camera models.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ProjectionDesc {
    /// Perspective, with `fov`, `screen_window`, a thin lens.
    Perspective,
    /// Parallel rays; the screen window is in camera-space units.
    Orthographic,
    /// Every pixel a direction.
    Spherical,
}

/// How a spherical camera's or an environment's image covers the sphere.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SphericalMappingDesc {
    /// Latitude–longitude.
    Equirectangular,
    /// pbrt-v4's square equal-area octahedral map.
    EqualArea,
}

/// Tone-mapping operators, as named in scene files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize, Default)]
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
#[derive(Clone, Debug, Deserialize, Serialize)]
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
    #[serde(default, skip_serializing_if = "Option::is_none")]
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
    /// Sample sequence (default `stratified` for `whitted`, `sobol` for
    /// `path`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sampler: Option<SamplerDesc>,
    /// Pixel reconstruction filter (default: a box over the pixel).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<FilterDesc>,
    /// Path integrator: roughen near-specular surfaces after the first
    /// diffuse bounce (pbrt-v4's `regularize`; default false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub regularize: bool,
    /// Factor of every sample's radiance, per channel (default `[1, 1, 1]`):
    /// exposure and white balance (pbrt-v4's film `iso`, `exposuretime`,
    /// `whitebalance` become this).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub film_scale: Option<Rgb>,
    /// A sample whose largest channel exceeds this is scaled down to it
    /// (pbrt-v4's `maxcomponentvalue`; default: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_component: Option<Positive>,
    /// Path tracer: a contribution of indirect light (light that bounced
    /// before reaching the first non-specular surface seen from the camera)
    /// whose largest channel exceeds this is scaled down to it (default:
    /// none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_indirect: Option<Positive>,
    /// Auxiliary images written beside the colour in EXR output (default:
    /// none), e.g. `aov = ["albedo", "normal"]`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub aov: Vec<AovDesc>,
    /// Place each sample in one pixel by importance sampling the filter,
    /// instead of splatting it into every pixel the filter covers (default
    /// false; `lucent render --denoise` turns it on).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub filter_importance: bool,
    /// Adaptive sampling: stop sampling pixels whose estimated error is
    /// below this threshold (e.g. 0.01; default: off).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adaptive: Option<Positive>,
}

/// The auxiliary images, as named in scene files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AovDesc {
    /// Surface reflectance.
    Albedo,
    /// Shading normal.
    Normal,
    /// Hit position.
    Position,
    /// Distance from the camera.
    Depth,
}

impl From<AovDesc> for Aov {
    fn from(a: AovDesc) -> Self {
        match a {
            AovDesc::Albedo => Aov::Albedo,
            AovDesc::Normal => Aov::Normal,
            AovDesc::Position => Aov::Position,
            AovDesc::Depth => Aov::Depth,
        }
    }
}

impl From<Aov> for AovDesc {
    fn from(a: Aov) -> Self {
        match a {
            Aov::Albedo => AovDesc::Albedo,
            Aov::Normal => AovDesc::Normal,
            Aov::Position => AovDesc::Position,
            Aov::Depth => AovDesc::Depth,
        }
    }
}

/// The integrators, as named in scene files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorDesc {
    /// Classic ray tracing.
    #[default]
    Whitted,
    /// Path tracing.
    Path,
    /// Bidirectional path tracing.
    Bdpt,
}

/// The samplers, as named in scene files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SamplerDesc {
    /// The classic jittered grid.
    Stratified,
    /// Owen-scrambled Sobol.
    Sobol,
    /// Independent uniform random numbers.
    Independent,
}

/// Filter kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
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
    /// Lanczos windowed sinc.
    Lanczos,
}

/// `filter = { kind = "...", radius = ... }` in `[render]`.
#[derive(Clone, Copy, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FilterDesc {
    /// Which filter.
    pub kind: FilterKindDesc,
    /// Radius in pixels (defaults: box 0.5, tent 1, gaussian 1.5, mitchell 2,
    /// lanczos 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<Positive>,
    /// Gaussian standard deviation (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<Positive>,
    /// Mitchell B (default 1/3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub b: Option<Finite>,
    /// Mitchell C (default 1/3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub c: Option<Finite>,
    /// Lanczos τ: periods of the windowing sinc (default 3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tau: Option<Positive>,
}

/// The `[environment]` table: light from infinitely far away, for the path
/// integrator.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentDesc {
    /// A constant colour (default white, unless `file` is given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgb>,
    /// An equirectangular (latitude–longitude) image, relative to the scene
    /// file: linear `.exr`, `.hdr` or `.pfm`, or an 8-bit image (PNG, JPEG,
    /// TGA, BMP, QOI) decoded from sRGB.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Multiplier (default 1).
    #[serde(default = "one")]
    pub intensity: NonNegative,
    /// Rotation of the image about +y, in degrees (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<Finite>,
    /// How the image covers the sphere (default `equirectangular`, `+y`
    /// up; `equal_area` is pbrt-v4's square map, `+z` up).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mapping: Option<SphericalMappingDesc>,
    /// The image's own frame to world, instead of `rotation`: rotations and
    /// mirrors (a translation or a uniform scale is ignored).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub transform: Vec<TransformOp>,
    /// Scale the radiance so that a surface facing the image's zenith
    /// receives this illuminance (times `intensity`; pbrt-v4's
    /// `illuminance`; default: no normalisation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub illuminance: Option<Positive>,
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
            sampler: None,
            filter: None,
            regularize: false,
            film_scale: None,
            max_component: None,
            max_indirect: None,
            aov: Vec::new(),
            filter_importance: false,
            adaptive: None,
        }
    }
}

/// The `[ambient]` table.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AmbientDesc {
    /// Colour (default white).
    #[serde(default = "white")]
    pub color: Rgb,
    /// Multiplier (default 1).
    #[serde(default = "one")]
    pub intensity: NonNegative,
}
