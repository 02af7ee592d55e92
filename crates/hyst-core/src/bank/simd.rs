//! The vector operations the bank's kernels are written in: one trait, [`Simd`], implemented by
//! `f32` and `f64` themselves (one lane: the portable kernels, also those of `no_std` builds and
//! of x86-64 processors without AVX2) and, in [`super::x86`], by AVX2 + FMA and AVX-512 vectors.
//! The kernels and the elementary functions ([`super::lanes`]) are written once against it.

use core::ops::{Add, Div, Mul, Neg, Sub};

use super::lanes::Lane;

/// A vector of `LANES` floats of type `T` and its comparison mask.
///
/// Every operation acts lane by lane; `fma` is fused (one rounding) where the instruction
/// set has FMA (the AVX2 and AVX-512 vectors) and a multiply then an add elsewhere.
pub trait Simd:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The lane type.
    type T: Lane;
    /// A lane mask (the result of a comparison).
    type M: Copy;
    /// Lanes per vector.
    const LANES: usize;
    /// Every lane `v`.
    fn splat(v: Self::T) -> Self;
    /// The first [`Simd::LANES`] values of `s` (`s` must hold that many; zeros otherwise).
    fn load(s: &[Self::T]) -> Self;
    /// Writes the lanes to the first [`Simd::LANES`] places of `s` (nothing if it is shorter).
    fn store(self, s: &mut [Self::T]);
    /// `self · b + c`.
    fn fma(self, b: Self, c: Self) -> Self;
    /// `self < b` (false when either is NaN).
    fn less(self, b: Self) -> Self::M;
    /// `self <= b` (false when either is NaN).
    fn less_eq(self, b: Self) -> Self::M;
    /// `self == b`.
    fn equal(self, b: Self) -> Self::M;
    /// `a` where `m` is set, else `b`.
    fn select(m: Self::M, a: Self, b: Self) -> Self;
    /// Both masks.
    fn and(a: Self::M, b: Self::M) -> Self::M;
    /// Either mask.
    fn or(a: Self::M, b: Self::M) -> Self::M;
    /// Lanes where `a` is set and `b` is not.
    fn and_not(a: Self::M, b: Self::M) -> Self::M;
    /// Whether any lane of `m` is set.
    fn any(m: Self::M) -> bool;
    /// Whether every lane of `m` is set.
    fn all(m: Self::M) -> bool;
    /// |self|.
    fn magnitude(self) -> Self;
    /// 2ⁿ for `t` = n + 1.5 · 2^p (p = 52 for f64, 23 for f32: the rounding trick of `exp`
    /// leaves the integer n in the low bits of t), n in [−1022, 1023] (f64) or [−126, 127] (f32).
    fn pow2_shifted(t: Self) -> Self;
    /// (m, k) with self = 2ᵏ · m, m ∈ [1, 2), k as a float, for positive normal values.
    fn split_exponent(self) -> (Self, Self);

    /// A constant from an `f64` literal.
    #[inline(always)]
    fn c(v: f64) -> Self {
        Self::splat(<Self::T as crate::Real>::from_f64(v))
    }
}

macro_rules! scalar_simd {
    ($t:ty, $bits:ty, $mant:expr, $bias:expr, $mant_mask:expr, $one_bits:expr) => {
        impl Simd for $t {
            type T = $t;
            type M = bool;
            const LANES: usize = 1;
            #[inline(always)]
            fn splat(v: $t) -> Self {
                v
            }
            #[inline(always)]
            fn load(s: &[$t]) -> Self {
                s.first().copied().unwrap_or(0.0)
            }
            #[inline(always)]
            fn store(self, s: &mut [$t]) {
                if let Some(slot) = s.first_mut() {
                    *slot = self;
                }
            }
            #[inline(always)]
            fn fma(self, b: Self, c: Self) -> Self {
                self * b + c
            }
            #[inline(always)]
            fn less(self, b: Self) -> bool {
                self < b
            }
            #[inline(always)]
            fn less_eq(self, b: Self) -> bool {
                self <= b
            }
            #[inline(always)]
            fn equal(self, b: Self) -> bool {
                self == b
            }
            #[inline(always)]
            fn select(m: bool, a: Self, b: Self) -> Self {
                if m {
                    a
                } else {
                    b
                }
            }
            #[inline(always)]
            fn and(a: bool, b: bool) -> bool {
                a & b
            }
            #[inline(always)]
            fn or(a: bool, b: bool) -> bool {
                a | b
            }
            #[inline(always)]
            fn and_not(a: bool, b: bool) -> bool {
                a & !b
            }
            #[inline(always)]
            fn any(m: bool) -> bool {
                m
            }
            #[inline(always)]
            fn all(m: bool) -> bool {
                m
            }
            #[inline(always)]
            fn magnitude(self) -> Self {
                <$t>::from_bits(self.to_bits() & (<$bits>::MAX >> 1))
            }
            #[inline(always)]
            fn pow2_shifted(t: Self) -> Self {
                <$t>::from_bits(t.to_bits().wrapping_add($bias) << $mant)
            }
            #[inline(always)]
            fn split_exponent(self) -> (Self, Self) {
                let bits = self.to_bits();
                let k = (bits >> $mant) as i64 - $bias as i64;
                let m = <$t>::from_bits((bits & $mant_mask) | $one_bits);
                (m, k as $t)
            }
        }
    };
}

scalar_simd!(
    f64,
    u64,
    52,
    1023_u64,
    0x000f_ffff_ffff_ffff_u64,
    0x3ff0_0000_0000_0000_u64
);
scalar_simd!(f32, u32, 23, 127_u32, 0x007f_ffff_u32, 0x3f80_0000_u32);
