//! Fitting a model with dynamics or a rate term (`--dynamics N`, `--rate-term viscous`): the
//! nesting that starts its fit, the static view its hysteresis part is checked on, and what the
//! report says of the plant and the rate term.
//!
//! - Nesting: a structure with a rate term contains the one without; one with dynamics of
//!   order n contains order n − 1, down to the static structure ([`simpler_timed`]). Each is
//!   fitted first (the static one with the whole static machinery), and its optimum starts the
//!   richer fit: a plant whose time constants are far below the sample period is the static
//!   model (the discretisation's limit), so a richer fit never ends worse.
//! - Static view ([`static_view`]): each record's input replaced by the hysteresis input v the
//!   fitted plant gives, its output by the output minus the rate term. The model's hysteresis
//!   part reproduces that view exactly as the whole model reproduces the data, so the family
//!   widths, the bound Δa and the check that the fit found hysteresis run on it unchanged.
//!   They cover the hysteresis part for the fitted plant and rate term, not the errors of
//!   a_i or c.
//! - Findings ([`TimedFindings`]): whether the records identify each a_i (its standard error,
//!   and whether order i fits better than order i − 1) and whether they support the rate term
//!   (c positive beyond three standard errors, and a lower error than without it). A rate term
//!   the data does not support is left out of the model.

use hyst_core::Shaping;
use hyst_io::number::sig;
use hyst_io::{IoError, SamplesWriter};
use hyst_model::dynamics::{DynamicsSection, RateSection};
use hyst_model::{ErrorStats, Estimate, SmoothModel, Structure};
use serde::{Deserialize, Serialize};

use crate::data::Dataset;
use crate::error::FitError;
use crate::layout::{dynamics_name, RATE_C};

/// Order i of the plant counts as identified when its fit's training RMS error is at least this
/// fraction below that of order i − 1 (and a_i's standard error is below
/// [`MAX_RELATIVE_ERROR`] of it).
pub const MIN_IMPROVEMENT: f64 = 0.02;

/// The largest standard error of an identified a_i or of a supported c, relative to its value.
pub const MAX_RELATIVE_ERROR: f64 = 1.0 / 3.0;

/// The highest plant order `--dynamics auto` tries.
pub const MAX_AUTO_ORDER: u8 = 4;

/// One plant order tried by `--dynamics auto` ([`crate::identify`]).
#[derive(Clone, Debug, PartialEq)]
pub struct OrderTried {
    /// The order.
    pub order: u8,
    /// Free parameters.
    pub parameters: usize,
    /// Training RMS error (% of span).
    pub training: f64,
    /// Validation RMS error (% of span), with validation records.
    pub validation: Option<f64>,
    /// The information criterion n_e ln(RSS / n) + p ln n_e, n_e = n / τ with τ the
    /// correlation time of the whitest residuals among the orders tried: Schwarz's BIC over
    /// the residuals' independent samples.
    pub criterion: f64,
}

impl OrderTried {
    /// The order the validation records prefer (the lowest within 1 % of the best validation
    /// error), or else the one of the lowest criterion; `None` for no order.
    #[must_use]
    pub fn choose(tried: &[OrderTried]) -> Option<u8> {
        let best_valid = tried
            .iter()
            .filter_map(|t| t.validation)
            .fold(f64::INFINITY, f64::min);
        if best_valid.is_finite() {
            return tried
                .iter()
                .find(|t| t.validation.is_some_and(|v| v <= 1.01 * best_valid))
                .map(|t| t.order);
        }
        tried
            .iter()
            .filter(|t| t.criterion.is_finite())
            .min_by(|a, b| a.criterion.total_cmp(&b.criterion))
            .map(|t| t.order)
    }

    /// The report's table of the orders tried and the one kept.
    #[must_use]
    pub fn note(tried: &[OrderTried], kept: u8, by_validation: bool) -> String {
        let rows: Vec<String> = tried
            .iter()
            .map(|t| {
                format!(
                    "order {} ({} parameters): training {} %{}, criterion {}",
                    t.order,
                    t.parameters,
                    sig(t.training, 3),
                    t.validation
                        .map_or(String::new(), |v| format!(", validation {} %", sig(v, 3))),
                    sig(t.criterion, 5)
                )
            })
            .collect();
        format!(
            "--dynamics auto kept order {kept}, {}: {}",
            if by_validation {
                "the validation records' lowest error (the lowest order within 1 % of it)"
            } else {
                "the lowest information criterion n_e ln(RSS/n) + p ln n_e over the residuals' \
                 independent samples n_e"
            },
            rows.join("; ")
        )
    }
}

/// An a_i whose time scale a_i^(1/i) is below this fraction of the shortest sample period is at
/// its limit a_i → 0: the plant's part of that order acts within a hundredth of a sample,
/// and every smaller a_i gives the same model.
pub const LIMIT_PERIODS: f64 = 0.01;

/// Whether a structure has dynamics or a rate term.
#[must_use]
pub fn is_timed(structure: Structure) -> bool {
    structure.dynamics > 0 || structure.rate.is_some()
}

/// The structure one step down the timed nesting: without the rate term, else with one order
/// of dynamics less; `None` for a static structure.
#[must_use]
pub fn simpler_timed(structure: Structure) -> Option<Structure> {
    if structure.rate.is_some() {
        Some(Structure {
            rate: None,
            ..structure
        })
    } else if structure.dynamics > 0 {
        Some(Structure {
            dynamics: structure.dynamics - 1,
            ..structure
        })
    } else {
        None
    }
}

/// The static view of a timed `model` on `data` (see the module docs), with the model's
/// hysteresis part (the model without plant and rate term). A long history's view goes to
/// temporary files ([`hyst_io::Samples`]), its records parts of them.
///
/// # Errors
/// [`FitError::NoConvergence`] when the model cannot run a record; a temporary file that
/// cannot be written ([`FitError::Io`], naming the data file).
pub fn static_view(
    data: &Dataset,
    model: &SmoothModel,
) -> Result<(Dataset, SmoothModel), FitError> {
    let cannot_run = || FitError::NoConvergence("the fitted model cannot run the records".into());
    let view = static_view_of(data, model)
        .map_err(|e| e.reading(&data.source))?
        .ok_or_else(cannot_run)?;
    Ok(view)
}

/// [`static_view`]: `Ok(None)` when the model cannot run a record.
fn static_view_of(
    data: &Dataset,
    model: &SmoothModel,
) -> Result<Option<(Dataset, SmoothModel)>, IoError> {
    let mut view = data.clone();
    for h in data.histories() {
        let (mut v, mut output) = (SamplesWriter::default(), SamplesWriter::default());
        let mut failed = None;
        let ran = model.run_timed(&h.input, h.period, None, |i, s| {
            // The observed output less the plant's and the rate term's share.
            let rate = s.y - model.output(model.input_shaping.apply(s.v), s.z);
            let observed = h.output.get(i).copied().unwrap_or(f64::NAN);
            if failed.is_none() {
                failed = v
                    .push(s.v)
                    .and_then(|()| output.push(observed - rate))
                    .err();
            }
        });
        if let Some(e) = failed {
            return Err(e);
        }
        if ran.is_err() || v.len() != h.input.len() {
            return Ok(None);
        }
        let (v, output) = (v.finish()?, output.finish()?);
        for (i, start, len) in h.parts {
            let Some(r) = view.records.get_mut(i) else {
                return Ok(None);
            };
            r.input = v.slice(start..start + len);
            r.output = output.slice(start..start + len);
        }
    }
    let hysteresis = SmoothModel {
        dynamics: None,
        rate: None,
        ..*model
    };
    Ok(Some((view, hysteresis)))
}

/// One coefficient a_i of the fitted plant, as the report states it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Coefficient {
    /// "dynamics.a1", …
    pub name: String,
    /// Its value (s^i).
    pub value: f64,
    /// Its standard error.
    pub std_error: f64,
    /// Whether the records identify it.
    pub identified: bool,
    /// Why not, when they do not.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub reason: String,
}

/// What the fit found of the plant and the rate term (the report's `timed`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct TimedFindings {
    /// The training RMS error (% of span) of each order fitted, 0 (static) … n.
    pub rms_by_order: Vec<f64>,
    /// The plant's coefficients (empty without dynamics).
    pub coefficients: Vec<Coefficient>,
    /// The rate term, when one was asked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<RateFinding>,
    /// The sample periods of the records (s): the smallest and the largest.
    pub periods: (f64, f64),
    /// Every timed structure the fit contains, fitted on the way, and the fit itself: each
    /// richer structure's training error is at most that of each structure it contains.
    #[serde(default)]
    pub nesting: Vec<Nested>,
}

/// One structure of a timed fit's nesting ([`TimedFindings::nesting`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Nested {
    /// "static", "rate", "dynamics 1", "dynamics 1 + rate", …
    pub structure: String,
    /// Its free parameters.
    pub parameters: usize,
    /// Its training RMS error (% of span).
    pub rms_pct_span: f64,
}

impl Nested {
    /// The name of a timed structure's nesting level.
    #[must_use]
    pub fn name(structure: Structure) -> String {
        match (structure.dynamics, structure.rate.is_some()) {
            (0, false) => "static".into(),
            (0, true) => "rate".into(),
            (n, false) => format!("dynamics {n}"),
            (n, true) => format!("dynamics {n} + rate"),
        }
    }
}

/// Whether the data supports the rate term asked for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RateFinding {
    /// c as fitted (output units · s / input unit).
    pub c: f64,
    /// Its standard error.
    pub std_error: f64,
    /// The training RMS error (% of span) without and with the term.
    pub rms_without: f64,
    /// With it.
    pub rms_with: f64,
    /// Whether the data supports it; when not, the model leaves it out.
    pub supported: bool,
    /// Why (in words).
    pub reason: String,
}

impl RateFinding {
    /// The finding on the rate term of a fit with `estimates` and training errors `with`,
    /// against the training RMS error `without` of the fit without it (% of span).
    fn new(estimates: &[Estimate], without: f64, with: ErrorStats) -> Self {
        let e = estimates.iter().find(|e| e.name == RATE_C);
        let (c, std_error) = e.map_or((f64::NAN, f64::NAN), |e| (e.value, e.std_error));
        let better = with.rms_pct_span <= (1.0 - MIN_IMPROVEMENT) * without;
        let significant = c > 0.0 && std_error.is_finite() && std_error <= MAX_RELATIVE_ERROR * c;
        let reason = if c <= 0.0 {
            format!(
                "c = {} is not positive: the output does not grow with the input's rate",
                sig(c, 3)
            )
        } else if !significant {
            format!(
                "c = {} ± {}: not distinguishable from 0",
                sig(c, 3),
                sig(std_error, 2)
            )
        } else if !better {
            format!(
                "it lowers the training RMS error from {} % to {} % of span only (less than \
                 {} % of it)",
                sig(without, 3),
                sig(with.rms_pct_span, 3),
                sig(100.0 * MIN_IMPROVEMENT, 2)
            )
        } else {
            format!(
                "c = {} lowers the training RMS error from {} % to {} % of span",
                sig(c, 3),
                sig(without, 3),
                sig(with.rms_pct_span, 3)
            )
        };
        RateFinding {
            c,
            std_error,
            rms_without: without,
            rms_with: with.rms_pct_span,
            supported: better && significant,
            reason,
        }
    }
}

impl TimedFindings {
    /// The standard errors the findings report, from `estimates` (the fit's full ones), in
    /// place of those the decisions looked at.
    pub fn report_errors(&mut self, estimates: &[Estimate]) {
        let error = |name: &str| {
            estimates
                .iter()
                .find(|e| e.name == name)
                .map(|e| e.std_error)
        };
        for c in &mut self.coefficients {
            if let Some(s) = error(&c.name) {
                c.std_error = s;
            }
        }
        if let Some(r) = self.rate.as_mut() {
            if let Some(s) = error(RATE_C) {
                r.std_error = s;
            }
        }
    }

    /// The findings of a timed fit: `rms_by_order` its nested fits' training errors (order 0
    /// … n, without the rate term), `estimates` the full fit's parameters, `with_rate` its
    /// training error with the rate term (when one was asked for).
    #[must_use]
    pub fn new(
        data: &Dataset,
        rms_by_order: Vec<f64>,
        estimates: &[Estimate],
        with_rate: Option<ErrorStats>,
    ) -> Self {
        let n = rms_by_order.len().saturating_sub(1);
        let shortest = data
            .records
            .iter()
            .filter_map(|r| r.period.as_ref().map(hyst_model::TimeSteps::nominal))
            .fold(f64::INFINITY, f64::min);
        let shortest = if shortest.is_finite() { shortest } else { 0.0 };
        let coefficients = (1..=n)
            .map(|i| {
                let name = dynamics_name(i);
                let e = estimates.iter().find(|e| e.name == name);
                let (value, std_error) = e.map_or((f64::NAN, f64::NAN), |e| (e.value, e.std_error));
                let (before, after) = (rms_by_order[i - 1], rms_by_order[i]);
                let better = after <= (1.0 - MIN_IMPROVEMENT) * before;
                let precise = std_error.is_finite() && std_error <= MAX_RELATIVE_ERROR * value;
                let scale = value.powf(1.0 / i as f64);
                let at_limit = scale.is_nan() || scale < LIMIT_PERIODS * shortest;
                let reason = if at_limit {
                    format!(
                        "a_{i} = {} is at its limit a_{i} → 0 (its time scale {} s is below {} % \
                         of the sample period): the order adds nothing the samples can see",
                        sig(value, 3),
                        sig(scale, 3),
                        sig(100.0 * LIMIT_PERIODS, 2)
                    )
                } else if !better {
                    format!(
                        "order {i} fits no better than order {} (training RMS {} % against {} % \
                         of span): the records do not excite the plant where a_{i} acts; record at \
                         rates nearer 1/τ",
                        i - 1,
                        sig(after, 3),
                        sig(before, 3)
                    )
                } else if !precise {
                    format!(
                        "its standard error is {} of its value: the records do not pin it down",
                        if std_error.is_finite() {
                            format!("{} %", sig(100.0 * std_error / value, 2))
                        } else {
                            "not finite".into()
                        }
                    )
                } else {
                    String::new()
                };
                Coefficient {
                    name,
                    value,
                    std_error,
                    identified: reason.is_empty(),
                    reason,
                }
            })
            .collect();
        let without = rms_by_order.last().copied().unwrap_or(f64::NAN);
        let rate = with_rate.map(|with| RateFinding::new(estimates, without, with));
        let periods = data
            .records
            .iter()
            .filter_map(|r| r.period.as_ref().map(hyst_model::TimeSteps::nominal))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| {
                (lo.min(h), hi.max(h))
            });
        Self {
            rms_by_order,
            coefficients,
            rate,
            periods,
            nesting: Vec::new(),
        }
    }

    /// The model file's `[dynamics]` section of `model`, with the standard errors and whether
    /// each a_i is identified.
    #[must_use]
    pub fn dynamics_section(&self, model: &SmoothModel) -> Option<DynamicsSection> {
        let d = model.dynamics?;
        Some(DynamicsSection {
            b: d.b,
            a: d.a().to_vec(),
            a_std_error: self.coefficients.iter().map(|c| c.std_error).collect(),
            identified: self.coefficients.iter().map(|c| c.identified).collect(),
            hold: d.hold().recorded(),
        })
    }

    /// The model file's `[rate]` section of `model`.
    #[must_use]
    pub fn rate_section(&self, model: &SmoothModel) -> Option<RateSection> {
        let r = model.rate?;
        Some(RateSection {
            c: r.c,
            c_std_error: self.rate.as_ref().map_or(f64::NAN, |f| f.std_error),
        })
    }

    /// The report's lines on the plant and the rate term, and on what the family widths cover.
    #[must_use]
    pub fn notes(&self) -> Vec<String> {
        let mut notes = Vec::new();
        if !self.coefficients.is_empty() {
            let orders: Vec<String> = self
                .rms_by_order
                .iter()
                .enumerate()
                .map(|(i, r)| format!("order {i}: {} %", sig(*r, 3)))
                .collect();
            notes.push(format!(
                "plant before the hysteresis, a_n v⁽ⁿ⁾ + … + a_1 v̇ + v = u (b = 1: ψ_in's gain \
                 holds the plant gain), exact for the command's hold over steps of nominal \
                 length {} to {} s; training RMS error by order ({})",
                sig(self.periods.0, 3),
                sig(self.periods.1, 3),
                orders.join(", ")
            ));
            for c in &self.coefficients {
                notes.push(if c.identified {
                    let power = &c.name["dynamics.a".len()..];
                    format!(
                        "{} = {} ± {} s{}",
                        c.name,
                        sig(c.value, 4),
                        sig(c.std_error, 2),
                        if power == "1" {
                            String::new()
                        } else {
                            format!("^{power}")
                        }
                    )
                } else {
                    format!("{} not identified: {}", c.name, c.reason)
                });
            }
            notes.push(
                "the family widths and the bound Δa cover the hysteresis part for the fitted \
                 plant (and rate term): they do not cover errors in a_i or c"
                    .into(),
            );
        }
        if !self.nesting.is_empty() {
            let rows: Vec<String> = self
                .nesting
                .iter()
                .map(|n| {
                    format!(
                        "{} ({} parameters) {} %",
                        n.structure,
                        n.parameters,
                        sig(n.rms_pct_span, 4)
                    )
                })
                .collect();
            notes.push(format!(
                "nesting, training RMS error of each structure fitted (% of span; a richer \
                 structure is started from each it contains and never ends above it): {}",
                rows.join("; ")
            ));
        }
        if let Some(r) = &self.rate {
            notes.push(if r.supported {
                format!("rate term supported: {}", r.reason)
            } else {
                format!(
                    "rate term not supported by the data, left out of the model: {}",
                    r.reason
                )
            });
        }
        notes
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use hyst_model::RateTerm;

    #[test]
    fn nesting_removes_the_rate_term_then_one_order_at_a_time() {
        let s = Structure {
            dynamics: 2,
            rate: Some(RateTerm::Viscous),
            ..Structure::default()
        };
        let a = simpler_timed(s).unwrap();
        assert_eq!((a.dynamics, a.rate), (2, None));
        let b = simpler_timed(a).unwrap();
        assert_eq!(b.dynamics, 1);
        let c = simpler_timed(b).unwrap();
        assert!(!is_timed(c));
        assert!(simpler_timed(c).is_none());
    }

    fn estimate(name: &str, value: f64, std_error: f64) -> Estimate {
        Estimate {
            name: name.into(),
            value,
            std_error,
            unit: String::new(),
        }
    }

    #[test]
    fn a_coefficient_is_identified_only_when_it_helps_and_is_precise() {
        let data = Dataset::single(&[0.0, 1.0], &[0.0, 1.0]);
        let estimates = [
            estimate("dynamics.a1", 0.1, 0.001),
            estimate("dynamics.a2", 1e-6, 1e-5),
        ];
        let f = TimedFindings::new(&data, vec![5.0, 1.0, 0.999], &estimates, None);
        assert!(f.coefficients[0].identified);
        assert!(!f.coefficients[1].identified);
        assert!(f.coefficients[1].reason.contains("no better"), "{:?}", f);
        let f = TimedFindings::new(&data, vec![5.0, 1.0, 0.5], &estimates, None);
        assert!(
            f.coefficients[1].reason.contains("standard error"),
            "{:?}",
            f
        );
    }

    #[test]
    fn a_rate_term_that_does_not_help_is_not_supported() {
        let data = Dataset::single(&[0.0, 1.0], &[0.0, 1.0]);
        let with = |rms| ErrorStats {
            rms_pct_span: rms,
            ..ErrorStats::default()
        };
        let f = TimedFindings::new(
            &data,
            vec![5.0],
            &[estimate(RATE_C, 0.2, 0.01)],
            Some(with(4.99)),
        );
        assert!(!f.rate.as_ref().unwrap().supported);
        let f = TimedFindings::new(
            &data,
            vec![5.0],
            &[estimate(RATE_C, 0.2, 0.01)],
            Some(with(3.0)),
        );
        assert!(f.rate.as_ref().unwrap().supported);
        let f = TimedFindings::new(
            &data,
            vec![5.0],
            &[estimate(RATE_C, -0.2, 0.01)],
            Some(with(3.0)),
        );
        assert!(!f.rate.as_ref().unwrap().supported);
    }
}
