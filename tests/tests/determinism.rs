//! Determinism: the same bits whatever the thread count, and after an interrupted render is
//! resumed from its checkpoint.

use std::time::Duration;

use glam::Vec3;
use oracle::{CheckpointConfig, RenderError, RenderJob, StopRule};
use scenes::*;
use verity_tests::*;

fn small_scene() -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 1.0, 4.0), Vec3::ZERO, Vec3::Y, 40.0);
    let mut scene = empty_scene(camera, 20, 16);
    add_shape(
        &mut scene,
        "floor",
        square(Vec3::new(0.0, -1.0, 0.0), 10.0, Vec3::Y),
        diffuse(Vec3::splat(0.6)),
    );
    add_shape(
        &mut scene,
        "ball",
        Geometry::Sphere {
            center: Vec3::ZERO,
            radius: 0.8,
        },
        Material::Ggx {
            reflectance: TexRgb::Constant(Vec3::ONE),
            f0: Vec3::new(0.9, 0.6, 0.3),
            roughness: TexScalar::Constant(0.4),
            masking: Masking::HeightCorrelated,
            scattering: Scattering::Single,
            conductor: None,
        },
    );
    let light = add_shape(
        &mut scene,
        "lamp",
        square(Vec3::new(0.0, 2.5, 0.0), 1.0, Vec3::NEG_Y),
        diffuse(Vec3::ZERO),
    );
    scene.shapes[light].emission = Some(Emission {
        radiance: TexRgb::Constant(Vec3::splat(5.0)),
        two_sided: false,
    });
    scene.environment = Some(Environment::Constant {
        radiance: Vec3::new(0.1, 0.2, 0.3),
    });
    scene
}

fn assert_same_bits(a: &scenes::layered::LayeredImage, b: &scenes::layered::LayeredImage) {
    assert_eq!(names(a), names(b));
    for ((name, x), (_, y)) in a.channels.iter().zip(&b.channels) {
        let diff = x
            .iter()
            .zip(y)
            .filter(|(p, q)| p.to_bits() != q.to_bits())
            .count();
        assert_eq!(diff, 0, "channel {name}: {diff} pixels differ");
    }
}

#[test]
fn identical_bits_for_one_and_two_threads() {
    let scene = small_scene();
    let s = settings(IntegratorKind::Path, 6, 9);
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("thread pool")
    };
    let one = pool(1).install(|| render(&scene, s, 12));
    let two = pool(2).install(|| render(&scene, s, 12));
    assert_same_bits(&one.image, &two.image);
    assert!(
        channel(&one.image, "R").iter().any(|&v| v > 0.0),
        "image is black"
    );
}

#[test]
fn interrupted_render_resumes_to_identical_bits() {
    let scene = small_scene();
    let s = settings(IntegratorKind::Path, 6, 4);
    let reference = render(&scene, s, 10);
    let path = std::env::temp_dir().join(format!("verity-resume-{}.ckpt", std::process::id()));
    let _ = std::fs::remove_file(&path);
    let job = RenderJob {
        light_visibility: true,
        scene: &scene,
        settings: s,
        stop: StopRule {
            spp: 10,
            time: None,
            target_rel_err: None,
        },
        checkpoint: Some(CheckpointConfig {
            path: path.clone(),
            interval: Duration::ZERO,
            resume: true,
        }),
    };
    // Interrupt after the first pass (always 1 spp): the checkpoint must be written.
    let err = oracle::render(&job, &mut |p| p.spp_done < 1).expect_err("render should have been interrupted");
    let at = match err {
        RenderError::Interrupted {
            spp,
            checkpointed: true,
        } => spp,
        other => panic!("unexpected error: {other}"),
    };
    assert_eq!(at, 1, "interrupted at {at} spp");
    assert!(path.exists(), "no checkpoint at {}", path.display());
    let resumed = oracle::render(&job, &mut |_| true).expect("resumed render");
    assert_eq!(resumed.spp, 10);
    assert_same_bits(&reference.image, &resumed.image);
    assert!(!path.exists(), "checkpoint not removed after completion");
}

#[test]
fn checkpoint_of_another_scene_is_refused() {
    let scene = small_scene();
    let path = std::env::temp_dir().join(format!("verity-foreign-{}.ckpt", std::process::id()));
    let mk = |scene| RenderJob {
        light_visibility: true,
        scene,
        settings: settings(IntegratorKind::Path, 6, 4),
        stop: StopRule {
            spp: 4,
            time: None,
            target_rel_err: None,
        },
        checkpoint: Some(CheckpointConfig {
            path: path.clone(),
            interval: Duration::ZERO,
            resume: true,
        }),
    };
    let _ = oracle::render(&mk(&scene), &mut |p| p.spp_done < 1);
    let mut other = small_scene();
    other.film.width = 20;
    other.materials[0] = diffuse(Vec3::splat(0.61));
    let err = oracle::render(&mk(&other), &mut |_| true).expect_err("foreign checkpoint accepted");
    assert!(err.to_string().contains("different scene"), "{err}");
    let _ = std::fs::remove_file(&path);
}

#[test]
fn time_budget_and_target_error_stop_early() {
    let scene = small_scene();
    let s = settings(IntegratorKind::Path, 6, 1);
    let job = RenderJob {
        light_visibility: true,
        scene: &scene,
        settings: s,
        stop: StopRule {
            spp: 1 << 20,
            time: Some(Duration::from_millis(300)),
            target_rel_err: None,
        },
        checkpoint: None,
    };
    let r = oracle::render(&job, &mut |_| true).expect("render");
    assert!(r.spp >= 1 && r.spp < 1 << 20, "spp {}", r.spp);
    assert!(r.seconds < 5.0, "time budget overrun: {} s", r.seconds);
    let job = RenderJob {
        light_visibility: true,
        stop: StopRule {
            spp: 1 << 20,
            time: None,
            target_rel_err: Some(0.2),
        },
        ..job
    };
    let target = 0.2;
    let mut history = Vec::new();
    let r = oracle::render(&job, &mut |p| {
        history.push((p.spp_done, p.rel_err));
        true
    })
    .expect("render");
    assert!(r.spp >= 16 && r.spp < 1 << 20, "spp {}", r.spp);
    // The last progress report is made on the final film, just before the rule stops it;
    // every earlier one had the error above the target or fewer than 16 spp (render.rs
    // `stop_now`), else the render went on past the rule.
    let (last_spp, reported) = *history.last().unwrap();
    let measured = mean_relative_error(&r.image);
    println!(
        "target relative error {target}: stopped at {} spp, error {measured:.4}; progress {history:?}",
        r.spp
    );
    assert_eq!(last_spp, r.spp, "the last progress report is of the final film");
    assert!(
        f64::from(reported) <= target,
        "stopped with a reported error {reported} above the target {target}"
    );
    for &(spp, err) in &history[..history.len() - 1] {
        assert!(
            spp < 16 || f64::from(err) > target,
            "at {spp} spp the error {err} already met the target {target}, yet the render went on"
        );
    }
    // Recomputed from the f32 image: equal to the f64 film's value up to rounding.
    assert!(
        (measured - f64::from(reported)).abs() <= 1e-4 * f64::from(reported),
        "image's mean relative error {measured} vs the film's {reported}"
    );
    assert!(
        measured <= target * (1.0 + 1e-4),
        "final mean relative error {measured} above the target {target}"
    );
}

/// `Film::mean_relative_error` (oracle/src/film.rs) from an image: mean over pixels of
/// s̄/(c₄·(|μ̄| + 0.01)), s̄² the estimated variance of the pixel mean and μ̄ the mean, both
/// averaged over R, G, B (`variance.*` is that variance of the mean, from the independent
/// replicates; c₄ of their number corrects the bias of s as an estimate of σ).
fn mean_relative_error(img: &scenes::layered::LayeredImage) -> f64 {
    let replicates: u32 = img
        .attribute("replicates")
        .and_then(|r| r.parse().ok())
        .expect("an oracle image names its replicates");
    let c4 = oracle::film::c4(replicates);
    let (r, g, b) = (channel(img, "R"), channel(img, "G"), channel(img, "B"));
    let (vr, vg, vb) = (
        channel(img, "variance.R"),
        channel(img, "variance.G"),
        channel(img, "variance.B"),
    );
    let n = r.len();
    let sum: f64 = (0..n)
        .map(|i| {
            let var = (f64::from(vr[i]) + f64::from(vg[i]) + f64::from(vb[i])) / 3.0;
            let mean = (f64::from(r[i]) + f64::from(g[i]) + f64::from(b[i])) / 3.0;
            var.sqrt() / (c4 * (mean.abs() + 0.01))
        })
        .sum();
    sum / n as f64
}
