//! The two traits the bank's kernels are written against, which name each other: [`Simd`], a
//! vector of lanes (implemented in [`simd`](crate::simd) for one lane of `f32`/`f64` and for
//! [`Pair`](crate::simd::Pair), and in the bank's `x86` module for SSE2, AVX2 + FMA and AVX-512
//! vectors), and [`Lane`], the float type of its lanes with the constants of the elementary
//! functions (implemented for `f32` and `f64` in [`lanes`](crate::lanes), with the functions).

use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::block::RunBlock;
use hyst_core::real::Real;

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
    /// The proof that this processor runs the vector's instructions: a value only run-time
    /// detection gives (the `x86` module's `Sse2`, `Avx2`, `Avx512`), `()` for plain floats.
    /// Every constructor of a vector takes one, and every vector holds its own, so no vector
    /// exists on a processor without its instruction set.
    type Token: Copy;
    /// The chunk a one-tick `step` of the inverse operator visits: two vectors with AVX-512,
    /// four with AVX2, SSE2 and the portable kernel (as blocks do); the direct operator's `step`
    /// runs a block's chunk of four vectors (docs/performance.md, "How the bank is built").
    type Tick: Simd<T = Self::T, Token = Self::Token>;
    /// Lanes per vector.
    const LANES: usize;
    /// The proof this vector holds (see [`Simd::Token`]).
    fn token(self) -> Self::Token;
    /// Every lane `v`.
    fn splat(token: Self::Token, v: Self::T) -> Self;
    /// The first [`Simd::LANES`] values of `s` (`s` must hold that many; zeros otherwise).
    fn load(token: Self::Token, s: &[Self::T]) -> Self;
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
    /// `-self` in the lanes of `m`, `self` elsewhere (a sign flip, exact). This default
    /// selects; the SSE2 and AVX2 vectors, whose mask lanes are all ones, flip the sign bit by
    /// the mask (an `and` and a `xor`: a variable blend is two or three micro-operations on
    /// Intel processors, and SSE2 has none).
    #[inline(always)]
    fn negate_where(self, m: Self::M) -> Self {
        Self::select(m, -self, self)
    }
    /// 2ⁿ for `t` = n + 1.5 · 2^p (p = 52 for f64, 23 for f32: the rounding trick of `exp`
    /// leaves the integer n in the low bits of t), n in [−1022, 1023] (f64) or [−126, 127] (f32).
    fn pow2_shifted(t: Self) -> Self;
    /// (m, k) with self = 2ᵏ · m, m ∈ [1, 2), k as a float, for positive normal values.
    fn split_exponent(self) -> (Self, Self);
    /// The larger of `self` and `b`; `b` where `self` is NaN (x86's `maxpd` with `b` second).
    fn max_or(self, b: Self) -> Self;

    /// Whether `exp` reduces by ln 2 / 8 (f64) or ln 2 / 16 (f32) with a table of 2^(j/8) or
    /// 2^(j/16) ([`Simd::exp2_frac`], [`Simd::scale`]) and a shorter polynomial, instead of by
    /// ln 2 with the long one (AVX-512, whose permutes make the table one instruction).
    const EXP_TABLE: bool = false;

    /// The vector registers the kernel's code may use: 16 (SSE2, AVX2, the portable kernel) or
    /// 32 (AVX-512). With 32, `step`'s visit of the inverse keeps the memory after its update in
    /// registers across `decay`; with 16 it loads it again from the columns after `decay`
    /// (`inverse_visit` in the `step` module).
    const REGISTERS: u32 = 16;

    /// 2^(j / 2^b) for j the low b bits of `t`'s bits, b = [`Lane::EXP_TABLE_BITS`] (the table
    /// reduction of `exp`). This default goes lane by lane through memory; AVX-512 permutes.
    #[inline(always)]
    fn exp2_frac(t: Self) -> Self {
        let zero = <Self::T as Real>::ZERO;
        let table = <Self::T as Lane>::EXP_TABLE;
        let mut a = [zero; 64];
        t.store(&mut a);
        for v in a.iter_mut().take(Self::LANES) {
            let j = v.low_bits() & (table.len() - 1);
            *v = <Self::T as Real>::from_f64(table.get(j).copied().unwrap_or(1.0));
        }
        Self::load(t.token(), &a)
    }

    /// e · 2^⌊n⌋ for every n (|n| ≤ 2000), with overflow to +∞ and underflow to 0. This default
    /// goes lane by lane; AVX-512 has `vscalefpd`.
    #[inline(always)]
    fn scale(e: Self, n: Self) -> Self {
        let zero = <Self::T as Real>::ZERO;
        let (mut a, mut b) = ([zero; 64], [zero; 64]);
        e.store(&mut a);
        n.store(&mut b);
        for (v, k) in a.iter_mut().zip(b).take(Self::LANES) {
            *v = *v
                * num_traits::Float::powi(
                    <Self::T as Real>::from_f64(2.0),
                    num_traits::Float::floor(k).as_f64() as i32,
                );
        }
        Self::load(e.token(), &a)
    }

    /// `exp`'s argument before the reduction: as is by default; clamped to ±1100 (NaN kept)
    /// where [`Simd::exp_tail`] scales by any power of two.
    #[inline(always)]
    fn exp_arg(x: Self) -> Self {
        x
    }

    /// The end of `exp`: e · 2ⁿ for the reduced e ∈ [√½, √2], n = t − 1.5 · 2^p (see
    /// [`Simd::pow2_shifted`]), with the ends of the range decided on the argument x: 0 below
    /// [`Lane::EXP_LO`], +∞ above [`Lane::EXP_HI`] (NaN stays NaN).
    #[inline(always)]
    fn exp_tail(e: Self, t: Self, n: Self, x: Self) -> Self {
        let _ = n;
        let k = x.token();
        let y = e * Self::pow2_shifted(t);
        let y = Self::select(
            x.less(Self::splat(k, <Self::T as Lane>::EXP_LO)),
            Self::c(k, 0.0),
            y,
        );
        Self::select(
            Self::splat(k, <Self::T as Lane>::EXP_HI).less(x),
            Self::splat(k, <Self::T as num_traits::Float>::infinity()),
            y,
        )
    }

    /// A constant from an `f64` literal.
    #[inline(always)]
    fn c(token: Self::Token, v: f64) -> Self {
        Self::splat(token, <Self::T as Real>::from_f64(v))
    }
}

/// A float type the bank runs: `f32` or `f64`, with the constants of its elementary functions.
pub trait Lane: Real + Simd<T = Self, M = bool> + RunBlock {
    /// Below this y, the five-term series of ω in t = eʸ (`omega_series`) is exact to
    /// rounding (its first omitted term, 10.8 t⁶, is below half an ulp of t).
    const OMEGA_SERIES: Self;
    /// Below this y, ω(y) = t − t² (t = eʸ) to within an ulp (used by
    /// [`omega`](crate::lanes::omega)).
    const OMEGA_SMALL: Self;
    /// One Fritsch–Shafer–Crowley step from the bank's start is accepted when the residual
    /// |y − w − ln w| of the start is below this (the step's fourth order then leaves less
    /// than an ulp); otherwise [`omega`](crate::lanes::omega) evaluates the lane from scratch.
    const RESIDUAL_OK: Self;
    /// Above this `exp` returns +∞.
    const EXP_HI: Self;
    /// Below this `exp` returns 0.
    const EXP_LO: Self;
    /// 1.5 · 2^(mantissa bits): adding it rounds to an integer, left in the low bits.
    const SHIFT: Self;
    /// ln 2 in two parts for `exp`'s reduction (high part with trailing zero bits).
    const EXP_LN2: (f64, f64);
    /// ln 2 in two parts for `ln`.
    const LOG_LN2: (f64, f64);
    /// How many of [`INV_FACTORIALS`](crate::lanes::INV_FACTORIALS) `exp` uses:
    /// e^r = 1 + r + r² Σ cᵢ rⁱ, |r| ≤ ln 2 / 2.
    const EXP_TERMS: usize;
    /// fdlibm's odd-indexed (Lg1, Lg3, …) and even-indexed (Lg2, Lg4, …) log coefficients.
    const LOG_POLY: (&'static [f64], &'static [f64]);
    /// The bits b of `exp`'s table reduction (see [`Simd::EXP_TABLE`]): 3 for f64, 4 for f32.
    const EXP_TABLE_BITS: u32;
    /// 2^(j / 2^b), j = 0 … 2^b − 1, rounded to this type.
    const EXP_TABLE: &'static [f64];
    /// How many of [`INV_FACTORIALS`](crate::lanes::INV_FACTORIALS) the table reduction uses
    /// (|r| ≤ ln 2 / 2^(b+1)).
    const EXP_TABLE_TERMS: usize;
    /// The bank's `decay` raises its arguments to this (e^z is then at least the smallest normal
    /// float times 2, so 2ⁿ is built from its bits without a range check).
    const DECAY_MIN: Self;
    /// The bank's `decay` polynomial: e^r ≈ Σ cᵢ rⁱ on |r| ≤ ln 2 / 2, interpolated at the
    /// Chebyshev nodes of that interval (degree 11 for f64, 6 for f32; error with the
    /// coefficients rounded to the type: 0.15 ulp for f64, 0.34 ulp for f32;
    /// `scripts/decay-coefficients` computes them).
    const DECAY_POLY: &'static [f64];
    /// u + 2u², u the unit roundoff (2⁻⁵³, 2⁻²⁴): for a normal v, v − |v| · this rounds to the
    /// next float towards −∞ and v + |v| · this to the next towards +∞ (one rounding, by FMA: the
    /// product is above half the spacing next to v and below one and a half), the vector form of
    /// [`Lane::next_below`] / [`Lane::next_above`] that the kernel's band clamp uses.
    const ONE_STEP: Self;
    /// The low bits of the value's representation (the table index of `exp`).
    fn low_bits(self) -> usize;
    /// The next float towards −∞ (finite values).
    fn next_below(self) -> Self;
    /// The next float towards +∞ (finite values).
    fn next_above(self) -> Self;

    /// eˣ, branch-free (see the [`lanes`](crate::lanes) module documentation for its range and
    /// error).
    fn exp_l(self) -> Self;
    /// ln x for normal positive x, branch-free (−∞ at 0, +∞ at +∞, NaN below 0 and for NaN).
    fn ln_l(self) -> Self;
}
