//! Cross-checks of exporter features the built-in scenes do not use, on one synthetic scene
//! per group: textures (all three wrap modes, uvs outside [0, 1] on a PLY mesh), flat and
//! smooth meshes, disks, a dielectric, GGX (F = 1, and a gold conductor's exact Fresnel), and
//! every delta light with a constant sky.

mod mitsuba_support;

use std::sync::Arc;

use compare::mitsuba::runner::Variant;
use glam::{Vec2, Vec3, Vec4};
use mitsuba_support::check;
use scenes::texture::Texture;
use scenes::{
    Camera, ComplexIor, Emission, Environment, Film, Geometry, Light, Masking, Material, Mesh,
    RenderSettings, Scattering, Scene, Shape, TexRgb, TexScalar, WrapMode,
};

fn base(name: &str) -> Scene {
    Scene {
        source: format!("<synthetic {name}>").into(),
        camera: Camera::look_at(Vec3::new(0.0, 1.6, 3.0), Vec3::new(0.0, 0.3, 0.0), Vec3::Y, 40.0),
        film: Film {
            width: 64,
            height: 64,
        },
        render: RenderSettings {
            max_depth: -1,
            ..RenderSettings::default()
        },
        textures: vec![],
        materials: vec![],
        shapes: vec![],
        lights: vec![],
        environment: None,
        provenance: Default::default(),
    }
}

fn shape(name: &str, geometry: Geometry, material: usize) -> Shape {
    Shape {
        name: name.into(),
        geometry,
        material,
        emission: None,
        normal_map: None,
        displacement: None,
    }
}

/// A W×H texture of distinct colours (so any misplaced texel changes the image).
fn pattern(w: u32, h: u32, wrap: WrapMode) -> Texture {
    let texels = (0..w * h)
        .map(|k| {
            let (i, j) = ((k % w) as f32, (k / w) as f32);
            Vec4::new(
                0.15 + 0.8 * i / w as f32,
                0.1 + 0.85 * j / h as f32,
                0.9 - 0.7 * ((i + j) % 3.0) / 2.0,
                1.0,
            )
        })
        .collect();
    Texture::from_texels(w, h, texels, [wrap; 2])
}

/// A quad mesh over [−s, s]² at height y with uvs from `uv0` to `uv1`, facing +Y.
fn quad(center: Vec3, s: f32, uv0: Vec2, uv1: Vec2, normals: bool) -> Mesh {
    let p = |x: f32, z: f32| center + Vec3::new(x * s, 0.0, z * s);
    Mesh {
        positions: vec![p(-1.0, -1.0), p(1.0, -1.0), p(1.0, 1.0), p(-1.0, 1.0)],
        normals: if normals { vec![Vec3::Y; 4] } else { vec![] },
        uvs: vec![uv0, Vec2::new(uv1.x, uv0.y), uv1, Vec2::new(uv0.x, uv1.y)],
        tangents: vec![],
        indices: vec![[0, 2, 1], [0, 3, 2]],
        uv1: vec![],
    }
}

/// A UV sphere with smooth vertex normals (interpolated shading normals).
fn smooth_sphere(center: Vec3, r: f32, rings: u32, segments: u32) -> Mesh {
    let mut m = Mesh::default();
    for i in 0..=rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..=segments {
            let phi = std::f32::consts::TAU * j as f32 / segments as f32;
            let n = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            m.positions.push(center + r * n);
            m.normals.push(n);
            m.uvs
                .push(Vec2::new(j as f32 / segments as f32, i as f32 / rings as f32));
        }
    }
    let row = segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (
                i * row + j,
                i * row + j + 1,
                (i + 1) * row + j,
                (i + 1) * row + j + 1,
            );
            m.indices.push([a, b, c]);
            m.indices.push([b, d, c]);
        }
    }
    m
}

#[test]
fn textures_meshes_and_disks_agree() {
    let mut s = base("textures");
    s.textures = vec![
        Arc::new(pattern(8, 4, WrapMode::Repeat)),
        Arc::new(pattern(5, 3, WrapMode::Mirror)),
        Arc::new(pattern(4, 4, WrapMode::Clamp)),
    ];
    let tex = |texture: usize| TexRgb::Image {
        texture,
        factor: Vec3::new(1.0, 0.9, 0.8),
    };
    s.materials = vec![
        Material::Diffuse { albedo: tex(0) },
        Material::Diffuse { albedo: tex(1) },
        Material::Diffuse { albedo: tex(2) },
        Material::Diffuse {
            albedo: TexRgb::Constant(Vec3::splat(0.6)),
        },
    ];
    // Rectangle uv in [0, 1]²; PLY quads with uvs reaching outside [0, 1] (wrap modes).
    s.shapes = vec![
        shape(
            "floor",
            Geometry::Rectangle {
                center: Vec3::ZERO,
                half_u: Vec3::new(1.6, 0.0, 0.0),
                half_v: Vec3::new(0.0, 0.0, -1.6),
            },
            0,
        ),
        shape(
            "mirror_wrap",
            Geometry::Mesh(Arc::new(quad(
                Vec3::new(-0.6, 0.01, 0.5),
                0.5,
                Vec2::new(-1.3, -0.7),
                Vec2::new(1.8, 2.2),
                true,
            ))),
            1,
        ),
        shape(
            "clamp_wrap",
            Geometry::Mesh(Arc::new(quad(
                Vec3::new(0.6, 0.01, 0.5),
                0.5,
                Vec2::new(-0.5, 1.5),
                Vec2::new(1.5, -0.5),
                false,
            ))),
            2,
        ),
        shape(
            "disk",
            Geometry::Disk {
                center: Vec3::new(0.0, 0.4, -0.6),
                half_u: Vec3::new(0.5, 0.0, 0.0),
                half_v: Vec3::new(0.0, 0.3, 0.2),
            },
            1,
        ),
        shape(
            "lamp",
            Geometry::Disk {
                center: Vec3::new(0.3, 2.0, 0.5),
                half_u: Vec3::new(0.6, 0.0, 0.0),
                half_v: Vec3::new(0.0, 0.0, 0.6),
            },
            3,
        ),
    ];
    // The lamp faces down: half_u × half_v = (0.6,0,0) × (0,0,0.6) = −Y·0.36.
    s.shapes[4].emission = Some(Emission {
        radiance: TexRgb::Constant(Vec3::new(6.0, 5.5, 5.0)),
        two_sided: false,
    });
    s.environment = Some(Environment::Constant {
        radiance: Vec3::new(0.2, 0.25, 0.3),
    });
    let c = check("features-textures", &s, &s, 256, Variant::LlvmAdRgb);
    assert!(
        c.ztest.pass,
        "textures/meshes/disks: the oracle and Mitsuba disagree: {:?}",
        c.ztest.failed
    );

    // The same check has the power to see a texture upside down (rows reversed).
    let mut flipped = s.clone();
    let mut t = (*flipped.textures[0]).clone();
    t.texels = t
        .texels
        .chunks(t.width as usize)
        .rev()
        .flatten()
        .copied()
        .collect();
    flipped.textures[0] = Arc::new(t);
    let f = check("features-textures-flipped", &s, &flipped, 256, Variant::LlvmAdRgb);
    assert!(
        !f.ztest.pass,
        "a vertically flipped floor texture passed the z-test"
    );
}

#[test]
fn delta_lights_glass_and_ggx_agree() {
    let mut s = base("lights");
    s.textures = vec![Arc::new(pattern(6, 6, WrapMode::Repeat))];
    s.materials = vec![
        Material::Diffuse {
            albedo: TexRgb::Constant(Vec3::new(0.7, 0.65, 0.6)),
        },
        Material::Dielectric {
            int_ior: 1.5,
            ext_ior: 1.0,
        },
        Material::Ggx {
            reflectance: TexRgb::Image {
                texture: 0,
                factor: Vec3::ONE,
            },
            f0: Vec3::ONE,
            roughness: TexScalar::Constant(0.4),
            masking: Masking::Separable,
            scattering: Scattering::Single,
            conductor: None,
        },
        Material::Mirror {
            reflectance: Vec3::new(0.9, 0.8, 0.7),
        },
        // Gold's exact conductor Fresnel (η + ik at 650 / 550 / 450 nm, Johnson & Christy 1972)
        // against `roughconductor`'s with the same `eta` and `k`.
        Material::Ggx {
            reflectance: TexRgb::Constant(Vec3::ONE),
            f0: Vec3::ONE,
            roughness: TexScalar::Constant(0.35),
            masking: Masking::Separable,
            scattering: Scattering::Single,
            conductor: Some(ComplexIor {
                eta: Vec3::new(0.166, 0.433, 1.51),
                k: Vec3::new(3.15, 2.32, 1.88),
            }),
        },
    ];
    s.shapes = vec![
        shape(
            "floor",
            Geometry::Rectangle {
                center: Vec3::ZERO,
                half_u: Vec3::new(2.0, 0.0, 0.0),
                half_v: Vec3::new(0.0, 0.0, -2.0),
            },
            0,
        ),
        shape(
            "glass",
            Geometry::Sphere {
                center: Vec3::new(-0.6, 0.35, 0.3),
                radius: 0.35,
            },
            1,
        ),
        shape(
            "ggx",
            Geometry::Mesh(Arc::new(smooth_sphere(Vec3::new(0.5, 0.4, 0.0), 0.4, 12, 24))),
            2,
        ),
        shape(
            "mirror",
            Geometry::Rectangle {
                center: Vec3::new(0.0, 0.6, -1.0),
                half_u: Vec3::new(0.8, 0.0, 0.0),
                half_v: Vec3::new(0.0, 0.6, 0.0),
            },
            3,
        ),
        shape(
            "gold",
            Geometry::Sphere {
                center: Vec3::new(0.05, 0.22, 1.0),
                radius: 0.22,
            },
            4,
        ),
    ];
    s.lights = vec![
        Light::Point {
            name: "point".into(),
            position: Vec3::new(-1.0, 2.0, 1.0),
            intensity: Vec3::new(3.0, 2.5, 2.0),
        },
        Light::Spot {
            name: "spot".into(),
            position: Vec3::new(1.2, 2.0, 1.2),
            direction: Vec3::new(-0.5, -1.0, -0.6).normalize(),
            intensity: Vec3::new(8.0, 8.0, 10.0),
            cutoff_deg: 30.0,
            beam_width_deg: 15.0,
            projection: None,
        },
        Light::Directional {
            name: "sun".into(),
            direction: Vec3::new(0.3, -1.0, -0.4).normalize(),
            irradiance: Vec3::new(1.0, 0.95, 0.9),
            angular_diameter_deg: 0.0,
        },
    ];
    s.environment = Some(Environment::Constant {
        radiance: Vec3::new(0.1, 0.12, 0.15),
    });
    let c = check("features-lights", &s, &s, 256, Variant::LlvmAdRgb);
    assert!(
        c.ztest.pass,
        "lights/glass/ggx: the oracle and Mitsuba disagree: {:?}",
        c.ztest.failed
    );
}

/// A spot light projecting a texture (a cookie, scenes::projection) onto a diffuse floor and
/// wall, against Mitsuba's `spot` with its `texture`: a 6 × 4 pattern of distinct colours
/// (any flip or rotation of the image, or a misplaced texel, changes the image), magnified
/// so that the bilinear reconstruction itself is compared, with a factor and tilted so the
/// projection is oblique.
#[test]
fn a_projected_spot_texture_agrees() {
    let mut s = base("projector");
    s.textures = vec![Arc::new(pattern(6, 4, WrapMode::Clamp))];
    s.materials = vec![Material::Diffuse {
        albedo: TexRgb::Constant(Vec3::splat(0.8)),
    }];
    s.shapes = vec![
        shape(
            "floor",
            Geometry::Rectangle {
                center: Vec3::ZERO,
                half_u: Vec3::new(2.0, 0.0, 0.0),
                half_v: Vec3::new(0.0, 0.0, -2.0),
            },
            0,
        ),
        shape(
            "wall",
            Geometry::Rectangle {
                center: Vec3::new(0.0, 1.0, -1.0),
                half_u: Vec3::new(2.0, 0.0, 0.0),
                half_v: Vec3::new(0.0, 1.0, 0.0),
            },
            0,
        ),
    ];
    s.lights = vec![Light::Spot {
        name: "projector".into(),
        position: Vec3::new(0.6, 1.8, 1.4),
        direction: Vec3::new(-0.3, -1.0, -0.9).normalize(),
        intensity: Vec3::splat(6.0),
        cutoff_deg: 35.0,
        beam_width_deg: 30.0,
        projection: Some(scenes::Projection {
            texture: TexRgb::Image {
                texture: 0,
                factor: Vec3::new(1.0, 0.8, 0.6),
            },
            up: Vec3::new(0.2, 0.3, -1.0).normalize(),
        }),
    }];
    let c = check("features-projector", &s, &s, 256, Variant::LlvmAdRgb);
    assert!(
        c.ztest.pass,
        "projected spot texture: the oracle and Mitsuba disagree: {:?}",
        c.ztest.failed
    );
}
