//! A homogeneous medium: the same coefficients everywhere, so
//! transmittance and distance sampling have closed forms (PBRT 4th ed.,
//! §11.1–11.2; §11.4.1 for `HomogeneousMedium`).
//!
//! Along a ray in the medium, the radiance arriving at the origin is the
//! volume rendering equation (PBRT 4th ed., eq. 14.3)
//!
//! `L(o) = T(t_s) L_s + ∫₀^{t_s} T(t) (σₐ Lₑ + σₛ ∫ p(ω, ω') L dω') dt`,
//!
//! with transmittance `T(t) = exp(−σₜ t)` (Beer–Lambert), `σₜ = σₐ + σₛ`,
//! `t_s` the distance to the next surface and `L_s` what leaves it.
//!
//! # Chromatic media in RGB
//!
//! `σₜ` differs between channels, so no single exponential distribution
//! of distances suits all three. [`HomogeneousMedium::sample`] draws a
//! channel `c` with probability `p_c` proportional to the path throughput
//! in that channel, then a distance with density `σₜ,c exp(−σₜ,c t)`, and
//! weights the sample by the *one-sample* MIS (balance heuristic) over the
//! three channels, i.e. divides by the mixture density
//! `Σ_c p_c σₜ,c exp(−σₜ,c t)` (or, past the surface, by
//! `Σ_c p_c exp(−σₜ,c t_s)`). This is the spectral MIS that spectral
//! renderers use across wavelengths (Wilkie et al., "Hero Wavelength
//! Spectral Sampling", EGSR 2014; for RGB, PBRT 3rd ed. §15.2.2 picks the
//! channel uniformly), with the throughput-weighted channel choice of
//! Chiang et al., "Practical and Controllable Subsurface Scattering for
//! Production Path Tracing" (SIGGRAPH 2016 talk): channels in which the
//! path carries no light are not sampled. Any `p_c` gives an unbiased
//! estimate as long as every channel that carries light has `p_c > 0`.
//!
//! A medium that does not scatter (`σₛ = 0`) and does not emit needs no
//! distances at all: the path goes on to the surface with weight `T(t_s)`,
//! exactly (a coloured glass's absorption costs no noise).

use super::phase::HenyeyGreenstein;
use super::MediumError;
use crate::color::Color;

/// A medium with constant absorption `σₐ`, scattering `σₛ` (per unit of
/// scene length), Henyey–Greenstein phase function and emission `Lₑ`.
#[derive(Clone, Debug, PartialEq)]
pub struct HomogeneousMedium {
    sigma_a: Color,
    sigma_s: Color,
    sigma_t: Color,
    le: Color,
    phase: HenyeyGreenstein,
}

/// Where a path collides in a medium, drawn before the segment is sampled
/// ([`HomogeneousMedium::free_flight`]): drawn once, it both bounds the
/// segment's ray query and samples the segment
/// ([`HomogeneousMedium::sample_flight`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeFlight {
    /// The channel probabilities.
    p: Color,
    /// The distance to the collision.
    t: f32,
}

impl FreeFlight {
    /// The distance along the ray (in units of its direction, which must
    /// be unit) at which the path collides in the medium, if it reaches no
    /// surface first: infinite where it cannot collide.
    #[inline]
    pub fn distance(&self) -> f32 {
        self.t
    }
}

/// What happened to a ray segment in a medium ([`HomogeneousMedium::sample`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MediumEvent {
    /// The ray scatters at distance `t` (`t < t_max`): multiply the path
    /// throughput β by `weight` and continue from there with the phase
    /// function. `emission` is the medium's emission estimate, to add
    /// (times β *before* the update) to the path's radiance.
    Scatter {
        /// Distance along the ray (in units of the ray's direction, which
        /// must be unit).
        t: f32,
        /// `T(t) σₛ / p(t)`.
        weight: Color,
        /// `T(t) σₐ Lₑ / p(t)`.
        emission: Color,
    },
    /// The ray reaches `t_max` (the surface, or infinity): multiply β by
    /// `weight`, `T(t_max) / P(t ≥ t_max)`.
    Pass {
        /// `T(t_max) / P(t ≥ t_max)`.
        weight: Color,
    },
}

impl HomogeneousMedium {
    /// A medium with `σₐ = scale · sigma_a`, `σₛ = scale · sigma_s`, phase
    /// asymmetry `g` and emitted radiance `le` (pbrt-v4's parameters). Every
    /// value must be finite, the coefficients, `scale` and `le` ≥ 0, and
    /// `|g| < 1`.
    pub fn new(sigma_a: Color, sigma_s: Color, scale: f32, g: f32, le: Color) -> Result<Self, MediumError> {
        let ok = |c: Color| c.is_finite() && c.min_element() >= 0.0;
        if !ok(sigma_a) {
            return Err(MediumError::Coefficient("sigma_a", sigma_a));
        }
        if !ok(sigma_s) {
            return Err(MediumError::Coefficient("sigma_s", sigma_s));
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(MediumError::Scale(scale));
        }
        if !(g.is_finite() && g.abs() < 1.0) {
            return Err(MediumError::Asymmetry(g));
        }
        if !ok(le) {
            return Err(MediumError::Coefficient("Le", le));
        }
        let (sigma_a, sigma_s) = (sigma_a * scale, sigma_s * scale);
        if !(sigma_a + sigma_s).is_finite() {
            return Err(MediumError::Coefficient("sigma_a + sigma_s", sigma_a + sigma_s));
        }
        Ok(Self { sigma_a, sigma_s, sigma_t: sigma_a + sigma_s, le, phase: HenyeyGreenstein::new(g) })
    }

    /// Absorption coefficient σₐ (scale applied).
    pub fn sigma_a(&self) -> Color {
        self.sigma_a
    }

    /// Scattering coefficient σₛ (scale applied).
    pub fn sigma_s(&self) -> Color {
        self.sigma_s
    }

    /// Emitted radiance Lₑ (emission per unit length is σₐ Lₑ).
    pub fn le(&self) -> Color {
        self.le
    }

    /// The phase function.
    pub fn phase(&self) -> &HenyeyGreenstein {
        &self.phase
    }

    /// Whether paths through the medium need distance sampling: it
    /// scatters or emits somewhere.
    #[inline]
    fn samples_distances(&self) -> bool {
        self.sigma_s.max_element() > 0.0 || (self.sigma_a * self.le).max_element() > 0.0
    }

    /// Transmittance `exp(−σₜ d)` over distance `d ≥ 0` (`d` may be
    /// infinite: 0 in every channel with σₜ > 0, 1 in the others).
    #[inline]
    pub fn transmittance(&self, d: f32) -> Color {
        Color::new(tr(self.sigma_t.x, d), tr(self.sigma_t.y, d), tr(self.sigma_t.z, d))
    }

    /// The free flight of a path of throughput `beta` in this medium,
    /// drawn with `u_channel` and `u_distance`: a channel with probability
    /// ∝ β (uniform where β is not usable), then the distance to the next
    /// collision in that channel, infinite where its σₜ is 0, or for a
    /// medium that needs no distances. [`HomogeneousMedium::sample_flight`]
    /// scatters exactly where [`FreeFlight::distance`] is below its
    /// `t_max`, at that distance. So a path needs the surface it would
    /// reach only when that surface is no farther: a ray query bounded by
    /// the distance (inclusively) finds the surface or, where the path
    /// collides in the medium first, nothing (and builds no hit record).
    #[inline]
    pub fn free_flight(&self, beta: Color, u_channel: f32, u_distance: f32) -> FreeFlight {
        let b = beta.max(Color::ZERO);
        let sum = b.x + b.y + b.z;
        let p = if sum > 0.0 && sum.is_finite() { b / sum } else { Color::splat(1.0 / 3.0) };
        if !self.samples_distances() {
            return FreeFlight { p, t: f32::INFINITY };
        }
        let c = if u_channel < p.x {
            0
        } else if u_channel < p.x + p.y || p.z == 0.0 {
            1
        } else {
            2
        };
        let sigma = self.sigma_t[c];
        let t = if sigma > 0.0 { -(1.0 - u_distance).ln() / sigma } else { f32::INFINITY };
        FreeFlight { p, t }
    }

    /// Sample the ray segment `[0, t_max)` (unit direction; `t_max` may be
    /// infinite) for a path of throughput `beta`, with uniform `u_channel`
    /// and `u_distance` (see the module docs): [`HomogeneousMedium::sample_flight`]
    /// of their [`HomogeneousMedium::free_flight`].
    pub fn sample(&self, t_max: f32, beta: Color, u_channel: f32, u_distance: f32) -> MediumEvent {
        self.sample_flight(self.free_flight(beta, u_channel, u_distance), t_max)
    }

    /// The segment `[0, t_max)` sampled with a free flight drawn before
    /// (by a caller that bounded its ray query with it).
    pub fn sample_flight(&self, flight: FreeFlight, t_max: f32) -> MediumEvent {
        if !self.samples_distances() {
            return MediumEvent::Pass { weight: self.transmittance(t_max) };
        }
        let FreeFlight { p, t } = flight;
        if t < t_max {
            let tr = self.transmittance(t);
            // Mixture density of distances: Σ p_c σₜ,c T_c(t).
            let pdf = (p * self.sigma_t * tr).element_sum();
            if !(pdf > 0.0 && pdf.is_finite()) {
                return MediumEvent::Pass { weight: Color::ZERO };
            }
            MediumEvent::Scatter { t, weight: tr * self.sigma_s / pdf, emission: tr * self.sigma_a * self.le / pdf }
        } else {
            let tr = self.transmittance(t_max);
            // Probability of passing: Σ p_c T_c(t_max).
            let pass = (p * tr).element_sum();
            let weight = if pass > 0.0 { tr / pass } else { Color::ZERO };
            MediumEvent::Pass { weight }
        }
    }
}

/// `exp(−σ d)` with `0 · ∞ = 0` (no extinction: transmittance 1 at any
/// distance).
#[inline]
fn tr(sigma: f32, d: f32) -> f32 {
    if sigma == 0.0 {
        1.0
    } else {
        (-sigma * d).exp()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    fn medium(a: [f32; 3], s: [f32; 3]) -> HomogeneousMedium {
        HomogeneousMedium::new(Color::from_array(a), Color::from_array(s), 1.0, 0.0, Color::ZERO).unwrap()
    }

    #[test]
    fn transmittance_is_beer_lambert() {
        let m = medium([0.5, 1.0, 0.0], [0.5, 0.0, 0.0]);
        let t = m.transmittance(2.0);
        assert_eq!(t, Color::new((-2.0f32).exp(), (-2.0f32).exp(), 1.0));
        assert_eq!(m.transmittance(f32::INFINITY), Color::new(0.0, 0.0, 1.0));
        assert_eq!(m.transmittance(0.0), Color::ONE);
    }

    /// E[β after the segment] with a constant radiance `l_surface` behind
    /// it and `l_scatter` arriving at every scattering point must equal
    /// `T(t_s) L_s + (1 − T(t_s)) σₛ/σₜ L_in` per channel (the integral of
    /// the volume rendering equation for constant in-scattered light).
    #[test]
    fn estimates_the_volume_rendering_integral_per_channel() {
        let m = medium([0.2, 0.9, 0.05], [0.6, 0.1, 1.5]);
        let mut rng = Pcg32::new(11, 3);
        for (t_s, beta) in [(1.3f32, Color::ONE), (0.4, Color::new(0.2, 1.0, 0.6)), (3.0, Color::new(1.0, 0.0, 0.5))] {
            let (l_s, l_in) = (Color::new(1.0, 2.0, 0.5), Color::new(0.7, 0.3, 1.1));
            let n = 400_000;
            let mut sum = Color::ZERO;
            for _ in 0..n {
                match m.sample(t_s, beta, rng.uniform(), rng.uniform()) {
                    MediumEvent::Scatter { t, weight, .. } => {
                        assert!(t < t_s);
                        sum += beta * weight * l_in;
                    }
                    MediumEvent::Pass { weight } => sum += beta * weight * l_s,
                }
            }
            let est = sum / n as f32;
            let tr = m.transmittance(t_s);
            let want = beta * (tr * l_s + (Color::ONE - tr) * m.sigma_s / m.sigma_t * l_in);
            for c in 0..3 {
                assert!((est[c] - want[c]).abs() < 0.01 * want[c].max(0.05), "t_s {t_s} channel {c}: {est} vs {want}");
            }
        }
    }

    #[test]
    fn a_pure_absorber_passes_with_its_transmittance() {
        let m = medium([1.0, 2.0, 0.5], [0.0; 3]);
        match m.sample(0.7, Color::ONE, 0.3, 0.9) {
            MediumEvent::Pass { weight } => assert_eq!(weight, m.transmittance(0.7)),
            other => panic!("{other:?}"),
        }
        // Emission: E[emission] = (1 − T) σₐ/σₜ Lₑ with σₛ = 0.
        let le = Color::new(2.0, 1.0, 0.5);
        let m = HomogeneousMedium::new(Color::new(1.0, 2.0, 0.5), Color::ZERO, 1.0, 0.0, le).unwrap();
        let mut rng = Pcg32::new(5, 5);
        let n = 200_000;
        let mut sum = Color::ZERO;
        for _ in 0..n {
            if let MediumEvent::Scatter { emission, weight, .. } =
                m.sample(0.8, Color::ONE, rng.uniform(), rng.uniform())
            {
                assert_eq!(weight, Color::ZERO);
                sum += emission;
            }
        }
        let want = (Color::ONE - m.transmittance(0.8)) * le;
        let est = sum / n as f32;
        assert!((est - want).abs().max_element() < 0.01 * want.max_element(), "{est} vs {want}");
    }

    /// `free_flight` is where `sample` scatters: for any segment length,
    /// `sample` scatters exactly when the free flight is shorter, at that
    /// distance, bit for bit; otherwise it passes. So a ray query bounded
    /// by the free flight decides the segment as an unbounded one would.
    /// Chromatic, grey, absorbing-only and one-channel-clear media, and
    /// throughputs with zero, negative and not-finite channels.
    #[test]
    fn free_flight_is_where_sample_scatters() {
        let media = [
            medium([0.2, 0.9, 0.05], [0.6, 0.1, 1.5]),
            medium([0.1; 3], [0.4; 3]),
            medium([1.0, 2.0, 0.5], [0.0; 3]),
            medium([0.0, 0.3, 0.0], [0.0, 0.2, 0.0]),
        ];
        let betas = [
            Color::ONE,
            Color::new(0.9, 0.1, 0.0),
            Color::new(0.0, 0.0, 2.0),
            Color::new(-1.0, 0.5, 0.5),
            Color::new(f32::NAN, 1.0, 1.0),
            Color::ZERO,
        ];
        let mut rng = Pcg32::new(17, 4);
        let mut seen = [0usize; 2];
        for m in &media {
            for &beta in &betas {
                for _ in 0..2_000 {
                    let (uc, ud) = (rng.uniform(), rng.uniform());
                    let flight = m.free_flight(beta, uc, ud).distance();
                    assert!(flight >= 0.0, "{flight}");
                    let t_max = if rng.uniform() < 0.1 { f32::INFINITY } else { 5.0 * rng.uniform() };
                    match m.sample(t_max, beta, uc, ud) {
                        MediumEvent::Scatter { t, .. } => {
                            assert!(flight < t_max, "scattered at {t}, free flight {flight}, t_max {t_max}");
                            assert_eq!(t.to_bits(), flight.to_bits());
                            seen[0] += 1;
                        }
                        MediumEvent::Pass { .. } => {
                            assert!(flight >= t_max, "passed, free flight {flight}, t_max {t_max}");
                            seen[1] += 1;
                        }
                    }
                    // A surface exactly at the free flight is reached (the
                    // path integrator bounds its query just above it).
                    if flight.is_finite() {
                        assert!(matches!(m.sample(flight, beta, uc, ud), MediumEvent::Pass { .. }));
                    }
                }
            }
        }
        assert!(seen.iter().all(|&n| n > 1000), "{seen:?}");
    }

    #[test]
    fn bad_parameters_are_refused() {
        let c = Color::ONE;
        assert!(HomogeneousMedium::new(Color::new(-1.0, 0.0, 0.0), c, 1.0, 0.0, Color::ZERO).is_err());
        assert!(HomogeneousMedium::new(c, Color::splat(f32::NAN), 1.0, 0.0, Color::ZERO).is_err());
        assert!(HomogeneousMedium::new(c, c, -2.0, 0.0, Color::ZERO).is_err());
        assert!(HomogeneousMedium::new(c, c, 1.0, 1.0, Color::ZERO).is_err());
        assert!(HomogeneousMedium::new(c, c, 1.0, 0.0, Color::splat(-1.0)).is_err());
        assert!(HomogeneousMedium::new(c, c, f32::MAX, 0.0, Color::ZERO).is_err());
        let m = HomogeneousMedium::new(c, c * 2.0, 3.0, 0.5, Color::ZERO).unwrap();
        assert_eq!((m.sigma_a(), m.sigma_s()), (Color::splat(3.0), Color::splat(6.0)));
    }
}
