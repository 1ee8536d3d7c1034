// detail/normal.wgsl — normal mapping and bump mapping: the displaced surface's normal on the
// undisplaced base point.
//
// Technique: normal mapping reads a normal map baked from h (detail/mod.rs `derivative_map`: per
// texel central differences of h, stored as derivatives — Mikkelsen 2010, "Bump Mapping
// Unparametrized Surfaces on the GPU", JGT 15(1) — so one map serves any uv scale), bilinearly
// filtered: 4 fetches. Bump mapping differences h at run time (Blinn 1978, "Simulation of
// Wrinkled Surfaces", SIGGRAPH, §3): w_u ≈ (w(u + δ, v) − w(u, v))/δ, likewise in v, δ = `delta`
// texels: 12 fetches. Both feed detail/common.wgsl's `displaced_normal`.
// Failure mode: the point stays on the base surface: no parallax (the texture seen is the one
// under the base point, not the one the ray meets), no self-occlusion, no self-shadowing, no
// silhouette — the missing occlusion the surface-detail studies bound from below. The
// parallax family uses the same normal map at its uv'.
// Inputs: the shape's height texture and derivative map, the family's `bump_delta` (δ).

// (w_u, w_v) from the baked map at uv.
fn normal_map_gradient(fr: DetailFrame, s: Shape, uv: vec2<f32>) -> vec2<f32> {
    return texture_sample(s.detail.z, uv).xy * fr.scale;
}

// (w_u, w_v) by forward differences of w over δ texels at uv.
fn bump_gradient(f: FrameUniforms, fr: DetailFrame, uv: vec2<f32>) -> vec2<f32> {
    let info = texture_infos[fr.tex];
    let step = f.families.detail.bump_delta / vec2<f32>(f32(info.width), f32(info.height));
    let w0 = detail_height(fr, uv);
    let wu = detail_height(fr, uv + vec2<f32>(step.x, 0.0));
    let wv = detail_height(fr, uv + vec2<f32>(0.0, step.y));
    return vec2<f32>(wu - w0, wv - w0) / step;
}
