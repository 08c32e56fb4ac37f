//! glTF 2.0 scenes (`.gltf` with its buffers and images, or one `.glb`),
//! parsed and validated by the `gltf` crate and built through the public
//! [`SceneBuilder`](crate::scene::SceneBuilder), as every other way into a
//! scene is. `docs/gltf.md` is the user's guide: what is read, what each
//! unit becomes, what is warned about.
//!
//! The importer in one pass over the chosen scene's node tree:
//! * **meshes** ([`meshes`]): each primitive is a lucent mesh, built once and
//!   placed by every node that uses it (instancing); accessors are read by
//!   hand ([`accessor`]) so that every component type and every malformed
//!   range is handled;
//! * **materials** ([`materials`]): glTF's metallic-roughness model and its
//!   Khronos extensions, normal maps, emission (area lights), alpha;
//! * **lights** and **cameras** ([`nodes`]): `KHR_lights_punctual` and the
//!   glTF cameras, placed by their nodes.
//!
//! glTF is right-handed with `+y` up, metres, and cameras looking down
//! their `−z`; lucent's world has no handedness of its own, so positions
//! are used as they are.

mod accessor;
mod data;
mod materials;
mod meshes;
mod nodes;

use super::LoadedScene;
use crate::camera::Camera;
use crate::color::Color;
use crate::light::Environment;
use crate::material::MaterialId;
use crate::render::{IntegratorKind, RenderSettings};
use crate::scene::{SceneBuilder, SceneError};
use data::{Buffers, Images};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

/// How to import a glTF file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GltfOptions {
    /// Every warning is an error.
    pub strict: bool,
    /// The environment image (glTF has none).
    pub environment: Option<PathBuf>,
    /// Image width and height, either or both; the other follows the
    /// camera's aspect ratio. Default 1280 wide.
    pub resolution: Option<(Option<u32>, Option<u32>)>,
    /// Which scene (`scenes[N]`); default `scene`, else the first.
    pub scene: Option<usize>,
    /// Which camera: its name or its index in `cameras`; default the first
    /// placed in the scene.
    pub camera: Option<String>,
}

/// Whether `path` names a glTF file (`.gltf`, `.glb`).
pub fn is_gltf_path(path: &Path) -> bool {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    matches!(ext.as_deref(), Some("gltf" | "glb"))
}

/// Why a glTF file cannot be imported, with the JSON path of the element
/// at fault where there is one (`meshes[3].primitives[0]`).
#[derive(Clone, Debug, PartialEq)]
pub struct GltfError {
    /// Where in the document.
    pub path: String,
    /// What is wrong.
    pub message: String,
}

impl GltfError {
    fn new(path: &str, message: impl Into<String>) -> Self {
        Self { path: path.to_owned(), message: message.into() }
    }
}

/// Extensions whose absence would make the scene wrong if they were
/// required (glTF 2.0 §3.12): those lucent honours.
const SUPPORTED: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_clearcoat",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_unlit",
    "KHR_materials_volume",
    "KHR_mesh_quantization",
    "KHR_texture_transform",
];

/// The state of one import.
pub(super) struct Importer<'a> {
    doc: &'a gltf::Document,
    base: &'a Path,
    buffers: &'a Buffers<'a>,
    images: Images,
    builder: SceneBuilder,
    strict: bool,
    warned: HashSet<String>,
    warnings: Vec<String>,
    notes: Vec<String>,
    /// Converted materials by glTF index (`None`: the default material)
    /// and whether the primitive has vertex colours (`COLOR_0` multiplies
    /// the base colour, so a material is converted once with and once
    /// without).
    materials: HashMap<(Option<usize>, bool), (MaterialId, materials::Converted)>,
}

impl Importer<'_> {
    /// A warning, reported once per `kind`; an error under `--strict`.
    fn warn_once(&mut self, kind: &str, message: String) -> Result<(), GltfError> {
        if self.strict {
            return Err(GltfError::new("", format!("{message} (an error because of --strict)")));
        }
        if self.warned.insert(kind.to_owned()) {
            self.warnings.push(message);
        }
        Ok(())
    }

    /// Something `lucent check` says about the file that is no problem.
    fn note(&mut self, message: &str) {
        if !self.notes.iter().any(|n| n == message) {
            self.notes.push(message.to_owned());
        }
    }
}

/// Import the glTF file at `path`.
pub fn import_gltf(path: &Path, options: &GltfOptions) -> Result<LoadedScene, SceneError> {
    let fail = |e: GltfError| {
        let message = if e.path.is_empty() { e.message } else { format!("{}: {}", e.path, e.message) };
        SceneError::new(Some(path.to_owned()), message)
    };
    let bytes = std::fs::read(path).map_err(|e| {
        SceneError::new(Some(path.to_owned()), format!("cannot read the glTF file: {}", super::io_reason(&e)))
    })?;
    let invalid = |e: String| SceneError::new(Some(path.to_owned()), format!("not a valid glTF 2.0 file: {e}"));
    // The JSON (of a `.glb`'s first chunk, or the whole `.gltf`), parsed
    // here so that the required extensions are checked against lucent's
    // list rather than the crate's (which lacks clearcoat, sheen and mesh
    // quantization), then validated by the crate.
    let glb = match bytes.starts_with(b"glTF") {
        true => Some(gltf::Glb::from_slice(&bytes).map_err(|e| invalid(e.to_string()))?),
        false => None,
    };
    let text: &[u8] = glb.as_ref().map_or(&bytes, |g| &g.json);
    let mut root: gltf::json::Root = serde_json::from_slice(text).map_err(|e| invalid(e.to_string()))?;
    let blob: Option<&[u8]> = glb.as_ref().and_then(|g| g.bin.as_deref());
    for ext in &root.extensions_required {
        if !SUPPORTED.contains(&ext.as_str()) {
            return Err(fail(GltfError::new(
                "extensionsRequired",
                format!("the file requires {ext}, which lucent does not support (supported: {})", SUPPORTED.join(", ")),
            )));
        }
    }
    root.extensions_required.clear();
    // gltf-json 1.4.1's validation reads the POSITION accessor before it
    // has checked that the index exists (and panics if not): check first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive.attributes.get(&gltf::json::validation::Checked::Valid(gltf::Semantic::Positions));
            if let Some(i) = position.map(|i| i.value()).filter(|&i| i >= root.accessors.len()) {
                return Err(fail(GltfError::new(
                    &format!("meshes[{m}].primitives[{p}].attributes.POSITION"),
                    format!("refers to accessors[{i}], which does not exist ({} accessors)", root.accessors.len()),
                )));
            }
        }
    }
    let document = gltf::Document::from_json(root).map_err(|e| invalid(e.to_string()))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let buffers = data::read_buffers(&document, blob, base).map_err(fail)?;
    let mut files = vec![path.to_owned()];
    files.extend(buffers.files.iter().cloned());
    // A placeholder camera until the scene's bounds or camera are known.
    let placeholder =
        Camera::new(crate::geometry::Vec3::Z, crate::geometry::Vec3::ZERO, crate::geometry::Vec3::Y, 45.0, 16, 16)
            .expect("a valid camera");
    let mut imp = Importer {
        doc: &document,
        base,
        buffers: &buffers,
        images: Images::default(),
        builder: SceneBuilder::new(placeholder),
        strict: options.strict,
        warned: HashSet::new(),
        warnings: Vec::new(),
        notes: Vec::new(),
        materials: HashMap::new(),
    };
    let mut unsupported_used = Vec::new();
    for ext in document.extensions_used() {
        if !SUPPORTED.contains(&ext) {
            unsupported_used.push(ext.to_owned());
        }
    }
    for ext in unsupported_used {
        imp.warn_once(&ext, format!("extension {ext} is not supported: the file is read without it")).map_err(fail)?;
    }
    let placed = imp.place_nodes(options).map_err(fail)?;
    let Importer { mut builder, images, warnings, notes, .. } = imp;
    files.extend(images.files);
    // glTF has no environment: `--env IMAGE`, else black where the file
    // has lights, else a uniform white sky so that the scene is seen.
    match &options.environment {
        Some(env) => {
            let e =
                Environment::from_file(env, 1.0, 0.0).map_err(|e| SceneError::new(Some(env.clone()), e.to_string()))?;
            builder.set_environment(e)?;
            files.push(env.clone());
        }
        None if !placed.has_lights => {
            builder.set_environment(Environment::Constant(Color::ONE))?;
            builder
                .warn("the file has no lights: it is lit by a uniform white environment (give one with --env IMAGE)");
        }
        None => {}
    }
    for w in warnings {
        builder.warn(w);
    }
    for n in notes.iter().chain(&placed.notes) {
        builder.warn(format!("note: {n}"));
    }
    builder.set_camera(placed.camera);
    let scene = builder.build()?;
    let settings = RenderSettings { spp: 64, ..RenderSettings::for_integrator(IntegratorKind::Path) };
    files.dedup();
    Ok(LoadedScene { scene, settings, files })
}
