//! One workload of benches/bank.rs at a time, for instruction counts under
//! `valgrind --tool=callgrind` (timings on the shared machine are noisy; counts are not):
//!
//! ```text
//! cargo bench -p hyst-bank --bench bank_count --no-run
//! valgrind --tool=callgrind <the bench binary> bank inverse f64   # or: scalar / direct / f32
//! valgrind --tool=callgrind <the bench binary> step inverse f64   # the bank by `step`, tick by tick
//! ```
//!
//! It runs 1,024 channels for 256 ticks (time-major `process` for the bank, each channel's
//! `process` for the scalar operators) twice; the second run's instructions per channel-sample
//! are the difference of two runs' totals divided by 262,144 (docs/performance.md). Valgrind
//! hides AVX-512 from the program, so the bank runs its AVX2 kernel there.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::hint::black_box;

use hyst_bank::BankVec;
use hyst_bank::{BankFormula, Lane};
use hyst_core::{ConstantK2, Direct, Inverse, Operator, ParametricHysteresis};

const CHANNELS: usize = 1024;
const TICKS: usize = 256;

fn signal(c: usize, t: usize) -> f64 {
    let tt = t as f64 * 0.05 + c as f64 * 0.01;
    1.5 * tt.sin() * (0.37 * tt).cos() + 0.3 * (7.1 * tt).sin()
}

fn run<T: Lane, F: BankFormula>(bank: bool, step: bool, repeats: usize) {
    let (k1, k2) = (T::from_f64(0.2), T::from_f64(8.0));
    let mut out = vec![T::zero(); CHANNELS * TICKS];
    if bank {
        let ticks: Vec<T> = (0..TICKS)
            .flat_map(|t| (0..CHANNELS).map(move |c| T::from_f64(signal(c, t))))
            .collect();
        let mut b = BankVec::<T, F>::from_vecs(vec![k1; CHANNELS], vec![k2; CHANNELS]).unwrap();
        for _ in 0..repeats {
            if step {
                for (row, o) in ticks
                    .chunks_exact(CHANNELS)
                    .zip(out.chunks_exact_mut(CHANNELS))
                {
                    b.step(black_box(row), o).unwrap();
                }
            } else {
                b.process(black_box(&ticks), &mut out).unwrap();
            }
        }
        eprintln!("kernel: {}", hyst_bank::isa().name());
    } else {
        let channels: Vec<T> = (0..CHANNELS)
            .flat_map(|c| (0..TICKS).map(move |t| T::from_f64(signal(c, t))))
            .collect();
        let mut ops: Vec<ParametricHysteresis<T, ConstantK2<T>, F>> = (0..CHANNELS)
            .map(|_| ParametricHysteresis::new(k1, k2).unwrap())
            .collect();
        for _ in 0..repeats {
            for (c, op) in ops.iter_mut().enumerate() {
                let r = c * TICKS..(c + 1) * TICKS;
                op.process(black_box(&channels[r.clone()]), &mut out[r])
                    .unwrap();
            }
        }
    }
    black_box(&out);
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    // `cargo bench` passes --bench; run nothing then.
    let (who, formula, precision, repeats) = match args.as_slice() {
        [w, f, p] => (*w, *f, *p, 1),
        [w, f, p, n] => (*w, *f, *p, n.parse().unwrap()),
        _ => return,
    };
    let (bank, step) = (who != "scalar", who == "step");
    match (formula, precision) {
        ("inverse", "f64") => run::<f64, Inverse>(bank, step, repeats),
        ("direct", "f64") => run::<f64, Direct>(bank, step, repeats),
        ("inverse", "f32") => run::<f32, Inverse>(bank, step, repeats),
        ("direct", "f32") => run::<f32, Direct>(bank, step, repeats),
        _ => panic!("usage: bank_count bank|step|scalar inverse|direct f64|f32 [repeats]"),
    }
}
