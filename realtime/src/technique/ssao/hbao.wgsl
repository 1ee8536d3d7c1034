// ssao/hbao.wgsl — horizon-based ambient occlusion (Bavoil, Sainz & Dimitrov 2008, "Image-Space
// Horizon-Based Ambient Occlusion", SIGGRAPH talk, §2), with the tangent plane from the
// G-buffer normal: along each of `directions` screen directions (turned per pixel) the march
// keeps the highest elevation h of a sample above the tangent plane, sin h = (D·n)/|D| for
// D = sample − point, and each rise of the horizon adds W(|D|)·(sin h − sin h_previous);
// AO = 1 − the mean over directions. W is the falloff (the paper's is 1 − d²/r², `quadratic`).
// Its quantity, for W = 1: 1 − (1/2π)∫ sin h(φ) dφ, the solid-angle (not cosine) weighted
// fraction of the hemisphere above the horizon; it reads darker than the oracle's cosine-weighted
// AO where the occluders stand at grazing angles, lighter where they rise near the normal.
// Failure modes: a depth layer of infinite thickness behind every sample (a thin pole hides all
// that lies behind it), nothing off screen, and banding along few directions.

fn ambient_occlusion(px: vec2<i32>, g: GSample) -> f32 {
    let nd = ssao.counts.y;
    let rot = pixel_noise(px);
    let shift = pixel_noise(px + vec2<i32>(17, 59));
    let radius_px = radius_pixels(g.p);
    var sum = 0.0;
    for (var d = 0u; d < nd; d++) {
        let a = 2.0 * PI * (f32(d) + rot) / f32(nd);
        let dir = vec2<f32>(cos(a), sin(a));
        var sin_h = 0.0;
        for (var s = 0u; s < ssao.counts.z; s++) {
            let pix = march_pixel(px, dir, s, radius_px, shift);
            if !in_target(pix) {
                break;
            }
            let o = gposition(pix);
            if o.w < 0.5 {
                continue;
            }
            let v = o.xyz - g.p;
            let dist = length(v);
            let height = dot(v, g.n);
            let w = falloff_weight(dist);
            if height < ssao.params.y || w <= 0.0 {
                continue;
            }
            let sin_e = height / dist;
            if sin_e > sin_h {
                sum += w * (sin_e - sin_h);
                sin_h = sin_e;
            }
        }
    }
    return 1.0 - sum / f32(nd);
}
