//! SplitMix64: a small seeded generator (no dependency), so that sampled tests and synthetic data
//! are the same on every machine. [`crate::testing`] adds deformations and rotations to it.

/// SplitMix64 (Steele, Lea & Flood 2014): 64-bit state, one addition and three xor-shift-multiply
/// steps per number.
#[derive(Debug, Clone)]
pub struct Sampler(u64);

impl Sampler {
    /// A generator with the given seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 53 random bits.
    fn bits(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) >> 11
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.bits() as f64 / (1u64 << 53) as f64
    }

    /// Uniform in (0, 1): the midpoints of the 2⁵³ cells, never 0 (for a logarithm).
    pub fn open_uniform(&mut self) -> f64 {
        (self.bits() as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Standard normal, by Box–Muller from two [`open_uniform`](Self::open_uniform) numbers.
    pub fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.open_uniform(), self.open_uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}

#[cfg(test)]
mod tests {
    use super::Sampler;

    #[test]
    fn reproduces_the_reference_splitmix64_stream() {
        // First outputs of SplitMix64 with seed 0 (Vigna's reference implementation), top 53 bits.
        let mut s = Sampler::new(0);
        for expected in [
            0xE220_A839_7B1D_CDAFu64,
            0x6E78_9E6A_A1B9_65F4,
            0x06C4_5D18_8009_454F,
        ] {
            assert_eq!(s.bits(), expected >> 11);
        }
    }

    #[test]
    fn normal_numbers_have_mean_zero_and_variance_one() {
        let mut s = Sampler::new(7);
        let n = 200_000;
        let v: Vec<f64> = (0..n).map(|_| s.normal()).collect();
        let mean = v.iter().sum::<f64>() / n as f64;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        // Standard errors: 1/√n ≈ 2.2e-3 for the mean, √(2/n) ≈ 3.2e-3 for the variance.
        assert!(
            mean.abs() < 0.011 && (var - 1.0).abs() < 0.016,
            "{mean} {var}"
        );
    }
}
