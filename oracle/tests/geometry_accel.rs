//! The BVH against brute force: random triangle soups with analytic shapes, a tessellated
//! sphere against the analytic one, watertightness, near hits, shadow rays, bad input.

mod geometry_util;

use geometry_util::{mesh_shape, scene, shape, uv_sphere, Rng};
use glam::{DVec3, Vec3};
use oracle::geometry::{Accel, Ray};
use scenes::{Geometry, Mesh, Shape};

/// Reference closest hit: (t, shape, prim, margin), margin = how far inside the primitive's
/// boundary the hit lies (0 on an edge), in f64 by formulas independent of the oracle's.
type RefHit = (f64, u32, u32, f64);

fn d(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

/// Möller & Trumbore 1997 in f64, both sides; margin = smallest barycentric.
fn ref_triangle(o: DVec3, dir: DVec3, p: [Vec3; 3]) -> Option<(f64, f64)> {
    let (e1, e2) = (d(p[1]) - d(p[0]), d(p[2]) - d(p[0]));
    let pv = dir.cross(e2);
    let det = e1.dot(pv);
    if det == 0.0 {
        return None;
    }
    let tv = o - d(p[0]);
    let u = tv.dot(pv) / det;
    let qv = tv.cross(e1);
    let v = dir.dot(qv) / det;
    let t = e2.dot(qv) / det;
    let margin = u.min(v).min(1.0 - u - v);
    (margin >= 0.0 && t > 0.0).then_some((t, margin))
}

/// Plane hit in f64 with local coordinates from the 3×3 solve (s·hu + t·hv + h·n = p − c).
fn ref_plane(o: DVec3, dir: DVec3, c: Vec3, hu: Vec3, hv: Vec3) -> Option<(f64, f64, f64)> {
    let (c, hu, hv) = (d(c), d(hu), d(hv));
    let n = hu.cross(hv);
    let t = (c - o).dot(n) / dir.dot(n);
    if !(t > 0.0 && t.is_finite()) {
        return None;
    }
    let r = o + dir * t - c;
    let m = glam::DMat3::from_cols(hu, hv, n).inverse() * r;
    Some((t, m.x, m.y))
}

fn ref_shape(o: DVec3, dir: DVec3, s: &Shape) -> Vec<(f64, u32, f64)> {
    match &s.geometry {
        Geometry::Sphere { center, radius } => {
            let f = o - d(*center);
            let (b, c) = (f.dot(dir), f.length_squared() - (*radius as f64).powi(2));
            let disc = b * b - c;
            if disc < 0.0 {
                return vec![];
            }
            let margin = disc / (*radius as f64).powi(2);
            [-b - disc.sqrt(), -b + disc.sqrt()]
                .into_iter()
                .filter(|&t| t > 0.0)
                .map(|t| (t, 0, margin))
                .take(1)
                .collect()
        }
        Geometry::Rectangle {
            center,
            half_u,
            half_v,
        } => ref_plane(o, dir, *center, *half_u, *half_v)
            .map(|(t, s, u)| (t, 0, 1.0 - s.abs().max(u.abs())))
            .filter(|h| h.2 >= 0.0)
            .into_iter()
            .collect(),
        Geometry::Disk {
            center,
            half_u,
            half_v,
        } => ref_plane(o, dir, *center, *half_u, *half_v)
            .map(|(t, s, u)| (t, 0, 1.0 - (s * s + u * u).sqrt()))
            .filter(|h| h.2 >= 0.0)
            .into_iter()
            .collect(),
        Geometry::Mesh(m) => m
            .indices
            .iter()
            .enumerate()
            .filter_map(|(k, idx)| {
                ref_triangle(o, dir, idx.map(|i| m.positions[i as usize])).map(|(t, mg)| (t, k as u32, mg))
            })
            .collect(),
    }
}

/// All reference hits along a ray, nearest first.
fn ref_hits(shapes: &[Shape], ray: &Ray) -> Vec<RefHit> {
    let (o, dir) = (d(ray.origin), d(ray.dir));
    let mut hits: Vec<RefHit> = shapes
        .iter()
        .enumerate()
        .flat_map(|(si, s)| {
            ref_shape(o, dir, s)
                .into_iter()
                .map(move |(t, p, m)| (t, si as u32, p, m))
        })
        .collect();
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    hits
}

/// Random triangle soup plus spheres, rectangles and disks in [−5, 5]³.
fn random_scene(rng: &mut Rng, triangles: usize) -> Vec<Shape> {
    let mut mesh = Mesh::default();
    for _ in 0..triangles {
        let c = rng.in_box(Vec3::splat(-5.0), Vec3::splat(5.0));
        let base = mesh.positions.len() as u32;
        for _ in 0..3 {
            mesh.positions.push(c + rng.dir() * rng.range(0.1, 1.5));
        }
        mesh.indices.push([base, base + 1, base + 2]);
    }
    let mut shapes = vec![mesh_shape("soup", mesh)];
    for i in 0..15 {
        let center = rng.in_box(Vec3::splat(-5.0), Vec3::splat(5.0));
        let (hu, hv) = (rng.dir() * rng.range(0.2, 1.0), rng.dir() * rng.range(0.2, 1.0));
        shapes.push(shape(
            &format!("sphere{i}"),
            Geometry::Sphere {
                center,
                radius: rng.range(0.1, 0.8),
            },
        ));
        shapes.push(shape(
            &format!("rect{i}"),
            Geometry::Rectangle {
                center: center + rng.dir(),
                half_u: hu,
                half_v: hv,
            },
        ));
        shapes.push(shape(
            &format!("disk{i}"),
            Geometry::Disk {
                center: center - rng.dir(),
                half_u: hv,
                half_v: hu,
            },
        ));
    }
    shapes
}

/// How one ray's closest hit compared with brute force.
enum Agreement {
    /// Both miss.
    Miss,
    /// The same hit (or a tie at the same distance).
    Hit,
    /// They differ where the reference grazes an edge (f32 may decide either way).
    EdgeCase,
}

/// (hits, edge cases) of `rays` against the f64 brute force over `shapes`; panics on a
/// disagreement that is not an edge case.
fn tally_against_brute_force(accel: &Accel, shapes: &[Shape], rays: impl Iterator<Item = Ray>) -> (u32, u32) {
    let (mut hits, mut edge_cases) = (0, 0);
    for ray in rays {
        match against_brute_force(accel, shapes, &ray) {
            Agreement::Miss => {}
            Agreement::Hit => hits += 1,
            Agreement::EdgeCase => edge_cases += 1,
        }
    }
    (hits, edge_cases)
}

/// The BVH's closest hit of `ray` against the f64 brute force over `shapes`; panics on a
/// disagreement that is not an edge case.
fn against_brute_force(accel: &Accel, shapes: &[Shape], ray: &Ray) -> Agreement {
    let reference = ref_hits(shapes, ray);
    let got = accel.intersect(ray, f32::INFINITY);
    // The closest reference hit, unless it grazes an edge (where f32 may differ).
    match (reference.first(), got) {
        (None, None) => Agreement::Miss,
        (Some(&(t, s, p, _)), Some(h)) if (t - h.t as f64).abs() <= 1e-4 * (1.0 + t) => {
            if (s, p) != (h.shape, h.prim) {
                // A tie: the oracle's primitive must also be hit at that distance.
                let tie = reference
                    .iter()
                    .any(|r| (r.1, r.2) == (h.shape, h.prim) && (r.0 - t).abs() < 1e-4);
                assert!(tie, "{ray:?}: expected shape {s} prim {p}, got {h:?}");
            }
            let p_expect = ray.at(h.t);
            assert!(
                (h.p - p_expect).length() < 1e-4 * (1.0 + h.t),
                "p: expected {p_expect}, actual {}",
                h.p
            );
            assert!((h.ng.length() - 1.0).abs() < 1e-5 && (h.ns.length() - 1.0).abs() < 1e-5);
            Agreement::Hit
        }
        (first, got) => {
            let grazes = |r: &RefHit| r.3 < 1e-4;
            let near_miss = first.is_none_or(grazes);
            assert!(near_miss, "{ray:?}: expected {first:?}, actual {got:?}");
            Agreement::EdgeCase
        }
    }
}

#[test]
fn geometry_bvh_matches_brute_force_on_random_soup() {
    let mut rng = Rng::new(7);
    let shapes = random_scene(&mut rng, 3000);
    let accel = Accel::build(&scene(shapes.clone())).expect("valid scene");
    assert_eq!(accel.triangle_count() + accel.dropped_degenerate(), 3000);
    let rays = (0..4000).map(|_| Ray::new(rng.in_box(Vec3::splat(-7.0), Vec3::splat(7.0)), rng.dir()));
    let (hits, edge_cases) = tally_against_brute_force(&accel, &shapes, rays);
    assert!(
        hits > 1500 && edge_cases < 5,
        "hits {hits}, edge cases {edge_cases}"
    );
}

/// Directions along an axis whose other components are exactly 0, −0.0, subnormal or tiny:
/// the node test reads components below `f32::MIN_POSITIVE` as +`f32::MIN_POSITIVE`, and
/// must still find every hit brute force finds.
#[test]
fn geometry_axis_parallel_and_nearly_parallel_rays_match_brute_force() {
    let mut rng = Rng::new(11);
    let shapes = random_scene(&mut rng, 3000);
    let accel = Accel::build(&scene(shapes.clone())).expect("valid scene");
    let small = [0.0, -0.0, 1e-40, -1e-40, 1e-30, -1e-30, 1e-20, -3e-8];
    let rays = (0..3000).map(|k| {
        let axis = k % 3;
        let mut dir = Vec3::ZERO;
        dir[axis] = if k % 2 == 0 { 1.0 } else { -1.0 };
        dir[(axis + 1) % 3] = small[(k / 6) % small.len()];
        dir[(axis + 2) % 3] = small[(k / 48) % small.len()];
        Ray::new(rng.in_box(Vec3::splat(-7.0), Vec3::splat(7.0)), dir)
    });
    let (hits, edge_cases) = tally_against_brute_force(&accel, &shapes, rays);
    assert!(
        hits > 800 && edge_cases < 5,
        "hits {hits}, edge cases {edge_cases}"
    );
}

#[test]
fn geometry_occluded_agrees_with_intersect() {
    let mut rng = Rng::new(11);
    let shapes = random_scene(&mut rng, 2000);
    let accel = Accel::build(&scene(shapes)).expect("valid scene");
    let mut checked = 0;
    for _ in 0..5000 {
        let ray = Ray::new(rng.in_box(Vec3::splat(-7.0), Vec3::splat(7.0)), rng.dir());
        let hit = accel.intersect(&ray, f32::INFINITY);
        assert_eq!(
            accel.occluded(&ray, f32::INFINITY),
            hit.is_some(),
            "{ray:?} {hit:?}"
        );
        if let Some(h) = hit {
            assert!(
                accel.occluded(&ray, h.t * 1.0001 + 1e-5),
                "{ray:?}: not occluded past t = {}",
                h.t
            );
            assert!(
                !accel.occluded(&ray, h.t * 0.9999),
                "{ray:?}: occluded before t = {}",
                h.t
            );
            assert_eq!(accel.intersect(&ray, h.t * 0.9999), None);
            checked += 1;
        }
    }
    assert!(checked > 2000, "only {checked} rays hit");
}

#[test]
fn geometry_tessellated_sphere_agrees_with_analytic() {
    let center = Vec3::new(0.3, -0.2, 0.1);
    let (n_phi, n_theta) = (512, 256);
    let mesh = uv_sphere(center, 1.0, n_phi, n_theta);
    let tessellated = Accel::build(&scene(vec![mesh_shape("mesh", mesh)])).unwrap();
    let analytic = Accel::build(&scene(vec![shape(
        "sphere",
        Geometry::Sphere { center, radius: 1.0 },
    )]))
    .unwrap();
    assert_eq!(tessellated.dropped_degenerate(), 0);
    // Chord sagitta of the coarser step Δ = π/256: 1 − cos(Δ/2) ≈ Δ²/8; ray incidence ≤ 45°.
    let step = std::f32::consts::PI / n_theta as f32;
    let t_tol = 2.0 * step * step / 8.0 * std::f32::consts::SQRT_2 + 1e-5;
    let mut rng = Rng::new(3);
    for _ in 0..20000 {
        let origin = center + rng.dir() * 4.0;
        let target = center + rng.dir() * rng.range(0.0, 0.7);
        let ray = Ray::new(origin, (target - origin).normalize());
        let (Some(m), Some(a)) = (
            tessellated.intersect(&ray, f32::INFINITY),
            analytic.intersect(&ray, f32::INFINITY),
        ) else {
            panic!("{ray:?} must hit both spheres");
        };
        assert!(
            (m.t - a.t).abs() <= t_tol,
            "t: analytic {}, mesh {} (tol {t_tol})",
            a.t,
            m.t
        );
        assert!(
            m.ns.dot(a.ng) > (2.0 * step).cos(),
            "ns: analytic {}, mesh {}",
            a.ng,
            m.ns
        );
        assert!(
            m.ng.dot(a.ng) > (2.0 * step).cos(),
            "ng: analytic {}, mesh {}",
            a.ng,
            m.ng
        );
        // uv away from the seam (u wraps) and the poles (u undefined).
        let du = (m.uv.x - a.uv.x).abs();
        if a.uv.y > 0.02 && a.uv.y < 0.98 {
            assert!(
                du.min(1.0 - du) < 2.0 / n_phi as f32,
                "u: analytic {}, mesh {}",
                a.uv,
                m.uv
            );
        }
        assert!(
            (m.uv.y - a.uv.y).abs() < 2.0 / n_theta as f32,
            "v: analytic {}, mesh {}",
            a.uv,
            m.uv
        );
    }
    // Lines farther than 1.01 from the centre miss both.
    for _ in 0..2000 {
        let dir = rng.dir();
        let side = dir.any_orthogonal_vector().normalize();
        let ray = Ray::new(center + side * rng.range(1.01, 2.0) - dir * 3.0, dir);
        assert!(
            tessellated.intersect(&ray, f32::INFINITY).is_none(),
            "mesh hit by {ray:?}"
        );
        assert!(
            analytic.intersect(&ray, f32::INFINITY).is_none(),
            "sphere hit by {ray:?}"
        );
    }
}

/// n×n unit squares in z = 0 with integer vertex coordinates and shared edges.
fn grid(n: u32) -> Mesh {
    let mut m = Mesh::default();
    for j in 0..=n {
        for i in 0..=n {
            m.positions.push(Vec3::new(i as f32, j as f32, 0.0));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let (b, c, dd) = (a + 1, a + n + 1, a + n + 2);
            m.indices.push([a, b, dd]);
            m.indices.push([a, dd, c]);
        }
    }
    m
}

#[test]
fn geometry_watertight_on_shared_edges_and_vertices() {
    let n = 16;
    let accel = Accel::build(&scene(vec![mesh_shape("grid", grid(n))])).unwrap();
    let dirs = [
        Vec3::NEG_Z,
        Vec3::new(0.25, 0.125, -1.0).normalize(),
        Vec3::new(-1.0, 1.0, -1.0).normalize(),
        Vec3::new(0.001, 0.0, -1.0).normalize(),
    ];
    let mut rays = 0;
    for dir in dirs {
        // Every vertex, edge midpoint and face centre of the interior (half-integer lattice).
        for j in 1..(2 * n) {
            for i in 1..(2 * n) {
                let target = Vec3::new(i as f32 * 0.5, j as f32 * 0.5, 0.0);
                let ray = Ray::new(target - dir * (3.0 / -dir.z), dir);
                let h = accel.intersect(&ray, f32::INFINITY);
                let h = h.unwrap_or_else(|| panic!("leak through {target} along {dir}"));
                assert!(
                    (h.p - target).length() < 1e-5,
                    "p: expected {target}, actual {}",
                    h.p
                );
                rays += 1;
            }
        }
    }
    assert_eq!(rays, 4 * 31 * 31);
}

#[test]
fn geometry_hits_closer_than_a_tenth_of_a_millimetre() {
    // A floor and a wall meeting at x = 0; rays start 5·10⁻⁵ m from the wall.
    let floor = Mesh {
        positions: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::new(2.0, 0.0, 2.0),
            Vec3::new(2.0, 0.0, 0.0),
        ],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..Mesh::default()
    };
    let wall = shape(
        "wall",
        Geometry::Rectangle {
            center: Vec3::new(0.0, 1.0, 1.0),
            half_u: Vec3::Y,
            half_v: Vec3::Z,
        },
    );
    let wall_mesh = Mesh {
        positions: floor.positions.iter().map(|p| Vec3::new(0.0, p.x, p.z)).collect(),
        ..floor.clone()
    };
    for second in [wall, mesh_shape("wall mesh", wall_mesh)] {
        let accel = Accel::build(&scene(vec![mesh_shape("floor", floor.clone()), second])).unwrap();
        for z in [0.3f32, 1.0, 1.7] {
            let ray = Ray::new(Vec3::new(5e-5, 1e-6, z), Vec3::new(-1.0, 0.01, 0.0).normalize());
            let h = accel.intersect(&ray, f32::INFINITY).expect("wall hit");
            assert_eq!(h.shape, 1, "{h:?}");
            assert!((h.t - 5e-5).abs() < 1e-7, "t: expected 5e-5, actual {}", h.t);
            assert!(accel.occluded(&ray, 1e-4), "shadow ray misses the wall");
        }
    }
}

#[test]
fn geometry_negative_zero_direction_components() {
    // −0.0 components must not flip the BVH's octant logic.
    let accel = Accel::build(&scene(vec![shape(
        "s",
        Geometry::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
    )]))
    .unwrap();
    for dir in [
        Vec3::new(-1.0, -0.0, -0.0),
        Vec3::new(-0.0, -1.0, 0.0),
        Vec3::new(0.0, -0.0, -1.0),
    ] {
        let ray = Ray::new(-dir * 3.0, dir);
        let h = accel.intersect(&ray, f32::INFINITY).expect("hit");
        assert!((h.t - 2.0).abs() < 1e-6, "t: expected 2, actual {}", h.t);
        assert!(accel.occluded(&ray, 10.0));
    }
}

#[test]
fn geometry_degenerate_triangles_are_dropped_and_counted() {
    let mesh = Mesh {
        positions: vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(2.0, 0.0, 0.0), // collinear with 0, 1
        ],
        indices: vec![[0, 1, 2], [0, 1, 3], [2, 2, 2], [1, 1, 0]],
        ..Mesh::default()
    };
    let accel = Accel::build(&scene(vec![mesh_shape("m", mesh)])).unwrap();
    assert_eq!((accel.triangle_count(), accel.dropped_degenerate()), (1, 3));
    let h = accel.intersect(&Ray::new(Vec3::new(0.2, 0.2, 1.0), Vec3::NEG_Z), f32::INFINITY);
    assert_eq!(
        h.map(|h| h.prim),
        Some(0),
        "the surviving triangle keeps its index"
    );
    assert!(accel.build_seconds() >= 0.0);
}

#[test]
fn geometry_bad_input_is_an_error_naming_shape_and_field() {
    let tri = |p: [Vec3; 3]| Mesh {
        positions: p.to_vec(),
        indices: vec![[0, 1, 2]],
        ..Mesh::default()
    };
    let cases: Vec<(Shape, &[&str])> = vec![
        (
            mesh_shape(
                "nan mesh",
                tri([Vec3::ZERO, Vec3::X, Vec3::new(0.0, f32::NAN, 0.0)]),
            ),
            &["nan mesh", "vertex 2"],
        ),
        (
            mesh_shape("inf mesh", tri([Vec3::splat(f32::INFINITY), Vec3::X, Vec3::Y])),
            &["inf mesh", "vertex 0"],
        ),
        (
            mesh_shape("huge mesh", tri([Vec3::splat(1e16), Vec3::X, Vec3::Y])),
            &["huge mesh", "vertex 0"],
        ),
        (
            mesh_shape(
                "bad index",
                Mesh {
                    indices: vec![[0, 1, 5]],
                    ..tri([Vec3::ZERO, Vec3::X, Vec3::Y])
                },
            ),
            &["bad index", "triangle 0", "5"],
        ),
        (
            mesh_shape(
                "short normals",
                Mesh {
                    normals: vec![Vec3::Z],
                    ..tri([Vec3::ZERO, Vec3::X, Vec3::Y])
                },
            ),
            &["short normals", "normals"],
        ),
        (
            shape(
                "zero ball",
                Geometry::Sphere {
                    center: Vec3::ZERO,
                    radius: 0.0,
                },
            ),
            &["zero ball", "radius"],
        ),
        (
            shape(
                "nan ball",
                Geometry::Sphere {
                    center: Vec3::NAN,
                    radius: 1.0,
                },
            ),
            &["nan ball", "center"],
        ),
        (
            shape(
                "flat rect",
                Geometry::Rectangle {
                    center: Vec3::ZERO,
                    half_u: Vec3::X,
                    half_v: Vec3::X * 2.0,
                },
            ),
            &["flat rect", "half_u"],
        ),
        (
            shape(
                "nan disk",
                Geometry::Disk {
                    center: Vec3::ZERO,
                    half_u: Vec3::X,
                    half_v: Vec3::new(0.0, f32::NAN, 0.0),
                },
            ),
            &["nan disk", "half_v"],
        ),
    ];
    for (s, words) in cases {
        let good = shape(
            "good",
            Geometry::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
        );
        let err = Accel::build(&scene(vec![good, s])).expect_err("bad input must be refused");
        for w in words {
            assert!(err.contains(w), "error {err:?} should mention {w:?}");
        }
        assert!(
            err.contains("shape 1"),
            "error {err:?} should give the shape index"
        );
    }
    // A normal map naming a missing texture.
    let mut s = shape(
        "mapped",
        Geometry::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
    );
    s.normal_map = Some(scenes::NormalMap {
        texture: 3,
        scale: 1.0,
    });
    let err = Accel::build(&scene(vec![s])).expect_err("missing texture");
    assert!(
        err.contains("mapped") && err.contains("normal_map.texture"),
        "{err}"
    );
}

#[test]
fn geometry_empty_scene_single_primitive_and_bad_rays() {
    let empty = Accel::build(&scene(vec![])).unwrap();
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    assert_eq!(empty.intersect(&ray, f32::INFINITY), None);
    assert!(!empty.occluded(&ray, f32::INFINITY));
    let one = Accel::build(&scene(vec![shape(
        "s",
        Geometry::Sphere {
            center: Vec3::X * 3.0,
            radius: 1.0,
        },
    )]))
    .unwrap();
    assert!(one.intersect(&ray, f32::INFINITY).is_some());
    for (bad, tmax) in [
        (Ray::new(Vec3::NAN, Vec3::X), f32::INFINITY),
        (Ray::new(Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 0.0)), f32::INFINITY),
        (Ray::new(Vec3::ZERO, Vec3::ZERO), f32::INFINITY),
        (ray, f32::NAN),
        (ray, 0.0),
        (ray, -1.0),
    ] {
        assert_eq!(one.intersect(&bad, tmax), None, "{bad:?} {tmax}");
        assert!(!one.occluded(&bad, tmax), "{bad:?} {tmax}");
    }
}

#[test]
fn geometry_deep_bvh_over_coincident_boxes() {
    // 3000 triangles sharing one bounding box [0, 1]³ (v0 = 0, v1 = 1, v2 random inside)
    // and 2000 copies of one of them: PLOC's Morton codes tie and the tree grows hundreds of
    // levels deep. Every closest hit must still match brute force.
    let mut rng = Rng::new(5);
    let mut mesh = Mesh::default();
    for k in 0..3000u32 {
        mesh.positions
            .extend([Vec3::ZERO, Vec3::ONE, rng.in_box(Vec3::ZERO, Vec3::ONE)]);
        mesh.indices.push([3 * k, 3 * k + 1, 3 * k + 2]);
    }
    // Plus exact duplicates of one triangle.
    let dup = mesh.indices[0];
    let on_dup = (mesh.positions[0] + mesh.positions[1] + mesh.positions[2]) / 3.0;
    mesh.indices.extend(std::iter::repeat_n(dup, 2000));
    let shapes = vec![mesh_shape("stack", mesh)];
    let accel = Accel::build(&scene(shapes.clone())).unwrap();
    assert_eq!(accel.triangle_count() + accel.dropped_degenerate(), 5000);
    for _ in 0..300 {
        let target = if rng.f32() < 0.3 {
            on_dup
        } else {
            rng.in_box(Vec3::ZERO, Vec3::ONE)
        };
        let origin = target + rng.dir() * 3.0;
        let ray = Ray::new(origin, (target - origin).normalize());
        let reference = ref_hits(&shapes, &ray);
        let got = accel.intersect(&ray, f32::INFINITY);
        match (reference.first(), got) {
            (Some(r), Some(h)) => assert!(
                (r.0 - h.t as f64).abs() < 1e-4 || r.3 < 1e-4,
                "{ray:?}: expected t {}, actual {}",
                r.0,
                h.t
            ),
            (None, None) => {}
            (r, h) => assert!(
                r.is_none_or(|r| r.3 < 1e-4),
                "{ray:?}: expected {r:?}, actual {h:?}"
            ),
        }
    }
}
