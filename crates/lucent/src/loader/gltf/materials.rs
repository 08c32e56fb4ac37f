//! glTF materials to lucent's: the metallic-roughness model and its
//! extensions ([`MetallicRoughnessMaterial`]), normal maps, emission and
//! alpha, with textures read in the channels glTF assigns them.

use super::{GltfError, Importer};
use crate::color::Color;
use crate::material::{Material, MetallicRoughnessMaterial, NormalPerturbation};
use crate::texture::{
    FilterFunction, FloatTexture, ImageTexture, ImageTextureParams, Texture, TextureMapping, WrapMode, WrapModes,
};
use serde_json::Value;
use std::sync::Arc;

/// What a glTF material becomes: the surface, its emission, its alpha.
#[derive(Clone, Debug)]
pub(super) struct Converted {
    /// The surface (normal map included).
    pub material: Material,
    /// Emitted radiance and its texture, if the material emits.
    pub emission: Option<(Color, Option<Texture>)>,
    /// The alpha cut-out (`MASK`: 0 or 1 at the cutoff; `BLEND`: the
    /// alpha itself, used as stochastic transparency), if not opaque.
    pub alpha: Option<FloatTexture>,
    /// `doubleSided`.
    pub double_sided: bool,
    /// The `KHR_materials_volume` interior, if the material has one:
    /// attenuation colour and distance.
    pub volume: Option<(Color, f32)>,
}

/// `KHR_texture_transform` of a texture reference.
#[derive(Clone, Copy, Debug)]
struct UvTransform {
    offset: [f32; 2],
    /// Radians, counter-clockwise.
    rotation: f32,
    scale: [f32; 2],
    /// Overrides the reference's `texCoord`.
    tex_coord: Option<u32>,
}

/// A texture reference: the texture, its `texCoord` set and its
/// `KHR_texture_transform`, from either the crate's `Info` or raw JSON.
pub(super) struct TexRef {
    index: usize,
    tex_coord: u32,
    transform: Option<UvTransform>,
}

impl TexRef {
    fn from_info(info: &gltf::texture::Info) -> Self {
        let transform = info.texture_transform().map(|t| UvTransform {
            offset: t.offset(),
            rotation: t.rotation(),
            scale: t.scale(),
            tex_coord: t.tex_coord(),
        });
        Self { index: info.texture().index(), tex_coord: info.tex_coord(), transform }
    }

    /// A `textureInfo` object of an extension the crate gives as JSON.
    fn from_json(v: &Value) -> Option<Self> {
        let index = v.get("index")?.as_u64()? as usize;
        let tex_coord = v.get("texCoord").and_then(Value::as_u64).unwrap_or(0) as u32;
        let transform = v.get("extensions").and_then(|e| e.get("KHR_texture_transform")).map(|t| {
            let pair = |k: &str, d: [f32; 2]| {
                t.get(k)
                    .and_then(Value::as_array)
                    .filter(|a| a.len() == 2)
                    .map(|a| [a[0].as_f64().unwrap_or(d[0] as f64) as f32, a[1].as_f64().unwrap_or(d[1] as f64) as f32])
                    .unwrap_or(d)
            };
            let rotation = t.get("rotation").and_then(Value::as_f64).unwrap_or(0.0) as f32;
            let tc = t.get("texCoord").and_then(Value::as_u64).map(|v| v as u32);
            UvTransform {
                offset: pair("offset", [0.0, 0.0]),
                rotation,
                scale: pair("scale", [1.0, 1.0]),
                tex_coord: tc,
            }
        });
        Some(Self { index, tex_coord, transform })
    }
}

impl TexRef {
    /// The texture-coordinate set the lookup reads: `texCoord`, unless
    /// `KHR_texture_transform` overrides it.
    fn set(&self) -> u32 {
        self.transform.and_then(|t| t.tex_coord).unwrap_or(self.tex_coord)
    }
}

/// The texture mapping of `r`: glTF's `v` runs down the image and lucent's
/// up, so the mesh stores `(u, 1 − v)`; `KHR_texture_transform`'s
/// `T·R·S` acts on glTF's `(u, v)`, so the mapping conjugates it by that
/// flip (see [`TextureMapping::UvAffine`]). Sets after `TEXCOORD_1` read
/// `TEXCOORD_0` (the importer warns).
fn mapping(r: &TexRef) -> TextureMapping {
    let set = u8::from(r.set() == 1);
    let Some(UvTransform { offset, rotation, scale, .. }) = r.transform else {
        return match set {
            0 => TextureMapping::default(),
            _ => TextureMapping::UvAffine { m: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0], set },
        };
    };
    // glTF: uv' = (a u + b v + c, d u + e v + f) with T·R·S of the
    // extension (R's columns are (cos, sin) and (−sin, cos)).
    let (s, c) = rotation.sin_cos();
    let (a, b, cc) = (c * scale[0], -s * scale[1], offset[0]);
    let (d, e, f) = (s * scale[0], c * scale[1], offset[1]);
    // In lucent's (u, t = 1 − v): s = a u − b t + (b + c),
    // t' = 1 − v' = −d u + e t + (1 − e − f).
    TextureMapping::UvAffine { m: [a, -b, b + cc, -d, e, 1.0 - e - f], set }
}

fn wrap(w: gltf::texture::WrappingMode) -> WrapMode {
    match w {
        gltf::texture::WrappingMode::ClampToEdge => WrapMode::Clamp,
        gltf::texture::WrappingMode::MirroredRepeat => WrapMode::MirroredRepeat,
        gltf::texture::WrappingMode::Repeat => WrapMode::Repeat,
    }
}

impl Importer<'_> {
    /// The image texture `r` refers to, decoded as sRGB colour or linear
    /// data, reading `channel` when a float texture reads one, with
    /// `scale` folded in.
    fn image_texture(
        &mut self,
        r: &TexRef,
        srgb: bool,
        channel: Option<u8>,
        scale: f32,
        what: &str,
    ) -> Result<Arc<ImageTexture>, GltfError> {
        let doc = self.doc;
        let texture = doc
            .textures()
            .nth(r.index)
            .ok_or_else(|| GltfError::new(what, format!("refers to textures[{}], which does not exist", r.index)))?;
        let image = texture.source().index();
        let set = r.set();
        if set > 1 {
            self.warn_once(
                "texcoord",
                format!(
                    "{what}: texture coordinate set TEXCOORD_{set} is not supported (only 0 and 1); TEXCOORD_0 is used"
                ),
            )?;
        }
        let mipmap = self.images.mipmap(doc, image, srgb, self.base, self.buffers)?;
        let sampler = texture.sampler();
        let filter = match (sampler.mag_filter(), sampler.min_filter()) {
            (Some(gltf::texture::MagFilter::Nearest), _) => FilterFunction::Point,
            (_, Some(gltf::texture::MinFilter::LinearMipmapLinear | gltf::texture::MinFilter::NearestMipmapLinear)) => {
                FilterFunction::Trilinear
            }
            _ => FilterFunction::Bilinear,
        };
        let params = ImageTextureParams {
            filter,
            wrap: WrapModes { s: wrap(sampler.wrap_s()), t: wrap(sampler.wrap_t()) },
            scale,
            channel,
            ..ImageTextureParams::default()
        };
        Ok(Arc::new(ImageTexture::new(mapping(r), mipmap, params)))
    }

    /// `factor ×` one channel of the texture `r` (or the factor alone).
    fn float(&mut self, factor: f32, r: Option<TexRef>, channel: u8, what: &str) -> Result<FloatTexture, GltfError> {
        Ok(match r {
            Some(r) if factor != 0.0 => {
                FloatTexture::Image(self.image_texture(&r, false, Some(channel), factor, what)?)
            }
            _ => FloatTexture::Constant(factor),
        })
    }

    /// The RGB of an sRGB colour texture.
    fn color(&mut self, r: Option<TexRef>, what: &str) -> Result<Option<Texture>, GltfError> {
        r.map(|r| Ok(Texture::Image(self.image_texture(&r, true, None, 1.0, what)?))).transpose()
    }

    /// glTF material `m` (the default material for `None`: glTF 2.0
    /// §3.9.6), on a primitive with vertex colours if `vertex_colors`:
    /// `COLOR_0` multiplies the base colour and its alpha (glTF 2.0
    /// §3.9.2).
    pub(super) fn material(&mut self, m: Option<gltf::Material>, vertex_colors: bool) -> Result<Converted, GltfError> {
        let Some(m) = m else {
            let mut mr = MetallicRoughnessMaterial::default();
            if vertex_colors {
                mr.base_color = Some(Texture::VertexColor);
            }
            return Ok(Converted {
                material: Material::MetallicRoughness(Box::new(mr)),
                emission: None,
                alpha: None,
                double_sided: false,
                volume: None,
            });
        };
        let what = format!("materials[{}]", m.index().unwrap_or(0));
        let pbr = m.pbr_metallic_roughness();
        let [r, g, b, a] = pbr.base_color_factor();
        let base_color = self.color(pbr.base_color_texture().map(|i| TexRef::from_info(&i)), &what)?;
        let base_color = with_vertex_color(base_color, vertex_colors);
        let mut mr = MetallicRoughnessMaterial {
            base_color_factor: Color::new(r, g, b),
            base_color: base_color.clone(),
            ..Default::default()
        };
        let mrt = pbr.metallic_roughness_texture().map(|i| TexRef::from_info(&i));
        mr.metallic = self.float(pbr.metallic_factor(), mrt.as_ref().map(clone_ref), 2, &what)?;
        mr.roughness = self.float(pbr.roughness_factor(), mrt, 1, &what)?;
        if let Some(ior) = m.ior() {
            // KHR_materials_ior: 0 is allowed and means F0 = 1 (a mirror);
            // lucent's model needs ≥ 1, so 0 maps to a very high index.
            mr.ior = if ior == 0.0 { 1.0e4 } else { ior };
        }
        if let Some(s) = m.specular() {
            mr.specular =
                self.float(s.specular_factor(), s.specular_texture().map(|i| TexRef::from_info(&i)), 3, &what)?;
            mr.specular_color_factor = Color::from(s.specular_color_factor());
            mr.specular_color = self.color(s.specular_color_texture().map(|i| TexRef::from_info(&i)), &what)?;
        }
        if let Some(t) = m.transmission() {
            mr.transmission =
                self.float(t.transmission_factor(), t.transmission_texture().map(|i| TexRef::from_info(&i)), 0, &what)?;
        }
        let mut volume = None;
        if let Some(v) = m.volume() {
            if v.thickness_factor() > 0.0 {
                mr.thin = false;
                let distance = v.attenuation_distance();
                if distance.is_finite() && distance > 0.0 {
                    volume = Some((Color::from(v.attenuation_color()), distance));
                }
            }
        }
        if let Some(c) = m.extension_value("KHR_materials_clearcoat") {
            let f = |k: &str| c.get(k).and_then(Value::as_f64).map(|v| v as f32);
            let tex = |k: &str| c.get(k).and_then(TexRef::from_json);
            mr.clearcoat = self.float(f("clearcoatFactor").unwrap_or(0.0), tex("clearcoatTexture"), 0, &what)?;
            mr.clearcoat_roughness =
                self.float(f("clearcoatRoughnessFactor").unwrap_or(0.0), tex("clearcoatRoughnessTexture"), 1, &what)?;
            if c.get("clearcoatNormalTexture").is_some() {
                self.warn_once(
                    "clearcoat normal",
                    format!("{what}: clearcoatNormalTexture is not supported; the coat uses the base's normal"),
                )?;
            }
        }
        if let Some(s) = m.extension_value("KHR_materials_sheen") {
            let color = s
                .get("sheenColorFactor")
                .and_then(Value::as_array)
                .filter(|a| a.len() == 3)
                .map(|a| Color::new(num(&a[0]), num(&a[1]), num(&a[2])))
                .unwrap_or(Color::ZERO);
            mr.sheen_color_factor = color;
            mr.sheen_color = self.color(s.get("sheenColorTexture").and_then(TexRef::from_json), &what)?;
            let rough = s.get("sheenRoughnessFactor").and_then(Value::as_f64).unwrap_or(0.0) as f32;
            mr.sheen_roughness =
                self.float(rough, s.get("sheenRoughnessTexture").and_then(TexRef::from_json), 3, &what)?;
        }
        let mut material = Material::MetallicRoughness(Box::new(mr));
        if let Some(n) = m.normal_texture() {
            let r = TexRef { index: n.texture().index(), tex_coord: n.tex_coord(), transform: None };
            let r = match n.extension_value("KHR_texture_transform") {
                Some(_) => TexRef::from_json(&serde_json::json!({
                    "index": n.texture().index(),
                    "texCoord": n.tex_coord(),
                    "extensions": { "KHR_texture_transform": n.extension_value("KHR_texture_transform") }
                }))
                .unwrap_or(r),
                None => r,
            };
            // Read bilinearly and repeated whatever the sampler says, as
            // pbrt-v4 reads its normal maps (a mipmapped normal is an
            // average of directions, not a normal).
            let t = self.image_texture(&r, false, None, 1.0, &what)?;
            let t = ImageTexture::new(*t.mapping(), Arc::clone(t.mipmap()), ImageTextureParams::default());
            let map = Texture::Image(Arc::new(t));
            material = Material::Shaded {
                material: Box::new(material),
                normal: NormalPerturbation::ScaledNormalMap { map, scale: n.scale() },
            };
        }
        // Emission (glTF 2.0 §3.9.4; KHR_materials_emissive_strength).
        let strength = m.emissive_strength().unwrap_or(1.0);
        let mut emissive = Color::from(m.emissive_factor()) * strength;
        let emissive_texture = m.emissive_texture().map(|i| TexRef::from_info(&i));
        if m.unlit() {
            // KHR_materials_unlit: the base colour is shown as it is; in a
            // path tracer, a black surface emitting its base colour.
            emissive = Color::new(r, g, b);
            material = Material::Diffuse { reflectance: Texture::Constant(Color::ZERO) };
        }
        let emission = if emissive.max_element() > 0.0 {
            let texture = if m.unlit() { base_color } else { self.color(emissive_texture, &what)? };
            Some((emissive, texture))
        } else {
            None
        };
        if m.occlusion_texture().is_some() {
            self.note("occlusionTexture is ignored: a path tracer computes occlusion itself");
        }
        // Alpha (glTF 2.0 §3.9.5): the base colour's alpha times its
        // texture's.
        let alpha = match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => None,
            mode => {
                let source = match pbr.base_color_texture() {
                    Some(info) => {
                        let r = TexRef::from_info(&info);
                        let tex = self.image_texture(&r, true, Some(3), a, &what)?;
                        FloatTexture::Image(tex)
                    }
                    None => FloatTexture::Constant(a),
                };
                let source =
                    if vertex_colors { FloatTexture::scale(source, FloatTexture::VertexAlpha) } else { source };
                Some(match mode {
                    gltf::material::AlphaMode::Mask => {
                        let cutoff = m.alpha_cutoff().unwrap_or(0.5);
                        alpha_mask(source, cutoff)
                    }
                    _ => source,
                })
            }
        };
        Ok(Converted { material, emission, alpha, double_sided: m.double_sided(), volume })
    }
}

/// The base colour texture times the vertex colour, when the primitive
/// has one.
fn with_vertex_color(texture: Option<Texture>, vertex_colors: bool) -> Option<Texture> {
    match (texture, vertex_colors) {
        (Some(t), true) => Some(Texture::product(t, Texture::VertexColor)),
        (None, true) => Some(Texture::VertexColor),
        (t, false) => t,
    }
}

/// A number of a JSON value (0 if it is none).
fn num(v: &Value) -> f32 {
    v.as_f64().unwrap_or(0.0) as f32
}

fn clone_ref(r: &TexRef) -> TexRef {
    TexRef { index: r.index, tex_coord: r.tex_coord, transform: r.transform }
}

/// `MASK`: opaque where `alpha ≥ cutoff`, absent below (glTF 2.0 §3.9.5).
fn alpha_mask(alpha: FloatTexture, cutoff: f32) -> FloatTexture {
    match alpha {
        FloatTexture::Constant(a) => FloatTexture::Constant(if a >= cutoff { 1.0 } else { 0.0 }),
        other => FloatTexture::Step { texture: Arc::new(other), threshold: cutoff },
    }
}
