//! AVX2 + FMA and AVX-512 vectors for the bank (x86-64 with `std`): the crate's only `unsafe`
//! code (docs/performance.md says why it is not left to the autovectoriser).
//!
//! # Safety argument
//! The intrinsics are `unsafe` only because the processor must have the instruction set. The
//! types here are private to the crate and are created and used only inside the
//! `#[target_feature]` kernels at the bottom of this module, which `run_f64` / `run_f32` call
//! only after `is_x86_feature_detected!` has confirmed the features (AVX2 and FMA for
//! [`F64x4`] / [`F32x8`], AVX-512F for [`F64x8`] / [`F32x16`]); [`F64x2`] / [`F32x4`] need
//! SSE2, which every x86-64 processor has. Loads and stores check the
//! slice length first, so no intrinsic reads or writes outside a slice.

#![allow(unsafe_code)]

use core::arch::x86_64::*;
use core::ops::{Add, Div, Mul, Neg, Sub};

use super::simd::{Pair, Simd};

/// 2⁵².
const TWO_52: f64 = (1_u64 << 52) as f64;
use super::{BankError, BankFormula, Block, Columns, Isa, Storage};

/// Runs an intrinsic. SAFETY: see the module's safety argument — every use is inside a vector
/// type of this module, which exists only on a processor with its instruction set; pointers are
/// passed only after the slice length was checked.
macro_rules! arch {
    ($e:expr) => {
        // SAFETY: the module's safety argument (instruction set detected before any value of
        // these types exists; slice lengths checked before pointer loads and stores).
        unsafe { $e }
    };
}

macro_rules! vector {
    (
        $name:ident, $t:ty, $raw:ty, $mask:ty, $lanes:expr,
        add $add:ident, sub $sub:ident, mul $mul:ident, div $div:ident, fma $fma:ident,
        set1 $set1:ident, loadu $loadu:ident, storeu $storeu:ident, xor $xor:ident
    ) => {
        /// A vector of the bank (see the module's safety argument).
        #[derive(Clone, Copy)]
        pub(crate) struct $name($raw);

        impl Add for $name {
            type Output = Self;
            #[inline(always)]
            fn add(self, b: Self) -> Self {
                Self(arch!($add(self.0, b.0)))
            }
        }
        impl Sub for $name {
            type Output = Self;
            #[inline(always)]
            fn sub(self, b: Self) -> Self {
                Self(arch!($sub(self.0, b.0)))
            }
        }
        impl Mul for $name {
            type Output = Self;
            #[inline(always)]
            fn mul(self, b: Self) -> Self {
                Self(arch!($mul(self.0, b.0)))
            }
        }
        impl Div for $name {
            type Output = Self;
            #[inline(always)]
            fn div(self, b: Self) -> Self {
                Self(arch!($div(self.0, b.0)))
            }
        }
        impl Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                Self($xor(self.0))
            }
        }
        impl $name {
            #[inline(always)]
            fn splat_raw(v: $t) -> Self {
                Self(arch!($set1(v)))
            }
            #[inline(always)]
            fn load_raw(s: &[$t]) -> Self {
                if s.len() < $lanes {
                    return Self::splat_raw(0.0);
                }
                Self(arch!($loadu(s.as_ptr())))
            }
            #[inline(always)]
            fn store_raw(self, s: &mut [$t]) {
                if s.len() >= $lanes {
                    arch!($storeu(s.as_mut_ptr(), self.0));
                }
            }
            #[inline(always)]
            fn fma_raw(self, b: Self, c: Self) -> Self {
                Self(arch!($fma(self.0, b.0, c.0)))
            }
        }
    };
}

vector!(F64x4, f64, __m256d, __m256d, 4,
    add _mm256_add_pd, sub _mm256_sub_pd, mul _mm256_mul_pd, div _mm256_div_pd,
    fma _mm256_fmadd_pd, set1 _mm256_set1_pd, loadu _mm256_loadu_pd,
    storeu _mm256_storeu_pd, xor flip_mm256_xor_pd);
vector!(F32x8, f32, __m256, __m256, 8,
    add _mm256_add_ps, sub _mm256_sub_ps, mul _mm256_mul_ps, div _mm256_div_ps,
    fma _mm256_fmadd_ps, set1 _mm256_set1_ps, loadu _mm256_loadu_ps,
    storeu _mm256_storeu_ps, xor flip_mm256_xor_ps);
vector!(F64x8, f64, __m512d, __mmask8, 8,
    add _mm512_add_pd, sub _mm512_sub_pd, mul _mm512_mul_pd, div _mm512_div_pd,
    fma _mm512_fmadd_pd, set1 _mm512_set1_pd, loadu _mm512_loadu_pd,
    storeu _mm512_storeu_pd, xor flip_mm512_xor_pd);
vector!(F32x16, f32, __m512, __mmask16, 16,
    add _mm512_add_ps, sub _mm512_sub_ps, mul _mm512_mul_ps, div _mm512_div_ps,
    fma _mm512_fmadd_ps, set1 _mm512_set1_ps, loadu _mm512_loadu_ps,
    storeu _mm512_storeu_ps, xor flip_mm512_xor_ps);

/// The sign bit flipped (integer xor: AVX-512F has no floating-point xor).
#[inline(always)]
fn flip_mm256_xor_pd(a: __m256d) -> __m256d {
    arch!(_mm256_castsi256_pd(_mm256_xor_si256(
        _mm256_castpd_si256(a),
        _mm256_set1_epi64x(i64::MIN)
    )))
}

/// The sign bit flipped (integer xor: AVX-512F has no floating-point xor).
#[inline(always)]
fn flip_mm256_xor_ps(a: __m256) -> __m256 {
    arch!(_mm256_castsi256_ps(_mm256_xor_si256(
        _mm256_castps_si256(a),
        _mm256_set1_epi32(i32::MIN)
    )))
}

/// The sign bit flipped (integer xor: AVX-512F has no floating-point xor).
#[inline(always)]
fn flip_mm512_xor_pd(a: __m512d) -> __m512d {
    arch!(_mm512_castsi512_pd(_mm512_xor_si512(
        _mm512_castpd_si512(a),
        _mm512_set1_epi64(i64::MIN)
    )))
}

/// The sign bit flipped (integer xor: AVX-512F has no floating-point xor).
#[inline(always)]
fn flip_mm512_xor_ps(a: __m512) -> __m512 {
    arch!(_mm512_castsi512_ps(_mm512_xor_si512(
        _mm512_castps_si512(a),
        _mm512_set1_epi32(i32::MIN)
    )))
}

/// The parts every implementation of [`Simd`] shares.
macro_rules! common {
    ($t:ty, $lanes:expr) => {
        type T = $t;
        const LANES: usize = $lanes;
        #[inline(always)]
        fn splat(v: $t) -> Self {
            Self::splat_raw(v)
        }
        #[inline(always)]
        fn load(s: &[$t]) -> Self {
            Self::load_raw(s)
        }
        #[inline(always)]
        fn store(self, s: &mut [$t]) {
            self.store_raw(s)
        }
        #[inline(always)]
        fn fma(self, b: Self, c: Self) -> Self {
            self.fma_raw(b, c)
        }
    };
}

impl Simd for F64x4 {
    type M = __m256d;
    common!(f64, 4);
    #[inline(always)]
    fn less(self, b: Self) -> __m256d {
        arch!(_mm256_cmp_pd::<_CMP_LT_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn less_eq(self, b: Self) -> __m256d {
        arch!(_mm256_cmp_pd::<_CMP_LE_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn equal(self, b: Self) -> __m256d {
        arch!(_mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn select(m: __m256d, a: Self, b: Self) -> Self {
        Self(arch!(_mm256_blendv_pd(b.0, a.0, m)))
    }
    #[inline(always)]
    fn and(a: __m256d, b: __m256d) -> __m256d {
        arch!(_mm256_and_pd(a, b))
    }
    #[inline(always)]
    fn or(a: __m256d, b: __m256d) -> __m256d {
        arch!(_mm256_or_pd(a, b))
    }
    #[inline(always)]
    fn and_not(a: __m256d, b: __m256d) -> __m256d {
        arch!(_mm256_andnot_pd(b, a))
    }
    #[inline(always)]
    fn any(m: __m256d) -> bool {
        arch!(_mm256_movemask_pd(m)) != 0
    }
    #[inline(always)]
    fn all(m: __m256d) -> bool {
        arch!(_mm256_movemask_pd(m)) == 0xf
    }
    #[inline(always)]
    fn magnitude(self) -> Self {
        Self(arch!(_mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0)))
    }
    #[inline(always)]
    fn pow2_shifted(t: Self) -> Self {
        Self(arch!(_mm256_castsi256_pd(_mm256_slli_epi64::<52>(
            _mm256_add_epi64(_mm256_castpd_si256(t.0), _mm256_set1_epi64x(1023))
        ))))
    }
    #[inline(always)]
    fn split_exponent(self) -> (Self, Self) {
        arch!({
            let bits = _mm256_castpd_si256(self.0);
            let m = _mm256_or_si256(
                _mm256_and_si256(bits, _mm256_set1_epi64x(0x000f_ffff_ffff_ffff)),
                _mm256_set1_epi64x(0x3ff0_0000_0000_0000),
            );
            // The biased exponent e as a float: the bits of 2⁵² + e, less 2⁵² + 1023.
            let e = _mm256_or_si256(
                _mm256_srli_epi64::<52>(bits),
                _mm256_set1_epi64x(0x4330_0000_0000_0000),
            );
            let k = _mm256_sub_pd(_mm256_castsi256_pd(e), _mm256_set1_pd(TWO_52 + 1023.0));
            (Self(_mm256_castsi256_pd(m)), Self(k))
        })
    }
}

impl Simd for F32x8 {
    type M = __m256;
    common!(f32, 8);
    #[inline(always)]
    fn less(self, b: Self) -> __m256 {
        arch!(_mm256_cmp_ps::<_CMP_LT_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn less_eq(self, b: Self) -> __m256 {
        arch!(_mm256_cmp_ps::<_CMP_LE_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn equal(self, b: Self) -> __m256 {
        arch!(_mm256_cmp_ps::<_CMP_EQ_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn select(m: __m256, a: Self, b: Self) -> Self {
        Self(arch!(_mm256_blendv_ps(b.0, a.0, m)))
    }
    #[inline(always)]
    fn and(a: __m256, b: __m256) -> __m256 {
        arch!(_mm256_and_ps(a, b))
    }
    #[inline(always)]
    fn or(a: __m256, b: __m256) -> __m256 {
        arch!(_mm256_or_ps(a, b))
    }
    #[inline(always)]
    fn and_not(a: __m256, b: __m256) -> __m256 {
        arch!(_mm256_andnot_ps(b, a))
    }
    #[inline(always)]
    fn any(m: __m256) -> bool {
        arch!(_mm256_movemask_ps(m)) != 0
    }
    #[inline(always)]
    fn all(m: __m256) -> bool {
        arch!(_mm256_movemask_ps(m)) == 0xff
    }
    #[inline(always)]
    fn magnitude(self) -> Self {
        Self(arch!(_mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0)))
    }
    #[inline(always)]
    fn pow2_shifted(t: Self) -> Self {
        Self(arch!(_mm256_castsi256_ps(_mm256_slli_epi32::<23>(
            _mm256_add_epi32(_mm256_castps_si256(t.0), _mm256_set1_epi32(127))
        ))))
    }
    #[inline(always)]
    fn split_exponent(self) -> (Self, Self) {
        arch!({
            let bits = _mm256_castps_si256(self.0);
            let m = _mm256_or_si256(
                _mm256_and_si256(bits, _mm256_set1_epi32(0x007f_ffff)),
                _mm256_set1_epi32(0x3f80_0000),
            );
            let e = _mm256_sub_epi32(_mm256_srli_epi32::<23>(bits), _mm256_set1_epi32(127));
            (Self(_mm256_castsi256_ps(m)), Self(_mm256_cvtepi32_ps(e)))
        })
    }
}

impl Simd for F64x8 {
    type M = __mmask8;
    common!(f64, 8);
    #[inline(always)]
    fn exp_arg(x: Self) -> Self {
        // max/min return their second operand when either is NaN: NaN stays NaN.
        let lo = Self::splat_raw(-1100.0).0;
        let hi = Self::splat_raw(1100.0).0;
        Self(arch!(_mm512_min_pd(hi, _mm512_max_pd(lo, x.0))))
    }
    const EXP_TABLE: bool = true;
    #[inline(always)]
    fn exp2_frac(t: Self) -> Self {
        let mut table = [0.0; 8];
        for (v, c) in table.iter_mut().zip(<f64 as super::lanes::Lane>::EXP_TABLE) {
            *v = <f64 as crate::Real>::from_f64(*c);
        }
        let table = Self::load_raw(&table);
        Self(arch!(_mm512_permutexvar_pd(
            _mm512_castpd_si512(t.0),
            table.0
        )))
    }
    #[inline(always)]
    fn scale(e: Self, n: Self) -> Self {
        Self(arch!(_mm512_scalef_pd(e.0, n.0)))
    }
    #[inline(always)]
    fn less(self, b: Self) -> __mmask8 {
        arch!(_mm512_cmp_pd_mask::<_CMP_LT_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn less_eq(self, b: Self) -> __mmask8 {
        arch!(_mm512_cmp_pd_mask::<_CMP_LE_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn equal(self, b: Self) -> __mmask8 {
        arch!(_mm512_cmp_pd_mask::<_CMP_EQ_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn select(m: __mmask8, a: Self, b: Self) -> Self {
        Self(arch!(_mm512_mask_blend_pd(m, b.0, a.0)))
    }
    #[inline(always)]
    fn and(a: __mmask8, b: __mmask8) -> __mmask8 {
        a & b
    }
    #[inline(always)]
    fn or(a: __mmask8, b: __mmask8) -> __mmask8 {
        a | b
    }
    #[inline(always)]
    fn and_not(a: __mmask8, b: __mmask8) -> __mmask8 {
        a & !b
    }
    #[inline(always)]
    fn any(m: __mmask8) -> bool {
        m != 0
    }
    #[inline(always)]
    fn all(m: __mmask8) -> bool {
        m == 0xff
    }
    #[inline(always)]
    fn magnitude(self) -> Self {
        Self(arch!(_mm512_abs_pd(self.0)))
    }
    #[inline(always)]
    fn pow2_shifted(t: Self) -> Self {
        Self(arch!(_mm512_castsi512_pd(_mm512_slli_epi64::<52>(
            _mm512_add_epi64(_mm512_castpd_si512(t.0), _mm512_set1_epi64(1023))
        ))))
    }
    #[inline(always)]
    fn split_exponent(self) -> (Self, Self) {
        arch!({
            let bits = _mm512_castpd_si512(self.0);
            let m = _mm512_or_si512(
                _mm512_and_si512(bits, _mm512_set1_epi64(0x000f_ffff_ffff_ffff)),
                _mm512_set1_epi64(0x3ff0_0000_0000_0000),
            );
            let e = _mm512_or_si512(
                _mm512_srli_epi64::<52>(bits),
                _mm512_set1_epi64(0x4330_0000_0000_0000),
            );
            let k = _mm512_sub_pd(_mm512_castsi512_pd(e), _mm512_set1_pd(TWO_52 + 1023.0));
            (Self(_mm512_castsi512_pd(m)), Self(k))
        })
    }
}

impl Simd for F32x16 {
    type M = __mmask16;
    common!(f32, 16);
    #[inline(always)]
    fn exp_arg(x: Self) -> Self {
        // max/min return their second operand when either is NaN: NaN stays NaN.
        let lo = Self::splat_raw(-1100.0).0;
        let hi = Self::splat_raw(1100.0).0;
        Self(arch!(_mm512_min_ps(hi, _mm512_max_ps(lo, x.0))))
    }
    const EXP_TABLE: bool = true;
    #[inline(always)]
    fn exp2_frac(t: Self) -> Self {
        let mut table = [0.0; 16];
        for (v, c) in table.iter_mut().zip(<f32 as super::lanes::Lane>::EXP_TABLE) {
            *v = <f32 as crate::Real>::from_f64(*c);
        }
        let table = Self::load_raw(&table);
        Self(arch!(_mm512_permutexvar_ps(
            _mm512_castps_si512(t.0),
            table.0
        )))
    }
    #[inline(always)]
    fn scale(e: Self, n: Self) -> Self {
        Self(arch!(_mm512_scalef_ps(e.0, n.0)))
    }
    #[inline(always)]
    fn less(self, b: Self) -> __mmask16 {
        arch!(_mm512_cmp_ps_mask::<_CMP_LT_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn less_eq(self, b: Self) -> __mmask16 {
        arch!(_mm512_cmp_ps_mask::<_CMP_LE_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn equal(self, b: Self) -> __mmask16 {
        arch!(_mm512_cmp_ps_mask::<_CMP_EQ_OQ>(self.0, b.0))
    }
    #[inline(always)]
    fn select(m: __mmask16, a: Self, b: Self) -> Self {
        Self(arch!(_mm512_mask_blend_ps(m, b.0, a.0)))
    }
    #[inline(always)]
    fn and(a: __mmask16, b: __mmask16) -> __mmask16 {
        a & b
    }
    #[inline(always)]
    fn or(a: __mmask16, b: __mmask16) -> __mmask16 {
        a | b
    }
    #[inline(always)]
    fn and_not(a: __mmask16, b: __mmask16) -> __mmask16 {
        a & !b
    }
    #[inline(always)]
    fn any(m: __mmask16) -> bool {
        m != 0
    }
    #[inline(always)]
    fn all(m: __mmask16) -> bool {
        m == 0xffff
    }
    #[inline(always)]
    fn magnitude(self) -> Self {
        Self(arch!(_mm512_abs_ps(self.0)))
    }
    #[inline(always)]
    fn pow2_shifted(t: Self) -> Self {
        Self(arch!(_mm512_castsi512_ps(_mm512_slli_epi32::<23>(
            _mm512_add_epi32(_mm512_castps_si512(t.0), _mm512_set1_epi32(127))
        ))))
    }
    #[inline(always)]
    fn split_exponent(self) -> (Self, Self) {
        arch!({
            let bits = _mm512_castps_si512(self.0);
            let m = _mm512_or_si512(
                _mm512_and_si512(bits, _mm512_set1_epi32(0x007f_ffff)),
                _mm512_set1_epi32(0x3f80_0000),
            );
            let e = _mm512_sub_epi32(_mm512_srli_epi32::<23>(bits), _mm512_set1_epi32(127));
            (Self(_mm512_castsi512_ps(m)), Self(_mm512_cvtepi32_ps(e)))
        })
    }
}

/// The kernels compiled for one instruction set each.
macro_rules! entry {
    ($name:ident, $t:ty, $v:ty, $features:literal) => {
        #[target_feature(enable = $features)]
        fn $name<F: BankFormula, S: Storage<$t>>(
            cols: &mut Columns<S>,
            block: &mut Block<'_, $t>,
        ) -> Result<Option<usize>, BankError> {
            super::kernel::run::<$v, F, S>(cols, block)
        }
    };
}

/// SSE2 vectors: x86-64's baseline (every x86-64 processor has SSE2), so no detection.
macro_rules! sse2_vector {
    (
        $name:ident, $t:ty, $raw:ty, $lanes:expr, $full:expr,
        [$add:ident, $sub:ident, $mul:ident, $div:ident, $xor:ident, $set1:ident],
        [$loadu:ident, $storeu:ident],
        [$lt:ident, $le:ident, $eq:ident, $and:ident, $or:ident, $andnot:ident, $movemask:ident],
        [$to_int:ident, $from_int:ident, $add_int:ident, $set1_int:ident, $bias:expr,
         $shl:ident, $shr:ident, $mant:literal, $mant_mask:expr, $one:expr, $exponent:expr]
    ) => {
        /// A vector of the bank's SSE2 kernel (x86-64's baseline).
        #[derive(Clone, Copy)]
        pub(crate) struct $name($raw);

        impl Add for $name {
            type Output = Self;
            #[inline(always)]
            fn add(self, b: Self) -> Self {
                Self(arch!($add(self.0, b.0)))
            }
        }
        impl Sub for $name {
            type Output = Self;
            #[inline(always)]
            fn sub(self, b: Self) -> Self {
                Self(arch!($sub(self.0, b.0)))
            }
        }
        impl Mul for $name {
            type Output = Self;
            #[inline(always)]
            fn mul(self, b: Self) -> Self {
                Self(arch!($mul(self.0, b.0)))
            }
        }
        impl Div for $name {
            type Output = Self;
            #[inline(always)]
            fn div(self, b: Self) -> Self {
                Self(arch!($div(self.0, b.0)))
            }
        }
        impl Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                Self(arch!($xor(self.0, $set1(-0.0))))
            }
        }
        impl Simd for $name {
            type T = $t;
            type M = $raw;
            const LANES: usize = $lanes;
            #[inline(always)]
            fn splat(v: $t) -> Self {
                Self(arch!($set1(v)))
            }
            #[inline(always)]
            fn load(s: &[$t]) -> Self {
                if s.len() < $lanes {
                    return Self::splat(0.0);
                }
                Self(arch!($loadu(s.as_ptr())))
            }
            #[inline(always)]
            fn store(self, s: &mut [$t]) {
                if s.len() >= $lanes {
                    arch!($storeu(s.as_mut_ptr(), self.0));
                }
            }
            #[inline(always)]
            fn fma(self, b: Self, c: Self) -> Self {
                self * b + c
            }
            #[inline(always)]
            fn less(self, b: Self) -> $raw {
                arch!($lt(self.0, b.0))
            }
            #[inline(always)]
            fn less_eq(self, b: Self) -> $raw {
                arch!($le(self.0, b.0))
            }
            #[inline(always)]
            fn equal(self, b: Self) -> $raw {
                arch!($eq(self.0, b.0))
            }
            #[inline(always)]
            fn select(m: $raw, a: Self, b: Self) -> Self {
                Self(arch!($or($and(m, a.0), $andnot(m, b.0))))
            }
            #[inline(always)]
            fn and(a: $raw, b: $raw) -> $raw {
                arch!($and(a, b))
            }
            #[inline(always)]
            fn or(a: $raw, b: $raw) -> $raw {
                arch!($or(a, b))
            }
            #[inline(always)]
            fn and_not(a: $raw, b: $raw) -> $raw {
                arch!($andnot(b, a))
            }
            #[inline(always)]
            fn any(m: $raw) -> bool {
                arch!($movemask(m)) != 0
            }
            #[inline(always)]
            fn all(m: $raw) -> bool {
                arch!($movemask(m)) == $full
            }
            #[inline(always)]
            fn magnitude(self) -> Self {
                Self(arch!($andnot($set1(-0.0), self.0)))
            }
            #[inline(always)]
            fn pow2_shifted(t: Self) -> Self {
                Self(arch!($from_int($shl::<$mant>($add_int(
                    $to_int(t.0),
                    $set1_int($bias)
                )))))
            }
            #[inline(always)]
            fn split_exponent(self) -> (Self, Self) {
                arch!({
                    let bits = $to_int(self.0);
                    let m =
                        _mm_or_si128(_mm_and_si128(bits, $set1_int($mant_mask)), $set1_int($one));
                    let k = $exponent($shr::<$mant>(bits));
                    (Self($from_int(m)), Self(k))
                })
            }
        }
    };
}

/// The unbiased exponent of f64 bits shifted down: as a float, the bits of 2⁵² + e less
/// 2⁵² + 1023 (SSE2 has no 64-bit integer conversion).
#[inline(always)]
fn exponent_f64(e: __m128i) -> __m128d {
    arch!({
        let e = _mm_or_si128(e, _mm_set1_epi64x(0x4330_0000_0000_0000));
        _mm_sub_pd(_mm_castsi128_pd(e), _mm_set1_pd(TWO_52 + 1023.0))
    })
}

/// The unbiased exponent of f32 bits shifted down, as a float.
#[inline(always)]
fn exponent_f32(e: __m128i) -> __m128 {
    arch!(_mm_cvtepi32_ps(_mm_sub_epi32(e, _mm_set1_epi32(127))))
}

sse2_vector!(
    F64x2,
    f64,
    __m128d,
    2,
    0x3,
    [
        _mm_add_pd,
        _mm_sub_pd,
        _mm_mul_pd,
        _mm_div_pd,
        _mm_xor_pd,
        _mm_set1_pd
    ],
    [_mm_loadu_pd, _mm_storeu_pd],
    [
        _mm_cmplt_pd,
        _mm_cmple_pd,
        _mm_cmpeq_pd,
        _mm_and_pd,
        _mm_or_pd,
        _mm_andnot_pd,
        _mm_movemask_pd
    ],
    [
        _mm_castpd_si128,
        _mm_castsi128_pd,
        _mm_add_epi64,
        _mm_set1_epi64x,
        1023,
        _mm_slli_epi64,
        _mm_srli_epi64,
        52,
        0x000f_ffff_ffff_ffff,
        0x3ff0_0000_0000_0000,
        exponent_f64
    ]
);
sse2_vector!(
    F32x4,
    f32,
    __m128,
    4,
    0xf,
    [
        _mm_add_ps,
        _mm_sub_ps,
        _mm_mul_ps,
        _mm_div_ps,
        _mm_xor_ps,
        _mm_set1_ps
    ],
    [_mm_loadu_ps, _mm_storeu_ps],
    [
        _mm_cmplt_ps,
        _mm_cmple_ps,
        _mm_cmpeq_ps,
        _mm_and_ps,
        _mm_or_ps,
        _mm_andnot_ps,
        _mm_movemask_ps
    ],
    [
        _mm_castps_si128,
        _mm_castsi128_ps,
        _mm_add_epi32,
        _mm_set1_epi32,
        127,
        _mm_slli_epi32,
        _mm_srli_epi32,
        23,
        0x007f_ffff,
        0x3f80_0000,
        exponent_f32
    ]
);

/// The vectors a chunk of each kernel is made of (measured: docs/performance.md).
type Avx2F64 = Pair<Pair<F64x4>>;
type Avx2F32 = Pair<Pair<F32x8>>;
type Avx512F64 = Pair<Pair<F64x8>>;
type Avx512F32 = Pair<Pair<F32x16>>;
type Sse2F64 = Pair<Pair<F64x2>>;
type Sse2F32 = Pair<Pair<F32x4>>;

/// The SSE2 kernels (x86-64's baseline: no detection, no `unsafe` call).
fn f64_sse2<F: BankFormula, S: Storage<f64>>(
    cols: &mut Columns<S>,
    block: &mut Block<'_, f64>,
) -> Result<Option<usize>, BankError> {
    super::kernel::run::<Sse2F64, F, S>(cols, block)
}

fn f32_sse2<F: BankFormula, S: Storage<f32>>(
    cols: &mut Columns<S>,
    block: &mut Block<'_, f32>,
) -> Result<Option<usize>, BankError> {
    super::kernel::run::<Sse2F32, F, S>(cols, block)
}

entry!(f64_avx2, f64, Avx2F64, "avx2,fma");
entry!(f32_avx2, f32, Avx2F32, "avx2,fma");
entry!(f64_avx512, f64, Avx512F64, "avx512f");
entry!(f32_avx512, f32, Avx512F32, "avx512f");

/// Runs the kernel of `isa` when this processor has it (`None` otherwise, and for
/// [`Isa::Portable`]).
macro_rules! dispatch {
    ($name:ident, $t:ty, $avx512:ident, $avx2:ident, $sse2:ident) => {
        pub(crate) fn $name<F: BankFormula, S: Storage<$t>>(
            isa: Isa,
            cols: &mut Columns<S>,
            block: &mut Block<'_, $t>,
        ) -> Option<Result<Option<usize>, BankError>> {
            match isa {
                Isa::Avx512 if std::arch::is_x86_feature_detected!("avx512f") => {
                    // SAFETY: AVX-512F was detected on this processor just above.
                    Some(unsafe { $avx512::<F, S>(cols, block) })
                }
                Isa::Avx2
                    if std::arch::is_x86_feature_detected!("avx2")
                        && std::arch::is_x86_feature_detected!("fma") =>
                {
                    // SAFETY: AVX2 and FMA were detected on this processor just above.
                    Some(unsafe { $avx2::<F, S>(cols, block) })
                }
                Isa::Sse2 => Some($sse2::<F, S>(cols, block)),
                _ => None,
            }
        }
    };
}

dispatch!(run_f64, f64, f64_avx512, f64_avx2, f64_sse2);
dispatch!(run_f32, f32, f32_avx512, f32_avx2, f32_sse2);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bank::lanes::{exp, ln};

    /// A deterministic generator (xorshift64*) of uniform numbers in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1_u64 << 53) as f64
        }
    }

    /// The worst error of `exp` and `ln` on vector `V` against the platform's, in ulp of the
    /// result (normal results only), over 2e5 arguments.
    fn worst<V: Simd>(
        to: impl Fn(f64) -> V::T,
        from: impl Fn(V::T) -> f64,
        eps: f64,
    ) -> (f64, f64) {
        let mut rng = Rng(5);
        let (mut e, mut l) = (0.0_f64, 0.0_f64);
        let n = V::LANES;
        for _ in 0..200_000 / n {
            let xs: std::vec::Vec<V::T> = (0..n).map(|_| to(-80.0 + 160.0 * rng.next())).collect();
            let ys: std::vec::Vec<V::T> = (0..n)
                .map(|_| to((60.0 * (2.0 * rng.next() - 1.0)).exp()))
                .collect();
            let mut ex = std::vec![to(0.0); n];
            let mut lx = std::vec![to(0.0); n];
            exp(V::load(&xs)).store(&mut ex);
            ln(V::load(&ys)).store(&mut lx);
            for i in 0..n {
                let r = from(xs[i]).exp();
                e = e.max((from(ex[i]) - r).abs() / (r * eps));
                let r = from(ys[i]).ln();
                l = l.max((from(lx[i]) - r).abs() / (r.abs().max(1e-30) * eps));
            }
        }
        (e, l)
    }

    #[test]
    fn every_vector_exp_and_ln_match_the_platform() {
        let f64s = |v: f64| v;
        let f32s = |v: f64| v as f32;
        let mut checked = 0;
        let mut check = |(e, l): (f64, f64), what: &str| {
            assert!(e <= 2.0 && l <= 2.0, "{what}: exp {e} ulp, ln {l} ulp");
            checked += 1;
        };
        check(worst::<F64x2>(f64s, f64::from, f64::EPSILON), "sse2 f64");
        check(
            worst::<F32x4>(f32s, f64::from, f64::from(f32::EPSILON)),
            "sse2 f32",
        );
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            check(worst::<F64x4>(f64s, f64::from, f64::EPSILON), "avx2 f64");
            check(
                worst::<F32x8>(f32s, f64::from, f64::from(f32::EPSILON)),
                "avx2 f32",
            );
        }
        if std::arch::is_x86_feature_detected!("avx512f") {
            check(worst::<F64x8>(f64s, f64::from, f64::EPSILON), "avx512 f64");
            check(
                worst::<F32x16>(f32s, f64::from, f64::from(f32::EPSILON)),
                "avx512 f32",
            );
        }
        assert!(checked >= 2);
    }
}
