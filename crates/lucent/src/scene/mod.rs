//! Scenes: what is rendered. A [`Scene`] can be built in code or loaded from
//! a TOML or JSON scene file ([`load_scene`]).
//!
//! ```
//! use lucent::prelude::*;
//!
//! let camera = Camera::new(Vec3::new(0.0, 1.0, -5.0), Vec3::ZERO, Vec3::Y, 60.0, 32, 24).unwrap();
//! let mut scene = Scene::new(camera);
//! let red = scene.add_material(Material::matte(Color::new(1.0, 0.2, 0.2), 0.8).unwrap());
//! scene.add(Primitive::new(Sphere::new(Vec3::ZERO, 1.0).unwrap(), Transform::IDENTITY, red));
//! scene.add_light(Light::point(Vec3::new(5.0, 5.0, -5.0), Color::ONE, 3.0, Falloff::None).unwrap());
//! scene.ambient = Color::splat(0.05);
//! let image = render(&scene, &RenderOptions::default()).unwrap();
//! assert_eq!(image.film.width(), 32);
//! ```

mod description;
mod error;
mod load;
mod primitive;

pub use description::*;
pub use error::{SceneError, SourceLocation};
pub use load::{load_scene, parse_scene, SceneFile, SceneFormat};
pub use primitive::Primitive;
use primitive::NO_LIGHT;

use crate::accel::{Aggregate, BvhAggregate};
use crate::camera::Camera;
use crate::color::Color;
use crate::geometry::Ray;
use crate::geometry::{Bounds3, Transform};
use crate::interaction::SurfaceInteraction;
use crate::light::{AreaLight, AreaShape, Emitter, Environment, Light, LightSet};
use crate::material::Material;
use crate::mesh::TriangleMesh;
use crate::render::RenderSettings;
use crate::shapes::{Mesh, Shape};
use std::sync::Arc;
use std::sync::OnceLock;

/// Index of a material in its [`Scene`]; only [`Scene::add_material`] makes
/// one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MaterialId(u32);

impl MaterialId {
    /// The index into the scene's material list.
    pub fn index(self) -> usize {
        self.0 as usize
    }
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

/// Everything needed to render an image: camera, settings, materials, lights
/// and geometry.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The camera (also fixes the image size).
    pub camera: Camera,
    /// Sampling, depth, background, tone mapping, seed.
    pub settings: RenderSettings,
    /// Ambient light: every surface reflects `ka · colour · ambient`.
    pub ambient: Color,
    lights: Vec<Light>,
    area_lights: Vec<AreaLight>,
    environment: Option<Environment>,
    materials: Vec<Material>,
    primitives: Vec<Primitive>,
    /// Built on first use, after the last [`Scene::add`].
    aggregate: OnceLock<BvhAggregate>,
    /// All lights with their sampling distribution, built on first use.
    light_set: OnceLock<LightSet>,
    /// Non-fatal problems found while loading (e.g. skipped degenerate
    /// triangles), for the user.
    pub warnings: Vec<String>,
}

impl Scene {
    /// An empty scene seen by `camera`, with default settings.
    pub fn new(camera: Camera) -> Self {
        Self {
            camera,
            settings: RenderSettings::default(),
            ambient: Color::ZERO,
            lights: Vec::new(),
            area_lights: Vec::new(),
            environment: None,
            materials: Vec::new(),
            primitives: Vec::new(),
            aggregate: OnceLock::new(),
            light_set: OnceLock::new(),
            warnings: Vec::new(),
        }
    }

    /// Add a material; returns its handle.
    pub fn add_material(&mut self, material: Material) -> MaterialId {
        self.materials.push(material);
        MaterialId(self.materials.len() as u32 - 1)
    }

    /// Add a primitive. Its material must come from this scene.
    pub fn add(&mut self, primitive: Primitive) {
        assert!(primitive.material().index() < self.materials.len(), "material handle from another scene");
        self.primitives.push(primitive);
        self.aggregate = OnceLock::new();
        self.light_set = OnceLock::new();
    }

    /// Add a primitive whose surface emits `radiance` (a diffuse area
    /// light): from its front side only (a triangle's normal side, a
    /// sphere's outside), or from both when `two_sided`. Every triangle of
    /// a mesh becomes its own light.
    ///
    /// Planes cannot emit (they have no finite area), nor can spheres
    /// stretched into ellipsoids.
    pub fn add_emissive(
        &mut self,
        primitive: Primitive,
        radiance: Color,
        two_sided: bool,
    ) -> Result<(), EmissionError> {
        if !(radiance.is_finite() && radiance.min_element() >= 0.0) {
            return Err(EmissionError::Radiance);
        }
        let t = primitive.transform();
        let first = self.area_lights.len();
        let light = |shape| AreaLight { shape, radiance, two_sided };
        match primitive.shape() {
            Shape::Plane(_) => return Err(EmissionError::Plane),
            Shape::Sphere(s) => {
                let scale = uniform_scale(&t).ok_or(EmissionError::Ellipsoid)?;
                let shape = AreaShape::Sphere { center: t.point(s.center()), radius: s.radius() * scale };
                self.area_lights.push(light(shape));
            }
            Shape::Triangle(tri) => {
                self.area_lights.push(light(AreaShape::Triangle(tri.vertices().map(|p| t.point(p)))))
            }
            Shape::Mesh(mesh) => {
                self.area_lights.reserve(mesh.triangle_count());
                for i in 0..mesh.triangle_count() {
                    self.area_lights.push(light(AreaShape::Triangle(mesh.triangle(i).map(|p| t.point(p)))));
                }
            }
        }
        let first = u32::try_from(first).map_err(|_| EmissionError::TooMany)?;
        u32::try_from(self.area_lights.len()).map_err(|_| EmissionError::TooMany)?;
        self.add(primitive.with_area_light(first));
        Ok(())
    }

    /// Add a light.
    pub fn add_light(&mut self, light: Light) {
        self.lights.push(light);
        self.light_set = OnceLock::new();
    }

    /// The point, spot and directional lights.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// The emissive surfaces, one light per sphere or triangle.
    pub fn area_lights(&self) -> &[AreaLight] {
        &self.area_lights
    }

    /// Light arriving from infinitely far away, for the path integrator.
    /// Without one, rays that leave the scene see the background colour of
    /// the render settings, which then acts as a constant environment.
    pub fn environment(&self) -> Option<&Environment> {
        self.environment.as_ref()
    }

    /// Set the environment light.
    pub fn set_environment(&mut self, environment: Option<Environment>) {
        self.environment = environment;
        self.light_set = OnceLock::new();
    }

    /// Every light of the path integrator, built on first use: the area
    /// lights first (so that area light `i` is emitter `i`), then the point,
    /// spot and directional lights, then the environment (or the
    /// background colour, if not black) last.
    pub fn light_set(&self) -> &LightSet {
        self.light_set.get_or_init(|| {
            let mut emitters: Vec<Emitter> = self.area_lights.iter().map(|&a| Emitter::Area(a)).collect();
            emitters.extend(self.lights.iter().cloned().map(Emitter::Delta));
            match &self.environment {
                Some(env) => emitters.push(Emitter::Environment(env.clone())),
                None if self.settings.background.max_element() > 0.0 => {
                    emitters.push(Emitter::Environment(Environment::Constant(self.settings.background)))
                }
                None => {}
            }
            LightSet::new(emitters, &self.bounds())
        })
    }

    /// The environment emitter of [`Scene::light_set`] and its index, if
    /// the scene has one (the environment, or a non-black background).
    pub fn environment_light(&self) -> Option<(usize, &Environment)> {
        let emitters = self.light_set().emitters();
        match emitters.last() {
            Some(Emitter::Environment(env)) => Some((emitters.len() - 1, env)),
            _ => None,
        }
    }

    /// Bounds of everything finite in the scene (planes excluded).
    pub fn bounds(&self) -> Bounds3 {
        self.primitives
            .iter()
            .map(Primitive::bounds)
            .filter(|b| !b.is_infinite())
            .fold(Bounds3::EMPTY, |a, b| a.union(&b))
    }

    /// The material behind a handle.
    #[inline]
    pub fn material(&self, id: MaterialId) -> &Material {
        &self.materials[id.index()]
    }

    /// The materials.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// The primitives.
    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }

    /// The acceleration structure, built now if it has not been yet. Calling
    /// this before rendering keeps the build out of the render time.
    ///
    /// Loose triangles (each its own primitive, as `[[triangle]]` and
    /// `[[quad]]` entries are) are merged into world-space meshes first, so
    /// that they are intersected four at a time by the meshes' SIMD
    /// triangle blocks rather than one by one through the top-level BVH;
    /// see `merge_loose_triangles` in this module. [`Scene::primitives`] is unchanged.
    pub fn aggregate(&self) -> &BvhAggregate {
        self.aggregate.get_or_init(|| BvhAggregate::new(&merge_loose_triangles(&self.primitives)))
    }

    /// The nearest surface hit by `ray` with `0 < t < t_max`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceInteraction> {
        self.aggregate().intersect(ray, t_max)
    }

    /// Whether anything blocks `ray` for `0 < t < t_max`.
    #[inline]
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        self.aggregate().intersect_p(ray, t_max)
    }
}

/// `primitives` with every loose triangle (a [`Shape::Triangle`] primitive)
/// moved into a world-space [`Mesh`]: one for the flat triangles, one for
/// the smooth ones (with per-vertex normals, carried through the inverse
/// transpose of each triangle's transform). Each face keeps its triangle's
/// material (through the mesh's material ids and
/// [`Primitive::with_face_materials`]) and area light (through a per-face
/// light table), and its texture coordinates, the barycentrics `(b₁, b₂)`.
/// Other primitives are returned as they are. With fewer than two loose
/// triangles, or if a mesh cannot be built, the triangles stay as they are.
pub(crate) fn merge_loose_triangles(primitives: &[Primitive]) -> Vec<Primitive> {
    let loose = |p: &Primitive| matches!(p.shape(), Shape::Triangle(_));
    if primitives.iter().filter(|p| loose(p)).count() < 2 {
        return primitives.to_vec();
    }
    let mut out: Vec<Primitive> = primitives.iter().filter(|p| !loose(p)).cloned().collect();
    for smooth in [false, true] {
        let group: Vec<&Primitive> = primitives
            .iter()
            .filter(|p| matches!(p.shape(), Shape::Triangle(t) if t.normals().is_some() == smooth))
            .collect();
        if group.is_empty() {
            continue;
        }
        let mut mesh = TriangleMesh::default();
        let mut normals = Vec::new();
        let mut table: Vec<MaterialId> = Vec::new();
        let mut material_ids = Vec::with_capacity(group.len());
        let mut lights = Vec::with_capacity(group.len());
        for prim in &group {
            let Shape::Triangle(tri) = prim.shape() else { unreachable!() };
            let t = prim.transform();
            let identity = t.is_identity();
            let base = mesh.positions.len() as u32;
            mesh.positions.extend(tri.vertices().map(|p| if identity { p } else { t.point(p) }));
            if let Some(ns) = tri.normals() {
                normals.extend(ns.map(|n| if identity { n } else { t.normal(n).normalize_or_zero() }));
            }
            mesh.indices.push([base, base + 1, base + 2]);
            let m = prim.material();
            let index = table.iter().position(|&x| x == m).unwrap_or_else(|| {
                table.push(m);
                table.len() - 1
            });
            material_ids.push(index as u32);
            lights.push(prim.area_light().unwrap_or(NO_LIGHT));
        }
        if smooth {
            mesh.normals = Some(normals);
        }
        mesh.material_ids = Some(material_ids);
        match Mesh::new(mesh) {
            Ok(mesh) if mesh.degenerate_count() == 0 => {
                let mut merged =
                    Primitive::new(Arc::new(mesh), Transform::IDENTITY, table[0]).with_face_materials(table.into());
                if lights.iter().any(|&l| l != NO_LIGHT) {
                    merged = merged.with_face_lights(lights.into());
                }
                out.push(merged);
            }
            // Degenerate once transformed, or not finite: leave them be.
            _ => out.extend(group.into_iter().cloned()),
        }
    }
    out
}

#[cfg(test)]
mod merge_tests {
    use super::*;
    use crate::accel::{Aggregate, LinearAggregate};
    use crate::geometry::Vec3;
    use crate::sampling::Pcg32;
    use crate::shapes::{Sphere, Triangle};

    /// Merging loose triangles into meshes must not change what a ray
    /// hits: the same surface, material, area light, normals and
    /// texture coordinates as the triangles tested one by one.
    #[test]
    fn merged_triangles_hit_like_the_loose_ones() {
        let camera = Camera::new(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y, 60.0, 8, 8).unwrap();
        let mut scene = Scene::new(camera);
        let m: Vec<MaterialId> = (0..3)
            .map(|i| scene.add_material(Material::matte(Color::splat(0.2 * i as f32 + 0.1), 0.8).unwrap()))
            .collect();
        let mut rng = Pcg32::new(3, 5);
        let mut v = |s: f32| Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * s;
        for i in 0..40 {
            let c = v(4.0);
            let p = [c + v(1.5), c + v(1.5), c + v(1.5)];
            let normals = (i % 3 == 0).then(|| [v(1.0) + Vec3::Z, v(1.0) + Vec3::Z, v(1.0) + Vec3::Z]);
            let t = if i % 4 == 1 { Transform::translate(v(1.0)) } else { Transform::rotate_y(37.0 * i as f32) };
            let prim = Primitive::new(Triangle::new(p, normals).unwrap(), t, m[i % 3]);
            if i % 5 == 2 {
                scene.add_emissive(prim, Color::splat(2.0), false).unwrap();
            } else {
                scene.add(prim);
            }
        }
        scene.add(Primitive::new(Sphere::new(Vec3::new(0.0, 3.0, 0.0), 0.7).unwrap(), Transform::IDENTITY, m[1]));
        let merged = merge_loose_triangles(scene.primitives());
        assert_eq!(merged.len(), 3, "a sphere, a flat mesh and a smooth mesh");
        let list = LinearAggregate::new(scene.primitives().to_vec());
        let mut rng = Pcg32::new(8, 1);
        let (mut hits, mut lit) = (0, 0);
        for _ in 0..20_000 {
            let o = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * 10.0;
            let d = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalize();
            let ray = Ray::new(o, d);
            let (a, b) = (scene.intersect(&ray, f32::INFINITY), list.intersect(&ray, f32::INFINITY));
            assert_eq!(scene.intersect_p(&ray, 6.0), list.intersect_p(&ray, 6.0));
            let (Some(a), Some(b)) = (a, b) else {
                assert_eq!(a.is_some(), b.is_some(), "ray {ray:?}");
                continue;
            };
            hits += 1;
            assert!((a.t - b.t).abs() <= 1e-4 * b.t.max(1.0), "{} vs {}", a.t, b.t);
            assert_eq!(a.material, b.material);
            assert_eq!(a.light, b.light);
            lit += a.light.is_some() as u32;
            assert!((a.n - b.n).length() < 1e-3 && (a.ns - b.ns).length() < 1e-3, "{a:?} vs {b:?}");
            assert!((a.uv - b.uv).length() < 1e-3, "{a:?} vs {b:?}");
        }
        assert!(hits > 500 && lit > 50, "{hits} hits, {lit} on lights");
    }
}
