//! The tokens of the x86 instruction sets: zero-sized proofs that this processor has them. Their
//! field is private to this module, so `detect`, which asks the processor, is the only way to
//! make one (the safety argument of the `x86` module rests on this).

/// The proof that this processor has SSE2 (every x86-64 processor has): only [`Sse2::detect`]
/// makes one.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sse2(());

impl Sse2 {
    /// `Some` when this processor has SSE2.
    pub(crate) fn detect() -> Option<Self> {
        std::arch::is_x86_feature_detected!("sse2").then_some(Self(()))
    }
}

/// The proof that this processor has AVX2 and FMA: only [`Avx2::detect`] makes one.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2(());

impl Avx2 {
    /// `Some` when this processor has AVX2 and FMA.
    pub(crate) fn detect() -> Option<Self> {
        (std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma"))
            .then_some(Self(()))
    }
}

/// The proof that this processor has AVX-512F: only [`Avx512::detect`] makes one.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx512(());

impl Avx512 {
    /// `Some` when this processor has AVX-512F.
    pub(crate) fn detect() -> Option<Self> {
        std::arch::is_x86_feature_detected!("avx512f").then_some(Self(()))
    }
}
