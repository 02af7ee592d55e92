//! Progress on a terminal (stderr), for long work: `hyst fit` (reading, then the fit's stages)
//! and `hyst run` on large files. Nothing is shown when stderr is not a terminal (a pipe, a
//! file, CI) or with `--json`, and nothing for work that ends within [`delay`] (one second, or
//! the milliseconds of the environment variable `HYST_PROGRESS_DELAY_MS`).

use std::io::IsTerminal;
use std::path::Path;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressFinish, ProgressStyle};

/// The environment variable that sets [`delay`] in milliseconds (0: at once).
pub const DELAY_ENV: &str = "HYST_PROGRESS_DELAY_MS";

/// How long work runs before its progress appears (no flicker for quick commands): one second,
/// or [`DELAY_ENV`]'s milliseconds.
pub fn delay() -> Duration {
    std::env::var(DELAY_ENV)
        .ok()
        .and_then(|ms| ms.trim().parse::<u64>().ok())
        .map_or(Duration::from_secs(1), Duration::from_millis)
}

/// `hyst run` shows the bytes it has read for input files of at least this size (bytes).
pub const LARGE_FILE: u64 = 50_000_000;

/// Whether progress may be shown: stderr is a terminal.
pub fn on_terminal() -> bool {
    std::io::stderr().is_terminal()
}

/// Whether a command writing its output to `output` must show no progress: `-o -` to the
/// terminal stderr would draw on too (the bar would interleave with the rows).
pub fn writes_to_terminal(output: &Path) -> bool {
    output.as_os_str() == hyst_io::STDOUT && std::io::stdout().is_terminal()
}

/// A bar of `len` units with `template`, cleared when dropped or finished.
pub fn bar(len: u64, template: &str) -> ProgressBar {
    let style = ProgressStyle::with_template(template)
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ");
    ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr())
        .with_style(style)
        .with_finish(ProgressFinish::AndClear)
}

/// The bytes of `path` read so far, for [`hyst_io::CountingReader`]: a callback that shows
/// "reading PATH" with the bytes read, the file's size and the time left, once reading has
/// taken [`delay`] and if the file has at least `min_size` bytes; a callback that does nothing
/// when nothing would be shown (not a terminal, `quiet`, a small file or one of unknown size).
pub fn reading(path: &Path, min_size: u64, quiet: bool) -> Box<dyn FnMut(u64)> {
    let size = std::fs::metadata(path)
        .ok()
        .filter(std::fs::Metadata::is_file)
        .map(|m| m.len())
        .filter(|&len| len >= min_size.max(1));
    let (Some(size), false) = (size, quiet || !on_terminal()) else {
        return Box::new(|_| {});
    };
    let what = format!("reading {}", path.display());
    let started = Instant::now();
    let after = delay();
    let mut shown: Option<ProgressBar> = None;
    Box::new(move |read: u64| {
        if shown.is_none() && started.elapsed() >= after {
            let b = bar(size, "{prefix} [{bar:30}] {bytes}/{total_bytes} {msg}");
            b.set_prefix(what.clone());
            shown = Some(b);
        }
        if let Some(b) = &shown {
            b.set_position(read.min(size));
            b.set_message(time_left(started.elapsed(), read as f64 / size as f64));
        }
    })
}

/// The time left for work that is `fraction` done after `elapsed`, in words ("about 12 s
/// left"); empty before 2 % (no estimate yet).
pub fn time_left(elapsed: Duration, fraction: f64) -> String {
    if !(0.02..1.0).contains(&fraction) {
        return String::new();
    }
    let left = elapsed.as_secs_f64() * (1.0 - fraction) / fraction;
    if left < 60.0 {
        format!("about {left:.0} s left")
    } else if left < 3600.0 {
        format!("about {:.0} min left", left / 60.0)
    } else {
        format!("about {:.1} h left", left / 3600.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_left_in_words() {
        assert_eq!(time_left(Duration::from_secs(10), 0.5), "about 10 s left");
        assert_eq!(time_left(Duration::from_secs(60), 0.25), "about 3 min left");
        assert_eq!(
            time_left(Duration::from_secs(3600), 0.5),
            "about 1.0 h left"
        );
        assert_eq!(time_left(Duration::from_secs(10), 0.01), "");
        assert_eq!(time_left(Duration::from_secs(10), 1.0), "");
    }
}
