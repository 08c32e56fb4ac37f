//! The film: the image being formed, in linear radiance, and its conversion
//! to display values and files.

mod accumulator;
mod checkpoint;
mod filter;
mod output;
mod tonemap;

pub use accumulator::{Accumulator, FIXED_POINT_SCALE, MAX_CONTRIBUTION};
pub use checkpoint::{load_checkpoint, save_checkpoint, CheckpointError};
pub use filter::{Filter, FilterError, FilterSample, FilterSampler, TABLE_SEGMENTS};
pub use output::{ImageFormat, OutputError, PendingImage};
pub use tonemap::{srgb_encode, ToneMap};

use crate::color::Color;

/// A linear-radiance image.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    pixels: Vec<Color>,
}

/// Largest image accepted: 2²⁸ pixels (16384 × 16384), whose film alone takes
/// 3 GiB.
pub const MAX_PIXELS: u64 = 1 << 28;

/// Largest width or height accepted.
pub const MAX_DIMENSION: u32 = 65_536;

/// The film cannot be allocated.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FilmError {
    /// Width or height zero.
    #[error("image size {0}×{1} is empty: width and height must be at least 1")]
    Empty(u32, u32),
    /// Larger than [`MAX_PIXELS`] or [`MAX_DIMENSION`].
    #[error("image size {0}×{1} is too large: at most {MAX_DIMENSION} per side and {MAX_PIXELS} pixels in all")]
    TooLarge(u32, u32),
    /// The memory could not be reserved.
    #[error("not enough memory for a {0}×{1} image")]
    OutOfMemory(u32, u32),
}

/// Check an image size before anything is allocated for it.
pub fn check_image_size(width: u32, height: u32) -> Result<(), FilmError> {
    if width == 0 || height == 0 {
        return Err(FilmError::Empty(width, height));
    }
    if width > MAX_DIMENSION || height > MAX_DIMENSION || width as u64 * height as u64 > MAX_PIXELS {
        return Err(FilmError::TooLarge(width, height));
    }
    Ok(())
}

impl Film {
    /// A black film; the size is checked and the memory reserved fallibly.
    pub fn new(width: u32, height: u32) -> Result<Self, FilmError> {
        check_image_size(width, height)?;
        let n = width as usize * height as usize;
        let mut pixels = Vec::new();
        pixels.try_reserve_exact(n).map_err(|_| FilmError::OutOfMemory(width, height))?;
        pixels.resize(n, Color::ZERO);
        Ok(Self { width, height, pixels })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixel at column `x`, row `y` (row 0 at the top).
    pub fn pixel(&self, x: u32, y: u32) -> Color {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// All pixels, row by row from the top.
    pub fn pixels(&self) -> &[Color] {
        &self.pixels
    }

    /// Mutable pixels, row by row from the top.
    pub fn pixels_mut(&mut self) -> &mut [Color] {
        &mut self.pixels
    }

    /// 8-bit display values: tone mapped, then sRGB-encoded if `srgb`
    /// (otherwise written linearly), then quantised with rounding.
    pub fn to_rgb8(&self, tone_map: ToneMap, srgb: bool) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.pixels.len() * 3);
        for &c in &self.pixels {
            let mapped = tone_map.apply(c);
            for v in mapped.to_array() {
                let v = if srgb { srgb_encode(v) } else { v };
                out.push((v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8);
            }
        }
        out
    }
}
