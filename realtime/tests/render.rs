//! The realtime renderer end to end on the adapter at hand (lavapipe in CI): cost counters
//! against the loop structure they count, the EXR layout and header, supersampling's object
//! ids, and bad settings and scenes as errors. Parity with the oracle is tested in
//! tests/tests/parity_*.rs.

mod support;

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Vec3, Vec4};
use realtime::{Method, PipelineKind, RasterError, RasterSettings};
use scenes::texture::Texture;
use scenes::*;
use support::renderer;

/// The process's renderer; no adapter fails the test with the install hint.
/// A camera looking straight down at a 100 m floor (it fills the view), lit by one rectangle
/// light above the camera (out of view); the floor's albedo is a 2×2 texture when `textured`.
fn floor_scene(textured: bool) -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO, Vec3::Z, 40.0);
    let mut textures = Vec::new();
    let albedo = if textured {
        let t = Texture::from_texels(2, 2, vec![Vec4::splat(0.5); 4], [WrapMode::Repeat; 2]);
        textures.push(Arc::new(t));
        TexRgb::Image {
            texture: 0,
            factor: Vec3::ONE,
        }
    } else {
        TexRgb::Constant(Vec3::splat(0.5))
    };
    let shape = |name: &str, geometry, emission| Shape {
        name: name.into(),
        geometry,
        material: 0,
        emission,
        normal_map: None,
        displacement: None,
    };
    Scene {
        source: PathBuf::from("<floor scene>"),
        camera,
        film: Film {
            width: 16,
            height: 16,
        },
        render: RenderSettings::default(),
        textures,
        materials: vec![Material::Diffuse { albedo }],
        shapes: vec![
            shape(
                "floor",
                Geometry::Rectangle {
                    center: Vec3::ZERO,
                    half_u: Vec3::new(0.0, 0.0, 50.0),
                    half_v: Vec3::new(50.0, 0.0, 0.0),
                },
                None,
            ),
            shape(
                "light",
                Geometry::Rectangle {
                    center: Vec3::new(0.0, 2.0, 0.0),
                    half_u: Vec3::new(0.2, 0.0, 0.0),
                    half_v: Vec3::new(0.0, 0.0, 0.2),
                },
                Some(Emission {
                    radiance: TexRgb::Constant(Vec3::splat(5.0)),
                    two_sided: false,
                }),
            ),
        ],
        lights: Vec::new(),
        environment: None,
        provenance: Default::default(),
    }
}

fn counters(scene: &Scene, s: RasterSettings) -> realtime::Counters {
    let out = renderer()
        .render(scene, &s.frames(0, 1).counters(true))
        .unwrap_or_else(|e| panic!("{e}"));
    out.counters.unwrap_or_else(|| panic!("counters were requested"))
}

/// Per visible sample: 1 emitter-loop iteration + n² quadrature iterations (one light), 4
/// texel fetches per bilinear albedo lookup; the representative point has no inner loop.
/// The background (none here) and forward overdraw (none: one floor) would add nothing.
#[test]
fn counters_match_the_loop_structure() {
    let plain = floor_scene(false);
    let textured = floor_scene(true);
    let s = RasterSettings::new(16, 16).method(Method::quadrature(4).with_env_n(0));
    let c = counters(&plain, s.clone());
    assert_eq!(
        (c.texel_fetches_per_pixel, c.loop_iterations_per_pixel),
        (0.0, 17.0),
        "forward, quadrature n = 4"
    );
    // 2×2 samples per pixel, each 17 iterations and one bilinear albedo lookup (4 texels);
    // forward and deferred count the same work.
    for p in [PipelineKind::Forward, PipelineKind::Deferred] {
        let c = counters(&textured, s.clone().pipeline(p).ssaa(2));
        assert_eq!(
            (c.texel_fetches_per_pixel, c.loop_iterations_per_pixel),
            (16.0, 68.0),
            "{p:?}, ssaa 2, textured"
        );
    }
    let c = counters(&plain, s.method(Method::representative_point().with_env_n(0)));
    assert_eq!(c.loop_iterations_per_pixel, 1.0, "representative point");
}

#[test]
fn image_has_the_oracle_layout_and_a_descriptive_header() {
    let scene = floor_scene(false);
    let out = renderer()
        .render(&scene, &RasterSettings::new(16, 8).frames(1, 3))
        .unwrap_or_else(|e| panic!("{e}"));
    let img = &out.image;
    assert_eq!((img.width, img.height), (16, 8));
    let names: Vec<&str> = img.channels.iter().map(|(n, _)| n.as_str()).collect();
    for want in [
        "R",
        "G",
        "B",
        "albedo.R",
        "albedo.G",
        "albedo.B",
        "normal.X",
        "normal.Y",
        "normal.Z",
        "depth.Z",
        "coverage.Y",
        "object_id.Y",
    ] {
        assert!(names.contains(&want), "channel {want} missing from {names:?}");
    }
    let gpu = renderer().gpu();
    for (key, want) in [
        ("adapter", gpu.adapter_name().to_string()),
        ("backend", gpu.backend()),
        ("method", "area_quadrature".to_string()),
        ("parameters", "n=16 env_n=8".to_string()),
        ("pipeline", "forward".to_string()),
        ("ssaa", "1".to_string()),
    ] {
        assert_eq!(img.attribute(key), Some(want.as_str()), "header attribute {key}");
    }
    let frame_ms: f64 = img
        .attribute("frame_ms")
        .and_then(|v| v.parse().ok())
        .unwrap_or(-1.0);
    assert!(
        frame_ms > 0.0 && out.timing.wall_ms > 0.0,
        "frame time {frame_ms} ms"
    );
    assert_eq!(out.timing.timed_frames, 3);
    // Floor everywhere: object id 1, depth 1 m at the centre pixel column, normal +Y.
    assert!(img
        .channel("object_id.Y")
        .unwrap_or_default()
        .iter()
        .all(|&id| id == 1.0));
    assert!(img
        .channel("normal.Y")
        .unwrap_or_default()
        .iter()
        .all(|&y| (y - 1.0).abs() < 1e-6));
}

/// Environment texels the scene's loading clamped (`[environment] negative = "clamp"`) are
/// counted in the header; none clamped, no attribute.
#[test]
fn clamped_environment_texels_reach_the_header() {
    let mut scene = floor_scene(false);
    let settings = RasterSettings::new(8, 4).frames(0, 1).counters(false);
    let plain = renderer()
        .render(&scene, &settings)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plain.image.attribute("environment_clamped_texels"), None);
    scene.provenance.clamped_environment_texels = 7;
    let clamped = renderer()
        .render(&scene, &settings)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(clamped.image.attribute("environment_clamped_texels"), Some("7"));
}

/// Even k has no subsample at the pixel centre: ids come from a 1× pass and equal k = 1's.
#[test]
fn supersampled_object_ids_are_taken_at_pixel_centres() {
    let mut scene = floor_scene(false);
    scene.camera = Camera::look_at(Vec3::new(0.3, 1.0, 0.0), Vec3::new(0.0, 2.0, 0.0), Vec3::Z, 120.0);
    scene.lights.push(Light::Point {
        name: "p".into(),
        position: Vec3::new(0.0, 1.0, 0.0),
        intensity: Vec3::ONE,
    });
    let ids = |k| {
        let out = renderer()
            .render(&scene, &RasterSettings::new(16, 16).ssaa(k).frames(0, 1))
            .unwrap_or_else(|e| panic!("{e}"));
        out.image.channel("object_id.Y").unwrap_or_default().to_vec()
    };
    let one = ids(1);
    assert!(
        one.contains(&2.0) && one.contains(&0.0),
        "the view should hold the light and background: {one:?}"
    );
    assert_eq!(ids(2), one);
    assert_eq!(ids(3), one);
}

#[test]
fn bad_settings_are_errors_naming_the_setting() {
    let scene = floor_scene(false);
    let max = renderer().gpu().limits().max_texture_dimension_2d;
    for (s, want) in [
        (RasterSettings::new(0, 4), "empty"),
        (RasterSettings::new(4, 4).ssaa(0), "ssaa"),
        (RasterSettings::new(4, 4).ssaa(17), "ssaa"),
        (RasterSettings::new(4, 4).frames(1, 0), "timed frame"),
        (
            RasterSettings::new(4, 4).method(Method::quadrature(0)),
            "n must be",
        ),
        (
            RasterSettings::new(4, 4).method(Method::quadrature(4).with_env_n(65)),
            "env_n",
        ),
        (RasterSettings::new(max, 4).ssaa(2), "per side"),
    ] {
        match renderer().render(&scene, &s) {
            Err(RasterError::Settings(m)) => assert!(m.contains(want), "{m}"),
            other => panic!(
                "{s:?}: expected a settings error, got {:?}",
                other.map(|o| o.timing)
            ),
        }
    }
}

#[test]
fn bad_scenes_are_errors_naming_the_shape_or_light() {
    let mut nan = floor_scene(false);
    nan.shapes[1].geometry = Geometry::Sphere {
        center: Vec3::ZERO,
        radius: f32::NAN,
    };
    let mut flat = floor_scene(false);
    flat.shapes[0].geometry = Geometry::Rectangle {
        center: Vec3::ZERO,
        half_u: Vec3::X,
        half_v: Vec3::X,
    };
    let mut spot = floor_scene(false);
    spot.lights.push(Light::Spot {
        name: "s".into(),
        position: Vec3::Y,
        direction: Vec3::ZERO,
        intensity: Vec3::ONE,
        cutoff_deg: 30.0,
        beam_width_deg: 10.0,
        projection: None,
    });
    let mut material = floor_scene(false);
    material.shapes[0].material = 5;
    for (scene, want) in [
        (nan, "shape 'light' (shapes[1]): radius"),
        (flat, "shape 'floor' (shapes[0]): zero area"),
        (spot, "light 's' (lights[0]): direction"),
        (material, "shape 'floor' (shapes[0]): material = 5"),
    ] {
        match renderer().render(&scene, &RasterSettings::new(4, 4)) {
            Err(RasterError::Scene(m)) => assert!(m.contains(want), "{m} (wanted {want})"),
            other => panic!(
                "expected a scene error ({want}), got {:?}",
                other.map(|o| o.timing)
            ),
        }
    }
}
