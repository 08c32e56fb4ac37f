//! Scene-file materials: `[materials.NAME.KIND]` tables and the materials of
//! mesh files.

use super::description::*;
use super::locate::*;
use super::textures::TextureTable;
use super::values::*;
use super::SceneFile;
use crate::bsdf::ConductorFresnel;
use crate::color::Color;
use crate::geometry::Vec3;
use crate::material::{
    CoatedConductorMaterial, CoatedDiffuseMaterial, Material, MaterialId, MetallicRoughnessMaterial, Roughness,
    COPPER_ETA, COPPER_K,
};
use crate::scene::SceneError;
use crate::texture::{ColorEncoding, FloatTexture, ImageTexture, ImageTextureParams, Texture, TextureMapping};
use std::collections::HashMap;
use std::sync::Arc;

impl SceneFile {
    /// The material of `[materials.NAME]`, its textures resolved in `tex`
    /// and the materials a `mix` names looked up in `ids` (added before).
    pub(super) fn material(
        &self,
        name: &str,
        m: &MaterialDesc,
        tex: &mut TextureTable,
        ids: &HashMap<String, MaterialId>,
    ) -> Result<Material, SceneError> {
        let at = || find_table(&self.source, name);
        let fail = |e: String| self.error(at(), format!("material \"{name}\": {e}"));
        let material = self.material_kind(&m.kind, tex, ids).map_err(fail)?;
        let mut material = match material {
            Ok(m) => m,
            Err(e) => return Err(self.error(at(), format!("material \"{name}\": {e}"))),
        };
        if let Some(d) = &m.displacement {
            material = material.with_bump(tex.float(d, "displacement").map_err(fail)?);
        }
        if let Some(file) = &m.normal_map {
            let map = normal_map(tex, file).map_err(fail)?;
            material = match m.normal_scale {
                None => material.with_normal_map(map),
                Some(scale) => Material::Shaded {
                    material: Box::new(material),
                    normal: crate::material::NormalPerturbation::ScaledNormalMap { map, scale },
                },
            };
        }
        Ok(material)
    }

    /// The material of one kind; the outer error is a message about a key,
    /// the inner one the model's refusal.
    fn material_kind(
        &self,
        m: &MaterialKindDesc,
        tex: &mut TextureTable,
        ids: &HashMap<String, MaterialId>,
    ) -> Result<Result<Material, crate::material::MaterialError>, String> {
        let color =
            |tex: &mut TextureTable, color: &Option<TexValue>, checker: &Option<CheckerDesc>| match (color, checker) {
                (Some(_), Some(_)) => Err("has both `color` and `checker`; give one".to_owned()),
                (Some(c), None) => tex.color(c, "color"),
                (None, Some(ch)) => {
                    Ok(Texture::Checker { even: ch.even.into(), odd: ch.odd.into(), scale: ch.scale.get() })
                }
                (None, None) => Ok(Texture::Constant(Color::ONE)),
            };
        let opt_color = |tex: &mut TextureTable, v: &Option<TexValue>, key: &str, default: Color| match v {
            Some(v) => tex.color(v, key),
            None => Ok(Texture::Constant(default)),
        };
        let opt_float = |tex: &mut TextureTable, v: &Option<TexValue>, key: &str, default: f32| match v {
            Some(v) => tex.float(v, key),
            None => Ok(FloatTexture::Constant(default)),
        };
        let roughness = |tex: &mut TextureTable,
                         prefix: &str,
                         r: &Option<TexValue>,
                         u: &Option<TexValue>,
                         v: &Option<TexValue>,
                         remap: bool| {
            let r = opt_float(tex, r, &format!("{prefix}roughness"), 0.0)?;
            let u = match u {
                Some(u) => tex.float(u, &format!("{prefix}u_roughness"))?,
                None => r.clone(),
            };
            let v = match v {
                Some(v) => tex.float(v, &format!("{prefix}v_roughness"))?,
                None => r,
            };
            Ok::<_, String>(Roughness::anisotropic(u, v, remap))
        };
        let fresnel = |tex: &mut TextureTable,
                       prefix: &str,
                       color: &Option<TexValue>,
                       eta: &Option<TexValue>,
                       k: &Option<TexValue>,
                       reflectance: &Option<TexValue>,
                       metal: Option<MetalDesc>,
                       default: ConductorFresnel<Texture>| {
            Ok::<_, String>(match (color, eta, k, reflectance, metal) {
                (Some(c), None, None, None, None) => ConductorFresnel::Schlick { r0: tex.color(c, "color")? },
                (None, Some(eta), Some(k), None, None) => ConductorFresnel::Complex {
                    eta: tex.color(eta, &format!("{prefix}eta"))?,
                    k: tex.color(k, &format!("{prefix}k"))?,
                },
                (None, None, None, Some(r), None) => {
                    ConductorFresnel::Reflectance { r: tex.color(r, &format!("{prefix}reflectance"))? }
                }
                (None, None, None, None, Some(metal)) => {
                    let (eta, k) = metal_ior(metal);
                    ConductorFresnel::Complex { eta: eta.into(), k: k.into() }
                }
                (None, None, None, None, None) => default,
                _ => {
                    return Err(format!(
                        "give one of `{prefix}color`, `{prefix}eta` with `{prefix}k`, or `metal` (or pbrt's `{prefix}reflectance`)"
                    ))
                }
            })
        };
        let layer = |tex: &mut TextureTable,
                     thickness: &Option<TexValue>,
                     albedo: &Option<TexValue>,
                     g: &Option<TexValue>,
                     max_depth: Option<u32>,
                     n_samples: Option<u32>| {
            let thickness = opt_float(tex, thickness, "thickness", 0.01)?;
            if let FloatTexture::Constant(t) = thickness {
                if t.is_nan() || t <= 0.0 {
                    return Err(format!("`thickness` must be > 0, got {t}"));
                }
            }
            let g = opt_float(tex, g, "g", 0.0)?;
            if let FloatTexture::Constant(g) = g {
                if !(-1.0..=1.0).contains(&g) {
                    return Err(format!("`g` must be from -1 to 1, got {g}"));
                }
            }
            let (max_depth, n_samples) = (max_depth.unwrap_or(10), n_samples.unwrap_or(1));
            if !(1..=1000).contains(&max_depth) || !(1..=1000).contains(&n_samples) {
                return Err("`max_depth` and `n_samples` must be from 1 to 1000".to_owned());
            }
            Ok::<_, String>((thickness, opt_color(tex, albedo, "albedo", Color::ZERO)?, g, max_depth, n_samples))
        };
        Ok(match m {
            MaterialKindDesc::Matte(m) => {
                let mat = Material::matte(color(tex, &m.color, &m.checker)?, m.kd.get());
                match m.ka {
                    Some(ka) => mat.and_then(|x| x.with_ka(ka.get())),
                    None => mat,
                }
            }
            MaterialKindDesc::Phong(p) => {
                let mat = Material::phong(
                    color(tex, &p.color, &p.checker)?,
                    p.kd.get(),
                    p.ks.get(),
                    p.exponent.get(),
                    p.kr.map_or(0.0, NonNegative::get),
                );
                match p.ka {
                    Some(ka) => mat.and_then(|x| x.with_ka(ka.get())),
                    None => mat,
                }
            }
            MaterialKindDesc::Diffuse(d) => Ok(Material::Diffuse { reflectance: color(tex, &d.color, &d.checker)? }),
            MaterialKindDesc::Conductor(c) => {
                let white = ConductorFresnel::Schlick { r0: Texture::Constant(Color::ONE) };
                let fresnel = fresnel(tex, "", &c.color, &c.eta, &c.k, &c.reflectance, c.metal, white)?;
                let roughness = roughness(tex, "", &c.roughness, &c.u_roughness, &c.v_roughness, c.remap_roughness)?;
                Ok(Material::Conductor { fresnel, roughness })
            }
            MaterialKindDesc::Dielectric(d) => Ok(Material::Dielectric {
                eta: d.eta.map_or(1.5, Positive::get),
                roughness: roughness(tex, "", &d.roughness, &d.u_roughness, &d.v_roughness, d.remap_roughness)?,
                tint: d.tint.map_or(Color::ONE, Color::from),
            }),
            MaterialKindDesc::Plastic(p) => Ok(Material::Plastic {
                reflectance: color(tex, &p.color, &p.checker)?,
                eta: p.eta.map_or(1.5, Positive::get),
                roughness: p.roughness.map_or(0.0, NonNegative::get),
            }),
            MaterialKindDesc::ThinDielectric(t) => {
                Ok(Material::ThinDielectric { eta: t.eta.map_or(1.5, Positive::get) })
            }
            MaterialKindDesc::DiffuseTransmission(d) => Ok(Material::DiffuseTransmission {
                reflectance: opt_color(tex, &d.reflectance, "reflectance", Color::splat(0.25))?,
                transmittance: opt_color(tex, &d.transmittance, "transmittance", Color::splat(0.25))?,
                scale: d.scale.map_or(1.0, NonNegative::get),
            }),
            MaterialKindDesc::CoatedDiffuse(c) => {
                let (thickness, albedo, g, max_depth, n_samples) =
                    layer(tex, &c.thickness, &c.albedo, &c.g, c.max_depth, c.n_samples)?;
                Ok(Material::CoatedDiffuse(CoatedDiffuseMaterial {
                    reflectance: opt_color(tex, &c.reflectance, "reflectance", Color::splat(0.5))?,
                    roughness: roughness(tex, "", &c.roughness, &c.u_roughness, &c.v_roughness, c.remap_roughness)?,
                    thickness,
                    eta: c.eta.map_or(1.5, Positive::get),
                    albedo,
                    g,
                    max_depth,
                    n_samples,
                }))
            }
            MaterialKindDesc::CoatedConductor(c) => {
                let (thickness, albedo, g, max_depth, n_samples) =
                    layer(tex, &c.thickness, &c.albedo, &c.g, c.max_depth, c.n_samples)?;
                let copper =
                    ConductorFresnel::Complex { eta: Texture::Constant(COPPER_ETA), k: Texture::Constant(COPPER_K) };
                let remap = c.remap_roughness;
                Ok(Material::CoatedConductor(CoatedConductorMaterial {
                    interface_roughness: roughness(
                        tex,
                        "interface_",
                        &c.interface_roughness,
                        &c.interface_u_roughness,
                        &c.interface_v_roughness,
                        remap,
                    )?,
                    interface_eta: c.interface_eta.map_or(1.5, Positive::get),
                    conductor: fresnel(
                        tex,
                        "conductor_",
                        &c.conductor_color,
                        &c.conductor_eta,
                        &c.conductor_k,
                        &c.conductor_reflectance,
                        c.metal,
                        copper,
                    )?,
                    conductor_roughness: roughness(
                        tex,
                        "conductor_",
                        &c.conductor_roughness,
                        &c.conductor_u_roughness,
                        &c.conductor_v_roughness,
                        remap,
                    )?,
                    thickness,
                    albedo,
                    g,
                    max_depth,
                    n_samples,
                }))
            }
            MaterialKindDesc::Mix(m) => {
                let mut materials = [MaterialId::new(0); 2];
                for (slot, other) in materials.iter_mut().zip(&m.materials) {
                    *slot = *ids.get(other).ok_or_else(|| {
                        let known: Vec<&str> = self.description.materials.keys().map(String::as_str).collect();
                        format!("`materials`: no material named \"{other}\" is defined (defined: {})", known.join(", "))
                    })?;
                }
                let amount = opt_float(tex, &m.amount, "amount", 0.5)?;
                Ok(Material::Mix { materials, amount })
            }
            MaterialKindDesc::Interface(_) => Ok(Material::Interface),
            MaterialKindDesc::MetallicRoughness(d) => {
                // A colour key: a constant is the factor itself; a texture
                // is multiplied by the `_factor` key.
                let factored = |tex: &mut TextureTable,
                                v: &Option<TexValue>,
                                factor: &Option<Rgb>,
                                key: &str,
                                default: Color|
                 -> Result<(Color, Option<Texture>), String> {
                    let factor = factor.map_or(Color::ONE, Color::from);
                    Ok(match v {
                        None => (default, None),
                        Some(v) => match tex.color(v, key)? {
                            Texture::Constant(c) => (c * factor, None),
                            t => (factor, Some(t)),
                        },
                    })
                };
                let (base_color_factor, base_color) =
                    factored(tex, &d.base_color, &d.base_color_factor, "base_color", Color::ONE)?;
                let (specular_color_factor, specular_color) =
                    factored(tex, &d.specular_color, &d.specular_color_factor, "specular_color", Color::ONE)?;
                let (sheen_color_factor, sheen_color) =
                    factored(tex, &d.sheen_color, &d.sheen_color_factor, "sheen_color", Color::ZERO)?;
                let ior = d.ior.map_or(1.5, Positive::get);
                if ior < 1.0 {
                    return Err(format!("`ior` must be at least 1, got {ior}"));
                }
                Ok(Material::MetallicRoughness(Box::new(MetallicRoughnessMaterial {
                    base_color_factor,
                    base_color,
                    metallic: opt_float(tex, &d.metallic, "metallic", 1.0)?,
                    roughness: opt_float(tex, &d.roughness, "roughness", 1.0)?,
                    ior,
                    specular: opt_float(tex, &d.specular, "specular", 1.0)?,
                    specular_color_factor,
                    specular_color,
                    transmission: opt_float(tex, &d.transmission, "transmission", 0.0)?,
                    thin: d.thin.unwrap_or(true),
                    clearcoat: opt_float(tex, &d.clearcoat, "clearcoat", 0.0)?,
                    clearcoat_roughness: opt_float(tex, &d.clearcoat_roughness, "clearcoat_roughness", 0.0)?,
                    sheen_color_factor,
                    sheen_color,
                    sheen_roughness: opt_float(tex, &d.sheen_roughness, "sheen_roughness", 0.0)?,
                })))
            }
        })
    }
}

/// A tangent-space normal map read from `file` (linear, `(u, v)` mapping,
/// pbrt-v4's defaults otherwise), as pbrt-v4's `normalmap` parameter.
fn normal_map(tex: &mut TextureTable, file: &str) -> Result<Texture, String> {
    let mipmap = tex.mipmap(file, ColorEncoding::Linear).map_err(|e| format!("`normal_map`: {e}"))?;
    let image = ImageTexture::new(TextureMapping::default(), mipmap, ImageTextureParams::default());
    Ok(Texture::image(Arc::new(image)))
}

/// A scene material for one of a mesh file's own materials (OBJ's MTL):
/// Phong when it has a specular colour, matte otherwise.
pub(super) fn material_from_file(m: &crate::mesh::MeshMaterial) -> Material {
    let kd = Texture::Constant(m.diffuse.max(Vec3::ZERO));
    let ks = m.specular.max_element().max(0.0);
    let material =
        if ks > 0.0 { Material::phong(kd, 1.0, ks, m.shininess.max(1.0), 0.0) } else { Material::matte(kd, 1.0) };
    material.unwrap_or_else(|_| Material::matte(Color::splat(0.8), 1.0).expect("valid constants"))
}

/// Complex indices of refraction of the named metals at 650, 550 and
/// 450 nm (red, green, blue), from the measurements tabulated at
/// refractiveindex.info: Johnson & Christy 1972 (gold, silver, copper) and
/// Rakić 1995 (aluminium).
pub(super) fn metal_ior(metal: MetalDesc) -> (Color, Color) {
    let (eta, k) = match metal {
        MetalDesc::Gold => ([0.166, 0.424, 1.316], [3.150, 2.380, 1.863]),
        MetalDesc::Silver => ([0.144, 0.120, 0.135], [4.243, 3.341, 2.484]),
        MetalDesc::Copper => ([0.214, 0.967, 1.158], [3.670, 2.578, 2.398]),
        MetalDesc::Aluminium => ([1.490, 0.958, 0.618], [7.821, 6.690, 5.471]),
    };
    (Color::from_array(eta), Color::from_array(k))
}
