//! Dense linear algebra for the small symmetric positive definite systems of the fits (normal
//! equations of a few dozen unknowns): Cholesky factorisation, solve and inverse, and
//! non-negative least squares ([`nnls`]). Matrices are row-major `p × p` slices; every function
//! but `nnls` returns `None` when the matrix is not (numerically) positive definite.

/// Cholesky factor L (row-major, lower) of a symmetric positive definite p × p matrix `a`
/// (`None` also when `a` does not hold p × p numbers).
fn cholesky(a: &[f64], p: usize) -> Option<Vec<f64>> {
    if a.len() != p * p {
        return None;
    }
    let mut l = vec![0.0; p * p];
    for i in 0..p {
        for j in 0..=i {
            let mut s = a[i * p + j];
            for k in 0..j {
                s -= l[i * p + k] * l[j * p + k];
            }
            if i == j {
                if s.is_nan() || s <= 0.0 || !s.is_finite() {
                    return None;
                }
                l[i * p + i] = s.sqrt();
            } else {
                l[i * p + j] = s / l[j * p + j];
            }
        }
    }
    Some(l)
}

/// Solves A x = b for a symmetric positive definite p × p matrix A and b of length p.
pub(crate) fn cholesky_solve(a: &[f64], b: &[f64], p: usize) -> Option<Vec<f64>> {
    if b.len() != p {
        return None;
    }
    let l = cholesky(a, p)?;
    let mut y = b.to_vec();
    for i in 0..p {
        for k in 0..i {
            y[i] -= l[i * p + k] * y[k];
        }
        y[i] /= l[i * p + i];
    }
    for i in (0..p).rev() {
        for k in i + 1..p {
            y[i] -= l[k * p + i] * y[k];
        }
        y[i] /= l[i * p + i];
    }
    Some(y)
}

/// The inverse of a symmetric positive definite p × p matrix (row-major), `None` when singular.
pub(crate) fn spd_inverse(a: &[f64], p: usize) -> Option<Vec<f64>> {
    if a.len() != p * p {
        return None;
    }
    // Equilibrate so that the check does not depend on the units of the parameters.
    let d: Vec<f64> = (0..p).map(|i| a[i * p + i].max(1e-300).sqrt()).collect();
    let mut s = vec![0.0; p * p];
    for i in 0..p {
        for j in 0..p {
            s[i * p + j] = a[i * p + j] / (d[i] * d[j]);
        }
    }
    let mut inv = vec![0.0; p * p];
    for j in 0..p {
        let mut e = vec![0.0; p];
        e[j] = 1.0;
        let col = cholesky_solve(&s, &e, p)?;
        for i in 0..p {
            inv[i * p + j] = col[i] / (d[i] * d[j]);
        }
    }
    Some(inv)
}

/// Lawson–Hanson non-negative least squares on the normal equations: minimises
/// ½ wᵀ G w − bᵀ w subject to w ≥ 0.
pub(crate) fn nnls(g: &[f64], b: &[f64], m: usize) -> Vec<f64> {
    let mut w = vec![0.0; m];
    let mut passive = vec![false; m];
    let scale = (0..m).map(|i| g[i * m + i]).fold(0.0_f64, f64::max);
    let tol =
        1e-12 * scale.max(f64::MIN_POSITIVE) * b.iter().fold(1e-300_f64, |a, v| a.max(v.abs()));
    for _outer in 0..(3 * m + 10) {
        let grad: Vec<f64> = (0..m)
            .map(|i| b[i] - (0..m).map(|j| g[i * m + j] * w[j]).sum::<f64>())
            .collect();
        let candidate = (0..m)
            .filter(|&i| !passive[i])
            .max_by(|&a, &c| grad[a].total_cmp(&grad[c]));
        let Some(t) = candidate else { break };
        if grad[t] <= tol {
            break;
        }
        passive[t] = true;
        for _inner in 0..(3 * m + 10) {
            let idx: Vec<usize> = (0..m).filter(|&i| passive[i]).collect();
            let k = idx.len();
            let mut sub = vec![0.0; k * k];
            for (a, &i) in idx.iter().enumerate() {
                for (c, &j) in idx.iter().enumerate() {
                    sub[a * k + c] = g[i * m + j];
                }
                sub[a * k + a] += 1e-13 * scale;
            }
            let rhs: Vec<f64> = idx.iter().map(|&i| b[i]).collect();
            let Some(s) = cholesky_solve(&sub, &rhs, k) else {
                passive[t] = false;
                break;
            };
            if s.iter().all(|v| *v > 0.0) {
                for (a, &i) in idx.iter().enumerate() {
                    w[i] = s[a];
                }
                break;
            }
            let mut alpha = 1.0_f64;
            for (a, &i) in idx.iter().enumerate() {
                if s[a] <= 0.0 {
                    let d = w[i] - s[a];
                    if d > 0.0 {
                        alpha = alpha.min(w[i] / d);
                    }
                }
            }
            for (a, &i) in idx.iter().enumerate() {
                w[i] += alpha * (s[a] - w[i]);
                if w[i] <= 1e-15 * (1.0 + s[a].abs()) {
                    w[i] = 0.0;
                    passive[i] = false;
                }
            }
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_of_spd() {
        let a = [4.0, 1.0, 1.0, 3.0];
        let inv = spd_inverse(&a, 2).unwrap_or_default();
        let det = 11.0;
        assert!((inv[0] - 3.0 / det).abs() < 1e-15);
        assert!((inv[1] + 1.0 / det).abs() < 1e-15);
        assert!(spd_inverse(&[1.0, 1.0, 1.0, 1.0], 2).is_none());
    }

    #[test]
    fn cholesky_solve_solves() {
        // A = [[4, 2, 0], [2, 5, 1], [0, 1, 3]], x = (1, −2, 0.5): b = A x.
        let a = [4.0, 2.0, 0.0, 2.0, 5.0, 1.0, 0.0, 1.0, 3.0];
        let b = [0.0, -7.5, -0.5];
        let x = cholesky_solve(&a, &b, 3).unwrap_or_default();
        for (got, want) in x.iter().zip([1.0, -2.0, 0.5]) {
            assert!((got - want).abs() < 1e-14, "{x:?}");
        }
        // Indefinite and mis-sized input are refused rather than answered.
        assert!(cholesky_solve(&[1.0, 2.0, 2.0, 1.0], &[1.0, 1.0], 2).is_none());
        assert!(cholesky_solve(&a, &b[..2], 3).is_none());
        assert!(cholesky_solve(&a[..8], &b, 3).is_none());
        assert!(spd_inverse(&a[..8], 3).is_none());
    }

    #[test]
    fn nnls_matches_a_small_case() {
        // min |A w − y|² with A = I, y = (1, −2): w = (1, 0)
        let g = [1.0, 0.0, 0.0, 1.0];
        let w = nnls(&g, &[1.0, -2.0], 2);
        assert!((w[0] - 1.0).abs() < 1e-12 && w[1] == 0.0, "{w:?}");
    }
}
