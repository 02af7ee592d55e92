//! Integrators for ẋ = f(t, x): one classical RK4 step ([`rk4_step`], what the closed loop
//! uses between samples) and an adaptive Dormand–Prince 5(4) integration
//! ([`integrate_adaptive`], the reference solution for fixed-step runs).

use crate::error::{check_finite, finite, positive, SimError};

fn axpy(x: &[f64], h: f64, d: &[f64]) -> Vec<f64> {
    x.iter().zip(d).map(|(x, d)| x + h * d).collect()
}

/// One classical fourth-order Runge–Kutta step of ẋ = f(t, x) from time `t` over `h` (same
/// time unit as f's). Fourth-order accurate when f is smooth over [t, t + h]; a simulator must
/// therefore start a new step at every kink or jump of the input (see
/// [`simulate_compensated`](crate::simulate_compensated)).
///
/// # Errors
/// [`SimError::DimensionMismatch`] when f returns a vector whose length is not that of `x`.
pub fn rk4_step(
    f: &mut impl FnMut(f64, &[f64]) -> Vec<f64>,
    t: f64,
    x: &[f64],
    h: f64,
) -> Result<Vec<f64>, SimError> {
    let n = x.len();
    let mut checked = |s: f64, y: &[f64]| {
        let k = f(s, y);
        if k.len() == n {
            Ok(k)
        } else {
            Err(SimError::DimensionMismatch {
                name: "right-hand side f(t, x)",
                len: k.len(),
                order: n,
            })
        }
    };
    let k1 = checked(t, x)?;
    let k2 = checked(t + 0.5 * h, &axpy(x, 0.5 * h, &k1))?;
    let k3 = checked(t + 0.5 * h, &axpy(x, 0.5 * h, &k2))?;
    let k4 = checked(t + h, &axpy(x, h, &k3))?;
    Ok(x.iter()
        .zip(k1.iter().zip(&k2).zip(k3.iter().zip(&k4)))
        .map(|(x, ((a, b), (c, d)))| x + h / 6.0 * (a + 2.0 * b + 2.0 * c + d))
        .collect())
}

/// Statistics of an adaptive integration ([`integrate_adaptive`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AdaptiveStats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps (error estimate above the tolerance; retried with a smaller step).
    pub rejected: usize,
}

/// The Dormand–Prince 5(4) tableau: the stages' times (fractions of the step)…
const DP_C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
/// …their coefficients on the earlier stages…
const DP_A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// …the fifth-order weights, the last stage's row (first same as last)…
const DP_B5: [f64; 7] = {
    let w = DP_A[6];
    [w[0], w[1], w[2], w[3], w[4], w[5], 0.0]
};
/// …and the embedded fourth-order weights.
const DP_B4: [f64; 7] = [
    5179.0 / 57600.0,
    0.0,
    7571.0 / 16695.0,
    393.0 / 640.0,
    -92097.0 / 339200.0,
    187.0 / 2100.0,
    1.0 / 40.0,
];

/// The seven Dormand–Prince stages k_i = f(t + c_i h, x + h Σ_j a_ij k_j) of a step `h` from
/// (`t`, `x`).
///
/// # Errors
/// [`SimError::DimensionMismatch`] when f returns a vector whose length is not that of `x`.
fn dp_stages(
    f: &mut impl FnMut(f64, &[f64]) -> Vec<f64>,
    t: f64,
    x: &[f64],
    h: f64,
) -> Result<Vec<Vec<f64>>, SimError> {
    let n = x.len();
    let mut k: Vec<Vec<f64>> = Vec::with_capacity(7);
    for (c, a) in DP_C.iter().zip(&DP_A) {
        let mut xs = x.to_vec();
        for (aj, kj) in a.iter().zip(&k) {
            for (xi, kji) in xs.iter_mut().zip(kj) {
                *xi += h * aj * kji;
            }
        }
        let ks = f(t + c * h, &xs);
        if ks.len() != n {
            return Err(SimError::DimensionMismatch {
                name: "right-hand side f(t, x)",
                len: ks.len(),
                order: n,
            });
        }
        k.push(ks);
    }
    Ok(k)
}

/// The fifth-order solution after a step `h` from `x` with the stages `k`, and the error
/// estimate (fifth minus fourth order) relative to the mixed tolerance `tol` (1 + |x|), the
/// largest over the components: the step is accepted when it is at most 1.
fn dp_solution(x: &[f64], k: &[Vec<f64>], h: f64, tol: f64) -> (Vec<f64>, f64) {
    let mut err = 0.0_f64;
    let mut x5 = x.to_vec();
    for (i, (xi, x5i)) in x.iter().zip(x5.iter_mut()).enumerate() {
        let stage = |s: &Vec<f64>| s.get(i).copied().unwrap_or(0.0);
        let d5: f64 = DP_B5.iter().zip(k).map(|(b, s)| b * stage(s)).sum();
        let d4: f64 = DP_B4.iter().zip(k).map(|(b, s)| b * stage(s)).sum();
        *x5i += h * d5;
        let scale = tol * (1.0 + xi.abs().max(x5i.abs()));
        err = err.max((h * (d5 - d4)).abs() / scale);
    }
    (x5, err)
}

/// The factor on the step size after a step with the relative error `err`: 0.9 err^(−1/5)
/// (the fifth-order step that would have met the tolerance, with a safety margin), kept in
/// [0.2, 5].
fn step_factor(err: f64) -> f64 {
    if err == 0.0 {
        5.0
    } else {
        (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
    }
}

/// Integrates ẋ = f(t, x) from `t0` to `t1` (t1 ≤ t0 returns `x0` unchanged) with the
/// Dormand–Prince 5(4) pair and step-size control on the mixed error tolerance `tol`
/// (absolute and relative, per component: |error| ≤ tol (1 + |x|)). Used as the reference
/// solution for fixed-step runs.
///
/// # Errors
/// [`SimError::InvalidParameter`] for a non-finite t0 or t1 or a tol that is not finite and
/// positive, [`SimError::NonFinite`] for a non-finite entry of `x0`,
/// [`SimError::DimensionMismatch`] when f returns a vector of the wrong length,
/// [`SimError::NonFiniteDerivative`] and [`SimError::StepSizeUnderflow`] for a singular or
/// non-finite right-hand side.
pub fn integrate_adaptive(
    f: &mut impl FnMut(f64, &[f64]) -> Vec<f64>,
    t0: f64,
    t1: f64,
    x0: &[f64],
    tol: f64,
) -> Result<(Vec<f64>, AdaptiveStats), SimError> {
    finite("t0", t0)?;
    finite("t1", t1)?;
    positive("tol", tol)?;
    check_finite("x0", x0)?;
    let mut stats = AdaptiveStats::default();
    let mut t = t0;
    let mut x = x0.to_vec();
    let span = t1 - t0;
    if span <= 0.0 {
        return Ok((x, stats));
    }
    let mut h = span.min(0.01 * span.max(1e-6));
    while t < t1 {
        if t + h > t1 {
            h = t1 - t;
        }
        let k = dp_stages(f, t, &x, h)?;
        let (x5, err) = dp_solution(&x, &k, h, tol);
        if !err.is_finite() {
            return Err(SimError::NonFiniteDerivative { t });
        }
        if err <= 1.0 {
            t += h;
            x = x5;
            stats.accepted += 1;
        } else {
            stats.rejected += 1;
        }
        h *= step_factor(err);
        if h < 1e-14 * span.max(1.0) {
            return Err(SimError::StepSizeUnderflow { t, h });
        }
    }
    Ok((x, stats))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrators_agree_with_the_exponential() -> Result<(), SimError> {
        let mut f = |_t: f64, x: &[f64]| vec![-x[0], x[0] - 2.0 * x[1]];
        let mut x = vec![1.0, 0.0];
        for k in 0..100 {
            x = rk4_step(&mut f, k as f64 * 0.01, &x, 0.01)?;
        }
        let exact0 = (-1.0_f64).exp();
        let exact1 = (-1.0_f64).exp() - (-2.0_f64).exp();
        assert!((x[0] - exact0).abs() < 1e-9 && (x[1] - exact1).abs() < 1e-9);
        let (y, stats) = integrate_adaptive(&mut f, 0.0, 1.0, &[1.0, 0.0], 1e-10)?;
        assert!(
            (y[0] - exact0).abs() < 1e-8 && (y[1] - exact1).abs() < 1e-8,
            "{y:?}"
        );
        assert!(stats.accepted > 3);
        // A right-hand side of the wrong length and a bad tolerance are errors, not panics.
        let mut short = |_t: f64, _x: &[f64]| vec![1.0];
        assert!(matches!(
            rk4_step(&mut short, 0.0, &[1.0, 2.0], 0.1),
            Err(SimError::DimensionMismatch {
                len: 1,
                order: 2,
                ..
            })
        ));
        assert!(integrate_adaptive(&mut short, 0.0, 1.0, &[1.0, 2.0], 1e-6).is_err());
        assert!(integrate_adaptive(&mut f, 0.0, 1.0, &[1.0, 0.0], -1.0).is_err());
        Ok(())
    }
}
