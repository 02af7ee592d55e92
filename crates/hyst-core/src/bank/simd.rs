//! The vector operations the bank's kernels are written in: one trait, [`Simd`], implemented by
//! `f32` and `f64` themselves (one lane: the portable kernels, which `no_std` builds and other
//! processors run), by [`Pair`] (two vectors as one: four per chunk in every kernel) and, in
//! the bank's `x86` module, by SSE2, AVX2 + FMA and AVX-512 vectors. The kernels and the
//! elementary functions ([`super::lanes`]) are written once against it.

use core::ops::{Add, Div, Mul, Neg, Sub};

use super::lanes::Lane;
use crate::Real as _;

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
    /// The chunk a one-tick `step` runs on: one vector for AVX-512 f64, two for AVX-512 f32 and
    /// AVX2, four for SSE2 and the portable kernel (as blocks do). Fewer than a block's four,
    /// because `step` holds the state of two chunks in registers at once (it loads the next
    /// chunk before storing this one; measured: docs/performance.md, "Where a tick of `step`
    /// goes").
    type Tick: Simd<T = Self::T>;
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
    /// The larger of `self` and `b`; `b` where `self` is NaN (x86's `maxpd` with `b` second).
    fn max_or(self, b: Self) -> Self;

    /// Whether `exp` reduces by ln 2 / 8 (f64) or ln 2 / 16 (f32) with a table of 2^(j/8) or
    /// 2^(j/16) ([`Simd::exp2_frac`], [`Simd::scale`]) and a shorter polynomial, instead of by
    /// ln 2 with the long one (AVX-512, whose permutes make the table one instruction).
    const EXP_TABLE: bool = false;

    /// 2^(j / 2^b) for j the low b bits of `t`'s bits, b = [`Lane::EXP_TABLE_BITS`] (the table
    /// reduction of `exp`). This default goes lane by lane through memory; AVX-512 permutes.
    #[inline(always)]
    fn exp2_frac(t: Self) -> Self {
        let zero = <Self::T as crate::Real>::ZERO;
        let table = <Self::T as Lane>::EXP_TABLE;
        let mut a = [zero; 64];
        t.store(&mut a);
        for v in a.iter_mut().take(Self::LANES) {
            let j = v.low_bits() & (table.len() - 1);
            *v = <Self::T as crate::Real>::from_f64(table.get(j).copied().unwrap_or(1.0));
        }
        Self::load(&a)
    }

    /// e · 2^⌊n⌋ for every n (|n| ≤ 2000), with overflow to +∞ and underflow to 0. This default
    /// goes lane by lane; AVX-512 has `vscalefpd`.
    #[inline(always)]
    fn scale(e: Self, n: Self) -> Self {
        let zero = <Self::T as crate::Real>::ZERO;
        let (mut a, mut b) = ([zero; 64], [zero; 64]);
        e.store(&mut a);
        n.store(&mut b);
        for (v, k) in a.iter_mut().zip(b).take(Self::LANES) {
            *v = *v
                * num_traits::Float::powi(
                    <Self::T as crate::Real>::from_f64(2.0),
                    num_traits::Float::floor(k).as_f64() as i32,
                );
        }
        Self::load(&a)
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
        let y = e * Self::pow2_shifted(t);
        let y = Self::select(
            x.less(Self::splat(<Self::T as Lane>::EXP_LO)),
            Self::c(0.0),
            y,
        );
        Self::select(
            Self::splat(<Self::T as Lane>::EXP_HI).less(x),
            Self::splat(<Self::T as num_traits::Float>::infinity()),
            y,
        )
    }

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
            type Tick = Pair<Pair<Self>>;
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
            fn max_or(self, b: Self) -> Self {
                if self > b {
                    self
                } else {
                    b
                }
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

/// Two vectors as one of twice the lanes: every operation is done on both halves, so a chunk
/// carries two independent dependency chains that the processor overlaps (a tick's `exp` is a
/// chain of about twenty dependent operations; one chunk alone leaves the pipes idle).
#[derive(Clone, Copy)]
pub struct Pair<V>(pub V, pub V);

macro_rules! pair_op {
    ($tr:ident, $f:ident) => {
        impl<V: Simd> core::ops::$tr for Pair<V> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, b: Self) -> Self {
                Pair(self.0.$f(b.0), self.1.$f(b.1))
            }
        }
    };
}
pair_op!(Add, add);
pair_op!(Sub, sub);
pair_op!(Mul, mul);
pair_op!(Div, div);

impl<V: Simd> Neg for Pair<V> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Pair(-self.0, -self.1)
    }
}

impl<V: Simd> Simd for Pair<V> {
    type T = V::T;
    type M = (V::M, V::M);
    type Tick = V::Tick;
    const LANES: usize = 2 * V::LANES;
    const EXP_TABLE: bool = V::EXP_TABLE;
    #[inline(always)]
    fn splat(v: V::T) -> Self {
        Pair(V::splat(v), V::splat(v))
    }
    #[inline(always)]
    fn load(s: &[V::T]) -> Self {
        Pair(V::load(s), V::load(s.get(V::LANES..).unwrap_or(&[])))
    }
    #[inline(always)]
    fn store(self, s: &mut [V::T]) {
        self.0.store(s);
        if let Some(rest) = s.get_mut(V::LANES..) {
            self.1.store(rest);
        }
    }
    #[inline(always)]
    fn fma(self, b: Self, c: Self) -> Self {
        Pair(self.0.fma(b.0, c.0), self.1.fma(b.1, c.1))
    }
    #[inline(always)]
    fn less(self, b: Self) -> Self::M {
        (self.0.less(b.0), self.1.less(b.1))
    }
    #[inline(always)]
    fn less_eq(self, b: Self) -> Self::M {
        (self.0.less_eq(b.0), self.1.less_eq(b.1))
    }
    #[inline(always)]
    fn equal(self, b: Self) -> Self::M {
        (self.0.equal(b.0), self.1.equal(b.1))
    }
    #[inline(always)]
    fn select(m: Self::M, a: Self, b: Self) -> Self {
        Pair(V::select(m.0, a.0, b.0), V::select(m.1, a.1, b.1))
    }
    #[inline(always)]
    fn and(a: Self::M, b: Self::M) -> Self::M {
        (V::and(a.0, b.0), V::and(a.1, b.1))
    }
    #[inline(always)]
    fn or(a: Self::M, b: Self::M) -> Self::M {
        (V::or(a.0, b.0), V::or(a.1, b.1))
    }
    #[inline(always)]
    fn and_not(a: Self::M, b: Self::M) -> Self::M {
        (V::and_not(a.0, b.0), V::and_not(a.1, b.1))
    }
    #[inline(always)]
    fn any(m: Self::M) -> bool {
        V::any(m.0) | V::any(m.1)
    }
    #[inline(always)]
    fn all(m: Self::M) -> bool {
        V::all(m.0) & V::all(m.1)
    }
    #[inline(always)]
    fn magnitude(self) -> Self {
        Pair(self.0.magnitude(), self.1.magnitude())
    }
    #[inline(always)]
    fn pow2_shifted(t: Self) -> Self {
        Pair(V::pow2_shifted(t.0), V::pow2_shifted(t.1))
    }
    #[inline(always)]
    fn max_or(self, b: Self) -> Self {
        Pair(self.0.max_or(b.0), self.1.max_or(b.1))
    }
    #[inline(always)]
    fn split_exponent(self) -> (Self, Self) {
        let (a, b) = (self.0.split_exponent(), self.1.split_exponent());
        (Pair(a.0, b.0), Pair(a.1, b.1))
    }
    #[inline(always)]
    fn exp2_frac(t: Self) -> Self {
        Pair(V::exp2_frac(t.0), V::exp2_frac(t.1))
    }
    #[inline(always)]
    fn scale(e: Self, n: Self) -> Self {
        Pair(V::scale(e.0, n.0), V::scale(e.1, n.1))
    }
    #[inline(always)]
    fn exp_arg(x: Self) -> Self {
        Pair(V::exp_arg(x.0), V::exp_arg(x.1))
    }
    #[inline(always)]
    fn exp_tail(e: Self, t: Self, n: Self, x: Self) -> Self {
        Pair(
            V::exp_tail(e.0, t.0, n.0, x.0),
            V::exp_tail(e.1, t.1, n.1, x.1),
        )
    }
}
