//! The life of an instance: fmi2Instantiate and fmi2FreeInstance, the mode changes
//! (initialisation, termination, reset), the communication steps (fmi2DoStep) and the logging
//! switch.

use std::ffi::{c_char, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

use crate::api::boundary::{free_component, get, input, new_component, text, with_instance, LIVE};
use crate::config::{resource_dir, Config};
use crate::fmi2::*;
use crate::instance::{Instance, Phase};
use crate::layout::CONFIG_FILE;
use crate::logger::Logger;

use Phase::{InitializationMode, Instantiated, StepMode, Terminated};

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
                new_component(instance)
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
            dir.join(CONFIG_FILE).display()
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
        unsafe { free_component(c) }
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

/// `fmi2DoStep` (StepMode): commits the current x as the communication point's sample, whose
/// output y keeps until an input is set; any step size ≥ 0 (the operator is rate
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
