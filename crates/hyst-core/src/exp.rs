//! e^x for `f64`, evaluated inline: the algorithm of ARM's optimized-routines `exp` (also
//! glibc's and musl's since 2018), 0.511 ulp at most without FMA, ported so that the inverse
//! operator (eq. 4) does not call out of line for its one exponential a sample (the direct
//! operator measures faster with the platform's: its chain through W0 is bound by latency).
//!
//! Why not the platform's `exp`: it is the same algorithm, but a call. In the loop of the inverse
//! operator (eq. 4) the call costs more than the function: the System V ABI saves no `xmm`
//! register across a call, so every value the loop keeps (k1, k2, the memory, the sum) is
//! stored before it and loaded after it (`hyst bench` measures this `exp` inline as
//! `exp_inline_ns`, the platform's as `exp_ns`). No crate has it: `libm`'s `exp` is fdlibm's,
//! with a division.
//!
//! Reduction: x = (128 n + j) ln 2 / 128 + r, |r| ≤ ln 2 / 256, so
//! e^x = 2^n · 2^(j/128) · e^r, with 2^(j/128) from [`TABLE`] (value and rounding tail) and
//! e^r − 1 by a polynomial of degree 5. Arguments with |x| < 2⁻⁵⁴ or |x| ≥ 512 (where the result
//! may overflow, underflow or be subnormal), ±∞ and NaN take a branch of their own, as in the
//! original, with no call either.
//!
//! Reference: Szabolcs Nagy, ARM optimized-routines, `math/exp.c` and `math/exp_data.c`
//! (MIT OR Apache-2.0 WITH LLVM-exception).

/// 1.5 · 2⁵²: adding it rounds to an integer, left in the low bits.
const SHIFT: f64 = f64::from_bits(0x4338_0000_0000_0000);
/// 128 / ln 2.
const INV_LN2_N: f64 = f64::from_bits(0x4067_1547_652b_82fe);
/// −ln 2 / 128, high part (its low 17 bits are zero, so n · this is exact).
const NEG_LN2_HI_N: f64 = f64::from_bits(0xbf76_2e42_fefa_0000);
/// −ln 2 / 128, low part.
const NEG_LN2_LO_N: f64 = f64::from_bits(0xbd0c_f79a_bc9e_3b3a);
/// e^r ≈ 1 + r + C2 r² + C3 r³ + C4 r⁴ + C5 r⁵ on |r| ≤ ln 2 / 256 (absolute error 1.555 · 2⁻⁶⁶).
const C2: f64 = f64::from_bits(0x3fdf_ffff_ffff_fdbd);
const C3: f64 = f64::from_bits(0x3fc5_5555_5555_543c);
const C4: f64 = f64::from_bits(0x3fa5_5555_cf17_2b91);
const C5: f64 = f64::from_bits(0x3f81_1111_67a4_d017);

/// For j = 0 … 127, 2^(j/128) as (tail, scale bits): the bits of 2^(j/128) rounded to `f64`
/// less j · 2⁴⁵ (the rounded argument's low bits add the exponent back), and the tail
/// (2^(j/128) − scale) / scale rounded to `f64`. Printed by `scripts/exp-table`.
static TABLE: [(u64, u64); 128] = [
    (0x0000000000000000, 0x3ff0000000000000),
    (0x3c9b3b4f1a88bf6e, 0x3feff63da9fb3335),
    (0xbc7160139cd8dc5d, 0x3fefec9a3e778061),
    (0xbc905e7a108766d1, 0x3fefe315e86e7f85),
    (0x3c8cd2523567f613, 0x3fefd9b0d3158574),
    (0xbc8bce8023f98efa, 0x3fefd06b29ddf6de),
    (0x3c60f74e61e6c861, 0x3fefc74518759bc8),
    (0x3c90a3e45b33d399, 0x3fefbe3ecac6f383),
    (0x3c979aa65d837b6d, 0x3fefb5586cf9890f),
    (0x3c8eb51a92fdeffc, 0x3fefac922b7247f7),
    (0x3c3ebe3d702f9cd1, 0x3fefa3ec32d3d1a2),
    (0xbc6a033489906e0b, 0x3fef9b66affed31b),
    (0xbc9556522a2fbd0e, 0x3fef9301d0125b51),
    (0xbc5080ef8c4eea55, 0x3fef8abdc06c31cc),
    (0xbc91c923b9d5f416, 0x3fef829aaea92de0),
    (0x3c80d3e3e95c55af, 0x3fef7a98c8a58e51),
    (0xbc801b15eaa59348, 0x3fef72b83c7d517b),
    (0xbc8f1ff055de323d, 0x3fef6af9388c8dea),
    (0x3c8b898c3f1353bf, 0x3fef635beb6fcb75),
    (0xbc96d99c7611eb26, 0x3fef5be084045cd4),
    (0x3c9aecf73e3a2f60, 0x3fef54873168b9aa),
    (0xbc8fe782cb86389d, 0x3fef4d5022fcd91d),
    (0x3c8a6f4144a6c38d, 0x3fef463b88628cd6),
    (0x3c807a05b0e4047d, 0x3fef3f49917ddc96),
    (0x3c968efde3a8a894, 0x3fef387a6e756238),
    (0x3c875e18f274487d, 0x3fef31ce4fb2a63f),
    (0x3c80472b981fe7f2, 0x3fef2b4565e27cdd),
    (0xbc96b87b3f71085e, 0x3fef24dfe1f56381),
    (0x3c82f7e16d09ab31, 0x3fef1e9df51fdee1),
    (0xbc3d219b1a6fbffa, 0x3fef187fd0dad990),
    (0x3c8b3782720c0ab4, 0x3fef1285a6e4030b),
    (0x3c6e149289cecb8f, 0x3fef0cafa93e2f56),
    (0x3c834d754db0abb6, 0x3fef06fe0a31b715),
    (0x3c864201e2ac744c, 0x3fef0170fc4cd831),
    (0x3c8fdd395dd3f84a, 0x3feefc08b26416ff),
    (0xbc86a3803b8e5b04, 0x3feef6c55f929ff1),
    (0xbc924aedcc4b5068, 0x3feef1a7373aa9cb),
    (0xbc9907f81b512d8e, 0x3feeecae6d05d866),
    (0xbc71d1e83e9436d2, 0x3feee7db34e59ff7),
    (0xbc991919b3ce1b15, 0x3feee32dc313a8e5),
    (0x3c859f48a72a4c6d, 0x3feedea64c123422),
    (0xbc9312607a28698a, 0x3feeda4504ac801c),
    (0xbc58a78f4817895b, 0x3feed60a21f72e2a),
    (0xbc7c2c9b67499a1b, 0x3feed1f5d950a897),
    (0x3c4363ed60c2ac11, 0x3feece086061892d),
    (0x3c9666093b0664ef, 0x3feeca41ed1d0057),
    (0x3c6ecce1daa10379, 0x3feec6a2b5c13cd0),
    (0x3c93ff8e3f0f1230, 0x3feec32af0d7d3de),
    (0x3c7690cebb7aafb0, 0x3feebfdad5362a27),
    (0x3c931dbdeb54e077, 0x3feebcb299fddd0d),
    (0xbc8f94340071a38e, 0x3feeb9b2769d2ca7),
    (0xbc87deccdc93a349, 0x3feeb6daa2cf6642),
    (0xbc78dec6bd0f385f, 0x3feeb42b569d4f82),
    (0xbc861246ec7b5cf6, 0x3feeb1a4ca5d920f),
    (0x3c93350518fdd78e, 0x3feeaf4736b527da),
    (0x3c7b98b72f8a9b05, 0x3feead12d497c7fd),
    (0x3c9063e1e21c5409, 0x3feeab07dd485429),
    (0x3c34c7855019c6ea, 0x3feea9268a5946b7),
    (0x3c9432e62b64c035, 0x3feea76f15ad2148),
    (0xbc8ce44a6199769f, 0x3feea5e1b976dc09),
    (0xbc8c33c53bef4da8, 0x3feea47eb03a5585),
    (0xbc845378892be9ae, 0x3feea34634ccc320),
    (0xbc93cedd78565858, 0x3feea23882552225),
    (0x3c5710aa807e1964, 0x3feea155d44ca973),
    (0xbc93b3efbf5e2228, 0x3feea09e667f3bcd),
    (0xbc6a12ad8734b982, 0x3feea012750bdabf),
    (0xbc6367efb86da9ee, 0x3fee9fb23c651a2f),
    (0xbc80dc3d54e08851, 0x3fee9f7df9519484),
    (0xbc781f647e5a3ecf, 0x3fee9f75e8ec5f74),
    (0xbc86ee4ac08b7db0, 0x3fee9f9a48a58174),
    (0xbc8619321e55e68a, 0x3fee9feb564267c9),
    (0x3c909ccb5e09d4d3, 0x3feea0694fde5d3f),
    (0xbc7b32dcb94da51d, 0x3feea11473eb0187),
    (0x3c94ecfd5467c06b, 0x3feea1ed0130c132),
    (0x3c65ebe1abd66c55, 0x3feea2f336cf4e62),
    (0xbc88a1c52fb3cf42, 0x3feea427543e1a12),
    (0xbc9369b6f13b3734, 0x3feea589994cce13),
    (0xbc805e843a19ff1e, 0x3feea71a4623c7ad),
    (0xbc94d450d872576e, 0x3feea8d99b4492ed),
    (0x3c90ad675b0e8a00, 0x3feeaac7d98a6699),
    (0x3c8db72fc1f0eab4, 0x3feeace5422aa0db),
    (0xbc65b6609cc5e7ff, 0x3feeaf3216b5448c),
    (0x3c7bf68359f35f44, 0x3feeb1ae99157736),
    (0xbc93091fa71e3d83, 0x3feeb45b0b91ffc6),
    (0xbc5da9b88b6c1e29, 0x3feeb737b0cdc5e5),
    (0xbc6c23f97c90b959, 0x3feeba44cbc8520f),
    (0xbc92434322f4f9aa, 0x3feebd829fde4e50),
    (0xbc85ca6cd7668e4b, 0x3feec0f170ca07ba),
    (0x3c71affc2b91ce27, 0x3feec49182a3f090),
    (0x3c6dd235e10a73bb, 0x3feec86319e32323),
    (0xbc87c50422622263, 0x3feecc667b5de565),
    (0x3c8b1c86e3e231d5, 0x3feed09bec4a2d33),
    (0xbc91bbd1d3bcbb15, 0x3feed503b23e255d),
    (0x3c90cc319cee31d2, 0x3feed99e1330b358),
    (0x3c8469846e735ab3, 0x3feede6b5579fdbf),
    (0xbc82dfcd978e9db4, 0x3feee36bbfd3f37a),
    (0x3c8c1a7792cb3387, 0x3feee89f995ad3ad),
    (0xbc907b8f4ad1d9fa, 0x3feeee07298db666),
    (0xbc55c3d956dcaeba, 0x3feef3a2b84f15fb),
    (0xbc90a40e3da6f640, 0x3feef9728de5593a),
    (0xbc68d6f438ad9334, 0x3feeff76f2fb5e47),
    (0xbc91eee26b588a35, 0x3fef05b030a1064a),
    (0x3c74ffd70a5fddcd, 0x3fef0c1e904bc1d2),
    (0xbc91bdfbfa9298ac, 0x3fef12c25bd71e09),
    (0x3c736eae30af0cb3, 0x3fef199bdd85529c),
    (0x3c8ee3325c9ffd94, 0x3fef20ab5fffd07a),
    (0x3c84e08fd10959ac, 0x3fef27f12e57d14b),
    (0x3c63cdaf384e1a67, 0x3fef2f6d9406e7b5),
    (0x3c676b2c6c921968, 0x3fef3720dcef9069),
    (0xbc808a1883ccb5d2, 0x3fef3f0b555dc3fa),
    (0xbc8fad5d3ffffa6f, 0x3fef472d4a07897c),
    (0xbc900dae3875a949, 0x3fef4f87080d89f2),
    (0x3c74a385a63d07a7, 0x3fef5818dcfba487),
    (0xbc82919e2040220f, 0x3fef60e316c98398),
    (0x3c8e5a50d5c192ac, 0x3fef69e603db3285),
    (0x3c843a59ac016b4b, 0x3fef7321f301b460),
    (0xbc82d52107b43e1f, 0x3fef7c97337b9b5f),
    (0xbc892ab93b470dc9, 0x3fef864614f5a129),
    (0x3c74b604603a88d3, 0x3fef902ee78b3ff6),
    (0x3c83c5ec519d7271, 0x3fef9a51fbc74c83),
    (0xbc8ff7128fd391f0, 0x3fefa4afa2a490da),
    (0xbc8dae98e223747d, 0x3fefaf482d8e67f1),
    (0x3c8ec3bc41aa2008, 0x3fefba1bee615a27),
    (0x3c842b94c3a9eb32, 0x3fefc52b376bba97),
    (0x3c8a64a931d185ee, 0x3fefd0765b6e4540),
    (0xbc8e37bae43be3ed, 0x3fefdbfdad9cbe14),
    (0x3c77893b4d91cd9d, 0x3fefe7c1819e90d8),
    (0x3c5305c14160cc89, 0x3feff3c22b8f71f1),
];

/// The biased exponent of |x|, and whether x is outside the main range 2⁻⁵⁴ ≤ |x| < 512 (one
/// unsigned compare): tiny, large, ±∞ or NaN.
#[inline(always)]
fn classify(x: f64) -> (u32, bool) {
    let abstop = (x.to_bits() >> 52) as u32 & 0x7ff;
    (abstop, abstop.wrapping_sub(0x3c9) >= 0x408 - 0x3c9)
}

/// The reduction and the polynomial: (p, scale bits, k) with e^x = scale · (1 + p), scale =
/// 2^(k/128) built from the bits (its exponent overflows or underflows for |x| ≥ 512).
#[inline(always)]
fn reduce(x: f64) -> (f64, u64, u64) {
    let kd = INV_LN2_N * x + SHIFT;
    let ki = kd.to_bits();
    let kd = kd - SHIFT;
    let r = x + kd * NEG_LN2_HI_N + kd * NEG_LN2_LO_N;
    // ki mod 128 < 128: the lookup never misses (the fallback is for the lint).
    let (tail, scale) = TABLE.get(ki as usize & 127).copied().unwrap_or((0, 0));
    let r2 = r * r;
    let p = f64::from_bits(tail) + r + r2 * (C2 + r * C3) + r2 * r2 * (C4 + r * C5);
    (p, scale.wrapping_add(ki << 45), ki)
}

/// e^x for every `f64` x, inline and without a call on any path: within 0.511 ulp of the exact
/// value (within an ulp of the platform's `exp`), exactly 1 + x for |x| < 2⁻⁵⁴, +∞ above
/// 709.78, 0 below −745.13 (subnormal results rounded once), NaN for NaN.
#[inline(always)]
pub(crate) fn exp(x: f64) -> f64 {
    let (abstop, special) = classify(x);
    if special {
        if abstop < 0x3c9 {
            // Tiny: 1 + x is e^x rounded.
            return 1.0 + x;
        }
        if abstop >= 0x409 {
            // |x| ≥ 1024, ±∞ or NaN: 0 for −∞ and every large negative x, x + 1 (+∞, NaN)
            // for +∞ and NaN, +∞ for every large positive x.
            return if x.is_nan() || x == f64::INFINITY {
                1.0 + x
            } else if x < 0.0 {
                0.0
            } else {
                f64::INFINITY
            };
        }
    }
    let (p, sbits, ki) = reduce(x);
    if special {
        return exp_scaled(p, sbits, ki);
    }
    let scale = f64::from_bits(sbits);
    scale + scale * p
}

/// [`exp`] with the arguments outside its main range out of line: the same values, bit for
/// bit, in shorter code.
#[inline(always)]
pub(crate) fn exp_short(x: f64) -> f64 {
    if classify(x).1 {
        return exp_special(x);
    }
    let (p, sbits, _) = reduce(x);
    let scale = f64::from_bits(sbits);
    scale + scale * p
}

/// The arguments of [`exp_short`] outside the main range: [`exp`], out of line.
#[cold]
#[inline(never)]
fn exp_special(x: f64) -> f64 {
    exp(x)
}

/// The end of [`exp`] for 512 ≤ |x| < 1024, where 2ⁿ may be beyond the exponent range:
/// scale · (1 + p) formed with the scale's exponent moved into range, then scaled back by a
/// power of two; below the normal range rounded once (not twice) to the subnormal result.
/// Plain arithmetic, so that `exp` makes no call (a call would make the operator's loop keep
/// its values in memory: the System V ABI saves no `xmm` register).
#[inline(always)]
fn exp_scaled(p: f64, sbits: u64, ki: u64) -> f64 {
    if ki & 0x8000_0000 == 0 {
        // n > 0: the scale's exponent may have overflowed by at most 460.
        let scale = f64::from_bits(sbits.wrapping_sub(1009 << 52));
        return f64::from_bits(0x7f00_0000_0000_0000) * (scale + scale * p); // 2¹⁰⁰⁹
    }
    // n < 0: the result may be subnormal.
    let scale = f64::from_bits(sbits.wrapping_add(1022 << 52));
    let mut y = scale + scale * p;
    if y < 1.0 {
        // Round y to the subnormal spacing before scaling, to avoid a double rounding.
        let lo = scale - y + scale * p;
        let hi = 1.0 + y;
        let lo = 1.0 - hi + y + lo;
        y = (hi + lo) - 1.0;
        if y == 0.0 {
            y = 0.0;
        }
    }
    f64::from_bits(0x0010_0000_0000_0000) * y // 2⁻¹⁰²²
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec;

    /// The scale bits plus j · 2⁴⁵ are 2^(j/128) to within half an ulp of the platform's
    /// `exp2` (itself within half an ulp), and the tail is below half an ulp of 1.
    #[test]
    fn the_table_is_2_to_the_j_over_128() {
        for (j, (tail, scale)) in TABLE.iter().enumerate() {
            let value = f64::from_bits(scale.wrapping_add((j as u64) << 45));
            let expected = (j as f64 / 128.0).exp2();
            assert!((value - expected).abs() <= f64::EPSILON * expected, "j {j}");
            assert!(f64::from_bits(*tail).abs() <= f64::EPSILON / 2.0, "j {j}");
            // 2^(j/128) · 2^((128 − j)/128) = 2: value · (1 + tail) is that exactly enough.
            let with_tail = value * (1.0 + f64::from_bits(*tail));
            assert!(
                (with_tail - expected).abs() <= f64::EPSILON * expected,
                "j {j}"
            );
        }
    }

    /// Within an ulp of the platform's `exp` (both within about half an ulp of e^x) on four
    /// million arguments spread over the whole range, and equal to it on most of them.
    #[test]
    fn exp_is_within_an_ulp_of_the_platform() {
        let n = 1_000_000;
        let mut differ = 0;
        for i in 0..n {
            let t = i as f64 / n as f64;
            for x in [
                -760.0 + 1480.0 * t,
                -4.0 + 8.0 * t,
                (t - 0.5) * 1e-3,
                -745.2 * t * t,
            ] {
                let (ours, theirs) = (exp(x), x.exp());
                if ours != theirs {
                    differ += 1;
                    let ulp = f64::from_bits(theirs.to_bits() + 1) - theirs;
                    assert!(
                        (ours - theirs).abs() <= ulp,
                        "x {x:e}: {ours:e} against {theirs:e}"
                    );
                }
            }
        }
        assert!(differ < 4 * n / 100, "{differ} differ");
    }

    /// The ends of the range: the platform's values (to an ulp where the result is finite and
    /// not 0), through overflow, the subnormal range and underflow, and the special values.
    #[test]
    fn the_ends_of_the_range_are_the_platforms() {
        let mut args = vec![
            0.0,
            -0.0,
            1e-300,
            -1e-300,
            1e-17,
            -1e-17,
            5e-324,
            511.9,
            512.0,
            -512.0,
            709.78,
            709.79,
            1000.0,
            1023.9,
            1024.0,
            1e300,
            -708.4,
            -745.1,
            -745.2,
            -1023.9,
            -1024.0,
            -1e300,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
        ];
        // Every 1e-3 from −760 to −700 (the subnormal results) and 700 to 712 (overflow).
        args.extend((0..60_000).map(|i| -760.0 + f64::from(i) * 1e-3));
        args.extend((0..12_000).map(|i| 700.0 + f64::from(i) * 1e-3));
        for x in args {
            let (ours, theirs) = (exp(x), x.exp());
            if ours.to_bits() != theirs.to_bits() {
                let ulp = f64::from_bits(theirs.to_bits() + 1) - theirs;
                assert!(
                    theirs.is_finite() && theirs > 0.0 && (ours - theirs).abs() <= ulp,
                    "x {x:e}: {ours:e} against {theirs:e}"
                );
            }
        }
        assert!(exp(f64::NAN).is_nan());
        assert_eq!(exp(f64::NEG_INFINITY).to_bits(), 0.0_f64.to_bits());
    }

    /// The short form is the whole one, bit for bit, in and out of the main range.
    #[test]
    fn exp_short_is_exp() {
        let mut args = vec![
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -0.0,
            1e-300,
        ];
        args.extend((0..200_000).map(|i| -800.0 + f64::from(i) * 8e-3));
        args.extend((0..2_000).map(|i| f64::from(i - 1000) * 1e-18));
        for x in args {
            assert_eq!(exp_short(x).to_bits(), exp(x).to_bits(), "x {x:e}");
        }
    }
}
