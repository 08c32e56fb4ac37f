//! Random numbers and sample patterns.
//!
//! Every pixel draws its samples from its own generator, seeded from the
//! scene seed and the pixel's coordinates alone, so an image does not depend
//! on how pixels are distributed over threads.

mod distribution;
mod lanes;
mod pattern;
mod rng;
mod sampler;
mod spherical_rectangle;
mod warp;

pub use distribution::{AliasTable, PiecewiseConstant1D, PiecewiseConstant2D};
pub use pattern::{stratified_2d, PixelSampler};
pub use rng::{mix_seed, Pcg32};
pub use sampler::{Sampler, SamplerKind, VertexSamples};
pub use spherical_rectangle::SphericalRectangle;
pub use warp::{
    concentric_disk, cosine_hemisphere, cosine_hemisphere_pdf, spherical_triangle, tent, uniform_sphere,
    uniform_triangle,
};
