//! Identification of the smooth parametric hysteresis model from measured data.
//!
//! The model itself (the model file, the fitted model kinds and their evaluator) lives in
//! `hyst-model`, the runtime that every surface runs models with; this crate writes what it
//! reads.
//!
//! - [`Dataset`]: records of (input, output) samples read from a CSV table (one record per value
//!   of a `loop` / `curve_index` column, each starting from its own initial state), optional
//!   weights, a train/validation split by record.
//! - [`layout::Layout`]: a model structure ([`hyst_model::Structure`]) laid out as free
//!   parameters.
//! - [`orientation`]: which way the data's loops run, and the form chosen from it.
//! - [`lm`]: the least-squares problem, method (bounded Levenberg–Marquardt, settings checked
//!   when set) and observers.
//! - [`fit_smooth`]: multi-start fit with standard errors; [`widths`]: the family widths
//!   (Definition 2.8, the core's [`hyst_core::Family`]) that reproduce the data and the bound
//!   Δa (Proposition 3.2).
//! - [`pi_fit`]: the Prandtl–Ishlinskii baseline's fit by non-negative least squares (with an
//!   optional monotone output polynomial).
//! - [`degeneracy`]: whether a fit found hysteresis at all.
//! - [`timed`]: fits with dynamics or a rate term: their nesting, the static view their
//!   hysteresis part is checked on, what the report says of the plant and the rate term.
//! - [`settling`]: a record's start discounted until its input has swept its range.
//! - [`identify()`]: the whole identification as one call (the fits a [`identify::Request`]
//!   asks for, the model file, the [`report`]), shared by `hyst fit` and the Python binding.
//!
//! The fit's choices ([`FormChoice`], [`StartChoice`], [`pi_fit::PiOutputKind`]) are
//! [`hyst_model::Choice`]s: named in one table each, parsed from text by the CLI and Python.

#![forbid(unsafe_code)]
// Dense numerical kernels read best with explicit indices.
#![allow(clippy::needless_range_loop)]

pub mod data;
pub mod degeneracy;
pub mod error;
pub mod file;
mod gauss_newton;
mod grouping;
pub mod identify;
pub mod layout;
mod linalg;
pub mod lm;
mod model_reading;
pub mod orientation;
pub mod outputs;
pub mod pi_fit;
mod race;
pub mod record;
pub mod reduction;
pub mod report;
pub mod rows;
pub mod settling;
pub mod smooth;
pub mod timed;
pub mod weights;
pub mod widths;

pub use data::{DataOptions, Dataset, Record};
pub use error::FitError;
pub use identify::identify;
pub use orientation::{FormChoice, Orientation, StartChoice};
pub use smooth::{fit_smooth, FitOptions, SmoothFit};
pub use weights::Weights;
