//! Light-transport integrators (docs/ARCHITECTURE.md "Ground truth is defined per effect"): `path`,
//! `direct` and `ao`, plus the pieces they share — shading setup at a hit, light sampling
//! and BSDF sampling combined by multiple importance sampling (Veach & Guibas 1995,
//! "Optimally Combining Sampling Techniques for Monte Carlo Rendering", power heuristic).

mod ao;
mod direct;
mod path;

pub use path::irradiance as path_irradiance;

use glam::{Vec2, Vec3};
use scenes::{IntegratorKind, RenderSettings, Rgb, Scene};

use crate::bsdf::{Bsdf, WalkSeed};
use crate::frame::Frame;
use crate::geometry::{spawn_ray, spawn_ray_to, Accel, Ray, SurfaceHit};
use crate::light::LightSet;
use crate::sampler::PixelSampler;
use crate::sampling::power_heuristic;

/// What every integrator reads.
pub struct Context<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// Its ray-tracing acceleration structure.
    pub accel: &'a Accel,
    /// Its emitters.
    pub lights: &'a LightSet,
    /// Integrator settings.
    pub settings: RenderSettings,
}

/// Surface data at the first hit of a camera ray, for the AOVs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirstHit {
    /// The hit itself.
    pub hit: SurfaceHit,
    /// The BSDF's albedo there.
    pub albedo: Rgb,
}

/// One camera sample's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSample {
    /// Radiance along the camera ray.
    pub radiance: Rgb,
    /// First surface hit, if any.
    pub first_hit: Option<FirstHit>,
    /// Rays traced (camera, bounce, shadow).
    pub rays: u32,
}

/// Estimates the radiance arriving along the camera ray `ray` with the configured integrator.
pub fn trace(ctx: &Context, ray: Ray, sampler: &mut PixelSampler) -> CameraSample {
    match ctx.settings.integrator {
        IntegratorKind::Path => path::trace(ctx, ray, sampler),
        IntegratorKind::Direct => direct::trace(ctx, ray, sampler, Visibility::Traced),
        IntegratorKind::DirectUnshadowed => direct::trace(ctx, ray, sampler, Visibility::Ignored),
        IntegratorKind::Ao => ao::trace(ctx, ray, sampler),
    }
}

/// The shading frame and BSDF at a hit. The frame's normal is the shading normal turned to
/// the geometric normal's side, so local z > 0 is the shape's front (a dielectric's outside).
/// A stochastic BSDF (multiple scattering) gets this vertex's own walk seed, one sampler
/// dimension; deterministic BSDFs draw none, so their scenes' sample layout is unchanged.
pub(crate) fn shade(ctx: &Context, hit: &SurfaceHit, sampler: &mut PixelSampler) -> (Frame, Bsdf) {
    let ns = if hit.ns.dot(hit.ng) < 0.0 { -hit.ns } else { hit.ns };
    let frame = Frame::from_normal_tangent(ns, hit.dpdu);
    let material = &ctx.scene.materials[ctx.scene.shapes[hit.shape as usize].material];
    let bsdf = Bsdf::from_material(material, hit.uv, &ctx.scene.textures);
    match bsdf.walk_seed() {
        Some(_) => (frame, bsdf.with_walk_seed(WalkSeed(sampler.next_seed()))),
        None => (frame, bsdf),
    }
}

/// How the ray that found an emitter was generated, for its MIS weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Origin {
    /// A camera ray or a perfect-specular bounce: light sampling could not have found this
    /// emission, so it counts fully.
    Unsampleable,
    /// A BSDF-sampled ray from point `p` with solid-angle pdf `pdf`.
    Bsdf {
        /// Where the ray started.
        p: Vec3,
        /// Its BSDF pdf.
        pdf: f32,
    },
}

impl Origin {
    /// MIS weight of an emission found by this ray when light sampling would have drawn the
    /// same direction with total pdf `light_pdf` (selection × solid angle).
    fn weight(self, light_pdf: f32) -> f32 {
        match self {
            Origin::Unsampleable => 1.0,
            Origin::Bsdf { pdf, .. } => power_heuristic(pdf, light_pdf),
        }
    }
}

/// Radiance emitted towards the ray by the surface it hit (area lights), MIS-weighted.
pub(crate) fn emission_at(ctx: &Context, ray: &Ray, hit: &SurfaceHit, origin: Origin) -> Rgb {
    let Some(e) = ctx.lights.emitter_of_shape(hit.shape as usize) else {
        return Rgb::ZERO;
    };
    let emitter = &ctx.lights.emitters()[e];
    let le = emitter.emitted(hit.ng, hit.uv, -ray.dir);
    if le == Rgb::ZERO {
        return le;
    }
    let light_pdf = match origin {
        Origin::Unsampleable => 0.0,
        Origin::Bsdf { p, .. } => ctx.lights.selection_pmf(e, p) * emitter.pdf_li(p, ray.dir, hit.p, hit.ng),
    };
    le * origin.weight(light_pdf)
}

/// Radiance arriving along a ray that left the scene (environment and sun disks),
/// MIS-weighted.
pub(crate) fn escaped(ctx: &Context, ray: &Ray, origin: Origin) -> Rgb {
    let mut total = Rgb::ZERO;
    for &i in ctx.lights.distant() {
        let emitter = &ctx.lights.emitters()[i];
        total += match origin {
            Origin::Unsampleable => emitter.radiance_from_direction(ray.dir),
            Origin::Bsdf { p, .. } => {
                let (l, pdf) = emitter.radiance_and_pdf_from_direction(ray.dir);
                if l == Rgb::ZERO {
                    continue;
                }
                l * origin.weight(ctx.lights.selection_pmf(i, p) * pdf)
            }
        };
    }
    total
}

/// Whether light samples are tested for occlusion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Visibility {
    /// Shadow rays; light and BSDF samples combined by MIS.
    Traced,
    /// Every light unoccluded: light sampling alone (every emitter's sampling covers all of
    /// it, so the estimate is unbiased without MIS), no shadow rays.
    Ignored,
}

/// Next-event estimation: one light sample (selection: [`crate::light::selection`]) with a shadow ray,
/// MIS-weighted against BSDF sampling (or, with [`Visibility::Ignored`], neither). Always
/// consumes 3 sampler dimensions. Returns the contribution and the number of rays traced.
pub(crate) fn sample_light(
    ctx: &Context,
    hit: &SurfaceHit,
    frame: &Frame,
    bsdf: &Bsdf,
    wo: Vec3,
    sampler: &mut PixelSampler,
    visibility: Visibility,
) -> (Rgb, u32) {
    let u_select = sampler.next_1d();
    let u = sampler.next_2d();
    if bsdf.is_delta() {
        return (Rgb::ZERO, 0);
    }
    let Some((index, ls)) = ctx.lights.sample(hit.p, u_select, u) else {
        return (Rgb::ZERO, 0);
    };
    // A convex emitter does not light its own surface (its contribution there is exactly 0;
    // sampling it from a point on its own plane is degenerate and returned noise).
    if ctx.lights.is_own_convex_emitter(hit.shape as usize, index) {
        return (Rgb::ZERO, 0);
    }
    if ls.pdf.is_nan() || ls.pdf <= 0.0 || ls.li == Rgb::ZERO {
        return (Rgb::ZERO, 0);
    }
    let wi = frame.to_local(ls.wi);
    let f = bsdf.eval(wo, wi);
    if f == Rgb::ZERO {
        return (Rgb::ZERO, 0);
    }
    if visibility == Visibility::Ignored {
        return (f * ls.li / ls.pdf, 0);
    }
    let (shadow, tmax) = shadow_ray(hit, ls.wi, ls.dist);
    if ctx.accel.occluded(&shadow, tmax) {
        return (Rgb::ZERO, 1);
    }
    let weight = if ls.delta {
        1.0
    } else {
        power_heuristic(ls.pdf, bsdf.pdf(wo, wi))
    };
    (f * ls.li * (weight / ls.pdf), 1)
}

/// Shadow ray from a hit towards a light sample at distance `dist` (∞ for distant lights).
pub(crate) fn shadow_ray(hit: &SurfaceHit, dir: Vec3, dist: f32) -> (Ray, f32) {
    if dist.is_finite() {
        spawn_ray_to(hit.p, hit.ng, hit.p + dir * dist, None)
    } else {
        (spawn_ray(hit.p, hit.ng, dir), f32::INFINITY)
    }
}

/// Fraction of each named light visible from the hit, one light sample and shadow ray per
/// light per call. Averaged over a pixel's samples this is the visible fraction of the light
/// as its sampling measures it: of its solid angle for rectangles, spheres seen from outside
/// and sun disks (sampled uniformly in solid angle); of its area, weighted by the
/// area-to-solid-angle factor, for disks, meshes and sheared parallelograms; 0 or 1 for delta
/// lights.
pub fn light_visibility(ctx: &Context, hit: &SurfaceHit, sampler: &mut PixelSampler, out: &mut [f32]) -> u32 {
    let mut rays = 0;
    for (k, v) in out.iter_mut().enumerate() {
        let u: Vec2 = sampler.next_2d();
        *v = 0.0;
        if let Some(ls) = ctx.lights.emitters()[k].sample_li(hit.p, u) {
            if ls.pdf > 0.0 {
                let (ray, tmax) = shadow_ray(hit, ls.wi, ls.dist);
                rays += 1;
                if !ctx.accel.occluded(&ray, tmax) {
                    *v = 1.0;
                }
            }
        }
    }
    rays
}
