//! # lucent
//!
//! A ray tracer: one render loop that runs either of two integrators, the
//! classic Whitted ray tracer (hard shadows, mirrors, ambient light) and a
//! physically based path tracer (next-event estimation with multiple
//! importance sampling), over scenes of spheres, planes, triangles and
//! instanced meshes in a two-level, eight-wide SIMD BVH.
//!
//! ## Architecture
//!
//! The modules are layers, listed here bottom-up in the order a sample's
//! data flows through them. A module uses only the modules listed before
//! it (`tests/layers.rs` checks this on every test run):
//!
//! | layer | modules | what they answer |
//! |---|---|---|
//! | foundations | [`geometry`], [`color`], [`spectrum`], [`texels`] | vectors, rays, bounds, transforms, floating-point error; RGB; spectra and colour spaces made RGB; grids of texels |
//! | sampling | [`sampling`] | random and low-discrepancy numbers, warps, distributions |
//! | acceleration | [`accel`] | a BVH over boxes, built and traversed |
//! | geometry of objects | [`mesh`], [`shapes`] | triangle meshes from files; where a ray hits a shape |
//! | appearance | [`texture`], [`bsdf`], [`material`] | images and procedural textures; how surfaces reflect light |
//! | volumes | [`medium`] | participating media (absorption, scattering, emission) and the media on a surface's two sides |
//! | hits | [`interaction`], [`primitive`] | shapes placed with materials; the nearest hit of many |
//! | emission | [`light`] | point, spot, directional, area and environment lights |
//! | the world | [`camera`], [`scene`] | the camera; an immutable [`scene::Scene`] made by a [`scene::SceneBuilder`] |
//! | the image | [`film`] | reconstruction filters, the accumulator, tone mapping, image files |
//! | light transport | [`integrator`] | radiance along a camera ray |
//! | the loop | [`render`] | [`render::RenderSettings`] and the parallel, deterministic render loop |
//! | ways in | [`loader`] | TOML/JSON scene files and pbrt-v4 scenes ([`loader::pbrt`]), built through the scene builder |
//! | tools | [`tools`] | image comparison, procedural skies, benchmark meshes: used by the program and tests, never by the layers above |
//!
//! One sample goes: the [`render`] loop asks the [`sampling::Sampler`] for
//! a film and a lens position, the [`camera`] turns them into a ray, the
//! [`integrator`] follows it through the [`scene`] (whose [`primitive`]
//! aggregate finds hits in [`shapes`] by way of the [`accel`] BVH, and
//! whose [`material`]s and [`light`]s give the [`bsdf`]s and emitted light
//! at each hit) and returns radiance, which the loop splats into the
//! [`film`]'s accumulator with the reconstruction filter.
//! `docs/architecture.md` tells the same story at more length.
//!
//! ```
//! use lucent::prelude::*;
//!
//! let loaded = parse_scene(r#"
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
//! "#, SceneFormat::Toml)?;
//! let out = render(&loaded.scene, &loaded.settings, RenderOptions::default())?;
//! // The centre pixel faces the light head on: kd · albedo / π · E = 1/π.
//! let c = out.film.pixel(8, 8);
//! assert!((c.x - std::f32::consts::FRAC_1_PI).abs() < 0.01);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]
// Every `unsafe` block says why it is sound (issue 32; the audit of each
// block is in docs/reliability.md). CI's `-D warnings` makes this an error.
#![warn(clippy::undocumented_unsafe_blocks)]

// The layers, bottom-up: a module uses only the modules declared before it
// (tests/layers.rs checks this). Blank lines keep rustfmt from sorting them.

// Foundations.
pub mod memory;

pub mod geometry;

pub mod color;

pub mod spectrum;

pub mod texels;

// Sampling.
pub mod sampling;

// Acceleration.
pub mod accel;

// The geometry of objects.
pub mod mesh;

pub mod shapes;

// Appearance.
pub mod texture;

pub mod bsdf;

pub mod material;

// Volumes.
pub mod medium;

// Hits.
pub mod interaction;

pub mod primitive;

// Emission.
pub mod light;

// The world.
pub mod camera;

pub mod scene;

// The image.
pub mod film;

// After the image: denoising it (Intel Open Image Denoise, opened at run
// time).
pub mod denoise;

// Light transport.
pub mod integrator;

// The loop.
pub mod render;

// Ways in.
pub mod loader;

// Tools (for the program and tests; nothing above uses them).
pub mod tools;

/// The names most programs need.
pub mod prelude {
    pub use crate::camera::{Camera, ThinLens};
    pub use crate::color::Color;
    pub use crate::film::{Film, PendingImage, ToneMap};
    pub use crate::geometry::{Ray, Transform, Vec2, Vec3};
    pub use crate::light::{Falloff, Light};
    pub use crate::loader::{load_scene, parse_scene, LoadedScene, SceneFile, SceneFormat};
    pub use crate::material::{Material, MaterialId};
    pub use crate::primitive::Primitive;
    pub use crate::render::{render, IntegratorKind, RenderOptions, RenderOutput, RenderSettings};
    pub use crate::scene::{Emission, Scene, SceneBuilder, SceneError};
    pub use crate::shapes::{Plane, Sphere, Triangle};
    pub use crate::texture::Texture;
}
