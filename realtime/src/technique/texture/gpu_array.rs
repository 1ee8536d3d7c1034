//! The scene's textures as one GPU texture array with MIP levels, for `tex_anisotropic`: the
//! one filter the adapter performs (`textureSampleGrad` on a sampler with `anisotropy_clamp`),
//! bound beside the texel buffer every other lookup reads (group 0, bindings 9–12,
//! shaders/common.wgsl).
//!
//! Layer i is scene texture i. The array needs one size for every layer, so a scene whose
//! textures differ in size, or a texture whose u and v wrap differently (one sampler per wrap
//! mode: repeat, clamp, mirror), is refused with a message saying so; level l is
//! [`super::pyramid::mip_levels`]'s, in the method's `mip_space`. Texels are `Rgba16Float`
//! (filterable on every adapter; 32-bit floats are filterable only with an optional feature):
//! each value is rounded to 11 significant bits. Every other method binds a 1 × 1 stand-in.

use scenes::texture::{Texture, WrapMode};
use scenes::Scene;
use wgpu::util::DeviceExt;

use super::{pyramid, TextureFilter};

/// The texture array and its three samplers (repeat, clamp-to-edge, mirror in both axes).
pub struct TextureArray {
    /// A 2D-array view of every layer and level.
    pub view: wgpu::TextureView,
    /// Samplers by wrap code (0 repeat, 1 clamp, 2 mirror: `TextureInfo.wrap`'s low bits).
    pub samplers: [wgpu::Sampler; 3],
}

fn address(w: WrapMode) -> wgpu::AddressMode {
    match w {
        WrapMode::Repeat => wgpu::AddressMode::Repeat,
        WrapMode::Clamp => wgpu::AddressMode::ClampToEdge,
        WrapMode::Mirror => wgpu::AddressMode::MirrorRepeat,
    }
}

fn samplers(device: &wgpu::Device, anisotropy: u16) -> [wgpu::Sampler; 3] {
    [WrapMode::Repeat, WrapMode::Clamp, WrapMode::Mirror].map(|w| {
        device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("tex_anisotropic sampler"),
            address_mode_u: address(w),
            address_mode_v: address(w),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::FilterMode::Linear,
            anisotropy_clamp: anisotropy,
            ..Default::default()
        })
    })
}

/// f16 bits of `t`'s texels, row-major.
fn half_texels(t: &Texture) -> Vec<u16> {
    t.texels
        .iter()
        .flat_map(|v| v.to_array())
        .map(|x| half::f16::from_f32(x).to_bits())
        .collect()
}

impl TextureArray {
    /// A 1 × 1 stand-in (every method but `tex_anisotropic`).
    pub fn stand_in(device: &wgpu::Device, queue: &wgpu::Queue) -> TextureArray {
        TextureArray::upload(device, queue, (1, 1, 1), 1, &[0; 4], 1)
    }

    /// A `width` × `height` × `layers` array of `levels` MIP levels from f16 `data` (layer
    /// major), viewed as a 2D array, with samplers of `anisotropy`.
    fn upload(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        (width, height, layers): (u32, u32, u32),
        levels: u32,
        data: &[u16],
        anisotropy: u16,
    ) -> TextureArray {
        let texture = device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some("scene texture array (tex_anisotropic)"),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: layers,
                },
                mip_level_count: levels,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba16Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(data),
        );
        TextureArray {
            view: texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            }),
            samplers: samplers(device, anisotropy),
        }
    }

    /// The scene's textures with the levels `filter` reads; `anisotropic`: whether the
    /// adapter filters anisotropically. Errors say why the scene cannot be uploaded.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        filter: &TextureFilter,
        colour: &[usize],
        anisotropic: bool,
    ) -> Result<TextureArray, String> {
        if !anisotropic && filter.max_anisotropy > 1 {
            return Err(format!(
                "tex_anisotropic: this adapter does not filter anisotropically (max_anisotropy = {} would be 1); \
                 use max_anisotropy = 1 or a filter written in WGSL (tex_footprint, tex_ewa)",
                filter.max_anisotropy
            ));
        }
        let Some(first) = scene.textures.first() else {
            return Ok(TextureArray::stand_in(device, queue));
        };
        let (w, h) = (first.width, first.height);
        for (i, t) in scene.textures.iter().enumerate() {
            if (t.width, t.height) != (w, h) {
                return Err(format!(
                    "tex_anisotropic: textures[{i}] is {}x{} but textures[0] is {w}x{h}: the GPU texture array \
                     holds one size",
                    t.width, t.height
                ));
            }
            if t.wrap[0] != t.wrap[1] {
                return Err(format!(
                    "tex_anisotropic: textures[{i}] wraps u and v differently ({:?}, {:?}): one sampler per wrap mode",
                    t.wrap[0], t.wrap[1]
                ));
            }
        }
        let levels = pyramid::level_count(w, h);
        // Layer-major: every level of layer 0, then of layer 1, … (wgpu's LayerMajor order).
        let mut data: Vec<u16> = Vec::new();
        for (i, t) in scene.textures.iter().enumerate() {
            data.extend(half_texels(t));
            for level in pyramid::mip_levels(t, filter.mip_space, colour.contains(&i)) {
                data.extend(half_texels(&level));
            }
        }
        let layers = scene.textures.len() as u32;
        Ok(TextureArray::upload(
            device,
            queue,
            (w, h, layers),
            levels,
            &data,
            filter.max_anisotropy as u16,
        ))
    }
}
