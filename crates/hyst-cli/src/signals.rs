//! SIGINT, SIGTERM and SIGHUP: every command stops at once, removes the temporary files it is
//! writing and exits with 128 + the signal number (130 for Ctrl-C, 143 for SIGTERM, 129 for
//! SIGHUP), as a shell reports a process killed by that signal.
//!
//! The signals are received by a thread of their own (signal-hook's iterator, which does only
//! async-signal-safe work in the handler itself), so the reaction does not wait for the command
//! to reach a check point: reading a large CSV file, running the operator over 10 M rows or
//! writing the output are interrupted equally fast. Outputs written atomically never exist half
//! written: the temporary file is removed ([`hyst_io::remove_temporary_files`]) and the
//! destination is left as it was.
//!
//! SIGXFSZ (a write beyond `ulimit -f`) would kill the process with no message and leave the
//! temporary file behind: a handler that does nothing makes the write fail with EFBIG instead,
//! which the command reports, naming the file, before removing the temporary file.

use std::process::exit;

use anyhow::{Context, Result};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGXFSZ};
use signal_hook::iterator::Signals;

/// The exit status for a command stopped by SIGINT (Ctrl-C): 128 + 2.
pub const EXIT_INTERRUPTED: u8 = 130;

/// Installs the handlers; call first thing in `main`.
///
/// # Errors
/// The handlers cannot be installed (the OS refuses).
pub fn install() -> Result<()> {
    signal_hook::flag::register(SIGXFSZ, Arc::new(AtomicBool::new(false)))
        .context("cannot install the SIGXFSZ handler")?;
    let mut signals =
        Signals::new([SIGINT, SIGTERM, SIGHUP]).context("cannot install the signal handlers")?;
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                // Held until the process ends: no temporary file is renamed into place after
                // this point.
                let _held = hyst_io::remove_temporary_files();
                exit(128 + signal);
            }
        })
        .context("cannot start the signal thread")?;
    Ok(())
}
