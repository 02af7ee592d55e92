//! Writing a model file: what the fit produces. Reading and running one is the model
//! runtime's (`hyst_model::ModelFile`), which needs no file system writes.

use std::path::Path;

use hyst_model::ModelFile;

use crate::error::FitError;

/// Writes `file` to `path` atomically (a temporary file in the same folder, then a rename): on
/// any failure, or Ctrl-C before the rename, no partial file exists and an existing file at
/// `path` is unchanged.
///
/// # Errors
/// As [`ModelFile::to_toml`], or the write error naming the path.
pub fn write(file: &ModelFile, path: &Path) -> Result<(), FitError> {
    let text = file.to_toml()?;
    hyst_io::write_atomic(path, text.as_bytes())?;
    Ok(())
}
