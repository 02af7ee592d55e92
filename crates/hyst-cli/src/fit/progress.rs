//! Progress of `hyst fit` on a terminal: the fit's observer shows one bar, its stage (search,
//! polish, family widths), the fraction of that stage done and the time it has left
//! ([`crate::progress`]; reading the data is shown before it). (Ctrl-C ends the process at once
//! from the signal thread, `crate::signals`, before any model file exists.)

use std::ops::ControlFlow;
use std::time::Instant;

use hyst_fit::lm::{Observer, Progress, Stage};
use indicatif::ProgressBar;

use crate::progress::{bar, delay, on_terminal, time_left};

/// The bar's resolution: positions per stage.
const STEPS: u64 = 1000;

/// Progress on stderr, shown once a fit has run for [`delay`] (never with `--json` or when
/// stderr is not a terminal).
pub(super) struct ProgressObserver {
    /// When the fit started.
    started: Instant,
    /// When to show it.
    after: std::time::Duration,
    /// Whether to show anything.
    enabled: bool,
    /// The bar, once shown.
    bar: Option<ProgressBar>,
    /// The stage shown, and when it started.
    stage: Option<(Stage, Instant)>,
}

impl ProgressObserver {
    /// An observer for a fit starting now; `quiet` (`--json`) shows nothing.
    pub(super) fn new(quiet: bool) -> Self {
        Self {
            started: Instant::now(),
            after: delay(),
            enabled: !quiet && on_terminal(),
            bar: None,
            stage: None,
        }
    }
}

/// A stage in words.
fn name(stage: Stage) -> &'static str {
    match stage {
        Stage::Search => "fit: search",
        Stage::Polish => "fit: polish",
        Stage::Widths => "fit: family widths",
    }
}

impl Observer for ProgressObserver {
    fn observe(&mut self, p: &Progress) -> ControlFlow<()> {
        if !self.enabled {
            return ControlFlow::Continue(());
        }
        if self.bar.is_none() && self.started.elapsed() >= self.after {
            self.bar = Some(bar(STEPS, "{prefix:>18} [{bar:30}] {percent:>3}% {msg}"));
        }
        let Some(bar) = &self.bar else {
            return ControlFlow::Continue(());
        };
        let now = Instant::now();
        let since = match self.stage {
            Some((stage, since)) if stage == p.stage => since,
            _ => {
                // A new stage (or the same again, for a nested or second fit): the bar restarts.
                self.stage = Some((p.stage, now));
                bar.set_prefix(name(p.stage));
                bar.set_position(0);
                now
            }
        };
        let fraction = p.fraction();
        bar.set_position((fraction * STEPS as f64) as u64);
        let left = time_left(now.duration_since(since), fraction);
        let detail = match p.stage {
            Stage::Widths => format!("step {}", p.iteration),
            Stage::Search | Stage::Polish if p.starts > 1 => format!(
                "start {}/{} ({} ended), iteration {}, cost {:.4e}",
                p.start.saturating_add(1).min(p.starts),
                p.starts,
                p.finished,
                p.iteration,
                p.cost
            ),
            Stage::Search | Stage::Polish => {
                format!("iteration {}, cost {:.4e}", p.iteration, p.cost)
            }
        };
        bar.set_message(if left.is_empty() {
            detail
        } else {
            format!("{detail}; {left}")
        });
        ControlFlow::Continue(())
    }
}

impl Drop for ProgressObserver {
    fn drop(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}
