//! The recovery study of timed fits: random in-class truths (plant orders 0–3, with and without
//! the viscous rate term, records that start from the start rule or mid-history, noise 0 or
//! 0.5 % of the span, one record or three at rates 1 : 4 : 16, either hold), fitted by `identify` with
//! the structure of the truth and its defaults. Each case prints one row of the table in
//! docs/fitting.md ("Recovery study"); the assertions hold the goals stated there.
//!
//! Every truth is drawn from its seed: a failure names it, and `STUDY_SEED=N cargo test -p
//! hyst-fit --release --test timed_study -- --nocapture` runs that one case alone.

// A truth that cannot be built or run is a broken study, not a finding: it stops the test.
#![allow(clippy::expect_used)]

mod common;
use common::{identify, normals};

use hyst_fit::identify::Request;
use hyst_fit::layout::Layout;
use hyst_fit::smooth::normalisation;
use hyst_fit::{Dataset, Record, Weights};
use hyst_model::Columns;
use hyst_model::{Hold, RateTerm, SmoothModel, Structure, TimeSteps};

/// The sample period of every record (s).
const H: f64 = 1e-3;
/// Samples a record holds.
const SAMPLES: usize = 2500;
/// Samples of history run before a record that starts mid-history.
const HISTORY: usize = 733;

/// One case of the study.
#[derive(Clone, Copy, Debug)]
struct Case {
    seed: u64,
    order: u8,
    rate: bool,
    mid_history: bool,
    noise: f64,
    multi_rate: bool,
}

/// The truth's parameters by name, from the case's seed.
fn truth_values(case: &Case) -> Vec<(String, f64)> {
    let r = normals(16, case.seed);
    let u = |i: usize| 0.5 * (1.0 + (r[i] / 2.0).tanh()); // in (0, 1)
    let mut v = vec![
        ("k1".to_string(), 0.1 + 0.2 * u(0)),
        ("k2".to_string(), 8.0 + 30.0 * u(1)),
        ("out.gain".to_string(), 1.0 + 4.0 * u(2)),
        ("out.offset".to_string(), -1.0 + 2.0 * u(3)),
    ];
    // The plant: poles of time constants 2 to 40 samples.
    let mut a = vec![1.0];
    for j in 0..usize::from(case.order) {
        let tau = H * (2.0 + 38.0 * u(4 + j));
        let mut next = vec![0.0; a.len() + 1];
        for (i, c) in a.iter().enumerate() {
            next[i] += c;
            next[i + 1] += tau * c;
        }
        a = next;
    }
    for (i, c) in a.iter().enumerate().skip(1) {
        v.push((format!("dynamics.a{i}"), *c));
    }
    if case.rate {
        // A viscous force of 5 to 20 % of the output's reach at the records' slowest rate.
        v.push(("rate.c".to_string(), 0.05 + 0.15 * u(8)));
    }
    v
}

/// The record's command: a sine with an overtone, centred in [0, 4], at `f` Hz, phase from
/// the seed, over `n` samples.
fn command(f: f64, phase: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let t = k as f64 * H;
            let w = std::f64::consts::TAU * f * t + phase;
            2.0 + 1.6 * w.sin() + 0.4 * (2.7 * w).sin()
        })
        .collect()
}

struct Outcome {
    /// Parameters within two standard errors of the truth, and parameters.
    covered: (usize, usize),
    worst: (String, f64),
    rms: f64,
    noise_rms: f64,
    recovered: bool,
}

fn run(case: &Case) -> Outcome {
    // Both holds: the zero-order hold for even seeds, the first-order hold for odd ones (the
    // truth's and the fit's alike).
    let structure = Structure {
        dynamics: case.order,
        rate: case.rate.then_some(RateTerm::Viscous),
        hold: if case.seed.is_multiple_of(2) {
            Hold::Zoh
        } else {
            Hold::Foh
        },
        ..Structure::default()
    };
    let values = truth_values(case);
    // The slowest rate excites the plant: a tenth of its slowest pole's corner.
    let base = 0.4;
    let rates: Vec<f64> = if case.multi_rate {
        vec![base, 4.0 * base, 16.0 * base]
    } else {
        vec![2.0 * base]
    };
    let r = normals(8, case.seed ^ 0x5eed);
    let before = if case.mid_history { HISTORY } else { 0 };
    let commands: Vec<Vec<f64>> = rates
        .iter()
        .enumerate()
        .map(|(i, f)| command(*f, 3.0 * r[i], before + SAMPLES))
        .collect();
    let all: Vec<f64> = commands.iter().flatten().copied().collect();
    let probe = Dataset::single(&all, &vec![0.0; all.len()]);
    let layout = Layout::new(structure, normalisation(&probe));
    let mut theta = layout.start();
    for (name, v) in &values {
        let i = layout.index(name).expect("a parameter of the layout");
        theta[i] = layout.params[i].transform.theta(*v);
    }
    let model: SmoothModel = layout
        .model(&theta, probe.input_range())
        .expect("a valid truth");
    let mut outputs = Vec::new();
    for u in &commands {
        let mut y = Vec::new();
        model
            .run_timed(u, Some(&TimeSteps::even(H)), None, |_, s| y.push(s.y))
            .expect("the truth runs");
        outputs.push(y);
    }
    let (lo, hi) = outputs
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
            (a.min(*y), b.max(*y))
        });
    let sigma = case.noise * (hi - lo);
    let records: Vec<Record> = commands
        .iter()
        .zip(&outputs)
        .enumerate()
        .map(|(i, (u, y))| {
            let e = normals(y.len(), case.seed.wrapping_mul(31) + i as u64);
            let u = &u[before..];
            let y: Vec<f64> = y[before..]
                .iter()
                .zip(&e[before..])
                .map(|(y, e)| y + sigma * e)
                .collect();
            Record {
                id: i as i64,
                input: u.to_vec().into(),
                output: y.into(),
                weight: Weights::Unit(u.len()),
                rows: (0..u.len()).collect(),
                validation: false,
                continues: false,
                period: Some(TimeSteps::even(H)),
            }
        })
        .collect();
    let data = Dataset::from_records(
        "<study>",
        Columns {
            input: "u".into(),
            output: "y".into(),
            record: Some("record".into()),
            weight: None,
            time: Some("t".into()),
        },
        records,
    );
    let request = Request {
        structure,
        keep_degenerate: true,
        ..Request::default()
    };
    let identified = identify(&data, &request).expect("the fit runs");
    if std::env::var("STUDY_SEED").is_ok() {
        println!("{:#?}", identified.report.findings.notes);
    }
    let fit = identified.smooth.expect("a smooth fit");
    if std::env::var("STUDY_SEED").is_ok() {
        println!("truth {values:?}\nfit {:?}", fit.estimates);
    }
    let span = hi - lo;
    let mut worst = (String::new(), 0.0_f64);
    let mut covered = (0, 0);
    for (name, v) in &values {
        let (got, sigma) = fit
            .estimates
            .iter()
            .find(|e| e.name == *name)
            .map_or((f64::NAN, f64::NAN), |e| (e.value, e.std_error));
        covered.1 += 1;
        if (got - v).abs() <= 2.0 * sigma {
            covered.0 += 1;
        }
        // Relative error; the output offset relative to the span (it may be near 0).
        let scale = if name == "out.offset" { span } else { v.abs() };
        let err = (got - v).abs() / scale;
        if err.is_nan() || err > worst.1 {
            worst = (name.clone(), err);
        }
    }
    let noise_rms = 100.0 * case.noise;
    let rms = 100.0 * fit.training.rms / span;
    let recovered = if case.noise == 0.0 {
        worst.1 <= 0.02
    } else {
        rms <= 1.2 * noise_rms
    };
    Outcome {
        covered,
        worst,
        rms,
        noise_rms,
        recovered,
    }
}

/// The cases: every order 0–3 with and without the rate term, each start, noise 0 and
/// 0.5 %, one record or three (a 4 × 2 × 2 × 2 × 2 = 64-case factorial, seeds 1…64).
fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    let mut seed = 0;
    for order in 0..=3u8 {
        for rate in [false, true] {
            for mid_history in [false, true] {
                for noise in [0.0, 0.005] {
                    for multi_rate in [false, true] {
                        seed += 1;
                        out.push(Case {
                            seed,
                            order,
                            rate,
                            mid_history,
                            noise,
                            multi_rate,
                        });
                    }
                }
            }
        }
    }
    out
}

/// Runs the cases `which` selects (or the one `STUDY_SEED` names) and prints their rows;
/// returns (recovered, run, failures).
fn study(which: impl Fn(&Case) -> bool) -> (usize, usize, Vec<String>, (usize, usize)) {
    let only: Option<u64> = std::env::var("STUDY_SEED")
        .ok()
        .and_then(|s| s.parse().ok());
    let mut failures = Vec::new();
    let (mut ok, mut all) = (0, 0);
    // Parameters of the noisy cases within two standard errors of the truth.
    let mut covered = (0, 0);
    for case in cases()
        .iter()
        .filter(|c| only.map_or(which(c), |s| c.seed == s))
    {
        let o = run(case);
        all += 1;
        if case.noise > 0.0 {
            covered.0 += o.covered.0;
            covered.1 += o.covered.1;
        }
        let row = format!(
            "| {} | {} | {} | {} | {} % | {} | {} {:.2e} | {:.3} % | {} of {} | {} |",
            case.seed,
            case.order,
            if case.rate { "yes" } else { "no" },
            if case.mid_history {
                "mid-history"
            } else {
                "rule"
            },
            100.0 * case.noise,
            if case.multi_rate { 3 } else { 1 },
            o.worst.0,
            o.worst.1,
            o.rms,
            o.covered.0,
            o.covered.1,
            if o.recovered { "yes" } else { "NO" }
        );
        println!("{row}");
        if o.recovered {
            ok += 1;
        } else {
            failures.push(row);
        }
        let _ = o.noise_rms;
    }
    (ok, all, failures, covered)
}

/// A static structure (no plant, no rate term) is fitted by the static machinery, which keeps
/// the start rule: a record of it that starts mid-history is the one case the study does not
/// hold to its goal (docs/fitting.md: `--estimate-initial-states` estimates such starts).
fn static_mid_history(c: &Case) -> bool {
    c.order == 0 && !c.rate && c.mid_history
}

/// Runs the cases of plant order `order` and holds them to the goals, allowing the `known`
/// failures docs/fitting.md reports with their seeds.
fn check(order: u8, known: usize) {
    let (ok, all, failures, covered) = study(|c| c.order == order && !static_mid_history(c));
    println!(
        "order {order}: {ok} of {all} recovered; with noise, {} of {} parameters within two \
         standard errors of the truth",
        covered.0, covered.1
    );
    // In class, the standard errors cover the truth: 95 % expected within 2σ; the records
    // that start mid-history keep a bias of their start that the noise hides (docs/fitting.md:
    // 83 % of their parameters), so at least 80 % of an order's few dozen.
    assert!(
        covered.0 as f64 >= 0.8 * covered.1 as f64,
        "{} of {} within 2σ",
        covered.0,
        covered.1
    );
    assert!(
        failures.len() <= known,
        "not recovered:\n{}",
        failures.join("\n")
    );
}

#[test]
fn static_and_rate_truths_are_recovered() {
    // Seed 14 (rate term only, mid-history, three records): k2 6.0 % off at RMS 0.078 %.
    check(0, 1);
}

#[test]
fn first_order_truths_are_recovered() {
    check(1, 0);
}

#[test]
fn second_order_truths_are_recovered() {
    check(2, 0);
}

#[test]
fn third_order_truths_are_recovered() {
    check(3, 0);
}
