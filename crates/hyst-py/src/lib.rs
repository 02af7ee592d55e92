//! `hyst._hyst`: the Python extension module behind the package `hyst` (PyO3 + rust-numpy,
//! built by maturin as an abi3 wheel for CPython ≥ 3.9).
//!
//! One Python class per concept of the paper, each a thin layer over the Rust type that
//! implements it:
//!
//! | Python | Rust |
//! |---|---|
//! | `Hysteresis`, `InverseHysteresis`, `Memory` ([`operator`]) | `hyst_core::Hysteresis`, `InverseHysteresis`, `Memory` (eqs. 2, 4, Definition 2.1) |
//! | `Bank` ([`bank`]) | `hyst_bank::BankVec`: N operators stepped together in SIMD lanes |
//! | `load_model`, `Model` ([`model`]) | `hyst_model::ModelFile` + `Evaluator` (the model file of `hyst fit`) |
//! | `fit`, `FitResult` ([`fit`]) | `hyst_fit::identify` (what `hyst fit` runs) |
//! | `Family` ([`family`]) | `hyst_core::Family` (Definition 2.8, Proposition 3.2) |
//! | `Compensator` ([`compensator`]) | `hyst_core::compensator::Compensator` (Lemma 5.1) |
//! | `Adaptive` ([`adaptive`]) | `hyst_core::adaptive::AdaptiveInverse`: the recursive estimator and the compensator that follows it |
//! | `MAX_ORDER` | `hyst_core::compensator::MAX_ORDER`: the largest plant order n of `Compensator` and the most time derivatives of `process(x, derivatives)` |
//!
//! Arrays ([`arrays`]): any 1-D array-like in; float32 stays float32 and float64 stays float64;
//! contiguous input is read in place; results are numpy arrays that own a Rust `Vec` (no copy);
//! the GIL is released while samples are processed. Errors ([`errors`]) are `ValueError` (or
//! `OSError` for files) with the CLI's words, and `RuntimeError` saying what to do for an object
//! that a second thread uses while a call that released the GIL holds it; nothing here panics on user input (the workspace
//! denies `unwrap`, `expect` and `panic!`), and PyO3 would turn a panic into an exception
//! rather than abort the interpreter.

// The doc comments of the Python classes are their docstrings, written in the paper's
// notation (u = H(k1, k2)[v], k1[c]): brackets there are no intra-doc links, and escaping
// them would put backslashes into Python's help().
#![allow(rustdoc::broken_intra_doc_links)]

use pyo3::prelude::*;

pub mod adaptive;
pub mod arrays;
pub mod bank;
pub mod compensator;
pub mod dicts;
pub mod errors;
pub mod family;
pub mod fit;
pub mod model;
mod model_memory;
pub mod mujoco;
pub mod operator;
mod timed;

/// The extension module `hyst._hyst`.
#[pymodule]
fn _hyst(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The largest plant order n of `Compensator` and the most derivative columns of
    // `process(x, derivatives)`.
    m.add("MAX_ORDER", hyst_core::compensator::MAX_ORDER)?;
    m.add_class::<operator::Hysteresis>()?;
    m.add_class::<operator::InverseHysteresis>()?;
    m.add_class::<operator::Memory>()?;
    m.add_class::<bank::Bank>()?;
    m.add_class::<model::Model>()?;
    m.add_class::<fit::FitResult>()?;
    m.add_class::<family::Family>()?;
    m.add_class::<compensator::Compensator>()?;
    m.add_class::<adaptive::Adaptive>()?;
    m.add_function(wrap_pyfunction!(model::load_model, m)?)?;
    m.add_function(wrap_pyfunction!(model::model_from_toml, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit_result_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(operator::bench_core, m)?)?;
    // The MuJoCo plugins (hyst.mujoco): the version they were compiled for, 0 without them.
    m.add("_MUJOCO_VERSION", mujoco::version())?;
    m.add_function(wrap_pyfunction!(mujoco::register, m)?)?;
    Ok(())
}
