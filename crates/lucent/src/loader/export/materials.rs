//! Materials and textures of the scene model as scene-file descriptions:
//! the inverse of `loader::materials` and `loader::textures`, so that a
//! material written out and read back is equal to the original.
//!
//! Constants are written inline (`color = [1, 0, 0]`, `roughness = 0.1`);
//! every other texture gets a `[textures.NAME]` table, one per distinct
//! description (two equal textures, or the colour and number views of one
//! image, share a name). Image textures name their file, which the model
//! remembers ([`crate::texture::ImageTexture::source`]); an image made in
//! memory cannot be written.
//!
//! Transforms of texture spaces are written as matrices. A round trip is
//! exact for transforms whose matrix inverse is computed exactly (such as
//! translations and power-of-two scales); for others the texture space may
//! move by float rounding.

use crate::bsdf::ConductorFresnel;
use crate::color::Color;
use crate::geometry::{Transform, Vec3};
use crate::loader::description::*;
use crate::loader::values::*;
use crate::material::{Material, NormalPerturbation, Roughness};
use crate::texture::{
    Checkerboard, CheckerboardMapping, ColorEncoding, FilterFunction, FloatTexture, ImageTexture, ImageTextureParams,
    MipMap, Texture, TextureMapping, WrapMode,
};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Collects the `[textures]` a set of exported materials needs.
pub(crate) struct TextureExport {
    /// The texture tables written so far, by name.
    pub textures: BTreeMap<String, TextureDesc>,
    /// Where the scene file is written: image paths are relative to it
    /// when they lie below it.
    out_dir: PathBuf,
    /// Names by description (its JSON text): equal textures share a name.
    by_desc: HashMap<String, String>,
    /// The folder (relative to `out_dir`) that images made in memory (a
    /// glTF file's embedded images) are written to.
    image_dir: String,
    /// Those images, each with its file name relative to `out_dir`.
    pub images: Vec<(String, Arc<MipMap>)>,
}

/// A value for an `f32` key that must be finite and ≥ 0.
fn non_negative(v: f32, key: &str) -> Result<NonNegative, String> {
    NonNegative::try_from(v).map_err(|e| format!("`{key}`: {e}"))
}

fn positive(v: f32, key: &str) -> Result<Positive, String> {
    Positive::try_from(v).map_err(|e| format!("`{key}`: {e}"))
}

fn finite(v: f32, key: &str) -> Result<Finite, String> {
    Finite::try_from(v).map_err(|e| format!("`{key}`: {e}"))
}

fn rgb(c: Color) -> Rgb {
    Rgb(c.to_array())
}

/// `Some(finite)` unless `v` is the default `d`.
fn finite_unless(v: f32, d: f32, key: &str) -> Result<Option<Finite>, String> {
    Ok(if v == d { None } else { Some(finite(v, key)?) })
}

/// A transform as a one-step list (empty for the identity).
fn transform_ops(t: &Transform) -> Vec<TransformOp> {
    if t.is_identity() {
        return Vec::new();
    }
    vec![TransformOp::Matrix(t.matrix().transpose().to_cols_array_2d())]
}

/// The `encoding` key's value.
fn encoding_name(e: ColorEncoding) -> String {
    match e {
        ColorEncoding::Linear => "linear".to_owned(),
        ColorEncoding::Srgb => "srgb".to_owned(),
        ColorEncoding::Gamma(g) => format!("gamma {g}"),
    }
}

fn mapping_desc(m: &TextureMapping) -> Result<Option<MappingDesc>, String> {
    Ok(match m {
        TextureMapping::Uv { su, sv, du, dv } => {
            if *m == TextureMapping::default() {
                None
            } else {
                Some(MappingDesc::Uv {
                    su: finite_unless(*su, 1.0, "su")?,
                    sv: finite_unless(*sv, 1.0, "sv")?,
                    du: finite_unless(*du, 0.0, "du")?,
                    dv: finite_unless(*dv, 0.0, "dv")?,
                })
            }
        }
        TextureMapping::UvAffine { m, set } => {
            let mut out = Vec::with_capacity(6);
            for v in m {
                out.push(finite(*v, "m")?);
            }
            let uv_set = (*set != 0).then_some(*set);
            Some(MappingDesc::Affine { m: out.try_into().expect("six entries"), uv_set })
        }
        TextureMapping::Spherical { texture_from_world } => {
            Some(MappingDesc::Spherical { transform: transform_ops(&texture_from_world.inverse()) })
        }
        TextureMapping::Cylindrical { texture_from_world } => {
            Some(MappingDesc::Cylindrical { transform: transform_ops(&texture_from_world.inverse()) })
        }
        TextureMapping::Planar { texture_from_world, vs, vt, ds, dt } => Some(MappingDesc::Planar {
            transform: transform_ops(&texture_from_world.inverse()),
            v1: (*vs != Vec3::X).then_some(Vec3Desc(vs.to_array())),
            v2: (*vt != Vec3::Y).then_some(Vec3Desc(vt.to_array())),
            du: finite_unless(*ds, 0.0, "du")?,
            dv: finite_unless(*dt, 0.0, "dv")?,
        }),
    })
}

impl TextureExport {
    /// An exporter for a scene file to be written in `out_dir`.
    pub fn new(out_dir: &Path) -> Self {
        let out_dir = std::fs::canonicalize(out_dir)
            .or_else(|_| std::path::absolute(out_dir))
            .unwrap_or_else(|_| out_dir.to_path_buf());
        Self {
            textures: BTreeMap::new(),
            out_dir,
            by_desc: HashMap::new(),
            image_dir: "textures".to_owned(),
            images: Vec::new(),
        }
    }

    /// Write images made in memory into `dir` (relative to the output
    /// directory) instead of `textures/`.
    pub fn with_image_dir(mut self, dir: &str) -> Self {
        self.image_dir = dir.to_owned();
        self
    }

    /// The file name (relative to the output directory) of an image made in
    /// memory: written as a linear EXR of its texels, so that it reads back
    /// exactly (see `export_scene`).
    fn memory_image(&mut self, map: &Arc<MipMap>) -> String {
        if let Some((name, _)) = self.images.iter().find(|(_, m)| Arc::ptr_eq(m, map)) {
            return name.clone();
        }
        let name = format!("{}/image-{}.exr", self.image_dir, self.images.len() + 1);
        self.images.push((name.clone(), Arc::clone(map)));
        name
    }

    /// A path as written: relative to the output directory when the two
    /// share a directory, else absolute.
    fn path_name(&self, path: &Path) -> String {
        super::relative_path(path, &self.out_dir)
    }

    /// The name of a texture table equal to `desc`, added if new; `hint`
    /// suggests the name.
    fn name(&mut self, desc: TextureDesc, hint: &str) -> TexValue {
        let key = serde_json::to_string(&desc).unwrap_or_default();
        if let Some(n) = self.by_desc.get(&key) {
            return TexValue::Name(n.clone());
        }
        let hint: String =
            hint.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' || c == '-' { c } else { '_' }).collect();
        let hint = if hint.is_empty() { "texture".to_owned() } else { hint };
        let mut name = hint.clone();
        let mut i = 2;
        while self.textures.contains_key(&name) {
            name = format!("{hint}_{i}");
            i += 1;
        }
        self.textures.insert(name.clone(), desc);
        self.by_desc.insert(key, name.clone());
        TexValue::Name(name)
    }

    /// The table of an image texture.
    fn image(&mut self, im: &ImageTexture) -> Result<TexValue, String> {
        let (file, encoding) = match im.mipmap().source() {
            Some(source) => (
                self.path_name(&source.path),
                (source.encoding != ColorEncoding::pbrt_default_for(&source.path))
                    .then(|| encoding_name(source.encoding)),
            ),
            // Texels in memory are linear: an EXR of them reads back as is.
            None => (self.memory_image(im.mipmap()), None),
        };
        let ImageTextureParams { filter, max_anisotropy, wrap, scale, invert, channel } = *im.params();
        let desc = ImageTextureDesc {
            file,
            mapping: mapping_desc(im.mapping())?,
            filter: match filter {
                FilterFunction::Bilinear => None,
                FilterFunction::Point => Some(FilterFunctionDesc::Point),
                FilterFunction::Trilinear => Some(FilterFunctionDesc::Trilinear),
                FilterFunction::Ewa => Some(FilterFunctionDesc::Ewa),
            },
            max_anisotropy: if max_anisotropy == 8.0 {
                None
            } else {
                Some(positive(max_anisotropy, "max_anisotropy")?)
            },
            wrap: match (wrap_desc(wrap.s), wrap_desc(wrap.t)) {
                (WrapDesc::Repeat, WrapDesc::Repeat) => None,
                (s, t) if s == t => Some(WrapSpec::Both(s)),
                (s, t) => Some(WrapSpec::Axes { s, t }),
            },
            encoding,
            scale: finite_unless(scale, 1.0, "scale")?,
            invert,
            channel: channel
                .map(|c| [ChannelDesc::R, ChannelDesc::G, ChannelDesc::B, ChannelDesc::A][usize::from(c.min(3))]),
        };
        let stem = Path::new(&desc.file).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        Ok(self.name(TextureDesc::Image(desc), &stem))
    }

    /// A checkerboard's table, its two sides already written.
    fn checkerboard<T>(&mut self, c: &Checkerboard<T>, tex1: TexValue, tex2: TexValue) -> Result<TexValue, String> {
        let (dimension, mapping, transform) = match &c.mapping {
            CheckerboardMapping::Planar(m) => (None, mapping_desc(m)?, Vec::new()),
            CheckerboardMapping::Solid(t) => (Some(3), None, transform_ops(&t.inverse())),
        };
        let desc = CheckerboardTextureDesc { tex1: Some(tex1), tex2: Some(tex2), dimension, mapping, transform };
        Ok(self.name(TextureDesc::Checkerboard(desc), "checkerboard"))
    }

    /// A number-valued texture as a parameter value.
    pub fn float(&mut self, t: &FloatTexture) -> Result<TexValue, String> {
        Ok(match t {
            FloatTexture::Constant(v) => TexValue::Number(finite(*v, "value")?.get()),
            FloatTexture::Image(im) => self.image(im)?,
            FloatTexture::Scale { tex, scale } => {
                let desc = ScaleTextureDesc { tex: Some(self.float(tex)?), scale: Some(self.float(scale)?) };
                self.name(TextureDesc::Scale(desc), "scale")
            }
            FloatTexture::Mix { tex1, tex2, amount } => {
                let desc = MixTextureDesc {
                    tex1: Some(self.float(tex1)?),
                    tex2: Some(self.float(tex2)?),
                    amount: Some(self.float(amount)?),
                };
                self.name(TextureDesc::Mix(desc), "mix")
            }
            FloatTexture::DirectionMix { tex1, tex2, dir } => {
                let desc = DirectionMixTextureDesc {
                    tex1: Some(self.float(tex1)?),
                    tex2: Some(self.float(tex2)?),
                    dir: Some(Direction(dir.to_array())),
                };
                self.name(TextureDesc::DirectionMix(desc), "direction_mix")
            }
            FloatTexture::Checkerboard(c) => {
                let (t1, t2) = (self.float(&c.tex1)?, self.float(&c.tex2)?);
                self.checkerboard(c, t1, t2)?
            }
            FloatTexture::Bilerp(b) => {
                let desc = BilerpTextureDesc {
                    mapping: mapping_desc(&b.mapping)?,
                    v00: Some(TexValue::Number(b.v00)),
                    v01: Some(TexValue::Number(b.v01)),
                    v10: Some(TexValue::Number(b.v10)),
                    v11: Some(TexValue::Number(b.v11)),
                };
                self.name(TextureDesc::Bilerp(desc), "bilerp")
            }
            FloatTexture::Step { texture, threshold } => {
                let desc = StepTextureDesc {
                    texture: self.float(texture)?,
                    threshold: Some(finite(*threshold, "threshold")?),
                };
                self.name(TextureDesc::Step(desc), "step")
            }
            FloatTexture::VertexAlpha => self.name(TextureDesc::VertexAlpha(VertexColorDesc {}), "vertex_alpha"),
        })
    }

    /// A colour constant: a number when grey.
    fn color_value(c: Color) -> Result<TexValue, String> {
        if !(c.is_finite() && c.min_element() >= 0.0) {
            return Err(format!("a colour must be finite and ≥ 0, got [{}, {}, {}]", c.x, c.y, c.z));
        }
        Ok(if c.x == c.y && c.y == c.z { TexValue::Number(c.x) } else { TexValue::Rgb(c.to_array()) })
    }

    /// A colour-valued texture as a parameter value.
    pub fn color(&mut self, t: &Texture) -> Result<TexValue, String> {
        Ok(match t {
            Texture::Constant(c) => Self::color_value(*c)?,
            Texture::Checker { even, odd, scale } => {
                let desc = CheckerDesc { even: rgb(*even), odd: rgb(*odd), scale: positive(*scale, "scale")? };
                self.name(TextureDesc::Checker(desc), "checker")
            }
            Texture::Image(im) => self.image(im)?,
            Texture::Scale { tex, scale } => {
                let desc = ScaleTextureDesc { tex: Some(self.color(tex)?), scale: Some(self.float(scale)?) };
                self.name(TextureDesc::Scale(desc), "scale")
            }
            Texture::Mix { tex1, tex2, amount } => {
                let desc = MixTextureDesc {
                    tex1: Some(self.color(tex1)?),
                    tex2: Some(self.color(tex2)?),
                    amount: Some(self.float(amount)?),
                };
                self.name(TextureDesc::Mix(desc), "mix")
            }
            Texture::DirectionMix { tex1, tex2, dir } => {
                let desc = DirectionMixTextureDesc {
                    tex1: Some(self.color(tex1)?),
                    tex2: Some(self.color(tex2)?),
                    dir: Some(Direction(dir.to_array())),
                };
                self.name(TextureDesc::DirectionMix(desc), "direction_mix")
            }
            Texture::Checkerboard(c) => {
                let (t1, t2) = (self.color(&c.tex1)?, self.color(&c.tex2)?);
                self.checkerboard(c, t1, t2)?
            }
            Texture::Bilerp(b) => {
                let desc = BilerpTextureDesc {
                    mapping: mapping_desc(&b.mapping)?,
                    v00: Some(Self::color_value(b.v00)?),
                    v01: Some(Self::color_value(b.v01)?),
                    v10: Some(Self::color_value(b.v10)?),
                    v11: Some(Self::color_value(b.v11)?),
                };
                self.name(TextureDesc::Bilerp(desc), "bilerp")
            }
            Texture::VertexColor => self.name(TextureDesc::VertexColor(VertexColorDesc {}), "vertex_color"),
            Texture::Product { tex1, tex2 } => {
                let desc = ProductTextureDesc { tex1: self.color(tex1)?, tex2: self.color(tex2)? };
                self.name(TextureDesc::Product(desc), "product")
            }
        })
    }

    /// The `color` and `checker` keys of the classic materials, diffuse and
    /// plastic: a checker inline, anything else as `color`.
    fn color_or_checker(&mut self, t: &Texture) -> Result<(Option<TexValue>, Option<CheckerDesc>), String> {
        Ok(match t {
            Texture::Checker { even, odd, scale } => {
                (None, Some(CheckerDesc { even: rgb(*even), odd: rgb(*odd), scale: positive(*scale, "scale")? }))
            }
            t => (Some(self.color(t)?), None),
        })
    }

    /// `roughness` (or `u_roughness` and `v_roughness`) and the remap flag.
    #[allow(clippy::type_complexity)]
    fn roughness(
        &mut self,
        r: &Roughness,
    ) -> Result<(Option<TexValue>, Option<TexValue>, Option<TexValue>, bool), String> {
        if r.u == r.v {
            let v = (r.u != FloatTexture::Constant(0.0)).then(|| self.float(&r.u)).transpose()?;
            Ok((v, None, None, r.remap))
        } else {
            Ok((None, Some(self.float(&r.u)?), Some(self.float(&r.v)?), r.remap))
        }
    }

    /// A conductor's Fresnel term as `(color, eta, k, reflectance)`.
    #[allow(clippy::type_complexity)]
    fn fresnel(
        &mut self,
        f: &ConductorFresnel<Texture>,
    ) -> Result<(Option<TexValue>, Option<TexValue>, Option<TexValue>, Option<TexValue>), String> {
        Ok(match f {
            ConductorFresnel::Schlick { r0 } => (Some(self.color(r0)?), None, None, None),
            ConductorFresnel::Complex { eta, k } => (None, Some(self.color(eta)?), Some(self.color(k)?), None),
            ConductorFresnel::Reflectance { r } => (None, None, None, Some(self.color(r)?)),
        })
    }

    /// A material as a `[materials.NAME]` description; `material_names`
    /// names the scene's materials by index (for `mix`).
    pub fn material(&mut self, m: &Material, material_names: &[String]) -> Result<MaterialDesc, String> {
        // The shading modifiers as the loader applies them: the bump
        // innermost, then the normal map.
        let (m, normal_map, normal_scale) = match m {
            Material::Shaded { material, normal: NormalPerturbation::NormalMap(t) } => {
                (&**material, Some(self.normal_map(t)?), None)
            }
            Material::Shaded { material, normal: NormalPerturbation::ScaledNormalMap { map, scale } } => {
                (&**material, Some(self.normal_map(map)?), (*scale != 1.0).then_some(*scale))
            }
            m => (m, None, None),
        };
        let (m, displacement) = match m {
            Material::Shaded { material, normal: NormalPerturbation::Bump(d) } => (&**material, Some(self.float(d)?)),
            m => (m, None),
        };
        if let Material::Shaded { .. } = m {
            return Err("a material with more than one bump or normal map (or a bump over a normal map) cannot be \
                        written to a scene file"
                .to_owned());
        }
        let kind = match m {
            Material::Classic(c) => {
                let (color, checker) = self.color_or_checker(&c.color)?;
                let kd = non_negative(c.kd, "kd")?;
                let ka = if c.ka == c.kd { None } else { Some(non_negative(c.ka, "ka")?) };
                if c.ks == 0.0 && c.kr == 0.0 && c.exponent == 1.0 {
                    MaterialKindDesc::Matte(MatteDesc { color, checker, kd, ka })
                } else {
                    MaterialKindDesc::Phong(PhongDesc {
                        color,
                        checker,
                        kd,
                        ka,
                        ks: non_negative(c.ks, "ks")?,
                        exponent: non_negative(c.exponent, "exponent")?,
                        kr: if c.kr == 0.0 { None } else { Some(non_negative(c.kr, "kr")?) },
                    })
                }
            }
            Material::Diffuse { reflectance } => {
                let (color, checker) = self.color_or_checker(reflectance)?;
                MaterialKindDesc::Diffuse(DiffuseDesc { color, checker })
            }
            Material::Conductor { fresnel, roughness } => {
                let (color, eta, k, reflectance) = self.fresnel(fresnel)?;
                let (roughness, u_roughness, v_roughness, remap_roughness) = self.roughness(roughness)?;
                MaterialKindDesc::Conductor(ConductorDesc {
                    color,
                    eta,
                    k,
                    reflectance,
                    metal: None,
                    roughness,
                    u_roughness,
                    v_roughness,
                    remap_roughness,
                })
            }
            Material::Dielectric { eta, roughness, tint } => {
                let (roughness, u_roughness, v_roughness, remap_roughness) = self.roughness(roughness)?;
                MaterialKindDesc::Dielectric(DielectricDesc {
                    eta: Some(positive(*eta, "eta")?),
                    roughness,
                    u_roughness,
                    v_roughness,
                    remap_roughness,
                    tint: (*tint != Color::ONE).then_some(rgb(*tint)),
                })
            }
            Material::Plastic { reflectance, eta, roughness } => {
                let (color, checker) = self.color_or_checker(reflectance)?;
                MaterialKindDesc::Plastic(PlasticDesc {
                    color,
                    checker,
                    eta: Some(positive(*eta, "eta")?),
                    roughness: (*roughness != 0.0).then(|| non_negative(*roughness, "roughness")).transpose()?,
                })
            }
            Material::ThinDielectric { eta } => {
                MaterialKindDesc::ThinDielectric(ThinDielectricDesc { eta: Some(positive(*eta, "eta")?) })
            }
            Material::DiffuseTransmission { reflectance, transmittance, scale } => {
                MaterialKindDesc::DiffuseTransmission(DiffuseTransmissionDesc {
                    reflectance: Some(self.color(reflectance)?),
                    transmittance: Some(self.color(transmittance)?),
                    scale: (*scale != 1.0).then(|| non_negative(*scale, "scale")).transpose()?,
                })
            }
            Material::CoatedDiffuse(c) => {
                let (roughness, u_roughness, v_roughness, remap_roughness) = self.roughness(&c.roughness)?;
                MaterialKindDesc::CoatedDiffuse(CoatedDiffuseDesc {
                    reflectance: Some(self.color(&c.reflectance)?),
                    roughness,
                    u_roughness,
                    v_roughness,
                    remap_roughness,
                    thickness: Some(self.float(&c.thickness)?),
                    eta: Some(positive(c.eta, "eta")?),
                    albedo: (c.albedo != Texture::Constant(Color::ZERO)).then(|| self.color(&c.albedo)).transpose()?,
                    g: (c.g != FloatTexture::Constant(0.0)).then(|| self.float(&c.g)).transpose()?,
                    max_depth: (c.max_depth != 10).then_some(c.max_depth),
                    n_samples: (c.n_samples != 1).then_some(c.n_samples),
                })
            }
            Material::CoatedConductor(c) => {
                if c.interface_roughness.remap != c.conductor_roughness.remap {
                    return Err("a coated conductor whose coat and conductor roughness are remapped differently \
                                cannot be written to a scene file (`remap_roughness` applies to both)"
                        .to_owned());
                }
                let (interface_roughness, interface_u_roughness, interface_v_roughness, remap_roughness) =
                    self.roughness(&c.interface_roughness)?;
                let (conductor_roughness, conductor_u_roughness, conductor_v_roughness, _) =
                    self.roughness(&c.conductor_roughness)?;
                let (conductor_color, conductor_eta, conductor_k, conductor_reflectance) =
                    self.fresnel(&c.conductor)?;
                MaterialKindDesc::CoatedConductor(CoatedConductorDesc {
                    interface_roughness,
                    interface_u_roughness,
                    interface_v_roughness,
                    interface_eta: Some(positive(c.interface_eta, "interface_eta")?),
                    conductor_eta,
                    conductor_k,
                    conductor_reflectance,
                    conductor_color,
                    metal: None,
                    conductor_roughness,
                    conductor_u_roughness,
                    conductor_v_roughness,
                    remap_roughness,
                    thickness: Some(self.float(&c.thickness)?),
                    albedo: (c.albedo != Texture::Constant(Color::ZERO)).then(|| self.color(&c.albedo)).transpose()?,
                    g: (c.g != FloatTexture::Constant(0.0)).then(|| self.float(&c.g)).transpose()?,
                    max_depth: (c.max_depth != 10).then_some(c.max_depth),
                    n_samples: (c.n_samples != 1).then_some(c.n_samples),
                })
            }
            Material::MetallicRoughness(m) => {
                // A colour and its factor: one constant, or the texture with
                // the factor beside it (omitted when white).
                let mut factored = |factor: Color, t: &Option<Texture>, default: Color| -> Result<_, String> {
                    Ok(match t {
                        None => ((factor != default).then(|| Self::color_value(factor)).transpose()?, None),
                        Some(t) => (Some(self.color(t)?), (factor != Color::ONE).then(|| rgb(factor))),
                    })
                };
                let (base_color, base_color_factor) = factored(m.base_color_factor, &m.base_color, Color::ONE)?;
                let (specular_color, specular_color_factor) =
                    factored(m.specular_color_factor, &m.specular_color, Color::ONE)?;
                let (sheen_color, sheen_color_factor) = factored(m.sheen_color_factor, &m.sheen_color, Color::ZERO)?;
                let mut float = |t: &FloatTexture, default: f32| -> Result<Option<TexValue>, String> {
                    (*t != FloatTexture::Constant(default)).then(|| self.float(t)).transpose()
                };
                MaterialKindDesc::MetallicRoughness(MetallicRoughnessDesc {
                    base_color,
                    base_color_factor,
                    metallic: float(&m.metallic, 1.0)?,
                    roughness: float(&m.roughness, 1.0)?,
                    ior: (m.ior != 1.5).then(|| positive(m.ior, "ior")).transpose()?,
                    specular: float(&m.specular, 1.0)?,
                    specular_color,
                    specular_color_factor,
                    transmission: float(&m.transmission, 0.0)?,
                    thin: (!m.thin).then_some(false),
                    clearcoat: float(&m.clearcoat, 0.0)?,
                    clearcoat_roughness: float(&m.clearcoat_roughness, 0.0)?,
                    sheen_color,
                    sheen_color_factor,
                    sheen_roughness: float(&m.sheen_roughness, 0.0)?,
                })
            }
            Material::Mix { materials, amount } => {
                let name = |i: usize| {
                    material_names
                        .get(materials[i].index())
                        .cloned()
                        .ok_or_else(|| format!("mix: material #{} has no name", materials[i].index()))
                };
                MaterialKindDesc::Mix(MixMaterialDesc {
                    materials: [name(0)?, name(1)?],
                    amount: Some(self.float(amount)?),
                })
            }
            Material::Interface => MaterialKindDesc::Interface(InterfaceDesc {}),
            Material::Shaded { .. } => unreachable!("unwrapped above"),
        };
        Ok(MaterialDesc { kind, displacement, normal_map, normal_scale })
    }

    /// A normal map as its file: only the form the loaders make (an image
    /// read linearly, `(u, v)` mapping, default lookup) can be written.
    fn normal_map(&mut self, t: &Texture) -> Result<String, String> {
        let unsupported = || {
            "a normal map other than an image file read linearly with the default mapping and filtering cannot be \
             written to a scene file"
                .to_owned()
        };
        let Texture::Image(im) = t else { return Err(unsupported()) };
        if *im.mapping() != TextureMapping::default() || *im.params() != ImageTextureParams::default() {
            return Err(unsupported());
        }
        match im.mipmap().source() {
            Some(source) if source.encoding == ColorEncoding::Linear => Ok(self.path_name(&source.path)),
            Some(_) => Err(unsupported()),
            // Texels in memory are linear, as the EXR written of them.
            None => Ok(self.memory_image(im.mipmap())),
        }
    }
}

/// The scene file's name of a wrap mode.
fn wrap_desc(w: WrapMode) -> WrapDesc {
    match w {
        WrapMode::Repeat => WrapDesc::Repeat,
        WrapMode::Clamp => WrapDesc::Clamp,
        WrapMode::Black => WrapDesc::Black,
        WrapMode::MirroredRepeat => WrapDesc::MirroredRepeat,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loader::textures::TextureTable;
    use crate::loader::{SceneFile, SceneFormat};
    use crate::material::{CoatedConductorMaterial, CoatedDiffuseMaterial, MaterialId};
    use crate::texture::{ImageCache, ImageTexture};
    use std::sync::Arc;

    /// Export `materials`, write the scene as TOML, read it back and build
    /// each material again; returns the TOML text and the rebuilt
    /// materials in the same order.
    fn round_trip(dir: &Path, materials: &[(String, Material)]) -> (String, Vec<Material>) {
        let names: Vec<String> = materials.iter().map(|(n, _)| n.clone()).collect();
        let mut export = TextureExport::new(dir);
        let mut desc: SceneDescription =
            toml::from_str("[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\n").expect("a minimal scene");
        for (name, m) in materials {
            let d = export.material(m, &names).unwrap_or_else(|e| panic!("{name}: {e}"));
            desc.materials.insert(name.clone(), d);
        }
        desc.textures = export.textures;
        let text = toml::to_string(&desc).expect("serialises");
        let file = SceneFile::parse(text.clone(), SceneFormat::Toml, Some(dir.join("scene.toml")))
            .unwrap_or_else(|e| panic!("{e}\n{text}"));
        let mut table = TextureTable::new(&file).unwrap_or_else(|e| panic!("{e}\n{text}"));
        let ids: HashMap<String, MaterialId> =
            names.iter().enumerate().map(|(i, n)| (n.clone(), MaterialId::new(i))).collect();
        let rebuilt = names
            .iter()
            .map(|n| {
                file.material(n, &file.description.materials[n], &mut table, &ids)
                    .unwrap_or_else(|e| panic!("{n}: {e}\n{text}"))
            })
            .collect();
        (text, rebuilt)
    }

    fn write_png(path: &Path, rgb: [u8; 3]) {
        image::RgbImage::from_fn(4, 2, |x, y| image::Rgb([rgb[0] ^ (x as u8 * 40), rgb[1] ^ (y as u8 * 60), rgb[2]]))
            .save(path)
            .unwrap();
    }

    #[test]
    fn every_material_kind_survives_a_toml_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let (wood, bumps) = (dir.path().join("wood.png"), dir.path().join("normals.png"));
        write_png(&wood, [200, 120, 40]);
        write_png(&bumps, [128, 128, 255]);
        let cache = ImageCache::new();
        let srgb = cache.mipmap(&wood, ColorEncoding::Srgb).unwrap();
        let linear = cache.mipmap(&bumps, ColorEncoding::Linear).unwrap();
        let params = ImageTextureParams {
            filter: FilterFunction::Ewa,
            max_anisotropy: 4.0,
            wrap: WrapMode::Clamp.into(),
            scale: 0.5,
            invert: true,
            channel: None,
        };
        let image = Arc::new(ImageTexture::new(TextureMapping::uv(2.0, 3.0, 0.25, 0.0), srgb.clone(), params));
        let moved = Transform::translate(Vec3::new(1.0, 2.0, 3.0));
        let doubled = Transform::scale(Vec3::splat(2.0)).unwrap();
        let sphere_image = Arc::new(ImageTexture::new(
            TextureMapping::spherical(&moved),
            // Gamma-encoded: the encoding is written out.
            cache.mipmap(&wood, ColorEncoding::Gamma(2.2)).unwrap(),
            ImageTextureParams::default(),
        ));
        let bilerp = FloatTexture::bilerp(TextureMapping::cylindrical(&doubled), 0.1, 0.2, 0.3, 0.4);
        let planar = TextureMapping::planar(&moved, Vec3::new(0.5, 0.0, 0.0), Vec3::Z, 0.5, -0.25);
        let board =
            Texture::checkerboard(planar, Texture::Constant(Color::new(0.1, 0.2, 0.3)), Texture::Image(image.clone()));
        let solid =
            FloatTexture::checkerboard_3d(&doubled, FloatTexture::Constant(0.2), FloatTexture::Image(image.clone()));
        let normal_map = Texture::image(Arc::new(ImageTexture::new(
            TextureMapping::default(),
            linear,
            ImageTextureParams::default(),
        )));
        let materials: Vec<(String, Material)> = vec![
            ("matte".into(), Material::matte(Color::new(0.5, 0.2, 0.1), 0.8).unwrap().with_ka(0.3).unwrap()),
            (
                "phong".into(),
                Material::phong(
                    Texture::Checker { even: Color::ONE, odd: Color::new(0.0, 0.5, 0.0), scale: 0.25 },
                    0.7,
                    0.4,
                    30.0,
                    0.2,
                )
                .unwrap(),
            ),
            ("diffuse".into(), Material::Diffuse { reflectance: Texture::Image(image.clone()) }),
            (
                "conductor".into(),
                Material::Conductor {
                    fresnel: ConductorFresnel::Complex {
                        eta: Texture::Scale {
                            tex: Arc::new(Texture::Image(image.clone())),
                            scale: Arc::new(bilerp.clone()),
                        },
                        k: Texture::Constant(Color::new(3.0, 2.5, 2.0)),
                    },
                    roughness: Roughness::anisotropic(0.1, FloatTexture::Image(image.clone()), true),
                },
            ),
            (
                "reflectance".into(),
                Material::Conductor {
                    fresnel: ConductorFresnel::Reflectance { r: Texture::Constant(Color::new(0.9, 0.5, 0.1)) },
                    roughness: Roughness::alpha(0.2),
                },
            ),
            (
                "glass".into(),
                Material::Dielectric {
                    eta: 1.33,
                    roughness: Roughness::isotropic(0.3, true),
                    tint: Color::new(1.0, 0.9, 0.8),
                },
            ),
            ("plastic".into(), Material::Plastic { reflectance: board.clone(), eta: 1.4, roughness: 0.05 }),
            ("pane".into(), Material::ThinDielectric { eta: 1.6 }),
            (
                "leaf".into(),
                Material::DiffuseTransmission {
                    reflectance: Texture::mix(
                        Texture::Constant(Color::splat(0.2)),
                        Texture::Image(sphere_image.clone()),
                        solid.clone(),
                    ),
                    transmittance: Texture::Constant(Color::new(0.1, 0.4, 0.1)),
                    scale: 0.9,
                },
            ),
            (
                "coated".into(),
                Material::CoatedDiffuse(CoatedDiffuseMaterial {
                    reflectance: Texture::direction_mix(
                        Texture::Constant(Color::ONE),
                        board,
                        Vec3::Z,
                        &Transform::IDENTITY,
                    )
                    .unwrap(),
                    roughness: Roughness::anisotropic(0.2, 0.05, false),
                    thickness: bilerp.clone(),
                    eta: 1.7,
                    albedo: Texture::Constant(Color::splat(0.3)),
                    g: FloatTexture::Constant(-0.4),
                    max_depth: 5,
                    n_samples: 3,
                }),
            ),
            (
                "coated_metal".into(),
                Material::CoatedConductor(CoatedConductorMaterial {
                    conductor: ConductorFresnel::Schlick { r0: Texture::Image(sphere_image) },
                    conductor_roughness: Roughness::isotropic(solid, true),
                    ..Default::default()
                }),
            ),
            ("coated_copper".into(), Material::CoatedConductor(CoatedConductorMaterial::default())),
            (
                "mix".into(),
                Material::Mix {
                    materials: [MaterialId::new(0), MaterialId::new(2)],
                    amount: FloatTexture::DirectionMix {
                        tex1: Arc::new(FloatTexture::Constant(0.0)),
                        tex2: Arc::new(bilerp),
                        dir: Vec3::Y,
                    },
                },
            ),
            ("medium".into(), Material::Interface),
            (
                "bumpy".into(),
                Material::Diffuse { reflectance: Texture::Constant(Color::splat(0.5)) }
                    .with_bump(FloatTexture::Scale {
                        tex: Arc::new(FloatTexture::Image(image.clone())),
                        scale: Arc::new(FloatTexture::Constant(0.01)),
                    })
                    .with_normal_map(normal_map.clone()),
            ),
            (
                "normal_mapped".into(),
                Material::Plastic { reflectance: Color::ONE.into(), eta: 1.5, roughness: 0.0 }
                    .with_normal_map(normal_map),
            ),
        ];
        let (text, rebuilt) = round_trip(dir.path(), &materials);
        for ((name, original), again) in materials.iter().zip(&rebuilt) {
            assert_eq!(original, again, "material \"{name}\" changed in the round trip:\n{text}");
        }
        // The image files are named relative to the scene, the encoding
        // only when it is not the file type's default; the image used
        // three times (colour, number, scaled) is one table.
        assert!(text.contains("file = \"wood.png\""), "{text}");
        assert!(text.contains("encoding = \"gamma 2.2\""), "{text}");
        assert!(text.contains("normal_map = \"normals.png\""), "{text}");
        assert_eq!(text.matches("filter = \"ewa\"").count(), 1, "{text}");
        // Constants are inline.
        assert!(text.contains("k = [3.0, 2.5, 2.0]"), "{text}");
        // The rebuilt image textures share one pyramid per file and
        // encoding and remember their file.
        let Material::Diffuse { reflectance: Texture::Image(a) } = &rebuilt[2] else { panic!() };
        assert_eq!(a.source(), Some(std::fs::canonicalize(&wood).unwrap().as_path()));
    }

    #[test]
    fn a_pbrt_scene_exports_to_equal_materials() {
        let dir = tempfile::tempdir().unwrap();
        write_png(&dir.path().join("wood.png"), [90, 60, 30]);
        write_png(&dir.path().join("n.png"), [128, 128, 255]);
        let pbrt = r#"
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" 45
WorldBegin
Texture "wood" "spectrum" "imagemap" "string filename" "wood.png" "float uscale" 4 "string wrap" "clamp"
Texture "woodf" "float" "imagemap" "string filename" "wood.png" "float uscale" 4 "string wrap" "clamp"
Texture "checks" "spectrum" "checkerboard" "float uscale" 8 "texture tex1" "wood" "rgb tex2" [0.1 0.2 0.3]
Texture "dim" "spectrum" "scale" "texture tex" "checks" "float scale" 0.5
AttributeBegin
  Translate 1 2 3
  Texture "sky" "spectrum" "directionmix" "texture tex1" "dim" "rgb tex2" [0 0 1]
  Texture "ball" "float" "imagemap" "string filename" "wood.png" "string mapping" "spherical"
AttributeEnd
Texture "blend" "float" "mix" "texture tex1" "woodf" "float tex2" 0.2 "texture amount" "ball"
MakeNamedMaterial "a" "string type" "coateddiffuse" "texture reflectance" "sky" "texture roughness" "blend"
MakeNamedMaterial "b" "string type" "coatedconductor" "rgb conductor.reflectance" [0.9 0.6 0.3] "float interface.roughness" 0.1
MakeNamedMaterial "c" "string type" "conductor" "float uroughness" 0.1 "float vroughness" 0.3 "texture displacement" "woodf"
MakeNamedMaterial "d" "string type" "mix" "string materials" ["a" "c"] "texture amount" "blend"
MakeNamedMaterial "e" "string type" "diffuse" "string normalmap" "n.png"
MakeNamedMaterial "f" "string type" "dielectric" "float eta" 1.33 "float roughness" 0.2
MakeNamedMaterial "g" "string type" "thindielectric"
MakeNamedMaterial "h" "string type" "diffusetransmission" "texture transmittance" "dim"
MakeNamedMaterial "i" "string type" "interface"
NamedMaterial "d"
Shape "sphere"
"#;
        let path = dir.path().join("scene.pbrt");
        std::fs::write(&path, pbrt).unwrap();
        let loaded = crate::loader::pbrt::import_pbrt(&path, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
        let materials: Vec<(String, Material)> =
            loaded.scene.materials().iter().enumerate().map(|(i, m)| (format!("m{i}"), m.clone())).collect();
        assert!(materials.len() >= 9, "{materials:?}");
        let (text, rebuilt) = round_trip(dir.path(), &materials);
        for ((name, original), again) in materials.iter().zip(&rebuilt) {
            assert_eq!(original, again, "material \"{name}\" changed in the round trip:\n{text}");
        }
        // The colour and number views of one image share a table.
        assert_eq!(text.matches("file = \"wood.png\"").count(), 2, "{text}");
    }

    #[test]
    fn images_made_in_memory_are_written_beside_the_scene() {
        let pixels = crate::texture::TextureImage::new(1, 1, 3, vec![0.5, 0.5, 0.5]).unwrap();
        let mipmap = Arc::new(crate::texture::MipMap::new(pixels).unwrap());
        let t = Texture::image(Arc::new(ImageTexture::new(
            TextureMapping::default(),
            Arc::clone(&mipmap),
            Default::default(),
        )));
        let mut export = TextureExport::new(Path::new(".")).with_image_dir("scene-textures");
        let m = Material::Diffuse { reflectance: t };
        let desc = export.material(&m, &[]).unwrap();
        // The same image twice is one file.
        export.material(&m, &[]).unwrap();
        assert_eq!(export.images.len(), 1);
        assert_eq!(export.images[0].0, "scene-textures/image-1.exr");
        assert!(Arc::ptr_eq(&export.images[0].1, &mipmap));
        let MaterialKindDesc::Diffuse(d) = desc.kind else { panic!("{desc:?}") };
        let Some(TexValue::Name(name)) = d.color else { panic!("{d:?}") };
        let TextureDesc::Image(im) = &export.textures[&name] else { panic!() };
        assert_eq!(im.file, "scene-textures/image-1.exr");
        // A mix naming a material outside the list.
        let mix = Material::Mix { materials: [MaterialId::new(0), MaterialId::new(5)], amount: 0.5.into() };
        let e = export.material(&mix, &["a".to_owned()]).unwrap_err();
        assert!(e.contains("#5"), "{e}");
    }
}
