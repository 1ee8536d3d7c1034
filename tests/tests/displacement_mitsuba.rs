//! Mitsuba 3 cross-check of true displacement: the oracle's heightfield patch (a displaced
//! rectangle, traced exactly) against Mitsuba rendering the same surface exported as an
//! explicit mesh (`scenes::displacement::patch_mesh`, every bilinear cell split 16 × 16),
//! under the per-pixel z-test of the other cross-checks (compare/README.md). The negative
//! control renders Mitsuba's mesh at 0.8 × the height scale, which the z-test must reject.
//!
//! The exporter itself does not yet know about displacement (it would write the base
//! rectangle), so the test exports a scene holding the explicit mesh; Mitsuba missing is a
//! failure that says what to install, never a skip.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use compare::mitsuba::crosscheck::{crosscheck, CrossCheckOptions};
use compare::mitsuba::runner::Variant;
use glam::Vec3;
use scenes::displacement::{patch_mesh, HeightGrid, PatchFrame, Procedural};
use scenes::{Camera, Displacement, Geometry, IntegratorKind, Light, Scene, WrapMode};
use verity_tests::{add_shape, diffuse, empty_scene};

/// Half size of the patch (m) and its displacement scale (m per unit height).
const HALF: f32 = 0.5;
const SCALE: f32 = 0.15;

/// The oracle's scene: the displaced patch (8 × 8 texels of 2 × 2 bumps) under a sun 30°
/// up and a dim sky, `direct` integrator; and the same with the patch as an explicit mesh of
/// `scale_factor` × the heights.
fn scenes_pair(scale_factor: f32) -> (Scene, Scene) {
    let texture = Procedural::Bumps { tiles: 2 }.texture(8, [WrapMode::Clamp; 2]);
    let camera = Camera::look_at(Vec3::new(0.0, 1.3, 1.5), Vec3::ZERO, Vec3::Y, 40.0);
    let mut base = empty_scene(camera, 64, 64);
    base.render.integrator = IntegratorKind::Direct;
    base.render.max_depth = 2;
    let e = 30f32.to_radians();
    base.lights.push(Light::Directional {
        name: "sun".to_string(),
        direction: Vec3::new(-e.cos(), -e.sin(), 0.0),
        irradiance: Vec3::splat(2.0),
        angular_diameter_deg: 0.0,
    });
    base.environment = Some(scenes::Environment::Constant {
        radiance: Vec3::splat(0.2),
    });
    let (half_u, half_v) = (Vec3::X * HALF, Vec3::NEG_Z * HALF);
    let mut displaced = base.clone();
    displaced.textures.push(Arc::new(texture.clone()));
    let rectangle = Geometry::Rectangle {
        center: Vec3::ZERO,
        half_u,
        half_v,
    };
    let i = add_shape(&mut displaced, "patch", rectangle, diffuse(Vec3::splat(0.7)));
    displaced.shapes[i].displacement = Some(Displacement {
        texture: 0,
        channel: 0,
        scale: SCALE,
    });
    let frame = PatchFrame::new(Vec3::ZERO, half_u, half_v).expect("a rectangle");
    let grid = HeightGrid::new(&texture, 0, SCALE * scale_factor);
    let mesh = Geometry::Mesh(Arc::new(patch_mesh(&frame, &grid, 16)));
    let mut explicit = base;
    add_shape(&mut explicit, "patch", mesh, diffuse(Vec3::splat(0.7)));
    (displaced, explicit)
}

fn out_dir(tag: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("mitsuba-displacement-{tag}"))
}

/// Cross-checks Mitsuba's render of the explicit mesh (heights × `scale_factor`) against the
/// oracle's heightfield patch; returns whether the z-test passed and its relMSE.
fn check(tag: &str, scale_factor: f32) -> (bool, f64) {
    let (oracle_scene, exported) = scenes_pair(scale_factor);
    let opts = CrossCheckOptions {
        spp: 256,
        variant: Variant::LlvmAdRgb,
        out_dir: out_dir(tag),
        verbose: false,
    };
    let c = crosscheck(&exported, &oracle_scene, &opts)
        .unwrap_or_else(|e| panic!("{tag}: cross-check could not run: {e}"));
    let z = &c.ztest;
    println!(
        "{tag}: pass {} — {:.3} % of pixel-channels pass, min p {:.2e}, relMSE {:.3e} (noise {:.3e}); oracle {:.2} s, Mitsuba {:.2} s; {}",
        z.pass,
        100.0 * z.passed_fraction,
        z.min_p,
        z.relmse,
        z.relmse_noise,
        c.oracle_seconds,
        c.mitsuba.timings.render_s,
        c.scene_xml.display()
    );
    (z.pass, z.relmse)
}

#[test]
fn displaced_patch_agrees_with_mitsuba_on_its_mesh() {
    let (pass, relmse) = check("patch", 1.0);
    assert!(
        pass,
        "the oracle's displaced patch and Mitsuba's mesh of it disagree (relMSE {relmse:.3e}); see {}",
        out_dir("patch").display()
    );
    let (pass, relmse) = check("wrong-scale", 0.8);
    assert!(!pass, "the z-test accepted Mitsuba's mesh at 0.8× the heights (relMSE {relmse:.3e}): it cannot tell the surfaces apart");
}
