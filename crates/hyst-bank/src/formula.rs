//! The formula a bank runs on every channel: the direct operator (eq. 2) or the inverse
//! (eq. 4), told apart at compile time.

use hyst_core::parametric::{Direct, Formula, Inverse};

/// The formula of a bank: eq. (2) or eq. (4). Implemented by [`Direct`] and [`Inverse`].
pub trait BankFormula: Formula {
    /// Whether this is the direct formula (eq. 2).
    #[doc(hidden)]
    const DIRECT: bool;
}

impl BankFormula for Direct {
    const DIRECT: bool = true;
}

impl BankFormula for Inverse {
    const DIRECT: bool = false;
}
