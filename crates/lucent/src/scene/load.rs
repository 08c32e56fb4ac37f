//! Reading scene files (TOML or JSON) and building [`Scene`]s from them.

use super::description::*;
use super::error::{SceneError, SourceLocation};
use super::{MaterialId, Primitive, Scene};
use crate::bsdf::ConductorFresnel;
use crate::camera::{Camera, CameraError, ThinLens};
use crate::color::Color;
use crate::film::{check_image_size, Filter, ToneMap};
use crate::geometry::{Mat4, Transform, Vec3};
use crate::light::Environment;
use crate::light::{Falloff, Light};
use crate::material::Material;
use crate::render::{IntegratorKind, RenderSettings};
use crate::sampling::SamplerKind;
use crate::shapes::{Mesh, Plane, Shape, Sphere, Triangle};
use crate::texture::Texture;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

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

/// Load and build a scene file (`.toml` or `.json`).
pub fn load_scene(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
    SceneFile::load(path)?.build()
}

/// Parse and build a scene from text.
///
/// ```
/// use lucent::scene::{parse_scene, SceneFormat};
/// let scene = parse_scene(r#"
///     [camera]
///     eye = [0, 0, -5]
///     look_at = [0, 0, 0]
///     [materials.red.matte]
///     color = [1, 0, 0]
///     [[sphere]]
///     radius = 1
///     material = "red"
/// "#, SceneFormat::Toml).unwrap();
/// assert_eq!(scene.primitives().len(), 1);
/// ```
pub fn parse_scene(source: &str, format: SceneFormat) -> Result<Scene, SceneError> {
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

    /// Validate the description and build the scene.
    pub fn build(&self) -> Result<Scene, SceneError> {
        let d = &self.description;
        let r = &d.render;
        let (w, h) = (r.width.0, r.height.0);
        check_image_size(w, h).map_err(|e| {
            let at = find_key(&self.source, "width", 0)
                .or_else(|| find_key(&self.source, "height", 0))
                .or_else(|| find_header(&self.source, "render"));
            self.error(at, e.to_string())
        })?;

        let c = &d.camera;
        let mut camera = Camera::new(c.eye.into(), c.look_at.into(), c.up.into(), c.fov.get(), w, h).map_err(|e| {
            let key = match e {
                CameraError::NoViewDirection => find_key(&self.source, "look_at", 0),
                CameraError::BadUp => find_key(&self.source, "up", 0).or_else(|| find_key(&self.source, "look_at", 0)),
                _ => None,
            };
            self.error(key.or_else(|| find_header(&self.source, "camera")), format!("[camera]: {e}"))
        })?;
        if let Some(radius) = c.lens_radius {
            let focal_distance =
                c.focal_distance.map_or_else(|| (Vec3::from(c.look_at) - Vec3::from(c.eye)).length(), |f| f.get());
            camera = camera
                .with_lens(ThinLens { radius: radius.get(), focal_distance })
                .map_err(|e| self.error(find_key(&self.source, "lens_radius", 0), e.to_string()))?;
        } else if c.focal_distance.is_some() {
            return Err(self.error(
                find_key(&self.source, "focal_distance", 0),
                "focal_distance needs lens_radius (a pinhole camera has everything in focus)",
            ));
        }

        let mut scene = Scene::new(camera);
        let integrator = match r.integrator {
            IntegratorDesc::Whitted => IntegratorKind::Whitted,
            IntegratorDesc::Path => IntegratorKind::Path,
        };
        let default_depth = match integrator {
            IntegratorKind::Whitted => 5,
            IntegratorKind::Path => 64,
        };
        scene.settings = RenderSettings {
            spp: r.spp.0,
            max_depth: r.max_depth.map_or(default_depth, |d| d.0),
            background: r.background.into(),
            tone_map: match r.tone_map {
                ToneMapDesc::Classic => ToneMap::Classic,
                ToneMapDesc::Clamp => ToneMap::Clamp,
                ToneMapDesc::Reinhard => ToneMap::Reinhard,
                ToneMapDesc::Aces => ToneMap::Aces,
            },
            srgb: r.srgb,
            seed: r.seed,
            integrator,
            sampler: match r.sampler {
                SamplerDesc::Sobol => SamplerKind::Sobol,
                SamplerDesc::Independent => SamplerKind::Independent,
            },
            filter: match r.filter {
                None => Filter::default(),
                Some(f) => self.filter(&f)?,
            },
        };
        if let Some(env) = &d.environment {
            scene.set_environment(Some(self.environment(env)?));
        }
        if let Some(a) = &d.ambient {
            scene.ambient = Color::from(a.color) * a.intensity.get();
        }

        let mut ids = HashMap::new();
        for (name, m) in &d.materials {
            let material = self.material(name, m)?;
            ids.insert(name.clone(), scene.add_material(material));
        }

        for (i, l) in d.point_light.iter().enumerate() {
            let falloff = falloff(l.falloff, Falloff::None);
            scene.add_light(Light::point(l.position.into(), l.color.into(), l.intensity.get(), falloff).map_err(
                |e| self.error(nth_table(&self.source, "point_light", i), format!("point_light #{}: {e}", i + 1)),
            )?);
        }
        for (i, l) in d.spot_light.iter().enumerate() {
            let falloff = falloff(l.falloff, Falloff::InverseSquare);
            let angle = l.angle.get();
            // The default blend width fits inside any cone; one given
            // explicitly must (the light error below says so).
            let delta = l.cone_delta.map_or(angle.min(5.0), NonNegative::get);
            let light = Light::spot(
                l.position.into(),
                l.direction.into(),
                l.color.into(),
                l.intensity.get(),
                angle,
                delta,
                falloff,
            )
            .map_err(|e| self.error(nth_table(&self.source, "spot_light", i), format!("spot_light #{}: {e}", i + 1)))?;
            scene.add_light(light);
        }
        for (i, l) in d.directional_light.iter().enumerate() {
            scene.add_light(Light::directional(l.direction.into(), l.color.into(), l.intensity.get()).map_err(
                |e| {
                    let at = nth_table(&self.source, "directional_light", i);
                    self.error(at, format!("directional_light #{}: {e}", i + 1))
                },
            )?);
        }

        let root = GroupDesc {
            name: None,
            transform: Vec::new(),
            material: None,
            sphere: d.sphere.clone(),
            plane: d.plane.clone(),
            triangle: d.triangle.clone(),
            quad: d.quad.clone(),
            group: d.group.clone(),
            mesh: d.mesh.clone(),
            instance: d.instance.clone(),
        };
        let mut ctx = BuildContext { ids, meshes: HashMap::new(), active_prototypes: Vec::new() };
        let place = Place { label: "", at: None, forced_material: None };
        self.add_group(&mut scene, &mut ctx, &root, Transform::IDENTITY, None, place)?;
        Ok(scene)
    }

    fn material(&self, name: &str, m: &MaterialDesc) -> Result<Material, SceneError> {
        let at = || find_table(&self.source, name);
        let texture = |color: &Option<Rgb>, checker: &Option<CheckerDesc>| match (color, checker) {
            (Some(_), Some(_)) => {
                Err(self.error(at(), format!("material \"{name}\" has both `color` and `checker`; give one")))
            }
            (Some(c), None) => Ok(Texture::Constant((*c).into())),
            (None, Some(ch)) => {
                Ok(Texture::Checker { even: ch.even.into(), odd: ch.odd.into(), scale: ch.scale.get() })
            }
            (None, None) => Ok(Texture::Constant(Color::ONE)),
        };
        let m = match m {
            MaterialDesc::Matte(m) => {
                let mat = Material::matte(texture(&m.color, &m.checker)?, m.kd.get());
                match m.ka {
                    Some(ka) => mat.and_then(|x| x.with_ka(ka.get())),
                    None => mat,
                }
            }
            MaterialDesc::Phong(p) => {
                let mat = Material::phong(
                    texture(&p.color, &p.checker)?,
                    p.kd.get(),
                    p.ks.get(),
                    p.exponent.get(),
                    p.kr.map_or(0.0, NonNegative::get),
                );
                match p.ka {
                    Some(ka) => mat.and_then(|x| x.with_ka(ka.get())),
                    None => mat,
                }
            }
            MaterialDesc::Diffuse(d) => {
                let reflectance = texture(&d.color, &d.checker)?;
                check_albedo(&reflectance).map_err(|e| self.error(at(), format!("material \"{name}\": {e}")))?;
                Ok(Material::Diffuse { reflectance })
            }
            MaterialDesc::Conductor(c) => {
                let fresnel = match (c.color, c.eta, c.k, c.metal) {
                    (Some(color), None, None, None) => {
                        ConductorFresnel::Schlick { r0: Texture::Constant(color.into()) }
                    }
                    (None, Some(eta), Some(k), None) => ConductorFresnel::Complex { eta: eta.into(), k: k.into() },
                    (None, None, None, Some(metal)) => {
                        let (eta, k) = metal_ior(metal);
                        ConductorFresnel::Complex { eta, k }
                    }
                    (None, None, None, None) => ConductorFresnel::Schlick { r0: Texture::Constant(Color::ONE) },
                    _ => {
                        return Err(self.error(
                            at(),
                            format!("material \"{name}\": give one of `color`, `eta` with `k`, or `metal`"),
                        ))
                    }
                };
                if let ConductorFresnel::Schlick { r0: t } = &fresnel {
                    check_albedo(t).map_err(|e| self.error(at(), format!("material \"{name}\": {e}")))?;
                }
                let roughness = self.roughness(name, c.roughness)?;
                Ok(Material::Conductor { fresnel, roughness })
            }
            MaterialDesc::Dielectric(d) => Ok(Material::Dielectric {
                eta: d.eta.map_or(1.5, Positive::get),
                roughness: self.roughness(name, d.roughness)?,
                tint: d.tint.map_or(Color::ONE, Color::from),
            }),
            MaterialDesc::Plastic(p) => {
                let reflectance = texture(&p.color, &p.checker)?;
                check_albedo(&reflectance).map_err(|e| self.error(at(), format!("material \"{name}\": {e}")))?;
                Ok(Material::Plastic {
                    reflectance,
                    eta: p.eta.map_or(1.5, Positive::get),
                    roughness: self.roughness(name, p.roughness)?,
                })
            }
        };
        m.map_err(|e| self.error(at(), format!("material \"{name}\": {e}")))
    }

    /// A GGX roughness, checked to lie in [0, 1].
    fn roughness(&self, name: &str, r: Option<NonNegative>) -> Result<f32, SceneError> {
        let r = r.map_or(0.0, NonNegative::get);
        if r > 1.0 {
            return Err(self.error(
                find_key_after(&self.source, "roughness", find_table(&self.source, name))
                    .or_else(|| find_table(&self.source, name)),
                format!("material \"{name}\": roughness must be from 0 (smooth) to 1, got {r}"),
            ));
        }
        Ok(r)
    }

    fn filter(&self, f: &FilterDesc) -> Result<Filter, SceneError> {
        let radius = |default: f32| f.radius.map_or(default, Positive::get);
        let filter = match f.kind {
            FilterKindDesc::Box => Filter::Box { radius: radius(0.5) },
            FilterKindDesc::Tent => Filter::Tent { radius: radius(1.0) },
            FilterKindDesc::Gaussian => {
                Filter::Gaussian { radius: radius(1.5), sigma: f.sigma.map_or(0.5, Positive::get) }
            }
            FilterKindDesc::Mitchell => Filter::Mitchell {
                radius: radius(2.0),
                b: f.b.map_or(1.0 / 3.0, Finite::get),
                c: f.c.map_or(1.0 / 3.0, Finite::get),
            },
        };
        let applies = |key: &str| {
            matches!((f.kind, key), (FilterKindDesc::Gaussian, "sigma") | (FilterKindDesc::Mitchell, "b" | "c"))
        };
        for (key, given) in [("sigma", f.sigma.is_some()), ("b", f.b.is_some()), ("c", f.c.is_some())] {
            if given && !applies(key) {
                return Err(self.error(
                    find_key(&self.source, key, 0).or_else(|| find_key(&self.source, "filter", 0)),
                    format!("[render] filter: `{key}` does not apply to a {:?} filter", f.kind).to_lowercase(),
                ));
            }
        }
        filter
            .validate()
            .map_err(|e| self.error(find_key(&self.source, "filter", 0), format!("[render] filter: {e}")))?;
        Ok(filter)
    }

    fn environment(&self, env: &EnvironmentDesc) -> Result<Environment, SceneError> {
        let at = || find_header(&self.source, "environment");
        let scale = env.intensity.get();
        match (&env.file, env.color) {
            (Some(_), Some(_)) => Err(self.error(at(), "[environment]: give `color` or `file`, not both")),
            (None, color) => {
                if env.rotation.is_some() {
                    return Err(self.error(at(), "[environment]: `rotation` applies to an image (`file`)"));
                }
                Ok(Environment::Constant(color.map_or(Color::ONE, Color::from) * scale))
            }
            (Some(file), None) => {
                let path = match self.path.as_ref().and_then(|p| p.parent()) {
                    Some(dir) => dir.join(file),
                    None => PathBuf::from(file),
                };
                let rotation = env.rotation.map_or(0.0, Finite::get);
                Environment::from_file(&path, scale, rotation).map_err(|e| {
                    self.error(find_value(&self.source, "file", file).or_else(at), format!("[environment]: {e}"))
                })
            }
        }
    }

    fn add_group(
        &self,
        scene: &mut Scene,
        ctx: &mut BuildContext,
        group: &GroupDesc,
        parent: Transform,
        parent_material: Option<&str>,
        place: Place<'_>,
    ) -> Result<(), SceneError> {
        let Place { label, at: group_at, forced_material } = place;
        let group_transform = self.transform(&group.transform, label, group_at)?.then(&parent);
        let material = group.material.as_deref().or(parent_material);
        // Top-level objects are the n-th `[[kind]]` table of the file;
        // nested ones are identified by their path in the message and
        // located at the top-level table that holds them.
        let locate =
            |kind: &str, index: usize| if label.is_empty() { nth_table(&self.source, kind, index) } else { group_at };
        let resolve = |ctx: &BuildContext, what: &str, own: Option<&str>, at| -> Result<MaterialId, SceneError> {
            let name = forced_material.or(own).or(material).ok_or_else(|| {
                self.error(at, format!("{what} has no material (set `material`, or one on its group)"))
            })?;
            self.material_id(ctx, what, name)
        };
        let add = |ctx: &mut BuildContext,
                   obj: Object<'_>,
                   shape: Result<Shape, crate::shapes::ShapeError>,
                   scene: &mut Scene|
         -> Result<(), SceneError> {
            let what = describe(label, obj.kind, obj.index, obj.name);
            let at = locate(obj.kind, obj.index);
            let shape = shape.map_err(|e| self.error(at, format!("{what}: {e}")))?;
            let id = resolve(ctx, &what, obj.material.as_deref(), at)?;
            let t = self.transform(obj.transform, &what, at)?.then(&group_transform);
            self.place(scene, Primitive::new(shape, t, id), obj.emission, &what, at)
        };
        for (i, s) in group.sphere.iter().enumerate() {
            let shape = Sphere::new(s.center.into(), s.radius.get()).map(Shape::from);
            let obj = Object::new("sphere", i, &s.name, &s.material, &s.transform, (s.emission, s.two_sided));
            add(ctx, obj, shape, scene)?;
        }
        for (i, p) in group.plane.iter().enumerate() {
            let shape = Plane::new(p.point.into(), p.normal.into()).map(Shape::from);
            add(ctx, Object::new("plane", i, &p.name, &p.material, &p.transform, (None, false)), shape, scene)?;
        }
        for (i, t) in group.triangle.iter().enumerate() {
            let v = t.vertices.map(Vec3::from);
            let n = t.normals.map(|n| n.map(Vec3::from));
            let shape = Triangle::new(v, n).map(Shape::from);
            let obj = Object::new("triangle", i, &t.name, &t.material, &t.transform, (t.emission, t.two_sided));
            add(ctx, obj, shape, scene)?;
        }
        for (i, q) in group.quad.iter().enumerate() {
            let obj = Object::new("quad", i, &q.name, &q.material, &q.transform, (q.emission, q.two_sided));
            match quad_triangles(q.vertices.map(Vec3::from)) {
                Ok([a, b]) => {
                    add(ctx, obj, Ok(a), scene)?;
                    add(ctx, obj, Ok(b), scene)?;
                }
                Err(e) => add(ctx, obj, Err(e), scene)?,
            }
        }
        for (i, m) in group.mesh.iter().enumerate() {
            let what = describe(label, "mesh", i, &m.name);
            let at = locate("mesh", i);
            let (mesh, file_materials) = self.mesh(scene, ctx, m, &what, at)?;
            let t = self.transform(&m.transform, &what, at)?.then(&group_transform);
            let explicit = forced_material.or(m.material.as_deref());
            let primitive = match (explicit, file_materials) {
                (None, Some(table)) => {
                    // The file's own materials; a face without one falls back
                    // to the group's material, or the file's first.
                    let fallback = match material {
                        Some(name) => self.material_id(ctx, &what, name)?,
                        None => table[0],
                    };
                    Primitive::new(Shape::Mesh(mesh), t, fallback).with_face_materials(table)
                }
                _ => Primitive::new(Shape::Mesh(mesh), t, resolve(ctx, &what, m.material.as_deref(), at)?),
            };
            self.place(scene, primitive, (m.emission, m.two_sided), &what, at)?;
        }
        for (i, g) in group.group.iter().enumerate() {
            let child_label = describe(label, "group", i, &g.name);
            let child_at = locate("group", i);
            let place = Place { label: &child_label, at: child_at, forced_material };
            self.add_group(scene, ctx, g, group_transform, material, place)?;
        }
        for (i, inst) in group.instance.iter().enumerate() {
            let what = describe(label, "instance", i, &inst.name);
            let at = locate("instance", i);
            let Some(prototype) = self.description.prototypes.get(&inst.prototype) else {
                let known: Vec<&str> = self.description.prototypes.keys().map(String::as_str).collect();
                let known = if known.is_empty() { "none".to_owned() } else { known.join(", ") };
                return Err(self.error(
                    find_value(&self.source, "prototype", &inst.prototype).or(at),
                    format!("{what}: prototype \"{}\" is not defined (defined: {known})", inst.prototype),
                ));
            };
            if ctx.active_prototypes.contains(&inst.prototype) {
                return Err(self.error(at, format!("{what}: prototype \"{}\" contains itself", inst.prototype)));
            }
            let t = self.transform(&inst.transform, &what, at)?.then(&group_transform);
            let child_label = format!("{what} of \"{}\"", inst.prototype);
            let forced = forced_material.or(inst.material.as_deref());
            ctx.active_prototypes.push(inst.prototype.clone());
            let place = Place { label: &child_label, at, forced_material: forced };
            let result = self.add_group(scene, ctx, prototype, t, material, place);
            ctx.active_prototypes.pop();
            result?;
        }
        Ok(())
    }

    /// Add a primitive to the scene, as an area light when it emits.
    fn place(
        &self,
        scene: &mut Scene,
        primitive: Primitive,
        (emission, two_sided): (Option<Rgb>, bool),
        what: &str,
        at: Option<SourceLocation>,
    ) -> Result<(), SceneError> {
        match emission {
            Some(radiance) => scene
                .add_emissive(primitive, radiance.into(), two_sided)
                .map_err(|e| self.error(find_key_after(&self.source, "emission", at).or(at), format!("{what}: {e}"))),
            None if two_sided => Err(self.error(at, format!("{what}: `two_sided` applies only with `emission`"))),
            None => {
                scene.add(primitive);
                Ok(())
            }
        }
    }

    fn material_id(&self, ctx: &BuildContext, what: &str, name: &str) -> Result<MaterialId, SceneError> {
        ctx.ids.get(name).copied().ok_or_else(|| {
            let mut known: Vec<&str> = ctx.ids.keys().map(String::as_str).filter(|k| !k.contains(':')).collect();
            known.sort_unstable();
            let known = if known.is_empty() { "none".to_owned() } else { known.join(", ") };
            self.error(
                find_value(&self.source, "material", name),
                format!("{what}: material \"{name}\" is not defined (defined: {known})"),
            )
        })
    }

    /// Load (once) the mesh a `[[mesh]]` refers to; returns it with the
    /// scene materials made from the file's own materials, if it has any.
    fn mesh(
        &self,
        scene: &mut Scene,
        ctx: &mut BuildContext,
        m: &MeshDesc,
        what: &str,
        at: Option<SourceLocation>,
    ) -> Result<LoadedMesh, SceneError> {
        let (file, normals) = match (&m.mesh, &m.file) {
            (Some(name), None) => {
                if m.normals.is_some() {
                    return Err(
                        self.error(at, format!("{what}: `normals` belongs to [meshes.{name}], not to a placement"))
                    );
                }
                let def = self.description.meshes.get(name).ok_or_else(|| {
                    let known: Vec<&str> = self.description.meshes.keys().map(String::as_str).collect();
                    let known = if known.is_empty() { "none".to_owned() } else { known.join(", ") };
                    self.error(
                        find_value(&self.source, "mesh", name).or(at),
                        format!("{what}: mesh \"{name}\" is not defined under [meshes] (defined: {known})"),
                    )
                })?;
                (def.file.as_str(), def.normals)
            }
            (None, Some(file)) => (file.as_str(), m.normals.unwrap_or_default()),
            _ => return Err(self.error(at, format!("{what}: give either `mesh` (a name under [meshes]) or `file`"))),
        };
        let path = match self.path.as_ref().and_then(|p| p.parent()) {
            Some(dir) => dir.join(file),
            None => PathBuf::from(file),
        };
        let key = (path.clone(), normals);
        if let Some(found) = ctx.meshes.get(&key) {
            return Ok(found.clone());
        }
        let file_at = find_value(&self.source, "file", file).or(at);
        let mut data = crate::mesh::load_mesh(&path).map_err(|e| self.error(file_at, format!("{what}: {e}")))?;
        match normals {
            NormalsDesc::File => {}
            NormalsDesc::Smooth => data.compute_smooth_normals(),
            NormalsDesc::Flat => data.normals = None,
        }
        let file_materials = if data.materials.is_empty() || data.material_ids.is_none() {
            None
        } else {
            let table: Vec<MaterialId> = data
                .materials
                .iter()
                .map(|mm| {
                    let key = format!("{file}:{}", mm.name);
                    *ctx.ids.entry(key).or_insert_with(|| scene.add_material(material_from_file(mm)))
                })
                .collect();
            Some(Arc::from(table))
        };
        let mesh = Mesh::new(data).map_err(|e| self.error(file_at, format!("{what}: {e}")))?;
        if mesh.degenerate_count() > 0 {
            scene.warnings.push(format!(
                "{}: {} zero-area triangle{} skipped",
                path.display(),
                mesh.degenerate_count(),
                if mesh.degenerate_count() == 1 { "" } else { "s" }
            ));
        }
        let entry = (Arc::new(mesh), file_materials);
        ctx.meshes.insert(key, entry.clone());
        Ok(entry)
    }

    /// The transform of `ops`. Scales and matrices are checked as they are
    /// read; what can still fail here (a rotation about an axis too long to
    /// normalise) is reported at `at`, the object's table.
    fn transform(&self, ops: &[TransformOp], what: &str, at: Option<SourceLocation>) -> Result<Transform, SceneError> {
        let mut t = Transform::IDENTITY;
        for op in ops {
            let step = match op {
                TransformOp::Translate(v) => Ok(Transform::translate((*v).into())),
                TransformOp::Scale(v) => Transform::scale((*v).into()),
                TransformOp::RotateX(a) => Ok(Transform::rotate_x(a.get())),
                TransformOp::RotateY(a) => Ok(Transform::rotate_y(a.get())),
                TransformOp::RotateZ(a) => Ok(Transform::rotate_z(a.get())),
                TransformOp::Rotate(aa) => Transform::rotate(aa.axis.into(), aa.angle.get()),
                TransformOp::Matrix(rows) => Transform::from_matrix(Mat4::from_cols_array_2d(rows).transpose()),
            };
            let step = step.map_err(|e| {
                let what = if what.is_empty() { "transform".to_owned() } else { format!("{what}: transform") };
                self.error(at, format!("{what}: {}", transform_error_message(&e)))
            })?;
            t = t.then(&step);
        }
        Ok(t)
    }
}

/// Where a group is, for messages: its label (`group #1 > group "arm"`,
/// empty for the scene's root) and the location of the top-level `[[group]]`
/// that holds it.
#[derive(Clone, Copy)]
struct Place<'a> {
    label: &'a str,
    at: Option<SourceLocation>,
    /// An instance's material, replacing every member's.
    forced_material: Option<&'a str>,
}

/// The keys every object kind shares, for [`SceneFile::add_group`].
#[derive(Clone, Copy)]
struct Object<'a> {
    kind: &'static str,
    index: usize,
    name: &'a Option<String>,
    material: &'a Option<String>,
    transform: &'a [TransformOp],
    emission: (Option<Rgb>, bool),
}

impl<'a> Object<'a> {
    fn new(
        kind: &'static str,
        index: usize,
        name: &'a Option<String>,
        material: &'a Option<String>,
        transform: &'a [TransformOp],
        emission: (Option<Rgb>, bool),
    ) -> Self {
        Self { kind, index, name, material, transform, emission }
    }
}

/// A quad as its two triangles, (v0, v1, v2) and (v0, v2, v3): separate
/// primitives in the top-level BVH (cheaper to intersect than a two-triangle
/// mesh with its own BVH), watertight along the shared diagonal.
fn quad_triangles(v: [Vec3; 4]) -> Result<[Shape; 2], crate::shapes::ShapeError> {
    Ok([Triangle::new([v[0], v[1], v[2]], None)?.into(), Triangle::new([v[0], v[2], v[3]], None)?.into()])
}

/// A mesh ready to place, with the scene materials of the file's own
/// materials (by mesh-local index), if it has any.
type LoadedMesh = (Arc<Mesh>, Option<Arc<[MaterialId]>>);

/// State carried through the walk over groups and prototypes.
struct BuildContext {
    /// Material names (scene materials, and `FILE:NAME` for a mesh file's
    /// own) to scene handles.
    ids: HashMap<String, MaterialId>,
    /// Meshes loaded so far, by path and normals mode: each file is read and
    /// built once however often it is placed.
    meshes: HashMap<(PathBuf, NormalsDesc), LoadedMesh>,
    /// Prototypes being expanded, to refuse one that contains itself.
    active_prototypes: Vec<String>,
}

/// A scene material for one of a mesh file's own materials (OBJ's MTL):
/// Phong when it has a specular colour, matte otherwise.
fn material_from_file(m: &crate::mesh::MeshMaterial) -> Material {
    let kd = Texture::Constant(m.diffuse.max(Vec3::ZERO));
    let ks = m.specular.max_element().max(0.0);
    let material =
        if ks > 0.0 { Material::phong(kd, 1.0, ks, m.shininess.max(1.0), 0.0) } else { Material::matte(kd, 1.0) };
    material.unwrap_or_else(|_| Material::matte(Color::splat(0.8), 1.0).expect("valid constants"))
}

/// Albedos above 1 would create energy under the path integrator.
fn check_albedo(t: &Texture) -> Result<(), String> {
    let colors = match t {
        Texture::Constant(c) => vec![*c],
        Texture::Checker { even, odd, .. } => vec![*even, *odd],
    };
    match colors.iter().find(|c| c.max_element() > 1.0) {
        Some(c) => Err(format!("albedo must be at most 1 in every channel (a surface cannot reflect more light than it receives), got [{}, {}, {}]", c.x, c.y, c.z)),
        None => Ok(()),
    }
}

/// Complex indices of refraction of the named metals at 650, 550 and
/// 450 nm (red, green, blue), from the measurements tabulated at
/// refractiveindex.info: Johnson & Christy 1972 (gold, silver, copper) and
/// Rakić 1995 (aluminium).
fn metal_ior(metal: MetalDesc) -> (Color, Color) {
    let (eta, k) = match metal {
        MetalDesc::Gold => ([0.166, 0.424, 1.316], [3.150, 2.380, 1.863]),
        MetalDesc::Silver => ([0.144, 0.120, 0.135], [4.243, 3.341, 2.484]),
        MetalDesc::Copper => ([0.214, 0.967, 1.158], [3.670, 2.578, 2.398]),
        MetalDesc::Aluminium => ([1.490, 0.958, 0.618], [7.821, 6.690, 5.471]),
    };
    (Color::from_array(eta), Color::from_array(k))
}

fn falloff(f: Option<FalloffDesc>, default: Falloff) -> Falloff {
    match f {
        None => default,
        Some(FalloffDesc::None) => Falloff::None,
        Some(FalloffDesc::InverseSquare) => Falloff::InverseSquare,
    }
}

fn describe(parent: &str, kind: &str, index: usize, name: &Option<String>) -> String {
    let own = match name {
        Some(n) => format!("{kind} \"{n}\""),
        None => format!("{kind} #{}", index + 1),
    };
    if parent.is_empty() {
        own
    } else {
        format!("{parent} > {own}")
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

// Best-effort locators for errors found after parsing, when the parser's
// positions are gone. They search the text for the key in either syntax and
// are only used to point the user at a line; a miss just omits the position.

fn is_key_at(line: &str, key: &str) -> Option<usize> {
    let trimmed = line.trim_start();
    let indent = line.len() - trimmed.len();
    for candidate in [key.to_owned(), format!("\"{key}\"")] {
        if let Some(rest) = trimmed.strip_prefix(&candidate) {
            let rest = rest.trim_start();
            if rest.starts_with('=') || rest.starts_with(':') {
                return Some(indent);
            }
        }
    }
    // Inline tables: `{ key = ... }` or `"key": ...` after other text.
    for pat in [format!("{{ {key} ="), format!("{{{key} ="), format!("\"{key}\":"), format!("\"{key}\" :")] {
        if let Some(i) = line.find(&pat) {
            return Some(i + pat.find(key).unwrap_or(0));
        }
    }
    None
}

/// The `nth` line (0-based) that assigns `key`.
pub(crate) fn find_key(source: &str, key: &str, nth: usize) -> Option<SourceLocation> {
    source
        .lines()
        .enumerate()
        .filter_map(|(i, l)| is_key_at(l, key).map(|c| (i, c)))
        .nth(nth)
        .map(|(i, c)| SourceLocation { line: i + 1, column: c + 1 })
}

/// The first line at or after `from` (the start of the file if `None`) that
/// assigns `key`: the key of one table among several that have it.
fn find_key_after(source: &str, key: &str, from: Option<SourceLocation>) -> Option<SourceLocation> {
    let first = from.map_or(0, |l| l.line - 1);
    source
        .lines()
        .enumerate()
        .skip(first)
        .find_map(|(i, l)| is_key_at(l, key).map(|c| SourceLocation { line: i + 1, column: c + 1 }))
}

/// The `nth` (0-based) line whose text, after indentation, starts with
/// `prefix`; the location is that of the first non-blank character.
fn nth_line_starting_with(source: &str, prefix: &str, nth: usize) -> Option<SourceLocation> {
    source
        .lines()
        .enumerate()
        .filter_map(|(i, l)| {
            let t = l.trim_start();
            t.starts_with(prefix).then(|| SourceLocation { line: i + 1, column: l.len() - t.len() + 1 })
        })
        .nth(nth)
}

/// A table header `[name]` (TOML) or the key `"name"` (JSON, or an inline
/// table in TOML).
fn find_header(source: &str, name: &str) -> Option<SourceLocation> {
    nth_line_starting_with(source, &format!("[{name}]"), 0).or_else(|| find_key(source, name, 0))
}

/// The line that assigns the string `value` to `key`.
fn find_value(source: &str, key: &str, value: &str) -> Option<SourceLocation> {
    let quoted = format!("\"{value}\"");
    source.lines().enumerate().find_map(|(i, l)| {
        is_key_at(l, key)?;
        l.find(&quoted).map(|c| SourceLocation { line: i + 1, column: c + 1 })
    })
}

/// The header of a named material, `[materials.NAME...]` or `"NAME": {`.
fn find_table(source: &str, name: &str) -> Option<SourceLocation> {
    let toml = format!("[materials.{name}");
    let json = format!("\"{name}\"");
    source.lines().enumerate().find_map(|(i, l)| {
        l.find(&toml).or_else(|| l.find(&json)).map(|c| SourceLocation { line: i + 1, column: c + 1 })
    })
}

/// The `nth` (0-based) top-level `[[kind]]` header in TOML; in JSON, the
/// `"kind"` key that holds the array.
fn nth_table(source: &str, kind: &str, nth: usize) -> Option<SourceLocation> {
    nth_line_starting_with(source, &format!("[[{kind}]]"), nth).or_else(|| find_key(source, kind, 0))
}
