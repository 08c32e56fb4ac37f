//! The `[camera]`, `[render]`, `[environment]` and `[ambient]` tables.

use super::super::values::*;
use super::{default_up, one, white};
use serde::{Deserialize, Serialize};

/// The `[camera]` table.
#[derive(Clone, Debug, Deserialize, Serialize)]
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
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lens_radius: Option<NonNegative>,
    /// Distance to the plane of focus (default: eye to look_at).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focal_distance: Option<Positive>,
}

fn default_fov() -> FieldOfView {
    FieldOfView(60.0)
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
}

/// `filter = { kind = "...", radius = ... }` in `[render]`.
#[derive(Clone, Copy, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FilterDesc {
    /// Which filter.
    pub kind: FilterKindDesc,
    /// Radius in pixels (defaults: box 0.5, tent 1, gaussian 1.5, mitchell 2).
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
}

/// The `[environment]` table: light from infinitely far away, for the path
/// integrator.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentDesc {
    /// A constant colour (default white, unless `file` is given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgb>,
    /// An equirectangular (latitude–longitude) `.hdr` or `.exr` image,
    /// relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Multiplier (default 1).
    #[serde(default = "one")]
    pub intensity: NonNegative,
    /// Rotation of the image about +y, in degrees (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
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
            sampler: None,
            filter: None,
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
