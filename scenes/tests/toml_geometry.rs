//! Shapes from scene files: transform order, rectangle/disk frames, box meshes.

mod toml_support;

use glam::Vec3;
use scenes::{Geometry, Mesh, Scene};
use toml_support::{append, scratch};

/// Loads BASE plus one extra shape table `shape` and returns that shape's geometry.
fn shape(test: &str, shape: &str) -> Geometry {
    let dir = scratch(test);
    let text = append(&format!("[[shape]]\nname = \"x\"\nmaterial = \"m\"\n{shape}\n"));
    let scene: Scene = toml_support::load_text(&dir, &text).unwrap_or_else(|e| panic!("{e}"));
    scene.shapes[1].geometry.clone()
}

fn assert_vec(what: &str, actual: Vec3, expected: Vec3) {
    assert!(
        (actual - expected).abs().max_element() < 1e-5,
        "{what}: expected {expected}, got {actual}"
    );
}

fn sphere(g: &Geometry) -> (Vec3, f32) {
    match g {
        Geometry::Sphere { center, radius } => (*center, *radius),
        other => panic!("expected a sphere, got {other:?}"),
    }
}

fn planar(g: &Geometry) -> (Vec3, Vec3, Vec3) {
    match g {
        Geometry::Rectangle {
            center,
            half_u,
            half_v,
        }
        | Geometry::Disk {
            center,
            half_u,
            half_v,
        } => (*center, *half_u, *half_v),
        other => panic!("expected a rectangle or disk, got {other:?}"),
    }
}

#[test]
fn transforms_apply_in_list_order() {
    let base = "type = \"sphere\"\ncenter = [1, 0, 0]\nradius = 1\n";
    let scale_first = shape(
        "order-a",
        &format!("{base}transform = [{{ scale = 2 }}, {{ translate = [1, 0, 0] }}]"),
    );
    let (c, r) = sphere(&scale_first);
    assert_vec("scale then translate: centre", c, Vec3::new(3.0, 0.0, 0.0));
    assert_eq!(r, 2.0);
    let translate_first = shape(
        "order-b",
        &format!("{base}transform = [{{ translate = [1, 0, 0] }}, {{ scale = 2 }}]"),
    );
    let (c, r) = sphere(&translate_first);
    assert_vec("translate then scale: centre", c, Vec3::new(4.0, 0.0, 0.0));
    assert_eq!(r, 2.0);
    // Rotation then translation of a sphere: rotate (1,0,0) by 90° about +Y → (0,0,−1).
    let rotated = shape(
        "order-c",
        &format!(
            "{base}transform = [{{ rotate = {{ axis = [0, 1, 0], angle = 90 }} }}, \
             {{ translate = [0, 2, 0] }}]"
        ),
    );
    assert_vec(
        "rotate then translate",
        sphere(&rotated).0,
        Vec3::new(0.0, 2.0, -1.0),
    );
    // A 3×4 matrix is the same as the steps it encodes.
    let m = shape(
        "order-d",
        &format!("{base}transform = [{{ matrix = [[2, 0, 0, 1], [0, 2, 0, 0], [0, 0, 2, 0]] }}]"),
    );
    assert_eq!(sphere(&m), sphere(&scale_first));
}

#[test]
fn rotation_is_right_handed() {
    let g = shape(
        "rotate",
        "type = \"rectangle\"\ncenter = [0, 0, 0]\nhalf_u = [1, 0, 0]\nhalf_v = [0, 1, 0]\n\
         transform = [{ rotate = { axis = [0, 1, 0], angle = 90 } }]",
    );
    let (_, u, v) = planar(&g);
    assert_vec("+X rotated 90° about +Y", u, Vec3::NEG_Z);
    assert_vec("+Y is on the axis", v, Vec3::Y);
    assert_vec(
        "the front normal turns from +Z to +X",
        u.cross(v).normalize(),
        Vec3::X,
    );
}

#[test]
fn rectangle_frames_from_size_normal_up() {
    let wall = planar(&shape(
        "frame-a",
        "type = \"rectangle\"\ncenter = [0, 1, 0]\nsize = [4, 2]\nnormal = [0, 0, 1]",
    ));
    assert_vec("wall half_u (width along +X)", wall.1, Vec3::new(2.0, 0.0, 0.0));
    assert_vec(
        "wall half_v (height along +Y, the default up)",
        wall.2,
        Vec3::new(0.0, 1.0, 0.0),
    );
    let floor = planar(&shape(
        "frame-b",
        "type = \"rectangle\"\ncenter = [0, 0, 0]\nsize = [4, 2]\nnormal = [0, 1, 0]",
    ));
    assert_vec("floor half_u", floor.1, Vec3::new(2.0, 0.0, 0.0));
    assert_vec(
        "floor half_v (up defaults to -Z)",
        floor.2,
        Vec3::new(0.0, 0.0, -1.0),
    );
    assert_vec("floor front", floor.1.cross(floor.2).normalize(), Vec3::Y);
    let tilted = planar(&shape(
        "frame-c",
        "type = \"rectangle\"\ncenter = [0, 0, 0]\nsize = [2, 2]\nnormal = [1, 1, 0]\nup = [0, 0, 1]",
    ));
    assert_vec(
        "tilted front",
        tilted.1.cross(tilted.2).normalize(),
        Vec3::new(1.0, 1.0, 0.0).normalize(),
    );
    assert_vec("tilted half_v follows up", tilted.2, Vec3::Z);
    let disk = planar(&shape(
        "frame-d",
        "type = \"disk\"\ncenter = [0, 2, 0]\nradius = 0.5\nnormal = [0, -1, 0]",
    ));
    assert_eq!((disk.1.length(), disk.2.length()), (0.5, 0.5));
    assert_vec("disk front", disk.1.cross(disk.2).normalize(), Vec3::NEG_Y);
    assert!(matches!(
        shape(
            "frame-e",
            "type = \"disk\"\ncenter = [0, 2, 0]\nradius = 0.5\nnormal = [0, -1, 0]"
        ),
        Geometry::Disk { .. }
    ));
}

#[test]
fn mirroring_keeps_the_front_side() {
    // Mirror a floor (front +Y) through the XZ plane: its front must become −Y.
    let g = shape(
        "mirror",
        "type = \"rectangle\"\ncenter = [0, 1, 0]\nsize = [2, 2]\nnormal = [0, 1, 0]\n\
         transform = [{ scale = [1, -1, 1] }]",
    );
    let (c, u, v) = planar(&g);
    assert_vec("mirrored centre", c, Vec3::new(0.0, -1.0, 0.0));
    assert_vec("mirrored front", u.cross(v).normalize(), Vec3::NEG_Y);
}

fn mesh(g: &Geometry) -> &Mesh {
    match g {
        Geometry::Mesh(m) => m,
        other => panic!("expected a mesh, got {other:?}"),
    }
}

/// Every triangle of a closed convex mesh faces away from `inside`; returns the face normals.
fn assert_outward(what: &str, m: &Mesh, inside: Vec3) -> Vec<Vec3> {
    assert_eq!(m.indices.len(), 12, "{what}: triangle count");
    m.indices
        .iter()
        .map(|&[a, b, c]| {
            let [p0, p1, p2] = [a, b, c].map(|i| m.positions[i as usize]);
            let n = (p1 - p0).cross(p2 - p0);
            let centroid = (p0 + p1 + p2) / 3.0;
            assert!(
                n.dot(centroid - inside) > 0.0,
                "{what}: triangle {p0} {p1} {p2} has normal {n}, pointing inwards"
            );
            n.normalize()
        })
        .collect()
}

#[test]
fn box_mesh_faces_point_outward() {
    let g = shape("box-a", "type = \"box\"\ncenter = [1, 2, 3]\nsize = [2, 4, 6]");
    let m = mesh(&g);
    let normals = assert_outward("axis-aligned box", m, Vec3::new(1.0, 2.0, 3.0));
    for axis in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z] {
        let k = normals.iter().filter(|n| n.dot(axis) > 0.9999).count();
        assert_eq!(k, 2, "two triangles face {axis}");
    }
    let area: f32 = m
        .indices
        .iter()
        .map(|&[a, b, c]| {
            let [p0, p1, p2] = [a, b, c].map(|i| m.positions[i as usize]);
            (p1 - p0).cross(p2 - p0).length() / 2.0
        })
        .sum();
    assert!(
        (area - 88.0).abs() < 1e-4,
        "surface area: expected 2·(8 + 24 + 12) = 88, got {area}"
    );
    assert!(m.normals.is_empty(), "flat shading: no vertex normals");
    assert_eq!((m.positions.len(), m.uvs.len()), (24, 24));
    assert_eq!(g.bounds(), (Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 4.0, 6.0)));

    let rotated = shape(
        "box-b",
        "type = \"box\"\ncenter = [0, 0.5, 0]\nsize = [1, 1, 2]\n\
         transform = [{ rotate = { axis = [1, 1, 0], angle = 33 } }, { translate = [5, 0, 0] }]",
    );
    let inside = glam::Affine3A::from_translation(Vec3::new(5.0, 0.0, 0.0))
        * glam::Affine3A::from_axis_angle(Vec3::new(1.0, 1.0, 0.0).normalize(), 33f32.to_radians());
    assert_outward(
        "rotated box",
        mesh(&rotated),
        inside.transform_point3(Vec3::new(0.0, 0.5, 0.0)),
    );
    // A mirroring transform reverses the winding back so the faces still point outward.
    let mirrored = shape(
        "box-c",
        "type = \"box\"\ncenter = [1, 0, 0]\nsize = [1, 2, 3]\ntransform = [{ scale = [-1, 1, 1] }]",
    );
    assert_outward("mirrored box", mesh(&mirrored), Vec3::new(-1.0, 0.0, 0.0));
}

#[test]
fn sphere_takes_similarities() {
    let g = shape(
        "sphere-sim",
        "type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 0.5\n\
         transform = [{ rotate = { axis = [0, 0, 1], angle = 30 } }, { scale = [-3, 3, 3] }, \
         { translate = [0, 1, 0] }]",
    );
    let (c, r) = sphere(&g);
    assert_vec("centre", c, Vec3::Y);
    assert!((r - 1.5).abs() < 1e-6, "radius: expected 1.5, got {r}");
}

/// An icosphere is a closed mesh of 20·4^s triangles on the sphere, with the sphere's own
/// normals at its vertices (or none: faceted), mapped by any transform; subdivisions beyond
/// the limit and a normal map (it has no uvs) are errors at their fields.
#[test]
fn icosphere_is_a_closed_tessellated_sphere() {
    let g = shape(
        "ico-a",
        "type = \"icosphere\"\ncenter = [1, 2, 3]\nradius = 0.5\nsubdivisions = 2",
    );
    let m = mesh(&g);
    let c = Vec3::new(1.0, 2.0, 3.0);
    assert_eq!((m.indices.len(), m.positions.len()), (320, 162));
    assert!(m.uvs.is_empty());
    for (p, n) in m.positions.iter().zip(&m.normals) {
        assert!(
            ((*p - c).length() - 0.5).abs() < 1e-5,
            "vertex {p} off the sphere"
        );
        assert_vec("vertex normal", *n, (*p - c) / 0.5);
    }
    for &[a, b, k] in &m.indices {
        let [p0, p1, p2] = [a, b, k].map(|i| m.positions[i as usize]);
        assert!(
            (p1 - p0).cross(p2 - p0).dot(p0 + p1 + p2 - 3.0 * c) > 0.0,
            "a face points inward"
        );
    }
    let faceted = shape(
        "ico-b",
        "type = \"icosphere\"\ncenter = [0, 0, 0]\nradius = 1\nsubdivisions = 0\nnormals = \"face\"\n\
         transform = [{ scale = [-2, 1, 1] }]",
    );
    let f = mesh(&faceted);
    assert!(f.normals.is_empty() && f.indices.len() == 20);
    for &[a, b, k] in &f.indices {
        let [p0, p1, p2] = [a, b, k].map(|i| f.positions[i as usize]);
        assert!(
            (p1 - p0).cross(p2 - p0).dot(p0 + p1 + p2) > 0.0,
            "mirrored: a face points inward"
        );
    }
    let dir = toml_support::scratch("ico-bad");
    for (extra, want) in [
        ("subdivisions = 8", "subdivisions"),
        ("subdivisions = 1\nnormals = \"smooth\"", "normals"),
        (
            "subdivisions = 1\nnormal_map = { texture = \"n.png\" }",
            "no texture coordinates",
        ),
    ] {
        let text = toml_support::append(&format!(
            "[[shape]]\nname = \"x\"\nmaterial = \"m\"\ntype = \"icosphere\"\ncenter = [0, 0, 0]\nradius = 1\n{extra}\n"
        ));
        toml_support::expect_error(toml_support::load_text(&dir, &text), &[want]);
    }
}

/// A generated mesh whose sides vanish in f32 where it stands (found by the hostile-input
/// mutations: a 5 mm box moved 4.3·10⁹ m out) is an error at its size field, not a mesh of
/// zero area that the renderers would refuse later without a line.
#[test]
fn a_box_too_small_for_its_position_is_an_error() {
    let dir = toml_support::scratch("box-collapsed");
    for (shape, want) in [
        (
            "type = \"box\"\ncenter = [4294967296, 4294967296, 4294967296]\nsize = [0.02, 0.005, 0.02]",
            "field `shape \"x\".size`",
        ),
        (
            "type = \"icosphere\"\ncenter = [4294967296, 4294967296, 4294967296]\nradius = 0.001\nsubdivisions = 1",
            "field `shape \"x\".radius`",
        ),
    ] {
        let text = toml_support::append(&format!("[[shape]]\nname = \"x\"\nmaterial = \"m\"\n{shape}\n"));
        toml_support::expect_error(toml_support::load_text(&dir, &text), &[want, "zero area"]);
    }
}
