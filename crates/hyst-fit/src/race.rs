//! The starts of a multi-start fit run on the machine's threads, with the result of running
//! them one after the other.
//!
//! A start is abandoned when it lags: after [`RACE_AFTER`] iterations, a cost above
//! [`RACE_RATIO`] times the best final cost of the starts *before it* is a different, worse
//! basin, and the rest of its iterations would only polish a point that will be discarded. That
//! rule depends on the order of the starts, so the threads keep it exactly: each start records
//! the highest cost it reports from iteration [`RACE_AFTER`] on, and is cut short only once
//! every start before it has finished (its bar is then known, the same as in a sequential run);
//! a start that finishes before that is judged afterwards by the same rule. A run of the method
//! depends only on its starting point, so the kept solutions, and the best of them (the first
//! of equal costs), are those of a sequential run for any number of threads.
//!
//! Progress goes to the caller's observer from the calling thread only (the other threads send
//! theirs over a channel, forwarded whenever the calling thread reports or waits), so an
//! observer that asks for Ctrl-C (Python's signal check) runs where it must; its `Break` stops
//! every thread.

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Mutex, PoisonError};

use crate::error::FitError;
use crate::lm::{LevenbergMarquardt, Observer, Problem, Progress, Solution};

/// Iterations a start runs before it can be abandoned.
pub(crate) const RACE_AFTER: usize = 10;
/// A start whose cost is above this multiple of the best so far after [`RACE_AFTER`]
/// iterations is abandoned.
pub(crate) const RACE_RATIO: f64 = 1.25;

/// What one start came to.
struct Run {
    /// The solution; `None` when the start was cut short (abandoned while it ran).
    solution: Option<Solution>,
    /// The highest cost it reported at an iteration ≥ [`RACE_AFTER`] (−∞ when none).
    race_cost: f64,
}

impl Run {
    /// Whether the race abandons this start against the bar `best` (the best final cost of the
    /// starts before it; ∞ when there is none).
    fn abandoned(&self, best: f64) -> bool {
        self.solution.is_none() || self.race_cost > RACE_RATIO * best
    }
}

/// The sequential race over finished runs: the index of the best kept solution (the first of
/// equal costs) and the best cost of those kept, ∞ when none is. `None` when a run is missing
/// (still running).
fn replay(runs: &[Option<Run>]) -> Option<(Option<usize>, f64)> {
    let mut best: Option<(usize, f64)> = None;
    for (k, run) in runs.iter().enumerate() {
        let run = run.as_ref()?;
        if run.abandoned(best.map_or(f64::INFINITY, |b| b.1)) {
            continue;
        }
        let Some(s) = &run.solution else { continue };
        if best.is_none_or(|b| s.cost < b.1) {
            best = Some((k, s.cost));
        }
    }
    Some((best.map(|b| b.0), best.map_or(f64::INFINITY, |b| b.1)))
}

/// The state the threads share.
struct Shared {
    /// The next start to take.
    next: usize,
    /// The finished runs, by start.
    runs: Vec<Option<Run>>,
    /// The first error (by start), which ends the fit.
    error: Option<(usize, FitError)>,
}

/// Where a thread's progress goes: the caller's observer (calling thread), or the channel to it.
trait Report {
    /// Passes `progress` on; `Break` stops the fit (and sets `stop`).
    fn send(&mut self, progress: &Progress, stop: &AtomicBool) -> ControlFlow<()>;
}

/// The calling thread's report: forwards the others' progress first, then its own.
struct ToObserver<'a>(&'a mut dyn Observer, &'a Receiver<Progress>);

impl Report for ToObserver<'_> {
    fn send(&mut self, progress: &Progress, stop: &AtomicBool) -> ControlFlow<()> {
        for p in self.1.try_iter() {
            if self.0.observe(&p).is_break() {
                stop.store(true, Ordering::Relaxed);
                return ControlFlow::Break(());
            }
        }
        let flow = self.0.observe(progress);
        if flow.is_break() {
            stop.store(true, Ordering::Relaxed);
        }
        flow
    }
}

/// Another thread's report: to the calling thread.
struct ToChannel(Sender<Progress>);

impl Report for ToChannel {
    fn send(&mut self, progress: &Progress, _stop: &AtomicBool) -> ControlFlow<()> {
        // The calling thread stops listening only after every other thread has ended.
        let _ = self.0.send(*progress);
        ControlFlow::Continue(())
    }
}

/// The observer of one start: tags its progress, reports it, and cuts the start short once the
/// race abandons it.
struct Racer<'b> {
    start: usize,
    report: &'b mut dyn Report,
    shared: &'b Mutex<Shared>,
    stop: &'b AtomicBool,
    race_cost: f64,
    abandoned: bool,
}

impl Observer for Racer<'_> {
    fn observe(&mut self, progress: &Progress) -> ControlFlow<()> {
        if self.stop.load(Ordering::Relaxed) {
            return ControlFlow::Break(());
        }
        let (starts, finished) = {
            let shared = self.shared.lock().unwrap_or_else(PoisonError::into_inner);
            (
                shared.runs.len(),
                shared.runs.iter().filter(|r| r.is_some()).count(),
            )
        };
        self.report.send(
            &Progress {
                start: self.start,
                starts,
                finished,
                ..*progress
            },
            self.stop,
        )?;
        if progress.iteration >= RACE_AFTER {
            self.race_cost = self.race_cost.max(progress.cost);
            let shared = self.shared.lock().unwrap_or_else(PoisonError::into_inner);
            let before = shared.runs.get(..self.start).and_then(replay);
            if before.is_some_and(|(_, best)| self.race_cost > RACE_RATIO * best) {
                self.abandoned = true;
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    }
}

/// Takes starts until none is left (or the fit stops), running each from its point in
/// `starts`.
fn work<P: Problem + Sync + ?Sized>(
    method: &LevenbergMarquardt,
    problem: &P,
    starts: &[Vec<f64>],
    shared: &Mutex<Shared>,
    stop: &AtomicBool,
    report: &mut dyn Report,
) {
    loop {
        if stop.load(Ordering::Relaxed) {
            return;
        }
        let start = {
            let mut s = shared.lock().unwrap_or_else(PoisonError::into_inner);
            if s.next >= starts.len() {
                return;
            }
            s.next += 1;
            s.next - 1
        };
        let mut racer = Racer {
            start,
            report: &mut *report,
            shared,
            stop,
            race_cost: f64::NEG_INFINITY,
            abandoned: false,
        };
        let theta0 = starts.get(start).map_or(&[][..], Vec::as_slice);
        let result = method.minimize(problem, theta0, &mut racer);
        let (race_cost, abandoned) = (racer.race_cost, racer.abandoned);
        let mut s = shared.lock().unwrap_or_else(PoisonError::into_inner);
        let run = match result {
            Ok(solution) => Run {
                solution: Some(solution),
                race_cost,
            },
            Err(FitError::Interrupted) if abandoned => Run {
                solution: None,
                race_cost,
            },
            Err(e) => {
                stop.store(true, Ordering::Relaxed);
                if s.error.as_ref().is_none_or(|(k, _)| start < *k) {
                    s.error = Some((start, e));
                }
                return;
            }
        };
        if let Some(slot) = s.runs.get_mut(start) {
            *slot = Some(run);
        }
    }
}

/// Runs the method from every point of `starts` (in that order of precedence) on up to
/// `threads` threads and returns the best kept solution: what running them one after the other,
/// each raced against the best before it, returns. `None` when every start was abandoned (never
/// the first) or there are none.
///
/// # Errors
/// The method's error of the earliest start that failed ([`FitError::Interrupted`] when the
/// observer stopped the fit).
pub(crate) fn best_of<P: Problem + Sync + ?Sized>(
    method: &LevenbergMarquardt,
    problem: &P,
    starts: &[Vec<f64>],
    threads: usize,
    observer: &mut dyn Observer,
) -> Result<Option<Solution>, FitError> {
    let shared = Mutex::new(Shared {
        next: 0,
        runs: starts.iter().map(|_| None).collect(),
        error: None,
    });
    let stop = AtomicBool::new(false);
    let threads = threads.clamp(1, starts.len().max(1));
    let (sender, receiver) = mpsc::channel::<Progress>();
    std::thread::scope(|scope| {
        for _ in 1..threads {
            let mut report = ToChannel(sender.clone());
            let (shared, stop) = (&shared, &stop);
            scope.spawn(move || work(method, problem, starts, shared, stop, &mut report));
        }
        drop(sender);
        let mut report = ToObserver(&mut *observer, &receiver);
        work(method, problem, starts, &shared, &stop, &mut report);
        // The others' progress until they end (the channel closes with the last of them).
        for p in receiver.iter() {
            if !stop.load(Ordering::Relaxed) && observer.observe(&p).is_break() {
                stop.store(true, Ordering::Relaxed);
            }
        }
    });
    let mut shared = shared.into_inner().unwrap_or_else(PoisonError::into_inner);
    if let Some((_, e)) = shared.error.take() {
        return Err(e);
    }
    if stop.load(Ordering::Relaxed) {
        return Err(FitError::Interrupted);
    }
    let Some((Some(best), _)) = replay(&shared.runs) else {
        return Ok(None);
    };
    Ok(shared
        .runs
        .get_mut(best)
        .and_then(Option::take)
        .and_then(|r| r.solution))
}

/// The threads the machine offers (1 when it does not say).
pub(crate) fn threads() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
}
