//! Pixel reconstruction filters, applied by filter importance sampling
//! (Ernst et al., "Filter Importance Sampling", 2006; PBRT 4th ed., §8.8):
//! each sample's position within the pixel is drawn from the filter's
//! distribution and weighted by `f/pdf`, so a sample affects one pixel only
//! and pixels stay independent.

use glam::Vec2;

/// A reconstruction filter. Radii are in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Filter {
    /// Constant over a square of half-width `radius` (0.5: the pixel).
    Box {
        /// Half-width.
        radius: f32,
    },
    /// The tent (triangle) filter `max(0, 1 - |x|/r)·max(0, 1 - |y|/r)`.
    Tent {
        /// Radius.
        radius: f32,
    },
    /// A Gaussian of standard deviation `sigma`, cut off at `radius`.
    Gaussian {
        /// Radius.
        radius: f32,
        /// Standard deviation.
        sigma: f32,
    },
    /// Mitchell–Netravali with parameters `b`, `c` (1/3, 1/3 recommended).
    Mitchell {
        /// Radius.
        radius: f32,
        /// B.
        b: f32,
        /// C.
        c: f32,
    },
}

impl Default for Filter {
    fn default() -> Self {
        Filter::Box { radius: 0.5 }
    }
}

/// A sample offset and its weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterSample {
    /// Offset from the pixel centre, in pixels.
    pub offset: Vec2,
    /// `f(offset) / pdf(offset)` (constant for filters that are never
    /// negative).
    pub weight: f32,
}

/// Draws offsets distributed like a [`Filter`].
#[derive(Clone, Debug)]
pub struct FilterSampler {
    filter: Filter,
}

impl FilterSampler {
    /// A sampler for `filter` (tabulated where the filter has no analytic
    /// inverse).
    pub fn new(filter: Filter) -> Self {
        Self { filter }
    }

    /// The filter.
    pub fn filter(&self) -> Filter {
        self.filter
    }

    /// An offset for the uniform sample `u`.
    pub fn sample(&self, u: Vec2) -> FilterSample {
        let _ = u;
        todo!()
    }
}
