//! Rendering a scene: settings, the frame loop (warm-up, timed frames, read-back), the
//! optional counting frame, the object-id pass at pixel centres and the visibility AOV.
//!
//! One frame is one command buffer: under a shadow method the shadow pass (one depth-only
//! render pass per map layer: per light, or per cascade), then the forward pass, or the
//! G-buffer pass and the lighting pass, each a labelled render pass with debug groups and,
//! when the adapter has them, timestamp writes at its start and end. Frames are submitted one
//! at a time and waited for, so wall time around submit-and-wait is one frame's latency.

use std::sync::{Arc, Mutex};
use std::time::Instant;

use glam::Vec2;
use scenes::layered::LayeredImage;
use scenes::Scene;

use crate::camera::camera_near;

use crate::error::RasterError;
use crate::frame::{encode_passes, Frame, Pass, ShadingGroups};
use crate::gpu::Gpu;
use crate::image::{assemble, box_filter, Readback};
use crate::pipelines::PipelineKind;
use crate::pipelines::{Pipelines, Stage};
use crate::settings::RasterSettings;
use crate::targets::{MultisampledOutputs, Targets};
use crate::technique::antialias::post::{AntiAliasPasses, PostPipelines};
use crate::technique::antialias::{taa, AntiAliasing};
use crate::technique::detail::ConeCache;
use crate::technique::envmap::build::EnvMapBuilder;
use crate::technique::shadow::maps::ShadowMaps;
use crate::technique::ssao::passes::{SsaoPasses, SsaoPipelines};
use crate::technique::ssao::AmbientOcclusion;
use crate::timestamps::Timestamps;
use crate::timing::{median, Counters, PassTime, Timing, TimingSource};
use crate::upload::SceneGpu;
use crate::visibility::{encode_visibility_pass, named_sources, slots_per_chunk, Chunk, Source};

/// The counting G-buffer names shapes below this (counters_on.wgsl `COUNT_RANGE`).
const COUNTED_SHAPES: u32 = 4095;

/// A finished raster render.
#[derive(Clone, Debug)]
pub struct RasterOutput {
    /// R, G, B, depth.Z, normal.X/Y/Z, albedo.R/G/B, coverage.Y, object_id.Y,
    /// visibility.<light>.Y and the header.
    pub image: LayeredImage,
    /// Cost.
    pub timing: Timing,
    /// Hardware-independent counters, when requested.
    pub counters: Option<Counters>,
}

/// The renderer: one device, the compiled shaders, and a lock that keeps renders (and so
/// their timings) from overlapping.
pub struct Renderer {
    pub(crate) gpu: Gpu,
    pub(crate) pipelines: Pipelines,
    lock: Mutex<()>,
    /// Cone maps of `cone_step`, built once per height texture.
    pub(crate) cones: ConeCache,
    /// Environment maps: group 3 of renders without one, the filters, the builds.
    envmaps: EnvMapBuilder,
    /// The anti-aliasing passes after shading (MSAA resolve, FXAA, MLAA, TAA), built on first use.
    post: PostPipelines,
    /// The SSAO passes between the G-buffer and the lighting, built on first use.
    ssao: SsaoPipelines,
}

impl Renderer {
    /// Picks the adapter (WGPU_BACKEND / WGPU_ADAPTER_NAME honoured), creates the device and
    /// compiles the shader module.
    pub fn new() -> Result<Renderer, RasterError> {
        let gpu = Gpu::new()?;
        let pipelines = Pipelines::new(&gpu.device);
        let envmaps = EnvMapBuilder::new(&gpu.device, &pipelines.envmap_layout);
        let post = PostPipelines::new(&gpu.device);
        let ssao = SsaoPipelines::new(&gpu.device);
        let r = Renderer {
            gpu,
            pipelines,
            lock: Mutex::new(()),
            cones: ConeCache::default(),
            envmaps,
            post,
            ssao,
        };
        r.gpu.check_errors("compiling the shaders")?;
        Ok(r)
    }

    /// The device and its adapter.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Renders `scene` (its camera; the settings' resolution) and reads the image back.
    pub fn render(&self, scene: &Scene, settings: &RasterSettings) -> Result<RasterOutput, RasterError> {
        let _guard = self.lock.lock().unwrap_or_else(|p| p.into_inner());
        let device = &self.gpu.device;
        settings.check(self.gpu.limits().max_texture_dimension_2d, self.gpu.msaa_counts())?;
        let scene_gpu = SceneGpu::new(
            &self.gpu,
            scene,
            &settings.method,
            &self.cones,
            settings.lightmap.as_ref().map(|l| &*l.map),
        )
        .map_err(RasterError::Scene)?;
        let shadow = ShadowMaps::new(
            device,
            &self.pipelines.shadow_layout,
            scene,
            &settings.method,
            settings.width as f32 / settings.height as f32,
            self.gpu.limits(),
        )
        .map_err(RasterError::Settings)?;
        let envmap = self
            .envmaps
            .build(&self.gpu, &self.pipelines, &self.cones, scene, settings)?;
        let aa = settings
            .method
            .get::<AntiAliasing>()
            .copied()
            .unwrap_or(AntiAliasing::None);
        let k = settings.supersampling();
        let samples = aa.msaa_samples();
        let (tw, th) = (settings.width * k, settings.height * k);
        let layout = &self.pipelines.scene_layout;
        let frame = Frame::new(device, layout, scene, &scene_gpu, &shadow, settings, k);
        let mut targets = Targets::new(device, settings.pipeline, tw, th, &self.pipelines.gbuffer_layout);
        if samples > 1 {
            let deferred =
                (settings.pipeline == PipelineKind::Deferred).then_some(&self.pipelines.gbuffer_msaa_layout);
            targets.msaa = Some(MultisampledOutputs::new(device, tw, th, samples, deferred));
        }
        let aa_passes = AntiAliasPasses::new(device, &self.post, &aa, &targets);
        let ssao_passes = settings
            .method
            .get::<AmbientOcclusion>()
            .and_then(|ao| SsaoPasses::new(device, &self.ssao, ao, &targets, scene));
        let groups = ShadingGroups {
            empty: &self.pipelines.empty_bind_group,
            shadow: &shadow,
            envmap: &envmap.bind_group,
            ssao: ssao_passes.as_ref(),
        };
        self.pipelines.prepare(
            device,
            &settings.method,
            &self.pipeline_requests(settings, &scene_gpu, samples, k),
        );
        let stages = self
            .pipelines
            .stages(device, &settings.method, settings.pipeline, false, samples);
        self.gpu
            .check_errors("creating the scene buffers and pipelines")?;

        let temporal_ssao = settings
            .method
            .get::<AmbientOcclusion>()
            .filter(|a| a.temporal > 0)
            .zip(ssao_passes.as_ref());
        let near = camera_near(scene);
        let queue = &self.gpu.queue;
        let (frame_ref, scene_gpu_ref) = (&frame, &scene_gpu);
        // A sequence of frames that differ (TAA; SSAO's temporal accumulation): how many, and
        // what each sets before it runs (its view, and its pass's per-frame parameters).
        type SetFrame<'a> = Box<dyn Fn(u32) + 'a>;
        let sequence: Option<(u32, SetFrame<'_>)> = match (&aa, aa_passes.post(), temporal_ssao) {
            (AntiAliasing::Taa { frames, jitter, .. }, Some(post), _) => Some((
                *frames,
                Box::new(move |i: u32| {
                    let camera = taa::camera(&aa, &scene.camera, i);
                    let jitter = taa::jitter(i, *jitter);
                    frame_ref.set_view(queue, scene, &camera, jitter, scene_gpu_ref, settings, k);
                    let previous = taa::camera(&aa, &scene.camera, i.saturating_sub(1));
                    let film = (settings.width, settings.height);
                    post.set_taa_frame(queue, i == 0, &camera, &previous, film, near);
                }),
            )),
            (_, _, Some((ao, passes))) => Some((
                ao.temporal,
                Box::new(move |i: u32| {
                    let camera = ao.camera(&scene.camera, i);
                    frame_ref.set_view(queue, scene, &camera, Vec2::ZERO, scene_gpu_ref, settings, k);
                    let previous = ao.camera(&scene.camera, i.saturating_sub(1));
                    passes.set_frame(queue, i, &camera, &previous, near);
                }),
            )),
            _ => None,
        };
        // Without a sequence every frame is the same one; with one, warm-up frames are its
        // first frame, each starting the history anew.
        let moves = sequence.is_some();
        let (frames, set_frame): (u32, SetFrame<'_>) =
            sequence.unwrap_or((settings.timed_frames, Box::new(|_| {})));
        let timing = self.timed_frames(
            &frame,
            &targets,
            &stages,
            &scene_gpu,
            &groups,
            Some(&aa_passes),
            (settings.warmup_frames, frames),
            &|i| set_frame(i.saturating_sub(settings.warmup_frames)),
        )?;
        if moves {
            // The AOV frames below see the scene's own view, unjittered.
            frame.set_view(queue, scene, &scene.camera, Vec2::ZERO, &scene_gpu, settings, k);
        }
        let main = self.read_back(&targets)?;
        let counters = if settings.counters {
            let taps = self.post_taps(&aa_passes, &targets, settings)?;
            let loads = match &ssao_passes {
                Some(p) => Some(self.ssao_loads(p, settings)?),
                None => None,
            };
            let mut c = self.counting_frame(&frame, &targets, &scene_gpu, &groups, settings)?;
            c.post_taps_per_pixel = taps;
            c.ssao_loads_per_pixel = loads;
            Some(c)
        } else {
            None
        };
        // Object ids at pixel centres: the centre subsample for odd k, else a 1× render.
        let ids = if k % 2 == 1 {
            None
        } else {
            let one = Frame::new(device, layout, scene, &scene_gpu, &shadow, settings, 1);
            let t1 = Targets::new(
                device,
                settings.pipeline,
                settings.width,
                settings.height,
                &self.pipelines.gbuffer_layout,
            );
            let single = self
                .pipelines
                .stages(device, &settings.method, settings.pipeline, false, 1);
            self.run_frame(&one, &t1, &single, &scene_gpu, &groups, None, None)?;
            Some(self.read_back(&t1)?.albedo_id.iter().map(|t| t[3]).collect())
        };
        let visibility = self.visibility_frame(&frame, &targets, &scene_gpu, &groups, settings)?;
        let mut image = assemble(&main, settings.width, settings.height, k, ids);
        let coverage = image
            .channel("coverage.Y")
            .map(<[f32]>::to_vec)
            .unwrap_or_default();
        for (name, source) in named_sources(scene) {
            let channel = match source {
                Source::Slot(slot) => box_filter(&visibility[slot], settings.width, settings.height, k),
                Source::Coverage => coverage.clone(),
            };
            image.push_channel(format!("visibility.{name}.Y"), channel);
        }
        add_header(
            &mut image,
            scene,
            settings,
            &self.gpu,
            &timing,
            counters.as_ref(),
            &scene_gpu,
            &shadow,
        );
        for (k, v) in &envmap.header {
            image.set_attribute(*k, v.clone());
        }
        Ok(RasterOutput {
            image,
            timing,
            counters,
        })
    }

    /// `frames` = (warm-up, timed) frames, each after `before(i)` (i counts every frame from
    /// 0); the last one's image stays in `targets`.
    #[allow(clippy::too_many_arguments)]
    fn timed_frames(
        &self,
        frame: &Frame,
        targets: &Targets,
        stages: &[(Stage, Arc<wgpu::RenderPipeline>)],
        scene_gpu: &SceneGpu,
        groups: &ShadingGroups<'_>,
        aa: Option<&AntiAliasPasses>,
        (warmup_frames, timed_frames): (u32, u32),
        before: &dyn Fn(u32),
    ) -> Result<Timing, RasterError> {
        let passes = Pass::of_frame(stages, groups.shadow, groups.ssao, targets, aa);
        let queries = self
            .gpu
            .has_timestamps()
            .then(|| Timestamps::new(&self.gpu.device, passes.len() as u32));
        let mut wall = Vec::new();
        let mut per_pass: Vec<Vec<f64>> = vec![Vec::new(); passes.len()];
        let mut gpu_total = Vec::new();
        for i in 0..warmup_frames + timed_frames {
            before(i);
            let t0 = Instant::now();
            self.run_frame(frame, targets, stages, scene_gpu, groups, aa, queries.as_ref())?;
            let dt = t0.elapsed().as_secs_f64() * 1e3;
            let ticks = match &queries {
                Some(q) => Some(q.read(&self.gpu)?),
                None => None,
            };
            if i < warmup_frames {
                continue;
            }
            wall.push(dt);
            if let Some(ms) = ticks {
                for (p, v) in per_pass.iter_mut().zip(&ms) {
                    p.push(*v);
                }
                gpu_total.push(ms.iter().sum());
            }
        }
        // Timestamps that did not advance (some drivers report zeros) fall back to wall time.
        let gpu_ms = (!gpu_total.is_empty())
            .then(|| median(&gpu_total))
            .filter(|t| *t > 0.0);
        Ok(Timing {
            adapter: self.gpu.adapter_name().to_string(),
            backend: self.gpu.backend(),
            driver: self.gpu.driver(),
            source: if gpu_ms.is_some() {
                TimingSource::GpuTimestamps
            } else {
                TimingSource::WallClock
            },
            passes: if gpu_ms.is_some() {
                passes
                    .iter()
                    .zip(&per_pass)
                    .map(|(n, v)| PassTime {
                        name: n.label().to_string(),
                        ms: median(v),
                    })
                    .collect()
            } else {
                Vec::new()
            },
            gpu_ms,
            wall_ms: median(&wall),
            warmup_frames,
            timed_frames,
        })
    }

    /// Encodes, submits and waits for one frame.
    #[allow(clippy::too_many_arguments)]
    fn run_frame(
        &self,
        frame: &Frame,
        targets: &Targets,
        stages: &[(Stage, Arc<wgpu::RenderPipeline>)],
        scene_gpu: &SceneGpu,
        groups: &ShadingGroups<'_>,
        aa: Option<&AntiAliasPasses>,
        queries: Option<&Timestamps>,
    ) -> Result<(), RasterError> {
        let device = &self.gpu.device;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame encoder"),
        });
        encode_passes(
            &mut encoder,
            frame,
            targets,
            stages,
            scene_gpu,
            groups,
            aa,
            queries,
        );
        if let Some(q) = queries {
            q.encode_resolve(&mut encoder);
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()?;
        self.gpu.check_errors("rendering a frame")
    }

    /// Copies the outputs back and maps them.
    fn read_back(&self, targets: &Targets) -> Result<Readback, RasterError> {
        let device = &self.gpu.device;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("read-back encoder"),
        });
        let buffers = targets.encode_readback(device, &mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        let mut out = Vec::with_capacity(3);
        for b in &buffers {
            let bytes = self.map(b)?;
            out.push(targets.unpad(&bytes));
        }
        let albedo_id = out.pop().unwrap_or_default();
        let normal_depth = out.pop().unwrap_or_default();
        let color = out.pop().unwrap_or_default();
        Ok(Readback {
            width: targets.width,
            height: targets.height,
            color,
            normal_depth,
            albedo_id,
        })
    }

    /// Maps `buffer` for reading and copies its contents out.
    /// Ends `encoder` with a copy of `src` into a fresh mappable buffer (`label`), submits it,
    /// waits, and returns the bytes; `what` names the frame in errors.
    fn submit_and_read(
        &self,
        mut encoder: wgpu::CommandEncoder,
        src: &wgpu::Buffer,
        label: &str,
        what: &str,
    ) -> Result<Vec<u8>, RasterError> {
        let readback = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: src.size(),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        encoder.copy_buffer_to_buffer(src, 0, &readback, 0, src.size());
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()?;
        self.gpu.check_errors(what)?;
        self.map(&readback)
    }

    fn map(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>, RasterError> {
        let slice = buffer.slice(..);
        let status = Arc::new(Mutex::new(None));
        let s = status.clone();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            *s.lock().unwrap_or_else(|p| p.into_inner()) = Some(r);
        });
        self.gpu.wait()?;
        let result = status.lock().unwrap_or_else(|p| p.into_inner()).take();
        match result {
            Some(Ok(())) => {
                let bytes = slice.get_mapped_range().to_vec();
                buffer.unmap();
                Ok(bytes)
            }
            other => Err(RasterError::Gpu {
                context: "reading back a buffer".into(),
                message: format!("{other:?}"),
            }),
        }
    }

    /// Single-sampled deferred targets of `targets`' size: `targets` itself when it has such a
    /// G-buffer, else new ones kept in `holder`.
    fn gbuffer_targets<'a>(&self, targets: &'a Targets, holder: &'a mut Option<Targets>) -> &'a Targets {
        if targets.gbuffer_views.is_some() && targets.msaa.is_none() {
            return targets;
        }
        holder.insert(Targets::new(
            &self.gpu.device,
            PipelineKind::Deferred,
            targets.width,
            targets.height,
            &self.pipelines.gbuffer_layout,
        ))
    }

    /// Every pipeline a render with `settings` draws with (stage, counting variant, samples
    /// per pixel), for [`Pipelines::prepare`]: the frame's stages, the counting frame's
    /// (`counting_frame`), the single-sampled frame of the object ids under an even
    /// supersampling factor `k`, and the visibility AOV frame's (`visibility_frame`).
    fn pipeline_requests(
        &self,
        settings: &RasterSettings,
        scene_gpu: &SceneGpu,
        samples: u32,
        k: u32,
    ) -> Vec<(Stage, bool, u32)> {
        let frame = |n| Pipelines::frame_stages(&settings.method, settings.pipeline, n);
        let mut out: Vec<(Stage, bool, u32)> =
            frame(samples).into_iter().map(|(s, n)| (s, false, n)).collect();
        if settings.counters {
            out.extend([Stage::GBufferMesh, Stage::GBufferAnalytic, Stage::Lighting].map(|s| (s, true, 1)));
        }
        if k.is_multiple_of(2) {
            out.extend(frame(1).into_iter().map(|(s, n)| (s, false, n)));
        }
        if scene_gpu.emitter_count + scene_gpu.light_count > 0 {
            out.extend(
                [Stage::GBufferMesh, Stage::GBufferAnalytic, Stage::VisibilityAov].map(|s| (s, false, 1)),
            );
        }
        out
    }

    /// The G-buffer stages of `settings`' method.
    fn gbuffer_stages(
        &self,
        settings: &RasterSettings,
        counters: bool,
    ) -> Vec<(Stage, Arc<wgpu::RenderPipeline>)> {
        [Stage::GBufferMesh, Stage::GBufferAnalytic]
            .into_iter()
            .map(|s| {
                (
                    s,
                    self.pipelines
                        .get(&self.gpu.device, s, &settings.method, counters),
                )
            })
            .collect()
    }

    /// The counting frame: a G-buffer pass, then the lighting pass compiled with the counters,
    /// so each visible sample is shaded (and counted) once whatever the pipeline; sums the rows.
    /// The G-buffer pass is the counting variant too: each sample carries the fetches its
    /// surface cost (normal map, surface detail) to the lighting pass in its object id
    /// (counters_on.wgsl), so only the visible surface's are counted.
    /// Shadow-map fetches are counted; the maps are those the timed frames left.
    fn counting_frame(
        &self,
        frame: &Frame,
        targets: &Targets,
        scene_gpu: &SceneGpu,
        groups: &ShadingGroups<'_>,
        settings: &RasterSettings,
    ) -> Result<Counters, RasterError> {
        let device = &self.gpu.device;
        if scene_gpu.shape_count >= COUNTED_SHAPES {
            return Err(RasterError::Settings(format!(
                "the counting frame names at most {} shapes (counters_on.wgsl); the scene has {}",
                COUNTED_SHAPES - 1,
                scene_gpu.shape_count
            )));
        }
        let mut holder = None;
        let targets = self.gbuffer_targets(targets, &mut holder);
        let mut stages = self.gbuffer_stages(settings, true);
        stages.push((
            Stage::Lighting,
            self.pipelines
                .get(device, Stage::Lighting, &settings.method, true),
        ));
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("counting frame encoder"),
        });
        encoder.clear_buffer(&frame.counters, 0, None);
        encode_passes(
            &mut encoder,
            frame,
            targets,
            &stages,
            scene_gpu,
            groups,
            None,
            None,
        );
        let bytes = self.submit_and_read(
            encoder,
            &frame.counters,
            "counters read-back",
            "the counting frame",
        )?;
        let mut sums = [0u64; 2];
        for (i, c) in bytes.chunks_exact(4).enumerate() {
            sums[i % 2] += u64::from(u32::from_le_bytes([c[0], c[1], c[2], c[3]]));
        }
        let pixels = f64::from(settings.width) * f64::from(settings.height);
        Ok(Counters {
            texel_fetches_per_pixel: sums[0] as f64 / pixels,
            loop_iterations_per_pixel: sums[1] as f64 / pixels,
            post_taps_per_pixel: None,
            ssao_loads_per_pixel: None,
        })
    }

    /// Texture loads per final pixel of the SSAO passes, counted by running them once more
    /// on the last frame's G-buffer (`SsaoPasses::encode_load_count`).
    fn ssao_loads(&self, passes: &SsaoPasses, settings: &RasterSettings) -> Result<f64, RasterError> {
        let device = &self.gpu.device;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("SSAO load count encoder"),
        });
        let rows = passes.encode_load_count(device, &self.ssao, &mut encoder);
        self.per_pixel_count(encoder, rows, "counting the SSAO loads", settings)
    }

    /// Texel loads per final pixel of the anti-aliasing passes after shading, counted by
    /// running them once more on the last frame (`AntiAliasPasses::encode_tap_count`); None
    /// without such passes.
    fn post_taps(
        &self,
        aa: &AntiAliasPasses,
        targets: &Targets,
        settings: &RasterSettings,
    ) -> Result<Option<f64>, RasterError> {
        let device = &self.gpu.device;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("post-process tap count encoder"),
        });
        let Some(taps) = aa.encode_tap_count(device, &self.post, &mut encoder, targets) else {
            return Ok(None);
        };
        self.per_pixel_count(encoder, taps, "counting the post-process taps", settings)
            .map(Some)
    }

    /// Submits `encoder`, reads back `rows` (u32 counters, one per target row) and returns
    /// their sum per final pixel; `what` names the work in errors.
    fn per_pixel_count(
        &self,
        encoder: wgpu::CommandEncoder,
        rows: &wgpu::Buffer,
        what: &str,
        settings: &RasterSettings,
    ) -> Result<f64, RasterError> {
        let bytes = self.submit_and_read(encoder, rows, "row counters read-back", what)?;
        let sum: u64 = bytes
            .chunks_exact(4)
            .map(|c| u64::from(u32::from_le_bytes([c[0], c[1], c[2], c[3]])))
            .sum();
        Ok(sum as f64 / (f64::from(settings.width) * f64::from(settings.height)))
    }

    /// The visibility AOV frame (visibility.rs): a G-buffer pass, then the visibility pass per
    /// chunk of light slots; V of every slot at every target sample, slot by slot.
    fn visibility_frame(
        &self,
        frame: &Frame,
        targets: &Targets,
        scene_gpu: &SceneGpu,
        groups: &ShadingGroups<'_>,
        settings: &RasterSettings,
    ) -> Result<Vec<Vec<f32>>, RasterError> {
        let device = &self.gpu.device;
        let slots = scene_gpu.emitter_count + scene_gpu.light_count;
        if slots == 0 {
            return Ok(Vec::new());
        }
        let mut holder = None;
        let targets = self.gbuffer_targets(targets, &mut holder);
        let pixels = targets.width * targets.height;
        let limits = self.gpu.limits();
        let max_bytes = u64::from(limits.max_storage_buffer_binding_size).min(limits.max_buffer_size);
        let per_chunk = slots_per_chunk(slots, pixels, max_bytes).map_err(RasterError::Settings)?;
        let chunk = Chunk::new(device, &self.pipelines.aov_layout, targets, per_chunk, slots);
        let pipeline = self
            .pipelines
            .get(device, Stage::VisibilityAov, &settings.method, false);
        let stages = self.gbuffer_stages(settings, false);
        let mut out = Vec::with_capacity(slots as usize);
        for c in 0..slots.div_ceil(per_chunk) {
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("visibility AOV encoder"),
            });
            if c == 0 {
                encode_passes(
                    &mut encoder,
                    frame,
                    targets,
                    &stages,
                    scene_gpu,
                    groups,
                    None,
                    None,
                );
            }
            let shadow_group = &groups.shadow.bind_group;
            encode_visibility_pass(
                &mut encoder,
                targets,
                &frame.bind_group,
                &chunk.bind_group,
                shadow_group,
                &pipeline,
                c,
            );
            let bytes = self.submit_and_read(
                encoder,
                &chunk.output,
                "visibility AOV read-back",
                "the visibility AOV frame",
            )?;
            let values: Vec<f32> = bytes
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect();
            let here = (slots - c * per_chunk).min(per_chunk) as usize;
            out.extend(
                values
                    .chunks_exact(pixels as usize)
                    .take(here)
                    .map(<[f32]>::to_vec),
            );
        }
        Ok(out)
    }
}

/// Header attributes: renderer, adapter, backend, method, parameters, timing, counters, the
/// shadow maps' projections, the object-id names (`scenes::layered::OBJECT_NAMES_ATTRIBUTE`),
/// the environment texels the scene's loading clamped.
#[allow(clippy::too_many_arguments)]
fn add_header(
    image: &mut LayeredImage,
    scene: &Scene,
    s: &RasterSettings,
    gpu: &Gpu,
    timing: &Timing,
    counters: Option<&Counters>,
    sg: &SceneGpu,
    shadow: &ShadowMaps,
) {
    let params: Vec<String> = s
        .method
        .params()
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect();
    let mut attrs = vec![
        (
            "renderer",
            format!("verity realtime {}", env!("CARGO_PKG_VERSION")),
        ),
        ("scene", scene.source.display().to_string()),
        ("adapter", gpu.adapter_name().to_string()),
        ("backend", gpu.backend()),
        ("driver", gpu.driver()),
        ("method", s.method.name().to_string()),
        ("parameters", params.join(" ")),
        ("pipeline", s.pipeline.name().to_string()),
        ("ssaa", s.ssaa.to_string()),
        ("samples_per_pixel", samples_per_pixel(s).to_string()),
        ("frame_ms", format!("{:.6}", timing.frame_ms())),
        ("wall_ms", format!("{:.6}", timing.wall_ms)),
        (
            "timing",
            match timing.source {
                TimingSource::GpuTimestamps => "gpu timestamps".to_string(),
                TimingSource::WallClock => "wall clock".to_string(),
            },
        ),
        ("timing_summary", timing.summary()),
    ];
    if !timing.passes.is_empty() {
        let passes: Vec<String> = timing
            .passes
            .iter()
            .map(|p| format!("{}: {:.6}", p.name, p.ms))
            .collect();
        attrs.push(("pass_ms", passes.join("; ")));
    }
    if let Some(c) = counters {
        attrs.push((
            "texel_fetches_per_pixel",
            format!("{:.4}", c.texel_fetches_per_pixel),
        ));
        attrs.push((
            "loop_iterations_per_pixel",
            format!("{:.4}", c.loop_iterations_per_pixel),
        ));
        if let Some(t) = c.ssao_loads_per_pixel {
            attrs.push(("ssao_loads_per_pixel", format!("{t:.4}")));
        }
        if let Some(t) = c.post_taps_per_pixel {
            attrs.push(("post_taps_per_pixel", format!("{t:.4}")));
        }
    }
    if !shadow.frusta.is_empty() {
        let maps: Vec<String> = shadow.frusta.iter().map(|f| f.describe()).collect();
        attrs.push(("shadow_maps", maps.join("; ")));
    }
    if !sg.emissive_meshes.is_empty() {
        attrs.push((
            "emissive_mesh_lights",
            format!(
                "lit per triangle by quadrature, unshadowed: {}",
                sg.emissive_meshes.join(", ")
            ),
        ));
    }
    let clamped = scene.provenance.clamped_environment_texels;
    if clamped > 0 {
        attrs.push(("environment_clamped_texels", clamped.to_string()));
    }
    for (k, v) in attrs {
        image.set_attribute(k, v);
    }
    image.set_object_names(scene.shapes.iter().map(|s| s.name.as_str()));
}

/// Samples taken in each pixel: k² shaded samples (`ssaa` × `aa_ssaa`), times the MSAA
/// coverage samples, times TAA's frames (one jittered sample each).
pub fn samples_per_pixel(s: &RasterSettings) -> u32 {
    let k = s.supersampling();
    let per_frame = match s.method.get::<AntiAliasing>().copied() {
        Some(AntiAliasing::Msaa { samples }) => samples,
        Some(AntiAliasing::Taa { frames, .. }) => frames,
        _ => 1,
    };
    k * k * per_frame
}
