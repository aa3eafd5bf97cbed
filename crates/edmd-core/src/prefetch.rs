//! A software prefetch hint: the event loop knows which particle comes next long before it reads it.

/// Asks the CPU to start loading the cache line holding `r`.
#[inline(always)]
#[allow(unsafe_code)]
pub(crate) fn prefetch<T>(r: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: `_mm_prefetch` is only a hint: it never faults, writes nothing and its address comes
    // from a valid reference. SSE is part of the x86_64 baseline.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            (r as *const T).cast::<i8>(),
        )
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = r;
}

/// Asks for the line of `items[idx]` without a bounds check: the address comes from wrapping
/// arithmetic and a prefetch never faults, so an index past the end would only waste the hint. For
/// the look-ahead, whose indices are valid but whose checks cost more instructions than its hints.
#[inline(always)]
pub(crate) fn prefetch_at<T>(items: &[T], idx: usize) {
    prefetch_ptr(items.as_ptr().wrapping_add(idx).cast::<u8>());
}

/// Asks for every cache line `items[idx]` spans (a record that is not line-aligned may straddle
/// two), without a bounds check (as [`prefetch_at`]).
#[inline(always)]
pub(crate) fn prefetch_record_at<T>(items: &[T], idx: usize) {
    let first = items.as_ptr().wrapping_add(idx).cast::<u8>();
    prefetch_ptr(first);
    let size = std::mem::size_of::<T>();
    if size > 1 {
        prefetch_ptr(first.wrapping_add(size - 1));
    }
}

#[inline(always)]
#[allow(unsafe_code)]
fn prefetch_ptr(p: *const u8) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is only a hint: it never faults and writes nothing, whatever the address
    // (the callers' addresses are in bounds or wrapping arithmetic past a slice).
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(p.cast::<i8>())
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}
