//! Scene files: TOML or JSON text (the same structure in either syntax,
//! documented key by key in `docs/scene-format.md`) read into a
//! [`SceneDescription`] and built, through the public
//! [`SceneBuilder`](crate::scene::SceneBuilder), into a
//! [`Scene`] and the [`RenderSettings`] of its `[render]` table.
//!
//! The loader is one client of the builder, as the pbrt-v4 importer and the
//! Python bindings are meant to be: it adds what the file names (groups and
//! prototypes flattened with their transforms and inherited materials) and
//! attaches file positions to the builder's errors.

mod build;
mod camera;
mod description;
mod export;
pub mod gltf;
mod locate;
mod materials;
mod media;
mod objects;
pub mod pbrt;
mod source;
mod textures;
mod values;

pub use description::*;
pub use export::{export_scene, ExportError, ExportSummary};
pub use source::{is_pbrt_path, SceneOverrides, SceneSource};
pub use values::*;

use crate::render::RenderSettings;
use crate::scene::{Scene, SceneError, SourceLocation};
use std::path::{Path, PathBuf};

/// The two scene syntaxes; the structure is the same.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneFormat {
    /// TOML (`.toml`).
    Toml,
    /// JSON (`.json`).
    Json,
}

impl SceneFormat {
    /// The format for a file name, by extension.
    pub fn from_path(path: &Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "toml" => Some(SceneFormat::Toml),
            "json" => Some(SceneFormat::Json),
            _ => None,
        }
    }
}

/// A parsed scene file: its description plus the source text, kept for
/// error messages while the scene is built.
#[derive(Clone, Debug)]
pub struct SceneFile {
    /// Where it came from.
    pub path: Option<PathBuf>,
    /// The file's text.
    pub source: String,
    /// The parsed description; may be edited (e.g. command-line overrides)
    /// before [`SceneFile::build`].
    pub description: SceneDescription,
}

/// A scene and the settings its file gives for rendering it.
#[derive(Clone, Debug)]
pub struct LoadedScene {
    /// What to render.
    pub scene: Scene,
    /// How to render it (the `[render]` table).
    pub settings: RenderSettings,
    /// The other files the scene was built from (meshes, environment
    /// images), sorted: what a checkpoint's fingerprint must cover besides
    /// the scene file.
    pub files: Vec<PathBuf>,
}

/// Load and build a scene file (`.toml` or `.json`).
pub fn load_scene(path: impl AsRef<Path>) -> Result<LoadedScene, SceneError> {
    SceneFile::load(path)?.build()
}

/// Parse and build a scene from text.
///
/// ```
/// use lucent::loader::{parse_scene, SceneFormat};
/// let loaded = parse_scene(r#"
///     [camera]
///     eye = [0, 0, -5]
///     look_at = [0, 0, 0]
///     [materials.red.matte]
///     color = [1, 0, 0]
///     [[sphere]]
///     radius = 1
///     material = "red"
/// "#, SceneFormat::Toml).unwrap();
/// assert_eq!(loaded.scene.primitives().len(), 1);
/// assert_eq!(loaded.settings.spp, 16);
/// ```
pub fn parse_scene(source: &str, format: SceneFormat) -> Result<LoadedScene, SceneError> {
    SceneFile::parse(source.to_owned(), format, None)?.build()
}

impl SceneFile {
    /// Read and parse a file; the format follows the extension.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, SceneError> {
        let path = path.as_ref();
        let owned = Some(path.to_owned());
        let format = SceneFormat::from_path(path)
            .ok_or_else(|| SceneError::new(owned.clone(), "unknown scene file extension (accepted: .toml, .json)"))?;
        if path.is_dir() {
            return Err(SceneError::new(owned, "cannot read the scene file: it is a directory"));
        }
        let bytes = std::fs::read(path)
            .map_err(|e| SceneError::new(owned.clone(), format!("cannot read the scene file: {}", io_reason(&e))))?;
        let source = String::from_utf8(bytes).map_err(|e| {
            let loc = SourceLocation::from_offset("", 0);
            let valid = e.utf8_error().valid_up_to();
            let text = String::from_utf8_lossy(&e.as_bytes()[..valid]).into_owned();
            let loc = if text.is_empty() { loc } else { SourceLocation::from_offset(&text, valid) };
            SceneError::at(owned.clone(), &text, Some(loc), "the file is not valid UTF-8 text")
        })?;
        Self::parse(source, format, owned)
    }

    /// Parse scene text.
    pub fn parse(source: String, format: SceneFormat, path: Option<PathBuf>) -> Result<Self, SceneError> {
        let description = match format {
            SceneFormat::Toml => toml::from_str::<SceneDescription>(&source).map_err(|e| {
                let loc = e.span().map(|s| SourceLocation::from_offset(&source, s.start));
                SceneError::at(path.clone(), &source, loc, explain(e.message().trim_end()))
            })?,
            SceneFormat::Json => serde_json::from_str::<SceneDescription>(&source).map_err(|e| {
                let full = e.to_string();
                let message = match full.rfind(" at line ") {
                    Some(i) => full[..i].to_owned(),
                    None => full,
                };
                let loc = (e.line() > 0).then(|| SourceLocation { line: e.line(), column: e.column().max(1) });
                SceneError::at(path.clone(), &source, loc, explain(&message))
            })?,
        };
        Ok(Self { path, source, description })
    }

    fn error(&self, location: Option<SourceLocation>, message: impl Into<String>) -> SceneError {
        SceneError::at(self.path.clone(), &self.source, location, message)
    }
}

/// Add a hint to parser messages that need one.
fn explain(message: &str) -> String {
    if message == "missing field `camera`" {
        "missing field `camera`: every scene needs a [camera] table with at least `eye` and `look_at`".to_owned()
    } else {
        message.to_owned()
    }
}

fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_owned(),
        std::io::ErrorKind::PermissionDenied => "permission denied".to_owned(),
        _ => e.to_string(),
    }
}
