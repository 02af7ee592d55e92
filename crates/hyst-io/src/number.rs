//! Numbers as the reports, summaries and error messages of every hyst tool print them: with
//! a given count of significant digits ([`sig`]), with exactly their shortest round-trip digits
//! ([`shortest`]), and as percentages that never round up to a threshold ([`percent_floor`]) or
//! keep the digits the user gave ([`percent_given`]).

/// `x` with `digits` significant digits: fixed notation for 1e-3 ≤ |x| < 1e6 (all the integer
/// digits kept), scientific outside, so that a number in any unit shows its digits ("29.87",
/// "0.005281", "5.281e-4", "3.000e300").
#[must_use]
pub fn sig(x: f64, digits: usize) -> String {
    let digits = digits.max(1);
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".into();
    }
    let magnitude = x.abs().log10().floor();
    if (-3.0..6.0).contains(&magnitude) {
        let decimals = (digits as f64 - 1.0 - magnitude).max(0.0) as usize;
        let s = format!("{x:.decimals$}");
        // Rounding may carry into a new digit (9.9996 → "10.000"): one decimal fewer.
        let significant = s.replace(['-', '.'], "");
        if significant.trim_start_matches('0').len() > digits && decimals > 0 {
            let decimals = decimals - 1;
            return format!("{x:.decimals$}");
        }
        s
    } else {
        format!("{x:.prec$e}", prec = digits - 1)
    }
}

/// `x` with exactly its shortest round-trip digits, in the notation of [`sig`] (fixed for
/// 1e-3 ≤ |x| < 1e6, exponent form outside): for numbers shown as given ("2e-6", "0.14", "2.5").
#[must_use]
pub fn shortest(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() || (1e-3..1e6).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A fraction as a percentage with `decimals` decimals, rounded towards zero, so that a value
/// below a threshold is never printed at or above it (0.98997 → "98.99", not "99.00").
#[must_use]
pub fn percent_floor(fraction: f64, decimals: usize) -> String {
    let scale = 10f64.powi(decimals as i32);
    let v = (100.0 * fraction * scale).floor() / scale;
    format!("{v:.decimals$}")
}

/// A fraction the user gave (a `--coverage`), as a percentage with exactly its digits: the
/// decimal point of its shortest round-trip form moved two places (0.1806 → "18.06", 0.9999 →
/// "99.99", 1 → "100"), so that an asked value is never shown as a different number.
#[must_use]
pub fn percent_given(fraction: f64) -> String {
    if !fraction.is_finite() {
        return format!("{}", 100.0 * fraction);
    }
    // `{}` never takes exponent form for f64: "0.000015", "1", "0.1806".
    let s = format!("{}", fraction.abs());
    let (int, frac) = s.split_once('.').unwrap_or((&s, ""));
    let mut digits = format!("{int}{frac:0<2}");
    let point = int.len() + 2;
    let (whole, decimals) = digits.split_at_mut(point);
    let whole = whole.trim_start_matches('0');
    let whole = if whole.is_empty() { "0" } else { whole };
    let sign = if fraction < 0.0 { "-" } else { "" };
    if decimals.is_empty() {
        format!("{sign}{whole}")
    } else {
        format!("{sign}{whole}.{decimals}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_their_significant_digits_at_any_scale() {
        assert_eq!(sig(29.87201, 4), "29.87");
        assert_eq!(sig(0.000528065, 4), "5.281e-4");
        assert_eq!(sig(0.00528065, 4), "0.005281");
        assert_eq!(sig(1.2344e-7, 4), "1.234e-7");
        assert_eq!(sig(3e300, 4), "3.000e300");
        assert_eq!(sig(-80.71770, 4), "-80.72");
        assert_eq!(sig(123_456.7, 4), "123457");
        assert_eq!(sig(9.99996, 4), "10.00");
        assert_eq!(sig(0.0, 4), "0");
        assert_eq!(sig(f64::NAN, 4), "NaN");
    }

    #[test]
    fn shortest_keeps_all_the_digits_given() {
        assert_eq!(shortest(2e-6), "2e-6");
        assert_eq!(shortest(0.14), "0.14");
        assert_eq!(shortest(1e300), "1e300");
        assert_eq!(shortest(500_000.0), "500000");
        assert_eq!(shortest(0.0), "0");
    }

    #[test]
    fn an_asked_percentage_keeps_the_digits_it_was_given() {
        assert_eq!(percent_given(0.1806), "18.06");
        assert_eq!(percent_given(0.9999), "99.99");
        assert_eq!(percent_given(0.9995), "99.95");
        assert_eq!(percent_given(1.0), "100");
        assert_eq!(percent_given(0.99), "99");
        assert_eq!(percent_given(0.5), "50");
        assert_eq!(percent_given(0.123456789), "12.3456789");
        assert_eq!(percent_given(0.000015), "0.0015");
    }

    #[test]
    fn percentages_are_never_rounded_up_to_a_threshold() {
        assert_eq!(percent_floor(0.98997, 2), "98.99");
        assert_eq!(percent_floor(0.99, 2), "99.00");
        assert_eq!(percent_floor(1.0, 1), "100.0");
    }
}
