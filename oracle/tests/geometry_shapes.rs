//! Ray hits on each analytic shape and on meshes against hand-computed t, p, normals, uv and
//! tangents; normal maps and the bitangent convention.

mod geometry_util;

use std::f32::consts::FRAC_1_SQRT_2;
use std::sync::Arc;

use geometry_util::{mesh_shape, scene, shape};
use glam::{Vec2, Vec3, Vec4};
use oracle::geometry::{Accel, Ray, SurfaceHit};
use scenes::texture::Texture;
use scenes::{Geometry, Mesh, NormalMap, Scene, WrapMode};

/// Closest hit, failing the test with the ray when there is none.
fn hit(accel: &Accel, origin: Vec3, dir: Vec3) -> SurfaceHit {
    let ray = Ray::new(origin, dir.normalize());
    accel
        .intersect(&ray, f32::INFINITY)
        .unwrap_or_else(|| panic!("expected a hit for {ray:?}"))
}

fn close3(name: &str, expected: Vec3, actual: Vec3, tol: f32) {
    assert!(
        (expected - actual).length() <= tol,
        "{name}: expected {expected}, actual {actual} (tolerance {tol})"
    );
}

fn close2(name: &str, expected: Vec2, actual: Vec2, tol: f32) {
    assert!(
        (expected - actual).length() <= tol,
        "{name}: expected {expected}, actual {actual} (tolerance {tol})"
    );
}

fn close(name: &str, expected: f32, actual: f32, tol: f32) {
    assert!(
        (expected - actual).abs() <= tol,
        "{name}: expected {expected}, actual {actual} (tolerance {tol})"
    );
}

fn build(shapes: Vec<scenes::Shape>) -> Accel {
    Accel::build(&scene(shapes)).expect("valid scene")
}

fn sphere(center: Vec3, radius: f32) -> scenes::Shape {
    shape("sphere", Geometry::Sphere { center, radius })
}

#[test]
fn geometry_sphere_front_hits() {
    let accel = build(vec![sphere(Vec3::ZERO, 2.0)]);
    // Along −x onto (2, 0, 0): φ = 0, θ = π/2.
    let h = hit(&accel, Vec3::new(5.0, 0.0, 0.0), -Vec3::X);
    close("t", 3.0, h.t, 1e-5);
    close3("p", Vec3::new(2.0, 0.0, 0.0), h.p, 1e-5);
    close3("ng", Vec3::X, h.ng, 1e-6);
    close3("ns", Vec3::X, h.ns, 1e-6);
    close2("uv", Vec2::new(0.0, 0.5), h.uv, 1e-6);
    close3("dpdu", Vec3::Y, h.dpdu, 1e-6);
    assert_eq!((h.shape, h.prim), (0, 0));
    // Along −y onto (0, 2, 0): φ = π/2 → u = 1/4, ∂p/∂φ = −x.
    let h = hit(&accel, Vec3::new(0.0, 5.0, 0.0), -Vec3::Y);
    close2("uv", Vec2::new(0.25, 0.5), h.uv, 1e-6);
    close3("dpdu", -Vec3::X, h.dpdu, 1e-6);
    // Onto 2·(0, sin 45°, cos 45°): φ = π/2, θ = π/4.
    let d = Vec3::new(0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2);
    let h = hit(&accel, d * 7.0, -d);
    close("t", 5.0, h.t, 1e-5);
    close3("p", d * 2.0, h.p, 1e-5);
    close2("uv", Vec2::new(0.25, 0.25), h.uv, 1e-6);
    // Third quadrant: φ = 5π/4 → u = 5/8.
    let d = Vec3::new(-FRAC_1_SQRT_2, -FRAC_1_SQRT_2, 0.0);
    close2("uv", Vec2::new(0.625, 0.5), hit(&accel, d * 3.0, -d).uv, 1e-6);
}

#[test]
fn geometry_sphere_inside_back_and_miss() {
    let c = Vec3::new(1.0, -2.0, 3.0);
    let accel = build(vec![sphere(c, 2.0)]);
    // From the centre: the far root, normal still outward (the ray sees the back side).
    let h = hit(&accel, c, Vec3::X);
    close("t", 2.0, h.t, 1e-5);
    close3("ng", Vec3::X, h.ng, 1e-6);
    assert!(h.ng.dot(Vec3::X) > 0.0, "inside hit sees the back: ng·d > 0");
    // Sphere behind the ray, and a ray passing 2.001 from the centre.
    let behind = Ray::new(c + Vec3::new(5.0, 0.0, 0.0), Vec3::X);
    assert_eq!(accel.intersect(&behind, f32::INFINITY), None);
    let past = Ray::new(c + Vec3::new(-5.0, 2.001, 0.0), Vec3::X);
    assert_eq!(accel.intersect(&past, f32::INFINITY), None);
    // tmax before the sphere.
    let short = Ray::new(c + Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
    assert_eq!(accel.intersect(&short, 2.9), None);
    close("t", 3.0, accel.intersect(&short, 3.1).expect("hit").t, 1e-5);
}

#[test]
fn geometry_sphere_grazing() {
    let accel = build(vec![sphere(Vec3::ZERO, 1.0)]);
    // A line 0.9999 from the centre: roots at x = ±√(1 − 0.9999²) ≈ ±0.014142.
    let y = 0.9999f32;
    let h = hit(&accel, Vec3::new(-3.0, y, 0.0), Vec3::X);
    let half_chord = (1.0 - (y as f64) * (y as f64)).sqrt() as f32;
    close("t", 3.0 - half_chord, h.t, 2e-5);
    close3("ng", Vec3::new(-half_chord, y, 0.0), h.ng, 2e-5);
    // Distant grazing ray: origin 10⁴ away, the precise discriminant still finds it.
    let h = hit(&accel, Vec3::new(-1e4, y, 0.0), Vec3::X);
    close("t", 1e4 - half_chord, h.t, 2e-3);
}

#[test]
fn geometry_rectangle_hits() {
    let rect = shape(
        "rect",
        Geometry::Rectangle {
            center: Vec3::new(0.0, 0.0, -3.0),
            half_u: Vec3::new(2.0, 0.0, 0.0),
            half_v: Vec3::new(0.0, 1.0, 0.0),
        },
    );
    let accel = build(vec![rect]);
    let h = hit(&accel, Vec3::new(1.0, 0.5, 0.0), -Vec3::Z);
    close("t", 3.0, h.t, 1e-6);
    close3("p", Vec3::new(1.0, 0.5, -3.0), h.p, 1e-6);
    close3("ng", Vec3::Z, h.ng, 1e-6);
    close3("ns", Vec3::Z, h.ns, 1e-6);
    close3("dpdu", Vec3::X, h.dpdu, 1e-6);
    close2("uv", Vec2::new(0.75, 0.75), h.uv, 1e-6);
    // From behind: same front normal.
    let h = hit(&accel, Vec3::new(-1.0, -0.5, -6.0), Vec3::Z);
    close("t", 3.0, h.t, 1e-6);
    close3("ng", Vec3::Z, h.ng, 1e-6);
    close2("uv", Vec2::new(0.25, 0.25), h.uv, 1e-6);
    // Outside the edge, parallel to the plane, and pointing away.
    for (o, d) in [
        (Vec3::new(2.01, 0.0, 0.0), -Vec3::Z),
        (Vec3::new(-5.0, 0.0, -3.0), Vec3::X),
        (Vec3::new(0.0, 0.0, 0.0), Vec3::Z),
    ] {
        assert_eq!(accel.intersect(&Ray::new(o, d), f32::INFINITY), None, "{o} {d}");
    }
}

#[test]
fn geometry_sheared_rectangle_local_coordinates() {
    // half_v = (1, 1, 0): the point c + (2s + t, t, 0) has local (s, t).
    let rect = shape(
        "parallelogram",
        Geometry::Rectangle {
            center: Vec3::ZERO,
            half_u: Vec3::new(2.0, 0.0, 0.0),
            half_v: Vec3::new(1.0, 1.0, 0.0),
        },
    );
    let accel = build(vec![rect]);
    let h = hit(&accel, Vec3::new(1.5, 0.5, 1.0), -Vec3::Z);
    close2("uv", Vec2::new(0.75, 0.75), h.uv, 1e-6);
    let h = hit(&accel, Vec3::new(2.49, 0.5, 1.0), -Vec3::Z);
    close2("uv", Vec2::new(0.9975, 0.75), h.uv, 1e-6);
    let outside = Ray::new(Vec3::new(2.6, 0.5, 1.0), -Vec3::Z);
    assert_eq!(accel.intersect(&outside, f32::INFINITY), None);
}

#[test]
fn geometry_disk_hits() {
    // half_u × half_v = (2,0,0) × (0,0,−1) ∥ +y.
    let disk = shape(
        "disk",
        Geometry::Disk {
            center: Vec3::ZERO,
            half_u: Vec3::new(2.0, 0.0, 0.0),
            half_v: Vec3::new(0.0, 0.0, -1.0),
        },
    );
    let accel = build(vec![disk]);
    // Local (x, y) = (0.5, 0.5): r = √½, φ = π/4.
    let h = hit(&accel, Vec3::new(1.0, 5.0, -0.5), -Vec3::Y);
    close("t", 5.0, h.t, 1e-6);
    close3("p", Vec3::new(1.0, 0.0, -0.5), h.p, 1e-6);
    close3("ng", Vec3::Y, h.ng, 1e-6);
    close2("uv", Vec2::new(FRAC_1_SQRT_2, 0.125), h.uv, 1e-6);
    close3(
        "dpdu (radial)",
        Vec3::new(2.0, 0.0, -1.0).normalize(),
        h.dpdu,
        1e-6,
    );
    // Local (0, −0.5): φ = 3π/2.
    let h = hit(&accel, Vec3::new(0.0, -5.0, 0.5), Vec3::Y);
    close2("uv", Vec2::new(0.5, 0.75), h.uv, 1e-6);
    close3("ng (back side)", Vec3::Y, h.ng, 1e-6);
    // Local (0.8, 0.7) lies outside (r² = 1.13).
    let outside = Ray::new(Vec3::new(1.6, 5.0, -0.7), -Vec3::Y);
    assert_eq!(accel.intersect(&outside, f32::INFINITY), None);
}

/// A 1×1 texture holding `c` (linear).
fn flat_texture(c: Vec3) -> Arc<Texture> {
    Arc::new(Texture::from_texels(
        1,
        1,
        vec![c.extend(1.0)],
        [WrapMode::Repeat; 2],
    ))
}

/// A scene whose only shape carries a normal map of constant tangent-space normal `n_ts`.
fn normal_mapped(mut s: scenes::Shape, n_ts: Vec3, scale: f32) -> Scene {
    s.normal_map = Some(NormalMap { texture: 0, scale });
    let mut sc = scene(vec![s]);
    sc.textures.push(flat_texture(n_ts * 0.5 + Vec3::splat(0.5)));
    sc
}

#[test]
fn geometry_normal_map_on_rectangle_follows_tangent_and_bitangent() {
    let rect = shape(
        "rect",
        Geometry::Rectangle {
            center: Vec3::ZERO,
            half_u: Vec3::X,
            half_v: Vec3::Y,
        },
    );
    let a = 0.4f32;
    // +X of tangent space is ∂p/∂u = +x.
    let accel = Accel::build(&normal_mapped(
        rect.clone(),
        Vec3::new(a.sin(), 0.0, a.cos()),
        1.0,
    ))
    .unwrap();
    let h = hit(&accel, Vec3::new(0.2, 0.1, 1.0), -Vec3::Z);
    close3("ns (x)", Vec3::new(a.sin(), 0.0, a.cos()), h.ns, 1e-5);
    close3("ng unchanged", Vec3::Z, h.ng, 1e-6);
    assert!(h.dpdu.dot(h.ns).abs() < 1e-5, "dpdu ⟂ ns: {} · {}", h.dpdu, h.ns);
    // +Y of tangent space points to the image's top row, v = 0, i.e. −half_v.
    let accel = Accel::build(&normal_mapped(
        rect.clone(),
        Vec3::new(0.0, a.sin(), a.cos()),
        1.0,
    ))
    .unwrap();
    let h = hit(&accel, Vec3::new(0.2, 0.1, 1.0), -Vec3::Z);
    close3("ns (y)", Vec3::new(0.0, -a.sin(), a.cos()), h.ns, 1e-5);
    // scale multiplies xy before renormalising: (0.3·2, 0, 0.8) → normalize.
    let accel = Accel::build(&normal_mapped(rect, Vec3::new(0.6, 0.0, 0.8), 2.0)).unwrap();
    let h = hit(&accel, Vec3::new(0.2, 0.1, 1.0), -Vec3::Z);
    close3("ns (scaled)", Vec3::new(1.2, 0.0, 0.8).normalize(), h.ns, 1e-5);
}

#[test]
fn geometry_normal_map_on_sphere_bitangent_points_north() {
    // On the equator at +x: T = ∂p/∂φ = +y, image up (decreasing v = decreasing θ) = +z.
    let a = 0.3f32;
    let s = sphere(Vec3::ZERO, 1.0);
    let accel = Accel::build(&normal_mapped(s, Vec3::new(0.0, a.sin(), a.cos()), 1.0)).unwrap();
    let h = hit(&accel, Vec3::new(3.0, 0.0, 0.0), -Vec3::X);
    close3("ns", Vec3::new(a.cos(), 0.0, a.sin()), h.ns, 1e-5);
}

/// Quad in z = 0 over [0, 2]², two triangles, counter-clockwise from +z.
fn quad() -> Mesh {
    Mesh {
        positions: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..Mesh::default()
    }
}

#[test]
fn geometry_mesh_interpolates_attributes() {
    let mut m = quad();
    let tilt = Vec3::new(1.0, 0.0, 1.0).normalize();
    m.normals = vec![Vec3::Z, tilt, tilt, Vec3::Z];
    // glTF layout: v = 0 at the top (y = 2).
    m.uvs = vec![
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 0.0),
    ];
    let accel = build(vec![mesh_shape("quad", m)]);
    // (1.5, 0.5) lies in triangle 0 with barycentrics (0.25, 0.5, 0.25).
    let h = hit(&accel, Vec3::new(1.5, 0.5, 3.0), -Vec3::Z);
    close("t", 3.0, h.t, 1e-6);
    close3("p", Vec3::new(1.5, 0.5, 0.0), h.p, 1e-6);
    close3("ng", Vec3::Z, h.ng, 1e-6);
    close3("ns", (Vec3::Z * 0.25 + tilt * 0.75).normalize(), h.ns, 1e-6);
    close2("uv", Vec2::new(0.75, 0.75), h.uv, 1e-6);
    assert_eq!((h.shape, h.prim), (0, 0));
    // ∂p/∂u = +x (made orthogonal to ns).
    let expected = (Vec3::X - h.ns * h.ns.dot(Vec3::X)).normalize();
    close3("dpdu", expected, h.dpdu, 1e-6);
    let h = hit(&accel, Vec3::new(0.5, 1.5, 3.0), -Vec3::Z);
    assert_eq!(h.prim, 1);
    // From below: the front side (ng) stays +z.
    let h = hit(&accel, Vec3::new(0.5, 1.5, -3.0), Vec3::Z);
    close3("ng from below", Vec3::Z, h.ng, 1e-6);
}

#[test]
fn geometry_mesh_bad_vertex_normals_fall_back_to_flat() {
    let mut m = quad();
    m.normals = vec![Vec3::Z, Vec3::NAN, Vec3::X, Vec3::ZERO];
    let accel = build(vec![mesh_shape("quad", m)]);
    for p in [Vec3::new(1.5, 0.5, 3.0), Vec3::new(0.5, 1.5, 3.0)] {
        let h = hit(&accel, p, -Vec3::Z);
        close3("ns == ng", Vec3::Z, h.ns, 0.0);
        assert!(h.dpdu.is_finite(), "dpdu {}", h.dpdu);
    }
}

#[test]
fn geometry_mesh_tangent_handedness_drives_the_normal_map() {
    let a = 0.5f32;
    let n_ts = Vec3::new(0.0, a.sin(), a.cos());
    for w in [1.0f32, -1.0] {
        let mut m = quad();
        m.uvs = vec![Vec2::ZERO; 4];
        m.tangents = vec![Vec4::new(1.0, 0.0, 0.0, w); 4];
        let sc = normal_mapped(mesh_shape("quad", m), n_ts, 1.0);
        let accel = Accel::build(&sc).unwrap();
        let h = hit(&accel, Vec3::new(1.5, 0.5, 3.0), -Vec3::Z);
        // B = w·(N × T) = w·(+y).
        close3("ns", Vec3::new(0.0, w * a.sin(), a.cos()), h.ns, 1e-5);
        close3("dpdu", Vec3::X, h.dpdu, 1e-5);
    }
}

#[test]
fn geometry_mesh_without_uvs_uses_barycentrics() {
    let accel = build(vec![mesh_shape("quad", quad())]);
    // Triangle 0 (p0, p1, p2) at barycentrics (0.25, 0.5, 0.25): uv = (b1, b2).
    let h = hit(&accel, Vec3::new(1.5, 0.5, 3.0), -Vec3::Z);
    close2("uv", Vec2::new(0.5, 0.25), h.uv, 1e-6);
    close3("dpdu = p1 − p0", Vec3::X, h.dpdu, 1e-6);
    // The sphere's u at the seam and pole stays in range.
    let pole = build(vec![sphere(Vec3::ZERO, 1.0)]);
    let h = hit(&pole, Vec3::new(0.0, 0.0, 4.0), -Vec3::Z);
    close("v at the pole", 0.0, h.uv.y, 1e-6);
    assert!((0.0..=1.0).contains(&h.uv.x) && h.dpdu.is_finite(), "{h:?}");
}
