//! SplitMix64 (Steele, Lea & Flood, "Fast Splittable Pseudorandom Number Generators", OOPSLA
//! 2014, https://doi.org/10.1145/2660193.2660195): the one source of deterministic
//! pseudo-random bits that the crates share — the oracle's independent sampler and its
//! scrambling seeds, the noise-floor resampling in `compare`, the Poisson-disk tap pattern in
//! `realtime`, and tests.

/// The generator's increment γ, the odd integer nearest 2⁶⁴/φ (φ the golden ratio).
pub const GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// SplitMix64's output for the state `x`: the finaliser ("mix64", variant 13 of Stafford's
/// MurmurHash3 mixers) applied to `x + γ`. A bijection of `u64`, so it also serves as a hash.
pub fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(GAMMA);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The generator: a 64-bit state that advances by γ per output.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 bits.
    pub fn next_u64(&mut self) -> u64 {
        let z = splitmix64(self.0);
        self.0 = self.0.wrapping_add(GAMMA);
        z
    }

    /// A uniform float in [0, 1) from the top 24 bits (every value exactly representable).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_outputs_of_seed_zero_are_the_reference_values() {
        // The first outputs of SplitMix64 seeded with 0 (the reference implementation's
        // well-known sequence).
        let mut g = SplitMix64(0);
        assert_eq!(g.next_u64(), 0xe220_a839_7b1d_cdaf);
        assert_eq!(g.next_u64(), 0x6e78_9e6a_a1b9_65f4);
        assert_eq!(g.next_u64(), 0x06c4_5d18_8009_454f);
        assert!((0.0..1.0).contains(&g.next_f32()));
    }
}
