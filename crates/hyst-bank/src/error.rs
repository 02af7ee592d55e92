//! A bank's error: the channel that failed and the core's [`Error`] for it.

use hyst_core::error::Error;

/// A channel's error: which channel, and the core's error for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BankError {
    /// The channel (from 0).
    pub channel: usize,
    /// What is wrong.
    pub error: Error,
}

impl core::fmt::Display for BankError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "channel {}: {}", self.channel, self.error)
    }
}

#[cfg(feature = "std")]
impl std::error::Error for BankError {}
