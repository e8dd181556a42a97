//! A cache prefetch hint, for traversals and look-ups whose next read is known before it is
//! needed (a ray tree's deferred nodes, an escaping ray's environment texels). A utility like
//! [`crate::mix`]: any stage may use it.

/// Asks the processor to bring `value`'s cache line into all cache levels without waiting for
/// it (x86-64 `prefetcht0`; a no-op elsewhere). It changes no result, only when memory is read.
#[inline(always)]
pub fn prefetch_read<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: a prefetch reads nothing and cannot fault; the pointer comes from a reference.
        unsafe { _mm_prefetch::<_MM_HINT_T0>((value as *const T).cast::<i8>()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}
