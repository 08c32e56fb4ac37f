use super::{mix_seed, Pcg32};
use glam::Vec2;

/// `n` stratified samples in the unit square.
///
/// When `n = k²` is a perfect square this is the classic jittered grid: one
/// uniformly placed sample in each of `k × k` cells. Otherwise it is Latin
/// hypercube ("N-rooks") sampling, stratified in `x` and in `y` separately
/// (Shirley, "Discrepancy as a Quality Measure for Sample Distributions",
/// 1991). The samples are shuffled, so that pairing two patterns does not
/// correlate them.
pub fn stratified_2d(n: u32, rng: &mut Pcg32, out: &mut Vec<Vec2>) {
    out.clear();
    let k = (n as f64).sqrt().round() as u32;
    if k * k == n {
        let inv = 1.0 / k as f32;
        for j in 0..k {
            for i in 0..k {
                out.push(Vec2::new(
                    ((i as f32 + rng.uniform()) * inv).min(ONE_MINUS_EPSILON),
                    ((j as f32 + rng.uniform()) * inv).min(ONE_MINUS_EPSILON),
                ));
            }
        }
    } else {
        let inv = 1.0 / n as f32;
        for i in 0..n {
            out.push(Vec2::new(
                ((i as f32 + rng.uniform()) * inv).min(ONE_MINUS_EPSILON),
                ((i as f32 + rng.uniform()) * inv).min(ONE_MINUS_EPSILON),
            ));
        }
        // Decorrelate y from x by shuffling the y strata.
        for i in (1..out.len()).rev() {
            let j = rng.below(i as u32 + 1) as usize;
            let tmp = out[i].y;
            out[i].y = out[j].y;
            out[j].y = tmp;
        }
    }
    for i in (1..out.len()).rev() {
        let j = rng.below(i as u32 + 1) as usize;
        out.swap(i, j);
    }
}

const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// The samples of one pixel: positions within the pixel and on the lens.
///
/// Seeded from the scene seed and the pixel coordinates only, so a pixel's
/// samples are the same whichever thread renders it. With one sample per
/// pixel the film sample is the pixel centre exactly.
///
/// The lens pattern is drawn from the generator right after the film
/// pattern, but only when first asked for: a pinhole camera never asks, and
/// the values are the same whenever they are drawn.
#[derive(Clone, Debug)]
pub struct PixelSampler {
    rng: Pcg32,
    film: Vec<Vec2>,
    lens: Vec<Vec2>,
    spp: u32,
    /// Whether `lens` holds this pixel's lens pattern yet.
    lens_ready: bool,
}

impl PixelSampler {
    /// A sampler with room for `spp` samples.
    pub fn new(spp: u32) -> Self {
        Self {
            rng: Pcg32::new(0, 0),
            film: Vec::with_capacity(spp as usize),
            lens: Vec::with_capacity(spp as usize),
            spp,
            lens_ready: false,
        }
    }

    /// Generate the samples of pixel `(x, y)`.
    pub fn start_pixel(&mut self, seed: u64, x: u32, y: u32, spp: u32) {
        self.rng = Pcg32::new(mix_seed(&[seed, x as u64, y as u64]), mix_seed(&[y as u64, x as u64]));
        self.spp = spp;
        self.lens_ready = false;
        if spp == 1 {
            self.film.clear();
            self.film.push(Vec2::splat(0.5));
        } else {
            stratified_2d(spp, &mut self.rng, &mut self.film);
        }
    }

    /// Draw the lens pattern, the generator's next values after the film
    /// pattern, if that has not been done for this pixel.
    #[inline]
    fn ensure_lens(&mut self) {
        if self.lens_ready {
            return;
        }
        if self.spp == 1 {
            self.lens.clear();
            self.lens.push(Vec2::new(self.rng.uniform(), self.rng.uniform()));
        } else {
            stratified_2d(self.spp, &mut self.rng, &mut self.lens);
        }
        self.lens_ready = true;
    }

    /// Offset of sample `i` within the pixel, in `[0, 1)²`.
    #[inline]
    pub fn film(&self, i: usize) -> Vec2 {
        self.film[i]
    }

    /// Lens sample `i`, in `[0, 1)²`.
    #[inline]
    pub fn lens(&mut self, i: usize) -> Vec2 {
        self.ensure_lens();
        self.lens[i]
    }

    /// The pixel's generator, for any further random decisions (its state
    /// follows the lens pattern, drawn now if it was not yet).
    pub fn rng(&mut self) -> &mut Pcg32 {
        self.ensure_lens();
        &mut self.rng
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_counts_fill_every_cell_once() {
        let mut rng = Pcg32::new(3, 4);
        let mut v = Vec::new();
        stratified_2d(25, &mut rng, &mut v);
        let mut cells = [0u8; 25];
        for s in &v {
            cells[(s.y * 5.0) as usize * 5 + (s.x * 5.0) as usize] += 1;
        }
        assert!(cells.iter().all(|&c| c == 1));
    }

    #[test]
    fn other_counts_are_latin_hypercube() {
        let mut rng = Pcg32::new(3, 4);
        let mut v = Vec::new();
        stratified_2d(7, &mut rng, &mut v);
        let mut xs = [0u8; 7];
        let mut ys = [0u8; 7];
        for s in &v {
            xs[(s.x * 7.0) as usize] += 1;
            ys[(s.y * 7.0) as usize] += 1;
        }
        assert!(xs.iter().chain(ys.iter()).all(|&c| c == 1));
    }

    #[test]
    fn one_sample_is_the_pixel_centre_and_pixels_are_reproducible() {
        let mut s = PixelSampler::new(1);
        s.start_pixel(9, 3, 4, 1);
        assert_eq!(s.film(0), Vec2::splat(0.5));
        let mut a = PixelSampler::new(16);
        let mut b = PixelSampler::new(16);
        a.start_pixel(9, 3, 4, 16);
        b.start_pixel(9, 5, 5, 16);
        b.start_pixel(9, 3, 4, 16);
        assert_eq!(a.film, b.film);
        assert_eq!((0..16).map(|i| a.lens(i)).collect::<Vec<_>>(), (0..16).map(|i| b.lens(i)).collect::<Vec<_>>());
    }
}
