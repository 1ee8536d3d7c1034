//! The rasteriser's camera near plane, shared by the frame's projection and the cascades'
//! view-depth range.

use scenes::Scene;

/// Near-plane distance as a fraction of the scene's bounding radius (reversed-Z keeps the
/// depth precise anyway; only geometry closer than this to the camera is clipped).
const NEAR_FRACTION: f32 = 1e-4;

/// The camera's near-plane distance for `scene`: [`NEAR_FRACTION`] × its bounding radius.
pub fn camera_near(scene: &Scene) -> f32 {
    NEAR_FRACTION * scene.bounding_sphere().1
}
