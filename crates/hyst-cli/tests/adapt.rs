//! `hyst adapt` (docs/adaptation.md): a drifting truth followed through the command line, the
//! adapted model file run back, the bundled records not made worse, bad rows counted, bad cells
//! and models it cannot follow refused. Each test prints the figures the page states.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic
)]

use std::fmt::Write as _;
use std::path::Path;

use hyst_core::{AnyK2Law, Hysteresis, Operator, ScaledShaping, ShapedModel};
use hyst_test_support::cli::Binary;
use hyst_test_support::files::{index, parse_cells, piezo, piezo_fit, repo, s};
use hyst_test_support::rng::{Lcg64, Random};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

type Model = ShapedModel<f64, ScaledShaping<f64>, AnyK2Law<f64>, ScaledShaping<f64>>;

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A model file of y = 2.0 · H(0.15, 10)[x] + 0.1 (hand-written: no training RMS).
const MODEL: &str = r#"format = "hyst-model"
version = 1
kind = "smooth"
parameters = []
[columns]
input = "u"
output = "y"
[units]
input = "V"
output = "um"
[metrics]
parameters = 0
fit_seconds = 0.0
ns_per_sample = 0.0
[metrics.training]
samples = 0
rms = 0.0
max_abs = 0.0
rms_pct_span = 0.0
max_pct_span = 0.0
[smooth]
k1 = 0.15
initial_state = "line"
[smooth.k2]
law = "constant"
value = 10.0
[smooth.input_shaping]
pre_gain = 1.0
pre_offset = 0.0
shape = "identity"
post_gain = 1.0
post_offset = 0.0
[smooth.output_shaping]
pre_gain = 1.0
pre_offset = 0.0
shape = "identity"
post_gain = 2.0
post_offset = 0.1
[provenance]
file = "none"
bytes = 0
fnv1a64 = "0"
rows = 0
records = 0
command = "hand-written"
hyst_version = "0.1.0"
created_unix = 0
"#;

fn model(k1: f64, gain: f64) -> Model {
    let mut out = ScaledShaping::identity();
    out.post_gain = gain;
    out.post_offset = 0.1;
    let h = Hysteresis::with_k2_law(k1, AnyK2Law::Constant { value: 10.0 }).unwrap();
    ShapedModel::new(ScaledShaping::identity(), h, out).unwrap()
}

/// A command with reversals of changing amplitude and rests (one block in five holds).
fn command(k: usize) -> f64 {
    if (k / 2000) % 5 == 4 {
        return command((k / 2000) * 2000 - 1);
    }
    let t = k as f64 * 1e-3;
    (0.55 + 0.35 * (0.13 * t).sin()) * (1.7 * t).sin() + 0.25 * (4.3 * t + 1.0).sin()
}

/// Writes the record of a truth whose k1 rises and output gain falls by 30 % over the first
/// 60 % of `n` samples, with noise σ 0.002; columns t, run (a text label), u, y.
fn drifting_record(path: &Path, n: usize) {
    let mut truth = model(0.15, 2.0);
    let mut rng = Lcg64::new(2026);
    let mut noise = || rng.gaussian(0.002);
    let mut csv = String::from("t,run,u,y\n");
    for k in 0..n {
        let r = (k as f64 / (0.6 * n as f64)).min(1.0);
        let memory = truth.memory();
        truth = model(0.15 * (1.0 + 0.3 * r), 2.0 * (1.0 - 0.3 * r));
        truth.set_memory(memory).unwrap();
        let x = command(k);
        let y = truth.step(x) + noise();
        writeln!(csv, "{},bench-{},{x},{y}", k as f64 * 1e-3, k / 50_000).unwrap();
    }
    std::fs::write(path, csv).unwrap();
}

fn json(out: &std::process::Output) -> serde_json::Value {
    assert!(out.status.success(), "{}", text(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn a_drifting_truth_is_followed_and_the_adapted_model_runs() {
    let dir = tempfile::tempdir().unwrap();
    let (m, data) = (dir.path().join("m.toml"), dir.path().join("drift.csv"));
    let (out, adapted) = (dir.path().join("out.csv"), dir.path().join("adapted.toml"));
    std::fs::write(&m, MODEL).unwrap();
    let n = 200_000;
    drifting_record(&data, n);
    let args = [
        "adapt",
        "--model",
        s(&m),
        s(&data),
        "--input",
        "u",
        "--output",
        "y",
        "--noise",
        "0.002",
        "--settle",
        "20000",
        "-o",
        s(&out),
        "--model-out",
        s(&adapted),
        "--json",
    ];
    let r = json(&HYST.output(&args));
    let (fixed, adaptive) = (
        r["rms_fixed"].as_f64().unwrap(),
        r["rms_adaptive"].as_f64().unwrap(),
    );
    let k1 = r["final"]["k1"].as_f64().unwrap();
    let gain = r["final"]["gain"].as_f64().unwrap();
    println!(
        "hyst adapt: rms_fixed {fixed:.5}, rms_adaptive {adaptive:.5} (after 20000 of {n} \
         samples), final k1 {k1:.5} (truth 0.195), gain {gain:.4} (truth 1.4), counts {}",
        r["counts"]
    );
    assert!(adaptive <= fixed / 3.0);
    assert!((k1 / 0.195 - 1.0).abs() <= 0.05 && (gain / 1.4 - 1.0).abs() <= 0.05);
    assert_eq!(r["rows"], n);

    // Every input column first (the text labels as read), then y_pred and the parameters.
    let written = std::fs::read_to_string(&out).unwrap();
    let mut lines = written.lines();
    assert_eq!(lines.next(), Some("t,run,u,y,y_pred,k1,k2,gain,offset"));
    let first: Vec<&str> = lines.next().unwrap().split(',').collect();
    let input = std::fs::read_to_string(&data).unwrap();
    let given: Vec<&str> = input.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(&first[..4], &given[..]);
    assert_eq!(written.lines().count(), n + 1);

    // The adapted model file runs as any other, and predicts the end of the record.
    let run = dir.path().join("run.csv");
    let o = HYST.output(&["run", "--model", s(&adapted), s(&data), "-o", s(&run)]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let (header, rows) = parse_cells(&std::fs::read_to_string(&run).unwrap());
    let (y, p) = (index(&header, "y"), index(&header, "y_out"));
    let tail = &rows[n - n / 5..];
    let rms = (tail
        .iter()
        .map(|r| (r[y].parse::<f64>().unwrap() - r[p].parse::<f64>().unwrap()).powi(2))
        .sum::<f64>()
        / tail.len() as f64)
        .sqrt();
    println!("adapted model file: rms {rms:.5} over the last fifth (noise 0.002)");
    assert!(rms <= 0.004, "{rms}");
    let toml = std::fs::read_to_string(&adapted).unwrap();
    assert!(toml.contains("adapted from: hand-written"), "{toml}");
}

/// Fits a model to a bundled record, then adapts it on the same record: (fixed, adaptive).
fn fit_then_adapt(dir: &Path, name: &str, fit: &[&str], adapt: &[&str]) -> (f64, f64) {
    let m = dir.join(format!("{name}.toml"));
    let o = HYST.output(&[&["fit"], fit, &["-o", s(&m)]].concat());
    assert!(o.status.success(), "{name}: {}", text(&o.stderr));
    let out = dir.join(format!("{name}.csv"));
    let r = json(
        &HYST.output(&[&["adapt", "--model", s(&m), "--json", "-o", s(&out)], adapt].concat()),
    );
    let (f, a) = (
        r["rms_fixed"].as_f64().unwrap(),
        r["rms_adaptive"].as_f64().unwrap(),
    );
    println!(
        "{name}: rms_fixed {f:.4e}, rms_adaptive {a:.4e} ({:+.1} %)",
        100.0 * (a / f - 1.0)
    );
    (f, a)
}

#[test]
fn adaptation_does_not_make_the_bundled_records_worse() {
    let dir = tempfile::tempdir().unwrap();
    let d = repo().join("data");
    let piezo = d.join("piezo-sine/piezo_sine_1hz.csv");
    let steel = d.join("bh-loops/m130_27s_steel_loops.csv");
    let ferrite = d.join("bh-loops/mnzn_ferrite_loops.csv");
    let feco = d.join("feco-forc/feco_forc_sequence.csv");
    let bh = ["--input", "H_A_per_m", "--output", "B_T"];
    let cases: Vec<(&str, Vec<&str>, Vec<&str>)> = vec![
        (
            "piezo",
            vec![
                s(&piezo),
                "--input",
                "u_actuator_V",
                "--output",
                "y_capsensor_um",
            ],
            vec![s(&piezo)],
        ),
        (
            "steel",
            [&[s(&steel)], &bh[..]].concat(),
            vec![s(&steel), "--record", "loop"],
        ),
        (
            "steel-langevin",
            [&[s(&steel)], &bh[..], &["--output-shaping", "langevin"]].concat(),
            vec![s(&steel), "--record", "loop"],
        ),
        (
            "ferrite",
            [&[s(&ferrite)], &bh[..]].concat(),
            vec![s(&ferrite), "--record", "loop"],
        ),
        (
            "feco-forc",
            vec![
                s(&feco),
                "--input",
                "H_Oe",
                "--output",
                "moment_emu",
                "--output-shaping",
                "langevin",
            ],
            vec![s(&feco)],
        ),
    ];
    for (name, fit, adapt) in cases {
        let (fixed, adaptive) = fit_then_adapt(dir.path(), name, &fit, &adapt);
        assert!(adaptive <= fixed, "{name}: {adaptive} > {fixed}");
    }
}

#[test]
fn bad_rows_are_counted_and_a_bad_cell_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let (m, data, out) = (
        dir.path().join("m.toml"),
        dir.path().join("d.csv"),
        dir.path().join("o.csv"),
    );
    std::fs::write(&m, MODEL).unwrap();
    let mut csv = String::from("u,y\n");
    for k in 0..400 {
        let x = command(k * 10);
        let cell = match k {
            100 => "nan".to_string(),
            101 => String::new(),
            _ => format!("{}", 2.0 * x + 0.1),
        };
        let u = match k {
            200 => "inf".to_string(),
            201 => "3.5".to_string(),
            _ => format!("{x}"),
        };
        writeln!(csv, "{u},{cell}").unwrap();
    }
    std::fs::write(&data, &csv).unwrap();
    let args = |extra: &[&str]| {
        let mut a = vec!["adapt", "--model", s(&m), s(&data), "-o", s(&out), "--json"];
        a.extend_from_slice(&["--noise", "0.01", "--input-range", "-2,2"]);
        a.extend_from_slice(extra);
        HYST.output(&a)
    };
    let r = json(&args(&[]));
    let c = &r["counts"];
    println!("bad rows: {c}");
    assert_eq!(
        (c["bad_output"].as_u64(), c["bad_input"].as_u64()),
        (Some(2), Some(1))
    );
    assert_eq!(c["out_of_range"].as_u64(), Some(1));
    let rows: Vec<String> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(String::from)
        .collect();
    assert_eq!(rows.len(), 401);
    assert!(rows[201].starts_with("inf,"), "{}", rows[201]);
    assert_eq!(
        rows[201].split(',').nth(2),
        Some(""),
        "no prediction for a command inf"
    );

    // A cell that is not a number is an error naming the file, line and column; nothing written.
    std::fs::remove_file(&out).unwrap();
    std::fs::write(&data, csv.replacen("nan", "abc", 1)).unwrap();
    let o = args(&[]);
    let e = text(&o.stderr);
    assert!(!o.status.success());
    assert!(
        e.contains("d.csv:102") && e.contains("column 2") && e.contains("abc"),
        "{e}"
    );
    assert!(!out.exists());
}

#[test]
fn models_and_settings_it_cannot_take_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let (m, data, out) = (
        dir.path().join("m.toml"),
        dir.path().join("d.csv"),
        dir.path().join("o.csv"),
    );
    std::fs::write(&data, "u,y\n0,0.1\n0.5,1.0\n").unwrap();
    let run = |model: &str, extra: &[&str]| {
        std::fs::write(&m, model).unwrap();
        let mut a = vec!["adapt", "--model", s(&m), s(&data), "-o", s(&out)];
        a.extend_from_slice(extra);
        let o = HYST.output(&a);
        assert!(!o.status.success());
        assert!(!out.exists());
        text(&o.stderr)
    };
    let pi = std::fs::read_to_string(repo().join("fuzz/corpus/model_file/pi.toml")).unwrap();
    assert!(run(&pi, &["--noise", "1"]).contains("Prandtl-Ishlinskii"));
    let stop = MODEL
        .replace("version = 1", "version = 3")
        .replace("k1 = 0.15\n", "k1 = 0.15\nform = \"stop\"\n");
    assert!(run(&stop, &["--noise", "1"]).contains("stop-form"));
    assert!(run(MODEL, &[]).contains("--noise is needed"));
    let e = run(MODEL, &["--noise", "1", "--parameters", "k1,gian"]);
    assert!(e.contains("\"gian\""), "{e}");
    let e = run(MODEL, &["--noise", "1", "--drift", "-1"]);
    assert!(e.contains("--drift -1"), "{e}");
    let e = run(MODEL, &["--noise", "1", "--input", "volts"]);
    assert!(e.contains("volts"), "{e}");
    let e = run(MODEL, &["--noise", "1", "--input-range", "2,-2"]);
    assert!(e.contains("--input-range \"2,-2\""), "{e}");
}

/// `rows` rows of MODEL's truth (y = 2 · H(0.15, 10)[u] + 0.1), with row `at` replaced.
fn record_with(path: &Path, rows: usize, at: usize, row: &str) {
    let mut truth = model(0.15, 2.0);
    let mut csv = String::from("u,y\n");
    for k in 0..rows {
        let x = command(k);
        let y = truth.step(x);
        if k == at {
            writeln!(csv, "{row}").unwrap();
        } else {
            writeln!(csv, "{x},{y}").unwrap();
        }
    }
    std::fs::write(path, csv).unwrap();
}

#[test]
fn one_huge_finite_error_gives_a_finite_rms() {
    let dir = tempfile::tempdir().unwrap();
    let m = dir.path().join("m.toml");
    std::fs::write(&m, MODEL).unwrap();
    let data = dir.path().join("huge.csv");
    let out = dir.path().join("out.csv");
    let rows = 20_000;
    let adapt = |extra: &[&str]| {
        let mut args = vec!["adapt", "--model", s(&m), s(&data), "--noise", "0.002"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--json", "-o", s(&out)]);
        json(&HYST.output(&args))
    };
    // A measurement of 1e308: its error dominates both sums; (1e308)² overflows a double.
    record_with(&data, rows, 5000, &format!("{},1e308", command(5000)));
    let r = adapt(&[]);
    let n = r["samples"].as_f64().unwrap();
    let (fixed, adaptive) = (
        r["rms_fixed"].as_f64().unwrap(),
        r["rms_adaptive"].as_f64().unwrap(),
    );
    println!("y = 1e308 in {rows} rows: rms_fixed {fixed:e}, rms_adaptive {adaptive:e} over {n}");
    let expected = 1e308 / n.sqrt();
    assert!(
        (fixed / expected - 1.0).abs() < 1e-9,
        "{fixed} against {expected}"
    );
    assert!(
        (adaptive / expected - 1.0).abs() < 1e-9,
        "{adaptive} against {expected}"
    );
    assert!(r["rms_note"].is_null(), "{r}");
    // A command of 1e300 (outside no input range: the model was not fitted): both models
    // predict about 2e300 there.
    record_with(&data, rows, 5000, "1e300,0.1");
    let r = adapt(&["--parameters", "offset"]);
    let fixed = r["rms_fixed"].as_f64().unwrap();
    let n = r["samples"].as_f64().unwrap();
    println!(
        "x = 1e300 in {rows} rows: rms_fixed {fixed:e} over {n}, {}",
        r["rms_adaptive"]
    );
    assert!((fixed / (2e300 / n.sqrt()) - 1.0).abs() < 1e-6, "{fixed}");
    assert!(r["rms_adaptive"].as_f64().unwrap().is_finite(), "{r}");
    assert!(r["rms_note"].is_null(), "{r}");
    // No row to count: the RMS are null, and the summary says why.
    let r = adapt(&["--settle", "30000"]);
    assert!(
        r["rms_fixed"].is_null() && r["rms_adaptive"].is_null(),
        "{r}"
    );
    let note = r["rms_note"].as_str().unwrap();
    assert!(note.contains("no row after --settle 30000"), "{note}");
}

#[test]
fn a_saturating_input_shaping_adapts_over_its_fitted_range() {
    let dir = tempfile::tempdir().unwrap();
    let piezo = piezo();
    for input in ["tanh", "langevin"] {
        let m = dir.path().join(format!("{input}.toml"));
        let mut fit = piezo_fit(&piezo, &m).to_vec();
        fit.extend_from_slice(&["--input-shaping", input]);
        let o = HYST.output(&fit);
        assert!(o.status.success(), "{input}: {}", text(&o.stderr));
        let out = dir.path().join("out.csv");
        let r = json(&HYST.output(&[
            "adapt",
            "--model",
            s(&m),
            s(&piezo),
            "--json",
            "-o",
            s(&out),
        ]));
        let range = &r["settings"]["input_range"];
        let (lo, hi) = (range[0].as_f64().unwrap(), range[1].as_f64().unwrap());
        println!(
            "{input}: default input range [{lo}, {hi}] V, counts {}",
            r["counts"]
        );
        // The data's 0 to 3.6 V, widened by 10 % of the span on each side (to the precision
        // of ψ_in, which the fit puts far in the tanh's tail: its value is a difference of two
        // numbers of 1.6e11).
        assert!(
            (lo + 0.36).abs() < 1e-3 && (hi - 3.96).abs() < 1e-3,
            "{input}: {range}"
        );
        assert_eq!(r["counts"]["out_of_range"], 0, "{input}: {r}");
        assert!(
            r["counts"]["updated"].as_u64().unwrap() > 1000,
            "{input}: {r}"
        );
    }
}
