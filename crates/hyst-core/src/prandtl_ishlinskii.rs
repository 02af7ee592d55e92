//! The Prandtl–Ishlinskii operator, the baseline most engineers try first, with its analytic
//! inverse: a weighted sum of play (backlash) operators,
//!
//! y = c + w0 (x − b) + Σ_{i=1..n} w_i p_i,   p_i = play_{r_i}[x − b],
//! play_r\[x\](k) = max(x(k) − r, min(x(k) + r, play_r\[x\](k − 1))),
//!
//! with thresholds 0 < r_1 < … < r_n, the identity weight w0 > 0, and cumulative weights
//! W_i = w0 + w_1 + … + w_i > 0 (the slope of the loading curve between r_i and r_{i+1}), which
//! make the operator strictly increasing on every monotone segment and invertible.
//!
//! The inverse is again of this form (Kuhnen 2003, "Modeling, identification and compensation
//! of complex hysteretic nonlinearities"): thresholds r'_i = Σ_{j≤i} w_j (r_i − r_j), identity
//! weight 1/w0, weights w'_i = −w_i / (W_i W_{i−1}), input offset c and output offset b; its play
//! states follow from the direct ones as p'_i = W_i p_i + Σ_{j>i} w_j p_j, so
//! [`PrandtlIshlinskii::inverse`] continues exactly where the direct operator stands.
//!
//! Storage is a const-generic capacity `N` (no allocation); `len ≤ N` plays are in use. The
//! first sample without history puts every play at rest at that input.
//!
//! [`ShapedPrandtlIshlinskii`] follows the sum with a monotone output polynomial P (degree ≤ 3,
//! strictly increasing on its domain, continued by tangents outside: [`Polynomial`]):
//! y = P(PI\[x\]). Its inverse [`InverseShapedPrandtlIshlinskii`] is PI⁻¹ ∘ P⁻¹: the analytic PI
//! inverse above after the polynomial's inverse ([`Shaping::invert`]), so it stays exact.
//!
//! Time derivatives ([`PrandtlIshlinskii::try_step`](crate::Operator::try_step) on a [`crate::Jet`]) are value-exact and
//! piecewise: a play at the edge of its band that the input pushes (the lowest-order non-zero
//! derivative of the input points outwards) moves with the input, every other play is stuck, so
//! every derivative of the output is (w0 + Σ_{moving} w_i) times the input's.

use crate::error::Error;
use crate::operator::Operator;
use crate::play;
use crate::real::Real;
use crate::sample::Sample;
use crate::shaping::{Polynomial, Shaping};

/// A Prandtl–Ishlinskii operator with up to `N` play operators (see the module docs).
///
/// # Examples
/// ```
/// use hyst_core::{Operator, PrandtlIshlinskii};
/// let mut pi = PrandtlIshlinskii::<f64, 8>::new(0.5, &[0.1, 0.2, 0.4], &[0.3, 0.2, 0.1], 0.0)?;
/// let mut inv = pi.inverse()?;
/// for k in 0..200 {
///     let y = (k as f64 * 0.07).sin();
///     let x = inv.step(y);
///     assert!((pi.step(x) - y).abs() < 1e-12);
/// }
/// # Ok::<(), hyst_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrandtlIshlinskii<T, const N: usize> {
    len: usize,
    identity_weight: T,
    thresholds: [T; N],
    weights: [T; N],
    input_offset: T,
    output_offset: T,
    plays: [T; N],
    last_output: Option<T>,
}

impl<T: Real, const N: usize> PrandtlIshlinskii<T, N> {
    /// A direct operator y = `offset` + w0 x + Σ w_i play_{r_i}\[x\] with no history.
    ///
    /// # Errors
    /// [`Error::LengthMismatch`] when `thresholds` and `weights` differ in length or exceed `N`;
    /// [`Error::InvalidParameter`] for non-finite values, w0 ≤ 0, thresholds not strictly
    /// increasing and > 0, or a cumulative weight W_i ≤ 0.
    pub fn new(w0: T, thresholds: &[T], weights: &[T], offset: T) -> Result<Self, Error> {
        Self::with_offsets(w0, thresholds, weights, T::zero(), offset)
    }

    /// The general form y = `output_offset` + w0 (x − b) + Σ w_i play_{r_i}[x − b] with
    /// b = `input_offset` (the inverse operator has both).
    ///
    /// # Errors
    /// As [`PrandtlIshlinskii::new`].
    pub fn with_offsets(
        w0: T,
        thresholds: &[T],
        weights: &[T],
        input_offset: T,
        output_offset: T,
    ) -> Result<Self, Error> {
        if thresholds.len() != weights.len() || thresholds.len() > N {
            return Err(Error::LengthMismatch {
                input: thresholds.len(),
                output: weights.len().max(if thresholds.len() > N { N } else { 0 }),
            });
        }
        let bad = |name: &'static str, value: T, expected: &'static str| Error::InvalidParameter {
            name,
            value: value.as_f64(),
            expected,
        };
        if !(w0.is_finite() && w0 > T::zero()) {
            return Err(bad("identity weight w0", w0, "finite and > 0"));
        }
        if !input_offset.is_finite() {
            return Err(bad("input offset", input_offset, "finite"));
        }
        if !output_offset.is_finite() {
            return Err(bad("output offset", output_offset, "finite"));
        }
        let mut t = [T::zero(); N];
        let mut w = [T::zero(); N];
        let mut previous = T::zero();
        let mut cumulative = w0;
        for (i, (r, wi)) in thresholds.iter().zip(weights).enumerate() {
            if !(r.is_finite() && *r > previous) {
                return Err(bad(
                    "threshold",
                    *r,
                    "finite, > 0 and greater than the previous threshold",
                ));
            }
            if !wi.is_finite() {
                return Err(bad("weight", *wi, "finite"));
            }
            cumulative = cumulative + *wi;
            if cumulative.is_nan() || cumulative <= T::zero() {
                return Err(bad(
                    "weight",
                    *wi,
                    "a cumulative weight w0 + w1 + … + wi > 0 (monotone loading curve)",
                ));
            }
            previous = *r;
            if let (Some(ts), Some(ws)) = (t.get_mut(i), w.get_mut(i)) {
                *ts = *r;
                *ws = *wi;
            }
        }
        Ok(Self {
            len: thresholds.len(),
            identity_weight: w0,
            thresholds: t,
            weights: w,
            input_offset,
            output_offset,
            plays: [T::zero(); N],
            last_output: None,
        })
    }

    /// Number of play operators in use.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no play operator is in use (then the operator is affine).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The identity weight w0.
    #[must_use]
    pub fn identity_weight(&self) -> T {
        self.identity_weight
    }

    /// The thresholds r_1..r_n (input units).
    #[must_use]
    pub fn thresholds(&self) -> &[T] {
        self.thresholds.get(..self.len).unwrap_or(&[])
    }

    /// The weights w_1..w_n.
    #[must_use]
    pub fn weights(&self) -> &[T] {
        self.weights.get(..self.len).unwrap_or(&[])
    }

    /// The input offset b.
    #[must_use]
    pub fn input_offset(&self) -> T {
        self.input_offset
    }

    /// The output offset c.
    #[must_use]
    pub fn output_offset(&self) -> T {
        self.output_offset
    }

    fn output(&self, z: T) -> T {
        let mut y = self.output_offset + self.identity_weight * z;
        for (w, p) in self.weights.iter().zip(&self.plays).take(self.len) {
            y = y + *w * *p;
        }
        y
    }

    /// The plays and the output for a finite input x (the value path of
    /// [`Operator::try_step`]).
    fn advance(&mut self, x: T) -> T {
        let z = x - self.input_offset;
        if self.last_output.is_none() {
            for p in self.plays.iter_mut().take(self.len) {
                *p = z;
            }
        }
        for (p, r) in self.plays.iter_mut().zip(&self.thresholds).take(self.len) {
            *p = play::update(*p, z, *r);
        }
        let y = self.output(z);
        self.last_output = Some(y);
        y
    }

    /// The exact inverse operator, with its plays set so that from here on
    /// `self.step(inverse.step(y))` = y. Inverting twice gives back this operator.
    ///
    /// # Errors
    /// Only if the inverse's parameters overflow (the checks of [`PrandtlIshlinskii::new`]).
    pub fn inverse(&self) -> Result<Self, Error> {
        let n = self.len;
        let w0 = self.identity_weight;
        let mut t = [T::zero(); N];
        let mut w = [T::zero(); N];
        // W_i with W_0 = w0, r_0 = 0.
        let mut cumulative = w0;
        for i in 0..n {
            let (Some(ri), Some(wi)) = (self.thresholds.get(i), self.weights.get(i)) else {
                break;
            };
            // r'_i = w0 r_i + Σ_{1≤j≤i} w_j (r_i − r_j)
            let mut r = w0 * *ri;
            for (rj, wj) in self.thresholds.iter().zip(&self.weights).take(i + 1) {
                r = r + *wj * (*ri - *rj);
            }
            let before = cumulative;
            cumulative = cumulative + *wi;
            if let (Some(ts), Some(ws)) = (t.get_mut(i), w.get_mut(i)) {
                *ts = r;
                *ws = -*wi / (cumulative * before);
            }
        }
        let mut inv = Self::with_offsets(
            T::one() / w0,
            t.get(..n).unwrap_or(&[]),
            w.get(..n).unwrap_or(&[]),
            self.output_offset,
            self.input_offset,
        )?;
        if let Some(y) = self.last_output {
            // p'_i = W_i p_i + Σ_{j>i} w_j p_j
            let mut cumulative = w0;
            for i in 0..n {
                let (Some(wi), Some(pi)) = (self.weights.get(i), self.plays.get(i)) else {
                    break;
                };
                cumulative = cumulative + *wi;
                let mut s = cumulative * *pi;
                for (wj, pj) in self.weights.iter().zip(&self.plays).take(n).skip(i + 1) {
                    s = s + *wj * *pj;
                }
                if let Some(p) = inv.plays.get_mut(i) {
                    *p = s;
                }
            }
            // The inverse's last output is the direct operator's last input.
            inv.last_output = Some(self.last_input_from(y));
        }
        Ok(inv)
    }

    /// The last input, recovered from the last output and the plays (used to mirror the state).
    fn last_input_from(&self, y: T) -> T {
        let mut rest = y - self.output_offset;
        for (w, p) in self.weights.iter().zip(&self.plays).take(self.len) {
            rest = rest - *w * *p;
        }
        rest / self.identity_weight + self.input_offset
    }

    /// The slope of the output for an input at z (after the offset) moving in direction `trend`
    /// (see [`Operator::try_step`]); w0 when the input does not move.
    fn slope(&self, z: T, trend: Option<bool>) -> T {
        let mut slope = self.identity_weight;
        let Some(rising) = trend else {
            return slope;
        };
        for ((p, r), w) in self
            .plays
            .iter()
            .zip(&self.thresholds)
            .zip(&self.weights)
            .take(self.len)
        {
            if play::is_pushed(*p, z, *r, Some(rising)) {
                slope = slope + *w;
            }
        }
        slope
    }
}

/// The history of a Prandtl–Ishlinskii operator: the play outputs (after the input offset) and
/// the last output, `None` before the first sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlayMemory<T, const N: usize> {
    /// The play outputs p_1..p_N (only the first `len()` are in use).
    pub plays: [T; N],
    /// The last output; `None` before the first sample (the plays are then unused).
    pub last_output: Option<T>,
}

impl<T: Real, const N: usize> Operator<T> for PrandtlIshlinskii<T, N> {
    type Memory = PlayMemory<T, N>;

    /// One sample, plain or a jet. Every derivative is the input's times the current slope
    /// w0 + Σ w_i over the plays that move ([`play::is_pushed`]: a play on the edge of its band
    /// that the input's lowest-order non-zero derivative pushes); a stuck play contributes
    /// nothing. This is exact wherever the play states do not switch between samples' instants.
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`] for a non-finite value or derivative; the state is then
    /// unchanged.
    fn try_step<S: Sample<T>>(&mut self, x: S) -> Result<S, Error> {
        let v = x.value();
        if !x.all_finite() {
            return Err(Error::NonFiniteInput { value: v.as_f64() });
        }
        let y = self.advance(v);
        let slope = self.slope(v - self.input_offset, x.trend());
        Ok((x - v) * slope + y)
    }

    fn last_output(&self) -> Option<T> {
        self.last_output
    }

    /// Forgets the history (the next sample puts every play at rest).
    fn reset(&mut self) {
        self.last_output = None;
    }

    fn memory(&self) -> PlayMemory<T, N> {
        PlayMemory {
            plays: self.plays,
            last_output: self.last_output,
        }
    }

    /// # Errors
    /// [`Error::InvalidParameter`] for a non-finite play output or last output.
    fn set_memory(&mut self, memory: PlayMemory<T, N>) -> Result<(), Error> {
        for p in memory.plays.iter().take(self.len) {
            crate::error::finite("play output", *p)?;
        }
        if let Some(y) = memory.last_output {
            crate::error::finite("last output", y)?;
        }
        self.plays = memory.plays;
        self.last_output = memory.last_output;
        Ok(())
    }
}

/// A Prandtl–Ishlinskii operator followed by a strictly increasing output polynomial:
/// y = P(PI\[x\]) (see the module docs). Copy, no allocation.
///
/// # Examples
/// ```
/// use hyst_core::{
///     prandtl_ishlinskii::ShapedPrandtlIshlinskii, Operator, Polynomial, PrandtlIshlinskii,
/// };
/// let pi = PrandtlIshlinskii::<f64, 4>::new(0.5, &[0.1, 0.3], &[0.4, 0.2], 0.0)?;
/// let p = Polynomial::new([0.0, 1.0, 0.2, 0.05], -2.0, 2.0)?;
/// let mut model = ShapedPrandtlIshlinskii::new(pi, p)?;
/// let mut comp = model.inverse()?;
/// for k in 0..300 {
///     let y = 0.8 * (k as f64 * 0.05).sin();
///     let x = comp.try_step(y)?;
///     assert!((model.try_step(x)? - y).abs() < 1e-12);
/// }
/// # Ok::<(), hyst_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapedPrandtlIshlinskii<T, const N: usize> {
    pi: PrandtlIshlinskii<T, N>,
    output: Polynomial<T>,
}

impl<T: Real, const N: usize> ShapedPrandtlIshlinskii<T, N> {
    /// P ∘ PI, with P checked to be strictly increasing on its domain.
    ///
    /// # Errors
    /// The polynomial's [`Shaping::validate`] error ([`Error::InvalidParameter`],
    /// [`Error::NotMonotone`]).
    pub fn new(pi: PrandtlIshlinskii<T, N>, output: Polynomial<T>) -> Result<Self, Error> {
        output.validate()?;
        Ok(Self { pi, output })
    }

    /// The Prandtl–Ishlinskii part (with its state).
    #[must_use]
    pub fn pi(&self) -> &PrandtlIshlinskii<T, N> {
        &self.pi
    }

    /// The output polynomial P.
    #[must_use]
    pub fn output(&self) -> &Polynomial<T> {
        &self.output
    }

    /// The exact inverse PI⁻¹ ∘ P⁻¹, continuing from this state so that from here on
    /// `self.step(inverse.step(y))` = y.
    ///
    /// # Errors
    /// As [`PrandtlIshlinskii::inverse`].
    pub fn inverse(&self) -> Result<InverseShapedPrandtlIshlinskii<T, N>, Error> {
        Ok(InverseShapedPrandtlIshlinskii {
            output: self.output,
            pi_inverse: self.pi.inverse()?,
        })
    }
}

impl<T: Real, const N: usize> Operator<T> for ShapedPrandtlIshlinskii<T, N> {
    type Memory = PlayMemory<T, N>;

    /// One sample, plain or a jet: P(PI\[x\]) with the derivatives of the PI sum carried
    /// through P.
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`]; the state is then unchanged.
    fn try_step<S: Sample<T>>(&mut self, x: S) -> Result<S, Error> {
        let s = self.pi.try_step(x)?;
        Ok(self.output.apply(s))
    }

    fn last_output(&self) -> Option<T> {
        self.pi.last_output.map(|s| self.output.apply(s))
    }

    forward_memory!(pi, PlayMemory<T, N>);
}

/// The inverse of [`ShapedPrandtlIshlinskii`]: x = PI⁻¹[P⁻¹(y)], with the analytic PI inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InverseShapedPrandtlIshlinskii<T, const N: usize> {
    output: Polynomial<T>,
    pi_inverse: PrandtlIshlinskii<T, N>,
}

impl<T: Real, const N: usize> InverseShapedPrandtlIshlinskii<T, N> {
    /// The inverse Prandtl–Ishlinskii operator (with its state).
    #[must_use]
    pub fn pi_inverse(&self) -> &PrandtlIshlinskii<T, N> {
        &self.pi_inverse
    }

    /// The output polynomial P of the direct model.
    #[must_use]
    pub fn output(&self) -> &Polynomial<T> {
        &self.output
    }

    /// The direct model P ∘ PI, continuing from this state.
    ///
    /// # Errors
    /// As [`PrandtlIshlinskii::inverse`].
    pub fn inverse(&self) -> Result<ShapedPrandtlIshlinskii<T, N>, Error> {
        Ok(ShapedPrandtlIshlinskii {
            pi: self.pi_inverse.inverse()?,
            output: self.output,
        })
    }
}

impl<T: Real, const N: usize> Operator<T> for InverseShapedPrandtlIshlinskii<T, N> {
    type Memory = PlayMemory<T, N>;

    /// One sample, plain or a jet: the command for the desired output y (and its derivatives).
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`] for a non-finite y; the state is then unchanged.
    fn try_step<S: Sample<T>>(&mut self, y: S) -> Result<S, Error> {
        if !y.all_finite() {
            return Err(Error::NonFiniteInput {
                value: y.value().as_f64(),
            });
        }
        let s = self.output.invert_sample(y)?;
        self.pi_inverse.try_step(s)
    }

    fn last_output(&self) -> Option<T> {
        self.pi_inverse.last_output
    }

    forward_memory!(pi_inverse, PlayMemory<T, N>);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signal(k: usize) -> f64 {
        let t = k as f64 * 0.05;
        (1.0 + 0.3 * t).min(3.0) * t.sin() + 0.4 * (2.7 * t).cos()
    }

    #[test]
    fn inverse_is_exact_from_any_state() -> Result<(), Error> {
        let mut pi = PrandtlIshlinskii::<f64, 16>::new(
            0.4,
            &[0.1, 0.25, 0.5, 0.9, 1.4],
            &[0.5, 0.0, 0.3, 0.2, 0.05],
            -1.5,
        )?;
        for k in 0..137 {
            pi.step(signal(k));
        }
        let mut inv = pi.inverse()?;
        for k in 0..2000 {
            let y = 0.8 * signal(k + 7) - 1.2;
            let x = inv.step(y);
            let back = pi.step(x);
            assert!((back - y).abs() < 1e-12, "{k}: {back} vs {y}");
        }
        Ok(())
    }

    #[test]
    fn double_inverse_is_the_operator() -> Result<(), Error> {
        let pi = PrandtlIshlinskii::<f64, 4>::new(0.7, &[0.2, 0.3], &[0.4, 0.1], 2.0)?;
        let back = pi.inverse()?.inverse()?;
        assert!((back.identity_weight() - 0.7).abs() < 1e-15);
        for (a, b) in back.thresholds().iter().zip(pi.thresholds()) {
            assert!((a - b).abs() < 1e-15);
        }
        for (a, b) in back.weights().iter().zip(pi.weights()) {
            assert!((a - b).abs() < 1e-15);
        }
        assert!((back.output_offset() - 2.0).abs() < 1e-15);
        Ok(())
    }

    #[test]
    fn play_is_a_backlash() -> Result<(), Error> {
        // w0 tiny, one play of half-width 0.5 with weight 1
        let mut pi = PrandtlIshlinskii::<f64, 1>::new(1e-12, &[0.5], &[1.0], 0.0)?;
        assert!((pi.step(0.0)).abs() < 1e-9);
        assert!((pi.step(1.0) - 0.5).abs() < 1e-9);
        assert!((pi.step(0.6) - 0.5).abs() < 1e-9); // inside the gap: held
        assert!((pi.step(-1.0) + 0.5).abs() < 1e-9);
        Ok(())
    }

    #[test]
    fn shaped_inverse_is_exact_and_round_trips() -> Result<(), Error> {
        let pi = PrandtlIshlinskii::<f64, 8>::new(
            0.4,
            &[0.1, 0.25, 0.5, 0.9],
            &[0.5, 0.1, 0.3, 0.2],
            0.3,
        )?;
        // Increasing on [-3, 4] (P' = 1 − 0.2 s + 0.09 s² > 0), tangents outside.
        let p = Polynomial::new([0.2, 1.0, -0.1, 0.03], -3.0, 4.0)?;
        let mut model = ShapedPrandtlIshlinskii::new(pi, p)?;
        for k in 0..53 {
            model.step(signal(k));
        }
        let mut comp = model.inverse()?;
        for k in 0..2000 {
            let y = 2.5 * signal(k + 3) + 0.4;
            let x = comp.try_step(y)?;
            let back = model.try_step(x)?;
            assert!(
                (back - y).abs() < 1e-12 * (1.0 + y.abs()),
                "{k}: {back} vs {y}"
            );
        }
        // Inverting twice gives the same direct model, state included.
        let mut again = comp.inverse()?;
        for k in 0..200 {
            let x = signal(k + 11);
            assert!((again.try_step(x)? - model.try_step(x)?).abs() < 1e-12);
        }
        // A non-monotone polynomial is refused.
        assert!(matches!(
            ShapedPrandtlIshlinskii::new(
                pi,
                Polynomial {
                    coefficients: [0.0, 1.0, -1.0, 0.0],
                    lo: -1.0,
                    hi: 1.0
                }
            ),
            Err(Error::NotMonotone { .. })
        ));
        Ok(())
    }

    #[test]
    fn jet_derivatives_follow_the_moving_plays() -> Result<(), Error> {
        use crate::jet::Jet;
        let mut pi = PrandtlIshlinskii::<f64, 2>::new(0.5, &[0.1, 0.3], &[1.0, 2.0], 0.0)?;
        // At rest: every play stuck, slope w0.
        let y = pi.try_step(Jet::<f64, 2>::from_derivatives(0.0, [1.0, 3.0]))?;
        assert_eq!(y.derivatives(), [0.5, 1.5]);
        // 0.2 above the start: the first play (r = 0.1) is dragged, the second is not.
        let y = pi.try_step(Jet::<f64, 2>::from_derivatives(0.2, [1.0, 3.0]))?;
        assert_eq!(y.value(), 0.5 * 0.2 + 1.0 * 0.1);
        assert_eq!(y.derivatives(), [1.5, 4.5]);
        // Both dragged.
        let y = pi.try_step(Jet::<f64, 2>::from_derivatives(0.5, [2.0, 0.0]))?;
        assert_eq!(y.derivatives(), [7.0, 0.0]);
        // Same place, now falling: every play leaves its upper edge, slope w0.
        let y = pi.try_step(Jet::<f64, 2>::from_derivatives(0.5, [-2.0, 0.0]))?;
        assert_eq!(y.derivatives(), [-1.0, 0.0]);
        // First derivative 0, second > 0: rising by the second derivative.
        let y = pi.try_step(Jet::<f64, 2>::from_derivatives(0.5, [0.0, 1.0]))?;
        assert_eq!(y.derivatives(), [0.0, 3.5]);
        // The value equals the plain step; the derivative matches a finite difference of a
        // smooth input away from switching instants.
        let mut a = PrandtlIshlinskii::<f64, 2>::new(0.5, &[0.1, 0.3], &[1.0, 2.0], 0.0)?;
        let mut b = a;
        let h = 1e-7;
        let mut mismatches = 0;
        for k in 0..400 {
            let t = k as f64 * 0.01;
            let jet = a.try_step(Jet::<f64, 1>::from_derivatives(t.sin(), [t.cos()]))?;
            let mut c = b;
            let y0 = b.try_step(t.sin())?;
            assert_eq!(jet.value(), y0);
            let fd = (c.try_step((t + h).sin())? - y0) / h;
            if (fd - jet.derivatives()[0]).abs() > 1e-5 {
                mismatches += 1;
            }
        }
        // Only where a play engages or is released within h of a sample can they differ:
        // sin t from 0 to 1 and back to −0.76 engages/releases the two plays 6 times.
        assert!(
            mismatches <= 6,
            "{mismatches} samples disagree with finite differences"
        );
        assert!(pi
            .try_step(Jet::<f64, 1>::from_derivatives(0.0, [f64::NAN]))
            .is_err());
        Ok(())
    }

    #[test]
    fn refuses_bad_parameters() -> Result<(), Error> {
        type P = PrandtlIshlinskii<f64, 2>;
        assert!(P::new(0.0, &[0.1], &[1.0], 0.0).is_err());
        assert!(P::new(1.0, &[0.2, 0.1], &[1.0, 1.0], 0.0).is_err());
        assert!(P::new(1.0, &[0.1, 0.2, 0.3], &[1.0, 1.0, 1.0], 0.0).is_err());
        assert!(P::new(1.0, &[0.1], &[-1.0], 0.0).is_err());
        assert!(P::new(1.0, &[0.1], &[f64::NAN], 0.0).is_err());
        let mut ok = P::new(1.0, &[0.1], &[0.5], 0.0)?;
        assert_eq!(ok.len(), 1);
        let y = ok.step(1.0);
        assert_eq!(ok.step(f64::NAN), y);
        assert!(ok.try_step(f64::INFINITY).is_err());
        Ok(())
    }
}
