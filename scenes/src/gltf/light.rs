//! KHR_lights_punctual → [`Light`].
//!
//! The light sits at its node's world origin and points down the node's −Z axis.
//!
//! | glTF | unit | model | unit | conversion |
//! |---|---|---|---|---|
//! | point `intensity` × `color` | cd (lm/sr) | [`Light::Point`] `intensity` | W/sr | value taken as is |
//! | spot `intensity` × `color` | cd | [`Light::Spot`] `intensity` | W/sr | value taken as is |
//! | spot `outerConeAngle` (default π/4) | rad | `cutoff_deg` | deg | to degrees |
//! | spot `innerConeAngle` (default 0) | rad | `beam_width_deg` | deg | to degrees |
//! | directional `intensity` × `color` | lux (lm/m²) | [`Light::Directional`] `irradiance` | W/m² | value taken as is |
//! | node −Z | | `direction` | | direction of travel, unit |
//! | `range` | m | — | | ignored (noted): our lights follow the inverse-square law to infinity |
//!
//! Photometric values are used as radiometric numbers (no 683 lm/W luminous efficacy): a
//! scene's absolute scale does not change any comparison, and both renderers read the same
//! numbers. The spot profile differs inside the transition band: glTF suggests a smooth
//! falloff in cos θ between the cone angles, the model uses Mitsuba's linear falloff in θ;
//! full-intensity and zero regions agree.

use std::collections::BTreeSet;

use ::gltf::khr_lights_punctual::Kind;
use glam::{Mat4, Vec3};

use super::source::Asset;
use crate::error::SceneError;
use crate::model::Light;

/// Converts `light`, attached to `nodes[node]` with world matrix `world`, named `name`.
pub(super) fn convert(
    asset: &Asset,
    light: &::gltf::khr_lights_punctual::Light,
    node: usize,
    world: &Mat4,
    name: String,
    notes: &mut BTreeSet<String>,
) -> Result<Light, SceneError> {
    let at = format!("extensions.KHR_lights_punctual.lights[{}]", light.index());
    let color = Vec3::from(light.color());
    if !(color.is_finite() && color.min_element() >= 0.0) {
        return Err(asset.err(
            format!("{at}.color"),
            format!("must be finite and ≥ 0, got {color}"),
        ));
    }
    let intensity = light.intensity();
    if !(intensity.is_finite() && intensity >= 0.0) {
        return Err(asset.err(
            format!("{at}.intensity"),
            format!("must be finite and ≥ 0, got {intensity}"),
        ));
    }
    if light.range().is_some() {
        notes.insert(format!(
            "{at}.range: ignored; the light falls off with the inverse square of distance"
        ));
    }
    let power = color * intensity;
    let position = world.transform_point3(Vec3::ZERO);
    let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    if !position.is_finite() || direction == Vec3::ZERO || !direction.is_finite() {
        return Err(asset.err(
            format!("nodes[{node}]"),
            "the light's node transform is degenerate (its −Z axis has no direction)",
        ));
    }
    Ok(match light.kind() {
        Kind::Point => Light::Point {
            name,
            position,
            intensity: power,
        },
        Kind::Directional => Light::Directional {
            name,
            direction,
            irradiance: power,
            angular_diameter_deg: 0.0,
        },
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let half_pi = std::f32::consts::FRAC_PI_2;
            if !(outer_cone_angle > 0.0 && outer_cone_angle <= half_pi) {
                return Err(asset.err(
                    format!("{at}.spot.outerConeAngle"),
                    format!("must lie in (0, π/2], got {outer_cone_angle}"),
                ));
            }
            if !(inner_cone_angle >= 0.0 && inner_cone_angle <= outer_cone_angle) {
                return Err(asset.err(
                    format!("{at}.spot.innerConeAngle"),
                    format!("must lie in [0, outerConeAngle = {outer_cone_angle}], got {inner_cone_angle}"),
                ));
            }
            Light::Spot {
                name,
                position,
                direction,
                intensity: power,
                cutoff_deg: outer_cone_angle.to_degrees(),
                beam_width_deg: inner_cone_angle.to_degrees(),
            }
        }
    })
}
