//! `hyst bound`: the error bound Δa of a family RH(k1, Δk1, k2, Δk2) (Proposition 3.2, eqs.
//! 12–13 with the corrected denominator k̄2 − k2), its four corner values, and Δb ≤ Δa
//! (Proposition 3.3), optionally scaled by a linear output shaping gain.

use anyhow::{Context, Result};
use hyst_core::family::delta_a;
use hyst_io::number::{shortest, sig};

/// Arguments of `hyst bound`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Nominal k1 (half-width of the loop, output units).
    #[arg(long)]
    pub k1: f64,
    /// Δk1: the family's k1 ranges over [k1 − Δk1, k1 + Δk1].
    #[arg(long, default_value_t = 0.0)]
    pub dk1: f64,
    /// Nominal k2 (transition rate, 1 / input units).
    #[arg(long)]
    pub k2: f64,
    /// Δk2: the family's k2 ranges over [k2 − Δk2, k2 + Δk2].
    #[arg(long, default_value_t = 0.0)]
    pub dk2: f64,
    /// Gain (Lipschitz constant, > 0) of a linear output shaping function: scales Δb. Shaping
    /// functions are increasing, so a gain <= 0 is refused (for a sensor that falls as the
    /// output rises, give the magnitude of its gain: the bound is the same).
    #[arg(long, allow_negative_numbers = true)]
    pub output_gain: Option<f64>,
    /// Print JSON (keys delta_a, corners, delta_b_max, ...) instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs `hyst bound`.
pub fn main(args: Args) -> Result<()> {
    if let Some(gain) = args.output_gain {
        if !(gain.is_finite() && gain > 0.0) {
            anyhow::bail!(
                "--output-gain {}: the gain must be finite and > 0 (the slope of an \
                 increasing output shaping; for a decreasing sensor give the magnitude of its \
                 gain, the bound is the same)",
                shortest(gain)
            );
        }
    }
    let b = delta_a(args.k1, args.dk1, args.k2, args.dk2).with_context(|| {
        format!(
            "invalid family RH(k1 = {}, dk1 = {}, k2 = {}, dk2 = {})",
            shortest(args.k1),
            shortest(args.dk1),
            shortest(args.k2),
            shortest(args.dk2)
        )
    })?;
    let gain = args.output_gain.unwrap_or(1.0);
    let delta_b_max = b.delta_a * gain;
    if !delta_b_max.is_finite() {
        anyhow::bail!(
            "--output-gain {}: the bound at the output, delta_a = {} times the gain, is beyond \
             the float range",
            shortest(gain),
            shortest(b.delta_a)
        );
    }
    if args.json {
        let corners: Vec<serde_json::Value> = b
            .corner_params
            .iter()
            .zip(b.corners.iter().zip(b.corner_points.iter()))
            .map(|((k1b, k2b), (value, at))| {
                serde_json::json!({ "k1": k1b, "k2": k2b, "value": value, "at_ud": at })
            })
            .collect();
        let out = serde_json::json!({
            "family": { "k1": args.k1, "dk1": args.dk1, "k2": args.k2, "dk2": args.dk2 },
            "delta_a": b.delta_a,
            "corners": b.corners,
            "corner_details": corners,
            "output_gain": gain,
            "delta_b_max": delta_b_max,
        });
        outln!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    out!("{}", text(&args, &b, gain));
    Ok(())
}

/// A computed value with 4 significant digits, its sign always shown.
fn signed(x: f64) -> String {
    let s = sig(x, 4);
    if s.starts_with('-') {
        s
    } else {
        format!("+{s}")
    }
}

/// The text output: every computed number with 4 significant digits (docs/fitting.md, "The
/// report"), the parameters as given.
fn text(args: &Args, b: &hyst_core::family::Bound<f64>, gain: f64) -> String {
    let mut s = format!(
        "family RH(k1 = {}, dk1 = {}, k2 = {}, dk2 = {})\n",
        shortest(args.k1),
        shortest(args.dk1),
        shortest(args.k2),
        shortest(args.dk2)
    );
    s += "corner values of eq. (13) (denominator corrected to k2bar - k2):\n";
    for (i, ((k1b, k2b), (value, at))) in b
        .corner_params
        .iter()
        .zip(b.corners.iter().zip(b.corner_points.iter()))
        .enumerate()
    {
        s += &format!(
            "  dx{} = {}   at k1bar = {}, k2bar = {}, ud~ = {}\n",
            i + 1,
            signed(*value),
            sig(*k1b, 4),
            sig(*k2b, 4),
            sig(*at, 4)
        );
    }
    s += &format!(
        "delta_a = {}  (Proposition 3.2, eq. 12)\n",
        sig(b.delta_a, 4)
    );
    s += &format!(
        "delta_b <= delta_a = {}  (Proposition 3.3, eq. 15)\n",
        sig(b.delta_a, 4)
    );
    if args.output_gain.is_some() {
        s += &format!(
            "after the output shaping (gain {}): delta_b <= {}\n",
            shortest(gain),
            sig(b.delta_a * gain, 4)
        );
    }
    s
}
