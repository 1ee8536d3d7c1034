//! The per-light visibility AOV, `visibility.<light>.Y`: what the method's visibility factor V
//! is at each sample, in the oracle's light order and naming (emissive shapes in scene order,
//! then scene lights: `scenes::Scene::light_names`), box-filtered like the oracle's (the
//! background counts as 0).
//!
//! Measured after the timed frames, untimed, on the shadow maps the last timed frame left: a
//! G-buffer pass, then a full-screen pass (`fs_visibility`) that writes V of every light slot
//! at every sample into a storage buffer — in chunks of slots when one buffer would exceed the
//! adapter's storage-binding limit. V follows the oracle's AOV: 0 where the light cannot reach
//! the point (behind a one-sided emitter, outside a spot's cone, the emitter's own surface),
//! else the shadow map's V (1 for unshadowed methods). Emissive meshes have no shadow maps
//! (their light, under `mesh_n` > 0, is unshadowed): their channel is the coverage (V = 1 on
//! every surface).

use bytemuck::{Pod, Zeroable};
use scenes::{Geometry, Scene};
use wgpu::util::DeviceExt;

use crate::targets::{view_entries, Targets};

/// Dimensions of one visibility chunk (WGSL `AovInfo`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuAovInfo {
    /// Target width, light slots per chunk, light slots in all, target pixels.
    pub dims: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuAovInfo>() == 16);

/// Where a named light's channel comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// A light slot's V (area emitter or scene light).
    Slot(usize),
    /// An emissive mesh: unshadowed and unlit here, so the coverage.
    Coverage,
}

/// (name, source) of every named light of `scene`, in `Scene::light_names` order.
pub fn named_sources(scene: &Scene) -> Vec<(String, Source)> {
    let mut out = Vec::new();
    let mut slot = 0;
    for shape in scene.shapes.iter().filter(|s| s.emission.is_some()) {
        let source = if matches!(shape.geometry, Geometry::Mesh(_)) {
            Source::Coverage
        } else {
            slot += 1;
            Source::Slot(slot - 1)
        };
        out.push((shape.name.clone(), source));
    }
    for light in &scene.lights {
        out.push((light.name().to_string(), Source::Slot(slot)));
        slot += 1;
    }
    out
}

/// Light slots per chunk so that one chunk's buffer (4 bytes per slot per target pixel) fits
/// `max_bytes`; an error when not even one slot fits.
pub fn slots_per_chunk(slots: u32, pixels: u32, max_bytes: u64) -> Result<u32, String> {
    let per_slot = 4 * u64::from(pixels);
    let fit = max_bytes / per_slot.max(1);
    if fit == 0 {
        return Err(format!(
            "the visibility AOV needs {per_slot} bytes per light, more than the adapter's storage \
             binding limit of {max_bytes}"
        ));
    }
    Ok(slots.min(u32::try_from(fit).unwrap_or(u32::MAX)).max(1))
}

/// The AOV buffer of one chunk and the bind group (group 1) that writes it.
pub(crate) struct Chunk {
    pub(crate) output: wgpu::Buffer,
    pub(crate) bind_group: wgpu::BindGroup,
}

impl Chunk {
    /// Chunk buffers for `per_chunk` slots of `targets` (deferred: they hold the G-buffer).
    pub(crate) fn new(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        targets: &Targets,
        per_chunk: u32,
        slots: u32,
    ) -> Chunk {
        let pixels = targets.width * targets.height;
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("visibility AOV (per light slot, per sample)"),
            size: 4 * u64::from(pixels) * u64::from(per_chunk),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let info = GpuAovInfo {
            dims: [targets.width, per_chunk, slots, pixels],
        };
        let info = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("visibility AOV dimensions"),
            contents: bytemuck::bytes_of(&info),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let views = targets
            .gbuffer_views
            .as_ref()
            .unwrap_or_else(|| unreachable!("the visibility AOV reads a G-buffer"));
        let mut entries = view_entries(views, 0);
        entries.push(wgpu::BindGroupEntry {
            binding: 3,
            resource: output.as_entire_binding(),
        });
        entries.push(wgpu::BindGroupEntry {
            binding: 4,
            resource: info.as_entire_binding(),
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("visibility AOV bind group"),
            layout,
            entries: &entries,
        });
        Chunk { output, bind_group }
    }
}

/// Records the visibility pass of chunk `chunk` (after the G-buffer pass into `targets`).
pub(crate) fn encode_visibility_pass(
    encoder: &mut wgpu::CommandEncoder,
    targets: &Targets,
    scene_group: &wgpu::BindGroup,
    chunk_group: &wgpu::BindGroup,
    shadow_group: &wgpu::BindGroup,
    pipeline: &wgpu::RenderPipeline,
    chunk: u32,
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("visibility AOV pass"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &targets.depth_view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
    });
    pass.push_debug_group("every light's V at every sample");
    pass.set_bind_group(0, scene_group, &[]);
    pass.set_bind_group(1, chunk_group, &[]);
    pass.set_bind_group(2, shadow_group, &[]);
    pass.set_pipeline(pipeline);
    pass.draw(0..3, chunk..chunk + 1);
    pass.pop_debug_group();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_fit_the_binding_limit() {
        assert_eq!(slots_per_chunk(5, 100, 1 << 20), Ok(5));
        assert_eq!(slots_per_chunk(5, 100, 800), Ok(2));
        assert!(slots_per_chunk(5, 100, 300)
            .unwrap_err()
            .contains("400 bytes per light"));
    }
}
