//! The classic Phong material, made energy conserving.
//!
//! Three lobes with weights `wd` (a colour), `ws` and `wr`:
//! * Lambertian `wd/π`;
//! * the normalised Phong lobe `ws · (n+2)/(2π) · cos^n α`, `α` the angle
//!   between `wi` and the mirror direction of `wo` (Lafortune & Willems,
//!   "Using the Modified Phong Reflectance Model for Physically Based
//!   Rendering", 1994). Its albedo is at most 1, reached at normal
//!   incidence; it is symmetric in `wo`, `wi` (reciprocal);
//! * a perfect mirror of weight `wr` (a delta lobe).
//!
//! Energy conservation: the albedo is at most `max(wd) + ws + wr`, so when
//! that sum exceeds 1 all three weights are divided by it (this keeps their
//! ratios, and the material's look, and makes it conserve energy).
//!
//! Sampling picks a lobe with probability proportional to its weight (the
//! diffuse weight being the mean of `wd`'s channels); the Phong lobe is
//! sampled as `cos^n α` about the mirror direction, density
//! `(n+1)/(2π) cos^n α` (Lafortune & Willems, §4). Directions below the
//! surface have `f = 0` and are rejected; `pdf` counts only directions on
//! the side of `wo`, so it is exactly the density of the returned samples.
//! Reflection only, two-sided.

use super::{flip_z, two_sided, BsdfSample, BxDF};
use crate::color::Color;
use crate::geometry::{Frame, Vec2, Vec3};
use crate::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use std::f32::consts::{FRAC_1_PI, PI};

/// The energy-conserving Phong material; see the module documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongBxdf {
    /// Diffuse weight (albedo of the Lambertian lobe), after rescaling.
    pub wd: Color,
    /// Weight of the glossy Phong lobe, after rescaling.
    pub ws: f32,
    /// Weight of the mirror, after rescaling.
    pub wr: f32,
    /// Phong exponent `n ≥ 0`.
    pub exponent: f32,
}

impl PhongBxdf {
    /// The material with the given weights, divided by
    /// `max(wd) + ws + wr` when that exceeds 1. Negative or NaN weights and
    /// exponents are taken as 0.
    pub fn new(diffuse: Color, ks: f32, exponent: f32, kr: f32) -> Self {
        let pos = |x: f32| if x > 0.0 { x } else { 0.0 };
        let wd = Color::new(pos(diffuse.x), pos(diffuse.y), pos(diffuse.z));
        let (ws, wr) = (pos(ks), pos(kr));
        let sum = wd.max_element() + ws + wr;
        let scale = if sum > 1.0 { 1.0 / sum } else { 1.0 };
        Self { wd: wd * scale, ws: ws * scale, wr: wr * scale, exponent: pos(exponent) }
    }

    /// Lobe selection probabilities (diffuse, glossy, mirror); all 0 if the
    /// material is black.
    #[inline]
    fn probabilities(&self) -> (f32, f32, f32) {
        let pd = self.wd.element_sum() / 3.0;
        let total = pd + self.ws + self.wr;
        if total > 0.0 {
            (pd / total, self.ws / total, self.wr / total)
        } else {
            (0.0, 0.0, 0.0)
        }
    }

    /// `max(0, cos α)^n` with `cos α = wi · mirror(wo)`.
    #[inline]
    fn lobe(&self, wo: Vec3, wi: Vec3) -> f32 {
        let cos_alpha = Vec3::new(-wo.x, -wo.y, wo.z).dot(wi);
        if cos_alpha > 0.0 {
            cos_alpha.min(1.0).powf(self.exponent)
        } else {
            0.0
        }
    }

    fn f_upper(&self, wo: Vec3, wi: Vec3) -> Color {
        let glossy = self.ws * (self.exponent + 2.0) / (2.0 * PI) * self.lobe(wo, wi);
        self.wd * FRAC_1_PI + Color::splat(glossy)
    }

    fn pdf_upper(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (pd, ps, _) = self.probabilities();
        pd * cosine_hemisphere_pdf(wi.z) + ps * (self.exponent + 1.0) / (2.0 * PI) * self.lobe(wo, wi)
    }
}

impl BxDF for PhongBxdf {
    /// BSDF value of the non-delta lobes.
    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        two_sided(wo, wi, |wo, wi| self.f_upper(wo, wi))
    }

    /// Pick a lobe with `uc`, sample it with `u`.
    fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let (pd, ps, pr) = self.probabilities();
        if pd + ps + pr == 0.0 {
            return None;
        }
        let lower = wo.z < 0.0;
        let wo_up = if lower { flip_z(wo) } else { wo };
        let unflip = |w: Vec3| if lower { flip_z(w) } else { w };
        let mirror = Vec3::new(-wo_up.x, -wo_up.y, wo_up.z);
        let wi = if uc < pr {
            let f = Color::splat(self.wr / mirror.z);
            return Some(BsdfSample { f, wi: unflip(mirror), pdf: pr, specular: true, transmission: false, eta: 1.0 });
        } else if uc < pr + pd {
            cosine_hemisphere(u)
        } else {
            // cos α = u^(1/(n+1)) about the mirror direction.
            let cos_a = u.x.powf(1.0 / (self.exponent + 1.0));
            let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
            let phi = 2.0 * PI * u.y;
            Frame::from_z(mirror).from_local(Vec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a))
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf_upper(wo_up, wi);
        if pdf <= 0.0 || !pdf.is_finite() {
            return None;
        }
        let f = self.f_upper(wo_up, wi);
        Some(BsdfSample { f, wi: unflip(wi), pdf, specular: false, transmission: false, eta: 1.0 })
    }

    /// Mixture pdf of the diffuse and glossy lobes.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        two_sided(wo, wi, |wo, wi| self.pdf_upper(wo, wi))
    }

    /// Whether only the mirror lobe is present.
    #[inline]
    fn is_specular(&self) -> bool {
        self.wd == Color::ZERO && self.ws == 0.0 && self.wr > 0.0
    }
}
