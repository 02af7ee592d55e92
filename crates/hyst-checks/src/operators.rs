//! Operator sequences with arbitrary parameters and inputs.
//!
//! The bytes choose the precision (f64 or f32), what is stepped, the parameters and the input
//! samples (raw bit patterns, including NaN, ±∞, subnormals and ±MAX, or small steps around the
//! last sample, or repeats). The invariants, from the crate docs of hyst-core:
//!
//! 1. A constructor either refuses the parameters or builds an operator; H and H⁻¹ agree.
//! 2. `try_step` of a non-finite sample is `NonFiniteInput`; of a finite one, a finite output or
//!    `NonFiniteOutput` (the output is beyond the float range); on every error the memory is
//!    unchanged. The memory never holds a NaN or ∞.
//! 3. The band: |y − x| ≤ k1 + ½ ulp(|x| + k1) for the operator's input x and output y.
//! 4. Proposition 4.1: H(H⁻¹(x)) = x within [`identity_tolerance`] · ε · s · √(1 + r) (128 for
//!    f64, 512 for f32), where ε is the precision's machine epsilon, s the largest magnitude among
//!    k1, the inputs and the outputs so far (reversal points from the whole history enter the
//!    result) and r the number of reversals of the input so far.
//! 5. Shaped models: finite outputs or an error with the memory unchanged; the compensator
//!    undoes the model within 4× the same tolerance, with s including the output gain times the
//!    magnitudes inside the model (the shaping functions' terms and k1).
//! 6. The compensator of Lemma 5.1 and jets: no panic, finite outputs or an error.

use hyst_core::{
    Affine, Compensator, Error, Hysteresis, InverseHysteresis, Jet, Memory, Operator, Real,
    ShapedModel,
};

/// The tolerance of H(H⁻¹(x)) = x in units of ε · s · √(1 + r), r the number of reversals of
/// the input so far (see the module docs): 128 for f64, 512 for f32. Eq. (2) adds W(·)/k2, of
/// size up to M* ≤ 2 k1, to ṽ − M*: the Lambert W's relative error (2e-15 ≈ 9 ε for f64,
/// 1e-6 ≈ 8 ε for f32) and the rounding of its argument reach the output multiplied by up to
/// 2 k1. And the pair's memories are mirrors only up to that error: at a reversal H keeps its own
/// output as β0, H⁻¹ the exact input, and near a reversal point (or when k2 k1 is small, so the
/// branch never reaches its asymptote) the difference carries into the next branch undamped, a
/// random walk over the reversals. The soak (`hyst-soak`) figures are in docs/reliability.md.
#[must_use]
pub fn identity_tolerance<T: Real>() -> f64 {
    if core::mem::size_of::<T>() == 4 {
        512.0
    } else {
        128.0
    }
}

/// Reads the fuzzer's bytes.
pub(crate) struct Bytes<'a>(pub(crate) &'a [u8]);

impl Bytes<'_> {
    pub(crate) fn u8(&mut self) -> Option<u8> {
        let (&b, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(b)
    }

    fn bits(&mut self) -> Option<u64> {
        let (head, rest) = self.0.split_at_checked(8)?;
        self.0 = rest;
        let mut b = [0u8; 8];
        b.copy_from_slice(head);
        Some(u64::from_le_bytes(b))
    }

    /// A number of either precision: raw bits (every pattern, NaN included) or a "nice" signed
    /// power of ten 10^(e/64), e in [−128·64, 127·64]/… of the byte pair.
    pub(crate) fn number<T: Precision>(&mut self) -> Option<T> {
        let tag = self.u8()?;
        if tag & 1 == 0 {
            Some(T::from_bits(self.bits()?))
        } else {
            let e = i16::from_le_bytes([self.u8()?, self.u8()?]);
            let magnitude = 10f64.powf(f64::from(e) / 100.0);
            let signed = if tag & 2 == 0 { magnitude } else { -magnitude };
            Some(T::from_f64(signed))
        }
    }

    /// The next input sample: a number, a small step from `last`, or `last` again.
    pub(crate) fn sample<T: Precision>(&mut self, last: T, k1: T) -> Option<T> {
        let tag = self.u8()?;
        match tag % 4 {
            0 => self.number(),
            1 | 2 => {
                let step = T::from_f64(f64::from(self.u8()? as i8) / 16.0);
                let unit = if tag % 4 == 1 { k1 } else { T::one() };
                Some(last + step * unit)
            }
            _ => Some(last),
        }
    }
}

/// The two precisions, with a way from raw bits.
pub trait Precision: Real {
    /// From the low bits of `bits` (all 64 for f64, 32 for f32).
    fn from_bits(bits: u64) -> Self;
}

impl Precision for f64 {
    fn from_bits(bits: u64) -> Self {
        f64::from_bits(bits)
    }
}

impl Precision for f32 {
    fn from_bits(bits: u64) -> Self {
        f32::from_bits(bits as u32)
    }
}

/// Every value of the memory finite and its last point in the band (up to ½ ulp).
fn memory_ok<T: Real>(what: &str, memory: Option<Memory<T>>, k1: T) -> Result<(), String> {
    let Some(m) = memory else { return Ok(()) };
    let values = [
        m.reversal_input,
        m.reversal_output,
        m.last_input,
        m.last_output,
    ];
    if values.iter().any(|v| !v.is_finite()) {
        return Err(format!(
            "{what}: the memory holds a non-finite value: {m:?}"
        ));
    }
    band(what, m.last_input, m.last_output, k1)
}

/// |y − x| ≤ k1 + ½ ulp(|x| + k1), computed exactly in f64.
fn band<T: Real>(what: &str, x: T, y: T, k1: T) -> Result<(), String> {
    let (x, y, k1) = (x.as_f64(), y.as_f64(), k1.as_f64());
    let half_ulp = (x.abs() + k1) * T::epsilon().as_f64() / 2.0;
    if (y - x).abs() > k1 + half_ulp {
        return Err(format!(
            "{what}: |y - x| = {} > k1 = {k1} (x = {x}, y = {y})",
            (y - x).abs()
        ));
    }
    Ok(())
}

/// One step of `op` with the contract of invariant 2; `Ok(None)` for a refused sample.
fn step<T: Real, O: Operator<T, Memory = Option<Memory<T>>>>(
    what: &str,
    op: &mut O,
    x: T,
    k1: T,
) -> Result<Option<T>, String> {
    let before = op.memory();
    let result = op.try_step(x);
    match result {
        Ok(y) if x.is_finite() && y.is_finite() => {
            band(what, x, y, k1)?;
            memory_ok(what, op.memory(), k1)?;
            Ok(Some(y))
        }
        Ok(y) => Err(format!("{what}: {x:?} -> Ok({y:?})")),
        Err(e) => {
            let expected = match e {
                Error::NonFiniteInput { .. } => !x.is_finite(),
                Error::NonFiniteOutput { .. } => x.is_finite(),
                _ => false,
            };
            if !expected {
                return Err(format!("{what}: {x:?} -> unexpected error {e}"));
            }
            if op.memory() != before {
                return Err(format!("{what}: the error {e} changed the memory"));
            }
            Ok(None)
        }
    }
}

/// The largest identity error seen by [`check_pair`], in units of ε · s.
#[derive(Clone, Copy, Debug, Default)]
pub struct PairReport {
    /// Worst |H(H⁻¹(x)) − x| / (ε s √(1 + r)), r the reversals so far (see [`check_pair`]).
    pub worst_identity: f64,
    /// Worst |H(H⁻¹(x)) − x| / (ε s), without the reversal factor.
    pub worst_raw: f64,
    /// Samples checked.
    pub samples: u64,
    /// Samples refused with `NonFiniteOutput` (the output is beyond the float range).
    pub refused: u64,
}

/// Invariants 1–4 for H(k1, k2) and H⁻¹(k1, k2) over `inputs`. Also used by the soak command.
///
/// # Errors
/// A description of the broken invariant.
pub fn check_pair<T: Real>(
    k1: T,
    k2: T,
    inputs: impl IntoIterator<Item = T>,
    report: &mut PairReport,
) -> Result<(), String> {
    let (h, inv) = (Hysteresis::new(k1, k2), InverseHysteresis::new(k1, k2));
    let (mut h, mut inv) = match (h, inv) {
        (Ok(h), Ok(inv)) => (h, inv),
        (Err(_), Err(_)) => return Ok(()),
        (a, b) => {
            return Err(format!(
                "H and H^-1 disagree on ({k1:?}, {k2:?}): {a:?} {b:?}"
            ))
        }
    };
    let mut alone = h;
    let mut scale = k1.as_f64();
    let eps = T::epsilon().as_f64();
    let (mut reversals, mut last, mut rising) = (0u32, None::<T>, None::<bool>);
    for x in inputs {
        report.samples += 1;
        if let (Some(l), true) = (last, x.is_finite()) {
            if x != l {
                let up = x > l;
                reversals += u32::from(rising.is_some_and(|r| r != up));
                rising = Some(up);
            }
        }
        if x.is_finite() {
            last = Some(x);
        }
        step("H alone", &mut alone, x, k1)?;
        let Some(v) = step("H^-1", &mut inv, x, k1)? else {
            report.refused += u64::from(x.is_finite());
            continue;
        };
        let Some(u) = step("H after H^-1", &mut h, v, k1)? else {
            return Err(format!(
                "H refused {v:?} = H^-1({x:?}) (k1 {k1:?}, k2 {k2:?})"
            ));
        };
        scale = scale.max(x.as_f64().abs()).max(v.as_f64().abs());
        let raw = (u.as_f64() - x.as_f64()).abs() / (eps * scale);
        let error = raw / f64::from(1 + reversals).sqrt();
        report.worst_raw = report.worst_raw.max(raw);
        report.worst_identity = report.worst_identity.max(error);
        if error > identity_tolerance::<T>() {
            return Err(format!(
                "H(H^-1({x:?})) = {u:?}: error {raw:.1} eps * {scale:e} after {reversals} \
                 reversals (k1 {k1:?}, k2 {k2:?})"
            ));
        }
    }
    Ok(())
}

/// Invariant 5: ψ_out(H[ψ_in(x)]) with affine shaping, and its compensator.
fn check_model<T: Real>(k1: T, k2: T, gains: [T; 4], inputs: &[T]) -> Result<(), String> {
    let [gi, oi, go, oo] = gains;
    let (Ok(psi_in), Ok(psi_out), Ok(h)) = (
        Affine::new(gi, oi),
        Affine::new(go, oo),
        Hysteresis::new(k1, k2),
    ) else {
        return Ok(());
    };
    let Ok(mut model) = ShapedModel::new(psi_in, h, psi_out) else {
        return Ok(());
    };
    let mut compensator = model.inverse();
    let mut scale = 0.0f64;
    let mut last_y: Option<f64> = None;
    for &y in inputs {
        let before = compensator.memory();
        let command = match compensator.try_step(y) {
            Ok(c) if c.is_finite() => c,
            Ok(c) => return Err(format!("compensator: {y:?} -> Ok({c:?})")),
            Err(_) if compensator.memory() == before => continue,
            Err(e) => return Err(format!("compensator: the error {e} changed the memory")),
        };
        memory_ok("compensator", compensator.memory(), k1)?;
        let before = model.memory();
        let out = match model.try_step(command) {
            Ok(o) if o.is_finite() => o,
            Ok(o) => return Err(format!("model: {command:?} -> Ok({o:?})")),
            // The model may refuse a command whose output overflows: with extreme gains the
            // shaping's rounding can move ψ_in(command) to the other branch of a near-backlash,
            // up to 2 k1 away, and ψ_out's gain then overflows. The memory must be unchanged;
            // the model and the compensator have then parted, so the identity check ends.
            Err(_) if model.memory() == before => return Ok(()),
            Err(e) => return Err(format!("model: the error {e} changed the memory")),
        };
        memory_ok("model", model.memory(), k1)?;
        // The identity holds for the operator in the middle; through ψ_out its error scales with
        // the output gain, through the shaping's offsets and products with their size (ψ_in's
        // rounding, ε |ψ_in's terms|, reaches the output times the output gain).
        let g = go.as_f64().abs();
        scale = scale
            .max(y.as_f64().abs())
            .max(oo.as_f64().abs())
            .max(g * k1.as_f64())
            .max(g * oi.as_f64().abs())
            .max(g * (gi.as_f64() * command.as_f64()).abs())
            // The command's resolution near 0 (subnormal spacing MIN_POSITIVE ε): a command
            // below the float range (|gain| 1e308) underflows.
            .max(g * gi.as_f64().abs() * T::min_positive_value().as_f64());
        if let Some(m) = model.memory() {
            scale = scale.max(go.as_f64().abs() * m.reversal_input.as_f64().abs());
        }
        let eps = T::epsilon().as_f64();
        let mut error = (out.as_f64() - y.as_f64()).abs();
        // Known limit: when the step of the operator's input, |Δy| / |g|, is below the rounding
        // of ψ_in(ψ_in⁻¹(v)), that rounding can reverse the step's direction and switch the
        // operator to the other branch: up to 2 k1 in operator units, 2 k1 |g| at the output.
        let step = last_y.map_or(f64::INFINITY, |l| (y.as_f64() - l).abs() / g);
        let rounding = eps * (oi.as_f64().abs() + (gi.as_f64() * command.as_f64()).abs());
        if step <= 4.0 * rounding {
            error = (error - 2.0 * k1.as_f64() * g).max(0.0);
        }
        last_y = Some(y.as_f64());
        let error = error / (eps * scale);
        if error > 4.0 * identity_tolerance::<T>() {
            return Err(format!(
                "model(compensator({y:?})) = {out:?}: error {error:.1} eps * {scale:e}"
            ));
        }
    }
    Ok(())
}

/// Invariant 6: the compensator of Lemma 5.1 (n = 2) and the operator on jets.
fn check_dynamic<T: Real>(k1: T, k2: T, coefficients: [T; 3], inputs: &[T]) -> Result<(), String> {
    let [b, a1, a2] = coefficients;
    let Ok(h) = Hysteresis::new(k1, k2) else {
        return Ok(());
    };
    let Ok(model) = ShapedModel::new(hyst_core::Identity, h, hyst_core::Identity) else {
        return Ok(());
    };
    if let Ok(mut c) = Compensator::from_shaped_model(&model, b, [a1, a2]) {
        let dt = T::from_f64(1e-3);
        for &u in inputs {
            match c.try_step(u, dt) {
                Ok(x) if !x.is_finite() => return Err(format!("compensator step {u:?} -> {x:?}")),
                _ => {}
            }
        }
    }
    let mut inv = InverseHysteresis::new(k1, k2).map_err(|e| e.to_string())?;
    let mut last = T::zero();
    for &x in inputs {
        let jet = Jet::from_derivatives(x, [x - last, a1]);
        last = x;
        let before = inv.memory();
        match inv.try_step(jet) {
            Ok(y) if !(y.value().is_finite() && y.derivatives().iter().all(|d| d.is_finite())) => {
                return Err(format!("jet {jet:?} -> {y:?}"));
            }
            Ok(y) => band("H^-1 jet", x, y.value(), k1)?,
            Err(_) if inv.memory() == before => {}
            Err(e) => return Err(format!("jet: the error {e} changed the memory")),
        }
        memory_ok("H^-1 jet", inv.memory(), k1)?;
    }
    Ok(())
}

fn check_precision<T: Precision>(kind: u8, mut bytes: Bytes<'_>) -> Result<(), String> {
    let (Some(k1), Some(k2)) = (bytes.number::<T>(), bytes.number::<T>()) else {
        return Ok(());
    };
    let mut extra = [T::one(); 4];
    if kind != 0 {
        for e in &mut extra {
            *e = bytes.number::<T>().unwrap_or(T::one());
        }
    }
    let unit = if k1.is_finite() && k1 > T::zero() {
        k1
    } else {
        T::one()
    };
    let mut inputs = Vec::new();
    let mut last = T::zero();
    while let Some(x) = bytes.sample(last, unit) {
        inputs.push(x);
        last = if x.is_finite() { x } else { last };
        if inputs.len() >= 4096 {
            break;
        }
    }
    match kind {
        0 => check_pair(k1, k2, inputs, &mut PairReport::default()),
        1 => check_model(k1, k2, extra, &inputs),
        _ => check_dynamic(k1, k2, [extra[0], extra[1], extra[2]], &inputs),
    }
}

/// The operator checks on arbitrary bytes: the first byte picks the precision (bit 0) and the
/// kind (pair, shaped model and compensator, Lemma 5.1 compensator and jets).
///
/// # Errors
/// A description of the broken invariant.
pub fn check_operators(data: &[u8]) -> Result<(), String> {
    let mut bytes = Bytes(data);
    let Some(mode) = bytes.u8() else {
        return Ok(());
    };
    let kind = (mode >> 1) % 3;
    if mode & 1 == 0 {
        check_precision::<f64>(kind, bytes)
    } else {
        check_precision::<f32>(kind, bytes)
    }
}
