//! `hyst.Bank`: N operators H(k1[c], k2[c]) (or H⁻¹), each with its own memory, stepped
//! together in SIMD lanes (the core's `BankVec`), in float64 or float32.
//!
//! Arrays: `.step(x)` takes a 1-D array of one value per channel; `.process(X)` a 2-D array of
//! shape (ticks, channels), row t being tick t. A C-contiguous array of the bank's dtype is
//! read in place and goes straight to the core's time-major `process`; any other layout
//! (Fortran order, strided views) is read tick block by tick block into a time-major buffer.
//! Results are in the bank's dtype.

use hyst_bank::{BankError, BankFormula, BankVec, Lane};
use hyst_core::{Direct, Error, Inverse, Memory as CoreMemory, Real};
use numpy::ndarray::{ArrayView2, ArrayViewMut2, Axis, Dimension, Slice};
use numpy::{
    Element, PyArray, PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArray,
    PyReadwriteArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::PyType;

use crate::arrays::{as_dtype, shape_of, signals, Stop, CHUNK};
use crate::errors::{self, borrow_mut, value_error, Shared};
use crate::operator::{from_core, to_core, Memory, Precision};

/// The core bank in the chosen formula and precision.
#[derive(Clone, Debug)]
enum Engine {
    D64(BankVec<f64, Direct>),
    I64(BankVec<f64, Inverse>),
    D32(BankVec<f32, Direct>),
    I32(BankVec<f32, Inverse>),
}

/// Runs `$e` with `$b` bound to the bank, whichever formula and precision it has.
macro_rules! each {
    ($engine:expr, $b:ident => $e:expr) => {
        match $engine {
            Engine::D64($b) => $e,
            Engine::I64($b) => $e,
            Engine::D32($b) => $e,
            Engine::I32($b) => $e,
        }
    };
}

/// Runs `$e` with `$b` bound to the bank and `$t` to its float type, for the float64 and the
/// float32 banks separately (numpy arrays are typed).
macro_rules! typed {
    ($engine:expr, $b:ident, $t:ident => $e:expr) => {
        match $engine {
            Engine::D64($b) => {
                type $t = f64;
                $e
            }
            Engine::I64($b) => {
                type $t = f64;
                $e
            }
            Engine::D32($b) => {
                type $t = f32;
                $e
            }
            Engine::I32($b) => {
                type $t = f32;
                $e
            }
        }
    };
}

/// Why a run stopped: the bank refused a sample at (tick, channel) of the array, or Ctrl-C.
enum Refusal {
    /// A sample: its tick (in the array), channel, value and the core's reason.
    Sample {
        tick: usize,
        channel: usize,
        value: f64,
        error: Error,
    },
    /// A signal handler's exception.
    Interrupted(PyErr),
}

impl Refusal {
    /// `ValueError("{name}[tick, channel] = value (channel c): reason")`; `one_tick` leaves the
    /// tick out (the argument of `.step` is 1-D).
    fn into_err(self, name: &str, one_tick: bool) -> PyErr {
        match self {
            Refusal::Sample {
                tick,
                channel,
                value,
                error,
            } => {
                let index = if one_tick {
                    format!("{channel}")
                } else {
                    format!("{tick}, {channel}")
                };
                value_error(format!(
                    "{name}[{index}] = {value:?} (channel {channel}): {error}"
                ))
            }
            Refusal::Interrupted(e) => e,
        }
    }
}

/// Every channel's memory, to restore after a refused call.
fn memories<T: Lane, F: BankFormula>(b: &BankVec<T, F>) -> Vec<Option<CoreMemory<T>>> {
    (0..b.channels()).map(|c| b.memory(c)).collect()
}

fn restore<T: Lane, F: BankFormula>(b: &mut BankVec<T, F>, saved: Vec<Option<CoreMemory<T>>>) {
    for (c, m) in saved.into_iter().enumerate() {
        // Memories the channels were in: valid.
        let _ = b.set_memory(c, m);
    }
}

/// Runs the ticks `x` (time-major, the first being tick `first` of the array) into `y`: the
/// first non-finite sample, or the first output beyond the float range, is refused with its
/// place (the caller restores the memories).
fn ticks<T: Lane, F: BankFormula>(
    b: &mut BankVec<T, F>,
    x: &[T],
    y: &mut [T],
    first: usize,
) -> Result<(), Refusal> {
    let n = b.channels().max(1);
    let refuse = |i: usize, error: Error| Refusal::Sample {
        tick: first + i / n,
        channel: i % n,
        value: x.get(i).map_or(f64::NAN, |v| v.as_f64()),
        error,
    };
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        let value = x.get(i).map_or(f64::NAN, |v| v.as_f64());
        return Err(refuse(i, Error::NonFiniteInput { value }));
    }
    // With the inputs finite, only an input or k1 near the float range can fail (an output
    // beyond it). The core stops a block at its failing tick without naming the tick, so such
    // ticks run one by one: `step` refuses a tick with every memory unchanged.
    let near = |v: &T| v.abs() > T::max_value() / T::from_f64(8.0);
    if x.iter().any(near) || b.k1().iter().any(near) {
        for (t, (row, out)) in x.chunks(n).zip(y.chunks_mut(n)).enumerate() {
            b.step(row, out)
                .map_err(|BankError { channel, error }| refuse(t * n + channel, error))?;
        }
    } else {
        b.process(x, y)
            .map_err(|BankError { channel, error }| refuse(channel, error))?;
    }
    if let Some(i) = y.iter().position(|v| !v.is_finite()) {
        let output = y.get(i).map_or(f64::NAN, |v| v.as_f64());
        let input = x.get(i).map_or(f64::NAN, |v| v.as_f64());
        return Err(refuse(i, Error::NonFiniteOutput { input, output }));
    }
    Ok(())
}

/// Runs the array `x` of shape (ticks, channels) into `y` (the same shape), [`CHUNK`]
/// channel-samples at a time with a check for Ctrl-C between them. A C-contiguous pair goes
/// straight through; other layouts through time-major buffers. On a refusal every memory is
/// restored and `y` holds the ticks before the chunk that failed.
fn run_array<T: Lane + Element, F: BankFormula>(
    b: &mut BankVec<T, F>,
    x: ArrayView2<'_, T>,
    mut y: ArrayViewMut2<'_, T>,
) -> Result<(), Refusal> {
    let saved = memories(b);
    let n = b.channels().max(1);
    let per = (CHUNK / n).max(1);
    let total = x.nrows();
    let mut xs = Vec::new();
    let mut ys = Vec::new();
    let mut t = 0;
    while t < total {
        let end = (t + per).min(total);
        if t > 0 {
            if let Err(e) = signals() {
                restore(b, saved);
                return Err(match e {
                    Stop::Interrupted(e) => Refusal::Interrupted(e),
                    Stop::Refused(r) => Refusal::Interrupted(r.into_err("x")),
                });
            }
        }
        let xv = x.slice_axis(Axis(0), Slice::from(t..end));
        let mut yv = y.slice_axis_mut(Axis(0), Slice::from(t..end));
        let done = match (xv.as_slice(), yv.as_slice_mut()) {
            (Some(xs), Some(ys)) => ticks(b, xs, ys, t),
            _ => {
                xs.clear();
                xs.extend(xv.iter().copied());
                ys.clear();
                ys.resize(xs.len(), T::zero());
                let done = ticks(b, &xs, &mut ys, t);
                for (slot, v) in yv.iter_mut().zip(&ys) {
                    *slot = *v;
                }
                done
            }
        };
        if let Err(e) = done {
            restore(b, saved);
            return Err(e);
        }
        t = end;
    }
    Ok(())
}

/// A bank of operators: channel c is H(k1[c], k2[c]) (eq. 2), or H⁻¹(k1[c], k2[c]) (eq. 4)
/// with `inverse=True`, each with its own memory, all stepped together in SIMD lanes (a
/// deformable mirror's actuators, the axes of a stage).
///
/// `Bank(k1, k2, inverse=False, dtype=None)`: k1 and k2 are 1-D array-likes of one value per
/// channel (finite, > 0); `dtype` float64 (default) or float32 chooses the arithmetic, and the
/// dtype of the results. A channel's outputs agree with `Hysteresis(k1[c], k2[c])` (or
/// `InverseHysteresis`) to a few ulp, not bit for bit: the bank has its own exp, ln and ω.
#[pyclass(module = "hyst")]
#[derive(Clone, Debug)]
pub struct Bank {
    engine: Engine,
}

impl Shared for Bank {
    const OWN: &'static str = "one Bank holds the memories of its channels, so give each thread \
                               its own object (copy.copy(bank))";
}

/// The constructor arguments of a `Bank`, as pickling stores them.
type BankArgs = (Vec<f64>, Vec<f64>, bool, &'static str);

/// `k1` or `k2` as float64 values, one per channel.
fn parameters(v: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    let a = as_dtype(v, name, "float64")?;
    let Ok(a) = a.cast::<PyArray1<f64>>() else {
        return Err(value_error(format!(
            "{name}: expected a 1-D array of one value per channel, got shape {}",
            shape_of(&a)
        )));
    };
    let ro = a
        .try_readonly()
        .map_err(|e| value_error(format!("{name}: the array cannot be read: {e}")))?;
    Ok(ro.as_array().iter().copied().collect())
}

impl Bank {
    fn build(k1: Vec<f64>, k2: Vec<f64>, inverse: bool, precision: Precision) -> PyResult<Self> {
        if k1.len() != k2.len() {
            return Err(value_error(format!(
                "k1 has {} values and k2 {}: give one of each per channel",
                k1.len(),
                k2.len()
            )));
        }
        if k1.is_empty() {
            return Err(value_error("k1, k2: no channels (empty arrays)"));
        }
        let wrap = |e: BankError, p: Precision| {
            let as32 = if p == Precision::F32 {
                " (as float32)"
            } else {
                ""
            };
            let value = |v: &[f64]| v.get(e.channel).copied().unwrap_or(f64::NAN);
            value_error(format!(
                "k1[{c}] = {:?}, k2[{c}] = {:?}{as32} (channel {c}): {}",
                value(&k1),
                value(&k2),
                e.error,
                c = e.channel
            ))
        };
        // The parameters must be valid in float64, and in the precision that computes.
        BankVec::<f64, Direct>::from_vecs(k1.clone(), k2.clone())
            .map_err(|e| wrap(e, Precision::F64))?;
        let k32 = |v: &[f64]| v.iter().map(|x| *x as f32).collect::<Vec<f32>>();
        let f32s = |e| wrap(e, Precision::F32);
        let engine = match (precision, inverse) {
            (Precision::F64, false) => Engine::D64(
                BankVec::from_vecs(k1.clone(), k2.clone()).map_err(|e| wrap(e, precision))?,
            ),
            (Precision::F64, true) => Engine::I64(
                BankVec::from_vecs(k1.clone(), k2.clone()).map_err(|e| wrap(e, precision))?,
            ),
            (Precision::F32, false) => {
                Engine::D32(BankVec::from_vecs(k32(&k1), k32(&k2)).map_err(f32s)?)
            }
            (Precision::F32, true) => {
                Engine::I32(BankVec::from_vecs(k32(&k1), k32(&k2)).map_err(f32s)?)
            }
        };
        Ok(Self { engine })
    }

    /// The number of channels.
    fn count(&self) -> usize {
        each!(&self.engine, b => b.channels())
    }

    /// Whether the channels are inverse operators.
    fn is_inverse(&self) -> bool {
        matches!(self.engine, Engine::I64(_) | Engine::I32(_))
    }

    /// The memory of the channel `c` (in range).
    fn memory_of(&self, c: usize) -> Option<Memory> {
        each!(&self.engine, b => b.memory(c).map(|m| from_core(&m))).map(|inner| Memory { inner })
    }

    /// `set_memory(channel, memory)`.
    fn put_memory(&mut self, channel: isize, memory: Option<&Memory>) -> PyResult<()> {
        let c = self.channel(channel)?;
        let m = memory.map(|m| m.inner);
        let wrap = |e: BankError| value_error(format!("memory of channel {c}: {}", e.error));
        match &mut self.engine {
            Engine::D64(b) => b.set_memory(c, m).map_err(wrap),
            Engine::I64(b) => b.set_memory(c, m).map_err(wrap),
            Engine::D32(b) => b.set_memory(c, m.map(|m| to_core(&m))).map_err(wrap),
            Engine::I32(b) => b.set_memory(c, m.map(|m| to_core(&m))).map_err(wrap),
        }
    }

    fn precision(&self) -> Precision {
        match self.engine {
            Engine::D64(_) | Engine::I64(_) => Precision::F64,
            Engine::D32(_) | Engine::I32(_) => Precision::F32,
        }
    }

    fn channel(&self, channel: isize) -> PyResult<usize> {
        let n = self.count();
        usize::try_from(channel)
            .ok()
            .filter(|c| *c < n)
            .ok_or_else(|| {
                PyIndexError::new_err(format!(
                    "channel {channel}: the bank has channels 0 to {}",
                    n.saturating_sub(1)
                ))
            })
    }

    fn parameters(&self, k1: bool) -> Vec<f64> {
        each!(&self.engine, b => {
            let v = if k1 { b.k1() } else { b.k2() };
            v.iter().map(|x| x.as_f64()).collect()
        })
    }

    fn memories(&self) -> Vec<Option<Memory>> {
        (0..self.count()).map(|c| self.memory_of(c)).collect()
    }
}

/// `numpy.asarray(x, dtype)`; for float32, a finite value beyond its range is refused with
/// its index (numpy would make it infinite, with only a warning).
fn converted<'py>(x: &Bound<'py, PyAny>, name: &str, dtype: &str) -> PyResult<Bound<'py, PyAny>> {
    let a = as_dtype(x, name, "float64")?;
    if dtype == "float32" {
        if let Ok(wide) = a.cast::<PyArrayDyn<f64>>() {
            let ro = wide
                .try_readonly()
                .map_err(|e| value_error(format!("{name}: the array cannot be read: {e}")))?;
            let beyond = ro
                .as_array()
                .indexed_iter()
                .find(|(_, v)| v.is_finite() && v.abs() > f64::from(f32::MAX))
                .map(|(i, v)| (i.slice().to_vec(), *v));
            if let Some((index, value)) = beyond {
                let at: Vec<String> = index.iter().map(ToString::to_string).collect();
                return Err(value_error(format!(
                    "{name}[{}] = {value:e}: beyond the float32 range of the bank",
                    at.join(", ")
                )));
            }
        }
    }
    as_dtype(&a, name, dtype)
}

/// Reads `x` as a 2-D array of the type `T` (converted by numpy when it is not).
fn array2<'py, T: Element>(
    x: &Bound<'py, PyAny>,
    name: &str,
    dtype: &str,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    let a = match x.cast::<PyArray2<T>>() {
        Ok(a) => a.clone(),
        Err(_) => {
            let a = converted(x, name, dtype)?;
            a.cast::<PyArray2<T>>().cloned().map_err(|_| {
                value_error(format!(
                    "{name}: expected a 2-D array of shape (ticks, channels), got shape {}",
                    shape_of(&a)
                ))
            })?
        }
    };
    Ok(a)
}

/// Read access to `x` and write access to `out` (a different array).
fn borrow<'py, T: Element, D: Dimension>(
    x: &Bound<'py, PyArray<T, D>>,
    out: &Bound<'py, PyArray<T, D>>,
) -> PyResult<(PyReadonlyArray<'py, T, D>, PyReadwriteArray<'py, T, D>)> {
    if out.is(x) {
        return Err(value_error(
            "out: must not be x (the outputs would overwrite the samples as they are read)",
        ));
    }
    let ro = x
        .try_readonly()
        .map_err(|e| value_error(format!("x: the array cannot be read: {e}")))?;
    let rw = out.try_readwrite().map_err(|e| {
        value_error(format!(
            "out: the array cannot be written (or overlaps x): {e}"
        ))
    })?;
    Ok((ro, rw))
}

/// Reads `x` as a 1-D array of the type `T`.
fn array1<'py, T: Element>(
    x: &Bound<'py, PyAny>,
    name: &str,
    dtype: &str,
) -> PyResult<Bound<'py, PyArray1<T>>> {
    match x.cast::<PyArray1<T>>() {
        Ok(a) => Ok(a.clone()),
        Err(_) => {
            let a = converted(x, name, dtype)?;
            a.cast::<PyArray1<T>>().cloned().map_err(|_| {
                value_error(format!(
                    "{name}: expected a 1-D array of one sample per channel, got shape {}",
                    shape_of(&a)
                ))
            })
        }
    }
}

/// The caller's `out=` or a new array of `shape`, checked: the bank's dtype, that shape,
/// writable.
fn output<'py, T: Element>(
    py: Python<'py>,
    out: Option<&Bound<'py, PyAny>>,
    shape: &[usize],
    dtype: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let Some(o) = out.filter(|o| !o.is_none()) else {
        return Ok(match shape {
            [n] => PyArray1::<T>::zeros(py, *n, false).into_any(),
            [t, n] => PyArray2::<T>::zeros(py, [*t, *n], false).into_any(),
            _ => return Err(value_error("out: unsupported shape")),
        });
    };
    let fits = match shape {
        [_] => o.cast::<PyArray1<T>>().is_ok(),
        _ => o.cast::<PyArray2<T>>().is_ok(),
    };
    let dims = o
        .getattr("shape")
        .and_then(|s| s.extract::<Vec<usize>>())
        .unwrap_or_default();
    if !fits || dims != shape {
        return Err(value_error(format!(
            "out: expected a {dtype} array of shape {shape:?}, got {} of shape {}{}",
            o.get_type()
                .name()
                .map_or_else(|_| "?".into(), |n| n.to_string()),
            shape_of(o),
            o.getattr("dtype")
                .and_then(|d| d.str())
                .map_or_else(|_| String::new(), |d| format!(" and dtype {d}"))
        )));
    }
    Ok(o.clone())
}

#[pymethods]
impl Bank {
    #[new]
    #[pyo3(signature = (k1, k2, inverse=false, dtype=None))]
    fn py_new(
        k1: &Bound<'_, PyAny>,
        k2: &Bound<'_, PyAny>,
        inverse: bool,
        dtype: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let precision = Precision::from_dtype(dtype)?;
        Self::build(
            parameters(k1, "k1")?,
            parameters(k2, "k2")?,
            inverse,
            precision,
        )
    }

    /// The number of channels.
    #[getter]
    fn channels(slf: &Bound<'_, Self>) -> PyResult<usize> {
        Ok(errors::borrow(slf)?.count())
    }

    /// The channels' k1 (a new float64 array).
    #[getter]
    fn k1<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let k1 = errors::borrow(slf)?.parameters(true);
        Ok(PyArray1::from_vec(slf.py(), k1))
    }

    /// The channels' k2 (a new float64 array).
    #[getter]
    fn k2<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let k2 = errors::borrow(slf)?.parameters(false);
        Ok(PyArray1::from_vec(slf.py(), k2))
    }

    /// Whether the channels are the inverse operators H⁻¹ (eq. 4).
    #[getter]
    fn inverse(slf: &Bound<'_, Self>) -> PyResult<bool> {
        Ok(errors::borrow(slf)?.is_inverse())
    }

    /// The arithmetic and the dtype of the results: "float64" or "float32".
    #[getter]
    fn dtype(slf: &Bound<'_, Self>) -> PyResult<&'static str> {
        Ok(errors::borrow(slf)?.precision().name())
    }

    /// One tick: `x` holds one sample per channel (a 1-D array-like of length `channels`);
    /// returns the outputs as a 1-D array of the bank's dtype, or writes them into `out` (a
    /// 1-D array of that dtype and length, not x) and returns it.
    ///
    /// Raises ValueError for a NaN or infinite sample (or an output beyond the float range),
    /// naming its channel and value; every memory is then as before the call.
    #[pyo3(signature = (x, *, out=None))]
    fn step<'py>(
        slf: &Bound<'py, Self>,
        x: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let mut me = borrow_mut(slf)?;
        let (n, dtype) = (me.count(), me.precision().name());
        typed!(&mut me.engine, b, T => {
            let a = array1::<T>(x, "x", dtype)?;
            if a.len() != n {
                return Err(value_error(format!(
                    "x: {} samples for a bank of {n} channels (one per channel)",
                    a.len()
                )));
            }
            let result = output::<T>(py, out, &[n], dtype)?;
            let (ro, mut rw) = borrow(&a, result.cast::<PyArray1<T>>()?)?;
            let (xv, yv) = (ro.as_array().insert_axis(Axis(0)), rw.as_array_mut().insert_axis(Axis(0)));
            run_array(b, xv, yv).map_err(|e| e.into_err("x", true))?;
            Ok(result)
        })
    }

    /// A block of ticks: `x` of shape (ticks, channels), row t the samples of tick t (a
    /// C-ordered array is time-major, the layout a controller produces; it is read in place
    /// when it has the bank's dtype; any other order or stride is accepted and read through a
    /// buffer). Returns the outputs in an array of the same shape and the bank's dtype, or
    /// writes them into `out` (that shape and dtype, not x) and returns it. The GIL is released
    /// meanwhile; Ctrl-C stops a long call with KeyboardInterrupt.
    ///
    /// Raises ValueError at the first NaN or infinite sample (or output beyond the float
    /// range), naming its tick, channel and value; every memory is then as before the call
    /// (and `out` may hold partial results).
    #[pyo3(signature = (x, *, out=None))]
    fn process<'py>(
        slf: &Bound<'py, Self>,
        x: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let mut me = borrow_mut(slf)?;
        let (n, dtype) = (me.count(), me.precision().name());
        typed!(&mut me.engine, b, T => {
            let a = array2::<T>(x, "x", dtype)?;
            let shape = a.shape().to_vec();
            let ticks_n = shape.first().copied().unwrap_or(0);
            if shape.get(1).copied() != Some(n) {
                return Err(value_error(format!(
                    "x: shape {} for a bank of {n} channels: expected (ticks, {n})",
                    shape_of(&a)
                )));
            }
            let result = output::<T>(py, out, &[ticks_n, n], dtype)?;
            let (ro, mut rw) = borrow(&a, result.cast::<PyArray2<T>>()?)?;
            let (xv, yv) = (ro.as_array(), rw.as_array_mut());
            py.detach(|| run_array(b, xv, yv))
                .map_err(|e| e.into_err("x", false))?;
            Ok(result)
        })
    }

    /// Forgets every channel's history (the next sample of each lies on the line output =
    /// input).
    fn reset(slf: &Bound<'_, Self>) -> PyResult<()> {
        each!(&mut borrow_mut(slf)?.engine, b => b.reset());
        Ok(())
    }

    /// The memory of Definition 2.1 of `channel` (a `Memory`, or None before its first
    /// sample). IndexError for a channel outside the bank.
    fn memory(slf: &Bound<'_, Self>, channel: isize) -> PyResult<Option<Memory>> {
        let me = errors::borrow(slf)?;
        Ok(me.memory_of(me.channel(channel)?))
    }

    /// Restores the memory of `channel` (None: no history), e.g. one saved from this bank or
    /// from a `Hysteresis` / `InverseHysteresis` with the same k1. IndexError for a channel
    /// outside the bank; ValueError for a memory outside the channel's band |output − input| ≤
    /// k1 (nothing changes then).
    #[pyo3(signature = (channel, memory))]
    fn set_memory(
        slf: &Bound<'_, Self>,
        channel: isize,
        memory: Option<PyRef<'_, Memory>>,
    ) -> PyResult<()> {
        borrow_mut(slf)?.put_memory(channel, memory.as_deref())
    }

    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyType>, BankArgs, Vec<Option<Memory>>)> {
        let me = errors::borrow(slf)?;
        Ok((
            slf.get_type(),
            (
                me.parameters(true),
                me.parameters(false),
                me.is_inverse(),
                me.precision().name(),
            ),
            me.memories(),
        ))
    }

    fn __setstate__(slf: &Bound<'_, Self>, state: Vec<Option<PyRef<'_, Memory>>>) -> PyResult<()> {
        let mut me = borrow_mut(slf)?;
        if state.len() != me.count() {
            return Err(value_error(format!(
                "state: {} memories for a bank of {} channels",
                state.len(),
                me.count()
            )));
        }
        for (c, m) in state.into_iter().enumerate() {
            me.put_memory(c as isize, m.as_deref())?;
        }
        Ok(())
    }

    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        let me = errors::borrow(slf)?;
        let dtype = match me.precision() {
            Precision::F64 => String::new(),
            Precision::F32 => ", dtype='float32'".into(),
        };
        Ok(format!(
            "Bank(channels={}, inverse={}{dtype})",
            me.count(),
            if me.is_inverse() { "True" } else { "False" }
        ))
    }
}
