//! The shader module, its bind group layouts and the render pipelines, created lazily and
//! cached per `Key` (the stage and the method's named override constants) — lavapipe compiles each with
//! LLVM, so a pipeline is built once per process, not once per frame or render. Each pipeline's module
//! is the shading module specialised for its entry points and constants (specialize.rs), and
//! keys whose specialised modules are equal share one pipeline.
//!
//! | pipeline | vertex | fragment | targets | depth |
//! |---|---|---|---|---|
//! | forward mesh | `vs_mesh` | `fs_mesh_forward` | colour, normal+depth, albedo+id | Greater, write |
//! | forward analytic | `vs_analytic` | `fs_analytic_forward` | same | Greater, write (frag_depth) |
//! | background | `vs_fullscreen` | `fs_background` | same | GreaterEqual against 0, no write (drawn first) |
//! | G-buffer mesh | `vs_mesh` | `fs_mesh_gbuffer` | G0, G1, G2 | Greater, write |
//! | G-buffer analytic | `vs_analytic` | `fs_analytic_gbuffer` | G0, G1, G2 | Greater, write (frag_depth) |
//! | lighting | `vs_fullscreen` | `fs_lighting` | colour, normal+depth, albedo+id | none |
//! | shadow mesh | `vs_shadow_mesh` | none (depth only) | none | Less, write (standard Z) |
//! | shadow analytic | `vs_shadow_analytic` | `fs_shadow_analytic` | none | Less, write (frag_depth) |
//! | visibility AOV | `vs_fullscreen_chunk` | `fs_visibility` | none (storage writes) | Always, no write |
//!
//! Every target is Rgba32Float; depth is Depth32Float, reversed-Z, cleared to 0; shadow maps
//! are Depth32Float layers, standard Z, cleared to 1.
//!
//! Bind groups: 0 the scene (and the shadow uniform), 1 the G-buffer (lighting; with the AOV
//! buffer for the visibility AOV; an empty group for the geometry pipelines), 2 the shadow maps
//! and their comparison samplers (every shading pipeline; a placeholder when unshadowed), 3 the
//! environment maps (the geometry and lighting pipelines; a placeholder without an
//! environment-mapping method). The shadow pass binds group 0 only: its maps cannot be bound
//! while it renders them. The environment-map filters are compute pipelines of their own
//! module (envmap/build.rs).
//!
//! The counting variant (the module with `counters_on.wgsl`) is used for the lighting pipeline
//! of the counting frame only: after a G-buffer pass it shades each visible sample once.

use std::sync::Arc;

use crate::built_once::BuiltOnce;

use crate::gpu_types::{AnalyticVertex, MeshVertex};
use crate::specialize::ShaderIr;
use crate::technique::shadow::Shadow;
use crate::technique::texture::{self as texture_filter, Filter};
use crate::technique::{self, Applies, Method, Override};

/// Forward shading or deferred shading (G-buffer + lighting pass).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum PipelineKind {
    /// Shade in the geometry pass.
    #[default]
    Forward,
    /// Write a G-buffer, then shade in a full-screen lighting pass.
    Deferred,
}

impl PipelineKind {
    /// `forward` or `deferred`.
    pub fn name(self) -> &'static str {
        match self {
            PipelineKind::Forward => "forward",
            PipelineKind::Deferred => "deferred",
        }
    }
}

pub use crate::gpu::{COLOR_FORMAT, DEPTH_FORMAT};

/// The shading module's own WGSL, shared by every method (the families' files join it,
/// [`crate::technique::Family::shading_sources`]); WGSL has no includes, so they form one module,
/// with `counters_on.wgsl` or `counters_off.wgsl` appended.
const SHADER_SOURCES: &[(&str, &str)] = &[
    ("common.wgsl", include_str!("../shaders/common.wgsl")),
    ("texture.wgsl", include_str!("../shaders/texture.wgsl")),
    ("surface.wgsl", include_str!("../shaders/surface.wgsl")),
    ("bsdf.wgsl", include_str!("../shaders/bsdf.wgsl")),
    (
        "lights_punctual.wgsl",
        include_str!("../shaders/lights_punctual.wgsl"),
    ),
    ("environment.wgsl", include_str!("../shaders/environment.wgsl")),
    ("projection.wgsl", include_str!("../shaders/projection.wgsl")),
    ("shade.wgsl", include_str!("../shaders/shade.wgsl")),
    ("passes.wgsl", include_str!("../shaders/passes.wgsl")),
];

/// The whole shader module's source, with or without the cost counters, for the texture
/// filter `filter`: the method codes ([`technique::wgsl_codes`]), the filter's dispatch
/// ([`Filter::wgsl_dispatch`]), then the files.
pub fn shader_source(counters: bool, filter: Filter) -> String {
    let tail = if counters {
        ("counters_on.wgsl", include_str!("../shaders/counters_on.wgsl"))
    } else {
        ("counters_off.wgsl", include_str!("../shaders/counters_off.wgsl"))
    };
    let families = technique::FAMILIES.iter().flat_map(|f| f.shading_sources());
    let sources: String = SHADER_SOURCES
        .iter()
        .chain(families)
        .chain([&tail])
        .map(|(name, src)| format!("// ---- {name} ----\n{src}\n"))
        .collect();
    technique::wgsl_codes() + &filter.wgsl_dispatch() + &sources
}

/// Which pipeline.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Forward shading of meshes.
    ForwardMesh,
    /// Forward shading of analytic shapes.
    ForwardAnalytic,
    /// Environment where the forward pass drew nothing.
    Background,
    /// G-buffer of meshes.
    GBufferMesh,
    /// G-buffer of analytic shapes.
    GBufferAnalytic,
    /// Deferred lighting (and background).
    Lighting,
    /// Depth of meshes from a light.
    ShadowMesh,
    /// Depth of analytic shapes from a light (ray traced on their proxies).
    ShadowAnalytic,
    /// Every light's visibility at every G-buffer sample (the `visibility.*` AOV).
    VisibilityAov,
}

impl Stage {
    fn entry_points(self) -> (&'static str, &'static str) {
        match self {
            Stage::ForwardMesh => ("vs_mesh", "fs_mesh_forward"),
            Stage::ForwardAnalytic => ("vs_analytic", "fs_analytic_forward"),
            Stage::Background => ("vs_fullscreen", "fs_background"),
            Stage::GBufferMesh => ("vs_mesh", "fs_mesh_gbuffer"),
            Stage::GBufferAnalytic => ("vs_analytic", "fs_analytic_gbuffer"),
            Stage::Lighting => ("vs_fullscreen", "fs_lighting"),
            Stage::ShadowMesh => ("vs_shadow_mesh", ""),
            Stage::ShadowAnalytic => ("vs_shadow_analytic", "fs_shadow_analytic"),
            Stage::VisibilityAov => ("vs_fullscreen_chunk", "fs_visibility"),
        }
    }

    /// Whether the stage shades (its overrides matter); the others are built once.
    fn shades(self) -> bool {
        matches!(
            self,
            Stage::ForwardMesh | Stage::ForwardAnalytic | Stage::Lighting | Stage::VisibilityAov
        )
    }

    /// A shadow-pass stage (depth from a light).
    pub fn is_shadow(self) -> bool {
        matches!(self, Stage::ShadowMesh | Stage::ShadowAnalytic)
    }

    /// The depth test and write of the stage's pipeline: reversed-Z (greater is nearer) for the
    /// camera's passes, the background only where nothing was drawn, conventional Z (less) in
    /// the shadow pass, none in the lighting pass.
    fn depth_stencil(self) -> Option<wgpu::DepthStencilState> {
        let depth = |compare, write| wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: write,
            depth_compare: compare,
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        };
        match self {
            Stage::Lighting => None,
            Stage::Background => Some(depth(wgpu::CompareFunction::GreaterEqual, false)),
            Stage::ShadowMesh | Stage::ShadowAnalytic => Some(depth(wgpu::CompareFunction::Less, true)),
            // A render pass needs an attachment: the G-buffer's depth, untouched.
            Stage::VisibilityAov => Some(depth(wgpu::CompareFunction::Always, false)),
            _ => Some(depth(wgpu::CompareFunction::Greater, true)),
        }
    }

    /// Analytic proxies are wound so that back-face culling keeps one layer; nothing else is culled.
    fn cull_mode(self) -> Option<wgpu::Face> {
        match self {
            Stage::ForwardAnalytic | Stage::GBufferAnalytic | Stage::ShadowAnalytic => Some(wgpu::Face::Back),
            _ => None,
        }
    }
}

/// Cache key: the stage, whether it is the counting variant, its sample count (MSAA), the
/// texture filter's WGSL code (the filter picks the shader module,
/// [`crate::technique::texture::Filter::wgsl_dispatch`]) and the override constants the stage
/// reads ([`Method::overrides`]: the geometry ones in every stage that draws the view, the
/// shading ones where it shades; none in the shadow pass), by name.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct Key {
    stage: Stage,
    counters: bool,
    samples: u32,
    filter: u32,
    overrides: Vec<Override>,
}

/// Layouts, the shader module and the pipeline cache.
pub struct Pipelines {
    pub(crate) scene_layout: wgpu::BindGroupLayout,
    pub(crate) gbuffer_layout: wgpu::BindGroupLayout,
    /// Group 1 of the lighting pass under deferred MSAA: the multisampled G-buffer (bindings 3–5).
    pub(crate) gbuffer_msaa_layout: wgpu::BindGroupLayout,
    /// Group 1 of the visibility AOV pass: the G-buffer, the AOV buffer, its dimensions.
    pub(crate) aov_layout: wgpu::BindGroupLayout,
    /// Group 2: the shadow-map array and its comparison samplers.
    pub(crate) shadow_layout: wgpu::BindGroupLayout,
    /// Group 3: the environment maps (envmap/envmap.wgsl).
    pub(crate) envmap_layout: wgpu::BindGroupLayout,
    /// The empty group 1 of the geometry pipelines.
    pub(crate) empty_bind_group: wgpu::BindGroup,
    forward_layout: wgpu::PipelineLayout,
    lighting_layout: wgpu::PipelineLayout,
    lighting_msaa_layout: wgpu::PipelineLayout,
    aov_pipeline_layout: wgpu::PipelineLayout,
    shadow_pass_layout: wgpu::PipelineLayout,
    /// The shading module's IR by (counting, texture filter code), parsed when first needed
    /// and specialised per pipeline (specialize.rs).
    modules: BuiltOnce<(bool, u32), ShaderIr>,
    cache: BuiltOnce<Key, wgpu::RenderPipeline>,
    /// The same pipelines by what the driver compiles: (stage, samples, the specialised
    /// module). Keys that differ only in constants a pipeline never reads (the background's
    /// area method, the visibility pass's every method) specialise to one module and share
    /// one pipeline.
    by_code: BuiltOnce<(Stage, u32, String), wgpu::RenderPipeline>,
}

/// A storage buffer: read-only ones are visible to the vertex stage too (the vertex-lit
/// shading frequencies shade there), writable ones to fragments only.
fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: if read_only {
            wgpu::ShaderStages::VERTEX_FRAGMENT
        } else {
            wgpu::ShaderStages::FRAGMENT
        },
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn layout_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty,
        count: None,
    }
}

/// The pipeline of a full-screen pass: entry points `vs` and `fs` of `module`, no vertex
/// buffers, no depth, one sample, one target per format written whole without blending, and
/// the pipeline-overridable `constants` (the anti-aliasing and SSAO passes).
pub(crate) fn fullscreen_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    (vs, fs): (&str, &str),
    formats: &[wgpu::TextureFormat],
    constants: &[(&str, f64)],
) -> wgpu::RenderPipeline {
    let options = wgpu::PipelineCompilationOptions {
        constants,
        zero_initialize_workgroup_memory: false,
    };
    let targets: Vec<_> = formats
        .iter()
        .map(|&format| {
            Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })
        })
        .collect();
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vs),
            compilation_options: options.clone(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fs),
            compilation_options: options,
            targets: &targets,
        }),
        multiview: None,
        cache: None,
    })
}

/// A 2D texture of unfilterable floats (the Rgba32Float targets: read with textureLoad).
pub(crate) fn unfilterable_texture(
    binding: u32,
    visibility: wgpu::ShaderStages,
    multisampled: bool,
) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        visibility,
        wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled,
        },
    )
}

fn uniform_type() -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

fn bind_group_layout(
    device: &wgpu::Device,
    label: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    })
}

fn pipeline_layout(
    device: &wgpu::Device,
    label: &str,
    groups: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: groups,
        push_constant_ranges: &[],
    })
}

/// Group 2: the shadow maps (a depth array) with their comparison samplers (shadow/maps.rs).
fn shadow_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    // The vertex-lit shading frequencies shade in the vertex stage too.
    let shading = wgpu::ShaderStages::VERTEX_FRAGMENT;
    let comparison = wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison);
    bind_group_layout(
        device,
        "shadow map bind group layout",
        &[
            layout_entry(
                0,
                shading,
                wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
            ),
            layout_entry(1, shading, comparison),
            layout_entry(2, shading, comparison),
        ],
    )
}

/// Group 3: the environment maps (envmap/build.rs `bind_maps` lists what each binding holds).
fn envmap_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    // The vertex-lit shading frequencies shade in the vertex stage too.
    let shading = wgpu::ShaderStages::VERTEX_FRAGMENT;
    let texture = |binding, view_dimension| {
        layout_entry(
            binding,
            shading,
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension,
                multisampled: false,
            },
        )
    };
    let cube = wgpu::TextureViewDimension::Cube;
    let array = wgpu::TextureViewDimension::D2Array;
    bind_group_layout(
        device,
        "environment map bind group layout",
        &[
            texture(0, cube),
            texture(1, array),
            texture(2, cube),
            texture(3, array),
            layout_entry(
                4,
                shading,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            ),
            storage_entry(5, true),
            layout_entry(6, shading, uniform_type()),
            texture(7, cube),
            texture(8, wgpu::TextureViewDimension::CubeArray),
        ],
    )
}

impl Pipelines {
    /// Compiles the shader module (validation errors come back from the caller's error scope).
    pub fn new(device: &wgpu::Device) -> Pipelines {
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let mut scene_entries = vec![layout_entry(0, vf, uniform_type())];
        scene_entries.extend((1..=6).map(|b| storage_entry(b, true)));
        scene_entries.push(storage_entry(7, false));
        // The shadow uniform: settings, taps and every light's frustum (shadow/maps.rs).
        scene_entries.push(layout_entry(8, vf, uniform_type()));
        // `tex_anisotropic`'s texture array and its samplers (repeat, clamp, mirror).
        scene_entries.push(layout_entry(
            9,
            vf,
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2Array,
                multisampled: false,
            },
        ));
        scene_entries.extend((10..13).map(|b| {
            layout_entry(
                b,
                vf,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            )
        }));
        let scene_layout = bind_group_layout(device, "scene bind group layout", &scene_entries);
        let gbuffer_entries: Vec<_> = (0..3).map(|b| unfilterable_texture(b, vf, false)).collect();
        // The lighting's group 1 adds the SSAO obscurance (binding 6) to the three layers.
        let mut lighting_entries = gbuffer_entries.clone();
        lighting_entries.push(unfilterable_texture(6, vf, false));
        let gbuffer_layout = bind_group_layout(device, "G-buffer bind group layout", &lighting_entries);
        let gbuffer_msaa_entries: Vec<_> = (3..6).map(|b| unfilterable_texture(b, vf, true)).collect();
        let gbuffer_msaa_layout = bind_group_layout(
            device,
            "multisampled G-buffer bind group layout",
            &gbuffer_msaa_entries,
        );
        let mut aov_entries = gbuffer_entries.clone();
        aov_entries.push(storage_entry(3, false));
        aov_entries.push(layout_entry(4, vf, uniform_type()));
        let aov_layout = bind_group_layout(device, "visibility AOV bind group layout", &aov_entries);
        let shadow_layout = shadow_group_layout(device);
        let envmap_layout = envmap_group_layout(device);
        let empty_layout = bind_group_layout(device, "empty bind group layout", &[]);
        let empty_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("empty bind group (group 1 of the geometry pipelines)"),
            layout: &empty_layout,
            entries: &[],
        });
        let forward_layout = pipeline_layout(
            device,
            "geometry pipeline layout",
            &[&scene_layout, &empty_layout, &shadow_layout, &envmap_layout],
        );
        let lighting_layout = pipeline_layout(
            device,
            "lighting pipeline layout",
            &[&scene_layout, &gbuffer_layout, &shadow_layout, &envmap_layout],
        );
        let lighting_msaa_layout = pipeline_layout(
            device,
            "lighting pipeline layout (multisampled G-buffer)",
            &[
                &scene_layout,
                &gbuffer_msaa_layout,
                &shadow_layout,
                &envmap_layout,
            ],
        );
        let aov_pipeline_layout = pipeline_layout(
            device,
            "visibility AOV pipeline layout",
            &[&scene_layout, &aov_layout, &shadow_layout],
        );
        let shadow_pass_layout = pipeline_layout(device, "shadow pass pipeline layout", &[&scene_layout]);
        Pipelines {
            scene_layout,
            gbuffer_layout,
            gbuffer_msaa_layout,
            aov_layout,
            shadow_layout,
            envmap_layout,
            empty_bind_group,
            forward_layout,
            lighting_layout,
            lighting_msaa_layout,
            aov_pipeline_layout,
            shadow_pass_layout,
            modules: BuiltOnce::new(),
            cache: BuiltOnce::new(),
            by_code: BuiltOnce::new(),
        }
    }

    /// The stages one frame of `method` draws under `pipeline`, in pass order, each with the
    /// samples per pixel its pipeline draws: the shadow pass's (under a shadow method), then
    /// the forward or the deferred ones, the geometry pass's drawing `samples` samples per
    /// pixel.
    pub(crate) fn frame_stages(method: &Method, pipeline: PipelineKind, samples: u32) -> Vec<(Stage, u32)> {
        let shadow: &[Stage] = if method.get::<Shadow>().is_some() {
            &[Stage::ShadowMesh, Stage::ShadowAnalytic]
        } else {
            &[]
        };
        // The forward pass draws the background first, over every pixel (its depth test passes
        // where nothing is drawn yet: all of them), and the scene over it: the same image as
        // drawing it last where the depth stayed 0. Drawn in that order because lavapipe (Mesa
        // 22.3.6) kept about 16 MB per frame, whatever the resolution, whenever a render pass's
        // first draw wrote frag_depth (the analytic shapes' pipeline, first in scenes without
        // meshes): a 200-render study of soft-shadow.toml peaked at 4.2 GB, now 0.72 GB
        // (compare/tests/report_memory.rs; issue 26).
        let list: &[Stage] = match pipeline {
            PipelineKind::Forward => &[Stage::Background, Stage::ForwardMesh, Stage::ForwardAnalytic],
            PipelineKind::Deferred => &[Stage::GBufferMesh, Stage::GBufferAnalytic, Stage::Lighting],
        };
        shadow
            .iter()
            .chain(list)
            .map(|&s| (s, if s.is_shadow() { 1 } else { samples }))
            .collect()
    }

    /// The pipelines one frame of `method` draws with under `pipeline`, in pass order
    /// ([`Pipelines::frame_stages`]).
    pub(crate) fn stages(
        &self,
        device: &wgpu::Device,
        method: &Method,
        pipeline: PipelineKind,
        counters: bool,
        samples: u32,
    ) -> Vec<(Stage, Arc<wgpu::RenderPipeline>)> {
        Self::frame_stages(method, pipeline, samples)
            .into_iter()
            .map(|(s, n)| (s, self.get_multisampled(device, s, method, counters, n)))
            .collect()
    }

    /// Builds the pipelines of `requests` (stage, counting variant, samples per pixel) for
    /// `method` that are not built yet, at once on as many threads as there are cores, so
    /// that a render's later [`Pipelines::get`] calls find them. A GPU driver compiles a
    /// pipeline on the thread that creates it (lavapipe only translates SPIR-V to NIR there;
    /// LLVM compiles on its queue thread at the first draw), and a render of a new method
    /// needs several: its shading passes, the counting frame's lighting, the G-buffer of its
    /// AOV passes.
    pub(crate) fn prepare(&self, device: &wgpu::Device, method: &Method, requests: &[(Stage, bool, u32)]) {
        let mut missing: Vec<Key> = Vec::new();
        for &(stage, counters, samples) in requests {
            let key = Self::key(stage, method, counters, samples);
            if !self.cache.contains(&key) && !missing.contains(&key) {
                missing.push(key);
            }
        }
        let workers = std::thread::available_parallelism()
            .map_or(1, |n| n.get())
            .min(missing.len());
        if workers <= 1 {
            return;
        }
        let next = std::sync::atomic::AtomicUsize::new(0);
        std::thread::scope(|scope| {
            for _ in 0..workers {
                scope.spawn(|| {
                    while let Some(key) = missing.get(next.fetch_add(1, std::sync::atomic::Ordering::Relaxed))
                    {
                        self.get_key(device, key);
                    }
                });
            }
        });
    }

    /// The pipeline for `stage` with `method`, the counting variant or not, built on first use.
    /// Stages that do not shade ignore the shadow method (and the shadow pass the area method
    /// and counters too), so they are built once.
    pub fn get(
        &self,
        device: &wgpu::Device,
        stage: Stage,
        method: &Method,
        counters: bool,
    ) -> Arc<wgpu::RenderPipeline> {
        self.get_multisampled(device, stage, method, counters, 1)
    }

    /// [`Pipelines::get`] drawing `samples` samples per pixel.
    fn get_multisampled(
        &self,
        device: &wgpu::Device,
        stage: Stage,
        method: &Method,
        counters: bool,
        samples: u32,
    ) -> Arc<wgpu::RenderPipeline> {
        self.get_key(device, &Self::key(stage, method, counters, samples))
    }

    /// The pipeline cache's key of `stage` with `method`.
    fn key(stage: Stage, method: &Method, counters: bool, samples: u32) -> Key {
        if stage.is_shadow() {
            return Key {
                stage,
                counters: false,
                samples: 1,
                filter: 0,
                overrides: Vec::new(),
            };
        }
        let applies = if stage.shades() {
            Applies::Shading
        } else {
            Applies::Geometry
        };
        Key {
            stage,
            counters,
            samples,
            filter: texture_filter::of(method).filter.shader_code(),
            overrides: method.overrides(applies),
        }
    }

    /// The pipeline of `key`, built on first use. The cache is not locked while the driver
    /// compiles, so that [`Pipelines::prepare`]'s threads compile side by side; two threads
    /// after the same key both build it and the first one stored is kept.
    fn get_key(&self, device: &wgpu::Device, key: &Key) -> Arc<wgpu::RenderPipeline> {
        if let Some(p) = self.cache.get(key) {
            return p;
        }
        let built = self.build(device, key);
        self.cache.keep_first(key.clone(), built)
    }

    /// The shading module's IR with or without counters for the texture filter of WGSL code
    /// `filter`.
    fn module(&self, counters: bool, filter: u32) -> Arc<ShaderIr> {
        self.modules.get_or_build(&(counters, filter), || {
            let f = (texture_filter::METHODS[filter as usize].default)().filter;
            ShaderIr::parse(&shader_source(counters, f))
                .unwrap_or_else(|e| panic!("Verity's shading module does not validate: {e}"))
        })
    }

    fn build(&self, device: &wgpu::Device, key: &Key) -> Arc<wgpu::RenderPipeline> {
        let Key {
            stage,
            counters,
            samples,
            filter,
            ref overrides,
        } = *key;
        let value = |name: &str| overrides.iter().find(|o| o.name == name).map_or(0, |o| o.value);
        // Under deferred MSAA the lighting pass reads `samples` G-buffer samples per pixel
        // and writes one: its own pipeline is single-sampled.
        let msaa_lighting = stage == Stage::Lighting && samples > 1;
        // Vertex-lit shading frequencies light the forward pass's meshes in the vertex stage.
        let (vs, fs) = if msaa_lighting {
            ("vs_fullscreen", "fs_lighting_msaa")
        } else if stage == Stage::ForwardMesh && value("SHADING_FREQUENCY") != 0 {
            ("vs_mesh_vertex_lit", "fs_mesh_vertex_lit")
        } else {
            stage.entry_points()
        };
        let named: Vec<String> = overrides
            .iter()
            .map(|o| format!("{}={}", o.name, o.value))
            .collect();
        let label = format!(
            "{vs}/{fs} (texture filter {filter}, counters {counters}, {samples} samples, {})",
            named.join(", ")
        );
        let constants: Vec<(&str, f64)> = overrides.iter().map(|o| (o.name, f64::from(o.value))).collect();
        let fragment_entry = (!fs.is_empty()).then_some(fs);
        let specialised = self
            .module(counters, filter)
            .specialise(&[vs, fs], &constants)
            .unwrap_or_else(|e| panic!("{label}: the shading module does not specialise: {e}"));
        // The module's debug form is its whole content (types, globals, functions, entry
        // points), so equal strings are equal code.
        let code_key = (stage, samples, format!("{specialised:?}"));
        if let Some(pipeline) = self.by_code.get(&code_key) {
            return pipeline;
        }
        let module = &device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(&label),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(specialised)),
        });
        let options = wgpu::PipelineCompilationOptions {
            constants: &[],
            zero_initialize_workgroup_memory: false,
        };
        let mesh_layout = [wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &MeshVertex::ATTRIBUTES,
        }];
        // The shadow pass reads only the position of the mesh vertex.
        let mesh_position_layout = [wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &MeshVertex::ATTRIBUTES[..1],
        }];
        let analytic_layout = [wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<AnalyticVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &AnalyticVertex::ATTRIBUTES,
        }];
        let buffers: &[wgpu::VertexBufferLayout] = match stage {
            Stage::ForwardMesh | Stage::GBufferMesh => &mesh_layout,
            Stage::ShadowMesh => &mesh_position_layout,
            Stage::ForwardAnalytic | Stage::GBufferAnalytic | Stage::ShadowAnalytic => &analytic_layout,
            Stage::Background | Stage::Lighting | Stage::VisibilityAov => &[],
        };
        let target = Some(wgpu::ColorTargetState {
            format: COLOR_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        });
        let three = [target.clone(), target.clone(), target];
        let targets: &[Option<wgpu::ColorTargetState>] = match stage {
            Stage::ShadowMesh | Stage::ShadowAnalytic | Stage::VisibilityAov => &[],
            _ => &three,
        };
        let layout = match stage {
            Stage::Lighting if msaa_lighting => &self.lighting_msaa_layout,
            Stage::Lighting => &self.lighting_layout,
            Stage::VisibilityAov => &self.aov_pipeline_layout,
            Stage::ShadowMesh | Stage::ShadowAnalytic => &self.shadow_pass_layout,
            _ => &self.forward_layout,
        };
        let fragment = fragment_entry.map(|fs| wgpu::FragmentState {
            module,
            entry_point: Some(fs),
            compilation_options: options.clone(),
            targets,
        });
        let pipeline = Arc::new(device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(vs),
                compilation_options: options.clone(),
                buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: stage.cull_mode(),
                ..Default::default()
            },
            depth_stencil: stage.depth_stencil(),
            multisample: wgpu::MultisampleState {
                count: if msaa_lighting { 1 } else { samples },
                ..Default::default()
            },
            fragment,
            multiview: None,
            cache: None,
        }));
        self.by_code.keep_first(code_key, pipeline)
    }
}

#[cfg(test)]
mod tests {
    use std::mem::size_of;

    use super::*;
    use crate::gpu_types::*;
    use crate::technique::envmap::build::{EnvMapUniforms, LOCAL_PEEL};
    use crate::technique::envmap::filter::FilterParams;
    use crate::technique::envmap::localization::Localization;
    use crate::technique::envmap::Irradiance;
    use crate::technique::shadow::maps::{GpuShadowLight, GpuShadowSettings, GpuShadowUniforms};
    use crate::visibility::GpuAovInfo;

    /// Both shader modules' sources in one naga module (the filters' module is the shading
    /// sources plus envmap/filter.wgsl).
    fn module() -> naga::Module {
        let source = shader_source(false, Filter::Bilinear) + include_str!("technique/envmap/filter.wgsl");
        naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)))
    }

    /// Every struct Rust uploads has the size WGSL's layout rules give its WGSL twin, so no
    /// field can be added on one side only.
    #[test]
    fn uploaded_structs_have_their_wgsl_size() {
        let module = module();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let wgsl_size = |name: &str| {
            let (handle, _) = module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("no WGSL struct {name}"));
            layouter[handle].size as usize
        };
        let families = technique::family_uniform_bytes(&Method::default()).len();
        for (name, rust) in [
            ("FrameUniforms", size_of::<FrameUniforms>() + families),
            ("Shape", size_of::<GpuShape>()),
            ("Material", size_of::<GpuMaterial>()),
            ("Light", size_of::<GpuLight>()),
            ("TextureInfo", size_of::<GpuTextureInfo>()),
            ("ShadowLight", size_of::<GpuShadowLight>()),
            ("ShadowSettings", size_of::<GpuShadowSettings>()),
            ("ShadowUniforms", size_of::<GpuShadowUniforms>()),
            ("EnvMapUniforms", size_of::<EnvMapUniforms>()),
            ("FilterParams", size_of::<FilterParams>()),
            ("AovInfo", size_of::<GpuAovInfo>()),
        ] {
            assert_eq!(
                wgsl_size(name),
                rust,
                "WGSL {name} and its Rust twin differ in size"
            );
        }
    }

    /// Each family's block of the frame uniform has its WGSL struct's size, and sits in WGSL's
    /// `FamilyUniforms` (after the core fields) where technique::family_uniform_bytes writes it.
    #[test]
    fn family_uniform_blocks_sit_where_rust_writes_them() {
        let module = module();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let named = |name: &str| {
            module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("no WGSL struct {name}"))
        };
        let members = |name: &str| match &named(name).1.inner {
            naga::TypeInner::Struct { members, .. } => members.clone(),
            other => panic!("{name} is not a struct: {other:?}"),
        };
        let frame = members("FrameUniforms");
        let families = frame
            .iter()
            .find(|m| m.name.as_deref() == Some("families"))
            .unwrap();
        assert_eq!(families.offset as usize, size_of::<FrameUniforms>());
        let blocks: Vec<_> = technique::uniform_blocks().collect();
        let wgsl = members("FamilyUniforms");
        assert_eq!(wgsl.len(), blocks.len());
        let mut offset = 0;
        for (block, member) in blocks.iter().zip(&wgsl) {
            assert_eq!(member.name.as_deref(), Some(block.field));
            assert_eq!(member.offset as usize, offset, "{}", block.field);
            assert_eq!(
                layouter[named(block.wgsl_type).0].size as usize,
                block.size,
                "{}",
                block.wgsl_type
            );
            assert_eq!(
                (block.bytes)(&Method::default()).len(),
                block.size,
                "{}",
                block.field
            );
            offset = (offset + block.size).next_multiple_of(16);
        }
        assert_eq!(offset, technique::family_uniform_bytes(&Method::default()).len());
    }

    /// Every integer code Rust writes into a buffer and WGSL compares against is the same on
    /// both sides (the method codes are generated; these are written in WGSL and checked).
    #[test]
    fn codes_rust_and_wgsl_share_are_equal() {
        let module = module();
        let wgsl = |name: &str| -> u32 {
            let (_, c) = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("no WGSL constant {name}"));
            match module.global_expressions[c.init] {
                naga::Expression::Literal(naga::Literal::U32(v)) => v,
                ref e => panic!("WGSL {name} = {e:?} is not a u32 literal"),
            }
        };
        let search = Localization::Search {
            linear_steps: 1,
            secant_steps: 0,
            layers: 1,
        };
        for (name, rust) in [
            ("NONE", NONE),
            ("SHAPE_MESH", ShapeKind::Mesh as u32),
            ("SHAPE_SPHERE", ShapeKind::Sphere as u32),
            ("SHAPE_RECTANGLE", ShapeKind::Rectangle as u32),
            ("SHAPE_DISK", ShapeKind::Disk as u32),
            ("MAT_DIFFUSE", MaterialKind::Diffuse as u32),
            ("MAT_PHONG", MaterialKind::Phong as u32),
            ("MAT_GGX", MaterialKind::Ggx as u32),
            ("MAT_METAL_ROUGH", MaterialKind::MetalRough as u32),
            ("MAT_MIRROR", MaterialKind::Mirror as u32),
            ("MAT_DIELECTRIC", MaterialKind::Dielectric as u32),
            ("LIGHT_POINT", LightKind::Point as u32),
            ("LIGHT_SPOT", LightKind::Spot as u32),
            ("LIGHT_DIRECTIONAL", LightKind::Directional as u32),
            ("ENV_NONE", EnvKind::None as u32),
            ("ENV_CONSTANT", EnvKind::Constant as u32),
            ("ENV_MAP", EnvKind::Map as u32),
            ("IRRADIANCE_MAP", Irradiance::Map.shader_code()),
            ("IRRADIANCE_SH9", Irradiance::Sh9.shader_code()),
            ("LOCAL_DISTANT", Localization::Distant.shader_info(false)[0]),
            (
                "LOCAL_ITERATIONS",
                Localization::Iterations(1).shader_info(false)[0],
            ),
            ("LOCAL_SEARCH", search.shader_info(false)[0]),
            ("LOCAL_PEEL", LOCAL_PEEL),
            (
                "SHADOW_PCSS",
                crate::ShadowTechnique::Pcss {
                    blocker_samples: 1,
                    filter_samples: 1,
                    light_size: None,
                    blocker_depth: crate::BlockerDepth::Search,
                }
                .shader_code(),
            ),
        ] {
            assert_eq!(wgsl(name), rust, "WGSL {name}");
        }
    }
}
