//! The pbrt-v4 importer: builds a lucent [`Scene`](crate::scene::Scene)
//! from the directives of a pbrt-v4 file, through the public
//! [`SceneBuilder`] (never through another format's text).
//!
//! It keeps pbrt-v4's graphics state (book §C.2): the current
//! transformation matrix (CTM), the material, the area light, the colour
//! space and `ReverseOrientation`, saved and restored by
//! `AttributeBegin`/`AttributeEnd`; named coordinate systems, materials,
//! textures and objects. Each directive becomes builder calls:
//!
//! | pbrt-v4 | lucent |
//! |---|---|
//! | `Camera`, `Film`, `Sampler`, `PixelFilter`, `Integrator` | [`Camera`](crate::camera::Camera) and [`RenderSettings`] ([`options`]) |
//! | `Material`, `MakeNamedMaterial`, `Texture` | [`SceneBuilder::add_material`] ([`materials`]) |
//! | `Shape` (+ `AreaLightSource`) | [`SceneBuilder::add`], emissive or not ([`shapes`]) |
//! | `LightSource` | [`SceneBuilder::add_light`], [`SceneBuilder::set_environment`] ([`lights`]) |
//! | `ObjectBegin`/`ObjectEnd`/`ObjectInstance` | prototypes and instances (shared meshes and BVHs) |
//!
//! Whatever lucent does not implement is reported once per kind as a
//! warning with its position and what was done instead ([`Warnings`]);
//! with [`ImportOptions::strict`] the first one is an error. Parameters a
//! directive does not use are reported the same way (pbrt-v4 itself stops
//! on them).

mod cameras;
mod lights;
mod materials;
mod media;
mod options;
mod shapes;
mod spectra;
mod textures;
mod warnings;

pub use warnings::Warnings;

use super::{parse_file, Directive, Loc, ParamList, PbrtError};
use crate::color::Color;
use crate::geometry::{Mat4, Transform, Vec3};
use crate::loader::LoadedScene;
use crate::material::MaterialId;
use crate::render::RenderSettings;
use crate::scene::{SceneBuilder, SceneError};
use materials::MaterialTable;
use options::RenderOptions;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// How a pbrt-v4 file is imported.
#[derive(Clone, Debug, Default)]
pub struct ImportOptions {
    /// Make every warning (an unsupported feature, an unused parameter) an
    /// error.
    pub strict: bool,
    /// Use this image for every `infinite` light with a `filename` instead
    /// of the file the scene names (for scenes shipped without their
    /// environment map).
    pub environment: Option<PathBuf>,
    /// Replace the `Film`'s `xresolution` and/or `yresolution`.
    pub resolution: Option<(Option<u32>, Option<u32>)>,
}

/// Import the pbrt-v4 scene `path` (`.pbrt`, or `.pbrt.gz`): the scene, the
/// render settings its `Film`, `Sampler`, `PixelFilter` and `Integrator`
/// give, and the files it read. Warnings are in the scene's
/// [`warnings`](crate::scene::Scene::warnings).
///
/// ```no_run
/// use lucent::loader::pbrt::{import_pbrt, ImportOptions};
/// let loaded = import_pbrt("cornell-box.pbrt", &ImportOptions::default())?;
/// println!("{} warnings", loaded.scene.warnings().len());
/// # Ok::<(), lucent::scene::SceneError>(())
/// ```
pub fn import_pbrt(path: impl AsRef<Path>, options: &ImportOptions) -> Result<LoadedScene, SceneError> {
    let path = path.as_ref();
    let mut importer = Importer::new(path, options);
    parse_file(path, &mut |directive, loc| importer.directive(directive, loc))?;
    Ok(importer.finish()?)
}

/// What `AttributeBegin`, `TransformBegin` and `ObjectBegin` saved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scope {
    Attribute,
    Transform,
    Object,
}

/// The area light that shapes get while it is set.
#[derive(Clone, Debug)]
pub(crate) struct AreaLightSpec {
    /// Emitted radiance (scale applied).
    pub radiance: Color,
    /// Both sides emit.
    pub two_sided: bool,
    /// An image over the surface's texture coordinates (`filename`),
    /// multiplying `radiance`.
    pub image: Option<crate::texture::Texture>,
}

/// pbrt-v4's graphics state (the part lucent uses).
#[derive(Clone, Debug)]
pub(crate) struct GraphicsState {
    /// Current transformation matrix: object (or light, camera) to world.
    pub ctm: Transform,
    /// Transforms given while `ActiveTransform EndTime` was set (motion
    /// blur) are ignored; this records whether it is set.
    pub end_time_only: bool,
    /// Flip which side of a shape is its front (area lights).
    pub reverse_orientation: bool,
    /// The current material.
    pub material: Option<MaterialId>,
    /// The current area light.
    pub area_light: Option<AreaLightSpec>,
    /// The RGB colour space of `rgb` values.
    pub color_space: crate::spectrum::ColorSpace,
    /// `Attribute "shape"|"light"|"material"|"texture"` defaults.
    pub attributes: HashMap<String, ParamList>,
    /// The current `MediumInterface`: the names of the media inside and
    /// outside the shapes that follow (`""`: vacuum).
    pub medium_inside: String,
    /// See `medium_inside`.
    pub medium_outside: String,
}

/// The importer's state while the directives stream in.
pub(crate) struct Importer<'a> {
    pub options: &'a ImportOptions,
    /// The top-level file.
    pub path: PathBuf,
    pub builder: SceneBuilder,
    pub warnings: Warnings,
    pub state: GraphicsState,
    stack: Vec<(GraphicsState, Scope, Loc)>,
    named_coordinate_systems: HashMap<String, Transform>,
    pub materials: MaterialTable,
    /// Camera, film, sampler, filter and integrator, until `WorldBegin`.
    pub render: RenderOptions,
    in_world: bool,
    /// The object being defined, if any.
    object: Option<(String, Loc)>,
    /// Every file read: scene files, meshes, images, spectra.
    pub files: Vec<PathBuf>,
    /// The file of the last directive.
    last_file: Option<std::sync::Arc<PathBuf>>,
    /// Images read for textures, each once.
    pub images: crate::texture::ImageCache,
    /// Named media (`None`: a kind that is not supported, rendered as
    /// vacuum).
    pub media: HashMap<String, Option<crate::medium::MediumId>>,
    /// The name of the medium the camera is in, and where the camera was
    /// given (resolved at the end: the medium may be defined after it).
    camera_medium: Option<(String, Loc)>,
    /// Media named by shapes before their `MakeNamedMedium`, with where
    /// each was first named: their handles hold vacuum until it comes.
    pub pending_media: HashMap<String, Loc>,
}

/// Most attribute scopes open at once.
const MAX_NESTING: usize = 100_000;

impl<'a> Importer<'a> {
    fn new(path: &Path, options: &'a ImportOptions) -> Self {
        Self {
            options,
            path: path.to_path_buf(),
            builder: SceneBuilder::new(options::placeholder_camera()),
            warnings: Warnings::new(options.strict),
            state: GraphicsState {
                ctm: Transform::IDENTITY,
                end_time_only: false,
                reverse_orientation: false,
                material: None,
                area_light: None,
                color_space: crate::spectrum::ColorSpace::Srgb,
                attributes: HashMap::new(),
                medium_inside: String::new(),
                medium_outside: String::new(),
            },
            stack: Vec::new(),
            named_coordinate_systems: HashMap::new(),
            materials: MaterialTable::default(),
            render: RenderOptions::default(),
            in_world: false,
            object: None,
            files: Vec::new(),
            last_file: None,
            images: crate::texture::ImageCache::new(),
            media: HashMap::new(),
            camera_medium: None,
            pending_media: HashMap::new(),
        }
    }

    /// Apply `t` to the CTM as pbrt does (`ctm = ctm · t`: `t` acts on the
    /// object first).
    fn transform(&mut self, t: Transform) {
        if !self.state.end_time_only {
            self.state.ctm = t.then(&self.state.ctm);
        }
    }

    fn set_transform(&mut self, t: Transform) {
        if !self.state.end_time_only {
            self.state.ctm = t;
        }
    }

    fn require_world(&self, loc: &Loc, what: &str, inside: bool) -> Result<(), PbrtError> {
        match (inside, self.in_world) {
            (true, false) => Err(PbrtError::at(loc, format!("{what} is only allowed after WorldBegin"))),
            (false, true) => Err(PbrtError::at(loc, format!("{what} is only allowed before WorldBegin"))),
            _ => Ok(()),
        }
    }

    /// Handle one directive.
    fn directive(&mut self, d: Directive, loc: &Loc) -> Result<(), PbrtError> {
        // Every scene file read (the top-level one and its includes) is part
        // of what a checkpoint's fingerprint covers.
        if self.last_file.as_ref().is_none_or(|f| !std::sync::Arc::ptr_eq(f, &loc.file)) {
            self.files.push(loc.file.as_ref().clone());
            self.files.extend(loc.included_from.iter().map(|(file, _, _)| file.as_ref().clone()));
            self.last_file = Some(loc.file.clone());
        }
        match d {
            Directive::Camera(ty, params) => {
                self.require_world(loc, "Camera", false)?;
                let camera_from_world = self.state.ctm;
                // pbrt-v4: the "camera" coordinate system is world-from-camera.
                self.named_coordinate_systems.insert("camera".into(), camera_from_world.inverse());
                self.render.camera = Some((ty, params, camera_from_world, loc.clone()));
                // pbrt-v4's CameraMedium: the current outside medium.
                self.camera_medium =
                    (!self.state.medium_outside.is_empty()).then(|| (self.state.medium_outside.clone(), loc.clone()));
            }
            Directive::Film(ty, params) => {
                self.require_world(loc, "Film", false)?;
                self.render.film = Some((ty, params, loc.clone()));
            }
            Directive::Sampler(ty, params) => {
                self.require_world(loc, "Sampler", false)?;
                self.render.sampler = Some((ty, params, loc.clone()));
            }
            Directive::PixelFilter(ty, params) => {
                self.require_world(loc, "PixelFilter", false)?;
                self.render.filter = Some((ty, params, loc.clone()));
            }
            Directive::Integrator(ty, params) => {
                self.require_world(loc, "Integrator", false)?;
                self.render.integrator = Some((ty, params, loc.clone()));
            }
            Directive::Accelerator(ty, params) => {
                self.require_world(loc, "Accelerator", false)?;
                // lucent always builds its own BVH; the choice changes speed only.
                for p in &params.params {
                    p.used.set(true);
                }
                if ty != "bvh" && ty != "kdtree" {
                    self.warnings.warn(loc, format!("unknown Accelerator \"{ty}\": lucent's BVH is used"))?;
                }
            }
            Directive::ColorSpace(name) => {
                self.state.color_space = crate::spectrum::ColorSpace::from_name(&name)
                    .map_err(|e| PbrtError::at(loc, format!("ColorSpace: {e}")))?;
            }
            Directive::Option(params) => self.option(&params, loc)?,
            Directive::WorldBegin => {
                self.require_world(loc, "WorldBegin", false)?;
                self.in_world = true;
                self.state.ctm = Transform::IDENTITY;
                self.named_coordinate_systems.insert("world".into(), Transform::IDENTITY);
                let mut render = std::mem::take(&mut self.render);
                render.apply(self, loc)?;
                self.render = render;
            }
            Directive::AttributeBegin => self.push(Scope::Attribute, loc)?,
            Directive::AttributeEnd => self.pop(Scope::Attribute, loc)?,
            Directive::TransformBegin => {
                self.warnings.warn_once(
                    "TransformBegin",
                    loc,
                    "TransformBegin/TransformEnd are deprecated in pbrt-v4 (read as saving and restoring the transform)",
                )?;
                self.push(Scope::Transform, loc)?
            }
            Directive::TransformEnd => self.pop(Scope::Transform, loc)?,
            Directive::Attribute(target, params) => {
                if !matches!(target.as_str(), "shape" | "light" | "material" | "medium" | "texture") {
                    return Err(PbrtError::at(
                        loc,
                        format!(
                            "unknown Attribute target \"{target}\" (accepted: \"shape\", \"light\", \"material\", \"medium\", \"texture\")"
                        ),
                    ));
                }
                let entry = self.state.attributes.entry(target).or_default();
                for p in params.params {
                    entry.params.retain(|q| q.name != p.name);
                    entry.params.push(p);
                }
            }
            Directive::Identity => self.set_transform(Transform::IDENTITY),
            Directive::Translate(v) => self.transform(Transform::translate(Vec3::from(v))),
            Directive::Scale(s) => {
                let t = Transform::scale(Vec3::from(s))
                    .map_err(|e| PbrtError::at(loc, format!("Scale {} {} {}: {e}", s[0], s[1], s[2])))?;
                self.transform(t)
            }
            Directive::Rotate(angle, axis) => {
                let t = Transform::rotate(Vec3::from(axis), angle)
                    .map_err(|_| PbrtError::at(loc, "Rotate: the axis has zero length"))?;
                self.transform(t)
            }
            Directive::LookAt(v) => {
                let t = look_at(Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]), Vec3::new(v[6], v[7], v[8]))
                    .map_err(|e| PbrtError::at(loc, format!("LookAt: {e}")))?;
                self.transform(t)
            }
            Directive::Transform(m) => {
                let t = matrix(&m).map_err(|e| PbrtError::at(loc, format!("Transform: {e}")))?;
                self.set_transform(t)
            }
            Directive::ConcatTransform(m) => {
                let t = matrix(&m).map_err(|e| PbrtError::at(loc, format!("ConcatTransform: {e}")))?;
                self.transform(t)
            }
            Directive::CoordinateSystem(name) => {
                self.named_coordinate_systems.insert(name, self.state.ctm);
            }
            Directive::CoordSysTransform(name) => match self.named_coordinate_systems.get(&name) {
                Some(t) => self.state.ctm = *t,
                None => {
                    let mut known: Vec<&str> = self.named_coordinate_systems.keys().map(String::as_str).collect();
                    known.sort_unstable();
                    return Err(PbrtError::at(
                        loc,
                        format!("unknown coordinate system \"{name}\" (defined so far: {})", list(&known)),
                    ));
                }
            },
            Directive::ActiveTransform(which) => {
                use super::ActiveTransform;
                if which != ActiveTransform::All {
                    self.warnings.warn_once(
                        "motion",
                        loc,
                        "motion blur (ActiveTransform) is not supported: everything is rendered at the start time",
                    )?;
                }
                self.state.end_time_only = which == ActiveTransform::End;
            }
            Directive::TransformTimes(_, _) => {
                self.warnings.warn_once(
                    "motion",
                    loc,
                    "motion blur (TransformTimes) is not supported: everything is rendered at the start time",
                )?;
            }
            Directive::ReverseOrientation => self.state.reverse_orientation = !self.state.reverse_orientation,
            Directive::Shape(ty, params) => {
                self.require_world(loc, "Shape", true)?;
                let params = self.with_attributes("shape", params);
                self.shape(&ty, &params, loc)?;
                self.check_unused(&params, &format!("Shape \"{ty}\""))?;
            }
            Directive::Material(ty, params) => {
                self.require_world(loc, "Material", true)?;
                let params = self.with_attributes("material", params);
                let id = self.material(&ty, &params, loc)?;
                self.state.material = Some(id);
                self.check_unused(&params, &format!("Material \"{ty}\""))?;
            }
            Directive::MakeNamedMaterial(name, params) => {
                self.require_world(loc, "MakeNamedMaterial", true)?;
                let params = self.with_attributes("material", params);
                let ty = params.string("type")?.ok_or_else(|| {
                    PbrtError::at(loc, format!("MakeNamedMaterial \"{name}\" needs a \"string type\" parameter"))
                })?;
                let id = self.material(ty, &params, loc)?;
                if self.materials.named.insert(name.clone(), id).is_some() {
                    self.warnings.warn(loc, format!("named material \"{name}\" redefined"))?;
                }
                self.check_unused(&params, &format!("MakeNamedMaterial \"{name}\""))?;
            }
            Directive::NamedMaterial(name) => {
                self.require_world(loc, "NamedMaterial", true)?;
                let id = *self.materials.named.get(&name).ok_or_else(|| {
                    PbrtError::at(
                        loc,
                        format!("named material \"{name}\" is not defined (MakeNamedMaterial must come first)"),
                    )
                })?;
                self.state.material = Some(id);
            }
            Directive::Texture { name, value_type, class, params } => {
                self.require_world(loc, "Texture", true)?;
                let params = self.with_attributes("texture", params);
                self.texture(&name, &value_type, &class, &params, loc)?;
                self.check_unused(&params, &format!("Texture \"{name}\""))?;
            }
            Directive::LightSource(ty, params) => {
                self.require_world(loc, "LightSource", true)?;
                let params = self.with_attributes("light", params);
                self.light(&ty, &params, loc)?;
                self.check_unused(&params, &format!("LightSource \"{ty}\""))?;
            }
            Directive::AreaLightSource(ty, params) => {
                self.require_world(loc, "AreaLightSource", true)?;
                let params = self.with_attributes("light", params);
                self.area_light(&ty, &params, loc)?;
                self.check_unused(&params, &format!("AreaLightSource \"{ty}\""))?;
            }
            Directive::MakeNamedMedium(name, params) => {
                let params = self.with_attributes("medium", params);
                self.make_named_medium(&name, &params, loc)?;
                self.check_unused(&params, &format!("MakeNamedMedium \"{name}\""))?;
            }
            Directive::MediumInterface(inside, outside) => {
                self.state.medium_inside = inside;
                self.state.medium_outside = outside;
            }
            Directive::ObjectBegin(name) => {
                self.require_world(loc, "ObjectBegin", true)?;
                if let Some((open, at)) = &self.object {
                    return Err(PbrtError::at(
                        loc,
                        format!(
                            "ObjectBegin \"{name}\" inside object \"{open}\" (begun at line {}): objects do not nest",
                            at.line
                        ),
                    ));
                }
                self.push(Scope::Object, loc)?;
                self.builder.begin_prototype(&name).map_err(|e| builder_error(loc, e))?;
                self.object = Some((name, loc.clone()));
            }
            Directive::ObjectEnd => {
                if self.object.is_none() {
                    return Err(PbrtError::at(loc, "ObjectEnd without ObjectBegin"));
                }
                self.pop(Scope::Object, loc)?;
                self.builder.end_prototype().map_err(|e| builder_error(loc, e))?;
                self.object = None;
            }
            Directive::ObjectInstance(name) => {
                self.require_world(loc, "ObjectInstance", true)?;
                if self.object.is_some() {
                    return Err(PbrtError::at(loc, "ObjectInstance inside ObjectBegin/ObjectEnd is not allowed"));
                }
                if !self.builder.prototype_names().any(|n| n == name) {
                    return Err(PbrtError::at(
                        loc,
                        format!("object \"{name}\" is not defined (ObjectBegin must come first)"),
                    ));
                }
                let transform = self.state.ctm;
                self.builder.add_instance(&name, transform, None).map_err(|e| builder_error(loc, e))?;
            }
        }
        Ok(())
    }

    fn option(&mut self, params: &ParamList, loc: &Loc) -> Result<(), PbrtError> {
        for p in &params.params {
            p.used.set(true);
            match p.name.as_str() {
                // Options that change nothing lucent renders.
                "disablepixeljitter"
                | "disabletexturefiltering"
                | "disablewavelengthjitter"
                | "forcediffuse"
                | "pixelstats"
                | "wavefront"
                | "seed"
                | "displacementedgescale"
                | "msereferenceimage"
                | "msereferenceout"
                | "rendercoordsys" => self.warnings.warn(loc, format!("Option \"{}\" is ignored by lucent", p.name))?,
                other => self.warnings.warn(loc, format!("unknown Option \"{other}\" (ignored)"))?,
            }
        }
        Ok(())
    }

    /// Parameters of a directive plus the `Attribute` defaults of `target`
    /// that it does not give itself.
    fn with_attributes(&self, target: &str, mut params: ParamList) -> ParamList {
        if let Some(defaults) = self.state.attributes.get(target) {
            for p in &defaults.params {
                if !params.params.iter().any(|q| q.name == p.name) {
                    params.params.push(p.clone());
                }
            }
        }
        params
    }

    /// Report every parameter the directive did not use.
    pub fn check_unused(&mut self, params: &ParamList, what: &str) -> Result<(), PbrtError> {
        let unused: Vec<(Loc, String)> = params.unused().map(|p| (p.loc.clone(), p.describe())).collect();
        for (loc, name) in unused {
            self.warnings.warn(&loc, format!("{what}: parameter {name} is not used by lucent (ignored)"))?;
        }
        Ok(())
    }

    fn push(&mut self, scope: Scope, loc: &Loc) -> Result<(), PbrtError> {
        if self.stack.len() >= MAX_NESTING {
            return Err(PbrtError::at(loc, format!("more than {MAX_NESTING} nested AttributeBegin")));
        }
        self.stack.push((self.state.clone(), scope, loc.clone()));
        Ok(())
    }

    fn pop(&mut self, scope: Scope, loc: &Loc) -> Result<(), PbrtError> {
        let name = |s: Scope| match s {
            Scope::Attribute => "AttributeEnd",
            Scope::Transform => "TransformEnd",
            Scope::Object => "ObjectEnd",
        };
        match self.stack.pop() {
            None => Err(PbrtError::at(loc, format!("{} without a matching begin", name(scope)))),
            Some((state, open, at)) if open == scope => {
                if scope == Scope::Transform {
                    // TransformEnd restores only the transform.
                    self.state.ctm = state.ctm;
                    self.state.end_time_only = state.end_time_only;
                } else {
                    self.state = state;
                }
                let _ = at;
                Ok(())
            }
            Some((_, open, at)) => Err(PbrtError::at(
                loc,
                format!("{} closes the scope opened at line {} by the begin of {}", name(scope), at.line, name(open)),
            )),
        }
    }

    fn finish(mut self) -> Result<LoadedScene, PbrtError> {
        let end = Loc::new(self.path.clone(), 1, 1);
        if let Some((name, loc)) = &self.object {
            return Err(PbrtError::at(loc, format!("object \"{name}\" is never ended (ObjectEnd missing)")));
        }
        if let Some((_, _, loc)) = self.stack.last() {
            return Err(PbrtError::at(loc, "this AttributeBegin is never closed (AttributeEnd missing)"));
        }
        if !self.in_world {
            // pbrt-v4 stops with "End of files before WorldBegin": a file
            // without a world is truncated or not a scene.
            return Err(PbrtError::at(
                &end,
                "the file ends before \"WorldBegin\": a pbrt-v4 scene gives its camera and film, then WorldBegin, then its lights and shapes (is the file empty or cut short?)",
            ));
        }
        let settings: RenderSettings = self.render.settings.clone().unwrap_or_default();
        if let Some((ty, _, loc)) = &self.render.integrator {
            if ty == "path" && self.media.values().any(Option::is_some) {
                let loc = loc.clone();
                self.warnings.warn(
                    &loc,
                    "Integrator \"path\" with participating media: pbrt-v4's \"path\" ignores media (\"volpath\" renders them); lucent renders them",
                )?;
            }
        }
        if let Some((name, loc)) = self.pending_media.iter().min_by_key(|(_, l)| (l.line, l.column)) {
            return Err(PbrtError::at(
                loc,
                format!("medium \"{name}\" is not defined (the file has no MakeNamedMedium \"{name}\")"),
            ));
        }
        if let Some((name, loc)) = self.camera_medium.take() {
            let id = self.medium_named(&name, &loc)?;
            self.builder.set_camera_medium(id).map_err(|e| builder_error(&loc, e))?;
        }
        for w in self.warnings.messages() {
            self.builder.warn(w.clone());
        }
        let scene = self.builder.build().map_err(|e| PbrtError { loc: None, message: e.message })?;
        self.files.sort();
        self.files.dedup();
        Ok(LoadedScene { scene, settings, files: self.files })
    }

    /// Resolve a file name given in a parameter: relative to the directory
    /// of the file that names it, else to the top-level file's directory
    /// (pbrt-v4's search directory).
    pub fn resolve(&self, name: &str, loc: &Loc) -> PathBuf {
        let p = Path::new(name);
        if p.is_absolute() {
            return p.to_path_buf();
        }
        let here = loc.file.parent().unwrap_or(Path::new("")).join(p);
        if here.exists() {
            return here;
        }
        let top = self.path.parent().unwrap_or(Path::new("")).join(p);
        if top.exists() {
            top
        } else {
            here
        }
    }
}

/// A builder error, placed at `loc`.
pub(crate) fn builder_error(loc: &Loc, e: SceneError) -> PbrtError {
    PbrtError::at(loc, e.message)
}

/// pbrt's `LookAt`: the world-to-camera transform of a camera at `eye`
/// looking at `look` with `up` (left-handed camera space: `+z` is the view
/// direction, `+x = up × dir`, `+y = dir × x`; pbrt-v4 book §3.9.5).
pub(crate) fn look_at(eye: Vec3, look: Vec3, up: Vec3) -> Result<Transform, String> {
    let dir = (look - eye).try_normalize().ok_or("the eye and the look-at point coincide")?;
    let right = up.try_normalize().ok_or("the up vector has zero length")?.cross(dir);
    let right = right.try_normalize().ok_or("the up vector is parallel to the view direction")?;
    let new_up = dir.cross(right);
    let world_from_camera = Mat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), eye.extend(1.0));
    Transform::from_matrix(world_from_camera).map(|t| t.inverse()).map_err(|e| e.to_string())
}

/// A `Transform`/`ConcatTransform` matrix: pbrt lists the 16 numbers
/// column by column (the translation is in elements 12–14).
pub(crate) fn matrix(m: &[f32; 16]) -> Result<Transform, String> {
    Transform::from_matrix(Mat4::from_cols_array(m)).map_err(|e| e.to_string())
}

/// `"a", "b", "c"` for a message.
pub(crate) fn list(names: &[&str]) -> String {
    if names.is_empty() {
        return "none".into();
    }
    names.iter().map(|n| format!("\"{n}\"")).collect::<Vec<_>>().join(", ")
}
