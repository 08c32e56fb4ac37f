//! Samplers: an endless, deterministic sequence of sample vectors per
//! pixel, addressed by sample index, so that a render can stop after any
//! number of samples and later continue (PBRT 4th ed., ch. 8).
//!
//! # The stratified sampler
//!
//! [`SamplerKind::Stratified`] is the classic renderer's jittered grid
//! ([`PixelSampler`]): the samples of a pixel come in runs of `spp` (the
//! render's samples per pixel); each run is one stratified pattern of film
//! positions and one of lens positions, drawn from a generator seeded by the
//! seed, the pixel and the run. With one sample per pixel the film position
//! is the pixel centre. Dimensions after the lens are independent uniform
//! numbers.
//!
//! # The Sobol sampler
//!
//! [`SamplerKind::Sobol`] is the "shuffled, scrambled, padded" Sobol sampler
//! of Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020, §4–5.
//! Every request for a 1D or 2D value opens a new *dimension* `d` (counted
//! from 0 at [`Sampler::start_pixel_sample`]). For dimension `d` of
//! sample `i` of pixel `(x, y)`:
//!
//! 1. the index is shuffled, `j = owen(i, h₀)`, a nested uniform Owen
//!    scramble of the index's bits (seen as a base-2 fraction), with a hash
//!    `h₀` of (seed, pixel, d). An Owen scramble of the index maps every
//!    aligned block of 2ᵏ indices onto an aligned block of 2ᵏ indices, so the
//!    first 2ᵏ samples of the pixel are always a whole aligned block of the
//!    Sobol sequence — and a different block, in a different order, for each
//!    dimension, which decorrelates the dimensions ("padding");
//! 2. the point `(sobol₀(j), sobol₁(j))` is taken from the first two Sobol
//!    dimensions (a 1D request uses `sobol₀` alone);
//! 3. each coordinate is Owen-scrambled with its own hash `h₁`, `h₂`.
//!
//! The first two Sobol dimensions form a (0,2)-sequence in base 2: every
//! aligned block of 2ᵏ points is a (0,k,2)-net, i.e. each elementary
//! interval `[a/2ᵖ, (a+1)/2ᵖ) × [b/2^q, (b+1)/2^q)` with `p + q = k` holds
//! exactly one point (Sobol 1967; Niederreiter, "Random Number Generation
//! and Quasi-Monte Carlo Methods", 1992, ch. 4). Owen scrambling preserves
//! that property (Owen 1995) while making each point uniformly distributed,
//! so the estimates are unbiased and their error falls faster than with
//! independent samples: for every power-of-two prefix of the samples, every
//! 2D request of a path is stratified.

use super::{mix_seed, Pcg32, PixelSampler};
use glam::Vec2;

/// Which sample sequence a render uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SamplerKind {
    /// Jittered (stratified) film and lens positions, in runs of the
    /// render's samples per pixel: the classic renderer's sampling.
    Stratified,
    /// Independent uniform random numbers.
    Independent,
    /// Owen-scrambled Sobol points: low discrepancy in every pair of
    /// dimensions.
    #[default]
    Sobol,
}

/// The sample vectors of one pixel sample. Dimensions are consumed in
/// order: [`Sampler::pixel_2d`] first, then whatever the camera and the
/// integrator ask for.
///
/// The values depend only on the seed, the pixel, the sample index and how
/// many values were requested before in the same pixel sample — not on the
/// thread, nor on which samples were rendered before — so a render can be
/// resumed at any sample index and two runs are bit-identical.
///
/// ```
/// use lucent::sampling::{Sampler, SamplerKind};
///
/// let mut s = Sampler::new(SamplerKind::Sobol, 7, 16);
/// s.start_pixel_sample(3, 4, 0);
/// let film = s.pixel_2d();
/// let lens = s.get_2d();
/// let light = s.get_1d();
/// for v in [film.x, film.y, lens.x, lens.y, light] {
///     assert!((0.0..1.0).contains(&v));
/// }
/// // The same pixel sample gives the same values again.
/// s.start_pixel_sample(3, 4, 0);
/// assert_eq!(s.pixel_2d(), film);
/// ```
#[derive(Clone, Debug)]
pub struct Sampler {
    kind: SamplerKind,
    seed: u64,
    /// Samples per pixel of a stratified run.
    strata: u32,
    /// The stratified sampler's patterns, and the (x, y, run) they are for.
    pattern: Option<(Box<PixelSampler>, (u32, u32, u32))>,
    /// The current sample's place in its run (stratified sampler).
    stratum: u32,
    /// The pixel of the current sample (stratified sampler).
    pixel: (u32, u32),
    /// Whether `rng` is seeded for the current pixel sample (stratified
    /// sampler).
    rng_ready: bool,
    /// Hash of (seed, x, y): the per-pixel part of every scramble seed.
    pixel_hash: u64,
    /// The pixel whose dimensions' scramble seeds `seeds` holds (Sobol).
    seeds_pixel: Option<(u32, u32)>,
    /// The scramble seeds of the current pixel's first dimensions, filled
    /// as they are first drawn one at a time ([`Sampler::get_1d`],
    /// [`Sampler::get_2d`]). They depend on the seed, the pixel and the
    /// dimension only, and a render draws a pixel's samples one after
    /// another, so every sample after the first reuses them. (A vertex's
    /// dimensions drawn for many paths at once, [`Sampler::vertex_lanes`],
    /// are hashed in vector code instead: cheaper there than reading and
    /// transposing the lanes' tables.)
    seeds: Vec<[u32; 3]>,
    /// The sample index within the pixel.
    index: u32,
    /// The index's bits reversed and put through the seed-independent
    /// first step of the scramble ([`lk_premix`]): the part of every
    /// dimension's index shuffle that is the same for all dimensions.
    index_premixed: u32,
    /// The next dimension (Sobol).
    dimension: u32,
    /// The independent sampler's generator, re-seeded per pixel sample.
    rng: Pcg32,
}

/// 2⁻²⁴: converts a 24-bit integer to a float in `[0, 1)` exactly.
const INV_2_24: f32 = 1.0 / (1u32 << 24) as f32;

impl Sampler {
    /// A sampler of `kind` for a render with `seed` and `spp` samples per
    /// pixel (the length of a stratified run; the other kinds ignore it).
    pub fn new(kind: SamplerKind, seed: u64, spp: u32) -> Self {
        Self {
            kind,
            seed,
            strata: spp.max(1),
            pattern: None,
            stratum: 0,
            pixel: (0, 0),
            rng_ready: false,
            pixel_hash: 0,
            seeds_pixel: None,
            seeds: Vec::new(),
            index: 0,
            index_premixed: 0,
            dimension: 0,
            rng: Pcg32::new(seed, 0),
        }
    }

    /// Which sequence this is.
    pub fn kind(&self) -> SamplerKind {
        self.kind
    }

    /// Start sample number `index` of pixel `(x, y)`; the values that follow
    /// depend only on the seed, the pixel, the index and the dimension.
    #[inline(always)]
    pub fn start_pixel_sample(&mut self, x: u32, y: u32, index: u32) {
        self.index = index;
        self.dimension = 0;
        match self.kind {
            SamplerKind::Independent => {
                // One generator per pixel sample; its draws are taken in
                // order, so the values depend on (seed, x, y, index) and the
                // position in the sequence only.
                self.rng = Pcg32::new(mix_seed(&[self.seed, x as u64, y as u64, index as u64]), 0);
            }
            SamplerKind::Sobol => {
                if self.seeds_pixel != Some((x, y)) {
                    self.pixel_hash = mix_seed(&[self.seed, x as u64, y as u64]);
                    self.seeds_pixel = Some((x, y));
                    self.seeds.clear();
                }
                self.index_premixed = lk_premix(index.reverse_bits());
            }
            SamplerKind::Stratified => {
                let run = index / self.strata;
                self.stratum = index - run * self.strata;
                let key = (x, y, run);
                if !matches!(&self.pattern, Some((_, k)) if *k == key) {
                    let mut pixel = match self.pattern.take() {
                        Some((p, _)) => p,
                        None => Box::new(PixelSampler::new(self.strata)),
                    };
                    // The first run is seeded as the classic renderer always
                    // was; later runs mix in their number.
                    let seed = if run == 0 { self.seed } else { mix_seed(&[self.seed, run as u64]) };
                    pixel.start_pixel(seed, x, y, self.strata);
                    self.pattern = Some((pixel, key));
                }
                // The generator of the dimensions after the lens is seeded
                // when first needed (the Whitted integrator needs none).
                self.pixel = (x, y);
                self.rng_ready = false;
            }
        }
    }

    /// The stratified sampler's generator for the dimensions after the
    /// lens, seeded by (seed, pixel, index) on first use.
    #[inline(always)]
    fn stratified_rng(&mut self) -> &mut Pcg32 {
        if !self.rng_ready {
            self.seed_stratified_rng();
        }
        &mut self.rng
    }

    /// Seed the stratified sampler's generator (once per pixel sample).
    #[inline(never)]
    fn seed_stratified_rng(&mut self) {
        let (x, y) = self.pixel;
        self.rng = Pcg32::new(mix_seed(&[self.seed, x as u64, y as u64, self.index as u64]), 1);
        self.rng_ready = true;
    }

    /// The stratified pattern's value for the current dimension, if it has
    /// one (dimension 0: film, 1: lens), and advance.
    #[inline(always)]
    fn stratified_2d(&mut self) -> Option<Vec2> {
        let d = self.dimension;
        self.dimension = self.dimension.wrapping_add(1);
        let (pattern, _) = self.pattern.as_mut()?;
        let i = self.stratum as usize;
        match d {
            0 => Some(pattern.film(i)),
            1 => Some(pattern.lens(i)),
            _ => None,
        }
    }

    /// Pass over the next two dimensions without their values (the lens
    /// dimensions, for a camera without a lens): what follows is the same
    /// as after [`Sampler::get_2d`]. The stratified sampler then never draws
    /// the pixel's lens pattern.
    #[inline(always)]
    pub fn skip_2d(&mut self) {
        match self.kind {
            SamplerKind::Stratified if self.dimension == 1 && self.pattern.is_some() => self.dimension += 1,
            _ => {
                self.get_2d();
            }
        }
    }

    /// The next dimension, uniform in `[0, 1)`.
    #[inline(always)]
    pub fn get_1d(&mut self) -> f32 {
        match self.kind {
            SamplerKind::Independent => self.rng.uniform(),
            SamplerKind::Stratified => {
                self.dimension = self.dimension.wrapping_add(1);
                self.stratified_rng().uniform()
            }
            SamplerKind::Sobol => {
                let [h_index, h_x, _] = self.dimension_seeds();
                // Sobol dimension 0 is the van der Corput sequence, the
                // index's bits mirrored about the binary point: the value
                // is `nested_uniform_scramble(j.reverse_bits(), h_x)` with
                // the shuffled index `j = nested_uniform_scramble(index,
                // h_index)`, whose reversals cancel in pairs (see
                // `lk_seeded`).
                let j = lk_seeded(self.index_premixed, h_index).reverse_bits();
                to_unit_float(lk_seeded(lk_premix(j), h_x).reverse_bits())
            }
        }
    }

    /// The next two dimensions, uniform in `[0, 1)²`.
    #[inline(always)]
    pub fn get_2d(&mut self) -> Vec2 {
        match self.kind {
            SamplerKind::Stratified => self.stratified_2d().unwrap_or_else(|| {
                let rng = self.stratified_rng();
                let u = rng.uniform();
                let v = rng.uniform();
                Vec2::new(u, v)
            }),
            SamplerKind::Independent => {
                // Two statements: the x draw comes first, whatever the
                // compiler's evaluation order of a tuple would be.
                let u = self.rng.uniform();
                let v = self.rng.uniform();
                Vec2::new(u, v)
            }
            SamplerKind::Sobol => {
                // As `get_1d`, with the second coordinate
                // `nested_uniform_scramble(sobol_1(j), h_y)`, whose input
                // reversal is folded into the tables of `sobol_1_reversed`.
                let [h_index, h_x, h_y] = self.dimension_seeds();
                let j = lk_seeded(self.index_premixed, h_index).reverse_bits();
                let x = lk_seeded(lk_premix(j), h_x).reverse_bits();
                let y = lk_seeded(lk_premix(sobol_1_reversed(j)), h_y).reverse_bits();
                Vec2::new(to_unit_float(x), to_unit_float(y))
            }
        }
    }

    /// The five dimensions a path vertex draws, in their order: light
    /// choice (1D), point on the light (2D), lobe choice (1D), direction
    /// (2D) and Russian roulette (1D). The same values as those calls one
    /// by one.
    #[inline(always)]
    pub fn vertex(&mut self) -> VertexSamples {
        let light = self.get_1d();
        let point = self.get_2d();
        let lobe = self.get_1d();
        let dir = self.get_2d();
        let rr = self.get_1d();
        VertexSamples { light, point, lobe, dir, rr }
    }

    /// The Sobol sampler's state for its next `dimensions` dimensions,
    /// which it then skips: the premixed index, the pixel's hash and the
    /// first of them. For [`super::lanes`], which computes the values of
    /// many samplers at once, scramble seeds included ([`dimension_hash`]).
    #[inline(always)]
    pub(super) fn sobol_state(&mut self, dimensions: u32) -> (u32, u64, u32) {
        debug_assert_eq!(self.kind, SamplerKind::Sobol);
        let d = self.dimension;
        self.dimension = d.wrapping_add(dimensions);
        (self.index_premixed, self.pixel_hash, d)
    }

    /// The Sobol scramble seeds the pixel's table keeps (for tests).
    #[cfg(test)]
    pub(super) fn kept_seeds(&self) -> &[[u32; 3]] {
        &self.seeds
    }

    /// Keep the Sobol scramble seeds of the pixel's first `dimensions`
    /// dimensions in its table, where a draw one at a time would have put
    /// them (for [`super::lanes`], whose kernels hash their own: later
    /// draws one at a time keep theirs only after these).
    #[inline]
    pub(super) fn keep_seeds(&mut self, dimensions: u32) {
        while self.seeds.len() < (dimensions as usize).min(MAX_KEPT_DIMENSIONS) {
            let d = self.seeds.len() as u32;
            self.seeds.push(dimension_hash(self.pixel_hash, d));
        }
    }

    /// The sample's position within the pixel filter's support: the first
    /// two dimensions.
    #[inline(always)]
    pub fn pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }

    /// Three 32-bit scramble seeds for the current dimension (index
    /// shuffle, first coordinate, second coordinate), and advance to the
    /// next dimension: from the pixel's table where it has them, else
    /// hashed (and kept, for the first [`MAX_KEPT_DIMENSIONS`]).
    #[inline(always)]
    fn dimension_seeds(&mut self) -> [u32; 3] {
        let d = self.dimension;
        self.dimension = self.dimension.wrapping_add(1);
        if let Some(&seeds) = self.seeds.get(d as usize) {
            return seeds;
        }
        let seeds = dimension_hash(self.pixel_hash, d);
        if self.seeds.len() == d as usize && self.seeds.len() < MAX_KEPT_DIMENSIONS {
            self.seeds.push(seeds);
        }
        seeds
    }
}

/// The sample dimensions of one path vertex ([`Sampler::vertex`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexSamples {
    /// Which light to sample.
    pub light: f32,
    /// Where on the light.
    pub point: Vec2,
    /// Which BSDF lobe to sample.
    pub lobe: f32,
    /// The direction within the lobe.
    pub dir: Vec2,
    /// Russian roulette.
    pub rr: f32,
}

/// How many dimensions' scramble seeds a Sobol sampler keeps for its
/// current pixel: enough for paths of about 200 bounces (five dimensions
/// each), 12 KiB. Deeper dimensions are hashed at every use.
const MAX_KEPT_DIMENSIONS: usize = 1024;

/// The three 32-bit scramble seeds of dimension `d` (index shuffle, first
/// coordinate, second coordinate) of the pixel with `pixel_hash`: two
/// SplitMix64 finalisations of (pixel hash, dimension) give 128 well-mixed
/// bits, of which 96 are used. Out of line: only the one-value requests
/// call it, and keep their callers small (the vertex kernel hashes in its
/// lanes from [`dimension_hash_xy`] and [`dimension_hash_y`]).
#[inline(never)]
fn dimension_hash(pixel_hash: u64, d: u32) -> [u32; 3] {
    let a = dimension_hash_xy(pixel_hash, d);
    [a as u32, (a >> 32) as u32, dimension_hash_y(a)]
}

/// The first 64 bits of [`dimension_hash`]: the index shuffle's seed (low
/// half) and the first coordinate's (high half), all a 1D dimension uses.
#[inline(always)]
pub(super) fn dimension_hash_xy(pixel_hash: u64, d: u32) -> u64 {
    splitmix64(pixel_hash ^ (d as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15))
}

/// The second coordinate's seed of [`dimension_hash`], from its first 64
/// bits `a`.
#[inline(always)]
pub(super) fn dimension_hash_y(a: u64) -> u32 {
    splitmix64(a ^ 0xD1B5_4A32_D192_ED03) as u32
}

/// The SplitMix64 output function (Steele, Lea and Flood, "Fast Splittable
/// Pseudorandom Number Generators", OOPSLA 2014): a bijective 64-bit mix.
#[inline]
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The top 24 bits of a 32-bit fixed-point fraction as a float in `[0, 1)`:
/// every value is exact and the largest is `1 − 2⁻²⁴`.
#[inline(always)]
pub(super) fn to_unit_float(bits: u32) -> f32 {
    (bits >> 8) as f32 * INV_2_24
}

/// The generator matrix of the second Sobol dimension, as its 32 columns
/// (direction numbers) in 0.32 fixed point: column `k` is the image of
/// index bit `k`.
///
/// The second dimension uses the primitive polynomial `x + 1` (degree 1)
/// with initial direction number `m₁ = 1`. The recurrence for direction
/// numbers (Bratley and Fox, "Algorithm 659", ACM TOMS 14(1), 1988, eq. 2),
/// `v_k = a₁v_{k−1} ⊕ v_{k−1}/2` with `a₁ = 1`, gives `v₁ = 1/2` and
/// `v_k = v_{k−1} ⊕ (v_{k−1} >> 1)`: the matrix is Pascal's triangle mod 2.
#[cfg(test)]
const SOBOL_1_MATRIX: [u32; 32] = {
    let mut m = [0u32; 32];
    m[0] = 1 << 31;
    let mut k = 1;
    while k < 32 {
        m[k] = m[k - 1] ^ (m[k - 1] >> 1);
        k += 1;
    }
    m
};

/// [`SOBOL_1_MATRIX`] applied to each possible byte of an index, one table
/// per byte position: the map is linear over GF(2), so the image of an
/// index is the XOR of the images of its four bytes.
#[cfg(test)]
const SOBOL_1_BYTES: [[u32; 256]; 4] = {
    let mut t = [[0u32; 256]; 4];
    let mut byte = 0;
    while byte < 4 {
        let mut x = 0;
        while x < 256 {
            let mut v = 0;
            let mut bit = 0;
            while bit < 8 {
                if x >> bit & 1 == 1 {
                    v ^= SOBOL_1_MATRIX[8 * byte + bit];
                }
                bit += 1;
            }
            t[byte][x] = v;
            x += 1;
        }
        byte += 1;
    }
    t
};

/// The second Sobol dimension of point `index`, in 0.32 fixed point: the
/// XOR of the matrix columns of the index's set bits, gathered a byte at a
/// time from [`SOBOL_1_BYTES`]. (The sampler uses its reversal,
/// [`sobol_1_reversed`].)
#[cfg(test)]
fn sobol_1(index: u32) -> u32 {
    let [b0, b1, b2, b3] = index.to_le_bytes();
    SOBOL_1_BYTES[0][b0 as usize]
        ^ SOBOL_1_BYTES[1][b1 as usize]
        ^ SOBOL_1_BYTES[2][b2 as usize]
        ^ SOBOL_1_BYTES[3][b3 as usize]
}

/// `sobol_1(index).reverse_bits()`: the bit order in which the Owen
/// scramble works, without a reversal, in five shift-mask-XOR steps.
///
/// Column `k` of [`SOBOL_1_MATRIX`] is row `k` of Pascal's triangle mod 2
/// read from the top bit down: bit `31 − m` of it is `C(k, m) mod 2`, which
/// by Lucas' theorem is 1 exactly when the binary digits of `m` are a
/// subset of those of `k`. Reversed, bit `m` of the image is therefore the
/// XOR of the index bits `k ⊇ m`: the superset-sum (zeta) transform over
/// the five-bit bit positions, which takes one step per position bit `b`,
/// `y ⊕= (y >> 2ᵇ) & mask_b` with `mask_b` the positions whose bit `b` is
/// clear. The same steps on every lane of a vector need no table lookups
/// (gathers).
#[inline(always)]
pub(super) fn sobol_1_reversed(index: u32) -> u32 {
    let mut y = index;
    y ^= (y >> 1) & 0x5555_5555;
    y ^= (y >> 2) & 0x3333_3333;
    y ^= (y >> 4) & 0x0f0f_0f0f;
    y ^= (y >> 8) & 0x00ff_00ff;
    y ^= y >> 16;
    y
}

/// The same as [`sobol_1`], one matrix column per set bit (the
/// definition, for tests).
#[cfg(test)]
fn sobol_1_bitwise(mut index: u32) -> u32 {
    let mut v = 0;
    while index != 0 {
        let k = index.trailing_zeros();
        v ^= SOBOL_1_MATRIX[k as usize];
        index &= index - 1;
    }
    v
}

/// A hash-based nested uniform (Owen) scramble of the 0.32 fixed-point
/// fraction `v` (Burley 2020, §3).
///
/// Owen scrambling flips digit `k` of a base-2 fraction according to a
/// random function of the digits before it (more significant ones). After
/// the bits are reversed, the digits before digit `k` are the *lower* bits,
/// and several integer operations have exactly that dependency structure:
/// bit `k` of `x + c`, of `x · odd` and of `x ⊕ (x · even)` is bit `k` of `x`
/// flipped by a function of the lower bits alone. Composing them with
/// seed-dependent operands is the Laine–Karras permutation ("Stratified
/// Sampling for Stochastic Transparency", EGSR 2011) that Burley uses;
/// this variant, with a seed-dependent odd multiplier, follows Vegdahl's
/// refinement of its constants ("Building a Better LK Hash", 2021), which
/// makes the flips of the leading digits depend on more of the seed.
///
/// The sampler evaluates it in two parts, [`lk_premix`] and [`lk_seeded`],
/// on bits it already holds reversed; this function is their definition.
#[cfg(test)]
fn nested_uniform_scramble(v: u32, seed: u32) -> u32 {
    lk_seeded(lk_premix(v.reverse_bits()), seed).reverse_bits()
}

/// The first step of the scramble, on reversed bits: the same for every
/// seed, so an index's is computed once per sample.
#[inline(always)]
pub(super) fn lk_premix(x: u32) -> u32 {
    x ^ x.wrapping_mul(0x3d20_adea)
}

/// The seeded steps of the scramble, on reversed bits: for a fraction `v`,
/// `nested_uniform_scramble(v, seed) = lk_seeded(lk_premix(r), seed)`
/// reversed, with `r` the reversal of `v`. So where `v` is itself a
/// reversal (`j.reverse_bits()`), `r` is `j` and no reversal is needed on
/// the way in.
#[inline(always)]
pub(super) fn lk_seeded(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x = x.wrapping_mul((seed >> 16) | 1);
    x ^= x.wrapping_mul(0x0552_6c56);
    x ^= x.wrapping_mul(0x53a2_2864);
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` successive 2D values of dimension pair `dim` (the `dim`-th
    /// request of each sample) for pixel `(x, y)`, samples `0..n`.
    fn points_2d(kind: SamplerKind, seed: u64, x: u32, y: u32, dim: usize, n: u32) -> Vec<Vec2> {
        let mut s = Sampler::new(kind, seed, 16);
        (0..n)
            .map(|i| {
                s.start_pixel_sample(x, y, i);
                for _ in 0..dim {
                    s.get_2d();
                }
                s.get_2d()
            })
            .collect()
    }

    /// Whether `points` form a (0, k, 2)-net in base 2: every elementary
    /// interval of area 2⁻ᵏ (all shapes 2⁻ᵃ × 2⁻⁽ᵏ⁻ᵃ⁾) holds exactly one.
    fn is_net(points: &[Vec2]) -> bool {
        let n = points.len();
        assert!(n.is_power_of_two());
        let k = n.trailing_zeros();
        for a in 0..=k {
            let (nx, ny) = (1u32 << a, 1u32 << (k - a));
            let mut seen = vec![false; n];
            for p in points {
                let cx = (p.x * nx as f32) as u32;
                let cy = (p.y * ny as f32) as u32;
                let cell = (cy * nx + cx) as usize;
                if seen[cell] {
                    return false;
                }
                seen[cell] = true;
            }
        }
        true
    }

    #[test]
    fn sobol_1_matrix_is_pascal_mod_2() {
        // Column k has bit (31 − r) set iff C(k, r) is odd (Lucas: r ⊆ k).
        for k in 0..32u32 {
            for r in 0..32u32 {
                let expected = r <= k && (r & k) == r;
                assert_eq!(SOBOL_1_MATRIX[k as usize] >> (31 - r) & 1 == 1, expected, "k={k} r={r}");
            }
        }
        // The first points of the second Sobol dimension in index (not Gray
        // code) order: 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8, 7/8.
        let first: Vec<f64> = (0..8).map(|i| sobol_1(i) as f64 / 2f64.powi(32)).collect();
        assert_eq!(first, [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875]);
    }

    #[test]
    fn sobol_1_tables_match_the_matrix() {
        let mut rng = crate::sampling::Pcg32::new(7, 7);
        for i in (0..4096u32).chain((0..100_000).map(|_| rng.next_u32())).chain([u32::MAX, 1 << 31]) {
            assert_eq!(sobol_1(i), sobol_1_bitwise(i), "index {i:#x}");
        }
    }

    #[test]
    fn unscrambled_sobol_is_a_net() {
        for k in 0..=10 {
            let pts: Vec<Vec2> =
                (0..1u32 << k).map(|i| Vec2::new(to_unit_float(i.reverse_bits()), to_unit_float(sobol_1(i)))).collect();
            assert!(is_net(&pts), "k = {k}");
        }
    }

    #[test]
    fn owen_scramble_is_a_nested_permutation() {
        // For every seed, a bijection of 8-bit prefixes that maps intervals
        // of length 2⁻ᵖ onto intervals of length 2⁻ᵖ.
        for seed in [0u32, 1, 0xdead_beef, 0x1234_5678, u32::MAX] {
            let image: Vec<u32> = (0..256u32).map(|v| nested_uniform_scramble(v << 24, seed) >> 24).collect();
            let mut sorted = image.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..256).collect::<Vec<_>>(), "seed {seed:#x}");
            for p in 0..8 {
                let shift = 8 - p;
                for block in 0..(1u32 << p) {
                    let targets: std::collections::HashSet<u32> =
                        (0..(1u32 << shift)).map(|low| image[((block << shift) | low) as usize] >> shift).collect();
                    assert_eq!(targets.len(), 1, "seed {seed:#x}, p {p}");
                }
            }
        }
    }

    /// Skipping two dimensions leaves every sampler where drawing them
    /// would: the values that follow are the same, at the lens dimensions
    /// (the stratified pattern's) and later ones (its generator's).
    #[test]
    fn skip_2d_is_get_2d_without_the_value() {
        for kind in [SamplerKind::Independent, SamplerKind::Sobol, SamplerKind::Stratified] {
            for spp in [1, 4, 9, 10] {
                for skip_at in [1, 2, 3] {
                    let mut a = Sampler::new(kind, 7, spp);
                    let mut b = Sampler::new(kind, 7, spp);
                    for i in 0..2 * spp {
                        a.start_pixel_sample(3, 5, i);
                        b.start_pixel_sample(3, 5, i);
                        assert_eq!(a.pixel_2d(), b.pixel_2d());
                        for _ in 1..skip_at {
                            assert_eq!(a.get_2d(), b.get_2d());
                        }
                        a.get_2d();
                        b.skip_2d();
                        let after_a = (a.get_1d(), a.get_2d(), a.get_1d());
                        let after_b = (b.get_1d(), b.get_2d(), b.get_1d());
                        assert_eq!(after_a, after_b, "{kind:?}, spp {spp}, skip at {skip_at}, sample {i}");
                    }
                }
            }
        }
    }

    /// The stratified sampler's first run of each pixel is exactly the
    /// classic renderer's pattern, and later runs are new patterns,
    /// stratified alike.
    #[test]
    fn stratified_runs_are_the_classic_patterns() {
        for spp in [1, 4, 9, 10] {
            let mut s = Sampler::new(SamplerKind::Stratified, 21, spp);
            let mut classic = PixelSampler::new(spp);
            classic.start_pixel(21, 5, 8, spp);
            for i in 0..spp {
                s.start_pixel_sample(5, 8, i);
                assert_eq!(s.pixel_2d(), classic.film(i as usize), "spp {spp}, sample {i}");
                assert_eq!(s.get_2d(), classic.lens(i as usize), "spp {spp}, sample {i}");
            }
            if spp == 9 {
                let mut cells = [0; 9];
                for i in spp..2 * spp {
                    s.start_pixel_sample(5, 8, i);
                    let p = s.pixel_2d();
                    cells[(p.y * 3.0) as usize * 3 + (p.x * 3.0) as usize] += 1;
                    s.start_pixel_sample(5, 8, i - spp);
                    let first_run = s.pixel_2d();
                    s.start_pixel_sample(5, 8, i);
                    assert_ne!(s.pixel_2d(), first_run);
                }
                assert_eq!(cells, [1; 9], "the second run is a jittered grid too");
            }
        }
    }

    #[test]
    fn values_are_in_unit_interval() {
        for kind in [SamplerKind::Independent, SamplerKind::Sobol, SamplerKind::Stratified] {
            let mut s = Sampler::new(kind, 3, 16);
            for i in 0..2000 {
                s.start_pixel_sample(i % 7, i / 7, i);
                for _ in 0..20 {
                    let v = s.get_2d();
                    assert!((0.0..1.0).contains(&v.x) && (0.0..1.0).contains(&v.y), "{v}");
                    let u = s.get_1d();
                    assert!((0.0..1.0).contains(&u), "{u}");
                }
            }
        }
        // The largest representable value is below 1.
        assert!(to_unit_float(u32::MAX) < 1.0);
    }

    #[test]
    fn deterministic_and_independent_of_history() {
        for kind in [SamplerKind::Independent, SamplerKind::Sobol, SamplerKind::Stratified] {
            let draw = |s: &mut Sampler, x, y, i| {
                s.start_pixel_sample(x, y, i);
                let mut v = vec![s.pixel_2d()];
                v.push(Vec2::splat(s.get_1d()));
                v.push(s.get_2d());
                v
            };
            let mut a = Sampler::new(kind, 11, 16);
            let mut b = Sampler::new(kind, 11, 16);
            // b renders other pixels and samples first: a resumed or
            // differently scheduled render.
            for i in 0..50 {
                draw(&mut b, 9, 9, i);
            }
            let va = draw(&mut a, 2, 5, 64);
            let vb = draw(&mut b, 2, 5, 64);
            assert_eq!(va, vb, "{kind:?}");
            // Other pixels, indices and seeds give other values.
            assert_ne!(va, draw(&mut a, 3, 5, 64), "{kind:?}");
            assert_ne!(va, draw(&mut a, 2, 6, 64), "{kind:?}");
            assert_ne!(va, draw(&mut a, 2, 5, 65), "{kind:?}");
            assert_ne!(va, draw(&mut Sampler::new(kind, 12, 16), 2, 5, 64), "{kind:?}");
        }
    }

    #[test]
    fn sobol_2d_dimensions_are_nets_for_every_power_of_two_prefix() {
        for (x, y, seed) in [(0, 0, 0), (17, 3, 1), (640, 480, 0xfeed)] {
            let all = points_2d(SamplerKind::Sobol, seed, x, y, 0, 1024);
            for dim in 0..6 {
                let pts = points_2d(SamplerKind::Sobol, seed, x, y, dim, 1024);
                for k in 0..=10 {
                    assert!(is_net(&pts[..1 << k]), "pixel ({x}, {y}) dim {dim}: first 2^{k} not a net");
                }
                if dim > 0 {
                    assert_ne!(pts, all, "dimension {dim} repeats dimension 0");
                }
            }
        }
    }

    #[test]
    fn sobol_1d_dimensions_are_stratified() {
        let mut s = Sampler::new(SamplerKind::Sobol, 5, 16);
        for dim in 0..5 {
            for k in 0..=10 {
                let n = 1usize << k;
                let mut seen = vec![false; n];
                for i in 0..n as u32 {
                    s.start_pixel_sample(4, 2, i);
                    for _ in 0..dim {
                        s.get_1d();
                    }
                    let cell = (s.get_1d() * n as f32) as usize;
                    assert!(!seen[cell], "dim {dim}, 2^{k} samples: interval {cell} hit twice");
                    seen[cell] = true;
                }
            }
        }
    }

    /// RMS error over `pixels` pixels of the `n`-sample estimate of the
    /// integral of `f` over the unit square, using 2D dimension `dim`.
    fn rms_error(kind: SamplerKind, n: u32, dim: usize, pixels: u32, f: &dyn Fn(Vec2) -> f64, exact: f64) -> f64 {
        let mut sum_sq = 0.0;
        for p in 0..pixels {
            let pts = points_2d(kind, 99, p % 64, p / 64, dim, n);
            let est = pts.iter().map(|&u| f(u)).sum::<f64>() / n as f64;
            sum_sq += (est - exact).powi(2);
        }
        (sum_sq / pixels as f64).sqrt()
    }

    #[test]
    fn sobol_converges_faster_than_independent() {
        // A smooth integrand: ∫∫ exp(−(x² + y²)) = (√π/2 · erf 1)².
        let smooth = |u: Vec2| (-(u.x as f64).powi(2) - (u.y as f64).powi(2)).exp();
        let erf1 = 0.842_700_792_949_714_9_f64;
        let smooth_exact = (std::f64::consts::PI.sqrt() / 2.0 * erf1).powi(2);
        // A discontinuous one: the disk of radius 0.4 about the centre.
        let disk = |u: Vec2| if (u - Vec2::splat(0.5)).length_squared() < 0.16 { 1.0 } else { 0.0 };
        let disk_exact = std::f64::consts::PI * 0.16;
        for dim in [0, 3] {
            let ind = rms_error(SamplerKind::Independent, 256, dim, 256, &smooth, smooth_exact);
            let sob = rms_error(SamplerKind::Sobol, 256, dim, 256, &smooth, smooth_exact);
            eprintln!("smooth, dim {dim}: independent {ind:.3e}, sobol {sob:.3e}, ratio {:.1}", ind / sob);
            assert!(sob * 4.0 < ind, "smooth, dim {dim}: sobol {sob:e} vs independent {ind:e}");
            let ind = rms_error(SamplerKind::Independent, 256, dim, 256, &disk, disk_exact);
            let sob = rms_error(SamplerKind::Sobol, 256, dim, 256, &disk, disk_exact);
            eprintln!("disk, dim {dim}: independent {ind:.3e}, sobol {sob:.3e}, ratio {:.1}", ind / sob);
            assert!(sob * 2.0 < ind, "disk, dim {dim}: sobol {sob:e} vs independent {ind:e}");
        }
    }

    #[test]
    fn sobol_dimensions_are_uncorrelated() {
        // E[u_d · u_d'] = 1/4 for independent uniforms; check every pair of
        // coordinates among the first four 2D requests, over many pixels.
        let n = 64u32;
        let pixels = 256u32;
        let mut s = Sampler::new(SamplerKind::Sobol, 42, 16);
        let coords = 8;
        let mut sums = vec![0.0f64; coords * coords];
        for p in 0..pixels {
            for i in 0..n {
                s.start_pixel_sample(p, 7, i);
                let mut c = Vec::with_capacity(coords);
                for _ in 0..coords / 2 {
                    let v = s.get_2d();
                    c.extend([v.x as f64, v.y as f64]);
                }
                for a in 0..coords {
                    for b in 0..coords {
                        sums[a * coords + b] += c[a] * c[b];
                    }
                }
            }
        }
        let total = (n * pixels) as f64;
        for a in 0..coords {
            for b in 0..coords {
                let mean = sums[a * coords + b] / total;
                if a == b {
                    // E[u²] = 1/3.
                    assert!((mean - 1.0 / 3.0).abs() < 0.005, "E[u{a}²] = {mean}");
                } else {
                    assert!((mean - 0.25).abs() < 0.008, "E[u{a} u{b}] = {mean}");
                }
            }
        }
    }

    /// The Sobol sampler's values written out as Burley's definition
    /// (module docs): seeds hashed from (seed, pixel, dimension), the index
    /// shuffled, the point's coordinates scrambled. The sampler computes
    /// them with kept seeds, a premixed index and reversals cancelled.
    fn sobol_by_definition(seed: u64, x: u32, y: u32, index: u32, d: u32, two: bool) -> Vec2 {
        let pixel_hash = mix_seed(&[seed, x as u64, y as u64]);
        let a = splitmix64(pixel_hash ^ (d as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let b = splitmix64(a ^ 0xD1B5_4A32_D192_ED03);
        let (h_index, h_x, h_y) = (a as u32, (a >> 32) as u32, b as u32);
        let j = nested_uniform_scramble(index, h_index);
        let u = to_unit_float(nested_uniform_scramble(j.reverse_bits(), h_x));
        let v = if two { to_unit_float(nested_uniform_scramble(sobol_1(j), h_y)) } else { 0.0 };
        Vec2::new(u, v)
    }

    #[test]
    fn sobol_values_equal_their_definition() {
        let mut rng = Pcg32::new(3, 9);
        let mut s = Sampler::new(SamplerKind::Sobol, 11, 16);
        // Pixels revisited out of order, indices large and small, and
        // paths longer than the kept seeds.
        let pixels = [(0, 0), (5, 7), (0, 0), (5, 7), (5, 8), (1023, 0)];
        for (round, &(x, y)) in pixels.iter().cycle().take(24).enumerate() {
            for k in 0..6u32 {
                let index = if k < 4 { k + round as u32 } else { rng.next_u32() };
                s.start_pixel_sample(x, y, index);
                let dims = if k == 5 { MAX_KEPT_DIMENSIONS as u32 + 40 } else { rng.next_u32() % 300 };
                for d in 0..dims {
                    let two = (d + k) % 3 != 0;
                    let expected = sobol_by_definition(11, x, y, index, d, two);
                    let got = if two { s.get_2d() } else { Vec2::new(s.get_1d(), 0.0) };
                    assert_eq!(got, expected, "pixel ({x}, {y}), index {index}, dimension {d}");
                }
            }
        }
        assert_eq!(s.seeds.len(), MAX_KEPT_DIMENSIONS);
    }

    #[test]
    fn sobol_1_reversed_is_sobol_1_reversed() {
        let mut rng = Pcg32::new(5, 5);
        for i in (0..4096u32).chain((0..10_000).map(|_| rng.next_u32())) {
            assert_eq!(sobol_1_reversed(i), sobol_1(i).reverse_bits());
        }
    }

    #[test]
    fn independent_matches_its_generator() {
        let mut s = Sampler::new(SamplerKind::Independent, 8, 16);
        s.start_pixel_sample(1, 2, 3);
        let mut rng = Pcg32::new(mix_seed(&[8, 1, 2, 3]), 0);
        let v = s.get_2d();
        assert_eq!(v, Vec2::new(rng.uniform(), rng.uniform()));
        assert_eq!(s.get_1d(), rng.uniform());
    }
}
