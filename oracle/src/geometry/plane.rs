//! The affine plane frame shared by [`super::rectangle`] and [`super::disk`].
//!
//! Points p = c + s·h_u + t·h_v of the plane through c spanned by the half axes h_u, h_v;
//! front normal n = (h_u × h_v)/|h_u × h_v|. Ray/plane: t_hit = ((c − o)·n)/(d·n). Local
//! coordinates of a point by the dual basis (h_u*, h_v*) with h_u*·h_u = 1, h_u*·h_v = 0:
//! h_u* = (h_v × n)/(h_u·(h_v × n)), h_v* = (n × h_u)/(h_v·(n × h_u)), so s = (p − c)·h_u*,
//! t = (p − c)·h_v* (exact for sheared, non-orthogonal axes too).

use glam::{Vec2, Vec3};

use super::Ray;

/// Plane frame with its dual basis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PlaneFrame {
    /// Origin of the local coordinates.
    pub(crate) center: Vec3,
    /// First half axis.
    pub(crate) half_u: Vec3,
    /// Second half axis.
    pub(crate) half_v: Vec3,
    /// Unit front normal.
    pub(crate) n: Vec3,
    dual_u: Vec3,
    dual_v: Vec3,
}

impl PlaneFrame {
    /// Validated frame; `what` names the shape kind in errors.
    pub(crate) fn new(what: &str, center: Vec3, half_u: Vec3, half_v: Vec3) -> Result<Self, String> {
        for (name, v) in [("center", center), ("half_u", half_u), ("half_v", half_v)] {
            if !v.is_finite() {
                return Err(format!("{what} `{name}` is not finite: {v}"));
            }
        }
        let cross = half_u.cross(half_v);
        let n = cross.normalize_or_zero();
        if n == Vec3::ZERO {
            return Err(format!(
                "{what} has zero area: `half_u` {half_u} and `half_v` {half_v} are parallel or zero"
            ));
        }
        let dual_u = half_v.cross(n) / half_u.dot(half_v.cross(n));
        let dual_v = n.cross(half_u) / half_v.dot(n.cross(half_u));
        Ok(PlaneFrame {
            center,
            half_u,
            half_v,
            n,
            dual_u,
            dual_v,
        })
    }

    /// Ray parameter t ∈ (0, tmax) and local (s, t) of the plane hit, if any.
    #[inline]
    pub(crate) fn hit(&self, ray: &Ray, tmax: f32) -> Option<(f32, Vec2)> {
        let denom = ray.dir.dot(self.n);
        let t = (self.center - ray.origin).dot(self.n) / denom;
        if !(t > 0.0 && t < tmax) {
            return None;
        }
        Some((t, self.local(ray.at(t))))
    }

    /// Local coordinates (s, t) of a point of the plane.
    #[inline]
    pub(crate) fn local(&self, p: Vec3) -> Vec2 {
        let r = p - self.center;
        Vec2::new(r.dot(self.dual_u), r.dot(self.dual_v))
    }

    /// The plane point at local (s, t): re-projects hits onto the plane.
    #[inline]
    pub(crate) fn point(&self, st: Vec2) -> Vec3 {
        self.center + self.half_u * st.x + self.half_v * st.y
    }
}
