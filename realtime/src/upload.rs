//! The scene on the GPU: `scenes::Scene` turned into the buffers `shaders/common.wgsl` reads.
//!
//! - Meshes are de-indexed: each triangle gets three vertices of its own carrying its flat data
//!   (geometric normal, ∂p/∂u, ∂p/∂v) and, where the oracle shades the triangle flat (a vertex
//!   normal missing, NaN or zero), the geometric normal as every vertex normal — so per-pixel
//!   interpolation reproduces oracle/src/geometry/triangle.rs exactly.
//! - Spheres, rectangles and disks become proxies ray traced per fragment (`surface.wgsl`):
//!   a sphere's bounding box (enlarged by [`SPHERE_PROXY_MARGIN`]) with inward-facing
//!   triangles, so back-face culling keeps exactly its far side; a rectangle itself and a
//!   disk's circumscribed parallelogram, each in both windings so one survives culling from
//!   either side.
//! - Textures are concatenated into one texel buffer (RGBA f32) read by `texture.wgsl`.
//!
//! Checks mirror the oracle's: non-finite geometry, zero-area planar shapes, out-of-range
//! indices, bad light parameters are errors naming the shape or light.

use std::borrow::Cow;

use glam::{Vec2, Vec3, Vec4};
use scenes::lightmap::LightMap;
use scenes::texture::Texture;
use scenes::{
    Displacement, Emission, Environment, Geometry, Light, Masking, Material, Mesh, Scene, TexRgb, TexScalar,
    WrapMode,
};
use wgpu::util::DeviceExt;

use crate::gpu::Gpu;
use crate::gpu_types::*;
use crate::technique::antialias::{toksvig_normal_map, AntiAliasing};
use crate::technique::detail::{derivative_map, ConeCache, Detail};
use crate::technique::energy::{self, EnergyCompensation};
use crate::technique::texture::gpu_array::TextureArray;
use crate::technique::texture::{self, pyramid, sat, Needs, TextureFilter};
use crate::technique::Method;

/// Relative enlargement of a sphere's bounding box proxy, so rasterisation never clips its
/// silhouette (the box touches the sphere at its face centres).
pub const SPHERE_PROXY_MARGIN: f32 = 0.01;

/// Everything the passes bind, built once per scene.
pub struct SceneGpu {
    pub(crate) shapes: wgpu::Buffer,
    pub(crate) materials: wgpu::Buffer,
    pub(crate) lights: wgpu::Buffer,
    pub(crate) emitters: wgpu::Buffer,
    pub(crate) texture_infos: wgpu::Buffer,
    pub(crate) texels: wgpu::Buffer,
    pub(crate) mesh_vertices: Option<(wgpu::Buffer, u32)>,
    pub(crate) analytic_vertices: Option<(wgpu::Buffer, u32)>,
    pub(crate) light_count: u32,
    pub(crate) shape_count: u32,
    pub(crate) emitter_count: u32,
    pub(crate) env: (EnvKind, u32, [f32; 4]),
    /// The emissive meshes (lit per triangle under `mesh_n` > 0, unshadowed).
    pub(crate) emissive_meshes: Vec<String>,
    /// The texture record of the emissive-mesh triangle table, or NONE (WGSL
    /// `frame.mesh_lights.x` under `mesh_n` > 0).
    pub(crate) emissive_triangles: u32,
    /// The scene's textures as a GPU texture array (`tex_anisotropic`; else a stand-in).
    pub(crate) texture_array: TextureArray,
    /// The energy-compensation table's texture record, or NONE (WGSL `frame.energy.y`).
    pub(crate) energy_table: u32,
}

/// CPU-side arrays before upload.
#[derive(Default)]
struct Arrays {
    shapes: Vec<GpuShape>,
    materials: Vec<GpuMaterial>,
    lights: Vec<GpuLight>,
    emitters: Vec<u32>,
    texture_infos: Vec<GpuTextureInfo>,
    texels: Vec<[f32; 4]>,
    mesh: Vec<MeshVertex>,
    analytic: Vec<AnalyticVertex>,
    emissive_meshes: Vec<String>,
    /// Six texel records per emissive mesh triangle ([`add_emissive_triangles`]).
    emissive_triangles: Vec<[f32; 4]>,
    /// Their table's texture record, or NONE (set by [`add_emissive_table`]).
    emissive_table: u32,
    /// The energy-compensation table's texture record, or NONE.
    energy_table: u32,
}

impl SceneGpu {
    /// Checks and uploads `scene`; `max_binding` is the device's storage-binding limit. Displaced
    /// shapes get the maps the method's surface detail reads (a derivative map; a cone map from
    /// `cones` under `cone_step`), textures the levels its texture filter reads.
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        method: &Method,
        cones: &ConeCache,
        lightmap: Option<&LightMap>,
    ) -> Result<SceneGpu, String> {
        let (device, queue) = (&gpu.device, &gpu.queue);
        let max_binding = u64::from(gpu.limits().max_storage_buffer_binding_size);
        let detail = method.get::<Detail>();
        let src = scene.source.display().to_string();
        let mut a = Arrays::default();
        let textures = method_textures(scene, method);
        for (i, t) in textures.iter().enumerate() {
            add_texture(&mut a, t).map_err(|e| format!("{src}: textures[{i}]: {e}"))?;
        }
        for (i, m) in scene.materials.iter().enumerate() {
            a.materials
                .push(material(m, scene.textures.len()).map_err(|e| format!("{src}: materials[{i}]: {e}"))?);
        }
        for (i, s) in scene.shapes.iter().enumerate() {
            add_shape(&mut a, scene, i, detail, cones)
                .map_err(|e| format!("{src}: shape '{}' (shapes[{i}]): {e}", s.name))?;
        }
        for (i, l) in scene.lights.iter().enumerate() {
            a.lights.push(
                light(l, scene.textures.len())
                    .map_err(|e| format!("{src}: light '{}' (lights[{i}]): {e}", l.name()))?,
            );
        }
        add_levels(&mut a, scene, &textures, &texture::of(method));
        if let Some(map) = lightmap {
            add_lightmap(&mut a, scene, map).map_err(|e| format!("{src}: light map: {e}"))?;
        }
        a.emissive_table = add_emissive_table(&mut a).map_err(|e| format!("{src}: emissive meshes: {e}"))?;
        a.energy_table = match method.get::<EnergyCompensation>() {
            Some(e) if e.needs_table() => {
                let record = a.texture_infos.len() as u32;
                add_texture(&mut a, &energy::tables::table(e.lut))
                    .map_err(|e| format!("{src}: energy table: {e}"))?;
                record
            }
            _ => NONE,
        };
        let env = environment(scene).map_err(|e| format!("{src}: environment: {e}"))?;
        let bytes = (a.texels.len() * 16) as u64;
        if bytes > max_binding {
            return Err(format!(
                "{src}: the textures need {bytes} bytes, more than the adapter's storage binding limit of {max_binding}"
            ));
        }
        let filter = texture::of(method);
        let texture_array = if filter.filter.needs().gpu {
            let colour = colour_textures(scene);
            TextureArray::new(
                device,
                queue,
                scene,
                &filter,
                &colour,
                gpu.anisotropic_filtering(),
            )
            .map_err(|e| format!("{src}: {e}"))?
        } else {
            TextureArray::stand_in(device, queue)
        };
        Ok(upload(device, a, env, texture_array))
    }
}

fn upload(
    device: &wgpu::Device,
    a: Arrays,
    env: (EnvKind, u32, [f32; 4]),
    texture_array: TextureArray,
) -> SceneGpu {
    fn storage<T: bytemuck::Pod + bytemuck::Zeroable>(
        device: &wgpu::Device,
        label: &str,
        data: &[T],
    ) -> wgpu::Buffer {
        // Empty bindings are invalid: one zeroed element stands in.
        let zero = [T::zeroed()];
        let contents: &[T] = if data.is_empty() { &zero } else { data };
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(contents),
            usage: wgpu::BufferUsages::STORAGE,
        })
    }
    fn vertices<T: bytemuck::Pod>(
        device: &wgpu::Device,
        label: &str,
        data: &[T],
    ) -> Option<(wgpu::Buffer, u32)> {
        (!data.is_empty()).then(|| {
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(data),
                usage: wgpu::BufferUsages::VERTEX,
            });
            (buffer, data.len() as u32)
        })
    }
    SceneGpu {
        shapes: storage(device, "scene shapes", &a.shapes),
        materials: storage(device, "scene materials", &a.materials),
        lights: storage(device, "scene lights", &a.lights),
        emitters: storage(device, "scene area emitters", &a.emitters),
        texture_infos: storage(device, "scene texture infos", &a.texture_infos),
        texels: storage(device, "scene texels", &a.texels),
        mesh_vertices: vertices(device, "mesh vertices (de-indexed)", &a.mesh),
        analytic_vertices: vertices(device, "analytic shape proxies", &a.analytic),
        light_count: a.lights.len() as u32,
        shape_count: a.shapes.len() as u32,
        emitter_count: a.emitters.len() as u32,
        env,
        emissive_meshes: a.emissive_meshes,
        emissive_triangles: a.emissive_table,
        energy_table: a.energy_table,
        texture_array,
    }
}

fn wrap_code(w: WrapMode) -> u32 {
    match w {
        WrapMode::Repeat => 0,
        WrapMode::Clamp => 1,
        WrapMode::Mirror => 2,
    }
}

fn add_texture(a: &mut Arrays, t: &Texture) -> Result<(), String> {
    let n = t.width as usize * t.height as usize;
    if n == 0 || t.texels.len() != n {
        return Err(format!(
            "{}x{} texture holds {} texels",
            t.width,
            t.height,
            t.texels.len()
        ));
    }
    let offset = u32::try_from(a.texels.len()).map_err(|_| "too many texels in total".to_string())?;
    let wrap = wrap_code(t.wrap[0]) | (wrap_code(t.wrap[1]) << 4);
    a.texture_infos
        .push(plain_record(offset, t.width, t.height, wrap));
    a.texels.extend(t.texels.iter().map(|v| v.to_array()));
    Ok(())
}

/// The light map's atlas as one more texture (E in rgb, coverage in a), and each chart's
/// place in its shape's record. The charts must name the scene's shapes (the map was baked
/// for this scene: `LightMap::from_image` checked names and geometry when it was read).
fn add_lightmap(a: &mut Arrays, scene: &Scene, map: &LightMap) -> Result<(), String> {
    let l = &map.layout;
    let texels = l.width as usize * l.height as usize;
    if texels == 0 || map.irradiance.len() != texels || map.covered.len() != texels {
        return Err(format!(
            "a {}x{} atlas holds {} texels",
            l.width,
            l.height,
            map.irradiance.len()
        ));
    }
    let texture = a.texture_infos.len() as u32;
    let offset = u32::try_from(a.texels.len()).map_err(|_| "too many texels in total".to_string())?;
    // Clamped in both directions: a lookup never wraps to the far side of the atlas.
    a.texture_infos.push(plain_record(
        offset,
        l.width,
        l.height,
        wrap_code(WrapMode::Clamp) * 0x11,
    ));
    a.texels.extend(
        map.irradiance
            .iter()
            .zip(&map.covered)
            .map(|(e, &c)| [e.x, e.y, e.z, f32::from(u8::from(c))]),
    );
    for c in &l.charts {
        match scene.shapes.get(c.shape) {
            Some(s) if s.name == c.name => {}
            _ => {
                return Err(format!(
                    "chart `{}` names no shape of this scene at index {}",
                    c.name, c.shape
                ))
            }
        }
        if c.width >= 1 << 16 || c.height >= 1 << 16 {
            return Err(format!(
                "chart `{}` is {}x{} texels, above 65535",
                c.name, c.width, c.height
            ));
        }
        a.shapes[c.shape].lightmap = [texture, c.x, c.y, c.width | c.height << 16];
    }
    Ok(())
}

/// A texture record without levels or tables.
fn plain_record(offset: u32, width: u32, height: u32, wrap: u32) -> GpuTextureInfo {
    GpuTextureInfo {
        offset,
        width,
        height,
        wrap,
        mips: NONE,
        mip_count: 1,
        rip: NONE,
        sat: NONE,
    }
}

/// The levels and tables `filter` reads, for every scene texture (technique/texture: MIP
/// levels, RIP levels, the summed-area table), appended as records after every other; colour
/// textures (base colour, reflectance, emission) are reduced in the filter's `mip_space`.
fn add_levels(a: &mut Arrays, scene: &Scene, textures: &[Cow<'_, Texture>], filter: &TextureFilter) {
    let needs = filter.filter.needs();
    if needs == Needs::default() {
        return;
    }
    let colour = colour_textures(scene);
    for (i, t) in textures.iter().enumerate() {
        let t: &Texture = t;
        let record = a.texture_infos.len() as u32;
        if needs.mips {
            let levels = pyramid::mip_levels(t, filter.mip_space, colour.contains(&i));
            a.texture_infos[i].mips = if levels.is_empty() { NONE } else { record };
            a.texture_infos[i].mip_count = 1 + levels.len() as u32;
            for level in &levels {
                add_texture(a, level).expect("a reduced level is well formed");
            }
        }
        if needs.rip {
            a.texture_infos[i].rip = a.texture_infos.len() as u32;
            for level in pyramid::rip_levels(t) {
                add_texture(a, &level).expect("a reduced level is well formed");
            }
        }
        if needs.sat {
            let (mean, table) = sat::summed_area_table(t);
            a.texture_infos[i].sat = a.texture_infos.len() as u32;
            let offset = a.texels.len() as u32;
            let wrap = a.texture_infos[i].wrap;
            a.texture_infos
                .push(plain_record(offset, t.width + 1, t.height + 1, wrap));
            a.texels.push(mean.to_array());
            a.texels.extend(table.iter().map(|v| v.to_array()));
        }
    }
}

/// The scene textures holding colours (sRGB-encoded in their files): base colours,
/// reflectances, emission.
/// The scene's textures as the method uploads them: as loaded, except the normal maps of
/// `aa_specular_toksvig`, renormalised texel by texel ([`toksvig_normal_map`]).
fn method_textures<'a>(scene: &'a Scene, method: &Method) -> Vec<Cow<'a, Texture>> {
    let toksvig = method.get::<AntiAliasing>() == Some(&AntiAliasing::SpecularToksvig);
    let normal_maps: Vec<usize> = scene
        .shapes
        .iter()
        .filter_map(|s| s.normal_map.as_ref().map(|m| m.texture))
        .collect();
    scene
        .textures
        .iter()
        .enumerate()
        .map(|(i, t)| {
            if toksvig && normal_maps.contains(&i) {
                Cow::Owned(toksvig_normal_map(t))
            } else {
                Cow::Borrowed(&**t)
            }
        })
        .collect()
}

fn colour_textures(scene: &Scene) -> Vec<usize> {
    let image = |t: &TexRgb| match t {
        TexRgb::Image { texture, .. } => Some(*texture),
        TexRgb::Constant(_) => None,
    };
    let materials = scene.materials.iter().filter_map(|m| match m {
        Material::Diffuse { albedo: c }
        | Material::Phong { reflectance: c, .. }
        | Material::Ggx { reflectance: c, .. }
        | Material::MetalRough { base_color: c, .. } => image(c),
        _ => None,
    });
    let emission = scene
        .shapes
        .iter()
        .filter_map(|s| s.emission.as_ref().and_then(|e| image(&e.radiance)));
    let projected = scene.lights.iter().filter_map(|l| match l {
        Light::Spot {
            projection: Some(p), ..
        } => image(&p.texture),
        _ => None,
    });
    materials.chain(emission).chain(projected).collect()
}

/// (texture or NONE, constant/factor) of a TexRgb.
fn tex_rgb(t: &TexRgb, textures: usize, field: &str) -> Result<(u32, [f32; 4]), String> {
    match t {
        TexRgb::Constant(c) => Ok((NONE, vec4(*c, 0.0))),
        TexRgb::Image { texture, factor } => {
            check_texture(*texture, textures, field)?;
            Ok((*texture as u32, vec4(*factor, 0.0)))
        }
    }
}

/// (texture or NONE, channel, constant/factor) of a TexScalar.
fn tex_scalar(t: &TexScalar, textures: usize, field: &str) -> Result<(u32, u32, f32), String> {
    match t {
        TexScalar::Constant(c) => Ok((NONE, 0, *c)),
        TexScalar::Image {
            texture,
            channel,
            factor,
        } => {
            check_texture(*texture, textures, field)?;
            if *channel > 3 {
                return Err(format!("{field}.channel = {channel} must be 0..=3"));
            }
            Ok((*texture as u32, *channel as u32, *factor))
        }
    }
}

fn check_texture(index: usize, textures: usize, field: &str) -> Result<(), String> {
    if index >= textures {
        return Err(format!(
            "{field}.texture = {index} is out of range (the scene has {textures} textures)"
        ));
    }
    Ok(())
}

fn material(m: &Material, textures: usize) -> Result<GpuMaterial, String> {
    let mut g = GpuMaterial {
        kind: 0,
        masking: 0,
        color_tex: NONE,
        roughness_tex: NONE,
        roughness_channel: 0,
        metallic_tex: NONE,
        metallic_channel: 0,
        fresnel: 0,
        color: [0.0; 4],
        f0: [0.0; 4],
        scalars: [0.0, 0.0, 1.0, 1.0],
        k: [0.0; 4],
    };
    match m {
        Material::Diffuse { albedo } => {
            g.kind = MaterialKind::Diffuse as u32;
            (g.color_tex, g.color) = tex_rgb(albedo, textures, "albedo")?;
        }
        Material::Phong {
            reflectance,
            exponent,
        } => {
            g.kind = MaterialKind::Phong as u32;
            (g.color_tex, g.color) = tex_rgb(reflectance, textures, "reflectance")?;
            g.scalars[0] = *exponent;
        }
        Material::Ggx {
            reflectance,
            f0,
            roughness,
            masking,
            conductor,
            ..
        } => {
            g.kind = MaterialKind::Ggx as u32;
            g.masking = match masking {
                Masking::HeightCorrelated => 0,
                Masking::Separable => 1,
            };
            (g.color_tex, g.color) = tex_rgb(reflectance, textures, "reflectance")?;
            g.f0 = vec4(*f0, 0.0);
            if let Some(ior) = conductor {
                (g.fresnel, g.f0, g.k) = (1, vec4(ior.eta, 0.0), vec4(ior.k, 0.0));
            }
            (g.roughness_tex, g.roughness_channel, g.scalars[0]) =
                tex_scalar(roughness, textures, "roughness")?;
        }
        Material::MetalRough {
            base_color,
            metallic,
            roughness,
            ..
        } => {
            g.kind = MaterialKind::MetalRough as u32;
            (g.color_tex, g.color) = tex_rgb(base_color, textures, "base_color")?;
            (g.roughness_tex, g.roughness_channel, g.scalars[0]) =
                tex_scalar(roughness, textures, "roughness")?;
            (g.metallic_tex, g.metallic_channel, g.scalars[1]) = tex_scalar(metallic, textures, "metallic")?;
        }
        Material::Mirror { reflectance } => {
            g.kind = MaterialKind::Mirror as u32;
            g.color = vec4(*reflectance, 0.0);
        }
        Material::Dielectric { int_ior, ext_ior } => {
            g.kind = MaterialKind::Dielectric as u32;
            g.scalars[2] = *int_ior;
            g.scalars[3] = *ext_ior;
        }
    }
    Ok(g)
}

fn finite(name: &str, v: Vec3) -> Result<Vec3, String> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{name} = {v} is not finite"))
    }
}

/// A shape with every field zero but its kind and material.
fn blank_shape(kind: ShapeKind, material: u32) -> GpuShape {
    GpuShape {
        kind: kind as u32,
        material,
        normal_map: NONE,
        normal_scale: 1.0,
        center: [0.0; 4],
        half_u: [0.0; 4],
        half_v: [0.0; 4],
        normal: [0.0; 4],
        dual_u: [0.0; 4],
        dual_v: [0.0; 4],
        emission: [0.0; 4],
        emission_info: [0, 0, NONE, 0],
        detail: [NONE; 4],
        detail_range: [0.0; 4],
        lightmap: [NONE, 0, 0, 0],
    }
}

fn add_shape(
    a: &mut Arrays,
    scene: &Scene,
    index: usize,
    detail: Option<&Detail>,
    cones: &ConeCache,
) -> Result<(), String> {
    let shape = &scene.shapes[index];
    if shape.material >= scene.materials.len() {
        return Err(format!(
            "material = {} is out of range (the scene has {} materials)",
            shape.material,
            scene.materials.len()
        ));
    }
    let id = index as u32;
    let mut g = match &shape.geometry {
        Geometry::Sphere { center, radius } => {
            let c = finite("center", *center)?;
            if !(*radius > 0.0 && radius.is_finite()) {
                return Err(format!("radius = {radius} must be finite and > 0"));
            }
            let mut g = blank_shape(ShapeKind::Sphere, shape.material as u32);
            g.center = vec4(c, *radius);
            g.normal[3] = 4.0 * std::f32::consts::PI * radius * radius;
            push_box(
                &mut a.analytic,
                c,
                Vec3::splat(radius * (1.0 + SPHERE_PROXY_MARGIN)),
                id,
            );
            g
        }
        Geometry::Rectangle {
            center,
            half_u,
            half_v,
        } => planar(
            a,
            ShapeKind::Rectangle,
            shape.material,
            id,
            *center,
            *half_u,
            *half_v,
        )?,
        Geometry::Disk {
            center,
            half_u,
            half_v,
        } => planar(a, ShapeKind::Disk, shape.material, id, *center, *half_u, *half_v)?,
        Geometry::Mesh(mesh) => {
            push_mesh(&mut a.mesh, mesh, id)?;
            let mut g = blank_shape(ShapeKind::Mesh, shape.material as u32);
            g.emission_info[3] = u32::from(!mesh.tangents.is_empty());
            g
        }
    };
    if let Some(map) = &shape.normal_map {
        check_texture(map.texture, scene.textures.len(), "normal_map")?;
        g.normal_map = map.texture as u32;
        g.normal_scale = map.scale;
    }
    if let Some(d) = &shape.displacement {
        add_displacement(a, &mut g, scene, d, detail, cones)?;
    }
    if let Some(Emission { radiance, two_sided }) = &shape.emission {
        let (tex, value) = tex_rgb(radiance, scene.textures.len(), "emission.radiance")?;
        if !value.iter().all(|v| v.is_finite() && *v >= 0.0) {
            return Err(format!("emission.radiance {value:?} must be finite and ≥ 0"));
        }
        g.emission = value;
        g.emission_info[0] = 1;
        g.emission_info[1] = u32::from(*two_sided);
        g.emission_info[2] = tex;
        if let Geometry::Mesh(mesh) = &shape.geometry {
            a.emissive_meshes.push(shape.name.clone());
            add_emissive_triangles(a, mesh, id, *two_sided)?;
        } else {
            a.emitters.push(id);
        }
    }
    a.shapes.push(g);
    Ok(())
}

/// Most emissive mesh triangles a scene may have: every pixel integrates each of them
/// (N² points per triangle), so a larger emitter would stall the frame; chosen here (a 12-
/// triangle box lamp is typical, a 4096-triangle one already costs 4096·N² evaluations).
pub const MAX_EMISSIVE_TRIANGLES: usize = 4096;

/// An emissive mesh's triangles as lights (area/quadrature.wgsl `emissive_mesh_quadrature`):
/// six texel records each — p0 and the shape's index (its bits), the edges p1 − p0 and
/// p2 − p0 with the area and two-sidedness, the unit front normal, the corners' uvs ((b1, b2)
/// corners without uvs, as the oracle's MeshLight). Degenerate triangles emit nothing and are
/// left out.
fn add_emissive_triangles(a: &mut Arrays, mesh: &Mesh, id: u32, two_sided: bool) -> Result<(), String> {
    for tri in &mesh.indices {
        let idx = tri.map(|i| i as usize);
        let Some(p) = idx
            .iter()
            .map(|&i| mesh.positions.get(i).copied())
            .collect::<Option<Vec<Vec3>>>()
        else {
            return Err(format!(
                "mesh indices {tri:?} are out of range ({} positions)",
                mesh.positions.len()
            ));
        };
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let cross = e1.cross(e2);
        let area = 0.5 * cross.length();
        if !(area > 0.0 && area.is_finite()) {
            continue;
        }
        let uv = if mesh.uvs.is_empty() {
            [Vec2::ZERO, Vec2::X, Vec2::Y]
        } else {
            idx.map(|i| mesh.uvs[i])
        };
        let n = cross / (2.0 * area);
        a.emissive_triangles.extend([
            [p[0].x, p[0].y, p[0].z, f32::from_bits(id)],
            [e1.x, e1.y, e1.z, area],
            [e2.x, e2.y, e2.z, f32::from(u8::from(two_sided))],
            [n.x, n.y, n.z, 0.0],
            [uv[0].x, uv[0].y, uv[1].x, uv[1].y],
            [uv[2].x, uv[2].y, 0.0, 0.0],
        ]);
    }
    let count = a.emissive_triangles.len() / 6;
    if count > MAX_EMISSIVE_TRIANGLES {
        return Err(format!(
            "the scene's emissive meshes have {count} triangles, more than the {MAX_EMISSIVE_TRIANGLES} the realtime \
             renderer integrates per pixel (simplify the emitter, or make it an area light)"
        ));
    }
    Ok(())
}

/// Appends the emissive triangle table as a texture record (6 texels wide, a row per
/// triangle); returns its index, or NONE without emissive meshes.
fn add_emissive_table(a: &mut Arrays) -> Result<u32, String> {
    if a.emissive_triangles.is_empty() {
        return Ok(NONE);
    }
    let index = a.texture_infos.len() as u32;
    let offset = u32::try_from(a.texels.len()).map_err(|_| "too many texels in total".to_string())?;
    let rows = (a.emissive_triangles.len() / 6) as u32;
    a.texture_infos.push(plain_record(offset, 6, rows, 0));
    a.texels.append(&mut a.emissive_triangles);
    Ok(index)
}

/// A displaced shape's detail inputs: its height range, the derivative map of its height
/// channel, and the cone map when the detail method steps by cones.
fn add_displacement(
    a: &mut Arrays,
    g: &mut GpuShape,
    scene: &Scene,
    d: &Displacement,
    detail: Option<&Detail>,
    cones: &ConeCache,
) -> Result<(), String> {
    check_texture(d.texture, scene.textures.len(), "displacement")?;
    if d.channel > 3 || !d.scale.is_finite() {
        return Err(format!(
            "displacement: channel {} must be 0..=3 and scale {} finite",
            d.channel, d.scale
        ));
    }
    let height = &scene.textures[d.texture];
    let (lo, hi) = height
        .texels
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), t| {
            let w = t[d.channel] * d.scale;
            (lo.min(w), hi.max(w))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        return Err("displacement: the height texture holds non-finite heights".into());
    }
    g.detail = [
        d.texture as u32,
        d.channel as u32,
        a.texture_infos.len() as u32,
        NONE,
    ];
    g.detail_range = [d.scale, lo, hi, 0.0];
    add_texture(a, &derivative_map(height, d.channel))?;
    if let Some(kind) = detail.and_then(|m| m.technique.cone_kind()) {
        g.detail[3] = a.texture_infos.len() as u32;
        add_texture(a, &cones.get(height, d.channel, d.scale, kind)[0])?;
    }
    // The horizon maps of normal and bump mapping's self-shadowing (rectangles: heightfield
    // patches), in consecutive records.
    let horizon = detail.map_or(0, |m| m.horizon);
    if horizon > 0 && g.kind == ShapeKind::Rectangle as u32 {
        let size = glam::Vec2::new(
            2.0 * Vec3::from_slice(&g.half_u[..3]).length(),
            2.0 * Vec3::from_slice(&g.half_v[..3]).length(),
        );
        g.detail[3] = a.texture_infos.len() as u32;
        for map in cones.horizon(height, d.channel, d.scale, size, horizon).iter() {
            add_texture(a, map)?;
        }
    }
    Ok(())
}

/// A rectangle or disk: plane frame with its dual basis (oracle plane.rs) and the proxy quad.
fn planar(
    a: &mut Arrays,
    kind: ShapeKind,
    material: usize,
    id: u32,
    center: Vec3,
    half_u: Vec3,
    half_v: Vec3,
) -> Result<GpuShape, String> {
    let c = finite("center", center)?;
    let hu = finite("half_u", half_u)?;
    let hv = finite("half_v", half_v)?;
    let cross = hu.cross(hv);
    let n = cross.normalize_or_zero();
    if n == Vec3::ZERO {
        return Err(format!(
            "zero area: half_u {hu} and half_v {hv} are parallel or zero"
        ));
    }
    let dual_u = hv.cross(n) / hu.dot(hv.cross(n));
    let dual_v = n.cross(hu) / hv.dot(n.cross(hu));
    let area = match kind {
        ShapeKind::Disk => std::f32::consts::PI * cross.length(),
        _ => 4.0 * cross.length(),
    };
    let mut g = blank_shape(kind, material as u32);
    g.center = vec4(c, 0.0);
    g.half_u = vec4(hu, 0.0);
    g.half_v = vec4(hv, 0.0);
    g.normal = vec4(n, area);
    g.dual_u = vec4(dual_u, 0.0);
    g.dual_v = vec4(dual_v, 0.0);
    let q = [c - hu - hv, c + hu - hv, c + hu + hv, c - hu + hv];
    for tri in [[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2]] {
        for k in tri {
            a.analytic.push(AnalyticVertex {
                position: q[k].to_array(),
                shape: id,
            });
        }
    }
    Ok(g)
}

/// The 12 triangles of the box centre ± extent, wound to face inwards.
fn push_box(out: &mut Vec<AnalyticVertex>, c: Vec3, e: Vec3, id: u32) {
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            let mut u = Vec3::ZERO;
            let mut v = Vec3::ZERO;
            let mut n = Vec3::ZERO;
            n[axis] = sign * e[axis];
            u[(axis + 1) % 3] = e[(axis + 1) % 3];
            v[(axis + 2) % 3] = e[(axis + 2) % 3];
            if sign < 0.0 {
                std::mem::swap(&mut u, &mut v);
            }
            // Counter-clockwise seen from outside is (−u−v, u−v, u+v, −u+v); reversed here.
            let q = [c + n - u - v, c + n + u - v, c + n + u + v, c + n - u + v];
            for k in [0, 2, 1, 0, 3, 2] {
                out.push(AnalyticVertex {
                    position: q[k].to_array(),
                    shape: id,
                });
            }
        }
    }
}

/// A vertex attribute the oracle uses: finite and not the zero vector.
fn usable(v: Vec3) -> bool {
    v.is_finite() && v.length_squared() > 0.0
}

fn push_mesh(out: &mut Vec<MeshVertex>, mesh: &Mesh, id: u32) -> Result<(), String> {
    let nv = mesh.positions.len();
    for (name, len) in [
        ("normals", mesh.normals.len()),
        ("uvs", mesh.uvs.len()),
        ("uv1", mesh.uv1.len()),
        ("tangents", mesh.tangents.len()),
    ] {
        if len != 0 && len != nv {
            return Err(format!("mesh has {nv} positions but {len} {name}"));
        }
    }
    for (t, tri) in mesh.indices.iter().enumerate() {
        if let Some(&bad) = tri.iter().find(|&&i| i as usize >= nv) {
            return Err(format!(
                "mesh indices[{t}] = {bad} is out of range ({nv} positions)"
            ));
        }
        let idx = tri.map(|i| i as usize);
        let p = idx.map(|i| mesh.positions[i]);
        if !p.iter().all(|q| q.is_finite()) {
            return Err(format!("mesh triangle {t} has a non-finite position"));
        }
        let ng = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or(Vec3::Z);
        let normals = if !mesh.normals.is_empty() && idx.iter().all(|&i| usable(mesh.normals[i])) {
            idx.map(|i| mesh.normals[i])
        } else {
            [ng; 3]
        };
        let (uvs, dpdu, dpdv) = if mesh.uvs.is_empty() {
            ([Vec2::ZERO, Vec2::X, Vec2::Y], p[1] - p[0], p[2] - p[0])
        } else {
            let uv = idx.map(|i| mesh.uvs[i]);
            let (du, dv) = scenes::triangle_uv_derivatives(p, uv).unwrap_or((p[1] - p[0], p[2] - p[0]));
            (uv, du, dv)
        };
        let tangents = if mesh.tangents.is_empty() {
            [Vec4::ZERO; 3]
        } else {
            idx.map(|i| mesh.tangents[i])
        };
        for k in 0..3 {
            out.push(MeshVertex {
                position: p[k].to_array(),
                shape: id,
                normal: normals[k].to_array(),
                uv: uvs[k].to_array(),
                tangent: tangents[k].to_array(),
                ng: ng.to_array(),
                dpdu: dpdu.to_array(),
                dpdv: dpdv.to_array(),
                uv1: mesh.uv1.get(idx[k]).map_or([0.0; 2], |uv| uv.to_array()),
            });
        }
    }
    Ok(())
}

fn check_rgb(name: &str, c: Vec3) -> Result<(), String> {
    if c.is_finite() && c.min_element() >= 0.0 {
        Ok(())
    } else {
        Err(format!("{name} = {c} must be finite and ≥ 0"))
    }
}

fn unit(name: &str, v: Vec3) -> Result<Vec3, String> {
    let n = finite(name, v)?.normalize_or_zero();
    if n == Vec3::ZERO {
        return Err(format!("{name} = {v} must be a non-zero direction"));
    }
    Ok(n)
}

fn light(l: &Light, textures: usize) -> Result<GpuLight, String> {
    let mut g = GpuLight {
        kind: 0,
        projection_tex: NONE,
        pad: [0; 2],
        position: [0.0; 4],
        direction: [0.0; 4],
        intensity: [0.0; 4],
        params: [0.0; 4],
        projection: [0.0; 4],
    };
    match l {
        Light::Point {
            position, intensity, ..
        } => {
            g.kind = LightKind::Point as u32;
            g.position = vec4(finite("position", *position)?, 1.0);
            check_rgb("intensity", *intensity)?;
            g.intensity = vec4(*intensity, 0.0);
        }
        Light::Spot {
            position,
            direction,
            intensity,
            cutoff_deg,
            beam_width_deg,
            projection,
            ..
        } => {
            g.kind = LightKind::Spot as u32;
            g.position = vec4(finite("position", *position)?, 1.0);
            g.direction = vec4(unit("direction", *direction)?, 0.0);
            check_rgb("intensity", *intensity)?;
            g.intensity = vec4(*intensity, 0.0);
            if !(*cutoff_deg > 0.0 && *cutoff_deg <= 90.0) {
                return Err(format!("cutoff_deg = {cutoff_deg} must be in (0, 90]"));
            }
            if !(*beam_width_deg >= 0.0 && beam_width_deg <= cutoff_deg) {
                return Err(format!(
                    "beam_width_deg = {beam_width_deg} must be in [0, cutoff_deg = {cutoff_deg}]"
                ));
            }
            let (c, b) = (cutoff_deg.to_radians(), beam_width_deg.to_radians());
            g.params = [c.cos(), b.cos(), c, b];
            if let Some(p) = projection {
                // The factor rides on the intensity (both multiply the texel).
                let (tex, factor) = tex_rgb(&p.texture, textures, "texture")?;
                if tex == NONE {
                    return Err("a projected texture must be an image".into());
                }
                let (right, _) = p
                    .frame(Vec3::from_slice(&g.direction[..3]))
                    .ok_or_else(|| format!("up = {} is along the spot's axis", p.up))?;
                check_rgb("texture.factor", Vec3::from_slice(&factor[..3]))?;
                g.intensity = vec4(*intensity * Vec3::from_slice(&factor[..3]), 0.0);
                g.projection_tex = tex;
                g.projection = vec4(right, c.tan());
            }
        }
        Light::Directional {
            direction,
            irradiance,
            angular_diameter_deg,
            ..
        } => {
            g.kind = LightKind::Directional as u32;
            g.direction = vec4(-unit("direction", *direction)?, 0.0);
            check_rgb("irradiance", *irradiance)?;
            g.intensity = vec4(*irradiance, 0.0);
            if !(0.0..180.0).contains(angular_diameter_deg) {
                return Err(format!(
                    "angular_diameter_deg = {angular_diameter_deg} must be in [0, 180)"
                ));
            }
            // h = 1 − cos θmax = 2 sin²(θmax/2), sin²θmax = h(2 − h) (oracle directional.rs).
            let half = 0.5 * angular_diameter_deg.to_radians();
            let h = 2.0 * (0.5 * half).sin().powi(2);
            g.params = [h, h * (2.0 - h), 0.0, 0.0];
        }
    }
    Ok(g)
}

fn environment(scene: &Scene) -> Result<(EnvKind, u32, [f32; 4]), String> {
    match &scene.environment {
        None => Ok((EnvKind::None, 0, [0.0; 4])),
        Some(Environment::Constant { radiance }) => {
            check_rgb("radiance", *radiance)?;
            Ok((EnvKind::Constant, 0, vec4(*radiance, 0.0)))
        }
        Some(Environment::Map { texture, scale }) => {
            check_texture(*texture, scene.textures.len(), "map")?;
            if !(scale.is_finite() && *scale >= 0.0) {
                return Err(format!("scale = {scale} must be finite and ≥ 0"));
            }
            Ok((EnvKind::Map, *texture as u32, [*scale; 4]))
        }
    }
}
