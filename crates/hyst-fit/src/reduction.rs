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
//! neighbour, a midpoint rule, was biased: the turning points, where the model's error is of
//! its own kind, carried the weight of the runs around them, and the reduction's optimum lay
//! 180 relative offsets from the full data's on the 2M-row piezo record, against 13 now.)
//! The fit uses it for the search (start grid, Levenberg–Marquardt from the starts, family
//! widths) and then polishes the result on the full data. A record whose input is noisy has a
//! turning point at almost every sample and is not reduced: the method needs no assumption on
//! the data, it only gains less.

use crate::data::{Dataset, Record};

/// Records with fewer training samples than this are fitted whole.
pub const REDUCE_ABOVE: usize = 100_000;

/// The smallest reduction aims at about this many samples (turning points are always kept, so
/// it may keep more).
pub const TARGET: usize = 50_000;

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
    let mut z = (i as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    z.is_multiple_of(stride as u64)
}

/// The dataset reduced to the turning points of each record's input, the samples where each
/// record's output is extreme (so the normalisation is unchanged), and one in k other samples;
/// a sample that must be kept has its own weight, one of the 1 in k has k times its own. `None` when `data` is small
/// (below [`REDUCE_ABOVE`] training samples) or the reduction would keep more than half of the
/// samples.
#[must_use]
pub fn reduce(data: &Dataset) -> Option<Dataset> {
    let total: usize = data.records.iter().map(Record::len).sum();
    if data.training_samples() < REDUCE_ABOVE {
        return None;
    }
    let stride = (total / TARGET).max(1);
    let mut kept_total = 0usize;
    let mut records = Vec::with_capacity(data.records.len());
    for r in &data.records {
        let n = r.len();
        // Kept whatever the draw: turning points and (below) the output's extremes.
        let mut forced: Vec<bool> = (0..n).map(|i| turning(&r.input, i)).collect();
        // The output's extremes, so that the reduced data has the same output range.
        for pick in [f64::total_cmp, |a: &f64, b: &f64| b.total_cmp(a)] {
            if let Some((i, _)) = r.output.iter().enumerate().max_by(|a, b| pick(a.1, b.1)) {
                forced[i] = true;
            }
        }
        let mut reduced = Record {
            id: r.id,
            input: Vec::new(),
            output: Vec::new(),
            weight: Vec::new(),
            rows: Vec::new(),
            validation: r.validation,
            continues: r.continues,
            period: r.period,
        };
        for (i, &must) in forced.iter().enumerate() {
            if !must && !picked(i, stride) {
                continue;
            }
            reduced.input.push(r.input[i]);
            reduced.output.push(r.output[i]);
            let w = if must { 1.0 } else { stride as f64 };
            reduced.weight.push(w * r.weight[i]);
            reduced.rows.push(r.rows[i]);
        }
        kept_total += reduced.len();
        records.push(reduced);
    }
    if 2 * kept_total > total {
        return None;
    }
    Some(Dataset::from_records(
        &data.source,
        data.columns.clone(),
        records,
    ))
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
        let reduced = reduce(&data).unwrap();
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
            assert_eq!(again[k].to_bits(), y[*row].to_bits(), "row {row}");
        }
    }

    #[test]
    fn small_or_noisy_records_are_not_reduced() {
        let x = sweep(50_000);
        assert!(reduce(&Dataset::single(&x, &x)).is_none());
        // A noisy input turns at about every other sample.
        let mut seed = 7u64;
        let noisy: Vec<f64> = sweep(300_000)
            .into_iter()
            .map(|v| {
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                v + 1e-3 * ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
            })
            .collect();
        assert!(reduce(&Dataset::single(&noisy, &noisy)).is_none());
    }
}
