//! Light samples of sphere lights across lanes.
//!
//! Sampling the cone of directions a sphere subtends (PBRT 4th ed.,
//! §6.2.4) is a chain of square roots and divisions, each waiting on the
//! one before: one lane at a time it was 7% of the time of Veach's
//! multiple importance sampling scene, whose lights are four spheres.
//! The light stage of [`super::lanes`] gathers the non-specular vertices
//! whose light pick is a sphere area light (without an emission texture,
//! seen from outside, in a scene without media) with their point, their
//! sphere and their sample, and [`sample_cones_lanes`] samples all their
//! cones at once; each lane's light sample is then weighed as
//! [`PathIntegrator::sample_light`] weighs it (whatever the BSDF), and its
//! shadow ray traced, lane by lane.
//!
//! The kernel runs the scalar function's operations in its order, so each
//! lane's sample is the scalar one bit for bit (a test compares them;
//! renders are byte-identical).

use super::lanes::LightStage;
#[cfg(doc)]
use super::PathIntegrator;
use crate::geometry::isa;
#[cfg(target_arch = "x86_64")]
use crate::geometry::Isa;
use crate::geometry::{Vec3Lanes, LANES};
use crate::interaction::SurfaceInteraction;
use crate::light::{AreaLight, Emitter, LightSampleContext};
use crate::scene::Scene;
use crate::shapes::{sample_cones_lanes, ShapeSample};
use glam::Vec2;

/// The lanes of one light stage whose light samples are points of sphere
/// lights, sampled together.
pub(super) struct SphereLanes<'a> {
    /// The lanes taken, each with its light and the light's pick
    /// probability.
    lanes: [u8; LANES],
    lights: [Option<(&'a AreaLight, f32)>; LANES],
    len: usize,
    /// The kernel's inputs: the shading point, the sphere's centre and
    /// radius, and the 2D sample; and its outputs: the point, normal and
    /// pdf of each lane's sample.
    p: Vec3Lanes,
    center: Vec3Lanes,
    radius: [f32; LANES],
    u: [[f32; LANES]; 2],
    p_light: Vec3Lanes,
    n_light: Vec3Lanes,
    pdf: [f32; LANES],
}

impl<'a> SphereLanes<'a> {
    /// No lanes.
    pub(super) fn new() -> Self {
        Self {
            lanes: [0; LANES],
            lights: [None; LANES],
            len: 0,
            p: Vec3Lanes::ZERO,
            center: Vec3Lanes::ZERO,
            radius: [0.0; LANES],
            u: [[0.0; LANES]; 2],
            p_light: Vec3Lanes::ZERO,
            n_light: Vec3Lanes::ZERO,
            pdf: [0.0; LANES],
        }
    }

    /// No lanes again, for the next stage.
    pub(super) fn clear(&mut self) {
        self.len = 0;
    }

    /// Take `lane` (at `si`, with `pick`, the index and probability of the
    /// light its sample picked, and the point sample `u_point`) if its
    /// light is a sphere whose cone the kernel samples; `false` leaves it
    /// to the scalar [`PathIntegrator::sample_light`].
    #[inline]
    pub(super) fn take(
        &mut self,
        scene: &'a Scene,
        lane: u8,
        si: &SurfaceInteraction,
        (index, pmf): (usize, f32),
        u_point: Vec2,
    ) -> bool {
        let Emitter::Area(area) = &scene.light_set().emitters()[index] else { return false };
        let Some(sphere) = area.plain_sphere() else { return false };
        if !sphere.samples_cone_from(si.p) {
            return false;
        }
        let k = self.len;
        self.lanes[k] = lane;
        self.lights[k] = Some((area, pmf));
        self.p.set(k, si.p);
        self.center.set(k, sphere.center());
        self.radius[k] = sphere.radius();
        (self.u[0][k], self.u[1][k]) = (u_point.x, u_point.y);
        self.len += 1;
        true
    }

    /// Next-event estimation for the lanes taken: the cones sampled
    /// together, then each lane's sample weighed and, where it carries
    /// light, tested with a shadow ray; what it finds is added to the
    /// lane's path.
    pub(super) fn estimate(&mut self, stage: &mut LightStage) {
        let n = self.len;
        if n == 0 {
            return;
        }
        sample_cones_any(self, n);
        for k in 0..n {
            let i = self.lanes[k] as usize;
            let (Some(si), Some((area, pmf))) = (&stage.hits[i], self.lights[k]) else {
                unreachable!("a lane taken has a vertex and a light")
            };
            let s = ShapeSample { p: self.p_light.get(k), n: self.n_light.get(k), pdf: self.pdf[k] };
            let ctx = LightSampleContext { p: si.p, n: si.n };
            let Some(ls) = area.sample_li_from(&ctx, s) else { continue };
            stage.add_light_sample(i, pmf, ls);
        }
    }
}

/// [`sample_cones_lanes`] on the lanes taken, in the build for this CPU.
fn sample_cones_any(s: &mut SphereLanes, n: usize) {
    match isa() {
        // SAFETY: `isa` found AVX2 (AVX-512 includes it).
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 | Isa::Avx512 => unsafe { sample_cones_avx2(s, n) },
        _ => sample_cones(s, n),
    }
}

/// [`sample_cones`] compiled for AVX2: eight lanes to a register.
///
/// # Safety
/// The CPU must have AVX2 and FMA. (FMA only makes the instructions
/// available: Rust never fuses a multiplication and an addition itself, so
/// the values are the portable build's.)
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn sample_cones_avx2(s: &mut SphereLanes, n: usize) {
    sample_cones(s, n);
}

/// The kernel on lanes `0..n`.
#[inline(always)]
fn sample_cones(s: &mut SphereLanes, n: usize) {
    sample_cones_lanes(&s.center, &s.radius, &s.p, &s.u, n, &mut s.p_light, &mut s.n_light, &mut s.pdf);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec3;
    use crate::sampling::Pcg32;
    use crate::shapes::Sphere;

    /// The kernel gives [`Sphere::sample_solid_angle`]'s point, normal and
    /// pdf bit for bit, in both builds, over random spheres (of radii from
    /// tiny to large, so both sides of the small-cone threshold), points
    /// outside them (far, and just beyond the area-sampling margin) and
    /// samples (with the square's edges mixed in), in batches of 1 to 64
    /// lanes.
    #[test]
    fn cone_kernel_equals_the_scalar_sample() {
        let mut rng = Pcg32::new(11, 5);
        let mut checked = 0;
        for batch in 0..300 {
            let n = 1 + batch % LANES;
            let mut lanes = SphereLanes::new();
            let mut spheres = Vec::new();
            while lanes.len < n {
                let scale = 0.5 + rng.uniform();
                let mut v = || Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
                let (center, dir) = (v() * 20.0, v().normalize());
                let radius = [1e-3, 0.05, 0.5, 2.0][lanes.len % 4] * scale;
                let distance = match lanes.len % 5 {
                    0 => radius * 1.0021,
                    1 => radius * (1.0 + rng.uniform()),
                    _ => radius * (1.0 + 100.0 * rng.uniform()),
                };
                let p = center + dir * distance;
                let sphere = Sphere::new(center, radius).unwrap();
                if !sphere.samples_cone_from(p) {
                    continue;
                }
                let mut u = Vec2::new(rng.uniform(), rng.uniform());
                match lanes.len % 7 {
                    0 => u = Vec2::ZERO,
                    1 => u.x = 0.0,
                    2 => u.y = 0.999_999_94,
                    _ => {}
                }
                let k = lanes.len;
                lanes.p.set(k, p);
                lanes.center.set(k, center);
                lanes.radius[k] = radius;
                (lanes.u[0][k], lanes.u[1][k]) = (u.x, u.y);
                lanes.len += 1;
                spheres.push((sphere, p, u));
            }
            sample_cones(&mut lanes, n);
            let portable = (lanes.p_light, lanes.n_light, lanes.pdf);
            sample_cones_any(&mut lanes, n);
            for (k, (sphere, p, u)) in spheres.iter().enumerate() {
                let s = sphere.sample_solid_angle(*p, *u).expect("a cone sample");
                let lane = |pl: &Vec3Lanes, nl: &Vec3Lanes, pdf: &[f32; LANES]| {
                    (pl.get(k).to_array().map(f32::to_bits), nl.get(k).to_array().map(f32::to_bits), pdf[k].to_bits())
                };
                let expected = (s.p.to_array().map(f32::to_bits), s.n.to_array().map(f32::to_bits), s.pdf.to_bits());
                assert_eq!(
                    lane(&portable.0, &portable.1, &portable.2),
                    expected,
                    "lane {k} of {n}: {sphere:?} from {p}"
                );
                assert_eq!(
                    lane(&lanes.p_light, &lanes.n_light, &lanes.pdf),
                    expected,
                    "lane {k} of {n}, this CPU's build"
                );
                checked += 1;
            }
        }
        assert!(checked > 9000, "{checked}");
    }
}
