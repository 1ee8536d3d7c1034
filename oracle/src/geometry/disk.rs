//! Disk (ellipse), Mitsuba 3's `disk` under an affine map.
//!
//! Surface: p(x, y) = c + x·h_u + y·h_v with x² + y² ≤ 1, i.e. c + r·(cos φ·h_u + sin φ·h_v),
//! r ∈ [0, 1]. Front normal n = (h_u × h_v)/|h_u × h_v|. Intersection: the plane hit of
//! [`super::plane`], accepted when x² + y² ≤ 1; the hit point is re-projected to p(x, y).
//! Texture coordinates as Mitsuba 3's `disk` (src/shapes/disk.cpp): uv = (r, φ/2π) with
//! φ = atan2(y, x) ∈ [0, 2π); ∂p/∂u = cos φ·h_u + sin φ·h_v (radial; h_u at the centre),
//! ∂p/∂v ∝ −sin φ·h_u + cos φ·h_v (Mitsuba's unscaled tangential direction).
//!
//! | name | type | default | unit |
//! |---|---|---|---|
//! | `center` | Vec3 | — | m |
//! | `half_u` | Vec3 (not parallel to `half_v`) | — | m |
//! | `half_v` | Vec3 | — | m |

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

use super::plane::PlaneFrame;
use super::{Ray, Surface};

/// An ellipse with semi-axes `half_u`, `half_v` around `center`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Disk {
    frame: PlaneFrame,
}

impl Disk {
    /// Validated disk; errors name the field.
    pub(crate) fn new(center: Vec3, half_u: Vec3, half_v: Vec3) -> Result<Self, String> {
        Ok(Disk {
            frame: PlaneFrame::new("disk", center, half_u, half_v)?,
        })
    }

    /// Nearest t ∈ (0, tmax) where the ray meets the disk.
    #[inline]
    pub(crate) fn intersect(&self, ray: &Ray, tmax: f32) -> Option<f32> {
        let (t, xy) = self.frame.hit(ray, tmax)?;
        (xy.length_squared() <= 1.0).then_some(t)
    }

    /// Differential geometry at the hit `ray.at(t)`.
    pub(crate) fn surface(&self, ray: &Ray, t: f32) -> Surface {
        let f = &self.frame;
        // Local (x, y), pulled back inside the unit circle against rounding at the rim.
        let mut xy = f.local(ray.at(t));
        let mut r = xy.length();
        if r > 1.0 {
            xy /= r;
            r = 1.0;
        }
        let (cos_phi, sin_phi) = if r > 0.0 { (xy.x / r, xy.y / r) } else { (1.0, 0.0) };
        let phi = {
            let phi = xy.y.atan2(xy.x);
            if phi < 0.0 {
                phi + TAU
            } else {
                phi
            }
        };
        Surface {
            p: f.point(xy),
            ng: f.n,
            ns: f.n,
            uv: Vec2::new(r, phi / TAU),
            dpdu: f.half_u * cos_phi + f.half_v * sin_phi,
            dpdv: f.half_v * cos_phi - f.half_u * sin_phi,
            tangent: None,
        }
    }
}
