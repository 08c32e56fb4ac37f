//! Colours of parameters: `rgb` (in the current colour space),
//! `blackbody`, and `spectrum` (inline pairs, a named spectrum or an `.spd`
//! file), converted to lucent's linear sRGB once, as
//! [`crate::spectrum`] documents.

use super::Importer;
use crate::color::Color;
use crate::loader::pbrt::{Loc, Param, ParamList, ParamType, ParamValues, PbrtError};
use crate::spectrum::{self, Spectrum};

/// How a spectrum is used, which decides how it becomes RGB.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SpectrumUse {
    /// A reflectance or transmittance in [0, 1].
    Albedo,
    /// Any non-negative quantity (a conductor's η or k).
    Unbounded,
    /// Emitted light (normalised to unit luminance as pbrt-v4 does).
    Illuminant,
}

impl Importer<'_> {
    /// The colour of parameter `name` if given as `rgb`, `blackbody` or
    /// `spectrum` (`Ok(None)` when absent or given as a texture).
    pub fn color(&mut self, params: &ParamList, name: &str, usage: SpectrumUse) -> Result<Option<Color>, PbrtError> {
        let Some(p) = params.get(name) else { return Ok(None) };
        let color = match p.ty {
            ParamType::Rgb => {
                let v = numbers(p)?;
                let [r, g, b] = [v[0], v[1], v[2]];
                if !(r >= 0.0 && g >= 0.0 && b >= 0.0 && r.is_finite() && g.is_finite() && b.is_finite()) {
                    return Err(PbrtError::at(&p.loc, format!("{}: RGB values must be finite and ≥ 0", p.describe())));
                }
                let rgb = Color::new(r, g, b);
                match usage {
                    SpectrumUse::Albedo if rgb.max_element() > 1.0 => {
                        return Err(PbrtError::at(
                            &p.loc,
                            format!(
                                "{}: a reflectance must be at most 1 in every channel, got {r} {g} {b}",
                                p.describe()
                            ),
                        ))
                    }
                    SpectrumUse::Illuminant => spectrum::illuminant_rgb_to_linear_srgb(self.state.color_space, rgb),
                    _ => spectrum::rgb_to_linear_srgb(self.state.color_space, rgb),
                }
            }
            ParamType::Blackbody => {
                let t = numbers(p)?[0];
                if !(t > 0.0 && t.is_finite()) {
                    return Err(PbrtError::at(
                        &p.loc,
                        format!("{}: the temperature must be positive (kelvin), got {t}", p.describe()),
                    ));
                }
                spectrum::blackbody_rgb(t).map_err(|e| PbrtError::at(&p.loc, format!("{}: {e}", p.describe())))?
            }
            ParamType::Spectrum => {
                let s = self.spectrum(p)?;
                match usage {
                    SpectrumUse::Albedo => spectrum::reflectance_to_rgb(&s),
                    SpectrumUse::Unbounded => spectrum::unbounded_to_rgb(&s),
                    SpectrumUse::Illuminant => spectrum::illuminant_to_rgb(&s),
                }
            }
            ParamType::Texture => return Ok(None),
            other => {
                return Err(PbrtError::at(
                    &p.loc,
                    format!("{}: expected an rgb, blackbody or spectrum value, not {}", p.describe(), other.name()),
                ))
            }
        };
        p.used.set(true);
        Ok(Some(color))
    }

    /// The spectrum of a `spectrum` parameter: inline wavelength–value
    /// pairs, a named spectrum, or an `.spd` file.
    pub fn spectrum(&mut self, p: &Param) -> Result<Spectrum, PbrtError> {
        p.used.set(true);
        match &p.values {
            ParamValues::Floats(v) => {
                Spectrum::from_interleaved(v).map_err(|e| PbrtError::at(&p.loc, format!("{}: {e}", p.describe())))
            }
            ParamValues::Strings(names) if names.len() == 1 => {
                let name = &names[0];
                if Spectrum::is_named(name) {
                    return Spectrum::named(name).map_err(|e| PbrtError::at(&p.loc, format!("{}: {e}", p.describe())));
                }
                let path = self.resolve(name, &p.loc);
                if path.exists() {
                    self.files.push(path.clone());
                    return spectrum::read_spd(&path)
                        .map_err(|e| PbrtError::at(&p.loc, format!("{}: {e}", p.describe())));
                }
                Err(PbrtError::at(
                    &p.loc,
                    format!(
                        "{}: \"{name}\" is neither a named spectrum (such as \"metal-Cu-eta\", \"glass-BK7\", \"stdillum-D65\") nor an existing .spd file ({})",
                        p.describe(),
                        path.display()
                    ),
                ))
            }
            _ => Err(PbrtError::at(
                &p.loc,
                format!("{}: give wavelength–value pairs, or one name of a spectrum or .spd file", p.describe()),
            )),
        }
    }

    /// An index of refraction: a `float`, or a `spectrum` taken at 550 nm
    /// (pbrt-v4 renders a dispersive glass spectrally; lucent uses one
    /// index).
    pub fn eta(&mut self, params: &ParamList, name: &str, default: f32) -> Result<f32, PbrtError> {
        let Some(p) = params.get(name) else { return Ok(default) };
        let eta = match p.ty {
            ParamType::Float => params.float(name)?.unwrap_or(default),
            ParamType::Spectrum => {
                let s = self.spectrum(p)?;
                if !matches!(s, Spectrum::Constant(_)) {
                    self.warnings.warn_once(
                        "dispersion",
                        &p.loc,
                        "dispersion is not rendered: a spectral index of refraction is taken at 550 nm",
                    )?;
                }
                spectrum::dielectric_eta(&s)
            }
            ParamType::Texture => {
                self.warnings.warn(
                    &p.loc,
                    format!("{}: a textured index of refraction is not supported: {default} is used", p.describe()),
                )?;
                p.used.set(true);
                default
            }
            other => {
                return Err(PbrtError::at(
                    &p.loc,
                    format!("{}: expected a float or a spectrum, not {}", p.describe(), other.name()),
                ))
            }
        };
        if !(eta > 0.0 && eta.is_finite()) {
            return Err(PbrtError::at(
                &p.loc,
                format!("{}: the index of refraction must be positive, got {eta}", p.describe()),
            ));
        }
        Ok(eta)
    }
}

/// The numbers of an `rgb` or `blackbody` parameter (the parser has
/// checked their count: 3 and 1).
fn numbers(p: &Param) -> Result<&[f32], PbrtError> {
    match &p.values {
        ParamValues::Floats(v) if !v.is_empty() => Ok(v),
        _ => Err(PbrtError::at(&p.loc, format!("{}: expected numbers", p.describe()))),
    }
}

/// Where a parameter is, or the directive when it is absent.
pub(crate) fn param_loc(params: &ParamList, name: &str, directive: &Loc) -> Loc {
    params.params.iter().find(|p| p.name == name).map_or_else(|| directive.clone(), |p| p.loc.clone())
}
