// texture/ripmap.wgsl — `tex_ripmap`: trilinear in both axes of a RIP map.
//
// Technique: RIP maps (rectangular MIP maps: every level reduced i times in u and j times in
// v; Akenine-Möller et al., Real-Time Rendering 4th ed. §6.2.2): λu, λv from the footprint's
// extents along u and v, bilinear in the four levels around (λu, λv), blended in both.
// Failure mode: anisotropic only along the texture axes: a footprint diagonal to them (a
// receding plane rotated 45°) gets a box as large as its bounding box, like the summed-area
// table; four times the memory of the texture.
// Inputs: texture `t` and its RIP levels, uv, `uv_footprint`.

fn rip_level(info: TextureInfo, i: u32, j: u32) -> TextureInfo {
    return texture_infos[info.rip + j * levels_over(info.width) + i];
}

fn texture_ripmap(t: u32, uv: vec2<f32>) -> vec4<f32> {
    let info = texture_infos[t];
    if info.rip == NONE {
        return texture_sample(t, uv);
    }
    let j = footprint_texels(info);
    let extent = max(abs(j.xy), abs(j.zw));
    let top = vec2<f32>(f32(levels_over(info.width) - 1u), f32(levels_over(info.height) - 1u));
    let l = clamp(log2(extent) + vec2<f32>(frame.families.texture.lod_bias), vec2<f32>(0.0), top);
    let l0 = floor(select(vec2<f32>(0.0), l, l == l));
    let f = select(vec2<f32>(0.0), l, l == l) - l0;
    let i0 = u32(l0.x);
    let j0 = u32(l0.y);
    let i1 = min(i0 + 1u, u32(top.x));
    let j1 = min(j0 + 1u, u32(top.y));
    let a = mix(bilinear(rip_level(info, i0, j0), uv), bilinear(rip_level(info, i1, j0), uv), f.x);
    let b = mix(bilinear(rip_level(info, i0, j1), uv), bilinear(rip_level(info, i1, j1), uv), f.x);
    return mix(a, b, f.y);
}
