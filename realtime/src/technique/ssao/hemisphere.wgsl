// ssao/hemisphere.wgsl — normal-oriented hemisphere SSAO (Filion & McNaughton 2008, "StarCraft
// II: Effects & Techniques", SIGGRAPH course, §5.4): point samples at cosine-distributed
// directions about the normal (a Fibonacci spiral on the disk lifted to the hemisphere, turned
// per pixel) and at distances t·r, t spread over (0, 1]; a sample is occluded where the surface
// seen at its pixel lies in front of it by more than the bias, weighted by the falloff of that
// surface's distance from the point. AO = 1 − the weighted fraction occluded.
// Its quantity: the mean, over cosine-distributed segments of length r, of the fraction of each
// segment in front of the depth buffer — a segment that enters an occluder half-way counts ½
// where the oracle's V_r counts the ray as blocked, so it reads lighter than the ground truth
// near occluders at a distance; no self-occlusion on flat surfaces (samples never go below).
// Failure modes: as every screen-space method, what is off screen or behind the front depth
// layer is free, and the layer is taken as infinitely thick.

fn ambient_occlusion(px: vec2<i32>, g: GSample) -> f32 {
    let r = ssao.params.x;
    let n = ssao.counts.x;
    let rot = 2.0 * PI * pixel_noise(px);
    let shift = pixel_noise(px + vec2<i32>(17, 59));
    let frame = basis(g.n);
    var occluded = 0.0;
    for (var i = 0u; i < n; i++) {
        let u = (f32(i) + 0.5) / f32(n);
        let rad = sqrt(u);
        let phi = f32(i) * GOLDEN_ANGLE + rot;
        let local = vec3<f32>(rad * cos(phi), rad * sin(phi), sqrt(max(0.0, 1.0 - u)));
        let t = fract(f32(i) * 0.618034 + shift) + 0.5 / f32(n);
        occluded += point_occlusion(g.p + frame * local * (min(t, 1.0) * r), g.p);
    }
    return 1.0 - occluded / f32(n);
}
