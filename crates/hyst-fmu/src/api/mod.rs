//! The exported FMI 2.0 Co-Simulation functions (every one, under its plain C name).
//!
//! Each function body runs inside `catch_unwind` (a caught panic gives `fmi2Fatal`, or NULL from
//! fmi2Instantiate, and the instance then refuses every call but fmi2FreeInstance), checks its
//! pointers (NULL, alignment, an instance handle's tag, an FMU state handle against the
//! instance's own list) and the mode of the instance (`fmi2Error` and a logged message for a call
//! in the wrong mode), then calls the safe [`Instance`](crate::instance::Instance). Unsupported
//! functions return `fmi2Error` with a logged message. All `unsafe` of the crate is here and in the logger call.
//!
//! One module per concept: [`lifecycle`] (instantiation, modes, steps), [`values`] (the
//! variables), [`states`] (FMU states and their serialised form), [`status`] (the status
//! functions), and the checks at the C boundary that they share (`boundary`).

mod boundary;
pub mod lifecycle;
pub mod states;
pub mod status;
pub mod values;

pub use lifecycle::*;
pub use states::*;
pub use status::*;
pub use values::*;
