//! Bad glTF input: every class of problem is an error naming the file and the JSON field,
//! and no corruption of a valid file makes the loader panic.

mod gltf_support;

use gltf_support::*;
use scenes::SceneError;

/// Asserts `result` is an error about `file_name` whose field is `field` and whose message
/// contains `words`.
#[track_caller]
fn expect_error<T: std::fmt::Debug>(
    result: Result<T, SceneError>,
    file_name: &str,
    field: Option<&str>,
    words: &str,
) {
    let err = result.expect_err("expected an error");
    let text = err.to_string();
    assert!(text.contains(file_name), "error should name {file_name}: {text}");
    assert_eq!(err.field.as_deref(), field, "wrong field in: {text}");
    assert!(text.contains(words), "error should say `{words}`: {text}");
}

/// One triangle with optional extra top-level members; returns the loader's result.
fn triangle_doc(tag: &str, edit: impl FnOnce(&mut Bin) -> String) -> Result<scenes::Scene, SceneError> {
    let mut bin = Bin::new();
    let rest = edit(&mut bin);
    load_json(tag, &document(&bin.parts(), &rest))
}

#[test]
fn malformed_json_names_the_line() {
    let err = load_json(
        "bad-json",
        "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"nodes\": [ {,} ]\n}",
    )
    .unwrap_err();
    assert!(err.to_string().contains("bad-json.gltf"), "{err}");
    assert_eq!(err.line, Some(3), "{err}");
}

#[test]
fn malformed_glb_containers() {
    let dir = temp_dir("bad-glb");
    let valid = glb("{\"asset\":{\"version\":\"2.0\"}}", &[1, 2, 3, 4]);
    let mut wrong_version = valid.clone();
    wrong_version[4] = 1;
    let mut long_chunk = valid.clone();
    long_chunk[12] = 200; // JSON chunk length beyond the file
    for (name, bytes, words) in [
        ("short.glb", b"glTF\x02\0".to_vec(), "truncated"),
        ("version.glb", wrong_version, "version 1"),
        ("chunk.glb", long_chunk, "runs past the end"),
        ("truncated.glb", valid[..valid.len() - 2].to_vec(), "header says"),
    ] {
        expect_error(scenes::gltf::load(&write(&dir, name, bytes)), name, None, words);
    }
    assert!(scenes::gltf::load(&write(&dir, "ok.glb", valid)).is_ok());
}

#[test]
fn missing_buffer_and_image_files() {
    let dir = temp_dir("missing-files");
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let json = document(
        &bin.parts_with_uri("nowhere.bin"),
        &format!("{meshes},\"nodes\":[{{\"mesh\":0}}]"),
    );
    let result = scenes::gltf::load(&write(&dir, "no-buffer.gltf", json));
    expect_error(result, "no-buffer.gltf", Some("buffers[0].uri"), "nowhere.bin");

    let mut bin = Bin::new();
    let uv = bin.vec2(&[[0.0, 0.0]; 3]);
    let meshes = triangle(&mut bin, &format!(",\"TEXCOORD_0\":{uv}"), Some(0));
    let rest = format!(
        "{meshes},\"nodes\":[{{\"mesh\":0}}],\"materials\":[{{\"emissiveFactor\":[1,1,1],\"emissiveTexture\":{{\"index\":0}}}}],\
         \"textures\":[{{\"source\":0}}],\"images\":[{{\"uri\":\"gone.png\"}}]"
    );
    let result = scenes::gltf::load(&write(&dir, "no-image.gltf", document(&bin.parts(), &rest)));
    expect_error(result, "no-image.gltf", Some("images[0].uri"), "gone.png");

    let bad_png = data_uri("image/png", b"not a png at all");
    let rest = rest.replace("gone.png", &bad_png);
    let result = scenes::gltf::load(&write(&dir, "bad-image.gltf", document(&bin.parts(), &rest)));
    expect_error(result, "bad-image.gltf", Some("images[0]"), "emissiveTexture");
}

#[test]
fn nan_position_and_out_of_range_index() {
    let result = triangle_doc("nan", |bin| {
        let pos = bin.vec3(&[[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        format!("\"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":{pos}}}}}]}}],\"nodes\":[{{\"mesh\":0}}]")
    });
    // The builder's min/max of a NaN column are not NaN, so the document itself is valid JSON.
    expect_error(
        result,
        "nan.gltf",
        Some("meshes[0].primitives[0].attributes.POSITION"),
        "vertex 1",
    );

    let result = triangle_doc("index-range", |bin| {
        let pos = bin.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        let idx = bin.indices(&[0, 1, 3]);
        format!("\"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":{pos}}},\"indices\":{idx}}}]}}],\"nodes\":[{{\"mesh\":0}}]")
    });
    expect_error(
        result,
        "index-range.gltf",
        Some("meshes[0].primitives[0].indices"),
        "out of range",
    );
}

#[test]
fn byte_ranges_outside_views_and_buffers() {
    let result = triangle_doc("accessor-range", |bin| {
        let view = bin.view(&[0u8; 24], None);
        let acc = bin.accessor(format!(
            "{{\"bufferView\":{view},\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,1]}}"
        ));
        format!("\"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":{acc}}}}}]}}],\"nodes\":[{{\"mesh\":0}}]")
    });
    expect_error(
        result,
        "accessor-range.gltf",
        Some("meshes[0].primitives[0].attributes.POSITION"),
        "run past the end of bufferViews[0]",
    );

    let dir = temp_dir("view-range");
    let json = document(
        &format!(
            "\"buffers\":[{{\"uri\":\"{}\",\"byteLength\":8}}],\"bufferViews\":[{{\"buffer\":0,\"byteOffset\":4,\"byteLength\":8}}]",
            data_uri("application/octet-stream", &[0u8; 8])
        ),
        "\"nodes\":[]",
    );
    expect_error(
        scenes::gltf::load(&write(&dir, "view.gltf", json)),
        "view.gltf",
        Some("bufferViews[0]"),
        "outside buffers[0]",
    );
}

#[test]
fn unsupported_primitive_mode_and_attribute_types() {
    let result = triangle_doc("lines", |bin| {
        let pos = bin.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
        format!("\"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":{pos}}},\"mode\":1}}]}}],\"nodes\":[{{\"mesh\":0}}]")
    });
    expect_error(
        result,
        "lines.gltf",
        Some("meshes[0].primitives[0].mode"),
        "Lines",
    );

    let result = triangle_doc("mode-enum", |bin| {
        let pos = bin.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        format!("\"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":{pos}}},\"mode\":9}}]}}],\"nodes\":[{{\"mesh\":0}}]")
    });
    expect_error(
        result,
        "mode-enum.gltf",
        Some("meshes[0].primitives[0].mode"),
        "Invalid value",
    );

    let result = triangle_doc("normal-type", |bin| {
        let pos = bin.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        let nrm = bin.vec2(&[[0.0, 1.0]; 3]);
        format!("\"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":{pos},\"NORMAL\":{nrm}}}}}]}}],\"nodes\":[{{\"mesh\":0}}]")
    });
    expect_error(
        result,
        "normal-type.gltf",
        Some("meshes[0].primitives[0].attributes.NORMAL"),
        "needs Vec3",
    );

    let result = triangle_doc("position-index", |_| {
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":7}}]}],\"nodes\":[{\"mesh\":0}]"
            .to_string()
    });
    expect_error(
        result,
        "position-index.gltf",
        Some("meshes[0].primitives[0].attributes.POSITION"),
        "does not exist",
    );
}

#[test]
fn required_extensions_we_lack_are_errors_with_a_fix() {
    for (ext, fix) in [
        (
            "KHR_draco_mesh_compression",
            "npx @gltf-transform/cli copy in.glb out.glb",
        ),
        (
            "EXT_meshopt_compression",
            "npx @gltf-transform/cli copy in.glb out.glb",
        ),
        ("KHR_texture_basisu", "ktxdecompress"),
        ("KHR_texture_transform", "supports only"),
    ] {
        let json = format!(
            "{{\"asset\":{{\"version\":\"2.0\"}},\"extensionsUsed\":[\"KHR_lights_punctual\",\"{ext}\"],\
             \"extensionsRequired\":[\"KHR_lights_punctual\",\"{ext}\"]}}"
        );
        let err = load_json("required", &json).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("extensionsRequired[1]"), "{err}");
        let text = err.to_string();
        assert!(
            text.contains("required.gltf") && text.contains(ext) && text.contains(fix),
            "{text}"
        );
    }
}

#[test]
fn material_problems_name_the_material_field() {
    let two_sets = triangle_doc("uv-sets", |bin| {
        let uv = bin.vec2(&[[0.0, 0.0]; 3]);
        let meshes = triangle(bin, &format!(",\"TEXCOORD_0\":{uv},\"TEXCOORD_1\":{uv}"), Some(0));
        let img = data_uri("image/png", &png(1, 1, &[[255; 4]]));
        format!(
            "{meshes},\"nodes\":[{{\"mesh\":0}}],\"textures\":[{{\"source\":0}}],\"images\":[{{\"uri\":\"{img}\"}}],\
             \"materials\":[{{\"pbrMetallicRoughness\":{{\"baseColorTexture\":{{\"index\":0}}}},\"normalTexture\":{{\"index\":0,\"texCoord\":1}}}}]"
        )
    });
    expect_error(
        two_sets,
        "uv-sets.gltf",
        Some("materials[0].normalTexture.texCoord"),
        "TEXCOORD_0",
    );

    let no_uv = triangle_doc("no-uv", |bin| {
        let meshes = triangle(bin, "", Some(0));
        let img = data_uri("image/png", &png(1, 1, &[[255; 4]]));
        format!(
            "{meshes},\"nodes\":[{{\"mesh\":0}}],\"textures\":[{{\"source\":0}}],\"images\":[{{\"uri\":\"{img}\"}}],\
             \"materials\":[{{\"pbrMetallicRoughness\":{{\"baseColorTexture\":{{\"index\":0}}}}}}]"
        )
    });
    expect_error(
        no_uv,
        "no-uv.gltf",
        Some("meshes[0].primitives[0].attributes.TEXCOORD_0"),
        "missing",
    );

    let factor = triangle_doc("factor", |bin| {
        let meshes = triangle(bin, "", Some(0));
        format!("{meshes},\"nodes\":[{{\"mesh\":0}}],\"materials\":[{{\"pbrMetallicRoughness\":{{\"roughnessFactor\":1.5}}}}]")
    });
    expect_error(
        factor,
        "factor.gltf",
        Some("materials[0].pbrMetallicRoughness.roughnessFactor"),
        "[0, 1]",
    );
}

#[test]
fn node_cycles_and_bad_transforms() {
    let cycle = triangle_doc("cycle", |bin| {
        let meshes = triangle(bin, "", None);
        format!("{meshes},\"nodes\":[{{\"mesh\":0,\"children\":[1]}},{{\"children\":[0]}}],\"scenes\":[{{\"nodes\":[0]}}]")
    });
    expect_error(cycle, "cycle.gltf", Some("nodes[0]"), "reached twice");

    let zero_quat = triangle_doc("quat", |bin| {
        let meshes = triangle(bin, "", None);
        format!("{meshes},\"nodes\":[{{\"mesh\":0,\"rotation\":[0,0,0,0]}}]")
    });
    expect_error(
        zero_quat,
        "quat.gltf",
        Some("nodes[0].rotation"),
        "unit quaternion",
    );
}

/// Truncating or corrupting a valid GLB anywhere yields a result or an error, never a panic.
#[test]
fn corrupted_glb_never_panics() {
    let mut bin = Bin::new();
    let uv = bin.vec2(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let meshes = triangle(&mut bin, &format!(",\"TEXCOORD_0\":{uv}"), Some(0));
    let view = bin.view(&png(1, 1, &[[9, 99, 199, 255]]), None);
    let rest = format!(
        "{meshes},\"nodes\":[{{\"mesh\":0,\"scale\":[1,2,3]}}],\"materials\":[{{\"normalTexture\":{{\"index\":0}}}}],\
         \"textures\":[{{\"source\":0}}],\"images\":[{{\"bufferView\":{view},\"mimeType\":\"image/png\"}}]"
    );
    let valid = glb(&document(&bin.parts_with_uri(""), &rest), &bin.bytes);
    let dir = temp_dir("fuzz");
    let path = dir.join("fuzz.glb");
    assert!(scenes::gltf::load(&write(&dir, "fuzz.glb", &valid)).is_ok());
    let (mut ok, mut errors) = (0, 0);
    let mut state = 0x9E37_79B9u32;
    for step in 0..600 {
        // xorshift32 picks a byte and a value; every 4th case truncates instead.
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        let at = state as usize % valid.len();
        let bytes = if step % 4 == 0 {
            valid[..at].to_vec()
        } else {
            let mut b = valid.clone();
            b[at] = (state >> 24) as u8;
            b
        };
        std::fs::write(&path, &bytes).unwrap();
        match scenes::gltf::load_with_notes(&path) {
            Ok(_) => ok += 1,
            Err(e) => {
                assert!(e.to_string().contains("fuzz.glb"), "{e}");
                errors += 1;
            }
        }
    }
    println!("corrupted GLBs: {ok} loaded, {errors} rejected");
    assert!(errors > 100, "most corruptions should be caught: {errors} errors");
}
