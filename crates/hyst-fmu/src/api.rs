//! The exported FMI 2.0 Co-Simulation functions (every one, under its plain C name).
//!
//! Each function body runs inside `catch_unwind` (a caught panic gives `fmi2Fatal`, or NULL from
//! fmi2Instantiate, and the instance then refuses every call but fmi2FreeInstance), checks its
//! pointers (NULL, alignment, an instance handle's tag, an FMU state handle against the
//! instance's own list) and the mode of the instance (`fmi2Error` and a logged message for a call
//! in the wrong mode), then calls the safe [`Instance`]. Unsupported functions return `fmi2Error`
//! with a logged message. All `unsafe` of the crate is here and in the logger call.

use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

use crate::config::{resource_dir, Config};
use crate::fmi2::*;
use crate::instance::{Instance, Phase};
use crate::logger::{Logger, CATEGORY_FATAL};

/// "hystFMUi": the tag at the start of a live instance (cleared when it is freed).
const INSTANCE_TAG: u64 = u64::from_le_bytes(*b"hystFMUi");

/// What an `fmi2Component` points to.
#[repr(C)]
struct Slot {
    tag: u64,
    instance: Instance,
}

use Phase::{InitializationMode, Instantiated, StepMode, Terminated};

/// Every mode but Fatal.
const LIVE: &[Phase] = &[Instantiated, InitializationMode, StepMode, Terminated];
/// Where values may be read (not Instantiated: y is "calculated").
const GET: &[Phase] = &[InitializationMode, StepMode, Terminated];
/// Where values may be set (which ones: see `Instance::set_real`).
const SET: &[Phase] = &[Instantiated, InitializationMode, StepMode];
/// Where the status functions answer.
const STATUS: &[Phase] = &[StepMode, Terminated];

/// The live instance `c` points to, or `None` for NULL, a misaligned pointer or a wrong tag.
///
/// # Safety
/// `c` is NULL or a pointer returned by [`fmi2Instantiate`] (the tag check is a safety net for a
/// freed or foreign pointer, not a guarantee), not used by another thread during the call.
unsafe fn slot<'a>(c: fmi2Component) -> Option<&'a mut Slot> {
    let p = c.cast::<Slot>();
    if p.is_null() || !p.is_aligned() {
        return None;
    }
    // SAFETY: non-NULL and aligned, and by the caller's contract an instance from
    // fmi2Instantiate, whose first field (repr(C)) is the u64 tag.
    let tag = unsafe { p.cast::<u64>().read() };
    if tag != INSTANCE_TAG {
        return None;
    }
    // SAFETY: a live Slot (tag set by fmi2Instantiate, cleared by fmi2FreeInstance), used by
    // one thread at a time (FMI 2.0 forbids concurrent calls on one instance).
    Some(unsafe { &mut *p })
}

/// Runs `body` on the instance `c` if its mode is one of `allowed`: errors are logged with the
/// function's name; a panic makes the instance Fatal.
///
/// # Safety
/// As [`slot`].
unsafe fn with_instance(
    c: fmi2Component,
    function: &str,
    allowed: &[Phase],
    body: impl FnOnce(&mut Instance) -> Result<fmi2Status, String>,
) -> fmi2Status {
    let result = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller's contract.
        let Some(slot) = (unsafe { slot(c) }) else {
            return fmi2Status::fmi2Error;
        };
        let instance = &mut slot.instance;
        if !allowed.contains(&instance.phase) {
            instance.log.error(&format!(
                "{function}: illegal call sequence: not allowed in the mode {}",
                instance.phase
            ));
            return fmi2Status::fmi2Error;
        }
        match body(instance) {
            Ok(status) => status,
            Err(message) => {
                instance.log.error(&format!("{function}: {message}"));
                fmi2Status::fmi2Error
            }
        }
    }));
    result.unwrap_or_else(|_| {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: the caller's contract.
            if let Some(slot) = unsafe { slot(c) } {
                slot.instance.phase = Phase::Fatal;
                slot.instance.log.send(
                    fmi2Status::fmi2Fatal,
                    CATEGORY_FATAL,
                    &format!("{function}: internal error (a panic was caught); only fmi2FreeInstance may follow"),
                );
            }
        }));
        fmi2Status::fmi2Fatal
    })
}

/// `n` elements of the caller's array `ptr` (empty when `n` = 0).
///
/// # Safety
/// When `n` > 0, `ptr` is NULL or valid for reading `n` values of `T` for `'a`.
unsafe fn input<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(format!("{what} is NULL"));
    }
    if !ptr.is_aligned() || n > isize::MAX.unsigned_abs() / std::mem::size_of::<T>().max(1) {
        return Err(format!("{what} is misaligned or {n} is too long"));
    }
    // SAFETY: non-NULL, aligned, n values readable (caller's contract), size within isize.
    Ok(unsafe { std::slice::from_raw_parts(ptr, n) })
}

/// `n` elements of the caller's writable array `ptr` (empty when `n` = 0).
///
/// # Safety
/// When `n` > 0, `ptr` is NULL or valid for writing `n` values of `T` for `'a`, not aliased.
unsafe fn output<'a, T>(ptr: *mut T, n: usize, what: &str) -> Result<&'a mut [T], String> {
    if n == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(format!("{what} is NULL"));
    }
    if !ptr.is_aligned() || n > isize::MAX.unsigned_abs() / std::mem::size_of::<T>().max(1) {
        return Err(format!("{what} is misaligned or {n} is too long"));
    }
    // SAFETY: non-NULL, aligned, n values writable and not aliased (caller's contract).
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
}

/// Writes `value` to the caller's `*ptr`.
///
/// # Safety
/// `ptr` is NULL or valid for writing one `T`.
unsafe fn put<T>(ptr: *mut T, value: T, what: &str) -> Result<(), String> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(format!("{what} is NULL or misaligned"));
    }
    // SAFETY: non-NULL, aligned, writable (caller's contract).
    unsafe { ptr.write(value) };
    Ok(())
}

/// Reads the caller's `*ptr`.
///
/// # Safety
/// `ptr` is NULL or valid for reading one `T`.
unsafe fn get<T: Copy>(ptr: *const T, what: &str) -> Result<T, String> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(format!("{what} is NULL or misaligned"));
    }
    // SAFETY: non-NULL, aligned, readable (caller's contract).
    Ok(unsafe { ptr.read() })
}

/// A C string argument as UTF-8.
///
/// # Safety
/// `s` is NULL or NUL-terminated.
unsafe fn text<'a>(s: fmi2String, what: &str) -> Result<&'a str, String> {
    if s.is_null() {
        return Err(format!("{what} is NULL"));
    }
    // SAFETY: non-NULL and NUL-terminated (caller's contract).
    unsafe { CStr::from_ptr(s) }
        .to_str()
        .map_err(|_| format!("{what} is not UTF-8"))
}

/// `fmi2GetTypesPlatform`: `"default"`.
#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    fmi2TypesPlatform.as_ptr()
}

/// `fmi2GetVersion`: `"2.0"`.
#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    fmi2Version.as_ptr()
}

/// `fmi2Instantiate`: a new Co-Simulation instance configured by `resources/fmu.toml` (and
/// `resources/model.toml`) under `fmuResourceLocation`. Returns NULL, after logging the reason
/// (file, key, value), for a wrong fmuType, GUID, resource location or configuration.
///
/// # Safety
/// Strings are NULL or NUL-terminated; `functions` is NULL or points to an
/// `fmi2CallbackFunctions` whose logger (if any) can be called for the instance's lifetime.
#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: fmi2Type,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    let _ = visible;
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: `functions` is NULL or readable (caller's contract); the struct is copied.
        let callbacks = unsafe { get(functions, "functions") }.ok();
        // SAFETY: NULL or NUL-terminated (caller's contract).
        let name = unsafe { text(instanceName, "instanceName") };
        let log = Logger::new(
            callbacks.and_then(|f| f.logger),
            callbacks.map_or(ptr::null_mut(), |f| f.componentEnvironment),
            CString::new(name.clone().unwrap_or("hyst")).unwrap_or_default(),
            loggingOn != fmi2False,
        );
        // SAFETY: as above, for the other strings.
        let checked = unsafe { instantiate(name, fmuType, fmuGUID, fmuResourceLocation) };
        // Without callbacks there is no logger to say why: NULL.
        let checked = checked.and_then(|config| {
            callbacks
                .map(|_| config)
                .ok_or_else(|| "functions is NULL".to_string())
        });
        match checked {
            Ok(config) => {
                let instance = Instance::new(config, log);
                instance.log.debug("fmi2Instantiate: ready");
                Box::into_raw(Box::new(Slot {
                    tag: INSTANCE_TAG,
                    instance,
                }))
                .cast()
            }
            Err(message) => {
                log.error(&format!("fmi2Instantiate: {message}"));
                ptr::null_mut()
            }
        }
    }))
    .unwrap_or(ptr::null_mut())
}

/// The checks of fmi2Instantiate: the configuration, or why there is none.
///
/// # Safety
/// Strings are NULL or NUL-terminated.
unsafe fn instantiate(
    name: Result<&str, String>,
    fmu_type: fmi2Type,
    guid: fmi2String,
    location: fmi2String,
) -> Result<Config, String> {
    if name?.is_empty() {
        return Err("instanceName is empty".into());
    }
    if fmu_type != fmi2CoSimulation {
        return Err(format!(
            "fmuType = {fmu_type}: this FMU supports only Co-Simulation (fmi2CoSimulation = \
             {fmi2CoSimulation})"
        ));
    }
    // SAFETY: NULL or NUL-terminated (caller's contract).
    let guid = unsafe { text(guid, "fmuGUID") }?;
    // SAFETY: as above.
    let location = unsafe { text(location, "fmuResourceLocation") }?;
    let dir = resource_dir(location)?;
    let config = Config::read(&dir)?;
    if guid != config.guid {
        return Err(format!(
            "fmuGUID \"{guid}\" differs from guid = \"{}\" in {}",
            config.guid,
            dir.join(crate::config::CONFIG_FILE).display()
        ));
    }
    Ok(config)
}

/// `fmi2FreeInstance`: releases the instance and its FMU states (NULL is ignored).
///
/// # Safety
/// `c` is NULL or an instance from [`fmi2Instantiate`], not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller's contract.
        if let Some(slot) = unsafe { slot(c) } {
            slot.tag = 0;
            // SAFETY: from Box::into_raw in fmi2Instantiate; the tag was live, so not freed yet.
            drop(unsafe { Box::from_raw(c.cast::<Slot>()) });
        }
    }));
}

/// `fmi2SetDebugLogging`: debug messages (category `logAll`) on or off; errors are always
/// logged. Categories are accepted and not used to filter.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `categories` is NULL or holds `nCategories` strings.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SetDebugLogging", LIVE, |inst| {
            let list = input(categories, nCategories, "categories")?;
            for (i, category) in list.iter().enumerate() {
                text(*category, &format!("categories[{i}]"))?;
            }
            inst.log.debug = loggingOn != fmi2False;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2SetupExperiment` (Instantiated): the start time; tolerance and stop time are not used.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`].
#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    toleranceDefined: fmi2Boolean,
    tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    let _ = (toleranceDefined, tolerance, stopTimeDefined, stopTime);
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SetupExperiment", &[Instantiated], |inst| {
            inst.setup_experiment(startTime)?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2EnterInitializationMode` (Instantiated → InitializationMode).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`].
#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2EnterInitializationMode", &[Instantiated], |inst| {
            inst.phase = InitializationMode;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2ExitInitializationMode` (InitializationMode → StepMode): builds the operator from k1,
/// k2; invalid values give fmi2Error naming the parameter and value (the mode is unchanged).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`].
#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(
            c,
            "fmi2ExitInitializationMode",
            &[InitializationMode],
            |inst| {
                inst.exit_initialization()?;
                Ok(fmi2Status::fmi2OK)
            },
        )
    }
}

/// `fmi2Terminate` (StepMode → Terminated).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`].
#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2Terminate", &[StepMode], |inst| {
            inst.phase = Terminated;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2Reset`: back to the state after fmi2Instantiate.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`].
#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2Reset", LIVE, |inst| {
            inst.reset();
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2GetReal`: x (0), y (1), k1 (2), k2 (3). y is the output for the committed history
/// followed by the current x.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `vr` and `value` are NULL or hold `nvr` values.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2GetReal", GET, |inst| {
            let vrs = input(vr, nvr, "vr")?;
            let values = output(value, nvr, "value")?;
            inst.get_real(vrs, values)?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// The common part of the Get/Set functions of types this FMU has no variables of.
///
/// # Safety
/// As [`fmi2GetReal`], for `T`.
unsafe fn no_variables<T>(
    c: fmi2Component,
    function: &str,
    allowed: &[Phase],
    type_name: &str,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const T,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, function, allowed, |_| {
            let vrs = input(vr, nvr, "vr")?;
            input(value, nvr, "value")?;
            match vrs.first() {
                None => Ok(fmi2Status::fmi2OK),
                Some(v) => Err(format!(
                    "no {type_name} variable has value reference {v} (this FMU has Real variables only)"
                )),
            }
        })
    }
}

/// `fmi2GetInteger`: this FMU has no Integer variables (nvr = 0 is fine).
///
/// # Safety
/// As [`fmi2GetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        no_variables(
            c,
            "fmi2GetInteger",
            GET,
            "Integer",
            vr,
            nvr,
            value.cast_const(),
        )
    }
}

/// `fmi2GetBoolean`: no Boolean variables.
///
/// # Safety
/// As [`fmi2GetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        no_variables(
            c,
            "fmi2GetBoolean",
            GET,
            "Boolean",
            vr,
            nvr,
            value.cast_const(),
        )
    }
}

/// `fmi2GetString`: no String variables.
///
/// # Safety
/// As [`fmi2GetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        no_variables(
            c,
            "fmi2GetString",
            GET,
            "String",
            vr,
            nvr,
            value.cast_const(),
        )
    }
}

/// `fmi2SetReal`: x (any mode before Terminated), k1 and k2 (before
/// fmi2ExitInitializationMode). All values or none are set.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `vr` and `value` are NULL or hold `nvr` values.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SetReal", SET, |inst| {
            let vrs = input(vr, nvr, "vr")?;
            let values = input(value, nvr, "value")?;
            inst.set_real(vrs, values)?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2SetInteger`: no Integer variables (nvr = 0 is fine).
///
/// # Safety
/// As [`fmi2SetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { no_variables(c, "fmi2SetInteger", SET, "Integer", vr, nvr, value) }
}

/// `fmi2SetBoolean`: no Boolean variables.
///
/// # Safety
/// As [`fmi2SetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { no_variables(c, "fmi2SetBoolean", SET, "Boolean", vr, nvr, value) }
}

/// `fmi2SetString`: no String variables.
///
/// # Safety
/// As [`fmi2SetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { no_variables(c, "fmi2SetString", SET, "String", vr, nvr, value) }
}

/// `fmi2GetFMUstate`: a copy of the instance state (x, k1, k2, time, history) in a new FMU state
/// (`*FMUstate` NULL) or in one of this instance's (`*FMUstate` from an earlier call).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `FMUstate` is NULL or points to an `fmi2FMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2GetFMUstate", LIVE, |inst| {
            let existing = get(FMUstate.cast_const(), "FMUstate")?;
            let handle = inst.store_state(existing, inst.snapshot())?;
            put(FMUstate, handle, "FMUstate")?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2SetFMUstate`: restores a state of this instance (checked again by the core; the mode
/// is kept; a state with a history needs step mode or Terminated).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `FMUstate` is any value (only this instance's states are
/// accepted; it is never dereferenced).
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SetFMUstate", LIVE, |inst| {
            let state = inst.state(FMUstate)?.clone();
            inst.apply(&state)?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2FreeFMUstate`: frees a state of this instance and sets `*FMUstate` to NULL (a NULL
/// `FMUstate` or `*FMUstate` is ignored).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `FMUstate` is NULL or points to an `fmi2FMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2FreeFMUstate", LIVE, |inst| {
            if FMUstate.is_null() {
                return Ok(fmi2Status::fmi2OK);
            }
            let handle = get(FMUstate.cast_const(), "FMUstate")?;
            if handle.is_null() {
                return Ok(fmi2Status::fmi2OK);
            }
            inst.free_state(handle)?;
            put(FMUstate, ptr::null_mut(), "FMUstate")?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2SerializedFMUstateSize`: the byte length of the state's serialised form.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `size` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SerializedFMUstateSize", LIVE, |inst| {
            let bytes = inst.serialize(inst.state(FMUstate)?)?;
            put(size, bytes.len(), "size")?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2SerializeFMUstate`: writes the serialised form (version 1, see `state`) into
/// `serializedState`, which must hold at least fmi2SerializedFMUstateSize bytes.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `serializedState` is NULL or writable for `size` bytes.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SerializeFMUstate", LIVE, |inst| {
            let bytes = inst.serialize(inst.state(FMUstate)?)?;
            if size < bytes.len() {
                return Err(format!(
                    "size = {size}: the serialised state needs {} bytes \
                     (fmi2SerializedFMUstateSize)",
                    bytes.len()
                ));
            }
            let out = output(serializedState.cast::<u8>(), bytes.len(), "serializedState")?;
            out.copy_from_slice(&bytes);
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2DeSerializeFMUstate`: reads a serialised state, checking everything (length, version,
/// checksum, GUID, kind, finite values, the memory through the core), into a new FMU state (or
/// into `*FMUstate` when it is one of this instance's).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `serializedState` is NULL or readable for `size` bytes;
/// `FMUstate` is NULL or points to an `fmi2FMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2DeSerializeFMUstate", LIVE, |inst| {
            let existing = get(FMUstate.cast_const(), "FMUstate")?;
            let bytes = input(serializedState.cast::<u8>(), size, "serializedState")?;
            let state = inst
                .deserialize(bytes)
                .map_err(|e| format!("the serialised state is refused: {e}"))?;
            let existing = if inst.state(existing).is_ok() {
                existing
            } else {
                ptr::null_mut()
            };
            let handle = inst.store_state(existing, state)?;
            put(FMUstate, handle, "FMUstate")?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2GetDirectionalDerivative`: not supported (providesDirectionalDerivative = false).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`] (no other argument is read).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    vUnknown_ref: *const fmi2ValueReference,
    nUnknown: usize,
    vKnown_ref: *const fmi2ValueReference,
    nKnown: usize,
    dvKnown: *const fmi2Real,
    dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    let _ = (
        vUnknown_ref,
        nUnknown,
        vKnown_ref,
        nKnown,
        dvKnown,
        dvUnknown,
    );
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2GetDirectionalDerivative", LIVE, |_| {
            Err("not supported (providesDirectionalDerivative = false)".into())
        })
    }
}

/// `fmi2SetRealInputDerivatives`: not supported (canInterpolateInputs = false).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`] (no other argument is read).
#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    let _ = (vr, nvr, order, value);
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SetRealInputDerivatives", LIVE, |_| {
            Err("not supported (canInterpolateInputs = false)".into())
        })
    }
}

/// `fmi2GetRealOutputDerivatives`: not supported (maxOutputDerivativeOrder = 0).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`] (no other argument is read).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *mut fmi2Real,
) -> fmi2Status {
    let _ = (vr, nvr, order, value);
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2GetRealOutputDerivatives", LIVE, |_| {
            Err("not supported (maxOutputDerivativeOrder = 0)".into())
        })
    }
}

/// `fmi2DoStep` (StepMode): commits the current x; any step size ≥ 0 (the operator is rate
/// independent). A refused sample gives fmi2Error and changes nothing. With `saturate = true`,
/// the first step whose desired output is clamped (after unclamped ones) gives fmi2Warning and
/// a logged warning; the step is committed.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`].
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    let _ = noSetFMUStatePriorToCurrentPoint;
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2DoStep", &[StepMode], |inst| {
            match inst.do_step(currentCommunicationPoint, communicationStepSize)? {
                Some(warning) => {
                    inst.log.warning(&format!("fmi2DoStep: {warning}"));
                    Ok(fmi2Status::fmi2Warning)
                }
                None => Ok(fmi2Status::fmi2OK),
            }
        })
    }
}

/// `fmi2CancelStep`: fmi2Error (fmi2DoStep never returns fmi2Pending, so no step is ever in
/// progress).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`].
#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2CancelStep", LIVE, |_| {
            Err(
                "no step in progress: fmi2DoStep is synchronous (it never returns fmi2Pending)"
                    .into(),
            )
        })
    }
}

/// The status functions: `answer` gives the value for a status kind this FMU has, `None` for a
/// defined kind it cannot answer (fmi2Discard, as FMI 2.0 prescribes); undefined kinds are
/// fmi2Error.
///
/// # Safety
/// As [`fmi2GetStatus`], for `T`.
unsafe fn status<T>(
    c: fmi2Component,
    function: &str,
    kind: fmi2StatusKind,
    value: *mut T,
    answer: impl FnOnce(&Instance) -> Option<T>,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, function, STATUS, |inst| {
            if !(fmi2DoStepStatus..=fmi2Terminated).contains(&kind) {
                return Err(format!("status kind {kind} is not an fmi2StatusKind"));
            }
            if value.is_null() {
                return Err("value is NULL".into());
            }
            match answer(inst) {
                Some(v) => {
                    put(value, v, "value")?;
                    Ok(fmi2Status::fmi2OK)
                }
                None => {
                    inst.log.send(
                        fmi2Status::fmi2Discard,
                        c"logStatusDiscard",
                        &format!(
                            "{function}: status kind {kind} is not available (fmi2DoStep is \
                             synchronous: there is never a pending step)"
                        ),
                    );
                    Ok(fmi2Status::fmi2Discard)
                }
            }
        })
    }
}

/// `fmi2GetStatus`: fmi2Discard (no asynchronous step, so no fmi2DoStepStatus).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Status,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { status(c, "fmi2GetStatus", s, value, |_| None) }
}

/// `fmi2GetRealStatus`: fmi2LastSuccessfulTime is the end of the last successful fmi2DoStep
/// (the start time before the first); other kinds give fmi2Discard.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        status(c, "fmi2GetRealStatus", s, value, |inst| {
            (s == fmi2LastSuccessfulTime).then(|| inst.time())
        })
    }
}

/// `fmi2GetIntegerStatus`: fmi2Discard (FMI 2.0 defines no Integer status).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Integer,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { status(c, "fmi2GetIntegerStatus", s, value, |_| None) }
}

/// `fmi2GetBooleanStatus`: fmi2Terminated is fmi2False (the FMU never asks to stop); other
/// kinds give fmi2Discard.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        status(c, "fmi2GetBooleanStatus", s, value, |_| {
            (s == fmi2Terminated).then_some(fmi2False)
        })
    }
}

/// `fmi2GetStringStatus`: fmi2Discard (fmi2PendingStatus needs a pending step).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2String,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { status(c, "fmi2GetStringStatus", s, value, |_| None) }
}
