//! The shader module, its bind group layouts and the render pipelines, created lazily and
//! cached per (entry point, area method, counters) — lavapipe compiles each with LLVM, so a
//! pipeline is built once per process, not once per frame or render.
//!
//! | pipeline | vertex | fragment | targets | depth |
//! |---|---|---|---|---|
//! | forward mesh | `vs_mesh` | `fs_mesh_forward` | colour, normal+depth, albedo+id | Greater, write |
//! | forward analytic | `vs_analytic` | `fs_analytic_forward` | same | Greater, write (frag_depth) |
//! | background | `vs_fullscreen` | `fs_background` | same | GreaterEqual against 0, no write |
//! | G-buffer mesh | `vs_mesh` | `fs_mesh_gbuffer` | G0, G1, G2 | Greater, write |
//! | G-buffer analytic | `vs_analytic` | `fs_analytic_gbuffer` | G0, G1, G2 | Greater, write (frag_depth) |
//! | lighting | `vs_fullscreen` | `fs_lighting` | colour, normal+depth, albedo+id | none |
//!
//! Every target is Rgba32Float; depth is Depth32Float, reversed-Z, cleared to 0.
//!
//! The counting variant (the module with `counters_on.wgsl`) is used for the lighting pipeline
//! of the counting frame only: after a G-buffer pass it shades each visible sample once.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use crate::gpu_types::{AnalyticVertex, MeshVertex};
use crate::method::AreaMethod;

/// Format of every colour target and G-buffer layer.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Depth buffer format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The WGSL sources in dependency order; WGSL has no includes, so they form one module, with
/// `counters_on.wgsl` or `counters_off.wgsl` appended.
const SHADER_SOURCES: [(&str, &str); 10] = [
    ("common.wgsl", include_str!("../shaders/common.wgsl")),
    ("texture.wgsl", include_str!("../shaders/texture.wgsl")),
    ("surface.wgsl", include_str!("../shaders/surface.wgsl")),
    ("bsdf.wgsl", include_str!("../shaders/bsdf.wgsl")),
    (
        "lights_punctual.wgsl",
        include_str!("../shaders/lights_punctual.wgsl"),
    ),
    ("environment.wgsl", include_str!("../shaders/environment.wgsl")),
    (
        "area_quadrature.wgsl",
        include_str!("../shaders/area_quadrature.wgsl"),
    ),
    (
        "area_representative_point.wgsl",
        include_str!("../shaders/area_representative_point.wgsl"),
    ),
    ("shade.wgsl", include_str!("../shaders/shade.wgsl")),
    ("passes.wgsl", include_str!("../shaders/passes.wgsl")),
];

/// The whole shader module's source, with or without the cost counters.
pub fn shader_source(counters: bool) -> String {
    let tail = if counters {
        ("counters_on.wgsl", include_str!("../shaders/counters_on.wgsl"))
    } else {
        ("counters_off.wgsl", include_str!("../shaders/counters_off.wgsl"))
    };
    SHADER_SOURCES
        .iter()
        .chain([&tail])
        .map(|(name, src)| format!("// ---- {name} ----\n{src}\n"))
        .collect()
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
        }
    }
}

/// Cache key: the pipeline, the area method, whether it is the counting variant.
type Key = (Stage, AreaMethod, bool);

/// Layouts, the shader module and the pipeline cache.
pub struct Pipelines {
    pub(crate) scene_layout: wgpu::BindGroupLayout,
    pub(crate) gbuffer_layout: wgpu::BindGroupLayout,
    forward_layout: wgpu::PipelineLayout,
    lighting_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    counting_module: wgpu::ShaderModule,
    cache: Mutex<HashMap<Key, Arc<wgpu::RenderPipeline>>>,
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl Pipelines {
    /// Compiles the shader module (validation errors come back from the caller's error scope).
    pub fn new(device: &wgpu::Device) -> Pipelines {
        let mut scene_entries = vec![wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }];
        scene_entries.extend((1..=6).map(|b| storage_entry(b, true)));
        scene_entries.push(storage_entry(7, false));
        let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scene bind group layout"),
            entries: &scene_entries,
        });
        let gbuffer_entries: Vec<_> = (0..3)
            .map(|b| wgpu::BindGroupLayoutEntry {
                binding: b,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            })
            .collect();
        let gbuffer_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("G-buffer bind group layout"),
            entries: &gbuffer_entries,
        });
        let forward_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("geometry pipeline layout"),
            bind_group_layouts: &[&scene_layout],
            push_constant_ranges: &[],
        });
        let lighting_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lighting pipeline layout"),
            bind_group_layouts: &[&scene_layout, &gbuffer_layout],
            push_constant_ranges: &[],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("verity realtime shaders"),
            source: wgpu::ShaderSource::Wgsl(shader_source(false).into()),
        });
        let counting_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("verity realtime shaders (counting)"),
            source: wgpu::ShaderSource::Wgsl(shader_source(true).into()),
        });
        Pipelines {
            scene_layout,
            gbuffer_layout,
            forward_layout,
            lighting_layout,
            module,
            counting_module,
            cache: Mutex::new(HashMap::new()),
        }
    }

    /// The pipeline for `stage` with `method`, the counting variant or not, built on first use.
    pub fn get(
        &self,
        device: &wgpu::Device,
        stage: Stage,
        method: AreaMethod,
        counters: bool,
    ) -> Arc<wgpu::RenderPipeline> {
        let key = (stage, method, counters);
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        cache
            .entry(key)
            .or_insert_with(|| Arc::new(self.build(device, key)))
            .clone()
    }

    fn build(&self, device: &wgpu::Device, (stage, method, counters): Key) -> wgpu::RenderPipeline {
        let (vs, fs) = stage.entry_points();
        let label = format!("{fs} ({method:?}, counters {counters})");
        let constants = [("AREA_METHOD", f64::from(method.shader_code()))];
        let module = if counters {
            &self.counting_module
        } else {
            &self.module
        };
        let options = wgpu::PipelineCompilationOptions {
            constants: &constants,
            zero_initialize_workgroup_memory: false,
        };
        let mesh_layout = [wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &MeshVertex::ATTRIBUTES,
        }];
        let analytic_layout = [wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<AnalyticVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &AnalyticVertex::ATTRIBUTES,
        }];
        let buffers: &[wgpu::VertexBufferLayout] = match stage {
            Stage::ForwardMesh | Stage::GBufferMesh => &mesh_layout,
            Stage::ForwardAnalytic | Stage::GBufferAnalytic => &analytic_layout,
            Stage::Background | Stage::Lighting => &[],
        };
        let depth = |compare, write| wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: write,
            depth_compare: compare,
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        };
        let depth_stencil = match stage {
            Stage::Lighting => None,
            Stage::Background => Some(depth(wgpu::CompareFunction::GreaterEqual, false)),
            _ => Some(depth(wgpu::CompareFunction::Greater, true)),
        };
        let cull_mode = match stage {
            // Analytic proxies are wound so that back-face culling keeps one layer.
            Stage::ForwardAnalytic | Stage::GBufferAnalytic => Some(wgpu::Face::Back),
            _ => None,
        };
        let target = Some(wgpu::ColorTargetState {
            format: COLOR_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        });
        let layout = match stage {
            Stage::Lighting => &self.lighting_layout,
            _ => &self.forward_layout,
        };
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
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
                cull_mode,
                ..Default::default()
            },
            depth_stencil,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(fs),
                compilation_options: options,
                targets: &[target.clone(), target.clone(), target],
            }),
            multiview: None,
            cache: None,
        })
    }
}
