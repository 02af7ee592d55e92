//! Nonlinear least squares: the problem (residuals and Jacobian), the method (a Levenberg–
//! Marquardt with infeasible-step rejection) and observers (progress, cancellation), kept
//! apart in the manner of argmin.
//!
//! Bounds are handled in two ways that compose: positive parameters are optimised as their
//! logarithm (so k1, k2, gains stay > 0), and any other constraint (a monotone shaping
//! function, a positive k2 law on the data) makes the problem report the point infeasible; the
//! method then rejects the step and increases the damping, so it never leaves the feasible set.

use std::ops::ControlFlow;

use crate::linalg::cholesky_solve;

/// A point the problem cannot evaluate (parameters outside their bounds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Infeasible;

/// A least-squares problem: minimise Σ r_i(θ)².
pub trait Problem {
    /// Number of parameters.
    fn parameters(&self) -> usize;
    /// Number of residuals.
    fn residual_count(&self) -> usize;
    /// The residuals at θ into `r` (length [`Problem::residual_count`]).
    ///
    /// # Errors
    /// [`Infeasible`] when θ is outside the feasible set.
    fn residuals(&self, theta: &[f64], r: &mut [f64]) -> Result<(), Infeasible>;
    /// The Jacobian at θ, column-major (`jac[j * n + i]` = ∂r_i/∂θ_j), given r at θ.
    ///
    /// # Errors
    /// [`Infeasible`] if it cannot be evaluated.
    fn jacobian(&self, theta: &[f64], r: &[f64], jac: &mut [f64]) -> Result<(), Infeasible>;
}

/// What an observer sees after each accepted (or final) iteration.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Iteration number (0 is the starting point).
    pub iteration: usize,
    /// Σ r² at the current point.
    pub cost: f64,
    /// The damping λ.
    pub lambda: f64,
    /// Which start of a multi-start fit (0-based; 0 for a single run).
    pub start: usize,
}

/// Watches the iterations; returning `ControlFlow::Break` stops the method (Ctrl-C).
pub trait Observer {
    /// Called at the start and after every iteration.
    fn observe(&mut self, progress: &Progress) -> ControlFlow<()>;
}

/// An observer that does nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Observer for Silent {
    fn observe(&mut self, _progress: &Progress) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// Why the method stopped (stopping is not an error).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Termination {
    /// The relative step fell below the tolerance.
    SmallStep,
    /// The relative cost decrease fell below the tolerance.
    SmallDecrease,
    /// The gradient vanished (a zero-residual fit, say).
    SmallGradient,
    /// The iteration limit was reached.
    MaxIterations,
    /// No damping made a feasible step that lowers the cost.
    Stalled,
}

/// The result of a run of the method.
#[derive(Clone, Debug)]
pub struct Solution {
    /// The parameters.
    pub theta: Vec<f64>,
    /// Σ r² there.
    pub cost: f64,
    /// Residuals there.
    pub residuals: Vec<f64>,
    /// JᵀJ there (row-major p × p), for the covariance.
    pub jtj: Vec<f64>,
    /// Iterations done.
    pub iterations: usize,
    /// Why it stopped.
    pub termination: Termination,
}

/// The observer asked to stop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cancelled;

/// Levenberg–Marquardt with Marquardt's diagonal scaling (invariant to the units of each
/// parameter) and Nielsen's damping update.
#[derive(Clone, Copy, Debug)]
pub struct LevenbergMarquardt {
    /// Iteration limit.
    pub max_iterations: usize,
    /// Stop when ‖δ‖ ≤ `xtol` (‖θ‖ + `xtol`).
    pub xtol: f64,
    /// Stop when the relative cost decrease of an accepted step is below `ftol` (twice running).
    pub ftol: f64,
    /// Stop when max |Jᵀr| ≤ `gtol` · (cost + tiny).
    pub gtol: f64,
}

impl Default for LevenbergMarquardt {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            xtol: 1e-12,
            ftol: 1e-14,
            gtol: 1e-300,
        }
    }
}

impl LevenbergMarquardt {
    /// Minimises Σ r² from `theta0`.
    ///
    /// # Errors
    /// [`Cancelled`] when the observer breaks; `Ok` with [`Termination::Stalled`] and the start
    /// when the start itself is infeasible is not possible: an infeasible start returns `Ok`
    /// with an infinite cost.
    pub fn minimize<P: Problem + ?Sized>(
        &self,
        problem: &P,
        theta0: &[f64],
        observer: &mut dyn Observer,
    ) -> Result<Solution, Cancelled> {
        let p = problem.parameters();
        let n = problem.residual_count();
        let mut theta = theta0.to_vec();
        let mut r = vec![0.0; n];
        if problem.residuals(&theta, &mut r).is_err() {
            return Ok(Solution {
                theta,
                cost: f64::INFINITY,
                residuals: r,
                jtj: vec![0.0; p * p],
                iterations: 0,
                termination: Termination::Stalled,
            });
        }
        let mut cost = sum_sq(&r);
        let mut jac = vec![0.0; n * p];
        let mut jtj = vec![0.0; p * p];
        let mut g = vec![0.0; p];
        let mut lambda = 1e-3;
        let mut nu = 2.0;
        let mut trial = vec![0.0; p];
        let mut r_trial = vec![0.0; n];
        let mut small_decreases = 0;
        let mut termination = Termination::MaxIterations;
        let mut iterations = 0;
        let mut need_jacobian = true;
        if observer
            .observe(&Progress {
                iteration: 0,
                cost,
                lambda,
                start: 0,
            })
            .is_break()
        {
            return Err(Cancelled);
        }
        'outer: for it in 1..=self.max_iterations {
            iterations = it;
            if need_jacobian {
                if problem.jacobian(&theta, &r, &mut jac).is_err() {
                    termination = Termination::Stalled;
                    break;
                }
                normal_equations(&jac, &r, n, p, &mut jtj, &mut g);
                need_jacobian = false;
            }
            let gmax = g.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            if gmax <= self.gtol * (cost + 1e-300) || cost == 0.0 {
                termination = Termination::SmallGradient;
                break;
            }
            // Try steps with growing damping until one is feasible and lowers the cost.
            loop {
                let mut a = jtj.clone();
                for j in 0..p {
                    let d = jtj[j * p + j].max(1e-30);
                    a[j * p + j] = jtj[j * p + j] + lambda * d;
                }
                let rhs: Vec<f64> = g.iter().map(|v| -v).collect();
                let delta = match cholesky_solve(&a, &rhs, p) {
                    Some(d) => d,
                    None => {
                        lambda *= nu;
                        nu *= 2.0;
                        if lambda > 1e20 {
                            termination = Termination::Stalled;
                            break 'outer;
                        }
                        continue;
                    }
                };
                for j in 0..p {
                    trial[j] = theta[j] + delta[j];
                }
                let step = norm(&delta);
                let size = norm(&theta);
                let feasible = problem.residuals(&trial, &mut r_trial).is_ok();
                let new_cost = if feasible {
                    sum_sq(&r_trial)
                } else {
                    f64::INFINITY
                };
                // Predicted decrease of the damped Gauss–Newton model.
                let mut predicted = 0.0;
                for j in 0..p {
                    predicted += delta[j] * (lambda * jtj[j * p + j].max(1e-30) * delta[j] - g[j]);
                }
                if new_cost.is_finite() && new_cost < cost {
                    let rho = (cost - new_cost) / predicted.max(1e-300);
                    let decrease = (cost - new_cost) / cost.max(1e-300);
                    std::mem::swap(&mut theta, &mut trial);
                    std::mem::swap(&mut r, &mut r_trial);
                    cost = new_cost;
                    need_jacobian = true;
                    let f = 1.0 - (2.0 * rho - 1.0).powi(3);
                    lambda *= f.max(1.0 / 3.0);
                    nu = 2.0;
                    if observer
                        .observe(&Progress {
                            iteration: it,
                            cost,
                            lambda,
                            start: 0,
                        })
                        .is_break()
                    {
                        return Err(Cancelled);
                    }
                    if step <= self.xtol * (size + self.xtol) {
                        termination = Termination::SmallStep;
                        break 'outer;
                    }
                    if decrease < self.ftol {
                        small_decreases += 1;
                        if small_decreases >= 2 {
                            termination = Termination::SmallDecrease;
                            break 'outer;
                        }
                    } else {
                        small_decreases = 0;
                    }
                    break;
                }
                if step <= self.xtol * (size + self.xtol) {
                    termination = Termination::SmallStep;
                    break 'outer;
                }
                lambda *= nu;
                nu *= 2.0;
                if lambda > 1e20 {
                    termination = Termination::Stalled;
                    break 'outer;
                }
            }
        }
        // JᵀJ at the final point, for the covariance.
        if need_jacobian && problem.jacobian(&theta, &r, &mut jac).is_ok() {
            normal_equations(&jac, &r, n, p, &mut jtj, &mut g);
        }
        Ok(Solution {
            theta,
            cost,
            residuals: r,
            jtj,
            iterations,
            termination,
        })
    }
}

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

fn norm(v: &[f64]) -> f64 {
    sum_sq(v).sqrt()
}

/// JᵀJ (row-major) and Jᵀr from a column-major J.
fn normal_equations(jac: &[f64], r: &[f64], n: usize, p: usize, jtj: &mut [f64], g: &mut [f64]) {
    for a in 0..p {
        let ca = &jac[a * n..(a + 1) * n];
        g[a] = ca.iter().zip(r).map(|(x, y)| x * y).sum();
        for b in a..p {
            let cb = &jac[b * n..(b + 1) * n];
            let s: f64 = ca.iter().zip(cb).map(|(x, y)| x * y).sum();
            jtj[a * p + b] = s;
            jtj[b * p + a] = s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y = a e^(b x): a classical small problem with a known optimum.
    struct Exp {
        x: Vec<f64>,
        y: Vec<f64>,
    }
    impl Problem for Exp {
        fn parameters(&self) -> usize {
            2
        }
        fn residual_count(&self) -> usize {
            self.x.len()
        }
        fn residuals(&self, t: &[f64], r: &mut [f64]) -> Result<(), Infeasible> {
            for i in 0..self.x.len() {
                r[i] = t[0] * (t[1] * self.x[i]).exp() - self.y[i];
            }
            Ok(())
        }
        fn jacobian(&self, t: &[f64], _r: &[f64], j: &mut [f64]) -> Result<(), Infeasible> {
            let n = self.x.len();
            for i in 0..n {
                let e = (t[1] * self.x[i]).exp();
                j[i] = e;
                j[n + i] = t[0] * self.x[i] * e;
            }
            Ok(())
        }
    }

    #[test]
    fn recovers_an_exponential() -> Result<(), Cancelled> {
        let x: Vec<f64> = (0..20).map(|i| i as f64 * 0.1).collect();
        let y = x.iter().map(|v| 2.5 * (-1.3 * v).exp()).collect();
        let s = LevenbergMarquardt::default().minimize(&Exp { x, y }, &[1.0, 0.0], &mut Silent)?;
        assert!((s.theta[0] - 2.5).abs() < 1e-10, "{:?}", s.theta);
        assert!((s.theta[1] + 1.3).abs() < 1e-10, "{:?}", s.theta);
        Ok(())
    }
}
