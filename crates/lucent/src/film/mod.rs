//! The film: the image being formed, in linear radiance, and its conversion
//! to display values and files.

mod accumulator;
pub mod adaptive;
mod aov;
mod checkpoint;
pub mod exr_layers;
mod filter;
mod output;
mod partial;
mod sensor;
mod splat;
mod tonemap;

pub use accumulator::{fixed_contribution, fixed_value, Accumulator, AovImages, FIXED_POINT_SCALE, MAX_CONTRIBUTION};
pub use aov::{Aov, AovSample, AovSet, UnknownAov};
pub use checkpoint::{load_checkpoint, save_checkpoint, CheckpointError};
pub use filter::{Filter, Filter1d, FilterError, FilterSample, FilterSampler, TABLE_SEGMENTS};
pub use output::{ImageFormat, Layers, OutputError, PendingImage};
pub(crate) use partial::fnv1a;
pub use partial::{show_ranges, PartialError, PartialFilm};
pub use sensor::{
    film_response, imaging_ratio, pbrt_film_scale, validate_film_response, white_balance_matrix, white_balance_scale,
    SensorError,
};
pub use splat::{LightSplatter, SplatBand, MAX_BAND_REACH};
pub use tonemap::{srgb_encode, ToneMap};

/// The film cannot be allocated: its size is unusable or the memory
/// cannot be had (the [`ImageSizeError`](crate::texels::ImageSizeError) of
/// the [`TexelGrid`] it is stored in).
pub use crate::texels::ImageSizeError as FilmError;
pub use crate::texels::{check_image_size, MAX_DIMENSION, MAX_PIXELS};

use crate::color::Color;
use crate::texels::TexelGrid;
use rayon::prelude::*;

/// A linear-radiance image, stored in a [`TexelGrid`].
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    texels: TexelGrid,
}

impl Film {
    /// A black film; the size is checked and the memory reserved fallibly.
    pub fn new(width: u32, height: u32) -> Result<Self, FilmError> {
        Ok(Self { texels: TexelGrid::new(width, height)? })
    }

    /// Width in pixels.
    #[inline]
    pub fn width(&self) -> u32 {
        self.texels.width()
    }

    /// Height in pixels.
    #[inline]
    pub fn height(&self) -> u32 {
        self.texels.height()
    }

    /// The pixel at column `x`, row `y` (row 0 at the top).
    #[inline]
    pub fn pixel(&self, x: u32, y: u32) -> Color {
        self.texels.pixel(x, y)
    }

    /// All pixels, row by row from the top.
    #[inline]
    pub fn pixels(&self) -> &[Color] {
        self.texels.pixels()
    }

    /// Mutable pixels, row by row from the top.
    #[inline]
    pub fn pixels_mut(&mut self) -> &mut [Color] {
        self.texels.pixels_mut()
    }

    /// The pixels as a grid.
    #[inline]
    pub fn texels(&self) -> &TexelGrid {
        &self.texels
    }

    /// The pixels as a grid, without copying.
    #[inline]
    pub fn into_texels(self) -> TexelGrid {
        self.texels
    }

    /// 8-bit display values: tone mapped, then sRGB-encoded if `srgb`
    /// (otherwise written linearly), then quantised with rounding.
    ///
    /// Pixels are converted in parallel (on the current rayon pool), in
    /// blocks: each value depends on its own pixel only, so the bytes are
    /// the same whatever the thread count. (The sRGB curve's `powf` made
    /// this a few percent of a small render's time when done on one
    /// thread after the render.)
    pub fn to_rgb8(&self, tone_map: ToneMap, srgb: bool) -> Vec<u8> {
        const BLOCK: usize = 4096;
        let mut out = vec![0u8; self.pixels().len() * 3];
        out.par_chunks_mut(3 * BLOCK).zip(self.pixels().par_chunks(BLOCK)).for_each(|(out, pixels)| {
            for (out, &c) in out.chunks_exact_mut(3).zip(pixels) {
                let mapped = tone_map.apply(c);
                for (o, v) in out.iter_mut().zip(mapped.to_array()) {
                    let v = if srgb { srgb_encode(v) } else { v };
                    *o = (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
                }
            }
        });
        out
    }
}

impl From<TexelGrid> for Film {
    /// A film showing the grid's colours.
    fn from(texels: TexelGrid) -> Self {
        Self { texels }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    /// The parallel conversion gives the bytes of converting the pixels one
    /// by one, in order, across block boundaries (the film is larger than
    /// one block, and its size not a multiple of it), for every tone map and
    /// with and without the sRGB curve, on values below 0, in range and
    /// above 1.
    #[test]
    fn to_rgb8_is_the_pixel_by_pixel_conversion() {
        let mut film = Film::new(97, 61).unwrap();
        let mut rng = Pcg32::new(4, 1);
        for c in film.pixels_mut() {
            *c = Color::new(rng.uniform() * 3.0 - 0.5, rng.uniform() * 1.2, rng.uniform() * 40.0);
        }
        for tone_map in [ToneMap::Classic, ToneMap::Clamp, ToneMap::Reinhard, ToneMap::Aces] {
            for srgb in [false, true] {
                let expected: Vec<u8> = film
                    .pixels()
                    .iter()
                    .flat_map(|&c| tone_map.apply(c).to_array())
                    .map(|v| {
                        let v = if srgb { srgb_encode(v) } else { v };
                        (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
                    })
                    .collect();
                assert_eq!(film.to_rgb8(tone_map, srgb), expected, "{tone_map:?}, srgb {srgb}");
            }
        }
    }
}
