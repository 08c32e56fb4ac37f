//! The film of progressive rendering: weighted sums of samples per pixel.

use super::{check_image_size, Film, FilmError};
use crate::color::Color;

/// Per-pixel sums `Σ wᵢ·Lᵢ` and `Σ wᵢ` of the samples taken so far, where
/// `wᵢ` is the filter weight of sample `i` (see
/// [`crate::film::FilterSampler`]). The image is their ratio.
///
/// Samples are added to a pixel one at a time in sample-index order, so the
/// sums after `n` samples are bit-identical however the work was split
/// into passes, threads, or interrupted and resumed runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Accumulator {
    width: u32,
    height: u32,
    spp: u32,
    sums: Vec<[f32; 4]>,
}

impl Accumulator {
    /// An empty accumulator; the size is checked and the memory reserved
    /// fallibly.
    pub fn new(width: u32, height: u32) -> Result<Self, FilmError> {
        check_image_size(width, height)?;
        let n = width as usize * height as usize;
        let mut sums = Vec::new();
        sums.try_reserve_exact(n).map_err(|_| FilmError::OutOfMemory(width, height))?;
        sums.resize(n, [0.0; 4]);
        Ok(Self { width, height, spp: 0, sums })
    }

    /// Rebuild from stored sums (a checkpoint); `sums` must hold one entry
    /// per pixel.
    pub fn from_parts(width: u32, height: u32, spp: u32, sums: Vec<[f32; 4]>) -> Result<Self, FilmError> {
        check_image_size(width, height)?;
        if sums.len() != width as usize * height as usize {
            return Err(FilmError::Empty(width, height));
        }
        Ok(Self { width, height, spp, sums })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Samples taken in every pixel so far.
    pub fn spp(&self) -> u32 {
        self.spp
    }

    /// Record that `n` more samples were added to every pixel.
    pub fn add_spp(&mut self, n: u32) {
        self.spp += n;
    }

    /// The sums, row by row from the top: `[Σw·r, Σw·g, Σw·b, Σw]`.
    pub fn sums(&self) -> &[[f32; 4]] {
        &self.sums
    }

    /// Mutable sums, row by row from the top.
    pub fn sums_mut(&mut self) -> &mut [[f32; 4]] {
        &mut self.sums
    }

    /// The image so far: each pixel's weighted mean (black where no weight
    /// has been recorded).
    pub fn to_film(&self) -> Film {
        let mut film = Film::new(self.width, self.height).expect("size checked at construction");
        for (out, s) in film.pixels_mut().iter_mut().zip(&self.sums) {
            *out = if s[3] != 0.0 { Color::new(s[0], s[1], s[2]) / s[3] } else { Color::ZERO };
        }
        film
    }
}

/// Add one sample of radiance `l` with filter weight `w` to a pixel's sums.
#[inline]
pub fn add_sample(sum: &mut [f32; 4], l: Color, w: f32) {
    sum[0] += w * l.x;
    sum[1] += w * l.y;
    sum[2] += w * l.z;
    sum[3] += w;
}
