//! The Henyey–Greenstein phase function (Henyey and Greenstein, "Diffuse
//! radiation in the galaxy", Astrophysical Journal 93, 1941; PBRT 4th ed.,
//! §11.3.1 and §11.3.1's sampling routine).
//!
//! Directions follow PBRT's convention: `wo` points away from the
//! scattering point towards where the light goes (the viewer), `wi` towards
//! where it comes from, so light scatters *forward* when `wi = −wo`. With
//! `cos θ = −wo · wi` (the angle between the incident light's direction of
//! travel and the outgoing one),
//!
//! `p(θ) = (1 − g²) / (4π (1 + g² + 2 g cos θ')^{3/2})` with `cos θ' = wo · wi`,
//!
//! which for `g > 0` peaks at `wi = −wo` (forward scattering), is uniform
//! (`1/4π`) at `g = 0` and peaks at `wi = wo` for `g < 0`. It integrates to
//! 1 over the sphere, and sampling it is exact: the pdf of a sampled
//! direction equals the phase function's value.

use crate::geometry::{Frame, Vec2, Vec3};
use std::f32::consts::PI;

/// A Henyey–Greenstein phase function with asymmetry `g ∈ (−1, 1)` (the
/// mean cosine of the scattering angle).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    g: f32,
}

/// `|g|` is clamped to this: at ±1 the phase function is a delta.
const MAX_G: f32 = 0.99;

/// Below this `|g|`, the inverse CDF loses precision and `g` is taken as 0.
const SMALL_G: f32 = 1e-3;

impl HenyeyGreenstein {
    /// The phase function with asymmetry `g`, clamped to `[−0.99, 0.99]`
    /// (pbrt-v4 clamps the same way); `g` must be finite. A `|g|` below
    /// 10⁻³ is taken as 0, where sampling is uniform: the value and the
    /// pdf then stay exactly equal.
    pub fn new(g: f32) -> Self {
        let g = g.clamp(-MAX_G, MAX_G);
        Self { g: if g.abs() < SMALL_G { 0.0 } else { g } }
    }

    /// The asymmetry parameter.
    pub fn g(&self) -> f32 {
        self.g
    }

    /// The phase function for unit `wo` and `wi` (see the module docs); also
    /// the solid-angle pdf of [`HenyeyGreenstein::sample`].
    #[inline]
    pub fn p(&self, wo: Vec3, wi: Vec3) -> f32 {
        hg(wo.dot(wi), self.g)
    }

    /// Sample `wi` for unit `wo` with uniform `u ∈ [0, 1)²`: returns `wi`
    /// and its pdf, which equals [`HenyeyGreenstein::p`].
    ///
    /// The cosine between `wi` and `−wo` is drawn by inverting the CDF of
    /// HG in `cos θ` (PBRT 4th ed., eq. 11.13):
    /// `cos θ = (1 + g² − ((1 − g²)/(1 + g − 2 g u))²) / (2 g)`, and
    /// `cos θ = 1 − 2u` for `g ≈ 0`; the azimuth is `2π u₂`.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> (Vec3, f32) {
        let g = self.g;
        // cos θ between −wo (forward) and wi.
        let cos_theta = if g == 0.0 {
            1.0 - 2.0 * u.x
        } else {
            let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
            ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
        };
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let (s, c) = phi.sin_cos();
        let frame = Frame::from_z(-wo);
        let wi = frame.from_local(Vec3::new(sin_theta * c, sin_theta * s, cos_theta));
        (wi, hg(wo.dot(wi), g))
    }
}

/// HG's value for `cos θ' = wo · wi` (so `cos θ = −cos θ'` is the
/// scattering angle's cosine).
#[inline]
fn hg(cos_wo_wi: f32, g: f32) -> f32 {
    let denom = 1.0 + g * g + 2.0 * g * cos_wo_wi;
    (1.0 - g * g) / (4.0 * PI * denom * denom.max(1e-12).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    fn rng_dirs(n: usize, seed: u64) -> Vec<Vec3> {
        let mut rng = Pcg32::new(seed, 1);
        (0..n).map(|_| crate::sampling::uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()))).collect()
    }

    #[test]
    fn integrates_to_one_and_has_mean_cosine_g() {
        // Monte Carlo over uniform directions: ∫p = 1, ∫p·cos θ = g.
        let dirs = rng_dirs(400_000, 7);
        let wo = Vec3::new(0.3, -0.5, 0.812).normalize();
        for g in [-0.7, -0.2, 0.0, 0.4, 0.9] {
            let hg = HenyeyGreenstein::new(g);
            let (mut sum, mut mean_cos) = (0.0f64, 0.0f64);
            for &wi in &dirs {
                let p = hg.p(wo, wi) as f64;
                sum += p;
                mean_cos += p * (-wo.dot(wi)) as f64;
            }
            let scale = 4.0 * std::f64::consts::PI / dirs.len() as f64;
            let tol = if g > 0.8 { 0.05 } else { 0.01 };
            assert!((sum * scale - 1.0).abs() < tol, "g {g}: ∫p = {}", sum * scale);
            assert!((mean_cos * scale - g as f64).abs() < tol, "g {g}: mean cos {}", mean_cos * scale);
        }
    }

    #[test]
    fn samples_follow_the_pdf() {
        // The sample's pdf is the value, and the mean cosine of samples is g.
        let mut rng = Pcg32::new(3, 9);
        let wo = Vec3::new(-0.2, 0.9, 0.1).normalize();
        for g in [-0.5, 0.0, 0.3, 0.8] {
            let hg = HenyeyGreenstein::new(g);
            let n = 200_000;
            let mut mean = 0.0f64;
            for _ in 0..n {
                let (wi, pdf) = hg.sample(wo, Vec2::new(rng.uniform(), rng.uniform()));
                assert!((wi.length() - 1.0).abs() < 1e-4);
                assert!((pdf - hg.p(wo, wi)).abs() <= 1e-4 * pdf.max(1.0), "g {g}: {pdf} vs {}", hg.p(wo, wi));
                mean += (-wo.dot(wi)) as f64;
            }
            assert!((mean / n as f64 - g as f64).abs() < 0.01, "g {g}: {}", mean / n as f64);
        }
    }

    #[test]
    fn isotropic_is_one_over_four_pi() {
        let hg = HenyeyGreenstein::new(0.0);
        assert!((hg.p(Vec3::X, Vec3::Y) - 1.0 / (4.0 * PI)).abs() < 1e-7);
        assert_eq!(HenyeyGreenstein::new(2.0).g(), 0.99);
    }
}
