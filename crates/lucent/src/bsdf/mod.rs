//! BSDFs of the physically based (path) integrator: how a surface scatters
//! light, with importance sampling and exact pdfs (after PBRT 4th ed.,
//! ch. 9–10).
//!
//! A [`Bxdf`] works in the *local shading frame*: the shading normal is
//! `+z`, and both directions are unit vectors pointing away from the
//! surface. A [`Bsdf`] wraps a `Bxdf` with the frame, and takes and returns
//! world-space directions.
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

mod frame;

pub use frame::Frame;

use crate::color::Color;
use crate::geometry::{Vec2, Vec3};

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
    pub eta: f32,
}

/// A scattering function in the local shading frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bxdf {
    /// Black: absorbs everything (e.g. an emitter's surface).
    Black,
}

impl Bxdf {
    /// A Lambertian reflector with albedo `r` (each channel in [0, 1]).
    pub fn diffuse(r: Color) -> Self {
        let _ = r;
        todo!()
    }

    /// A conductor with complex index of refraction `eta + i·k` (per RGB
    /// channel) and GGX roughness `alpha` (0: a perfect mirror).
    pub fn conductor(eta: Color, k: Color, alpha: f32) -> Self {
        let _ = (eta, k, alpha);
        todo!()
    }

    /// A conductor given by its colour at normal incidence `r0` (Schlick's
    /// Fresnel approximation) and GGX roughness `alpha`.
    pub fn conductor_schlick(r0: Color, alpha: f32) -> Self {
        let _ = (r0, alpha);
        todo!()
    }

    /// A dielectric (glass) with relative index of refraction `eta` (inside
    /// over outside, the side the normal points to being outside) and GGX
    /// roughness `alpha` (0: smooth). `tint` scales transmitted light.
    pub fn dielectric(eta: f32, alpha: f32, tint: Color) -> Self {
        let _ = (eta, alpha, tint);
        todo!()
    }

    /// A diffuse base of albedo `diffuse` under a dielectric coat of index
    /// `eta` and GGX roughness `alpha` ("plastic").
    pub fn plastic(diffuse: Color, eta: f32, alpha: f32) -> Self {
        let _ = (diffuse, eta, alpha);
        todo!()
    }

    /// The classic Phong material made energy conserving: Lambertian
    /// `kd·colour`, a normalised Phong lobe `ks` with `exponent`, and a
    /// perfect mirror `kr`.
    pub fn phong(diffuse: Color, ks: f32, exponent: f32, kr: f32) -> Self {
        let _ = (diffuse, ks, exponent, kr);
        todo!()
    }

    /// BSDF value for light arriving from `wi`, leaving towards `wo`.
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        let _ = (wo, wi);
        Color::ZERO
    }

    /// Sample an incident direction for `wo`, from a 1D sample `uc` (used to
    /// pick a lobe) and a 2D sample `u`.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let _ = (wo, uc, u);
        None
    }

    /// Solid-angle pdf of sampling `wi` given `wo`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let _ = (wo, wi);
        0.0
    }

    /// Whether every lobe is a delta: light sampling cannot help.
    pub fn is_specular(&self) -> bool {
        false
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
