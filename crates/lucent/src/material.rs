//! Materials: how a surface reflects light. A material describes the surface
//! only; what light reaches it is the integrator's business.

use crate::color::Color;
use crate::geometry::{reflect, Vec2, Vec3};
use crate::texture::Texture;
use std::f32::consts::FRAC_1_PI;

/// Why material parameters are unusable.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MaterialError {
    /// A coefficient is negative or not finite.
    #[error("{name} must be a finite number ≥ 0, got {value}")]
    Coefficient {
        /// Parameter name.
        name: &'static str,
        /// Value given.
        value: f32,
    },
}

/// A surface description of the classic renderer.
///
/// * **Matte** is a Lambertian reflector: BRDF `kd · colour / π`.
/// * **Phong** adds a specular lobe `ks · max(0, r·wo)^exponent`, with `r`
///   the mirror direction of the light about the normal (the form of Suffern,
///   *Ray Tracing from the Ground Up*, ch. 15, white highlights), and a
///   perfect mirror term: the colour seen along the reflected view ray,
///   weighted by `kr`.
///
/// Both reflect the scene's ambient light as `ka · colour · ambient`, where
/// `ka` defaults to `kd`.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
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

fn coefficient(name: &'static str, value: f32) -> Result<f32, MaterialError> {
    if value >= 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(MaterialError::Coefficient { name, value })
    }
}

impl Material {
    /// A Lambertian material.
    ///
    /// ```
    /// use lucent::material::Material;
    /// use lucent::color::Color;
    /// let red = Material::matte(Color::new(1.0, 0.0, 0.0), 0.8).unwrap();
    /// assert_eq!(red.kr, 0.0);
    /// ```
    pub fn matte(color: impl Into<Texture>, kd: f32) -> Result<Self, MaterialError> {
        let kd = coefficient("kd", kd)?;
        Ok(Self { color: color.into(), ka: kd, kd, ks: 0.0, exponent: 1.0, kr: 0.0 })
    }

    /// A Phong material with mirror reflection.
    pub fn phong(color: impl Into<Texture>, kd: f32, ks: f32, exponent: f32, kr: f32) -> Result<Self, MaterialError> {
        let kd = coefficient("kd", kd)?;
        Ok(Self {
            color: color.into(),
            ka: kd,
            kd,
            ks: coefficient("ks", ks)?,
            exponent: coefficient("exponent", exponent)?,
            kr: coefficient("kr", kr)?,
        })
    }

    /// Override the ambient coefficient.
    pub fn with_ka(mut self, ka: f32) -> Result<Self, MaterialError> {
        self.ka = coefficient("ka", ka)?;
        Ok(self)
    }

    /// The reflection model at a point with texture coordinates `uv`.
    #[inline]
    pub fn bsdf(&self, uv: Vec2) -> PhongBsdf {
        let albedo = self.color.evaluate(uv);
        PhongBsdf {
            ambient: self.ka * albedo,
            diffuse: self.kd * albedo * FRAC_1_PI,
            ks: self.ks,
            exponent: self.exponent,
            kr: self.kr,
        }
    }
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
    /// Mirror reflectivity.
    pub kr: f32,
}

impl PhongBsdf {
    /// BRDF value for light arriving from `wi` and leaving towards `wo`,
    /// both unit and pointing away from the surface, with unit normal `n`.
    #[inline]
    pub fn f(&self, wo: Vec3, wi: Vec3, n: Vec3) -> Color {
        let mut f = self.diffuse;
        if self.ks > 0.0 {
            let r = reflect(-wi, n);
            let cos_r = r.dot(wo);
            if cos_r > 0.0 {
                f += Color::splat(self.ks * cos_r.powf(self.exponent));
            }
        }
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_brdf_is_albedo_over_pi() {
        let m = Material::matte(Color::new(0.5, 1.0, 0.25), 0.8).unwrap();
        let b = m.bsdf(Vec2::ZERO);
        let f = b.f(Vec3::Y, Vec3::new(0.6, 0.8, 0.0), Vec3::Y);
        assert!((f - Color::new(0.4, 0.8, 0.2) / std::f32::consts::PI).length() < 1e-7);
        assert_eq!(b.ambient, Color::new(0.4, 0.8, 0.2));
    }

    #[test]
    fn phong_peak_is_in_the_mirror_direction() {
        let m = Material::phong(Color::ONE, 0.0, 0.5, 10.0, 0.0).unwrap();
        let b = m.bsdf(Vec2::ZERO);
        let wi = Vec3::new(1.0, 1.0, 0.0).normalize();
        let mirror = Vec3::new(-1.0, 1.0, 0.0).normalize();
        assert!((b.f(mirror, wi, Vec3::Y).x - 0.5).abs() < 1e-6);
        let off = Vec3::new(-1.0, 2.0, 0.0).normalize();
        let expected = 0.5 * off.dot(mirror).powf(10.0);
        assert!((b.f(off, wi, Vec3::Y).x - expected).abs() < 1e-6);
    }

    #[test]
    fn negative_coefficients_are_refused() {
        assert!(Material::matte(Color::ONE, -0.1).is_err());
        assert!(Material::phong(Color::ONE, 0.5, 0.5, 10.0, f32::NAN).is_err());
    }
}
