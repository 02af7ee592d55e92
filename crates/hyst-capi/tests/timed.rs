//! Models with dynamics or a rate term through the host API: `hyst_model_load`
//! refuses them with the reason, `hyst_model_load_timed` runs them bit for bit as
//! `hyst_model::TimedRun` and `TimedCompensator` (what `hyst run --model` runs on a timed
//! record), and every call that cannot run them says so by its status.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the C API through raw pointers, as a C program does.
#![allow(unsafe_code)]

use std::ffi::{c_char, CStr, CString};
use std::path::{Path, PathBuf};
use std::ptr;

use ::hyst_model::{ModelFile, TimedCompensator, TimedRun};
use hyst::host::*;
use hyst::status::*;

/// A static smooth model file as `hyst fit` writes it (format version 1): y = 3 H(0.2, 6)[v] + 1,
/// v = x / 2 − 1 (hyst-model's test fixture, shared with hyst-codegen's tests).
const STATIC: &str = include_str!("../../hyst-model/testdata/static-model.toml");

const FIRST_ORDER: &str = "[dynamics]\nb = 1.0\na = [0.05]\n";
const SECOND_ORDER: &str = "[dynamics]\nb = 1.0\na = [0.05, 0.0004]\n";
const RATE: &str = "[rate]\nc = 0.3\n";

/// A fresh folder for the test `name` (tests run in parallel threads of one process).
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hyst-capi-timed-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The static model with `sections` appended (format version 4 when there are any).
fn write(dir: &Path, name: &str, sections: &str) -> (PathBuf, CString) {
    let text = if sections.is_empty() {
        STATIC.to_string()
    } else {
        STATIC.replace("version = 1", "version = 4") + sections
    };
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let c = CString::new(path.to_str().unwrap()).unwrap();
    (path, c)
}

fn message(buffer: &[c_char]) -> String {
    unsafe { CStr::from_ptr(buffer.as_ptr()) }
        .to_str()
        .unwrap()
        .to_string()
}

fn load_timed(path: &CString, period: f64) -> *mut hyst_model {
    let mut error = [0 as c_char; 512];
    let m = unsafe { hyst_model_load_timed(path.as_ptr(), period, error.as_mut_ptr(), 512) };
    assert!(!m.is_null(), "{}", message(&error));
    m
}

fn input(k: usize) -> f64 {
    let t = k as f64 * 1e-3;
    2.0 + 1.5 * (7.0 * t).sin() + 0.3 * (31.0 * t).cos()
}

/// The desired output 1 + 2.4 sin(ωt) and its first two derivatives at sample k (h = 1 ms).
fn desired(k: usize) -> [f64; 3] {
    let (w, t) = (9.0, k as f64 * 1e-3);
    [
        1.0 + 2.4 * (w * t).sin(),
        2.4 * w * (w * t).cos(),
        -2.4 * w * w * (w * t).sin(),
    ]
}

#[test]
fn hyst_model_load_refuses_a_timed_model_with_the_reason() {
    let dir = folder("refused");
    let (_, plain) = write(&dir, "static.toml", "");
    let m = unsafe { hyst_model_load(plain.as_ptr(), ptr::null_mut(), 0) };
    assert!(!m.is_null());
    unsafe { hyst_model_free(m) };
    for (sections, what) in [
        (FIRST_ORDER, "dynamics of order 1"),
        (RATE, "a rate term"),
        (
            &*format!("{FIRST_ORDER}{RATE}"),
            "dynamics of order 1 and a rate term",
        ),
    ] {
        let (_, path) = write(&dir, "timed.toml", sections);
        let mut error = [0 as c_char; 512];
        let m = unsafe { hyst_model_load(path.as_ptr(), error.as_mut_ptr(), error.len()) };
        assert!(m.is_null(), "{sections}");
        let text = message(&error);
        for part in [
            "timed.toml",
            what,
            "without a sample period",
            "hyst_model_load_timed",
        ] {
            assert!(text.contains(part), "{text:?} lacks {part:?}");
        }
    }
    // A period that is not finite and positive is refused, naming it.
    let (_, path) = write(&dir, "timed.toml", FIRST_ORDER);
    for period in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let mut error = [0 as c_char; 256];
        let m = unsafe { hyst_model_load_timed(path.as_ptr(), period, error.as_mut_ptr(), 256) };
        assert!(m.is_null(), "{period}");
        assert!(message(&error).contains("sample period"), "{period}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_direct_run_equals_timed_run_in_one_block_or_many() {
    let dir = folder("direct");
    let h = 1e-3;
    let x: Vec<f64> = (0..1500).map(input).collect();
    for (name, sections) in [
        ("first.toml", FIRST_ORDER),
        ("second.toml", SECOND_ORDER),
        ("rate.toml", RATE),
        ("both.toml", &*format!("{SECOND_ORDER}{RATE}")),
    ] {
        let (path, c) = write(&dir, name, sections);
        let file = ModelFile::read(&path).unwrap();
        let smooth = file.smooth.as_ref().unwrap();
        let mut run = TimedRun::new(smooth, h, x[0]).unwrap();
        let expected: Vec<u64> = x
            .iter()
            .map(|v| run.step(*v).unwrap().y.to_bits())
            .collect();
        let m = load_timed(&c, h);
        let mut whole = vec![0.0; x.len()];
        let mut blocks = vec![0.0; x.len()];
        unsafe {
            assert_eq!(
                hyst_model_process(m, 0, x.as_ptr(), whole.as_mut_ptr(), x.len()),
                HYST_OK
            );
            assert_eq!(hyst_model_reset(m), HYST_OK);
            for (xs, ys) in x.chunks(97).zip(blocks.chunks_mut(97)) {
                assert_eq!(
                    hyst_model_process(m, 0, xs.as_ptr(), ys.as_mut_ptr(), xs.len()),
                    HYST_OK
                );
            }
            // No exact inverse, no saturation: the status says so, nothing changes.
            let mut y = [0.0];
            assert_eq!(
                hyst_model_process(m, 1, [1.0].as_ptr(), y.as_mut_ptr(), 1),
                HYST_ERR_UNSUPPORTED
            );
            assert_eq!(hyst_model_saturate(m, 1), HYST_ERR_UNSUPPORTED);
            assert_eq!(hyst_model_saturate(m, 0), HYST_OK);
            // A refused sample stops the run with its status, the run unchanged by it.
            assert_eq!(
                hyst_model_process(m, 0, [f64::NAN].as_ptr(), y.as_mut_ptr(), 1),
                HYST_ERR_NON_FINITE
            );
            assert!(!CStr::from_ptr(hyst_status_message(HYST_ERR_UNSUPPORTED))
                .to_str()
                .unwrap()
                .contains("unknown"));
            hyst_model_free(m);
        }
        assert_eq!(
            whole.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            expected,
            "{name}"
        );
        assert_eq!(whole, blocks, "{name}");
    }
    // A static model loaded with a period runs as from hyst_model_load.
    let (_, c) = write(&dir, "static.toml", "");
    let timed = load_timed(&c, h);
    let plain = unsafe { hyst_model_load(c.as_ptr(), ptr::null_mut(), 0) };
    let (mut a, mut b) = (vec![0.0; x.len()], vec![0.0; x.len()]);
    for inverse in [0, 1] {
        let xs: Vec<f64> = if inverse == 0 {
            x.clone()
        } else {
            (0..1500).map(|k| desired(k)[0]).collect()
        };
        unsafe {
            assert_eq!(
                hyst_model_process(timed, inverse, xs.as_ptr(), a.as_mut_ptr(), xs.len()),
                HYST_OK
            );
            assert_eq!(
                hyst_model_process(plain, inverse, xs.as_ptr(), b.as_mut_ptr(), xs.len()),
                HYST_OK
            );
        }
        assert_eq!(a, b);
    }
    unsafe {
        hyst_model_free(timed);
        hyst_model_free(plain);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_compensator_equals_timed_compensator() {
    let dir = folder("compensate");
    let h = 1e-3;
    let n = 1500;
    for (name, sections, order) in [
        ("first.toml", FIRST_ORDER, 1),
        ("second.toml", SECOND_ORDER, 2),
    ] {
        let (path, c) = write(&dir, name, sections);
        let file = ModelFile::read(&path).unwrap();
        let rows: Vec<f64> = (0..n).flat_map(|k| desired(k)[..=order].to_vec()).collect();
        let mut core = TimedCompensator::new(file.smooth.as_ref().unwrap(), rows[0]).unwrap();
        let expected: Vec<u64> = rows
            .chunks(order + 1)
            .map(|r| core.step(r).unwrap().0.to_bits())
            .collect();
        let m = load_timed(&c, h);
        let mut whole = vec![0.0; n];
        let mut blocks = vec![0.0; n];
        unsafe {
            assert_eq!(
                hyst_model_compensate(m, rows.as_ptr(), order, whole.as_mut_ptr(), n),
                HYST_OK
            );
            assert_eq!(hyst_model_reset(m), HYST_OK);
            let per = 61;
            for (d, u) in rows.chunks(per * (order + 1)).zip(blocks.chunks_mut(per)) {
                assert_eq!(
                    hyst_model_compensate(m, d.as_ptr(), order, u.as_mut_ptr(), u.len()),
                    HYST_OK
                );
            }
            let mut u = [0.0];
            // The plant order, and nothing else, is the number of derivatives.
            for wrong in [0, order + 1, 7] {
                assert_eq!(
                    hyst_model_compensate(m, rows.as_ptr(), wrong, u.as_mut_ptr(), 1),
                    HYST_ERR_LENGTH
                );
            }
            assert_eq!(
                hyst_model_compensate(m, ptr::null(), order, u.as_mut_ptr(), 1),
                HYST_ERR_NULL_POINTER
            );
            assert_eq!(
                hyst_model_compensate(ptr::null_mut(), rows.as_ptr(), order, u.as_mut_ptr(), 1),
                HYST_ERR_NULL_POINTER
            );
            // A refused sample: its status, the compensator unchanged (the next call continues).
            let mut bad = rows[..=order].to_vec();
            bad[0] = f64::NAN;
            assert_eq!(
                hyst_model_compensate(m, bad.as_ptr(), order, u.as_mut_ptr(), 1),
                HYST_ERR_NON_FINITE
            );
            hyst_model_free(m);
        }
        let got: Vec<u64> = whole.iter().map(|v| v.to_bits()).collect();
        assert_eq!(got, expected, "{name}");
        assert_eq!(whole, blocks, "{name}");
        // The period that resolves the corners met: the core's, +∞ before the first sample.
        let needed = core.fastest_corner().map(|c| c.needed_period()).unwrap();
        let m = load_timed(&c, h);
        let mut period = 0.0;
        unsafe {
            assert_eq!(hyst_model_corner_period(m, &mut period), HYST_OK);
            assert_eq!(period, f64::INFINITY);
            assert_eq!(
                hyst_model_compensate(m, rows.as_ptr(), order, whole.as_mut_ptr(), n),
                HYST_OK
            );
            assert_eq!(hyst_model_corner_period(m, &mut period), HYST_OK);
            assert_eq!(period.to_bits(), needed.to_bits(), "{name}");
            assert_eq!(
                hyst_model_corner_period(m, ptr::null_mut()),
                HYST_ERR_NULL_POINTER
            );
            hyst_model_free(m);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A model without a compensator (a static model, whose exact inverse is hyst_model_process,
/// or one with a rate term): `compensate` and `corner_period` are unsupported.
#[test]
fn models_without_a_compensator_refuse_to_compensate() {
    let dir = folder("uncompensated");
    let h = 1e-3;
    for (name, sections) in [
        ("static.toml", ""),
        ("rate.toml", RATE),
        ("both.toml", &*format!("{FIRST_ORDER}{RATE}")),
    ] {
        let (_, c) = write(&dir, name, sections);
        let m = load_timed(&c, h);
        let mut u = [0.0];
        unsafe {
            assert_eq!(
                hyst_model_compensate(m, [1.0, 0.0].as_ptr(), 1, u.as_mut_ptr(), 1),
                HYST_ERR_UNSUPPORTED,
                "{name}"
            );
            let mut period = 0.0;
            assert_eq!(
                hyst_model_corner_period(m, &mut period),
                HYST_ERR_UNSUPPORTED,
                "{name}"
            );
            hyst_model_free(m);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Time stamps with jittered steps around 1 ms (some 2.3 ms), from a Unix-epoch start.
fn uneven_stamps(n: usize) -> Vec<f64> {
    let mut t = vec![1.7e9];
    for k in 1..n {
        let h = [1e-3, 1.25e-3, 0.75e-3, 2.3e-3, 1e-3][k % 5];
        t.push(t[k - 1] + h);
    }
    t
}

#[test]
fn uneven_steps_run_as_hyst_run_runs_the_stamps() {
    let dir = folder("steps");
    let n = 1200;
    let x: Vec<f64> = (0..n).map(input).collect();
    let t = uneven_stamps(n);
    let (parts, gaps) = ::hyst_model::time::split(&t).unwrap();
    assert!(gaps.is_empty());
    let (_, steps) = &parts[0];
    // The steps each sample takes: the raw differences of the stamps.
    let step: Vec<f64> = (0..n)
        .map(|k| if k == 0 { 0.0 } else { t[k] - t[k - 1] })
        .collect();
    let zoh = format!("{SECOND_ORDER}hold = \"zoh\"\n");
    for (name, sections) in [
        ("second.toml", SECOND_ORDER.to_string()),
        ("both.toml", format!("{SECOND_ORDER}{RATE}")),
        ("rate.toml", RATE.to_string()),
        ("zoh.toml", zoh),
    ] {
        let (path, c) = write(&dir, name, &sections);
        let text = std::fs::read_to_string(&path).unwrap();
        if sections.contains("hold") {
            std::fs::write(&path, text.replace("version = 4", "version = 5")).unwrap();
        }
        let file = ModelFile::read(&path).unwrap();
        let smooth = file.smooth.as_ref().unwrap();
        let mut expected = Vec::new();
        smooth
            .run_timed(&x, Some(steps), None, |_, s| expected.push(s.y.to_bits()))
            .unwrap();
        let m = load_timed(&c, steps.nominal());
        let mut y = vec![0.0; n];
        unsafe {
            assert_eq!(
                hyst_model_process_steps(m, x.as_ptr(), step.as_ptr(), y.as_mut_ptr(), n),
                HYST_OK
            );
        }
        let got: Vec<u64> = y.iter().map(|v| v.to_bits()).collect();
        assert_eq!(got, expected, "{name}");
        // The hold, as the file says, and set.
        let mut hold = -1;
        let status = unsafe { hyst_model_hold(m, &mut hold) };
        if sections.contains("[dynamics]") {
            assert_eq!(status, HYST_OK);
            let want = if name == "zoh.toml" {
                HYST_HOLD_ZOH
            } else {
                HYST_HOLD_FOH
            };
            assert_eq!(hold, want, "{name}");
            let other = if want == HYST_HOLD_ZOH {
                HYST_HOLD_FOH
            } else {
                HYST_HOLD_ZOH
            };
            assert_eq!(unsafe { hyst_model_set_hold(m, other) }, HYST_OK);
            let mut z = vec![0.0; n];
            unsafe {
                hyst_model_process_steps(m, x.as_ptr(), step.as_ptr(), z.as_mut_ptr(), n);
            }
            assert_ne!(z, y, "{name}: the hold matters");
            assert_eq!(
                unsafe { hyst_model_set_hold(m, 7) },
                HYST_ERR_INVALID_PARAMETER
            );
        } else {
            assert_eq!(status, HYST_ERR_UNSUPPORTED);
            assert_eq!(
                unsafe { hyst_model_set_hold(m, HYST_HOLD_ZOH) },
                HYST_ERR_UNSUPPORTED
            );
        }
        // A step that is not > 0 is refused at its sample.
        let mut bad = step.clone();
        bad[7] = 0.0;
        unsafe {
            hyst_model_reset(m);
            assert_eq!(
                hyst_model_process_steps(m, x.as_ptr(), bad.as_ptr(), y.as_mut_ptr(), n),
                HYST_ERR_INVALID_PARAMETER
            );
            hyst_model_free(m);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
