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

/// Asks for every cache line `r` spans (a record that is not line-aligned may straddle two).
#[inline(always)]
pub(crate) fn prefetch_record<T>(r: &T) {
    prefetch(r);
    let size = std::mem::size_of::<T>();
    if size > 1 {
        let last = (r as *const T).cast::<u8>().wrapping_add(size - 1);
        prefetch_ptr(last);
    }
}

#[inline(always)]
#[allow(unsafe_code)]
fn prefetch_ptr(p: *const u8) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: as in `prefetch`: a hint that never faults, to the last byte of a valid reference.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(p.cast::<i8>())
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}
