//! Fresnel reflectance: the fraction of light a smooth interface reflects
//! (PBRT 4th ed., §9.3).
//!
//! * [`fr_dielectric`]: two dielectrics, unpolarised light, both sides of
//!   the interface, total internal reflection.
//! * [`fr_complex`] / [`fr_conductor`]: a dielectric over a conductor with
//!   complex index of refraction `η + i·k`, the exact formula evaluated with
//!   complex arithmetic (PBRT 4th ed., §9.3.6).
//! * [`fr_schlick`]: Schlick's approximation from the colour at normal
//!   incidence (Schlick, "An Inexpensive BRDF Model for Physically-based
//!   Rendering", Computer Graphics Forum 13(3), 1994).

use crate::color::Color;
use crate::geometry::hypot;

/// Unpolarised Fresnel reflectance of a dielectric interface.
///
/// `cos_theta_i` is the cosine between the direction and the normal and
/// `eta` the relative index of refraction, transmitted side over incident
/// side *for a direction on the normal's side*. A negative cosine means the
/// direction is on the other side: the interface is then seen with index
/// `1/eta`. Beyond the critical angle (total internal reflection) the result
/// is 1.
///
/// With `η = η_t/η_i`, Snell's law gives `sin θt = sin θi / η`, and the
/// Fresnel equations for the two polarisations are
/// `r∥ = (η cos θi − cos θt)/(η cos θi + cos θt)` and
/// `r⊥ = (cos θi − η cos θt)/(cos θi + η cos θt)`; unpolarised light
/// reflects their mean square (PBRT 4th ed., eq. 9.4–9.6).
pub fn fr_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    let mut cos_i = cos_theta_i.clamp(-1.0, 1.0);
    let mut eta = eta;
    if cos_i < 0.0 {
        // The direction is on the far side: swap the media.
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        // Total internal reflection (also the exact grazing limit).
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parl * r_parl + r_perp * r_perp)
}

/// Hemispherical (cosine-weighted) average of [`fr_dielectric`] for light
/// arriving uniformly, diffusely, on the side of the normal:
/// `F̄ = ∫₀¹ F(μ, η) 2μ dμ`.
///
/// The integrand is smooth for `η ≥ 1` (no critical angle on this side), so
/// composite Simpson with 32 intervals is accurate to about 1e-6.
pub fn fr_dielectric_hemispherical(eta: f32) -> f32 {
    const N: usize = 32;
    let h = 1.0 / N as f32;
    let mut sum = 0.0;
    for i in 0..=N {
        let mu = i as f32 * h;
        let w = if i == 0 || i == N {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        sum += w * fr_dielectric(mu, eta) * 2.0 * mu;
    }
    sum * h / 3.0
}

/// `N` complex numbers side by side, just enough arithmetic for
/// [`fr_complex`] and [`fr_conductor`]: each operation is a loop over the
/// lanes, which the compiler turns into vector instructions, and does in
/// every lane what one complex number's operation does.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Complex<const N: usize> {
    re: [f32; N],
    im: [f32; N],
}

impl<const N: usize> Complex<N> {
    fn new(re: [f32; N], im: [f32; N]) -> Self {
        Self { re, im }
    }
    fn real(re: f32) -> Self {
        Self { re: [re; N], im: [0.0; N] }
    }
    fn lanes(f: impl Fn(usize) -> (f32, f32)) -> Self {
        let (mut re, mut im) = ([0.0; N], [0.0; N]);
        for j in 0..N {
            (re[j], im[j]) = f(j);
        }
        Self { re, im }
    }
    fn add(self, o: Self) -> Self {
        Self::lanes(|j| (self.re[j] + o.re[j], self.im[j] + o.im[j]))
    }
    fn sub(self, o: Self) -> Self {
        Self::lanes(|j| (self.re[j] - o.re[j], self.im[j] - o.im[j]))
    }
    fn mul(self, o: Self) -> Self {
        Self::lanes(|j| {
            let (a, b, c, d) = (self.re[j], self.im[j], o.re[j], o.im[j]);
            (a * c - b * d, a * d + b * c)
        })
    }
    fn div(self, o: Self) -> Self {
        Self::lanes(|j| {
            let (a, b, c, e) = (self.re[j], self.im[j], o.re[j], o.im[j]);
            let d = c * c + e * e;
            ((a * c + b * e) / d, (b * c - a * e) / d)
        })
    }
    /// Squared magnitudes.
    fn norm(self) -> [f32; N] {
        std::array::from_fn(|j| self.re[j] * self.re[j] + self.im[j] * self.im[j])
    }
    /// Principal square roots: `√((|z|+re)/2) + i·sign(im)·√((|z|−re)/2)`,
    /// with `|z|` the library's [`hypot`].
    fn sqrt(self) -> Self {
        Self::lanes(|j| {
            let m = hypot(self.re[j], self.im[j]);
            let re = (0.5 * (m + self.re[j])).max(0.0).sqrt();
            let im = (0.5 * (m - self.re[j])).max(0.0).sqrt();
            (re, if self.im[j] < 0.0 { -im } else { im })
        })
    }
}

/// Fresnel reflectance of a conductor of complex index `eta + i·k` (one
/// wavelength), for light from the outside at `cos_theta_i` (clamped to
/// [0, 1]).
///
/// The dielectric equations hold unchanged with a complex index: Snell's
/// law gives a complex `cos θt = √(1 − sin²θi/η²)`, and the reflectance is
/// the mean of `|r∥|²` and `|r⊥|²` (PBRT 4th ed., §9.3.6, eq. 9.4–9.6 over
/// the complex numbers). For `k = 0` this is [`fr_dielectric`].
pub fn fr_complex(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
    fr_complex_lanes([cos_theta_i], [eta], [k])[0]
}

/// [`fr_complex`] per RGB channel: the three channels in the lanes of one
/// computation (the fourth repeats the first), so that its divisions and
/// square roots run side by side.
pub fn fr_conductor(cos_theta_i: f32, eta: Color, k: Color) -> Color {
    let r = fr_complex_lanes([cos_theta_i; 4], [eta.x, eta.y, eta.z, eta.x], [k.x, k.y, k.z, k.x]);
    Color::new(r[0], r[1], r[2])
}

/// [`fr_complex`] of each lane: `cos_theta_i[j]` and the index `eta[j] +
/// i·k[j]`. Every lane runs the operations of one [`fr_complex`], so its
/// value is that lane's [`fr_complex`] bit for bit (the path integrator's
/// conductor lanes take one channel of many vertices at once through it).
#[inline(always)]
pub(crate) fn fr_complex_lanes<const N: usize>(cos_theta_i: [f32; N], eta: [f32; N], k: [f32; N]) -> [f32; N] {
    let cos_i = cos_theta_i.map(|c| c.clamp(0.0, 1.0));
    let eta = Complex::new(eta, k);
    let sin2_i = Complex::new(cos_i.map(|c| 1.0 - c * c), [0.0; N]);
    let sin2_t = sin2_i.div(eta.mul(eta));
    let cos_t = Complex::real(1.0).sub(sin2_t).sqrt();
    let ci = Complex::new(cos_i, [0.0; N]);
    let r_parl = eta.mul(ci).sub(cos_t).div(eta.mul(ci).add(cos_t));
    let r_perp = ci.sub(eta.mul(cos_t)).div(ci.add(eta.mul(cos_t)));
    let (parl, perp) = (r_parl.norm(), r_perp.norm());
    std::array::from_fn(|j| {
        let r = 0.5 * (parl[j] + perp[j]);
        if r.is_finite() {
            r.clamp(0.0, 1.0)
        } else {
            1.0
        }
    })
}

/// Schlick's approximation `F = r0 + (1 − r0)(1 − cos θ)⁵` with a colour
/// `r0` at normal incidence; `cos_theta_i` is taken in absolute value.
pub fn fr_schlick(cos_theta_i: f32, r0: Color) -> Color {
    let m = (1.0 - cos_theta_i.abs().min(1.0)).max(0.0);
    let m2 = m * m;
    r0 + (Color::ONE - r0) * (m2 * m2 * m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_normal_incidence_is_r0() {
        // ((1.5 − 1)/(1.5 + 1))² = 0.04, from either side.
        assert!((fr_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fr_dielectric(-1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fr_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(fr_dielectric(0.7, 1.0), 0.0);
    }

    #[test]
    fn dielectric_total_internal_reflection_beyond_the_critical_angle() {
        // Inside glass (cos < 0 for η = 1.5), the critical angle is
        // asin(1/1.5) ≈ 41.8°.
        let crit = (1.0f32 / 1.5).asin();
        let just_below = (crit - 0.01).cos();
        let just_above = (crit + 0.01).cos();
        assert!(fr_dielectric(-just_below, 1.5) < 1.0);
        assert_eq!(fr_dielectric(-just_above, 1.5), 1.0);
        assert_eq!(fr_dielectric(0.3, 1.0 / 1.5), 1.0);
        // Outside, no TIR; at grazing all light reflects.
        assert!(fr_dielectric(0.3, 1.5) < 1.0);
        assert_eq!(fr_dielectric(0.0, 1.5), 1.0);
    }

    #[test]
    fn dielectric_is_monotone_outside_and_in_range() {
        let mut prev = 0.0;
        for i in (0..=100).rev() {
            let c = i as f32 / 100.0;
            let f = fr_dielectric(c, 1.5);
            assert!((0.0..=1.0).contains(&f) && f >= prev - 1e-6, "{c} {f}");
            prev = f;
        }
    }

    #[test]
    fn conductor_formula_reduces_to_dielectric_for_k_zero() {
        for eta in [1.2f32, 1.5, 2.4] {
            for i in 0..=20 {
                let c = i as f32 / 20.0;
                let a = fr_complex(c, eta, 0.0);
                let b = fr_dielectric(c, eta);
                assert!((a - b).abs() < 1e-5, "η {eta} cos {c}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn conductor_normal_incidence_and_grazing() {
        // ((η−1)² + k²)/((η+1)² + k²) at normal incidence; gold-ish values.
        let (eta, k) = (0.2f32, 3.0f32);
        let r0 = ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k);
        assert!((fr_complex(1.0, eta, k) - r0).abs() < 1e-5);
        assert!((fr_complex(0.0, eta, k) - 1.0).abs() < 1e-5);
        let c = fr_conductor(0.5, Color::new(0.2, 0.9, 1.1), Color::new(3.9, 2.4, 2.2));
        assert!(c.is_finite() && c.min_element() > 0.0 && c.max_element() <= 1.0);
    }

    #[test]
    fn schlick_end_points() {
        let r0 = Color::new(0.9, 0.5, 0.1);
        assert!((fr_schlick(1.0, r0) - r0).length() < 1e-6);
        assert!((fr_schlick(0.0, r0) - Color::ONE).length() < 1e-6);
    }

    #[test]
    fn hemispherical_average_matches_known_value() {
        // Against a fine midpoint rule; for η = 1.5 the diffuse
        // reflectance from outside is about 0.092.
        let f = fr_dielectric_hemispherical(1.5);
        let mut fine = 0.0f64;
        let n = 100_000;
        for i in 0..n {
            let mu = (i as f64 + 0.5) / n as f64;
            fine += fr_dielectric(mu as f32, 1.5) as f64 * 2.0 * mu / n as f64;
        }
        assert!((f as f64 - fine).abs() < 2e-5, "{f} {fine}");
        assert!((f - 0.0918).abs() < 0.002, "{f}");
    }

    /// The conductor's reflectance one complex operation at a time, on
    /// plain floats (the form before the lanes): the reference that the
    /// lane code must equal bit for bit.
    fn fr_complex_one_by_one(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
        type C = (f32, f32);
        let add = |a: C, b: C| (a.0 + b.0, a.1 + b.1);
        let sub = |a: C, b: C| (a.0 - b.0, a.1 - b.1);
        let mul = |a: C, b: C| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let div = |a: C, b: C| {
            let d = b.0 * b.0 + b.1 * b.1;
            ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        };
        let sqrt = |a: C| {
            let m = crate::geometry::hypot(a.0, a.1);
            let (re, im) = ((0.5 * (m + a.0)).max(0.0).sqrt(), (0.5 * (m - a.0)).max(0.0).sqrt());
            (re, if a.1 < 0.0 { -im } else { im })
        };
        let norm = |a: C| a.0 * a.0 + a.1 * a.1;
        let cos_i = cos_theta_i.clamp(0.0, 1.0);
        let eta = (eta, k);
        let cos_t = sqrt(sub((1.0, 0.0), div((1.0 - cos_i * cos_i, 0.0), mul(eta, eta))));
        let ci = (cos_i, 0.0);
        let r_parl = div(sub(mul(eta, ci), cos_t), add(mul(eta, ci), cos_t));
        let r_perp = div(sub(ci, mul(eta, cos_t)), add(ci, mul(eta, cos_t)));
        let r = 0.5 * (norm(r_parl) + norm(r_perp));
        if r.is_finite() {
            r.clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// `fr_complex` and every channel of `fr_conductor` (three channels in
    /// vector lanes) are the one-by-one computation bit for bit: random
    /// angles and indices of metals and of dielectrics, with normal and
    /// grazing incidence, angles outside [0, 1], zero and huge indices.
    #[test]
    fn conductor_lanes_equal_the_one_by_one_formula() {
        let mut rng = crate::sampling::Pcg32::new(21, 4);
        let specials = [0.0, 1.0, 1e-30, 1e30, 0.5];
        for n in 0..20_000 {
            let mut cos = rng.uniform();
            match n % 9 {
                0 => cos = 0.0,
                1 => cos = 1.0,
                2 => cos = -0.3,
                3 => cos = 1.7,
                _ => {}
            }
            let mut pick = || if n % 13 == 0 { specials[(n / 13) % 5] } else { 5.0 * rng.uniform() };
            let (eta, k) = (Color::new(pick(), pick(), pick()), Color::new(pick(), pick(), pick()));
            let k = if n % 7 == 0 { Color::ZERO } else { k };
            let lanes = fr_conductor(cos, eta, k);
            for c in 0..3 {
                let expected = fr_complex_one_by_one(cos, eta[c], k[c]);
                assert_eq!(lanes[c].to_bits(), expected.to_bits(), "channel {c}: cos {cos}, η {}, k {}", eta[c], k[c]);
                assert_eq!(fr_complex(cos, eta[c], k[c]).to_bits(), expected.to_bits());
            }
        }
    }
}
