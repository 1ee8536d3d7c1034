//! `path`: unidirectional path tracing with next-event estimation and MIS, with Mitsuba 3's
//! `path` semantics so the two renderers compute the same quantity: `max_depth` = 1 shows
//! emitters seen directly, 2 adds direct illumination, −1 is unbounded; Russian roulette from
//! `rr_depth` on with survival q = min(max(β)·η², 0.95) (Mitsuba 3 `path` plugin docs;
//! Veach 1997 §10.4.1 for the estimator).
//!
//! [`irradiance`] runs the same walk from a given surface point whose BSDF is replaced by a
//! white Lambertian one: its outgoing radiance is then E/π, E the irradiance there with the
//! light that paths of the same `max_depth` bring (a light map's texel, [`crate::bake`]).

use glam::Vec3;
use scenes::{Material, Rgb, TexRgb};

use super::{emission_at, escaped, sample_light, shade, CameraSample, Context, FirstHit, Origin, Visibility};
use crate::bsdf::Bsdf;
use crate::frame::Frame;
use crate::geometry::{spawn_ray, Ray, SurfaceHit};
use crate::sampler::PixelSampler;

/// Where a path stands: the ray that reached `hit` (None: it left the scene), its throughput
/// and relative IOR, how it was generated, its bounces so far and rays traced.
struct Walk {
    ray: Ray,
    hit: Option<SurfaceHit>,
    throughput: Rgb,
    eta: f32,
    origin: Origin,
    depth: u32,
    rays: u32,
}

/// `max_depth` as a bound on the surface vertices (u32::MAX when unbounded).
fn depth_bound(ctx: &Context) -> u32 {
    if ctx.settings.max_depth < 0 {
        u32::MAX
    } else {
        ctx.settings.max_depth as u32
    }
}

/// Radiance along `ray`, path traced.
pub fn trace(ctx: &Context, ray: Ray, sampler: &mut PixelSampler) -> CameraSample {
    if depth_bound(ctx) == 0 {
        return CameraSample {
            radiance: Rgb::ZERO,
            first_hit: None,
            rays: 0,
        };
    }
    let hit = ctx.accel.intersect(&ray, f32::INFINITY);
    let start = Walk {
        ray,
        hit,
        throughput: Rgb::ONE,
        eta: 1.0,
        origin: Origin::Unsampleable,
        depth: 0,
        rays: 1,
    };
    let (radiance, first_hit, rays) = walk(ctx, start, sampler);
    CameraSample {
        radiance,
        first_hit,
        rays,
    }
}

/// Irradiance E at surface point `hit` on the side of its shading normal (turned to the
/// geometric normal's side, as [`shade`] turns it), from the light that paths of the
/// settings' `max_depth` bring to a camera-ray hit there: direct light at `max_depth` 2,
/// every bounce when unbounded, nothing below 2. E = π·L_o of a white Lambertian surface
/// (f = 1/π): one light sample MIS-combined with one cosine-sampled direction, the path
/// continued from there as [`trace`] continues it. The surface's own emission is not
/// irradiance and is left out. Returns E and the rays traced.
pub fn irradiance(ctx: &Context, hit: &SurfaceHit, sampler: &mut PixelSampler) -> (Rgb, u32) {
    if depth_bound(ctx) < 2 {
        return (Rgb::ZERO, 0);
    }
    let ns = if hit.ns.dot(hit.ng) < 0.0 { -hit.ns } else { hit.ns };
    let frame = Frame::from_normal_tangent(ns, hit.dpdu);
    let white = Material::Diffuse {
        albedo: TexRgb::Constant(Rgb::ONE),
    };
    let bsdf = Bsdf::from_material(&white, hit.uv, &[]);
    // Seen head-on: wo is the shading normal.
    let wo = Vec3::Z;
    let (direct, shadow_rays) = sample_light(ctx, hit, &frame, &bsdf, wo, sampler, Visibility::Traced);
    let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
    // The roulette dimension the camera path's first bounce draws, kept for the same layout.
    let _ = sampler.next_1d();
    let mut radiance = direct;
    let mut rays = shadow_rays;
    if let Some(s) = bsdf.sample(wo, u_lobe, u) {
        let ray = spawn_ray(hit.p, hit.ng, frame.to_world(s.wi));
        let next = Walk {
            hit: ctx.accel.intersect(&ray, f32::INFINITY),
            ray,
            throughput: s.weight,
            eta: 1.0,
            origin: Origin::Bsdf { p: hit.p, pdf: s.pdf },
            depth: 1,
            rays: 1,
        };
        let (rest, _, more) = walk(ctx, next, sampler);
        radiance += rest;
        rays += more;
    }
    (radiance * std::f32::consts::PI, rays)
}

/// The path from where `w` stands to its end: the radiance it gathers, the first surface
/// (when it starts at depth 0) and the rays traced.
fn walk(ctx: &Context, mut w: Walk, sampler: &mut PixelSampler) -> (Rgb, Option<FirstHit>, u32) {
    let max_depth = depth_bound(ctx);
    let mut radiance = Rgb::ZERO;
    let mut first_hit = None;
    loop {
        let Some(h) = w.hit else {
            radiance += w.throughput * escaped(ctx, &w.ray, w.origin);
            break;
        };
        radiance += w.throughput * emission_at(ctx, &w.ray, &h, w.origin);
        let (frame, bsdf) = shade(ctx, &h, sampler);
        if w.depth == 0 {
            first_hit = Some(FirstHit {
                hit: h,
                albedo: bsdf.albedo(),
            });
        }
        if w.depth + 1 >= max_depth {
            break;
        }
        let wo = frame.to_local(-w.ray.dir);
        // Next-event estimation.
        let (direct, shadow_rays) = sample_light(ctx, &h, &frame, &bsdf, wo, sampler, Visibility::Traced);
        radiance += w.throughput * direct;
        w.rays += shadow_rays;
        // Continue the path by sampling the BSDF.
        let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
        let u_rr = sampler.next_1d();
        let Some(s) = bsdf.sample(wo, u_lobe, u) else {
            break;
        };
        w.throughput *= s.weight;
        w.eta *= s.eta;
        let wi = frame.to_world(s.wi);
        w.origin = if s.delta {
            Origin::Unsampleable
        } else {
            Origin::Bsdf { p: h.p, pdf: s.pdf }
        };
        w.ray = spawn_ray(h.p, h.ng, wi);
        w.hit = ctx.accel.intersect(&w.ray, f32::INFINITY);
        w.rays += 1;
        w.depth += 1;
        // Russian roulette (unbiased: survivors are reweighted by 1/q).
        let max_t = w.throughput.max_element();
        if w.depth >= ctx.settings.rr_depth {
            let q = (max_t * w.eta * w.eta).min(0.95);
            if u_rr >= q {
                break;
            }
            w.throughput /= q;
        }
        if max_t == 0.0 || !max_t.is_finite() {
            break;
        }
    }
    (radiance, first_hit, w.rays)
}
