//! The oracle's sample generators: Owen-scrambled Sobol points (the default), or independent
//! uniform random numbers, one decorrelated stream per pixel sample.
//!
//! Independent samples make the textbook Monte Carlo estimator: its error falls as 1/spp
//! exactly and the per-pixel sample variance is an unbiased estimate of the estimator's
//! variance. Scrambled Sobol points are stratified, so the error falls at least that fast,
//! often faster, and their per-pixel sample variance over-states the variance of their mean
//! (by ~1,000× on the default study's scene at 256 spp): it is no estimate of the reference's
//! noise at all.
//!
//! **Independent replicates.** The variance of a randomized quasi-Monte Carlo mean is
//! estimated the standard way, from independent replicates (Owen 1997, "Monte Carlo variance
//! of scrambled net quadrature", SIAM J. Numer. Anal. 34(5), §1; L'Ecuyer & Lemieux 2002,
//! "Recent advances in randomized quasi-Monte Carlo methods", §3): each pixel's samples are
//! dealt to [`REPLICATES`] independently scrambled Sobol sequences, stream index i to replicate
//! i mod R at index ⌊i / R⌋ of that replicate's sequence. The replicate means m₁ … m_R are then
//! independent and unbiased, their mean m̄ is the pixel's value, and
//! s² = Σ (m_r − m̄)² / (R (R − 1)) is an unbiased estimate of Var(m̄) whatever the replicates'
//! own variances (crate::film). Interleaving keeps every stop progressive: after any sample
//! count each replicate holds a prefix of its own sequence, and with spp a multiple of R each
//! holds the same number of points (a power of two when spp is, Sobol's best-stratified
//! sizes). Below R samples per pixel each replicate holds at most one point: the samples are
//! then simply independent. The price is the stratification lost between replicates: a
//! variance of roughly R^(α−1) times one sequence's where one sequence's variance falls as
//! n^−α (measured in docs/ARCHITECTURE.md, "Decisions"). The independent sampler needs no
//! replicates but is dealt to them the same way, so one estimator serves both.
//!
//! Points come from Burley 2020, "Practical Hash-based Owen Scrambling" (JCGT 9(4)), via the
//! `sobol_burley` crate: a nested-uniform scrambled and shuffled Sobol sequence per seed.
//! Each (pixel, replicate) gets the seed hash(pixel, replicate, user seed), so error shows as
//! noise, not structure, and a pixel's samples depend only on (pixel, sample index, seed): the
//! image is identical whatever the thread count or the order in which pixels are rendered.
//!
//! Limits handled here: the crate serves 2¹⁶ samples and 256 dimensions per seed; sample
//! indices and dimensions beyond those move to further seeds (independent sequences), so
//! sample counts are unbounded (the stratification then holds within each block of 2¹⁶).

use scenes::random::{splitmix64, GAMMA};

/// Samples per Sobol block (the crate's maximum sequence length).
const BLOCK: u32 = 1 << 16;
/// Dimensions per seed (the crate's maximum).
const DIMS: u32 = 256;

/// Independent replicates per pixel (module header): the degrees of freedom of every variance
/// estimate are R − 1. 4 is the decision of docs/ARCHITECTURE.md ("Decisions": what 4, 8 and
/// 16 cost in error; a replicate needs enough points of its own for the stratification to
/// pay, 64 on the default study's scene).
pub const REPLICATES: u32 = 4;

/// The replicate that pixel-stream sample `index` belongs to (module header).
pub const fn replicate_of(index: u32) -> u32 {
    index % REPLICATES
}

/// Sample stream for one pixel sample: successive calls walk the dimensions.
#[derive(Clone, Debug)]
pub struct PixelSampler {
    seed: u32,
    index: u32,
    /// The sample index shuffled by `seed`, bits reversed (Burley 2020, §4): the same for
    /// every dimension under one seed, so computed once per stream instead of once per four
    /// dimensions.
    shuffled_rev: u32,
    dimension: u32,
    /// `Some(state)` for an independent (pseudo-random) stream.
    random: Option<u64>,
    /// The current set of 4 Sobol dimensions (`sample_4d` computes four at once with SIMD).
    cached: [f32; 4],
}

impl PixelSampler {
    /// Owen-scrambled Sobol stream for sample `index` of pixel (x, y) under the user `seed`:
    /// point ⌊index / R⌋ of replicate [`replicate_of`]`(index)`'s own sequence.
    pub fn new(x: u32, y: u32, index: u32, seed: u64) -> Self {
        let pixel = (u64::from(y) << 32) | u64::from(x);
        let (replicate, index) = (replicate_of(index), index / REPLICATES);
        let sequence = u64::from(index / BLOCK) | u64::from(replicate) << 32;
        let h = splitmix64(splitmix64(pixel ^ splitmix64(seed)) ^ sequence.wrapping_mul(GAMMA));
        let seed = h as u32 ^ (h >> 32) as u32;
        let index = index % BLOCK;
        PixelSampler {
            seed,
            index,
            shuffled_rev: shuffle_rev(index, seed),
            dimension: 0,
            random: None,
            cached: [0.0; 4],
        }
    }

    /// Independent uniform stream for sample `index` of pixel (x, y): SplitMix64 seeded by a
    /// hash of (pixel, index, seed).
    pub fn independent(x: u32, y: u32, index: u32, seed: u64) -> Self {
        let pixel = (u64::from(y) << 32) | u64::from(x);
        let state = splitmix64(
            splitmix64(splitmix64(pixel) ^ u64::from(index)) ^ splitmix64(seed ^ 0x1d8e_4e27_c47d_124f),
        );
        PixelSampler {
            seed: 0,
            index,
            shuffled_rev: 0,
            dimension: 0,
            random: Some(state),
            cached: [0.0; 4],
        }
    }

    /// The stream `kind` asks for.
    pub fn of_kind(kind: scenes::SamplerKind, x: u32, y: u32, index: u32, seed: u64) -> Self {
        match kind {
            scenes::SamplerKind::Sobol => Self::new(x, y, index, seed),
            scenes::SamplerKind::Independent => Self::independent(x, y, index, seed),
        }
    }

    /// Next value in [0, 1).
    pub fn next_1d(&mut self) -> f32 {
        let d = self.dimension;
        self.dimension += 1;
        if let Some(state) = &mut self.random {
            *state = state.wrapping_add(GAMMA);
            // 24 random bits → a float in [0, 1) with every value exactly representable.
            return (splitmix64(*state) >> 40) as f32 * (1.0 / (1u32 << 24) as f32);
        }
        if d.is_multiple_of(4) {
            self.cached = if d < DIMS {
                sobol_4d(self.shuffled_rev, d / 4, self.seed)
            } else {
                let seed = splitmix64(u64::from(self.seed) ^ u64::from(d / DIMS)) as u32;
                sobol_burley::sample_4d(self.index, (d % DIMS) / 4, seed)
            };
        }
        self.cached[(d % 4) as usize]
    }

    /// A 64-bit seed for a generator of this vertex's own (a stochastic BSDF's random walk):
    /// uses up one dimension, and is a hash of (pixel seed, sample index, dimension) for
    /// Sobol streams or the next state of an independent one, so no two dimensions, samples
    /// or pixels share a seed.
    pub fn next_seed(&mut self) -> u64 {
        let d = self.dimension;
        // Drawn like any dimension, which keeps the cache of four Sobol dimensions in step.
        let _ = self.next_1d();
        if let Some(state) = self.random {
            return splitmix64(state ^ 0x5eed_0f5e_edf0_0d5e);
        }
        let key = (u64::from(self.seed) << 32) | u64::from(self.index);
        splitmix64(splitmix64(key) ^ u64::from(d).wrapping_mul(GAMMA))
    }

    /// Next point in [0, 1)².
    pub fn next_2d(&mut self) -> glam::Vec2 {
        glam::Vec2::new(self.next_1d(), self.next_1d())
    }
}

/// The constant `sobol_burley::sample_4d` mixes into the seed of its index shuffle (read from
/// its 0.5 source; [`sobol_4d`] must return what it returns, which a test checks).
const SHUFFLE_SALT: u32 = 0x79c6_8e4a;
/// The per-lane salts `sobol_burley::sample_4d` mixes into the Owen scramble of each of the
/// four dimensions of a set (its 0.5 source).
const LANE_SALT: [u32; 4] = [0x912f_69ba, 0x174f_18ab, 0x691e_72ca, 0xb40c_c1b8];
/// The multiplier `sobol_burley::sample_4d` applies to the seed of the Owen scramble.
const SCRAMBLE_MUL: u32 = 0x9c8f_2d3b;

/// The unscrambled Sobol points of every set of four dimensions, per 4-bit digit of the
/// (bit-reversed) sample index: entry `set·64 + 16k + b` is the point of index bits
/// `b << (28 − 4k)`. A Sobol point is the XOR of the direction numbers of its index's set bits
/// (the digital construction over GF(2), Joe & Kuo 2008, "Constructing Sobol sequences with
/// better two-dimensional projections", SIAM J. Sci. Comput. 30(5), §2), so the point of a
/// 16-bit index (the crate reads the top 16 bits of the reversed index) is the XOR of its four
/// digits' entries: four loads instead of a loop over the index's bits. 64 sets × 64 entries ×
/// 16 bytes = 64 KiB, built from the crate's own `sobol_int4_rev` on first use. (Per-byte
/// tables, 512 KiB, were no faster.)
static SOBOL_DIGITS: std::sync::LazyLock<Vec<sobol_burley::parts::Int4>> = std::sync::LazyLock::new(|| {
    use sobol_burley::parts::sobol_int4_rev;
    (0..DIMS / 4)
        .flat_map(|set| (0..64u32).map(move |e| sobol_int4_rev((e % 16) << (28 - 4 * (e / 16)), set)))
        .collect()
});

/// Sample `index` shuffled by `seed` (a nested uniform scramble of the index, Burley 2020,
/// §4), bits reversed.
fn shuffle_rev(index: u32, seed: u32) -> u32 {
    use sobol_burley::parts::{hash, owen_scramble_rev};
    owen_scramble_rev(index.reverse_bits(), hash(seed ^ SHUFFLE_SALT))
}

/// Dimensions 4·set .. 4·set + 3 of the Sobol point at the shuffled index `shuffled_rev`,
/// Owen-scrambled under `seed`: `sobol_burley::sample_4d(index, set, seed)` with the index
/// shuffle done once per stream ([`shuffle_rev`]) and the unscrambled point read from
/// [`SOBOL_DIGITS`]. Equal to it bit for bit (tested).
fn sobol_4d(shuffled_rev: u32, set: u32, seed: u32) -> [f32; 4] {
    use sobol_burley::parts::{hash_int4, owen_scramble_int4_rev, Int4};
    let table = &SOBOL_DIGITS[set as usize * 64..][..64];
    let n = |k: u32| table[(k * 16 + ((shuffled_rev >> (28 - 4 * k)) & 15)) as usize];
    let sobol = (n(0) ^ n(1)) ^ (n(2) ^ n(3));
    let scramble = Int4::from([seed.wrapping_mul(SCRAMBLE_MUL) ^ set; 4]) ^ Int4::from(LANE_SALT);
    owen_scramble_int4_rev(sobol, hash_int4(scramble))
        .reverse_bits()
        .to_f32_norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shuffle_once_per_stream_equals_the_crates_sample_4d() {
        for seed in [0, 1, 0xdead_beef, u32::MAX] {
            for index in [0, 1, 2, 3, 255, 4096, 65_535] {
                let shuffled = shuffle_rev(index, seed);
                for set in 0..DIMS / 4 {
                    let ours = sobol_4d(shuffled, set, seed).map(f32::to_bits);
                    let crates = sobol_burley::sample_4d(index, set, seed).map(f32::to_bits);
                    assert_eq!(ours, crates, "seed {seed}, index {index}, set {set}");
                }
            }
        }
    }

    #[test]
    fn streams_are_deterministic_and_in_range() {
        let mut a = PixelSampler::new(3, 7, 42, 1);
        let mut b = PixelSampler::new(3, 7, 42, 1);
        for _ in 0..600 {
            let (x, y) = (a.next_1d(), b.next_1d());
            assert_eq!(x.to_bits(), y.to_bits());
            assert!((0.0..1.0).contains(&x));
        }
    }

    #[test]
    fn first_dimensions_are_stratified_per_replicate() {
        // 2^k Sobol points of one replicate hit each of 2^k strata of the first dimension
        // exactly once; the pixel's first 2^k samples, spread over R replicates, do not.
        let n = 256;
        for r in 0..REPLICATES {
            let mut seen = vec![0u32; n];
            for i in 0..n as u32 {
                let index = r + REPLICATES * i;
                assert_eq!(replicate_of(index), r);
                let v = PixelSampler::new(5, 9, index, 7).next_1d();
                seen[(v * n as f32) as usize] += 1;
            }
            assert!(
                seen.iter().all(|&c| c == 1),
                "replicate {r}: strata counts {seen:?}"
            );
        }
        let mut seen = vec![0u32; n];
        for i in 0..n as u32 {
            seen[(PixelSampler::new(5, 9, i, 7).next_1d() * n as f32) as usize] += 1;
        }
        assert!(seen.iter().any(|&c| c != 1), "replicates share one scramble");
    }

    #[test]
    fn independent_stream_is_uniform() {
        // Mean and variance of U[0,1) are 1/2 and 1/12; 40 000 draws: σ_mean ≈ 0.0014.
        let mut sum = 0.0f64;
        let mut sum2 = 0.0f64;
        let n = 40_000;
        for i in 0..n / 8 {
            let mut s = PixelSampler::independent(i % 13, i / 13, i, 3);
            for _ in 0..8 {
                let v = f64::from(s.next_1d());
                assert!((0.0..1.0).contains(&v));
                sum += v;
                sum2 += v * v;
            }
        }
        let mean = sum / f64::from(n);
        let var = sum2 / f64::from(n) - mean * mean;
        assert!(
            (mean - 0.5).abs() < 0.006 && (var - 1.0 / 12.0).abs() < 0.003,
            "mean {mean}, var {var}"
        );
    }

    #[test]
    fn pixels_and_seeds_decorrelate() {
        let a = PixelSampler::new(0, 0, 0, 0).next_1d();
        let b = PixelSampler::new(1, 0, 0, 0).next_1d();
        let c = PixelSampler::new(0, 0, 0, 1).next_1d();
        assert!(a != b && a != c);
    }
}
