//! `hyst fit --dynamics N` and `hyst run --inverse` of a model with dynamics, against synthetic
//! truths (docs/fitting.md, "Dynamics and rate"): the paper's Example 2 (a first-order RL
//! plant before the hysteresis) and Example 3's mass-spring-damper (second order) before a
//! near-hard backlash. Each prints the figures docs/fitting.md states.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::needless_range_loop
)]

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

/// A static fit of `y` against `x` (columns u, y) written to `model`, given the plant
/// `[dynamics] a = A` (b = 1) by hand (format version 4).
fn fit_with_plant(dir: &Path, x: &[f64], y: &[f64], a: &str, model: &Path) {
    let rows: Vec<Vec<f64>> = x.iter().zip(y).map(|(&x, &y)| vec![x, y]).collect();
    let data = dir.join("s.csv");
    write_csv(&data, "u,y", &rows);
    hyst(&[
        "fit",
        data.to_str().unwrap(),
        "--input",
        "u",
        "--output",
        "y",
        "-o",
        model.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(model)
        .unwrap()
        .replace("version = 1", "version = 4")
        + &format!("\n[dynamics]\nb = 1.0\na = {a}\n");
    std::fs::write(model, text).unwrap();
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
        // The truth's command is continuous (a multisine): linear between samples is its hold.
        "--hold",
        "foh",
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
    // The command is named after the model's input column.
    let dynamic_error = through_truth(&read_column(&out, "u"));
    // The file records the period the records were sampled at, and a record whose time is in
    // milliseconds (read as seconds: 1000 × the period) runs with a note saying so.
    let periods = &json["model"]["provenance"]["sample_periods"];
    for end in 0..2 {
        let p = periods[end].as_f64().unwrap();
        assert!((p / h - 1.0).abs() < 1e-9, "sample_periods {periods}");
    }
    let in_ms: Vec<Vec<f64>> = rows.iter().map(|r| vec![r[0] * 1e3, r[1], r[2]]).collect();
    let target_ms = dir.path().join("desired-ms.csv");
    write_csv(&target_ms, "t,phi,phi_d1", &in_ms);
    for (file, noted) in [(&target, false), (&target_ms, true)] {
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_hyst"))
            .args(["run", "--model", model.to_str().unwrap(), "--inverse"])
            .arg(file)
            .args(["-o", dir.path().join("c.csv").to_str().unwrap()])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{err}");
        assert_eq!(
            err.contains("record 1: the record's sample period 1.000e0 s is 1000 × longer than \
                          the period the model was fitted at (1.000e-3 s): is the time column in seconds?"),
            noted,
            "{err}"
        );
    }
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
    let static_error = through_truth(&read_column(&out_static, "u"));
    println!(
        "example 2, compensation of a new reference through the true plant: max flux error \
         {:.3} % of span with the fitted plant, {:.2} % with the static model",
        100.0 * dynamic_error,
        100.0 * static_error
    );
    assert!(dynamic_error < 0.01, "{dynamic_error}");
    assert!(static_error > 2.0 * dynamic_error, "{static_error}");
}

/// Example 3's plant m ẍ + c ẋ + k x = k u (m = 1, c = 0.9, k = 1: a_1 = 0.9 s, a_2 = 1 s²)
/// before a near-hard backlash H(0.2, 40): `--dynamics 2` recovers a_1 and a_2 within 5 %.
#[test]
fn second_order_plant_before_a_backlash_is_identified() {
    let dir = tempfile::tempdir().unwrap();
    let h = 0.01;
    let samples = 6000;
    let mut noise = Noise(11);
    let mut rows = Vec::new();
    const SLOW: &[f64] = &[0.05, 0.11, 0.19, 0.31, 0.53];
    for (record, amp) in [0.8, 1.4, 2.0].into_iter().enumerate() {
        let u = multisine(0.0, amp, SLOW, 2.0 + record as f64);
        let x = plant(&[0.9, 1.0], &u, h, samples);
        let mut backlash = InitialState::Rising
            .start(Hysteresis::new(0.2, 40.0).unwrap(), x[0])
            .unwrap();
        let y = hysteresis(&mut backlash, &x);
        for k in 0..samples {
            let t = k as f64 * h;
            rows.push(vec![record as f64, t, u(t), y[k] + 1e-3 * noise.normal()]);
        }
    }
    let data = dir.path().join("msd.csv");
    write_csv(&data, "record,t,u,y", &rows);
    let model = dir.path().join("m.toml");
    let report = hyst(&[
        "fit",
        data.to_str().unwrap(),
        "--input",
        "u",
        "--output",
        "y",
        "--dynamics",
        "2",
        // The truth's command is continuous: linear between samples is its hold.
        "--hold",
        "foh",
        "--json",
        "-o",
        model.to_str().unwrap(),
    ]);
    let json: serde_json::Value = serde_json::from_str(&report).unwrap();
    let a = &json["model"]["dynamics"]["a"];
    let (a1, a2) = (a[0].as_f64().unwrap(), a[1].as_f64().unwrap());
    println!("example 3's plant, --dynamics 2: a1 = {a1:.4} s (0.9), a2 = {a2:.4} s² (1)");
    assert!((a1 / 0.9 - 1.0).abs() < 0.05, "a1 {a1}");
    assert!((a2 - 1.0).abs() < 0.05, "a2 {a2}");
    let identified = &json["model"]["dynamics"]["identified"];
    assert_eq!(identified, &serde_json::json!([true, true]));
}

/// Records of a static truth do not identify a plant: the report says a_1 is not identified
/// and why, instead of printing a time constant.
#[test]
fn a_plant_the_records_do_not_excite_is_reported_not_identified() {
    let dir = tempfile::tempdir().unwrap();
    let h = 1e-3;
    let mut noise = Noise(3);
    let u = multisine(2.0, 1.5, &[0.05, 0.13], 1.0);
    let v: Vec<f64> = (0..4000).map(|k| u(k as f64 * h)).collect();
    let phi = hysteresis(&mut example2_model(v[0]), &v);
    let rows: Vec<Vec<f64>> = (0..v.len())
        .map(|k| vec![k as f64 * h, v[k], phi[k] + 2e-3 * noise.normal()])
        .collect();
    let data = dir.path().join("slow.csv");
    write_csv(&data, "t,u,phi", &rows);
    let model = dir.path().join("m.toml");
    let args = [
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
        "-o",
        model.to_str().unwrap(),
    ];
    let text = hyst(&args);
    assert!(text.contains("dynamics.a1 not identified"), "{text}");
    assert!(!text.contains("dynamics.a1 = "), "{text}");
    // The parameter table prints no value for it either.
    let row = text
        .lines()
        .find(|l| l.trim_start().starts_with("dynamics.a1 "))
        .unwrap();
    assert!(row.contains("not identified"), "{row}");
    let json: serde_json::Value =
        serde_json::from_str(&hyst(&[&args[..], &["--json"]].concat())).unwrap();
    assert_eq!(
        json["model"]["dynamics"]["identified"][0].as_bool(),
        Some(false)
    );
}

/// Time stamps that repeat, go back or are uneven are refused with the line and value; so is
/// a file without a time column when dynamics are asked for; nothing is written.
#[test]
fn bad_time_stamps_are_refused_with_their_line() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.toml");
    let cases = [
        (
            "t,u,y\n0,0,0\n0.1,1,1\n0.1,2,3\n0.3,1,2\n",
            "d.csv:4:",
            "repeats",
        ),
        (
            "t,u,y\n0,0,0\n0.1,1,1\n0.05,2,3\n0.3,1,2\n",
            "d.csv:4:",
            "goes back",
        ),
        (
            "t,u,y\n1700000000,0,0\n1700000000.000001,1,1\n1700000000.000002,2,3\n",
            "d.csv:2:",
            "t − t0",
        ),
        ("u,y\n0,0\n1,1\n2,3\n1,2\n", "--time", "time column"),
    ];
    for (text, at, what) in cases {
        let data = dir.path().join("d.csv");
        std::fs::write(&data, text).unwrap();
        let out = Command::new(HYST)
            .args([
                "fit",
                data.to_str().unwrap(),
                "--input",
                "u",
                "--output",
                "y",
            ])
            .args(["--dynamics", "1", "-o", model.to_str().unwrap()])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert!(err.contains(at) && err.contains(what), "{text}: {err}");
        assert!(!model.exists());
    }
}

/// `--prefilter-hz`: without derivative columns the compensator tracks the prefiltered
/// reference, which the forward model (`hyst run` of the command) reproduces.
#[test]
fn prefilter_gives_a_command_that_tracks_the_filtered_reference() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.toml");
    // A static fit of a simple truth, given a plant by hand (format version 4).
    let u = multisine(1.0, 1.0, FREQS, 0.5);
    let x: Vec<f64> = (0..3000).map(|k| u(k as f64 * 1e-3)).collect();
    let mut truth = InitialState::Rising
        .start(Hysteresis::new(0.1, 5.0).unwrap(), x[0])
        .unwrap();
    let y = hysteresis(&mut truth, &x);
    let y: Vec<f64> = y.iter().map(|v| 2.0 * v).collect();
    fit_with_plant(dir.path(), &x, &y, "[0.05, 0.001]", &model);
    let h = 1e-3;
    let rows: Vec<Vec<f64>> = (0..3000)
        .map(|k| {
            let t = k as f64 * h;
            vec![
                t,
                if t < 0.5 {
                    0.0
                } else {
                    1.0 + 0.5 * (3.0 * t).sin()
                },
            ]
        })
        .collect();
    let desired = dir.path().join("d.csv");
    write_csv(&desired, "t,y", &rows);
    let command = dir.path().join("c.csv");
    let out = Command::new(HYST)
        .args(["run", "--model", model.to_str().unwrap(), "--inverse"])
        .args([desired.to_str().unwrap(), "-o", command.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("--prefilter-hz"),
        "{err}"
    );
    hyst(&[
        "run",
        "--model",
        model.to_str().unwrap(),
        "--inverse",
        "--prefilter-hz",
        "5",
        desired.to_str().unwrap(),
        "-o",
        command.to_str().unwrap(),
    ]);
    // INPUT's columns, the command (the model's input column) and the prefiltered reference.
    let header = std::fs::read_to_string(&command).unwrap();
    assert_eq!(header.lines().next(), Some("t,y,u,y_filtered"));
    let u = read_column(&command, "u");
    let filtered = read_column(&command, "y_filtered");
    let forward_in: Vec<Vec<f64>> = (0..u.len()).map(|k| vec![k as f64 * h, u[k]]).collect();
    let commands = dir.path().join("u.csv");
    write_csv(&commands, "t,u", &forward_in);
    let back = dir.path().join("back.csv");
    hyst(&[
        "run",
        "--model",
        model.to_str().unwrap(),
        commands.to_str().unwrap(),
        "-o",
        back.to_str().unwrap(),
    ]);
    assert_eq!(
        std::fs::read_to_string(&back).unwrap().lines().next(),
        Some("t,u,y")
    );
    let y = read_column(&back, "y");
    let worst = y
        .iter()
        .zip(&filtered)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("prefilter 5 Hz: the model driven by the command follows the filtered reference within {worst:.2e}");
    assert!(worst < 5e-3, "{worst}");
}

/// `hyst ARGS`, expected to fail: its stderr; OUTPUT (`-o` of ARGS, the last argument) is not
/// written.
fn refused(args: &[&str]) -> String {
    let out = Command::new(HYST).args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "hyst {args:?} succeeded");
    assert!(!Path::new(args.last().unwrap()).exists(), "{args:?}");
    err
}

/// `--prefilter-hz F` is checked whenever it is given: a finite, positive frequency (with the
/// derivative columns in the file, which the compensator then takes instead, and with --k1/--k2,
/// which refuse it), at most 1/20 of the Nyquist frequency of the record's sample period (25 Hz
/// at 1 kHz). At that bound the plant of order 2 driven by the commands follows the prefiltered
/// reference of a step within 0.5 % of its span; above it the commands grow without bound
/// (5e11 Hz at 1 kHz would give commands of 4e10 for outputs of 20).
#[test]
fn prefilter_bandwidth_is_checked_whenever_given() {
    let dir = tempfile::tempdir().unwrap();
    let model = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/firmware/models/piezo_dyn.toml")
        .to_str()
        .unwrap()
        .to_string();
    let h = 1e-3;
    let desired = |t: f64| {
        if t < 0.5 {
            -110.0
        } else {
            -100.0 + 10.0 * (3.0 * t).sin()
        }
    };
    let rows: Vec<Vec<f64>> = (0..3000)
        .map(|k| vec![k as f64 * h, desired(k as f64 * h)])
        .collect();
    let plain = dir.path().join("d.csv");
    write_csv(&plain, "t,y_capsensor_um", &rows);
    let with_derivatives = dir.path().join("dd.csv");
    let rows_d: Vec<Vec<f64>> = rows.iter().map(|r| vec![r[0], r[1], 0.0, 0.0]).collect();
    write_csv(
        &with_derivatives,
        "t,y_capsensor_um,y_capsensor_um_d1,y_capsensor_um_d2",
        &rows_d,
    );
    let (plain, with_derivatives) = (plain.to_str().unwrap(), with_derivatives.to_str().unwrap());
    let command = dir.path().join("c.csv");
    let command = command.to_str().unwrap();
    // Just below the bound: the model driven by the commands follows the filtered reference.
    hyst(&[
        "run",
        "--model",
        &model,
        "--inverse",
        "--prefilter-hz",
        "24.9",
        plain,
        "-o",
        command,
    ]);
    let u = read_column(Path::new(command), "u_actuator_V");
    let filtered = read_column(Path::new(command), "y_capsensor_um_filtered");
    let forward: Vec<Vec<f64>> = u
        .iter()
        .enumerate()
        .map(|(k, u)| vec![k as f64 * h, *u])
        .collect();
    let commands = dir.path().join("u.csv");
    write_csv(&commands, "t,u_actuator_V", &forward);
    let back = dir.path().join("y.csv");
    hyst(&[
        "run",
        "--model",
        &model,
        commands.to_str().unwrap(),
        "-o",
        back.to_str().unwrap(),
    ]);
    let y = read_column(&back, "y_capsensor_um");
    let span = filtered.iter().copied().fold(f64::MIN, f64::max)
        - filtered.iter().copied().fold(f64::MAX, f64::min);
    let worst = y
        .iter()
        .zip(&filtered)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!(
        "prefilter 24.9 Hz at 1 kHz: the model driven by the commands follows the filtered \
         reference within {:.3} % of its span",
        100.0 * worst / span
    );
    assert!(worst < 5e-3 * span, "{worst} of {span}");
    std::fs::remove_file(command).unwrap();
    // Above it: refused, with the bound and the reason, with or without derivative columns.
    for (hz, data) in [("26", plain), ("1e12", plain), ("1e12", with_derivatives)] {
        let err = refused(&[
            "run",
            "--model",
            &model,
            "--inverse",
            "--prefilter-hz",
            hz,
            data,
            "-o",
            command,
        ]);
        assert!(
            err.contains(&format!("--prefilter-hz {hz}: above 25 Hz")) && err.contains("Nyquist"),
            "{err}"
        );
    }
    // A value that is no bandwidth: refused wherever it is given, naming the flag and the value.
    for bad in ["nan", "-1", "0", "inf"] {
        for args in [
            &["--model", &model, "--inverse", with_derivatives][..],
            &["--k1", "0.2", "--k2", "8", plain][..],
        ] {
            let mut all = vec!["run", "--prefilter-hz", bad];
            all.extend(args);
            all.extend(["-o", command]);
            let err = refused(&all);
            assert!(
                err.contains("--prefilter-hz") && err.contains(bad) && err.contains("positive"),
                "{bad}: {err}"
            );
        }
    }
    // A bandwidth for an operator that has no plant: refused.
    let err = refused(&[
        "run",
        "--k1",
        "0.2",
        "--k2",
        "8",
        "--prefilter-hz",
        "5",
        plain,
        "-o",
        command,
    ]);
    assert!(err.contains("--prefilter-hz applies to"), "{err}");
}

/// The measured friction damper (data/friction-damper): fitted on the 0.25 Hz and 1 Hz
/// records, it predicts the 0.5 Hz and 2 Hz ones; `--rate-term viscous` finds no support for a
/// viscous term there (the damper's force barely follows velocity) and leaves it out. Beside it,
/// a Coulomb + viscous fit F = F_c sign(v) + c v + F_0 by least squares.
#[test]
fn friction_damper_predicts_other_frequencies_without_an_invented_rate_term() {
    let dir = tempfile::tempdir().unwrap();
    let source = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/friction-damper/friction_damper_sines.csv");
    let text = std::fs::read_to_string(source).unwrap();
    // Text labels to record numbers 0..9, in file order.
    let mut labels: Vec<String> = Vec::new();
    let mut rows: Vec<[f64; 4]> = Vec::new();
    let mut csv = String::from("record,t_s,x_mm,v_mm_s,force_kN\n");
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if labels.last().map(String::as_str) != Some(f[0]) {
            labels.push(f[0].to_string());
        }
        let id = labels.len() - 1;
        csv.push_str(&format!("{id},{},{},{},{}\n", f[2], f[3], f[4], f[5]));
        let v = |i: usize| f[i].parse::<f64>().unwrap();
        rows.push([id as f64, v(3), v(4), v(5)]);
    }
    let data = dir.path().join("damper.csv");
    std::fs::write(&data, csv).unwrap();
    let held_out = [3.0, 4.0, 5.0, 9.0]; // 0.5 Hz and 2 Hz
    let model = dir.path().join("m.toml");
    let fit = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec![
            "fit",
            data.to_str().unwrap(),
            "--input",
            "x_mm",
            "--output",
            "force_kN",
            "--validate",
            "3,4,5,9",
            "--json",
            "-o",
            model.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        serde_json::from_str(&hyst(&args)).unwrap()
    };
    let plain = fit(&[]);
    let rated = fit(&["--rate-term", "viscous"]);
    let pct = |j: &serde_json::Value, set: &str| {
        j["model"]["metrics"][set]["rms_pct_span"].as_f64().unwrap()
    };
    // Coulomb + viscous by least squares on the training records.
    let (lo, hi) = rows
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(r[3]), b.max(r[3]))
        });
    let features = |r: &[f64; 4]| [r[2].signum(), r[2], 1.0];
    let (mut ata, mut atb) = ([[0.0; 3]; 3], [0.0; 3]);
    for r in rows.iter().filter(|r| !held_out.contains(&r[0])) {
        let x = features(r);
        for i in 0..3 {
            atb[i] += x[i] * r[3];
            for j in 0..3 {
                ata[i][j] += x[i] * x[j];
            }
        }
    }
    let coef = solve3(ata, atb);
    let rms = |validation: bool| {
        let e: Vec<f64> = rows
            .iter()
            .filter(|r| held_out.contains(&r[0]) == validation)
            .map(|r| {
                let x = features(r);
                x[0] * coef[0] + x[1] * coef[1] + x[2] * coef[2] - r[3]
            })
            .collect();
        100.0 * (e.iter().map(|v| v * v).sum::<f64>() / e.len() as f64).sqrt() / (hi - lo)
    };
    println!(
        "friction damper (train 0.25 + 1 Hz, validate 0.5 + 2 Hz), RMS % of span: stop form \
         {:.2} / {:.2}; with --rate-term viscous {:.2} / {:.2} (rate term: {}); Coulomb + \
         viscous (F_c = {:.3} kN, c = {:.2e} kN s/mm) {:.2} / {:.2}",
        pct(&plain, "training"),
        pct(&plain, "validation"),
        pct(&rated, "training"),
        pct(&rated, "validation"),
        rated["notes"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|n| n.as_str())
            .find(|n| n.contains("rate term"))
            .unwrap_or("none"),
        coef[0],
        coef[1],
        rms(false),
        rms(true)
    );
    assert!(rated["model"]["rate"].is_null(), "a rate term was invented");
    assert!(pct(&plain, "validation") < 1.2 * pct(&plain, "training"));
    assert!(pct(&plain, "validation") < rms(true));
}

/// The solution of a 3 × 3 system by Cramer's rule.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let mut x = [0.0; 3];
    for (k, slot) in x.iter_mut().enumerate() {
        let mut m = a;
        for i in 0..3 {
            m[i][k] = b[i];
        }
        *slot = det(m) / d;
    }
    x
}

/// Dynamics belong to the smooth model: a Prandtl–Ishlinskii fit with them is refused.
#[test]
fn dynamics_with_a_prandtl_ishlinskii_model_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("d.csv");
    let rows: Vec<Vec<f64>> = (0..200)
        .map(|k| {
            let t = f64::from(k) * 0.01;
            vec![t, t.sin(), t.sin() + 0.1 * t.cos()]
        })
        .collect();
    write_csv(&data, "t,u,y", &rows);
    let model = dir.path().join("m.toml");
    let out = Command::new(HYST)
        .args([
            "fit",
            data.to_str().unwrap(),
            "--input",
            "u",
            "--output",
            "y",
        ])
        .args(["--model-kind", "pi", "--dynamics", "1", "-o"])
        .arg(&model)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("smooth model"),
        "{err}"
    );
    assert!(!model.exists());
}

/// A viscous force on a counterclockwise hysteresis, y = 3 H(0.2, 5)[v] + 1 + 0.05 v̇: the
/// force turns the loops clockwise, yet with `--rate-term viscous` the fit finds the operator
/// form and c (the form the loops suggest is overruled, with a note).
#[test]
fn a_viscous_force_on_an_operator_is_found_whatever_the_loops_look_like() {
    let dir = tempfile::tempdir().unwrap();
    let h = 1e-3;
    let v: Vec<f64> = (0..5000)
        .map(|k| {
            let t = k as f64 * h;
            (2.0 * std::f64::consts::PI * 1.3 * t).sin() * (t / 0.3).min(1.0)
                + 0.4 * (2.0 * std::f64::consts::PI * 4.1 * t + 1.0).sin()
        })
        .collect();
    let mut op = InitialState::Rising
        .start(Hysteresis::new(0.2, 5.0).unwrap(), v[0])
        .unwrap();
    let z = hysteresis(&mut op, &v);
    let rows: Vec<Vec<f64>> = (0..v.len())
        .map(|k| {
            let rate = if k == 0 { 0.0 } else { (v[k] - v[k - 1]) / h };
            vec![k as f64 * h, v[k], 3.0 * z[k] + 1.0 + 0.05 * rate]
        })
        .collect();
    let data = dir.path().join("visc.csv");
    write_csv(&data, "t,v,y", &rows);
    let model = dir.path().join("m.toml");
    let json: serde_json::Value = serde_json::from_str(&hyst(&[
        "fit",
        data.to_str().unwrap(),
        "--input",
        "v",
        "--output",
        "y",
        "--rate-term",
        "viscous",
        "--json",
        "-o",
        model.to_str().unwrap(),
    ]))
    .unwrap();
    let c = json["model"]["rate"]["c"].as_f64().unwrap();
    println!("viscous force on an operator: c = {c:.5} (0.05)");
    assert!((c / 0.05 - 1.0).abs() < 0.02, "{c}");
    assert!(
        json["model"]["smooth"]["form"].is_null(),
        "the operator form"
    );
}

/// `hyst run` of a model with dynamics streams INPUT twice (each record's sample period comes
/// from all its stamps): a pipe (standard input, copied to a temporary file) gives the rows a
/// file gives, record by record; a record whose stamps are refused is named by its line, even
/// after records that ran, and nothing is written.
#[test]
fn a_timed_run_streams_its_input_from_a_file_or_a_pipe() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.toml");
    let x: Vec<f64> = (0..400).map(|k| (k as f64 * 0.05).sin()).collect();
    let y = hysteresis(&mut Hysteresis::new(0.1, 5.0).unwrap(), &x);
    fit_with_plant(dir.path(), &x, &y, "[0.02]", &model);
    // Two records (the second restarts its time), 2 ms and 1 ms steps; `late` moves row 250.
    let table = |late: f64| {
        let mut csv = String::from("t,u,rec\n");
        for k in 0..300 {
            let (t, rec) = if k < 120 {
                (k as f64 * 2e-3, "a")
            } else {
                (
                    (k - 120) as f64 * 1e-3 + if k == 250 { late } else { 0.0 },
                    "b",
                )
            };
            csv.push_str(&format!("{t:e},{},{rec}\n", (k as f64 * 0.03).sin()));
        }
        csv
    };
    let csv = table(0.0);
    let input = dir.path().join("in.csv");
    std::fs::write(&input, &csv).unwrap();
    let run = |stdin: Option<&str>, path: &str, out: &Path| {
        let mut cmd = Command::new(HYST);
        cmd.args(["run", "--model", model.to_str().unwrap(), "--record", "rec"])
            .args([path, "-o", out.to_str().unwrap()])
            .stdin(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped());
        let mut child = cmd.spawn().unwrap();
        let mut pipe = child.stdin.take().unwrap();
        std::io::Write::write_all(&mut pipe, stdin.unwrap_or("").as_bytes()).unwrap();
        drop(pipe);
        child.wait_with_output().unwrap()
    };
    let (from_file, from_pipe) = (dir.path().join("f.csv"), dir.path().join("p.csv"));
    assert!(run(None, input.to_str().unwrap(), &from_file)
        .status
        .success());
    assert!(run(Some(&csv), "/dev/stdin", &from_pipe).status.success());
    let written = std::fs::read_to_string(&from_file).unwrap();
    assert_eq!(written.lines().count(), 301);
    assert_eq!(written, std::fs::read_to_string(&from_pipe).unwrap());
    // Row 250 (line 252) of the second record is 1.5 ms early: before the stamp above it.
    // Refused by line, from a file and from a pipe; nothing written.
    let uneven = table(-1.5e-3);
    std::fs::write(&input, &uneven).unwrap();
    for (stdin, path) in [
        (None, input.to_str().unwrap()),
        (Some(&uneven), "/dev/stdin"),
    ] {
        let out_path = dir.path().join("bad.csv");
        let out = run(stdin.map(String::as_str), path, &out_path);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert!(
            err.contains(":252: column \"t\": time stamp") && err.contains("goes back"),
            "{err}"
        );
        assert!(!out_path.exists());
    }
}

/// A timed run to standard output writes nothing when a later record's time stamps are refused:
/// not the rows of the records before it (more than a buffer's worth).
#[test]
fn a_refused_stamp_writes_nothing_to_standard_output() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.toml");
    let x: Vec<f64> = (0..400).map(|k| (k as f64 * 0.05).sin()).collect();
    let y = hysteresis(&mut Hysteresis::new(0.1, 5.0).unwrap(), &x);
    fit_with_plant(dir.path(), &x, &y, "[0.02]", &model);
    let mut csv = String::from("t,u,rec\n");
    for k in 0..5000 {
        csv.push_str(&format!(
            "{:e},{},a\n",
            k as f64 * 1e-3,
            (k as f64 * 0.01).sin()
        ));
    }
    // The second record's third stamp goes back.
    for (k, t) in [0.0, 1e-3, 0.5e-3, 3e-3].iter().enumerate() {
        csv.push_str(&format!("{t:e},{},b\n", k as f64 * 0.1));
    }
    let input = dir.path().join("in.csv");
    std::fs::write(&input, &csv).unwrap();
    let out = Command::new(HYST)
        .args(["run", "--model", model.to_str().unwrap(), "--record", "rec"])
        .args([input.to_str().unwrap(), "-o", "-"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains(":5004: column \"t\"") && err.contains("goes back"),
        "{err}"
    );
    assert!(
        out.stdout.is_empty(),
        "{} bytes written before the refusal",
        out.stdout.len()
    );
}

/// `hyst run --inverse` of a model with dynamics warns, on standard error, when the record's
/// sample period does not resolve the corners of the model's loop: the desired output
/// 30 sin³(4πt) µm about the piezo model's centre (at 1 kHz, with its exact derivatives) crosses a
/// corner (1/k2 wide in the operator's output units) in 1/(k2 |ẏ_d| / gain) s. The piezo model
/// (k2 = 2.39) resolves it; the same model with k2 = 1000 does not, and the warning names the
/// line of the fastest corner and the period needed (a third of its time).
#[test]
fn a_compensator_warns_when_the_sample_period_cannot_resolve_the_loops_corners() {
    let dir = tempfile::tempdir().unwrap();
    let piezo =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/firmware/models/piezo_dyn.toml");
    let text = std::fs::read_to_string(&piezo).unwrap();
    let sharp = dir.path().join("sharp.toml");
    std::fs::write(&sharp, text.replace("2.393823624410437", "1000.0")).unwrap();
    let (w, h, gain) = (4.0 * std::f64::consts::PI, 1e-3, 35.078039285444284);
    let rows: Vec<Vec<f64>> = (0..2000)
        .map(|k| {
            let t = k as f64 * h;
            let (s, c) = (w * t).sin_cos();
            vec![
                t,
                -95.9 + 30.0 * s * s * s,
                90.0 * w * s * s * c,
                90.0 * w * w * s * (2.0 * c * c - s * s),
            ]
        })
        .collect();
    let data = dir.path().join("d.csv");
    write_csv(
        &data,
        "t,y_capsensor_um,y_capsensor_um_d1,y_capsensor_um_d2",
        &rows,
    );
    let (fastest, rate) = rows.iter().enumerate().fold((0, 0.0), |(i, r), (k, row)| {
        if row[2].abs() > r {
            (k, row[2].abs())
        } else {
            (i, r)
        }
    });
    let run = |model: &Path| {
        let out = Command::new(HYST)
            .args(["run", "--model", model.to_str().unwrap(), "--inverse"])
            .arg(&data)
            .args(["-o", dir.path().join("u.csv").to_str().unwrap()])
            .output()
            .unwrap();
        assert!(out.status.success());
        // The commands are written whatever the warning says.
        assert_eq!(
            read_column(&dir.path().join("u.csv"), "u_actuator_V").len(),
            2000
        );
        String::from_utf8(out.stderr).unwrap()
    };
    assert_eq!(run(&piezo), "");
    let warning = run(&sharp);
    println!("{warning}");
    let time = gain / (1000.0 * rate);
    for part in [
        "hyst run: warning: ".to_string(),
        format!("d.csv:{}: ", fastest + 2),
        format!("in {} s there", hyst_io::number::sig(time, 4)),
        format!(
            "sample at most every {} s",
            hyst_io::number::sig(time / 3.0, 4)
        ),
    ] {
        assert!(warning.contains(&part), "{part:?} not in {warning}");
    }
}
