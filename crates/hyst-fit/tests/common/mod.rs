//! Helpers shared by the hyst-fit integration tests.

/// A deterministic standard normal sequence (xorshift64* and Box–Muller).
pub fn normals(n: usize, mut seed: u64) -> Vec<f64> {
    let mut uniform = move || {
        seed ^= seed >> 12;
        seed ^= seed << 25;
        seed ^= seed >> 27;
        ((seed.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let (a, b) = (uniform(), uniform());
            (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
        })
        .collect()
}

/// An input that sweeps loops of growing then shrinking amplitude around an offset (volts,
/// say): `n` samples.
#[allow(dead_code)] // not every test file that shares this module sweeps loops
pub fn loops_input(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let t = k as f64 / n as f64;
            let amp = 0.3 + 1.5 * (std::f64::consts::PI * t).sin();
            2.0 + amp * (40.0 * t).sin() + 0.2 * (97.0 * t).sin()
        })
        .collect()
}

/// A piston stroke (mm) at 1 kHz, `n` samples: three sines with amplitudes 4 + 2 |r| mm,
/// frequencies `f0` + `f_spread` |r| Hz and random phases, r standard normals from `seed`.
#[allow(dead_code)] // not every test file that shares this module strokes a piston
pub fn stroke(n: usize, seed: u64, f0: f64, f_spread: f64) -> Vec<f64> {
    let r = normals(9, seed);
    (0..n)
        .map(|k| {
            let t = k as f64 * 1e-3;
            (0..3)
                .map(|i| {
                    let amp = 4.0 + 2.0 * r[3 * i].abs();
                    let f = f0 + f_spread * r[3 * i + 1].abs();
                    amp * (2.0 * std::f64::consts::PI * f * t + r[3 * i + 2]).sin()
                })
                .sum()
        })
        .collect()
}

/// `identify` as these tests call it: no progress output, never interrupted, no provenance.
#[allow(dead_code)] // not every test file that shares this module identifies
pub fn identify(
    data: &hyst_fit::Dataset,
    request: &hyst_fit::identify::Request,
) -> Result<hyst_fit::identify::Identified, hyst_fit::FitError> {
    hyst_fit::identify::identify(
        data,
        request,
        &mut hyst_fit::lm::Silent,
        &|| false,
        hyst_model::Provenance::default(),
    )
}
