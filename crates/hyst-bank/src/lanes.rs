//! Branch-free `exp`, `ln` and Wright ω for the channel bank, written once for every vector
//! width ([`Simd`]: one lane of `f32`/`f64`, SSE2, AVX2, AVX-512) as straight-line code: selects, no
//! branches per lane, no calls into libm.
//!
//! - `exp`: Cody–Waite reduction x = n ln 2 + r, |r| ≤ ln 2 / 2, the Taylor polynomial of e^r
//!   to degree 13 (f64) or 7 (f32) evaluated in pairs (c₂ᵢ + c₂ᵢ₊₁ r, then Horner in r²), and
//!   2ⁿ built from its bits; results below the smallest normal float (x < −708.39 for f64,
//!   −87.33 for f32) are 0, and above 709.43 (f64) / 88.37 (f32) +∞, a factor of at most 2
//!   before the float range ends (the bank's callers hand such samples to the scalar operator).
//!   AVX-512 reduces by ln 2 / 8 (f64) or ln 2 / 16 (f32) instead, with the table of 2^(j/8) or
//!   2^(j/16) in one register (one permute), degree 8 or 4, and `vscalefpd`, which gets
//!   subnormal results and the end of the range right. Error ≤ 2 ulp for normal results
//!   (tested against the platform's `exp` in `tests/bank.rs` and, per kernel, in the unit tests
//!   of the `x86` module).
//! - `decay`: e^z for z ≤ 0 to an absolute ulp of 1, all eq. (4) needs of its e^(−k2 ũd): the
//!   argument raised to the float range's end, one-constant ln 2 reduction, an interpolant at
//!   the Chebyshev nodes (degree 11 / 6), 2ⁿ from its bits, no range selects (AVX-512: `exp`).
//! - `ln`: fdlibm's `e_log.c` / `e_logf.c` (x = 2ᵏ m, √½ ≤ m < √2, s = f / (2 + f), minimax
//!   polynomial in s²); error ≤ 1 ulp for normal positive x.
//! - ω(y) = W0(eʸ), the solution of ω + ln ω = y: see [`omega`] and the direct kernel.
//!
//! The functions are `#[inline(always)]` only when optimising (see the chunk module: debug
//! builds' stack).
//!
//! # References
//! - W. J. Cody, W. Waite, *Software Manual for the Elementary Functions* (1980).
//! - Sun Microsystems, fdlibm 5.3, `e_log.c`, `e_logf.c`.
//! - S. Winitzki, "Uniform approximations for transcendental functions", ICCSA 2003.
//! - F. N. Fritsch, R. E. Shafer, W. P. Crowley, Comm. ACM 16 (1973), Algorithm 443.

pub use crate::vector::Lane;
use crate::vector::Simd;

/// 1/k!, k = 2 … 13: the Taylor coefficients of (e^r − 1 − r) / r².
pub const INV_FACTORIALS: [f64; 12] = [
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5_040.0,
    1.0 / 40_320.0,
    1.0 / 362_880.0,
    1.0 / 3_628_800.0,
    1.0 / 39_916_800.0,
    1.0 / 479_001_600.0,
    1.0 / 6_227_020_800.0,
];

/// The first `n` of [`INV_FACTORIALS`].
#[inline(always)]
fn inv_factorials(n: usize) -> &'static [f64] {
    INV_FACTORIALS.get(..n).unwrap_or(&INV_FACTORIALS)
}

/// The functions of [`Lane`], the same for both types: the bit-level ones, and the one-lane
/// `exp` and `ln`.
macro_rules! lane_functions {
    ($t:ty) => {
        #[inline(always)]
        fn exp_l(self) -> Self {
            exp(self)
        }
        #[inline(always)]
        fn ln_l(self) -> Self {
            ln(self)
        }
        #[inline(always)]
        fn low_bits(self) -> usize {
            self.to_bits() as usize
        }
        #[inline]
        fn next_below(self) -> Self {
            <$t>::next_down(self)
        }
        #[inline]
        fn next_above(self) -> Self {
            <$t>::next_up(self)
        }
    };
}

// fdlibm's constants as published (more digits than an f64 holds; they round to it).
#[allow(clippy::excessive_precision)]
impl Lane for f64 {
    const EXP_TERMS: usize = 12;
    const OMEGA_SERIES: Self = -9.2;
    const OMEGA_SMALL: Self = -20.0;
    const RESIDUAL_OK: Self = 1e-4;
    const EXP_HI: Self = 709.43;
    const EXP_LO: Self = -708.396;
    const SHIFT: Self = 6_755_399_441_055_744.0;
    const EXP_LN2: (f64, f64) = (
        6.931_471_803_691_238_164_90e-1,
        1.908_214_929_270_587_700_02e-10,
    );
    const LOG_LN2: (f64, f64) = (
        6.931_471_803_691_238_164_90e-1,
        1.908_214_929_270_587_700_02e-10,
    );
    const LOG_POLY: (&'static [f64], &'static [f64]) = (
        &[
            6.666_666_666_666_735_130e-1,
            2.857_142_874_366_239_149e-1,
            1.818_357_216_161_805_012e-1,
            1.479_819_860_511_658_591e-1,
        ],
        &[
            3.999_999_999_940_941_908e-1,
            2.222_219_843_214_978_396e-1,
            1.531_383_769_920_937_332e-1,
        ],
    );
    const EXP_TABLE_BITS: u32 = 3;
    const EXP_TABLE: &'static [f64] = &[
        1.0,
        1.090_507_732_665_257_7,
        1.189_207_115_002_721,
        1.296_839_554_651_009_6,
        core::f64::consts::SQRT_2,
        1.542_210_825_407_940_7,
        1.681_792_830_507_429,
        1.834_008_086_409_342_4,
    ];
    // |r| ≤ ln 2 / 16: the first omitted term r⁹/9! is below 1.5e-18.
    const EXP_TABLE_TERMS: usize = 7;
    const DECAY_MIN: Self = -708.0;
    const ONE_STEP: Self = 1.1102230246251568e-16; // 2⁻⁵³ + 2⁻¹⁰⁵
    const DECAY_POLY: &'static [f64] = &[
        1.0,
        1.0,
        0.500_000_000_000_001_9,
        0.166_666_666_666_666_8,
        0.041_666_666_666_487_95,
        0.008_333_333_333_319_589,
        0.001_388_888_895_235_286_3,
        0.000_198_412_698_900_764_03,
        2.480_148_544_156_131_3e-5,
        2.755_724_088_722_987e-6,
        2.763_265_472_252_779e-7,
        2.511_004_920_481_865_8e-8,
    ];
    lane_functions!(f64);
}

#[allow(clippy::excessive_precision)]
impl Lane for f32 {
    const EXP_TERMS: usize = 6;
    const OMEGA_SERIES: Self = -4.0;
    const OMEGA_SMALL: Self = -10.0;
    const RESIDUAL_OK: Self = 1e-2;
    const EXP_HI: Self = 88.37;
    const EXP_LO: Self = -87.336;
    const SHIFT: Self = 12_582_912.0;
    const EXP_LN2: (f64, f64) = (6.931_457_5e-1, 1.428_606_8e-6);
    const LOG_LN2: (f64, f64) = (6.931_381_2e-1, 9.058_001e-6);
    const LOG_POLY: (&'static [f64], &'static [f64]) = (
        &[0.666_666_626_93, 0.284_987_866_88],
        &[0.400_009_721_52, 0.242_790_788_41],
    );
    const EXP_TABLE_BITS: u32 = 4;
    const EXP_TABLE: &'static [f64] = &[
        1.0,
        1.044_273_734_092_712_4,
        1.090_507_745_742_797_9,
        1.138_788_580_894_470_2,
        1.189_207_077_026_367_2,
        1.241_857_767_105_102_5,
        1.296_839_594_841_003_4,
        1.354_255_557_060_241_7,
        1.414_213_538_169_860_8,
        1.476_826_190_948_486_3,
        1.542_210_817_337_036_1,
        1.610_490_322_113_037,
        1.681_792_855_262_756_3,
        1.756_252_169_609_069_8,
        1.834_008_097_648_620_6,
        1.915_206_551_551_818_8,
    ];
    // |r| ≤ ln 2 / 32: the first omitted term r⁵/5! is below 4e-11.
    const EXP_TABLE_TERMS: usize = 3;
    const DECAY_MIN: Self = -87.0;
    const ONE_STEP: Self = 5.9604652e-8; // 2⁻²⁴ + 2⁻⁴⁷
    const DECAY_POLY: &'static [f64] = &[
        1.0,
        1.0,
        0.5,
        0.166_664_153_337_478_64,
        0.041_666_351_258_754_73,
        0.008_375_134_319_067_001,
        0.001_394_111_895_933_747_3,
    ];
    lane_functions!(f32);
}

/// Σ cᵢ xⁱ by Horner's scheme.
#[inline(always)]
fn horner<V: Simd>(x: V, coefficients: &[f64]) -> V {
    let tk = x.token();
    let mut p = V::c(tk, 0.0);
    for c in coefficients.iter().rev() {
        p = p.fma(x, V::c(tk, *c));
    }
    p
}

/// Σ cᵢ xⁱ in pairs: qⱼ = c₂ⱼ + c₂ⱼ₊₁ x (independent), then Horner in x² (half the chain).
#[inline(always)]
fn poly_pairs<V: Simd>(x: V, coefficients: &[f64]) -> V {
    let tk = x.token();
    let x2 = x * x;
    let mut p: Option<V> = None;
    for pair in coefficients.chunks(2).rev() {
        let q = match pair {
            [a, b] => x.fma(V::c(tk, *b), V::c(tk, *a)),
            [a] => V::c(tk, *a),
            _ => V::c(tk, 0.0),
        };
        p = Some(match p {
            Some(p) => p.fma(x2, q),
            None => q,
        });
    }
    p.unwrap_or(V::c(tk, 0.0))
}

/// e^z for z ≤ 0 (the decay e^(−k2 ũd) of eq. 4), with an absolute error of about an ulp of 1,
/// which is all eq. (4) needs: z is raised to [`Lane::DECAY_MIN`] (e^z is then below an ulp of
/// 1 anyway), reduced once by ln 2 (z = n ln 2 + r, |r| ≤ ln 2 / 2; the rounding of ln 2 costs
/// e^z a relative n · 2⁻⁵⁵, absolutely below 2⁻⁵⁵), [`Lane::DECAY_POLY`] in pairs, and 2ⁿ from
/// the bits of the rounded argument. 17 vector operations (f64), no range selects. NaN gives
/// e^DECAY_MIN; ±∞ is not an argument the bank gives it (z = −k2 ũd with finite factors).
///
/// Vectors with a table [`exp`] (AVX-512: `vpermpd` table, `vscalefpd`) reduce by its table
/// instead, with its two-part ln 2 but without its range clamp: `hyst bench` measures the
/// tick faster this way than through `exp` itself, and the reduction by ln 2 with the long polynomial
/// slower in AVX-512 blocks. ln 2 / 2^b in one constant would be faster still but raises the
/// bank's worst f64 inverse error (`tests/bank.rs`) from under 3 to 3.5 ulp, near the bound
/// of 4.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn decay<V: Simd>(z: V) -> V
where
    V::T: Lane,
{
    let tk = z.token();
    let z = z.max_or(V::splat(tk, <V::T as Lane>::DECAY_MIN));
    if V::EXP_TABLE {
        return exp_by_table(z);
    }
    let shift = V::splat(tk, <V::T as Lane>::SHIFT);
    let t = z.fma(V::c(tk, core::f64::consts::LOG2_E), shift);
    let n = t - shift;
    let r = n.fma(V::c(tk, -core::f64::consts::LN_2), z);
    poly_pairs(r, <V::T as Lane>::DECAY_POLY) * V::pow2_shifted(t)
}

/// eˣ on every lane (see the module documentation).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn exp<V: Simd>(x: V) -> V
where
    V::T: Lane,
{
    let tk = x.token();
    let shift = V::splat(tk, <V::T as Lane>::SHIFT);
    let (ln2_hi, ln2_lo) = <V::T as Lane>::EXP_LN2;
    if V::EXP_TABLE {
        return exp_by_table(V::exp_arg(x));
    }
    let xr = V::exp_arg(x);
    let t = xr.fma(V::c(tk, core::f64::consts::LOG2_E), shift);
    let n = t - shift;
    let r = n.fma(V::c(tk, -ln2_hi), xr);
    let r = n.fma(V::c(tk, -ln2_lo), r);
    let p = poly_pairs(r, inv_factorials(<V::T as Lane>::EXP_TERMS));
    let e = (r * r).fma(p, r) + V::c(tk, 1.0);
    V::exp_tail(e, t, n, x)
}

/// eˣ by the table of [`Simd::EXP_TABLE`], for x within the range [`Simd::scale`] takes
/// (`exp` clamps it first, `decay` raises it to [`Lane::DECAY_MIN`]):
/// x = (8 n + j) ln 2 / 8 + r (f64; 16 for f32), eˣ = 2ⁿ 2^(j/8) eʳ.
#[cfg_attr(not(debug_assertions), inline(always))]
fn exp_by_table<V: Simd>(x: V) -> V
where
    V::T: Lane,
{
    let tk = x.token();
    let shift = V::splat(tk, <V::T as Lane>::SHIFT);
    let (ln2_hi, ln2_lo) = <V::T as Lane>::EXP_LN2;
    let k = f64::from(1_u32 << <V::T as Lane>::EXP_TABLE_BITS);
    let t = x.fma(V::c(tk, k * core::f64::consts::LOG2_E), shift);
    let m = t - shift;
    let r = m.fma(V::c(tk, -ln2_hi / k), x);
    let r = m.fma(V::c(tk, -ln2_lo / k), r);
    let p = poly_pairs(r, inv_factorials(<V::T as Lane>::EXP_TABLE_TERMS));
    let e = (r * r).fma(p, r) + V::c(tk, 1.0);
    V::scale(e * V::exp2_frac(t), m * V::c(tk, 1.0 / k))
}

/// ln x for positive normal x (no special cases: 0, subnormals, ∞ and NaN give wrong finite
/// values or NaN; the callers select those lanes away).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn ln_pos<V: Simd>(x: V) -> V
where
    V::T: Lane,
{
    let tk = x.token();
    let (m, k) = x.split_exponent();
    let big = V::c(tk, core::f64::consts::SQRT_2).less(m);
    let m = V::select(big, m * V::c(tk, 0.5), m);
    let k = V::select(big, k + V::c(tk, 1.0), k);
    let (ln2_hi, ln2_lo) = <V::T as Lane>::LOG_LN2;
    let (odd, even) = <V::T as Lane>::LOG_POLY;
    let f = m - V::c(tk, 1.0);
    let hfsq = V::c(tk, 0.5) * f * f;
    let s = f / (V::c(tk, 2.0) + f);
    let z = s * s;
    let w = z * z;
    let r = z * horner(w, odd) + w * horner(w, even);
    k * V::c(tk, ln2_hi) - ((hfsq - (s * (hfsq + r) + k * V::c(tk, ln2_lo))) - f)
}

/// ln x with its special values: −∞ at 0, +∞ at +∞, NaN below 0 and for NaN.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn ln<V: Simd>(x: V) -> V
where
    V::T: Lane,
{
    let tk = x.token();
    let inf = V::splat(tk, <V::T as num_traits::Float>::infinity());
    let zero = V::c(tk, 0.0);
    let inside = V::and(zero.less(x), x.less(inf));
    let v = V::select(
        inside,
        ln_pos(x),
        V::splat(tk, <V::T as num_traits::Float>::nan()),
    );
    let v = V::select(x.equal(zero), -inf, v);
    V::select(x.equal(inf), inf, v)
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

/// The series ω = t − t² + 3/2 t³ − 8/3 t⁴ + 125/24 t⁵ in t = eʸ (W0's series at 0): exact to
/// rounding below [`Lane::OMEGA_SERIES`], a start within 3.4e-6 below y = −3.
#[inline(always)]
pub(crate) fn omega_series<V: Simd>(t: V) -> V {
    let tk = t.token();
    let one = V::c(tk, 1.0);
    let inner = t.fma(-V::c(tk, 125.0 / 24.0), V::c(tk, 8.0 / 3.0));
    let inner = (-t).fma(inner, V::c(tk, 1.5));
    let inner = (-t).fma(inner, one);
    t * (-t).fma(inner, one)
}

/// A start for ω(y) within 2.2e-5 (relative) for every y ≥ −3 (below, `series` from
/// [`omega_series`] is kept): the fits above on [−3, 12] and the asymptotic expansion
/// y − L + (L / y)(1 + (L − 2) / (2y) + (2L² − 9L + 6) / (6y²)), L = ln y, above 12. Each piece is
/// evaluated only when some lane needs it.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn omega_start<V: Simd>(y: V, series: V) -> V
where
    V::T: Lane,
{
    let tk = y.token();
    let mut start = series;
    let mid_on = V::c(tk, -3.0).less_eq(y);
    if V::any(mid_on) {
        start = V::select(mid_on, horner(y * V::c(tk, 1.0 / 3.0), &OMEGA_MID), start);
    }
    let high_on = V::c(tk, 3.0).less(y);
    if V::any(high_on) {
        let x = y.fma(V::c(tk, 2.0 / 9.0), V::c(tk, -15.0 / 9.0));
        start = V::select(high_on, horner(x, &OMEGA_HIGH), start);
    }
    let asym_on = V::c(tk, 12.0).less(y);
    if V::any(asym_on) {
        let one = V::c(tk, 1.0);
        // Lanes below 12 would take ln of anything; 12 keeps them finite.
        let ys = V::select(asym_on, y, V::c(tk, 12.0));
        let l = ln_pos(ys);
        let iy = one / ys;
        let c2 = (V::c(tk, 2.0) * l - V::c(tk, 9.0)).fma(l, V::c(tk, 6.0)) * V::c(tk, 1.0 / 6.0);
        let c1 = V::c(tk, 0.5) * (l - V::c(tk, 2.0));
        let asym = ys - l + l * iy * iy.fma(iy.fma(c2, c1), one);
        start = V::select(asym_on, asym, start);
    }
    start
}

/// One Fritsch–Shafer–Crowley step for ω + ln ω = y from w (fourth order), with the residual
/// r = y − w − ln w it started from. Written so that nothing overflows for large w.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn fsc_step<V: Simd>(w: V, y: V) -> (V, V)
where
    V::T: Lane,
{
    let tk = w.token();
    let one = V::c(tk, 1.0);
    let r = y - w - ln_pos(w);
    let iq = one / (one + w);
    let rq = r * iq;
    let t = rq.fma(V::c(tk, 2.0 / 3.0), one);
    let num = (V::c(tk, -0.5) * rq).fma(iq, t);
    let den = (-rq).fma(iq, t);
    (w * (rq * (num / den)) + w, r)
}

/// ω(y) = W0(eʸ) from scratch on every lane: Winitzki's start L (1 − ln(1 + L) / (2 + L)),
/// L = ln(1 + eʸ), refined by two fourth-order Fritsch–Shafer–Crowley steps; t − t² (t = eʸ)
/// below [`Lane::OMEGA_SMALL`]. ω(−∞) = 0.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn omega_v<V: Simd>(y: V) -> V
where
    V::T: Lane,
{
    let tk = y.token();
    let one = V::c(tk, 1.0);
    let zero = V::c(tk, 0.0);
    let t = exp(y);
    let positive = zero.less(y);
    // L = ln(1 + eʸ) without overflow: max(y, 0) + ln(1 + e^(−|y|)).
    let l = V::select(positive, y, zero) + ln_pos(one + exp(-y.magnitude()));
    let mut w = l * (one - ln_pos(one + l) / (V::c(tk, 2.0) + l));
    for _ in 0..2 {
        w = fsc_step(w, y).0;
    }
    V::select(
        y.less(V::splat(tk, <V::T as Lane>::OMEGA_SMALL)),
        t - t * t,
        w,
    )
}

/// ω(y) = W0(eʸ), the Wright omega function, for one value, as the bank evaluates it from
/// scratch: Winitzki's start L (1 − ln(1 + L) / (2 + L)), L = ln(1 + eʸ), refined by two
/// fourth-order Fritsch–Shafer–Crowley steps; t − t² (t = eʸ) below [`Lane::OMEGA_SMALL`].
/// ω(−∞) = 0. For tests and comparisons with [`hyst_core::lambert::omega`].
///
/// # Examples
/// ```
/// use hyst_bank::lanes::omega;
/// let w = omega(1.0_f64); // W(e) = 1
/// assert!((w - 1.0).abs() < 1e-15);
/// ```
#[must_use]
pub fn omega<T: Lane>(y: T) -> T {
    omega_v(y)
}
