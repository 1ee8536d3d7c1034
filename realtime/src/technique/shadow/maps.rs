//! Shadow maps (Williams 1978): Depth32Float layers, one per light (k per directional light
//! under `cascades = k`), rendered every frame in a depth-only pass from the light, then
//! filtered into a visibility factor V by the method's technique (`technique/shadow/*.wgsl`,
//! `shadow/pcf.wgsl`, `shadow/pcss.wgsl`).
//!
//! Light slots are the realtime light order: the area emitters (spheres, rectangles, disks) in
//! scene order, then the scene lights. Emissive meshes get no map (their light, under `mesh_n` > 0, is
//! unshadowed). Each
//! slot owns consecutive map layers (the shaders' `shadow.slots[slot]` = first layer, count,
//! cube flag; `shadow.layers[layer]` = that layer's projection): one, one per cascade, or a
//! cube's six faces.
//!
//! | light | projection | field of view / extent |
//! |---|---|---|
//! | rectangle, disk | perspective from the centre along the emitting normal | fitted to the other shapes' bounding boxes in front of the light, at most [`MAX_FOV_DEG`] |
//! | sphere, point | perspective from the centre towards the centre of the other shapes' bounding box | the same fit |
//! | sphere, point, `point_maps = cube` | six perspective maps along ±x, ±y, ±z (a cube map, Gerasimov 2004) | 90° each, widened by [`CUBE_FACE_MARGIN_TEXELS`] on every side; depth range fitted per face |
//! | spot | perspective along the spot axis | the fit, at most 2 × the cutoff angle |
//! | directional (delta or sun disk), `cascades = 1` | orthographic along the light's direction | the scene's bounding box, square |
//! | directional, `cascades = k ≥ 2` | k orthographic maps along the light's direction (cascades) | cascade i: the camera frustum between view depths z_i and z_{i+1}, clipped to the scene's box, square, snapped to texels |
//!
//! Cascades (Zhang et al. 2006, "Parallel-Split Shadow Maps for Large-scale Virtual
//! Environments", VRCIA 2006, <https://doi.org/10.1145/1128923.1128975>; Dimitrov 2007,
//! "Cascaded Shadow Maps", NVIDIA whitepaper): the camera's view depth range [n, f] — n its
//! near plane, f the farthest corner of the scene's bounding box along its view direction (at
//! least n) — is split by the practical split scheme
//! z_i = λ·n·(f/n)^(i/k) + (1 − λ)·(n + (f − n)·i/k), i = 0..=k ([`super::cascades::pssm_splits`]; λ =
//! `split_lambda`: 0 uniform; 1 logarithmic, the split that spreads perspective aliasing
//! evenly over depth, but with a near plane close to the eye spends cascades on the first
//! metres). Cascade i is an orthographic map along the light fitted to the eight
//! corners of the camera frustum between z_i and z_{i+1} in light space ([`super::cascades::frustum_slice`]),
//! clipped to the scene's light-space box (every receiver of the slice lies in both), squared;
//! its depth range is the whole scene's, so casters outside the slice still shadow it. The
//! square is snapped to its texels (Valient 2008, "Stable Rendering of Cascaded Shadow Maps",
//! ShaderX6): texel size t = 2·half/(side − 2), the centre a whole number of texels, the side
//! t·side — so the centre's shift (≤ t/2) never uncovers the fit, and a camera moving without
//! changing the extent moves the texel grid by whole texels. A receiver takes the first cascade
//! whose far split is at or beyond its camera view depth (interval-based selection, Dimitrov
//! 2007), and each cascade's own texel size t sizes the normal offset, the slope bias and the
//! PCF/PCSS footprints in texels; the penumbra term 2·tan(θ/2) per metre is the same in every
//! cascade. Cascade edges are not blended: a kernel reaching past a cascade's square is clamped
//! to its edge texels.
//!
//! The fit: every corner of every other shape's bounding box, in light view space, must lie
//! inside the square frustum; a shape whose box crosses the light's plane (depth ≤ 0 — a wall
//! meeting a ceiling light) forces the widest field of view. One frustum per light unless a
//! point or sphere light gets a cube (`point_maps = cube`): what falls outside (beyond 150°,
//! behind a one-sided emitter, the far side of a point or sphere light's one frustum, the back
//! of a two-sided emitter) is treated as lit. A cube's receiver takes the face of the major
//! axis of its direction from the light; a kernel that reaches past a face's 90° reads the
//! face's own margin, and past the margin is clamped to its edge texels (no filtering across
//! faces). The near plane is
//! [`NEAR_MARGIN`] × the nearest box depth in front of the light (at least
//! [`MIN_NEAR_FRACTION`] × the scene radius, when a box crosses the light's plane); the far
//! plane is [`FAR_MARGIN`] × the farthest box depth. PCSS's blocker search assumes no blocker
//! nearer the light than its *search* near plane (Bavoil 2008): [`NEAR_MARGIN`] × the nearest
//! depth of the boxes wholly in front of the light — the near plane itself unless boxes cross
//! the light's plane (walls meeting a ceiling light), whose parts nearer than that are then
//! missed by the search (still in the map, so PCF sees them), instead of the search growing
//! to the whole map.
//!
//! Emitters do not shadow their own light: the light's own shape is skipped in its map
//! (`vs_shadow_analytic`), not left to the bias.
//!
//! PCSS light size w_light (overridden by the `light_size` parameter): a rectangle's larger
//! side — the penumbra of a blocker edge parallel to one side spans the light's extent across
//! it exactly (similar triangles), so for the square lights of the shadow studies the side is
//! exact and the larger side bounds every axis-aligned penumbra, where the diagonal would be
//! exact only for edges at 45°; a disk's larger diameter; a sphere's diameter; 0 for point
//! and spot lights (hard); for directional lights the term is 2·tan(θ/2) of the angular
//! diameter θ (an orthographic map: the penumbra grows by that per metre behind the blocker).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use scenes::{Geometry, Light, Scene};
use wgpu::util::DeviceExt;

use super::poisson::poisson_disk;
use super::{BlockerDepth, PointMaps, Shadow, ShadowTechnique};
use crate::gpu::DEPTH_FORMAT;
use crate::gpu_types::NONE;
use crate::technique::Method;

use super::cascades::cascades;
use super::frustum::{corners, orthographic, LightFrustum, FAR_MARGIN};
use super::poisson::POISSON_TAPS;

/// Light slots the shadow uniform holds (WGSL `slots: array<vec4<u32>, 64>`).
pub const MAX_SHADOWED_LIGHTS: usize = 64;
/// Map layers the shadow uniform holds (WGSL `layers: array<ShadowLight, 128>`): every slot's
/// one layer, or its cascades. Chosen here: room for every slot plus cascades for a few suns,
/// the uniform well under wgpu's default 64 KiB binding limit.
pub const MAX_SHADOW_LAYERS: usize = 128;
/// Widest perspective field of view (the brief's rule for lights whose frustum cannot be fitted:
/// 150° keeps the texel footprint at the edge within tan 75°/tan 0° ≈ 3.7× the centre's).
pub const MAX_FOV_DEG: f32 = 150.0;
/// Narrowest field of view (a light far from a tiny scene), so the projection stays regular.
pub const MIN_FOV_DEG: f32 = 1.0;
/// Near plane as a fraction of the nearest bounding-box depth (a margin so the nearest caster
/// is not clipped), chosen here.
pub const NEAR_MARGIN: f32 = 0.9;
/// Smallest near plane as a fraction of the scene's bounding radius (as the camera's
/// NEAR_FRACTION, frame.rs, but 10× larger: a standard-Z map loses depth precision as n/z²).
pub const MIN_NEAR_FRACTION: f32 = 1e-3;
/// Largest total size of the shadow-map array accepted (bytes), chosen here: 1 GiB.
pub const MAX_SHADOW_MAP_BYTES: u64 = 1 << 30;

/// One map layer's projection (WGSL `ShadowLight`, shadow/map_common.wgsl): a light slot's one
/// map, or one of its cascades.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuShadowLight {
    /// World to clip, depth in [0, 1], column-major.
    pub view_proj: [[f32; 4]; 4],
    /// Its inverse.
    pub inv_view_proj: [[f32; 4]; 4],
    /// Perspective: the eye. Orthographic: a point on the view axis.
    pub eye: [f32; 3],
    /// 1 perspective, 0 orthographic.
    pub perspective: f32,
    /// Unit view direction.
    pub axis: [f32; 3],
    /// The PCSS light-size term s: w_light in metres (perspective), 2·tan(θ/2) of the angular
    /// diameter θ (orthographic).
    pub light_size: f32,
    /// Near view depth.
    pub near: f32,
    /// Far view depth.
    pub far: f32,
    /// The texel footprint τ(z) = z·texel_slope + texel_offset.
    pub texel_slope: f32,
    /// See `texel_slope`.
    pub texel_offset: f32,
    /// PCSS's search near plane (the nearest blocker depth it assumes).
    pub search_near: f32,
    /// A cascade's far split in camera view depth (f32::MAX for a map over the whole scene).
    pub cascade_far: f32,
    /// 1: the layer is a shadowed light's; 0: unused.
    pub shadowed: u32,
    /// The light's own shape (a sphere or rectangle emitter) or NONE.
    pub own_shape: u32,
}
const _: () = assert!(std::mem::size_of::<GpuShadowLight>() == 2 * 64 + 4 * 16);

/// The method's parameters (WGSL `ShadowSettings`), each by its name; a technique's own are 0
/// under the others.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuShadowSettings {
    /// Constant bias, m (`bias`).
    pub bias: f32,
    /// Slope-scaled bias (`slope_bias`).
    pub slope_bias: f32,
    /// Normal offset, texels (`normal_offset`).
    pub normal_offset: f32,
    /// Map side, texels (`map`).
    pub map_side: f32,
    /// `pcf_box`'s k.
    pub kernel: u32,
    /// `pcf_poisson`'s taps.
    pub taps: u32,
    /// `pcss`'s blocker-search taps.
    pub blocker_samples: u32,
    /// `pcss`'s filter taps.
    pub filter_samples: u32,
    /// `pcf_poisson`'s disk radius, texels.
    pub radius: f32,
    /// `pcss`'s `blocker_depth = ignore` (1) or the search (0).
    pub ignore_blocker_depth: u32,
    /// Receiver-plane depth bias (1) or none (0): `receiver_plane`, multi-tap kernels only.
    pub receiver_plane: u32,
    /// Poisson taps rotated per pixel (1) or fixed (0): `rotate`, Poisson-tap kernels only.
    pub rotate: u32,
}
const _: () = assert!(std::mem::size_of::<GpuShadowSettings>() == 3 * 16);

/// Everything the shadow pass and the shading read (WGSL `ShadowUniforms`, group 0 binding 8).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuShadowUniforms {
    /// The method's parameters.
    pub settings: GpuShadowSettings,
    /// The Poisson taps, two per entry.
    pub poisson: [[f32; 4]; POISSON_TAPS / 2],
    /// Per light slot: its first layer, its layer count (1, the cascades, or a cube's 6), 1
    /// for a cube, unused.
    pub slots: [[u32; 4]; MAX_SHADOWED_LIGHTS],
    /// One projection per map layer.
    pub layers: [GpuShadowLight; MAX_SHADOW_LAYERS],
}
const _: () = assert!(
    std::mem::size_of::<GpuShadowUniforms>()
        == 3 * 16
            + POISSON_TAPS * 8
            + MAX_SHADOWED_LIGHTS * 16
            + MAX_SHADOW_LAYERS * std::mem::size_of::<GpuShadowLight>()
);
// wgpu's default `max_uniform_buffer_binding_size` (the limit gpu.rs requests).
const _: () = assert!(std::mem::size_of::<GpuShadowUniforms>() <= 64 << 10);

/// The frusta of every light slot of `scene` (area emitters, then scene lights), one per map
/// layer of the slot: one, or `shadow.cascades` for a directional light (module docs) seen
/// through a `aspect` (width / height) film. The PCSS light size is overridden by the method's
/// `light_size` where given.
pub fn light_frusta(scene: &Scene, shadow: &Shadow, aspect: f32) -> Vec<Vec<LightFrustum>> {
    let light_size = light_size_override(shadow);
    let mut out = Vec::new();
    for (i, shape) in scene.shapes.iter().enumerate() {
        if shape.emission.is_none() {
            continue;
        }
        let (eye, axis, up, size) = match &shape.geometry {
            Geometry::Mesh(_) => continue,
            Geometry::Rectangle {
                center,
                half_u,
                half_v,
            }
            | Geometry::Disk {
                center,
                half_u,
                half_v,
            } => {
                let axis = half_u.cross(*half_v).normalize_or(Vec3::NEG_Y);
                let size = 2.0 * half_u.length().max(half_v.length());
                (*center, axis, Some(*half_u), size)
            }
            Geometry::Sphere { center, radius } => {
                let size = light_size.unwrap_or(2.0 * radius);
                if shadow.point_maps == PointMaps::Cube {
                    out.push(cube(scene, &shape.name, Some(i), *center, size, shadow.map));
                    continue;
                }
                let axis = towards_scene(scene, Some(i), *center);
                (*center, axis, None, 2.0 * radius)
            }
        };
        let size = light_size.unwrap_or(size);
        out.push(vec![perspective(
            scene,
            &shape.name,
            Some(i),
            eye,
            axis,
            up,
            Fov::Fit(MAX_FOV_DEG),
            size,
        )]);
    }
    for light in &scene.lights {
        let name = light.name();
        out.push(match light {
            Light::Point { position, .. } if shadow.point_maps == PointMaps::Cube => cube(
                scene,
                name,
                None,
                *position,
                light_size.unwrap_or(0.0),
                shadow.map,
            ),
            Light::Point { position, .. } => {
                let axis = towards_scene(scene, None, *position);
                vec![perspective(
                    scene,
                    name,
                    None,
                    *position,
                    axis,
                    None,
                    Fov::Fit(MAX_FOV_DEG),
                    light_size.unwrap_or(0.0),
                )]
            }
            Light::Spot {
                position,
                direction,
                cutoff_deg,
                ..
            } => {
                let axis = direction.normalize_or(Vec3::NEG_Y);
                let fov = (2.0 * cutoff_deg).min(MAX_FOV_DEG);
                vec![perspective(
                    scene,
                    name,
                    None,
                    *position,
                    axis,
                    None,
                    Fov::Fit(fov),
                    light_size.unwrap_or(0.0),
                )]
            }
            Light::Directional {
                direction,
                angular_diameter_deg,
                ..
            } => {
                let theta = light_size.unwrap_or(*angular_diameter_deg);
                let size = 2.0 * (0.5 * theta.to_radians()).tan();
                let axis = direction.normalize_or(Vec3::NEG_Y);
                if shadow.cascades <= 1 {
                    vec![orthographic(scene, name, axis, size, None)]
                } else {
                    cascades(scene, name, axis, size, shadow, aspect)
                }
            }
        });
    }
    out
}

/// Texels a cube face extends past its 90° on every side, so that a filter kernel at a face's
/// edge still reads the face's own map (chosen here: PCF's widest box kernel is 15 texels,
/// PCSS's filter radius is clamped to the map's penumbra search, and 16 covers the former).
pub const CUBE_FACE_MARGIN_TEXELS: f32 = 16.0;

/// The six faces of a cube map at `eye` (Gerasimov 2004, "Omnidirectional Shadow Mapping", GPU
/// Gems ch. 12), in the order the shaders pick them (shadow/map_common.wgsl `shadow_layer`):
/// +x, −x, +y, −y, +z, −z; each a 90° square frustum widened by [`CUBE_FACE_MARGIN_TEXELS`]
/// on each side of a `side`² map, its depth range fitted as any perspective map's.
fn cube(scene: &Scene, name: &str, own: Option<usize>, eye: Vec3, size: f32, side: u32) -> Vec<LightFrustum> {
    // tan(half) = 1 + margin: the face's 90° plus the margin's texels at its edge.
    let fov = 2.0
        * (1.0 + 2.0 * CUBE_FACE_MARGIN_TEXELS / side as f32)
            .atan()
            .to_degrees();
    [
        (Vec3::X, Vec3::Y),
        (Vec3::NEG_X, Vec3::Y),
        (Vec3::Y, Vec3::Z),
        (Vec3::NEG_Y, Vec3::Z),
        (Vec3::Z, Vec3::Y),
        (Vec3::NEG_Z, Vec3::Y),
    ]
    .into_iter()
    .zip(["+x", "-x", "+y", "-y", "+z", "-z"])
    .map(|((axis, up), face)| {
        let mut f = perspective(
            scene,
            &format!("{name} cube {face}"),
            own,
            eye,
            axis,
            Some(up),
            Fov::Fixed(fov),
            size,
        );
        f.cube_face = true;
        f
    })
    .collect()
}

/// A perspective map's field of view.
#[derive(Clone, Copy, Debug)]
enum Fov {
    /// Fitted to the other shapes, at most this many degrees.
    Fit(f32),
    /// Exactly this many degrees (a cube face).
    Fixed(f32),
}

/// Unit direction from `eye` to the centre of the bounding box of every shape but `own`.
fn towards_scene(scene: &Scene, own: Option<usize>, eye: Vec3) -> Vec3 {
    let (lo, hi) = scene
        .shapes
        .iter()
        .enumerate()
        .filter(|(i, _)| Some(*i) != own)
        .map(|(_, s)| s.geometry.bounds())
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), (a, b)| {
            (lo.min(a), hi.max(b))
        });
    let target = if lo.x <= hi.x { 0.5 * (lo + hi) } else { Vec3::ZERO };
    (target - eye).try_normalize().unwrap_or(Vec3::NEG_Y)
}

/// A perspective frustum from `eye` along `axis` fitted to the other shapes (module docs), its
/// field of view fitted (at most the given degrees) or fixed.
#[allow(clippy::too_many_arguments)]
fn perspective(
    scene: &Scene,
    name: &str,
    own: Option<usize>,
    eye: Vec3,
    axis: Vec3,
    up: Option<Vec3>,
    fov: Fov,
    size: f32,
) -> LightFrustum {
    let up = up
        .map(|u| u - axis * u.dot(axis))
        .and_then(|u| u.try_normalize())
        .unwrap_or_else(|| axis.any_orthonormal_vector());
    let view = Mat4::look_to_rh(eye, axis, up);
    let (_, radius) = scene.bounding_sphere();
    let (mut tan_max, mut z_min, mut z_max, mut crossing) = (0.0f32, f32::INFINITY, 0.0f32, false);
    for (i, shape) in scene.shapes.iter().enumerate() {
        if Some(i) == own {
            continue;
        }
        let v = corners(shape.geometry.bounds()).map(|c| view.transform_point3(c));
        let (lo, hi) = v.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(-p.z), hi.max(-p.z))
        });
        // Entirely behind the light (or NaN): nothing to fit.
        if hi.is_nan() || hi <= 0.0 {
            continue;
        }
        z_max = z_max.max(hi);
        if lo <= 0.0 {
            crossing = true;
            continue;
        }
        z_min = z_min.min(lo);
        for p in v {
            tan_max = tan_max.max(p.x.abs().max(p.y.abs()) / -p.z);
        }
    }
    let half = match fov {
        Fov::Fixed(deg) => 0.5 * deg.to_radians(),
        Fov::Fit(max) if crossing => 0.5 * max.to_radians(),
        Fov::Fit(max) => (tan_max * 1.01)
            .atan()
            .clamp(0.5 * MIN_FOV_DEG.to_radians(), 0.5 * max.to_radians()),
    };
    let near_floor = MIN_NEAR_FRACTION * radius;
    let near = if crossing || !z_min.is_finite() {
        near_floor
    } else {
        (NEAR_MARGIN * z_min).max(near_floor)
    };
    let far = FAR_MARGIN * z_max.max(near);
    let search_near = if z_min.is_finite() {
        (NEAR_MARGIN * z_min).max(near)
    } else {
        near
    };
    let proj = Mat4::perspective_rh(2.0 * half, 1.0, near, far);
    LightFrustum {
        name: name.to_string(),
        view_proj: proj * view,
        eye,
        axis,
        perspective: true,
        extent: (2.0 * half).to_degrees(),
        near,
        far,
        search_near,
        size,
        own_shape: own,
        slice: None,
        cube_face: false,
    }
}

/// The WGSL `ShadowLight` of frustum `f` on a `side`² map.
fn gpu_light(f: &LightFrustum, side: u32) -> GpuShadowLight {
    let (a, b) = f.texel(side);
    GpuShadowLight {
        view_proj: f.view_proj.to_cols_array_2d(),
        inv_view_proj: f.view_proj.inverse().to_cols_array_2d(),
        eye: f.eye.to_array(),
        perspective: if f.perspective { 1.0 } else { 0.0 },
        axis: f.axis.to_array(),
        light_size: f.size,
        near: f.near,
        far: f.far,
        texel_slope: a,
        texel_offset: b,
        search_near: f.search_near,
        cascade_far: f.slice.map_or(f32::MAX, |s| s.1),
        shadowed: 1,
        own_shape: f.own_shape.map_or(NONE, |s| s as u32),
    }
}

/// The shadow uniform of `method` over `frusta` (per light slot, its layers' frusta; at most
/// [`MAX_SHADOWED_LIGHTS`] slots and [`MAX_SHADOW_LAYERS`] layers, the rest ignored — `ShadowMaps`
/// refuses more); all zero when unshadowed: V = 1 everywhere.
pub fn shadow_uniforms(method: &Method, frusta: &[Vec<LightFrustum>]) -> GpuShadowUniforms {
    let mut u = GpuShadowUniforms::zeroed();
    let Some(&s) = method.get::<Shadow>() else {
        return u;
    };
    let multi_tap = !matches!(s.technique, ShadowTechnique::Hard | ShadowTechnique::PcfHw2x2);
    let mut g = GpuShadowSettings {
        bias: s.bias,
        slope_bias: s.slope_bias,
        normal_offset: s.normal_offset,
        map_side: s.map as f32,
        receiver_plane: u32::from(s.receiver_plane && multi_tap),
        rotate: u32::from(s.rotate && s.uses_poisson_taps()),
        ..GpuShadowSettings::zeroed()
    };
    match s.technique {
        ShadowTechnique::Hard | ShadowTechnique::PcfHw2x2 => {}
        ShadowTechnique::PcfBox { kernel } => g.kernel = kernel,
        ShadowTechnique::PcfPoisson { taps, radius } => {
            g.taps = taps;
            g.radius = radius;
        }
        ShadowTechnique::Pcss {
            blocker_samples,
            filter_samples,
            blocker_depth,
            ..
        } => {
            g.blocker_samples = blocker_samples;
            g.filter_samples = filter_samples;
            g.ignore_blocker_depth = u32::from(blocker_depth == BlockerDepth::Ignore);
        }
    }
    u.settings = g;
    let disk = poisson_disk();
    for (k, pair) in u.poisson.iter_mut().enumerate() {
        *pair = [
            disk[2 * k][0],
            disk[2 * k][1],
            disk[2 * k + 1][0],
            disk[2 * k + 1][1],
        ];
    }
    let mut first = 0;
    for (slot, layers) in frusta.iter().enumerate().take(MAX_SHADOWED_LIGHTS) {
        let cube = u32::from(layers.first().is_some_and(|f| f.cube_face));
        u.slots[slot] = [first as u32, layers.len() as u32, cube, 0];
        for f in layers {
            if let Some(layer) = u.layers.get_mut(first) {
                *layer = gpu_light(f, s.map);
            }
            first += 1;
        }
    }
    u
}

/// The PCSS light-size override of a method, if any.
fn light_size_override(shadow: &Shadow) -> Option<f32> {
    match shadow.technique {
        ShadowTechnique::Pcss { light_size, .. } => light_size,
        _ => None,
    }
}

/// The shadow maps of one render: the uniform, the map array and its per-layer views, the
/// sampling bind group (group 2).
pub(crate) struct ShadowMaps {
    /// `GpuShadowUniforms` (group 0, binding 8).
    pub(crate) uniform: wgpu::Buffer,
    /// (layer name, depth view of the layer), in layer order; empty when unshadowed.
    pub(crate) layers: Vec<(String, wgpu::TextureView)>,
    /// The array view and the two comparison samplers.
    pub(crate) bind_group: wgpu::BindGroup,
    /// The frusta, in layer order (empty when unshadowed).
    pub(crate) frusta: Vec<LightFrustum>,
}

impl ShadowMaps {
    /// The maps of `method` for `scene` seen through a film of aspect `aspect` (width / height;
    /// the cascades' camera frustum), or a 1×1 placeholder layer when it is unshadowed;
    /// `layout` is the group-2 layout. Errors: too many lights or layers, too large an array.
    pub(crate) fn new(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        scene: &Scene,
        method: &Method,
        aspect: f32,
        limits: &wgpu::Limits,
    ) -> Result<ShadowMaps, String> {
        let shadow = method.get::<Shadow>();
        let per_slot = match shadow {
            Some(s) => light_frusta(scene, s, aspect),
            None => Vec::new(),
        };
        let side = shadow.map_or(1, |s| s.map);
        if per_slot.len() > MAX_SHADOWED_LIGHTS {
            return Err(format!(
                "method {method}: the scene has {} lights, at most {MAX_SHADOWED_LIGHTS} can be shadowed",
                per_slot.len()
            ));
        }
        let frusta: Vec<LightFrustum> = per_slot.iter().flatten().cloned().collect();
        let cascades = shadow.map_or(1, |s| s.cascades);
        if frusta.len() > MAX_SHADOW_LAYERS {
            return Err(format!(
                "method {method}: the scene's {} lights need {} shadow-map layers ({cascades} per \
                 directional light), at most {MAX_SHADOW_LAYERS} fit the shadow uniform; lower `cascades`",
                per_slot.len(),
                frusta.len()
            ));
        }
        let layers = frusta.len().max(1) as u32;
        let bytes = 4 * u64::from(side) * u64::from(side) * u64::from(layers);
        if side > limits.max_texture_dimension_2d
            || layers > limits.max_texture_array_layers
            || bytes > MAX_SHADOW_MAP_BYTES
        {
            return Err(format!(
                "method {method}: {layers} shadow maps of {side}² texels ({} MiB; {cascades} per \
                 directional light) exceed the adapter's texture limits ({} texels per side, {} \
                 layers) or {} MiB",
                bytes >> 20,
                limits.max_texture_dimension_2d,
                limits.max_texture_array_layers,
                MAX_SHADOW_MAP_BYTES >> 20
            ));
        }
        let uniforms = shadow_uniforms(method, &per_slot);
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("shadow uniforms (settings, Poisson taps, light frusta)"),
            contents: bytemuck::bytes_of(&uniforms),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(if frusta.is_empty() {
                "shadow maps (placeholder: unshadowed method)"
            } else {
                "shadow maps (one layer per light, or per cascade)"
            }),
            size: wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let layer_views = frusta
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let view = texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(&format!("shadow map layer {i} ({})", f.name)),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: i as u32,
                    array_layer_count: Some(1),
                    ..Default::default()
                });
                (f.name.clone(), view)
            })
            .collect();
        let bind_group = map_bind_group(device, layout, &texture);
        Ok(ShadowMaps {
            uniform,
            layers: layer_views,
            bind_group,
            frusta,
        })
    }
}

/// Group 2 of the shading pipelines: the map array (`texture`) and its two comparison
/// samplers, nearest and bilinear.
fn map_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    texture: &wgpu::Texture,
) -> wgpu::BindGroup {
    let array = texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("shadow map array view"),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let sampler = |label: &str, filter: wgpu::FilterMode| {
        device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some(label),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: filter,
            min_filter: filter,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        })
    };
    let nearest = sampler("shadow comparison sampler (nearest)", wgpu::FilterMode::Nearest);
    let bilinear = sampler("shadow comparison sampler (bilinear)", wgpu::FilterMode::Linear);
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("shadow map bind group"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&array),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(&nearest),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(&bilinear),
            },
        ],
    })
}

#[cfg(test)]
pub(in crate::technique::shadow) mod tests {
    use super::*;
    use scenes::{Camera, Emission, Film, Material, RenderSettings, Shape, TexRgb};
    use std::path::PathBuf;

    pub(in crate::technique::shadow) fn scene(shapes: Vec<(Geometry, bool)>, lights: Vec<Light>) -> Scene {
        Scene {
            source: PathBuf::from("<shadow test>"),
            camera: Camera::look_at(Vec3::new(0.0, 1.0, 3.0), Vec3::ZERO, Vec3::Y, 40.0),
            film: Film { width: 4, height: 4 },
            render: RenderSettings::default(),
            textures: Vec::new(),
            materials: vec![Material::Diffuse {
                albedo: TexRgb::Constant(Vec3::splat(0.5)),
            }],
            shapes: shapes
                .into_iter()
                .enumerate()
                .map(|(i, (geometry, emits))| Shape {
                    name: format!("s{i}"),
                    geometry,
                    material: 0,
                    emission: emits.then_some(Emission {
                        radiance: TexRgb::Constant(Vec3::ONE),
                        two_sided: false,
                    }),
                    normal_map: None,
                    displacement: None,
                })
                .collect(),
            lights,
            environment: None,
            provenance: Default::default(),
        }
    }

    /// Every slot's frusta for `shadow`, each slot asserted to have one layer.
    pub(in crate::technique::shadow) fn single_layers(s: &Scene, shadow: &Shadow) -> Vec<LightFrustum> {
        light_frusta(s, shadow, 1.0)
            .into_iter()
            .map(|layers| {
                assert_eq!(layers.len(), 1, "{layers:?}");
                layers[0].clone()
            })
            .collect()
    }

    pub(in crate::technique::shadow) fn hard() -> Shadow {
        Shadow::new(ShadowTechnique::Hard)
    }

    pub(in crate::technique::shadow) fn rect(center: Vec3, half: f32, normal_down: bool) -> Geometry {
        let (u, v) = (Vec3::X * half, Vec3::Z * half);
        Geometry::Rectangle {
            center,
            half_u: if normal_down { u } else { v },
            half_v: if normal_down { v } else { u },
        }
    }

    /// The soft-shadow layout: a 0.5 m light 1.5 m over a 4 m floor, a blocker at 0.5 m. The
    /// fitted frustum holds every floor corner, its near plane sits 10 % before the blocker, and
    /// points project where the frustum says.
    #[test]
    fn rectangle_light_frustum_fits_the_scene() {
        let s = scene(
            vec![
                (rect(Vec3::ZERO, 2.0, false), false),
                (rect(Vec3::new(0.0, 0.5, 0.0), 0.2, false), false),
                (rect(Vec3::new(-0.8, 1.5, 0.0), 0.25, true), true),
            ],
            Vec::new(),
        );
        let f = single_layers(&s, &hard());
        assert_eq!(f.len(), 1);
        let f = &f[0];
        assert!(f.perspective && f.axis.abs_diff_eq(Vec3::NEG_Y, 1e-6), "{f:?}");
        assert_eq!((f.own_shape, f.size), (Some(2), 0.5));
        assert!(
            (f.near - 0.9).abs() < 1e-5 && (f.far - 1.515).abs() < 1e-4,
            "{}",
            f.describe()
        );
        // The farthest floor corner is 2.8 m off-axis at depth 1.5: tan = 2.8/1.5.
        let want = 2.0 * (2.8f32 / 1.5 * 1.01).atan().to_degrees();
        assert!((f.extent - want).abs() < 1e-3, "fov {} vs {want}", f.extent);
        for corner in [
            Vec3::new(2.0, 0.0, 2.0),
            Vec3::new(-2.0, 0.0, -2.0),
            Vec3::new(0.2, 0.5, 0.2),
        ] {
            let c = f.view_proj * corner.extend(1.0);
            let ndc = c.truncate() / c.w;
            assert!(
                ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && (0.0..=1.0).contains(&ndc.z),
                "{corner}: {ndc}"
            );
        }
        // Texel footprint: 2·tan(fov/2)/side per metre of depth.
        let (a, b) = f.texel(1024);
        assert!((a - 2.0 * 2.8 * 1.01 / 1.5 / 1024.0).abs() < 1e-6 && b == 0.0);
    }

    /// A point light under `point_maps = cube`: six faces along +x, −x, +y, −y, +z, −z (the
    /// order `shadow_layer` picks them in), each a little over 90° so its 16-texel margin
    /// overlaps the next face; every direction's point projects inside the face of its major
    /// axis; the slot is flagged as a cube in the uniform.
    #[test]
    fn a_cube_has_six_faces_in_the_shaders_order() {
        let s = scene(
            vec![(rect(Vec3::ZERO, 2.0, false), false)],
            vec![Light::Point {
                name: "bulb".into(),
                position: Vec3::new(0.0, 1.0, 0.0),
                intensity: Vec3::ONE,
            }],
        );
        let shadow = Shadow {
            point_maps: PointMaps::Cube,
            ..hard()
        };
        let slots = light_frusta(&s, &shadow, 1.0);
        assert_eq!(slots.len(), 1);
        let faces = &slots[0];
        let axes = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];
        assert_eq!(faces.len(), 6);
        for (f, axis) in faces.iter().zip(axes) {
            assert!(f.cube_face && f.perspective && f.axis == axis, "{}", f.describe());
            let want = 2.0 * (1.0 + 32.0 / 1024.0f32).atan().to_degrees();
            assert!(
                (f.extent - want).abs() < 1e-4 && f.extent > 90.0,
                "{}",
                f.describe()
            );
            // A point 45° off the face's axis towards each neighbour is still inside it.
            for off in [f.axis.any_orthonormal_vector(), -f.axis.any_orthonormal_vector()] {
                let p = Vec3::new(0.0, 1.0, 0.0) + f.axis + off * 0.999;
                let c = f.view_proj * p.extend(1.0);
                let ndc = c.truncate() / c.w;
                assert!(
                    ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && c.w > 0.0,
                    "{}: {ndc}",
                    f.describe()
                );
            }
        }
        let u = shadow_uniforms(&Method::of(shadow, 0), &slots);
        assert_eq!(u.slots[0], [0, 6, 1, 0]);
        let single = light_frusta(&s, &hard(), 1.0);
        assert_eq!(single[0].len(), 1);
        assert_eq!(
            shadow_uniforms(&Method::of(hard(), 0), &single).slots[0],
            [0, 1, 0, 0]
        );
        // A sphere emitter gets a cube too, its own shape left out of every face, its
        // diameter the PCSS light size; the rectangle emitter keeps its one frustum.
        let lamps = scene(
            vec![
                (rect(Vec3::ZERO, 2.0, false), false),
                (
                    Geometry::Sphere {
                        center: Vec3::Y,
                        radius: 0.1,
                    },
                    true,
                ),
                (rect(Vec3::new(0.0, 2.0, 0.0), 0.2, true), true),
            ],
            Vec::new(),
        );
        let slots = light_frusta(&lamps, &shadow, 1.0);
        assert_eq!(slots.iter().map(Vec::len).collect::<Vec<_>>(), [6, 1]);
        assert!(slots[0]
            .iter()
            .all(|f| f.cube_face && f.own_shape == Some(1) && (f.size - 0.2).abs() < 1e-6));
        assert!(!slots[1][0].cube_face);
    }

    /// A wall crossing the light's plane forces the widest field of view and the smallest near
    /// plane; spots are capped at twice their cutoff; suns get square orthographic boxes.
    #[test]
    fn crossing_shapes_spots_and_suns() {
        let wall = Geometry::Rectangle {
            center: Vec3::new(1.0, 1.0, 0.0),
            half_u: Vec3::Y,
            half_v: Vec3::Z,
        };
        let spot = Light::Spot {
            name: "spot".into(),
            position: Vec3::new(0.0, 3.0, 0.0),
            direction: Vec3::NEG_Y,
            intensity: Vec3::ONE,
            cutoff_deg: 20.0,
            beam_width_deg: 10.0,
            projection: None,
        };
        let sun = Light::Directional {
            name: "sun".into(),
            direction: Vec3::new(0.0, -1.0, -1.0),
            irradiance: Vec3::ONE,
            angular_diameter_deg: 2.0,
        };
        let s = scene(
            vec![
                (rect(Vec3::ZERO, 2.0, false), false),
                (wall, false),
                (rect(Vec3::new(0.0, 1.5, 0.0), 0.25, true), true),
            ],
            vec![spot, sun],
        );
        let f = single_layers(&s, &hard());
        assert_eq!(f.len(), 3);
        let radius = s.bounding_sphere().1;
        assert!(
            (f[0].extent - MAX_FOV_DEG).abs() < 1e-3
                && (f[0].near - MIN_NEAR_FRACTION * radius).abs() < 1e-6
                && (f[0].search_near - 0.9 * 1.5).abs() < 1e-5
        );
        assert!(
            (f[1].extent - 40.0).abs() < 1e-3 && f[1].size == 0.0,
            "{}",
            f[1].describe()
        );
        assert!(!f[2].perspective && (f[2].size - 2.0 * 1f32.to_radians().tan()).abs() < 1e-7);
        for c in corners(s.bounds()) {
            let p = f[2].view_proj * c.extend(1.0);
            assert!(
                p.x.abs() <= 1.0 && p.y.abs() <= 1.0 && (0.0..=1.0).contains(&p.z),
                "{c}: {p}"
            );
        }
        // light_size overrides every light: metres, degrees for the sun.
        let pcss = Shadow::new(ShadowTechnique::Pcss {
            blocker_samples: 16,
            filter_samples: 16,
            light_size: Some(4.0),
            blocker_depth: BlockerDepth::Search,
        });
        let g = single_layers(&s, &pcss);
        assert_eq!((g[0].size, g[1].size), (4.0, 4.0));
        assert!((g[2].size - 2.0 * 2f32.to_radians().tan()).abs() < 1e-7);
    }

    pub(in crate::technique::shadow) fn sun(direction: Vec3) -> Light {
        Light::Directional {
            name: "sun".into(),
            direction,
            irradiance: Vec3::ONE,
            angular_diameter_deg: 1.0,
        }
    }

    pub(in crate::technique::shadow) fn cascaded(k: u32, lambda: f32) -> Shadow {
        Shadow {
            cascades: k,
            split_lambda: lambda,
            map: 512,
            ..hard()
        }
    }

    /// The uniform: each slot's first layer and layer count, each cascade's far split in
    /// `search[1]`, the rotation flag only for the Poisson-tap techniques.
    #[test]
    fn uniform_maps_slots_to_layers() {
        let s = scene(
            vec![
                (rect(Vec3::ZERO, 2.0, false), false),
                (rect(Vec3::new(0.0, 1.5, 0.0), 0.25, true), true),
            ],
            vec![sun(Vec3::new(0.0, -1.0, -1.0))],
        );
        let mut shadow = cascaded(3, 0.5);
        shadow.rotate = true;
        let frusta = light_frusta(&s, &shadow, 1.0);
        let u = shadow_uniforms(&Method::of(shadow, 0), &frusta);
        assert_eq!((u.slots[0], u.slots[1]), ([0, 1, 0, 0], [1, 3, 0, 0]));
        assert_eq!(u.layers[0].cascade_far, f32::MAX);
        assert_eq!(frusta[1].len(), 3);
        for (layer, f) in u.layers[1..4].iter().zip(&frusta[1]) {
            assert_eq!(layer.cascade_far, f.slice.unwrap().1);
        }
        assert_eq!(u.layers[4].shadowed, 0, "unused layers are unshadowed");
        assert_eq!(u.settings.rotate, 0, "shadow_hard has no taps to rotate");
        let poisson = Shadow {
            technique: ShadowTechnique::PcfPoisson { taps: 8, radius: 2.0 },
            ..shadow
        };
        let u = shadow_uniforms(&Method::of(poisson, 0), &frusta);
        assert_eq!(u.settings.rotate, 1);
    }
}
