//! The damped Gauss–Newton step of [`LevenbergMarquardt`](crate::lm::LevenbergMarquardt), the
//! decrease it predicts, and the statistical tests that stop the descent: Bates and Watts'
//! relative offset and decreases that fade.

use crate::linalg::cholesky_solve;

/// The damped Gauss–Newton step δ: (JᵀJ + λ D) δ = −g, D the diagonal of JᵀJ (Marquardt's
/// scaling, each entry at least 1e-30); `None` when the matrix is not positive definite.
pub(crate) fn damped_step(jtj: &[f64], g: &[f64], lambda: f64, p: usize) -> Option<Vec<f64>> {
    let mut a = jtj.to_vec();
    for j in 0..p {
        let d = jtj[j * p + j].max(1e-30);
        a[j * p + j] = jtj[j * p + j] + lambda * d;
    }
    let rhs: Vec<f64> = g.iter().map(|v| -v).collect();
    cholesky_solve(&a, &rhs, p)
}

/// The decrease of the cost the damped Gauss–Newton model predicts for the step δ:
/// Σ δ_j (λ D_j δ_j − g_j).
pub(crate) fn predicted_decrease(delta: &[f64], jtj: &[f64], g: &[f64], lambda: f64) -> f64 {
    let p = delta.len();
    let mut predicted = 0.0;
    for j in 0..p {
        predicted += delta[j] * (lambda * jtj[j * p + j].max(1e-30) * delta[j] - g[j]);
    }
    predicted
}

/// Bates and Watts' relative offset √(gᵀ(JᵀJ)⁻¹g / p) / √(cost / (n − p)), g = Jᵀr; infinite
/// when it cannot be evaluated (n ≤ p, a singular JᵀJ), so the test never stops the method then.
pub(crate) fn relative_offset(jtj: &[f64], g: &[f64], cost: f64, n: usize, p: usize) -> f64 {
    if n <= p || cost <= 0.0 {
        return f64::INFINITY;
    }
    // (JᵀJ)⁻¹ in Marquardt's scaling (unit diagonal), for its conditioning; a column of zeros
    // (a parameter the residuals ignore) keeps a unit diagonal and contributes nothing.
    let d: Vec<f64> = (0..p)
        .map(|j| {
            let v = jtj[j * p + j];
            if v > 0.0 {
                v.sqrt()
            } else {
                1.0
            }
        })
        .collect();
    let mut a = vec![0.0; p * p];
    for i in 0..p {
        for j in 0..p {
            a[i * p + j] = jtj[i * p + j] / (d[i] * d[j]);
        }
        a[i * p + i] = a[i * p + i].max(1.0);
    }
    let b: Vec<f64> = g.iter().zip(&d).map(|(v, s)| v / s).collect();
    let Some(x) = cholesky_solve(&a, &b, p) else {
        return f64::INFINITY;
    };
    let projected: f64 = x.iter().zip(&b).map(|(u, v)| u * v).sum();
    let value = (projected.max(0.0) / p as f64).sqrt() / (cost / (n - p) as f64).sqrt();
    if value.is_finite() {
        value
    } else {
        f64::INFINITY
    }
}

/// The cost decrease the relative-offset test counts as negligible: ‖r‖² p/(n − p) · `offset`²
/// (a relative offset of `offset`); 0 when the test is off (`offset` = 0) or cannot be
/// evaluated (n ≤ p).
pub(crate) fn negligible_gain(cost: f64, n: usize, p: usize, offset: f64) -> f64 {
    if n <= p {
        return 0.0;
    }
    cost * p as f64 / (n - p) as f64 * offset * offset
}

/// Whether the decreases `d` = [d₁, d₂, d₃] of the last three accepted steps (oldest first)
/// fade so fast that the steps to come gain at most `negligible` in all: each dᵢ > 0, the
/// slower ratio q = max(d₂/d₁, d₃/d₂) < 1, and d₃ q / (1 − q) ≤ `negligible` (the sum of the
/// geometric series d₃ q + d₃ q² + …). See [`Termination::FadingDecrease`](crate::lm::Termination::FadingDecrease).
pub(crate) fn fading(d: [f64; 3], negligible: f64) -> bool {
    if !(negligible > 0.0 && d.iter().all(|x| *x > 0.0)) {
        return false;
    }
    let q = (d[1] / d[0]).max(d[2] / d[1]);
    q < 1.0 && d[2] * q / (1.0 - q) <= negligible
}
