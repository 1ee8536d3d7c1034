// ssao/crytek.wgsl — Crytek's screen-space ambient occlusion (Mittring 2007, "Finding Next Gen:
// CryEngine 2", SIGGRAPH course, §8.5.4.3). Depth only: point samples spread uniformly over the
// ball of radius r around the point (spherical Fibonacci directions, radii ∝ ∛u, the set turned
// about the view axis per pixel) are projected into the depth buffer; a sample is occluded where
// the surface seen at its pixel lies in front of it by more than the bias, that surface weighted
// by the falloff of its distance from the point (the "range check"). With v the weighted
// fraction of samples not occluded, AO = min(1, 2v): half the ball lies behind any flat surface,
// so an open plane reads 1 and the inside of a right-angled corner ½ (the exact cosine-weighted
// value at the corner line is ½ too).
// Its own quantity — the free volume of the ball — is not the oracle's AO (cosine-weighted ray
// visibility within r): they agree on open planes and corners, not in general.
// Failure modes: the depth-only test darkens convex edges and silhouettes and the unweighted
// "doubling" saturates; samples off screen or behind the front layer count as free.

fn ambient_occlusion(px: vec2<i32>, g: GSample) -> f32 {
    let r = ssao.params.x;
    let n = ssao.counts.x;
    let rot = 2.0 * PI * pixel_noise(px);
    let shift = pixel_noise(px + vec2<i32>(17, 59));
    var occluded = 0.0;
    for (var i = 0u; i < n; i++) {
        let u = (f32(i) + 0.5) / f32(n);
        let cos_t = 1.0 - 2.0 * u;
        let sin_t = sqrt(max(0.0, 1.0 - cos_t * cos_t));
        let phi = f32(i) * GOLDEN_ANGLE + rot;
        let dir = (cos(phi) * ssao.cam_right.xyz + sin(phi) * ssao.cam_up.xyz) * sin_t
            + cos_t * ssao.cam_forward.xyz;
        let rho = r * pow(fract(f32(i) * 0.618034 + shift) + 0.5 / f32(n), 1.0 / 3.0);
        occluded += point_occlusion(g.p + min(rho, r) * dir, g.p);
    }
    return min(1.0, 2.0 * (1.0 - occluded / f32(n)));
}
