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
//! Every light of the file is checked at load, placed or not ([`check_all`]), against the
//! ranges of the KHR_lights_punctual specification ("Light Types", "Spot", and its JSON
//! schema): `color` components ≥ 0, `intensity` ≥ 0, `range` > 0, `innerConeAngle` ≥ 0,
//! `outerConeAngle` in (0, π/2], `innerConeAngle` ≤ `outerConeAngle` (the extension asks for
//! `<`; equal angles, a hard-edged cone, are what Blender writes for a spot blend of 0 and are
//! accepted). Everything must be finite, and `intensity` × `color` at most [`MAX_EMITTED`].
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

/// Largest emitted quantity accepted (a light's `intensity` × `color`, in cd or lux; an
/// emissive material's radiance). The renderers multiply it by BSDF values, cosines and
/// 1/distance² (10¹² at a micrometre) and add up many samples in f32, whose largest value is
/// 3.4·10³⁸: 10²⁰ keeps all of that finite, and is far beyond any physical source (the
/// sun's luminance is about 1.6·10⁹ cd/m²).
pub(super) const MAX_EMITTED: f32 = 1e20;

/// Checks every light of the file (module header).
pub(super) fn check_all(asset: &Asset) -> Result<(), SceneError> {
    for light in asset.doc.lights().into_iter().flatten() {
        check(asset, &light)?;
    }
    Ok(())
}

/// Checks one light's numbers (module header).
fn check(asset: &Asset, light: &::gltf::khr_lights_punctual::Light) -> Result<(), SceneError> {
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
    let power = color * intensity;
    if !(power.is_finite() && power.max_element() <= MAX_EMITTED) {
        return Err(asset.err(
            format!("{at}.intensity"),
            format!(
                "intensity {intensity:e} × color {color} exceeds {MAX_EMITTED:e}, more than the renderers can sum in f32"
            ),
        ));
    }
    if let Some(range) = light.range() {
        if !(range.is_finite() && range > 0.0) {
            return Err(asset.err(
                format!("{at}.range"),
                format!("must be finite and > 0, got {range}"),
            ));
        }
    }
    if let Kind::Spot {
        inner_cone_angle,
        outer_cone_angle,
    } = light.kind()
    {
        let half_pi = std::f32::consts::FRAC_PI_2;
        if !(outer_cone_angle > 0.0 && outer_cone_angle <= half_pi) {
            return Err(asset.err(
                format!("{at}.spot.outerConeAngle"),
                format!("must lie in (0, π/2] (KHR_lights_punctual), got {outer_cone_angle}"),
            ));
        }
        if !(inner_cone_angle >= 0.0 && inner_cone_angle <= outer_cone_angle) {
            return Err(asset.err(
                format!("{at}.spot.innerConeAngle"),
                format!(
                    "must lie in [0, outerConeAngle = {outer_cone_angle}] (KHR_lights_punctual), got {inner_cone_angle}"
                ),
            ));
        }
    }
    Ok(())
}

/// Converts `light` (checked by [`check_all`]), attached to `nodes[node]` with world matrix
/// `world`, named `name`.
pub(super) fn convert(
    asset: &Asset,
    light: &::gltf::khr_lights_punctual::Light,
    node: usize,
    world: &Mat4,
    name: String,
    notes: &mut BTreeSet<String>,
) -> Result<Light, SceneError> {
    let at = format!("extensions.KHR_lights_punctual.lights[{}]", light.index());
    if light.range().is_some() {
        notes.insert(format!(
            "{at}.range: ignored; the light falls off with the inverse square of distance"
        ));
    }
    let power = Vec3::from(light.color()) * light.intensity();
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
        } => Light::Spot {
            name,
            position,
            direction,
            intensity: power,
            cutoff_deg: outer_cone_angle.to_degrees(),
            beam_width_deg: inner_cone_angle.to_degrees(),
            projection: None,
        },
    })
}
