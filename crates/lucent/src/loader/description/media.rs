//! `[media.NAME.KIND]`: participating media, placed by the
//! `medium_inside`/`medium_outside` keys of objects and the camera's
//! `medium`.

use super::super::values::*;
use serde::{Deserialize, Serialize};

/// A participating medium (one kind key under `[media.NAME]`).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MediumDesc {
    /// The same coefficients everywhere.
    Homogeneous(HomogeneousDesc),
}

/// Keys of a homogeneous medium (pbrt-v4's `homogeneous`).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HomogeneousDesc {
    /// A measured medium by name (pbrt-v4's presets, in mm⁻¹): replaces
    /// `sigma_a` and `sigma_s`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// Absorption coefficient per unit length (default `[1, 1, 1]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_a: Option<Rgb>,
    /// Scattering coefficient per unit length (default `[1, 1, 1]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_s: Option<Rgb>,
    /// Multiplies both coefficients (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<NonNegative>,
    /// Henyey–Greenstein asymmetry, −1 < g < 1 (default 0, isotropic).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub g: Option<Finite>,
    /// Emitted radiance Lₑ (emission per unit length is σₐ Lₑ; default
    /// none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emission: Option<Rgb>,
}
