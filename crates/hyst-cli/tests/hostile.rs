//! Hostile inputs, odd paths and signals: an output that is an input is refused before
//! anything is written; `-o -`, symbolic links and devices are written through; SIGINT/SIGTERM
//! stop at once with 130/143 and leave no output or temporary file; extreme numbers give finite
//! results or a one-line error naming the file and line; fits on data beyond the float range fail;
//! `hyst bench` is short by default; OS errors are printed once.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_test_support::cli::{stderr, wait_at_most, Binary};
use std::fs;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

/// Names of the entries of `dir`, hidden ones included, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

const DATA: &str = "x\n0\n0.5\n1\n0.2\n-0.4\n";

#[cfg(unix)]
#[test]
fn an_output_that_is_the_input_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fs::write(d.join("f.csv"), DATA).unwrap();
    std::os::unix::fs::symlink("f.csv", d.join("soft.csv")).unwrap();
    fs::hard_link(d.join("f.csv"), d.join("hard.csv")).unwrap();
    for out in ["f.csv", "soft.csv", "hard.csv", "./f.csv"] {
        let o = HYST.output_in(&["run", "--k1", "0.2", "--k2", "8", "f.csv", "-o", out], d);
        assert_eq!(o.status.code(), Some(1), "{out}");
        assert_eq!(
            stderr(&o),
            format!(
                "error: {out}: is the same file as the input f.csv (the input would be \
                 overwritten); choose another output\n"
            )
        );
        assert_eq!(fs::read_to_string(d.join("f.csv")).unwrap(), DATA);
    }
    // hyst fit: the data file is not replaced by the model.
    fs::write(d.join("d.csv"), "u,y\n0,0\n1,0.8\n0,0.2\n").unwrap();
    let o = HYST.output_in(
        &[
            "fit", "d.csv", "--input", "u", "--output", "y", "-o", "d.csv",
        ],
        d,
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("d.csv: is the same file as the input d.csv"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        fs::read_to_string(d.join("d.csv")).unwrap(),
        "u,y\n0,0\n1,0.8\n0,0.2\n"
    );
    assert_eq!(entries(d), ["d.csv", "f.csv", "hard.csv", "soft.csv"]);
}

#[cfg(unix)]
#[test]
fn dash_streams_to_stdout_and_links_and_devices_are_written_through() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fs::write(d.join("f.csv"), DATA).unwrap();
    let o = HYST.output_in(&["run", "--k1", "0.2", "--k2", "8", "f.csv", "-o", "-"], d);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.starts_with("x,y\n0,0\n0.5,"), "{text}");
    assert_eq!(text.lines().count(), 6);
    // The same bytes as a file.
    let o = HYST.output_in(
        &["run", "--k1", "0.2", "--k2", "8", "f.csv", "-o", "out.csv"],
        d,
    );
    assert!(o.status.success());
    assert_eq!(fs::read_to_string(d.join("out.csv")).unwrap(), text);
    // A symbolic link stays a link; its target gets the output.
    std::os::unix::fs::symlink("target.csv", d.join("link.csv")).unwrap();
    let o = HYST.output_in(
        &["run", "--k1", "0.2", "--k2", "8", "f.csv", "-o", "link.csv"],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(fs::symlink_metadata(d.join("link.csv"))
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(fs::read_to_string(d.join("target.csv")).unwrap(), text);
    // /dev/stdout (a link to /proc/self/fd/1, here a pipe) is written through, not replaced.
    let o = HYST.output_in(
        &[
            "run",
            "--k1",
            "0.2",
            "--k2",
            "8",
            "f.csv",
            "-o",
            "/dev/stdout",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8(o.stdout).unwrap(), text);
    assert!(fs::symlink_metadata("/dev/stdout")
        .unwrap()
        .file_type()
        .is_symlink());
    // A device is written, not replaced by a regular file; also through a link to it.
    std::os::unix::fs::symlink("/dev/null", d.join("null")).unwrap();
    for out in ["/dev/null", "null"] {
        let o = HYST.output_in(&["run", "--k1", "0.2", "--k2", "8", "f.csv", "-o", out], d);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert!(!fs::metadata("/dev/null").unwrap().is_file());
    assert!(fs::symlink_metadata(d.join("null"))
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(
        entries(d),
        ["f.csv", "link.csv", "null", "out.csv", "target.csv"]
    );
}

/// A CSV file of `rows` samples of a slow sine.
fn big_input(path: &Path, rows: usize) {
    use std::io::Write;
    let mut w = std::io::BufWriter::new(fs::File::create(path).unwrap());
    writeln!(w, "x").unwrap();
    for k in 0..rows {
        writeln!(w, "{:.6}", (k as f64 * 1e-3).sin() * 1.5).unwrap();
    }
}

fn signal(pid: u32, name: &str) {
    let status = Command::new("kill")
        .args([&format!("-{name}"), &pid.to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

/// How long a signalled run may take to end before the test fails instead of hanging: far
/// beyond any stop (the debug binary takes many seconds for the whole file), not a measure of
/// speed.
const HANG: Duration = Duration::from_secs(60);

/// Spawns `hyst run` on 2 M rows in a fresh directory (input outside it), waits for
/// `ready(directory, time since the spawn)`, checks that the run is still going, sends `sig` and
/// returns (exit code, the directory's entries afterwards).
fn interrupt_run(sig: &str, ready: impl Fn(&Path, Duration) -> bool) -> (Option<i32>, Vec<String>) {
    let input_dir = tempfile::tempdir().unwrap();
    let input = input_dir.path().join("in.csv");
    big_input(&input, 2_000_000);
    let dir = tempfile::tempdir().unwrap();
    let mut child = HYST
        .command()
        .args(["run", "--k1", "0.2", "--k2", "8"])
        .arg(&input)
        .args(["-o", "out.csv"])
        .current_dir(dir.path())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let waited = Instant::now();
    while !ready(dir.path(), waited.elapsed()) {
        assert!(
            waited.elapsed() < Duration::from_secs(120),
            "never ready: {:?}",
            entries(dir.path())
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    // Still running: the signal interrupts work in progress.
    assert!(
        child.try_wait().unwrap().is_none(),
        "finished before the signal"
    );
    signal(child.id(), sig);
    let out = wait_at_most(child, HANG, "hyst run after the signal");
    (out.status.code(), entries(dir.path()))
}

// The run was still going when signalled (interrupt_run checks), so its exit code 128 + signal
// (only the signal handler exits with it) and an empty directory (no output, no temporary file;
// a run that went on to the end would have renamed out.csv into place) show that it stopped on
// the signal.
#[cfg(unix)]
#[test]
fn ctrl_c_during_run_stops_with_130_and_no_output() {
    // Signalled while the 2 M rows are being read or run: 100 ms in, where the release binary
    // takes about 0.4 s for the whole file and the debug binary many seconds.
    let (code, left) = interrupt_run("INT", |_, running| running > Duration::from_millis(100));
    assert_eq!(code, Some(130));
    assert!(left.is_empty(), "{left:?}");
}

#[cfg(unix)]
#[test]
fn sigterm_while_writing_removes_the_temporary_file() {
    // Signalled once the hidden temporary file exists, i.e. while the output is being written.
    let (code, left) = interrupt_run("TERM", |d, _| {
        entries(d)
            .iter()
            .any(|n| n.starts_with(".out.csv.") && n.ends_with(".tmp"))
    });
    assert_eq!(code, Some(143));
    assert!(left.is_empty(), "{left:?}");
}

#[cfg(unix)]
#[test]
fn ctrl_c_during_fit_exits_130_and_writes_no_model() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    {
        let mut w = std::io::BufWriter::new(fs::File::create(d.join("d.csv")).unwrap());
        writeln!(w, "u,y").unwrap();
        let mut h = hyst_core::Hysteresis::new(0.2, 8.0).unwrap();
        // 10^6 rows: a fit of several seconds, so that the signal 0.7 s in still finds it
        // running on a loaded machine (with 2·10^5 rows it took about 1 s, and a sleep
        // overshooting under load let it finish first).
        for k in 0..1_000_000 {
            let u = (k as f64 * 0.003).sin() * (1.0 + 0.3 * (k as f64 * 1e-4).cos());
            writeln!(w, "{u},{}", hyst_core::Operator::step(&mut h, u) * 2.0).unwrap();
        }
    }
    let mut child = HYST
        .command()
        .args([
            "fit", "d.csv", "--input", "u", "--output", "y", "-o", "m.toml",
        ])
        .current_dir(d)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(700));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the fit finished before the signal"
    );
    signal(child.id(), "INT");
    let out = wait_at_most(child, HANG, "hyst fit after the signal");
    assert_eq!(out.status.code(), Some(130));
    assert_eq!(entries(d), ["d.csv"]);
}

#[test]
fn extreme_inputs_give_finite_outputs_or_an_error_naming_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fs::write(d.join("big.csv"), "x\n1e308\n-1e308\n1e308\n").unwrap();
    let o = HYST.output_in(
        &["run", "--k1", "0.2", "--k2", "8", "big.csv", "-o", "-"],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        String::from_utf8(o.stdout).unwrap(),
        "x,y\n1e308,1e308\n-1e308,-1e308\n1e308,1e308\n"
    );
    // The inverse within k1 = 1e300 of -MAX would be below -MAX: refused, naming line 3.
    fs::write(
        d.join("max.csv"),
        "# falls to -MAX\nx\n0\n-1.7976931348623157e308\n",
    )
    .unwrap();
    let o = HYST.output_in(
        &[
            "run",
            "--inverse",
            "--k1",
            "1e300",
            "--k2",
            "1",
            "max.csv",
            "-o",
            "out.csv",
        ],
        d,
    );
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "error: max.csv:4: column 1 (\"x\"): value -1.7976931348623157e308: input sample \
         -1.7976931348623157e308: the output or one of its time derivatives is beyond the float \
         range (-inf)\n"
    );
    assert_eq!(entries(d), ["big.csv", "max.csv"]);
    // new(1e300, 1e300): a near-backlash far beyond the float range of k2 M*, finite.
    fs::write(d.join("small.csv"), "x\n0\n1\n-1\n").unwrap();
    let o = HYST.output_in(
        &[
            "run",
            "--k1",
            "1e300",
            "--k2",
            "1e300",
            "small.csv",
            "-o",
            "-",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for line in String::from_utf8(o.stdout).unwrap().lines().skip(1) {
        let y: f64 = line.split(',').nth(1).unwrap().parse().unwrap();
        assert!(y.abs() < 1e-15, "{line}");
    }
}

#[test]
fn a_subnormal_k2_is_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("f.csv"), DATA).unwrap();
    let o = HYST.output_in(
        &[
            "run", "--k1", "0.2", "--k2", "1e-320", "f.csv", "-o", "o.csv",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "error: --k1/--k2: invalid parameter k2 = 1e-320: must be finite and > 0, a normal float \
         (>= 2.2e-308 for f64, >= 1.2e-38 for f32; subnormal values lose precision)\n"
    );
    assert_eq!(entries(dir.path()), ["f.csv"]);
}

#[test]
fn a_k1_k2_product_below_the_float_range_is_named_with_its_factors() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("f.csv"), DATA).unwrap();
    let o = HYST.output_in(
        &[
            "run", "--k1", "1e-300", "--k2", "1e-300", "f.csv", "-o", "o.csv",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "error: --k1/--k2: invalid parameters k1 = 1e-300 and k2 = 1e-300: their product k1·k2 \
         = 1e-600 is below 2.0e-292 for f64 (9.9e-32 for f32), where k2 M* turns subnormal and \
         the output loses its precision; express the input in other units\n"
    );
    assert_eq!(entries(dir.path()), ["f.csv"]);
}

#[test]
fn fits_on_data_beyond_the_float_range_fail_with_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut scaled = String::from("u,y\n");
    let mut outlier = String::from("u,y\n");
    let mut h = hyst_core::Hysteresis::new(0.2, 8.0).unwrap();
    for k in 0..400 {
        let u = (k as f64 * 0.05).sin();
        let y = hyst_core::Operator::step(&mut h, u);
        scaled.push_str(&format!("{:e},{:e}\n", u * 1e300, y * 1e300));
        let y = if k == 100 { 1e308 } else { y };
        outlier.push_str(&format!("{u},{y}\n"));
    }
    fs::write(d.join("scaled.csv"), scaled).unwrap();
    fs::write(d.join("outlier.csv"), outlier).unwrap();
    for (file, line, value) in [
        ("scaled.csv", 3, "4.997916927067833e298"),
        ("outlier.csv", 102, "1e308"),
    ] {
        let o = HYST.output_in(
            &["fit", file, "--input", "u", "--output", "y", "-o", "m.toml"],
            d,
        );
        assert_eq!(o.status.code(), Some(1), "{file}");
        let column = if file == "scaled.csv" { "u" } else { "y" };
        assert_eq!(
            stderr(&o),
            format!(
                "error: {file}:{line}: column \"{column}\": {value} is too large for the fit \
                 (|value| must be at most 1e100, or squared residuals overflow): rescale the \
                 column (other units) or remove the outlier\n"
            )
        );
    }
    assert_eq!(entries(d), ["outlier.csv", "scaled.csv"]);
}

/// Data whose span is below 1e-100 squared to zero in the fit (1e-300: "RMS 0 … standard error
/// NaN"; 1e-160: the output offset unidentified): refused, symmetric to the upper limit. A
/// constant output and the same column as input and output are refused too.
#[test]
fn tiny_constant_and_repeated_columns_are_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut tiny = String::from("u,y\n");
    let mut flat = String::from("u,y\n");
    let mut h = hyst_core::Hysteresis::new(0.2, 8.0).unwrap();
    for k in 0..400 {
        let u = (k as f64 * 0.05).sin();
        let y = hyst_core::Operator::step(&mut h, u);
        tiny.push_str(&format!("{u},{:e}\n", y * 1e-300));
        flat.push_str(&format!("{u},2.5\n"));
    }
    fs::write(d.join("tiny.csv"), tiny).unwrap();
    fs::write(d.join("flat.csv"), flat).unwrap();
    let o = HYST.output_in(
        &[
            "fit", "tiny.csv", "--input", "u", "--output", "y", "-o", "m.toml",
        ],
        d,
    );
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(
        e.starts_with("error: tiny.csv: column \"y\" spans only ")
            && e.contains("e-300 (from ")
            && e.contains(
                "too small for the fit (the span must be at least 1e-100, or squared residuals \
                 underflow): rescale the column (other units)"
            ),
        "{e}"
    );
    let o = HYST.output_in(
        &[
            "fit", "flat.csv", "--input", "u", "--output", "y", "-o", "m.toml",
        ],
        d,
    );
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "error: flat.csv: column \"y\" (the output) is constant (2.5) over all 400 training \
         samples: a hysteresis model needs an output that moves\n"
    );
    let o = HYST.output_in(
        &[
            "fit", "flat.csv", "--input", "u", "--output", "u", "-o", "m.toml",
        ],
        d,
    );
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "error: flat.csv: the input and the output are the same column \"u\": a hysteresis \
         model needs an output measured apart from its input\n"
    );
    assert_eq!(entries(d), ["flat.csv", "tiny.csv"]);
}

/// The figure `key` of `hyst bench --json`'s report `json` (NaN if it is null).
fn ns(json: &serde_json::Value, key: &str) -> f64 {
    json[key].as_f64().unwrap_or(f64::NAN)
}

/// The ratio `key` of the report `json` is `expected`, the quotient of the figures it names.
fn ratio_is(json: &serde_json::Value, key: &str, expected: f64) {
    let ratio = ns(json, key);
    assert!(
        (ratio - expected).abs() <= 1e-12 * expected,
        "{key}: {ratio} vs {expected}"
    );
}

/// Whether this processor has AVX2 + FMA (the bank's forced-AVX2 figures are null otherwise).
fn avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    let avx2 =
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma");
    #[cfg(not(target_arch = "x86_64"))]
    let avx2 = false;
    avx2
}

/// The report's tick-by-tick figures of the banks and of 1,024 scalar operators are there, and
/// each tick ratio is the quotient of the figures it names (null with them).
fn tick_ratios_are_the_quotients(json: &serde_json::Value) {
    let ns = |key: &str| ns(json, key);
    // The banks tick by tick, next to 1,024 scalar operators stepped the same way, on the
    // kernel of the run and with the AVX2 kernel forced (null where the processor has none).
    for key in [
        "bank_tick_inverse_ns",
        "bank_tick_direct_ns",
        "bank_tick_inverse_f32_ns",
        "scalar_tick_inverse_ns",
        "scalar_tick_direct_ns",
    ] {
        assert!(ns(key) > 0.0 && ns(key).is_finite(), "{key}: {}", json[key]);
    }
    for (ratio, over, under) in [
        (
            "bank_tick_inverse_over_scalar",
            "bank_tick_inverse_ns",
            "scalar_tick_inverse_ns",
        ),
        (
            "bank_tick_direct_over_scalar",
            "bank_tick_direct_ns",
            "scalar_tick_direct_ns",
        ),
        (
            "bank_tick_inverse_f32_over_bank_tick_inverse",
            "bank_tick_inverse_f32_ns",
            "bank_tick_inverse_ns",
        ),
        (
            "bank_avx2_tick_inverse_over_scalar",
            "bank_avx2_tick_inverse_ns",
            "scalar_tick_inverse_ns",
        ),
        (
            "bank_avx2_tick_direct_over_scalar",
            "bank_avx2_tick_direct_ns",
            "scalar_tick_direct_ns",
        ),
        (
            "bank_avx2_tick_inverse_f32_over_bank_avx2_tick_inverse",
            "bank_avx2_tick_inverse_f32_ns",
            "bank_avx2_tick_inverse_ns",
        ),
    ] {
        let expected = ns(over) / ns(under);
        if json[over].is_null() {
            assert!(json[ratio].is_null(), "{ratio}: {}", json[ratio]);
        } else {
            ratio_is(json, ratio, expected);
        }
    }
    assert!(json["bank_tick_goals_met"].is_boolean());
}

#[test]
fn bench_says_what_its_time_means_and_is_short_by_default() {
    let help = HYST.command().args(["bench", "--help"]).output().unwrap();
    let help = String::from_utf8(help.stdout).unwrap();
    assert!(
        help.contains("Total measuring time of the whole run"),
        "{help}"
    );
    // The default measuring budget is 1 s (stated, not timed: wall clocks on a shared machine
    // say nothing).
    assert!(help.contains("[default: 1]"), "{help}");
    let o = HYST.command().args(["bench", "--json"]).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(json["direct_ns"].as_f64().unwrap() > 0.0);
    let ns = |key: &str| json[key].as_f64().unwrap_or(f64::NAN);
    // The banks of 1,024 channels are measured in the same run, next to the scalar keys.
    for key in [
        "inverse_ns",
        "inverse_d2_ns",
        "model_ns",
        "exp_ns",
        "lambert_w0_ns",
        "bank_inverse_ns",
        "bank_direct_ns",
        "bank_inverse_f32_ns",
    ] {
        assert!(ns(key) > 0.0 && ns(key).is_finite(), "{key}: {}", ns(key));
    }
    // Each ratio is the quotient of the figures it names, measured in the same run.
    let ratio_is = |key: &str, expected: f64| ratio_is(&json, key, expected);
    ratio_is(
        "direct_over_w0_plus_exp",
        ns("direct_ns") / (ns("lambert_w0_ns") + ns("exp_ns")),
    );
    ratio_is("inverse_over_exp", ns("inverse_ns") / ns("exp_ns"));
    ratio_is(
        "bank_inverse_over_inverse",
        ns("bank_inverse_ns") / ns("inverse_ns"),
    );
    // The f32 bank against the f64 bank, its rate, and one verdict over the four bank goals.
    let f32_ns = ns("bank_inverse_f32_ns");
    ratio_is(
        "bank_inverse_f32_over_bank_inverse",
        f32_ns / ns("bank_inverse_ns"),
    );
    let rate = json["bank_inverse_f32_channel_samples_per_s"]
        .as_f64()
        .unwrap();
    assert!((rate * f32_ns - 1e9).abs() <= 1e-3, "{rate} x {f32_ns}");
    assert!(json["bank_goals_met"].is_boolean());
    tick_ratios_are_the_quotients(&json);
    let avx2 = avx2();
    assert_eq!(json["bank_avx2_tick_goals_met"].is_boolean(), avx2);
    assert_eq!(json["bank_avx2_tick_inverse_ns"].is_f64(), avx2);
    assert!(json["kernel"].as_str().is_some_and(|k| !k.is_empty()));
}

/// `hyst bench` prints the banks' rows and goals; `--kernel` forces the kernel that runs
/// (portable runs everywhere), one this processor cannot run is refused by name, an unknown one
/// by clap.
#[test]
fn bench_prints_the_banks_and_runs_the_kernel_it_is_given() {
    let avx2 = avx2();
    let text = HYST
        .command()
        .args(["bench", "--seconds", "0.05"])
        .output()
        .unwrap();
    let text = String::from_utf8(text.stdout).unwrap();
    for row in [
        "bank of 1024 H^-1, f64",
        "bank of 1024 H, f64",
        "bank H f64 / scalar H:",
        "bank H^-1 f32 / bank H^-1 f64:",
        "goal bank H^-1 f32 >= 500 M channel-samples/s",
        "bank kernel:",
        "1024 scalar H^-1, f64, tick by tick",
        "bank H^-1 f64 / scalar H^-1, tick:",
        "goal bank H^-1 f32 tick <= 0.5 x bank H^-1 f64",
    ] {
        assert!(text.contains(row), "{text}");
    }
    let forced = HYST
        .command()
        .args([
            "bench",
            "--seconds",
            "0.05",
            "--json",
            "--kernel",
            "portable",
        ])
        .output()
        .unwrap();
    assert!(forced.status.success(), "{}", stderr(&forced));
    let forced: serde_json::Value = serde_json::from_slice(&forced.stdout).unwrap();
    // The kernel of the run, also after the workloads that forced AVX2 for their calls.
    assert_eq!(forced["kernel"], "portable");
    assert_eq!(forced["bank_avx2_tick_direct_ns"].is_f64(), avx2);
    let unknown = HYST
        .command()
        .args(["bench", "--kernel", "neon"])
        .output()
        .unwrap();
    assert!(!unknown.status.success() && stderr(&unknown).contains("neon"));
}

#[test]
fn bench_fits_a_random_walk_when_asked() {
    let o = HYST
        .command()
        .args(["bench", "--seconds", "0.05", "--json"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    // Left out by default, its keys there all the same.
    assert_eq!(json["fit_rows"], 0);
    assert!(json["fit_over_run"].is_null() && json["fit_peak_bytes"].is_null());
    assert!(json["run_peak_bytes"].is_null());
    let o = HYST
        .command()
        .args([
            "bench",
            "--seconds",
            "0.05",
            "--json",
            "--fit-rows",
            "20000",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["fit_rows"], 20000);
    let (fit, run) = (
        json["fit_seconds"].as_f64().unwrap(),
        json["run_seconds"].as_f64().unwrap(),
    );
    let ratio = json["fit_over_run"].as_f64().unwrap();
    assert!(fit > 0.0 && run > 0.0 && (ratio - fit / run).abs() <= 1e-12 * ratio);
    assert!(json["fit_goal_met"].is_boolean());
    // The memory goal is stated at 10 M rows: no verdict below.
    assert!(json["fit_memory_goal_met"].is_null());
    if cfg!(target_os = "linux") {
        let peak = json["fit_peak_bytes"].as_f64().unwrap();
        assert!(peak > 1e5 && peak < 1e10, "{peak}");
        let run_peak = json["run_peak_bytes"].as_f64().unwrap();
        assert!(run_peak > 1e5 && run_peak < 1e10, "{run_peak}");
    }
}

#[test]
fn an_os_error_is_printed_once() {
    let dir = tempfile::tempdir().unwrap();
    let o = HYST.output_in(
        &[
            "run",
            "--k1",
            "0.2",
            "--k2",
            "8",
            "missing.csv",
            "-o",
            "o.csv",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    let os = std::io::Error::from_raw_os_error(2).to_string();
    assert_eq!(
        stderr(&o),
        format!("error: missing.csv: cannot read: {os}\n")
    );
    let o = HYST.output_in(
        &[
            "run",
            "--k1",
            "0.2",
            "--k2",
            "8",
            "missing.csv",
            "-o",
            "no/dir/o.csv",
        ],
        dir.path(),
    );
    assert_eq!(stderr(&o).matches("os error").count(), 1, "{}", stderr(&o));
}
