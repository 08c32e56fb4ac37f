//! Conductors: a perfect mirror, or a rough Torrance–Sparrow reflector with
//! a GGX distribution (PBRT 4th ed., §9.4 and §9.6).

use super::fresnel::{fr_conductor, fr_schlick};
use super::microfacet::TrowbridgeReitz;
use super::{flip_z, same_hemisphere, BsdfSample, BxDF};
use crate::color::Color;
use crate::geometry::{reflect, Vec2, Vec3};

/// How a conductor's Fresnel reflectance is computed.
///
/// `R` is the type of the colours: a [`Color`] (the default) in a
/// [`ConductorBxdf`], which holds the values at one point, and a `Texture`
/// in a material's `Conductor`, which describes a whole surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConductorFresnel<R = Color> {
    /// Exact Fresnel equations with complex index `eta + i·k` per RGB
    /// channel (e.g. gold: eta (0.143, 0.374, 1.442), k (3.983, 2.385,
    /// 1.603)).
    Complex {
        /// Real part of the index of refraction.
        eta: R,
        /// Absorption coefficient (imaginary part).
        k: R,
    },
    /// Schlick's approximation from the reflectance (colour) at normal
    /// incidence, towards white at grazing angles.
    Schlick {
        /// Reflectance at normal incidence.
        r0: R,
    },
    /// pbrt-v4's "artist" conductor given by its `reflectance`: the exact
    /// Fresnel equations with `eta = 1` and `k = 2√r / √(1 − r)`, the
    /// index whose normal-incidence reflectance `((η−1)² + k²)/((η+1)² + k²)`
    /// is exactly `r` (`ConductorMaterial::GetBxDF`; `r` clamped to
    /// [0, 0.9999]).
    Reflectance {
        /// Reflectance at normal incidence.
        r: R,
    },
}

/// pbrt-v4's complex index `(eta, k) = (1, 2√r/√(1 − r))` for a conductor
/// of normal-incidence reflectance `r` (clamped to [0, 0.9999]).
pub fn reflectance_to_complex_ior(r: Color) -> (Color, Color) {
    let r = r.clamp(Color::ZERO, Color::splat(0.9999));
    let k = 2.0 * Color::new(r.x.sqrt(), r.y.sqrt(), r.z.sqrt())
        / Color::new((1.0 - r.x).sqrt(), (1.0 - r.y).sqrt(), (1.0 - r.z).sqrt());
    (Color::ONE, k)
}

impl ConductorFresnel {
    /// Reflectance for a direction at `cos_theta` to the (micro)normal.
    #[inline]
    pub fn eval(&self, cos_theta: f32) -> Color {
        match *self {
            Self::Complex { eta, k } => fr_conductor(cos_theta.abs(), eta, k),
            Self::Schlick { r0 } => fr_schlick(cos_theta, r0),
            Self::Reflectance { r } => {
                let (eta, k) = reflectance_to_complex_ior(r);
                fr_conductor(cos_theta.abs(), eta, k)
            }
        }
    }
}

/// A conductor (metal). Smooth (`α < 1e-3`): a delta mirror of weight
/// `F(cos θo)`. Rough: the Torrance–Sparrow BRDF
/// `f = D(wm) G(wo, wi) F(wo·wm) / (4 cos θo cos θi)` with `wm` the half
/// vector, sampled by visible normals, whose reflection has the density
/// `D_wo(wm) / (4 |wo·wm|)` (PBRT 4th ed., eq. 9.28 and 9.33).
/// Two-sided: for `wo.z < 0` it reflects on the lower side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConductorBxdf {
    /// The Fresnel model.
    pub fresnel: ConductorFresnel,
    /// The microfacet distribution.
    pub distrib: TrowbridgeReitz,
}

impl ConductorBxdf {
    /// Torrance–Sparrow with both directions above the surface.
    fn f_upper(&self, wo: Vec3, wi: Vec3) -> Color {
        let (cos_o, cos_i) = (wo.z, wi.z);
        if cos_o <= 0.0 || cos_i <= 0.0 {
            return Color::ZERO;
        }
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return Color::ZERO;
        }
        let wm = wm.normalize();
        let d = self.distrib.d(wm);
        let g = self.distrib.g(wo, wi);
        self.fresnel.eval(wo.dot(wm)) * (d * g / (4.0 * cos_o * cos_i))
    }
}

impl BxDF for ConductorBxdf {
    /// BSDF value (0 for a mirror).
    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        if self.is_specular() || !same_hemisphere(wo, wi) {
            return Color::ZERO;
        }
        let (wo, wi) = if wo.z < 0.0 { (flip_z(wo), flip_z(wi)) } else { (wo, wi) };
        self.f_upper(wo, wi)
    }

    /// Mirror reflection, or a visible-normal sample reflected about `wm`
    /// (`uc` is not used).
    fn sample_f(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let lower = wo.z < 0.0;
        let wo_up = if lower { flip_z(wo) } else { wo };
        let unflip = |w: Vec3| if lower { flip_z(w) } else { w };
        if self.is_specular() {
            // Delta mirror: f = F/|cos θi| so that f·|cos θi|/pdf = F.
            let wi = Vec3::new(-wo_up.x, -wo_up.y, wo_up.z);
            let f = self.fresnel.eval(wi.z) / wi.z;
            return Some(BsdfSample { f, wi: unflip(wi), pdf: 1.0, specular: true, transmission: false, eta: 1.0 });
        }
        let wm = self.distrib.sample_wm(wo_up, u);
        let wi = reflect(wo_up, wm);
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.distrib.d_visible(wo_up, wm) / (4.0 * wo_up.dot(wm).abs());
        let f = self.f_upper(wo_up, wi);
        if pdf <= 0.0 || !pdf.is_finite() {
            return None;
        }
        Some(BsdfSample { f, wi: unflip(wi), pdf, specular: false, transmission: false, eta: 1.0 })
    }

    /// `D_wo(wm) / (4 |wo·wm|)` for the half vector (0 for a mirror).
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.is_specular() || !same_hemisphere(wo, wi) {
            return 0.0;
        }
        let (wo, wi) = if wo.z < 0.0 { (flip_z(wo), flip_z(wi)) } else { (wo, wi) };
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = wm.normalize();
        self.distrib.d_visible(wo, wm) / (4.0 * wo.dot(wm).abs())
    }

    /// Whether this is a perfect mirror.
    #[inline]
    fn is_specular(&self) -> bool {
        self.distrib.effectively_smooth()
    }

    /// Widen a near-mirror (see [`TrowbridgeReitz::regularize`]).
    fn regularize(&mut self) {
        self.distrib.regularize();
    }
}
