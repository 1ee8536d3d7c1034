//! Surface-detail methods end to end on the adapter at hand (lavapipe in CI): texel-fetch
//! counts against each technique's lookups, every technique collapsing to the flat base on a
//! flat heightfield, forward and deferred agreeing (POM's self-shadowing included), the flat
//! base unchanged by a displacement, discarding past a patch's edge, and the cone maps'
//! cache. Accuracy against the oracle is measured by the surface-detail studies
//! (scenes/studies/detail-*.toml).

mod support;

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};
use realtime::{Detail, Method, PipelineKind, RasterSettings};
use scenes::displacement::Procedural;
use scenes::texture::Texture;
use scenes::*;
use support::{method, renderer};

/// A 1 m heightfield patch in the XY plane (normal +Z) displaced by `height` × `scale` m,
/// seen from `eye` (looking at its centre), lit by a low sun; it fills the view from the front.
fn patch_scene(height: Texture, scale: f32, eye: Vec3) -> Scene {
    Scene {
        source: PathBuf::from("<patch scene>"),
        camera: Camera::look_at(eye, Vec3::ZERO, Vec3::Y, 30.0),
        film: Film {
            width: 24,
            height: 24,
        },
        render: RenderSettings::default(),
        textures: vec![Arc::new(height)],
        materials: vec![Material::Diffuse {
            albedo: TexRgb::Constant(Vec3::splat(0.6)),
        }],
        shapes: vec![Shape {
            name: "patch".into(),
            geometry: Geometry::Rectangle {
                center: Vec3::ZERO,
                half_u: Vec3::new(0.5, 0.0, 0.0),
                half_v: Vec3::new(0.0, 0.5, 0.0),
            },
            material: 0,
            emission: None,
            normal_map: None,
            displacement: Some(Displacement {
                texture: 0,
                channel: 0,
                scale,
            }),
        }],
        lights: vec![Light::Directional {
            name: "sun".into(),
            direction: Vec3::new(0.7, -0.3, -0.4).normalize(),
            irradiance: Vec3::splat(3.0),
            angular_diameter_deg: 0.0,
        }],
        environment: None,
        provenance: Default::default(),
    }
}

fn bumps() -> Texture {
    Procedural::Bumps { tiles: 4 }.texture(64, [WrapMode::Clamp; 2])
}

fn render(scene: &Scene, m: &Method, pipeline: PipelineKind) -> realtime::RasterOutput {
    let s = RasterSettings::new(scene.film.width, scene.film.height)
        .method(m.clone())
        .pipeline(pipeline)
        .frames(0, 1)
        .counters(true);
    renderer()
        .render(scene, &s)
        .unwrap_or_else(|e| panic!("{m}: {e}"))
}

fn rgb(out: &realtime::RasterOutput) -> Vec<f32> {
    ["R", "G", "B"]
        .iter()
        .flat_map(|c| out.image.channel(c).expect("RGB").to_vec())
        .collect()
}

fn max_difference(a: &[f32], b: &[f32]) -> f32 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f32::max)
}

/// Seen head-on, the patch fills every pixel: the fetches per pixel are the technique's
/// lookups exactly (4 texels per bilinear lookup), and the marching ones stay within their
/// layer counts.
#[test]
fn texel_fetches_are_each_techniques_lookups() {
    let scene = patch_scene(bumps(), 0.05, Vec3::new(0.0, 0.0, 1.5));
    let fetches = |m: Method| {
        let c = render(&scene, &m, PipelineKind::Deferred)
            .counters
            .expect("counted");
        c.texel_fetches_per_pixel
    };
    let env0 = [("env_n", "0")];
    assert_eq!(fetches(method("area_quadrature", &env0)), 0.0, "flat base");
    assert_eq!(
        fetches(method("normal_mapping", &env0)),
        4.0,
        "one normal-map lookup"
    );
    assert_eq!(
        fetches(method("bump_mapping", &env0)),
        12.0,
        "three height lookups"
    );
    assert_eq!(fetches(method("parallax", &env0)), 8.0, "height, then normal map");
    assert_eq!(fetches(method("parallax_offset_limited", &env0)), 8.0);
    // Steep parallax with k layers: 1 to k + 1 height lookups, then the normal map.
    let steep = fetches(method("steep_parallax", &[("env_n", "0"), ("steps", "8")]));
    assert!(
        (8.0..=40.0).contains(&steep) && steep > 8.0,
        "steep parallax: {steep}"
    );
    // Relief mapping adds exactly 6 halvings to the same linear search.
    let relief = fetches(method(
        "relief_mapping",
        &[("env_n", "0"), ("steps", "8"), ("binary_steps", "6")],
    ));
    assert!(
        (relief - steep - 24.0).abs() < 1e-9,
        "relief {relief} vs steep {steep}"
    );
    // POM with min = max = 8 layers searches as steep parallax does; with more layers at
    // grazing incidence it searches more off the axis (the view is 15° wide here), but at
    // most the layers of cos θ = 0.9.
    let pom = |max: &str| {
        fetches(method(
            "pom",
            &[("env_n", "0"), ("min_steps", "8"), ("max_steps", max)],
        ))
    };
    let (pom8, pom64) = (pom("8"), pom("64"));
    assert!((pom8 - steep).abs() < 0.5, "pom {pom8} vs steep {steep}");
    assert!(
        pom64 > pom8 && pom64 < pom8 + 4.0 * 6.0,
        "pom: {pom8} (8 layers), {pom64} (8 to 64)"
    );
    // Cone stepping: 8 fetches per step (height and cone ratio) plus the normal map.
    let cone = |steps: &str| fetches(method("cone_step", &[("env_n", "0"), ("steps", steps)]));
    // (A ray that starts on a plateau's top stops before reading the cone ratio.)
    let one = cone("1");
    assert!(
        one <= 12.0 && one > 11.9,
        "one step: height, cone ratio, normal map: {one}"
    );
    let four = cone("4");
    assert!(
        (12.0..=36.0).contains(&four) && four > 20.0,
        "cone stepping, 4 steps: {four}"
    );
}

/// On a heightfield of constant height 0 every technique finds the base point and the base
/// normal: the image is the flat base's.
#[test]
fn a_flat_heightfield_gives_the_flat_base_under_every_technique() {
    let flat = Texture::from_texels(
        8,
        8,
        vec![Vec4::new(0.0, 0.0, 0.0, 1.0); 64],
        [WrapMode::Clamp; 2],
    );
    let scene = patch_scene(flat, 0.05, Vec3::new(0.4, 0.2, 1.2));
    let base = rgb(&render(
        &scene,
        &method("area_quadrature", &[("n", "8")]),
        PipelineKind::Forward,
    ));
    for spec in realtime::technique::detail::METHODS {
        let name = spec.name;
        let params: &[(&str, &str)] = if name == "pom" {
            &[("self_shadow", "on")]
        } else {
            &[]
        };
        let image = rgb(&render(&scene, &method(name, params), PipelineKind::Forward));
        let d = max_difference(&image, &base);
        assert!(d < 1e-5, "{name}: differs from the flat base by {d}");
    }
}

/// Forward and deferred shading give the same image under the detail methods (the G-buffer
/// carries the detailed surface point), and self-shadowing changes it.
#[test]
fn forward_and_deferred_agree_under_surface_detail() {
    let scene = patch_scene(bumps(), 0.06, Vec3::new(0.9, 0.3, 1.0));
    for (name, params) in [
        ("pom", &[("self_shadow", "on")][..]),
        ("relief_mapping", &[][..]),
        ("cone_step", &[("relaxed", "on")][..]),
    ] {
        let m = method(name, params);
        let f = rgb(&render(&scene, &m, PipelineKind::Forward));
        let d = rgb(&render(&scene, &m, PipelineKind::Deferred));
        let diff = max_difference(&f, &d);
        assert!(diff < 1e-4, "{m}: forward and deferred differ by {diff}");
    }
    let lit = rgb(&render(&scene, &method("pom", &[]), PipelineKind::Forward));
    let shadowed = rgb(&render(
        &scene,
        &method("pom", &[("self_shadow", "on")]),
        PipelineKind::Forward,
    ));
    let darker = lit
        .iter()
        .zip(&shadowed)
        .filter(|(a, b)| **b < **a - 1e-3)
        .count();
    let brighter = lit
        .iter()
        .zip(&shadowed)
        .filter(|(a, b)| **b > **a + 1e-6)
        .count();
    assert!(
        darker > 20,
        "self-shadowing darkened only {darker} channel values"
    );
    assert_eq!(brighter, 0, "self-shadowing only removes light");
}

/// Outside a detail method the displaced patch is drawn flat: the displacement changes nothing.
#[test]
fn without_a_detail_method_the_base_is_drawn() {
    let mut scene = patch_scene(bumps(), 0.05, Vec3::new(0.4, 0.2, 1.2));
    let m = method("area_quadrature", &[("n", "8")]);
    let displaced = rgb(&render(&scene, &m, PipelineKind::Forward));
    scene.shapes[0].displacement = None;
    let plain = rgb(&render(&scene, &m, PipelineKind::Forward));
    assert_eq!(displaced, plain);
}

/// Seen at a grazing angle across its edge, a marching technique discards where the ray
/// leaves the patch's uv square before meeting the surface (the patch ends there): a plateau
/// 15 cm above the base, met by rays that hit the base within 4 cm of the edge outside it.
#[test]
fn rays_leaving_the_patch_are_discarded() {
    let plateau = Texture::from_texels(8, 8, vec![Vec4::ONE; 64], [WrapMode::Clamp; 2]);
    let mut scene = patch_scene(plateau, 0.15, Vec3::new(1.6, 0.0, 0.3));
    scene.camera = Camera::look_at(Vec3::new(1.6, 0.0, 0.3), Vec3::new(0.45, 0.0, 0.0), Vec3::Y, 30.0);
    let coverage = |m: Method| -> f32 {
        let out = render(&scene, &m, PipelineKind::Forward);
        out.image.channel("coverage.Y").expect("coverage").iter().sum()
    };
    let flat = coverage(method("area_quadrature", &[]));
    let pom = coverage(method("pom", &[]));
    assert!(pom < flat - 1.0, "POM covers {pom} pixels, the flat base {flat}");
}

/// Cone and horizon maps are built once per height texture, kind and scale.
#[test]
fn cone_maps_are_cached_by_content() {
    let cache = realtime::technique::detail::ConeCache::default();
    let t = bumps();
    let kind = realtime::technique::detail::cone_map::ConeKind::Conservative;
    let a = cache.get(&t, 0, 0.05, kind);
    let b = cache.get(&t.clone(), 0, 0.05, kind);
    assert!(Arc::ptr_eq(&a, &b), "same heights: the same map");
    let c = cache.get(&t, 0, 0.1, kind);
    assert!(!Arc::ptr_eq(&a, &c), "another scale: another map");
    // Twice the heights, half the ratio (uv per metre).
    let (ra, rc) = (a[0].sample(Vec2::splat(0.3)).x, c[0].sample(Vec2::splat(0.3)).x);
    assert!((ra - 2.0 * rc).abs() <= 1e-3 * ra, "{ra} vs {rc}");
    let d = Detail::by_name("cone_step").unwrap();
    assert_eq!(d.technique.cone_kind(), Some(kind));
    // Horizon maps share the cache under their own arguments: 8 azimuths, two RGBA maps.
    let h = cache.horizon(&t, 0, 0.05, Vec2::ONE, 8);
    assert!(Arc::ptr_eq(&h, &cache.horizon(&t, 0, 0.05, Vec2::ONE, 8)));
    assert!(!Arc::ptr_eq(&h, &a) && h.len() == 2);
}
