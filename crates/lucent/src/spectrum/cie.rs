//! CIE 1931 colorimetry: the colour-matching functions and the tristimulus
//! values XYZ of a spectrum (PBRT 4th ed., §4.6.1).

use super::{data, Spectrum};
use glam::DVec3;

/// The shortest wavelength (nm) of the colour-matching functions' table and
/// of every spectral integral here.
pub const LAMBDA_MIN: f64 = 360.0;

/// The longest wavelength (nm) of the colour-matching functions' table.
pub const LAMBDA_MAX: f64 = 830.0;

/// `∫ȳ(λ) dλ` over the table, as pbrt-v4 defines it: the luminance of the
/// constant spectrum 1 before normalisation.
pub const CIE_Y_INTEGRAL: f64 = 106.856895;

/// The CIE 1931 2° colour-matching functions `(x̄, ȳ, z̄)` at `lambda`
/// (nm): linear between the 1 nm samples, zero outside 360–830 nm.
pub fn color_matching(lambda: f64) -> DVec3 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return DVec3::ZERO;
    }
    let f = lambda - LAMBDA_MIN;
    let i = (f.floor() as usize).min(data::CIE_X.len() - 2);
    let t = f - i as f64;
    let at = |k: usize| DVec3::new(data::CIE_X[k], data::CIE_Y[k], data::CIE_Z[k]);
    at(i).lerp(at(i + 1), t)
}

/// `∫ s(λ) (x̄, ȳ, z̄)(λ) dλ`, unnormalised: as pbrt-v4's `InnerProduct`, the
/// sum over the 471 whole wavelengths 360, 361, …, 830 nm of `s(λ)` times
/// the tabulated functions (the rectangle rule with a 1 nm step).
pub fn xyz_integral(s: &Spectrum) -> DVec3 {
    let mut sum = DVec3::ZERO;
    for k in 0..data::CIE_X.len() {
        let v = s.value(LAMBDA_MIN + k as f64);
        sum += v * DVec3::new(data::CIE_X[k], data::CIE_Y[k], data::CIE_Z[k]);
    }
    sum
}

/// The tristimulus values of `s`, `∫ s (x̄, ȳ, z̄) dλ / ∫ȳ dλ` (pbrt-v4's
/// `SpectrumToXYZ`): the constant spectrum 1 has `Y = 1`.
pub fn spectrum_to_xyz(s: &Spectrum) -> DVec3 {
    xyz_integral(s) / CIE_Y_INTEGRAL
}

/// The chromaticity `(x, y) = (X, Y) / (X + Y + Z)` of `xyz` (zero for
/// black).
pub fn chromaticity(xyz: DVec3) -> (f64, f64) {
    let sum = xyz.x + xyz.y + xyz.z;
    if sum == 0.0 {
        (0.0, 0.0)
    } else {
        (xyz.x / sum, xyz.y / sum)
    }
}

/// The XYZ of chromaticity `(x, y)` at luminance `Y`:
/// `(xY/y, Y, (1 − x − y)Y/y)`.
pub fn xyz_from_xy_y(x: f64, y: f64, luminance: f64) -> DVec3 {
    if y == 0.0 {
        return DVec3::ZERO;
    }
    DVec3::new(x * luminance / y, luminance, (1.0 - x - y) * luminance / y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_y_integral_is_pbrts_constant() {
        let y = xyz_integral(&Spectrum::Constant(1.0)).y;
        assert!((y - CIE_Y_INTEGRAL).abs() < 1e-4, "{y}");
        // Illuminant E (constant) sits at the centre of the chromaticity
        // diagram: x = y = 1/3 (to the table's rounding).
        let (x, y) = chromaticity(spectrum_to_xyz(&Spectrum::Constant(1.0)));
        assert!((x - 1.0 / 3.0).abs() < 1e-4 && (y - 1.0 / 3.0).abs() < 1e-4, "{x} {y}");
    }

    #[test]
    fn matching_functions_are_the_table_at_whole_wavelengths() {
        // ȳ(555 nm) = 1.0 (the photopic peak), x̄(600) = 1.0622, z̄(450) = 1.77211
        // (CIE 015:2004, table T.4).
        assert_eq!(color_matching(555.0).y, 1.0);
        assert!((color_matching(600.0).x - 1.0622).abs() < 1e-9);
        assert!((color_matching(450.0).z - 1.77211).abs() < 1e-9);
        assert_eq!(color_matching(359.0), DVec3::ZERO);
        assert_eq!(color_matching(831.0), DVec3::ZERO);
        let mid = color_matching(555.5);
        let (a, b) = (color_matching(555.0), color_matching(556.0));
        assert!((mid - (a + b) / 2.0).length() < 1e-12);
    }

    #[test]
    fn xy_round_trip() {
        let xyz = xyz_from_xy_y(0.3127, 0.3290, 1.0);
        let (x, y) = chromaticity(xyz);
        assert!((x - 0.3127).abs() < 1e-12 && (y - 0.3290).abs() < 1e-12 && xyz.y == 1.0);
    }
}
