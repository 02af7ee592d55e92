//! The truths of the recovery studies (`timed_study.rs`, in class; `mismatch_study.rs`, with a
//! known mismatch): random parameters of a timed smooth model drawn from a seed, the records it
//! produces from sine commands at 1 kHz, and how a fit's estimates compare with the truth.

use hyst_test_support::rng::XorShift64Star;
use hyst_test_support::signals::normals;

use hyst_fit::layout::Layout;
use hyst_fit::smooth::normalisation;
use hyst_fit::{Dataset, Record, Weights};
use hyst_model::{Columns, Estimate, SmoothModel, Structure, TimeSteps};

/// The sample period of every record (s).
pub const H: f64 = 1e-3;
/// Samples a record holds.
pub const SAMPLES: usize = 2500;
/// Samples of history run before a record that starts mid-history.
pub const HISTORY: usize = 733;

/// The truth's parameters by name, from `seed`: plant order `order` (poles of time constants 2
/// to 40 samples), the viscous rate term when `rate`.
pub fn truth_values(seed: u64, order: u8, rate: bool) -> Vec<(String, f64)> {
    let r = normals(&mut XorShift64Star(seed), 16);
    let u = |i: usize| 0.5 * (1.0 + (r[i] / 2.0).tanh()); // in (0, 1)
    let mut v = vec![
        ("k1".to_string(), 0.1 + 0.2 * u(0)),
        ("k2".to_string(), 8.0 + 30.0 * u(1)),
        ("out.gain".to_string(), 1.0 + 4.0 * u(2)),
        ("out.offset".to_string(), -1.0 + 2.0 * u(3)),
    ];
    let mut a = vec![1.0];
    for j in 0..usize::from(order) {
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
    if rate {
        // A viscous force of 5 to 20 % of the output's reach at the records' slowest rate.
        v.push(("rate.c".to_string(), 0.05 + 0.15 * u(8)));
    }
    v
}

/// The record's command: a sine with an overtone, centred in [0, 4], at `f` Hz, phase
/// `phase`, over `n` samples.
pub fn command(f: f64, phase: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let t = k as f64 * H;
            let w = std::f64::consts::TAU * f * t + phase;
            2.0 + 1.6 * w.sin() + 0.4 * (2.7 * w).sin()
        })
        .collect()
}

/// The commands of a truth's records: one at 0.8 Hz, or three at 0.4, 1.6 and 6.4 Hz (the
/// slowest a tenth of the slowest pole's corner), phases from `seed`, each `before` samples of
/// history longer than [`SAMPLES`].
pub fn commands(seed: u64, multi_rate: bool, before: usize) -> Vec<Vec<f64>> {
    let base = 0.4;
    let rates: Vec<f64> = if multi_rate {
        vec![base, 4.0 * base, 16.0 * base]
    } else {
        vec![2.0 * base]
    };
    let r = normals(&mut XorShift64Star(seed ^ 0x5eed), 8);
    rates
        .iter()
        .enumerate()
        .map(|(i, f)| command(*f, 3.0 * r[i], before + SAMPLES))
        .collect()
}

/// The model of `structure` with the parameters `values`, normalised over `commands`.
pub fn truth_model(
    structure: Structure,
    values: &[(String, f64)],
    commands: &[Vec<f64>],
) -> SmoothModel {
    let all: Vec<f64> = commands.iter().flatten().copied().collect();
    let probe = Dataset::single(&all, &vec![0.0; all.len()]);
    let layout = Layout::new(structure, normalisation(&probe));
    let mut theta = layout.start();
    for (name, v) in values {
        let i = layout.index(name).expect("a parameter of the layout");
        theta[i] = layout.params[i].transform.theta(*v);
    }
    layout
        .model(&theta, probe.input_range())
        .expect("a valid truth")
}

/// The outputs of `model` on each command, from the start rule, at [`H`].
pub fn outputs(model: &SmoothModel, commands: &[Vec<f64>]) -> Vec<Vec<f64>> {
    commands
        .iter()
        .map(|u| {
            let mut y = Vec::new();
            model
                .run_timed(u, Some(&TimeSteps::even(H)), None, |_, s| y.push(s.y))
                .expect("the truth runs");
            y
        })
        .collect()
}

/// The lowest and highest of `outputs`.
pub fn range(outputs: &[Vec<f64>]) -> (f64, f64) {
    outputs
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
            (a.min(*y), b.max(*y))
        })
}

/// The records from sample `before` on of each command and output, with normal noise of
/// standard deviation `sigma` drawn from `seed`.
pub fn dataset(
    commands: &[Vec<f64>],
    outputs: &[Vec<f64>],
    before: usize,
    sigma: f64,
    seed: u64,
) -> Dataset {
    let records: Vec<Record> = commands
        .iter()
        .zip(outputs)
        .enumerate()
        .map(|(i, (u, y))| {
            let e = normals(
                &mut XorShift64Star(seed.wrapping_mul(31) + i as u64),
                y.len(),
            );
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
    Dataset::from_records(
        "<study>",
        Columns {
            input: "u".into(),
            output: "y".into(),
            record: Some("record".into()),
            weight: None,
            time: Some("t".into()),
        },
        records,
    )
}

/// How a fit's estimates compare with the truth.
pub struct Comparison {
    /// Parameters within two standard errors of the truth, and parameters.
    pub covered: (usize, usize),
    /// The parameter furthest from the truth and its relative error (the output offset's
    /// relative to `span`).
    pub worst: (String, f64),
    /// The parameters outside two standard errors: name and distance in standard errors.
    pub missed: Vec<(String, f64)>,
}

/// Compares `estimates` with the truth `values`; `span` is the output's range.
pub fn compare(values: &[(String, f64)], estimates: &[Estimate], span: f64) -> Comparison {
    let mut out = Comparison {
        covered: (0, 0),
        worst: (String::new(), 0.0),
        missed: Vec::new(),
    };
    for (name, v) in values {
        let (got, sigma) = estimates
            .iter()
            .find(|e| e.name == *name)
            .map_or((f64::NAN, f64::NAN), |e| (e.value, e.std_error));
        out.covered.1 += 1;
        let z = (got - v).abs() / sigma;
        if z <= 2.0 {
            out.covered.0 += 1;
        } else {
            out.missed.push((name.clone(), z));
        }
        let scale = if name == "out.offset" { span } else { v.abs() };
        let err = (got - v).abs() / scale;
        if err.is_nan() || err > out.worst.1 {
            out.worst = (name.clone(), err);
        }
    }
    out
}

/// Asserts that at least `share` of the parameters lie within two standard errors of the
/// truth (`covered`: those within, all).
pub fn assert_covered(covered: (usize, usize), share: f64) {
    assert!(
        covered.0 as f64 >= share * covered.1 as f64,
        "{} of {} parameters within two standard errors",
        covered.0,
        covered.1
    );
}
