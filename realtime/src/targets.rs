//! Render targets of one resolution and their read-back to f32.
//!
//! The three outputs (colour, normal + depth, albedo + object id) are Rgba32Float, so the HDR
//! image comes back as the shader wrote it, bit for bit. The deferred pipeline adds a G-buffer
//! of three more Rgba32Float layers and the SSAO passes' R32Float obscurance; both share one
//! Depth32Float buffer.

use crate::gpu::{COLOR_FORMAT, DEPTH_FORMAT};
use crate::pipelines::PipelineKind;

/// Bytes of one Rgba32Float texel.
const TEXEL_BYTES: u32 = 16;

/// The SSAO passes' targets: one f32 channel (renderable everywhere, not filterable; every
/// read is a `textureLoad`).
pub(crate) const OBSCURANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// A `w`×`h` single-channel target of the SSAO passes, readable by the next pass.
pub(crate) fn obscurance_texture(device: &wgpu::Device, label: &str, w: u32, h: u32) -> wgpu::TextureView {
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
    labelled_view(
        &texture_2d(device, label, (w, h), OBSCURANCE_FORMAT, usage),
        label,
    )
}

/// Targets of a `width`×`height` render.
pub struct Targets {
    pub(crate) width: u32,
    pub(crate) height: u32,
    /// Colour, normal + depth, albedo + id.
    pub(crate) outputs: [wgpu::Texture; 3],
    pub(crate) output_views: [wgpu::TextureView; 3],
    pub(crate) depth_view: wgpu::TextureView,
    /// G-buffer (deferred only) and its bind group (the three layers, then the obscurance).
    pub(crate) gbuffer_views: Option<[wgpu::TextureView; 3]>,
    pub(crate) gbuffer_bind_group: Option<wgpu::BindGroup>,
    /// Ambient obscurance 1 − AO per pixel (deferred only; [`OBSCURANCE_FORMAT`]), written by
    /// the SSAO passes and read by the lighting: zero, nothing occluded, unless one ran.
    pub(crate) obscurance_view: Option<wgpu::TextureView>,
    /// The multisampled outputs the forward pass draws into under `aa_msaa`, resolved into
    /// the outputs (None: it draws into the outputs).
    pub(crate) msaa: Option<MultisampledOutputs>,
}

/// A `w`×`h` single-sample 2D texture of `format` with `usage`.
pub(crate) fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    (w, h): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn color_texture(
    device: &wgpu::Device,
    label: &str,
    w: u32,
    h: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    texture_2d(device, label, (w, h), COLOR_FORMAT, usage)
}

/// The multisampled targets and depth buffer the geometry pass draws into under `aa_msaa`:
/// the outputs (forward; the resolve pass reads them) or the G-buffer (deferred; the lighting
/// pass reads them through `gbuffer_bind_group`).
pub(crate) struct MultisampledOutputs {
    /// Colour, normal + depth, albedo + id (forward) or the three G-buffer layers (deferred),
    /// `samples` samples per pixel.
    pub(crate) views: [wgpu::TextureView; 3],
    pub(crate) depth_view: wgpu::TextureView,
    /// Group 1 of the deferred MSAA lighting pass (`gbuffer_msaa_layout`), or None (forward).
    pub(crate) gbuffer_bind_group: Option<wgpu::BindGroup>,
}

impl MultisampledOutputs {
    /// `samples`-sample targets of `width`×`height`; with `gbuffer_layout` (deferred) they are
    /// the G-buffer, bound for the lighting pass.
    pub(crate) fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        samples: u32,
        gbuffer_layout: Option<&wgpu::BindGroupLayout>,
    ) -> MultisampledOutputs {
        let texture = |label: &str, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let views = [
            "colour target (MSAA)",
            "normal + depth target (MSAA)",
            "albedo + object id target (MSAA)",
        ]
        .map(|label| labelled_view(&texture(label, COLOR_FORMAT, usage), label));
        let depth = texture(
            "depth buffer (MSAA, reversed-Z)",
            DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let gbuffer_bind_group = gbuffer_layout.map(|layout| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("multisampled G-buffer bind group"),
                layout,
                entries: &view_entries(&views, 3),
            })
        });
        MultisampledOutputs {
            views,
            depth_view: labelled_view(&depth, "depth view (MSAA)"),
            gbuffer_bind_group,
        }
    }
}

/// Colour attachments of `views`, cleared to zero and stored.
pub(crate) fn cleared_attachments<'a>(
    views: impl IntoIterator<Item = &'a wgpu::TextureView>,
) -> Vec<Option<wgpu::RenderPassColorAttachment<'a>>> {
    let ops = wgpu::Operations {
        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
        store: wgpu::StoreOp::Store,
    };
    views
        .into_iter()
        .map(|view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops,
            })
        })
        .collect()
}

/// Bind-group entries of texture `views` at bindings `first`, `first` + 1, ….
pub(crate) fn view_entries<'a>(
    views: impl IntoIterator<Item = &'a wgpu::TextureView>,
    first: u32,
) -> Vec<wgpu::BindGroupEntry<'a>> {
    views
        .into_iter()
        .enumerate()
        .map(|(i, v)| wgpu::BindGroupEntry {
            binding: first + i as u32,
            resource: wgpu::BindingResource::TextureView(v),
        })
        .collect()
}

/// A view of the whole texture, labelled.
fn labelled_view(texture: &wgpu::Texture, label: &str) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some(label),
        ..Default::default()
    })
}

impl Targets {
    /// Targets for `kind` at `width`×`height`; `gbuffer_layout` describes the lighting pass's
    /// G-buffer bindings.
    pub fn new(
        device: &wgpu::Device,
        kind: PipelineKind,
        width: u32,
        height: u32,
        gbuffer_layout: &wgpu::BindGroupLayout,
    ) -> Targets {
        // Sampled too: the environment capture copies its colour target into a cube face, and
        // the anti-aliasing post-processes read it and copy their result back.
        let out_usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::TEXTURE_BINDING;
        let outputs = [
            "colour target (HDR)",
            "normal + depth target",
            "albedo + object id target",
        ]
        .map(|label| color_texture(device, label, width, height, out_usage));
        let output_views = [0, 1, 2].map(|i| outputs[i].create_view(&wgpu::TextureViewDescriptor::default()));
        let depth = texture_2d(
            device,
            "depth buffer (reversed-Z)",
            (width, height),
            DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let depth_view = labelled_view(&depth, "depth view");
        let (gbuffer_views, gbuffer_bind_group, obscurance_view) = if kind == PipelineKind::Deferred {
            let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
            let layers = [
                "G-buffer 0 (position, object id)",
                "G-buffer 1 (shading normal, u)",
                "G-buffer 2 (geometric normal, v)",
            ]
            .map(|label| color_texture(device, label, width, height, usage));
            let views = [0, 1, 2].map(|i| labelled_view(&layers[i], "G-buffer view"));
            let obscurance = obscurance_texture(device, "ambient obscurance (SSAO)", width, height);
            let mut entries = view_entries(&views, 0);
            entries.extend(view_entries([&obscurance], 6));
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("G-buffer bind group"),
                layout: gbuffer_layout,
                entries: &entries,
            });
            (Some(views), Some(bind_group), Some(obscurance))
        } else {
            (None, None, None)
        };
        Targets {
            width,
            height,
            outputs,
            output_views,
            depth_view,
            gbuffer_views,
            gbuffer_bind_group,
            obscurance_view,
            msaa: None,
        }
    }

    /// Bytes per row of a read-back copy (padded to wgpu's 256-byte alignment).
    fn padded_row(&self) -> u32 {
        let row = self.width * TEXEL_BYTES;
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
    }

    /// Copies the three outputs into mappable buffers (encoded into `encoder`).
    pub fn encode_readback(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
    ) -> [wgpu::Buffer; 3] {
        let row = self.padded_row();
        let size = u64::from(row) * u64::from(self.height);
        let buffers = [
            "colour read-back",
            "normal + depth read-back",
            "albedo + id read-back",
        ]
        .map(|label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            })
        });
        for (texture, buffer) in self.outputs.iter().zip(&buffers) {
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(self.height),
                    },
                },
                wgpu::Extent3d {
                    width: self.width,
                    height: self.height,
                    depth_or_array_layers: 1,
                },
            );
        }
        buffers
    }

    /// The texels of a mapped read-back buffer, row 0 at the top, padding removed.
    pub fn unpad(&self, bytes: &[u8]) -> Vec<[f32; 4]> {
        let row = self.padded_row() as usize;
        let used = (self.width * TEXEL_BYTES) as usize;
        let mut out = Vec::with_capacity((self.width * self.height) as usize);
        for r in 0..self.height as usize {
            let line = &bytes[r * row..r * row + used];
            out.extend(line.chunks_exact(16).map(|t| {
                let f = |k: usize| f32::from_le_bytes([t[4 * k], t[4 * k + 1], t[4 * k + 2], t[4 * k + 3]]);
                [f(0), f(1), f(2), f(3)]
            }));
        }
        out
    }
}
