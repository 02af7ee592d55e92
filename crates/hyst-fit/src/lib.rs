//! Identification of the smooth parametric hysteresis model from measured data.
//!
//! - [`Dataset`]: records of (input, output) samples read from a CSV table (one record per value
//!   of a `loop` / `curve_index` column, each starting from its own initial state), optional
//!   weights, a train/validation split by record.
//! - [`Structure`]: the model structure (k2 constant or affine, shaping functions, offsets, the
//!   start rule), laid out as free parameters by [`structure::Layout`].
//! - [`lm`]: the least-squares problem, method (bounded Levenberg–Marquardt) and observers.
//! - [`fit_smooth`]: multi-start fit with standard errors; [`widths`]: the family widths
//!   (Definition 2.8) that reproduce the data and the bound Δa (Proposition 3.2).
//! - [`pi`]: the Prandtl–Ishlinskii baseline, fitted by non-negative least squares.
//! - [`ModelFile`]: the versioned TOML model file (see `docs/formats.md`).

#![forbid(unsafe_code)]
// Dense numerical kernels read best with explicit indices.
#![allow(clippy::needless_range_loop)]

pub mod data;
pub mod error;
pub mod evaluator;
pub mod lm;
pub mod model;
pub mod modelfile;
pub mod pi;
pub mod scaled_shaping;
pub mod smooth;
pub mod structure;
pub mod widths;

pub use data::{Columns, DataOptions, Dataset, Record};
pub use error::FitError;
pub use evaluator::Evaluator;
pub use model::{InitialState, SmoothModel};
pub use modelfile::ModelFile;
pub use scaled_shaping::ScaledShaping;
pub use smooth::{fit_smooth, ErrorStats, Estimate, FitOptions, SmoothFit};
pub use structure::{K2Kind, ShapingKind, Structure};
