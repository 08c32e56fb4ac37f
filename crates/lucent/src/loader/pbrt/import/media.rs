//! `MakeNamedMedium` and `MediumInterface`: pbrt-v4's participating media.
//!
//! A named medium is made once; `MediumInterface "inside" "outside"` sets
//! the media of the shapes that follow (saved and restored by
//! `AttributeBegin`/`AttributeEnd`, `""` meaning vacuum), and the camera
//! is in the "outside" medium current at the `Camera` directive (pbrt-v4's
//! `CameraMedium`). Homogeneous media are rendered
//! ([`crate::medium::HomogeneousMedium`]); grid media (`uniformgrid`,
//! `rgbgrid`, `cloud`, `nanovdb`) are skipped with a warning and render as
//! vacuum. As in pbrt-v4, which resolves names after the whole file is
//! read, a shape may name a medium defined further on.

use super::spectra::{param_loc, SpectrumUse};
use super::Importer;
use crate::color::Color;
use crate::loader::pbrt::{Loc, ParamList, PbrtError};
use crate::medium::{measured_medium, HomogeneousMedium, Medium, MediumId, MediumInterface};

impl Importer<'_> {
    /// `MakeNamedMedium "name"` with its parameters.
    pub fn make_named_medium(&mut self, name: &str, params: &ParamList, loc: &Loc) -> Result<(), PbrtError> {
        let ty = params.string("type")?.ok_or_else(|| {
            PbrtError::at(loc, format!("MakeNamedMedium \"{name}\" needs a \"string type\" parameter"))
        })?;
        // A medium a shape named before: its handle is already taken.
        let reserved = self.pending_media.remove(name).and_then(|_| self.media.get(name).copied().flatten());
        let id = match ty {
            "homogeneous" => {
                let medium = Medium::Homogeneous(self.homogeneous(name, params, loc)?);
                let id = match reserved {
                    Some(id) => self.builder.set_medium(id, medium).map(|_| id),
                    None => self.builder.add_medium(medium),
                };
                Some(id.map_err(|e| super::builder_error(loc, e))?)
            }
            "uniformgrid" | "rgbgrid" | "cloud" | "nanovdb" => {
                for p in &params.params {
                    p.used.set(true);
                }
                self.warnings.warn(
                    loc,
                    format!("MakeNamedMedium \"{name}\": \"{ty}\" media are not supported: rendered as vacuum (supported: homogeneous)"),
                )?;
                // A reserved handle stays vacuum.
                reserved
            }
            other => {
                return Err(PbrtError::at(
                    &param_loc(params, "type", loc),
                    format!("MakeNamedMedium \"{name}\": unknown medium type \"{other}\" (accepted: homogeneous, uniformgrid, rgbgrid, cloud, nanovdb)"),
                ))
            }
        };
        if self.media.insert(name.to_owned(), id).is_some() && reserved.is_none() {
            self.warnings.warn(loc, format!("named medium \"{name}\" redefined"))?;
        }
        Ok(())
    }

    /// pbrt-v4's `HomogeneousMedium::Create`: `preset` (a measured medium)
    /// or `sigma_a` and `sigma_s` (default 1 each), times `scale`; `g`;
    /// emission `Le` times `Lescale`.
    fn homogeneous(&mut self, name: &str, params: &ParamList, loc: &Loc) -> Result<HomogeneousMedium, PbrtError> {
        let mut coefficients = None;
        if let Some(preset) = params.string("preset")? {
            match measured_medium(preset) {
                Some(c) => coefficients = Some(c),
                None => self.warnings.warn(
                    &param_loc(params, "preset", loc),
                    format!("MakeNamedMedium \"{name}\": unknown preset \"{preset}\" (sigma_a and sigma_s are used; the presets are pbrt-v4's, e.g. \"Wholemilk\", \"Ketchup\", \"Espresso\")"),
                )?,
            }
        }
        let sigma_a = self.color(params, "sigma_a", SpectrumUse::Unbounded)?;
        let sigma_s = self.color(params, "sigma_s", SpectrumUse::Unbounded)?;
        let (sigma_a, sigma_s) = match coefficients {
            // pbrt-v4 ignores sigma_a and sigma_s when a preset is found.
            Some(c) => c,
            None => (sigma_a.unwrap_or(Color::ONE), sigma_s.unwrap_or(Color::ONE)),
        };
        let scale = params.float("scale")?.unwrap_or(1.0);
        let g = params.float("g")?.unwrap_or(0.0);
        let le = self.color(params, "Le", SpectrumUse::Illuminant)?.unwrap_or(Color::ZERO);
        let le_scale = params.float("Lescale")?.unwrap_or(1.0);
        if !(le_scale.is_finite() && le_scale >= 0.0) {
            return Err(PbrtError::at(
                &param_loc(params, "Lescale", loc),
                format!("MakeNamedMedium \"{name}\": \"float Lescale\" must be ≥ 0, got {le_scale}"),
            ));
        }
        HomogeneousMedium::new(sigma_a, sigma_s, scale, g, le * le_scale)
            .map_err(|e| PbrtError::at(loc, format!("MakeNamedMedium \"{name}\": {e}")))
    }

    /// The medium named `name` (`""`: vacuum, as is a medium of an
    /// unsupported type).
    pub fn medium_named(&self, name: &str, loc: &Loc) -> Result<Option<MediumId>, PbrtError> {
        if name.is_empty() {
            return Ok(None);
        }
        self.media.get(name).copied().ok_or_else(|| {
            PbrtError::at(loc, format!("medium \"{name}\" is not defined (MakeNamedMedium must come first)"))
        })
    }

    /// The media of the current `MediumInterface`, for a shape. A name not
    /// defined yet gets a handle that holds vacuum until its
    /// `MakeNamedMedium` (an error at the end if none comes).
    pub fn current_media(&mut self, loc: &Loc) -> Result<MediumInterface, PbrtError> {
        let inside = self.state.medium_inside.clone();
        let outside = self.state.medium_outside.clone();
        Ok(MediumInterface::new(self.medium_for_shape(&inside, loc)?, self.medium_for_shape(&outside, loc)?))
    }

    fn medium_for_shape(&mut self, name: &str, loc: &Loc) -> Result<Option<MediumId>, PbrtError> {
        if name.is_empty() {
            return Ok(None);
        }
        if let Some(&id) = self.media.get(name) {
            return Ok(id);
        }
        let vacuum = HomogeneousMedium::new(Color::ZERO, Color::ZERO, 1.0, 0.0, Color::ZERO)
            .expect("zero coefficients are a valid medium");
        let id = self.builder.add_medium(Medium::Homogeneous(vacuum)).map_err(|e| super::builder_error(loc, e))?;
        self.media.insert(name.to_owned(), Some(id));
        self.pending_media.insert(name.to_owned(), loc.clone());
        Ok(Some(id))
    }
}
