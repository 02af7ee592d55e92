//! AVX2 + FMA and AVX-512 vectors for the bank (x86-64 with `std`): the crate's only `unsafe`
//! code (docs/performance.md says why it is not left to the autovectoriser).
//!
//! # Safety argument
//! The intrinsics are `unsafe` only because the processor must have the instruction set. Each
//! vector type holds a token of its instruction set ([`Sse2`] for [`F64x2`] / [`F32x4`],
//! [`Avx2`] (AVX2 and FMA) for [`F64x4`] / [`F32x8`], [`Avx512`] (AVX-512F) for [`F64x8`] /
//! [`F32x16`]): a zero-sized value whose field is private to this module and whose only
//! constructor, `detect`, asks the processor (`is_x86_feature_detected!`). Every constructor of
//! a vector takes a token, and every operation makes its result from its operands' token, so a
//! vector exists only on a processor with its instruction set. The `#[target_feature]` kernels
//! take the token too, which is what makes their calls sound. Loads and stores check the slice
//! length first, so no intrinsic reads or writes outside a slice.

#![allow(unsafe_code)]

use core::arch::x86_64::*;
use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::block::Block;
use crate::columns::ColumnsMut;
use crate::error::BankError;
use crate::formula::BankFormula;
use crate::instruction_set::Isa;
use crate::kernel;
use crate::simd::Pair;
use crate::vector::{Lane, Simd};
use hyst_core::real::Real;

/// 2⁵².
const TWO_52: f64 = (1_u64 << 52) as f64;

pub(crate) use crate::token::{Avx2, Avx512, Sse2};

/// A vector type and the token of its instruction set (the one its intrinsics need).
pub(crate) trait Proven {
    /// [`Sse2`], [`Avx2`] or [`Avx512`].
    type Token;
}

/// Runs an intrinsic. SAFETY: the module's safety argument (a vector, or the token it is made
/// from, exists only on a processor with its instruction set; pointers are passed after the
/// slice length is checked).
macro_rules! arch {
    ($e:expr) => {
        // SAFETY: the module's safety argument (the operands' token, or the token passed to the
        // constructor, proves the instruction set; slice lengths checked before pointer loads
        // and stores).
        unsafe { $e }
    };
}

mod sse2;

use sse2::*;

macro_rules! vector {
    (
        $name:ident, $token:ty, $t:ty, $raw:ty, $mask:ty, $lanes:expr,
        add $add:ident, sub $sub:ident, mul $mul:ident, div $div:ident, fma $fma:ident,
        set1 $set1:ident, loadu $loadu:ident, storeu $storeu:ident, xor $xor:ident
    ) => {
        /// A vector of the bank, with the proof that this processor runs its instructions
        /// (see the module's safety argument).
        #[derive(Clone, Copy)]
        pub(crate) struct $name($raw, $token);

        impl Proven for $name {
            type Token = $token;
        }

        impl Add for $name {
            type Output = Self;
            #[inline(always)]
            fn add(self, b: Self) -> Self {
                Self(arch!($add(self.0, b.0)), self.1)
            }
        }
        impl Sub for $name {
            type Output = Self;
            #[inline(always)]
            fn sub(self, b: Self) -> Self {
                Self(arch!($sub(self.0, b.0)), self.1)
            }
        }
        impl Mul for $name {
            type Output = Self;
            #[inline(always)]
            fn mul(self, b: Self) -> Self {
                Self(arch!($mul(self.0, b.0)), self.1)
            }
        }
        impl Div for $name {
            type Output = Self;
            #[inline(always)]
            fn div(self, b: Self) -> Self {
                Self(arch!($div(self.0, b.0)), self.1)
            }
        }
        impl Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                Self($xor(self.0), self.1)
            }
        }
        impl $name {
            #[inline(always)]
            fn splat_raw(token: $token, v: $t) -> Self {
                Self(arch!($set1(v)), token)
            }
            #[inline(always)]
            fn load_raw(token: $token, s: &[$t]) -> Self {
                if s.len() < $lanes {
                    return Self::splat_raw(token, 0.0);
                }
                Self(arch!($loadu(s.as_ptr())), token)
            }
            #[inline(always)]
            fn store_raw(self, s: &mut [$t]) {
                if s.len() >= $lanes {
                    arch!($storeu(s.as_mut_ptr(), self.0));
                }
            }
            #[inline(always)]
            fn fma_raw(self, b: Self, c: Self) -> Self {
                Self(arch!($fma(self.0, b.0, c.0)), self.1)
            }
        }
    };
}

vector!(F64x4, Avx2, f64, __m256d, __m256d, 4,
    add _mm256_add_pd, sub _mm256_sub_pd, mul _mm256_mul_pd, div _mm256_div_pd,
    fma _mm256_fmadd_pd, set1 _mm256_set1_pd, loadu _mm256_loadu_pd,
    storeu _mm256_storeu_pd, xor flip_mm256_xor_pd);
vector!(F32x8, Avx2, f32, __m256, __m256, 8,
    add _mm256_add_ps, sub _mm256_sub_ps, mul _mm256_mul_ps, div _mm256_div_ps,
    fma _mm256_fmadd_ps, set1 _mm256_set1_ps, loadu _mm256_loadu_ps,
    storeu _mm256_storeu_ps, xor flip_mm256_xor_ps);
vector!(F64x8, Avx512, f64, __m512d, __mmask8, 8,
    add _mm512_add_pd, sub _mm512_sub_pd, mul _mm512_mul_pd, div _mm512_div_pd,
    fma _mm512_fmadd_pd, set1 _mm512_set1_pd, loadu _mm512_loadu_pd,
    storeu _mm512_storeu_pd, xor flip_mm512_xor_pd);
vector!(F32x16, Avx512, f32, __m512, __mmask16, 16,
    add _mm512_add_ps, sub _mm512_sub_ps, mul _mm512_mul_ps, div _mm512_div_ps,
    fma _mm512_fmadd_ps, set1 _mm512_set1_ps, loadu _mm512_loadu_ps,
    storeu _mm512_storeu_ps, xor flip_mm512_xor_ps);

/// The parts every implementation of [`Simd`] here shares.
macro_rules! common {
    ($t:ty, $lanes:expr, $tick:ty) => {
        type T = $t;
        type Token = <Self as Proven>::Token;
        type Tick = $tick;
        const LANES: usize = $lanes;
        #[inline(always)]
        fn token(self) -> Self::Token {
            self.1
        }
        #[inline(always)]
        fn splat(token: Self::Token, v: $t) -> Self {
            Self::splat_raw(token, v)
        }
        #[inline(always)]
        fn load(token: Self::Token, s: &[$t]) -> Self {
            Self::load_raw(token, s)
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

/// The sign bit flipped by an integer xor (AVX-512F has no floating-point xor).
macro_rules! flip {
    ($name:ident, $raw:ty, $to_int:ident, $from_int:ident, $xor:ident, $set1_int:ident, $min:expr) => {
        #[inline(always)]
        fn $name(a: $raw) -> $raw {
            arch!($from_int($xor($to_int(a), $set1_int($min))))
        }
    };
}

flip!(
    flip_mm256_xor_pd,
    __m256d,
    _mm256_castpd_si256,
    _mm256_castsi256_pd,
    _mm256_xor_si256,
    _mm256_set1_epi64x,
    i64::MIN
);
flip!(
    flip_mm256_xor_ps,
    __m256,
    _mm256_castps_si256,
    _mm256_castsi256_ps,
    _mm256_xor_si256,
    _mm256_set1_epi32,
    i32::MIN
);
flip!(
    flip_mm512_xor_pd,
    __m512d,
    _mm512_castpd_si512,
    _mm512_castsi512_pd,
    _mm512_xor_si512,
    _mm512_set1_epi64,
    i64::MIN
);
flip!(
    flip_mm512_xor_ps,
    __m512,
    _mm512_castps_si512,
    _mm512_castsi512_ps,
    _mm512_xor_si512,
    _mm512_set1_epi32,
    i32::MIN
);

/// The exponent field of f64 bits shifted down, as a float less 1023: the bits of 2⁵² + e,
/// less 2⁵² + 1023 (no 64-bit integer conversion before AVX-512DQ).
macro_rules! exponent_f64 {
    ($name:ident, $int:ty, $raw:ty, $or:ident, $set1_int:ident, $sub:ident, $from_int:ident,
     $set1:ident) => {
        #[inline(always)]
        fn $name(e: $int) -> $raw {
            arch!($sub(
                $from_int($or(e, $set1_int(0x4330_0000_0000_0000))),
                $set1(TWO_52 + 1023.0)
            ))
        }
    };
}

/// The exponent field of f32 bits shifted down, as a float less 127.
macro_rules! exponent_f32 {
    ($name:ident, $int:ty, $raw:ty, $sub_int:ident, $set1_int:ident, $cvt:ident) => {
        #[inline(always)]
        fn $name(e: $int) -> $raw {
            arch!($cvt($sub_int(e, $set1_int(127))))
        }
    };
}

exponent_f64!(
    exponent_f64x4,
    __m256i,
    __m256d,
    _mm256_or_si256,
    _mm256_set1_epi64x,
    _mm256_sub_pd,
    _mm256_castsi256_pd,
    _mm256_set1_pd
);
exponent_f32!(
    exponent_f32x8,
    __m256i,
    __m256,
    _mm256_sub_epi32,
    _mm256_set1_epi32,
    _mm256_cvtepi32_ps
);
exponent_f64!(
    exponent_f64x8,
    __m512i,
    __m512d,
    _mm512_or_si512,
    _mm512_set1_epi64,
    _mm512_sub_pd,
    _mm512_castsi512_pd,
    _mm512_set1_pd
);
exponent_f32!(
    exponent_f32x16,
    __m512i,
    __m512,
    _mm512_sub_epi32,
    _mm512_set1_epi32,
    _mm512_cvtepi32_ps
);

/// The bit-level parts of [`Simd`] (2ⁿ from its bits, the exponent and mantissa of a float).
macro_rules! bits {
    ($raw:ty, $to_int:ident, $from_int:ident, $add_int:ident, $set1_int:ident, $and:ident,
     $or:ident, $shl:ident, $shr:ident, $mant:literal, $bias:expr, $mant_mask:expr, $one:expr,
     $exponent:ident) => {
        #[inline(always)]
        fn pow2_shifted(t: Self) -> Self {
            Self(
                arch!($from_int($shl::<$mant>($add_int(
                    $to_int(t.0),
                    $set1_int($bias)
                )))),
                t.1,
            )
        }
        #[inline(always)]
        fn split_exponent(self) -> (Self, Self) {
            let bits = arch!($to_int(self.0));
            let m = arch!($or($and(bits, $set1_int($mant_mask)), $set1_int($one)));
            let k = $exponent(arch!($shr::<$mant>(bits)));
            (Self(arch!($from_int(m)), self.1), Self(k, self.1))
        }
    };
}

/// [`Simd`] for an AVX2 or SSE2 vector (vector masks).
macro_rules! avx2_simd {
    ($name:ident, $tick:ty, $t:ty, $raw:ty, $lanes:expr, $full:expr, $cmp:ident, $blend:ident, $and:ident,
     $or:ident, $andnot:ident, $xor:ident, $movemask:ident, $set1:ident, $max:ident,
     [$($bits:tt)*]) => {
        impl Simd for $name {
            type M = $raw;
            common!($t, $lanes, $tick);
            #[inline(always)]
            fn less(self, b: Self) -> $raw {
                arch!($cmp::<_CMP_LT_OQ>(self.0, b.0))
            }
            #[inline(always)]
            fn less_eq(self, b: Self) -> $raw {
                arch!($cmp::<_CMP_LE_OQ>(self.0, b.0))
            }
            #[inline(always)]
            fn equal(self, b: Self) -> $raw {
                arch!($cmp::<_CMP_EQ_OQ>(self.0, b.0))
            }
            #[inline(always)]
            fn select(m: $raw, a: Self, b: Self) -> Self {
                Self(arch!($blend(b.0, a.0, m)), a.1)
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
                Self(arch!($andnot($set1(-0.0), self.0)), self.1)
            }
            #[inline(always)]
            fn negate_where(self, m: $raw) -> Self {
                Self(arch!($xor(self.0, $and(m, $set1(-0.0)))), self.1)
            }
            #[inline(always)]
            fn max_or(self, b: Self) -> Self {
                Self(arch!($max(self.0, b.0)), self.1)
            }
            bits!($($bits)*);
        }
    };
}

avx2_simd!(
    F64x4,
    Pair<Pair<F64x4>>,
    f64,
    __m256d,
    4,
    0xf,
    _mm256_cmp_pd,
    _mm256_blendv_pd,
    _mm256_and_pd,
    _mm256_or_pd,
    _mm256_andnot_pd,
    _mm256_xor_pd,
    _mm256_movemask_pd,
    _mm256_set1_pd,
    _mm256_max_pd,
    [
        __m256d,
        _mm256_castpd_si256,
        _mm256_castsi256_pd,
        _mm256_add_epi64,
        _mm256_set1_epi64x,
        _mm256_and_si256,
        _mm256_or_si256,
        _mm256_slli_epi64,
        _mm256_srli_epi64,
        52,
        1023,
        0x000f_ffff_ffff_ffff,
        0x3ff0_0000_0000_0000,
        exponent_f64x4
    ]
);
avx2_simd!(
    F32x8,
    Pair<Pair<F32x8>>,
    f32,
    __m256,
    8,
    0xff,
    _mm256_cmp_ps,
    _mm256_blendv_ps,
    _mm256_and_ps,
    _mm256_or_ps,
    _mm256_andnot_ps,
    _mm256_xor_ps,
    _mm256_movemask_ps,
    _mm256_set1_ps,
    _mm256_max_ps,
    [
        __m256,
        _mm256_castps_si256,
        _mm256_castsi256_ps,
        _mm256_add_epi32,
        _mm256_set1_epi32,
        _mm256_and_si256,
        _mm256_or_si256,
        _mm256_slli_epi32,
        _mm256_srli_epi32,
        23,
        127,
        0x007f_ffff,
        0x3f80_0000,
        exponent_f32x8
    ]
);

/// [`Simd`] for an AVX-512 vector (mask registers), with `exp` by the table of
/// [`crate::lanes::Lane::EXP_TABLE`] in one register (`vpermpd`) and `vscalefpd`.
macro_rules! avx512_simd {
    ($name:ident, $tick:ty, $t:ty, $raw:ty, $mask:ty, $lanes:expr, $full:expr, $cmp:ident, $blend:ident,
     $abs:ident, $min:ident, $max:ident, $scalef:ident, $permute:ident, $to_int:ident,
     [$($bits:tt)*]) => {
        impl Simd for $name {
            type M = $mask;
            common!($t, $lanes, $tick);
            const EXP_TABLE: bool = true;
            const REGISTERS: u32 = 32;
            #[inline(always)]
            fn exp_arg(x: Self) -> Self {
                // max/min return their second operand when either is NaN: NaN stays NaN.
                let lo = Self::splat_raw(x.1, -1100.0).0;
                let hi = Self::splat_raw(x.1, 1100.0).0;
                Self(arch!($min(hi, $max(lo, x.0))), x.1)
            }
            #[inline(always)]
            fn exp2_frac(t: Self) -> Self {
                let mut table = [0.0; $lanes];
                for (v, c) in table.iter_mut().zip(<$t as Lane>::EXP_TABLE) {
                    *v = <$t as Real>::from_f64(*c);
                }
                let table = Self::load_raw(t.1, &table);
                Self(arch!($permute($to_int(t.0), table.0)), t.1)
            }
            #[inline(always)]
            fn scale(e: Self, n: Self) -> Self {
                Self(arch!($scalef(e.0, n.0)), e.1)
            }
            #[inline(always)]
            fn less(self, b: Self) -> $mask {
                arch!($cmp::<_CMP_LT_OQ>(self.0, b.0))
            }
            #[inline(always)]
            fn less_eq(self, b: Self) -> $mask {
                arch!($cmp::<_CMP_LE_OQ>(self.0, b.0))
            }
            #[inline(always)]
            fn equal(self, b: Self) -> $mask {
                arch!($cmp::<_CMP_EQ_OQ>(self.0, b.0))
            }
            #[inline(always)]
            fn select(m: $mask, a: Self, b: Self) -> Self {
                Self(arch!($blend(m, b.0, a.0)), a.1)
            }
            #[inline(always)]
            fn and(a: $mask, b: $mask) -> $mask {
                a & b
            }
            #[inline(always)]
            fn or(a: $mask, b: $mask) -> $mask {
                a | b
            }
            #[inline(always)]
            fn and_not(a: $mask, b: $mask) -> $mask {
                a & !b
            }
            #[inline(always)]
            fn any(m: $mask) -> bool {
                m != 0
            }
            #[inline(always)]
            fn all(m: $mask) -> bool {
                m == $full
            }
            #[inline(always)]
            fn magnitude(self) -> Self {
                Self(arch!($abs(self.0)), self.1)
            }
            #[inline(always)]
            fn max_or(self, b: Self) -> Self {
                Self(arch!($max(self.0, b.0)), self.1)
            }
            bits!($($bits)*);
        }
    };
}

avx512_simd!(
    F64x8,
    Pair<F64x8>,
    f64,
    __m512d,
    __mmask8,
    8,
    0xff,
    _mm512_cmp_pd_mask,
    _mm512_mask_blend_pd,
    _mm512_abs_pd,
    _mm512_min_pd,
    _mm512_max_pd,
    _mm512_scalef_pd,
    _mm512_permutexvar_pd,
    _mm512_castpd_si512,
    [
        __m512d,
        _mm512_castpd_si512,
        _mm512_castsi512_pd,
        _mm512_add_epi64,
        _mm512_set1_epi64,
        _mm512_and_si512,
        _mm512_or_si512,
        _mm512_slli_epi64,
        _mm512_srli_epi64,
        52,
        1023,
        0x000f_ffff_ffff_ffff,
        0x3ff0_0000_0000_0000,
        exponent_f64x8
    ]
);
avx512_simd!(
    F32x16,
    Pair<F32x16>,
    f32,
    __m512,
    __mmask16,
    16,
    0xffff,
    _mm512_cmp_ps_mask,
    _mm512_mask_blend_ps,
    _mm512_abs_ps,
    _mm512_min_ps,
    _mm512_max_ps,
    _mm512_scalef_ps,
    _mm512_permutexvar_ps,
    _mm512_castps_si512,
    [
        __m512,
        _mm512_castps_si512,
        _mm512_castsi512_ps,
        _mm512_add_epi32,
        _mm512_set1_epi32,
        _mm512_and_si512,
        _mm512_or_si512,
        _mm512_slli_epi32,
        _mm512_srli_epi32,
        23,
        127,
        0x007f_ffff,
        0x3f80_0000,
        exponent_f32x16
    ]
);

/// The kernels compiled for one instruction set each: `$name` takes the token of the
/// instruction set and calls `$inner`, compiled for it.
macro_rules! entry {
    ($name:ident, $inner:ident, $token:ty, $t:ty, $v:ty, $features:literal) => {
        #[target_feature(enable = $features)]
        fn $inner<F: BankFormula>(
            token: $token,
            cols: &mut ColumnsMut<'_, $t>,
            block: &mut Block<'_, $t>,
        ) -> Result<Option<usize>, BankError> {
            kernel::run::<$v, F>(token, cols, block)
        }

        fn $name<F: BankFormula>(
            token: $token,
            cols: &mut ColumnsMut<'_, $t>,
            block: &mut Block<'_, $t>,
        ) -> Result<Option<usize>, BankError> {
            // SAFETY: `token` proves that this processor has the features `$inner` is compiled
            // for (the module's safety argument).
            unsafe { $inner::<F>(token, cols, block) }
        }
    };
}

vector!(F64x2, Sse2, f64, __m128d, __m128d, 2,
    add _mm_add_pd, sub _mm_sub_pd, mul _mm_mul_pd, div _mm_div_pd, fma sse2_mul_add_pd,
    set1 _mm_set1_pd, loadu _mm_loadu_pd, storeu _mm_storeu_pd, xor flip_mm_xor_pd);
vector!(F32x4, Sse2, f32, __m128, __m128, 4,
    add _mm_add_ps, sub _mm_sub_ps, mul _mm_mul_ps, div _mm_div_ps, fma sse2_mul_add_ps,
    set1 _mm_set1_ps, loadu _mm_loadu_ps, storeu _mm_storeu_ps, xor flip_mm_xor_ps);
flip!(
    flip_mm_xor_pd,
    __m128d,
    _mm_castpd_si128,
    _mm_castsi128_pd,
    _mm_xor_si128,
    _mm_set1_epi64x,
    i64::MIN
);
flip!(
    flip_mm_xor_ps,
    __m128,
    _mm_castps_si128,
    _mm_castsi128_ps,
    _mm_xor_si128,
    _mm_set1_epi32,
    i32::MIN
);
exponent_f64!(
    exponent_f64x2,
    __m128i,
    __m128d,
    _mm_or_si128,
    _mm_set1_epi64x,
    _mm_sub_pd,
    _mm_castsi128_pd,
    _mm_set1_pd
);
exponent_f32!(
    exponent_f32x4,
    __m128i,
    __m128,
    _mm_sub_epi32,
    _mm_set1_epi32,
    _mm_cvtepi32_ps
);

avx2_simd!(
    F64x2,
    Pair<Pair<F64x2>>,
    f64,
    __m128d,
    2,
    0x3,
    sse2_cmp_pd,
    sse2_blend_pd,
    _mm_and_pd,
    _mm_or_pd,
    _mm_andnot_pd,
    _mm_xor_pd,
    _mm_movemask_pd,
    _mm_set1_pd,
    _mm_max_pd,
    [
        __m128d,
        _mm_castpd_si128,
        _mm_castsi128_pd,
        _mm_add_epi64,
        _mm_set1_epi64x,
        _mm_and_si128,
        _mm_or_si128,
        _mm_slli_epi64,
        _mm_srli_epi64,
        52,
        1023,
        0x000f_ffff_ffff_ffff,
        0x3ff0_0000_0000_0000,
        exponent_f64x2
    ]
);
avx2_simd!(
    F32x4,
    Pair<Pair<F32x4>>,
    f32,
    __m128,
    4,
    0xf,
    sse2_cmp_ps,
    sse2_blend_ps,
    _mm_and_ps,
    _mm_or_ps,
    _mm_andnot_ps,
    _mm_xor_ps,
    _mm_movemask_ps,
    _mm_set1_ps,
    _mm_max_ps,
    [
        __m128,
        _mm_castps_si128,
        _mm_castsi128_ps,
        _mm_add_epi32,
        _mm_set1_epi32,
        _mm_and_si128,
        _mm_or_si128,
        _mm_slli_epi32,
        _mm_srli_epi32,
        23,
        127,
        0x007f_ffff,
        0x3f80_0000,
        exponent_f32x4
    ]
);

/// The vectors a chunk of each kernel is made of (measured: docs/performance.md).
type Avx2F64 = Pair<Pair<F64x4>>;
type Avx2F32 = Pair<F32x8>;
type Avx512F64 = Pair<Pair<F64x8>>;
type Avx512F32 = Pair<Pair<F32x16>>;
type Sse2F64 = Pair<Pair<F64x2>>;
type Sse2F32 = Pair<Pair<F32x4>>;

/// The SSE2 kernels (x86-64's baseline: compiled for it, no `unsafe` call).
fn f64_sse2<F: BankFormula>(
    token: Sse2,
    cols: &mut ColumnsMut<'_, f64>,
    block: &mut Block<'_, f64>,
) -> Result<Option<usize>, BankError> {
    kernel::run::<Sse2F64, F>(token, cols, block)
}

fn f32_sse2<F: BankFormula>(
    token: Sse2,
    cols: &mut ColumnsMut<'_, f32>,
    block: &mut Block<'_, f32>,
) -> Result<Option<usize>, BankError> {
    kernel::run::<Sse2F32, F>(token, cols, block)
}

entry!(f64_avx2, f64_avx2_compiled, Avx2, f64, Avx2F64, "avx2,fma");
entry!(f32_avx2, f32_avx2_compiled, Avx2, f32, Avx2F32, "avx2,fma");
entry!(
    f64_avx512,
    f64_avx512_compiled,
    Avx512,
    f64,
    Avx512F64,
    "avx512f"
);
entry!(
    f32_avx512,
    f32_avx512_compiled,
    Avx512,
    f32,
    Avx512F32,
    "avx512f"
);

/// Runs the kernel of `isa` when this processor has it (`None` otherwise, and for
/// [`Isa::Portable`]).
macro_rules! dispatch {
    ($name:ident, $t:ty, $avx512:ident, $avx2:ident, $sse2:ident) => {
        pub(crate) fn $name<F: BankFormula>(
            isa: Isa,
            cols: &mut ColumnsMut<'_, $t>,
            block: &mut Block<'_, $t>,
        ) -> Option<Result<Option<usize>, BankError>> {
            match isa {
                Isa::Avx512 => Avx512::detect().map(|t| $avx512::<F>(t, cols, block)),
                Isa::Avx2 => Avx2::detect().map(|t| $avx2::<F>(t, cols, block)),
                Isa::Sse2 => Sse2::detect().map(|t| $sse2::<F>(t, cols, block)),
                Isa::Portable => None,
            }
        }
    };
}

dispatch!(run_f64, f64, f64_avx512, f64_avx2, f64_sse2);
dispatch!(run_f32, f32, f32_avx512, f32_avx2, f32_sse2);

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::lanes::{decay, exp, ln};

    /// The i-th point of the golden-ratio sequence in [0, 1) (evenly spread, deterministic).
    fn spread(i: usize) -> f64 {
        (i as f64 * 0.618_033_988_749_894_9).fract()
    }

    /// The worst error of `exp` and `ln` on vector `V` against the platform's, in ulp of the
    /// result (normal results only), over 2e5 arguments.
    fn worst<V: Simd>(
        tk: V::Token,
        to: impl Fn(f64) -> V::T,
        from: impl Fn(V::T) -> f64,
        eps: f64,
    ) -> (f64, f64) {
        let (mut e, mut l) = (0.0_f64, 0.0_f64);
        let n = V::LANES;
        for k in 0..200_000 / n {
            let u = |i: usize, shift: usize| spread(2 * (k * n + i) + shift);
            let xs: std::vec::Vec<V::T> = (0..n).map(|i| to(-80.0 + 160.0 * u(i, 0))).collect();
            let ys: std::vec::Vec<V::T> = (0..n)
                .map(|i| to((60.0 * (2.0 * u(i, 1) - 1.0)).exp()))
                .collect();
            let mut ex = std::vec![to(0.0); n];
            let mut lx = std::vec![to(0.0); n];
            exp(V::load(tk, &xs)).store(&mut ex);
            ln(V::load(tk, &ys)).store(&mut lx);
            for i in 0..n {
                let r = from(xs[i]).exp();
                e = e.max((from(ex[i]) - r).abs() / (r * eps));
                let r = from(ys[i]).ln();
                l = l.max((from(lx[i]) - r).abs() / (r.abs().max(1e-30) * eps));
            }
        }
        (e, l)
    }

    /// The worst absolute error of `decay` on vector `V` against the platform's `exp`, in ulp
    /// of 1, over 2e5 arguments in [−760, 0] (beyond the clamp too), and whether NaN gives a
    /// value below an ulp of 1.
    fn worst_decay<V: Simd>(
        tk: V::Token,
        to: impl Fn(f64) -> V::T,
        from: impl Fn(V::T) -> f64,
        eps: f64,
    ) -> f64
    where
        V::T: Lane,
    {
        let n = V::LANES;
        let mut worst = 0.0_f64;
        for k in 0..200_000 / n {
            // Half the arguments near 0, where e^z is near 1 and every bit counts.
            let z = |i: usize| {
                let u = spread(k * n + i);
                if i.is_multiple_of(2) {
                    -760.0 * u
                } else {
                    -4.0 * u
                }
            };
            let zs: std::vec::Vec<V::T> = (0..n).map(|i| to(z(i))).collect();
            let mut out = std::vec![to(0.0); n];
            decay(V::load(tk, &zs)).store(&mut out);
            for i in 0..n {
                let r = from(zs[i]).exp();
                worst = worst.max((from(out[i]) - r).abs() / eps);
            }
        }
        let mut out = std::vec![to(1.0); n];
        decay(V::load(tk, &std::vec![to(f64::NAN); n])).store(&mut out);
        assert!(
            out.iter().all(|&v| from(v) >= 0.0 && from(v) < eps),
            "decay(NaN)"
        );
        worst
    }

    #[test]
    fn every_vector_decay_is_within_an_ulp_of_1() {
        let sse2 = Sse2::detect().unwrap();
        let f64s = |v: f64| v;
        let f32s = |v: f64| v as f32;
        let f32eps = f64::from(f32::EPSILON);
        let mut all = std::vec![
            (
                "portable f64",
                worst_decay::<f64>((), f64s, f64::from, f64::EPSILON)
            ),
            (
                "portable f32",
                worst_decay::<f32>((), f32s, f64::from, f32eps)
            ),
            (
                "sse2 f64",
                worst_decay::<F64x2>(sse2, f64s, f64::from, f64::EPSILON)
            ),
            (
                "sse2 f32",
                worst_decay::<F32x4>(sse2, f32s, f64::from, f32eps)
            ),
        ];
        if let Some(avx2) = Avx2::detect() {
            all.push((
                "avx2 f64",
                worst_decay::<F64x4>(avx2, f64s, f64::from, f64::EPSILON),
            ));
            all.push((
                "avx2 f32",
                worst_decay::<F32x8>(avx2, f32s, f64::from, f32eps),
            ));
        }
        if let Some(avx512) = Avx512::detect() {
            all.push((
                "avx512 f64",
                worst_decay::<F64x8>(avx512, f64s, f64::from, f64::EPSILON),
            ));
            all.push((
                "avx512 f32",
                worst_decay::<F32x16>(avx512, f32s, f64::from, f32eps),
            ));
        }
        for (what, ulp) in all {
            assert!(ulp <= 1.0, "{what}: decay {ulp} ulp of 1");
        }
    }

    /// `negate_where` on vector `V` against the select it replaces, bit for bit: values of both
    /// signs, zeros, ±∞ and NaN, each lane negated or not by a comparison's mask.
    fn negate_where_is_the_select<V: Simd>(
        tk: V::Token,
        to: impl Fn(f64) -> V::T,
        bits: impl Fn(V::T) -> u64,
    ) {
        let values = [
            1.5,
            -2.25,
            0.0,
            -0.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
            1e-310,
            -7.0,
        ];
        let n = V::LANES;
        for shift in 0..values.len() {
            let a: std::vec::Vec<V::T> = (0..n)
                .map(|i| to(values[(i + shift) % values.len()]))
                .collect();
            // A mask from a comparison: lanes i with i * 3 + shift odd, more or less at random.
            let m: std::vec::Vec<V::T> = (0..n)
                .map(|i| to(if (i * 3 + shift) % 2 == 1 { 1.0 } else { -1.0 }))
                .collect();
            let (a, m) = (V::load(tk, &a), V::c(tk, 0.0).less(V::load(tk, &m)));
            let (mut got, mut want) = (std::vec![to(0.0); n], std::vec![to(0.0); n]);
            a.negate_where(m).store(&mut got);
            V::select(m, -a, a).store(&mut want);
            for i in 0..n {
                assert_eq!(bits(got[i]), bits(want[i]), "lane {i} of {shift}");
            }
        }
    }

    #[test]
    fn every_vector_negates_where_its_mask_says() {
        let sse2 = Sse2::detect().unwrap();
        let (f64s, f32s) = (|v: f64| v, |v: f64| v as f32);
        let (b64, b32) = (f64::to_bits, |v: f32| u64::from(v.to_bits()));
        negate_where_is_the_select::<f64>((), f64s, b64);
        negate_where_is_the_select::<f32>((), f32s, b32);
        negate_where_is_the_select::<F64x2>(sse2, f64s, b64);
        negate_where_is_the_select::<F32x4>(sse2, f32s, b32);
        negate_where_is_the_select::<Pair<F64x2>>(sse2, f64s, b64);
        if let Some(avx2) = Avx2::detect() {
            negate_where_is_the_select::<F64x4>(avx2, f64s, b64);
            negate_where_is_the_select::<F32x8>(avx2, f32s, b32);
        }
        if let Some(avx512) = Avx512::detect() {
            negate_where_is_the_select::<F64x8>(avx512, f64s, b64);
            negate_where_is_the_select::<F32x16>(avx512, f32s, b32);
        }
    }

    #[test]
    fn every_vector_exp_and_ln_match_the_platform() {
        let sse2 = Sse2::detect().unwrap();
        let f64s = |v: f64| v;
        let f32s = |v: f64| v as f32;
        let mut checked = 0;
        let mut check = |(e, l): (f64, f64), what: &str| {
            assert!(e <= 2.0 && l <= 2.0, "{what}: exp {e} ulp, ln {l} ulp");
            checked += 1;
        };
        check(
            worst::<F64x2>(sse2, f64s, f64::from, f64::EPSILON),
            "sse2 f64",
        );
        check(
            worst::<F32x4>(sse2, f32s, f64::from, f64::from(f32::EPSILON)),
            "sse2 f32",
        );
        if let Some(avx2) = Avx2::detect() {
            check(
                worst::<F64x4>(avx2, f64s, f64::from, f64::EPSILON),
                "avx2 f64",
            );
            check(
                worst::<F32x8>(avx2, f32s, f64::from, f64::from(f32::EPSILON)),
                "avx2 f32",
            );
        }
        if let Some(avx512) = Avx512::detect() {
            check(
                worst::<F64x8>(avx512, f64s, f64::from, f64::EPSILON),
                "avx512 f64",
            );
            check(
                worst::<F32x16>(avx512, f32s, f64::from, f64::from(f32::EPSILON)),
                "avx512 f32",
            );
        }
        assert!(checked >= 2);
    }
}
