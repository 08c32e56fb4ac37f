//! Samplers for the path integrator: an endless, deterministic sequence of
//! sample vectors per pixel, addressed by sample index, so that a render can
//! stop after any number of samples and later continue (PBRT 4th ed., ch. 8).

use glam::Vec2;

/// Which sample sequence a render uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SamplerKind {
    /// Independent uniform random numbers.
    Independent,
    /// Owen-scrambled Sobol points: low discrepancy in every pair of
    /// dimensions.
    #[default]
    Sobol,
}

/// The sample vectors of one pixel sample. Dimensions are consumed in
/// order: [`PathSampler::pixel_2d`] first, then whatever the camera and the
/// integrator ask for.
#[derive(Clone, Debug)]
pub struct PathSampler {
    kind: SamplerKind,
    seed: u64,
}

impl PathSampler {
    /// A sampler of `kind` for a render with `seed`.
    pub fn new(kind: SamplerKind, seed: u64) -> Self {
        Self { kind, seed }
    }

    /// Which sequence this is.
    pub fn kind(&self) -> SamplerKind {
        self.kind
    }

    /// Start sample number `index` of pixel `(x, y)`; the values that follow
    /// depend only on the seed, the pixel, the index and the dimension.
    pub fn start_pixel_sample(&mut self, x: u32, y: u32, index: u32) {
        let _ = (x, y, index, self.seed);
        todo!()
    }

    /// The next dimension, uniform in `[0, 1)`.
    pub fn get_1d(&mut self) -> f32 {
        todo!()
    }

    /// The next two dimensions, uniform in `[0, 1)²`.
    pub fn get_2d(&mut self) -> Vec2 {
        todo!()
    }

    /// The sample's position within the pixel filter's support: the first
    /// two dimensions.
    pub fn pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }
}
