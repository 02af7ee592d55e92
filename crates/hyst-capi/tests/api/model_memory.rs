//! `hyst_model_get_memory` and `hyst_model_set_memory`: a run saved after any sample resumes
//! bit for bit, in the same model or in another one loaded from the same file; impossible
//! memories and models without such a memory are refused, leaving the model unchanged.

use super::*;
use crate::operator::*;

/// The fixture with a tanh input shaping (docs/formats.md), loaded through the C API.
fn load_fixture(name: &str) -> *mut hyst_model {
    let path = format!(
        "{}/../hyst-model/testdata/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    let c = CString::new(path).unwrap();
    let mut error = [0 as std::ffi::c_char; 512];
    let m = unsafe { hyst_model_load(c.as_ptr(), error.as_mut_ptr(), error.len()) };
    let message = unsafe { CStr::from_ptr(error.as_ptr()) };
    assert!(!m.is_null(), "{message:?}");
    m
}

fn run(m: *mut hyst_model, inverse: i32, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    let status = unsafe { hyst_model_process(m, inverse, x.as_ptr(), y.as_mut_ptr(), x.len()) };
    assert_eq!(status, HYST_OK);
    y
}

fn memory_of(m: *const hyst_model, inverse: i32) -> hyst_memory {
    let mut memory: hyst_memory = zeroed();
    assert_eq!(
        unsafe { hyst_model_get_memory(m, inverse, &mut memory) },
        HYST_OK
    );
    memory
}

#[test]
fn a_saved_run_resumes_bit_for_bit_in_another_model_of_the_same_file() {
    for fixture in ["tanh-input.toml", "static-model.toml"] {
        for inverse in [0, 1] {
            let x: Vec<f64> = (0..600).map(|k| 0.6 * signal(k)).collect();
            let x = if inverse == 1 {
                // Desired outputs the model reaches: its own outputs.
                let m = load_fixture(fixture);
                let y = run(m, 0, &x);
                unsafe { hyst_model_free(m) };
                y
            } else {
                x
            };
            let whole = load_fixture(fixture);
            assert_eq!(memory_of(whole, inverse).has_history, 0, "{fixture}");
            let expected = run(whole, inverse, &x);
            for cut in [1, 137, 599] {
                let first = load_fixture(fixture);
                let mut got = run(first, inverse, &x[..cut]);
                let saved = memory_of(first, inverse);
                assert_eq!(saved.has_history, 1);
                let second = load_fixture(fixture);
                assert_eq!(
                    unsafe { hyst_model_set_memory(second, inverse, &saved) },
                    HYST_OK
                );
                assert_eq!(
                    memory_of(second, inverse),
                    saved,
                    "{fixture} {inverse} {cut}"
                );
                got.extend(run(second, inverse, &x[cut..]));
                let bits = |v: &[f64]| v.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&got),
                    bits(&expected),
                    "{fixture} inverse {inverse} cut {cut}"
                );
                unsafe {
                    hyst_model_free(first);
                    hyst_model_free(second);
                }
            }
            // No history: the run starts again from the start rule, as after a reset.
            let none = hyst_memory {
                has_history: 0,
                ..memory_of(whole, inverse)
            };
            assert_eq!(
                unsafe { hyst_model_set_memory(whole, inverse, &none) },
                HYST_OK
            );
            assert_eq!(run(whole, inverse, &x), expected);
            unsafe { hyst_model_free(whole) };
        }
    }
}

#[test]
fn impossible_memories_and_null_pointers_are_refused_without_a_change() {
    let m = load_fixture("static-model.toml");
    let x: Vec<f64> = (0..50).map(signal).collect();
    run(m, 0, &x);
    let saved = memory_of(m, 0);
    for bad in [
        hyst_memory {
            last_input: f64::NAN,
            ..saved
        },
        hyst_memory {
            direction: 0,
            ..saved
        },
        hyst_memory {
            has_history: 2,
            ..saved
        },
        hyst_memory {
            reversal_output: saved.reversal_input + 1e6,
            ..saved
        },
    ] {
        let status = unsafe { hyst_model_set_memory(m, 0, &bad) };
        assert_ne!(status, HYST_OK, "{bad:?}");
        assert_eq!(memory_of(m, 0), saved);
    }
    let mut out: hyst_memory = zeroed();
    unsafe {
        assert_eq!(
            hyst_model_get_memory(ptr::null(), 0, &mut out),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_model_get_memory(m, 0, ptr::null_mut()),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_model_set_memory(ptr::null_mut(), 0, &saved),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_model_set_memory(m, 0, ptr::null()),
            HYST_ERR_NULL_POINTER
        );
        hyst_model_free(m);
    }
}
