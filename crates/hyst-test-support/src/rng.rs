//! Seeded pseudo-random sequences: the four generators the tests use, each written once. A
//! test keeps its generator and seed, so its sequence (and every figure computed from it) is
//! the same from run to run and machine to machine. None is for cryptography.

/// A generator of 64-bit words and what the tests draw from them.
pub trait Random {
    /// The next word of the sequence.
    fn next_u64(&mut self) -> u64;

    /// Uniform in [0, 1): the word's top 53 bits over 2⁵³.
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in (0, 1), never 0 (a logarithm may take it): the word's top 53 bits plus ½,
    /// over 2⁵³.
    fn open_unit(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi): lo + (hi − lo)·[`unit`](Random::unit).
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in [−amplitude, amplitude): amplitude·(2·[`unit`](Random::unit) − 1).
    fn symmetric(&mut self, amplitude: f64) -> f64 {
        amplitude * (2.0 * self.unit() - 1.0)
    }

    /// Log-uniform in [lo, hi) for 0 < lo < hi: exp(ln lo + (ln hi − ln lo)·unit).
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }

    /// A standard normal number (Box–Muller from two [`open_unit`](Random::open_unit) draws
    /// a, b: √(−2 ln a)·cos(2π b); the sine's twin is not kept).
    fn normal(&mut self) -> f64 {
        self.gaussian(1.0)
    }

    /// A normal number of mean 0 and standard deviation `sigma`: σ·√(−2 ln a)·cos(2π b), the
    /// products taken in that order (as [`normal`](Random::normal) times σ, to the last bit
    /// only when σ is a power of 2).
    fn gaussian(&mut self, sigma: f64) -> f64 {
        let (a, b) = (self.open_unit(), self.open_unit());
        sigma * (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
    }
}

/// Marsaglia's xorshift64 (shifts 13, 7, 17); the state is the seed (not 0) and each word is the
/// new state.
#[derive(Clone, Debug)]
pub struct XorShift64(pub u64);

impl Random for XorShift64 {
    fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }
}

/// Vigna's xorshift64* (shifts 12, 25, 27, then the product with 0x2545F4914F6CDD1D); the state
/// is the seed (not 0).
#[derive(Clone, Debug)]
pub struct XorShift64Star(pub u64);

impl Random for XorShift64Star {
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

/// Knuth's 64-bit linear congruential generator (MMIX's multiplier 6364136223846793005):
/// state ← state·a + c mod 2⁶⁴, each word the new state.
#[derive(Clone, Debug)]
pub struct Lcg64 {
    /// The state: the seed at first.
    pub state: u64,
    /// The increment c (odd).
    pub increment: u64,
}

impl Lcg64 {
    /// MMIX's increment, 1442695040888963407.
    pub const MMIX: u64 = 1_442_695_040_888_963_407;

    /// From `seed` with MMIX's increment.
    pub fn new(seed: u64) -> Self {
        Self::with_increment(seed, Self::MMIX)
    }

    /// From `seed` with the increment `increment` (odd).
    pub fn with_increment(seed: u64, increment: u64) -> Self {
        Self {
            state: seed,
            increment,
        }
    }
}

impl Random for Lcg64 {
    fn next_u64(&mut self) -> u64 {
        self.state = self
            .state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(self.increment);
        self.state
    }
}

/// Steele, Lea and Flood's SplitMix64: the state steps by the golden ratio's 0x9E3779B97F4A7C15
/// and each word is that state mixed.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl Random for SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first words of each generator, as their authors' reference code gives them.
    #[test]
    fn first_words_are_the_published_ones() {
        // SplitMix64 from 0 (the reference implementation's first output).
        assert_eq!(SplitMix64(0).next_u64(), 0xE220_A839_7B1D_CDAF);
        // xorshift64 from 1: 1 ^ 1<<13 = 0x2001, ^ >>7 = 0x2041, ^ <<17 = 0x4082_2041.
        assert_eq!(XorShift64(1).next_u64(), 0x4082_2041);
        // The LCG from 0 is its increment.
        assert_eq!(Lcg64::new(0).next_u64(), Lcg64::MMIX);
        // xorshift64* from 1: the state 0x0200_0001 times the multiplier.
        assert_eq!(XorShift64Star(1).next_u64(), 0x47E4_CE4B_896C_DD1D);
    }

    #[test]
    fn draws_stay_in_their_ranges() {
        let mut r = XorShift64(0x9E37_79B9_7F4A_7C15);
        for _ in 0..10_000 {
            let u = r.unit();
            assert!((0.0..1.0).contains(&u));
            let o = r.open_unit();
            assert!(o > 0.0 && o < 1.0);
            let l = r.log_uniform(1e-3, 10.0);
            assert!((1e-3..=10.0).contains(&l), "{l}");
            assert!(r.normal().is_finite());
        }
    }
}
