//! Integrators: light transport. An integrator answers "how much light
//! arrives along this ray?" using the scene's geometry, materials and
//! lights. There are three: the classic [`WhittedIntegrator`] (hard
//! shadows, perfect mirrors, ambient light), the physically based
//! [`PathIntegrator`] (global illumination with multiple importance
//! sampling), and the [`BdptIntegrator`] (bidirectional path tracing: the
//! same light transport, with light subpaths for caustics).

mod aov;
mod bdpt;
mod medium_segment;
mod path;
mod whitted;

pub use aov::{reflectance, visible_surface, MAX_DELTA_BOUNCES};
pub use bdpt::BdptIntegrator;
pub use path::{power_heuristic, DirectLighting, PathIntegrator, PATH_LANES, RR_DEPTH};
pub use whitted::WhittedIntegrator;

use crate::color::Color;
use crate::geometry::{Ray, Vec2};
use crate::sampling::Sampler;
use crate::scene::Scene;

/// Counts of rays traced, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayStats {
    /// Rays from the camera.
    pub camera: u64,
    /// Shadow (visibility) rays towards lights.
    pub shadow: u64,
    /// Secondary rays (mirror reflections).
    pub secondary: u64,
}

impl RayStats {
    /// All rays traced.
    pub fn total(&self) -> u64 {
        self.camera + self.shadow + self.secondary
    }

    /// Add another tally to this one.
    pub fn merge(&mut self, other: &RayStats) {
        self.camera += other.camera;
        self.shadow += other.shadow;
        self.secondary += other.secondary;
    }
}

/// Light a camera sample sends to the film somewhere other than its own
/// pixel: a light-tracing contribution of bidirectional path tracing,
/// splatted at film position `film` (pixels) into the film's light image
/// ([`crate::film::AovSet::with_light_image`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmSplat {
    /// Where it lands on the film, in pixels.
    pub film: Vec2,
    /// Its value: divided by the samples per pixel, the radiance it adds
    /// there.
    pub l: Color,
}

/// Computes the radiance arriving along a camera ray: the one interface of
/// light transport, through which the render loop runs every integrator.
pub trait Integrator: Sync {
    /// Radiance arriving at the ray's origin from along `-ray.dir`, in linear
    /// RGB. `sampler` is positioned at the pixel sample the ray belongs to,
    /// with its film and lens dimensions consumed; `stats` counts the rays
    /// traced.
    fn li(&self, scene: &Scene, ray: &Ray, sampler: &mut Sampler, stats: &mut RayStats) -> Color;

    /// Whether the integrator also sends light straight to the film
    /// ([`FilmSplat`]s, from [`Integrator::li_splat`]): the render loop then
    /// calls that instead of [`Integrator::li_lanes`], and the film keeps a
    /// light image. False by default.
    fn splats_light(&self) -> bool {
        false
    }

    /// [`Integrator::li`], also pushing onto `splats` the light this sample
    /// sends to other places of the film. The default sends none.
    fn li_splat(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        splats: &mut Vec<FilmSplat>,
        stats: &mut RayStats,
    ) -> Color {
        let _ = splats;
        self.li(scene, ray, sampler, stats)
    }

    /// [`Integrator::li`] for many camera rays at once: `radiance[i]` is the
    /// radiance along `rays[i]`, with `samplers[i]` positioned at its pixel
    /// sample. The result for each ray is the same as [`Integrator::li`]'s,
    /// bit for bit; an integrator that traces paths together (the
    /// [`PathIntegrator`]) overrides it, the default traces them one by one.
    ///
    /// # Panics
    /// If the three slices differ in length.
    fn li_lanes(
        &self,
        scene: &Scene,
        rays: &[Ray],
        samplers: &mut [Sampler],
        radiance: &mut [Color],
        stats: &mut RayStats,
    ) {
        assert!(rays.len() == samplers.len() && rays.len() == radiance.len());
        for ((ray, sampler), out) in rays.iter().zip(samplers.iter_mut()).zip(radiance.iter_mut()) {
            *out = self.li(scene, ray, sampler, stats);
        }
    }
}
