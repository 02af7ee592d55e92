//! The estimator's covariance P of the relative parameters θ (a 6 × 6 symmetric matrix) and the
//! Kalman filter's arithmetic on it: time update, gain and measurement update, the cap.

use crate::real::Real;

/// P (W × W, by slot), with the rows and columns of the slots beyond the adapted parameters
/// kept at zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Covariance<T, const W: usize> {
    p: [[T; W]; W],
}

impl<T: Real, const W: usize> Covariance<T, W> {
    /// σ² on the diagonal of the first `n` slots, zero elsewhere.
    pub(super) fn diagonal(variance: T, n: usize) -> Self {
        let mut p = [[T::zero(); W]; W];
        for (i, row) in p.iter_mut().enumerate().take(n) {
            if let Some(slot) = row.get_mut(i) {
                *slot = variance;
            }
        }
        Self { p }
    }

    /// P ← P + q I on the first `n` slots.
    pub(super) fn grow(&mut self, q: T, n: usize) {
        for (i, row) in self.p.iter_mut().enumerate().take(n) {
            if let Some(slot) = row.get_mut(i) {
                *slot = *slot + q;
            }
        }
    }

    /// h = P φ.
    pub(super) fn times(&self, phi: &[T; W]) -> [T; W] {
        let mut h = [T::zero(); W];
        for (hi, row) in h.iter_mut().zip(self.p.iter()) {
            *hi = row
                .iter()
                .zip(phi.iter())
                .fold(T::zero(), |s, (a, b)| s + *a * *b);
        }
        h
    }

    /// P ← P − h hᵀ / d, then the diagonal capped at `cap` and kept ≥ 0.
    pub(super) fn update(&mut self, h: &[T; W], d: T, cap: T) {
        let inv = d.recip();
        let mut over = false;
        for (i, (row, hi)) in self.p.iter_mut().zip(h.iter()).enumerate() {
            // A parameter that does not adapt has h_i = 0 and a zero row: nothing to do.
            if *hi == T::zero() {
                continue;
            }
            let f = *hi * inv;
            for (pij, hj) in row.iter_mut().zip(h.iter()) {
                *pij = *pij - f * *hj;
            }
            let pii = row.get(i).copied().unwrap_or_else(T::zero);
            over |= !(pii > T::zero() && pii <= cap);
        }
        if over {
            self.cap(cap);
        }
    }

    /// Each diagonal entry above `cap` brought down to it by scaling its row and column (a
    /// congruence D P D with D diagonal: P stays positive semidefinite); a negative diagonal
    /// entry (rounding) set to zero with its row and column.
    fn cap(&mut self, cap: T) {
        for i in 0..W {
            let pii = self.p.get(i).and_then(|r| r.get(i)).copied();
            let Some(pii) = pii else { continue };
            let scale = if pii <= T::zero() || !pii.is_finite() {
                T::zero()
            } else if pii > cap {
                (cap / pii).sqrt()
            } else {
                continue;
            };
            for (j, row) in self.p.iter_mut().enumerate() {
                if let Some(x) = row.get_mut(i) {
                    *x = *x * scale;
                }
                if j == i {
                    for x in row.iter_mut() {
                        *x = *x * scale;
                    }
                    if scale > T::zero() {
                        if let Some(x) = row.get_mut(i) {
                            *x = cap;
                        }
                    }
                }
            }
        }
    }

    /// σ of parameter `i` (relative units): √P_ii.
    pub(super) fn sigma(&self, i: usize) -> T {
        self.p
            .get(i)
            .and_then(|r| r.get(i))
            .map_or(T::zero(), |x| x.max(T::zero()).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cap_keeps_p_symmetric_and_bounded() {
        const N: usize = 6;
        let mut p = Covariance::<f64, N>::diagonal(0.01_f64, N);
        let phi = [1.0, 0.5, -0.2, 0.3, 0.0, 0.1];
        for _ in 0..50 {
            p.grow(0.02, N);
            let h = p.times(&phi);
            let d = 1e-4 + phi.iter().zip(h.iter()).map(|(a, b)| a * b).sum::<f64>();
            p.update(&h, d, 0.01);
        }
        for i in 0..N {
            assert!(p.p[i][i] <= 0.01 + 1e-15 && p.p[i][i] >= 0.0);
            for j in 0..N {
                assert!((p.p[i][j] - p.p[j][i]).abs() < 1e-15);
                assert!(p.p[i][j].abs() <= 0.01 + 1e-15);
            }
        }
    }
}
