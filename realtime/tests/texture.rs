//! Texture filters end to end on the adapter at hand (lavapipe in CI), on the texture-filtering
//! study's checkerboard plane (scenes/studies/scenes/texture-plane.toml) at 48²: where texels
//! are magnified every MIP-based filter is the bilinear lookup; at the horizon, where hundreds
//! of texels fall in a pixel, MIP-mapped filters give the checker's mean (0.5 in linear
//! radiance) and the sRGB-space mistake its sRGB mean decoded (0.214), while point lookups
//! scatter 0s and 1s; `tex_bilinear` is exactly the lookup of every other method; analytic
//! derivatives need the forward pipeline; a mesh and the rectangle it tessellates filter alike
//! (the mesh's `dpdx` against the analytic shape's in-lane differences). Accuracy against the oracle is the study's
//! (scenes/studies/texture-filtering.toml).

mod support;

use std::path::Path;

use realtime::{PipelineKind, RasterError, RasterOutput, RasterSettings};
use support::{method, renderer, rgb_id};

const SIZE: u32 = 48;

fn plane() -> scenes::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/scenes/texture-plane.toml");
    scenes::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn render(name: &str, params: &[(&str, &str)]) -> RasterOutput {
    render_scene(&plane(), name, params)
}

fn render_scene(scene: &scenes::Scene, name: &str, params: &[(&str, &str)]) -> RasterOutput {
    let mut all = vec![("env_n", "0")];
    all.extend_from_slice(params);
    let settings = RasterSettings::new(SIZE, SIZE)
        .method(method(name, &all))
        .frames(0, 1)
        .counters(false);
    renderer()
        .render(scene, &settings)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The red channel of rows `rows` (top row 0), only where the plane is seen.
fn rows(out: &RasterOutput, rows: std::ops::Range<u32>) -> Vec<f32> {
    let (rgb, ids) = rgb_id(out);
    rows.flat_map(|y| (0..SIZE).map(move |x| (y * SIZE + x) as usize))
        .filter(|&i| ids[i] > 0.0)
        .map(|i| rgb[i][0])
        .collect()
}

/// The first rows below the horizon that show the plane across the whole width.
fn horizon(out: &RasterOutput) -> std::ops::Range<u32> {
    let (_, ids) = rgb_id(out);
    let first = (0..SIZE)
        .find(|&y| (0..SIZE).all(|x| ids[(y * SIZE + x) as usize] > 0.0))
        .expect("the plane fills the lower rows");
    first..first + 3
}

fn mean(v: &[f32]) -> f64 {
    v.iter().map(|&x| f64::from(x)).sum::<f64>() / v.len() as f64
}

#[test]
fn tex_bilinear_is_every_other_methods_lookup() {
    let a = render("tex_bilinear", &[]);
    let b = render("area_quadrature", &[]);
    assert_eq!(rgb_id(&a), rgb_id(&b));
}

#[test]
fn mip_filters_are_bilinear_where_texels_are_magnified_and_the_mean_at_the_horizon() {
    let bilinear = render("tex_bilinear", &[]);
    let near = (SIZE - 4)..SIZE;
    let far = horizon(&bilinear);
    let reference = rows(&bilinear, near.clone());
    for (name, params) in [
        ("tex_mip_nearest", vec![]),
        ("tex_trilinear", vec![]),
        ("tex_trilinear", vec![("derivatives", "analytic")]),
        ("tex_sat", vec![]),
        ("tex_ripmap", vec![]),
    ] {
        let out = render(name, &params);
        let fg = rows(&out, near.clone());
        let worst = fg
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(
            worst < 2e-3,
            "{name} {params:?}: {worst} from bilinear where magnified"
        );
        let m = mean(&rows(&out, far.clone()));
        assert!(
            (m - 0.5).abs() < 0.08,
            "{name} {params:?}: horizon mean {m}, not the checker's 0.5"
        );
    }
    for (name, params) in [("tex_footprint", vec![]), ("tex_ewa", vec![])] {
        let m = mean(&rows(&render(name, &params), far.clone()));
        assert!((m - 0.5).abs() < 0.08, "{name}: horizon mean {m}");
    }
    // sRGB-space levels: the mean of the encodings, 0.5, decodes to 0.214 (IEC 61966-2-1).
    let srgb = mean(&rows(
        &render("tex_trilinear", &[("mip_space", "srgb")]),
        far.clone(),
    ));
    assert!(
        (srgb - 0.214).abs() < 0.06,
        "sRGB-space levels: horizon mean {srgb}"
    );
    // Point lookups alias: the horizon rows keep values far from the mean.
    for name in ["tex_nearest", "tex_bilinear"] {
        let v = rows(&render(name, &[]), far.clone());
        let spread = v.iter().map(|&x| (f64::from(x) - 0.5).abs()).sum::<f64>() / v.len() as f64;
        assert!(
            spread > 0.25,
            "{name}: horizon values within {spread} of the mean, no aliasing?"
        );
    }
}

#[test]
fn a_larger_lod_bias_blurs_and_more_anisotropy_sharpens() {
    let far_rows = |out: &RasterOutput| {
        let r = horizon(out);
        rows(out, r.start + 3..r.start + 10)
    };
    let contrast = |v: Vec<f32>| v.iter().map(|&x| (f64::from(x) - 0.5).abs()).sum::<f64>() / v.len() as f64;
    let biased = contrast(far_rows(&render("tex_trilinear", &[("lod_bias", "2")])));
    let plain = contrast(far_rows(&render("tex_trilinear", &[])));
    assert!(biased < plain, "lod_bias 2 kept contrast {biased} ≥ {plain}");
    let one = contrast(far_rows(&render("tex_footprint", &[("max_anisotropy", "1")])));
    let sixteen = contrast(far_rows(&render("tex_footprint", &[("max_anisotropy", "16")])));
    assert!(
        sixteen > one,
        "16 probes kept contrast {sixteen} ≤ 1 probe's {one}"
    );
}

#[test]
fn analytic_derivatives_need_the_forward_pipeline() {
    let settings = RasterSettings::new(SIZE, SIZE)
        .method(method("tex_trilinear", &[("derivatives", "analytic")]))
        .pipeline(PipelineKind::Deferred);
    match renderer().render(&plane(), &settings) {
        Err(RasterError::Settings(m)) => assert!(m.contains("needs the forward pipeline"), "{m}"),
        other => panic!("expected a settings error, got {:?}", other.map(|_| ())),
    }
}

/// The plane as a two-triangle mesh with the rectangle's uv (corner (s, t) at
/// center + s·half_u + t·half_v has uv ((s + 1)/2, (t + 1)/2)): the mesh's hardware
/// derivatives (`dpdx` of the interpolated uv) and the rectangle's in-lane differences give
/// the same filtered image, with no line along the diagonal where the quads straddle the two
/// triangles.
#[test]
fn a_mesh_and_the_rectangle_it_tessellates_filter_alike() {
    let rectangle = plane();
    let mut mesh = rectangle.clone();
    let scenes::Geometry::Rectangle {
        center,
        half_u,
        half_v,
    } = rectangle.shapes[0].geometry
    else {
        panic!("the study's plane is a rectangle");
    };
    let corners = [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    mesh.shapes[0].geometry = scenes::Geometry::Mesh(std::sync::Arc::new(scenes::Mesh {
        positions: corners
            .iter()
            .map(|&(s, t)| center + half_u * s + half_v * t)
            .collect(),
        uvs: corners
            .iter()
            .map(|&(s, t)| glam::Vec2::new((s + 1.0) / 2.0, (t + 1.0) / 2.0))
            .collect(),
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..Default::default()
    }));
    for name in ["tex_trilinear", "tex_ewa"] {
        let (a, ids) = rgb_id(&render_scene(&rectangle, name, &[]));
        let (b, _) = rgb_id(&render_scene(&mesh, name, &[]));
        let worst = (0..a.len())
            .filter(|&i| ids[i] > 0.0)
            .map(|i| (a[i][0] - b[i][0]).abs())
            .fold(0.0f32, f32::max);
        assert!(
            worst < 0.05,
            "{name}: mesh and rectangle differ by {worst} in a pixel"
        );
    }
}

/// The adapter's sampler at max_anisotropy 1 is trilinear over the same levels: the image is
/// `tex_trilinear`'s but for f16 texels and the adapter's own λ (the right layer, levels and
/// orientation are sampled).
#[test]
fn tex_anisotropic_at_1_is_the_adapters_trilinear() {
    let (a, ids) = rgb_id(&render("tex_anisotropic", &[("max_anisotropy", "1")]));
    let (b, _) = rgb_id(&render("tex_trilinear", &[]));
    let plane: Vec<usize> = (0..a.len()).filter(|&i| ids[i] > 0.0).collect();
    let diff: Vec<f32> = plane.iter().map(|&i| (a[i][0] - b[i][0]).abs()).collect();
    let worst = diff.iter().copied().fold(0.0f32, f32::max);
    let mean = diff.iter().sum::<f32>() / diff.len() as f32;
    assert!(
        worst < 0.05 && mean < 3e-3,
        "hardware trilinear vs ours: worst {worst}, mean {mean}"
    );
}
