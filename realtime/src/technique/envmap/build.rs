//! Building an environment-mapping method's maps for one render (module docs of
//! [`super`]): the capture, the filtering passes of `technique/envmap/filter.wgsl`, and
//! the bind group (group 3) the shading pipelines read them from.
//!
//! Capture: six forward renders of the scene without the reflector, from the capture point,
//! 90° square views of side `size` along ±X, ±Y, ±Z (up vectors of the cube-map convention:
//! −Z for +Y, +Z for −Y, +Y otherwise); each colour target is copied into its Rgba16Float cube
//! face with its columns mirrored (the convention's faces are left-handed). Pixel centres of a
//! 90° view are the cube texels' centres, so the copy is exact up to the f16 rounding.
//! Then: box mips of the radiance cube (full chain), the prefiltered levels (when the
//! reflector's material has a glossy lobe and `prefilter = lobe`; otherwise the box mips are
//! read), the irradiance cube (16², from the level of side ≤ 32) or SH9 (from the level of side
//! ≤ 64) when it has a diffuse lobe, the warp into the sphere or paraboloid map (from the
//! same levels; the capture cube has the map's side), the BRDF table for GGX and metal-rough.
//! Level 0's alpha holds each texel's distance from the capture point (the distance
//! impostors' lookups, [`crate::technique::distance_impostor`]); with `double_refraction` a second cube
//! holds the refractor's outward normals and distances from its centre; with `layers` > 1
//! the capture is repeated with depth peeling (`shaders/passes.wgsl` `peel_distance`: each
//! pass keeps the nearest surface behind the previous layer's, level 0 only) and the further
//! layers are copied into a cube array (binding 8).

use std::sync::{Arc, OnceLock};
use std::time::Instant;

use glam::Vec3;
use scenes::{Camera, Geometry, Material, Scene};
use wgpu::util::DeviceExt;

use super::filter::{
    bind_entries, dispatch, encode_box_mips, encode_brdf_table, encode_irradiance, encode_prefilter,
    encode_sh9, encode_warp, face_view, level_view, map_texture, sampler, sh_buffer, tiles, view,
    FilterParams, FilterPipelines, Res,
};
use super::localization::Localization;
use super::{EnvMapping, Irradiance, Parameterization, Prefilter};
use crate::error::RasterError;
use crate::frame::{encode_passes, Frame, ShadingGroups};
use crate::gpu::Gpu;
use crate::pipelines::{shader_source, PipelineKind, Pipelines};
use crate::settings::RasterSettings;
use crate::specialize::ShaderIr;
use crate::targets::Targets;
use crate::technique::detail::ConeCache;
use crate::technique::shadow::maps::ShadowMaps;
use crate::technique::texture::Filter;
use crate::upload::SceneGpu;

/// `EnvMapUniforms` of envmap/envmap.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct EnvMapUniforms {
    info: [u32; 4],
    frame_x: [f32; 4],
    frame_y: [f32; 4],
    frame_z: [f32; 4],
    local: [u32; 4],
    capture: [f32; 4],
    refractor: [f32; 4],
    layers: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<EnvMapUniforms>() == 8 * 16);

/// The maps of one render and group 3 over them.
pub(crate) struct EnvMaps {
    pub(crate) bind_group: wgpu::BindGroup,
    /// Header attributes (`environment_map`, `environment_map_texels`, `environment_map_build_ms`), empty for the
    /// placeholder.
    pub(crate) header: Vec<(&'static str, String)>,
}

/// The index of the reflector of `e` in `scene`: the named shape, or the one non-diffuse,
/// non-emissive shape, or the one non-emissive shape.
pub(crate) fn reflector_index(scene: &Scene, e: &EnvMapping) -> Result<usize, String> {
    let names = || {
        scene
            .shapes
            .iter()
            .map(|s| s.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if let Some(name) = &e.reflector {
        return scene.shapes.iter().position(|s| &s.name == name).ok_or_else(|| {
            format!(
                "reflector = {name}: the scene has no such shape; shapes: {}",
                names()
            )
        });
    }
    let lit: Vec<usize> = (0..scene.shapes.len())
        .filter(|&i| scene.shapes[i].emission.is_none())
        .collect();
    let glossy: Vec<usize> = lit
        .iter()
        .copied()
        .filter(|&i| {
            !matches!(
                scene.materials[scene.shapes[i].material],
                Material::Diffuse { .. }
            )
        })
        .collect();
    match (&glossy[..], &lit[..]) {
        ([i], _) | ([], [i]) => Ok(*i),
        _ => Err(format!(
            "name the reflector (reflector = NAME): the scene has {} non-diffuse, non-emissive shapes; shapes: {}",
            glossy.len(),
            names()
        )),
    }
}

/// What the reflector's material needs: (a glossy lobe and whether it is Phong's, a diffuse
/// lobe, the split-sum table).
fn lobes(m: &Material) -> (Option<bool>, bool, bool) {
    match m {
        Material::Diffuse { .. } => (None, true, false),
        Material::Phong { .. } => (Some(true), false, false),
        Material::Ggx { .. } => (Some(false), false, true),
        Material::MetalRough { .. } => (Some(false), true, true),
        _ => (None, false, false),
    }
}

/// The six capture cameras at `p`, in layer order (+X, −X, +Y, −Y, +Z, −Z).
fn face_cameras(p: Vec3) -> [Camera; 6] {
    let faces = [
        (Vec3::X, Vec3::Y),
        (Vec3::NEG_X, Vec3::Y),
        (Vec3::Y, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::Z),
        (Vec3::Z, Vec3::Y),
        (Vec3::NEG_Z, Vec3::Y),
    ];
    faces.map(|(forward, up)| Camera::look_at(p, p + forward, up, 90.0))
}

/// Orthonormal frame (x, y, z) with z = `z` and y as close to world +Y as possible.
fn frame_about(z: Vec3) -> [Vec3; 3] {
    let up = if z.y.abs() > 0.999 { Vec3::X } else { Vec3::Y };
    let x = up.cross(z).normalize();
    [x, z.cross(x), z]
}

/// Group 3 over the given maps.
#[allow(clippy::too_many_arguments)]
fn bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    cube: &wgpu::TextureView,
    flat: &wgpu::TextureView,
    irradiance: &wgpu::TextureView,
    brdf: &wgpu::TextureView,
    sh: &wgpu::Buffer,
    refractor: &wgpu::TextureView,
    layers: &wgpu::TextureView,
    uniforms: EnvMapUniforms,
) -> wgpu::BindGroup {
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("environment map uniforms"),
        contents: bytemuck::bytes_of(&uniforms),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let s = sampler(device);
    let entries = bind_entries(&[
        (0, Res::View(cube)),
        (1, Res::View(flat)),
        (2, Res::View(irradiance)),
        (3, Res::View(brdf)),
        (4, Res::Sampler(&s)),
        (5, Res::Buffer(sh)),
        (6, Res::Buffer(&uniform)),
        (7, Res::View(refractor)),
        (8, Res::View(layers)),
    ]);
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("environment map bind group"),
        layout,
        entries: &entries,
    })
}

/// `envmap.local.x` of a depth-peeling capture (distance_impostor/lookup.wgsl `LOCAL_PEEL`).
pub(crate) const LOCAL_PEEL: u32 = 3;

/// Uniforms of a render without a reflector: `local` and `capture` as given.
fn no_reflector_uniforms(local: [u32; 4], capture: [f32; 4]) -> EnvMapUniforms {
    EnvMapUniforms {
        info: [u32::MAX, 0, 1, 0],
        frame_x: [1.0, 0.0, 0.0, 0.0],
        frame_y: [0.0, 1.0, 0.0, 0.0],
        frame_z: [0.0, 0.0, 1.0, 0.0],
        local,
        capture,
        refractor: [0.0; 4],
        layers: [1, 0, 0, 0],
    }
}

/// Group 3 without a reflector, over 1×1 maps except `flat` (None: 1×1 too).
fn bind_group_without_reflector(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    flat: Option<&wgpu::TextureView>,
    uniforms: EnvMapUniforms,
) -> wgpu::BindGroup {
    let cube = map_texture(device, "placeholder cube", 1, 6, 1);
    let placeholder_flat = map_texture(device, "placeholder map", 1, 2, 1);
    let cube_view = view(&cube, wgpu::TextureViewDimension::Cube, 0..1);
    let layers_view = view(&cube, wgpu::TextureViewDimension::CubeArray, 0..1);
    let flat_view = view(&placeholder_flat, wgpu::TextureViewDimension::D2Array, 0..1);
    let sh = sh_buffer(device);
    bind_group(
        device,
        layout,
        &cube_view,
        flat.unwrap_or(&flat_view),
        &cube_view,
        &flat_view,
        &sh,
        &cube_view,
        &layers_view,
        uniforms,
    )
}

impl EnvMaps {
    /// Group 3 of every render without an environment map: 1×1 maps, no reflector.
    pub(crate) fn placeholder(device: &wgpu::Device, layout: &wgpu::BindGroupLayout) -> EnvMaps {
        EnvMaps {
            bind_group: bind_group_without_reflector(
                device,
                layout,
                None,
                no_reflector_uniforms([0; 4], [0.0; 4]),
            ),
            header: Vec::new(),
        }
    }
}

/// What a renderer keeps for environment mapping: group 3 of the renders without a map, and
/// the filter pipelines, compiled on first use (only renders with a map pay for them).
pub(crate) struct EnvMapBuilder {
    placeholder: EnvMaps,
    filters: OnceLock<Arc<FilterPipelines>>,
}

impl EnvMapBuilder {
    /// The placeholder group for `layout` (the shading pipelines' group 3); no filters yet.
    pub(crate) fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout) -> EnvMapBuilder {
        EnvMapBuilder {
            placeholder: EnvMaps::placeholder(device, layout),
            filters: OnceLock::new(),
        }
    }

    /// The environment-map filter pipelines: a module of the shading sources (whose BSDF and
    /// frame helpers the filters call) and envmap/filter.wgsl, parsed once and specialised
    /// for each filter's entry point (specialize.rs).
    pub(crate) fn filters(&self, device: &wgpu::Device) -> Arc<FilterPipelines> {
        self.filters
            .get_or_init(|| {
                let source = shader_source(false, Filter::Bilinear)
                    + "// ---- envmap/filter.wgsl ----\n"
                    + include_str!("filter.wgsl");
                let ir = ShaderIr::parse(&source).unwrap_or_else(|e| {
                    panic!("Verity's environment-map filter module does not validate: {e}")
                });
                Arc::new(FilterPipelines::new(device, &ir))
            })
            .clone()
    }

    /// Captures and filters the maps of `settings`' environment-mapping method for `scene`
    /// with the renderer's device, pipelines and cone maps (the placeholder without a method).
    pub(crate) fn build(
        &self,
        gpu: &Gpu,
        pipelines: &Pipelines,
        cones: &ConeCache,
        scene: &Scene,
        settings: &RasterSettings,
    ) -> Result<EnvMaps, RasterError> {
        let build = Build {
            gpu,
            pipelines,
            cones,
            builder: self,
        };
        build.environment_maps(scene, settings)
    }
}

/// One build: what it borrows from the renderer.
struct Build<'a> {
    gpu: &'a Gpu,
    pipelines: &'a Pipelines,
    cones: &'a ConeCache,
    builder: &'a EnvMapBuilder,
}

impl Build<'_> {
    /// The maps of `settings`' method for `scene`.
    fn environment_maps(&self, scene: &Scene, settings: &RasterSettings) -> Result<EnvMaps, RasterError> {
        let placeholder = &self.builder.placeholder;
        let Some(e) = settings.method.get::<EnvMapping>() else {
            return Ok(EnvMaps {
                bind_group: placeholder.bind_group.clone(),
                header: Vec::new(),
            });
        };
        let device = &self.gpu.device;
        let limits = self.gpu.limits();
        let bad = |m: String| RasterError::Settings(format!("method {}: {m}", settings.method));
        if e.size > limits.max_texture_dimension_2d {
            return Err(bad(format!(
                "size = {} exceeds the adapter's {} texels per side",
                e.size, limits.max_texture_dimension_2d
            )));
        }
        let start = Instant::now();
        let index = reflector_index(scene, e).map_err(bad)?;
        let reflector = &scene.shapes[index];
        let (lo, hi) = reflector.bounds(&scene.textures);
        let capture = e.capture.unwrap_or((lo + hi) * 0.5);
        let (glossy, diffuse, split_sum) = lobes(&scene.materials[reflector.material]);

        // Capture: the scene without the reflector, six faces of side `size`.
        let mut without = scene.clone();
        without.shapes.remove(index);
        let radiance = self.capture_cube(&without, capture, settings, CaptureKind::Radiance, None)?;
        // The further layers of a layered distance map, each peeled behind the one before.
        let layer_count = e.localization.distance_layers();
        let layers = self.distance_layers(&without, capture, settings, &radiance, layer_count)?;

        // The refractor's own map, for double refraction: a sphere's from its centre and
        // radius, a mesh's rendered from its bounding-box centre.
        let refractor_centre = (lo + hi) * 0.5;
        let is_dielectric = matches!(scene.materials[reflector.material], Material::Dielectric { .. });
        let refractor = if e.double_refraction && is_dielectric {
            Some(self.refractor_map(scene, index, refractor_centre, settings)?)
        } else {
            None
        };

        let maps = self.filter_maps(scene, e, &radiance, capture, (glossy, diffuse, split_sum))?;
        let build_ms = start.elapsed().as_secs_f64() * 1e3;

        let (levels, frame) = (maps.levels, maps.frame);
        let f4 = |v: Vec3| [v.x, v.y, v.z, 0.0];
        let uniforms = EnvMapUniforms {
            info: [
                index as u32,
                e.irradiance.shader_code(),
                levels,
                u32::from(e.dominant_direction),
            ],
            frame_x: f4(frame[0]),
            frame_y: f4(frame[1]),
            frame_z: f4(frame[2]),
            local: e.localization.shader_info(refractor.is_some()),
            capture: f4(capture),
            refractor: f4(refractor_centre),
            layers: [layer_count, 0, 0, 0],
        };
        let bind_group = bind_maps(
            device,
            &self.pipelines.envmap_layout,
            &Maps {
                specular_cube: &maps.specular_cube,
                levels,
                flat: maps.flat.as_ref(),
                irradiance: maps.irradiance.as_ref(),
                brdf: maps.brdf.as_ref(),
                sh: &maps.sh,
                refractor: refractor.as_ref(),
                layers: layers.as_ref(),
            },
            uniforms,
        );
        let describe = describe(e, levels, glossy, &reflector.name, capture, refractor.is_some());
        Ok(EnvMaps {
            bind_group,
            header: vec![
                ("environment_map", describe),
                ("environment_map_texels", e.texels().to_string()),
                ("environment_map_build_ms", format!("{build_ms:.3}")),
            ],
        })
    }

    /// The filtering passes over the captured `radiance` cube (module docs): box mips, then
    /// what the reflector's material reads, submitted and waited for.
    /// `lobes` as [`lobes`] gives them.
    fn filter_maps(
        &self,
        scene: &Scene,
        e: &EnvMapping,
        radiance: &wgpu::Texture,
        capture: Vec3,
        (glossy, diffuse, split_sum): (Option<bool>, bool, bool),
    ) -> Result<Filtered, RasterError> {
        let device = &self.gpu.device;
        let filters = self.builder.filters(device);
        let size = e.size;
        let mips = size.ilog2() + 1;
        // Box mips, then what the material reads.
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("environment map filtering"),
        });
        encode_box_mips(device, &mut encoder, &filters, radiance, size, mips);
        let levels = EnvMapping::levels(size).min(mips);
        let s = sampler(device);
        let radiance_cube = view(radiance, wgpu::TextureViewDimension::Cube, 0..mips);
        let prefiltered = match (glossy, e.prefilter) {
            (Some(phong), Prefilter::Lobe) => Some(encode_prefilter(
                device,
                &mut encoder,
                &filters,
                (&radiance_cube, &s),
                e,
                phong,
                levels,
            )),
            _ => None,
        };
        let specular_cube = match &prefiltered {
            Some(t) => view(t, wgpu::TextureViewDimension::Cube, 0..levels),
            None => view(radiance, wgpu::TextureViewDimension::Cube, 0..levels),
        };
        let sh = sh_buffer(device);
        let irradiance = (diffuse && e.irradiance == Irradiance::Map)
            .then(|| encode_irradiance(device, &mut encoder, &filters, radiance, size));
        if diffuse && e.irradiance == Irradiance::Sh9 {
            encode_sh9(device, &mut encoder, &filters, radiance, size, &sh);
        }
        let frame = map_frame(e, scene, capture);
        let flat = (e.parameterization != Parameterization::Cube).then(|| {
            encode_warp(
                device,
                &mut encoder,
                &filters,
                (&specular_cube, &s),
                e,
                frame,
                levels,
            )
        });
        let brdf = split_sum.then(|| encode_brdf_table(device, &mut encoder, &filters));
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()?;
        self.gpu.check_errors("building the environment maps")?;
        Ok(Filtered {
            levels,
            frame,
            _prefiltered: prefiltered,
            specular_cube,
            flat,
            irradiance,
            sh,
            brdf,
        })
    }
}

/// The maps a build made, for group 3 (None: the method does not read that map).
/// The filtered maps of one build (`Build::filter_maps`).
struct Filtered {
    /// Levels of the specular cube the material reads.
    levels: u32,
    /// The sphere or paraboloid map's frame (the axes for a cube).
    frame: [Vec3; 3],
    /// The prefiltered cube, kept alive beside its view.
    _prefiltered: Option<wgpu::Texture>,
    specular_cube: wgpu::TextureView,
    flat: Option<wgpu::Texture>,
    irradiance: Option<wgpu::Texture>,
    sh: wgpu::Buffer,
    brdf: Option<wgpu::Texture>,
}

/// The frame of the map's parameterisation: the world axes for a cube, the sphere map's frame
/// about its view direction (`sphere_view`, or from the capture point to the camera), the
/// paraboloid's with its front along +Y.
fn map_frame(e: &EnvMapping, scene: &Scene, capture: Vec3) -> [Vec3; 3] {
    match e.parameterization {
        Parameterization::Cube => [Vec3::X, Vec3::Y, Vec3::Z],
        Parameterization::Sphere => {
            let towards = e
                .sphere_view
                .unwrap_or_else(|| scene.camera.position() - capture)
                .try_normalize()
                .unwrap_or(Vec3::Z);
            frame_about(towards)
        }
        Parameterization::Paraboloid => [Vec3::X, Vec3::NEG_Z, Vec3::Y],
    }
}

struct Maps<'a> {
    /// The prefiltered cube (or the radiance cube's box mips), `levels` levels.
    specular_cube: &'a wgpu::TextureView,
    levels: u32,
    flat: Option<&'a wgpu::Texture>,
    irradiance: Option<&'a wgpu::Texture>,
    brdf: Option<&'a wgpu::Texture>,
    sh: &'a wgpu::Buffer,
    refractor: Option<&'a wgpu::Texture>,
    layers: Option<&'a wgpu::Texture>,
}

/// Group 3 of the render: `maps`, 1×1 stand-ins where the method reads none, and `uniforms`.
fn bind_maps(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    maps: &Maps,
    uniforms: EnvMapUniforms,
) -> wgpu::BindGroup {
    // 1×1 stand-ins for the maps this method does not build.
    let placeholder_cube = map_texture(device, "placeholder cube", 1, 6, 1);
    let placeholder_flat = map_texture(device, "placeholder map", 1, 2, 1);
    let irradiance_view = match maps.irradiance {
        Some(t) => view(t, wgpu::TextureViewDimension::Cube, 0..1),
        None => view(&placeholder_cube, wgpu::TextureViewDimension::Cube, 0..1),
    };
    let flat_view = match maps.flat {
        Some(t) => view(t, wgpu::TextureViewDimension::D2Array, 0..maps.levels),
        None => view(&placeholder_flat, wgpu::TextureViewDimension::D2Array, 0..1),
    };
    let brdf_view = match maps.brdf {
        Some(t) => view(t, wgpu::TextureViewDimension::D2Array, 0..1),
        None => view(&placeholder_flat, wgpu::TextureViewDimension::D2Array, 0..1),
    };
    let refractor_view = match maps.refractor {
        Some(t) => view(t, wgpu::TextureViewDimension::Cube, 0..1),
        None => irradiance_view.clone(),
    };
    let layers_view = view(
        maps.layers.unwrap_or(&placeholder_cube),
        wgpu::TextureViewDimension::CubeArray,
        0..1,
    );
    bind_group(
        device,
        layout,
        maps.specular_cube,
        &flat_view,
        &irradiance_view,
        &brdf_view,
        maps.sh,
        &refractor_view,
        &layers_view,
        uniforms,
    )
}

/// The header's `environment_map`: the map, its levels and filter, the reflector, the capture
/// point and how lookups are localized.
fn describe(
    e: &EnvMapping,
    levels: u32,
    glossy: Option<bool>,
    reflector: &str,
    capture: Vec3,
    double_refraction: bool,
) -> String {
    let size = e.size;
    let localized = match e.localization {
        Localization::Distant => String::new(),
        Localization::Iterations(k) => format!(", lookups localized by {k} iterations"),
        Localization::Search {
            linear_steps,
            secant_steps,
            layers: 1,
        } => format!(", lookups localized by {linear_steps} linear + {secant_steps} secant steps"),
        Localization::Search {
            linear_steps,
            secant_steps,
            layers,
        } => format!(
            ", lookups localized by {linear_steps} linear + {secant_steps} secant steps in {layers} depth-peeled distance layers"
        ),
    };
    let refracted = if double_refraction {
        ", double refraction through the reflector's own map"
    } else {
        ""
    };
    format!(
        "{} of side {size}, {levels} levels ({}), reflector {}, captured at ({:.4}, {:.4}, {:.4}){localized}{refracted}",
        e.parameterization,
        match (glossy, e.prefilter) {
            (Some(true), Prefilter::Lobe) => "Phong lobe",
            (Some(false), Prefilter::Lobe) => "GGX lobe",
            (Some(_), Prefilter::Box) => "box mips",
            (None, _) => "unfiltered",
        },
        reflector,
        capture.x,
        capture.y,
        capture.z
    )
}

/// What a capture stores in rgb (alpha: the distance from the capture point).
#[derive(Clone, Copy, PartialEq, Eq)]
enum CaptureKind {
    /// The radiance seen (the environment's map).
    Radiance,
    /// The shading normal (a refractor's map).
    Normal,
}

impl Build<'_> {
    /// Layers 2..=`layer_count` of a layered distance map (GPU Gems 3 §17.2), each captured
    /// behind the one before (depth peeling from `radiance`, the first), in one cube array;
    /// None for one layer.
    fn distance_layers(
        &self,
        scene: &Scene,
        capture: Vec3,
        settings: &RasterSettings,
        radiance: &wgpu::Texture,
        layer_count: u32,
    ) -> Result<Option<wgpu::Texture>, RasterError> {
        let device = &self.gpu.device;
        let size = settings.method.get::<EnvMapping>().map_or(1, |e| e.size);
        let mut further: Vec<wgpu::Texture> = Vec::new();
        for _ in 1..layer_count {
            let previous = further.last().unwrap_or(radiance);
            let layer = self.capture_cube(scene, capture, settings, CaptureKind::Radiance, Some(previous))?;
            further.push(layer);
        }
        Ok((layer_count > 1).then(|| {
            let t = map_texture(device, "distance map layers", size, 6 * (layer_count - 1), 1);
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("distance map layers"),
            });
            for (k, layer) in further.iter().enumerate() {
                encoder.copy_texture_to_texture(
                    layer.as_image_copy(),
                    wgpu::TexelCopyTextureInfo {
                        texture: &t,
                        mip_level: 0,
                        origin: wgpu::Origin3d {
                            x: 0,
                            y: 0,
                            z: 6 * k as u32,
                        },
                        aspect: wgpu::TextureAspect::All,
                    },
                    wgpu::Extent3d {
                        width: size,
                        height: size,
                        depth_or_array_layers: 6,
                    },
                );
            }
            self.gpu.queue.submit([encoder.finish()]);
            t
        }))
    }

    /// The refractor's own distance map for double refraction, centred at `centre`: a
    /// sphere's computed from its radius, a mesh's captured (outward normals and distances);
    /// other shapes are not closed and refused.
    fn refractor_map(
        &self,
        scene: &Scene,
        index: usize,
        centre: Vec3,
        settings: &RasterSettings,
    ) -> Result<wgpu::Texture, RasterError> {
        let device = &self.gpu.device;
        let size = settings.method.get::<EnvMapping>().map_or(1, |e| e.size);
        let reflector = &scene.shapes[index];
        match &reflector.geometry {
            Geometry::Sphere { radius, .. } => {
                let t = map_texture(device, "refractor map", size, 6, 1);
                let dst = level_view(&t, 0);
                let params = FilterParams {
                    roughness: *radius,
                    ..FilterParams::new(size)
                };
                let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("refractor map"),
                });
                dispatch(
                    device,
                    &mut encoder,
                    &self.builder.filters(device).refractor_sphere,
                    params,
                    &[(14, Res::View(&dst))],
                    [tiles(size), tiles(size), 6],
                );
                self.gpu.queue.submit([encoder.finish()]);
                Ok(t)
            }
            Geometry::Mesh { .. } => {
                let mut alone = scene.clone();
                alone.shapes = vec![reflector.clone()];
                self.capture_cube(&alone, centre, settings, CaptureKind::Normal, None)
            }
            _ => Err(RasterError::Settings(format!(
                "method {}: double_refraction = on: reflector {} is not a closed shape (a sphere or a mesh)",
                settings.method, reflector.name
            ))),
        }
    }

    /// The scene buffers and shadow maps of a capture render with `face_settings`.
    fn capture_scene(
        &self,
        scene: &Scene,
        face_settings: &RasterSettings,
    ) -> Result<(SceneGpu, ShadowMaps), RasterError> {
        let device = &self.gpu.device;
        let limits = self.gpu.limits();
        let scene_gpu = SceneGpu::new(self.gpu, scene, &face_settings.method, self.cones, None)
            .map_err(RasterError::Scene)?;
        let shadow = ShadowMaps::new(
            device,
            &self.pipelines.shadow_layout,
            scene,
            &face_settings.method,
            1.0,
            limits,
        )
        .map_err(RasterError::Settings)?;
        Ok((scene_gpu, shadow))
    }

    /// Six 90° forward renders of `scene` from `point`, of side `size` (the method's), copied
    /// into a new cube of the full mip chain (level 0 written; envmap/filter.wgsl
    /// `cs_face_copy`). With `peel`, a cube of one level holding the nearest surfaces behind
    /// those `peel` holds (depth peeling: passes.wgsl `peel_distance`).
    fn capture_cube(
        &self,
        scene: &Scene,
        point: Vec3,
        settings: &RasterSettings,
        kind: CaptureKind,
        peel: Option<&wgpu::Texture>,
    ) -> Result<wgpu::Texture, RasterError> {
        let placeholder = &self.builder.placeholder;
        let device = &self.gpu.device;
        let size = settings.method.get::<EnvMapping>().map_or(1, |e| e.size);
        let capture_method = settings.method.clone().without::<EnvMapping>();
        let face_settings = RasterSettings::new(size, size)
            .method(capture_method)
            .pipeline(PipelineKind::Forward)
            .frames(0, 1);
        let (scene_gpu, shadow) = self.capture_scene(scene, &face_settings)?;
        let groups = ShadingGroups {
            empty: &self.pipelines.empty_bind_group,
            shadow: &shadow,
            envmap: &placeholder.bind_group,
            ssao: None,
        };
        let stages = self
            .pipelines
            .stages(device, &face_settings.method, face_settings.pipeline, false, 1);
        let filters = self.builder.filters(device);
        let mips = match (kind, peel) {
            (CaptureKind::Radiance, None) => size.ilog2() + 1,
            _ => 1,
        };
        let label = match kind {
            CaptureKind::Radiance => "radiance cube",
            CaptureKind::Normal => "refractor map",
        };
        let cube = map_texture(device, label, size, 6, mips);
        let targets = Targets::new(
            device,
            PipelineKind::Forward,
            size,
            size,
            &self.pipelines.gbuffer_layout,
        );
        for (face, camera) in face_cameras(point).into_iter().enumerate() {
            let peel_group = peel.map(|previous| {
                let previous_face = face_view(previous, face as u32);
                let uniforms = no_reflector_uniforms([LOCAL_PEEL, 0, 0, 0], [point.x, point.y, point.z, 0.0]);
                bind_group_without_reflector(
                    device,
                    &self.pipelines.envmap_layout,
                    Some(&previous_face),
                    uniforms,
                )
            });
            let groups = ShadingGroups {
                envmap: peel_group.as_ref().unwrap_or(&placeholder.bind_group),
                ..groups
            };
            let mut view_scene = scene.clone();
            view_scene.camera = camera;
            let frame = Frame::new(
                device,
                &self.pipelines.scene_layout,
                &view_scene,
                &scene_gpu,
                &shadow,
                &face_settings,
                1,
            );
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("environment capture"),
            });
            encode_passes(
                &mut encoder,
                &frame,
                &targets,
                &stages,
                &scene_gpu,
                &groups,
                None,
                None,
            );
            let dst = face_view(&cube, face as u32);
            encode_face_copy(device, &mut encoder, &filters, &targets, &dst, kind);
            self.gpu.queue.submit([encoder.finish()]);
        }
        Ok(cube)
    }
}

/// Copies a capture render's colour (radiance, or normal and distance for `Normal`) into cube
/// face `dst`, mirroring its columns (envmap/filter.wgsl `cs_face_copy`).
fn encode_face_copy(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    filters: &FilterPipelines,
    targets: &Targets,
    dst: &wgpu::TextureView,
    kind: CaptureKind,
) {
    let size = targets.width;
    let params = FilterParams {
        mode: match kind {
            CaptureKind::Radiance => 0,
            CaptureKind::Normal => 1,
        },
        ..FilterParams::new(size)
    };
    dispatch(
        device,
        encoder,
        &filters.face_copy,
        params,
        &[
            (10, Res::View(&targets.output_views[0])),
            (17, Res::View(&targets.output_views[1])),
            (14, Res::View(dst)),
        ],
        [tiles(size), tiles(size), 1],
    );
}
