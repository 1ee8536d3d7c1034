// shadow/map_common.wgsl — shadow maps: the per-light projection, the receiver's biased
// lookup, and the leaf samplers every shadow technique filters with.
//
// Technique: Williams 1978, "Casting Curved Shadows on Curved Surfaces", SIGGRAPH '78
// (https://doi.org/10.1145/965139.807402): render depth from the light, then a point is lit
// where its own depth from the light is not greater than the stored one. One Depth32Float
// layer per shadowed light (realtime/src/technique/shadow/maps.rs builds the projections: perspective from a
// rectangle's or disk's centre along its normal, from a sphere or point light towards the
// scene, along a spot's axis; orthographic over the scene for directional lights), depth in
// [0, 1] (near → 0), cleared to 1, compared with `LessEqual` (1 = lit).
// Cascaded shadow maps (Zhang et al. 2006, "Parallel-Split Shadow Maps for Large-scale Virtual
// Environments", VRCIA 2006, https://doi.org/10.1145/1128923.1128975; Dimitrov 2007, "Cascaded
// Shadow Maps", NVIDIA whitepaper): under `cascades = k` a directional light has k layers, each
// an orthographic map over one slice [z_i, z_{i+1}] of the camera's view depth (shadow/maps.rs,
// "Cascades"); a receiver at camera view depth d takes the first cascade with d ≤ z_{i+1}
// (`shadow_layer`), and that layer's texel size sizes every footprint.
// Rotated Poisson taps (`rotate`): the disk turned per pixel by 2π·IGN(x, y), interleaved
// gradient noise (Jimenez 2014, "Next Generation Post Processing in Call of Duty: Advanced
// Warfare", SIGGRAPH 2014 Advances in Real-Time Rendering course,
// https://advances.realtimerendering.com/s2014/): the fixed pattern's banding turns into
// per-pixel noise with the same mean.
// Bias, three terms, applied to the lookup point q of a receiver p with geometric normal n
// (turned towards the light) and texel footprint τ = world size of one texel at p's depth:
// - normal offset: q = p + n·normal_offset·τ (Holbein 2011, "Normal Offset Shadows", GDC 2011
//   poster; http://www.dissidentlogic.com/old/#Normal%20Offset%20Shadows);
// - constant + slope-scaled: the reference depth is that of q moved towards the light by
//   b = bias + slope_bias·τ·tan θ metres (θ between n and the light direction; the slope term
//   is the depth change across one texel, as OpenGL's glPolygonOffset factor·m, OpenGL 1.1
//   spec §3.5.5), tan θ clamped at SHADOW_MAX_SLOPE. Biases are in world metres, so one value
//   means the same on every light and map resolution;
// - receiver-plane depth bias for the multi-tap kernels (Isidoro 2006, "Shadow Mapping:
//   GPU-based Tips and Techniques", GDC 2006): a tap at Δuv from the lookup compares against
//   depth + ∇d·Δuv, the depth there of the receiver's tangent plane. A plane's projected
//   depth is affine in the map's (u, v) (a projective map takes planes to planes), so ∇d comes
//   exactly from projecting two tangent offsets of q — from the geometric normal rather than
//   screen-space derivatives, so forward, deferred and the AOV pass agree.
// Failure mode: too little bias gives self-shadowing "acne" (the receiver's own depth,
// resampled at texel centres, occludes it), too much detaches shadows from their casters
// ("peter-panning") and leaks light through thin blockers; points outside a light's frustum
// (beyond a perspective map's 150° field of view, behind a one-sided emitter's plane, the
// far side of a point or sphere light's single frustum, unless it has a cube) are treated as lit; without the
// receiver-plane bias, wide kernels on receivers tilted to the light self-shadow (one reference
// depth for the whole kernel), and with it curved receivers still do (the tangent plane leaves
// the surface across a wide kernel).
// Inputs: `shadow` (group 0, binding 8: settings, Poisson taps, per light slot — area emitters
// first, then scene lights — its first map layer and layer count, one ShadowLight per layer),
// the map array and two comparison samplers (group 2). Only the leaf samplers below and the
// entry points read these bindings.

// Shadow methods SHADOW_NONE (0), SHADOW_HARD, …, SHADOW_PCSS, picked per pipeline: generated
// from the method tables (technique/mod.rs `wgsl_codes`).

// Pipeline-overridable constant: the shadow method (shadow/visibility.wgsl dispatches on it).
override SHADOW_METHOD: u32 = 0u;

// Largest tan θ of the slope-scaled bias (θ ≈ 84°), chosen here: beyond it the receiver is
// nearly edge-on to the light (cos θ < 0.1, little light arrives), and an unbounded slope term
// would detach the whole receiver's shadow.
const SHADOW_MAX_SLOPE: f32 = 10.0;

// Tangent step of the receiver-plane gradient, in texel footprints (any step is exact for a
// plane; 4 keeps the projected differences well above f32 rounding, chosen here).
const SHADOW_PLANE_STEP: f32 = 4.0;

// One light's shadow map (shadow/maps.rs `GpuShadowLight`).
struct ShadowLight {
    // World to clip; depth z/w in [0, 1].
    view_proj: mat4x4<f32>,
    // Its inverse (the shadow pass's rays through texels).
    inv_view_proj: mat4x4<f32>,
    // Perspective: the eye. Orthographic: a point on the view axis.
    eye: vec3<f32>,
    // 1 perspective, 0 orthographic.
    perspective: f32,
    // Unit view direction.
    axis: vec3<f32>,
    // The PCSS light-size term s: w_light in metres for perspective maps, 2·tan(θ/2) of the
    // angular diameter θ for orthographic ones.
    light_size: f32,
    // Near and far view depth.
    near: f32,
    far: f32,
    // The texel footprint τ(z) = z·texel_slope + texel_offset.
    texel_slope: f32,
    texel_offset: f32,
    // PCSS's search near plane (the nearest blocker depth it assumes).
    search_near: f32,
    // A cascade's far split z_{i+1} in camera view depth (f32 max for a map over the scene).
    cascade_far: f32,
    // 1: the layer is a shadowed light's; 0: unused.
    shadowed: u32,
    // The light's own shape (NONE for scene lights).
    own_shape: u32,
}

// The method's parameters by name (GpuShadowSettings in shadow/maps.rs); a technique's own are
// 0 under the others.
struct ShadowSettings {
    // Constant bias, m.
    bias: f32,
    slope_bias: f32,
    // Normal offset, texels.
    normal_offset: f32,
    // Map side, texels.
    map_side: f32,
    // pcf_box's k.
    kernel: u32,
    // pcf_poisson's taps.
    taps: u32,
    // pcss's blocker-search and filter taps.
    blocker_samples: u32,
    filter_samples: u32,
    // pcf_poisson's disk radius, texels.
    radius: f32,
    // pcss's blocker_depth = ignore (1) or the search (0).
    ignore_blocker_depth: u32,
    // Receiver-plane depth bias (1) or none (0).
    receiver_plane: u32,
    // Poisson taps rotated per pixel (1) or fixed (0).
    rotate: u32,
}

struct ShadowUniforms {
    settings: ShadowSettings,
    // 64 taps in the unit disk, two per vec4 (shadow/poisson.rs `poisson_disk`).
    poisson: array<vec4<f32>, 32>,
    // Per light slot: first map layer, layer count (1, its cascades, or a cube's 6), 1 for a
    // cube, unused.
    slots: array<vec4<u32>, 64>,
    // One projection per map layer (shadow/maps.rs MAX_SHADOW_LAYERS).
    layers: array<ShadowLight, 128>,
}

@group(0) @binding(8) var<uniform> shadow: ShadowUniforms;
@group(2) @binding(0) var shadow_maps: texture_depth_2d_array;
@group(2) @binding(1) var shadow_nearest: sampler_comparison;
@group(2) @binding(2) var shadow_bilinear: sampler_comparison;

// Where a receiver looks the map up.
struct ShadowReceiver {
    // Map coordinates of the lookup point (row 0 at the top).
    uv: vec2<f32>,
    // The biased reference depth in the map's [0, 1].
    depth: f32,
    // View depth of the lookup point along the light's axis (PCSS's z_r).
    z: f32,
    // ∂depth/∂(u, v) of the receiver's tangent plane (zero without receiver-plane bias).
    gradient: vec2<f32>,
    // Inside the frustum; outside counts as lit.
    valid: bool,
}

// The reference depth of a tap `offset` (map coordinates) away from the lookup.
fn shadow_tap_depth(r: ShadowReceiver, offset: vec2<f32>) -> f32 {
    return r.depth + dot(r.gradient, offset);
}

// ∂depth/∂(u, v) of the plane through q with unit normal n (`at` = q's projection), from the
// projections of q + ε·t and q + ε·b, ε = `step` world units; zero where the plane is seen
// edge-on (the two offsets project onto one line).
fn shadow_plane_gradient(sl: ShadowLight, q: vec3<f32>, n: vec3<f32>, at: vec4<f32>, step: f32) -> vec2<f32> {
    let a = shadow_project(sl, q + basis_t(n) * step).xyz - at.xyz;
    let b = shadow_project(sl, q + basis_b(n) * step).xyz - at.xyz;
    let det = a.x * b.y - a.y * b.x;
    if !(abs(det) > 1e-3 * length(a.xy) * length(b.xy)) {
        return vec2<f32>(0.0);
    }
    return vec2<f32>(a.z * b.y - b.z * a.y, a.x * b.z - b.x * a.z) / det;
}

fn shadow_is_perspective(sl: ShadowLight) -> bool {
    return sl.perspective > 0.5;
}

// View depth of p along the light's axis.
fn shadow_view_depth(sl: ShadowLight, p: vec3<f32>) -> f32 {
    return dot(p - sl.eye, sl.axis);
}

// World size of one texel at view depth z.
fn shadow_texel_size(sl: ShadowLight, z: f32) -> f32 {
    return sl.texel_slope * z + sl.texel_offset;
}

// Unit direction from p towards the light.
fn shadow_to_light(sl: ShadowLight, p: vec3<f32>) -> vec3<f32> {
    if shadow_is_perspective(sl) {
        return normalize(sl.eye - p);
    }
    return -sl.axis;
}

// (u, v, depth, clip w) of world point p; v = 0 is the top row, as texture coordinates.
fn shadow_project(sl: ShadowLight, p: vec3<f32>) -> vec4<f32> {
    let c = sl.view_proj * vec4<f32>(p, 1.0);
    let ndc = c.xyz / c.w;
    return vec4<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5, ndc.z, c.w);
}

// View depth of a stored depth d: perspective z = n·f/(f − d(f − n)) (the inverse of
// glam's `perspective_rh`), orthographic z = n + d(f − n).
fn shadow_linear_depth(sl: ShadowLight, d: f32) -> f32 {
    let n = sl.near;
    let f = sl.far;
    if shadow_is_perspective(sl) {
        return n * f / (f - d * (f - n));
    }
    return n + d * (f - n);
}

// The ray through the point `ndc` of the light's image plane, from its near to its far plane.
struct ShadowRay {
    o: vec3<f32>,
    d: vec3<f32>,
}

fn shadow_ray(sl: ShadowLight, ndc: vec2<f32>) -> ShadowRay {
    let a = sl.inv_view_proj * vec4<f32>(ndc, 0.0, 1.0);
    let b = sl.inv_view_proj * vec4<f32>(ndc, 1.0, 1.0);
    let o = a.xyz / a.w;
    return ShadowRay(o, b.xyz / b.w - o);
}

// The lookup of receiver p with unit front geometric normal ng (see the header for the bias).
fn shadow_receiver(sl: ShadowLight, s: ShadowSettings, p: vec3<f32>, ng: vec3<f32>) -> ShadowReceiver {
    let wl = shadow_to_light(sl, p);
    let n = select(ng, -ng, dot(ng, wl) < 0.0);
    let texel = shadow_texel_size(sl, max(shadow_view_depth(sl, p), sl.near));
    let q = p + n * (s.normal_offset * texel);
    let cos_t = clamp(dot(n, wl), 0.0, 1.0);
    let tan_t = min(sqrt(max(1.0 - cos_t * cos_t, 0.0)) / max(cos_t, 1e-6), SHADOW_MAX_SLOPE);
    let b = s.bias + s.slope_bias * texel * tan_t;
    let at = shadow_project(sl, q);
    let biased = shadow_project(sl, q + shadow_to_light(sl, q) * b);
    let inside = all(at.xy >= vec2<f32>(0.0)) && all(at.xy <= vec2<f32>(1.0));
    let valid = at.w > 0.0 && biased.w > 0.0 && inside && at.z >= 0.0 && at.z <= 1.0;
    var gradient = vec2<f32>(0.0);
    if s.receiver_plane != 0u {
        gradient = shadow_plane_gradient(sl, q, n, at, SHADOW_PLANE_STEP * texel);
    }
    return ShadowReceiver(at.xy, biased.z, shadow_view_depth(sl, q), gradient, valid);
}

// Leaf samplers. One comparison of the nearest texel: 1 fetch.
fn shadow_compare_nearest(layer: u32, uv: vec2<f32>, depth: f32) -> f32 {
    count_fetch();
    return textureSampleCompareLevel(shadow_maps, shadow_nearest, uv, layer, depth);
}

// The hardware's bilinear comparison: 2×2 texels compared, then weighted (4 fetches).
fn shadow_compare_bilinear(layer: u32, uv: vec2<f32>, depth: f32) -> f32 {
    cost.x += 4u;
    return textureSampleCompareLevel(shadow_maps, shadow_bilinear, uv, layer, depth);
}

// The stored depth of the texel containing uv (edges clamped): 1 fetch.
fn shadow_depth_nearest(layer: u32, uv: vec2<f32>, side: f32) -> f32 {
    count_fetch();
    let n = i32(side);
    let texel = clamp(vec2<i32>(floor(uv * side)), vec2<i32>(0), vec2<i32>(n - 1));
    return textureLoad(shadow_maps, texel, layer, 0);
}

// Tap k of the Poisson disk in the unit disk, turned by `rot` = (cos φ, sin φ).
fn poisson_tap(k: u32, rot: vec2<f32>) -> vec2<f32> {
    let v = shadow.poisson[k / 2u];
    let t = select(v.xy, v.zw, (k & 1u) == 1u);
    return vec2<f32>(rot.x * t.x - rot.y * t.y, rot.y * t.x + rot.x * t.y);
}

// The map layer of light slot `slot` for a receiver at p, camera view depth `view_depth`:
// under a cube map (slots[slot].z = 1) the face of the major axis of p − light, in the order
// +x, −x, +y, −y, +z, −z (Gerasimov 2004, "Omnidirectional Shadow Mapping", GPU Gems ch. 12;
// each face is widened past 90° so that kernels at its edge read its own texels); else the
// first of its cascades whose far split z_{i+1} is at or beyond it (its last one past them
// all), or its one layer (Dimitrov 2007's interval-based selection).
fn shadow_layer(slot: u32, p: vec3<f32>, view_depth: f32) -> u32 {
    let m = shadow.slots[slot];
    if m.z == 1u {
        let d = p - shadow.layers[m.x].eye;
        let a = abs(d);
        var axis = 2u;
        if a.x >= a.y && a.x >= a.z {
            axis = 0u;
        } else if a.y >= a.z {
            axis = 1u;
        }
        return m.x + 2u * axis + select(0u, 1u, d[axis] < 0.0);
    }
    let last = m.x + max(m.y, 1u) - 1u;
    var layer = m.x;
    while layer < last && view_depth > shadow.layers[layer].cascade_far {
        layer += 1u;
    }
    return layer;
}

// Interleaved gradient noise at target pixel (x, y) (Jimenez 2014, the slides' constants):
// fract(52.9829189·fract(0.06711056·x + 0.00583715·y)), on integer pixel coordinates.
fn interleaved_gradient_noise(frag: vec2<f32>) -> f32 {
    let p = floor(frag);
    return fract(52.9829189 * fract(dot(p, vec2<f32>(0.06711056, 0.00583715))));
}

// The Poisson taps' rotation (cos φ, sin φ) at target pixel `frag`: φ = 2π·IGN when the
// settings rotate them, else none.
fn shadow_tap_rotation(s: ShadowSettings, frag: vec2<f32>) -> vec2<f32> {
    if s.rotate == 0u {
        return vec2<f32>(1.0, 0.0);
    }
    let phi = 6.283185307 * interleaved_gradient_noise(frag);
    return vec2<f32>(cos(phi), sin(phi));
}
