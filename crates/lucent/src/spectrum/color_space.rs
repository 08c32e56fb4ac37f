//! RGB colour spaces (PBRT 4th ed., §4.6.3): each is three primaries and a
//! white, which give its RGB↔XYZ matrices; lucent's working space is linear
//! sRGB, and [`rgb_to_linear_srgb`] brings a colour of any other space there.

use super::cie::{chromaticity, spectrum_to_xyz, xyz_from_xy_y};
use super::{Spectrum, SpectrumError};
use crate::color::Color;
use glam::{DMat3, DVec3};
use std::sync::OnceLock;

/// The RGB colour spaces of pbrt-v4's `ColorSpace` directive.
///
/// As in pbrt-v4, a space's white is the chromaticity of its illuminant
/// spectrum (CIE D65 for all but ACES, whose white is the ACES D60
/// spectrum), integrated against the CIE 1931 tables, and its RGB→XYZ
/// matrix follows from the primaries and that white (SMPTE RP 177-1993):
/// the primaries' XYZ at `Y = 1` as columns `P`, scaled by `C = P⁻¹W` so
/// that RGB (1, 1, 1) is the white `W` at `Y = 1`.
///
/// ```
/// use lucent::spectrum::ColorSpace;
///
/// assert_eq!(ColorSpace::from_name("ACES2065-1")?, ColorSpace::Aces2065_1);
/// let e = ColorSpace::from_name("adobe-rgb").unwrap_err().to_string();
/// assert!(e.contains("srgb, rec2020, aces2065-1, dci-p3"));
/// # Ok::<(), lucent::spectrum::SpectrumError>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// sRGB / Rec. ITU-R BT.709 primaries, D65 white (IEC 61966-2-1):
    /// lucent's working space.
    #[default]
    Srgb,
    /// Rec. ITU-R BT.2020 primaries, D65 white.
    Rec2020,
    /// ACES2065-1 (the AP0 primaries, SMPTE ST 2065-1), ACES white (≈ D60).
    Aces2065_1,
    /// pbrt-v4's `dci-p3`: the DCI-P3 primaries (SMPTE EG 432-1) with the
    /// D65 white, that is Display P3; not the DCI theatre white
    /// (0.314, 0.351), which pbrt-v4 does not use.
    DciP3,
}

/// The matrices of one space, computed once.
#[derive(Clone, Copy, Debug)]
struct Matrices {
    white: (f64, f64),
    rgb_to_xyz: DMat3,
    xyz_to_rgb: DMat3,
}

impl ColorSpace {
    /// Every space, in the order [`ColorSpace::from_name`] lists them.
    pub const ALL: [ColorSpace; 4] = [ColorSpace::Srgb, ColorSpace::Rec2020, ColorSpace::Aces2065_1, ColorSpace::DciP3];

    /// The space of pbrt-v4 name `name` (`srgb`, `rec2020`, `aces2065-1`,
    /// `dci-p3`; case-insensitive as in pbrt-v4), or an error listing them.
    pub fn from_name(name: &str) -> Result<Self, SpectrumError> {
        Self::ALL
            .into_iter()
            .find(|s| s.name().eq_ignore_ascii_case(name))
            .ok_or_else(|| SpectrumError::UnknownColorSpace(name.to_owned()))
    }

    /// The pbrt-v4 name.
    pub fn name(self) -> &'static str {
        match self {
            ColorSpace::Srgb => "srgb",
            ColorSpace::Rec2020 => "rec2020",
            ColorSpace::Aces2065_1 => "aces2065-1",
            ColorSpace::DciP3 => "dci-p3",
        }
    }

    /// The chromaticities `(x, y)` of the red, green and blue primaries.
    pub fn primaries(self) -> [(f64, f64); 3] {
        match self {
            ColorSpace::Srgb => [(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)],
            ColorSpace::Rec2020 => [(0.708, 0.292), (0.170, 0.797), (0.131, 0.046)],
            ColorSpace::Aces2065_1 => [(0.7347, 0.2653), (0.0, 1.0), (0.0001, -0.0770)],
            ColorSpace::DciP3 => [(0.680, 0.320), (0.265, 0.690), (0.150, 0.060)],
        }
    }

    /// The illuminant spectrum whose colour is the space's white, at
    /// luminance 1: `stdillum-D65`, or `illum-acesD60` for ACES.
    pub fn illuminant(self) -> Spectrum {
        let name = if self == ColorSpace::Aces2065_1 { "illum-acesD60" } else { "stdillum-D65" };
        Spectrum::named(name).expect("the colour spaces' illuminants are named spectra")
    }

    /// The chromaticity `(x, y)` of the white (of [`ColorSpace::illuminant`]).
    pub fn white(self) -> (f64, f64) {
        self.matrices().white
    }

    /// The matrix from this space's linear RGB to CIE XYZ.
    pub fn rgb_to_xyz(self) -> DMat3 {
        self.matrices().rgb_to_xyz
    }

    /// The matrix from CIE XYZ to this space's linear RGB.
    pub fn xyz_to_rgb(self) -> DMat3 {
        self.matrices().xyz_to_rgb
    }

    /// The matrix from this space's linear RGB to linear sRGB, with the
    /// white adapted: XYZ of this space, then the Bradford adaptation from
    /// its white to D65 ([`bradford_adaptation`]), then sRGB, so that this
    /// space's white (1, 1, 1) becomes sRGB (1, 1, 1). The identity for
    /// sRGB; no adaptation for spaces whose white is D65.
    pub fn to_linear_srgb(self) -> DMat3 {
        if self == ColorSpace::Srgb {
            return DMat3::IDENTITY;
        }
        let srgb = ColorSpace::Srgb;
        let adapt = if self.white() == srgb.white() {
            DMat3::IDENTITY
        } else {
            bradford_adaptation(self.white(), srgb.white())
        };
        srgb.xyz_to_rgb() * adapt * self.rgb_to_xyz()
    }

    /// The matrix from this space's linear RGB to linear sRGB without
    /// adapting the white (pbrt-v4's `ConvertRGBColorSpace`): the same
    /// XYZ, so ACES's white (1, 1, 1) becomes the slightly warmer sRGB
    /// colour of the D60 illuminant. The identity for sRGB.
    pub fn to_linear_srgb_unadapted(self) -> DMat3 {
        if self == ColorSpace::Srgb {
            return DMat3::IDENTITY;
        }
        ColorSpace::Srgb.xyz_to_rgb() * self.rgb_to_xyz()
    }

    fn matrices(self) -> Matrices {
        static CACHE: [OnceLock<Matrices>; 4] = [OnceLock::new(), OnceLock::new(), OnceLock::new(), OnceLock::new()];
        let index = Self::ALL.iter().position(|&s| s == self).unwrap_or(0);
        *CACHE[index].get_or_init(|| {
            let w_xyz = spectrum_to_xyz(&self.illuminant());
            let white = chromaticity(w_xyz);
            let w = xyz_from_xy_y(white.0, white.1, 1.0);
            let [r, g, b] = self.primaries().map(|(x, y)| xyz_from_xy_y(x, y, 1.0));
            let p = DMat3::from_cols(r, g, b);
            let c = p.inverse() * w;
            let rgb_to_xyz = p * DMat3::from_diagonal(c);
            Matrices { white, rgb_to_xyz, xyz_to_rgb: rgb_to_xyz.inverse() }
        })
    }
}

/// The Bradford cone-response matrix (Lam 1985; CIE 159:2004 uses its
/// linearised form): rows give the sharpened cone responses ρ, γ, β of XYZ.
const BRADFORD: DMat3 = DMat3::from_cols(
    DVec3::new(0.8951, -0.7502, 0.0389),
    DVec3::new(0.2664, 1.7135, -0.0685),
    DVec3::new(-0.1614, 0.0367, 1.0296),
);

/// The von Kries chromatic adaptation in the Bradford cone space from white
/// `from` to white `to` (chromaticities), an XYZ→XYZ matrix:
/// `M⁻¹ · diag(M·W_to / M·W_from) · M`, both whites at `Y = 1`. pbrt-v4's
/// `WhiteBalance` is the same transform.
///
/// ```
/// use lucent::spectrum::{bradford_adaptation, xyz_from_xy_y};
///
/// let a = bradford_adaptation((0.3457, 0.3585), (0.3127, 0.3290));
/// let d65 = a * xyz_from_xy_y(0.3457, 0.3585, 1.0);
/// assert!((d65 - xyz_from_xy_y(0.3127, 0.3290, 1.0)).length() < 1e-12);
/// ```
pub fn bradford_adaptation(from: (f64, f64), to: (f64, f64)) -> DMat3 {
    let src = BRADFORD * xyz_from_xy_y(from.0, from.1, 1.0);
    let dst = BRADFORD * xyz_from_xy_y(to.0, to.1, 1.0);
    BRADFORD.inverse() * DMat3::from_diagonal(dst / src) * BRADFORD
}

/// A colour of `space` in lucent's working space, linear sRGB, with the
/// white adapted ([`ColorSpace::to_linear_srgb`]): for reflectances and
/// other unitless colours (`rgb` albedos, `eta`/`k`, image textures).
/// For `rgb` light values use [`illuminant_rgb_to_linear_srgb`].
pub fn rgb_to_linear_srgb(space: ColorSpace, c: Color) -> Color {
    if space == ColorSpace::Srgb {
        return c;
    }
    (space.to_linear_srgb() * c.as_dvec3()).as_vec3a()
}

/// An `rgb` light value (`L`, `I`) of `space` in linear sRGB, as pbrt-v4
/// renders it: its `RGBIlluminantSpectrum` is the colour times the space's
/// illuminant, normalised by the illuminant's luminance alone, so it
/// carries the colour's XYZ in that space unadapted
/// ([`ColorSpace::to_linear_srgb_unadapted`]). sRGB values pass through:
/// (1, 1, 1) is radiance (1, 1, 1).
pub fn illuminant_rgb_to_linear_srgb(space: ColorSpace, c: Color) -> Color {
    if space == ColorSpace::Srgb {
        return c;
    }
    (space.to_linear_srgb_unadapted() * c.as_dvec3()).as_vec3a()
}

/// CIE XYZ in linear sRGB.
pub fn xyz_to_linear_srgb(xyz: DVec3) -> Color {
    (ColorSpace::Srgb.xyz_to_rgb() * xyz).as_vec3a()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_matrix(m: DMat3, rows: [[f64; 3]; 3], tol: f64, what: &str) {
        for (i, row) in rows.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                let got = m.col(j)[i];
                assert!((got - v).abs() < tol, "{what}[{i}][{j}] = {got}, expected {v}\n{m}");
            }
        }
    }

    #[test]
    fn names_round_trip_and_unknown_names_list_them() {
        for s in ColorSpace::ALL {
            assert_eq!(ColorSpace::from_name(s.name()), Ok(s));
            assert_eq!(ColorSpace::from_name(&s.name().to_uppercase()), Ok(s));
        }
        let e = ColorSpace::from_name("p3").unwrap_err().to_string();
        assert!(e.contains("`p3`") && e.contains("srgb, rec2020, aces2065-1, dci-p3"), "{e}");
    }

    #[test]
    fn srgb_is_the_identity_and_its_matrix_the_standard_one() {
        assert_eq!(ColorSpace::Srgb.to_linear_srgb(), DMat3::IDENTITY);
        assert_eq!(ColorSpace::Srgb.to_linear_srgb_unadapted(), DMat3::IDENTITY);
        let c = Color::new(0.25, 2.0, -0.5);
        assert_eq!(rgb_to_linear_srgb(ColorSpace::Srgb, c), c);
        assert_eq!(illuminant_rgb_to_linear_srgb(ColorSpace::Srgb, c), c);
        // IEC 61966-2-1 (its white is D65 at (0.3127, 0.3290); ours is the
        // tabulated D65 spectrum's, (0.31272, 0.32903)).
        assert_matrix(
            ColorSpace::Srgb.xyz_to_rgb(),
            [[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]],
            2e-3,
            "XYZ→sRGB",
        );
    }

    #[test]
    fn every_white_becomes_srgb_white() {
        for s in ColorSpace::ALL {
            let w = rgb_to_linear_srgb(s, Color::ONE);
            assert!((w - Color::ONE).abs().max_element() < 1e-5, "{s:?}: {w}");
            // Its white is its illuminant's colour, at Y = 1.
            let xyz = s.rgb_to_xyz() * DVec3::ONE;
            assert!((xyz - spectrum_to_xyz(&s.illuminant())).length() < 1e-9, "{s:?}");
        }
        // Unadapted, ACES's white is the D60 illuminant: warmer than D65.
        let w = illuminant_rgb_to_linear_srgb(ColorSpace::Aces2065_1, Color::ONE);
        assert!(w.x > 1.0 && w.z < 1.0, "{w}");
        assert!((crate::color::luminance(w) - 1.0).abs() < 1e-3, "{w}");
    }

    #[test]
    fn known_conversion_matrices() {
        // Rec. 2020 → Rec. 709 (ITU-R BT.2087-0, eq. 4): the images of the
        // Rec. 2020 primaries are its columns.
        let m = ColorSpace::Rec2020.to_linear_srgb();
        assert_matrix(
            m,
            [[1.6605, -0.5876, -0.0728], [-0.1246, 1.1329, -0.0083], [-0.0182, -0.1006, 1.1187]],
            1e-3,
            "Rec.2020→sRGB",
        );
        let red = rgb_to_linear_srgb(ColorSpace::Rec2020, Color::X);
        assert!((red - Color::new(1.6605, -0.1246, -0.0182)).abs().max_element() < 1e-3, "{red}");
        // Display P3 → sRGB (both D65).
        assert_matrix(
            ColorSpace::DciP3.to_linear_srgb(),
            [[1.2249, -0.2247, 0.0], [-0.0420, 1.0419, 0.0], [-0.0197, -0.0786, 1.0979]],
            1e-3,
            "P3→sRGB",
        );
        // ACES2065-1 → sRGB with Bradford adaptation from the ACES white
        // (as tabulated by e.g. colour-science and OpenColorIO's ACES config).
        assert_matrix(
            ColorSpace::Aces2065_1.to_linear_srgb(),
            [[2.5217, -1.1341, -0.3876], [-0.2765, 1.3727, -0.0962], [-0.0154, -0.1530, 1.1684]],
            3e-3,
            "AP0→sRGB",
        );
    }

    #[test]
    fn bradford_maps_white_to_white_and_is_identity_for_one_white() {
        let d50 = (0.34567, 0.35851);
        let d65 = (0.31272, 0.32903);
        assert!((bradford_adaptation(d65, d65) - DMat3::IDENTITY).abs().to_cols_array().iter().all(|v| *v < 1e-12));
        // Bradford D65 → D50 (Lindbloom's table, whites (0.95047, 1, 1.08883)
        // and (0.96422, 1, 0.82521)).
        let m = bradford_adaptation((0.95047 / 3.03930, 1.0 / 3.03930), (0.96422 / 2.78943, 1.0 / 2.78943));
        assert_matrix(
            m,
            [
                [1.0478112, 0.0228866, -0.0501270],
                [0.0295424, 0.9904844, -0.0170491],
                [-0.0092345, 0.0150436, 0.7521316],
            ],
            1e-5,
            "Bradford D65→D50",
        );
        let a = bradford_adaptation(d65, d50);
        assert!((a * xyz_from_xy_y(d65.0, d65.1, 1.0) - xyz_from_xy_y(d50.0, d50.1, 1.0)).length() < 1e-12);
    }
}
