//! numpy in and out: any 1-D array-like becomes a read-only view (float32 and float64 arrays
//! as they are, without a copy when contiguous; anything else through `numpy.asarray(x,
//! dtype=float64)`), and an operator runs over it into a `Vec` that becomes the result array
//! without a copy. A call either processes every sample or, at the first sample the operator
//! refuses, restores the memory it started with and reports that sample.

use hyst_core::{Error, Jet, Operator, Real};
use hyst_io::number::shortest;
use numpy::ndarray::{ArrayView1, ArrayView2, Axis};
use numpy::{
    Element, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;

use hyst_core::compensator::MAX_ORDER;

/// Runs `$e` with `$a` bound to the array of the samples `$samples` (and `$dtype` to the name of
/// its dtype), for float64 and float32 separately (numpy arrays are typed).
macro_rules! each_dtype {
    ($samples:expr, $a:ident => $e:expr) => {
        each_dtype!($samples, $a, _dtype => $e)
    };
    ($samples:expr, $a:ident, $dtype:ident => $e:expr) => {
        match $samples {
            $crate::arrays::Samples::F64($a) => {
                let $dtype = "float64";
                $e
            }
            $crate::arrays::Samples::F32($a) => {
                let $dtype = "float32";
                $e
            }
        }
    };
}
pub(crate) use each_dtype;

/// A 1-D array of samples, read in place.
pub enum Samples<'py> {
    /// float64 samples.
    F64(PyReadonlyArray1<'py, f64>),
    /// float32 samples (results stay float32).
    F32(PyReadonlyArray1<'py, f32>),
}

fn readonly<'py, T: Element>(
    a: &Bound<'py, PyArray1<T>>,
    name: &str,
) -> PyResult<PyReadonlyArray1<'py, T>> {
    a.try_readonly().map_err(|_| {
        value_error(format!(
            "{name}: the array is being written (is it also passed as out?): hyst reads {name} \
             while it writes out, so they must be separate arrays"
        ))
    })
}

/// `numpy.asarray(x, dtype=float64)`, with the argument's name in the error.
fn as_float64<'py>(x: &Bound<'py, PyAny>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    as_dtype(x, name, "float64")
}

/// `numpy.asarray(x, dtype=dtype)`, with the argument's name in the error (complex numbers
/// are refused rather than silently losing their imaginary part).
///
/// # Errors
/// `ValueError` when `x` cannot be read as numbers.
pub fn as_dtype<'py>(
    x: &Bound<'py, PyAny>,
    name: &str,
    dtype: &str,
) -> PyResult<Bound<'py, PyAny>> {
    // numpy would drop the imaginary part with only a warning.
    let kind: Option<String> = x
        .getattr("dtype")
        .and_then(|d| d.getattr("kind"))
        .and_then(|k| k.extract())
        .ok();
    if kind.as_deref() == Some("c") {
        return Err(value_error(format!(
            "{name}: complex samples; pass the real part (x.real) if that is what is meant"
        )));
    }
    let converted = asarray(x, dtype);
    // numpy reads None as NaN, which the operators would then report as a NaN sample: name the
    // missing value instead. Only inputs that are not already numeric arrays can hold one, and
    // only a conversion that failed or holds a NaN is searched for it (the search converts the
    // input once more, to objects).
    if !matches!(kind.as_deref(), Some("f" | "i" | "u" | "b"))
        && converted.as_ref().map_or(true, has_nan)
    {
        if x.is_none() {
            return Err(value_error(format!("{name}: got None, expected numbers")));
        }
        if let Some(at) = first_none(x)? {
            return Err(value_error(format!(
                "{name}: {at} is None (a missing value); drop or fill the missing samples first"
            )));
        }
    }
    converted.map_err(|e| {
        value_error(format!(
            "{name}: cannot be read as an array of numbers: {e}"
        ))
    })
}

/// Whether the numeric array `a` holds a NaN (true when that cannot be told).
fn has_nan(a: &Bound<'_, PyAny>) -> bool {
    a.py()
        .import("numpy")
        .and_then(|np| np.call_method1("isnan", (a,)))
        .and_then(|m| m.call_method0("any"))
        .and_then(|b| b.extract())
        .unwrap_or(true)
}

/// `numpy.asarray(x, dtype=dtype)`.
fn asarray<'py>(x: &Bound<'py, PyAny>, dtype: &str) -> PyResult<Bound<'py, PyAny>> {
    let kwargs = PyDict::new(x.py());
    kwargs.set_item("dtype", dtype)?;
    x.py()
        .import("numpy")?
        .call_method("asarray", (x,), Some(&kwargs))
}

/// Where `x` (a list, a tuple or an object array, any shape) holds None: "sample i" in one
/// dimension, "element (i, j, …)" in more; `None` when it holds none or cannot be read as an
/// array of objects (the conversion that follows then gives its own error).
fn first_none(x: &Bound<'_, PyAny>) -> PyResult<Option<String>> {
    let np = x.py().import("numpy")?;
    let Ok(objects) = asarray(x, "object") else {
        return Ok(None);
    };
    let Ok(mask) = np.call_method1("equal", (&objects, x.py().None())) else {
        return Ok(None);
    };
    let at: Vec<Vec<usize>> = np
        .call_method1("argwhere", (mask,))
        .and_then(|w| w.call_method0("tolist"))
        .and_then(|w| w.extract())
        .unwrap_or_default();
    Ok(at.first().map(|index| match index.as_slice() {
        [i] => format!("sample {i}"),
        [] => "the argument".into(),
        more => format!(
            "element ({})",
            more.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }))
}

/// The `shape` of an array, as Python prints it ("?" if it has none).
pub fn shape_of(a: &Bound<'_, PyAny>) -> String {
    a.getattr("shape")
        .and_then(|s| s.repr())
        .map_or_else(|_| "?".into(), |s| s.to_string())
}

/// Reads `x` as a 1-D array of samples. `name` names the argument in errors.
///
/// # Errors
/// `ValueError` when `x` is not a 1-D array of numbers (the message gives its shape).
pub fn samples<'py>(x: &Bound<'py, PyAny>, name: &str) -> PyResult<Samples<'py>> {
    if let Ok(a) = x.cast::<PyArray1<f64>>() {
        return readonly(a, name).map(Samples::F64);
    }
    if let Ok(a) = x.cast::<PyArray1<f32>>() {
        return readonly(a, name).map(Samples::F32);
    }
    let a = as_float64(x, name)?;
    match a.cast::<PyArray1<f64>>() {
        Ok(a) => readonly(a, name).map(Samples::F64),
        Err(_) => Err(value_error(format!(
            "{name}: expected a 1-D array of samples, got shape {}",
            shape_of(&a)
        ))),
    }
}

/// Reads `x` as a 1-D array of samples and copies it into float64 values (for the calls that
/// keep their own copy: the fit, the family envelope, the benchmark).
///
/// # Errors
/// As [`samples`].
pub fn samples_f64(x: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    Ok(each_dtype!(samples(x, name)?, a => a.as_array().iter().map(|v| v.as_f64()).collect()))
}

/// Reads `d` as the time derivatives of `n` samples: shape (n, N) with 1 ≤ N ≤
/// [`MAX_ORDER`] (a 1-D array of length n is the first derivative alone). Returns the
/// array (float64) and whether it was 1-D.
///
/// # Errors
/// `ValueError` for another shape.
pub fn derivatives<'py>(
    d: &Bound<'py, PyAny>,
    n: usize,
) -> PyResult<(PyReadonlyArray2<'py, f64>, bool)> {
    let a = as_float64(d, "derivatives")?;
    let one_d = a.cast::<PyArray1<f64>>().is_ok();
    let a = if one_d {
        a.call_method1("reshape", ((n as isize, 1_isize),))
            .map_err(|_| {
                value_error(format!(
                    "derivatives: shape {} does not match the {n} samples of x",
                    shape_of(&a)
                ))
            })?
    } else {
        a
    };
    let Ok(arr) = a.cast::<PyArray2<f64>>() else {
        return Err(value_error(format!(
            "derivatives: expected shape (n, N) with N time derivatives per sample, got shape {}",
            shape_of(&a)
        )));
    };
    let shape = arr.shape();
    let (rows, cols) = (shape.first().copied(), shape.get(1).copied());
    if rows != Some(n) {
        return Err(value_error(format!(
            "derivatives: {} rows but x has {n} samples",
            rows.unwrap_or(0)
        )));
    }
    if !(1..=MAX_ORDER).contains(&cols.unwrap_or(0)) {
        return Err(value_error(format!(
            "derivatives: {} columns; give 1 to hyst.MAX_ORDER = {MAX_ORDER} time derivatives \
             per sample",
            cols.unwrap_or(0)
        )));
    }
    let ro = arr
        .try_readonly()
        .map_err(|e| value_error(format!("derivatives: the array cannot be read: {e}")))?;
    // A non-finite derivative is named here, where its place is known (the operator would
    // blame the sample's value).
    if let Some(((i, k), v)) = ro.as_array().indexed_iter().find(|(_, v)| !v.is_finite()) {
        return Err(non_finite_derivative(i, k, *v, one_d));
    }
    Ok((ro, one_d))
}

/// The error of the non-finite derivative `v` of sample `i`, column `k` (named `[i]` alone for
/// derivatives given as a 1-D array: `one_d`).
pub(crate) fn non_finite_derivative(i: usize, k: usize, v: f64, one_d: bool) -> PyErr {
    let at = if one_d {
        format!("{i}")
    } else {
        format!("{i}, {k}")
    };
    value_error(format!(
        "derivatives[{at}] = {}: not a finite number",
        shortest(v)
    ))
}

/// A sample an operator refused: its index in the array, its value and the core's reason.
#[derive(Debug)]
pub struct Refused {
    /// Index in the array (from 0).
    pub index: usize,
    /// The sample.
    pub value: f64,
    /// Why.
    pub error: Error,
}

impl Refused {
    /// `ValueError("{name}[{index}] = {value}: {reason}")`, with the reason's advice
    /// ([`crate::errors::advice`]).
    #[must_use]
    pub fn into_err(self, name: &str) -> PyErr {
        value_error(format!(
            "{name}[{}] = {}: {}{}",
            self.index,
            shortest(self.value),
            self.error,
            crate::errors::advice(&self.error)
        ))
    }
}

/// Why a run over an array stopped early.
#[derive(Debug)]
pub enum Stop {
    /// The operator refused a sample.
    Refused(Refused),
    /// A signal handler raised (Ctrl-C: `KeyboardInterrupt`) between two chunks.
    Interrupted(PyErr),
}

impl Stop {
    /// The Python exception: `ValueError` naming the refused sample of the array `name`, or the
    /// signal handler's exception.
    #[must_use]
    pub fn into_err(self, name: &str) -> PyErr {
        match self {
            Stop::Refused(r) => r.into_err(name),
            Stop::Interrupted(e) => e,
        }
    }
}

/// Samples processed between two checks for Ctrl-C (a few ms of work): a long array run
/// without the GIL still stops on KeyboardInterrupt.
pub const CHUNK: usize = 1 << 20;

/// Runs pending Python signal handlers (Ctrl-C raises `KeyboardInterrupt`).
///
/// # Errors
/// The handler's exception.
pub fn signals() -> Result<(), Stop> {
    Python::attach(|py| py.check_signals()).map_err(Stop::Interrupted)
}

/// Runs `op` (arithmetic in `T`) over the samples `x` (stored as `X`) into `out` (same
/// length, checked by the caller): no allocation; the one loop behind `process` with a new
/// result array and with `out=`. Checks for Ctrl-C every [`CHUNK`] samples. When it stops
/// early, the memory is restored and `out` holds partial results.
///
/// # Errors
/// The first refused sample, or the exception of a signal handler.
pub fn run_into<T: Real, X: Real, O: Operator<T>>(
    op: &mut O,
    x: ArrayView1<'_, X>,
    out: &mut [X],
) -> Result<(), Stop> {
    let saved = op.memory();
    let mut offset = 0;
    let mut done = Ok(());
    for (chunk, dest) in x
        .axis_chunks_iter(Axis(0), CHUNK)
        .zip(out.chunks_mut(CHUNK))
    {
        if offset > 0 {
            done = signals();
        }
        if done.is_ok() {
            done = match chunk.as_slice() {
                Some(s) => fill_into(op, s.iter().copied(), dest, offset),
                None => fill_into(op, chunk.iter().copied(), dest, offset),
            };
        }
        if done.is_err() {
            // The memory saved a moment ago is valid for this operator.
            let _ = op.set_memory(saved);
            return done;
        }
        offset += chunk.len();
    }
    done
}

/// Steps `op` over `xs` into `out`. Every slot is written and a refused sample is recorded
/// (the first one) instead of leaving the loop early; the loop is kept out of line so that its
/// code does not change with its callers'. Measured (examples/python/bench.py, 10⁶ samples):
/// 1.00–1.09 × the core's own `process` loop. Building a `Vec` by `extend` or over a zeroed
/// `Vec` measured 1.13–1.2 in the same conditions.
#[inline(never)]
fn fill_into<T: Real, X: Real, O: Operator<T>>(
    op: &mut O,
    xs: impl Iterator<Item = X>,
    out: &mut [X],
    offset: usize,
) -> Result<(), Stop> {
    let mut refused: Option<Refused> = None;
    for (index, (x, slot)) in xs.zip(out.iter_mut()).enumerate() {
        *slot = match op.try_step(T::from_f64(x.as_f64())) {
            Ok(y) => X::from_f64(y.as_f64()),
            Err(error) => {
                if refused.is_none() {
                    refused = Some(Refused {
                        index: offset + index,
                        value: x.as_f64(),
                        error,
                    });
                }
                X::zero()
            }
        };
    }
    refused.map_or(Ok(()), |r| Err(Stop::Refused(r)))
}

/// The array a result goes into: the caller's `out=` (checked by [`out_array`]) or a new
/// zero-filled one (numpy's `calloc`: fresh pages cost no fill), with write access to it.
///
/// # Errors
/// As [`out_array`].
pub fn result_array<'py, X: Element>(
    py: Python<'py>,
    out: Option<&Bound<'py, PyAny>>,
    n: usize,
    dtype: &str,
) -> PyResult<(Bound<'py, PyAny>, numpy::PyReadwriteArray1<'py, X>)> {
    let out = match out.filter(|o| !o.is_none()) {
        Some(o) => o.clone(),
        None => PyArray1::<X>::zeros(py, n, false).into_any(),
    };
    let rw = out_array::<X>(&out, n, dtype)?;
    Ok((out, rw))
}

/// Checks a caller's `out=` array for the results of `n` samples of type `X`: 1-D, writable,
/// that dtype, length n.
///
/// # Errors
/// `ValueError` saying what does not fit.
pub fn out_array<'py, X: Element>(
    out: &Bound<'py, PyAny>,
    n: usize,
    dtype: &str,
) -> PyResult<numpy::PyReadwriteArray1<'py, X>> {
    let Ok(a) = out.cast::<PyArray1<X>>() else {
        return Err(value_error(format!(
            "out: expected a 1-D {dtype} array (the dtype of the result), got {}",
            out.get_type()
                .name()
                .map_or_else(|_| "?".into(), |n| n.to_string())
                + &format!(" of shape {}", shape_of(out))
                + &out
                    .getattr("dtype")
                    .and_then(|d| d.str())
                    .map_or_else(|_| String::new(), |d| format!(" and dtype {d}"))
        )));
    };
    if a.len() != n {
        return Err(value_error(format!(
            "out: {} elements for {n} samples",
            a.len()
        )));
    }
    if !a.is_contiguous() {
        return Err(value_error(
            "out: the array is not contiguous (a strided view such as a[::2]): pass a \
             contiguous array, e.g. numpy.empty(n), or none",
        ));
    }
    a.try_readwrite().map_err(|e| {
        if e.to_string().contains("writeable") {
            value_error("out: the array is read-only and cannot be written")
        } else {
            value_error(
                "out: the array is in use: it must not be x, or share memory with x (hyst \
                 reads x while it writes out); pass another array, or none",
            )
        }
    })
}

fn run_order<T: Real, X: Real, O: Operator<T>, const N: usize>(
    op: &mut O,
    x: ArrayView1<'_, X>,
    d: ArrayView2<'_, f64>,
) -> Result<(Vec<X>, Vec<X>), Stop> {
    let saved = op.memory();
    let mut y = Vec::with_capacity(x.len());
    let mut dy = Vec::with_capacity(x.len() * N);
    for (index, (xi, row)) in x.iter().zip(d.rows()).enumerate() {
        if index > 0 && index % CHUNK == 0 {
            if let Err(e) = signals() {
                let _ = op.set_memory(saved);
                return Err(e);
            }
        }
        let mut di = [T::zero(); N];
        for (slot, v) in di.iter_mut().zip(row.iter()) {
            *slot = T::from_f64(*v);
        }
        let jet = Jet::<T, N>::from_derivatives(T::from_f64(xi.as_f64()), di);
        match op.try_step(jet) {
            Ok(out) => {
                y.push(X::from_f64(out.value().as_f64()));
                dy.extend(out.derivatives().iter().map(|v| X::from_f64(v.as_f64())));
            }
            Err(error) => {
                let _ = op.set_memory(saved);
                return Err(Stop::Refused(Refused {
                    index,
                    value: xi.as_f64(),
                    error,
                }));
            }
        }
    }
    Ok((y, dy))
}

/// Runs `op` over the jets (x, d): outputs and their time derivatives (row-major, N per
/// sample), by the core's Taylor arithmetic (Proposition 2.7 and beyond). `d` has been checked
/// by [`derivatives`] (1 ≤ N ≤ [`MAX_ORDER`] columns, one row per sample).
///
/// # Errors
/// The first refused sample, or a signal handler's exception (the memory is then restored).
pub fn run_jets<T: Real, X: Real, O: Operator<T>>(
    op: &mut O,
    x: ArrayView1<'_, X>,
    d: ArrayView2<'_, f64>,
) -> Result<(Vec<X>, Vec<X>), Stop> {
    macro_rules! orders {
        ($($n:literal)*) => {
            match d.ncols() {
                $($n => run_order::<T, X, O, $n>(op, x, d),)*
                // derivatives() admits 1 ..= MAX_ORDER columns only.
                _ => Ok((Vec::new(), Vec::new())),
            }
        };
    }
    orders!(1 2 3 4)
}

/// A result vector as a numpy array (the array takes the `Vec`; no copy).
pub fn to_numpy<'py, X: Element>(py: Python<'py>, v: Vec<X>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v).into_any()
}

/// Derivatives (row-major, `cols` per sample) as an (n, cols) array, or 1-D when the input
/// derivatives were 1-D.
///
/// # Errors
/// Only if numpy refuses the reshape of a contiguous array of the right size.
pub fn derivatives_to_numpy<'py, X: Element>(
    py: Python<'py>,
    v: Vec<X>,
    cols: usize,
    one_d: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let a = PyArray1::from_vec(py, v);
    if one_d {
        return Ok(a.into_any());
    }
    let rows = a.len() / cols.max(1);
    Ok(a.reshape([rows, cols])?.into_any())
}

/// `(y, dy)` as a Python tuple of arrays (dy shaped as [`derivatives_to_numpy`] does).
///
/// # Errors
/// As [`derivatives_to_numpy`].
pub fn pair<'py, X: Element>(
    py: Python<'py>,
    y: Vec<X>,
    dy: Vec<X>,
    cols: usize,
    one_d: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let y = to_numpy(py, y);
    let dy = derivatives_to_numpy(py, dy, cols, one_d)?;
    Ok(pyo3::types::PyTuple::new(py, [y, dy])?.into_any())
}
