//! The rasteriser's camera: its near plane (shared by the frame's projection and the
//! cascades' view-depth range) and its view-projection (the frame's, and TAA's reprojection).

use glam::{Mat4, Vec2, Vec3};
use scenes::{Camera, Scene};

/// Near-plane distance as a fraction of the scene's bounding radius (reversed-Z keeps the
/// depth precise anyway; only geometry closer than this to the camera is clipped).
const NEAR_FRACTION: f32 = 1e-4;

/// The camera's near-plane distance for `scene`: [`NEAR_FRACTION`] × its bounding radius.
pub fn camera_near(scene: &Scene) -> f32 {
    NEAR_FRACTION * scene.bounding_sphere().1
}

/// The view-projection of `camera` on a `w`×`h` film (reversed-Z, infinite far plane, near
/// plane `near`), its image moved by `jitter` pixels (x right, y down).
pub(crate) fn view_proj(camera: &Camera, w: u32, h: u32, near: f32, jitter: Vec2) -> Mat4 {
    let aspect = w as f32 / h as f32;
    let proj = Mat4::perspective_infinite_reverse_rh(camera.fov_y_deg.to_radians(), aspect, near);
    // NDC spans the film's 2 units over W (x, up) and H (y, down) pixels.
    let shift = Mat4::from_translation(Vec3::new(
        2.0 * jitter.x / w as f32,
        -2.0 * jitter.y / h as f32,
        0.0,
    ));
    shift * proj * Mat4::from(camera.to_world.inverse())
}
