//! `hyst_model_column`: the model file's column names through the host API, as C would ask for
//! them (a buffer sized by a first call, a buffer too small, NULL pointers, a bad `which`).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the C API through raw pointers, as a C program does.
#![allow(unsafe_code)]

use std::ffi::{c_char, CStr, CString};
use std::path::{Path, PathBuf};
use std::ptr;

use hyst::host::*;
use hyst::status::*;

/// The static smooth model fixture (`[columns]` input = "x", output = "y").
const STATIC: &str = include_str!("../../hyst-model/testdata/static-model.toml");

/// A fresh folder for the test `name` (tests run in parallel threads of one process).
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hyst-capi-column-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn load(path: &Path) -> *mut hyst_model {
    let c = CString::new(path.to_str().unwrap()).unwrap();
    let mut error = [0 as c_char; 512];
    let m = unsafe { hyst_model_load(c.as_ptr(), error.as_mut_ptr(), error.len()) };
    let message = unsafe { CStr::from_ptr(error.as_ptr()) };
    assert!(!m.is_null(), "{message:?}");
    m
}

/// The fixture with its `[columns]` names replaced (TOML basic strings: `\u0000` escapes work).
fn with_columns(dir: &Path, input: &str, output: &str) -> PathBuf {
    let text = STATIC.replace(
        "[columns]\ninput = \"x\"\noutput = \"y\"\n",
        &format!("[columns]\ninput = \"{input}\"\noutput = \"{output}\"\n"),
    );
    assert_ne!(text, STATIC, "the fixture's [columns] changed");
    let path = dir.join("model.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// The name `which` through a buffer sized by a first call, as a C caller would.
fn column(m: *const hyst_model, which: i32) -> String {
    let mut needed = 0usize;
    let status = unsafe { hyst_model_column(m, which, ptr::null_mut(), 0, &mut needed) };
    assert_eq!(status, HYST_ERR_LENGTH);
    let mut name = vec![1 as c_char; needed];
    let mut again = 0usize;
    let status = unsafe { hyst_model_column(m, which, name.as_mut_ptr(), needed, &mut again) };
    assert_eq!(status, HYST_OK);
    assert_eq!(again, needed);
    let text = unsafe { CStr::from_ptr(name.as_ptr()) }.to_str().unwrap();
    assert_eq!(text.len() + 1, needed);
    text.to_string()
}

#[test]
fn a_fitted_models_column_names() {
    // A model file as `hyst fit` wrote it (the firmware example's piezo actuator).
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/firmware/models/piezo.toml");
    let m = load(&path);
    assert_eq!(column(m, HYST_COLUMN_INPUT), "u_actuator_V");
    assert_eq!(column(m, HYST_COLUMN_OUTPUT), "y_capsensor_um");
    // A roomy buffer, and no `needed`.
    let mut name = [1 as c_char; 64];
    unsafe {
        assert_eq!(
            hyst_model_column(
                m,
                HYST_COLUMN_OUTPUT,
                name.as_mut_ptr(),
                64,
                ptr::null_mut()
            ),
            HYST_OK
        );
        assert_eq!(
            CStr::from_ptr(name.as_ptr()).to_str().unwrap(),
            "y_capsensor_um"
        );
        // Exactly the size needed: the name and its NUL.
        let mut exact = [1 as c_char; 13];
        let mut needed = 0usize;
        assert_eq!(
            hyst_model_column(m, HYST_COLUMN_INPUT, exact.as_mut_ptr(), 13, &mut needed),
            HYST_OK
        );
        assert_eq!(needed, 13);
        assert_eq!(
            CStr::from_ptr(exact.as_ptr()).to_str().unwrap(),
            "u_actuator_V"
        );
        hyst_model_free(m);
    }
    // A model with dynamics (loaded with its period) has its names too.
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/firmware/models/piezo_dyn.toml");
    let c = CString::new(path.to_str().unwrap()).unwrap();
    let mut error = [0 as c_char; 512];
    let m = unsafe { hyst_model_load_timed(c.as_ptr(), 1e-3, error.as_mut_ptr(), error.len()) };
    assert!(!m.is_null());
    assert!(!column(m, HYST_COLUMN_INPUT).is_empty());
    assert!(!column(m, HYST_COLUMN_OUTPUT).is_empty());
    unsafe { hyst_model_free(m) };
}

#[test]
fn a_buffer_too_small_gets_the_name_cut_at_a_character_and_the_size_needed() {
    let dir = folder("small");
    // "B_µT": 5 bytes (µ takes 2), 6 with the NUL.
    let m = load(&with_columns(&dir, "H_A_per_m", "B_µT"));
    assert_eq!(column(m, HYST_COLUMN_OUTPUT), "B_µT");
    assert_eq!(column(m, HYST_COLUMN_INPUT), "H_A_per_m");
    unsafe {
        let mut needed = 0usize;
        // Room for "B_" and half of µ: cut before µ, NUL-terminated.
        let mut small = [1 as c_char; 4];
        assert_eq!(
            hyst_model_column(m, HYST_COLUMN_OUTPUT, small.as_mut_ptr(), 4, &mut needed),
            HYST_ERR_LENGTH
        );
        assert_eq!(needed, 6);
        assert_eq!(CStr::from_ptr(small.as_ptr()).to_str().unwrap(), "B_");
        assert_eq!(small[3], 1, "nothing written after the NUL");
        // One byte short: the whole µ fits, not the T.
        let mut short = [1 as c_char; 5];
        assert_eq!(
            hyst_model_column(m, HYST_COLUMN_OUTPUT, short.as_mut_ptr(), 5, &mut needed),
            HYST_ERR_LENGTH
        );
        assert_eq!(CStr::from_ptr(short.as_ptr()).to_str().unwrap(), "B_µ");
        // One byte: the empty string.
        let mut one = [1 as c_char; 1];
        assert_eq!(
            hyst_model_column(m, HYST_COLUMN_INPUT, one.as_mut_ptr(), 1, ptr::null_mut()),
            HYST_ERR_LENGTH
        );
        assert_eq!(one[0], 0);
        // A length of 0 writes nothing, even through a valid pointer.
        let mut none = [1 as c_char; 4];
        assert_eq!(
            hyst_model_column(m, HYST_COLUMN_INPUT, none.as_mut_ptr(), 0, &mut needed),
            HYST_ERR_LENGTH
        );
        assert_eq!(needed, 10);
        assert_eq!(none, [1; 4]);
        hyst_model_free(m);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn null_pointers_a_bad_which_and_a_name_with_a_nul_are_refused() {
    let dir = folder("refused");
    let m = load(&with_columns(&dir, "u", "y\\u0000z"));
    let mut name = [1 as c_char; 16];
    let mut needed = 7usize;
    unsafe {
        assert_eq!(
            hyst_model_column(
                ptr::null(),
                HYST_COLUMN_INPUT,
                name.as_mut_ptr(),
                16,
                &mut needed
            ),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_model_column(m, HYST_COLUMN_INPUT, ptr::null_mut(), 16, &mut needed),
            HYST_ERR_NULL_POINTER
        );
        for which in [-1, 2, i32::MAX, i32::MIN] {
            assert_eq!(
                hyst_model_column(m, which, name.as_mut_ptr(), 16, &mut needed),
                HYST_ERR_INVALID_PARAMETER
            );
        }
        // A name a C string cannot hold.
        assert_eq!(
            hyst_model_column(m, HYST_COLUMN_OUTPUT, name.as_mut_ptr(), 16, &mut needed),
            HYST_ERR_MODEL_FILE
        );
        // Nothing was written by any of them.
        assert_eq!(name, [1; 16]);
        assert_eq!(needed, 7);
        // The other name is fine.
        assert_eq!(
            hyst_model_column(m, HYST_COLUMN_INPUT, name.as_mut_ptr(), 16, &mut needed),
            HYST_OK
        );
        assert_eq!(CStr::from_ptr(name.as_ptr()).to_str().unwrap(), "u");
        assert_eq!(needed, 2);
        hyst_model_free(m);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
