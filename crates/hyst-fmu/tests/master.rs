//! The FMU driven as a master drives it: resources written to a temporary folder, every exported
//! function called through its C signature, and the results compared bit for bit with the core
//! (`Hysteresis`, `InverseHysteresis`) and the model file's `Evaluator` run over the same inputs.
//!
//! The test logger is a non-variadic Rust function called through the variadic
//! `fmi2CallbackLogger` type; that is sound on the platforms this test runs on (see `logger`),
//! which are the FMU's platform (linux64).
#![cfg(all(
    target_os = "linux",
    any(target_arch = "x86_64", target_arch = "aarch64")
))]
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the FMI functions through raw pointers, as a C program does.
#![allow(unsafe_code)]

use std::cell::{Cell, RefCell};
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::path::Path;
use std::ptr;

use hyst_core::{
    AnyK2Law, AnyShaping, Hysteresis, InverseHysteresis, Operator, ScaledShaping, Tanh,
};
use hyst_fmu::fmi2::*;
use hyst_fmu::layout::{VR_K1, VR_K2, VR_X, VR_Y};
use hyst_fmu::*;
use hyst_model::PiModel;
use hyst_model::{file::fnv1a64, file::FORMAT, ModelKind};
use hyst_model::{InitialState, ModelFile, SmoothModel};

use fmi2Status::{
    fmi2Discard as DISCARD, fmi2Error as ERROR, fmi2OK as OK, fmi2Warning as WARNING,
};

const GUID: &str = "{6f1c2a3e-hyst-test}";

// ------------------------------------------------------------------------------------------
// The logger.

#[derive(Clone, Debug)]
struct Logged {
    status: c_int,
    category: String,
    message: String,
    /// The format was "%s" (the FMU must never pass its text as the format).
    format_is_percent_s: bool,
    instance: String,
}

type Log = RefCell<Vec<Logged>>;

/// Records a message into the `Log` the environment pointer points to.
unsafe extern "C" fn record(
    env: *mut c_void,
    instance: *const c_char,
    status: c_int,
    category: *const c_char,
    format: *const c_char,
    message: *const c_char,
) {
    let text = |p: *const c_char| {
        if p.is_null() {
            String::from("<NULL>")
        } else {
            // SAFETY: the FMU passes NUL-terminated strings.
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    // SAFETY: the environment is the test's `Log`, alive while the instance lives.
    let log = unsafe { &*env.cast::<Log>() };
    log.borrow_mut().push(Logged {
        status,
        category: text(category),
        message: text(message),
        format_is_percent_s: text(format) == "%s",
        instance: text(instance),
    });
}

type Record = unsafe extern "C" fn(
    *mut c_void,
    *const c_char,
    c_int,
    *const c_char,
    *const c_char,
    *const c_char,
);

fn logger() -> fmi2CallbackLogger {
    // SAFETY: on x86-64 System V and AArch64 Linux (this file's cfg), a variadic call passes its
    // fixed arguments and a pointer vararg in the same registers as a non-variadic call with
    // the same parameter list, and fmi2Status is an int; the FMU always passes exactly one
    // vararg (the "%s" argument), which `record` receives as its sixth parameter.
    unsafe { std::mem::transmute::<Record, fmi2CallbackLogger>(record) }
}

// ------------------------------------------------------------------------------------------
// Resources.

/// A signal with many reversals of varying amplitude.
fn signal(k: usize) -> f64 {
    let t = k as f64 * 0.03;
    (0.4 + 0.04 * t).min(1.3) * t.sin() + 0.25 * (2.9 * t).cos()
}

fn write_config(dir: &Path, body: &str) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("fmu.toml"), body).unwrap();
}

fn operator_config(inverse: bool, k1: f64, k2: f64) -> String {
    format!(
        "format = \"hyst-fmu\"\nversion = 1\nguid = \"{GUID}\"\nkind = \"operator\"\n\
         inverse = {inverse}\nk1 = {k1:?}\nk2 = {k2:?}\n"
    )
}

fn model_config(inverse: bool) -> String {
    format!(
        "format = \"hyst-fmu\"\nversion = 1\nguid = \"{GUID}\"\nkind = \"model\"\n\
         inverse = {inverse}\n"
    )
}

fn operator_resources(inverse: bool, k1: f64, k2: f64) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write_config(dir.path(), &operator_config(inverse, k1, k2));
    dir
}

fn model_file(smooth: Option<SmoothModel>, pi: Option<PiModel>) -> ModelFile {
    ModelFile {
        format: FORMAT.into(),
        version: 1,
        kind: if smooth.is_some() {
            ModelKind::Smooth
        } else {
            ModelKind::PrandtlIshlinskii
        },
        columns: hyst_model::Columns {
            input: "x".into(),
            output: "y".into(),
            ..Default::default()
        },
        units: Default::default(),
        parameters: Vec::new(),
        metrics: Default::default(),
        structure: smooth.as_ref().map(|_| hyst_model::Structure::default()),
        smooth,
        prandtl_ishlinskii: pi,
        dynamics: None,
        rate: None,
        family: None,
        provenance: Default::default(),
    }
}

/// A smooth model as `hyst fit` makes it from data of a known operator.
fn fitted_model() -> ModelFile {
    // The operator the data would come from, as a fitted smooth model: y = 3 H(0.2, 6)[x] + 1,
    // starting as after a rise (a fit of that data recovers it).
    let model = hyst_model::SmoothModel {
        k1: 0.2,
        k2: hyst_core::AnyK2Law::Constant { value: 6.0 },
        input_shaping: hyst_core::ScaledShaping::identity(),
        output_shaping: hyst_core::ScaledShaping::new(
            1.0,
            0.0,
            hyst_core::AnyShaping::Identity,
            3.0,
            1.0,
        )
        .unwrap(),
        initial_state: hyst_model::InitialState::Rising,
        form: hyst_model::Form::Operator,
        linear: 0.0,
        dynamics: None,
        rate: None,
    };
    model_file(Some(model), None)
}

/// A Prandtl–Ishlinskii model (its memory is the plays).
fn pi_model() -> ModelFile {
    model_file(
        None,
        Some(PiModel {
            identity_weight: 0.5,
            thresholds: vec![0.1, 0.3, 0.6],
            weights: vec![0.4, 0.3, 0.2],
            offset: 0.1,
            output: None,
        }),
    )
}

/// A smooth model whose output saturates at ±2 (tanh): its inverse refuses |y| ≥ 2.
fn saturating_model() -> ModelFile {
    model_file(
        Some(SmoothModel {
            k1: 0.2,
            k2: AnyK2Law::Constant { value: 6.0 },
            input_shaping: ScaledShaping::identity(),
            output_shaping: ScaledShaping {
                pre_gain: 1.0,
                pre_offset: 0.0,
                shape: AnyShaping::Tanh(Tanh::new(1.0, 1.0).unwrap()),
                post_gain: 2.0,
                post_offset: 0.0,
            },
            initial_state: InitialState::Line,
            form: hyst_model::Form::Operator,
            linear: 0.0,
            dynamics: None,
            rate: None,
        }),
        None,
    )
}

fn model_resources(file: &ModelFile, inverse: bool) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write_config(dir.path(), &model_config(inverse));
    std::fs::write(dir.path().join("model.toml"), file.to_toml().unwrap()).unwrap();
    dir
}

/// `file:///…` with every byte but unreserved ones and '/' percent-encoded.
fn uri(dir: &Path) -> String {
    let mut out = String::from("file://");
    for b in dir.to_str().unwrap().bytes() {
        if b.is_ascii_alphanumeric() || b"/-._~".contains(&b) {
            out.push(char::from(b));
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

// ------------------------------------------------------------------------------------------
// A small safe master.

struct Fmu {
    c: fmi2Component,
    log: Box<Log>,
    time: Cell<f64>,
    /// The communication step size of `do_step` (0.01 unless a test sets it).
    step_size: Cell<f64>,
}

impl Fmu {
    fn instantiate_with(
        location: &str,
        guid: &str,
        fmu_type: fmi2Type,
    ) -> Result<Fmu, Vec<Logged>> {
        let log: Box<Log> = Box::default();
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: Some(logger()),
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: ptr::from_ref::<Log>(&log).cast_mut().cast(),
        });
        let name = CString::new("inst").unwrap();
        let guid = CString::new(guid).unwrap();
        let location = CString::new(location).unwrap();
        let c = unsafe {
            fmi2Instantiate(
                name.as_ptr(),
                fmu_type,
                guid.as_ptr(),
                location.as_ptr(),
                &*callbacks,
                fmi2False,
                fmi2False,
            )
        };
        // The FMU must have copied the callbacks: the struct is gone while the instance lives.
        drop(callbacks);
        if c.is_null() {
            Err(log.take())
        } else {
            Ok(Fmu {
                c,
                log,
                time: Cell::new(0.0),
                step_size: Cell::new(0.01),
            })
        }
    }

    fn instantiate(dir: &Path) -> Fmu {
        Self::instantiate_with(&uri(dir), GUID, fmi2CoSimulation).unwrap()
    }

    /// Instantiated, set up, initialised: in step mode.
    fn started(dir: &Path) -> Fmu {
        let fmu = Self::instantiate(dir);
        fmu.initialise();
        fmu
    }

    fn initialise(&self) {
        unsafe {
            assert_eq!(
                fmi2SetupExperiment(self.c, fmi2False, 0.0, 0.0, fmi2False, 0.0),
                OK
            );
            assert_eq!(fmi2EnterInitializationMode(self.c), OK);
            assert_eq!(fmi2ExitInitializationMode(self.c), OK);
        }
    }

    fn set(&self, vr: u32, value: f64) -> fmi2Status {
        unsafe { fmi2SetReal(self.c, &vr, 1, &value) }
    }

    fn get(&self, vr: u32) -> Result<f64, fmi2Status> {
        let mut value = f64::NAN;
        match unsafe { fmi2GetReal(self.c, &vr, 1, &mut value) } {
            OK => Ok(value),
            s => Err(s),
        }
    }

    fn y(&self) -> f64 {
        self.get(VR_Y).unwrap()
    }

    fn do_step(&self) -> fmi2Status {
        let (t, h) = (self.time.get(), self.step_size.get());
        let status = unsafe { fmi2DoStep(self.c, t, h, fmi2True) };
        if status == OK {
            self.time.set(t + h);
        }
        status
    }

    /// One communication step as a master does it: set x, read y (direct feedthrough), step,
    /// read y again (the same bits). Returns y.
    fn step(&self, x: f64) -> f64 {
        assert_eq!(self.set(VR_X, x), OK);
        let y = self.y();
        assert_eq!(self.do_step(), OK);
        assert_eq!(
            self.y().to_bits(),
            y.to_bits(),
            "y changed by fmi2DoStep at x = {x}"
        );
        y
    }

    fn run(&self, xs: &[f64]) -> Vec<f64> {
        xs.iter().map(|x| self.step(*x)).collect()
    }

    /// The error messages logged since the last call.
    fn errors(&self) -> Vec<String> {
        let log = self.log.take();
        assert!(log
            .iter()
            .all(|l| l.format_is_percent_s && l.instance == "inst"));
        log.into_iter()
            .filter(|l| l.status == ERROR as c_int)
            .map(|l| l.message)
            .collect()
    }

    /// Asserts that exactly one error was logged and that it contains every `part`.
    fn expect_error(&self, parts: &[&str]) {
        let errors = self.errors();
        assert_eq!(errors.len(), 1, "{errors:?}");
        for p in parts {
            assert!(errors[0].contains(p), "{:?} lacks {p:?}", errors[0]);
        }
    }

    fn get_state(&self) -> fmi2FMUstate {
        let mut s: fmi2FMUstate = ptr::null_mut();
        assert_eq!(unsafe { fmi2GetFMUstate(self.c, &mut s) }, OK);
        assert!(!s.is_null());
        s
    }

    fn set_state(&self, s: fmi2FMUstate) -> fmi2Status {
        unsafe { fmi2SetFMUstate(self.c, s) }
    }

    fn serialize(&self, s: fmi2FMUstate) -> Vec<u8> {
        let mut size = 0;
        assert_eq!(
            unsafe { fmi2SerializedFMUstateSize(self.c, s, &mut size) },
            OK
        );
        let mut bytes = vec![0u8; size];
        assert_eq!(
            unsafe { fmi2SerializeFMUstate(self.c, s, bytes.as_mut_ptr().cast(), size) },
            OK
        );
        bytes
    }

    fn deserialize(&self, bytes: &[u8]) -> Result<fmi2FMUstate, fmi2Status> {
        let mut s: fmi2FMUstate = ptr::null_mut();
        match unsafe { fmi2DeSerializeFMUstate(self.c, bytes.as_ptr().cast(), bytes.len(), &mut s) }
        {
            OK => Ok(s),
            status => {
                assert!(s.is_null(), "a refused state was handed out");
                Err(status)
            }
        }
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        unsafe { fmi2FreeInstance(self.c) };
    }
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The core operator run over `xs`.
fn core_run<O: Operator<f64>>(mut op: O, xs: &[f64]) -> Vec<f64> {
    xs.iter().map(|x| op.try_step(*x).unwrap()).collect()
}

/// The model file's evaluator run over `xs`, started at the first sample (`hyst run --model`).
fn evaluator_run(file: &ModelFile, inverse: bool, xs: &[f64]) -> Vec<f64> {
    core_run(file.evaluator(xs[0], inverse).unwrap(), xs)
}

// ------------------------------------------------------------------------------------------
// Outputs.

#[test]
fn operator_outputs_equal_the_core_bit_for_bit() {
    let xs: Vec<f64> = (0..3000).map(signal).collect();
    for inverse in [false, true] {
        let dir = operator_resources(inverse, 0.2, 8.0);
        let fmu = Fmu::started(dir.path());
        let mut reference: Box<dyn FnMut(f64) -> f64> = if inverse {
            let mut op = InverseHysteresis::new(0.2, 8.0).unwrap();
            Box::new(move |x| op.try_step(x).unwrap())
        } else {
            let mut op = Hysteresis::new(0.2, 8.0).unwrap();
            Box::new(move |x| op.try_step(x).unwrap())
        };
        let peek = |committed: &[f64], x: f64| {
            let mut all = committed.to_vec();
            all.push(x);
            let ys = if inverse {
                core_run(InverseHysteresis::new(0.2, 8.0).unwrap(), &all)
            } else {
                core_run(Hysteresis::new(0.2, 8.0).unwrap(), &all)
            };
            *ys.last().unwrap()
        };
        for (k, x) in xs.iter().enumerate() {
            if k % 499 == 7 {
                // A value set and read but replaced before fmi2DoStep is never committed.
                assert_eq!(fmu.set(VR_X, x + 0.3), OK);
                assert_eq!(fmu.y().to_bits(), peek(&xs[..k], x + 0.3).to_bits());
            }
            let y = fmu.step(*x);
            assert_eq!(
                y.to_bits(),
                reference(*x).to_bits(),
                "inverse {inverse}, sample {k}"
            );
        }
        assert!(fmu.errors().is_empty());
        let mut t = 0.0;
        assert_eq!(
            unsafe { fmi2GetRealStatus(fmu.c, fmi2LastSuccessfulTime, &mut t) },
            OK
        );
        assert_eq!(t, fmu.time.get());
        assert_eq!(fmu.get(VR_K1), Ok(0.2));
        assert_eq!(fmu.get(VR_K2), Ok(8.0));
        assert_eq!(fmu.get(VR_X), Ok(xs[2999]));
    }
}

#[test]
fn model_outputs_equal_the_evaluator_bit_for_bit() {
    let xs: Vec<f64> = (0..1500).map(|k| signal(k + 11)).collect();
    for (name, file) in [("smooth", fitted_model()), ("pi", pi_model())] {
        for inverse in [false, true] {
            let input: Vec<f64> = if inverse {
                xs.iter().map(|x| 3.0 * x + 1.0).collect()
            } else {
                xs.clone()
            };
            let dir = model_resources(&file, inverse);
            let fmu = Fmu::started(dir.path());
            // Before the first fmi2DoStep, y comes from an evaluator started at the current x.
            assert_eq!(fmu.set(VR_X, input[5]), OK);
            assert_eq!(
                fmu.y().to_bits(),
                evaluator_run(&file, inverse, &input[5..6])[0].to_bits()
            );
            let ys = fmu.run(&input);
            assert_eq!(
                bits(&ys),
                bits(&evaluator_run(&file, inverse, &input)),
                "{name} {inverse}"
            );
            // A model has no parameters k1, k2.
            assert_eq!(fmu.get(VR_K1), Err(ERROR));
            fmu.expect_error(&["value reference 2"]);
            assert_eq!(fmu.set(VR_K2, 1.0), ERROR);
            fmu.expect_error(&["value reference 3"]);
        }
    }
}

#[test]
fn two_instances_are_independent() {
    let dir_a = operator_resources(false, 0.2, 8.0);
    let dir_b = operator_resources(true, 0.5, 3.0);
    let a = Fmu::started(dir_a.path());
    let b = Fmu::started(dir_b.path());
    let file = pi_model();
    let dir_c = model_resources(&file, false);
    let c = Fmu::started(dir_c.path());
    let xa: Vec<f64> = (0..1000).map(signal).collect();
    let xb: Vec<f64> = (0..1000).map(|k| -2.0 * signal(k + 300)).collect();
    let xc: Vec<f64> = (0..1000).map(|k| signal(2 * k)).collect();
    let (mut ya, mut yb, mut yc) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..1000 {
        ya.push(a.step(xa[k]));
        yb.push(b.step(xb[k]));
        yc.push(c.step(xc[k]));
    }
    assert_eq!(
        bits(&ya),
        bits(&core_run(Hysteresis::new(0.2, 8.0).unwrap(), &xa))
    );
    assert_eq!(
        bits(&yb),
        bits(&core_run(InverseHysteresis::new(0.5, 3.0).unwrap(), &xb))
    );
    assert_eq!(bits(&yc), bits(&evaluator_run(&file, false, &xc)));
}

// ------------------------------------------------------------------------------------------
// Parameters and modes.

#[test]
fn parameters_are_set_before_initialisation_only() {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::instantiate(dir.path());
    let xs: Vec<f64> = (0..800).map(signal).collect();
    unsafe {
        assert_eq!(fmu.set(VR_K1, 0.3), OK); // Instantiated
        assert_eq!(fmi2EnterInitializationMode(fmu.c), OK);
        assert_eq!(fmu.set(VR_K2, 5.0), OK); // InitializationMode
        assert_eq!(fmu.set(VR_X, xs[0]), OK);
        // y is an initial unknown: computed with the current k1, k2 and x.
        assert_eq!(
            fmu.y().to_bits(),
            Hysteresis::new(0.3, 5.0)
                .unwrap()
                .try_step(xs[0])
                .unwrap()
                .to_bits()
        );
        assert_eq!(fmi2ExitInitializationMode(fmu.c), OK);
    }
    let ys = fmu.run(&xs[..400]);
    let reference = core_run(Hysteresis::new(0.3, 5.0).unwrap(), &xs);
    assert_eq!(bits(&ys), bits(&reference[..400]));
    // After initialisation k1 and k2 are fixed: refused, named, nothing changes.
    assert_eq!(fmu.set(VR_K1, 0.25), ERROR);
    fmu.expect_error(&["fmi2SetReal", "k1 = 0.25", "fixed parameter"]);
    assert_eq!(fmu.get(VR_K1), Ok(0.3));
    // All values or none: x is not set when k2 is refused in the same call.
    let (vrs, values) = ([VR_X, VR_K2], [9.0, 1.0]);
    assert_eq!(
        unsafe { fmi2SetReal(fmu.c, vrs.as_ptr(), 2, values.as_ptr()) },
        ERROR
    );
    fmu.expect_error(&["k2 = 1"]);
    assert_eq!(fmu.get(VR_X), Ok(xs[399]));
    assert_eq!(fmu.get(VR_K2), Ok(5.0));
    // y is an output.
    assert_eq!(fmu.set(VR_Y, 1.0), ERROR);
    fmu.expect_error(&["output"]);
    assert_eq!(bits(&fmu.run(&xs[400..])), bits(&reference[400..]));
    // Several values in one call, y once.
    let vrs = [VR_Y, VR_X, VR_K1, VR_K2, VR_Y];
    let mut out = [0.0; 5];
    assert_eq!(
        unsafe { fmi2GetReal(fmu.c, vrs.as_ptr(), 5, out.as_mut_ptr()) },
        OK
    );
    assert_eq!(out, [reference[799], xs[799], 0.3, 5.0, reference[799]]);
    unsafe {
        assert_eq!(fmi2Terminate(fmu.c), OK);
        assert_eq!(fmu.set(VR_K1, 0.3), ERROR); // Terminated: nothing may be set
        fmu.expect_error(&["fmi2SetReal", "Terminated"]);
        assert_eq!(fmu.y(), reference[799]); // but values may be read
    }
}

#[test]
fn invalid_parameters_fail_initialisation_naming_them() {
    let dir = operator_resources(true, 0.2, 8.0);
    let fmu = Fmu::instantiate(dir.path());
    unsafe {
        assert_eq!(fmi2EnterInitializationMode(fmu.c), OK);
        assert_eq!(fmu.set(VR_K1, -1.0), OK);
        assert_eq!(fmu.get(VR_Y), Err(ERROR));
        fmu.expect_error(&["fmi2GetReal", "k1", "-1"]);
        assert_eq!(fmi2ExitInitializationMode(fmu.c), ERROR);
        fmu.expect_error(&["fmi2ExitInitializationMode", "k1 = -1"]);
        assert_eq!(fmu.do_step(), ERROR); // still in InitializationMode
        fmu.expect_error(&["fmi2DoStep", "InitializationMode"]);
        assert_eq!(fmu.set(VR_K2, f64::NAN), OK);
        assert_eq!(fmu.set(VR_K1, 0.4), OK);
        assert_eq!(fmi2ExitInitializationMode(fmu.c), ERROR);
        fmu.expect_error(&["k2 = NaN"]);
        assert_eq!(fmu.set(VR_K2, 2.0), OK);
        assert_eq!(fmi2ExitInitializationMode(fmu.c), OK);
    }
    let xs: Vec<f64> = (0..500).map(signal).collect();
    assert_eq!(
        bits(&fmu.run(&xs)),
        bits(&core_run(InverseHysteresis::new(0.4, 2.0).unwrap(), &xs))
    );
}

#[test]
fn calls_in_the_wrong_mode_are_refused_and_reset_starts_over() {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::instantiate(dir.path());
    let xs: Vec<f64> = (0..600).map(signal).collect();
    unsafe {
        assert_eq!(fmu.get(VR_Y), Err(ERROR)); // Instantiated: y is not yet calculated
        fmu.expect_error(&["fmi2GetReal", "Instantiated"]);
        assert_eq!(fmu.do_step(), ERROR);
        fmu.expect_error(&["fmi2DoStep", "Instantiated"]);
        assert_eq!(fmi2ExitInitializationMode(fmu.c), ERROR);
        assert_eq!(fmi2Terminate(fmu.c), ERROR);
        fmu.errors();
        assert_eq!(fmu.set(VR_K1, 0.7), OK);
        assert_eq!(fmi2EnterInitializationMode(fmu.c), OK);
        assert_eq!(fmi2EnterInitializationMode(fmu.c), ERROR);
        assert_eq!(fmi2SetupExperiment(fmu.c, 0, 0.0, 0.0, 0, 0.0), ERROR);
        assert_eq!(fmi2Terminate(fmu.c), ERROR);
        assert_eq!(fmu.errors().len(), 3);
        assert_eq!(fmi2ExitInitializationMode(fmu.c), OK);
        fmu.run(&xs[..100]);
        let mut status = fmi2Status::fmi2OK;
        assert_eq!(fmi2GetStatus(fmu.c, fmi2DoStepStatus, &mut status), DISCARD);
        let mut terminated = fmi2True;
        assert_eq!(
            fmi2GetBooleanStatus(fmu.c, fmi2Terminated, &mut terminated),
            OK
        );
        assert_eq!(terminated, fmi2False);
        assert_eq!(fmi2GetRealStatus(fmu.c, 17, &mut 0.0), ERROR);
        assert_eq!(fmi2Terminate(fmu.c), OK);
        assert_eq!(fmu.do_step(), ERROR);
        assert_eq!(fmu.set(VR_X, 1.0), ERROR);
        assert_eq!(fmi2Terminate(fmu.c), ERROR);
        fmu.errors();
        // Reset: Instantiated again, k1 back to its start value, no history.
        assert_eq!(fmi2Reset(fmu.c), OK);
        assert_eq!(fmu.get(VR_Y), Err(ERROR));
        fmu.errors();
        assert_eq!(fmi2EnterInitializationMode(fmu.c), OK);
        assert_eq!(fmu.get(VR_K1), Ok(0.2));
        assert_eq!(fmu.get(VR_X), Ok(0.0));
        assert_eq!(fmi2ExitInitializationMode(fmu.c), OK);
    }
    assert_eq!(
        bits(&fmu.run(&xs)),
        bits(&core_run(Hysteresis::new(0.2, 8.0).unwrap(), &xs))
    );
}

// ------------------------------------------------------------------------------------------
// Refused samples.

#[test]
fn a_non_finite_input_is_refused_and_changes_nothing() {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::started(dir.path());
    let xs: Vec<f64> = (0..900).map(signal).collect();
    let reference = core_run(Hysteresis::new(0.2, 8.0).unwrap(), &xs);
    let mut ys = fmu.run(&xs[..450]);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(fmu.set(VR_X, bad), OK);
        assert_eq!(fmu.get(VR_Y), Err(ERROR));
        fmu.expect_error(&["fmi2GetReal", "y", "not finite"]);
        assert_eq!(fmu.do_step(), ERROR);
        fmu.expect_error(&["fmi2DoStep", "not finite"]);
    }
    ys.extend(fmu.run(&xs[450..]));
    assert_eq!(bits(&ys), bits(&reference));
    // A model, before and after its first step.
    let file = pi_model();
    let dir = model_resources(&file, false);
    let fmu = Fmu::started(dir.path());
    assert_eq!(fmu.set(VR_X, f64::NAN), OK);
    assert_eq!(fmu.get(VR_Y), Err(ERROR));
    assert_eq!(fmu.do_step(), ERROR);
    assert_eq!(fmu.errors().len(), 2);
    assert_eq!(bits(&fmu.run(&xs)), bits(&evaluator_run(&file, false, &xs)));
}

#[test]
fn a_desired_output_beyond_saturation_is_refused_and_changes_nothing() {
    let file = saturating_model();
    let dir = model_resources(&file, true);
    let fmu = Fmu::started(dir.path());
    let desired: Vec<f64> = (0..700).map(|k| 1.5 * signal(k) / 1.3).collect();
    assert!(desired.iter().all(|y| y.abs() < 2.0));
    // Refused at the first step: the evaluator cannot start at 3 (tanh's range is (-2, 2)).
    assert_eq!(fmu.set(VR_X, 3.0), OK);
    assert_eq!(fmu.get(VR_Y), Err(ERROR));
    fmu.expect_error(&["fmi2GetReal", "x = 3"]);
    assert_eq!(fmu.do_step(), ERROR);
    fmu.expect_error(&["fmi2DoStep", "x = 3"]);
    let mut ys = fmu.run(&desired[..300]);
    assert_eq!(fmu.set(VR_X, -2.5), OK);
    assert_eq!(fmu.do_step(), ERROR);
    fmu.expect_error(&["fmi2DoStep", "-2.5", "tanh"]);
    ys.extend(fmu.run(&desired[300..]));
    assert_eq!(bits(&ys), bits(&evaluator_run(&file, true, &desired)));
}

#[test]
fn saturate_clamps_desired_outputs_and_warns_when_saturation_starts() {
    let file = saturating_model();
    let limits = file.saturation().unwrap().limits;
    let dir = tempfile::tempdir().unwrap();
    write_config(
        dir.path(),
        &format!("{}saturate = true\n", model_config(true)),
    );
    std::fs::write(dir.path().join("model.toml"), file.to_toml().unwrap()).unwrap();
    let fmu = Fmu::started(dir.path());
    // Starts beyond the range (tanh's is (-2, 2)): clamped, with a warning, and run.
    let desired: Vec<f64> = [3.0, 2.5, 1.0, 0.2]
        .into_iter()
        .chain((0..300).map(|k| 1.5 * signal(k) / 1.3))
        .chain([-2.0, -7.0, -1.5, 1.9, 2.0])
        .collect();
    let mut ys = Vec::new();
    let mut warnings = Vec::new();
    for (k, x) in desired.iter().enumerate() {
        assert_eq!(fmu.set(VR_X, *x), OK);
        let y = fmu.y();
        let status = fmu.do_step();
        let clamped = x.clamp(limits.0, limits.1) != *x;
        let entering =
            clamped && (k == 0 || desired[k - 1].clamp(limits.0, limits.1) == desired[k - 1]);
        assert_eq!(status, if entering { WARNING } else { OK }, "x = {x}");
        if status == WARNING {
            fmu.time.set(fmu.time.get() + 0.01);
        }
        assert_eq!(fmu.y().to_bits(), y.to_bits());
        ys.push(y);
        let log = fmu.log.take();
        assert!(log.iter().all(|l| l.status != ERROR as c_int), "{log:?}");
        warnings.extend(log.into_iter().filter(|l| l.status == WARNING as c_int));
    }
    // A warning where saturation starts (3.0, -2.0), none while it lasts (2.5, -7.0).
    assert_eq!(warnings.len(), 3, "{warnings:?}");
    assert!(warnings.iter().all(|w| w.category == "logStatusWarning"));
    for part in ["fmi2DoStep", "x = 3", "tanh", "clamped to"] {
        assert!(
            warnings[0].message.contains(part),
            "{:?} lacks {part}",
            warnings[0]
        );
    }
    // The outputs are the evaluator's for the clamped desired outputs.
    let clamped: Vec<f64> = desired
        .iter()
        .map(|x| x.clamp(limits.0, limits.1))
        .collect();
    assert_eq!(bits(&ys), bits(&evaluator_run(&file, true, &clamped)));
}

// ------------------------------------------------------------------------------------------
// FMU states.

/// Saves the state after `xs[..split]`, runs the rest, restores and runs it again, then
/// serialises the state, reads it into `other` (another instance of the same FMU, in step mode)
/// and runs the rest there: the three runs are the same bits.
fn check_state_round_trip(fmu: &Fmu, other: &Fmu, xs: &[f64], split: usize) {
    fmu.run(&xs[..split]);
    let saved = fmu.get_state();
    let first = fmu.run(&xs[split..]);
    assert_eq!(fmu.set_state(saved), OK);
    assert_eq!(fmu.get(VR_X), Ok(xs[split - 1]));
    assert_eq!(bits(&fmu.run(&xs[split..])), bits(&first));
    let bytes = fmu.serialize(saved);
    other.run(&xs[..17]); // whatever it did before is replaced
    let restored = other.deserialize(&bytes).unwrap();
    assert_eq!(other.set_state(restored), OK);
    assert_eq!(bits(&other.run(&xs[split..])), bits(&first));
    // The same state serialises to the same bytes in the other instance.
    assert_eq!(other.serialize(restored), bytes);
    // fmi2GetFMUstate into an existing state overwrites it.
    let mut handle = saved;
    assert_eq!(unsafe { fmi2GetFMUstate(fmu.c, &mut handle) }, OK);
    assert_eq!(handle, saved);
    assert_ne!(fmu.serialize(saved), bytes);
    // Freed: NULL, and no longer accepted.
    let mut handle = saved;
    assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut handle) }, OK);
    assert!(handle.is_null());
    assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut handle) }, OK); // NULL is ignored
    assert_eq!(fmu.set_state(saved), ERROR);
    fmu.expect_error(&["fmi2SetFMUstate", "not one of this instance"]);
    // A state of another instance is not accepted either (it is never dereferenced).
    assert_eq!(fmu.set_state(restored), ERROR);
    fmu.expect_error(&["not one of this instance"]);
    assert!(other.errors().is_empty());
}

#[test]
fn fmu_states_and_their_serialisation_resume_bit_for_bit() {
    let xs: Vec<f64> = (0..1200).map(signal).collect();
    for inverse in [false, true] {
        let dir = operator_resources(inverse, 0.2, 8.0);
        let (a, b) = (Fmu::started(dir.path()), Fmu::started(dir.path()));
        check_state_round_trip(&a, &b, &xs, 613);
    }
    for file in [fitted_model(), pi_model()] {
        for inverse in [false, true] {
            let dir = model_resources(&file, inverse);
            let (a, b) = (Fmu::started(dir.path()), Fmu::started(dir.path()));
            check_state_round_trip(&a, &b, &xs, 613);
        }
    }
}

#[test]
fn states_before_the_first_step_and_across_modes() {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::instantiate(dir.path());
    // A state of the Instantiated mode, with a parameter set, restores k1 and x.
    assert_eq!(fmu.set(VR_K1, 0.35), OK);
    assert_eq!(fmu.set(VR_X, 0.5), OK);
    let early = fmu.get_state();
    let early_bytes = fmu.serialize(early);
    assert_eq!(fmu.set(VR_K1, 0.9), OK);
    assert_eq!(fmu.set_state(early), OK);
    fmu.initialise();
    assert_eq!(fmu.get(VR_K1), Ok(0.35));
    let xs: Vec<f64> = (0..300).map(signal).collect();
    let ys = fmu.run(&xs);
    assert_eq!(
        bits(&ys),
        bits(&core_run(Hysteresis::new(0.35, 8.0).unwrap(), &xs))
    );
    let late = fmu.get_state();
    let late_bytes = fmu.serialize(late);
    // In step mode, the early state (no history) starts over.
    assert_eq!(fmu.set_state(early), OK);
    assert_eq!(bits(&fmu.run(&xs)), bits(&ys));
    // A fresh instance in Instantiated reads the late state but cannot restore a history yet.
    let other = Fmu::instantiate(dir.path());
    let late_other = other.deserialize(&late_bytes).unwrap();
    assert_eq!(other.set_state(late_other), ERROR);
    other.expect_error(&["fmi2SetFMUstate", "history", "Instantiated"]);
    let early_other = other.deserialize(&early_bytes).unwrap();
    assert_eq!(other.set_state(early_other), OK);
    other.initialise();
    assert_eq!(other.set_state(late_other), OK);
    let more: Vec<f64> = (300..600).map(signal).collect();
    let all: Vec<f64> = xs.iter().chain(&more).copied().collect();
    let reference = core_run(Hysteresis::new(0.35, 8.0).unwrap(), &all);
    assert_eq!(bits(&other.run(&more)), bits(&reference[300..]));
    // A state with a NaN input lives in memory but is not serialised.
    assert_eq!(fmu.set(VR_X, f64::NAN), OK);
    let nan = fmu.get_state();
    let mut size = 0;
    assert_eq!(
        unsafe { fmi2SerializedFMUstateSize(fmu.c, nan, &mut size) },
        ERROR
    );
    fmu.expect_error(&["cannot be serialised", "x = NaN"]);
    assert_eq!(fmu.set_state(late), OK);
    assert_eq!(bits(&fmu.run(&more)), bits(&reference[300..]));
}

/// Re-seals edited bytes with a correct checksum (so the deeper checks are reached).
fn reseal(bytes: &mut [u8]) {
    let n = bytes.len() - 8;
    let sum = fnv1a64(&bytes[..n]);
    bytes[n..].copy_from_slice(&sum.to_le_bytes());
}

fn with_f64(bytes: &[u8], offset: usize, value: f64) -> Vec<u8> {
    let mut b = bytes.to_vec();
    b[offset..offset + 8].copy_from_slice(&value.to_le_bytes());
    reseal(&mut b);
    b
}

#[test]
fn corrupted_serialised_states_are_refused() {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::started(dir.path());
    let xs: Vec<f64> = (0..800).map(signal).collect();
    fmu.run(&xs[..400]);
    let state = fmu.get_state();
    let bytes = fmu.serialize(state);
    // Layout (see hyst_fmu::state): header 24, x 24, time 32, k1 40, k2 48, memory 56:
    // reversal input 56, reversal output 64, last input 72, last output 80, direction 88;
    // checksum 89..97.
    assert_eq!(bytes.len(), 97);
    assert_eq!(&bytes[..8], b"hystFMUs");
    assert_eq!(
        f64::from_le_bytes(bytes[24..32].try_into().unwrap()),
        xs[399]
    );
    assert_eq!(f64::from_le_bytes(bytes[40..48].try_into().unwrap()), 0.2);
    let last_input = f64::from_le_bytes(bytes[72..80].try_into().unwrap());
    assert_eq!(last_input, xs[399]);
    let refuse = |b: &[u8], parts: &[&str]| {
        assert_eq!(fmu.deserialize(b), Err(ERROR));
        fmu.expect_error(&[&["fmi2DeSerializeFMUstate"][..], parts].concat());
    };
    // Every truncation, and one byte more.
    for n in 0..bytes.len() {
        assert_eq!(fmu.deserialize(&bytes[..n]), Err(ERROR), "{n} bytes");
    }
    fmu.errors();
    let mut longer = bytes.clone();
    longer.insert(90, 0);
    reseal(&mut longer);
    refuse(&longer, &["length"]);
    let mut b = bytes.clone();
    b[0] = b'X';
    refuse(&b, &["magic"]);
    let mut b = bytes.clone();
    b[8..12].copy_from_slice(&2u32.to_le_bytes());
    reseal(&mut b);
    refuse(&b, &["version 2"]);
    let mut b = bytes.clone();
    b[60] ^= 0x10;
    refuse(&b, &["checksum"]);
    let mut b = bytes.clone();
    b[12] ^= 1;
    reseal(&mut b);
    refuse(&b, &["another FMU"]);
    let mut b = bytes.clone();
    b[20] = 1;
    reseal(&mut b);
    refuse(&b, &["kind"]);
    let mut b = bytes.clone();
    b[21] = 1;
    reseal(&mut b);
    refuse(&b, &["inverse"]);
    let mut b = bytes.clone();
    b[88] = 2;
    reseal(&mut b);
    refuse(&b, &["direction = 2"]);
    refuse(&with_f64(&bytes, 24, f64::NAN), &["x = NaN"]);
    refuse(&with_f64(&bytes, 56, f64::NAN), &["reversal input = NaN"]);
    refuse(&with_f64(&bytes, 32, f64::INFINITY), &["time = inf"]);
    refuse(&with_f64(&bytes, 40, -0.2), &["k1 = -0.2"]);
    // A memory outside the band |output - input| <= k1, refused by the core's set_memory.
    refuse(
        &with_f64(&bytes, 80, last_input + 0.5),
        &["outside the band"],
    );
    // A PI state in the operator FMU.
    let file = pi_model();
    let pi_dir = model_resources(&file, false);
    let pi = Fmu::started(pi_dir.path());
    pi.run(&xs[..50]);
    let pi_state = pi.get_state();
    let pi_bytes = pi.serialize(pi_state);
    refuse(&pi_bytes, &["kind"]);
    // And a NaN play in the PI FMU: the plays start after x, time, first (24 + 24) and n (4).
    assert_eq!(
        pi.deserialize(&with_f64(&pi_bytes, 52, f64::NAN)),
        Err(ERROR)
    );
    pi.expect_error(&["play output = NaN"]);
    assert!(pi.deserialize(&pi_bytes).is_ok());
    // Nothing of this changed the instance.
    let ys = fmu.run(&xs[400..]);
    let reference = core_run(Hysteresis::new(0.2, 8.0).unwrap(), &xs);
    assert_eq!(bits(&ys), bits(&reference[400..]));
    assert!(fmu.deserialize(&bytes).is_ok());
    // NULL pointers.
    unsafe {
        assert_eq!(
            fmi2DeSerializeFMUstate(fmu.c, bytes.as_ptr().cast(), bytes.len(), ptr::null_mut()),
            ERROR
        );
        let mut s: fmi2FMUstate = ptr::null_mut();
        assert_eq!(
            fmi2DeSerializeFMUstate(fmu.c, ptr::null(), 97, &mut s),
            ERROR
        );
        assert_eq!(
            fmi2SerializeFMUstate(fmu.c, state, ptr::null_mut(), 97),
            ERROR
        );
        let mut small = [0 as fmi2Byte; 96];
        assert_eq!(
            fmi2SerializeFMUstate(fmu.c, state, small.as_mut_ptr(), 96),
            ERROR
        );
        assert_eq!(
            fmi2SerializedFMUstateSize(fmu.c, state, ptr::null_mut()),
            ERROR
        );
        assert_eq!(fmi2GetFMUstate(fmu.c, ptr::null_mut()), ERROR);
        let mut foreign = 0x1000 as fmi2FMUstate;
        assert_eq!(fmi2GetFMUstate(fmu.c, &mut foreign), ERROR);
    }
    let errors = fmu.errors();
    assert_eq!(errors.len(), 7, "{errors:?}");
}

// ------------------------------------------------------------------------------------------
// Instantiation.

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
fn refused(location: &str, guid: &str, fmu_type: fmi2Type, parts: &[&str]) {
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

// ------------------------------------------------------------------------------------------
// Models with dynamics or a rate term: each communication step size is the direct model's time
// step to the next sample (the first its nominal step); the inverse is Lemma 5.1's
// compensator, with the desired output's derivatives as the inputs x_d1 … x_dn.

/// The dynamics and rate sections the timed tests append to a model file.
const DYNAMICS_2: &str = "[dynamics]\nb = 1.0\na = [0.05, 0.001]\n";
const RATE: &str = "[rate]\nc = 0.3\n";

/// A sample period that is exact in binary (2⁻¹⁰ s), so `hyst run`'s mean step equals it.
const H: f64 = 1.0 / 1024.0;

/// `fitted_model()` as a version-4 file with `sections` appended: its text and the model as
/// `ModelFile::read` reads it.
fn timed_model(sections: &str) -> (String, ModelFile) {
    let text = fitted_model().to_toml().unwrap();
    assert!(text.contains("\nversion = 1\n"), "{text}");
    // A hold other than the first-order one needs version 5.
    let version = if sections.contains("hold") { 5 } else { 4 };
    let text =
        text.replacen("\nversion = 1\n", &format!("\nversion = {version}\n"), 1) + "\n" + sections;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("timed.toml");
    std::fs::write(&path, &text).unwrap();
    let file = ModelFile::read(&path).unwrap();
    assert!(file.smooth.as_ref().unwrap().is_timed());
    (text, file)
}

fn timed_resources(text: &str, inverse: bool) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write_config(dir.path(), &model_config(inverse));
    std::fs::write(dir.path().join("model.toml"), text).unwrap();
    dir
}

/// `TimedRun` over `xs` at the period `h`, as `hyst run --model` runs a timed record.
fn timed_run(file: &ModelFile, h: f64, xs: &[f64]) -> Vec<f64> {
    let smooth = file.smooth.as_ref().unwrap();
    let mut run = hyst_model::TimedRun::new(smooth, h, xs[0]).unwrap();
    xs.iter().map(|x| run.step(*x).unwrap().y).collect()
}

/// A smooth desired output and its first two time derivatives at sample k (period H).
fn desired(k: usize) -> [f64; 3] {
    let (t, w, a) = (k as f64 * H, 2.0 * std::f64::consts::PI * 3.0, 0.5);
    [
        1.0 + a * (w * t).sin(),
        a * w * (w * t).cos(),
        -a * w * w * (w * t).sin(),
    ]
}

/// One communication step of a timed model: set x, read y, step, read y again (`Fmu::step`:
/// the same bits, the output at the communication point held).
fn timed_step(fmu: &Fmu, x: f64) -> f64 {
    fmu.step(x)
}

fn timed_steps(fmu: &Fmu, xs: &[f64]) -> Vec<f64> {
    xs.iter().map(|x| timed_step(fmu, *x)).collect()
}

#[test]
fn a_timed_model_runs_as_timed_run_bit_for_bit() {
    let xs: Vec<f64> = (0..2500).map(signal).collect();
    let both = format!("{DYNAMICS_2}{RATE}");
    for sections in [DYNAMICS_2, RATE, both.as_str()] {
        let (text, file) = timed_model(sections);
        let dir = timed_resources(&text, false);
        let fmu = Fmu::started(dir.path());
        fmu.step_size.set(H);
        // y before the first fmi2DoStep (the period not fixed yet) is the first doStep's.
        assert_eq!(fmu.set(VR_X, xs[0]), OK);
        let before = fmu.y();
        let ys = timed_steps(&fmu, &xs);
        let reference = timed_run(&file, H, &xs);
        // y after the last doStep is the last sample's, held; x set again (the same value)
        // is the next sample's, for x held there (the plant moved on).
        assert_eq!(fmu.y().to_bits(), reference[xs.len() - 1].to_bits());
        let held: Vec<f64> = xs.iter().chain(xs.last()).copied().collect();
        assert_eq!(fmu.set(VR_X, xs[xs.len() - 1]), OK);
        let next = timed_run(&file, H, &held)[xs.len()];
        assert_eq!(fmu.y().to_bits(), next.to_bits());
        assert_ne!(
            next.to_bits(),
            reference[xs.len() - 1].to_bits(),
            "{sections}"
        );
        assert_eq!(before.to_bits(), reference[0].to_bits(), "{sections}");
        assert_eq!(bits(&ys), bits(&reference), "{sections}");
        // The plant or the rate term matters: the static model gives other outputs.
        assert_ne!(bits(&ys), bits(&evaluator_run(&fitted_model(), false, &xs)));
        assert!(fmu.errors().is_empty());
    }
}

/// Time stamps with steps of H, 2H, 3H, 2H over and over (exact in binary): their mean step is
/// 2H, and the first H.
fn uneven_stamps(n: usize) -> Vec<f64> {
    let mut t = vec![0.0];
    for k in 1..n {
        t.push(t[k - 1] + H * [1.0, 2.0, 3.0, 2.0][(k - 1) % 4]);
    }
    t
}

/// What `hyst run --model` (and Python's `Model.process(x, t=...)`) computes on a record with
/// the time stamps `t`: the record cut at its gaps, each part run at its measured steps.
fn timed_run_at(file: &ModelFile, t: &[f64], xs: &[f64]) -> Vec<f64> {
    let smooth = file.smooth.as_ref().unwrap();
    let (parts, _) = hyst_model::time::split(t).unwrap();
    let mut y = Vec::new();
    for (range, steps) in parts {
        smooth
            .run_timed(&xs[range], Some(&steps), None, |_, s| y.push(s.y))
            .unwrap();
    }
    y
}

#[test]
fn varying_steps_run_as_hyst_run_at_the_same_stamps() {
    let n = 2001;
    let xs: Vec<f64> = (0..n).map(signal).collect();
    let t = uneven_stamps(n);
    let both = format!("{DYNAMICS_2}{RATE}");
    let zoh = format!("{DYNAMICS_2}hold = \"zoh\"\n");
    for sections in [DYNAMICS_2, RATE, both.as_str(), zoh.as_str()] {
        let (text, file) = timed_model(sections);
        let dir = timed_resources(&text, false);
        let fmu = Fmu::started(dir.path());
        // Each fmi2DoStep's size is the step from its sample to the next.
        let mut ys = Vec::new();
        for k in 0..n {
            let next = t.get(k + 1).map_or(H, |after| after - t[k]);
            fmu.step_size.set(next);
            ys.push(timed_step(&fmu, xs[k]));
        }
        let reference = timed_run_at(&file, &t, &xs);
        assert_eq!(bits(&ys), bits(&reference), "{sections}");
        // The steps matter: the record at its mean step gives other outputs.
        assert_ne!(
            bits(&ys),
            bits(&timed_run(&file, 2.0 * H, &xs)),
            "{sections}"
        );
        assert!(fmu.errors().is_empty(), "{sections}");
    }
}

#[test]
fn a_zero_step_is_refused_for_a_timed_model() {
    let xs: Vec<f64> = (0..400).map(signal).collect();
    let (text, file) = timed_model(DYNAMICS_2);
    let reference = timed_run(&file, H, &xs);
    let dir = timed_resources(&text, false);
    let fmu = Fmu::started(dir.path());
    // A first step of 0 cannot be the sample period.
    fmu.step_size.set(0.0);
    assert_eq!(fmu.set(VR_X, xs[0]), OK);
    assert_eq!(fmu.do_step(), ERROR);
    fmu.expect_error(&["fmi2DoStep", "communicationStepSize = 0", "must be > 0"]);
    fmu.step_size.set(H);
    let mut ys = timed_steps(&fmu, &xs[..200]);
    // A step of 0 or below: refused, naming it; nothing changes.
    for factor in [0.0, -1.0] {
        fmu.step_size.set(H * factor);
        assert_eq!(fmu.set(VR_X, xs[200]), OK);
        assert_eq!(fmu.do_step(), ERROR, "{factor}");
        let step = format!("communicationStepSize = {}", H * factor);
        fmu.expect_error(&["fmi2DoStep", &step]);
    }
    fmu.step_size.set(H);
    ys.extend(timed_steps(&fmu, &xs[200..]));
    assert_eq!(bits(&ys), bits(&reference));
    // fmi2Reset forgets the period: the next first step fixes another one.
    assert_eq!(unsafe { fmi2Reset(fmu.c) }, OK);
    fmu.initialise();
    fmu.step_size.set(2.0 * H);
    let ys = timed_steps(&fmu, &xs);
    assert_eq!(bits(&ys), bits(&timed_run(&file, 2.0 * H, &xs)));
    assert!(fmu.errors().is_empty());
    // The inverse (the compensator) takes the derivatives as inputs: any steps are fine.
    let inverse = Fmu::started(timed_resources(&text, true).path());
    for (k, h) in [H, 3.0 * H, 0.0, 0.5 * H].into_iter().enumerate() {
        inverse.step_size.set(h);
        let d = desired(k);
        assert_eq!(inverse.set(VR_X, d[0]), OK);
        assert_eq!(inverse.do_step(), OK);
    }
}

#[test]
fn the_inverse_of_a_timed_model_is_its_compensator_with_derivative_inputs() {
    let (text, file) = timed_model(DYNAMICS_2);
    let dir = timed_resources(&text, true);
    let fmu = Fmu::started(dir.path());
    fmu.step_size.set(H);
    let smooth = file.smooth.as_ref().unwrap();
    let mut compensator = hyst_model::TimedCompensator::new(smooth, desired(0)[0]).unwrap();
    let mut commands = Vec::new();
    for k in 0..3000 {
        let d = desired(k);
        let vrs = [VR_X, 2, 3];
        assert_eq!(
            unsafe { fmi2SetReal(fmu.c, vrs.as_ptr(), 3, d.as_ptr()) },
            OK
        );
        let y = fmu.y();
        assert_eq!(fmu.do_step(), OK);
        let (u, _) = compensator.step(&d).unwrap();
        assert_eq!(y.to_bits(), u.to_bits(), "sample {k}");
        commands.push(u);
    }
    // The command drives the plant and the hysteresis along the desired output (once the
    // start, at rest, has settled).
    let ys = timed_run(&file, H, &commands);
    let worst = (1000..3000)
        .map(|k| (ys[k] - desired(k)[0]).abs())
        .fold(0.0, f64::max);
    assert!(worst < 5e-3, "{worst}"); // 1.4e-3 here: a sanity check, the bits are checked above
                                      // The derivatives read back; there are exactly n = 2 of them.
    assert_eq!(fmu.get(2), Ok(desired(2999)[1]));
    assert_eq!(fmu.get(3), Ok(desired(2999)[2]));
    assert_eq!(fmu.get(4), Err(ERROR));
    fmu.expect_error(&["value reference 4"]);
    assert_eq!(fmu.set(4, 1.0), ERROR);
    fmu.expect_error(&["value reference 4"]);
    // A non-finite derivative is refused and changes nothing.
    assert_eq!(fmu.set(3, f64::NAN), OK);
    assert_eq!(fmu.do_step(), ERROR);
    fmu.expect_error(&["fmi2DoStep", "x_d2 = NaN"]);
    // The direct FMU of the same model has no derivative inputs.
    let direct = Fmu::started(timed_resources(&text, false).path());
    assert_eq!(direct.set(2, 1.0), ERROR);
    direct.expect_error(&["value reference 2"]);
}

#[test]
fn timed_states_are_restored_in_memory_and_not_serialised() {
    let xs: Vec<f64> = (0..800).map(signal).collect();
    for inverse in [false, true] {
        let (text, _) = timed_model(DYNAMICS_2);
        let dir = timed_resources(&text, inverse);
        let fmu = Fmu::started(dir.path());
        fmu.step_size.set(H);
        let drive = |range: std::ops::Range<usize>| -> Vec<f64> {
            range
                .map(|k| {
                    let d = if inverse {
                        desired(k)
                    } else {
                        [xs[k], 0.0, 0.0]
                    };
                    if inverse {
                        assert_eq!(fmu.set(2, d[1]), OK);
                        assert_eq!(fmu.set(3, d[2]), OK);
                    }
                    timed_step(&fmu, d[0])
                })
                .collect()
        };
        drive(0..400);
        let saved = fmu.get_state();
        let first = drive(400..800);
        assert_eq!(fmu.set_state(saved), OK);
        assert_eq!(bits(&drive(400..800)), bits(&first), "inverse = {inverse}");
        let mut size = 0;
        assert_eq!(
            unsafe { fmi2SerializedFMUstateSize(fmu.c, saved, &mut size) },
            ERROR
        );
        fmu.expect_error(&["dynamics of order 2", "not serialised"]);
        let bytes = vec![0u8; 64];
        assert_eq!(fmu.deserialize(&bytes), Err(ERROR));
        fmu.expect_error(&["fmi2DeSerializeFMUstate", "not serialised"]);
    }
}

/// What the FMU cannot run is refused at instantiation (NULL, and the reason logged): the
/// inverse of a model without a compensator (a rate term), and saturate with a timed model.
#[test]
fn a_timed_model_without_a_compensator_is_refused_as_an_inverse() {
    let both = format!("{DYNAMICS_2}{RATE}");
    for (sections, what) in [
        (RATE, "a rate term"),
        (both.as_str(), "dynamics of order 2 and a rate term"),
    ] {
        let (text, _) = timed_model(sections);
        let dir = timed_resources(&text, true);
        refused(
            &uri(dir.path()),
            GUID,
            fmi2CoSimulation,
            &["fmi2Instantiate", "model.toml", what, "inverse"],
        );
        // Its direct model runs.
        Fmu::started(timed_resources(&text, false).path());
    }
    let (text, _) = timed_model(DYNAMICS_2);
    let dir = timed_resources(&text, true);
    let config = model_config(true) + "saturate = true\n";
    write_config(dir.path(), &config);
    refused(
        &uri(dir.path()),
        GUID,
        fmi2CoSimulation,
        &[
            "fmi2Instantiate",
            "model.toml",
            "saturate",
            "dynamics of order 2",
        ],
    );
}

/// One communication point as fmuCheck steps it: set the inputs (x, then x_d1 … of a
/// compensator), read y, fmi2DoStep, read y again. Returns y read before the step, and the
/// samples where the read after it differed.
fn read_twice(fmu: &Fmu, inputs: &[Vec<f64>]) -> (Vec<f64>, Vec<usize>) {
    let mut ys = Vec::new();
    let mut changed = Vec::new();
    for (k, sample) in inputs.iter().enumerate() {
        let vrs: Vec<u32> = (0..sample.len())
            .map(|i| if i == 0 { VR_X } else { VR_Y + i as u32 })
            .collect();
        let status = unsafe { fmi2SetReal(fmu.c, vrs.as_ptr(), vrs.len(), sample.as_ptr()) };
        assert_eq!(status, OK);
        let y = fmu.y();
        assert_eq!(fmu.do_step(), OK);
        if fmu.y().to_bits() != y.to_bits() {
            changed.push(k);
        }
        ys.push(y);
    }
    (ys, changed)
}

/// An FMU to step: its name, its resources, the inputs of each sample (x, then x_d1 …) and
/// the outputs `hyst run` gives for them.
type Kind = (String, tempfile::TempDir, Vec<Vec<f64>>, Vec<f64>);

/// Every kind of FMU: y is the output at the communication point, for the inputs set there.
/// fmi2DoStep commits that sample once, and y read after it (before the next inputs are set)
/// is the same output, bit for bit; both equal the run of the same samples (`hyst run`).
#[test]
fn y_read_before_and_after_do_step_is_the_same_output_for_every_kind() {
    let xs: Vec<f64> = (0..3000).map(signal).collect();
    let plain: Vec<Vec<f64>> = xs.iter().map(|x| vec![*x]).collect();
    let mut kinds: Vec<Kind> = Vec::new();
    for inverse in [false, true] {
        let reference = if inverse {
            core_run(InverseHysteresis::new(0.2, 8.0).unwrap(), &xs)
        } else {
            core_run(Hysteresis::new(0.2, 8.0).unwrap(), &xs)
        };
        let dir = operator_resources(inverse, 0.2, 8.0);
        kinds.push((
            format!("operator, inverse {inverse}"),
            dir,
            plain.clone(),
            reference,
        ));
        let file = fitted_model();
        let input: Vec<f64> = if inverse {
            xs.iter().map(|x| 3.0 * x + 1.0).collect()
        } else {
            xs.clone()
        };
        let reference = evaluator_run(&file, inverse, &input);
        let inputs = input.iter().map(|x| vec![*x]).collect();
        let dir = model_resources(&file, inverse);
        kinds.push((format!("model, inverse {inverse}"), dir, inputs, reference));
    }
    let both = format!("{DYNAMICS_2}{RATE}");
    let (text, file) = timed_model(&both);
    let reference = timed_run(&file, H, &xs);
    kinds.push((
        "timed model".into(),
        timed_resources(&text, false),
        plain,
        reference,
    ));
    let (text, file) = timed_model(DYNAMICS_2);
    let smooth = file.smooth.as_ref().unwrap();
    let mut compensator = hyst_model::TimedCompensator::new(smooth, desired(0)[0]).unwrap();
    let inputs: Vec<Vec<f64>> = (0..3000).map(|k| desired(k).to_vec()).collect();
    let reference = inputs
        .iter()
        .map(|d| compensator.step(d).unwrap().0)
        .collect();
    kinds.push((
        "compensator".into(),
        timed_resources(&text, true),
        inputs,
        reference,
    ));
    let mut changed_by_a_step = Vec::new();
    for (name, dir, inputs, reference) in kinds {
        let fmu = Fmu::started(dir.path());
        fmu.step_size.set(H);
        let (ys, changed) = read_twice(&fmu, &inputs);
        // A saved state keeps the held output: another x set and read, the state restored, y
        // is the last sample's again.
        let saved = fmu.get_state();
        assert_eq!(fmu.set(VR_X, inputs[0][0] + 0.25), OK);
        assert_ne!(fmu.y().to_bits(), ys[ys.len() - 1].to_bits(), "{name}");
        assert_eq!(fmu.set_state(saved), OK);
        assert_eq!(fmu.y().to_bits(), ys[ys.len() - 1].to_bits(), "{name}");
        println!(
            "{name}: y changed by fmi2DoStep at {} of {} samples",
            changed.len(),
            ys.len()
        );
        changed_by_a_step.push((name.clone(), changed.len()));
        assert_eq!(bits(&ys), bits(&reference), "{name}");
        assert!(fmu.errors().is_empty(), "{name}");
    }
    assert!(
        changed_by_a_step.iter().all(|(_, n)| *n == 0),
        "{changed_by_a_step:?}"
    );
}

/// The compensator of a model whose loop's corners the communication step does not resolve
/// (k2 = 1000: the desired output crosses a corner in 3.2e-4 s, steps of 2⁻¹⁰ s) warns once,
/// with the step it needs, and computes the commands all the same; at k2 = 6 it does not warn.
#[test]
fn a_compensator_warns_once_when_the_step_cannot_resolve_the_loops_corners() {
    let (text, _) = timed_model(DYNAMICS_2);
    let constant = "law = \"constant\"\nvalue = 6.0\n";
    assert!(text.contains(constant), "{text}");
    let sharp = text.replace(constant, "law = \"constant\"\nvalue = 1000.0\n");
    for (text, warns) in [(text.as_str(), false), (sharp.as_str(), true)] {
        let dir = timed_resources(text, true);
        let fmu = Fmu::started(dir.path());
        fmu.step_size.set(H);
        let file = ModelFile::read(&dir.path().join("model.toml")).unwrap();
        let smooth = file.smooth.as_ref().unwrap();
        let mut compensator = hyst_model::TimedCompensator::new(smooth, desired(0)[0]).unwrap();
        let mut statuses = Vec::new();
        for k in 0..600 {
            let d = desired(k);
            let vrs = [VR_X, 2, 3];
            assert_eq!(
                unsafe { fmi2SetReal(fmu.c, vrs.as_ptr(), 3, d.as_ptr()) },
                OK
            );
            let y = fmu.y();
            statuses.push(fmu.do_step());
            assert_eq!(
                y.to_bits(),
                compensator.step(&d).unwrap().0.to_bits(),
                "{k}"
            );
        }
        let warnings: Vec<Logged> = fmu
            .log
            .take()
            .into_iter()
            .filter(|l| l.status == WARNING as c_int)
            .collect();
        let warned = statuses.iter().filter(|s| **s == WARNING).count();
        assert_eq!(
            (warned, warnings.len()),
            if warns { (1, 1) } else { (0, 0) }
        );
        assert!(statuses.iter().all(|s| *s == OK || *s == WARNING));
        if warns {
            let message = &warnings[0].message;
            let corner = compensator.fastest_corner().unwrap();
            println!("{message}");
            assert!((corner.time - 3.2e-4).abs() < 0.05e-4, "{corner:?}");
            for part in [
                "fmi2DoStep: ".to_string(),
                "corner of the model's loop".to_string(),
                format!("step at most every {:.4e} s", corner.time / 3.0),
            ] {
                assert!(message.contains(&part), "{part:?} not in {message}");
            }
        }
    }
}
