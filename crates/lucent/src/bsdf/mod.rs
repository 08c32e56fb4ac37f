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
//! glass after Walter et al. 2007), [`ThinDielectricBxdf`] (a thin pane),
//! [`DiffuseTransmissionBxdf`] (Lambertian reflection and transmission),
//! [`PlasticBxdf`] (diffuse under a dielectric coat, after Weidlich &
//! Wilkie 2007), the stochastic layered BxDFs [`CoatedDiffuseBxdf`] and
//! [`CoatedConductorBxdf`] (PBRT-v4's `LayeredBxDF`) and [`PhongBxdf`] (the
//! classic model made energy conserving), and glTF 2.0's
//! [`MetallicRoughnessBxdf`] (Appendix B with the KHR material extensions),
//! built on [`fresnel`] and the anisotropic GGX distribution of
//! [`microfacet`].
//!
//! Anisotropic roughness is oriented by the local frame: `x` is the
//! surface's ∂p/∂u made orthogonal to the shading normal (see
//! [`Bsdf::new`]).
//!
//! A lobe is treated as a delta when its GGX `α < 1e-3`
//! ([`microfacet::SMOOTH_ALPHA`]). All BxDFs return no sample for a `wo`
//! exactly in the tangent plane (`wo.z = 0`).

mod conductor;
mod dielectric;
mod diffuse;
mod diffuse_transmission;
pub mod fresnel;
mod layered;
mod metallic_roughness;
pub mod microfacet;
mod phong;
mod plastic;
mod sheen;
#[cfg(test)]
mod tests;
mod thin_dielectric;

pub use conductor::{reflectance_to_complex_ior, ConductorBxdf, ConductorFresnel};
pub use dielectric::DielectricBxdf;
pub use diffuse::DiffuseBxdf;
pub use diffuse_transmission::DiffuseTransmissionBxdf;
pub use layered::{CoatedConductorBxdf, CoatedDiffuseBxdf, LayeredBxdf};
pub use metallic_roughness::MetallicRoughnessBxdf;
pub use microfacet::{roughness_to_alpha, TrowbridgeReitz};
pub use phong::PhongBxdf;
pub use plastic::PlasticBxdf;
pub use thin_dielectric::ThinDielectricBxdf;

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

    /// Roughen near-specular lobes (PBRT-v4's `Regularize`, used by the
    /// path integrator's `regularize` option after the first non-specular
    /// bounce; see [`TrowbridgeReitz::regularize`]). BxDFs without a
    /// microfacet lobe are unchanged.
    fn regularize(&mut self) {}
}

/// Which quantity a BSDF transports (PBRT 4th ed., §9.5.2): radiance
/// (paths traced from the camera: the path tracer, and the camera subpaths
/// of bidirectional path tracing) or importance, its adjoint (paths traced
/// from the lights). They differ in the `1/η²` scaling of refraction; the
/// layered BxDFs also need the adjoint for the directions they sample from
/// `wi`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    /// Radiance: refraction scales by `1/η'²`.
    Radiance,
    /// Importance: no scaling.
    Importance,
}

/// Which lobes a restricted sample may come from (PBRT-v4's
/// `BxDFReflTransFlags`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Lobes {
    reflection: bool,
    transmission: bool,
}

impl Lobes {
    /// Both.
    pub(crate) const ALL: Self = Self { reflection: true, transmission: true };
    /// Reflection only.
    pub(crate) const REFLECTION: Self = Self { reflection: true, transmission: false };
    /// Transmission only.
    pub(crate) const TRANSMISSION: Self = Self { reflection: false, transmission: true };

    /// The lobe weights `(r, t)` with the excluded ones set to 0.
    #[inline]
    pub(crate) fn weights(self, r: f32, t: f32) -> (f32, f32) {
        (if self.reflection { r } else { 0.0 }, if self.transmission { t } else { 0.0 })
    }
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
    /// A thin dielectric slab: specular reflection and straight
    /// transmission.
    ThinDielectric(ThinDielectricBxdf),
    /// Lambertian reflection and transmission.
    DiffuseTransmission(DiffuseTransmissionBxdf),
    /// A diffuse base under a dielectric coat, evaluated stochastically.
    CoatedDiffuse(CoatedDiffuseBxdf),
    /// A conductor under a dielectric coat, evaluated stochastically.
    CoatedConductor(CoatedConductorBxdf),
    /// glTF 2.0's metallic-roughness BRDF with the KHR material extensions.
    MetallicRoughness(MetallicRoughnessBxdf),
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
        Self::Dielectric(DielectricBxdf::new(eta, TrowbridgeReitz::new(alpha), tint))
    }

    /// A thin dielectric slab of index `eta` (non-positive or NaN: 1).
    pub fn thin_dielectric(eta: f32) -> Self {
        let eta = if eta > 0.0 && eta.is_finite() { eta } else { 1.0 };
        Self::ThinDielectric(ThinDielectricBxdf { eta })
    }

    /// Lambertian reflectance `r` and transmittance `t`.
    pub fn diffuse_transmission(r: Color, t: Color) -> Self {
        Self::DiffuseTransmission(DiffuseTransmissionBxdf { r, t })
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
    #[inline]
    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        // The most common BxDF in place; the rest out of line.
        match self {
            Self::Diffuse(b) => b.f(wo, wi),
            _ => self.f_any(wo, wi),
        }
    }

    /// Sample an incident direction for `wo`, from a 1D sample `uc` (used to
    /// pick a lobe) and a 2D sample `u`.
    #[inline]
    fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        match self {
            Self::Diffuse(b) => b.sample_f(wo, uc, u),
            _ => self.sample_f_any(wo, uc, u),
        }
    }

    /// Solid-angle pdf of sampling `wi` given `wo`.
    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Self::Diffuse(b) => b.pdf(wo, wi),
            _ => self.pdf_any(wo, wi),
        }
    }

    /// Whether every lobe is a delta: light sampling cannot help.
    #[inline]
    fn is_specular(&self) -> bool {
        match self {
            Self::Black => false,
            Self::Diffuse(b) => b.is_specular(),
            Self::Conductor(b) => b.is_specular(),
            Self::Dielectric(b) => b.is_specular(),
            Self::Plastic(b) => b.is_specular(),
            Self::Phong(b) => b.is_specular(),
            Self::ThinDielectric(b) => b.is_specular(),
            Self::DiffuseTransmission(b) => b.is_specular(),
            Self::CoatedDiffuse(b) => b.is_specular(),
            Self::CoatedConductor(b) => b.is_specular(),
            Self::MetallicRoughness(b) => b.is_specular(),
        }
    }

    /// Roughen near-specular lobes.
    fn regularize(&mut self) {
        match self {
            Self::Black
            | Self::Diffuse(_)
            | Self::Phong(_)
            | Self::ThinDielectric(_)
            | Self::DiffuseTransmission(_) => {}
            Self::Conductor(b) => b.regularize(),
            Self::Dielectric(b) => b.regularize(),
            Self::Plastic(b) => b.regularize(),
            Self::CoatedDiffuse(b) => b.regularize(),
            Self::CoatedConductor(b) => b.regularize(),
            Self::MetallicRoughness(b) => b.regularize(),
        }
    }
}

/// The out-of-line halves of [`Bxdf`]'s [`BxDF`] methods: every kind but
/// the diffuse one, which the methods evaluate in place.
impl Bxdf {
    /// [`BxDF::f`] of any kind.
    fn f_any(&self, wo: Vec3, wi: Vec3) -> Color {
        match self {
            Self::Black => Color::ZERO,
            Self::Diffuse(b) => b.f(wo, wi),
            Self::Conductor(b) => b.f(wo, wi),
            Self::Dielectric(b) => b.f(wo, wi),
            Self::Plastic(b) => b.f(wo, wi),
            Self::Phong(b) => b.f(wo, wi),
            Self::ThinDielectric(b) => b.f(wo, wi),
            Self::DiffuseTransmission(b) => b.f(wo, wi),
            Self::CoatedDiffuse(b) => b.f(wo, wi),
            Self::CoatedConductor(b) => b.f(wo, wi),
            Self::MetallicRoughness(b) => b.f(wo, wi),
        }
    }

    /// [`BxDF::sample_f`] of any kind.
    fn sample_f_any(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        match self {
            Self::Black => None,
            Self::Diffuse(b) => b.sample_f(wo, uc, u),
            Self::Conductor(b) => b.sample_f(wo, uc, u),
            Self::Dielectric(b) => b.sample_f(wo, uc, u),
            Self::Plastic(b) => b.sample_f(wo, uc, u),
            Self::Phong(b) => b.sample_f(wo, uc, u),
            Self::ThinDielectric(b) => b.sample_f(wo, uc, u),
            Self::DiffuseTransmission(b) => b.sample_f(wo, uc, u),
            Self::CoatedDiffuse(b) => b.sample_f(wo, uc, u),
            Self::CoatedConductor(b) => b.sample_f(wo, uc, u),
            Self::MetallicRoughness(b) => b.sample_f(wo, uc, u),
        }
    }

    /// [`BxDF::pdf`] of any kind.
    fn pdf_any(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Self::Black => 0.0,
            Self::Diffuse(b) => b.pdf(wo, wi),
            Self::Conductor(b) => b.pdf(wo, wi),
            Self::Dielectric(b) => b.pdf(wo, wi),
            Self::Plastic(b) => b.pdf(wo, wi),
            Self::Phong(b) => b.pdf(wo, wi),
            Self::ThinDielectric(b) => b.pdf(wo, wi),
            Self::DiffuseTransmission(b) => b.pdf(wo, wi),
            Self::CoatedDiffuse(b) => b.pdf(wo, wi),
            Self::CoatedConductor(b) => b.pdf(wo, wi),
            Self::MetallicRoughness(b) => b.pdf(wo, wi),
        }
    }
}

impl Bxdf {
    /// The factor by which radiance transport scales this BxDF's value for
    /// the local pair (`wo`, `wi`) relative to importance transport:
    /// `1/η'²` for a pair on opposite sides of a refracting interface
    /// (PBRT 4th ed. §9.5.2: radiance is compressed into a smaller solid
    /// angle on entering a denser medium; importance is not), with
    /// `η' = η` when `wo` is on the outside (`wo.z > 0`) and `1/η`
    /// otherwise; 1 for every other pair and BxDF. The BxDFs of this
    /// module compute radiance transport; importance transport divides by
    /// this ([`Bsdf::f_mode`]).
    #[inline]
    pub fn radiance_scale(&self, wo: Vec3, wi: Vec3) -> f32 {
        let eta = match self {
            Self::Dielectric(b) => b.eta,
            Self::MetallicRoughness(b) => b.refraction_eta(),
            _ => return 1.0,
        };
        if wo.z * wi.z >= 0.0 || eta == 1.0 {
            return 1.0;
        }
        let etap = if wo.z > 0.0 { eta } else { 1.0 / eta };
        1.0 / (etap * etap)
    }

    /// Whether [`BxDF::f`] for the local pair (`wo`, `wi`) costs more than
    /// a shadow ray, so that a light sample is better tested for
    /// visibility before the BSDF is evaluated: true for the coated BxDFs,
    /// whose `f` and `pdf` are random walks through the layers (see
    /// [`CoatedDiffuseBxdf`]), on a pair that may reflect; false for every
    /// other BxDF, and for a coated pair on opposite sides of the surface
    /// (they reflect only: `f` is 0 there without a walk). Either order
    /// gives the same value: a walk's random numbers are a hash of its
    /// pair.
    #[inline]
    pub fn f_costs_more_than_a_ray(&self, wo: Vec3, wi: Vec3) -> bool {
        matches!(self, Self::CoatedDiffuse(_) | Self::CoatedConductor(_)) && same_hemisphere(wo, wi)
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
    /// `bxdf` on a surface with unit shading normal `ns` and tangent
    /// `dpdu` (∂p/∂u, any length): the local `x` axis is `dpdu` made
    /// orthogonal to `ns` by Gram–Schmidt, `y = ns × x`, so anisotropic
    /// roughness follows the surface's `u` direction (PBRT-v4's
    /// `BSDF(ns, dpdus)`). A `dpdu` that is zero, not finite or parallel to
    /// `ns` falls back to an arbitrary tangent ([`Bsdf::from_normal`]).
    #[inline]
    pub fn new(ns: Vec3, dpdu: Vec3, bxdf: Bxdf) -> Self {
        Self { frame: shading_frame(ns, dpdu), bxdf }
    }

    /// `bxdf` on a surface with unit shading normal `ns` and an arbitrary
    /// tangent: enough for isotropic BxDFs.
    pub fn from_normal(ns: Vec3, bxdf: Bxdf) -> Self {
        Self { frame: Frame::from_z(ns), bxdf }
    }

    /// The diffuse `lobe` on a surface with unit shading normal `ns` and
    /// tangent `dpdu`, its frame left unfinished: [`Bsdf::new`]'s
    /// Gram–Schmidt (a square root and a division, one after the other) is
    /// left to the path integrator's diffuse scatter kernel, which makes the
    /// frames of all its lanes at once with [`shading_frame`]'s operations.
    ///
    /// Until then the frame's `z` is `ns`, its `x` holds `dpdu` as given and
    /// its `y` is zero, which no finished frame has
    /// ([`Bsdf::frame_pending`]). The diffuse lobe's value and pdf read only
    /// the local `z` of the two directions (their cosines with `ns`), so
    /// [`Bsdf::f`] and [`Bsdf::pdf`] are already exact on it; sampling needs
    /// the finished frame and must not be asked of it.
    #[inline]
    pub(crate) fn diffuse_unframed(ns: Vec3, dpdu: Vec3, lobe: DiffuseBxdf) -> Self {
        Self { frame: Frame { x: dpdu, y: Vec3::ZERO, z: ns }, bxdf: Bxdf::Diffuse(lobe) }
    }

    /// Whether the frame is unfinished ([`Bsdf::diffuse_unframed`]): its
    /// `x` is the surface's ∂p/∂u as given.
    #[inline]
    pub(crate) fn frame_pending(&self) -> bool {
        self.frame.y == Vec3::ZERO
    }

    /// The shading frame (`z` is the shading normal).
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// Roughen near-specular lobes (see [`BxDF::regularize`]).
    pub fn regularize(&mut self) {
        self.bxdf.regularize();
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
        debug_assert!(!self.frame_pending(), "sampling a BSDF whose frame is unfinished");
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

    /// [`Bsdf::f`] for the quantity `mode` transports: for importance, the
    /// adjoint BSDF `f*(wo, wi) = f(wi, wo)`, which for the reciprocal
    /// BxDFs here differs from `f(wo, wi)` only by the `η'²` of
    /// refraction ([`Bxdf::radiance_scale`]; Veach 1997, §5.2).
    #[inline]
    pub fn f_mode(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Color {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let f = self.bxdf.f(o, i);
        match mode {
            TransportMode::Radiance => f,
            TransportMode::Importance => f / self.bxdf.radiance_scale(o, i),
        }
    }

    /// [`Bsdf::sample_f`] for the quantity `mode` transports: the same
    /// direction and pdf, and for importance the adjoint's value (see
    /// [`Bsdf::f_mode`]).
    #[inline]
    pub fn sample_f_mode(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        debug_assert!(!self.frame_pending(), "sampling a BSDF whose frame is unfinished");
        let o = self.frame.to_local(wo);
        let mut s = self.bxdf.sample_f(o, uc, u)?;
        if mode == TransportMode::Importance {
            s.f /= self.bxdf.radiance_scale(o, s.wi);
        }
        s.wi = self.frame.from_local(s.wi);
        Some(s)
    }
}

/// The orthonormal frame with normal `ns` and first tangent `dpdu` made
/// orthogonal to it (Gram–Schmidt), or an arbitrary tangent when `dpdu` is
/// unusable.
#[inline]
pub fn shading_frame(ns: Vec3, dpdu: Vec3) -> Frame {
    let x = dpdu - ns * ns.dot(dpdu);
    let len2 = x.length_squared();
    // Reject tangents (nearly) parallel to ns: their direction is noise.
    if !len2.is_finite() || len2 <= 1e-12 * dpdu.length_squared() {
        return Frame::from_z(ns);
    }
    let x = x / len2.sqrt();
    Frame { x, y: ns.cross(x), z: ns }
}
