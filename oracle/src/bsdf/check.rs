//! Test support: the property checks every non-delta BSDF passes (sample consistency,
//! reciprocity, energy bound, pdf normalisation, χ² of the sampler). Each BSDF's own test
//! module calls [`standard_checks`] for its parameter grid, plus its closed-form θ sweep.

use std::f64::consts::PI;

use glam::Vec3;
use scenes::Rgb;

use super::chi2::{chi2_test, integrate_sphere, Pcg32};
use super::Bsdf;
use crate::sampling::square_to_uniform_sphere;

/// Outgoing directions every check runs at: (θo in degrees, φo in radians). The last one
/// is below the surface (two-sided reflection).
pub const WO_ANGLES: [(f32, f32); 4] = [(10.0, 0.9), (45.0, 0.9), (80.0, 0.9), (125.0, 2.0)];

/// Samples per χ² test.
const CHI2_SAMPLES: u32 = 1_000_000;

/// Unit direction at polar angle `theta_deg` and azimuth `phi`.
pub fn direction(theta_deg: f32, phi: f32) -> Vec3 {
    let (st, ct) = theta_deg.to_radians().sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new(st * cp, st * sp, ct)
}

/// What [`standard_checks`] expects of a BSDF beyond the universal properties.
pub struct Expect {
    /// Reflectance parameters are white (≤ 1): check ∫ f cos dωi ≤ 1 per channel.
    pub white: bool,
    /// No sample is ever lost: check ∫ pdf dω = 1, not just ≤ 1.
    pub lossless: bool,
    /// θo (degrees, measured from the side of ωo) above which the energy bound is not
    /// checked because the model is known not to conserve energy there (90 = everywhere).
    pub energy_max_theta_deg: f32,
    /// Exact ∫ f cos dωi per channel, where known in closed form (Lambert: ρ).
    pub albedo: Option<Rgb>,
    /// Run the χ² test (skipped where the sampling code path and pdf are identical to a
    /// configuration already tested, e.g. GGX masking variants).
    pub chi2: bool,
}

/// Sample consistency, reciprocity, energy, pdf normalisation and (optionally) χ² at every
/// [`WO_ANGLES`] direction. `seed` makes each caller's random streams distinct.
pub fn standard_checks(name: &str, bsdf: &Bsdf, expect: &Expect, seed: u64) {
    assert!(!bsdf.is_delta(), "{name}: is_delta");
    let mut rng = Pcg32::new(seed, 1);
    check_reciprocity(name, bsdf, &mut rng);
    for (k, &(theta, phi)) in WO_ANGLES.iter().enumerate() {
        let wo = direction(theta, phi);
        let case = format!("{name}, θo = {theta}°");
        check_sample_consistency(&case, bsdf, wo, &mut rng);
        let pdf_integral = if expect.chi2 {
            chi2_test(bsdf, wo, CHI2_SAMPLES, seed * 16 + k as u64)
                .unwrap_or_else(|e| panic!("{case}: χ² test failed: {e}"))
        } else {
            integrate_sphere(&|w| bsdf.pdf(wo, w) as f64)
        };
        assert!(
            pdf_integral <= 1.0 + 1e-4,
            "{case}: ∫pdf = {pdf_integral}, expected ≤ 1"
        );
        if expect.lossless {
            assert!(
                (pdf_integral - 1.0).abs() < 1e-4,
                "{case}: ∫pdf = {pdf_integral}, expected 1"
            );
        }
        check_energy(&case, bsdf, wo, expect, &mut rng);
    }
}

/// ∫ f cos dωi: the Monte Carlo estimate (BSDF sampling) agrees with quadrature of eval,
/// is ≤ 1 for white parameters and equals the closed form where one is given.
fn check_energy(case: &str, bsdf: &Bsdf, wo: Vec3, expect: &Expect, rng: &mut Pcg32) {
    let (mean, sigma) = energy_estimate(bsdf, wo, rng);
    // Quadrature of the channel sum, compared with the MC estimate of the channel sum.
    let exact = integrate_sphere(&|w| bsdf.eval(wo, w).element_sum() as f64);
    let (mc_sum, mc_sigma) = (mean.iter().sum::<f64>(), sigma.iter().sum::<f64>());
    assert!(
        (mc_sum - exact).abs() <= 4.0 * mc_sigma + 1e-4 * exact.max(1e-3),
        "{case}: Σ channels ∫f cos: MC {mc_sum} ± {mc_sigma}, quadrature {exact}"
    );
    let theta_side = wo.z.abs().acos().to_degrees();
    for c in 0..3 {
        if expect.white && theta_side <= expect.energy_max_theta_deg + 1e-3 {
            assert!(
                mean[c] <= 1.0 + 3.0 * sigma[c],
                "{case}: channel {c}: ∫f cos = {} ± {} > 1",
                mean[c],
                sigma[c]
            );
        }
        if let Some(albedo) = expect.albedo {
            let a = albedo[c] as f64;
            assert!(
                (mean[c] - a).abs() <= 3.0 * sigma[c] + 1e-5,
                "{case}: channel {c}: ∫f cos = {} ± {}, expected {a}",
                mean[c],
                sigma[c]
            );
        }
    }
    if let Some(albedo) = expect.albedo {
        let a = albedo.element_sum() as f64;
        assert!(
            (exact - a).abs() < 1e-4 * a,
            "{case}: quadrature Σ ∫f cos = {exact}, expected {a}"
        );
    }
}

/// For sampled ωi: unit length, weight = eval/pdf, pdf = pdf(ωo, ωi), not a delta.
pub fn check_sample_consistency(case: &str, bsdf: &Bsdf, wo: Vec3, rng: &mut Pcg32) {
    for _ in 0..20_000 {
        let (u_lobe, u) = (rng.next_f32(), rng.next_vec2());
        let Some(s) = bsdf.sample(wo, u_lobe, u) else {
            continue;
        };
        assert!(
            (s.wi.length() - 1.0).abs() < 1e-4,
            "{case}: |ωi| = {}",
            s.wi.length()
        );
        assert!(!s.delta && s.eta == 1.0, "{case}: sample {s:?}");
        assert!(s.pdf > 0.0 && s.pdf.is_finite(), "{case}: pdf {}", s.pdf);
        let pdf = bsdf.pdf(wo, s.wi);
        assert!(
            (pdf - s.pdf).abs() <= 2e-3 * s.pdf,
            "{case}: sample pdf {} vs pdf(ωo, ωi) {pdf} at ωi = {}",
            s.pdf,
            s.wi
        );
        let expected = bsdf.eval(wo, s.wi) / s.pdf;
        let tol = 2e-3 * expected.max_element().max(1e-6);
        assert!(
            (s.weight - expected).abs().max_element() <= tol && s.weight.min_element() >= 0.0,
            "{case}: weight {} vs eval/pdf {expected} at ωi = {}",
            s.weight,
            s.wi
        );
    }
}

/// eval(ωo, ωi)/|cos θi| = eval(ωi, ωo)/|cos θo| for random pairs on the same side.
pub fn check_reciprocity(name: &str, bsdf: &Bsdf, rng: &mut Pcg32) {
    let mut uniform = || {
        let u = rng.next_vec2();
        square_to_uniform_sphere(u)
    };
    let mut checked = 0;
    while checked < 20_000 {
        let (wo, wi) = (uniform(), uniform());
        if wo.z.abs() < 1e-2 || wi.z.abs() < 1e-2 {
            continue;
        }
        checked += 1;
        let a = bsdf.eval(wo, wi) / wi.z.abs();
        let b = bsdf.eval(wi, wo) / wo.z.abs();
        let tol = 5e-4 * a.max(b).max_element() + 1e-7;
        assert!(
            (a - b).abs().max_element() <= tol,
            "{name}: f(ωo, ωi) = {a} ≠ f(ωi, ωo) = {b} for ωo = {wo}, ωi = {wi}"
        );
        if wo.z * wi.z < 0.0 {
            assert_eq!(
                a,
                Rgb::ZERO,
                "{name}: reflection across the surface, ωo = {wo}, ωi = {wi}"
            );
        }
    }
}

/// Monte Carlo estimate of ∫ f cos θi dωi with the BSDF's own sampling: (mean, standard
/// error) per channel, lost samples counting zero.
pub fn energy_estimate(bsdf: &Bsdf, wo: Vec3, rng: &mut Pcg32) -> ([f64; 3], [f64; 3]) {
    let n = 200_000;
    let (mut sum, mut sum2) = ([0.0f64; 3], [0.0f64; 3]);
    for _ in 0..n {
        let (u_lobe, u) = (rng.next_f32(), rng.next_vec2());
        if let Some(s) = bsdf.sample(wo, u_lobe, u) {
            for c in 0..3 {
                let w = s.weight[c] as f64;
                sum[c] += w;
                sum2[c] += w * w;
            }
        }
    }
    let mean = sum.map(|s| s / n as f64);
    let mut sigma = [0.0; 3];
    for c in 0..3 {
        let var = (sum2[c] / n as f64 - mean[c] * mean[c]).max(0.0);
        sigma[c] = (var / n as f64).sqrt();
    }
    (mean, sigma)
}

/// One configuration of the closed-form θ sweeps: ωo at θo (azimuth 0) and ωi at θi in the
/// plane of incidence, opposite ωo in azimuth or on its side, with the GGX quantities
/// derived by hand from the angles alone (independent of the vector code under test).
pub struct InPlane {
    /// θo, θi in radians.
    pub theta_o: f64,
    /// See `theta_o`.
    pub theta_i: f64,
    /// The directions as the BSDF sees them.
    pub wo: Vec3,
    /// See `wo`.
    pub wi: Vec3,
    /// GGX D(h) = α²/(π cos⁴θh (α² + tan²θh)²) (Walter et al. 2007, eq. 33, angle form).
    pub d: f64,
    /// Λ(θo), Λ(θi) with Λ(θ) = (−1 + √(1 + α² tan²θ))/2.
    pub lambda_o: f64,
    /// See `lambda_o`.
    pub lambda_i: f64,
    /// cos θd = ωo·h.
    pub cos_d: f64,
}

/// Calls `check` for θo ∈ {0°, 30°, 70°} × θi ∈ {0°, 15°, 30°, 50°, 85°} × {opposite, same
/// azimuth}. Opposite: θh = |θi − θo|/2, θd = (θo + θi)/2; same azimuth: θh = (θo + θi)/2,
/// θd = |θo − θi|/2.
pub fn in_plane_sweep(alpha: f64, mut check: impl FnMut(&InPlane)) {
    let lambda = |theta: f64| 0.5 * ((1.0 + alpha * alpha * theta.tan().powi(2)).sqrt() - 1.0);
    for theta_o in [0.0f64, 30.0, 70.0].map(f64::to_radians) {
        for theta_i in [0.0f64, 15.0, 30.0, 50.0, 85.0].map(f64::to_radians) {
            for opposite in [true, false] {
                let (th, td) = if opposite {
                    ((theta_i - theta_o).abs() / 2.0, (theta_o + theta_i) / 2.0)
                } else {
                    ((theta_o + theta_i) / 2.0, (theta_o - theta_i).abs() / 2.0)
                };
                let a2 = alpha * alpha;
                let phi_i = if opposite { std::f32::consts::PI } else { 0.0 };
                check(&InPlane {
                    theta_o,
                    theta_i,
                    wo: direction(theta_o.to_degrees() as f32, 0.0),
                    wi: direction(theta_i.to_degrees() as f32, phi_i),
                    d: a2 / (PI * th.cos().powi(4) * (a2 + th.tan().powi(2)).powi(2)),
                    lambda_o: lambda(theta_o),
                    lambda_i: lambda(theta_i),
                    cos_d: td.cos(),
                });
            }
        }
    }
}

/// |actual − expected| ≤ 10⁻³·|expected| + 10⁻⁶.
pub fn close(actual: f32, expected: f64) -> bool {
    (actual as f64 - expected).abs() <= 1e-3 * expected.abs() + 1e-6
}

/// Checks of a stochastic (multiple-scattering) BSDF, whose sample weight is an estimate of
/// f cos θi / p for a density p with no closed form, so the sample-consistency and χ² checks
/// above do not apply. For g ∈ {1, ωi.x, ωi.z}, ∫ g f cos θi dωi is estimated two ways per
/// channel and must agree within 5σ (+10⁻³): from `bsdf.sample` (the mean of g·weight), and
/// from `bsdf.eval` at directions drawn half from `single` (the same material with single
/// scattering, whose own sample and pdf are exact) and half cosine-weighted. Each draw
/// reseeds the walks. Also at ωo under the surface (two-sided), and `pdf` is `single`'s.
pub fn check_stochastic(name: &str, bsdf: &Bsdf, single: &Bsdf, seed: u64) {
    use super::WalkSeed;
    let mut rng = Pcg32::new(seed, 3);
    let n = 200_000;
    for &(theta, phi) in &WO_ANGLES {
        let wo = direction(theta, phi);
        let up = wo.z.signum();
        let mut sampled = [[[0.0f64; 2]; 3]; 3];
        let mut evaluated = [[[0.0f64; 2]; 3]; 3];
        let moments = |w: Vec3| [1.0f64, w.x as f64, (w.z * up) as f64];
        let add = |acc: &mut [[[f64; 2]; 3]; 3], w: Vec3, value: Rgb| {
            for (g, gv) in moments(w).into_iter().enumerate() {
                for c in 0..3 {
                    let v = gv * value[c] as f64;
                    acc[g][c][0] += v;
                    acc[g][c][1] += v * v;
                }
            }
        };
        for _ in 0..n {
            let walk = WalkSeed((u64::from(rng.next_u32()) << 32) | u64::from(rng.next_u32()));
            let b = bsdf.with_walk_seed(walk);
            let (u_lobe, u) = (rng.next_f32(), rng.next_vec2());
            if let Some(s) = b.sample(wo, u_lobe, u) {
                assert_eq!(s.pdf, single.pdf(wo, s.wi), "{name}: pdf is not the stand-in");
                add(&mut sampled, s.wi, s.weight);
            }
            // A direction from the mixture of `single`'s sampling and cosine weighting.
            let (u_lobe, u) = (rng.next_f32(), rng.next_vec2());
            let wi = if rng.next_f32() < 0.5 {
                single.sample(wo, u_lobe, u).map(|s| s.wi)
            } else {
                let c = crate::sampling::square_to_cosine_hemisphere(u);
                Some(Vec3::new(c.x, c.y, c.z * up))
            };
            if let Some(wi) = wi {
                let q = 0.5 * single.pdf(wo, wi) as f64 + 0.5 * (wi.z * up).max(0.0) as f64 / PI;
                if q > 0.0 {
                    add(&mut evaluated, wi, b.eval(wo, wi) / q as f32);
                }
            }
        }
        for g in 0..3 {
            for c in 0..3 {
                let stats = |[s, s2]: [f64; 2]| {
                    let mean = s / n as f64;
                    (mean, ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt())
                };
                let (a, sa) = stats(sampled[g][c]);
                let (b, sb) = stats(evaluated[g][c]);
                assert!(
                    (a - b).abs() < 5.0 * (sa * sa + sb * sb).sqrt() + 1e-3,
                    "{name}, θo {theta}°, moment {g}, channel {c}: by sampling {a} ± {sa}, by eval {b} ± {sb}"
                );
            }
        }
    }
}
