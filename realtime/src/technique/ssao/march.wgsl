// ssao/march.wgsl — the screen-space march of the horizon methods (HBAO, GTAO): `steps`
// samples along a screen direction out to the radius's projection at the point's depth,
// r·f/z pixels (f the focal length in pixels), the first at least one pixel out and every one
// jittered by the same per-pixel offset.

// The target pixel of sample `s` of `steps` along unit screen direction `dir` from pixel `px`
// (None: off the target, which ends the march).
fn march_pixel(px: vec2<i32>, dir: vec2<f32>, s: u32, radius_px: f32, shift: f32) -> vec2<i32> {
    let t = 1.0 + (f32(s) + shift) * max(radius_px - 1.0, 0.0) / f32(ssao.counts.z);
    return vec2<i32>(floor(vec2<f32>(px) + 0.5 + dir * t));
}

// The projected radius at `p`, in target pixels.
fn radius_pixels(p: vec3<f32>) -> f32 {
    return ssao.params.x * ssao.cam_pos.w / max(view_depth(p), 1e-6);
}
