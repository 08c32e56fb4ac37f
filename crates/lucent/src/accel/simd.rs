//! Which instruction set the traversal runs on, chosen once per process.
//!
//! The library is compiled for the baseline x86-64 (SSE2), so that one
//! binary runs on every x86-64 CPU. An eight-wide node's box test is then
//! two four-lane passes; with AVX it is one eight-lane pass, as in Embree's
//! AVX2 kernels, which Embree also picks at run time. The hot queries (a
//! mesh BVH's closest and any hit, the scene's top level) therefore come in
//! two builds of the same source: one compiled with AVX2 enabled (through
//! `#[target_feature]`), taken when the CPU has it, and the portable one.
//! Both do the same IEEE arithmetic in the same order, so they give
//! bit-identical answers and images; tests compare them ray for ray.
//!
//! Setting the environment variable `LUCENT_SIMD=portable` before the first
//! query forces the portable build (for measuring one against the other in
//! one binary).

use std::sync::atomic::{AtomicU8, Ordering};

/// 0: not decided yet; 1: portable; 2: AVX2.
static CHOICE: AtomicU8 = AtomicU8::new(0);

/// Whether the queries run their AVX2 build: the CPU has AVX2 and
/// `LUCENT_SIMD` does not say `portable`. Decided on the first call.
#[inline(always)]
pub(crate) fn use_avx2() -> bool {
    match CHOICE.load(Ordering::Relaxed) {
        0 => decide(),
        c => c == 2,
    }
}

#[cold]
fn decide() -> bool {
    let forced_portable = std::env::var_os("LUCENT_SIMD").is_some_and(|v| v == "portable");
    #[cfg(target_arch = "x86_64")]
    let avx2 = !forced_portable && std::arch::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    let avx2 = {
        let _ = forced_portable;
        false
    };
    CHOICE.store(if avx2 { 2 } else { 1 }, Ordering::Relaxed);
    avx2
}

/// The name of the build the queries run: `"avx2"` or `"portable"`.
pub fn traversal_isa() -> &'static str {
    if use_avx2() {
        "avx2"
    } else {
        "portable"
    }
}
