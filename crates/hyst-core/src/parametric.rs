//! The direct (Definition 2.2, eq. 2) and inverse (Definition 2.5, eq. 4) parametric hysteresis
//! operators, as one generic type [`ParametricHysteresis`] whose [`Formula`] is eq. (2) or
//! eq. (4).

use core::marker::PhantomData;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::{positive_normal, Error};
use crate::k2law::{ConstantK2, K2Law};
use crate::memory::{Direction, Memory};
use crate::operator::Operator;
use crate::real::Real;
use crate::sample::Sample;

mod sealed {
    pub trait Sealed {}
}

/// Which formula of the pair the operator evaluates: [`Direct`] (eq. 2) or [`Inverse`] (eq. 4).
pub trait Formula: sealed::Sealed + Copy + core::fmt::Debug {
    /// "direct" or "inverse".
    const NAME: &'static str;
    /// M* from the memory: M(α, β) + k1 for the direct operator, −M(α, β) + k1 for the inverse
    /// (eq. 4; Proposition 2.7 uses the same, see `docs/errata.md`). On every consistent state it
    /// lies in [0, 2 k1].
    fn m_star<T: Real>(memory: &Memory<T>, k1: T) -> T;
    /// The operator's output β for the input α = `x`: eq. (2) or eq. (4) between the
    /// transformation T of Definition 2.1 (α̃ = s (α − α0)) and its inverse (β = β0 + s β̃).
    fn output<T: Real, S: Sample<T>>(memory: &Memory<T>, x: S, m_star: T, k2: S) -> S;
    /// The same output for a plain sample, in a form that overflows only when the result itself
    /// does: the output is written as the input plus its signed distance from the line
    /// output = input, which lies in [−k1, k1] (the band), so no intermediate value is larger
    /// than |x| + 2 k1. Used only when [`Formula::output`] is not finite (a transformed input
    /// s (α − α0) or k2 M* beyond the float range, e.g. α0 = 1e308 and α = −1e308); slower.
    fn output_wide<T: Real>(memory: &Memory<T>, x: T, m_star: T, k2: T) -> T;
}

/// Marker for the direct operator u = H(k1, k2)\[v\] of eq. (2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Direct;

/// Marker for the inverse operator v = H⁻¹(k1, k2)\[u_d\] of eq. (4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Inverse;

impl sealed::Sealed for Direct {}
impl sealed::Sealed for Inverse {}

#[inline]
fn clamp_band<T: Real>(m: T, k1: T) -> T {
    m.max(T::zero()).min(k1 + k1)
}

impl Formula for Direct {
    const NAME: &'static str = "direct";
    #[inline]
    fn m_star<T: Real>(memory: &Memory<T>, k1: T) -> T {
        clamp_band(memory.m() + k1, k1)
    }
    /// Eq. (2) between the transformation of Definition 2.1 and its inverse.
    #[inline]
    fn output<T: Real, S: Sample<T>>(memory: &Memory<T>, x: S, m_star: T, k2: S) -> S {
        memory.untransform(direct_transition(memory.transform(x), m_star, k2))
    }
    /// u = v + s (M − e) with e = ṽ − ũ ∈ [0, min(M*, ṽ)] the root of
    /// e = M* (1 − e^(−k2 (ṽ − e))) (eq. 4 solved for eq. 2's ũ), by safeguarded Newton.
    fn output_wide<T: Real>(memory: &Memory<T>, x: T, m_star: T, k2: T) -> T {
        let e = direct_gap(half_transform(memory, x), m_star, k2);
        x + (memory.m() - e) * memory.direction.sign::<T>()
    }
}

/// The error for the finite input `x` whose output is the non-finite `output`.
#[cold]
#[inline(never)]
fn overflow<T: Real>(x: T, output: T) -> Error {
    Error::NonFiniteOutput {
        input: x.as_f64(),
        output: output.as_f64(),
    }
}

/// ṽ / 2 = s (α/2 − α0/2): half the transformed input of Definition 2.1, finite for all finite
/// α and α0 (ṽ itself overflows when α and α0 are far apart with opposite signs).
#[inline]
fn half_transform<T: Real>(memory: &Memory<T>, alpha: T) -> T {
    let half = T::from_f64(0.5);
    (alpha * half - memory.reversal_input * half) * memory.direction.sign::<T>()
}

/// e^(−k2 z) for z = 2 `z_half`, without forming z (which may overflow while k2 z is moderate).
#[inline]
fn decay<T: Real>(k2: T, z_half: T) -> T {
    let two = T::one() + T::one();
    (-((k2 * z_half) * two)).exp()
}

/// The root e ∈ [0, min(M*, ṽ)] of g(e) = e − M* (1 − e^(−k2 (ṽ − e))), given ṽ / 2 (g is
/// increasing, g(0) ≤ 0, g(min(M*, ṽ)) ≥ 0): Newton steps kept inside the bracket, bisection
/// when a step leaves it. Every intermediate value is finite or +∞ (e^(−∞) = 0), never NaN for
/// finite M*, k2 > 0 and ṽ ≥ 0.
fn direct_gap<T: Real>(v_half: T, m_star: T, k2: T) -> T {
    // Derivatives (duals) from g(e) = 0 at the root, not through the iterations.
    bracketed_gap(v_half, m_star, k2).implicit_root(|e| {
        let t = decay(k2, v_half - e * T::from_f64(0.5));
        (e - m_star * (T::one() - t), T::one() + m_star * (k2 * t))
    })
}

/// The iteration of [`direct_gap`] on the values.
fn bracketed_gap<T: Real>(v_half: T, m_star: T, k2: T) -> T {
    let zero = T::zero();
    let half = T::from_f64(0.5);
    let mut lo = zero;
    let mut hi = m_star.min(v_half + v_half).max(zero);
    let mut e = hi;
    for _ in 0..200 {
        let t = decay(k2, v_half - e * half);
        let g = e - m_star * (T::one() - t);
        if g > zero {
            hi = e;
        } else if g < zero {
            lo = e;
        } else {
            return e;
        }
        let slope = T::one() + m_star * (k2 * t);
        let newton = e - g / slope;
        let next = if slope.is_finite() && newton > lo && newton < hi {
            newton
        } else {
            lo + (hi - lo) / (T::one() + T::one())
        };
        if !(next > lo && next < hi) {
            // Converged: the step is below the resolution, or the bracket is down to adjacent
            // floats.
            return e;
        }
        e = next;
    }
    e
}

/// The repair of a sample whose output value `y` for the input value `v` failed the band test,
/// on plain values (one copy per number type and formula, whatever the sample type or k2 law: a
/// firmware build holds few): a non-finite input is refused; an output value that is not finite
/// is computed again by [`Formula::output_wide`] (refused when that is not finite either); then
/// the value is clamped into [v − k1, v + k1].
#[cold]
#[inline(never)]
fn repair<T: Real, F: Formula>(
    memory: &Memory<T>,
    k1: T,
    v: T,
    y: T,
    m_star: T,
    k2: T,
) -> Result<T, Error> {
    if !v.is_finite() {
        return Err(Error::NonFiniteInput { value: v.as_f64() });
    }
    let y = if y.is_finite() {
        y
    } else {
        let wide = F::output_wide(memory, v, m_star, k2);
        if !wide.is_finite() {
            return Err(overflow(v, wide));
        }
        wide
    };
    Ok(y.max(v - k1).min(v + k1))
}

/// The rare path of [`ParametricHysteresis::advance`]: [`repair`], and on a refusal the undoing
/// of what [`Memory::observe`] changed (it returned `reversed`), so the memory is as it was.
///
/// On a host out of line and by `&mut`: the caller then reads the memory again after the call,
/// and keeps no copy of it in registers across the formula's `exp` for a refusal. On bare metal
/// (built for size) inlined: one swap in the caller takes fewer bytes than one in each copy.
/// The host/bare-metal forks here change the code's shape, not its results: each computes the
/// same values.
#[cfg_attr(not(target_os = "none"), cold, inline(never))]
#[cfg_attr(target_os = "none", inline(always))]
fn rare<T: Real, F: Formula>(
    memory: &mut Memory<T>,
    reversed: bool,
    k1: T,
    v: T,
    y: T,
    m_star: T,
    k2: T,
) -> Result<T, Error> {
    // On a host M* is derived again from the memory (the same value), so the caller keeps
    // nothing for this path across the formula's `exp`; on bare metal the caller's.
    let m_star = if cfg!(target_os = "none") {
        m_star
    } else {
        F::m_star(memory, k1)
    };
    let repaired = repair::<T, F>(memory, k1, v, y, m_star, k2);
    if repaired.is_err() {
        memory.unobserve(reversed);
    }
    repaired
}

/// Eq. (2): ũ = ṽ − M* + W(k2 M* e^(k2 (M* − ṽ))) / k2.
///
/// With a = k2 M*, b = k2 (M* − ṽ) and w = W(a e^b): while a e^b is finite, eq. (2) as
/// printed (its rounding error is a few ulps of max(|ṽ|, M*), below that of the output
/// u = β0 + s ũ itself), with w / k2 formed as w · (1 / k2) with `std`: the reciprocal is taken
/// while `exp` and W run, off the chain of dependent operations that bounds the loop (a division
/// at its end would lengthen that chain). When a e^b overflows, w = ω(ln a + b) (Wright omega,
/// log domain)
/// and, using w + ln w = ln a + b, ũ = (ln a − ln w) / k2, which has no cancellation between
/// large terms: k2 up to 1e12 (near-backlash) stays finite and accurate. At a reversal point
/// (ṽ = 0) the value is exactly 0.
#[inline]
fn direct_transition<T: Real, S: Sample<T>>(v_tilde: S, m_star: T, k2: S) -> S {
    // On a host, a plain sample at the reversal point returns at once (a jet needs its
    // derivatives): then ṽ is not kept across the calls below for the test at the end. The
    // result is the one the end gives it, exactly 0.
    if S::ORDER == 0 && cfg!(not(target_os = "none")) && v_tilde.value() == T::zero() {
        return S::constant(T::zero());
    }
    let a = k2 * m_star;
    let b = k2 * (S::constant(m_star) - v_tilde);
    let x = a * b.exp();
    // x = a e^b is ≥ 0 or NaN (a = k2 M* ≥ 0 finite), so `x < ∞` is `is_finite`, in one compare.
    let u_tilde = if x.value() < T::infinity() {
        let w = x.w0();
        // A dual's gradient of x = a e^b overflows before x does (e^b times k2's gradient);
        // for W > 1 it comes from w + ln w = ln a + b instead (identity on plain floats).
        let w = if w.value() > T::one() {
            w.implicit(|w| {
                let slope = S::constant(T::one()) + S::constant(T::one()) / w;
                (w + w.ln() - (k2.ln() + m_star.ln() + b), slope)
            })
        } else {
            w
        };
        // With `std` w / k2 as w · (1 / k2), the reciprocal off the chain; without (a firmware
        // build, for size: 20 bytes) the division. They differ by an ulp at most, as the
        // two builds' maths do (`Real`).
        if cfg!(feature = "std") {
            v_tilde - m_star + w * (S::constant(T::one()) / k2)
        } else {
            v_tilde - m_star + w / k2
        }
    } else if cfg!(target_os = "none") {
        // Inline on bare metal, out of line on a host: the same operations, the same value.
        let ln_a = k2.ln() + m_star.ln();
        let w = (ln_a + b).omega();
        (ln_a - w.ln()) / k2
    } else {
        // On a host out of line, so that b is not kept across the calls of the common path.
        direct_transition_log(v_tilde, m_star, k2)
    };
    if v_tilde.value() == T::zero() {
        u_tilde.with_value(T::zero())
    } else {
        u_tilde
    }
}

/// The log-domain branch of [`direct_transition`] on a host (a e^b beyond the float range),
/// out of line: b is formed again here (the same value).
#[cold]
#[inline(never)]
fn direct_transition_log<T: Real, S: Sample<T>>(v_tilde: S, m_star: T, k2: S) -> S {
    let b = k2 * (S::constant(m_star) - v_tilde);
    let ln_a = k2.ln() + m_star.ln();
    let w = (ln_a + b).omega();
    (ln_a - w.ln()) / k2
}

/// Eq. (4) of [`Inverse::output`].
#[inline(always)]
fn inverse_output<T: Real, S: Sample<T>>(memory: &Memory<T>, x: S, m_star: T, k2: S) -> S {
    let s = memory.direction;
    let ud_tilde = memory.transform(x);
    let along_input = s.apply(ud_tilde) + memory.reversal_output;
    along_input + (S::constant(T::one()) - (-(k2 * ud_tilde)).exp()) * s.apply(m_star)
}

/// [`inverse_output`] for a jet, inlined where the compiler finds it worth it.
#[inline]
fn inverse_output_jet<T: Real, S: Sample<T>>(memory: &Memory<T>, x: S, m_star: T, k2: S) -> S {
    inverse_output(memory, x, m_star, k2)
}

impl Formula for Inverse {
    const NAME: &'static str = "inverse";
    /// Not clamped: eq. (4) stays well defined for any M*, and the memory only leaves the band by
    /// rounding (a state from outside is checked by `set_memory`).
    #[inline]
    fn m_star<T: Real>(memory: &Memory<T>, k1: T) -> T {
        k1 - memory.m()
    }
    /// Eq. (4), ṽ = ũ_d + M* (1 − e^(−k2 ũ_d)), with Definition 2.1's transformation folded in:
    /// v = (β0 + s ũ_d) + s M* (1 − e^(−k2 ũ_d)), so only two numbers wait for the exponential.
    /// Exactly β0 at a reversal point (ũ_d = 0). 1 − e^(−z) is computed with `exp`, not `expm1`:
    /// its absolute error, ≤ 2 k1 ε, is below the rounding of v itself, and `exp` is faster.
    /// On a host, for plain samples always inlined (LLVM would otherwise make it a call, and the
    /// caller's values would wait in memory across it); for jets left to the compiler (always
    /// inlined, the loop on jets runs slower: its code outgrows the registers).
    #[cfg_attr(not(target_os = "none"), inline(always))]
    #[cfg_attr(target_os = "none", inline)]
    fn output<T: Real, S: Sample<T>>(memory: &Memory<T>, x: S, m_star: T, k2: S) -> S {
        if S::ORDER == 0 {
            inverse_output(memory, x, m_star, k2)
        } else {
            inverse_output_jet(memory, x, m_star, k2)
        }
    }
    /// v = u_d + s (M + M* (1 − e^(−k2 ũ_d))): eq. (4) with β0 − α0 = s M folded in, so an
    /// overflowing ũ_d only makes the exponential 0.
    fn output_wide<T: Real>(memory: &Memory<T>, x: T, m_star: T, k2: T) -> T {
        let s = memory.direction.sign::<T>();
        let gap = memory.m() + m_star * (T::one() - decay(k2, half_transform(memory, x)));
        x + gap * s
    }
}

/// A parametric hysteresis operator with its memory: parameters k1 (half-width of the loop, in
/// output units, > 0) and k2 (rate of the transition, 1/input units, > 0, or a law k2 = φ(input)),
/// the memory of Definition 2.1, and the formula `F` ([`Direct`], eq. 2, or [`Inverse`], eq. 4).
///
/// Use the aliases [`Hysteresis`] and [`InverseHysteresis`]. The value is small and `Copy` (when
/// the k2 law is), never allocates and never panics.
///
/// Non-finite input: [`Operator::try_step`] returns [`Error::NonFiniteInput`] and leaves the
/// memory untouched; [`Operator::step`] then holds the last output (or returns the input as is
/// when there is no history yet). The memory never holds a NaN.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct ParametricHysteresis<T, K, F> {
    k1: T,
    law: K,
    initial: Option<Memory<T>>,
    memory: Option<Memory<T>>,
    formula: PhantomData<F>,
}

/// The direct parametric hysteresis operator u = H(k1, k2)\[v\] (Definition 2.2, eq. 2).
///
/// # Examples
/// ```
/// use hyst_core::{Hysteresis, Operator};
/// let mut h = Hysteresis::new(0.14_f64, 8.0)?;
/// assert_eq!(h.step(0.0), 0.0); // the first sample is a reversal point on u = v
/// let up = h.step(1.0);
/// assert!(up < 1.0 && up > 1.0 - 0.14); // rising: below the line, above the asymptote v − k1
/// # Ok::<(), hyst_core::Error>(())
/// ```
pub type Hysteresis<T, K = ConstantK2<T>> = ParametricHysteresis<T, K, Direct>;

/// The inverse parametric hysteresis operator v = H⁻¹(k1, k2)\[u_d\] (Definition 2.5, eq. 4),
/// the exact left and right inverse of [`Hysteresis`] with the same parameters and initial
/// state (Proposition 4.1).
///
/// # Examples
/// ```
/// use hyst_core::{Hysteresis, InverseHysteresis, Operator};
/// let mut h = Hysteresis::new(0.2_f64, 8.0)?;
/// let mut hinv = InverseHysteresis::new(0.2_f64, 8.0)?;
/// for k in 0..100 {
///     let ud = (k as f64 * 0.1).sin();
///     let v = hinv.step(ud);
///     assert!((h.step(v) - ud).abs() < 1e-12);
/// }
/// # Ok::<(), hyst_core::Error>(())
/// ```
pub type InverseHysteresis<T, K = ConstantK2<T>> = ParametricHysteresis<T, K, Inverse>;

impl<T: Real, F: Formula> ParametricHysteresis<T, ConstantK2<T>, F> {
    /// An operator with constant k2, no history (its first sample becomes a reversal point on
    /// the line output = input).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `k1` or `k2` unless both are finite, > 0 and normal
    /// floats, [`Error::SmallK1K2`] when their product is too small (see
    /// [`ParametricHysteresis::with_k2_law`]).
    pub fn new(k1: T, k2: T) -> Result<Self, Error> {
        Self::with_k2_law(k1, ConstantK2(k2))
    }

    /// k2 (constant).
    #[must_use]
    pub fn k2(&self) -> T {
        self.law.0
    }
}

impl<T: Real, K: K2Law<T>, F: Formula> ParametricHysteresis<T, K, F> {
    /// An operator whose k2 follows `law` (Section 4.3), no history.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming
    /// - `k1` unless it is finite, > 0, a normal float (not subnormal) and at most a quarter of
    ///   the largest float;
    /// - the law's parameter from its own check (a constant `k2` must be finite, > 0 and normal).
    ///
    /// [`Error::SmallK1K2`] when k1 times the law's smallest k2 ([`K2Law::min_k2`]) is below
    /// `T::MIN_POSITIVE / T::EPSILON` (2.0e-292 for f64, 9.9e-32 for f32): then k2 M* in eq. (2)
    /// is subnormal for every M* that matters and the output loses its precision. Such a loop is
    /// below the float resolution anyway; express the input in other units.
    ///
    /// Large products k1 k2 (beyond the float range: `new(1e300, 1e300)`) are accepted: the
    /// operator then evaluates eq. (2) in an overflow-free form (see [`Operator::try_step`]).
    pub fn with_k2_law(k1: T, law: K) -> Result<Self, Error> {
        Self::check_parameters(k1, &law)?;
        Ok(Self {
            k1,
            law,
            initial: None,
            memory: None,
            formula: PhantomData,
        })
    }

    /// The checks of [`ParametricHysteresis::with_k2_law`].
    fn check_parameters(k1: T, law: &K) -> Result<(), Error> {
        positive_normal("k1", k1)?;
        if k1 > T::max_value() * T::from_f64(0.25) {
            return Err(Error::InvalidParameter {
                name: "k1",
                value: k1.as_f64(),
                expected: "at most a quarter of the largest float (4.5e307 for f64, 8.5e37 for \
                           f32), so that the output near any representable input is finite",
            });
        }
        law.validate()?;
        if let Some(k2) = law.min_k2() {
            let product = k1 * k2;
            if product < T::min_positive_value() / T::epsilon() {
                return Err(Error::SmallK1K2 {
                    k1: k1.as_f64(),
                    k2: k2.as_f64(),
                });
            }
        }
        Ok(())
    }

    /// New parameters for this operator, its memory kept as it is (the caller keeps it valid
    /// for them: [`crate::adaptive`] re-anchors it).
    ///
    /// # Errors
    /// As [`ParametricHysteresis::with_k2_law`]; the operator is then unchanged.
    pub(crate) fn set_parameters(&mut self, k1: T, law: K) -> Result<(), Error> {
        Self::check_parameters(k1, &law)?;
        self.k1 = k1;
        self.law = law;
        Ok(())
    }

    /// The memory, in place (`None` before the first sample).
    pub(crate) fn memory_mut(&mut self) -> Option<&mut Memory<T>> {
        self.memory.as_mut()
    }

    /// The memory, by reference.
    pub(crate) fn memory_ref(&self) -> Option<&Memory<T>> {
        self.memory.as_ref()
    }

    /// Starts the operator at rest at (input, output), heading in `direction`: that point is the
    /// reversal point (α0, β0). [`Operator::reset`] returns here.
    ///
    /// # Errors
    /// [`Error::StateOutsideBand`] unless |output − input| ≤ k1 (outside that band the paper's
    /// operator is not defined); [`Error::InvalidParameter`] for non-finite values.
    pub fn with_initial_state(
        mut self,
        input: T,
        output: T,
        direction: Direction,
    ) -> Result<Self, Error> {
        let m = Memory::at_rest(input, output, direction, self.k1)?;
        self.initial = Some(m);
        self.memory = Some(m);
        Ok(self)
    }

    /// k1, the half-width of the loop (the asymptotes are output = input ∓ k1).
    #[must_use]
    pub fn k1(&self) -> T {
        self.k1
    }

    /// The k2 law.
    #[must_use]
    pub fn k2_law(&self) -> &K {
        &self.law
    }

    /// The output the operator would give for `x`, without changing its memory.
    ///
    /// # Errors
    /// As [`Operator::try_step`].
    pub fn peek<S: Sample<T>>(&self, x: S) -> Result<S, Error> {
        self.compute(x).map(|(y, _)| y)
    }

    /// The output for `x` and the memory after it, without committing the memory.
    #[inline]
    pub(crate) fn compute<S: Sample<T>>(&self, x: S) -> Result<(S, Memory<T>), Error> {
        let k2 = self.checked_k2(x, true)?;
        let mut memory = self
            .memory
            .unwrap_or_else(|| Memory::first_sample(x.value(), x.trend()));
        let y = Self::advance(&mut memory, self.k1, x, k2)?;
        Ok((y, memory))
    }

    /// k2 for the sample `x`, with everything that can refuse it checked before the memory is
    /// touched when `check` is true: a non-finite input (tested before the law sees it), and a
    /// k2 from the law that is not finite and > 0. Unchecked, the law's k2 as it comes (for a
    /// law that takes any input: `advance`'s band test refuses what the checks would).
    #[inline(always)]
    fn checked_k2<S: Sample<T>>(&self, x: S, check: bool) -> Result<S, Error> {
        if check && !x.all_finite() {
            return Err(Error::NonFiniteInput {
                value: x.value().as_f64(),
            });
        }
        let k2 = self.law.k2(x);
        if !check || K::ALWAYS_VALID || (k2.value() > T::zero() && k2.all_finite()) {
            Ok(k2)
        } else {
            Err(Error::InvalidK2 {
                input: x.value().as_f64(),
                k2: k2.value().as_f64(),
            })
        }
    }

    /// Definition 2.1's memory update followed by the formula, in place. On a refusal the
    /// memory is as it was (what `observe` changed is undone): [`Error::NonFiniteOutput`] when
    /// this finite input has no finite output (NaN stands for a jet's overflowing derivative),
    /// [`Error::NonFiniteInput`] for a non-finite plain input (which the caller need not test
    /// first: see [`Operator::try_step`]).
    ///
    /// The output is kept in the band [x − k1, x + k1] as computed in floating point (eqs. 2
    /// and 4 stay inside it in exact arithmetic; rounding can step out by an ulp, and by more
    /// when k1 is below the float spacing of the input, e.g. f32 with k1 = 5e-6 and inputs near
    /// 1000, where errors would otherwise accumulate through the reversal points). So
    /// |output − input| ≤ k1 + ½ ulp(|input| + k1) always holds, and the memory stays in the band.
    ///
    /// When eq. (2) or (4) as written is not finite for a finite input (an intermediate value
    /// overflows), [`Formula::output_wide`] computes the value again in a form that overflows
    /// only with the result (which lies within 3 k1 of x, k1 ≤ `T::MAX` / 4).
    // `!(a <= b)` on purpose: NaN must take the slow path. Inlined into every caller on a
    // host; on bare metal (firmware, built for size) left to the compiler, so `try_step` and
    // `peek` may share one copy of the formulas.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    #[cfg_attr(target_os = "none", inline)]
    fn advance<S: Sample<T>>(memory: &mut Memory<T>, k1: T, x: S, k2: S) -> Result<S, Error> {
        let v = x.value();
        // Nothing is saved to undo `observe` on a refusal: on a reversal it keeps the previous
        // reversal point in the last-sample slots, which this sample then overwrites.
        let reversed = memory.observe(v, x.trend());
        let m_star = F::m_star(memory, k1);
        let mut y = F::output(memory, x, m_star, k2);
        // The one test on the common path. It fails for NaN and ±∞ outputs, and for every
        // non-finite input: |y − x| ≤ k1 (k1 finite) is false for any y when x is NaN or ±∞.
        let jet_overflow = S::ORDER > 0 && !y.all_finite();
        if !((y.value() - v).abs() <= k1) || jet_overflow {
            // A jet whose derivatives overflow has no overflow-free form: refused (after a
            // non-finite input, which `rare` names).
            if jet_overflow && v.is_finite() {
                memory.unobserve(reversed);
                let output = y.value();
                return Err(overflow(
                    v,
                    if output.is_finite() { T::nan() } else { output },
                ));
            }
            let value = rare::<T, F>(memory, reversed, k1, v, y.value(), m_star, k2.value())?;
            y = y.with_value(value);
        }
        memory.last_input = v;
        memory.last_output = y.value();
        Ok(y)
    }

    /// One step of a model built around this operator (the shaped [`crate::ShapedModel`], the
    /// [`crate::Stop`] form): steps on `v` and maps the operator output to the model's output
    /// with `output`. When that is not finite, the memory is put back (cheaper than stepping a
    /// copy: the restore is off the hot path) and the error names the model's input `x`.
    #[inline]
    pub(crate) fn step_into<S: Sample<T>>(
        &mut self,
        x: S,
        v: S,
        output: impl FnOnce(S) -> S,
    ) -> Result<S, Error> {
        let before = self.memory;
        let y = output(self.try_step(v)?);
        if !y.all_finite() {
            self.memory = before;
            return Err(Error::NonFiniteOutput {
                input: x.value().as_f64(),
                output: y.value().as_f64(),
            });
        }
        Ok(y)
    }

    /// Puts back a memory saved from this operator (no check: it was this operator's).
    #[inline]
    pub(crate) fn restore(&mut self, memory: Option<Memory<T>>) {
        self.memory = memory;
    }

    /// Commits a memory produced by [`ParametricHysteresis::compute`].
    #[inline]
    pub(crate) fn commit(&mut self, memory: Memory<T>) {
        self.memory = Some(memory);
    }
}

impl<T: Real, K: K2Law<T>, F: Formula> Operator<T> for ParametricHysteresis<T, K, F> {
    /// The memory of Definition 2.1, `None` before the first sample (without an initial state).
    type Memory = Option<Memory<T>>;

    /// One sample, plain or a jet: Definition 2.1's memory update, then eq. (2) or eq. (4).
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`], [`Error::InvalidK2`], or [`Error::NonFiniteOutput`] when the
    /// output of a finite input is beyond the float range; the memory is then unchanged.
    #[inline(always)]
    fn try_step<S: Sample<T>>(&mut self, x: S) -> Result<S, Error> {
        // A plain sample tests nothing before the formula, the first one included: `advance`'s
        // band test fails for every non-finite input, and its rare path refuses it with the
        // memory as it was. A jet, or a law that must not see a non-finite input, is tested
        // first. One call of `advance` (a firmware build holds one copy of the formulas).
        let unchecked = S::ORDER == 0 && K::ALWAYS_VALID && K::ANY_INPUT;
        let k2 = self.checked_k2(x, !unchecked)?;
        // The memory of a first sample is created in place; when `advance` refuses the sample
        // (a non-finite input, a jet whose derivatives overflow) it undoes what it changed, and
        // the memory created for this sample goes again.
        let fresh = self.memory.is_none();
        let memory = self
            .memory
            .get_or_insert_with(|| Memory::first_sample(x.value(), x.trend()));
        let y = Self::advance(memory, self.k1, x, k2);
        if fresh && y.is_err() {
            self.memory = None;
        }
        y
    }

    #[inline(always)]
    fn step(&mut self, x: T) -> T {
        match self.try_step(x) {
            Ok(y) => y,
            Err(_) => self.memory.map_or(x, |m| m.last_output),
        }
    }

    #[inline]
    fn last_output(&self) -> Option<T> {
        self.memory.map(|m| m.last_output)
    }

    /// Back to the initial state, or to "no history" if none was given.
    fn reset(&mut self) {
        self.memory = self.initial;
    }

    fn memory(&self) -> Option<Memory<T>> {
        self.memory
    }

    /// Restores a saved memory (`None`: no history, the next sample starts on the line
    /// output = input).
    ///
    /// # Errors
    /// As [`Memory::validate`]; on error the operator is unchanged.
    fn set_memory(&mut self, memory: Option<Memory<T>>) -> Result<(), Error> {
        if let Some(m) = &memory {
            m.validate(self.k1)?;
        }
        self.memory = memory;
        Ok(())
    }
}

impl<T: Real, K: K2Law<T> + Clone, F: Formula> ParametricHysteresis<T, K, F> {
    /// The other operator of the pair with the same parameters and this one's memory seen from
    /// the other side (input and output swapped).
    fn mirrored<F2: Formula>(&self) -> ParametricHysteresis<T, K, F2> {
        ParametricHysteresis {
            k1: self.k1,
            law: self.law.clone(),
            initial: self.initial.map(|m| m.swapped()),
            memory: self.memory.map(|m| m.swapped()),
            formula: PhantomData,
        }
    }
}

impl<T: Real, K: K2Law<T> + Clone> ParametricHysteresis<T, K, Direct> {
    /// The inverse operator with the same parameters, whose memory mirrors this one's: from here
    /// on, `inverse.step(u_d)` fed into `self.step` gives back `u_d` (Proposition 4.1).
    #[must_use]
    pub fn inverse(&self) -> ParametricHysteresis<T, K, Inverse> {
        self.mirrored()
    }
}

impl<T: Real, K: K2Law<T> + Clone> ParametricHysteresis<T, K, Inverse> {
    /// The direct operator with the same parameters, whose memory mirrors this one's.
    #[must_use]
    pub fn direct(&self) -> ParametricHysteresis<T, K, Direct> {
        self.mirrored()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dual::Dual;

    /// The overflow-free form's root e(ṽ/2, M*, k2): its dual gradient (implicit-function
    /// theorem) against central differences of the plain iteration.
    #[test]
    fn direct_gap_gradient_is_the_implicit_one() {
        for &(v_half, m_star, k2) in &[(0.1_f64, 0.3, 8.0), (0.02, 0.25, 40.0), (1.5, 0.1, 0.7)] {
            let p = [v_half, m_star, k2];
            let e = direct_gap(
                Dual::<f64, 3>::variable(v_half, 0),
                Dual::variable(m_star, 1),
                Dual::variable(k2, 2),
            );
            assert_eq!(e.value(), direct_gap(v_half, m_star, k2));
            for (j, g) in e.gradient().iter().enumerate() {
                let h = 1e-6 * p[j];
                let (mut up, mut down) = (p, p);
                up[j] += h;
                down[j] -= h;
                let fd = (direct_gap(up[0], up[1], up[2]) - direct_gap(down[0], down[1], down[2]))
                    / (2.0 * h);
                assert!(
                    (g - fd).abs() <= 1e-7 * (1.0 + fd.abs()),
                    "{p:?} {j}: {g} vs {fd}"
                );
            }
        }
    }
}
