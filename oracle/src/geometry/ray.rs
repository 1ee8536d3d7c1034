//! Rays and robust ray spawning.
//!
//! A ray leaving a surface must not hit that surface again because the hit point carries
//! floating-point error. We offset the origin along the geometric normal with the integer-ULP
//! scheme of Wächter & Binder 2019, "A Fast and Robust Method for Avoiding Self-Intersection",
//! Ray Tracing Gems ch. 6, Listing 6-1:
//!
//! - far from the origin (|pᵢ| ≥ 1/32) each coordinate moves by ⌊256·nᵢ⌋ units in the last
//!   place of pᵢ (the error of a computed hit point grows with |pᵢ|, and so does the offset);
//! - near the origin (|pᵢ| < 1/32), where ULPs become tiny, it moves by nᵢ/65536.
//!
//! The scheme assumes the hit point is computed from the primitive's own parametrisation
//! (barycentric interpolation of the vertices, re-projection onto the sphere or plane), which
//! is what every shape in this module does; the offset then exceeds the error of p.
//!
//! | constant | value | meaning |
//! |---|---|---|
//! | `ORIGIN` | 1/32 | below this |pᵢ| use a fixed offset |
//! | `FLOAT_SCALE` | 1/65536 | fixed offset per unit normal component |
//! | `INT_SCALE` | 256 | ULPs per unit normal component |
//! | `SHADOW_EPSILON` | 10⁻⁴ | relative shortening of shadow segments (pbrt-v4 §6.8.6) |

use glam::Vec3;

/// A ray `origin + t·dir`, t > 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin, world space (metres).
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
}

impl Ray {
    /// Ray from `origin` along unit `dir`.
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray { origin, dir }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// Below this magnitude a coordinate is offset by a fixed amount (Wächter & Binder 2019).
const ORIGIN: f32 = 1.0 / 32.0;
/// Fixed offset per unit normal component near the origin (Wächter & Binder 2019).
const FLOAT_SCALE: f32 = 1.0 / 65536.0;
/// ULPs of offset per unit normal component (Wächter & Binder 2019).
const INT_SCALE: f32 = 256.0;
/// Shadow segments end this fraction short of their target (pbrt-v4 §6.8.6 `ShadowEpsilon`).
pub const SHADOW_EPSILON: f32 = 1e-4;

/// Moves `p` off its surface along unit `n` (already turned to the side to leave on):
/// Wächter & Binder 2019, Ray Tracing Gems ch. 6, Listing 6-1.
pub fn offset_point(p: Vec3, n: Vec3) -> Vec3 {
    let offset = |p: f32, n: f32| -> f32 {
        if p.abs() < ORIGIN {
            return p + FLOAT_SCALE * n;
        }
        // Truncation towards zero as in the listing's int conversion.
        let of_i = (INT_SCALE * n) as i32;
        let of_i = if p < 0.0 { -of_i } else { of_i };
        f32::from_bits((p.to_bits() as i32).wrapping_add(of_i) as u32)
    };
    Vec3::new(offset(p.x, n.x), offset(p.y, n.y), offset(p.z, n.z))
}

/// `ng` turned to the side `dir` points to.
#[inline]
fn facing(ng: Vec3, dir: Vec3) -> Vec3 {
    if ng.dot(dir) < 0.0 {
        -ng
    } else {
        ng
    }
}

/// Robust origin offset against self-intersection: Wächter & Binder 2019, "A Fast and Robust
/// Method for Avoiding Self-Intersection", Ray Tracing Gems ch. 6. Offsets `p` along ±`ng`
/// (the side of `dir`); `dir` must be unit.
pub fn spawn_ray(p: Vec3, ng: Vec3, dir: Vec3) -> Ray {
    Ray {
        origin: offset_point(p, facing(ng, dir)),
        dir,
    }
}

/// Ray from surface point `p` (geometric normal `ng`) towards the point `q`, offset at `p`;
/// returns (ray, tmax). When `ng_q` is given, `q` lies on a surface and is offset along
/// ±`ng_q` towards the ray's origin, so that surface is not hit; tmax is further shortened by
/// the relative [`SHADOW_EPSILON`] (pbrt-v4 §6.8.6, `SpawnRayTo`). A segment that collapses
/// to zero length after the offsets returns tmax = 0 (nothing can occlude it).
pub fn spawn_ray_to(p: Vec3, ng: Vec3, q: Vec3, ng_q: Option<Vec3>) -> (Ray, f32) {
    let origin = offset_point(p, facing(ng, q - p));
    let target = match ng_q {
        Some(nq) => offset_point(q, facing(nq, origin - q)),
        None => q,
    };
    let d = target - origin;
    let len = d.length();
    if !(len > 0.0 && len.is_finite()) {
        return (Ray { origin, dir: ng }, 0.0);
    }
    (Ray { origin, dir: d / len }, len * (1.0 - SHADOW_EPSILON))
}
