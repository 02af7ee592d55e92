//! Criterion benchmarks of the fit's speed goals (`cargo bench -p hyst-bench --bench fit`):
//! - a fit with `--dynamics 2` on 100,000 samples costs at most 3 × the static fit of
//!   the same data (group `fit_100k`; compare the two times of one run). The data: a multisine
//!   command through the plant 4e-4 s² v̈ + 0.05 s v̇ + v = u (run by the model runtime's
//!   discretisation at 1 kHz), then 2 H(0.1, 5)[v] with 0.1 % noise.
//! - a timed fit of 36,000 samples (three records, plant order 1) takes at most 3 s on
//!   2 cores (group `fit_36k`). The data: three records of 12,000 samples at 1 kHz, an actuator
//!   commanded by a sine with an overtone at 2, 10 and 40 Hz, through the plant
//!   0.02 s v̇ + v = u (zero-order hold), then 3 H(0.2, 15)[0.5 v − 1] + 1 with Gaussian noise
//!   of 0.2 % of the output's span (the records of `tests/trust.rs`, with a first-order plant).
//!   The fit is the one `hyst fit --dynamics 1` runs: its defaults, the zero-order hold, each
//!   record's start discounted until its input has swept its range and then until the fitted
//!   model has forgotten it (settling, which may fit again).
//!
//! The other fit goal, a static fit of 10 M rows at most 6 × `hyst run` of the same file, is
//! shown by `hyst bench --fit-rows 10000000` (its `fit_over_run`), not here.
#![allow(missing_docs, clippy::expect_used)]

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode};
use hyst_core::{Hysteresis, InitialState, Operator};
use hyst_fit::identify::{identify, Request};
use hyst_fit::lm::Silent;
use hyst_fit::{Dataset, Record};
use hyst_model::{Columns, Dynamics, Hold, Provenance, Structure, TimeSteps};
use hyst_test_support::rng::{Lcg64, Random, XorShift64};

const SAMPLES: usize = 100_000;

/// The timed goal's records: samples a record holds, and the rates of their commands (Hz).
const TIMED_SAMPLES: usize = 12_000;
const TIMED_RATES: [f64; 3] = [2.0, 10.0, 40.0];

fn data_100k() -> Dataset {
    let h = 1e-3;
    let u: Vec<f64> = (0..SAMPLES)
        .map(|k| {
            let t = k as f64 * h;
            let tau = 2.0 * std::f64::consts::PI;
            1.0 + (0.8 * (tau * 0.7 * t).sin()
                + 0.5 * (tau * 3.1 * t + 1.0).sin()
                + 0.3 * (tau * 9.3 * t + 2.0).sin())
                * (t / 0.5).min(1.0)
        })
        .collect();
    let plant = Dynamics::new(1.0, &[0.05, 4e-4])
        .and_then(|d| d.discretise(h))
        .expect("a stable plant");
    let mut state = plant.at_rest(u[0]);
    let v: Vec<f64> = (0..SAMPLES)
        .map(|k| {
            if k == 0 {
                u[0]
            } else {
                plant.step(&mut state, u[k])
            }
        })
        .collect();
    let mut op = InitialState::Rising
        .start(Hysteresis::new(0.1, 5.0).expect("valid"), v[0])
        .expect("a start");
    let mut rng = Lcg64::with_increment(1, 1);
    let y: Vec<f64> = v
        .iter()
        .map(|x| {
            let noise = (rng.unit() - 0.5) * 0.014;
            2.0 * op.step(*x) + noise
        })
        .collect();
    let record = Record {
        id: 0,
        weight: hyst_fit::Weights::Unit(SAMPLES),
        rows: (0..SAMPLES).collect(),
        input: u.into(),
        output: y.into(),
        validation: false,
        continues: false,
        period: Some(hyst_model::TimeSteps::even(h)),
    };
    Dataset::from_records("bench", Columns::default(), vec![record])
}

/// The timed case, the records of `tests/trust.rs` with a first-order plant: three
/// records of [`TIMED_SAMPLES`] at 1 kHz, each the command 2 + 1.6 sin ω + 0.4 sin 2.7ω in
/// [0, 4] at one of [`TIMED_RATES`], through 0.02 s v̇ + v = u (zero-order hold, from rest),
/// then 3 H(0.2, 15)[0.5 v − 1] + 1 (each record starting as after a rise), plus Gaussian noise
/// of 0.2 % of the outputs' span.
fn data_36k() -> Dataset {
    let h = 1e-3;
    let plant = Dynamics::new(1.0, &[0.02])
        .map(|d| d.with_hold(Hold::Zoh))
        .and_then(|d| d.discretise(h))
        .expect("a stable plant");
    let outputs: Vec<(Vec<f64>, Vec<f64>)> = TIMED_RATES
        .iter()
        .enumerate()
        .map(|(r, f)| {
            let u: Vec<f64> = (0..TIMED_SAMPLES)
                .map(|k| {
                    let w = std::f64::consts::TAU * f * k as f64 * h + 0.7 * r as f64 + 0.3;
                    2.0 + 1.6 * w.sin() + 0.4 * (2.7 * w).sin()
                })
                .collect();
            let mut state = plant.at_rest(u[0]);
            let mut op = InitialState::Rising
                .start(Hysteresis::new(0.2, 15.0).expect("valid"), 0.5 * u[0] - 1.0)
                .expect("a start");
            let y: Vec<f64> = u
                .iter()
                .enumerate()
                .map(|(k, x)| {
                    let v = if k == 0 {
                        *x
                    } else {
                        plant.step(&mut state, *x)
                    };
                    3.0 * op.step(0.5 * v - 1.0) + 1.0
                })
                .collect();
            (u, y)
        })
        .collect();
    let (lo, hi) = outputs
        .iter()
        .flat_map(|(_, y)| y)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
            (a.min(*y), b.max(*y))
        });
    let sigma = 0.002 * (hi - lo);
    let mut rng = XorShift64(7);
    let records = outputs
        .into_iter()
        .enumerate()
        .map(|(r, (u, y))| {
            let y: Vec<f64> = y.iter().map(|y| y + sigma * rng.normal()).collect();
            Record {
                id: r as i64,
                weight: hyst_fit::Weights::Unit(TIMED_SAMPLES),
                rows: (r * TIMED_SAMPLES..(r + 1) * TIMED_SAMPLES).collect(),
                input: u.into(),
                output: y.into(),
                validation: false,
                continues: false,
                period: Some(TimeSteps::even(h)),
            }
        })
        .collect();
    Dataset::from_records("bench", Columns::default(), records)
}

/// One fit of `data` as `request` asks, silent and never interrupted.
fn fit_once(data: &Dataset, request: &Request) -> hyst_fit::identify::Identified {
    identify(data, request, &mut Silent, &|| false, Provenance::default()).expect("the fit")
}

fn fit(c: &mut Criterion) {
    let data = data_100k();
    let mut group = c.benchmark_group("fit_100k");
    group.sample_size(10);
    for (name, dynamics) in [("static", 0_u8), ("dynamics_2", 2)] {
        let request = Request {
            structure: Structure {
                dynamics,
                ..Structure::default()
            },
            ..Request::default()
        };
        group.bench_function(name, |b| b.iter(|| fit_once(&data, &request)));
    }
    group.finish();

    // What `hyst fit --dynamics 1` asks for (crates/hyst-cli/src/fit: the CLI's defaults are
    // `Request::default()`'s, its hold `Hold::FIT_DEFAULT`).
    let data = data_36k();
    let request = Request {
        structure: Structure {
            dynamics: 1,
            hold: Hold::FIT_DEFAULT,
            ..Structure::default()
        },
        ..Request::default()
    };
    let mut group = c.benchmark_group("fit_36k");
    group.sample_size(10);
    // One fit a sample: a fit takes seconds.
    group.sampling_mode(SamplingMode::Flat);
    group.bench_function("dynamics_1", |b| b.iter(|| fit_once(&data, &request)));
    group.finish();
}

criterion_group!(benches, fit);
criterion_main!(benches);
