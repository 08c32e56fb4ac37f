//! Scene-file materials: `[materials.NAME.KIND]` tables and the materials of
//! mesh files.

use super::description::*;
use super::locate::*;
use super::values::*;
use super::SceneFile;
use crate::bsdf::ConductorFresnel;
use crate::color::Color;
use crate::geometry::Vec3;
use crate::material::{Material, Roughness};
use crate::scene::SceneError;
use crate::texture::Texture;

impl SceneFile {
    pub(super) fn material(&self, name: &str, m: &MaterialDesc) -> Result<Material, SceneError> {
        let at = || find_table(&self.source, name);
        let texture = |color: &Option<Rgb>, checker: &Option<CheckerDesc>| match (color, checker) {
            (Some(_), Some(_)) => {
                Err(self.error(at(), format!("material \"{name}\" has both `color` and `checker`; give one")))
            }
            (Some(c), None) => Ok(Texture::Constant((*c).into())),
            (None, Some(ch)) => {
                Ok(Texture::Checker { even: ch.even.into(), odd: ch.odd.into(), scale: ch.scale.get() })
            }
            (None, None) => Ok(Texture::Constant(Color::ONE)),
        };
        let m = match m {
            MaterialDesc::Matte(m) => {
                let mat = Material::matte(texture(&m.color, &m.checker)?, m.kd.get());
                match m.ka {
                    Some(ka) => mat.and_then(|x| x.with_ka(ka.get())),
                    None => mat,
                }
            }
            MaterialDesc::Phong(p) => {
                let mat = Material::phong(
                    texture(&p.color, &p.checker)?,
                    p.kd.get(),
                    p.ks.get(),
                    p.exponent.get(),
                    p.kr.map_or(0.0, NonNegative::get),
                );
                match p.ka {
                    Some(ka) => mat.and_then(|x| x.with_ka(ka.get())),
                    None => mat,
                }
            }
            MaterialDesc::Diffuse(d) => {
                let reflectance = texture(&d.color, &d.checker)?;
                Ok(Material::Diffuse { reflectance })
            }
            MaterialDesc::Conductor(c) => {
                let fresnel = match (c.color, c.eta, c.k, c.metal) {
                    (Some(color), None, None, None) => {
                        ConductorFresnel::Schlick { r0: Texture::Constant(color.into()) }
                    }
                    (None, Some(eta), Some(k), None) => {
                        ConductorFresnel::Complex { eta: Texture::Constant(eta.into()), k: Texture::Constant(k.into()) }
                    }
                    (None, None, None, Some(metal)) => {
                        let (eta, k) = metal_ior(metal);
                        ConductorFresnel::Complex { eta: eta.into(), k: k.into() }
                    }
                    (None, None, None, None) => ConductorFresnel::Schlick { r0: Texture::Constant(Color::ONE) },
                    _ => {
                        return Err(self.error(
                            at(),
                            format!("material \"{name}\": give one of `color`, `eta` with `k`, or `metal`"),
                        ))
                    }
                };
                let roughness = Roughness::alpha(roughness(c.roughness));
                Ok(Material::Conductor { fresnel, roughness })
            }
            MaterialDesc::Dielectric(d) => Ok(Material::Dielectric {
                eta: d.eta.map_or(1.5, Positive::get),
                roughness: Roughness::alpha(roughness(d.roughness)),
                tint: d.tint.map_or(Color::ONE, Color::from),
            }),
            MaterialDesc::Plastic(p) => {
                let reflectance = texture(&p.color, &p.checker)?;
                Ok(Material::Plastic {
                    reflectance,
                    eta: p.eta.map_or(1.5, Positive::get),
                    roughness: roughness(p.roughness),
                })
            }
        };
        m.map_err(|e| self.error(at(), format!("material \"{name}\": {e}")))
    }
}

/// A scene material for one of a mesh file's own materials (OBJ's MTL):
/// Phong when it has a specular colour, matte otherwise.
pub(super) fn material_from_file(m: &crate::mesh::MeshMaterial) -> Material {
    let kd = Texture::Constant(m.diffuse.max(Vec3::ZERO));
    let ks = m.specular.max_element().max(0.0);
    let material =
        if ks > 0.0 { Material::phong(kd, 1.0, ks, m.shininess.max(1.0), 0.0) } else { Material::matte(kd, 1.0) };
    material.unwrap_or_else(|_| Material::matte(Color::splat(0.8), 1.0).expect("valid constants"))
}

/// A GGX roughness (its range is checked by the scene builder).
fn roughness(r: Option<NonNegative>) -> f32 {
    r.map_or(0.0, NonNegative::get)
}

/// Complex indices of refraction of the named metals at 650, 550 and
/// 450 nm (red, green, blue), from the measurements tabulated at
/// refractiveindex.info: Johnson & Christy 1972 (gold, silver, copper) and
/// Rakić 1995 (aluminium).
fn metal_ior(metal: MetalDesc) -> (Color, Color) {
    let (eta, k) = match metal {
        MetalDesc::Gold => ([0.166, 0.424, 1.316], [3.150, 2.380, 1.863]),
        MetalDesc::Silver => ([0.144, 0.120, 0.135], [4.243, 3.341, 2.484]),
        MetalDesc::Copper => ([0.214, 0.967, 1.158], [3.670, 2.578, 2.398]),
        MetalDesc::Aluminium => ([1.490, 0.958, 0.618], [7.821, 6.690, 5.471]),
    };
    (Color::from_array(eta), Color::from_array(k))
}
