// ssao/gtao.wgsl — ground-truth-based ambient occlusion (Jimenez, Wu, Pesce & Jarabo 2016,
// "Practical Real-Time Strategies for Accurate Indirect Occlusion", SIGGRAPH course, §4). Each
// of `directions` slices (half-planes through the view vector v, turned per pixel) is searched
// both ways for the horizon, the largest cos of the angle between v and a sample's direction;
// the normal projected into the slice, n_p, makes the angle γ with v, and the horizons are
// clamped to the hemisphere about n_p (h₁ ≥ γ − π/2, h₂ ≤ γ + π/2). The cosine-weighted
// visibility between them is, in closed form (their eq. 10),
//   â = ¼(−cos(2h₁ − γ) + cos γ + 2h₁ sin γ) + ¼(−cos(2h₂ − γ) + cos γ + 2h₂ sin γ),
// and AO = mean over slices of |n_p|·â (eq. 9; exactly 1 with no occluder at any normal).
// The falloff blends a sample's horizon cosine towards −1 by its weight.
// Its quantity is the oracle's: the cosine-weighted visibility within r, if the depth buffer
// were a height field of infinite thickness seen whole on screen. Failure modes: thin occluders
// (a pole) hide all that lies behind them, occluders off screen or behind the front layer are
// lost, and few slices band.

fn ambient_occlusion(px: vec2<i32>, g: GSample) -> f32 {
    let nd = ssao.counts.y;
    let rot = pixel_noise(px);
    let shift = pixel_noise(px + vec2<i32>(17, 59));
    let radius_px = radius_pixels(g.p);
    let v = normalize(ssao.cam_pos.xyz - g.p);
    var sum = 0.0;
    for (var d = 0u; d < nd; d++) {
        let a = PI * (f32(d) + rot) / f32(nd);
        let dir = vec2<f32>(cos(a), sin(a));
        // The slice's in-plane axis ⟂ v (on the side of +dir on screen) and its normal.
        let dir3 = dir.x * ssao.cam_right.xyz - dir.y * ssao.cam_up.xyz;
        let ortho = normalize(dir3 - dot(dir3, v) * v);
        let axis = cross(ortho, v);
        let np = g.n - axis * dot(g.n, axis);
        let np_len = length(np);
        if np_len < 1e-6 {
            continue;
        }
        let gamma = sign(dot(np, ortho)) * acos(clamp(dot(np, v) / np_len, -1.0, 1.0));
        // Horizon cosines on the −dir (x) and +dir (y) sides.
        var c = vec2<f32>(-1.0);
        for (var side = 0u; side < 2u; side++) {
            let sdir = select(-dir, dir, side == 1u);
            for (var s = 0u; s < ssao.counts.z; s++) {
                let pix = march_pixel(px, sdir, s, radius_px, shift);
                if !in_target(pix) {
                    break;
                }
                let o = gposition(pix);
                if o.w < 0.5 {
                    continue;
                }
                let dv = o.xyz - g.p;
                let dist = length(dv);
                let w = falloff_weight(dist);
                if dot(dv, g.n) < ssao.params.y || w <= 0.0 {
                    continue;
                }
                let cos_h = mix(-1.0, dot(dv, v) / dist, w);
                c[side] = max(c[side], cos_h);
            }
        }
        let h1 = gamma + max(-acos(c.x) - gamma, -0.5 * PI);
        let h2 = gamma + min(acos(c.y) - gamma, 0.5 * PI);
        let sg = sin(gamma);
        let cg = cos(gamma);
        let vis = 0.25 * (-cos(2.0 * h1 - gamma) + cg + 2.0 * h1 * sg)
            + 0.25 * (-cos(2.0 * h2 - gamma) + cg + 2.0 * h2 * sg);
        sum += np_len * vis;
    }
    return sum / f32(nd);
}
