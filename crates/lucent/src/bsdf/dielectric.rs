//! Dielectrics (glass, water): smooth Fresnel-weighted specular reflection
//! and refraction, or rough microfacet reflection and transmission
//! (PBRT 4th ed., §9.5 and §9.7; Walter et al., "Microfacet Models for
//! Refraction through Rough Surfaces", EGSR 2007).

use super::fresnel::fr_dielectric;
use super::microfacet::TrowbridgeReitz;
use super::{same_hemisphere, BsdfSample, BxDF, Lobes, TransportMode};
use crate::color::Color;
use crate::geometry::{reflect, refract, Vec2, Vec3};

/// An interface between two dielectrics. `eta` is the relative index of
/// refraction, inside (the side opposite the normal) over outside; a `wo`
/// with `wo.z < 0` is inside and sees the index `1/eta`.
///
/// Smooth (`α < 1e-3`, or `η = 1`, where nothing bends): reflection with
/// probability `F(cos θo)` and weight `F`, refraction with probability
/// `1 − F` and weight `(1 − F)·tint/η'²`, where `η'` is the index on the
/// side of `wi` over that on the side of `wo` (the `1/η'²` is the radiance
/// compression of §9.5.2). Total internal reflection has `F = 1`.
///
/// Rough: Walter et al.'s BSDF. For reflection `wm` is the half vector and
/// `f = D G F / (4 |cos θo cos θi|)`; for transmission the generalised half
/// vector `wm ∝ η' wi + wo` gives
/// `f = D G (1 − F) |wi·wm| |wo·wm| / (|cos θi cos θo| (wi·wm + wo·wm/η')²) / η'²`
/// (Walter eq. 21, PBRT eq. 9.40). Sampling picks a visible normal, then
/// reflects with probability `F(wo·wm)` or refracts through it; the pdfs
/// are `D_wo(wm)/(4|wo·wm|)·F` and `D_wo(wm)·|wi·wm|/(wi·wm + wo·wm/η')²·(1 − F)`
/// (Walter eq. 14 and 17). `tint` scales transmitted light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricBxdf {
    /// Relative index of refraction, inside over outside.
    pub eta: f32,
    /// The microfacet distribution.
    pub distrib: TrowbridgeReitz,
    /// Colour of transmitted light.
    pub tint: Color,
}

impl DielectricBxdf {
    /// A dielectric of relative index `eta` (non-positive or NaN: 1) with
    /// roughness `distrib` and transmission `tint`.
    pub fn new(eta: f32, distrib: TrowbridgeReitz, tint: Color) -> Self {
        let eta = if eta > 0.0 && eta.is_finite() { eta } else { 1.0 };
        Self { eta, distrib, tint }
    }

    /// The generalised half vector of `(wo, wi)`, facing `+z`, with `η'`;
    /// `None` for degenerate pairs and for back-facing microfacets (those
    /// `wo` or `wi` would see from behind, which contribute nothing).
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32, bool)> {
        let (cos_o, cos_i) = (wo.z, wi.z);
        if cos_o == 0.0 || cos_i == 0.0 {
            return None;
        }
        let is_reflection = cos_o * cos_i > 0.0;
        let etap = if is_reflection {
            1.0
        } else if cos_o > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        let wm = wi * etap + wo;
        if wm.length_squared() == 0.0 {
            return None;
        }
        let mut wm = wm.normalize();
        if wm.z < 0.0 {
            wm = -wm;
        }
        if wm.dot(wi) * cos_i < 0.0 || wm.dot(wo) * cos_o < 0.0 {
            return None;
        }
        Some((wm, etap, is_reflection))
    }

    /// Walter et al.'s transmission term without tint, given the half
    /// vector; the radiance compression `1/η'²` only for `mode` radiance.
    fn ft(&self, wo: Vec3, wi: Vec3, wm: Vec3, etap: f32, t: f32, mode: TransportMode) -> f32 {
        let (dwi, dwo) = (wi.dot(wm), wo.dot(wm));
        let denom = (dwi + dwo / etap) * (dwi + dwo / etap) * wi.z * wo.z;
        let ft = self.distrib.d(wm) * t * self.distrib.g(wo, wi) * (dwi * dwo / denom).abs();
        match mode {
            TransportMode::Radiance => ft / (etap * etap),
            TransportMode::Importance => ft,
        }
    }

    /// The BSDF for transport `mode` (PBRT-v4's `DielectricBxDF::f`): for
    /// importance transport the transmission is not scaled by `1/η'²`
    /// (PBRT 4th ed., §9.5.2); the layered BxDFs need both.
    pub(crate) fn f_mode(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Color {
        if self.is_specular() {
            return Color::ZERO;
        }
        let Some((wm, etap, is_reflection)) = self.half_vector(wo, wi) else {
            return Color::ZERO;
        };
        let r = fr_dielectric(wo.dot(wm), self.eta);
        if is_reflection {
            let v = self.distrib.d(wm) * self.distrib.g(wo, wi) * r / (4.0 * wi.z * wo.z).abs();
            Color::splat(v)
        } else {
            self.tint * self.ft(wo, wi, wm, etap, 1.0 - r, mode)
        }
    }

    /// Sample reflection and/or transmission as `lobes` allows, with
    /// probabilities proportional to their Fresnel weights among the
    /// allowed lobes (PBRT-v4's `Sample_f` with `BxDFReflTransFlags`).
    pub(crate) fn sample_f_mode(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        lobes: Lobes,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let scale = |etap: f32| match mode {
            TransportMode::Radiance => 1.0 / (etap * etap),
            TransportMode::Importance => 1.0,
        };
        if self.is_specular() {
            let r = if self.eta == 1.0 { 0.0 } else { fr_dielectric(wo.z, self.eta) };
            let t = 1.0 - r;
            let (pr, pt) = lobes.weights(r, t);
            if pr + pt <= 0.0 {
                return None;
            }
            if uc < pr / (pr + pt) {
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                let f = Color::splat(r / wi.z.abs());
                return Some(BsdfSample { f, wi, pdf: pr / (pr + pt), specular: true, transmission: false, eta: 1.0 });
            }
            let (wi, etap) = refract(wo, Vec3::Z, self.eta)?;
            if wi.z == 0.0 || t <= 0.0 {
                return None;
            }
            let f = self.tint * (t / wi.z.abs() * scale(etap));
            return Some(BsdfSample { f, wi, pdf: pt / (pr + pt), specular: true, transmission: true, eta: etap });
        }
        let wm = self.distrib.sample_wm(wo, u);
        let r = fr_dielectric(wo.dot(wm), self.eta);
        let t = 1.0 - r;
        let (pr, pt) = lobes.weights(r, t);
        if pr + pt <= 0.0 {
            return None;
        }
        if uc < pr / (pr + pt) {
            let wi = reflect(wo, wm);
            if !same_hemisphere(wo, wi) {
                return None;
            }
            let pdf = self.distrib.d_visible(wo, wm) / (4.0 * wo.dot(wm).abs()) * pr / (pr + pt);
            let v = self.distrib.d(wm) * self.distrib.g(wo, wi) * r / (4.0 * wi.z * wo.z).abs();
            if pdf <= 0.0 || !pdf.is_finite() || !v.is_finite() {
                return None;
            }
            Some(BsdfSample { f: Color::splat(v), wi, pdf, specular: false, transmission: false, eta: 1.0 })
        } else {
            let (wi, etap) = refract(wo, wm, self.eta)?;
            if same_hemisphere(wo, wi) || wi.z == 0.0 {
                return None;
            }
            let (dwi, dwo) = (wi.dot(wm), wo.dot(wm));
            let dwm_dwi = dwi.abs() / ((dwi + dwo / etap) * (dwi + dwo / etap));
            let pdf = self.distrib.d_visible(wo, wm) * dwm_dwi * pt / (pr + pt);
            let f = self.tint * self.ft(wo, wi, wm, etap, t, mode);
            if pdf <= 0.0 || !pdf.is_finite() || !f.is_finite() {
                return None;
            }
            Some(BsdfSample { f, wi, pdf, specular: false, transmission: true, eta: etap })
        }
    }

    /// The pdf of [`DielectricBxdf::sample_f_mode`] restricted to `lobes`
    /// (0 when smooth).
    pub(crate) fn pdf_lobes(&self, wo: Vec3, wi: Vec3, lobes: Lobes) -> f32 {
        if self.is_specular() {
            return 0.0;
        }
        let Some((wm, etap, is_reflection)) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let r = fr_dielectric(wo.dot(wm), self.eta);
        let (pr, pt) = lobes.weights(r, 1.0 - r);
        if pr + pt <= 0.0 {
            return 0.0;
        }
        if is_reflection {
            self.distrib.d_visible(wo, wm) / (4.0 * wo.dot(wm).abs()) * pr / (pr + pt)
        } else {
            let (dwi, dwo) = (wi.dot(wm), wo.dot(wm));
            let dwm_dwi = dwi.abs() / ((dwi + dwo / etap) * (dwi + dwo / etap));
            self.distrib.d_visible(wo, wm) * dwm_dwi * pt / (pr + pt)
        }
    }
}

impl BxDF for DielectricBxdf {
    /// BSDF value (0 when smooth).
    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        self.f_mode(wo, wi, TransportMode::Radiance)
    }

    /// Sample reflection or transmission, each with its Fresnel
    /// probability.
    fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        self.sample_f_mode(wo, uc, u, TransportMode::Radiance, Lobes::ALL)
    }

    /// Solid-angle pdf of [`DielectricBxdf::sample_f`] (0 when smooth).
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.pdf_lobes(wo, wi, Lobes::ALL)
    }

    /// Whether reflection and refraction are both delta lobes.
    #[inline]
    fn is_specular(&self) -> bool {
        self.eta == 1.0 || self.distrib.effectively_smooth()
    }

    /// Widen a near-specular interface (see [`TrowbridgeReitz::regularize`]).
    fn regularize(&mut self) {
        self.distrib.regularize();
    }
}
