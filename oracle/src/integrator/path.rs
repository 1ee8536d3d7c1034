//! `path`: unidirectional path tracing with next-event estimation and MIS, with Mitsuba 3's
//! `path` semantics so the two renderers compute the same quantity: `max_depth` = 1 shows
//! emitters seen directly, 2 adds direct illumination, −1 is unbounded; Russian roulette from
//! `rr_depth` on with survival q = min(max(β)·η², 0.95) (Mitsuba 3 `path` plugin docs;
//! Veach 1997 §10.4.1 for the estimator).

use scenes::Rgb;

use super::{emission_at, escaped, sample_light, shade, CameraSample, Context, FirstHit, Origin, Visibility};
use crate::geometry::{spawn_ray, Ray};
use crate::sampler::PixelSampler;

/// Radiance along `ray`, path traced.
pub fn trace(ctx: &Context, mut ray: Ray, sampler: &mut PixelSampler) -> CameraSample {
    let max_depth = if ctx.settings.max_depth < 0 {
        u32::MAX
    } else {
        ctx.settings.max_depth as u32
    };
    let mut radiance = Rgb::ZERO;
    let mut throughput = Rgb::ONE;
    let mut eta = 1.0f32;
    let mut origin = Origin::Unsampleable;
    let mut first_hit = None;
    let mut rays = 1;
    let mut hit = ctx.accel.intersect(&ray, f32::INFINITY);
    let mut depth = 0u32;
    if max_depth == 0 {
        return CameraSample {
            radiance,
            first_hit,
            rays: 0,
        };
    }
    loop {
        let Some(h) = hit else {
            radiance += throughput * escaped(ctx, &ray, origin);
            break;
        };
        radiance += throughput * emission_at(ctx, &ray, &h, origin);
        let (frame, bsdf) = shade(ctx, &h);
        if depth == 0 {
            first_hit = Some(FirstHit {
                hit: h,
                albedo: bsdf.albedo(),
            });
        }
        if depth + 1 >= max_depth {
            break;
        }
        let wo = frame.to_local(-ray.dir);
        // Next-event estimation.
        let (direct, shadow_rays) = sample_light(ctx, &h, &frame, &bsdf, wo, sampler, Visibility::Traced);
        radiance += throughput * direct;
        rays += shadow_rays;
        // Continue the path by sampling the BSDF.
        let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
        let u_rr = sampler.next_1d();
        let Some(s) = bsdf.sample(wo, u_lobe, u) else {
            break;
        };
        throughput *= s.weight;
        eta *= s.eta;
        let wi = frame.to_world(s.wi);
        origin = if s.delta {
            Origin::Unsampleable
        } else {
            Origin::Bsdf { p: h.p, pdf: s.pdf }
        };
        ray = spawn_ray(h.p, h.ng, wi);
        hit = ctx.accel.intersect(&ray, f32::INFINITY);
        rays += 1;
        depth += 1;
        // Russian roulette (unbiased: survivors are reweighted by 1/q).
        let max_t = throughput.max_element();
        if depth >= ctx.settings.rr_depth {
            let q = (max_t * eta * eta).min(0.95);
            if u_rr >= q {
                break;
            }
            throughput /= q;
        }
        if max_t == 0.0 || !max_t.is_finite() {
            break;
        }
    }
    CameraSample {
        radiance,
        first_hit,
        rays,
    }
}
