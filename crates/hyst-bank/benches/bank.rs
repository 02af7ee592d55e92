//! The bank's speed goals as ratios measured in one run (`cargo bench -p hyst-bank
//! --bench bank`; docs/performance.md records the figures): 1,024 channels, f64 (and f32), ns
//! per channel-sample, each figure the fastest of interleaved rounds (on a shared machine the
//! slower rounds measure the neighbours).
//!
//! Four ways of running, each against the scalar operators run the same way:
//! - tick by tick (the controller's loop: `step` with one sample per channel; the scalar
//!   operators stepped once each per tick), each tick's row (8 KiB for f64) read from a block of
//!   256 rows that the other workloads push out of the caches between rounds: rows that arrive
//!   cold, as from a sensor's DMA;
//! - tick by tick with the rows in cache (`hot`): the same, over eight rows (the first eight
//!   ticks, in the order 0, 1, …, 7, 6, …, 1, 0, 1, …), as when the controller has just computed
//!   the row it passes;
//! - blocks of 32 ticks (`process`, time-major; the scalar operators each `process`
//!   their channel's 32 samples) — 256 KiB in and out for f64, in L2;
//! - a block of 256 ticks — 2 MiB in and 2 MiB out for f64, more than L2 holds, so the bank's
//!   time there is partly memory bandwidth, shared with whatever else the machine runs (f32
//!   moves half the bytes).
//!
//! `HYST_BANK_ISA=avx512|avx2|sse2|portable` forces one kernel. `HYST_BANK_WORKLOAD=mixed` gives
//! every channel its own k1 and k2 (log-uniform in [1e-3, 10] and [1e-2, 1e6], signals of 20 k1:
//! most ticks far past the reversal point, where the outputs sit at the band's edge).
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use std::hint::black_box;
use std::time::Instant;

use hyst_bank::BankVec;
use hyst_bank::{force_isa, BankFormula, Isa, Lane};
use hyst_core::{ConstantK2, Direct, Inverse, Operator, ParametricHysteresis};
use hyst_test_support::rng::{Random, XorShift64};

const CHANNELS: usize = 1024;
const TICKS: usize = 256;
/// Ticks per block of the L2-resident blocks.
const SHORT: usize = 32;
const ROUNDS: usize = 60;

/// Channel c's signal at tick t: a sum of sines with many reversals, each channel shifted in
/// phase.
fn signal(c: usize, t: usize) -> f64 {
    let tt = t as f64 * 0.05 + c as f64 * 0.01;
    1.5 * tt.sin() * (0.37 * tt).cos() + 0.3 * (7.1 * tt).sin()
}

type Job<'a> = (String, Box<dyn FnMut() + 'a>);

/// The inputs of one precision: each channel's k1 and k2, and its signal of [`TICKS`] ticks,
/// time-major (`ticks`, a tick's channels together) and channel-major (`channels`).
struct Workload<T> {
    k1s: Vec<T>,
    k2s: Vec<T>,
    ticks: Vec<T>,
    channels: Vec<T>,
}

/// Each channel's k1, k2 and the factor of its signal: k1 = 0.2, k2 = 8 and the signal as it
/// is; or (`mixed`) k1 log-uniform in [1e-3, 10], k2 in [1e-2, 1e6] and the signal times
/// 20 k1, the ranges of tests/bank.rs, where most ticks are far past the reversal point.
fn workload<T: Lane>(mixed: bool) -> Workload<T> {
    let mut rng = XorShift64(0x9e37_79b9_7f4a_7c15);
    let params: Vec<(f64, f64, f64)> = (0..CHANNELS)
        .map(|_| {
            if mixed {
                let k1 = 1e-3 * 1e4f64.powf(rng.unit());
                (k1, 1e-2 * 1e8f64.powf(rng.unit()), 20.0 * k1)
            } else {
                (0.2, 8.0, 1.0)
            }
        })
        .collect();
    let p = &params;
    Workload {
        k1s: params.iter().map(|p| T::from_f64(p.0)).collect(),
        k2s: params.iter().map(|p| T::from_f64(p.1)).collect(),
        ticks: (0..TICKS)
            .flat_map(|t| (0..CHANNELS).map(move |c| (c, t)))
            .map(|(c, t)| T::from_f64(p[c].2 * signal(c, t)))
            .collect(),
        channels: (0..CHANNELS)
            .flat_map(|c| (0..TICKS).map(move |t| (c, t)))
            .map(|(c, t)| T::from_f64(p[c].2 * signal(c, t)))
            .collect(),
    }
}

/// The channels of row `i` of the `hot` jobs: eight rows, back and forth.
fn hot_row(i: usize) -> core::ops::Range<usize> {
    let m = i % 14;
    let r = if m < 8 { m } else { 14 - m };
    r * CHANNELS..(r + 1) * CHANNELS
}

/// The four jobs of the bank: tick by tick, in one block of [`TICKS`] ticks, in blocks of
/// [`SHORT`] ticks, and on eight hot rows.
fn bank_jobs<'a, T: Lane, F: BankFormula + 'a>(name: &str, w: &Workload<T>) -> Vec<Job<'a>> {
    let bank = || BankVec::<T, F>::from_vecs(w.k1s.clone(), w.k2s.clone()).unwrap();
    let (mut b1, mut b2, mut b3, mut b4) = (bank(), bank(), bank(), bank());
    let (t1, t2, t5) = (w.ticks.clone(), w.ticks.clone(), w.ticks.clone());
    let h1: Vec<T> = w.ticks[..8 * CHANNELS].to_vec();
    let mut o1 = vec![T::zero(); CHANNELS];
    let mut o2 = vec![T::zero(); CHANNELS * TICKS];
    let mut o5 = vec![T::zero(); CHANNELS * TICKS].into_boxed_slice();
    let mut o7 = vec![T::zero(); CHANNELS];
    vec![
        (
            format!("tick  bank   {name}"),
            Box::new(move || {
                for row in t1.chunks_exact(CHANNELS) {
                    b1.step(black_box(row), &mut o1).unwrap();
                }
            }),
        ),
        (
            format!("block bank   {name}"),
            Box::new(move || b2.process(black_box(&t2), &mut o2).unwrap()),
        ),
        (
            format!("short bank   {name}"),
            Box::new(move || {
                for (block, out) in t5
                    .chunks_exact(CHANNELS * SHORT)
                    .zip(o5.chunks_exact_mut(CHANNELS * SHORT))
                {
                    b3.process(black_box(block), out).unwrap();
                }
            }),
        ),
        (
            format!("hot   bank   {name}"),
            Box::new(move || {
                for i in 0..TICKS {
                    b4.step(black_box(&h1[hot_row(i)]), &mut o7).unwrap();
                }
            }),
        ),
    ]
}

/// The four jobs of as many scalar operators, the same ways.
fn scalar_jobs<'a, T: Lane, F: BankFormula + 'a>(name: &str, w: &Workload<T>) -> Vec<Job<'a>> {
    let ops = || -> Vec<ParametricHysteresis<T, ConstantK2<T>, F>> {
        w.k1s
            .iter()
            .zip(&w.k2s)
            .map(|(&k1, &k2)| ParametricHysteresis::new(k1, k2).unwrap())
            .collect()
    };
    let (mut s1, mut s2, mut s3, mut s4) = (ops(), ops(), ops(), ops());
    let (t3, c4, channels) = (w.ticks.clone(), w.channels.clone(), w.channels.clone());
    let h2: Vec<T> = w.ticks[..8 * CHANNELS].to_vec();
    let mut o3 = [T::zero(); CHANNELS];
    let mut o4 = vec![T::zero(); CHANNELS * TICKS];
    let mut o6 = vec![T::zero(); CHANNELS * SHORT].into_boxed_slice();
    let mut o8 = [T::zero(); CHANNELS];
    vec![
        (
            format!("tick  scalar {name}"),
            Box::new(move || {
                for row in t3.chunks_exact(CHANNELS) {
                    for ((op, y), x) in s1.iter_mut().zip(o3.iter_mut()).zip(black_box(row)) {
                        *y = op.step(*x);
                    }
                }
            }),
        ),
        (
            format!("block scalar {name}"),
            Box::new(move || {
                let (input, output) = (black_box(&c4), &mut o4);
                for (c, op) in s2.iter_mut().enumerate() {
                    let r = c * TICKS..(c + 1) * TICKS;
                    op.process(&input[r.clone()], &mut output[r]).unwrap();
                }
            }),
        ),
        (
            format!("short scalar {name}"),
            Box::new(move || {
                // The same samples in blocks of SHORT ticks, each channel's block contiguous.
                for b in 0..TICKS / SHORT {
                    for (c, op) in s3.iter_mut().enumerate() {
                        let r = c * TICKS + b * SHORT..c * TICKS + (b + 1) * SHORT;
                        let o = c * SHORT..(c + 1) * SHORT;
                        op.process(black_box(&channels[r]), &mut o6[o]).unwrap();
                    }
                }
            }),
        ),
        (
            format!("hot   scalar {name}"),
            Box::new(move || {
                for i in 0..TICKS {
                    let row = &h2[hot_row(i)];
                    for ((op, y), x) in s4.iter_mut().zip(o8.iter_mut()).zip(black_box(row)) {
                        *y = op.step(*x);
                    }
                }
            }),
        ),
    ]
}

/// The eight jobs of one precision and formula: [`bank_jobs`], then [`scalar_jobs`].
fn jobs<'a, T: Lane, F: BankFormula + 'a>(name: &str, mixed: bool) -> Vec<Job<'a>> {
    let w = workload::<T>(mixed);
    let mut jobs = bank_jobs::<T, F>(name, &w);
    jobs.extend(scalar_jobs::<T, F>(name, &w));
    jobs
}

fn main() {
    if let Ok(name) = std::env::var("HYST_BANK_ISA") {
        let isa = Isa::ALL.into_iter().find(|i| i.name() == name);
        if let Some(Ok(())) = isa.map(|i| force_isa(Some(i))) {
        } else {
            eprintln!(
                "HYST_BANK_ISA={name}: not one this processor runs (avx512, avx2, sse2, portable)"
            );
            std::process::exit(2);
        }
    }
    // HYST_BANK_WORKLOAD=mixed: every channel its own k1 and k2 over the tested ranges.
    let mixed = std::env::var("HYST_BANK_WORKLOAD").is_ok_and(|w| w == "mixed");
    let mut all: Vec<Job> = Vec::new();
    all.extend(jobs::<f64, Inverse>("inverse f64", mixed));
    all.extend(jobs::<f64, Direct>("direct f64", mixed));
    all.extend(jobs::<f32, Inverse>("inverse f32", mixed));
    all.extend(jobs::<f32, Direct>("direct f32", mixed));
    let mut best = vec![f64::INFINITY; all.len()];
    for _ in 0..ROUNDS {
        for (b, (_, job)) in best.iter_mut().zip(all.iter_mut()) {
            let start = Instant::now();
            job();
            let ns = start.elapsed().as_secs_f64() * 1e9 / (CHANNELS * TICKS) as f64;
            *b = b.min(ns);
        }
    }
    for ((name, _), ns) in all.iter().zip(&best) {
        println!("{name:<26} {ns:>7.3} ns/channel-sample");
    }
    // Per (formula, precision), 8 jobs: bank tick, block, short, hot; scalar the same.
    for (mode, k) in [
        ("tick by tick", 0),
        ("block of 256", 1),
        ("blocks of 32", 2),
        ("tick by tick, rows in cache", 3),
    ] {
        let (inv, dir, inv32) = (best[k], best[8 + k], best[16 + k]);
        let (sinv, sdir) = (best[4 + k], best[12 + k]);
        println!(
            "{mode}: inverse {:.3} x scalar (goal <= 0.25), direct {:.3} x scalar (goal <= 0.33), \
             f32 inverse {:.3} x f64 (goal <= 0.5), f32 inverse {:.0} M channel-samples/s \
             (goal >= 500)",
            inv / sinv,
            dir / sdir,
            inv32 / inv,
            1e3 / inv32
        );
    }
    println!("kernel: {}", hyst_bank::isa().name());
}
