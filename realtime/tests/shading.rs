//! Shading frequency end to end on the adapter at hand (lavapipe in CI), on the shading
//! study's glossy icosphere (scenes/studies/scenes/shading-sphere.toml) at 48²: per-vertex
//! lighting matches per-pixel lighting on a fine mesh and loses the highlights on a coarse
//! one; flat shading gives every triangle one colour; the analytic floor is shaded per pixel
//! under every frequency; the deferred pipeline refuses vertex lighting; Gouraud applies a
//! texture per pixel with the specular interpolated apart (shading-textured-sphere.toml).
//! Accuracy against the oracle is the studies' (scenes/studies/shading-frequency*.toml).

mod support;

use std::path::Path;

use realtime::{PipelineKind, RasterError, RasterOutput, RasterSettings};
use support::{method, renderer, rgb_id};

const SIZE: u32 = 48;

fn sphere(subdivisions: u32) -> scenes::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/scenes/shading-sphere.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let dir = std::env::temp_dir().join(format!("verity-shading-{}-{subdivisions}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let copy = dir.join("shading-sphere.toml");
    std::fs::write(
        &copy,
        text.replace("subdivisions = 3", &format!("subdivisions = {subdivisions}")),
    )
    .unwrap();
    let scene = scenes::load(&copy).unwrap_or_else(|e| panic!("{e}"));
    std::fs::remove_dir_all(&dir).ok();
    scene
}

fn settings(name: &str) -> RasterSettings {
    RasterSettings::new(SIZE, SIZE)
        .method(method(name, &[("env_n", "0"), ("n", "8")]))
        .frames(0, 1)
}

fn render(scene: &scenes::Scene, name: &str) -> RasterOutput {
    renderer()
        .render(scene, &settings(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Mean squared difference of the RGB channels over the pixels whose object is `id` (the ball
/// is shape 0: id 1; the floor id 2).
fn mse_on(a: &RasterOutput, b: &RasterOutput, id: f32) -> f64 {
    let (a, ids) = rgb_id(a);
    let (b, _) = rgb_id(b);
    let picked: Vec<usize> = (0..a.len()).filter(|&i| ids[i] == id).collect();
    assert!(picked.len() > 50, "object {id} covers {} pixels", picked.len());
    let (a, b) = (&a, &b);
    picked
        .iter()
        .flat_map(|&i| (0..3).map(move |c| (f64::from(a[i][c]) - f64::from(b[i][c])).powi(2)))
        .sum::<f64>()
        / (3 * picked.len()) as f64
}

#[test]
fn vertex_lighting_converges_on_fine_meshes_and_loses_highlights_on_coarse_ones() {
    let (coarse, fine) = (sphere(1), sphere(5));
    let phong = (render(&coarse, "shading_phong"), render(&fine, "shading_phong"));
    let gouraud = (
        render(&coarse, "shading_gouraud"),
        render(&fine, "shading_gouraud"),
    );
    let flat = (render(&coarse, "shading_flat"), render(&fine, "shading_flat"));
    let (g_coarse, g_fine) = (
        mse_on(&gouraud.0, &phong.0, 1.0),
        mse_on(&gouraud.1, &phong.1, 1.0),
    );
    let (f_coarse, f_fine) = (mse_on(&flat.0, &phong.0, 1.0), mse_on(&flat.1, &phong.1, 1.0));
    eprintln!("MSE against per-pixel lighting on the ball: Gouraud {g_coarse:.3e} → {g_fine:.3e}, flat {f_coarse:.3e} → {f_fine:.3e}");
    assert!(
        g_coarse > 1e-2 && g_fine < 0.05 * g_coarse,
        "Gouraud: {g_coarse:.3e} → {g_fine:.3e}"
    );
    assert!(
        f_coarse > 1e-2 && f_fine < 0.2 * f_coarse && f_fine > g_fine,
        "flat: {f_coarse:.3e} → {f_fine:.3e}"
    );
    // The floor is an analytic rectangle: per pixel under every frequency, bit for bit.
    for (name, out) in [("shading_gouraud", &gouraud.0), ("shading_flat", &flat.0)] {
        assert_eq!(
            mse_on(out, &phong.0, 2.0),
            0.0,
            "{name} changed the analytic floor"
        );
    }
    // Flat: one colour per triangle, so far fewer distinct colours on the ball than per pixel.
    let distinct = |o: &RasterOutput| {
        let (rgb, ids) = rgb_id(o);
        let mut v: Vec<[u32; 3]> = (0..rgb.len())
            .filter(|&i| ids[i] == 1.0)
            .map(|i| rgb[i].map(f32::to_bits))
            .collect();
        v.sort_unstable();
        v.dedup();
        v.len()
    };
    assert!(
        distinct(&flat.0) * 3 < distinct(&phong.0),
        "flat shading: {} colours, per pixel {}",
        distinct(&flat.0),
        distinct(&phong.0)
    );
}

#[test]
fn the_deferred_pipeline_refuses_vertex_lighting() {
    let s = settings("shading_gouraud").pipeline(PipelineKind::Deferred);
    match renderer().render(&sphere(2), &s) {
        Err(RasterError::Settings(m)) => assert!(m.contains("vertex stage"), "{m}"),
        other => panic!("deferred Gouraud: {:?}", other.map(|o| o.timing)),
    }
    assert!(renderer()
        .render(
            &sphere(2),
            &settings("shading_phong").pipeline(PipelineKind::Deferred)
        )
        .is_ok());
}

/// The textured plastic sphere of scenes/studies/scenes/shading-textured-sphere.toml (a UV
/// sphere with a checker base colour); `untextured` gives the plastic a constant colour.
fn textured_sphere(untextured: bool) -> scenes::Scene {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/scenes/shading-textured-sphere.toml");
    if !untextured {
        return scenes::load(&path).unwrap_or_else(|e| panic!("{e}"));
    }
    let edit = scenes::toml::overrides::Override {
        path: "material.plastic.base_color".into(),
        edit: scenes::toml::overrides::Edit::Set(scenes::toml::tree::Value::Float(0.3)),
    };
    scenes::toml::load_with(&path, &[edit]).unwrap_or_else(|e| panic!("{e}"))
}

fn gouraud(scene: &scenes::Scene, albedo: &str) -> RasterOutput {
    let s = RasterSettings::new(SIZE, SIZE)
        .method(method(
            "shading_gouraud",
            &[("env_n", "0"), ("n", "8"), ("albedo", albedo)],
        ))
        .frames(0, 1);
    renderer()
        .render(scene, &s)
        .unwrap_or_else(|e| panic!("albedo = {albedo}: {e}"))
}

/// Gouraud's texture variants: with a constant base colour, the specular term interpolated
/// separately is the vertex colour split in two (the same image to rounding), while
/// modulating multiplies the white specular by the base colour (darker highlights); with the
/// checker, applying it per pixel to the diffuse term alone comes closest to per-pixel
/// shading, and the other two are further off.
#[test]
fn gouraud_applies_a_texture_per_pixel_with_the_specular_apart() {
    let plain = textured_sphere(true);
    let ball = 1.0 + plain.shapes.iter().position(|s| s.name == "sphere/0").unwrap() as f32;
    let (vertex, separate, modulate) = (
        gouraud(&plain, "vertex"),
        gouraud(&plain, "separate_specular"),
        gouraud(&plain, "modulate"),
    );
    let split = mse_on(&separate, &vertex, ball);
    let darker = mse_on(&modulate, &vertex, ball);
    eprintln!(
        "constant base colour, MSE against vertex: separate specular {split:.3e}, modulate {darker:.3e}"
    );
    assert!(
        split < 1e-9,
        "separate specular on a constant colour: {split:.3e}"
    );
    assert!(darker > 1e-5, "modulate on a constant colour: {darker:.3e}");
    let sum = |o: &RasterOutput| -> f64 {
        let (rgb, ids) = rgb_id(o);
        (0..rgb.len())
            .filter(|&i| ids[i] == ball)
            .map(|i| rgb[i].iter().map(|&c| f64::from(c)).sum::<f64>())
            .sum()
    };
    assert!(sum(&modulate) < sum(&vertex), "modulating darkens the highlights");

    let checker = textured_sphere(false);
    let phong = renderer().render(&checker, &settings("shading_phong")).unwrap();
    let errors: Vec<(&str, f64)> = ["separate_specular", "modulate", "vertex"]
        .into_iter()
        .map(|a| (a, mse_on(&gouraud(&checker, a), &phong, ball)))
        .collect();
    eprintln!("checker, MSE against per pixel: {errors:?}");
    assert!(
        errors[0].1 < 0.7 * errors[1].1 && errors[0].1 < 0.7 * errors[2].1,
        "{errors:?}"
    );
}
