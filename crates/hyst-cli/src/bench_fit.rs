//! `hyst bench`'s long-record workload (the fit's goals): a random walk with a reversal
//! every three samples or so (the case the turning-point reduction cannot shorten), its output
//! from a known operator plus noise, written to a temporary CSV; then `hyst fit` and
//! `hyst run --model` of the fitted model on that file, each as a child process of this very
//! executable (the commands a user runs, CSV reading and writing included): wall time of each,
//! the fit's over the run's (goal ≤ 6), and the fit's and the run's peak resident memory (Linux:
//! the child's `VmHWM` from `/proc`, read until it exits; goals ≤ 256 MB at 10 M rows for the
//! fit, the same few MB at any length for the run).

use std::fmt::Write as _;
use std::io::{BufWriter, Write as _};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use hyst_core::{Hysteresis, Operator};

/// The fit's goal: its wall time over `hyst run`'s on the same file.
pub const FIT_OVER_RUN_GOAL: f64 = 6.0;

/// The fit's memory goal: peak resident bytes at [`MEMORY_GOAL_ROWS`] rows.
pub const MEMORY_GOAL_BYTES: f64 = 256e6;

/// The record length at which the memory goal is stated.
pub const MEMORY_GOAL_ROWS: usize = 10_000_000;

/// What the long-record workload measured.
pub struct FitFigures {
    /// Rows of the record.
    pub rows: usize,
    /// Wall time of `hyst fit`, s.
    pub fit_s: f64,
    /// Wall time of `hyst run --model` (the faster of two runs), s.
    pub run_s: f64,
    /// The fit's peak resident memory, bytes (`None` where `/proc` does not tell).
    pub peak_bytes: Option<f64>,
    /// The run's peak resident memory (the larger of its two runs), bytes (`None` where
    /// `/proc` does not tell).
    pub run_peak_bytes: Option<f64>,
}

impl FitFigures {
    /// `fit_s` over `run_s`.
    pub fn ratio(&self) -> f64 {
        self.fit_s / self.run_s
    }

    /// Whether the memory goal is met: `None` below [`MEMORY_GOAL_ROWS`] rows, where it is not
    /// stated, or without a peak.
    pub fn memory_goal_met(&self) -> Option<bool> {
        let peak = self.peak_bytes?;
        (self.rows >= MEMORY_GOAL_ROWS).then_some(peak <= MEMORY_GOAL_BYTES)
    }
}

/// Writes the record, then fits it and runs the fitted model on it (see the module docs).
///
/// # Errors
/// When the temporary files cannot be written, or a child fails (its stderr is in the error).
pub fn measure(rows: usize) -> Result<FitFigures> {
    let dir = tempfile::tempdir().context("bench: cannot make a temporary directory")?;
    let data = dir.path().join("random_walk.csv");
    write_record(&data, rows)?;
    let model = dir.path().join("model.toml");
    let data_arg = data.to_string_lossy().into_owned();
    let model_arg = model.to_string_lossy().into_owned();
    let (fit_s, peak_bytes) = timed(
        dir.path(),
        &[
            "fit", &data_arg, "--input", "u_V", "--output", "y_um", "-o", &model_arg,
        ],
    )?;
    let out = dir.path().join("out.csv").to_string_lossy().into_owned();
    let run = ["run", "--model", &model_arg, &data_arg, "-o", &out];
    let (first_s, first_peak) = timed(dir.path(), &run)?;
    let (second_s, second_peak) = timed(dir.path(), &run)?;
    Ok(FitFigures {
        rows,
        fit_s,
        run_s: first_s.min(second_s),
        peak_bytes,
        run_peak_bytes: first_peak.into_iter().chain(second_peak).reduce(f64::max),
    })
}

/// Runs this executable with `args` (stdout discarded, stderr into a file of `dir`: a pipe
/// nobody reads while the child runs could fill and stop it): its wall time, s, and its peak
/// resident memory, bytes, where `/proc` tells it.
fn timed(dir: &Path, args: &[&str]) -> Result<(f64, Option<f64>)> {
    let exe = std::env::current_exe().context("bench: cannot find the hyst executable")?;
    let stderr_path = dir.join("stderr.txt");
    let stderr_file = std::fs::File::create(&stderr_path)
        .with_context(|| format!("bench: cannot write {}", stderr_path.display()))?;
    let started = Instant::now();
    let mut child = Command::new(&exe)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(stderr_file)
        .spawn()
        .with_context(|| format!("bench: cannot start {}", exe.display()))?;
    let status_file = format!("/proc/{}/status", child.id());
    let mut peak = None;
    let status = loop {
        if let Some(status) = child.try_wait()? {
            break status;
        }
        // The high-water mark only grows: the last reading before the exit is the peak up to
        // the last few milliseconds.
        if let Some(kb) = std::fs::read_to_string(&status_file)
            .ok()
            .and_then(|s| high_water_kb(&s))
        {
            peak = Some(kb * 1024.0);
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let seconds = started.elapsed().as_secs_f64();
    if !status.success() {
        let stderr = std::fs::read_to_string(&stderr_path).unwrap_or_default();
        bail!(
            "bench: hyst {} failed ({status}): {}",
            args.join(" "),
            stderr.trim()
        );
    }
    Ok((seconds, peak))
}

/// `VmHWM` (kB) from the text of `/proc/PID/status`.
fn high_water_kb(status: &str) -> Option<f64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The record: `t_s,u_V,y_um`, 10 kHz, the input a random walk in [−10, 140] V (steps of up
/// to 2 V, the direction turned with probability 0.3 a sample, reflected at the ends), the output 1000 H(0.05,
/// 8)[ψ(u)] + 20 µm for ψ(u) = (u − 65) / 75, plus uniform noise of ±0.5 µm; the same numbers
/// every run (a fixed-seed generator).
fn write_record(path: &Path, rows: usize) -> Result<()> {
    let file = std::fs::File::create(path)
        .with_context(|| format!("bench: cannot write {}", path.display()))?;
    let mut out = BufWriter::new(file);
    let mut h = Hysteresis::new(0.05, 8.0)?;
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut uniform = move || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut u, mut direction) = (50.0_f64, 1.0_f64);
    let mut line = String::with_capacity(64);
    writeln!(out, "t_s,u_V,y_um")?;
    for i in 0..rows {
        if uniform() < 0.3 {
            direction = -direction;
        }
        u += direction * 2.0 * uniform();
        // Reflected at the ends of the range.
        if u > 140.0 {
            (u, direction) = (280.0 - u, -1.0);
        } else if u < -10.0 {
            (u, direction) = (-20.0 - u, 1.0);
        }
        let y = 1000.0 * h.step((u - 65.0) / 75.0) + 20.0 + (uniform() - 0.5);
        line.clear();
        write!(line, "{:.4},{u:.4},{y:.4}", i as f64 * 1e-4)?;
        writeln!(out, "{line}")?;
    }
    out.flush()
        .with_context(|| format!("bench: cannot write {}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn the_high_water_mark_is_read_from_proc_status() {
        let status = "Name:\thyst\nVmPeak:\t  2000 kB\nVmHWM:\t    1234 kB\nVmRSS:\t 1000 kB\n";
        assert_eq!(high_water_kb(status), Some(1234.0));
        assert_eq!(high_water_kb("Name:\thyst\n"), None);
    }

    #[test]
    fn the_record_is_a_random_walk_that_turns_often() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.csv");
        write_record(&path, 10_000).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let u: Vec<f64> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
            .collect();
        assert_eq!(u.len(), 10_000);
        let turns = u
            .windows(3)
            .filter(|w| (w[1] - w[0]) * (w[2] - w[1]) <= 0.0)
            .count();
        // A reversal about every three samples: the turning-point reduction keeps a third.
        assert!(turns > 2_000 && turns < 5_000, "{turns}");
        assert!(u.iter().all(|v| (-10.0..=140.0).contains(v)));
    }
}
