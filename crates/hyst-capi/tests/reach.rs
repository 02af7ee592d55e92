//! A model whose output is bounded by its input shaping alone (tanh ψ_in, affine ψ_out) through
//! the host C API: a desired output out of reach is `HYST_ERR_OUT_OF_RANGE`,
//! `hyst_model_saturation` gives the figures the CLI names, and `hyst_model_saturate` clamps.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the C API through raw pointers, as a C program does.
#![allow(unsafe_code)]

use std::ffi::CString;
use std::ptr;

use hyst::host::*;
use hyst::status::*;

/// y = 10 · H(0.1, 8)[tanh(x)]: outputs in (−11, 11), limits 10 · (±0.999 ∓ 0.1) = ±8.99.
const MODEL: &str = include_str!("../../hyst-model/testdata/tanh-input.toml");

#[test]
fn a_saturating_input_shaping_bounds_the_inverse() {
    let file = std::env::temp_dir().join(format!("hyst-reach-{}.toml", std::process::id()));
    std::fs::write(&file, MODEL).unwrap();
    let path = CString::new(file.to_str().unwrap()).unwrap();
    let mut error = [0 as std::ffi::c_char; 256];
    // SAFETY: a NUL-terminated path and a writable buffer.
    let m = unsafe { hyst_model_load(path.as_ptr(), error.as_mut_ptr(), error.len()) };
    std::fs::remove_file(&file).unwrap();
    assert!(!m.is_null());
    let (mut range, mut limits) = ([0.0; 2], [0.0; 2]);
    // SAFETY: a live model, two writable pairs.
    let status = unsafe { hyst_model_saturation(m, range.as_mut_ptr(), limits.as_mut_ptr()) };
    assert_eq!(status, HYST_OK);
    assert!(
        (range[0] + 11.0).abs() < 1e-12 && (range[1] - 11.0).abs() < 1e-12,
        "{range:?}"
    );
    assert!(
        (limits[0] + 8.99).abs() < 1e-12 && (limits[1] - 8.99).abs() < 1e-12,
        "{limits:?}"
    );
    // Out of reach from the state after 8.5 (rising on the lower asymptote: below 9).
    let desired = [0.0, 5.0, 8.5, 9.5, 12.0, 3.0];
    let mut y = [f64::NAN; 6];
    // SAFETY: a live model, 6 values each.
    let status = unsafe { hyst_model_process(m, 1, desired.as_ptr(), y.as_mut_ptr(), 6) };
    assert_eq!(status, HYST_ERR_OUT_OF_RANGE);
    assert!(
        y[..3].iter().all(|u| u.is_finite()) && y[3].is_nan(),
        "{y:?}"
    );
    // Saturated: every row runs, 9.5 and 12 at the limit 8.99 (v = 0.999).
    // SAFETY: a live model.
    assert_eq!(unsafe { hyst_model_reset(m) }, HYST_OK);
    assert_eq!(unsafe { hyst_model_saturate(m, 1) }, HYST_OK);
    // SAFETY: as above.
    let status = unsafe { hyst_model_process(m, 1, desired.as_ptr(), y.as_mut_ptr(), 6) };
    assert_eq!(status, HYST_OK);
    assert!(
        (y[3] - 0.999_f64.atanh()).abs() < 1e-9 && y[4] == y[3],
        "{y:?}"
    );
    let mut count = 0_u64;
    // SAFETY: a live model and a writable count.
    assert_eq!(unsafe { hyst_model_saturated(m, &mut count) }, HYST_OK);
    assert_eq!(count, 2);
    // SAFETY: NULL pointers are refused.
    let status = unsafe { hyst_model_saturation(m, ptr::null_mut(), limits.as_mut_ptr()) };
    assert_eq!(status, HYST_ERR_NULL_POINTER);
    // SAFETY: from hyst_model_load, freed once.
    unsafe { hyst_model_free(m) };
}
