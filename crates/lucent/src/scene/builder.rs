//! [`SceneBuilder`]: the one way to make a [`Scene`].

use super::{finite_bounds, Scene, SceneError};
use crate::bsdf::ConductorFresnel;
use crate::camera::Camera;
use crate::color::Color;
use crate::geometry::{Transform, Vec3};
use crate::light::{merge_rectangles, AreaLight, EmissionImage, Emitter, Environment, Light, LightSet};
use crate::material::{Material, MaterialId};
use crate::medium::{Medium, MediumId};
use crate::primitive::{merge_loose_triangles, merge_small_meshes, BvhAggregate, Primitive};
use crate::shapes::{Mesh, Shape, Sphere, Triangle};
use crate::texture::Texture;
use std::collections::BTreeMap;
use std::sync::Arc;

/// Checks that a prototype named in an instance (placed within the
/// prototype given, if any) exists.
type PrototypeCheck<'a> = dyn Fn(&str, Option<&str>) -> Result<(), SceneError> + 'a;

/// Light emitted by a surface: it becomes a diffuse area light.
#[derive(Clone, Debug, PartialEq)]
pub struct Emission {
    /// Emitted radiance, linear RGB.
    pub radiance: Color,
    /// Whether both sides emit (otherwise only the front: a triangle's
    /// normal side, a sphere's outside).
    pub two_sided: bool,
    /// Whether a one-sided emitter emits from its back instead (pbrt-v4's
    /// `ReverseOrientation`; see [`AreaLight::reverse`]).
    pub reverse: bool,
    /// Radiance varying over the surface: `radiance` times this texture,
    /// at the surface's texture coordinates (pbrt-v4's area light
    /// `filename`; see [`EmissionImage`]).
    pub image: Option<Texture>,
}

/// Why a primitive cannot be an area light.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EmissionError {
    /// A plane has infinite area.
    #[error("an infinite plane cannot emit light (use a quad or a large triangle)")]
    Plane,
    /// Only spheres that stay spheres can be sampled as lights.
    #[error(
        "an emissive sphere must stay a sphere: its transform may translate, rotate and scale uniformly, but not stretch it into an ellipsoid"
    )]
    Ellipsoid,
    /// Negative or non-finite radiance.
    #[error("emitted radiance must be finite and ≥ 0 in every channel")]
    Radiance,
    /// More than 2³² light triangles.
    #[error("too many emissive triangles (at most 4294967295)")]
    TooMany,
}

/// Something placed in a prototype: a primitive (perhaps emissive), or an
/// instance of another prototype.
#[derive(Clone, Debug)]
enum Member {
    Primitive(Box<Primitive>, Option<Emission>),
    Instance(Instance),
}

/// A placement of a prototype.
#[derive(Clone, Debug)]
struct Instance {
    prototype: String,
    transform: Transform,
    /// Replaces the material of every member, when given.
    material: Option<MaterialId>,
}

/// Builds a [`Scene`]: cameras, materials, lights, shapes and meshes, and
/// prototypes placed any number of times by instances.
///
/// Each method validates what it is given and returns the same
/// [`SceneError`] that the scene-file loader reports (the loader adds the
/// file position); [`SceneBuilder::build`] checks the whole (prototypes
/// that place themselves, an unfinished prototype) and builds the BVH and
/// the light distribution, using the current rayon pool.
///
/// Between [`SceneBuilder::begin_prototype`] and
/// [`SceneBuilder::end_prototype`], shapes and instances are added to the
/// prototype instead of the scene (as pbrt-v4's `ObjectBegin`/`ObjectEnd`).
///
/// ```
/// use lucent::prelude::*;
///
/// let camera = Camera::new(Vec3::new(0.0, 2.0, -8.0), Vec3::ZERO, Vec3::Y, 50.0, 64, 48)?;
/// let mut b = SceneBuilder::new(camera);
/// let white = b.add_material(Material::matte(Color::splat(0.8), 1.0)?)?;
/// let red = b.add_material(Material::matte(Color::new(0.8, 0.1, 0.1), 1.0)?)?;
/// // A prototype: two spheres, placed three times.
/// b.begin_prototype("pair")?;
/// b.add_shape(Sphere::new(Vec3::new(-0.6, 0.0, 0.0), 0.5)?, Transform::IDENTITY, white)?;
/// b.add_shape(Sphere::new(Vec3::new(0.6, 0.0, 0.0), 0.5)?, Transform::IDENTITY, white)?;
/// b.end_prototype()?;
/// for (i, x) in [-3.0, 0.0, 3.0].into_iter().enumerate() {
///     let material = (i == 1).then_some(red); // the middle pair is red
///     b.add_instance("pair", Transform::translate(Vec3::new(x, 0.0, 0.0)), material)?;
/// }
/// b.add_light(Light::directional(Vec3::new(0.0, -1.0, 1.0), Color::ONE, 1.0)?);
/// let scene = b.build()?;
/// assert_eq!(scene.primitives().len(), 6);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct SceneBuilder {
    camera: Camera,
    ambient: Color,
    background: Color,
    environment: Option<Environment>,
    lights: Vec<Light>,
    area_lights: Vec<AreaLight>,
    materials: Vec<Material>,
    primitives: Vec<Primitive>,
    prototypes: BTreeMap<String, Vec<Member>>,
    /// The prototype being defined, if any.
    open: Option<(String, Vec<Member>)>,
    /// Instances placed in the scene, expanded by `build`.
    instances: Vec<Instance>,
    media: Vec<Medium>,
    camera_medium: Option<MediumId>,
    warnings: Vec<String>,
}

impl SceneBuilder {
    /// An empty scene seen by `camera`: no ambient light, a black
    /// background.
    pub fn new(camera: Camera) -> Self {
        Self {
            camera,
            ambient: Color::ZERO,
            background: Color::ZERO,
            environment: None,
            lights: Vec::new(),
            area_lights: Vec::new(),
            materials: Vec::new(),
            primitives: Vec::new(),
            prototypes: BTreeMap::new(),
            open: None,
            instances: Vec::new(),
            media: Vec::new(),
            camera_medium: None,
            warnings: Vec::new(),
        }
    }

    /// Replace the camera.
    pub fn set_camera(&mut self, camera: Camera) -> &mut Self {
        self.camera = camera;
        self
    }

    /// Set the ambient light of the classic renderer (default black).
    pub fn set_ambient(&mut self, ambient: Color) -> Result<&mut Self, SceneError> {
        self.ambient = check_color("ambient light", ambient)?;
        Ok(self)
    }

    /// Set the radiance of rays that leave the scene when there is no
    /// environment (default black).
    pub fn set_background(&mut self, background: Color) -> Result<&mut Self, SceneError> {
        self.background = check_color("background", background)?;
        Ok(self)
    }

    /// Set the environment light (path integrator).
    pub fn set_environment(&mut self, environment: Environment) -> Result<&mut Self, SceneError> {
        if let Environment::Constant(c) = environment {
            check_color("environment", c)?;
        }
        self.environment = Some(environment);
        Ok(self)
    }

    /// Add a material; returns its handle. Materials of the path tracer are
    /// checked for energy conservation: albedos at most 1, roughness from 0
    /// to 1.
    pub fn add_material(&mut self, material: Material) -> Result<MaterialId, SceneError> {
        check_material(&material).map_err(|m| SceneError::new(None, m))?;
        if self.materials.len() >= u32::MAX as usize {
            return Err(SceneError::new(None, "too many materials (at most 4294967295)"));
        }
        self.materials.push(material);
        Ok(MaterialId::new(self.materials.len() - 1))
    }

    /// The materials added so far.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Add a participating medium; returns its handle, for
    /// [`Primitive::with_media`] and [`SceneBuilder::set_camera_medium`].
    pub fn add_medium(&mut self, medium: Medium) -> Result<MediumId, SceneError> {
        if self.media.len() >= u32::MAX as usize - 1 {
            return Err(SceneError::new(None, "too many media"));
        }
        self.media.push(medium);
        Ok(MediumId::new(self.media.len() - 1))
    }

    /// Replace the medium `id` (added before with
    /// [`SceneBuilder::add_medium`]): for a format that may name a medium
    /// before it defines it, as pbrt-v4's does.
    pub fn set_medium(&mut self, id: MediumId, medium: Medium) -> Result<&mut Self, SceneError> {
        self.check_medium_id(id)?;
        self.media[id.index()] = medium;
        Ok(self)
    }

    /// The medium the camera is in (default: none, vacuum): where camera
    /// rays start.
    pub fn set_camera_medium(&mut self, medium: Option<MediumId>) -> Result<&mut Self, SceneError> {
        if let Some(m) = medium {
            self.check_medium_id(m)?;
        }
        self.camera_medium = medium;
        Ok(self)
    }

    /// Add a point, spot or directional light.
    pub fn add_light(&mut self, light: Light) -> &mut Self {
        self.lights.push(light);
        self
    }

    /// Record a non-fatal problem (such as skipped degenerate triangles)
    /// for the user; the built scene lists them in [`Scene::warnings`].
    pub fn warn(&mut self, warning: impl Into<String>) -> &mut Self {
        self.warnings.push(warning.into());
        self
    }

    /// Place `shape` with `transform` (object to world) and `material`.
    pub fn add_shape(
        &mut self,
        shape: impl Into<Shape>,
        transform: Transform,
        material: MaterialId,
    ) -> Result<&mut Self, SceneError> {
        self.add(Primitive::new(shape, transform, material), None)
    }

    /// Place a mesh (shared, not copied, however often it is placed). With
    /// `face_materials`, face `i` takes `face_materials[m]` where `m` is its
    /// material index in the mesh, and `material` is the fallback for faces
    /// without one (see [`Primitive::with_face_materials`]).
    pub fn add_mesh(
        &mut self,
        mesh: Arc<Mesh>,
        transform: Transform,
        material: MaterialId,
        face_materials: Option<Arc<[MaterialId]>>,
        emission: Option<Emission>,
    ) -> Result<&mut Self, SceneError> {
        let mut primitive = Primitive::new(Shape::Mesh(mesh), transform, material);
        if let Some(table) = face_materials {
            primitive = primitive.with_face_materials(table);
        }
        self.add(primitive, emission)
    }

    /// Place a primitive whose surface emits (a diffuse area light): every
    /// triangle of a mesh becomes its own light. Planes cannot emit (they
    /// have no finite area), nor can spheres stretched into ellipsoids.
    pub fn add_emissive(
        &mut self,
        shape: impl Into<Shape>,
        transform: Transform,
        material: MaterialId,
        emission: Emission,
    ) -> Result<&mut Self, SceneError> {
        self.add(Primitive::new(shape, transform, material), Some(emission))
    }

    /// Place a primitive, emissive with `emission`: in the prototype being
    /// defined, if there is one, else in the scene.
    pub fn add(&mut self, primitive: Primitive, emission: Option<Emission>) -> Result<&mut Self, SceneError> {
        self.check_material_ids(&primitive)?;
        let media = primitive.media();
        for m in [media.inside, media.outside].into_iter().flatten() {
            self.check_medium_id(m)?;
        }
        if let Some(e) = &emission {
            // Check now, so that an error names the object, not an instance.
            area_shapes(&primitive, e).map_err(|e| SceneError::new(None, e.to_string()))?;
        }
        match &mut self.open {
            Some((_, members)) => members.push(Member::Primitive(Box::new(primitive), emission)),
            None => self.place(primitive, emission)?,
        }
        Ok(self)
    }

    /// Start defining the prototype `name`: until
    /// [`SceneBuilder::end_prototype`], what is added goes into it.
    /// Prototypes do not nest, but may contain instances of others.
    pub fn begin_prototype(&mut self, name: &str) -> Result<&mut Self, SceneError> {
        if let Some((open, _)) = &self.open {
            return Err(SceneError::new(
                None,
                format!("prototype \"{name}\" begins inside prototype \"{open}\" (prototypes do not nest)"),
            ));
        }
        if self.prototypes.contains_key(name) {
            return Err(SceneError::new(None, format!("prototype \"{name}\" is defined twice")));
        }
        self.open = Some((name.to_owned(), Vec::new()));
        Ok(self)
    }

    /// Finish the prototype begun last.
    pub fn end_prototype(&mut self) -> Result<&mut Self, SceneError> {
        let (name, members) =
            self.open.take().ok_or_else(|| SceneError::new(None, "end of a prototype that was not begun"))?;
        self.prototypes.insert(name, members);
        Ok(self)
    }

    /// Place prototype `name` with `transform` (applied after the
    /// prototype's own transforms), in the prototype being defined if there
    /// is one, else in the scene. With `material`, every member takes that
    /// material instead of its own. The prototype may be defined later;
    /// [`SceneBuilder::build`] checks that it exists.
    pub fn add_instance(
        &mut self,
        name: &str,
        transform: Transform,
        material: Option<MaterialId>,
    ) -> Result<&mut Self, SceneError> {
        if let Some(m) = material {
            self.check_material_id(m)?;
        }
        let instance = Instance { prototype: name.to_owned(), transform, material };
        match &mut self.open {
            Some((_, members)) => members.push(Member::Instance(instance)),
            None => self.instances.push(instance),
        }
        Ok(self)
    }

    /// The names of the prototypes defined so far.
    pub fn prototype_names(&self) -> impl Iterator<Item = &str> {
        self.prototypes.keys().map(String::as_str)
    }

    /// Check the whole scene and build it: expand the instances, then build
    /// the BVH (over loose triangles, and small meshes, merged into meshes)
    /// and the light distribution.
    ///
    /// Fails when a prototype is still open, when an instance names a
    /// prototype that does not exist, or when a prototype places itself,
    /// directly or through others (whether or not anything places it).
    pub fn build(mut self) -> Result<Scene, SceneError> {
        if let Some((name, _)) = &self.open {
            return Err(SceneError::new(None, format!("prototype \"{name}\" is never ended")));
        }
        self.check_prototypes()?;
        for instance in std::mem::take(&mut self.instances) {
            self.expand(&instance, Transform::IDENTITY, None)?;
        }

        // Emissive quads become one rectangular light each (sampled with
        // one spherical-rectangle sample instead of two triangles).
        if let Some((lights, remap)) = merge_rectangles(&self.area_lights) {
            self.area_lights = lights;
            for primitive in &mut self.primitives {
                primitive.remap_area_lights(&remap);
            }
        }
        let merged = merge_small_meshes(merge_loose_triangles(&self.primitives));
        // Point and spot lights get light buffers in scenes of few
        // primitives (shadow rays then skip the BVH).
        let positions: Vec<Vec3> = self
            .lights
            .iter()
            .filter_map(|l| match l {
                Light::Point { position, .. } | Light::Spot { position, .. } => Some(*position),
                _ => None,
            })
            .collect();
        let aggregate = BvhAggregate::new(&merged).with_light_buffers(&positions);
        let bounds = finite_bounds(&self.primitives);
        let mut emitters: Vec<Emitter> = self.area_lights.iter().cloned().map(Emitter::Area).collect();
        emitters.extend(self.lights.iter().cloned().map(Emitter::Delta));
        match &self.environment {
            Some(env) => emitters.push(Emitter::Environment(env.clone())),
            None if self.background.max_element() > 0.0 => {
                emitters.push(Emitter::Environment(Environment::Constant(self.background)))
            }
            None => {}
        }
        let light_set = LightSet::new(emitters, &bounds);
        Ok(Scene {
            camera: self.camera,
            ambient: self.ambient,
            background: self.background,
            lights: self.lights,
            area_lights: self.area_lights,
            environment: self.environment,
            materials: self.materials,
            primitives: self.primitives,
            aggregate,
            light_set,
            media: self.media,
            camera_medium: self.camera_medium,
            warnings: self.warnings,
        })
    }

    fn check_material_id(&self, id: MaterialId) -> Result<(), SceneError> {
        if id.index() < self.materials.len() {
            Ok(())
        } else {
            Err(SceneError::new(None, "a material handle from another scene"))
        }
    }

    fn check_medium_id(&self, id: MediumId) -> Result<(), SceneError> {
        if id.index() < self.media.len() {
            Ok(())
        } else {
            Err(SceneError::new(None, "a medium handle from another scene"))
        }
    }

    fn check_material_ids(&self, primitive: &Primitive) -> Result<(), SceneError> {
        self.check_material_id(primitive.material())?;
        if let Some(table) = primitive.face_materials() {
            table.iter().try_for_each(|&m| self.check_material_id(m))?;
        }
        Ok(())
    }

    /// Put a primitive in the scene, with its area lights.
    fn place(&mut self, primitive: Primitive, emission: Option<Emission>) -> Result<(), SceneError> {
        let Some(e) = emission else {
            self.primitives.push(primitive);
            return Ok(());
        };
        let error = |e: EmissionError| SceneError::new(None, e.to_string());
        let shapes = area_shapes(&primitive, &e).map_err(error)?;
        let first = u32::try_from(self.area_lights.len()).map_err(|_| error(EmissionError::TooMany))?;
        u32::try_from(self.area_lights.len() + shapes.len()).map_err(|_| error(EmissionError::TooMany))?;
        let image = e.image.map(|texture| Arc::new(EmissionImage::new(texture, primitive.clone())));
        self.area_lights.extend(shapes.into_iter().map(|shape| AreaLight {
            shape,
            radiance: e.radiance,
            two_sided: e.two_sided,
            reverse: e.reverse,
            image: image.clone(),
        }));
        self.primitives.push(primitive.with_area_light(first));
        Ok(())
    }

    /// Every prototype an instance names exists, and none places itself.
    fn check_prototypes(&self) -> Result<(), SceneError> {
        let exists = |name: &str, within: Option<&str>| {
            if self.prototypes.contains_key(name) {
                return Ok(());
            }
            let known: Vec<&str> = self.prototype_names().collect();
            let known = if known.is_empty() { "none".to_owned() } else { known.join(", ") };
            let place = within.map_or_else(String::new, |w| format!(" (placed in prototype \"{w}\")"));
            Err(SceneError::new(None, format!("prototype \"{name}\" is not defined{place} (defined: {known})")))
        };
        for instance in &self.instances {
            exists(&instance.prototype, None)?;
        }
        // Depth-first search from every prototype; `path` is the chain of
        // prototypes being expanded.
        fn visit<'a>(
            builder: &'a SceneBuilder,
            name: &'a str,
            path: &mut Vec<&'a str>,
            done: &mut Vec<&'a str>,
            exists: &PrototypeCheck,
        ) -> Result<(), SceneError> {
            if let Some(start) = path.iter().position(|&p| p == name) {
                let mut cycle: Vec<String> = path[start..].iter().map(|p| format!("\"{p}\"")).collect();
                cycle.push(format!("\"{name}\""));
                return Err(SceneError::new(
                    None,
                    format!("prototype \"{name}\" contains itself ({})", cycle.join(" > ")),
                ));
            }
            if done.contains(&name) {
                return Ok(());
            }
            path.push(name);
            for member in &builder.prototypes[name] {
                if let Member::Instance(inner) = member {
                    exists(&inner.prototype, Some(name))?;
                    visit(builder, &inner.prototype, path, done, exists)?;
                }
            }
            path.pop();
            done.push(name);
            Ok(())
        }
        let mut done = Vec::new();
        for name in self.prototypes.keys() {
            visit(self, name, &mut Vec::new(), &mut done, &exists)?;
        }
        Ok(())
    }

    /// Place the members of an instance (prototypes checked, so this ends).
    fn expand(&mut self, instance: &Instance, parent: Transform, forced: Option<MaterialId>) -> Result<(), SceneError> {
        let transform = instance.transform.then(&parent);
        let forced = forced.or(instance.material);
        let members = self.prototypes[&instance.prototype].clone();
        for member in &members {
            match member {
                Member::Primitive(p, emission) => {
                    let t = p.transform().then(&transform);
                    let placed = match forced {
                        Some(m) => Primitive::new(p.shape().clone(), t, m)
                            .with_reverse_orientation(p.reverse_orientation())
                            .with_media(p.media()),
                        None => p.with_transform(t),
                    };
                    self.place(placed, emission.clone())?;
                }
                Member::Instance(inner) => self.expand(inner, transform, forced)?,
            }
        }
        Ok(())
    }
}

/// The uniform scale factor of a transform that is a similarity (rotation,
/// uniform scale, translation), or `None`.
fn uniform_scale(t: &Transform) -> Option<f32> {
    let m = t.matrix();
    let cols = [m.x_axis.truncate(), m.y_axis.truncate(), m.z_axis.truncate()];
    let s = cols[0].length();
    let tol = 1e-4 * s;
    let similar = cols.iter().all(|c| (c.length() - s).abs() <= tol)
        && cols[0].dot(cols[1]).abs() <= tol * s
        && cols[0].dot(cols[2]).abs() <= tol * s
        && cols[1].dot(cols[2]).abs() <= tol * s;
    similar.then_some(s)
}

/// The world-space light shapes of an emissive primitive: one sphere, or one
/// triangle per face (degenerate faces included, so that face `i` is light
/// `first + i`). Only [`Shape::Sphere`] and [`Shape::Triangle`], the shapes
/// an [`AreaLight`] samples.
fn area_shapes(primitive: &Primitive, emission: &Emission) -> Result<Vec<Shape>, EmissionError> {
    if !(emission.radiance.is_finite() && emission.radiance.min_element() >= 0.0) {
        return Err(EmissionError::Radiance);
    }
    let t = primitive.transform();
    let triangle = |v: [Vec3; 3]| Shape::Triangle(Triangle::new_unchecked(v.map(|p| t.point(p))));
    Ok(match primitive.shape() {
        Shape::Plane(_) => return Err(EmissionError::Plane),
        // Partial spheres, disks and cylinders keep their frame: their
        // world copy needs a similarity transform, as a sphere does.
        shape @ (Shape::Disk(_) | Shape::Cylinder(_) | Shape::Rectangle(_)) => {
            vec![shape.transformed(&t).ok_or(EmissionError::Ellipsoid)?]
        }
        // A "partial" sphere that is whole (pbrt's parameterisation) is
        // sampled as a sphere: by the cone it subtends.
        shape @ Shape::Sphere(s)
            if s.clipping()
                .is_some_and(|(lo, hi, phi)| lo > -s.radius() || hi < s.radius() || phi < std::f32::consts::TAU) =>
        {
            vec![shape.transformed(&t).ok_or(EmissionError::Ellipsoid)?]
        }
        Shape::Sphere(s) => {
            let scale = uniform_scale(&t).ok_or(EmissionError::Ellipsoid)?;
            vec![Shape::Sphere(Sphere::new_unchecked(t.point(s.center()), s.radius() * scale))]
        }
        Shape::Triangle(tri) => vec![triangle(tri.vertices())],
        Shape::Mesh(mesh) => {
            let mut shapes = Vec::new();
            shapes.try_reserve_exact(mesh.triangle_count()).map_err(|_| EmissionError::TooMany)?;
            shapes.extend((0..mesh.triangle_count()).map(|i| triangle(mesh.triangle(i))));
            shapes
        }
    })
}

/// A colour that must be finite and non-negative.
fn check_color(what: &str, c: Color) -> Result<Color, SceneError> {
    if c.is_finite() && c.min_element() >= 0.0 {
        Ok(c)
    } else {
        Err(SceneError::new(
            None,
            format!("{what} must be finite and ≥ 0 in every channel, got [{}, {}, {}]", c.x, c.y, c.z),
        ))
    }
}

/// The path tracer's materials must conserve energy: albedos at most 1 and
/// GGX roughness from 0 to 1 (where textures are constant; the BxDFs clamp
/// varying albedos to [0, 1]). A diffuse transmitter's reflectance and
/// transmittance are each checked (after `scale`), not their sum, as pbrt-v4
/// accepts any pair.
fn check_material(m: &Material) -> Result<(), String> {
    use crate::material::Roughness;
    use crate::texture::FloatTexture;
    let mut albedos: Vec<(&Texture, f32)> = Vec::new();
    let mut roughness: Vec<&FloatTexture> = Vec::new();
    let mut alphas: Vec<f32> = Vec::new();
    fn add_roughness<'a>(r: &'a Roughness, out: &mut Vec<&'a FloatTexture>) {
        out.push(&r.u);
        out.push(&r.v);
    }
    fn fresnel_albedo(f: &ConductorFresnel<Texture>) -> Option<(&Texture, f32)> {
        match f {
            ConductorFresnel::Schlick { r0: t } | ConductorFresnel::Reflectance { r: t } => Some((t, 1.0)),
            ConductorFresnel::Complex { .. } => None,
        }
    }
    match m {
        Material::Classic(_) | Material::Mix { .. } | Material::Interface => {}
        Material::Diffuse { reflectance } => albedos.push((reflectance, 1.0)),
        Material::Conductor { fresnel, roughness: r } => {
            albedos.extend(fresnel_albedo(fresnel));
            add_roughness(r, &mut roughness);
        }
        Material::Dielectric { roughness: r, .. } => add_roughness(r, &mut roughness),
        Material::Plastic { reflectance, roughness: r, .. } => {
            albedos.push((reflectance, 1.0));
            alphas.push(*r);
        }
        Material::ThinDielectric { .. } => {}
        Material::DiffuseTransmission { reflectance, transmittance, scale } => {
            if !(scale.is_finite() && *scale >= 0.0) {
                return Err(format!("scale must be a finite number ≥ 0, got {scale}"));
            }
            albedos.push((reflectance, *scale));
            albedos.push((transmittance, *scale));
        }
        Material::CoatedDiffuse(c) => {
            albedos.push((&c.reflectance, 1.0));
            albedos.push((&c.albedo, 1.0));
            add_roughness(&c.roughness, &mut roughness);
        }
        Material::CoatedConductor(c) => {
            albedos.extend(fresnel_albedo(&c.conductor));
            albedos.push((&c.albedo, 1.0));
            add_roughness(&c.interface_roughness, &mut roughness);
            add_roughness(&c.conductor_roughness, &mut roughness);
        }
        Material::MetallicRoughness(m) => {
            if !(m.ior.is_finite() && m.ior >= 1.0) {
                return Err(format!("ior must be a finite number ≥ 1, got {}", m.ior));
            }
            let factors = [m.base_color_factor, m.specular_color_factor, m.sheen_color_factor];
            if let Some(c) = factors.iter().find(|c| !c.is_finite() || c.min_element() < 0.0) {
                return Err(format!("colour factors must be finite and ≥ 0, got [{}, {}, {}]", c.x, c.y, c.z));
            }
        }
        Material::Shaded { material, .. } => return check_material(material),
    }
    for (t, scale) in albedos {
        #[allow(unreachable_patterns)]
        let colors = match t {
            Texture::Constant(c) => vec![*c * scale],
            Texture::Checker { even, odd, .. } => vec![*even * scale, *odd * scale],
            // Other textures vary; the BxDFs clamp them.
            _ => vec![],
        };
        if let Some(c) = colors.iter().find(|c| c.max_element() > 1.0) {
            return Err(format!(
                "albedo must be at most 1 in every channel (a surface cannot reflect more light than it receives), got [{}, {}, {}]",
                c.x, c.y, c.z
            ));
        }
    }
    for t in roughness {
        #[allow(irrefutable_let_patterns)]
        if let FloatTexture::Constant(r) = t {
            alphas.push(*r);
        }
    }
    for r in alphas {
        if !(0.0..=1.0).contains(&r) {
            return Err(format!("roughness must be from 0 (smooth) to 1, got {r}"));
        }
    }
    Ok(())
}
