//! Accuracy tests of the special functions against high-precision reference
//! data (see `tests/data/README.md` for how the data were generated and for
//! the tolerance policy).
//!
//! Run with `cargo test -p hyst-core --test special_functions -- --nocapture`
//! to see the worst relative error found for each function.

// Test code: panicking on malformed data or on a failed check is the point.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

use hyst_core::lambert::{omega, w0};
use hyst_core::shaping::langevin;
use hyst_test_support::rng::{Random, XorShift64};

const LAMBERT_W0_CSV: &str = include_str!("data/lambert_w0.csv");
const WRIGHT_OMEGA_CSV: &str = include_str!("data/wright_omega.csv");
const LANGEVIN_CSV: &str = include_str!("data/langevin.csv");
const LANGEVIN_SERIES_TXT: &str = include_str!("data/langevin_series.txt");

/// Relative tolerance of `w0::<f64>` and `omega::<f64>`.
const TOL_LAMBERT_F64: f64 = 2e-15;
/// Relative tolerance of `langevin::<f64>`.
const TOL_LANGEVIN_F64: f64 = 4e-15;
/// Relative tolerance of `w0::<f32>` and `omega::<f32>`.
const TOL_F32: f64 = 5e-6;
/// Absolute tolerance where the f64 reference is below `f64::MIN_POSITIVE`.
const TOL_UNDERFLOW_ABS: f64 = 1e-300;
/// Residual tolerance of the random sweep: |w + ln w - y| <= this * max(1, |y|).
const TOL_SWEEP_RESIDUAL: f64 = 4e-15;
/// Number of random points of the sweep.
const SWEEP_N: usize = 1_000_000;
/// Most failure messages printed per check (the total count is always given).
const MAX_REPORTED: usize = 40;

// ------------------------------------------------------------------ parsing

/// Parse a two-column numeric CSV with the given header line.
fn parse_two_columns(name: &str, text: &str, header: &str) -> Vec<(f64, f64)> {
    let mut lines = text.lines();
    let first = lines.next().unwrap_or("");
    assert_eq!(first.trim(), header, "{name}: unexpected header line");
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let lineno = i + 2;
        let mut fields = line.split(',');
        let (a, b) = match (fields.next(), fields.next(), fields.next()) {
            (Some(a), Some(b), None) => (a.trim(), b.trim()),
            _ => panic!("{name}:{lineno}: expected two fields, got {line:?}"),
        };
        let a: f64 = a
            .parse()
            .unwrap_or_else(|e| panic!("{name}:{lineno}: bad number {a:?}: {e}"));
        let b: f64 = b
            .parse()
            .unwrap_or_else(|e| panic!("{name}:{lineno}: bad number {b:?}: {e}"));
        rows.push((a, b));
    }
    assert!(!rows.is_empty(), "{name}: no data rows");
    rows
}

// ------------------------------------------------------------------ bookkeeping

/// Relative error; a zero reference demands an exact zero; NaN maps to +inf.
fn rel_err(got: f64, want: f64) -> f64 {
    let e = if want == 0.0 {
        if got == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    } else {
        ((got - want) / want).abs()
    };
    if e.is_nan() {
        f64::INFINITY
    } else {
        e
    }
}

/// Collects the checks of one function at one precision.
struct Tally {
    name: &'static str,
    tol: f64,
    /// Machine epsilon of the precision under test (for the report only).
    eps: f64,
    checked: usize,
    skipped: usize,
    abs_checked: usize,
    worst: f64,
    worst_case: Option<(f64, f64, f64)>,
    failures: Vec<String>,
    n_failures: usize,
}

impl Tally {
    fn new(name: &'static str, tol: f64, eps: f64) -> Self {
        Tally {
            name,
            tol,
            eps,
            checked: 0,
            skipped: 0,
            abs_checked: 0,
            worst: 0.0,
            worst_case: None,
            failures: Vec::new(),
            n_failures: 0,
        }
    }

    fn fail(&mut self, msg: String) {
        self.n_failures += 1;
        if self.failures.len() < MAX_REPORTED {
            self.failures.push(msg);
        }
    }

    /// Relative-error check.
    fn rel(&mut self, input: f64, want: f64, got: f64) {
        self.checked += 1;
        let e = rel_err(got, want);
        if e > self.worst || self.worst_case.is_none() {
            self.worst = e;
            self.worst_case = Some((input, want, got));
        }
        if e > self.tol {
            let name = self.name;
            let tol = self.tol;
            self.fail(format!(
                "{name}({input:?}): expected {want:?}, got {got:?}, \
                 relative error {e:.3e} > {tol:.1e}"
            ));
        }
    }

    /// Absolute-error check (reference below the normal range).
    fn abs(&mut self, input: f64, want: f64, got: f64, tol: f64) {
        self.abs_checked += 1;
        let d = (got - want).abs();
        if d.is_nan() || d > tol || (got < 0.0) {
            let name = self.name;
            let e = rel_err(got, want);
            self.fail(format!(
                "{name}({input:?}) [underflow region]: expected {want:?}, got {got:?}, \
                 absolute error {d:.3e} > {tol:.1e} (relative error {e:.3e})"
            ));
        }
    }

    fn skip(&mut self) {
        self.skipped += 1;
    }

    fn finish(self) {
        let Tally {
            name,
            tol,
            eps,
            checked,
            skipped,
            abs_checked,
            worst,
            worst_case,
            failures,
            n_failures,
        } = self;
        match worst_case {
            Some((x, want, got)) => println!(
                "{name}: worst relative error {worst:.3e} (tolerance {tol:.1e}, \
                 = {:.2} eps) at input {x:?}: expected {want:?}, got {got:?}; \
                 {checked} relative checks, {abs_checked} absolute (underflow) checks, \
                 {skipped} skipped",
                worst / eps,
            ),
            None => println!("{name}: no relative checks ({skipped} skipped)"),
        }
        assert!(
            n_failures == 0,
            "{name}: {n_failures} of {} checks out of tolerance{}:\n{}",
            checked + abs_checked,
            if n_failures > failures.len() {
                format!(" (first {} shown)", failures.len())
            } else {
                String::new()
            },
            failures.join("\n")
        );
    }
}

/// `v` is zero or a normal, finite f32 value (in magnitude).
fn f32_normal_or_zero(v: f64) -> bool {
    v == 0.0 || (v.abs() >= f64::from(f32::MIN_POSITIVE) && v.abs() <= f64::from(f32::MAX))
}

// ------------------------------------------------------------------ Lambert W0

#[test]
fn lambert_w0_f64_matches_reference() {
    let rows = parse_two_columns("lambert_w0.csv", LAMBERT_W0_CSV, "x,w0");
    let mut t = Tally::new("w0::<f64>", TOL_LAMBERT_F64, f64::EPSILON);
    for &(x, want) in &rows {
        let got = w0::<f64>(x);
        if want != 0.0 && want.abs() < f64::MIN_POSITIVE {
            // Subnormal reference (subnormal input): relative accuracy is
            // not attainable in general; see the README.
            t.abs(x, want, got, TOL_UNDERFLOW_ABS);
        } else {
            t.rel(x, want, got);
        }
    }
    t.finish();
}

#[test]
fn lambert_w0_f32_matches_reference() {
    let rows = parse_two_columns("lambert_w0.csv", LAMBERT_W0_CSV, "x,w0");
    let mut t = Tally::new("w0::<f32>", TOL_F32, f64::from(f32::EPSILON));
    for &(x, want) in &rows {
        if !f32_normal_or_zero(x) || !f32_normal_or_zero(want) {
            t.skip();
            continue;
        }
        let xf = x as f32;
        // The reference is for the f64 input; move it to the f32-rounded
        // input to first order: W'(x) = W / (x (1 + W)).
        let want_f = if x == 0.0 {
            0.0
        } else {
            let dx = f64::from(xf) - x;
            want + want / (x * (1.0 + want)) * dx
        };
        let got = f64::from(w0::<f32>(xf));
        t.rel(f64::from(xf), want_f, got);
    }
    t.finish();
}

// ------------------------------------------------------------------ Wright omega

#[test]
fn wright_omega_f64_matches_reference() {
    let rows = parse_two_columns("wright_omega.csv", WRIGHT_OMEGA_CSV, "y,omega");
    let mut t = Tally::new("omega::<f64>", TOL_LAMBERT_F64, f64::EPSILON);
    for &(y, want) in &rows {
        let got = omega::<f64>(y);
        if want < f64::MIN_POSITIVE {
            t.abs(y, want, got, TOL_UNDERFLOW_ABS);
        } else {
            t.rel(y, want, got);
        }
    }
    t.finish();
}

#[test]
fn wright_omega_f32_matches_reference() {
    let rows = parse_two_columns("wright_omega.csv", WRIGHT_OMEGA_CSV, "y,omega");
    let mut t = Tally::new("omega::<f32>", TOL_F32, f64::from(f32::EPSILON));
    for &(y, want) in &rows {
        if !f32_normal_or_zero(y) || want == 0.0 || !f32_normal_or_zero(want) {
            t.skip();
            continue;
        }
        let yf = y as f32;
        // Move the reference to the f32-rounded input:
        // omega'(y) = omega / (1 + omega), i.e. d ln omega = dy / (1 + omega).
        let dy = f64::from(yf) - y;
        let want_f = want * (dy / (1.0 + want)).exp();
        let got = f64::from(omega::<f32>(yf));
        t.rel(f64::from(yf), want_f, got);
    }
    t.finish();
}

#[test]
fn wright_omega_random_sweep_satisfies_defining_equation() {
    // y in [-1e3, 1e20], log-uniform magnitudes in [1e-12, 1e3] (negative)
    // and [1e-12, 1e20] (positive); the sign is drawn in proportion to the
    // number of decades on each side.
    const NEG_DECADES: f64 = 15.0; // 1e-12 .. 1e3
    const POS_DECADES: f64 = 32.0; // 1e-12 .. 1e20
    let mut rng = XorShift64(0x9E37_79B9_7F4A_7C15);
    let name = "omega::<f64> sweep";
    let mut n_failures = 0usize;
    let mut failures: Vec<String> = Vec::new();
    let mut worst = 0.0f64;
    let mut worst_case = (0.0f64, 0.0f64);
    let mut n_residual = 0usize;
    for _ in 0..SWEEP_N {
        let neg = rng.unit() * (NEG_DECADES + POS_DECADES) < NEG_DECADES;
        let u = rng.unit();
        let y = if neg {
            -(10f64.powf(-12.0 + NEG_DECADES * u)).min(1e3)
        } else {
            10f64.powf(-12.0 + POS_DECADES * u).min(1e20)
        };
        let w = omega::<f64>(y);
        let mut problem = None;
        if !w.is_finite() || w < 0.0 {
            problem = Some("expected a finite, non-negative value".to_string());
        } else if w > 1e-300 {
            n_residual += 1;
            let scale = y.abs().max(1.0);
            let r = (w + w.ln() - y).abs() / scale;
            let r = if r.is_nan() { f64::INFINITY } else { r };
            if r > worst {
                worst = r;
                worst_case = (y, w);
            }
            if r > TOL_SWEEP_RESIDUAL {
                problem = Some(format!(
                    "|w + ln w - y| / max(1, |y|) = {r:.3e} > {TOL_SWEEP_RESIDUAL:.1e}"
                ));
            }
        }
        if let Some(p) = problem {
            n_failures += 1;
            if failures.len() < MAX_REPORTED {
                failures.push(format!("{name}: omega({y:?}) = {w:?}: {p}"));
            }
        }
    }
    println!(
        "{name}: worst relative residual |w + ln w - y| / max(1, |y|) = {worst:.3e} \
         (tolerance {TOL_SWEEP_RESIDUAL:.1e}) at y = {:?}, omega = {:?}; \
         {SWEEP_N} points, {n_residual} residual checks",
        worst_case.0, worst_case.1
    );
    assert!(
        n_failures == 0,
        "{name}: {n_failures} of {SWEEP_N} points failed (first {} shown):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

// ------------------------------------------------------------------ Langevin

#[test]
fn langevin_f64_matches_reference() {
    let rows = parse_two_columns("langevin.csv", LANGEVIN_CSV, "x,langevin");
    let mut t = Tally::new("langevin::<f64>", TOL_LANGEVIN_F64, f64::EPSILON);
    for &(x, want) in &rows {
        let got = langevin::<f64>(x);
        t.rel(x, want, got);
    }
    t.finish();
}

/// Consistency of the two Langevin data files (no library code involved):
/// the tabulated Taylor coefficients summed at small |x| reproduce the
/// tabulated values of L(x).
#[test]
fn langevin_series_data_is_consistent() {
    let coeffs = parse_two_columns("langevin_series.txt", LANGEVIN_SERIES_TXT, "n,c_n");
    assert_eq!(coeffs.len(), 20, "langevin_series.txt: expected n = 1..20");
    for (i, &(n, _)) in coeffs.iter().enumerate() {
        assert_eq!(n, (i + 1) as f64, "langevin_series.txt: n out of order");
    }
    assert_eq!(coeffs[0].1, 1.0 / 3.0, "c_1 must be 1/3");
    let rows = parse_two_columns("langevin.csv", LANGEVIN_CSV, "x,langevin");
    let mut t = Tally::new("langevin Taylor series (data check)", 4e-15, f64::EPSILON);
    for &(x, want) in rows.iter().filter(|(x, _)| x.abs() <= 0.5) {
        // Horner in x^2: L(x) = x * sum c_n (x^2)^(n-1).
        let x2 = x * x;
        let s = coeffs.iter().rev().fold(0.0, |acc, &(_, c)| acc * x2 + c);
        t.rel(x, want, x * s);
    }
    t.finish();
}
