//! Rust errors as Python exceptions, with the words the CLI prints: `ValueError` for bad
//! values and data, `OSError` (or its subclass for the cause) for files, `KeyboardInterrupt`
//! passed through from a fit stopped by Ctrl-C.

use std::fmt::Display;
use std::io;
use std::path::Path;

use hyst_fit::FitError;
use hyst_io::IoError;
use hyst_model::ModelError;
use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyIsADirectoryError, PyOSError, PyPermissionError,
    PyValueError,
};
use pyo3::PyErr;

/// `ValueError(message)`.
pub fn value_error(message: impl Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}

/// `ValueError("{context}: {error}")` for an error of the core (an invalid parameter, a
/// refused sample).
pub fn core(context: impl Display, error: hyst_core::Error) -> PyErr {
    value_error(format!("{context}: {error}"))
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
