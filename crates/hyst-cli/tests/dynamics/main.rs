//! `hyst fit --dynamics N` and `hyst run --inverse` of a model with dynamics, against synthetic
//! truths (docs/fitting.md, "Dynamics and rate"): the paper's Example 2 (a first-order RL
//! plant before the hysteresis) and Example 3's mass-spring-damper (second order) before a
//! near-hard backlash. Each prints the figures docs/fitting.md states.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::needless_range_loop
)]

use std::path::Path;

use hyst_core::{Hysteresis, Identity, InitialState, Operator, QuadraticExp, ShapedModel};
use hyst_test_support::cli::Binary;
use hyst_test_support::plant::LinearPlant;
use hyst_test_support::rng::{Random, SplitMix64};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

mod examples;
mod prefilter;
mod rate;
mod streams;
mod truths;
