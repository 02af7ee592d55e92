//! `hyst.Compensator`: feed-forward compensation of a plant whose linear dynamics come before
//! the hysteresis (Lemma 5.1, eqs. 18–20).

use hyst_core::compensator::Compensator as CoreCompensator;
use hyst_core::{AnyK2Law, Hysteresis as CoreHysteresis, ScaledShaping, ShapedModel};
use hyst_io::number::shortest;
use hyst_model::smooth::CoreInverseShapedModel;
use hyst_model::{ModelKind, TimedCompensator};
use numpy::ndarray::ArrayView1;
use pyo3::prelude::*;

use crate::arrays::{each_dtype, samples, signals, to_numpy, Refused, Stop, CHUNK};
use crate::errors::{borrow, borrow_mut, core, value_error, Shared};
use crate::model::Model;
use crate::operator::{Hysteresis, InverseHysteresis, Memory};

pub use hyst_core::compensator::MAX_ORDER;

type Shaping = ScaledShaping<f64>;
type Small = CoreCompensator<f64, 2, Shaping, AnyK2Law<f64>, Shaping>;
type Large = CoreCompensator<f64, MAX_ORDER, Shaping, AnyK2Law<f64>, Shaping>;

/// The core compensator: jets of 2 derivatives for n ≤ 2 (the paper's examples), of
/// [`MAX_ORDER`] above.
#[derive(Clone, Debug)]
enum Inner {
    Small(Box<Small>),
    Large(Box<Large>),
}

macro_rules! each {
    ($inner:expr, $c:ident => $e:expr) => {
        match $inner {
            Inner::Small($c) => $e,
            Inner::Large($c) => $e,
        }
    };
}

/// The Lemma 5.1 compensator for the plant x1(s)/u(s) = b / (a_n sⁿ + … + a_1 s + 1) (eq. 18)
/// followed by the hysteresis `model` (a smooth `Model`, `Hysteresis(k1, k2)` or
/// `InverseHysteresis(k1, k2)`, which stands for the same H(k1, k2)).
///
/// `Compensator(model, b=None, a=None, state=None)`: `b` ≠ 0 is the plant gain,
/// `a = [a_1, …, a_n]` the denominator coefficients (n ≤ `hyst.MAX_ORDER`; n = 0 is a static
/// plant; both required unless `model` brings its own, below), `state` the
/// integrators' start (v, v̇, …, v⁽ⁿ⁻¹⁾) (default 0). Each `step(u_new, dt)` takes the new
/// input u_new = v⁽ⁿ⁾ (the n-th derivative of the reference v, the desired output), evaluates
/// the exact inverse model on the jet (v, …, v⁽ⁿ⁾), which gives the target x1 and its
/// derivatives, and returns the plant command of eq. (19),
/// u = (1/b)(x1 + a_1 ẋ1 + … + a_n x1⁽ⁿ⁾); then it integrates u_new over `dt` (s, ≥ 0). With
/// the exact model the plant output follows v (eq. 20 with Δ = 0); with a hysteresis
/// reproduced by a family, within the family's Δa. `last_reference`, `last_target` and
/// `last_command` are v, x1 and u of the last step.
///
/// A `Model` with dynamics brings its own plant: `Compensator(model)` takes b and a from it
/// (`Model.dynamics`; giving them too raises ValueError), and with `derivatives` equal to the
/// integrators' jet its commands are `Model.compensate`'s. A model with a rate term or of the
/// stop form has no compensator (ValueError, as `compensate`). `state` and `memory` read and
/// restore the whole state (`hyst.control.iosys` keeps it as its state vector); `copy.copy`
/// copies it.
#[pyclass(module = "hyst")]
pub struct Compensator {
    inner: Inner,
    b: f64,
    a: Vec<f64>,
}

impl Shared for Compensator {
    const OWN: &'static str = "one Compensator holds the state of one plant, so give each thread \
                               its own object (copy.copy(compensator), which goes on from the \
                               same state independently)";
}

/// The plant a `Model` with dynamics brings (b, [a_1, …, a_n]); `None` for anything else. A
/// model whose compensator Lemma 5.1 cannot give (a rate term, the stop form) is refused here,
/// in the words of `Model.compensate`.
fn own_plant(model: &Bound<'_, PyAny>) -> PyResult<Option<(f64, Vec<f64>)>> {
    let Ok(m) = model.cast::<Model>() else {
        return Ok(None);
    };
    let m = borrow(m)?;
    match (m.file.kind, &m.file.smooth) {
        (ModelKind::Smooth, Some(s)) if s.is_timed() => {
            TimedCompensator::check(s).map_err(crate::errors::model)?;
            Ok(s.dynamics.map(|d| (d.b, d.a().to_vec())))
        }
        _ => Ok(None),
    }
}

/// The plant (b, a) of a compensator: given, or the model's own.
fn plant_of(
    model: &Bound<'_, PyAny>,
    b: Option<f64>,
    a: Option<Vec<f64>>,
) -> PyResult<(f64, Vec<f64>)> {
    match (own_plant(model)?, b, a) {
        (Some(plant), None, None) => Ok(plant),
        (Some((b, a)), _, _) => {
            let a: Vec<String> = a.iter().map(|x| shortest(*x)).collect();
            Err(value_error(format!(
                "b, a: the model has its own plant (dynamics of order {}: b = {}, a = [{}]), \
                 which its compensator takes: give neither (Compensator(model)), or give the \
                 hysteresis part another plant: Compensator(model.hysteresis, b, a)",
                a.len(),
                shortest(b),
                a.join(", ")
            )))
        }
        (None, Some(b), Some(a)) => Ok((b, a)),
        (None, _, _) => Err(value_error(
            "b and a: give the plant gain b and the denominator coefficients a = [a_1, ..., a_n] \
             of eq. (18) (a = [] for a static plant); only a Model with dynamics brings its own",
        )),
    }
}

fn inverse_of(model: &Bound<'_, PyAny>, v0: f64) -> PyResult<CoreInverseShapedModel> {
    if let Ok(m) = model.cast::<Model>() {
        let m = borrow(m)?;
        let smooth = match (m.file.kind, &m.file.smooth) {
            (ModelKind::Smooth, Some(s)) => *s,
            _ => {
                return Err(value_error(format!(
                    "model: {} is a Prandtl-Ishlinskii model; Lemma 5.1 needs the smooth \
                     model's derivatives (fit with model_kind=\"smooth\")",
                    m.source
                )))
            }
        };
        return smooth.inverse_from_desired(v0).map_err(|e| match e {
            hyst_model::ModelError::Core(e) => core(
                format!("state: v = {} is not reachable by the model", shortest(v0)),
                e,
            ),
            e => crate::errors::model(e),
        });
    }
    let (k1, k2) = if let Ok(h) = model.cast::<Hysteresis>() {
        let h = borrow(h)?;
        (h.engine.k1(), h.engine.k2())
    } else if let Ok(h) = model.cast::<InverseHysteresis>() {
        let h = borrow(h)?;
        (h.engine.k1(), h.engine.k2())
    } else {
        return Err(value_error(format!(
            "model: expected a hyst.Model, hyst.Hysteresis or hyst.InverseHysteresis, got {}",
            model
                .get_type()
                .name()
                .map_or_else(|_| "?".into(), |n| n.to_string())
        )));
    };
    let operator = CoreHysteresis::with_k2_law(k1, AnyK2Law::Constant { value: k2 })
        .map_err(|e| core("model", e))?;
    ShapedModel::new(Shaping::identity(), operator, Shaping::identity())
        .map(|m| m.inverse())
        .map_err(|e| core("model", e))
}

#[pymethods]
impl Compensator {
    #[new]
    #[pyo3(signature = (model, b=None, a=None, state=None))]
    fn new(
        model: &Bound<'_, PyAny>,
        b: Option<f64>,
        a: Option<Vec<f64>>,
        state: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        let (b, a) = plant_of(model, b, a)?;
        if a.len() > MAX_ORDER {
            return Err(value_error(format!(
                "a has {} coefficients: the plant order n = len(a) must be at most \
                 hyst.MAX_ORDER = {MAX_ORDER}",
                a.len()
            )));
        }
        if let Some(s) = &state {
            if s.len() != a.len() {
                return Err(value_error(format!(
                    "state has {} values: give n = len(a) = {} (v, v', ...)",
                    s.len(),
                    a.len()
                )));
            }
        }
        let v0 = state
            .as_ref()
            .and_then(|s| s.first().copied())
            .unwrap_or(0.0);
        let inverse = inverse_of(model, v0)?;
        let context = |e| {
            let a: Vec<String> = a.iter().map(|x| shortest(*x)).collect();
            core(
                format!("Compensator(b={}, a=[{}])", shortest(b), a.join(", ")),
                e,
            )
        };
        let mut inner = if a.len() <= 2 {
            Inner::Small(Box::new(
                Small::with_order(inverse, b, &a).map_err(context)?,
            ))
        } else {
            Inner::Large(Box::new(
                Large::with_order(inverse, b, &a).map_err(context)?,
            ))
        };
        if let Some(s) = &state {
            let check = |e| core(format!("state = {s:?}"), e);
            inner = match inner {
                Inner::Small(c) => {
                    let mut st = [0.0; 2];
                    for (slot, v) in st.iter_mut().zip(s) {
                        *slot = *v;
                    }
                    Inner::Small(Box::new(c.with_state(st).map_err(check)?))
                }
                Inner::Large(c) => {
                    let mut st = [0.0; MAX_ORDER];
                    for (slot, v) in st.iter_mut().zip(s) {
                        *slot = *v;
                    }
                    Inner::Large(Box::new(c.with_state(st).map_err(check)?))
                }
            };
        }
        Ok(Self { inner, b, a })
    }

    /// One sample: the plant command u for the new input u_new = v⁽ⁿ⁾ (held over the next
    /// `dt` seconds, dt ≥ 0). Raises ValueError for a non-finite value or a reference the
    /// model cannot produce (the compensator is then unchanged).
    fn step(slf: &Bound<'_, Self>, u_new: f64, dt: f64) -> PyResult<f64> {
        check_dt(dt)?;
        each!(&mut borrow_mut(slf)?.inner, c => c.try_step(u_new, dt)).map_err(|e| {
            core(
                format!("u_new = {}, dt = {}", shortest(u_new), shortest(dt)),
                e,
            )
        })
    }

    /// `step` over every sample of `u_new` (a 1-D array-like, float32 stays float32) with the
    /// fixed step `dt`: the commands. At a refused sample raises ValueError naming its index,
    /// and the compensator is as it was before the call.
    fn process<'py>(
        slf: &Bound<'py, Self>,
        u_new: &Bound<'py, PyAny>,
        dt: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        check_dt(dt)?;
        fn go<X: hyst_core::Real>(
            inner: &mut Inner,
            xs: ArrayView1<'_, X>,
            dt: f64,
        ) -> Result<Vec<X>, Stop> {
            let saved = inner.clone();
            let mut out = Vec::with_capacity(xs.len());
            for (index, x) in xs.iter().enumerate() {
                let step = if index > 0 && index % CHUNK == 0 {
                    signals()
                } else {
                    Ok(())
                }
                .and_then(|()| {
                    each!(&mut *inner, c => c.try_step(x.as_f64(), dt)).map_err(|error| {
                        Stop::Refused(Refused {
                            index,
                            value: x.as_f64(),
                            error,
                        })
                    })
                });
                match step {
                    Ok(u) => out.push(X::from_f64(u)),
                    Err(e) => {
                        *inner = saved;
                        return Err(e);
                    }
                }
            }
            Ok(out)
        }
        let refused = |stop: Stop| match stop {
            Stop::Refused(r) => core(
                format!(
                    "u_new[{}] = {}, dt = {}",
                    r.index,
                    shortest(r.value),
                    shortest(dt)
                ),
                r.error,
            ),
            Stop::Interrupted(e) => e,
        };
        let py = slf.py();
        let mut me = borrow_mut(slf)?;
        let inner = &mut me.inner;
        each_dtype!(samples(u_new, "u_new")?, a => {
            let view = a.as_array();
            let out = py.detach(|| go(inner, view, dt)).map_err(refused)?;
            Ok(to_numpy(py, out))
        })
    }

    /// Back to the start state (the integrators' `state`, the inverse model's history).
    fn reset(slf: &Bound<'_, Self>) -> PyResult<()> {
        each!(&mut borrow_mut(slf)?.inner, c => c.reset());
        Ok(())
    }

    /// The plant order n = len(a).
    #[getter]
    fn order(slf: &Bound<'_, Self>) -> PyResult<usize> {
        Ok(borrow(slf)?.a.len())
    }

    /// The plant gain b.
    #[getter]
    fn b(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(borrow(slf)?.b)
    }

    /// The denominator coefficients [a_1, …, a_n].
    #[getter]
    fn a(slf: &Bound<'_, Self>) -> PyResult<Vec<f64>> {
        Ok(borrow(slf)?.a.clone())
    }

    /// The integrators' state (v, v̇, …, v⁽ⁿ⁻¹⁾) now: n floats (output units and their time
    /// derivatives). Assigning n finite floats sets it (the next `step` integrates from
    /// there); ValueError for another count or a non-finite value, and nothing changes.
    /// With `memory`, the whole state: saved and assigned back (to this compensator or a copy
    /// of it), the compensator goes on bit for bit.
    #[getter]
    fn get_state(slf: &Bound<'_, Self>) -> PyResult<Vec<f64>> {
        let me = borrow(slf)?;
        let n = me.a.len();
        Ok(match &me.inner {
            Inner::Small(c) => c.state().iter().take(n).copied().collect(),
            Inner::Large(c) => c.state().iter().take(n).copied().collect(),
        })
    }

    #[setter]
    fn set_state(slf: &Bound<'_, Self>, state: Vec<f64>) -> PyResult<()> {
        let mut me = borrow_mut(slf)?;
        let n = me.a.len();
        if state.len() != n {
            return Err(value_error(format!(
                "state has {} values: give n = len(a) = {n} (v, v', ...)",
                state.len()
            )));
        }
        let check = |e| core(format!("state = {state:?}"), e);
        each!(&mut me.inner, c => {
            let mut saved = c.saved_state();
            for (slot, v) in saved.integrators.iter_mut().zip(&state) {
                *slot = *v;
            }
            c.restore_state(&saved).map_err(check)
        })
    }

    /// The memory of the compensator's inverse model (Definition 2.1): a `hyst.Memory` of
    /// H⁻¹ in operator units (reversal_input, last_input: ψ_out⁻¹(v); reversal_output,
    /// last_output: ψ_in of the target x1), as `Model.memory` of the inverse model gives it;
    /// None before any history. A new compensator of a `Model` already has the memory its
    /// start rule gives at v = state[0]. Assigning one restores it (None forgets the history);
    /// ValueError for a memory the inverse cannot be in (outside the band |output − input| ≤
    /// k1, non-finite), and nothing changes.
    #[getter]
    fn get_memory(slf: &Bound<'_, Self>) -> PyResult<Option<Memory>> {
        let me = borrow(slf)?;
        let m = each!(&me.inner, c => c.saved_state().memory);
        Ok(m.map(|inner| Memory { inner }))
    }

    #[setter]
    fn set_memory(slf: &Bound<'_, Self>, memory: Option<PyRef<'_, Memory>>) -> PyResult<()> {
        let mut me = borrow_mut(slf)?;
        let m = memory.as_deref().map(|m| m.inner);
        each!(&mut me.inner, c => {
            let mut saved = c.saved_state();
            saved.memory = m;
            c.restore_state(&saved).map_err(|e| core("memory", e))
        })
    }

    /// A copy with the same model, plant and whole state (integrators, memory, last step): it
    /// goes on as this one does, independently.
    fn __copy__(slf: &Bound<'_, Self>) -> PyResult<Self> {
        let me = borrow(slf)?;
        Ok(Self {
            inner: me.inner.clone(),
            b: me.b,
            a: me.a.clone(),
        })
    }

    /// As `__copy__` (a compensator holds no Python objects).
    fn __deepcopy__(slf: &Bound<'_, Self>, _memo: &Bound<'_, PyAny>) -> PyResult<Self> {
        Self::__copy__(slf)
    }

    /// The reference v of the last step: the plant output the command aims at (u_new
    /// integrated n times; u_new itself for n = 0).
    #[getter]
    fn last_reference(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&borrow(slf)?.inner, c => c.last_reference()))
    }

    /// The target x1 of the last step: the hysteresis input (the plant state x1 of eq. 18)
    /// that the exact inverse model gives for the reference v, x1 = ψ_in⁻¹(H⁻¹[ψ_out⁻¹(v)]).
    #[getter]
    fn last_target(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&borrow(slf)?.inner, c => c.last_target().value()))
    }

    /// The command u of the last step (eq. 19): the plant input.
    #[getter]
    fn last_command(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&borrow(slf)?.inner, c => c.last_command()))
    }

    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        let me = borrow(slf)?;
        Ok(format!(
            "Compensator(order={}, b={:?}, a={:?})",
            me.a.len(),
            me.b,
            me.a
        ))
    }
}

/// A compensator's time step: finite and ≥ 0 seconds (the core would call a bad one a
/// non-finite input sample).
fn check_dt(dt: f64) -> PyResult<()> {
    if dt.is_finite() && dt >= 0.0 {
        Ok(())
    } else {
        Err(crate::errors::value_error(format!(
            "dt = {}: the time step must be finite and >= 0 seconds",
            shortest(dt)
        )))
    }
}
