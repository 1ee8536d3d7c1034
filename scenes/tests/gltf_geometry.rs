//! glTF geometry: node transform composition (TRS and matrix), mirroring transforms,
//! indexed/non-indexed primitives, quantized and sparse accessors, tangents, naming and
//! the default camera.

mod gltf_support;

use glam::{Vec3, Vec4};
use gltf_support::*;

/// p ↦ world for the hierarchy used below, computed by hand:
/// child = T(0,0,1)·S(3,1,1); parent = T(1,2,3)·R_y(90°)·S(2); R_y(90°): (x,y,z) → (z,y,−x).
fn expected_world(p: Vec3) -> Vec3 {
    let child = Vec3::new(3.0 * p.x, p.y, p.z + 1.0);
    let scaled = child * 2.0;
    let rotated = Vec3::new(scaled.z, scaled.y, -scaled.x);
    rotated + Vec3::new(1.0, 2.0, 3.0)
}

#[test]
fn trs_parent_and_matrix_child_compose_into_world_space() {
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    // Column-major: scale x by 3, translate z by 1.
    let matrix = "[3,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]";
    let nodes = format!(
        "\"nodes\":[{{\"name\":\"parent\",\"translation\":[1,2,3],\"rotation\":[0,{s},0,{s}],\"scale\":[2,2,2],\"children\":[1]}},\
         {{\"name\":\"child\",\"matrix\":{matrix},\"mesh\":0}}],\"scenes\":[{{\"nodes\":[0]}}],\"scene\":0"
    );
    let scene = load_json("compose", &document(&bin.parts(), &format!("{meshes},{nodes}"))).unwrap();
    assert_eq!(names(&scene), ["child/0"]);
    let m = mesh(&scene, "child/0");
    let local = [Vec3::ZERO, Vec3::X, Vec3::Y];
    for (p, q) in local.iter().zip(&m.positions) {
        assert_close(*q, expected_world(*p), 1e-5);
    }
    // Linear part A = R_y(90°)·diag(6, 2, 2): A⁻ᵀ·(0,0,1) ∝ R_y·(0,0,½) = (½,0,0) → +X.
    for n in &m.normals {
        assert_close(*n, Vec3::X, 1e-6);
    }
    // Positive determinant: winding kept, and the geometric normal agrees with the shading one.
    assert_eq!(m.indices, vec![[0, 1, 2]]);
    let [a, b, c] = m.indices[0].map(|i| m.positions[i as usize]);
    assert!((b - a).cross(c - a).dot(Vec3::X) > 0.0);
}

/// A mesh with a normal map, uvs and TANGENT under `node_transform`.
fn mapped_triangle(tag: &str, node_transform: &str, tangent: bool) -> scenes::Scene {
    let mut bin = Bin::new();
    let uv = bin.vec2(&[[0.0, 1.0], [1.0, 1.0], [0.0, 0.0]]);
    let extra = if tangent {
        let tan = bin.vec4(&[[1.0, 0.0, 0.0, 1.0]; 3]);
        format!(",\"TEXCOORD_0\":{uv},\"TANGENT\":{tan}")
    } else {
        format!(",\"TEXCOORD_0\":{uv}")
    };
    let meshes = triangle(&mut bin, &extra, Some(0));
    let img = data_uri("image/png", &png(1, 1, &[[128, 128, 255, 255]]));
    let rest = format!(
        "{meshes},\"materials\":[{{\"normalTexture\":{{\"index\":0}}}}],\"textures\":[{{\"source\":0}}],\
         \"images\":[{{\"uri\":\"{img}\"}}],\"nodes\":[{{\"mesh\":0{node_transform}}}]"
    );
    load_json(tag, &document(&bin.parts(), &rest)).unwrap()
}

#[test]
fn mirroring_scale_flips_winding_and_tangent_handedness() {
    for (tag, transform) in [
        ("mirror-trs", ",\"scale\":[-1,1,1]"),
        (
            "mirror-matrix",
            ",\"matrix\":[-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]",
        ),
    ] {
        let scene = mapped_triangle(tag, transform, true);
        let m = mesh(&scene, "tri/0");
        assert_eq!(
            m.indices,
            vec![[0, 2, 1]],
            "{tag}: winding must flip under det < 0"
        );
        let [a, b, c] = m.indices[0].map(|i| m.positions[i as usize]);
        let geometric = (b - a).cross(c - a).normalize();
        assert_close(geometric, Vec3::Z, 1e-6);
        for (n, t) in m.normals.iter().zip(&m.tangents) {
            assert_close(*n, Vec3::Z, 1e-6);
            // t' = A·(1,0,0) = (−1,0,0), w' = +1·sign(det) = −1; bitangent (n × t)·w stays +Y = A·(+Y).
            assert_eq!(*t, Vec4::new(-1.0, 0.0, 0.0, -1.0), "{tag}");
            assert_close(n.cross(t.truncate()) * t.w, Vec3::Y, 1e-6);
        }
    }
}

#[test]
fn generated_tangents_follow_gltf_uv_orientation() {
    // uv = (x, 1 − y): u grows to +X, v grows downwards (glTF's image convention), so the
    // normal map's green axis (up in the image) is +Y: tangent +X with w = +1.
    let scene = mapped_triangle("tangent-gen", "", false);
    let m = mesh(&scene, "tri/0");
    assert_eq!(m.tangents.len(), 3);
    for t in &m.tangents {
        assert_eq!(*t, Vec4::new(1.0, 0.0, 0.0, 1.0));
    }
    // Mirrored uvs (u = 1 − x): tangent −X, and w = −1 keeps the bitangent at +Y.
    let mut bin = Bin::new();
    let uv = bin.vec2(&[[1.0, 1.0], [0.0, 1.0], [1.0, 0.0]]);
    let meshes = triangle(&mut bin, &format!(",\"TEXCOORD_0\":{uv}"), Some(0));
    let img = data_uri("image/png", &png(1, 1, &[[128, 128, 255, 255]]));
    let rest = format!(
        "{meshes},\"materials\":[{{\"normalTexture\":{{\"index\":0}}}}],\"textures\":[{{\"source\":0}}],\
         \"images\":[{{\"uri\":\"{img}\"}}],\"nodes\":[{{\"mesh\":0}}]"
    );
    let scene = load_json("tangent-mirrored-uv", &document(&bin.parts(), &rest)).unwrap();
    for t in &mesh(&scene, "tri/0").tangents {
        assert_eq!(*t, Vec4::new(-1.0, 0.0, 0.0, -1.0));
    }
}

#[test]
fn non_indexed_primitive_without_normals_is_flat() {
    let mut bin = Bin::new();
    let pos = bin.vec3(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
    ]);
    let rest = format!(
        "\"meshes\":[{{\"name\":\"pair\",\"primitives\":[{{\"attributes\":{{\"POSITION\":{pos}}}}}]}}],\"nodes\":[{{\"mesh\":0}}]"
    );
    let scene = load_json("non-indexed", &document(&bin.parts(), &rest)).unwrap();
    let m = mesh(&scene, "pair/0");
    assert_eq!(m.indices, vec![[0, 1, 2], [3, 4, 5]]);
    assert!(m.normals.is_empty() && m.uvs.is_empty() && m.tangents.is_empty());
}

#[test]
fn normal_map_without_normals_unwelds_to_face_normals() {
    let mut bin = Bin::new();
    // Two triangles sharing the edge p0–p1, folded 90° along it: faces +Z and +X.
    let pos = bin.vec3(&[
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 0.0, -1.0],
    ]);
    let uv = bin.vec2(&[[0.0, 1.0], [0.0, 0.0], [1.0, 1.0], [1.0, 1.0]]);
    let idx = bin.indices(&[0, 2, 1, 0, 3, 1]);
    let img = data_uri("image/png", &png(1, 1, &[[128, 128, 255, 255]]));
    let rest = format!(
        "\"meshes\":[{{\"name\":\"fold\",\"primitives\":[{{\"attributes\":{{\"POSITION\":{pos},\"TEXCOORD_0\":{uv}}},\"indices\":{idx},\"material\":0}}]}}],\
         \"materials\":[{{\"normalTexture\":{{\"index\":0,\"scale\":0.5}}}}],\"textures\":[{{\"source\":0}}],\
         \"images\":[{{\"uri\":\"{img}\"}}],\"nodes\":[{{\"mesh\":0}}]"
    );
    let scene = load_json("unweld", &document(&bin.parts(), &rest)).unwrap();
    let m = mesh(&scene, "fold/0");
    assert_eq!(m.positions.len(), 6, "each triangle gets its own corners");
    assert_eq!(m.indices, vec![[0, 1, 2], [3, 4, 5]]);
    for k in 0..3 {
        assert_close(m.normals[k], Vec3::Z, 1e-6);
        assert_close(m.normals[3 + k], Vec3::X, 1e-6);
    }
    assert_eq!(m.tangents.len(), 6);
    for (n, t) in m.normals.iter().zip(&m.tangents) {
        assert!(n.dot(t.truncate()).abs() < 1e-6, "tangent {t} not ⟂ normal {n}");
    }
    assert_eq!(scene.shapes[0].normal_map.as_ref().map(|n| n.scale), Some(0.5));
}

#[test]
fn quantized_positions_and_normals_decode_with_the_node_scale() {
    let mut bin = Bin::new();
    // Unnormalized u16 positions scaled by the node (KHR_mesh_quantization's dequantisation).
    let pos: Vec<u8> = [0u16, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let pv = bin.view(&pos, Some(8));
    let pa = bin.accessor(format!(
        "{{\"bufferView\":{pv},\"componentType\":5123,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[2,2,0]}}"
    ));
    // Normalized i8 normals (0, 0, 127) → (0, 0, 1), padded to 4 bytes per vertex.
    let nv = bin.view(&[0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0], Some(4));
    let na = bin.accessor(format!(
        "{{\"bufferView\":{nv},\"componentType\":5120,\"normalized\":true,\"count\":3,\"type\":\"VEC3\"}}"
    ));
    let rest = format!(
        "\"extensionsUsed\":[\"KHR_mesh_quantization\"],\"extensionsRequired\":[\"KHR_mesh_quantization\"],\
         \"meshes\":[{{\"name\":\"q\",\"primitives\":[{{\"attributes\":{{\"POSITION\":{pa},\"NORMAL\":{na}}}}}]}}],\
         \"nodes\":[{{\"mesh\":0,\"scale\":[0.5,0.5,0.5]}}]"
    );
    let scene = load_json("quantized", &document(&bin.parts(), &rest)).unwrap();
    let m = mesh(&scene, "q/0");
    assert_eq!(m.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
    assert_eq!(m.normals, vec![Vec3::Z; 3]);
}

#[test]
fn sparse_accessor_substitutes_values() {
    let mut bin = Bin::new();
    let floats = |v: &[f32]| -> Vec<u8> { v.iter().flat_map(|x| x.to_le_bytes()).collect() };
    let base = bin.view(&floats(&[0.0, 0.0, 0.0, 9.0, 9.0, 9.0, 0.0, 1.0, 0.0]), None);
    let iv = bin.view(&1u16.to_le_bytes(), None);
    let vv = bin.view(&floats(&[1.0, 0.0, 0.0]), None);
    let sparse = bin.accessor(format!(
        "{{\"bufferView\":{base},\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0],\
         \"sparse\":{{\"count\":1,\"indices\":{{\"bufferView\":{iv},\"componentType\":5123}},\"values\":{{\"bufferView\":{vv}}}}}}}"
    ));
    let rest = format!(
        "\"meshes\":[{{\"name\":\"s\",\"primitives\":[{{\"attributes\":{{\"POSITION\":{sparse}}}}}]}}],\"nodes\":[{{\"mesh\":0}}]"
    );
    let scene = load_json("sparse", &document(&bin.parts(), &rest)).unwrap();
    assert_eq!(mesh(&scene, "s/0").positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
}

#[test]
fn instances_get_unique_names_and_share_materials() {
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let rest = format!(
        "{meshes},\"nodes\":[{{\"mesh\":0}},{{\"mesh\":0,\"translation\":[5,0,0]}},{{\"name\":\"named\",\"mesh\":0}}],\
         \"scenes\":[{{\"nodes\":[0,1,2]}}]"
    );
    let scene = load_json("instances", &document(&bin.parts(), &rest)).unwrap();
    assert_eq!(names(&scene), ["tri/0", "tri/0#2", "named/0"]);
    assert_eq!(scene.materials.len(), 1, "the default material is built once");
    assert_close(
        mesh(&scene, "tri/0#2").positions[1],
        Vec3::new(6.0, 0.0, 0.0),
        0.0,
    );
}

#[test]
fn default_camera_frames_the_bounds_from_the_y_z_diagonal() {
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let rest = format!("{meshes},\"nodes\":[{{\"mesh\":0,\"scale\":[4,2,1]}}]");
    let scene = load_json("default-camera", &document(&bin.parts(), &rest)).unwrap();
    assert_eq!((scene.film.width, scene.film.height), (512, 512));
    assert_eq!(scene.camera.fov_y_deg, 40.0);
    let (center, radius) = scene.bounding_sphere();
    let eye = scene.camera.position();
    let towards = (eye - center).normalize();
    assert_close(towards, Vec3::new(0.0, 1.0, 1.0).normalize(), 1e-5);
    assert_close(scene.camera.forward(), -towards, 1e-5);
    // The bounding sphere touches the vertical field of view: sin(20°) = r / distance.
    let half = (eye - center).length().recip() * radius;
    assert!(
        (half.asin().to_degrees() - 20.0).abs() < 1e-3,
        "half-angle {}",
        half.asin().to_degrees()
    );
    assert!(scene.lights.is_empty(), "a glTF without lights adds none");
}

#[test]
fn placement_transform_applies_above_the_root_nodes() {
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let lights = "\"extensionsUsed\":[\"KHR_lights_punctual\"],\
        \"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":\"point\"}]}}";
    let rest = format!(
        "{meshes},{lights},\"nodes\":[{{\"mesh\":0,\"translation\":[1,0,0]}},\
         {{\"translation\":[0,1,0],\"extensions\":{{\"KHR_lights_punctual\":{{\"light\":0}}}}}}]"
    );
    let dir = temp_dir("placement");
    let path = write(&dir, "placed.gltf", document(&bin.parts(), &rest));
    // Mirror x, then move by (0, 0, 5): p ↦ (−x, y, z + 5).
    let to_world = glam::Mat4::from_translation(Vec3::new(0.0, 0.0, 5.0))
        * glam::Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    let loaded = scenes::gltf::load_transformed(&path, to_world).unwrap();
    let m = mesh(&loaded.scene, "tri/0");
    let want = [
        Vec3::new(-1.0, 0.0, 5.0),
        Vec3::new(-2.0, 0.0, 5.0),
        Vec3::new(-1.0, 1.0, 5.0),
    ];
    for (got, want) in m.positions.iter().zip(want) {
        assert_close(*got, want, 1e-6);
    }
    assert_eq!(
        m.indices,
        vec![[0, 2, 1]],
        "mirroring placement flips the winding"
    );
    let scenes::Light::Point { position, .. } = &loaded.scene.lights[0] else {
        panic!("{:?}", loaded.scene.lights);
    };
    assert_close(*position, Vec3::new(0.0, 1.0, 5.0), 1e-6);
}

#[test]
fn normals_use_the_inverse_transpose_under_shear() {
    // Parent scale (1, 3, 1) above a child rotated 45° about X: A = S·R shears the triangle's
    // plane, so A·n ≠ A⁻ᵀ·n; only the latter stays perpendicular to the transformed surface.
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let (s, c) = 22.5f32.to_radians().sin_cos();
    let nodes = format!(
        "\"nodes\":[{{\"scale\":[1,3,1],\"children\":[1]}},{{\"name\":\"tilted\",\"rotation\":[{s},0,0,{c}],\"mesh\":0}}],\
         \"scenes\":[{{\"nodes\":[0]}}]"
    );
    let scene = load_json("shear", &document(&bin.parts(), &format!("{meshes},{nodes}"))).unwrap();
    let m = mesh(&scene, "tilted/0");
    let [a, b, c] = m.indices[0].map(|i| m.positions[i as usize]);
    let geometric = (b - a).cross(c - a).normalize();
    // By hand: A⁻ᵀ·(0,0,1) = S⁻¹·R·(0,0,1) ∝ (0, −sin45°/3, cos45°).
    let by_hand = Vec3::new(0.0, -1.0 / 3.0, 1.0).normalize();
    assert_close(geometric, by_hand, 1e-6);
    for n in &m.normals {
        assert_close(*n, by_hand, 1e-6);
    }
}

/// TEXCOORD_1 is read as the mesh's light-map chart (`Mesh::uv1`) whatever set the material
/// samples, and checked like every attribute (count, finite).
#[test]
fn texcoord_1_is_the_light_map_chart() {
    let mut bin = Bin::new();
    let uv0 = bin.vec2(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let uv1 = bin.vec2(&[[0.25, 0.25], [0.75, 0.25], [0.25, 0.75]]);
    let meshes = triangle(
        &mut bin,
        &format!(",\"TEXCOORD_0\":{uv0},\"TEXCOORD_1\":{uv1}"),
        None,
    );
    let rest = format!("{meshes},\"nodes\":[{{\"mesh\":0}}]");
    let scene = load_json("uv1", &document(&bin.parts(), &rest)).unwrap();
    let m = mesh(&scene, "tri/0");
    assert_eq!(
        m.uv1,
        [[0.25, 0.25], [0.75, 0.25], [0.25, 0.75]].map(glam::Vec2::from)
    );
    assert_eq!(m.uvs[1], glam::Vec2::X);
    let mut bin = Bin::new();
    let short = bin.vec2(&[[0.25, 0.25], [0.75, 0.25]]);
    let meshes = triangle(&mut bin, &format!(",\"TEXCOORD_1\":{short}"), None);
    let rest = format!("{meshes},\"nodes\":[{{\"mesh\":0}}]");
    let e = load_json("uv1-short", &document(&bin.parts(), &rest))
        .unwrap_err()
        .to_string();
    assert!(e.contains("TEXCOORD_1"), "{e}");
}
