//! The memory carried across a change of parameters: the state (the last input and output) does
//! not jump, the branch it is on is moved.
//!
//! Definition 2.1's output is a function of the input and the reversal point (α0, β0). New k1
//! and k2 from the same reversal point would put the last output elsewhere: a jump in the
//! model's output, and in a compensator's command. So the reversal input α0 and the direction
//! stay, and β0 moves until the new branch passes through the last point (α, β):
//! with ṽ = s (α − α0), a = s (β − α0) and w = s (β − β0), eq. (2) written as
//! ṽ − w = M* (1 − e^(−k2 w)), M* = a − w + k1, gives
//!
//! g(w) = (a + k1 − w)(1 − e^(−k2 w)) − (ṽ − w) = 0,
//!
//! increasing in w on [max(0, a − k1), min(ṽ, a + k1)] (where 0 ≤ M* ≤ 2 k1), g ≤ 0 at the left
//! end and ≥ 0 at the right end once the last point is in the band. Its root has a closed form
//! through Lambert's W, as eq. (2) itself (see `root`). β0 keeps its gradient (its sensitivity to the parameters before the move):
//! the sensitivities stay those of the run, and are not divided by g', which vanishes where the
//! reversal point nears the band's edge. Far along a
//! branch (g' below √ε) the output no longer depends on β0 and the memory is kept: there the
//! output is the asymptote v ∓ k1 whatever the history, and a new k1 moves it by the change
//! of k1, which no memory can undo.

use crate::dual::Dual;
use crate::lambert::w0;
use crate::memory::Memory;
use crate::real::Real;

type D<T, const W: usize> = Dual<T, W>;

/// `m` made right for the parameters k1 and k2 (k2 at the last input): the last point moved
/// into the band |β − α| ≤ k1 (onto its edge), then β0 moved so that the branch passes
/// through it.
pub(super) fn reanchor<T: Real, const W: usize>(m: &mut Memory<D<T, W>>, k1: D<T, W>, k2: D<T, W>) {
    into_band(m, k1);
    let s = m.direction.sign::<T>();
    let vt = (m.last_input.value() - m.reversal_input.value()) * s;
    let a = (m.last_output.value() - m.reversal_input.value()) * s;
    let Some(w) = root(vt, a, k1.value(), k2.value()) else {
        return;
    };
    // The value moves; the gradient stays β0's own. Differentiating through the root would
    // divide by g', which is small where the reversal point lies near the band's edge (M* → 0),
    // and an update at every sample would compound that division into an overflow.
    m.reversal_output = D::new(m.last_output.value() - w * s, m.reversal_output.gradient());
}

/// The root w of g (plain numbers), in closed form: with z = A − w and A = a + k1, g(w) = 0 is
/// z e^(k2 z) = (A − ṽ) e^(k2 A), so k2 z = W0(k2 (A − ṽ) e^(k2 A)). `None` when k2 A is
/// beyond the exponent range (`Real::EXP_ARG_MAX`), when the branch is flat in w there
/// (g' = e^(−k2 w) (1 + k2 z) = (A − ṽ)(1 + k2 z) / z below √ε: 1.5e-8 for f64, 3.5e-4 for
/// f32), at the reversal point itself (ṽ = 0), or when the numbers are not finite.
fn root<T: Real>(vt: T, a: T, k1: T, k2: T) -> Option<T> {
    let zero = T::zero();
    let big_a = a + k1;
    let gap = big_a - vt;
    if vt.partial_cmp(&zero) != Some(core::cmp::Ordering::Greater) || gap <= zero {
        return None;
    }
    // Beyond the exponent range (a near-hard backlash far past its reversal, where the branch
    // has all but met its asymptote) the memory is kept: the Wright omega that would reach
    // there costs a firmware its own code for an edge the no-jump promise can spare.
    let y = k2 * big_a;
    if y > T::EXP_ARG_MAX {
        return None;
    }
    let z = w0(k2 * gap * y.exp()) / k2;
    let slope = gap * (T::one() + k2 * z) / z;
    let w = (big_a - z).max((a - k1).max(zero)).min(vt.min(big_a));
    (z > zero && slope > T::epsilon().sqrt() && w.is_finite()).then_some(w)
}

/// Each output of `m` moved into the band |output − input| ≤ k1 (onto its edge).
fn into_band<T: Real, const W: usize>(m: &mut Memory<D<T, W>>, k1: D<T, W>) {
    let clamp = |input: D<T, W>, output: D<T, W>| {
        if output.value() > input.value() + k1.value() {
            input + k1
        } else if output.value() < input.value() - k1.value() {
            input - k1
        } else {
            output
        }
    };
    m.reversal_output = clamp(m.reversal_input, m.reversal_output);
    m.last_output = clamp(m.last_input, m.last_output);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::operator::Operator;
    use crate::parametric::Hysteresis;

    /// After new k1 and k2, the operator from the re-anchored memory gives the last output again
    /// at the last input (no jump).
    #[test]
    fn the_new_branch_passes_through_the_last_point() -> Result<(), crate::Error> {
        let mut h = Hysteresis::new(D::<f64, 6>::constant(0.2), D::constant(8.0))?;
        for v in [0.0, 0.5, 0.9, 0.4, 0.1, 0.25] {
            h.step(D::constant(v));
        }
        let m = h
            .memory()
            .ok_or(crate::Error::NonFiniteInput { value: 0.0 })?;
        for (k1, k2) in [(0.23, 7.0), (0.21, 12.0), (0.2, 8.0)] {
            let (k1d, k2d) = (D::constant(k1), D::constant(k2));
            let mut h2 = Hysteresis::new(k1d, k2d)?;
            let mut m2 = m;
            reanchor(&mut m2, k1d, k2d);
            h2.set_memory(Some(m2))?;
            let again = h2.step(m.last_input);
            assert!(
                (again.value() - m.last_output.value()).abs() < 1e-12,
                "{k1} {k2}"
            );
        }
        Ok(())
    }
}
