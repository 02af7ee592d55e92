//! The grid of starting points of the least-squares method: points over (k1, k2), each with
//! the output gain and offset that fit the data best for them by linear least squares.

use hyst_core::Shaping;
use rayon::prelude::*;

use crate::linalg::cholesky_solve;
use crate::smooth::problem::SmoothProblem;

/// Points θ, each with a cost (NaN when not known).
pub(super) type Starts = Vec<(f64, Vec<f64>)>;

/// The points of a grid over (k1, k2), each with the least-squares output gain and offset
/// ([`linear_output_start`]) and its cost, lowest cost first; points that are infeasible or
/// cost a non-finite amount are left out. Evaluated on the machine's threads (in grid order, as
/// one after the other).
pub(super) fn grid_starts(problem: &SmoothProblem<'_>) -> Starts {
    let layout = problem.layout;
    let points = [0.02_f64, 0.05, 0.1, 0.2, 0.4]
        .into_iter()
        .flat_map(|k1| [1.0_f64, 3.0, 10.0, 30.0].map(|k2| (k1, k2)))
        .map(|(k1, k2)| {
            let mut theta = layout.start();
            if let Some(i) = layout.index("k1") {
                theta[i] = k1.ln();
            }
            if let Some(i) = layout.index("k2") {
                theta[i] = k2.ln();
            }
            theta
        })
        .collect();
    ranked_starts(problem, points)
}

/// The points θ, each with the least-squares output gain and offset
/// ([`linear_output_start`]) and its cost, lowest cost first; points that are infeasible or
/// cost a non-finite amount are left out. Evaluated on the machine's threads (the result that
/// of evaluating them in order: the sort is stable).
pub(super) fn ranked_starts(problem: &SmoothProblem<'_>, points: Vec<Vec<f64>>) -> Starts {
    let timed = crate::timed::is_timed(problem.layout.structure);
    let mut candidates: Starts = points
        .into_par_iter()
        .filter_map(|theta| {
            let (theta, z) = linear_output_start(problem, theta)?;
            // A plant or a rate term changes what the output sees beyond the operator output:
            // the full run.
            let cost = if timed {
                crate::lm::Problem::cost(problem, &theta).ok()?
            } else {
                problem.cost_from_operator(&theta, &z)?
            };
            cost.is_finite().then_some((cost, theta))
        })
        .collect();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    candidates
}

/// Sets the output gain (and offset, and the stop form's linear term) of θ by linear least
/// squares on the shaped operator output (the rest of θ fixed), and returns it with the
/// operator output H[ψ_in(in)] per residual (which the new θ leaves as it is). `None` when the
/// point is infeasible.
fn linear_output_start(
    problem: &SmoothProblem<'_>,
    mut theta: Vec<f64>,
) -> Option<(Vec<f64>, Vec<f64>)> {
    let layout = problem.layout;
    // The overall gain: ψ_out's, a saturating ψ_out's slope at the centre, or the stop form's
    // level (gain × k1); the offset: ψ_out's, or a saturating ψ_out's level at the centre
    // (ψ_out is linear in both).
    let gi = layout
        .index("out.gain")
        .or_else(|| layout.index("out.slope"))
        .or_else(|| layout.index("out.level"))?;
    let oi = layout
        .index("out.offset")
        .or_else(|| layout.index("out.level_at_centre"));
    let li = layout.index("out.linear");
    let ci = layout.index(crate::layout::RATE_C);
    theta[gi] = 0.0; // gain 1
    for k in [oi, li, ci].into_iter().flatten() {
        theta[k] = 0.0;
    }
    let m = problem.model(&theta).ok()?;
    let (mut s, mut z) = (vec![0.0; problem.n], vec![0.0; problem.n]);
    problem.simulate(&m, &mut s, Some(&mut z)).ok()?;
    let rate = match ci {
        Some(_) => Some(problem.rate_column(&m)?),
        None => None,
    };
    // Columns: the shaped output (gain 1), then v = ψ_in(in) for the linear term, then 1,
    // then the rate term's v̇.
    let p = 1 + usize::from(li.is_some()) + usize::from(oi.is_some()) + usize::from(ci.is_some());
    let (mut a, mut b) = (vec![0.0; p * p], vec![0.0; p]);
    let mut i = 0;
    for rec in problem.data.training() {
        for ((x, obs), w) in rec.input.iter().zip(&rec.output).zip(&rec.weight) {
            let mut row = [s[i], 0.0, 0.0, 0.0];
            let mut k = 1;
            if li.is_some() {
                row[k] = m.input_shaping.apply(*x);
                k += 1;
            }
            if oi.is_some() {
                row[k] = 1.0;
                k += 1;
            }
            if let Some(r) = &rate {
                row[k] = r[i];
            }
            for r in 0..p {
                b[r] += w * row[r] * obs;
                for c in 0..p {
                    a[r * p + c] += w * row[r] * row[c];
                }
            }
            i += 1;
        }
    }
    let coef = cholesky_solve(&a, &b, p).unwrap_or_else(|| vec![f64::NAN; p]);
    let gain = coef[0];
    let gain = if gain.is_finite() && gain > 0.0 {
        gain
    } else {
        1e-3 * layout.norm.output_half_span
    };
    theta[gi] = gain.ln();
    for (k, index) in (1..).zip([li, oi, ci].into_iter().flatten()) {
        theta[index] = if coef[k].is_finite() { coef[k] } else { 0.0 };
    }
    Some((theta, z))
}
