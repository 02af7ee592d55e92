//! Simulation for hyst: the paper's closed loop (Lemma 5.1, eqs. 18–20) and its Examples 1–3
//! (Section 6). One concept per module:
//!
//! - [`plant`]: the linear plant of eq. (18), [`StateSpace`] (from its matrices or a transfer
//!   function);
//! - [`integrate`]: one fixed RK4 step ([`rk4_step`]) and an adaptive Dormand–Prince 5(4)
//!   integration ([`integrate_adaptive`], with its [`AdaptiveStats`]);
//! - [`truth`]: the simulated "true" hysteresis that the core does not provide — a family member
//!   whose parameters drift inside the family ([`Drifting`], with its [`DriftingMemory`]), a
//!   discrete [`Preisach`] model, and the reversal-curve input [`forc_input`];
//! - [`closed_loop`]: [`simulate_compensated`], plant → truth driven by the compensator of
//!   eq. (19), sampled into a [`Trace`];
//! - [`friction`]: a LuGre friction force ([`LuGre`]), a clockwise "truth" for identification;
//! - [`examples`]: the paper's Examples 1–3 as runs, with documented synthetic truths;
//! - [`error`]: the error type, [`SimError`].
//!
//! The simulator steps every truth through the one stepping trait of the workspace,
//! [`hyst_core::Operator`]`<f64>`: the exact [`hyst_core::ShapedModel`], a fitted model, the hard
//! backlash [`hyst_core::Play`] (Example 3), [`Drifting`] and [`Preisach`] alike.
//!
//! Times are in seconds; every other quantity is in the units of the signal it belongs to (the
//! plant's input and output, the hysteresis input and output), stated on each item.
//!
//! Every function that takes user input checks it and returns a [`SimError`] naming the
//! parameter and the value; nothing here panics on user input.

pub mod closed_loop;
pub mod error;
pub mod examples;
pub mod friction;
pub mod integrate;
pub mod plant;
pub mod truth;

pub use closed_loop::{simulate_compensated, Trace};
pub use error::SimError;
pub use friction::LuGre;
pub use integrate::{integrate_adaptive, rk4_step, AdaptiveStats};
pub use plant::StateSpace;
pub use truth::{forc_input, Drifting, DriftingMemory, Preisach};
