//! Spectra and RGB colour spaces, for scenes that describe colour
//! spectrally (pbrt-v4): lucent renders in linear RGB with the sRGB /
//! Rec. 709 primaries and the D65 white, so every spectrum becomes RGB
//! once, at load time.
//!
//! # Spectra
//!
//! A [`Spectrum`] is a constant, a blackbody (Planck's law, normalised to
//! peak 1 as in pbrt-v4), or piecewise linear: pbrt's inline `spectrum`
//! values ([`Spectrum::from_interleaved`]), `.spd` files ([`parse_spd`],
//! [`read_spd`]) and pbrt-v4's named spectra ([`Spectrum::named`],
//! [`NAMED_SPECTRA`]): metal `eta`/`k`, glass `eta` and the CIE standard
//! illuminants. Colour comes from the CIE 1931 2° colour-matching functions
//! tabulated at 1 nm from 360 to 830 nm (CIE 015:2004); every integral is
//! pbrt-v4's sum over the whole wavelengths 360, 361, …, 830 nm.
//!
//! # Conversions
//!
//! Which conversion applies depends on what the spectrum is
//! ([`SpectrumType`], as pbrt-v4's `SpectrumType`); `M` is the XYZ → linear
//! sRGB matrix and `x̄ȳz̄` the colour-matching functions:
//!
//! - **reflectances** (albedos, [`reflectance_to_rgb`]): the colour of the
//!   spectrum under D65, the sRGB white, relative to a white surface,
//!   `M · Σ ρ D65 x̄ȳz̄ / Σ D65 ȳ`. The constant `c` is `(c, c, c)`.
//! - **unbounded** quantities (a conductor's `eta`, `k`;
//!   [`unbounded_to_rgb`]): the same projection, so a constant `c` is
//!   `(c, c, c)`. This approximates spectral rendering: Fresnel reflectance
//!   is not linear in η and k.
//! - **illuminants** (`L`, `I`; [`illuminant_to_rgb`]): pbrt-v4's lights
//!   divide their `scale` by the spectrum's luminance
//!   (`SpectrumToPhotometric`), so a spectral light has luminance 1 times
//!   `scale`: `M · XYZ(s) / Y(s)`. An `rgb` light value is, in pbrt-v4,
//!   the colour times the colour space's illuminant, normalised by the
//!   illuminant's luminance, so sRGB (1, 1, 1) is radiance (1, 1, 1) and an
//!   sRGB value passes through ([`illuminant_rgb_to_linear_srgb`]).
//! - **`blackbody`** values ([`blackbody_rgb`]): the normalised blackbody
//!   as an illuminant, luminance 1 at any temperature.
//! - a **dielectric's `eta`** given as a spectrum ([`dielectric_eta`]): its
//!   value at 550 nm (lucent has no dispersion).
//!
//! # Colour spaces
//!
//! `rgb` values and images may be in any of pbrt-v4's spaces
//! ([`ColorSpace`]: sRGB, Rec. 2020, ACES2065-1, DCI-P3 with the D65
//! white). [`rgb_to_linear_srgb`] brings reflectance-like colours to
//! linear sRGB through XYZ, adapting the white with the Bradford transform
//! where it is not D65 (ACES); [`illuminant_rgb_to_linear_srgb`] does not
//! adapt, as pbrt-v4's light colours keep their space's white.

mod cie;
mod color_space;
mod convert;
mod data;
mod kinds;
mod named;
mod spd;

pub use cie::{
    chromaticity, color_matching, spectrum_to_xyz, xyz_from_xy_y, xyz_integral, CIE_Y_INTEGRAL, LAMBDA_MAX, LAMBDA_MIN,
};
pub use color_space::{
    bradford_adaptation, illuminant_rgb_to_linear_srgb, rgb_to_linear_srgb, xyz_to_linear_srgb, ColorSpace,
};
pub use convert::{
    blackbody_rgb, dielectric_eta, illuminant_to_rgb, luminance_of, reflectance_to_rgb, unbounded_to_rgb, SpectrumType,
    ETA_WAVELENGTH,
};
pub use kinds::{planck, Blackbody, PiecewiseLinear, Spectrum};
pub use named::{cie_daylight, NAMED_SPECTRA};
pub use spd::{parse_spd, read_spd};

use std::path::PathBuf;

/// A spectrum or colour space cannot be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpectrumError {
    /// Not one of [`NAMED_SPECTRA`].
    #[error("unknown named spectrum `{0}`; the named spectra are: {names}", names = NAMED_SPECTRA.join(", "))]
    UnknownName(String),
    /// Neither a named spectrum nor an existing `.spd` file.
    #[error(
        "`{name}` is neither a named spectrum nor a spectrum file ({} does not exist); the named spectra are: {names}",
        path.display(),
        names = NAMED_SPECTRA.join(", ")
    )]
    NoSuchSpectrum {
        /// The name as written.
        name: String,
        /// The file it would be.
        path: PathBuf,
    },
    /// Not one of pbrt-v4's colour spaces.
    #[error("unknown colour space `{0}`; the colour spaces are: srgb, rec2020, aces2065-1, dci-p3")]
    UnknownColorSpace(String),
    /// No samples.
    #[error("a spectrum needs at least one wavelength–value pair")]
    Empty,
    /// An odd count of numbers: a wavelength without its value.
    #[error("a spectrum needs wavelength–value pairs, but {0} numbers were given")]
    OddCount(usize),
    /// The wavelengths do not increase.
    #[error("spectrum wavelengths must increase, but pair {index} has wavelength {lambda} after {previous}")]
    NotIncreasing {
        /// Which pair (from 0).
        index: usize,
        /// The wavelength before it.
        previous: f64,
        /// Its wavelength.
        lambda: f64,
    },
    /// A wavelength or value is NaN or infinite.
    #[error("spectrum pair {index} ({lambda}, {value}) is not finite")]
    NonFinite {
        /// Which pair (from 0).
        index: usize,
        /// Its wavelength.
        lambda: f64,
        /// Its value.
        value: f64,
    },
    /// A blackbody or white-balance temperature that is not positive and
    /// finite.
    #[error("temperature {0} K is invalid: it must be a positive finite number of kelvin")]
    Temperature(f64),
    /// A `.spd` text is malformed.
    #[error("{}line {line}: {message}", path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default())]
    Spd {
        /// The file, if the text came from one.
        path: Option<PathBuf>,
        /// The line (from 1).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A `.spd` file cannot be read.
    #[error("cannot read spectrum file {}: {message}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        message: String,
    },
}
