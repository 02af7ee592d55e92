//! A record's start, discounted until its input has swept its range ([`settle`]).
//!
//! A measured record starts wherever the actuator was: the operator's memory (Definition 2.1:
//! the last reversal point and the direction) and the plant's state at its first sample are not
//! known. A fit that assumes them (`--initial-state`, the plant at rest) is biased by the
//! samples they shape: a first-order plant with τ = 0.1 s whose record starts mid-band came out
//! 6 % long, 72 of its own standard errors away. Once the input has gone from one end of the
//! record's range to the other, the memory of the operator is that of the sweep (whatever it
//! was before, it is forgotten by the travel across the loop, as the branch converges to the
//! asymptote), and a plant whose time constants are short against the sweep has forgotten its
//! start too. The samples before that point get weight 0: they still run the model (its state
//! carries on from them), but do not count in the fit's cost or its error statistics.
//!
//! A record that never sweeps its range within its first half (first-order reversal curves,
//! a single rise, a slow record among fast ones) has no such point. When other records do, the
//! first fit leaves it out, and the fitted operator's forgetting ([`resettle`]) sets its
//! discount; when none does, every record keeps every sample, and its start is the start
//! rule's (or, with `--estimate-initial-states`, estimated).
//!
//! A static fit trusts the start rule unless its records' starts fit worse than the rest
//! ([`start_mismatch`]); then it is settled the same way ([`settle_fit`]).

use hyst_core::{K2Law, Shaping};
use hyst_io::number::sig;
use hyst_model::SmoothModel;

use crate::data::{abbreviate, range, Dataset};
use crate::smooth::SmoothFit;

/// How close to an end of its range the input must come to count as reaching it (fraction of
/// the record's input span): noise and a sine sampled off its peak reach 98 %. (At 10 %, a
/// single slow record gave up half of itself to the first stage, too little to place the
/// loop.)
pub const SWEEP_REACH: f64 = 0.02;

/// The latest a sweep may end (fraction of the record's samples) for the start to be
/// discounted: a record that needs more than half of itself to sweep its range keeps every
/// sample (see the module docs).
pub const MAX_SETTLING_SHARE: f64 = 0.5;

/// The samples at the start of a history of inputs `input` before its input has swept its
/// range (reached one end, then the other, within [`SWEEP_REACH`] of the span); `None` when it
/// never does within [`MAX_SETTLING_SHARE`] of its samples.
#[must_use]
pub fn settling_samples(input: &[f64]) -> Option<usize> {
    let (lo, hi) = range(input.iter());
    let reach = SWEEP_REACH * (hi - lo);
    if reach.is_nan() || reach <= 0.0 {
        return None;
    }
    let low = input.iter().position(|&x| x <= lo + reach)?;
    let high = input.iter().position(|&x| x >= hi - reach)?;
    // The sweep ends where the later end is first reached after the earlier one.
    let end = low.max(high);
    (end as f64 <= MAX_SETTLING_SHARE * input.len() as f64).then_some(end)
}

/// `data` with each history's start discounted (weight 0) until its input has swept its range
/// ([`settling_samples`]), and the report's note on it (`None` when nothing was discounted).
/// A history that never sweeps its range is left out whole when another one does (the first
/// fit then comes from the records whose start is known to be forgotten).
#[must_use]
pub fn settle(data: &Dataset) -> (Dataset, Option<String>) {
    let mut settled = data.clone();
    let histories = data.histories();
    let ends: Vec<Option<usize>> = histories
        .iter()
        .map(|h| settling_samples(&h.input.iter().copied().collect::<Vec<f64>>()))
        .collect();
    let any = ends.iter().any(Option::is_some);
    let (mut discounted, mut swept, mut kept) = (0usize, 0usize, Vec::new());
    for (h, end) in histories.iter().zip(&ends) {
        let Some(first) = h.parts.first().map(|p| p.0) else {
            continue;
        };
        let end = match end {
            Some(end) => {
                swept += 1;
                *end
            }
            None => {
                if let Some(r) = data.records.get(first) {
                    kept.push(r.id);
                }
                if !any {
                    continue;
                }
                h.input.len()
            }
        };
        discounted += end;
        discount(&mut settled, &h.parts, end);
    }
    if swept == 0 && kept.is_empty() {
        return (settled, None);
    }
    let mut note = String::new();
    if swept > 0 {
        note.push_str(&format!(
            "the start of each record is not known (the operator's memory, the plant's state): \
             {discounted} samples at the starts of {swept} record(s), before each input had \
             swept its range, set the state but do not count in the fit ({} % of the samples; \
             --fit-from-start counts them, trusting the start rule)",
            sig(
                100.0 * discounted as f64 / data.training_samples().max(1) as f64,
                2
            )
        ));
    }
    if !kept.is_empty() {
        if !note.is_empty() {
            note.push_str("; ");
        }
        note.push_str(&format!(
            "record(s) {} never sweep their range in their first half: {}",
            ids(&kept),
            if any {
                "the first fit leaves them out"
            } else {
                "they start by the start rule (--estimate-initial-states estimates their starts \
                 instead)"
            }
        ));
    }
    (settled, Some(note))
}

/// The most fits [`settle_fit`] makes again on a longer discount.
pub const SETTLING_ROUNDS: usize = 3;

/// A timed fit settled: `fit`, made on `settled` (`data` after [`settle`]), made again by
/// `refit` while the discount its model needs ([`resettle`]) is longer than the one it was
/// made on (by 2 % of a record), or the first stage left a record out whole; up to
/// [`SETTLING_ROUNDS`] times, the discount never shorter than the round before. A fit still
/// biased by its start forgets too early, so the discount grows until the fitted model
/// agrees with it. `settled` ends as the discount of the last model; the note on it.
///
/// # Errors
/// What `refit` returns.
pub fn settle_fit<E>(
    data: &Dataset,
    settled: &mut Dataset,
    fit: &mut SmoothFit,
    mut refit: impl FnMut(&Dataset) -> Result<SmoothFit, E>,
) -> Result<Option<String>, E> {
    let mut floor: Vec<usize> = Vec::new();
    let mut note = None;
    for round in 0..SETTLING_ROUNDS {
        let (again, n) = resettle(data, &fit.model, &floor);
        let before = discounted(settled);
        let left_out = round == 0
            && before
                .iter()
                .zip(&settled.records)
                .any(|(n, r)| *n == r.len() && !r.is_empty());
        let longer = left_out
            || discounted(&again)
                .iter()
                .zip(&again.records)
                .zip(before.iter().chain(std::iter::repeat(&0)))
                .any(|((now, r), was)| *now > *was + r.len() / 50);
        floor = discounted_histories(&again);
        note = n;
        *settled = again;
        if !longer {
            break;
        }
        *fit = refit(settled)?;
    }
    Ok(note)
}

/// How much worse (RMS) the records' starts must fit than the rest for a static fit to
/// discount them: a start the start rule does not describe.
pub const START_MISMATCH: f64 = 2.0;

/// The most training samples [`start_mismatch`] checks: its runs hold a record's outputs, and
/// in a longer fit the starts' share is too small to bias it (the long-record fit stays flat
/// in memory).
pub const START_CHECK_SAMPLES: usize = 1 << 20;

/// A static fit's check of the start rule: the records' starts, until the fitted `model`
/// forgets them ([`resettle`]), against the rest. When the starts' RMS error is above
/// [`START_MISMATCH`] times the rest's (the records do not start as the rule says), the
/// report's words on it, to go before [`settle_fit`]'s note; `None` otherwise.
#[must_use]
pub fn start_mismatch(data: &Dataset, model: &SmoothModel) -> Option<String> {
    if data.training_samples() > START_CHECK_SAMPLES {
        return None;
    }
    let (again, _) = resettle(data, model, &[]);
    let ends = discounted(&again);
    let outputs = data.run_histories(|x| model.run(x).ok())?;
    let (mut start, mut rest) = ((0.0, 0.0), (0.0, 0.0));
    for ((r, y), end) in data.records.iter().zip(&outputs).zip(&ends) {
        if r.validation {
            continue;
        }
        for (i, ((obs, w), y)) in r.output.iter().zip(&r.weight).zip(y).enumerate() {
            let e = w * (y - obs).powi(2);
            let sum = if i < *end { &mut start } else { &mut rest };
            sum.0 += e;
            sum.1 += w;
        }
    }
    let rms = |(e, w): (f64, f64)| (e / w).sqrt();
    let (a, b) = (rms(start), rms(rest));
    (start.1 > 0.0 && rest.1 > 0.0 && a > START_MISMATCH * b).then(|| {
        format!(
            "the records' starts fit worse than the rest (RMS {} against {}): they do not start \
             by the start rule, so ",
            sig(a, 3),
            sig(b, 3)
        )
    })
}

/// The travel past a reversal, in units of 1/k2 beyond the loop's width 2 k1, after which the
/// operator's branch has come within e⁻¹² ≈ 6·10⁻⁶ of its asymptote: its memory is forgotten
/// (with e⁻⁷, a rate-term truth that starts mid-history came out with k2 2.6 % off).
pub const FORGETTING_TRAVEL: f64 = 12.0;

/// The plant's settling: from rest to within this fraction of a step's final value.
pub const PLANT_SETTLED: f64 = 1e-3;

/// How a timed fit's records start, after a first fit: `data` (its original weights) with each
/// history's start discounted until the fitted `model`'s operator has forgotten its memory
/// (its input ψ_in(v) moved one way by more than the loop's width plus
/// [`FORGETTING_TRAVEL`]/k2: [`forgotten_at`]) and the plant has settled from rest (within [`PLANT_SETTLED`]);
/// the report's note (which names the records whose memory is never forgotten: their start
/// shapes the fit unless it is estimated).
///
/// No history's discount is shorter than its entry of `floor` (one per history of
/// [`Dataset::histories`], in order; missing entries are 0): a fit made again on a longer
/// discount never shortens it.
#[must_use]
pub fn resettle(data: &Dataset, model: &SmoothModel, floor: &[usize]) -> (Dataset, Option<String>) {
    let mut settled = data.clone();
    let (mut discounted, mut remembers, mut short) = (0usize, Vec::new(), Vec::new());
    for (index, h) in data.histories().into_iter().enumerate() {
        let Some(&(first, _, _)) = h.parts.first() else {
            continue;
        };
        let id = data.records.get(first).map_or(0, |r| r.id);
        let mut w = Vec::with_capacity(h.input.len());
        let ran = model.run_timed(&h.input, h.period, None, |_, s| {
            w.push(model.input_shaping.apply(s.v));
        });
        if ran.is_err() || w.len() != h.input.len() {
            continue;
        }
        let sweep = forgotten_at(&w, forgetting_width(model, &w));
        if sweep.is_none() {
            remembers.push(id);
        }
        let plant = h
            .period
            .map_or(0, |steps| plant_settling(model, steps.nominal(), w.len()));
        let mut end = sweep
            .unwrap_or(0)
            .max(plant)
            .max(floor.get(index).copied().unwrap_or(0));
        let half = (MAX_SETTLING_SHARE * w.len() as f64) as usize;
        if end > half {
            short.push(id);
            end = half;
        }
        discounted += end;
        discount(&mut settled, &h.parts, end);
    }
    let mut note = format!(
        "the start of each record is not known (the operator's memory, the plant's state): \
         {discounted} samples at the records' starts, before the fitted operator had forgotten \
         its memory and the fitted plant had settled from rest, set the state but do not count \
         in the fit ({} % of the samples; --fit-from-start counts them, trusting the start rule)",
        sig(
            100.0 * discounted as f64 / data.training_samples().max(1) as f64,
            2
        )
    );
    if !remembers.is_empty() {
        note.push_str(&format!(
            "; the fitted operator never forgets its memory at the start of record(s) {} (its \
             input never moves one way across the loop and past its corners): their start \
             shapes the fit (--estimate-initial-states estimates it)",
            ids(&remembers)
        ));
    }
    if !short.is_empty() {
        note.push_str(&format!(
            "; record(s) {} are short against the plant's settling or the operator's memory: \
             only their first half is discounted, and their start still shapes the fit",
            ids(&short)
        ));
    }
    (settled, Some(note))
}

/// The travel after which the operator forgets its memory, whatever it was: the loop's width
/// 2 k1 plus [`FORGETTING_TRAVEL`]/k2 (k2 the law's smallest at the inputs' ends and centre).
fn forgetting_width(model: &SmoothModel, w: &[f64]) -> f64 {
    let (lo, hi) = range(w.iter());
    let k2 = [lo, 0.5 * (lo + hi), hi]
        .into_iter()
        .map(|x| model.k2.k2(x))
        .fold(f64::INFINITY, f64::min);
    2.0 * model.k1 + FORGETTING_TRAVEL / k2
}

/// The first sample of the operator inputs `w` by which they have moved one way, without a
/// reversal, by more than `width` (from anywhere in the band the branch has then reached its
/// asymptote: the memory is forgotten); `None` when they never do.
#[must_use]
pub fn forgotten_at(w: &[f64], width: f64) -> Option<usize> {
    if !(width.is_finite() && width > 0.0) {
        return None;
    }
    let first = *w.first()?;
    // The run's start (the last reversal) and its direction (0 until the input moves).
    let (mut from, mut last, mut direction) = (first, first, 0.0_f64);
    for (i, &x) in w.iter().enumerate().skip(1) {
        let step = x - last;
        if step != 0.0 {
            if direction != 0.0 && step.signum() != direction {
                from = last;
            }
            direction = step.signum();
        }
        last = x;
        if (x - from).abs() > width {
            return Some(i);
        }
    }
    None
}

/// The samples the fitted plant of `model` takes, at sample period `period`, from rest to
/// within [`PLANT_SETTLED`] of a unit step's final value for good (at most `limit`); 0 without
/// a plant.
fn plant_settling(model: &SmoothModel, period: f64, limit: usize) -> usize {
    let Some(d) = model.dynamics else {
        return 0;
    };
    let Ok(plant) = d.discretise(period) else {
        return 0;
    };
    let mut state = plant.at_rest(0.0);
    let mut last_out = 0;
    for k in 1..=limit {
        let v = plant.step(&mut state, d.b);
        if (v - d.b).abs() > PLANT_SETTLED * d.b.abs() {
            last_out = k;
        }
    }
    last_out
}

/// Weight 0 for the first `end` samples of a history of `settled` whose `parts` (record, first
/// sample in the history, length) are given.
fn discount(settled: &mut Dataset, parts: &[(usize, usize, usize)], end: usize) {
    for &(i, start, len) in parts {
        if start >= end {
            break;
        }
        if let Some(r) = settled.records.get_mut(i) {
            r.weight.fill(0..(end - start).min(len), 0.0);
        }
    }
}

/// Record ids as the report lists them.
fn ids(ids: &[i64]) -> String {
    abbreviate(&ids.iter().map(i64::to_string).collect::<Vec<_>>())
}

/// The samples of weight 0 at the start of each record of `data` (a discounted start).
#[must_use]
pub fn discounted(data: &Dataset) -> Vec<usize> {
    data.records
        .iter()
        .map(|r| r.weight.iter().take_while(|w| *w == 0.0).count())
        .collect()
}

/// The samples of weight 0 at the start of each history of `data` ([`Dataset::histories`], in
/// order): the `floor` of [`resettle`].
#[must_use]
pub fn discounted_histories(data: &Dataset) -> Vec<usize> {
    data.histories()
        .iter()
        .map(|h| h.weight.iter().take_while(|w| *w == 0.0).count())
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;

    #[test]
    fn a_sweep_ends_where_the_later_end_is_first_reached() {
        // From the middle up to the top, then down to the bottom at sample 30.
        let x: Vec<f64> = (0..100)
            .map(|i| (std::f64::consts::TAU * i as f64 / 40.0).sin())
            .collect();
        let end = settling_samples(&x).unwrap();
        assert!((29..=31).contains(&end), "{end}");
    }

    #[test]
    fn a_record_that_only_rises_keeps_its_start() {
        let x: Vec<f64> = (0..100).map(f64::from).collect();
        assert_eq!(settling_samples(&x), None);
        assert_eq!(settling_samples(&[1.0; 10]), None);
        assert_eq!(settling_samples(&[]), None);
    }

    #[test]
    fn memory_is_forgotten_after_a_run_across_the_loop() {
        // Up by 0.5, down by 1.2 (a run of 1.2 from the reversal at 0.5): past 1.05 at −0.6, sample 16.
        let mut w: Vec<f64> = (0..=5).map(|i| 0.1 * f64::from(i)).collect();
        w.extend((1..=12).map(|i| 0.5 - 0.1 * f64::from(i)));
        assert_eq!(forgotten_at(&w, 1.05), Some(16));
        assert_eq!(forgotten_at(&w, 2.0), None);
        assert_eq!(forgotten_at(&[], 1.0), None);
    }

    /// The static operator model H(k1, k2) without shaping.
    fn operator(k1: f64, k2: f64) -> SmoothModel {
        SmoothModel {
            k1,
            k2: hyst_core::AnyK2Law::Constant { value: k2 },
            input_shaping: hyst_core::ScaledShaping::identity(),
            output_shaping: hyst_core::ScaledShaping::identity(),
            initial_state: hyst_model::InitialState::Rising,
            form: hyst_model::Form::Operator,
            linear: 0.0,
            dynamics: None,
            rate: None,
        }
    }

    fn record(id: i64, x: &[f64]) -> crate::Record {
        crate::Record {
            id,
            input: x.to_vec().into(),
            output: x.to_vec().into(),
            weight: crate::Weights::Unit(x.len()),
            rows: (0..x.len()).collect(),
            validation: false,
            continues: false,
            period: None,
        }
    }

    #[test]
    fn a_record_that_never_sweeps_is_left_out_of_the_first_fit_when_another_sweeps() {
        let sweeps: Vec<f64> = (0..100)
            .map(|i| (std::f64::consts::TAU * i as f64 / 40.0).sin())
            .collect();
        let rises: Vec<f64> = (0..100).map(f64::from).collect();
        let data = Dataset::from_records(
            "<test>",
            hyst_model::Columns::default(),
            vec![record(1, &sweeps), record(2, &rises)],
        );
        let (settled, note) = settle(&data);
        assert_eq!(
            discounted(&settled),
            vec![settling_samples(&sweeps).unwrap(), 100]
        );
        assert!(note.unwrap().contains("record(s) 2 never sweep their range in their first half: the first fit leaves them out"));
        // Alone, it keeps its samples and the start rule.
        let alone = Dataset::from_records(
            "<test>",
            hyst_model::Columns::default(),
            vec![record(2, &rises)],
        );
        let (settled, note) = settle(&alone);
        assert_eq!(discounted(&settled), vec![0]);
        assert!(note.unwrap().contains("they start by the start rule"));
    }

    #[test]
    fn a_floor_keeps_a_discount_from_shortening() {
        let x: Vec<f64> = (0..200)
            .map(|i| (std::f64::consts::TAU * i as f64 / 40.0).sin())
            .collect();
        let data = Dataset::single(&x, &x);
        let model = operator(0.1, 20.0);
        let (free, _) = resettle(&data, &model, &[]);
        let (floored, _) = resettle(&data, &model, &[90]);
        assert!(discounted(&free)[0] < 90, "{:?}", discounted(&free));
        assert_eq!(discounted(&floored), vec![90]);
    }

    #[test]
    fn a_start_the_rule_does_not_describe_is_found() {
        let model = operator(0.3, 10.0);
        let x: Vec<f64> = (0..400)
            .map(|i| 1.5 * (std::f64::consts::TAU * f64::from(i) / 100.0).sin())
            .collect();
        // By the rule: the model's own output.
        let y = model.run(&x).unwrap();
        assert_eq!(start_mismatch(&Dataset::single(&x, &y), &model), None);
        // After unrecorded motion: the record starts at sample 60 of a longer run.
        let (x, y) = (&x[60..], &y[60..]);
        let noise: Vec<f64> = (0..y.len())
            .map(|i| 1e-3 * (f64::from(i as u32) * 1.7).sin())
            .collect();
        let y: Vec<f64> = y.iter().zip(&noise).map(|(a, b)| a + b).collect();
        let note = start_mismatch(&Dataset::single(x, &y), &model).unwrap();
        assert!(
            note.contains("they do not start by the start rule"),
            "{note}"
        );
    }

    #[test]
    fn settled_data_weighs_nothing_before_the_sweep() {
        let x: Vec<f64> = (0..100)
            .map(|i| (std::f64::consts::TAU * i as f64 / 40.0).sin())
            .collect();
        let data = Dataset::single(&x, &x);
        let (settled, note) = settle(&data);
        let w = settled.records[0].weight.to_vec();
        let end = settling_samples(&x).unwrap();
        assert!(w[..end].iter().all(|&w| w == 0.0));
        assert!(w[end..].iter().all(|&w| w == 1.0));
        assert!(note.unwrap().contains("do not count"));
    }
}
