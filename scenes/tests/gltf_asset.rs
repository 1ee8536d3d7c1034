//! The vendored real asset (scenes/assets/suzanne.glb, see ATTRIBUTION.md) and its original
//! Draco-compressed form (scenes/tests/data/suzanne-draco.glb).

mod gltf_support;

use std::path::PathBuf;

use glam::Vec3;
use gltf_support::*;
use scenes::{Material, Scattering, TexRgb, TexScalar};

fn crate_path(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(rel)
}

#[test]
fn suzanne_loads_with_the_expected_triangles() {
    let start = std::time::Instant::now();
    let loaded = scenes::gltf::load_with_notes(&crate_path("assets/suzanne.glb")).unwrap();
    println!(
        "suzanne.glb loaded in {:.2} ms",
        start.elapsed().as_secs_f64() * 1e3
    );
    assert!(loaded.notes.is_empty(), "{:?}", loaded.notes);
    let scene = &loaded.scene;
    assert_eq!(names(scene), ["mesh/0"]);
    let m = mesh(scene, "mesh/0");
    // Counts from the file's accessors (44,526 indices, 7,503 vertices).
    assert_eq!(m.indices.len(), 14_842);
    assert_eq!(m.positions.len(), 7_503);
    assert_eq!(m.normals.len(), 7_503);
    assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
    // The accessor's min/max (the node has no transform).
    let (lo, hi) = scene.shapes[0].geometry.bounds();
    assert_close(lo, Vec3::new(-0.929_730_1, -0.669_794_8, -0.544_786_3), 1e-6);
    assert_close(hi, Vec3::new(0.929_730_1, 0.668_249_2, 0.576_133_5), 1e-6);
    // "base" has an empty pbrMetallicRoughness: glTF defaults.
    assert_eq!(
        scene.materials,
        vec![Material::MetalRough {
            base_color: TexRgb::Constant(Vec3::ONE),
            metallic: TexScalar::Constant(1.0),
            roughness: TexScalar::Constant(1.0),
            scattering: Scattering::Single,
        }]
    );
    assert!(scene.lights.is_empty() && scene.textures.is_empty());
    // The face looks down +Z (Blender's −Y after the glTF exporter's axis change): the default
    // camera on the +Y/+Z diagonal sees it.
    assert!(scene.camera.position().z > 0.0 && scene.camera.position().y > 0.0);
}

#[test]
fn draco_compressed_original_is_rejected_with_the_fix() {
    let path = crate_path("tests/data/suzanne-draco.glb");
    let err = scenes::load(&path).unwrap_err();
    let text = err.to_string();
    assert_eq!(err.field.as_deref(), Some("extensionsRequired[0]"), "{text}");
    assert!(text.contains("suzanne-draco.glb"), "{text}");
    assert!(text.contains("KHR_draco_mesh_compression"), "{text}");
    assert!(
        text.contains("npx @gltf-transform/cli copy in.glb out.glb"),
        "{text}"
    );
}
