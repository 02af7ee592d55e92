//! Error statistics of a fitted model on the training and validation records, and the check
//! that a fit's numbers are finite.

use hyst_model::{ErrorStats, ErrorSums, SmoothModel};

use crate::data::Dataset;
use crate::error::FitError;
use crate::outputs::{ModelOutputs, Outputs};

/// The output of `model` on every record of `data` (record order), held: the replay of
/// [`ModelOutputs`] collected (each history from its estimated start `starts` or the start rule,
/// at its sample period). `None` when the model cannot run a record.
#[must_use]
pub fn run_records(
    data: &Dataset,
    model: &SmoothModel,
    starts: Option<&[f64]>,
) -> Option<Vec<Vec<f64>>> {
    let mut out: Vec<Vec<f64>> = data
        .records
        .iter()
        .map(|r| Vec::with_capacity(r.len()))
        .collect();
    let outputs = ModelOutputs {
        data,
        model,
        starts,
    };
    let ran = outputs.replay(&mut |i, _, y| {
        if let Some(record) = out.get_mut(i) {
            record.push(y);
        }
    });
    ran.then_some(out)
}

/// Training and validation error statistics of any model (`run` maps a record's input to its
/// output, `None` when the model cannot run it).
///
/// # Errors
/// [`FitError::NoConvergence`] when the model cannot run a record.
pub fn error_stats(
    data: &Dataset,
    run: impl Fn(&[f64]) -> Option<Vec<f64>>,
) -> Result<(ErrorStats, Option<ErrorStats>), FitError> {
    let outputs = data
        .run_histories(run)
        .ok_or_else(|| FitError::NoConvergence("the fitted model cannot run the records".into()))?;
    error_stats_of(data, &outputs)
}

/// Training and validation error statistics of the model `outputs`, in one replay (no error is
/// held).
///
/// # Errors
/// [`FitError::NoConvergence`] when the model cannot run a record.
pub fn error_stats_of(
    data: &Dataset,
    outputs: &dyn Outputs,
) -> Result<(ErrorStats, Option<ErrorStats>), FitError> {
    let (lo, hi) = data.output_range();
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let (mut training, mut validation) = (ErrorSums::default(), ErrorSums::default());
    let ran = outputs.replay(&mut |i, j, m| {
        let Some(r) = data.records.get(i) else {
            return;
        };
        if let (Some(o), Some(w)) = (r.output.get(j), r.weight.get(j)) {
            if w > 0.0 {
                let sums = if r.validation {
                    &mut validation
                } else {
                    &mut training
                };
                sums.add(m - o);
            }
        }
    });
    if !ran {
        return Err(FitError::NoConvergence(
            "the fitted model cannot run the records".into(),
        ));
    }
    let validation = (validation.samples() > 0).then(|| validation.stats(span));
    Ok((training.stats(span), validation))
}

/// Refuses a fit whose error statistics or parameter values are not finite
/// ([`FitError::NonFiniteResult`]). Standard errors may be NaN (a parameter the data does not
/// identify) and are not checked.
///
/// # Errors
/// [`FitError::NonFiniteResult`] naming the first non-finite number.
pub fn check_finite<'a>(
    file: &str,
    training: &ErrorStats,
    validation: Option<&ErrorStats>,
    parameters: impl IntoIterator<Item = (&'a str, f64)>,
) -> Result<(), FitError> {
    let stats = [("training", Some(training)), ("validation", validation)];
    let mut numbers: Vec<(String, f64)> = Vec::new();
    for (set, s) in stats {
        if let Some(s) = s {
            numbers.push((format!("the {set} RMS"), s.rms));
            numbers.push((format!("the {set} max error"), s.max_abs));
        }
    }
    numbers.extend(
        parameters
            .into_iter()
            .map(|(name, v)| (format!("parameter {name}"), v)),
    );
    match numbers.into_iter().find(|(_, v)| !v.is_finite()) {
        Some((what, value)) => Err(FitError::NonFiniteResult {
            file: file.to_string(),
            what,
            value,
        }),
        None => Ok(()),
    }
}
