//! Shading frame at a hit: tangent, bitangent sign and tangent-space normal mapping.
//!
//! Tangent T: the authored tangent (glTF TANGENT) when present, else ∂p/∂u; made orthogonal
//! to the interpolated normal N by Gram–Schmidt (falling back to an arbitrary tangent of N,
//! Duff et al. 2017, when it is parallel or zero). Bitangent B = w·(N × T) (glTF 2.0, mesh attribute
//! `TANGENT`; MikkTSpace): w is the authored handedness, or otherwise chosen so that B points along
//! −∂p/∂v — towards the image's top row (texture v = 0 is the top row, and tangent-space +Y is
//! "up" in the image, glTF 2.0 `normalTexture`), which is what MikkTSpace tangents exported
//! for a glTF (v-flipped) uv layout give.
//!
//! Normal map (glTF 2.0 `material.normalTextureInfo`): texel c (linear), tangent-space
//! normal n_ts = (2c − 1) with n_ts.xy multiplied by `scale`, renormalised;
//! n = normalize(T·n_ts.x + B·n_ts.y + N·n_ts.z). T is then re-orthogonalised to n.
//!
//! | name | type | default | unit |
//! |---|---|---|---|
//! | `texture` | linear RGB texture index | — | — |
//! | `scale` | f32 | 1 | — |

use std::sync::Arc;

use glam::{Vec3, Vec4Swizzles};
use scenes::texture::Texture;

use super::Surface;
use crate::frame::Frame;

/// A shape's normal map, resolved to its texture.
#[derive(Clone, Debug)]
pub(crate) struct NormalMapTex {
    texture: Arc<Texture>,
    scale: f32,
}

impl NormalMapTex {
    /// Normal map reading `texture` with glTF's `scale`.
    pub(crate) fn new(texture: Arc<Texture>, scale: f32) -> Self {
        NormalMapTex { texture, scale }
    }

    /// Perturbed unit normal for the frame (T, B, N) at texture coordinate `uv`; N when the
    /// texel decodes to no direction.
    fn perturb(&self, uv: glam::Vec2, t: Vec3, b: Vec3, n: Vec3) -> Vec3 {
        let c = self.texture.sample(uv).xyz();
        let mut n_ts = c * 2.0 - Vec3::ONE;
        n_ts.x *= self.scale;
        n_ts.y *= self.scale;
        let Some(n_ts) = n_ts.try_normalize() else {
            return n;
        };
        (t * n_ts.x + b * n_ts.y + n * n_ts.z)
            .try_normalize()
            .unwrap_or(n)
    }
}

/// Unit `v` made orthogonal to unit `n` (Gram–Schmidt), or an arbitrary tangent of `n`.
#[inline]
fn orthogonal_tangent(v: Vec3, n: Vec3) -> Vec3 {
    (v - n * n.dot(v))
        .try_normalize()
        .unwrap_or_else(|| Frame::from_normal(n).s)
}

/// Shading normal and unit tangent (orthogonal to it) at `s`, with the normal map applied.
pub(crate) fn shading(s: &Surface, map: Option<&NormalMapTex>) -> (Vec3, Vec3) {
    let n = s.ns;
    let (t, sign) = match s.tangent {
        Some((t, w)) => (t, w),
        None => {
            let w = if n.cross(s.dpdu).dot(s.dpdv) > 0.0 {
                -1.0
            } else {
                1.0
            };
            (s.dpdu, w)
        }
    };
    let t = orthogonal_tangent(t, n);
    let Some(map) = map else {
        return (n, t);
    };
    let b = n.cross(t) * sign;
    let n_mapped = map.perturb(s.uv, t, b, n);
    (n_mapped, orthogonal_tangent(t, n_mapped))
}
