//! Families of operators (Definition 2.8, eqs. 9–10) and their error bounds: Δa of
//! Proposition 3.2 (eqs. 12–14, with the corrected denominator of eq. 13), Δb ≤ Δa of
//! Proposition 3.3 (eq. 15), the bound after an output shaping function, the parameter deviation
//! Δk2 of Proposition 4.3, the envelope Υ(RH)\[v\] of a family along an input signal, and a check
//! that measured data is reproducible by a family.
//!
//! # The bound as implemented
//! For the exact inverse H⁻¹(k1, k2) and a family member H⁻¹(k̄1, k̄2), the worst-case error on
//! a monotone segment (eq. 14) is, with ũd ≥ 0 the transformed input,
//!
//! Δx(ũd) = k̄1 − k1 + 2 (k1 e^(−k2 ũd) − k̄1 e^(−k̄2 ũd)).
//!
//! Its end values are Δx(0) = k1 − k̄1 and Δx(∞) = k̄1 − k1. Its only stationary point
//! (∂Δx/∂ũd = 0) is ũd* = ln(k̄1 k̄2 / (k1 k2)) / (k̄2 − k2) — eq. (13) prints the denominator as
//! "k2 − k2", a misprint — taken when it is finite and > 0; for k̄2 = k2 there is none. The corner
//! value Δxi is Δx at max(ũd*, 0) for each of the four corners (k1 ∓ Δk1, k2 ∓ Δk2) of eq. (13),
//! and Δa = max over the corners of max(|Δxi|, |k̄1 − k1|), the last term covering ũd → ∞.

use crate::error::{finite, positive, Error};
use crate::k2law::{ConstantK2, K2Law};
use crate::operator::Operator;
use crate::parametric::{Hysteresis, InverseHysteresis};
use crate::real::Real;
use crate::sample::Sample;
use crate::shaping::Shaping;

/// Eq. (14): the worst-case error Δx(ũd) = k̄1 − k1 + 2 (k1 e^(−k2 ũd) − k̄1 e^(−k̄2 ũd)) between
/// H⁻¹(k̄1, k̄2) and H⁻¹(k1, k2) at the transformed input ũd ≥ 0 (output units of H⁻¹).
#[must_use]
pub fn delta_x<T: Real>(k1: T, k1_bar: T, k2: T, k2_bar: T, ud: T) -> T {
    let two = T::from_f64(2.0);
    k1_bar - k1 + two * (k1 * (-k2 * ud).exp() - k1_bar * (-k2_bar * ud).exp())
}

/// The stationary point ũd* = ln(k̄1 k̄2 / (k1 k2)) / (k̄2 − k2) of eq. (14) (eq. 13 with its
/// denominator corrected to k̄2 − k2), clipped to ũd ≥ 0: `max(ũd*, 0)`. Returns 0 when there is
/// no finite stationary point (k̄2 = k2).
#[must_use]
pub fn extremum_point<T: Real>(k1: T, k1_bar: T, k2: T, k2_bar: T) -> T {
    let x = ((k1_bar * k2_bar) / (k1 * k2)).ln() / (k2_bar - k2);
    if x.is_finite() && x > T::zero() {
        x
    } else {
        T::zero()
    }
}

/// One corner value Δxi of eq. (13): Δx of eq. (14) at `max(ũd*, 0)` (see [`extremum_point`]).
#[must_use]
pub fn corner_value<T: Real>(k1: T, k1_bar: T, k2: T, k2_bar: T) -> T {
    delta_x(
        k1,
        k1_bar,
        k2,
        k2_bar,
        extremum_point(k1, k1_bar, k2, k2_bar),
    )
}

/// The bound of Proposition 3.2 for one family RH(k1, Δk1, k2, Δk2) with constant k2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound<T> {
    /// Δa (eq. 12): the largest |H⁻¹(k̄1, k̄2)\[ud\] − H⁻¹(k1, k2)\[ud\]| over the family, in the
    /// output units of H⁻¹ (the input units of H). Also the bound on Δb (eq. 15).
    pub delta_a: T,
    /// Δx1..Δx4 of eq. (13), at the corners (k1 − Δk1, k2 − Δk2), (k1 − Δk1, k2 + Δk2),
    /// (k1 + Δk1, k2 − Δk2), (k1 + Δk1, k2 + Δk2).
    pub corners: [T; 4],
    /// The transformed inputs max(ũd*, 0) at which the corner values are taken.
    pub corner_points: [T; 4],
    /// The corner parameters (k̄1, k̄2), in the order of `corners`.
    pub corner_params: [(T, T); 4],
}

/// Δa of Proposition 3.2 (eqs. 12–13, corrected) with its four corner values.
///
/// # Errors
/// [`Error::InvalidParameter`] unless k1, k2 are finite and > 0, Δk1, Δk2 are finite and ≥ 0,
/// and the family stays positive: k1 − Δk1 > 0 and k2 − Δk2 > 0.
///
/// # Examples
/// Example 1 of the paper, RH(0.14, 0.1, 8, 5):
/// ```
/// let b = hyst_core::family::delta_a(0.14_f64, 0.1, 8.0, 5.0)?;
/// assert!((b.delta_a - 0.1301).abs() < 5e-5);
/// assert!((b.corners[0] + 0.1131).abs() < 5e-5);
/// # Ok::<(), hyst_core::Error>(())
/// ```
pub fn delta_a<T: Real>(k1: T, dk1: T, k2: T, dk2: T) -> Result<Bound<T>, Error> {
    check_family(k1, dk1, k2, dk2)?;
    Ok(corner_bound(k1, dk1, k2, dk2))
}

/// Δa and the corner values for parameters [`check_family`] has accepted.
fn corner_bound<T: Real>(k1: T, dk1: T, k2: T, dk2: T) -> Bound<T> {
    let params = [
        (k1 - dk1, k2 - dk2),
        (k1 - dk1, k2 + dk2),
        (k1 + dk1, k2 - dk2),
        (k1 + dk1, k2 + dk2),
    ];
    let mut corners = [T::zero(); 4];
    let mut points = [T::zero(); 4];
    let mut worst = T::zero();
    for (i, (k1b, k2b)) in params.iter().enumerate() {
        let x = extremum_point(k1, *k1b, k2, *k2b);
        let value = delta_x(k1, *k1b, k2, *k2b, x);
        if let (Some(c), Some(p)) = (corners.get_mut(i), points.get_mut(i)) {
            *c = value;
            *p = x;
        }
        // The end points ũd = 0 and ũd → ∞ have |value| = |k̄1 − k1|.
        worst = worst.max(value.abs()).max((*k1b - k1).abs());
    }
    Bound {
        delta_a: worst,
        corners,
        corner_points: points,
        corner_params: params,
    }
}

/// Δa by brute force: the largest |Δx(ũd)| of eq. (14) over a grid of `n` × `n` parameter
/// pairs in the family's rectangle and `m` transformed inputs ũd ∈ [0, 50 / min k̄2] plus
/// ũd → ∞. A cross-check of [`delta_a`] (which evaluates only the corners, after the
/// monotonicity argument of the proof of Proposition 3.2).
///
/// # Errors
/// As [`delta_a`].
pub fn delta_a_scan<T: Real>(k1: T, dk1: T, k2: T, dk2: T, n: usize, m: usize) -> Result<T, Error> {
    check_family(k1, dk1, k2, dk2)?;
    let n = n.max(2);
    let m = m.max(2);
    let frac = |i: usize, count: usize| T::from_f64(i as f64 / (count - 1) as f64);
    let x_max = T::from_f64(50.0) / (k2 - dk2);
    let mut worst = T::zero();
    for i in 0..n {
        let k1b = k1 - dk1 + (dk1 + dk1) * frac(i, n);
        worst = worst.max((k1b - k1).abs());
        for j in 0..n {
            let k2b = k2 - dk2 + (dk2 + dk2) * frac(j, n);
            for l in 0..m {
                let x = x_max * frac(l, m) * frac(l, m);
                worst = worst.max(delta_x(k1, k1b, k2, k2b, x).abs());
            }
        }
    }
    Ok(worst)
}

fn check_family<T: Real>(k1: T, dk1: T, k2: T, dk2: T) -> Result<(), Error> {
    positive("k1", k1)?;
    positive("k2", k2)?;
    for (name, d) in [("dk1", dk1), ("dk2", dk2)] {
        finite(name, d)?;
        if d < T::zero() {
            return Err(Error::InvalidParameter {
                name,
                value: d.as_f64(),
                expected: ">= 0",
            });
        }
    }
    if k1 - dk1 <= T::zero() {
        return Err(Error::InvalidParameter {
            name: "dk1",
            value: dk1.as_f64(),
            expected: "< k1 (every member needs k1 > 0)",
        });
    }
    if k2 - dk2 <= T::zero() {
        return Err(Error::InvalidParameter {
            name: "dk2",
            value: dk2.as_f64(),
            expected: "< k2 (every member needs k2 > 0)",
        });
    }
    // The corners' arithmetic (sums and differences of the members' outputs) stays finite.
    let most = T::max_value() / T::from_f64(4.0);
    for (name, top, value) in [("k1", k1 + dk1, k1), ("k2", k2 + dk2, k2)] {
        if top.is_nan() || top > most {
            return Err(Error::InvalidParameter {
                name,
                value: value.as_f64(),
                expected: "with its width at most a quarter of the float range (MAX / 4), so \
                           that the bound's arithmetic stays finite",
            });
        }
    }
    Ok(())
}

/// Δa over a range of nominal k2 (an input-dependent k2 = φ(·) taking values in [k2_lo, k2_hi]):
/// the largest Δa of [`delta_a`] over `points` ≥ 2 values of k2 spread over the range, with the
/// values at both ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RangeBound<T> {
    /// The largest Δa over the range.
    pub delta_a: T,
    /// The nominal k2 where it occurs.
    pub at_k2: T,
    /// Δa at k2 = k2_lo.
    pub at_lo: T,
    /// Δa at k2 = k2_hi.
    pub at_hi: T,
}

/// Δa for a family whose nominal k2 ranges over [k2_lo, k2_hi] (Example 1 with φ(in) = 9 − 2 in:
/// k2 ∈ [5, 12]), scanning `points` values of k2.
///
/// # Errors
/// As [`delta_a`] (at k2_lo and k2_hi), or [`Error::InvalidParameter`] when k2_hi < k2_lo.
pub fn delta_a_over_k2_range<T: Real>(
    k1: T,
    dk1: T,
    k2_lo: T,
    k2_hi: T,
    dk2: T,
    points: usize,
) -> Result<RangeBound<T>, Error> {
    if k2_hi.is_nan() || k2_lo.is_nan() || k2_hi < k2_lo {
        return Err(Error::InvalidParameter {
            name: "k2_hi",
            value: k2_hi.as_f64(),
            expected: ">= k2_lo",
        });
    }
    let at_lo = delta_a(k1, dk1, k2_lo, dk2)?.delta_a;
    let at_hi = delta_a(k1, dk1, k2_hi, dk2)?.delta_a;
    let mut best = RangeBound {
        delta_a: at_lo,
        at_k2: k2_lo,
        at_lo,
        at_hi,
    };
    let points = points.max(2);
    for i in 0..points {
        let k2 = k2_lo + (k2_hi - k2_lo) * T::from_f64(i as f64 / (points - 1) as f64);
        let d = delta_a(k1, dk1, k2, dk2)?.delta_a;
        if d > best.delta_a {
            best.delta_a = d;
            best.at_k2 = k2;
        }
    }
    Ok(best)
}

/// The bound after an output shaping function ψ_out: Δ · L, with L = sup ψ_out' on the working
/// interval [lo, hi] of the operator output (the Lipschitz constant of ψ_out there).
pub fn shaped_bound<T: Real, O: Shaping<T>>(delta: T, output: &O, lo: T, hi: T) -> T {
    delta * output.lipschitz(lo, hi)
}

/// Proposition 4.3: with k2 = φ(·), the direct operator uses φ(v) and the inverse φ(ud), with
/// |v − ud| ≤ k1, so the pair differs by Δk2* ≤ sup over [lo, hi] of |φ'| · k1.
pub fn delta_k2_prop43<T: Real, K: K2Law<T>>(law: &K, k1: T, lo: T, hi: T) -> T {
    law.max_slope(lo, hi) * k1
}

/// A k2 law shifted by a constant: k2 = φ(input) + `shift` (a member of a family with
/// input-dependent k2, Definition 2.8 with k2 ± Δk2 around φ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShiftedK2<K, T> {
    /// The nominal law φ.
    pub law: K,
    /// The shift, in the units of k2 (1 / input units).
    pub shift: T,
}

impl<T: Real, K: K2Law<T>> K2Law<T> for ShiftedK2<K, T> {
    #[inline]
    fn k2<S: Sample<T>>(&self, input: S) -> S {
        self.law.k2(input) + self.shift
    }
    fn validate(&self) -> Result<(), Error> {
        finite("k2 shift", self.shift)?;
        self.law.validate()
    }
    fn range(&self, lo: T, hi: T) -> (T, T) {
        let (a, b) = self.law.range(lo, hi);
        (a + self.shift, b + self.shift)
    }
    fn max_slope(&self, lo: T, hi: T) -> T {
        self.law.max_slope(lo, hi)
    }
}

/// A family RH(k1, Δk1, k2, Δk2) of direct operators (eq. 9) and RH⁻¹ of inverse ones (eq. 10):
/// every H(k̄1, k̄2) with |k̄1 − k1| ≤ Δk1 and |k̄2 − k2| ≤ Δk2. The nominal k2 is a law `K`
/// (a constant, or φ(input) as in Example 1; members are then φ(input) + δ, |δ| ≤ Δk2).
///
/// # Examples
/// ```
/// use hyst_core::{family::Family, Operator};
/// let family = Family::new(0.06_f64, 0.005, 5.0, 2.5)?; // Example 2
/// assert!((family.bound().delta_a - 0.0302).abs() < 5e-5);
/// let mut corner = family.member(-1.0, 1.0)?; // H(0.055, 7.5)
/// assert!((corner.k1() - 0.055).abs() < 1e-15);
/// let _ = corner.step(0.3);
/// # Ok::<(), hyst_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Family<T, K = ConstantK2<T>> {
    k1: T,
    dk1: T,
    law: K,
    dk2: T,
}

impl<T: Real> Family<T, ConstantK2<T>> {
    /// RH(k1, Δk1, k2, Δk2) with constant nominal k2.
    ///
    /// # Errors
    /// As [`delta_a`].
    pub fn new(k1: T, dk1: T, k2: T, dk2: T) -> Result<Self, Error> {
        check_family(k1, dk1, k2, dk2)?;
        Ok(Self {
            k1,
            dk1,
            law: ConstantK2(k2),
            dk2,
        })
    }

    /// The nominal k2.
    #[must_use]
    pub fn k2(&self) -> T {
        self.law.0
    }

    /// Δa and the corner values of Proposition 3.2 (also the bound on Δb, Proposition 3.3),
    /// in the output units of H⁻¹. [`Family::new`] has checked the parameters, so this cannot
    /// fail.
    #[must_use]
    pub fn bound(&self) -> Bound<T> {
        corner_bound(self.k1, self.dk1, self.law.0, self.dk2)
    }
}

impl<T: Real, K: K2Law<T> + Clone> Family<T, K> {
    /// A family around an input-dependent k2 = φ(input): members use φ(input) + δ, |δ| ≤ Δk2.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for k1 not finite and > 0, Δk1, Δk2 not finite and ≥ 0, or
    /// Δk1 ≥ k1; the law's own validation errors.
    pub fn with_k2_law(k1: T, dk1: T, law: K, dk2: T) -> Result<Self, Error> {
        check_family(k1, dk1, T::one(), T::zero())?;
        finite("dk2", dk2)?;
        if dk2 < T::zero() {
            return Err(Error::InvalidParameter {
                name: "dk2",
                value: dk2.as_f64(),
                expected: ">= 0",
            });
        }
        law.validate()?;
        Ok(Self { k1, dk1, law, dk2 })
    }

    /// The nominal k1.
    #[must_use]
    pub fn k1(&self) -> T {
        self.k1
    }
    /// Δk1.
    #[must_use]
    pub fn dk1(&self) -> T {
        self.dk1
    }
    /// Δk2.
    #[must_use]
    pub fn dk2(&self) -> T {
        self.dk2
    }
    /// The nominal k2 law.
    #[must_use]
    pub fn law(&self) -> &K {
        &self.law
    }

    /// The member parameters at relative position (a, b) ∈ [−1, 1]²: k̄1 = k1 + a Δk1 and the
    /// k2 shift δ = b Δk2 (a and b are clamped into [−1, 1]; the corners are a, b = ±1).
    #[must_use]
    pub fn member_params(&self, a: T, b: T) -> (T, T) {
        let one = T::one();
        let a = a.max(-one).min(one);
        let b = b.max(-one).min(one);
        (self.k1 + a * self.dk1, b * self.dk2)
    }

    /// The direct member H(k1 + a Δk1, k2 + b Δk2) (eq. 9), with no history.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] when a or b is not finite.
    pub fn member(&self, a: T, b: T) -> Result<Hysteresis<T, ShiftedK2<K, T>>, Error> {
        finite("member position a", a)?;
        finite("member position b", b)?;
        let (k1, shift) = self.member_params(a, b);
        Hysteresis::with_k2_law(
            k1,
            ShiftedK2 {
                law: self.law.clone(),
                shift,
            },
        )
    }

    /// The inverse member H⁻¹(k1 + a Δk1, k2 + b Δk2) (eq. 10), with no history.
    ///
    /// # Errors
    /// As [`Family::member`].
    pub fn inverse_member(
        &self,
        a: T,
        b: T,
    ) -> Result<InverseHysteresis<T, ShiftedK2<K, T>>, Error> {
        finite("member position a", a)?;
        finite("member position b", b)?;
        let (k1, shift) = self.member_params(a, b);
        InverseHysteresis::with_k2_law(
            k1,
            ShiftedK2 {
                law: self.law.clone(),
                shift,
            },
        )
    }

    /// The nominal member H(k1, k2) (no shift).
    ///
    /// # Errors
    /// As [`Family::member`]: the law's own validation, which the family's constructor has
    /// already passed.
    pub fn nominal(&self) -> Result<Hysteresis<T, ShiftedK2<K, T>>, Error> {
        self.member(T::zero(), T::zero())
    }

    /// Δa for this family on a working interval [lo, hi] of the operator input, with k2 = φ
    /// ranging over φ([lo, hi]) and Δk2 widened by Proposition 4.3 when `with_prop43` is true
    /// (Δk2 + sup|φ'| k1: the inverse H⁻¹ uses φ(ud) rather than φ(v)). `points` values of
    /// the nominal k2 are scanned.
    ///
    /// # Errors
    /// As [`delta_a_over_k2_range`].
    pub fn bound_on(
        &self,
        lo: T,
        hi: T,
        with_prop43: bool,
        points: usize,
    ) -> Result<RangeBound<T>, Error> {
        let (k2_lo, k2_hi) = self.law.range(lo, hi);
        let extra = if with_prop43 {
            delta_k2_prop43(&self.law, self.k1, lo, hi)
        } else {
            T::zero()
        };
        delta_a_over_k2_range(self.k1, self.dk1, k2_lo, k2_hi, self.dk2 + extra, points)
    }

    /// The positions (a, b) ∈ [−1, 1]² of a `grid` × `grid` lattice of members, corners
    /// included (`grid` ≥ 2; smaller values use 2), row by row: a = −1 first.
    pub fn lattice(grid: usize) -> impl Iterator<Item = (T, T)> {
        let grid = grid.max(2);
        let pos = move |i: usize| T::from_f64(-1.0 + 2.0 * i as f64 / (grid - 1) as f64);
        (0..grid).flat_map(move |i| (0..grid).map(move |j| (pos(i), pos(j))))
    }

    /// The envelope Υ(RH)\[v\] of the family along the input signal `input` (Section 3): for each
    /// sample, the smallest and the largest output over the `grid` × `grid` [`Family::lattice`]
    /// of members, all started without history. Writes into `lower` and `upper` (same length as
    /// `input`); no allocation.
    ///
    /// # Errors
    /// As [`Family::envelope_with`].
    pub fn envelope(
        &self,
        input: &[T],
        lower: &mut [T],
        upper: &mut [T],
        grid: usize,
    ) -> Result<(), Error> {
        self.envelope_with(input, lower, upper, grid, Ok)
    }

    /// The envelope of any operators built around the family's members: `build` turns each
    /// member H(k1 + a Δk1, k2 + b Δk2) of the lattice into the operator that is run over
    /// `input` (a shaped model with its initial state, say), and `lower` / `upper` receive the
    /// smallest and largest output at each sample.
    ///
    /// # Errors
    /// As [`Family::envelope_of`].
    pub fn envelope_with<O: Operator<T>>(
        &self,
        input: &[T],
        lower: &mut [T],
        upper: &mut [T],
        grid: usize,
        build: impl FnMut(Hysteresis<T, ShiftedK2<K, T>>) -> Result<O, Error>,
    ) -> Result<(), Error> {
        self.envelope_of(Self::lattice(grid), input, lower, upper, build)
    }

    /// The envelope over the members at the positions `members` ((a, b) in [−1, 1]², as
    /// [`Family::lattice`] gives them), each built by `build` and run over `input`: `lower` and
    /// `upper` receive the smallest and largest output at each sample. The one loop over the
    /// members of a family; envelopes of disjoint sets of members combine by taking the smaller
    /// lower and the larger upper value (so the members can be shared among threads).
    ///
    /// # Errors
    /// [`Error::LengthMismatch`] for slices of different lengths; the first error of `build`, or
    /// of a member other than [`Error::NonFiniteInput`] (an invalid k2 from a law that goes
    /// non-positive once shifted by −Δk2). Non-finite input samples give NaN envelope samples.
    pub fn envelope_of<O: Operator<T>>(
        &self,
        members: impl IntoIterator<Item = (T, T)>,
        input: &[T],
        lower: &mut [T],
        upper: &mut [T],
        mut build: impl FnMut(Hysteresis<T, ShiftedK2<K, T>>) -> Result<O, Error>,
    ) -> Result<(), Error> {
        if input.len() != lower.len() || input.len() != upper.len() {
            return Err(Error::LengthMismatch {
                input: input.len(),
                output: lower.len().min(upper.len()),
            });
        }
        lower.iter_mut().for_each(|x| *x = T::infinity());
        upper.iter_mut().for_each(|x| *x = T::neg_infinity());
        for (a, b) in members {
            let mut member = build(self.member(a, b)?)?;
            fold_envelope(core::slice::from_mut(&mut member), input, lower, upper)?;
        }
        Ok(())
    }
}

/// Steps each of the `members` (built and started, in any state) over `input` in turn and
/// folds its outputs into the envelope: `lower` and `upper` take the smaller and larger of
/// their value and the member's output at each sample (start them at +∞ and −∞). The step of
/// [`Family::envelope_of`]; the members keep their memory, so a long input can be folded in
/// consecutive pieces, with the same result as in one.
///
/// # Errors
/// [`Error::LengthMismatch`] for slices of different lengths; the first error of a member
/// other than [`Error::NonFiniteInput`] (a non-finite input sample makes the envelope NaN
/// there).
pub fn fold_envelope<T: Real, O: Operator<T>>(
    members: &mut [O],
    input: &[T],
    lower: &mut [T],
    upper: &mut [T],
) -> Result<(), Error> {
    if input.len() != lower.len() || input.len() != upper.len() {
        return Err(Error::LengthMismatch {
            input: input.len(),
            output: lower.len().min(upper.len()),
        });
    }
    for member in members {
        for ((x, lo), hi) in input.iter().zip(lower.iter_mut()).zip(upper.iter_mut()) {
            match member.try_step(*x) {
                Ok(y) => {
                    *lo = lo.min(y);
                    *hi = hi.max(y);
                }
                Err(Error::NonFiniteInput { .. }) => {
                    *lo = T::nan();
                    *hi = T::nan();
                }
                Err(e) => return Err(e),
            }
        }
    }
    Ok(())
}

/// How well measured data is reproduced by a family (Definition 2.8: at each sample some member
/// gives the measured output), from the family's envelope ([`Family::envelope_with`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reproducibility<T> {
    /// Fraction of the compared samples inside the envelope, within the tolerance (0 when none
    /// was compared).
    pub fraction_inside: T,
    /// The number of compared samples inside the envelope.
    pub inside: usize,
    /// The largest distance of a sample outside the envelope (0 when all are inside), in
    /// output units.
    pub worst_excursion: T,
    /// The index of that sample.
    pub worst_index: usize,
    /// The number of samples compared: finite output and envelope, and weight > 0 when weights
    /// are given.
    pub samples: usize,
}

impl<T: Real> Reproducibility<T> {
    /// Compares measured `output` with the envelope [`lower`, `upper`] sample by sample: a
    /// sample is inside when lower − `tolerance` ≤ output ≤ upper + `tolerance`. Samples whose
    /// weight is ≤ 0 (when `weights` is given) or that are not finite are not compared. Slices
    /// of different lengths are compared over the shortest.
    #[must_use]
    pub fn compare(
        output: &[T],
        weights: Option<&[T]>,
        lower: &[T],
        upper: &[T],
        tolerance: T,
    ) -> Self {
        let mut inside = 0usize;
        let mut counted = 0usize;
        let mut worst = T::zero();
        let mut worst_index = 0usize;
        for (k, ((y, lo), hi)) in output.iter().zip(lower).zip(upper).enumerate() {
            let weighted = match weights {
                Some(w) => w.get(k).is_some_and(|w| *w > T::zero()),
                None => true,
            };
            if !(weighted && y.is_finite() && lo.is_finite() && hi.is_finite()) {
                continue;
            }
            counted += 1;
            let excursion = (*lo - *y).max(*y - *hi).max(T::zero());
            if excursion <= tolerance {
                inside += 1;
            }
            if excursion > worst {
                worst = excursion;
                worst_index = k;
            }
        }
        Self {
            fraction_inside: if counted == 0 {
                T::zero()
            } else {
                T::from_f64(inside as f64 / counted as f64)
            },
            inside,
            worst_excursion: worst,
            worst_index,
            samples: counted,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A family beyond a quarter of the float range is refused; up to it the
    /// bound and its corners are finite.
    #[test]
    fn huge_families_are_refused_or_finite() -> Result<(), Error> {
        assert!(delta_a(1e308_f64, 9e307, 1.0, 0.5).is_err());
        assert!(delta_a(0.5_f64, 0.1, 1e308, 1e307).is_err());
        assert!(Family::new(1e308_f64, 9e307, 1.0, 0.5).is_err());
        for k1 in [1e300_f64, 1e306, 0.6 * f64::MAX / 4.0] {
            let b = delta_a(k1, 0.5 * k1, 1.0, 0.5)?;
            assert!(b.delta_a.is_finite(), "{k1}: {b:?}");
            assert!(b.corners.iter().all(|c| c.is_finite()), "{k1}: {b:?}");
        }
        for k2 in [1e300_f64, 0.6 * f64::MAX / 4.0] {
            let b = delta_a(0.2_f64, 0.1, k2, 0.5 * k2)?;
            assert!(
                b.delta_a.is_finite() && b.corners.iter().all(|c| c.is_finite()),
                "{b:?}"
            );
        }
        Ok(())
    }

    use crate::k2law::AffineK2;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn example1_linear_matches_notes() -> Result<(), Error> {
        let b = delta_a(0.14_f64, 0.1, 8.0, 5.0)?;
        assert!(close(b.delta_a, 0.1301, 5e-5), "{}", b.delta_a);
        let expected = [-0.1131, 0.1000, -0.1301, 0.1209];
        for (c, e) in b.corners.iter().zip(expected) {
            assert!(close(*c, e, 5e-5), "{c} vs {e}");
        }
        // After the output shaping 1.4 out: 0.1822.
        let shaped = shaped_bound(
            b.delta_a,
            &crate::shaping::Affine::new(1.4, 0.0)?,
            -1.0,
            1.0,
        );
        assert!(close(shaped, 0.1822, 5e-5), "{shaped}");
        Ok(())
    }

    #[test]
    fn example2_and_nonlinear_match_notes() -> Result<(), Error> {
        let b = delta_a(0.06_f64, 0.005, 5.0, 2.5)?;
        assert!(close(b.delta_a, 0.0302, 5e-5), "{}", b.delta_a);
        let lo = delta_a(0.105_f64, 0.005, 5.0, 1.235)?.delta_a;
        let hi = delta_a(0.105_f64, 0.005, 12.0, 1.235)?.delta_a;
        assert!(close(lo, 0.0229, 5e-5), "{lo}");
        assert!(close(hi, 0.0102, 5e-5), "{hi}");
        let r = delta_a_over_k2_range(0.105_f64, 0.005, 5.0, 12.0, 1.235, 65)?;
        assert!(close(r.delta_a, lo, 1e-12) && r.at_k2 == 5.0);
        Ok(())
    }

    #[test]
    fn corners_agree_with_a_dense_scan() -> Result<(), Error> {
        for &(k1, dk1, k2, dk2) in &[
            (0.14_f64, 0.1, 8.0, 5.0),
            (0.06, 0.005, 5.0, 2.5),
            (0.105, 0.005, 5.0, 1.235),
            (0.2, 0.15, 3.0, 2.9),
            (1.0, 0.0, 4.0, 0.0),
        ] {
            let corners = delta_a(k1, dk1, k2, dk2)?.delta_a;
            let scan = delta_a_scan(k1, dk1, k2, dk2, 41, 4001)?;
            assert!(scan <= corners * (1.0 + 1e-9) + 1e-15, "{scan} > {corners}");
            assert!(scan >= corners * 0.995, "{scan} << {corners}");
        }
        Ok(())
    }

    #[test]
    fn equal_k2_has_no_interior_extremum() {
        assert_eq!(extremum_point(0.1_f64, 0.12, 5.0, 5.0), 0.0);
        let v = corner_value(0.1_f64, 0.12, 5.0, 5.0);
        assert!(close(v, -0.02, 1e-15));
        assert!(close(delta_x(0.1_f64, 0.12, 5.0, 5.0, 1e9), 0.02, 1e-15));
    }

    #[test]
    fn invalid_families_are_refused() {
        assert!(delta_a(0.1_f64, 0.1, 8.0, 1.0).is_err());
        assert!(delta_a(0.1_f64, 0.01, 8.0, 8.0).is_err());
        assert!(delta_a(0.1_f64, -0.01, 8.0, 1.0).is_err());
        assert!(Family::new(f64::NAN, 0.0, 1.0, 0.0).is_err());
    }

    #[test]
    fn prop43_example1() -> Result<(), Error> {
        let phi = AffineK2::new(9.0_f64, -2.0, 5.0, 12.0)?;
        let d = delta_k2_prop43(&phi, 0.105, -1.5, 2.0);
        assert!(close(d, 0.21, 1e-12));
        assert!(close(phi.max_slope(-1.0, 1.0), 2.0, 1e-12));
        Ok(())
    }

    #[test]
    fn envelope_contains_every_member() -> Result<(), Error> {
        let fam = Family::new(0.1_f64, 0.02, 6.0, 2.0)?;
        let input: [f64; 64] = core::array::from_fn(|k| (k as f64 * 0.3).sin() * (k as f64 / 20.0));
        let mut lo = [0.0; 64];
        let mut hi = [0.0; 64];
        fam.envelope(&input, &mut lo, &mut hi, 5)?;
        let mut m = fam.member(0.3, -0.7)?;
        for ((x, l), h) in input.iter().zip(&lo).zip(&hi) {
            let y = m.step(*x);
            // Interior members lie between the lattice's members up to the lattice spacing.
            assert!(y >= l - 2e-3 && y <= h + 2e-3, "{l} <= {y} <= {h}");
        }
        let mut nominal = fam.nominal()?;
        let out: [f64; 64] = core::array::from_fn(|k| nominal.step(input[k]));
        fam.envelope(&input, &mut lo, &mut hi, 3)?;
        let r = Reproducibility::compare(&out, None, &lo, &hi, 0.0);
        assert_eq!(r.fraction_inside, 1.0);
        assert_eq!((r.inside, r.samples), (64, 64));
        assert_eq!(r.worst_excursion, 0.0);
        let shifted: [f64; 64] = core::array::from_fn(|k| out[k] + 0.5);
        let r = Reproducibility::compare(&shifted, None, &lo, &hi, 0.0);
        assert!(r.fraction_inside < 0.1 && r.worst_excursion > 0.3);
        // Weights: only samples with weight > 0 are compared.
        let weights: [f64; 64] = core::array::from_fn(|k| if k < 10 { 1.0 } else { 0.0 });
        let r = Reproducibility::compare(&out, Some(&weights), &lo, &hi, 0.0);
        assert_eq!((r.inside, r.samples), (10, 10));
        Ok(())
    }
}
