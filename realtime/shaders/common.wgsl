// common.wgsl — scene bindings, GPU structs, the camera, and the cost counters.
//
// Technique: none (shared declarations). Every struct mirrors a `#[repr(C)]` Pod struct in
// realtime/src/gpu_types.rs field for field; the Rust side asserts the sizes.
// Inputs: group 0 = the scene (frame uniform, shapes, materials, lights, emitters, textures,
// texels) and the counter buffer (written only by the counting variant of the module). Conventions: docs/ARCHITECTURE.md "Conventions" (right-handed, +Y up,
// camera looks down −Z, pixel (i, j) covers [i, i+1]×[j, j+1], row 0 at the top).
// Failure mode: none of its own; the projection must stay identical to
// `scenes::Camera::ray_direction` (the parity tests check it).

const PI: f32 = 3.14159265358979323846;
const TAU: f32 = 6.28318530717958647692;
const INV_PI: f32 = 0.31830988618379067154;
// "No texture / no emission" marker in index fields (u32::MAX on the Rust side).
const NONE: u32 = 0xffffffffu;

// Shape kinds (gpu_types.rs `ShapeKind`).
const SHAPE_MESH: u32 = 0u;
const SHAPE_SPHERE: u32 = 1u;
const SHAPE_RECTANGLE: u32 = 2u;
const SHAPE_DISK: u32 = 3u;

// Material kinds (gpu_types.rs `MaterialKind`).
const MAT_DIFFUSE: u32 = 0u;
const MAT_PHONG: u32 = 1u;
const MAT_GGX: u32 = 2u;
const MAT_METAL_ROUGH: u32 = 3u;
const MAT_MIRROR: u32 = 4u;
const MAT_DIELECTRIC: u32 = 5u;

// Light kinds (gpu_types.rs `LightKind`).
const LIGHT_POINT: u32 = 0u;
const LIGHT_SPOT: u32 = 1u;
const LIGHT_DIRECTIONAL: u32 = 2u;

// Environment kinds (gpu_types.rs `EnvKind`).
const ENV_NONE: u32 = 0u;
const ENV_CONSTANT: u32 = 1u;
const ENV_MAP: u32 = 2u;

// Area-light methods AREA_QUADRATURE, AREA_REPRESENTATIVE_POINT: generated from the method
// tables (technique/mod.rs `wgsl_codes`), ahead of this file.

// Pipeline-overridable constant: the area-light method (shade.wgsl dispatches on it).
override AREA_METHOD: u32 = 0u;
// The footprint's source of the texture filters (0 hardware derivatives, 1 ray
// differentials). The filter itself, TEXTURE_FILTER and `texture_filtered`, is generated per
// shader module (pipelines.rs `shader_source`): every lookup site calls the one filter the
// method uses, rather than a switch over all of them inlined at each site (as a uniform, that
// switch made lavapipe's frame time grow twelvefold).
override TEXTURE_DERIVATIVES: u32 = 0u;

struct FrameUniforms {
    view_proj: mat4x4<f32>,
    // Camera position (xyz) and the near-plane distance (w).
    cam_pos: vec4<f32>,
    // Columns of Camera::to_world's 3×3 part.
    cam_x: vec4<f32>,
    cam_y: vec4<f32>,
    cam_z: vec4<f32>,
    // Unit view direction (the depth AOV's axis).
    cam_forward: vec4<f32>,
    // Final film width, height, tan(fov_y/2), aspect W/H (as f32, as the oracle computes it).
    film: vec4<f32>,
    // Supersampling factor k (x), 1/k (y), TAA's sub-pixel jitter in film pixels (zw).
    ssaa: vec4<f32>,
    // Environment: constant radiance (rgb) or the map's scale (x).
    env_radiance: vec4<f32>,
    // Environment kind, texture index, quadrature n (n×n directions), unused.
    env_info: vec4<u32>,
    // Punctual/directional lights, area emitters, area quadrature n, unused.
    counts: vec4<u32>,
    // Emissive meshes as lights: the triangle table's texture record (6 texels a triangle) or
    // NONE, the quadrature n per triangle (`mesh_n`), unused, unused.
    mesh_lights: vec4<u32>,
    // Energy compensation (energy/*.wgsl): the method (ENERGY_*; the shader reads the
    // pipeline's ENERGY_METHOD), its table's texture record or NONE, unused, unused.
    energy: vec4<u32>,
    // Each family's block, by name (`families.detail.height_scale`): FamilyUniforms is
    // generated from the registry (technique/mod.rs `wgsl_codes`), the blocks written by
    // technique::family_uniform_bytes after the fields above.
    families: FamilyUniforms,
}

struct Shape {
    kind: u32,
    material: u32,
    normal_map: u32,
    normal_scale: f32,
    // xyz centre; w radius (sphere).
    center: vec4<f32>,
    half_u: vec4<f32>,
    half_v: vec4<f32>,
    // Unit front normal of planar shapes (rectangle, disk); w = area (rectangle, disk, sphere).
    normal: vec4<f32>,
    // Dual basis of (half_u, half_v) in their plane: local s = (p − c)·dual_u, t = (p − c)·dual_v.
    dual_u: vec4<f32>,
    dual_v: vec4<f32>,
    // Emitted radiance (constant) or its factor (textured).
    emission: vec4<f32>,
    // Emits (0/1), two-sided (0/1), radiance texture or NONE, mesh has authored tangents (0/1).
    emission_info: vec4<u32>,
    // Displacement: height texture or NONE, channel, derivative map, cone map or NONE.
    detail: vec4<u32>,
    // Displacement scale s (metres per unit h), min and max of s·h over the texels, unused.
    detail_range: vec4<f32>,
    // Light map: atlas texture or NONE (no chart), the chart's first atlas texel x and y,
    // width | height << 16 in texels (lightmap/lookup.wgsl).
    lightmap: vec4<u32>,
}

struct Material {
    kind: u32,
    masking: u32,
    // Colour texture (albedo, ks, reflectance, base colour) or NONE.
    color_tex: u32,
    // Roughness texture or NONE, and its channel.
    roughness_tex: u32,
    roughness_channel: u32,
    // Metallic texture or NONE, and its channel.
    metallic_tex: u32,
    metallic_channel: u32,
    // GGX Fresnel: 0 Schlick's with f0, 1 a conductor's exact one of index f0 + i·k.
    fresnel: u32,
    // Colour (constant) or its factor (textured).
    color: vec4<f32>,
    // GGX f0 (rgb), or a conductor's η.
    f0: vec4<f32>,
    // x: roughness (constant or factor) or Phong exponent; y: metallic (constant or factor);
    // z: interior IOR; w: exterior IOR.
    scalars: vec4<f32>,
    // A GGX conductor's extinction coefficient k (rgb).
    k: vec4<f32>,
}

struct Light {
    kind: u32,
    // Spot: the projected texture (its factor is in `intensity`), or NONE.
    projection_tex: u32,
    pad1: u32,
    pad2: u32,
    position: vec4<f32>,
    // Spot axis, or the unit direction towards a directional light.
    direction: vec4<f32>,
    // Intensity (W/sr) or irradiance (W/m²).
    intensity: vec4<f32>,
    // Spot: cos θc, cos θb, θc, θb. Directional: 1 − cos θmax, sin²θmax, 0, 0 (0 = delta).
    params: vec4<f32>,
    // Spot with a projected texture: its right axis r (xyz), tan θc (w).
    projection: vec4<f32>,
}

struct TextureInfo {
    offset: u32,
    width: u32,
    height: u32,
    // Wrap mode of u (bits 0–3) and v (bits 4–7): 0 repeat, 1 clamp, 2 mirror.
    wrap: u32,
    // Record of MIP level 1 (the next levels follow), or NONE; level count (level 0 included).
    mips: u32,
    mip_count: u32,
    // Record of the RIP map's level (0, 0) (row-major in (v, u)), or NONE.
    rip: u32,
    // Record of the summed-area table (its first texel the mean), or NONE.
    sat: u32,
}

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> shapes: array<Shape>;
@group(0) @binding(2) var<storage, read> materials: array<Material>;
@group(0) @binding(3) var<storage, read> lights: array<Light>;
@group(0) @binding(4) var<storage, read> emitters: array<u32>;
@group(0) @binding(5) var<storage, read> texture_infos: array<TextureInfo>;
@group(0) @binding(6) var<storage, read> texels: array<vec4<f32>>;
// Per target row: texel fetches, loop iterations (summed in u64 on the CPU).
@group(0) @binding(7) var<storage, read_write> counters: array<atomic<u32>>;
// `tex_anisotropic` (texture/anisotropic.wgsl): scene texture i is layer i, with its MIP
// levels; one sampler per wrap mode (repeat, clamp to edge, mirror). A 1 × 1 stand-in otherwise.
@group(0) @binding(9) var scene_texture_array: texture_2d_array<f32>;
@group(0) @binding(10) var sampler_repeat: sampler;
@group(0) @binding(11) var sampler_clamp: sampler;
@group(0) @binding(12) var sampler_mirror: sampler;

// Cost counters of the current invocation: texel fetches (x) and loop iterations (y); the
// entry points hand them to `flush_counters` (counters_on.wgsl / counters_off.wgsl).
var<private> cost: vec2<u32>;

fn count_fetch() {
    cost.x += 1u;
}

// k texel fetches at once (a hardware-filtered lookup: 4 bilinear, 8 trilinear).
fn count_fetches(k: u32) {
    cost.x += k;
}

fn count_iteration() {
    cost.y += 1u;
}

// Camera::ray_direction for the raster position (x, y) of the final film (docs/ARCHITECTURE.md "Camera"):
// x_cam = (2x/W − 1)·tan(fov/2)·W/H, y_cam = (1 − 2y/H)·tan(fov/2), z_cam = −1.
fn camera_ray_direction(f: FrameUniforms, x: f32, y: f32) -> vec3<f32> {
    let xc = (2.0 * x / f.film.x - 1.0) * f.film.z * f.film.w;
    let yc = (1.0 - 2.0 * y / f.film.y) * f.film.z;
    return normalize(f.cam_x.xyz * xc + f.cam_y.xyz * yc - f.cam_z.xyz);
}

// The raster position on the final film of a fragment of the k·W × k·H target.
// Offset by TAA's jitter (zero otherwise), as the jittered projection places the fragment.
fn film_position(f: FrameUniforms, frag: vec2<f32>) -> vec2<f32> {
    return frag * f.ssaa.y + f.ssaa.zw;
}

// Orthonormal basis (t, b) around unit n: Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited" (JCGT 6(1)), Listing 3.
fn basis_t(n: vec3<f32>) -> vec3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
}

fn basis_b(n: vec3<f32>) -> vec3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(b, s + n.y * n.y * a, -n.y);
}

// (v.x, v.y, v.z) in the frame (t, b, n) around unit n, to world space.
fn to_world(n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    return basis_t(n) * v.x + basis_b(n) * v.y + n * v.z;
}

// x > 0 (false for NaN): the sanitising test of oracle/src/bsdf/mod.rs.
fn positive_or_zero(x: f32) -> f32 {
    return select(0.0, x, x > 0.0);
}
