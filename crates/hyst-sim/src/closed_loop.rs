//! The closed loop of Lemma 5.1 (eqs. 18–20): a linear plant followed by a "true" hysteresis,
//! driven by the compensator of eq. (19); [`simulate_compensated`] returns a [`Trace`].

use hyst_core::{Compensator, K2Law, Operator, Shaping};

use crate::error::{check_finite, SimError};
use crate::integrate::rk4_step;
use crate::plant::StateSpace;

/// One sampled trace of a compensated plant (Lemma 5.1), one entry per sample. "Output units"
/// are those of the hysteresis output x2 (and of v), "plant units" those of the plant output x1
/// (the hysteresis input).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// Sample times t_k = k dt (s).
    pub t: Vec<f64>,
    /// The new input u_new = v⁽ⁿ⁾, held over the sample (output units per sⁿ).
    pub u_new: Vec<f64>,
    /// The reference v(t_k): what the compensated output x2 should be (eq. 20 with Δ = 0;
    /// output units).
    pub reference: Vec<f64>,
    /// The target x(t_k) = ψ_in⁻¹(H⁻¹[ψ_out⁻¹(v)]) that x1 should follow (plant units).
    pub target: Vec<f64>,
    /// The command u (eq. 19) sent to the plant just after t_k (the right limit: at a reversal
    /// of v at t_k it is the new branch's value; the plant's input units).
    pub command: Vec<f64>,
    /// The plant output x1(t_k) before the hysteresis (plant units).
    pub x1: Vec<f64>,
    /// The hysteresis output x2(t_k) = truth\[x1\] (output units).
    pub output: Vec<f64>,
}

/// The most integration pieces per sample: the compensator itself commits at most 4 turning
/// points of v per sample.
const MAX_PIECES: usize = 5;

/// Simulates eq. (18)'s plant b / (a_n sⁿ + … + 1) (here `plant`, a [`StateSpace`] whose output
/// is x1) followed by the hysteresis `truth` on x1, driven by the Lemma 5.1 compensator `comp`
/// (eq. 19) with the new input `u_new(t, [v, v̇, …])` (evaluated mid-sample and held over each
/// sample), for `samples` samples of `dt` (s), starting from the plant state `x0`.
///
/// Between samples the plant is integrated with RK4, with the command evaluated at the stage
/// times ([`Compensator::peek`]). The command is smooth only between reversals of v (it has a
/// kink for n = 1 and a jump for n ≥ 2 there, Proposition 2.7), so each step is split at the
/// reversal instants: at the sample instant (n = 1: v̇ = u_new changes sign between samples;
/// the stages use the new branch's command) and at the turning points inside the sample
/// ([`Compensator::turning_point`], n ≥ 2; the piece before one ends on the old branch's command,
/// the piece after it starts on the new one). RK4's fourth order is kept that way: with the exact
/// model as the truth, x1 − x and x2 − v shrink 16-fold when dt is halved (n = 1, 2).
///
/// The truth is any [`Operator`] (the exact [`hyst_core::ShapedModel`], a fitted model, a
/// [`hyst_core::Play`], a [`crate::Drifting`] member, a [`crate::Preisach`] model). It is
/// stepped once per sample with x1(t_k), and once more with x1 at each turning point inside a
/// sample (n ≥ 2 only), so that its reversal point is the extremum and not the nearest sample;
/// only the per-sample outputs enter the trace. A truth that counts its evaluations (such as
/// [`crate::Drifting`]'s drift index) counts those extra ones too.
///
/// # Errors
/// [`SimError::InvalidParameter`] for a `dt` that is not finite and > 0,
/// [`SimError::DimensionMismatch`] when `x0` does not have the plant's order,
/// [`SimError::NonFinite`] for a non-finite entry of `x0`, and the compensator's errors as
/// [`SimError::Core`] (a non-finite u_new, a reference outside a shaping function's range),
/// and a sample the truth refuses ([`Operator::try_step`], e.g. a non-finite x1) as
/// [`SimError::Core`].
#[allow(clippy::too_many_arguments)]
pub fn simulate_compensated<const N: usize, I, K, O, H>(
    plant: &StateSpace,
    comp: &mut Compensator<f64, N, I, K, O>,
    truth: &mut H,
    u_new: &mut dyn FnMut(f64, &[f64]) -> f64,
    x0: &[f64],
    dt: f64,
    samples: usize,
) -> Result<Trace, SimError>
where
    I: Shaping<f64> + Clone,
    K: K2Law<f64> + Clone,
    O: Shaping<f64> + Clone,
    H: Operator<f64>,
{
    if !(dt.is_finite() && dt > 0.0) {
        return Err(SimError::InvalidParameter {
            name: "dt",
            value: dt,
            expected: "finite and > 0 (s)",
        });
    }
    if x0.len() != plant.order() {
        return Err(SimError::DimensionMismatch {
            name: "x0",
            len: x0.len(),
            order: plant.order(),
        });
    }
    check_finite("x0", x0)?;
    let mut x = x0.to_vec();
    let mut trace = Trace::default();
    for k in 0..samples {
        let t = k as f64 * dt;
        let un = u_new(t + 0.5 * dt, &comp.state());
        // `piece` is the compensator at the start of the current integration piece with the value
        // there committed, so that a reversal exactly there is seen through the trend of the jet:
        // its `peek(un, 0)` is the right limit of the command.
        let mut piece = comp.clone();
        let _ = piece.try_step(un, 0.0)?;
        let command = piece.peek(un, 0.0)?;
        let x1 = plant.output(&x, command);
        let _ = comp.try_step(un, dt)?;
        trace.t.push(t);
        trace.u_new.push(un);
        trace.reference.push(comp.last_reference());
        trace.target.push(comp.last_target().value());
        trace.command.push(command);
        trace.x1.push(x1);
        trace.output.push(truth.try_step(x1)?);

        let mut t0 = 0.0;
        for index in 0..MAX_PIECES {
            let rest = dt - t0;
            let turning = match piece.turning_point(un, rest) {
                Some(tau) if index + 1 < MAX_PIECES && tau < rest => Some(tau),
                _ => None,
            };
            let h = turning.unwrap_or(rest);
            // The last stage ends on the current branch: just before a turning point (the left
            // limit; 1e-9 of the step changes the command by O(1e-9 dt)).
            let end = if turning.is_some() || piece.turning_point(un, rest).is_some() {
                (h - 1e-9 * dt).max(0.0)
            } else {
                h
            };
            let us = [
                piece.peek(un, 0.0)?,
                piece.peek(un, 0.5 * h)?,
                piece.peek(un, end)?,
            ];
            let mut f = |s: f64, xs: &[f64]| {
                let u = if s <= 0.0 {
                    us[0]
                } else if s < h {
                    us[1]
                } else {
                    us[2]
                };
                plant.derivative(xs, u)
            };
            x = rk4_step(&mut f, 0.0, &x, h)?;
            match turning {
                Some(tau) => {
                    let _ = truth.try_step(plant.output(&x, us[2]))?;
                    // Advance to the turning point (committing it as the reversal point) and
                    // commit the value there; the next piece starts on the new branch.
                    let _ = piece.try_step(un, tau)?;
                    let _ = piece.try_step(un, 0.0)?;
                    t0 += tau;
                }
                None => break,
            }
        }
    }
    Ok(trace)
}
