//! Spectra to lucent's linear sRGB, once, at load time: the conversion for
//! each use of a spectrum (pbrt-v4's `SpectrumType`s and its lights'
//! luminance normalisation). The [module documentation](super) explains
//! each.

use super::cie::{spectrum_to_xyz, CIE_Y_INTEGRAL, LAMBDA_MIN};
use super::color_space::{xyz_to_linear_srgb, ColorSpace};
use super::{data, Spectrum, SpectrumError};
use crate::color::Color;
use glam::DVec3;
use std::sync::OnceLock;

/// How a spectrum is used, which decides how it becomes RGB (pbrt-v4's
/// `SpectrumType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SpectrumType {
    /// A reflectance or transmittance in `[0, 1]` (`reflectance`, `Kd`…):
    /// its colour under D65 ([`reflectance_to_rgb`]).
    Albedo,
    /// Any other unitless quantity (`eta`, `k` of conductors): the same
    /// projection ([`unbounded_to_rgb`]).
    Unbounded,
    /// Emitted light (`L`, `I`): normalised to luminance 1
    /// ([`illuminant_to_rgb`]).
    Illuminant,
}

impl Spectrum {
    /// This spectrum in linear sRGB for use `kind`: [`reflectance_to_rgb`],
    /// [`unbounded_to_rgb`] or [`illuminant_to_rgb`].
    pub fn to_linear_srgb(&self, kind: SpectrumType) -> Color {
        match kind {
            SpectrumType::Albedo => reflectance_to_rgb(self),
            SpectrumType::Unbounded => unbounded_to_rgb(self),
            SpectrumType::Illuminant => illuminant_to_rgb(self),
        }
    }
}

/// `D65(λ)·(x̄, ȳ, z̄)(λ) / Σ D65·ȳ` at λ = 360, 361, …, 830 nm: the weights
/// of the reflectance projection.
fn d65_weights() -> &'static [DVec3] {
    static WEIGHTS: OnceLock<Vec<DVec3>> = OnceLock::new();
    WEIGHTS.get_or_init(|| {
        let d65 = ColorSpace::Srgb.illuminant();
        let mut w: Vec<DVec3> = (0..data::CIE_X.len())
            .map(|k| {
                let cmf = DVec3::new(data::CIE_X[k], data::CIE_Y[k], data::CIE_Z[k]);
                d65.value(LAMBDA_MIN + k as f64) * cmf
            })
            .collect();
        let y: f64 = w.iter().map(|v| v.y).sum();
        for v in &mut w {
            *v /= y;
        }
        w
    })
}

/// A reflectance spectrum `ρ` in linear sRGB: the colour of a surface of
/// that reflectance lit by D65 (the sRGB white), relative to a white one,
/// `M_sRGB · Σ ρ(λ) D65(λ) (x̄, ȳ, z̄)(λ) / Σ D65(λ) ȳ(λ)` over 360–830 nm.
/// A constant `c` gives `(c, c, c)` exactly. This is how a pbrt-v4 render
/// in sRGB under D65-white light sees the reflectance.
///
/// ```
/// use lucent::color::Color;
/// use lucent::spectrum::{reflectance_to_rgb, Spectrum};
///
/// assert_eq!(reflectance_to_rgb(&Spectrum::constant(0.5)), Color::splat(0.5));
/// ```
pub fn reflectance_to_rgb(s: &Spectrum) -> Color {
    if let Spectrum::Constant(c) = *s {
        return Color::splat(c as f32);
    }
    let xyz: DVec3 = d65_weights().iter().enumerate().map(|(k, &w)| s.value(LAMBDA_MIN + k as f64) * w).sum();
    xyz_to_linear_srgb(xyz)
}

/// An unbounded spectrum (a conductor's `eta` or `k`) in linear sRGB: the
/// same projection as [`reflectance_to_rgb`], so a constant `c` gives
/// `(c, c, c)`. This approximates spectral rendering: the Fresnel
/// equations are not linear in η and k, so the reflectance of the
/// projected η, k is not exactly the projection of the spectral
/// reflectance (a few percent for the common metals).
pub fn unbounded_to_rgb(s: &Spectrum) -> Color {
    reflectance_to_rgb(s)
}

/// An emission spectrum (`L`, `I`) in linear sRGB, normalised as pbrt-v4's
/// lights normalise it (they divide `scale` by `SpectrumToPhotometric`):
/// `M_sRGB · XYZ(s) / Y(s)`, so the result has luminance 1 (then times the
/// light's `scale`). Black for a spectrum without luminance.
///
/// pbrt-v4's `rgb` light values are not spectra: use
/// [`illuminant_rgb_to_linear_srgb`](super::illuminant_rgb_to_linear_srgb)
/// (sRGB values pass through unchanged).
///
/// ```
/// use lucent::spectrum::{illuminant_to_rgb, Spectrum};
///
/// let white = illuminant_to_rgb(&Spectrum::named("stdillum-D65")?);
/// assert!((white - lucent::color::Color::ONE).abs().max_element() < 1e-3);
/// # Ok::<(), lucent::spectrum::SpectrumError>(())
/// ```
pub fn illuminant_to_rgb(s: &Spectrum) -> Color {
    let xyz = spectrum_to_xyz(s);
    if !(xyz.y > 0.0 && xyz.is_finite()) {
        return Color::ZERO;
    }
    xyz_to_linear_srgb(xyz / xyz.y)
}

/// The wavelength (nm) at which a dielectric's spectral `eta` is read.
pub const ETA_WAVELENGTH: f64 = 550.0;

/// A dielectric's spectral index of refraction as one number: its value at
/// 550 nm ([`ETA_WAVELENGTH`]). pbrt-v4 renders a varying `eta` with
/// dispersion (terminating all but one wavelength); lucent has one index.
pub fn dielectric_eta(s: &Spectrum) -> f32 {
    s.value(ETA_WAVELENGTH) as f32
}

/// The linear sRGB colour of a `blackbody` value of `temperature` kelvin:
/// the normalised blackbody spectrum at luminance 1 (as pbrt-v4 lights
/// make it, whatever the temperature), so `scale` alone sets the
/// brightness.
///
/// ```
/// use lucent::spectrum::blackbody_rgb;
///
/// let warm = blackbody_rgb(2700.0)?;
/// assert!(warm.x > warm.y && warm.y > warm.z);
/// assert!((lucent::color::luminance(warm) - 1.0).abs() < 1e-3);
/// # Ok::<(), lucent::spectrum::SpectrumError>(())
/// ```
pub fn blackbody_rgb(temperature: f32) -> Result<Color, SpectrumError> {
    Ok(illuminant_to_rgb(&Spectrum::blackbody(temperature)?))
}

/// The luminance `Y` of a spectrum, `Σ s ȳ / Σ ȳ` (pbrt-v4's
/// `SpectrumToPhotometric` divided by `CIE_Y_integral`).
pub fn luminance_of(s: &Spectrum) -> f64 {
    super::cie::xyz_integral(s).y / CIE_Y_INTEGRAL
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::luminance;
    use crate::spectrum::{spectrum_to_xyz, xyz_to_linear_srgb};

    fn close(a: Color, b: Color, tol: f32) -> bool {
        (a - b).abs().max_element() <= tol
    }

    #[test]
    fn constant_spectra_are_grey() {
        for c in [0.0, 0.18, 1.0, 3.5] {
            assert_eq!(reflectance_to_rgb(&Spectrum::constant(c)), Color::splat(c));
            assert_eq!(unbounded_to_rgb(&Spectrum::constant(c)), Color::splat(c));
        }
        // The same spectrum as a table over the whole range: grey to rounding.
        let flat = Spectrum::from_interleaved(&[300.0, 0.5, 900.0, 0.5]).unwrap();
        assert!(close(reflectance_to_rgb(&flat), Color::splat(0.5), 1e-6), "{}", reflectance_to_rgb(&flat));
    }

    #[test]
    fn d65_is_white_and_other_illuminants_have_unit_luminance() {
        let d65 = Spectrum::named("stdillum-D65").unwrap();
        let w = illuminant_to_rgb(&d65);
        assert!(close(w, Color::ONE, 1e-3), "{w}");
        // Any scale of it too: lights are normalised.
        assert!(close(illuminant_to_rgb(&d65.clone().scaled(40.0)), Color::ONE, 1e-3));
        for name in ["stdillum-A", "stdillum-F2", "stdillum-D50"] {
            let c = illuminant_to_rgb(&Spectrum::named(name).unwrap());
            assert!((luminance(c) - 1.0).abs() < 2e-3, "{name}: {c}");
            assert!(c.x > c.z, "{name} is warmer than D65: {c}");
        }
        assert_eq!(illuminant_to_rgb(&Spectrum::constant(0.0)), Color::ZERO);
    }

    #[test]
    fn blackbodies_have_unit_luminance_and_6504_k_is_nearly_white() {
        for t in [1000.0, 2700.0, 6504.0, 12000.0] {
            let c = blackbody_rgb(t).unwrap();
            assert!((luminance(c) - 1.0).abs() < 1e-3, "{t}: {c}");
        }
        // 6504 K lies near, not on, D65 (the daylight locus is above the
        // Planckian one): within a few percent of white.
        let c = blackbody_rgb(6504.0).unwrap();
        assert!(close(c, Color::ONE, 0.05), "{c}");
        // Hotter is bluer.
        let (cold, hot) = (blackbody_rgb(3000.0).unwrap(), blackbody_rgb(10000.0).unwrap());
        assert!(cold.x / cold.z > 1.0 && hot.x / hot.z < 1.0);
        assert!(blackbody_rgb(-5.0).is_err());
    }

    #[test]
    fn glass_eta_at_550_nm() {
        // Schott BK7: n(550 nm) = 1.51852 (Sellmeier); the table interpolates
        // between 542 and 564 nm.
        let eta = dielectric_eta(&Spectrum::named("glass-BK7").unwrap());
        assert!((eta - 1.5185).abs() < 1e-4, "{eta}");
        assert_eq!(dielectric_eta(&Spectrum::constant(1.33)), 1.33);
    }

    /// Fresnel reflectance at normal incidence of a conductor,
    /// `((η − 1)² + k²) / ((η + 1)² + k²)`.
    fn r0(eta: f32, k: f32) -> f32 {
        ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k)
    }

    #[test]
    fn gold_and_copper_eta_k_reproduce_their_reflectance() {
        // The RGB gold η ≈ (0.143, 0.374, 1.442), k ≈ (3.983, 2.385, 1.603)
        // that renderers commonly use are the same tables projected without
        // an illuminant (equal energy, pbrt-v3's XYZ → sRGB): our data gives
        // them to 1%.
        let au_eta = Spectrum::named("metal-Au-eta").unwrap();
        let au_k = Spectrum::named("metal-Au-k").unwrap();
        let e_eta = xyz_to_linear_srgb(spectrum_to_xyz(&au_eta));
        let e_k = xyz_to_linear_srgb(spectrum_to_xyz(&au_k));
        let (usual_eta, usual_k) = (Color::new(0.143, 0.374, 1.442), Color::new(3.983, 2.385, 1.603));
        for i in 0..3 {
            assert!((e_eta[i] / usual_eta[i] - 1.0).abs() < 0.01, "η {e_eta} vs {usual_eta}");
            assert!((e_k[i] / usual_k[i] - 1.0).abs() < 0.01, "k {e_k} vs {usual_k}");
        }
        // Under D65 (the projection lucent uses, white-preserving) green and
        // blue stay within 10% of them; red η is lower (0.080), a channel
        // where the reflectance hardly depends on η.
        let (eta, k) = (unbounded_to_rgb(&au_eta), unbounded_to_rgb(&au_k));
        for i in 1..3 {
            assert!((eta[i] / usual_eta[i] - 1.0).abs() < 0.1, "η {eta} vs {usual_eta}");
            assert!((k[i] / usual_k[i] - 1.0).abs() < 0.15, "k {k} vs {usual_k}");
        }
        // What matters is the reflectance: the Fresnel reflectance of the
        // projected η, k is within 0.05 of the projected spectral
        // reflectance (Au red is clipped: its spectral projection is > 1).
        for metal in ["Au", "Cu", "Ag", "Al", "CuZn"] {
            let eta_s = Spectrum::named(&format!("metal-{metal}-eta")).unwrap();
            let k_s = Spectrum::named(&format!("metal-{metal}-k")).unwrap();
            let mut lambdas = Vec::new();
            let mut values = Vec::new();
            for l in 360..=830 {
                let (e, kk) = (eta_s.evaluate(l as f32), k_s.evaluate(l as f32));
                lambdas.push(l as f64);
                values.push(r0(e, kk) as f64);
            }
            let spectral = reflectance_to_rgb(&Spectrum::PiecewiseLinear(
                crate::spectrum::PiecewiseLinear::new(lambdas, values).unwrap(),
            ))
            .min(Color::ONE);
            let (eta, k) = (unbounded_to_rgb(&eta_s), unbounded_to_rgb(&k_s));
            for i in 0..3 {
                let r = r0(eta[i], k[i]);
                assert!((r - spectral[i]).abs() < 0.05, "{metal}[{i}]: {r} vs spectral {spectral}");
            }
        }
    }

    #[test]
    fn to_linear_srgb_dispatches_on_the_use() {
        let s = Spectrum::blackbody(4000.0).unwrap();
        assert_eq!(s.to_linear_srgb(SpectrumType::Albedo), reflectance_to_rgb(&s));
        assert_eq!(s.to_linear_srgb(SpectrumType::Unbounded), unbounded_to_rgb(&s));
        assert_eq!(s.to_linear_srgb(SpectrumType::Illuminant), illuminant_to_rgb(&s));
        assert!((luminance_of(&Spectrum::constant(2.0)) - 2.0).abs() < 1e-6);
    }
}
