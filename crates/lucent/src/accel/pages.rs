//! Arrays for the acceleration structures, backed by 2 MiB pages when they
//! are large and the system allows it.
//!
//! Incoherent rays visit nodes and triangle blocks scattered over tens of
//! megabytes; with 4 KiB pages most of those visits also miss the TLB and
//! pay for a page walk. On Linux, memory that is marked
//! `madvise(MADV_HUGEPAGE)` before it is first touched is backed by
//! transparent huge pages when the system's policy is `madvise` or
//! `always` (the usual default is `madvise`), which removes most of those
//! misses. Embree's allocator does the same. Anywhere else, or when the
//! mapping fails, the array is an ordinary heap allocation.

use std::ops::{Deref, DerefMut};

/// Types for which memory of all zero bytes is a valid value.
///
/// # Safety
/// Implement only for types made of integers and floats (no references,
/// no enums, no `NonZero`), for which zeroed memory is a valid value.
pub(crate) unsafe trait ZeroIsValid: Copy {}

/// Arrays at least this large are mapped for huge pages. (Under Miri, which
/// checks the mapping code, 16 KiB: Miri runs a test's loops over millions
/// of elements for hours.)
const MIN_MAPPED_BYTES: usize = if cfg!(miri) { 16 << 10 } else { 4 << 20 };
/// The huge page size the mapping is aligned to.
const HUGE_PAGE: usize = 2 << 20;

/// A fixed-length array of `T`, on huge pages where possible.
pub(crate) struct PageArray<T: ZeroIsValid> {
    storage: Storage<T>,
}

enum Storage<T> {
    Heap(Vec<T>),
    #[cfg(target_os = "linux")]
    Mapped(linux::Mapping<T>),
}

impl<T: ZeroIsValid> PageArray<T> {
    /// `len` zeroed elements.
    pub(crate) fn zeroed(len: usize) -> Self {
        #[cfg(target_os = "linux")]
        if let Some(m) = linux::Mapping::new(len) {
            return Self { storage: Storage::Mapped(m) };
        }
        // SAFETY: zeroed memory is a valid `T` (`ZeroIsValid`).
        let zero: T = unsafe { std::mem::zeroed() };
        Self { storage: Storage::Heap(vec![zero; len]) }
    }

    /// A copy of `items`.
    pub(crate) fn from_slice(items: &[T]) -> Self {
        let mut array = Self::zeroed(items.len());
        array.copy_from_slice(items);
        array
    }

    /// Keep the first `len` elements. A mapped array keeps its mapping:
    /// the pages past the new end that were never written were never
    /// backed by memory, so an array can be made as large as a bound on
    /// its size, filled from the start, and cut to what was filled,
    /// without a copy.
    pub(crate) fn truncate(&mut self, len: usize) {
        match &mut self.storage {
            Storage::Heap(v) => {
                v.truncate(len);
                v.shrink_to_fit();
            }
            #[cfg(target_os = "linux")]
            Storage::Mapped(m) => m.truncate(len),
        }
    }

    /// Whether the array lives on memory mapped and advised for huge pages
    /// (the kernel decides whether it gets them).
    pub(crate) fn is_mapped(&self) -> bool {
        !matches!(self.storage, Storage::Heap(_))
    }
}

impl<T: ZeroIsValid> Deref for PageArray<T> {
    type Target = [T];
    #[inline(always)]
    fn deref(&self) -> &[T] {
        match &self.storage {
            Storage::Heap(v) => v,
            #[cfg(target_os = "linux")]
            Storage::Mapped(m) => m.as_slice(),
        }
    }
}

impl<T: ZeroIsValid> DerefMut for PageArray<T> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [T] {
        match &mut self.storage {
            Storage::Heap(v) => v,
            #[cfg(target_os = "linux")]
            Storage::Mapped(m) => m.as_mut_slice(),
        }
    }
}

impl<T: ZeroIsValid> Default for PageArray<T> {
    fn default() -> Self {
        Self { storage: Storage::Heap(Vec::new()) }
    }
}

impl<T: ZeroIsValid> Clone for PageArray<T> {
    fn clone(&self) -> Self {
        Self::from_slice(self)
    }
}

impl<T: ZeroIsValid + std::fmt::Debug> std::fmt::Debug for PageArray<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

#[cfg(target_os = "linux")]
mod linux {
    use super::{ZeroIsValid, HUGE_PAGE, MIN_MAPPED_BYTES};
    use std::ptr::NonNull;

    /// An anonymous private mapping holding `len` values of `T` from a
    /// 2 MiB-aligned address, advised for huge pages.
    pub(super) struct Mapping<T> {
        /// Start of the whole mapping (for `munmap`).
        base: NonNull<libc::c_void>,
        /// Bytes mapped.
        mapped: usize,
        /// The first element: `base` rounded up to a huge page.
        data: NonNull<T>,
        len: usize,
    }

    // SAFETY: the mapping is owned exclusively, like a `Vec<T>`'s buffer.
    unsafe impl<T: Send> Send for Mapping<T> {}
    // SAFETY: shared access only reads, like `&[T]`.
    unsafe impl<T: Sync> Sync for Mapping<T> {}

    impl<T: ZeroIsValid> Mapping<T> {
        /// Map room for `len` values, or `None` when the array is small,
        /// too large to describe, or the system refuses.
        pub(super) fn new(len: usize) -> Option<Self> {
            let bytes = len.checked_mul(std::mem::size_of::<T>())?;
            if bytes < MIN_MAPPED_BYTES || std::mem::align_of::<T>() > HUGE_PAGE {
                return None;
            }
            // One extra huge page, so a 2 MiB-aligned start fits inside.
            let mapped = bytes.checked_add(2 * HUGE_PAGE)? & !(HUGE_PAGE - 1);
            // SAFETY: a fresh anonymous mapping, no address hint; the
            // result is checked against MAP_FAILED.
            let base = unsafe {
                libc::mmap(
                    std::ptr::null_mut(),
                    mapped,
                    libc::PROT_READ | libc::PROT_WRITE,
                    libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
                    -1,
                    0,
                )
            };
            if base == libc::MAP_FAILED {
                return None;
            }
            let base = NonNull::new(base)?;
            let offset = (HUGE_PAGE - base.as_ptr() as usize % HUGE_PAGE) % HUGE_PAGE;
            // SAFETY: `offset < HUGE_PAGE` and `offset + bytes ≤ mapped`.
            let data = unsafe { base.as_ptr().cast::<u8>().add(offset) };
            // A hint: if it is refused the pages are ordinary ones. It
            // must come before the first touch for the page faults to
            // allocate huge pages directly. (Miri, which checks the
            // unsafe code here, has no `madvise`; without the hint the
            // mapping is the same.)
            // SAFETY: the range lies inside the mapping just made.
            #[cfg(not(miri))]
            unsafe {
                libc::madvise(data.cast(), bytes, libc::MADV_HUGEPAGE)
            };
            let data = NonNull::new(data.cast::<T>())?;
            Some(Self { base, mapped, data, len })
        }

        /// Keep the first `len` values (the mapping stays as it is).
        pub(super) fn truncate(&mut self, len: usize) {
            self.len = self.len.min(len);
        }

        #[inline(always)]
        pub(super) fn as_slice(&self) -> &[T] {
            // SAFETY: `data` is aligned (a multiple of 2 MiB, at least the
            // alignment of `T`), holds `len` values (zeroed memory is a
            // valid `T`), and lives as long as `self`.
            unsafe { std::slice::from_raw_parts(self.data.as_ptr(), self.len) }
        }

        #[inline(always)]
        pub(super) fn as_mut_slice(&mut self) -> &mut [T] {
            // SAFETY: as in `as_slice`, and `&mut self` is exclusive.
            unsafe { std::slice::from_raw_parts_mut(self.data.as_ptr(), self.len) }
        }
    }

    impl<T> Drop for Mapping<T> {
        fn drop(&mut self) {
            // SAFETY: unmaps exactly the mapping made in `new`; `T` is
            // `Copy` (`ZeroIsValid`), so nothing needs dropping first.
            unsafe { libc::munmap(self.base.as_ptr(), self.mapped) };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Copy, Debug, PartialEq)]
    #[repr(C, align(64))]
    struct Wide([f32; 16], [u32; 16]);
    // SAFETY: floats and integers only.
    unsafe impl ZeroIsValid for Wide {}

    #[test]
    fn small_arrays_stay_on_the_heap_and_large_ones_are_aligned() {
        let small = PageArray::<Wide>::zeroed(10);
        assert!(!small.is_mapped());
        assert!(small.iter().all(|w| *w == Wide([0.0; 16], [0; 16])));

        let n = (MIN_MAPPED_BYTES / std::mem::size_of::<Wide>()) * 3 + 7;
        let mut large = PageArray::<Wide>::zeroed(n);
        assert_eq!(large.len(), n);
        if cfg!(target_os = "linux") {
            assert!(large.is_mapped());
            assert_eq!(large.as_ptr() as usize % HUGE_PAGE, 0);
        }
        assert!(large.iter().all(|w| *w == Wide([0.0; 16], [0; 16])));
        for (i, w) in large.iter_mut().enumerate() {
            w.1[0] = i as u32;
        }
        let copy = large.clone();
        assert_eq!(&copy[..], &large[..]);
        assert!(copy.is_mapped() == large.is_mapped());
        assert_eq!(&PageArray::from_slice(&[Wide([1.0; 16], [2; 16])])[..], &[Wide([1.0; 16], [2; 16])]);
        assert_eq!(copy[n - 1].1[0], (n - 1) as u32);
        assert!(PageArray::<Wide>::default().is_empty());
        for mut array in [large, PageArray::<Wide>::zeroed(10)] {
            let was_mapped = array.is_mapped();
            array.truncate(array.len() + 1);
            array.truncate(3);
            assert_eq!(array.len(), 3);
            assert_eq!(array.is_mapped(), was_mapped);
            array.truncate(0);
            assert!(array.is_empty());
        }
    }
}
