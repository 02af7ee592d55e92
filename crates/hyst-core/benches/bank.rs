//! The bank's speed goals of issue 13 as ratios measured in one run (`cargo bench -p hyst-core
//! --bench bank`; docs/performance.md records the figures): 1,024 channels, per channel-sample,
//! bank against the scalar operators run channel by channel over the same signals, each figure
//! the fastest of interleaved rounds (on a shared machine the slower rounds measure the
//! neighbours). `HYST_BANK_ISA=avx512|avx2|portable` forces one clone of the kernels.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use std::hint::black_box;
use std::time::Instant;

use hyst_core::bank::{force_isa, Isa};
use hyst_core::{BankVec, Direct, Hysteresis, Inverse, InverseHysteresis, Operator};

const CHANNELS: usize = 1024;
const TICKS: usize = 256;
const ROUNDS: usize = 30;

/// Channel c's signal at tick t (time-major): a sum of sines with many reversals, each channel
/// shifted in phase.
fn signal(c: usize, t: usize) -> f64 {
    let tt = t as f64 * 0.05 + c as f64 * 0.01;
    1.5 * tt.sin() * (0.37 * tt).cos() + 0.3 * (7.1 * tt).sin()
}

type Job<'a> = (&'static str, Box<dyn FnMut() + 'a>);

fn main() {
    if let Ok(name) = std::env::var("HYST_BANK_ISA") {
        let isa = [Isa::Avx512, Isa::Avx2, Isa::Portable]
            .into_iter()
            .find(|i| i.name() == name);
        match isa.map(|i| force_isa(Some(i))) {
            Some(Ok(())) => {}
            _ => {
                eprintln!(
                    "HYST_BANK_ISA={name}: not one this processor runs (avx512, avx2, portable)"
                );
                std::process::exit(2);
            }
        }
    }
    let (k1, k2) = (0.2, 8.0);
    let ticks: Vec<f64> = (0..TICKS)
        .flat_map(|t| (0..CHANNELS).map(move |c| signal(c, t)))
        .collect();
    let channels: Vec<f64> = (0..CHANNELS)
        .flat_map(|c| (0..TICKS).map(move |t| signal(c, t)))
        .collect();
    let ticks32: Vec<f32> = ticks.iter().map(|v| *v as f32).collect();
    let mut out = vec![0.0; CHANNELS * TICKS];
    let mut out2 = vec![0.0; CHANNELS * TICKS];
    let mut out3 = vec![0.0; CHANNELS * TICKS];
    let mut out4 = vec![0.0; CHANNELS * TICKS];
    let mut out32 = vec![0.0_f32; CHANNELS * TICKS];
    let mut out32d = vec![0.0_f32; CHANNELS * TICKS];
    let mut inv =
        BankVec::<f64, Inverse>::from_vecs(vec![k1; CHANNELS], vec![k2; CHANNELS]).unwrap();
    let mut dir =
        BankVec::<f64, Direct>::from_vecs(vec![k1; CHANNELS], vec![k2; CHANNELS]).unwrap();
    let mut inv32 =
        BankVec::<f32, Inverse>::from_vecs(vec![0.2; CHANNELS], vec![8.0; CHANNELS]).unwrap();
    let mut dir32 =
        BankVec::<f32, Direct>::from_vecs(vec![0.2; CHANNELS], vec![8.0; CHANNELS]).unwrap();
    let mut sinv: Vec<_> = (0..CHANNELS)
        .map(|_| InverseHysteresis::new(k1, k2).unwrap())
        .collect();
    let mut sdir: Vec<_> = (0..CHANNELS)
        .map(|_| Hysteresis::new(k1, k2).unwrap())
        .collect();
    let mut jobs: Vec<Job> = vec![
        (
            "bank inverse f64",
            Box::new(|| inv.process_ticks(black_box(&ticks), &mut out).unwrap()),
        ),
        (
            "bank direct f64",
            Box::new(|| dir.process_ticks(black_box(&ticks), &mut out2).unwrap()),
        ),
        (
            "bank inverse f32",
            Box::new(|| {
                inv32
                    .process_ticks(black_box(&ticks32), &mut out32)
                    .unwrap()
            }),
        ),
        (
            "bank direct f32",
            Box::new(|| {
                dir32
                    .process_ticks(black_box(&ticks32), &mut out32d)
                    .unwrap()
            }),
        ),
        (
            "scalar inverse f64",
            Box::new(|| {
                for (c, op) in sinv.iter_mut().enumerate() {
                    let r = c * TICKS..(c + 1) * TICKS;
                    op.process(black_box(&channels[r.clone()]), &mut out3[r])
                        .unwrap();
                }
            }),
        ),
        (
            "scalar direct f64",
            Box::new(|| {
                for (c, op) in sdir.iter_mut().enumerate() {
                    let r = c * TICKS..(c + 1) * TICKS;
                    op.process(black_box(&channels[r.clone()]), &mut out4[r])
                        .unwrap();
                }
            }),
        ),
    ];
    let names: Vec<&str> = jobs.iter().map(|(name, _)| *name).collect();
    let mut best = vec![f64::INFINITY; jobs.len()];
    for _ in 0..ROUNDS {
        for (b, (_, job)) in best.iter_mut().zip(jobs.iter_mut()) {
            let start = Instant::now();
            job();
            let ns = start.elapsed().as_secs_f64() * 1e9 / (CHANNELS * TICKS) as f64;
            *b = b.min(ns);
        }
    }
    drop(jobs);
    for (name, ns) in names.iter().zip(&best) {
        println!("{name:<22} {ns:>7.3} ns/channel-sample");
    }
    let (bi, bd, bi32, si, sd) = (best[0], best[1], best[2], best[4], best[5]);
    println!(
        "ratios: inverse {:.3} (goal <= 0.25), direct {:.3} (goal <= 0.33), f32/f64 inverse {:.3} (goal <= 0.5), f32 inverse {:.0} M channel-samples/s (goal >= 500)",
        bi / si,
        bd / sd,
        bi32 / bi,
        1e3 / bi32
    );
    println!("isa: {}", hyst_core::bank::isa().name());
}
