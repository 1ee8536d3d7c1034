//! Scene fields changed from outside the file (`scenes::toml::load_with`): the study files'
//! scene-parameter sweeps and light motion.

use std::path::{Path, PathBuf};

use glam::Vec3;
use scenes::toml::overrides::{Edit, Override};
use scenes::toml::tree::Value;
use scenes::Geometry;

fn soft_shadow() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/soft-shadow.toml")
}

fn set(path: &str, v: f64) -> Override {
    Override {
        path: path.into(),
        edit: Edit::Set(Value::Float(v)),
    }
}

fn light(scene: &scenes::Scene) -> (Vec3, Vec3, Vec3) {
    let s = scene.shapes.iter().find(|s| s.name == "light").unwrap();
    match s.geometry {
        Geometry::Rectangle {
            center,
            half_u,
            half_v,
        } => (center, half_u, half_v),
        _ => panic!("the soft-shadow light is a rectangle"),
    }
}

#[test]
fn a_resized_and_moved_light_is_read_as_if_written_in_the_file() {
    let plain = scenes::load(&soft_shadow()).unwrap();
    let edited = scenes::toml::load_with(
        &soft_shadow(),
        &[
            set("shape.light.size[0]", 1.5),
            set("shape.light.size[1]", 1.5),
            Override {
                path: "shape.light.center[0]".into(),
                edit: Edit::Add(0.1),
            },
        ],
    )
    .unwrap();
    let (c0, u0, _) = light(&plain);
    let (c1, u1, v1) = light(&edited);
    assert!((u0.length() - 0.25).abs() < 1e-6);
    assert!((u1.length() - 0.75).abs() < 1e-6 && (v1.length() - 0.75).abs() < 1e-6);
    assert!((c1 - c0 - Vec3::new(0.1, 0.0, 0.0)).length() < 1e-6);
    // Everything else is the same scene.
    assert_eq!(plain.shapes.len(), edited.shapes.len());
    assert_eq!(format!("{:?}", plain.camera), format!("{:?}", edited.camera));
}

#[test]
fn a_bad_path_or_value_names_the_file_the_field_and_the_line() {
    let e = scenes::toml::load_with(&soft_shadow(), &[set("shape.lamp.size[0]", 1.0)]).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("soft-shadow.toml") && msg.contains("no entry named `lamp`") && msg.contains("light"),
        "{msg}"
    );
    // A value the scene reader rejects fails with its own message, at the field's line.
    let e = scenes::toml::load_with(&soft_shadow(), &[set("shape.light.size[0]", -1.0)]).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("soft-shadow.toml") && msg.contains("size"), "{msg}");
    assert_eq!(e.line, Some(55), "{msg}");
}
