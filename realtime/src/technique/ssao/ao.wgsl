// ssao/ao.wgsl — the AO pass's entry point: one AO texel per fragment, read from the G-buffer
// pixel it stands for (every second pixel in each axis at half resolution: point decimation),
// estimated by the method's `ambient_occlusion` (its own file, ahead of this one) and stored
// as obscurance 1 − AO. The background stores 0.

@fragment
fn fs_ao(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let out = estimate(pos);
    flush_loads(pos.y);
    return out;
}

fn estimate(pos: vec4<f32>) -> vec4<f32> {
    let px = vec2<i32>(pos.xy) * i32(ssao.params.w);
    let g = gsample(px);
    if !g.valid {
        return vec4<f32>(0.0);
    }
    // Not clamped here: one pixel's estimate may leave [0, 1] (a single GTAO slice reads up to
    // ~1.5 on an open plane, where the mean over slices is 1), and the blur and the temporal
    // accumulation must average it as it is; the lighting clamps what reaches it.
    return vec4<f32>(1.0 - ambient_occlusion(px, g), 0.0, 0.0, 0.0);
}
