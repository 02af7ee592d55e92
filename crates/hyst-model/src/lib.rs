//! The model runtime of hyst: everything needed to *run* a fitted model, nothing needed to fit
//! one. hyst-fit writes what this crate reads; the C API, the FMU, `hyst run` and the Python
//! package run models through it.
//!
//! - [`ModelFile`] (module [`file`](mod@file)): the versioned TOML model file (`docs/formats.md`), read,
//!   checked and turned into text ([`ModelFile::to_toml`]; `hyst_fit::file::write` writes it
//!   to disk, atomically, for the fit, `hyst adapt` and Python).
//! - [`SmoothModel`] (module [`smooth`]): the fitted smooth model y = ψ_out(H(k1, k2)\[ψ_in(x)\])
//!   or its stop form, with its start rule ([`InitialState`]) and [`Form`]; its exact inverse.
//! - [`PiModel`] (module [`pi`]): the Prandtl–Ishlinskii baseline, with its optional output
//!   polynomial, and its exact inverse.
//! - [`Evaluator`]: any of them (or its inverse) behind the core's one stepping interface
//!   [`hyst_core::Operator`]; [`Saturated`]: an inverse whose desired outputs are clamped into a
//!   saturating model's limits ([`Saturation`]).
//! - [`Dynamics`] and [`Rate`] (module [`dynamics`]): Lemma 5.1's plant before the hysteresis
//!   and a viscous rate term, with the one discretisation every surface uses and its [`Hold`];
//!   [`TimeSteps`] (module [`time`]): a record's time steps as measured; [`TimedRun`],
//!   [`TimedCompensator`] and [`Prefilter`] (module [`timed`]) run such a model over a timed
//!   record.
//! - [`Structure`]: the structure a model was fitted with; [`FamilyWidths`]: the family that
//!   reproduces the data and its bound Δa; [`provenance`]: what the file records of the data
//!   and the fit.
//!
//! A model file as firmware source (`hyst export c|rust`) is hyst-codegen's: the C library and
//! the FMU, which run models through this crate, do not compile the code generators.
//!
//! - [`Choice`] (module [`choice`]): the named choices of a model file, a command line and
//!   Python's keywords ([`ShapingKind`], [`K2Kind`], [`RateTerm`], [`Form`], [`Hold`],
//!   [`ModelKind`]): each one's names and descriptions in one table, parsed from text.
//! - [`time::TIME_COLUMNS`]: the names a record's time column goes by when none is named.

#![forbid(unsafe_code)]

pub mod adaptive;
pub mod choice;
pub mod dynamics;
pub mod error;
pub mod evaluator;
pub mod family;
pub mod file;
pub mod input_units;
pub mod pi;
pub mod provenance;
pub mod saturation;
pub mod smooth;
pub mod structure;
pub mod time;
pub mod timed;

pub use choice::{Choice, UnknownChoice};
pub use dynamics::{Dynamics, Hold, Rate, MAX_DYNAMICS};
pub use error::ModelError;
pub use evaluator::{Evaluator, EvaluatorMemory};
pub use family::FamilyWidths;
pub use file::{ModelFile, ModelKind};
pub use input_units::{input_units, InputUnits};
pub use pi::{PiModel, PiOperator, PiOutput};
pub use provenance::{Columns, ErrorStats, ErrorSums, Estimate, Metrics, Provenance, Units};
pub use saturation::{Saturated, Saturation};
pub use smooth::{Form, InitialState, SmoothModel};
pub use structure::{K2Kind, RateTerm, ShapingKind, Structure};
pub use time::TimeSteps;
pub use timed::{
    Corner, Prefilter, TimedCompensator, TimedRun, TimedSample, CORNER_SAMPLES,
    PREFILTER_NYQUIST_FRACTION,
};
