//! The film of progressive rendering: filter-weighted sums of samples per
//! pixel, kept in fixed point so that they are exact.

use super::{check_image_size, Film, FilmError};
use crate::color::Color;
use std::sync::atomic::{AtomicI64, Ordering};

/// Fixed-point scale of the sums: one unit is 2⁻²⁰ (about 10⁻⁶).
pub const FIXED_POINT_SCALE: f64 = (1u64 << 20) as f64;

/// Largest radiance (times filter weight) one sample may add to a pixel;
/// larger values are clamped. With at most 2²⁰ samples per pixel and 16
/// pixels per sample's filter footprint this keeps every sum inside an
/// `i64`. 524,288 is far above anything but looking straight into a
/// point-sized sun.
pub const MAX_CONTRIBUTION: f32 = (1u32 << 19) as f32;

/// Per-pixel sums `Σ wᵢ·Lᵢ` and `Σ wᵢ` of the samples that reached a pixel,
/// where `wᵢ` is the reconstruction filter evaluated at the sample's
/// offset from the pixel centre (samples are "splatted" to every pixel
/// whose filter covers them). The image is their ratio.
///
/// The sums are fixed-point integers updated atomically. Integer addition
/// is exact and associative, so the sums after `n` samples are
/// bit-identical however the work was split among threads, passes, or
/// interrupted and resumed runs, even though neighbouring rows rendered by
/// different threads add to the same pixels.
#[derive(Debug)]
pub struct Accumulator {
    width: u32,
    height: u32,
    spp: u32,
    sums: Vec<[AtomicI64; 4]>,
}

impl Accumulator {
    /// An empty accumulator; the size is checked and the memory reserved
    /// fallibly.
    pub fn new(width: u32, height: u32) -> Result<Self, FilmError> {
        check_image_size(width, height)?;
        let n = width as usize * height as usize;
        let mut sums = Vec::new();
        sums.try_reserve_exact(n).map_err(|_| FilmError::OutOfMemory(width, height))?;
        sums.resize_with(n, Default::default);
        Ok(Self { width, height, spp: 0, sums })
    }

    /// Rebuild from stored fixed-point sums (a checkpoint): one
    /// `[Σw·r, Σw·g, Σw·b, Σw]` per pixel, row by row from the top.
    pub fn from_raw(width: u32, height: u32, spp: u32, raw: &[[i64; 4]]) -> Result<Self, FilmError> {
        check_image_size(width, height)?;
        if raw.len() != width as usize * height as usize {
            return Err(FilmError::Empty(width, height));
        }
        let sums = raw.iter().map(|s| s.map(AtomicI64::new)).collect();
        Ok(Self { width, height, spp, sums })
    }

    /// The fixed-point sums, row by row from the top.
    pub fn raw(&self) -> Vec<[i64; 4]> {
        self.sums.iter().map(|s| std::array::from_fn(|i| s[i].load(Ordering::Relaxed))).collect()
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

    /// Record that `n` more samples were taken in every pixel.
    pub fn add_spp(&mut self, n: u32) {
        self.spp += n;
    }

    /// Add radiance `l` with filter weight `w` to pixel `(x, y)`. Safe to
    /// call from many threads at once.
    #[inline]
    pub fn splat(&self, x: u32, y: u32, l: Color, w: f32) {
        self.add_fixed(x, y, fixed_contribution(l, w));
    }

    /// Add fixed-point sums (of [`fixed_contribution`]s) to pixel `(x, y)`.
    /// Integer addition is exact, so adding several samples' contributions
    /// at once gives the same sums as splatting them one by one.
    #[inline]
    pub fn add_fixed(&self, x: u32, y: u32, sums: [i64; 4]) {
        let s = &self.sums[y as usize * self.width as usize + x as usize];
        for (sum, v) in s.iter().zip(sums) {
            sum.fetch_add(v, Ordering::Relaxed);
        }
    }

    /// The image so far: each pixel's weighted mean (black where no weight
    /// has been recorded).
    pub fn to_film(&self) -> Film {
        let mut film = Film::new(self.width, self.height).expect("size checked at construction");
        for (out, s) in film.pixels_mut().iter_mut().zip(&self.sums) {
            let [r, g, b, w] = std::array::from_fn(|i| s[i].load(Ordering::Relaxed) as f64);
            *out = if w != 0.0 { Color::new((r / w) as f32, (g / w) as f32, (b / w) as f32) } else { Color::ZERO };
        }
        film
    }
}

/// What [`Accumulator::splat`] adds for radiance `l` with filter weight
/// `w`: `[w·r, w·g, w·b, w]` clamped to ±[`MAX_CONTRIBUTION`] and rounded
/// to fixed point.
#[inline]
pub fn fixed_contribution(l: Color, w: f32) -> [i64; 4] {
    let wl = (l * w).clamp(Color::splat(-MAX_CONTRIBUTION), Color::splat(MAX_CONTRIBUTION));
    [to_fixed(wl.x), to_fixed(wl.y), to_fixed(wl.z), to_fixed(w)]
}

/// Round to the nearest fixed-point unit.
#[inline]
fn to_fixed(v: f32) -> i64 {
    // `x.round()` (half away from zero), without a call into libm on CPUs
    // without SSE4.1: x is an f32 times 2²⁰, so it has at most 24
    // significant bits and |x| < 2³⁹ after clamping; adding ±½ is then
    // exact in f64, and truncation towards zero finishes the rounding.
    let x = v as f64 * FIXED_POINT_SCALE;
    (x + 0.5f64.copysign(x)) as i64
}

impl Clone for Accumulator {
    fn clone(&self) -> Self {
        Self::from_raw(self.width, self.height, self.spp, &self.raw()).expect("same size")
    }
}

impl PartialEq for Accumulator {
    fn eq(&self, other: &Self) -> bool {
        (self.width, self.height, self.spp) == (other.width, other.height, other.spp) && self.raw() == other.raw()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fast rounding equals `f64::round` on every input it can get:
    /// random f32s of every magnitude up to the clamp, and the halves.
    #[test]
    fn to_fixed_rounds_half_away_from_zero() {
        let mut rng = crate::sampling::Pcg32::new(1, 2);
        let unit = 1.0 / FIXED_POINT_SCALE as f32;
        let mut values = vec![0.0, -0.0, 0.5 * unit, -0.5 * unit, 1.5 * unit, -2.5 * unit, MAX_CONTRIBUTION];
        for _ in 0..200_000 {
            let e = (rng.uniform() * 60.0) as i32 - 40;
            let v = (rng.uniform() * 2.0 - 1.0) * 2f32.powi(e);
            values.push(v.clamp(-MAX_CONTRIBUTION, MAX_CONTRIBUTION));
        }
        for v in values {
            assert_eq!(to_fixed(v), (v as f64 * FIXED_POINT_SCALE).round() as i64, "{v:e}");
        }
    }

    #[test]
    fn sums_are_exact_in_any_order() {
        let a = Accumulator::new(2, 1).unwrap();
        let b = Accumulator::new(2, 1).unwrap();
        let samples = [(Color::new(0.1, 3.0, 1e-4), 0.25), (Color::splat(7.3), 0.5), (Color::new(1e-3, 0.0, 2.0), 1.0)];
        for (l, w) in samples {
            a.splat(1, 0, l, w);
        }
        for (l, w) in samples.iter().rev() {
            b.splat(1, 0, *l, *w);
        }
        assert_eq!(a, b);
        let p = a.to_film().pixel(1, 0);
        let expect = (Color::new(0.1, 3.0, 1e-4) * 0.25 + Color::splat(7.3) * 0.5 + Color::new(1e-3, 0.0, 2.0)) / 1.75;
        assert!((p - expect).abs().max_element() < 1e-5, "{p} vs {expect}");
        assert_eq!(a.to_film().pixel(0, 0), Color::ZERO);
    }

    #[test]
    fn huge_contributions_are_clamped_not_wrapped() {
        let a = Accumulator::new(1, 1).unwrap();
        for _ in 0..16 {
            a.splat(0, 0, Color::splat(f32::MAX), 1.0);
        }
        assert_eq!(a.to_film().pixel(0, 0), Color::splat(MAX_CONTRIBUTION));
    }
}
