//! The Poisson-disk tap pattern of `pcf_poisson` and `pcss` (technique/shadow/pcf.wgsl, shadow/pcss.wgsl):
//! [`POISSON_TAPS`] points in the unit disk, generated once, deterministically, on the CPU.

use scenes::random::SplitMix64;

use super::MAX_SHADOW_TAPS;

/// Poisson taps in the table (WGSL `poisson`, two per vec4).
pub const POISSON_TAPS: usize = MAX_SHADOW_TAPS as usize;

/// Mitchell's best-candidate factor: tap k is the best of `BEST_CANDIDATE_FACTOR`·k candidates
/// (Mitchell 1991 uses a similar multiple; 10 chosen here).
const BEST_CANDIDATE_FACTOR: usize = 10;

/// A uniform point of the unit disk (rejection from the square).
fn in_disk(rng: &mut SplitMix64) -> [f32; 2] {
    loop {
        let (x, y) = (2.0 * rng.next_f32() - 1.0, 2.0 * rng.next_f32() - 1.0);
        if x * x + y * y <= 1.0 {
            return [x, y];
        }
    }
}

/// The Poisson-disk tap pattern in the unit disk: tap 0 at the centre, then Mitchell's best
/// candidate (Mitchell 1991, "Spectrally Optimal Sampling for Distribution Ray Tracing",
/// SIGGRAPH '91, https://doi.org/10.1145/122718.122736): tap k is, of `BEST_CANDIDATE_FACTOR`·k
/// uniform candidates, the farthest from taps 0..k. Progressive: every prefix (the first N taps
/// a method uses) is itself well spread.
pub fn poisson_disk() -> [[f32; 2]; POISSON_TAPS] {
    let mut rng = SplitMix64(0x5653_5348_4144_4f57);
    let mut taps = vec![[0.0f32, 0.0]];
    while taps.len() < POISSON_TAPS {
        let mut best = ([0.0, 0.0], -1.0f32);
        for _ in 0..BEST_CANDIDATE_FACTOR * taps.len() {
            let c = in_disk(&mut rng);
            let d = taps
                .iter()
                .map(|t| (t[0] - c[0]).powi(2) + (t[1] - c[1]).powi(2))
                .fold(f32::INFINITY, f32::min);
            if d > best.1 {
                best = (c, d);
            }
        }
        taps.push(best.0);
    }
    std::array::from_fn(|k| taps[k])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poisson_taps_are_in_the_disk_and_spread() {
        let taps = poisson_disk();
        assert_eq!(taps[0], [0.0, 0.0]);
        let mut min_d = f32::INFINITY;
        for (i, a) in taps.iter().enumerate() {
            assert!(a[0].hypot(a[1]) <= 1.0, "{a:?}");
            for b in &taps[..i] {
                min_d = min_d.min((a[0] - b[0]).hypot(a[1] - b[1]));
            }
        }
        // 64 points in the unit disk: a hexagonal packing would give spacing ≈ 0.24; best
        // candidate reaches a good fraction of it, pure random would give ~0.01.
        assert!(min_d > 0.08, "closest taps {min_d}");
        assert_eq!(taps, poisson_disk(), "deterministic");
    }
}
