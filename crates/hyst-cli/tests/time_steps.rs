//! Time stamps as measured and the hold (docs/fitting.md, "Dynamics and rate"): `hyst run` and
//! `hyst fit` of a model with dynamics over records with uneven steps, gaps and Unix-epoch
//! offsets, under the zero- or first-order hold.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

use std::path::Path;

use hyst_model::{ModelFile, TimeSteps};
use hyst_test_support::cli::Binary;
use hyst_test_support::rng::{Lcg64, Random};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

/// The static model fixture with `[dynamics]` (and whatever `extra` adds) appended.
fn model_file(dir: &Path, name: &str, sections: &str) -> std::path::PathBuf {
    let base = include_str!("../../hyst-model/testdata/static-model.toml");
    let version = if sections.contains("hold") { 5 } else { 4 };
    let text = base.replace("version = 1", &format!("version = {version}")) + sections;
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The column `name` of the CSV file `path`.
fn column(path: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(at).unwrap().parse().unwrap())
        .collect()
}

/// A DAQ record's stamps: steps of 10 to 63 ms around a 10 ms mean (deterministic), from `t0`.
fn daq_stamps(t0: f64, n: usize) -> Vec<f64> {
    let mut t = vec![t0];
    let mut rng = Lcg64::with_increment(11, 1);
    for k in 1..n {
        let r = (rng.next_u64() >> 40) as f64 / (1_u64 << 24) as f64;
        let h = if r < 0.02 {
            0.063
        } else {
            0.010 + 0.0004 * (r * 10.0).floor()
        };
        t.push(t[k - 1] + h);
    }
    t
}

fn write(path: &Path, t: &[f64], u: &[f64]) {
    let mut text = String::from("t,x\n");
    for (t, u) in t.iter().zip(u) {
        text.push_str(&format!("{t:?},{u:?}\n"));
    }
    std::fs::write(path, text).unwrap();
}

/// What `hyst run` computes, from the library: the record cut at its gaps, each part at its
/// measured steps.
fn library_run(model: &Path, t: &[f64], u: &[f64]) -> Vec<f64> {
    let file = ModelFile::read(model).unwrap();
    let smooth = file.smooth.unwrap();
    let (parts, _) = hyst_model::time::split(t).unwrap();
    let mut y = Vec::new();
    for (range, steps) in parts {
        smooth
            .run_timed(&u[range], Some(&steps), None, |_, s| y.push(s.y))
            .unwrap();
    }
    y
}

#[test]
fn uneven_stamps_run_at_their_steps_under_the_file_s_hold() {
    let dir = tempfile::tempdir().unwrap();
    let n = 3000;
    let t = daq_stamps(0.0, n);
    let u: Vec<f64> = t.iter().map(|t| 2.0 + 1.5 * (0.9 * t).sin()).collect();
    let data = dir.path().join("daq.csv");
    write(&data, &t, &u);
    for (name, sections) in [
        ("foh.toml", "\n[dynamics]\nb = 1.0\na = [0.05]\n"),
        (
            "zoh.toml",
            "\n[dynamics]\nb = 1.0\na = [0.05]\nhold = \"zoh\"\n",
        ),
        (
            "rate.toml",
            "\n[dynamics]\nb = 1.0\na = [0.05, 0.0004]\n[rate]\nc = 0.3\n",
        ),
    ] {
        let model = model_file(dir.path(), name, sections);
        let out = dir.path().join("out.csv");
        let s = |p: &Path| p.to_str().unwrap().to_string();
        HYST.success(&["run", "--model", &s(&model), &s(&data), "-o", &s(&out)]);
        let y = column(&out, "y");
        let want = library_run(&model, &t, &u);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&y), bits(&want), "{name}");
        // Not the record at its mean step.
        let file = ModelFile::read(&model).unwrap();
        let mut even = Vec::new();
        let mean = (t[n - 1] - t[0]) / (n - 1) as f64;
        file.smooth
            .unwrap()
            .run_timed(&u, Some(&TimeSteps::even(mean)), None, |_, s| {
                even.push(s.y)
            })
            .unwrap();
        assert_ne!(bits(&y), bits(&even), "{name}");
    }
    // --hold overrides the file's: foh.toml run under zoh is zoh.toml.
    let (foh, zoh) = (
        model_file(
            dir.path(),
            "foh.toml",
            "\n[dynamics]\nb = 1.0\na = [0.05]\n",
        ),
        model_file(
            dir.path(),
            "zoh.toml",
            "\n[dynamics]\nb = 1.0\na = [0.05]\nhold = \"zoh\"\n",
        ),
    );
    let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    let s = |p: &Path| p.to_str().unwrap().to_string();
    HYST.success(&[
        "run",
        "--model",
        &s(&foh),
        "--hold",
        "zoh",
        &s(&data),
        "-o",
        &s(&a),
    ]);
    HYST.success(&["run", "--model", &s(&zoh), &s(&data), "-o", &s(&b)]);
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    // A hold for the compensator, or for a model without dynamics, is refused with the reason.
    let out = HYST.output(&[
        "run",
        "--model",
        &s(&zoh),
        "--inverse",
        "--hold",
        "foh",
        "--prefilter-hz",
        "5",
        &s(&data),
        "-o",
        &s(&a),
    ]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("whatever the hold"));
}

#[test]
fn a_gap_splits_the_record_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let mut t: Vec<f64> = (0..400).map(|k| f64::from(k) * 0.01).collect();
    t.extend((0..300).map(|k| 100.0 + f64::from(k) * 0.01));
    let u: Vec<f64> = t.iter().map(|t| 2.0 + (1.3 * t).sin()).collect();
    let data = dir.path().join("gap.csv");
    write(&data, &t, &u);
    let model = model_file(dir.path(), "m.toml", "\n[dynamics]\nb = 1.0\na = [0.05]\n");
    let out = dir.path().join("out.csv");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let done = HYST.success(&["run", "--model", &s(&model), &s(&data), "-o", &s(&out)]);
    let err = String::from_utf8_lossy(&done.stderr);
    // Line 402: the header, then 400 rows.
    assert!(
        err.contains("gap.csv:402:") && err.contains("split"),
        "{err}"
    );
    let y = column(&out, "y");
    let want = library_run(&model, &t, &u);
    assert_eq!(y, want);
    // The part after the gap starts at rest: as a record of its own.
    let mut second = Vec::new();
    let file = ModelFile::read(&model).unwrap();
    file.smooth
        .unwrap()
        .run_timed(&u[400..], Some(&TimeSteps::even(0.01)), None, |_, s| {
            second.push(s.y)
        })
        .unwrap();
    for (a, b) in y[400..].iter().zip(&second) {
        assert!((a - b).abs() < 1e-9, "{a} {b}");
    }
    // A repeated stamp is still refused with its line and value.
    let mut bad = t.clone();
    bad[10] = bad[9];
    write(&data, &bad, &u);
    let out = HYST.output(&[
        "run",
        "--model",
        &s(&model),
        &s(&data),
        "-o",
        &s(&dir.path().join("o.csv")),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("gap.csv:12:") && err.contains("repeats"),
        "{err}"
    );
}

#[test]
fn epoch_stamps_run_or_say_why_they_cannot() {
    let dir = tempfile::tempdir().unwrap();
    let model = model_file(dir.path(), "m.toml", "\n[dynamics]\nb = 1.0\na = [0.05]\n");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let n = 2000;
    let u: Vec<f64> = (0..n).map(|k| 2.0 + (0.01 * k as f64).sin()).collect();
    // Epoch seconds at 1 kHz: the offset cancels in each step (to the stamps' 2.4e-7 s).
    let local: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
    let epoch: Vec<f64> = local.iter().map(|t| 1.7e9 + t).collect();
    let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    write(&a, &local, &u);
    write(&b, &epoch, &u);
    let (ya, yb) = (dir.path().join("ya.csv"), dir.path().join("yb.csv"));
    HYST.success(&["run", "--model", &s(&model), &s(&a), "-o", &s(&ya)]);
    HYST.success(&["run", "--model", &s(&model), &s(&b), "-o", &s(&yb)]);
    let (ya, yb) = (column(&ya, "y"), column(&yb, "y"));
    let worst = ya
        .iter()
        .zip(&yb)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-4, "{worst}");
    // At 1 MHz they cannot resolve the steps: refused, saying so.
    let micro: Vec<f64> = (0..n).map(|k| 1.7e9 + k as f64 * 1e-6).collect();
    write(&b, &micro, &u);
    let out = HYST.output(&[
        "run",
        "--model",
        &s(&model),
        &s(&b),
        "-o",
        &s(&dir.path().join("o.csv")),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains(":2:") && err.contains("apart in 64-bit floats") && err.contains("t − t0"),
        "{err}"
    );
}

/// `hyst fit --dynamics 1` on jittered stamps: a first-order plant before a hysteresis,
/// simulated exactly under the zero-order hold at each step, is found exactly (the fit's
/// discretisation is the truth's), and the model file records the hold; `--hold foh` writes
/// none (format version 4) and, the wrong hold for this record, a biased τ.
#[test]
fn an_uneven_record_fits_and_records_its_hold() {
    let dir = tempfile::tempdir().unwrap();
    let n = 4000;
    let t = daq_stamps(5.0, n);
    let tau = 0.08;
    let u: Vec<f64> = t
        .iter()
        .map(|t| 1.0 * (0.7 * t).sin() + 0.5 * (2.9 * t).sin() + 0.3 * (7.3 * t).cos())
        .collect();
    // The truth: v through the plant under the zero-order hold, exact per step; y = 2 H(0.2, 6)[v].
    let mut v = vec![u[0]];
    for k in 1..n {
        let e = (-(t[k] - t[k - 1]) / tau).exp();
        v.push(e * v[k - 1] + (1.0 - e) * u[k - 1]);
    }
    let mut h = hyst_core::Hysteresis::new(0.2_f64, 6.0).unwrap();
    use hyst_core::Operator;
    let y: Vec<f64> = v.iter().map(|v| 2.0 * h.step(*v) + 1.0).collect();
    let mut text = String::from("t,u,y\n");
    for k in 0..n {
        text.push_str(&format!("{:?},{:?},{:?}\n", t[k], u[k], y[k]));
    }
    let data = dir.path().join("jitter.csv");
    std::fs::write(&data, &text).unwrap();
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let model = dir.path().join("m.toml");
    // The truth's hysteresis starts without history: `--initial-state line`.
    let fit = |hold: &str, out: &Path| {
        HYST.success(&[
            "fit",
            &s(&data),
            "--input",
            "u",
            "--output",
            "y",
            "--dynamics",
            "1",
            "--hold",
            hold,
            "--initial-state",
            "line",
            "-o",
            &s(out),
        ]);
    };
    fit("zoh", &model);
    let text = std::fs::read_to_string(&model).unwrap();
    assert!(
        text.contains("hold = \"zoh\"") && text.contains("version = 5"),
        "{text}"
    );
    let file = ModelFile::read(&model).unwrap();
    let a1 = file.smooth.unwrap().dynamics.unwrap().a()[0];
    assert!((a1 - tau).abs() < 1e-6 * tau, "a1 = {a1}");
    // The model runs its own data back.
    let out = dir.path().join("out.csv");
    HYST.success(&["run", "--model", &s(&model), &s(&data), "-o", &s(&out)]);
    let fitted = column(&out, "y_out");
    let rms = (fitted
        .iter()
        .zip(&y)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        / n as f64)
        .sqrt();
    assert!(rms < 1e-9, "{rms}");
    // --hold foh: no hold written, version 4.
    let foh = dir.path().join("foh.toml");
    fit("foh", &foh);
    let text = std::fs::read_to_string(&foh).unwrap();
    assert!(
        !text.contains("hold =") && text.contains("version = 4"),
        "{text}"
    );
    let a1 = ModelFile::read(&foh)
        .unwrap()
        .smooth
        .unwrap()
        .dynamics
        .unwrap()
        .a()[0];
    assert!(
        (a1 - tau).abs() > 0.05 * tau,
        "a1 = {a1} under the first-order hold"
    );
    // --hold without --dynamics is refused.
    let out = HYST.output(&[
        "fit",
        &s(&data),
        "--input",
        "u",
        "--output",
        "y",
        "--hold",
        "zoh",
        "-o",
        &s(&foh),
    ]);
    assert!(!out.status.success());
}
