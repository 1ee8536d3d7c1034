//! The anti-aliasing passes that run after the scene is lit: the MSAA resolve, and the
//! post-processes of FXAA, MLAA and TAA over the colour target (docs/ARCHITECTURE.md "Passes of
//! one frame", stage 5). Each technique is one shader module of its own
//! (`technique/antialias/<technique>.wgsl` after `common.wgsl`), built on first use.
//!
//! | pass | reads | writes |
//! |---|---|---|
//! | MSAA resolve | the three multisampled outputs | the three outputs |
//! | FXAA | colour | colour |
//! | MLAA edges → weights → blend | colour; edges; weights | edges; weights; colour |
//! | TAA | colour, normal + depth, history | colour and the next history |
//!
//! A post-process renders into a target of its own, which is then copied into the colour
//! output (and, for TAA, into the history the next frame reads).

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::Vec2;
use scenes::Camera;
use wgpu::util::DeviceExt;

use super::{AntiAliasing, TaaClamp};
use crate::built_once::BuiltOnce;
use crate::camera::view_proj;
use crate::gpu::COLOR_FORMAT;
use crate::gpu_types::vec4;
use crate::pipelines::{fullscreen_pipeline, unfilterable_texture};

const FRAGMENT: wgpu::ShaderStages = wgpu::ShaderStages::FRAGMENT;
use crate::targets::{cleared_attachments, view_entries, Targets};
use crate::timestamps::Timestamps;

const COMMON: &str = include_str!("common.wgsl");
const POST: &str = include_str!("post.wgsl");

/// A post-process entry point and the technique file that holds it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Entry {
    Fxaa,
    MlaaEdges,
    MlaaWeights,
    MlaaBlend,
    Taa,
    MsaaResolve,
}

impl Entry {
    fn fragment(self) -> &'static str {
        match self {
            Entry::Fxaa => "fs_fxaa",
            Entry::MlaaEdges => "fs_mlaa_edges",
            Entry::MlaaWeights => "fs_mlaa_weights",
            Entry::MlaaBlend => "fs_mlaa_blend",
            Entry::Taa => "fs_taa",
            Entry::MsaaResolve => "fs_msaa_resolve",
        }
    }

    /// The module's source: the shared helpers, the post-process bindings (not the resolve's)
    /// and the technique's file.
    fn source(self) -> String {
        let technique = match self {
            Entry::Fxaa => include_str!("fxaa.wgsl"),
            Entry::MlaaEdges | Entry::MlaaWeights | Entry::MlaaBlend => {
                include_str!("mlaa.wgsl")
            }
            Entry::Taa => include_str!("taa.wgsl"),
            Entry::MsaaResolve => include_str!("msaa_resolve.wgsl"),
        };
        let bindings = if self == Entry::MsaaResolve { "" } else { POST };
        format!("{COMMON}\n{bindings}\n{technique}")
    }

    /// Colour targets it writes.
    fn targets(self) -> usize {
        if self == Entry::MsaaResolve {
            3
        } else {
            1
        }
    }
}

/// WGSL `PostParams` (technique/antialias/post.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct PostParams {
    pub(crate) size: [f32; 4],
    pub(crate) p0: [f32; 4],
    pub(crate) p1: [f32; 4],
    pub(crate) prev_view_proj: [[f32; 4]; 4],
    pub(crate) cam_pos: [f32; 4],
    pub(crate) cam_x: [f32; 4],
    pub(crate) cam_y: [f32; 4],
    pub(crate) cam_z: [f32; 4],
    pub(crate) cam_forward: [f32; 4],
    pub(crate) film: [f32; 4],
}

/// The layouts and the pipelines of the passes, cached by entry point.
pub(crate) struct PostPipelines {
    pub(crate) layout: wgpu::BindGroupLayout,
    pub(crate) resolve_layout: wgpu::BindGroupLayout,
    post_pipeline_layout: wgpu::PipelineLayout,
    resolve_pipeline_layout: wgpu::PipelineLayout,
    /// By entry point and whether it counts its taps (`COUNT_TAPS`).
    cache: BuiltOnce<(Entry, bool), wgpu::RenderPipeline>,
}

/// Binding 4 of every pass: the tap counters, one per target row.
fn taps_entry() -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding: 4,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: false },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl PostPipelines {
    pub(crate) fn new(device: &wgpu::Device) -> PostPipelines {
        let mut entries: Vec<_> = (0..3).map(|b| unfilterable_texture(b, FRAGMENT, false)).collect();
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: 3,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        });
        entries.push(taps_entry());
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("post-process bind group layout"),
            entries: &entries,
        });
        let mut resolve_entries: Vec<_> = (0..3).map(|b| unfilterable_texture(b, FRAGMENT, true)).collect();
        resolve_entries.push(taps_entry());
        let resolve_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("MSAA resolve bind group layout"),
            entries: &resolve_entries,
        });
        let pipeline_layout = |label, layout| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[layout],
                push_constant_ranges: &[],
            })
        };
        PostPipelines {
            post_pipeline_layout: pipeline_layout("post-process pipeline layout", &layout),
            resolve_pipeline_layout: pipeline_layout("MSAA resolve pipeline layout", &resolve_layout),
            layout,
            resolve_layout,
            cache: BuiltOnce::new(),
        }
    }

    /// The pipeline of `entry`, counting its taps or not, built on first use.
    fn get(&self, device: &wgpu::Device, entry: Entry, counting: bool) -> Arc<wgpu::RenderPipeline> {
        self.cache.get_or_build(&(entry, counting), || {
            let label = format!("anti-aliasing: {} (counting {counting})", entry.fragment());
            let constants = [("COUNT_TAPS", if counting { 1.0 } else { 0.0 })];
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&label),
                source: wgpu::ShaderSource::Wgsl(entry.source().into()),
            });
            let layout = match entry {
                Entry::MsaaResolve => &self.resolve_pipeline_layout,
                _ => &self.post_pipeline_layout,
            };
            fullscreen_pipeline(
                device,
                &label,
                layout,
                &module,
                ("vs_post", entry.fragment()),
                &vec![COLOR_FORMAT; entry.targets()],
                &constants,
            )
        })
    }
}

/// One full-screen pass: its entry point and pipeline, inputs and target.
struct PostPass {
    entry: Entry,
    pipeline: Arc<wgpu::RenderPipeline>,
    bind_group: wgpu::BindGroup,
    target: wgpu::TextureView,
}

/// The post-process of one render.
pub(crate) struct PostProcess {
    passes: Vec<PostPass>,
    /// The last pass's target, copied into the colour output after the passes.
    result: wgpu::Texture,
    /// TAA's history (the previous output), or None.
    history: Option<wgpu::Texture>,
    params: wgpu::Buffer,
    base: PostParams,
}

fn image(device: &wgpu::Device, label: &str, targets: &Targets) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: targets.width,
            height: targets.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: COLOR_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor::default())
}

impl PostProcess {
    /// The passes of `aa` over `targets`' colour output, or None if it has no post-process.
    fn new(
        device: &wgpu::Device,
        pipelines: &PostPipelines,
        aa: &AntiAliasing,
        targets: &Targets,
        taps: &wgpu::Buffer,
    ) -> Option<PostProcess> {
        let (w, h) = (targets.width as f32, targets.height as f32);
        let p0 = match *aa {
            AntiAliasing::Fxaa {
                edge_threshold,
                edge_threshold_min,
                subpixel,
                search_steps,
            } => [edge_threshold, edge_threshold_min, subpixel, search_steps as f32],
            AntiAliasing::Mlaa {
                threshold,
                max_search,
            } => [threshold, max_search as f32, 0.0, 0.0],
            AntiAliasing::Taa { blend, clamp, .. } => {
                let mode = match clamp {
                    TaaClamp::None => 0.0,
                    TaaClamp::Aabb => 1.0,
                    TaaClamp::Clip => 2.0,
                };
                [blend, 1.0, mode, 0.0]
            }
            _ => return None,
        };
        let base = PostParams {
            size: [w, h, 1.0 / w, 1.0 / h],
            p0,
            ..PostParams::zeroed()
        };
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("post-process parameters"),
            contents: bytemuck::bytes_of(&base),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let colour = &targets.output_views[0];
        let group = |label: &str, inputs: [&wgpu::TextureView; 3]| {
            let mut entries = view_entries(inputs, 0);
            entries.push(wgpu::BindGroupEntry {
                binding: 3,
                resource: params.as_entire_binding(),
            });
            entries.push(wgpu::BindGroupEntry {
                binding: 4,
                resource: taps.as_entire_binding(),
            });
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &pipelines.layout,
                entries: &entries,
            })
        };
        let result = image(device, "post-process result", targets);
        let result_view = view(&result);
        let pass = |entry, bind_group, target| PostPass {
            entry,
            pipeline: pipelines.get(device, entry, false),
            bind_group,
            target,
        };
        let (passes, history) = match aa {
            AntiAliasing::Fxaa { .. } => (
                vec![pass(
                    Entry::Fxaa,
                    group("FXAA inputs", [colour, colour, colour]),
                    result_view,
                )],
                None,
            ),
            AntiAliasing::Mlaa { .. } => {
                let edges = view(&image(device, "MLAA edges", targets));
                let weights = view(&image(device, "MLAA blend weights", targets));
                let passes = vec![
                    pass(
                        Entry::MlaaEdges,
                        group("MLAA edge inputs", [colour, colour, colour]),
                        edges.clone(),
                    ),
                    pass(
                        Entry::MlaaWeights,
                        group("MLAA weight inputs", [colour, &edges, colour]),
                        weights.clone(),
                    ),
                    pass(
                        Entry::MlaaBlend,
                        group("MLAA blend inputs", [colour, &weights, colour]),
                        result_view,
                    ),
                ];
                (passes, None)
            }
            _ => {
                let history = image(device, "TAA history", targets);
                let passes = vec![pass(
                    Entry::Taa,
                    group("TAA inputs", [colour, &targets.output_views[1], &view(&history)]),
                    result_view,
                )];
                (passes, Some(history))
            }
        };
        Some(PostProcess {
            passes,
            result,
            history,
            params,
            base,
        })
    }

    /// Writes TAA's parameters for one frame seen from `camera` after `previous` (the
    /// previous frame's, unjittered) on a `w`×`h` film with near plane `near`; `first`: no
    /// history yet.
    pub(crate) fn set_taa_frame(
        &self,
        queue: &wgpu::Queue,
        first: bool,
        camera: &Camera,
        previous: &Camera,
        (w, h): (u32, u32),
        near: f32,
    ) {
        let m = camera.to_world.matrix3;
        let p = PostParams {
            p0: [
                self.base.p0[0],
                if first { 1.0 } else { 0.0 },
                self.base.p0[2],
                self.base.p0[3],
            ],
            prev_view_proj: view_proj(previous, w, h, near, Vec2::ZERO).to_cols_array_2d(),
            cam_pos: vec4(camera.position(), near),
            cam_x: vec4(m.x_axis.into(), 0.0),
            cam_y: vec4(m.y_axis.into(), 0.0),
            cam_z: vec4(m.z_axis.into(), 0.0),
            cam_forward: vec4(camera.forward(), 0.0),
            film: [
                w as f32,
                h as f32,
                (camera.fov_y_deg.to_radians() * 0.5).tan(),
                w as f32 / h as f32,
            ],
            ..self.base
        };
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
    }

    /// Records the passes, each with the pipeline `pipeline_of` gives it, timed together as
    /// one entry.
    fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        queries: Option<(&Timestamps, u32)>,
        pipeline_of: impl Fn(&PostPass) -> Arc<wgpu::RenderPipeline>,
    ) {
        let last = self.passes.len() - 1;
        for (i, pass) in self.passes.iter().enumerate() {
            let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &cleared_attachments([&pass.target]),
                depth_stencil_attachment: None,
                timestamp_writes: queries.and_then(|(q, k)| q.span_writes(k, i == 0, i == last)),
                occlusion_query_set: None,
            });
            rp.set_pipeline(&pipeline_of(pass));
            rp.set_bind_group(0, &pass.bind_group, &[]);
            rp.draw(0..3, 0..1);
        }
    }

    /// Records the passes (timed together as one entry) and the copies of the result.
    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets,
        label: &str,
        queries: Option<(&Timestamps, u32)>,
    ) {
        self.draw(encoder, label, queries, |p| p.pipeline.clone());
        let size = wgpu::Extent3d {
            width: targets.width,
            height: targets.height,
            depth_or_array_layers: 1,
        };
        let copy_to = |encoder: &mut wgpu::CommandEncoder, dst: &wgpu::Texture| {
            encoder.copy_texture_to_texture(self.result.as_image_copy(), dst.as_image_copy(), size);
        };
        copy_to(encoder, &targets.outputs[0]);
        if let Some(history) = &self.history {
            copy_to(encoder, history);
        }
    }
}

/// The MSAA resolve of `targets.msaa` into the outputs.
struct Resolve {
    pipeline: Arc<wgpu::RenderPipeline>,
    bind_group: wgpu::BindGroup,
}

impl Resolve {
    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets,
        label: &str,
        queries: Option<(&Timestamps, u32)>,
        pipeline: &wgpu::RenderPipeline,
    ) {
        let color = cleared_attachments(&targets.output_views);
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &color,
            depth_stencil_attachment: None,
            timestamp_writes: queries.map(|(q, k)| q.writes(k)),
            occlusion_query_set: None,
        });
        rp.set_pipeline(pipeline);
        rp.set_bind_group(0, &self.bind_group, &[]);
        rp.draw(0..3, 0..1);
    }
}

/// The anti-aliasing passes of one render after its shading: the MSAA resolve (when the
/// targets are multisampled) and the post-process (FXAA, MLAA, TAA), either or none.
pub(crate) struct AntiAliasPasses {
    resolve: Option<Resolve>,
    post: Option<PostProcess>,
    /// Texel loads of the counting run, one counter per target row.
    taps: wgpu::Buffer,
}

impl AntiAliasPasses {
    /// The passes of `aa` over `targets`.
    pub(crate) fn new(
        device: &wgpu::Device,
        pipelines: &PostPipelines,
        aa: &AntiAliasing,
        targets: &Targets,
    ) -> AntiAliasPasses {
        let taps = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("post-process taps (per target row)"),
            size: 4 * u64::from(targets.height.max(1)),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        // Deferred MSAA needs no resolve: its lighting pass averages the samples.
        let forward_msaa = targets.msaa.as_ref().filter(|m| m.gbuffer_bind_group.is_none());
        let resolve = forward_msaa.map(|msaa| {
            let mut entries = view_entries(&msaa.views, 0);
            entries.push(wgpu::BindGroupEntry {
                binding: 4,
                resource: taps.as_entire_binding(),
            });
            Resolve {
                pipeline: pipelines.get(device, Entry::MsaaResolve, false),
                bind_group: device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("MSAA resolve inputs"),
                    layout: &pipelines.resolve_layout,
                    entries: &entries,
                }),
            }
        });
        let post = PostProcess::new(device, pipelines, aa, targets, &taps);
        AntiAliasPasses { resolve, post, taps }
    }

    /// Records the counting run: the resolve and the post-process once more, each pass
    /// compiled with `COUNT_TAPS`, counting its texel loads into the buffer it returns (one u32
    /// per target row) — without copying a result anywhere, so the image and TAA's history
    /// stay as the last frame left them. None without any pass.
    pub(crate) fn encode_tap_count(
        &self,
        device: &wgpu::Device,
        pipelines: &PostPipelines,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets,
    ) -> Option<&wgpu::Buffer> {
        if self.resolve.is_none() && self.post.is_none() {
            return None;
        }
        encoder.clear_buffer(&self.taps, 0, None);
        if let Some(r) = &self.resolve {
            let counting = pipelines.get(device, Entry::MsaaResolve, true);
            r.encode(encoder, targets, "MSAA resolve (counting taps)", None, &counting);
        }
        if let Some(p) = &self.post {
            p.draw(encoder, "post-process (counting taps)", None, |pass| {
                pipelines.get(device, pass.entry, true)
            });
        }
        Some(&self.taps)
    }

    /// Whether there is a resolve pass.
    pub(crate) fn resolves(&self) -> bool {
        self.resolve.is_some()
    }

    /// Whether there is a post-process.
    pub(crate) fn post_processes(&self) -> bool {
        self.post.is_some()
    }

    /// The post-process, if any (TAA's per-frame parameters are written through it).
    pub(crate) fn post(&self) -> Option<&PostProcess> {
        self.post.as_ref()
    }

    /// Records the resolve (if any) as the pass `label`.
    pub(crate) fn encode_resolve(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets,
        label: &str,
        queries: Option<(&Timestamps, u32)>,
    ) {
        if let Some(r) = &self.resolve {
            r.encode(encoder, targets, label, queries, &r.pipeline);
        }
    }

    /// Records the post-process (if any) as the pass `label`.
    pub(crate) fn encode_post(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets,
        label: &str,
        queries: Option<(&Timestamps, u32)>,
    ) {
        if let Some(p) = &self.post {
            p.encode(encoder, targets, label, queries);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every technique's module parses and validates on its own, as the device will see it.
    #[test]
    fn each_technique_module_validates() {
        for entry in [Entry::Fxaa, Entry::MlaaEdges, Entry::Taa, Entry::MsaaResolve] {
            let source = entry.source();
            let module = naga::front::wgsl::parse_str(&source)
                .unwrap_or_else(|e| panic!("{entry:?}: {}", e.emit_to_string(&source)));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::all(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{entry:?}: {}", e.emit_to_string(&source)));
            assert!(
                module.entry_points.iter().any(|e| e.name == entry.fragment()),
                "{entry:?}"
            );
        }
        // The uniform Rust uploads has its WGSL twin's size.
        let source = Entry::Fxaa.source();
        let module = naga::front::wgsl::parse_str(&source).expect("parsed above");
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).expect("layout");
        let (handle, _) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("PostParams"))
            .expect("WGSL PostParams");
        assert_eq!(layouter[handle].size as usize, std::mem::size_of::<PostParams>());
    }
}
