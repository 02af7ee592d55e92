//! The Prandtl–Ishlinskii operator, the baseline most engineers try first, with its analytic
//! inverse: a weighted sum of play (backlash) operators,
//!
//! y = c + w0 (x − b) + Σ_{i=1..n} w_i p_i,   p_i = play_{r_i}[x − b],
//! play_r[x](k) = max(x(k) − r, min(x(k) + r, play_r[x](k − 1))),
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

use crate::{Error, Real};

/// A Prandtl–Ishlinskii operator with up to `N` play operators (see the module docs).
///
/// # Examples
/// ```
/// use hyst_core::PrandtlIshlinskii;
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
    /// A direct operator y = `offset` + w0 x + Σ w_i play_{r_i}[x] with no history.
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

    /// The play outputs p_1..p_n, `None` before the first sample.
    #[must_use]
    pub fn play_states(&self) -> Option<&[T]> {
        self.last_output
            .map(|_| self.plays.get(..self.len).unwrap_or(&[]))
    }

    /// Starts every play at rest at input `x` (as after a long stay at x).
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`] for a non-finite x.
    pub fn start_at(&mut self, x: T) -> Result<(), Error> {
        if !x.is_finite() {
            return Err(Error::NonFiniteInput { value: x.as_f64() });
        }
        let z = x - self.input_offset;
        for p in self.plays.iter_mut().take(self.len) {
            *p = z;
        }
        self.last_output = Some(self.output(z));
        Ok(())
    }

    /// Forgets the history.
    pub fn reset(&mut self) {
        self.last_output = None;
    }

    fn output(&self, z: T) -> T {
        let mut y = self.output_offset + self.identity_weight * z;
        for (w, p) in self.weights.iter().zip(&self.plays).take(self.len) {
            y = y + *w * *p;
        }
        y
    }

    /// One sample.
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`]; the state is then unchanged.
    pub fn try_step(&mut self, x: T) -> Result<T, Error> {
        if !x.is_finite() {
            return Err(Error::NonFiniteInput { value: x.as_f64() });
        }
        let z = x - self.input_offset;
        if self.last_output.is_none() {
            for p in self.plays.iter_mut().take(self.len) {
                *p = z;
            }
        }
        for (p, r) in self.plays.iter_mut().zip(&self.thresholds).take(self.len) {
            *p = (z - *r).max((z + *r).min(*p));
        }
        let y = self.output(z);
        self.last_output = Some(y);
        Ok(y)
    }

    /// One sample; a non-finite input holds the last output (the input itself before any).
    pub fn step(&mut self, x: T) -> T {
        match self.try_step(x) {
            Ok(y) => y,
            Err(_) => self.last_output.unwrap_or(x),
        }
    }

    /// The inverse operator (the compensator), with its plays set so that from here on
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

    /// Processes a block of samples in place (each as [`PrandtlIshlinskii::step`]).
    pub fn process_in_place(&mut self, samples: &mut [T]) {
        for x in samples.iter_mut() {
            *x = self.step(*x);
        }
    }
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
