//! A global-allocator wrapper that starts every large allocation on a cache-line boundary.
//!
//! The engine's per-particle arrays are large allocations, which the C library hands out 16 bytes
//! past a page boundary: with that offset a 64-byte sphere record (`Particle<3>`) and the start of
//! every neighbour list (a stride of 64-byte multiples) straddle two cache lines, and an event
//! that needs one line of each waits for two. [`LineAligned`] raises the alignment of every
//! allocation of [`LARGE`] bytes or more to [`LINE`], so that such records each lie in one line
//! (3D φ 0.45, alternating `edmd-bench` builds: N 1 000 188 1.14×, N 97 556 1.13×, N 10 976 1.03×;
//! 2D N 10⁶, whose 48-byte records gain nothing from it, 0.98×: docs/benchmarks.md). The binaries
//! of this project install it:
//!
//! ```ignore
//! #[global_allocator]
//! static ALLOC: edmd_core::LineAligned = edmd_core::LineAligned(std::alloc::System);
//! ```
//!
//! Without it the engine computes the same results, only slower for large 3D systems.

use std::alloc::{GlobalAlloc, Layout, System};

/// Size of a cache line, the alignment [`LineAligned`] gives large allocations.
pub const LINE: usize = 64;
/// Allocations of at least this many bytes are aligned to [`LINE`]; smaller ones are left alone
/// (the many small vectors would only waste their padding).
pub const LARGE: usize = 4096;

/// Forwards to the allocator `A`, asking it for [`LINE`]-aligned blocks of [`LARGE`] bytes or more.
#[derive(Debug, Default, Clone, Copy)]
pub struct LineAligned<A = System>(pub A);

/// The layout actually requested from the inner allocator for `layout`: a pure function of it, so
/// that `dealloc` and `realloc` present the inner allocator with the layout it allocated.
#[inline]
fn widened(layout: Layout) -> Layout {
    if layout.size() >= LARGE && layout.align() < LINE {
        // A size that fits `layout` also fits the larger power-of-two alignment (sizes are not
        // rounded by `Layout`, and `LARGE` is far below `isize::MAX - LINE`).
        Layout::from_size_align(layout.size(), LINE).unwrap_or(layout)
    } else {
        layout
    }
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
        unsafe { self.0.alloc(widened(layout)) }
    }

    #[inline]
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as for `alloc`.
        unsafe { self.0.alloc_zeroed(widened(layout)) }
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
        if new.align() == old.align() {
            // SAFETY: `ptr` was allocated by the inner allocator with `old`; `new_size` is
            // non-zero and valid for `old.align()` (the same alignment as `new`).
            return unsafe { self.0.realloc(ptr, old, new_size) };
        }
        // The block crosses `LARGE`: move it to a block of the new alignment.
        // SAFETY: `new` is a valid layout of non-zero size; the copy stays within both blocks
        // (the smaller of the two sizes), which do not overlap, and `ptr` is freed with the layout
        // it was allocated with.
        unsafe {
            let moved = self.0.alloc(new);
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
        for size in [8, 100, LARGE - 1, LARGE, 1 << 20, 3 << 20] {
            let layout = Layout::from_size_align(size, 8).unwrap();
            let w = widened(layout);
            assert_eq!(w.size(), size);
            assert_eq!(w.align(), if size >= LARGE { LINE } else { 8 });
            #[allow(unsafe_code)]
            // SAFETY: non-zero sizes; each block is written within its size, then freed with the
            // layout it was allocated with (after the reallocations, the latest one).
            unsafe {
                let p = a.alloc(layout);
                assert!(!p.is_null());
                if size >= LARGE {
                    assert_eq!(p as usize % LINE, 0, "{size} bytes");
                }
                p.write_bytes(0xab, size);
                // Grow across LARGE and far beyond, then shrink below it: contents survive.
                let mut q = p;
                let mut cur = layout;
                for new_size in [LARGE + 8, 2 << 20, 16] {
                    q = a.realloc(q, cur, new_size);
                    assert!(!q.is_null());
                    let keep = cur.size().min(new_size).min(size);
                    assert!((0..keep).all(|k| *q.add(k) == 0xab), "{size} -> {new_size}");
                    if new_size >= LARGE {
                        assert_eq!(q as usize % LINE, 0, "{size} -> {new_size}");
                    }
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
