//! The built-in scenes load, with the expected contents.

use std::path::PathBuf;

use glam::Vec3;
use scenes::{Environment, Geometry, IntegratorKind, Material, Scene, TexRgb};

fn builtin(name: &str) -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(name);
    scenes::load(&path).unwrap_or_else(|e| panic!("{name} does not load: {e}"))
}

fn count(scene: &Scene, pred: impl Fn(&Geometry) -> bool) -> usize {
    scene.shapes.iter().filter(|s| pred(&s.geometry)).count()
}

fn assert_close(what: &str, actual: Vec3, expected: Vec3) {
    assert!(
        (actual - expected).abs().max_element() < 1e-5,
        "{what}: expected {expected}, got {actual}"
    );
}

#[test]
fn cornell_box() {
    let s = builtin("cornell-box.toml");
    assert_eq!((s.film.width, s.film.height), (256, 256));
    assert_eq!(s.render.spp, 64);
    assert_eq!(s.render.integrator, IntegratorKind::Path);
    assert_eq!(s.materials.len(), 3);
    assert_eq!(s.shapes.len(), 8, "5 walls, 2 blocks, 1 light");
    assert_eq!(count(&s, |g| matches!(g, Geometry::Rectangle { .. })), 6);
    assert_eq!(
        count(&s, |g| matches!(g, Geometry::Mesh(m) if m.indices.len() == 12)),
        2
    );
    assert!(s.lights.is_empty() && s.environment.is_none());
    assert_eq!(s.light_names(), vec!["light".to_string()]);
    assert!((s.camera.fov_y_deg - 39.3).abs() < 1e-6);
    assert_close(
        "camera position",
        s.camera.position(),
        Vec3::new(0.278, 0.273, -0.8),
    );
    assert_close("camera forward", s.camera.forward(), Vec3::Z);

    let light = s.shapes.iter().find(|sh| sh.name == "light").unwrap();
    let e = light.emission.as_ref().unwrap();
    assert_eq!(e.radiance, TexRgb::Constant(Vec3::new(17.0, 12.0, 4.0)));
    assert!(!e.two_sided);
    let Geometry::Rectangle { half_u, half_v, .. } = light.geometry else {
        panic!("the light is a rectangle")
    };
    assert_close("light normal", half_u.cross(half_v).normalize(), Vec3::NEG_Y);
    let area = 4.0 * half_u.cross(half_v).length();
    assert!(
        (area - 0.130 * 0.105).abs() < 1e-7,
        "light area: expected 0.01365, got {area}"
    );

    // Every wall faces the inside: its front normal points at the box centre.
    let centre = Vec3::new(0.278, 0.2744, 0.2796);
    for wall in ["floor", "ceiling", "back", "left_red", "right_green"] {
        let shape = s.shapes.iter().find(|sh| sh.name == wall).unwrap();
        let Geometry::Rectangle {
            center,
            half_u,
            half_v,
        } = shape.geometry
        else {
            panic!("{wall} is a rectangle")
        };
        let n = half_u.cross(half_v);
        assert!(
            n.dot(centre - center) > 0.0,
            "{wall} faces away from the interior (normal {n})"
        );
    }
    let red = &s.materials[s.shapes.iter().find(|sh| sh.name == "left_red").unwrap().material];
    assert_eq!(
        *red,
        Material::Diffuse {
            albedo: TexRgb::Constant(Vec3::new(0.63, 0.065, 0.05))
        }
    );
    // The fitted blocks stand on the floor, and their top corners lie within 3 mm of the
    // measured ones (Cornell "Cornell Box Data", millimetres).
    let measured = [
        (
            "short_block",
            0.165,
            [(130.0, 65.0), (82.0, 225.0), (240.0, 272.0), (290.0, 114.0)],
        ),
        (
            "tall_block",
            0.330,
            [(423.0, 247.0), (265.0, 296.0), (314.0, 456.0), (472.0, 406.0)],
        ),
    ];
    for (block, height, corners) in measured {
        let shape = s.shapes.iter().find(|sh| sh.name == block).unwrap();
        let Geometry::Mesh(mesh) = &shape.geometry else {
            panic!("{block} is a mesh")
        };
        let (lo, hi) = shape.geometry.bounds();
        assert!(
            lo.y.abs() < 1e-6 && (hi.y - height).abs() < 1e-6,
            "{block} spans y {}..{}",
            lo.y,
            hi.y
        );
        for (x, z) in corners {
            let c = Vec3::new(x / 1000.0, height, z / 1000.0);
            let nearest = mesh
                .positions
                .iter()
                .map(|p| p.distance(c))
                .fold(f32::INFINITY, f32::min);
            assert!(
                nearest < 0.003,
                "{block}: measured corner {c} is {nearest} m from the model"
            );
        }
    }
}

#[test]
fn soft_shadow() {
    let s = builtin("soft-shadow.toml");
    assert_eq!((s.film.width, s.film.height, s.render.spp), (256, 256, 64));
    assert_eq!(s.shapes.len(), 3);
    assert_eq!(s.light_names(), vec!["light".to_string()]);
    assert!(s.environment.is_none() && s.lights.is_empty());
    // The camera looks at the middle of the shadow, x = 0.4 on the floor.
    let hit = {
        let (o, d) = (s.camera.position(), s.camera.forward());
        o + d * (-o.y / d.y)
    };
    assert_close("view centre on the floor", hit, Vec3::new(0.4, 0.0, 0.0));
}

#[test]
fn mirror_sphere() {
    let s = builtin("mirror-sphere.toml");
    assert_eq!((s.film.width, s.film.height, s.render.spp), (256, 256, 64));
    assert_eq!(s.shapes.len(), 3);
    assert_eq!(count(&s, |g| matches!(g, Geometry::Sphere { .. })), 2);
    assert!(s.light_names().is_empty());
    let Some(Environment::Map { texture, scale }) = s.environment else {
        panic!("expected an environment map, got {:?}", s.environment)
    };
    assert_eq!(scale, 1.0);
    let t = &s.textures[texture];
    assert_eq!((t.width, t.height), (512, 256));
    let mean = t.texels.iter().map(|x| x.truncate()).sum::<Vec3>() / t.texels.len() as f32;
    let min = t
        .texels
        .iter()
        .map(|x| x.min_element())
        .fold(f32::INFINITY, f32::min);
    assert!(min >= 0.0, "the environment has negative texels (min {min})");
    assert!(
        (mean.element_sum() / 3.0 - 0.714).abs() < 0.01,
        "mean environment radiance: expected 0.714 (prepare_hdri.sh), got {mean}"
    );
    let glossy = s.shapes.iter().find(|sh| sh.name == "glossy_sphere").unwrap();
    assert!(matches!(
        s.materials[glossy.material],
        Material::Ggx { roughness: scenes::TexScalar::Constant(r), .. } if r == 0.3
    ));
    let mirror = s.shapes.iter().find(|sh| sh.name == "mirror_sphere").unwrap();
    assert!(matches!(s.materials[mirror.material], Material::Mirror { .. }));
}

/// The other vendored environment maps (no built-in scene uses them yet): each loads as a
/// scene's `[environment] file`, non-negative, with the radiance prepare_hdri.sh reports, and
/// its brightest texel where the source image has it (row 0 = up).
#[test]
fn vendored_environment_maps() {
    // (file, mean radiance, max radiance, brightest texel (row, column))
    let maps = [
        // The setting sun, 3.2° above the horizon.
        ("venice_sunset_512.exr", 0.4405, 801.0, (123, 307)),
        // The studio's ring light, 42.7° up.
        ("studio_small_03_512.exr", 1.8939, 3730.0, (67, 118)),
    ];
    for (file, mean_expected, max_expected, brightest) in maps {
        let text = format!(
            "[camera]\neye = [0.0, 0.0, 0.0]\ntarget = [0.0, 0.0, -1.0]\nfov = 40.0\n\n\
             [environment]\nfile = \"assets/{file}\"\n"
        );
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("environment.toml");
        let s = scenes::toml::load_str(&text, &path).unwrap_or_else(|e| panic!("{file}: {e}"));
        let Some(Environment::Map { texture, scale }) = s.environment else {
            panic!("{file}: expected an environment map, got {:?}", s.environment)
        };
        assert_eq!(scale, 1.0);
        let t = &s.textures[texture];
        assert_eq!((t.width, t.height), (512, 256), "{file}");
        let min = t
            .texels
            .iter()
            .map(|x| x.truncate().min_element())
            .fold(f32::INFINITY, f32::min);
        assert!(min >= 0.0, "{file} has negative texels (min {min})");
        let mean = t.texels.iter().map(|x| x.truncate()).sum::<Vec3>() / t.texels.len() as f32;
        let mean = mean.element_sum() / 3.0;
        assert!(
            (mean - mean_expected).abs() < 0.01,
            "{file}: mean radiance: expected {mean_expected} (prepare_hdri.sh), got {mean}"
        );
        let (i, max) = t
            .texels
            .iter()
            .map(|x| x.truncate().max_element())
            .enumerate()
            .fold(
                (0, f32::NEG_INFINITY),
                |best, (i, m)| if m > best.1 { (i, m) } else { best },
            );
        assert!(
            (max - max_expected).abs() < 1e-3 * max_expected,
            "{file}: max radiance: expected {max_expected} (prepare_hdri.sh), got {max}"
        );
        let at = (i / t.width as usize, i % t.width as usize);
        assert_eq!(at, brightest, "{file}: brightest texel (row, column)");
    }
}

/// The worked example of `[[include]]` with `materials`, `transform` and `camera`: Suzanne in
/// the scene's clay, turned 25° about +Y and stood on the floor, seen through the asset's
/// camera (moved with it) on a film of its aspect ratio.
#[test]
fn include_asset() {
    let s = builtin("include-asset.toml");
    assert_eq!((s.film.width, s.film.height), (240, 160));
    assert_eq!(s.provenance.camera_aspect, Some(1.5));
    let suzanne = s
        .shapes
        .iter()
        .find(|sh| sh.name == "suzanne/0")
        .expect("the included mesh");
    assert_eq!(suzanne.material, 0, "the scene's clay");
    assert!(suzanne.emission.is_none() && suzanne.normal_map.is_none());
    let (lo, _) = suzanne.bounds(&s.textures);
    assert!(lo.y.abs() < 1e-3, "stands on the floor: lowest point {lo}");
    let (sin, cos) = 25f32.to_radians().sin_cos();
    assert_close(
        "eye",
        s.camera.position(),
        Vec3::new(3.1 * sin, 0.35 + 0.67, 3.1 * cos),
    );
    assert!((s.camera.fov_y_deg - 0.7f32.to_degrees()).abs() < 1e-4);
}
