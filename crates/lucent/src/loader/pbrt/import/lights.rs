//! `LightSource` and `AreaLightSource`: pbrt-v4's lights.
//!
//! Light colours become linear sRGB as [`super::spectra`] says (an `rgb`
//! value is kept; a `blackbody` or `spectrum` has unit luminance), then
//! are multiplied by `scale` and, where given, by `power / k` (point,
//! spot) or `illuminance / k` (distant, infinite), as pbrt-v4 does (its
//! `power` assumes a light of unit luminance: an `rgb` colour is not
//! normalised first, so `rgb I [2 2 2]` with `power` emits twice that
//! power, in pbrt-v4 as here), where `k` is pbrt-v4's constant: a point light of intensity `I` emits `4π I`,
//! a spot `2π I (1 − (cos θ_start + cos θ_end)/2)`, a one-sided diffuse
//! area light of radiance `L` and area `A` emits `π A L`; a distant light
//! of radiance `L` gives irradiance `L`, a constant infinite light `π L`
//! on an upward-facing surface.

use super::builder_error;
use super::spectra::{param_loc, SpectrumUse};
use super::{AreaLightSpec, Importer};
use crate::color::Color;
use crate::geometry::Vec3;
use crate::light::{read_environment_image, Environment, EnvironmentMapping, Falloff, Light, MapOptions};
use crate::loader::pbrt::{Loc, ParamList, PbrtError};
use std::f32::consts::PI;

impl Importer<'_> {
    /// A light colour: `name` as an illuminant, else `default`, times
    /// `scale`.
    fn light_color(&mut self, params: &ParamList, name: &str, default: Color, loc: &Loc) -> Result<Color, PbrtError> {
        let c = self.color(params, name, SpectrumUse::Illuminant)?.unwrap_or(default);
        let scale = params.float("scale")?.unwrap_or(1.0);
        if !(scale >= 0.0 && scale.is_finite()) {
            return Err(PbrtError::at(
                &param_loc(params, "scale", loc),
                format!("\"float scale\" must be ≥ 0, got {scale}"),
            ));
        }
        Ok(c * scale)
    }

    /// A non-negative `power`/`illuminance` parameter, if given (pbrt's
    /// default −1 means "not given").
    fn photometric(&self, params: &ParamList, name: &str, loc: &Loc) -> Result<Option<f32>, PbrtError> {
        match params.float(name)? {
            Some(v) if v > 0.0 && v.is_finite() => Ok(Some(v)),
            Some(v) if v < 0.0 => Ok(None),
            Some(v) => Err(PbrtError::at(
                &param_loc(params, name, loc),
                format!("\"float {name}\" must be a finite number, got {v}"),
            )),
            None => Ok(None),
        }
    }

    /// Handle a `LightSource` directive.
    pub fn light(&mut self, ty: &str, params: &ParamList, loc: &Loc) -> Result<(), PbrtError> {
        let t = self.state.ctm;
        let light_err = |e: crate::light::LightError| PbrtError::at(loc, format!("LightSource \"{ty}\": {e}"));
        match ty {
            "point" => {
                let mut i = self.light_color(params, "I", Color::ONE, loc)?;
                let from = params.point3("from")?.unwrap_or(Vec3::ZERO);
                if let Some(power) = self.photometric(params, "power", loc)? {
                    i *= power / (4.0 * PI);
                }
                let light = Light::point(t.point(from), i, 1.0, Falloff::InverseSquare).map_err(light_err)?;
                self.builder.add_light(light);
            }
            "spot" => {
                let mut i = self.light_color(params, "I", Color::ONE, loc)?;
                let from = params.point3("from")?.unwrap_or(Vec3::ZERO);
                let to = params.point3("to")?.unwrap_or(Vec3::Z);
                let angle = params.float("coneangle")?.unwrap_or(30.0);
                let delta = params.float("conedelta")?.unwrap_or(5.0);
                if let Some(power) = self.photometric(params, "power", loc)? {
                    let cos_end = angle.to_radians().cos();
                    let cos_start = (angle - delta).to_radians().cos();
                    i *= power / (2.0 * PI * (1.0 - 0.5 * (cos_start + cos_end)));
                }
                let dir = t.vector(to - from);
                let light = Light::spot(t.point(from), dir, i, 1.0, angle, delta.min(angle), Falloff::InverseSquare)
                    .map_err(light_err)?;
                self.builder.add_light(light);
            }
            "distant" => {
                let mut l = self.light_color(params, "L", Color::ONE, loc)?;
                let from = params.point3("from")?.unwrap_or(Vec3::ZERO);
                let to = params.point3("to")?.unwrap_or(Vec3::Z);
                if let Some(e) = self.photometric(params, "illuminance", loc)? {
                    l *= e;
                }
                // Light travels from `from` towards `to`.
                let light = Light::directional(t.vector(to - from), l, 1.0).map_err(light_err)?;
                self.builder.add_light(light);
            }
            "infinite" => self.infinite(params, loc)?,
            "goniometric" | "projection" => {
                for p in &params.params {
                    p.used.set(true);
                }
                let i = self.light_color(params, "I", Color::ONE, loc).unwrap_or(Color::ONE);
                let light = Light::point(t.point(Vec3::ZERO), i, 1.0, Falloff::InverseSquare).map_err(light_err)?;
                self.builder.add_light(light);
                self.warnings.warn(
                    loc,
                    format!("LightSource \"{ty}\" is not supported: rendered as a point light of the same intensity `I`, without its image"),
                )?;
            }
            other => {
                for p in &params.params {
                    p.used.set(true);
                }
                self.warnings.warn(
                    loc,
                    format!("unknown LightSource \"{other}\" is skipped (supported: point, spot, distant, infinite)"),
                )?;
            }
        }
        Ok(())
    }

    /// `LightSource "infinite"`: constant `L`, or an image (`filename`:
    /// pbrt-v4's equal-area octahedral square, or a lat-long image).
    fn infinite(&mut self, params: &ParamList, loc: &Loc) -> Result<(), PbrtError> {
        let world_from_light = self.state.ctm;
        let filename = params.string("filename")?;
        let _ = params.get("portal");
        if filename.is_none() {
            let l = self.light_color(params, "L", Color::ONE, loc)?;
            let illuminance = self.photometric(params, "illuminance", loc)?;
            let env = Environment::uniform(l, 1.0, illuminance)
                .map_err(|e| PbrtError::at(loc, format!("LightSource \"infinite\": {e}")))?;
            self.builder.set_environment(env).map_err(|e| builder_error(loc, e))?;
            return Ok(());
        }
        if params.get("L").is_some() {
            return Err(PbrtError::at(loc, "LightSource \"infinite\": give either \"L\" or \"filename\", not both"));
        }
        let name = filename.unwrap_or_default();
        let at = param_loc(params, "filename", loc);
        let path = match &self.options.environment {
            Some(over) => over.clone(),
            None => {
                let path = self.resolve(name, &at);
                if !path.exists() {
                    return Err(PbrtError::at(
                        &at,
                        format!(
                            "the environment map {} does not exist (the scene may be shipped without it): render with `--env IMAGE` to light the scene with another image",
                            path.display()
                        ),
                    ));
                }
                path
            }
        };
        let scale = params.float("scale")?.unwrap_or(1.0);
        let illuminance = self.photometric(params, "illuminance", loc)?;
        // pbrt-v4 ships square equal-area octahedral maps; a non-square
        // image is read as latitude–longitude (what most users have).
        // One reader for every format (EXR, HDR, PFM, 8-bit), shared with
        // image textures; the image is read once and its size picks the
        // mapping.
        let image = read_environment_image(&path).map_err(|e| PbrtError::at(&at, e.to_string()))?;
        let (w, h) = (image.width(), image.height());
        // pbrt's light space is z-up; a lat-long image is y-up in its own
        // frame, so it is first turned (y → z) to keep the scene's zenith.
        let (mapping, light_to_world) = if w == h {
            (EnvironmentMapping::EqualArea, world_from_light)
        } else {
            (EnvironmentMapping::Equirectangular, crate::geometry::Transform::rotate_x(90.0).then(&world_from_light))
        };
        let options = MapOptions { mapping, light_to_world, scale, illuminance };
        let env = Environment::from_image_with(&path, &image, &options)
            .map_err(|e| PbrtError::at(&at, format!("LightSource \"infinite\": {e}")))?;
        self.files.push(path);
        self.builder.set_environment(env).map_err(|e| builder_error(loc, e))?;
        Ok(())
    }

    /// Handle an `AreaLightSource` directive: shapes that follow emit.
    pub fn area_light(&mut self, ty: &str, params: &ParamList, loc: &Loc) -> Result<(), PbrtError> {
        if ty != "diffuse" {
            for p in &params.params {
                p.used.set(true);
            }
            self.warnings
                .warn(loc, format!("AreaLightSource \"{ty}\" is not supported: shapes after it do not emit"))?;
            self.state.area_light = None;
            return Ok(());
        }
        let two_sided = params.bool("twosided")?.unwrap_or(false);
        // pbrt-v4's DiffuseAreaLight: an image `filename` replaces `L`; its
        // RGB, read at the surface's (u, 1 − v) with bilinear interpolation,
        // is the radiance (times `scale`).
        let image = match params.string("filename")? {
            None => None,
            Some(name) => {
                if params.get("L").is_some() {
                    return Err(PbrtError::at(
                        &param_loc(params, "L", loc),
                        "AreaLightSource \"diffuse\": give either \"L\" or \"filename\", not both",
                    ));
                }
                let at = param_loc(params, "filename", loc);
                let path = self.resolve(name, &at);
                Some(self.emission_image(&path, &at)?)
            }
        };
        let l = self.light_color(params, "L", Color::ONE, loc)?;
        if self.photometric(params, "power", loc)?.is_some() {
            self.warnings.warn(
                loc,
                "AreaLightSource \"power\" is not supported (it depends on each shape's area): \"L\" and \"scale\" are used",
            )?;
        }
        self.state.area_light = Some(AreaLightSpec { radiance: l, two_sided, image });
        Ok(())
    }
}
