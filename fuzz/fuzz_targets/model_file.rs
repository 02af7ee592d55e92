//! Fuzz target: hyst_checks::check_model_file (see crates/hyst-checks).
#![no_main]
// A fuzz target reports a broken invariant to libFuzzer by panicking.
#![allow(clippy::panic)]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(broken) = hyst_checks::check_model_file(data) {
        panic!("{broken}");
    }
});
