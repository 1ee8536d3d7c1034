// ssao/filter.wgsl — the passes after the AO pass, both weighted by the geometry they smooth
// over, neither by the AO itself (the G-buffer is the guide):
// - fs_blur, the cross-bilateral blur (Tomasi & Manduchi 1998, "Bilateral Filtering for Gray
//   and Color Images", ICCV; the guide another image: Eisemann & Durand 2004, Petschnigg et al.
//   2004): one axis per pass (pass_info.axis), run along x then y. Weights: a Gaussian of the
//   texel offset (σ = radius/2), a Gaussian of the neighbour's distance from the centre's
//   tangent plane (σ = 2 % of the view depth, so a slanted plane is not cut into bands), and
//   (n·n′)⁸. Failure mode: the 2-D bilateral filter is not separable, so the two passes leak
//   across diagonal edges (Pham & van Vliet 2005, "Separable Bilateral Filtering for Fast Video
//   Preprocessing", ICME); and a blur wide enough to hide few samples' noise flattens contact
//   shadows and thin occluders' AO.
// - fs_temporal, temporal accumulation (reverse reprojection: Nehab, Sander, Lawrence,
//   Tatarchuk & Isidoro 2007, "Accelerating Real-Time Shading with Reverse Reprojection
//   Caching", Graphics Hardware; over the frames' rotations: Jimenez et al. 2016, §5): the
//   point's position through the previous frame's view-projection finds its history texel; the
//   history is kept where the depth stored there is the point's own previous depth within 2 %,
//   and blended as the mean of the frames so far, then with weight 1/frames. Failure modes: a
//   history dropped at disocclusions restarts from one frame's noise there, and a history
//   read at the nearest texel of a moving view is resampled, so detail blurs and lags.
// - fs_upsample, joint bilateral upsampling (Kopf, Cohen, Lischinski & Uyttendaele 2007, "Joint
//   Bilateral Upsampling", SIGGRAPH) of half-resolution AO: the four AO texels around each
//   pixel, bilinear weights × the same geometric weights; where none is the same surface (a
//   one-pixel feature), the nearest in depth. Failure mode: detail finer than two pixels (a thin
//   pole's contact shadow) is lost or blocky.

const PLANE_SIGMA: f32 = 0.02;
const NORMAL_POWER: f32 = 8.0;

// The geometric weight of neighbour `o` for centre `c` (both valid).
fn geometric_weight(c: GSample, o: GSample) -> f32 {
    let plane = dot(o.p - c.p, c.n) / (PLANE_SIGMA * max(view_depth(c.p), 1e-6));
    return exp(-0.5 * plane * plane) * pow(max(dot(o.n, c.n), 0.0), NORMAL_POWER);
}

@fragment
fn fs_blur(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let out = blur(pos);
    flush_loads(pos.y);
    return out;
}

fn blur(pos: vec4<f32>) -> vec4<f32> {
    let q = vec2<i32>(pos.xy);
    let scale = i32(ssao.params.w);
    let c = gsample(q * scale);
    if !c.valid {
        return vec4<f32>(0.0);
    }
    let radius = i32(ssao.params.z);
    let sigma = max(0.5 * f32(radius), 0.5);
    let size = vec2<i32>(ssao.sizes.zw);
    var sum = 0.0;
    var weights = 0.0;
    for (var i = -radius; i <= radius; i++) {
        let t = q + pass_info.axis.xy * i;
        if any(t < vec2<i32>(0)) || any(t >= size) {
            continue;
        }
        let o = gsample(t * scale);
        if !o.valid {
            continue;
        }
        let x = f32(i) / sigma;
        let w = exp(-0.5 * x * x) * geometric_weight(c, o);
        sum += w * obscurance_at(t);
        weights += w;
    }
    return vec4<f32>(sum / weights, 0.0, 0.0, 0.0);
}

@fragment
fn fs_upsample(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let out = upsample(pos);
    flush_loads(pos.y);
    return out;
}

fn upsample(pos: vec4<f32>) -> vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let c = gsample(p);
    if !c.valid {
        return vec4<f32>(0.0);
    }
    // AO texel q stands for target pixel 2q: pixel p sits at p/2 in AO texels.
    let f = vec2<f32>(p) * 0.5;
    let b = vec2<i32>(floor(f));
    let t = f - floor(f);
    let size = vec2<i32>(ssao.sizes.zw);
    var sum = 0.0;
    var weights = 0.0;
    var nearest = 0.0;
    var nearest_plane = 1e30;
    for (var k = 0; k < 4; k++) {
        let o = vec2<i32>(k & 1, k >> 1u);
        let q = min(b + o, size - vec2<i32>(1));
        let g = gsample(q * 2);
        if !g.valid {
            continue;
        }
        let value = obscurance_at(q);
        let bilinear = mix(1.0 - t.x, t.x, f32(o.x)) * mix(1.0 - t.y, t.y, f32(o.y));
        let w = bilinear * geometric_weight(c, g);
        sum += w * value;
        weights += w;
        let plane = abs(dot(g.p - c.p, c.n));
        if plane < nearest_plane {
            nearest_plane = plane;
            nearest = value;
        }
    }
    if weights < 1e-4 {
        return vec4<f32>(nearest, 0.0, 0.0, 0.0);
    }
    return vec4<f32>(sum / weights, 0.0, 0.0, 0.0);
}

const HISTORY_DEPTH_TOLERANCE: f32 = 0.02;

struct TemporalOut {
    @location(0) obscurance: vec4<f32>,
    // The next frame's history: obscurance, this frame's view depth (0: background).
    @location(1) history: vec4<f32>,
}

@fragment
fn fs_temporal(@builtin(position) pos: vec4<f32>) -> TemporalOut {
    let out = accumulate(pos);
    flush_loads(pos.y);
    return out;
}

fn accumulate(pos: vec4<f32>) -> TemporalOut {
    let p = vec2<i32>(pos.xy);
    let g0 = gposition(p);
    if g0.w < 0.5 {
        return TemporalOut(vec4<f32>(0.0), vec4<f32>(0.0));
    }
    let current = obscurance_at(p);
    let depth = (ssao.view_proj * vec4<f32>(g0.xyz, 1.0)).w;
    var value = current;
    let frame = ssao.temporal.x;
    let c = ssao.prev_view_proj * vec4<f32>(g0.xyz, 1.0);
    if frame > 0u && c.w > 0.0 {
        let ndc = c.xy / c.w;
        let q = vec2<i32>(floor(vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * vec2<f32>(ssao.sizes.xy)));
        if in_target(q) {
            let h = textureLoad(history, q, 0);
            loads += 1u;
            if h.g > 0.0 && abs(h.g - c.w) < HISTORY_DEPTH_TOLERANCE * c.w {
                let weight = 1.0 / f32(min(frame + 1u, ssao.temporal.y));
                value = mix(h.r, current, weight);
            }
        }
    }
    return TemporalOut(vec4<f32>(value, 0.0, 0.0, 0.0), vec4<f32>(value, depth, 0.0, 0.0));
}
