//! glTF 2.0's metallic-roughness BRDF with the Khronos material extensions:
//! [`MetallicRoughnessBxdf`], whose documentation gives the model, the
//! specification sections it follows and where it departs from the
//! informative sample implementation.

use super::fresnel::fr_schlick;
use super::microfacet::TrowbridgeReitz;
use super::{flip_z, sheen, BsdfSample, BxDF};
use crate::color::Color;
use crate::geometry::{reflect, refract, Vec2, Vec3};
use crate::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use rayon::prelude::*;
use std::f32::consts::{FRAC_1_PI, PI};
use std::sync::OnceLock;

/// glTF 2.0's metallic-roughness BRDF (glTF 2.0 specification, Appendix B,
/// "BRDF Implementation") with the Khronos material extensions
/// `KHR_materials_ior`, `KHR_materials_specular`,
/// `KHR_materials_transmission` (with `KHR_materials_volume`'s refraction),
/// `KHR_materials_clearcoat` and `KHR_materials_sheen`.
///
/// # The model
///
/// Appendix B builds the material from two BRDFs and two mixing operators
/// (§B.2 "Material Structure", and the informative sample implementation's
/// §B.3.2 "Specular BRDF", §B.3.3 "Diffuse BRDF", §B.3.4 "Fresnel" and
/// §B.3.5 "Metal BRDF and Dielectric BRDF"):
///
/// * `specular_brdf(α) = D G / (4 |cos θo| |cos θi|)` with the GGX
///   distribution `D` and the height-correlated Smith masking-shadowing `G`
///   (lucent's [`TrowbridgeReitz`]), `α = roughness²`;
/// * `diffuse_brdf(c) = c/π`;
/// * `conductor_fresnel(f0, bsdf) = bsdf · (f0 + (1 − f0)(1 − |V·H|)⁵)`;
/// * `fresnel_mix(ior, base, layer) = mix(base, layer, F)` with Schlick's
///   `F = f0 + (1 − f0)(1 − |V·H|)⁵` and `f0 = ((ior − 1)/(ior + 1))²`;
///
/// and `material = mix(dielectric_brdf, metal_brdf, metallic)` with
/// `metal_brdf = conductor_fresnel(baseColor, specular_brdf(α))` and
/// `dielectric_brdf = fresnel_mix(ior, diffuse_brdf(baseColor), specular_brdf(α))`.
///
/// The extensions change it as follows:
///
/// * `KHR_materials_ior` ("Implementation"): `f0` from `ior` (1.5 gives
///   0.04). 0 and ∞ are allowed and give `f0 = 1`.
/// * `KHR_materials_specular` ("Implementation"): the dielectric Fresnel
///   becomes `F_d = specular · (f0c + (1 − f0c)(1 − |V·H|)⁵)` with
///   `f0c = min(f0 · specularColor, 1)` (RGB), the layer is weighted by
///   `F_d` and the base by `1 − max(F_d)` (its largest channel).
/// * `KHR_materials_transmission` ("Transmission BTDF"): the dielectric's
///   base becomes `mix(diffuse_brdf(baseColor), specular_btdf(α) · baseColor,
///   transmission)`. Thin-walled (the extension alone), `specular_btdf` is
///   the specular lobe mirrored to the other side (its half vector is that
///   of `wo` and `wi` mirrored, "Implementation Notes"), a straight-through
///   delta when smooth; no `1/η²`. With `KHR_materials_volume` (a
///   thickness above 0, [`MetallicRoughnessBxdf::thin`] false) light
///   refracts by `ior`: Walter et al.'s microfacet BTDF, as
///   [`super::DielectricBxdf`], with the radiance compression `1/η'²`.
/// * `KHR_materials_sheen` ("Sheen layering"): `sheen_material =
///   sheenColor · f_sheen + material · S` with the Charlie sheen `f_sheen`
///   and the albedo scaling
///   `S = min(1 − max(sheenColor) E(|cos θo|), 1 − max(sheenColor) E(|cos θi|))`,
///   `E` the Charlie lobe's directional albedo, computed numerically once
///   (see the `sheen` module). Where the fitted Charlie visibility gains
///   energy (`E > 1`: sheen `α` below about 0.07 at grazing angles) the
///   lobe is divided by `max(1, E(|cos θo|), E(|cos θi|))` and `E` is
///   taken as 1.
/// * `KHR_materials_clearcoat` ("Layering"): `fresnel_coat(ior = 1.5,
///   weight = clearcoat, base = sheen_material, layer = specular_brdf(
///   clearcoatRoughness²))`, Schlick with `f0 = 0.04` at the shading normal
///   (there is no separate coat normal here).
///
/// # Energy conservation and reciprocity
///
/// Any implementation adhering to the mixing rules conforms, and in a
/// physically accurate simulation the BRDF "MUST be positive, reciprocal,
/// and energy conserving" (§B.2.4 "Complete Model"). The sample
/// implementation is informative, and the specification says that its
/// `fresnel_mix` breaks energy conservation, pointing to Kulla & Conty's
/// albedo scaling as a remedy (§B.3.6.3 "Coupling Diffuse and Specular
/// Reflection"). Taken literally, weighting the diffuse base by
/// `1 − F(V·H)` reflects more than it receives at grazing incidence (a
/// smooth white dielectric at `cos θo = 0.1` reflects `F(0.1) ≈ 0.61`
/// specularly and 0.94 diffusely), and `fresnel_coat`'s `F(N·V)` is not
/// reciprocal. Lucent keeps every layer's own lobe as
/// specified — Fresnel at the microfacet normal, `F(V·H)` — and weights what
/// lies *under* a layer by that layer's directional reflectance
/// `R(μ) = f0 + (1 − f0) W(μ, α)`, where `W(μ, α)` is Schlick's `(1 − |V·H|)⁵`
/// averaged over the microfacet normals visible from a direction at
/// `cos θ = μ` (tabulated once, at first use; `(1 − μ)⁵` when smooth):
///
/// * the diffuse lobe under the specular layer gets Kulla & Conty's
///   `(1 − R(cos θo)) (1 − R(cos θi)) / (1 − R̄)` with
///   `R = specular (max(f0c) + (1 − max(f0c)) W)` and `R̄ = ∫ R(μ) 2μ dμ`:
///   for a white base its albedo is exactly `1 − R(cos θo)`;
/// * everything under the clearcoat is weighted by
///   `C = 1 − max(R_c(cos θo), R_c(cos θi))`,
///   `R_c = clearcoat (0.04 + 0.96 W(·, α_c))`, the `min` form that
///   `KHR_materials_sheen` uses for its albedo scaling (the base under the
///   coat is not Lambertian, so Kulla & Conty's form could exceed 1 there).
///
/// Both are reciprocal. For smooth layers `R(μ) = F(μ)`: the coat weights
/// its base by `1 − clearcoat F(N·V)`, as `fresnel_coat` does, wherever
/// `F(cos θi) ≤ F(cos θo)`, and a smooth white dielectric reflects exactly
/// all light, `F` specularly and `1 − F` diffusely. And they bound the
/// albedo by 1: a layer's lobe reflects at most `R(cos θo)` (the Fresnel
/// reflectance of the visible microfacets, less what masking and shadowing
/// lose), and the base gets at most `1 − R(cos θo)`. With `specular = 0`
/// the diffuse lobe is exactly `baseColor/π`. The specular transmission lobe
/// is weighted by `1 − max F_d(V·H)` at its own (generalised) half vector,
/// so that reflection and transmission split each microfacet's light as the
/// [`super::DielectricBxdf`] does.
///
/// The complete BSDF, with `m = metallic`, `t = transmission`, `c` the
/// clearcoat weight, `H` the half vector of the pair and `H_t` that of the
/// transmission (thin: of `wo` and `wi` mirrored; refractive: Walter's
/// generalised one):
///
/// ```text
/// f = c F_c(V·H) f_spec(α_c)
///   + C · [ sheenColor f_sheen + S · ( (1 − m) F_d(V·H) f_spec(α)
///                                     + m F_s(baseColor, V·H) f_spec(α)
///                                     + (1 − m)(1 − t) (1 − R(θo))(1 − R(θi))/(1 − R̄) baseColor/π
///                                     + (1 − m) t (1 − max F_d(V·H_t)) baseColor f_btdf(α) ) ]
/// C = 1 − max(R_c(θo), R_c(θi)),   S = 1 − max(sheenColor) max(E(θo), E(θi))
/// ```
///
/// Reflection is two-sided (a `wo` below the surface reflects on the lower
/// side). For refractive transmission `F_d` sees the interface from the
/// side of `wo`: from the denser side it is evaluated at the cosine in the
/// rarer medium (Snell's law), and is 1 beyond the critical angle (total
/// internal reflection), so that it is the same for a pair seen from either
/// end; there (for a refracting material seen from inside) the diffuse
/// lobe is weighted by `1 − max(F_d(cos θo), F_d(cos θi))` instead of the
/// albedo scaling, whose table knows no total internal reflection. The
/// sheen and the coat are symmetric in the two sides.
///
/// # Smooth surfaces
///
/// A lobe with GGX `α < 1e-3` ([`super::microfacet::SMOOTH_ALPHA`]) is a
/// delta, its weight the rough lobe's limit: the mirror reflection
/// `C S ((1 − m) F_d(cos θo) + m F_s(baseColor, cos θo))` (plus
/// `c F_c(cos θo)` for a smooth coat), the straight thin transmission
/// `C S (1 − m) t (1 − max F_d(cos θo)) baseColor`, the refraction the same
/// with `F_d` at the interface, over `η'²`. Refraction with `ior = 1` bends
/// nothing and is a straight delta at any roughness.
///
/// # Sampling
///
/// One-sample MIS over the lobes (Veach's thesis, 1997, §9.2.4, "the
/// one-sample model"; as PBRT 3rd ed.'s `BSDF::Sample_f`, which averages
/// its BxDFs' pdfs): a lobe is chosen with probability proportional to an estimate of
/// its weight for `wo` (see [`MetallicRoughnessBxdf::lobe_probabilities`]),
/// sampled — visible GGX normals for the coat, the specular reflection and
/// the transmission, cosine-weighted for the diffuse lobe, uniform on the
/// hemisphere for the sheen — and the sample carries the full `f` and the
/// mixture pdf `Σ pᵢ pdfᵢ` over the non-delta lobes, which
/// [`BxDF::pdf`] returns too. A delta sample has `f = weight/|cos θi|` and
/// `pdf = p` (the probability of the delta lobes in its direction), as
/// [`super::DielectricBxdf`], so that `f |cos θi| / pdf = weight / p`.
///
/// # Parameters
///
/// All parameters are as glTF gives them, textures already applied, except
/// the roughnesses, which are GGX `α = roughness²`. Out-of-range values are
/// clamped where they are used (weights and colours to [0, 1]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughnessBxdf {
    /// Base colour, linear RGB in [0, 1] (`baseColorFactor` × texture ×
    /// vertex colour): the diffuse albedo, the metal's `f0`, and the tint of
    /// transmitted light.
    pub base_color: Color,
    /// `metallic` in [0, 1]: the mix between the dielectric and the metal.
    pub metallic: f32,
    /// GGX `α = roughness²` of the specular reflection and transmission.
    pub alpha: f32,
    /// `KHR_materials_ior` (default 1.5): the dielectric's `f0` and, for
    /// refractive transmission, the index inside.
    pub ior: f32,
    /// `KHR_materials_specular`'s `specularFactor` (default 1): the weight
    /// of the dielectric's specular layer.
    pub specular: f32,
    /// `KHR_materials_specular`'s `specularColorFactor` (default white):
    /// scales the dielectric's `f0` (the product clamped to 1).
    pub specular_color: Color,
    /// `KHR_materials_transmission`'s `transmissionFactor` (default 0): the
    /// fraction of the dielectric's non-reflected light transmitted instead
    /// of diffusely reflected.
    pub transmission: f32,
    /// Thin-walled transmission (no refraction: `KHR_materials_volume`
    /// absent or of thickness 0) when true; refraction by `ior` when false.
    pub thin: bool,
    /// `KHR_materials_clearcoat`'s `clearcoatFactor` (default 0).
    pub clearcoat: f32,
    /// GGX `α` of the clearcoat, `clearcoatRoughness²`.
    pub clearcoat_alpha: f32,
    /// `KHR_materials_sheen`'s `sheenColorFactor` (default black: no sheen).
    pub sheen_color: Color,
    /// Charlie sheen `α = sheenRoughness²` (raised to at least 0.01).
    pub sheen_alpha: f32,
}

impl Default for MetallicRoughnessBxdf {
    /// glTF's defaults: white, metallic 1, roughness 1, IOR 1.5, full white
    /// specular, no transmission (not thin), no clearcoat, no sheen.
    fn default() -> Self {
        Self {
            base_color: Color::ONE,
            metallic: 1.0,
            alpha: 1.0,
            ior: 1.5,
            specular: 1.0,
            specular_color: Color::ONE,
            transmission: 0.0,
            thin: false,
            clearcoat: 0.0,
            clearcoat_alpha: 0.0,
            sheen_color: Color::ZERO,
            sheen_alpha: 0.0,
        }
    }
}

/// The lobes, in the order of [`MetallicRoughnessBxdf::lobe_probabilities`].
const COAT: usize = 0;
const SPECULAR: usize = 1;
const DIFFUSE: usize = 2;
const SHEEN: usize = 3;
const TRANSMISSION: usize = 4;
const N_LOBES: usize = 5;

/// Each present lobe keeps at least this selection weight, so that no lobe
/// whose `f` can be positive is left unsampled (e.g. a black metal seen
/// head-on, whose Schlick reflectance is 0 at `wo` but not at other `V·H`).
const MIN_LOBE_WEIGHT: f32 = 1e-3;

/// Clearcoat `f0` (index 1.5, `KHR_materials_clearcoat`).
const COAT_F0: f32 = 0.04;

/// How the transmitted light leaves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Transmit {
    /// Thin-walled: the specular lobe mirrored to the other side.
    Thin,
    /// Refractive with `ior = 1` (or an unusable `ior`): nothing bends, a
    /// straight delta.
    Straight,
    /// Refraction by `ior`.
    Refract,
}

/// Schlick's `(1 − cos)⁵`.
#[inline]
fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - cos.abs().min(1.0)).max(0.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// The mean of the channels.
#[inline]
fn mean(c: Color) -> f32 {
    c.element_sum() / 3.0
}

/// The parameters, clamped, and what follows from them.
struct Setup {
    base: Color,
    metallic: f32,
    transmission: f32,
    specular: f32,
    /// `min(f0(ior) · specularColor, 1)`.
    f0c: Color,
    transmit: Transmit,
    /// The relative index for refraction (1 unless `transmit` is `Refract`).
    eta: f32,
    distrib: TrowbridgeReitz,
    clearcoat: f32,
    coat: TrowbridgeReitz,
    sheen_color: Color,
    sheen_max: f32,
    sheen_alpha: f32,
}

impl Setup {
    fn new(p: &MetallicRoughnessBxdf) -> Self {
        let unit = |x: f32| if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
        let color = |c: Color| Color::new(unit(c.x), unit(c.y), unit(c.z));
        let ior = if p.ior.is_nan() { 1.5 } else { p.ior };
        let eta = if ior > 0.0 && ior.is_finite() { ior } else { 1.0 };
        let transmits = unit(p.transmission) * (1.0 - unit(p.metallic)) > 0.0;
        // Without transmission the material is opaque and both sides alike.
        let transmit = if p.thin || !transmits {
            Transmit::Thin
        } else if eta == 1.0 {
            Transmit::Straight
        } else {
            Transmit::Refract
        };
        let sheen_color = color(p.sheen_color);
        let specular_color = if p.specular_color.is_nan() { Color::ONE } else { p.specular_color.max(Color::ZERO) };
        Self {
            base: color(p.base_color),
            metallic: unit(p.metallic),
            transmission: unit(p.transmission),
            specular: unit(p.specular),
            f0c: (MetallicRoughnessBxdf::f0_from_ior(ior) * specular_color).min(Color::ONE),
            transmit,
            eta: if transmit == Transmit::Refract { eta } else { 1.0 },
            distrib: TrowbridgeReitz::new(p.alpha),
            clearcoat: unit(p.clearcoat),
            coat: TrowbridgeReitz::new(p.clearcoat_alpha),
            sheen_color,
            sheen_max: sheen_color.max_element(),
            sheen_alpha: sheen::clamp_alpha(p.sheen_alpha),
        }
    }

    /// Weight of the dielectric (non-metal) part.
    #[inline]
    fn dielectric(&self) -> f32 {
        1.0 - self.metallic
    }

    /// Whether each lobe can contribute, in lobe order.
    fn present(&self) -> [bool; N_LOBES] {
        let d = self.dielectric();
        let base = self.base.max_element() > 0.0;
        [
            self.clearcoat > 0.0,
            self.metallic > 0.0 || (d > 0.0 && self.specular > 0.0),
            d * (1.0 - self.transmission) > 0.0 && base,
            self.sheen_max > 0.0,
            d * self.transmission > 0.0 && base,
        ]
    }

    /// Whether the specular transmission is a delta.
    #[inline]
    fn transmission_is_delta(&self) -> bool {
        self.transmit == Transmit::Straight || self.distrib.effectively_smooth()
    }

    /// The dielectric Fresnel `F_d` (RGB) for a direction at `cos` to the
    /// (micro)normal, on the lower side of the surface if `below`
    /// (`KHR_materials_specular`: `specular · (f0c + (1 − f0c)(1 − cos)⁵)`).
    /// For refraction, from the denser side the cosine is that of the
    /// refracted direction and beyond the critical angle `F_d = specular`.
    fn fd(&self, cos: f32, below: bool) -> Color {
        let c = cos.abs().min(1.0);
        let w = if self.transmit == Transmit::Refract {
            let eta = if below { 1.0 / self.eta } else { self.eta };
            if eta < 1.0 {
                let sin2_t = (1.0 - c * c) / (eta * eta);
                if sin2_t >= 1.0 {
                    1.0
                } else {
                    schlick_weight((1.0 - sin2_t).sqrt())
                }
            } else {
                schlick_weight(c)
            }
        } else {
            schlick_weight(c)
        };
        self.specular * (self.f0c + (Color::ONE - self.f0c) * w)
    }

    /// The clearcoat's weighted Fresnel `clearcoat · F_c(cos)`.
    #[inline]
    fn coat_fresnel(&self, cos: f32) -> f32 {
        self.clearcoat * (COAT_F0 + (1.0 - COAT_F0) * schlick_weight(cos))
    }

    /// The coat's directional reflectance
    /// `R_c(μ) = clearcoat (f0 + (1 − f0) W(μ, α_c))`, `f0 = 0.04`.
    #[inline]
    fn coat_albedo(&self, cos: f32) -> f32 {
        self.clearcoat * (COAT_F0 + (1.0 - COAT_F0) * visible_schlick_weight(cos, self.coat.alpha()))
    }

    /// The weight `C = 1 − max(R_c(cos θo), R_c(cos θi))` of everything
    /// under the coat.
    #[inline]
    fn under_coat(&self, co: f32, ci: f32) -> f32 {
        if self.clearcoat > 0.0 {
            1.0 - self.coat_albedo(co).max(self.coat_albedo(ci))
        } else {
            1.0
        }
    }

    /// The specular layer's directional reflectance, largest channel:
    /// `R(μ) = specular (max(f0c) + (1 − max(f0c)) W(μ, α))`.
    #[inline]
    fn layer_albedo(&self, cos: f32) -> f32 {
        let f0 = self.f0c.max_element();
        self.specular * (f0 + (1.0 - f0) * visible_schlick_weight(cos, self.distrib.alpha()))
    }

    /// The diffuse lobe's weight under the specular layer,
    /// `(1 − R(cos θo))(1 − R(cos θi)) / (1 − R̄)` (Kulla & Conty's albedo
    /// scaling), and for refraction seen from inside
    /// `1 − max(F_d(cos θo), F_d(cos θi))` (largest channels).
    fn diffuse_weight(&self, co: f32, ci: f32, below: bool) -> f32 {
        if self.specular == 0.0 {
            return 1.0;
        }
        if below && self.transmit == Transmit::Refract {
            return 1.0 - self.fd(co, true).max_element().max(self.fd(ci, true).max_element());
        }
        let f0 = self.f0c.max_element();
        let mean = self.specular * (f0 + (1.0 - f0) * mean_visible_schlick_weight(self.distrib.alpha()));
        if mean >= 1.0 {
            return 0.0;
        }
        (1.0 - self.layer_albedo(co)) * (1.0 - self.layer_albedo(ci)) / (1.0 - mean)
    }

    /// The sheen lobe's albedo `E(cos)` (before [`Setup::sheen_brdf`]'s
    /// normalisation; 0 without sheen).
    #[inline]
    fn sheen_e(&self, cos: f32) -> f32 {
        if self.sheen_max > 0.0 {
            sheen::albedo(cos, self.sheen_alpha)
        } else {
            0.0
        }
    }

    /// The sheen's albedo `max(sheenColor) · min(E(cos), 1)`.
    #[inline]
    fn sheen_albedo(&self, cos: f32) -> f32 {
        self.sheen_max * self.sheen_e(cos).min(1.0)
    }

    /// The Charlie sheen BRDF for an upper-side pair, divided by
    /// `max(1, E(cos θo), E(cos θi))` where the fit gains energy (see the
    /// `sheen` module).
    #[inline]
    fn sheen_brdf(&self, o: Vec3, i: Vec3) -> f32 {
        let norm = self.sheen_e(o.z).max(self.sheen_e(i.z)).max(1.0);
        sheen::brdf(o, i, self.sheen_alpha) / norm
    }

    /// The sheen's albedo scaling `S` of the material under it.
    #[inline]
    fn under_sheen(&self, co: f32, ci: f32) -> f32 {
        if self.sheen_max > 0.0 {
            1.0 - self.sheen_albedo(co).max(self.sheen_albedo(ci))
        } else {
            1.0
        }
    }

    /// Lobe selection probabilities for `wo`; all 0 if nothing scatters.
    fn lobe_probabilities(&self, wo: Vec3) -> [f32; N_LOBES] {
        let co = wo.z.abs();
        let below = wo.z < 0.0;
        let d = self.dielectric();
        let coat = if self.clearcoat > 0.0 { self.coat_albedo(co) } else { 0.0 };
        let outer = (1.0 - coat) * (1.0 - self.sheen_albedo(co));
        // Schlick's weight averaged over the visible normals: the layers'
        // directional reflectances.
        let w5 = visible_schlick_weight(co, self.distrib.alpha());
        let (layer, layer_max) = if below && self.transmit == Transmit::Refract {
            let fd = self.fd(co, true);
            (mean(fd), fd.max_element())
        } else {
            let fd = (self.f0c + (Color::ONE - self.f0c) * w5) * self.specular;
            (mean(fd), fd.max_element())
        };
        let metal = mean(self.base + (Color::ONE - self.base) * w5);
        let base = mean(self.base);
        let mut w = [0.0; N_LOBES];
        w[COAT] = coat;
        w[SPECULAR] = outer * (d * layer + self.metallic * metal);
        w[DIFFUSE] = outer * d * (1.0 - self.transmission) * (1.0 - layer_max) * base;
        w[SHEEN] = (1.0 - coat) * mean(self.sheen_color) * self.sheen_e(co).min(1.0);
        w[TRANSMISSION] = outer * d * self.transmission * (1.0 - layer_max) * base;
        let present = self.present();
        let mut sum = 0.0;
        for k in 0..N_LOBES {
            w[k] = if present[k] { w[k].max(MIN_LOBE_WEIGHT) } else { 0.0 };
            sum += w[k];
        }
        if sum > 0.0 {
            for x in &mut w {
                *x /= sum;
            }
        }
        w
    }

    /// The BSDF for both directions above the surface (a lower-side pair
    /// mirrored up; `below` tells the dielectric Fresnel which side it is).
    fn f_reflect(&self, o: Vec3, i: Vec3, below: bool) -> Color {
        let (co, ci) = (o.z, i.z);
        let d = self.dielectric();
        let mut inner = Color::ZERO;
        if d * (1.0 - self.transmission) > 0.0 {
            let weight = self.diffuse_weight(co, ci, below);
            inner += self.base * (d * (1.0 - self.transmission) * weight * FRAC_1_PI);
        }
        let mut coat = 0.0;
        let h = (o + i).normalize_or_zero();
        if h != Vec3::ZERO {
            let oh = o.dot(h);
            if !self.distrib.effectively_smooth() && (self.metallic > 0.0 || self.specular > 0.0) {
                let spec = self.distrib.d(h) * self.distrib.g(o, i) / (4.0 * co * ci);
                inner += (self.fd(oh, below) * d + fr_schlick(oh, self.base) * self.metallic) * spec;
            }
            if self.clearcoat > 0.0 && !self.coat.effectively_smooth() {
                coat = self.coat_fresnel(oh) * self.coat.d(h) * self.coat.g(o, i) / (4.0 * co * ci);
            }
        }
        let mut under = inner * self.under_sheen(co, ci);
        if self.sheen_max > 0.0 {
            under += self.sheen_color * self.sheen_brdf(o, i);
        }
        Color::splat(coat) + under * self.under_coat(co, ci)
    }

    /// The rough transmission for a pair on opposite sides, without the
    /// coat's and the sheen's scaling.
    fn f_transmit(&self, wo: Vec3, wi: Vec3) -> Color {
        let weight = self.dielectric() * self.transmission;
        if weight <= 0.0 || self.transmission_is_delta() {
            return Color::ZERO;
        }
        match self.transmit {
            Transmit::Thin => {
                let (o, i) = if wo.z < 0.0 { (flip_z(wo), wi) } else { (wo, flip_z(wi)) };
                let h = (o + i).normalize_or_zero();
                if h == Vec3::ZERO {
                    return Color::ZERO;
                }
                let btdf = self.distrib.d(h) * self.distrib.g(o, i) / (4.0 * o.z * i.z);
                let t = 1.0 - self.fd(o.dot(h), false).max_element();
                self.base * (weight * t * btdf)
            }
            Transmit::Refract => {
                let Some((wm, etap)) = refraction_half_vector(wo, wi, self.eta) else {
                    return Color::ZERO;
                };
                let (dwi, dwo) = (wi.dot(wm), wo.dot(wm));
                let denom = (dwi + dwo / etap) * (dwi + dwo / etap) * wi.z * wo.z;
                let btdf = self.distrib.d(wm) * self.distrib.g(wo, wi) * (dwi * dwo / denom).abs() / (etap * etap);
                let t = 1.0 - self.fd(dwo, wo.z < 0.0).max_element();
                self.base * (weight * t * btdf)
            }
            Transmit::Straight => Color::ZERO,
        }
    }

    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        if wo.z == 0.0 || wi.z == 0.0 {
            return Color::ZERO;
        }
        if wo.z * wi.z > 0.0 {
            let below = wo.z < 0.0;
            let (o, i) = if below { (flip_z(wo), flip_z(wi)) } else { (wo, wi) };
            self.f_reflect(o, i, below)
        } else {
            let (co, ci) = (wo.z.abs(), wi.z.abs());
            self.f_transmit(wo, wi) * (self.under_coat(co, ci) * self.under_sheen(co, ci))
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z == 0.0 || wi.z == 0.0 {
            return 0.0;
        }
        let p = self.lobe_probabilities(wo);
        if wo.z * wi.z > 0.0 {
            let (o, i) = if wo.z < 0.0 { (flip_z(wo), flip_z(wi)) } else { (wo, wi) };
            let mut pdf = p[DIFFUSE] * cosine_hemisphere_pdf(i.z) + p[SHEEN] / (2.0 * PI);
            let h = (o + i).normalize_or_zero();
            if h != Vec3::ZERO {
                let jacobian = 1.0 / (4.0 * o.dot(h).abs());
                if p[SPECULAR] > 0.0 && !self.distrib.effectively_smooth() {
                    pdf += p[SPECULAR] * self.distrib.d_visible(o, h) * jacobian;
                }
                if p[COAT] > 0.0 && !self.coat.effectively_smooth() {
                    pdf += p[COAT] * self.coat.d_visible(o, h) * jacobian;
                }
            }
            pdf
        } else {
            if p[TRANSMISSION] <= 0.0 || self.transmission_is_delta() {
                return 0.0;
            }
            match self.transmit {
                Transmit::Thin => {
                    let (o, i) = if wo.z < 0.0 { (flip_z(wo), wi) } else { (wo, flip_z(wi)) };
                    let h = (o + i).normalize_or_zero();
                    if h == Vec3::ZERO {
                        return 0.0;
                    }
                    p[TRANSMISSION] * self.distrib.d_visible(o, h) / (4.0 * o.dot(h).abs())
                }
                Transmit::Refract => {
                    let Some((wm, etap)) = refraction_half_vector(wo, wi, self.eta) else {
                        return 0.0;
                    };
                    let (dwi, dwo) = (wi.dot(wm), wo.dot(wm));
                    let dwm_dwi = dwi.abs() / ((dwi + dwo / etap) * (dwi + dwo / etap));
                    p[TRANSMISSION] * self.distrib.d_visible(wo, wm) * dwm_dwi
                }
                Transmit::Straight => 0.0,
            }
        }
    }

    /// The delta mirror reflection for `wo` (upper side `o`), if the coat or
    /// the specular reflection is smooth: its weight and the probability of
    /// choosing it.
    fn mirror(&self, o: Vec3, below: bool, p: &[f32; N_LOBES]) -> (Color, f32) {
        let co = o.z;
        let (mut weight, mut prob) = (Color::ZERO, 0.0);
        if p[SPECULAR] > 0.0 && self.distrib.effectively_smooth() {
            let spec = self.fd(co, below) * self.dielectric() + fr_schlick(co, self.base) * self.metallic;
            weight += spec * (self.under_coat(co, co) * self.under_sheen(co, co));
            prob += p[SPECULAR];
        }
        if p[COAT] > 0.0 && self.coat.effectively_smooth() {
            weight += Color::splat(self.coat_fresnel(co));
            prob += p[COAT];
        }
        (weight, prob)
    }

    fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let p = self.lobe_probabilities(wo);
        // The lobe whose cumulative probability first exceeds uc (the last
        // one that can be chosen, against rounding).
        let mut lobe = (0..N_LOBES).rev().find(|&k| p[k] > 0.0)?;
        let mut cdf = 0.0;
        for (k, &pk) in p.iter().enumerate() {
            cdf += pk;
            if pk > 0.0 && uc < cdf {
                lobe = k;
                break;
            }
        }
        let below = wo.z < 0.0;
        let o = if below { flip_z(wo) } else { wo };
        let unflip = |w: Vec3| if below { flip_z(w) } else { w };
        let wi = match lobe {
            COAT | SPECULAR => {
                let distrib = if lobe == COAT { self.coat } else { self.distrib };
                if distrib.effectively_smooth() {
                    let (weight, prob) = self.mirror(o, below, &p);
                    let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                    let f = weight / wo.z.abs();
                    return Some(BsdfSample { f, wi, pdf: prob, specular: true, transmission: false, eta: 1.0 });
                }
                let i = reflect(o, distrib.sample_wm(o, u));
                if i.z <= 0.0 {
                    return None;
                }
                unflip(i)
            }
            DIFFUSE => unflip(cosine_hemisphere(u)),
            SHEEN => {
                // Uniform on the hemisphere: z = u₀.
                let z = u.x;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = 2.0 * PI * u.y;
                unflip(Vec3::new(r * phi.cos(), r * phi.sin(), z))
            }
            _ => return self.sample_transmission(wo, o, u, p[TRANSMISSION]),
        };
        self.finish(wo, wi, 1.0)
    }

    /// A sample of the transmission lobe, chosen with probability `prob`.
    fn sample_transmission(&self, wo: Vec3, o: Vec3, u: Vec2, prob: f32) -> Option<BsdfSample> {
        let co = wo.z.abs();
        let weight = self.base * (self.dielectric() * self.transmission);
        if self.transmission_is_delta() {
            let (wi, etap) = match self.transmit {
                Transmit::Refract => refract(wo, Vec3::Z, self.eta)?,
                _ => (-wo, 1.0),
            };
            let ci = wi.z.abs();
            if ci == 0.0 {
                return None;
            }
            let t = 1.0 - self.fd(co, wo.z < 0.0).max_element();
            let scale = self.under_coat(co, ci) * self.under_sheen(co, ci) * t / (etap * etap);
            let f = weight * (scale / ci);
            return Some(BsdfSample { f, wi, pdf: prob, specular: true, transmission: true, eta: etap });
        }
        match self.transmit {
            Transmit::Thin => {
                let r = reflect(o, self.distrib.sample_wm(o, u));
                if r.z <= 0.0 {
                    return None;
                }
                // The reflection mirrored to the far side of wo.
                let wi = if wo.z < 0.0 { r } else { flip_z(r) };
                self.finish(wo, wi, 1.0)
            }
            _ => {
                let (wi, etap) = refract(wo, self.distrib.sample_wm(wo, u), self.eta)?;
                if wi.z * wo.z >= 0.0 {
                    return None;
                }
                self.finish(wo, wi, etap)
            }
        }
    }

    /// A non-delta sample: the full `f` and the mixture pdf.
    fn finish(&self, wo: Vec3, wi: Vec3, eta: f32) -> Option<BsdfSample> {
        if wi.z == 0.0 || !wi.is_finite() {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        let f = self.f(wo, wi);
        if pdf <= 0.0 || !pdf.is_finite() || !f.is_finite() {
            return None;
        }
        let transmission = wo.z * wi.z < 0.0;
        Some(BsdfSample { f, wi, pdf, specular: false, transmission, eta: if transmission { eta } else { 1.0 } })
    }

    fn is_specular(&self) -> bool {
        let present = self.present();
        let delta = [
            self.coat.effectively_smooth(),
            self.distrib.effectively_smooth(),
            false,
            false,
            self.transmission_is_delta(),
        ];
        present.iter().any(|&p| p) && present.iter().zip(delta).all(|(&p, d)| !p || d)
    }
}

/// The generalised half vector of a transmission pair (Walter et al. 2007,
/// eq. 16: `wm ∝ η' wi + wo`, facing `+z`) with `η'`, the index on the side
/// of `wi` over that on the side of `wo`; `None` when degenerate or when
/// `wo` or `wi` would see the microfacet from behind.
fn refraction_half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let etap = if wo.z > 0.0 { eta } else { 1.0 / eta };
    let wm = (wi * etap + wo).normalize_or_zero();
    if wm == Vec3::ZERO {
        return None;
    }
    let wm = if wm.z < 0.0 { -wm } else { wm };
    if wm.dot(wi) * wi.z < 0.0 || wm.dot(wo) * wo.z < 0.0 {
        return None;
    }
    Some((wm, etap))
}

/// Schlick's weight averaged over the GGX normals visible from a
/// direction at `cos θ = μ`, `W(μ, α) = E_{wm ~ D_wo}[(1 − |wo·wm|)⁵]`: with
/// it a layer's directional Fresnel reflectance is `f0 + (1 − f0) W`. For a
/// smooth surface (`α` < [`super::microfacet::SMOOTH_ALPHA`]) it is
/// `(1 − μ)⁵`; otherwise it is read from a table computed once, at first
/// use, by a 32 × 32 midpoint rule over the visible-normal samples of
/// [`TrowbridgeReitz::sample_wm`], on 33 × 33 nodes in `(√μ, √α)`.
fn visible_schlick_weight(cos: f32, alpha: f32) -> f32 {
    let mu = cos.abs().min(1.0);
    if alpha < super::microfacet::SMOOTH_ALPHA {
        return schlick_weight(mu);
    }
    let t = fresnel_table();
    let x = mu.sqrt() * (N_TABLE - 1) as f32;
    let y = (alpha.min(1.0).sqrt() * (N_TABLE - 1) as f32).min((N_TABLE - 1) as f32);
    let (i, j) = ((x as usize).min(N_TABLE - 2), (y as usize).min(N_TABLE - 2));
    let (fx, fy) = (x - i as f32, y - j as f32);
    let at = |i: usize, j: usize| t.w[j * N_TABLE + i];
    let lo = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
    let hi = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
    lo * (1.0 - fy) + hi * fy
}

/// The cosine-weighted mean `W̄(α) = ∫₀¹ W(μ, α) 2μ dμ` (1/21 when smooth),
/// of the table's interpolant in `μ`, linearly interpolated in `√α`.
fn mean_visible_schlick_weight(alpha: f32) -> f32 {
    if alpha < super::microfacet::SMOOTH_ALPHA {
        return 1.0 / 21.0;
    }
    let t = fresnel_table();
    let y = (alpha.min(1.0).sqrt() * (N_TABLE - 1) as f32).min((N_TABLE - 1) as f32);
    let j = (y as usize).min(N_TABLE - 2);
    let fy = y - j as f32;
    t.mean[j] * (1.0 - fy) + t.mean[j + 1] * fy
}

/// Nodes of the `W` table per axis (`√μ` and `√α`, each 0 to 1).
const N_TABLE: usize = 33;
/// Visible-normal samples per table entry along each side of the grid.
const TABLE_QUAD: usize = 32;

struct FresnelTable {
    /// `W` at `(√μ, √α) = (i, j)/(N_TABLE − 1)`, row by row in `α`.
    w: Vec<f32>,
    /// `W̄` at `√α = j/(N_TABLE − 1)`.
    mean: Vec<f32>,
}

fn fresnel_table() -> &'static FresnelTable {
    static TABLE: OnceLock<FresnelTable> = OnceLock::new();
    TABLE.get_or_init(|| {
        let step = 1.0 / (N_TABLE - 1) as f32;
        let w: Vec<f32> = (0..N_TABLE * N_TABLE)
            .into_par_iter()
            .map(|k| {
                let (s, r) = ((k % N_TABLE) as f32 * step, (k / N_TABLE) as f32 * step);
                // The first node stands for μ = 1e-4: the sampling of
                // visible normals needs a direction above the surface.
                let mu = (s * s).max(1e-4);
                let alpha = r * r;
                if alpha < super::microfacet::SMOOTH_ALPHA {
                    return schlick_weight(mu);
                }
                let distrib = TrowbridgeReitz::new(alpha);
                let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
                let mut sum = 0.0f64;
                for a in 0..TABLE_QUAD {
                    for b in 0..TABLE_QUAD {
                        let u = Vec2::new((a as f32 + 0.5) / TABLE_QUAD as f32, (b as f32 + 0.5) / TABLE_QUAD as f32);
                        sum += schlick_weight(wo.dot(distrib.sample_wm(wo, u))) as f64;
                    }
                }
                (sum / (TABLE_QUAD * TABLE_QUAD) as f64) as f32
            })
            .collect();
        // W̄ = ∫ W 2μ dμ = ∫₀¹ W 4s³ ds with μ = s², exactly for the
        // interpolant that the lookup evaluates (linear in s between nodes),
        // so that the diffuse lobe's normalisation matches it: on [s0, s1],
        // with W = a + b s, ∫ (a + b s) 4s³ ds = a (s1⁴ − s0⁴) + 4b (s1⁵ − s0⁵)/5.
        let h = 1.0 / (N_TABLE - 1) as f64;
        let mean = (0..N_TABLE)
            .map(|j| {
                let row = &w[j * N_TABLE..][..N_TABLE];
                let mut sum = 0.0f64;
                for i in 0..N_TABLE - 1 {
                    let (s0, s1) = (i as f64 * h, (i + 1) as f64 * h);
                    let b = (row[i + 1] as f64 - row[i] as f64) / h;
                    let a = row[i] as f64 - b * s0;
                    sum += a * (s1.powi(4) - s0.powi(4)) + 0.8 * b * (s1.powi(5) - s0.powi(5));
                }
                sum as f32
            })
            .collect();
        FresnelTable { w, mean }
    })
}

impl MetallicRoughnessBxdf {
    /// The relative index of refraction of the transmission lobe (1 when
    /// it does not bend light: thin-walled or `ior = 1`).
    pub(crate) fn refraction_eta(&self) -> f32 {
        Setup::new(self).eta
    }

    /// A dielectric's reflectance at normal incidence against air,
    /// `f0 = ((ior − 1)/(ior + 1))²` (glTF 2.0 Appendix B, `fresnel_mix`;
    /// `KHR_materials_ior`): 0.04 for the default 1.5, 1 for `ior` 0 or ∞
    /// (`KHR_materials_specular`'s conversion of specular-glossiness
    /// materials).
    pub fn f0_from_ior(ior: f32) -> f32 {
        if ior.is_infinite() {
            return 1.0;
        }
        let r = (ior - 1.0) / (ior + 1.0);
        r * r
    }

    /// The probabilities with which [`BxDF::sample_f`] picks each lobe for
    /// `wo`: coat, specular reflection (dielectric and metal together),
    /// diffuse, sheen, transmission. Proportional to each lobe's albedo
    /// estimated at `wo`, from the layers' directional reflectances at
    /// `μ = |cos θo|` (see the module documentation: `R_c` of the coat,
    /// `R_d = specular (f0c + (1 − f0c) W(μ, α))` of the dielectric layer,
    /// per channel, `R_m = baseColor + (1 − baseColor) W(μ, α)` of the
    /// metal, `E` of the sheen), with `C₀ = 1 − R_c` and
    /// `S₀ = 1 − max(sheenColor) E`:
    ///
    /// * coat: `R_c`;
    /// * specular: `C₀ S₀ ((1 − m) mean(R_d) + m mean(R_m))`;
    /// * diffuse: `C₀ S₀ (1 − m)(1 − t)(1 − max R_d) mean(baseColor)`;
    /// * sheen: `C₀ mean(sheenColor) E`;
    /// * transmission: `C₀ S₀ (1 − m) t (1 − max R_d) mean(baseColor)`;
    ///
    /// (for refraction seen from inside, `R_d` is `F_d(μ)` with total
    /// internal reflection), each lobe that can contribute raised to at
    /// least 0.001, then normalised (all 0 when nothing scatters).
    pub fn lobe_probabilities(&self, wo: Vec3) -> [f32; 5] {
        Setup::new(self).lobe_probabilities(wo)
    }
}

impl BxDF for MetallicRoughnessBxdf {
    /// BSDF value (delta lobes excluded).
    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        Setup::new(self).f(wo, wi)
    }

    /// Pick a lobe with `uc` ([`MetallicRoughnessBxdf::lobe_probabilities`])
    /// and sample it with `u`.
    fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        Setup::new(self).sample_f(wo, uc, u)
    }

    /// The mixture pdf `Σ pᵢ pdfᵢ(wo, wi)` over the non-delta lobes.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        Setup::new(self).pdf(wo, wi)
    }

    /// Whether every lobe that can contribute is a delta (e.g. a smooth
    /// metal, or smooth thin glass of transmission 1).
    fn is_specular(&self) -> bool {
        Setup::new(self).is_specular()
    }

    /// Widen near-specular reflection, transmission and coat (see
    /// [`TrowbridgeReitz::regularize`]).
    fn regularize(&mut self) {
        let widen = |alpha: f32| {
            let mut d = TrowbridgeReitz::new(alpha);
            d.regularize();
            d.alpha()
        };
        self.alpha = widen(self.alpha);
        self.clearcoat_alpha = widen(self.clearcoat_alpha);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    #[test]
    fn visible_schlick_weight_table_matches_monte_carlo() {
        // Smooth: exactly (1 − μ)⁵ and its mean 2∫(1 − μ)⁵ μ dμ = 1/21.
        assert_eq!(visible_schlick_weight(0.3, 0.0), 0.7f32.powi(5));
        assert_eq!(mean_visible_schlick_weight(0.0), 1.0 / 21.0);
        // Just above the smooth threshold the table agrees with the limit.
        for mu in [0.05f32, 0.3, 0.9] {
            let w = visible_schlick_weight(mu, 1.1e-3);
            assert!((w - (1.0 - mu).powi(5)).abs() < 2e-3, "μ {mu}: {w}");
        }
        assert!((mean_visible_schlick_weight(1.1e-3) - 1.0 / 21.0).abs() < 1e-3);
        // Rough: against independent random visible-normal samples.
        let mut rng = Pcg32::new(3, 8);
        for alpha in [0.05f32, 0.3, 0.7, 1.0] {
            let d = TrowbridgeReitz::new(alpha);
            for mu in [0.02f32, 0.2, 0.55, 1.0] {
                let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                let n = 200_000;
                let mc: f64 = (0..n)
                    .map(|_| schlick_weight(wo.dot(d.sample_wm(wo, Vec2::new(rng.uniform(), rng.uniform())))) as f64)
                    .sum::<f64>()
                    / n as f64;
                let w = visible_schlick_weight(mu, alpha) as f64;
                assert!((w - mc).abs() < 3e-3, "α {alpha} μ {mu}: table {w}, sampled {mc}");
            }
            // The mean against a fine midpoint rule over the table lookups.
            let m = 4000;
            let fine: f64 = (0..m)
                .map(|i| {
                    let mu = (i as f64 + 0.5) / m as f64;
                    visible_schlick_weight(mu as f32, alpha) as f64 * 2.0 * mu / m as f64
                })
                .sum();
            let mean = mean_visible_schlick_weight(alpha) as f64;
            assert!((mean - fine).abs() < 1e-3, "α {alpha}: W̄ {mean} vs {fine}");
        }
    }

    #[test]
    fn lobe_probabilities_are_normalised_and_cover_every_present_lobe() {
        let b = MetallicRoughnessBxdf {
            metallic: 1.0,
            base_color: Color::ZERO,
            clearcoat: 0.5,
            sheen_color: Color::splat(0.3),
            ..Default::default()
        };
        // A black metal seen head-on reflects nothing at wo, but not nothing
        // at other V·H: its lobe keeps a small probability.
        let p = b.lobe_probabilities(Vec3::Z);
        assert!((p.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        assert!(p[SPECULAR] > 0.0 && p[COAT] > 0.0 && p[SHEEN] > 0.0);
        assert_eq!((p[DIFFUSE], p[TRANSMISSION]), (0.0, 0.0));
        // Nothing scatters: no lobe, no sample.
        let black = MetallicRoughnessBxdf { metallic: 0.0, base_color: Color::ZERO, specular: 0.0, ..b };
        let black = MetallicRoughnessBxdf { clearcoat: 0.0, sheen_color: Color::ZERO, ..black };
        assert_eq!(black.lobe_probabilities(Vec3::Z), [0.0; 5]);
        assert!(black.sample_f(Vec3::Z, 0.5, Vec2::splat(0.5)).is_none());
        assert!(!black.is_specular());
    }
}
