//! Saturation of a model whose output is bounded: by a saturating output shaping (tanh,
//! Langevin), or by a saturating input shaping, whose bounded range bounds the operator's input
//! and so, within k1, its output. The open range of the output, the limits a compensator clamps
//! desired outputs to ([`Saturation`], computed once for every surface by
//! [`Saturation::of`]), and the wrapper that clamps them ([`Saturated`]).

use hyst_core::{Error, Operator, Sample, Shaping};

use crate::smooth::{Form, SmoothModel};

/// The fraction of a saturating shaping's range, about its centre, that
/// [`Saturation::of`] lets the compensator ask for: a tanh reaches 99.9 % of its
/// saturation level at atanh(0.999) ≈ 3.8 times its scale, so the command stays finite and
/// moderate, while the last 0.1 % would need a command growing without bound.
pub const SATURATION_FRACTION: f64 = 0.999;

/// What a model with a bounded output lets the compensator reach (see [`Saturation::of`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Saturation {
    /// The saturating shaping function that bounds the output ("tanh", "langevin"): the
    /// output shaping's when it saturates, the input shaping's otherwise.
    pub shaping: &'static str,
    /// The output shaping's name when it saturates.
    pub output_shaping: Option<&'static str>,
    /// The input shaping's name when it saturates: its bounded range bounds the operator's
    /// input, and so the output.
    pub input_shaping: Option<&'static str>,
    /// The open range (lo, hi) of the model's output: no command, from any state, produces lo,
    /// hi or beyond.
    pub range: (f64, f64),
    /// The desired outputs a compensator may be asked for, reachable from every state (see
    /// [`Saturation::of`]). Clamping a desired output into these limits keeps the command
    /// finite and the map from desired output to command monotone.
    pub limits: (f64, f64),
    /// Whether a limit was widened beyond [`SATURATION_FRACTION`] of a range to cover the
    /// model's outputs (or operator inputs) over its fitted input range.
    pub widened: bool,
}

impl Saturation {
    /// The saturation of a smooth model of the operator form whose output is bounded; `None`
    /// when it is unbounded (affine or polynomial shapings), for the stop form (no inverse),
    /// and when the limits are not finite.
    ///
    /// The limits are the intersection of two intervals, one per saturating shaping:
    /// - ψ_out with the open range (lo, hi): [`SATURATION_FRACTION`] of it about its centre,
    ///   widened to every output the model gives over its fitted input range
    ///   ([`SmoothModel::fitted_output_range`]: a fit may put its data in the last 0.1 % of a
    ///   tanh, its tail used as an exponential).
    /// - ψ_in with the open range (a, b) of the operator input v: from a state (v0, u0) the
    ///   operator's output moves monotonically along a branch that stays within k1 of v, so
    ///   rising it passes every u up to b − k1 before v reaches b, and falling every u down to
    ///   a + k1: ψ_out(\[a + k1, b − k1\]) is reachable from every state, while outputs up to
    ///   ψ_out(b + k1) are reachable only from some. With a′, b′ = [`SATURATION_FRACTION`] of
    ///   (a, b) about its centre, the limits are ψ_out(a′ + k1) and ψ_out(b′ − k1), widened to
    ///   the outputs over the fitted input range as above: those are reachable from the states
    ///   the fitted data passes through (from another state a desired output in the widened
    ///   part may be out of reach, and is refused as such). The range is
    ///   ψ_out((a − k1, b + k1)).
    #[must_use]
    pub fn of(m: &SmoothModel) -> Option<Self> {
        if m.form == Form::Stop {
            return None;
        }
        let psi_out = &m.output_shaping;
        let mut range = (f64::NEG_INFINITY, f64::INFINITY);
        // Each limit with whether it was widened.
        let (mut lo, mut hi) = ((f64::NEG_INFINITY, false), (f64::INFINITY, false));
        let output = m.output_range();
        let fitted = m.fitted_output_range();
        if let Some((r_lo, r_hi)) = output {
            range = (r_lo, r_hi);
            lo = fraction(r_lo, r_hi, -1.0, fitted.map(|f| f.0));
            hi = fraction(r_lo, r_hi, 1.0, fitted.map(|f| f.1));
        }
        let input = m.input_range();
        if let Some((a, b)) = input {
            let (a1, _) = fraction(a, b, -1.0, None);
            let (b1, _) = fraction(a, b, 1.0, None);
            range = (
                range.0.max(psi_out.apply(a - m.k1)),
                range.1.min(psi_out.apply(b + m.k1)),
            );
            // The outputs reachable from every state; none when 2·k1 exceeds the fraction of
            // ψ_in's range.
            let (mut y_lo, mut y_hi) = if a1 + m.k1 < b1 - m.k1 {
                (
                    (psi_out.apply(a1 + m.k1), false),
                    (psi_out.apply(b1 - m.k1), false),
                )
            } else {
                ((f64::INFINITY, false), (f64::NEG_INFINITY, false))
            };
            // Widened to the fitted outputs, strictly inside the range.
            if let Some((f_lo, f_hi)) = fitted {
                if f_lo < y_lo.0 && f_lo > range.0 {
                    y_lo = (f_lo, true);
                }
                if f_hi > y_hi.0 && f_hi < range.1 {
                    y_hi = (f_hi, true);
                }
            }
            if y_lo.0 > lo.0 {
                lo = y_lo;
            }
            if y_hi.0 < hi.0 {
                hi = y_hi;
            }
        }
        let (output, input) = (
            output.map(|_| psi_out.name()),
            input.map(|_| m.input_shaping.name()),
        );
        let shaping = output.or(input)?;
        let limits = (lo.0, hi.0);
        (limits.0.is_finite() && limits.1.is_finite() && limits.0 < limits.1).then_some(Self {
            shaping,
            output_shaping: output,
            input_shaping: input,
            range,
            limits,
            widened: lo.1 || hi.1,
        })
    }

    /// What `range` is the range of, for messages: "the model's tanh output shaping" when only
    /// ψ_out bounds the output, "the model's outputs (bounded by its tanh input shaping)" or
    /// "… (bounded by its tanh input and tanh output shapings)" when ψ_in does too.
    #[must_use]
    pub fn range_of(&self) -> String {
        match (self.input_shaping, self.output_shaping) {
            (Some(input), Some(output)) => format!(
                "the model's outputs (bounded by its {input} input and {output} output shapings)"
            ),
            (Some(input), None) => {
                format!("the model's outputs (bounded by its {input} input shaping)")
            }
            (None, _) => format!("the model's {} output shaping", self.shaping),
        }
    }

    /// How the limits were chosen, for messages: "99.9 % of the range about its centre", and
    /// when widened, that they cover the model's outputs over its fitted input range.
    #[must_use]
    pub fn rule(&self) -> String {
        let percent = 100.0 * SATURATION_FRACTION;
        let fraction = match self.input_shaping {
            None => format!("{percent} % of the range about its centre"),
            Some(_) => format!(
                "the outputs reachable from every state: operator outputs k1 inside {percent} % \
                 of the input shaping's range about its centre"
            ),
        };
        if self.widened {
            format!(
                "{fraction}, widened to every output the model gives over its fitted input range"
            )
        } else {
            fraction
        }
    }
}

/// The end (`side` −1: low, +1: high) of [`SATURATION_FRACTION`] of the open range (lo, hi)
/// about its centre, widened to `fitted` when that lies beyond it and strictly inside the range
/// (its ends have no command); and whether it was widened.
fn fraction(lo: f64, hi: f64, side: f64, fitted: Option<f64>) -> (f64, bool) {
    let (centre, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    let end = centre + side * SATURATION_FRACTION * half;
    match fitted {
        Some(f) if f > lo && f < hi && side * (f - end) > 0.0 => (f, true),
        _ => (end, false),
    }
}

/// An inverse whose desired outputs are clamped into a saturating model's limits
/// ([`Saturation::limits`]) before `inner` sees them, as `hyst run --saturate`
/// clamps them: a finite value beyond the limits steps `inner` with the nearer limit (a jet
/// with zero derivatives: a clamped desired output stands still); non-finite values reach
/// `inner`, which refuses them. With `limits` `None` it is `inner` unchanged.
#[derive(Clone, Debug)]
pub struct Saturated<O> {
    /// The inverse.
    pub inner: O,
    /// The clamp limits (lo, hi), lo < hi; `None`: nothing is clamped.
    pub limits: Option<(f64, f64)>,
    /// How many accepted samples were saturated (clamped into the limits) since the wrapper
    /// was made or reset.
    pub saturated: u64,
}

impl<O> Saturated<O> {
    /// `inner` with desired outputs clamped into `limits` (`None`: not clamped).
    #[must_use]
    pub fn new(inner: O, limits: Option<(f64, f64)>) -> Self {
        Self {
            inner,
            limits,
            saturated: 0,
        }
    }

    /// `x` clamped into the limits when it is finite and beyond them; `None` otherwise.
    #[must_use]
    pub fn clamp(&self, x: f64) -> Option<f64> {
        let (lo, hi) = self.limits?;
        (x.is_finite() && (x < lo || x > hi)).then(|| x.clamp(lo, hi))
    }
}

impl<O: Operator<f64>> Operator<f64> for Saturated<O> {
    type Memory = O::Memory;

    /// One sample of `inner`, clamped first when it is beyond the limits.
    ///
    /// # Errors
    /// `inner`'s error for this sample (the memory and the count are then unchanged).
    fn try_step<S: Sample<f64>>(&mut self, x: S) -> Result<S, Error> {
        match self.clamp(x.value()) {
            Some(v) => {
                let y = self.inner.try_step(S::constant(v))?;
                self.saturated += 1;
                Ok(y)
            }
            None => self.inner.try_step(x),
        }
    }

    fn last_output(&self) -> Option<f64> {
        self.inner.last_output()
    }

    /// `inner` back to its initial state, and the count to 0.
    fn reset(&mut self) {
        self.inner.reset();
        self.saturated = 0;
    }

    fn memory(&self) -> O::Memory {
        self.inner.memory()
    }

    /// # Errors
    /// `inner`'s check of the memory.
    fn set_memory(&mut self, memory: O::Memory) -> Result<(), Error> {
        self.inner.set_memory(memory)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use hyst_core::InverseHysteresis;

    #[test]
    fn values_beyond_the_limits_step_the_compensator_with_the_limit() {
        let plain = InverseHysteresis::new(0.2, 8.0).unwrap();
        let mut clamped = Saturated::new(plain, Some((-1.0, 1.0)));
        let mut reference = plain;
        for (x, seen) in [(0.5, 0.5), (3.0, 1.0), (-7.0, -1.0), (1.0, 1.0), (0.2, 0.2)] {
            assert_eq!(
                clamped.try_step(x).unwrap().to_bits(),
                reference.try_step(seen).unwrap().to_bits()
            );
        }
        assert_eq!(clamped.saturated, 2);
        // Non-finite values are refused by the compensator, not clamped; nothing changes.
        let before = clamped.memory();
        assert!(clamped.try_step(f64::INFINITY).is_err());
        assert_eq!((clamped.memory(), clamped.saturated), (before, 2));
        clamped.reset();
        assert_eq!((clamped.memory(), clamped.saturated), (None, 0));
        // Without limits: the compensator unchanged.
        let mut open = Saturated::new(plain, None);
        assert_eq!(
            open.try_step(3.0).unwrap(),
            plain.clone().try_step(3.0).unwrap()
        );
        assert_eq!(open.saturated, 0);
    }

    /// y = 10 · H(0.1, 8)[tanh(x)] (affine ψ_out): ψ_in bounds the output to (−11, 11), and
    /// every state reaches 10 · [−0.899, 0.899]; inside the limits a desired output always has
    /// a command, whatever came before. With k1 wider than ψ_in's range, no output is reachable
    /// from every state and the limits fall back on the fitted outputs.
    #[test]
    fn a_saturating_input_shaping_bounds_the_output_from_every_state() {
        use hyst_core::{AnyK2Law, AnyShaping, InitialState, ScaledShaping, Tanh};
        let shaping = |shape| ScaledShaping::new(1.0, 0.0, shape, 1.0, 0.0).unwrap();
        let mut m = SmoothModel {
            k1: 0.1,
            k2: AnyK2Law::Constant { value: 8.0 },
            input_shaping: shaping(AnyShaping::Tanh(Tanh::new(1.0, 1.0).unwrap())),
            output_shaping: shaping(AnyShaping::Affine(
                hyst_core::Affine::new(10.0, 0.0).unwrap(),
            )),
            initial_state: InitialState::Rising,
            form: Form::Operator,
            linear: 0.0,
            dynamics: None,
            rate: None,
        };
        let s = Saturation::of(&m).unwrap();
        assert_eq!(
            (s.shaping, s.output_shaping, s.input_shaping),
            ("tanh", None, Some("tanh"))
        );
        assert!((s.range.0 + 11.0).abs() < 1e-12 && (s.range.1 - 11.0).abs() < 1e-12);
        assert!((s.limits.0 + 8.99).abs() < 1e-12 && (s.limits.1 - 8.99).abs() < 1e-12);
        assert!(!s.widened);
        // From the ends of the band at either end of ψ_in's range, the limits invert.
        for path in [[8.9, -8.99, 8.99], [-8.9, 8.99, -8.99]] {
            let inverse = m.inverse_from_desired(0.0).unwrap();
            let mut inverse = Saturated::new(inverse, Some(s.limits));
            for y in path.into_iter().chain([100.0, -100.0]) {
                let x = inverse.try_step(y).unwrap();
                assert!(x.is_finite() && x.abs() < 4.0, "{y} -> {x}");
            }
        }
        // k1 = 1.2: 2·k1 > 99.9 % of (−1, 1); the limits are the fitted outputs 10 · (±tanh 1 ± k1).
        m.k1 = 1.2;
        let s = Saturation::of(&m).unwrap();
        let fitted = 10.0 * (1.0_f64.tanh() + 1.2);
        assert!((s.limits.1 - fitted).abs() < 1e-9 && s.widened, "{s:?}");
    }
}
