//! `hyst.Adaptive`: online adaptation of a fitted model (`hyst_core::adaptive`): the recursive
//! estimator over recorded data, and the exact inverse that follows a drifting actuator.

use hyst_core::adaptive::{AdaptiveConfig, AdaptiveInverse, Parameter, Parameters, Status, Update};
use hyst_io::number::shortest;
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{samples_f64, to_numpy};
use crate::errors::{self, borrow, borrow_mut, core, value_error, Shared};
use crate::model::Model;

/// The recursive estimator of a fitted model's parameters, and the exact inverse that uses them.
///
/// `Adaptive(model, *, parameters=("k1", "k2", "gain", "offset"), noise=None, drift=1e-3,
/// uncertainty=0.01, rest=1e-3, step=0.01, range=4.0, dead_zone=0.0, input_range=None,
/// strict=False)`: `model` a smooth `Model` of the operator form without dynamics (as `hyst
/// adapt` takes); `noise` the measurement noise σ (output units; default the model's training
/// RMS); the other settings as `hyst adapt`'s flags (docs/adaptation.md). `input_range`
/// (min, max) defaults to the range the model was fitted on, widened by 10 %.
///
/// - `process(x, y)`: a record of commands and measured outputs → `(y_pred, params)`, the
///   one-step predictions (float64, n) and the parameters after each sample (float64, (n, p),
///   columns in the order of `parameters`).
/// - `step(desired)` → the command for a desired output with the current parameters;
///   `measure(y)` → the update with the output measured for that command (its prediction).
/// - `values`, `std_errors`, `counts`, `parameters`; `model()` the model with the current
///   parameters (a `Model`: save it, export it, run it).
///
/// A sample with a non-finite command or measurement, or a command outside `input_range`,
/// skips the update and is counted in `counts`; with `strict=True` it raises ValueError instead
/// (the state is then as after the samples before it).
#[pyclass(module = "hyst")]
pub struct Adaptive {
    inverse: AdaptiveInverse<f64>,
    file: hyst_model::ModelFile,
    source: String,
    adapted: Vec<Parameter>,
    strict: bool,
}

impl Shared for Adaptive {
    const OWN: &'static str = "one Adaptive follows one actuator, so give each thread its own \
                               object (hyst.Adaptive(model, ...))";
}

/// Whether a status is a skipped bad sample (what `strict` refuses).
fn bad(s: Status) -> bool {
    matches!(s, Status::BadInput | Status::OutOfRange | Status::BadOutput)
}

impl Adaptive {
    fn check(&self, i: Option<usize>, x: f64, y: f64, u: Update<f64>) -> PyResult<()> {
        if self.strict && bad(u.status) {
            let at = i.map_or(String::new(), |i| format!("sample {i}: "));
            let (lo, hi) = self.inverse.estimator().config().input_range;
            return Err(value_error(format!(
                "{at}x = {}, y = {}: {} (strict=True; input_range = ({}, {}))",
                shortest(x),
                shortest(y),
                match u.status {
                    Status::BadInput => "the command is not finite",
                    Status::OutOfRange => "the command is outside input_range",
                    _ => "the measurement is not finite",
                },
                shortest(lo),
                shortest(hi)
            )));
        }
        Ok(())
    }

    fn dict<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(Parameter) -> f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for p in &self.adapted {
            d.set_item(p.name(), f(*p))?;
        }
        Ok(d)
    }
}

#[pymethods]
impl Adaptive {
    #[new]
    #[pyo3(signature = (model, *, parameters=None, noise=None, drift=1e-3, uncertainty=0.01, rest=1e-3, step=0.01, range=4.0, dead_zone=0.0, input_range=None, strict=false))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        model: &Bound<'_, Model>,
        parameters: Option<Vec<String>>,
        noise: Option<f64>,
        drift: f64,
        uncertainty: f64,
        rest: f64,
        step: f64,
        range: f64,
        dead_zone: f64,
        input_range: Option<(f64, f64)>,
        strict: bool,
    ) -> PyResult<Self> {
        let m = borrow(model)?;
        let file = m.file.clone();
        let source = m.source.clone();
        drop(m);
        let smooth = hyst_model::adaptive::adaptable(&file)
            .map_err(|e| value_error(format!("model: {source}: {e}")))?;
        let mut set = Parameters::NONE;
        for name in parameters.unwrap_or_else(|| {
            Parameters::DEFAULT
                .iter()
                .map(|p| p.name().to_string())
                .collect()
        }) {
            let p = Parameter::from_name(&name).ok_or_else(|| {
                value_error(format!(
                    "parameters: {name:?} is not a parameter: give some of k1, k2, gain, \
                     offset, input_gain, input_offset"
                ))
            })?;
            set = set.with(p);
        }
        let noise = noise
            .or_else(|| hyst_model::adaptive::training_noise(&file))
            .ok_or_else(|| {
                value_error(format!(
                    "noise is needed: the model {source} has no training RMS to take the \
                     measurement noise from"
                ))
            })?;
        let config = AdaptiveConfig {
            parameters: set,
            noise,
            drift,
            uncertainty,
            rest,
            step,
            range,
            dead_zone,
            input_range: input_range
                .unwrap_or_else(|| hyst_model::adaptive::fitted_input_range(&file, smooth)),
        };
        let estimator = hyst_model::adaptive::estimator(smooth, config).map_err(|e| match e {
            hyst_model::ModelError::Core(e) => core("Adaptive", e),
            e => crate::errors::model(e),
        })?;
        Ok(Self {
            inverse: AdaptiveInverse::new(estimator),
            adapted: set.iter().collect(),
            file,
            source,
            strict,
        })
    }

    /// A record: commands `x` and measured outputs `y` (1-D, the same length) → `(y_pred,
    /// params)`: the one-step predictions (NaN where the command is not finite) and the
    /// parameters after each sample, one column per name in `parameters`.
    fn process<'py>(
        slf: &Bound<'py, Self>,
        x: &Bound<'py, PyAny>,
        y: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let py = slf.py();
        let (xs, ys) = (samples_f64(x, "x")?, samples_f64(y, "y")?);
        if xs.len() != ys.len() {
            return Err(value_error(format!(
                "x has {} samples and y {}: give one measurement per command",
                xs.len(),
                ys.len()
            )));
        }
        let mut me = borrow_mut(slf)?;
        let strict = me.strict;
        let adapted = me.adapted.clone();
        let inverse = &mut me.inverse;
        let mut pred = Vec::with_capacity(xs.len());
        let mut params = Array2::<f64>::zeros((xs.len(), adapted.len()));
        // Without the GIL; with `strict`, up to the first bad sample.
        let stopped = py.detach(|| {
            for (i, (xi, yi)) in xs.iter().zip(ys.iter()).enumerate() {
                let u = inverse.update(*xi, *yi);
                if strict && bad(u.status) {
                    return Some((i, *xi, *yi, u));
                }
                pred.push(u.prediction);
                let est = inverse.estimator();
                for (j, q) in adapted.iter().enumerate() {
                    if let Some(slot) = params.get_mut((i, j)) {
                        *slot = est.value(*q);
                    }
                }
            }
            None
        });
        if let Some((i, x, y, u)) = stopped {
            me.check(Some(i), x, y, u)?;
        }
        Ok((to_numpy(py, pred), params.into_pyarray(py).into_any()))
    }

    /// One sample: (prediction, status), status one of "updated", "rest", "starting", "dead_zone",
    /// "bad_input", "out_of_range", "bad_output", "refused".
    fn update(slf: &Bound<'_, Self>, x: f64, y: f64) -> PyResult<(f64, &'static str)> {
        let mut me = borrow_mut(slf)?;
        let u = me.inverse.update(x, y);
        me.check(None, x, y, u)?;
        Ok((u.prediction, u.status.name()))
    }

    /// The inverse's step: the command for the desired output `desired` with the current
    /// parameters. Raises ValueError for a desired output the model cannot produce (the state
    /// is unchanged).
    fn step(slf: &Bound<'_, Self>, desired: f64) -> PyResult<f64> {
        let mut me = borrow_mut(slf)?;
        me.inverse
            .step(desired)
            .map_err(|e| core(format!("desired = {}", shortest(desired)), e))
    }

    /// The output measured for the last command: its one-step prediction, or None when no
    /// command is waiting for a measurement.
    fn measure(slf: &Bound<'_, Self>, y: f64) -> PyResult<Option<f64>> {
        let mut me = borrow_mut(slf)?;
        let Some(x) = me.inverse.pending() else {
            return Ok(None);
        };
        let Some(u) = me.inverse.measure(y) else {
            return Ok(None);
        };
        me.check(None, x, y, u)?;
        Ok(Some(u.prediction))
    }

    /// A separate experiment follows: back to the fitted parameters, their initial
    /// uncertainty and no history (the counts stay).
    fn reset(slf: &Bound<'_, Self>) -> PyResult<()> {
        let mut me = borrow_mut(slf)?;
        let estimator = {
            let mut e = *me.inverse.estimator();
            e.reset();
            e
        };
        me.inverse = AdaptiveInverse::new(estimator);
        Ok(())
    }

    /// The names of the adapted parameters, in the order of `process`'s columns.
    #[getter]
    fn parameters(slf: &Bound<'_, Self>) -> PyResult<Vec<&'static str>> {
        Ok(borrow(slf)?.adapted.iter().map(|p| p.name()).collect())
    }

    /// The current value of each adapted parameter.
    #[getter]
    fn values<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let me = borrow(slf)?;
        let e = me.inverse.estimator();
        me.dict(slf.py(), |p| e.value(p))
    }

    /// The standard error σ of each adapted parameter's estimate (its units).
    #[getter]
    fn std_errors<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let me = borrow(slf)?;
        let e = me.inverse.estimator();
        me.dict(slf.py(), |p| e.std_error(p))
    }

    /// The old name of `std_errors` (a DeprecationWarning).
    #[getter]
    fn sigmas<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        errors::deprecated(slf.py(), "Adaptive.sigmas", "Adaptive.std_errors")?;
        Self::std_errors(slf)
    }

    /// How many samples had each status.
    #[getter]
    fn counts<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let c = borrow(slf)?.inverse.estimator().counts();
        let d = PyDict::new(slf.py());
        for s in Status::ALL {
            d.set_item(s.name(), c.of(s))?;
        }
        Ok(d)
    }

    /// The model with the current parameters (the fit's file with k1, k2 and the shaping
    /// functions replaced), a new `Model` with no history.
    fn model(slf: &Bound<'_, Self>) -> PyResult<Model> {
        let me = borrow(slf)?;
        let current = me
            .inverse
            .estimator()
            .model()
            .map_err(|e| core("Adaptive.model()", e))?;
        let file = hyst_model::adaptive::adapted_file(&me.file, &current, "hyst.Adaptive");
        Ok(Model::new(file, false, format!("<adapted {}>", me.source)))
    }

    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        let me = borrow(slf)?;
        let e = me.inverse.estimator();
        let values: Vec<String> = me
            .adapted
            .iter()
            .map(|p| format!("{}={}", p.name(), shortest(e.value(*p))))
            .collect();
        Ok(format!("Adaptive({}; {})", me.source, values.join(", ")))
    }
}
