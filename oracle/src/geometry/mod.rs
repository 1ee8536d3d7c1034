//! Ray/surface geometry: rays, the shapes of the scene model, and the acceleration structure.
//!
//! Every surface of a [`scenes::Scene`] — each triangle of every mesh (of a displaced mesh:
//! each micro-triangle), each analytic sphere, rectangle and disk, and each heightfield patch
//! (a displaced rectangle) — is one primitive of a single four-wide BVH ([`Accel`]: PLOC
//! from obvhs, collapsed to four children per node, `wide_bvh.rs` and `traverse.rs`). A
//! closest hit comes back as a [`SurfaceHit`]: position, geometric and shading normals,
//! tangent and texture coordinates, computed by the primitive's own file:
//!
//! | shape | file | intersection |
//! |---|---|---|
//! | triangle | `triangle.rs` | watertight (Woop, Benthin & Wald 2013) |
//! | sphere | `sphere.rs` | precise quadratic (Haines et al. 2019) |
//! | rectangle | `rectangle.rs` | plane + dual-basis local coordinates |
//! | disk | `disk.rs` | plane + dual-basis local coordinates |
//! | heightfield patch | `heightfield.rs` | min/max quadtree of bilinear cells (`bilinear.rs`, Reshetov 2019) |
//!
//! Rays leaving a surface are offset with [`spawn_ray`] / [`spawn_ray_to`]
//! (Wächter & Binder 2019).

mod accel;
mod bilinear;
mod disk;
mod heightfield;
mod normal_map;
mod plane;
mod ray;
mod rectangle;
mod sphere;
mod traverse;
mod triangle;
mod wide_bvh;

use glam::{Vec2, Vec3};

pub use accel::{Accel, BuildQuality};
pub use ray::{offset_point, spawn_ray, spawn_ray_to, Ray, SHADOW_EPSILON};

use disk::Disk;
use rectangle::Rectangle;
use sphere::Sphere;

/// A ray's closest hit on a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// Ray parameter of the hit (distance, the direction being unit).
    pub t: f32,
    /// Hit point, computed from the primitive's parametrisation (not o + t·d).
    pub p: Vec3,
    /// Unit geometric normal on the shape's FRONT side: rectangle/disk half_u × half_v,
    /// triangle (p₁ − p₀) × (p₂ − p₀) (counter-clockwise front), sphere outward, heightfield
    /// patch ∂p/∂u × ∂p/∂v of the displaced surface.
    pub ng: Vec3,
    /// Unit shading normal: interpolated vertex normals with the normal map applied; not
    /// flipped towards the ray or `ng`; equal to `ng` when the shape has neither.
    pub ns: Vec3,
    /// Unit tangent orthogonal to `ns`: the authored tangent, else ∂p/∂u (sphere ∂p/∂φ,
    /// rectangle half_u's direction, disk radial).
    pub dpdu: Vec3,
    /// Texture coordinates (interpolated mesh uvs; analytic shapes as `scenes::Geometry`
    /// documents).
    pub uv: Vec2,
    /// Index into `scene.shapes`.
    pub shape: u32,
    /// Triangle index within its mesh (`Mesh::indices`; of a displaced mesh, within its
    /// micro-triangle mesh), cell index j·(cells along u) + i of a heightfield patch; 0 for
    /// analytic shapes.
    pub prim: u32,
}

/// Differential geometry of a hit before the shading frame is set up.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Surface {
    /// Hit point.
    pub(crate) p: Vec3,
    /// Unit front-side geometric normal.
    pub(crate) ng: Vec3,
    /// Unit interpolated shading normal (`ng` when none).
    pub(crate) ns: Vec3,
    /// Texture coordinates.
    pub(crate) uv: Vec2,
    /// ∂p/∂u (any length, possibly zero).
    pub(crate) dpdu: Vec3,
    /// ∂p/∂v (any length, possibly zero).
    pub(crate) dpdv: Vec3,
    /// Authored tangent and its handedness w = ±1.
    pub(crate) tangent: Option<(Vec3, f32)>,
}

/// The analytic shapes: a closed set dispatched by one `match` per method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Analytic {
    /// See [`sphere`].
    Sphere(Sphere),
    /// See [`rectangle`].
    Rectangle(Rectangle),
    /// See [`disk`].
    Disk(Disk),
}

impl Analytic {
    /// Nearest t ∈ (0, tmax) where the ray meets the shape.
    #[inline]
    pub(crate) fn intersect(&self, ray: &Ray, tmax: f32) -> Option<f32> {
        match self {
            Analytic::Sphere(s) => s.intersect(ray, tmax),
            Analytic::Rectangle(r) => r.intersect(ray, tmax),
            Analytic::Disk(d) => d.intersect(ray, tmax),
        }
    }

    /// Differential geometry at the hit `ray.at(t)`.
    pub(crate) fn surface(&self, ray: &Ray, t: f32) -> Surface {
        match self {
            Analytic::Sphere(s) => s.surface(ray, t),
            Analytic::Rectangle(r) => r.surface(ray, t),
            Analytic::Disk(d) => d.surface(ray, t),
        }
    }
}
