//! A desired output that the inverse of a model cannot reach from its state (the core's
//! [`hyst_core::Error::Unreachable`]: a saturating input shaping bounds the operator input), said
//! in the user's units: the file, line and column, the value as given, the outputs the model
//! reaches from its state there, and the limits `--saturate` clamps into.

use anyhow::{bail, Result};
use hyst_io::number::sig;
use hyst_model::saturation::Saturation;

use crate::run::columns::Num;

/// The core error inside `e` (a model that could not start), if any.
pub(crate) fn core_error(e: &anyhow::Error) -> Option<hyst_core::Error> {
    e.chain().find_map(|cause| match cause.downcast_ref() {
        Some(hyst_model::ModelError::Core(core)) => Some(*core),
        _ => None,
    })
}

/// Fails with the message for `e` when it is a desired output out of reach, at `place`
/// (`FILE:LINE: column C ("NAME")`), with the advice of `--saturate` when the model's output
/// is bounded (`saturation`); any other error is left to the caller.
///
/// # Errors
/// The refusal.
pub(crate) fn refuse(
    e: &hyst_core::Error,
    place: &str,
    saturation: Option<&Saturation>,
) -> Result<()> {
    let hyst_core::Error::Unreachable { value, min, max } = *e else {
        return Ok(());
    };
    let advice = saturation.map_or(String::new(), |s| {
        format!(
            "; --saturate clamps desired outputs into [{}, {}] ({})",
            sig(s.limits.0, 7),
            sig(s.limits.1, 7),
            s.rule()
        )
    });
    let bounded = saturation
        .and_then(|s| s.input_shaping)
        .map_or("its input shaping".to_string(), |name| {
            format!("its {name} input shaping")
        });
    bail!(
        "{place}: desired output {} is outside the range ({}, {}) of the outputs the model can \
         reach from its state at this line ({bounded} bounds its operator input){advice}",
        Num(value),
        sig(min, 7),
        sig(max, 7),
    )
}
