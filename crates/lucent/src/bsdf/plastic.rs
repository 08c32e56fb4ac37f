//! Plastic: a diffuse base under a smooth or rough dielectric coat.
//!
//! The model is that of Weidlich & Wilkie, "Arbitrarily Layered
//! Micro-Facet Surfaces" (GRAPHITE 2007), in the form of Mitsuba 0.6's
//! `plastic` and `roughplastic` plugins (Jakob, Mitsuba documentation,
//! §8.2): light either reflects off the coat, or enters it, is scattered by
//! the Lambertian base of albedo `ρ` — bouncing between base and coat, where
//! a fraction `F̄_int` of diffuse light is reflected back each time — and
//! leaves through the coat. Summing the geometric series of inner bounces,
//!
//! `f = f_coat(wo, wi) + ρ/π · T(wi) T(wo) / (η² (1 − ρ F̄_int))`
//!
//! where `T(w)` is the coat's directional transmittance, `1/η²` the radiance
//! compression on entering and leaving, and
//! `F̄_int = 1 − T̄/η²` the coat's internal diffuse reflectance, `T̄` being
//! the cosine-weighted average of `T` outside (by reciprocity, diffuse light
//! inside crosses the coat with `T̄/η²`; PBRT 4th ed., §9.5.2).
//!
//! Smooth coat: `f_coat` is a delta mirror of weight `F(cos θo)` and
//! `T = 1 − F`. Rough coat: `f_coat` is GGX Torrance–Sparrow with the
//! dielectric Fresnel term, and `T(w) = 1 − R(w)` with `R` its albedo
//! (directional reflectance), tabulated once over `(η, α, cos θ)` like
//! Mitsuba's rough transmittance tables. With this choice the energy the
//! single-scattering coat loses is handed to the base, and for `ρ = 1` the
//! model reflects all light (up to the table's interpolation error): the
//! total albedo is `R(wo) + T(wo) · ρ(T̄/η²)/(1 − ρF̄_int)`, which is 1 when
//! `ρ = 1`.
//!
//! The coat index is clamped to `[1, 3]` (the range of the table).
//! Reflection only, two-sided.
//!
//! Against pbrt-v4's stochastic coated diffuse
//! ([`super::CoatedDiffuseBxdf`]) with the same base, coat index 1.5 and
//! roughness (its default thickness 0.01, no medium, walks of 100 events),
//! the directional albedos (per channel, bases (0.8, 0.4, 0.1) and 0.5,
//! cos θo = 0.9, 0.5, 0.2; test `plastic_approximates_coated_diffuse`)
//! differ by at most 0.038 for a smooth coat, 0.076 at α = 0.1 and 0.24
//! at α = 0.4, plastic always the brighter: the coated model's slab absorbs
//! a little (`exp(−0.01/cos θ)` per crossing) and, above all, its rough
//! coat scatters only once per interface event and so loses energy, while
//! plastic hands all of it to the base.

use super::fresnel::{fr_dielectric, fr_dielectric_hemispherical};
use super::microfacet::TrowbridgeReitz;
use super::{flip_z, two_sided, BsdfSample, BxDF};
use crate::color::Color;
use crate::geometry::{reflect, Vec2, Vec3};
use crate::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use rayon::prelude::*;
use std::f32::consts::PI;
use std::sync::OnceLock;

/// A diffuse base under a dielectric coat; see the module documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlasticBxdf {
    /// Albedo of the base.
    pub diffuse: Color,
    /// Index of refraction of the coat, in [1, 3].
    pub eta: f32,
    /// Roughness of the coat.
    pub distrib: TrowbridgeReitz,
    /// `ρ / (π η² (1 − ρ F̄_int))`: multiplied by `T(wi) T(wo)` it is the
    /// diffuse term.
    diffuse_scale: Color,
    /// `T̄`, the cosine-weighted mean transmittance of the coat.
    t_mean: f32,
}

impl PlasticBxdf {
    /// Base of albedo `diffuse`, coat of index `eta` (clamped to [1, 3])
    /// and roughness `distrib`.
    pub fn new(diffuse: Color, eta: f32, distrib: TrowbridgeReitz) -> Self {
        let eta = if eta.is_nan() { 1.5 } else { eta.clamp(ETA_MIN, ETA_MAX) };
        let diffuse = diffuse.max(Color::ZERO);
        let t_mean = if distrib.effectively_smooth() {
            1.0 - fr_dielectric_hemispherical(eta)
        } else {
            table().t_mean(eta, distrib.alpha())
        };
        let f_int = 1.0 - t_mean / (eta * eta);
        let diffuse_scale = diffuse / ((Color::ONE - diffuse * f_int) * (PI * eta * eta));
        Self { diffuse, eta, distrib, diffuse_scale, t_mean }
    }

    /// Transmittance of the coat for a direction at `cos_theta`.
    #[inline]
    fn t(&self, cos_theta: f32) -> f32 {
        if self.distrib.effectively_smooth() {
            1.0 - fr_dielectric(cos_theta.abs(), self.eta)
        } else {
            table().t(self.eta, self.distrib.alpha(), cos_theta.abs())
        }
    }

    /// Probability of sampling the coat for `wo` (upper side): its share of
    /// the albedo, `R(wo) / (R(wo) + T(wo) · ρ̄_diffuse)`.
    fn p_coat(&self, wo: Vec3) -> f32 {
        let t_o = self.t(wo.z);
        let w_coat = 1.0 - t_o;
        let w_base = t_o * self.diffuse_scale.element_sum() / 3.0 * PI * self.t_mean;
        let sum = w_coat + w_base;
        if sum > 0.0 {
            w_coat / sum
        } else {
            0.5
        }
    }

    /// Both directions on the upper side.
    fn f_upper(&self, wo: Vec3, wi: Vec3) -> Color {
        let mut f = self.diffuse_scale * (self.t(wi.z) * self.t(wo.z));
        if !self.distrib.effectively_smooth() {
            let wm = (wo + wi).normalize_or_zero();
            if wm != Vec3::ZERO {
                let d = self.distrib.d(wm);
                let g = self.distrib.g(wo, wi);
                f += Color::splat(d * g * fr_dielectric(wo.dot(wm), self.eta) / (4.0 * wo.z * wi.z));
            }
        }
        f
    }

    fn pdf_upper(&self, wo: Vec3, wi: Vec3) -> f32 {
        let p = self.p_coat(wo);
        let mut pdf = (1.0 - p) * cosine_hemisphere_pdf(wi.z);
        if !self.distrib.effectively_smooth() {
            let wm = (wo + wi).normalize_or_zero();
            if wm != Vec3::ZERO {
                pdf += p * self.distrib.d_visible(wo, wm) / (4.0 * wo.dot(wm).abs());
            }
        }
        pdf
    }
}

impl BxDF for PlasticBxdf {
    /// BSDF value (for a smooth coat, without the delta reflection).
    fn f(&self, wo: Vec3, wi: Vec3) -> Color {
        two_sided(wo, wi, |wo, wi| self.f_upper(wo, wi))
    }

    /// Sample the coat or the base, with probabilities proportional to
    /// their albedos for `wo`.
    fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let lower = wo.z < 0.0;
        let wo_up = if lower { flip_z(wo) } else { wo };
        let unflip = |w: Vec3| if lower { flip_z(w) } else { w };
        let p = self.p_coat(wo_up);
        let wi = if uc < p {
            if self.distrib.effectively_smooth() {
                let wi = Vec3::new(-wo_up.x, -wo_up.y, wo_up.z);
                let f = Color::splat(fr_dielectric(wo_up.z, self.eta) / wi.z);
                return Some(BsdfSample { f, wi: unflip(wi), pdf: p, specular: true, transmission: false, eta: 1.0 });
            }
            reflect(wo_up, self.distrib.sample_wm(wo_up, u))
        } else {
            cosine_hemisphere(u)
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf_upper(wo_up, wi);
        let f = self.f_upper(wo_up, wi);
        if pdf <= 0.0 || !pdf.is_finite() || !f.is_finite() {
            return None;
        }
        Some(BsdfSample { f, wi: unflip(wi), pdf, specular: false, transmission: false, eta: 1.0 })
    }

    /// Mixture pdf of the coat (if rough) and the base.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        two_sided(wo, wi, |wo, wi| self.pdf_upper(wo, wi))
    }

    /// Never: the base is diffuse.
    fn is_specular(&self) -> bool {
        false
    }

    /// Widen a near-smooth coat (see [`TrowbridgeReitz::regularize`]).
    fn regularize(&mut self) {
        let mut distrib = self.distrib;
        distrib.regularize();
        *self = PlasticBxdf::new(self.diffuse, self.eta, distrib);
    }
}

const ETA_MIN: f32 = 1.0;
const ETA_MAX: f32 = 3.0;
const N_ETA: usize = 21;
const N_ALPHA: usize = 21;
const N_COS: usize = 33;
/// Visible-normal samples per table entry (a midpoint grid, side²).
const QUAD_SIDE: usize = 24;

/// Rough-coat transmittance `T(η, α, cos θ) = 1 − R` tabulated on a regular
/// grid (21 η in [1, 3], 21 α in [0, 1], 33 cos θ in [0, 1]), with its
/// cosine-weighted mean `T̄(η, α)`. Building it takes about a CPU second;
/// the table is stored with the source ([`STORED_TABLE`]) and read from
/// there.
struct CoatTable {
    t: Vec<f32>,
    t_mean: Vec<f32>,
}

/// [`CoatTable::build`]'s result, stored: `T` then `T̄`, in the order of
/// [`CoatTable`]'s vectors, as little-endian `f32`. The test
/// `stored_table_is_the_built_one` checks it against a fresh build and, with
/// the environment variable `LUCENT_WRITE_COAT_TABLE` set, writes it anew
/// (needed after any change to the grid or to the estimator).
static STORED_TABLE: &[u8] = include_bytes!("coat_table.bin");

/// The table, read from [`STORED_TABLE`] on first use (built if that does
/// not have the grid's size).
fn table() -> &'static CoatTable {
    static TABLE: OnceLock<CoatTable> = OnceLock::new();
    TABLE.get_or_init(|| CoatTable::from_bytes(STORED_TABLE).unwrap_or_else(CoatTable::build))
}

/// Grid coordinate of `x` in `[lo, hi]` with `n` points: the lower index and
/// the interpolation weight.
#[inline]
fn grid(x: f32, lo: f32, hi: f32, n: usize) -> (usize, f32) {
    let s = ((x - lo) / (hi - lo)).clamp(0.0, 1.0) * (n - 1) as f32;
    let i = (s as usize).min(n - 2);
    (i, s - i as f32)
}

impl CoatTable {
    /// Directional albedo of the GGX coat, `R(wo) = ∫ f cos θi dωi`,
    /// estimated with visible-normal sampling, whose estimator is
    /// `F(wo·wm) G(wo, wi) / G1(wo)` (PBRT 4th ed., eq. 9.33 into 9.28).
    fn albedo(eta: f32, alpha: f32, cos_o: f32) -> f32 {
        let distrib = TrowbridgeReitz::new(alpha);
        let cos_o = cos_o.max(1e-4);
        let wo = Vec3::new((1.0 - cos_o * cos_o).sqrt(), 0.0, cos_o);
        let g1 = distrib.g1(wo);
        let mut sum = 0.0f64;
        for i in 0..QUAD_SIDE {
            for j in 0..QUAD_SIDE {
                let u = Vec2::new((i as f32 + 0.5) / QUAD_SIDE as f32, (j as f32 + 0.5) / QUAD_SIDE as f32);
                let wm = distrib.sample_wm(wo, u);
                let wi = reflect(wo, wm);
                if wi.z > 0.0 {
                    sum += (fr_dielectric(wo.dot(wm), eta) * distrib.g(wo, wi) / g1) as f64;
                }
            }
        }
        (sum / (QUAD_SIDE * QUAD_SIDE) as f64) as f32
    }

    fn build() -> Self {
        let mut t = vec![0.0; N_ETA * N_ALPHA * N_COS];
        let mut t_mean = vec![0.0; N_ETA * N_ALPHA];
        t.par_chunks_mut(N_ALPHA * N_COS).zip(t_mean.par_chunks_mut(N_ALPHA)).enumerate().for_each(
            |(ie, (t, t_mean))| {
                let eta = ETA_MIN + (ETA_MAX - ETA_MIN) * ie as f32 / (N_ETA - 1) as f32;
                for ia in 0..N_ALPHA {
                    let alpha = ia as f32 / (N_ALPHA - 1) as f32;
                    let row = &mut t[ia * N_COS..][..N_COS];
                    for (ic, v) in row.iter_mut().enumerate() {
                        let c = ic as f32 / (N_COS - 1) as f32;
                        *v = if ia == 0 {
                            1.0 - fr_dielectric(c, eta)
                        } else {
                            (1.0 - Self::albedo(eta, alpha, c)).clamp(0.0, 1.0)
                        };
                    }
                    // T̄ = ∫₀¹ T(μ) 2μ dμ, exactly for the piecewise-linear
                    // interpolant of the row that `t` evaluates, so that the
                    // diffuse term's normalisation matches it: on [μ0, μ1],
                    // ∫ (T0 + (T1−T0)(μ−μ0)/h) 2μ dμ = h (T0 (2μ0+μ1) + T1 (μ0+2μ1)) / 3.
                    let h = 1.0 / (N_COS - 1) as f32;
                    let mut s = 0.0;
                    for ic in 0..N_COS - 1 {
                        let (m0, m1) = (ic as f32 * h, (ic + 1) as f32 * h);
                        s += h * (row[ic] * (2.0 * m0 + m1) + row[ic + 1] * (m0 + 2.0 * m1)) / 3.0;
                    }
                    t_mean[ia] = s;
                }
            },
        );
        Self { t, t_mean }
    }

    /// The table stored as [`CoatTable::to_bytes`] writes it; `None` if
    /// `bytes` does not hold one of this grid's size.
    fn from_bytes(bytes: &[u8]) -> Option<Self> {
        let n_t = N_ETA * N_ALPHA * N_COS;
        if bytes.len() != (n_t + N_ETA * N_ALPHA) * 4 {
            return None;
        }
        let mut values = bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        let t = values.by_ref().take(n_t).collect();
        Some(Self { t, t_mean: values.collect() })
    }

    /// `T` then `T̄` as little-endian `f32`.
    #[cfg(test)]
    fn to_bytes(&self) -> Vec<u8> {
        self.t.iter().chain(&self.t_mean).flat_map(|v| v.to_le_bytes()).collect()
    }

    /// Trilinear interpolation of `T`.
    fn t(&self, eta: f32, alpha: f32, cos_theta: f32) -> f32 {
        let (ie, fe) = grid(eta, ETA_MIN, ETA_MAX, N_ETA);
        let (ia, fa) = grid(alpha, 0.0, 1.0, N_ALPHA);
        let (ic, fc) = grid(cos_theta, 0.0, 1.0, N_COS);
        let at = |e: usize, a: usize, c: usize| self.t[((ie + e) * N_ALPHA + ia + a) * N_COS + ic + c];
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let along_c = |e, a| lerp(at(e, a, 0), at(e, a, 1), fc);
        lerp(lerp(along_c(0, 0), along_c(0, 1), fa), lerp(along_c(1, 0), along_c(1, 1), fa), fe)
    }

    /// Bilinear interpolation of `T̄`.
    fn t_mean(&self, eta: f32, alpha: f32) -> f32 {
        let (ie, fe) = grid(eta, ETA_MIN, ETA_MAX, N_ETA);
        let (ia, fa) = grid(alpha, 0.0, 1.0, N_ALPHA);
        let at = |e: usize, a: usize| self.t_mean[(ie + e) * N_ALPHA + ia + a];
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        lerp(lerp(at(0, 0), at(0, 1), fa), lerp(at(1, 0), at(1, 1), fa), fe)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_column_of_the_table_is_fresnel() {
        let tb = table();
        for c in [0.0f32, 0.3, 1.0] {
            let a = tb.t(1.5, 0.0, c);
            let b = 1.0 - fr_dielectric(c, 1.5);
            assert!((a - b).abs() < 5e-3, "{c}: {a} {b}");
        }
        let a = tb.t_mean(1.5, 0.0);
        assert!((a - (1.0 - fr_dielectric_hemispherical(1.5))).abs() < 2e-3, "{a}");
        assert!(tb.t.iter().all(|t| (0.0..=1.0).contains(t)));
    }

    /// The stored table is what `CoatTable::build` computes (to rounding:
    /// another CPU's or platform's `sin` and `cos` may differ in the last
    /// bit; on the x86-64 machine that wrote it, it was the build bit for
    /// bit); with
    /// `LUCENT_WRITE_COAT_TABLE` set, the build is written over it.
    #[test]
    fn stored_table_is_the_built_one() {
        let built = CoatTable::build();
        if std::env::var_os("LUCENT_WRITE_COAT_TABLE").is_some() {
            let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/bsdf/coat_table.bin");
            std::fs::write(path, built.to_bytes()).unwrap();
            return;
        }
        let stored = CoatTable::from_bytes(STORED_TABLE).expect("coat_table.bin has the grid's size");
        let max_diff = |a: &[f32], b: &[f32]| a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f32::max);
        assert!(max_diff(&stored.t, &built.t) <= 1e-5, "T differs by {}", max_diff(&stored.t, &built.t));
        assert!(max_diff(&stored.t_mean, &built.t_mean) <= 1e-5);
    }
}
