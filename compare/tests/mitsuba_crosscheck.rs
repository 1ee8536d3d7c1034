//! Every built-in scene that Mitsuba 3 can express agrees with Mitsuba under the per-pixel
//! z-test, at a CI-friendly 64×64 and 256 spp; the others are listed in README.md
//! ("Mitsuba cross-check") and refused with the reason given there. The Cornell box is also
//! cross-checked at bounded depths, where the two renderers' `max_depth` conventions must
//! agree exactly (a light seen directly is depth 1, direct illumination depth 2).

mod mitsuba_support;

use std::path::Path;

use compare::mitsuba::export;
use compare::mitsuba::runner::Variant;
use mitsuba_support::{at, builtin, check};

/// Built-in scenes cross-checked below.
const CROSSCHECKED: &[&str] = &[
    "cornell-box",
    "include-asset",
    "mirror-sphere",
    "soft-shadow",
    "studies/scenes/contact-hardening",
    "studies/scenes/overlapping-blockers",
    "studies/scenes/envmap-ball",
    "studies/scenes/envmap-locality",
    "studies/scenes/envmap-room",
    "studies/scenes/distance-room",
    "studies/scenes/distance-room-glass",
    "studies/scenes/distance-room-occluders",
    "studies/scenes/texture-plane",
    "studies/scenes/thin-edges",
    "studies/scenes/shading-sphere",
    "studies/scenes/projector",
    "studies/scenes/lightmap-room",
    "studies/scenes/lightmap-seams",
    "studies/scenes/lightmap-wall",
    "studies/scenes/omni-room",
    "studies/scenes/ssao-yard",
    "studies/scenes/ssao-edge",
    "studies/scenes/mesh-lamp",
    "bench/rock-under-sky",
    "bench/many-lights",
];

/// Built-in scenes Mitsuba cannot express, with a phrase of the refusal (README.md lists them).
const NOT_EXPRESSIBLE: &[(&str, &str)] = &[
    ("suzanne", "metal_rough, used by"),
    (
        "studies/scenes/glossy-area-light",
        "Schlick Fresnel with f0 = [0.6, 0.6, 0.6]",
    ),
    (
        "studies/scenes/grazing-sun",
        "angular diameter of 2° (a sun disk)",
    ),
    (
        "studies/scenes/slatted-screen",
        "angular diameter of 0.5° (a sun disk)",
    ),
    (
        "studies/scenes/long-sun-field",
        "angular diameter of 1° (a sun disk)",
    ),
    ("studies/scenes/relief-patch", "shape `patch`: displacement"),
    ("studies/scenes/relief-sphere", "shape `sphere/0`: displacement"),
    ("studies/scenes/shading-textured-sphere", "metal_rough, used by"),
    ("studies/scenes/specular-bumps", "normal map"),
    ("studies/scenes/energy-spheres", "cannot ignore visibility"),
];

fn agrees(name: &str, variant: Variant, size: u32, spp: u32) {
    agrees_at_depth(name, None, variant, (size, size), spp);
}

/// As [`agrees`] on a `width`×`height` film, with the scene's `max_depth` replaced when
/// `max_depth` is given (the same value reaches the oracle and, through the export, Mitsuba's
/// `path` integrator).
fn agrees_at_depth(
    name: &str,
    max_depth: Option<i32>,
    variant: Variant,
    (width, height): (u32, u32),
    spp: u32,
) {
    let mut scene = at(builtin(name), width, height);
    let mut tag = format!("{name}-{}", variant.name());
    if let Some(d) = max_depth {
        scene.render.max_depth = d;
        tag = format!("{name}-depth{d}-{}", variant.name());
    }
    let c = check(&tag, &scene, &scene, spp, variant);
    assert!(
        c.ztest.pass,
        "{tag}: the oracle and Mitsuba {} disagree: {:.3} % of pixel-channels fail (≤ 0.25 % allowed), \
         min p {:.2e}, relMSE {:.3e} vs noise {:.3e}; see {}",
        variant.name(),
        100.0 * (1.0 - c.ztest.passed_fraction),
        c.ztest.min_p,
        c.ztest.relmse,
        c.ztest.relmse_noise,
        c.oracle_exr.parent().unwrap_or(Path::new(".")).display()
    );
}

#[test]
fn cornell_box_agrees() {
    agrees("cornell-box", Variant::LlvmAdRgb, 64, 256);
}

/// Mitsuba's `max_depth` 2: emitters seen directly plus direct illumination, no indirect
/// light (Mitsuba 3 docs, `path` plugin, `max_depth`: "A value of 1 will only render directly
/// visible light sources. 2 will lead to single-bounce (direct-only) illumination").
#[test]
fn cornell_box_agrees_at_depth_2() {
    agrees_at_depth("cornell-box", Some(2), Variant::LlvmAdRgb, (64, 64), 256);
}

/// `max_depth` 3: direct illumination plus one bounce of indirect light.
#[test]
fn cornell_box_agrees_at_depth_3() {
    agrees_at_depth("cornell-box", Some(3), Variant::LlvmAdRgb, (64, 64), 256);
}

/// A CC0 mesh included from a glTF file with the scene's own material in place of the
/// asset's, a transform, and the asset's camera (scenes/include-asset.toml), on a film of the
/// camera's aspect ratio: what loading resolved is what both renderers see.
#[test]
fn include_asset_agrees() {
    agrees_at_depth("include-asset", None, Variant::LlvmAdRgb, (72, 48), 256);
}

#[test]
fn mirror_sphere_agrees() {
    agrees("mirror-sphere", Variant::LlvmAdRgb, 64, 256);
}

#[test]
fn soft_shadow_agrees() {
    agrees("soft-shadow", Variant::LlvmAdRgb, 64, 256);
}

#[test]
fn soft_shadow_agrees_with_scalar_variant() {
    agrees("soft-shadow", Variant::ScalarRgb, 32, 128);
}

#[test]
fn every_builtin_scene_is_crosschecked_or_listed() {
    // The built-in scenes, the studies' own scenes (scenes/studies/scenes/) and the bench
    // scenes (scenes/bench/).
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut names: Vec<String> = Vec::new();
    for (dir, prefix) in [
        (root.clone(), ""),
        (root.join("studies/scenes"), "studies/scenes/"),
        (root.join("bench"), "bench/"),
    ] {
        let found = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .filter_map(|e| e.ok()?.path().file_name()?.to_str().map(String::from))
            .filter_map(|f| f.strip_suffix(".toml").map(|s| format!("{prefix}{s}")))
            .filter(|stem| stem != "Cargo");
        names.extend(found);
    }
    names.sort();
    for name in &names {
        let outcome = export::export(&builtin(name));
        let listed = NOT_EXPRESSIBLE.iter().find(|(n, _)| n == name);
        match (outcome, listed) {
            (Ok(_), None) => assert!(
                CROSSCHECKED.contains(&name.as_str()),
                "scenes/{name}.toml is expressible in Mitsuba but has no cross-check test here"
            ),
            (Ok(_), Some(_)) => panic!("scenes/{name}.toml is listed as not expressible, but it exports"),
            (Err(e), Some((_, why))) => assert!(
                e.to_string().contains(why),
                "scenes/{name}.toml: refused for another reason than listed (`{why}`): {e}"
            ),
            (Err(e), None) => {
                panic!("scenes/{name}.toml cannot be cross-checked and is not listed in README.md: {e}")
            }
        }
    }
    for n in CROSSCHECKED {
        assert!(
            names.iter().any(|x| x == n),
            "CROSSCHECKED names scenes/{n}.toml, which does not exist"
        );
    }
}

/// The shadow studies' scenes (their ground truth is the oracle's `direct` with exact
/// visibility, which Mitsuba computes as `path` with max_depth 2).
#[test]
fn shadow_study_scenes_agree() {
    agrees("studies/scenes/contact-hardening", Variant::LlvmAdRgb, 64, 256);
    agrees("studies/scenes/overlapping-blockers", Variant::LlvmAdRgb, 64, 256);
}

/// The environment-mapping studies' scenes as their files stand (a mirror ball under an HDR;
/// with a glowing ball; the room), whose ground truth is the oracle's `path`.
#[test]
fn envmap_study_scenes_agree() {
    agrees("studies/scenes/envmap-ball", Variant::LlvmAdRgb, 64, 256);
    agrees("studies/scenes/envmap-locality", Variant::LlvmAdRgb, 64, 256);
    agrees("studies/scenes/envmap-room", Variant::LlvmAdRgb, 64, 256);
}

/// The texture-filtering study's checkerboard plane receding to the horizon (an emitter with a
/// bitmap radiance, seen directly: Mitsuba's bilinear `bitmap` against the oracle's bilinear
/// level 0, box pixel filter both).
#[test]
fn texture_study_scene_agrees() {
    agrees("studies/scenes/texture-plane", Variant::LlvmAdRgb, 64, 256);
}

/// The shading-frequency scene: a glossy icosphere (a generated triangle mesh with the
/// sphere's normals at its vertices, interpolated: Mitsuba's PLY mesh with vertex normals)
/// under a point and an area light.
#[test]
fn shading_study_scene_agrees() {
    agrees("studies/scenes/shading-sphere", Variant::LlvmAdRgb, 64, 256);
}

/// The projective-texturing scene: a spot light projecting a 512² checkerboard cookie onto a
/// floor, minified 8 texels per pixel at 128² (the exporter's frame for the cookie is checked
/// with an asymmetric pattern in mitsuba_features.rs).
#[test]
fn projective_texture_study_scene_agrees() {
    agrees("studies/scenes/projector", Variant::LlvmAdRgb, 64, 256);
}

/// The light-map studies' scenes: a room corner with a table under an area light, a floor of
/// two charts under a low light, a thin wall with a lit and a dark side — the path-traced
/// images (depth 4: direct light and two bounces) the baked maps are measured against, and
/// the transport the bake itself traces (`oracle::bake` shares the path integrator's walk).
#[test]
fn lightmap_study_scenes_agree() {
    for name in [
        "studies/scenes/lightmap-room",
        "studies/scenes/lightmap-seams",
        "studies/scenes/lightmap-wall",
    ] {
        agrees(name, Variant::LlvmAdRgb, 48, 256);
    }
}

/// The omnidirectional-shadow room: a point light inside a closed room with blockers in four
/// directions, direct light with exact visibility (hard shadows on floor, ceiling and walls).
#[test]
fn omni_shadow_room_agrees() {
    agrees("studies/scenes/omni-room", Variant::LlvmAdRgb, 48, 256);
}

/// The SSAO studies' yard: white clay under a constant white sky, the sky's direct light with
/// exact visibility (the sky-lit image the SSAO methods are also measured against).
#[test]
fn ssao_yard_agrees() {
    agrees("studies/scenes/ssao-yard", Variant::LlvmAdRgb, 48, 256);
}

/// The SSAO screen-edge scene: a wall just outside the frame, over a floor under the white sky.
#[test]
fn ssao_edge_agrees() {
    agrees("studies/scenes/ssao-edge", Variant::LlvmAdRgb, 48, 256);
}

/// The emissive-mesh scene: a box lamp of 12 emissive triangles (Mitsuba's `area` emitter
/// on a PLY mesh) over a floor and a glossy ball.
#[test]
fn mesh_lamp_agrees() {
    agrees("studies/scenes/mesh-lamp", Variant::LlvmAdRgb, 48, 256);
}

/// The anti-aliasing study's thin geometry (emissive boxes, as triangle meshes, over an
/// emissive bitmap): sub-pixel bars, wires and spokes are where the pixel's box filter is
/// all there is to measure, so both renderers must integrate it alike.
#[test]
fn antialias_study_scene_agrees() {
    agrees("studies/scenes/thin-edges", Variant::LlvmAdRgb, 64, 256);
}

/// The distance-impostor studies' rooms (emissive checkerboards on black walls around a mirror
/// or glass ball; with occluders), whose ground truth is the oracle's `path`.
#[test]
fn distance_impostor_study_scenes_agree() {
    agrees("studies/scenes/distance-room", Variant::LlvmAdRgb, 64, 256);
    agrees("studies/scenes/distance-room-glass", Variant::LlvmAdRgb, 64, 256);
    agrees(
        "studies/scenes/distance-room-occluders",
        Variant::LlvmAdRgb,
        64,
        256,
    );
}

/// The `verity bench` scene of a large mesh: a generated 1.3 M-triangle rock from a glTF file
/// (scenes/bench/make_rock.py, written by scripts/setup.sh) on a ground plane under an HDR sky.
#[test]
fn bench_rock_under_sky_agrees() {
    agrees("bench/rock-under-sky", Variant::LlvmAdRgb, 48, 256);
}

/// The `verity bench` scene of many lights: 64 small rectangle lights, each its own emitter,
/// over a furnished room (scenes/bench/make_many_lights.py).
#[test]
fn bench_many_lights_agrees() {
    agrees("bench/many-lights", Variant::LlvmAdRgb, 48, 256);
}
