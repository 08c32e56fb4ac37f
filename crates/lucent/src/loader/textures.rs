//! Scene-file textures: the `[textures.NAME.KIND]` tables built into
//! [`crate::texture`] values, and texture-valued parameters
//! ([`TexValue`]) resolved against them.
//!
//! A texture table is untyped: it is built as a colour ([`Texture`]) or a
//! number ([`FloatTexture`]) when a parameter asks for one, once per name
//! and type (the `Arc` is shared by every user). Image files go through
//! one [`ImageCache`] per scene load, so a file read by several textures
//! (or as a colour and as a number) is loaded once. Unknown names and
//! cycles are found for the whole table before anything is built.

use super::description::*;
use super::locate::*;
use super::values::*;
use super::SceneFile;
use crate::color::Color;
use crate::geometry::{Transform, Vec3};
use crate::scene::{SceneError, SourceLocation};
use crate::texture::{
    ColorEncoding, FilterFunction, FloatTexture, ImageCache, ImageTexture, ImageTextureParams, Texture, TextureMapping,
    WrapMode, WrapModes,
};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// The textures of one scene file while it is built.
pub(super) struct TextureTable<'a> {
    file: &'a SceneFile,
    images: ImageCache,
    image_textures: HashMap<String, Arc<ImageTexture>>,
    colors: HashMap<String, Arc<Texture>>,
    floats: HashMap<String, Arc<FloatTexture>>,
    /// Image files read (textures and normal maps).
    pub files: Vec<PathBuf>,
}

/// The texture names a texture table refers to, with the key naming each.
fn references(t: &TextureDesc) -> Vec<(&'static str, &str)> {
    let keyed: Vec<(&'static str, Option<&TexValue>)> = match t {
        TextureDesc::Image(_) | TextureDesc::Checker(_) | TextureDesc::VertexColor(_) | TextureDesc::VertexAlpha(_) => {
            Vec::new()
        }
        TextureDesc::Scale(s) => vec![("tex", s.tex.as_ref()), ("scale", s.scale.as_ref())],
        TextureDesc::Mix(m) => {
            vec![("tex1", m.tex1.as_ref()), ("tex2", m.tex2.as_ref()), ("amount", m.amount.as_ref())]
        }
        TextureDesc::DirectionMix(m) => vec![("tex1", m.tex1.as_ref()), ("tex2", m.tex2.as_ref())],
        TextureDesc::Checkerboard(c) => vec![("tex1", c.tex1.as_ref()), ("tex2", c.tex2.as_ref())],
        TextureDesc::Bilerp(b) => {
            vec![("v00", b.v00.as_ref()), ("v01", b.v01.as_ref()), ("v10", b.v10.as_ref()), ("v11", b.v11.as_ref())]
        }
        TextureDesc::Constant(c) => vec![("value", Some(&c.value))],
        TextureDesc::Step(t) => vec![("texture", Some(&t.texture))],
        TextureDesc::Product(p) => vec![("tex1", Some(&p.tex1)), ("tex2", Some(&p.tex2))],
    };
    keyed
        .into_iter()
        .filter_map(|(k, v)| match v {
            Some(TexValue::Name(n)) => Some((k, n.as_str())),
            _ => None,
        })
        .collect()
}

/// The transform of a list of steps, applied in order (as objects'
/// `transform`).
pub(super) fn transform_of(ops: &[TransformOp]) -> Result<Transform, String> {
    let mut t = Transform::IDENTITY;
    for op in ops {
        let step = op.to_transform();
        t = t.then(&step.map_err(|e| format!("transform: {}", transform_error_message(&e)))?);
    }
    Ok(t)
}

/// A scene-file mapping as a [`TextureMapping`]; `None` is `uv`.
fn mapping(m: &Option<MappingDesc>) -> Result<TextureMapping, String> {
    let f = |v: Option<Finite>, d: f32| v.map_or(d, Finite::get);
    Ok(match m {
        None => TextureMapping::default(),
        Some(MappingDesc::Uv { su, sv, du, dv }) => {
            TextureMapping::uv(f(*su, 1.0), f(*sv, 1.0), f(*du, 0.0), f(*dv, 0.0))
        }
        Some(MappingDesc::Affine { m, uv_set }) => {
            let set = uv_set.unwrap_or(0);
            if set > 1 {
                return Err(format!("`uv_set` must be 0 or 1 (a mesh has at most two uv sets), got {set}"));
            }
            TextureMapping::UvAffine { m: m.map(Finite::get), set }
        }
        Some(MappingDesc::Spherical { transform }) => TextureMapping::spherical(&transform_of(transform)?),
        Some(MappingDesc::Cylindrical { transform }) => TextureMapping::cylindrical(&transform_of(transform)?),
        Some(MappingDesc::Planar { transform, v1, v2, du, dv }) => TextureMapping::planar(
            &transform_of(transform)?,
            v1.map_or(Vec3::X, Vec3::from),
            v2.map_or(Vec3::Y, Vec3::from),
            f(*du, 0.0),
            f(*dv, 0.0),
        ),
    })
}

/// The `encoding` key: `"srgb"`, `"linear"` or `"gamma G"`.
pub(super) fn encoding(s: &str) -> Result<ColorEncoding, String> {
    match s {
        "srgb" | "sRGB" => Ok(ColorEncoding::Srgb),
        _ => ColorEncoding::parse(s).map_err(|_| {
            format!("unknown encoding \"{s}\": expected \"srgb\", \"linear\" or \"gamma G\" (e.g. \"gamma 2.2\")")
        }),
    }
}

impl<'a> TextureTable<'a> {
    /// Check the `[textures]` table of `file` (every name a texture refers
    /// to exists, no texture contains itself) and read its image files.
    pub fn new(file: &'a SceneFile) -> Result<Self, SceneError> {
        let mut table = Self {
            file,
            images: ImageCache::new(),
            image_textures: HashMap::new(),
            colors: HashMap::new(),
            floats: HashMap::new(),
            files: Vec::new(),
        };
        table.check_graph()?;
        // Build every texture once, as a colour (which every valid texture
        // can be: numbers are greys), so that mistakes in unused textures
        // are found too and image files are read up front.
        for name in file.description.textures.keys() {
            table.color_named(name, "").map_err(|e| {
                let e = if e.starts_with("texture \"") { e } else { format!("texture \"{name}\": {e}") };
                file.error(table.at(name), e)
            })?;
        }
        Ok(table)
    }

    fn textures(&self) -> &'a std::collections::BTreeMap<String, TextureDesc> {
        &self.file.description.textures
    }

    /// Where texture `name` is defined.
    fn at(&self, name: &str) -> Option<SourceLocation> {
        nth_line_starting_with(&self.file.source, &format!("[textures.{name}"), 0)
            .or_else(|| find_key(&self.file.source, name, 0))
    }

    fn error(&self, name: &str, message: impl std::fmt::Display) -> SceneError {
        self.file.error(self.at(name), format!("texture \"{name}\": {message}"))
    }

    /// "not defined" with the defined names.
    pub fn undefined(&self, name: &str) -> String {
        let known: Vec<&str> = self.textures().keys().map(String::as_str).collect();
        let known = if known.is_empty() { "none".to_owned() } else { known.join(", ") };
        format!("no texture named \"{name}\" is defined in [textures] (defined: {known})")
    }

    fn check_graph(&self) -> Result<(), SceneError> {
        fn visit<'t>(
            table: &TextureTable<'t>,
            name: &'t str,
            path: &mut Vec<&'t str>,
            done: &mut Vec<&'t str>,
        ) -> Result<(), SceneError> {
            if let Some(start) = path.iter().position(|&p| p == name) {
                let mut cycle: Vec<String> = path[start..].iter().map(|p| format!("\"{p}\"")).collect();
                cycle.push(format!("\"{name}\""));
                return Err(table.error(path[start], format!("refers to itself ({})", cycle.join(" > "))));
            }
            if done.contains(&name) {
                return Ok(());
            }
            let (key, desc) = table.textures().get_key_value(name).expect("checked by the caller");
            path.push(key);
            for (param, r) in references(desc) {
                let Some((k, _)) = table.textures().get_key_value(r) else {
                    return Err(table.error(key, format!("`{param}`: {}", table.undefined(r))));
                };
                visit(table, k, path, done)?;
            }
            path.pop();
            done.push(key);
            Ok(())
        }
        let mut done = Vec::new();
        for name in self.textures().keys() {
            visit(self, name, &mut Vec::new(), &mut done)?;
        }
        Ok(())
    }

    /// Read an image file (through the cache), relative to the scene file.
    pub fn mipmap(&mut self, file: &str, enc: ColorEncoding) -> Result<Arc<crate::texture::MipMap>, String> {
        let path = self.file.relative(file);
        let m = self.images.mipmap(&path, enc).map_err(|e| e.to_string())?;
        self.files.push(path);
        Ok(m)
    }

    /// The image texture of the `image` table `name`.
    fn image(&mut self, name: &str) -> Result<Arc<ImageTexture>, String> {
        self.read_image(name).map_err(|e| format!("texture \"{name}\": {e}"))
    }

    fn read_image(&mut self, name: &str) -> Result<Arc<ImageTexture>, String> {
        if let Some(t) = self.image_textures.get(name) {
            return Ok(Arc::clone(t));
        }
        let Some(TextureDesc::Image(d)) = self.textures().get(name) else { unreachable!("an image table") };
        let enc = match &d.encoding {
            Some(e) => encoding(e)?,
            None => ColorEncoding::pbrt_default_for(&self.file.relative(&d.file)),
        };
        let params = ImageTextureParams {
            filter: match d.filter {
                None | Some(FilterFunctionDesc::Bilinear) => FilterFunction::Bilinear,
                Some(FilterFunctionDesc::Point) => FilterFunction::Point,
                Some(FilterFunctionDesc::Trilinear) => FilterFunction::Trilinear,
                Some(FilterFunctionDesc::Ewa) => FilterFunction::Ewa,
            },
            max_anisotropy: d.max_anisotropy.map_or(8.0, Positive::get),
            wrap: match d.wrap {
                None => WrapMode::Repeat.into(),
                Some(WrapSpec::Both(w)) => wrap_mode(w).into(),
                Some(WrapSpec::Axes { s, t }) => WrapModes { s: wrap_mode(s), t: wrap_mode(t) },
            },
            scale: d.scale.map_or(1.0, Finite::get),
            invert: d.invert,
            channel: d.channel.map(|c| c as u8),
        };
        let mapping = mapping(&d.mapping)?;
        let mipmap = self.mipmap(&d.file, enc)?;
        let t = Arc::new(ImageTexture::new(mapping, mipmap, params));
        self.image_textures.insert(name.to_owned(), Arc::clone(&t));
        Ok(t)
    }

    /// A colour parameter `what`: a grey, a colour or a texture.
    pub fn color(&mut self, v: &TexValue, what: &str) -> Result<Texture, String> {
        Ok(match v {
            TexValue::Number(x) => Texture::Constant(Color::splat(*x)),
            TexValue::Rgb(c) => Texture::Constant(Color::from_array(*c)),
            TexValue::Name(n) => (*self.color_named(n, what)?).clone(),
        })
    }

    /// A number parameter `what`: a number or a texture.
    pub fn float(&mut self, v: &TexValue, what: &str) -> Result<FloatTexture, String> {
        Ok(match v {
            TexValue::Number(x) => FloatTexture::Constant(*x),
            TexValue::Rgb(c) => {
                return Err(format!(
                    "`{what}` is a number or a texture name, not a colour [{}, {}, {}]",
                    c[0], c[1], c[2]
                ))
            }
            TexValue::Name(n) => (*self.float_named(n, what)?).clone(),
        })
    }

    fn color_arc(&mut self, v: &Option<TexValue>, default: f32, what: &str) -> Result<Arc<Texture>, String> {
        match v {
            Some(TexValue::Name(n)) => self.color_named(n, what),
            Some(v) => Ok(Arc::new(self.color(v, what)?)),
            None => Ok(Arc::new(Texture::Constant(Color::splat(default)))),
        }
    }

    fn float_arc(&mut self, v: &Option<TexValue>, default: f32, what: &str) -> Result<Arc<FloatTexture>, String> {
        match v {
            Some(TexValue::Name(n)) => self.float_named(n, what),
            Some(v) => Ok(Arc::new(self.float(v, what)?)),
            None => Ok(Arc::new(FloatTexture::Constant(default))),
        }
    }

    /// The texture `name` as a colour (`what` names the parameter, for
    /// messages).
    pub fn color_named(&mut self, name: &str, what: &str) -> Result<Arc<Texture>, String> {
        if let Some(t) = self.colors.get(name) {
            return Ok(Arc::clone(t));
        }
        let Some(desc) = self.textures().get(name) else {
            return Err(format!("`{what}`: {}", self.undefined(name)));
        };
        let inner = |key: &str| format!("texture \"{name}\" `{key}`");
        let t = match desc {
            TextureDesc::Image(_) => Texture::Image(self.image(name)?),
            TextureDesc::Scale(s) => Texture::Scale {
                tex: self.color_arc(&s.tex, 1.0, &inner("tex"))?,
                scale: self.float_arc(&s.scale, 1.0, &inner("scale"))?,
            },
            TextureDesc::Mix(m) => Texture::Mix {
                tex1: self.color_arc(&m.tex1, 0.0, &inner("tex1"))?,
                tex2: self.color_arc(&m.tex2, 1.0, &inner("tex2"))?,
                amount: self.float_arc(&m.amount, 0.5, &inner("amount"))?,
            },
            TextureDesc::DirectionMix(m) => Texture::direction_mix(
                self.color_arc(&m.tex1, 0.0, &inner("tex1"))?,
                self.color_arc(&m.tex2, 1.0, &inner("tex2"))?,
                m.dir.map_or(Vec3::Y, Vec3::from),
                &Transform::IDENTITY,
            )?,
            TextureDesc::Checkerboard(c) => {
                let (t1, t2) =
                    (self.color_arc(&c.tex1, 1.0, &inner("tex1"))?, self.color_arc(&c.tex2, 0.0, &inner("tex2"))?);
                match checkerboard_space(c).map_err(|e| format!("texture \"{name}\": {e}"))? {
                    Ok(m) => Texture::checkerboard(m, t1, t2),
                    Err(t) => Texture::checkerboard_3d(&t, t1, t2),
                }
            }
            TextureDesc::Bilerp(b) => {
                let m = mapping(&b.mapping).map_err(|e| format!("texture \"{name}\": {e}"))?;
                let mut v = [Color::ZERO; 4];
                for (slot, (key, value, d)) in v.iter_mut().zip(corners(b)) {
                    *slot = match value {
                        None => Color::splat(d),
                        Some(TexValue::Number(x)) => Color::splat(*x),
                        Some(TexValue::Rgb(c)) => Color::from_array(*c),
                        Some(TexValue::Name(_)) => {
                            return Err(format!("{}: a corner is a number or a colour, not a texture", inner(key)))
                        }
                    };
                }
                Texture::bilerp(m, v[0], v[1], v[2], v[3])
            }
            TextureDesc::Constant(c) => self.color(&c.value, &inner("value"))?,
            // A number is a grey.
            TextureDesc::Step(t) => Texture::Scale {
                tex: Arc::new(Texture::Constant(Color::ONE)),
                scale: Arc::new(FloatTexture::Step {
                    texture: self.float_arc(&Some(t.texture.clone()), 0.0, &inner("texture"))?,
                    threshold: t.threshold.map_or(0.5, Finite::get),
                }),
            },
            TextureDesc::Checker(c) => {
                Texture::Checker { even: c.even.into(), odd: c.odd.into(), scale: c.scale.get() }
            }
            TextureDesc::VertexColor(_) => Texture::VertexColor,
            // The alpha as a grey.
            TextureDesc::VertexAlpha(_) => Texture::Scale {
                tex: Arc::new(Texture::Constant(Color::ONE)),
                scale: Arc::new(FloatTexture::VertexAlpha),
            },
            TextureDesc::Product(p) => Texture::product(
                self.color_arc(&Some(p.tex1.clone()), 1.0, &inner("tex1"))?,
                self.color_arc(&Some(p.tex2.clone()), 1.0, &inner("tex2"))?,
            ),
        };
        let t = Arc::new(t);
        self.colors.insert(name.to_owned(), Arc::clone(&t));
        Ok(t)
    }

    /// The texture `name` as a number.
    pub fn float_named(&mut self, name: &str, what: &str) -> Result<Arc<FloatTexture>, String> {
        if let Some(t) = self.floats.get(name) {
            return Ok(Arc::clone(t));
        }
        let Some(desc) = self.textures().get(name) else {
            return Err(format!("`{what}`: {}", self.undefined(name)));
        };
        let inner = |key: &str| format!("texture \"{name}\" `{key}`");
        let t = match desc {
            TextureDesc::Image(_) => FloatTexture::Image(self.image(name)?),
            TextureDesc::Scale(s) => FloatTexture::Scale {
                tex: self.float_arc(&s.tex, 1.0, &inner("tex"))?,
                scale: self.float_arc(&s.scale, 1.0, &inner("scale"))?,
            },
            TextureDesc::Mix(m) => FloatTexture::Mix {
                tex1: self.float_arc(&m.tex1, 0.0, &inner("tex1"))?,
                tex2: self.float_arc(&m.tex2, 1.0, &inner("tex2"))?,
                amount: self.float_arc(&m.amount, 0.5, &inner("amount"))?,
            },
            TextureDesc::DirectionMix(m) => FloatTexture::direction_mix(
                self.float_arc(&m.tex1, 0.0, &inner("tex1"))?,
                self.float_arc(&m.tex2, 1.0, &inner("tex2"))?,
                m.dir.map_or(Vec3::Y, Vec3::from),
                &Transform::IDENTITY,
            )?,
            TextureDesc::Checkerboard(c) => {
                let (t1, t2) =
                    (self.float_arc(&c.tex1, 1.0, &inner("tex1"))?, self.float_arc(&c.tex2, 0.0, &inner("tex2"))?);
                match checkerboard_space(c).map_err(|e| format!("texture \"{name}\": {e}"))? {
                    Ok(m) => FloatTexture::checkerboard(m, t1, t2),
                    Err(t) => FloatTexture::checkerboard_3d(&t, t1, t2),
                }
            }
            TextureDesc::Bilerp(b) => {
                let m = mapping(&b.mapping).map_err(|e| format!("texture \"{name}\": {e}"))?;
                let mut v = [0.0; 4];
                for (slot, (key, value, d)) in v.iter_mut().zip(corners(b)) {
                    *slot = match value {
                        None => d,
                        Some(TexValue::Number(x)) => *x,
                        Some(_) => {
                            return Err(format!(
                                "{}: `{what}` needs a number, so the corners must be numbers",
                                inner(key)
                            ))
                        }
                    };
                }
                FloatTexture::bilerp(m, v[0], v[1], v[2], v[3])
            }
            TextureDesc::Constant(c) => self.float(&c.value, &inner("value"))?,
            TextureDesc::Step(t) => FloatTexture::Step {
                texture: self.float_arc(&Some(t.texture.clone()), 0.0, &inner("texture"))?,
                threshold: t.threshold.map_or(0.5, Finite::get),
            },
            TextureDesc::Checker(_) => {
                return Err(format!(
                    "`{what}` needs a number, but texture \"{name}\" is a `checker`, which has colours"
                ))
            }
            TextureDesc::VertexColor(_) => {
                return Err(format!(
                    "`{what}` needs a number, but texture \"{name}\" is a `vertex_color`, which is a colour \
                     (`vertex_alpha` is the vertex colour's alpha)"
                ))
            }
            TextureDesc::VertexAlpha(_) => FloatTexture::VertexAlpha,
            TextureDesc::Product(p) => FloatTexture::scale(
                self.float_arc(&Some(p.tex1.clone()), 1.0, &inner("tex1"))?,
                self.float_arc(&Some(p.tex2.clone()), 1.0, &inner("tex2"))?,
            ),
        };
        let t = Arc::new(t);
        self.floats.insert(name.to_owned(), Arc::clone(&t));
        Ok(t)
    }
}

/// The four corners of a bilerp with their keys and defaults.
fn corners(b: &BilerpTextureDesc) -> [(&'static str, &Option<TexValue>, f32); 4] {
    [("v00", &b.v00, 0.0), ("v01", &b.v01, 1.0), ("v10", &b.v10, 0.0), ("v11", &b.v11, 1.0)]
}

/// A checkerboard's squares: `Ok(mapping)` in 2D, `Err(world_from_texture)`
/// in 3D.
fn checkerboard_space(c: &CheckerboardTextureDesc) -> Result<Result<TextureMapping, Transform>, String> {
    match c.dimension.unwrap_or(2) {
        2 if c.transform.is_empty() => Ok(Ok(mapping(&c.mapping)?)),
        2 => Err("`transform` is for a 3D checkerboard (`dimension = 3`); a 2D one takes a `mapping`".to_owned()),
        3 if c.mapping.is_none() => Ok(Err(transform_of(&c.transform)?)),
        3 => Err("`mapping` is for a 2D checkerboard; a 3D one (`dimension = 3`) takes a `transform`".to_owned()),
        d => Err(format!("`dimension` must be 2 or 3, got {d}")),
    }
}

/// The texture's wrap mode for a scene file's.
fn wrap_mode(w: WrapDesc) -> WrapMode {
    match w {
        WrapDesc::Repeat => WrapMode::Repeat,
        WrapDesc::Clamp => WrapMode::Clamp,
        WrapDesc::Black => WrapMode::Black,
        WrapDesc::MirroredRepeat => WrapMode::MirroredRepeat,
    }
}
