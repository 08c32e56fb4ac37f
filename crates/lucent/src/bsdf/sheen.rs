//! The "Charlie" sheen of `KHR_materials_sheen`: the microfibre BRDF of
//! Conty Estevez & Kulla, "Production Friendly Microfacet Sheen BRDF"
//! (SIGGRAPH 2017), and its directional albedo, which the extension's
//! albedo-scaling layering needs.
//!
//! With `α = sheenRoughness²` (the extension's `alpha_g`, "Sheen
//! distribution"), the distribution of fibre normals is the exponentiated
//! sine `D(h) = (2 + 1/α) sin^{1/α}θh / (2π)`, and the visibility is
//! Conty & Kulla's fitted Smith-like term
//! `V = 1 / ((1 + Λ(cos θo) + Λ(cos θi)) · 4 cos θo cos θi)` ("Sheen
//! visibility"), so that `f_sheen = D V` (without the sheen colour).
//!
//! The directional albedo `E(μ, α) = ∫ f_sheen(wo, wi) cos θi dωi` (the
//! extension's "Albedo-scaling technique") is computed numerically, once, at
//! first use (a [`OnceLock`]), on a 32 × 32 grid in `(√μ, √α)`, and read
//! back by bilinear interpolation.
//!
//! The fitted visibility does not conserve energy everywhere: for `α` below
//! about 0.07 and grazing `μ`, `E` exceeds 1 (up to 2.1 at `α = 0.01`,
//! `μ = 0.001`), and as `μ → 0` the fit's `Λ` stays finite, so `E` grows
//! without bound. Lucent therefore evaluates `f_sheen` with both cosines
//! raised to at least `1e-4` (which bounds `E` at grazing by its value at
//! `1e-4`), and [`super::MetallicRoughnessBxdf`] divides the lobe by
//! `max(1, E(μo), E(μi))` (reciprocal, and its albedo is then at most 1);
//! where `E ≤ 1`, which is everywhere for `α ≥ 0.07`, nothing changes.

use crate::geometry::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;
use std::sync::OnceLock;

/// Smallest sheen `α` (sheen roughness 0.1): below it the distribution
/// collapses onto the tangent plane, where it reflects nothing visible, and
/// is too narrow for the albedo table's quadrature. glTF's default sheen
/// roughness, 0, is raised to it.
pub(crate) const SHEEN_ALPHA_MIN: f32 = 0.01;

/// `α` clamped to `[SHEEN_ALPHA_MIN, 1]` (NaN: the minimum).
#[inline]
pub(crate) fn clamp_alpha(alpha: f32) -> f32 {
    if alpha >= SHEEN_ALPHA_MIN {
        alpha.min(1.0)
    } else {
        SHEEN_ALPHA_MIN
    }
}

/// The Charlie distribution `D(h) = (2 + 1/α) (sin²θh)^{1/(2α)} / (2π)` for
/// a fibre normal at `cos_h` to the surface normal.
#[inline]
pub(crate) fn distribution(alpha: f32, cos_h: f32) -> f32 {
    let inv_r = 1.0 / alpha;
    let sin2 = (1.0 - cos_h * cos_h).max(0.0);
    (2.0 + inv_r) * sin2.powf(0.5 * inv_r) / (2.0 * PI)
}

/// Conty & Kulla's fit `L(x) = a/(1 + b x^c) + d x + e`, its coefficients
/// interpolated between `α = 1` and `α = 0` by `(1 − α)²`.
#[inline]
fn fit_l(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let mix = |at1: f32, at0: f32| at1 + (at0 - at1) * t;
    let a = mix(21.5473, 25.3245);
    let b = mix(3.82987, 3.32435);
    let c = mix(0.19823, 0.16801);
    let d = mix(-1.97760, -1.27393);
    let e = mix(-4.32054, -4.85967);
    a / (1.0 + b * x.powf(c)) + d * x + e
}

/// The masking function `Λ(cos θ) = exp(L(cos θ))` below 0.5, and
/// `exp(2 L(0.5) − L(1 − cos θ))` above (the fit's symmetrisation).
#[inline]
pub(crate) fn lambda(cos_theta: f32, alpha: f32) -> f32 {
    let c = cos_theta.abs().min(1.0);
    if c < 0.5 {
        fit_l(c, alpha).exp()
    } else {
        (2.0 * fit_l(0.5, alpha) - fit_l(1.0 - c, alpha)).exp()
    }
}

/// The sheen BRDF (without colour) for both directions above the surface:
/// `D(h) / ((1 + Λ(cos θo) + Λ(cos θi)) · 4 cos θo cos θi)`, the cosines
/// raised to at least `MU_MIN` (see the module documentation); 0 when
/// either direction is not above.
#[inline]
pub(crate) fn brdf(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let h = (wo + wi).normalize_or_zero();
    if h == Vec3::ZERO {
        return 0.0;
    }
    let (co, ci) = (wo.z.max(MU_MIN), wi.z.max(MU_MIN));
    let v = 1.0 / ((1.0 + lambda(co, alpha) + lambda(ci, alpha)) * 4.0 * co * ci);
    distribution(alpha, h.z) * v
}

/// Directional albedo `E(μ, α)` of the sheen BRDF for a direction at
/// `cos θ = μ` (either side; clamped to [0, 1]) and sheen `α` (clamped as
/// [`clamp_alpha`]), by bilinear interpolation in the table. Above 1 where
/// the fit gains energy (see the module documentation).
#[inline]
pub(crate) fn albedo(mu: f32, alpha: f32) -> f32 {
    table().lookup(mu.abs().min(1.0).sqrt(), clamp_alpha(alpha).sqrt())
}

/// Table size along `√μ` and along `√α`.
const N_MU: usize = 32;
const N_ALPHA: usize = 32;
/// The smallest cosine [`brdf`] uses, and the `μ` of the table's first
/// `√μ` node: the fitted `Λ` stays finite at grazing, so without it `E`
/// would grow without bound as `μ → 0`.
const MU_MIN: f32 = 1e-4;

/// `E` on the grid `√μ = i/(N_MU − 1)` (the first node at [`MU_MIN`]) by
/// `√α` from `√SHEEN_ALPHA_MIN` to 1.
struct AlbedoTable {
    values: Vec<f32>,
}

fn alpha_sqrt_node(j: usize) -> f32 {
    let r0 = SHEEN_ALPHA_MIN.sqrt();
    r0 + (1.0 - r0) * j as f32 / (N_ALPHA - 1) as f32
}

impl AlbedoTable {
    /// Bilinear interpolation at `s = √μ`, `r = √α`.
    fn lookup(&self, s: f32, r: f32) -> f32 {
        let r0 = SHEEN_ALPHA_MIN.sqrt();
        let x = (s * (N_MU - 1) as f32).clamp(0.0, (N_MU - 1) as f32);
        let y = ((r - r0) / (1.0 - r0) * (N_ALPHA - 1) as f32).clamp(0.0, (N_ALPHA - 1) as f32);
        let (i, j) = ((x as usize).min(N_MU - 2), (y as usize).min(N_ALPHA - 2));
        let (fx, fy) = (x - i as f32, y - j as f32);
        let at = |i: usize, j: usize| self.values[j * N_MU + i];
        let lo = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
        let hi = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
        lo * (1.0 - fy) + hi * fy
    }
}

/// `E(μ, α)` by quadrature over the hemisphere of `wi`: a midpoint rule in
/// `t` with `cos θi = t²` (points crowd towards the horizon, where the
/// sheen lobe lives) and in `φ` over `[0, π]`, doubled by symmetry. `f cos θi`
/// is finite everywhere, so the rule converges without special care.
pub(crate) fn albedo_by_quadrature(mu: f32, alpha: f32, n_t: usize, n_phi: usize) -> f32 {
    let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let mut sum = 0.0f64;
    for a in 0..n_t {
        let t = (a as f64 + 0.5) / n_t as f64;
        let z = t * t;
        let dz = 2.0 * t / n_t as f64;
        let r = (1.0 - z * z).max(0.0).sqrt();
        for b in 0..n_phi {
            let phi = std::f64::consts::PI * (b as f64 + 0.5) / n_phi as f64;
            let wi = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
            sum += brdf(wo, wi, alpha) as f64 * z * dz;
        }
    }
    (2.0 * std::f64::consts::PI / n_phi as f64 * sum) as f32
}

fn table() -> &'static AlbedoTable {
    static TABLE: OnceLock<AlbedoTable> = OnceLock::new();
    TABLE.get_or_init(|| {
        let values = (0..N_MU * N_ALPHA)
            .into_par_iter()
            .map(|k| {
                let (i, j) = (k % N_MU, k / N_MU);
                let s = i as f32 / (N_MU - 1) as f32;
                let mu = (s * s).max(MU_MIN);
                let r = alpha_sqrt_node(j);
                albedo_by_quadrature(mu, r * r, 96, 48).max(0.0)
            })
            .collect();
        AlbedoTable { values }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distribution_is_normalised() {
        // ∫ D(h) cos θh dωh = 1 over the hemisphere.
        for alpha in [0.01f32, 0.1, 0.5, 1.0] {
            let n = 20_000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let c = (i as f64 + 0.5) / n as f64;
                sum += distribution(alpha, c as f32) as f64 * c * 2.0 * std::f64::consts::PI / n as f64;
            }
            assert!((sum - 1.0).abs() < 2e-3, "α {alpha}: {sum}");
        }
    }

    #[test]
    fn albedo_table_matches_fine_quadrature() {
        let mut worst = 0.0f32;
        for alpha in [0.01f32, 0.05, 0.07, 0.2, 0.37, 0.6, 1.0] {
            for mu in [0.0, 0.001f32, 0.02, 0.1, 0.33, 0.5, 0.77, 1.0] {
                let fine = albedo_by_quadrature(mu.max(MU_MIN), alpha, 400, 200);
                let e = albedo(mu, alpha);
                let err = (e - fine).abs() / fine.max(1.0);
                worst = worst.max(err);
                assert!(err < 1e-2, "α {alpha} μ {mu}: table {e}, quadrature {fine}");
                // Above α = 0.07 the fitted visibility conserves energy.
                if alpha >= 0.07 {
                    assert!(fine <= 1.0, "α {alpha} μ {mu}: {fine}");
                }
            }
        }
        eprintln!("sheen albedo table: largest relative error {worst:.5}");
        // Below MU_MIN the albedo is that at MU_MIN.
        let at_min = albedo_by_quadrature(MU_MIN, 0.01, 400, 200);
        assert!((albedo_by_quadrature(1e-7, 0.01, 400, 200) - at_min).abs() < 1e-3 * at_min);
    }
}
