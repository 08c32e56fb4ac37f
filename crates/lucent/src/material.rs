//! Materials: how a surface reflects light. A material describes the surface
//! only; what light reaches it is the integrator's business.

use crate::bsdf::{Bxdf, ConductorFresnel};
use crate::color::Color;
use crate::geometry::{reflect, Vec2, Vec3};
use crate::texture::{Texture, TextureContext};
use std::f32::consts::FRAC_1_PI;

/// Index of a material in its scene; only the scene builder's
/// `add_material` makes one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MaterialId(u32);

impl MaterialId {
    /// The handle of the material at `index` in a scene's material list.
    pub(crate) fn new(index: usize) -> Self {
        Self(index as u32)
    }

    /// The index into the scene's material list.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

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

/// A surface description.
///
/// The classic materials, for the Whitted integrator (and given an
/// energy-conserving reading under the path tracer, see [`Material::bxdf`]):
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
///
/// The physically based materials, for the path integrator: `Diffuse`,
/// `Conductor`, `Dielectric` and `Plastic` (see [`crate::bsdf`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Matte or Phong.
    Classic(ClassicMaterial),
    /// Lambertian reflection.
    Diffuse {
        /// Albedo, each channel in [0, 1].
        reflectance: Texture,
    },
    /// A metal.
    Conductor {
        /// How the Fresnel reflectance is given; Schlick's reflectance at
        /// normal incidence may be textured.
        fresnel: ConductorFresnel<Texture>,
        /// GGX roughness α (0: a perfect mirror).
        roughness: f32,
    },
    /// Glass, water: reflects and refracts.
    Dielectric {
        /// Index of refraction of the inside (the outside is vacuum).
        eta: f32,
        /// GGX roughness α (0: smooth).
        roughness: f32,
        /// Scales transmitted light (white: clear glass).
        tint: Color,
    },
    /// A diffuse base under a clear dielectric coat.
    Plastic {
        /// Albedo of the base.
        reflectance: Texture,
        /// Index of refraction of the coat.
        eta: f32,
        /// GGX roughness α of the coat (0: smooth).
        roughness: f32,
    },
}

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
    /// assert_eq!(red.classic().unwrap().kr, 0.0);
    /// ```
    pub fn matte(color: impl Into<Texture>, kd: f32) -> Result<Self, MaterialError> {
        let kd = coefficient("kd", kd)?;
        Ok(Self::Classic(ClassicMaterial { color: color.into(), ka: kd, kd, ks: 0.0, exponent: 1.0, kr: 0.0 }))
    }

    /// A Phong material with mirror reflection.
    pub fn phong(color: impl Into<Texture>, kd: f32, ks: f32, exponent: f32, kr: f32) -> Result<Self, MaterialError> {
        let kd = coefficient("kd", kd)?;
        Ok(Self::Classic(ClassicMaterial {
            color: color.into(),
            ka: kd,
            kd,
            ks: coefficient("ks", ks)?,
            exponent: coefficient("exponent", exponent)?,
            kr: coefficient("kr", kr)?,
        }))
    }

    /// Override the ambient coefficient of a classic material (other
    /// materials have none and are returned unchanged).
    pub fn with_ka(mut self, ka: f32) -> Result<Self, MaterialError> {
        if let Self::Classic(c) = &mut self {
            c.ka = coefficient("ka", ka)?;
        }
        Ok(self)
    }

    /// The classic parameters, for a matte or Phong material.
    pub fn classic(&self) -> Option<&ClassicMaterial> {
        match self {
            Self::Classic(c) => Some(c),
            _ => None,
        }
    }

    /// The classic reflection model at a point with texture coordinates
    /// `uv`, as the Whitted integrator sees it. Physically based materials
    /// are approximated: a diffuse surface as matte, a conductor or a
    /// dielectric as a mirror weighted by its reflectance at normal
    /// incidence (the Whitted integrator does not refract), plastic as
    /// matte plus that mirror.
    #[inline]
    pub fn bsdf(&self, uv: Vec2) -> PhongBsdf {
        let matte = |albedo: Color, kr: Color| PhongBsdf {
            ambient: albedo,
            diffuse: albedo * FRAC_1_PI,
            ks: 0.0,
            exponent: 1.0,
            kr,
        };
        match self {
            Self::Classic(m) => {
                let albedo = m.color.evaluate(&TextureContext::from_uv(uv));
                PhongBsdf {
                    ambient: m.ka * albedo,
                    diffuse: m.kd * albedo * FRAC_1_PI,
                    ks: m.ks,
                    exponent: m.exponent,
                    kr: Color::splat(m.kr),
                }
            }
            Self::Diffuse { reflectance } => matte(reflectance.evaluate(&TextureContext::from_uv(uv)), Color::ZERO),
            Self::Conductor { fresnel, .. } => {
                let r0 = match fresnel {
                    ConductorFresnel::Complex { eta, k } => {
                        // Normal-incidence reflectance of a conductor:
                        // ((η-1)² + k²) / ((η+1)² + k²).
                        let one = Color::ONE;
                        ((*eta - one) * (*eta - one) + *k * *k) / ((*eta + one) * (*eta + one) + *k * *k)
                    }
                    ConductorFresnel::Schlick { r0 } => r0.evaluate(&TextureContext::from_uv(uv)),
                };
                matte(Color::ZERO, r0)
            }
            Self::Dielectric { eta, .. } => matte(Color::ZERO, Color::splat(dielectric_r0(*eta))),
            Self::Plastic { reflectance, eta, .. } => {
                matte(reflectance.evaluate(&TextureContext::from_uv(uv)), Color::splat(dielectric_r0(*eta)))
            }
        }
    }

    /// The scattering function of the path integrator at a point with
    /// texture coordinates `uv`.
    ///
    /// The classic materials are read so as to conserve energy: matte is
    /// Lambertian with albedo `kd·colour`; Phong is that plus a normalised
    /// Phong lobe (Lafortune & Willems 1994) of weight `ks` and a perfect
    /// mirror of weight `kr` (see [`Bxdf::phong`]).
    pub fn bxdf(&self, uv: Vec2) -> Bxdf {
        match self {
            Self::Classic(m) => {
                let albedo = m.kd * m.color.evaluate(&TextureContext::from_uv(uv));
                if m.ks == 0.0 && m.kr == 0.0 {
                    Bxdf::diffuse(albedo)
                } else {
                    Bxdf::phong(albedo, m.ks, m.exponent, m.kr)
                }
            }
            Self::Diffuse { reflectance } => Bxdf::diffuse(reflectance.evaluate(&TextureContext::from_uv(uv))),
            Self::Conductor { fresnel, roughness } => match fresnel {
                ConductorFresnel::Complex { eta, k } => Bxdf::conductor(*eta, *k, *roughness),
                ConductorFresnel::Schlick { r0 } => {
                    Bxdf::conductor_schlick(r0.evaluate(&TextureContext::from_uv(uv)), *roughness)
                }
            },
            Self::Dielectric { eta, roughness, tint } => Bxdf::dielectric(*eta, *roughness, *tint),
            Self::Plastic { reflectance, eta, roughness } => {
                Bxdf::plastic(reflectance.evaluate(&TextureContext::from_uv(uv)), *eta, *roughness)
            }
        }
    }
}

/// Reflectance of a dielectric interface at normal incidence,
/// `((η-1)/(η+1))²`.
fn dielectric_r0(eta: f32) -> f32 {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
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
