//! What the diagnosis ([`crate::degeneracy::diagnose`]) reads of a fitted model's outputs on
//! the training records ([`ModelReading`]), gathered from two replays of them
//! ([`Outputs`]): none of a long record's outputs is held.

use crate::data::{range, Dataset};
use crate::orientation::LoopSums;
use crate::outputs::Outputs;

/// The model's findings on the training records of a dataset.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ModelReading {
    /// The gap between the model's own rising and falling branches on the training inputs
    /// (its outputs in place of the measured ones), as a fraction of the data's output span,
    /// not the model's (positive for clockwise).
    pub(crate) gap: f64,
    /// The RMS of the model's outputs against the training data (samples of positive weight;
    /// output units).
    pub(crate) rms: f64,
    /// The share of the residual variance explained by a least-squares term c · ẋ (ẋ the
    /// central difference of the input, per sample; weighted), in [0, 1].
    pub(crate) rate_share: f64,
    /// The share of the residual variance that a least-squares line in the sample index
    /// explains within each training record beyond what a line in the input explains (each
    /// record's own means removed, so an offset per record is not counted; weighted), in
    /// [0, 1]. Beyond the input: a record whose input moves one way in time (a first-order
    /// reversal curve) has residuals that follow its input, which is misfit, not drift.
    pub(crate) drift_share: f64,
}

/// Per training record, the first replay's weighted sums for the drift: Σw, Σw·t, Σw·x, Σw·e
/// (t the sample index, x the input, e the residual measured − model).
type Means = [f64; 4];

/// Per training record, the second replay's weighted sums about the record's means: Σw·t²,
/// Σw·t·x, Σw·x², Σw·t·e, Σw·x·e, Σw·e².
type Moments = [f64; 6];

impl ModelReading {
    /// The findings of the model `outputs` on the training records of `data`; when the model
    /// cannot run a record, those of no outputs at all (as a fit whose model cannot run its
    /// data has none).
    pub(crate) fn of(data: &Dataset, outputs: &dyn Outputs) -> Self {
        Self::read(data, outputs)
            .or_else(|| Self::read(data, &Vec::new()))
            .unwrap_or_default()
    }

    /// [`ModelReading::of`]; `None` when a replay fails.
    fn read(data: &Dataset, outputs: &dyn Outputs) -> Option<Self> {
        // Sample j of training record i: the record, its measured output, weight and input.
        let sample = |i: usize, j: usize| {
            let r = data.records.get(i).filter(|r| !r.validation)?;
            Some((r, *r.output.get(j)?, r.weight.get(j)?, *r.input.get(j)?))
        };
        // First replay: the inputs and outputs' ranges, the RMS, the rate term's sums and the
        // drift's means.
        let mut input_range = (f64::INFINITY, f64::NEG_INFINITY);
        let mut model_range = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut ss, mut n) = (0.0, 0usize);
        let (mut srr, mut srd, mut sdd) = (0.0, 0.0, 0.0);
        let mut means: Vec<Option<Means>> = vec![None; data.records.len()];
        let ran = outputs.replay(&mut |i, j, m| {
            let Some((r, o, w, x)) = sample(i, j) else {
                return;
            };
            if j == 0 {
                let seen = range(r.input.iter());
                input_range = (input_range.0.min(seen.0), input_range.1.max(seen.1));
            }
            model_range = (model_range.0.min(m), model_range.1.max(m));
            if w > 0.0 {
                ss += (m - o).powi(2);
                n += 1;
            }
            let last = r.input.len() - 1;
            let d = r.input[(j + 1).min(last)] - r.input[j.saturating_sub(1)];
            let e = o - m;
            srr += w * e * e;
            srd += w * e * d;
            sdd += w * d * d;
            let s = means[i].get_or_insert([0.0; 4]);
            s[0] += w;
            s[1] += w * j as f64;
            s[2] += w * x;
            s[3] += w * e;
        });
        if !ran {
            return None;
        }
        // Each record's means (none for a record of no weight).
        let centres: Vec<Option<[f64; 3]>> = means
            .iter()
            .map(|s| {
                let [sw, st, sx, se] = (*s)?;
                (sw > 0.0).then(|| [st / sw, sx / sw, se / sw])
            })
            .collect();
        // Second replay: the model's loops over the ranges found, the drift's moments.
        let mut loops = LoopSums::new(input_range, model_range);
        let mut moments: Vec<Moments> = vec![[0.0; 6]; data.records.len()];
        let ran = outputs.replay(&mut |i, j, m| {
            let Some((r, o, w, x)) = sample(i, j) else {
                return;
            };
            loops.add(&r.input, j, m, w);
            if let (Some(Some([tm, xm, em])), Some(s)) = (centres.get(i), moments.get_mut(i)) {
                let (t, x, e) = (j as f64 - tm, x - xm, o - m - em);
                // Each product as w · a · b, left to right.
                let terms = [
                    w * t * t,
                    w * t * x,
                    w * x * x,
                    w * t * e,
                    w * x * e,
                    w * e * e,
                ];
                for (acc, v) in s.iter_mut().zip(terms) {
                    *acc += v;
                }
            }
        });
        if !ran {
            return None;
        }
        let (ylo, yhi) = data.output_range();
        let model_span = model_range.1 - model_range.0;
        Some(ModelReading {
            gap: loops.loops().gap * model_span / (yhi - ylo).max(f64::MIN_POSITIVE),
            rms: (ss / n.max(1) as f64).sqrt(),
            rate_share: if srr > 0.0 && sdd > 0.0 {
                (srd * srd / (sdd * srr)).clamp(0.0, 1.0)
            } else {
                0.0
            },
            drift_share: drift_share(&centres, &moments),
        })
    }
}

/// The drift's share of the residual variance from each training record's moments (records
/// whose `centres` are `None` left out).
fn drift_share(centres: &[Option<[f64; 3]>], moments: &[Moments]) -> f64 {
    let (mut explained, mut total) = (0.0, 0.0);
    for (_, &[stt, stx, sxx, ste, sxe, see]) in
        centres.iter().zip(moments).filter(|(c, _)| c.is_some())
    {
        total += see;
        // Explained by [t, x] together, less what x alone explains.
        let det = stt * sxx - stx * stx;
        if sxx > 0.0 && det > 1e-9 * stt * sxx {
            let a = (sxx * ste - stx * sxe) / det;
            let b = (stt * sxe - stx * ste) / det;
            explained += (a * ste + b * sxe - sxe * sxe / sxx).max(0.0);
        }
    }
    if total > 0.0 {
        (explained / total).clamp(0.0, 1.0)
    } else {
        0.0
    }
}
