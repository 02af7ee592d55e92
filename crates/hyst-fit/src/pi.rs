//! The Prandtl–Ishlinskii baseline: y = c + w0 x + Σ w_i play_{r_i}[x] with thresholds spread
//! evenly over half the input span, fitted by weighted non-negative least squares
//! (w0 ≥ ε > 0, w_i ≥ 0, c free), which keeps the operator monotone and its analytic inverse
//! valid (see `hyst_core::prandtl_ishlinskii`).

use std::time::Instant;

use hyst_core::{Error, PrandtlIshlinskii};
use serde::{Deserialize, Serialize};

use crate::lm::{cholesky_solve, spd_inverse};
use crate::smooth::{error_stats, ErrorStats, Estimate};
use crate::{Dataset, FitError};

/// The largest number of play operators (the core type's capacity).
pub const MAX_OPERATORS: usize = 128;

/// The core operator type used for the baseline.
pub type CorePi = PrandtlIshlinskii<f64, MAX_OPERATORS>;

/// A Prandtl–Ishlinskii model as plain data (model files).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PiModel {
    /// w0, the weight of the identity (output units per input unit).
    pub identity_weight: f64,
    /// Play thresholds r_i (input units), strictly increasing.
    pub thresholds: Vec<f64>,
    /// Play weights w_i (output units per input unit), ≥ 0 when fitted.
    pub weights: Vec<f64>,
    /// Output offset c (output units).
    pub offset: f64,
}

impl PiModel {
    /// The core operator (no history: the plays start at rest at the first sample).
    ///
    /// # Errors
    /// Invalid parameters (the core's checks), more than [`MAX_OPERATORS`] plays.
    pub fn core(&self) -> Result<CorePi, Error> {
        CorePi::new(
            self.identity_weight,
            &self.thresholds,
            &self.weights,
            self.offset,
        )
    }

    /// Runs the model over one record.
    ///
    /// # Errors
    /// As [`PiModel::core`], or a non-finite input.
    pub fn run(&self, input: &[f64]) -> Result<Vec<f64>, Error> {
        let mut op = self.core()?;
        input.iter().map(|x| op.try_step(*x)).collect()
    }

    /// Runs the compensator (desired output → command) over one record; the plays start at
    /// rest at the first command.
    ///
    /// # Errors
    /// As [`PiModel::core`], or a non-finite desired output.
    pub fn run_inverse(&self, desired: &[f64]) -> Result<Vec<f64>, Error> {
        let mut op = self.core()?.inverse()?;
        desired.iter().map(|y| op.try_step(*y)).collect()
    }

    /// Number of free parameters (w0, the weights, the offset).
    #[must_use]
    pub fn parameter_count(&self) -> usize {
        self.weights.len() + 2
    }
}

/// A fitted Prandtl–Ishlinskii model.
#[derive(Clone, Debug)]
pub struct PiFit {
    /// The model.
    pub model: PiModel,
    /// w0, offset and weights with standard errors (from the unconstrained covariance of the
    /// free set; weights at the bound 0 get 0).
    pub estimates: Vec<Estimate>,
    /// Training errors.
    pub training: ErrorStats,
    /// Validation errors.
    pub validation: Option<ErrorStats>,
    /// Wall time (s).
    pub seconds: f64,
}

/// Play outputs of one record for thresholds `r` (plays at rest at the first sample).
fn plays(input: &[f64], r: &[f64]) -> Vec<Vec<f64>> {
    let mut state: Vec<f64> = r
        .iter()
        .map(|_| input.first().copied().unwrap_or(0.0))
        .collect();
    let mut cols = vec![Vec::with_capacity(input.len()); r.len()];
    for x in input {
        for ((p, ri), col) in state.iter_mut().zip(r).zip(cols.iter_mut()) {
            *p = (x - ri).max((x + ri).min(*p));
            col.push(*p);
        }
    }
    cols
}

/// Fits a Prandtl–Ishlinskii model with `operators` plays to the training records.
///
/// # Errors
/// Bad data ([`Dataset::check`]), an operator count outside 1..=[`MAX_OPERATORS`].
pub fn fit_pi(data: &Dataset, operators: usize) -> Result<PiFit, FitError> {
    let started = Instant::now();
    if operators == 0 || operators > MAX_OPERATORS {
        return Err(FitError::Invalid(format!(
            "--operators {operators}: choose 1 to {MAX_OPERATORS} play operators"
        )));
    }
    data.check(operators + 2)?;
    let (lo, hi) = data.input_range();
    let span = hi - lo;
    let r: Vec<f64> = (1..=operators)
        .map(|i| span * i as f64 / (2.0 * (operators + 1) as f64))
        .collect();
    let m = operators + 1; // identity + plays
                           // Weighted means, then the centred Gram matrix (the free offset is eliminated exactly).
    let mut sw = 0.0;
    let mut mean = vec![0.0; m];
    let mut ymean = 0.0;
    let mut columns: Vec<(Vec<Vec<f64>>, &crate::Record)> = Vec::new();
    for rec in data.training() {
        let mut cols = vec![rec.input.clone()];
        cols.extend(plays(&rec.input, &r));
        for (i, w) in rec.weight.iter().enumerate() {
            sw += w;
            ymean += w * rec.output[i];
            for (j, c) in cols.iter().enumerate() {
                mean[j] += w * c[i];
            }
        }
        columns.push((cols, rec));
    }
    for v in mean.iter_mut() {
        *v /= sw;
    }
    ymean /= sw;
    let mut gram = vec![0.0; m * m];
    let mut rhs = vec![0.0; m];
    let mut syy = 0.0;
    for (cols, rec) in &columns {
        for (i, w) in rec.weight.iter().enumerate() {
            let yc = rec.output[i] - ymean;
            syy += w * yc * yc;
            for a in 0..m {
                let xa = cols[a][i] - mean[a];
                rhs[a] += w * xa * yc;
                for b in a..m {
                    gram[a * m + b] += w * xa * (cols[b][i] - mean[b]);
                }
            }
        }
    }
    for a in 0..m {
        for b in 0..a {
            gram[a * m + b] = gram[b * m + a];
        }
    }
    // w0 ≥ ε: shift the variable.
    let eps = 1e-6 * (rhs[0] / gram[0].max(f64::MIN_POSITIVE)).abs().max(1e-12);
    let shifted: Vec<f64> = (0..m).map(|a| rhs[a] - gram[a * m] * eps).collect();
    let mut w = nnls(&gram, &shifted, m);
    w[0] += eps;
    let offset = ymean - w.iter().zip(&mean).map(|(a, b)| a * b).sum::<f64>();
    let model = PiModel {
        identity_weight: w[0],
        thresholds: r,
        weights: w[1..].to_vec(),
        offset,
    };
    // Standard errors on the free set (weights away from 0), offset from the centred model.
    let cost = (syy - 2.0 * w.iter().zip(&rhs).map(|(a, b)| a * b).sum::<f64>()
        + (0..m)
            .map(|a| (0..m).map(|b| w[a] * gram[a * m + b] * w[b]).sum::<f64>())
            .sum::<f64>())
    .max(0.0);
    let n = data.training_samples();
    let free: Vec<usize> = (0..m).filter(|&j| j == 0 || w[j] > 0.0).collect();
    let k = free.len();
    let s2 = cost / (n.saturating_sub(k + 1).max(1)) as f64;
    let sub: Vec<f64> = free
        .iter()
        .flat_map(|&a| free.iter().map(move |&b| (a, b)))
        .map(|(a, b)| gram[a * m + b])
        .collect();
    let inv = spd_inverse(&sub, k);
    let se = |j: usize| -> f64 {
        match (free.iter().position(|&f| f == j), &inv) {
            (Some(p), Some(inv)) => (inv[p * k + p] * s2).max(0.0).sqrt(),
            (Some(_), None) => f64::NAN,
            (None, _) => 0.0,
        }
    };
    let mut estimates = vec![
        Estimate {
            name: "w0".into(),
            value: w[0],
            std_error: se(0),
            unit: "output/input".into(),
        },
        Estimate {
            name: "offset".into(),
            value: offset,
            std_error: (s2 / sw).sqrt(),
            unit: "output units".into(),
        },
    ];
    for j in 1..m {
        estimates.push(Estimate {
            name: format!("w{j} (r = {:.4})", model.thresholds[j - 1]),
            value: w[j],
            std_error: se(j),
            unit: "output/input".into(),
        });
    }
    let (training, validation) = error_stats(data, |x| model.run(x).ok())?;
    Ok(PiFit {
        model,
        estimates,
        training,
        validation,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// Lawson–Hanson non-negative least squares on the normal equations: minimises
/// ½ wᵀ G w − bᵀ w subject to w ≥ 0.
#[must_use]
pub fn nnls(g: &[f64], b: &[f64], m: usize) -> Vec<f64> {
    let mut w = vec![0.0; m];
    let mut passive = vec![false; m];
    let scale = (0..m).map(|i| g[i * m + i]).fold(0.0_f64, f64::max);
    let tol =
        1e-12 * scale.max(f64::MIN_POSITIVE) * b.iter().fold(1e-300_f64, |a, v| a.max(v.abs()));
    for _outer in 0..(3 * m + 10) {
        let grad: Vec<f64> = (0..m)
            .map(|i| b[i] - (0..m).map(|j| g[i * m + j] * w[j]).sum::<f64>())
            .collect();
        let candidate = (0..m)
            .filter(|&i| !passive[i])
            .max_by(|&a, &c| grad[a].total_cmp(&grad[c]));
        let Some(t) = candidate else { break };
        if grad[t] <= tol {
            break;
        }
        passive[t] = true;
        for _inner in 0..(3 * m + 10) {
            let idx: Vec<usize> = (0..m).filter(|&i| passive[i]).collect();
            let k = idx.len();
            let mut sub = vec![0.0; k * k];
            for (a, &i) in idx.iter().enumerate() {
                for (c, &j) in idx.iter().enumerate() {
                    sub[a * k + c] = g[i * m + j];
                }
                sub[a * k + a] += 1e-13 * scale;
            }
            let rhs: Vec<f64> = idx.iter().map(|&i| b[i]).collect();
            let Some(s) = cholesky_solve(&sub, &rhs, k) else {
                passive[t] = false;
                break;
            };
            if s.iter().all(|v| *v > 0.0) {
                for (a, &i) in idx.iter().enumerate() {
                    w[i] = s[a];
                }
                break;
            }
            let mut alpha = 1.0_f64;
            for (a, &i) in idx.iter().enumerate() {
                if s[a] <= 0.0 {
                    let d = w[i] - s[a];
                    if d > 0.0 {
                        alpha = alpha.min(w[i] / d);
                    }
                }
            }
            for (a, &i) in idx.iter().enumerate() {
                w[i] += alpha * (s[a] - w[i]);
                if w[i] <= 1e-15 * (1.0 + s[a].abs()) {
                    w[i] = 0.0;
                    passive[i] = false;
                }
            }
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nnls_matches_a_small_case() {
        // min |A w − y|² with A = I, y = (1, −2): w = (1, 0)
        let g = [1.0, 0.0, 0.0, 1.0];
        let w = nnls(&g, &[1.0, -2.0], 2);
        assert!((w[0] - 1.0).abs() < 1e-12 && w[1] == 0.0, "{w:?}");
    }

    #[test]
    fn recovers_a_known_pi_model() -> Result<(), FitError> {
        let x: Vec<f64> = (0..3000)
            .map(|k| {
                let t = k as f64 * 0.01;
                (0.2 + 0.03 * t).min(1.0) * (2.0 * t).sin()
            })
            .collect();
        // Same thresholds as the fit will use for 4 operators on this input range.
        let (lo, hi) = x
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(*v), b.max(*v))
            });
        let r: Vec<f64> = (1..=4).map(|i| (hi - lo) * i as f64 / 10.0).collect();
        let truth = PiModel {
            identity_weight: 0.8,
            thresholds: r,
            weights: vec![0.5, 0.0, 0.3, 0.1],
            offset: -2.0,
        };
        let y = truth.run(&x)?;
        let fit = fit_pi(&Dataset::single(&x, &y), 4)?;
        assert!(
            (fit.model.identity_weight - 0.8).abs() < 1e-8,
            "{:?}",
            fit.model
        );
        for (a, b) in fit.model.weights.iter().zip(&truth.weights) {
            assert!((a - b).abs() < 1e-8, "{:?}", fit.model);
        }
        assert!((fit.model.offset + 2.0).abs() < 1e-8);
        assert!(fit.training.rms < 1e-8);
        Ok(())
    }
}
