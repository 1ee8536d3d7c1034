//! One frame's GPU work: the frame uniform and scene bind group, the passes it records (a
//! labelled render pass per stage, debug groups per draw), and the timestamp queries around
//! each pass. Under a shadow method the frame starts with the shadow pass: one depth-only
//! render pass per map layer (`shadow pass: <light>`, or `<light> cascade i/k`), timed
//! together as `shadow pass` (the first one's start to the last one's end).

use std::sync::Arc;

use glam::{Vec2, Vec3};
use scenes::{Camera, Scene};
use wgpu::util::DeviceExt;

use crate::camera::{camera_near, view_proj};
use crate::gpu_types::{vec4, FrameUniforms, NONE};
use crate::pipelines::Stage;
use crate::settings::RasterSettings;
use crate::targets::{cleared_attachments, Targets};
use crate::technique::antialias::post::AntiAliasPasses;
use crate::technique::shadow::maps::ShadowMaps;
use crate::technique::ssao::passes::SsaoPasses;
use crate::technique::{self, energy};
use crate::timestamps::Timestamps;
use crate::upload::SceneGpu;

/// The per-render uniform, counter buffer and scene bind group.
pub(crate) struct Frame {
    pub(crate) bind_group: wgpu::BindGroup,
    pub(crate) counters: wgpu::Buffer,
    uniform: wgpu::Buffer,
}

impl Frame {
    /// The frame of a k·W × k·H render of `scene`; `layout` is the scene bind group layout.
    pub(crate) fn new(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        scene: &Scene,
        sg: &SceneGpu,
        shadow: &ShadowMaps,
        settings: &RasterSettings,
        k: u32,
    ) -> Frame {
        // The fields every method has, then the families' blocks (set once: a frame sequence
        // rewrites only the view, `set_view`).
        let uniforms = frame_uniforms(scene, &scene.camera, Vec2::ZERO, sg, settings, k);
        let mut contents = bytemuck::bytes_of(&uniforms).to_vec();
        contents.extend(technique::family_uniform_bytes(&settings.method));
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame uniforms"),
            contents: &contents,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let counters = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("cost counters (per target row)"),
            size: 8 * u64::from(settings.height * k),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let buffers = [
            &uniform,
            &sg.shapes,
            &sg.materials,
            &sg.lights,
            &sg.emitters,
            &sg.texture_infos,
            &sg.texels,
            &counters,
            &shadow.uniform,
        ];
        let mut entries: Vec<_> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        // The texture array of `tex_anisotropic` (a stand-in otherwise) and its samplers.
        let array = &sg.texture_array;
        entries.push(wgpu::BindGroupEntry {
            binding: 9,
            resource: wgpu::BindingResource::TextureView(&array.view),
        });
        for (k, sampler) in array.samplers.iter().enumerate() {
            entries.push(wgpu::BindGroupEntry {
                binding: 10 + k as u32,
                resource: wgpu::BindingResource::Sampler(sampler),
            });
        }
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene bind group"),
            layout,
            entries: &entries,
        });
        Frame {
            bind_group,
            counters,
            uniform,
        }
    }

    /// Moves the frame's view to `camera`, its samples offset by `jitter` pixels of the final
    /// film (TAA's frames; [`Frame::new`] is the scene's camera, unjittered).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn set_view(
        &self,
        queue: &wgpu::Queue,
        scene: &Scene,
        camera: &Camera,
        jitter: Vec2,
        sg: &SceneGpu,
        settings: &RasterSettings,
        k: u32,
    ) {
        let uniforms = frame_uniforms(scene, camera, jitter, sg, settings, k);
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniforms));
    }
}

/// The camera and counts for a k·W × k·H target (docs/ARCHITECTURE.md "Camera": the projection of
/// `scenes::Camera::ray_direction`; reversed-Z, infinite far plane), seen from `cam` with its
/// samples offset by `jitter` pixels of the final film.
fn frame_uniforms(
    scene: &Scene,
    cam: &Camera,
    jitter: Vec2,
    sg: &SceneGpu,
    settings: &RasterSettings,
    k: u32,
) -> FrameUniforms {
    let (w, h) = (settings.width, settings.height);
    let aspect = w as f32 / h as f32;
    let fov = cam.fov_y_deg.to_radians();
    let near = camera_near(scene);
    let m = cam.to_world.matrix3;
    let (env_kind, env_tex, env_radiance) = sg.env;
    FrameUniforms {
        view_proj: view_proj(cam, w, h, near, jitter).to_cols_array_2d(),
        cam_pos: vec4(cam.position(), near),
        cam_x: vec4(Vec3::from(m.x_axis), 0.0),
        cam_y: vec4(Vec3::from(m.y_axis), 0.0),
        cam_z: vec4(Vec3::from(m.z_axis), 0.0),
        cam_forward: vec4(cam.forward(), 0.0),
        film: [w as f32, h as f32, (fov * 0.5).tan(), aspect],
        ssaa: [k as f32, 1.0 / k as f32, jitter.x, jitter.y],
        env_radiance,
        env_info: [env_kind as u32, env_tex, settings.method.env_n, 0],
        counts: [sg.light_count, sg.emitter_count, settings.method.area_n, 0],
        mesh_lights: match settings.method.mesh_n {
            0 => [NONE, 0, 0, 0],
            n => [sg.emissive_triangles, n, 0, 0],
        },
        energy: [energy::code(&settings.method), sg.energy_table, 0, 0],
    }
}

/// The bind groups every shading pass sets: group 1 (G-buffer, or empty), group 2 (shadow
/// maps) and group 3 (environment maps).
pub(crate) struct ShadingGroups<'a> {
    /// Group 1 of the geometry pipelines (empty).
    pub(crate) empty: &'a wgpu::BindGroup,
    /// The shadow maps (group 2).
    pub(crate) shadow: &'a ShadowMaps,
    /// The environment maps (group 3), or their placeholder.
    pub(crate) envmap: &'a wgpu::BindGroup,
    /// The SSAO passes between the G-buffer and the lighting (None: no SSAO method, or a frame
    /// that does not light).
    pub(crate) ssao: Option<&'a SsaoPasses>,
}

/// One timed pass of a frame. The frame runs its passes in the order of [`Pass::of_frame`], and
/// the i-th pass writes timestamp queries 2i and 2i + 1, so each pass is timed on its own and
/// the timing names it by [`Pass::label`].
///
/// The stages of a frame, in order (docs/ARCHITECTURE.md "Passes of one frame"):
/// 1. [`Pass::Shadow`]: depth from each light (under a shadow method with a map layer);
/// 2. [`Pass::Forward`], or [`Pass::GBuffer`]: the scene rasterised once;
/// 3. [`Pass::AmbientOcclusion`], the G-buffer post-passes (after `GBuffer`, before
///    `Lighting`): they read positions and normals and write an input of the lighting, the
///    SSAO methods' obscurance (technique/ssao/passes.rs);
/// 4. [`Pass::Lighting`]: the deferred full-screen lighting;
/// 5. [`Pass::Resolve`]: the MSAA resolve (under `aa_msaa`), then [`Pass::PostProcess`]: the
///    anti-aliasing that reads the lit image (FXAA, MLAA's three passes, TAA), timed together.
///
/// A new pass is a variant here, its encode function (called from [`encode_passes`]) and its
/// place in [`Pass::of_frame`]; its timestamps and its timing entry follow from that place.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Pass {
    /// Depth-only passes into the shadow map layers, timed together.
    Shadow,
    /// Forward shading of the scene into the outputs.
    Forward,
    /// The scene's G-buffer.
    GBuffer,
    /// Screen-space AO: its estimate, blur and upsampling passes, timed together.
    AmbientOcclusion,
    /// The full-screen deferred lighting reading the G-buffer.
    Lighting,
    /// The MSAA resolve into the outputs.
    Resolve,
    /// The anti-aliasing post-process of the colour output.
    PostProcess,
}

impl Pass {
    /// The passes of a frame with these pipelines, in the order they run: the shadow pass when
    /// `stages` holds the shadow pipelines and the method has map layers, the geometry pass, and
    /// the lighting pass when `stages` holds the lighting pipeline, after the SSAO passes when
    /// there are some.
    pub(crate) fn of_frame(
        stages: &[(Stage, Arc<wgpu::RenderPipeline>)],
        shadow: &ShadowMaps,
        ssao: Option<&SsaoPasses>,
        targets: &Targets,
        aa: Option<&AntiAliasPasses>,
    ) -> Vec<Pass> {
        let has = |wanted: fn(Stage) -> bool| stages.iter().any(|(s, _)| wanted(*s));
        let mut passes = Vec::with_capacity(3);
        if has(Stage::is_shadow) && !shadow.layers.is_empty() {
            passes.push(Pass::Shadow);
        }
        passes.push(if targets.gbuffer_views.is_some() {
            Pass::GBuffer
        } else {
            Pass::Forward
        });
        if has(|s| s == Stage::Lighting) {
            if ssao.is_some() && targets.gbuffer_views.is_some() {
                passes.push(Pass::AmbientOcclusion);
            }
            passes.push(Pass::Lighting);
        }
        if aa.is_some_and(AntiAliasPasses::resolves) {
            passes.push(Pass::Resolve);
        }
        if aa.is_some_and(AntiAliasPasses::post_processes) {
            passes.push(Pass::PostProcess);
        }
        passes
    }

    /// The pass's name in the timing (`Timing::passes`) and in the render-pass labels.
    pub(crate) fn label(self) -> &'static str {
        match self {
            Pass::Shadow => "shadow pass",
            Pass::Forward => "forward pass",
            Pass::GBuffer => "G-buffer pass",
            Pass::AmbientOcclusion => "SSAO pass",
            Pass::Lighting => "lighting pass",
            Pass::Resolve => "MSAA resolve pass",
            Pass::PostProcess => "post-process pass",
        }
    }
}

/// Records the frame's render passes, [`Pass::of_frame`] in order; pass i writes query pair i.
#[allow(clippy::too_many_arguments)]
pub(crate) fn encode_passes(
    encoder: &mut wgpu::CommandEncoder,
    frame: &Frame,
    targets: &Targets,
    stages: &[(Stage, Arc<wgpu::RenderPipeline>)],
    sg: &SceneGpu,
    groups: &ShadingGroups<'_>,
    aa: Option<&AntiAliasPasses>,
    queries: Option<&Timestamps>,
) {
    for (i, pass) in Pass::of_frame(stages, groups.shadow, groups.ssao, targets, aa)
        .into_iter()
        .enumerate()
    {
        let queries = queries.map(|q| (q, i as u32));
        match pass {
            Pass::Shadow => encode_shadow_passes(encoder, frame, stages, sg, groups.shadow, queries),
            Pass::Forward | Pass::GBuffer => {
                encode_geometry_pass(encoder, frame, targets, stages, sg, groups, queries)
            }
            Pass::AmbientOcclusion => {
                if let Some(ssao) = groups.ssao {
                    ssao.encode(encoder, queries);
                }
            }
            Pass::Lighting => {
                let lighting = stages.iter().find(|(s, _)| *s == Stage::Lighting);
                if let Some((_, pipeline)) = lighting {
                    encode_lighting_pass(encoder, frame, targets, pipeline, groups, queries);
                }
            }
            Pass::Resolve => {
                if let Some(aa) = aa {
                    aa.encode_resolve(encoder, targets, pass.label(), queries);
                }
            }
            Pass::PostProcess => {
                if let Some(aa) = aa {
                    aa.encode_post(encoder, targets, pass.label(), queries);
                }
            }
        }
    }
}

/// The shadow pass: for each map layer (a light slot's, or one of its cascades), a depth-only
/// render pass into it drawing the meshes and the analytic proxies with instance index = layer.
fn encode_shadow_passes(
    encoder: &mut wgpu::CommandEncoder,
    frame: &Frame,
    stages: &[(Stage, Arc<wgpu::RenderPipeline>)],
    sg: &SceneGpu,
    shadow: &ShadowMaps,
    queries: Option<(&Timestamps, u32)>,
) {
    let last = shadow.layers.len() - 1;
    for (layer, (name, view)) in shadow.layers.iter().enumerate() {
        let depth = wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        };
        let label = format!("shadow pass: {name}");
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(&label),
            color_attachments: &[],
            depth_stencil_attachment: Some(depth),
            timestamp_writes: queries.and_then(|(q, i)| q.span_writes(i, layer == 0, layer == last)),
            occlusion_query_set: None,
        });
        pass.set_bind_group(0, &frame.bind_group, &[]);
        let instance = layer as u32..layer as u32 + 1;
        for (stage, pipeline) in stages {
            let (group, vertices) = match stage {
                Stage::ShadowMesh => ("meshes (depth)", sg.mesh_vertices.as_ref()),
                Stage::ShadowAnalytic => (
                    "analytic shapes (depth, ray traced on proxies)",
                    sg.analytic_vertices.as_ref(),
                ),
                _ => continue,
            };
            let Some((vb, n)) = vertices else { continue };
            pass.push_debug_group(group);
            pass.set_pipeline(pipeline);
            pass.set_vertex_buffer(0, vb.slice(..));
            pass.draw(0..*n, instance.clone());
            pass.pop_debug_group();
        }
    }
}

/// The pass that rasterises the scene: shading into the outputs (forward), or the G-buffer.
fn encode_geometry_pass(
    encoder: &mut wgpu::CommandEncoder,
    frame: &Frame,
    targets: &Targets,
    stages: &[(Stage, Arc<wgpu::RenderPipeline>)],
    sg: &SceneGpu,
    groups: &ShadingGroups<'_>,
    queries: Option<(&Timestamps, u32)>,
) {
    let depth = wgpu::RenderPassDepthStencilAttachment {
        view: targets
            .msaa
            .as_ref()
            .map_or(&targets.depth_view, |m| &m.depth_view),
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(0.0),
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    };
    // Under MSAA the forward pass draws into the multisampled outputs the resolve reads.
    // Under MSAA the geometry pass draws into the multisampled outputs (forward) or
    // G-buffer (deferred).
    let (color, label) = match (&targets.gbuffer_views, &targets.msaa) {
        (Some(_), Some(msaa)) => (cleared_attachments(&msaa.views), Pass::GBuffer.label()),
        (Some(views), None) => (cleared_attachments(views), Pass::GBuffer.label()),
        (None, Some(msaa)) => (cleared_attachments(&msaa.views), Pass::Forward.label()),
        (None, None) => (cleared_attachments(&targets.output_views), Pass::Forward.label()),
    };
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &color,
        depth_stencil_attachment: Some(depth),
        timestamp_writes: queries.map(|(q, i)| q.writes(i)),
        occlusion_query_set: None,
    });
    pass.set_bind_group(0, &frame.bind_group, &[]);
    pass.set_bind_group(1, groups.empty, &[]);
    pass.set_bind_group(2, &groups.shadow.bind_group, &[]);
    pass.set_bind_group(3, groups.envmap, &[]);
    for (stage, pipeline) in stages {
        let (group, vertices) = match stage {
            Stage::ForwardMesh | Stage::GBufferMesh => ("meshes", sg.mesh_vertices.as_ref()),
            Stage::ForwardAnalytic | Stage::GBufferAnalytic => (
                "analytic shapes (ray traced on proxies)",
                sg.analytic_vertices.as_ref(),
            ),
            Stage::Background => ("background", None),
            Stage::Lighting | Stage::ShadowMesh | Stage::ShadowAnalytic | Stage::VisibilityAov => continue,
        };
        if *stage != Stage::Background && vertices.is_none() {
            continue;
        }
        pass.push_debug_group(group);
        pass.set_pipeline(pipeline);
        match vertices {
            Some((vb, n)) => {
                pass.set_vertex_buffer(0, vb.slice(..));
                pass.draw(0..*n, 0..1);
            }
            None => pass.draw(0..3, 0..1),
        }
        pass.pop_debug_group();
    }
}

/// The deferred lighting pass: one full-screen triangle reading the G-buffer.
fn encode_lighting_pass(
    encoder: &mut wgpu::CommandEncoder,
    frame: &Frame,
    targets: &Targets,
    pipeline: &wgpu::RenderPipeline,
    groups: &ShadingGroups<'_>,
    queries: Option<(&Timestamps, u32)>,
) {
    let color = cleared_attachments(&targets.output_views);
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(Pass::Lighting.label()),
        color_attachments: &color,
        depth_stencil_attachment: None,
        timestamp_writes: queries.map(|(q, i)| q.writes(i)),
        occlusion_query_set: None,
    });
    pass.push_debug_group("full-screen lighting");
    pass.set_bind_group(0, &frame.bind_group, &[]);
    let msaa_gbuffer = targets.msaa.as_ref().and_then(|m| m.gbuffer_bind_group.as_ref());
    if let Some(bg) = msaa_gbuffer.or(targets.gbuffer_bind_group.as_ref()) {
        pass.set_bind_group(1, bg, &[]);
    }
    pass.set_bind_group(2, &groups.shadow.bind_group, &[]);
    pass.set_bind_group(3, groups.envmap, &[]);
    pass.set_pipeline(pipeline);
    pass.draw(0..3, 0..1);
    pass.pop_debug_group();
}
