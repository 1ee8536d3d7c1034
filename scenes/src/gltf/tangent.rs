//! Per-vertex tangent frames for normal mapping when an asset has none.
//!
//! Method: Lengyel 2001, "Computing Tangent Space Basis Vectors for an Arbitrary Mesh"
//! (Terathon). For a triangle with edges e₁ = p₁ − p₀, e₂ = p₂ − p₀ and texture-coordinate
//! deltas (s₁, t₁), (s₂, t₂), solve e₁ = s₁·T + t₁·B, e₂ = s₂·T + t₂·B:
//!
//!   r = 1 / (s₁t₂ − s₂t₁),  T = r·(t₂·e₁ − t₁·e₂),  B = r·(s₁·e₂ − s₂·e₁).
//!
//! T and B are summed over the triangles sharing a vertex, then T is Gram–Schmidt
//! orthogonalised against the vertex normal n: t = normalize(T − n·(n·T)), and the
//! handedness is w = sign((n × t)·B).
//!
//! glTF orientation (glTF 2.0 "Additional Textures", normalTexture): the texture's green axis points "up"
//! in the image, and glTF's v runs downwards (v = 0 is the top row), so the bitangent the
//! normal map means is −∂p/∂v. We therefore use t = −v in the equations above, so that
//! bitangent = (n × t)·w matches the MikkTSpace convention glTF's TANGENT uses.

use glam::{Vec2, Vec3, Vec4};

/// Unit tangent with handedness (xyz, w = ±1) for every vertex.
pub(super) fn generate(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    triangles: &[[u32; 3]],
) -> Vec<Vec4> {
    let mut tan = vec![Vec3::ZERO; positions.len()];
    let mut bitan = vec![Vec3::ZERO; positions.len()];
    for tri in triangles {
        let [a, b, c] = tri.map(|i| i as usize);
        let e1 = positions[b] - positions[a];
        let e2 = positions[c] - positions[a];
        // Texture deltas with t = −v (see the module header).
        let d1 = (uvs[b] - uvs[a]) * Vec2::new(1.0, -1.0);
        let d2 = (uvs[c] - uvs[a]) * Vec2::new(1.0, -1.0);
        let det = d1.x * d2.y - d2.x * d1.y;
        if det.abs() < 1e-20 || !det.is_finite() {
            continue; // degenerate uv mapping: no information about T, B
        }
        let r = 1.0 / det;
        let t = (e1 * d2.y - e2 * d1.y) * r;
        let bt = (e2 * d1.x - e1 * d2.x) * r;
        for v in [a, b, c] {
            tan[v] += t;
            bitan[v] += bt;
        }
    }
    normals
        .iter()
        .zip(tan.iter().zip(&bitan))
        .map(|(&n, (&t, &bt))| frame(n, t, bt))
        .collect()
}

/// Gram–Schmidt orthogonalises `t` against `n` and derives the handedness from `bt`.
fn frame(n: Vec3, t: Vec3, bt: Vec3) -> Vec4 {
    let t = orthogonalize(n, t);
    let w = if n.cross(t).dot(bt) < 0.0 { -1.0 } else { 1.0 };
    t.extend(w)
}

/// normalize(t − n·(n·t)) for unit `n`; an arbitrary unit vector perpendicular to `n` when
/// `t` is absent or (numerically) parallel to `n`.
pub(super) fn orthogonalize(n: Vec3, t: Vec3) -> Vec3 {
    let ortho = t - n * n.dot(t);
    let len2 = ortho.length_squared();
    if len2.is_finite() && len2 > 0.0 && len2 > 1e-12 * t.length_squared() {
        ortho / len2.sqrt()
    } else {
        perpendicular(n)
    }
}

/// A unit vector perpendicular to unit `n` (Duff et al. 2017, "Building an Orthonormal Basis,
/// Revisited", JCGT 6(1), Listing 3: the first basis vector).
fn perpendicular(n: Vec3) -> Vec3 {
    let sign = 1.0_f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x)
}
