use crate::geometry::Vec3;

/// A ray `o + t d`. The direction need not be unit length: transforms keep
/// `t` meaningful between world and object space by not renormalising it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin `o`.
    pub origin: Vec3,
    /// Direction `d`.
    pub dir: Vec3,
}

impl Ray {
    /// A ray from `origin` along `dir`.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}
