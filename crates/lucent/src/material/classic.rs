//! The classic materials (matte and Phong) and the reflection model the
//! Whitted integrator evaluates.

use crate::color::Color;
use crate::geometry::{reflect, Vec3};
use crate::texture::Texture;

/// The parameters of the classic matte and Phong materials.
#[derive(Clone, Debug, PartialEq)]
pub struct ClassicMaterial {
    /// Surface colour (albedo).
    pub color: Texture,
    /// Ambient coefficient.
    pub ka: f32,
    /// Diffuse coefficient.
    pub kd: f32,
    /// Specular coefficient of the Phong lobe (0 for matte).
    pub ks: f32,
    /// Phong exponent.
    pub exponent: f32,
    /// Mirror reflectivity (0 for matte).
    pub kr: f32,
}

/// The classic reflection model evaluated at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongBsdf {
    /// Reflectance of the ambient light.
    pub ambient: Color,
    /// Lambertian BRDF value `kd · albedo / π`.
    pub diffuse: Color,
    /// Phong specular coefficient.
    pub ks: f32,
    /// Phong exponent.
    pub exponent: f32,
    /// Mirror reflectivity, per channel.
    pub kr: Color,
}

impl PhongBsdf {
    /// BRDF value for light arriving from `wi` and leaving towards `wo`,
    /// both unit and pointing away from the surface, with unit normal `n`.
    #[inline]
    pub fn f(&self, wo: Vec3, wi: Vec3, n: Vec3) -> Color {
        let mut f = self.diffuse;
        if self.ks > 0.0 {
            let r = reflect(wi, n);
            let cos_r = r.dot(wo);
            if cos_r > 0.0 {
                f += Color::splat(self.ks * cos_r.powf(self.exponent));
            }
        }
        f
    }
}
