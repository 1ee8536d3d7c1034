//! Horizon maps (Max 1988, "Horizon Mapping: Shadows for Bump-Mapped Surfaces", The Visual
//! Computer 4(2); on graphics hardware Sloan & Cohen 2000, "Interactive Horizon Mapping",
//! EGWR): for every texel of a heightfield patch and D azimuths φ_k = 2πk/D in its tangent
//! plane, the tangent of the horizon's elevation, tan β_k = max_t (w(p + t·d_k) − w(p))/t over
//! the points a distance t away along d_k (never below 0: a flat horizon). A light at
//! elevation e above the base plane in azimuth φ is visible where tan e > tan β(φ), β
//! interpolated linearly between the two nearest azimuths (detail/horizon.wgsl) — the
//! self-shadowing normal and bump mapping lack, at the cost of D/4 RGBA lookups.
//!
//! Precomputed at height multiplier 1 (w = s·h): the horizon tangents scale with the method's
//! `height_scale` k exactly (every Δw does), so the shader multiplies by k. The map is
//! [`HORIZON_RESOLUTION`]² at most (the heights sampled bilinearly at its texel centres), the
//! search [`HORIZON_STEPS`] samples out to [`HORIZON_REACH`] of the patch's shorter side; a
//! patch ends at its border (nothing beyond casts a shadow), as the displaced surface the
//! oracle traces does.
//!
//! Failure modes: D azimuths interpolate the horizon linearly between them, so a narrow ridge
//! between two azimuths is missed; blockers farther than the reach are not seen; the map is
//! of the base point (normal and bump mapping do not move it), so what it shadows is where
//! the flat base is, not where the displaced surface would appear.

use glam::{Vec2, Vec4};
use rayon::prelude::*;
use scenes::texture::Texture;

/// Largest horizon-map side in texels (chosen here: horizons vary slower than heights).
pub const HORIZON_RESOLUTION: u32 = 256;
/// Samples along each azimuth (chosen here).
pub const HORIZON_STEPS: u32 = 64;
/// How far the search reaches, as a fraction of the patch's shorter side (chosen here: a
/// 4 m patch is searched 1 m out, a shadow 0.12 m high blockers cast under a 7° sun).
pub const HORIZON_REACH: f32 = 0.25;
/// Most azimuths (`horizon`).
pub const MAX_HORIZON_DIRECTIONS: u32 = 16;

/// The horizon maps of channel `channel` of `height` at `scale` metres per unit h, on a patch
/// `size` metres across (u, v), for `directions` azimuths: ⌈D/4⌉ RGBA textures, azimuth k in
/// texture k / 4, channel k % 4, holding tan β_k. Azimuth φ points along the patch's +u axis at
/// 0 and +v at 90°.
pub fn horizon_maps(
    height: &Texture,
    channel: usize,
    scale: f32,
    size: Vec2,
    directions: u32,
) -> Vec<Texture> {
    let (w, h) = (
        height.width.min(HORIZON_RESOLUTION),
        height.height.min(HORIZON_RESOLUTION),
    );
    let d = directions.clamp(1, MAX_HORIZON_DIRECTIONS) as usize;
    let reach = HORIZON_REACH * size.min_element();
    let dt = reach / HORIZON_STEPS as f32;
    let height_at = |uv: Vec2| height.sample(uv)[channel] * scale;
    let azimuths: Vec<Vec2> = (0..d)
        .map(|k| {
            let phi = std::f32::consts::TAU * k as f32 / d as f32;
            // uv per metre along the azimuth.
            Vec2::new(phi.cos() / size.x, phi.sin() / size.y)
        })
        .collect();
    let rows: Vec<Vec<f32>> = (0..h)
        .into_par_iter()
        .map(|j| {
            let mut row = Vec::with_capacity((w as usize) * d);
            for i in 0..w {
                let uv = Vec2::new((i as f32 + 0.5) / w as f32, (j as f32 + 0.5) / h as f32);
                let w0 = height_at(uv);
                for dir in &azimuths {
                    let mut best = 0.0f32;
                    for s in 1..=HORIZON_STEPS {
                        let t = s as f32 * dt;
                        let q = uv + *dir * t;
                        if !(q.cmpge(Vec2::ZERO).all() && q.cmple(Vec2::ONE).all()) {
                            break;
                        }
                        best = best.max((height_at(q) - w0) / t);
                    }
                    row.push(best);
                }
            }
            row
        })
        .collect();
    (0..d.div_ceil(4))
        .map(|m| {
            let texels = rows
                .iter()
                .flat_map(|row| row.chunks(d))
                .map(|tans| {
                    let at = |c: usize| tans.get(4 * m + c).copied().unwrap_or(0.0);
                    Vec4::new(at(0), at(1), at(2), at(3))
                })
                .collect();
            Texture::from_texels(w, h, texels, [scenes::WrapMode::Clamp; 2])
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A single step of height 1 (scale 0.1 m) across the middle of a 1 m patch: looking
    /// towards it from 0.2 m away the horizon rises to 0.1/0.2 (the step's near edge sampled
    /// on the search grid), looking away it is flat; on top of the step both are flat.
    #[test]
    fn a_step_raises_the_horizon_towards_it_only() {
        let n = 64u32;
        let texels = (0..n * n)
            .map(|k| Vec4::splat(if k % n >= n / 2 { 1.0 } else { 0.0 }))
            .collect();
        let step = Texture::from_texels(n, n, texels, [scenes::WrapMode::Clamp; 2]);
        let maps = horizon_maps(&step, 0, 0.1, Vec2::ONE, 4);
        assert_eq!(maps.len(), 1);
        let m = &maps[0];
        // Texel at u ≈ 0.3 (0.2 m before the step at u = 0.5): +u sees the step.
        let low = m.texel(19, 32);
        assert!(low.x > 0.35 && low.x <= 0.55, "towards the step: {}", low.x);
        assert_eq!((low.y, low.z, low.w), (0.0, 0.0, 0.0), "{low}");
        let high = m.texel(50, 32);
        assert_eq!(high, Vec4::ZERO, "on top of the step");
    }
}
