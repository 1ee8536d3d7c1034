//! Light-map lookups end to end on the adapter at hand (lavapipe in CI): a floor seen straight
//! down (so pixels map affinely onto it) under a map whose texels hold an affine irradiance
//! E(c) = 1 + 3c_u + 2c_v of their chart coordinates, sampled at the texel centres the bake
//! uses (`Chart::texel_centre`). Bilinear and cubic B-spline lookups both reproduce affine
//! functions exactly, so the image must be affine in the pixel coordinates and equal ρ/π·E(½, ½)
//! under the camera — a half-texel error in the lookup would be off by 5/(2·16) of E there.
//! The same floor as a two-triangle mesh reads its chart through its uv1 (TEXCOORD_1).
//! Also: a light-map method without a map, a map without a light-map method, a map of
//! another scene and a light-mapped mesh in the deferred pipeline are refused. Accuracy against the oracle is the studies'
//! (scenes/studies/lightmap-*.toml).

mod support;

use std::sync::Arc;

use glam::Vec3;
use realtime::technique::lightmap::BakedMap;
use realtime::{RasterError, RasterSettings};
use scenes::lightmap::{layout, LightMap};
use scenes::{Geometry, Mesh};
use support::{method, renderer};

const SIZE: u32 = 32;
const ALBEDO: f32 = 0.5;

fn floor_scene() -> scenes::Scene {
    scenes::toml::load_str(
        "[camera]\neye = [0, 3, 0]\ntarget = [0, 0, 0]\nup = [0, 0, -1]\nfov = 40\n\
         [film]\nwidth = 32\nheight = 32\n\
         [[material]]\nname = \"m\"\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
         [[shape]]\nname = \"floor\"\ntype = \"rectangle\"\nmaterial = \"m\"\ncenter = [0, 0, 0]\n\
         size = [4, 4]\nnormal = [0, 1, 0]\n\
         [[light]]\nname = \"bulb\"\ntype = \"point\"\nposition = [0.5, 1, 0]\nintensity = 3\n",
        std::path::Path::new("floor.toml"),
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

fn affine(c: glam::Vec2) -> f32 {
    1.0 + 3.0 * c.x + 2.0 * c.y
}

/// A 16-texel map of the floor holding the affine E at every texel centre, its padding
/// continuing the same function (so that lookups at the border stay exact).
fn affine_map(scene: &scenes::Scene) -> BakedMap {
    let l = layout(scene, 16, 2, &[]).unwrap();
    let chart = l.charts[0].clone();
    let n = (l.width * l.height) as usize;
    let mut irradiance = vec![Vec3::ZERO; n];
    for y in 0..l.height {
        for x in 0..l.width {
            let (i, j) = (x as f32 - chart.x as f32, y as f32 - chart.y as f32);
            let c = glam::Vec2::new((i + 0.5) / chart.width as f32, (j + 0.5) / chart.height as f32);
            irradiance[(y * l.width + x) as usize] = Vec3::splat(affine(c));
        }
    }
    assert_eq!(
        chart.texel_centre(3, 5, 0.0),
        glam::Vec2::new(3.5 / 16.0, 5.5 / 16.0)
    );
    BakedMap {
        map: Arc::new(LightMap {
            layout: l,
            irradiance,
            variance: vec![Vec3::ZERO; n],
            covered: vec![true; n],
        }),
        label: "affine test map".into(),
    }
}

fn settings(name: &str) -> RasterSettings {
    RasterSettings::new(SIZE, SIZE)
        .method(method(name, &[]))
        .frames(0, 1)
}

/// The floor as a two-triangle mesh whose uv1 runs over [0, 1]² with the position.
fn mesh_floor_scene() -> scenes::Scene {
    let mut scene = floor_scene();
    let corners = [(-2.0, -2.0), (2.0, -2.0), (2.0, 2.0), (-2.0, 2.0)];
    scene.shapes[0].geometry = Geometry::Mesh(Arc::new(Mesh {
        positions: corners.map(|(x, z)| Vec3::new(x, 0.0, z)).to_vec(),
        uv1: corners
            .map(|(x, z)| glam::Vec2::new((x + 2.0) / 4.0, (z + 2.0) / 4.0))
            .to_vec(),
        // Counter-clockwise seen from above (+Y).
        indices: vec![[0, 2, 1], [0, 3, 2]],
        ..Mesh::default()
    }));
    scene
}

#[test]
fn lookups_reproduce_an_affine_irradiance_at_the_texel_centres() {
    for (scene, what) in [(floor_scene(), "rectangle"), (mesh_floor_scene(), "mesh")] {
        for name in ["lightmap_bilinear", "lightmap_bicubic"] {
            affine_read_back(&scene, &format!("{name} on a {what}"), name);
        }
    }
}

/// Renders `scene` with `method` under its affine map; `what` names the case in messages.
fn affine_read_back(scene: &scenes::Scene, what: &str, method: &str) {
    let out = renderer()
        .render(scene, &settings(method).lightmap(affine_map(scene)))
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    let rgb = out.image.rgb("").unwrap();
    let at = |i: u32, j: u32| rgb[(j * SIZE + i) as usize].x;
    // The four pixels around the image centre average to the point under the camera.
    let h = SIZE / 2;
    let centre = (at(h - 1, h - 1) + at(h, h - 1) + at(h - 1, h) + at(h, h)) / 4.0;
    let expected = ALBEDO / std::f32::consts::PI * affine(glam::Vec2::splat(0.5));
    assert!(
        (centre / expected - 1.0).abs() < 2e-4,
        "{what}: {centre} under the camera, expected {expected}"
    );
    // Affine in the pixels: every second difference vanishes.
    let mut worst = 0.0f32;
    for j in 1..SIZE - 1 {
        for i in 1..SIZE - 1 {
            let d2x = at(i - 1, j) - 2.0 * at(i, j) + at(i + 1, j);
            let d2y = at(i, j - 1) - 2.0 * at(i, j) + at(i, j + 1);
            worst = worst.max(d2x.abs()).max(d2y.abs());
        }
    }
    assert!(worst < 1e-4 * expected, "{what}: a second difference of {worst}");
    // A gradient along both axes (not a constant map read back).
    assert!(
        (at(SIZE - 1, h) - at(0, h)).abs() > 0.1 * expected,
        "{what}: flat along x"
    );
    assert!(
        (at(h, SIZE - 1) - at(h, 0)).abs() > 0.1 * expected,
        "{what}: flat along y"
    );
}

#[test]
fn maps_and_methods_must_go_together() {
    let scene = floor_scene();
    let map = affine_map(&scene);
    let e = renderer()
        .render(&scene, &settings("lightmap_bilinear"))
        .unwrap_err();
    assert!(
        matches!(&e, RasterError::Settings(m) if m.contains("none was given")),
        "{e}"
    );
    let e = renderer()
        .render(&scene, &settings("area_quadrature").lightmap(map.clone()))
        .unwrap_err();
    assert!(
        matches!(&e, RasterError::Settings(m) if m.contains("does not read one")),
        "{e}"
    );
    let mesh = mesh_floor_scene();
    let e = renderer()
        .render(
            &mesh,
            &settings("lightmap_bilinear")
                .pipeline(realtime::PipelineKind::Deferred)
                .lightmap(affine_map(&mesh)),
        )
        .unwrap_err();
    assert!(
        matches!(&e, RasterError::Settings(m) if m.contains("light-mapped mesh") && m.contains("forward")),
        "{e}"
    );
    let mut other = scene.clone();
    other.shapes[0].name = "ground".into();
    let e = renderer()
        .render(&other, &settings("lightmap_bilinear").lightmap(map))
        .unwrap_err();
    assert!(
        matches!(&e, RasterError::Scene(m) if m.contains("chart `floor` names no shape")),
        "{e}"
    );
}

/// `specular = direct` adds the lights' specular lobes per pixel: on a Lambertian floor under a
/// point light (which has none) the image is the plain map's bit for bit, and without the
/// option the light adds nothing (the map holds every light).
#[test]
fn direct_specular_adds_nothing_to_a_diffuse_surface() {
    let scene = floor_scene();
    let map = affine_map(&scene);
    let render = |params: &[(&str, &str)]| {
        let s = RasterSettings::new(SIZE, SIZE)
            .method(method("lightmap_bilinear", params))
            .frames(0, 1)
            .lightmap(map.clone());
        renderer()
            .render(&scene, &s)
            .unwrap_or_else(|e| panic!("{e}"))
            .image
            .rgb("")
            .unwrap()
    };
    let (plain, direct) = (render(&[]), render(&[("specular", "direct")]));
    assert!(
        plain.iter().zip(&direct).all(|(a, b)| a == b),
        "a diffuse floor changed"
    );
    let mut unlit = scene.clone();
    unlit.lights.clear();
    let s = RasterSettings::new(SIZE, SIZE)
        .method(method("lightmap_bilinear", &[]))
        .frames(0, 1)
        .lightmap(map);
    let without = renderer().render(&unlit, &s).unwrap().image.rgb("").unwrap();
    assert!(
        plain.iter().zip(&without).all(|(a, b)| a == b),
        "the map holds every light"
    );
}
