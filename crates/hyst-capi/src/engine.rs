//! The generic work behind the C functions, written once for `f32` and `f64`: every call goes
//! through the core's [`Operator`] trait; the C wrappers only check pointers and convert.

use core::ptr;

use hyst_core::{
    AffineK2, AffineShaping, AnyK2Law, AnyShaping, Compensator, ConstantK2, Direction, Error,
    Hysteresis, Identity, InitialState, InverseHysteresis, InverseShapedModel, Jet, Langevin,
    Memory, Operator, Polynomial, QuadraticExp, Real, ScaledShaping, ShapedModel, Started, Stop,
    Tanh,
};

use crate::status::{self, HYST_ERR_LENGTH, HYST_ERR_NULL_POINTER, HYST_OK};

/// The highest time-derivative order of the `_step_derivatives` functions and the highest plant
/// order n of the compensator.
pub const HYST_MAX_ORDER: usize = 4;

// One limit on every surface: the core's (cbindgen needs the literal above).
const _: () = assert!(HYST_MAX_ORDER == hyst_core::compensator::MAX_ORDER);

/// The parametric operator, direct (eq. 2) or inverse (eq. 4).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Pair<T: Real> {
    Direct(Hysteresis<T>),
    Inverse(InverseHysteresis<T>),
}

/// The shaped model ψ_out ∘ H ∘ ψ_in, or its exact inverse.
pub(crate) type Shaping<T> = ScaledShaping<T>;
/// A shaped model with run-time shaping functions and k2 law.
pub(crate) type AnyShapedModel<T> = ShapedModel<T, Shaping<T>, AnyK2Law<T>, Shaping<T>>;

/// A shaping function whose shape is affine (identity or affine): the same arithmetic as
/// [`Shaping`], and none of the nonlinear shapes' code in a firmware.
pub(crate) type Linear<T> = ScaledShaping<T, AffineShaping<T>>;

/// The shaped model with shapings `S`, direct, inverse or in its stop form, run by its start
/// rule.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Shaped<T: Real, S = Shaping<T>> {
    Direct(Started<ShapedModel<T, S, AnyK2Law<T>, S>>),
    Inverse(Started<InverseShapedModel<T, S, AnyK2Law<T>, S>>),
    Stop(Started<Stop<T, S, AnyK2Law<T>, S>>),
}

/// The Lemma 5.1 compensator for plant orders n = 0 … 4 chosen at run time (one
/// monomorphisation for every order: see `Compensator::with_order`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Comp<T: Real, I, K, O>(pub(crate) Compensator<T, HYST_MAX_ORDER, I, K, O>);

/// The compensator of the plain operator H(k1, k2): no shaping code is linked with it.
pub(crate) type PlainComp<T> = Comp<T, Identity, ConstantK2<T>, Identity>;
/// The compensator of a shaped model.
pub(crate) type ShapedComp<T> = Comp<T, Shaping<T>, AnyK2Law<T>, Shaping<T>>;

/// Forwards an [`Operator`] method to whichever model an enum of this module holds: static
/// dispatch, so a firmware links only the methods its C calls reach (no vtable pulls in the jet
/// steps of every order).
macro_rules! each {
    ($value:expr, $op:ident => $body:expr, $($variant:path),+) => {
        match $value {
            $($variant($op) => $body,)+
        }
    };
}

/// [`Operator`] for an enum of models, variant by variant.
macro_rules! operator_enum {
    ($ty:ident, $($variant:path),+) => {
        operator_enum!($ty<>, $($variant),+);
    };
    ($ty:ident<$($extra:ident: $bound:path),*>, $($variant:path),+) => {
        impl<T: Real, $($extra: $bound + Copy),*> Operator<T> for $ty<T, $($extra),*> {
            type Memory = Option<Memory<T>>;

            #[inline]
            fn try_step<X: hyst_core::Sample<T>>(&mut self, x: X) -> Result<X, Error> {
                each!(self, op => Operator::try_step(op, x), $($variant),+)
            }
            fn last_output(&self) -> Option<T> {
                each!(self, op => Operator::last_output(op), $($variant),+)
            }
            fn reset(&mut self) {
                each!(self, op => Operator::reset(op), $($variant),+)
            }
            fn memory(&self) -> Option<Memory<T>> {
                each!(self, op => Operator::memory(op), $($variant),+)
            }
            fn set_memory(&mut self, memory: Option<Memory<T>>) -> Result<(), Error> {
                each!(self, op => Operator::set_memory(op, memory), $($variant),+)
            }
        }
    };
}

operator_enum!(Pair, Pair::Direct, Pair::Inverse);
operator_enum!(Shaped<S: hyst_core::Shaping<T>>, Shaped::Direct, Shaped::Inverse, Shaped::Stop);

/// The part of [`Operator`] that the C functions need: plain samples, jets of order 1 … 4,
/// memory, as plain (non-generic) methods.
pub(crate) trait Dyn<T: Real> {
    fn step(&mut self, x: T) -> Result<T, (Error, T)>;
    fn jet(&mut self, x: &[T], y: &mut [T]) -> Result<(), Error>;
    fn memory(&self) -> Option<Memory<T>>;
    fn set_memory(&mut self, memory: Option<Memory<T>>) -> Result<(), Error>;
    fn reset(&mut self);
}

impl<T: Real, O: Operator<T, Memory = Option<Memory<T>>>> Dyn<T> for O {
    fn step(&mut self, x: T) -> Result<T, (Error, T)> {
        match self.try_step(x) {
            Ok(y) => Ok(y),
            Err(e) => Err((e, self.last_output().unwrap_or(x))),
        }
    }
    fn jet(&mut self, x: &[T], y: &mut [T]) -> Result<(), Error> {
        jet_step(self, x, y)
    }
    fn memory(&self) -> Option<Memory<T>> {
        Operator::memory(self)
    }
    fn set_memory(&mut self, memory: Option<Memory<T>>) -> Result<(), Error> {
        Operator::set_memory(self, memory)
    }
    fn reset(&mut self) {
        Operator::reset(self);
    }
}

/// One jet sample of order `x.len() − 1` (1 … 4) through `op`: `x` = [value, d1, …],
/// `y` receives the same for the output.
fn jet_step<T: Real, O: Operator<T> + ?Sized>(
    op: &mut O,
    x: &[T],
    y: &mut [T],
) -> Result<(), Error> {
    fn run<T: Real, O: Operator<T> + ?Sized, const N: usize>(
        op: &mut O,
        x: &[T],
        y: &mut [T],
    ) -> Result<(), Error> {
        let value = x.first().copied().unwrap_or_else(T::zero);
        let d: [T; N] = core::array::from_fn(|k| x.get(k + 1).copied().unwrap_or_else(T::zero));
        let out = op.try_step(Jet::<T, N>::from_derivatives(value, d))?;
        if let Some(v) = y.first_mut() {
            *v = out.value();
        }
        for (slot, d) in y.iter_mut().skip(1).zip(out.derivatives()) {
            *slot = d;
        }
        Ok(())
    }
    match x.len() {
        1 => run::<T, O, 0>(op, x, y),
        2 => run::<T, O, 1>(op, x, y),
        3 => run::<T, O, 2>(op, x, y),
        4 => run::<T, O, 3>(op, x, y),
        5 => run::<T, O, 4>(op, x, y),
        _ => Err(Error::LengthMismatch {
            input: x.len(),
            output: y.len(),
        }),
    }
}

/// `hyst_*_step`: one plain sample; a refused sample writes the held output and returns its
/// status.
///
/// # Safety
/// `y` is NULL or valid for one write.
pub(crate) unsafe fn step<T: Real, O: Dyn<T>>(op: &mut O, x: T, y: *mut T) -> i32 {
    if y.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    let (value, status) = match op.step(x) {
        Ok(v) => (v, HYST_OK),
        Err((e, held)) => (held, status::of(&e)),
    };
    // SAFETY: non-NULL (checked) and valid for a write (caller's contract).
    unsafe { ptr::write(y, value) };
    status
}

/// `hyst_*_step_derivatives`: `x` and `y` hold order + 1 values each.
///
/// # Safety
/// `x` and `y` are NULL or valid for `order + 1` reads / writes.
pub(crate) unsafe fn step_derivatives<T: Real, O: Dyn<T>>(
    op: &mut O,
    x: *const T,
    y: *mut T,
    order: usize,
) -> i32 {
    if x.is_null() || y.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    if order > HYST_MAX_ORDER {
        return HYST_ERR_LENGTH;
    }
    let mut input = [T::zero(); HYST_MAX_ORDER + 1];
    for (k, slot) in input.iter_mut().enumerate().take(order + 1) {
        // SAFETY: k ≤ order, within the caller's array.
        *slot = unsafe { ptr::read(x.add(k)) };
    }
    let mut output = [T::zero(); HYST_MAX_ORDER + 1];
    let (Some(xs), Some(ys)) = (input.get(..=order), output.get_mut(..=order)) else {
        return HYST_ERR_LENGTH;
    };
    if let Err(e) = op.jet(xs, ys) {
        return status::of(&e);
    }
    for (k, v) in ys.iter().enumerate() {
        // SAFETY: k ≤ order, within the caller's array.
        unsafe { ptr::write(y.add(k), *v) };
    }
    HYST_OK
}

/// `hyst_*_process`: every sample as [`step`]; returns the first refused sample's status.
///
/// # Safety
/// When `n > 0`, `x` and `y` are NULL or valid for `n` reads / writes (they may be the same
/// array).
pub(crate) unsafe fn process<T: Real, O: Dyn<T>>(
    op: &mut O,
    x: *const T,
    y: *mut T,
    n: usize,
) -> i32 {
    if n == 0 {
        return HYST_OK;
    }
    if x.is_null() || y.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    let mut first = HYST_OK;
    for i in 0..n {
        // SAFETY: i < n, within the caller's arrays; read before write, so x == y is fine.
        let xi = unsafe { ptr::read(x.add(i)) };
        let (value, status) = match op.step(xi) {
            Ok(v) => (v, HYST_OK),
            Err((e, held)) => (held, status::of(&e)),
        };
        if first == HYST_OK {
            first = status;
        }
        // SAFETY: as above.
        unsafe { ptr::write(y.add(i), value) };
    }
    first
}

/// The memory of Definition 2.1 as the C struct's fields.
pub(crate) struct MemoryFields<T> {
    pub reversal_input: T,
    pub reversal_output: T,
    pub last_input: T,
    pub last_output: T,
    pub direction: i32,
    pub has_history: i32,
}

impl<T: Real> MemoryFields<T> {
    pub(crate) fn of(memory: Option<Memory<T>>) -> Self {
        match memory {
            Some(m) => Self {
                reversal_input: m.reversal_input,
                reversal_output: m.reversal_output,
                last_input: m.last_input,
                last_output: m.last_output,
                direction: if m.direction == Direction::Rising {
                    1
                } else {
                    -1
                },
                has_history: 1,
            },
            None => Self {
                reversal_input: T::zero(),
                reversal_output: T::zero(),
                last_input: T::zero(),
                last_output: T::zero(),
                direction: 1,
                has_history: 0,
            },
        }
    }

    pub(crate) fn to_core(&self) -> Result<Option<Memory<T>>, Error> {
        match self.has_history {
            0 => return Ok(None),
            1 => {}
            other => {
                return Err(Error::InvalidParameter {
                    name: "has_history",
                    value: f64::from(other),
                    expected: "0 (no history) or 1",
                })
            }
        }
        Ok(Some(Memory {
            reversal_input: self.reversal_input,
            reversal_output: self.reversal_output,
            direction: direction(self.direction)?,
            last_input: self.last_input,
            last_output: self.last_output,
        }))
    }
}

/// +1 → rising, −1 → falling.
pub(crate) fn direction(d: i32) -> Result<Direction, Error> {
    match d {
        1 => Ok(Direction::Rising),
        -1 => Ok(Direction::Falling),
        _ => Err(Error::InvalidParameter {
            name: "direction",
            value: f64::from(d),
            expected: "+1 (rising) or -1 (falling)",
        }),
    }
}

/// A builder of a shaping function from a `hyst_shaping`'s fields (kind, p, pre_gain,
/// pre_offset, post_gain, post_offset): [`shaping`] or [`linear_shaping`].
pub(crate) type ShapingFn<T, S> = fn(i32, [T; 6], T, T, T, T) -> Result<S, Error>;

/// Shaping kinds of `hyst_shaping.kind`.
pub(crate) fn shaping<T: Real>(
    kind: i32,
    p: [T; 6],
    pre_gain: T,
    pre_offset: T,
    post_gain: T,
    post_offset: T,
) -> Result<Shaping<T>, Error> {
    let [p0, p1, p2, p3, p4, p5] = p;
    let shape = match kind {
        0 => AnyShaping::Identity,
        1 => AnyShaping::Affine(hyst_core::Affine::new(p0, p1)?),
        2 => AnyShaping::Polynomial(Polynomial::new([p0, p1, p2, p3], p4, p5)?),
        3 => AnyShaping::Tanh(Tanh::new(p0, p1)?),
        4 => AnyShaping::Langevin(Langevin::new(p0, p1)?),
        5 => AnyShaping::QuadraticExp(QuadraticExp::new(p0, p1, p2, p3, p4)?),
        _ => {
            return Err(Error::InvalidParameter {
                name: "shaping kind",
                value: f64::from(kind),
                expected: "one of HYST_SHAPING_IDENTITY … HYST_SHAPING_QUADRATIC_EXP (0 … 5)",
            })
        }
    };
    ScaledShaping::new(pre_gain, pre_offset, shape, post_gain, post_offset)
}

/// k2 laws of `hyst_k2_law.kind`.
pub(crate) fn k2_law<T: Real>(
    kind: i32,
    value: T,
    slope: T,
    min: T,
    max: T,
) -> Result<AnyK2Law<T>, Error> {
    use hyst_core::K2Law;
    let law = match kind {
        0 => AnyK2Law::Constant { value },
        1 => AnyK2Law::Affine(AffineK2::new(value, slope, min, max)?),
        _ => {
            return Err(Error::InvalidParameter {
                name: "k2 law kind",
                value: f64::from(kind),
                expected: "HYST_K2_CONSTANT (0) or HYST_K2_AFFINE (1)",
            })
        }
    };
    law.validate()?;
    Ok(law)
}

/// The start rule of `hyst_shaped_model_params.initial_state`.
pub(crate) fn initial_state(rule: i32) -> Result<InitialState, Error> {
    match rule {
        0 => Ok(InitialState::Line),
        1 => Ok(InitialState::Rising),
        2 => Ok(InitialState::Falling),
        _ => Err(Error::InvalidParameter {
            name: "initial_state",
            value: f64::from(rule),
            expected: "HYST_INITIAL_STATE_LINE, _RISING or _FALLING (0, 1, 2)",
        }),
    }
}

/// A compensator's model is the operator form, its history set by the integrators' state (`v0`),
/// not by a start rule.
pub(crate) fn compensated_form(form: i32, rule: i32) -> Result<(), Error> {
    if form != 0 {
        return Err(Error::InvalidParameter {
            name: "form",
            value: f64::from(form),
            expected: "HYST_FORM_OPERATOR (a compensator inverts H)",
        });
    }
    if rule != 0 {
        return Err(Error::InvalidParameter {
            name: "initial_state",
            value: f64::from(rule),
            expected: "HYST_INITIAL_STATE_LINE (the compensator starts from its integrators' \
                       state v0)",
        });
    }
    Ok(())
}

/// The shaped model of `params` in its form (`HYST_FORM_*`), direct or inverse, run by the
/// start rule `rule`. The stop form has no inverse.
pub(crate) fn shaped<T: Real, S: hyst_core::Shaping<T> + Copy>(
    model: ShapedModel<T, S, AnyK2Law<T>, S>,
    form: i32,
    linear: T,
    rule: i32,
    inverse: bool,
) -> Result<Shaped<T, S>, Error> {
    let rule = initial_state(rule)?;
    match (form, inverse) {
        (0, _) if linear != T::zero() => Err(Error::InvalidParameter {
            name: "linear",
            value: linear.as_f64(),
            expected: "0 for HYST_FORM_OPERATOR (the linear term belongs to the stop form)",
        }),
        (0, false) => Ok(Shaped::Direct(Started::new(model, rule))),
        (0, true) => Ok(Shaped::Inverse(Started::new(model.inverse(), rule))),
        (1, false) => {
            let stop = Stop::new(
                *model.input_shaping(),
                *model.operator(),
                *model.output_shaping(),
                linear,
            )?;
            Ok(Shaped::Stop(Started::new(stop, rule)))
        }
        (1, true) => Err(Error::InvalidParameter {
            name: "form",
            value: 1.0,
            expected: "HYST_FORM_OPERATOR: the stop form (friction) has no inverse",
        }),
        _ => Err(Error::InvalidParameter {
            name: "form",
            value: f64::from(form),
            expected: "HYST_FORM_OPERATOR or HYST_FORM_STOP (0, 1)",
        }),
    }
}

/// A shaping function of `hyst_shaping.kind` identity or affine, as a [`Linear`] one (the
/// same numbers as [`shaping`] builds, without the nonlinear kinds' code).
///
/// # Errors
/// [`Error::InvalidParameter`] for another kind, and the checks of [`shaping`].
pub(crate) fn linear_shaping<T: Real>(
    kind: i32,
    p: [T; 6],
    pre_gain: T,
    pre_offset: T,
    post_gain: T,
    post_offset: T,
) -> Result<Linear<T>, Error> {
    let [p0, p1, ..] = p;
    let shape = match kind {
        0 => AffineShaping::Identity,
        1 => AffineShaping::Affine(hyst_core::Affine::new(p0, p1)?),
        _ => {
            return Err(Error::InvalidParameter {
                name: "shaping kind",
                value: f64::from(kind),
                expected: "HYST_SHAPING_IDENTITY or HYST_SHAPING_AFFINE (0, 1) for a linear model",
            })
        }
    };
    ScaledShaping::new(pre_gain, pre_offset, shape, post_gain, post_offset)
}

/// The plain operator.
pub(crate) fn pair<T: Real>(k1: T, k2: T, inverse: bool) -> Result<Pair<T>, Error> {
    Ok(if inverse {
        Pair::Inverse(InverseHysteresis::new(k1, k2)?)
    } else {
        Pair::Direct(Hysteresis::new(k1, k2)?)
    })
}

/// Checks the compensator's plant coefficients and builds it for the order n = `a.len()` ≤ 4,
/// with the integrators at `state` (n values) or at rest.
pub(crate) fn compensator<T: Real, I, K, O>(
    inverse: InverseShapedModel<T, I, K, O>,
    b: T,
    a: &[T],
    state: Option<&[T]>,
) -> Result<Comp<T, I, K, O>, Error>
where
    I: hyst_core::Shaping<T> + Clone,
    K: hyst_core::K2Law<T> + Clone,
    O: hyst_core::Shaping<T> + Clone,
{
    let c = Compensator::with_order(inverse, b, a)?;
    Ok(Comp(match state {
        Some(v) => c.with_state(core::array::from_fn(|k| {
            v.get(k).copied().unwrap_or_else(T::zero)
        }))?,
        None => c,
    }))
}

impl<T: Real, I, K, O> Comp<T, I, K, O>
where
    I: hyst_core::Shaping<T> + Clone,
    K: hyst_core::K2Law<T> + Clone,
    O: hyst_core::Shaping<T> + Clone,
{
    /// The plant order n.
    pub(crate) fn order(&self) -> usize {
        self.0.order()
    }

    /// One sample of Lemma 5.1: the command for v⁽ⁿ⁾ = `u_new` held over `dt` seconds; a refused
    /// sample gives the held command.
    pub(crate) fn step(&mut self, u_new: T, dt: T) -> Result<T, (Error, T)> {
        let c = &mut self.0;
        c.try_step(u_new, dt).map_err(|e| (e, c.last_command()))
    }

    /// Reference-trajectory mode: `reference` = [v, v̇, …, v⁽ⁿ⁾] (the rest 0).
    pub(crate) fn track(&mut self, reference: &[T]) -> Result<T, Error> {
        let value = reference.first().copied().unwrap_or_else(T::zero);
        let d = core::array::from_fn(|k| reference.get(k + 1).copied().unwrap_or_else(T::zero));
        self.0.track(Jet::from_derivatives(value, d))
    }

    /// The integrator chain (v, v̇, …, v⁽ⁿ⁻¹⁾) into `out`.
    pub(crate) fn state(&self, out: &mut [T]) {
        for (slot, v) in out.iter_mut().zip(self.0.state()) {
            *slot = v;
        }
    }

    pub(crate) fn reset(&mut self) {
        self.0.reset();
    }

    /// The memory of the compensator's inverse model.
    pub(crate) fn memory(&self) -> Option<Memory<T>> {
        Operator::memory(self.0.inverse())
    }
}
