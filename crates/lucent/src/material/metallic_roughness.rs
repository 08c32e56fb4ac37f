//! glTF 2.0's material: metallic-roughness with the Khronos material
//! extensions, as textures to evaluate at a hit. The scattering function
//! itself is [`MetallicRoughnessBxdf`]; this file only reads its parameters
//! off the textures, in the channels glTF assigns them (glTF 2.0 §3.9.2 and
//! the `KHR_materials_*` specifications).

use crate::bsdf::{Bxdf, MetallicRoughnessBxdf};
use crate::color::Color;
use crate::texture::{FloatTexture, Texture, TextureContext};

/// glTF 2.0's metallic-roughness material (see [`MetallicRoughnessBxdf`]
/// for the model). Each parameter is a factor times a texture, as glTF
/// gives it: colour textures are [`Texture`]s multiplied by their factor,
/// scalar ones [`FloatTexture`]s reading one channel of an image with the
/// factor folded into the image's `scale` (or a constant, without a
/// texture). `Default` gives glTF's defaults: white, metallic 1,
/// roughness 1, IOR 1.5, full specular, no transmission, coat or sheen.
///
/// ```
/// use lucent::color::Color;
/// use lucent::material::{Material, MetallicRoughnessMaterial};
/// let gold = MetallicRoughnessMaterial {
///     base_color_factor: Color::new(1.0, 0.766, 0.336),
///     roughness: 0.3.into(),
///     ..Default::default()
/// };
/// let m = Material::MetallicRoughness(Box::new(gold));
/// assert!(matches!(m.bxdf(Default::default()), lucent::bsdf::Bxdf::MetallicRoughness(_)));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct MetallicRoughnessMaterial {
    /// `baseColorFactor` (linear RGB; its alpha is the primitive's alpha
    /// cut-out, not the material's business).
    pub base_color_factor: Color,
    /// `baseColorTexture`'s RGB (sRGB-decoded), if any.
    pub base_color: Option<Texture>,
    /// `metallicFactor` × the blue channel of `metallicRoughnessTexture`.
    pub metallic: FloatTexture,
    /// `roughnessFactor` × its green channel: perceptual roughness, GGX
    /// `α = roughness²`.
    pub roughness: FloatTexture,
    /// `KHR_materials_ior` (1.5 without it).
    pub ior: f32,
    /// `KHR_materials_specular`: `specularFactor` × the alpha channel of
    /// `specularTexture` (1 without the extension).
    pub specular: FloatTexture,
    /// `specularColorFactor` (white without the extension).
    pub specular_color_factor: Color,
    /// `specularColorTexture`'s RGB, if any.
    pub specular_color: Option<Texture>,
    /// `KHR_materials_transmission`: `transmissionFactor` × the red channel
    /// of `transmissionTexture` (0 without the extension).
    pub transmission: FloatTexture,
    /// Whether transmission is through a thin wall (no refraction): true
    /// unless `KHR_materials_volume` gives a thickness above 0.
    pub thin: bool,
    /// `KHR_materials_clearcoat`: `clearcoatFactor` × the red channel of
    /// `clearcoatTexture` (0 without it).
    pub clearcoat: FloatTexture,
    /// `clearcoatRoughnessFactor` × the green channel of
    /// `clearcoatRoughnessTexture`.
    pub clearcoat_roughness: FloatTexture,
    /// `KHR_materials_sheen`: `sheenColorFactor` (black without it: no
    /// sheen).
    pub sheen_color_factor: Color,
    /// `sheenColorTexture`'s RGB, if any.
    pub sheen_color: Option<Texture>,
    /// `sheenRoughnessFactor` × the alpha channel of
    /// `sheenRoughnessTexture`.
    pub sheen_roughness: FloatTexture,
}

impl Default for MetallicRoughnessMaterial {
    fn default() -> Self {
        Self {
            base_color_factor: Color::ONE,
            base_color: None,
            metallic: FloatTexture::Constant(1.0),
            roughness: FloatTexture::Constant(1.0),
            ior: 1.5,
            specular: FloatTexture::Constant(1.0),
            specular_color_factor: Color::ONE,
            specular_color: None,
            transmission: FloatTexture::Constant(0.0),
            thin: true,
            clearcoat: FloatTexture::Constant(0.0),
            clearcoat_roughness: FloatTexture::Constant(0.0),
            sheen_color_factor: Color::ZERO,
            sheen_color: None,
            sheen_roughness: FloatTexture::Constant(0.0),
        }
    }
}

/// `factor × texture` (the factor alone without a texture), clamped to
/// [0, 1] per channel.
fn color(factor: Color, texture: &Option<Texture>, ctx: &TextureContext) -> Color {
    let c = match texture {
        Some(t) => factor * t.evaluate(ctx),
        None => factor,
    };
    c.clamp(Color::ZERO, Color::ONE)
}

/// A scalar parameter clamped to [0, 1].
fn unit(t: &FloatTexture, ctx: &TextureContext) -> f32 {
    t.evaluate(ctx).clamp(0.0, 1.0)
}

impl MetallicRoughnessMaterial {
    /// The BxDF with every texture evaluated at `ctx`.
    pub fn bxdf_at(&self, ctx: &TextureContext) -> Bxdf {
        let roughness = unit(&self.roughness, ctx);
        let clearcoat_roughness = unit(&self.clearcoat_roughness, ctx);
        let sheen_roughness = unit(&self.sheen_roughness, ctx);
        let sheen_color = color(self.sheen_color_factor, &self.sheen_color, ctx);
        Bxdf::MetallicRoughness(MetallicRoughnessBxdf {
            base_color: color(self.base_color_factor, &self.base_color, ctx),
            metallic: unit(&self.metallic, ctx),
            alpha: roughness * roughness,
            ior: self.ior,
            specular: unit(&self.specular, ctx),
            specular_color: self.specular_color_factor.max(Color::ZERO)
                * self.specular_color.as_ref().map_or(Color::ONE, |t| t.evaluate(ctx).max(Color::ZERO)),
            transmission: unit(&self.transmission, ctx),
            thin: self.thin,
            clearcoat: unit(&self.clearcoat, ctx),
            clearcoat_alpha: clearcoat_roughness * clearcoat_roughness,
            sheen_color,
            sheen_alpha: sheen_roughness * sheen_roughness,
        })
    }

    /// Whether the surface lets light through (transmission anywhere above
    /// 0): such a surface is no occluder that a shadow ray can ignore.
    pub fn transmits(&self) -> bool {
        self.transmission.as_constant() != Some(0.0)
    }
}
