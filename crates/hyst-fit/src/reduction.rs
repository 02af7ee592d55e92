//! Rate independence makes long records cheap to fit: the operator's output at a sample depends
//! only on the input's turning points before it and on the sample's own input (Definition 2.1:
//! the memory changes only at a reversal, and between reversals the output is eq. (2) of the
//! reversal point and the current input). Dropping samples inside a monotone run of the input
//! therefore leaves the output at every kept sample exactly as it was, and a record reduced to
//! its turning points plus every k-th sample is simulated exactly where it is kept, at a
//! fraction of the cost.
//!
//! [`reduce`] builds that reduced dataset. Its weights make its cost an unbiased estimate of
//! the full cost (Horvitz–Thompson): a sample kept because it must be (a turning point, an
//! output extreme) stands for itself, and a sample kept by the 1-in-k draw, which does not look
//! at the data, stands for k samples. (Moving each dropped sample's weight onto its nearer kept
//! neighbour, a midpoint rule, is biased: the turning points, where the model's error is of
//! its own kind, carry the weight of the runs around them, and the reduction's optimum lies
//! 180 relative offsets from the full data's on the 2M-row piezo record, against 13 with these
//! weights.)
//! The fit uses it for the search (start grid, Levenberg–Marquardt from the starts, family
//! widths) and then polishes the result on the full data.
//!
//! A record whose input turns at almost every sample (a random walk, a noisy input) has nothing
//! to drop: then the search runs on a draw of windows instead ([`draw`]): contiguous stretches
//! of the record, one at a random place in each block of the record, each simulated from the
//! model's start rule. The state a window starts from is not the one the history would have
//! left; the operator forgets it as the input travels (a branch approaches its asymptote as
//! e^(−k2 ũ)), so the samples before the input has travelled over the record's span within the
//! window have weight 0. The draw is an estimate, not exact where kept: the polish on the full
//! data corrects it.

use crate::data::{Dataset, Record};
use crate::rows::Rows;
use crate::weights::Weights;

/// Records with fewer training samples than this are fitted whole.
pub const REDUCE_ABOVE: usize = 100_000;

/// The smallest reduction aims at about this many samples (turning points are always kept, so
/// it may keep more).
pub const TARGET: usize = 50_000;

/// The search's data for a long record ([`reduce`]).
#[derive(Clone, Debug)]
pub enum Reduction {
    /// Turning points, output extremes and 1 in k other samples: exact where kept.
    Turning(Dataset),
    /// A [`draw`] of windows: an estimate.
    Draw(Dataset),
}

impl Reduction {
    /// The reduced data.
    #[must_use]
    pub fn data(&self) -> &Dataset {
        match self {
            Reduction::Turning(d) | Reduction::Draw(d) => d,
        }
    }
}

/// Whether sample `i` of `x` must be kept: the ends, and every turning point of the input (a
/// local extremum, or the ends of a plateau), where the operator's memory may change.
fn turning(x: &[f64], i: usize) -> bool {
    let n = x.len();
    if i == 0 || i + 1 >= n {
        return true;
    }
    let (a, b) = (x[i] - x[i - 1], x[i + 1] - x[i]);
    // Not strictly monotone through i (a sign change, or a zero step on either side).
    !(a > 0.0 && b > 0.0 || a < 0.0 && b < 0.0)
}

/// Whether sample `i` is among the 1-in-`stride` samples kept between turning points: chosen
/// by a hash of `i` (SplitMix64), not every `stride`-th sample, so that a periodic input whose
/// period is a multiple of the stride is still sampled at every phase (a fixed stride would see
/// the same few phases in every period and bias the cost).
fn picked(i: usize, stride: usize) -> bool {
    splitmix64(i as u64).is_multiple_of(stride as u64)
}

/// SplitMix64's output for the state `z`: a hash whose every output bit depends on every input
/// bit.
fn splitmix64(z: u64) -> u64 {
    let mut z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// All samples of `data`, every record's.
fn samples(data: &Dataset) -> usize {
    data.records.iter().map(Record::len).sum()
}

/// The k of the reduction's 1 in k, which also sets the [`draw`]'s block length: about
/// [`TARGET`] samples are kept.
fn stride(data: &Dataset) -> usize {
    (samples(data) / TARGET).max(1)
}

/// The most samples a reduction keeps: beyond, the search runs on the [`draw`] (bounded in
/// size whatever the record's length). A random walk keeps 4 in 10 of its samples as turning
/// points: 4.2 M samples, 100 MB, of a 10 M-row record.
pub const MAX_KEPT: usize = 1 << 20;

/// Samples in a window of the [`draw`].
pub const WINDOW: usize = 2_000;

/// Samples around each extreme of a record's input and output that the [`draw`] keeps, at
/// weight 0, so that the drawn data has the full data's ranges (and normalisation).
const EXTREME_WINDOW: usize = 16;

/// The dataset reduced to the turning points of each record's input, the samples where each
/// record's output is extreme (so the normalisation is unchanged), and one in k other samples;
/// a sample that must be kept has its own weight, one of the 1 in k has k times its own. When
/// that would keep more than half of the samples (an input that turns at almost every
/// sample), or more than [`MAX_KEPT`] samples, the [`draw`] of windows instead. `None` when
/// `data` is small (below [`REDUCE_ABOVE`] training samples).
#[must_use]
pub fn reduce(data: &Dataset) -> Option<Reduction> {
    reduce_keeping(data, MAX_KEPT)
}

/// [`reduce`], drawing when the reduction would keep more than `max_kept` samples.
fn reduce_keeping(data: &Dataset, max_kept: usize) -> Option<Reduction> {
    if data.training_samples() < REDUCE_ABOVE {
        return None;
    }
    let total = samples(data);
    let stride = stride(data);
    // The samples each record keeps, counted before anything is copied: a record whose input
    // turns at almost every sample would otherwise build a reduction of more than half the
    // data only to drop it for the draw. (No flag per sample is held: they are worked out
    // again as the reduction is copied.)
    let mut forced: Vec<Forced> = Vec::with_capacity(data.records.len());
    let mut kept_total = 0usize;
    for r in &data.records {
        let must = Forced::of(r);
        kept_total += (0..r.len())
            .filter(|&i| must.at(r, i) || picked(i, stride))
            .count();
        if 2 * kept_total > total || kept_total > max_kept {
            return Some(Reduction::Draw(draw(data)));
        }
        forced.push(must);
    }
    let records = data
        .records
        .iter()
        .zip(forced)
        .map(|(r, must)| kept(r, &must, stride))
        .collect();
    Some(Reduction::Turning(Dataset::from_records(
        &data.source,
        data.columns.clone(),
        records,
    )))
}

/// The samples of a record that must be kept whatever the draw: its turning points, and the
/// extremes of its output (so that the reduced data has the same output range; the input's
/// are turning points already).
struct Forced {
    /// The extremes of the record ([`extremes`]).
    extremes: Vec<usize>,
}

impl Forced {
    /// The samples `r` must keep.
    fn of(r: &Record) -> Forced {
        Forced {
            extremes: extremes(r),
        }
    }

    /// Whether sample `i` of `r` must be kept.
    fn at(&self, r: &Record, i: usize) -> bool {
        turning(&r.input, i) || self.extremes.contains(&i)
    }
}

/// The samples of `r` kept by the reduction: those `forced` at their own weight, the 1 in
/// `stride` others at `stride` times theirs.
fn kept(r: &Record, forced: &Forced, stride: usize) -> Record {
    let (mut input, mut output, mut weight) = (Vec::new(), Vec::new(), Vec::new());
    let mut rows = Rows::default();
    for (i, row) in r.rows.iter().enumerate().take(r.len()) {
        let must = forced.at(r, i);
        if !must && !picked(i, stride) {
            continue;
        }
        input.push(r.input[i]);
        output.push(r.output[i]);
        let w = if must { 1.0 } else { stride as f64 };
        weight.push(w * r.weight[i]);
        rows.push(row);
    }
    Record {
        id: r.id,
        input: input.into(),
        output: output.into(),
        weight: Weights::from_values(weight),
        rows,
        validation: r.validation,
        continues: r.continues,
        // The kept samples are not consecutive: only a static model (which takes no time)
        // runs on a reduction.
        period: r.period.clone(),
    }
}

/// The search's data for records that do not reduce: in each block of k · [`WINDOW`] samples
/// of a record (k the reduction's 1 in k, at least 2), one window of [`WINDOW`] contiguous samples at a place drawn by a hash
/// of the block (each its own record, simulated from the start rule), and a few samples around
/// each extreme of the record's input and output at weight 0 (the ranges stay the full
/// data's). In a window, the samples before the input has travelled over the record's input
/// span (at most the first half of the window) have weight 0: the state the window starts from
/// is forgotten by then. The others carry the block's weight (block length over the samples
/// counted), so the cost estimates the full cost. A record of at most two windows is kept
/// whole.
#[must_use]
pub fn draw(data: &Dataset) -> Dataset {
    let stride = stride(data);
    let mut records = Vec::new();
    for (index, r) in data.records.iter().enumerate() {
        let n = r.len();
        if n <= 2 * WINDOW {
            records.push(r.clone());
            continue;
        }
        let span = {
            let (lo, hi) = crate::data::range(r.input.iter());
            hi - lo
        };
        let block = WINDOW * stride.max(2);
        // The windows taken so far (one per block, and a few around the extremes).
        let mut covered: Vec<core::ops::Range<usize>> = Vec::new();
        let mut start = 0;
        while start < n {
            let len = block.min(n - start);
            let room = len.saturating_sub(WINDOW) + 1;
            let at = start + hash(index as u64, start as u64) % room;
            let end = (at + WINDOW).min(n);
            records.push(window(r, at..end, span, len));
            covered.push(at..end);
            start += len;
        }
        for i in extremes(r) {
            if !covered.iter().any(|w| w.contains(&i)) {
                let at = i.saturating_sub(EXTREME_WINDOW / 2);
                let end = (at + EXTREME_WINDOW).min(n);
                let mut kept = window(r, at..end, span, 0);
                kept.weight.fill(0..kept.len(), 0.0);
                records.push(kept);
                covered.push(at..end);
            }
        }
    }
    Dataset::from_records(&data.source, data.columns.clone(), records)
}

/// The rows of the extremes of a record's input and output.
fn extremes(r: &Record) -> Vec<usize> {
    let mut rows = Vec::with_capacity(4);
    for values in [&r.input, &r.output] {
        for pick in [f64::total_cmp, |a: &f64, b: &f64| b.total_cmp(a)] {
            if let Some((i, _)) = values.iter().enumerate().max_by(|a, b| pick(a.1, b.1)) {
                rows.push(i);
            }
        }
    }
    rows
}

/// The samples `rows` of `r` as a record of their own (not continuing another), weight 0 until
/// the input has travelled over `span` (at most the first half), the others weighted to stand
/// for the `block` samples the window was drawn from.
fn window(r: &Record, rows: core::ops::Range<usize>, span: f64, block: usize) -> Record {
    let input = r.input[rows.clone()].to_vec();
    let mut travel = 0.0;
    let warm = input
        .windows(2)
        .position(|w| {
            travel += (w[1] - w[0]).abs();
            travel >= span
        })
        .map_or(input.len() / 2, |i| i + 1)
        .min(input.len() / 2);
    let counted = (input.len() - warm).max(1);
    let scale = block as f64 / counted as f64;
    let weight = Weights::Each(
        r.weight
            .slice(rows.clone())
            .iter()
            .enumerate()
            .map(|(k, w)| if k < warm { 0.0 } else { w * scale })
            .collect(),
    );
    Record {
        id: r.id,
        input: input.into(),
        output: r.output[rows.clone()].into(),
        weight,
        rows: r.rows.slice(rows.clone()),
        validation: r.validation,
        continues: false,
        period: r.period.as_ref().map(|p| p.after(rows.start)),
    }
}

/// A hash of (record, block start) ([`splitmix64`] of their mix): where the draw's window
/// lies.
fn hash(record: u64, start: u64) -> usize {
    splitmix64(start ^ record.rotate_left(32)) as usize
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use hyst_core::{AnyK2Law, ScaledShaping};
    use hyst_model::{InitialState, SmoothModel};

    fn sweep(n: usize) -> Vec<f64> {
        (0..n)
            .map(|k| {
                let t = k as f64 * 2e-4;
                (1.0 + 0.3 * (0.05 * t).sin()) * t.sin() + 0.2 * (2.7 * t).cos()
            })
            .collect()
    }

    #[test]
    fn the_operator_output_is_exact_at_every_kept_sample() {
        let x = sweep(300_000);
        let model = SmoothModel {
            k1: 0.2,
            k2: AnyK2Law::Constant { value: 6.0 },
            input_shaping: ScaledShaping::identity(),
            output_shaping: ScaledShaping::identity(),
            initial_state: InitialState::Rising,
            form: hyst_model::Form::Operator,
            linear: 0.0,
            dynamics: None,
            rate: None,
        };
        let y = model.run(&x).unwrap();
        let data = Dataset::single(&x, &y);
        let reduced = match reduce(&data) {
            Some(Reduction::Turning(d)) => Some(d),
            _ => None,
        }
        .unwrap();
        let r = &reduced.records[0];
        assert!(r.len() < 60_000 && r.len() > 10_000, "{}", r.len());
        // The weights estimate the number of samples (and any sum over them) without bias: a
        // forced sample counts once, a drawn one `stride` times. The ranges are the same.
        let w: f64 = r.weight.iter().sum();
        assert!((w / 300_000.0 - 1.0).abs() < 0.02, "{w}");
        let full: f64 = y.iter().map(|v| v * v).sum();
        let estimate: f64 = r.output.iter().zip(&r.weight).map(|(v, w)| w * v * v).sum();
        assert!(
            (estimate / full - 1.0).abs() < 0.02,
            "{estimate} against {full}"
        );
        assert_eq!(reduced.input_range(), data.input_range());
        assert_eq!(reduced.output_range(), data.output_range());
        // Simulated on the kept samples alone, the model gives the full run's outputs there.
        let again = model.run(&r.input).unwrap();
        for (k, row) in r.rows.iter().enumerate() {
            assert_eq!(again[k].to_bits(), y[row].to_bits(), "row {row}");
        }
    }

    /// A reduction that would keep more than its cap is a draw: the search's data stays
    /// bounded whatever the record's length.
    #[test]
    fn a_reduction_beyond_its_cap_is_a_draw() {
        let x = sweep(300_000);
        let data = Dataset::single(&x, &x);
        let kept = reduce_keeping(&data, usize::MAX).map(|r| r.data().records[0].len());
        assert!(matches!(
            reduce_keeping(&data, usize::MAX),
            Some(Reduction::Turning(_))
        ));
        let cap = kept.unwrap() - 1;
        assert!(matches!(
            reduce_keeping(&data, cap),
            Some(Reduction::Draw(_))
        ));
    }

    #[test]
    fn small_records_are_not_reduced_and_noisy_ones_are_drawn() {
        let x = sweep(50_000);
        assert!(reduce(&Dataset::single(&x, &x)).is_none());
        // A noisy input turns at about every other sample: nothing to drop, so a draw of
        // windows.
        let mut seed = 7u64;
        let noisy: Vec<f64> = sweep(300_000)
            .into_iter()
            .map(|v| {
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                v + 1e-3 * ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
            })
            .collect();
        let y: Vec<f64> = noisy.iter().map(|v| 2.0 * v + 0.1 * v * v).collect();
        let data = Dataset::single(&noisy, &y);
        let drawn = match reduce(&data) {
            Some(Reduction::Draw(d)) => Some(d),
            _ => None,
        }
        .unwrap();
        let kept: usize = drawn.records.iter().map(Record::len).sum();
        assert!(kept <= TARGET + 2 * WINDOW, "{kept}");
        // Each window is a contiguous stretch of the record, as it was.
        for r in &drawn.records {
            assert!(r.len() <= WINDOW && !r.continues);
            for (k, row) in r.rows.iter().enumerate() {
                assert_eq!(r.rows.get(0).map(|first| first + k), Some(row));
                assert_eq!(r.input[k].to_bits(), noisy[row].to_bits());
                assert_eq!(r.output[k].to_bits(), y[row].to_bits());
            }
        }
        // Same ranges (so the same normalisation); the weights estimate the sample count.
        assert_eq!(drawn.input_range(), data.input_range());
        assert_eq!(drawn.output_range(), data.output_range());
        let w: f64 = drawn.records.iter().flat_map(|r| r.weight.iter()).sum();
        assert!((w / 300_000.0 - 1.0).abs() < 1e-9, "{w}");
    }

    #[test]
    fn a_window_counts_once_the_input_has_travelled_over_the_span() {
        // A ramp over the span in 100 samples, then back: the first 100 have weight 0.
        let x: Vec<f64> = (0..1000)
            .map(|i| {
                let p = i % 200;
                if p < 100 {
                    p as f64
                } else {
                    200.0 - p as f64
                }
            })
            .collect();
        let data = Dataset::single(&x, &x);
        let w = window(&data.records[0], 0..1000, 99.0, 4000);
        assert!(w.weight.slice(0..99).iter().all(|v| v == 0.0));
        assert!(w.weight.slice(99..1000).iter().all(|v| v > 0.0));
        let total: f64 = w.weight.iter().sum();
        assert!((total - 4000.0).abs() < 1e-9, "{total}");
        // A window that never travels that far counts its second half.
        let w = window(&data.records[0], 0..50, 99.0, 100);
        assert_eq!(w.weight.iter().filter(|v| *v > 0.0).count(), 25);
    }
}
