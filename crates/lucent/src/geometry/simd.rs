//! Which instruction set the vector code runs on, chosen once per process.
//!
//! The library is compiled for the baseline x86-64 (SSE2), so that one
//! binary runs on every x86-64 CPU. An eight-wide node's box test is then
//! two four-lane passes; with AVX it is one eight-lane pass, as in Embree's
//! AVX2 kernels, which Embree also picks at run time. The hot queries (a
//! mesh BVH's closest and any hit, the scene's top level) therefore come in
//! three builds of the same source: one compiled with AVX-512 enabled
//! (through `#[target_feature]`), one with AVX2, each taken when the CPU has
//! it, and the portable one. All three do the same IEEE arithmetic in the
//! same order, so they give bit-identical answers and images; tests compare
//! them ray for ray. The path integrator's lane kernels (the Sobol
//! sampler's, the light and scatter stages', the film's) choose their
//! builds here too. This lives in the bottom layer so that every layer can
//! ask.
//!
//! The AVX-512 build of the traversal runs the same 256-bit and 128-bit
//! vector code as the AVX2 one. What it gains is the compiler's: EVEX
//! encodings with 32 vector registers instead of 16 (the traversal loop
//! keeps the ray's slab offsets, the node and the stack in registers
//! instead of spilling them) and comparisons into mask registers (measured
//! in `docs/performance.md`).
//!
//! Setting the environment variable `LUCENT_SIMD` to `portable` or `avx2`
//! before the first query caps the choice at that build (for measuring one
//! against another in one binary).

use std::sync::atomic::{AtomicU8, Ordering};

/// The builds of the hot queries, from the most portable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Isa {
    /// Baseline x86-64 (SSE2), or any other architecture.
    Portable = 1,
    /// AVX2 with FMA, BMI1/2, LZCNT and POPCNT (x86-64-v3).
    Avx2 = 2,
    /// The AVX2 set plus AVX-512 F, VL, BW and DQ (x86-64-v4).
    Avx512 = 3,
}

/// 0: not decided yet; else an [`Isa`] as its number.
static CHOICE: AtomicU8 = AtomicU8::new(0);

/// The build the queries run: the best the CPU has, capped by
/// `LUCENT_SIMD`. Decided on the first call.
#[inline(always)]
pub(crate) fn isa() -> Isa {
    match CHOICE.load(Ordering::Relaxed) {
        1 => Isa::Portable,
        2 => Isa::Avx2,
        3 => Isa::Avx512,
        _ => decide(),
    }
}

#[cold]
fn decide() -> Isa {
    let cap = match std::env::var("LUCENT_SIMD").as_deref() {
        Ok("portable") => Isa::Portable,
        Ok("avx2") => Isa::Avx2,
        _ => Isa::Avx512,
    };
    let isa = detect().min(cap);
    CHOICE.store(isa as u8, Ordering::Relaxed);
    isa
}

/// The best build this CPU can run, whatever `LUCENT_SIMD` says (for
/// tests that compare every build the CPU has).
pub(crate) fn detect() -> Isa {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::is_x86_feature_detected as has;
        let v3 = has!("avx2") && has!("fma") && has!("bmi1") && has!("bmi2") && has!("lzcnt") && has!("popcnt");
        let v4 = v3 && has!("avx512f") && has!("avx512vl") && has!("avx512bw") && has!("avx512dq");
        if v4 {
            return Isa::Avx512;
        }
        if v3 {
            return Isa::Avx2;
        }
    }
    Isa::Portable
}

/// The name of the build the queries run: `"avx512"`, `"avx2"` or
/// `"portable"`.
pub fn traversal_isa() -> &'static str {
    match isa() {
        Isa::Avx512 => "avx512",
        Isa::Avx2 => "avx2",
        Isa::Portable => "portable",
    }
}
