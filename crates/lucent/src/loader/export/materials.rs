//! TEMPORARY stand-in until the materials exporter lands (constants only).

use super::super::description::*;
use super::super::values::*;
use crate::material::Material;
use crate::texture::Texture;
use std::path::Path;

pub(crate) struct TextureExport {}

impl TextureExport {
    pub fn new(_out_dir: &Path) -> Self {
        Self {}
    }

    pub fn material(&mut self, m: &Material, _names: &[String]) -> Result<MaterialDesc, String> {
        match m {
            Material::Diffuse { reflectance: Texture::Constant(c) } => {
                Ok(MaterialDesc::Diffuse(DiffuseDesc { color: Some(Rgb(c.to_array())), checker: None }))
            }
            _ => Err("not yet".into()),
        }
    }
}
