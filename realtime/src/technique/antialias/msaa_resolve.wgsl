// The MSAA resolve (technique/antialias/post.rs): each output pixel is the mean of its
// samples — the box filter over the pixel that the ground truth integrates, estimated from
// `samples` coverage samples but one shading per primitive and pixel (forward). Written as a
// pass, not the attachment's resolve target, because Rgba32Float is not resolvable everywhere
// and the object id must not be averaged: it is taken from sample 0, so the pixel's
// `coverage.Y` is binary under MSAA, as at one sample.

@group(0) @binding(0) var ms_color: texture_multisampled_2d<f32>;
@group(0) @binding(1) var ms_normal_depth: texture_multisampled_2d<f32>;
@group(0) @binding(2) var ms_albedo_id: texture_multisampled_2d<f32>;

struct Resolved {
    @location(0) color: vec4<f32>,
    @location(1) normal_depth: vec4<f32>,
    @location(2) albedo_id: vec4<f32>,
}

@fragment
fn fs_msaa_resolve(@builtin(position) frag: vec4<f32>) -> Resolved {
    let p = vec2<i32>(frag.xy);
    let n = textureNumSamples(ms_color);
    var color = vec4<f32>(0.0);
    var normal_depth = vec4<f32>(0.0);
    var albedo = vec3<f32>(0.0);
    for (var s = 0u; s < n; s += 1u) {
        taps += 3u;
        color += textureLoad(ms_color, p, i32(s));
        normal_depth += textureLoad(ms_normal_depth, p, i32(s));
        albedo += textureLoad(ms_albedo_id, p, i32(s)).rgb;
    }
    let inv = 1.0 / f32(n);
    let id = textureLoad(ms_albedo_id, p, 0).w;
    taps += 1u;
    flush_taps(frag.y);
    return Resolved(color * inv, normal_depth * inv, vec4<f32>(albedo * inv, id));
}
