//! The test's master: a logger that records the FMU's messages, the resources an instance reads
//! (configurations, model files), and `Fmu`, a small safe wrapper of one instance.

use super::*;

#[derive(Clone, Debug)]
pub(crate) struct Logged {
    pub(crate) status: c_int,
    pub(crate) category: String,
    pub(crate) message: String,
    /// The format was "%s" (the FMU must never pass its text as the format).
    pub(crate) format_is_percent_s: bool,
    pub(crate) instance: String,
}

pub(crate) type Log = RefCell<Vec<Logged>>;

/// Records a message into the `Log` the environment pointer points to.
pub(crate) unsafe extern "C" fn record(
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

pub(crate) type Record = unsafe extern "C" fn(
    *mut c_void,
    *const c_char,
    c_int,
    *const c_char,
    *const c_char,
    *const c_char,
);

pub(crate) fn logger() -> fmi2CallbackLogger {
    // SAFETY: on x86-64 System V and AArch64 Linux (this file's cfg), a variadic call passes its
    // fixed arguments and a pointer vararg in the same registers as a non-variadic call with
    // the same parameter list, and fmi2Status is an int; the FMU always passes exactly one
    // vararg (the "%s" argument), which `record` receives as its sixth parameter.
    unsafe { std::mem::transmute::<Record, fmi2CallbackLogger>(record) }
}

// ------------------------------------------------------------------------------------------
// Resources.

/// A signal with many reversals of varying amplitude.
pub(crate) fn signal(k: usize) -> f64 {
    let t = k as f64 * 0.03;
    (0.4 + 0.04 * t).min(1.3) * t.sin() + 0.25 * (2.9 * t).cos()
}

pub(crate) fn write_config(dir: &Path, body: &str) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("fmu.toml"), body).unwrap();
}

pub(crate) fn operator_config(inverse: bool, k1: f64, k2: f64) -> String {
    format!(
        "format = \"hyst-fmu\"\nversion = 1\nguid = \"{GUID}\"\nkind = \"operator\"\n\
         inverse = {inverse}\nk1 = {k1:?}\nk2 = {k2:?}\n"
    )
}

pub(crate) fn model_config(inverse: bool) -> String {
    format!(
        "format = \"hyst-fmu\"\nversion = 1\nguid = \"{GUID}\"\nkind = \"model\"\n\
         inverse = {inverse}\n"
    )
}

pub(crate) fn operator_resources(inverse: bool, k1: f64, k2: f64) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write_config(dir.path(), &operator_config(inverse, k1, k2));
    dir
}

pub(crate) fn model_file(smooth: Option<SmoothModel>, pi: Option<PiModel>) -> ModelFile {
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
pub(crate) fn fitted_model() -> ModelFile {
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
pub(crate) fn pi_model() -> ModelFile {
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
pub(crate) fn saturating_model() -> ModelFile {
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

pub(crate) fn model_resources(file: &ModelFile, inverse: bool) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write_config(dir.path(), &model_config(inverse));
    std::fs::write(dir.path().join("model.toml"), file.to_toml().unwrap()).unwrap();
    dir
}

/// `file:///…` with every byte but unreserved ones and '/' percent-encoded.
pub(crate) fn uri(dir: &Path) -> String {
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

pub(crate) struct Fmu {
    pub(crate) c: fmi2Component,
    pub(crate) log: Box<Log>,
    pub(crate) time: Cell<f64>,
    /// The communication step size of `do_step` (0.01 unless a test sets it).
    pub(crate) step_size: Cell<f64>,
}

impl Fmu {
    pub(crate) fn instantiate_with(
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

    pub(crate) fn instantiate(dir: &Path) -> Fmu {
        Self::instantiate_with(&uri(dir), GUID, fmi2CoSimulation).unwrap()
    }

    /// Instantiated, set up, initialised: in step mode.
    pub(crate) fn started(dir: &Path) -> Fmu {
        let fmu = Self::instantiate(dir);
        fmu.initialise();
        fmu
    }

    pub(crate) fn initialise(&self) {
        unsafe {
            assert_eq!(
                fmi2SetupExperiment(self.c, fmi2False, 0.0, 0.0, fmi2False, 0.0),
                OK
            );
            assert_eq!(fmi2EnterInitializationMode(self.c), OK);
            assert_eq!(fmi2ExitInitializationMode(self.c), OK);
        }
    }

    pub(crate) fn set(&self, vr: u32, value: f64) -> fmi2Status {
        unsafe { fmi2SetReal(self.c, &vr, 1, &value) }
    }

    pub(crate) fn get(&self, vr: u32) -> Result<f64, fmi2Status> {
        let mut value = f64::NAN;
        match unsafe { fmi2GetReal(self.c, &vr, 1, &mut value) } {
            OK => Ok(value),
            s => Err(s),
        }
    }

    pub(crate) fn y(&self) -> f64 {
        self.get(VR_Y).unwrap()
    }

    pub(crate) fn do_step(&self) -> fmi2Status {
        let (t, h) = (self.time.get(), self.step_size.get());
        let status = unsafe { fmi2DoStep(self.c, t, h, fmi2True) };
        if status == OK {
            self.time.set(t + h);
        }
        status
    }

    /// One communication step as a master does it: set x, read y (direct feedthrough), step,
    /// read y again (the same bits). Returns y.
    pub(crate) fn step(&self, x: f64) -> f64 {
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

    pub(crate) fn run(&self, xs: &[f64]) -> Vec<f64> {
        xs.iter().map(|x| self.step(*x)).collect()
    }

    /// The error messages logged since the last call.
    pub(crate) fn errors(&self) -> Vec<String> {
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
    pub(crate) fn expect_error(&self, parts: &[&str]) {
        let errors = self.errors();
        assert_eq!(errors.len(), 1, "{errors:?}");
        for p in parts {
            assert!(errors[0].contains(p), "{:?} lacks {p:?}", errors[0]);
        }
    }

    pub(crate) fn get_state(&self) -> fmi2FMUstate {
        let mut s: fmi2FMUstate = ptr::null_mut();
        assert_eq!(unsafe { fmi2GetFMUstate(self.c, &mut s) }, OK);
        assert!(!s.is_null());
        s
    }

    pub(crate) fn set_state(&self, s: fmi2FMUstate) -> fmi2Status {
        unsafe { fmi2SetFMUstate(self.c, s) }
    }

    pub(crate) fn serialize(&self, s: fmi2FMUstate) -> Vec<u8> {
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

    pub(crate) fn deserialize(&self, bytes: &[u8]) -> Result<fmi2FMUstate, fmi2Status> {
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

pub(crate) fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The core operator run over `xs`.
pub(crate) fn core_run<O: Operator<f64>>(mut op: O, xs: &[f64]) -> Vec<f64> {
    xs.iter().map(|x| op.try_step(*x).unwrap()).collect()
}

/// The model file's evaluator run over `xs`, started at the first sample (`hyst run --model`).
pub(crate) fn evaluator_run(file: &ModelFile, inverse: bool, xs: &[f64]) -> Vec<f64> {
    core_run(file.evaluator(xs[0], inverse).unwrap(), xs)
}
