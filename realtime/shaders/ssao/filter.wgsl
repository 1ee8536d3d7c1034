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
        sum += w * textureLoad(obscurance_in, t, 0).r;
        weights += w;
    }
    return vec4<f32>(sum / weights, 0.0, 0.0, 0.0);
}

@fragment
fn fs_upsample(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
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
        let value = textureLoad(obscurance_in, q, 0).r;
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
