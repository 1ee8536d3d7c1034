//! The SSAO passes of one render (docs/ARCHITECTURE.md "Passes of one frame", stage 3): after
//! the G-buffer pass and before the lighting, full-screen passes into single-channel targets
//! that hold the ambient obscurance 1 − AO (targets.rs `OBSCURANCE_FORMAT`):
//!
//! | pass | reads | writes |
//! |---|---|---|
//! | AO (`fs_ao`, the method's file) | G-buffer positions, normals | obscurance at AO resolution |
//! | blur x, blur y (`fs_blur`, under `blur`) | G-buffer, obscurance | obscurance |
//! | upsample (`fs_upsample`, under `half_res`) | G-buffer, half-resolution obscurance | obscurance |
//! | temporal (`fs_temporal`, under `temporal`) | G-buffer positions, obscurance, history | obscurance, next history |
//!
//! The last pass writes the targets' obscurance, which the lighting reads; under `temporal` the
//! next history is then copied over the history (obscurance and view depth, Rg32Float). Each estimator is a
//! shader module of its own (common.wgsl, march.wgsl, its file, ao.wgsl); the blur and the
//! upsampling share one (common.wgsl, filter.wgsl). The pipelines are built on first use and
//! held by the renderer.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::Vec2;
use scenes::{Camera, Scene};
use wgpu::util::DeviceExt;

use super::{AmbientOcclusion, SsaoTechnique};
use crate::built_once::BuiltOnce;
use crate::camera::{camera_near, view_proj};
use crate::gpu_types::vec4;
use crate::pipelines::{fullscreen_pipeline, unfilterable_texture};
use crate::targets::{
    cleared_attachments, obscurance_texture, texture_2d, view_entries, Targets, OBSCURANCE_FORMAT,
};
use crate::timestamps::Timestamps;

const COMMON: &str = include_str!("common.wgsl");
const MARCH: &str = include_str!("march.wgsl");
const AO: &str = include_str!("ao.wgsl");
const FILTER: &str = include_str!("filter.wgsl");

/// A pass's entry point (and the module holding it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Entry {
    Ao(SsaoTechnique),
    Blur,
    Upsample,
    Temporal,
}

impl Entry {
    fn fragment(self) -> &'static str {
        match self {
            Entry::Ao(_) => "fs_ao",
            Entry::Blur => "fs_blur",
            Entry::Upsample => "fs_upsample",
            Entry::Temporal => "fs_temporal",
        }
    }

    fn source(self) -> String {
        let technique = match self {
            Entry::Ao(SsaoTechnique::Crytek) => include_str!("crytek.wgsl"),
            Entry::Ao(SsaoTechnique::Hemisphere) => include_str!("hemisphere.wgsl"),
            Entry::Ao(SsaoTechnique::Hbao) => include_str!("hbao.wgsl"),
            Entry::Ao(SsaoTechnique::Gtao) => include_str!("gtao.wgsl"),
            Entry::Blur | Entry::Upsample | Entry::Temporal => return format!("{COMMON}\n{FILTER}"),
        };
        format!("{COMMON}\n{MARCH}\n{technique}\n{AO}")
    }
}

/// WGSL `SsaoUniforms` (ssao/common.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct SsaoUniforms {
    view_proj: [[f32; 4]; 4],
    /// Camera position, focal length in target pixels.
    cam_pos: [f32; 4],
    cam_right: [f32; 4],
    cam_up: [f32; 4],
    cam_forward: [f32; 4],
    /// Target width, height; AO width, height.
    sizes: [u32; 4],
    /// Radius, bias (m), blur radius, AO texel → target pixel scale.
    params: [f32; 4],
    /// Samples, directions, steps, falloff.
    counts: [u32; 4],
    /// The previous frame's view-projection (temporal accumulation).
    prev_view_proj: [[f32; 4]; 4],
    /// Frame index, frames accumulated (0: none), unused ×2.
    temporal: [u32; 4],
}

/// The temporal history's format: obscurance and view depth.
const HISTORY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;

/// The layouts and the pipelines, cached by entry point.
pub(crate) struct SsaoPipelines {
    /// Group 0: G-buffer positions and normals, the uniforms.
    shared_layout: wgpu::BindGroupLayout,
    /// Group 1: the previous pass's obscurance, the pass's axis.
    pass_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// By entry point and whether it counts its loads (`COUNT_LOADS`).
    cache: BuiltOnce<(Entry, bool), wgpu::RenderPipeline>,
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl SsaoPipelines {
    pub(crate) fn new(device: &wgpu::Device) -> SsaoPipelines {
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let shared_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("SSAO bind group layout (G-buffer, uniforms, load counters)"),
            entries: &[
                unfilterable_texture(0, fragment, false),
                unfilterable_texture(1, fragment, false),
                uniform_entry(2),
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: fragment,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: false },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        let pass_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("SSAO pass bind group layout (obscurance, axis, history)"),
            entries: &[
                unfilterable_texture(0, fragment, false),
                uniform_entry(1),
                unfilterable_texture(2, fragment, false),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("SSAO pipeline layout"),
            bind_group_layouts: &[&shared_layout, &pass_layout],
            push_constant_ranges: &[],
        });
        SsaoPipelines {
            shared_layout,
            pass_layout,
            pipeline_layout,
            cache: BuiltOnce::new(),
        }
    }

    /// The pipeline of `entry`, counting its loads or not, built on first use.
    fn get(&self, device: &wgpu::Device, entry: Entry, counting: bool) -> Arc<wgpu::RenderPipeline> {
        self.cache.get_or_build(&(entry, counting), || {
            let label = format!("SSAO: {entry:?} (counting {counting})");
            let constants = [("COUNT_LOADS", if counting { 1.0 } else { 0.0 })];
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&label),
                source: wgpu::ShaderSource::Wgsl(entry.source().into()),
            });
            let formats: &[wgpu::TextureFormat] = match entry {
                Entry::Temporal => &[OBSCURANCE_FORMAT, HISTORY_FORMAT],
                _ => &[OBSCURANCE_FORMAT],
            };
            fullscreen_pipeline(
                device,
                &label,
                &self.pipeline_layout,
                &module,
                ("vs_fullscreen", entry.fragment()),
                formats,
                &constants,
            )
        })
    }
}

/// One full-screen pass: its pipeline, its inputs and axis, its targets.
struct SsaoPass {
    label: &'static str,
    entry: Entry,
    pipeline: Arc<wgpu::RenderPipeline>,
    inputs: wgpu::BindGroup,
    targets: Vec<wgpu::TextureView>,
}

/// Temporal accumulation's history: read by the temporal pass, rewritten from `next` after it.
struct History {
    current: wgpu::Texture,
    next: wgpu::Texture,
}

/// The SSAO passes of one render, over `targets`' G-buffer into its obscurance.
pub(crate) struct SsaoPasses {
    shared: wgpu::BindGroup,
    passes: Vec<SsaoPass>,
    uniforms: wgpu::Buffer,
    base: SsaoUniforms,
    history: Option<History>,
    /// Texture loads per target row (`COUNT_LOADS`), summed by the counting run.
    load_rows: wgpu::Buffer,
}

/// A `w`×`h` history texture (render target, read by the next frame, copied).
fn history_texture(device: &wgpu::Device, label: &str, w: u32, h: u32) -> wgpu::Texture {
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
        | wgpu::TextureUsages::TEXTURE_BINDING
        | wgpu::TextureUsages::COPY_SRC
        | wgpu::TextureUsages::COPY_DST;
    texture_2d(device, label, (w, h), HISTORY_FORMAT, usage)
}

impl SsaoPasses {
    /// The passes of `ao` for deferred `targets` (None for targets without a G-buffer), seen
    /// from `scene`'s camera, with `scene`'s `ao_radius` where `ao` names no radius.
    pub(crate) fn new(
        device: &wgpu::Device,
        pipelines: &SsaoPipelines,
        ao: &AmbientOcclusion,
        targets: &Targets,
        scene: &Scene,
    ) -> Option<SsaoPasses> {
        let (gbuffer, output) = (targets.gbuffer_views.as_ref()?, targets.obscurance_view.as_ref()?);
        let (w, h) = (targets.width, targets.height);
        let scale = if ao.half_res { 2 } else { 1 };
        let (aw, ah) = (w.div_ceil(scale), h.div_ceil(scale));
        let camera = &scene.camera;
        let radius = ao.radius.unwrap_or(scene.render.ao_radius);
        let near = camera_near(scene);
        let m = camera.to_world.matrix3;
        let focal = 0.5 * h as f32 / (0.5 * camera.fov_y_deg.to_radians()).tan();
        let uniforms = SsaoUniforms {
            view_proj: view_proj(camera, w, h, near, Vec2::ZERO).to_cols_array_2d(),
            cam_pos: vec4(camera.position(), focal),
            cam_right: vec4(m.x_axis.into(), 0.0),
            cam_up: vec4(m.y_axis.into(), 0.0),
            cam_forward: vec4(camera.forward(), 0.0),
            sizes: [w, h, aw, ah],
            params: [radius, ao.bias * radius, ao.blur as f32, scale as f32],
            counts: [ao.samples, ao.directions, ao.steps, ao.falloff.code()],
            prev_view_proj: view_proj(camera, w, h, near, Vec2::ZERO).to_cols_array_2d(),
            temporal: [0, ao.temporal, 0, 0],
        };
        let uniform_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("SSAO uniforms"),
            contents: bytemuck::bytes_of(&uniforms),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let load_rows = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("SSAO load counters (one per target row)"),
            size: 4 * u64::from(h),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut shared_entries = view_entries(&gbuffer[..2], 0);
        shared_entries.push(wgpu::BindGroupEntry {
            binding: 2,
            resource: uniform_buffer.as_entire_binding(),
        });
        shared_entries.push(wgpu::BindGroupEntry {
            binding: 3,
            resource: load_rows.as_entire_binding(),
        });
        let shared = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("SSAO bind group (G-buffer, uniforms)"),
            layout: &pipelines.shared_layout,
            entries: &shared_entries,
        });
        let a = obscurance_texture(device, "SSAO obscurance A", aw, ah);
        let b = obscurance_texture(device, "SSAO obscurance B", aw, ah);
        let history = (ao.temporal > 0).then(|| History {
            current: history_texture(device, "SSAO history", w, h),
            next: history_texture(device, "SSAO next history", w, h),
        });
        let history_views = history.as_ref().map(|h| {
            let view = |t: &wgpu::Texture| t.create_view(&wgpu::TextureViewDescriptor::default());
            (view(&h.current), view(&h.next))
        });
        // Under temporal accumulation the chain ends in a full-resolution texture the temporal
        // pass reads. Binding 2 (the history) is bound in every pass: the others, which read
        // none, get the history too, or without one a texel that no pass writes (a texture
        // bound for reading may not be the pass's target).
        let accumulated = history
            .as_ref()
            .map(|_| obscurance_texture(device, "SSAO this frame", w, h));
        let placeholder = obscurance_texture(device, "SSAO history placeholder", 1, 1);
        let (last, unread) = match (&accumulated, &history_views) {
            (Some(t), Some((current, _))) => (t, current),
            _ => (output, &placeholder),
        };
        let pass = |label, entry, input: &wgpu::TextureView, axis: [i32; 4], target: &wgpu::TextureView| {
            let axis = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("SSAO pass axis"),
                contents: bytemuck::bytes_of(&axis),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let mut entries = view_entries([input], 0);
            entries.push(wgpu::BindGroupEntry {
                binding: 1,
                resource: axis.as_entire_binding(),
            });
            entries.extend(view_entries([unread], 2));
            SsaoPass {
                label,
                entry,
                pipeline: pipelines.get(device, entry, false),
                inputs: device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(label),
                    layout: &pipelines.pass_layout,
                    entries: &entries,
                }),
                targets: vec![target.clone()],
            }
        };
        let estimate = Entry::Ao(ao.technique);
        let (x, y, none) = ([1, 0, 0, 0], [0, 1, 0, 0], [0; 4]);
        let mut passes = match (ao.half_res, ao.blur > 0) {
            (false, false) => vec![pass("SSAO: estimate", estimate, &b, none, last)],
            (false, true) => vec![
                pass("SSAO: estimate", estimate, &b, none, &a),
                pass("SSAO: blur x", Entry::Blur, &a, x, &b),
                pass("SSAO: blur y", Entry::Blur, &b, y, last),
            ],
            (true, false) => vec![
                pass("SSAO: estimate (half resolution)", estimate, &b, none, &a),
                pass("SSAO: upsample", Entry::Upsample, &a, none, last),
            ],
            (true, true) => vec![
                pass("SSAO: estimate (half resolution)", estimate, &b, none, &a),
                pass("SSAO: blur x", Entry::Blur, &a, x, &b),
                pass("SSAO: blur y", Entry::Blur, &b, y, &a),
                pass("SSAO: upsample", Entry::Upsample, &a, none, last),
            ],
        };
        if let (Some(this_frame), Some((_, next))) = (&accumulated, &history_views) {
            let mut temporal = pass(
                "SSAO: temporal accumulation",
                Entry::Temporal,
                this_frame,
                none,
                output,
            );
            temporal.targets.push(next.clone());
            passes.push(temporal);
        }
        Some(SsaoPasses {
            shared,
            passes,
            uniforms: uniform_buffer,
            base: uniforms,
            history,
            load_rows,
        })
    }

    /// Frame `i` of a temporal accumulation, seen from `camera` after `previous` (both at the
    /// targets' size and near plane of [`SsaoPasses::new`]).
    pub(crate) fn set_frame(
        &self,
        queue: &wgpu::Queue,
        i: u32,
        camera: &Camera,
        previous: &Camera,
        near: f32,
    ) {
        let (w, h) = (self.base.sizes[0], self.base.sizes[1]);
        let m = camera.to_world.matrix3;
        let u = SsaoUniforms {
            view_proj: view_proj(camera, w, h, near, Vec2::ZERO).to_cols_array_2d(),
            cam_pos: vec4(camera.position(), self.base.cam_pos[3]),
            cam_right: vec4(m.x_axis.into(), 0.0),
            cam_up: vec4(m.y_axis.into(), 0.0),
            cam_forward: vec4(camera.forward(), 0.0),
            prev_view_proj: view_proj(previous, w, h, near, Vec2::ZERO).to_cols_array_2d(),
            temporal: [i, self.base.temporal[1], 0, 0],
            ..self.base
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
    }

    /// Records the passes, timed together as frame pass `queries.1`.
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder, queries: Option<(&Timestamps, u32)>) {
        self.draw(encoder, queries, |p| p.pipeline.clone());
    }

    /// Records the passes once more with their counting pipelines into cleared load counters,
    /// and returns the counters (one u32 per target row) to read back.
    pub(crate) fn encode_load_count(
        &self,
        device: &wgpu::Device,
        pipelines: &SsaoPipelines,
        encoder: &mut wgpu::CommandEncoder,
    ) -> &wgpu::Buffer {
        encoder.clear_buffer(&self.load_rows, 0, None);
        self.draw(encoder, None, |p| pipelines.get(device, p.entry, true));
        &self.load_rows
    }

    /// The passes with the pipelines `pipeline` picks, then the history copy.
    fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        queries: Option<(&Timestamps, u32)>,
        pipeline: impl Fn(&SsaoPass) -> Arc<wgpu::RenderPipeline>,
    ) {
        let last = self.passes.len() - 1;
        for (i, p) in self.passes.iter().enumerate() {
            let pipeline = pipeline(p);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(p.label),
                color_attachments: &cleared_attachments(&p.targets),
                depth_stencil_attachment: None,
                timestamp_writes: queries.and_then(|(q, k)| q.span_writes(k, i == 0, i == last)),
                occlusion_query_set: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &self.shared, &[]);
            pass.set_bind_group(1, &p.inputs, &[]);
            pass.draw(0..3, 0..1);
        }
        if let Some(h) = &self.history {
            encoder.copy_texture_to_texture(
                h.next.as_image_copy(),
                h.current.as_image_copy(),
                h.current.size(),
            );
        }
    }
}
