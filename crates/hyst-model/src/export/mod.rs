//! A model file as firmware source: a header-only C99 file over `hyst.h` ([`c()`]), or a `no_std`
//! Rust constructor over hyst-core ([`rust()`]). Both run the model exactly as `hyst run --model`
//! does, from the first sample: the start rule is applied at the first sample, the parameters
//! are the file's, bit for bit, and an inverse clamps desired outputs into the limits of a
//! saturating output shaping as `hyst run --inverse --saturate` does.
//!
//! `hyst export c|rust` and Python's `Model.export_c`/`export_rust` call these functions, so
//! every surface writes the same text.

pub mod c;
pub mod rust;
mod shared;

pub use c::c;
pub use rust::rust;
pub use shared::{check_name, Source};
