//! Rectangle (parallelogram), Mitsuba 3's `rectangle` under an affine map.
//!
//! Surface: p(s, t) = c + s·h_u + t·h_v, s, t ∈ [−1, 1]. Front normal
//! n = (h_u × h_v)/|h_u × h_v| (one-sided emitters emit towards n). Intersection: the plane
//! hit of [`super::plane`], accepted when |s| ≤ 1 and |t| ≤ 1; the hit point is re-projected
//! to p(s, t). Texture coordinates as Mitsuba 3's `rectangle` (src/shapes/rectangle.cpp):
//! uv = ((s + 1)/2, (t + 1)/2), so ∂p/∂u = 2·h_u, ∂p/∂v = 2·h_v; the shading tangent is h_u's
//! direction.
//!
//! | name | type | default | unit |
//! |---|---|---|---|
//! | `center` | Vec3 | — | m |
//! | `half_u` | Vec3 (not parallel to `half_v`) | — | m |
//! | `half_v` | Vec3 | — | m |

use glam::{Vec2, Vec3};

use super::plane::PlaneFrame;
use super::{Ray, Surface};

/// A parallelogram `center ± half_u ± half_v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Rectangle {
    frame: PlaneFrame,
}

impl Rectangle {
    /// Validated rectangle; errors name the field.
    pub(crate) fn new(center: Vec3, half_u: Vec3, half_v: Vec3) -> Result<Self, String> {
        Ok(Rectangle {
            frame: PlaneFrame::new("rectangle", center, half_u, half_v)?,
        })
    }

    /// Nearest t ∈ (0, tmax) where the ray meets the rectangle.
    #[inline]
    pub(crate) fn intersect(&self, ray: &Ray, tmax: f32) -> Option<f32> {
        let (t, st) = self.frame.hit(ray, tmax)?;
        (st.x.abs() <= 1.0 && st.y.abs() <= 1.0).then_some(t)
    }

    /// Differential geometry at the hit `ray.at(t)`.
    pub(crate) fn surface(&self, ray: &Ray, t: f32) -> Surface {
        let f = &self.frame;
        let st = f.local(ray.at(t)).clamp(Vec2::NEG_ONE, Vec2::ONE);
        Surface {
            p: f.point(st),
            ng: f.n,
            ns: f.n,
            uv: (st + Vec2::ONE) * 0.5,
            dpdu: f.half_u * 2.0,
            dpdv: f.half_v * 2.0,
            tangent: None,
        }
    }
}
