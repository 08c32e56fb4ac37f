//! # lucent
//!
//! A ray tracer. This release is the classic (Whitted-style) renderer: a
//! pinhole or thin-lens perspective camera with stratified anti-aliasing;
//! spheres, planes and flat or smooth triangles under arbitrary affine
//! transforms and nested groups; matte and Phong materials with recursive
//! mirror reflection; ambient, point, spot and directional lights with hard
//! shadows; tone mapping; PNG, BMP and OpenEXR output.
//!
//! The modules follow the architecture of a physically based renderer
//! (after PBRT): [`geometry`] and [`shapes`] answer *where* rays hit,
//! [`material`]s describe surfaces, [`light`]s emit, an [`integrator`]
//! computes light transport, the [`camera`] makes rays and the [`film`]
//! collects the image; [`render`] runs it all in parallel.
//!
//! ```
//! use lucent::prelude::*;
//!
//! let scene = parse_scene(r#"
//!     [camera]
//!     eye = [0, 0, -4]
//!     look_at = [0, 0, 0]
//!     [render]
//!     width = 16
//!     height = 16
//!     spp = 1
//!     [materials.white.matte]
//!     color = [1, 1, 1]
//!     [[sphere]]
//!     material = "white"
//!     [[directional_light]]
//!     direction = [0, 0, 1]
//! "#, SceneFormat::Toml).unwrap();
//! let out = render(&scene, &RenderOptions::default()).unwrap();
//! // The centre pixel faces the light head on: kd · albedo / π · E = 1/π.
//! let c = out.film.pixel(8, 8);
//! assert!((c.x - std::f32::consts::FRAC_1_PI).abs() < 0.01);
//! ```

#![warn(missing_docs)]

pub mod accel;
pub mod bsdf;
pub mod camera;
pub mod color;
pub mod film;
pub mod geometry;
pub mod integrator;
pub mod interaction;
pub mod light;
pub mod material;
pub mod mesh;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod shapes;
pub mod texels;
pub mod texture;

/// The names most programs need.
pub mod prelude {
    pub use crate::camera::{Camera, ThinLens};
    pub use crate::color::Color;
    pub use crate::film::{Film, PendingImage, ToneMap};
    pub use crate::geometry::{Ray, Transform, Vec2, Vec3};
    pub use crate::light::{Falloff, Light};
    pub use crate::material::Material;
    pub use crate::render::{render, RenderOptions, RenderOutput, RenderSettings};
    pub use crate::scene::{load_scene, parse_scene, Primitive, Scene, SceneError, SceneFile, SceneFormat};
    pub use crate::shapes::{Plane, Sphere, Triangle};
    pub use crate::texture::Texture;
}
