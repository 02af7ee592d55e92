//! What every refusal must be: a one-line message.

/// An error message must be one line (the tools print it after `error: `).
pub(crate) fn one_line(what: &str, message: &str) -> Result<(), String> {
    if message.is_empty() || message.contains('\n') {
        return Err(format!(
            "{what}: the error message is not one line: {message:?}"
        ));
    }
    Ok(())
}
