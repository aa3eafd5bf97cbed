//! A global-allocator wrapper that starts every large allocation on a cache-line boundary, and
//! offers the very large ones to the kernel for transparent huge pages.
//!
//! The engine's per-particle arrays are large allocations, which the C library hands out 16 bytes
//! past a page boundary: with that offset a 64-byte sphere record (`Particle<3>`) and the start of
//! every neighbour list (a stride of 64-byte multiples) straddle two cache lines, and an event
//! that needs one line of each waits for two. [`LineAligned`] raises the alignment of every
//! allocation of [`LARGE`] bytes or more to [`LINE`], so that such records each lie in one line
//! (what it gains by size: docs/benchmarks.md). The binaries of this project install it:
//!
//! ```ignore
//! #[global_allocator]
//! static ALLOC: edmd_core::LineAligned = edmd_core::LineAligned(std::alloc::System);
//! ```
//!
//! Blocks of [`HUGE`] bytes or more (the per-particle arrays from N ≈ 10⁵ on) start on a 2 MiB
//! boundary and are advised `MADV_HUGEPAGE` before their pages are touched, so that a kernel with
//! transparent huge pages in `madvise` mode (the default of many distributions) backs them with
//! 2 MiB pages: an event's random lines then rarely miss the TLB (docs/benchmarks.md).
//!
//! Without it the engine computes the same results, only slower for large systems.

use std::alloc::{GlobalAlloc, Layout, System};

/// Size of a cache line, the alignment [`LineAligned`] gives large allocations.
pub const LINE: usize = 64;
/// Allocations of at least this many bytes are aligned to [`LINE`]; smaller ones are left alone
/// (the many small vectors would only waste their padding).
pub const LARGE: usize = 4096;

/// Forwards to the allocator `A`, asking it for [`LINE`]-aligned blocks of [`LARGE`] bytes or more.
#[derive(Debug, Default, Clone, Copy)]
pub struct LineAligned<A = System>(pub A);

/// Allocations of at least this many bytes also start on a [`HUGE_PAGE`] boundary and are offered
/// to the kernel for transparent huge pages (Linux `madvise(MADV_HUGEPAGE)`): an event at N = 10⁶
/// reads ~20 lines at random over ~190 MB, and with 4 KiB pages nearly each of them also misses the
/// TLB and walks the page table.
pub const HUGE: usize = 4 << 20;
/// The size of a transparent huge page on x86-64 and most arm64 kernels.
pub const HUGE_PAGE: usize = 2 << 20;

/// The layout actually requested from the inner allocator for `layout`: a pure function of it, so
/// that `dealloc` and `realloc` present the inner allocator with the layout it allocated.
#[inline]
fn widened(layout: Layout) -> Layout {
    let align = if layout.size() >= HUGE {
        HUGE_PAGE
    } else if layout.size() >= LARGE {
        LINE
    } else {
        return layout;
    };
    if layout.align() < align {
        // A size that fits `layout` also fits the larger power-of-two alignment (sizes are not
        // rounded by `Layout`, and `HUGE_PAGE` is far below `isize::MAX - size`).
        Layout::from_size_align(layout.size(), align).unwrap_or(layout)
    } else {
        layout
    }
}

/// Asks the kernel to back the block `[ptr, ptr + size)` with huge pages, if it is [`HUGE`] or
/// larger. A hint: where the kernel has transparent huge pages off, or lacks them, nothing changes.
#[inline]
fn advise(ptr: *mut u8, size: usize) {
    #[cfg(target_os = "linux")]
    if size >= HUGE && !ptr.is_null() {
        // SAFETY: `ptr` starts a block of `size` bytes that this allocator owns; madvise with
        // MADV_HUGEPAGE changes only how the kernel backs those pages, never their contents, and an
        // error (e.g. a kernel without THP) is harmless and ignored. `ptr` is page aligned: blocks
        // of `HUGE` bytes or more are `HUGE_PAGE` aligned (`widened`).
        #[allow(unsafe_code)]
        unsafe {
            libc::madvise(ptr.cast(), size, libc::MADV_HUGEPAGE);
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (ptr, size);
}

// SAFETY: every method forwards to the inner allocator with `widened(layout)`, a valid layout of
// the same size and an alignment at least the requested one, so each block it returns satisfies
// `layout`; a block is always freed or resized with the widened form of the layout it was
// allocated with, which is what the inner allocator's contract requires, because `widened` depends
// on the layout alone.
#[allow(unsafe_code)]
unsafe impl<A: GlobalAlloc> GlobalAlloc for LineAligned<A> {
    #[inline]
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: `widened(layout)` has the non-zero size of `layout` (the caller's guarantee).
        let p = unsafe { self.0.alloc(widened(layout)) };
        advise(p, layout.size());
        p
    }

    #[inline]
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if layout.size() < HUGE {
            // SAFETY: as for `alloc`.
            return unsafe { self.0.alloc_zeroed(widened(layout)) };
        }
        // Advised before the zeroing touches the pages, so that they are faulted in huge.
        // SAFETY: as for `alloc`; the zeroing stays within the block just allocated.
        unsafe {
            let p = self.alloc(layout);
            if !p.is_null() {
                p.write_bytes(0, layout.size());
            }
            p
        }
    }

    #[inline]
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was allocated by this allocator with `layout`, i.e. by the inner one with
        // `widened(layout)`.
        unsafe { self.0.dealloc(ptr, widened(layout)) }
    }

    #[inline]
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = widened(layout);
        // SAFETY (of the unchecked layout): the caller guarantees that `new_size`, rounded up to
        // `layout.align()`, does not overflow `isize`, and the alignment is `layout`'s.
        let new = widened(unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) });
        if new.align() == old.align() && new_size < HUGE {
            // SAFETY: `ptr` was allocated by the inner allocator with `old`; `new_size` is
            // non-zero and valid for `old.align()` (the same alignment as `new`).
            return unsafe { self.0.realloc(ptr, old, new_size) };
        }
        // The block crosses `LARGE`, or is huge (advised before the copy touches its pages): move
        // it to a block of the new alignment.
        // SAFETY: `new` is a valid layout of non-zero size; the copy stays within both blocks
        // (the smaller of the two sizes), which do not overlap, and `ptr` is freed with the layout
        // it was allocated with.
        unsafe {
            let moved = self.0.alloc(new);
            advise(moved, new_size);
            if !moved.is_null() {
                std::ptr::copy_nonoverlapping(ptr, moved, layout.size().min(new_size));
                self.0.dealloc(ptr, old);
            }
            moved
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_blocks_start_on_a_line_and_small_ones_keep_their_layout() {
        let a = LineAligned(System);
        for size in [8, 100, LARGE - 1, LARGE, 1 << 20, 3 << 20, HUGE, HUGE + 100] {
            let layout = Layout::from_size_align(size, 8).unwrap();
            let w = widened(layout);
            assert_eq!(w.size(), size);
            let align = match size {
                s if s >= HUGE => HUGE_PAGE,
                s if s >= LARGE => LINE,
                _ => 8,
            };
            assert_eq!(w.align(), align);
            #[allow(unsafe_code)]
            // SAFETY: non-zero sizes; each block is written within its size, then freed with the
            // layout it was allocated with (after the reallocations, the latest one).
            unsafe {
                let p = a.alloc(layout);
                assert!(!p.is_null());
                assert_eq!(p as usize % align, 0, "{size} bytes");
                p.write_bytes(0xab, size);
                // Grow across LARGE and far beyond, then shrink below it: contents survive.
                let mut q = p;
                let mut cur = layout;
                let mut valid = size;
                for new_size in [LARGE + 8, 2 << 20, HUGE + 8, 2 * HUGE, 16] {
                    q = a.realloc(q, cur, new_size);
                    assert!(!q.is_null());
                    // The bytes written at first that every block so far has held.
                    valid = valid.min(new_size);
                    assert!(
                        (0..valid).all(|k| *q.add(k) == 0xab),
                        "{size} -> {new_size}"
                    );
                    let want = widened(Layout::from_size_align(new_size, 8).unwrap()).align();
                    assert_eq!(q as usize % want, 0, "{size} -> {new_size}");
                    cur = Layout::from_size_align(new_size, 8).unwrap();
                }
                a.dealloc(q, cur);
                let z = a.alloc_zeroed(layout);
                assert!((0..size).all(|k| *z.add(k) == 0));
                a.dealloc(z, layout);
            }
        }
    }
}
