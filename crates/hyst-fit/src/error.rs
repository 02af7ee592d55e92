//! The error type of identification.

use std::path::PathBuf;

use hyst_io::number::{shortest, sig};
use hyst_model::ModelError;

/// Everything that can go wrong while preparing data, fitting, or reading a model file. Messages
/// name the file, the line and the column where there is one.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FitError {
    /// Reading the CSV failed: missing file, missing column, non-numeric or non-finite cell
    /// (the message names file, line and column).
    #[error(transparent)]
    Io(#[from] hyst_io::IoError),

    /// The input column does not vary, so no hysteresis can be identified from it.
    #[error(
        "{file}: column {column:?} (the input) is constant ({value}) over all {samples} \
         training samples: a hysteresis model needs an input that moves"
    )]
    ConstantInput {
        /// The data file.
        file: String,
        /// The input column.
        column: String,
        /// Its only value.
        value: f64,
        /// How many samples were looked at.
        samples: usize,
    },

    /// The output column does not vary: there is nothing to fit.
    #[error(
        "{file}: column {column:?} (the output) is constant ({value}) over all {samples} \
         training samples: a hysteresis model needs an output that moves"
    )]
    ConstantOutput {
        /// The data file.
        file: String,
        /// The output column.
        column: String,
        /// Its only value.
        value: f64,
        /// How many samples were looked at.
        samples: usize,
    },

    /// A column's span is too small for the fit: squared residuals and their sums underflow
    /// (data in units where values are near 1e-300).
    #[error(
        "{file}: column {column:?} spans only {span:e} (from {min:e} to {max:e}): too small for \
         the fit (the span must be at least {limit:e}, or squared residuals underflow): rescale \
         the column (other units)"
    )]
    SpanTooSmall {
        /// The data file.
        file: String,
        /// The column name.
        column: String,
        /// Its span (max − min).
        span: f64,
        /// Its smallest value.
        min: f64,
        /// Its largest value.
        max: f64,
        /// The smallest span accepted ([`crate::data::MIN_SPAN`]).
        limit: f64,
    },

    /// Fewer training samples than free parameters.
    #[error(
        "{file}: {samples} training samples but the model has {parameters} free parameters: \
         the fit needs more samples than parameters"
    )]
    TooFewSamples {
        /// The data file.
        file: String,
        /// Training samples.
        samples: usize,
        /// Free parameters of the chosen structure.
        parameters: usize,
    },

    /// A weight is negative (weights must be ≥ 0, and not all 0).
    #[error("{file}:{line}: column {column:?}: weight {value} is negative (weights must be >= 0)")]
    NegativeWeight {
        /// The data file.
        file: String,
        /// The 1-based line.
        line: usize,
        /// The weight column.
        column: String,
        /// The weight.
        value: f64,
    },

    /// A time stamp that is repeated, decreasing or off the record's even spacing (a model
    /// with dynamics or a rate term).
    #[error("{file}:{line}: column {column:?} (record {record}): {message}")]
    BadTime {
        /// The data file.
        file: String,
        /// The 1-based line.
        line: usize,
        /// The time column.
        column: String,
        /// The record id.
        record: i64,
        /// What is wrong with the stamp.
        message: String,
    },

    /// The record id is not an integer, or beyond the integers a float holds exactly
    /// (`limit`, [`crate::data::MAX_RECORD_ID`]).
    #[error("{file}:{line}: column {column:?}: record id {}", record_id_problem(*value, *limit))]
    BadRecordId {
        /// The data file.
        file: String,
        /// The 1-based line.
        line: usize,
        /// The record column.
        column: String,
        /// The value.
        value: f64,
        /// The largest magnitude of a record id.
        limit: f64,
    },

    /// The options ask for something that cannot be done with this data (an unknown validation
    /// record, all records held out, a bad coverage, …).
    #[error("{0}")]
    Invalid(String),

    /// A setting or argument of a method is out of its range (a tolerance or iteration limit of
    /// the least-squares method, its starting point, the number of play operators, …).
    #[error("{name} = {value}: expected {expected}")]
    InvalidSetting {
        /// The setting, as the library names it.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The range it must lie in.
        expected: String,
    },

    /// The output falls while the input rises: the model's maps are increasing.
    #[error(
        "{file}: the output column {column:?} decreases when the input increases; the model \
         (increasing shaping, counter-clockwise loops) needs an increasing map: negate the output \
         (a clockwise loop, such as friction against position, takes the stop form: --form stop)"
    )]
    DecreasingOutput {
        /// The data file.
        file: String,
        /// The output column.
        column: String,
    },

    /// The core refused a value (an invalid parameter in a model file, a non-monotone shaping,
    /// a desired output beyond a saturating shaping). The message includes the core's, so the
    /// core error is not also this error's `source()`: a report that prints an error and its
    /// sources would otherwise say it twice ("… of the tanh shaping function: … of the tanh
    /// shaping function").
    #[error("model: {0}")]
    Core(hyst_core::Error),

    /// A model file could not be read or understood.
    #[error("{}: {message}", path.display())]
    ModelFile {
        /// The model file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },

    /// No start of the optimiser produced a finite cost.
    #[error("the fit failed: {0}")]
    NoConvergence(String),

    /// A data value is too large in magnitude for the fit: squares and sums of residuals would
    /// overflow (e.g. data in units where values reach 1e300, or a 1e308 outlier).
    #[error(
        "{file}:{line}: column {column:?}: {value:e} is too large for the fit (|value| must be \
         at most {limit:e}, or squared residuals overflow): rescale the column (other units) or \
         remove the outlier"
    )]
    ValueTooLarge {
        /// The data file.
        file: String,
        /// The 1-based line of the value.
        line: usize,
        /// The column name.
        column: String,
        /// The value.
        value: f64,
        /// The largest magnitude accepted ([`crate::data::MAX_MAGNITUDE`]).
        limit: f64,
    },

    /// The fit ended with a non-finite error statistic or parameter: the data cannot be
    /// described by a finite model at this scale.
    #[error(
        "{file}: the fit gave {what} = {value}: not a finite number (badly scaled data or \
         outliers); no model file was written"
    )]
    NonFiniteResult {
        /// The data file.
        file: String,
        /// Which number, e.g. "the training RMS" or "parameter k1".
        what: String,
        /// The value (NaN or infinite).
        value: f64,
    },

    /// The fit found no hysteresis: the model collapsed to a curve without loops, or its
    /// parameters are not identified by the data. Nothing was written.
    #[error("{0}")]
    Degenerate(String),

    /// The user interrupted the fit (Ctrl-C); nothing was written.
    #[error("interrupted: no model file was written")]
    Interrupted,
}

impl From<hyst_core::Error> for FitError {
    fn from(e: hyst_core::Error) -> Self {
        FitError::Core(e)
    }
}

/// A model runtime error as the fit's: the same variant for the same fault (a core refusal, a
/// model file, an invalid request, a write), so every message reads as before.
impl From<ModelError> for FitError {
    fn from(e: ModelError) -> Self {
        match e {
            ModelError::Core(e) => FitError::Core(e),
            ModelError::File { path, message } => FitError::ModelFile { path, message },
            ModelError::Invalid(message) => FitError::Invalid(message),
            other => FitError::Invalid(other.to_string()),
        }
    }
}

/// What is wrong with a record id: beyond the range (printed with significant digits, not as
/// its 301 digits) or not an integer (printed with all its digits, so the fraction shows).
fn record_id_problem(value: f64, limit: f64) -> String {
    if value.is_finite() && value.abs() > limit {
        format!(
            "{} is beyond the range of record ids (integers within ±{}, which a float holds \
             exactly)",
            sig(value, 4),
            sig(limit, 2)
        )
    } else {
        format!("{} is not an integer", shortest(value))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An error and its sources on one line, as a report that follows `source()` prints them.
    fn chain(e: &dyn std::error::Error) -> String {
        let mut line = e.to_string();
        let mut next = e.source();
        while let Some(cause) = next {
            line = format!("{line}: {cause}");
            next = cause.source();
        }
        line
    }

    #[test]
    fn a_core_error_is_said_once() {
        let e = FitError::from(hyst_core::Error::OutOfRange {
            name: "tanh",
            value: 2.0,
            min: -1.0,
            max: 1.0,
        });
        assert_eq!(
            chain(&e),
            "model: 2 is outside the range (-1, 1) of the tanh shaping function"
        );
    }

    #[test]
    fn a_record_id_beyond_the_range_is_said_so_with_significant_digits() {
        let bad = |value| FitError::BadRecordId {
            file: "r.csv".into(),
            line: 7,
            column: "record".into(),
            value,
            limit: crate::data::MAX_RECORD_ID,
        };
        assert_eq!(
            bad(1e300).to_string(),
            "r.csv:7: column \"record\": record id 1.000e300 is beyond the range of record ids \
             (integers within ±9.0e15, which a float holds exactly)"
        );
        assert_eq!(
            bad(-2.5).to_string(),
            "r.csv:7: column \"record\": record id -2.5 is not an integer"
        );
    }
}
