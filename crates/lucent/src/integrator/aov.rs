//! The visible surface of a camera ray, for the auxiliary images
//! ([`AovSample`]) a denoiser or a compositor wants: what the camera sees,
//! without its lighting.
//!
//! Position and depth are those of the first surface the ray hits. Albedo
//! and normal are taken where a denoiser needs them (Intel Open Image
//! Denoise's guidance; Cycles' denoising passes do the same): at the first
//! surface that is not a perfect mirror or smooth glass. The ray follows
//! such surfaces along their strongest delta lobe (a fixed choice, so the
//! layers are free of noise: through glass where transmission dominates,
//! off it at grazing angles), multiplying their tints into the albedo.

use super::path::{material_context, MAX_INTERFACE_SKIPS};
use super::RayStats;
use crate::bsdf::{Bsdf, Bxdf};
use crate::color::Color;
use crate::film::AovSample;
use crate::geometry::{Ray, Vec2, Vec3};
use crate::scene::Scene;

/// Most perfect mirrors and smooth glass surfaces followed before the
/// albedo and normal are taken where the ray stands.
pub const MAX_DELTA_BOUNCES: u32 = 16;

/// Samples of the hemispherical-directional reflectance estimate (a 4 × 4
/// grid of direction samples, each with its own lobe choice).
const RHO_SAMPLES: u32 = 16;
/// The same for the layered BSDFs, whose every sample is a random walk
/// through the coat (a 2 × 2 grid): the albedo guides a denoiser, and 16
/// walks per camera sample cost more than the path itself.
const RHO_SAMPLES_LAYERED: u32 = 4;

/// The [`AovSample`] of camera ray `ray` (its direction need not be unit).
///
/// Where the ray escapes, the albedo is the environment's radiance in that
/// direction (or the background colour) clamped to 1, times the tint of the
/// delta surfaces on the way; position, depth and normal stay 0 where
/// nothing is hit.
/// `stats` counts the rays traced: the first as a camera ray, the rest as
/// secondary rays.
pub fn visible_surface(scene: &Scene, ray: &Ray, stats: &mut RayStats) -> AovSample {
    let mut sample = AovSample::default();
    let mut ray = *ray;
    let mut tint = Color::ONE;
    let mut first = true;
    let (mut delta_bounces, mut skips) = (0, 0);
    loop {
        if first {
            stats.camera += 1;
        } else {
            stats.secondary += 1;
        }
        let Some(si) = scene.intersect(&ray, f32::INFINITY) else {
            let seen = match scene.environment_light() {
                Some((_, env)) => env.le(ray.dir.normalize_or_zero()),
                None => scene.background(),
            };
            sample.albedo = tint * seen.max(Color::ZERO).min(Color::ONE);
            return sample;
        };
        if first {
            first = false;
            sample.position = si.p;
            sample.depth = si.t * ray.dir.length();
        }
        let wo = -ray.dir.normalize_or_zero();
        let bsdf = scene.material(si.material).bsdf_at(&material_context(&si, wo), scene.materials());
        let Some(bsdf) = bsdf else {
            // An interface between media: no surface, go on through it.
            skips += 1;
            if skips > MAX_INTERFACE_SKIPS {
                return sample;
            }
            ray = si.spawn_ray(ray.dir);
            continue;
        };
        if bsdf.is_specular() && delta_bounces < MAX_DELTA_BOUNCES {
            // The strongest delta lobe: `uc = ½` picks the more probable of
            // a dielectric's reflection and transmission.
            if let Some(s) = bsdf.sample_f(wo, 0.5, Vec2::splat(0.5)).filter(|s| s.pdf > 0.0) {
                let weight = s.f * s.wi.dot(si.ns).abs() / s.pdf;
                tint *= weight.max(Color::ZERO).min(Color::ONE);
                delta_bounces += 1;
                ray = si.spawn_ray(s.wi);
                continue;
            }
        }
        let ns = bsdf.frame().z;
        sample.normal = if ns.dot(wo) < 0.0 { -ns } else { ns };
        sample.albedo = tint * reflectance(&bsdf, wo);
        return sample;
    }
}

/// The hemispherical-directional reflectance ρ(wo) = ∫ f(wo, wi) |cos θi|
/// dwi, estimated with the BSDF's own sampling on a fixed stratified set
/// of samples (as pbrt-v4's `BSDF::rho` estimates a surface's albedo for
/// its G-buffer). A Lambertian surface's is its albedo, taken as it is
/// (its sampling would give exactly that: f·cos/pdf = (R/π)·cos/(cos/π)
/// for every sample); the layered BSDFs
/// (`coated_diffuse`, `coated_conductor`) are estimated from 4 samples
/// instead of 16.
pub fn reflectance(bsdf: &Bsdf, wo: Vec3) -> Color {
    let (count, side) = match bsdf.bxdf() {
        Bxdf::Diffuse(d) => return d.r,
        Bxdf::CoatedDiffuse(_) | Bxdf::CoatedConductor(_) => (RHO_SAMPLES_LAYERED, 2),
        _ => (RHO_SAMPLES, 4),
    };
    let mut sum = Color::ZERO;
    let n = bsdf.frame().z;
    for i in 0..count {
        // A grid of directions; the lobe choice runs through the strata in
        // another order (7 is prime to both counts) so that every lobe
        // meets every part of the grid.
        let s = side as f32;
        let u = Vec2::new(((i % side) as f32 + 0.5) / s, ((i / side) as f32 + 0.5) / s);
        let uc = (((i * 7) % count) as f32 + 0.5) / count as f32;
        if let Some(s) = bsdf.sample_f(wo, uc, u).filter(|s| s.pdf > 0.0) {
            let value = s.f * s.wi.dot(n).abs() / s.pdf;
            if value.is_finite() {
                sum += value;
            }
        }
    }
    (sum / count as f32).max(Color::ZERO)
}
