//! SSE2 in the shape of the AVX intrinsics the vector macros of the `x86` module take.

#![allow(unsafe_code)]

use core::arch::x86_64::*;

/// SSE2 in the shape of the AVX intrinsics the vector macros take: x86-64's baseline (every
/// x86-64 processor has SSE2; its vectors hold an `Sse2` token all the same); no fused
/// multiply-add (a multiply, then an add).
macro_rules! sse2_shims {
    ($raw:ty, $cmp:ident, $blend:ident, $fma:ident, $lt:ident, $le:ident, $eq:ident,
     $and:ident, $or:ident, $andnot:ident, $add:ident, $mul:ident) => {
        /// # Safety
        /// The processor has SSE2 (every x86-64 processor has).
        #[inline(always)]
        pub(super) unsafe fn $cmp<const P: i32>(a: $raw, b: $raw) -> $raw {
            match P {
                _CMP_LT_OQ => arch!($lt(a, b)),
                _CMP_LE_OQ => arch!($le(a, b)),
                _ => arch!($eq(a, b)),
            }
        }
        /// # Safety
        /// As the comparison.
        #[inline(always)]
        pub(super) unsafe fn $blend(b: $raw, a: $raw, m: $raw) -> $raw {
            arch!($or($and(m, a), $andnot(m, b)))
        }
        /// # Safety
        /// As the comparison.
        #[inline(always)]
        pub(super) unsafe fn $fma(a: $raw, b: $raw, c: $raw) -> $raw {
            arch!($add($mul(a, b), c))
        }
    };
}

sse2_shims!(
    __m128d,
    sse2_cmp_pd,
    sse2_blend_pd,
    sse2_mul_add_pd,
    _mm_cmplt_pd,
    _mm_cmple_pd,
    _mm_cmpeq_pd,
    _mm_and_pd,
    _mm_or_pd,
    _mm_andnot_pd,
    _mm_add_pd,
    _mm_mul_pd
);
sse2_shims!(
    __m128,
    sse2_cmp_ps,
    sse2_blend_ps,
    sse2_mul_add_ps,
    _mm_cmplt_ps,
    _mm_cmple_ps,
    _mm_cmpeq_ps,
    _mm_and_ps,
    _mm_or_ps,
    _mm_andnot_ps,
    _mm_add_ps,
    _mm_mul_ps
);
