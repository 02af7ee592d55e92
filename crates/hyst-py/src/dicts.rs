//! A model file's values as Python dicts: what `Model` and `FitResult` return.

use hyst_model::{Estimate, FamilyWidths, ModelFile};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;

/// A value as a Python object through JSON (dicts, lists, floats, strings; NaN becomes None).
///
/// # Errors
/// Only if the value cannot be written as JSON.
pub fn to_python<'py>(
    py: Python<'py>,
    value: &impl serde::Serialize,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(value_error)?;
    py.import("json")?.call_method1("loads", (text,))
}

/// A dict from each fitted parameter's name to `field` of its estimate (value, standard
/// error, unit): what `params`, `std_errors` and `units` of `Model` and `FitResult` return.
///
/// # Errors
/// Only if Python cannot store an item.
pub fn by_parameter<'py, V: IntoPyObject<'py>>(
    py: Python<'py>,
    file: &ModelFile,
    field: impl Fn(&Estimate) -> V,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for e in &file.parameters {
        d.set_item(&e.name, field(e))?;
    }
    Ok(d)
}

/// The family of a model file when it reaches the coverage asked (Definition 2.8); `None`
/// for no family, or one that does not reach it: then neither it nor its bound is reported.
#[must_use]
pub fn reached(file: &ModelFile) -> Option<&FamilyWidths> {
    file.family.as_ref().filter(|w| w.reachable)
}
