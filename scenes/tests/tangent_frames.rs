//! Generated tangent frames (`scenes::tangent::generate`, Lengyel 2001 / Mikkelsen 2008)
//! on a UV sphere and a cylinder against their analytic frames: the tangent along ∂p/∂u,
//! orthogonal to the normal, and the handedness w that makes w·(n × t) point along −∂p/∂v
//! (glTF's bitangent: up in the image, where v = 0 is the top row).
//!
//! Bounds. Both meshes triangulate quads of constant u and v lines, so every triangle's T
//! is a chord of a parallel: horizontal, and the tangent of the parallel at the chord's
//! middle, half a column (Δφ/2) from the vertex. A vertex's summed T is therefore horizontal
//! and off ∂p/∂φ by an angle δ, |δ| ≤ Δφ/2, δ = 0 where the columns on both sides carry equal
//! weight, |δ| = Δφ/2 at the seam (vertices split at u = 0 and u = 1 see one side only).
//! Gram–Schmidt against the exact normal n = sin θ·e_r + cos θ·Y keeps the ∂p/∂φ part and
//! scales the radial part by |cos θ|, so the angle error is atan(tan δ·|cos θ|): zero on the
//! cylinder (θ = π/2 everywhere) and the sphere's equator, at most atan(tan(Δφ/2)·|cos θ|)
//! elsewhere, and exactly that at the sphere's seam. The tests check all three.

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3, Vec4};
use scenes::tangent::generate;

/// A mesh of revolution around +Y: `columns` × `rows` quads, vertex (i, j) at
/// φ = 2π·i/columns, v = j/rows, placed by `at(φ, v)` = (position, unit normal); u = i/columns
/// (or 1 − that when `mirror_u`). Quads are two triangles, counter-clockwise from outside.
struct Revolution {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    triangles: Vec<[u32; 3]>,
    /// φ of each vertex.
    phi: Vec<f32>,
}

fn revolution(columns: u32, rows: u32, mirror_u: bool, at: impl Fn(f32, f32) -> (Vec3, Vec3)) -> Revolution {
    let mut m = Revolution {
        positions: Vec::new(),
        normals: Vec::new(),
        uvs: Vec::new(),
        triangles: Vec::new(),
        phi: Vec::new(),
    };
    for j in 0..=rows {
        for i in 0..=columns {
            let (u, v) = (i as f32 / columns as f32, j as f32 / rows as f32);
            let (p, n) = at(TAU * u, v);
            m.positions.push(p);
            m.normals.push(n);
            m.uvs.push(Vec2::new(if mirror_u { 1.0 - u } else { u }, v));
            m.phi.push(TAU * u);
        }
    }
    let row = columns + 1;
    for j in 0..rows {
        for i in 0..columns {
            let (a, b, c, d) = (
                j * row + i,
                j * row + i + 1,
                (j + 1) * row + i,
                (j + 1) * row + i + 1,
            );
            m.triangles.push([a, c, b]);
            m.triangles.push([b, c, d]);
        }
    }
    m
}

/// Unit ∂p/∂φ of a surface of revolution around +Y with p = (r·cos φ, y, −r·sin φ).
fn dp_dphi(phi: f32) -> Vec3 {
    Vec3::new(-phi.sin(), 0.0, -phi.cos())
}

/// Angle in degrees between two directions.
fn angle_deg(a: Vec3, b: Vec3) -> f32 {
    a.normalize()
        .dot(b.normalize())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

/// Angle in degrees between the generated tangent `t[k]` of `m` and `sign`·∂p/∂φ, after
/// checking that it is unit, orthogonal to the normal, of handedness `w`, and that the
/// bitangent w·(n × t) points up (along −∂p/∂v).
fn frame_error(m: &Revolution, t: &[Vec4], k: usize, sign: f32, w: f32) -> f32 {
    let n = m.normals[k];
    let dir = t[k].truncate();
    assert!(
        (dir.length() - 1.0).abs() < 1e-5,
        "vertex {k}: tangent {dir} not unit"
    );
    assert!(
        dir.dot(n).abs() < 1e-5,
        "vertex {k}: tangent {dir} not orthogonal to {n}"
    );
    assert_eq!(t[k].w, w, "vertex {k}: handedness");
    let b = n.cross(dir) * t[k].w;
    assert!(b.y > 0.0, "vertex {k}: bitangent {b} does not point along −∂p/∂v");
    angle_deg(dir, dp_dphi(m.phi[k]) * sign)
}

/// Slack on the bounds: f32 rounding of the chords and of Gram–Schmidt.
const BOUND_DEG: f32 = 0.05;

#[test]
fn uv_sphere_frames_match_the_analytic_frame() {
    let (columns, rows) = (32, 16);
    // θ = π·v from the north pole (v = 0, the top row): p = (sin θ cos φ, cos θ, −sin θ sin φ).
    let sphere = |mirror| {
        revolution(columns, rows, mirror, |phi, v| {
            let theta = PI * v;
            let d = Vec3::new(theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin());
            (d * 2.0, d)
        })
    };
    let row = (columns + 1) as usize;
    let half_column = PI / columns as f32;
    // The bound of the module header at vertex k (θ from its row).
    let bound = |k: usize| {
        let theta = PI * (k / row) as f32 / rows as f32;
        (half_column.tan() * theta.cos().abs()).atan().to_degrees()
    };
    for mirror in [false, true] {
        let (sign, w) = if mirror { (-1.0, -1.0) } else { (1.0, 1.0) };
        let m = sphere(mirror);
        let t = generate(&m.positions, &m.normals, &m.uvs, &m.triangles);
        let (mut seam_gap, mut equator) = (0.0f32, 0.0f32);
        // Every vertex but the poles (rows 0 and `rows`, where ∂p/∂φ = 0).
        for k in row..row * rows as usize {
            let err = frame_error(&m, &t, k, sign, w);
            assert!(err <= bound(k) + BOUND_DEG, "vertex {k}: {err}° > {}°", bound(k));
            if k % row == 0 || k % row == columns as usize {
                seam_gap = seam_gap.max(bound(k) - err);
            }
            if k / row == rows as usize / 2 {
                equator = equator.max(err);
            }
        }
        println!("sphere (mirrored u: {mirror}): equator error {equator:.2e}°, seam within {seam_gap:.2e}° of the bound");
        assert!(equator < BOUND_DEG, "equator {equator}°");
        assert!(
            seam_gap < BOUND_DEG,
            "the seam is {seam_gap}° below the bound it should reach"
        );
    }
}

#[test]
fn cylinder_frames_match_the_analytic_frame() {
    // Radius 0.5, y from 1 (v = 0, top) down to −1.
    let cylinder = |mirror| {
        revolution(24, 6, mirror, |phi, v| {
            let n = Vec3::new(phi.cos(), 0.0, -phi.sin());
            (n * 0.5 + Vec3::Y * (1.0 - 2.0 * v), n)
        })
    };
    for mirror in [false, true] {
        let (sign, w) = if mirror { (-1.0, -1.0) } else { (1.0, 1.0) };
        let m = cylinder(mirror);
        let t = generate(&m.positions, &m.normals, &m.uvs, &m.triangles);
        let worst = (0..m.positions.len())
            .map(|k| frame_error(&m, &t, k, sign, w))
            .fold(0.0f32, f32::max);
        println!("cylinder (mirrored u: {mirror}): worst tangent error {worst:.2e}°");
        assert!(worst < BOUND_DEG, "{worst}°");
    }
}

/// A vertex sums its triangles' unnormalised T (Lengyel 2001): two triangles of the plane
/// z = 0 sharing vertex 0, one mapped with ∂p/∂u = +X (length 1), the other with ∂p/∂u = +Y
/// (length 2), give T ∝ X + 2Y there, and each other vertex its own triangle's T.
#[test]
fn shared_vertex_sums_its_triangles() {
    let p = [
        Vec3::ZERO,
        Vec3::X,
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::Y * 2.0,
    ];
    let n = [Vec3::Z; 5];
    // Triangle A (0, 1, 2): u = x, v = −y. Triangle B (0, 3, 4): u = y/2, v = x.
    let uv = [
        Vec2::ZERO,
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 1.0),
        Vec2::new(0.0, -1.0),
        Vec2::new(1.0, 0.0),
    ];
    let t = generate(&p, &n, &uv, &[[0, 1, 2], [0, 3, 4]]);
    let expected = (Vec3::X + Vec3::Y * 2.0).normalize();
    assert!(
        angle_deg(t[0].truncate(), expected) < 1e-4,
        "shared vertex: {}",
        t[0]
    );
    assert!(angle_deg(t[1].truncate(), Vec3::X) < 1e-4 && angle_deg(t[4].truncate(), Vec3::Y) < 1e-4);
    // A: B = −∂p/∂v = +Y, (Z × X)·Y > 0: w = +1. B: B = −∂p/∂v = −X, (Z × Y)·(−X) > 0: w = +1.
    assert_eq!((t[1].w, t[4].w), (1.0, 1.0));
}

#[test]
fn missing_attributes_and_degenerate_uvs() {
    let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let n = [Vec3::Z; 3];
    // Without uvs there is nothing to generate from.
    assert!(generate(&p, &n, &[], &[[0, 1, 2]]).is_empty());
    // A degenerate uv mapping and out-of-range indices contribute nothing: an arbitrary unit
    // tangent of the normal, w = +1.
    let uv = [Vec2::ZERO; 3];
    for t in generate(&p, &n, &uv, &[[0, 1, 2], [0, 1, 7]]) {
        assert!(t.truncate().dot(Vec3::Z).abs() < 1e-6 && (t.truncate().length() - 1.0).abs() < 1e-6);
        assert_eq!(t.w, 1.0);
    }
    // One flat triangle with u along +X and v down along −Y: T = +X, w = +1 (B = +Y).
    let uv = [Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 0.0)];
    for t in generate(&p, &n, &uv, &[[0, 1, 2]]) {
        assert!((t - Vec4::new(1.0, 0.0, 0.0, 1.0)).length() < 1e-6, "{t}");
    }
}
