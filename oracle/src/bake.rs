//! Light-map baking: the irradiance at every texel centre of every static planar shape's
//! chart ([`scenes::lightmap`]), path traced with the transport of a camera path of the same
//! `max_depth` ([`crate::integrator::path::irradiance`]: E = π·L_o of a white Lambertian
//! surface, light sampling MIS-combined with cosine sampling, the path continued as the
//! `path` integrator continues it). The shapes listed as dynamic are left out of the scene
//! the map is baked in — they neither receive a chart nor cast shadows or bounce light into
//! it, as a dynamic object in an engine is not in its bake.
//!
//! Each texel's estimate is the mean of `spp` samples (its own sampler stream, keyed by the
//! atlas texel and the seed), dealt to independent replicates as a pixel's are, with the
//! variance of that mean from the spread of the replicate means (crate::sampler, "Independent
//! replicates"; crate::film::replicate_estimate); the uncovered texels (padding, outside a disk) are then filled by dilation.

use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;
use scenes::lightmap::{self, LightMap};
use scenes::{IntegratorKind, RenderSettings, Scene};

use crate::film::{replicate_estimate, REPLICATE_SUMS};
use crate::geometry::{Accel, SurfaceHit};
use crate::integrator::{path_irradiance, Context};
use crate::light::LightSet;
use crate::sampler::{replicate_of, PixelSampler};

/// What a bake computes.
#[derive(Clone, Debug, PartialEq)]
pub struct BakeSettings {
    /// Texels along each chart's longer side (1..=[`lightmap::MAX_RESOLUTION`]).
    pub resolution: u32,
    /// Texels of padding around each chart in the atlas.
    pub padding: u32,
    /// Dilation rings (at least the padding, so a chart's border is read back alone).
    pub dilation: u32,
    /// Samples per texel.
    pub spp: u32,
    /// Path depth, Mitsuba semantics (2: direct light only; −1: unbounded).
    pub max_depth: i32,
    /// Sampler seed.
    pub seed: u64,
    /// Shapes left out of the bake (lit per pixel by the realtime renderer).
    pub dynamic: Vec<String>,
    /// Where in each texel the irradiance is taken, in texels from its centre (0: the centre
    /// a bilinear lookup reads back; ½: the classic half-texel mistake, kept as a variant).
    pub texel_offset: f32,
}

/// A baked light map with its cost and noise.
#[derive(Clone, Debug)]
pub struct Baked {
    /// The map.
    pub map: LightMap,
    /// Wall time of the bake, seconds (acceleration structure included).
    pub seconds: f64,
    /// Rays traced.
    pub rays: u64,
    /// Mean over the covered texels of the relative standard error √var/E (channel mean;
    /// texels with E = 0 left out).
    pub mean_relative_std_error: f64,
}

impl Baked {
    /// The atlas EXR ([`LightMap::to_image`]) with the bake's settings, cost and noise in its
    /// header: `verity.lightmap.spp`, `.max_depth`, `.texel_offset`, `.seconds`, `.rays`,
    /// `.mean_relative_std_error`.
    pub fn to_image(&self, s: &BakeSettings) -> scenes::layered::LayeredImage {
        let mut image = self.map.to_image();
        for (key, value) in [
            ("spp", s.spp.to_string()),
            ("max_depth", s.max_depth.to_string()),
            ("texel_offset", s.texel_offset.to_string()),
            ("seconds", format!("{:.3}", self.seconds)),
            ("rays", self.rays.to_string()),
            (
                "mean_relative_std_error",
                self.mean_relative_std_error.to_string(),
            ),
        ] {
            image.set_attribute(format!("verity.lightmap.{key}"), value);
        }
        image
    }
}

/// One texel's estimate: E, the variance of its mean, whether the shape covers it.
type Texel = (Vec3, Vec3, bool);

/// Bakes `scene`'s light map. Errors name the shape or setting at fault.
pub fn bake(scene: &Scene, s: &BakeSettings) -> Result<Baked, String> {
    if s.spp == 0 {
        return Err("a bake needs at least 1 sample per texel".into());
    }
    let start = Instant::now();
    let layout = lightmap::layout(scene, s.resolution, s.padding, &s.dynamic)?;
    // Per atlas texel: E and its variance (12 bytes each), `covered` and the dilation's two
    // copies of it (3), and at most one chart's estimates in flight (a 28-byte Texel),
    // rounded up to 80 bytes.
    let texels = u64::from(layout.width) * u64::from(layout.height);
    scenes::budget::check(texels * 80, format!("the light-map atlas of {texels} texels"))
        .map_err(|e| e.to_string())?;
    let mut baked_scene = scene.clone();
    baked_scene
        .shapes
        .retain(|shape| !s.dynamic.contains(&shape.name));
    let accel = Accel::build(&baked_scene)?;
    let lights = LightSet::new(&baked_scene)?;
    let ctx = Context {
        scene: &baked_scene,
        accel: &accel,
        lights: &lights,
        settings: RenderSettings {
            integrator: IntegratorKind::Path,
            max_depth: s.max_depth,
            seed: s.seed,
            spp: s.spp,
            ..baked_scene.render
        },
    };
    let (w, h) = (layout.width as usize, layout.height as usize);
    let mut irradiance = vec![Vec3::ZERO; w * h];
    let mut variance = vec![Vec3::ZERO; w * h];
    let mut covered = vec![false; w * h];
    let mut rays = 0u64;
    for chart in &layout.charts {
        let index = baked_scene
            .shapes
            .iter()
            .position(|shape| shape.name == chart.name)
            .expect("a chart's shape is static") as u32;
        let rows: Vec<(u32, Vec<Texel>, u64)> = (0..chart.height)
            .into_par_iter()
            .map(|j| {
                let mut row = Vec::with_capacity(chart.width as usize);
                let mut row_rays = 0u64;
                for i in 0..chart.width {
                    let c = chart.texel_centre(i, j, s.texel_offset);
                    let Some(q) = chart.point(c) else {
                        row.push((Vec3::ZERO, Vec3::ZERO, false));
                        continue;
                    };
                    let hit = SurfaceHit {
                        t: 0.0,
                        p: q.p,
                        ng: q.ng,
                        ns: q.ns,
                        dpdu: q.dpdu,
                        uv: c,
                        shape: index,
                        prim: q.triangle,
                    };
                    let (ax, ay) = (chart.x + i, chart.y + j);
                    let mut sums = [0.0f64; REPLICATE_SUMS];
                    for k in 0..s.spp {
                        let mut sampler = PixelSampler::of_kind(ctx.settings.sampler, ax, ay, k, s.seed);
                        let (e, r) = path_irradiance(&ctx, &hit, &mut sampler);
                        row_rays += u64::from(r);
                        let rep = &mut sums[4 * replicate_of(k) as usize..][..4];
                        rep[0] += 1.0;
                        (0..3).for_each(|c| rep[1 + c] += f64::from(e[c]));
                    }
                    let (mean, var, _) = replicate_estimate(&sums);
                    let vec = |v: [f64; 3]| glam::DVec3::from_array(v).as_vec3();
                    row.push((vec(mean), vec(var), true));
                }
                (j, row, row_rays)
            })
            .collect();
        for (j, row, row_rays) in rows {
            rays += row_rays;
            for (i, (e, v, on)) in row.into_iter().enumerate() {
                let k = (chart.y + j) as usize * w + (chart.x as usize + i);
                irradiance[k] = e;
                variance[k] = v;
                covered[k] = on;
            }
        }
    }
    let mut map = LightMap {
        layout,
        irradiance,
        variance,
        covered,
    };
    map.dilate(s.dilation.max(s.padding));
    let relative: Vec<f64> = (0..w * h)
        .filter(|&k| map.covered[k])
        .filter_map(|k| {
            let e = f64::from(map.irradiance[k].element_sum()) / 3.0;
            let sd = (f64::from(map.variance[k].element_sum()) / 3.0).sqrt();
            (e > 0.0).then(|| sd / e)
        })
        .collect();
    let mean_relative_std_error = if relative.is_empty() {
        0.0
    } else {
        relative.iter().sum::<f64>() / relative.len() as f64
    };
    Ok(Baked {
        map,
        seconds: start.elapsed().as_secs_f64(),
        rays,
        mean_relative_std_error,
    })
}
