//! Hints to the memory system.
//!
//! A renderer reads large tables at random (a BVH's nodes, an environment
//! map's sampling tables and pixels): each read is likely a cache miss of
//! tens to hundreds of cycles. Where the address of a later read is known
//! early, [`prefetch`] asks for it without waiting, so that the miss
//! overlaps other work, or other misses, instead of stalling on its own.

/// Ask the memory system for the `lines` cache lines (64 bytes each) from
/// `p` into the first-level cache, without waiting for them. A hint only:
/// it never faults, whatever the address (dangling, null, past the end),
/// and does nothing on CPUs other than x86-64.
///
/// ```
/// let table = vec![0.0f32; 1 << 20];
/// lucent::memory::prefetch(table.as_ptr().wrapping_add(12_345), 1);
/// ```
#[inline(always)]
pub fn prefetch<T>(p: *const T, lines: usize) {
    #[cfg(target_arch = "x86_64")]
    for line in 0..lines {
        // SAFETY: a prefetch is a hint; it never faults, whatever address.
        #[allow(unused_unsafe)]
        unsafe {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>().wrapping_add(64 * line));
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (p, lines);
}
