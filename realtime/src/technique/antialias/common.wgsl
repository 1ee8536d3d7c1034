// Shared by the anti-aliasing passes after lighting (technique/antialias/): the full-screen
// triangle, texel loads clamped to the image, bilinear interpolation of unfilterable targets,
// the luma the edge detectors compare, and the count of texel loads (the post-process taps,
// a hardware-independent cost). Each pass declares its own inputs; binding 4 of every pass
// is the tap counter.

// Counts the taps into `tap_rows` (one counter per target row) when true: the counting pass
// only (post.rs `AntiAliasPasses::count_taps`); the timed frames skip the atomics.
override COUNT_TAPS: bool = false;

@group(0) @binding(4) var<storage, read_write> tap_rows: array<atomic<u32>>;

// Texel loads of the pixel being processed.
var<private> taps: u32;

// Adds the pixel's taps to its row's counter (under COUNT_TAPS). Call once, last.
fn flush_taps(y: f32) {
    if COUNT_TAPS {
        atomicAdd(&tap_rows[u32(y)], taps);
    }
}

// One triangle covering the target (vertices 0, 1, 2 → (−1, −1), (3, −1), (−1, 3)).
@vertex
fn vs_post(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

// Texel p of t, the nearest edge texel outside the image.
fn load_clamped(t: texture_2d<f32>, p: vec2<i32>) -> vec4<f32> {
    taps += 1u;
    let size = vec2<i32>(textureDimensions(t));
    return textureLoad(t, clamp(p, vec2<i32>(0), size - 1), 0);
}

// Texel p of t, zero outside the image.
fn load_or_zero(t: texture_2d<f32>, p: vec2<i32>) -> vec4<f32> {
    taps += 1u;
    let size = vec2<i32>(textureDimensions(t));
    if any(p < vec2<i32>(0)) || any(p >= size) {
        return vec4<f32>(0.0);
    }
    return textureLoad(t, p, 0);
}

// Bilinear interpolation of t at x in pixels (texel centres at i + 0.5), edges clamped: the
// targets are Rgba32Float, which WebGPU does not filter, so the four texels are read here.
fn bilinear(t: texture_2d<f32>, x: vec2<f32>) -> vec4<f32> {
    let q = x - 0.5;
    let i = vec2<i32>(floor(q));
    let f = q - floor(q);
    let a = load_clamped(t, i);
    let b = load_clamped(t, i + vec2<i32>(1, 0));
    let c = load_clamped(t, i + vec2<i32>(0, 1));
    let d = load_clamped(t, i + vec2<i32>(1, 1));
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

// Perceptual luma of linear radiance: √ of the Rec. 709 luminance, clamped to [0, 1] (a
// gamma-2 encoding; FXAA 3.11 and MLAA both expect luma in a perceptual space). Radiance
// above 1 reads as 1: the edge tests see the image as a display would.
fn luma(c: vec3<f32>) -> f32 {
    return sqrt(clamp(dot(c, vec3<f32>(0.2126, 0.7152, 0.0722)), 0.0, 1.0));
}
