//! Lambertian reflection and transmission: paper, leaves, thin fabric
//! (PBRT 4th ed., §9.2, `DiffuseTransmissionBxDF`).

use super::{same_hemisphere, BsdfSample, BxDF};
use crate::color::Color;
use crate::geometry::{Vec2, Vec3};
use crate::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use std::f32::consts::FRAC_1_PI;

/// `f = R/π` for `wi` on the side of `wo`, `T/π` on the other side: of the
/// light arriving from any direction, exactly `R` is reflected and `T`
/// transmitted, each diffusely.
///
/// Sampling picks reflection with probability `max R / (max R + max T)`
/// (maxima over the RGB channels) and draws a cosine-weighted direction on
/// the chosen side. Both lobes are symmetric in `wo` and `wi`, so the BSDF
/// is reciprocal, transmission included.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmissionBxdf {
    /// Diffuse reflectance per channel, in [0, 1].
    pub r: Color,
    /// Diffuse transmittance per channel, in [0, 1] (`r + t ≤ 1`
    /// conserves energy).
    pub t: Color,
}

impl DiffuseTransmissionBxdf {
    /// Probability of sampling reflection.
    fn p_reflect(&self) -> f32 {
        let (pr, pt) = (self.r.max_element().max(0.0), self.t.max_element().max(0.0));
        if pr + pt > 0.0 {
            pr / (pr + pt)
        } else {
            0.0
        }
    }
}

impl BxDF for DiffuseTransmissionBxdf {
    /// `R/π` on the side of `wo`, `T/π` on the other.
    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        if wo.z == 0.0 || wi.z == 0.0 {
            Color::ZERO
        } else if same_hemisphere(wo, wi) {
            self.r * FRAC_1_PI
        } else {
            self.t * FRAC_1_PI
        }
    }

    /// Choose a side, then a cosine-weighted direction on it.
    fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 || (self.r.max_element() <= 0.0 && self.t.max_element() <= 0.0) {
            return None;
        }
        let pr = self.p_reflect();
        let mut wi = cosine_hemisphere(u);
        if wi.z == 0.0 {
            return None;
        }
        let reflect = uc < pr;
        // The upper hemisphere sample goes to wo's side for reflection,
        // to the other side for transmission.
        if (wo.z < 0.0) == reflect {
            wi.z = -wi.z;
        }
        let (f, p) = if reflect { (self.r, pr) } else { (self.t, 1.0 - pr) };
        let pdf = p * cosine_hemisphere_pdf(wi.z.abs());
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample { f: f * FRAC_1_PI, wi, pdf, specular: false, transmission: !reflect, eta: 1.0 })
    }

    /// The mixture of the two cosine-weighted lobes.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z == 0.0 || wi.z == 0.0 || (self.r.max_element() <= 0.0 && self.t.max_element() <= 0.0) {
            return 0.0;
        }
        let pr = self.p_reflect();
        let p = if same_hemisphere(wo, wi) { pr } else { 1.0 - pr };
        p * cosine_hemisphere_pdf(wi.z.abs())
    }

    /// Never: both lobes are diffuse.
    fn is_specular(&self) -> bool {
        false
    }
}
