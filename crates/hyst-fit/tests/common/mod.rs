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
