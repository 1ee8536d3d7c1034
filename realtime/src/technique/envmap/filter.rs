//! The filtering passes of an environment map (`technique/envmap/filter.wgsl`, compute): the
//! maps' textures and views, the dispatch helper, and one encoder per product — box mips,
//! lobe-prefiltered levels, the irradiance cube, SH9, the sphere or paraboloid warp and the
//! split-sum BRDF table ([`super::build`] runs them after the capture).

use glam::Vec3;
use wgpu::util::DeviceExt;

use super::{EnvMapping, Parameterization, IRRADIANCE_SIZE};
use crate::specialize::ShaderIr;

/// Format of every map.
pub(super) const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Side of the split-sum BRDF table, and its samples per texel.
pub(super) const BRDF_TABLE_SIZE: u32 = 32;
pub(super) const BRDF_TABLE_SAMPLES: u32 = 512;
/// Largest source level side for the irradiance cube and for SH9.
pub(super) const IRRADIANCE_SOURCE: u32 = 32;
pub(super) const SH9_SOURCE: u32 = 64;

/// `FilterParams` of envmap/filter.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct FilterParams {
    pub(super) size: u32,
    pub(super) roughness: f32,
    pub(super) source_size: u32,
    pub(super) mode: u32,
    pub(super) samples: u32,
    pub(super) source_level: u32,
    pub(super) layers: u32,
    pub(super) flag: u32,
    pub(super) frame_x: [f32; 4],
    pub(super) frame_y: [f32; 4],
    pub(super) frame_z: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<FilterParams>() == 8 * 4 + 3 * 16);

impl FilterParams {
    pub(super) fn new(size: u32) -> FilterParams {
        FilterParams {
            size,
            roughness: 0.0,
            source_size: 0,
            mode: 0,
            samples: 1,
            source_level: 0,
            layers: 1,
            flag: 0,
            frame_x: [1.0, 0.0, 0.0, 0.0],
            frame_y: [0.0, 1.0, 0.0, 0.0],
            frame_z: [0.0, 0.0, 1.0, 0.0],
        }
    }
}

/// The compute pipelines of envmap/filter.wgsl (auto layouts: group 0, bindings 10–17).
pub(crate) struct FilterPipelines {
    pub(super) face_copy: wgpu::ComputePipeline,
    pub(super) refractor_sphere: wgpu::ComputePipeline,
    pub(super) downsample: wgpu::ComputePipeline,
    pub(super) prefilter: wgpu::ComputePipeline,
    pub(super) irradiance: wgpu::ComputePipeline,
    sh9: wgpu::ComputePipeline,
    pub(super) warp: wgpu::ComputePipeline,
    pub(super) brdf_lut: wgpu::ComputePipeline,
}

impl FilterPipelines {
    /// Each filter's pipeline from `ir` specialised for its entry point alone.
    pub(crate) fn new(device: &wgpu::Device, ir: &ShaderIr) -> FilterPipelines {
        let make = |entry: &str| {
            let specialised = ir
                .specialise(&[entry], &[])
                .unwrap_or_else(|e| panic!("{entry}: the filter module does not specialise: {e}"));
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(entry),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(specialised)),
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        FilterPipelines {
            face_copy: make("cs_face_copy"),
            refractor_sphere: make("cs_refractor_sphere"),
            downsample: make("cs_downsample"),
            prefilter: make("cs_prefilter"),
            irradiance: make("cs_irradiance"),
            sh9: make("cs_sh9"),
            warp: make("cs_warp"),
            brdf_lut: make("cs_brdf_lut"),
        }
    }
}

/// One binding of a filter dispatch.
pub(super) enum Res<'a> {
    View(&'a wgpu::TextureView),
    Sampler(&'a wgpu::Sampler),
    Buffer(&'a wgpu::Buffer),
}

pub(super) fn map_texture(
    device: &wgpu::Device,
    label: &str,
    size: u32,
    layers: u32,
    levels: u32,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: layers,
        },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: MAP_FORMAT,
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

pub(super) fn view(
    t: &wgpu::Texture,
    dim: wgpu::TextureViewDimension,
    mips: std::ops::Range<u32>,
) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(dim),
        base_mip_level: mips.start,
        mip_level_count: Some(mips.end - mips.start),
        ..Default::default()
    })
}

/// Level 0 of cube face `face` of `t`, as a one-layer array.
pub(super) fn face_view(t: &wgpu::Texture, face: u32) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        base_mip_level: 0,
        mip_level_count: Some(1),
        base_array_layer: face,
        array_layer_count: Some(1),
        ..Default::default()
    })
}

/// A storage view of level `level` of `t` (every layer).
pub(super) fn level_view(t: &wgpu::Texture, level: u32) -> wgpu::TextureView {
    view(t, wgpu::TextureViewDimension::D2Array, level..level + 1)
}

pub(super) fn sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("environment map sampler (trilinear, clamped)"),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        address_mode_w: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    })
}

/// Bind group entries of `res` (binding number, resource).
pub(super) fn bind_entries<'a>(res: &[(u32, Res<'a>)]) -> Vec<wgpu::BindGroupEntry<'a>> {
    res.iter()
        .map(|(binding, r)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: match r {
                Res::View(v) => wgpu::BindingResource::TextureView(v),
                Res::Sampler(s) => wgpu::BindingResource::Sampler(s),
                Res::Buffer(b) => b.as_entire_binding(),
            },
        })
        .collect()
}

/// Records one filter dispatch of `pipeline` over `groups` workgroups with `params` and
/// the bindings `res` (binding number, resource).
pub(super) fn dispatch(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    params: FilterParams,
    res: &[(u32, Res<'_>)],
    groups: [u32; 3],
) {
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("filter parameters"),
        contents: bytemuck::bytes_of(&params),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let mut entries = bind_entries(res);
    entries.push(wgpu::BindGroupEntry {
        binding: 15,
        resource: uniform.as_entire_binding(),
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("filter bind group"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("environment map filtering"),
        timestamp_writes: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, &bind_group, &[]);
    pass.dispatch_workgroups(groups[0], groups[1], groups[2]);
}

pub(super) fn tiles(n: u32) -> u32 {
    n.div_ceil(8)
}

pub(super) fn sh_buffer(device: &wgpu::Device) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("SH9 irradiance coefficients"),
        size: 9 * 16,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    })
}

/// The box mips of `radiance` (side `size`, `mips` levels), each level from the one above.
pub(super) fn encode_box_mips(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    filters: &FilterPipelines,
    radiance: &wgpu::Texture,
    size: u32,
    mips: u32,
) {
    for k in 1..mips {
        let n = (size >> k).max(1);
        let src = level_view(radiance, k - 1);
        let dst = level_view(radiance, k);
        let params = FilterParams {
            layers: 6,
            ..FilterParams::new(n)
        };
        dispatch(
            device,
            encoder,
            &filters.downsample,
            params,
            &[(11, Res::View(&src)), (14, Res::View(&dst))],
            [tiles(n), tiles(n), 6],
        );
    }
}

/// The lobe-prefiltered cube (Karis 2013's split sum, n = v = r; filtered importance
/// sampling, Křivánek & Colbert 2008): level k of `levels` convolved with the lobe of roughness
/// k/(levels − 1), normalized Phong if `phong`, else GGX, from `source` (the radiance cube and
/// its sampler).
pub(super) fn encode_prefilter(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    filters: &FilterPipelines,
    source: (&wgpu::TextureView, &wgpu::Sampler),
    e: &EnvMapping,
    phong: bool,
    levels: u32,
) -> wgpu::Texture {
    let (radiance_cube, s) = source;
    let size = e.size;
    let t = map_texture(device, "prefiltered cube", size, 6, levels);
    for k in 0..levels {
        let n = (size >> k).max(1);
        let dst = level_view(&t, k);
        let params = FilterParams {
            roughness: if levels > 1 {
                k as f32 / (levels - 1) as f32
            } else {
                0.0
            },
            source_size: size,
            mode: u32::from(phong),
            samples: e.filter_samples,
            ..FilterParams::new(n)
        };
        dispatch(
            device,
            encoder,
            &filters.prefilter,
            params,
            &[
                (12, Res::View(radiance_cube)),
                (13, Res::Sampler(s)),
                (14, Res::View(&dst)),
            ],
            [tiles(n), tiles(n), 6],
        );
    }
    t
}

/// The cosine-convolved irradiance cube (faces of [`IRRADIANCE_SIZE`]) from the radiance
/// level nearest [`IRRADIANCE_SOURCE`] texels across.
pub(super) fn encode_irradiance(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    filters: &FilterPipelines,
    radiance: &wgpu::Texture,
    size: u32,
) -> wgpu::Texture {
    let t = map_texture(device, "irradiance cube", IRRADIANCE_SIZE, 6, 1);
    let level = level_of_side(size, IRRADIANCE_SOURCE);
    let src = level_view(radiance, level);
    let params = FilterParams {
        source_size: (size >> level).max(1),
        ..FilterParams::new(IRRADIANCE_SIZE)
    };
    let dst = level_view(&t, 0);
    dispatch(
        device,
        encoder,
        &filters.irradiance,
        params,
        &[(11, Res::View(&src)), (14, Res::View(&dst))],
        [tiles(IRRADIANCE_SIZE), tiles(IRRADIANCE_SIZE), 6],
    );
    t
}

/// Nine spherical-harmonic coefficients of the radiance (Ramamoorthi & Hanrahan 2001) into
/// `sh`, from the level nearest [`SH9_SOURCE`] texels across.
pub(super) fn encode_sh9(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    filters: &FilterPipelines,
    radiance: &wgpu::Texture,
    size: u32,
    sh: &wgpu::Buffer,
) {
    let level = level_of_side(size, SH9_SOURCE);
    let src = level_view(radiance, level);
    let params = FilterParams {
        source_size: (size >> level).max(1),
        ..FilterParams::new(1)
    };
    dispatch(
        device,
        encoder,
        &filters.sh9,
        params,
        &[(11, Res::View(&src)), (16, Res::Buffer(sh))],
        [1, 1, 1],
    );
}

/// The sphere or dual-paraboloid levels of `e`, warped from `source` (the specular cube and
/// its sampler) in the map frame `frame`.
pub(super) fn encode_warp(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    filters: &FilterPipelines,
    source: (&wgpu::TextureView, &wgpu::Sampler),
    e: &EnvMapping,
    frame: [Vec3; 3],
    levels: u32,
) -> wgpu::Texture {
    let (specular_cube, s) = source;
    let size = e.size;
    let f4 = |v: Vec3| [v.x, v.y, v.z, 0.0];
    let layers = e.parameterization.layers();
    let t = map_texture(device, "sphere or paraboloid map", size, layers, levels);
    for k in 0..levels {
        let n = (size >> k).max(1);
        let dst = level_view(&t, k);
        let params = FilterParams {
            mode: u32::from(e.parameterization == Parameterization::Paraboloid),
            source_level: k,
            layers,
            flag: u32::from(e.seam_fill),
            frame_x: f4(frame[0]),
            frame_y: f4(frame[1]),
            frame_z: f4(frame[2]),
            ..FilterParams::new(n)
        };
        dispatch(
            device,
            encoder,
            &filters.warp,
            params,
            &[
                (12, Res::View(specular_cube)),
                (13, Res::Sampler(s)),
                (14, Res::View(&dst)),
            ],
            [tiles(n), tiles(n), layers],
        );
    }
    t
}

/// The split-sum BRDF table (Karis 2013): scale and bias of F0 per (n·v, roughness), two
/// layers for the two masking variants.
pub(super) fn encode_brdf_table(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    filters: &FilterPipelines,
) -> wgpu::Texture {
    let t = map_texture(device, "split-sum BRDF table", BRDF_TABLE_SIZE, 2, 1);
    let dst = level_view(&t, 0);
    let params = FilterParams {
        samples: BRDF_TABLE_SAMPLES,
        ..FilterParams::new(BRDF_TABLE_SIZE)
    };
    dispatch(
        device,
        encoder,
        &filters.brdf_lut,
        params,
        &[(14, Res::View(&dst))],
        [tiles(BRDF_TABLE_SIZE), tiles(BRDF_TABLE_SIZE), 2],
    );
    t
}

/// The first mip level of a `size` chain whose side is at most `max`.
pub(super) fn level_of_side(size: u32, max: u32) -> u32 {
    let mut k = 0;
    while (size >> k) > max {
        k += 1;
    }
    k
}
