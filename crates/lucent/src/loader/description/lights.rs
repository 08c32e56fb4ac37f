//! `[[point_light]]`, `[[spot_light]]` and `[[directional_light]]` tables.

use super::super::values::*;
use super::{one, white};
use serde::{Deserialize, Serialize};

/// Distance falloff of point and spot lights.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FalloffDesc {
    /// Constant.
    None,
    /// `1/d²`.
    InverseSquare,
}

/// A `[[point_light]]`.
#[derive(Clone, Debug, Deserialize, Serialize)]
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
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub falloff: Option<FalloffDesc>,
}

/// A `[[spot_light]]`.
#[derive(Clone, Debug, Deserialize, Serialize)]
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
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cone_delta: Option<NonNegative>,
    /// Falloff (default `inverse_square`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub falloff: Option<FalloffDesc>,
}

fn thirty() -> Positive {
    Positive(30.0)
}

/// A `[[directional_light]]`.
#[derive(Clone, Debug, Deserialize, Serialize)]
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
