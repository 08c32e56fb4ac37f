//! Adaptive sampling: stop sampling the pixels whose estimated error is
//! below a threshold, so that the samples go where the noise is.
//!
//! The error of a pixel is estimated from two interleaved halves of its
//! samples, as Blender's Cycles does (`film_adaptive_sampling_convergence_check`,
//! after Rousselle et al.'s half-buffers): with `I` the mean of all its
//! samples and `A` the mean of the odd-numbered ones,
//!
//! ```text
//! error = (|I_r − A_r| + |I_g − A_g| + |I_b − A_b|) / (10⁻⁴ + √(I_r + I_g + I_b))
//! ```
//!
//! a difference relative to the square root of the pixel's brightness
//! (a relative error that does not chase the last noise of dark pixels; the
//! 10⁻⁴ is the floor for black ones). A pixel stops once the error of
//! every pixel within one pixel of it (itself and its eight neighbours) is
//! below the threshold: the dilation keeps the neighbours of a noisy pixel
//! sampling, so an isolated noisy pixel is not starved by converged ones
//! around it.
//!
//! Decisions are taken only at fixed sample counts ([`is_decision_point`]:
//! 16, 24, 32, ... samples), whatever the passes, threads or time budget of
//! the render, and only from the exact fixed-point sums: so an adaptive
//! render is bit-identical for any thread count, and when resumed.

use super::Accumulator;

/// Samples every pixel takes before the first decision.
pub const ADAPTIVE_MIN_SPP: u32 = 16;
/// Samples between two decisions.
pub const ADAPTIVE_STEP: u32 = 8;

/// Whether adaptive sampling decides after `spp` samples.
pub fn is_decision_point(spp: u32) -> bool {
    spp >= ADAPTIVE_MIN_SPP && spp.is_multiple_of(ADAPTIVE_STEP)
}

/// The first decision point after `spp` samples.
pub fn next_decision_point(spp: u32) -> u32 {
    if spp < ADAPTIVE_MIN_SPP {
        ADAPTIVE_MIN_SPP
    } else {
        (spp / ADAPTIVE_STEP + 1) * ADAPTIVE_STEP
    }
}

/// The error estimate of a pixel from its sums (colour and weight of all
/// its samples, then of the odd-numbered half); infinite while the half
/// holds no weight.
pub fn pixel_error(all: [i64; 4], odd: [i64; 4]) -> f64 {
    if all[3] == 0 || odd[3] == 0 {
        return f64::INFINITY;
    }
    let mean = |s: [i64; 4]| [0, 1, 2].map(|c| s[c] as f64 / s[3] as f64);
    let (i, a) = (mean(all), mean(odd));
    let difference: f64 = (0..3).map(|c| (i[c] - a[c]).abs()).sum();
    let intensity: f64 = i.iter().sum::<f64>().max(0.0);
    difference / (1e-4 + intensity.sqrt())
}

impl Accumulator {
    /// Adaptive sampling's decision: stop every pixel still sampling whose
    /// error, and that of its eight neighbours, is below `threshold`.
    /// Returns how many pixels were stopped. Does nothing on an
    /// accumulator without adaptive state.
    pub fn stop_converged(&mut self, threshold: f32) -> usize {
        if !self.is_adaptive() {
            return 0;
        }
        let (w, h) = (self.width() as usize, self.height() as usize);
        let odd_at = 4 + self.aovs().stored_channels();
        let converged: Vec<bool> = (0..w * h)
            .map(|i| {
                let s: Vec<i64> = self.pixel_raw(i).collect();
                let all = [s[0], s[1], s[2], s[3]];
                let odd = [s[odd_at], s[odd_at + 1], s[odd_at + 2], s[odd_at + 3]];
                pixel_error(all, odd) < threshold as f64
            })
            .collect();
        // Dilate the pixels that have not converged by one pixel.
        let mut stop = vec![false; w * h];
        for y in 0..h {
            for x in 0..w {
                let rows = y.saturating_sub(1)..=(y + 1).min(h - 1);
                stop[y * w + x] = rows
                    .into_iter()
                    .all(|yy| (x.saturating_sub(1)..=(x + 1).min(w - 1)).all(|xx| converged[yy * w + xx]));
            }
        }
        self.stop(&stop)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Color;
    use crate::film::AovSet;

    #[test]
    fn decision_points_are_fixed_sample_counts() {
        let points: Vec<u32> = (0..60).filter(|&s| is_decision_point(s)).collect();
        assert_eq!(points, [16, 24, 32, 40, 48, 56]);
        assert_eq!(next_decision_point(0), 16);
        assert_eq!(next_decision_point(16), 24);
        assert_eq!(next_decision_point(17), 24);
    }

    #[test]
    fn the_error_is_the_half_buffers_difference_relative_to_the_brightness() {
        let one = 1i64 << 20;
        // All samples mean 1, the odd half 0.9: difference 0.3 over √3.
        let e = pixel_error([one, one, one, one], [9 * one / 10, 9 * one / 10, 9 * one / 10, one]);
        assert!((e - 0.3 / (1e-4 + 3f64.sqrt())).abs() < 1e-6, "{e}");
        assert_eq!(pixel_error([0; 4], [0; 4]), f64::INFINITY);
        assert_eq!(pixel_error([0, 0, 0, one], [0, 0, 0, one]), 0.0);
    }

    /// A noisy pixel keeps itself and its neighbours sampling; the rest
    /// stop, and stopped pixels take no more samples.
    #[test]
    fn converged_pixels_stop_and_a_noisy_one_keeps_its_neighbours() {
        let mut acc = Accumulator::with_layout(5, 4, AovSet::NONE, true).unwrap();
        for y in 0..4 {
            for x in 0..5 {
                for k in 0..2 {
                    // Sample 1 is odd; the noisy pixel's odd sample differs.
                    let l = if (x, y, k) == (1, 1, 1) { 3.0 } else { 0.5 };
                    let aux = if k == 1 { [l, l, l, 1.0] } else { [0.0; 4] };
                    acc.splat_with_aovs(x, y, Color::splat(l), &aux, 1.0);
                }
            }
        }
        acc.add_spp(2);
        assert_eq!(acc.stop_converged(0.01), 20 - 9);
        for y in 0..4 {
            for x in 0..5 {
                assert_eq!(acc.is_active(x, y), x <= 2 && y <= 2, "({x}, {y})");
            }
        }
        acc.add_spp(3);
        let counts = acc.sample_counts().unwrap();
        assert_eq!(counts[0], 5);
        assert_eq!(counts[4], 2);
        assert_eq!(acc.active_pixels(), 9);
    }
}
