//! Fitting the smooth model to a dataset, one concept per module:
//!
//! - `fit`: what a fit takes and gives ([`FitOptions`], [`SmoothFit`]);
//! - `problem`: the least-squares problem (output error over the training records, each
//!   simulated from its own initial state) and its exact Jacobian by forward-mode duals;
//! - `starts`: the grid of starting points, each with its least-squares output gain and offset;
//! - `nesting`: the simpler structures a structure contains ([`contained`], [`simpler`]), whose
//!   optima start its fit;
//! - `driver`: the multi-start driver ([`fit_smooth`]) and the data's [`normalisation`];
//! - `std_errors`: the parameters' standard errors from the covariance;
//! - `allowance`: what a timed fit's standard errors allow for beyond the noise (the hold when
//!   not stated, creep: [`Allowance`]);
//! - `limits`: the parameter limits where a parameter is no longer identified
//!   ([`ParameterLimit`]);
//! - `stats`: error statistics ([`error_stats`], [`error_stats_of`]), a model's run over the
//!   records ([`run_records`]) and the check that a fit's numbers are finite ([`check_finite`]).

pub(crate) mod allowance;
pub(crate) mod driver;
pub(crate) mod fit;
pub(crate) mod limits;
pub(crate) mod nesting;
mod problem;
mod starts;
pub(crate) mod stats;
mod std_errors;

pub use allowance::{Allowance, Creep};
pub use driver::{fit_smooth, normalisation};
pub use fit::{FitOptions, SmoothFit};
pub use limits::{ParameterLimit, BACKLASH_LIMIT, DAHL_LIMIT};
pub use nesting::{contained, simpler};
pub use stats::{check_finite, error_stats, error_stats_of, run_records};
