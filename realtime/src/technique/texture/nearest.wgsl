// texture/nearest.wgsl — `tex_nearest`: the level-0 texel under uv.
//
// Technique: point sampling, no interpolation, no prefilter.
// Reference: none (the baseline).
// Failure mode: blocky under magnification; under minification every pixel takes one texel
// of many, so fine detail aliases and shimmers as the camera moves.
// Inputs: texture `t`, uv.

fn texture_nearest(t: u32, uv: vec2<f32>) -> vec4<f32> {
    let info = texture_infos[t];
    let x = uv.x * f32(info.width);
    let y = uv.y * f32(info.height);
    if !(abs(x) < 1e9 && abs(y) < 1e9) {
        return vec4<f32>(0.0);
    }
    return texel_wrapped(info, i32(floor(x)), i32(floor(y)));
}
