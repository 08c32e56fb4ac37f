//! A `width × height` grid of colours: the storage the film forms its image
//! in and environment maps are read into, with the image size limits both
//! obey.
//!
//! This module depends on `color` only, so that anything may use it.

use crate::color::Color;

/// Largest image accepted: 2²⁸ pixels (16384 × 16384), whose film alone takes
/// 3 GiB.
pub const MAX_PIXELS: u64 = 1 << 28;

/// Largest width or height accepted.
pub const MAX_DIMENSION: u32 = 65_536;

/// An image size that cannot be used, or memory that cannot be had for it.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ImageSizeError {
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
pub fn check_image_size(width: u32, height: u32) -> Result<(), ImageSizeError> {
    if width == 0 || height == 0 {
        return Err(ImageSizeError::Empty(width, height));
    }
    if width > MAX_DIMENSION || height > MAX_DIMENSION || width as u64 * height as u64 > MAX_PIXELS {
        return Err(ImageSizeError::TooLarge(width, height));
    }
    Ok(())
}

/// A `width × height` grid of colours, stored row by row from the top; its
/// size always passes [`check_image_size`].
#[derive(Clone, Debug, PartialEq)]
pub struct TexelGrid {
    width: u32,
    height: u32,
    pixels: Vec<Color>,
}

impl TexelGrid {
    /// A black grid; the size is checked and the memory reserved fallibly.
    pub fn new(width: u32, height: u32) -> Result<Self, ImageSizeError> {
        check_image_size(width, height)?;
        let n = width as usize * height as usize;
        let mut pixels = Vec::new();
        pixels.try_reserve_exact(n).map_err(|_| ImageSizeError::OutOfMemory(width, height))?;
        pixels.resize(n, Color::ZERO);
        Ok(Self { width, height, pixels })
    }

    /// The grid of `pixels`, row by row from the top; `None` unless the size
    /// passes [`check_image_size`] and there are `width × height` pixels.
    pub fn from_pixels(width: u32, height: u32, pixels: Vec<Color>) -> Option<Self> {
        let fits = check_image_size(width, height).is_ok() && pixels.len() == width as usize * height as usize;
        fits.then_some(Self { width, height, pixels })
    }

    /// Width in pixels.
    #[inline]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[inline]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixel at column `x`, row `y` (row 0 at the top).
    #[inline]
    pub fn pixel(&self, x: u32, y: u32) -> Color {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// All pixels, row by row from the top.
    #[inline]
    pub fn pixels(&self) -> &[Color] {
        &self.pixels
    }

    /// Mutable pixels, row by row from the top.
    #[inline]
    pub fn pixels_mut(&mut self) -> &mut [Color] {
        &mut self.pixels
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_checked() {
        assert_eq!(check_image_size(0, 5), Err(ImageSizeError::Empty(0, 5)));
        assert_eq!(check_image_size(MAX_DIMENSION + 1, 1), Err(ImageSizeError::TooLarge(MAX_DIMENSION + 1, 1)));
        assert_eq!(check_image_size(MAX_DIMENSION, MAX_DIMENSION), Err(ImageSizeError::TooLarge(65_536, 65_536)));
        assert!(check_image_size(16_384, 16_384).is_ok());
        assert!(TexelGrid::new(0, 1).is_err());
    }

    #[test]
    fn pixels_are_row_major_from_the_top() {
        let px: Vec<Color> = (0..6).map(|i| Color::splat(i as f32)).collect();
        let mut g = TexelGrid::from_pixels(3, 2, px).unwrap();
        assert_eq!((g.width(), g.height()), (3, 2));
        assert_eq!(g.pixel(2, 0), Color::splat(2.0));
        assert_eq!(g.pixel(0, 1), Color::splat(3.0));
        g.pixels_mut()[4] = Color::ONE;
        assert_eq!(g.pixel(1, 1), Color::ONE);
        assert_eq!(TexelGrid::new(2, 2).unwrap().pixels(), &[Color::ZERO; 4]);
        assert!(TexelGrid::from_pixels(3, 2, vec![Color::ZERO; 5]).is_none());
        assert!(TexelGrid::from_pixels(0, 0, Vec::new()).is_none());
    }
}
