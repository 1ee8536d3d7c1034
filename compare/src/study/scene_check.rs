//! A study checked against its scene before anything renders: the scene is loaded at every
//! scene point (the file as written with `[scene_set]`, or each `[scene_sweep]` value) and at
//! every frame of a flicker `shift` (and the `[second_ground_truth]` scene at every point it
//! follows), and at each point `visibility_of` must name one of the
//! scene's lights and every object of an `objects` mask one of its shapes. These used to fail
//! only after the ground truth had rendered (a mask of a misspelt shape), or not at all.
//!
//! Errors name the study file, the line and the field that is wrong: `scene_sweep.values`
//! (with the value) for a point that does not load, `second_ground_truth.scene` for a second
//! ground truth that does not load there or has another camera, `ground_truth.visibility_of`,
//! `mask[i].objects[j]`, `stability.flicker.shift`.

use scenes::toml::read::Table;
use scenes::{Scene, SceneError};

use super::run::{prepare, prepare_second};
use super::{shifted, MaskSpec, Motion, ScenePoint, Study};

/// Most names an error lists (a glTF asset can have hundreds of shapes).
const LISTED_NAMES: usize = 20;

/// Runs every check of this module; `doc` is the study file's root table (for locations).
pub(super) fn check(study: &Study, doc: &Table) -> Result<(), SceneError> {
    let points = study.scene_points();
    for point in &points {
        let at = point
            .value
            .as_ref()
            .map_or(String::new(), |(k, v)| format!(" at scene_sweep {k} = {v}"));
        let scene = match prepare(study, false, &point.overrides) {
            Ok((scene, _)) => scene,
            Err(e) => {
                return Err(match &point.value {
                    Some((k, v)) => doc
                        .req("scene_sweep")?
                        .table()?
                        .req("values")?
                        .err(format!("scene_sweep {k} = {v}: the scene does not load: {e}")),
                    None => doc.req("scene")?.err(format!("the scene does not load: {e}")),
                })
            }
        };
        check_visibility(study, doc, &scene, &at)?;
        check_second_ground_truth(study, doc, point, &scene, &at)?;
        check_mask_objects(study, doc, &scene, &at)?;
    }
    if let Some(f) = &study.stability.flicker {
        if let Motion::Shift { .. } = f.motion {
            for k in 1..f.frames {
                let mut edits = points[0].overrides.clone();
                edits.extend(shifted(&f.motion, k));
                if let Err(e) = prepare(study, false, &edits) {
                    let shift = doc
                        .req("stability")?
                        .table()?
                        .req("flicker")?
                        .table()?
                        .req("shift")?;
                    return Err(shift.err(format!("flicker frame {k}: the scene does not load: {e}")));
                }
            }
        }
    }
    Ok(())
}

/// The `[second_ground_truth]` scene loads at `point` (with the sweep's value when it follows
/// the sweep) and is seen from `scene`'s camera.
fn check_second_ground_truth(
    study: &Study,
    doc: &Table,
    point: &ScenePoint,
    scene: &Scene,
    at: &str,
) -> Result<(), SceneError> {
    if let Err(e) = prepare_second(study, false, point, scene) {
        // The edits when it has them (they are what differs), else the scene file.
        let table = doc.req("second_ground_truth")?;
        let t = table.table()?;
        let field = t.get("scene_set").or_else(|| t.get("scene")).unwrap_or(table);
        return Err(field.err(format!("the second ground truth{at}: {e}")));
    }
    Ok(())
}

/// `visibility_of` names a light of `scene` (an emissive shape or a `[[light]]`: the names
/// both renderers give their `visibility.<light>.Y` channels, `Scene::light_names`).
fn check_visibility(study: &Study, doc: &Table, scene: &Scene, at: &str) -> Result<(), SceneError> {
    let Some(light) = &study.visibility_of else {
        return Ok(());
    };
    let names = scene.light_names();
    if names.contains(light) {
        return Ok(());
    }
    let field = doc.req("ground_truth")?.table()?.req("visibility_of")?;
    Err(field
        .err(format!(
            "the scene has no light `{light}`{at}; its lights: {}",
            listed(&names)
        ))
        .hint("name an emissive shape or a [[light]] of the scene"))
}

/// Every object of every `objects` mask names a shape of `scene`.
fn check_mask_objects(study: &Study, doc: &Table, scene: &Scene, at: &str) -> Result<(), SceneError> {
    for (i, spec) in study.masks.iter().enumerate() {
        let MaskSpec::Objects { name, objects, .. } = spec else {
            continue;
        };
        let Some(j) = objects
            .iter()
            .position(|o| !scene.shapes.iter().any(|s| scenes::glob::matches(o, &s.name)))
        else {
            continue;
        };
        let shapes: Vec<String> = scene.shapes.iter().map(|s| s.name.clone()).collect();
        let field = doc.req("mask")?.tables()?[i].req("objects")?.array()?[j].clone();
        return Err(field.err(format!(
            "mask `{name}`: the scene has no shape `{}`{at}; shapes: {}",
            objects[j],
            listed(&shapes)
        )));
    }
    Ok(())
}

/// `a, b, c` (at most [`LISTED_NAMES`], then how many more), or `none`.
fn listed(names: &[String]) -> String {
    if names.is_empty() {
        return "none".into();
    }
    let mut text = names
        .iter()
        .take(LISTED_NAMES)
        .map(String::as_str)
        .collect::<Vec<_>>()
        .join(", ");
    if names.len() > LISTED_NAMES {
        text += &format!(" and {} more", names.len() - LISTED_NAMES);
    }
    text
}
