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

use crate::accel::{Aggregate, BvhAggregate};
use crate::camera::Camera;
use crate::color::Color;
use crate::geometry::Ray;
use crate::interaction::SurfaceInteraction;
use crate::light::Light;
use crate::material::Material;
use crate::render::RenderSettings;
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
    materials: Vec<Material>,
    primitives: Vec<Primitive>,
    /// Built on first use, after the last [`Scene::add`].
    aggregate: OnceLock<BvhAggregate>,
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
            materials: Vec::new(),
            primitives: Vec::new(),
            aggregate: OnceLock::new(),
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
    }

    /// Add a light.
    pub fn add_light(&mut self, light: Light) {
        self.lights.push(light);
    }

    /// The lights.
    pub fn lights(&self) -> &[Light] {
        &self.lights
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
    pub fn aggregate(&self) -> &BvhAggregate {
        self.aggregate.get_or_init(|| BvhAggregate::new(&self.primitives))
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
