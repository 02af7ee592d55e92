//! `hyst.Hysteresis` (eq. 2), `hyst.InverseHysteresis` (eq. 4) and `hyst.Memory`
//! (Definition 2.1), over the core's `ParametricHysteresis` in float64 or float32.

use hyst_io::number::shortest;
use std::time::Instant;

use hyst_core::{
    ConstantK2, Direct, Direction, Formula, Inverse, Memory as CoreMemory, Operator,
    ParametricHysteresis, Real,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyType};

use crate::arrays::{
    derivatives, each_dtype, pair, result_array, run_into, run_jets, samples, samples_f64,
};
use crate::errors::{borrow, borrow_mut, core, value_error, Shared};

/// The arithmetic of an operator: float64 (default) or float32 (as on a microcontroller's FPU;
/// the same results as the C API's float twins, `hyst_operator_init_direct_f32` and the other
/// functions ending in `_f32`, on the same machine).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// f64.
    F64,
    /// f32.
    F32,
}

impl Precision {
    /// From a `dtype=` argument: `None`, or anything `numpy.dtype()` reads as float64 or
    /// float32 ("float64", `numpy.float32`, "f4", …).
    ///
    /// # Errors
    /// `ValueError` for another dtype.
    pub fn from_dtype(dtype: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let Some(dtype) = dtype else {
            return Ok(Precision::F64);
        };
        if dtype.is_none() {
            return Ok(Precision::F64);
        }
        let name: Option<String> = dtype
            .py()
            .import("numpy")?
            .call_method1("dtype", (dtype,))
            .and_then(|d| d.getattr("name"))
            .and_then(|n| n.extract())
            .ok();
        match name.as_deref() {
            Some("float64") => Ok(Precision::F64),
            Some("float32") => Ok(Precision::F32),
            _ => Err(value_error(format!(
                "dtype = {}: expected float64 or float32",
                dtype.repr().map_or_else(|_| "?".into(), |r| r.to_string())
            ))),
        }
    }

    /// "float64" or "float32".
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Precision::F64 => "float64",
            Precision::F32 => "float32",
        }
    }
}

/// The core operator in the chosen precision.
#[derive(Clone, Copy, Debug)]
pub enum Engine<F> {
    /// float64 arithmetic.
    F64(ParametricHysteresis<f64, ConstantK2<f64>, F>),
    /// float32 arithmetic.
    F32(ParametricHysteresis<f32, ConstantK2<f32>, F>),
}

/// Runs `$e` with `$op` bound to the engine's operator, whichever precision it has.
macro_rules! each {
    ($engine:expr, $op:ident => $e:expr) => {
        match $engine {
            Engine::F64($op) => $e,
            Engine::F32($op) => $e,
        }
    };
}

/// A float64 memory in the arithmetic `T`.
pub(crate) fn to_core<T: Real>(m: &CoreMemory<f64>) -> CoreMemory<T> {
    CoreMemory {
        reversal_input: T::from_f64(m.reversal_input),
        reversal_output: T::from_f64(m.reversal_output),
        direction: m.direction,
        last_input: T::from_f64(m.last_input),
        last_output: T::from_f64(m.last_output),
    }
}

/// A memory in float64 (exact from float32).
pub(crate) fn from_core<T: Real>(m: &CoreMemory<T>) -> CoreMemory<f64> {
    CoreMemory {
        reversal_input: m.reversal_input.as_f64(),
        reversal_output: m.reversal_output.as_f64(),
        direction: m.direction,
        last_input: m.last_input.as_f64(),
        last_output: m.last_output.as_f64(),
    }
}

impl<F: Formula + Send + Sync> Engine<F> {
    /// H(k1, k2) or H⁻¹(k1, k2) with no history, checked by the core.
    ///
    /// # Errors
    /// `ValueError` naming k1 or k2 unless both are finite and > 0 (in float32 too).
    pub fn new(k1: f64, k2: f64, precision: Precision) -> PyResult<Self> {
        let context = |p: Precision| match p {
            Precision::F64 => "k1/k2".to_string(),
            Precision::F32 => format!("k1 = {}, k2 = {} (as float32)", shortest(k1), shortest(k2)),
        };
        match precision {
            Precision::F64 => ParametricHysteresis::new(k1, k2)
                .map(Engine::F64)
                .map_err(|e| core(context(precision), e)),
            Precision::F32 => {
                // The parameters must be valid in the precision that computes with them.
                ParametricHysteresis::<f64, ConstantK2<f64>, F>::new(k1, k2)
                    .map_err(|e| core("k1/k2", e))?;
                ParametricHysteresis::new(k1 as f32, k2 as f32)
                    .map(Engine::F32)
                    .map_err(|e| core(context(precision), e))
            }
        }
    }

    /// k1 (output units of H).
    pub fn k1(&self) -> f64 {
        each!(self, op => op.k1().as_f64())
    }

    /// k2 (1 / input units of H).
    pub fn k2(&self) -> f64 {
        each!(self, op => op.k2().as_f64())
    }

    /// The arithmetic.
    pub fn precision(&self) -> Precision {
        match self {
            Engine::F64(_) => Precision::F64,
            Engine::F32(_) => Precision::F32,
        }
    }

    /// One sample.
    ///
    /// # Errors
    /// `ValueError` for a sample the core refuses (the memory is unchanged).
    pub fn step(&mut self, x: f64) -> PyResult<f64> {
        match self {
            Engine::F64(op) => op.try_step(x),
            Engine::F32(op) => op.try_step(x as f32).map(f64::from),
        }
        .map_err(|e| core(format!("x = {}", shortest(x)), e))
    }

    /// `.process(x, derivatives=None)`.
    ///
    /// # Errors
    /// Bad arrays; the first refused sample (the memory is then as before the call).
    pub fn process<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        d: Option<&Bound<'py, PyAny>>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let xs = samples(x, "x")?;
        let Some(d) = d.filter(|d| !d.is_none()) else {
            return each_dtype!(xs, a, dtype => {
                let (out, mut o) = result_array(py, out, a.len()?, dtype)?;
                let (view, dest) = (
                    a.as_array(),
                    o.as_slice_mut()
                        .map_err(|_| value_error("out: the array is not contiguous"))?,
                );
                py.detach(|| each!(self, op => run_into(op, view, dest)))
                    .map_err(|e| e.into_err("x"))?;
                Ok(out)
            });
        };
        if out.is_some_and(|o| !o.is_none()) {
            return Err(value_error(
                "out: not with derivatives (the result is a pair of arrays)",
            ));
        }
        let n = each_dtype!(&xs, a => a.len()?);
        let (d, one_d) = derivatives(d, n)?;
        let dv = d.as_array();
        each_dtype!(xs, a => {
            let view = a.as_array();
            let (y, dy) = py
                .detach(|| each!(self, op => run_jets(op, view, dv)))
                .map_err(|e| e.into_err("x"))?;
            pair(py, y, dy, dv.ncols(), one_d)
        })
    }

    /// The memory (float64 values; exact for a float32 operator).
    pub fn memory(&self) -> Option<Memory> {
        let m = match self {
            Engine::F64(op) => op.memory().map(|m| from_core(&m)),
            Engine::F32(op) => op.memory().map(|m| from_core(&m)),
        };
        m.map(|inner| Memory { inner })
    }

    /// Restores a memory (`None`: no history).
    ///
    /// # Errors
    /// `ValueError` for a memory outside the band of this operator's k1 (the core's check).
    pub fn set_memory(&mut self, memory: Option<&Memory>) -> PyResult<()> {
        let m = memory.map(|m| m.inner);
        match self {
            Engine::F64(op) => op.set_memory(m),
            Engine::F32(op) => op.set_memory(m.map(|m| to_core(&m))),
        }
        .map_err(|e| core("memory", e))
    }

    /// Back to no history.
    pub fn reset(&mut self) {
        each!(self, op => op.reset());
    }
}

impl Engine<Direct> {
    fn inverse(&self) -> Engine<Inverse> {
        match self {
            Engine::F64(op) => Engine::F64(op.inverse()),
            Engine::F32(op) => Engine::F32(op.inverse()),
        }
    }
}

impl Engine<Inverse> {
    fn direct(&self) -> Engine<Direct> {
        match self {
            Engine::F64(op) => Engine::F64(op.direct()),
            Engine::F32(op) => Engine::F32(op.direct()),
        }
    }
}

/// The memory of Definition 2.1: the last reversal point (α0, β0), the direction of the input,
/// and the last sample (α, β). α is the operator's input and β its output: for `Hysteresis`
/// α = v and β = u; for `InverseHysteresis` α = u_d and β = v.
///
/// Read it from `op.memory`, store or pickle it, and assign it back (`op.memory = m`) to resume
/// exactly where the operator was; `None` means no history (the next sample lies on the line
/// output = input).
#[pyclass(module = "hyst", frozen, eq)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Memory {
    pub(crate) inner: CoreMemory<f64>,
}

/// The constructor arguments of a `Memory`, as pickling stores them.
type MemoryArgs = (f64, f64, &'static str, f64, f64);

fn direction(name: &str) -> PyResult<Direction> {
    match name {
        "rising" => Ok(Direction::Rising),
        "falling" => Ok(Direction::Falling),
        _ => Err(value_error(format!(
            "direction = {name:?}: expected \"rising\" or \"falling\""
        ))),
    }
}

#[pymethods]
impl Memory {
    /// A memory at the reversal point (reversal_input, reversal_output), heading in
    /// `direction` ("rising" or "falling"), whose last sample is (last_input, last_output)
    /// (default: the reversal point). The operator checks it against its band
    /// |output − input| ≤ k1 when it is assigned.
    #[new]
    #[pyo3(signature = (reversal_input, reversal_output, direction="rising", last_input=None, last_output=None))]
    fn new(
        reversal_input: f64,
        reversal_output: f64,
        direction: &str,
        last_input: Option<f64>,
        last_output: Option<f64>,
    ) -> PyResult<Self> {
        let dir = self::direction(direction)?;
        let inner = CoreMemory {
            reversal_input,
            reversal_output,
            direction: dir,
            last_input: last_input.unwrap_or(reversal_input),
            last_output: last_output.unwrap_or(reversal_output),
        };
        for (name, v) in [
            ("reversal_input", inner.reversal_input),
            ("reversal_output", inner.reversal_output),
            ("last_input", inner.last_input),
            ("last_output", inner.last_output),
        ] {
            if !v.is_finite() {
                return Err(value_error(format!(
                    "{name} = {v}: expected a finite number"
                )));
            }
        }
        Ok(Self { inner })
    }

    /// α0: the operator input at the last reversal.
    #[getter]
    fn reversal_input(&self) -> f64 {
        self.inner.reversal_input
    }

    /// β0: the operator output at the last reversal.
    #[getter]
    fn reversal_output(&self) -> f64 {
        self.inner.reversal_output
    }

    /// "rising" (s = +1 in Definition 2.1's transformation) or "falling" (s = −1).
    #[getter]
    fn direction(&self) -> &'static str {
        match self.inner.direction {
            Direction::Rising => "rising",
            Direction::Falling => "falling",
        }
    }

    /// The last input sample.
    #[getter]
    fn last_input(&self) -> f64 {
        self.inner.last_input
    }

    /// The last output sample.
    #[getter]
    fn last_output(&self) -> f64 {
        self.inner.last_output
    }

    /// The fields as a dict (the constructor's keyword arguments).
    #[pyo3(name = "to_dict")]
    fn as_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("reversal_input", self.inner.reversal_input)?;
        d.set_item("reversal_output", self.inner.reversal_output)?;
        d.set_item("direction", self.direction())?;
        d.set_item("last_input", self.inner.last_input)?;
        d.set_item("last_output", self.inner.last_output)?;
        Ok(d)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyType>, MemoryArgs)> {
        let m = slf.get();
        Ok((
            slf.get_type(),
            (
                m.inner.reversal_input,
                m.inner.reversal_output,
                m.direction(),
                m.inner.last_input,
                m.inner.last_output,
            ),
        ))
    }

    fn __repr__(&self) -> String {
        format!(
            "Memory(reversal_input={:?}, reversal_output={:?}, direction={:?}, last_input={:?}, last_output={:?})",
            self.inner.reversal_input,
            self.inner.reversal_output,
            self.direction(),
            self.inner.last_input,
            self.inner.last_output
        )
    }
}

/// The Python surface shared by `Hysteresis` and `InverseHysteresis`.
macro_rules! operator_class {
    ($name:ident, $formula:ty, $other:ident, $flip:ident, $flip_doc:literal, $what:literal) => {
        impl Shared for $name {
            const OWN: &'static str = concat!(
                "one ",
                $what,
                " holds one actuator's memory, so give each thread its own object (copy.copy(op))"
            );
        }

        #[pymethods]
        impl $name {
            #[new]
            #[pyo3(signature = (k1, k2, dtype=None))]
            fn py_new(k1: f64, k2: f64, dtype: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
                Ok(Self {
                    engine: Engine::new(k1, k2, Precision::from_dtype(dtype)?)?,
                })
            }

            /// k1 > 0: the half-width of the loop (the asymptotes are u = v ∓ k1), in the
            /// output units of the direct operator H.
            #[getter]
            fn k1(slf: &Bound<'_, Self>) -> PyResult<f64> {
                Ok(borrow(slf)?.engine.k1())
            }

            /// k2 > 0: the rate of the transition to the asymptotes, in 1 / (input units of H).
            #[getter]
            fn k2(slf: &Bound<'_, Self>) -> PyResult<f64> {
                Ok(borrow(slf)?.engine.k2())
            }

            /// The arithmetic: "float64" or "float32".
            #[getter]
            fn dtype(slf: &Bound<'_, Self>) -> PyResult<&'static str> {
                Ok(borrow(slf)?.engine.precision().name())
            }

            /// Processes the samples `x` (any 1-D array-like) in order and returns the outputs
            /// as a numpy array of the same length (float32 stays float32, anything else
            /// becomes float64). Contiguous float arrays are read in place and the GIL is
            /// released meanwhile.
            ///
            /// With `derivatives` of shape (n, N) (x's first N time derivatives at each
            /// sample, N ≤ `hyst.MAX_ORDER`; a 1-D array is the first derivative), returns
            /// `(y, dy)` with dy of the same shape: the outputs' time derivatives by Taylor
            /// arithmetic (Proposition 2.7 and beyond), as `hyst run --derivatives`.
            ///
            /// With `out` (a 1-D array of the result's dtype and x's length), the outputs are
            /// written into it and it is returned: no allocation, for block-by-block loops.
            ///
            /// Raises ValueError at the first sample the operator refuses (NaN or infinity),
            /// naming its index; the memory is then as it was before the call (and `out` holds
            /// partial results). Ctrl-C stops a long call with KeyboardInterrupt, likewise.
            #[pyo3(signature = (x, derivatives=None, *, out=None))]
            fn process<'py>(
                slf: &Bound<'py, Self>,
                x: &Bound<'py, PyAny>,
                derivatives: Option<&Bound<'py, PyAny>>,
                out: Option<&Bound<'py, PyAny>>,
            ) -> PyResult<Bound<'py, PyAny>> {
                borrow_mut(slf)?
                    .engine
                    .process(slf.py(), x, derivatives, out)
            }

            /// One sample: returns the output as a float. Raises ValueError for NaN or
            /// infinity (the memory is unchanged).
            fn step(slf: &Bound<'_, Self>, x: f64) -> PyResult<f64> {
                borrow_mut(slf)?.engine.step(x)
            }

            /// Forgets the history: the next sample starts on the line output = input.
            fn reset(slf: &Bound<'_, Self>) -> PyResult<()> {
                borrow_mut(slf)?.engine.reset();
                Ok(())
            }

            /// The memory of Definition 2.1 (a `Memory`, or None before the first sample).
            /// Assign a saved one to resume exactly where it was (checked against the band
            /// |output − input| ≤ k1; ValueError otherwise, and nothing changes).
            #[getter]
            fn get_memory(slf: &Bound<'_, Self>) -> PyResult<Option<Memory>> {
                Ok(borrow(slf)?.engine.memory())
            }

            #[setter]
            fn set_memory(
                slf: &Bound<'_, Self>,
                memory: Option<PyRef<'_, Memory>>,
            ) -> PyResult<()> {
                borrow_mut(slf)?.engine.set_memory(memory.as_deref())
            }

            #[doc = $flip_doc]
            fn $flip(slf: &Bound<'_, Self>) -> PyResult<$other> {
                Ok($other {
                    engine: borrow(slf)?.engine.$flip(),
                })
            }

            fn __reduce__<'py>(
                slf: &Bound<'py, Self>,
            ) -> PyResult<(Bound<'py, PyType>, (f64, f64, &'static str), Option<Memory>)> {
                let me = borrow(slf)?;
                let e = &me.engine;
                Ok((
                    slf.get_type(),
                    (e.k1(), e.k2(), e.precision().name()),
                    e.memory(),
                ))
            }

            fn __setstate__(
                slf: &Bound<'_, Self>,
                state: Option<PyRef<'_, Memory>>,
            ) -> PyResult<()> {
                borrow_mut(slf)?.engine.set_memory(state.as_deref())
            }

            fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
                let e = &borrow(slf)?.engine;
                let dtype = match e.precision() {
                    Precision::F64 => String::new(),
                    Precision::F32 => ", dtype='float32'".into(),
                };
                Ok(format!(
                    "{}(k1={:?}, k2={:?}{dtype})",
                    $what,
                    e.k1(),
                    e.k2()
                ))
            }
        }
    };
}

/// The direct operator u = H(k1, k2)[v] of eq. (2) with the memory of Definition 2.1.
///
/// `Hysteresis(k1, k2, dtype=None)`: k1 > 0 is the half-width of the loop (output units), k2 > 0
/// the rate of the transition to the asymptotes u = v ∓ k1 (1 / input units); `dtype` float64
/// (default) or float32 chooses the arithmetic. The first sample lies on the line u = v.
#[pyclass(module = "hyst")]
#[derive(Clone, Debug)]
pub struct Hysteresis {
    pub(crate) engine: Engine<Direct>,
}

/// The inverse operator v = H⁻¹(k1, k2)[u_d] of eq. (4): the exact inverse of
/// `Hysteresis(k1, k2)` (Proposition 4.1), desired output in, command out.
///
/// `InverseHysteresis(k1, k2, dtype=None)`, parameters as for `Hysteresis`.
#[pyclass(module = "hyst")]
#[derive(Clone, Debug)]
pub struct InverseHysteresis {
    pub(crate) engine: Engine<Inverse>,
}

operator_class!(
    Hysteresis,
    Direct,
    InverseHysteresis,
    inverse,
    "The inverse operator H⁻¹(k1, k2) (eq. 4) whose memory mirrors this one's: from here on, its \
     output fed into this operator gives back its input (Proposition 4.1).",
    "Hysteresis"
);
operator_class!(
    InverseHysteresis,
    Inverse,
    Hysteresis,
    direct,
    "The direct operator H(k1, k2) (eq. 2) whose memory mirrors this one's.",
    "InverseHysteresis"
);

/// `hyst._bench_core(k1, k2, x, inverse=False, dtype=None, repeats=5)`: the core's own loop
/// (`Operator::process` on Rust vectors, no Python in between) over a copy of `x`; returns the
/// best time in ns per sample. The yardstick of `examples/python/bench.py`.
///
/// # Errors
/// Invalid parameters or arrays.
#[pyfunction(name = "_bench_core")]
#[pyo3(signature = (k1, k2, x, inverse=false, dtype=None, repeats=5))]
pub fn bench_core(
    py: Python<'_>,
    k1: f64,
    k2: f64,
    x: &Bound<'_, PyAny>,
    inverse: bool,
    dtype: Option<&Bound<'_, PyAny>>,
    repeats: usize,
) -> PyResult<f64> {
    fn best<T: Real, O: Operator<T>>(op: &mut O, input: &[T], repeats: usize) -> f64 {
        let mut output = vec![T::zero(); input.len()];
        let mut best = f64::INFINITY;
        for _ in 0..repeats.max(1) {
            op.reset();
            let started = Instant::now();
            let _ = op.process(std::hint::black_box(input), &mut output);
            std::hint::black_box(&output);
            best = best.min(started.elapsed().as_secs_f64());
        }
        best * 1e9 / input.len().max(1) as f64
    }
    let input = samples_f64(x, "x")?;
    let precision = Precision::from_dtype(dtype)?;
    let direct = Engine::<Direct>::new(k1, k2, precision)?;
    let input32: Vec<f32> = input.iter().map(|v| *v as f32).collect();
    Ok(py.detach(|| match (direct, inverse) {
        (Engine::F64(mut op), false) => best(&mut op, &input, repeats),
        (Engine::F64(op), true) => best(&mut op.inverse(), &input, repeats),
        (Engine::F32(mut op), false) => best(&mut op, &input32, repeats),
        (Engine::F32(op), true) => best(&mut op.inverse(), &input32, repeats),
    }))
}
