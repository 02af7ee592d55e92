//! Running a binary of the workspace, as its integration tests do: `hyst ARGS` to its end, its
//! exit status, stdout and stderr.

use std::path::Path;
use std::process::{Child, Command, Output};
use std::time::{Duration, Instant};

/// A binary of the workspace, by its path: `Binary::new(env!("CARGO_BIN_EXE_hyst"))` in an
/// integration test of hyst-cli (cargo builds the binary first and names its path to the tests
/// of its package only).
#[derive(Clone, Copy, Debug)]
pub struct Binary(&'static str);

impl Binary {
    /// The binary at `path`.
    pub const fn new(path: &'static str) -> Self {
        Self(path)
    }

    /// A command of the binary, to add arguments, a directory, pipes or an environment to.
    pub fn command(&self) -> Command {
        Command::new(self.0)
    }

    /// The binary run with `args` to its end (panics if it cannot be started).
    pub fn output(&self, args: &[&str]) -> Output {
        run(self.command().args(args))
    }

    /// As [`output`](Binary::output), in the directory `dir`.
    pub fn output_in(&self, args: &[&str], dir: &Path) -> Output {
        run(self.command().args(args).current_dir(dir))
    }

    /// A run with `args` that must succeed (panics with its stderr otherwise).
    pub fn success(&self, args: &[&str]) -> Output {
        let out = self.output(args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        out
    }

    /// The stdout of a run with `args` that must succeed (panics with its stderr otherwise).
    pub fn stdout(&self, args: &[&str]) -> String {
        String::from_utf8(self.success(args).stdout).expect("stdout is UTF-8")
    }

    /// The stderr of a run with `args` that must fail (panics if it succeeds).
    pub fn failure(&self, args: &[&str]) -> String {
        let out = self.output(args);
        assert!(
            !out.status.success(),
            "{args:?} succeeded: {}",
            stdout(&out)
        );
        stderr(&out)
    }
}

/// `command` run to its end (panics if it cannot be started).
pub fn run(command: &mut Command) -> Output {
    command
        .output()
        .unwrap_or_else(|e| panic!("cannot run {command:?}: {e}"))
}

/// A run's stderr as text (invalid UTF-8 replaced).
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A run's stdout as text (invalid UTF-8 replaced).
pub fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The output of `child` once it ends; if it is still running after `limit`, kills it and
/// panics naming `what`. The limit is there to fail a hung process instead of hanging the test
/// run, not to measure speed: give it generously.
pub fn wait_at_most(mut child: Child, limit: Duration, what: &str) -> Output {
    let start = Instant::now();
    while child
        .try_wait()
        .expect("the child can be waited for")
        .is_none()
    {
        if start.elapsed() > limit {
            child.kill().ok();
            panic!("{what}: still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("the child's output")
}
