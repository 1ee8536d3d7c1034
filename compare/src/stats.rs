//! The few distribution tools the comparisons share: the normal two-sided tail probability
//! (through erfc) and its inverse, Student's t tail probability, and Šidák's correction for
//! testing several hypotheses at once.
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

/// Two-sided p-value of `t` under Student's t with `dof` degrees of freedom:
/// P(|T| ≥ |t|) = I_{ν/(ν+t²)}(ν/2, ½) (Abramowitz & Stegun 26.7.1 with 26.5.27).
pub fn student_t_p(t: f64, dof: f64) -> f64 {
    if t == 0.0 {
        return 1.0;
    }
    incomplete_beta(0.5 * dof, 0.5, dof / (dof + t * t))
}

/// The regularized incomplete beta function I_x(a, b) by its continued fraction (Abramowitz &
/// Stegun 26.5.8), evaluated with the modified Lentz algorithm (Press et al., Numerical Recipes
/// in C, 2nd ed., §5.2 and §6.4), using the symmetry I_x(a, b) = 1 − I_{1−x}(b, a) where the
/// fraction converges slowly (x > (a + 1)/(a + b + 2)).
fn incomplete_beta(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let front = (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_fraction(a, b, x) / a
    } else {
        1.0 - front * beta_fraction(b, a, 1.0 - x) / b
    }
}

/// The continued fraction of A&S 26.5.8, d₂ₘ₊₁ = −(a+m)(a+b+m)x / ((a+2m)(a+2m+1)),
/// d₂ₘ = m(b−m)x / ((a+2m−1)(a+2m)), by the modified Lentz algorithm.
fn beta_fraction(a: f64, b: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let guard = |v: f64| if v.abs() < TINY { TINY } else { v };
    let (mut c, mut d) = (1.0, 1.0 / guard(1.0 - (a + b) * x / (a + 1.0)));
    let mut h = d;
    for m in 1..=300 {
        let m = f64::from(m);
        let even = m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m));
        d = 1.0 / guard(1.0 + even * d);
        c = guard(1.0 + even / c);
        h *= d * c;
        let odd = -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
        d = 1.0 / guard(1.0 + odd * d);
        c = guard(1.0 + odd / c);
        let step = d * c;
        h *= step;
        if (step - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// ln Γ(x) for x > 0 by Lanczos' approximation, |ε| < 2·10⁻¹⁰ (Lanczos 1964, "A precision
/// approximation of the gamma function", SIAM J. Numer. Anal. B 1; the coefficients for γ = 5,
/// N = 6 of Numerical Recipes in C, 2nd ed., §6.1).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 6] = [
        76.180_091_729_471_46,
        -86.505_320_329_416_77,
        24.014_098_240_830_91,
        -1.231_739_572_450_155,
        0.120_865_097_386_617_9e-2,
        -0.539_523_938_495_3e-5,
    ];
    let t = x + 5.5 - (x + 0.5) * (x + 5.5).ln();
    let series = C.iter().enumerate().fold(1.000_000_000_190_015, |acc, (j, c)| {
        acc + c / (x + 1.0 + j as f64)
    });
    -t + (2.506_628_274_631_000_5 * series / x).ln()
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

    #[test]
    fn student_t_p_values_match_tables() {
        // Two-sided p of Student's t (scipy.stats.t.sf(t, ν)·2): t_7 = 2.365 at 0.05,
        // t_7 = 4.785 at 0.002, t_63 = 2.656 at 0.01, t_1 = 1 at 0.5 (Cauchy), and the normal
        // limit erfc(5/√2) = 5.733e-7 at ν = 1e7.
        for (t, dof, want) in [
            (2.364_624_251_6, 7.0, 0.05),
            (4.785_289_628_6, 7.0, 0.002),
            (2.656_145_2, 63.0, 0.01),
            (1.0, 1.0, 0.5),
            (5.0, 1e7, 5.733_128_1e-7),
        ] {
            let got = student_t_p(t, dof);
            assert!(
                ((got - want) / want).abs() < 1e-4,
                "t = {t}, ν = {dof}: expected {want:e}, got {got:e}"
            );
            assert!((student_t_p(-t, dof) - got).abs() < 1e-15);
        }
        assert_eq!(student_t_p(0.0, 7.0), 1.0);
    }
}
