//! The channel bank against the scalar operator: same memory rule, outputs within a stated
//! number of ulp for every kernel this processor runs (AVX-512, AVX2 + FMA, portable), over
//! ≥ 1e7 random samples and parameters per kernel in release builds; errors and memory on bad
//! input as the scalar operator's; its `exp`, `ln` and ω against the platform's and the scalar
//! ones.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_bank::lanes::{omega, Lane};
use hyst_bank::{force_isa, isa, Isa};
use hyst_bank::{BankError, BankVec};
use hyst_core::{Direct, Error, Inverse, Memory, Operator};
use hyst_test_support::rng::{Random, XorShift64Star};
use std::sync::Mutex;

/// Tests that force a kernel or depend on which one runs hold this (the choice is global).
static ISA_LOCK: Mutex<()> = Mutex::new(());

fn ulps_f64(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / (scale.abs() * f64::EPSILON)
}

#[test]
fn exp_and_ln_match_the_platform() {
    let mut rng = XorShift64Star(7);
    let mut worst = (0.0_f64, 0.0_f64);
    for _ in 0..1_000_000 {
        let x = -745.0 + 1454.0 * rng.unit();
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
        let x = (-87.0 + 175.0 * rng.unit()) as f32;
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
    let mut rng = XorShift64Star(11);
    let mut worst = 0.0_f64;
    for _ in 0..1_000_000 {
        let y = if rng.unit() < 0.5 {
            -60.0 + 80.0 * rng.unit()
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

/// Stated agreement of the bank with the scalar operator, in ulp (T::EPSILON) of [`scale`], for
/// every kernel. Inverse: the bank's `exp` against the platform's (≤ 2 ulp each) and fused
/// multiply-adds. Direct: the bank's ω (one fourth-order step from a start within 2.2e-5)
/// against the scalar's W0 (Fukushima's 50-bit approximation after two roundings), so the
/// scalar side carries most of it; the sum ṽ − M* + ω/k2 then cancels down to the output.
const INVERSE_ULP: f64 = 4.0;
const DIRECT_ULP: f64 = 16.0;

/// Ticks per comparison of 67 channels (not a multiple of any vector width, so the padded
/// remainder chunk runs too): 67 × 40,000 × 4 (two formulas, two precisions) = 1.07e7 samples
/// per kernel in release builds (`cargo test --release -p hyst-bank --test bank`, ~1 s per
/// kernel); a tenth in debug builds.
const TICKS: usize = if cfg!(debug_assertions) {
    4_000
} else {
    40_000
};
const CHANNELS: usize = 67;

/// Runs `CHANNELS` random operators of formula `F` through the bank and through the scalar
/// operator from the same memory at every tick (the scalar operator gets the bank's memory
/// first, so differences do not accumulate; `set_memory` also checks that the bank's memory
/// lies in the band), and returns the worst difference in ulp of [`scale`].
fn compare<T, F>(seed: u64, ticks: usize) -> f64
where
    T: LaneEps,
    F: hyst_bank::BankFormula,
{
    let mut rng = XorShift64Star(seed);
    let wide = T::EPSILON_F64 < 1e-10;
    let (k2_hi, amp_hi) = if wide { (1e6, 100.0) } else { (1e4, 100.0) };
    let k1: Vec<f64> = (0..CHANNELS).map(|_| rng.log_uniform(1e-3, 10.0)).collect();
    let k2: Vec<f64> = (0..CHANNELS)
        .map(|_| rng.log_uniform(1e-2, k2_hi))
        .collect();
    let amp: Vec<f64> = k1
        .iter()
        .map(|k| k * rng.log_uniform(0.1, amp_hi))
        .collect();
    // Half the channels swing around an offset far from 0 (rounding at the band's edge).
    let offset: Vec<f64> = k1
        .iter()
        .map(|k| {
            if rng.unit() < 0.5 {
                k * 100.0 * (2.0 * rng.unit() - 1.0)
            } else {
                0.0
            }
        })
        .collect();
    let t = |v: f64| T::from_f64(v);
    let mut bank = BankVec::<T, F>::from_vecs(
        k1.iter().map(|v| t(*v)).collect(),
        k2.iter().map(|v| t(*v)).collect(),
    )
    .unwrap();
    let mut ops: Vec<_> = (0..CHANNELS)
        .map(|c| {
            hyst_core::ParametricHysteresis::<T, hyst_core::ConstantK2<T>, F>::new(
                bank.k1()[c],
                bank.k2()[c],
            )
            .unwrap()
        })
        .collect();
    let mut x = vec![T::zero(); CHANNELS];
    let mut y = vec![T::zero(); CHANNELS];
    let mut worst = 0.0_f64;
    for _ in 0..ticks {
        for c in 0..CHANNELS {
            let big = if rng.unit() < 0.1 { 1.0 } else { 0.3 };
            x[c] = t(offset[c] + amp[c] * (2.0 * rng.unit() - 1.0) * big);
            ops[c]
                .set_memory(bank.memory(c))
                .unwrap_or_else(|e| panic!("channel {c}: the bank's memory is refused: {e}"));
        }
        let before: Vec<_> = (0..CHANNELS).map(|c| bank.memory(c)).collect();
        bank.step(&x, &mut y).unwrap();
        for c in 0..CHANNELS {
            let s = ops[c].step(x[c]);
            let m = before[c].map(|m| Memory {
                reversal_input: m.reversal_input.as_f64(),
                reversal_output: m.reversal_output.as_f64(),
                direction: m.direction,
                last_input: m.last_input.as_f64(),
                last_output: m.last_output.as_f64(),
            });
            let sc = scale(x[c].as_f64(), s.as_f64(), k1[c], m);
            let d = (y[c].as_f64() - s.as_f64()).abs() / (sc * T::EPSILON_F64);
            worst = worst.max(d);
        }
    }
    worst
}

/// The machine epsilon of a lane type as an `f64`.
trait Epsilon {
    const EPSILON_F64: f64;
}
impl Epsilon for f64 {
    const EPSILON_F64: f64 = f64::EPSILON;
}
impl Epsilon for f32 {
    const EPSILON_F64: f64 = f32::EPSILON as f64;
}
trait LaneEps: Lane + Epsilon {}
impl<T: Lane + Epsilon> LaneEps for T {}

#[test]
fn every_kernel_agrees_with_the_scalar_operator() {
    let _guard = ISA_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let mut ran = 0;
    for kernel in Isa::ALL {
        if force_isa(Some(kernel)).is_err() {
            eprintln!("{}: not available here", kernel.name());
            continue;
        }
        assert_eq!(isa(), kernel);
        ran += 1;
        let r = [
            compare::<f64, Inverse>(1, TICKS),
            compare::<f64, Direct>(2, TICKS),
            compare::<f32, Inverse>(3, TICKS),
            compare::<f32, Direct>(4, TICKS),
        ];
        eprintln!(
            "{}: f64 inverse {:.2}, direct {:.2}; f32 inverse {:.2}, direct {:.2} ulp ({} samples each)",
            kernel.name(),
            r[0],
            r[1],
            r[2],
            r[3],
            CHANNELS * TICKS
        );
        force_isa(None).unwrap();
        for (what, worst, bound) in [
            ("f64 inverse", r[0], INVERSE_ULP),
            ("f64 direct", r[1], DIRECT_ULP),
            ("f32 inverse", r[2], INVERSE_ULP),
            ("f32 direct", r[3], DIRECT_ULP),
        ] {
            assert!(
                worst <= bound,
                "{}: {what} {worst} ulp > {bound}",
                kernel.name()
            );
        }
    }
    assert!(ran >= 1);
}

fn memories<F: hyst_bank::BankFormula>(bank: &BankVec<f64, F>) -> Vec<Option<Memory<f64>>> {
    (0..bank.channels()).map(|c| bank.memory(c)).collect()
}

/// A non-finite sample is an error naming its channel, in every layout: in one tick no
/// channel's memory changes; in a block the ticks before the failing one are done (the memory
/// is as after them) and the rest are not. Slices of the wrong length are errors, never panics.
#[test]
fn bad_input_is_an_error_that_leaves_every_memory_as_before_the_tick() {
    let n = 11;
    let mut bank = BankVec::<f64, Direct>::from_vecs(vec![0.2; n], vec![8.0; n]).unwrap();
    let ticks: Vec<f64> = (0..3 * n).map(|i| (i as f64 * 0.37).sin()).collect();
    let mut out = vec![0.0; 3 * n];
    bank.process(&ticks, &mut out).unwrap();
    let before = memories(&bank);
    // The same bank after two more good ticks (what a block failing at its third tick leaves).
    let mut two = bank.clone();
    two.process(&ticks[..2 * n], &mut out[..2 * n]).unwrap();
    let after_two = memories(&two);
    let mut one = bank.clone();
    let first: Vec<f64> = (0..n).map(|c| ticks[c * 3]).collect();
    one.step(&first, &mut out[..n]).unwrap();
    let after_one = memories(&one);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut x: Vec<f64> = (0..n).map(|c| c as f64 * 0.01).collect();
        x[7] = bad;
        let e = bank.step(&x, &mut out[..n]).unwrap_err();
        assert_eq!(e.channel, 7);
        assert!(matches!(e.error, Error::NonFiniteInput { .. }));
        assert_eq!(memories(&bank), before);

        let mut b = bank.clone();
        let mut block = ticks.clone();
        block[2 * n + 5] = bad; // tick 2, channel 5, time-major
        assert_eq!(b.process(&block, &mut out).unwrap_err().channel, 5);
        assert_eq!(memories(&b), after_two);

        let mut b = bank.clone();
        let block: Vec<f64> = (0..n)
            .flat_map(|c| (0..3).map(move |t| (c, t)))
            .map(|(c, t)| {
                if c == 4 && t == 1 {
                    bad
                } else {
                    ticks[c * 3 + t]
                }
            })
            .collect(); // channel 4, tick 1, channel-major
        let e = b.process_block(&block, &mut out, 3).unwrap_err();
        assert_eq!(e.channel, 4);
        assert_eq!(memories(&b), after_one);
    }
    // Lengths: errors, not panics, and nothing changes.
    let short = vec![0.0; n - 1];
    let mut o = vec![0.0; n];
    assert!(matches!(
        bank.step(&short, &mut o).unwrap_err().error,
        Error::LengthMismatch { .. }
    ));
    assert!(bank.step(&o.clone(), &mut o[..2]).is_err());
    assert!(bank
        .process(&vec![0.0; n + 1], &mut vec![0.0; n + 1])
        .is_err());
    assert!(bank
        .process_block(&vec![0.0; 2 * n], &mut vec![0.0; 2 * n], 3)
        .is_err());
    assert!(bank.process_block(&[], &mut [], usize::MAX).is_err());
    assert_eq!(memories(&bank), before);
    assert!(bank.memory(n).is_none());
    assert!(bank.set_memory(n, None).is_err());
    // Parameters the scalar operator refuses, with their channel.
    let e = BankVec::<f64, Inverse>::from_vecs(vec![0.1, 0.1, 0.1], vec![1.0, 1e-320, 1.0]);
    assert_eq!(e.unwrap_err().channel, 1);
    let e = BankVec::<f64, Inverse>::from_vecs(vec![0.1, f64::MAX], vec![1.0, 1.0]);
    assert_eq!(e.unwrap_err().channel, 1);
    assert!(BankVec::<f64, Inverse>::from_vecs(vec![0.1], vec![1.0, 2.0]).is_err());
}

/// Samples at the end of the float range: the bank gives the scalar operator's outputs (its
/// overflow-free forms) or, where the scalar operator refuses a sample, the same error naming
/// the channel, with every memory as before the block.
#[test]
fn the_end_of_the_float_range_is_handled_like_the_scalar_operator() {
    fn run<F: hyst_bank::BankFormula>() -> (usize, usize) {
        // Four kinds of channel, nine of each: whole chunks of every kernel and a remainder.
        const N: usize = 36;
        let (mut fine, mut refused) = (0, 0);
        let k1: Vec<f64> = (0..N).map(|c| [1e300, 0.5, 1e307, 2.0][c % 4]).collect();
        let k2: Vec<f64> = (0..N).map(|c| [1e-290, 8.0, 1.0, 1e6][c % 4]).collect();
        let seq = [
            [0.0, 1.0, 0.0, 0.0],
            [1e308, -1.0, -1.7e308, 1e308],
            [-1e308, 1e300, 1.7e308, -1e308],
            [-f64::MAX, -f64::MAX, 1.0, f64::MAX],
            [-f64::MAX, 0.0, 1.0, f64::MAX],
        ];
        let mut bank = BankVec::<f64, F>::from_vecs(k1.clone(), k2.clone()).unwrap();
        let mut ops: Vec<_> = (0..N)
            .map(|c| {
                hyst_core::ParametricHysteresis::<f64, hyst_core::ConstantK2<f64>, F>::new(
                    k1[c], k2[c],
                )
                .unwrap()
            })
            .collect();
        let mut out = [0.0; N];
        for row in seq {
            let x: [f64; N] = core::array::from_fn(|c| row[c % 4]);
            let before = memories(&bank);
            let scalar: Vec<_> = (0..N).map(|c| ops[c].try_step(x[c])).collect();
            match bank.step(&x, &mut out) {
                Ok(()) => {
                    fine += 1;
                    for c in 0..N {
                        let s = scalar[c].unwrap();
                        assert!(out[c].is_finite());
                        assert!((out[c] - x[c]).abs() <= k1[c]);
                        let tol = 16.0 * f64::EPSILON * x[c].abs().max(s.abs()).max(k1[c]);
                        assert!((out[c] - s).abs() <= tol, "{c}: {} vs {s}", out[c]);
                    }
                }
                Err(BankError { channel, error }) => {
                    refused += 1;
                    assert!(matches!(error, Error::NonFiniteOutput { .. }));
                    assert!(scalar[channel].is_err(), "channel {channel}");
                    assert_eq!(memories(&bank), before);
                    // The scalar operators step on: put the bank where they are.
                    for (c, op) in ops.iter().enumerate() {
                        bank.set_memory(c, op.memory()).unwrap();
                    }
                }
            }
        }
        (fine, refused)
    }
    let _guard = ISA_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    for kernel in Isa::ALL {
        if force_isa(Some(kernel)).is_ok() {
            // The inverse falling to −max on channel 0 (k1 = 1e300) has its output beyond the
            // float range; the direct operator's output lies between the input and the
            // reversal point's side, so it never leaves the range.
            let (fine, refused) = run::<Inverse>();
            assert!(
                fine >= 1 && refused >= 1,
                "inverse: {fine} ticks, {refused} refused"
            );
            let (fine, _) = run::<Direct>();
            assert!(fine >= 4, "direct: {fine} ticks");
        }
    }
    force_isa(None).unwrap();

    // In a block, a refused tick stops it there: the ticks before are done.
    let mut bank = BankVec::<f64, Inverse>::from_vecs(vec![1e300, 0.5], vec![1e-290, 8.0]).unwrap();
    let block = [0.0, 0.0, -1e308, 1.0, -f64::MAX, 2.0, 0.0, 3.0];
    let mut out = [0.0; 8];
    let mut two = bank.clone();
    two.process(&block[..4], &mut out[..4]).unwrap();
    let e = bank.process(&block, &mut out).unwrap_err();
    assert_eq!(e.channel, 0);
    assert!(matches!(e.error, Error::NonFiniteOutput { .. }));
    assert_eq!(memories(&bank), memories(&two));
}

/// One tick at a time, a time-major block and a channel-major block give the same outputs and
/// memories, bit for bit, with arrays or vectors as storage, for both formulas and every
/// kernel, for a channel count that is not a multiple of the vector width (whole chunks of every
/// kernel and a remainder), on signals with reversals and, half of the channels, far from 0
/// (rounding at the band's edge).
#[test]
fn layouts_and_storage_agree() {
    let _guard = ISA_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    for kernel in Isa::ALL {
        if force_isa(Some(kernel)).is_ok() {
            layouts_agree::<Direct>();
            layouts_agree::<Inverse>();
        }
    }
    force_isa(None).unwrap();
}

/// The input of channel `c` at tick `t` of the layout tests: a sine of its own, offset by
/// 1,000 k1 on the even channels (far past the reversal point).
fn layout_input(k1: &[f64], c: usize, t: usize) -> f64 {
    let offset = if c.is_multiple_of(2) {
        1e3 * k1[c]
    } else {
        0.0
    };
    offset + (0.21 * t as f64 + c as f64).sin() * (1.0 + 0.1 * c as f64)
}

/// Banks of N channels (k1, k2) started from the memories `start`, every third channel from no
/// history instead, then driven against their direction of travel: stepped tick by tick and
/// processed as one block of three ticks, they agree bit for bit.
fn first_samples_at_a_reversal_agree<F: hyst_bank::BankFormula, const N: usize>(
    k1: &[f64; N],
    k2: &[f64; N],
    start: &[Option<Memory<f64>>],
) {
    let x = |c: usize, t: usize| layout_input(k1, c, t);
    let mut a = vec![0.0; N];
    // Channels at their first sample in the chunks of channels that run on, and reverse, at
    // that tick (`step`'s visit hands such a chunk to the general tick): as a block of three
    // ticks gives them.
    let mut stepped = BankVec::<f64, F>::from_vecs(k1.to_vec(), k2.to_vec()).unwrap();
    let mut blocked = BankVec::<f64, F>::from_vecs(k1.to_vec(), k2.to_vec()).unwrap();
    for (c, m) in start.iter().enumerate() {
        let m = if c % 3 == 1 { None } else { *m };
        stepped.set_memory(c, m).unwrap();
        blocked.set_memory(c, m).unwrap();
    }
    let turn = |c: usize, t: usize| match start[c] {
        // Against the direction of travel: a reversal at the first tick.
        Some(m) => m.last_input - m.direction.sign::<f64>() * (0.3 + 0.1 * t as f64),
        None => x(c, t),
    };
    let mut by_step = vec![0.0; N * 3];
    for t in 0..3 {
        let row: Vec<f64> = (0..N).map(|c| turn(c, t)).collect();
        stepped.step(&row, &mut a).unwrap();
        by_step[t * N..(t + 1) * N].copy_from_slice(&a);
    }
    let channel_major: Vec<f64> = (0..N)
        .flat_map(|c| (0..3).map(move |t| turn(c, t)))
        .collect();
    let mut by_block = vec![0.0; N * 3];
    blocked
        .process_block(&channel_major, &mut by_block, 3)
        .unwrap();
    for c in 0..N {
        for t in 0..3 {
            assert_eq!(
                by_step[t * N + c].to_bits(),
                by_block[c * 3 + t].to_bits(),
                "channel {c}, tick {t}"
            );
        }
    }
    assert_eq!(memories(&stepped), memories(&blocked));
}

fn layouts_agree<F: hyst_bank::BankFormula>() {
    const N: usize = 45;
    const T: usize = 37;
    let k1: [f64; N] = core::array::from_fn(|c| 0.05 + 0.03 * c as f64);
    let k2: [f64; N] = core::array::from_fn(|c| 0.5 + 3.0 * c as f64);
    let x = |c: usize, t: usize| layout_input(&k1, c, t);
    let mut by_tick = hyst_bank::Bank::<f64, F, N>::new(k1, k2).unwrap();
    let mut ticks = BankVec::<f64, F>::from_vecs(k1.to_vec(), k2.to_vec()).unwrap();
    let mut block = BankVec::<f64, F>::from_vecs(k1.to_vec(), k2.to_vec()).unwrap();
    let mut one = vec![0.0; N * T];
    for t in 0..T {
        let row: [f64; N] = core::array::from_fn(|c| x(c, t));
        let mut y = [0.0; N];
        by_tick.step(&row, &mut y).unwrap();
        one[t * N..(t + 1) * N].copy_from_slice(&y);
    }
    let time_major: Vec<f64> = (0..T).flat_map(|t| (0..N).map(move |c| x(c, t))).collect();
    let mut two = vec![0.0; N * T];
    ticks.process(&time_major, &mut two).unwrap();
    let channel_major: Vec<f64> = (0..N).flat_map(|c| (0..T).map(move |t| x(c, t))).collect();
    let mut three = vec![0.0; N * T];
    block.process_block(&channel_major, &mut three, T).unwrap();
    for c in 0..N {
        for t in 0..T {
            assert_eq!(one[t * N + c].to_bits(), two[t * N + c].to_bits());
            assert_eq!(one[t * N + c].to_bits(), three[c * T + t].to_bits());
        }
        assert_eq!(by_tick.memory(c), ticks.memory(c));
        assert_eq!(by_tick.memory(c), block.memory(c));
    }
    // reset and set_memory: back to the start, or to a saved memory.
    let saved = memories(&ticks);
    ticks.reset();
    assert!(ticks.memory(0).is_none());
    for (c, m) in saved.iter().enumerate() {
        ticks.set_memory(c, *m).unwrap();
    }
    assert_eq!(memories(&ticks), saved);
    let mut a = vec![0.0; N];
    let mut b = vec![0.0; N];
    let row: Vec<f64> = (0..N).map(|c| x(c, T)).collect();
    ticks.step(&row, &mut a).unwrap();
    block.step(&row, &mut b).unwrap();
    assert_eq!(a, b);
    // set_memory over a channel that has run elsewhere: nothing of its former state (the
    // direct formula's M* and ln(k2 M*) kept in columns) may survive.
    let mut other = BankVec::<f64, F>::from_vecs(k1.to_vec(), k2.to_vec()).unwrap();
    for t in 0..T {
        let row: Vec<f64> = (0..N).map(|c| 0.1 - 0.6 * x(c, t + 11)).collect();
        other.step(&row, &mut b).unwrap();
    }
    for (c, m) in memories(&ticks).iter().enumerate() {
        other.set_memory(c, *m).unwrap();
    }
    for t in T + 1..T + 6 {
        let row: Vec<f64> = (0..N).map(|c| x(c, t) + 0.4 * (t as f64).cos()).collect();
        ticks.step(&row, &mut a).unwrap();
        other.step(&row, &mut b).unwrap();
        let bits = |v: &[f64]| v.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a), bits(&b), "tick {t}");
    }
    assert_eq!(memories(&ticks), memories(&other));
    first_samples_at_a_reversal_agree::<F, N>(&k1, &k2, &memories(&ticks));
}

/// Threads: `step_par` and `process_block_par` give the sequential outputs and memories bit for
/// bit (1,000 channels: parts of whole chunks plus a remainder), and bad input is the
/// sequential error.
#[cfg(feature = "rayon")]
#[test]
fn threads_agree_with_one_thread() {
    const N: usize = 1000;
    const T: usize = 20;
    let k1: Vec<f64> = (0..N).map(|c| 0.05 + 0.001 * c as f64).collect();
    let k2: Vec<f64> = (0..N).map(|c| 0.5 + 0.01 * c as f64).collect();
    let x = |c: usize, t: usize| (0.3 * t as f64 + 0.1 * c as f64).sin() * 1.3;
    let mut seq = BankVec::<f64, Direct>::from_vecs(k1.clone(), k2.clone()).unwrap();
    let mut par = seq.clone();
    for t in 0..T {
        let row: Vec<f64> = (0..N).map(|c| x(c, t)).collect();
        let (mut a, mut b) = (vec![0.0; N], vec![0.0; N]);
        seq.step(&row, &mut a).unwrap();
        par.step_par(&row, &mut b).unwrap();
        assert_eq!(a, b);
    }
    let block: Vec<f64> = (0..N)
        .flat_map(|c| (0..T).map(move |t| x(c, t + T)))
        .collect();
    let (mut a, mut b) = (vec![0.0; N * T], vec![0.0; N * T]);
    seq.process_block(&block, &mut a, T).unwrap();
    par.process_block_par(&block, &mut b, T).unwrap();
    assert_eq!(a, b);
    assert_eq!(memories(&seq), memories(&par));
    let mut bad: Vec<f64> = (0..N).map(|c| x(c, 0)).collect();
    bad[777] = f64::NAN;
    let e = par.step_par(&bad, &mut vec![0.0; N]).unwrap_err();
    assert_eq!(e.channel, 777);
    assert_eq!(memories(&seq), memories(&par));
    assert!(par.step_par(&bad[1..], &mut vec![0.0; N - 1]).is_err());
}
