//! `hyst fit` end to end: the bundled piezo data, the model file read back by `hyst run --model`,
//! and every bad-data error (each names what is wrong, and no model file is left behind).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn hyst(args: &[&str]) -> Output {
    match Command::new(env!("CARGO_BIN_EXE_hyst")).args(args).output() {
        Ok(o) => o,
        Err(e) => unreachable!("cannot run hyst: {e}"),
    }
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
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

#[test]
fn piezo_fit_is_accurate_and_run_reads_the_model_back() -> R {
    let dir = tempfile::tempdir()?;
    let model = dir.path().join("piezo.toml");
    let data = repo().join("data/piezo-sine/piezo_sine_1hz.csv");
    let out = hyst(&[
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
    let out = hyst(&[
        "run",
        "--model",
        model.to_str().ok_or("path")?,
        data.to_str().ok_or("path")?,
        "-o",
        run_out.to_str().ok_or("path")?,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let y = column(&std::fs::read_to_string(&run_out)?, "y")?;
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

    // --inverse: the compensator turns the model output back into the input exactly.
    let inv_out = dir.path().join("inv.csv");
    let out = hyst(&[
        "run",
        "--model",
        model.to_str().ok_or("path")?,
        "--inverse",
        "--column",
        "y",
        run_out.to_str().ok_or("path")?,
        "-o",
        inv_out.to_str().ok_or("path")?,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let back = column(&std::fs::read_to_string(&inv_out)?, "y")?;
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
    let out = hyst(&[
        "fit",
        data.to_str().ok_or("path")?,
        "--input",
        "H_A_per_m",
        "--output",
        "B_T",
        "--model-kind",
        "pi",
        "--operators",
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
    let out = hyst(&args);
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
fn fewer_samples_than_parameters_is_refused() -> R {
    let err = fails(&format!("x,y\n{}", good_rows(3)), &[])?;
    assert!(
        err.contains("3 training samples but the model has 4 free parameters"),
        "{err}"
    );
    let err = fails(
        &format!("x,y\n{}", good_rows(10)),
        &["--model-kind", "pi", "--operators", "12"],
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
