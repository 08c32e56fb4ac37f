//! Writing a scene back out as a scene file: the scene model
//! ([`Scene`](crate::scene::Scene) and its
//! [`RenderSettings`](crate::render::RenderSettings)) described in the
//! TOML/JSON format ([`SceneDescription`](super::SceneDescription)), meshes
//! as PLY files beside it. `lucent convert` is this, after an import.

mod materials;
mod scene;

pub(crate) use materials::*;
pub(crate) use scene::relative_path;
pub use scene::{export_scene, ExportError, ExportSummary};
