//! `ao`: ambient occlusion with a radius, the ground truth for SSAO (docs/ARCHITECTURE.md).
//!
//! AO(x) = (1/π) ∫ V_r(x, ω) cosθ dω over the hemisphere of the shading normal turned
//! towards the viewer, V_r = 1 when nothing lies within distance r along ω (Zhukov, Iones,
//! Kronin 1998, "An ambient light illumination model", with a hard cut-off at r). Estimated
//! with cosine-weighted directions, so each sample is 0 or 1. Directions below the geometric
//! surface count as occluded. Pixels that see no surface are 0. Written to R = G = B.

use scenes::Rgb;

use super::{shade, CameraSample, Context, FirstHit};
use crate::geometry::{spawn_ray, Ray};
use crate::sampler::PixelSampler;
use crate::sampling::square_to_cosine_hemisphere;

/// Ambient occlusion at the surface seen along `ray`.
pub fn trace(ctx: &Context, ray: Ray, sampler: &mut PixelSampler) -> CameraSample {
    let Some(h) = ctx.accel.intersect(&ray, f32::INFINITY) else {
        return CameraSample {
            radiance: Rgb::ZERO,
            first_hit: None,
            rays: 1,
        };
    };
    let (frame, bsdf) = shade(ctx, &h, sampler);
    let first_hit = Some(FirstHit {
        hit: h,
        albedo: bsdf.albedo(),
    });
    let facing = if frame.n.dot(ray.dir) > 0.0 { -1.0 } else { 1.0 };
    let mut local = square_to_cosine_hemisphere(sampler.next_2d());
    local.z *= facing;
    let dir = frame.to_world(local);
    let below = dir.dot(h.ng) * ray.dir.dot(h.ng) > 0.0;
    if below {
        return CameraSample {
            radiance: Rgb::ZERO,
            first_hit,
            rays: 1,
        };
    }
    let open = !ctx
        .accel
        .occluded(&spawn_ray(h.p, h.ng, dir), ctx.settings.ao_radius);
    CameraSample {
        radiance: Rgb::splat(if open { 1.0 } else { 0.0 }),
        first_hit,
        rays: 2,
    }
}
