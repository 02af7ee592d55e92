//! The columns of one `hyst run`, and numbers in its messages.

/// One input column of a run.
pub(super) struct Input {
    /// Its index in INPUT.
    pub(super) index: usize,
    /// Its name.
    pub(super) name: String,
    /// The derivative columns `<name>_d1 …`.
    pub(super) derivatives: Vec<usize>,
}

/// The columns of one run.
pub(super) struct Columns {
    /// The input columns, one operator each.
    pub(super) inputs: Vec<Input>,
    /// The record column.
    pub(super) record: Option<usize>,
    /// Every column of INPUT (passed through to OUTPUT).
    pub(super) width: usize,
    /// Whether OUTPUT has the desired outputs after `--saturate` (`<column>_saturated`).
    pub(super) saturated: bool,
}

/// A number in a message: shortest round trip, in exponent form outside [1e-5, 1e16).
pub(super) struct Num(pub(super) f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) || !a.is_finite() {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}
