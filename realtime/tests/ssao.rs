//! Screen-space AO end to end on the adapter at hand (lavapipe in CI), on white floors under a
//! white sky, where the exact answers are known without the oracle:
//! - an open floor has nothing within any radius: every method reads AO = 1 (Crytek through
//!   its doubling, the horizon methods because the floor's own samples lie in its tangent
//!   plane), with and without the blur and at half resolution;
//! - beside a wall, the floor further than r from it is unoccluded under the distance cut-off,
//!   and darkened without it (the depth threshold's lower bound), and the floor at the wall's
//!   foot is darkened under both;
//! - `output = ao` is the shaded image divided by the albedo (the sky is 1 and the env
//!   quadrature exact for it); the frame's timing names the SSAO pass, and its counters the
//!   passes' texture loads;
//! - temporal accumulation of one rotated slice per frame approaches eight slices in one frame,
//!   under a still and an orbiting camera;
//! - the forward pipeline and bad parameters are refused.
//!
//! Accuracy against the oracle's `ao` is the studies' (scenes/studies/ssao-*.toml).

mod support;

use realtime::{PipelineKind, RasterError, RasterSettings};
use support::{method, renderer, rgb_id};

const SIZE: u32 = 48;

/// A floor 8 m wide seen from 2 m up and 3 m back, white (or `albedo`) under a white sky;
/// with `wall`, a wall 2 m high along x = `wall` (facing +x), 4 m wide.
fn scene(albedo: f32, wall: Option<f32>) -> scenes::Scene {
    let mut text = format!(
        "[camera]\neye = [2.5, 2, 0]\ntarget = [0, 0, 0]\nfov = 60\n\
         [film]\nwidth = {SIZE}\nheight = {SIZE}\n\
         [render]\nao_radius = 0.5\n\
         [environment]\nradiance = [1, 1, 1]\n\
         [[material]]\nname = \"m\"\ntype = \"diffuse\"\nalbedo = [{albedo}, {albedo}, {albedo}]\n\
         [[shape]]\nname = \"floor\"\ntype = \"rectangle\"\nmaterial = \"m\"\ncenter = [0, 0, 0]\n\
         size = [8, 8]\nnormal = [0, 1, 0]\n"
    );
    if let Some(x) = wall {
        text += &format!(
            "[[shape]]\nname = \"wall\"\ntype = \"rectangle\"\nmaterial = \"m\"\ncenter = [{x}, 1, 0]\n\
             half_u = [0, 0, -2]\nhalf_v = [0, 1, 0]\n"
        );
    }
    scenes::toml::load_str(&text, std::path::Path::new("yard.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn settings(name: &str, params: &[(&str, &str)]) -> RasterSettings {
    RasterSettings::new(SIZE, SIZE)
        .method(method(name, params))
        .pipeline(PipelineKind::Deferred)
        .frames(0, 1)
}

/// The red channel and the object id of every pixel.
fn render(scene: &scenes::Scene, s: &RasterSettings) -> (Vec<f32>, Vec<f32>) {
    let out = renderer().render(scene, s).unwrap_or_else(|e| panic!("{e}"));
    let (rgb, ids) = rgb_id(&out);
    (rgb.iter().map(|p| p[0]).collect(), ids)
}

/// Every SSAO method, from the family's table: a new one is tested without an edit here.
fn methods() -> impl Iterator<Item = &'static str> {
    realtime::technique::ssao::METHODS.iter().map(|m| m.name)
}

#[test]
fn an_open_floor_is_unoccluded() {
    let yard = scene(1.0, None);
    for name in methods() {
        for extra in [&[][..], &[("blur", "3")], &[("half_res", "on")]] {
            let mut params = vec![("output", "ao")];
            params.extend_from_slice(extra);
            let (ao, ids) = render(&yard, &settings(name, &params));
            let floor: Vec<f32> = ao
                .iter()
                .zip(&ids)
                .filter(|(_, id)| **id == 1.0)
                .map(|(a, _)| *a)
                .collect();
            assert!(floor.len() > 500, "{name}: the floor fills most of the frame");
            let mean = floor.iter().sum::<f32>() / floor.len() as f32;
            let min = floor.iter().cloned().fold(f32::INFINITY, f32::min);
            // GTAO's few slices integrate |n_p|·â over the slice angle by a rotated midpoint
            // rule: exact in the mean, within a per cent per pixel. The point methods compare
            // a sample with the depth at its pixel's centre, and a pixel of a floor seen at a
            // grazing angle spans more depth than the bias: a few samples just above the floor
            // read as occluded there (their known self-occlusion), so only their mean is tight.
            let horizons = name == "ssao_hbao" || name == "ssao_gtao";
            let floor_min = if horizons { 0.96 } else { 0.8 };
            assert!(
                mean > 0.99 && min > floor_min,
                "{name} {extra:?}: mean {mean}, min {min}"
            );
            assert!(floor.iter().all(|a| *a <= 1.0 + 1e-6), "{name}: AO above 1");
        }
    }
}

#[test]
fn the_radius_bounds_what_occludes() {
    // The wall stands at x = −1; the camera looks at the floor between x = −1 and 2.
    let yard = scene(1.0, Some(-1.0));
    for name in ["ssao_hbao", "ssao_gtao"] {
        let with_falloff = |falloff: &str| {
            render(
                &yard,
                &settings(
                    name,
                    &[("output", "ao"), ("falloff", falloff), ("directions", "16")],
                ),
            )
        };
        let (cut, ids) = with_falloff("cutoff");
        let (none, _) = with_falloff("none");
        let (quadratic, _) = with_falloff("quadratic");
        let floor: Vec<usize> = (0..ids.len()).filter(|i| ids[*i] == 1.0).collect();
        // The floor pixels the cut-off leaves unoccluded lie further than r from the wall: the
        // same pixels without the distance test are darker (the wall is higher on screen).
        let open: Vec<usize> = floor.iter().cloned().filter(|i| cut[*i] > 0.999).collect();
        assert!(
            open.len() > 200,
            "{name}: most of the floor is further than 0.5 m from the wall"
        );
        // Those within r of the wall on screen (r·f/z pixels): a band along its foot.
        let darker = open.iter().filter(|i| none[**i] < 0.98).count();
        assert!(
            darker > 20,
            "{name}: without the distance test the wall darkens the far floor ({darker} of {})",
            open.len()
        );
        // The quadratic attenuation 1 − d²/r² is zero from r on, as the cut-off is.
        let beyond = open.iter().filter(|i| quadratic[**i] < 0.999).count();
        assert!(
            beyond == 0,
            "{name}: the quadratic falloff darkens {beyond} floor pixels further than r"
        );
        // The floor at the wall's foot is occluded under both, less under the attenuation
        // (its weights are at most the cut-off's 1).
        let foot: Vec<usize> = floor.iter().cloned().filter(|i| cut[*i] < 0.8).collect();
        assert!(!foot.is_empty(), "{name}: the wall's foot is occluded");
        let lighter = foot.iter().filter(|i| quadratic[**i] > cut[**i] + 1e-3).count();
        assert!(
            lighter * 2 > foot.len(),
            "{name}: the quadratic falloff occludes the foot as much as the cut-off ({lighter} of {} lighter)",
            foot.len()
        );
    }
}

#[test]
fn ao_output_is_the_shaded_image_over_the_albedo() {
    let grey = scene(0.5, Some(-1.0));
    let (shaded, ids) = render(&grey, &settings("ssao_gtao", &[]));
    let (ao, _) = render(&grey, &settings("ssao_gtao", &[("output", "ao")]));
    let mut occluded = 0;
    for i in 0..ids.len() {
        if ids[i] == 0.0 {
            assert_eq!(ao[i], 0.0, "background AO is 0 (the oracle's)");
            continue;
        }
        assert!(
            (shaded[i] - 0.5 * ao[i]).abs() < 1e-5,
            "pixel {i}: {} vs 0.5 × {}",
            shaded[i],
            ao[i]
        );
        occluded += usize::from(ao[i] < 0.9);
    }
    assert!(occluded > 20, "the wall occludes the floor at its foot");
}

#[test]
fn temporal_accumulation_averages_the_rotations() {
    // One slice per frame, its rotation advanced every frame: eight frames accumulated come
    // close to eight slices in one frame, where one frame of one slice does not.
    let yard = scene(1.0, Some(-1.0));
    let one = |extra: &[(&'static str, &'static str)]| {
        let mut params = vec![("output", "ao"), ("directions", "1")];
        params.extend_from_slice(extra);
        render(&yard, &settings("ssao_gtao", &params))
    };
    let (single, ids) = one(&[]);
    let (accumulated, _) = one(&[("temporal", "8")]);
    let (moving, _) = one(&[("temporal", "8"), ("orbit_degrees", "1"), ("orbit_distance", "3")]);
    let (eight, _) = render(
        &yard,
        &settings("ssao_gtao", &[("output", "ao"), ("directions", "8")]),
    );
    let floor: Vec<usize> = (0..ids.len()).filter(|i| ids[*i] == 1.0).collect();
    let mean_diff =
        |a: &[f32]| floor.iter().map(|i| (a[*i] - eight[*i]).abs()).sum::<f32>() / floor.len() as f32;
    let (d1, d8, dm) = (mean_diff(&single), mean_diff(&accumulated), mean_diff(&moving));
    assert!(d8 < 0.5 * d1, "accumulated {d8} against one frame {d1}");
    // Under motion the reprojected history still averages (the last frame is the scene's view).
    assert!(
        dm < 0.7 * d1,
        "accumulated under motion {dm} against one frame {d1}"
    );
    let still = settings("ssao_gtao", &[("orbit_degrees", "1")]);
    match renderer().render(&yard, &still) {
        Err(RasterError::Settings(m)) => assert!(m.contains("temporal"), "{m}"),
        other => panic!("expected a settings error, got {:?}", other.map(|_| ())),
    }
}

#[test]
fn the_timing_and_the_counters_name_the_ssao_passes() {
    let yard = scene(1.0, Some(-1.0));
    let run = |params: &[(&str, &str)]| {
        renderer()
            .render(&yard, &settings("ssao_gtao", params).counters(true))
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let out = run(&[("blur", "2"), ("half_res", "on")]);
    if !out.timing.passes.is_empty() {
        let names: Vec<&str> = out.timing.passes.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["G-buffer pass", "SSAO pass", "lighting pass"]);
    }
    // Texture loads per pixel: a surface pixel's estimate reads its own texel (position and
    // normal) and at most 2 × directions × steps positions; the background one position.
    let loads = |params: &[(&str, &str)]| {
        run(params)
            .counters
            .and_then(|c| c.ssao_loads_per_pixel)
            .expect("SSAO loads counted")
    };
    let (full, half, blurred) = (loads(&[]), loads(&[("half_res", "on")]), loads(&[("blur", "2")]));
    assert!(full > 10.0 && full <= 2.0 + 2.0 * 4.0 * 8.0, "{full}");
    // Half resolution: a quarter of the estimates, then 4 × 3 loads (+ 1 own) per pixel.
    assert!(
        half < 0.5 * full + 13.0 && half > 0.25 * full,
        "{half} against {full}"
    );
    // The blur's two passes: 5 taps of position, normal and obscurance, plus the centre.
    assert!(
        blurred > full + 10.0 && blurred <= full + 2.0 * (2.0 + 5.0 * 3.0),
        "{blurred}"
    );
    let plain = renderer()
        .render(&yard, &settings("area_quadrature", &[]).counters(true))
        .unwrap();
    assert_eq!(plain.counters.and_then(|c| c.ssao_loads_per_pixel), None);
}

#[test]
fn the_forward_pipeline_and_bad_parameters_are_refused() {
    let yard = scene(1.0, None);
    let forward = settings("ssao_gtao", &[]).pipeline(PipelineKind::Forward);
    match renderer().render(&yard, &forward) {
        Err(RasterError::Settings(m)) => assert!(m.contains("deferred"), "{m}"),
        other => panic!("expected a settings error, got {:?}", other.map(|_| ())),
    }
    let bad = |k: &str, v: &str| {
        realtime::Method::parse("ssao_hbao", &[(k.to_string(), v.to_string())]).expect_err("refused")
    };
    assert!(bad("radius", "-1").contains("radius"));
    assert!(bad("falloff", "linear").contains("none, cutoff, quadratic"));
    assert!(bad("steps", "0").contains("1..=64"));
    assert!(bad("samples", "8").contains("no parameter `samples`"));
    assert!(bad("blur", "NaN").contains("blur"));
}
