//! `Material`, `MakeNamedMaterial` and `Texture`: pbrt-v4's materials and
//! textures as lucent's.

use super::spectra::{param_loc, SpectrumUse};
use super::Importer;
use crate::bsdf::ConductorFresnel;
use crate::color::Color;
use crate::loader::pbrt::{Loc, ParamList, ParamType, PbrtError};
use crate::material::{
    CoatedConductorMaterial, CoatedDiffuseMaterial, Material, MaterialId, Roughness, COPPER_ETA, COPPER_K,
};
use crate::texture::{FloatTexture, Texture};
use std::collections::HashMap;
use std::sync::Arc;

/// Materials and textures by name.
#[derive(Clone, Debug, Default)]
pub(crate) struct MaterialTable {
    /// `MakeNamedMaterial` names.
    pub named: HashMap<String, MaterialId>,
    /// pbrt-v4's default material (diffuse, reflectance 0.5), once made.
    pub default: Option<MaterialId>,
    /// Spectrum textures by name.
    pub textures: HashMap<String, Arc<Texture>>,
    /// Float textures by name.
    pub float_textures: HashMap<String, Arc<FloatTexture>>,
}

impl Importer<'_> {
    /// A spectrum-valued parameter that may be a texture: `Ok(None)` when
    /// absent.
    pub fn spectrum_texture(
        &mut self,
        params: &ParamList,
        name: &str,
        usage: SpectrumUse,
    ) -> Result<Option<Texture>, PbrtError> {
        let Some(p) = params.get(name) else { return Ok(None) };
        if p.ty == ParamType::Texture {
            let tex = params.texture(name)?.unwrap_or_default().to_owned();
            return match self.materials.textures.get(&tex) {
                Some(t) => Ok(Some((**t).clone())),
                None if self.materials.float_textures.contains_key(&tex) => Err(PbrtError::at(
                    &p.loc,
                    format!("{}: \"{tex}\" is a float texture; a spectrum texture is needed here", p.describe()),
                )),
                None => Err(PbrtError::at(&p.loc, format!("{}: no texture named \"{tex}\" is defined", p.describe()))),
            };
        }
        if p.ty == ParamType::Float {
            // pbrt-v4 accepts a float where a spectrum is expected.
            let v = params.float(name)?.unwrap_or(0.0);
            return Ok(Some(Texture::Constant(Color::splat(v))));
        }
        Ok(self.color(params, name, usage)?.map(Texture::Constant))
    }

    /// A float parameter that may be a texture, `default` when absent.
    pub fn float_texture(
        &mut self,
        params: &ParamList,
        name: &str,
        default: f32,
        _loc: &Loc,
    ) -> Result<FloatTexture, PbrtError> {
        let Some(p) = params.get(name) else { return Ok(FloatTexture::Constant(default)) };
        if p.ty == ParamType::Texture {
            let tex = params.texture(name)?.unwrap_or_default().to_owned();
            return match self.materials.float_textures.get(&tex) {
                Some(t) => Ok((**t).clone()),
                None if self.materials.textures.contains_key(&tex) => Err(PbrtError::at(
                    &p.loc,
                    format!("{}: \"{tex}\" is a spectrum texture; a float texture is needed here", p.describe()),
                )),
                None => Err(PbrtError::at(&p.loc, format!("{}: no texture named \"{tex}\" is defined", p.describe()))),
            };
        }
        Ok(FloatTexture::Constant(params.float(name)?.unwrap_or(default)))
    }

    /// `roughness`, or `uroughness`/`vroughness` (each defaulting to
    /// `roughness`), with the `remaproughness` flag (default true).
    fn roughness(&mut self, params: &ParamList, prefix: &str, loc: &Loc) -> Result<Roughness, PbrtError> {
        let r = self.float_texture(params, &format!("{prefix}roughness"), 0.0, loc)?;
        let u = if params.get(&format!("{prefix}uroughness")).is_some() {
            self.float_texture(params, &format!("{prefix}uroughness"), 0.0, loc)?
        } else {
            r.clone()
        };
        let v = if params.get(&format!("{prefix}vroughness")).is_some() {
            self.float_texture(params, &format!("{prefix}vroughness"), 0.0, loc)?
        } else {
            r
        };
        let remap = params.bool("remaproughness")?.unwrap_or(true);
        Ok(Roughness::anisotropic(u, v, remap))
    }

    /// A conductor's Fresnel term: `eta`/`k` (spectra, RGB or textures;
    /// pbrt-v4's default is copper), or a `reflectance`.
    fn conductor_fresnel(&mut self, params: &ParamList, prefix: &str) -> Result<ConductorFresnel<Texture>, PbrtError> {
        let reflectance = self.spectrum_texture(params, &format!("{prefix}reflectance"), SpectrumUse::Albedo)?;
        let (eta_name, k_name) = (format!("{prefix}eta"), format!("{prefix}k"));
        if let Some(r) = reflectance {
            if params.get(&eta_name).is_some() || params.get(&k_name).is_some() {
                let p = params.get(&format!("{prefix}reflectance")).expect("present");
                return Err(PbrtError::at(
                    &p.loc,
                    "conductor: give either \"reflectance\" or \"eta\" and \"k\", not both",
                ));
            }
            return Ok(ConductorFresnel::Reflectance { r });
        }
        let eta = self.spectrum_texture(params, &eta_name, SpectrumUse::Unbounded)?;
        let k = self.spectrum_texture(params, &k_name, SpectrumUse::Unbounded)?;
        Ok(ConductorFresnel::Complex {
            eta: eta.unwrap_or(Texture::Constant(COPPER_ETA)),
            k: k.unwrap_or(Texture::Constant(COPPER_K)),
        })
    }

    /// Make the material of a `Material` or `MakeNamedMaterial` directive
    /// and add it to the scene.
    pub fn material(&mut self, ty: &str, params: &ParamList, loc: &Loc) -> Result<MaterialId, PbrtError> {
        let material = self.material_model(ty, params, loc)?;
        let material = self.shading_modifiers(material, params, loc)?;
        self.builder.add_material(material).map_err(|e| PbrtError::at(loc, format!("Material \"{ty}\": {}", e.message)))
    }

    /// `displacement` (bump map) and `normalmap`, on any material.
    fn shading_modifiers(&mut self, material: Material, params: &ParamList, loc: &Loc) -> Result<Material, PbrtError> {
        let mut material = material;
        if params.get("displacement").is_some() {
            let d = self.float_texture(params, "displacement", 0.0, loc)?;
            if d != FloatTexture::Constant(0.0) {
                material = material.with_bump(d);
            }
        }
        if let Some(name) = params.string("normalmap")? {
            let at = param_loc(params, "normalmap", loc);
            let path = self.resolve(name, &at);
            let texture = self.normal_map_texture(&path, &at)?;
            material = material.with_normal_map(texture);
        }
        Ok(material)
    }

    /// The material of type `ty`, without shading modifiers.
    fn material_model(&mut self, ty: &str, params: &ParamList, loc: &Loc) -> Result<Material, PbrtError> {
        let albedo = |me: &mut Self, name: &str, default: f32| -> Result<Texture, PbrtError> {
            Ok(me
                .spectrum_texture(params, name, SpectrumUse::Albedo)?
                .unwrap_or(Texture::Constant(Color::splat(default))))
        };
        Ok(match ty {
            "diffuse" => Material::Diffuse { reflectance: albedo(self, "reflectance", 0.5)? },
            "conductor" => Material::Conductor {
                fresnel: self.conductor_fresnel(params, "")?,
                roughness: self.roughness(params, "", loc)?,
            },
            "dielectric" => Material::Dielectric {
                eta: self.eta(params, "eta", 1.5)?,
                roughness: self.roughness(params, "", loc)?,
                tint: Color::ONE,
            },
            "thindielectric" => Material::ThinDielectric { eta: self.eta(params, "eta", 1.5)? },
            "coateddiffuse" => {
                let reflectance = albedo(self, "reflectance", 0.5)?;
                let roughness = self.roughness(params, "", loc)?;
                let eta = self.eta(params, "eta", 1.5)?;
                let layer = self.layer(params, loc)?;
                Material::CoatedDiffuse(CoatedDiffuseMaterial {
                    reflectance,
                    roughness,
                    eta,
                    thickness: layer.thickness,
                    albedo: layer.albedo,
                    g: layer.g,
                    max_depth: layer.max_depth,
                    n_samples: layer.n_samples,
                })
            }
            "coatedconductor" => {
                let interface_roughness = self.roughness(params, "interface.", loc)?;
                let interface_eta = self.eta(params, "interface.eta", 1.5)?;
                let conductor = self.conductor_fresnel(params, "conductor.")?;
                let conductor_roughness = self.roughness(params, "conductor.", loc)?;
                let layer = self.layer(params, loc)?;
                Material::CoatedConductor(CoatedConductorMaterial {
                    interface_roughness,
                    interface_eta,
                    conductor,
                    conductor_roughness,
                    thickness: layer.thickness,
                    albedo: layer.albedo,
                    g: layer.g,
                    max_depth: layer.max_depth,
                    n_samples: layer.n_samples,
                })
            }
            "diffusetransmission" => Material::DiffuseTransmission {
                reflectance: albedo(self, "reflectance", 0.25)?,
                transmittance: albedo(self, "transmittance", 0.25)?,
                scale: params.float("scale")?.unwrap_or(1.0),
            },
            "mix" => {
                let names: Vec<String> = params
                    .strings("materials")?
                    .ok_or_else(|| PbrtError::at(loc, "Material \"mix\" needs \"string materials\" [ \"first\" \"second\" ]"))?
                    .to_vec();
                let at = param_loc(params, "materials", loc);
                if names.len() != 2 {
                    return Err(PbrtError::at(&at, format!("\"string materials\" needs exactly 2 names, got {}", names.len())));
                }
                let mut ids = Vec::with_capacity(2);
                for name in &names {
                    ids.push(*self.materials.named.get(name.as_str()).ok_or_else(|| {
                        PbrtError::at(&at, format!("mix: named material \"{name}\" is not defined (MakeNamedMaterial must come first)"))
                    })?);
                }
                let amount = self.float_texture(params, "amount", 0.5, loc)?;
                Material::Mix { materials: [ids[0], ids[1]], amount }
            }
            "interface" | "" | "none" => Material::Interface,
            "measured" | "hair" | "subsurface" => {
                for p in &params.params {
                    p.used.set(true);
                }
                self.warnings.warn(
                    loc,
                    format!("Material \"{ty}\" is not supported: rendered as grey diffuse (reflectance 0.5)"),
                )?;
                Material::Diffuse { reflectance: Texture::Constant(Color::splat(0.5)) }
            }
            other => {
                return Err(PbrtError::at(
                    loc,
                    format!("unknown material type \"{other}\" (accepted: diffuse, conductor, dielectric, thindielectric, coateddiffuse, coatedconductor, diffusetransmission, mix, interface, measured, hair, subsurface)"),
                ))
            }
        })
    }

    /// The layer parameters of the coated materials (pbrt-v4 defaults).
    fn layer(&mut self, params: &ParamList, loc: &Loc) -> Result<Layer, PbrtError> {
        let thickness = self.float_texture(params, "thickness", 0.01, loc)?;
        let g = self.float_texture(params, "g", 0.0, loc)?;
        let max_depth = params.int("maxdepth")?.unwrap_or(10);
        let n_samples = params.int("nsamples")?.unwrap_or(1);
        let albedo =
            self.spectrum_texture(params, "albedo", SpectrumUse::Albedo)?.unwrap_or(Texture::Constant(Color::ZERO));
        if let FloatTexture::Constant(t) = thickness {
            if !(t > 0.0 && t.is_finite()) {
                return Err(PbrtError::at(
                    &param_loc(params, "thickness", loc),
                    format!("\"float thickness\" must be positive, got {t}"),
                ));
            }
        }
        if let FloatTexture::Constant(g) = g {
            if !(-1.0..=1.0).contains(&g) {
                return Err(PbrtError::at(
                    &param_loc(params, "g", loc),
                    format!("\"float g\" must be from -1 to 1, got {g}"),
                ));
            }
        }
        if !(1..=1000).contains(&max_depth) || !(1..=1000).contains(&n_samples) {
            return Err(PbrtError::at(loc, "\"integer maxdepth\" and \"integer nsamples\" must be from 1 to 1000"));
        }
        Ok(Layer { thickness, albedo, g, max_depth: max_depth as u32, n_samples: n_samples as u32 })
    }
}

/// The medium between the coat and the base of a coated material.
struct Layer {
    thickness: FloatTexture,
    albedo: Texture,
    g: FloatTexture,
    max_depth: u32,
    n_samples: u32,
}
