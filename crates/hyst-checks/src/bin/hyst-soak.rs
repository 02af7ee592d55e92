//! `hyst-soak`: N samples through the operator pair H(H⁻¹(x)) (and H alone), f64 and f32, with
//! random parameters over the whole valid range, checking every invariant of
//! `hyst_checks::operators::check_pair`. Prints the worst inverse-identity error (in units of
//! ε · s, see the crate docs) and the counts of refused samples and of broken invariants
//! (non-finite outputs among them). Exit status 1 if any invariant broke.
//!
//! ```text
//! cargo run --release -p hyst-checks --bin hyst-soak -- --samples 1e9 [--seed 1]
//! ```

use std::process::ExitCode;
use std::time::Instant;

use hyst_checks::operators::{check_pair, PairReport};
use hyst_core::Real;

/// splitmix64: small, fast, good enough to spread parameters and inputs.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    fn sign(&mut self) -> f64 {
        if self.next() & 1 == 0 {
            1.0
        } else {
            -1.0
        }
    }
}

struct Totals {
    report: PairReport,
    episodes: u64,
    refused_parameters: u64,
    broken: u64,
}

/// Runs `samples` samples in episodes of 1000 with fresh parameters: k1 and k2 log-uniform over
/// [MIN_POSITIVE, MAX/4] and [MIN_POSITIVE, MAX] (the constructor refuses the pairs whose product
/// is too small), inputs a random walk at a random scale with occasional jumps anywhere in the
/// float range.
fn soak<T: Real>(samples: u64, rng: &mut Rng) -> Totals {
    let (lo, hi) = (
        T::min_positive_value().as_f64().log10(),
        T::max_value().as_f64().log10(),
    );
    let k1_hi = (T::max_value().as_f64() / 4.0).log10();
    let mut totals = Totals {
        report: PairReport::default(),
        episodes: 0,
        refused_parameters: 0,
        broken: 0,
    };
    let mut inputs: Vec<T> = Vec::with_capacity(1000);
    while totals.report.samples < samples {
        totals.episodes += 1;
        let k1 = T::from_f64(10f64.powf(rng.uniform(lo, k1_hi)));
        let k2 = T::from_f64(10f64.powf(rng.uniform(lo, hi)));
        if hyst_core::Hysteresis::new(k1, k2).is_err() {
            totals.refused_parameters += 1;
            continue;
        }
        // The input scale: around the loop width, around 1/k2, or anywhere.
        let scale = match rng.next() % 3 {
            0 => k1.as_f64() * 10f64.powf(rng.uniform(-2.0, 3.0)),
            1 => 10f64.powf(rng.uniform(-2.0, 3.0)) / k2.as_f64(),
            _ => 10f64.powf(rng.uniform(lo, hi)),
        };
        let max = T::max_value().as_f64();
        let mut x = 0.0f64;
        inputs.clear();
        for _ in 0..1000 {
            if rng.next().is_multiple_of(64) {
                x = rng.sign() * 10f64.powf(rng.uniform(lo, hi));
            } else {
                x += scale * rng.uniform(-1.0, 1.0);
            }
            x = x.clamp(-max, max);
            if !x.is_finite() {
                x = 0.0;
            }
            inputs.push(T::from_f64(x));
        }
        if let Err(broken) = check_pair(k1, k2, inputs.iter().copied(), &mut totals.report) {
            totals.broken += 1;
            if totals.broken <= 10 {
                eprintln!("broken: {broken}");
            }
        }
    }
    totals
}

fn main() -> ExitCode {
    let mut samples = 1e6_f64;
    let mut seed = 1u64;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let value = args.get(i + 1);
        match (args[i].as_str(), value) {
            ("--samples", Some(v)) => match v.parse::<f64>() {
                Ok(n) if (1.0..=1e13).contains(&n) => samples = n,
                _ => {
                    eprintln!("error: --samples {v}: a number of samples in [1, 1e13]");
                    return ExitCode::FAILURE;
                }
            },
            ("--seed", Some(v)) => match v.parse() {
                Ok(s) => seed = s,
                Err(_) => {
                    eprintln!("error: --seed {v}: an unsigned integer");
                    return ExitCode::FAILURE;
                }
            },
            (other, _) => {
                eprintln!(
                    "usage: hyst-soak [--samples N] [--seed S] (unknown or incomplete {other:?})"
                );
                return ExitCode::FAILURE;
            }
        }
        i += 2;
    }
    let samples = samples as u64;
    let mut rng = Rng(seed);
    let mut failed = false;
    println!("hyst-soak: {samples} samples per precision, seed {seed}");
    for (name, run) in [
        ("f64", soak::<f64> as fn(u64, &mut Rng) -> Totals),
        ("f32", soak::<f32>),
    ] {
        let started = Instant::now();
        let t = run(samples, &mut rng);
        let seconds = started.elapsed().as_secs_f64();
        println!(
            "{name}: {} samples in {seconds:.1} s ({:.1} ns/sample), {} parameter sets ({} refused \
             by the constructor), worst |H(H^-1(x)) - x| = {:.2} eps * s * sqrt(1 + reversals) \
             ({:.2} eps * s without the reversal factor), {} samples refused (output beyond the \
             float range), {} broken invariants (non-finite outputs included)",
            t.report.samples,
            seconds * 1e9 / t.report.samples.max(1) as f64,
            t.episodes,
            t.refused_parameters,
            t.report.worst_identity,
            t.report.worst_raw,
            t.report.refused,
            t.broken
        );
        failed |= t.broken > 0;
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
