//! glTF cameras → [`Camera`] and [`Film`].
//!
//! | glTF (2.0 "Cameras") | model | notes |
//! |---|---|---|
//! | node world transform, looking down its −Z, +Y up | `Camera::to_world` | made rigid: scale, shear and mirroring removed by Gram–Schmidt keeping −Z exact |
//! | perspective `yfov` (rad) | `fov_y_deg` | to degrees |
//! | perspective `aspectRatio` | `Film` | height 512, width round(512·aspect); 512×512 when absent |
//! | `znear`, `zfar` | — | checked, then ignored: neither renderer clips |
//! | orthographic | — | unsupported (an error when no perspective camera is placed) |
//!
//! Every perspective camera of the file is checked at load, used or not ([`check_all`]),
//! against glTF 2.0 §5.13 "camera.perspective": `yfov` > 0 (and < π here), `aspectRatio` > 0,
//! `znear` > 0, `zfar` > `znear`, all finite.
//!
//! Without a camera the scene is framed from the +Y/+Z diagonal with a 40° field of view,
//! far enough that the bounding sphere fits the vertical field of view.

use glam::{Affine3A, Mat3, Mat4, Vec3};

use super::source::Asset;
use crate::error::SceneError;
use crate::model::{Camera, Film};

/// Film height used for glTF cameras and the default framing, pixels.
pub(super) const FILM_HEIGHT: u32 = 512;
/// Vertical field of view of the default framing, degrees.
pub(super) const DEFAULT_FOV_DEG: f32 = 40.0;
/// Largest film side the model allows.
const MAX_FILM: u32 = 16384;

/// Checks every perspective camera of the file (module header).
pub(super) fn check_all(asset: &Asset) -> Result<(), SceneError> {
    for cam in asset.doc.cameras() {
        let ::gltf::camera::Projection::Perspective(persp) = cam.projection() else {
            continue;
        };
        let at = format!("cameras[{}].perspective", cam.index());
        let yfov = persp.yfov();
        if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
            return Err(asset.err(
                format!("{at}.yfov"),
                format!("must lie in (0, π) radians, got {yfov}"),
            ));
        }
        if let Some(aspect) = persp.aspect_ratio() {
            if !(aspect.is_finite() && aspect > 0.0) {
                return Err(asset.err(
                    format!("{at}.aspectRatio"),
                    format!("must be finite and > 0, got {aspect}"),
                ));
            }
        }
        let znear = persp.znear();
        if !(znear.is_finite() && znear > 0.0) {
            return Err(asset.err(
                format!("{at}.znear"),
                format!("must be finite and > 0, got {znear}"),
            ));
        }
        if let Some(zfar) = persp.zfar() {
            if !(zfar.is_finite() && zfar > znear) {
                return Err(asset.err(
                    format!("{at}.zfar"),
                    format!("must be finite and greater than znear = {znear}, got {zfar}"),
                ));
            }
        }
    }
    Ok(())
}

/// The camera placed at `nodes[node]` with world matrix `world` (a perspective camera,
/// checked by [`check_all`]).
pub(super) fn from_node(
    asset: &Asset,
    persp: &::gltf::camera::Perspective,
    camera_index: usize,
    node: usize,
    world: &Mat4,
) -> Result<(Camera, Film), SceneError> {
    let at = format!("cameras[{camera_index}].perspective");
    let yfov = persp.yfov();
    let film = match persp.aspect_ratio() {
        None => Film {
            width: FILM_HEIGHT,
            height: FILM_HEIGHT,
        },
        Some(aspect) => {
            let width = (FILM_HEIGHT as f32 * aspect).round();
            if !(aspect.is_finite() && width >= 1.0 && width <= MAX_FILM as f32) {
                return Err(asset.err(
                    format!("{at}.aspectRatio"),
                    format!("{aspect} gives a film width outside 1..={MAX_FILM} at height {FILM_HEIGHT}"),
                ));
            }
            Film {
                width: width as u32,
                height: FILM_HEIGHT,
            }
        }
    };
    let to_world = rigid(world).ok_or_else(|| {
        asset.err(
            format!("nodes[{node}]"),
            "the camera node's transform is degenerate (no view or up direction)",
        )
    })?;
    Ok((
        Camera {
            to_world,
            fov_y_deg: yfov.to_degrees(),
        },
        film,
    ))
}

/// The rigid part of `world` keeping its −Z axis (view direction) exactly and its +Y axis
/// (up) as closely as possible: z = normalize(Z), x = normalize(Y × z), y = z × x.
fn rigid(world: &Mat4) -> Option<Affine3A> {
    let z = world.z_axis.truncate().try_normalize()?;
    let x = world.y_axis.truncate().cross(z).try_normalize()?;
    let y = z.cross(x);
    let origin = world.w_axis.truncate();
    origin
        .is_finite()
        .then(|| Affine3A::from_mat3_translation(Mat3::from_cols(x, y, z), origin))
}

/// A camera that frames the sphere (`center`, `radius`) from the +Y/+Z diagonal.
pub(super) fn framing(center: Vec3, radius: f32) -> (Camera, Film) {
    let half = (DEFAULT_FOV_DEG * 0.5).to_radians();
    let distance = radius / half.sin();
    let eye = center + Vec3::new(0.0, 1.0, 1.0).normalize() * distance;
    let camera = Camera::look_at(eye, center, Vec3::Y, DEFAULT_FOV_DEG);
    (
        camera,
        Film {
            width: FILM_HEIGHT,
            height: FILM_HEIGHT,
        },
    )
}
