//! Status codes: every fallible call returns one (`HYST_OK` = 0 on success), and
//! [`hyst_status_message`] says what it means.

use core::ffi::c_char;

use hyst_core::Error;

/// Success.
pub const HYST_OK: i32 = 0;
/// A required pointer argument is NULL.
pub const HYST_ERR_NULL_POINTER: i32 = 1;
/// A length or derivative order is out of range (order > 4, n > 4 for the compensator, …).
pub const HYST_ERR_LENGTH: i32 = 2;
/// An input sample (or one of its derivatives, or dt) is NaN or infinite; the state is unchanged.
pub const HYST_ERR_NON_FINITE: i32 = 3;
/// A parameter is outside its range (k1, k2 not finite and > 0, a bad shaping parameter, …).
pub const HYST_ERR_INVALID_PARAMETER: i32 = 4;
/// A memory or initial state lies outside the band |output − input| ≤ k1.
pub const HYST_ERR_STATE_OUTSIDE_BAND: i32 = 5;
/// A desired output is outside the range of a saturating shaping function (tanh, Langevin), or
/// outside the outputs the model can reach from its state (a saturating input shaping bounds
/// its operator input).
pub const HYST_ERR_OUT_OF_RANGE: i32 = 6;
/// A shaping function is not strictly increasing on its domain.
pub const HYST_ERR_NOT_MONOTONE: i32 = 7;
/// The k2 law gave a k2 that is not finite and > 0.
pub const HYST_ERR_INVALID_K2: i32 = 8;
/// The state was not initialised by its `_init` function (or was overwritten).
pub const HYST_ERR_NOT_INITIALISED: i32 = 9;
/// The state pointer is not aligned to 8 bytes.
pub const HYST_ERR_MISALIGNED: i32 = 10;
/// A model file cannot be read or is invalid (host part).
pub const HYST_ERR_MODEL_FILE: i32 = 11;
/// An internal error was caught at the boundary (host part; a bug: please report it).
pub const HYST_ERR_INTERNAL: i32 = 12;
/// A finite input gives an output beyond the float range (e.g. the output shaping overflows);
/// the state is unchanged and the last output is written.
pub const HYST_ERR_OVERFLOW: i32 = 13;
/// The model cannot run this way (host part): a model with dynamics or a rate term has no
/// exact inverse (`hyst_model_compensate` is its Lemma 5.1 compensator) nor saturation, and a
/// compensator needs a model with dynamics, of the operator form, without a rate term.
pub const HYST_ERR_UNSUPPORTED: i32 = 14;
/// A measurement came with no command waiting for it (`hyst_adaptive_measure` without a
/// `hyst_adaptive_step` since the last measurement); nothing changed.
pub const HYST_ERR_NO_COMMAND: i32 = 15;

/// The status of a core error.
pub(crate) fn of(error: &Error) -> i32 {
    match error {
        Error::InvalidParameter { .. } | Error::SmallK1K2 { .. } => HYST_ERR_INVALID_PARAMETER,
        Error::NonFiniteInput { .. } => HYST_ERR_NON_FINITE,
        Error::StateOutsideBand { .. } => HYST_ERR_STATE_OUTSIDE_BAND,
        Error::NotMonotone { .. } => HYST_ERR_NOT_MONOTONE,
        Error::OutOfRange { .. } | Error::Unreachable { .. } => HYST_ERR_OUT_OF_RANGE,
        Error::InvalidK2 { .. } => HYST_ERR_INVALID_K2,
        Error::LengthMismatch { .. } => HYST_ERR_LENGTH,
        Error::NonFiniteOutput { .. } => HYST_ERR_OVERFLOW,
        _ => HYST_ERR_INTERNAL,
    }
}

/// The meaning of a status code, as a static NUL-terminated English sentence (never NULL; an
/// unknown code gives "unknown status").
// Exported unmangled for C (`no_mangle` counts as unsafe code); nothing else here is unsafe.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn hyst_status_message(status: i32) -> *const c_char {
    let message: &'static core::ffi::CStr = match status {
        HYST_OK => c"success",
        HYST_ERR_NULL_POINTER => c"a required pointer argument is NULL",
        HYST_ERR_LENGTH => c"a length or derivative order is out of range",
        HYST_ERR_NON_FINITE => {
            c"an input sample, derivative or time step is not finite; the state is unchanged"
        }
        HYST_ERR_INVALID_PARAMETER => c"a parameter is outside its range",
        HYST_ERR_STATE_OUTSIDE_BAND => c"the state lies outside the band |output - input| <= k1",
        HYST_ERR_OUT_OF_RANGE => {
            c"the desired output is outside the range of a saturating shaping function, or of \
              the outputs the model can reach from its state"
        }
        HYST_ERR_NOT_MONOTONE => c"a shaping function is not strictly increasing on its domain",
        HYST_ERR_INVALID_K2 => c"the k2 law gave a k2 that is not finite and > 0",
        HYST_ERR_NOT_INITIALISED => c"the state was not initialised by its _init function",
        HYST_ERR_MISALIGNED => c"the state pointer is not aligned to 8 bytes",
        HYST_ERR_MODEL_FILE => c"the model file cannot be read or is invalid",
        HYST_ERR_INTERNAL => c"internal error caught at the C boundary",
        HYST_ERR_OVERFLOW => {
            c"a finite input gives an output beyond the float range; the state is unchanged"
        }
        HYST_ERR_UNSUPPORTED => {
            c"the model cannot run this way (dynamics or a rate term: no exact inverse nor \
              saturation; a compensator needs dynamics, the operator form and no rate term)"
        }
        HYST_ERR_NO_COMMAND => {
            c"a measurement came with no command waiting for it; nothing changed"
        }
        _ => c"unknown status",
    };
    message.as_ptr()
}
