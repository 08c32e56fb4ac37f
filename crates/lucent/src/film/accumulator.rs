//! The film of progressive rendering: filter-weighted sums of samples per
//! pixel, kept in fixed point so that they are exact.

use super::{check_image_size, Aov, AovSet, Film, FilmError};
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
/// whose filter covers them). The image is their ratio. A render with
/// auxiliary images ([`AovSet`]) keeps `Σ wᵢ·aᵢ` of each of their
/// channels too, after the colour's four sums: the same weights, so each
/// layer is the same filtered average.
///
/// The sums are fixed-point integers updated atomically. Integer addition
/// is exact and associative, so the sums after `n` samples are
/// bit-identical however the work was split among threads, passes, or
/// interrupted and resumed runs, even though neighbouring rows rendered by
/// different threads add to the same pixels.
///
/// A film with a light image ([`AovSet::with_light_image`]) keeps three
/// more sums per pixel after the AOV channels: `Σ w·S` of the light-tracing
/// splats `S` that landed near it, each weighted by the normalised filter
/// ([`super::LightSplatter`]; pbrt-v4's `RGBFilm::AddSplat`). They estimate the
/// pixel's share of light reaching the camera straight from light
/// subpaths, and are added to the colour's mean divided by the samples per
/// pixel, as in pbrt-v4 (every camera sample traced one light subpath).
///
/// An accumulator for adaptive sampling (see [`super::adaptive`]) keeps,
/// after the AOV channels, the sums `Σw·r, Σw·g, Σw·b, Σw` of the
/// odd-numbered samples alone (the half-buffer its error estimate compares
/// with the whole), and each pixel's sample count: a pixel samples on while
/// its count equals [`spp`](Self::spp), and keeps the count it stopped at.
#[derive(Debug)]
pub struct Accumulator {
    width: u32,
    height: u32,
    spp: u32,
    aovs: AovSet,
    adaptive: bool,
    /// Sums per pixel: `4 + aovs.channel_count()`, and 4 more if adaptive.
    stride: usize,
    sums: Vec<AtomicI64>,
    /// Samples taken per pixel, with [`STOPPED`] set once adaptive
    /// sampling has stopped the pixel (adaptive only; empty otherwise).
    counts: Vec<u32>,
}

/// The flag of a pixel's sample count that marks it stopped by adaptive
/// sampling (sample counts are below 2²¹).
const STOPPED: u32 = 1 << 31;

impl Accumulator {
    /// An empty accumulator of colour only; the size is checked and the
    /// memory reserved fallibly.
    pub fn new(width: u32, height: u32) -> Result<Self, FilmError> {
        Self::with_aovs(width, height, AovSet::NONE)
    }

    /// An empty accumulator of colour and the auxiliary images `aovs`.
    pub fn with_aovs(width: u32, height: u32, aovs: AovSet) -> Result<Self, FilmError> {
        Self::with_layout(width, height, aovs, false)
    }

    /// An empty accumulator of colour, the auxiliary images `aovs` and, if
    /// `adaptive`, the state of adaptive sampling.
    pub fn with_layout(width: u32, height: u32, aovs: AovSet, adaptive: bool) -> Result<Self, FilmError> {
        check_image_size(width, height)?;
        let stride = Self::stride_of(aovs, adaptive);
        let pixels = width as usize * height as usize;
        let n = pixels * stride;
        let mut sums = Vec::new();
        sums.try_reserve_exact(n).map_err(|_| FilmError::OutOfMemory(width, height))?;
        sums.resize_with(n, Default::default);
        let counts = if adaptive { vec![0; pixels] } else { Vec::new() };
        Ok(Self { width, height, spp: 0, aovs, adaptive, stride, sums, counts })
    }

    fn stride_of(aovs: AovSet, adaptive: bool) -> usize {
        4 + aovs.stored_channels() + if adaptive { 4 } else { 0 }
    }

    /// Rebuild from stored fixed-point sums (a checkpoint): per pixel, row
    /// by row from the top, `[Σw·r, Σw·g, Σw·b, Σw]` and then `Σw·a` of each
    /// channel of `aovs`.
    pub fn from_raw(width: u32, height: u32, spp: u32, aovs: AovSet, raw: &[i64]) -> Result<Self, FilmError> {
        Self::from_parts(width, height, spp, aovs, raw, None)
    }

    /// Rebuild from stored sums laid out as [`raw`](Self::raw) gives them
    /// and, for adaptive sampling, the per-pixel sample counts (each at
    /// most `spp`).
    pub fn from_parts(
        width: u32,
        height: u32,
        spp: u32,
        aovs: AovSet,
        raw: &[i64],
        counts: Option<Vec<u32>>,
    ) -> Result<Self, FilmError> {
        check_image_size(width, height)?;
        let adaptive = counts.is_some();
        let stride = Self::stride_of(aovs, adaptive);
        let pixels = width as usize * height as usize;
        let counts = counts.unwrap_or_default();
        if raw.len() != pixels * stride
            || (adaptive && (counts.len() != pixels || counts.iter().any(|&c| c & !STOPPED > spp)))
        {
            return Err(FilmError::Empty(width, height));
        }
        let sums = raw.iter().map(|&s| AtomicI64::new(s)).collect();
        Ok(Self { width, height, spp, aovs, adaptive, stride, sums, counts })
    }

    /// The fixed-point sums, laid out as [`from_raw`](Self::from_raw)
    /// takes them.
    pub fn raw(&self) -> Vec<i64> {
        self.sums.iter().map(|s| s.load(Ordering::Relaxed)).collect()
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The auxiliary images accumulated besides colour.
    pub fn aovs(&self) -> AovSet {
        self.aovs
    }

    /// Fixed-point sums per pixel: 4 for colour and weight, then one per
    /// AOV channel.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Samples taken in every pixel so far.
    pub fn spp(&self) -> u32 {
        self.spp
    }

    /// Record that `n` more samples were taken in every pixel (every
    /// pixel still sampling, under adaptive sampling).
    pub fn add_spp(&mut self, n: u32) {
        let spp = self.spp;
        for c in self.counts.iter_mut().filter(|c| **c == spp) {
            *c += n;
        }
        self.spp += n;
    }

    /// Whether the accumulator keeps the state of adaptive sampling.
    pub fn is_adaptive(&self) -> bool {
        self.adaptive
    }

    /// Samples taken per pixel, row by row (adaptive sampling only).
    pub fn sample_counts(&self) -> Option<Vec<u32>> {
        self.adaptive.then(|| self.counts.iter().map(|&c| c & !STOPPED).collect())
    }

    /// The per-pixel state as stored in checkpoints: the sample count, with
    /// bit 31 set where adaptive sampling stopped the pixel.
    pub fn raw_counts(&self) -> Option<&[u32]> {
        self.adaptive.then_some(&self.counts[..])
    }

    /// Whether pixel `(x, y)` still takes samples (always, unless adaptive
    /// sampling stopped it).
    #[inline]
    pub fn is_active(&self, x: u32, y: u32) -> bool {
        !self.adaptive || self.counts[y as usize * self.width as usize + x as usize] == self.spp
    }

    /// Pixels still taking samples.
    pub fn active_pixels(&self) -> usize {
        if self.adaptive {
            self.counts.iter().filter(|&&c| c == self.spp).count()
        } else {
            self.width as usize * self.height as usize
        }
    }

    /// Stop the pixels whose `stop[i]` is set (adaptive sampling's
    /// decision; the others go on). Returns how many were stopped.
    pub(crate) fn stop(&mut self, stop: &[bool]) -> usize {
        debug_assert!(self.adaptive && stop.len() == self.counts.len());
        let mut n = 0;
        for (c, _) in self.counts.iter_mut().zip(stop).filter(|(_, &s)| s) {
            if *c & STOPPED == 0 {
                *c |= STOPPED;
                n += 1;
            }
        }
        n
    }

    /// The sums of pixel `i` (row-major): colour and weight, AOV channels,
    /// and for adaptive sampling the odd half's colour and weight last.
    pub(crate) fn pixel_raw(&self, i: usize) -> impl Iterator<Item = i64> + '_ {
        self.sums[i * self.stride..(i + 1) * self.stride].iter().map(|s| s.load(Ordering::Relaxed))
    }

    /// Add radiance `l` with filter weight `w` to pixel `(x, y)`. Safe to
    /// call from many threads at once.
    #[inline]
    pub fn splat(&self, x: u32, y: u32, l: Color, w: f32) {
        self.add_fixed(x, y, &fixed_contribution(l, w));
    }

    /// Add radiance `l` and the AOV channels `aux` (one value per channel
    /// of [`aovs`](Self::aovs)) with filter weight `w` to pixel `(x, y)`.
    #[inline]
    pub fn splat_with_aovs(&self, x: u32, y: u32, l: Color, aux: &[f32], w: f32) {
        let s = self.pixel_sums(x, y);
        for (sum, v) in s.iter().zip(fixed_contribution(l, w)) {
            sum.fetch_add(v, Ordering::Relaxed);
        }
        for (sum, &a) in s[4..].iter().zip(aux) {
            sum.fetch_add(fixed_value(a, w), Ordering::Relaxed);
        }
    }

    /// Add fixed-point sums (of [`fixed_contribution`]s, and for the AOV
    /// channels [`fixed_value`]s) to pixel `(x, y)`: the colour's four
    /// first, then as many AOV channels as `sums` holds. Integer addition is
    /// exact, so adding several samples' contributions at once gives the
    /// same sums as splatting them one by one.
    #[inline]
    pub fn add_fixed(&self, x: u32, y: u32, sums: &[i64]) {
        for (sum, &v) in self.pixel_sums(x, y).iter().zip(sums) {
            sum.fetch_add(v, Ordering::Relaxed);
        }
    }

    /// Add the light-tracing splat `s`, already weighted by the normalised
    /// filter, to pixel `(x, y)`'s light image (a film that keeps one:
    /// otherwise nothing happens).
    #[inline]
    pub fn add_light(&self, x: u32, y: u32, s: Color) {
        if !self.aovs.has_light_image() {
            return;
        }
        let at = 4 + self.aovs.channel_count();
        for (sum, v) in self.pixel_sums(x, y)[at..at + 3].iter().zip(s.to_array()) {
            sum.fetch_add(fixed_value(v, 1.0), Ordering::Relaxed);
        }
    }

    #[inline]
    fn pixel_sums(&self, x: u32, y: u32) -> &[AtomicI64] {
        let i = (y as usize * self.width as usize + x as usize) * self.stride;
        &self.sums[i..i + self.stride]
    }

    /// The weighted means of every pixel, `stride − 1` values each (colour
    /// then the AOV channels), 0 where no weight has been recorded.
    fn means(&self) -> impl Iterator<Item = (f64, &[AtomicI64])> + '_ {
        self.sums.chunks_exact(self.stride).map(|s| {
            let w = s[3].load(Ordering::Relaxed) as f64;
            (if w != 0.0 { 1.0 / w } else { 0.0 }, s)
        })
    }

    /// The image so far: each pixel's weighted mean (black where no weight
    /// has been recorded).
    ///
    /// With a light image, each pixel's light sums divided by the samples
    /// per pixel are added.
    pub fn to_film(&self) -> Film {
        let mut film = Film::new(self.width, self.height).expect("size checked at construction");
        let light = (self.aovs.has_light_image() && self.spp > 0).then(|| 4 + self.aovs.channel_count());
        let inv_spp = 1.0 / (self.spp.max(1) as f64 * FIXED_POINT_SCALE);
        for (out, (inv_w, s)) in film.pixels_mut().iter_mut().zip(self.means()) {
            let [r, g, b] = std::array::from_fn(|i| {
                let mean = s[i].load(Ordering::Relaxed) as f64 * inv_w;
                let splats = light.map_or(0.0, |at| s[at + i].load(Ordering::Relaxed) as f64 * inv_spp);
                (mean + splats) as f32
            });
            *out = Color::new(r, g, b);
        }
        film
    }

    /// The auxiliary images so far: each pixel's weighted mean of every
    /// AOV channel (0 where no weight has been recorded).
    pub fn to_aov_images(&self) -> AovImages {
        let channels = self.aovs.channel_count();
        let mut values = Vec::with_capacity(self.width as usize * self.height as usize * channels);
        for (inv_w, s) in self.means() {
            values.extend(s[4..4 + channels].iter().map(|v| (v.load(Ordering::Relaxed) as f64 * inv_w) as f32));
        }
        AovImages { width: self.width, height: self.height, aovs: self.aovs.without_light_image(), values }
    }
}

/// The auxiliary images of a render, pixel-interleaved: per pixel, row by
/// row from the top, every channel of [`aovs`](Self::aovs) in storage
/// order.
#[derive(Clone, Debug, PartialEq)]
pub struct AovImages {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The images held.
    pub aovs: AovSet,
    /// The values, `aovs.channel_count()` per pixel.
    pub values: Vec<f32>,
}

impl AovImages {
    /// No auxiliary images, for a film of `width × height`.
    pub fn none(width: u32, height: u32) -> Self {
        AovImages { width, height, aovs: AovSet::NONE, values: Vec::new() }
    }

    /// Only the images of `keep` (those of them held).
    pub fn select(&self, keep: AovSet) -> AovImages {
        let aovs = AovSet::of(&self.aovs.iter().filter(|&a| keep.contains(a)).collect::<Vec<_>>());
        let stride = self.aovs.channel_count();
        let offsets: Vec<usize> = aovs
            .iter()
            .flat_map(|a| {
                let o = self.aovs.offset(a).expect("held");
                o..o + a.channels().len()
            })
            .collect();
        let values = self.values.chunks_exact(stride.max(1)).flat_map(|p| offsets.iter().map(|&o| p[o])).collect();
        AovImages { width: self.width, height: self.height, aovs, values }
    }

    /// The channels of `aov` (1 or 3 values per pixel), if held.
    pub fn layer(&self, aov: Aov) -> Option<Vec<f32>> {
        let offset = self.aovs.offset(aov)?;
        let n = aov.channels().len();
        let stride = self.aovs.channel_count();
        Some(self.values.chunks_exact(stride).flat_map(|p| p[offset..offset + n].iter().copied()).collect())
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

/// What an AOV channel of value `a` with filter weight `w` adds: `w·a`
/// clamped to ±[`MAX_CONTRIBUTION`] (non-finite values count as 0) and
/// rounded to fixed point.
#[inline]
pub fn fixed_value(a: f32, w: f32) -> i64 {
    to_fixed(clamp_contribution(a * w))
}

#[inline]
fn clamp_contribution(v: f32) -> f32 {
    if v.is_nan() {
        0.0
    } else {
        v.clamp(-MAX_CONTRIBUTION, MAX_CONTRIBUTION)
    }
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

/// Add [`fixed_contribution`]`(l, w)` to `sums`, in four lanes of AVX2:
/// the same IEEE operations as the scalar definition (the clamp is glam's,
/// then the exact f32 → f64 widening, the scaling by 2²⁰ and the ±½), with
/// the truncation done by `vroundpd` and the conversion to integers by the
/// "magic number" 1.5·2⁵²: for an integral `t` with `|t| < 2⁵¹`, `t + 1.5·2⁵²`
/// is exact and lies in `[2⁵², 2⁵³)`, where one unit of the significand is
/// 1, so its bits minus the bits of 1.5·2⁵² are `t` in two's complement.
/// Bit-identical to the scalar sums for every `l` and every finite `w` with
/// `|w| ≤` [`MAX_CONTRIBUTION`] (tested lane by lane).
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(super) unsafe fn add_contribution_avx2(sums: &mut [i64; 4], l: Color, w: f32) {
    use std::arch::x86_64::*;
    debug_assert!(w.abs() <= MAX_CONTRIBUTION, "filter weight {w}");
    let wl = (l * w).clamp(Color::splat(-MAX_CONTRIBUTION), Color::splat(MAX_CONTRIBUTION));
    let v = _mm_set_ps(w, wl.z, wl.y, wl.x);
    let x = _mm256_mul_pd(_mm256_cvtps_pd(v), _mm256_set1_pd(FIXED_POINT_SCALE));
    // x + copysign(½, x), then towards zero: half away from zero.
    let half = _mm256_or_pd(_mm256_and_pd(x, _mm256_set1_pd(-0.0)), _mm256_set1_pd(0.5));
    let t = _mm256_round_pd::<{ _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC }>(_mm256_add_pd(x, half));
    let magic = _mm256_set1_pd(6_755_399_441_055_744.0);
    let fixed = _mm256_sub_epi64(_mm256_castpd_si256(_mm256_add_pd(t, magic)), _mm256_castpd_si256(magic));
    let at = sums.as_mut_ptr().cast::<__m256i>();
    // SAFETY: `sums` is four i64, 32 bytes; unaligned loads and stores.
    unsafe { _mm256_storeu_si256(at, _mm256_add_epi64(_mm256_loadu_si256(at), fixed)) };
}

/// Add [`fixed_contribution`]`(l, w[i])` to the four sums of each of the
/// first `n ≤ 4` pixels of `sums` (four sums a pixel, one after another),
/// in AVX-512: the same IEEE operations as the scalar definition, sixteen
/// values at a time. The weight rides in the fourth lane of each pixel as
/// `1 · w` (exact, and inside the clamp: `|w| ≤ MAX_CONTRIBUTION`), and
/// `vcvttpd2qq` truncates towards zero as `as i64` does. Pixels of weight
/// 0 add nothing (where the scalar callers skip them); pixels past `n` are
/// neither read nor written.
///
/// # Safety
/// The CPU must have AVX-512 F, DQ and VL.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f,avx512dq,avx512vl")]
#[inline]
pub(super) unsafe fn add_contributions_avx512(sums: &mut [i64], n: usize, l: Color, w: [f32; 4]) {
    use std::arch::x86_64::*;
    assert!(n <= 4 && sums.len() >= 4 * n, "{n} pixels in {} sums", sums.len());
    debug_assert!(w[..n].iter().all(|w| w.abs() <= MAX_CONTRIBUTION), "filter weights {w:?}");
    let colour = _mm512_set_ps(1.0, l.z, l.y, l.x, 1.0, l.z, l.y, l.x, 1.0, l.z, l.y, l.x, 1.0, l.z, l.y, l.x);
    let weights =
        _mm512_set_ps(w[3], w[3], w[3], w[3], w[2], w[2], w[2], w[2], w[1], w[1], w[1], w[1], w[0], w[0], w[0], w[0]);
    let max = _mm512_set1_ps(MAX_CONTRIBUTION);
    // glam's clamp: max, then min (a NaN becomes −MAX_CONTRIBUTION in both).
    let wl = _mm512_min_ps(_mm512_max_ps(_mm512_mul_ps(colour, weights), _mm512_set1_ps(-MAX_CONTRIBUTION)), max);
    // A pixel of weight 0 adds nothing, as the callers of the scalar
    // definition skip it (even where `l` is not finite: 0·∞ clamps to
    // −MAX_CONTRIBUTION).
    let wl = _mm512_maskz_mov_ps(_mm512_cmp_ps_mask::<_CMP_NEQ_UQ>(weights, _mm512_setzero_ps()), wl);
    let halves = [_mm512_castps512_ps256(wl), _mm512_extractf32x8_ps::<1>(wl)];
    for (k, half) in halves.into_iter().enumerate() {
        // Pixels 2k and 2k + 1.
        if 2 * k >= n {
            break;
        }
        let x = _mm512_mul_pd(_mm512_cvtps_pd(half), _mm512_set1_pd(FIXED_POINT_SCALE));
        // x + copysign(½, x), then towards zero: half away from zero.
        let half_away = _mm512_or_pd(_mm512_and_pd(x, _mm512_set1_pd(-0.0)), _mm512_set1_pd(0.5));
        let fixed = _mm512_cvttpd_epi64(_mm512_add_pd(x, half_away));
        // Each pixel's four sums loaded and stored alone: the next sample's
        // footprint, one pixel over, then loads what this one stored from
        // the very addresses, which the store buffer forwards (a load that
        // straddled two stores would wait for both to reach the cache).
        let pixels = [_mm512_castsi512_si256(fixed), _mm512_extracti64x4_epi64::<1>(fixed)];
        for (p, fixed) in pixels.into_iter().enumerate().take(n - 2 * k) {
            let at = sums[4 * (2 * k + p)..4 * (2 * k + p) + 4].as_mut_ptr().cast::<__m256i>();
            // SAFETY: the four sums of pixel 2k + p < n, inside `sums`
            // (asserted above); unaligned loads and stores.
            unsafe { _mm256_storeu_si256(at, _mm256_add_epi64(_mm256_loadu_si256(at), fixed)) };
        }
    }
}

impl Clone for Accumulator {
    fn clone(&self) -> Self {
        let counts = self.adaptive.then(|| self.counts.clone());
        Self::from_parts(self.width, self.height, self.spp, self.aovs, &self.raw(), counts).expect("same size")
    }
}

impl PartialEq for Accumulator {
    fn eq(&self, other: &Self) -> bool {
        (self.width, self.height, self.spp, self.aovs) == (other.width, other.height, other.spp, other.aovs)
            && (self.adaptive, &self.counts) == (other.adaptive, &other.counts)
            && self.raw() == other.raw()
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

    /// The AVX2 kernel adds exactly the scalar [`fixed_contribution`], lane
    /// by lane: radiance of every magnitude and sign, ties at half a unit,
    /// values beyond the clamp, infinities and NaN; weights of every
    /// magnitude up to the clamp.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_contributions_equal_the_scalar_ones() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            eprintln!("no AVX2 on this CPU: the kernel is not taken, nothing to compare");
            return;
        }
        let mut rng = crate::sampling::Pcg32::new(7, 3);
        let unit = 1.0 / FIXED_POINT_SCALE as f32;
        let any = |rng: &mut crate::sampling::Pcg32| {
            let e = (rng.uniform() * 90.0) as i32 - 60;
            (rng.uniform() * 2.0 - 1.0) * 2f32.powi(e)
        };
        let special = [0.0, -0.0, 0.5 * unit, -2.5 * unit, 1.0, MAX_CONTRIBUTION, 3e38, f32::INFINITY, f32::NAN];
        let weights = [0.0, -0.0, 1.0, -1.0, 0.5 * unit, MAX_CONTRIBUTION, -MAX_CONTRIBUTION];
        let mut sums = [3i64, -5, 1 << 40, -(1 << 40)];
        let mut expect = sums;
        for i in 0..300_000 {
            let mut c = [any(&mut rng), any(&mut rng), any(&mut rng)];
            if i % 7 == 0 {
                c[i % 3] = special[i % special.len()] * if i % 2 == 0 { 1.0 } else { -1.0 };
            }
            let w = if i % 11 == 0 { weights[i % weights.len()] } else { rng.uniform() * 2.0 - 1.0 };
            let l = Color::from_array(c);
            for (e, v) in expect.iter_mut().zip(fixed_contribution(l, w)) {
                *e = e.wrapping_add(v);
            }
            // SAFETY: the CPU has AVX2 (checked above).
            unsafe { add_contribution_avx2(&mut sums, l, w) };
            assert_eq!(sums, expect, "l = {l:?}, w = {w:e}");
        }
    }

    /// The AVX-512 row kernel adds each of its first `n` pixels'
    /// [`fixed_contribution`] (none for a weight of 0) and leaves the sums
    /// after them alone.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx512_rows_equal_the_scalar_contributions() {
        if crate::geometry::simd_detected() != crate::geometry::Isa::Avx512 {
            eprintln!("no AVX-512 on this CPU: the kernel is not taken, nothing to compare");
            return;
        }
        let mut rng = crate::sampling::Pcg32::new(8, 5);
        let unit = 1.0 / FIXED_POINT_SCALE as f32;
        let special = [0.0, -0.0, 0.5 * unit, -2.5 * unit, 1.0, MAX_CONTRIBUTION, 3e38, f32::INFINITY, f32::NAN];
        let weights = [0.0, -0.0, 1.0, -1.0, 0.5 * unit, MAX_CONTRIBUTION, -MAX_CONTRIBUTION];
        let mut sums: Vec<i64> = (0..20).map(|k| (k - 9) << (2 * k)).collect();
        let mut expect = sums.clone();
        for i in 0..100_000 {
            let mut c =
                [0.0f32; 3].map(|_| (rng.uniform() * 2.0 - 1.0) * 2f32.powi((rng.uniform() * 90.0) as i32 - 60));
            if i % 7 == 0 {
                c[i % 3] = special[i % special.len()] * if i % 2 == 0 { 1.0 } else { -1.0 };
            }
            let l = Color::from_array(c);
            let w: [f32; 4] = std::array::from_fn(|p| {
                if (i + p) % 11 == 0 {
                    weights[(i + p) % weights.len()]
                } else {
                    rng.uniform() * 2.0 - 1.0
                }
            });
            let n = i % 5;
            // (A weight of 0 is skipped, as the band's scalar loops skip it.)
            for p in (0..n).filter(|&p| w[p] != 0.0) {
                for (e, v) in expect[4 * p..4 * p + 4].iter_mut().zip(fixed_contribution(l, w[p])) {
                    *e = e.wrapping_add(v);
                }
            }
            // SAFETY: the CPU has AVX-512 (checked above).
            unsafe { add_contributions_avx512(&mut sums, n, l, w) };
            assert_eq!(sums, expect, "l = {l:?}, w = {w:?}, {n} pixels");
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
