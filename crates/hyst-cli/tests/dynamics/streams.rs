//! Timed runs: the input streamed from a file or a pipe, refused stamps, the warning about a
//! sample period too long for the loops' corners.

use super::*;
use crate::truths::*;

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
        let mut cmd = HYST.command();
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
    let out = HYST
        .command()
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
        let out = HYST
            .command()
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
