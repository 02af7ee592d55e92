//! Time stamps and the prefilter: bad stamps refused with their line, the prefiltered reference
//! tracked, its bandwidth checked.

use super::*;
use crate::truths::*;

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
        let out = HYST
            .command()
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
    let out = HYST
        .command()
        .args(["run", "--model", model.to_str().unwrap(), "--inverse"])
        .args([desired.to_str().unwrap(), "-o", command.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("--prefilter-hz"),
        "{err}"
    );
    HYST.stdout(&[
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
    HYST.stdout(&[
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
    let err = HYST.failure(args);
    assert!(!Path::new(args.last().unwrap()).exists(), "{args:?}");
    err
}

/// The piezo model with dynamics of the firmware examples, and a desired output at 1 kHz that
/// steps at 0.5 s then follows a sine, written to `dir` twice: plain (`d.csv`) and with zero
/// derivative columns (`dd.csv`). Returns the three paths.
fn step_reference(dir: &Path) -> (String, String, String) {
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
    let plain = dir.join("d.csv");
    write_csv(&plain, "t,y_capsensor_um", &rows);
    let with_derivatives = dir.join("dd.csv");
    let rows_d: Vec<Vec<f64>> = rows.iter().map(|r| vec![r[0], r[1], 0.0, 0.0]).collect();
    write_csv(
        &with_derivatives,
        "t,y_capsensor_um,y_capsensor_um_d1,y_capsensor_um_d2",
        &rows_d,
    );
    let text = |p: std::path::PathBuf| p.to_str().unwrap().to_string();
    (model, text(plain), text(with_derivatives))
}

/// `--prefilter-hz` just below its bound, at most 1/20 of the Nyquist frequency of the record's
/// sample period (25 Hz at 1 kHz): the plant of order 2 driven by the commands follows the
/// prefiltered reference of a step within 0.5 % of its span.
#[test]
fn a_prefilter_at_its_bound_is_followed() {
    let dir = tempfile::tempdir().unwrap();
    let (model, plain, _) = step_reference(dir.path());
    let h = 1e-3;
    let command = dir.path().join("c.csv");
    let command = command.to_str().unwrap();
    HYST.stdout(&[
        "run",
        "--model",
        &model,
        "--inverse",
        "--prefilter-hz",
        "24.9",
        &plain,
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
    HYST.stdout(&[
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
}

/// `--prefilter-hz F` is checked whenever it is given: a finite, positive frequency (with the
/// derivative columns in the file, which the compensator then takes instead, and with --k1/--k2,
/// which refuse it), at most 1/20 of the Nyquist frequency of the record's sample period (25 Hz
/// at 1 kHz); above it the commands grow without bound (5e11 Hz at 1 kHz would give commands
/// of 4e10 for outputs of 20).
#[test]
fn prefilter_bandwidth_is_checked_whenever_given() {
    let dir = tempfile::tempdir().unwrap();
    let (model, plain, with_derivatives) = step_reference(dir.path());
    let (plain, with_derivatives) = (plain.as_str(), with_derivatives.as_str());
    let command = dir.path().join("c.csv");
    let command = command.to_str().unwrap();
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
