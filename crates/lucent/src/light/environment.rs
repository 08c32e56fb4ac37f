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
    /// Radiance arriving from direction `-dir`, i.e. seen by a ray
    /// travelling along unit `dir` that escapes the scene.
    pub fn le(&self, dir: Vec3) -> Color {
        let _ = dir;
        match self {
            Environment::Constant(c) => *c,
        }
    }
}
