//! Sampling tabulated distributions: piecewise-constant densities in 1D and
//! 2D (PBRT 4th ed., §A.5.1 and §A.5.2) and discrete choice with Vose's alias
//! method (PBRT 4th ed., §A.1; M. D. Vose, "A Linear Algorithm for Generating
//! Random Numbers with a Given Distribution", IEEE TSE 17(9), 1991).
//!
//! **Guide tables.** Inverting a CDF of `n` bins by binary search is a
//! chain of `log₂ n` dependent loads. [`PiecewiseConstant1D`] also keeps a
//! guide table (the "cutpoint" or "indexed search" method: H.-C. Chen and
//! Y. Asau, "On Generating Random Variates from an Empirical
//! Distribution", AIIE Transactions 6(2), 1974; L. Devroye, *Non-Uniform
//! Random Variate Generation*, 1986, §III.2.4): for `K` equal slices of
//! `[0, 1]`, where the search's answer for each slice's start lies. A
//! sample then reads its slice's two guide entries and searches only the
//! few CDF entries between them, with exactly the answer of the full
//! search, so the sampled points are unchanged.
//!
//! **Many samples at once.** [`PiecewiseConstant2D`] keeps its rows'
//! tables in two flat arrays (the bins, the guide tables), so that a
//! sample's reads depend on no pointer but the row. For a large table (an
//! environment map of 512 × 256 has 1 MB of rows) the row's guide entries
//! and bins are usually cache misses; a caller with many samples to take
//! takes them together ([`PiecewiseConstant2D::sample_many`]), each step of
//! the searches for all of them before the next, so that the misses
//! overlap.
//!
//! **Zero functions.** A function that is zero everywhere (or has no
//! entries) cannot be normalised. All three types then fall back to the
//! *uniform* distribution over their domain, so sampling never fails and the
//! returned pdf is always the density actually used. Negative entries count
//! by their absolute value and non-finite entries count as zero.

use crate::geometry::LANES;
use crate::memory::prefetch;
use glam::Vec2;
use rayon::prelude::*;

/// Clean up one tabulated value: absolute value, non-finite → 0.
#[inline]
fn sanitize(v: f32) -> f32 {
    if v.is_finite() {
        v.abs()
    } else {
        0.0
    }
}

/// A piecewise-constant density on `[0, 1]` with `n` equal bins, sampled by
/// inverting its cumulative distribution (PBRT 4th ed., §A.5.1).
///
/// With bin values `f_i`, the integral is `I = Σ f_i / n`, the density is
/// `p(x) = f_i / I` on bin `i`, and the CDF is the running sum
/// `P(i) = Σ_{j<i} f_j / (n I)`.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant1D {
    /// `n + 1` entries `[P(i), p_i]`: the CDF at the start of bin `i`
    /// (from 0 to 1) and the density on bin `i` (`f_i / I`; all ones for a
    /// zero function; 0 in the last entry, which only closes the CDF). One
    /// array, so that a sample finds its bin's density in the cache line
    /// its search ended in.
    bins: Vec<[f32; 2]>,
    /// The guide table: `guide[k]` is the number of CDF entries `≤ k / K`
    /// (`K = guide.len() - 1`, a power of two), so that the search for any
    /// `u` in `[k / K, (k + 1) / K)` ends between `guide[k]` and
    /// `guide[k + 1]`.
    guide: Vec<u32>,
    /// `∫ f` over `[0, 1]` of the function as given (0 for a zero function).
    integral: f32,
}

/// Bins per guide-table slice, about: a slice's search then reads one or
/// two cache lines, and the guide table is an eighth of the CDF's size.
const BINS_PER_GUIDE_SLICE: usize = 8;

impl PiecewiseConstant1D {
    /// The density proportional to `f` (see the module docs for zero
    /// functions).
    pub fn new(f: &[f32]) -> Self {
        // An empty table gets one zero bin.
        let f = if f.is_empty() { &[0.0][..] } else { f };
        let mut bins = vec![[0.0; 2]; f.len() + 1];
        let mut guide = vec![0; guide_len(f.len())];
        let integral = tabulate(f, &mut Vec::new(), &mut bins, &mut guide);
        Self { bins, guide, integral }
    }

    /// Number of bins.
    pub fn len(&self) -> usize {
        self.bins.len() - 1
    }

    /// Whether there are no bins (never: an empty table gets one zero bin).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The integral of the function over `[0, 1]` as given: 0 for a zero
    /// function (which is sampled uniformly).
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// Sample the density with a uniform `u` in `[0, 1)`: the point `x` in
    /// `[0, 1)`, its density, and the index of its bin.
    pub fn sample(&self, u: f32) -> (f32, f32, usize) {
        sample_table(&self.bins, &self.guide, u)
    }

    /// The density at `x` (clamped into `[0, 1]`).
    pub fn pdf(&self, x: f32) -> f32 {
        self.bins[self.bin(x)][1]
    }

    /// The bin containing `x`.
    #[inline]
    fn bin(&self, x: f32) -> usize {
        let n = self.len();
        ((x * n as f32).max(0.0) as usize).min(n - 1)
    }
}

/// The number of entries of the guide table of `n` bins: `K + 1`, `K` a
/// power of two near `n` over [`BINS_PER_GUIDE_SLICE`] (at most 2²⁴).
fn guide_len(n: usize) -> usize {
    (n / BINS_PER_GUIDE_SLICE).clamp(1, 1 << 24).next_power_of_two() + 1
}

/// The table of the density proportional to `f` (not empty), written
/// into `bins` (`f.len() + 1` entries: see [`PiecewiseConstant1D`]'s
/// fields) and its guide table into `guide` ([`guide_len`] entries);
/// returns the integral of `f` as given (0 for a zero function, which is
/// then sampled uniformly). `cdf` is scratch space, so that the rows of a
/// [`PiecewiseConstant2D`] are written in place, with one allocation for
/// all of them.
fn tabulate(f: &[f32], cdf: &mut Vec<f64>, bins: &mut [[f32; 2]], guide: &mut [u32]) -> f32 {
    let n = f.len();
    debug_assert!(n > 0 && bins.len() == n + 1 && guide.len() == guide_len(n));
    // Accumulate in f64 so that long tables keep their small entries.
    cdf.clear();
    cdf.push(0.0f64);
    let mut sum = 0.0f64;
    for &v in f {
        sum += sanitize(v) as f64 / n as f64;
        cdf.push(sum);
    }
    let total = cdf[n];
    let uniform = !(total > 0.0 && total.is_finite());
    // (The uniform fallback: every bin 1, the CDF i / n.)
    let norm = if uniform { 1.0 } else { total as f32 };
    for (i, bin) in bins[..n].iter_mut().enumerate() {
        let (c, v) = if uniform { (i as f64 / n as f64, 1.0) } else { (cdf[i] / total, sanitize(f[i])) };
        *bin = [c as f32, v / norm];
    }
    bins[n] = [1.0, 0.0];
    guide_table(bins, guide);
    if uniform {
        0.0
    } else {
        total as f32
    }
}

/// The guide table of the CDF in `bins`, into `guide`: entry `k` of its
/// `K + 1` the number of CDF values `≤ k / K`. (`k` and `K` are exact in
/// `f32`, so `k / K` is, and so is the slice `⌊u K⌋` of a sample `u`.) One
/// pass over the CDF, which is non-decreasing.
fn guide_table(bins: &[[f32; 2]], guide: &mut [u32]) {
    let slices = guide.len() - 1;
    let mut count = 0;
    for (k, g) in guide.iter_mut().enumerate() {
        let start = k as f32 / slices as f32;
        while count < bins.len() && bins[count][0] <= start {
            count += 1;
        }
        *g = count as u32;
    }
}

/// The entries `lo..hi` of the CDF in `bins` among which the search for
/// `u` ends: those of `u`'s slice of the guide table `guide` (see
/// [`PiecewiseConstant1D`]'s fields) for `u` in `[0, 1)`, all of them for
/// any other `u` (or NaN). Every entry before `lo` is `≤ u` and every entry
/// from `hi` on is `> u`.
#[inline]
fn cdf_span(bins: &[[f32; 2]], guide: &[u32], u: f32) -> (usize, usize) {
    if !(0.0..1.0).contains(&u) {
        return (0, bins.len());
    }
    let k = guide_slice(guide, u);
    // Every entry before guide[k] is ≤ k/K ≤ u; every entry from
    // guide[k + 1] on is > (k+1)/K > u.
    (guide[k] as usize, guide[k + 1] as usize)
}

/// The number of entries of the CDF in `bins` that are `≤ u`, given the
/// span `lo..hi` from [`cdf_span`]: the full binary search's answer.
#[inline]
fn cdf_rank_in(bins: &[[f32; 2]], (lo, hi): (usize, usize), u: f32) -> usize {
    lo + bins[lo..hi].partition_point(|b| b[0] <= u)
}

/// The number of entries of the CDF in `bins` that are `≤ u` (with the
/// guide table `guide`).
#[cfg(test)]
fn cdf_rank(bins: &[[f32; 2]], guide: &[u32], u: f32) -> usize {
    cdf_rank_in(bins, cdf_span(bins, guide, u), u)
}

/// The guide slice `⌊u K⌋` of `u` in `[0, 1)` (`u·K` is exact: `K` is a
/// power of two), clamped into the table for any other `u`.
#[inline]
fn guide_slice(guide: &[u32], u: f32) -> usize {
    let slices = guide.len() - 1;
    ((u * slices as f32) as usize).min(slices - 1)
}

/// [`PiecewiseConstant1D::sample`] of the table `bins` with its guide
/// table `guide`.
#[inline]
fn sample_table(bins: &[[f32; 2]], guide: &[u32], u: f32) -> (f32, f32, usize) {
    sample_at_rank(bins, cdf_rank_in(bins, cdf_span(bins, guide, u), u), u)
}

/// The sample of `u` from the table `bins`, given `rank`, the number of
/// its CDF entries `≤ u`: the point in the last bin whose CDF start is
/// `≤ u` (zero-width bins are skipped, because the next bin starts at the
/// same value), its density and the bin.
#[inline(always)]
fn sample_at_rank(bins: &[[f32; 2]], rank: usize, u: f32) -> (f32, f32, usize) {
    let n = bins.len() - 1;
    let o = rank.saturating_sub(1).min(n - 1);
    let [start, density] = bins[o];
    let width = bins[o + 1][0] - start;
    let mut du = u - start;
    if width > 0.0 {
        du /= width;
    }
    let x = ((o as f32 + du.clamp(0.0, 1.0)) / n as f32).min(1.0 - f32::EPSILON / 2.0);
    (x, density, o)
}

/// Equal-length tables laid end to end in one array (a
/// [`PiecewiseConstant2D`]'s rows, or one table alone), for
/// [`TablesOf::sample_lanes`].
struct TablesOf<'a> {
    /// Every table's bins: table `t`'s are `bins[t * len..(t + 1) * len]`.
    bins: &'a [[f32; 2]],
    /// Every table's guide table, likewise `guide_len` entries apart.
    guide: &'a [u32],
    len: usize,
    guide_len: usize,
}

impl TablesOf<'_> {
    /// [`sample_table`] of `u[k]` from table `table[k]`, for each of the
    /// first `n` lanes, into `out[k]` (point, density, bin) bit for bit.
    ///
    /// One search at a time is a chain of loads, each waiting on the one
    /// before, in a loop whose length changes from sample to sample. Here
    /// every lane still searching takes a step of its binary search before
    /// any takes the next, so the loads of the lanes overlap (cache misses
    /// included). The order of the steps cannot change the answer: the
    /// CDF is non-decreasing, so the number of its entries `≤ u` is one
    /// number however it is found.
    #[inline(always)]
    fn sample_lanes(&self, table: &[u32; LANES], u: &[f32; LANES], n: usize, out: &mut [(f32, f32, usize); LANES]) {
        let len = self.len;
        // Each lane's span (from its guide table): the index in `bins` of
        // its first entry, and its length.
        let (mut lo, mut size) = ([0usize; LANES], [0usize; LANES]);
        for k in 0..n {
            let t = table[k] as usize;
            let (bins, guide) = self.table(t);
            let (l, h) = cdf_span(bins, guide, u[k]);
            (lo[k], size[k]) = (t * len + l, h - l);
            // Ask for the span's ends now: every step below, and the
            // sample's bin, read between them.
            prefetch(bins.as_ptr().wrapping_add(l.saturating_sub(1)), 1);
            prefetch(bins.as_ptr().wrapping_add(h), 1);
        }
        // The binary search: halve each span, keeping the upper half where
        // its first entry is ≤ u, until one entry is left. Most spans start
        // with one entry or none (a guide slice usually holds one CDF entry
        // or none), a few with hundreds (where the density is low): only
        // the lanes still searching take the next step, so each lane takes
        // as many as its own span needs.
        let mut active = [0u8; LANES];
        let mut m = 0;
        for (k, &size) in size[..n].iter().enumerate() {
            active[m] = k as u8;
            m += (size > 1) as usize;
        }
        while m > 0 {
            let mut still = 0;
            for j in 0..m {
                let k = active[j] as usize;
                let half = size[k] / 2;
                let mid = lo[k] + half;
                // (Without a branch on the comparison, whose outcome is a
                // coin toss.)
                lo[k] = std::hint::select_unpredictable(self.bins[mid][0] <= u[k], mid, lo[k]);
                size[k] -= half;
                active[still] = k as u8;
                still += (size[k] > 1) as usize;
            }
            m = still;
        }
        for k in 0..n {
            let start = table[k] as usize * len;
            // The span's last entry, if it is ≤ u, counts too.
            let last = size[k] == 1 && self.bins[lo[k]][0] <= u[k];
            out[k] = sample_at_rank(&self.bins[start..start + len], lo[k] - start + last as usize, u[k]);
        }
    }

    /// Table `t`'s bins and guide table.
    #[inline(always)]
    fn table(&self, t: usize) -> (&[[f32; 2]], &[u32]) {
        (&self.bins[t * self.len..(t + 1) * self.len], &self.guide[t * self.guide_len..(t + 1) * self.guide_len])
    }
}

/// A piecewise-constant density on `[0, 1]²` over an `nu × nv` grid, sampled
/// as a marginal density in `v` and a conditional density in `u` for the
/// chosen row (PBRT 4th ed., §A.5.2): `p(u, v) = p(v) · p(u | v)`.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant2D {
    /// The conditional densities `p(u | v)` of the rows, one after the
    /// other in one array: row `v`'s [`PiecewiseConstant1D`] bins are
    /// `conditional[v * (nu + 1)..(v + 1) * (nu + 1)]`. (One array rather
    /// than a table per row: a sample reads a row's bins without first
    /// reading where they are.)
    conditional: Vec<[f32; 2]>,
    /// The rows' guide tables, likewise: `guide_len` entries a row.
    conditional_guide: Vec<u32>,
    guide_len: usize,
    marginal: PiecewiseConstant1D,
    /// `p(v) · p(u | v)` of every cell, row by row: what
    /// [`PiecewiseConstant2D::pdf`] returns, with one load instead of a
    /// walk through the marginal and a row's own table.
    joint: Vec<f32>,
    /// Cells per row.
    nu: usize,
}

impl PiecewiseConstant2D {
    /// The density proportional to `f`, given row by row: `f[v * nu + u]`,
    /// `v` (the row) in `0..nv`, `u` (the column) in `0..nu`.
    ///
    /// # Panics
    /// If `f.len() != nu * nv` or either size is zero.
    pub fn new(f: &[f32], nu: usize, nv: usize) -> Self {
        assert!(nu > 0 && nv > 0 && f.len() == nu * nv, "table size {} is not {nu} × {nv}", f.len());
        // Every row has `nu` bins, so guide tables of one length. The rows
        // are written in place, in parallel (the same values whatever the
        // threads): a large map has millions of bins.
        let guide_len = guide_len(nu);
        let mut conditional = vec![[0.0; 2]; nv * (nu + 1)];
        let mut conditional_guide = vec![0; nv * guide_len];
        let mut integrals = vec![0.0; nv];
        conditional
            .par_chunks_mut(nu + 1)
            .zip(conditional_guide.par_chunks_mut(guide_len))
            .zip(f.par_chunks(nu))
            .zip(integrals.par_iter_mut())
            .with_min_len(64)
            .for_each_init(Vec::new, |cdf, (((bins, guide), f), integral)| *integral = tabulate(f, cdf, bins, guide));
        let marginal = PiecewiseConstant1D::new(&integrals);
        // The very products `sample` and `pdf` computed from the two
        // tables, so that they are equal bit for bit.
        let joint = conditional
            .chunks_exact(nu + 1)
            .enumerate()
            .flat_map(|(row, bins)| {
                let pdf_v = marginal.bins[row][1];
                bins[..nu].iter().map(move |b| pdf_v * b[1])
            })
            .collect();
        Self { conditional, conditional_guide, guide_len, marginal, joint, nu }
    }

    /// The integral of the function over `[0, 1]²` (0 for a zero function,
    /// which is sampled uniformly).
    pub fn integral(&self) -> f32 {
        self.marginal.integral()
    }

    /// Sample a point with uniform `u` in `[0, 1)²` (`u.y` picks the row,
    /// `u.x` the column): the point and its density.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (v, pdf_v, row) = self.marginal.sample(u.y);
        let (bins, guide) = self.row(row);
        let (x, pdf_u, _) = sample_table(bins, guide, u.x);
        (Vec2::new(x, v), pdf_v * pdf_u)
    }

    /// Row `row`'s conditional table: its bins and its guide table.
    #[inline]
    fn row(&self, row: usize) -> (&[[f32; 2]], &[u32]) {
        let (b, g) = (self.nu + 1, self.guide_len);
        (&self.conditional[row * b..(row + 1) * b], &self.conditional_guide[row * g..(row + 1) * g])
    }

    /// [`PiecewiseConstant2D::sample`] of each point of `u`, into `out`
    /// (of the same length), bit for bit, for a caller with many samples
    /// to take. A large table's rows are read at random (an environment
    /// map of 512 × 256 has 1 MB of them) and are usually cache misses:
    /// here up to [`LANES`] samples take each step of their two searches
    /// together (the marginal's, then their rows'), so that the misses of
    /// all of them overlap instead of following one another.
    ///
    /// ```
    /// use lucent::geometry::Vec2;
    /// use lucent::sampling::PiecewiseConstant2D;
    ///
    /// let d = PiecewiseConstant2D::new(&[1.0, 2.0, 3.0, 0.0, 5.0, 6.0], 3, 2);
    /// let u = [Vec2::new(0.1, 0.9), Vec2::new(0.7, 0.2)];
    /// let mut out = [(Vec2::ZERO, 0.0); 2];
    /// d.sample_many(&u, &mut out);
    /// assert_eq!(out, [d.sample(u[0]), d.sample(u[1])]);
    /// ```
    ///
    /// # Panics
    /// If `out` and `u` differ in length.
    pub fn sample_many(&self, u: &[Vec2], out: &mut [(Vec2, f32)]) {
        assert_eq!(u.len(), out.len(), "one sample per point");
        let marginal = TablesOf {
            bins: &self.marginal.bins,
            guide: &self.marginal.guide,
            len: self.marginal.bins.len(),
            guide_len: self.marginal.guide.len(),
        };
        let rows = TablesOf {
            bins: &self.conditional,
            guide: &self.conditional_guide,
            len: self.nu + 1,
            guide_len: self.guide_len,
        };
        for (u, out) in u.chunks(LANES).zip(out.chunks_mut(LANES)) {
            let n = u.len();
            let (mut ux, mut uy) = ([0.0; LANES], [0.0; LANES]);
            for (k, u) in u.iter().enumerate() {
                (ux[k], uy[k]) = (u.x, u.y);
            }
            // The rows, from the marginal table; then the columns.
            let mut v = [(0.0, 0.0, 0); LANES];
            marginal.sample_lanes(&[0; LANES], &uy, n, &mut v);
            let mut row = [0u32; LANES];
            for k in 0..n {
                row[k] = v[k].2 as u32;
            }
            let mut x = [(0.0, 0.0, 0); LANES];
            rows.sample_lanes(&row, &ux, n, &mut x);
            for (k, out) in out.iter_mut().enumerate() {
                *out = (Vec2::new(x[k].0, v[k].0), v[k].1 * x[k].1);
            }
        }
    }

    /// The density at `uv`: exactly what [`PiecewiseConstant2D::sample`]
    /// returns for a point there.
    pub fn pdf(&self, uv: Vec2) -> f32 {
        self.cell_pdf(self.cell(uv))
    }

    /// The index (row by row) of the cell containing `uv` (clamped into
    /// `[0, 1]²`): [`PiecewiseConstant2D::pdf`] in two steps, for callers
    /// that look many cells up at once.
    #[inline]
    pub fn cell(&self, uv: Vec2) -> usize {
        let row = self.marginal.bin(uv.y);
        // The bin of `uv.x` in the row (`PiecewiseConstant1D::bin` of a
        // table of `nu` bins).
        let col = ((uv.x * self.nu as f32).max(0.0) as usize).min(self.nu - 1);
        row * self.nu + col
    }

    /// The density on cell `cell` (an index from
    /// [`PiecewiseConstant2D::cell`]).
    #[inline]
    pub fn cell_pdf(&self, cell: usize) -> f32 {
        self.joint[cell]
    }
}

/// Choosing one of `n` items with probabilities proportional to weights, in
/// constant time per choice: Vose's alias method (PBRT 4th ed., §A.1.4).
///
/// Each of the `n` slots holds a probability `q_i` and an alias `a_i`: pick
/// slot `i` uniformly, keep `i` with probability `q_i`, otherwise take `a_i`.
#[derive(Clone, Debug, PartialEq)]
pub struct AliasTable {
    /// The slots, each with everything a choice reads: one load.
    slots: Vec<AliasSlot>,
    /// The normalised probabilities.
    pmf: Vec<f32>,
    /// The number of slots as a float, for [`AliasTable::sample`].
    n: f64,
}

/// One slot of an [`AliasTable`]: its item is kept with probability
/// `keep`, otherwise its alias is taken; the probabilities of both items
/// are stored beside them, so that a choice reads one slot and nothing else.
#[derive(Clone, Copy, Debug, PartialEq)]
struct AliasSlot {
    keep: f32,
    alias: u32,
    pmf: f32,
    alias_pmf: f32,
}

impl AliasTable {
    /// A table for `weights` (see the module docs for zero weights). An empty
    /// `weights` gives an empty table, which samples nothing.
    pub fn new(weights: &[f32]) -> Self {
        let n = weights.len();
        let w: Vec<f64> = weights.iter().map(|&v| sanitize(v) as f64).collect();
        let total: f64 = w.iter().sum();
        let pmf64: Vec<f64> = if total > 0.0 && total.is_finite() {
            w.iter().map(|v| v / total).collect()
        } else {
            vec![1.0 / n as f64; n]
        };
        // Scaled probabilities: an item with p·n < 1 is "small" and fills
        // its slot up with a "large" one (Vose's two work lists).
        let mut keep = vec![1.0f64; n];
        let mut alias: Vec<u32> = (0..n as u32).collect();
        let mut scaled: Vec<f64> = pmf64.iter().map(|p| p * n as f64).collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            large.pop();
            keep[s] = scaled[s];
            alias[s] = l as u32;
            // The large item gave away 1 - scaled[s] of its mass.
            scaled[l] = (scaled[l] + scaled[s]) - 1.0;
            if scaled[l] < 1.0 {
                small.push(l);
            } else {
                large.push(l);
            }
        }
        // What remains is 1 up to rounding.
        for i in small.into_iter().chain(large) {
            keep[i] = 1.0;
            alias[i] = i as u32;
        }
        let pmf: Vec<f32> = pmf64.into_iter().map(|p| p as f32).collect();
        let slots = (0..n)
            .map(|i| AliasSlot {
                keep: keep[i] as f32,
                alias: alias[i],
                pmf: pmf[i],
                alias_pmf: pmf[alias[i] as usize],
            })
            .collect();
        Self { slots, pmf, n: n as f64 }
    }

    /// Number of items.
    pub fn len(&self) -> usize {
        self.pmf.len()
    }

    /// Whether there are no items.
    pub fn is_empty(&self) -> bool {
        self.pmf.is_empty()
    }

    /// Choose an item with a uniform `u` in `[0, 1)`: its index and
    /// probability. `None` for an empty table. The slot comes from the
    /// integer part of `u·n` and the keep/alias decision from the fraction.
    #[inline]
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        let last = self.slots.len().checked_sub(1)?;
        // u·n is exact in f64 (a 24-bit fraction times n < 2³²), and so is
        // its fraction. (Slot numbers fit in u32, whose conversions to and
        // from f64 are single instructions, unlike usize's.)
        let scaled = u.clamp(0.0, 1.0) as f64 * self.n;
        let slot = (scaled as u32).min(last as u32);
        let frac = (scaled - slot as f64) as f32;
        let s = &self.slots[slot as usize];
        Some(if frac < s.keep { (slot as usize, s.pmf) } else { (s.alias as usize, s.alias_pmf) })
    }

    /// Probability of item `i` (0 when out of range).
    pub fn pmf(&self, i: usize) -> f32 {
        self.pmf.get(i).copied().unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    #[test]
    fn pdf_1d_integrates_to_one_and_matches_samples() {
        let f = [0.0, 1.0, 3.0, 0.0, 0.5, 2.0, 0.0, 0.0];
        let d = PiecewiseConstant1D::new(&f);
        assert!((d.integral() - 6.5 / 8.0).abs() < 1e-6);
        let n = 8000;
        let integral: f32 = (0..n).map(|i| d.pdf((i as f32 + 0.5) / n as f32)).sum::<f32>() / n as f32;
        assert!((integral - 1.0).abs() < 1e-4, "{integral}");
        // Histogram of samples per bin against the expected probabilities.
        let mut rng = Pcg32::new(3, 0);
        let m = 200_000;
        let mut hist = [0u32; 8];
        for _ in 0..m {
            let (x, pdf, o) = d.sample(rng.uniform());
            assert!((0.0..1.0).contains(&x));
            assert_eq!(o, (x * 8.0) as usize);
            assert_eq!(pdf, d.pdf(x), "sample and pdf agree");
            assert!(pdf > 0.0, "zero bins are never sampled");
            hist[o] += 1;
        }
        for (i, &h) in hist.iter().enumerate() {
            let p = f[i] / 6.5;
            let sigma = (m as f32 * p * (1.0 - p)).sqrt();
            assert!((h as f32 - m as f32 * p).abs() <= 5.0 * sigma + 1.0, "bin {i}: {h} vs {}", m as f32 * p);
        }
    }

    /// The guide table changes how the CDF is searched, never the answer:
    /// for tables of many sizes and shapes (zero runs, spikes, one bin,
    /// sizes off and on powers of two), every `u` gives the full binary
    /// search's bin, at random, on the slice boundaries `k / K`, on the
    /// CDF's own values and their neighbours, and outside `[0, 1)`.
    #[test]
    fn guide_table_gives_the_full_search_answer() {
        let mut rng = Pcg32::new(11, 5);
        for n in [1usize, 2, 3, 7, 8, 9, 64, 100, 513, 1000] {
            for shape in 0..4 {
                let f: Vec<f32> = (0..n)
                    .map(|i| match shape {
                        0 => 1.0,
                        1 => rng.uniform(),
                        // Long runs of zero bins.
                        2 => (i % 5 == 0) as u8 as f32 * rng.uniform(),
                        // One spike among tiny values.
                        _ => {
                            if i == n / 3 {
                                1e6
                            } else {
                                1e-3
                            }
                        }
                    })
                    .collect();
                let d = PiecewiseConstant1D::new(&f);
                let slices = (d.guide.len() - 1) as f32;
                let mut us: Vec<f32> = (0..2000).map(|_| rng.uniform()).collect();
                us.extend((0..d.guide.len()).map(|k| k as f32 / slices));
                for &[c, _] in &d.bins {
                    us.extend([c, c.next_up(), c.next_down()]);
                }
                us.extend([-1.0, -0.0, 1.0, 1.5, f32::NAN, f32::INFINITY, 1.0f32.next_down()]);
                for u in us {
                    let full = d.bins.partition_point(|b| b[0] <= u);
                    assert_eq!(cdf_rank(&d.bins, &d.guide, u), full, "n {n}, shape {shape}, u {u:e}");
                }
            }
        }
    }

    #[test]
    fn sample_1d_inverts_the_cdf_within_a_bin() {
        let d = PiecewiseConstant1D::new(&[1.0, 3.0]);
        // CDF: 0, 0.25, 1. u = 0.625 is half-way through bin 1.
        let (x, pdf, o) = d.sample(0.625);
        assert_eq!(o, 1);
        assert!((x - 0.75).abs() < 1e-6);
        assert!((pdf - 1.5).abs() < 1e-6);
        assert_eq!(d.sample(0.0).2, 0);
    }

    #[test]
    fn zero_functions_fall_back_to_uniform() {
        for f in [&[0.0f32, 0.0, 0.0][..], &[][..], &[f32::NAN, 0.0][..]] {
            let d = PiecewiseConstant1D::new(f);
            assert_eq!(d.integral(), 0.0);
            let (x, pdf, _) = d.sample(0.3);
            assert!((x - 0.3).abs() < 1e-6);
            assert_eq!(pdf, 1.0);
            assert_eq!(d.pdf(0.9), 1.0);
        }
        let d2 = PiecewiseConstant2D::new(&[0.0; 6], 3, 2);
        let (uv, pdf) = d2.sample(Vec2::new(0.2, 0.7));
        assert!((uv - Vec2::new(0.2, 0.7)).length() < 1e-6);
        assert_eq!(pdf, 1.0);
        let a = AliasTable::new(&[0.0, 0.0]);
        assert_eq!(a.pmf(0), 0.5);
        assert!(AliasTable::new(&[]).sample(0.5).is_none());
    }

    #[test]
    fn pdf_2d_integrates_to_one_and_agrees_with_samples() {
        let (nu, nv) = (5, 4);
        let f: Vec<f32> =
            (0..nu * nv).map(|i| if i % 7 == 3 { 0.0 } else { (i % 5) as f32 + 0.25 * (i / 5) as f32 }).collect();
        let d = PiecewiseConstant2D::new(&f, nu, nv);
        let total: f32 = f.iter().sum::<f32>() / (nu * nv) as f32;
        assert!((d.integral() - total).abs() < 1e-5);
        let g = 200;
        let mut integral = 0.0;
        for i in 0..g {
            for j in 0..g {
                integral += d.pdf(Vec2::new((i as f32 + 0.5) / g as f32, (j as f32 + 0.5) / g as f32));
            }
        }
        integral /= (g * g) as f32;
        assert!((integral - 1.0).abs() < 1e-4, "{integral}");
        let mut rng = Pcg32::new(11, 1);
        let m = 200_000;
        let mut hist = vec![0u32; nu * nv];
        for _ in 0..m {
            let (uv, pdf) = d.sample(Vec2::new(rng.uniform(), rng.uniform()));
            let cell = (uv.y * nv as f32) as usize * nu + (uv.x * nu as f32) as usize;
            assert!((pdf - d.pdf(uv)).abs() <= 1e-6 * pdf, "{pdf} vs {}", d.pdf(uv));
            // pdf = f / ∫f.
            assert!((pdf - f[cell] / total).abs() < 1e-4 * pdf.max(1.0));
            hist[cell] += 1;
        }
        for (c, &h) in hist.iter().enumerate() {
            let p = f[c] / (total * (nu * nv) as f32);
            let sigma = (m as f32 * p * (1.0 - p)).sqrt();
            assert!((h as f32 - m as f32 * p).abs() <= 5.0 * sigma + 1.0, "cell {c}: {h} vs {}", m as f32 * p);
        }
    }

    /// The joint table gives exactly the product of the marginal's and the
    /// row's densities, anywhere (edges, outside `[0, 1]²`, zero rows and
    /// zero functions included).
    #[test]
    fn pdf_2d_joint_table_is_the_product_of_the_two_densities() {
        let mut rng = Pcg32::new(7, 3);
        for (nu, nv) in [(1, 1), (5, 4), (16, 9), (33, 2)] {
            for zero in [false, true] {
                let f: Vec<f32> =
                    (0..nu * nv).map(|i| if zero || (i / nu) % 3 == 1 { 0.0 } else { rng.uniform() * 10.0 }).collect();
                let d = PiecewiseConstant2D::new(&f, nu, nv);
                let mut uvs: Vec<Vec2> = (0..3000).map(|_| Vec2::new(rng.uniform(), rng.uniform())).collect();
                for x in [-0.5, 0.0, 1.0f32.next_down(), 1.0, 1.5, f32::NAN] {
                    uvs.extend([Vec2::new(x, 0.5), Vec2::new(0.5, x), Vec2::splat(x)]);
                }
                for uv in uvs {
                    let row = d.marginal.bin(uv.y);
                    let conditional = PiecewiseConstant1D::new(&f[row * nu..(row + 1) * nu]);
                    let product = d.marginal.pdf(uv.y) * conditional.pdf(uv.x);
                    assert_eq!(d.pdf(uv).to_bits(), product.to_bits(), "{nu}×{nv}, {uv}");
                }
            }
        }
    }

    /// The rows of a 2D table, written in place and in parallel, are the
    /// 1D tables of the rows bit for bit (bins, guide tables, integrals),
    /// zero rows and non-finite entries included, with enough rows to be
    /// split among threads.
    #[test]
    fn rows_in_place_equal_one_dimensional_tables() {
        let mut rng = Pcg32::new(31, 7);
        let (nu, nv) = (37, 300);
        let f: Vec<f32> = (0..nu * nv)
            .map(|i| match (i / nu) % 7 {
                0 => 0.0,
                1 => f32::NAN,
                2 => -rng.uniform(),
                3 if i % nu == 5 => f32::INFINITY,
                _ => rng.uniform() * 100.0,
            })
            .collect();
        let d = PiecewiseConstant2D::new(&f, nu, nv);
        let mut integrals = Vec::new();
        for (row, values) in f.chunks_exact(nu).enumerate() {
            let want = PiecewiseConstant1D::new(values);
            let (bins, guide) = d.row(row);
            let bits = |b: &[[f32; 2]]| b.iter().map(|b| b.map(f32::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(bins), bits(&want.bins), "row {row}");
            assert_eq!(guide, &want.guide[..], "row {row}");
            integrals.push(want.integral());
        }
        assert_eq!(d.marginal, PiecewiseConstant1D::new(&integrals));
    }

    /// Samples taken together ([`PiecewiseConstant2D::sample_many`]) are
    /// [`PiecewiseConstant2D::sample`]'s bit for bit, for tables with zero
    /// rows, zero runs and spikes (whose guide slices span many bins or
    /// none), samples on the slice boundaries and outside `[0, 1)`, and
    /// batches of every length around the lane count.
    #[test]
    fn samples_together_equal_samples_one_at_a_time() {
        let mut rng = Pcg32::new(23, 1);
        for (nu, nv) in [(1, 1), (7, 3), (64, 32), (513, 5), (2048, 2)] {
            for shape in 0..4 {
                let f: Vec<f32> = (0..nu * nv)
                    .map(|i| match shape {
                        0 => rng.uniform(),
                        1 => ((i / nu) % 2 == 0 && i % 5 == 0) as u8 as f32 * rng.uniform(),
                        2 => {
                            if i == nu * nv / 3 {
                                1e6
                            } else {
                                1e-3
                            }
                        }
                        // Nothing but a few spikes: most slices hold no CDF entry.
                        _ => (i % 97 == 3) as u8 as f32,
                    })
                    .collect();
                let d = PiecewiseConstant2D::new(&f, nu, nv);
                let slices = (d.guide_len - 1) as f32;
                let mut us: Vec<Vec2> = (0..3000).map(|_| Vec2::new(rng.uniform(), rng.uniform())).collect();
                us.extend((0..d.guide_len - 1).map(|k| Vec2::new(k as f32 / slices, rng.uniform())));
                us.extend((0..d.guide_len - 1).map(|k| Vec2::new(rng.uniform(), k as f32 / slices)));
                us.extend([
                    Vec2::ZERO,
                    Vec2::splat(1.0f32.next_down()),
                    Vec2::new(1.0, 0.5),
                    Vec2::new(0.5, 1.0),
                    Vec2::new(-0.25, 0.5),
                    Vec2::new(0.5, f32::NAN),
                    Vec2::new(f32::INFINITY, 0.5),
                ]);
                let want: Vec<(Vec2, f32)> = us.iter().map(|&u| d.sample(u)).collect();
                for batch in [1, 5, LANES - 1, LANES, LANES + 1, 3 * LANES + 7] {
                    for (us, want) in us.chunks(batch).zip(want.chunks(batch)) {
                        let mut got = vec![(Vec2::ZERO, 0.0); us.len()];
                        d.sample_many(us, &mut got);
                        for ((u, g), w) in us.iter().zip(&got).zip(want) {
                            assert_eq!(
                                (g.0.x.to_bits(), g.0.y.to_bits(), g.1.to_bits()),
                                (w.0.x.to_bits(), w.0.y.to_bits(), w.1.to_bits()),
                                "{nu}×{nv}, shape {shape}, batch {batch}, {u}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn alias_table_frequencies_match_weights() {
        let w = [1.0, 0.0, 5.0, 2.0, 0.25, 10.0];
        let t = AliasTable::new(&w);
        let total: f32 = w.iter().sum();
        assert!((0..w.len()).map(|i| t.pmf(i)).sum::<f32>() - 1.0 < 1e-6);
        let mut rng = Pcg32::new(5, 5);
        let m = 300_000;
        let mut hist = [0u32; 6];
        for _ in 0..m {
            let (i, p) = t.sample(rng.uniform()).unwrap();
            assert_eq!(p, t.pmf(i));
            hist[i] += 1;
        }
        for (i, &h) in hist.iter().enumerate() {
            let p = w[i] / total;
            assert!((t.pmf(i) - p).abs() < 1e-6);
            let sigma = (m as f32 * p * (1.0 - p)).sqrt();
            assert!((h as f32 - m as f32 * p).abs() <= 5.0 * sigma + 1.0, "item {i}: {h}");
        }
        assert_eq!(hist[1], 0);
        assert_eq!(t.pmf(99), 0.0);
    }

    /// A choice takes the slot from the integer part of `u·n` and decides
    /// between the slot's item and its alias by the fraction, both computed
    /// in f64: the packed slots and the 32-bit conversions of
    /// [`AliasTable::sample`] give that choice for every `u`, the ends and
    /// values outside `[0, 1)` included.
    #[test]
    fn alias_table_choice_is_the_integer_and_fraction_of_u_n() {
        let mut rng = Pcg32::new(8, 1);
        for n in [1usize, 2, 3, 7, 64, 1000, 4099] {
            let w: Vec<f32> = (0..n).map(|i| if i % 5 == 3 { 0.0 } else { rng.uniform() + 0.01 }).collect();
            let t = AliasTable::new(&w);
            let mut us: Vec<f32> = (0..20_000).map(|_| rng.uniform()).collect();
            us.extend((0..=n).map(|k| k as f32 / n as f32));
            us.extend([0.0, -0.0, 1.0f32.next_down(), 1.0, 1.5, -0.5, f32::INFINITY, f32::NAN]);
            for u in us {
                let scaled = u.clamp(0.0, 1.0) as f64 * n as f64;
                let slot = (scaled as usize).min(n - 1);
                let frac = (scaled - slot as f64) as f32;
                let s = &t.slots[slot];
                let i = if frac < s.keep { slot } else { s.alias as usize };
                assert_eq!(t.sample(u), Some((i, t.pmf(i))), "n = {n}, u = {u}");
            }
        }
        assert_eq!(AliasTable::new(&[]).sample(0.5), None);
    }
}
