//! Branch-free `exp`, `ln` and Wright ω for the channel bank: straight-line code (selects, no
//! branches, no calls into libm) that the compiler vectorises across channels.
//!
//! - `exp`: Cody–Waite reduction x = n ln 2 + r, |r| ≤ ln 2 / 2, a degree-13 (f64) or degree-7
//!   (f32) Taylor polynomial evaluated by Estrin's scheme, and 2ⁿ built from its bits in two factors (so subnormal results
//!   and overflow to +∞ come out right without a branch). Error ≤ 2 ulp (tested against the
//!   platform's `exp` in `tests/bank.rs`).
//! - `ln`: fdlibm's `e_log.c` / `e_logf.c` (x = 2ᵏ m, √½ ≤ m < √2, s = f / (2 + f), minimax
//!   polynomial in s²); error ≤ 1 ulp for normal positive x.
//! - ω(y) = W0(eʸ), the solution of ω + ln ω = y: for y < −20 (f64; −10 for f32) t − t² with
//!   t = eʸ (the next term, 1.5 t³, is below an ulp); elsewhere Winitzki's start
//!   L (1 − ln(1 + L) / (2 + L)), L = ln(1 + eʸ), refined by two fourth-order
//!   Fritsch–Shafer–Crowley steps, as the scalar [`crate::lambert::omega`] does for large y.
//!
//! # References
//! - W. J. Cody, W. Waite, *Software Manual for the Elementary Functions* (1980).
//! - Sun Microsystems, fdlibm 5.3, `e_log.c`, `e_logf.c`.
//! - S. Winitzki, "Uniform approximations for transcendental functions", ICCSA 2003.
//! - F. N. Fritsch, R. E. Shafer, W. P. Crowley, Comm. ACM 16 (1973), Algorithm 443.

use crate::Real;

/// A float type the bank vectorises: `f64` (8 lanes per chunk) or `f32` (16 lanes).
pub trait Lane: Real + super::RunBlock {
    /// Channels per chunk: one AVX-512 register (8 × f64, 16 × f32), two AVX2 registers.
    const LANES: usize;
    /// Below this y, ω(y) = t − t² with t = eʸ to within an ulp.
    const OMEGA_SMALL: Self;
    /// A first FSC step from the previous sample's ω is accepted when its residual
    /// |y − w − ln w| is below this (the step's fourth order then leaves less than an ulp).
    const RESIDUAL_OK: Self;
    /// `exp`, branch-free.
    fn exp_l(self) -> Self;
    /// `if m { a } else { b }` as a bit blend. Written as a plain `if` over values loaded from
    /// memory, the compiler turns the choice into a choice of addresses and stops vectorising
    /// the loop; the blend keeps it a vector operation.
    fn select(m: bool, a: Self, b: Self) -> Self;
    /// `ln` for normal positive values, branch-free (−∞ at 0, NaN below).
    fn ln_l(self) -> Self;
}

/// 1.5 · 2⁵²: adding it rounds an f64 of magnitude < 2⁵¹ to an integer (ties to even).
const SHIFT_F64: f64 = 6_755_399_441_055_744.0;
/// 1.5 · 2²³, the same for f32.
const SHIFT_F32: f32 = 12_582_912.0;

/// 2ⁿ for −1022 ≤ n ≤ 1023 from its bits.
#[inline(always)]
fn pow2_f64(n: i64) -> f64 {
    f64::from_bits(((n + 1023) as u64) << 52)
}

/// 2ⁿ for −126 ≤ n ≤ 127 from its bits.
#[inline(always)]
fn pow2_f32(n: i32) -> f32 {
    f32::from_bits(((n + 127) as u32) << 23)
}

impl Lane for f64 {
    const LANES: usize = 8;

    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        let mask = u64::from(m).wrapping_neg();
        f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
    }
    const OMEGA_SMALL: Self = -20.0;
    const RESIDUAL_OK: Self = 1e-4;

    #[inline(always)]
    fn exp_l(self) -> Self {
        const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-1;
        const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;
        const INV_LN2: f64 = core::f64::consts::LOG2_E;
        // Beyond these e^x is +∞ or rounds to 0; clamping keeps n in the range of the two
        // factors below (NaN stays NaN through the arithmetic: `max`/`min` are not used on it).
        let x = if self > 709.8 {
            709.8
        } else if self < -745.2 {
            -745.2
        } else {
            self
        };
        let t = x * INV_LN2 + SHIFT_F64;
        let n = t - SHIFT_F64;
        let r = (x - n * LN2_HI) - n * LN2_LO;
        // e^r = 1 + r + r² P(r), P the Taylor coefficients 1/k!, k = 2 … 13, by Estrin's
        // scheme (four levels instead of a chain of eleven: the loop is latency-bound).
        let r2 = r * r;
        let r4 = r2 * r2;
        let p01 = 1.0 / 2.0 + r * (1.0 / 6.0);
        let p23 = 1.0 / 24.0 + r * (1.0 / 120.0);
        let p45 = 1.0 / 720.0 + r * (1.0 / 5_040.0);
        let p67 = 1.0 / 40_320.0 + r * (1.0 / 362_880.0);
        let p89 = 1.0 / 3_628_800.0 + r * (1.0 / 39_916_800.0);
        let p1011 = 1.0 / 479_001_600.0 + r * (1.0 / 6_227_020_800.0);
        let q0 = p01 + r2 * p23;
        let q1 = p45 + r2 * p67;
        let q2 = p89 + r2 * p1011;
        let p = q0 + r4 * (q1 + r4 * q2);
        let e = 1.0 + (r + r2 * p);
        // n sits in the low bits of t; split 2ⁿ in two factors so that n ∈ [−1075, 1024]
        // needs no branch (subnormal results, overflow to +∞).
        let ni = (t.to_bits() as i64).wrapping_sub(SHIFT_F64.to_bits() as i64);
        let n1 = ni >> 1;
        e * pow2_f64(n1) * pow2_f64(ni - n1)
    }

    #[inline(always)]
    fn ln_l(self) -> Self {
        const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-1;
        const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;
        const LG1: f64 = 6.666_666_666_666_735_130e-1;
        const LG2: f64 = 3.999_999_999_940_941_908e-1;
        const LG3: f64 = 2.857_142_874_366_239_149e-1;
        const LG4: f64 = 2.222_219_843_214_978_396e-1;
        const LG5: f64 = 1.818_357_216_161_805_012e-1;
        const LG6: f64 = 1.531_383_769_920_937_332e-1;
        const LG7: f64 = 1.479_819_860_511_658_591e-1;
        let bits = self.to_bits();
        let exponent = ((bits >> 52) & 0x7ff) as i64 - 1023;
        let m = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
        let big = m > core::f64::consts::SQRT_2;
        let m = if big { 0.5 * m } else { m };
        let k = (exponent + i64::from(big)) as f64;
        let f = m - 1.0;
        let hfsq = 0.5 * f * f;
        let s = f / (2.0 + f);
        let z = s * s;
        let w = z * z;
        let t1 = w * (LG2 + w * (LG4 + w * LG6));
        let t2 = z * (LG1 + w * (LG3 + w * (LG5 + w * LG7)));
        let r = t2 + t1;
        let ln = k * LN2_HI - ((hfsq - (s * (hfsq + r) + k * LN2_LO)) - f);
        if self == 0.0 {
            f64::NEG_INFINITY
        } else if self > 0.0 && self < f64::INFINITY {
            ln
        } else if self == f64::INFINITY {
            self
        } else {
            f64::NAN
        }
    }
}

impl Lane for f32 {
    const LANES: usize = 16;

    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        let mask = u32::from(m).wrapping_neg();
        f32::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
    }
    const OMEGA_SMALL: Self = -10.0;
    const RESIDUAL_OK: Self = 1e-2;

    #[inline(always)]
    fn exp_l(self) -> Self {
        const LN2_HI: f32 = 6.931_457_5e-1;
        const LN2_LO: f32 = 1.428_606_8e-6;
        const INV_LN2: f32 = core::f32::consts::LOG2_E;
        let x = if self > 88.8 {
            88.8
        } else if self < -104.0 {
            -104.0
        } else {
            self
        };
        let t = x * INV_LN2 + SHIFT_F32;
        let n = t - SHIFT_F32;
        let r = (x - n * LN2_HI) - n * LN2_LO;
        // e^r = 1 + r + r² P(r), P of degree 5 (1/k!, k = 2 … 7) by Estrin's scheme.
        let r2 = r * r;
        let r4 = r2 * r2;
        let p01 = 1.0 / 2.0 + r * (1.0 / 6.0);
        let p23 = 1.0 / 24.0 + r * (1.0 / 120.0);
        let p45 = 1.0 / 720.0 + r * (1.0 / 5_040.0);
        let p = p01 + r2 * p23 + r4 * p45;
        let e = 1.0 + (r + r2 * p);
        let ni = (t.to_bits() as i32).wrapping_sub(SHIFT_F32.to_bits() as i32);
        let n1 = ni >> 1;
        e * pow2_f32(n1) * pow2_f32(ni - n1)
    }

    #[inline(always)]
    fn ln_l(self) -> Self {
        const LN2_HI: f32 = 6.931_381_2e-1;
        const LN2_LO: f32 = 9.058_001e-6;
        const LG1: f32 = 0.666_666_626_93;
        const LG2: f32 = 0.400_009_721_52;
        const LG3: f32 = 0.284_987_866_88;
        const LG4: f32 = 0.242_790_788_41;
        let bits = self.to_bits();
        let exponent = ((bits >> 23) & 0xff) as i32 - 127;
        let m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
        let big = m > core::f32::consts::SQRT_2;
        let m = if big { 0.5 * m } else { m };
        let k = (exponent + i32::from(big)) as f32;
        let f = m - 1.0;
        let hfsq = 0.5 * f * f;
        let s = f / (2.0 + f);
        let z = s * s;
        let w = z * z;
        let t1 = w * (LG2 + w * LG4);
        let t2 = z * (LG1 + w * LG3);
        let r = t2 + t1;
        let ln = k * LN2_HI - ((hfsq - (s * (hfsq + r) + k * LN2_LO)) - f);
        if self == 0.0 {
            f32::NEG_INFINITY
        } else if self > 0.0 && self < f32::INFINITY {
            ln
        } else if self == f32::INFINITY {
            self
        } else {
            f32::NAN
        }
    }
}

/// Chebyshev fits of ω(y) (relative error ≤ 2.2e-5 on [−3, 3], ≤ 7.2e-6 on [3, 12]), in powers
/// of x = y / 3 and x = (2 y − 15) / 9; fitted with numpy's `chebfit` (weights 1/ω) to ω from
/// Newton's iteration, then converted to the power basis.
const OMEGA_MID: [f64; 11] = [
    0.567_139_760_733_183_5,
    1.085_692_254_275_998_8,
    0.663_337_199_796_251_4,
    -0.036_069_530_211_063_67,
    -0.134_939_132_726_527_94,
    0.053_925_896_915_444_714,
    0.043_377_952_362_204_35,
    -0.032_096_626_929_540_226,
    -0.015_125_614_632_217_078,
    0.008_803_468_978_835_438,
    0.003_942_879_691_216_917,
];
const OMEGA_HIGH: [f64; 7] = [
    5.750_673_737_084_118,
    3.833_336_838_233_287_3,
    0.189_444_865_663_644_5,
    -0.064_806_214_977_238_57,
    0.022_966_849_068_361_776,
    -0.009_828_198_754_520_248,
    0.003_541_166_858_665_075_8,
];

#[inline(always)]
fn horner<T: Lane>(x: T, coefficients: &[f64]) -> T {
    let mut p = T::zero();
    for c in coefficients.iter().rev() {
        p = p * x + T::from_f64(*c);
    }
    p
}

/// A start for ω(y) within 2.2e-5 (relative) for every y, without iteration: the series
/// t − t² + 1.5 t³ − 8/3 t⁴ + 125/24 t⁵ in t = eʸ below −3 (`t` is eʸ, passed in), the fits
/// above on [−3, 12], and the asymptotic expansion y − L + (L / y)(1 + (L − 2) / (2y) +
/// (2L² − 9L + 6) / (6y²)), L = ln y, above 12 (`ln_y` is ln y, passed in; only read there).
/// One FSC step from it is within an ulp.
#[inline(always)]
pub fn omega_start<T: Lane>(y: T, t: T, ln_y: T) -> T {
    let one = T::one();
    let c = T::from_f64;
    let series = t * (one - t * (one - t * (c(1.5) - t * (c(8.0 / 3.0) - t * c(125.0 / 24.0)))));
    let mid = horner(y * c(1.0 / 3.0), &OMEGA_MID);
    let high = horner(y * c(2.0 / 9.0) - c(15.0 / 9.0), &OMEGA_HIGH);
    let iy = one / y;
    let asymptotic = y - ln_y
        + ln_y
            * iy
            * (one
                + iy * (c(0.5) * (ln_y - c(2.0))
                    + iy * ((c(2.0) * ln_y - c(9.0)) * ln_y + c(6.0)) * c(1.0 / 6.0)));
    T::select(
        y < c(-3.0),
        series,
        T::select(y <= c(3.0), mid, T::select(y <= c(12.0), high, asymptotic)),
    )
}

/// One Fritsch–Shafer–Crowley step for ω + ln ω = y from w (fourth order), with the residual
/// r = y − w − ln w it started from. Two divisions.
#[inline(always)]
pub fn fsc_step<T: Lane>(w: T, y: T) -> (T, T) {
    let one = T::one();
    let r = y - w - w.ln_l();
    let iq = one / (one + w);
    let rq = r * iq;
    let t = one + T::from_f64(2.0 / 3.0) * rq;
    let num = t - T::from_f64(0.5) * rq * iq;
    let den = t - rq * iq;
    (w * (one + rq * (num / den)), r)
}

/// ω(y) = W0(eʸ) from scratch (Winitzki's start and two FSC steps; the small-y series below
/// [`Lane::OMEGA_SMALL`]). ω(−∞) = 0.
#[inline(always)]
pub fn omega<T: Lane>(y: T) -> T {
    let one = T::one();
    let zero = T::zero();
    let t = y.exp_l();
    // L = ln(1 + eʸ) without overflow: max(y, 0) + ln(1 + e^(−|y|)).
    let neg_abs = if y > zero { -y } else { y };
    let l = (if y > zero { y } else { zero }) + (one + neg_abs.exp_l()).ln_l();
    let mut w = l * (one - (one + l).ln_l() / (T::from_f64(2.0) + l));
    for _ in 0..2 {
        w = fsc_step(w, y).0;
    }
    if y < T::OMEGA_SMALL {
        t - t * t
    } else {
        w
    }
}
