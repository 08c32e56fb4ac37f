//! BSDFs of the physically based (path) integrator: how a surface scatters
//! light, with importance sampling and exact pdfs (after PBRT 4th ed.,
//! ch. 9–10).
//!
//! A [`Bxdf`] works in the *local shading frame*: the shading normal is
//! `+z`, and both directions are unit vectors pointing away from the
//! surface. A [`Bsdf`] wraps a `Bxdf` with the frame, and takes and returns
//! world-space directions.
//!
//! Every BxDF implements the [`BxDF`] trait (`f`, `sample_f`, `pdf`,
//! `is_specular`, all with the same signatures), and the enum [`Bxdf`]
//! dispatches to them.
//!
//! Conventions every BxDF follows:
//! * `f(wo, wi)` is the BSDF value, *without* the cosine factor.
//! * `pdf(wo, wi)` is the solid-angle density with which `sample_f(wo, ..)`
//!   produces `wi`; it is 0 for directions that only a delta lobe reaches.
//! * `sample_f` returns `f` (for delta lobes: the delta's weight, so that
//!   `f · |cos θi| / pdf` is the throughput factor) and the pdf of the
//!   sampled direction; delta samples have `specular = true`.
//! * Reflection-only BxDFs are two-sided: for `wo.z < 0` they reflect on the
//!   lower side (PBRT's `SameHemisphere`).
//! * Radiance transport: refraction scales `f` by `1/η²` (PBRT §9.5.2).

//!
//! The BxDFs, one file each: [`DiffuseBxdf`] (Lambert), [`ConductorBxdf`]
//! (mirror or GGX Torrance–Sparrow), [`DielectricBxdf`] (smooth or rough
//! glass after Walter et al. 2007), [`PlasticBxdf`] (diffuse under a
//! dielectric coat, after Weidlich & Wilkie 2007) and [`PhongBxdf`] (the
//! classic model made energy conserving), built on [`fresnel`] and the GGX
//! distribution of [`microfacet`].
//!
//! A lobe is treated as a delta when its GGX `α < 1e-3`
//! ([`microfacet::SMOOTH_ALPHA`]). All BxDFs return no sample for a `wo`
//! exactly in the tangent plane (`wo.z = 0`).

mod conductor;
mod dielectric;
mod diffuse;
pub mod fresnel;
pub mod microfacet;
mod phong;
mod plastic;
#[cfg(test)]
mod tests;

pub use conductor::{ConductorBxdf, ConductorFresnel};
pub use dielectric::DielectricBxdf;
pub use diffuse::DiffuseBxdf;
pub use microfacet::TrowbridgeReitz;
pub use phong::PhongBxdf;
pub use plastic::PlasticBxdf;

use crate::color::Color;
use crate::geometry::{Frame, Vec2, Vec3};

/// A direction sampled from a BSDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// BSDF value for the pair (for a delta lobe, its weight).
    pub f: Color,
    /// The sampled incident direction (local frame for [`Bxdf`], world
    /// space for [`Bsdf`]).
    pub wi: Vec3,
    /// Solid-angle pdf of `wi` (for a delta lobe, its discrete probability).
    pub pdf: f32,
    /// Whether `wi` was chosen from a delta (perfectly specular) lobe.
    pub specular: bool,
    /// Whether `wi` is on the other side of the surface from `wo`.
    pub transmission: bool,
    /// Relative index of refraction across the surface for a transmission
    /// (η_i/η_t as in PBRT), 1 otherwise. Used by Russian roulette.
    ///
    /// Precisely: the index of the medium on the side of `wi` over that on
    /// the side of `wo` (PBRT-v4's `etap`), e.g. 1.5 for light entering
    /// glass of index 1.5 from the outside (`wo` outside, `wi` inside).
    pub eta: f32,
}

/// The interface of every scattering function, in the local shading frame
/// (PBRT 4th ed., §9.1.2, `BxDF`). See the module documentation for the
/// conventions.
pub trait BxDF {
    /// BSDF value for light arriving from `wi`, leaving towards `wo`
    /// (without the cosine factor; 0 for delta lobes).
    fn f(&self, wo: Vec3, wi: Vec3) -> Color;

    /// Sample an incident direction for `wo`, from a 1D sample `uc` (used to
    /// pick a lobe; BxDFs with one lobe ignore it) and a 2D sample `u`.
    /// `None` when no direction is produced.
    fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample>;

    /// Solid-angle pdf with which [`BxDF::sample_f`] produces `wi` given
    /// `wo` (0 for directions that only a delta lobe reaches).
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32;

    /// Whether every lobe is a delta: light sampling cannot help.
    fn is_specular(&self) -> bool;
}

/// A scattering function in the local shading frame: one of the BxDFs of
/// this module, dispatched through [`BxDF`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bxdf {
    /// Black: absorbs everything (e.g. an emitter's surface).
    Black,
    /// Lambertian reflection.
    Diffuse(DiffuseBxdf),
    /// A metal: mirror or rough.
    Conductor(ConductorBxdf),
    /// Glass: smooth or rough reflection and transmission.
    Dielectric(DielectricBxdf),
    /// A diffuse base under a dielectric coat.
    Plastic(PlasticBxdf),
    /// The energy-conserving classic Phong model.
    Phong(PhongBxdf),
}

impl Bxdf {
    /// A Lambertian reflector with albedo `r` (each channel in [0, 1]).
    pub fn diffuse(r: Color) -> Self {
        Self::Diffuse(DiffuseBxdf { r })
    }

    /// A conductor with complex index of refraction `eta + i·k` (per RGB
    /// channel) and GGX roughness `alpha` (0: a perfect mirror).
    pub fn conductor(eta: Color, k: Color, alpha: f32) -> Self {
        Self::Conductor(ConductorBxdf {
            fresnel: ConductorFresnel::Complex { eta, k },
            distrib: TrowbridgeReitz::new(alpha),
        })
    }

    /// A conductor given by its colour at normal incidence `r0` (Schlick's
    /// Fresnel approximation) and GGX roughness `alpha`.
    pub fn conductor_schlick(r0: Color, alpha: f32) -> Self {
        Self::Conductor(ConductorBxdf {
            fresnel: ConductorFresnel::Schlick { r0 },
            distrib: TrowbridgeReitz::new(alpha),
        })
    }

    /// A dielectric (glass) with relative index of refraction `eta` (inside
    /// over outside, the side the normal points to being outside) and GGX
    /// roughness `alpha` (0: smooth). `tint` scales transmitted light.
    /// A non-positive or NaN `eta` is taken as 1 (an invisible interface).
    pub fn dielectric(eta: f32, alpha: f32, tint: Color) -> Self {
        let eta = if eta > 0.0 && eta.is_finite() { eta } else { 1.0 };
        Self::Dielectric(DielectricBxdf { eta, distrib: TrowbridgeReitz::new(alpha), tint })
    }

    /// A diffuse base of albedo `diffuse` under a dielectric coat of index
    /// `eta` and GGX roughness `alpha` ("plastic").
    pub fn plastic(diffuse: Color, eta: f32, alpha: f32) -> Self {
        Self::Plastic(PlasticBxdf::new(diffuse, eta, TrowbridgeReitz::new(alpha)))
    }

    /// The classic Phong material made energy conserving: Lambertian
    /// `kd·colour`, a normalised Phong lobe `ks` with `exponent`, and a
    /// perfect mirror `kr`.
    pub fn phong(diffuse: Color, ks: f32, exponent: f32, kr: f32) -> Self {
        Self::Phong(PhongBxdf::new(diffuse, ks, exponent, kr))
    }
}

impl BxDF for Bxdf {
    /// BSDF value for light arriving from `wi`, leaving towards `wo`.
    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        match self {
            Self::Black => Color::ZERO,
            Self::Diffuse(b) => b.f(wo, wi),
            Self::Conductor(b) => b.f(wo, wi),
            Self::Dielectric(b) => b.f(wo, wi),
            Self::Plastic(b) => b.f(wo, wi),
            Self::Phong(b) => b.f(wo, wi),
        }
    }

    /// Sample an incident direction for `wo`, from a 1D sample `uc` (used to
    /// pick a lobe) and a 2D sample `u`.
    fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        match self {
            Self::Black => None,
            Self::Diffuse(b) => b.sample_f(wo, uc, u),
            Self::Conductor(b) => b.sample_f(wo, uc, u),
            Self::Dielectric(b) => b.sample_f(wo, uc, u),
            Self::Plastic(b) => b.sample_f(wo, uc, u),
            Self::Phong(b) => b.sample_f(wo, uc, u),
        }
    }

    /// Solid-angle pdf of sampling `wi` given `wo`.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Self::Black => 0.0,
            Self::Diffuse(b) => b.pdf(wo, wi),
            Self::Conductor(b) => b.pdf(wo, wi),
            Self::Dielectric(b) => b.pdf(wo, wi),
            Self::Plastic(b) => b.pdf(wo, wi),
            Self::Phong(b) => b.pdf(wo, wi),
        }
    }

    /// Whether every lobe is a delta: light sampling cannot help.
    fn is_specular(&self) -> bool {
        match self {
            Self::Black => false,
            Self::Diffuse(b) => b.is_specular(),
            Self::Conductor(b) => b.is_specular(),
            Self::Dielectric(b) => b.is_specular(),
            Self::Plastic(b) => b.is_specular(),
            Self::Phong(b) => b.is_specular(),
        }
    }
}

/// Whether two local directions are strictly on the same side of the
/// surface.
#[inline]
pub(crate) fn same_hemisphere(a: Vec3, b: Vec3) -> bool {
    a.z * b.z > 0.0
}

/// Mirror a local direction in the tangent plane (`z → −z`): how the
/// two-sided reflection-only BxDFs move a lower-side query to the upper
/// side (isotropic BxDFs are unchanged by it).
#[inline]
pub(crate) fn flip_z(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

/// Evaluate a reflection-only BxDF's value or pdf two-sidedly: `f_upper`
/// is the quantity for `wo` above the surface; a pair below is mirrored up,
/// a pair on opposite sides gets zero (`T::default()`).
#[inline]
pub(crate) fn two_sided<T: Default>(wo: Vec3, wi: Vec3, f_upper: impl Fn(Vec3, Vec3) -> T) -> T {
    if !same_hemisphere(wo, wi) {
        T::default()
    } else if wo.z < 0.0 {
        f_upper(flip_z(wo), flip_z(wi))
    } else {
        f_upper(wo, wi)
    }
}

/// A [`Bxdf`] placed on a surface: the shading frame and the geometric
/// normal. Directions are world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bsdf {
    frame: Frame,
    bxdf: Bxdf,
}

impl Bsdf {
    /// `bxdf` on a surface with unit shading normal `ns`.
    pub fn new(ns: Vec3, bxdf: Bxdf) -> Self {
        Self { frame: Frame::from_z(ns), bxdf }
    }

    /// The BxDF.
    pub fn bxdf(&self) -> &Bxdf {
        &self.bxdf
    }

    /// BSDF value for world-space `wo`, `wi`.
    #[inline]
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        self.bxdf.f(self.frame.to_local(wo), self.frame.to_local(wi))
    }

    /// Sample a world-space incident direction.
    #[inline]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let mut s = self.bxdf.sample_f(self.frame.to_local(wo), uc, u)?;
        s.wi = self.frame.from_local(s.wi);
        Some(s)
    }

    /// Solid-angle pdf of world-space `wi` given `wo`.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.bxdf.pdf(self.frame.to_local(wo), self.frame.to_local(wi))
    }

    /// Whether every lobe is a delta.
    #[inline]
    pub fn is_specular(&self) -> bool {
        self.bxdf.is_specular()
    }
}
