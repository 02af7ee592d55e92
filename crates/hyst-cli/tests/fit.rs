//! `hyst fit` end to end: the bundled piezo data, the model file read back by `hyst run --model`,
//! and every bad-data error (each names what is wrong, and no model file is left behind).

use std::path::Path;
use std::process::Output;

use hyst_test_support::cli::Binary;
use hyst_test_support::files::repo;
use hyst_test_support::rng::{Lcg64, Random};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

type R = Result<(), Box<dyn std::error::Error>>;

fn column(csv: &str, name: &str) -> Result<Vec<f64>, Box<dyn std::error::Error>> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let i = header
        .iter()
        .position(|h| *h == name)
        .ok_or_else(|| format!("no column {name}"))?;
    Ok(lines
        .map(|l| l.split(',').nth(i).unwrap_or("nan").parse::<f64>())
        .collect::<Result<_, _>>()?)
}

/// The header of the piezo data (data/piezo-sine) and of `hyst run --model` of a model fitted
/// on it, run on it: the prediction is named after the model's output column, which the data
/// already has, so with the suffix `_out`.
const PIEZO_HEADER: &str = "t_s,u_actuator_V,y_capsensor_um";
const PIEZO_RUN_HEADER: &str = "t_s,u_actuator_V,y_capsensor_um,y_capsensor_um_out";

/// Feeds a direct run's output (y_capsensor_um and its derivatives _d1, _d2) back through
/// `hyst run --model MODEL --inverse --derivatives 2` (the model's output column is the
/// default) and returns the inverse's CSV: the command is `u_actuator_V`, with `_d1`, `_d2`.
fn invert_with_derivatives(
    dir: &Path,
    model: &str,
    direct: &str,
    name: &str,
) -> Result<String, Box<dyn std::error::Error>> {
    let y = column(direct, "y_capsensor_um")?;
    let d1 = column(direct, "y_capsensor_um_d1")?;
    let d2 = column(direct, "y_capsensor_um_d2")?;
    let mut back = String::from("y_capsensor_um,y_capsensor_um_d1,y_capsensor_um_d2\n");
    for ((a, b), c) in y.iter().zip(&d1).zip(&d2) {
        back += &format!("{a},{b},{c}\n");
    }
    let desired = dir.join(format!("desired-{name}.csv"));
    std::fs::write(&desired, back)?;
    let inv_out = dir.join(format!("{name}.csv"));
    let out = HYST.output(&[
        "run",
        "--model",
        model,
        "--inverse",
        "--derivatives",
        "2",
        desired.to_str().ok_or("path")?,
        "-o",
        inv_out.to_str().ok_or("path")?,
    ]);
    if !out.status.success() {
        return Err(text(&out.stderr).into());
    }
    let inverse = std::fs::read_to_string(&inv_out)?;
    assert!(inverse.starts_with(
        "y_capsensor_um,y_capsensor_um_d1,y_capsensor_um_d2,u_actuator_V,u_actuator_V_d1,\
         u_actuator_V_d2\n"
    ));
    Ok(inverse)
}

#[test]
fn piezo_fit_is_accurate_and_run_reads_the_model_back() -> R {
    let dir = tempfile::tempdir()?;
    let model = dir.path().join("piezo.toml");
    let data = repo().join("data/piezo-sine/piezo_sine_1hz.csv");
    let out = HYST.output(&[
        "fit",
        data.to_str().ok_or("path")?,
        "--input",
        "u_actuator_V",
        "--output",
        "y_capsensor_um",
        "-o",
        model.to_str().ok_or("path")?,
        "--json",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout)?;
    let rms = report["model"]["metrics"]["training"]["rms"]
        .as_f64()
        .ok_or("rms")?;
    let pct = report["model"]["metrics"]["training"]["rms_pct_span"]
        .as_f64()
        .ok_or("pct")?;
    assert!(pct <= 1.2, "RMS {pct} % of span");
    assert!(report["model"]["family"]["delta_a"].as_f64().ok_or("Δa")? > 0.0);

    // hyst run --model reproduces the fitted model's output on the data: same RMS.
    let run_out = dir.path().join("run.csv");
    let out = HYST.output(&[
        "run",
        "--model",
        model.to_str().ok_or("path")?,
        data.to_str().ok_or("path")?,
        "-o",
        run_out.to_str().ok_or("path")?,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let run_csv = std::fs::read_to_string(&run_out)?;
    assert!(std::fs::read_to_string(&data)?.starts_with(&format!("{PIEZO_HEADER}\n")));
    assert!(run_csv.starts_with(&format!("{PIEZO_RUN_HEADER}\n")));
    let y = column(&run_csv, "y_capsensor_um_out")?;
    let measured = column(&std::fs::read_to_string(&data)?, "y_capsensor_um")?;
    let n = y.len() as f64;
    let rms_back = (y
        .iter()
        .zip(&measured)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        / n)
        .sqrt();
    assert!((rms_back - rms).abs() <= 1e-12 * rms, "{rms_back} vs {rms}");

    // --inverse: the inverse turns the model output back into the input exactly.
    let inv_out = dir.path().join("inv.csv");
    let out = HYST.output(&[
        "run",
        "--model",
        model.to_str().ok_or("path")?,
        "--inverse",
        "--column",
        "y_capsensor_um_out",
        run_out.to_str().ok_or("path")?,
        "-o",
        inv_out.to_str().ok_or("path")?,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // The command is named after the model's input column, which the file has: `_out`.
    let inv_csv = std::fs::read_to_string(&inv_out)?;
    assert!(inv_csv.starts_with(&format!("{PIEZO_RUN_HEADER},u_actuator_V_out\n")));
    let back = column(&inv_csv, "u_actuator_V_out")?;
    let input = column(&std::fs::read_to_string(&data)?, "u_actuator_V")?;
    for (a, b) in back.iter().zip(&input) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
    Ok(())
}

#[test]
fn pi_baseline_and_comparison() -> R {
    let dir = tempfile::tempdir()?;
    let model = dir.path().join("pi.toml");
    let data = repo().join("data/bh-loops/mnzn_ferrite_loops.csv");
    let out = HYST.output(&[
        "fit",
        data.to_str().ok_or("path")?,
        "--input",
        "H_A_per_m",
        "--output",
        "B_T",
        "--model-kind",
        "pi",
        "--plays",
        "12",
        "--compare",
        "--validate",
        "1",
        "-o",
        model.to_str().ok_or("path")?,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report = text(&out.stdout);
    assert!(report.contains("prandtl-ishlinskii"), "{report}");
    assert!(report.contains("smooth"), "{report}");
    assert!(report.contains("validation (129 samples)"), "{report}");
    let file = std::fs::read_to_string(&model)?;
    assert!(file.contains("kind = \"prandtl-ishlinskii\""), "{file}");
    Ok(())
}

/// Runs `hyst fit` on `csv` and returns stderr, checking that it failed and wrote nothing.
fn fails(csv: &str, extra: &[&str]) -> Result<String, Box<dyn std::error::Error>> {
    let dir = tempfile::tempdir()?;
    let data = dir.path().join("bad.csv");
    std::fs::write(&data, csv)?;
    let model = dir.path().join("model.toml");
    let mut args = vec![
        "fit",
        data.to_str().ok_or("path")?,
        "--input",
        "x",
        "--output",
        "y",
        "-o",
        model.to_str().ok_or("path")?,
    ];
    args.extend_from_slice(extra);
    let out = HYST.output(&args);
    assert!(!out.status.success(), "{}", text(&out.stdout));
    assert!(!model.exists(), "a model file was written");
    let leftovers = std::fs::read_dir(dir.path())?.count();
    assert_eq!(leftovers, 1, "temporary files left behind");
    Ok(text(&out.stderr))
}

fn good_rows(n: usize) -> String {
    (0..n)
        .map(|k| {
            let x = (k as f64 * 0.1).sin();
            format!("{x},{}\n", 2.0 * x + 0.1)
        })
        .collect()
}

#[test]
fn missing_column_is_named() -> R {
    let err = fails(&format!("x,z\n{}", good_rows(50)), &[])?;
    assert!(err.contains("no column named \"y\""), "{err}");
    assert!(err.contains("\"x\", \"z\""), "{err}");
    Ok(())
}

#[test]
fn non_numeric_cell_names_file_line_and_column() -> R {
    let mut csv = format!("x,y\n{}", good_rows(10));
    csv.push_str("0.5,abc\n");
    let err = fails(&csv, &[])?;
    assert!(err.contains("bad.csv:12: column 2 (\"y\")"), "{err}");
    assert!(err.contains("\"abc\""), "{err}");
    Ok(())
}

#[test]
fn nan_cell_is_refused() -> R {
    let mut csv = format!("x,y\n{}", good_rows(5));
    csv.push_str("NaN,1.0\n");
    let err = fails(&csv, &[])?;
    assert!(err.contains("bad.csv:7: column 1 (\"x\")"), "{err}");
    assert!(err.contains("not a finite number"), "{err}");
    Ok(())
}

#[test]
fn constant_input_is_refused() -> R {
    let csv: String = std::iter::once("x,y\n".to_string())
        .chain((0..40).map(|k| format!("1.5,{}\n", k as f64 * 0.01)))
        .collect();
    let err = fails(&csv, &[])?;
    assert!(
        err.contains("column \"x\" (the input) is constant (1.5)"),
        "{err}"
    );
    Ok(())
}

#[test]
fn operator_count_out_of_range_names_the_flag() -> R {
    for n in ["0", "129"] {
        let err = fails(
            &format!("x,y\n{}", good_rows(50)),
            &["--model-kind", "pi", "--plays", n],
        )?;
        assert!(
            err.contains(&format!("--plays {n}: expected 1 to 128")),
            "{err}"
        );
    }
    Ok(())
}

#[test]
fn fewer_samples_than_parameters_is_refused() -> R {
    let err = fails(&format!("x,y\n{}", good_rows(3)), &[])?;
    assert!(
        err.contains("3 training samples but the model has 4 free parameters"),
        "{err}"
    );
    let err = fails(
        &format!("x,y\n{}", good_rows(10)),
        &["--model-kind", "pi", "--plays", "12"],
    )?;
    assert!(err.contains("14 free parameters"), "{err}");
    Ok(())
}

#[test]
fn decreasing_output_and_bad_split_are_explained() -> R {
    let csv: String = std::iter::once("x,y\n".to_string())
        .chain((0..50).map(|k| {
            let x = (k as f64 * 0.2).sin();
            format!("{x},{}\n", -x)
        }))
        .collect();
    let err = fails(&csv, &[])?;
    assert!(err.contains("negate the output"), "{err}");
    let err = fails(&format!("x,y\n{}", good_rows(50)), &["--validate", "7"])?;
    assert!(err.contains("no record 7"), "{err}");
    Ok(())
}

/// The header of `hyst run --model M --derivatives 2` of a piezo model on [`jet_csv`]'s file.
const JETS_RUN_HEADER: &str = "u_actuator_V,u_actuator_V_d1,u_actuator_V_d2,y_capsensor_um,\
                               y_capsensor_um_d1,y_capsensor_um_d2\n";

/// A smooth test signal with its first two time derivatives, as a CSV with the given column.
fn jet_csv(name: &str, n: usize, lo: f64, hi: f64) -> String {
    let mut s = format!("{name},{name}_d1,{name}_d2\n");
    let (mid, amp) = (0.5 * (lo + hi), 0.3 * (hi - lo));
    for k in 0..n {
        let t = k as f64 * 1e-3;
        let a = amp * (1.0 - 0.3 * (0.7 * t).cos());
        // x = mid + a(t) sin(3t)
        let (s3, c3) = ((3.0 * t).sin(), (3.0 * t).cos());
        let da = amp * 0.3 * 0.7 * (0.7 * t).sin();
        let dda = amp * 0.3 * 0.49 * (0.7 * t).cos();
        let x = mid + a * s3;
        let d1 = da * s3 + 3.0 * a * c3;
        let d2 = dda * s3 + 6.0 * da * c3 - 9.0 * a * s3;
        s += &format!("{x},{d1},{d2}\n");
    }
    s
}

/// Checks the output's derivatives (the model's output column y_capsensor_um, with _d1 and _d2)
/// against centred differences of y (y_d1) at dt = 1e-3, away from the input's reversals (where
/// the output's derivatives have a kink in time): all but `allowed_misses` samples (where a
/// piecewise model switches) must agree.
fn check_derivatives(csv: &str, input_d1: &[f64], tolerance: f64, allowed_misses: usize) -> R {
    let y = column(csv, "y_capsensor_um")?;
    let d1 = column(csv, "y_capsensor_um_d1")?;
    let d2 = column(csv, "y_capsensor_um_d2")?;
    let scale1 = d1.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let scale2 = d2.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let mut misses = 0;
    for k in 2..y.len() - 2 {
        if (k - 2..k + 2).any(|j| (input_d1[j] > 0.0) != (input_d1[j + 1] > 0.0)) {
            continue;
        }
        let fd1 = (y[k + 1] - y[k - 1]) / 2e-3;
        let fd2 = (d1[k + 1] - d1[k - 1]) / 2e-3;
        if (fd1 - d1[k]).abs() > tolerance * scale1 || (fd2 - d2[k]).abs() > tolerance * scale2 {
            misses += 1;
        }
    }
    assert!(
        misses <= allowed_misses,
        "{misses} samples disagree with finite differences"
    );
    Ok(())
}

/// `hyst fit --model-kind pi --json` of the bundled piezo record into `model`, with the
/// arguments `extra`.
fn fit_pi(model: &Path, extra: &[&str]) -> Output {
    let data = repo().join("data/piezo-sine/piezo_sine_1hz.csv");
    let mut args = vec![
        "fit",
        data.to_str().unwrap_or(""),
        "--input",
        "u_actuator_V",
        "--output",
        "y_capsensor_um",
        "-o",
        model.to_str().unwrap_or(""),
        "--model-kind",
        "pi",
        "--json",
    ];
    args.extend_from_slice(extra);
    HYST.output(&args)
}

#[test]
fn pi_with_output_polynomial_fits_runs_and_inverts_exactly() -> R {
    let dir = tempfile::tempdir()?;
    let model = dir.path().join("pi.toml");
    let data = repo().join("data/piezo-sine/piezo_sine_1hz.csv");
    let fit = |extra: &[&str]| fit_pi(&model, extra);
    let plain = fit(&[]);
    assert!(plain.status.success(), "{}", text(&plain.stderr));
    let plain: serde_json::Value = serde_json::from_slice(&plain.stdout)?;
    assert_eq!(plain["model"]["version"], 1);
    let out = fit(&["--pi-output", "poly3"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout)?;
    assert_eq!(report["model"]["version"], 2);
    assert_eq!(report["model"]["metrics"]["parameters"], 20);
    let pct = report["model"]["metrics"]["training"]["rms_pct_span"]
        .as_f64()
        .ok_or("pct")?;
    let plain_pct = plain["model"]["metrics"]["training"]["rms_pct_span"]
        .as_f64()
        .ok_or("pct")?;
    assert!(pct < plain_pct - 0.05, "{pct} vs plain PI {plain_pct}");
    let file = std::fs::read_to_string(&model)?;
    assert!(file.contains("[prandtl-ishlinskii.output]"), "{file}");
    assert!(file.contains("degree = 3"), "{file}");

    // hyst run --model reproduces the fitted RMS …
    let run_out = dir.path().join("run.csv");
    let m = model.to_str().ok_or("path")?;
    let out = HYST.output(&[
        "run",
        "--model",
        m,
        data.to_str().ok_or("path")?,
        "-o",
        run_out.to_str().ok_or("path")?,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let run_csv = std::fs::read_to_string(&run_out)?;
    assert!(run_csv.starts_with(&format!("{PIEZO_RUN_HEADER}\n")));
    let y = column(&run_csv, "y_capsensor_um_out")?;
    let measured = column(&std::fs::read_to_string(&data)?, "y_capsensor_um")?;
    let rms = (y
        .iter()
        .zip(&measured)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        / y.len() as f64)
        .sqrt();
    let fitted = report["model"]["metrics"]["training"]["rms"]
        .as_f64()
        .ok_or("rms")?;
    assert!((rms - fitted).abs() <= 1e-9 * fitted, "{rms} vs {fitted}");

    // … and its exact inverse gives back the command that produced the output.
    let command = dir.path().join("command.csv");
    let out = HYST.output(&[
        "run",
        "--model",
        m,
        "--inverse",
        "--column",
        "y_capsensor_um_out",
        run_out.to_str().ok_or("path")?,
        "-o",
        command.to_str().ok_or("path")?,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let u = column(&std::fs::read_to_string(&command)?, "u_actuator_V_out")?;
    let original = column(&run_csv, "u_actuator_V")?;
    let worst = u
        .iter()
        .zip(&original)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "compensator misses the command by {worst}");

    Ok(())
}

/// Derivatives through the PI model with its output polynomial (piecewise, value-exact), direct
/// and inverse; a missing derivative column is named with the option.
#[test]
fn pi_with_output_polynomial_passes_derivatives_both_ways() -> R {
    let dir = tempfile::tempdir()?;
    let model = dir.path().join("pi.toml");
    let out = fit_pi(&model, &["--pi-output", "poly3"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let m = model.to_str().ok_or("path")?;
    let jets = dir.path().join("jets.csv");
    std::fs::write(&jets, jet_csv("u_actuator_V", 4000, 0.0, 75.0))?;
    let out_jets = dir.path().join("out-jets.csv");
    let out = HYST.output(&[
        "run",
        "--model",
        m,
        "--derivatives",
        "2",
        jets.to_str().ok_or("path")?,
        "-o",
        out_jets.to_str().ok_or("path")?,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let direct = std::fs::read_to_string(&out_jets)?;
    assert!(direct.starts_with(JETS_RUN_HEADER));
    // Each of the 16 plays engages once after each of the 4 reversals, which upsets at most 3
    // centred differences.
    let input_d1 = column(&std::fs::read_to_string(&jets)?, "u_actuator_V_d1")?;
    check_derivatives(&direct, &input_d1, 1e-3, 3 * 16 * 4)?;
    let inverse = invert_with_derivatives(dir.path(), m, &direct, "pi-inverse")?;
    let input = std::fs::read_to_string(&jets)?;
    let (x, xd1) = (
        column(&input, "u_actuator_V")?,
        column(&input, "u_actuator_V_d1")?,
    );
    let (u, ud1) = (
        column(&inverse, "u_actuator_V")?,
        column(&inverse, "u_actuator_V_d1")?,
    );
    let scale = xd1.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let mut misses = 0;
    for k in 0..x.len() {
        assert!((u[k] - x[k]).abs() < 1e-9, "{k}: {} vs {}", u[k], x[k]);
        if (ud1[k] - xd1[k]).abs() > 1e-9 * scale {
            misses += 1;
        }
    }
    assert_eq!(misses, 0, "the inverse's derivative misses the command's");

    // A missing derivative column is named with the option.
    let out = HYST.output(&[
        "run",
        "--model",
        m,
        "--derivatives",
        "3",
        jets.to_str().ok_or("path")?,
        "-o",
        out_jets.to_str().ok_or("path")?,
    ]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("--derivatives 3") && err.contains("u_actuator_V_d3"),
        "{err}"
    );
    Ok(())
}

#[test]
fn smooth_model_derivatives_through_run_model() -> R {
    let dir = tempfile::tempdir()?;
    let model = dir.path().join("smooth.toml");
    let data = repo().join("data/piezo-sine/piezo_sine_1hz.csv");
    let out = HYST.output(&[
        "fit",
        data.to_str().ok_or("path")?,
        "--input",
        "u_actuator_V",
        "--output",
        "y_capsensor_um",
        "--output-shaping",
        "poly2",
        "-o",
        model.to_str().ok_or("path")?,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let m = model.to_str().ok_or("path")?;
    let jets = dir.path().join("jets.csv");
    std::fs::write(&jets, jet_csv("u_actuator_V", 4000, 0.0, 75.0))?;
    let out_jets = dir.path().join("out.csv");
    let out = HYST.output(&[
        "run",
        "--model",
        m,
        "--derivatives",
        "2",
        jets.to_str().ok_or("path")?,
        "-o",
        out_jets.to_str().ok_or("path")?,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let direct = std::fs::read_to_string(&out_jets)?;
    assert!(direct.starts_with(JETS_RUN_HEADER));
    // Smooth away from the reversals: every sample agrees.
    let input_d1 = column(&std::fs::read_to_string(&jets)?, "u_actuator_V_d1")?;
    check_derivatives(&direct, &input_d1, 1e-3, 0)?;
    // The compensator's derivatives give back the command's.
    let inverse = invert_with_derivatives(dir.path(), m, &direct, "smooth-inverse")?;
    let input = std::fs::read_to_string(&jets)?;
    let (xd1, xd2) = (
        column(&input, "u_actuator_V_d1")?,
        column(&input, "u_actuator_V_d2")?,
    );
    let (ud1, ud2) = (
        column(&inverse, "u_actuator_V_d1")?,
        column(&inverse, "u_actuator_V_d2")?,
    );
    for k in 0..xd1.len() {
        assert!(
            (ud1[k] - xd1[k]).abs() < 1e-6 * (1.0 + xd1[k].abs()),
            "{k}: {} vs {}",
            ud1[k],
            xd1[k]
        );
        assert!(
            (ud2[k] - xd2[k]).abs() < 1e-5 * (1.0 + xd2[k].abs()),
            "{k}: {} vs {}",
            ud2[k],
            xd2[k]
        );
    }
    Ok(())
}

#[test]
fn plots_are_written_and_a_bad_time_column_is_named() -> R {
    let dir = tempfile::tempdir()?;
    let data = repo().join("data/piezo-sine/piezo_sine_1hz.csv");
    let model = dir.path().join("m.toml");
    let plots = dir.path().join("plots");
    let args = |time: Option<&str>| {
        let mut a = vec![
            "fit".to_string(),
            data.to_string_lossy().into_owned(),
            "--input".into(),
            "u_actuator_V".into(),
            "--output".into(),
            "y_capsensor_um".into(),
            "-o".into(),
            model.to_string_lossy().into_owned(),
            "--plot".into(),
            plots.to_string_lossy().into_owned(),
        ];
        if let Some(t) = time {
            a.push("--time".into());
            a.push(t.into());
        }
        a
    };
    let bad = args(Some("seconds"));
    let out = HYST.output(&bad.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("--time") && err.contains("\"seconds\""),
        "{err}"
    );
    assert!(!model.exists(), "no model file after a failed fit");
    let good = args(None); // t_s is found by its name
    let out = HYST.output(&good.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(out.status.success(), "{}", text(&out.stderr));
    for f in [
        "fit-io.png",
        "fit-io.svg",
        "fit-residuals.png",
        "fit-residuals.svg",
    ] {
        assert!(plots.join(f).metadata()?.len() > 1000, "{f}");
    }
    let svg = std::fs::read_to_string(plots.join("fit-residuals.svg"))?;
    assert!(
        svg.contains("t_s"),
        "residuals are drawn over the time column"
    );
    Ok(())
}

/// The asked coverage is printed with the digits it was given (never rounded to another
/// number: 0.9999 is not "100 %"), the reached one rounded towards zero.
#[test]
fn the_asked_coverage_is_printed_as_given() -> R {
    let dir = tempfile::tempdir()?;
    let model = dir.path().join("m.toml");
    let data = repo().join("data/piezo-sine/piezo_sine_1hz.csv");
    for (coverage, shown) in [("0.1806", "18.06"), ("0.9999", "99.99"), ("1", "100")] {
        let out = HYST.output(&[
            "fit",
            data.to_str().ok_or("path")?,
            "--input",
            "u_actuator_V",
            "--output",
            "y_capsensor_um",
            "--coverage",
            coverage,
            "-o",
            model.to_str().ok_or("path")?,
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let report = text(&out.stdout);
        assert!(
            report.contains(&format!(
                "family RH(k1, Δk1, k2, Δk2) reproducing {shown} % of the samples"
            )),
            "{report}"
        );
    }
    Ok(())
}

/// Record ids beyond the integers a float holds are said to be so, with significant digits (not
/// "1000…000 (301 digits) is not an integer"); a `--validate` that is not an id says what the
/// option takes.
#[test]
fn record_ids_out_of_range_and_bad_validate_ids_are_explained() -> R {
    let mut csv = String::from("record,x,y\n");
    for (k, row) in good_rows(40).lines().enumerate() {
        let id = if k < 20 { "0" } else { "1e300" };
        csv += &format!("{id},{row}\n");
    }
    let err = fails(&csv, &[])?;
    assert!(
        err.contains(
            "bad.csv:22: column \"record\": record id 1.000e300 is beyond the range of record \
             ids (integers within ±9.0e15, which a float holds exactly)"
        ),
        "{err}"
    );
    let err = fails(&format!("x,y\n{}", good_rows(50)), &["--validate", "0.5"])?;
    assert!(
        err.contains(
            "invalid value '0.5' for '--validate <VALIDATE>': --validate takes the integer ids \
             of the records to hold out for validation"
        ),
        "{err}"
    );
    Ok(())
}

/// The clockwise refusal of the Prandtl–Ishlinskii model gives the gap with 3 significant
/// digits, not 3 fixed decimals.
#[test]
fn the_clockwise_gap_has_significant_digits() -> R {
    let csv: String = std::iter::once("x,y\n".to_string())
        .chain((0..400).map(|k| {
            let t = k as f64 * 0.05;
            format!("{},{}\n", t.sin(), (t + 0.6).sin())
        }))
        .collect();
    let err = fails(&csv, &["--model-kind", "pi"])?;
    let from = err.find("falling branch +").ok_or("no gap")? + "falling branch +".len();
    let gap = &err[from..from + err[from..].find(" %").ok_or("no %")?];
    assert_eq!(
        gap.replace('.', "").trim_start_matches('0').len(),
        3,
        "{err}"
    );
    Ok(())
}

/// `--plays 0` names the option once, with its value.
#[test]
fn a_bad_operator_count_names_the_option_once() -> R {
    let err = fails(
        &format!("x,y\n{}", good_rows(50)),
        &["--model-kind", "pi", "--plays", "0"],
    )?;
    assert_eq!(err, "error: --plays 0: expected 1 to 128 plays\n");
    Ok(())
}

/// Numbers in JSON (the reports' findings, pickled Python fit results) read back to the same
/// bits: serde_json's default parser is off by an ulp for some (0.48357522195178276, a fitted
/// loop gap, read back as 0.4835752219517827); the workspace enables its `float_roundtrip`.
#[test]
fn json_numbers_read_back_bit_for_bit() -> R {
    let mut values = vec![0.483_575_221_951_782_76_f64, 1e-300, 5e-324, f64::MAX, 0.1];
    // A spread of mantissas and exponents (a fixed linear congruential sequence).
    let mut bits = Lcg64::new(0x3ff0_0000_0000_0001);
    for _ in 0..20_000 {
        let v = f64::from_bits(bits.next_u64() >> 2); // positive, below 2^1022: finite
        values.push(v);
    }
    for v in values {
        let text = serde_json::to_string(&v)?;
        let back: f64 = serde_json::from_str(&text)?;
        assert_eq!(
            back.to_bits(),
            v.to_bits(),
            "{v:e} written {text}, read {back:e}"
        );
    }
    Ok(())
}
