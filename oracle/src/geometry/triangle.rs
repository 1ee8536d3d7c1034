//! Triangles of a mesh: watertight intersection and barycentric interpolation.
//!
//! Intersection: Woop, Benthin & Wald 2013, "Watertight Ray/Triangle Intersection", JCGT 2(1).
//! Per ray, the dominant axis k_z = argmax |dᵢ| (k_x, k_y the others, swapped when d_kz < 0
//! to keep the winding) and the shear S = (d_kx/d_kz, d_ky/d_kz, 1/d_kz) map the ray to the
//! +z axis. Per triangle, the sheared vertices A, B, C relative to the origin give the 2D
//! edge functions U = C_x·B_y − C_y·B_x, V = A_x·C_y − A_y·C_x, W = B_x·A_y − B_y·A_x, which
//! are recomputed in f64 when one is exactly zero (§3 of the paper), so edges shared by two
//! triangles leak no rays. A hit needs U, V, W of one sign; with det = U + V + W and
//! T = U·A_z + V·B_z + W·C_z, t = T/det and the barycentrics are (U, V, W)/det. Both sides
//! are hit (no culling).
//!
//! Interpolation at barycentrics (b₀, b₁, b₂): p = Σ bᵢ·pᵢ (the hit point from the
//! primitive's parametrisation, as Wächter & Binder's offset assumes); geometric normal
//! n_g = normalize((p₁ − p₀) × (p₂ − p₀)) (counter-clockwise front); shading normal
//! normalize(Σ bᵢ·nᵢ), or n_g for the whole triangle when a vertex normal is missing, NaN or
//! zero; uv = Σ bᵢ·uvᵢ, or (b₁, b₂) without texture coordinates (Mitsuba 3's convention).
//! ∂p/∂u, ∂p/∂v solve [p₀ − p₂; p₁ − p₂] = [uv₀ − uv₂; uv₁ − uv₂]·[∂p/∂u; ∂p/∂v]
//! (Pharr, Jakob & Humphreys, PBR 4th ed. (pbrt-v4) §6.5.3), falling back to the edges
//! p₁ − p₀, p₂ − p₀ when the uv mapping is degenerate or absent. An authored tangent
//! (glTF TANGENT: xyz, w = handedness) is interpolated the same way.
//!
//! | name | type | default | unit |
//! |---|---|---|---|
//! | `positions` | [Vec3] | — | m |
//! | `indices` | [[u32; 3]], counter-clockwise front | — | — |
//! | `normals` | [Vec3] or empty | flat | — |
//! | `uvs` | [Vec2] or empty | (b₁, b₂) | — |
//! | `tangents` | [Vec4] or empty | from ∂p/∂u | — |

use glam::{DVec2, Vec2, Vec3, Vec4, Vec4Swizzles};
use scenes::Mesh;

use super::{Ray, Surface};

/// The three vertices of a triangle, stored in BVH order for locality.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Triangle {
    /// Vertices p₀, p₁, p₂ (counter-clockwise seen from the front).
    pub(crate) v: [Vec3; 3],
}

/// The per-ray part of the watertight test: the shear to ray space (Woop et al. 2013, §2).
#[derive(Clone, Copy, Debug)]
pub(crate) struct WatertightRay {
    org: Vec3,
    k: [usize; 3],
    shear: Vec3,
}

impl WatertightRay {
    /// Precomputes the permutation and shear for `ray` (direction non-zero and finite).
    pub(crate) fn new(ray: &Ray) -> Self {
        let d = ray.dir;
        let a = d.abs();
        let kz = if a.x > a.y {
            if a.x > a.z {
                0
            } else {
                2
            }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        // Swap to preserve the winding (sign of the edge functions) when d_kz < 0.
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        WatertightRay {
            org: ray.origin,
            k: [kx, ky, kz],
            shear: Vec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]),
        }
    }
}

impl Triangle {
    /// Nearest hit t ∈ (0, tmax) and barycentrics (b₀, b₁, b₂) (Woop et al. 2013, Fig. 1 without
    /// back-face culling).
    #[inline]
    pub(crate) fn intersect(&self, r: &WatertightRay, tmax: f32) -> Option<(f32, Vec3)> {
        let [kx, ky, kz] = r.k;
        let s = r.shear;
        let a = self.v[0] - r.org;
        let b = self.v[1] - r.org;
        let c = self.v[2] - r.org;
        // Sheared 2D vertex coordinates.
        let (ax, ay) = (a[kx] - s.x * a[kz], a[ky] - s.y * a[kz]);
        let (bx, by) = (b[kx] - s.x * b[kz], b[ky] - s.y * b[kz]);
        let (cx, cy) = (c[kx] - s.x * c[kz], c[ky] - s.y * c[kz]);
        // Scaled barycentric coordinates (2D edge functions).
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            // Exact products in f64 decide the sign on the edge (§3 of the paper).
            let edge = |p: (f32, f32), q: (f32, f32)| -> f32 {
                let (p, q) = (
                    DVec2::new(p.0 as f64, p.1 as f64),
                    DVec2::new(q.0 as f64, q.1 as f64),
                );
                (p.x * q.y - p.y * q.x) as f32
            };
            u = edge((cx, cy), (bx, by));
            v = edge((ax, ay), (cx, cy));
            w = edge((bx, by), (ax, ay));
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        // Scaled hit distance T = det·t, compared before the division.
        let tt = u * (s.z * a[kz]) + v * (s.z * b[kz]) + w * (s.z * c[kz]);
        let (tt_abs, det_abs) = if det < 0.0 { (-tt, -det) } else { (tt, det) };
        if tt_abs <= 0.0 || tt_abs.is_nan() || tt_abs > tmax * det_abs {
            return None;
        }
        let inv_det = 1.0 / det;
        let t = tt * inv_det;
        (t > 0.0 && t < tmax).then(|| (t, Vec3::new(u, v, w) * inv_det))
    }
}

/// A vertex attribute is usable when it is finite and not the zero vector.
#[inline]
fn usable(v: Vec3) -> bool {
    v.is_finite() && v.length_squared() > 0.0
}

impl Triangle {
    /// Differential geometry at barycentrics `b`; vertex attributes come from triangle `tri`
    /// of `mesh` when given (its positions are this triangle's vertices).
    pub(crate) fn surface(&self, attrs: Option<(&Mesh, usize)>, b: Vec3) -> Surface {
        let [p0, p1, p2] = self.v;
        let p = p0 * b.x + p1 * b.y + p2 * b.z;
        let ng = (p1 - p0).cross(p2 - p0).normalize_or(Vec3::Z);
        let mut s = Surface {
            p,
            ng,
            ns: ng,
            uv: Vec2::new(b.y, b.z),
            dpdu: p1 - p0,
            dpdv: p2 - p0,
            tangent: None,
        };
        if let Some((mesh, tri)) = attrs {
            interpolate_attributes(&mut s, self.v, mesh, mesh.indices[tri].map(|i| i as usize), b);
        }
        s
    }
}

/// Fills the shading normal, uv, ∂p/∂u, ∂p/∂v and tangent of `s` from the vertex attributes
/// `idx` of `mesh` (whose positions are `v`).
fn interpolate_attributes(s: &mut Surface, v: [Vec3; 3], mesh: &Mesh, idx: [usize; 3], b: Vec3) {
    let lerp3 = |v: [Vec3; 3]| v[0] * b.x + v[1] * b.y + v[2] * b.z;
    if !mesh.normals.is_empty() {
        // Shading normal only when all three vertex normals are usable.
        let n = idx.map(|i| mesh.normals[i]);
        if n.iter().all(|&n| usable(n)) {
            s.ns = lerp3(n).normalize_or(s.ng);
        }
    }
    if !mesh.uvs.is_empty() {
        let uv = idx.map(|i| mesh.uvs[i]);
        s.uv = uv[0] * b.x + uv[1] * b.y + uv[2] * b.z;
        if let Some((dpdu, dpdv)) = scenes::triangle_uv_derivatives(v, uv) {
            (s.dpdu, s.dpdv) = (dpdu, dpdv);
        }
    }
    if !mesh.tangents.is_empty() {
        let t: [Vec4; 3] = idx.map(|i| mesh.tangents[i]);
        let t = t[0] * b.x + t[1] * b.y + t[2] * b.z;
        if usable(t.xyz()) {
            s.tangent = Some((t.xyz(), if t.w < 0.0 { -1.0 } else { 1.0 }));
        }
    }
}
