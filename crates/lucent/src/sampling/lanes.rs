//! Sample values for many paths at once: the path integrator draws the five
//! dimensions of a vertex ([`VertexSamples`]) for all the paths of a batch
//! together ([`Sampler::vertex_lanes`]), and the render loop the camera's
//! two dimensions of a run of pixel samples ([`Sampler::camera_lanes`]).
//!
//! The Sobol sampler's values are pure integer arithmetic on (index, seed)
//! pairs: the same multiplications, additions, XORs and bit reversals for
//! every path. Sixteen paths' values are therefore computed as sixteen
//! lanes of vector code ([`sobol_vertices`], [`sobol_camera`], each
//! dimension by [`sobol_dimension`]), with the lanes laid out
//! structure-of-arrays so that the compiler turns each step into one
//! instruction over all lanes (`vpmulld`, `vpaddd`, `vpxor`). The values
//! are those of [`Sampler::vertex`] (and [`Sampler::pixel_2d`],
//! [`Sampler::get_2d`]) bit for bit: the arithmetic is integer, and the
//! same.
//!
//! The kernel also hashes each lane's scramble seeds from (pixel,
//! dimension) itself, rather than reading them from the lane's sampler,
//! where they are kept for one-at-a-time draws. Gathering fifteen seeds a
//! lane from sixty-four samplers' tables into the kernel's lanes (cache
//! misses and scalar stores), and hashing one lane at a time the seeds
//! that the tables lacked, cost more than the hashes in vector code: in
//! the Cornell box at 512², 16 spp, the sampler's functions went from 8.8%
//! of the render to 5.6%. The hash is two SplitMix64 rounds, whose 64-bit
//! multiplications AVX-512 DQ does in one instruction (`vpmullq`), hence
//! the AVX-512 build; AVX2 makes each of them from three 32-bit ones, and
//! its build of the kernel, with the hashes, is as fast as it was with the
//! tables (`docs/performance.md`, twenty-ninth sitting). An earlier
//! AVX-512 build without the hashes, with GFNI's `vgf2p8affineqb` for the
//! bit reversals, had been 5% slower than the AVX2 one
//! (`docs/reliability.md`).

use super::sampler::{
    dimension_hash_xy, dimension_hash_y, lk_premix, lk_seeded, sobol_1_reversed, to_unit_float, Sampler, SamplerKind,
    VertexSamples,
};
use crate::geometry::isa;
#[cfg(target_arch = "x86_64")]
use crate::geometry::Isa;
use glam::Vec2;

/// Paths whose Sobol values one kernel call computes.
const KERNEL_LANES: usize = 16;

/// The inputs of [`sobol_vertices`] and [`sobol_camera`], lane by lane:
/// each path's premixed sample index, its pixel's hash and the first
/// dimension to draw ([`Sampler::sobol_state`]).
#[derive(Clone, Copy, Default)]
struct SobolLanes {
    index_premixed: [u32; KERNEL_LANES],
    pixel_hash: [u64; KERNEL_LANES],
    dimension: [u32; KERNEL_LANES],
}

impl SobolLanes {
    /// Lane `k`'s input: the state of `sampler`, which then skips its next
    /// `dimensions` dimensions.
    #[inline(always)]
    fn set(&mut self, k: usize, sampler: &mut Sampler, dimensions: u32) {
        let (index_premixed, pixel_hash, dimension) = sampler.sobol_state(dimensions);
        self.index_premixed[k] = index_premixed;
        self.pixel_hash[k] = pixel_hash;
        self.dimension[k] = dimension;
    }
}

/// The seven values of a vertex, lane by lane, in [`Sampler::vertex`]'s
/// order: light, point (2), lobe, direction (2), roulette.
type VertexValues = [[f32; KERNEL_LANES]; 7];

impl Sampler {
    /// [`Sampler::vertex`] of `samplers[i]` for each lane `i` in `lanes`,
    /// into `out[i]`: the same values as drawn one by one. The Sobol
    /// sampler's are computed sixteen lanes at a time in vector code; the
    /// other kinds draw theirs one by one.
    pub fn vertex_lanes(samplers: &mut [Sampler], lanes: &[u8], out: &mut [VertexSamples]) {
        for group in lanes.chunks(KERNEL_LANES) {
            // (A render's samplers are all of one kind.)
            if !group.iter().all(|&lane| samplers[lane as usize].kind() == SamplerKind::Sobol) {
                for &lane in group {
                    out[lane as usize] = samplers[lane as usize].vertex();
                }
                continue;
            }
            let mut input = SobolLanes::default();
            for (k, &lane) in group.iter().enumerate().take(KERNEL_LANES) {
                input.set(k, &mut samplers[lane as usize], 5);
            }
            let values = sobol_vertices(&input);
            for (slot, &lane) in group.iter().enumerate() {
                let v = |c: usize| values[c][slot];
                out[lane as usize] = VertexSamples {
                    light: v(0),
                    point: Vec2::new(v(1), v(2)),
                    lobe: v(3),
                    dir: Vec2::new(v(4), v(5)),
                    rr: v(6),
                };
            }
        }
    }

    /// The camera's dimensions of every sampler, each just started on its
    /// pixel sample ([`Sampler::start_pixel_sample`]): `film[i]` the
    /// position in the pixel ([`Sampler::pixel_2d`]), and `lens[i]` the
    /// lens sample ([`Sampler::get_2d`]) if `has_lens`, else zero, its
    /// dimension skipped ([`Sampler::skip_2d`]). The same values as drawn
    /// one by one; the Sobol sampler's are computed sixteen lanes at a
    /// time, as [`Sampler::vertex_lanes`] does.
    ///
    /// # Panics
    /// If `samplers`, `film` and `lens` differ in length.
    pub fn camera_lanes(samplers: &mut [Sampler], has_lens: bool, film: &mut [Vec2], lens: &mut [Vec2]) {
        assert!(
            samplers.len() == film.len() && film.len() == lens.len(),
            "a film position and a lens sample for each sampler"
        );
        for ((samplers, film), lens) in
            samplers.chunks_mut(KERNEL_LANES).zip(film.chunks_mut(KERNEL_LANES)).zip(lens.chunks_mut(KERNEL_LANES))
        {
            if !samplers.iter().all(|s| s.kind() == SamplerKind::Sobol) {
                for ((sampler, film), lens) in samplers.iter_mut().zip(film).zip(lens) {
                    *film = sampler.pixel_2d();
                    *lens = if has_lens {
                        sampler.get_2d()
                    } else {
                        sampler.skip_2d();
                        Vec2::ZERO
                    };
                }
                continue;
            }
            let mut input = SobolLanes::default();
            for (k, sampler) in samplers.iter_mut().enumerate() {
                input.set(k, sampler, 2);
                debug_assert_eq!(input.dimension[k], 0, "the camera's dimensions come first");
                sampler.keep_seeds(2);
            }
            let values = sobol_camera(&input, has_lens);
            for (k, (film, lens)) in film.iter_mut().zip(lens).enumerate() {
                *film = Vec2::new(values[0][k], values[1][k]);
                *lens = Vec2::new(values[2][k], values[3][k]);
            }
        }
    }
}

/// The camera's Sobol values of every lane (film x, y; lens x, y, zero
/// without a lens), in the best build the CPU runs (all give the same
/// bits).
#[inline]
fn sobol_camera(input: &SobolLanes, has_lens: bool) -> CameraValues {
    match isa() {
        // SAFETY: `isa` found the features of `Isa::Avx512`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { sobol_camera_avx512(input, has_lens) },
        // SAFETY: `isa` found the features of `Isa::Avx2`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { sobol_camera_avx2(input, has_lens) },
        _ => sobol_camera_portable(input, has_lens),
    }
}

/// The four camera values of a sample, lane by lane: film x and y, lens x
/// and y.
type CameraValues = [[f32; KERNEL_LANES]; 4];

/// [`sobol_camera_portable`] compiled for AVX2.
///
/// # Safety
/// The CPU must have the features of `Isa::Avx2`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn sobol_camera_avx2(input: &SobolLanes, has_lens: bool) -> CameraValues {
    sobol_camera_portable(input, has_lens)
}

/// [`sobol_camera_portable`] compiled for AVX-512 (see
/// [`sobol_vertices_avx512`]).
///
/// # Safety
/// The CPU must have the features of `Isa::Avx512`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
unsafe fn sobol_camera_avx512(input: &SobolLanes, has_lens: bool) -> CameraValues {
    sobol_camera_portable(input, has_lens)
}

/// The definition: the film position's dimension and, with a lens, the
/// lens sample's, each by [`sobol_dimension`].
#[inline(always)]
fn sobol_camera_portable(input: &SobolLanes, has_lens: bool) -> CameraValues {
    let mut out = [[0.0f32; KERNEL_LANES]; 4];
    let [film_x, film_y, lens_x, lens_y] = &mut out;
    sobol_dimension(input, 0, film_x, Some(film_y));
    if has_lens {
        sobol_dimension(input, 1, lens_x, Some(lens_y));
    }
    out
}

/// The Sobol values of a vertex for every lane, in the best build the CPU
/// runs (all give the same bits).
#[inline]
fn sobol_vertices(input: &SobolLanes) -> VertexValues {
    match isa() {
        // SAFETY: `isa` found the features of `Isa::Avx512`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { sobol_vertices_avx512(input) },
        // SAFETY: `isa` found the features of `Isa::Avx2`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { sobol_vertices_avx2(input) },
        _ => sobol_vertices_portable(input),
    }
}

/// [`sobol_vertices_portable`] compiled for AVX2.
///
/// # Safety
/// The CPU must have the features of `Isa::Avx2`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn sobol_vertices_avx2(input: &SobolLanes) -> VertexValues {
    sobol_vertices_portable(input)
}

/// [`sobol_vertices_portable`] compiled for AVX-512, whose DQ extension
/// multiplies 64-bit lanes in one instruction (`vpmullq`), as the seeds'
/// hash does; AVX2 has no such multiply and builds it from three 32-bit
/// ones.
///
/// # Safety
/// The CPU must have the features of `Isa::Avx512`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
unsafe fn sobol_vertices_avx512(input: &SobolLanes) -> VertexValues {
    sobol_vertices_portable(input)
}

/// The definition: the five dimensions of a vertex, each by
/// [`sobol_dimension`].
#[inline(always)]
fn sobol_vertices_portable(input: &SobolLanes) -> VertexValues {
    let mut out = [[0.0f32; KERNEL_LANES]; 7];
    let [light, point_x, point_y, lobe, dir_x, dir_y, rr] = &mut out;
    // Dimensions 1 (point on the light) and 3 (direction) are 2D.
    sobol_dimension(input, 0, light, None);
    sobol_dimension(input, 1, point_x, Some(point_y));
    sobol_dimension(input, 2, lobe, None);
    sobol_dimension(input, 3, dir_x, Some(dir_y));
    sobol_dimension(input, 4, rr, None);
    out
}

/// Dimension `input.dimension + k` of every lane: its first coordinate
/// into `x`, and for a 2D dimension its second into `y`. Its scramble
/// seeds are hashed from (pixel, dimension) ([`dimension_hash_xy`], and
/// [`dimension_hash_y`] for the second coordinate); then the shuffled
/// index `j = reverse(lk_seeded(index_premixed, h_index))`, the first
/// coordinate `reverse(lk_seeded(lk_premix(j), h_x))` and the second
/// `reverse(lk_seeded(lk_premix(sobol_1_reversed(j)), h_y))` (the steps of
/// [`Sampler::get_1d`] and [`Sampler::get_2d`]), each step a loop over the
/// lanes.
#[inline(always)]
fn sobol_dimension(input: &SobolLanes, k: u32, x: &mut [f32; KERNEL_LANES], y: Option<&mut [f32; KERNEL_LANES]>) {
    // The seeds: index shuffle (low half) and first coordinate (high).
    let mut h = [0u64; KERNEL_LANES];
    for ((h, &ph), &d) in h.iter_mut().zip(&input.pixel_hash).zip(&input.dimension) {
        *h = dimension_hash_xy(ph, d.wrapping_add(k));
    }
    let mut j = [0u32; KERNEL_LANES];
    for ((j, &ip), &h) in j.iter_mut().zip(&input.index_premixed).zip(&h) {
        *j = lk_seeded(ip, h as u32).reverse_bits();
    }
    for ((v, &j), &h) in x.iter_mut().zip(&j).zip(&h) {
        *v = to_unit_float(lk_seeded(lk_premix(j), (h >> 32) as u32).reverse_bits());
    }
    if let Some(y) = y {
        for ((v, &j), &h) in y.iter_mut().zip(&j).zip(&h) {
            let h_y = dimension_hash_y(h);
            *v = to_unit_float(lk_seeded(lk_premix(sobol_1_reversed(j)), h_y).reverse_bits());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samplers of `kind` at many pixels, sample indices and depths.
    fn samplers(kind: SamplerKind, n: usize) -> Vec<Sampler> {
        (0..n)
            .map(|i| {
                let mut s = Sampler::new(kind, 11, 64);
                s.start_pixel_sample(i as u32 % 7, i as u32 / 7, (i as u32).wrapping_mul(2_654_435_761) % 5000);
                s.pixel_2d();
                s.skip_2d();
                // Lanes at different depths.
                for _ in 0..i % 9 {
                    s.vertex();
                }
                s
            })
            .collect()
    }

    #[test]
    fn lanes_equal_one_by_one() {
        for kind in [SamplerKind::Sobol, SamplerKind::Independent, SamplerKind::Stratified] {
            for n in [1, 5, 16, 37] {
                let mut lanes = samplers(kind, n);
                let mut one = samplers(kind, n);
                // Every other lane, in reverse order.
                let list: Vec<u8> = (0..n as u8).rev().step_by(2).collect();
                for _ in 0..3 {
                    let mut out = vec![VertexSamples::default(); n];
                    Sampler::vertex_lanes(&mut lanes, &list, &mut out);
                    for &lane in &list {
                        let i = lane as usize;
                        assert_eq!(out[i], one[i].vertex(), "{kind:?}, lane {i} of {n}");
                    }
                }
                // The samplers stand at the same dimension after: the next
                // values agree too.
                for &lane in &list {
                    let i = lane as usize;
                    assert_eq!(lanes[i].get_2d(), one[i].get_2d());
                }
            }
        }
    }

    /// The camera's dimensions in lanes equal `pixel_2d` then `get_2d` or
    /// `skip_2d`, one by one; the samplers stand at the same dimension
    /// after, with the same seeds kept (so later draws one by one agree).
    #[test]
    fn camera_lanes_equal_one_by_one() {
        for kind in [SamplerKind::Sobol, SamplerKind::Independent, SamplerKind::Stratified] {
            for n in [1, 5, 16, 37, 64] {
                for has_lens in [false, true] {
                    let mut lanes: Vec<Sampler> = (0..n).map(|_| Sampler::new(kind, 23, 16)).collect();
                    let mut one = lanes.clone();
                    // Three sample indices of the same pixels (the seeds
                    // tables filled on the first), then other pixels.
                    for (round, index) in [0u32, 1, 7, 3].into_iter().enumerate() {
                        let pixel = |i: usize| (i as u32 + 40 * (round as u32 / 3), round as u32 / 3);
                        for (i, (a, b)) in lanes.iter_mut().zip(&mut one).enumerate() {
                            let (x, y) = pixel(i);
                            a.start_pixel_sample(x, y, index);
                            b.start_pixel_sample(x, y, index);
                        }
                        let mut film = vec![Vec2::splat(-1.0); n];
                        let mut lens = vec![Vec2::splat(-1.0); n];
                        Sampler::camera_lanes(&mut lanes, has_lens, &mut film, &mut lens);
                        for i in 0..n {
                            let s = &mut one[i];
                            assert_eq!(film[i], s.pixel_2d(), "{kind:?}, lane {i} of {n}");
                            let l = if has_lens {
                                s.get_2d()
                            } else {
                                s.skip_2d();
                                Vec2::ZERO
                            };
                            assert_eq!(lens[i], l, "{kind:?}, lane {i} of {n}, lens {has_lens}");
                        }
                        for (a, b) in lanes.iter_mut().zip(&mut one) {
                            assert_eq!(a.kept_seeds(), b.kept_seeds(), "{kind:?}: the kept seeds");
                            assert_eq!(a.vertex(), b.vertex(), "{kind:?}: the next dimensions");
                        }
                    }
                }
            }
        }
    }

    /// Every build the CPU runs gives the portable build's bits, over many
    /// random inputs.
    #[test]
    fn builds_agree() {
        let mut rng = crate::sampling::Pcg32::new(5, 0);
        for _ in 0..2000 {
            let mut input = SobolLanes::default();
            for l in 0..KERNEL_LANES {
                input.index_premixed[l] = rng.next_u32();
                input.pixel_hash[l] = (rng.next_u32() as u64) << 32 | rng.next_u32() as u64;
                // Dimensions near u32::MAX too, where d + k wraps.
                input.dimension[l] = rng.next_u32();
            }
            let portable = sobol_vertices_portable(&input);
            assert_eq!(sobol_vertices(&input), portable);
            let camera = [false, true].map(|lens| sobol_camera_portable(&input, lens));
            for lens in [false, true] {
                assert_eq!(sobol_camera(&input, lens), camera[lens as usize]);
            }
            #[cfg(target_arch = "x86_64")]
            {
                let best = crate::geometry::simd_detected();
                if best >= Isa::Avx2 {
                    // SAFETY: the CPU has the features of `Isa::Avx2`.
                    assert_eq!(unsafe { sobol_vertices_avx2(&input) }, portable);
                    for lens in [false, true] {
                        // SAFETY: as above.
                        assert_eq!(unsafe { sobol_camera_avx2(&input, lens) }, camera[lens as usize]);
                    }
                }
                if best == Isa::Avx512 {
                    // SAFETY: the CPU has the features of `Isa::Avx512`.
                    assert_eq!(unsafe { sobol_vertices_avx512(&input) }, portable);
                    for lens in [false, true] {
                        // SAFETY: as above.
                        assert_eq!(unsafe { sobol_camera_avx512(&input, lens) }, camera[lens as usize]);
                    }
                }
            }
        }
    }
}
