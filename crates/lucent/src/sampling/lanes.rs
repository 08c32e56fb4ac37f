//! Sample values for many paths at once: the path integrator draws the five
//! dimensions of a vertex ([`VertexSamples`]) for all the paths of a batch
//! together ([`Sampler::vertex_lanes`]).
//!
//! The Sobol sampler's values are pure integer arithmetic on (index, seed)
//! pairs: the same multiplications, additions, XORs and bit reversals for
//! every path. Sixteen paths' values are therefore computed as sixteen
//! lanes of vector code ([`sobol_vertices`]), with the lanes laid out
//! structure-of-arrays so that the compiler turns each step into one
//! instruction over all lanes (`vpmulld`, `vpaddd`, `vpxor` in the AVX2
//! build). The values are those of [`Sampler::vertex`] bit for bit: the
//! arithmetic is integer, and the same.
//!
//! There is no AVX-512 build: one (with GFNI's `vgf2p8affineqb` for the bit
//! reversals) ran the Cornell box 5% slower than the AVX2 build on a Zen 4
//! (issue 32's audit of the `unsafe` code, `docs/reliability.md`).

use super::sampler::{lk_premix, lk_seeded, sobol_1_reversed, to_unit_float, Sampler, SamplerKind, VertexSamples};
use glam::Vec2;

/// Paths whose Sobol values one kernel call computes.
const KERNEL_LANES: usize = 16;

/// The inputs of [`sobol_vertices`], lane by lane: each path's premixed
/// sample index, and for each of the vertex's five dimensions its three
/// scramble seeds (index shuffle, first and second coordinate).
#[derive(Clone, Copy, Default)]
struct SobolLanes {
    index_premixed: [u32; KERNEL_LANES],
    seeds: [[[u32; KERNEL_LANES]; 3]; 5],
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
                let (index_premixed, seeds) = samplers[lane as usize].sobol_vertex_state();
                input.index_premixed[k] = index_premixed;
                for (d, seeds) in seeds.iter().enumerate() {
                    for (c, &seed) in seeds.iter().enumerate() {
                        input.seeds[d][c][k] = seed;
                    }
                }
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
}

/// The Sobol values of a vertex for every lane, in the best build the CPU
/// runs (all give the same bits).
#[inline]
fn sobol_vertices(input: &SobolLanes) -> VertexValues {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has the features the build is compiled for.
            return unsafe { sobol_vertices_avx2(input) };
        }
    }
    sobol_vertices_portable(input)
}

/// [`sobol_vertices_portable`] compiled for AVX2.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn sobol_vertices_avx2(input: &SobolLanes) -> VertexValues {
    sobol_vertices_portable(input)
}

/// The definition: for each dimension, the shuffled index
/// `j = reverse(lk_seeded(index_premixed, h_index))`, its first coordinate
/// `reverse(lk_seeded(lk_premix(j), h_x))`, and for the two 2D dimensions
/// its second, `reverse(lk_seeded(lk_premix(sobol_1_reversed(j)), h_y))`
/// (the steps of [`Sampler::get_1d`] and [`Sampler::get_2d`]), each step a
/// loop over the lanes.
#[inline(always)]
fn sobol_vertices_portable(input: &SobolLanes) -> VertexValues {
    let mut out = [[0.0f32; KERNEL_LANES]; 7];
    let mut o = 0;
    for (d, [h_index, h_x, h_y]) in input.seeds.iter().enumerate() {
        let mut j = [0u32; KERNEL_LANES];
        for ((j, &ip), &h) in j.iter_mut().zip(&input.index_premixed).zip(h_index) {
            *j = lk_seeded(ip, h).reverse_bits();
        }
        for ((v, &j), &h) in out[o].iter_mut().zip(&j).zip(h_x) {
            *v = to_unit_float(lk_seeded(lk_premix(j), h).reverse_bits());
        }
        o += 1;
        // Dimensions 1 (point on the light) and 3 (direction) are 2D.
        if d == 1 || d == 3 {
            for ((v, &j), &h) in out[o].iter_mut().zip(&j).zip(h_y) {
                *v = to_unit_float(lk_seeded(lk_premix(sobol_1_reversed(j)), h).reverse_bits());
            }
            o += 1;
        }
    }
    out
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

    /// Every build the CPU runs gives the portable build's bits, over many
    /// random inputs.
    #[test]
    fn builds_agree() {
        let mut rng = crate::sampling::Pcg32::new(5, 0);
        for _ in 0..2000 {
            let mut input = SobolLanes::default();
            for l in 0..KERNEL_LANES {
                input.index_premixed[l] = rng.next_u32();
                for d in 0..5 {
                    for c in 0..3 {
                        input.seeds[d][c][l] = rng.next_u32();
                    }
                }
            }
            let portable = sobol_vertices_portable(&input);
            assert_eq!(sobol_vertices(&input), portable);
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has AVX2.
                assert_eq!(unsafe { sobol_vertices_avx2(&input) }, portable);
            }
        }
    }
}
