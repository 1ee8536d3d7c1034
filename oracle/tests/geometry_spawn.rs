//! Self-intersection avoidance (Wächter & Binder 2019 offsets) on spheres and triangles near
//! the origin and at 10⁴ m, over many random rays, and shadow segments between surfaces.

mod geometry_util;

use geometry_util::{mesh_shape, scene, shape, Rng};
use glam::Vec3;
use oracle::geometry::{spawn_ray, spawn_ray_to, Accel, Ray, SurfaceHit, SHADOW_EPSILON};
use scenes::{Geometry, Mesh};

/// Spacing of f32 values at magnitude `x`.
fn ulp(x: f32) -> f32 {
    f32::from_bits(x.abs().to_bits() + 1) - x.abs()
}

/// Random direction in the hemisphere around `n` with cos θ ≥ `min_cos`.
fn hemisphere(rng: &mut Rng, n: Vec3, min_cos: f32) -> Vec3 {
    loop {
        let d = rng.dir();
        let c = d.dot(n);
        if c.abs() >= min_cos {
            return if c > 0.0 { d } else { -d };
        }
    }
}

/// Far root of the ray against the sphere, in f64 (the origin lies inside).
fn exit_distance(ray: &Ray, center: Vec3, radius: f32) -> f64 {
    let f = ray.origin.as_dvec3() - center.as_dvec3();
    let d = ray.dir.as_dvec3();
    let b = f.dot(d);
    let c = f.length_squared() - (radius as f64).powi(2);
    -b + (b * b - c).max(0.0).sqrt()
}

/// Random hits on the only shape of `accel`, by rays from a box around `center`.
fn random_hits(accel: &Accel, rng: &mut Rng, center: Vec3, size: f32, n: usize) -> Vec<SurfaceHit> {
    let mut hits = Vec::with_capacity(n);
    while hits.len() < n {
        let origin = center + rng.dir() * 3.0 * size;
        let target = center + rng.dir() * rng.range(0.0, 0.9 * size);
        if let Some(h) = accel.intersect(&Ray::new(origin, (target - origin).normalize()), f32::INFINITY) {
            hits.push(h);
        }
    }
    hits
}

fn sphere_case(center: Vec3, radius: f32) {
    let accel = Accel::build(&scene(vec![shape("ball", Geometry::Sphere { center, radius })])).unwrap();
    let mut rng = Rng::new(17);
    let (mut leaving, mut entering) = (0, 0);
    for h in random_hits(&accel, &mut rng, center, radius, 10000) {
        // Leaving: a convex surface is never hit again, even at grazing angles.
        let out = spawn_ray(h.p, h.ng, hemisphere(&mut rng, h.ng, 1e-3));
        if let Some(again) = accel.intersect(&out, f32::INFINITY) {
            panic!(
                "self-hit leaving {center} r={radius}: {out:?} hit again at t = {}",
                again.t
            );
        }
        assert!(!accel.occluded(&out, f32::INFINITY), "{out:?} occluded");
        leaving += 1;
        // Entering: the next hit is the far side, where f64 says.
        let inward = spawn_ray(h.p, h.ng, hemisphere(&mut rng, -h.ng, 0.05));
        let expected = exit_distance(&inward, center, radius);
        let got = accel.intersect(&inward, f32::INFINITY).expect("far side").t as f64;
        let tol = 1e-4 * radius as f64 + 1e-5 * center.length() as f64;
        assert!(
            (got - expected).abs() <= tol,
            "entering {center} r={radius}: expected t {expected}, actual {got} (tol {tol})"
        );
        entering += 1;
    }
    assert_eq!((leaving, entering), (10000, 10000));
}

#[test]
fn geometry_spawn_avoids_self_hits_on_spheres() {
    sphere_case(Vec3::ZERO, 0.01); // all coordinates below 1/32: the fixed-offset branch
    sphere_case(Vec3::new(0.3, -1.2, 2.0), 1.0);
    sphere_case(Vec3::new(1e4, -1e4, 1e4), 10.0);
    sphere_case(Vec3::new(1e4, 2e3, -1e4), 200.0);
}

fn triangle_case(center: Vec3, size: f32, rng: &mut Rng) {
    let (a, b) = (rng.dir(), rng.dir());
    let v = [center + a * size, center + b * size, center - (a + b) * size];
    let mesh = Mesh {
        positions: v.to_vec(),
        indices: vec![[0, 1, 2]],
        ..Mesh::default()
    };
    let accel = Accel::build(&scene(vec![mesh_shape("tri", mesh)])).unwrap();
    let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize().as_dvec3();
    let signed = |p: Vec3| (p.as_dvec3() - v[0].as_dvec3()).dot(n);
    for h in random_hits(&accel, rng, center, size * 0.3, 20000) {
        let side = if rng.f32() < 0.5 { h.ng } else { -h.ng };
        let dir = hemisphere(rng, side, 1e-3);
        let ray = spawn_ray(h.p, h.ng, dir);
        // The origin moved to the side the ray leaves to, and the plane is not hit again.
        let side = signed(ray.origin);
        assert!(
            side * dir.as_dvec3().dot(n) > 0.0,
            "origin {} on the wrong side ({side}) for {dir}",
            ray.origin
        );
        if let Some(again) = accel.intersect(&ray, f32::INFINITY) {
            panic!("self-hit at {center}: {ray:?} hit again at t = {}", again.t);
        }
    }
}

#[test]
fn geometry_spawn_avoids_self_hits_on_triangles() {
    let mut rng = Rng::new(23);
    for _ in 0..3 {
        triangle_case(Vec3::new(0.01, -0.02, 0.005), 0.02, &mut rng);
        triangle_case(Vec3::new(0.5, 1.0, -0.3), 2.0, &mut rng);
        triangle_case(Vec3::new(1e4, 1e4, 1e4), 50.0, &mut rng);
        triangle_case(Vec3::new(-1e4, 3e3, 1e4), 500.0, &mut rng);
    }
}

/// Two facing quads (floor up, ceiling down) `gap` apart around `c`, and optionally a blocker.
fn rooms(c: Vec3, size: f32, gap: f32, blocker: bool) -> Accel {
    let quad = |z: f32, up: bool| {
        let s = size;
        let p = [(-s, -s), (s, -s), (s, s), (-s, s)].map(|(x, y)| c + Vec3::new(x, y, z));
        let indices = if up {
            vec![[0, 1, 2], [0, 2, 3]]
        } else {
            vec![[0, 2, 1], [0, 3, 2]]
        };
        Mesh {
            positions: p.to_vec(),
            indices,
            ..Mesh::default()
        }
    };
    let mut shapes = vec![
        mesh_shape("floor", quad(0.0, true)),
        mesh_shape("ceiling", quad(gap, false)),
    ];
    if blocker {
        shapes.push(shape(
            "blocker",
            Geometry::Rectangle {
                center: c + Vec3::new(0.0, 0.0, 0.5 * gap),
                half_u: Vec3::X * 2.0 * size,
                half_v: Vec3::Y * 2.0 * size,
            },
        ));
    }
    Accel::build(&scene(shapes)).unwrap()
}

#[test]
fn geometry_spawn_ray_to_connects_surfaces_without_self_hits() {
    let mut rng = Rng::new(29);
    for (c, size, gap) in [
        (Vec3::new(0.0, 0.0, 0.0), 1.0, 0.5),
        (Vec3::new(1e4, -1e4, 1e4), 100.0, 20.0),
    ] {
        let open = rooms(c, size, gap, false);
        let blocked = rooms(c, size, gap, true);
        let at = |rng: &mut Rng, z: f32| c + Vec3::new(rng.range(-size, size), rng.range(-size, size), z);
        for _ in 0..20000 {
            let (p, q) = (at(&mut rng, 0.0), at(&mut rng, gap));
            let down = Vec3::NEG_Z;
            let hp = open
                .intersect(&Ray::new(p - down * gap * 0.25, down), f32::INFINITY)
                .expect("floor");
            let hq = open
                .intersect(&Ray::new(q + down * gap * 0.25, -down), f32::INFINITY)
                .expect("ceiling");
            let (ray, tmax) = spawn_ray_to(hp.p, hp.ng, hq.p, Some(hq.ng));
            assert!(
                !open.occluded(&ray, tmax),
                "self-hit between {} and {}",
                hp.p,
                hq.p
            );
            assert!(
                blocked.occluded(&ray, tmax),
                "blocker missed between {} and {}",
                hp.p,
                hq.p
            );
            // The segment ends within the two offsets (256 ULPs each) and the shortening.
            let end = ray.at(tmax);
            let tol = 600.0 * ulp(c.abs().max_element() + size + gap)
                + 2.0 * SHADOW_EPSILON * (hq.p - hp.p).length();
            assert!(
                (end - hq.p).length() < tol,
                "segment ends at {end}, target {} (tol {tol})",
                hq.p
            );
            // A point light just below the ceiling (no surface at q).
            let light = hq.p + Vec3::NEG_Z * (0.01 * gap);
            let (ray, tmax) = spawn_ray_to(hp.p, hp.ng, light, None);
            assert!(
                !open.occluded(&ray, tmax),
                "point-light ray blocked from {}",
                hp.p
            );
        }
    }
    // Degenerate segment: nothing can occlude it.
    let (_, tmax) = spawn_ray_to(Vec3::ONE, Vec3::Z, Vec3::ONE, None);
    assert!(tmax < 1e-3, "tmax {tmax}");
}
