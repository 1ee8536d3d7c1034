//! Convergence: an unbiased Monte Carlo estimator's relMSE against the converged image falls
//! as 1/spp, so its log-log slope is −1 (Veach 1997, §2.4). A biased estimator flattens out;
//! a broken sampler or estimator changes the slope.

use std::path::Path;

use verity_tests::*;

#[test]
fn rel_mse_falls_as_one_over_spp_on_the_cornell_box() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box.toml");
    let mut scene = scenes::load(&path).unwrap_or_else(|e| panic!("{e}"));
    scene.film = scenes::Film { width: 32, height: 32 };
    let mut s = scene.render;
    s.max_depth = 6;
    s.integrator = scenes::IntegratorKind::Path;
    // The reference uses another seed: its error is independent of the test renders'.
    let reference = render(&scene, scenes::RenderSettings { seed: 1000, ..s }, 4096).image;
    let floor = reference_noise_rel_mse(&reference);
    let spps = [4u32, 16, 64, 256];
    let mut xs = Vec::new();
    let mut ys = Vec::new();
    for &spp in &spps {
        let img = render(&scene, scenes::RenderSettings { seed: 7, ..s }, spp).image;
        // E[(a − r)²] = Var(a) + Var(r): remove the reference's share.
        let err = rel_mse(&img, &reference) - floor;
        println!("spp {spp:5}: relMSE {err:.3e} (reference noise {floor:.3e})");
        assert!(err > 0.0, "relMSE at {spp} spp below the reference's noise floor");
        xs.push(f64::from(spp).ln());
        ys.push(err.ln());
    }
    let k = slope(&xs, &ys);
    assert!((-1.15..=-0.85).contains(&k), "log-log slope {k:.3}, expected −1 ± 15 %");
}
