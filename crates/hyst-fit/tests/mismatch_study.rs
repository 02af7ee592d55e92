//! The standard errors under a known mismatch: random truths of plant order 1–3, with and
//! without the viscous rate term, three records at rates 1 : 4 : 16 with noise of 0.5 % of the
//! span, fitted by `identify` with the truth's structure and its defaults, where the records
//! differ from what the model assumes in one known way:
//!
//! - **start**: each record starts after unrecorded motion (mid-history), not from the start
//!   rule;
//! - **hold**: the actuator holds its command the other way than the fit assumes (zero-order
//!   against first-order hold);
//! - **creep**: the output creeps: a slow first-order lag of the command (time constant 1.5 s,
//!   1 % of the span per volt) that no part of the model represents.
//!
//! Each case prints one row of the table in docs/fitting.md ("Standard errors under a known
//! mismatch"); the assertion holds the goal stated there. `STUDY_SEED=N cargo test -p hyst-fit
//! --release --test mismatch_study -- --nocapture` runs one case alone.

// A truth that cannot be built or run is a broken study, not a finding: it stops the test.
#![allow(clippy::expect_used)]

mod common;
mod study;
use common::identify;
use study::{
    assert_covered, commands, compare, dataset, outputs, range, truth_model, truth_values, H,
    HISTORY,
};

use hyst_fit::identify::Request;
use hyst_model::{Hold, RateTerm, Structure};

/// The noise of every case, a share of the output's span.
const NOISE: f64 = 0.005;

/// How the records differ from the model's assumptions.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mismatch {
    Start,
    Hold,
    Creep,
}

#[derive(Clone, Copy, Debug)]
struct Case {
    seed: u64,
    order: u8,
    rate: bool,
    mismatch: Mismatch,
}

/// Parameters within two standard errors, parameters, the training RMS error (% of the span)
/// and the row of the table.
fn run(case: &Case) -> ((usize, usize), f64, String) {
    let fit_hold = if case.seed.is_multiple_of(2) {
        Hold::Zoh
    } else {
        Hold::Foh
    };
    let truth_hold = match (case.mismatch, fit_hold) {
        (Mismatch::Hold, Hold::Zoh) => Hold::Foh,
        (Mismatch::Hold, Hold::Foh) => Hold::Zoh,
        (_, h) => h,
    };
    let structure = Structure {
        dynamics: case.order,
        rate: case.rate.then_some(RateTerm::Viscous),
        hold: truth_hold,
        ..Structure::default()
    };
    let values = truth_values(case.seed, case.order, case.rate);
    let before = if case.mismatch == Mismatch::Start {
        HISTORY
    } else {
        0
    };
    let commands = commands(case.seed, true, before);
    let model = truth_model(structure, &values, &commands);
    let mut outputs = outputs(&model, &commands);
    let (lo, hi) = range(&outputs);
    let span = hi - lo;
    if case.mismatch == Mismatch::Creep {
        // w' = (u − w) / τ, exact for a held command; 1 % of the span per volt of w − 2.
        let a = (-H / 1.5_f64).exp();
        for (u, y) in commands.iter().zip(&mut outputs) {
            let mut w = 2.0;
            for (u, y) in u.iter().zip(y.iter_mut()) {
                *y += 0.01 * span * (w - 2.0);
                w = a * w + (1.0 - a) * u;
            }
        }
    }
    let data = dataset(&commands, &outputs, before, NOISE * span, case.seed);
    let request = Request {
        structure: Structure {
            hold: fit_hold,
            ..structure
        },
        keep_degenerate: true,
        ..Request::default()
    };
    let identified = identify(&data, &request).expect("the fit runs");
    let fit = identified.smooth.expect("a smooth fit");
    if std::env::var("STUDY_SEED").is_ok() {
        println!("{:#?}", identified.report.findings.notes);
        println!("truth {values:?}\nfit {:?}", fit.estimates);
    }
    let c = compare(&values, &fit.estimates, span);
    let missed: Vec<String> = c
        .missed
        .iter()
        .map(|(name, z)| format!("{name} {z:.1}σ"))
        .collect();
    let rms = 100.0 * fit.training.rms / span;
    let row = format!(
        "| {} | {} | {} | {} | {rms:.3} % | {} of {} | {} |",
        case.seed,
        match case.mismatch {
            Mismatch::Start => "start",
            Mismatch::Hold => "hold",
            Mismatch::Creep => "creep",
        },
        case.order,
        if case.rate { "yes" } else { "no" },
        c.covered.0,
        c.covered.1,
        if missed.is_empty() {
            "—".to_string()
        } else {
            missed.join(", ")
        }
    );
    (c.covered, rms, row)
}

/// The cases of one mismatch: orders 1–3, with and without the rate term, two seeds each but
/// for order 1 without and order 3 with the rate term (10 cases a mismatch, 30 in all; seeds
/// 101…136, the Start cases first, then Hold, then Creep, 12 seeds each).
fn cases(mismatch: Mismatch) -> Vec<Case> {
    let first = match mismatch {
        Mismatch::Start => 100,
        Mismatch::Hold => 112,
        Mismatch::Creep => 124,
    };
    let mut out = Vec::new();
    let mut seed = first;
    for order in 1..=3u8 {
        for rate in [false, true] {
            for repeat in 0..2 {
                seed += 1;
                if repeat == 1 && ((order == 1 && !rate) || (order == 3 && rate)) {
                    continue;
                }
                out.push(Case {
                    seed,
                    order,
                    rate,
                    mismatch,
                });
            }
        }
    }
    out
}

/// Runs the cases of `mismatch` (or the one `STUDY_SEED` names), prints their rows and holds
/// them to the goals: at least 90 % of the parameters, and of the truths whole, within two
/// standard errors; the records that start mid-history fitted to the noise.
fn check(mismatch: Mismatch) {
    let only: Option<u64> = std::env::var("STUDY_SEED")
        .ok()
        .and_then(|s| s.parse().ok());
    let (mut covered, mut cases_covered, mut all) = ((0, 0), 0, 0);
    let mut unsettled = Vec::new();
    for case in cases(mismatch)
        .iter()
        .filter(|c| only.is_none_or(|s| c.seed == s))
    {
        let (c, rms, row) = run(case);
        println!("{row}");
        covered.0 += c.0;
        covered.1 += c.1;
        all += 1;
        if c.0 == c.1 {
            cases_covered += 1;
        }
        // A start mid-history is in the model's class once discounted: the fit reaches the
        // noise.
        if case.mismatch == Mismatch::Start && rms > 1.2 * 100.0 * NOISE {
            unsettled.push(row);
        }
    }
    println!(
        "{mismatch:?}: {} of {} parameters within two standard errors of the truth; \
         {cases_covered} of {all} cases with every parameter within",
        covered.0, covered.1
    );
    assert_covered(covered, 0.9);
    assert!(
        cases_covered as f64 >= 0.9 * all as f64,
        "{cases_covered} of {all} cases covered"
    );
    assert!(
        unsettled.is_empty(),
        "above the noise:\n{}",
        unsettled.join("\n")
    );
}

#[test]
fn standard_errors_cover_the_truth_of_records_that_start_mid_history() {
    check(Mismatch::Start);
}

#[test]
fn standard_errors_cover_the_truth_under_the_other_hold() {
    check(Mismatch::Hold);
}

#[test]
fn standard_errors_cover_the_truth_of_records_that_creep() {
    check(Mismatch::Creep);
}
