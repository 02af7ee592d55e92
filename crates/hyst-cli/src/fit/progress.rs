//! Progress of `hyst fit` on stderr: the fit's observer. (Ctrl-C ends the process at once from
//! the signal thread, `crate::signals`, before any model file exists.)

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use hyst_fit::lm::{Observer, Progress};

/// Progress on stderr (indicatif), shown once a fit has run for a second.
pub(super) struct ProgressObserver {
    pub(super) started: Instant,
    pub(super) bar: Option<indicatif::ProgressBar>,
    pub(super) starts: usize,
}

impl Observer for ProgressObserver {
    fn observe(&mut self, p: &Progress) -> ControlFlow<()> {
        if self.bar.is_none() && self.started.elapsed() > Duration::from_secs(1) {
            let bar = indicatif::ProgressBar::new_spinner();
            bar.enable_steady_tick(Duration::from_millis(120));
            self.bar = Some(bar);
        }
        if let Some(bar) = &self.bar {
            if p.start == usize::MAX {
                bar.set_message(format!("family widths: step {}", p.iteration));
            } else {
                bar.set_message(format!(
                    "least squares: start {}/{}, iteration {}, cost {:.4e}",
                    p.start + 1,
                    self.starts,
                    p.iteration,
                    p.cost
                ));
            }
        }
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
