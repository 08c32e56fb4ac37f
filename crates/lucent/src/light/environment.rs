//! Environment lights: radiance arriving from infinitely far away.

use crate::color::Color;
use crate::geometry::Vec3;

/// Light from every direction at infinity.
#[derive(Clone, Debug)]
pub enum Environment {
    /// The same radiance from every direction.
    Constant(Color),
}

impl Environment {
    /// TEMPORARY stub until image environments land.
    pub fn from_file(path: &std::path::Path, scale: f32, rotation: f32) -> Result<Self, String> {
        let _ = (path, scale, rotation);
        Err("image environments are not supported yet".into())
    }

    /// Radiance arriving from direction `-dir`, i.e. seen by a ray
    /// travelling along unit `dir` that escapes the scene.
    pub fn le(&self, dir: Vec3) -> Color {
        let _ = dir;
        match self {
            Environment::Constant(c) => *c,
        }
    }
}
