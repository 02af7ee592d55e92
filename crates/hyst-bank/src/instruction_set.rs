//! The instruction sets the bank's kernels are compiled for, and the choice of the one that
//! runs: the best this processor has, or the one [`force_isa`] forced (for measurements and
//! for testing each kernel against the scalar operator).

/// An instruction set the bank's kernels are compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Isa {
    /// AVX-512F, 512-bit vectors (8 × f64, 16 × f32) with fused multiply-add (x86-64, `std`).
    Avx512,
    /// AVX2 + FMA, 256-bit vectors (4 × f64, 8 × f32) (x86-64, `std`).
    Avx2,
    /// SSE2, 128-bit vectors (2 × f64, 4 × f32), no fused multiply-add: x86-64's baseline
    /// (`std`).
    Sse2,
    /// Portable code, plain floats (every target).
    Portable,
}

impl Isa {
    /// Every instruction set, best first.
    pub const ALL: [Isa; 4] = [Isa::Avx512, Isa::Avx2, Isa::Sse2, Isa::Portable];

    /// "avx512", "avx2", "sse2" or "portable".
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Isa::Avx512 => "avx512",
            Isa::Avx2 => "avx2",
            Isa::Sse2 => "sse2",
            Isa::Portable => "portable",
        }
    }

    /// Whether this processor (and build) can run it: whether its token can be made (the `x86`
    /// module's `detect`, the one place that asks the processor).
    #[must_use]
    pub fn available(self) -> bool {
        match self {
            Isa::Portable => true,
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            Isa::Avx512 => crate::token::Avx512::detect().is_some(),
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            Isa::Sse2 => crate::token::Sse2::detect().is_some(),
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            Isa::Avx2 => crate::token::Avx2::detect().is_some(),
            #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
            _ => false,
        }
    }
}

/// The forced instruction set: 0 none, else 1 + its index in `ISAS`.
static FORCED: core::sync::atomic::AtomicU8 = core::sync::atomic::AtomicU8::new(0);
const ISAS: [Isa; 4] = Isa::ALL;

/// Chooses the instruction set of every bank in the process (`None`: the best available, the
/// default) — for measurements and for testing each kernel against the scalar operator.
///
/// # Errors
/// `Err(isa)` when this processor or build cannot run `isa`; nothing changes then.
pub fn force_isa(isa: Option<Isa>) -> Result<(), Isa> {
    let code = match isa {
        None => 0,
        Some(i) if i.available() => match i {
            Isa::Avx512 => 1,
            Isa::Avx2 => 2,
            Isa::Sse2 => 3,
            Isa::Portable => 4,
        },
        Some(i) => return Err(i),
    };
    FORCED.store(code, core::sync::atomic::Ordering::Relaxed);
    Ok(())
}

/// The instruction set the banks run on now: the forced one ([`force_isa`]), else the best
/// available (AVX-512, AVX2 + FMA, SSE2, portable, in that order).
#[must_use]
pub fn isa() -> Isa {
    let forced = FORCED.load(core::sync::atomic::Ordering::Relaxed);
    if let Some(i) = ISAS.get(usize::from(forced).wrapping_sub(1)) {
        return *i;
    }
    ISAS.into_iter()
        .find(|i| i.available())
        .unwrap_or(Isa::Portable)
}
