//! Pipes, FIFOs and outputs that would replace an input: `hyst fit` reads its data once and records
//! the size and hash of what it read, even from a pipe; no output (the model file or a plot) may be
//! the data or another output; a FIFO as input or output never hangs the same-file check.
#![cfg(unix)]
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_test_support::cli::{stderr, wait_at_most, Binary};
use std::fs;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

/// The first 300 rows of the bundled piezo record: a fit of a few seconds in a debug build.
fn piezo(dir: &Path) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = fs::read_to_string(root.join("data/piezo-sine/piezo_sine_1hz.csv")).unwrap();
    let head: Vec<&str> = text.lines().take(301).collect();
    let path = dir.join("d.csv");
    fs::write(&path, head.join("\n") + "\n").unwrap();
    path
}

const FIT: [&str; 4] = ["--input", "u_actuator_V", "--output", "y_capsensor_um"];

fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

#[test]
fn a_fit_from_a_pipe_records_what_it_read() {
    let dir = tempfile::tempdir().unwrap();
    let data = piezo(dir.path());
    let bytes = fs::read(&data).unwrap();
    let model = dir.path().join("m.toml");
    let mut child = HYST
        .command()
        .arg("fit")
        .arg("/dev/stdin")
        .args(FIT)
        .arg("-o")
        .arg(&model)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(&bytes).unwrap();
    let out = wait_at_most(child, Duration::from_secs(120), "hyst fit /dev/stdin");
    assert!(out.status.success(), "{}", stderr(&out));
    let file: toml::Table = fs::read_to_string(&model).unwrap().parse().unwrap();
    let provenance = &file["provenance"];
    assert_eq!(provenance["bytes"].as_integer(), Some(bytes.len() as i64));
    assert_eq!(
        provenance["fnv1a64"].as_str().unwrap(),
        format!("{:016x}", fnv1a64(&bytes))
    );
}

#[test]
fn no_output_may_be_the_data_or_another_output() {
    let dir = tempfile::tempdir().unwrap();
    let data = piezo(dir.path());
    let original = fs::read(&data).unwrap();
    let plots = dir.path().join("pl");
    fs::create_dir(&plots).unwrap();
    // The data file is where a plot would go.
    let inside = plots.join("fit-io.svg");
    fs::copy(&data, &inside).unwrap();
    let out = HYST
        .command()
        .arg("fit")
        .arg(&inside)
        .args(FIT)
        .args(["-o", "m.toml", "--plot", "pl"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("is the same file as the input"),
        "{}",
        stderr(&out)
    );
    assert_eq!(fs::read(&inside).unwrap(), original);
    assert!(!dir.path().join("m.toml").exists());
    // The model file is where a plot would go.
    let out = HYST
        .command()
        .arg("fit")
        .arg(&data)
        .args(FIT)
        .args(["-o", "pl/fit-io.png", "--plot", "pl"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("is the same file as the output"),
        "{}",
        stderr(&out)
    );
    assert!(!plots.join("fit-io.png").exists());
}

fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(status.success());
}

#[test]
fn fifos_as_output_and_as_input_do_not_hang() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("x.csv");
    fs::write(&input, "x\n0\n0.5\n1\n0.2\n").unwrap();
    // Output into a FIFO that a reader drains.
    let fifo = dir.path().join("out.fifo");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let mut text = String::new();
            fs::File::open(&fifo)
                .unwrap()
                .read_to_string(&mut text)
                .unwrap();
            text
        })
    };
    let child = HYST
        .command()
        .args(["run", "--k1", "0.2", "--k2", "8"])
        .arg(&input)
        .arg("-o")
        .arg(&fifo)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let out = wait_at_most(child, Duration::from_secs(30), "hyst run -o FIFO");
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(reader.join().unwrap().starts_with("x,y\n"));
    // A fit whose data comes through a FIFO.
    let data = piezo(dir.path());
    let bytes = fs::read(&data).unwrap();
    let in_fifo = dir.path().join("in.fifo");
    mkfifo(&in_fifo);
    let writer = {
        let in_fifo = in_fifo.clone();
        std::thread::spawn(move || {
            fs::OpenOptions::new()
                .write(true)
                .open(&in_fifo)
                .unwrap()
                .write_all(&bytes)
                .unwrap();
        })
    };
    let model = dir.path().join("fifo.toml");
    let child = HYST
        .command()
        .arg("fit")
        .arg(&in_fifo)
        .args(FIT)
        .arg("-o")
        .arg(&model)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let out = wait_at_most(child, Duration::from_secs(120), "hyst fit FIFO");
    writer.join().unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(model.exists());
}

/// Item 10: beyond `ulimit -f` the write fails with a message naming the output, and no
/// temporary file is left (SIGXFSZ killed hyst silently and left `.NAME.XXXXXX.tmp`).
#[test]
fn a_file_size_limit_is_an_error_that_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut data = String::from("x\n");
    for i in 0..200_000 {
        data += &format!("{}\n", (f64::from(i) * 0.01).sin());
    }
    fs::write(dir.path().join("big.csv"), data).unwrap();
    let script = format!(
        "ulimit -f 100; exec '{}' run --k1 0.2 --k2 8 big.csv -o out.csv",
        env!("CARGO_BIN_EXE_hyst")
    );
    let out = Command::new("sh")
        .args(["-c", &script])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("out.csv") && stderr(&out).contains("too large"),
        "{}",
        stderr(&out)
    );
    let left: Vec<_> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, ["big.csv"], "{left:?}");
}

/// Item 9: a line without end (/dev/zero; a header and a 300 MB line of NUL bytes under
/// `ulimit -v 1000000`) is refused at the bound, naming the line, in constant memory.
#[test]
fn endless_lines_are_refused_in_constant_memory() {
    let dir = tempfile::tempdir().unwrap();
    let out = HYST
        .command()
        .args(["run", "--k1", "1", "--k2", "1", "/dev/zero", "-o", "x.csv"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("/dev/zero:1: the line is longer than"),
        "{}",
        stderr(&out)
    );
    let mut f = fs::File::create(dir.path().join("nul.csv")).unwrap();
    f.write_all(b"x\n").unwrap();
    let block = vec![0_u8; 1 << 20];
    for _ in 0..300 {
        f.write_all(&block).unwrap();
    }
    drop(f);
    let script = format!(
        "ulimit -v 1000000; exec '{}' run --k1 1 --k2 1 nul.csv -o x.csv",
        env!("CARGO_BIN_EXE_hyst")
    );
    let out = Command::new("sh")
        .args(["-c", &script])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("nul.csv:2: the line is longer than"),
        "{}",
        stderr(&out)
    );
    assert!(!dir.path().join("x.csv").exists());
}

/// Item 11: a message quotes at most the start of a long value, and says how long it was (a
/// 5 MB cell, a 5 MB column name in a model file).
#[test]
fn long_values_are_cut_in_messages() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(
        dir.path().join("cell.csv"),
        format!("x,y\n1,{}\n", "z".repeat(5_000_000)),
    )
    .unwrap();
    let out = HYST
        .command()
        .args([
            "run", "--k1", "1", "--k2", "1", "cell.csv", "--column", "y", "-o", "o.csv",
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.len() < 400 && err.contains("(5000000 bytes in all)"),
        "{}",
        &err[..err.len().min(400)]
    );
    // A model whose input column name is 5 MB long.
    let data = piezo(dir.path());
    let model = dir.path().join("m.toml");
    let fit = HYST
        .command()
        .arg("fit")
        .arg(&data)
        .args(FIT)
        .arg("-o")
        .arg(&model)
        .output()
        .unwrap();
    assert!(fit.status.success(), "{}", stderr(&fit));
    let text = fs::read_to_string(&model).unwrap().replacen(
        "input = \"u_actuator_V\"",
        &format!("input = \"{}\"", "u".repeat(5_000_000)),
        1,
    );
    fs::write(&model, text).unwrap();
    let out = HYST
        .command()
        .args(["run", "--model", "m.toml", "d.csv", "-o", "o.csv"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.len() < 400 && err.contains("(5000000 bytes in all)"),
        "{}",
        &err[..err.len().min(400)]
    );
}

/// A report or `-o -` whose reader went away (`hyst bench | head`, `hyst run ... -o - | head`)
/// ends quietly with status 0: no panic, no "Broken pipe".
#[test]
fn a_closed_standard_output_ends_quietly() {
    let dir = tempfile::tempdir().expect("a directory");
    let data = dir.path().join("x.csv");
    let rows: String = (0..200_000)
        .map(|k| format!("{}\n", f64::from(k) * 1e-4))
        .collect();
    fs::write(&data, format!("x\n{rows}")).expect("written");
    let data = data.to_string_lossy().into_owned();
    let commands: [&[&str]; 2] = [
        &["bench", "--seconds", "0.3"],
        &["run", "--k1", "0.1", "--k2", "5", &data, "-o", "-"],
    ];
    for args in commands {
        let mut child = HYST
            .command()
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("hyst runs");
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("hyst ends");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {err}");
        assert!(err.is_empty(), "{args:?}: {err}");
    }
}
