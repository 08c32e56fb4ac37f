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

/// A complex number, just enough arithmetic for [`fr_complex`].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Complex {
    re: f32,
    im: f32,
}

impl Complex {
    fn new(re: f32, im: f32) -> Self {
        Self { re, im }
    }
    fn real(re: f32) -> Self {
        Self { re, im: 0.0 }
    }
    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: Self) -> Self {
        Self::new(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)
    }
    fn div(self, o: Self) -> Self {
        let d = o.re * o.re + o.im * o.im;
        Self::new((self.re * o.re + self.im * o.im) / d, (self.im * o.re - self.re * o.im) / d)
    }
    /// Squared magnitude.
    fn norm(self) -> f32 {
        self.re * self.re + self.im * self.im
    }
    /// Principal square root: `√((|z|+re)/2) + i·sign(im)·√((|z|−re)/2)`.
    fn sqrt(self) -> Self {
        let m = self.re.hypot(self.im);
        let re = (0.5 * (m + self.re)).max(0.0).sqrt();
        let im = (0.5 * (m - self.re)).max(0.0).sqrt();
        Self::new(re, if self.im < 0.0 { -im } else { im })
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
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let eta = Complex::new(eta, k);
    let sin2_i = Complex::real(1.0 - cos_i * cos_i);
    let sin2_t = sin2_i.div(eta.mul(eta));
    let cos_t = Complex::real(1.0).sub(sin2_t).sqrt();
    let ci = Complex::real(cos_i);
    let r_parl = eta.mul(ci).sub(cos_t).div(eta.mul(ci).add(cos_t));
    let r_perp = ci.sub(eta.mul(cos_t)).div(ci.add(eta.mul(cos_t)));
    let r = 0.5 * (r_parl.norm() + r_perp.norm());
    if r.is_finite() {
        r.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// [`fr_complex`] per RGB channel.
pub fn fr_conductor(cos_theta_i: f32, eta: Color, k: Color) -> Color {
    Color::new(
        fr_complex(cos_theta_i, eta.x, k.x),
        fr_complex(cos_theta_i, eta.y, k.y),
        fr_complex(cos_theta_i, eta.z, k.z),
    )
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
}
