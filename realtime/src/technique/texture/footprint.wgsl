// texture/footprint.wgsl — `tex_footprint`: footprint assembly, trilinear probes along the
// footprint's major axis.
//
// Technique: Schilling, Knittel & Straßer 1996, "Texram: A Smart Memory for Texturing", IEEE
// CG&A 16(3): N = min(⌈major/minor⌉, max_anisotropy) trilinear probes spaced evenly along the
// longer of the footprint's axes, each at λ = log₂(major/N) + lod_bias, averaged (the scheme
// GPUs' anisotropic filtering is modelled on, e.g. EXT_texture_filter_anisotropic).
// Failure mode: the axes J·x̂ and J·ŷ stand in for the ellipse's (they are not orthogonal in
// general); past max_anisotropy the probes blur across the short axis; the probes' boxes
// overlap or leave gaps where N is rounded.
// Inputs: texture `t` and its MIP levels, uv, `uv_footprint`, `frame.families.texture.max_anisotropy`.

fn texture_footprint(t: u32, uv: vec2<f32>) -> vec4<f32> {
    let info = texture_infos[t];
    let j = footprint_texels(info);
    let lx = length(j.xy);
    let ly = length(j.zw);
    let major_uv = select(uv_footprint.zw, uv_footprint.xy, lx >= ly);
    let major = max(lx, ly);
    let minor = min(lx, ly);
    if !(major > 0.0) || !(major < 1e30) {
        return texture_sample(t, uv);
    }
    let n = u32(clamp(ceil(major / max(minor, 1e-6 * major)), 1.0, frame.families.texture.max_anisotropy));
    let lambda = log2(major / f32(n)) + frame.families.texture.lod_bias;
    var sum = vec4<f32>(0.0);
    for (var k = 0u; k < n; k++) {
        count_iteration();
        let offset = (f32(k) + 0.5) / f32(n) - 0.5;
        sum += trilinear_at(t, uv + major_uv * offset, lambda);
    }
    return sum / f32(n);
}
