// ssao/common.wgsl — what every SSAO pass shares: the G-buffer it reads, the camera, the
// method's parameters, the per-pixel rotation and the falloff.
//
// The passes (technique/ssao/passes.rs) are full-screen triangles into R32Float targets that
// hold the ambient *obscurance* 1 − AO, so that the lighting's AO texture, zero where no pass
// wrote it, leaves the image unchanged. Positions come from the G-buffer (world space, f32: the
// position a depth-buffer reconstruction gives, without its quantisation); "depth" below is the
// view depth along the camera's axis, what a depth buffer stores.

struct SsaoUniforms {
    view_proj: mat4x4<f32>,
    // Camera position (xyz), focal length in target pixels (w): (H/2)/tan(fov_y/2).
    cam_pos: vec4<f32>,
    // Camera axes in world space: right (x), up (y), forward (−z of its frame).
    cam_right: vec4<f32>,
    cam_up: vec4<f32>,
    cam_forward: vec4<f32>,
    // Target width, height; AO width, height.
    sizes: vec4<u32>,
    // Radius r (m), bias × r (m), blur radius (texels), AO texel → target pixel scale.
    params: vec4<f32>,
    // Samples, directions, steps, falloff (0 none, 1 cutoff, 2 quadratic).
    counts: vec4<u32>,
    // Temporal accumulation: the previous frame's view-projection.
    prev_view_proj: mat4x4<f32>,
    // Frame index in the accumulation, frames accumulated (0: none), unused ×2.
    temporal: vec4<u32>,
}

// One pass's own inputs: the previous pass's obscurance, the blur axis (x, y), and the temporal
// history (obscurance, view depth; the temporal pass alone reads it).
struct PassUniforms {
    axis: vec4<i32>,
}

@group(0) @binding(0) var gbuffer0: texture_2d<f32>;
@group(0) @binding(1) var gbuffer1: texture_2d<f32>;
@group(0) @binding(2) var<uniform> ssao: SsaoUniforms;
// Texture loads of the passes, one counter per target row, under COUNT_LOADS (the counting
// run only: passes.rs `SsaoPasses::encode_load_count`; the timed frames skip the atomics).
@group(0) @binding(3) var<storage, read_write> load_rows: array<atomic<u32>>;
@group(1) @binding(0) var obscurance_in: texture_2d<f32>;
@group(1) @binding(1) var<uniform> pass_info: PassUniforms;
@group(1) @binding(2) var history: texture_2d<f32>;

override COUNT_LOADS: bool = false;

// Texture loads of the fragment being processed.
var<private> loads: u32;

// Adds the fragment's loads to its row's counter (under COUNT_LOADS). Call once, last.
fn flush_loads(y: f32) {
    if COUNT_LOADS {
        atomicAdd(&load_rows[u32(y)], loads);
    }
}

const PI: f32 = 3.14159265358979;
const GOLDEN_ANGLE: f32 = 2.39996322972865;

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * vec2<f32>(2.0, -2.0) + vec2<f32>(-1.0, 1.0), 0.0, 1.0);
}

// A G-buffer texel: the surface point and its shading normal turned towards the camera, or
// `valid` false where the pixel sees the background.
struct GSample {
    p: vec3<f32>,
    n: vec3<f32>,
    valid: bool,
}

fn in_target(px: vec2<i32>) -> bool {
    return all(px >= vec2<i32>(0)) && all(px < vec2<i32>(ssao.sizes.xy));
}

fn gsample(px: vec2<i32>) -> GSample {
    let g0 = textureLoad(gbuffer0, px, 0);
    loads += 1u;
    if g0.w < 0.5 {
        return GSample(vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), false);
    }
    loads += 1u;
    var n = normalize(textureLoad(gbuffer1, px, 0).xyz);
    if dot(n, ssao.cam_pos.xyz - g0.xyz) < 0.0 {
        n = -n;
    }
    return GSample(g0.xyz, n, true);
}

// The position only (the depth-only methods read nothing else).
fn gposition(px: vec2<i32>) -> vec4<f32> {
    loads += 1u;
    return textureLoad(gbuffer0, px, 0);
}

// The previous pass's obscurance at `q`.
fn obscurance_at(q: vec2<i32>) -> f32 {
    loads += 1u;
    return textureLoad(obscurance_in, q, 0).r;
}

fn view_depth(p: vec3<f32>) -> f32 {
    return dot(p - ssao.cam_pos.xyz, ssao.cam_forward.xyz);
}

// The target pixel (continuous, row 0 at the top) a world point projects to.
fn project(p: vec3<f32>) -> vec2<f32> {
    let c = ssao.view_proj * vec4<f32>(p, 1.0);
    let ndc = c.xy / c.w;
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * vec2<f32>(ssao.sizes.xy);
}

// Interleaved gradient noise (Jimenez 2014, "Next Generation Post Processing in Call of Duty:
// Advanced Warfare", SIGGRAPH course): a per-pixel value in [0, 1) whose 3×3 neighbourhoods
// are nearly stratified, so a small blur removes most of the pattern; each frame of a temporal
// accumulation moves the pattern by 5.588238 pixels in x and y (the same talk), so successive
// frames take other rotations.
fn pixel_noise(px: vec2<i32>) -> f32 {
    let p = vec2<f32>(px) + 5.588238 * f32(ssao.temporal.x);
    return fract(52.9829189 * fract(dot(p, vec2<f32>(0.06711056, 0.00583715))));
}

// The weight of an occluder at distance d (falloff 0 none, 1 cutoff, 2 quadratic).
fn falloff_weight(d: f32) -> f32 {
    let r = ssao.params.x;
    switch ssao.counts.w {
        case 0u: {
            return 1.0;
        }
        case 1u: {
            return select(0.0, 1.0, d <= r);
        }
        default: {
            return max(0.0, 1.0 - d * d / (r * r));
        }
    }
}

// The point methods' test of sample `s` for the point `p`: the surface seen at the sample's
// pixel, when it lies in front of the sample by more than the bias, occludes with the falloff
// weight of its distance from `p`; a sample off the target or over the background does not.
fn point_occlusion(s: vec3<f32>, p: vec3<f32>) -> f32 {
    let pix = vec2<i32>(floor(project(s)));
    if !in_target(pix) {
        return 0.0;
    }
    let o = gposition(pix);
    if o.w < 0.5 || view_depth(o.xyz) >= view_depth(s) - ssao.params.y {
        return 0.0;
    }
    return falloff_weight(length(o.xyz - p));
}

// A frame with `n` as its z axis (Duff et al. 2017, "Building an Orthonormal Basis, Revisited",
// JCGT 6(1)).
fn basis(n: vec3<f32>) -> mat3x3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return mat3x3<f32>(
        vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        vec3<f32>(b, s + n.y * n.y * a, -n.y),
        n,
    );
}
