//! The error type of the model runtime.

use std::path::PathBuf;

/// What can go wrong while reading, checking or running a fitted model. Messages name the file,
/// the line and the column where there is one.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// The core refused a value (an invalid parameter in a model file, a non-monotone shaping,
    /// a desired output beyond a saturating shaping, a non-finite sample). The message includes
    /// the core's, so the core error is not also this error's `source()`: a report that prints
    /// an error and its sources would otherwise say it twice.
    #[error("model: {0}")]
    Core(hyst_core::Error),

    /// A model file could not be read or understood.
    #[error("{}: {message}", path.display())]
    File {
        /// The model file.
        path: PathBuf,
        /// What is wrong (with the line and column for TOML errors).
        message: String,
    },

    /// The model cannot do what was asked (invert a stop-form model, run a file without a
    /// model), or a sample of a record was refused (the message names the sample).
    #[error("{0}")]
    Invalid(String),
}

impl From<hyst_core::Error> for ModelError {
    fn from(e: hyst_core::Error) -> Self {
        ModelError::Core(e)
    }
}
