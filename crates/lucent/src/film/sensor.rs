//! The film's response to radiance, after pbrt-v4's `RGBFilm` and its
//! default `PixelSensor` ("cie1931"; PBRT 4th ed., §5.4.2): each sample's
//! radiance is multiplied by a per-channel scale (exposure and white
//! balance), then, if its largest component exceeds `maxcomponentvalue`,
//! scaled down to it. `RenderSettings::film_scale` and
//! `RenderSettings::max_component` (in the render layer) hold the scale
//! and the limit; the render loop applies
//! [`film_response`] to every sample before it is filtered into pixels.

use crate::color::Color;
use crate::spectrum::{bradford_adaptation, chromaticity, cie_daylight, spectrum_to_xyz, ColorSpace};
use glam::{DMat3, DVec3};

/// A film parameter is out of range.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum SensorError {
    /// `exposuretime` (the camera's shutter interval) is negative or not
    /// finite.
    #[error("exposure time {0} is invalid: it must be a finite number of seconds, at least 0")]
    ExposureTime(f32),
    /// `iso` is negative or not finite.
    #[error("ISO {0} is invalid: it must be a finite number, at least 0")]
    Iso(f32),
    /// `whitebalance` is negative or not finite.
    #[error("white balance temperature {0} K is invalid: it must be 0 (none) or a positive finite number of kelvin")]
    WhiteBalance(f32),
    /// The white of `whitebalance` lies outside the sRGB gamut, so it has
    /// no per-channel correction.
    #[error("white balance temperature {0} K is too far from daylight: its white is outside the sRGB gamut")]
    WhiteOutOfGamut(f32),
    /// A film scale component is negative or not finite.
    #[error("film scale {0} is invalid: every component must be a finite number, at least 0")]
    Scale(Color),
    /// The sample limit is not positive (or is NaN).
    #[error("max component value {0} is invalid: it must be a positive number")]
    MaxComponent(f32),
}

/// One sample's contribution to the film: `l × scale` (per channel), then
/// scaled down uniformly to `max_component` if its largest component
/// exceeds it (pbrt-v4's `RGBFilm::AddSample`).
///
/// ```
/// use lucent::color::Color;
/// use lucent::film::film_response;
///
/// let l = Color::new(8.0, 2.0, 1.0);
/// assert_eq!(film_response(l, Color::splat(2.0), None), Color::new(16.0, 4.0, 2.0));
/// assert_eq!(film_response(l, Color::ONE, Some(4.0)), Color::new(4.0, 1.0, 0.5));
/// ```
#[inline]
pub fn film_response(l: Color, scale: Color, max_component: Option<f32>) -> Color {
    let c = l * scale;
    match max_component {
        Some(max) => {
            let m = c.max_element();
            if m > max {
                c * (max / m)
            } else {
                c
            }
        }
        None => c,
    }
}

/// Check a film scale and limit as [`film_response`] takes them: scale
/// components finite and ≥ 0, the limit positive (infinity allowed).
pub fn validate_film_response(scale: Color, max_component: Option<f32>) -> Result<(), SensorError> {
    if !(scale.is_finite() && scale.min_element() >= 0.0) {
        return Err(SensorError::Scale(scale));
    }
    match max_component {
        Some(m) if m.is_nan() || m <= 0.0 => Err(SensorError::MaxComponent(m)),
        _ => Ok(()),
    }
}

/// pbrt-v4's imaging ratio, `exposure_time · iso / 100` (`PixelSensor::
/// Create`): 1 for pbrt's defaults (the camera's shutter open from 0 to 1,
/// ISO 100).
pub fn imaging_ratio(exposure_time: f32, iso: f32) -> Result<f32, SensorError> {
    if !(exposure_time.is_finite() && exposure_time >= 0.0) {
        return Err(SensorError::ExposureTime(exposure_time));
    }
    if !(iso.is_finite() && iso >= 0.0) {
        return Err(SensorError::Iso(iso));
    }
    Ok(exposure_time * iso / 100.0)
}

/// The white balance pbrt-v4's "cie1931" sensor applies for
/// `whitebalance = temperature` (K), as a matrix on linear sRGB: the
/// Bradford von Kries adaptation (pbrt-v4's `WhiteBalance`) from the
/// chromaticity of the CIE daylight illuminant of that temperature
/// ([`cie_daylight`], a blackbody below 4000 K) to the sRGB white, taken to
/// linear sRGB (`M · A · M⁻¹`). `temperature` 0 is no white balance: the
/// identity.
pub fn white_balance_matrix(temperature: f32) -> Result<DMat3, SensorError> {
    if temperature == 0.0 {
        return Ok(DMat3::IDENTITY);
    }
    let from = daylight_white(temperature)?;
    let srgb = ColorSpace::Srgb;
    Ok(srgb.xyz_to_rgb() * bradford_adaptation(from, srgb.white()) * srgb.rgb_to_xyz())
}

/// The per-channel white balance for `whitebalance = temperature` (K):
/// `1 / rgb_w`, where `rgb_w` is the linear sRGB colour (at luminance 1) of
/// the CIE daylight illuminant of that temperature, so that light of that
/// colour becomes white. This is a von Kries adaptation in the sRGB
/// primaries; pbrt-v4 adapts in the Bradford cone space
/// ([`white_balance_matrix`]), which maps the white identically but other
/// colours slightly differently (a per-channel scale is what
/// [`film_response`] applies). `temperature` 0 is none: (1, 1, 1).
pub fn white_balance_scale(temperature: f32) -> Result<Color, SensorError> {
    if temperature == 0.0 {
        return Ok(Color::ONE);
    }
    let (x, y) = daylight_white(temperature)?;
    let rgb = ColorSpace::Srgb.xyz_to_rgb() * crate::spectrum::xyz_from_xy_y(x, y, 1.0);
    if rgb.min_element() <= 1e-3 {
        return Err(SensorError::WhiteOutOfGamut(temperature));
    }
    Ok((DVec3::ONE / rgb).as_vec3a())
}

/// pbrt-v4's `Film "rgb"` exposure and white balance as the per-channel
/// `RenderSettings::film_scale` of the render layer:
/// [`imaging_ratio`]`(exposure_time, iso)` times
/// [`white_balance_scale`]`(white_balance)`. pbrt-v4's defaults (exposure
/// 1, ISO 100, white balance 0) give (1, 1, 1).
///
/// ```
/// use lucent::color::Color;
/// use lucent::film::pbrt_film_scale;
///
/// assert_eq!(pbrt_film_scale(1.0, 100.0, 0.0)?, Color::ONE);
/// assert_eq!(pbrt_film_scale(0.5, 400.0, 0.0)?, Color::splat(2.0));
/// # Ok::<(), lucent::film::SensorError>(())
/// ```
pub fn pbrt_film_scale(exposure_time: f32, iso: f32, white_balance: f32) -> Result<Color, SensorError> {
    Ok(imaging_ratio(exposure_time, iso)? * white_balance_scale(white_balance)?)
}

/// The chromaticity of pbrt-v4's white-balance illuminant.
fn daylight_white(temperature: f32) -> Result<(f64, f64), SensorError> {
    let spectrum = cie_daylight(temperature as f64).map_err(|_| SensorError::WhiteBalance(temperature))?;
    Ok(chromaticity(spectrum_to_xyz(&spectrum)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn response_scales_then_clamps_the_largest_component() {
        let l = Color::new(3.0, 1.5, 0.75);
        assert_eq!(film_response(l, Color::ONE, None), l);
        assert_eq!(film_response(l, Color::new(2.0, 1.0, 0.0), None), Color::new(6.0, 1.5, 0.0));
        // Scale first, then clamp: 6 > 4 → × 4/6, hue kept.
        assert_eq!(film_response(l, Color::splat(2.0), Some(4.0)), Color::new(4.0, 2.0, 1.0));
        assert_eq!(film_response(l, Color::ONE, Some(3.0)), l);
        assert_eq!(film_response(l, Color::ONE, Some(f32::INFINITY)), l);
    }

    #[test]
    fn validation() {
        assert!(validate_film_response(Color::ONE, None).is_ok());
        assert!(validate_film_response(Color::ZERO, Some(f32::INFINITY)).is_ok());
        assert_eq!(
            validate_film_response(Color::new(1.0, -1.0, 1.0), None),
            Err(SensorError::Scale(Color::new(1.0, -1.0, 1.0)))
        );
        assert!(validate_film_response(Color::splat(f32::NAN), None).is_err());
        assert_eq!(validate_film_response(Color::ONE, Some(0.0)), Err(SensorError::MaxComponent(0.0)));
        assert!(validate_film_response(Color::ONE, Some(f32::NAN)).is_err());
    }

    #[test]
    fn imaging_ratio_is_exposure_times_iso_over_100() {
        assert_eq!(imaging_ratio(1.0, 100.0), Ok(1.0));
        assert_eq!(imaging_ratio(0.01, 800.0), Ok(0.08));
        assert_eq!(imaging_ratio(-1.0, 100.0), Err(SensorError::ExposureTime(-1.0)));
        assert_eq!(imaging_ratio(1.0, f32::INFINITY), Err(SensorError::Iso(f32::INFINITY)));
    }

    #[test]
    fn white_balance_makes_its_illuminant_white() {
        assert_eq!(white_balance_scale(0.0), Ok(Color::ONE));
        assert_eq!(white_balance_matrix(0.0), Ok(DMat3::IDENTITY));
        for t in [3000.0f32, 5000.0, 6500.0, 9000.0] {
            let (x, y) = daylight_white(t).unwrap();
            let white = ColorSpace::Srgb.xyz_to_rgb() * crate::spectrum::xyz_from_xy_y(x, y, 1.0);
            let by_scale = white.as_vec3a() * white_balance_scale(t).unwrap();
            assert!((by_scale - Color::ONE).abs().max_element() < 1e-5, "{t}: {by_scale}");
            let by_matrix = white_balance_matrix(t).unwrap() * white;
            assert!((by_matrix - DVec3::ONE).abs().max_element() < 1e-9, "{t}: {by_matrix}");
        }
        // 6500 K is (almost) D65: almost no correction. A warm white
        // balance cools the image.
        let s = white_balance_scale(6500.0).unwrap();
        assert!((s - Color::ONE).abs().max_element() < 0.01, "{s}");
        let warm = white_balance_scale(3000.0).unwrap();
        assert!(warm.x < 1.0 && warm.z > 1.0, "{warm}");
        assert_eq!(white_balance_scale(-5.0), Err(SensorError::WhiteBalance(-5.0)));
        assert_eq!(white_balance_scale(500.0), Err(SensorError::WhiteOutOfGamut(500.0)));
    }

    #[test]
    fn pbrt_defaults_give_unit_scale() {
        assert_eq!(pbrt_film_scale(1.0, 100.0, 0.0), Ok(Color::ONE));
        let s = pbrt_film_scale(2.0, 100.0, 3000.0).unwrap();
        assert_eq!(s, 2.0 * white_balance_scale(3000.0).unwrap());
    }
}
