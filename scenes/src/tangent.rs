//! Per-vertex tangent frames for meshes that have none (glTF assets without TANGENT).
//!
//! Method: Lengyel 2001, "Computing Tangent Space Basis Vectors for an Arbitrary Mesh"
//! (Terathon), the per-triangle basis of Mikkelsen 2008, "Simulation of Wrinkled Surfaces
//! Revisited" (MSc thesis, Copenhagen), §3. Per triangle, T = ∂p/∂s and B = ∂p/∂t solve
//! e₁ = Δs₁·T + Δt₁·B, e₂ = Δs₂·T + Δt₂·B for its edges and texture deltas
//! ([`crate::triangle_uv_derivatives`], pbrt-v4 §6.5.3). T and B are summed over the
//! triangles sharing a vertex, then T is Gram–Schmidt orthogonalised against the vertex
//! normal n: t = normalize(T − n·(n·T)), and the handedness is w = sign((n × t)·B), so that
//! the bitangent is b = w·(n × t).
//!
//! glTF orientation (glTF 2.0 "Meshes", TANGENT, and `normalTexture`): the texture's green
//! axis points "up" in the image and glTF's v runs downwards (v = 0 is the top row), so the
//! bitangent a normal map means is −∂p/∂v: (s, t) = (u, −v), T = ∂p/∂u, B = −∂p/∂v. Then
//! b = w·(n × t) matches the MikkTSpace convention of glTF's TANGENT, which the glTF loader
//! uses as is when an asset has it.

use glam::{Vec2, Vec3, Vec4};

/// Unit tangent with handedness (xyz, w = ±1) for every vertex. Needs one normal and one uv
/// per position (returns an empty list otherwise); triangles with out-of-range indices or a
/// degenerate uv mapping contribute nothing, and a vertex without information gets an
/// arbitrary tangent of its normal with w = +1.
pub fn generate(positions: &[Vec3], normals: &[Vec3], uvs: &[Vec2], triangles: &[[u32; 3]]) -> Vec<Vec4> {
    let n = positions.len();
    if normals.len() != n || uvs.len() != n {
        return Vec::new();
    }
    let mut tan = vec![Vec3::ZERO; n];
    let mut bitan = vec![Vec3::ZERO; n];
    for tri in triangles {
        if tri.iter().any(|&i| i as usize >= n) {
            continue;
        }
        let idx = tri.map(|i| i as usize);
        let Some((dpdu, dpdv)) =
            crate::triangle_uv_derivatives(idx.map(|i| positions[i]), idx.map(|i| uvs[i]))
        else {
            continue; // degenerate uv mapping: no information about T, B
        };
        for v in idx {
            tan[v] += dpdu;
            bitan[v] -= dpdv; // B = −∂p/∂v (module header)
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
pub fn orthogonalize(n: Vec3, t: Vec3) -> Vec3 {
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
