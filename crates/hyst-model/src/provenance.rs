//! What a model file records beside the model: the data's columns, units and provenance, the
//! fitted parameters with their standard errors, and the fit's error statistics and metrics.

use serde::{Deserialize, Serialize};

/// Which columns hold what, and where the data came from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct Columns {
    /// Input column name.
    pub input: String,
    /// Output column name.
    pub output: String,
    /// Record column name, if the file is segmented.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub record: Option<String>,
    /// Weight column name, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weight: Option<String>,
    /// Time column name (s), for a model with dynamics or a rate term.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<String>,
}

/// Units of the data columns (free text, e.g. "V", "um").
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct Units {
    /// Input units.
    pub input: String,
    /// Output units.
    pub output: String,
}

/// Fit metrics.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct Metrics {
    /// Number of free parameters.
    pub parameters: usize,
    /// Errors on the training records.
    pub training: ErrorStats,
    /// Errors on the validation records.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub validation: Option<ErrorStats>,
    /// Wall time of the fit (s).
    pub fit_seconds: f64,
    /// Time to evaluate the model, ns per sample (measured after the fit).
    pub ns_per_sample: f64,
}

/// Where the data came from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct Provenance {
    /// The data file as given on the command line.
    pub file: String,
    /// Its size in bytes.
    pub bytes: u64,
    /// FNV-1a 64-bit hash of its bytes (hex), to recognise the exact file.
    pub fnv1a64: String,
    /// Data rows read.
    pub rows: usize,
    /// Number of records.
    pub records: usize,
    /// Record ids held out for validation.
    #[serde(default)]
    pub validation_records: Vec<i64>,
    /// The command that made the file.
    pub command: String,
    /// hyst version.
    pub hyst_version: String,
    /// Creation time, seconds since the Unix epoch.
    pub created_unix: u64,
    /// The smallest and largest nominal sample period (s) of the records a model with
    /// dynamics or a rate term was fitted on (absent for a static fit, and in files written
    /// before it was recorded): a record run at a period far from them ([`PERIOD_FACTOR`]) is
    /// noted ([`Provenance::period_note`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sample_periods: Option<[f64; 2]>,
}

/// How far (a factor either way) a record's sample period may be from the periods a model was
/// fitted at before [`Provenance::period_note`] notes it: a time column in milliseconds read as
/// seconds is 1000 × off; sampling 10 × faster or slower than the fit is ordinary.
pub const PERIOD_FACTOR: f64 = 100.0;

impl Provenance {
    /// Checks `sample_periods`: finite, positive, the smallest first.
    ///
    /// # Errors
    /// What is wrong, naming the key and the values.
    pub fn check(&self) -> Result<(), String> {
        match self.sample_periods {
            Some([lo, hi]) if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo <= hi) => {
                Err(format!(
                    "[provenance] sample_periods = [{lo:e}, {hi:e}]: expected the smallest and \
                     the largest sample period (s) of the records, finite and positive, the \
                     smallest first"
                ))
            }
            _ => Ok(()),
        }
    }

    /// A note for a record run at the sample period `period` (s) more than [`PERIOD_FACTOR`]
    /// away from the periods the model was fitted at (the plant's and the rate term's
    /// discretisation are in seconds: a record in other units runs without error, and wrong);
    /// `None` within them, or when the file records none.
    #[must_use]
    pub fn period_note(&self, period: f64) -> Option<String> {
        let [lo, hi] = self.sample_periods?;
        if !(period < lo / PERIOD_FACTOR || period > hi * PERIOD_FACTOR) {
            return None;
        }
        let fitted = if lo == hi {
            format!("{lo:.3e} s")
        } else {
            format!("{lo:.3e} to {hi:.3e} s")
        };
        let ratio = if period > hi {
            period / hi
        } else {
            lo / period
        };
        Some(format!(
            "the record's sample period {period:.3e} s is {ratio:.0} × {} the period the model was \
             fitted at ({fitted}): is the time column in seconds?",
            if period > hi { "longer than" } else { "shorter than" }
        ))
    }
}

/// A fitted parameter with its standard error.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// Name ("k1", "out.gain", …).
    pub name: String,
    /// Value.
    pub value: f64,
    /// Standard error from the covariance σ² (JᵀJ)⁻¹ (NaN when the parameter is not
    /// identifiable from the data). Assumes independent residuals: correlated measurement
    /// noise makes it optimistic.
    pub std_error: f64,
    /// Units.
    pub unit: String,
}

/// Error statistics of a model on a set of records.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct ErrorStats {
    /// Samples used (weight > 0).
    pub samples: usize,
    /// Root mean square error (output units).
    pub rms: f64,
    /// Largest absolute error (output units).
    pub max_abs: f64,
    /// RMS as % of the output span of the whole dataset.
    pub rms_pct_span: f64,
    /// Max error as % of the output span.
    pub max_pct_span: f64,
}

impl ErrorStats {
    /// Statistics of `errors` against an output span.
    #[must_use]
    pub fn new(errors: &[f64], span: f64) -> Self {
        Self::of(errors.iter().copied(), span)
    }

    /// Statistics of the `errors` an iterator gives, in one pass and constant memory (the
    /// same numbers, bit for bit, as [`ErrorStats::new`] of them collected).
    #[must_use]
    pub fn of(errors: impl IntoIterator<Item = f64>, span: f64) -> Self {
        let mut sums = ErrorSums::default();
        errors.into_iter().for_each(|e| sums.add(e));
        sums.stats(span)
    }
}

/// [`ErrorStats`] gathered one error at a time, in constant memory: [`ErrorSums::add`] each
/// error, then [`ErrorSums::stats`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorSums {
    /// Errors added.
    samples: usize,
    /// Their sum of squares, in the order added (output units²).
    squares: f64,
    /// The largest magnitude (output units).
    max_abs: f64,
}

impl ErrorSums {
    /// Adds one error (output units).
    pub fn add(&mut self, error: f64) {
        self.samples += 1;
        self.squares += error * error;
        self.max_abs = self.max_abs.max(error.abs());
    }

    /// The errors added so far.
    #[must_use]
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// The statistics of the errors added, against an output span (none added: the default).
    #[must_use]
    pub fn stats(&self, span: f64) -> ErrorStats {
        if self.samples == 0 {
            return ErrorStats::default();
        }
        let rms = (self.squares / self.samples as f64).sqrt();
        ErrorStats {
            samples: self.samples,
            rms,
            max_abs: self.max_abs,
            rms_pct_span: 100.0 * rms / span,
            max_pct_span: 100.0 * self.max_abs / span,
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::ErrorStats;

    /// The one-pass statistics are those of the errors collected, bit for bit (the fit's
    /// report must not move when it stops holding them), and none for no errors.
    #[test]
    fn statistics_in_one_pass_are_those_of_a_slice() {
        let errors: Vec<f64> = (0..1000)
            .map(|k| (f64::from(k) * 0.37).sin() * 1e-3 + 1e-7 * f64::from(k))
            .collect();
        let a = ErrorStats::of(errors.iter().copied(), 2.5);
        let folded = errors.iter().map(|e| e * e).sum::<f64>();
        assert_eq!(a.rms.to_bits(), (folded / 1000.0).sqrt().to_bits());
        assert_eq!(
            a.max_abs,
            errors.iter().fold(0.0_f64, |m, e| m.max(e.abs()))
        );
        assert_eq!(a, ErrorStats::new(&errors, 2.5));
        assert_eq!(a.samples, 1000);
        assert_eq!(
            ErrorStats::of(std::iter::empty(), 1.0),
            ErrorStats::default()
        );
    }
    #[test]
    fn sample_periods_are_checked_and_noted_100_times_away() {
        let mut p = super::Provenance {
            sample_periods: Some([1e-3, 2e-3]),
            ..super::Provenance::default()
        };
        assert!(p.check().is_ok());
        assert_eq!(p.period_note(1e-4), None);
        assert_eq!(p.period_note(0.1), None);
        assert!(p.period_note(0.3).unwrap().contains("150 × longer"));
        assert!(p.period_note(5e-6).unwrap().contains("200 × shorter"));
        for bad in [[2e-3, 1e-3], [0.0, 1.0], [f64::NAN, 1.0]] {
            p.sample_periods = Some(bad);
            assert!(p.check().unwrap_err().contains("sample_periods"));
        }
        p.sample_periods = None;
        assert_eq!(p.period_note(1e9), None);
    }
}
