//! The channel bank against the scalar operator: same memory rule, outputs within a stated
//! number of ulp, over ≥ 1e7 random samples and parameters; its `exp`, `ln` and ω against the
//! platform's and the scalar ones.

use hyst_core::bank::lanes::{omega, Lane};
use hyst_core::{DirectBank, Hysteresis, InverseBank, InverseHysteresis, Operator};

/// A small deterministic generator (xorshift64*), so the tests need no dependency.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.next()).exp()
    }
}

fn ulps_f64(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / (scale.abs() * f64::EPSILON)
}

#[test]
fn exp_and_ln_match_the_platform() {
    let mut rng = Rng(7);
    let mut worst = (0.0_f64, 0.0_f64);
    for _ in 0..1_000_000 {
        let x = -745.0 + 1454.0 * rng.next();
        let e = x.exp_l();
        let r = x.exp();
        if r.is_normal() {
            worst.0 = worst.0.max(ulps_f64(e, r, r));
        }
        let y = rng.log_uniform(1e-300, 1e300);
        worst.1 = worst
            .1
            .max(ulps_f64(y.ln_l(), y.ln(), y.ln().abs().max(1e-300)));
    }
    assert!(
        worst.0 <= 2.0 && worst.1 <= 2.0,
        "exp {} ulp, ln {} ulp",
        worst.0,
        worst.1
    );
    assert_eq!(0.0_f64.ln_l(), f64::NEG_INFINITY);
    assert_eq!((-800.0_f64).exp_l(), 0.0);
    assert_eq!(710.0_f64.exp_l(), f64::INFINITY);
    assert_eq!(0.0_f64.exp_l(), 1.0);
    let mut worst32 = (0.0_f32, 0.0_f32);
    for _ in 0..1_000_000 {
        let x = (-87.0 + 175.0 * rng.next()) as f32;
        let r = x.exp();
        if r.is_normal() {
            worst32.0 = worst32.0.max((x.exp_l() - r).abs() / (r * f32::EPSILON));
        }
        let y = rng.log_uniform(1e-37, 1e37) as f32;
        worst32.1 = worst32
            .1
            .max((y.ln_l() - y.ln()).abs() / (y.ln().abs().max(1e-30) * f32::EPSILON));
    }
    assert!(
        worst32.0 <= 2.0 && worst32.1 <= 2.0,
        "f32: exp {} ulp, ln {} ulp",
        worst32.0,
        worst32.1
    );
}

#[test]
fn omega_matches_the_scalar_one() {
    let mut rng = Rng(11);
    let mut worst = 0.0_f64;
    for _ in 0..1_000_000 {
        let y = if rng.next() < 0.5 {
            -60.0 + 80.0 * rng.next()
        } else {
            rng.log_uniform(1.0, 1e300)
        };
        let a = omega(y);
        let b = hyst_core::lambert::omega(y);
        worst = worst.max(ulps_f64(a, b, b));
    }
    // The scalar ω (Fukushima's W0 of e^y, ≤ 2e-15 relative) and the bank's each carry a few
    // ulp; their difference stays within the sum.
    assert!(worst <= 24.0, "omega: {worst} ulp");
}

/// The size of the terms eq. (2) or (4) adds for this sample: the input, the output, k1 and
/// the reversal point (β = β0 + s β̃ with α̃ = s (α − α0)). Rounding is relative to it, so the
/// agreement is stated in ulp of this size.
fn scale(x: f64, out: f64, k1: f64, memory: Option<hyst_core::Memory<f64>>) -> f64 {
    // The step may make the last point the reversal point.
    let m = memory.map_or(0.0, |m| {
        m.reversal_input
            .abs()
            .max(m.reversal_output.abs())
            .max(m.last_input.abs())
            .max(m.last_output.abs())
    });
    x.abs().max(out.abs()).max(k1).max(m)
}

/// Runs `N` random operators through bank and scalar from the same memory at every tick (the
/// scalar operator gets the bank's memory first, so differences do not accumulate), and
/// returns the worst difference in ulp of [`scale`].
fn compare_f64<const N: usize>(seed: u64, ticks: usize, direct: bool) -> f64 {
    let mut rng = Rng(seed);
    let k1: [f64; N] = core::array::from_fn(|_| rng.log_uniform(1e-3, 10.0));
    let k2: [f64; N] = core::array::from_fn(|_| rng.log_uniform(1e-2, 1e6));
    let amp: [f64; N] = core::array::from_fn(|c| k1[c] * rng.log_uniform(0.1, 100.0));
    let mut x = [0.0; N];
    let mut y = [0.0; N];
    let mut worst = 0.0_f64;
    if direct {
        let mut bank = DirectBank::<f64, N>::new(k1, k2).unwrap();
        let mut ops: Vec<_> = (0..N)
            .map(|c| Hysteresis::new(k1[c], k2[c]).unwrap())
            .collect();
        for _ in 0..ticks {
            for c in 0..N {
                x[c] = amp[c] * (2.0 * rng.next() - 1.0) * if rng.next() < 0.1 { 1.0 } else { 0.3 };
                ops[c].set_memory(bank.memory(c)).unwrap();
            }
            let before: Vec<_> = (0..N).map(|c| bank.memory(c)).collect();
            bank.step(&x, &mut y).unwrap();
            for c in 0..N {
                let s = ops[c].step(x[c]);
                worst = worst.max(ulps_f64(y[c], s, scale(x[c], s, k1[c], before[c])));
            }
        }
    } else {
        let mut bank = InverseBank::<f64, N>::new(k1, k2).unwrap();
        let mut ops: Vec<_> = (0..N)
            .map(|c| InverseHysteresis::new(k1[c], k2[c]).unwrap())
            .collect();
        for _ in 0..ticks {
            for c in 0..N {
                x[c] = amp[c] * (2.0 * rng.next() - 1.0);
                ops[c].set_memory(bank.memory(c)).unwrap();
            }
            let before: Vec<_> = (0..N).map(|c| bank.memory(c)).collect();
            bank.step(&x, &mut y).unwrap();
            for c in 0..N {
                let s = ops[c].step(x[c]);
                worst = worst.max(ulps_f64(y[c], s, scale(x[c], s, k1[c], before[c])));
            }
        }
    }
    worst
}

/// Ticks per comparison: 64 channels × 80,000 ticks × 2 formulas × 2 precisions > 2e7 samples
/// in the release run of scripts/test-all (`cargo test --release -p hyst-core --test bank`);
/// a tenth of it in the debug run of `cargo test`.
const TICKS: usize = if cfg!(debug_assertions) {
    8_000
} else {
    80_000
};

/// Agreement of the bank with the scalar operator, in ulp of [`scale`]: the inverse's one
/// `exp` against the platform's; the direct operator's ω against the scalar's W0, which is
/// Fukushima's 50-bit approximation of W0(k2 M* e^b) after two roundings, so the scalar side
/// carries most of this.
const INVERSE_ULP: f64 = 4.0;
const DIRECT_ULP: f64 = 16.0;

#[test]
fn bank_agrees_with_the_scalar_operator_f64() {
    let inv = compare_f64::<64>(1, TICKS, false);
    let dir = compare_f64::<64>(2, TICKS, true);
    eprintln!(
        "f64: inverse {inv:.2} ulp, direct {dir:.2} ulp over {} samples each",
        64 * TICKS
    );
    assert!(inv <= INVERSE_ULP, "inverse: {inv} ulp");
    assert!(dir <= DIRECT_ULP, "direct: {dir} ulp");
}

fn compare_f32<const N: usize>(seed: u64, ticks: usize, direct: bool) -> f64 {
    let mut rng = Rng(seed);
    let k1: [f32; N] = core::array::from_fn(|_| rng.log_uniform(1e-2, 10.0) as f32);
    let k2: [f32; N] = core::array::from_fn(|_| rng.log_uniform(1e-2, 1e4) as f32);
    let amp: [f32; N] = core::array::from_fn(|c| k1[c] * rng.log_uniform(0.1, 100.0) as f32);
    let mut x = [0.0_f32; N];
    let mut y = [0.0_f32; N];
    let mut worst = 0.0_f64;
    let ulp = |a: f32, b: f32, x: f32, k1: f32, m: Option<hyst_core::Memory<f32>>| {
        let m = m.map(|m| hyst_core::Memory {
            reversal_input: f64::from(m.reversal_input),
            reversal_output: f64::from(m.reversal_output),
            direction: m.direction,
            last_input: f64::from(m.last_input),
            last_output: f64::from(m.last_output),
        });
        let sc = scale(f64::from(x), f64::from(b), f64::from(k1), m);
        f64::from((a - b).abs()) / (sc * f64::from(f32::EPSILON))
    };
    macro_rules! run {
        ($bank:expr, $op:expr) => {{
            let mut bank = $bank;
            let mut ops: Vec<_> = (0..N).map(|c| $op(k1[c], k2[c]).unwrap()).collect();
            for _ in 0..ticks {
                for c in 0..N {
                    x[c] = amp[c] * (2.0 * rng.next() as f32 - 1.0);
                    ops[c].set_memory(bank.memory(c)).unwrap();
                }
                let before: Vec<_> = (0..N).map(|c| bank.memory(c)).collect();
                bank.step(&x, &mut y).unwrap();
                for c in 0..N {
                    let s = ops[c].step(x[c]);
                    worst = worst.max(ulp(y[c], s, x[c], k1[c], before[c]));
                }
            }
        }};
    }
    if direct {
        run!(
            DirectBank::<f32, N>::new(k1, k2).unwrap(),
            Hysteresis::<f32>::new
        );
    } else {
        run!(
            InverseBank::<f32, N>::new(k1, k2).unwrap(),
            InverseHysteresis::<f32>::new
        );
    }
    worst
}

#[test]
fn bank_agrees_with_the_scalar_operator_f32() {
    let inv = compare_f32::<64>(3, TICKS, false);
    let dir = compare_f32::<64>(4, TICKS, true);
    eprintln!(
        "f32: inverse {inv:.2} ulp, direct {dir:.2} ulp over {} samples each",
        64 * TICKS
    );
    assert!(inv <= INVERSE_ULP, "inverse: {inv} ulp");
    assert!(dir <= DIRECT_ULP, "direct: {dir} ulp");
}
