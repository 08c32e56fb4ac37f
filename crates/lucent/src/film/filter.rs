//! Pixel reconstruction filters, applied by filter importance sampling
//! (Ernst et al., "Filter Importance Sampling", 2006; PBRT 4th ed., §8.8):
//! each sample's position within the pixel is drawn from the filter's
//! distribution and weighted by `f/pdf`, so a sample affects one pixel only
//! and pixels stay independent.
//!
//! # Weights
//!
//! Offsets are drawn with density `p = |f| / ∫|f|`, and
//! [`FilterSample::weight`] is `f(offset) / (p(offset) · ∫|f|)`, that is
//! `sign f(offset)`: `1` for the box, tent and Gaussian filters, which are
//! never negative, and `±1` for Mitchell–Netravali and Lanczos, whose
//! negative lobes are sampled by their magnitude. Its expectation is `∫f / ∫|f|` (1 for the
//! non-negative filters). The film forms each pixel as `Σ w·L / Σ w`, in
//! which any constant factor of the weights cancels, so this is the
//! filter-weighted average of the radiance over the filter's support.
//!
//! All five filters are separable, `f(x, y) = f₁(x)·f₁(y)`, so a 2D offset is
//! two independent 1D draws and the weight is the product of their signs.
//! The box and tent are inverted analytically. The Gaussian,
//! Mitchell–Netravali and Lanczos filters have no closed-form inverse CDF; they are
//! tabulated as `|f₁|` at [`TABLE_SEGMENTS`]` + 1` evenly spaced points over
//! `[−r, r]` and sampled *exactly* from the piecewise-linear interpolant of
//! those points. The interpolant differs from `|f₁|` by at most `h²·max|f₁''|/8`
//! (`h = 2r / TABLE_SEGMENTS`), a few parts in a million of the peak for the
//! usual parameters; within that tolerance the sampling is proportional to
//! `|f|`, which is why the weight is a constant sign.
//!
//! # pbrt-v4's filters
//!
//! The definitions are pbrt-v4's (PBRT 4th ed., §8.8; `filters.h`), up to
//! constant factors, which cancel: box `1` for `|x| ≤ r`; triangle
//! (`Tent`) `max(0, r − |x|)`; Gaussian `max(0, g(x) − g(r))`; Mitchell
//! `k(2x/r)`; Lanczos `sinc(x)·sinc(x/τ)` for `|x| ≤ r`. Their pbrt-v4
//! defaults are [`Filter::pbrt_default`]; pbrt-v4 allows a different
//! `xradius` and `yradius`, lucent's filters are square.

use crate::geometry::{isa, Isa};
use crate::sampling::tent;
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
    /// A Gaussian of standard deviation `sigma`, cut off at `radius`: as in
    /// PBRT 4th ed. (§8.8.3), the value at the radius is subtracted so that
    /// the filter falls to zero there, `f₁(x) = max(0, g(x) − g(r))`.
    Gaussian {
        /// Radius.
        radius: f32,
        /// Standard deviation.
        sigma: f32,
    },
    /// Mitchell–Netravali with parameters `b`, `c` (1/3, 1/3 recommended),
    /// its support `[−2, 2]` scaled to `[−radius, radius]` (Mitchell and
    /// Netravali, "Reconstruction Filters in Computer Graphics", SIGGRAPH
    /// 1988, eq. 8).
    Mitchell {
        /// Radius.
        radius: f32,
        /// B.
        b: f32,
        /// C.
        c: f32,
    },
    /// The Lanczos windowed sinc `sinc(x)·sinc(x/τ)`, `sinc(x) =
    /// sin(πx)/(πx)`, cut off at `radius` (pbrt-v4's `LanczosSincFilter`,
    /// PBRT 4th ed. §8.8.5; Duchon, "Lanczos Filtering in One and Two
    /// Dimensions", 1979). Unlike the classic Lanczos-a kernel the window's
    /// width `τ` and the radius are separate: pbrt-v4's default is radius 4,
    /// τ 3, so the window's first negative lobe (3 < |x| < 4) is kept.
    Lanczos {
        /// Radius.
        radius: f32,
        /// Width of the window sinc(x/τ) (its first zero is at τ).
        tau: f32,
    },
}

impl Default for Filter {
    fn default() -> Self {
        Filter::Box { radius: 0.5 }
    }
}

/// A filter's parameters are out of range.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum FilterError {
    /// The radius is not a positive finite number.
    #[error("filter radius {0} is invalid: it must be a positive finite number of pixels")]
    Radius(f32),
    /// The Gaussian's standard deviation is not a positive finite number.
    #[error("Gaussian filter sigma {0} is invalid: it must be a positive finite number of pixels")]
    Sigma(f32),
    /// The Lanczos window width is not a positive finite number.
    #[error("Lanczos filter tau {0} is invalid: it must be a positive finite number of pixels")]
    Tau(f32),
    /// A Mitchell–Netravali parameter is not finite.
    #[error("Mitchell filter parameters b = {b}, c = {c} are invalid: both must be finite")]
    Mitchell {
        /// B.
        b: f32,
        /// C.
        c: f32,
    },
    /// The filter is zero (to double precision) everywhere in its support,
    /// e.g. a Gaussian whose sigma dwarfs its radius.
    #[error("filter {0:?} is zero everywhere within its radius")]
    Degenerate(Filter),
}

impl Filter {
    /// The half-width of the filter's support, in pixels.
    pub fn radius(&self) -> f32 {
        match *self {
            Filter::Box { radius } | Filter::Tent { radius } => radius,
            Filter::Gaussian { radius, .. } | Filter::Mitchell { radius, .. } | Filter::Lanczos { radius, .. } => {
                radius
            }
        }
    }

    /// pbrt-v4's `PixelFilter` `name` with its default parameters
    /// (`filters.cpp`): `box` radius 0.5; `triangle` radius 2; `gaussian`
    /// radius 1.5, sigma 0.5 (pbrt-v4's default filter); `mitchell` radius
    /// 2, B = C = 1/3; `sinc` (Lanczos) radius 4, tau 3. `None` for other
    /// names.
    ///
    /// ```
    /// use lucent::film::Filter;
    ///
    /// assert_eq!(Filter::pbrt_default("sinc"), Some(Filter::Lanczos { radius: 4.0, tau: 3.0 }));
    /// assert_eq!(Filter::pbrt_default("blackman"), None);
    /// ```
    pub fn pbrt_default(name: &str) -> Option<Filter> {
        Some(match name {
            "box" => Filter::Box { radius: 0.5 },
            "triangle" => Filter::Tent { radius: 2.0 },
            "gaussian" => Filter::Gaussian { radius: 1.5, sigma: 0.5 },
            "mitchell" => Filter::Mitchell { radius: 2.0, b: 1.0 / 3.0, c: 1.0 / 3.0 },
            "sinc" | "lanczos" => Filter::Lanczos { radius: 4.0, tau: 3.0 },
            _ => return None,
        })
    }

    /// Check the parameters: radius and sigma positive and finite,
    /// Mitchell's `b` and `c` finite.
    ///
    /// ```
    /// use lucent::film::{Filter, FilterError};
    ///
    /// assert!(Filter::Gaussian { radius: 1.5, sigma: 0.5 }.validate().is_ok());
    /// assert_eq!(Filter::Tent { radius: -1.0 }.validate(), Err(FilterError::Radius(-1.0)));
    /// ```
    pub fn validate(&self) -> Result<(), FilterError> {
        let r = self.radius();
        if !(r.is_finite() && r > 0.0) {
            return Err(FilterError::Radius(r));
        }
        match *self {
            Filter::Gaussian { sigma, .. } if !(sigma.is_finite() && sigma > 0.0) => Err(FilterError::Sigma(sigma)),
            Filter::Mitchell { b, c, .. } if !(b.is_finite() && c.is_finite()) => Err(FilterError::Mitchell { b, c }),
            Filter::Lanczos { tau, .. } if !(tau.is_finite() && tau > 0.0) => Err(FilterError::Tau(tau)),
            _ => Ok(()),
        }
    }

    /// The 1D factor `f₁` of the separable filter at offset `x` (pixels),
    /// zero outside `[−r, r]`. Not normalised: the scale does not matter to
    /// filter importance sampling.
    pub fn evaluate_1d(&self, x: f32) -> f32 {
        self.eval_1d_f64(x as f64) as f32
    }

    /// The filter's value `f₁(x)·f₁(y)` at `offset` (not normalised).
    pub fn evaluate(&self, offset: Vec2) -> f32 {
        self.evaluate_1d(offset.x) * self.evaluate_1d(offset.y)
    }

    fn eval_1d_f64(&self, x: f64) -> f64 {
        Filter1d::new(self).eval_f64(x)
    }

    /// Whether the filter has negative lobes (Mitchell, Lanczos), so that
    /// sample weights may be −1.
    fn has_negative_lobes(&self) -> bool {
        matches!(self, Filter::Mitchell { .. } | Filter::Lanczos { .. })
    }
}

/// A filter's 1D factor `f₁` with what does not depend on the offset
/// computed once: [`Filter::evaluate_1d`] for many offsets (the Gaussian's
/// floor `g(r)` is an `exp` of its own).
///
/// ```
/// use lucent::film::{Filter, Filter1d};
///
/// let g = Filter::Gaussian { radius: 1.5, sigma: 0.5 };
/// let f1 = Filter1d::new(&g);
/// for x in [0.0, 0.3, -1.2, 1.5, 2.0] {
///     assert_eq!(f1.evaluate(x), g.evaluate_1d(x));
/// }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filter1d {
    filter: Filter,
    /// The radius.
    r: f64,
    /// Gaussian: `2σ²` and `g(r) = exp(−r²/2σ²)`.
    two_sigma2: f64,
    floor: f64,
}

impl Filter1d {
    /// The 1D factor of `filter`.
    pub fn new(filter: &Filter) -> Self {
        let r = filter.radius() as f64;
        let (two_sigma2, floor) = match *filter {
            Filter::Gaussian { sigma, .. } => {
                let s2 = 2.0 * (sigma as f64).powi(2);
                (s2, exp_nonpositive(-r * r / s2))
            }
            _ => (0.0, 0.0),
        };
        Self { filter: *filter, r, two_sigma2, floor }
    }

    /// `f₁(x)`: the same value as [`Filter::evaluate_1d`].
    #[inline]
    pub fn evaluate(&self, x: f32) -> f32 {
        self.eval_f64(x as f64) as f32
    }

    #[inline]
    pub(super) fn eval_f64(&self, x: f64) -> f64 {
        let r = self.r;
        let ax = x.abs();
        if ax > r {
            return 0.0;
        }
        match self.filter {
            Filter::Box { .. } => 1.0,
            // (Radius 1, the common tent, divides by 1: exact, skipped.)
            Filter::Tent { .. } => 1.0 - if r == 1.0 { ax } else { ax / r },
            Filter::Gaussian { .. } => self.gaussian(ax),
            Filter::Mitchell { b, c, .. } => mitchell_1d(2.0 * ax / r, b as f64, c as f64),
            Filter::Lanczos { tau, .. } => sinc(x) * sinc(x / tau as f64),
        }
    }

    /// The Gaussian's `g(x) − g(r)` at `|x| = ax ≤ r`, clamped at 0.
    #[inline(always)]
    fn gaussian(&self, ax: f64) -> f64 {
        (exp_nonpositive(-ax * ax / self.two_sigma2) - self.floor).max(0.0)
    }

    /// [`Filter1d::evaluate`] of each of the eight offsets `x`, bit for
    /// bit ([`Filter1d::evaluate_many`] of eight).
    #[inline]
    pub(super) fn evaluate8(&self, x: [f32; 8]) -> [f32; 8] {
        let mut out = [0.0; 8];
        self.evaluate_many(&x, &mut out);
        out
    }

    /// [`Filter1d::evaluate`] of each offset in `x`, into `out` (as long),
    /// bit for bit: the Gaussian's in AVX2 vector instructions where the
    /// CPU has them ([`Filter1d::gaussian4_avx2`]: the same operations as
    /// [`Filter1d::gaussian`], four lanes to a register), the other
    /// filters' one by one.
    #[inline]
    pub(super) fn evaluate_many(&self, x: &[f32], out: &mut [f32]) {
        self.evaluate_many_as(isa(), x, out);
    }

    /// [`Filter1d::evaluate_many`] in the build for `build` (or the best
    /// the CPU has, if it lacks that one): the same values in every build.
    pub(super) fn evaluate_many_as(&self, build: Isa, x: &[f32], out: &mut [f32]) {
        assert_eq!(x.len(), out.len(), "one weight per offset");
        #[cfg(not(target_arch = "x86_64"))]
        let _ = build;
        #[cfg(target_arch = "x86_64")]
        if matches!(self.filter, Filter::Gaussian { .. }) {
            match build.min(crate::geometry::simd_detected()) {
                // SAFETY: `isa` found the features of `Isa::Avx512`.
                Isa::Avx512 => return unsafe { self.gaussian_many_avx512(x, out) },
                // SAFETY: `isa` found AVX2.
                Isa::Avx2 => return unsafe { self.gaussian_many_avx2(x, out) },
                Isa::Portable => {}
            }
        }
        for (out, &x) in out.iter_mut().zip(x) {
            *out = self.evaluate(x);
        }
    }

    /// Whether [`Filter1d::evaluate_many_as`] `build` computes several
    /// weights for less than as many calls of [`Filter1d::evaluate`]: a
    /// Gaussian in the AVX2 or AVX-512 build.
    pub(super) fn has_lanes(&self, build: Isa) -> bool {
        cfg!(target_arch = "x86_64") && matches!(self.filter, Filter::Gaussian { .. }) && build >= Isa::Avx2
    }

    /// The Gaussian's [`Filter1d::evaluate_many`] in AVX2: four offsets a
    /// step, the last one to three one by one.
    ///
    /// # Safety
    /// The CPU must have AVX2, and the filter must be a Gaussian.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn gaussian_many_avx2(&self, x: &[f32], out: &mut [f32]) {
        use std::arch::x86_64::*;
        let mut xs = x.chunks_exact(4);
        let mut outs = out.chunks_exact_mut(4);
        for (x4, out4) in (&mut xs).zip(&mut outs) {
            // SAFETY: four f32 each (unaligned loads and stores of exactly
            // them).
            unsafe { _mm_storeu_ps(out4.as_mut_ptr(), self.gaussian4_avx2(_mm_loadu_ps(x4.as_ptr()))) };
        }
        for (out, &x) in outs.into_remainder().iter_mut().zip(xs.remainder()) {
            *out = self.evaluate(x);
        }
    }

    /// The Gaussian's [`Filter1d::evaluate_many`] in AVX-512: eight offsets
    /// a step ([`Filter1d::gaussian8_avx512`]), then as AVX2 does. Twice
    /// the lanes of an instruction let twice the offsets' long chains of
    /// dependent steps be under way at once.
    ///
    /// # Safety
    /// The CPU must have the features of `Isa::Avx512`, and the filter must
    /// be a Gaussian.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
    unsafe fn gaussian_many_avx512(&self, x: &[f32], out: &mut [f32]) {
        use std::arch::x86_64::*;
        let mut xs = x.chunks_exact(8);
        let mut outs = out.chunks_exact_mut(8);
        for (x8, out8) in (&mut xs).zip(&mut outs) {
            // SAFETY: eight f32 each (unaligned loads and stores of exactly
            // them).
            unsafe { _mm256_storeu_ps(out8.as_mut_ptr(), self.gaussian8_avx512(_mm256_loadu_ps(x8.as_ptr()))) };
        }
        // SAFETY: the CPU has AVX2 (AVX-512 includes it).
        unsafe { self.gaussian_many_avx2(xs.remainder(), outs.into_remainder()) };
    }

    /// [`Filter1d::gaussian4_avx2`] of eight offsets in AVX-512: the same
    /// operations, the comparisons' results as masks.
    ///
    /// # Safety
    /// The CPU must have the features of `Isa::Avx512`, and the filter must
    /// be a Gaussian.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
    #[inline]
    unsafe fn gaussian8_avx512(&self, xs: std::arch::x86_64::__m256) -> std::arch::x86_64::__m256 {
        use std::arch::x86_64::*;
        let c = _mm512_set1_pd;
        let sign = c(-0.0);
        let ax = _mm512_andnot_pd(sign, _mm512_cvtps_pd(xs));
        // −ax·ax / 2σ²
        let arg = _mm512_div_pd(_mm512_mul_pd(_mm512_xor_pd(ax, sign), ax), c(self.two_sigma2));
        // exp_nonpositive(arg)
        let xc = _mm512_max_pd(arg, c(-700.0));
        let t = _mm512_add_pd(_mm512_mul_pd(xc, c(std::f64::consts::LOG2_E)), c(EXP_ROUND));
        let k = _mm512_sub_pd(t, c(EXP_ROUND));
        let r = _mm512_sub_pd(_mm512_sub_pd(xc, _mm512_mul_pd(k, c(EXP_LN2_HI))), _mm512_mul_pd(k, c(EXP_LN2_LO)));
        let r2 = _mm512_mul_pd(r, r);
        let pair = |i: usize| _mm512_add_pd(c(EXP_Q[i]), _mm512_mul_pd(c(EXP_Q[i + 1]), r));
        let quad = |i: usize| _mm512_add_pd(pair(i), _mm512_mul_pd(pair(i + 2), r2));
        let r4 = _mm512_mul_pd(r2, r2);
        let q = _mm512_add_pd(
            _mm512_add_pd(quad(0), _mm512_mul_pd(quad(4), r4)),
            _mm512_mul_pd(quad(8), _mm512_mul_pd(r4, r4)),
        );
        let er = _mm512_add_pd(c(1.0), _mm512_add_pd(r, _mm512_mul_pd(r2, q)));
        let two_k = _mm512_castsi512_pd(_mm512_slli_epi64::<52>(_mm512_add_epi64(
            _mm512_castpd_si512(t),
            _mm512_set1_epi64(1023),
        )));
        let below = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(arg, c(-700.0));
        let e = _mm512_maskz_mov_pd(!below, _mm512_mul_pd(er, two_k));
        // (e − g(r)).max(0), and 0 beyond the radius.
        let g = _mm512_max_pd(_mm512_sub_pd(e, c(self.floor)), _mm512_setzero_pd());
        let outside = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(ax, c(self.r));
        _mm512_cvtpd_ps(_mm512_maskz_mov_pd(!outside, g))
    }

    /// The Gaussian's [`Filter1d::evaluate`] of four offsets, in AVX2:
    /// each step below is one of [`Filter1d::gaussian`]'s and
    /// [`exp_nonpositive`]'s operations (multiplications and additions
    /// apart, never fused), on four `f64` lanes at once.
    ///
    /// # Safety
    /// The CPU must have AVX2, and the filter must be a Gaussian.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn gaussian4_avx2(&self, xs: std::arch::x86_64::__m128) -> std::arch::x86_64::__m128 {
        use std::arch::x86_64::*;
        let c = _mm256_set1_pd;
        let sign = c(-0.0);
        let ax = _mm256_andnot_pd(sign, _mm256_cvtps_pd(xs));
        // −ax·ax / 2σ²
        let arg = _mm256_div_pd(_mm256_mul_pd(_mm256_xor_pd(ax, sign), ax), c(self.two_sigma2));
        // exp_nonpositive(arg)
        let xc = _mm256_max_pd(arg, c(-700.0));
        let t = _mm256_add_pd(_mm256_mul_pd(xc, c(std::f64::consts::LOG2_E)), c(EXP_ROUND));
        let k = _mm256_sub_pd(t, c(EXP_ROUND));
        let r = _mm256_sub_pd(_mm256_sub_pd(xc, _mm256_mul_pd(k, c(EXP_LN2_HI))), _mm256_mul_pd(k, c(EXP_LN2_LO)));
        let r2 = _mm256_mul_pd(r, r);
        let pair = |i: usize| _mm256_add_pd(c(EXP_Q[i]), _mm256_mul_pd(c(EXP_Q[i + 1]), r));
        let quad = |i: usize| _mm256_add_pd(pair(i), _mm256_mul_pd(pair(i + 2), r2));
        let r4 = _mm256_mul_pd(r2, r2);
        let q = _mm256_add_pd(
            _mm256_add_pd(quad(0), _mm256_mul_pd(quad(4), r4)),
            _mm256_mul_pd(quad(8), _mm256_mul_pd(r4, r4)),
        );
        let er = _mm256_add_pd(c(1.0), _mm256_add_pd(r, _mm256_mul_pd(r2, q)));
        let two_k = _mm256_castsi256_pd(_mm256_slli_epi64::<52>(_mm256_add_epi64(
            _mm256_castpd_si256(t),
            _mm256_set1_epi64x(1023),
        )));
        let below = _mm256_cmp_pd::<_CMP_LT_OQ>(arg, c(-700.0));
        let e = _mm256_andnot_pd(below, _mm256_mul_pd(er, two_k));
        // (e − g(r)).max(0), and 0 beyond the radius.
        let g = _mm256_max_pd(_mm256_sub_pd(e, c(self.floor)), _mm256_setzero_pd());
        let outside = _mm256_cmp_pd::<_CMP_GT_OQ>(ax, c(self.r));
        _mm256_cvtpd_ps(_mm256_andnot_pd(outside, g))
    }
}

/// The constants of [`exp_nonpositive`]: `ln 2 = EXP_LN2_HI + EXP_LN2_LO`,
/// the high part with 21 trailing zero bits (the split of Cody and Waite,
/// as in fdlibm), so that `k · EXP_LN2_HI` is exact for `|k| < 2²¹`.
const EXP_LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const EXP_LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
/// `1.5 · 2⁵²`: adding and subtracting it rounds to an integer.
const EXP_ROUND: f64 = 6_755_399_441_055_744.0;
/// `1/(n + 2)!` for `n = 0..=11`: `q(r) = Σ rⁿ / (n + 2)!`.
const EXP_Q: [f64; 12] = [
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5_040.0,
    1.0 / 40_320.0,
    1.0 / 362_880.0,
    1.0 / 3_628_800.0,
    1.0 / 39_916_800.0,
    1.0 / 479_001_600.0,
    1.0 / 6_227_020_800.0,
];

/// `eˣ` for `x ≤ 0` (0 below −700, where `eˣ < 10⁻³⁰⁴`), in `f64`: the
/// Gaussian filter's `exp`, several times a sample, in a form that
/// [`Filter1d::gaussian4_avx2`] repeats in vector instructions.
///
/// The classical reduction (W. J. Cody and W. Waite, *Software Manual for
/// the Elementary Functions*, 1980, ch. 6): `x = k ln 2 + r` with `k` the
/// integer nearest `x / ln 2` and `|r| ≤ ln 2 / 2`, `k ln 2` subtracted in
/// two parts ([`EXP_LN2_HI`], [`EXP_LN2_LO`]), then `eˣ = 2ᵏ eʳ` with
/// `eʳ = 1 + r + r² q(r)`, `q` the Taylor series of `(eʳ − 1 − r) / r²`
/// to `r¹¹/13!` (truncation below 10⁻¹⁷ relative), evaluated by Estrin's
/// scheme, and `2ᵏ` made from its exponent bits. `k` is rounded by adding
/// and subtracting `1.5 · 2⁵²`, whose sum also holds `k` in its low bits.
/// Within 1 unit in the last place of the exact value (tested against the
/// C library's `exp`).
#[inline(always)]
fn exp_nonpositive(x: f64) -> f64 {
    let xc = x.max(-700.0);
    let t = xc * std::f64::consts::LOG2_E + EXP_ROUND;
    let k = t - EXP_ROUND;
    let r = (xc - k * EXP_LN2_HI) - k * EXP_LN2_LO;
    // q(r) by Estrin's scheme: pairs, then pairs of pairs, so that the
    // steps do not all wait on one another.
    let c = EXP_Q;
    let (r2, pairs) = (
        r * r,
        [c[0] + c[1] * r, c[2] + c[3] * r, c[4] + c[5] * r, c[6] + c[7] * r, c[8] + c[9] * r, c[10] + c[11] * r],
    );
    let r4 = r2 * r2;
    let quads = [pairs[0] + pairs[1] * r2, pairs[2] + pairs[3] * r2, pairs[4] + pairs[5] * r2];
    let q = (quads[0] + quads[1] * r4) + quads[2] * (r4 * r4);
    let er = 1.0 + (r + r2 * q);
    // t's low bits hold k (two's complement): k + 1023 in the exponent
    // field is 2ᵏ (k ≥ −1010 here).
    let two_k = f64::from_bits(t.to_bits().wrapping_add(1023) << 52);
    if x < -700.0 {
        0.0
    } else {
        er * two_k
    }
}

/// `sin(πx)/(πx)`, 1 at 0 (where the quotient is replaced by its Taylor
/// series `1 − (πx)²/6`, exact to double precision for `|πx| < 1e-4`).
fn sinc(x: f64) -> f64 {
    let px = std::f64::consts::PI * x;
    if px.abs() < 1e-4 {
        1.0 - px * px / 6.0
    } else {
        px.sin() / px
    }
}

/// The Mitchell–Netravali cubic (SIGGRAPH 1988, eq. 8) on `[0, 2]`:
///
/// ```text
/// 6k(x) = (12 − 9B − 6C)x³ + (−18 + 12B + 6C)x² + (6 − 2B)            x < 1
///       = (−B − 6C)x³ + (6B + 30C)x² + (−12B − 48C)x + (8B + 24C)     1 ≤ x < 2
/// ```
fn mitchell_1d(x: f64, b: f64, c: f64) -> f64 {
    let v = if x < 1.0 {
        ((12.0 - 9.0 * b - 6.0 * c) * x + (-18.0 + 12.0 * b + 6.0 * c)) * x * x + (6.0 - 2.0 * b)
    } else if x < 2.0 {
        (((-b - 6.0 * c) * x + (6.0 * b + 30.0 * c)) * x + (-12.0 * b - 48.0 * c)) * x + (8.0 * b + 24.0 * c)
    } else {
        0.0
    };
    v / 6.0
}

/// A sample offset and its weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterSample {
    /// Offset from the pixel centre, in pixels.
    pub offset: Vec2,
    /// `f(offset) / (pdf(offset) · ∫|f|)`: the sign of the filter there, so
    /// `1` for filters that are never negative and `±1` for Mitchell and
    /// Lanczos (see
    /// the module documentation).
    pub weight: f32,
}

/// Segments of the tabulated 1D distributions (Gaussian, Mitchell, Lanczos).
pub const TABLE_SEGMENTS: usize = 1024;

/// A 1D density proportional to the piecewise-linear interpolant of
/// `|f₁|` at evenly spaced nodes over `[−r, r]`, sampled by inverting its
/// (piecewise-quadratic) CDF exactly.
#[derive(Clone, Debug)]
struct Table1D {
    radius: f32,
    /// `|f₁|` at the `TABLE_SEGMENTS + 1` nodes.
    values: Vec<f32>,
    /// The normalised CDF at the nodes: `cdf[0] = 0`, `cdf[n] = 1`.
    cdf: Vec<f32>,
}

impl Table1D {
    fn new(filter: &Filter) -> Option<Self> {
        let r = filter.radius() as f64;
        let n = TABLE_SEGMENTS;
        let h = 2.0 * r / n as f64;
        let values: Vec<f64> = (0..=n).map(|i| filter.eval_1d_f64(-r + i as f64 * h).abs()).collect();
        // Trapezoids: the exact areas of the piecewise-linear interpolant.
        let mut cdf = Vec::with_capacity(n + 1);
        let mut total = 0.0;
        cdf.push(0.0);
        for w in values.windows(2) {
            total += 0.5 * (w[0] + w[1]);
            cdf.push(total);
        }
        if !(total.is_finite() && total > 0.0) {
            return None;
        }
        // Normalise the values too (by the peak), so that they stay well
        // within f32 range whatever the filter's scale.
        let peak = values.iter().cloned().fold(0.0, f64::max);
        let cdf: Vec<f32> = cdf.iter().map(|c| (c / total) as f32).collect();
        let mut cdf = cdf;
        cdf[n] = 1.0;
        Some(Self { radius: r as f32, values: values.iter().map(|v| (v / peak) as f32).collect(), cdf })
    }

    /// The offset for `u ∈ [0, 1)`; monotone in `u`, so stratification of
    /// the input carries over to the offsets.
    #[inline]
    fn sample(&self, u: f32) -> f32 {
        let n = self.values.len() - 1;
        let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) };
        // The segment: the last node whose CDF is ≤ u. Segments of zero
        // area have equal CDF at both ends and are skipped.
        let i = self.cdf.partition_point(|&c| c <= u).saturating_sub(1).min(n - 1);
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let s = if c1 > c0 { ((u - c0) / (c1 - c0)).clamp(0.0, 1.0) } else { 0.5 };
        // Within the segment the density is linear from a to b; the fraction
        // t ∈ [0, 1] with a·t + (b − a)t²/2 = s·(a + b)/2 is
        // t = s(a + b) / (a + √(a² + s(b² − a²))), the root of the quadratic
        // written without the cancellation of (−a + √…)/(b − a).
        let (a, b) = (self.values[i], self.values[i + 1]);
        let root = (a * a + s * (b * b - a * a)).max(0.0).sqrt();
        let t = if a + root > 0.0 { (s * (a + b) / (a + root)).clamp(0.0, 1.0) } else { s };
        let h = 2.0 * self.radius / n as f32;
        (-self.radius + (i as f32 + t) * h).clamp(-self.radius, self.radius)
    }
}

/// Draws offsets distributed like a [`Filter`].
///
/// ```
/// use glam::Vec2;
/// use lucent::film::{Filter, FilterSampler};
///
/// let sampler = FilterSampler::try_new(Filter::Tent { radius: 1.0 }).unwrap();
/// let s = sampler.sample(Vec2::new(0.5, 0.5));
/// assert_eq!(s.offset, Vec2::ZERO);
/// assert_eq!(s.weight, 1.0);
/// ```
#[derive(Clone, Debug)]
pub struct FilterSampler {
    filter: Filter,
    table: Option<Table1D>,
}

impl FilterSampler {
    /// A sampler for `filter` (tabulated where the filter has no analytic
    /// inverse).
    ///
    /// # Panics
    ///
    /// If the filter's parameters are invalid; [`FilterSampler::try_new`]
    /// returns the error instead.
    pub fn new(filter: Filter) -> Self {
        Self::try_new(filter).unwrap_or_else(|e| panic!("{e}"))
    }

    /// A sampler for `filter`, or why its parameters are invalid.
    pub fn try_new(filter: Filter) -> Result<Self, FilterError> {
        filter.validate()?;
        let table = match filter {
            Filter::Box { .. } | Filter::Tent { .. } => None,
            Filter::Gaussian { .. } | Filter::Mitchell { .. } | Filter::Lanczos { .. } => {
                Some(Table1D::new(&filter).ok_or(FilterError::Degenerate(filter))?)
            }
        };
        Ok(Self { filter, table })
    }

    /// The filter.
    pub fn filter(&self) -> Filter {
        self.filter
    }

    /// An offset for the uniform sample `u ∈ [0, 1)²`, with density
    /// proportional to `|f|`, and its weight (see [`FilterSample::weight`]).
    /// Each coordinate of the offset is a non-decreasing function of the
    /// matching coordinate of `u`, so stratified `u` give stratified offsets.
    #[inline]
    pub fn sample(&self, u: Vec2) -> FilterSample {
        match self.filter {
            Filter::Box { radius } => {
                let offset = (Vec2::new(2.0 * u.x - 1.0, 2.0 * u.y - 1.0) * radius)
                    .clamp(-Vec2::splat(radius), Vec2::splat(radius));
                FilterSample { offset, weight: 1.0 }
            }
            Filter::Tent { radius } => {
                FilterSample { offset: Vec2::new(tent(u.x, radius), tent(u.y, radius)), weight: 1.0 }
            }
            Filter::Gaussian { .. } | Filter::Mitchell { .. } | Filter::Lanczos { .. } => {
                let table = self.table.as_ref().expect("tabulated filters have a table");
                let offset = Vec2::new(table.sample(u.x), table.sample(u.y));
                let weight = match self.filter {
                    // The sign of a filter with negative lobes: negative in
                    // a negative lobe of exactly one of the two axes.
                    f if f.has_negative_lobes() => {
                        let sx = self.filter.evaluate_1d(offset.x) < 0.0;
                        let sy = self.filter.evaluate_1d(offset.y) < 0.0;
                        if sx != sy {
                            -1.0
                        } else {
                            1.0
                        }
                    }
                    _ => 1.0,
                };
                FilterSample { offset, weight }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [Filter; 9] = [
        Filter::Box { radius: 0.5 },
        Filter::Box { radius: 1.5 },
        Filter::Tent { radius: 1.0 },
        Filter::Tent { radius: 2.0 },
        Filter::Gaussian { radius: 1.5, sigma: 0.5 },
        Filter::Mitchell { radius: 2.0, b: 1.0 / 3.0, c: 1.0 / 3.0 },
        Filter::Mitchell { radius: 1.0, b: 0.0, c: 0.75 },
        Filter::Lanczos { radius: 4.0, tau: 3.0 },
        Filter::Lanczos { radius: 2.0, tau: 2.0 },
    ];

    /// [`exp_nonpositive`] is within 1 unit in the last place of the C
    /// library's `exp` on `[−700, 0]` (at every scale of `x`), exactly 1
    /// at 0, and 0 below −700.
    #[test]
    fn exp_is_within_one_ulp() {
        let mut rng = crate::sampling::Pcg32::new(4, 4);
        let mut worst = 0.0f64;
        for i in 0..1_000_000 {
            let x = -(rng.uniform() as f64) * if i % 7 == 0 { 700.0 } else { 10f64.powi(i % 6 - 3) };
            let (got, want) = (exp_nonpositive(x), x.exp());
            let ulps = (got - want).abs() / (want.next_up() - want);
            worst = worst.max(ulps);
            assert!(ulps <= 1.0, "exp({x:e}) = {got:e}, want {want:e}");
        }
        assert!(worst > 0.0, "some values differ in the last place: the test is live");
        assert_eq!(exp_nonpositive(0.0), 1.0);
        assert_eq!(exp_nonpositive(-0.0), 1.0);
        assert_eq!(exp_nonpositive(-700.5), 0.0);
        assert_eq!(exp_nonpositive(-1e300), 0.0);
    }

    /// The lanes give [`Filter1d::evaluate`]'s values bit for bit, for
    /// every filter, inside and outside the radius; and the Gaussian's
    /// weights are within one `f32` unit in the last place of the C
    /// library's `exp` (the same as its in all but rare cases).
    #[test]
    fn filter_lanes_equal_one_at_a_time() {
        let mut rng = crate::sampling::Pcg32::new(6, 2);
        let (mut same, mut all) = (0, 0);
        for filter in ALL
            .iter()
            .chain(&[Filter::Gaussian { radius: 3.0, sigma: 0.1 }, Filter::Gaussian { radius: 2.0, sigma: 4.0 }])
        {
            let f1 = Filter1d::new(filter);
            for _ in 0..20_000 {
                let x: [f32; 8] = std::array::from_fn(|_| (rng.uniform() - 0.5) * 2.5 * filter.radius());
                let lanes = f1.evaluate8(x);
                for (k, &x) in x.iter().enumerate() {
                    assert_eq!(lanes[k].to_bits(), f1.evaluate(x).to_bits(), "{filter:?} at {x}");
                    if let Filter::Gaussian { sigma, radius } = *filter {
                        let s2 = 2.0 * (sigma as f64).powi(2);
                        let r = radius as f64;
                        let ax = (x as f64).abs();
                        let libm =
                            if ax > r { 0.0 } else { ((-ax * ax / s2).exp() - (-r * r / s2).exp()).max(0.0) as f32 };
                        let unit = libm.next_up() - libm;
                        assert!((lanes[k] - libm).abs() <= unit, "{filter:?} at {x}: {} against {libm}", lanes[k]);
                        same += (lanes[k] == libm) as u32;
                        all += 1;
                    }
                }
            }
        }
        assert!(same as f64 >= 0.999 * all as f64, "{same} of {all} equal to the C library's");
    }

    /// [`Filter1d::evaluate_many`] gives [`Filter1d::evaluate`]'s bits in
    /// every build the CPU runs, at every length (the kernels' tails of
    /// fewer than eight and four offsets included), at the radius and
    /// beyond it.
    #[test]
    fn evaluate_many_equals_evaluate_in_every_build() {
        let mut rng = crate::sampling::Pcg32::new(9, 4);
        let filters = [
            Filter::Gaussian { radius: 1.5, sigma: 0.5 },
            Filter::Gaussian { radius: 3.0, sigma: 0.1 },
            Filter::Gaussian { radius: 2.0, sigma: 4.0 },
            Filter::Tent { radius: 1.0 },
            Filter::Mitchell { radius: 2.0, b: 1.0 / 3.0, c: 1.0 / 3.0 },
        ];
        for filter in filters {
            let f1 = Filter1d::new(&filter);
            let r = filter.radius();
            let special = [0.0, -0.0, r, -r, r.next_up(), -r.next_down(), 1e-20, 40.0, -1e30];
            for len in 0..40 {
                let x: Vec<f32> = (0..len)
                    .map(|i| if i % 5 == 4 { special[i % special.len()] } else { (rng.uniform() - 0.5) * 2.5 * r })
                    .collect();
                let expect: Vec<u32> = x.iter().map(|&x| f1.evaluate(x).to_bits()).collect();
                let bits = |out: &[f32]| out.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                let mut out = vec![f32::NAN; len];
                f1.evaluate_many(&x, &mut out);
                assert_eq!(bits(&out), expect, "{filter:?}, {len} offsets");
                #[cfg(target_arch = "x86_64")]
                if matches!(filter, Filter::Gaussian { .. }) {
                    let best = crate::geometry::simd_detected();
                    if best >= Isa::Avx2 {
                        out.fill(f32::NAN);
                        // SAFETY: the CPU has AVX2; the filter is a Gaussian.
                        unsafe { f1.gaussian_many_avx2(&x, &mut out) };
                        assert_eq!(bits(&out), expect, "AVX2, {filter:?}, {len} offsets");
                    }
                    if best == Isa::Avx512 {
                        out.fill(f32::NAN);
                        // SAFETY: the CPU has AVX-512; the filter is a Gaussian.
                        unsafe { f1.gaussian_many_avx512(&x, &mut out) };
                        assert_eq!(bits(&out), expect, "AVX-512, {filter:?}, {len} offsets");
                    }
                }
            }
        }
    }

    /// ∫f₁ and ∫|f₁| over [−r, r] by the midpoint rule on a fine grid.
    fn integrals_1d(filter: &Filter) -> (f64, f64) {
        let r = filter.radius() as f64;
        let n = 200_000;
        let h = 2.0 * r / n as f64;
        let (mut s, mut a) = (0.0, 0.0);
        for i in 0..n {
            let v = filter.eval_1d_f64(-r + (i as f64 + 0.5) * h);
            s += v * h;
            a += v.abs() * h;
        }
        (s, a)
    }

    /// Stratified, jittered uniforms: `n` values, one per `[i/n, (i+1)/n)`.
    fn jittered(n: usize, seed: u64) -> Vec<f32> {
        let mut rng = crate::sampling::Pcg32::new(seed, 1);
        (0..n).map(|i| ((i as f32 + rng.uniform()) / n as f32).min(1.0 - f32::EPSILON / 2.0)).collect()
    }

    #[test]
    fn histograms_match_the_filter_shape() {
        let bins = 40;
        let n = 400_000;
        for filter in ALL {
            let sampler = FilterSampler::new(filter);
            let r = filter.radius() as f64;
            let (_, abs_integral) = integrals_1d(&filter);
            let mut hist = vec![0usize; bins];
            let us = jittered(n, 3);
            let vs = jittered(n, 4);
            for (&u, &v) in us.iter().zip(&vs) {
                let s = sampler.sample(Vec2::new(u, v));
                for c in [s.offset.x, s.offset.y] {
                    assert!((-filter.radius()..=filter.radius()).contains(&c), "{filter:?}: {c}");
                }
                let bin = (((s.offset.x as f64 + r) / (2.0 * r)) * bins as f64) as usize;
                hist[bin.min(bins - 1)] += 1;
            }
            // Expected fraction per bin: ∫_bin |f₁| / ∫|f₁|.
            for (k, &count) in hist.iter().enumerate() {
                let (lo, hi) = (-r + 2.0 * r * k as f64 / bins as f64, -r + 2.0 * r * (k + 1) as f64 / bins as f64);
                let m = 2000;
                let mass: f64 = (0..m)
                    .map(|j| {
                        filter.eval_1d_f64(lo + (j as f64 + 0.5) * (hi - lo) / m as f64).abs() * (hi - lo) / m as f64
                    })
                    .sum::<f64>()
                    / abs_integral;
                let got = count as f64 / n as f64;
                assert!((got - mass).abs() < 0.002 + 0.01 * mass, "{filter:?} bin {k}: {got} vs {mass}");
            }
        }
    }

    #[test]
    fn mean_weight_is_signed_mass_over_absolute_mass() {
        let n = 1 << 20;
        let mut rng = crate::sampling::Pcg32::new(5, 5);
        for filter in ALL {
            let sampler = FilterSampler::new(filter);
            let (s, a) = integrals_1d(&filter);
            let expected = (s / a).powi(2);
            let mut sum = 0.0f64;
            for _ in 0..n {
                let w = sampler.sample(Vec2::new(rng.uniform(), rng.uniform())).weight;
                assert!(w == 1.0 || w == -1.0);
                sum += w as f64;
            }
            let mean = sum / n as f64;
            // Standard error ≤ 1/√n ≈ 0.001.
            assert!((mean - expected).abs() < 0.004, "{filter:?}: mean weight {mean}, expected {expected}");
            if !filter.has_negative_lobes() {
                assert_eq!(mean, 1.0);
            }
        }
    }

    #[test]
    fn mitchell_and_lanczos_weights_match_the_sign_of_the_filter() {
        for filter in
            [Filter::Mitchell { radius: 2.0, b: 1.0 / 3.0, c: 1.0 / 3.0 }, Filter::Lanczos { radius: 4.0, tau: 3.0 }]
        {
            weights_match_the_sign(filter);
        }
    }

    fn weights_match_the_sign(filter: Filter) {
        let sampler = FilterSampler::new(filter);
        let mut negatives = 0;
        for u in jittered(1000, 1) {
            for v in [0.1, 0.5, 0.97] {
                let s = sampler.sample(Vec2::new(u, v));
                let f = filter.evaluate(s.offset);
                if f != 0.0 {
                    assert_eq!(s.weight, f.signum(), "{s:?}");
                }
                negatives += (s.weight < 0.0) as usize;
            }
        }
        assert!(negatives > 0, "the negative lobes are sampled");
    }

    #[test]
    fn extreme_inputs_give_finite_offsets_in_the_support() {
        let edge = [0.0, 1.0 - f32::EPSILON / 2.0, 1.0, 0.5, f32::MIN_POSITIVE];
        for filter in ALL {
            let sampler = FilterSampler::new(filter);
            let r = filter.radius();
            for &u in &edge {
                for &v in &edge {
                    let s = sampler.sample(Vec2::new(u, v));
                    assert!(s.offset.is_finite() && s.weight.is_finite(), "{filter:?} ({u}, {v}): {s:?}");
                    assert!(s.offset.abs().max_element() <= r, "{filter:?} ({u}, {v}): {s:?}");
                }
            }
            // Monotone in u.
            let mut prev = -f32::INFINITY;
            for u in jittered(10_000, 9) {
                let x = sampler.sample(Vec2::new(u, 0.5)).offset.x;
                assert!(x >= prev, "{filter:?}: not monotone at {u}");
                prev = x;
            }
        }
    }

    #[test]
    fn invalid_parameters_are_rejected() {
        for (filter, err) in [
            (Filter::Box { radius: 0.0 }, FilterError::Radius(0.0)),
            (Filter::Tent { radius: f32::INFINITY }, FilterError::Radius(f32::INFINITY)),
            (Filter::Gaussian { radius: 1.0, sigma: -0.5 }, FilterError::Sigma(-0.5)),
            (Filter::Mitchell { radius: 2.0, b: f32::NAN, c: 0.0 }, FilterError::Mitchell { b: f32::NAN, c: 0.0 }),
            (Filter::Lanczos { radius: 4.0, tau: 0.0 }, FilterError::Tau(0.0)),
        ] {
            let got = FilterSampler::try_new(filter).map(|_| ()).unwrap_err();
            // NaN ≠ NaN: compare the messages.
            assert_eq!(got.to_string(), err.to_string());
        }
        assert!(matches!(Filter::Box { radius: f32::NAN }.validate(), Err(FilterError::Radius(_))));
        // A Gaussian far wider than its radius is zero to double precision.
        let flat = Filter::Gaussian { radius: 1e-30, sigma: 1e30 };
        assert_eq!(FilterSampler::try_new(flat).map(|_| ()), Err(FilterError::Degenerate(flat)));
    }

    #[test]
    fn mitchell_kernel_is_normalised() {
        // The Mitchell–Netravali family integrates to 1 over [−2, 2] for any
        // B and C, and k(0) = (6 − 2B)/6.
        for (b, c) in [(1.0 / 3.0, 1.0 / 3.0), (0.0, 0.5), (1.0, 0.0)] {
            let f = Filter::Mitchell { radius: 2.0, b, c };
            let (s, _) = integrals_1d(&f);
            assert!((s - 1.0).abs() < 1e-6, "b {b} c {c}: {s}");
            assert!((f.eval_1d_f64(0.0) - (6.0 - 2.0 * b as f64) / 6.0).abs() < 1e-12);
        }
    }

    #[test]
    fn lanczos_is_one_at_zero_and_zero_at_the_integers() {
        let f = Filter::Lanczos { radius: 4.0, tau: 3.0 };
        assert_eq!(f.eval_1d_f64(0.0), 1.0);
        assert_eq!(f.evaluate(Vec2::ZERO), 1.0);
        for k in 1..=4 {
            for x in [k as f64, -(k as f64)] {
                assert!(f.eval_1d_f64(x).abs() < 1e-15, "{x}: {}", f.eval_1d_f64(x));
            }
        }
        assert_eq!(f.eval_1d_f64(4.0001), 0.0);
        // A known value: sinc(½)·sinc(1/6) = (2/π)·(3/π)·sin(π/6)·2 … i.e.
        // (sin(π/2)/(π/2))·(sin(π/6)/(π/6)) = (2/π)·(3/π) = 6/π².
        let v = f.eval_1d_f64(0.5);
        assert!((v - 6.0 / std::f64::consts::PI.powi(2)).abs() < 1e-15, "{v}");
        // The lobes: negative for 1 < |x| < 2, positive for 2 < |x| < 3, and
        // positive again for 3 < |x| < 4, where the window sinc(x/3) is
        // negative too.
        assert!(f.eval_1d_f64(1.5) < 0.0 && f.eval_1d_f64(2.5) > 0.0 && f.eval_1d_f64(3.5) > 0.0);
        // Continuous through the small-argument series.
        assert!((f.eval_1d_f64(3.0e-5) - f.eval_1d_f64(4.0e-5)).abs() < 1e-8);
    }

    #[test]
    fn lanczos_sampling_weight_is_normalised() {
        // E[w] = (∫f/∫|f|)² (module docs), and the weighted estimate of
        // ∫ g·f / ∫ f is unbiased: for g(x, y) = x², the filter's second
        // moment, the two ratios agree.
        let filter = Filter::Lanczos { radius: 4.0, tau: 3.0 };
        let sampler = FilterSampler::new(filter);
        let (s, a) = integrals_1d(&filter);
        let (mut sum_w, mut sum_wg) = (0.0f64, 0.0f64);
        let n = 1 << 20;
        let mut rng = crate::sampling::Pcg32::new(11, 3);
        for _ in 0..n {
            let smp = sampler.sample(Vec2::new(rng.uniform(), rng.uniform()));
            sum_w += smp.weight as f64;
            sum_wg += smp.weight as f64 * (smp.offset.x as f64).powi(2);
        }
        let expected_w = (s / a).powi(2);
        assert!((sum_w / n as f64 - expected_w).abs() < 0.005, "{} vs {expected_w}", sum_w / n as f64);
        // ∫x² f₁(x) dx / ∫f₁ by the midpoint rule.
        let m = 400_000;
        let h = 8.0 / m as f64;
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..m {
            let x = -4.0 + (i as f64 + 0.5) * h;
            let v = filter.eval_1d_f64(x);
            num += x * x * v * h;
            den += v * h;
        }
        let got = sum_wg / sum_w;
        assert!((got - num / den).abs() < 0.02, "{got} vs {}", num / den);
    }

    #[test]
    fn pbrt_defaults() {
        assert_eq!(Filter::pbrt_default("box"), Some(Filter::Box { radius: 0.5 }));
        assert_eq!(Filter::pbrt_default("triangle"), Some(Filter::Tent { radius: 2.0 }));
        assert_eq!(Filter::pbrt_default("gaussian"), Some(Filter::Gaussian { radius: 1.5, sigma: 0.5 }));
        assert_eq!(
            Filter::pbrt_default("mitchell"),
            Some(Filter::Mitchell { radius: 2.0, b: 1.0 / 3.0, c: 1.0 / 3.0 })
        );
        assert_eq!(Filter::pbrt_default("sinc"), Some(Filter::Lanczos { radius: 4.0, tau: 3.0 }));
        // pbrt-v4's Gaussian falls to zero at its radius: g(x) − g(r).
        let g = Filter::pbrt_default("gaussian").unwrap();
        assert_eq!(g.evaluate_1d(1.5), 0.0);
        let expected = (-0.25f64 / 0.5).exp() - (-2.25f64 / 0.5).exp(); // x² = 0.25, r² = 2.25, 2σ² = 0.5
        assert!((g.eval_1d_f64(0.5) - expected).abs() < 1e-15);
        // Triangle: proportional to max(0, r − |x|).
        let t = Filter::pbrt_default("triangle").unwrap();
        assert_eq!(t.evaluate_1d(0.5) / t.evaluate_1d(0.0), 1.5 / 2.0);
    }
}
