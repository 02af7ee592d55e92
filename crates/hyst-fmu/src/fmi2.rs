//! The FMI 2.0 C types, written out from the standard headers `fmi2TypesPlatform.h` and
//! `fmi2FunctionTypes.h` (FMI 2.0.x). No FMI crate is used: the few types an FMU needs are
//! defined here, one to one with the headers, so the exported functions have exactly the C
//! signatures a master calls.
//!
//! C enums that a master *passes in* (`fmi2Type`, `fmi2StatusKind`) are declared as the C `int`
//! they are, with their values as constants, so an out-of-range value from C is an ordinary
//! integer the FMU refuses, never an invalid Rust enum. `fmi2Status`, which the FMU only returns
//! and writes, is a `#[repr(C)]` enum (the size of a C enum, an `int`, on every FMI platform).

use std::ffi::{c_char, c_int, c_uint, c_void};

/// `typedef void* fmi2Component;` — the instance handle fmi2Instantiate returns.
pub type fmi2Component = *mut c_void;
/// `typedef void* fmi2ComponentEnvironment;` — the master's pointer, handed back to the logger.
pub type fmi2ComponentEnvironment = *mut c_void;
/// `typedef void* fmi2FMUstate;` — a saved FMU state (fmi2GetFMUstate).
pub type fmi2FMUstate = *mut c_void;
/// `typedef unsigned int fmi2ValueReference;`
pub type fmi2ValueReference = c_uint;
/// `typedef double fmi2Real;`
pub type fmi2Real = f64;
/// `typedef int fmi2Integer;`
pub type fmi2Integer = c_int;
/// `typedef int fmi2Boolean;` (`fmi2True` = 1, `fmi2False` = 0)
pub type fmi2Boolean = c_int;
/// `typedef char fmi2Char;`
pub type fmi2Char = c_char;
/// `typedef const fmi2Char* fmi2String;`
pub type fmi2String = *const fmi2Char;
/// `typedef char fmi2Byte;`
pub type fmi2Byte = c_char;

/// `#define fmi2True 1`
pub const fmi2True: fmi2Boolean = 1;
/// `#define fmi2False 0`
pub const fmi2False: fmi2Boolean = 0;

/// `fmi2Status`: the result of every function.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum fmi2Status {
    /// All well.
    fmi2OK = 0,
    /// Things are not quite right, but the computation can continue.
    fmi2Warning = 1,
    /// The call was not carried out (only for the functions the standard allows it).
    fmi2Discard = 2,
    /// The call failed; the instance is unchanged by it (this FMU's promise).
    fmi2Error = 3,
    /// The instance is corrupted; only fmi2FreeInstance may follow.
    fmi2Fatal = 4,
    /// An asynchronous step is in progress (never returned by this FMU).
    fmi2Pending = 5,
}

/// `fmi2Type` (an `int` here, see the module docs).
pub type fmi2Type = c_int;
/// `fmi2ModelExchange`
pub const fmi2ModelExchange: fmi2Type = 0;
/// `fmi2CoSimulation`
pub const fmi2CoSimulation: fmi2Type = 1;

/// `fmi2StatusKind` (an `int` here, see the module docs).
pub type fmi2StatusKind = c_int;
/// `fmi2DoStepStatus`
pub const fmi2DoStepStatus: fmi2StatusKind = 0;
/// `fmi2PendingStatus`
pub const fmi2PendingStatus: fmi2StatusKind = 1;
/// `fmi2LastSuccessfulTime`
pub const fmi2LastSuccessfulTime: fmi2StatusKind = 2;
/// `fmi2Terminated`
pub const fmi2Terminated: fmi2StatusKind = 3;

/// `typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment, fmi2String instanceName,
/// fmi2Status, fmi2String category, fmi2String message, ...);` — `message` is a printf format;
/// this FMU always passes `"%s"` and the text as its one argument.
pub type fmi2CallbackLogger = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    ...
);
/// `typedef void* (*fmi2CallbackAllocateMemory)(size_t, size_t);` (not used:
/// canNotUseMemoryManagementFunctions = true)
pub type fmi2CallbackAllocateMemory = unsafe extern "C" fn(usize, usize) -> *mut c_void;
/// `typedef void (*fmi2CallbackFreeMemory)(void*);` (not used)
pub type fmi2CallbackFreeMemory = unsafe extern "C" fn(*mut c_void);
/// `typedef void (*fmi2StepFinished)(fmi2ComponentEnvironment, fmi2Status);` (not used: no
/// asynchronous steps)
pub type fmi2StepFinished = unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status);

/// `fmi2CallbackFunctions`: the master's callbacks, given to fmi2Instantiate. Function pointers
/// are `Option`s (the same layout as a nullable C function pointer), so a NULL entry is seen.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct fmi2CallbackFunctions {
    /// `const fmi2CallbackLogger logger;`
    pub logger: Option<fmi2CallbackLogger>,
    /// `const fmi2CallbackAllocateMemory allocateMemory;`
    pub allocateMemory: Option<fmi2CallbackAllocateMemory>,
    /// `const fmi2CallbackFreeMemory freeMemory;`
    pub freeMemory: Option<fmi2CallbackFreeMemory>,
    /// `const fmi2StepFinished stepFinished;`
    pub stepFinished: Option<fmi2StepFinished>,
    /// `const fmi2ComponentEnvironment componentEnvironment;`
    pub componentEnvironment: fmi2ComponentEnvironment,
}

/// `#define fmi2TypesPlatform "default"`
pub const fmi2TypesPlatform: &std::ffi::CStr = c"default";
/// `#define fmi2Version "2.0"`
pub const fmi2Version: &std::ffi::CStr = c"2.0";
