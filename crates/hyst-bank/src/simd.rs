//! The vector operations the bank's kernels are written in: one trait, [`Simd`], implemented
//! here by `f32` and `f64` themselves (one lane: the portable kernels, which `no_std` builds and
//! other processors run) and by [`Pair`] (two vectors as one: four per chunk in every kernel),
//! and in the bank's `x86` module by SSE2, AVX2 + FMA and AVX-512 vectors. The kernels and the
//! elementary functions ([`crate::lanes`]) are written once against it.

use core::ops::Neg;

pub use crate::vector::Simd;

macro_rules! scalar_simd {
    ($t:ty, $bits:ty, $mant:expr, $bias:expr, $mant_mask:expr, $one_bits:expr) => {
        impl Simd for $t {
            type T = $t;
            type M = bool;
            type Token = ();
            type Tick = Pair<Pair<Self>>;
            const LANES: usize = 1;
            #[inline(always)]
            fn token(self) {}
            #[inline(always)]
            fn splat(_: (), v: $t) -> Self {
                v
            }
            #[inline(always)]
            fn load(_: (), s: &[$t]) -> Self {
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
    type Token = V::Token;
    type Tick = V::Tick;
    const LANES: usize = 2 * V::LANES;
    const EXP_TABLE: bool = V::EXP_TABLE;
    const REGISTERS: u32 = V::REGISTERS;
    #[inline(always)]
    fn token(self) -> V::Token {
        self.0.token()
    }
    #[inline(always)]
    fn splat(token: V::Token, v: V::T) -> Self {
        Pair(V::splat(token, v), V::splat(token, v))
    }
    #[inline(always)]
    fn load(token: V::Token, s: &[V::T]) -> Self {
        Pair(
            V::load(token, s),
            V::load(token, s.get(V::LANES..).unwrap_or(&[])),
        )
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
    fn negate_where(self, m: Self::M) -> Self {
        Pair(self.0.negate_where(m.0), self.1.negate_where(m.1))
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
