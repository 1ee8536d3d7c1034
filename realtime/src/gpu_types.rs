//! The data the shaders read: `#[repr(C)]` Pod structs in the field order of their WGSL
//! counterparts in `shaders/common.wgsl` (and `passes.wgsl` for the vertex layouts), each with a
//! size assertion, and the kind codes the shaders switch on. The shadow maps' structs live with
//! their technique in shadow/maps.rs (`technique/shadow/map_common.wgsl`), the visibility AOV's in
//! visibility.rs.
//!
//! Layout rules: storage and uniform structs follow WGSL's host-shareable layout (vec4 and
//! mat4 aligned to 16 bytes, scalars to 4); every struct here is a multiple of 16 bytes made of
//! scalar quads and vec4s, so `#[repr(C)]` and WGSL agree byte for byte.

use bytemuck::{Pod, Zeroable};

/// Marker for "no texture" / "none" in index fields (WGSL `NONE`).
pub const NONE: u32 = u32::MAX;

/// Shape kinds (WGSL `SHAPE_*`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum ShapeKind {
    /// Triangle mesh, rasterised.
    Mesh = 0,
    /// Sphere, ray traced on its bounding box.
    Sphere = 1,
    /// Parallelogram, ray traced on itself.
    Rectangle = 2,
    /// Ellipse, ray traced on its circumscribed parallelogram.
    Disk = 3,
}

/// Material kinds (WGSL `MAT_*`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum MaterialKind {
    /// Lambert.
    Diffuse = 0,
    /// Normalized Phong lobe.
    Phong = 1,
    /// GGX with Schlick Fresnel.
    Ggx = 2,
    /// glTF metallic-roughness.
    MetalRough = 3,
    /// Ideal mirror.
    Mirror = 4,
    /// Ideal dielectric.
    Dielectric = 5,
}

/// Punctual and distant light kinds (WGSL `LIGHT_*`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum LightKind {
    /// Isotropic point light.
    Point = 0,
    /// Spot light (Mitsuba falloff).
    Spot = 1,
    /// Directional light, delta or sun disk.
    Directional = 2,
}

/// Environment kinds (WGSL `ENV_*`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum EnvKind {
    /// No environment (black).
    None = 0,
    /// Constant radiance.
    Constant = 1,
    /// Equirectangular map × scale.
    Map = 2,
}

/// Per-frame uniform (WGSL `FrameUniforms`): the fields every method has. In the buffer the
/// families' blocks follow it (WGSL `families`, [`crate::technique::family_uniform_bytes`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    /// Projection × view (reversed-Z, infinite far plane), column-major.
    pub view_proj: [[f32; 4]; 4],
    /// Camera position, near-plane distance.
    pub cam_pos: [f32; 4],
    /// First column of the camera-to-world 3×3 matrix.
    pub cam_x: [f32; 4],
    /// Second column.
    pub cam_y: [f32; 4],
    /// Third column.
    pub cam_z: [f32; 4],
    /// Unit view direction.
    pub cam_forward: [f32; 4],
    /// Final film width, height, tan(fov_y/2), aspect W/H.
    pub film: [f32; 4],
    /// Supersampling factor k, 1/k, unused, unused.
    pub ssaa: [f32; 4],
    /// Environment constant radiance (rgb), or the map's scale in x.
    pub env_radiance: [f32; 4],
    /// Environment kind, texture index, quadrature n, unused.
    pub env_info: [u32; 4],
    /// Lights, area emitters, area quadrature n, unused.
    pub counts: [u32; 4],
    /// Emissive meshes as lights: the triangle table's texture record or NONE (none, or
    /// `mesh_n` = 0), the quadrature n per triangle, unused, unused.
    pub mesh_lights: [u32; 4],
    /// Energy compensation: the method (WGSL `ENERGY_*`), its table's texture record or NONE,
    /// unused, unused.
    pub energy: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<FrameUniforms>() == 64 + 12 * 16);

/// One shape (WGSL `Shape`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuShape {
    /// [`ShapeKind`].
    pub kind: u32,
    /// Material index.
    pub material: u32,
    /// Normal-map texture or [`NONE`].
    pub normal_map: u32,
    /// glTF `normalTexture.scale`.
    pub normal_scale: f32,
    /// Centre (xyz), radius (w, spheres).
    pub center: [f32; 4],
    /// Half edge / semi-axis u.
    pub half_u: [f32; 4],
    /// Half edge / semi-axis v.
    pub half_v: [f32; 4],
    /// Unit front normal (planar shapes); w = surface area.
    pub normal: [f32; 4],
    /// Dual basis vector of `half_u` in the plane.
    pub dual_u: [f32; 4],
    /// Dual basis vector of `half_v` in the plane.
    pub dual_v: [f32; 4],
    /// Emitted radiance (constant) or its factor (textured).
    pub emission: [f32; 4],
    /// Emits (0/1), two-sided (0/1), radiance texture or [`NONE`], mesh has tangents (0/1).
    pub emission_info: [u32; 4],
    /// Displacement: height texture or [`NONE`], its channel, the derivative map, the cone
    /// map or [`NONE`] (only under `cone_step`).
    pub detail: [u32; 4],
    /// Displacement: scale s (metres per unit h), min and max of s·h over the texels, unused.
    pub detail_range: [f32; 4],
    /// Light map: the atlas texture or [`NONE`] (no chart), the chart's first atlas texel x
    /// and y, its width | height << 16 in texels.
    pub lightmap: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuShape>() == 16 + 11 * 16);

/// One material (WGSL `Material`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuMaterial {
    /// [`MaterialKind`].
    pub kind: u32,
    /// 0 height-correlated, 1 separable Smith.
    pub masking: u32,
    /// Colour texture or [`NONE`].
    pub color_tex: u32,
    /// Roughness texture or [`NONE`].
    pub roughness_tex: u32,
    /// Roughness texture channel.
    pub roughness_channel: u32,
    /// Metallic texture or [`NONE`].
    pub metallic_tex: u32,
    /// Metallic texture channel.
    pub metallic_channel: u32,
    /// GGX Fresnel: 0 Schlick's with `f0`, 1 a conductor's exact one of index `f0` + i`k`.
    pub fresnel: u32,
    /// Colour (constant) or its factor.
    pub color: [f32; 4],
    /// GGX f0, or a conductor's η.
    pub f0: [f32; 4],
    /// Roughness or Phong exponent, metallic, interior IOR, exterior IOR.
    pub scalars: [f32; 4],
    /// A GGX conductor's extinction coefficient k.
    pub k: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuMaterial>() == 32 + 4 * 16);

/// One punctual or distant light (WGSL `Light`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuLight {
    /// [`LightKind`].
    pub kind: u32,
    /// Spot: the projected texture (its factor is in `intensity`), or [`NONE`].
    pub projection_tex: u32,
    /// Padding.
    pub pad: [u32; 2],
    /// Position (point, spot).
    pub position: [f32; 4],
    /// Spot axis, or the unit direction towards a directional light.
    pub direction: [f32; 4],
    /// Intensity (W/sr) or irradiance (W/m²).
    pub intensity: [f32; 4],
    /// Spot: cos θc, cos θb, θc, θb (radians). Directional: 1 − cos θmax, sin²θmax (0 = delta).
    pub params: [f32; 4],
    /// Spot with a projected texture: the light's right axis r (xyz) and tan θc
    /// (scenes::projection).
    pub projection: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuLight>() == 16 + 5 * 16);

/// Where a texture's texels start in the texel buffer, and where its reduced levels are
/// (WGSL `TextureInfo`). The records of levels and tables are `GpuTextureInfo`s too, after
/// the scene's textures, with [`NONE`] in the last four fields.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuTextureInfo {
    /// Index of texel (0, 0).
    pub offset: u32,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Wrap of u (bits 0–3) and v (bits 4–7): 0 repeat, 1 clamp, 2 mirror.
    pub wrap: u32,
    /// Record of MIP level 1 (levels 2, 3, … follow), or [`NONE`].
    pub mips: u32,
    /// Number of MIP levels, level 0 included (1 without a pyramid).
    pub mip_count: u32,
    /// Record of the RIP map's level (0, 0) (the others follow, row-major in (v, u)), or [`NONE`].
    pub rip: u32,
    /// Record of the summed-area table ((W + 1) × (H + 1), after one texel holding the mean), or [`NONE`].
    pub sat: u32,
}
const _: () = assert!(std::mem::size_of::<GpuTextureInfo>() == 32);

/// A vertex of a de-indexed mesh triangle (WGSL `MeshVertexIn`); the last three fields are the
/// same on the triangle's three vertices (flat interpolation).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct MeshVertex {
    /// World position.
    pub position: [f32; 3],
    /// Shape index.
    pub shape: u32,
    /// Vertex normal, or the geometric normal when the triangle has no usable vertex normals.
    pub normal: [f32; 3],
    /// Texture coordinates (barycentric (b₁, b₂) corners without uvs).
    pub uv: [f32; 2],
    /// Authored tangent and handedness, or zero.
    pub tangent: [f32; 4],
    /// Unit geometric normal (p₁ − p₀) × (p₂ − p₀).
    pub ng: [f32; 3],
    /// ∂p/∂u of the triangle.
    pub dpdu: [f32; 3],
    /// ∂p/∂v of the triangle.
    pub dpdv: [f32; 3],
    /// Light-map chart coordinates (`Mesh::uv1`), or zero.
    pub uv1: [f32; 2],
}
const _: () = assert!(std::mem::size_of::<MeshVertex>() == 96);

impl MeshVertex {
    /// Vertex attributes at locations 0–8 of `vs_mesh`.
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 9] = wgpu::vertex_attr_array![
        0 => Float32x3, 1 => Uint32, 2 => Float32x3, 3 => Float32x2,
        4 => Float32x4, 5 => Float32x3, 6 => Float32x3, 7 => Float32x3, 8 => Float32x2
    ];
}

/// A vertex of an analytic shape's proxy (WGSL `AnalyticVertexIn`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct AnalyticVertex {
    /// World position.
    pub position: [f32; 3],
    /// Shape index.
    pub shape: u32,
}
const _: () = assert!(std::mem::size_of::<AnalyticVertex>() == 16);

impl AnalyticVertex {
    /// Vertex attributes at locations 0–1 of `vs_analytic`.
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Uint32];
}

/// `[x, y, z, w]` from a vector and a fourth component.
pub fn vec4(v: glam::Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}
