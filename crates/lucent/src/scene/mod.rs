//! Scenes: what is rendered. A [`Scene`] is the world (camera, materials,
//! lights and placed geometry, with its acceleration structure and light
//! distribution) and nothing about *how* it is rendered, which is the
//! business of the render settings (a layer above).
//!
//! A scene is made by a [`SceneBuilder`] and is immutable afterwards: the
//! BVH and the light set are built once by [`SceneBuilder::build`], so no
//! later change can leave them stale. Every way into a scene goes through
//! the builder: code (below), the TOML/JSON loader (a layer above) and the
//! importers to come.
//!
//! ```
//! use lucent::prelude::*;
//!
//! let camera = Camera::new(Vec3::new(0.0, 1.0, -5.0), Vec3::ZERO, Vec3::Y, 60.0, 32, 24)?;
//! let mut builder = SceneBuilder::new(camera);
//! let red = builder.add_material(Material::matte(Color::new(1.0, 0.2, 0.2), 0.8)?)?;
//! builder.add_shape(Sphere::new(Vec3::ZERO, 1.0)?, Transform::IDENTITY, red)?;
//! builder.add_light(Light::point(Vec3::new(5.0, 5.0, -5.0), Color::ONE, 3.0, Falloff::None)?);
//! builder.set_ambient(Color::splat(0.05))?;
//! let scene = builder.build()?;
//! let image = render(&scene, &RenderSettings::default(), RenderOptions::default())?;
//! assert_eq!(image.film.width(), 32);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod builder;
mod error;

pub use builder::{Emission, EmissionError, SceneBuilder};
pub use error::{SceneError, SourceLocation};

use crate::camera::Camera;
use crate::color::Color;
use crate::geometry::{Bounds3, Ray, Vec3};
use crate::interaction::SurfaceInteraction;
use crate::light::{AreaLight, Emitter, Environment, Light, LightSet};
use crate::material::{Material, MaterialId};
use crate::medium::{Medium, MediumId};
use crate::primitive::{Aggregate, BvhAggregate, Primitive};

/// Everything that is rendered: the camera, materials, lights and placed
/// geometry, with the acceleration structure and light distribution built
/// from them. Made by a [`SceneBuilder`]; immutable afterwards (only the
/// camera may be replaced, with [`Scene::with_camera`], since nothing is
/// derived from it).
#[derive(Clone, Debug)]
pub struct Scene {
    camera: Camera,
    ambient: Color,
    background: Color,
    lights: Vec<Light>,
    area_lights: Vec<AreaLight>,
    environment: Option<Environment>,
    materials: Vec<Material>,
    primitives: Vec<Primitive>,
    aggregate: BvhAggregate,
    light_set: LightSet,
    media: Vec<Medium>,
    camera_medium: Option<MediumId>,
    warnings: Vec<String>,
}

impl Scene {
    /// The camera (it also fixes the image size).
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The same scene seen through another camera (for example at another
    /// image size).
    pub fn with_camera(mut self, camera: Camera) -> Self {
        self.camera = camera;
        self
    }

    /// Ambient light of the classic renderer: every surface reflects
    /// `ka · colour · ambient`.
    pub fn ambient(&self) -> Color {
        self.ambient
    }

    /// Radiance of rays that leave the scene when there is no
    /// [`Scene::environment`]. Under the path integrator a non-black
    /// background is a constant environment light.
    pub fn background(&self) -> Color {
        self.background
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
    pub fn environment(&self) -> Option<&Environment> {
        self.environment.as_ref()
    }

    /// Every light of the path integrator: the area lights first (so that
    /// area light `i` is emitter `i`), then the point, spot and directional
    /// lights, then the environment (or the background colour, if not
    /// black) last.
    pub fn light_set(&self) -> &LightSet {
        &self.light_set
    }

    /// The participating media, indexed by [`MediumId`].
    pub fn media(&self) -> &[Medium] {
        &self.media
    }

    /// The medium `id`.
    #[inline]
    pub fn medium(&self, id: MediumId) -> &Medium {
        &self.media[id.index()]
    }

    /// The medium camera rays start in (`None`: vacuum).
    pub fn camera_medium(&self) -> Option<MediumId> {
        self.camera_medium
    }

    /// Whether the scene has participating media (the path integrator then
    /// tracks which medium each ray is in).
    #[inline]
    pub fn has_media(&self) -> bool {
        !self.media.is_empty()
    }

    /// The environment emitter of [`Scene::light_set`] and its index, if
    /// the scene has one (the environment, or a non-black background).
    pub fn environment_light(&self) -> Option<(usize, &Environment)> {
        let emitters = self.light_set.emitters();
        match emitters.last() {
            Some(Emitter::Environment(env)) => Some((emitters.len() - 1, env)),
            _ => None,
        }
    }

    /// Bounds of everything finite in the scene (planes excluded).
    pub fn bounds(&self) -> Bounds3 {
        finite_bounds(&self.primitives)
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

    /// The primitives, as they were added (before loose triangles are
    /// merged into meshes for the BVH).
    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }

    /// The acceleration structure.
    pub fn aggregate(&self) -> &BvhAggregate {
        &self.aggregate
    }

    /// Non-fatal problems found while building (such as skipped degenerate
    /// triangles), for the user.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The nearest surface hit by `ray` with `0 < t < t_max`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceInteraction> {
        self.aggregate.intersect(ray, t_max)
    }

    /// [`Scene::intersect`], written into `out` (see
    /// [`Aggregate::intersect_into`]).
    #[inline]
    pub fn intersect_into(&self, ray: &Ray, t_max: f32, out: &mut Option<SurfaceInteraction>) {
        self.aggregate.intersect_into(ray, t_max, out)
    }

    /// Whether anything blocks `ray` for `0 < t < t_max`.
    #[inline]
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        self.aggregate.intersect_p(ray, t_max)
    }

    /// [`Scene::intersect_p`] for a ray from its origin towards `target`
    /// (direction `target − origin`, `t_max ≤ 1`): a point light's shadow
    /// ray, which a light buffer may answer (see
    /// [`BvhAggregate::with_light_buffers`]).
    #[inline]
    pub(crate) fn intersect_p_toward(&self, ray: &Ray, t_max: f32, target: Vec3) -> bool {
        self.aggregate.intersect_p_toward(ray, t_max, target)
    }
}

/// The union of the bounds of the primitives that have finite bounds.
fn finite_bounds(primitives: &[Primitive]) -> Bounds3 {
    primitives.iter().map(Primitive::bounds).filter(|b| !b.is_infinite()).fold(Bounds3::EMPTY, |a, b| a.union(&b))
}
