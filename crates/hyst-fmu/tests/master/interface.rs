//! Instantiation (resource locations in every form, bad resources) and the rest of the
//! interface: unsupported functions, null pointers, other FMU types, logged messages.

use super::*;
use crate::harness::*;

#[test]
fn resource_locations_in_every_form() {
    let base = tempfile::tempdir().unwrap();
    let dir = base.path().join("res dir #1 é");
    write_config(&dir, &operator_config(false, 0.2, 8.0));
    let plain = dir.to_str().unwrap().to_string();
    let encoded = uri(&dir); // file:///…%20…%23…
    assert!(encoded.contains("%20") && encoded.contains("%23"));
    let path_part = encoded.trim_start_matches("file://").to_string();
    for location in [
        encoded.clone(),
        format!("{encoded}/"),
        format!("file:{path_part}"),
        format!("file://localhost{path_part}/"),
        plain.clone(),
    ] {
        let fmu = Fmu::instantiate_with(&location, GUID, fmi2CoSimulation)
            .unwrap_or_else(|log| panic!("{location}: {log:?}"));
        fmu.initialise();
        assert_eq!(
            fmu.step(0.5).to_bits(),
            Hysteresis::new(0.2, 8.0)
                .unwrap()
                .try_step(0.5_f64)
                .unwrap()
                .to_bits()
        );
    }
}

/// Instantiation fails with NULL and a logged error containing every `part`.
pub(crate) fn refused(location: &str, guid: &str, fmu_type: fmi2Type, parts: &[&str]) {
    let log = match Fmu::instantiate_with(location, guid, fmu_type) {
        Ok(_) => panic!("{location} was accepted"),
        Err(log) => log,
    };
    assert_eq!(log.len(), 1, "{log:?}");
    let entry = &log[0];
    assert_eq!(entry.status, ERROR as c_int);
    assert_eq!(entry.category, "logStatusError");
    assert!(entry.format_is_percent_s);
    for p in parts {
        assert!(entry.message.contains(p), "{:?} lacks {p:?}", entry.message);
    }
}

#[test]
fn bad_resources_give_null_and_a_message() {
    let dir = operator_resources(false, 0.2, 8.0);
    let good = uri(dir.path());
    refused(
        &good,
        "{another}",
        fmi2CoSimulation,
        &["fmuGUID \"{another}\"", GUID, "fmu.toml"],
    );
    refused(
        &good,
        GUID,
        fmi2ModelExchange,
        &["fmuType = 0", "Co-Simulation"],
    );
    let missing = dir.path().join("nowhere");
    refused(
        &uri(&missing),
        GUID,
        fmi2CoSimulation,
        &["nowhere/fmu.toml", "cannot read"],
    );
    refused(
        "http://example.com/r",
        GUID,
        fmi2CoSimulation,
        &["file URI"],
    );
    refused(
        "file://server/r",
        GUID,
        fmi2CoSimulation,
        &["host \"server\""],
    );
    refused(
        "resources",
        GUID,
        fmi2CoSimulation,
        &["fmuResourceLocation \"resources\""],
    );
    let cases: [(&str, &[&str]); 11] = [
        ("format = \"hyst-model\"\nversion = 1\n", &["format = \"hyst-model\""]),
        ("format = \"hyst-fmu\"\nversion = 2\n", &["version = 2"]),
        ("format = \"hyst-fmu\"\n", &["no `version`"]),
        ("format = \"hyst-fmu\"\nversion = 1\nguid = \"g\"\nkind = \"operator\"\nk1 = 1.0\nk2 = 1.0\nk3 = 1\n", &["k3"]),
        ("format = \"hyst-fmu\"\nversion = 1\nguid = \"g\"\nkind = \"operator\"\nk1 = -0.2\nk2 = 8.0\n", &["k1 = -0.2", "invalid parameter k1"]),
        ("format = \"hyst-fmu\"\nversion = 1\nguid = \"g\"\nkind = \"operator\"\nk1 = 0.2\nk2 = 0.0\n", &["invalid parameter k2 = 0"]),
        ("format = \"hyst-fmu\"\nversion = 1\nguid = \"g\"\nkind = \"operator\"\nk1 = 0.2\n", &["needs k2"]),
        ("format = \"hyst-fmu\"\nversion = 1\nguid = \"g\"\nkind = \"play\"\n", &["kind = \"play\""]),
        ("format = \"hyst-fmu\"\nversion = 1\nguid = \"g\"\nkind = \"model\"\n", &["model.toml"]),
        ("format = \"hyst-fmu\"\nversion = 1\nguid = \"g\"\nkind = \"model\"\nk1 = 0.2\n", &["k1 = 0.2", "only kind = \"operator\""]),
        ("format = \"hyst-fmu\"\nversion = 1\nguid = \"g\"\nkind = \"operator\"\ninverse = true\nsaturate = true\nk1 = 0.2\nk2 = 8.0\n", &["saturate = true", "kind = \"model\" with inverse = true"]),
    ];
    for (body, parts) in cases {
        let d = tempfile::tempdir().unwrap();
        write_config(d.path(), body);
        refused(
            &uri(d.path()),
            "g",
            fmi2CoSimulation,
            &[&["fmu.toml"][..], parts].concat(),
        );
    }
    // NULL arguments.
    let guid = CString::new(GUID).unwrap();
    let location = CString::new(good.clone()).unwrap();
    let name = CString::new("n").unwrap();
    let empty = CString::new("").unwrap();
    let log: Box<Log> = Box::default();
    let callbacks = fmi2CallbackFunctions {
        logger: Some(logger()),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: ptr::from_ref::<Log>(&log).cast_mut().cast(),
    };
    unsafe {
        let i = |n: fmi2String, g: fmi2String, l: fmi2String, f: *const fmi2CallbackFunctions| {
            fmi2Instantiate(n, fmi2CoSimulation, g, l, f, 0, 0)
        };
        assert!(i(name.as_ptr(), guid.as_ptr(), location.as_ptr(), ptr::null()).is_null());
        assert!(i(ptr::null(), guid.as_ptr(), location.as_ptr(), &callbacks).is_null());
        assert!(i(empty.as_ptr(), guid.as_ptr(), location.as_ptr(), &callbacks).is_null());
        assert!(i(name.as_ptr(), ptr::null(), location.as_ptr(), &callbacks).is_null());
        assert!(i(name.as_ptr(), guid.as_ptr(), ptr::null(), &callbacks).is_null());
        let c = i(name.as_ptr(), guid.as_ptr(), location.as_ptr(), &callbacks);
        assert!(!c.is_null());
        fmi2FreeInstance(c);
    }
    let messages: Vec<String> = log.take().into_iter().map(|l| l.message).collect();
    assert_eq!(messages.len(), 4, "{messages:?}");
    for (m, part) in messages.iter().zip([
        "instanceName is NULL",
        "instanceName is empty",
        "fmuGUID is NULL",
        "fmuResourceLocation is NULL",
    ]) {
        assert!(m.contains(part), "{m:?} lacks {part:?}");
    }
}

// ------------------------------------------------------------------------------------------
// The rest of the interface.

#[test]
fn unsupported_functions_null_pointers_and_other_types() {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::started(dir.path());
    let c = fmu.c;
    unsafe {
        assert_eq!(CStr::from_ptr(fmi2GetTypesPlatform()), c"default");
        assert_eq!(CStr::from_ptr(fmi2GetVersion()), c"2.0");
        let vr = [VR_X];
        let mut v = [0.0];
        assert_eq!(
            fmi2GetDirectionalDerivative(
                c,
                vr.as_ptr(),
                1,
                vr.as_ptr(),
                1,
                v.as_ptr(),
                v.as_mut_ptr()
            ),
            ERROR
        );
        fmu.expect_error(&["fmi2GetDirectionalDerivative", "not supported"]);
        let order = [1];
        assert_eq!(
            fmi2SetRealInputDerivatives(c, vr.as_ptr(), 1, order.as_ptr(), v.as_ptr()),
            ERROR
        );
        fmu.expect_error(&["fmi2SetRealInputDerivatives", "not supported"]);
        assert_eq!(
            fmi2GetRealOutputDerivatives(c, vr.as_ptr(), 1, order.as_ptr(), v.as_mut_ptr()),
            ERROR
        );
        fmu.expect_error(&["fmi2GetRealOutputDerivatives", "not supported"]);
        assert_eq!(fmi2CancelStep(c), ERROR);
        fmu.expect_error(&["fmi2CancelStep"]);
        // No Integer, Boolean or String variables: an empty call is fine, any reference is not.
        let mut i = [0 as fmi2Integer];
        let mut s = [ptr::null() as fmi2String];
        assert_eq!(fmi2GetInteger(c, ptr::null(), 0, ptr::null_mut()), OK);
        assert_eq!(fmi2GetInteger(c, vr.as_ptr(), 1, i.as_mut_ptr()), ERROR);
        fmu.expect_error(&["no Integer variable has value reference 0"]);
        assert_eq!(fmi2SetInteger(c, vr.as_ptr(), 1, i.as_ptr()), ERROR);
        assert_eq!(fmi2GetBoolean(c, vr.as_ptr(), 1, i.as_mut_ptr()), ERROR);
        assert_eq!(fmi2SetBoolean(c, vr.as_ptr(), 1, i.as_ptr()), ERROR);
        assert_eq!(fmi2GetString(c, vr.as_ptr(), 1, s.as_mut_ptr()), ERROR);
        assert_eq!(fmi2SetString(c, vr.as_ptr(), 1, s.as_ptr()), ERROR);
        assert_eq!(fmi2SetBoolean(c, ptr::null(), 0, ptr::null()), OK);
        assert_eq!(fmu.errors().len(), 5);
        // NULL arrays, unknown references.
        assert_eq!(fmi2GetReal(c, ptr::null(), 1, v.as_mut_ptr()), ERROR);
        fmu.expect_error(&["vr is NULL"]);
        assert_eq!(fmi2GetReal(c, vr.as_ptr(), 1, ptr::null_mut()), ERROR);
        fmu.expect_error(&["value is NULL"]);
        assert_eq!(fmi2SetReal(c, vr.as_ptr(), 1, ptr::null()), ERROR);
        fmu.expect_error(&["value is NULL"]);
        assert_eq!(fmi2GetReal(c, ptr::null(), 0, ptr::null_mut()), OK);
        assert_eq!(fmu.get(7), Err(ERROR));
        fmu.expect_error(&["value reference 7"]);
        assert_eq!(fmi2DoStep(c, 0.0, -1.0, 0), ERROR);
        fmu.expect_error(&["communicationStepSize = -1"]);
        assert_eq!(fmi2DoStep(c, f64::NAN, 0.0, 0), ERROR);
        fmu.expect_error(&["currentCommunicationPoint = NaN"]);
        assert_eq!(fmi2DoStep(c, 5.0, 0.0, 0), OK); // a zero step is fine
        let mut t = 0.0;
        assert_eq!(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &mut t), OK);
        assert_eq!(t, 5.0);
        assert_eq!(
            fmi2GetRealStatus(c, fmi2LastSuccessfulTime, ptr::null_mut()),
            ERROR
        );
        fmu.expect_error(&["value is NULL"]);
        let mut n = 0;
        assert_eq!(fmi2GetIntegerStatus(c, fmi2DoStepStatus, &mut n), DISCARD);
        assert_eq!(
            fmi2GetStringStatus(c, fmi2PendingStatus, s.as_mut_ptr()),
            DISCARD
        );
        assert!(fmu.errors().is_empty());
        // Debug logging: on, a debug message per ...; categories are checked for NULL.
        let categories = [c"logAll".as_ptr()];
        assert_eq!(fmi2SetDebugLogging(c, fmi2True, 1, categories.as_ptr()), OK);
        assert_eq!(fmi2SetDebugLogging(c, fmi2True, 1, ptr::null()), ERROR);
        fmu.expect_error(&["categories is NULL"]);
        assert_eq!(fmi2SetDebugLogging(c, fmi2False, 0, ptr::null()), OK);
        // A NULL or foreign instance: fmi2Error, nothing logged (there is no logger to call).
        let mut garbage = [0u64; 64];
        for bad in [ptr::null_mut(), garbage.as_mut_ptr().cast::<c_void>()] {
            assert_eq!(fmi2SetReal(bad, vr.as_ptr(), 1, v.as_ptr()), ERROR);
            assert_eq!(fmi2GetReal(bad, vr.as_ptr(), 1, v.as_mut_ptr()), ERROR);
            assert_eq!(fmi2DoStep(bad, 0.0, 1.0, 0), ERROR);
            assert_eq!(fmi2EnterInitializationMode(bad), ERROR);
            assert_eq!(fmi2Reset(bad), ERROR);
            assert_eq!(fmi2GetFMUstate(bad, &mut ptr::null_mut()), ERROR);
            fmi2FreeInstance(bad);
        }
        assert!(fmu.errors().is_empty());
    }
}

#[test]
fn messages_are_passed_as_a_percent_s_argument_with_hash_escaped() {
    let dir = operator_resources(false, 0.2, 8.0);
    // A GUID full of printf directives and '#': passed through literally ('#' doubled).
    let log = match Fmu::instantiate_with(&uri(dir.path()), "%s%n%d #1", fmi2CoSimulation) {
        Ok(_) => panic!("accepted"),
        Err(log) => log,
    };
    assert_eq!(log.len(), 1);
    assert!(log[0].format_is_percent_s);
    assert!(
        log[0].message.contains("fmuGUID \"%s%n%d ##1\""),
        "{}",
        log[0].message
    );
    // Debug messages only while debug logging is on.
    let fmu = Fmu::instantiate(dir.path());
    let count = |fmu: &Fmu| {
        fmu.log
            .borrow()
            .iter()
            .filter(|l| l.category == "logAll")
            .count()
    };
    assert_eq!(count(&fmu), 0);
    let log: Box<Log> = Box::default();
    let callbacks = fmi2CallbackFunctions {
        logger: Some(logger()),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: ptr::from_ref::<Log>(&log).cast_mut().cast(),
    };
    let (name, guid, location) = (
        CString::new("loud").unwrap(),
        CString::new(GUID).unwrap(),
        CString::new(uri(dir.path())).unwrap(),
    );
    unsafe {
        let c = fmi2Instantiate(
            name.as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            location.as_ptr(),
            &callbacks,
            0,
            fmi2True,
        );
        assert!(!c.is_null());
        fmi2FreeInstance(c);
    }
    let log = log.take();
    assert!(
        !log.is_empty()
            && log
                .iter()
                .all(|l| l.category == "logAll" && l.instance == "loud" && l.status == OK as c_int)
    );
}

#[test]
fn saturate_needs_the_inverse_of_a_saturating_model() {
    for (file, inverse, part) in [
        (saturating_model(), false, "with inverse = true"),
        (fitted_model(), true, "unbounded"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        write_config(
            dir.path(),
            &format!("{}saturate = true\n", model_config(inverse)),
        );
        std::fs::write(dir.path().join("model.toml"), file.to_toml().unwrap()).unwrap();
        refused(
            &uri(dir.path()),
            GUID,
            fmi2CoSimulation,
            &["fmu.toml", "saturate = true", part],
        );
    }
}
