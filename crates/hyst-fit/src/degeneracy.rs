//! Whether a fit found hysteresis at all. A least-squares fit on data its structure cannot
//! describe (a clockwise loop fitted by the operator form, say) does not fail: it slides to the
//! edge of the parameter space, where the model is a curve without loops and some parameters
//! are not identified (k1 → 0, k2 → 0, NaN standard errors). [`diagnose`] says so, with the
//! RMS of the straight line that does as well, so that the user is not handed a line as a
//! hysteresis model.

use serde::{Deserialize, Serialize};

use hyst_io::number::sig;
use hyst_model::Estimate;

use crate::data::Dataset;
use crate::layout::{IN_ARG_AT_CENTRE, IN_SCALE, OUT_ARG_AT_CENTRE, OUT_SCALE};
use crate::model_reading::ModelReading;
use crate::orientation::{loops, one_way, Orientation, MIN_GAP};
use crate::outputs::Outputs;

/// A model whose RMS error is above this fraction of the straight line's does no better than
/// a line.
pub const LINE_RATIO: f64 = 0.95;

/// A model whose loop is below this share of the data's, and no better than a line, is a line
/// in effect.
pub const LOOP_SHARE: f64 = 0.1;

/// The parameters of the hysteresis itself: when the data does not identify one of them, the
/// fit found no hysteresis.
pub const HYSTERESIS_PARAMETERS: [&str; 3] = ["k1", "k2", "k2.slope"];

/// The scales of the saturating shapings, whose standard error [`VAGUE`] times their value
/// gets a note.
pub const SCALE_PARAMETERS: [&str; 2] = [IN_SCALE, OUT_SCALE];

/// The arguments at the centre of the saturating shapings (dimensionless), whose standard
/// error above [`VAGUE`] gets a note.
pub const ARGUMENT_PARAMETERS: [&str; 2] = [IN_ARG_AT_CENTRE, OUT_ARG_AT_CENTRE];

/// A scale whose standard error is above this multiple of its value, or an argument whose
/// standard error is above this, is hardly identified.
pub const VAGUE: f64 = 10.0;

/// A model whose loop on the training inputs is at least this share of a loop the data visibly
/// has (a branch gap of at least [`MIN_GAP`]) has found that loop, however small both are.
pub const RESOLVED_SHARE: f64 = 0.5;

/// Samples per leg of the full sweep on which [`diagnose`] measures the model's own loop.
const SWEEP_SAMPLES: usize = 256;

/// What [`diagnose`] found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Diagnosis {
    /// The model has no loop, or parameters the data does not identify.
    pub degenerate: bool,
    /// The model has its loop, and only parameters of the hysteresis went unidentified (k2 at
    /// its bound, say): degenerate, but not "no hysteresis".
    pub found_loop: bool,
    /// One clause per finding ("the fitted model has no loop …"), then what the data's loops
    /// call for.
    pub reasons: Vec<String>,
    /// Findings that do not make the fit degenerate (shaping parameters the data does not
    /// identify).
    pub notes: Vec<String>,
    /// The gap between the model's own rising and falling branches on the training inputs
    /// (fraction of the output span; positive for clockwise).
    pub model_gap: f64,
    /// The same on a full sweep of the training input range (lowest → highest → lowest →
    /// highest, the first rise a burn-in): the model's own loop, whatever directions the data
    /// visits (first-order reversal curves, say, rise only). NaN if the model cannot run it.
    #[serde(default)]
    pub swept_gap: f64,
    /// RMS of the least-squares straight line output = a + b · input on the training data
    /// (output units).
    pub line_rms: f64,
    /// The share of the residuals' variance that a term proportional to the input's rate of
    /// change (the signed central difference) explains, in [0, 1]: rate-dependent behaviour
    /// (viscous friction, creep, eddy currents) that no rate-independent model represents.
    pub rate_share: f64,
    /// The share of the residuals' variance that a straight line in time (the sample index)
    /// within each training record explains beyond a line in the input, in [0, 1]: drift,
    /// creep or a temperature change, which no rate-independent model represents.
    #[serde(default)]
    pub drift_share: f64,
}

/// Above this [`Diagnosis::drift_share`], the report notes drift.
pub const DRIFT_NOTE: f64 = 0.1;

/// Above this [`Diagnosis::rate_share`], the report notes rate dependence.
pub const RATE_NOTE: f64 = 0.1;

impl Diagnosis {
    /// The one-line message: "no hysteresis found in FILE: …; a straight line fits with RMS …".
    #[must_use]
    pub fn message(&self, file: &str, unit: &str, span: f64) -> String {
        let unit = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        format!(
            "{} {file}: {}; a straight line fits with RMS {}{unit} ({} % of the output span)",
            if self.found_loop {
                "degenerate fit of"
            } else {
                "no hysteresis found in"
            },
            self.reasons.join("; "),
            sig(self.line_rms, 3),
            sig(100.0 * self.line_rms / span, 3),
        )
    }
}

/// The least-squares line a + b x over the weighted training samples, and its RMS over the
/// samples of positive weight.
fn line_rms(data: &Dataset) -> f64 {
    let (mut sw, mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for r in data.training() {
        for ((x, y), w) in r.input.iter().zip(&r.output).zip(&r.weight) {
            sw += w;
            sx += w * x;
            sy += w * y;
            sxx += w * x * x;
            sxy += w * x * y;
        }
    }
    let det = sw * sxx - sx * sx;
    let b = if det > 0.0 {
        (sw * sxy - sx * sy) / det
    } else {
        0.0
    };
    let a = (sy - b * sx) / sw;
    training_rms(data, |x, y| y - a - b * x)
}

/// The RMS of `residual(x, y)` over the training samples of positive weight.
fn training_rms(data: &Dataset, residual: impl Fn(f64, f64) -> f64) -> f64 {
    let (mut ss, mut n) = (0.0, 0usize);
    for r in data.training() {
        for ((x, y), w) in r.input.iter().zip(&r.output).zip(&r.weight) {
            if w > 0.0 {
                ss += residual(*x, *y).powi(2);
                n += 1;
            }
        }
    }
    (ss / n.max(1) as f64).sqrt()
}

/// The branch gap of `run`'s output on a full sweep of the training input range: lowest →
/// highest (a burn-in, weight 0) → lowest → highest, [`SWEEP_SAMPLES`] samples a leg, as a
/// fraction of the data's output span (positive for clockwise). `None` if the model cannot run
/// it or the range is a point.
fn swept_gap(data: &Dataset, run: &dyn Fn(&[f64]) -> Option<Vec<f64>>) -> Option<f64> {
    let (lo, hi) = data.input_range();
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let n = SWEEP_SAMPLES;
    let at = |i: usize| lo + (hi - lo) * (i as f64 / n as f64);
    let input: Vec<f64> = (0..=n)
        .map(at)
        .chain((0..n).rev().map(at))
        .chain((1..=n).map(at))
        .collect();
    let output = run(&input)?;
    if output.len() != input.len() || output.iter().any(|y| !y.is_finite()) {
        return None;
    }
    let mut sweep = Dataset::single(&input, &output);
    if let Some(r) = sweep.records.first_mut() {
        r.weight.fill(0..n, 0.0);
    }
    let (ylo, yhi) = data.output_range();
    let (slo, shi) = sweep.output_range();
    Some(loops(&sweep).gap * (shi - slo) / (yhi - ylo).max(f64::MIN_POSITIVE))
}

/// Diagnoses a fitted model from its output on the training records (`outputs`, replayed twice:
/// held, or the model run again) and its estimates
/// (`None` for models whose standard errors may be NaN by design, such as the
/// Prandtl–Ishlinskii weights at their bound 0). `run` runs the model on any input history (its
/// own loop is measured on a full sweep of the input range). `unidentified_ok` names parameters
/// whose NaN standard error is expected (k1 in the stop form's Dahl limit). `data_orientation`
/// and `used` (the orientation the fitted structure is made for: clockwise for the stop form)
/// word the advice.
#[must_use]
pub fn diagnose(
    data: &Dataset,
    outputs: &dyn Outputs,
    run: &dyn Fn(&[f64]) -> Option<Vec<f64>>,
    estimates: Option<&[Estimate]>,
    unidentified_ok: &[&str],
    data_orientation: Orientation,
    used: Orientation,
) -> Diagnosis {
    let model = ModelReading::of(data, outputs);
    let gap = model.gap;
    let data_gap = loops(data).gap;
    let swept = swept_gap(data, run).unwrap_or(f64::NAN);
    let mut reasons = Vec::new();
    reasons.extend(loop_reason(gap, data_gap, swept));
    let line = line_rms(data);
    if reasons.is_empty() {
        reasons.extend(line_reason(model.rms, line, gap, data_gap));
    }
    if reasons.is_empty() {
        reasons.extend(dependence_reason(model.rms, constant_rms(data)));
    }
    let mut notes = Vec::new();
    let mut found_loop = false;
    if let Some(estimates) = estimates {
        let (core, shaping) = (
            lost(estimates, unidentified_ok, true),
            lost(estimates, unidentified_ok, false),
        );
        if !core.is_empty() {
            found_loop = reasons.is_empty();
            reasons.push(format!(
                "the data does not identify {} (standard error NaN)",
                core.join(", ")
            ));
        }
        let vague_core = vague_loop(estimates, unidentified_ok);
        if !vague_core.is_empty() {
            found_loop = found_loop || reasons.is_empty();
            reasons.push(format!(
                "the data hardly identifies {} (a standard error above its value): the \
                 records are too short or too poor in reversals to place the loop; record more \
                 loops, or longer ones",
                vague_core.join(", ")
            ));
        }
        if !shaping.is_empty() {
            notes.push(format!(
                "the data does not identify {} (standard error NaN): the structure has a \
                 freedom the data does not show (a shaping that does not saturate on the data, \
                 say); a simpler structure fits as well and is better conditioned",
                shaping.join(", ")
            ));
        }
        notes.extend(vague_note(estimates));
    }
    if !reasons.is_empty() && !found_loop {
        reasons.push(advice(data, data_orientation, used, data_gap));
    }
    Diagnosis {
        degenerate: !reasons.is_empty(),
        found_loop,
        reasons,
        notes,
        model_gap: gap,
        swept_gap: swept,
        line_rms: line,
        rate_share: model.rate_share,
        drift_share: model.drift_share,
    }
}

/// The reason a model with the branch gaps `gap` (on the training inputs) and `swept` (on a
/// full sweep, NaN if unknown) found no hysteresis in data of branch gap `data_gap`: its loops
/// run the other way, or it has none. The model has a loop if it shows one on a full sweep, or
/// reproduces most of a loop the data visibly has (a small loop, near the threshold, both in
/// model and data).
fn loop_reason(gap: f64, data_gap: f64, swept: f64) -> Option<String> {
    let has_loop = swept.abs() >= MIN_GAP
        || gap.abs() >= MIN_GAP
        || (data_gap.abs() >= MIN_GAP
            && gap * data_gap > 0.0
            && gap.abs() >= RESOLVED_SHARE * data_gap.abs());
    if gap.abs() >= MIN_GAP && data_gap.abs() >= MIN_GAP && gap * data_gap < 0.0 {
        Some(format!(
            "the fitted model's loops run {} and the data's {} (branch gaps {} % and {} % of \
             the output span): the structure cannot describe the data",
            if gap > 0.0 {
                "clockwise"
            } else {
                "counterclockwise"
            },
            if data_gap > 0.0 {
                "clockwise"
            } else {
                "counterclockwise"
            },
            sig(100.0 * gap, 2),
            sig(100.0 * data_gap, 2),
        ))
    } else if !has_loop {
        Some(format!(
            "the fitted model has no loop (its rising and falling branches are {} % of the \
             output span apart on a full sweep of the input range, below {} %)",
            sig(100.0 * if swept.is_nan() { gap } else { swept }.abs(), 2),
            100.0 * MIN_GAP,
        ))
    } else {
        None
    }
}

/// The model's RMS at or above this fraction of the RMS of the output about its mean (the
/// model explains 5 % of the output's variance or less): the output does not follow the input.
/// Pure noise gives 0.03–0.2 %; every bundled record explains over 90 %.
const DEPENDENCE_RATIO: f64 = 0.975;

/// The RMS of the training outputs about their weighted mean (what a constant output fits).
fn constant_rms(data: &Dataset) -> f64 {
    let (mut sw, mut sy) = (0.0, 0.0);
    for r in data.training() {
        for (y, w) in r.output.iter().zip(&r.weight) {
            sw += w;
            sy += w * y;
        }
    }
    if sw.is_nan() || sw <= 0.0 {
        return f64::NAN;
    }
    let mean = sy / sw;
    training_rms(data, |_, y| y - mean)
}

/// The reason a model of RMS `model_rms` found nothing, when it does barely better than the
/// output's mean (RMS `constant` about it): the output does not depend on the input.
fn dependence_reason(model_rms: f64, constant: f64) -> Option<String> {
    if !(constant > 0.0 && model_rms >= DEPENDENCE_RATIO * constant) {
        return None;
    }
    let explained = (1.0 - (model_rms / constant).powi(2)).max(0.0);
    Some(format!(
        "the output does not follow the input: the fitted model explains {} % of its variance \
         (RMS {} against {} for the output's mean)",
        sig(100.0 * explained, 2),
        sig(model_rms, 3),
        sig(constant, 3),
    ))
}

/// The reason a model of RMS `model_rms` and branch gap `gap` is a line in effect, when it
/// does no better than the straight line's RMS `line` on data of branch gap `data_gap`.
fn line_reason(model_rms: f64, line: f64, gap: f64, data_gap: f64) -> Option<String> {
    if !(model_rms >= LINE_RATIO * line && line > 0.0) {
        return None;
    }
    if data_gap.abs() < MIN_GAP {
        // No loop in the data to compare the model's with: a model no better than a line
        // has found nothing (a loop on the sweep alone is the start's, not the data's).
        Some(format!(
            "the fitted model does no better than a straight line (RMS {} against the \
             line's {})",
            sig(model_rms, 3),
            sig(line, 3),
        ))
    } else if gap.abs() < LOOP_SHARE * data_gap.abs() {
        Some(format!(
            "the fitted model is a line in effect (its loop is {} % of the data's, and its \
             RMS {} is no better than a straight line's)",
            sig(100.0 * gap.abs() / data_gap.abs(), 2),
            sig(model_rms, 3),
        ))
    } else {
        None
    }
}

/// The estimates whose standard error is NaN (the data does not identify them), except those
/// `unidentified_ok` names, as "name = value": the parameters of the hysteresis itself
/// ([`HYSTERESIS_PARAMETERS`]) for `hysteresis`, the others otherwise.
fn lost(estimates: &[Estimate], unidentified_ok: &[&str], hysteresis: bool) -> Vec<String> {
    estimates
        .iter()
        .filter(|e| e.std_error.is_nan() && !unidentified_ok.contains(&e.name.as_str()))
        .filter(|e| HYSTERESIS_PARAMETERS.contains(&e.name.as_str()) == hysteresis)
        .map(|e| format!("{} = {}", e.name, sig(e.value, 4)))
        .collect()
}

/// The loop's half-width k1 when its standard error exceeds its value (unless
/// `unidentified_ok` names it: a parameter limit), as "k1 = value ± error": the records cannot
/// place the loop (an 8-sample record gave k1 = 2.25 ± 12.4 in normalised units, a band wider
/// than the input range). Not k2: a corner whose sharpness is known only within its own value
/// (far outliers in the records) still belongs to a loop the data shows.
fn vague_loop(estimates: &[Estimate], unidentified_ok: &[&str]) -> Vec<String> {
    estimates
        .iter()
        .filter(|e| e.name == "k1")
        .filter(|e| !unidentified_ok.contains(&e.name.as_str()))
        .filter(|e| e.std_error.is_finite() && e.std_error > e.value.abs())
        .map(|e| format!("{} = {} ± {}", e.name, sig(e.value, 4), sig(e.std_error, 2)))
        .collect()
}

/// The note on saturating shapes the data hardly identifies ([`VAGUE`]), if any.
///
/// A saturating shape's scale known only to within many times itself: the shape sits deep in
/// saturation or at its linear limit, where the data cannot place it; its inverse then loses
/// digits (a compensator round trip 1e-8 instead of 1e-15).
fn vague_note(estimates: &[Estimate]) -> Option<String> {
    let vague: Vec<String> = estimates
        .iter()
        .filter(|e| {
            // A scale relative to itself; the argument at the centre (dimensionless, in
            // units of the scale: saturated beyond a few) in absolute terms.
            let bound = if SCALE_PARAMETERS.contains(&e.name.as_str()) {
                VAGUE * e.value.abs()
            } else if ARGUMENT_PARAMETERS.contains(&e.name.as_str()) {
                VAGUE
            } else {
                return false;
            };
            e.std_error.is_finite() && e.std_error > bound
        })
        .map(|e| format!("{} = {} ± {}", e.name, sig(e.value, 4), sig(e.std_error, 2)))
        .collect();
    (!vague.is_empty()).then(|| {
        format!(
            "the data hardly identifies {} (a scale's standard error above {VAGUE} times \
             its value, or an argument's above {VAGUE}): \
             the shaping sits deep in saturation or at its linear limit on this data; a \
             simpler shaping (affine or a polynomial) fits about as well and inverts with \
             more digits",
            vague.join(", ")
        )
    })
}

/// What the data's loops (`data_orientation`, branch gap `data_gap`) call for, after a fit of a
/// structure made for `used` found no hysteresis.
fn advice(
    data: &Dataset,
    data_orientation: Orientation,
    used: Orientation,
    data_gap: f64,
) -> String {
    let direction = data_orientation.name();
    match data_orientation {
        Orientation::None if one_way(data).is_some() => "the data holds no loop either: \
             each record moves one way (first-order reversal curves, say), so its loops \
             cannot be seen in it: the fit then rests on how each record starts \
             (--initial-state, or --estimate-initial-states) and, for a material that \
             saturates, on a shaping that does (--output-shaping tanh or langevin)"
            .to_string(),
        Orientation::None => "the data holds no loop either".to_string(),
        _ if data_orientation == used => format!(
            "the data's loops run {direction} as this structure's do, but their branch gap \
             ({} % of the output span) is not resolved by this fit",
            sig(100.0 * data_gap.abs(), 2)
        ),
        Orientation::Clockwise => {
            "the data's loops run clockwise: the stop form (--form stop or auto) fits those"
                .to_string()
        }
        Orientation::Counterclockwise => "the data's loops run counterclockwise: the \
             operator form (--form operator or auto) fits those"
            .to_string(),
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::data::Record;
    use hyst_core::{AnyK2Law, ScaledShaping};
    use hyst_model::{InitialState, SmoothModel};

    fn operator_model() -> SmoothModel {
        SmoothModel {
            k1: 0.2,
            k2: AnyK2Law::Constant { value: 5.0 },
            input_shaping: ScaledShaping::identity(),
            output_shaping: ScaledShaping::identity(),
            initial_state: InitialState::Rising,
            form: hyst_model::Form::Operator,
            linear: 0.0,
            dynamics: None,
            rate: None,
        }
    }

    fn input() -> Vec<f64> {
        (0..2000)
            .map(|k| (k as f64 * 0.01).sin() * (1.0 + 0.3 * (k as f64 * 0.0013).cos()))
            .collect()
    }

    fn estimate(name: &str, std_error: f64) -> Estimate {
        Estimate {
            name: name.into(),
            value: 1.0,
            std_error,
            unit: String::new(),
        }
    }

    #[test]
    fn a_line_is_degenerate_and_a_loop_is_not() {
        let x = input();
        let y: Vec<f64> = x.iter().map(|v| 2.0 * v + 1.0).collect();
        let data = Dataset::single(&x, &y);
        let line = |x: &[f64]| Some(x.iter().map(|v| 2.0 * v + 1.0).collect());
        let d = diagnose(
            &data,
            &vec![y.clone()],
            &line,
            None,
            &[],
            Orientation::Counterclockwise,
            Orientation::Counterclockwise,
        );
        assert!(d.degenerate && d.line_rms < 1e-12, "{d:?}");
        let message = d.message("f.csv", "N", 4.0);
        assert!(message.starts_with("no hysteresis found in f.csv: the fitted model has no loop"));

        let model = operator_model();
        let looped = model.run(&x).unwrap();
        let data = Dataset::single(&x, &looped);
        let d = diagnose(
            &data,
            &vec![looped],
            &|x| model.run(x).ok(),
            Some(&[estimate("k1", 0.1)]),
            &[],
            Orientation::Counterclockwise,
            Orientation::Counterclockwise,
        );
        assert!(!d.degenerate, "{d:?}");
        assert!(d.model_gap < -0.01, "{d:?}");
    }

    #[test]
    fn residuals_that_follow_the_rate_are_found() {
        let x = input();
        let model = operator_model();
        let y = model.run(&x).unwrap();
        let mut measured = y.clone();
        for i in 1..x.len() - 1 {
            measured[i] += 30.0 * (x[i + 1] - x[i - 1]);
        }
        let data = Dataset::single(&x, &measured);
        let run = |x: &[f64]| model.run(x).ok();
        let d = diagnose(
            &data,
            &vec![y.clone()],
            &run,
            None,
            &[],
            Orientation::Counterclockwise,
            Orientation::Counterclockwise,
        );
        assert!(d.rate_share > 0.95, "{d:?}");
        let data = Dataset::single(&x, &y);
        let d = diagnose(
            &data,
            &vec![y],
            &run,
            None,
            &[],
            Orientation::Counterclockwise,
            Orientation::Counterclockwise,
        );
        assert!(d.rate_share < 1e-6, "{d:?}");
        assert!(d.drift_share < 1e-6, "{d:?}");
    }

    #[test]
    fn a_nan_standard_error_is_degenerate_unless_expected() {
        let x = input();
        let model = operator_model();
        let y = model.run(&x).unwrap();
        let data = Dataset::single(&x, &y);
        let nan = [estimate("k1", f64::NAN), estimate("k2", 0.5)];
        let run = |x: &[f64]| model.run(x).ok();
        let d = diagnose(
            &data,
            &vec![y.clone()],
            &run,
            Some(&nan),
            &[],
            Orientation::Clockwise,
            Orientation::Counterclockwise,
        );
        assert!(
            d.degenerate && d.reasons[0].contains("does not identify k1"),
            "{d:?}"
        );
        let d = diagnose(
            &data,
            &vec![y],
            &run,
            Some(&nan),
            &["k1"],
            Orientation::Clockwise,
            Orientation::Counterclockwise,
        );
        assert!(!d.degenerate, "{d:?}");
    }

    /// y = x + w · sign(ẋ) on `x` (the sign of the step into each sample; the first sample
    /// rising): a rectangular loop of height 2 w.
    fn with_loop(x: &[f64], w: f64) -> Vec<f64> {
        let mut rising = true;
        (0..x.len())
            .map(|i| {
                if i > 0 && x[i] != x[i - 1] {
                    rising = x[i] > x[i - 1];
                }
                x[i] + if rising { -w } else { w }
            })
            .collect()
    }

    #[test]
    fn first_order_reversal_curves_rise_only_and_still_have_a_loop() {
        // 12 curves: each falls from the top to its reversal point (not measured) and rises
        // back (measured): the data has no falling sample, the model a loop of half-width 0.2.
        let model = operator_model();
        let mut history = Vec::new();
        let mut parts = Vec::new();
        for c in 0..12 {
            let reversal = 1.0 - 0.15 * f64::from(c + 1);
            history.extend((0..100).map(|i| 1.0 - (1.0 - reversal) * f64::from(i) / 100.0));
            let start = history.len();
            history.extend((0..=100).map(|i| reversal + (1.0 - reversal) * f64::from(i) / 100.0));
            parts.push(start..history.len());
        }
        let y = model.run(&history).unwrap();
        let records: Vec<Record> = parts
            .iter()
            .enumerate()
            .map(|(id, p)| {
                let n = p.len();
                Record {
                    id: id as i64,
                    input: history[p.clone()].into(),
                    output: y[p.clone()].into(),
                    weight: crate::Weights::Unit(n),
                    rows: (0..n).collect(),
                    validation: false,
                    continues: false,
                    period: None,
                }
            })
            .collect();
        let outputs: Vec<Vec<f64>> = records.iter().map(|r| r.output.to_vec()).collect();
        let data = Dataset::single(&[0.0], &[0.0]);
        let data = Dataset::from_records("forc.csv", data.columns, records);
        assert_eq!(loops(&data).orientation, Orientation::None);
        let d = diagnose(
            &data,
            &outputs,
            &|x| model.run(x).ok(),
            Some(&[estimate("k1", 0.01), estimate("k2", 0.5)]),
            &[],
            Orientation::None,
            Orientation::Counterclockwise,
        );
        assert!(!d.degenerate, "{d:?}");
        assert!(d.swept_gap < -0.05, "{d:?}");
        // The same curves from a model without hysteresis: no loop on the sweep either.
        let line = |x: &[f64]| Some(x.to_vec());
        let d = diagnose(
            &data,
            &outputs,
            &line,
            None,
            &[],
            Orientation::None,
            Orientation::Counterclockwise,
        );
        assert!(d.swept_gap.abs() < 1e-12, "{d:?}");
        // A fit that found nothing on such data (a loop from its start, but no better than a
        // line) is degenerate, and the advice names the start rules.
        let mean: Vec<Vec<f64>> = outputs
            .iter()
            .map(|y| vec![y.iter().sum::<f64>() / y.len() as f64; y.len()])
            .collect();
        let d = diagnose(
            &data,
            &mean,
            &|x| model.run(x).ok(),
            None,
            &[],
            Orientation::None,
            Orientation::Counterclockwise,
        );
        assert!(d.degenerate, "{d:?}");
        let advice = d.reasons.last().unwrap();
        assert!(advice.contains("--initial-state"), "{advice}");
    }

    #[test]
    fn a_small_loop_the_model_reproduces_is_found() {
        // A clockwise loop just above the 0.1 % threshold, and a model that reproduces 98 % of
        // it (0.099 % of the span: below the threshold on its own).
        let x = input();
        let (lo, hi) = x
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(*v), b.max(*v))
            });
        let w = 0.5 * 1.01e-3 * (hi - lo);
        let measured = with_loop(&x, -w);
        let data = Dataset::single(&x, &measured);
        let gap = loops(&data).gap;
        assert!(gap > MIN_GAP && gap < 1.05 * MIN_GAP, "{gap}");
        // A stop-form fit whose loop is `share` of the data's.
        let fit = |share: f64| {
            let model = |v: &[f64]| Some(with_loop(v, -share * w));
            diagnose(
                &data,
                &vec![with_loop(&x, -share * w)],
                &model,
                None,
                &[],
                Orientation::Clockwise,
                Orientation::Clockwise,
            )
        };
        let d = fit(0.98);
        assert!(!d.degenerate, "{d:?}");
        // A model with a fifth of it has not found it, and the advice does not send the user to
        // the form that was used.
        let d = fit(0.2);
        assert!(d.degenerate, "{d:?}");
        let advice = d.reasons.last().unwrap();
        assert!(
            advice.contains("as this structure's do") && !advice.contains("--form"),
            "{advice}"
        );
    }

    #[test]
    fn residuals_that_drift_over_time_are_found() {
        let x = input();
        let model = operator_model();
        let y = model.run(&x).unwrap();
        // Creep: the output drifts by 0.2 over the record, with a wiggle that is no trend.
        let measured: Vec<f64> = y
            .iter()
            .enumerate()
            .map(|(i, v)| v + 0.2 * i as f64 / x.len() as f64 + 0.01 * (i as f64 * 0.3).sin())
            .collect();
        let data = Dataset::single(&x, &measured);
        let d = diagnose(
            &data,
            &vec![y.clone()],
            &|v| model.run(v).ok(),
            None,
            &[],
            Orientation::Counterclockwise,
            Orientation::Counterclockwise,
        );
        assert!(d.drift_share > 0.9, "{d:?}");
        // A record whose input only rises in time, with residuals that follow the input: misfit,
        // not drift.
        let x: Vec<f64> = (0..500).map(|i| f64::from(i) / 500.0).collect();
        let fitted: Vec<f64> = x.iter().map(|v| 2.0 * v).collect();
        let measured: Vec<f64> = x.iter().map(|v| 2.0 * v + 0.3 * v * v).collect();
        let data = Dataset::single(&x, &measured);
        let d = diagnose(
            &data,
            &vec![fitted],
            &|v| Some(v.iter().map(|v| 2.0 * v).collect()),
            None,
            &[],
            Orientation::None,
            Orientation::Counterclockwise,
        );
        assert!(d.drift_share < 0.01, "{d:?}");
    }

    #[test]
    fn a_shaping_the_data_hardly_places_gets_a_note() {
        let x = input();
        let model = operator_model();
        let y = model.run(&x).unwrap();
        let data = Dataset::single(&x, &y);
        let with = |scale_se: f64, arg_se: f64| {
            let mut scale = estimate(OUT_SCALE, scale_se);
            scale.value = 20.0;
            let estimates = [
                estimate("k1", 0.01),
                estimate("k2", 0.5),
                scale,
                estimate(OUT_ARG_AT_CENTRE, arg_se),
            ];
            diagnose(
                &data,
                &vec![y.clone()],
                &|v| model.run(v).ok(),
                Some(&estimates),
                &[],
                Orientation::Counterclockwise,
                Orientation::Counterclockwise,
            )
        };
        let d = with(5.0, 0.5);
        assert!(d.notes.is_empty(), "{d:?}");
        let d = with(1e5, 0.5);
        assert!(!d.degenerate, "{d:?}");
        assert!(
            d.notes[0].contains("hardly identifies out.scale = 20.00 ± 100000"),
            "{d:?}"
        );
        let d = with(5.0, 1e4);
        assert!(d.notes[0].contains(OUT_ARG_AT_CENTRE), "{d:?}");
    }
}
