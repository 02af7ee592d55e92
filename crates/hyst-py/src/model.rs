//! `hyst.load_model` and `hyst.Model`: the model file of `hyst fit` (docs/formats.md), run
//! sample by sample with the same code as `hyst run --model`, so the results are bit-identical.

use hyst_io::number::shortest;
use std::path::{Path, PathBuf};

use hyst_model::{Choice, ModelKind};
use hyst_model::{Evaluator, ModelFile, Saturated};
use hyst_model::{SmoothModel, TimedCompensator};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{
    derivatives, each_dtype, pair, result_array, run_into, run_jets, samples, to_numpy, Samples,
};
use crate::dicts::{by_parameter, reached, to_python};
use crate::errors::{self, borrow, borrow_mut, value_error, Shared};
use crate::model_memory;
use crate::timed::{timed_model, untimed};
use hyst_core::Real as _;

/// A fitted model (smooth or Prandtl–Ishlinskii) from a model file, direct (input x, output
/// y) or as its exact inverse (desired output in, command out).
///
/// `process(x)` runs it over a record: the first sample starts it by the model's start rule,
/// exactly as `hyst run --model FILE` does (bit-identical results). `inverse()` gives the
/// exact inverse (desired output in, command out; `hyst run --model FILE --inverse`).
///
/// A model with dynamics or a rate term (`dynamics`, `rate`: fitted with `hyst.fit(...,
/// time=..., dynamics=N, rate_term="viscous")`) runs on timed records only:
/// `process(x, t=...)` or `process(x, period=...)`, and its Lemma 5.1 compensator is
/// `compensate(desired, time=..., derivatives=... or prefilter_hz=...)`; `inverse()`, `step()`
/// and the exports refuse it.
#[pyclass(module = "hyst")]
#[derive(Clone, Debug)]
pub struct Model {
    pub(crate) file: ModelFile,
    pub(crate) inverse: bool,
    /// Where it came from, for messages (`"<fit>"` for a fit's result).
    pub(crate) source: String,
    /// FNV-1a 64 of the model file's bytes (of its TOML text for a model never read from a
    /// file): what an exported header names beside `source`.
    pub(crate) source_fnv1a64: u64,
    /// The inverse clamps desired outputs into the saturation limits (`inverse(saturate=True)`).
    pub(crate) saturate: bool,
    evaluator: Option<Saturated<Evaluator>>,
}

impl Model {
    /// A model from a model file's content.
    #[must_use]
    pub fn new(file: ModelFile, inverse: bool, source: String) -> Self {
        let source_fnv1a64 = file
            .to_toml()
            .map_or(0, |text| hyst_model::file::fnv1a64(text.as_bytes()));
        Self {
            file,
            inverse,
            source,
            source_fnv1a64,
            saturate: false,
            evaluator: None,
        }
    }

    /// The clamp limits of the inverse with `saturate` (`None`: nothing is clamped).
    fn limits(&self) -> Option<(f64, f64)> {
        if self.inverse && self.saturate {
            self.file.saturation().map(|s| s.limits)
        } else {
            None
        }
    }

    /// The evaluator, started at `first` (clamped, with `saturate`) if there is none yet;
    /// `true` when it was started now.
    fn started(&mut self, first: f64) -> PyResult<(&mut Saturated<Evaluator>, bool)> {
        let fresh = self.evaluator.is_none();
        let evaluator = match self.evaluator.take() {
            Some(e) => e,
            None => {
                let limits = self.limits();
                let at = Saturated::new((), limits).clamp(first).unwrap_or(first);
                let e = self.file.evaluator(at, self.inverse).map_err(|e| {
                    let advice = match &e {
                        hyst_model::ModelError::Core(core) => errors::advice(core),
                        _ => "",
                    };
                    value_error(format!(
                        "x[0] = {first}: the model {} cannot start here: {e}{advice}",
                        self.source
                    ))
                })?;
                Saturated::new(e, limits)
            }
        };
        Ok((self.evaluator.insert(evaluator), fresh))
    }
}

impl Model {
    /// `ValueError` for the inverse of a model with dynamics or a rate term `m`: it has none
    /// without time, and its compensator is `compensate`.
    fn no_inverse(&self, m: &SmoothModel) -> PyErr {
        let how = if TimedCompensator::check(m).is_ok() {
            "its Lemma 5.1 compensator is Model.compensate(desired, time=..., derivatives=... or \
             prefilter_hz=...) or hyst.Compensator(model), and the inverse of its hysteresis \
             part Model.hysteresis.inverse()"
        } else {
            "it has no inverse"
        };
        match self
            .file
            .untimed(&format!("Model.inverse() (without time); {how}"))
        {
            Err(e) => errors::model(e),
            Ok(()) => value_error(format!(
                "the model {} has {}: {how}",
                self.source,
                m.timed_parts()
            )),
        }
    }

    /// What an exported file names as its source.
    fn export_source(&self) -> hyst_codegen::Source {
        hyst_codegen::Source {
            name: self.source.clone(),
            fnv1a64: self.source_fnv1a64,
        }
    }

    /// "smooth" or "prandtl-ishlinskii".
    fn kind_name(&self) -> &'static str {
        match self.file.kind {
            ModelKind::Smooth => "smooth",
            ModelKind::PrandtlIshlinskii => "prandtl-ishlinskii",
        }
    }

    /// `process` of a static model (`time` and `period` refused).
    fn process_static<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        derivatives: Option<&Bound<'py, PyAny>>,
        t: Option<&Bound<'py, PyAny>>,
        period: Option<f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        if let Some(name) = [(t.is_some(), "time"), (period.is_some(), "period")]
            .into_iter()
            .find_map(|(given, name)| given.then_some(name))
        {
            return Err(value_error(format!(
                "{name} applies to a model with dynamics or a rate term; the model {} has \
                 neither, and runs without time (process(x))",
                self.source
            )));
        }
        let xs = samples(x, "x")?;
        let Some(first) = first_of(&xs) else {
            return match xs {
                Samples::F64(_) => Ok(to_numpy(py, Vec::<f64>::new())),
                Samples::F32(_) => Ok(to_numpy(py, Vec::<f32>::new())),
            };
        };
        let (op, fresh) = self.started(first)?;
        let d = match derivatives {
            Some(d) => {
                let n = each_dtype!(&xs, a => a.len()?);
                Some(self::derivatives(d, n)?)
            }
            None => None,
        };
        let result = match &d {
            None => each_dtype!(&xs, a, dtype => {
                let (out, mut o) = result_array(py, None, a.len()?, dtype)?;
                let (view, dest) = (
                    a.as_array(),
                    o.as_slice_mut()
                        .map_err(|_| value_error("out: the array is not contiguous"))?,
                );
                py.detach(|| run_into(op, view, dest)).map(|()| Ok(out))
            }),
            Some((d, one_d)) => each_dtype!(&xs, a => {
                let (view, dv) = (a.as_array(), d.as_array());
                py.detach(|| run_jets(op, view, dv))
                    .map(|(y, dy)| pair(py, y, dy, dv.ncols(), *one_d))
            }),
        };
        match result {
            Ok(out) => out,
            Err(refused) => {
                if fresh {
                    self.evaluator = None;
                }
                Err(refused.into_err("x"))
            }
        }
    }

    /// `step`.
    fn step_one(&mut self, x: f64) -> PyResult<f64> {
        use hyst_core::Operator;
        untimed(
            &self.file,
            "Model.step(x), which has no sample period: run whole records with \
             Model.process(x, time=...) or Model.process(x, period=...)",
        )?;
        let (op, fresh) = self.started(x)?;
        match op.try_step(x) {
            Ok(y) => Ok(y),
            Err(e) => {
                if fresh {
                    self.evaluator = None;
                }
                Err(errors::core(format!("x = {}", shortest(x)), e))
            }
        }
    }

    /// `memory = memory`: restores it (None: no history, as `reset()`), or refuses it and
    /// changes nothing.
    fn restore(&mut self, memory: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        use hyst_core::Operator;
        let Some(memory) = memory.filter(|m| !m.is_none()) else {
            self.evaluator = None;
            return Ok(());
        };
        untimed(
            &self.file,
            "Model.memory, which it does not keep: each process(x, time=...) is one record from rest",
        )?;
        let m = model_memory::from_python(&self.file, memory)?;
        let refused = |e| errors::core(format!("memory = {}", model_memory::shown(memory)), e);
        match self.evaluator.as_mut() {
            Some(e) => e.set_memory(m).map_err(refused),
            None => {
                let mut e = model_memory::blank(&self.file, self.inverse, &m).map_err(|e| {
                    value_error(format!(
                        "memory = {}: the model {} cannot start there: {e}",
                        model_memory::shown(memory),
                        self.source
                    ))
                })?;
                e.set_memory(m).map_err(refused)?;
                self.evaluator = Some(Saturated::new(e, self.limits()));
                Ok(())
            }
        }
    }

    /// `inverse(saturate=...)`.
    fn inverted(&self, saturate: bool) -> PyResult<Self> {
        if let Some(m) = timed_model(&self.file) {
            return Err(self.no_inverse(m));
        }
        if let Some(m) = &self.file.smooth {
            // The model's own refusal, so that the words are the CLI's.
            m.invertible().map_err(errors::model)?;
        }
        if saturate && self.file.saturation().is_none() {
            return Err(value_error(
                "saturate=True: the model's output is unbounded (neither its input nor its \
                 output shaping saturates), so no desired output needs clamping",
            ));
        }
        let mut m = Self::new(self.file.clone(), true, self.source.clone());
        m.saturate = saturate;
        Ok(m)
    }
}

impl Shared for Model {
    const OWN: &'static str = "one Model holds one actuator's memory, so give each thread its own \
                               object (copy.copy(model), which starts with no history)";
}

/// What pickling a `Model` stores: its TOML text, `inverse`, `source`, `saturate` and the
/// source's hash (the arguments of `_model_from_toml`).
type Pickled = (String, bool, String, bool, u64);

fn first_of(xs: &Samples<'_>) -> Option<f64> {
    each_dtype!(xs, a => a.as_array().first().map(|v| v.as_f64()))
}

#[pymethods]
impl Model {
    /// Runs the model over the samples `x` (any 1-D array-like; float32 stays float32) and
    /// returns its outputs; with `derivatives` of shape (n, N) (N ≤ `hyst.MAX_ORDER`; a 1-D
    /// array is the first derivative), returns `(y, dy)` with the outputs' time derivatives
    /// (as `hyst run --model FILE --derivatives N`). The first sample ever (or after
    /// `reset()`) starts the model by its start rule; later calls continue.
    ///
    /// Raises ValueError at the first sample the model refuses (NaN, infinity, a desired
    /// output beyond a saturating shaping's range), naming its index; the model is then as it
    /// was before the call.
    ///
    /// A model with dynamics or a rate term needs the record's time stamps `time` (s, one per
    /// sample, increasing; each step is taken as measured, and a gap of more than 10 times the
    /// median step starts the rest afresh, with a `UserWarning`) or its sample `period` (s),
    /// and runs each call as one record that starts at rest at its first sample, as
    /// `hyst run --model FILE` runs a timed record (bit-identical results); it takes no
    /// `derivatives` and keeps no history between calls. `hold` ("zoh" or "foh") runs a model
    /// with dynamics under that hold instead of its file's (`hyst run --hold`). A static model
    /// refuses `time`, `period` and `hold`.
    #[pyo3(signature = (x, derivatives=None, *, time=None, period=None, hold=None, t=None))]
    fn process<'py>(
        slf: &Bound<'py, Self>,
        x: &Bound<'py, PyAny>,
        derivatives: Option<&Bound<'py, PyAny>>,
        time: Option<&Bound<'py, PyAny>>,
        period: Option<f64>,
        hold: Option<&str>,
        t: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let t = errors::renamed(slf.py(), ("time", time), ("t", t))?;
        let t = t.as_ref();
        let derivatives = derivatives.filter(|d| !d.is_none());
        let timed = {
            let me = borrow(slf)?;
            match timed_model(&me.file) {
                Some(m) if me.inverse => return Err(me.no_inverse(m)),
                Some(m) => Some((*m, me.source.clone(), me.file.provenance.clone())),
                None => None,
            }
        };
        if let Some((m, source, provenance)) = timed {
            // A timed run keeps no history: the model is not held while it runs, and other
            // threads may use it meanwhile.
            let origin = crate::timed::Origin::of(&source, &provenance);
            return crate::timed::process(slf.py(), &m, &origin, x, derivatives, t, period, hold);
        }
        if let Some(hold) = hold {
            return Err(value_error(format!(
                "hold = {hold:?}: the model {} has no dynamics (the hold is how a plant sees its \
                 command)",
                borrow(slf)?.source
            )));
        }
        borrow_mut(slf)?.process_static(slf.py(), x, derivatives, t, period)
    }

    /// One sample (starts the model by its start rule if it has no history yet). A model with
    /// dynamics or a rate term has no sample period here: ValueError (run its records with
    /// `process(x, t=...)`).
    fn step(slf: &Bound<'_, Self>, x: f64) -> PyResult<f64> {
        borrow_mut(slf)?.step_one(x)
    }

    /// Forgets the history: the next sample starts the model by its start rule again.
    fn reset(slf: &Bound<'_, Self>) -> PyResult<()> {
        borrow_mut(slf)?.evaluator = None;
        Ok(())
    }

    /// The model's memory: where it stands in its history, to save and assign back (to this
    /// model or a copy of it: the same model file, direction and `saturate`) so that it goes
    /// on exactly, bit for bit, as the model that had it.
    ///
    /// None before the first sample (and after `reset()`); assigning None forgets the history
    /// as `reset()` does (the next sample starts the model by its start rule). A smooth model's
    /// memory is its operator's, a `hyst.Memory` (Definition 2.1) in operator units, between
    /// the shaping functions: of H(k1, k2) for the direct model (reversal_input, last_input:
    /// ψ_in(x); reversal_output, last_output: H's output), of H⁻¹ for the inverse (inputs:
    /// ψ_out⁻¹(y_d); outputs: H⁻¹'s, ψ_in of the command). A Prandtl–Ishlinskii model's is the
    /// pair `(plays, last_output)`: a tuple of its play outputs p_1 … p_n (one per play; in
    /// input units for the direct model, for the inverse in the units of the PI sum's output
    /// less its offset) and the last output of its PI sum (the direct model's before its
    /// output polynomial; the inverse's is the last command). `clamped` is a count, not part
    /// of the memory.
    ///
    /// Assigning raises TypeError for an object that is not a memory of this kind of model and
    /// ValueError for one the model cannot be in (a non-finite value, a `Memory` outside the
    /// band |output − input| ≤ k1 or off its branch, the wrong number of play outputs),
    /// naming it; the model is then unchanged. A model with dynamics or a rate term keeps no
    /// memory (None; assigning one raises ValueError). Pickling and `copy.copy` keep the model,
    /// not its memory: a copy starts with no history (assign `copy.memory = model.memory`).
    #[getter]
    fn get_memory<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyAny>>> {
        use hyst_core::Operator;
        let me = borrow(slf)?;
        let memory = me.evaluator.as_ref().map(Operator::memory);
        model_memory::to_python(slf.py(), &me.file, memory)
    }

    #[setter]
    fn set_memory(slf: &Bound<'_, Self>, memory: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        borrow_mut(slf)?.restore(memory)
    }

    /// The model's exact inverse ψ_in⁻¹(H⁻¹[ψ_out⁻¹(y_d)]) (eq. 4 inside the shaping;
    /// PI⁻¹ for a Prandtl–Ishlinskii model): desired output in, command out. No history.
    /// Raises ValueError for a stop-form (friction) model, which has no inverse.
    ///
    /// `saturate=True` (a model whose output or input shaping saturates: tanh, Langevin; see
    /// `saturation`): a desired output beyond the limits is clamped to the nearer one instead of
    /// raising ValueError, as `hyst run --inverse --saturate` does; `clamped` counts them.
    /// ValueError for a model whose output is unbounded (nothing could need clamping).
    ///
    /// A model with dynamics or a rate term has no inverse without time: ValueError (its
    /// compensator is `compensate(desired, time=..., derivatives=... or prefilter_hz=...)`).
    #[pyo3(signature = (*, saturate=false))]
    fn inverse(slf: &Bound<'_, Self>, saturate: bool) -> PyResult<Self> {
        borrow(slf)?.inverted(saturate)
    }

    /// Lemma 5.1's compensator of a model with dynamics (and no rate term, of the operator
    /// form): for the desired outputs `desired` (1-D, one record) it returns the commands u
    /// that make the plant and the hysteresis give them, u = (1/b) Σ a_i dⁱx/dtⁱ with
    /// x = ψ_in⁻¹(H⁻¹[ψ_out⁻¹(y_d)]) (eq. 19), exactly as `hyst run --model FILE --inverse`
    /// computes them on a timed record (bit-identical results).
    ///
    /// The record's time stamps `time` (s) or its sample `period` give the sample period. The
    /// desired output's first n time derivatives (n the plant order) are `derivatives`, of
    /// shape (len(desired), n) (1-D for n = 1; `hyst run`'s columns `y_d1 … y_dn`), or come
    /// from the reference prefilter 1/(s/ω + 1)ⁿ, ω = 2π·`prefilter_hz` (`--prefilter-hz`):
    /// the commands then make the plant track the prefiltered reference. Give one of them.
    /// `prefilter_hz` is a finite, positive frequency of at most 1/20 of the Nyquist frequency
    /// of the record's sample period (25 Hz at 1 kHz): ValueError otherwise, saying the bound.
    ///
    /// Returns the commands, shape (len(desired),); with `prefilter_hz`, the pair
    /// `(commands, y_filtered)`: the commands and the prefiltered reference they make the plant
    /// track (`hyst run`'s column `<column>_filtered`), both of shape (len(desired),).
    ///
    /// Raises ValueError for a model without dynamics (its compensator is the exact inverse,
    /// `inverse()`), with a rate term or of the stop form, and at the first desired output the
    /// model cannot give, naming its index. Each call is one record, started at rest.
    #[pyo3(signature = (desired, *, time=None, period=None, derivatives=None, prefilter_hz=None, t=None))]
    fn compensate<'py>(
        slf: &Bound<'py, Self>,
        desired: &Bound<'py, PyAny>,
        time: Option<&Bound<'py, PyAny>>,
        period: Option<f64>,
        derivatives: Option<&Bound<'py, PyAny>>,
        prefilter_hz: Option<f64>,
        t: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let t = errors::renamed(slf.py(), ("time", time), ("t", t))?;
        // Copied: the model is not held while it runs, and other threads may use it meanwhile.
        let (smooth, source, provenance) = {
            let me = borrow(slf)?;
            match (&me.file.smooth, me.file.kind) {
                (Some(m), ModelKind::Smooth) => (*m, me.source.clone(), me.file.provenance.clone()),
                _ => {
                    return Err(value_error(format!(
                        "the model {} is a Prandtl-Ishlinskii model: it has no dynamics, and \
                         its compensator is the exact inverse (inverse())",
                        me.source
                    )))
                }
            }
        };
        let derivatives = derivatives.filter(|d| !d.is_none());
        let origin = crate::timed::Origin::of(&source, &provenance);
        crate::timed::compensate(
            slf.py(),
            &smooth,
            &origin,
            desired,
            (t.as_ref(), period),
            derivatives,
            prefilter_hz,
        )
    }

    /// The hysteresis part of a model with dynamics or a rate term: the static model
    /// x1 → y = ψ_out(H(k1, k2)[ψ_in(x1)]) of the plant output x1 (input units), without the
    /// plant (eq. 18) or the rate term, and without their parameters; a new `Model` with no
    /// history, which `inverse()`, `step()`, `memory`, `hyst.control.iosys` and the exports
    /// take as any static model (its metrics and family are the fit's, of the whole model). A
    /// static model gives a copy of itself (no history).
    #[getter]
    fn hysteresis(slf: &Bound<'_, Self>) -> PyResult<Self> {
        let me = borrow(slf)?;
        Ok(Self::new(me.file.hysteresis(), false, me.source.clone()))
    }

    /// Lemma 5.1's plant before the hysteresis, b / (a_n sⁿ + … + a_1 s + 1) (eq. 18), as the
    /// model file's `[dynamics]` section: {"b": b, "a": [a_1, …, a_n], "a_std_error": […],
    /// "identified": […], "hold": "zoh" or "foh"} (the standard errors and flags when the fit
    /// recorded them; the hold always, "foh" for a file without it); None for a model without
    /// dynamics.
    #[getter]
    fn dynamics<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let (py, me) = (slf.py(), borrow(slf)?);
        let Some(d) = me.file.smooth.as_ref().and_then(|m| m.dynamics) else {
            return Ok(None);
        };
        let out = match &me.file.dynamics {
            Some(section) => to_python(py, section)?,
            None => {
                let out = PyDict::new(py);
                out.set_item("b", d.b)?;
                out.set_item("a", d.a().to_vec())?;
                out.into_any()
            }
        };
        out.set_item("hold", d.hold().name())?;
        Ok(Some(out))
    }

    /// The rate term c·v̇ added to the output, as the model file's `[rate]` section:
    /// {"c": c, "c_std_error": …}; None for a model without one.
    #[getter]
    fn rate<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let (py, me) = (slf.py(), borrow(slf)?);
        let Some(r) = me.file.smooth.as_ref().and_then(|m| m.rate) else {
            return Ok(None);
        };
        match &me.file.rate {
            Some(section) => to_python(py, section).map(Some),
            None => {
                let out = PyDict::new(py);
                out.set_item("c", r.c)?;
                Ok(Some(out.into_any()))
            }
        }
    }

    /// The output range of a model bounded by a saturating output or input shaping (tanh,
    /// Langevin) and the limits (docs/formats.md; `hyst_model::Saturation::of`)
    /// that `inverse(saturate=True)` clamps desired outputs into:
    /// {"shaping": "tanh", "range": (lo, hi), "limits": (lo, hi)}; None for a model whose
    /// output is unbounded.
    #[getter]
    fn saturation<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let (py, me) = (slf.py(), borrow(slf)?);
        let Some(s) = me.file.saturation() else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("shaping", s.shaping)?;
        d.set_item("range", s.range)?;
        d.set_item("limits", s.limits)?;
        Ok(Some(d))
    }

    /// Whether this inverse clamps desired outputs (`inverse(saturate=True)`).
    #[getter]
    fn saturate(slf: &Bound<'_, Self>) -> PyResult<bool> {
        Ok(borrow(slf)?.saturate)
    }

    /// How many desired outputs were saturated (clamped into the limits) since the model was made or `reset()` (0 unless
    /// it is an inverse with `saturate=True`).
    #[getter]
    fn saturated(slf: &Bound<'_, Self>) -> PyResult<u64> {
        let me = borrow(slf)?;
        Ok(me.evaluator.as_ref().map_or(0, |e| e.saturated))
    }

    /// The old name of `saturated` (a DeprecationWarning).
    #[getter]
    fn clamped(slf: &Bound<'_, Self>) -> PyResult<u64> {
        errors::deprecated(slf.py(), "Model.clamped", "Model.saturated")?;
        Self::saturated(slf)
    }

    /// The direct model ψ_out(H[ψ_in(x)]), with no history.
    fn direct(slf: &Bound<'_, Self>) -> PyResult<Self> {
        let me = borrow(slf)?;
        Ok(Self::new(me.file.clone(), false, me.source.clone()))
    }

    /// Whether this is the exact inverse (from `inverse()`).
    #[getter]
    fn is_inverse(slf: &Bound<'_, Self>) -> PyResult<bool> {
        Ok(borrow(slf)?.inverse)
    }

    /// "smooth" or "prandtl-ishlinskii".
    #[getter]
    fn kind(slf: &Bound<'_, Self>) -> PyResult<&'static str> {
        Ok(borrow(slf)?.kind_name())
    }

    /// The fitted parameters by name ("k1", "k2", "out.gain", …), in the units of `units`
    /// (k1, k2 in normalised input units; in input units: `in_input_units`). For a model file
    /// of adapted parameters (`Adaptive.model()`, `hyst adapt --model-out`), k1, k2, k2.slope
    /// and an unsaturated output's out.gain and out.offset are the adapted values the model
    /// computes with; the other entries (and `std_errors`) are the fit's.
    #[getter]
    fn params<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let (py, me) = (slf.py(), borrow(slf)?);
        by_parameter(py, &me.file, |e| e.value)
    }

    /// k1 in input units and k2 in 1/input units beside the normalised `params`:
    /// {"k1_input", "k1_input_std_error", "k2_input", "k2_input_std_error", "input_slope"}
    /// (the JSON report's keys), k1_input = k1 / s and k2_input = k2 · s with s (operator
    /// units per input unit) ψ_in's mean slope over the fitted input range (exact for an
    /// affine ψ_in: 1 / half-span); None for a Prandtl–Ishlinskii model.
    #[getter]
    fn in_input_units<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let (py, me) = (slf.py(), borrow(slf)?);
        hyst_model::input_units(&me.file)
            .map(|k| to_python(py, &k))
            .transpose()
    }

    /// The parameters' standard errors by name (NaN where the data do not identify one).
    #[getter]
    fn std_errors<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let (py, me) = (slf.py(), borrow(slf)?);
        by_parameter(py, &me.file, |e| e.std_error)
    }

    /// The old name of `std_errors` (a DeprecationWarning).
    #[getter]
    fn stderr<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        errors::deprecated(slf.py(), "Model.stderr", "Model.std_errors")?;
        Self::std_errors(slf)
    }

    /// The parameters' units by name.
    #[getter]
    fn units<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let (py, me) = (slf.py(), borrow(slf)?);
        by_parameter(py, &me.file, |e| e.unit.clone())
    }

    /// The data columns the model was fitted on, with their units: {"input", "output",
    /// "input_unit", "output_unit", …}.
    #[getter]
    fn columns<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let (py, me) = (slf.py(), borrow(slf)?);
        let d = to_python(py, &me.file.columns)?;
        d.set_item("input_unit", &me.file.units.input)?;
        d.set_item("output_unit", &me.file.units.output)?;
        Ok(d)
    }

    /// The fit's error statistics ({"training": {...}, "validation": {...} or None, …}).
    #[getter]
    fn metrics<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let (py, me) = (slf.py(), borrow(slf)?);
        to_python(py, &me.file.metrics)
    }

    /// The family RH(k1, Δk1, k2, Δk2) that reproduces the data (Definition 2.8) with its
    /// bound, as a dict; None when the model has none or the family does not reach the
    /// coverage asked.
    #[getter]
    fn family<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let (py, me) = (slf.py(), borrow(slf)?);
        reached(&me.file).map(|w| to_python(py, w)).transpose()
    }

    /// Δa of the family (Proposition 3.2; operator units), None when there is no reached
    /// family.
    #[getter]
    fn delta_a(slf: &Bound<'_, Self>) -> PyResult<Option<f64>> {
        let me = borrow(slf)?;
        Ok(reached(&me.file).and_then(|w| w.delta_a))
    }

    /// The model file's text (TOML, docs/formats.md).
    fn to_toml(slf: &Bound<'_, Self>) -> PyResult<String> {
        borrow(slf)?.file.to_toml().map_err(errors::model)
    }

    /// The model as one header-only C99 file over `hyst.h` whose identifiers all start with
    /// `name` (`NAME_state`, `NAME_init`, `NAME_init_inverse`, `NAME_step`, `NAME_reset`,
    /// `NAME_params` and their `_f32` twins): the text `hyst export c` writes for the same
    /// model file (docs/c.md). For a model with dynamics it also holds the Lemma 5.1
    /// compensator with the fitted plant (`NAME_timed_compensator_*`), and with `period` (s)
    /// the forward model with its plant discretised for that period (`NAME_timed_*`), as
    /// `hyst export c --period`. Raises ValueError for a name that is not a C identifier or
    /// clashes with hyst.h's, and for a model the firmware cannot run (Prandtl–Ishlinskii, a
    /// rate term, a stop form with dynamics without `period`).
    #[pyo3(signature = (name, *, period=None))]
    fn export_c(slf: &Bound<'_, Self>, name: &str, period: Option<f64>) -> PyResult<String> {
        let me = borrow(slf)?;
        let options = hyst_codegen::Options { period };
        hyst_codegen::c_with(&me.file, name, &me.export_source(), &options).map_err(errors::model)
    }

    /// The model as `no_std` Rust over hyst-core (`NAME::<T>()`, `NAME_inverse::<T>()`,
    /// `NAME_clamp`): the text `hyst export rust` writes for the same model file (docs/c.md);
    /// for a model with dynamics also its compensator, and with `period` its forward model with
    /// the plant (`hyst export rust --period`). Raises ValueError for a name that is not an
    /// identifier, and for a model the export cannot run (a rate term, a stop form with
    /// dynamics without `period`).
    #[pyo3(signature = (name, *, period=None))]
    fn export_rust(slf: &Bound<'_, Self>, name: &str, period: Option<f64>) -> PyResult<String> {
        let me = borrow(slf)?;
        let options = hyst_codegen::Options { period };
        hyst_codegen::rust_with(&me.file, name, &me.export_source(), &options)
            .map_err(errors::model)
    }

    /// Writes the model file to `path` (atomically: a failed write leaves no partial file and
    /// an existing file untouched). Raises OSError when it cannot be written.
    fn save(slf: &Bound<'_, Self>, path: PathBuf) -> PyResult<()> {
        hyst_fit::file::write(&borrow(slf)?.file, &path).map_err(errors::fit)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Pickled)> {
        let me = borrow(slf)?;
        let restore = slf.py().import("hyst._hyst")?.getattr("_model_from_toml")?;
        Ok((
            restore,
            (
                me.file.to_toml().map_err(errors::model)?,
                me.inverse,
                me.source.clone(),
                me.saturate,
                me.source_fnv1a64,
            ),
        ))
    }

    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        let me = borrow(slf)?;
        Ok(format!(
            "Model(kind={:?}, source={:?}{})",
            me.kind_name(),
            me.source,
            match (me.inverse, me.saturate) {
                (true, true) => ", inverse, saturate",
                (true, false) => ", inverse",
                _ => "",
            }
        ))
    }
}

/// `hyst.load_model(path)`: reads and checks a model file written by `hyst fit` (or
/// `Model.save`). Raises OSError when the file cannot be read, ValueError when it is not a
/// valid model file (the message names the file and the problem).
#[pyfunction]
pub fn load_model(path: PathBuf) -> PyResult<Model> {
    let text = std::fs::read_to_string(&path).map_err(|e| errors::io(&path, "read", &e))?;
    let file = ModelFile::from_toml(&text, &path).map_err(errors::model)?;
    let mut model = Model::new(file, false, path.display().to_string());
    model.source_fnv1a64 = hyst_model::file::fnv1a64(text.as_bytes());
    Ok(model)
}

/// Rebuilds a model from its TOML text (what pickling a `Model` stores).
#[pyfunction(name = "_model_from_toml")]
#[pyo3(signature = (text, inverse=false, source="<toml>".to_string(), saturate=false, source_fnv1a64=None))]
pub fn model_from_toml(
    text: &str,
    inverse: bool,
    source: String,
    saturate: bool,
    source_fnv1a64: Option<u64>,
) -> PyResult<Model> {
    let file = ModelFile::from_toml(text, Path::new(&source)).map_err(errors::model)?;
    let mut model = Model::new(file, inverse, source);
    if let Some(m) = timed_model(&model.file).filter(|_| inverse) {
        return Err(model.no_inverse(m));
    }
    model.saturate = inverse && saturate;
    if let Some(h) = source_fnv1a64 {
        model.source_fnv1a64 = h;
    }
    Ok(model)
}
