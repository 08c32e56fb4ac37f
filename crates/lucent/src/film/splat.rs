//! Splatting the samples of one image row: each sample is added, weighted
//! by the reconstruction filter, to every pixel whose filter covers it
//! (PBRT 3rd ed. §7.8). A row's samples reach a band of rows around it; the
//! band is summed here, in plain integers, and added to the shared
//! [`Accumulator`] once when the row is done.
//!
//! Both steps give exactly the sums of splatting every sample straight into
//! the accumulator: the weights are the same products `f₁(x)·f₁(y)`, and
//! fixed-point integer addition is exact and associative. What they save is
//! work: the separable filter is evaluated once per footprint column and
//! row instead of twice per pixel (a Gaussian evaluates two `exp` each
//! time), and the atomic additions, which serialise the core, come once per
//! pixel of the band and row instead of once per sample and pixel.
//!
//! The renderer traces a row's samples in runs (a sample index across up
//! to 64 pixels), and a run's filter factors are computed together
//! ([`SplatBand::weigh`]): a Gaussian's six `exp` for a sample's 3 × 3
//! footprint fill a vector register only across samples. With AVX-512 a
//! footprint row of up to four pixels then takes one kernel call, its
//! sixteen sums converted to fixed point in two registers
//! ([`SplatBand::add_weighed`]). The sums are the same integers as one
//! sample and one pixel at a time.

use super::{fixed_contribution, fixed_value, Accumulator, Filter, Filter1d};
use crate::color::Color;
use crate::geometry::{Isa, Vec2};

/// The builds of [`SplatBand::add_footprint`] (its `BUILD`): portable,
/// AVX2, AVX-512.
const PORTABLE: u8 = 0;
const AVX2: u8 = 1;
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
const AVX512: u8 = 2;

/// The offsets of [`SplatBand::add_footprint`]'s columns and rows from
/// samples at in-pixel positions `us`, `m` of each from the footprint's
/// first, into `offsets` (column `i` of sample `j` at `i·n + j`, row `i`
/// at `(m + i)·n + j`, for `n` samples): k + ½ − u, the same values, as
/// k_lo + i is an integer (exact in f32) whichever way it is formed.
#[inline(always)]
fn footprint_offsets(us: &[Vec2], radius: f32, m: usize, offsets: &mut [f32]) {
    let n = us.len();
    for (j, &u) in us.iter().enumerate() {
        let k_lo = (u - Vec2::splat(0.5 + radius)).floor() + Vec2::ONE;
        for i in 0..m {
            offsets[i * n + j] = (k_lo.x + i as f32) + 0.5 - u.x;
            offsets[(m + i) * n + j] = (k_lo.y + i as f32) + 0.5 - u.y;
        }
    }
}

/// [`footprint_offsets`] compiled for AVX2, whose `vroundss` floors
/// without a call to the C library.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn footprint_offsets_avx2(us: &[Vec2], radius: f32, m: usize, offsets: &mut [f32]) {
    footprint_offsets(us, radius, m, offsets);
}

/// How many rows above and below its own a band holds.
pub const MAX_BAND_REACH: i64 = 16;

/// The most columns (and rows) of a footprint that [`SplatBand::weigh`]
/// weighs for a run: a Gaussian of radius up to 2.
const MAX_RUN_FOOTPRINT: usize = 4;

/// A band of rows of fixed-point sums `[Σw·r, Σw·g, Σw·b, Σw]` (and
/// `Σw·a` of each AOV channel, laid out as the [`Accumulator`]'s): the
/// share of one image row's samples in every pixel they reach.
#[derive(Clone, Debug)]
pub struct SplatBand {
    /// The filter's 1D factor.
    filter: Filter1d,
    /// The filter radius, in pixels.
    radius: f32,
    /// Whether the filter is a box over exactly the pixel: every sample
    /// then lands in its own pixel with weight 1.
    pixel_box: bool,
    width: u32,
    height: u32,
    /// The image row whose samples the band holds.
    y: u32,
    /// Offset (from `y`) of the band's first row; it has `rows` rows.
    first: i64,
    rows: usize,
    /// Sums per pixel: 4 and the AOV channels.
    stride: usize,
    sums: Vec<i64>,
    /// The filter's factors of the current sample's footprint columns and
    /// rows.
    wx: Vec<f32>,
    wy: Vec<f32>,
    /// The filter's factors of the footprints of a run of samples, weighed
    /// together ([`weigh`](Self::weigh)): `run_m` columns, then `run_m`
    /// rows, from each footprint's first before clipping to the image,
    /// for each of the run's `run_len` samples (factor `m` of sample `j`
    /// at `m·run_len + j`); `run_m` is 0 where the filter is weighed
    /// sample by sample.
    run_weights: Vec<f32>,
    /// The offsets of those columns and rows from the samples.
    run_offsets: Vec<f32>,
    run_m: usize,
    run_len: usize,
    /// Which build of [`add`](Self::add) runs: AVX-512 or AVX2 where the
    /// CPU has it and `LUCENT_SIMD` allows it, else the portable one.
    isa: Isa,
}

impl SplatBand {
    /// An empty band for an image `width` × `height` under `filter`, of
    /// `stride` sums per pixel (the accumulator's
    /// [`stride`](Accumulator::stride)).
    ///
    /// A sample at `y + u` (with `0 ≤ u < 1`) reaches the rows `y + k` whose
    /// centres `k + ½` lie within the radius `r`: `u − ½ − r < k ≤ u − ½ + r`,
    /// so `k` lies in `[⌊−½ − r⌋, ⌈r + ½⌉]` (one row of margin each side,
    /// against rounding). The band holds at most [`MAX_BAND_REACH`] rows
    /// each side; the rare filter that reaches further adds its far rows
    /// straight to the accumulator.
    pub fn new(filter: &Filter, width: u32, height: u32, stride: usize) -> Self {
        let radius = filter.radius();
        let first = ((-0.5 - radius).floor() as i64).max(-MAX_BAND_REACH);
        let last = ((radius + 0.5).ceil() as i64).min(MAX_BAND_REACH);
        let rows = (last - first + 1) as usize;
        Self {
            filter: Filter1d::new(filter),
            radius,
            pixel_box: matches!(*filter, Filter::Box { radius } if radius == 0.5),
            width,
            height,
            y: 0,
            first,
            rows,
            stride,
            sums: vec![0; rows * width as usize * stride],
            // A footprint spans at most 2r + 1 columns and rows (and no
            // more than the image).
            wx: vec![0.0; ((2.0 * radius).ceil() as usize).saturating_add(2).min(width as usize)],
            wy: vec![0.0; ((2.0 * radius).ceil() as usize).saturating_add(2).min(height as usize)],
            run_weights: Vec::new(),
            run_offsets: Vec::new(),
            run_m: 0,
            run_len: 0,
            isa: crate::geometry::isa(),
        }
    }

    /// Empty the band for the samples of row `y`.
    pub fn start_row(&mut self, y: u32) {
        self.y = y;
        self.run_m = 0;
        self.sums.fill(0);
    }

    /// Add the sample's contribution with filter weight `w` to the sums of
    /// pixel `px` in the band's row `y + k`.
    #[inline(always)]
    fn add_at(&mut self, k: i64, px: usize, l: Color, aux: &[f32], w: f32) {
        self.add_at_with::<PORTABLE>(k, px, l, aux, w);
    }

    /// [`add_at`](Self::add_at), with the colour's sums added by the AVX2
    /// kernel in the AVX2 and AVX-512 builds (only in code compiled for
    /// AVX2).
    #[inline(always)]
    fn add_at_with<const BUILD: u8>(&mut self, k: i64, px: usize, l: Color, aux: &[f32], w: f32) {
        let row = (k - self.first) as usize;
        debug_assert!(row < self.rows, "footprint row {k} outside the band");
        let i = (row * self.width as usize + px) * self.stride;
        let colour: &mut [i64; 4] = (&mut self.sums[i..i + 4]).try_into().expect("4 sums");
        if cfg!(target_arch = "x86_64") && BUILD >= AVX2 {
            // SAFETY: `BUILD` is `AVX2` or `AVX512` only in
            // `add_footprint_avx2` and `add_footprint_avx512`, which run
            // only where the CPU has AVX2 (and AVX-512).
            #[cfg(target_arch = "x86_64")]
            unsafe {
                super::accumulator::add_contribution_avx2(colour, l, w)
            };
        } else {
            for (s, c) in colour.iter_mut().zip(fixed_contribution(l, w)) {
                *s += c;
            }
        }
        if !aux.is_empty() {
            self.add_aux(i + 4, aux, w);
        }
    }

    /// The AOV (and adaptive) channels of [`add_at`](Self::add_at), out of
    /// line: renders without them never come here.
    #[inline(never)]
    fn add_aux(&mut self, at: usize, aux: &[f32], w: f32) {
        for (s, &a) in self.sums[at..at + aux.len()].iter_mut().zip(aux) {
            *s += fixed_value(a, w);
        }
    }

    /// Add a sample of radiance `l` at `u` (in `[0, 1)²`) within pixel
    /// `(x, y)` of the band's row to every pixel it reaches (in `acc`
    /// directly for rows beyond the band), with its AOV channels `aux`
    /// (empty without AOVs). It forgets the run last
    /// [`weigh`](Self::weigh)ed.
    pub fn add(&mut self, x: u32, u: Vec2, l: Color, aux: &[f32], acc: &Accumulator) {
        self.run_m = 0;
        self.add_sample(None, x, u, l, aux, acc);
    }

    /// Weigh a run of samples at in-pixel positions `us` together: the
    /// filter's factors of all their footprints, computed in vector code
    /// where the filter has it (a Gaussian: about two `exp` a column or
    /// row, too few per sample to fill the vector lanes one sample at a
    /// time). [`add_weighed`](Self::add_weighed) then adds them.
    pub fn weigh(&mut self, us: &[Vec2]) {
        // A footprint has at most ⌈2r⌉ columns (and rows): u − ½ − r < k ≤
        // u − ½ + r. (Where rounding gives it one more, the sample is
        // weighed alone.)
        let m = (2.0 * self.radius).ceil() as usize;
        self.run_m = 0;
        if self.pixel_box || !self.filter.has_lanes(self.isa) || m > MAX_RUN_FOOTPRINT {
            return;
        }
        let n = us.len();
        self.run_offsets.resize(2 * m * n, 0.0);
        self.run_weights.resize(2 * m * n, 0.0);
        match self.isa {
            // SAFETY: `isa` is `Avx2` or `Avx512` only where the CPU has
            // AVX2.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 | Isa::Avx512 => unsafe { footprint_offsets_avx2(us, self.radius, m, &mut self.run_offsets) },
            _ => footprint_offsets(us, self.radius, m, &mut self.run_offsets),
        }
        self.filter.evaluate_many_as(self.isa, &self.run_offsets, &mut self.run_weights);
        (self.run_m, self.run_len) = (m, n);
    }

    /// Add sample `lane` of the run last [`weigh`](Self::weigh)ed in this
    /// row (`u` must be the `us[lane]` weighed), of radiance `l` at `u`
    /// within pixel `(x, y)` of the band's row, as [`add`](Self::add) adds
    /// it (the same sums), with the factors weighed for it.
    pub fn add_weighed(&mut self, lane: usize, x: u32, u: Vec2, l: Color, aux: &[f32], acc: &Accumulator) {
        let lane = (self.run_m > 0).then(|| {
            assert!(lane < self.run_len, "sample {lane} of a run of {}", self.run_len);
            lane
        });
        self.add_sample(lane, x, u, l, aux, acc);
    }

    /// The body of [`add`](Self::add) and [`add_weighed`](Self::add_weighed).
    #[inline(always)]
    fn add_sample(&mut self, lane: Option<usize>, x: u32, u: Vec2, l: Color, aux: &[f32], acc: &Accumulator) {
        if self.pixel_box {
            self.add_at(0, x as usize, l, aux, 1.0);
            return;
        }
        match self.isa {
            // SAFETY: `isa` is `Avx512` only where the CPU has its features.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => unsafe { self.add_footprint_avx512(lane, x, u, l, aux, acc) },
            // SAFETY: `isa` is `Avx2` only where the CPU has AVX2.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { self.add_footprint_avx2(lane, x, u, l, aux, acc) },
            _ => self.add_footprint::<PORTABLE>(lane, x, u, l, aux, acc),
        }
    }

    /// [`add_footprint`](Self::add_footprint) compiled for AVX2: the same
    /// operations in the same order (bit-identical sums; tests compare the
    /// builds), with the fixed-point conversion in four lanes.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn add_footprint_avx2(
        &mut self,
        lane: Option<usize>,
        x: u32,
        u: Vec2,
        l: Color,
        aux: &[f32],
        acc: &Accumulator,
    ) {
        self.add_footprint::<AVX2>(lane, x, u, l, aux, acc);
    }

    /// [`add_footprint`](Self::add_footprint) compiled for AVX-512, whose
    /// rows of up to four pixels take one kernel call each, not one a
    /// pixel ([`add_rows_avx512`](Self::add_rows_avx512)): the same sums.
    ///
    /// # Safety
    /// The CPU must have the features of `Isa::Avx512`.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
    unsafe fn add_footprint_avx512(
        &mut self,
        lane: Option<usize>,
        x: u32,
        u: Vec2,
        l: Color,
        aux: &[f32],
        acc: &Accumulator,
    ) {
        self.add_footprint::<AVX512>(lane, x, u, l, aux, acc);
    }

    /// The body of [`add`](Self::add) for filters wider than the pixel box,
    /// with the factors weighed for sample `lane` of a run where it has
    /// them.
    #[inline(always)]
    fn add_footprint<const BUILD: u8>(
        &mut self,
        lane: Option<usize>,
        x: u32,
        u: Vec2,
        l: Color,
        aux: &[f32],
        acc: &Accumulator,
    ) {
        // The footprint: offsets k with u − ½ − r < k ≤ u − ½ + r. The
        // interval is half open, so a box filter of radius ½ puts every
        // sample in exactly its own pixel, and the offsets are computed from
        // the in-pixel position u, free of the rounding of x + u.
        let k_lo = (u - Vec2::splat(0.5 + self.radius)).floor() + Vec2::ONE;
        let k_hi = (u + Vec2::splat(self.radius - 0.5)).floor();
        if k_lo == Vec2::ZERO && k_hi == Vec2::ZERO {
            // Only its own pixel (a box of radius ½).
            let offset = Vec2::splat(0.5) - u;
            let weight = self.filter.evaluate(offset.x) * self.filter.evaluate(offset.y);
            if weight != 0.0 {
                self.add_at_with::<BUILD>(0, x as usize, l, aux, weight);
            }
            return;
        }
        // Only pixels of the image count.
        let (w, h) = (self.width as i64, self.height as i64);
        let (x, y) = (x as i64, self.y as i64);
        let (kx_lo, kx_hi) = ((k_lo.x as i64).max(-x), (k_hi.x as i64).min(w - 1 - x));
        let (ky_lo, ky_hi) = ((k_lo.y as i64).max(-y), (k_hi.y as i64).min(h - 1 - y));
        // The separable filter's factors: f₁ at each column's and each
        // row's offset, the very values `Filter::evaluate` multiplies. (The
        // footprint never holds more columns or rows than `wx` and `wy`.)
        let (nx, ny) = ((kx_hi - kx_lo + 1).max(0) as usize, (ky_hi - ky_lo + 1).max(0) as usize);
        let filter = self.filter;
        let band = self.first..self.first + self.rows as i64;
        // The run's factors of this footprint's columns and rows (from
        // `sx`, `sy` on, past those clipped away), where they hold them all.
        let (sx, sy) = ((kx_lo - k_lo.x as i64) as usize, (ky_lo - k_lo.y as i64) as usize);
        let (m, n) = (self.run_m, self.run_len);
        let weighed = lane.filter(|_| sx + nx <= m && sy + ny <= m);
        let run = |i: usize, j: usize| self.run_weights[i * n + j];
        #[cfg(target_arch = "x86_64")]
        if let Some(j) = weighed.filter(|_| {
            BUILD == AVX512
                && self.stride == 4
                && nx <= 4
                && (1..=4).contains(&ny)
                && band.contains(&ky_lo)
                && band.contains(&(ky_lo + ny as i64 - 1))
        }) {
            // The common case with AVX-512: a footprint of up to four
            // columns, all its rows in the band, weighed with its run.
            let wx: [f32; 4] = std::array::from_fn(|i| if i < nx { run(sx + i, j) } else { 0.0 });
            let wy: [f32; 4] = std::array::from_fn(|r| if r < ny { run(m + sy + r, j) } else { 0.0 });
            // SAFETY: `BUILD` is `AVX512` only in `add_footprint_avx512`.
            unsafe { self.add_rows_avx512(ky_lo, (x + kx_lo) as usize, [nx, ny], l, wx, wy) };
            return;
        }
        if nx == 2 && ny == 2 && aux.is_empty() && band.contains(&ky_lo) && band.contains(&(ky_lo + 1)) {
            // The common footprint (a tent of radius 1, a box of radius 1
            // away from the edges): 2 × 2 pixels of the band, without the
            // loops. The same weights, added to the same sums.
            let (wx, wy) = match weighed {
                Some(j) => ([run(sx, j), run(sx + 1, j)], [run(m + sy, j), run(m + sy + 1, j)]),
                None => {
                    let x0 = (kx_lo as f32 + 0.5 - u.x, (kx_lo + 1) as f32 + 0.5 - u.x);
                    let y0 = (ky_lo as f32 + 0.5 - u.y, (ky_lo + 1) as f32 + 0.5 - u.y);
                    ([filter.evaluate(x0.0), filter.evaluate(x0.1)], [filter.evaluate(y0.0), filter.evaluate(y0.1)])
                }
            };
            let px = (x + kx_lo) as usize;
            for (j, wy) in wy.into_iter().enumerate() {
                for (i, wx) in wx.into_iter().enumerate() {
                    let weight = wx * wy;
                    if weight != 0.0 {
                        self.add_at_with::<BUILD>(ky_lo + j as i64, px + i, l, aux, weight);
                    }
                }
            }
            return;
        }
        let column = |i: usize| (kx_lo + i as i64) as f32 + 0.5 - u.x;
        let row = |j: usize| (ky_lo + j as i64) as f32 + 0.5 - u.y;
        if let Some(j) = weighed {
            for i in 0..nx {
                self.wx[i] = self.run_weights[(sx + i) * n + j];
            }
            for i in 0..ny {
                self.wy[i] = self.run_weights[(m + sy + i) * n + j];
            }
        } else if nx + ny <= 8 {
            // Columns and rows together in one set of lanes (a Gaussian of
            // radius 1.5 has 3 of each): their factors computed side by
            // side, the values of `evaluate`.
            let mut x = [0.0; 8];
            for (k, x) in x.iter_mut().enumerate() {
                *x = if k < nx { column(k) } else { row(k - nx) };
            }
            let w = filter.evaluate8(x);
            self.wx[..nx].copy_from_slice(&w[..nx]);
            self.wy[..ny].copy_from_slice(&w[nx..nx + ny]);
        } else {
            for (i, w) in self.wx[..nx].iter_mut().enumerate() {
                *w = filter.evaluate(column(i));
            }
            for (j, w) in self.wy[..ny].iter_mut().enumerate() {
                *w = filter.evaluate(row(j));
            }
        }
        for j in 0..ny {
            let (ky, wy) = (ky_lo + j as i64, self.wy[j]);
            let in_band = band.contains(&ky);
            #[cfg(target_arch = "x86_64")]
            if BUILD == AVX512 && in_band && self.stride == 4 && nx <= 4 {
                let wx = std::array::from_fn(|i| if i < nx { self.wx[i] } else { 0.0 });
                // SAFETY: `BUILD` is `AVX512` only in `add_footprint_avx512`.
                unsafe { self.add_rows_avx512(ky, (x + kx_lo) as usize, [nx, 1], l, wx, [wy, 0.0, 0.0, 0.0]) };
                continue;
            }
            for i in 0..nx {
                let weight = self.wx[i] * wy;
                if weight == 0.0 {
                    continue;
                }
                let px = (x + kx_lo) as usize + i;
                if in_band {
                    self.add_at_with::<BUILD>(ky, px, l, aux, weight);
                } else {
                    acc.splat_with_aovs(px as u32, (y + ky) as u32, l, aux, weight);
                }
            }
        }
    }

    /// Add a sample of radiance `l` to the footprint of `nx ≤ 4` columns
    /// from pixel `px` and `ny ≤ 4` rows from the band's row `y + k` on
    /// (all in the band, of four sums a pixel), with filter weights
    /// `wx[i]·wy[r]`: the sums of [`add_at`](Self::add_at) for each pixel
    /// (a weight of 0 adds nothing, as there), a kernel call a
    /// row ([`add_contributions_avx512`](super::accumulator::add_contributions_avx512)).
    ///
    /// # Safety
    /// The CPU must have the features of `Isa::Avx512`.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
    unsafe fn add_rows_avx512(
        &mut self,
        k: i64,
        px: usize,
        [nx, ny]: [usize; 2],
        l: Color,
        wx: [f32; 4],
        wy: [f32; 4],
    ) {
        assert_eq!(self.stride, 4, "four sums a pixel: no AOV channels, no light image");
        for (r, wy) in wy.into_iter().enumerate().take(ny) {
            let row = (k + r as i64 - self.first) as usize;
            debug_assert!(row < self.rows, "footprint row {} outside the band", k + r as i64);
            let i = (row * self.width as usize + px) * 4;
            let sums = &mut self.sums[i..i + 4 * nx];
            // SAFETY: the CPU has AVX-512 (this function's contract).
            unsafe { super::accumulator::add_contributions_avx512(sums, nx, l, wx.map(|wx| wx * wy)) };
        }
    }

    /// Add a sample of radiance `l` (and AOV channels `aux`) to its own
    /// pixel `x` of the band's row alone, with weight `w`: a sample placed
    /// by filter importance sampling.
    pub fn add_own(&mut self, x: u32, l: Color, aux: &[f32], w: f32) {
        self.add_at(0, x as usize, l, aux, w);
    }

    /// Add the band's sums to `acc`, pixels of the image only.
    pub fn flush(&self, acc: &Accumulator) {
        let w = self.width as usize;
        for (row, sums) in self.sums.chunks_exact(w * self.stride).enumerate() {
            let py = self.y as i64 + self.first + row as i64;
            if py < 0 || py >= self.height as i64 {
                continue;
            }
            for (px, s) in sums.chunks_exact(self.stride).enumerate() {
                // Every sample adds its weight (to `s[3]`, or its colour
                // where the weight rounds to 0), so a pixel no sample
                // reached is all zeros.
                if s.iter().any(|&v| v != 0) {
                    acc.add_fixed(px as u32, py as u32, s);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::{Aov, AovSet};
    use crate::sampling::Pcg32;

    /// Splatting every sample straight into the accumulator, pixel by
    /// pixel with `Filter::evaluate`, as the renderer did before bands.
    fn splat_directly(acc: &Accumulator, filter: &Filter, x: u32, y: u32, u: Vec2, l: Color, aux: &[f32]) {
        let r = filter.radius();
        let k_lo = (u - Vec2::splat(0.5 + r)).floor() + Vec2::ONE;
        let k_hi = (u + Vec2::splat(r - 0.5)).floor();
        for ky in k_lo.y as i64..=k_hi.y as i64 {
            for kx in k_lo.x as i64..=k_hi.x as i64 {
                let (px, py) = (x as i64 + kx, y as i64 + ky);
                if px < 0 || py < 0 || px >= acc.width() as i64 || py >= acc.height() as i64 {
                    continue;
                }
                let weight = filter.evaluate(Vec2::new(kx as f32 + 0.5 - u.x, ky as f32 + 0.5 - u.y));
                if weight != 0.0 {
                    acc.splat_with_aovs(px as u32, py as u32, l, aux, weight);
                }
            }
        }
    }

    /// Bands give bit for bit the sums of splatting each sample directly,
    /// for every kind of filter and radius, at the image's edges too.
    #[test]
    fn bands_equal_direct_splats() {
        // A sample: its pixel's column, its place in the pixel, its
        // radiance and its AOV channels.
        type Sample = (u32, Vec2, Color, Vec<f32>);
        let filters = [
            Filter::Box { radius: 0.5 },
            Filter::Box { radius: 1.0 },
            Filter::Tent { radius: 1.0 },
            Filter::Tent { radius: 0.3 },
            Filter::Gaussian { radius: 1.5, sigma: 0.5 },
            // Footprints of at most 1, 2, 4 and 5 columns: weighed in runs
            // (the 2 × 2 branch among them, and empty footprints), and too
            // wide for a run.
            Filter::Gaussian { radius: 0.3, sigma: 0.2 },
            Filter::Gaussian { radius: 1.0, sigma: 0.4 },
            Filter::Gaussian { radius: 2.0, sigma: 0.5 },
            Filter::Gaussian { radius: 2.5, sigma: 1.0 },
            Filter::Mitchell { radius: 2.0, b: 1.0 / 3.0, c: 1.0 / 3.0 },
            Filter::Lanczos { radius: 3.0, tau: 3.0 },
            // Beyond the band's reach: far rows go straight to the
            // accumulator.
            Filter::Gaussian { radius: 20.0, sigma: 8.0 },
        ];
        // Every build the CPU runs, each adding samples one at a time and
        // in weighed runs (of all a row's pixels, up to 64, and of 5).
        #[cfg_attr(not(target_arch = "x86_64"), allow(unused_mut))]
        let mut builds = vec![Isa::Portable];
        #[cfg(target_arch = "x86_64")]
        builds.extend([Isa::Avx2, Isa::Avx512].into_iter().filter(|&b| b <= crate::geometry::simd_detected()));
        // Without AOVs, with two, and with a light image alone (three sums
        // a pixel that the band carries and the samples leave at 0).
        let aovs = [AovSet::NONE, AovSet::of(&[Aov::Albedo, Aov::Depth]), AovSet::NONE.with_light_image()];
        for (filter, aovs) in filters.iter().flat_map(|f| aovs.map(|a| (f, a))) {
            // A row wider than a run, but few rows for the widest filter.
            let (w, h) = if filter.radius() > 3.0 { (7, 40) } else { (70, 9) };
            let mut rng = Pcg32::new(3, 1);
            // Each row's samples, six a pixel, in the renderer's order:
            // a sample index at a time across the row.
            let rows: Vec<Vec<Sample>> = (0..h)
                .map(|_| {
                    (0..6 * w)
                        .map(|i| {
                            // Now and then a sample at a pixel's corner or
                            // middle, where footprint columns and rows at
                            // the radius weigh 0, and one of infinite
                            // radiance (0·∞ must not reach a sum).
                            let u = match i % 13 {
                                0 => Vec2::new(0.0, 0.5),
                                1 => Vec2::new(0.5, 0.0),
                                _ => Vec2::new(rng.uniform(), rng.uniform()),
                            };
                            let l = if i % 17 == 0 {
                                Color::new(f32::INFINITY, 1.0, 0.5)
                            } else {
                                Color::new(rng.uniform(), 2.0 * rng.uniform(), 0.5)
                            };
                            let aux = (0..aovs.channel_count()).map(|_| 10.0 * rng.uniform() - 2.0).collect();
                            (i % w, u, l, aux)
                        })
                        .collect()
                })
                .collect();
            let direct = Accumulator::with_aovs(w, h, aovs).unwrap();
            for (y, row) in rows.iter().enumerate() {
                for (x, u, l, aux) in row {
                    splat_directly(&direct, filter, *x, y as u32, *u, *l, aux);
                }
            }
            assert!(direct.raw().iter().any(|&s| s != 0));
            for (&build, run) in builds.iter().flat_map(|b| [None, Some(64), Some(5)].map(|r| (b, r))) {
                let banded = Accumulator::with_aovs(w, h, aovs).unwrap();
                let mut band = SplatBand::new(filter, w, h, banded.stride());
                band.isa = build;
                for (y, row) in rows.iter().enumerate() {
                    band.start_row(y as u32);
                    for samples in row.chunks(run.unwrap_or(1).min(w as usize)) {
                        if run.is_some() {
                            band.weigh(&samples.iter().map(|s| s.1).collect::<Vec<_>>());
                        }
                        for (j, (x, u, l, aux)) in samples.iter().enumerate() {
                            match run {
                                None => band.add(*x, *u, *l, aux, &banded),
                                Some(_) => band.add_weighed(j, *x, *u, *l, aux, &banded),
                            }
                        }
                    }
                    band.flush(&banded);
                }
                assert_eq!(direct.raw(), banded.raw(), "{filter:?}, {aovs:?}, {build:?}, runs of {run:?}");
            }
        }
    }

    #[test]
    fn light_splats_are_normalised_inside_the_image() {
        use crate::film::AovSet;
        for filter in
            [Filter::Box { radius: 0.5 }, Filter::Gaussian { radius: 1.5, sigma: 0.5 }, Filter::Tent { radius: 2.0 }]
        {
            let (w, h) = (9u32, 7u32);
            let splatter = LightSplatter::new(&filter, w, h);
            // A stratified spray of splats, 40 × 40 per pixel, of total
            // value w·h.
            let mut spray = Accumulator::with_aovs(w, h, AovSet::NONE.with_light_image()).unwrap();
            spray.add_spp(1);
            let (nx, ny) = (40 * w, 40 * h);
            let v = 1.0 / (40 * 40) as f32;
            for i in 0..nx {
                for j in 0..ny {
                    let p = Vec2::new((i as f32 + 0.5) / 40.0, (j as f32 + 0.5) / 40.0);
                    splatter.splat(&spray, p, Color::splat(v));
                }
            }
            for c in spray.to_film().pixels() {
                assert!((c.x - 1.0).abs() < 5e-3, "{filter:?}: a pixel of a uniform spray is {}", c.x);
            }
        }
    }
}

/// Splats of light tracing ([`Accumulator::add_light`]): a splat of value
/// `S` landing at film position `p` adds `w·S` to the light image of every
/// pixel whose filter covers it, with `w = f(p − c) / ∫_image f(x − c) dx`
/// for the pixel centre `c`: the filter normalised over the part of its
/// footprint inside the image. That is how a pixel's camera samples are
/// normalised too (their weighted mean divides by the sum of the weights,
/// which lands only inside the image), so both parts of a pixel are the
/// same filtered average, at the edges as well (pbrt-v4 divides by the
/// whole filter's integral, which darkens the light-traced share of edge
/// pixels under wide filters). The filter is separable, so the clipped
/// integral is a product of one per column and one per row.
#[derive(Clone, Debug)]
pub struct LightSplatter {
    filter: Filter1d,
    radius: f32,
    /// `1 / ∫ f₁` over the image, per column and per row.
    inv_x: Vec<f32>,
    inv_y: Vec<f32>,
}

impl LightSplatter {
    /// The splatter of `filter` on an image `width` × `height`.
    pub fn new(filter: &Filter, width: u32, height: u32) -> Self {
        let f1 = Filter1d::new(filter);
        let radius = filter.radius();
        // ∫ f₁(u − c) du over u ∈ [0, n] ∩ [c − r, c + r], c = i + ½: the
        // midpoint rule on 256 intervals.
        let clipped = |i: u32, n: u32| {
            let c = i as f64 + 0.5;
            let (a, b) = ((c - radius as f64).max(0.0), (c + radius as f64).min(n as f64));
            let steps = 256;
            let h = (b - a) / steps as f64;
            let s: f64 = (0..steps).map(|k| f1.eval_f64(a + (k as f64 + 0.5) * h - c)).sum::<f64>() * h;
            if s != 0.0 {
                (1.0 / s) as f32
            } else {
                0.0
            }
        };
        Self {
            radius,
            inv_x: (0..width).map(|x| clipped(x, width)).collect(),
            inv_y: (0..height).map(|y| clipped(y, height)).collect(),
            filter: f1,
        }
    }

    /// Add the splat `l` landing at film position `film` (pixels) to the
    /// light image of `acc`.
    pub fn splat(&self, acc: &Accumulator, film: Vec2, l: Color) {
        if !(film.x.is_finite() && film.y.is_finite()) {
            return;
        }
        // Pixel i's centre is i + ½: covered when |i + ½ − p| ≤ r.
        let span = |p: f32, n: usize| {
            let lo = (p - 0.5 - self.radius).ceil().max(0.0);
            let hi = (p - 0.5 + self.radius).floor().min(n as f32 - 1.0);
            (lo as i64, hi as i64)
        };
        let (x0, x1) = span(film.x, self.inv_x.len());
        let (y0, y1) = span(film.y, self.inv_y.len());
        for y in y0..=y1 {
            let wy = self.filter.evaluate(y as f32 + 0.5 - film.y) * self.inv_y[y as usize];
            if wy == 0.0 {
                continue;
            }
            for x in x0..=x1 {
                let w = wy * self.filter.evaluate(x as f32 + 0.5 - film.x) * self.inv_x[x as usize];
                if w != 0.0 {
                    acc.add_light(x as u32, y as u32, l * w);
                }
            }
        }
    }
}
