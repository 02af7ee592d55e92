//! `hyst fit --dynamics N` and `hyst run --inverse` of a model with dynamics, against synthetic
//! truths (docs/fitting.md, "Dynamics and rate"): the paper's Example 2 (a first-order RL
//! plant before the hysteresis) and Example 3's mass-spring-damper (second order) before a
//! near-hard backlash. Each prints the figures docs/fitting.md states.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

use std::path::Path;
use std::process::Command;

use hyst_core::{Hysteresis, Identity, InitialState, Operator, QuadraticExp, ShapedModel};

const HYST: &str = env!("CARGO_BIN_EXE_hyst");

/// Deterministic standard normal numbers (SplitMix64 and Box–Muller).
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (a, b) = (self.uniform(), self.uniform());
        (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
    }
}

/// A linear plant a_n v⁽ⁿ⁾ + … + a_1 v̇ + v = u driven by the continuous command `u(t)`,
/// sampled every `h` from rest at u(0): RK4 with 20 steps per sample.
fn plant(a: &[f64], u: &dyn Fn(f64) -> f64, h: f64, samples: usize) -> Vec<f64> {
    let n = a.len();
    let mut x = vec![0.0; n];
    x[0] = u(0.0);
    let f = |t: f64, x: &[f64]| -> Vec<f64> {
        let mut d: Vec<f64> = x[1..].to_vec();
        let mut top = u(t) - x[0];
        for i in 1..n {
            top -= a[i - 1] * x[i];
        }
        d.push(top / a[n - 1]);
        d
    };
    let mut out = vec![x[0]];
    let steps = 20;
    let dt = h / f64::from(steps);
    for k in 1..samples {
        for j in 0..steps {
            let t = (k - 1) as f64 * h + f64::from(j) * dt;
            let add = |x: &[f64], d: &[f64], s: f64| -> Vec<f64> {
                x.iter().zip(d).map(|(x, d)| x + s * d).collect()
            };
            let k1 = f(t, &x);
            let k2 = f(t + dt / 2.0, &add(&x, &k1, dt / 2.0));
            let k3 = f(t + dt / 2.0, &add(&x, &k2, dt / 2.0));
            let k4 = f(t + dt, &add(&x, &k3, dt));
            for i in 0..n {
                x[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        out.push(x[0]);
    }
    out
}

/// The truth's hysteresis output ψ(H[v]) along `v`, started as after a rise.
fn hysteresis(model: &mut impl Operator<f64>, v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| model.try_step(*x).unwrap()).collect()
}

fn example2_model(first: f64) -> impl Operator<f64> {
    let h = InitialState::Rising
        .start(Hysteresis::new(0.06, 5.0).unwrap(), first)
        .unwrap();
    ShapedModel::new(Identity, h, QuadraticExp::<f64>::example2().unwrap()).unwrap()
}

/// A multisine about `centre` with amplitude `amp`, phases set by `seed`.
fn multisine(centre: f64, amp: f64, freqs: &'static [f64], seed: f64) -> impl Fn(f64) -> f64 {
    move |t: f64| {
        let s: f64 = freqs
            .iter()
            .enumerate()
            .map(|(i, f)| (2.0 * std::f64::consts::PI * f * t + seed * (i as f64 + 1.0)).sin())
            .sum();
        // Start at rest: the envelope rises over the first half second.
        let ramp = (t / 0.5).min(1.0);
        centre + amp * ramp * s / freqs.len() as f64
    }
}

fn write_csv(path: &Path, header: &str, rows: &[Vec<f64>]) {
    let mut text = format!("{header}\n");
    for r in rows {
        let line: Vec<String> = r.iter().map(|v| format!("{v:e}")).collect();
        text.push_str(&line.join(","));
        text.push('\n');
    }
    std::fs::write(path, text).unwrap();
}

fn hyst(args: &[&str]) -> String {
    let out = Command::new(HYST).args(args).output().unwrap();
    assert!(
        out.status.success(),
        "hyst {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn read_column(path: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(at).unwrap().parse().unwrap())
        .collect()
}

const FREQS: &[f64] = &[0.31, 0.77, 1.6, 3.3, 6.1];

/// Example 2 as a truth: L İ = −R I + U (R = 1 Ω, L = 0.1 H), Φ = ψ(H(0.06, 5)[I]) with the
/// paper's quadratic-exp ψ (fitted with a cubic ψ_out, which represents it on this range to the
/// noise), driven by multisines at three amplitudes with 0.1 % noise.
/// `--dynamics 1` recovers L/R within 2 % and k1, k2 within 5 %; the compensator of a new
/// reference keeps the flux error through the true plant within 1 % of span.
#[test]
fn example2_first_order_plant_is_identified_and_compensated() {
    let dir = tempfile::tempdir().unwrap();
    let h = 1e-3;
    let samples = 6000;
    let mut noise = Noise(7);
    let mut rows = Vec::new();
    let mut span: (f64, f64) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut clean = Vec::new();
    for (record, amp) in [0.9, 1.6, 2.3].into_iter().enumerate() {
        let u = multisine(2.0, amp, FREQS, 1.0 + record as f64);
        let current = plant(&[0.1], &u, h, samples);
        let phi = hysteresis(&mut example2_model(current[0]), &current);
        for k in 0..samples {
            span = (span.0.min(phi[k]), span.1.max(phi[k]));
            clean.push((record, k as f64 * h, u(k as f64 * h), phi[k]));
        }
    }
    let sigma = 1e-3 * (span.1 - span.0);
    for (record, t, u, phi) in clean {
        rows.push(vec![record as f64, t, u, phi + sigma * noise.normal()]);
    }
    let data = dir.path().join("rl.csv");
    write_csv(&data, "record,t,u,phi", &rows);
    if let Ok(keep) = std::env::var("HYST_KEEP") {
        std::fs::copy(&data, Path::new(&keep).join("rl.csv")).unwrap();
    }

    // Fits: with the plant, and static for comparison.
    let model = dir.path().join("m.toml");
    let report = hyst(&[
        "fit",
        data.to_str().unwrap(),
        "--input",
        "u",
        "--output",
        "phi",
        "--output-shaping",
        "poly3",
        "--dynamics",
        "1",
        "--json",
        "-o",
        model.to_str().unwrap(),
    ]);
    let json: serde_json::Value = serde_json::from_str(&report).unwrap();
    let a1 = json["model"]["dynamics"]["a"][0].as_f64().unwrap();
    let a1_se = json["model"]["dynamics"]["a_std_error"][0]
        .as_f64()
        .unwrap();
    let smooth = &json["model"]["smooth"];
    let slope = smooth["input_shaping"]["pre_gain"].as_f64().unwrap()
        * smooth["input_shaping"]["post_gain"].as_f64().unwrap();
    let k1 = smooth["k1"].as_f64().unwrap() / slope;
    let k2 = smooth["k2"]["value"].as_f64().unwrap() * slope;
    let rms = json["model"]["metrics"]["training"]["rms_pct_span"]
        .as_f64()
        .unwrap();
    println!(
        "example 2, --dynamics 1: L/R = {a1:.5} ± {a1_se:.1e} s (truth 0.1), k1 = {k1:.5} \
         (0.06), k2 = {k2:.4} (5), training RMS {rms:.3} % of span"
    );
    assert!((a1 / 0.1 - 1.0).abs() < 0.02, "L/R {a1}");
    assert!((k1 / 0.06 - 1.0).abs() < 0.05, "k1 {k1}");
    assert!((k2 / 5.0 - 1.0).abs() < 0.05, "k2 {k2}");
    assert_eq!(json["model"]["version"].as_u64(), Some(4));
    assert_eq!(
        json["model"]["dynamics"]["identified"][0].as_bool(),
        Some(true)
    );

    let static_model = dir.path().join("static.toml");
    hyst(&[
        "fit",
        data.to_str().unwrap(),
        "--input",
        "u",
        "--output",
        "phi",
        "--output-shaping",
        "poly3",
        "-o",
        static_model.to_str().unwrap(),
    ]);

    // A new reference (other frequencies and phases), its derivative in a column.
    let reference = |t: f64| 2.0 + 1.5 * (t / 0.5).min(1.0) * (0.9 * t).sin() * (0.37 * t).cos();
    let n: usize = 8000;
    let desired_current: Vec<f64> = (0..n).map(|k| reference(k as f64 * h)).collect();
    let desired = hysteresis(&mut example2_model(desired_current[0]), &desired_current);
    let deriv: Vec<f64> = (0..n)
        .map(|k| {
            // The desired flux's derivative by central differences of the exact flux (the
            // truth's, so that the reference is reachable); one-sided at the ends.
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
            (desired[b] - desired[a]) / ((b - a) as f64 * h)
        })
        .collect();
    let target = dir.path().join("desired.csv");
    let rows: Vec<Vec<f64>> = (0..n)
        .map(|k| vec![k as f64 * h, desired[k], deriv[k]])
        .collect();
    write_csv(&target, "t,phi,phi_d1", &rows);
    let (lo, hi) = desired
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
            (a.min(*y), b.max(*y))
        });
    let through_truth = |command: &[f64]| -> f64 {
        // The command linear between samples, through the true plant and hysteresis.
        let u = |t: f64| {
            let k = ((t / h).floor() as usize).min(command.len() - 2);
            let f = t / h - k as f64;
            command[k] + f * (command[k + 1] - command[k])
        };
        let current = plant(&[0.1], &u, h, command.len());
        let phi = hysteresis(&mut example2_model(current[0]), &current);
        phi.iter()
            .zip(&desired)
            .skip(1)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
            / (hi - lo)
    };
    let out = dir.path().join("command.csv");
    hyst(&[
        "run",
        "--model",
        model.to_str().unwrap(),
        "--inverse",
        target.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let dynamic_error = through_truth(&read_column(&out, "y"));
    let out_static = dir.path().join("command-static.csv");
    hyst(&[
        "run",
        "--model",
        static_model.to_str().unwrap(),
        "--inverse",
        "--column",
        "phi",
        target.to_str().unwrap(),
        "-o",
        out_static.to_str().unwrap(),
    ]);
    let static_error = through_truth(&read_column(&out_static, "y"));
    println!(
        "example 2, compensation of a new reference through the true plant: max flux error \
         {:.3} % of span with the fitted plant, {:.2} % with the static model",
        100.0 * dynamic_error,
        100.0 * static_error
    );
    assert!(dynamic_error < 0.01, "{dynamic_error}");
    assert!(static_error > 2.0 * dynamic_error, "{static_error}");
}
