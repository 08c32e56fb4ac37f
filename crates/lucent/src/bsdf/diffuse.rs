//! The Lambertian reflector (PBRT 4th ed., §9.2).

use super::{same_hemisphere, BsdfSample, BxDF};
use crate::color::Color;
use crate::geometry::{Vec2, Vec3};
use crate::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use std::f32::consts::FRAC_1_PI;

/// Lambertian reflection: `f = R/π` on the side of `wo`, sampled with the
/// cosine-weighted hemisphere so that `f·cos θi/pdf = R` exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseBxdf {
    /// Albedo (directional-hemispherical reflectance) per channel.
    pub r: Color,
}

impl BxDF for DiffuseBxdf {
    /// `R/π` on the side of `wo`.
    #[inline]
    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        if same_hemisphere(wo, wi) {
            self.r * FRAC_1_PI
        } else {
            Color::ZERO
        }
    }

    /// Cosine-weighted sample on the side of `wo` (`uc` is not used).
    #[inline]
    fn sample_f(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let mut wi = cosine_hemisphere(u);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = cosine_hemisphere_pdf(wi.z.abs());
        if pdf <= 0.0 || wi.z == 0.0 {
            return None;
        }
        Some(BsdfSample { f: self.r * FRAC_1_PI, wi, pdf, specular: false, transmission: false, eta: 1.0 })
    }

    /// `|cos θi|/π` on the side of `wo`.
    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if same_hemisphere(wo, wi) {
            cosine_hemisphere_pdf(wi.z.abs())
        } else {
            0.0
        }
    }

    /// Never: the lobe is diffuse.
    fn is_specular(&self) -> bool {
        false
    }
}
