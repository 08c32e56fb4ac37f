//! Choosing a light to sample.

use super::Emitter;
use crate::geometry::Bounds3;

/// All the lights of a scene, with a distribution for picking one in
/// proportion to its power.
#[derive(Clone, Debug)]
pub struct LightSet {
    emitters: Vec<Emitter>,
}

impl LightSet {
    /// The lights of a scene bounded by `bounds`.
    pub fn new(emitters: Vec<Emitter>, bounds: &Bounds3) -> Self {
        let _ = bounds;
        Self { emitters }
    }

    /// The lights.
    pub fn emitters(&self) -> &[Emitter] {
        &self.emitters
    }

    /// Pick a light with a uniform sample `u`: its index and probability.
    /// `None` when there are no lights (or all have zero power).
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        let _ = u;
        todo!()
    }

    /// Probability that [`LightSet::sample`] picks light `index`.
    pub fn pmf(&self, index: usize) -> f32 {
        let _ = index;
        todo!()
    }
}
