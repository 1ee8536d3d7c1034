//! The shadow methods end to end on the adapter at hand: their cost counters against the
//! kernels they run, the shadow pass in the timing and the header, forward = deferred with
//! shadows (cascaded and rotated too), the visibility channels, rotated Poisson taps against
//! fixed ones, and bad settings as errors. Accuracy against the oracle
//! is tested in tests/tests/parity_shadow.rs.

mod support;

use std::path::PathBuf;

use glam::Vec3;
use realtime::technique::shadow::Shadow;
use realtime::{PipelineKind, RasterError, RasterSettings};
use scenes::*;
use support::{method, renderer};

fn shape(name: &str, geometry: Geometry, emission: Option<f32>) -> Shape {
    Shape {
        name: name.into(),
        geometry,
        material: 0,
        emission: emission.map(|l| Emission {
            radiance: TexRgb::Constant(Vec3::splat(l)),
            two_sided: false,
        }),
        normal_map: None,
        displacement: None,
    }
}

/// A camera 1 m above a 100 m floor looking straight down (the floor fills the view), a
/// 0.4 m rectangle light 2 m up facing down; with `blocker`, the light shrunk to 0.1 m (same
/// power), a 0.2 m square 1.5 m up (above the camera, out of view) and a 90° view: umbra
/// ±0.25 m, penumbra out to ±0.55 m, lit floor beyond, all in view.
fn floor_scene(blocker: bool) -> Scene {
    let mut shapes = vec![
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
            Some(5.0),
        ),
    ];
    let mut fov = 40.0;
    if blocker {
        shapes[1].geometry = Geometry::Rectangle {
            center: Vec3::new(0.0, 2.0, 0.0),
            half_u: Vec3::new(0.05, 0.0, 0.0),
            half_v: Vec3::new(0.0, 0.0, 0.05),
        };
        shapes[1].emission = Some(Emission {
            radiance: TexRgb::Constant(Vec3::splat(80.0)),
            two_sided: false,
        });
        shapes.push(shape(
            "blocker",
            Geometry::Rectangle {
                center: Vec3::new(0.0, 1.5, 0.0),
                half_u: Vec3::new(0.0, 0.0, 0.1),
                half_v: Vec3::new(0.1, 0.0, 0.0),
            },
            None,
        ));
        fov = 90.0;
    }
    Scene {
        source: PathBuf::from("<shadow floor scene>"),
        camera: Camera::look_at(Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO, Vec3::Z, fov),
        film: Film {
            width: 16,
            height: 16,
        },
        render: RenderSettings::default(),
        textures: Vec::new(),
        materials: vec![Material::Diffuse {
            albedo: TexRgb::Constant(Vec3::splat(0.5)),
        }],
        shapes,
        lights: Vec::new(),
        environment: None,
        provenance: Default::default(),
    }
}

/// On the unoccluded floor (every sample lit, inside the light's frustum) each visible sample
/// runs 1 emitter iteration + n² = 16 quadrature iterations, then the shadow kernel: its
/// comparisons (1 fetch nearest, 4 bilinear) and, for the looping kernels, one iteration per
/// tap. PCSS's blocker search finds no blocker (16 loads) and stops; with the blocker depth
/// ignored it filters (32 bilinear taps).
#[test]
fn counters_count_shadow_map_fetches_per_kernel() {
    let scene = floor_scene(false);
    let n = [("n", "4")];
    for (name, extra, fetches, loops) in [
        ("shadow_hard", None, 1.0, 17.0),
        ("pcf_hw_2x2", None, 4.0, 17.0),
        ("pcf_box", None, 9.0, 26.0),
        ("pcf_box", Some(("kernel", "5")), 25.0, 42.0),
        ("pcf_poisson", None, 64.0, 33.0),
        ("pcf_poisson", Some(("taps", "4")), 16.0, 21.0),
        ("pcss", None, 16.0, 33.0),
        ("pcss", Some(("blocker_depth", "ignore")), 128.0, 49.0),
    ] {
        let mut params = n.to_vec();
        params.extend(extra);
        let s = RasterSettings::new(16, 16)
            .method(method(name, &params))
            .frames(0, 1)
            .counters(true);
        for pipeline in [PipelineKind::Forward, PipelineKind::Deferred] {
            let out = renderer()
                .render(&scene, &s.clone().pipeline(pipeline))
                .unwrap_or_else(|e| panic!("{e}"));
            let c = out.counters.unwrap_or_else(|| panic!("counters were requested"));
            assert_eq!(
                (c.texel_fetches_per_pixel, c.loop_iterations_per_pixel),
                (fetches, loops),
                "{name} {extra:?} ({pipeline:?})"
            );
        }
    }
}

/// The shadow pass is its own timed entry before the shading passes; the header lists the
/// shadow parameters and each light's projection; the visibility channel is there.
#[test]
fn shadow_pass_is_timed_and_described() {
    let scene = floor_scene(true);
    let gpu = renderer().gpu();
    for (pipeline, passes) in [
        (PipelineKind::Forward, vec!["shadow pass", "forward pass"]),
        (
            PipelineKind::Deferred,
            vec!["shadow pass", "G-buffer pass", "lighting pass"],
        ),
    ] {
        let s = RasterSettings::new(16, 16)
            .method(method("pcss", &[("map", "256")]))
            .pipeline(pipeline)
            .frames(1, 2);
        let out = renderer().render(&scene, &s).unwrap_or_else(|e| panic!("{e}"));
        if gpu.has_timestamps() && !out.timing.passes.is_empty() {
            let names: Vec<&str> = out.timing.passes.iter().map(|p| p.name.as_str()).collect();
            assert_eq!(names, passes);
            assert!(out.timing.passes.iter().all(|p| p.ms >= 0.0));
        }
        let img = &out.image;
        assert_eq!(img.attribute("method"), Some("pcss"));
        assert_eq!(
            img.attribute("parameters"),
            Some(
                "n=8 env_n=0 map=256 bias=0.002 slope_bias=1 normal_offset=1 cascades=1 \
                 split_lambda=0.5 point_maps=frustum blocker_samples=16 filter_samples=32 blocker_depth=search \
                 receiver_plane=on rotate=off"
            )
        );
        let maps = img.attribute("shadow_maps").unwrap_or_default();
        assert!(maps.starts_with("light: perspective"), "{maps}");
        let v = img.channel("visibility.light.Y").unwrap_or_default();
        assert_eq!(v.len(), 256);
        assert!(v.iter().all(|x| (0.0..=1.0).contains(x)), "{v:?}");
        assert!(v.contains(&0.0) && v.contains(&1.0), "umbra and lit: {v:?}");
    }
    let plain = renderer()
        .render(&scene, &RasterSettings::new(16, 16).frames(0, 1))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plain.image.attribute("shadow_maps"), None);
    assert!(plain
        .image
        .channel("visibility.light.Y")
        .unwrap_or_default()
        .iter()
        .all(|&x| x == 1.0));
}

/// Forward and deferred call the same functions on the same f32 inputs: with shadows too the
/// images and visibilities agree (to 1e-5, instruction scheduling aside), at SSAA 2 (whose
/// object ids take the extra 1× frame, shadow pass included).
#[test]
fn forward_and_deferred_agree_with_shadows() {
    let scene = floor_scene(true);
    for name in ["shadow_hard", "pcf_box", "pcss"] {
        let s = RasterSettings::new(16, 16)
            .method(method(name, &[("map", "256")]))
            .ssaa(2)
            .frames(0, 1);
        let f = renderer().render(&scene, &s).unwrap_or_else(|e| panic!("{e}"));
        let d = renderer()
            .render(&scene, &s.pipeline(PipelineKind::Deferred))
            .unwrap_or_else(|e| panic!("{e}"));
        for c in ["R", "G", "B", "visibility.light.Y", "object_id.Y"] {
            let (a, b) = (f.image.channel(c).unwrap(), d.image.channel(c).unwrap());
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() <= 1e-5 * y.abs().max(1.0), "{name} {c}: {x} vs {y}");
            }
        }
    }
}

#[test]
fn bad_shadow_settings_are_errors() {
    let scene = floor_scene(true);
    let max = renderer().gpu().limits().max_texture_dimension_2d;
    let mut big = method("shadow_hard", &[]);
    big.get_mut::<Shadow>().expect("shadow_hard maps shadows").map = max + 1;
    let mut many = scene.clone();
    for i in 0..70 {
        many.lights.push(Light::Point {
            name: format!("p{i}"),
            position: Vec3::new(0.0, 3.0, 0.0),
            intensity: Vec3::ONE,
        });
    }
    for (scene, m, want) in [
        (&scene, big, "map"),
        (&many, method("shadow_hard", &[]), "at most 64 can be shadowed"),
    ] {
        match renderer().render(scene, &RasterSettings::new(4, 4).method(m)) {
            Err(RasterError::Settings(e)) => assert!(e.contains(want), "{e} (wanted {want})"),
            other => panic!(
                "expected a settings error ({want}), got {:?}",
                other.map(|o| o.timing)
            ),
        }
    }
}

/// The long sunlit field of the cascade study (scenes/studies/scenes/long-sun-field.toml) at
/// `size`².
fn long_sun_field(size: u32) -> Scene {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/scenes/long-sun-field.toml");
    let mut s = scenes::load(&path).unwrap_or_else(|e| panic!("{e}"));
    s.film = Film {
        width: size,
        height: size,
    };
    s
}

/// Cascades: the header lists one orthographic map per cascade with its camera-depth slice,
/// forward and deferred agree with cascades and rotated taps (the same pixel, the same
/// rotation), and the visibility stays in [0, 1] with both shadow and light.
#[test]
fn cascades_are_described_and_forward_and_deferred_agree() {
    let scene = long_sun_field(32);
    let one = renderer()
        .render(
            &scene,
            &RasterSettings::new(32, 32)
                .method(method("pcf_hw_2x2", &[("map", "256")]))
                .frames(0, 1),
        )
        .unwrap_or_else(|e| panic!("{e}"));
    let maps = one.image.attribute("shadow_maps").unwrap_or_default();
    assert!(
        maps.starts_with("sun: orthographic") && !maps.contains("cascade"),
        "{maps}"
    );
    for (name, extra) in [
        ("pcf_hw_2x2", None),
        ("pcss", Some(("rotate", "on"))),
        ("pcf_poisson", Some(("rotate", "on"))),
    ] {
        let mut params = vec![("map", "256"), ("cascades", "4")];
        params.extend(extra);
        let s = RasterSettings::new(32, 32)
            .method(method(name, &params))
            .frames(0, 1);
        let f = renderer().render(&scene, &s).unwrap_or_else(|e| panic!("{e}"));
        let d = renderer()
            .render(&scene, &s.pipeline(PipelineKind::Deferred))
            .unwrap_or_else(|e| panic!("{e}"));
        let maps = f.image.attribute("shadow_maps").unwrap_or_default();
        let parts: Vec<&str> = maps.split("; ").collect();
        assert_eq!(parts.len(), 4, "{maps}");
        for (i, p) in parts.iter().enumerate() {
            let want = format!("sun cascade {}/4: orthographic", i + 1);
            assert!(p.starts_with(&want) && p.contains("camera depth"), "{p}");
        }
        for c in ["R", "G", "B", "visibility.sun.Y"] {
            let (a, b) = (f.image.channel(c).unwrap(), d.image.channel(c).unwrap());
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() <= 1e-5 * y.abs().max(1.0), "{name} {c}: {x} vs {y}");
            }
        }
        let v = f.image.channel("visibility.sun.Y").unwrap_or_default();
        assert!(v.iter().all(|x| (0.0..=1.0).contains(x)), "{name}: {v:?}");
        assert!(
            v.contains(&1.0) && v.iter().any(|&x| x < 0.5),
            "{name}: shadow and light: {v:?}"
        );
    }
}

/// Rotating the Poisson taps per pixel (interleaved gradient noise) moves each pixel's V —
/// banding becomes noise — but not its mean over the penumbra: the same kernel, turned.
#[test]
fn rotated_taps_change_the_pattern_but_keep_the_mean() {
    let scene = floor_scene(true);
    for (name, params) in [
        (
            "pcf_poisson",
            vec![("taps", "8"), ("radius", "12"), ("map", "512")],
        ),
        (
            "pcss",
            vec![("blocker_samples", "8"), ("filter_samples", "8"), ("map", "512")],
        ),
    ] {
        let render = |rotate: &str| {
            let mut p = params.clone();
            p.push(("rotate", rotate));
            let s = RasterSettings::new(64, 64).method(method(name, &p)).frames(0, 1);
            let out = renderer().render(&scene, &s).unwrap_or_else(|e| panic!("{e}"));
            out.image
                .channel("visibility.light.Y")
                .unwrap_or_default()
                .to_vec()
        };
        let (fixed, turned) = (render("off"), render("on"));
        let soft: Vec<usize> = (0..fixed.len())
            .filter(|&i| fixed[i] > 0.0 && fixed[i] < 1.0 || turned[i] > 0.0 && turned[i] < 1.0)
            .collect();
        let n = soft.len() as f64;
        let mean = |v: &[f32]| soft.iter().map(|&i| f64::from(v[i])).sum::<f64>() / n;
        let moved = soft
            .iter()
            .filter(|&&i| (fixed[i] - turned[i]).abs() > 0.05)
            .count() as f64
            / n;
        let (a, b) = (mean(&fixed), mean(&turned));
        println!(
            "{name}: {n} penumbra pixels, mean V fixed {a:.4}, rotated {b:.4}, {:.1} % moved by > 0.05",
            100.0 * moved
        );
        assert!(n >= 100.0, "{name}: only {n} penumbra pixels");
        assert!(
            (a - b).abs() < 0.02,
            "{name}: mean V {a:.4} fixed vs {b:.4} rotated"
        );
        assert!(
            moved > 0.2,
            "{name}: rotation moved only {:.1} % of the penumbra",
            100.0 * moved
        );
    }
}

/// More map layers than the shadow uniform holds — 40 suns at 4 cascades each — is a settings
/// error naming the layers and the cascades, before anything renders.
#[test]
fn too_many_cascade_layers_are_an_error() {
    let mut scene = floor_scene(true);
    for i in 0..40 {
        scene.lights.push(Light::Directional {
            name: format!("sun{i}"),
            direction: Vec3::new(0.1, -1.0, 0.0),
            irradiance: Vec3::ONE,
            angular_diameter_deg: 0.5,
        });
    }
    let m = method("shadow_hard", &[("cascades", "4")]);
    match renderer().render(&scene, &RasterSettings::new(4, 4).method(m)) {
        Err(RasterError::Settings(e)) => {
            assert!(
                e.contains("161 shadow-map layers") && e.contains("cascades"),
                "{e}"
            )
        }
        other => panic!("expected a settings error, got {:?}", other.map(|o| o.timing)),
    }
    let m = method("shadow_hard", &[("cascades", "2"), ("map", "64")]);
    assert!(renderer()
        .render(&scene, &RasterSettings::new(4, 4).method(m).frames(0, 1))
        .is_ok());
}
