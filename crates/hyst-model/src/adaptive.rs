//! A model file's side of online adaptation (`hyst_core::adaptive`): which models the estimator
//! can follow, the defaults it takes from the file (noise, input range), the estimator started
//! at a record's first command, and the model file of the adapted parameters. `hyst adapt` and
//! Python's `hyst.Adaptive` both go through here.

use hyst_core::adaptive::{Adaptive, AdaptiveConfig, AdaptiveModel};
use hyst_core::{Hysteresis, ShapedModel};

use crate::error::ModelError;
use crate::file::{ModelFile, ModelKind};
use crate::smooth::SmoothModel;

/// The smooth model of `file` if the estimator can follow it: a smooth model of the operator
/// form without dynamics or a rate term.
///
/// # Errors
/// [`ModelError::Invalid`] saying why not and what to fit instead.
pub fn adaptable(file: &ModelFile) -> Result<&SmoothModel, ModelError> {
    let Some(smooth) = file
        .smooth
        .as_ref()
        .filter(|_| file.kind == ModelKind::Smooth)
    else {
        return Err(ModelError::Invalid(
            "a Prandtl-Ishlinskii model: adaptation follows the parameters of a smooth model \
             (fit one with the default model kind, smooth)"
                .into(),
        ));
    };
    file.untimed("adaptation, which follows a static model's parameters (fit one without dynamics or a rate term)")?;
    if !smooth.form.is_operator() {
        return Err(ModelError::Invalid(
            "a stop-form (friction) model: adaptation follows a model of the operator form".into(),
        ));
    }
    Ok(smooth)
}

/// The measurement noise σ the file suggests: its training RMS (output units), if it has one.
#[must_use]
pub fn training_noise(file: &ModelFile) -> Option<f64> {
    let rms = file.metrics.training.rms;
    (rms > 0.0 && rms.is_finite()).then_some(rms)
}

/// The commands the estimator learns from by default: for a fitted model, the input range it
/// was fitted on ([`SmoothModel::fitted_input_interval`]) widened by 10 % of its span on each side;
/// the whole line for a model that was not fitted (no data rows in its provenance).
#[must_use]
pub fn fitted_input_range(file: &ModelFile, smooth: &SmoothModel) -> (f64, f64) {
    let whole = (f64::NEG_INFINITY, f64::INFINITY);
    if file.provenance.rows == 0 {
        return whole;
    }
    let (lo, hi) = smooth.fitted_input_interval();
    let margin = 0.1 * (hi - lo);
    if lo.is_finite() && hi.is_finite() && lo < hi {
        (lo - margin, hi + margin)
    } else {
        whole
    }
}

/// The estimator of `smooth`'s parameters, with no history: at its first sample (a command
/// given to [`Adaptive::update`], or a desired output given to a compensator's `command`) the
/// model starts by its start rule there, as `hyst run` starts it.
///
/// # Errors
/// [`ModelError::Core`] for invalid parameters or a bad setting.
pub fn estimator(
    smooth: &SmoothModel,
    config: AdaptiveConfig<f64>,
) -> Result<Adaptive<f64>, ModelError> {
    let operator = Hysteresis::with_k2_law(smooth.k1, smooth.k2)?;
    let model = ShapedModel::new(smooth.input_shaping, operator, smooth.output_shaping)?;
    Ok(Adaptive::new(&model, smooth.initial_state, config)?)
}

/// `file` with the parameters of `adapted` (k1, the k2 law, both shaping functions): a model
/// file `hyst run`, `hyst export` and the bindings use as any other. In its `parameters`
/// table, each value that is one of the model's numbers ([`table_value`]: k1, k2, k2.slope, an
/// unsaturated output's out.gain and out.offset) becomes the adapted number the model computes
/// with; the standard errors and metrics (`[metrics]`) stay the fit's, and its provenance's
/// command says what adapted it.
#[must_use]
pub fn adapted_file(file: &ModelFile, adapted: &AdaptiveModel<f64>, command: &str) -> ModelFile {
    let mut out = file.clone();
    if let Some(m) = out.smooth.as_mut() {
        m.k1 = adapted.operator().k1();
        m.k2 = *adapted.operator().k2_law();
        m.input_shaping = *adapted.input_shaping();
        m.output_shaping = *adapted.output_shaping();
    }
    if let (Some(before), Some(after)) = (file.smooth.as_ref(), out.smooth) {
        for e in &mut out.parameters {
            // Only where the table held the fitted model's own number (bit for bit): a name
            // that is not one of them keeps the fit's value.
            if let (Some(was), Some(now)) =
                (table_value(before, &e.name), table_value(&after, &e.name))
            {
                if was.to_bits() == e.value.to_bits() {
                    e.value = now;
                }
            }
        }
    }
    out.provenance.command = format!("{command} (adapted from: {})", file.provenance.command);
    out
}

/// The number of `m` that the parameters table's entry `name` holds, for the entries that are
/// one of the model's own numbers: `k1`; `k2` (a constant law's value, an affine law's φ(0)) and
/// `k2.slope` (an affine law's dφ/dv); `out.gain` and `out.offset`, the gain and offset after
/// an unsaturated ψ_out of the operator form. `None` for the others (normalised or derived
/// quantities, such as a saturating shaping's scale).
#[must_use]
pub fn table_value(m: &SmoothModel, name: &str) -> Option<f64> {
    let unsaturated = m.form.is_operator()
        && !matches!(
            m.output_shaping.shape,
            hyst_core::AnyShaping::Tanh(_) | hyst_core::AnyShaping::Langevin(_)
        );
    match name {
        "k1" => Some(m.k1),
        "k2" => Some(m.k2.at_zero()),
        "k2.slope" => match m.k2 {
            hyst_core::AnyK2Law::Affine(law) => Some(law.slope),
            hyst_core::AnyK2Law::Constant { .. } => None,
        },
        "out.gain" if unsaturated => Some(m.output_shaping.post_gain),
        "out.offset" if unsaturated => Some(m.output_shaping.post_offset),
        _ => None,
    }
}
