//! Camera, film, render settings, lights, environment, includes and TOML syntax variants.

mod toml_support;

use glam::Vec3;
use scenes::{
    ComplexIor, Environment, Geometry, IntegratorKind, Light, Masking, Material, PixelFilter, RenderSettings,
    SamplerKind, Scattering, TexRgb,
};
use toml_support::{append, load_text, replace_line, scratch, BASE};

fn assert_vec(what: &str, actual: Vec3, expected: Vec3) {
    assert!(
        (actual - expected).abs().max_element() < 1e-5,
        "{what}: expected {expected}, got {actual}"
    );
}

#[test]
fn camera_film_and_render_defaults() {
    let dir = scratch("defaults");
    let s = load_text(&dir, BASE).unwrap();
    assert_eq!((s.film.width, s.film.height), (256, 256));
    assert_eq!(s.render, RenderSettings::default());
    assert_vec("eye", s.camera.position(), Vec3::new(0.0, 1.0, 5.0));
    assert_vec(
        "forward",
        s.camera.forward(),
        Vec3::new(0.0, -1.0, -5.0).normalize(),
    );
    assert_eq!(s.camera.fov_y_deg, 40.0);
    // The centre ray goes to the target; the top of the image is towards +Y.
    assert_vec(
        "centre ray",
        s.camera.ray_direction(128.0, 128.0, 256, 256),
        s.camera.forward(),
    );
    assert!(s.camera.ray_direction(128.0, 0.0, 256, 256).y > s.camera.forward().y);
    assert_eq!(s.source, dir.join("bad.toml"));
}

/// `distance`/`azimuth`/`elevation` put the eye on an orbit about the target.
#[test]
fn orbit_camera() {
    let dir = scratch("orbit");
    let eye_of = |with: &str| load_text(&dir, &replace_line(2, with)).unwrap().camera.position();
    assert_vec("default angles", eye_of("distance = 5"), Vec3::new(0.0, 0.0, 5.0));
    assert_vec(
        "azimuth 90",
        eye_of("distance = 2\nazimuth = 90"),
        Vec3::new(2.0, 0.0, 0.0),
    );
    let e = eye_of("distance = 2\nazimuth = 180\nelevation = 30");
    assert_vec("azimuth 180, elevation 30", e, Vec3::new(0.0, 1.0, -3f32.sqrt()));
    // The same camera as the equivalent eye.
    let a = load_text(
        &dir,
        &replace_line(2, "distance = 5.0990195\nelevation = 11.309932"),
    )
    .unwrap();
    let b = load_text(&dir, BASE).unwrap();
    assert_vec("as eye", a.camera.position(), b.camera.position());
    assert_vec("forward", a.camera.forward(), b.camera.forward());
}

#[test]
fn render_settings_are_read() {
    let dir = scratch("render-ok");
    let text = append(
        "[film]\nwidth = 640\nheight = 360\n\n[render]\nspp = 1024\nintegrator = \"ao\"\nmax_depth = -1\n\
         rr_depth = 3\nseed = 42\nao_radius = 0.25\nsampler = \"independent\"\npixel_filter = \"centre\"\n",
    );
    let s = load_text(&dir, &text).unwrap();
    assert_eq!((s.film.width, s.film.height), (640, 360));
    let want = RenderSettings {
        spp: 1024,
        integrator: IntegratorKind::Ao,
        max_depth: -1,
        rr_depth: 3,
        ao_radius: 0.25,
        seed: 42,
        sampler: SamplerKind::Independent,
        pixel_filter: PixelFilter::Centre { ssaa: 1 },
    };
    assert_eq!(s.render, want);
}

/// `centre` and `center` read as one filter, printed `centre`; `box` is the default.
#[test]
fn pixel_filters_are_read_by_either_spelling_and_printed_by_one() {
    let dir = scratch("render-pixel-filters");
    for (spelling, filter) in PixelFilter::SPELLINGS {
        let text = append(&format!("[render]\npixel_filter = \"{spelling}\"\n"));
        let s = load_text(&dir, &text).unwrap();
        assert_eq!(s.render.pixel_filter, filter, "{spelling}");
    }
    let centre = load_text(&dir, &append("[render]\npixel_filter = \"center\"\n")).unwrap();
    assert_eq!(centre.render.pixel_filter.name(), "centre");
    assert_eq!(
        load_text(&dir, BASE).unwrap().render.pixel_filter,
        PixelFilter::Box
    );
}

/// One integrator, one printed name; both spellings of `direct-unshadowed` are read.
#[test]
fn integrators_are_read_by_either_spelling_and_printed_by_one() {
    let dir = scratch("render-integrators");
    for (spelling, kind) in IntegratorKind::SPELLINGS {
        let text = append(&format!("[render]\nintegrator = \"{spelling}\"\n"));
        let s = load_text(&dir, &text).unwrap();
        assert_eq!(s.render.integrator, kind, "{spelling}");
        assert_eq!(kind.name().replace('-', "_"), spelling.replace('-', "_"));
    }
    let e = load_text(&dir, &append("[render]\nintegrator = \"direct unshadowed\"\n"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("render.integrator") && e.contains("`direct-unshadowed`, `direct_unshadowed`"),
        "{e}"
    );
}

#[test]
fn lights_are_read_with_defaults() {
    let dir = scratch("lights-ok");
    let text = append(
        r#"[[light]]
name = "bulb"
type = "point"
position = [0, 3, 0]
intensity = [10, 10, 5]

[[light]]
name = "spot"
type = "spot"
position = [0, 4, 0]
target = [0, 0, 3]
intensity = 100

[[light]]
name = "sun"
type = "directional"
direction = [1, -1, 0]
irradiance = [3, 3, 3]
angular_diameter = 0.53
"#,
    );
    let s = load_text(&dir, &text).unwrap();
    assert_eq!(s.light_names(), vec!["bulb", "spot", "sun"]);
    assert_eq!(
        s.lights[0],
        Light::Point {
            name: "bulb".into(),
            position: Vec3::new(0.0, 3.0, 0.0),
            intensity: Vec3::new(10.0, 10.0, 5.0)
        }
    );
    let Light::Spot {
        direction,
        intensity,
        cutoff_deg,
        beam_width_deg,
        ..
    } = &s.lights[1]
    else {
        panic!("{:?}", s.lights[1])
    };
    assert_vec(
        "spot direction from target",
        *direction,
        Vec3::new(0.0, -4.0, 3.0) / 5.0,
    );
    assert_eq!(
        (*intensity, *cutoff_deg, *beam_width_deg),
        (Vec3::splat(100.0), 20.0, 15.0)
    );
    let Light::Directional {
        direction,
        angular_diameter_deg,
        ..
    } = &s.lights[2]
    else {
        panic!("{:?}", s.lights[2])
    };
    assert_vec(
        "sun direction (normalised)",
        *direction,
        Vec3::new(1.0, -1.0, 0.0).normalize(),
    );
    assert_eq!(*angular_diameter_deg, 0.53);
}

#[test]
fn materials_are_read_with_defaults() {
    let dir = scratch("materials-ok");
    let text = append(
        r#"[[material]]
name = "gold"
type = "ggx"
f0 = [1.0, 0.78, 0.34]
roughness = 0.2
masking = "separable"

[[material]]
name = "plastic"
type = "metal_rough"
metallic = 0

[[material]]
name = "glass"
type = "dielectric"
int_ior = 1.5

[[material]]
name = "shiny"
type = "phong"
reflectance = 0.5
exponent = 100
"#,
    );
    let s = load_text(&dir, &text).unwrap();
    assert_eq!(
        s.materials[0],
        Material::Diffuse {
            albedo: TexRgb::Constant(Vec3::splat(0.5))
        }
    );
    assert_eq!(
        s.materials[1],
        Material::Ggx {
            reflectance: TexRgb::Constant(Vec3::ONE),
            f0: Vec3::new(1.0, 0.78, 0.34),
            roughness: scenes::TexScalar::Constant(0.2),
            masking: Masking::Separable,
            scattering: Scattering::Single,
            conductor: None,
        }
    );
    assert_eq!(
        s.materials[2],
        Material::MetalRough {
            base_color: TexRgb::Constant(Vec3::ONE),
            metallic: scenes::TexScalar::Constant(0.0),
            roughness: scenes::TexScalar::Constant(1.0),
            scattering: Scattering::Single,
        }
    );
    assert_eq!(
        s.materials[3],
        Material::Dielectric {
            int_ior: 1.5,
            ext_ior: 1.000_277
        }
    );
    assert_eq!(
        s.materials[4],
        Material::Phong {
            reflectance: TexRgb::Constant(Vec3::splat(0.5)),
            exponent: 100.0
        }
    );
}

/// `scattering` selects the multiple-scattering ground truth on the two microfacet
/// materials; anywhere else, or with the separable masking the random walk cannot have, it
/// is a one-line error naming the file, line and field.
#[test]
fn scattering_is_read_and_checked() {
    let dir = scratch("scattering");
    let text = append(
        r#"[[material]]
name = "gold"
type = "ggx"
roughness = 0.7
scattering = "multiple"

[[material]]
name = "metal"
type = "metal_rough"
scattering = "multiple"

[[material]]
name = "plain"
type = "metal_rough"
scattering = "single"
"#,
    );
    let s = load_text(&dir, &text).unwrap();
    assert!(matches!(
        s.materials[1],
        Material::Ggx {
            scattering: Scattering::Multiple,
            masking: Masking::HeightCorrelated,
            ..
        }
    ));
    assert!(matches!(
        s.materials[2],
        Material::MetalRough {
            scattering: Scattering::Multiple,
            ..
        }
    ));
    assert!(matches!(
        s.materials[3],
        Material::MetalRough {
            scattering: Scattering::Single,
            ..
        }
    ));
    let on_diffuse = append("[[material]]\nname = \"d\"\ntype = \"diffuse\"\nscattering = \"multiple\"\n");
    toml_support::expect_error(
        load_text(&dir, &on_diffuse),
        &[
            "bad.toml:20:",
            "scattering",
            "a diffuse material has no microsurface",
            "ggx and metal_rough",
        ],
    );
    let on_glass = append("[[material]]\nname = \"g\"\ntype = \"dielectric\"\nscattering = \"multiple\"\n");
    toml_support::expect_error(
        load_text(&dir, &on_glass),
        &["bad.toml:20:", "a dielectric material has no microsurface"],
    );
    let separable = append(
        "[[material]]\nname = \"g\"\ntype = \"ggx\"\nroughness = 0.5\nmasking = \"separable\"\nscattering = \"multiple\"\n",
    );
    toml_support::expect_error(
        load_text(&dir, &separable),
        &[
            "bad.toml:21:",
            "masking",
            "multiple scattering needs height-correlated masking",
        ],
    );
    let unknown =
        append("[[material]]\nname = \"g\"\ntype = \"ggx\"\nroughness = 0.5\nscattering = \"double\"\n");
    toml_support::expect_error(
        load_text(&dir, &unknown),
        &["bad.toml:21:", "scattering", "single", "multiple"],
    );
}

/// A GGX conductor's exact Fresnel: `eta` and `k` together, not with Schlick's `f0`, in range.
#[test]
fn conductor_is_read_and_checked() {
    let dir = scratch("conductor");
    let gold = "[[material]]\nname = \"gold\"\ntype = \"ggx\"\nroughness = 0.3\neta = [0.166, 0.433, 1.51]\nk = [3.15, 2.32, 1.88]\n";
    let s = load_text(&dir, &append(gold)).unwrap();
    assert!(matches!(
        s.materials[1],
        Material::Ggx {
            conductor: Some(ComplexIor { eta, k }),
            ..
        } if eta == Vec3::new(0.166, 0.433, 1.51) && k == Vec3::new(3.15, 2.32, 1.88)
    ));
    toml_support::expect_error(
        load_text(&dir, &append(&gold.replace("k = [3.15, 2.32, 1.88]\n", ""))),
        &["bad.toml:21:", "eta", "a conductor needs both eta and k"],
    );
    toml_support::expect_error(
        load_text(&dir, &append(&format!("{gold}f0 = 0.9\n"))),
        &["bad.toml:23:", "f0", "exact conductor Fresnel"],
    );
    toml_support::expect_error(
        load_text(&dir, &append(&gold.replace("eta = [0.166", "eta = [0.0"))),
        &["bad.toml:21:", "eta", "must lie in (0, 100]"],
    );
    toml_support::expect_error(
        load_text(&dir, &append(&gold.replace("k = [3.15", "k = [-1"))),
        &["bad.toml:22:", "k", "must lie in [0, 100]"],
    );
}

#[test]
fn constant_environment() {
    let dir = scratch("env-const");
    let s = load_text(&dir, &append("[environment]\nradiance = 0.25\n")).unwrap();
    assert_eq!(
        s.environment,
        Some(Environment::Constant {
            radiance: Vec3::splat(0.25)
        })
    );
}

#[test]
fn dotted_keys_and_inline_tables_are_equivalent() {
    let dir = scratch("dotted");
    let inline =
        "[[shape]]\nname = \"lamp\"\ntype = \"disk\"\nmaterial = \"m\"\ncenter = [0, 3, 0]\nradius = 0.5\n\
                  normal = [0, -1, 0]\nemission = { radiance = [5, 5, 5], two_sided = true }\n";
    let dotted = inline.replace(
        "emission = { radiance = [5, 5, 5], two_sided = true }",
        "emission.radiance = [5, 5, 5]\nemission.two_sided = true",
    );
    let a = load_text(&dir, &append(inline)).unwrap();
    let b = load_text(&dir, &append(&dotted)).unwrap();
    assert_eq!(a.shapes, b.shapes);
    assert!(b.shapes[1].emission.as_ref().unwrap().two_sided);
    // Errors inside an implicit (dotted) table still know their line.
    let bad = dotted.replace("emission.two_sided = true", "emission.two_sided = 1");
    toml_support::expect_error(
        load_text(&dir, &append(&bad)),
        &[
            "bad.toml:25:",
            "`shape \"lamp\".emission.two_sided`",
            "expected true or false",
        ],
    );
    // Whole-table syntax for the camera works the same as a [camera] section.
    let inline_camera = replace_line(
        1,
        "camera = { eye = [0, 1, 5], target = [0, 0, 0], fov = 40 }\n[unused]",
    )
    .replace("[unused]\neye = [0, 1, 5]\ntarget = [0, 0, 0]\nfov = 40\n", "");
    let c = load_text(&dir, &inline_camera).unwrap_or_else(|e| panic!("{e}\n{inline_camera}"));
    assert_eq!(c.camera, a.camera);
}

#[test]
fn included_gltf_is_merged() {
    let assets = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets");
    let glb = assets.join("suzanne.glb");
    let alone = scenes::gltf::load(&glb).unwrap_or_else(|e| panic!("the glTF asset must load: {e}"));
    let dir = scratch("include");
    let text = append(&format!("[[include]]\nfile = {:?}\n", glb.display().to_string()));
    let s = load_text(&dir, &text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.shapes.len(), 1 + alone.shapes.len());
    assert_eq!(s.materials.len(), 1 + alone.materials.len());
    assert!(
        s.shapes[1..].iter().all(|sh| sh.material >= 1),
        "included shapes use included materials"
    );
    assert!(matches!(s.shapes[1].geometry, Geometry::Mesh(_)) || alone.shapes.is_empty());
    // The scene file's camera wins.
    assert_vec(
        "camera from the TOML",
        s.camera.position(),
        Vec3::new(0.0, 1.0, 5.0),
    );
    // A name clash between the scene file and the asset is an error on the include. Shape
    // names an asset generates hold a `/` ("mesh/0"), which a scene file cannot write, so the
    // clash comes from a light: a glTF point light named like the scene's shape `s`.
    assert!(alone.shapes.iter().all(|sh| sh.name.contains('/')));
    let lit = dir.join("lit.gltf");
    std::fs::write(
        &lit,
        r#"{"asset":{"version":"2.0"},"extensionsUsed":["KHR_lights_punctual"],
           "extensions":{"KHR_lights_punctual":{"lights":[{"type":"point","name":"s","intensity":1}]}},
           "nodes":[{"extensions":{"KHR_lights_punctual":{"light":0}}}],"scenes":[{"nodes":[0]}],"scene":0}"#,
    )
    .unwrap();
    let clash = append(&format!("[[include]]\nfile = {:?}\n", lit.display().to_string()));
    toml_support::expect_error(
        load_text(&dir, &clash),
        &[
            "bad.toml:18:",
            "`include[0].file`",
            "the included light \"s\" has the same name as shape on line 11",
        ],
    );
}

/// `enabled = false` leaves a shape or an include out, after checking it.
#[test]
fn disabled_shapes_and_includes_are_left_out() {
    let dir = scratch("enabled");
    let second =
        "[[shape]]\nname = \"t\"\ntype = \"sphere\"\nmaterial = \"m\"\ncenter = [3, 0, 0]\nradius = 1\n";
    let both = load_text(&dir, &append(second)).unwrap();
    assert_eq!(both.shapes.len(), 2);
    let off = load_text(&dir, &append(&format!("{second}enabled = false\n"))).unwrap();
    assert_eq!(off.shapes.len(), 1);
    assert_eq!(off.shapes[0].name, "s");
    let on = load_text(&dir, &append(&format!("{second}enabled = true\n"))).unwrap();
    assert_eq!(on.shapes.len(), 2);
    // A disabled shape is still checked: a bad radius is an error.
    let bad = second.replace("radius = 1", "radius = -1");
    assert!(load_text(&dir, &append(&format!("{bad}enabled = false\n"))).is_err());
    // `enabled` must be a boolean.
    toml_support::expect_error(
        load_text(&dir, &append(&format!("{second}enabled = 0\n"))),
        &["enabled"],
    );
    let glb = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/suzanne.glb");
    let include = format!(
        "[[include]]\nfile = {:?}\nenabled = false\n",
        glb.display().to_string()
    );
    assert_eq!(load_text(&dir, &append(&include)).unwrap().shapes.len(), 1);
}
