//! Light-map baking (oracle::bake) against closed forms: a point light's irradiance
//! E = I·cos θ/r² at every texel centre (and at the half-texel-shifted points of the broken
//! variant), a white furnace's E = π·L within the bake's own error bars, a static blocker's
//! shadow and a dynamic one's absence, dilation past a disk's edge, a box's six face cells,
//! and the errors for what cannot be baked (a sphere, a mesh without TEXCOORD_1 or with
//! overlapping or out-of-range uv1, a resolution of 0 or 65536).

use std::path::Path;

use std::sync::Arc;

use glam::{Vec2, Vec3};
use oracle::bake::{bake, BakeSettings};
use scenes::lightmap::ChartSurface;
use scenes::{Geometry, Mesh, Scene, Shape};

const FLOOR: &str = r#"
[camera]
eye = [0.0, 3.0, 3.0]
target = [0.0, 0.0, 0.0]
fov = 40.0
[film]
width = 16
height = 16
[[material]]
name = "grey"
type = "diffuse"
albedo = 0.5
[[shape]]
name = "floor"
type = "rectangle"
material = "grey"
center = [0.0, 0.0, 0.0]
half_u = [1.0, 0.0, 0.0]
half_v = [0.0, 0.0, -0.5]
"#;

fn scene(extra: &str) -> Scene {
    scenes::toml::load_str(&format!("{FLOOR}{extra}"), Path::new("bake-test.toml"))
        .unwrap_or_else(|e| panic!("{e}"))
}

fn settings(resolution: u32, spp: u32) -> BakeSettings {
    BakeSettings {
        resolution,
        padding: 1,
        dilation: 1,
        spp,
        max_depth: 2,
        seed: 0,
        dynamic: Vec::new(),
        texel_offset: 0.0,
    }
}

const POINT: &str = r#"
[[light]]
name = "bulb"
type = "point"
position = [0.3, 1.5, -0.2]
intensity = [4.0, 3.0, 2.0]
"#;

/// E at p on the floor (normal +Y) from the point light.
fn point_irradiance(p: Vec3) -> Vec3 {
    let d = Vec3::new(0.3, 1.5, -0.2) - p;
    Vec3::new(4.0, 3.0, 2.0) * (d.y / d.length()) / d.length_squared()
}

#[test]
fn a_point_light_gives_its_closed_form_at_every_texel_centre() {
    let s = scene(POINT);
    for offset in [0.0f32, 0.5] {
        let baked = bake(
            &s,
            &BakeSettings {
                texel_offset: offset,
                ..settings(16, 4)
            },
        )
        .unwrap();
        let map = &baked.map;
        let chart = &map.layout.charts[0];
        // The rectangle is twice as wide as deep: 16 × 8 texels.
        assert_eq!((chart.width, chart.height), (16, 8));
        for j in 0..chart.height {
            for i in 0..chart.width {
                let k = ((chart.y + j) * map.layout.width + chart.x + i) as usize;
                assert!(map.covered[k]);
                let p = chart.point(chart.texel_centre(i, j, offset)).unwrap().p;
                let want = point_irradiance(p);
                let got = map.irradiance[k];
                assert!(
                    (got - want).length() < 1e-4 * want.length(),
                    "offset {offset}, texel ({i}, {j}) at {p}: {got} vs {want}"
                );
                // A delta light and nothing to bounce off: no noise at all.
                assert!(map.variance[k].max_element() < 1e-10, "{}", map.variance[k]);
            }
        }
        // The padding ring is dilated from the chart's border.
        let corner = ((chart.y - 1) * map.layout.width + chart.x - 1) as usize;
        assert!(!map.covered[corner] && map.irradiance[corner].x > 0.0);
        assert!(baked.rays > 0);
    }
}

#[test]
fn a_white_furnace_gives_pi_times_the_radiance() {
    let s = scene("[environment]\nradiance = 0.7\n");
    let baked = bake(&s, &settings(8, 64)).unwrap();
    let map = &baked.map;
    let want = std::f32::consts::PI * 0.7;
    let mut mean = 0.0f64;
    let mut n = 0.0f64;
    for k in (0..map.covered.len()).filter(|&k| map.covered[k]) {
        let (e, v) = (map.irradiance[k].x, map.variance[k].x);
        assert!(
            (e - want).abs() <= 5.0 * v.sqrt().max(1e-6),
            "texel {k}: E = {e}, π·L = {want}, σ = {}",
            v.sqrt()
        );
        mean += f64::from(e);
        n += 1.0;
    }
    let mean = mean / n;
    assert!(
        (mean - f64::from(want)).abs() < 0.01 * f64::from(want),
        "mean E {mean} vs {want}"
    );
    assert!(
        baked.mean_relative_std_error < 0.05,
        "{}",
        baked.mean_relative_std_error
    );
}

#[test]
fn static_blockers_shadow_the_map_and_dynamic_ones_do_not() {
    // A small square 0.5 m under the light: static, it shadows the texels below it.
    let blocker = r#"
[[shape]]
name = "blocker"
type = "rectangle"
material = "grey"
center = [0.3, 1.0, -0.2]
half_u = [0.1, 0.0, 0.0]
half_v = [0.0, 0.0, -0.1]
"#;
    let s = scene(&format!("{POINT}{blocker}"));
    let floor_e = |baked: &oracle::bake::Baked, at: Vec3| {
        let map = &baked.map;
        let chart = map.layout.charts.iter().find(|c| c.name == "floor").unwrap();
        let c = glam::Vec2::new((at.x + 1.0) / 2.0, (-at.z + 0.5) / 1.0);
        let (i, j) = (
            (c.x * chart.width as f32) as u32,
            (c.y * chart.height as f32) as u32,
        );
        map.irradiance[((chart.y + j) * map.layout.width + chart.x + i) as usize]
    };
    let under = Vec3::new(0.3, 0.0, -0.2);
    let fixed = bake(&s, &settings(32, 1)).unwrap();
    assert_eq!(fixed.map.layout.charts.len(), 2);
    assert_eq!(floor_e(&fixed, under), Vec3::ZERO);
    let moving = bake(
        &s,
        &BakeSettings {
            dynamic: vec!["blocker".into()],
            ..settings(32, 1)
        },
    )
    .unwrap();
    assert_eq!(moving.map.layout.charts.len(), 1);
    assert!(floor_e(&moving, under).x > 0.5 * point_irradiance(under).x);
}

#[test]
fn a_disk_chart_is_dilated_past_its_edge() {
    let disk = FLOOR.replace("type = \"rectangle\"", "type = \"disk\"");
    let s = scenes::toml::load_str(&format!("{disk}{POINT}"), Path::new("bake-test.toml")).unwrap();
    let baked = bake(&s, &settings(16, 1)).unwrap();
    let map = &baked.map;
    let chart = &map.layout.charts[0];
    // Texels of the bounding parallelogram off the ellipse are not baked; those a bilinear
    // lookup at the ellipse's edge reads (next to a baked one) are filled from it.
    let (w, at) = (map.layout.width as i64, |i: u32, j: u32| {
        ((chart.y + j) * map.layout.width + chart.x + i) as usize
    });
    assert!(!map.covered[at(0, 0)] && map.covered[at(8, 4)]);
    let mut edge = 0;
    for j in 0..chart.height {
        for i in 0..chart.width {
            let k = at(i, j);
            let next_to_baked = [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)].iter().any(|(dx, dy)| {
                let q = k as i64 + dy * w + dx;
                q >= 0 && (q as usize) < map.covered.len() && map.covered[q as usize]
            });
            if !map.covered[k] && next_to_baked {
                assert!(
                    map.irradiance[k].x > 0.0,
                    "texel ({i}, {j}) beside the edge is unfilled"
                );
                edge += 1;
            }
        }
    }
    assert!(edge > 8, "{edge} edge texels");
}

#[test]
fn what_cannot_be_baked_is_refused_by_name() {
    let s = scene(POINT);
    for (resolution, want) in [(0, "resolution 0"), (65536, "resolution 65536")] {
        let e = bake(&s, &settings(resolution, 1)).unwrap_err();
        assert!(e.contains(want) && e.contains("1..=8192"), "{e}");
    }
    let ball = "[[shape]]\nname = \"ball\"\ntype = \"sphere\"\nmaterial = \"grey\"\ncenter = [0, 0.5, 0]\nradius = 0.2\n";
    let e = bake(&scene(ball), &settings(8, 1)).unwrap_err();
    assert!(
        e.contains("shape `ball`: a sphere has no light-map chart") && e.contains("dynamic"),
        "{e}"
    );
    let ico = "[[shape]]\nname = \"ico\"\ntype = \"icosphere\"\nmaterial = \"grey\"\ncenter = [0, 0.5, 0]\nradius = 0.2\nsubdivisions = 1\n";
    let e = bake(&scene(ico), &settings(8, 1)).unwrap_err();
    assert!(
        e.contains("shape `ico`: a triangle mesh without a second uv set (glTF TEXCOORD_1)"),
        "{e}"
    );
    // Two triangles on one uv triangle: two surface points would share each texel.
    let mut overlapping = s.clone();
    let tri = [
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::new(0.2, 0.5, 0.0),
        Vec3::new(0.0, 0.5, -0.2),
    ];
    let uv = [Vec2::new(0.1, 0.1), Vec2::new(0.9, 0.1), Vec2::new(0.1, 0.9)];
    overlapping.shapes.push(Shape {
        name: "folded".into(),
        geometry: Geometry::Mesh(Arc::new(Mesh {
            positions: [tri, tri.map(|p| p + Vec3::Y * 0.1)].concat(),
            uv1: [uv, uv].concat(),
            indices: vec![[0, 1, 2], [3, 4, 5]],
            ..Mesh::default()
        })),
        ..overlapping.shapes[0].clone()
    });
    let e = bake(&overlapping, &settings(8, 1)).unwrap_err();
    assert!(
        e.contains("shape `folded`: its TEXCOORD_1 triangles 0 and 1 overlap at"),
        "{e}"
    );
    if let Geometry::Mesh(m) = &mut overlapping.shapes[1].geometry {
        Arc::make_mut(m).uv1[4] = Vec2::new(1.5, 0.1);
    }
    let e = bake(&overlapping, &settings(8, 1)).unwrap_err();
    assert!(
        e.contains("shape `folded`: TEXCOORD_1 of vertex 4 is [1.5, 0.1], outside the chart's [0, 1]²"),
        "{e}"
    );
    let e = bake(
        &s,
        &BakeSettings {
            dynamic: vec!["flor".into()],
            ..settings(8, 1)
        },
    )
    .unwrap_err();
    assert!(
        e.contains("dynamic shape `flor` is not in the scene; shapes: floor"),
        "{e}"
    );
    assert!(bake(&s, &settings(8, 0))
        .unwrap_err()
        .contains("at least 1 sample"));
}

/// A box's chart: its six faces in the cells of a 3 × 2 grid (scenes `box_mesh`), each inset
/// by the gutter; the top face (cell 2) lit by the bulb above, the bottom face (cell 3, on the
/// floor's side) unlit at depth 2, and the gutters between cells left to dilation.
#[test]
fn a_box_bakes_one_cell_per_face() {
    let cube = "[[shape]]\nname = \"cube\"\ntype = \"box\"\nmaterial = \"grey\"\ncenter = [0, 0.5, 0]\nsize = [0.4, 0.4, 0.4]\n";
    let r = 48;
    let map = bake(&scene(&format!("{POINT}{cube}")), &settings(r, 4))
        .unwrap()
        .map;
    let chart = map.layout.charts.iter().find(|c| c.name == "cube").unwrap();
    assert!(matches!(chart.surface, ChartSurface::Mesh(_)));
    assert_eq!((chart.width, chart.height), (r, r));
    let (cw, ch) = (r / 3, r / 2);
    let mut covered = [0u32; 6];
    let mut mean = [0.0f32; 6];
    for j in 0..r {
        for i in 0..r {
            let k = ((chart.y + j) * map.layout.width + chart.x + i) as usize;
            if map.covered[k] {
                let face = (j / ch * 3 + i / cw) as usize;
                covered[face] += 1;
                mean[face] += map.irradiance[k].x;
            }
        }
    }
    // Each face: its cell less the 1/8 gutter on each side, (16·0.75) × (24·0.75) = 12 × 18.
    for (face, n) in covered.iter().enumerate() {
        assert!((200..=240).contains(n), "face {face}: {n} covered texels");
        mean[face] /= *n as f32;
    }
    assert!(
        mean[2] > 1.0 && mean[3] == 0.0,
        "top {} bottom {}",
        mean[2],
        mean[3]
    );
}
