//! What the tests, benchmarks and examples of the hyst workspace share. A dev-dependency only
//! (`publish = false`; no crate of the workspace depends on it otherwise), with `std`: the
//! crates it serves may be `no_std`, their tests are not.
//!
//! - [`rng`]: the seeded pseudo-random sequences the tests draw from, each algorithm once, so a
//!   test's figures stay those of its seed;
//! - [`signals`]: test signals built on them (standard normal noise, loops, piston strokes);
//! - [`plant`]: a linear plant a_n x⁽ⁿ⁾ + … + a_1 ẋ + x = b u integrated with classical RK4;
//! - [`cli`]: running a binary of the workspace (`hyst`) and collecting its exit, stdout and
//!   stderr, with a limit that fails a hung run instead of waiting for ever;
//! - [`files`]: the repository's paths and the CSV files `hyst` writes, read back.
//!
//! Helpers for tests panic on failure (with a message naming what failed): that is how a test
//! fails.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
#![forbid(unsafe_code)]

pub mod cli;
pub mod files;
pub mod plant;
pub mod rng;
pub mod signals;
