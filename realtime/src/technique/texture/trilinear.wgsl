// texture/trilinear.wgsl — `tex_trilinear`: bilinear in the two MIP levels around λ, blended.
//
// Technique: Williams 1983, "Pyramidal Parametrics", SIGGRAPH (OpenGL's LINEAR_MIPMAP_LINEAR).
// Failure mode: the prefilter is a square of side ρ, the footprint's longer axis: where the
// footprint is long and thin (a plane seen at a grazing angle) detail along the short axis is
// blurred away; the 2×2 box pyramid is itself a poor low-pass filter (some aliasing remains).
// Inputs: texture `t` and its MIP levels, uv, `uv_footprint`.

fn texture_trilinear(t: u32, uv: vec2<f32>) -> vec4<f32> {
    return trilinear_at(t, uv, level_of_detail(texture_infos[t]));
}
