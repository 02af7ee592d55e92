//! The linear plant of eq. (18): [`StateSpace`], built from its matrices or from a transfer
//! function (controllable canonical form).

use crate::error::{check_finite, SimError};

/// A linear time-invariant single-input single-output plant ẋ = A x + B u, y = C x + D u
/// (state x ∈ ℝⁿ; u and y in the units of the plant's input and output; time in s, so ẋ is
/// in state units per s and A in 1/s). Eq. (18)'s
/// b / (a_n sⁿ + … + a_1 s + 1) is built with [`StateSpace::from_transfer_function`].
#[derive(Clone, Debug, PartialEq)]
pub struct StateSpace {
    a: Vec<Vec<f64>>,
    b: Vec<f64>,
    c: Vec<f64>,
    d: f64,
}

impl StateSpace {
    /// A plant from its matrices: A (n × n, a vector of rows), B and C (n entries each), D.
    ///
    /// # Errors
    /// [`SimError::NotSquare`] when a row of A does not have n entries,
    /// [`SimError::DimensionMismatch`] when B or C does not have n entries,
    /// [`SimError::NonFinite`] for a NaN or infinite entry.
    pub fn new(a: Vec<Vec<f64>>, b: Vec<f64>, c: Vec<f64>, d: f64) -> Result<Self, SimError> {
        let n = a.len();
        if let Some(row) = a.iter().find(|r| r.len() != n) {
            return Err(SimError::NotSquare {
                rows: n,
                cols: row.len(),
            });
        }
        for (name, v) in [("state-space B", &b), ("state-space C", &c)] {
            if v.len() != n {
                return Err(SimError::DimensionMismatch {
                    name,
                    len: v.len(),
                    order: n,
                });
            }
        }
        let flat: Vec<f64> = a.iter().flatten().copied().collect();
        check_finite("state-space A", &flat)?;
        check_finite("state-space B", &b)?;
        check_finite("state-space C", &c)?;
        check_finite("state-space D", &[d])?;
        Ok(Self { a, b, c, d })
    }

    /// The controllable canonical form of num(s) / den(s), coefficients from the highest power
    /// down: eq. (18)'s b / (a_n sⁿ + … + a_1 s + 1) is `num = [b]`, `den = [a_n, …, a_1, 1]`
    /// (e.g. Example 3's 1 / (s² + 0.9 s + 1) is `[1.0]` over `[1.0, 0.9, 1.0]`). Needs
    /// deg num ≤ deg den; a proper (not strictly proper) function gets a feed-through D.
    ///
    /// # Errors
    /// [`SimError::EmptyDenominator`], [`SimError::LeadingCoefficientZero`] (a_n = 0),
    /// [`SimError::Improper`] (deg num > deg den), [`SimError::NonFinite`] for a NaN or
    /// infinite coefficient.
    pub fn from_transfer_function(num: &[f64], den: &[f64]) -> Result<Self, SimError> {
        check_finite("transfer function numerator", num)?;
        check_finite("transfer function denominator", den)?;
        let Some(&lead) = den.first() else {
            return Err(SimError::EmptyDenominator);
        };
        if lead == 0.0 {
            return Err(SimError::LeadingCoefficientZero { a_n: lead });
        }
        let n = den.len() - 1;
        if num.len() > den.len() {
            return Err(SimError::Improper {
                num_degree: num.len().saturating_sub(1),
                den_degree: n,
            });
        }
        let den: Vec<f64> = den.iter().map(|x| x / lead).collect();
        let mut nump = vec![0.0; den.len() - num.len()];
        nump.extend(num.iter().map(|x| x / lead));
        // Strictly proper part: num = d den + r.
        let d = nump.first().copied().unwrap_or(0.0);
        let r: Vec<f64> = nump.iter().zip(&den).map(|(p, q)| p - d * q).collect();
        // x = [z, ż, …, z^(n−1)], z^(n) = u − Σ den[n−i] z^(i); y = Σ r[n−i] z^(i) + d u.
        let a: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                if i + 1 < n {
                    (0..n).map(|j| if j == i + 1 { 1.0 } else { 0.0 }).collect()
                } else {
                    den.iter().skip(1).rev().map(|x| -x).collect()
                }
            })
            .collect();
        let b: Vec<f64> = (0..n).map(|i| if i + 1 == n { 1.0 } else { 0.0 }).collect();
        let c: Vec<f64> = r.iter().skip(1).rev().copied().collect();
        Self::new(a, b, c, d)
    }

    /// The state matrix A (n × n, rows).
    #[must_use]
    pub fn a(&self) -> &[Vec<f64>] {
        &self.a
    }

    /// The input vector B (n entries).
    #[must_use]
    pub fn b(&self) -> &[f64] {
        &self.b
    }

    /// The output vector C (n entries).
    #[must_use]
    pub fn c(&self) -> &[f64] {
        &self.c
    }

    /// The feed-through D (0 for a strictly proper plant such as eq. 18).
    #[must_use]
    pub fn d(&self) -> f64 {
        self.d
    }

    /// The state dimension n (the order of eq. 18's denominator).
    #[must_use]
    pub fn order(&self) -> usize {
        self.b.len()
    }

    /// ẋ = A x + B u (state units per s) for the state `x` (n entries; missing entries count
    /// as 0, extra ones are ignored) and the input `u`.
    #[must_use]
    pub fn derivative(&self, x: &[f64], u: f64) -> Vec<f64> {
        self.a
            .iter()
            .zip(&self.b)
            .map(|(row, b)| row.iter().zip(x).map(|(a, x)| a * x).sum::<f64>() + b * u)
            .collect()
    }

    /// y = C x + D u, in the plant's output units (as [`StateSpace::derivative`] for the
    /// length of `x`).
    #[must_use]
    pub fn output(&self, x: &[f64], u: f64) -> f64 {
        self.c.iter().zip(x).map(|(c, x)| c * x).sum::<f64>() + self.d * u
    }

    /// The steady state x (n entries) for a constant input u: the solution of A x = −B u (Gaussian elimination
    /// with partial pivoting), `None` when A is singular (a pure integrator, say).
    #[must_use]
    pub fn equilibrium(&self, u: f64) -> Option<Vec<f64>> {
        let n = self.order();
        let mut m: Vec<Vec<f64>> = self
            .a
            .iter()
            .zip(&self.b)
            .map(|(row, b)| {
                let mut r = row.clone();
                r.push(-b * u);
                r
            })
            .collect();
        for col in 0..n {
            let magnitude = |r: &Vec<f64>| r.get(col).map_or(0.0, |x| x.abs());
            let pivot = (col..n).max_by(|&i, &j| {
                let (a, b) = (
                    m.get(i).map_or(0.0, magnitude),
                    m.get(j).map_or(0.0, magnitude),
                );
                a.total_cmp(&b)
            })?;
            m.swap(col, pivot);
            let pivot_row = m.get(col)?.clone();
            let p = *pivot_row.get(col)?;
            if p.abs() < 1e-300 {
                return None;
            }
            for (r, row) in m.iter_mut().enumerate() {
                if r != col {
                    let f = row.get(col).copied().unwrap_or(0.0) / p;
                    for (x, q) in row.iter_mut().zip(&pivot_row).skip(col) {
                        *x -= f * q;
                    }
                }
            }
        }
        m.iter()
            .enumerate()
            .map(|(i, row)| Some(row.get(n)? / row.get(i)?))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transfer_function_realisation() -> Result<(), SimError> {
        // 1 / (s² + 0.9 s + 1): A = [[0, 1], [−1, −0.9]], C = [1, 0].
        let p = StateSpace::from_transfer_function(&[1.0], &[1.0, 0.9, 1.0])?;
        assert_eq!(p.a(), &[vec![0.0, 1.0], vec![-1.0, -0.9]][..]);
        assert_eq!(p.c(), &[1.0, 0.0][..]);
        let eq = p.equilibrium(2.0).unwrap_or_default();
        assert!((p.output(&eq, 2.0) - 2.0).abs() < 1e-12);
        // (s + 3) / (s + 1): D = 1, and the DC gain is 3.
        let q = StateSpace::from_transfer_function(&[1.0, 3.0], &[1.0, 1.0])?;
        let e = q.equilibrium(1.0).unwrap_or_default();
        assert!((q.output(&e, 1.0) - 3.0).abs() < 1e-12);
        // A pure integrator 1 / s has no equilibrium.
        let i = StateSpace::from_transfer_function(&[1.0], &[1.0, 0.0])?;
        assert_eq!(i.equilibrium(1.0), None);
        Ok(())
    }

    #[test]
    fn bad_plants_are_refused_with_the_parameter_and_value() {
        let msg = |r: Result<StateSpace, SimError>| r.err().map(|e| e.to_string());
        let m = msg(StateSpace::from_transfer_function(&[1.0], &[0.0, 1.0, 1.0]));
        assert!(
            m.as_deref()
                .is_some_and(|m| m.contains("leading coefficient a_n = 0")),
            "{m:?}"
        );
        let m = msg(StateSpace::from_transfer_function(&[1.0], &[]));
        assert!(m.is_some_and(|m| m.contains("empty")));
        let m = msg(StateSpace::from_transfer_function(
            &[1.0, 0.0, 0.0],
            &[1.0, 1.0],
        ));
        assert!(m.is_some_and(|m| m.contains("numerator degree 2 > denominator degree 1")));
        let m = msg(StateSpace::from_transfer_function(&[1.0], &[1.0, f64::NAN]));
        assert!(
            m.as_deref()
                .is_some_and(|m| m.contains("denominator[1] = NaN is not finite")),
            "{m:?}"
        );
        let m = msg(StateSpace::new(
            vec![vec![0.0, 1.0], vec![0.0, 1.0], vec![1.0, 0.0]],
            vec![0.0; 3],
            vec![0.0; 3],
            0.0,
        ));
        assert_eq!(m.as_deref(), Some("state-space A is 3×2, must be square"));
        let m = msg(StateSpace::new(
            vec![vec![1.0]],
            vec![1.0, 2.0],
            vec![1.0],
            0.0,
        ));
        assert_eq!(
            m.as_deref(),
            Some("state-space B has 2 entries, the state dimension is n = 1")
        );
        let m = msg(StateSpace::new(
            vec![vec![f64::INFINITY]],
            vec![1.0],
            vec![1.0],
            0.0,
        ));
        assert_eq!(m.as_deref(), Some("state-space A[0] = inf is not finite"));
    }
}
