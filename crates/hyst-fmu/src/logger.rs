//! Messages to the master through its `fmi2CallbackLogger`.
//!
//! Errors and warnings are always logged (category `logStatusError`, `logStatusFatal` or
//! `logStatusWarning`); debug messages
//! (category `logAll`) only while debug logging is on (fmi2Instantiate's `loggingOn`,
//! fmi2SetDebugLogging). The text is always passed as the argument of a `"%s"` format, never as
//! the format itself, and `#` is written `##` (FMI 2.0 reserves `#` for variable references in
//! log messages).

use std::ffi::{CStr, CString};

use crate::fmi2::{fmi2CallbackLogger, fmi2ComponentEnvironment, fmi2Status};

/// The category of error messages.
pub const CATEGORY_ERROR: &CStr = c"logStatusError";
/// The category of warnings.
pub const CATEGORY_WARNING: &CStr = c"logStatusWarning";
/// The category of the message that reports a fatal error.
pub const CATEGORY_FATAL: &CStr = c"logStatusFatal";
/// The category of debug messages.
pub const CATEGORY_DEBUG: &CStr = c"logAll";

/// The master's logger, its environment pointer and the instance name (copied at
/// fmi2Instantiate).
#[derive(Debug)]
pub struct Logger {
    callback: Option<fmi2CallbackLogger>,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
    /// Whether debug messages are sent.
    pub debug: bool,
}

impl Logger {
    /// A logger calling `callback` (none: messages are dropped) with `environment` and
    /// `instance_name`.
    #[must_use]
    pub fn new(
        callback: Option<fmi2CallbackLogger>,
        environment: fmi2ComponentEnvironment,
        instance_name: CString,
        debug: bool,
    ) -> Self {
        Self {
            callback,
            environment,
            instance_name,
            debug,
        }
    }

    /// The instance name given to fmi2Instantiate.
    #[must_use]
    pub fn instance_name(&self) -> &CStr {
        &self.instance_name
    }

    /// Sends an error message (always).
    pub fn error(&self, message: &str) {
        self.send(fmi2Status::fmi2Error, CATEGORY_ERROR, message);
    }

    /// Sends a warning (always).
    pub fn warning(&self, message: &str) {
        self.send(fmi2Status::fmi2Warning, CATEGORY_WARNING, message);
    }

    /// Sends a debug message when debug logging is on.
    pub fn debug(&self, message: &str) {
        if self.debug {
            self.send(fmi2Status::fmi2OK, CATEGORY_DEBUG, message);
        }
    }

    /// Sends `message` with `status` and `category`.
    // Calls the master's C callback: the one unsafe block of this module.
    #[allow(unsafe_code)]
    pub fn send(&self, status: fmi2Status, category: &CStr, message: &str) {
        let Some(callback) = self.callback else {
            return;
        };
        let text = message.replace('\0', " ").replace('#', "##");
        let Ok(text) = CString::new(text) else {
            return;
        };
        // SAFETY: FFI boundary. `callback` is the logger the master gave fmi2Instantiate, which
        // the standard requires to stay callable for the instance's lifetime; every string is a
        // NUL-terminated CString alive for the call, and the text is the argument of a "%s"
        // format (one `char*` vararg), so the master's printf-style formatting reads exactly
        // one string.
        unsafe {
            callback(
                self.environment,
                self.instance_name.as_ptr(),
                status,
                category.as_ptr(),
                c"%s".as_ptr(),
                text.as_ptr(),
            );
        }
    }
}
