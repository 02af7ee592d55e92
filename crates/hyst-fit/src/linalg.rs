//! Dense linear algebra for the small symmetric positive definite systems of the fits (normal
//! equations of a few dozen unknowns): Cholesky factorisation, solve and inverse. Matrices are
//! row-major `p × p` slices; every function returns `None` when the matrix is not (numerically)
//! positive definite.

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
}
