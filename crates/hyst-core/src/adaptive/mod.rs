//! Online adaptation: a recursive estimator that follows a drifting actuator's parameters from
//! each new pair of command x and measured output y, and the exact inverse that uses them ([`AdaptiveInverse`]).
//!
//! The model is a shaped model y = ψ_out(H(k1, k2)\[ψ_in(x)\]) (Section 4.3) with
//! ψ = `post_gain` · shape(`pre_gain` · x + `pre_offset`) + `post_offset` ([`ScaledShaping`](crate::ScaledShaping)).
//! The estimator follows up to six of its parameters ([`Parameter`]): k1, k2 (a constant k2, or
//! an input-dependent law scaled as a whole), the output gain and offset (ψ_out's `post_gain`
//! and `post_offset`) and, where asked, the input gain and offset (ψ_in's).
//!
//! # Method: an extended Kalman filter on the exact sensitivities
//!
//! The parameters are a random walk θ\[k\] = θ\[k−1\] + w, in relative units (each parameter is
//! its fitted value times 1 + θ_i; an offset is its fitted value plus θ_i times the loop's
//! half-width). Each sample:
//!
//! 1. **Prediction.** The model steps once on [`Dual`](crate::Dual) numbers: the one-step prediction ŷ with
//!    parameters before the update, and φ = ∂ŷ/∂θ, exact, through the operator's memory (the
//!    reversal point carries its own sensitivities: Definition 2.1 on duals).
//! 2. **Start.** Until the model meets its first reversal after a start (its first sample, or
//!    [`Adaptive::restart`] for a new record), its state is the start rule's guess and the
//!    prediction error says as much about that guess as about the parameters: nothing is
//!    updated.
//! 3. **Excitation gate.** The input's travel since the last update, |Δv| summed in operator
//!    units, must reach `rest` · k1. Until it does, nothing is updated and nothing grows: at a
//!    constant input the parameters do not move at all, and a slowly creeping input updates
//!    them as often as it moves (a rest of 10⁶ samples leaves them bit-identical).
//! 4. **Time update.** P ← P + (`drift`² · travel / k1) I on the adapted parameters: the
//!    uncertainty grows with the input travel since the last update, not with time, so the
//!    sample rate does not change the behaviour.
//! 5. **Measurement update.** With R = `noise`², h = P φ, d = R + φᵀh: the innovation
//!    e = y − ŷ is clipped to ±5 √d (one wild sample cannot throw the parameters), a dead zone
//!    |e| ≤ `dead_zone` skips the update, θ ← θ + h e / d with the step scaled so that no
//!    parameter moves by more than `step` (relative) per update, P ← P − h hᵀ / d.
//! 6. **Ranges.** Each gain, k1 and k2 stays in \[fitted / `range`, fitted · `range`\] (so > 0),
//!    each offset within ± `range` half-widths of its fitted value, and P's diagonal never
//!    exceeds the cap, max(`uncertainty`, 0.1)² (a congruence scaling, which keeps P positive semidefinite): no
//!    burst when excitation returns after a long rest. A change that the core refuses (k1 k2
//!    below the float resolution) is not taken.
//!
//! The memory stays in operator units across an update. Before the inverse computes a
//! command the memory is re-anchored for the current parameters (`anchor`): the last point
//! stays (moved onto the band's edge if a smaller k1 leaves it outside) and the reversal output
//! moves so that the new branch passes through it. The command for the desired output last met
//! is then the last command wherever the branch still depends on its reversal point: switching
//! parameters adds no jump to the command ([`AdaptiveInverse`]).
//!
//! Bad samples: a non-finite x, or one outside `input_range`, skips the update (and a
//! non-finite x leaves the memory unchanged); a non-finite y skips it too; each is counted
//! ([`Counts`]). Nothing is corrupted.

mod anchor;
mod covariance;
mod estimator;
mod inverse;
mod settings;
mod status;

pub use inverse::AdaptiveInverse;

/// The old name of [`AdaptiveInverse`]: it is an exact inverse, and "compensator" names
/// Lemma 5.1's law alone (docs/formats.md, "Deprecated names").
#[deprecated(note = "renamed AdaptiveInverse")]
pub type AdaptiveCompensator<T> = AdaptiveInverse<T>;
pub use estimator::{Adaptive, AdaptiveModel};
pub use settings::{AdaptiveConfig, Parameter, Parameters, MAX_PARAMETERS};
pub use status::{Counts, Status, Update};

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::panic)]
mod tests;
