//! The oracle's geometric AOVs against closed forms: `position.*` and `depth.Z` of a floor
//! seen at a grazing angle, `uv.*` of a tilted rectangle, and `visibility.<light>.Y` on the
//! soft-shadow scene (umbra, penumbra and lit floor).
//!
//! Every AOV is a box-filtered mean over the pixel's samples (oracle/src/film.rs), each sample
//! at a uniform jitter within the pixel. The expected value of a pixel is therefore the mean
//! of the quantity over the pixel's footprint, computed here by a 16×16 midpoint rule (its
//! error estimated by the difference from an 8×8 rule). With independent samples (the
//! `independent` sampler) the pixel's error has standard deviation σ/√n, σ² the variance of
//! the quantity over the footprint (a Bernoulli p(1 − p) for visibility); the tolerances are
//! 6 of those standard errors plus the quadrature error and f32 rounding.

use std::path::Path;

use glam::{Vec2, Vec3};
use scenes::layered::LayeredImage;
use scenes::*;
use verity_tests::*;

/// Standard errors allowed: a 6σ deviation has probability 2·10⁻⁹ per value.
const K: f64 = 6.0;

/// Raster positions of the midpoints of a g×g grid over pixel (px, py).
fn grid(px: u32, py: u32, g: u32) -> impl Iterator<Item = (f32, f32)> {
    (0..g * g).map(move |k| {
        let (i, j) = (k % g, k / g);
        (
            px as f32 + (i as f32 + 0.5) / g as f32,
            py as f32 + (j as f32 + 0.5) / g as f32,
        )
    })
}

/// The pixel's four corners: with the grid, they decide whether a footprint lies in a convex
/// region (a pixel's footprint on a plane is the convex image of the pixel square).
fn corners(px: u32, py: u32) -> impl Iterator<Item = (f32, f32)> {
    (0..4u32).map(move |k| ((px + k % 2) as f32, (py + k / 2) as f32))
}

/// Mean and (population) variance of `f` over the pixel footprint by a g×g midpoint rule;
/// `None` if `f` is undefined (the ray misses) anywhere on the grid.
fn footprint<const N: usize>(
    px: u32,
    py: u32,
    g: u32,
    f: &dyn Fn(f32, f32) -> Option<[f64; N]>,
) -> Option<([f64; N], [f64; N])> {
    let mut sum = [0.0; N];
    let mut sum2 = [0.0; N];
    for (x, y) in grid(px, py, g) {
        let v = f(x, y)?;
        for c in 0..N {
            sum[c] += v[c];
            sum2[c] += v[c] * v[c];
        }
    }
    let n = f64::from(g * g);
    let mean = sum.map(|s| s / n);
    let mut var = [0.0; N];
    for c in 0..N {
        var[c] = (sum2[c] / n - mean[c] * mean[c]).max(0.0);
    }
    Some((mean, var))
}

/// The expected pixel value of `f` and its tolerance at `spp` independent samples:
/// K·σ/√spp + |16×16 − 8×8 midpoint rule| + `abs` (f32 rounding).
fn expected<const N: usize>(
    px: u32,
    py: u32,
    spp: u32,
    abs: f64,
    f: &dyn Fn(f32, f32) -> Option<[f64; N]>,
) -> Option<([f64; N], [f64; N])> {
    let (fine, var) = footprint(px, py, 16, f)?;
    let (coarse, _) = footprint(px, py, 8, f)?;
    let mut tol = [0.0; N];
    for c in 0..N {
        tol[c] = K * (var[c] / f64::from(spp)).sqrt() + (fine[c] - coarse[c]).abs() + abs;
    }
    Some((fine, tol))
}

/// Value of channel `name` at pixel (x, y).
fn at(img: &LayeredImage, name: &str, x: u32, y: u32) -> f64 {
    f64::from(channel(img, name)[(y * img.width + x) as usize])
}

/// Ray–plane intersection (the plane through `c` with normal `n`): the hit point, if ahead.
fn hit_plane(o: Vec3, d: Vec3, c: Vec3, n: Vec3) -> Option<Vec3> {
    let t = (c - o).dot(n) / d.dot(n);
    (t > 0.0 && t.is_finite()).then(|| o + t * d)
}

fn independent(max_depth: i32, seed: u64) -> RenderSettings {
    RenderSettings {
        sampler: SamplerKind::Independent,
        ..settings(IntegratorKind::Path, max_depth, seed)
    }
}

/// A 20 m floor at y = −1 seen from 2 m above, the far edge within the frame, so that pixels
/// are fully covered, partly covered (the edge) or empty (the sky).
#[test]
fn position_and_depth_follow_the_camera_rays() {
    let (w, h, spp) = (32u32, 24u32, 16u32);
    let camera = Camera::look_at(Vec3::new(0.0, 1.0, 4.0), Vec3::new(0.0, -1.0, 0.0), Vec3::Y, 40.0);
    let mut scene = empty_scene(camera, w, h);
    let (floor_y, half) = (-1.0f32, 10.0f32);
    add_shape(
        &mut scene,
        "floor",
        square(Vec3::new(0.0, floor_y, 0.0), 2.0 * half, Vec3::Y),
        diffuse(Vec3::splat(0.5)),
    );
    let img = render(&scene, independent(1, 3), spp).image;

    let (eye, forward) = (camera.position(), camera.forward());
    let floor_hit = |x: f32, y: f32| {
        let d = camera.ray_direction(x, y, w, h);
        let p = hit_plane(eye, d, Vec3::new(0.0, floor_y, 0.0), Vec3::Y)?;
        (p.x.abs() <= half && p.z.abs() <= half).then_some(p)
    };
    let (mut covered, mut partial, mut empty, mut worst) = (0, 0, 0, 0.0f64);
    let mut not_euclidean = 0;
    for py in 0..h {
        for px in 0..w {
            let pos = [
                at(&img, "position.X", px, py),
                at(&img, "position.Y", px, py),
                at(&img, "position.Z", px, py),
            ];
            let depth = at(&img, "depth.Z", px, py);
            let coverage = at(&img, "coverage.Y", px, py);
            // depth is the distance along the view axis, (p − eye)·forward (film.rs); both
            // AOVs average over all samples with misses counted as 0, so for any coverage
            // depth = (position − coverage·eye)·forward.
            let from_pos: f64 = (0..3)
                .map(|c| (pos[c] - coverage * f64::from(eye[c])) * f64::from(forward[c]))
                .sum();
            assert!(
                (depth - from_pos).abs() <= 1e-5 * (1.0 + depth.abs()),
                "pixel ({px}, {py}): depth.Z {depth} vs (position − coverage·eye)·forward {from_pos}"
            );

            // Position and depth: the footprint means of the hit point and of (p − eye)·forward.
            let f = |x: f32, y: f32| {
                let p = floor_hit(x, y)?;
                Some([
                    f64::from(p.x),
                    f64::from(p.y),
                    f64::from(p.z),
                    f64::from((p - eye).dot(forward)),
                    f64::from((p - eye).length()),
                ])
            };
            // f32 rounding: a few ulps (2⁻²³ ≈ 1.2·10⁻⁷ relative) of coordinates ≤ 20 m.
            let all_corners = corners(px, py).all(|(x, y)| floor_hit(x, y).is_some());
            let Some((mean, tol)) = expected(px, py, spp, 1e-5, &f).filter(|_| all_corners) else {
                // coverage.Y is a Bernoulli mean of the footprint's covered fraction q; the
                // 16×16 grid resolves q to within its boundary cells (≤ 2·16 of 256 → 1/8).
                let hits = grid(px, py, 16)
                    .filter(|&(x, y)| floor_hit(x, y).is_some())
                    .count();
                let q = hits as f64 / 256.0;
                if hits == 0 {
                    empty += 1;
                } else {
                    partial += 1;
                }
                let tol = K * (q * (1.0 - q) / f64::from(spp)).sqrt() + 0.125;
                assert!(
                    (coverage - q).abs() <= tol,
                    "edge or sky pixel ({px}, {py}): coverage {coverage} vs covered fraction {q} ± {tol:.3}"
                );
                continue;
            };
            covered += 1;
            assert_eq!(coverage, 1.0, "covered pixel ({px}, {py})");
            let got = [pos[0], pos[1], pos[2], depth];
            for (c, name) in ["position.X", "position.Y", "position.Z", "depth.Z"]
                .iter()
                .enumerate()
            {
                let err = (got[c] - mean[c]).abs();
                worst = worst.max(err / tol[c]);
                assert!(
                    err <= tol[c],
                    "pixel ({px}, {py}) {name}: oracle {} vs footprint mean {} (tolerance {:.2e})",
                    got[c],
                    mean[c],
                    tol[c]
                );
            }
            // The Euclidean distance |p − eye| is another quantity (equal on the view axis):
            // counted where it falls outside the tolerance, so that a depth.Z of that meaning
            // would fail here.
            if (mean[4] - depth).abs() > tol[4] + tol[3] {
                not_euclidean += 1;
            }
        }
    }
    println!(
        "position/depth: {covered} covered, {partial} edge, {empty} empty pixels; worst error {worst:.3} of \
         its tolerance; the Euclidean distance differs from depth.Z beyond tolerance at {not_euclidean}"
    );
    assert!(
        covered >= 300 && partial >= 16 && empty >= 16,
        "the frame must show floor, its edge and sky: {covered}/{partial}/{empty}"
    );
    assert!(
        not_euclidean * 4 >= covered,
        "depth.Z is told from the Euclidean distance at only {not_euclidean} of {covered} pixels"
    );
}

/// A tilted, non-square rectangle: uv = ((s + 1)/2, (t + 1)/2) with
/// p = c + s·h_u + t·h_v (Mitsuba 3 `rectangle`, as oracle/src/geometry/rectangle.rs).
#[test]
fn uv_of_a_rectangle_follows_its_parameterisation() {
    let (w, h, spp) = (32u32, 32u32, 16u32);
    let camera = Camera::look_at(Vec3::new(0.0, 0.3, 3.0), Vec3::ZERO, Vec3::Y, 40.0);
    let mut scene = empty_scene(camera, w, h);
    let a = 30f32.to_radians();
    let (c, hu, hv) = (
        Vec3::new(0.1, -0.05, 0.0),
        0.9 * Vec3::new(a.cos(), 0.0, -a.sin()),
        Vec3::new(0.0, 0.6, 0.0),
    );
    add_shape(
        &mut scene,
        "card",
        Geometry::Rectangle {
            center: c,
            half_u: hu,
            half_v: hv,
        },
        diffuse(Vec3::splat(0.5)),
    );
    let img = render(&scene, independent(1, 5), spp).image;

    let (eye, n) = (camera.position(), hu.cross(hv).normalize());
    let uv_at = |x: f32, y: f32| {
        let p = hit_plane(eye, camera.ray_direction(x, y, w, h), c, n)?;
        // h_u ⟂ h_v: the coordinates are the projections on them.
        let st = Vec2::new(
            (p - c).dot(hu) / hu.length_squared(),
            (p - c).dot(hv) / hv.length_squared(),
        );
        (st.x.abs() <= 1.0 && st.y.abs() <= 1.0).then(|| {
            let uv = (st + Vec2::ONE) * 0.5;
            [f64::from(uv.x), f64::from(uv.y)]
        })
    };
    let (mut tested, mut worst) = (0, 0.0f64);
    for py in 0..h {
        for px in 0..w {
            let all_corners = corners(px, py).all(|(x, y)| uv_at(x, y).is_some());
            let Some((mean, tol)) = expected(px, py, spp, 1e-5, &uv_at).filter(|_| all_corners) else {
                continue;
            };
            tested += 1;
            let got = [at(&img, "uv.U", px, py), at(&img, "uv.V", px, py)];
            if [(w / 2, h / 2), (9, 14), (25, 21)].contains(&(px, py)) {
                println!(
                    "uv at ({px}, {py}): oracle ({:.4}, {:.4}), footprint mean ({:.4}, {:.4}) ± ({:.1e}, {:.1e})",
                    got[0], got[1], mean[0], mean[1], tol[0], tol[1]
                );
            }
            for c in 0..2 {
                let err = (got[c] - mean[c]).abs();
                worst = worst.max(err / tol[c]);
                assert!(
                    err <= tol[c],
                    "pixel ({px}, {py}) uv.{}: oracle {} vs footprint mean {} (tolerance {:.2e})",
                    ["U", "V"][c],
                    got[c],
                    mean[c],
                    tol[c]
                );
            }
        }
    }
    println!("uv: {tested} pixels; worst error {worst:.3} of its tolerance");
    assert!(tested >= 100, "only {tested} pixels fully on the rectangle");
}

/// Extent of an axis-aligned horizontal rectangle: (x0, x1, z0, z1, y).
fn horizontal_rect(scene: &Scene, name: &str) -> (f64, f64, f64, f64, f64) {
    let shape = scene.shapes.iter().find(|s| s.name == name).unwrap();
    let Geometry::Rectangle {
        center,
        half_u,
        half_v,
    } = shape.geometry
    else {
        panic!("{name} is not a rectangle")
    };
    let e = (half_u.abs() + half_v.abs()).as_dvec3();
    assert!(
        half_u.y == 0.0 && half_v.y == 0.0 && half_u.x * half_u.z == 0.0 && half_v.x * half_v.z == 0.0,
        "{name} must be horizontal and axis-aligned"
    );
    let c = center.as_dvec3();
    (c.x - e.x, c.x + e.x, c.z - e.z, c.z + e.z, c.y)
}

/// Solid angle of the rectangle [x0, x1] × [z0, z1] in a plane at height h above the point
/// (coordinates relative to the point's foot): inclusion–exclusion of the corner-anchored
/// solid angles atan(xz / (h·√(h² + x² + z²))) (e.g. Wikipedia, "Solid angle", rectangle).
fn rect_solid_angle(x0: f64, x1: f64, z0: f64, z1: f64, h: f64) -> f64 {
    let f = |x: f64, z: f64| (x * z / (h * (h * h + x * x + z * z).sqrt())).atan();
    f(x1, z1) - f(x0, z1) - f(x1, z0) + f(x0, z0)
}

/// The soft-shadow scene's light visibility at 48²: exactly 0 in the umbra, exactly 1 on
/// the lit floor and the blocker's top, and in between in the penumbra, where it matches the
/// unoccluded fraction of the light's solid angle (the oracle samples the light uniformly
/// by solid angle, oracle/src/light/rectangle.rs).
#[test]
fn light_visibility_in_umbra_penumbra_and_light() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/soft-shadow.toml");
    let mut scene = scenes::load(&path).unwrap();
    let (w, h, spp) = (48u32, 48u32, 1024u32);
    scene.film = Film { width: w, height: h };
    // Depth 1 (emitters seen directly): the visibility AOV of the first hit is all we need.
    let img = render(&scene, independent(1, 11), spp).image;
    let vis = "visibility.light.Y";

    let light = horizontal_rect(&scene, "light");
    let blocker = horizontal_rect(&scene, "blocker");
    let floor = horizontal_rect(&scene, "floor");
    // By similar triangles (the scene file's comment), from light height L and blocker height
    // B above the floor: a floor point x is occluded from light point x_l when the segment
    // crosses the blocker, i.e. x_l ∈ x + (L/B)·([b0, b1] − x).
    let (hl, hb) = (light.4 - floor.4, blocker.4 - floor.4);
    let k = hl / hb;
    // Umbra: that interval covers the light's; shadow (umbra and penumbra): it meets it.
    let umbra = (
        (k * blocker.0 - light.0) / (k - 1.0),
        (k * blocker.1 - light.1) / (k - 1.0),
        (k * blocker.2 - light.2) / (k - 1.0),
        (k * blocker.3 - light.3) / (k - 1.0),
    );
    let shadow = (
        (k * blocker.0 - light.1) / (k - 1.0),
        (k * blocker.1 - light.0) / (k - 1.0),
        (k * blocker.2 - light.3) / (k - 1.0),
        (k * blocker.3 - light.2) / (k - 1.0),
    );
    // The scene file: umbra 0.35 m and penumbrae 0.25 m wide along x, centred at x = 0.4.
    let close = |a: f64, b: f64| (a - b).abs() < 1e-6;
    assert!(
        close(umbra.1 - umbra.0, 0.35) && close(umbra.0 - shadow.0, 0.25) && close(umbra.0 + umbra.1, 0.8),
        "umbra {umbra:?}, shadow {shadow:?}"
    );

    // Visible fraction of the light's solid angle from floor point (x, z).
    let omega_light =
        |x: f64, z: f64| rect_solid_angle(light.0 - x, light.1 - x, light.2 - z, light.3 - z, hl);
    let visible = |x: f64, z: f64| {
        let (o0, o1) = (
            (k * blocker.0 - (k - 1.0) * x).max(light.0),
            (k * blocker.1 - (k - 1.0) * x).min(light.1),
        );
        let (p0, p1) = (
            (k * blocker.2 - (k - 1.0) * z).max(light.2),
            (k * blocker.3 - (k - 1.0) * z).min(light.3),
        );
        let occluded = if o0 < o1 && p0 < p1 {
            rect_solid_angle(o0 - x, o1 - x, p0 - z, p1 - z, hl)
        } else {
            0.0
        };
        1.0 - occluded / omega_light(x, z)
    };

    #[derive(Clone, Copy, PartialEq, Debug)]
    enum Region {
        Umbra,
        Penumbra,
        Lit,
    }
    // 1 cm from every boundary, far more than a 16×16 grid cell's footprint (< 3 mm).
    let m = 0.01;
    let region = |x: f64, z: f64| {
        let inside =
            |r: (f64, f64, f64, f64), m: f64| x > r.0 + m && x < r.1 - m && z > r.2 + m && z < r.3 - m;
        if inside(umbra, m) {
            Some(Region::Umbra)
        } else if !inside(shadow, -m) {
            Some(Region::Lit)
        } else if inside(shadow, m) && !inside(umbra, -m) {
            Some(Region::Penumbra)
        } else {
            None
        }
    };
    let (eye, cam) = (scene.camera.position(), scene.camera);
    // The first surface along a camera ray: the blocker's top (lit: nothing is above it) or
    // the floor, with its region; None elsewhere or within the margin of a boundary.
    let first_hit = |x: f32, y: f32| -> Option<(Region, f64)> {
        let d = cam.ray_direction(x, y, w, h).as_dvec3();
        let o = eye.as_dvec3();
        let on = |r: (f64, f64, f64, f64, f64)| {
            let t = (r.4 - o.y) / d.y;
            let p = o + t * d;
            (t > 0.0 && p.x >= r.0 - m && p.x <= r.1 + m && p.z >= r.2 - m && p.z <= r.3 + m).then_some(p)
        };
        if let Some(p) = on(blocker) {
            // Strictly inside the blocker's top, else too close to its silhouette.
            let b = blocker;
            return (p.x > b.0 + m && p.x < b.1 - m && p.z > b.2 + m && p.z < b.3 - m)
                .then_some((Region::Lit, 1.0));
        }
        let p = on(floor)?;
        Some((region(p.x, p.z)?, visible(p.x, p.z)))
    };

    let (mut counts, mut worst) = ([0usize; 3], 0.0f64);
    let mut row_report = Vec::new();
    for py in 0..h {
        for px in 0..w {
            let regions: Option<Vec<Region>> = grid(px, py, 16)
                .chain(corners(px, py))
                .map(|(x, y)| first_hit(x, y).map(|r| r.0))
                .collect();
            let Some(regions) = regions else { continue };
            let class = regions[0];
            if regions.iter().any(|&r| r != class) {
                continue;
            }
            let f = |x: f32, y: f32| first_hit(x, y).map(|(_, v)| [v]);
            let (mean, _) = footprint(px, py, 16, &f).unwrap();
            let (coarse, _) = footprint(px, py, 8, &f).unwrap();
            let p = mean[0];
            // Each sample is a Bernoulli draw of mean p (a uniform point of the footprint,
            // then a uniform direction towards the light): standard error √(p(1−p)/n).
            let tol = K * (p * (1.0 - p) / f64::from(spp)).sqrt() + (p - coarse[0]).abs() + 1e-6;
            let v = at(&img, vis, px, py);
            match class {
                Region::Umbra => assert_eq!(v, 0.0, "umbra pixel ({px}, {py}): visibility {v}"),
                Region::Lit => assert_eq!(v, 1.0, "lit pixel ({px}, {py}): visibility {v}"),
                Region::Penumbra => {
                    if p > 0.02 && p < 0.98 {
                        assert!(
                            v > 0.0 && v < 1.0,
                            "penumbra pixel ({px}, {py}): visibility {v}, expected {p:.3}"
                        );
                    }
                }
            }
            assert!(
                (v - p).abs() <= tol,
                "{class:?} pixel ({px}, {py}): visibility {v} vs the visible solid-angle fraction {p:.4} \
                 (tolerance {tol:.4})"
            );
            if tol > 1e-5 {
                worst = worst.max((v - p).abs() / tol);
            }
            counts[class as usize] += 1;
            if class == Region::Penumbra && py == h / 2 {
                row_report.push(format!("({px}: {v:.3} vs {p:.3})"));
            }
        }
    }
    println!(
        "visibility: {} umbra, {} penumbra, {} lit pixels; worst penumbra error {worst:.3} of its tolerance; \
         row {}: {}",
        counts[0],
        counts[1],
        counts[2],
        h / 2,
        row_report.join(" ")
    );
    assert!(
        counts[0] >= 10 && counts[1] >= 20 && counts[2] >= 500,
        "too few pixels classified (umbra, penumbra, lit): {counts:?}"
    );
}
