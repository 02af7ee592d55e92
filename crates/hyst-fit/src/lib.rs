//! Identification of the smooth parametric hysteresis model from measured data.
//!
//! - [`Dataset`]: records of (input, output) samples read from a CSV table (one record per value
//!   of a `loop` / `curve_index` column, each starting from its own initial state), optional
//!   weights, a train/validation split by record.
//! - [`Structure`]: the model structure (k2 constant or affine, shaping functions, offsets, the
//!   start rule), laid out as free parameters by [`structure::Layout`].
//! - [`SmoothModel`]: the fitted model ψ_out(H(k1, k2)[ψ_in(in)]), or its stop form
//!   ψ_out(v − H[v]) + c·v for clockwise loops ([`Form`]), with its k2 law (the core's
//!   [`hyst_core::AnyK2Law`]), [`hyst_core::ScaledShaping`] and start rule ([`InitialState`]).
//! - [`orientation`]: which way the data's loops run, and the form chosen from it.
//! - [`lm`]: the least-squares problem, method (bounded Levenberg–Marquardt, settings checked
//!   when set) and observers.
//! - [`fit_smooth`]: multi-start fit with standard errors; [`widths`]: the family widths
//!   (Definition 2.8, the core's [`hyst_core::Family`]) that reproduce the data and the bound
//!   Δa (Proposition 3.2).
//! - [`pi`]: the Prandtl–Ishlinskii baseline model; [`pi_fit`]: its fit by non-negative least
//!   squares (with an optional monotone output polynomial).
//! - [`Evaluator`]: any fitted model (or its compensator) behind the core's
//!   [`hyst_core::Operator`].
//! - [`ModelFile`]: the versioned TOML model file (see `docs/formats.md`).
//! - [`identify()`]: the whole identification as one call (the fits a [`identify::Request`]
//!   asks for, the model file, the [`report`]), shared by `hyst fit` and the Python binding.
//!
//! The optional feature `clap` derives `clap::ValueEnum` for the choices a command line offers
//! ([`ShapingKind`], [`K2Kind`], [`InitialState`], [`FormChoice`], [`StartChoice`], [`pi::PiOutputKind`],
//! [`modelfile::ModelKind`]).

#![forbid(unsafe_code)]
// Dense numerical kernels read best with explicit indices.
#![allow(clippy::needless_range_loop)]

pub mod data;
pub mod degeneracy;
pub mod error;
pub mod evaluator;
pub mod identify;
mod linalg;
pub mod lm;
pub mod model;
pub mod modelfile;
pub mod orientation;
pub mod pi;
pub mod pi_fit;
mod race;
pub mod reduction;
pub mod report;
pub mod smooth;
pub mod structure;
pub mod widths;

pub use data::{Columns, DataOptions, Dataset, Record};
pub use error::FitError;
pub use evaluator::{Evaluator, Saturated};
pub use identify::identify;
pub use model::{FitReal, Form, InitialState, SmoothModel};
pub use modelfile::ModelFile;
pub use orientation::{FormChoice, Orientation, StartChoice};
pub use smooth::{fit_smooth, ErrorStats, Estimate, FitOptions, SmoothFit};
pub use structure::{K2Kind, ShapingKind, Structure};
