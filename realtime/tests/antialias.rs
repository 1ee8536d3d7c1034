//! Anti-aliasing end to end on the adapter at hand (lavapipe in CI), on the anti-aliasing
//! study's scene (scenes/studies/scenes/thin-edges.toml: a fence, a star of spokes, wires, a
//! turned square, all emitters) at 64². The reference here is the realtime renderer's own box
//! filter at 8×8 samples per pixel (`aa_ssaa k = 8`): the estimator the oracle's ground truth
//! uses, on a regular grid; accuracy against the oracle is the study's
//! (scenes/studies/antialias-edges.toml). Each method must land between that reference and
//! one sample per pixel, for the reason it exists: FXAA that finds no edge (threshold 1) is
//! next to no anti-aliasing; TAA without jitter samples the same point every frame; TAA's
//! history ghosts under motion unless it is clipped; MSAA sample counts the adapter cannot do
//! are errors, and deferred MSAA (edge samples lit one by one) matches forward MSAA.

mod support;

use std::path::Path;

use realtime::{PipelineKind, RasterError, RasterOutput, RasterSettings};
use support::{method, renderer, rgb_id};

const SIZE: u32 = 64;

fn edges() -> scenes::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/scenes/thin-edges.toml");
    scenes::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn settings(name: &str, params: &[(&str, &str)]) -> RasterSettings {
    let mut all = vec![("env_n", "0")];
    all.extend_from_slice(params);
    RasterSettings::new(SIZE, SIZE)
        .method(method(name, &all))
        .frames(0, 1)
}

fn render(name: &str, params: &[(&str, &str)]) -> RasterOutput {
    renderer()
        .render(&edges(), &settings(name, params))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Mean squared difference of the RGB channels.
fn mse(a: &RasterOutput, b: &RasterOutput) -> f64 {
    let (a, _) = rgb_id(a);
    let (b, _) = rgb_id(b);
    let sum: f64 = a
        .iter()
        .zip(&b)
        .flat_map(|(p, q)| (0..3).map(move |c| (f64::from(p[c]) - f64::from(q[c])).powi(2)))
        .sum();
    sum / (3 * a.len()) as f64
}

#[test]
fn each_method_lands_between_one_sample_and_the_box_filter() {
    let reference = render("aa_ssaa", &[("k", "8")]);
    let none = mse(&render("aa_none", &[]), &reference);
    let ssaa4 = mse(&render("aa_ssaa", &[("k", "4")]), &reference);
    let msaa = mse(&render("aa_msaa", &[("samples", "4")]), &reference);
    let fxaa = mse(&render("aa_fxaa", &[]), &reference);
    let mlaa = mse(&render("aa_mlaa", &[]), &reference);
    let taa = mse(
        &render(
            "aa_taa",
            &[("frames", "32"), ("blend", "0.05"), ("clamp", "none")],
        ),
        &reference,
    );
    eprintln!("MSE against ssaa 8x8: none {none:.3e}, ssaa 4x4 {ssaa4:.3e}, msaa 4 {msaa:.3e}, fxaa {fxaa:.3e}, mlaa {mlaa:.3e}, taa {taa:.3e}");
    // A post-process cannot restore what one sample missed; MSAA's 4 samples are fewer than 16.
    for (name, e) in [("msaa", msaa), ("fxaa", fxaa), ("mlaa", mlaa)] {
        assert!(
            e > ssaa4 && e < 0.8 * none,
            "{name}: {e:.3e} (ssaa 4x4 {ssaa4:.3e}, none {none:.3e})"
        );
    }
    assert!(msaa < 0.3 * none, "msaa 4: {msaa:.3e} against none {none:.3e}");
    // 32 jittered frames accumulate about as many samples as 4×4 supersampling.
    assert!(taa < 0.2 * none, "taa: {taa:.3e} against none {none:.3e}");
}

#[test]
fn fxaa_that_finds_no_edge_and_taa_without_jitter_do_not_anti_alias() {
    // Lottes's test (range < max(edge_threshold_min, edge_threshold · brightest)) still passes
    // a pixel at threshold 1 where its darkest neighbour is pure black; nowhere else.
    let reference = render("aa_ssaa", &[("k", "8")]);
    let none_out = render("aa_none", &[]);
    let blind_out = render("aa_fxaa", &[("edge_threshold", "1")]);
    let (none_err, blind_err) = (mse(&none_out, &reference), mse(&blind_out, &reference));
    assert!(
        blind_err > 0.9 * none_err,
        "FXAA blind to edges: {blind_err:.3e} vs none {none_err:.3e}"
    );
    let none = rgb_id(&none_out).0;
    let still = rgb_id(&render("aa_taa", &[("jitter", "off"), ("frames", "8")])).0;
    let worst = none
        .iter()
        .zip(&still)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
        .fold(0f32, f32::max);
    // Reprojecting through depth and back lands within float rounding of the pixel centre.
    assert!(
        worst < 1e-4,
        "TAA without jitter differs from one sample by {worst}"
    );
}

#[test]
fn taa_history_ghosts_under_motion_unless_clipped_or_clamped() {
    let reference = render("aa_ssaa", &[("k", "8")]);
    let moving = |clamp: &str| {
        mse(
            &render(
                "aa_taa",
                &[("orbit_degrees", "1"), ("clamp", clamp), ("frames", "16")],
            ),
            &reference,
        )
    };
    let (ghosting, clipped, clamped) = (moving("none"), moving("clip"), moving("aabb"));
    let still = mse(
        &render("aa_taa", &[("clamp", "none"), ("frames", "16")]),
        &reference,
    );
    eprintln!(
        "TAA under a 1°/frame orbit: clamp none {ghosting:.3e}, clip {clipped:.3e}, aabb {clamped:.3e}; still view {still:.3e}"
    );
    assert!(
        ghosting > 3.0 * still,
        "no ghosting under motion: {ghosting:.3e} vs still {still:.3e}"
    );
    assert!(
        clipped < 0.8 * ghosting,
        "clipping did not limit the ghosts: {clipped:.3e} vs {ghosting:.3e}"
    );
    // Clamping to the neighbourhood's box (Karis 2014) limits them too, if less tightly than
    // clipping towards its centre can.
    assert!(
        clamped < 0.8 * ghosting,
        "clamping did not limit the ghosts: {clamped:.3e} vs {ghosting:.3e}"
    );
}

#[test]
fn msaa_sample_counts_the_adapter_cannot_do_are_errors() {
    let e = realtime::Method::parse("aa_msaa", &[("samples".into(), "16".into())]).unwrap_err();
    assert!(e.contains("samples") && e.contains("2, 4, 8"), "{e}");
    let counts = renderer().gpu().msaa_counts().to_vec();
    for n in [2u32, 4, 8] {
        let result = renderer().render(&edges(), &settings("aa_msaa", &[("samples", &n.to_string())]));
        match result {
            Ok(_) => assert!(
                counts.contains(&n),
                "{n} samples rendered though the adapter lists {counts:?}"
            ),
            Err(RasterError::Settings(m)) => {
                assert!(!counts.contains(&n), "{m}");
                assert!(
                    m.contains(&format!("cannot render {n} samples")) && m.contains("it can do"),
                    "{m}"
                );
            }
            Err(e) => panic!("{e}"),
        }
    }
}

#[test]
fn deferred_msaa_lights_edge_samples_and_matches_forward() {
    let reference = render("aa_ssaa", &[("k", "8")]);
    let none = mse(&render("aa_none", &[]), &reference);
    let forward = render("aa_msaa", &[]);
    let deferred = renderer()
        .render(
            &edges(),
            &settings("aa_msaa", &[]).pipeline(PipelineKind::Deferred),
        )
        .unwrap_or_else(|e| panic!("deferred MSAA: {e}"));
    let (f, d) = (mse(&forward, &reference), mse(&deferred, &reference));
    eprintln!("MSAA 4x against ssaa 8x8: forward {f:.3e}, deferred {d:.3e}; none {none:.3e}");
    // Flat emitters: lighting each edge sample gives what shading once per primitive gives.
    assert!(d < 0.3 * none, "deferred MSAA: {d:.3e} against none {none:.3e}");
    assert!(
        mse(&forward, &deferred) < 0.05 * none,
        "forward and deferred MSAA differ"
    );
    let labels = deferred
        .timing
        .passes
        .iter()
        .map(|p| p.name.as_str())
        .collect::<Vec<_>>();
    if !labels.is_empty() {
        assert_eq!(
            labels,
            ["G-buffer pass", "lighting pass"],
            "deferred MSAA needs no resolve pass"
        );
    }
}

fn bumps() -> scenes::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/scenes/specular-bumps.toml");
    scenes::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn render_bumps(name: &str, params: &[(&str, &str)]) -> RasterOutput {
    renderer()
        .render(&bumps(), &settings(name, params))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Specular AA on the bumpy glossy floor and smooth spheres of the specular study: widening
/// the lobe takes most of the sparkle's energy error away (MSE against the 8×8 box filter);
/// with no variance it is one sample's shading; Toksvig on a scene's normal maps is not the
/// trilinear lookup it builds on.
#[test]
fn specular_aa_widens_the_lobe_by_the_normals_spread() {
    let reference = render_bumps("aa_ssaa", &[("k", "8")]);
    let none_out = render_bumps("aa_none", &[]);
    let none = mse(&none_out, &reference);
    let geometric = mse(&render_bumps("aa_specular_geometric", &[]), &reference);
    let toksvig_out = render_bumps("aa_specular_toksvig", &[]);
    let toksvig = mse(&toksvig_out, &reference);
    let trilinear = mse(&render_bumps("tex_trilinear", &[]), &reference);
    eprintln!("MSE against ssaa 8x8: none {none:.3e}, geometric {geometric:.3e}, toksvig {toksvig:.3e}, trilinear {trilinear:.3e}");
    assert!(
        geometric < 0.5 * none,
        "geometric: {geometric:.3e} against none {none:.3e}"
    );
    assert!(
        toksvig < 0.5 * trilinear,
        "toksvig: {toksvig:.3e} against its trilinear lookups {trilinear:.3e}"
    );
    // No variance: α² + 0 is α², one sample's shading up to the square root's rounding.
    let flat = rgb_id(&render_bumps("aa_specular_geometric", &[("variance", "0")])).0;
    let none_rgb = rgb_id(&none_out).0;
    let worst = none_rgb
        .iter()
        .zip(&flat)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs() / (p[c].abs() + 1e-3)))
        .fold(0f32, f32::max);
    assert!(worst < 1e-3, "variance 0 changed a pixel by {worst} (relative)");
}

/// The post-process taps (texel loads of the passes after shading) are counted in a rerun
/// of the last frame's passes: none without such passes; exactly 3 outputs × 4 samples + the
/// object id for the 4× MSAA resolve; FXAA's 5 loads where it finds no edge and more where it
/// searches one; MLAA's three passes at least 8 per pixel.
#[test]
fn post_process_taps_are_counted() {
    let taps = |name: &str, params: &[(&str, &str)]| {
        renderer()
            .render(&edges(), &settings(name, params).counters(true))
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .counters
            .expect("counters were asked for")
            .post_taps_per_pixel
    };
    assert_eq!(taps("aa_none", &[]), None);
    assert_eq!(taps("aa_msaa", &[("samples", "4")]), Some(13.0));
    let fxaa = taps("aa_fxaa", &[]).expect("FXAA taps");
    let blind = taps("aa_fxaa", &[("edge_threshold", "1")]).expect("FXAA taps");
    let mlaa = taps("aa_mlaa", &[]).expect("MLAA taps");
    let taa = taps("aa_taa", &[("frames", "4")]).expect("TAA taps");
    eprintln!("post-process taps per pixel: FXAA {fxaa:.1} (edge_threshold 1: {blind:.1}), MLAA {mlaa:.1}, TAA {taa:.1}");
    assert!(
        blind >= 5.0 && blind < fxaa,
        "FXAA: {blind} (threshold 1) vs {fxaa}"
    );
    assert!(fxaa < 60.0, "FXAA: {fxaa}");
    assert!(mlaa >= 8.0, "MLAA: {mlaa}");
    // The current pixel, its depth, the bilinear history and the 3×3 neighbourhood.
    assert!((13.0..=15.0).contains(&taa), "TAA: {taa}");
}

/// MSAA's coverage is the rasterised proxy's: a rectangle's proxy is the rectangle, so its
/// edges are resolved; a sphere is traced inside a bounding proxy, so its outline is decided
/// per pixel like alpha-tested geometry and MSAA leaves it as one sample draws it.
#[test]
fn msaa_resolves_rectangle_edges_but_not_traced_sphere_outlines() {
    let dir = std::env::temp_dir().join(format!("verity-msaa-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = |shape: &str| {
        let path = dir.join("scene.toml");
        let text = format!(
            "[camera]\neye = [0.0, 0.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\nfov = 40.0\n\n\
             [film]\nwidth = 64\nheight = 64\n\n\
             [[material]]\nname = \"black\"\ntype = \"diffuse\"\nalbedo = [0.0, 0.0, 0.0]\n\n\
             [[shape]]\nname = \"lamp\"\nmaterial = \"black\"\nemission = {{ radiance = [1.0, 1.0, 1.0] }}\n{shape}\n"
        );
        std::fs::write(&path, text).unwrap();
        scenes::load(&path).unwrap_or_else(|e| panic!("{e}"))
    };
    let sphere = scene("type = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.6");
    let square = scene(
        "type = \"rectangle\"\ncenter = [0.0, 0.0, 0.0]\nsize = [1.0, 1.0]\nnormal = [0.0, 0.0, 1.0]\n\
         transform = [{ rotate = { axis = [0, 0, 1], angle = 17 } }]",
    );
    let differing = |s: &scenes::Scene| {
        let one = rgb_id(&renderer().render(s, &settings("aa_none", &[])).unwrap()).0;
        let msaa = rgb_id(&renderer().render(s, &settings("aa_msaa", &[])).unwrap()).0;
        one.iter()
            .zip(&msaa)
            .filter(|(a, b)| (a[0] - b[0]).abs() > 1e-6)
            .count()
    };
    let (on_sphere, on_square) = (differing(&sphere), differing(&square));
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(
        on_sphere, 0,
        "MSAA changed {on_sphere} pixels of a traced sphere's outline"
    );
    assert!(
        on_square > 40,
        "MSAA resolved only {on_square} pixels of a turned square's edges"
    );
}
