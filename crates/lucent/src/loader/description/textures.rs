//! `[textures.NAME.KIND]` tables and texture-valued parameters
//! ([`TexValue`]): pbrt-v4's texture classes (see [`crate::texture`]) in
//! the scene file's syntax.
//!
//! A texture table has no value type: the same `[textures.NAME]` serves a
//! colour parameter (`color`, `reflectance`, …) and a number parameter
//! (`roughness`, `amount`, `displacement`, …); it is built as whichever the
//! parameter needs (an image file is still read once).

use super::super::values::*;
use super::{CheckerDesc, TransformOp};
use serde::{
    de::{Error as _, MapAccess, SeqAccess, Visitor},
    Deserialize, Deserializer, Serialize,
};
use std::fmt;

/// A parameter that may vary over a surface: a number, an RGB colour, or
/// the name of a `[textures.NAME]` table.
///
/// A number given for a colour is a grey; a colour given for a number is
/// an error. Colours are three finite numbers ≥ 0, numbers any finite
/// number (the parameter checks its own range).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum TexValue {
    /// A constant number (or grey).
    Number(f32),
    /// A constant colour.
    Rgb([f32; 3]),
    /// A texture named in `[textures]`.
    Name(String),
}

impl From<f32> for TexValue {
    fn from(v: f32) -> Self {
        TexValue::Number(v)
    }
}

impl From<Rgb> for TexValue {
    fn from(c: Rgb) -> Self {
        TexValue::Rgb(c.0)
    }
}

/// Written by hand (not `#[serde(untagged)]`) so that a wrong value says
/// what is accepted instead of "did not match any variant".
impl<'de> Deserialize<'de> for TexValue {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        const EXPECTING: &str = "a number, a colour [r, g, b] or the name of a texture in [textures]";
        fn number<E: serde::de::Error>(v: f64) -> Result<TexValue, E> {
            if v.is_finite() && (v as f32).is_finite() {
                Ok(TexValue::Number(v as f32))
            } else {
                Err(E::custom(format!("expected a finite number, got {v}")))
            }
        }
        impl<'de> Visitor<'de> for V {
            type Value = TexValue;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(EXPECTING)
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<TexValue, E> {
                number(v)
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<TexValue, E> {
                number(v as f64)
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<TexValue, E> {
                number(v as f64)
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<TexValue, E> {
                if v.is_empty() {
                    return Err(E::custom("a texture name must not be empty"));
                }
                Ok(TexValue::Name(v.to_owned()))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<TexValue, A::Error> {
                let mut c = Vec::with_capacity(3);
                while let Some(v) = seq.next_element::<Finite>()? {
                    if c.len() == 3 {
                        return Err(A::Error::custom("expected a colour [r, g, b] of three numbers, got more"));
                    }
                    c.push(v.get());
                }
                if c.len() != 3 {
                    return Err(A::Error::custom(format!(
                        "expected a colour [r, g, b] of three numbers, got {}",
                        c.len()
                    )));
                }
                if c.iter().any(|&v| v < 0.0) {
                    return Err(A::Error::custom("expected a colour [r, g, b] of finite numbers ≥ 0"));
                }
                Ok(TexValue::Rgb([c[0], c[1], c[2]]))
            }
        }
        d.deserialize_any(V)
    }
}

/// How an image is filtered (pbrt-v4's `filter`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FilterFunctionDesc {
    /// Nearest texel.
    Point,
    /// Bilinear in one MIP level (the default).
    Bilinear,
    /// Bilinear in two levels, blended.
    Trilinear,
    /// Elliptically weighted average.
    Ewa,
}

/// What a lookup outside the image reads (pbrt-v4's `wrap`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WrapDesc {
    /// The image tiles the plane (the default).
    Repeat,
    /// The edge texels extend outwards.
    Clamp,
    /// Black outside.
    Black,
    /// Tiles mirrored every other time (glTF's `MIRRORED_REPEAT`).
    MirroredRepeat,
}

/// One channel of an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ChannelDesc {
    /// Red.
    R,
    /// Green.
    G,
    /// Blue.
    B,
    /// Alpha.
    A,
}

/// The wrap of an image texture: one mode for both axes (`wrap =
/// "clamp"`) or one per axis (`wrap = { s = "repeat", t = "clamp" }`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(untagged)]
pub enum WrapSpec {
    /// The same mode across and down.
    Both(WrapDesc),
    /// `s` across, `t` down.
    Axes {
        /// Across the image.
        s: WrapDesc,
        /// Down the image.
        t: WrapDesc,
    },
}

/// A 2D texture mapping: `{ uv = { … } }`, `{ spherical = { … } }`,
/// `{ cylindrical = { … } }` or `{ planar = { … } }`. The `transform` of
/// the last three places texture space in the world, like an object's
/// (pbrt-v4: the CTM when the texture is defined).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MappingDesc {
    /// `(s, t) = (su·u + du, sv·v + dv)`.
    Uv {
        /// Scale of `u` (default 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        su: Option<Finite>,
        /// Scale of `v` (default 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        sv: Option<Finite>,
        /// Offset of `s` (default 0).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        du: Option<Finite>,
        /// Offset of `t` (default 0).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        dv: Option<Finite>,
    },
    /// `(s, t) = (m[0]·u + m[1]·v + m[2], m[3]·u + m[4]·v + m[5])`: any
    /// affine map of `(u, v)` (what glTF's textures and
    /// `KHR_texture_transform` convert to).
    Affine {
        /// The two rows of the 2×3 matrix.
        m: [Finite; 6],
        /// Which texture-coordinate set `(u, v)` is: 0 (the default) or 1,
        /// a mesh's second set (glTF's `TEXCOORD_1`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        uv_set: Option<u8>,
    },
    /// Spherical coordinates about the texture-space origin.
    Spherical {
        /// Texture space to world (default identity).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        transform: Vec<TransformOp>,
    },
    /// Cylindrical coordinates about the texture-space z axis.
    Cylindrical {
        /// Texture space to world (default identity).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        transform: Vec<TransformOp>,
    },
    /// `(s, t) = (du + p·v1, dv + p·v2)`, `p` in texture space.
    Planar {
        /// Texture space to world (default identity).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        transform: Vec<TransformOp>,
        /// The `s` direction (default `[1, 0, 0]`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        v1: Option<Vec3Desc>,
        /// The `t` direction (default `[0, 1, 0]`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        v2: Option<Vec3Desc>,
        /// Offset of `s` (default 0).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        du: Option<Finite>,
        /// Offset of `t` (default 0).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        dv: Option<Finite>,
    },
}

/// `[textures.NAME.image]`: an image file (pbrt-v4's `imagemap`).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ImageTextureDesc {
    /// The file, relative to the scene file.
    pub file: String,
    /// The mapping (default `uv`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mapping: Option<MappingDesc>,
    /// The filter (default bilinear).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<FilterFunctionDesc>,
    /// Largest EWA anisotropy (default 8).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_anisotropy: Option<Positive>,
    /// Outside the image (default repeat).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wrap: Option<WrapSpec>,
    /// A float texture's one channel: `"r"`, `"g"`, `"b"` or `"a"`
    /// (default: grey, the mean of RGB, or alpha where the image has it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub channel: Option<ChannelDesc>,
    /// `"srgb"`, `"linear"` or `"gamma G"` (default: sRGB for PNG files,
    /// linear otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub encoding: Option<String>,
    /// Multiplies every value (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<Finite>,
    /// `1 − value`, clamped at 0 (default false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub invert: bool,
}

/// `[textures.NAME.scale]`: `tex × scale`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ScaleTextureDesc {
    /// The scaled value (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tex: Option<TexValue>,
    /// The factor, a number (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<TexValue>,
}

/// `[textures.NAME.mix]`: `(1 − amount)·tex1 + amount·tex2`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MixTextureDesc {
    /// Where `amount` is 0 (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tex1: Option<TexValue>,
    /// Where `amount` is 1 (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tex2: Option<TexValue>,
    /// The weight of `tex2`, a number (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amount: Option<TexValue>,
}

/// `[textures.NAME.direction_mix]`: `a·tex1 + (1 − a)·tex2`, `a = |n·dir|`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DirectionMixTextureDesc {
    /// Where the normal is along `dir` (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tex1: Option<TexValue>,
    /// Where the normal is perpendicular to `dir` (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tex2: Option<TexValue>,
    /// World-space direction (default `[0, 1, 0]`), normalised.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dir: Option<Direction>,
}

/// `[textures.NAME.checkerboard]`: pbrt-v4's filtered checkerboard.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CheckerboardTextureDesc {
    /// On even squares (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tex1: Option<TexValue>,
    /// On odd squares (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tex2: Option<TexValue>,
    /// 2 (squares of a mapping's `(s, t)`, the default) or 3 (unit cubes
    /// of texture space).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dimension: Option<u8>,
    /// The mapping of a 2D board (default `uv`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mapping: Option<MappingDesc>,
    /// Texture space to world, for a 3D board (default identity).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub transform: Vec<TransformOp>,
}

/// `[textures.NAME.bilerp]`: bilinear between four corner values.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BilerpTextureDesc {
    /// The mapping (default `uv`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mapping: Option<MappingDesc>,
    /// Value at `(0, 0)`, a number or colour (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v00: Option<TexValue>,
    /// Value at `(0, 1)` (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v01: Option<TexValue>,
    /// Value at `(1, 0)` (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v10: Option<TexValue>,
    /// Value at `(1, 1)` (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v11: Option<TexValue>,
}

/// `[textures.NAME.constant]`: one value everywhere.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ConstantTextureDesc {
    /// A number or a colour (or another texture's name).
    pub value: TexValue,
}

/// `[textures.NAME.step]`: 1 where `texture ≥ threshold`, else 0 (numbers
/// only; glTF's alpha cut-off).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StepTextureDesc {
    /// The texture compared (a number or a texture's name).
    pub texture: TexValue,
    /// The cut-off (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threshold: Option<Finite>,
}

/// `[textures.NAME.vertex_color]` or `[textures.NAME.vertex_alpha]`: a
/// mesh's interpolated vertex colour (its RGB, or its alpha as a number);
/// white, or 1, on surfaces without one. The table has no keys.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct VertexColorDesc {}

/// `[textures.NAME.product]`: `tex1 × tex2`, channel by channel.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ProductTextureDesc {
    /// The first factor (a number, a colour or a texture's name).
    pub tex1: TexValue,
    /// The second factor.
    pub tex2: TexValue,
}

/// A texture: `[textures.NAME.KIND]` with one kind.
#[derive(Clone, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TextureDesc {
    /// An image file.
    Image(ImageTextureDesc),
    /// A product.
    Scale(ScaleTextureDesc),
    /// A blend.
    Mix(MixTextureDesc),
    /// A blend by the normal's direction.
    DirectionMix(DirectionMixTextureDesc),
    /// pbrt-v4's checkerboard.
    Checkerboard(CheckerboardTextureDesc),
    /// Bilinear interpolation.
    Bilerp(BilerpTextureDesc),
    /// A constant.
    Constant(ConstantTextureDesc),
    /// lucent's `(u, v)` checker (colours only).
    Checker(CheckerDesc),
    /// A threshold (numbers only).
    Step(StepTextureDesc),
    /// A mesh's vertex colour.
    VertexColor(VertexColorDesc),
    /// A mesh's vertex alpha.
    VertexAlpha(VertexColorDesc),
    /// A product of two textures.
    Product(ProductTextureDesc),
}

/// The kinds of texture, for messages.
pub(crate) const TEXTURE_KINDS: &[&str] = &[
    "image",
    "scale",
    "mix",
    "direction_mix",
    "checkerboard",
    "bilerp",
    "constant",
    "checker",
    "step",
    "vertex_color",
    "vertex_alpha",
    "product",
];

pub(crate) fn kinds_list(kinds: &[&str]) -> String {
    let quoted: Vec<String> = kinds.iter().map(|k| format!("`{k}`")).collect();
    match quoted.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => quoted.join(""),
    }
}

/// One kind per table, with messages that say so (as for materials).
impl<'de> Deserialize<'de> for TextureDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct KindVisitor;
        impl<'de> Visitor<'de> for KindVisitor {
            type Value = TextureDesc;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "a texture table with one kind: {}", kinds_list(TEXTURE_KINDS))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<TextureDesc, A::Error> {
                let Some(kind) = map.next_key::<String>()? else {
                    return Err(A::Error::custom(format!("a texture needs a kind: {}", kinds_list(TEXTURE_KINDS))));
                };
                let texture = match kind.as_str() {
                    "image" => TextureDesc::Image(map.next_value()?),
                    "scale" => TextureDesc::Scale(map.next_value()?),
                    "mix" => TextureDesc::Mix(map.next_value()?),
                    "direction_mix" => TextureDesc::DirectionMix(map.next_value()?),
                    "checkerboard" => TextureDesc::Checkerboard(map.next_value()?),
                    "bilerp" => TextureDesc::Bilerp(map.next_value()?),
                    "constant" => TextureDesc::Constant(map.next_value()?),
                    "checker" => TextureDesc::Checker(map.next_value()?),
                    "step" => TextureDesc::Step(map.next_value()?),
                    "vertex_color" => TextureDesc::VertexColor(map.next_value()?),
                    "vertex_alpha" => TextureDesc::VertexAlpha(map.next_value()?),
                    "product" => TextureDesc::Product(map.next_value()?),
                    _ => return Err(A::Error::unknown_variant(&kind, TEXTURE_KINDS)),
                };
                if let Some(second) = map.next_key::<String>()? {
                    return Err(A::Error::custom(format!(
                        "a texture has exactly one kind, but `{second}` follows `{kind}`; give each kind its own texture name"
                    )));
                }
                Ok(texture)
            }
        }
        d.deserialize_map(KindVisitor)
    }
}
