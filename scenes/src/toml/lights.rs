//! `[[light]]` tables → point, spot and directional [`Light`]s (area lights are emissive
//! shapes). Angles are in degrees.

use super::inputs::{rgb_const, rgb_input, Bound, Textures};
use super::read::{Field, Table};
use crate::model::{Light, Projection};
use crate::SceneError;

const TYPES: &[&str] = &["point", "spot", "directional"];

/// Spot defaults, as Mitsuba 3's `spot`: cutoff 20°, beam width 3/4 of the cutoff.
const SPOT_CUTOFF_DEG: f32 = 20.0;
const SPOT_BEAM_FRACTION: f32 = 0.75;

/// Reads every `[[light]]`; returns each light with the line of its `name`.
pub(crate) fn read_all(
    doc: &Table,
    textures: &mut Textures,
) -> Result<Vec<(Light, Option<usize>)>, SceneError> {
    let Some(list) = doc.get("light") else {
        return Ok(Vec::new());
    };
    let mut lights = Vec::new();
    for t in list.tables()? {
        let name_field = t.req("name")?;
        let name = name_field.str()?.to_string();
        let t = t.clone().renamed(format!("light {}", crate::error::echo(&name)));
        lights.push((read_one(&t, name, textures)?, name_field.line));
    }
    Ok(lights)
}

fn read_one(t: &Table, name: String, textures: &mut Textures) -> Result<Light, SceneError> {
    let kind = t.req("type")?.keyword(TYPES)?;
    let fields: &[&str] = match kind {
        "point" => &["name", "type", "position", "intensity"],
        "spot" => &[
            "name",
            "type",
            "position",
            "direction",
            "target",
            "intensity",
            "cutoff_angle",
            "beam_width",
            "texture",
            "up",
        ],
        _ => &["name", "type", "direction", "irradiance", "angular_diameter"],
    };
    t.only(fields, &format!("a {kind} light"))?;
    Ok(match kind {
        "point" => Light::Point {
            name,
            position: t.req("position")?.position()?,
            intensity: rgb_const(Some(t.req("intensity")?), Bound::NonNegative, glam::Vec3::ZERO)?,
        },
        "spot" => spot(t, name, textures)?,
        _ => {
            let d = t.get("angular_diameter");
            let angular_diameter_deg = d.as_ref().map_or(Ok(0.0), Field::f32)?;
            if !(0.0..180.0).contains(&angular_diameter_deg) {
                let f = d.expect("the default 0 is in range");
                return Err(f
                    .err(format!("must be in [0, 180) degrees, got {angular_diameter_deg}"))
                    .hint("the sun is about 0.53 degrees across"));
            }
            Light::Directional {
                name,
                direction: t.req("direction")?.direction()?,
                irradiance: rgb_const(Some(t.req("irradiance")?), Bound::NonNegative, glam::Vec3::ZERO)?,
                angular_diameter_deg,
            }
        }
    })
}

/// Spot: `position`, `direction` or `target`, `intensity`, `cutoff_angle`, `beam_width`, and
/// a projected `texture` with its `up` (crate::projection).
fn spot(t: &Table, name: String, textures: &mut Textures) -> Result<Light, SceneError> {
    let position = t.req("position")?.position()?;
    let direction = match t.one_of(&["direction", "target"])? {
        Some("direction") => t.req("direction")?.direction()?,
        Some(_) => {
            let f = t.req("target")?;
            (f.position()? - position)
                .try_normalize()
                .ok_or_else(|| f.err("the target is the spot's own position"))?
        }
        None => return Err(t.err("a spot light needs `direction` or `target`")),
    };
    let cutoff_field = t.get("cutoff_angle");
    let cutoff_deg = cutoff_field.as_ref().map_or(Ok(SPOT_CUTOFF_DEG), Field::f32)?;
    if !(cutoff_deg > 0.0 && cutoff_deg <= 90.0) {
        let f = cutoff_field.expect("the default is in range");
        return Err(f.err(format!("must be in (0, 90] degrees, got {cutoff_deg}")));
    }
    let beam_field = t.get("beam_width");
    let beam_width_deg = beam_field
        .as_ref()
        .map_or(Ok(cutoff_deg * SPOT_BEAM_FRACTION), Field::f32)?;
    if !(0.0..=cutoff_deg).contains(&beam_width_deg) {
        let f = beam_field.expect("the default is in range");
        return Err(f.err(format!(
            "must be in [0, cutoff_angle = {cutoff_deg}] degrees, got {beam_width_deg}"
        )));
    }
    Ok(Light::Spot {
        name,
        position,
        direction,
        intensity: rgb_const(Some(t.req("intensity")?), Bound::NonNegative, glam::Vec3::ZERO)?,
        cutoff_deg,
        beam_width_deg,
        projection: projection(t, direction, textures)?,
    })
}

/// A spot's projected `texture` (an image table; a constant colour is the intensity's job)
/// and the image's `up` (default +Y), which must not be along the axis.
fn projection(
    t: &Table,
    axis: glam::Vec3,
    textures: &mut Textures,
) -> Result<Option<Projection>, SceneError> {
    let Some(field) = t.get("texture") else {
        if let Some(up) = t.get("up") {
            return Err(up.err("`up` orients a projected `texture`; this spot has none"));
        }
        return Ok(None);
    };
    if !field.is_table() {
        return Err(field
            .err("a projected texture must be an image, `{ texture = \"file.png\", … }`")
            .hint("a constant colour is the spot's `intensity`"));
    }
    let texture = rgb_input(&field, Bound::NonNegative, textures)?;
    let up_field = t.get("up");
    let up = up_field.as_ref().map_or(Ok(glam::Vec3::Y), Field::direction)?;
    let projection = Projection { texture, up };
    if projection.frame(axis).is_none() {
        return Err(match up_field {
            Some(f) => f.err("`up` is along the spot's axis: the projected image has no orientation"),
            None => t.err(
                "the spot points along +Y or −Y, the default `up` of its projected texture: give `up`, a direction across the axis",
            ),
        });
    }
    Ok(Some(projection))
}
