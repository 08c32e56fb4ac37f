//! `[materials.NAME.KIND]` tables.

use super::super::values::*;
use super::{one, positive_one};
use serde::{
    de::{Error as _, Visitor},
    Deserialize, Deserializer, Serialize,
};
use std::fmt;

/// A checkerboard colour.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CheckerDesc {
    /// Colour of the square at the origin.
    pub even: Rgb,
    /// The other colour.
    pub odd: Rgb,
    /// Side of a square in texture units (default 1).
    #[serde(default = "positive_one")]
    pub scale: Positive,
}

/// A material: `[materials.NAME.matte]` or `[materials.NAME.phong]`.
#[derive(Clone, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MaterialDesc {
    /// Lambertian.
    Matte(MatteDesc),
    /// Phong with mirror reflection.
    Phong(PhongDesc),
    /// Lambertian (path integrator).
    Diffuse(DiffuseDesc),
    /// Metal.
    Conductor(ConductorDesc),
    /// Glass.
    Dielectric(DielectricDesc),
    /// Diffuse under a clear coat.
    Plastic(PlasticDesc),
}

/// Keys of a diffuse material.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DiffuseDesc {
    /// Albedo, each channel ≤ 1 (default white), or give `checker`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgb>,
    /// A checkerboard albedo.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checker: Option<CheckerDesc>,
}

/// Named conductors with measured complex indices of refraction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MetalDesc {
    /// Gold.
    Gold,
    /// Silver.
    Silver,
    /// Copper.
    Copper,
    /// Aluminium.
    Aluminium,
}

/// Keys of a conductor: give `color`, or `eta` and `k`, or `metal`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ConductorDesc {
    /// Reflectance at normal incidence (Schlick's approximation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgb>,
    /// Real part of the complex index of refraction, per channel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<Rgb>,
    /// Imaginary part (absorption), per channel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k: Option<Rgb>,
    /// A named metal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub metal: Option<MetalDesc>,
    /// GGX roughness α from 0 (mirror) to 1 (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness: Option<NonNegative>,
}

/// Keys of a dielectric.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DielectricDesc {
    /// Index of refraction (default 1.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<Positive>,
    /// GGX roughness α from 0 (smooth) to 1 (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness: Option<NonNegative>,
    /// Colour of transmitted light (default white).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tint: Option<Rgb>,
}

/// Keys of a plastic.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlasticDesc {
    /// Albedo of the diffuse base (default white), or give `checker`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgb>,
    /// A checkerboard albedo.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checker: Option<CheckerDesc>,
    /// Index of refraction of the coat (default 1.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<Positive>,
    /// GGX roughness α of the coat from 0 (smooth) to 1 (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness: Option<NonNegative>,
}

/// A material is a table with exactly one key, its kind. Written by hand
/// (rather than derived) so that a second kind or a missing kind gets a
/// message that says so.
impl<'de> Deserialize<'de> for MaterialDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct KindVisitor;
        const KINDS: &[&str] = &["matte", "phong", "diffuse", "conductor", "dielectric", "plastic"];
        impl<'de> Visitor<'de> for KindVisitor {
            type Value = MaterialDesc;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a material table with one kind: `matte`, `phong`, `diffuse`, `conductor`, `dielectric` or `plastic`")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<MaterialDesc, A::Error> {
                let Some(kind) = map.next_key::<String>()? else {
                    return Err(A::Error::custom(
                        "a material needs a kind: `matte`, `phong`, `diffuse`, `conductor`, `dielectric` or `plastic`",
                    ));
                };
                let material = match kind.as_str() {
                    "matte" => MaterialDesc::Matte(map.next_value()?),
                    "phong" => MaterialDesc::Phong(map.next_value()?),
                    "diffuse" => MaterialDesc::Diffuse(map.next_value()?),
                    "conductor" => MaterialDesc::Conductor(map.next_value()?),
                    "dielectric" => MaterialDesc::Dielectric(map.next_value()?),
                    "plastic" => MaterialDesc::Plastic(map.next_value()?),
                    _ => return Err(A::Error::unknown_variant(&kind, KINDS)),
                };
                if let Some(second) = map.next_key::<String>()? {
                    return Err(A::Error::custom(format!(
                        "a material has exactly one kind, but `{second}` follows `{kind}`; give each kind its own material name"
                    )));
                }
                Ok(material)
            }
        }
        d.deserialize_map(KindVisitor)
    }
}

/// Keys of a matte material.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MatteDesc {
    /// Colour (default white); or use `checker`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgb>,
    /// A checkerboard instead of a plain colour.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checker: Option<CheckerDesc>,
    /// Diffuse coefficient (default 1).
    #[serde(default = "one")]
    pub kd: NonNegative,
    /// Ambient coefficient (default: kd).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ka: Option<NonNegative>,
}

/// Keys of a Phong material.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PhongDesc {
    /// Colour (default white); or use `checker`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgb>,
    /// A checkerboard instead of a plain colour.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checker: Option<CheckerDesc>,
    /// Diffuse coefficient (default 1).
    #[serde(default = "one")]
    pub kd: NonNegative,
    /// Ambient coefficient (default: kd).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ka: Option<NonNegative>,
    /// Specular coefficient (default 0.5).
    #[serde(default = "half")]
    pub ks: NonNegative,
    /// Phong exponent (default 20).
    #[serde(default = "twenty")]
    pub exponent: NonNegative,
    /// Mirror reflectivity (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kr: Option<NonNegative>,
}

fn half() -> NonNegative {
    NonNegative(0.5)
}
fn twenty() -> NonNegative {
    NonNegative(20.0)
}
