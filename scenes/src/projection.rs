//! A texture projected by a spot light: a cookie or gobo, projective texture mapping (Segal,
//! Korobkin, van Widenfelt, Foran & Haeberli 1992, "Fast Shadows and Lighting Effects Using
//! Texture Mapping", SIGGRAPH, §3: the light as a projector whose texture coordinates are the
//! point's position in the light's clip space).
//!
//! The radiant intensity leaving the spot along unit direction ω is I·s(θ)·T(uv(ω)), s the
//! spot's falloff and T the texture (bilinear, texel centres at ((i + ½)/W, (j + ½)/H), v = 0
//! the top row, as every texture). In the light's frame — axis a, right r = a × up/|a × up|,
//! image up t = r × a —
//!
//! uv(ω) = (½ + ½·(r·ω)/((a·ω)·tan θc),  ½ − ½·(t·ω)/((a·ω)·tan θc)),
//!
//! so the image fills the square around the cutoff cone (its inscribed disk is the cone) and
//! stands upright seen from behind the light looking along a with `up` up, as a slide
//! projector shows it. This is Mitsuba 3's `spot` `texture` mapping (uv = ½ + ½·(x, y)/(z·tan θc)
//! in its `to_world` frame) with that frame's up vector −up (compare's exporter writes it so).
//!
//! The model's [`crate::model::Projection`] (texture and up) holds a spot's projection; the
//! functions here are its geometry.

use glam::{Vec2, Vec3};

/// Right r and image-up t of a projector with unit axis `axis` and image up `up` (module
/// docs); None when `up` is along the axis.
pub fn frame(axis: Vec3, up: Vec3) -> Option<(Vec3, Vec3)> {
    let r = axis.cross(up).try_normalize()?;
    Some((r, r.cross(axis)))
}

/// uv(ω) of unit direction `w` leaving a projector with axis `axis`, frame (r, t) and
/// tan θc = `tan_cutoff` (module docs); None behind it.
pub fn uv(axis: Vec3, (r, t): (Vec3, Vec3), tan_cutoff: f32, w: Vec3) -> Option<Vec2> {
    // Behind the light, on its plane, or NaN: no projection.
    let z = axis.dot(w);
    if z.is_nan() || z <= 0.0 {
        return None;
    }
    let s = 0.5 / (z * tan_cutoff);
    Some(Vec2::new(0.5 + s * r.dot(w), 0.5 - s * t.dot(w)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_image_stands_upright_behind_the_light_and_fills_the_cone_square() {
        // Pointing down −Z with up +Y: right is +X.
        let axis = -Vec3::Z;
        let f = frame(axis, Vec3::Y).unwrap();
        assert!((f.0 - Vec3::X).length() < 1e-6 && (f.1 - Vec3::Y).length() < 1e-6);
        let tan = 30f32.to_radians().tan();
        let at = |w: Vec3| uv(axis, f, tan, w.normalize()).unwrap();
        assert!((at(axis) - Vec2::splat(0.5)).length() < 1e-6);
        // Right of the axis at the cutoff: u = 1; above it: v = 0 (the top row).
        assert!((at(Vec3::new(tan, 0.0, -1.0)) - Vec2::new(1.0, 0.5)).length() < 1e-5);
        assert!((at(Vec3::new(0.0, tan, -1.0)) - Vec2::new(0.5, 0.0)).length() < 1e-5);
        assert!(uv(axis, f, tan, Vec3::Z).is_none());
        assert!(frame(axis, -Vec3::Z).is_none());
    }
}
