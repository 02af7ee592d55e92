//! A timed record's time stamps as measured, on every surface that runs a model with dynamics
//! or a rate term (`hyst run`, `hyst fit`, Python, C, the FMU):
//!
//! - **Steps.** Each step h_k = t_k − t_{k−1} (s) is the difference of the raw stamps, in
//!   64-bit floats: a large offset (Unix epoch seconds) cancels in it and is never accumulated.
//!   The plant is discretised for each step's own h ([`crate::dynamics::Dynamics::discretise`]),
//!   one discretisation per distinct step, kept for the next step of the same length.
//! - **Nominal step.** A record (or a part of one, below) has a nominal step: its mean step
//!   (t_last − t_first) / (n − 1). A step within [`STEP_TOLERANCE`] (relative) of it is taken
//!   as the nominal step: such differences are the rounding of the stamps (their decimal
//!   digits, 64-bit floats), and an evenly sampled record runs on one discretisation.
//! - **Gaps.** A step more than [`GAP_FACTOR`] times the record's median step (the median to
//!   0.4 %, [`Stamps`]) splits the record there: the part after the gap starts at rest as a
//!   record of its own, and the surface says so (a note of `hyst fit`, a line on `hyst run`'s
//!   stderr, a Python warning).
//! - **Refused:** a record with fewer than 2 stamps, a stamp that is not finite, repeats or goes
//!   back, and stamps too large to resolve the steps: their spacing in 64-bit floats (the ulp
//!   of the largest stamp) above [`RESOLUTION`] of the median step (Unix-epoch seconds,
//!   ulp 2.4e-7 s, at 1 MHz).

use std::collections::BTreeMap;
use std::ops::Range;
use std::sync::Arc;

/// The names a record's time column (s) goes by when none is named (`--time COLUMN`), in the
/// order they are looked for.
pub const TIME_COLUMNS: [&str; 4] = ["t", "t_s", "time", "time_s"];

/// The time column of a table that `has` the columns it is asked for: `named` if given (its
/// presence is the caller's to check), else the first of [`TIME_COLUMNS`] it has.
#[must_use]
pub fn time_column(named: Option<&str>, has: impl Fn(&str) -> bool) -> Option<&str> {
    named.or_else(|| TIME_COLUMNS.into_iter().find(|n| has(n)))
}

/// Whether `name` is the time column [`time_column`] would take: `named` if given, else one of
/// [`TIME_COLUMNS`].
#[must_use]
pub fn is_time_column(name: &str, named: Option<&str>) -> bool {
    named.map_or_else(|| TIME_COLUMNS.contains(&name), |named| name == named)
}

/// The largest relative difference of a step from the nominal step that is taken as the nominal
/// step: 1e-9. Decimal stamps of 10 significant digits and 64-bit rounding differ by less; the
/// discretisation for a step 1e-9 off differs by about 1e-9 of a step's change.
pub const STEP_TOLERANCE: f64 = 1e-9;

/// A step more than this many times the record's median step is a gap that splits the record:
/// 10.
pub const GAP_FACTOR: f64 = 10.0;

/// The largest spacing of the stamps in 64-bit floats (the ulp of the largest stamp), relative
/// to the record's median step, that still resolves the steps: 1 %.
pub const RESOLUTION: f64 = 0.01;

/// Whether the step `h` (s) is taken as the nominal step `nominal` (s): within
/// [`STEP_TOLERANCE`] of it.
#[must_use]
pub fn is_nominal(h: f64, nominal: f64) -> bool {
    (h - nominal).abs() <= STEP_TOLERANCE * nominal
}

/// The time steps of a record (or of a part of one): the nominal step, and each step that is not
/// taken as it. Cheap to clone (the irregular steps are shared), and as small as one number for
/// an evenly sampled record.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeSteps {
    /// The nominal step (s).
    nominal: f64,
    /// (k, h_k) for the steps not taken as the nominal one, k (the sample the step ends at,
    /// counted from the record's first) ascending.
    irregular: Arc<[(usize, f64)]>,
    /// The sample of the record these steps start at ([`TimeSteps::after`]).
    start: usize,
}

impl TimeSteps {
    /// Every step `period` (s): an evenly sampled record.
    #[must_use]
    pub fn even(period: f64) -> Self {
        Self {
            nominal: period,
            irregular: Arc::from(Vec::new()),
            start: 0,
        }
    }

    /// The steps of the stamps `t` (s, increasing) with the nominal step `nominal` (s).
    #[must_use]
    pub fn of(t: &[f64], nominal: f64) -> Self {
        let irregular: Vec<(usize, f64)> = t
            .windows(2)
            .enumerate()
            .filter_map(|(i, w)| match w {
                [a, b] if !is_nominal(b - a, nominal) => Some((i + 1, b - a)),
                _ => None,
            })
            .collect();
        Self {
            nominal,
            irregular: Arc::from(irregular),
            start: 0,
        }
    }

    /// The nominal step (s).
    #[must_use]
    pub fn nominal(&self) -> f64 {
        self.nominal
    }

    /// Whether every step is the nominal one.
    #[must_use]
    pub fn is_even(&self) -> bool {
        self.irregular.is_empty()
    }

    /// The steps from sample `offset` on (a segment of the record, a window of it).
    #[must_use]
    pub fn after(&self, offset: usize) -> Self {
        Self {
            start: self.start + offset,
            ..self.clone()
        }
    }

    /// The step (s) that ends at sample `k` ≥ 1 (k = 0 has none: the nominal step).
    #[must_use]
    pub fn step(&self, k: usize) -> f64 {
        let at = self.start + k;
        match self.irregular.binary_search_by_key(&at, |(i, _)| *i) {
            Ok(i) if k > 0 => self.irregular.get(i).map_or(self.nominal, |(_, h)| *h),
            _ => self.nominal,
        }
    }

    /// The steps ending at samples 1, 2, … in order (the nominal step past the last irregular
    /// one, for as many samples as asked).
    #[must_use]
    pub fn walk(&self) -> StepWalk<'_> {
        let first = self.start + 1;
        StepWalk {
            steps: self,
            next: self.irregular.partition_point(|(i, _)| *i < first),
            at: first,
        }
    }
}

/// The steps of a [`TimeSteps`] one after the other ([`TimeSteps::walk`]).
#[derive(Clone, Debug)]
pub struct StepWalk<'a> {
    steps: &'a TimeSteps,
    next: usize,
    at: usize,
}

impl Iterator for StepWalk<'_> {
    type Item = f64;

    fn next(&mut self) -> Option<f64> {
        let h = match self.steps.irregular.get(self.next) {
            Some((i, h)) if *i == self.at => {
                self.next += 1;
                *h
            }
            _ => self.steps.nominal,
        };
        self.at += 1;
        Some(h)
    }
}

/// A gap that splits a record ([`GAP_FACTOR`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gap<P> {
    /// Where the stamp after the gap is (an index, a line).
    pub at: P,
    /// That stamp (s).
    pub stamp: f64,
    /// The gap (s).
    pub step: f64,
    /// The record's median step (s).
    pub median: f64,
}

impl<P> Gap<P> {
    /// What happens, in words: "a gap of 2.5 s before time stamp 12.5 (250 × the record's
    /// median step 0.01 s): the record is split there, the part after it starting at rest".
    #[must_use]
    pub fn describe(&self) -> String {
        format!(
            "a gap of {} s before time stamp {} ({} × the record's median step {} s, more \
             than {GAP_FACTOR} ×): the record is split there, the part after it starting at rest",
            self.step,
            self.stamp,
            ratio_text(self.step / self.median),
            self.median
        )
    }
}

/// A gap's ratio to the median step in as few decimals as show it above [`GAP_FACTOR`]
/// (`250`, `10.002`), at most 6.
fn ratio_text(ratio: f64) -> String {
    let mut text = String::new();
    for decimals in 0..=6 {
        text = format!("{ratio:.decimals$}");
        if text.parse::<f64>().is_ok_and(|shown| shown > GAP_FACTOR) {
            break;
        }
    }
    text
}

/// What the stamps of a record say once all are seen ([`Stamps::check`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StampCheck {
    /// The mean step (t_last − t_first) / (n − 1) (s): the nominal step of a record without
    /// gaps.
    pub mean: f64,
    /// The median step (s), to 0.4 %.
    pub median: f64,
    /// The largest step (s).
    pub largest: f64,
}

impl StampCheck {
    /// Whether the step `h` (s) is a gap.
    #[must_use]
    pub fn is_gap(&self, h: f64) -> bool {
        h > GAP_FACTOR * self.median
    }

    /// Whether the record has a gap.
    #[must_use]
    pub fn has_gaps(&self) -> bool {
        self.is_gap(self.largest)
    }
}

/// The bits of a step kept by [`Stamps`]'s median: sign, exponent and 8 bits of the
/// significand (bins 0.4 % wide).
const BIN_SHIFT: u32 = 44;

/// The time stamps of a record seen one at a time (a file streamed, a column), for the checks of
/// the module in their order of precedence: the first non-finite stamp, else the first that does
/// not increase, else too few stamps, else a resolution too coarse for the steps. `P` is where a
/// stamp is (an index, a line), for the messages. Its memory is one count per 0.4 % bin of the
/// steps seen (a few for an evenly sampled record).
#[derive(Clone, Debug, Default)]
pub struct Stamps<P> {
    /// Stamps seen.
    count: usize,
    /// The first stamp and where it is.
    first: Option<(f64, P)>,
    /// The last stamp.
    last: f64,
    /// The largest step (s).
    largest: f64,
    /// The steps, counted by bin ([`BIN_SHIFT`]).
    bins: BTreeMap<u64, usize>,
    /// The first stamp that is not finite, and where.
    non_finite: Option<(f64, P)>,
    /// The first stamp not above the one before (that one, this one), and where.
    backward: Option<(f64, f64, P)>,
}

impl<P: Copy + Default> Stamps<P> {
    /// Takes the next stamp `t` (s), found `at`.
    pub fn push(&mut self, t: f64, at: P) {
        if self.non_finite.is_none() && !t.is_finite() {
            self.non_finite = Some((t, at));
        }
        if self.first.is_none() {
            self.first = Some((t, at));
            self.largest = f64::NEG_INFINITY;
        } else {
            let before = self.last;
            if self.backward.is_none() && t <= before {
                self.backward = Some((before, t, at));
            }
            let step = t - before;
            if self.non_finite.is_none() && self.backward.is_none() {
                self.largest = self.largest.max(step);
                *self.bins.entry(step.to_bits() >> BIN_SHIFT).or_insert(0) += 1;
            }
        }
        self.last = t;
        self.count += 1;
    }

    /// The record's mean, median and largest step.
    ///
    /// # Errors
    /// `(where, message)`: a non-finite stamp, one that repeats or goes back, fewer than 2
    /// stamps, or stamps whose spacing in 64-bit floats is above [`RESOLUTION`] of the median
    /// step (named at the first stamp).
    pub fn check(&self) -> Result<StampCheck, (P, String)> {
        if let Some((t, at)) = self.non_finite {
            return Err((at, format!("time stamp {t} is not finite")));
        }
        if let Some((before, t, at)) = self.backward {
            let what = if t == before {
                "repeats"
            } else {
                "goes back from"
            };
            return Err((
                at,
                format!("time stamp {t} {what} the one before ({before}): time must increase"),
            ));
        }
        let (first, at) = match self.first {
            Some(f) if self.count >= 2 => f,
            _ => {
                let at = self.first.map_or_else(P::default, |(_, at)| at);
                return Err((at, "a record needs at least 2 time stamps".into()));
            }
        };
        let steps = self.count - 1;
        let mut seen = 0;
        let mut median = f64::NAN;
        for (bin, n) in &self.bins {
            seen += n;
            if 2 * seen >= steps {
                median = f64::from_bits(bin << BIN_SHIFT);
                break;
            }
        }
        let largest_stamp = first.abs().max(self.last.abs());
        let spacing = ulp(largest_stamp);
        if spacing > RESOLUTION * median {
            return Err((
                at,
                format!(
                    "time stamps near {largest_stamp:e} s are {spacing:e} s apart in 64-bit \
                     floats, {:.2} % of the record's median step {median:e} s (at most {:.0} \
                     %): they cannot resolve the steps; write the time column relative to the \
                     record's start (t − t0)",
                    100.0 * spacing / median,
                    100.0 * RESOLUTION
                ),
            ));
        }
        Ok(StampCheck {
            mean: (self.last - first) / steps as f64,
            median,
            largest: self.largest,
        })
    }
}

/// One part of a record between gaps ([`Parts`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Part {
    /// Its first sample in the record.
    pub start: usize,
    /// Its samples.
    pub len: usize,
    /// Its nominal step (s): its mean step, or the record's median step for a part of one
    /// sample (which takes no step).
    pub nominal: f64,
}

impl Part {
    /// Its samples in the record.
    #[must_use]
    pub fn range(&self) -> Range<usize> {
        self.start..self.start + self.len
    }
}

/// A record's stamps walked again, once [`Stamps::check`] has passed, cut at its gaps: the
/// parts, and the gaps (for the notes).
#[derive(Clone, Debug)]
pub struct Parts<P> {
    check: StampCheck,
    /// Parts done.
    pub parts: Vec<Part>,
    /// Gaps found.
    pub gaps: Vec<Gap<P>>,
    /// The current part: its first sample and first stamp, its samples, its last stamp.
    start: usize,
    first: f64,
    len: usize,
    last: f64,
}

impl<P> Parts<P> {
    /// Starts the walk over a record that `check` describes.
    #[must_use]
    pub fn new(check: StampCheck) -> Self {
        Self {
            check,
            parts: Vec::new(),
            gaps: Vec::new(),
            start: 0,
            first: f64::NAN,
            len: 0,
            last: f64::NAN,
        }
    }

    /// Takes the next stamp `t`, found `at`.
    pub fn push(&mut self, t: f64, at: P) {
        if self.len > 0 && self.check.is_gap(t - self.last) {
            self.gaps.push(Gap {
                at,
                stamp: t,
                step: t - self.last,
                median: self.check.median,
            });
            self.close();
        }
        if self.len == 0 {
            self.first = t;
        }
        self.len += 1;
        self.last = t;
    }

    /// Ends the current part.
    fn close(&mut self) {
        let nominal = if self.len > 1 {
            (self.last - self.first) / (self.len - 1) as f64
        } else {
            self.check.median
        };
        self.parts.push(Part {
            start: self.start,
            len: self.len,
            nominal,
        });
        self.start += self.len;
        self.len = 0;
    }

    /// The parts and the gaps, once every stamp is pushed.
    #[must_use]
    pub fn finish(mut self) -> (Vec<Part>, Vec<Gap<P>>) {
        if self.len > 0 {
            self.close();
        }
        (self.parts, self.gaps)
    }
}

/// A record's stamps, checked and cut at its gaps: each part's samples and time steps, and the
/// gaps. What [`split`] and [`split_of`] return.
pub type Split<P> = (Vec<(Range<usize>, TimeSteps)>, Vec<Gap<P>>);

/// The parts of the record whose stamps are `t` (s) and their time steps, and its gaps.
///
/// # Errors
/// As [`Stamps::check`]: `(index, message)`.
pub fn split(t: &[f64]) -> Result<Split<usize>, (usize, String)> {
    split_of(|| t.iter().copied().enumerate())
}

/// [`split`] of the stamps `stamps()` walks (up to three times), each with where it is (`P`:
/// an index, a row), in order.
///
/// # Errors
/// As [`Stamps::check`].
pub fn split_of<P: Copy + Default, I: Iterator<Item = (P, f64)>>(
    stamps: impl Fn() -> I,
) -> Result<Split<P>, (P, String)> {
    let mut seen = Stamps::default();
    for (at, t) in stamps() {
        seen.push(t, at);
    }
    let check = seen.check()?;
    let (parts, gaps) = if check.has_gaps() {
        let mut parts = Parts::new(check);
        for (at, t) in stamps() {
            parts.push(t, at);
        }
        parts.finish()
    } else {
        let len = seen.count;
        let whole = Part {
            start: 0,
            len,
            nominal: check.mean,
        };
        (vec![whole], Vec::new())
    };
    // The irregular steps of each part, in one more walk.
    let mut irregular: Vec<Vec<(usize, f64)>> = vec![Vec::new(); parts.len()];
    let mut part = 0;
    let mut before = f64::NAN;
    for (k, (_, t)) in stamps().enumerate() {
        while parts.get(part).is_some_and(|p| k >= p.start + p.len) {
            part += 1;
        }
        if let (Some(p), Some(list)) = (parts.get(part), irregular.get_mut(part)) {
            if k > p.start && !is_nominal(t - before, p.nominal) {
                list.push((k - p.start, t - before));
            }
        }
        before = t;
    }
    let split = parts
        .iter()
        .zip(irregular)
        .map(|(p, list)| {
            let steps = TimeSteps {
                nominal: p.nominal,
                irregular: Arc::from(list),
                start: 0,
            };
            (p.range(), steps)
        })
        .collect();
    Ok((split, gaps))
}

/// The distance from |x| to the next larger 64-bit float (its ulp; NaN for a non-finite x).
fn ulp(x: f64) -> f64 {
    let x = x.abs();
    if x.is_finite() {
        f64::from_bits(x.to_bits() + 1) - x
    } else {
        f64::NAN
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;

    #[test]
    fn even_stamps_have_one_step() {
        let t: Vec<f64> = (0..1000).map(|k| 12.3 + f64::from(k) * 0.001).collect();
        let (parts, gaps) = split(&t).unwrap();
        assert!(gaps.is_empty());
        assert_eq!(parts.len(), 1);
        let (range, steps) = &parts[0];
        assert_eq!(*range, 0..1000);
        assert!(steps.is_even(), "{steps:?}");
        assert_eq!(steps.nominal(), (t[999] - t[0]) / 999.0);
    }

    #[test]
    fn uneven_steps_are_kept_as_measured() {
        // Steps of 10 to 63 ms, a mean near 15 ms.
        let mut t = vec![100.0];
        for k in 0..500 {
            let h = if k % 7 == 3 {
                0.063
            } else {
                0.010 + 0.001 * (k % 4) as f64
            };
            t.push(t[k] + h);
        }
        let (parts, gaps) = split(&t).unwrap();
        assert!(gaps.is_empty());
        let (_, steps) = &parts[0];
        let walked: Vec<f64> = steps.walk().take(500).collect();
        for k in 1..=500 {
            let raw = t[k] - t[k - 1];
            let h = steps.step(k);
            assert_eq!(walked[k - 1].to_bits(), h.to_bits());
            if is_nominal(raw, steps.nominal()) {
                assert_eq!(h, steps.nominal());
            } else {
                assert_eq!(h.to_bits(), raw.to_bits(), "{k}");
            }
        }
        assert_eq!(steps.after(10).step(5).to_bits(), steps.step(15).to_bits());
    }

    #[test]
    fn a_gap_splits_the_record() {
        let mut t: Vec<f64> = (0..100).map(|k| f64::from(k) * 0.01).collect();
        t.extend((0..50).map(|k| 5.0 + f64::from(k) * 0.01));
        let (parts, gaps) = split(&t).unwrap();
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0].0, 0..100);
        assert_eq!(parts[1].0, 100..150);
        assert_eq!(gaps.len(), 1);
        assert_eq!(gaps[0].at, 100);
        assert!((gaps[0].step - 4.01).abs() < 1e-12);
        assert!(
            gaps[0].describe().contains("split"),
            "{}",
            gaps[0].describe()
        );
        assert!(parts.iter().all(|(_, s)| s.is_even()));
        assert!((parts[1].1.nominal() - 0.01).abs() < 1e-12);
        // 9 × the median is not a gap.
        let t = [0.0, 1.0, 2.0, 11.0, 12.0, 13.0];
        assert_eq!(split(&t).unwrap().0.len(), 1);
    }

    /// A gap just above the factor is not called the factor itself.
    #[test]
    fn a_gap_just_above_the_factor_says_by_how_much() {
        let gap = Gap {
            at: 3,
            stamp: 12.0015,
            step: 10.0015,
            median: 1.0,
        };
        let text = gap.describe();
        assert!(
            text.contains("(10.002 × the record's median step 1 s, more than 10 ×)"),
            "{text}"
        );
        let gap = Gap { step: 250.0, ..gap };
        assert!(gap.describe().contains("(250 × "), "{}", gap.describe());
    }

    #[test]
    fn epoch_offsets_cancel_in_the_steps() {
        let t0 = 1.7e9;
        // Epoch seconds at 1 kHz: ulp(1.7e9) = 2.4e-7 s, 0.024 % of a step.
        let t: Vec<f64> = (0..2000).map(|k| t0 + f64::from(k) * 1e-3).collect();
        let (parts, _) = split(&t).unwrap();
        let (_, steps) = &parts[0];
        assert!((steps.nominal() - 1e-3).abs() < 2e-10);
        for k in 1..2000 {
            assert!((steps.step(k) - 1e-3).abs() <= 2.5e-7, "{k}");
        }
        // At 1 MHz the stamps cannot resolve the steps: refused, saying why.
        let t: Vec<f64> = (0..2000).map(|k| t0 + f64::from(k) * 1e-6).collect();
        let (at, message) = split(&t).unwrap_err();
        assert_eq!(at, 0);
        assert!(
            message.contains("2.384185791015625e-7 s apart"),
            "{message}"
        );
        assert!(message.contains("t − t0"), "{message}");
        // Relative to the start, they do.
        let t: Vec<f64> = (0..2000).map(|k| f64::from(k) * 1e-6).collect();
        assert!(split(&t).is_ok());
    }

    #[test]
    fn bad_stamps_are_named() {
        let (i, m) = split(&[0.0, 0.1, 0.1, 0.3]).unwrap_err();
        assert_eq!(i, 2);
        assert!(m.contains("repeats"), "{m}");
        let (i, m) = split(&[0.0, 0.1, 0.05]).unwrap_err();
        assert_eq!(i, 2);
        assert!(m.contains("goes back"), "{m}");
        let (i, m) = split(&[0.0, f64::NAN, 0.05]).unwrap_err();
        assert_eq!(i, 1);
        assert!(m.contains("not finite"), "{m}");
        assert!(split(&[1.0]).is_err());
    }
}
