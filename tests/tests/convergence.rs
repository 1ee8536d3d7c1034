//! Convergence: an unbiased Monte Carlo estimator with independent samples has relMSE against
//! the converged image ∝ 1/spp, a log-log slope of −1 (Veach 1997, §2.4); a biased estimator
//! flattens out, a broken one changes the slope. Owen-scrambled Sobol points converge at least
//! as fast (Owen 1997, "Scrambled net variance for integrals of smooth functions"), so their
//! slope must be −1 or steeper.

use std::path::Path;
use std::sync::OnceLock;

use scenes::layered::LayeredImage;

use verity_tests::*;

fn cornell() -> (scenes::Scene, scenes::RenderSettings) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box.toml");
    let mut scene = scenes::load(&path).unwrap_or_else(|e| panic!("{e}"));
    scene.film = scenes::Film {
        width: 32,
        height: 32,
    };
    let mut s = scene.render;
    s.max_depth = 6;
    s.integrator = scenes::IntegratorKind::Path;
    (scene, s)
}

/// 4096 spp with independent samples and its own seed: its error is independent of the test
/// renders', and its per-pixel variance estimates its noise without bias.
fn reference() -> &'static LayeredImage {
    static REFERENCE: OnceLock<LayeredImage> = OnceLock::new();
    REFERENCE.get_or_init(|| {
        let (scene, s) = cornell();
        let s = scenes::RenderSettings {
            seed: 1000,
            sampler: scenes::SamplerKind::Independent,
            ..s
        };
        render(&scene, s, 4096).image
    })
}

/// Log-log slope of relMSE against spp for the Cornell box with `sampler`.
fn cornell_slope(sampler: scenes::SamplerKind) -> f64 {
    let (scene, mut s) = cornell();
    s.sampler = sampler;
    let reference = reference();
    let floor = reference_noise_rel_mse(reference);
    let spps = [4u32, 16, 64, 256];
    let mut xs = Vec::new();
    let mut ys = Vec::new();
    for &spp in &spps {
        let img = render(&scene, scenes::RenderSettings { seed: 7, ..s }, spp).image;
        // E[(a − r)²] = Var(a) + Var(r): remove the reference's share.
        let err = rel_mse(&img, reference) - floor;
        println!("{sampler:?} spp {spp:5}: relMSE {err:.3e} (reference noise {floor:.3e})");
        assert!(err > 0.0, "relMSE at {spp} spp below the reference's noise floor");
        xs.push(f64::from(spp).ln());
        ys.push(err.ln());
    }
    slope(&xs, &ys)
}

#[test]
fn rel_mse_falls_as_one_over_spp_with_independent_samples() {
    let k = cornell_slope(scenes::SamplerKind::Independent);
    assert!(
        (-1.15..=-0.85).contains(&k),
        "log-log slope {k:.3}, expected −1 ± 15 %"
    );
}

#[test]
fn rel_mse_falls_at_least_as_one_over_spp_with_sobol_samples() {
    let k = cornell_slope(scenes::SamplerKind::Sobol);
    // Faster than −1 is QMC's gain. Steeper than −2 is not plausible for a path-traced image
    // with edges and 6-bounce paths: it would mean the renders share samples with the reference.
    assert!(
        (-2.0..=-0.85).contains(&k),
        "log-log slope {k:.3}, expected between −2 and −0.85"
    );
}
