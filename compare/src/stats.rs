//! The few normal-distribution tools the comparisons share: the two-sided tail probability
//! (through erfc), its inverse, and Šidák's correction for testing several hypotheses at once.
//! Used by the Mitsuba z-test ([`crate::mitsuba::ztest`]) and the bias test of `verity diff`
//! ([`crate::diff`]).

/// Šidák's per-test level for `n` tests at family-wise level `alpha`:
/// 1 − (1 − α)^(1/n), computed as −expm1(ln(1 − α)/n) to keep its digits for large n.
pub fn sidak(alpha: f64, n: usize) -> f64 {
    -((-alpha).ln_1p() / n.max(1) as f64).exp_m1()
}

/// Complementary error function with fractional error < 1.2·10⁻⁷ everywhere (Press et al.,
/// Numerical Recipes in C, 2nd ed., §6.2, `erfcc`: a Chebyshev fit of erfc(z)·exp(z²)).
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    const C: [f64; 10] = [
        -1.265_512_23,
        1.000_023_68,
        0.374_091_96,
        0.096_784_18,
        -0.186_288_06,
        0.278_868_07,
        -1.135_203_98,
        1.488_515_87,
        -0.822_152_23,
        0.170_872_77,
    ];
    let poly = C.iter().rev().fold(0.0, |acc, &c| c + t * acc);
    let ans = t * (-z * z + poly).exp();
    if x >= 0.0 {
        ans
    } else {
        2.0 - ans
    }
}

/// The two-sided standard-normal quantile: the z > 0 with P(|Z| > z) = erfc(z/√2) = `alpha`
/// (1.96 for 0.05, 2.576 for 0.01). Found by bisection on [`erfc`], which is monotonic, to
/// the digits erfc carries (fractional error < 1.2·10⁻⁷); `alpha` is clamped to
/// [1e-300, 1].
pub fn two_sided_normal_quantile(alpha: f64) -> f64 {
    let alpha = alpha.clamp(1e-300, 1.0);
    // P(|Z| > 38) ≈ 1e-314 < 1e-300: every clamped alpha's z lies in [0, 38].
    let (mut lo, mut hi) = (0.0f64, 38.0f64);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if erfc(mid / std::f64::consts::SQRT_2) > alpha {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erfc_matches_tabulated_values() {
        // erfc to 16 digits (C's erfc, via Python's math.erfc).
        let table = [
            (0.0, 1.0),
            (0.5, 0.479_500_122_186_953_5),
            (1.0, 0.157_299_207_050_285_1),
            (2.0, 4.677_734_981_047_266e-3),
            (3.0, 2.209_049_699_858_544e-5),
            (5.0, 1.537_459_794_428_035e-12),
            (-1.0, 1.842_700_792_949_715),
        ];
        for (x, want) in table {
            let got = erfc(x);
            assert!(
                ((got - want) / want).abs() < 1.2e-7,
                "erfc({x}): expected {want:e}, got {got:e}"
            );
        }
    }

    #[test]
    fn sidak_level() {
        // 1 − 0.99^(1/4096) = 2.453692…e-6; for one test it is the level itself.
        let got = sidak(0.01, 4096);
        assert!(
            (got - 2.453_692_3e-6).abs() < 1e-13,
            "expected 2.4536923e-6, got {got:e}"
        );
        assert!((sidak(0.01, 1) - 0.01).abs() < 1e-15);
    }

    #[test]
    fn two_sided_quantiles_match_tables() {
        // Φ⁻¹(1 − α/2) to 7 digits (Abramowitz & Stegun, Table 26.5; Python's
        // statistics.NormalDist().inv_cdf).
        for (alpha, want) in [
            (0.05, 1.959_964),
            (0.01, 2.575_829),
            (0.001, 3.290_527),
            (1e-6, 4.891_638),
        ] {
            let got = two_sided_normal_quantile(alpha);
            assert!(
                (got - want).abs() < 2e-6,
                "alpha {alpha}: expected {want}, got {got}"
            );
        }
        assert!(two_sided_normal_quantile(1.0) < 1e-3);
    }
}
