//! Statistical and consistency tests of the BxDFs.
//!
//! * χ² goodness of fit of `sample_f` against `pdf`, in the manner of
//!   PBRT's and Mitsuba's test suites: directions are binned in (θ, φ) over
//!   the whole sphere, the expected count of each bin is the sample count
//!   times the integral of `pdf` over the bin (composite Simpson), bins
//!   expecting fewer than 5 samples are pooled, and the p-value of the χ²
//!   statistic comes from the regularised incomplete gamma function. Each
//!   test rejects at significance 0.01, Šidák-corrected for the number of
//!   tests. Samples that `sample_f` rejects are not counted, which matches
//!   `pdf`: it gives no density to the directions those samples would have
//!   had (e.g. a microfacet reflection below the surface).
//! * `pdf` and `f` agree with what `sample_f` returns.
//! * Reciprocity; white-furnace energy checks; edge cases.

use super::*;
use crate::sampling::Pcg32;
use std::f64::consts::PI;

// ---------------------------------------------------------------------------
// Incomplete gamma function and χ².

/// `ln Γ(x)` for `x > 0`: shift `x` up to at least 10 with
/// `Γ(x) = Γ(x+1)/x`, then Stirling's series (Abramowitz & Stegun 6.1.40).
fn ln_gamma(x: f64) -> f64 {
    let mut x = x;
    let mut acc = 0.0;
    while x < 10.0 {
        acc -= x.ln();
        x += 1.0;
    }
    let x2 = x * x;
    acc + (x - 0.5) * x.ln() - x + 0.5 * (2.0 * PI).ln() + 1.0 / (12.0 * x) - 1.0 / (360.0 * x * x2)
        + 1.0 / (1260.0 * x * x2 * x2)
        - 1.0 / (1680.0 * x * x2 * x2 * x2)
}

/// Regularised upper incomplete gamma function `Q(a, x) = Γ(a, x)/Γ(a)`:
/// the power series of `P = 1 − Q` for `x < a + 1`, else the continued
/// fraction of `Γ(a, x)` evaluated with the modified Lentz method (both as
/// in A&S 6.5.29 and 6.5.31).
fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let prefactor = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        // P(a, x) = e^{-x} x^a / Γ(a) · Σ x^n / (a (a+1) … (a+n)).
        let mut term = 1.0 / a;
        let mut sum = term;
        let mut n = 1.0;
        while term.abs() > sum.abs() * 1e-16 {
            term *= x / (a + n);
            sum += term;
            n += 1.0;
        }
        (1.0 - prefactor * sum).max(0.0)
    } else {
        // Γ(a, x) = e^{-x} x^a · 1/(x+1−a − 1(1−a)/(x+3−a − 2(2−a)/(x+5−a − …))).
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        prefactor * h
    }
}

/// p-value of a χ² statistic with `dof` degrees of freedom.
fn chi2_p_value(chi2: f64, dof: usize) -> f64 {
    gamma_q(dof as f64 / 2.0, chi2 / 2.0)
}

#[test]
fn incomplete_gamma_matches_closed_forms() {
    // Q(1, x) = e^{-x}; Q(n, x) for integer n is e^{-x} Σ_{k<n} x^k/k!.
    for x in [0.1, 1.0, 2.5, 10.0, 40.0] {
        assert!((gamma_q(1.0, x) - (-x).exp()).abs() < 1e-12);
        let q3 = (-x).exp() * (1.0 + x + x * x / 2.0);
        assert!((gamma_q(3.0, x) - q3).abs() < 1e-12, "{x}");
    }
    // ln Γ(n) = ln (n−1)!, Γ(1/2) = √π.
    assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
    assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-12);
    // χ² quantile: P(χ²₁₀ > 23.209) = 0.01.
    assert!((chi2_p_value(23.209, 10) - 0.01).abs() < 1e-4);
}

// ---------------------------------------------------------------------------
// χ² goodness of fit.

const THETA_BINS: usize = 16;
const PHI_BINS: usize = 32;
const CHI2_SAMPLES: usize = 100_000;
const SIGNIFICANCE: f64 = 0.01;

fn dir(theta: f64, phi: f64) -> Vec3 {
    let s = theta.sin();
    Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, theta.cos() as f32)
}

fn wo_at(cos_theta: f32, phi: f32) -> Vec3 {
    let s = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), cos_theta)
}

fn bin_of(w: Vec3) -> usize {
    let w = w.as_dvec3().normalize();
    let theta = w.z.clamp(-1.0, 1.0).acos();
    let mut phi = w.y.atan2(w.x);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let i = ((theta / PI * THETA_BINS as f64) as usize).min(THETA_BINS - 1);
    let j = ((phi / (2.0 * PI) * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
    i * PHI_BINS + j
}

/// Composite Simpson over `[t0, t1] × [p0, p1]` of `pdf sin θ` with `n`
/// subintervals per side.
fn simpson_rect(g: &dyn Fn(Vec3) -> f64, (t0, t1, p0, p1): (f64, f64, f64, f64), n: usize) -> f64 {
    let weight = |k: usize| {
        if k == 0 || k == n {
            1.0
        } else if k % 2 == 1 {
            4.0
        } else {
            2.0
        }
    };
    let (ht, hp) = ((t1 - t0) / n as f64, (p1 - p0) / n as f64);
    let mut sum = 0.0;
    for a in 0..=n {
        let theta = t0 + a as f64 * ht;
        let st = theta.sin();
        for b in 0..=n {
            let phi = p0 + b as f64 * hp;
            sum += weight(a) * weight(b) * g(dir(theta, phi)) * st;
        }
    }
    sum * ht * hp / 9.0
}

/// Adaptive 2D Simpson: compare 4 and 8 subintervals per side, and split
/// the rectangle in four where they disagree (sharp lobes: a GGX
/// reflection at grazing incidence is only ~0.02 rad wide sideways).
fn integrate_rect(g: &dyn Fn(Vec3) -> f64, r: (f64, f64, f64, f64), tol: f64, depth: u32) -> f64 {
    let coarse = simpson_rect(g, r, 4);
    let fine = simpson_rect(g, r, 8);
    if (fine - coarse).abs() <= tol.max(1e-5 * fine.abs()) || depth == 0 {
        return fine + (fine - coarse) / 15.0;
    }
    let (t0, t1, p0, p1) = r;
    let (tm, pm) = (0.5 * (t0 + t1), 0.5 * (p0 + p1));
    [(t0, tm, p0, pm), (tm, t1, p0, pm), (t0, tm, pm, p1), (tm, t1, pm, p1)]
        .into_iter()
        .map(|q| integrate_rect(g, q, tol / 4.0, depth - 1))
        .sum()
}

/// Expected frequency of every bin: `∫∫ pdf sin θ dθ dφ` by adaptive
/// Simpson inside each bin (bin edges nudged inwards, so that a pdf that
/// jumps at the horizon, a bin edge, is integrated from the correct side).
fn expected_frequencies(bxdf: &Bxdf, wo: Vec3) -> Vec<f64> {
    let (dt, dp) = (PI / THETA_BINS as f64, 2.0 * PI / PHI_BINS as f64);
    let nudge = 1e-7;
    let mut out = vec![0.0; THETA_BINS * PHI_BINS];
    for i in 0..THETA_BINS {
        for j in 0..PHI_BINS {
            let r = (
                i as f64 * dt + nudge,
                (i + 1) as f64 * dt - nudge,
                j as f64 * dp + nudge,
                (j + 1) as f64 * dp - nudge,
            );
            out[i * PHI_BINS + j] = integrate_rect(&|w| bxdf.pdf(wo, w) as f64, r, 1e-6, 6);
        }
    }
    out
}

struct Chi2Case {
    name: String,
    bxdf: Bxdf,
    wo: Vec3,
}

/// Every χ² case of every BxDF: the Šidák correction counts them all.
fn chi2_cases() -> Vec<Chi2Case> {
    let mut v = Vec::new();
    let mut add = |name: String, bxdf: Bxdf, wo: Vec3| v.push(Chi2Case { name, bxdf, wo });
    let wos = [wo_at(0.999, 0.3), wo_at(0.5, 1.0), wo_at(0.08, 2.0)];
    for (k, &wo) in wos.iter().chain([wo_at(-0.6, 0.5)].iter()).enumerate() {
        add(format!("diffuse wo{k}"), Bxdf::diffuse(Color::new(0.8, 0.5, 0.2)), wo);
    }
    for alpha in [0.1, 0.3, 0.8] {
        for (k, &wo) in wos.iter().enumerate() {
            let b = Bxdf::conductor(Color::new(0.2, 0.9, 1.1), Color::new(3.9, 2.4, 2.2), alpha);
            add(format!("conductor α{alpha} wo{k}"), b, wo);
        }
    }
    add("conductor-schlick α0.3 lower".into(), Bxdf::conductor_schlick(Color::splat(0.9), 0.3), wo_at(-0.7, 0.1));
    for alpha in [0.2, 0.5] {
        for (k, c) in [0.9f32, 0.4, 0.1, -0.9, -0.4, -0.1].into_iter().enumerate() {
            let b = Bxdf::dielectric(1.5, alpha, Color::ONE);
            add(format!("dielectric α{alpha} wo{k} (cos {c})"), b, wo_at(c, 0.7));
        }
    }
    for alpha in [0.0, 0.1, 0.4] {
        for (k, &wo) in wos.iter().enumerate() {
            add(format!("plastic α{alpha} wo{k}"), Bxdf::plastic(Color::new(0.7, 0.4, 0.2), 1.5, alpha), wo);
        }
    }
    for n in [1.0, 10.0, 100.0] {
        for (k, &wo) in wos.iter().enumerate() {
            add(format!("phong n{n} wo{k}"), Bxdf::phong(Color::new(0.3, 0.2, 0.1), 0.5, n, 0.2), wo);
        }
    }
    for (ax, ay) in [(0.05, 0.4), (0.6, 0.15)] {
        for (k, &wo) in wos.iter().enumerate() {
            add(format!("anisotropic conductor α({ax}, {ay}) wo{k}"), aniso_conductor(ax, ay), wo);
        }
        for (k, c) in [0.8f32, 0.3, -0.7].into_iter().enumerate() {
            add(format!("anisotropic dielectric α({ax}, {ay}) wo{k}"), aniso_dielectric(ax, ay), wo_at(c, 0.9));
        }
    }
    for (k, &wo) in wos.iter().chain([wo_at(-0.6, 0.5)].iter()).enumerate() {
        let b = Bxdf::diffuse_transmission(Color::new(0.5, 0.3, 0.1), Color::new(0.2, 0.6, 0.3));
        add(format!("diffuse transmission wo{k}"), b, wo);
    }
    let mr_wos = [wo_at(0.95, 0.3), wo_at(0.5, 1.0), wo_at(0.1, 2.0), wo_at(-0.6, 0.5)];
    for (name, b) in mr_configs().into_iter().filter(|(_, b)| !b.is_specular()) {
        for (k, &wo) in mr_wos.iter().enumerate() {
            add(format!("{name} wo{k}"), b, wo);
        }
    }
    v
}

/// Run the χ² test of one case; returns (p-value, description).
fn chi2_run(case: &Chi2Case, seed: u64) -> (f64, String) {
    let mut rng = Pcg32::new(seed, 17);
    let mut observed = vec![0.0f64; THETA_BINS * PHI_BINS];
    for _ in 0..CHI2_SAMPLES {
        let (uc, u) = (rng.uniform(), Vec2::new(rng.uniform(), rng.uniform()));
        if let Some(s) = case.bxdf.sample_f(case.wo, uc, u) {
            if !s.specular && s.pdf > 0.0 {
                observed[bin_of(s.wi)] += 1.0;
            }
        }
    }
    let expected: Vec<f64> =
        expected_frequencies(&case.bxdf, case.wo).iter().map(|e| e * CHI2_SAMPLES as f64).collect();
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].partial_cmp(&expected[b]).unwrap());
    let (mut chi2, mut dof) = (0.0, 0usize);
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    for &c in &order {
        if expected[c] == 0.0 && observed[c] > 0.0 {
            return (0.0, format!("{}: {} samples in bin {c} of zero pdf", case.name, observed[c]));
        }
        if expected[c] < 5.0 {
            pool_obs += observed[c];
            pool_exp += expected[c];
        } else {
            chi2 += (observed[c] - expected[c]).powi(2) / expected[c];
            dof += 1;
        }
    }
    if pool_exp > 0.0 || pool_obs > 0.0 {
        if pool_exp == 0.0 {
            return (0.0, format!("{}: {pool_obs} samples where pdf is 0", case.name));
        }
        chi2 += (pool_obs - pool_exp).powi(2) / pool_exp;
        dof += 1;
    }
    let dof = dof.saturating_sub(1).max(1);
    let p = chi2_p_value(chi2, dof);
    let total_obs: f64 = observed.iter().sum();
    let total_exp: f64 = expected.iter().sum();
    (p, format!("{}: χ² = {chi2:.1}, dof {dof}, p = {p:.4}, samples {total_obs} vs expected {total_exp:.0}", case.name))
}

fn chi2_family(prefix: &str) {
    let cases = chi2_cases();
    let alpha = 1.0 - (1.0 - SIGNIFICANCE).powf(1.0 / cases.len() as f64);
    let mut ran = 0;
    let mut failures = Vec::new();
    for (k, case) in cases.iter().enumerate() {
        if !case.name.starts_with(prefix) {
            continue;
        }
        ran += 1;
        let (p, msg) = chi2_run(case, 1000 + k as u64);
        eprintln!("{msg}");
        if p < alpha {
            failures.push(msg);
        }
    }
    assert!(ran > 0);
    assert!(failures.is_empty(), "rejected at corrected significance {alpha:.2e}:\n{}", failures.join("\n"));
}

#[test]
fn chi2_diffuse() {
    chi2_family("diffuse");
}

#[test]
fn chi2_rough_conductor() {
    chi2_family("conductor");
}

#[test]
fn chi2_rough_dielectric() {
    chi2_family("dielectric");
}

#[test]
fn chi2_plastic() {
    chi2_family("plastic");
}

#[test]
fn chi2_phong() {
    chi2_family("phong");
}

#[test]
fn chi2_anisotropic() {
    chi2_family("anisotropic");
}

#[test]
fn chi2_diffuse_transmission() {
    chi2_family("diffuse transmission");
}

#[test]
fn chi2_detects_a_wrong_pdf() {
    // The test has power: Phong samples of exponent 10 are rejected when
    // checked against the pdf of exponent 12.
    let good = Bxdf::phong(Color::ZERO, 1.0, 10.0, 0.0);
    let bad = Bxdf::phong(Color::ZERO, 1.0, 12.0, 0.0);
    let wo = wo_at(0.7, 0.0);
    let mut rng = Pcg32::new(3, 3);
    let mut observed = vec![0.0f64; THETA_BINS * PHI_BINS];
    for _ in 0..CHI2_SAMPLES {
        if let Some(s) = good.sample_f(wo, rng.uniform(), Vec2::new(rng.uniform(), rng.uniform())) {
            observed[bin_of(s.wi)] += 1.0;
        }
    }
    let expected = expected_frequencies(&bad, wo);
    let mut chi2 = 0.0;
    let mut dof = 0;
    for (o, e) in observed.iter().zip(&expected) {
        let e = e * CHI2_SAMPLES as f64;
        if e >= 5.0 {
            chi2 += (o - e).powi(2) / e;
            dof += 1;
        }
    }
    assert!(chi2_p_value(chi2, dof - 1) < 1e-6, "χ² {chi2} dof {dof}");
}

// ---------------------------------------------------------------------------
// Consistency of sample_f with f and pdf; reciprocity.

fn all_bxdfs() -> Vec<(&'static str, Bxdf)> {
    vec![
        ("diffuse", Bxdf::diffuse(Color::new(0.8, 0.5, 0.2))),
        ("conductor mirror", Bxdf::conductor(Color::new(0.2, 0.9, 1.1), Color::new(3.9, 2.4, 2.2), 0.0)),
        ("conductor α0.1", Bxdf::conductor(Color::new(0.2, 0.9, 1.1), Color::new(3.9, 2.4, 2.2), 0.1)),
        ("conductor α0.8", Bxdf::conductor_schlick(Color::new(0.9, 0.6, 0.3), 0.8)),
        ("conductor α1", Bxdf::conductor_schlick(Color::new(0.9, 0.6, 0.3), 1.0)),
        ("dielectric smooth", Bxdf::dielectric(1.5, 0.0, Color::new(1.0, 0.9, 0.8))),
        ("dielectric η1", Bxdf::dielectric(1.0, 0.3, Color::ONE)),
        ("dielectric α0.2", Bxdf::dielectric(1.5, 0.2, Color::new(1.0, 0.9, 0.8))),
        ("dielectric α0.5", Bxdf::dielectric(1.5, 0.5, Color::ONE)),
        ("dielectric α1 η0.7", Bxdf::dielectric(0.7, 1.0, Color::ONE)),
        ("plastic smooth", Bxdf::plastic(Color::new(0.7, 0.4, 0.2), 1.5, 0.0)),
        ("plastic α0.1", Bxdf::plastic(Color::new(0.7, 0.4, 0.2), 1.5, 0.1)),
        ("plastic α1", Bxdf::plastic(Color::new(0.7, 0.4, 0.2), 1.8, 1.0)),
        ("phong n1", Bxdf::phong(Color::new(0.3, 0.2, 0.1), 0.5, 1.0, 0.2)),
        ("phong n100", Bxdf::phong(Color::new(0.3, 0.2, 0.1), 0.5, 100.0, 0.2)),
        ("phong mirror only", Bxdf::phong(Color::ZERO, 0.0, 10.0, 0.7)),
        ("black", Bxdf::Black),
        ("conductor anisotropic", aniso_conductor(0.05, 0.4)),
        ("dielectric anisotropic", aniso_dielectric(0.4, 0.1)),
        ("thin dielectric", Bxdf::thin_dielectric(1.5)),
        ("diffuse transmission", Bxdf::diffuse_transmission(Color::new(0.5, 0.3, 0.1), Color::new(0.2, 0.6, 0.3))),
    ]
    .into_iter()
    .chain(mr_configs())
    .collect()
}

fn aniso_conductor(ax: f32, ay: f32) -> Bxdf {
    Bxdf::Conductor(ConductorBxdf {
        fresnel: ConductorFresnel::Complex { eta: Color::new(0.2, 0.9, 1.1), k: Color::new(3.9, 2.4, 2.2) },
        distrib: TrowbridgeReitz::anisotropic(ax, ay),
    })
}

fn aniso_dielectric(ax: f32, ay: f32) -> Bxdf {
    Bxdf::Dielectric(DielectricBxdf::new(1.5, TrowbridgeReitz::anisotropic(ax, ay), Color::ONE))
}

fn random_wo(rng: &mut Pcg32) -> Vec3 {
    // Uniform on the sphere.
    let z = 1.0 - 2.0 * rng.uniform();
    wo_at(z, 2.0 * std::f32::consts::PI * rng.uniform())
}

fn rel_err(a: f32, b: f32) -> f32 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-6)
}

#[test]
fn pdf_and_f_agree_with_sample_f() {
    let mut rng = Pcg32::new(11, 5);
    for (name, b) in all_bxdfs() {
        let mut checked = 0;
        for _ in 0..20_000 {
            let wo = random_wo(&mut rng);
            let Some(s) = b.sample_f(wo, rng.uniform(), Vec2::new(rng.uniform(), rng.uniform())) else {
                continue;
            };
            assert!((s.wi.length() - 1.0).abs() < 1e-4, "{name}: |wi| = {}", s.wi.length());
            assert_eq!(s.transmission, wo.z * s.wi.z < 0.0, "{name}");
            if s.specular {
                continue;
            }
            checked += 1;
            let pdf = b.pdf(wo, s.wi);
            let f = b.f(wo, s.wi);
            assert!(rel_err(pdf, s.pdf) < 1e-3, "{name}: wo {wo} wi {} pdf {pdf} vs sampled {}", s.wi, s.pdf);
            for c in 0..3 {
                assert!(rel_err(f[c], s.f[c]) < 1e-3, "{name}: wo {wo} wi {} f {f} vs sampled {}", s.wi, s.f);
            }
        }
        if !b.is_specular() && b != Bxdf::Black {
            assert!(checked > 1000, "{name}: only {checked} non-specular samples");
        }
    }
}

/// The near-specular copper plates of Veach's MIS scene (α 0.01 to 0.25,
/// pbrt-v4's `remaproughness false`): the pdf that MIS evaluates for a
/// light-sampled direction is the density `sample_f` drew it with, and the
/// sample weight is exactly `f·cos θi / pdf = F(wo·wm) · G(wo, wi) / G1(wo)`
/// (visible-normal sampling: `D` and the cosines cancel, Heitz 2018, §2;
/// PBRT 4th ed., eq. 9.28 with 9.33), so it never exceeds `F` however
/// narrow the lobe: BSDF sampling of these plates cannot make fireflies.
#[test]
fn near_specular_conductor_weights_are_fresnel_times_masking() {
    let (eta, k) = (Color::new(0.200438, 0.924033, 1.102212), Color::new(3.912949, 2.452848, 2.142188));
    let mut rng = Pcg32::new(23, 7);
    for alpha in [0.01f32, 0.05, 0.1, 0.25] {
        let b = Bxdf::conductor(eta, k, alpha);
        let distrib = TrowbridgeReitz::new(alpha);
        let fresnel = ConductorFresnel::Complex { eta, k };
        let mut checked = 0;
        for i in 0..20_000 {
            // Both sides (the conductor is two-sided), from head-on to grazing.
            let cos_o = (1.0 - rng.uniform()).max(0.02) * if i % 2 == 0 { 1.0 } else { -1.0 };
            let wo = wo_at(cos_o, 2.0 * std::f32::consts::PI * rng.uniform());
            let Some(s) = b.sample_f(wo, rng.uniform(), Vec2::new(rng.uniform(), rng.uniform())) else { continue };
            assert!(!s.specular && s.pdf > 0.0, "α {alpha}");
            let pdf = b.pdf(wo, s.wi);
            assert!(rel_err(pdf, s.pdf) < 2e-3, "α {alpha}: wo {wo} wi {} pdf {pdf} vs sampled {}", s.wi, s.pdf);
            // The upper-side configuration of the two-sided lobe.
            let flip = |w: Vec3| if wo.z < 0.0 { Vec3::new(w.x, w.y, -w.z) } else { w };
            let (wo_u, wi_u) = (flip(wo), flip(s.wi));
            let wm = (wo_u + wi_u).normalize();
            let want = fresnel.eval(wo_u.dot(wm)) * (distrib.g(wo_u, wi_u) / distrib.g1(wo_u));
            let got = s.f * (s.wi.z.abs() / s.pdf);
            for c in 0..3 {
                assert!(
                    rel_err(got[c], want[c]) < 2e-3,
                    "α {alpha}: wo {wo} wi {} weight {got} vs F·G/G1 {want}",
                    s.wi
                );
                assert!(got[c] <= fresnel.eval(wo_u.dot(wm))[c] * (1.0 + 1e-4), "α {alpha}: weight {got} above F");
            }
            checked += 1;
        }
        assert!(checked > 15_000, "α {alpha}: only {checked} samples");
    }
}

#[test]
fn delta_lobes_have_no_density() {
    let mut rng = Pcg32::new(12, 5);
    for (name, b) in all_bxdfs() {
        for _ in 0..2000 {
            let wo = random_wo(&mut rng);
            if let Some(s) = b.sample_f(wo, rng.uniform(), Vec2::new(rng.uniform(), rng.uniform())) {
                if s.specular && b.is_specular() {
                    assert_eq!(b.pdf(wo, s.wi), 0.0, "{name}");
                    assert_eq!(b.f(wo, s.wi), Color::ZERO, "{name}");
                }
            }
        }
    }
    let specular: Vec<_> = all_bxdfs().into_iter().filter(|(_, b)| b.is_specular()).map(|(n, _)| n).collect();
    assert_eq!(
        specular,
        [
            "conductor mirror",
            "dielectric smooth",
            "dielectric η1",
            "phong mirror only",
            "thin dielectric",
            "mr smooth metal",
            "mr smooth thin glass",
            "mr smooth glass"
        ]
    );
}

#[test]
fn reflection_is_reciprocal_and_transmission_generalised_reciprocal() {
    let mut rng = Pcg32::new(13, 5);
    for (name, b) in all_bxdfs() {
        let eta = match b {
            Bxdf::Dielectric(d) => d.eta,
            _ => 1.0,
        };
        for _ in 0..20_000 {
            let (wo, wi) = (random_wo(&mut rng), random_wo(&mut rng));
            let (a, c) = (b.f(wo, wi), b.f(wi, wo));
            if wo.z * wi.z > 0.0 {
                for k in 0..3 {
                    assert!(rel_err(a[k], c[k]) < 1e-3, "{name}: f(wo, wi) {a} vs f(wi, wo) {c}");
                }
            } else if let Bxdf::Dielectric(d) = b {
                // Radiance BTDF: f(wo, wi)/η(wo side)² = f(wi, wo)/η(wi side)².
                let eta_side = |w: Vec3| if w.z > 0.0 { 1.0 } else { eta };
                let lhs = a / (eta_side(wo) * eta_side(wo)) / d.tint;
                let rhs = c / (eta_side(wi) * eta_side(wi)) / d.tint;
                // Values below ~1e-2 lose relative precision to the
                // cancellation in (wi·wm + wo·wm/η')²: compare absolutely.
                for k in 0..3 {
                    let err = (lhs[k] - rhs[k]).abs() / lhs[k].abs().max(rhs[k].abs()).max(1e-2);
                    assert!(err < 1e-3, "{name}: {lhs} vs {rhs}");
                }
            } else if let Bxdf::DiffuseTransmission(_) = b {
                // T/π both ways.
                assert_eq!(a, c, "{name}");
            } else if let Bxdf::MetallicRoughness(m) = b {
                // Thin: symmetric; refractive: as the dielectric, η = ior.
                let eta_side = |w: Vec3| if m.thin || w.z > 0.0 { 1.0 } else { m.ior };
                let lhs = a / (eta_side(wo) * eta_side(wo));
                let rhs = c / (eta_side(wi) * eta_side(wi));
                for k in 0..3 {
                    let err = (lhs[k] - rhs[k]).abs() / lhs[k].abs().max(rhs[k].abs()).max(1e-2);
                    assert!(err < 1e-3, "{name}: {lhs} vs {rhs}");
                }
            } else {
                assert_eq!(a, Color::ZERO, "{name}: reflection-only BxDF transmits");
            }
        }
    }
}

/// The adjoint BSDF of importance transport is the radiance BSDF with its
/// arguments swapped, `f*(wo, wi) = f(wi, wo)` (Veach 1997, §5.2), for
/// every BxDF and pair; and a sample in importance mode is the radiance
/// sample with that value.
#[test]
fn importance_mode_is_the_adjoint() {
    let mut rng = Pcg32::new(17, 5);
    for (name, b) in all_bxdfs() {
        let bsdf = Bsdf::from_normal(Vec3::Z, b);
        for _ in 0..20_000 {
            let (wo, wi) = (random_wo(&mut rng), random_wo(&mut rng));
            let adjoint = bsdf.f_mode(wo, wi, TransportMode::Importance);
            let swapped = bsdf.f_mode(wi, wo, TransportMode::Radiance);
            for k in 0..3 {
                // (Small rough-refraction values lose relative precision
                // to cancellation: compared absolutely below 0.05.)
                let err = (adjoint[k] - swapped[k]).abs() / adjoint[k].abs().max(swapped[k].abs()).max(5e-2);
                assert!(err < 1e-3, "{name}: f*(wo, wi) {adjoint} vs f(wi, wo) {swapped}");
            }
            let (uc, u) = (rng.uniform(), Vec2::new(rng.uniform(), rng.uniform()));
            if let Some(r) = bsdf.sample_f_mode(wo, uc, u, TransportMode::Radiance) {
                let i = bsdf.sample_f_mode(wo, uc, u, TransportMode::Importance).expect("same sample");
                assert_eq!((i.wi, i.pdf, i.specular), (r.wi, r.pdf, r.specular), "{name}");
                let want = if r.transmission { r.f * (r.eta * r.eta) } else { r.f };
                assert!((i.f - want).abs().max_element() <= 1e-4 * want.max_element().max(1.0), "{name}");
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Energy.

/// Monte Carlo directional albedo `E[f |cos θi| / pdf]` (all lobes, delta
/// ones included) for `wo`, transmission weighted by `η'²` so that a
/// lossless interface gives 1 (undoing the radiance compression). Returns
/// the mean and its standard error, per channel.
fn albedo(b: &Bxdf, wo: Vec3, n: usize, seed: u64) -> (Color, Color) {
    let mut rng = Pcg32::new(seed, 9);
    let (mut sum, mut sum2) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for _ in 0..n {
        if let Some(s) = b.sample_f(wo, rng.uniform(), Vec2::new(rng.uniform(), rng.uniform())) {
            let mut w = s.f * s.wi.z.abs() / s.pdf;
            if s.transmission {
                w *= s.eta * s.eta;
            }
            let w = w.as_dvec3();
            sum += w;
            sum2 += w * w;
        }
    }
    let mean = sum / n as f64;
    let var = (sum2 / n as f64 - mean * mean).max(glam::DVec3::ZERO);
    (mean.as_vec3a(), (var / n as f64).sqrt().as_vec3a())
}

#[test]
fn lambert_albedo_is_exact_per_sample() {
    let b = Bxdf::diffuse(Color::ONE);
    let mut rng = Pcg32::new(1, 1);
    for _ in 0..10_000 {
        let wo = random_wo(&mut rng);
        if let Some(s) = b.sample_f(wo, rng.uniform(), Vec2::new(rng.uniform(), rng.uniform())) {
            let w = s.f * s.wi.z.abs() / s.pdf;
            assert!((w - Color::ONE).abs().max_element() < 1e-5, "{w}");
        }
    }
}

#[test]
fn smooth_conductor_with_unit_reflectance_is_lossless() {
    for b in [Bxdf::conductor_schlick(Color::ONE, 0.0), Bxdf::conductor(Color::ZERO, Color::ZERO, 0.0)] {
        for c in [1.0f32, 0.5, 0.01, -0.3] {
            let s = b.sample_f(wo_at(c, 0.4), 0.5, Vec2::splat(0.5)).unwrap();
            let w = s.f * s.wi.z.abs() / s.pdf;
            assert!(s.specular && (w - Color::ONE).abs().max_element() < 1e-5, "{b:?} {c}: {w}");
        }
    }
    // Gold-like complex index: the weight is the exact Fresnel reflectance.
    let (eta, k) = (Color::new(0.2, 0.9, 1.1), Color::new(3.9, 2.4, 2.2));
    let s = Bxdf::conductor(eta, k, 0.0).sample_f(Vec3::Z, 0.5, Vec2::splat(0.5)).unwrap();
    let r0 = ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
    assert!((s.f * s.wi.z / s.pdf - r0).abs().max_element() < 1e-5);
}

/// Measured (200k samples each) albedo of a GGX conductor with `r0 = 1`:
/// single scattering loses the energy of light that would scatter again
/// between microfacets (and of reflections below the horizon), more with
/// α:
///
/// | α    | cos θo = 1 | 0.5    | 0.1    |
/// |------|------------|--------|--------|
/// | 0.05 | 0.9973     | 0.9927 | 0.9111 |
/// | 0.1  | 0.9882     | 0.9689 | 0.8831 |
/// | 0.3  | 0.8764     | 0.8207 | 0.8881 |
/// | 0.5  | 0.6863     | 0.6969 | 0.8590 |
/// | 0.8  | 0.4249     | 0.5381 | 0.7992 |
/// | 1.0  | 0.3052     | 0.4488 | 0.7589 |
///
/// (At normal incidence and α = 1 half the visible normals are tilted by
/// more than 45°, and send the light below the horizon.) The quadrature
/// test below confirms these through `f` alone.
#[test]
fn rough_conductor_loses_energy_growing_with_roughness() {
    let mut prev = [1.0f32; 3];
    for alpha in [0.05f32, 0.1, 0.3, 0.5, 0.8, 1.0] {
        let b = Bxdf::conductor_schlick(Color::ONE, alpha);
        let mut row = Vec::new();
        for (k, c) in [1.0f32, 0.5, 0.1].into_iter().enumerate() {
            let (m, se) = albedo(&b, wo_at(c, 0.3), 200_000, 7);
            assert!(m.x <= 1.0 + 3.0 * se.x + 1e-4, "α {alpha} cos {c}: {m} ± {se}");
            // At cos θo = 0.1 the loss is not monotone in α (0.1: 0.883,
            // 0.3: 0.888): rougher lobes send less light to grazing
            // directions, where shadowing is strongest.
            if c >= 0.5 {
                assert!(m.x <= prev[k] + 3.0 * se.x + 1e-4, "α {alpha} cos {c}: {m} not below {}", prev[k]);
            }
            prev[k] = m.x;
            row.push(format!("{:.4}", m.x));
        }
        eprintln!("rough conductor r0=1 α {alpha}: albedo at cos θo 1, 0.5, 0.1 = {}", row.join(", "));
    }
    // Nearly smooth keeps almost all; α = 1 at grazing loses a lot.
    let (m, _) = albedo(&Bxdf::conductor_schlick(Color::ONE, 0.05), Vec3::Z, 100_000, 3);
    assert!(m.x > 0.995, "{m}");
}

#[test]
fn smooth_dielectric_conserves_energy_from_both_sides() {
    for eta in [1.5f32, 1.33, 0.8] {
        let b = Bxdf::dielectric(eta, 0.0, Color::ONE);
        for c in [1.0f32, 0.7, 0.3, 0.05, -1.0, -0.7, -0.3, -0.05] {
            let wo = wo_at(c, 1.1);
            let mut refl = 0;
            let n = 20_000;
            let mut rng = Pcg32::new(4, 4);
            for _ in 0..n {
                let s = b.sample_f(wo, rng.uniform(), Vec2::new(rng.uniform(), rng.uniform())).unwrap();
                assert!(s.specular);
                let mut w = s.f * s.wi.z.abs() / s.pdf;
                if s.transmission {
                    w *= s.eta * s.eta;
                    // Snell: η(wo side) sin θo = η(wi side) sin θi.
                    let (so, si) = ((1.0 - wo.z * wo.z).sqrt(), (1.0 - s.wi.z * s.wi.z).max(0.0).sqrt());
                    assert!((so - s.eta * si).abs() < 1e-4, "Snell");
                } else {
                    refl += 1;
                }
                assert!((w - Color::ONE).abs().max_element() < 1e-4, "η {eta} cos {c}: {w}");
            }
            let f = fresnel::fr_dielectric(c, eta);
            let frac = refl as f32 / n as f32;
            assert!((frac - f).abs() < 0.015, "η {eta} cos {c}: reflected {frac}, Fresnel {f}");
        }
    }
    // Tint scales transmission only.
    let b = Bxdf::dielectric(1.5, 0.0, Color::new(1.0, 0.5, 0.25));
    let s = b.sample_f(Vec3::Z, 0.99, Vec2::splat(0.5)).unwrap();
    assert!(s.transmission);
    let w = s.f * s.wi.z.abs() / s.pdf * s.eta * s.eta;
    assert!((w - Color::new(1.0, 0.5, 0.25)).abs().max_element() < 1e-5);
}

/// Measured (50k samples each; `R + T·η'²`, 1 for a lossless interface):
///
/// | α   | cos θo = 1 | 0.5    | 0.1    | −1     | −0.5   | −0.1   |
/// |-----|------------|--------|--------|--------|--------|--------|
/// | 0.1 | 0.9988     | 0.9926 | 0.9231 | 0.9892 | 0.9637 | 0.8640 |
/// | 0.3 | 0.9889     | 0.9489 | 0.9060 | 0.8999 | 0.7836 | 0.7870 |
/// | 0.6 | 0.9554     | 0.8615 | 0.8260 | 0.6766 | 0.6166 | 0.6414 |
/// | 1.0 | 0.8930     | 0.7414 | 0.7408 | 0.4156 | 0.5126 | 0.5098 |
///
/// Inside (cos θo < 0) loses more: beyond the critical angle microfacets
/// reflect totally, and single scattering drops what would bounce again.
#[test]
fn rough_dielectric_does_not_create_energy() {
    for alpha in [0.1f32, 0.3, 0.6, 1.0] {
        let b = Bxdf::dielectric(1.5, alpha, Color::ONE);
        let mut row = Vec::new();
        for c in [1.0f32, 0.5, 0.1, -1.0, -0.5, -0.1] {
            let (m, se) = albedo(&b, wo_at(c, 0.2), 50_000, 8);
            assert!(m.x <= 1.0 + 3.0 * se.x + 1e-3, "α {alpha} cos {c}: {m} ± {se}");
            assert!(m.x > 0.3, "α {alpha} cos {c}: {m}");
            row.push(format!("{:.4}", m.x));
        }
        eprintln!(
            "rough dielectric η 1.5 α {alpha}: albedo (R + T·η'²) at cos θo 1, 0.5, 0.1, -1, -0.5, -0.1 = {}",
            row.join(", ")
        );
    }
}

#[test]
fn plastic_with_white_base_conserves_energy() {
    // α 0.33 and η 1.45, 2.37 are off the coat table's grid.
    let mut seed = 100;
    for alpha in [0.0f32, 0.05, 0.33, 1.0] {
        for eta in [1.3f32, 1.45, 2.37] {
            let b = Bxdf::plastic(Color::ONE, eta, alpha);
            let mut row = Vec::new();
            for c in [1.0f32, 0.5, 0.1, -0.5] {
                seed += 1;
                let (m, se) = albedo(&b, wo_at(c, 0.9), 40_000, seed);
                // 1 up to the coat table's error (a few 1e-4) and noise.
                assert!(
                    m.max_element() <= 1.0 + 3.0 * se.max_element() + 1e-3,
                    "α {alpha} η {eta} cos {c}: {m} ± {se}"
                );
                assert!(m.min_element() >= 0.97, "α {alpha} η {eta} cos {c}: {m} ± {se}");
                row.push(format!("{:.4} ± {:.4}", m.x, se.x));
            }
            eprintln!("plastic ρ=1 η {eta} α {alpha}: albedo at cos θo 1, 0.5, 0.1, -0.5 = {}", row.join(", "));
        }
    }
    // A longer run of one configuration: 1 within noise (measured
    // 0.99979 ± 0.00014 with 10⁶ samples).
    let (m, se) = albedo(&Bxdf::plastic(Color::ONE, 2.0, 1.0), Vec3::Z, 300_000, 99);
    eprintln!("plastic ρ=1 η 2 α 1 normal incidence, 3·10⁵ samples: {m} ± {se}");
    assert!((m.x - 1.0).abs() < 4.0 * se.x + 5e-4, "{m} ± {se}");
    // A black base leaves only the coat's reflection.
    let (m, _) = albedo(&Bxdf::plastic(Color::ZERO, 1.5, 0.0), Vec3::Z, 10_000, 1);
    assert!((m.x - 0.04).abs() < 1e-4, "{m}");
}

#[test]
fn phong_conserves_energy_and_rescales_weights() {
    // kd + ks + kr = 1: at most 1.
    for n in [0.0f32, 1.0, 10.0, 100.0, 1000.0] {
        let b = Bxdf::phong(Color::splat(0.4), 0.4, n, 0.2);
        for c in [1.0f32, 0.5, 0.1] {
            let (m, se) = albedo(&b, wo_at(c, 0.0), 100_000, 10);
            assert!(m.x <= 1.0 + 3.0 * se.x + 1e-4, "n {n} cos {c}: {m} ± {se}");
            if c == 1.0 {
                // Normal incidence: the normalised lobe keeps all of ks.
                assert!((m.x - 1.0).abs() < 3.0 * se.x + 2e-3, "n {n}: {m} ± {se}");
            }
        }
    }
    // Weights summing to more than 1 are divided by their sum.
    let Bxdf::Phong(p) = Bxdf::phong(Color::new(0.9, 0.3, 0.1), 0.8, 20.0, 0.5) else { unreachable!() };
    assert!((p.wd.max_element() + p.ws + p.wr - 1.0).abs() < 1e-6);
    assert!((p.ws / p.wr - 0.8 / 0.5).abs() < 1e-5 && (p.wd.x / p.ws - 0.9 / 0.8).abs() < 1e-5);
    let b = Bxdf::Phong(p);
    let (m, se) = albedo(&b, Vec3::Z, 100_000, 11);
    assert!(m.max_element() <= 1.0 + 3.0 * se.max_element() + 1e-4, "{m}");
    // Weights within budget are kept.
    let Bxdf::Phong(q) = Bxdf::phong(Color::splat(0.3), 0.2, 5.0, 0.1) else { unreachable!() };
    assert_eq!((q.wd, q.ws, q.wr), (Color::splat(0.3), 0.2, 0.1));
}

// ---------------------------------------------------------------------------
// Edge cases.

#[test]
fn grazing_and_extreme_samples_are_finite() {
    let edge = [0.0f32, 1e-7, 0.25, 0.5, 1.0 - f32::EPSILON / 2.0];
    let mut wos = vec![Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.6, 0.8, 0.0), wo_at(1e-7, 0.0), wo_at(-1e-7, 1.0)];
    let mut rng = Pcg32::new(21, 2);
    for _ in 0..200 {
        wos.push(random_wo(&mut rng));
    }
    for (name, b) in all_bxdfs() {
        for &wo in &wos {
            if wo.z == 0.0 {
                assert!(b.sample_f(wo, 0.5, Vec2::splat(0.5)).is_none(), "{name}: sample at grazing wo");
            }
            for &uc in &edge {
                for &u0 in &edge {
                    for &u1 in &edge {
                        let Some(s) = b.sample_f(wo, uc, Vec2::new(u0, u1)) else { continue };
                        assert!(
                            s.f.is_finite()
                                && s.f.min_element() >= 0.0
                                && s.wi.is_finite()
                                && s.pdf.is_finite()
                                && s.pdf > 0.0,
                            "{name}: wo {wo} u ({uc}, {u0}, {u1}) → {s:?}"
                        );
                        assert!(s.eta.is_finite() && s.eta > 0.0);
                        let (f, pdf) = (b.f(wo, s.wi), b.pdf(wo, s.wi));
                        assert!(f.is_finite() && pdf.is_finite() && pdf >= 0.0, "{name}: {f} {pdf}");
                    }
                }
            }
            for &wi in &wos {
                let (f, pdf) = (b.f(wo, wi), b.pdf(wo, wi));
                assert!(
                    f.is_finite() && f.min_element() >= 0.0 && pdf.is_finite() && pdf >= 0.0,
                    "{name}: wo {wo} wi {wi}: {f} {pdf}"
                );
            }
        }
    }
}

#[test]
fn bsdf_wrapper_maps_to_world_space() {
    let n = Vec3::new(0.3, -0.5, 0.8).normalize();
    let b = Bsdf::from_normal(n, Bxdf::conductor_schlick(Color::ONE, 0.0));
    let wo = (n + Vec3::new(0.2, 0.1, 0.0)).normalize();
    let s = b.sample_f(wo, 0.5, Vec2::splat(0.5)).unwrap();
    let mirror = 2.0 * wo.dot(n) * n - wo;
    assert!((s.wi - mirror).length() < 1e-5);
    let d = Bsdf::from_normal(n, Bxdf::diffuse(Color::ONE));
    let s = d.sample_f(wo, 0.5, Vec2::new(0.3, 0.8)).unwrap();
    assert!(s.wi.dot(n) > 0.0 && (d.pdf(wo, s.wi) - s.wi.dot(n) / std::f32::consts::PI).abs() < 1e-5);
    assert!((d.f(wo, s.wi) - Color::splat(std::f32::consts::FRAC_1_PI)).length() < 1e-6);
}

#[test]
fn sampled_albedo_matches_quadrature_of_f() {
    // ∫ f |cos θi| dωi by adaptive quadrature over the sphere (non-delta
    // BxDFs, transmission weighted by η'² as in `albedo`) against the
    // Monte Carlo estimate through sample_f: checks the sample weights
    // against f independently of pdf.
    let cases = [
        ("conductor α0.1 grazing", Bxdf::conductor_schlick(Color::ONE, 0.1), wo_at(0.1, 0.3)),
        ("conductor α0.3 grazing", Bxdf::conductor_schlick(Color::ONE, 0.3), wo_at(0.1, 0.3)),
        ("conductor α0.8", Bxdf::conductor(Color::new(0.2, 0.9, 1.1), Color::new(3.9, 2.4, 2.2), 0.8), wo_at(0.6, 0.3)),
        ("dielectric α0.3 outside", Bxdf::dielectric(1.5, 0.3, Color::ONE), wo_at(0.7, 0.3)),
        ("dielectric α0.5 inside", Bxdf::dielectric(1.5, 0.5, Color::ONE), wo_at(-0.8, 0.3)),
        ("plastic α0.3", Bxdf::plastic(Color::new(0.9, 0.5, 0.1), 1.5, 0.3), wo_at(0.4, 0.3)),
        ("phong n20", Bxdf::phong(Color::new(0.3, 0.2, 0.1), 0.6, 20.0, 0.0), wo_at(0.4, 0.3)),
        ("mr dielectric", mr_config("mr dielectric"), wo_at(0.4, 0.3)),
        ("mr thin transmission", mr_config("mr thin transmission"), wo_at(0.6, 0.3)),
        ("mr refraction inside", mr_config("mr refraction"), wo_at(-0.8, 0.3)),
        ("mr mixed", mr_config("mr mixed"), wo_at(0.5, 0.3)),
        ("mr sheen grazing", mr_config("mr sheen"), wo_at(0.2, 0.3)),
    ];
    for (name, b, wo) in cases {
        let eta = match b {
            Bxdf::Dielectric(d) => d.eta,
            Bxdf::MetallicRoughness(m) if !m.thin => m.ior,
            _ => 1.0,
        };
        let g = |wi: Vec3| {
            let mut v = b.f(wo, wi).x as f64 * wi.z.abs() as f64;
            if wo.z * wi.z < 0.0 {
                // η' = η(wi side)/η(wo side).
                let etap = if wo.z > 0.0 { eta } else { 1.0 / eta } as f64;
                v *= etap * etap;
            }
            v
        };
        let mut q = 0.0;
        for i in 0..8 {
            for j in 0..16 {
                let (dt, dp) = (PI / 8.0, 2.0 * PI / 16.0);
                let r = (i as f64 * dt + 1e-7, (i + 1) as f64 * dt - 1e-7, j as f64 * dp, (j + 1) as f64 * dp);
                q += integrate_rect(&g, r, 1e-7, 7);
            }
        }
        let (m, se) = albedo(&b, wo, 100_000, 5);
        eprintln!("{name}: quadrature {q:.5}, sampled {:.5} ± {:.5}", m.x, se.x);
        assert!((m.x as f64 - q).abs() < 4.0 * se.x as f64 + 2e-3, "{name}: quadrature {q} vs sampled {m} ± {se}");
    }
}

// ---------------------------------------------------------------------------
// Anisotropy, thin dielectric, diffuse transmission, layered BxDFs.

/// ∫ pdf(wo, ·) over the sphere by adaptive quadrature.
fn pdf_integral(b: &Bxdf, wo: Vec3) -> f64 {
    expected_frequencies(b, wo).iter().sum()
}

#[test]
fn anisotropic_pdf_integrates_to_the_fraction_of_samples() {
    // The pdf of a rough BxDF integrates to the probability that sample_f
    // produces a direction (visible normals whose reflection falls below
    // the surface are lost); near normal incidence that is nearly 1.
    for (name, b, wo) in [
        ("conductor", aniso_conductor(0.05, 0.4), wo_at(0.9, 0.4)),
        ("conductor grazing", aniso_conductor(0.6, 0.15), wo_at(0.2, 1.3)),
        ("dielectric", aniso_dielectric(0.4, 0.1), wo_at(0.7, 0.2)),
        ("dielectric inside", aniso_dielectric(0.3, 0.6), wo_at(-0.8, 2.0)),
    ] {
        let q = pdf_integral(&b, wo);
        let mut rng = Pcg32::new(77, 1);
        let n = 200_000;
        let ok =
            (0..n).filter(|_| b.sample_f(wo, rng.uniform(), Vec2::new(rng.uniform(), rng.uniform())).is_some()).count();
        let frac = ok as f64 / n as f64;
        let se = (frac * (1.0 - frac) / n as f64).sqrt();
        eprintln!("{name}: ∫pdf {q:.5}, sampled fraction {frac:.5}");
        assert!(q <= 1.0 + 2e-3 && (q - frac).abs() < 4.0 * se + 2e-3, "{name}: ∫pdf {q} vs {frac}");
    }
    // At normal incidence and small α nearly nothing is lost (GGX puts
    // 1 − 1/(1 + α²) of its normals beyond 45°, below 0.4% here).
    let q = pdf_integral(&aniso_conductor(0.03, 0.06), Vec3::Z);
    assert!((q - 1.0).abs() < 5e-3, "normal incidence: {q}");
}

#[test]
fn anisotropy_follows_the_tangent() {
    // αx = 0.05 along ∂p/∂u, αy = 0.5 across: seen from the normal, the
    // lobe is narrow in the u direction and wide across it.
    let n = Vec3::new(0.0, 0.0, 1.0);
    let b = aniso_conductor(0.05, 0.5);
    let tilt = |d: Vec3| (n * 0.95 + d * 0.312).normalize();
    let along_x = Bsdf::new(n, Vec3::X, b);
    let along_y = Bsdf::new(n, Vec3::Y, b);
    let fx = along_x.f(n, tilt(Vec3::X)).x;
    let fy = along_x.f(n, tilt(Vec3::Y)).x;
    assert!(fy > 100.0 * fx, "u along x: f towards x {fx}, towards y {fy}");
    // Turning the tangent by 90° swaps them.
    assert!((along_y.f(n, tilt(Vec3::X)).x - fy).abs() < 1e-4 * fy);
    assert!((along_y.f(n, tilt(Vec3::Y)).x - fx).abs() < 1e-3 * fx.max(1e-6));
    // Gram–Schmidt: a tangent not orthogonal to the normal gives the same
    // frame as its projection.
    let skew = Bsdf::new(n, Vec3::new(2.0, 0.0, 1.0), b);
    assert!((skew.frame().x - Vec3::X).length() < 1e-6 && (skew.frame().y - Vec3::Y).length() < 1e-6);
    // A degenerate tangent falls back to some frame around the normal.
    let flat = Bsdf::new(n, Vec3::ZERO, b);
    assert_eq!(flat.frame().z, n);
}

#[test]
fn thin_dielectric_reflects_the_series_and_transmits_the_rest() {
    let b = ThinDielectricBxdf { eta: 1.5 };
    for c in [1.0f32, 0.8, 0.5, 0.2, 0.05, -0.6] {
        let wo = wo_at(c, 0.7);
        // R' = R + T²R Σ R^{2k}, summed directly.
        let r = fresnel::fr_dielectric(c.abs(), 1.5);
        let t = 1.0 - r;
        let series: f32 = r + (0..200).map(|k| t * t * r * r.powi(2 * k)).sum::<f32>();
        assert!((b.reflectance(c) - series).abs() < 1e-6, "cos {c}");
        let refl = b.sample_f(wo, 0.0, Vec2::ZERO).unwrap();
        let trans = b.sample_f(wo, 0.99999, Vec2::ZERO).unwrap();
        assert!(!refl.transmission && trans.transmission && refl.specular && trans.specular);
        assert_eq!(trans.wi, -wo);
        assert!((refl.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-7);
        // Each sample carries weight 1: R' + T' = 1 exactly, no absorption.
        let w = |s: BsdfSample| s.f.x * s.wi.z.abs() / s.pdf;
        assert!((w(refl) - 1.0).abs() < 1e-5 && (w(trans) - 1.0).abs() < 1e-5);
        assert!((refl.pdf + trans.pdf - 1.0).abs() < 1e-6);
        assert!((refl.pdf - series).abs() < 1e-6);
    }
    // η = 1: all light passes.
    let s = ThinDielectricBxdf { eta: 1.0 }.sample_f(wo_at(0.3, 0.0), 0.5, Vec2::ZERO).unwrap();
    assert!(s.transmission && (s.pdf - 1.0).abs() < 1e-6);
}

#[test]
fn diffuse_transmission_splits_exactly_r_and_t() {
    let (r, t) = (Color::new(0.5, 0.3, 0.1), Color::new(0.2, 0.6, 0.3));
    let b = Bxdf::diffuse_transmission(r, t);
    for wo in [wo_at(0.9, 0.1), wo_at(0.2, 2.0), wo_at(-0.5, 1.0)] {
        let mut rng = Pcg32::new(5, 5);
        let (mut refl, mut trans) = (Color::ZERO, Color::ZERO);
        let n = 100_000;
        for _ in 0..n {
            let s = b.sample_f(wo, rng.uniform(), Vec2::new(rng.uniform(), rng.uniform())).unwrap();
            let w = s.f * s.wi.z.abs() / s.pdf;
            if s.transmission {
                trans += w / n as f32;
            } else {
                refl += w / n as f32;
            }
        }
        // Per sample the weight is r/p_r or t/p_t: only the lobe choice is
        // random (p_r = 0.5/(0.5 + 0.6)).
        let pr = 0.5f64 / 1.1;
        let se = (pr * (1.0 - pr) / n as f64).sqrt() as f32 / pr as f32;
        assert!((refl - r).abs().max_element() < 4.0 * se * r.max_element(), "{refl} vs {r}");
        assert!((trans - t).abs().max_element() < 4.0 * se * t.max_element() * 1.5, "{trans} vs {t}");
        // Analytically: ∫ f cos over each hemisphere is r and t.
        let g_r = |wi: Vec3| if wi.z * wo.z > 0.0 { (b.f(wo, wi).y * wi.z.abs()) as f64 } else { 0.0 };
        let g_t = |wi: Vec3| if wi.z * wo.z < 0.0 { (b.f(wo, wi).y * wi.z.abs()) as f64 } else { 0.0 };
        let q = |g: &dyn Fn(Vec3) -> f64| integrate_rect(g, (1e-7, PI - 1e-7, 0.0, 2.0 * PI), 1e-7, 8);
        assert!((q(&g_r) - 0.3).abs() < 1e-4 && (q(&g_t) - 0.6).abs() < 1e-4);
        assert!((pdf_integral(&b, wo) - 1.0).abs() < 1e-3);
    }
}

fn coated_diffuse(r: Color, alpha: f32, albedo: Color, max_depth: u32) -> Bxdf {
    Bxdf::CoatedDiffuse(LayeredBxdf::new(
        DielectricBxdf::new(1.5, TrowbridgeReitz::new(alpha), Color::ONE),
        DiffuseBxdf { r },
        0.01,
        albedo,
        0.0,
        max_depth,
        1,
    ))
}

fn coated_conductor(r: Color, alpha: f32, conductor_alpha: f32) -> Bxdf {
    let (eta, k) = reflectance_to_complex_ior(r);
    Bxdf::CoatedConductor(LayeredBxdf::new(
        DielectricBxdf::new(1.5, TrowbridgeReitz::new(alpha), Color::ONE),
        ConductorBxdf {
            fresnel: ConductorFresnel::Complex { eta: eta / 1.5, k: k / 1.5 },
            distrib: TrowbridgeReitz::new(conductor_alpha),
        },
        0.01,
        Color::ZERO,
        0.0,
        10,
        1,
    ))
}

/// Albedo by quadrature of the (stochastic) `f` over the hemisphere of
/// `wo`: a midpoint grid in (cos θ, φ).
fn albedo_by_f(b: &Bxdf, wo: Vec3) -> f64 {
    let (nc, np) = (96, 96);
    let mut sum = 0.0;
    for i in 0..nc {
        let c = (i as f64 + 0.5) / nc as f64;
        for j in 0..np {
            let phi = 2.0 * PI * (j as f64 + 0.5) / np as f64;
            let wi = wo_at(c as f32 * wo.z.signum(), phi as f32);
            sum += b.f(wo, wi).x as f64 * c * (1.0 / nc as f64) * (2.0 * PI / np as f64);
        }
    }
    sum
}

fn white_layer(alpha: f32, thickness: f32, max_depth: u32) -> Bxdf {
    Bxdf::CoatedDiffuse(LayeredBxdf::new(
        DielectricBxdf::new(1.5, TrowbridgeReitz::new(alpha), Color::ONE),
        DiffuseBxdf { r: Color::ONE },
        thickness,
        Color::ZERO,
        0.0,
        max_depth,
        1,
    ))
}

#[test]
fn white_coated_diffuse_reflects_nearly_all_light() {
    // A white base under a clear, infinitely thin smooth coat of index 1.5
    // loses nothing but what the walk's depth limit cuts off.
    for c in [0.95f32, 0.6, 0.3, 0.1, -0.5] {
        let wo = wo_at(c, 0.4);
        let (m, se) = albedo(&white_layer(0.0, 1e-6, 100), wo, 40_000, 3);
        eprintln!("thin smooth coat, cos {c}: sampled albedo {:.4} ± {:.4}", m.x, se.x);
        assert!(m.x < 1.0 + 4.0 * se.x && m.x > 0.97, "cos {c}: {m} ± {se}");
        // pbrt-v4's defaults (thickness 0.01, 10 events): close to 1, but
        // the slab absorbs a little (see the layered module).
        let (m, se) = albedo(&white_layer(0.0, 0.01, 10), wo, 40_000, 3);
        assert!(m.x < 1.0 + 4.0 * se.x && m.x > 0.8, "cos {c}: {m} ± {se}");
        // A rough coat loses the light its microfacets would scatter
        // again, but never creates any.
        let (m, se) = albedo(&white_layer(0.3, 1e-6, 100), wo, 40_000, 3);
        eprintln!("thin rough coat, cos {c}: sampled albedo {:.4} ± {:.4}", m.x, se.x);
        assert!(m.x < 1.0 + 4.0 * se.x && m.x > 0.55, "cos {c}: {m} ± {se}");
    }
    // f's quadrature agrees with the sampled albedo (plus, for the smooth
    // coat, its delta reflection F(cos θo), which f leaves out).
    for alpha in [0.0, 0.3] {
        let b = white_layer(alpha, 0.01, 100);
        let wo = wo_at(0.7, 0.1);
        let (m, se) = albedo(&b, wo, 40_000, 4);
        let delta = if alpha == 0.0 { fresnel::fr_dielectric(0.7, 1.5) as f64 } else { 0.0 };
        let q = albedo_by_f(&b, wo) + delta;
        eprintln!("α {alpha}: sampled {:.4} ± {:.4}, quadrature of f {q:.4}", m.x, se.x);
        assert!((q - m.x as f64).abs() < 0.03, "{q} vs {m}");
    }
}

#[test]
fn white_coated_conductor_and_scattering_layers_conserve_energy() {
    for (name, b, lower) in [
        ("coated mirror", coated_conductor(Color::ONE, 0.0, 0.0), 0.8),
        ("rough coat, rough metal", coated_conductor(Color::ONE, 0.2, 0.4), 0.3),
        ("coated diffuse in a white medium", coated_diffuse(Color::ONE, 0.0, Color::ONE, 50), 0.8),
        ("grey medium absorbs", coated_diffuse(Color::ONE, 0.2, Color::splat(0.5), 50), 0.0),
    ] {
        for c in [0.9f32, 0.4, 0.15] {
            let wo = wo_at(c, 1.1);
            let (m, se) = albedo(&b, wo, 20_000, 8);
            eprintln!("{name} cos {c}: {:.4} ± {:.4}", m.x, se.x);
            assert!(m.x < 1.0 + 4.0 * se.x + 1e-3 && m.x > lower, "{name}: {m}");
        }
    }
    // A smooth coat over a mirror with no medium is specular.
    assert!(coated_conductor(Color::ONE, 0.0, 0.0).is_specular());
    assert!(!coated_conductor(Color::ONE, 0.1, 0.0).is_specular());
}

#[test]
fn layered_estimates_are_deterministic_finite_and_consistent() {
    for (name, b) in [
        ("coated diffuse smooth", coated_diffuse(Color::new(0.8, 0.4, 0.1), 0.0, Color::ZERO, 10)),
        ("coated diffuse rough", coated_diffuse(Color::new(0.8, 0.4, 0.1), 0.3, Color::splat(0.5), 10)),
        ("coated conductor", coated_conductor(Color::new(0.9, 0.6, 0.3), 0.1, 0.3)),
    ] {
        let mut rng = Pcg32::new(31, 2);
        let mut sampled = 0;
        for _ in 0..3000 {
            let wo = random_wo(&mut rng);
            let wi = random_wo(&mut rng);
            let (f, p) = (b.f(wo, wi), b.pdf(wo, wi));
            assert!(f.is_finite() && f.min_element() >= 0.0 && p.is_finite() && p >= 0.0, "{name}");
            assert_eq!(f, b.f(wo, wi), "{name}: f is a function of (wo, wi)");
            assert_eq!(p, b.pdf(wo, wi), "{name}: pdf is a function of (wo, wi)");
            if wo.z * wi.z < 0.0 {
                assert_eq!(f, Color::ZERO);
                assert_eq!(p, 0.0);
            } else if wo.z != 0.0 {
                assert!(p > 0.0, "{name}: pdf 0 on wo's side");
            }
            let (uc, u) = (rng.uniform(), Vec2::new(rng.uniform(), rng.uniform()));
            if let Some(s) = b.sample_f(wo, uc, u) {
                assert!(s.f.is_finite() && s.pdf > 0.0 && s.pdf.is_finite() && s.wi.z * wo.z > 0.0, "{name}: {s:?}");
                assert_eq!(Some(s), b.sample_f(wo, uc, u));
                if !s.specular {
                    // The sample's pdf is the BxDF's pdf, for MIS.
                    assert_eq!(s.pdf, b.pdf(wo, s.wi), "{name}");
                    sampled += 1;
                }
            }
        }
        assert!(sampled > 1000, "{name}: {sampled}");
        // The layered pdf is a stochastic estimate, on which the adaptive
        // quadrature of `pdf_integral` never converges: a midpoint rule on
        // equal-area cells (uniform in z = cos θ and φ) is enough here.
        let (nz, nphi) = (64, 128);
        let wo = wo_at(0.7, 0.3);
        let mut q = 0.0f64;
        for i in 0..nz {
            let z = -1.0 + 2.0 * (i as f64 + 0.5) / nz as f64;
            let r = (1.0 - z * z).sqrt();
            for j in 0..nphi {
                let phi = 2.0 * PI * (j as f64 + 0.5) / nphi as f64;
                let wi = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                q += b.pdf(wo, wi) as f64;
            }
        }
        q *= 4.0 * PI / (nz * nphi) as f64;
        eprintln!("{name}: ∫ pdf = {q:.3}");
        assert!(q > 0.5 && q < 1.8, "{name}: ∫pdf {q}");
    }
}

#[test]
fn plastic_approximates_coated_diffuse() {
    // The closed-form PlasticBxdf against pbrt-v4's stochastic coated
    // diffuse with the same base, coat index and roughness (thickness
    // 0.01, no medium, a walk of 100 events): directional albedos, per
    // channel, at several angles. The largest difference is recorded in
    // PlasticBxdf's documentation.
    let mut worst = 0.0f32;
    for alpha in [0.0f32, 0.1, 0.4] {
        for r in [Color::new(0.8, 0.4, 0.1), Color::splat(0.5)] {
            let plastic = Bxdf::plastic(r, 1.5, alpha);
            let coated = coated_diffuse(r, alpha, Color::ZERO, 100);
            for c in [0.9f32, 0.5, 0.2] {
                let wo = wo_at(c, 0.3);
                let (a, _) = albedo(&plastic, wo, 40_000, 1);
                let (b, se) = albedo(&coated, wo, 40_000, 2);
                let d = (a - b).abs().max_element();
                eprintln!("α{alpha} r {r} cos {c}: plastic {a}, coated {b} ± {se}: |Δ| {d:.4}");
                worst = worst.max(d);
            }
        }
    }
    eprintln!("largest albedo difference {worst:.4}");
    // The documented figure (0.24, at α = 0.4), with statistical margin.
    assert!(worst < 0.26, "{worst}");
}

// ---------------------------------------------------------------------------
// glTF metallic-roughness.

/// A metallic-roughness BxDF: a white, rough, non-metallic dielectric
/// changed by `set`.
fn mr(set: impl FnOnce(&mut MetallicRoughnessBxdf)) -> Bxdf {
    let mut m = MetallicRoughnessBxdf { metallic: 0.0, alpha: 0.3, ..Default::default() };
    set(&mut m);
    Bxdf::MetallicRoughness(m)
}

/// The metallic-roughness parameter sets of the tests (the ones that are
/// not specular also run the χ² test).
fn mr_configs() -> Vec<(&'static str, Bxdf)> {
    let gold = Color::new(1.0, 0.766, 0.336);
    vec![
        (
            "mr diffuse",
            mr(|m| {
                m.base_color = Color::new(0.8, 0.5, 0.2);
                m.specular = 0.0;
            }),
        ),
        ("mr dielectric", mr(|m| m.base_color = Color::new(0.7, 0.4, 0.2))),
        (
            "mr metal",
            mr(|m| {
                m.base_color = gold;
                m.metallic = 1.0;
                m.alpha = 0.2;
            }),
        ),
        (
            "mr thin transmission",
            mr(|m| {
                m.base_color = Color::new(0.9, 0.8, 0.5);
                m.alpha = 0.25;
                m.transmission = 0.8;
                m.thin = true;
            }),
        ),
        (
            "mr refraction",
            mr(|m| {
                m.base_color = Color::new(0.9, 0.9, 0.8);
                m.transmission = 1.0;
                m.thin = false;
            }),
        ),
        (
            "mr clearcoat",
            mr(|m| {
                m.base_color = Color::new(0.6, 0.1, 0.1);
                m.alpha = 0.5;
                m.clearcoat = 1.0;
                m.clearcoat_alpha = 0.05;
            }),
        ),
        (
            "mr sheen",
            mr(|m| {
                m.base_color = Color::new(0.3, 0.2, 0.6);
                m.alpha = 0.6;
                m.sheen_color = Color::new(0.9, 0.8, 0.7);
                m.sheen_alpha = 0.3;
            }),
        ),
        (
            "mr mixed",
            mr(|m| {
                m.base_color = Color::new(0.8, 0.6, 0.4);
                m.metallic = 0.4;
                m.alpha = 0.15;
                m.ior = 1.8;
                m.specular = 0.7;
                m.specular_color = Color::new(1.0, 0.5, 2.0);
                m.transmission = 0.3;
                m.thin = false;
                m.clearcoat = 0.5;
                m.clearcoat_alpha = 0.1;
                m.sheen_color = Color::splat(0.5);
                m.sheen_alpha = 0.5;
            }),
        ),
        (
            "mr smooth plastic",
            mr(|m| {
                m.base_color = Color::new(0.7, 0.4, 0.2);
                m.alpha = 0.0;
            }),
        ),
        (
            "mr smooth coat over rough metal",
            mr(|m| {
                m.base_color = Color::new(0.9, 0.6, 0.3);
                m.metallic = 1.0;
                m.clearcoat = 1.0;
                m.clearcoat_alpha = 0.0;
            }),
        ),
        (
            "mr smooth metal",
            mr(|m| {
                m.base_color = gold;
                m.metallic = 1.0;
                m.alpha = 0.0;
            }),
        ),
        (
            "mr smooth thin glass",
            mr(|m| {
                m.alpha = 0.0;
                m.transmission = 1.0;
                m.thin = true;
            }),
        ),
        (
            "mr smooth glass",
            mr(|m| {
                m.base_color = Color::new(1.0, 0.9, 0.8);
                m.alpha = 0.0;
                m.transmission = 1.0;
                m.thin = false;
            }),
        ),
        ("mr gltf default", Bxdf::MetallicRoughness(MetallicRoughnessBxdf::default())),
    ]
}

fn mr_config(name: &str) -> Bxdf {
    mr_configs().into_iter().find(|(n, _)| *n == name).unwrap().1
}

fn mr_params(b: Bxdf) -> MetallicRoughnessBxdf {
    let Bxdf::MetallicRoughness(m) = b else { panic!("not metallic-roughness") };
    m
}

#[test]
fn chi2_metallic_roughness_reflection() {
    for prefix in ["mr diffuse", "mr dielectric", "mr metal", "mr gltf default"] {
        chi2_family(prefix);
    }
}

#[test]
fn chi2_metallic_roughness_transmission() {
    for prefix in ["mr thin transmission", "mr refraction"] {
        chi2_family(prefix);
    }
}

#[test]
fn chi2_metallic_roughness_layers() {
    for prefix in ["mr clearcoat", "mr sheen"] {
        chi2_family(prefix);
    }
}

#[test]
fn chi2_metallic_roughness_mixed_and_partly_smooth() {
    for prefix in ["mr mixed", "mr smooth"] {
        chi2_family(prefix);
    }
}

#[test]
fn metallic_roughness_keeps_bxdf_small() {
    // 88 bytes before the variant was added (CoatedConductor's size) with
    // 12-byte colours; 128 since `Color` is the 16-byte `Vec3A` (issue 28,
    // fourteenth sitting of docs/performance.md).
    let size = std::mem::size_of::<Bxdf>();
    eprintln!("size_of::<Bxdf>() = {size}, MetallicRoughnessBxdf {}", std::mem::size_of::<MetallicRoughnessBxdf>());
    assert!(size <= 128, "{size}");
}

#[test]
fn metallic_roughness_white_furnace_lambert_is_exact() {
    // White base, no specular layer, no metal, no transmission: pure
    // Lambert, every sample of weight exactly 1 from every wo.
    let mut rng = Pcg32::new(41, 3);
    for alpha in [0.0f32, 0.3, 1.0] {
        let b = mr(|m| {
            m.specular = 0.0;
            m.alpha = alpha;
        });
        assert!(!b.is_specular());
        for _ in 0..20_000 {
            let wo = random_wo(&mut rng);
            let Some(s) = b.sample_f(wo, rng.uniform(), Vec2::new(rng.uniform(), rng.uniform())) else { continue };
            let w = s.f * s.wi.z.abs() / s.pdf;
            assert!((w - Color::ONE).abs().max_element() < 1e-5, "α {alpha} wo {wo}: {w}");
        }
    }
}

#[test]
fn metallic_roughness_without_specular_is_lambert() {
    let base = Color::new(0.8, 0.3, 0.05);
    let mut rng = Pcg32::new(42, 3);
    for alpha in [0.0f32, 0.5] {
        let b = mr(|m| {
            m.base_color = base;
            m.specular = 0.0;
            m.alpha = alpha;
        });
        for _ in 0..5000 {
            let (wo, wi) = (random_wo(&mut rng), random_wo(&mut rng));
            let f = b.f(wo, wi);
            if wo.z * wi.z > 0.0 {
                assert!((f - base * std::f32::consts::FRAC_1_PI).abs().max_element() < 1e-7, "{f}");
            } else {
                assert_eq!(f, Color::ZERO);
            }
        }
    }
}

#[test]
fn metallic_roughness_f0_follows_the_ior() {
    assert!((MetallicRoughnessBxdf::f0_from_ior(1.5) - 0.04).abs() < 1e-7);
    assert_eq!(MetallicRoughnessBxdf::f0_from_ior(1.0), 0.0);
    assert_eq!(MetallicRoughnessBxdf::f0_from_ior(0.0), 1.0);
    assert_eq!(MetallicRoughnessBxdf::f0_from_ior(f32::INFINITY), 1.0);
    // A smooth black dielectric reflects f0 at normal incidence: 0.04 for
    // the default ior; KHR_materials_specular scales f0 by the specular
    // colour (clamped to 1) and the whole Fresnel by the specular factor.
    let black = |set: fn(&mut MetallicRoughnessBxdf)| {
        mr(|m| {
            m.base_color = Color::ZERO;
            m.alpha = 0.0;
            set(m);
        })
    };
    let weight = |b: Bxdf, c: f32| {
        let s = b.sample_f(wo_at(c, 0.2), 0.5, Vec2::splat(0.5)).unwrap();
        assert!(s.specular && !s.transmission && (s.pdf - 1.0).abs() < 1e-6, "{s:?}");
        s.f * s.wi.z.abs() / s.pdf
    };
    assert!((weight(black(|_| {}), 1.0) - Color::splat(0.04)).abs().max_element() < 1e-6);
    let b = black(|m| {
        m.specular = 0.5;
        m.specular_color = Color::new(0.5, 1.0, 40.0);
    });
    assert!((weight(b, 1.0) - Color::new(0.01, 0.02, 0.5)).abs().max_element() < 1e-6);
    // F90 is the specular factor: at grazing incidence the reflectance
    // tends to 0.5 in every channel.
    let g = weight(b, 1e-4);
    assert!((g - Color::splat(0.5)).abs().max_element() < 1e-3, "{g}");
    // KHR_materials_ior: ior 1.33 gives ((0.33)/(2.33))².
    let b = black(|m| m.ior = 1.33);
    let f0 = (0.33f32 / 2.33).powi(2);
    assert!((weight(b, 1.0) - Color::splat(f0)).abs().max_element() < 1e-6);
}

#[test]
fn smooth_metallic_roughness_metal_reflects_schlick_of_the_base_colour() {
    // metallic 1, smooth: one delta lobe of weight c + (1 − c)(1 − cos θ)⁵.
    let c = Color::new(0.9, 0.6, 0.3);
    let b = mr(|m| {
        m.base_color = c;
        m.metallic = 1.0;
        m.alpha = 0.0;
    });
    assert!(b.is_specular());
    for cos in [1.0f32, 0.7, 0.3, 0.05, -0.5, -0.02] {
        let wo = wo_at(cos, 1.3);
        let s = b.sample_f(wo, 0.3, Vec2::new(0.2, 0.9)).unwrap();
        assert!(s.specular && !s.transmission && s.pdf == 1.0);
        assert!((s.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-6);
        let w = s.f * s.wi.z.abs() / s.pdf;
        let want = c + (Color::ONE - c) * (1.0 - cos.abs()).powi(5);
        assert!((w - want).abs().max_element() < 1e-6, "cos {cos}: {w} vs {want}");
        assert_eq!(b.f(wo, s.wi), Color::ZERO);
        assert_eq!(b.pdf(wo, s.wi), 0.0);
    }
}

#[test]
fn metallic_roughness_is_specular_only_when_every_lobe_is_a_delta() {
    let smooth_metal = mr(|m| {
        m.metallic = 1.0;
        m.alpha = 0.0;
    });
    assert!(smooth_metal.is_specular());
    // A smooth dielectric still has its diffuse base.
    assert!(!mr(|m| m.alpha = 0.0).is_specular());
    // ... unless the base is black, or all of it is transmitted.
    assert!(mr(|m| {
        m.alpha = 0.0;
        m.base_color = Color::ZERO;
    })
    .is_specular());
    assert!(mr_config("mr smooth thin glass").is_specular());
    assert!(mr_config("mr smooth glass").is_specular());
    // A smooth coat over a rough metal, or sheen on a smooth metal, is not.
    assert!(!mr_config("mr smooth coat over rough metal").is_specular());
    let mut sheen = mr_params(smooth_metal);
    sheen.sheen_color = Color::splat(0.5);
    assert!(!Bxdf::MetallicRoughness(sheen).is_specular());
    // A smooth coat over a smooth metal is.
    let mut coated = mr_params(smooth_metal);
    coated.clearcoat = 1.0;
    assert!(Bxdf::MetallicRoughness(coated).is_specular());
    // Refraction with ior 1 bends nothing: a delta at any roughness.
    assert!(mr(|m| {
        m.transmission = 1.0;
        m.thin = false;
        m.ior = 1.0;
        m.alpha = 0.5;
        m.specular = 0.0;
    })
    .is_specular());
    // Regularisation widens the smooth lobes.
    let mut r = smooth_metal;
    r.regularize();
    assert!(!r.is_specular());
    assert_eq!(mr_params(r).alpha, 0.1);
}

#[test]
fn smooth_metallic_roughness_transmission_splits_fresnel() {
    // Thin glass: reflection F(cos θo) (Schlick, f0 0.04) and straight
    // transmission 1 − F, tinted; no bending, no 1/η².
    let b = mr_config("mr smooth thin glass");
    for cos in [1.0f32, 0.6, 0.2, -0.4] {
        let wo = wo_at(cos, 0.5);
        let f = 0.04 + 0.96 * (1.0 - cos.abs()).powi(5);
        let (mut refl, mut trans) = (None, None);
        for k in 0..100 {
            let s = b.sample_f(wo, (k as f32 + 0.5) / 100.0, Vec2::splat(0.5)).unwrap();
            assert!(s.specular);
            if s.transmission {
                trans = Some(s);
            } else {
                refl = Some(s);
            }
        }
        let (r, t) = (refl.unwrap(), trans.unwrap());
        assert_eq!(t.wi, -wo);
        assert_eq!(t.eta, 1.0);
        assert!((r.f.x * r.wi.z.abs() - f).abs() < 1e-6);
        assert!((t.f.x * t.wi.z.abs() - (1.0 - f)).abs() < 1e-6);
        assert!((r.pdf + t.pdf - 1.0).abs() < 1e-6);
    }
    // Refractive glass: Snell's law, η'² · T = (1 − F) · tint, and total
    // internal reflection inside beyond the critical angle.
    let b = mr_config("mr smooth glass");
    let tint = Color::new(1.0, 0.9, 0.8);
    for cos in [1.0f32, 0.5, 0.1, -1.0, -0.9, -0.75] {
        let wo = wo_at(cos, 0.5);
        let s = b.sample_f(wo, 0.999, Vec2::splat(0.5)).unwrap();
        assert!(s.specular && s.transmission, "cos {cos}: {s:?}");
        let (so, si) = ((1.0 - wo.z * wo.z).sqrt(), (1.0 - s.wi.z * s.wi.z).max(0.0).sqrt());
        assert!((so - s.eta * si).abs() < 1e-4, "Snell");
        // Schlick at the cosine in air.
        let c_air = if cos > 0.0 { cos } else { s.wi.z.abs() };
        let f = 0.04 + 0.96 * (1.0 - c_air).powi(5);
        let w = s.f * s.wi.z.abs() * s.eta * s.eta;
        assert!((w - tint * (1.0 - f)).abs().max_element() < 1e-5, "cos {cos}: {w}");
    }
    let tir = wo_at(-0.5, 0.5);
    for k in 0..20 {
        if let Some(s) = b.sample_f(tir, (k as f32 + 0.5) / 20.0, Vec2::splat(0.5)) {
            assert!(!s.transmission && (s.f.x * s.wi.z.abs() - 1.0).abs() < 1e-6, "{s:?}");
        }
    }
}

#[test]
fn metallic_roughness_sheen_matches_its_albedo_table() {
    // Sheen alone (black base, no specular layer): the sampled albedo is
    // the table's E(μ, α) times the sheen colour.
    // Where the fitted visibility gains energy (E > 1, small α at grazing
    // angles) the lobe is divided by max(1, E(cos θo), E(cos θi)): its
    // albedo is then at most min(E(cos θo), 1), and a little less where
    // E(cos θi) > 1.
    for alpha in [0.01f32, 0.05, 0.3, 1.0] {
        let b = mr(|m| {
            m.base_color = Color::ZERO;
            m.specular = 0.0;
            m.sheen_color = Color::ONE;
            m.sheen_alpha = alpha;
        });
        for c in [0.9f32, 0.5, 0.15, 0.02, -0.3] {
            let (m, se) = albedo(&b, wo_at(c, 0.7), 100_000, 21);
            let e = super::sheen::albedo(c, alpha).min(1.0);
            eprintln!("sheen α {alpha} cos {c}: sampled {:.4} ± {:.4}, table {e:.4}", m.x, se.x);
            if alpha >= 0.07 {
                assert!((m.x - e).abs() < 4.0 * se.x + 3e-3, "α {alpha} cos {c}: {m} vs {e}");
            } else {
                assert!(
                    m.x < e + 4.0 * se.x + 3e-3 && m.x > 0.9 * e - 4.0 * se.x - 1e-4,
                    "α {alpha} cos {c}: {m} vs {e}"
                );
            }
        }
    }
}

#[test]
fn metallic_roughness_conserves_energy() {
    // Every parameter set, and white variants of the worst cases: the
    // directional albedo (transmission weighted by η'²) is at most 1.
    let mut cases = mr_configs();
    let white = |set: fn(&mut MetallicRoughnessBxdf)| mr(set);
    cases.extend([
        ("white dielectric α0.3", white(|_| {})),
        ("white dielectric α1", white(|m| m.alpha = 1.0)),
        ("white smooth dielectric", white(|m| m.alpha = 0.0)),
        (
            "white dielectric ior 3",
            white(|m| {
                m.ior = 3.0;
                m.alpha = 0.1;
            }),
        ),
        (
            "white metal α0.5",
            white(|m| {
                m.metallic = 1.0;
                m.alpha = 0.5;
            }),
        ),
        (
            "white thin transmission",
            white(|m| {
                m.transmission = 1.0;
                m.thin = true;
            }),
        ),
        (
            "white refraction",
            white(|m| {
                m.transmission = 1.0;
                m.thin = false;
                m.alpha = 0.2;
            }),
        ),
        (
            "white coated",
            white(|m| {
                m.clearcoat = 1.0;
                m.clearcoat_alpha = 0.2;
            }),
        ),
        (
            "white velvet",
            white(|m| {
                m.alpha = 1.0;
                m.sheen_color = Color::ONE;
                m.sheen_alpha = 0.4;
            }),
        ),
        (
            "white fine velvet",
            white(|m| {
                m.alpha = 1.0;
                m.sheen_color = Color::ONE;
                m.sheen_alpha = 0.0;
            }),
        ),
        (
            "white everything",
            white(|m| {
                m.metallic = 0.3;
                m.transmission = 0.5;
                m.clearcoat = 1.0;
                m.clearcoat_alpha = 0.0;
                m.sheen_color = Color::ONE;
                m.sheen_alpha = 0.2;
            }),
        ),
    ]);
    let mut seed = 500;
    for (name, b) in cases {
        let mut row = Vec::new();
        for c in [0.95f32, 0.5, 0.15, 0.03, -0.5, -0.9] {
            seed += 1;
            let (m, se) = albedo(&b, wo_at(c, 0.8), 40_000, seed);
            assert!(m.max_element() <= 1.0 + 4.0 * se.max_element() + 3e-3, "{name} cos {c}: albedo {m} ± {se}");
            row.push(format!("{:.3}", m.max_element()));
        }
        eprintln!("{name}: albedo at cos θo 0.95, 0.5, 0.15, 0.03, -0.5, -0.9 = {}", row.join(", "));
    }
}

#[test]
fn white_metallic_roughness_dielectric_hands_the_base_what_the_layer_leaves() {
    // Kulla & Conty's albedo scaling: a smooth white dielectric reflects
    // exactly all light (F specularly, 1 − F diffusely), from both sides
    // and whatever the specular factor; a rough one loses only what the
    // GGX lobe's masking and shadowing lose. With a specular colour the
    // base is weighted by the largest channel's 1 − F
    // (KHR_materials_specular's max_value), so only that channel keeps all.
    let mut seed = 900;
    for (name, b, lower) in [
        ("smooth", mr(|m| m.alpha = 0.0), 1.0),
        (
            "smooth, specular colour",
            mr(|m| {
                m.alpha = 0.0;
                m.specular = 0.6;
                m.specular_color = Color::new(3.0, 1.0, 0.2);
                m.ior = 1.7;
            }),
            1.0,
        ),
        ("rough α0.1", mr(|m| m.alpha = 0.1), 0.9),
        ("rough α0.5", mr(|m| m.alpha = 0.5), 0.85),
    ] {
        for c in [1.0f32, 0.7, 0.3, 0.08, -0.6] {
            seed += 1;
            let (m, se) = albedo(&b, wo_at(c, 0.4), 100_000, seed);
            eprintln!("white dielectric {name} cos {c}: {m} ± {se}");
            assert!(m.max_element() <= 1.0 + 4.0 * se.max_element() + 2e-3, "{name} cos {c}: {m} ± {se}");
            assert!(m.max_element() >= lower - 4.0 * se.max_element() - 2e-3, "{name} cos {c}: {m} ± {se}");
            assert!(m.min_element() >= 0.85, "{name} cos {c}: {m} ± {se}");
        }
    }
}

#[test]
fn metallic_roughness_clearcoat_and_sheen_follow_the_layering() {
    // Smooth clearcoat over a white Lambertian base without specular: the
    // coat's mirror reflects clearcoat · F_c(cos θo) and the base is
    // weighted by 1 − clearcoat · max(F_c(cos θo), F_c(cos θi)).
    let fc = |c: f32| 0.04 + 0.96 * (1.0 - c.abs()).powi(5);
    let b = mr(|m| {
        m.specular = 0.0;
        m.clearcoat = 0.8;
        m.clearcoat_alpha = 0.0;
    });
    for cos in [1.0f32, 0.6, 0.2] {
        let wo = wo_at(cos, 0.1);
        let s = b.sample_f(wo, 0.0, Vec2::splat(0.5)).unwrap();
        assert!(s.specular);
        let p = mr_params(b).lobe_probabilities(wo)[0];
        assert!((s.pdf - p).abs() < 1e-7);
        assert!((s.f.x * s.wi.z.abs() - 0.8 * fc(cos)).abs() < 1e-6);
        let wi = wo_at(0.4, 2.0);
        let want = (1.0 - 0.8 * fc(cos).max(fc(0.4))) / std::f32::consts::PI;
        assert!((b.f(wo, wi).x - want).abs() < 1e-6);
    }
    // Sheen over a Lambertian base: f = sheen f_sheen + S base/π with
    // S = 1 − max(sheen) max(E(cos θo), E(cos θi)).
    let b = mr(|m| {
        m.specular = 0.0;
        m.sheen_color = Color::new(0.2, 0.4, 0.6);
        m.sheen_alpha = 0.5;
    });
    let (wo, wi) = (wo_at(0.3, 0.0), wo_at(0.7, 2.5));
    let e = |c: f32| super::sheen::albedo(c, 0.5);
    let s = 1.0 - 0.6 * e(0.3).max(e(0.7));
    let want = Color::new(0.2, 0.4, 0.6) * super::sheen::brdf(wo, wi, 0.5) + Color::splat(s / std::f32::consts::PI);
    assert!((b.f(wo, wi) - want).abs().max_element() < 1e-6);
}

/// Light sampling tests visibility before a BxDF whose value costs more
/// than a shadow ray (`Bxdf::f_costs_more_than_a_ray`): that is every
/// coated BxDF on a pair that may reflect, and nothing else; where a
/// coated pair is answered `false`, its value and density are 0 (so
/// skipping the ray loses nothing); and a coated value is the same bits
/// whenever it is asked for (its walk's random numbers are a hash of the
/// pair), so evaluating it after the ray changes no image.
#[test]
fn only_coated_pairs_that_may_reflect_cost_more_than_a_ray() {
    let mut rng = Pcg32::new(29, 3);
    let coated = [
        coated_diffuse(Color::new(0.7, 0.4, 0.2), 0.1, Color::ZERO, 10),
        coated_diffuse(Color::new(0.3, 0.6, 0.2), 0.3, Color::new(0.5, 0.5, 0.5), 10),
        coated_conductor(Color::new(0.9, 0.6, 0.3), 0.0, 0.2),
    ];
    let mut walked = 0;
    for _ in 0..2000 {
        let (wo, wi) = (random_wo(&mut rng), random_wo(&mut rng));
        for (name, b) in all_bxdfs() {
            assert!(!b.f_costs_more_than_a_ray(wo, wi), "{name}");
        }
        for b in &coated {
            let dear = b.f_costs_more_than_a_ray(wo, wi);
            assert_eq!(dear, wo.z * wi.z > 0.0, "{wo} {wi}");
            let (f, pdf) = (b.f(wo, wi), b.pdf(wo, wi));
            if dear {
                walked += 1;
                assert_eq!(b.f(wo, wi).to_array().map(f32::to_bits), f.to_array().map(f32::to_bits));
                assert_eq!(b.pdf(wo, wi).to_bits(), pdf.to_bits());
            } else {
                assert_eq!((f, pdf), (Color::ZERO, 0.0), "{wo} {wi}");
            }
        }
    }
    assert!(walked > 2000, "{walked}");
}
