//! The scene file format, as Rust types. A TOML or JSON scene file
//! deserialises into [`SceneDescription`]; every key is documented in
//! `docs/scene-format.md`. Unknown keys are errors.

mod lights;
mod materials;
mod media;
mod objects;
mod settings;
mod textures;

pub use lights::*;
pub use materials::*;
pub use media::*;
pub use objects::*;
pub use settings::*;
pub use textures::*;

use super::values::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A whole scene file.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDescription {
    /// The camera.
    pub camera: CameraDesc,
    /// Image and sampling settings.
    #[serde(default)]
    pub render: RenderDesc,
    /// Environment light (path integrator).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub environment: Option<EnvironmentDesc>,
    /// Ambient light.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambient: Option<AmbientDesc>,
    /// Named textures, referred to by name from texture-valued material
    /// parameters and from other textures.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub textures: BTreeMap<String, TextureDesc>,
    /// Named materials.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub materials: BTreeMap<String, MaterialDesc>,
    /// Named participating media.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub media: BTreeMap<String, MediumDesc>,
    /// Point lights.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub point_light: Vec<PointLightDesc>,
    /// Spot lights.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub spot_light: Vec<SpotLightDesc>,
    /// Directional lights.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub directional_light: Vec<DirectionalLightDesc>,
    /// Spheres.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sphere: Vec<SphereDesc>,
    /// Planes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub plane: Vec<PlaneDesc>,
    /// Triangles.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub triangle: Vec<TriangleDesc>,
    /// Quadrilaterals.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub quad: Vec<QuadDesc>,
    /// Disks.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub disk: Vec<DiskDesc>,
    /// Cylinders.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cylinder: Vec<CylinderDesc>,
    /// Groups of objects with a shared transform.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub group: Vec<GroupDesc>,
    /// Named mesh files, loaded once and placed by `[[mesh]] mesh = "NAME"`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub meshes: BTreeMap<String, MeshFileDesc>,
    /// Placed meshes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mesh: Vec<MeshDesc>,
    /// Named groups defined once and placed by `[[instance]]`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub prototypes: BTreeMap<String, GroupDesc>,
    /// Placements of prototypes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub instance: Vec<InstanceDesc>,
}

// Defaults shared by several tables.

fn white() -> Rgb {
    Rgb([1.0; 3])
}

fn one() -> NonNegative {
    NonNegative(1.0)
}

fn positive_one() -> Positive {
    Positive(1.0)
}

fn default_up() -> Direction {
    Direction([0.0, 1.0, 0.0])
}
