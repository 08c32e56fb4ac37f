//! The named spectra of pbrt-v4 (`Spectrum::named`), and the CIE daylight
//! series at any temperature.

use super::cie::spectrum_to_xyz;
use super::kinds::{Blackbody, PiecewiseLinear};
use super::{data, Spectrum, SpectrumError};

/// Every name [`Spectrum::named`] knows, as pbrt-v4 spells them.
pub const NAMED_SPECTRA: [&str; 37] = [
    "glass-BK7",
    "glass-BAF10",
    "glass-FK51A",
    "glass-LASF9",
    "glass-F5",
    "glass-F10",
    "glass-F11",
    "metal-Ag-eta",
    "metal-Ag-k",
    "metal-Al-eta",
    "metal-Al-k",
    "metal-Au-eta",
    "metal-Au-k",
    "metal-Cu-eta",
    "metal-Cu-k",
    "metal-CuZn-eta",
    "metal-CuZn-k",
    "metal-MgO-eta",
    "metal-MgO-k",
    "metal-TiO2-eta",
    "metal-TiO2-k",
    "stdillum-A",
    "stdillum-D50",
    "stdillum-D65",
    "stdillum-F1",
    "stdillum-F2",
    "stdillum-F3",
    "stdillum-F4",
    "stdillum-F5",
    "stdillum-F6",
    "stdillum-F7",
    "stdillum-F8",
    "stdillum-F9",
    "stdillum-F10",
    "stdillum-F11",
    "stdillum-F12",
    "illum-acesD60",
];

/// The table of a name (all but `stdillum-D50`, which is computed), and whether it is an illuminant (normalised to
/// luminance 1, as pbrt-v4 does for its illuminants).
fn table(name: &str) -> Option<(&'static [(f64, f64)], bool)> {
    let t: (&'static [(f64, f64)], bool) = match name {
        "glass-BK7" => (&data::GLASS_BK7, false),
        "glass-BAF10" => (&data::GLASS_BAF10, false),
        "glass-FK51A" => (&data::GLASS_FK51A, false),
        "glass-LASF9" => (&data::GLASS_LASF9, false),
        "glass-F5" => (&data::GLASS_F5, false),
        "glass-F10" => (&data::GLASS_F10, false),
        "glass-F11" => (&data::GLASS_F11, false),
        "metal-Ag-eta" => (&data::AG_ETA, false),
        "metal-Ag-k" => (&data::AG_K, false),
        "metal-Al-eta" => (&data::AL_ETA, false),
        "metal-Al-k" => (&data::AL_K, false),
        "metal-Au-eta" => (&data::AU_ETA, false),
        "metal-Au-k" => (&data::AU_K, false),
        "metal-Cu-eta" => (&data::CU_ETA, false),
        "metal-Cu-k" => (&data::CU_K, false),
        "metal-CuZn-eta" => (&data::CUZN_ETA, false),
        "metal-CuZn-k" => (&data::CUZN_K, false),
        "metal-MgO-eta" => (&data::MGO_ETA, false),
        "metal-MgO-k" => (&data::MGO_K, false),
        "metal-TiO2-eta" => (&data::TIO2_ETA, false),
        "metal-TiO2-k" => (&data::TIO2_K, false),
        "stdillum-A" => (&data::ILLUM_A, true),
        "stdillum-D65" => (&data::ILLUM_D65, true),
        "stdillum-F1" => (&data::ILLUM_F1, true),
        "stdillum-F2" => (&data::ILLUM_F2, true),
        "stdillum-F3" => (&data::ILLUM_F3, true),
        "stdillum-F4" => (&data::ILLUM_F4, true),
        "stdillum-F5" => (&data::ILLUM_F5, true),
        "stdillum-F6" => (&data::ILLUM_F6, true),
        "stdillum-F7" => (&data::ILLUM_F7, true),
        "stdillum-F8" => (&data::ILLUM_F8, true),
        "stdillum-F9" => (&data::ILLUM_F9, true),
        "stdillum-F10" => (&data::ILLUM_F10, true),
        "stdillum-F11" => (&data::ILLUM_F11, true),
        "stdillum-F12" => (&data::ILLUM_F12, true),
        "illum-acesD60" => (&data::ILLUM_ACES_D60, true),
        _ => return None,
    };
    Some(t)
}

impl Spectrum {
    /// The named spectrum `name` of pbrt-v4 (one of [`NAMED_SPECTRA`],
    /// case-sensitive): measured metal `eta`/`k`, glass `eta`, or a standard
    /// illuminant.
    ///
    /// As in pbrt-v4 (`PiecewiseLinearSpectrum::FromInterleaved`), a table
    /// that starts above 360 nm or ends below 830 nm is extended with its
    /// first or last value to 359 and 831 nm, and the illuminants
    /// (`stdillum-*`, `illum-acesD60`) are scaled to luminance `Y = 1`.
    ///
    /// `stdillum-D50` is CIE D50 computed from the daylight basis
    /// ([`cie_daylight`] of 5000 K, that is CCT 5003 K), not pbrt-v4's
    /// D5000 table, which departs from D50 above 560 nm.
    ///
    /// ```
    /// use lucent::spectrum::Spectrum;
    ///
    /// let bk7 = Spectrum::named("glass-BK7")?;
    /// assert!((bk7.evaluate(550.0) - 1.5185).abs() < 1e-4);
    /// assert!(Spectrum::named("glass-BK8").unwrap_err().to_string().contains("glass-BK7"));
    /// # Ok::<(), lucent::spectrum::SpectrumError>(())
    /// ```
    pub fn named(name: &str) -> Result<Self, SpectrumError> {
        if name == "stdillum-D50" {
            return Ok(normalise_luminance(cie_daylight(5000.0)?));
        }
        let (table, illuminant) = table(name).ok_or_else(|| SpectrumError::UnknownName(name.to_owned()))?;
        let s = Spectrum::PiecewiseLinear(PiecewiseLinear::from_table(table));
        Ok(if illuminant { normalise_luminance(s) } else { s })
    }

    /// Whether `name` is one of [`NAMED_SPECTRA`].
    pub fn is_named(name: &str) -> bool {
        NAMED_SPECTRA.contains(&name)
    }
}

/// `s` scaled to luminance `Y = 1` (unchanged if it has none).
fn normalise_luminance(s: Spectrum) -> Spectrum {
    let y = spectrum_to_xyz(&s).y;
    if y > 0.0 && y.is_finite() {
        s.scaled(1.0 / y)
    } else {
        s
    }
}

/// The CIE daylight illuminant of correlated colour temperature
/// `temperature` (K), as pbrt-v4's `Spectra::D` makes it for white
/// balancing: the temperature is first corrected for the revised second
/// radiation constant (`T · 1.4388/1.4380`); below 4000 K, where the
/// daylight series is undefined, it is the blackbody of that temperature;
/// otherwise `S₀ + M₁S₁ + M₂S₂` with the chromaticity `x_D` of CIE
/// 015:2004 eq. 3.3/3.4, `y_D = −3x_D² + 2.870x_D − 0.275`, and
/// `M₁, M₂` of eq. 3.5, over 300–830 nm in 5 nm steps, times 0.01.
/// Only the spectrum's chromaticity matters to its uses.
pub fn cie_daylight(temperature: f64) -> Result<Spectrum, SpectrumError> {
    if !(temperature.is_finite() && temperature > 0.0) {
        return Err(SpectrumError::Temperature(temperature));
    }
    let cct = temperature * 1.4388 / 1.4380;
    if cct < 4000.0 {
        return Ok(Spectrum::Blackbody(Blackbody::new(cct)?));
    }
    let (t, t2, t3) = (cct, cct * cct, cct * cct * cct);
    let x = if cct <= 7000.0 {
        -4.607e9 / t3 + 2.9678e6 / t2 + 0.09911e3 / t + 0.244063
    } else {
        -2.0064e9 / t3 + 1.9018e6 / t2 + 0.24748e3 / t + 0.23704
    };
    let y = -3.0 * x * x + 2.870 * x - 0.275;
    let m = 0.0241 + 0.2562 * x - 0.7341 * y;
    let m1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / m;
    let m2 = (0.0300 - 31.4424 * x + 30.0717 * y) / m;
    let n = data::CIE_D_S0.len();
    let lambdas = (0..n).map(|i| 300.0 + 5.0 * i as f64).collect();
    let values = (0..n).map(|i| (data::CIE_D_S0[i] + m1 * data::CIE_D_S1[i] + m2 * data::CIE_D_S2[i]) * 0.01).collect();
    Ok(Spectrum::PiecewiseLinear(PiecewiseLinear::new(lambdas, values)?))
}

#[cfg(test)]
mod tests {
    use super::super::cie::chromaticity;
    use super::*;

    #[test]
    fn every_name_resolves_and_unknown_names_list_them() {
        for name in NAMED_SPECTRA {
            let s = Spectrum::named(name).unwrap();
            // MgO and TiO2 are transparent (k = 0) in most of the visible.
            let transparent = matches!(name, "metal-MgO-k" | "metal-TiO2-k");
            assert!(s.value(550.0) > 0.0 || transparent, "{name}");
            // Defined over the whole visible range (extended where needed).
            let Spectrum::PiecewiseLinear(p) = &s else { panic!("{name}") };
            assert!(p.lambdas()[0] <= 360.0 && *p.lambdas().last().unwrap() >= 830.0, "{name}");
        }
        let e = Spectrum::named("metal-Pt-eta").unwrap_err().to_string();
        for name in NAMED_SPECTRA {
            assert!(e.contains(name), "{e}");
        }
        assert!(e.contains("metal-Pt-eta"));
    }

    #[test]
    fn illuminants_have_unit_luminance() {
        for name in ["stdillum-A", "stdillum-D50", "stdillum-D65", "stdillum-F7", "illum-acesD60"] {
            let y = spectrum_to_xyz(&Spectrum::named(name).unwrap()).y;
            assert!((y - 1.0).abs() < 1e-12, "{name}: {y}");
        }
    }

    #[test]
    fn standard_illuminants_have_their_cie_chromaticities() {
        // CIE 015:2004, table T.3 (2° observer).
        for (name, x, y) in [
            ("stdillum-D65", 0.31272, 0.32903),
            ("stdillum-D50", 0.34567, 0.35851),
            ("stdillum-A", 0.44757, 0.40745),
            ("stdillum-F2", 0.37208, 0.37529),
            ("stdillum-F11", 0.38052, 0.37713),
        ] {
            let (cx, cy) = chromaticity(spectrum_to_xyz(&Spectrum::named(name).unwrap()));
            assert!((cx - x).abs() < 3e-4 && (cy - y).abs() < 3e-4, "{name}: ({cx}, {cy}) vs ({x}, {y})");
        }
        // The ACES white: x = 0.32168, y = 0.33767 (SMPTE ST 2065-1).
        let (x, y) = chromaticity(spectrum_to_xyz(&Spectrum::named("illum-acesD60").unwrap()));
        assert!((x - 0.32168).abs() < 3e-4 && (y - 0.33767).abs() < 3e-4, "({x}, {y})");
    }

    #[test]
    fn daylight_series_matches_the_tabulated_illuminants() {
        // D65 by its nominal temperature (6500 K, which pbrt's correction
        // turns into CCT 6504 K), against the tabulated D65.
        let (x0, y0) = chromaticity(spectrum_to_xyz(&cie_daylight(6500.0).unwrap()));
        let (x1, y1) = chromaticity(spectrum_to_xyz(&Spectrum::named("stdillum-D65").unwrap()));
        assert!((x0 - x1).abs() < 5e-4 && (y0 - y1).abs() < 5e-4, "({x0}, {y0}) vs ({x1}, {y1})");
        // D75 (CIE 015:2004, table T.3: x = 0.29902, y = 0.31485).
        let (x, y) = chromaticity(spectrum_to_xyz(&cie_daylight(7500.0).unwrap()));
        assert!((x - 0.29902).abs() < 3e-4 && (y - 0.31485).abs() < 3e-4, "({x}, {y})");
        // Below 4000 K: a blackbody.
        assert!(matches!(cie_daylight(3000.0).unwrap(), Spectrum::Blackbody(_)));
        assert!(cie_daylight(-1.0).is_err());
    }
}
