//! Hostile glTF input (issue 19): URIs that leave the asset's folder, files that are not
//! regular, sizes beyond the memory budget, indices of 2³² and more, values the renderers
//! cannot sum, names unfit for AOV channels and file names, and messages that must stay one
//! line. Each case is a reproducer from the fuzzing campaign: it loaded (or hung) before.

mod gltf_support;

use std::path::{Path, PathBuf};

use gltf_support::*;
use scenes::SceneError;

/// Asserts `result` is an error naming `file_name`, with field `field`, whose text contains
/// every one of `words`; returns the text.
#[track_caller]
fn expect_error<T: std::fmt::Debug>(
    result: Result<T, SceneError>,
    file_name: &str,
    field: &str,
    words: &[&str],
) -> String {
    let err = result.expect_err("expected an error");
    let text = err.to_string();
    assert!(text.contains(file_name), "error should name {file_name}: {text}");
    assert_eq!(err.field.as_deref(), Some(field), "wrong field in: {text}");
    for w in words {
        assert!(text.contains(w), "error should say `{w}`: {text}");
    }
    assert!(!text.contains('\n'), "one line: {text}");
    text
}

/// The one-triangle document with its buffer at `uri`, written as `<tag>.gltf` in `dir`.
fn triangle_with_buffer_at(dir: &Path, tag: &str, uri: &str) -> PathBuf {
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let json = document(
        &bin.parts_with_uri(uri),
        &format!("{meshes},\"nodes\":[{{\"mesh\":0}}]"),
    );
    write(dir, &format!("{tag}.gltf"), json)
}

/// The one-triangle document (buffer embedded) with an emissive texture whose image is at
/// `uri`.
fn triangle_with_image_at(dir: &Path, tag: &str, uri: &str) -> PathBuf {
    let mut bin = Bin::new();
    let uv = bin.vec2(&[[0.0, 0.0]; 3]);
    let meshes = triangle(&mut bin, &format!(",\"TEXCOORD_0\":{uv}"), Some(0));
    let rest = format!(
        "{meshes},\"nodes\":[{{\"mesh\":0}}],\"materials\":[{{\"emissiveFactor\":[1,1,1],\"emissiveTexture\":{{\"index\":0}}}}],\
         \"textures\":[{{\"source\":0}}],\"images\":[{{\"uri\":\"{uri}\"}}]"
    );
    write(dir, &format!("{tag}.gltf"), document(&bin.parts(), &rest))
}

/// A scene file in `dir` that includes `asset` (a path relative to `dir`) with `extra` lines.
fn scene_including(dir: &Path, asset: &str, extra: &str) -> PathBuf {
    let text = format!(
        "[camera]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\nfov = 40\n\n[[include]]\nfile = \"{asset}\"\n{extra}"
    );
    write(dir, "scene.toml", text)
}

#[test]
fn uris_that_leave_the_asset_folder_are_refused() {
    let dir = temp_dir("outside");
    for (i, uri) in [
        "/etc/passwd",
        "file:///etc/passwd",
        "../../../../etc/passwd",
        "%2e%2e/%2e%2e/%2e%2e/%2e%2e/etc/passwd",
        "%2Fetc%2Fpasswd",
        "/proc/self/environ",
    ]
    .into_iter()
    .enumerate()
    {
        let tag = format!("buffer{i}");
        let path = triangle_with_buffer_at(&dir, &tag, uri);
        let text = expect_error(
            scenes::gltf::load(&path),
            &format!("{tag}.gltf"),
            "buffers[0].uri",
            &["is refused", "--allow-paths-outside"],
        );
        assert!(
            text.contains("absolute path") || text.contains("resolves to /etc/passwd, outside"),
            "the reason: {text}"
        );
    }
    let path = triangle_with_image_at(&dir, "image", "..%2F..%2F..%2F..%2Fetc%2Fpasswd");
    expect_error(
        scenes::gltf::load(&path),
        "image.gltf",
        "images[0].uri",
        &[
            "is refused",
            "resolves to /etc/passwd, outside",
            "--allow-paths-outside",
        ],
    );
    let path = triangle_with_buffer_at(&dir, "web", "https://example.com/a.bin");
    expect_error(
        scenes::gltf::load(&path),
        "web.gltf",
        "buffers[0].uri",
        &["the `https:` scheme does not name a local file"],
    );
}

#[cfg(unix)]
#[test]
fn a_symbolic_link_out_of_the_folder_is_refused() {
    let outside = temp_dir("link-target");
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let secret = write(&outside, "secret.bin", &bin.bytes);
    let dir = temp_dir("link");
    std::os::unix::fs::symlink(&secret, dir.join("inside.bin")).unwrap();
    let json = document(
        &bin.parts_with_uri("inside.bin"),
        &format!("{meshes},\"nodes\":[{{\"mesh\":0}}]"),
    );
    let path = write(&dir, "link.gltf", json);
    expect_error(
        scenes::gltf::load(&path),
        "link.gltf",
        "buffers[0].uri",
        &[
            "a symbolic link takes it to",
            "secret.bin, outside",
            "--allow-paths-outside",
        ],
    );
    // A link that stays inside the folder is fine.
    std::fs::copy(&secret, dir.join("real.bin")).unwrap();
    std::fs::remove_file(dir.join("inside.bin")).unwrap();
    std::os::unix::fs::symlink("real.bin", dir.join("inside.bin")).unwrap();
    assert_eq!(scenes::gltf::load(&path).unwrap().shapes.len(), 1);
}

/// A FIFO must never be opened (opening one blocks until a writer comes: the load hung), a
/// folder or a device is "not a regular file", and a `/proc` file (size 0) is shorter than
/// its `byteLength`.
#[cfg(unix)]
#[test]
fn only_regular_files_are_read() {
    let dir = temp_dir("special");
    let fifo = dir.join("pipe.bin");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success(), "mkfifo");
    let path = triangle_with_buffer_at(&dir, "fifo", "pipe.bin");
    expect_error(
        scenes::gltf::load(&path),
        "fifo.gltf",
        "buffers[0].uri",
        &["pipe.bin is not a regular file (it is a FIFO)"],
    );
    let path = triangle_with_image_at(&dir, "fifo-image", "pipe.bin");
    expect_error(
        scenes::gltf::load(&path),
        "fifo-image.gltf",
        "images[0].uri",
        &["is not a regular file (it is a FIFO)"],
    );
    std::fs::create_dir(dir.join("folder.bin")).unwrap();
    let path = triangle_with_buffer_at(&dir, "folder", "folder.bin");
    expect_error(
        scenes::gltf::load(&path),
        "folder.gltf",
        "buffers[0].uri",
        &["folder.bin is not a regular file (it is a directory)"],
    );
    // Outside the folder only with the include's permission; still only regular files.
    for (i, (uri, words)) in [
        ("/dev/zero", "/dev/zero is not a regular file (it is a device)"),
        ("/proc/self/environ", "holds 0 bytes, fewer than the"),
    ]
    .into_iter()
    .enumerate()
    {
        let dir = temp_dir(&format!("special-include{i}"));
        triangle_with_buffer_at(&dir, "device", uri);
        let scene = scene_including(&dir, "device.gltf", "allow_paths_outside = true");
        expect_error(
            scenes::toml::load(&scene),
            "device.gltf",
            "buffers[0].uri",
            &[words],
        );
    }
}

/// An asset included from a scene file may also read the scene's folder; with
/// `allow_paths_outside = true` anywhere; loaded by itself, only its own folder.
#[test]
fn includes_may_read_the_scene_folder_or_be_allowed_out() {
    let scene_dir = temp_dir("include-scene");
    let assets = scene_dir.join("assets");
    std::fs::create_dir(&assets).unwrap();
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    write(&scene_dir, "scene-folder.bin", &bin.bytes);
    let json = document(
        &bin.parts_with_uri("../scene-folder.bin"),
        &format!("{meshes},\"nodes\":[{{\"mesh\":0}}]"),
    );
    let asset = write(&assets, "up.gltf", json);
    let scene = scene_including(&scene_dir, "assets/up.gltf", "");
    assert_eq!(scenes::toml::load(&scene).unwrap().shapes.len(), 1);
    expect_error(
        scenes::gltf::load(&asset),
        "up.gltf",
        "buffers[0].uri",
        &["scene-folder.bin, outside"],
    );

    let elsewhere = temp_dir("include-elsewhere");
    let data = write(&elsewhere, "far.bin", &bin.bytes);
    let json = document(
        &bin.parts_with_uri(&data.display().to_string()),
        &format!("{meshes},\"nodes\":[{{\"mesh\":0}}]"),
    );
    write(&assets, "far.gltf", json);
    let scene = scene_including(&scene_dir, "assets/far.gltf", "");
    expect_error(
        scenes::toml::load(&scene),
        "far.gltf",
        "buffers[0].uri",
        &["absolute path", "allow_paths_outside = true"],
    );
    let scene = scene_including(&scene_dir, "assets/far.gltf", "allow_paths_outside = true");
    assert_eq!(scenes::toml::load(&scene).unwrap().shapes.len(), 1);
}

#[test]
fn declared_sizes_beyond_the_budget_are_errors_before_allocating() {
    let huge = 1u64 << 50;
    let dir = temp_dir("budget");
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let json = document(
        &bin.parts().replacen(
            &format!("\"byteLength\":{}}}]", bin.bytes.len()),
            &format!("\"byteLength\":{huge}}}]"),
            1,
        ),
        &format!("{meshes},\"nodes\":[{{\"mesh\":0}}]"),
    );
    let path = write(&dir, "buffer.gltf", json);
    expect_error(
        scenes::gltf::load(&path),
        "buffer.gltf",
        "buffers[0].byteLength",
        &[
            "the 1125899906842624 bytes of buffers[0]: 1024.0 TiB (1125899906842624 bytes) needed",
            "over the memory limit",
        ],
    );

    // A sparse accessor without a buffer view is `count` zeros plus its substitutions: any
    // count can be declared in a few bytes.
    let mut bin = Bin::new();
    let indices = bin.view(&0u32.to_le_bytes(), None);
    let values = bin.view(&[0u8; 12], None);
    let pos = bin.accessor(format!(
        "{{\"componentType\":5126,\"count\":{huge},\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[0,0,0],\
         \"sparse\":{{\"count\":1,\"indices\":{{\"bufferView\":{indices},\"componentType\":5125}},\
         \"values\":{{\"bufferView\":{values}}}}}}}"
    ));
    let json = document(
        &bin.parts(),
        &format!("\"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":{pos}}}}}]}}],\"nodes\":[{{\"mesh\":0}}]"),
    );
    let path = write(&dir, "count.gltf", json);
    expect_error(
        scenes::gltf::load(&path),
        "count.gltf",
        "accessors[0].count",
        &[
            "values read for meshes[0].primitives[0].attributes.POSITION: ",
            "over the memory limit",
        ],
    );

    // A GLB whose buffer claims more than its BIN chunk.
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let json = document(
        &bin.parts_with_uri("").replacen(
            &format!("\"byteLength\":{}}}]", bin.bytes.len()),
            &format!("\"byteLength\":{}}}]", bin.bytes.len() + 64),
            1,
        ),
        &format!("{meshes},\"nodes\":[{{\"mesh\":0}}]"),
    );
    let path = write(&dir, "short.glb", glb(&json, &bin.bytes));
    expect_error(
        scenes::gltf::load(&path),
        "short.glb",
        "buffers[0].byteLength",
        &["but the GLB BIN chunk holds only"],
    );
}

#[test]
fn indices_of_2_to_the_32_do_not_wrap_around() {
    let cases = [
        (
            "\"indices\":2",
            "\"indices\":4294967298",
            "meshes[0].primitives[0].indices",
        ),
        ("{\"mesh\":0}", "{\"mesh\":4294967296}", "nodes[0].mesh"),
        (
            "\"bufferView\":0",
            "\"bufferView\":4294967296",
            "accessors[0].bufferView",
        ),
    ];
    for (i, (from, to, field)) in cases.into_iter().enumerate() {
        let mut bin = Bin::new();
        let meshes = triangle(&mut bin, "", None);
        let json = document(&bin.parts(), &format!("{meshes},\"nodes\":[{{\"mesh\":0}}]"));
        assert!(json.contains(from), "{json}");
        let tag = format!("wrap{i}");
        expect_error(
            load_json(&tag, &json.replacen(from, to, 1)),
            &format!("{tag}.gltf:1:"),
            field,
            &["is out of range", "below 2^32"],
        );
    }
}

#[test]
fn gltf_versions_other_than_2_x_are_errors() {
    let with_asset = |asset: &str| format!("{{\"asset\":{asset},\"nodes\":[]}}");
    for (i, (asset, field)) in [
        ("{\"version\":\"1.0\"}", "asset.version"),
        ("{\"version\":\"3.0\"}", "asset.version"),
        ("{\"version\":\"2\"}", "asset.version"),
        ("{\"version\":\"2.0\",\"minVersion\":\"2.1\"}", "asset.minVersion"),
    ]
    .into_iter()
    .enumerate()
    {
        let tag = format!("version{i}");
        expect_error(load_json(&tag, &with_asset(asset)), &tag, field, &["glTF"]);
    }
    assert!(load_json(
        "version-ok",
        &with_asset("{\"version\":\"2.1\",\"minVersion\":\"2.0\"}")
    )
    .is_ok());
}

/// Lights are checked at load whether or not a node places them.
#[test]
fn lights_outside_the_extension_ranges_or_beyond_f32_sums_are_errors() {
    let at = "extensions.KHR_lights_punctual.lights[0]";
    for (i, (light, field, words)) in [
        (
            "{\"type\":\"spot\",\"spot\":{\"innerConeAngle\":0.6,\"outerConeAngle\":0.5}}",
            format!("{at}.spot.innerConeAngle"),
            "must lie in [0, outerConeAngle = 0.5]",
        ),
        (
            "{\"type\":\"spot\",\"spot\":{\"outerConeAngle\":3}}",
            format!("{at}.spot.outerConeAngle"),
            "(0, π/2]",
        ),
        (
            "{\"type\":\"spot\",\"spot\":{\"innerConeAngle\":-0.1}}",
            format!("{at}.spot.innerConeAngle"),
            "got -0.1",
        ),
        (
            "{\"type\":\"point\",\"intensity\":3e38}",
            format!("{at}.intensity"),
            "exceeds 1e20, more than the renderers can sum",
        ),
        (
            "{\"type\":\"point\",\"range\":0}",
            format!("{at}.range"),
            "must be finite and > 0",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let mut bin = Bin::new();
        let meshes = triangle(&mut bin, "", None);
        let rest = format!(
            "{meshes},\"extensionsUsed\":[\"KHR_lights_punctual\"],\
             \"extensions\":{{\"KHR_lights_punctual\":{{\"lights\":[{light}]}}}},\"nodes\":[{{\"mesh\":0}}]"
        );
        let tag = format!("light{i}");
        expect_error(
            load_json(&tag, &document(&bin.parts(), &rest)),
            &tag,
            &field,
            &[words],
        );
    }
}

#[test]
fn materials_and_cameras_that_would_overflow_are_errors() {
    for (i, (rest, field, words)) in [
        (
            "\"materials\":[{\"emissiveFactor\":[1,1,1],\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":1e30}}}]",
            "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength",
            "exceeds 1e20",
        ),
        (
            "\"materials\":[{\"normalTexture\":{\"index\":0,\"scale\":1e30}}],\"textures\":[{\"source\":0}],\"images\":[{\"uri\":\"x.png\"}]",
            "materials[0].normalTexture.scale",
            "at most 1e6",
        ),
        (
            "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.5,\"znear\":0}}]",
            "cameras[0].perspective.znear",
            "must be finite and > 0",
        ),
        (
            "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.5,\"znear\":1,\"zfar\":0.5}}]",
            "cameras[0].perspective.zfar",
            "greater than znear",
        ),
        (
            "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.5,\"znear\":0.1,\"aspectRatio\":-1}}]",
            "cameras[0].perspective.aspectRatio",
            "> 0",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let mut bin = Bin::new();
        let material = rest.starts_with("\"materials\"").then_some(0);
        let uv = bin.vec2(&[[0.0, 0.0]; 3]);
        let meshes = triangle(&mut bin, &format!(",\"TEXCOORD_0\":{uv}"), material);
        let rest = format!("{meshes},\"nodes\":[{{\"mesh\":0}}],{rest}");
        let tag = format!("overflow{i}");
        expect_error(load_json(&tag, &document(&bin.parts(), &rest)), &tag, field, &[words]);
    }
}

#[test]
fn projective_singular_and_non_finite_node_matrices_are_errors() {
    let singular = ["is singular", "§3.5.3"];
    for (i, (matrix, words)) in [
        (
            "[1,0,0,0.5, 0,1,0,0, 0,0,1,0, 0,0,0,1]",
            &["is projective", "§3.5.3"][..],
        ),
        ("[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,2]", &["is projective"][..]),
        ("[1,0,0,0, 0,0,0,0, 0,0,1,0, 0,0,0,1]", &singular[..]),
        (
            "[1e30,0,0,0, 0,1e30,0,0, 0,0,1e30,0, 0,0,0,1]",
            &["determinant overflows f32"][..],
        ),
        (
            "[1e39,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]",
            &["non-finite entry"][..],
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let mut bin = Bin::new();
        let meshes = triangle(&mut bin, "", None);
        let rest = format!("{meshes},\"nodes\":[{{\"mesh\":0,\"matrix\":{matrix}}}]");
        let tag = format!("matrix{i}");
        expect_error(
            load_json(&tag, &document(&bin.parts(), &rest)),
            &tag,
            "nodes[0].matrix",
            words,
        );
    }
}

/// Names become AOV channels and file names: only `[A-Za-z0-9_-]`, at most 64 characters,
/// still unique; the asset loads and one note says so.
#[test]
fn names_from_the_file_are_made_safe_with_one_note() {
    let long = "L".repeat(200_000);
    let given = [
        "Cube.001".to_string(),
        "Left Arm".to_string(),
        "a/b:c*d".to_string(),
        "\u{202e}gnp.exe\n".to_string(),
        "🙂".to_string(),
        "Cube 001".to_string(),
        long,
    ];
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let nodes: Vec<String> = given
        .iter()
        .map(|n| format!("{{\"mesh\":0,\"name\":{}}}", json_string(n)))
        .collect();
    let lights = "\"extensionsUsed\":[\"KHR_lights_punctual\"],\
        \"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":\"point\",\"name\":\"Lamp.001\"}]}}";
    let rest = format!(
        "{meshes},{lights},\"nodes\":[{},{{\"name\":\"holder\",\"extensions\":{{\"KHR_lights_punctual\":{{\"light\":0}}}}}}]",
        nodes.join(",")
    );
    let dir = temp_dir("names");
    let loaded =
        scenes::gltf::load_with_notes(&write(&dir, "names.gltf", document(&bin.parts(), &rest))).unwrap();
    let mut expected: Vec<String> = [
        "Cube_001/0",
        "Left_Arm/0",
        "a_b_c_d/0",
        "_gnp_exe_/0",
        "_/0",
        "Cube_001/0#2",
    ]
    .map(String::from)
    .to_vec();
    expected.push(format!("{}/0", "L".repeat(64)));
    assert_eq!(names(&loaded.scene), expected);
    assert_eq!(loaded.scene.lights[0].name(), "Lamp_001");
    let noted: Vec<&String> = loaded.notes.iter().filter(|n| n.starts_with("names:")).collect();
    assert_eq!(noted.len(), 1, "{:?}", loaded.notes);
    assert!(noted[0].contains("\"Cube.001\" → Cube_001"), "{}", noted[0]);
}

/// A JSON string literal for `s` (quotes, backslashes and control characters escaped).
fn json_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[test]
fn json_errors_name_the_field_and_echoes_stay_short() {
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let json = document(&bin.parts(), &format!("{meshes},\"nodes\":[{{\"mesh\":0}}]"));
    let bad = json.replacen("\"POSITION\":0", "\"POSITION\":\"zero\"", 1);
    assert_ne!(bad, json);
    let text = expect_error(
        load_json("json-field", &bad),
        "json-field.gltf:1:",
        "meshes[0].primitives[0].attributes.POSITION",
        &[
            "malformed glTF JSON",
            "expected index into child of root",
            "column",
        ],
    );
    assert!(text.len() < 400, "{text}");

    let name = format!("KHR_evil\n\u{202e}{}", "x".repeat(1_000_000));
    let json = format!(
        "{{\"asset\":{{\"version\":\"2.0\"}},\"extensionsUsed\":[{0}],\"extensionsRequired\":[{0}]}}",
        json_string(&name)
    );
    let text = expect_error(
        load_json("echo", &json),
        "echo.gltf",
        "extensionsRequired[0]",
        &["required extension \"KHR_evil\\n\\u{202e}xxx", "…"],
    );
    assert!(text.len() < 600, "{} bytes", text.len());
}

/// glTF loading was quadratic in the number of shapes (20,000 nodes sharing a named mesh:
/// about a minute), because every unique name searched `#2, #3, …` from the start. This
/// checks the result of the large loads; the linear work is counted (not timed) by the
/// loader's own test `gltf::names::tests::uniqueness_work_grows_linearly_with_equal_bases`.
#[test]
fn twenty_thousand_primitives_or_instances_load() {
    let n = 20_000;
    let mut bin = Bin::new();
    let pos = bin.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let prim = format!("{{\"attributes\":{{\"POSITION\":{pos}}}}}");
    let prims = vec![prim.as_str(); n].join(",");
    let rest = format!(
        "\"meshes\":[{{\"name\":\"many\",\"primitives\":[{prims}]}},{{\"name\":\"tri\",\"primitives\":[{prim}]}}],\
         \"nodes\":[{{\"mesh\":0}}]"
    );
    let scene = load_json("many-prims", &document(&bin.parts(), &rest)).unwrap();
    assert_eq!(scene.shapes.len(), n);
    assert_eq!(scene.shapes[n - 1].name, format!("many/{}", n - 1));
    let triangles: usize = scene
        .shapes
        .iter()
        .map(|s| match &s.geometry {
            scenes::Geometry::Mesh(m) => m.indices.len(),
            other => panic!("{} is not a mesh: {other:?}", s.name),
        })
        .sum();
    assert_eq!(triangles, n);

    let nodes: Vec<String> = (0..n)
        .map(|i| format!("{{\"mesh\":1,\"translation\":[{i},0,0]}}"))
        .collect();
    let rest = format!(
        "\"meshes\":[{{\"primitives\":[{prim}]}},{{\"name\":\"tri\",\"primitives\":[{prim}]}}],\"nodes\":[{}]",
        nodes.join(",")
    );
    let scene = load_json("many-nodes", &document(&bin.parts(), &rest)).unwrap();
    assert_eq!(scene.shapes.len(), n);
    assert_eq!(scene.shapes[n - 1].name, format!("tri/0#{n}"));
    let last = mesh(&scene, &format!("tri/0#{n}"));
    assert_eq!(last.indices.len(), 1);
    assert_eq!(last.positions[0], glam::Vec3::new((n - 1) as f32, 0.0, 0.0));
}
