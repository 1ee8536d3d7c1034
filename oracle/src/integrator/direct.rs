//! `direct`: emission + one bounce of direct light + perfect-specular chains (docs/ARCHITECTURE.md).
//!
//! From the camera, rays follow mirror and dielectric bounces (up to `max_depth` surfaces,
//! 64 when unbounded); at the first non-delta surface the direct light is estimated by one
//! light sample and one BSDF sample combined with MIS (Veach 1997 §9.2), and the path ends.
//! Light reaching that surface through other surfaces (indirect light, caustics) is excluded.
//!
//! `direct_unshadowed` is the same with visibility ignored: one light sample per surface, no
//! shadow ray, no BSDF sample (see [`Visibility::Ignored`]).

use scenes::Rgb;

use super::{emission_at, escaped, sample_light, shade, CameraSample, Context, FirstHit, Origin, Visibility};
use crate::geometry::{spawn_ray, Ray};
use crate::sampler::PixelSampler;

/// Longest perfect-specular chain followed when `max_depth` is −1.
const MAX_SPECULAR_CHAIN: u32 = 64;

/// Radiance along `ray`: directly visible and direct light, through specular chains.
pub fn trace(
    ctx: &Context,
    mut ray: Ray,
    sampler: &mut PixelSampler,
    visibility: Visibility,
) -> CameraSample {
    let max_surfaces = if ctx.settings.max_depth < 0 {
        MAX_SPECULAR_CHAIN
    } else {
        ctx.settings.max_depth as u32
    };
    let mut radiance = Rgb::ZERO;
    let mut throughput = Rgb::ONE;
    let mut first_hit = None;
    let mut rays = 1;
    for depth in 0..max_surfaces {
        let Some(h) = ctx.accel.intersect(&ray, f32::INFINITY) else {
            radiance += throughput * escaped(ctx, &ray, Origin::Unsampleable);
            break;
        };
        radiance += throughput * emission_at(ctx, &ray, &h, Origin::Unsampleable);
        let (frame, bsdf) = shade(ctx, &h, sampler);
        if depth == 0 {
            first_hit = Some(FirstHit {
                hit: h,
                albedo: bsdf.albedo(),
            });
        }
        if depth + 1 >= max_surfaces {
            break;
        }
        let wo = frame.to_local(-ray.dir);
        let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
        if bsdf.is_delta() {
            let Some(s) = bsdf.sample(wo, u_lobe, u) else {
                break;
            };
            throughput *= s.weight;
            ray = spawn_ray(h.p, h.ng, frame.to_world(s.wi));
            rays += 1;
            continue;
        }
        // Direct light at the first non-delta surface: light sample + BSDF sample, MIS.
        let (direct, shadow_rays) = sample_light(ctx, &h, &frame, &bsdf, wo, sampler, visibility);
        radiance += throughput * direct;
        rays += shadow_rays;
        if visibility == Visibility::Ignored {
            break;
        }
        if let Some(s) = bsdf.sample(wo, u_lobe, u) {
            let next = spawn_ray(h.p, h.ng, frame.to_world(s.wi));
            let origin = Origin::Bsdf { p: h.p, pdf: s.pdf };
            rays += 1;
            let found = match ctx.accel.intersect(&next, f32::INFINITY) {
                Some(h2) => emission_at(ctx, &next, &h2, origin),
                None => escaped(ctx, &next, origin),
            };
            radiance += throughput * s.weight * found;
        }
        break;
    }
    CameraSample {
        radiance,
        first_hit,
        rays,
    }
}
