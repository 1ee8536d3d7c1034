//! KHR_lights_punctual (units, cone angles, directions) and glTF cameras (rigid frame,
//! field of view, film aspect, orthographic handling).

mod gltf_support;

use std::f32::consts::{FRAC_1_SQRT_2, FRAC_PI_4, FRAC_PI_8};

use glam::{Mat3, Vec3};
use gltf_support::*;
use scenes::Light;

/// A document with one triangle (so bounds exist), `lights` and `nodes` (node 0 = the mesh).
fn with_lights(
    tag: &str,
    lights: &str,
    extra_nodes: &str,
) -> Result<scenes::gltf::Loaded, scenes::SceneError> {
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let rest = format!(
        "{meshes},\"extensionsUsed\":[\"KHR_lights_punctual\"],\
         \"extensions\":{{\"KHR_lights_punctual\":{{\"lights\":[{lights}]}}}},\
         \"nodes\":[{{\"mesh\":0}}{extra_nodes}]"
    );
    let dir = temp_dir(tag);
    scenes::gltf::load_with_notes(&write(
        &dir,
        &format!("{tag}.gltf"),
        document(&bin.parts(), &rest),
    ))
}

#[test]
fn point_spot_and_directional_lights_convert_units_angles_and_directions() {
    let s = FRAC_1_SQRT_2;
    let lights = format!(
        "{{\"name\":\"bulb\",\"type\":\"point\",\"color\":[1,0.5,0.25],\"intensity\":100,\"range\":10}},\
         {{\"type\":\"spot\",\"intensity\":20,\"spot\":{{\"innerConeAngle\":{FRAC_PI_8},\"outerConeAngle\":{FRAC_PI_4}}}}},\
         {{\"name\":\"sun\",\"type\":\"directional\",\"color\":[1,1,0.5],\"intensity\":3}}"
    );
    // Node 2: rotation −90° about X maps the local −Z to −Y (a spot pointing down), with a
    // non-uniform scale that must not change the direction. Node 3: the sun, rotated 90° about Y:
    // R_y(90°)·(0,0,−1) = (−1,0,0).
    let nodes = format!(
        ",{{\"translation\":[1,2,3],\"extensions\":{{\"KHR_lights_punctual\":{{\"light\":0}}}}}},\
         {{\"name\":\"lamp\",\"translation\":[0,5,0],\"rotation\":[-{s},0,0,{s}],\"scale\":[1,3,0.5],\
            \"extensions\":{{\"KHR_lights_punctual\":{{\"light\":1}}}}}},\
         {{\"rotation\":[0,{s},0,{s}],\"extensions\":{{\"KHR_lights_punctual\":{{\"light\":2}}}}}}"
    );
    let loaded = with_lights("lights", &lights, &nodes).unwrap();
    let [point, spot, sun] = loaded.scene.lights.as_slice() else {
        panic!("expected 3 lights, got {:?}", loaded.scene.lights);
    };
    assert_eq!(
        *point,
        Light::Point {
            name: "bulb".into(),
            position: Vec3::new(1.0, 2.0, 3.0),
            intensity: Vec3::new(100.0, 50.0, 25.0)
        }
    );
    let Light::Spot {
        name,
        position,
        direction,
        intensity,
        cutoff_deg,
        beam_width_deg,
        ..
    } = spot
    else {
        panic!("{spot:?}");
    };
    assert_eq!(name, "lamp", "an unnamed light takes its node's name");
    assert_close(*position, Vec3::new(0.0, 5.0, 0.0), 1e-6);
    assert_close(*direction, Vec3::NEG_Y, 1e-6);
    assert_eq!(*intensity, Vec3::splat(20.0), "white default colour × intensity");
    assert!(
        (cutoff_deg - 45.0).abs() < 1e-4,
        "cutoff: expected 45°, got {cutoff_deg}"
    );
    assert!(
        (beam_width_deg - 22.5).abs() < 1e-4,
        "beam: expected 22.5°, got {beam_width_deg}"
    );
    let Light::Directional {
        name,
        direction,
        irradiance,
        angular_diameter_deg,
    } = sun
    else {
        panic!("{sun:?}");
    };
    assert_eq!(name, "sun");
    assert_close(*direction, Vec3::NEG_X, 1e-6);
    assert_eq!(*irradiance, Vec3::new(3.0, 3.0, 1.5), "lux taken as W/m²");
    assert_eq!(*angular_diameter_deg, 0.0);
    assert!(
        loaded.notes.iter().any(|n| n.contains("lights[0].range")),
        "{:?}",
        loaded.notes
    );
}

#[test]
fn spot_cone_outside_the_hemisphere_is_an_error() {
    let lights = "{\"type\":\"spot\",\"spot\":{\"outerConeAngle\":2.0}}";
    let nodes = ",{\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}}";
    let err = with_lights("bad-spot", lights, nodes).unwrap_err();
    assert_eq!(
        err.field.as_deref(),
        Some("extensions.KHR_lights_punctual.lights[0].spot.outerConeAngle"),
        "{err}"
    );
    assert!(err.to_string().contains("bad-spot.gltf"), "{err}");
}

/// A document with a triangle at node 0 and the given cameras and extra nodes.
fn with_cameras(tag: &str, cameras: &str, extra_nodes: &str) -> Result<scenes::Scene, scenes::SceneError> {
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let rest = format!("{meshes},\"cameras\":[{cameras}],\"nodes\":[{{\"mesh\":0}}{extra_nodes}]");
    load_json(tag, &document(&bin.parts(), &rest))
}

#[test]
fn perspective_camera_is_rigid_with_fov_and_film_from_the_file() {
    // Parent translates by (0,1,5) and scales by 2; the child camera node rotates 30° about Y.
    let (sin, cos) = 15f32.to_radians().sin_cos();
    let cameras =
        "{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.6,\"aspectRatio\":1.5,\"znear\":0.1}}";
    let nodes = format!(
        ",{{\"translation\":[0,1,5],\"scale\":[2,2,2],\"children\":[2]}},{{\"rotation\":[0,{sin},0,{cos}],\"camera\":0}}"
    );
    let scene = with_cameras("camera", cameras, &nodes).unwrap();
    assert_eq!((scene.film.width, scene.film.height), (768, 512));
    assert!(
        (scene.camera.fov_y_deg - 0.6f32.to_degrees()).abs() < 1e-4,
        "fov {}",
        scene.camera.fov_y_deg
    );
    assert_close(scene.camera.position(), Vec3::new(0.0, 1.0, 5.0), 1e-6);
    let (s30, c30) = 30f32.to_radians().sin_cos();
    assert_close(scene.camera.forward(), Vec3::new(-s30, 0.0, -c30), 1e-6);
    let m = Mat3::from(scene.camera.to_world.matrix3);
    for (k, axis) in [m.x_axis, m.y_axis, m.z_axis].iter().enumerate() {
        assert!(
            (axis.length() - 1.0).abs() < 1e-6,
            "axis {k} has length {} (scale not removed)",
            axis.length()
        );
    }
    assert!(
        (m.determinant() - 1.0).abs() < 1e-5,
        "rotation determinant {}",
        m.determinant()
    );
}

#[test]
fn camera_without_aspect_ratio_renders_square() {
    let cameras = "{\"type\":\"perspective\",\"perspective\":{\"yfov\":1.0,\"znear\":0.1}}";
    let scene = with_cameras(
        "camera-square",
        cameras,
        ",{\"translation\":[0,0,4],\"camera\":0}",
    )
    .unwrap();
    assert_eq!((scene.film.width, scene.film.height), (512, 512));
    assert_close(scene.camera.forward(), Vec3::NEG_Z, 1e-6);
}

#[test]
fn orthographic_camera_is_an_error_only_without_a_perspective_one() {
    let ortho =
        "{\"type\":\"orthographic\",\"orthographic\":{\"xmag\":1,\"ymag\":1,\"znear\":0.1,\"zfar\":10}}";
    let err = with_cameras("ortho", ortho, ",{\"camera\":0}").unwrap_err();
    assert_eq!(err.field.as_deref(), Some("cameras[0].orthographic"), "{err}");
    assert!(err.to_string().contains("ortho.gltf"), "{err}");

    let both = format!("{ortho},{{\"type\":\"perspective\",\"perspective\":{{\"yfov\":0.5,\"znear\":0.1}}}}");
    let scene = with_cameras(
        "ortho-and-persp",
        &both,
        ",{\"camera\":0},{\"camera\":1,\"translation\":[0,0,3]}",
    )
    .unwrap();
    assert!((scene.camera.fov_y_deg - 0.5f32.to_degrees()).abs() < 1e-4);
    assert_close(scene.camera.position(), Vec3::new(0.0, 0.0, 3.0), 1e-6);
}
