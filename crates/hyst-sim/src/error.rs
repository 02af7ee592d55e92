//! [`SimError`]: everything that can go wrong in a simulation, each message naming the
//! parameter and the value.

use hyst_core::Error;

/// Everything that can go wrong in a simulation. Each message names the parameter and the value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// A transfer function with no denominator coefficients.
    #[error(
        "transfer function denominator is empty: give [a_n, …, a_1, a_0], highest power first"
    )]
    EmptyDenominator,
    /// The highest-power coefficient of the denominator is zero.
    #[error(
        "transfer function denominator: leading coefficient a_n = {a_n} (the coefficient of the \
         highest power of s must be non-zero; drop leading zeros)"
    )]
    LeadingCoefficientZero {
        /// The leading coefficient given.
        a_n: f64,
    },
    /// The numerator has a higher degree than the denominator.
    #[error(
        "transfer function is improper: numerator degree {num_degree} > denominator degree \
         {den_degree} (needs deg num ≤ deg den)"
    )]
    Improper {
        /// Degree of the numerator (its length − 1).
        num_degree: usize,
        /// Degree of the denominator (its length − 1).
        den_degree: usize,
    },
    /// A coefficient, state entry or sample is NaN or infinite.
    #[error("{name}[{index}] = {value} is not finite")]
    NonFinite {
        /// Which array, e.g. "transfer function numerator", "state-space A".
        name: &'static str,
        /// The position in it (row-major for matrices).
        index: usize,
        /// The value given.
        value: f64,
    },
    /// The state matrix A is not n × n.
    #[error("state-space A is {rows}×{cols}, must be square")]
    NotSquare {
        /// Number of rows of A.
        rows: usize,
        /// Length of the first row whose length differs from the number of rows.
        cols: usize,
    },
    /// A vector has the wrong length for the state dimension n.
    #[error("{name} has {len} entries, the state dimension is n = {order}")]
    DimensionMismatch {
        /// Which vector: "state-space B", "state-space C", "x0", "right-hand side f(t, x)".
        name: &'static str,
        /// Its length.
        len: usize,
        /// The state dimension n.
        order: usize,
    },
    /// A scalar parameter outside its valid range.
    #[error("invalid parameter {name} = {value}: must be {expected}")]
    InvalidParameter {
        /// The parameter's name, e.g. "dt", "tol", "backlash width".
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// The adaptive integrator's right-hand side returned NaN or infinity.
    #[error("non-finite right-hand side f(t, x) at t = {t}")]
    NonFiniteDerivative {
        /// The time of the failing evaluation.
        t: f64,
    },
    /// The adaptive integrator needed a step below 1e-14 of the span (a stiff or singular
    /// right-hand side).
    #[error("step size underflow at t = {t} (step {h})")]
    StepSizeUnderflow {
        /// The time reached.
        t: f64,
        /// The step size that was too small.
        h: f64,
    },
    /// An error of the hysteresis core (a model parameter, a reference outside a shaping
    /// function's range, …), passed through unchanged.
    #[error(transparent)]
    Core(#[from] Error),
}

/// `Ok` when every entry of `values` is finite, else [`SimError::NonFinite`] naming the array
/// `name` and the first bad entry.
pub(crate) fn check_finite(name: &'static str, values: &[f64]) -> Result<(), SimError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(SimError::NonFinite {
            name,
            index,
            value: values.get(index).copied().unwrap_or(f64::NAN),
        }),
        None => Ok(()),
    }
}

/// `Ok` when `value` is finite, else [`SimError::InvalidParameter`] naming the parameter.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<(), SimError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(SimError::InvalidParameter {
            name,
            value,
            expected: "finite",
        })
    }
}

/// `Ok` when `value` is finite and > 0, else [`SimError::InvalidParameter`] naming the
/// parameter.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<(), SimError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SimError::InvalidParameter {
            name,
            value,
            expected: "finite and > 0",
        })
    }
}
