//! `displacement` in scene files: procedural and file heights on rectangles, displaced
//! includes, and every bad input as an error naming the file and the field.

mod gltf_support;
mod toml_support;

use glam::{Vec2, Vec3};
use gltf_support::{document, Bin};
use scenes::displacement::{HeightGrid, Procedural};
use scenes::{Geometry, WrapMode};
use toml_support::{expect_error, load_text, scratch, write};

/// A scene with one displaced rectangle; `disp` is the inline displacement table.
fn patch_scene(disp: &str) -> String {
    format!(
        r#"[camera]
eye = [0, 2, 2]
target = [0, 0, 0]
fov = 40

[[material]]
name = "m"
type = "diffuse"

[[shape]]
name = "patch"
type = "rectangle"
material = "m"
center = [0, 0, 0]
size = [1, 1]
normal = [0, 1, 0]
displacement = {disp}
"#
    )
}

#[test]
fn procedural_bumps_are_sampled_at_texel_centres() {
    let dir = scratch("disp-bumps");
    let scene = load_text(
        &dir,
        &patch_scene(r#"{ procedural = "bumps", tiles = 2, resolution = 8, scale = 0.05 }"#),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let d = scene.shapes[0].displacement.clone().expect("displaced");
    assert_eq!((d.channel, d.scale), (0, 0.05));
    let t = &scene.textures[d.texture];
    assert_eq!((t.width, t.height, t.wrap), (8, 8, [WrapMode::Clamp; 2]));
    let bumps = Procedural::Bumps { tiles: 2 };
    for j in 0..8 {
        for i in 0..8 {
            let uv = Vec2::new((i as f32 + 0.5) / 8.0, (j as f32 + 0.5) / 8.0);
            assert_eq!(t.texels[j * 8 + i].x, bumps.height(uv));
        }
    }
    // The base surface is unchanged; the bounds grow by the largest height.
    assert!(matches!(scene.shapes[0].geometry, Geometry::Rectangle { .. }));
    let (lo, hi) = scene.shapes[0].bounds(&scene.textures);
    let top = 0.05 * t.texels.iter().fold(0.0f32, |m, x| m.max(x.x));
    assert!(
        (hi.y - top).abs() < 1e-6 && (lo.y + top).abs() < 1e-6,
        "{lo} {hi}"
    );
}

#[test]
fn defaults_and_shared_procedural_textures() {
    let dir = scratch("disp-defaults");
    let two = patch_scene(r#"{ procedural = "bricks", scale = -0.01 }"#)
        + r#"
[[shape]]
name = "other"
type = "rectangle"
material = "m"
center = [2, 0, 0]
size = [1, 1]
normal = [0, 1, 0]
displacement = { procedural = "bricks", scale = 0.02, wrap = "repeat" }

[[shape]]
name = "third"
type = "rectangle"
material = "m"
center = [4, 0, 0]
size = [1, 1]
normal = [0, 1, 0]
displacement = { procedural = "bricks", scale = 0.03 }
"#;
    let scene = load_text(&dir, &two).unwrap_or_else(|e| panic!("{e}"));
    let d: Vec<_> = scene
        .shapes
        .iter()
        .map(|s| s.displacement.clone().unwrap())
        .collect();
    let t = &scene.textures[d[0].texture];
    assert_eq!((t.width, t.height), (256, 256), "default resolution");
    assert_eq!(
        t.texels[0].x,
        Procedural::Bricks { rows: 8 }.height(Vec2::splat(0.5 / 256.0))
    );
    // Same generator and wrap: one texture; another wrap mode: its own.
    assert_eq!(d[0].texture, d[2].texture);
    assert_ne!(d[0].texture, d[1].texture);
    assert_eq!(scene.textures.len(), 2);
}

#[test]
fn height_texture_file_with_channel() {
    let dir = scratch("disp-file");
    let path = dir.join("h.exr");
    exr::prelude::write_rgb_file(&path, 4, 2, |x, y| (0.0, (x + 4 * y) as f32 / 8.0, 1.0))
        .expect("write the height image");
    let scene = load_text(
        &dir,
        &patch_scene(r#"{ texture = "h.exr", channel = 1, scale = 0.1 }"#),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let d = scene.shapes[0].displacement.clone().unwrap();
    assert_eq!(d.channel, 1);
    let grid = HeightGrid::new(&scene.textures[d.texture], d.channel, d.scale);
    // Texel (3, 1) (centre uv (7/8, 3/4)) holds 7/8: w = 0.1·7/8 there.
    assert!((grid.height(Vec2::new(0.875, 0.75)) - 0.0875).abs() < 1e-7);
}

#[test]
fn bad_displacements_name_the_field() {
    let dir = scratch("disp-bad");
    let cases: &[(&str, &[&str])] = &[
        (
            r#"{ texture = "missing.exr", scale = 0.1 }"#,
            &[
                "bad.toml:17:",
                "field `shape \"patch\".displacement.texture`",
                "file not found",
                "missing.exr",
            ],
        ),
        (
            r#"{ procedural = "bumps", resolution = 0, scale = 0.1 }"#,
            &["displacement.resolution`", "must be in 1..=8192, got 0"],
        ),
        (
            r#"{ procedural = "bumps", resolution = 100000, scale = 0.1 }"#,
            &["displacement.resolution`", "got 100000", "4096² 256 MiB"],
        ),
        (
            r#"{ procedural = "bumps" }"#,
            &[
                "field `shape \"patch\".displacement.scale`",
                "missing required field",
            ],
        ),
        (
            r#"{ procedural = "bumps", scale = nan }"#,
            &["displacement.scale`", "is NaN"],
        ),
        (
            r#"{ procedural = "waves", scale = 0.1 }"#,
            &["displacement.procedural`", "unknown value \"waves\""],
        ),
        (
            r#"{ scale = 0.1 }"#,
            &["field `shape \"patch\".displacement`", "needs its heights"],
        ),
        (
            r#"{ procedural = "bumps", texture = "h.png", scale = 0.1 }"#,
            &["cannot be given together"],
        ),
        (
            r#"{ procedural = "bumps", channel = 1, scale = 0.1 }"#,
            &["displacement.channel`", "applies to texture heights only"],
        ),
        (
            r#"{ procedural = "bumps", scale = 0.1, heigth = 1 }"#,
            &["unknown field `heigth` for a displacement"],
        ),
    ];
    for (disp, parts) in cases {
        expect_error(load_text(&dir, &patch_scene(disp)), parts);
    }
}

#[test]
fn nan_heights_are_an_error_naming_the_image() {
    let dir = scratch("disp-nan");
    let path = dir.join("nan.exr");
    exr::prelude::write_rgb_file(&path, 2, 2, |x, y| {
        let v = if (x, y) == (1, 0) { f32::NAN } else { 0.5 };
        (v, v, v)
    })
    .expect("write the image");
    expect_error(
        load_text(&dir, &patch_scene(r#"{ texture = "nan.exr", scale = 0.1 }"#)),
        &[
            "displacement.texture`",
            "nan.exr",
            "texel (1, 0) is NaN or infinite",
        ],
    );
}

#[test]
fn only_rectangles_and_meshes_are_displaced() {
    let dir = scratch("disp-kinds");
    let sphere = r#"[camera]
eye = [0, 2, 2]
target = [0, 0, 0]
fov = 40

[[material]]
name = "m"
type = "diffuse"

[[shape]]
name = "ball"
type = "sphere"
material = "m"
center = [0, 0, 0]
radius = 1
displacement = { procedural = "bumps", scale = 0.1 }
"#;
    expect_error(
        load_text(&dir, sphere),
        &[
            "bad.toml:16:",
            "field `shape \"ball\".displacement`",
            "a sphere cannot be displaced",
        ],
    );
    let cube = sphere
        .replace("type = \"sphere\"", "type = \"box\"")
        .replace("radius = 1", "size = [1, 1, 1]");
    expect_error(
        load_text(&dir, &cube),
        &["a box cannot be displaced", "tear apart"],
    );
    let light = patch_scene(r#"{ procedural = "bumps", scale = 0.1 }"#) + "emission = { radiance = 1 }\n";
    expect_error(
        load_text(&dir, &light),
        &["an emitting shape cannot be displaced"],
    );
}

/// A two-triangle glTF square in the XZ plane (normal +Y) with NORMAL and, if asked,
/// TEXCOORD_0 (u along +X, v along +Z).
fn square_gltf(with_uvs: bool) -> String {
    let mut bin = Bin::new();
    let pos = bin.vec3(&[
        [-0.5, 0.0, 0.5],
        [0.5, 0.0, 0.5],
        [0.5, 0.0, -0.5],
        [-0.5, 0.0, -0.5],
    ]);
    let nrm = bin.vec3(&[[0.0, 1.0, 0.0]; 4]);
    let uv = bin.vec2(&[[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    let idx = bin.indices(&[0, 1, 2, 0, 2, 3]);
    let uv_attr = if with_uvs {
        format!(",\"TEXCOORD_0\":{uv}")
    } else {
        String::new()
    };
    let rest = format!(
        "\"meshes\":[{{\"name\":\"square\",\"primitives\":[{{\"attributes\":{{\"POSITION\":{pos},\"NORMAL\":{nrm}{uv_attr}}},\"indices\":{idx}}}]}}],\"nodes\":[{{\"mesh\":0}}]"
    );
    document(&bin.parts(), &rest)
}

#[test]
fn included_meshes_are_displaced() {
    let dir = scratch("disp-include");
    write(&dir, "square.gltf", &square_gltf(true));
    write(&dir, "bare.gltf", &square_gltf(false));
    let scene = |file: &str| {
        format!(
            r#"[camera]
eye = [0, 2, 2]
target = [0, 0, 0]
fov = 40

[[include]]
file = "{file}"
displacement = {{ procedural = "bumps", resolution = 16, scale = 0.2 }}
"#
        )
    };
    let s = load_text(&dir, &scene("square.gltf")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.shapes.len(), 1);
    let d = s.shapes[0]
        .displacement
        .clone()
        .expect("the included mesh is displaced");
    assert_eq!((s.textures[d.texture].width, d.scale), (16, 0.2));
    let Geometry::Mesh(m) = &s.shapes[0].geometry else {
        panic!("a mesh")
    };
    let (micro, level) = scenes::displacement::displace_mesh(m, &s.textures[d.texture], 0, 0.2).unwrap();
    assert_eq!(level, 16);
    // Micro-vertices sit at height 0.2·h(uv) above the square.
    let tex = &s.textures[d.texture];
    for (p, uv) in micro.positions.iter().zip(&micro.uvs) {
        assert!((p.y - 0.2 * tex.sample(*uv).x).abs() < 1e-6);
        assert!((Vec3::new(p.x, 0.0, p.z) - Vec3::new(uv.x - 0.5, 0.0, uv.y - 0.5)).length() < 1e-6);
    }
    expect_error(
        load_text(&dir, &scene("bare.gltf")),
        &[
            "bad.toml:8:",
            "field `include[0].displacement`",
            "\"square/0\" has no texture coordinates",
        ],
    );
}

#[test]
fn displacement_scenes_load() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("displacement");
    for (name, shape, resolution) in [("bumps.toml", "floor", 256), ("bricks.toml", "wall", 512)] {
        let s = scenes::load(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"));
        let sh = s
            .shapes
            .iter()
            .find(|x| x.name == shape)
            .expect("the displaced shape");
        let d = sh.displacement.as_ref().expect("displaced");
        assert_eq!(s.textures[d.texture].width, resolution, "{name}");
    }
}

/// Many procedural displacements that each fit the memory budget but together do not are
/// refused at the first that does not fit, before its heights are generated, naming its
/// field and line (the issue's reproducer: 16 at resolution 8192 ask 16 GiB; here 8 at 1024
/// under 40 MiB, 16 MiB each: the third is refused).
#[test]
fn displacements_are_charged_together_against_the_budget() {
    use scenes::budget::{Ledger, Limit, Source};
    let dir = scratch("disp-budget");
    let mut text = patch_scene(r#"{ procedural = "bumps", tiles = 1, resolution = 1024, scale = 0.05 }"#);
    for tiles in 2..=16 {
        text.push_str(&format!(
            "\n[[shape]]\nname = \"p{tiles}\"\ntype = \"rectangle\"\nmaterial = \"m\"\ncenter = [0, 0, 0]\nsize = [1, 1]\nnormal = [0, 1, 0]\ndisplacement = {{ procedural = \"bumps\", tiles = {tiles}, resolution = 1024, scale = 0.05 }}\n"
        ));
    }
    let path = write(&dir, "many.toml", &text);
    let ledger = Ledger::with_limit(Limit {
        bytes: 40 << 20,
        source: Source::Flag,
    });
    let e = scenes::toml::load_in(&path, &ledger).unwrap_err().to_string();
    for part in [
        "many.toml:",
        "many.toml:35: field `shape \"p3\".displacement.procedural`",
        "the procedural bumps, tiles 3, 1024² texels: 16.0 MiB (16777216 bytes) needed",
        "on top of 32.0 MiB already loaded",
        "over the memory limit of 40.0 MiB",
    ] {
        assert!(e.contains(part), "{part:?} missing from: {e}");
    }
    assert!(ledger.used() <= 40 << 20);
}
