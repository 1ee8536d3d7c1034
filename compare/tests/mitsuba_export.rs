//! The Mitsuba exporter, element by element: the XML it writes for each feature, the files
//! beside it, and the message of each refusal.

use std::sync::Arc;

use compare::mitsuba::export::{export, Asset, Export};
use glam::{Vec2, Vec3, Vec4};
use scenes::texture::Texture;
use scenes::{
    Camera, Displacement, Emission, Environment, Film, Geometry, IntegratorKind, Light, Masking, Material,
    Mesh, NormalMap, PixelFilter, RenderSettings, Scattering, Scene, Shape, TexRgb, TexScalar, WrapMode,
};

fn scene(materials: Vec<Material>, shapes: Vec<Shape>) -> Scene {
    Scene {
        source: "test.toml".into(),
        camera: Camera::look_at(Vec3::new(0.0, 1.0, 4.0), Vec3::ZERO, Vec3::Y, 35.0),
        film: Film {
            width: 40,
            height: 30,
        },
        render: RenderSettings {
            spp: 16,
            max_depth: 5,
            rr_depth: 3,
            seed: 7,
            ..RenderSettings::default()
        },
        textures: vec![],
        materials,
        shapes,
        lights: vec![],
        environment: None,
        provenance: Default::default(),
    }
}

fn sphere(name: &str, material: usize) -> Shape {
    Shape {
        name: name.into(),
        geometry: Geometry::Sphere {
            center: Vec3::new(1.0, 2.0, 3.0),
            radius: 0.5,
        },
        material,
        emission: None,
        normal_map: None,
        displacement: None,
    }
}

fn diffuse(a: f32) -> Material {
    Material::Diffuse {
        albedo: TexRgb::Constant(Vec3::splat(a)),
    }
}

fn ok(s: &Scene) -> Export {
    export(s).unwrap_or_else(|e| panic!("expected an export, got: {e}"))
}

/// The export's XML with all whitespace runs collapsed, for substring checks.
fn xml(s: &Scene) -> String {
    ok(s).xml.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn assert_has(xml: &str, needle: &str) {
    assert!(xml.contains(needle), "expected `{needle}` in\n{xml}");
}

fn refusal(s: &Scene) -> String {
    match export(s) {
        Ok(e) => panic!("expected a refusal, got\n{}", e.xml),
        Err(e) => e.to_string(),
    }
}

#[test]
fn integrator_camera_film_and_sampler() {
    let x = xml(&scene(vec![diffuse(0.5)], vec![sphere("s", 0)]));
    assert_has(
        &x,
        r#"<integrator type="path"> <integer name="max_depth" value="5"/> <integer name="rr_depth" value="3"/>"#,
    );
    assert_has(
        &x,
        r#"<sensor type="perspective"> <string name="fov_axis" value="y"/> <float name="fov" value="35.0"/>"#,
    );
    assert_has(&x, r#"<lookat origin="0.0, 1.0, 4.0""#);
    assert_has(
        &x,
        r#"<sampler type="independent"> <integer name="sample_count" value="16"/> <integer name="seed" value="7"/>"#,
    );
    assert_has(
        &x,
        r#"<integer name="width" value="40"/> <integer name="height" value="30"/>"#,
    );
    assert_has(
        &x,
        r#"<string name="pixel_format" value="rgb"/> <string name="component_format" value="float32"/> <rfilter type="box"/>"#,
    );
}

#[test]
fn lookat_target_is_along_the_view_direction() {
    let s = scene(vec![diffuse(0.5)], vec![sphere("s", 0)]);
    let x = ok(&s).xml;
    let target = x
        .split("target=\"")
        .nth(1)
        .and_then(|t| t.split('"').next())
        .expect("a target");
    let v: Vec<f32> = target.split(", ").map(|c| c.parse().unwrap()).collect();
    let want = s.camera.position() + s.camera.forward();
    assert!(
        (Vec3::new(v[0], v[1], v[2]) - want).length() < 1e-6,
        "lookat target: expected {want}, got {target}"
    );
}

#[test]
fn direct_without_specular_surfaces_is_path_depth_2() {
    let mut s = scene(vec![diffuse(0.5)], vec![sphere("s", 0)]);
    s.render.integrator = IntegratorKind::Direct;
    s.render.max_depth = -1;
    assert_has(&xml(&s), r#"<integer name="max_depth" value="2"/>"#);
}

#[test]
fn materials_map_to_twosided_bsdfs_except_the_dielectric() {
    let materials = vec![
        diffuse(0.25),
        Material::Mirror {
            reflectance: Vec3::new(0.9, 0.8, 0.7),
        },
        Material::Ggx {
            reflectance: TexRgb::Constant(Vec3::splat(0.5)),
            f0: Vec3::ONE,
            roughness: TexScalar::Constant(0.5),
            masking: Masking::Separable,
            scattering: Scattering::Single,
            conductor: None,
        },
        Material::Dielectric {
            int_ior: 1.5,
            ext_ior: 1.25,
        },
    ];
    let shapes = (0..4).map(|i| sphere(&format!("s{i}"), i)).collect();
    let x = xml(&scene(materials, shapes));
    assert_has(
        &x,
        r#"<bsdf type="twosided" id="bsdf-0"> <bsdf type="diffuse"> <rgb name="reflectance" value="0.25, 0.25, 0.25"/>"#,
    );
    assert_has(
        &x,
        r#"<bsdf type="twosided" id="bsdf-1"> <bsdf type="conductor"> <string name="material" value="none"/> <rgb name="specular_reflectance" value="0.9, 0.8, 0.7"/>"#,
    );
    // alpha = roughness² = 0.25.
    assert_has(
        &x,
        r#"<bsdf type="roughconductor"> <string name="distribution" value="ggx"/> <float name="alpha" value="0.25"/> <boolean name="sample_visible" value="true"/> <string name="material" value="none"/> <rgb name="specular_reflectance" value="0.5, 0.5, 0.5"/>"#,
    );
    assert_has(
        &x,
        r#"<bsdf type="dielectric" id="bsdf-3"> <float name="int_ior" value="1.5"/> <float name="ext_ior" value="1.25"/>"#,
    );
    assert!(
        !x.contains(r#"type="twosided" id="bsdf-3""#),
        "the dielectric must stay one-sided"
    );
}

#[test]
fn unused_materials_are_not_exported_and_cannot_refuse() {
    let phong = Material::Phong {
        reflectance: TexRgb::Constant(Vec3::ONE),
        exponent: 10.0,
    };
    let x = xml(&scene(vec![diffuse(0.5), phong], vec![sphere("s", 0)]));
    assert!(!x.contains("bsdf-1"), "unused material exported:\n{x}");
}

#[test]
fn shapes_sphere_rectangle_disk_and_area_emission() {
    let mut rect = sphere("lamp", 0);
    rect.geometry = Geometry::Rectangle {
        center: Vec3::new(1.0, 2.0, 3.0),
        half_u: Vec3::new(2.0, 0.0, 0.0),
        half_v: Vec3::new(0.0, 0.0, -3.0),
    };
    rect.emission = Some(Emission {
        radiance: TexRgb::Constant(Vec3::new(5.0, 4.0, 3.0)),
        two_sided: false,
    });
    let mut disk = sphere("d", 0);
    disk.geometry = Geometry::Disk {
        center: Vec3::ZERO,
        half_u: Vec3::new(0.0, 0.0, 1.0),
        half_v: Vec3::new(1.0, 0.0, 0.0),
    };
    let x = xml(&scene(vec![diffuse(0.5)], vec![sphere("ball", 0), rect, disk]));
    assert_has(
        &x,
        r#"<shape type="sphere" id="shape-0-ball"> <point name="center" value="1.0, 2.0, 3.0"/> <float name="radius" value="0.5"/> <ref id="bsdf-0"/>"#,
    );
    // Columns (half_u, half_v, n, center) with n = normalize((2,0,0) × (0,0,−3)) = +Y.
    assert_has(
        &x,
        r#"<shape type="rectangle" id="shape-1-lamp"> <transform name="to_world"> <matrix value="2.0 0.0 0.0 1.0 0.0 0.0 1.0 2.0 0.0 -3.0 0.0 3.0 0.0 0.0 0.0 1.0"/>"#,
    );
    assert_has(
        &x,
        r#"<emitter type="area"> <rgb name="radiance" value="5.0, 4.0, 3.0"/> </emitter>"#,
    );
    // n = (0,0,1) × (1,0,0) = +Y.
    assert_has(
        &x,
        r#"<shape type="disk" id="shape-2-d"> <transform name="to_world"> <matrix value="0.0 1.0 0.0 0.0 0.0 0.0 1.0 0.0 1.0 0.0 0.0 0.0 0.0 0.0 0.0 1.0"/>"#,
    );
}

#[test]
fn meshes_become_ply_files() {
    let tri = |normals: bool| Mesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        normals: if normals { vec![Vec3::Z; 3] } else { vec![] },
        uvs: vec![Vec2::ZERO, Vec2::X, Vec2::Y],
        tangents: vec![],
        indices: vec![[0, 1, 2]],
        uv1: Vec::new(),
    };
    let mut smooth = sphere("smooth one", 0);
    smooth.geometry = Geometry::Mesh(Arc::new(tri(true)));
    let mut flat = sphere("flat", 0);
    flat.geometry = Geometry::Mesh(Arc::new(tri(false)));
    let e = ok(&scene(vec![diffuse(0.5)], vec![smooth, flat]));
    let x = e.xml.split_whitespace().collect::<Vec<_>>().join(" ");
    assert_has(
        &x,
        r#"<shape type="ply" id="shape-0-smooth_one"> <string name="filename" value="meshes/0-smooth_one.ply"/> <boolean name="face_normals" value="false"/> <boolean name="flip_tex_coords" value="false"/>"#,
    );
    assert_has(
        &x,
        r#"<string name="filename" value="meshes/1-flat.ply"/> <boolean name="face_normals" value="true"/>"#,
    );
    let names: Vec<&str> = e.assets.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["meshes/0-smooth_one.ply", "meshes/1-flat.ply"]);
    assert!(
        matches!(&e.assets[0].1, Asset::Ply(b) if b.starts_with(b"ply\nformat binary_little_endian 1.0"))
    );
}

#[test]
fn textures_are_baked_with_their_factor_and_wrap_mode() {
    let texels = vec![Vec4::new(0.5, 0.25, 1.0, 1.0), Vec4::ONE];
    let mut s = scene(
        vec![Material::Diffuse {
            albedo: TexRgb::Image {
                texture: 0,
                factor: Vec3::new(0.5, 1.0, 0.5),
            },
        }],
        vec![sphere("s", 0)],
    );
    s.textures = vec![Arc::new(Texture::from_texels(
        2,
        1,
        texels,
        [WrapMode::Mirror; 2],
    ))];
    let e = ok(&s);
    let x = e.xml.split_whitespace().collect::<Vec<_>>().join(" ");
    assert_has(
        &x,
        r#"<texture type="bitmap" name="reflectance"> <string name="filename" value="textures/tex0-0.exr"/> <string name="filter_type" value="bilinear"/> <string name="wrap_mode" value="mirror"/> <boolean name="raw" value="true"/>"#,
    );
    let Some((_, Asset::Exr(img))) = e.assets.iter().find(|(n, _)| n == "textures/tex0-0.exr") else {
        panic!(
            "no texture file in {:?}",
            e.assets.iter().map(|a| &a.0).collect::<Vec<_>>()
        )
    };
    assert_eq!(
        img.rgb("").unwrap(),
        vec![Vec3::new(0.25, 0.25, 0.5), Vec3::new(0.5, 1.0, 0.5)]
    );
}

#[test]
fn lights_and_environments() {
    let mut s = scene(vec![diffuse(0.5)], vec![sphere("s", 0)]);
    s.lights = vec![
        Light::Point {
            name: "p".into(),
            position: Vec3::new(1.0, 2.0, 3.0),
            intensity: Vec3::new(4.0, 5.0, 6.0),
        },
        Light::Spot {
            name: "sp".into(),
            position: Vec3::new(0.0, 3.0, 0.0),
            direction: Vec3::NEG_Y,
            intensity: Vec3::splat(2.0),
            cutoff_deg: 30.0,
            beam_width_deg: 20.0,
            projection: None,
        },
        Light::Directional {
            name: "sun".into(),
            direction: Vec3::new(0.0, -1.0, 0.0),
            irradiance: Vec3::splat(3.0),
            angular_diameter_deg: 0.0,
        },
    ];
    s.environment = Some(Environment::Constant {
        radiance: Vec3::splat(0.5),
    });
    let x = xml(&s);
    assert_has(
        &x,
        r#"<emitter type="point"> <point name="position" value="1.0, 2.0, 3.0"/> <rgb name="intensity" value="4.0, 5.0, 6.0"/>"#,
    );
    assert_has(
        &x,
        r#"<emitter type="spot"> <rgb name="intensity" value="2.0, 2.0, 2.0"/> <float name="cutoff_angle" value="30.0"/> <float name="beam_width" value="20.0"/> <transform name="to_world"> <lookat origin="0.0, 3.0, 0.0" target="0.0, 2.0, 0.0" up="1.0, 0.0, 0.0"/>"#,
    );
    assert_has(
        &x,
        r#"<emitter type="directional"> <vector name="direction" value="0.0, -1.0, 0.0"/> <rgb name="irradiance" value="3.0, 3.0, 3.0"/>"#,
    );
    assert_has(
        &x,
        r#"<emitter type="constant"> <rgb name="radiance" value="0.5, 0.5, 0.5"/>"#,
    );

    s.textures = vec![Arc::new(Texture::from_texels(
        2,
        1,
        vec![Vec4::ONE; 2],
        [WrapMode::Repeat; 2],
    ))];
    s.environment = Some(Environment::Map {
        texture: 0,
        scale: 2.5,
    });
    let e = ok(&s);
    let x = e.xml.split_whitespace().collect::<Vec<_>>().join(" ");
    assert_has(
        &x,
        r#"<emitter type="envmap"> <string name="filename" value="textures/environment.exr"/> <float name="scale" value="2.5"/>"#,
    );
    assert!(e
        .assets
        .iter()
        .any(|(n, a)| n == "textures/environment.exr" && matches!(a, Asset::Exr(_))));
}

#[test]
fn refusals_name_the_item_and_the_feature() {
    let ggx = |f0: Vec3, roughness: TexScalar, masking: Masking| Material::Ggx {
        reflectance: TexRgb::Constant(Vec3::ONE),
        f0,
        roughness,
        masking,
        scattering: Scattering::Single,
        conductor: None,
    };
    let cases: Vec<(Material, &str)> = vec![
        (
            Material::Phong {
                reflectance: TexRgb::Constant(Vec3::ONE),
                exponent: 5.0,
            },
            "material #0 (phong, used by `s`): Mitsuba 3 has no normalized Phong lobe",
        ),
        (
            Material::MetalRough {
                base_color: TexRgb::Constant(Vec3::ONE),
                metallic: TexScalar::Constant(1.0),
                roughness: TexScalar::Constant(0.5),
                scattering: Scattering::Single,
            },
            "material #0 (metal_rough, used by `s`): glTF metallic-roughness",
        ),
        (
            ggx(Vec3::splat(0.04), TexScalar::Constant(0.5), Masking::Separable),
            "Schlick Fresnel with f0",
        ),
        (
            ggx(Vec3::ONE, TexScalar::Constant(0.5), Masking::HeightCorrelated),
            "height-correlated Smith masking",
        ),
        (
            ggx(
                Vec3::ONE,
                TexScalar::Image {
                    texture: 0,
                    channel: 1,
                    factor: 1.0,
                },
                Masking::Separable,
            ),
            "textured roughness",
        ),
        (
            ggx(Vec3::ONE, TexScalar::Constant(0.0), Masking::Separable),
            "roughness 0 is a mirror",
        ),
        (
            Material::Ggx {
                reflectance: TexRgb::Constant(Vec3::ONE),
                f0: Vec3::ONE,
                roughness: TexScalar::Constant(0.5),
                masking: Masking::HeightCorrelated,
                scattering: Scattering::Multiple,
                conductor: None,
            },
            "material #0 (ggx, used by `s`): multiple scattering on the microsurface",
        ),
    ];
    for (material, want) in cases {
        let mut s = scene(vec![material], vec![sphere("s", 0)]);
        s.textures = vec![Arc::new(Texture::from_texels(
            1,
            1,
            vec![Vec4::ONE],
            [WrapMode::Repeat; 2],
        ))];
        let msg = refusal(&s);
        assert!(
            msg.contains(want) && msg.starts_with("test.toml: Mitsuba 3 cannot express"),
            "expected `{want}` in: {msg}"
        );
    }
}

#[test]
fn refusals_of_shapes_lights_textures_and_integrators() {
    let base = || scene(vec![diffuse(0.5)], vec![sphere("s", 0)]);

    let mut s = base();
    s.shapes[0].emission = Some(Emission {
        radiance: TexRgb::Constant(Vec3::ONE),
        two_sided: true,
    });
    assert!(refusal(&s).contains("shape `s`: two-sided emission"));

    let mut s = base();
    s.shapes[0].normal_map = Some(NormalMap {
        texture: 0,
        scale: 1.0,
    });
    assert!(refusal(&s).contains("shape `s`: normal map"));

    let mut s = base();
    s.shapes[0].geometry = Geometry::Rectangle {
        center: Vec3::ZERO,
        half_u: Vec3::X,
        half_v: Vec3::Y,
    };
    s.textures = vec![Arc::new(Texture::from_texels(
        1,
        1,
        vec![Vec4::ONE],
        [WrapMode::Clamp, WrapMode::Clamp],
    ))];
    s.shapes[0].displacement = Some(Displacement {
        texture: 0,
        channel: 0,
        scale: 0.1,
    });
    assert!(refusal(&s).contains("shape `s`: displacement"));

    let mut s = base();
    s.lights.push(Light::Directional {
        name: "sun".into(),
        direction: Vec3::NEG_Y,
        irradiance: Vec3::ONE,
        angular_diameter_deg: 0.53,
    });
    assert!(refusal(&s).contains("light `sun`: directional light with an angular diameter of 0.53°"));

    let mut s = base();
    s.textures = vec![Arc::new(Texture::from_texels(
        1,
        1,
        vec![Vec4::ONE],
        [WrapMode::Repeat, WrapMode::Clamp],
    ))];
    s.materials[0] = Material::Diffuse {
        albedo: TexRgb::Image {
            texture: 0,
            factor: Vec3::ONE,
        },
    };
    assert!(refusal(&s).contains("wrap modes Repeat in u and Clamp in v"));

    let mut s = base();
    s.render.integrator = IntegratorKind::Ao;
    assert!(refusal(&s).contains("integrator `ao`"));

    let mut s = base();
    s.render.integrator = IntegratorKind::DirectUnshadowed;
    assert!(refusal(&s).contains("integrator `direct-unshadowed`"));

    let mut s = base();
    s.render.integrator = IntegratorKind::Direct;
    s.materials[0] = Material::Mirror {
        reflectance: Vec3::ONE,
    };
    assert!(refusal(&s).contains("integrator `direct`: ours follows perfect-specular chains"));

    let mut s = base();
    s.render.pixel_filter = PixelFilter::Centre { ssaa: 2 };
    assert!(refusal(&s).contains("pixel_filter `centre`: only the box pixel filter is exported"));
}

#[test]
fn every_problem_is_reported_at_once() {
    let mut s = scene(
        vec![Material::Phong {
            reflectance: TexRgb::Constant(Vec3::ONE),
            exponent: 5.0,
        }],
        vec![sphere("s", 0)],
    );
    s.render.integrator = IntegratorKind::Ao;
    let e = export(&s).expect_err("two problems");
    assert_eq!(e.problems.len(), 2, "{:?}", e.problems);
}

/// A scene that includes a glTF asset with `materials`, `transform` and `camera`
/// (scenes/include-asset.toml) exports what loading resolved: the asset's metal-rough
/// material (which Mitsuba cannot express) is replaced by the scene's clay, the PLY holds the
/// vertices placed by the include's transform, and the sensor is the asset's camera moved by
/// the same transform.
#[test]
fn an_included_asset_exports_with_its_replaced_material_transform_and_camera() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let s = scenes::load(&root.join("include-asset.toml")).unwrap_or_else(|e| panic!("{e}"));
    let (index, suzanne) = s
        .shapes
        .iter()
        .enumerate()
        .find(|(_, sh)| sh.name == "suzanne/0")
        .expect("the included mesh");
    assert_eq!(
        s.materials[suzanne.material],
        Material::Diffuse {
            albedo: TexRgb::Constant(Vec3::new(0.7, 0.55, 0.45))
        }
    );
    let e = ok(&s);
    let x = e.xml.split_whitespace().collect::<Vec<_>>().join(" ");
    let shape = x
        .split(&format!(r#"<shape type="ply" id="shape-{index}-suzanne_0">"#))
        .nth(1)
        .and_then(|rest| rest.split("</shape>").next())
        .unwrap_or_else(|| panic!("no ply shape for suzanne/0 in\n{x}"));
    let bsdf = format!("bsdf-{}", suzanne.material);
    assert_has(shape, &format!(r#"<ref id="{bsdf}"/>"#));
    assert_has(
        &x,
        &format!(
            r#"<bsdf type="twosided" id="{bsdf}"> <bsdf type="diffuse"> <rgb name="reflectance" value="0.7, 0.55, 0.45"/>"#
        ),
    );

    // The PLY's vertices are the asset's own turned 25° about +Y and lifted by 0.67 m.
    let alone = scenes::gltf::load(&root.join("assets/suzanne.glb")).unwrap();
    let Geometry::Mesh(own) = &alone.shapes[0].geometry else {
        panic!("suzanne.glb holds a mesh")
    };
    let file = format!("meshes/{index}-suzanne_0.ply");
    let Some((_, Asset::Ply(ply))) = e.assets.iter().find(|(n, _)| *n == file) else {
        panic!(
            "no {file} among {:?}",
            e.assets.iter().map(|(n, _)| n).collect::<Vec<_>>()
        )
    };
    let body = ply
        .windows(11)
        .position(|w| w == b"end_header\n")
        .map(|at| &ply[at + 11..])
        .expect("a PLY header");
    let place = glam::Affine3A::from_translation(Vec3::new(0.0, 0.67, 0.0))
        * glam::Affine3A::from_rotation_y(25f32.to_radians());
    // x y z nx ny nz per vertex, little-endian f32 (compare/src/mitsuba/ply.rs).
    let stride = 24;
    for (i, p) in own.positions.iter().enumerate().step_by(500) {
        let f = |k: usize| {
            let at = i * stride + 4 * k;
            f32::from_le_bytes(body[at..at + 4].try_into().unwrap())
        };
        let got = Vec3::new(f(0), f(1), f(2));
        let want = place.transform_point3(*p);
        assert!(
            (got - want).abs().max_element() < 1e-5,
            "vertex {i}: {got} vs {want}"
        );
    }

    // The sensor: the asset camera at (0, 0.35, 3.1), placed by the same transform.
    let eye = place.transform_point3(Vec3::new(0.0, 0.35, 3.1));
    assert!(
        (s.camera.position() - eye).abs().max_element() < 1e-5,
        "{}",
        s.camera.position()
    );
    assert_has(
        &x,
        &format!(
            r#"<lookat origin="{}""#,
            compare::mitsuba::xml::triple(s.camera.position())
        ),
    );
    assert_has(
        &x,
        r#"<integer name="width" value="240"/> <integer name="height" value="160"/>"#,
    );
}
