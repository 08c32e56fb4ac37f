//! `[materials.NAME.KIND]` tables.

use super::super::values::*;
use super::{kinds_list, one, positive_one, TexValue};
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

/// A material: `[materials.NAME.KIND]` with one kind, and optionally a
/// bump map (`displacement`) or a normal map (`normal_map`) beside it.
#[derive(Clone, Debug)]
pub struct MaterialDesc {
    /// The kind and its keys.
    pub kind: MaterialKindDesc,
    /// A bump map: a height (world units along the normal), a number or a
    /// texture name.
    pub displacement: Option<TexValue>,
    /// A tangent-space normal map: an image file relative to the scene file.
    pub normal_map: Option<String>,
    /// Scale of the normal map's tangent-plane components (glTF's
    /// `normalTexture.scale`; default 1).
    pub normal_scale: Option<f32>,
}

impl From<MaterialKindDesc> for MaterialDesc {
    fn from(kind: MaterialKindDesc) -> Self {
        Self { kind, displacement: None, normal_map: None, normal_scale: None }
    }
}

/// The kind of a material and its keys.
#[derive(Clone, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MaterialKindDesc {
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
    /// A thin pane of glass.
    ThinDielectric(ThinDielectricDesc),
    /// Lambertian reflection and transmission.
    DiffuseTransmission(DiffuseTransmissionDesc),
    /// pbrt-v4's coated diffuse.
    CoatedDiffuse(CoatedDiffuseDesc),
    /// pbrt-v4's coated conductor.
    CoatedConductor(CoatedConductorDesc),
    /// One of two materials, chosen per hit.
    Mix(MixMaterialDesc),
    /// No surface (the boundary of a medium).
    Interface(InterfaceDesc),
    /// glTF 2.0's metallic-roughness material.
    MetallicRoughness(MetallicRoughnessDesc),
}

/// Keys of glTF 2.0's metallic-roughness material (what `lucent convert`
/// writes for a glTF file's materials). Each key is a number or colour, or
/// the name of a texture; glTF's factors that multiply a colour texture
/// have keys of their own.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MetallicRoughnessDesc {
    /// Base colour (default white).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_color: Option<TexValue>,
    /// Multiplies a `base_color` texture (default white).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_color_factor: Option<Rgb>,
    /// Metalness, 0 to 1 (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub metallic: Option<TexValue>,
    /// Perceptual roughness, 0 to 1, GGX α = roughness² (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness: Option<TexValue>,
    /// Index of refraction (default 1.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ior: Option<Positive>,
    /// Strength of the dielectric's specular reflection (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular: Option<TexValue>,
    /// Colour of the dielectric's specular reflection (default white).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular_color: Option<TexValue>,
    /// Multiplies a `specular_color` texture (default white).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular_color_factor: Option<Rgb>,
    /// Fraction of the dielectric part transmitted (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transmission: Option<TexValue>,
    /// Transmission through a thin wall, without refraction (default
    /// true); false: refraction by `ior`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thin: Option<bool>,
    /// Strength of a clear coat (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clearcoat: Option<TexValue>,
    /// Perceptual roughness of the coat (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clearcoat_roughness: Option<TexValue>,
    /// Colour of the sheen (default black: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sheen_color: Option<TexValue>,
    /// Multiplies a `sheen_color` texture (default white).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sheen_color_factor: Option<Rgb>,
    /// Perceptual roughness of the sheen (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sheen_roughness: Option<TexValue>,
}

/// Keys of a thin dielectric.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ThinDielectricDesc {
    /// Index of refraction (default 1.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<Positive>,
}

/// Keys of a diffuse transmitter.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DiffuseTransmissionDesc {
    /// Reflectance (default 0.25).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reflectance: Option<TexValue>,
    /// Transmittance (default 0.25).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transmittance: Option<TexValue>,
    /// Scale of both (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<NonNegative>,
}

/// Keys of a coated diffuse material.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CoatedDiffuseDesc {
    /// Albedo of the base (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reflectance: Option<TexValue>,
    /// Roughness of the coat, both directions (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness: Option<TexValue>,
    /// Roughness along ∂p/∂u (default `roughness`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u_roughness: Option<TexValue>,
    /// Roughness along ∂p/∂v (default `roughness`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_roughness: Option<TexValue>,
    /// Roughness is pbrt's (α = √roughness) rather than α (default false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub remap_roughness: bool,
    /// Thickness of the medium between coat and base (default 0.01).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<TexValue>,
    /// Index of refraction of the coat (default 1.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<Positive>,
    /// Scattering albedo of the medium (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub albedo: Option<TexValue>,
    /// Henyey–Greenstein asymmetry of the medium (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub g: Option<TexValue>,
    /// Most scattering events per random walk (default 10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_depth: Option<u32>,
    /// Random walks per evaluation (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub n_samples: Option<u32>,
}

/// Keys of a coated conductor.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CoatedConductorDesc {
    /// Roughness of the coat, both directions (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interface_roughness: Option<TexValue>,
    /// Coat roughness along ∂p/∂u.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interface_u_roughness: Option<TexValue>,
    /// Coat roughness along ∂p/∂v.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interface_v_roughness: Option<TexValue>,
    /// Index of refraction of the coat (default 1.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interface_eta: Option<Positive>,
    /// Conductor's index of refraction, real part (default copper).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_eta: Option<TexValue>,
    /// Conductor's index of refraction, imaginary part (default copper).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_k: Option<TexValue>,
    /// Conductor's reflectance (pbrt-v4's `reflectance`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_reflectance: Option<TexValue>,
    /// Conductor's Schlick reflectance at normal incidence.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_color: Option<TexValue>,
    /// A named metal for the conductor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub metal: Option<MetalDesc>,
    /// Roughness of the conductor, both directions (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_roughness: Option<TexValue>,
    /// Conductor roughness along ∂p/∂u.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_u_roughness: Option<TexValue>,
    /// Conductor roughness along ∂p/∂v.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_v_roughness: Option<TexValue>,
    /// Both roughnesses are pbrt's (α = √roughness) (default false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub remap_roughness: bool,
    /// Thickness of the medium (default 0.01).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<TexValue>,
    /// Scattering albedo of the medium (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub albedo: Option<TexValue>,
    /// Henyey–Greenstein asymmetry (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub g: Option<TexValue>,
    /// Most scattering events per random walk (default 10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_depth: Option<u32>,
    /// Random walks per evaluation (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub n_samples: Option<u32>,
}

/// Keys of a mix of two materials.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MixMaterialDesc {
    /// The two materials' names.
    pub materials: [String; 2],
    /// Probability of the second (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amount: Option<TexValue>,
}

/// An interface has no keys.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InterfaceDesc {}

/// Keys of a diffuse material.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DiffuseDesc {
    /// Albedo, each channel ≤ 1 (default white), or give `checker`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<TexValue>,
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

/// Keys of a conductor: give `color`, or `eta` and `k`, or `reflectance`,
/// or `metal`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ConductorDesc {
    /// Reflectance at normal incidence (Schlick's approximation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<TexValue>,
    /// Real part of the complex index of refraction, per channel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<TexValue>,
    /// Imaginary part (absorption), per channel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k: Option<TexValue>,
    /// pbrt-v4's `reflectance`: exact Fresnel with this reflectance at
    /// normal incidence.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reflectance: Option<TexValue>,
    /// A named metal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub metal: Option<MetalDesc>,
    /// GGX roughness α from 0 (mirror) to 1 (default 0), both directions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness: Option<TexValue>,
    /// Roughness along ∂p/∂u (default `roughness`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u_roughness: Option<TexValue>,
    /// Roughness along ∂p/∂v (default `roughness`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_roughness: Option<TexValue>,
    /// Roughness is pbrt's (α = √roughness) rather than α (default false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub remap_roughness: bool,
}

/// Keys of a dielectric.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DielectricDesc {
    /// Index of refraction (default 1.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<Positive>,
    /// GGX roughness α from 0 (smooth) to 1 (default 0), both directions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness: Option<TexValue>,
    /// Roughness along ∂p/∂u (default `roughness`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u_roughness: Option<TexValue>,
    /// Roughness along ∂p/∂v (default `roughness`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_roughness: Option<TexValue>,
    /// Roughness is pbrt's (α = √roughness) rather than α (default false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub remap_roughness: bool,
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
    pub color: Option<TexValue>,
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

/// The kinds of material, for messages.
const KINDS: &[&str] = &[
    "matte",
    "phong",
    "diffuse",
    "conductor",
    "dielectric",
    "plastic",
    "thin_dielectric",
    "diffuse_transmission",
    "coated_diffuse",
    "coated_conductor",
    "mix",
    "interface",
    "metallic_roughness",
];

/// A material is a table with exactly one kind, plus the optional
/// `displacement` and `normal_map`. Written by hand (rather than derived)
/// so that a second kind or a missing kind gets a message that says so.
impl<'de> Deserialize<'de> for MaterialDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct KindVisitor;
        impl<'de> Visitor<'de> for KindVisitor {
            type Value = MaterialDesc;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "a material table with one kind: {}", kinds_list(KINDS))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<MaterialDesc, A::Error> {
                let (mut kind, mut displacement, mut normal_map) = (None::<(String, MaterialKindDesc)>, None, None);
                let mut normal_scale = None;
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "displacement" if displacement.is_none() => displacement = Some(map.next_value()?),
                        "normal_map" if normal_map.is_none() => normal_map = Some(map.next_value::<String>()?),
                        "normal_scale" if normal_scale.is_none() => {
                            normal_scale = Some(map.next_value::<Finite>()?.get())
                        }
                        "displacement" | "normal_map" | "normal_scale" => {
                            return Err(A::Error::custom(format!("duplicate key `{key}`")))
                        }
                        _ => {
                            if let Some((first, _)) = &kind {
                                return Err(A::Error::custom(format!(
                                    "a material has exactly one kind, but `{key}` follows `{first}`; give each kind its own material name"
                                )));
                            }
                            let k = match key.as_str() {
                                "matte" => MaterialKindDesc::Matte(map.next_value()?),
                                "phong" => MaterialKindDesc::Phong(map.next_value()?),
                                "diffuse" => MaterialKindDesc::Diffuse(map.next_value()?),
                                "conductor" => MaterialKindDesc::Conductor(map.next_value()?),
                                "dielectric" => MaterialKindDesc::Dielectric(map.next_value()?),
                                "plastic" => MaterialKindDesc::Plastic(map.next_value()?),
                                "thin_dielectric" => MaterialKindDesc::ThinDielectric(map.next_value()?),
                                "diffuse_transmission" => MaterialKindDesc::DiffuseTransmission(map.next_value()?),
                                "coated_diffuse" => MaterialKindDesc::CoatedDiffuse(map.next_value()?),
                                "coated_conductor" => MaterialKindDesc::CoatedConductor(map.next_value()?),
                                "mix" => MaterialKindDesc::Mix(map.next_value()?),
                                "interface" => MaterialKindDesc::Interface(map.next_value()?),
                                "metallic_roughness" => MaterialKindDesc::MetallicRoughness(map.next_value()?),
                                _ => {
                                    return Err(A::Error::custom(format!(
                                        "unknown material kind `{key}`: expected {} (and optionally `displacement`, `normal_map`, `normal_scale`)",
                                        kinds_list(KINDS)
                                    )))
                                }
                            };
                            kind = Some((key, k));
                        }
                    }
                }
                let Some((_, kind)) = kind else {
                    return Err(A::Error::custom(format!("a material needs a kind: {}", kinds_list(KINDS))));
                };
                if normal_scale.is_some() && normal_map.is_none() {
                    return Err(A::Error::custom("`normal_scale` scales a `normal_map`, and there is none"));
                }
                Ok(MaterialDesc { kind, displacement, normal_map, normal_scale })
            }
        }
        d.deserialize_map(KindVisitor)
    }
}

/// Written as the kind's table with `displacement` and `normal_map`
/// beside it.
impl Serialize for MaterialDesc {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let n = 1
            + self.displacement.is_some() as usize
            + self.normal_map.is_some() as usize
            + self.normal_scale.is_some() as usize;
        let mut map = s.serialize_map(Some(n))?;
        if let Some(d) = &self.displacement {
            map.serialize_entry("displacement", d)?;
        }
        if let Some(n) = &self.normal_map {
            map.serialize_entry("normal_map", n)?;
        }
        if let Some(k) = &self.normal_scale {
            map.serialize_entry("normal_scale", k)?;
        }
        match &self.kind {
            MaterialKindDesc::Matte(m) => map.serialize_entry("matte", m)?,
            MaterialKindDesc::Phong(m) => map.serialize_entry("phong", m)?,
            MaterialKindDesc::Diffuse(m) => map.serialize_entry("diffuse", m)?,
            MaterialKindDesc::Conductor(m) => map.serialize_entry("conductor", m)?,
            MaterialKindDesc::Dielectric(m) => map.serialize_entry("dielectric", m)?,
            MaterialKindDesc::Plastic(m) => map.serialize_entry("plastic", m)?,
            MaterialKindDesc::ThinDielectric(m) => map.serialize_entry("thin_dielectric", m)?,
            MaterialKindDesc::DiffuseTransmission(m) => map.serialize_entry("diffuse_transmission", m)?,
            MaterialKindDesc::CoatedDiffuse(m) => map.serialize_entry("coated_diffuse", m)?,
            MaterialKindDesc::CoatedConductor(m) => map.serialize_entry("coated_conductor", m)?,
            MaterialKindDesc::Mix(m) => map.serialize_entry("mix", m)?,
            MaterialKindDesc::Interface(m) => map.serialize_entry("interface", m)?,
            MaterialKindDesc::MetallicRoughness(m) => map.serialize_entry("metallic_roughness", m)?,
        }
        map.end()
    }
}

/// Keys of a matte material.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MatteDesc {
    /// Colour (default white); or use `checker`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<TexValue>,
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
    pub color: Option<TexValue>,
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
