//! Rust errors as Python exceptions, with the words the CLI prints: `ValueError` for bad
//! values and data, `OSError` (or its subclass for the cause) for files, `KeyboardInterrupt`
//! passed through from a fit stopped by Ctrl-C, and `RuntimeError` for an object used by a
//! second thread while a call that released the GIL holds it ([`borrow`], [`borrow_mut`]).

use std::fmt::Display;
use std::io;
use std::path::Path;

use hyst_fit::FitError;
use hyst_io::IoError;
use hyst_model::{Choice, ModelError};
use pyo3::exceptions::PyRuntimeError;
use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyIsADirectoryError, PyOSError, PyPermissionError,
    PyValueError,
};
use pyo3::prelude::*;
use pyo3::{PyClass, PyErr};

/// `ValueError(message)`.
pub fn value_error(message: impl Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}

/// `ValueError("{context}: {error}")` for an error of the core (an invalid parameter, a
/// refused sample), with its [`advice`].
pub fn core(context: impl Display, error: hyst_core::Error) -> PyErr {
    value_error(format!("{context}: {error}{}", advice(&error)))
}

/// What to do about a refused sample, appended to its message: a desired output out of the
/// model's reach ([`hyst_core::Error::Unreachable`]) is what the saturating inverse clamps
/// (as the CLI advises `--saturate`); "" for any other error.
#[must_use]
pub fn advice(error: &hyst_core::Error) -> &'static str {
    match error {
        hyst_core::Error::Unreachable { .. } => {
            "; Model.inverse(saturate=True) clamps desired outputs into \
             Model.saturation[\"limits\"]"
        }
        _ => "",
    }
}

/// The `OSError` subclass for an I/O error's kind, with `message`.
pub fn os_error(kind: io::ErrorKind, message: String) -> PyErr {
    match kind {
        io::ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
        io::ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
        io::ErrorKind::AlreadyExists => PyFileExistsError::new_err(message),
        io::ErrorKind::IsADirectory => PyIsADirectoryError::new_err(message),
        _ => PyOSError::new_err(message),
    }
}

/// `OSError` naming `path` for an I/O error on it.
pub fn io(path: &Path, action: &str, error: &io::Error) -> PyErr {
    os_error(
        error.kind(),
        format!("{}: cannot {action}: {error}", path.display()),
    )
}

/// A [`FitError`]: `OSError` for what went wrong with a file, `ValueError` for the rest.
pub fn fit(error: FitError) -> PyErr {
    match &error {
        FitError::Io(IoError::Read { source, .. })
        | FitError::Io(IoError::Write { source, .. }) => os_error(source.kind(), error.to_string()),
        FitError::Io(IoError::IsDirectory { .. }) => {
            PyIsADirectoryError::new_err(error.to_string())
        }
        _ => value_error(error),
    }
}

/// A [`ModelError`] (reading, checking or running a model): as the same fault of a fit.
pub fn model(error: ModelError) -> PyErr {
    fit(FitError::from(error))
}

/// A class whose objects a call holds while it releases the GIL (`process()` runs without
/// it): what the message for a second thread that uses such an object meanwhile says (the
/// class is named by its Python name, `PyClass::NAME`).
pub trait Shared: PyClass<Frozen = pyo3::pyclass::boolean_struct::False> {
    /// The call that holds the object for writing with the GIL released ("process()").
    const WRITER: &'static str = "process()";
    /// What one object holds and how each thread gets its own ("one Hysteresis holds one
    /// actuator's memory, so give each thread its own object (copy.copy(op))").
    const OWN: &'static str;
}

/// `RuntimeError` for an object of `T` that another thread holds, where `running` is the
/// call that holds it (`None`: not known).
fn in_use<T: Shared>(running: Option<&str>) -> PyErr {
    let running = running.map_or_else(
        || "another of its calls is running".to_string(),
        |call| format!("its {call} is running"),
    );
    PyRuntimeError::new_err(format!(
        "{} is in use by another thread ({running}): {}, or guard it with a threading.Lock",
        <T as PyClass>::NAME,
        T::OWN
    ))
}

/// Read access to `slf`.
///
/// # Errors
/// `RuntimeError` saying so when another thread's call holds it for writing (PyO3's own would
/// be "Already mutably borrowed").
pub fn borrow<'py, T: Shared>(slf: &Bound<'py, T>) -> PyResult<PyRef<'py, T>> {
    slf.try_borrow().map_err(|_| in_use::<T>(Some(T::WRITER)))
}

/// Write access to `slf`.
///
/// # Errors
/// `RuntimeError` saying so when another thread's call holds it (PyO3's own would be
/// "Already borrowed"). It names the writer when the object cannot even be read (no call
/// holds it for reading while the GIL is released).
pub fn borrow_mut<'py, T: Shared>(slf: &Bound<'py, T>) -> PyResult<PyRefMut<'py, T>> {
    slf.try_borrow_mut().map_err(|_| {
        let writing = slf.try_borrow().is_err();
        in_use::<T>(writing.then_some(T::WRITER))
    })
}

/// A choice by its name (`ShapingKind`, `K2Kind`, …; ASCII letters in either case). An old
/// name the choice still reads (`quad-exp`, `pi`) gives a DeprecationWarning.
pub fn choice<E: Choice>(option: &str, value: &str) -> PyResult<E> {
    let chosen = E::parse(value, true).map_err(|e| {
        value_error(format!(
            "{option} = {value:?}: invalid value; possible values: {}",
            e.names.join(", ")
        ))
    })?;
    if !E::CHOICES
        .iter()
        .any(|(_, name, _)| name.eq_ignore_ascii_case(value))
    {
        Python::attach(|py| {
            deprecated(
                py,
                &format!("{option} = {value:?}"),
                &format!("{option} = {:?}", chosen.name()),
            )
        })?;
    }
    Ok(chosen)
}

/// A `DeprecationWarning` that `old` is the old name of `new` (docs/formats.md lists them).
pub fn deprecated(py: Python<'_>, old: &str, new: &str) -> PyResult<()> {
    let text = format!("{old} is deprecated: use {new} (docs/formats.md, \"Deprecated names\")");
    let message = std::ffi::CString::new(text).unwrap_or_default();
    let category = py.get_type::<pyo3::exceptions::PyDeprecationWarning>();
    PyErr::warn(py, &category, &message, 1)
}

/// The value of a keyword that was renamed from `old` to `new`: the new keyword's, or the old
/// one's with a DeprecationWarning; ValueError when both are given. A value of None counts as
/// not given.
pub fn renamed<'py>(
    py: Python<'py>,
    (new, new_value): (&str, Option<&Bound<'py, PyAny>>),
    (old, old_value): (&str, Option<&Bound<'py, PyAny>>),
) -> PyResult<Option<Bound<'py, PyAny>>> {
    let given = |v: Option<&Bound<'py, PyAny>>| v.filter(|v| !v.is_none()).cloned();
    match (given(new_value), given(old_value)) {
        (Some(_), Some(_)) => Err(value_error(format!(
            "{new} and {old} are given: {old} is the old name of {new}; give {new} alone"
        ))),
        (None, Some(v)) => {
            deprecated(py, old, new)?;
            Ok(Some(v))
        }
        (v, None) => Ok(v),
    }
}
