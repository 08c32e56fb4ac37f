//! A thin dielectric slab: a window pane or a soap bubble (PBRT 4th ed.,
//! §9.5.3, `ThinDielectricBxDF`).

use super::fresnel::fr_dielectric;
use super::{BsdfSample, BxDF};
use crate::color::Color;
use crate::geometry::{Vec2, Vec3};

/// Two parallel smooth interfaces of index `eta`, infinitely close: light
/// either reflects specularly or passes straight through (`wi = −wo`, no
/// bending: the two refractions cancel).
///
/// With single-interface reflectance `R = F(cos θo)` and `T = 1 − R`, the
/// light bouncing between the two faces adds up to the geometric series
/// `R' = R + T² R (1 + R² + R⁴ + …) = R + T² R / (1 − R²)` for the slab's
/// reflectance and `T' = 1 − R'` for its transmittance (no absorption).
/// Both lobes are deltas, sampled with probabilities `R'` and `T'`. There
/// is no `1/η²` radiance scaling: the light ends on the side it started in
/// medium-wise. Both sides behave alike.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectricBxdf {
    /// Index of refraction of the slab relative to its surroundings.
    pub eta: f32,
}

impl ThinDielectricBxdf {
    /// The slab's reflectance `R'` for a direction at `cos_theta` to the
    /// normal (either side).
    pub fn reflectance(&self, cos_theta: f32) -> f32 {
        let r = fr_dielectric(cos_theta.abs(), self.eta);
        if r < 1.0 {
            let t = 1.0 - r;
            r + t * t * r / (1.0 - r * r)
        } else {
            1.0
        }
    }
}

impl BxDF for ThinDielectricBxdf {
    /// Zero: both lobes are deltas.
    fn f(&self, _wo: Vec3, _wi: Vec3) -> Color {
        Color::ZERO
    }

    /// Specular reflection with probability `R'`, else straight
    /// transmission (`u` is not used).
    fn sample_f(&self, wo: Vec3, uc: f32, _u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let r = self.reflectance(wo.z);
        let t = 1.0 - r;
        let cos = wo.z.abs();
        if uc < r {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            Some(BsdfSample { f: Color::splat(r / cos), wi, pdf: r, specular: true, transmission: false, eta: 1.0 })
        } else if t > 0.0 {
            Some(BsdfSample { f: Color::splat(t / cos), wi: -wo, pdf: t, specular: true, transmission: true, eta: 1.0 })
        } else {
            None
        }
    }

    /// Zero: both lobes are deltas.
    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    /// Always: both lobes are deltas.
    fn is_specular(&self) -> bool {
        true
    }
}
