// texture/ewa.wgsl — `tex_ewa`: the elliptical weighted average.
//
// Technique: Greene & Heckbert 1986, "Creating Raster Omnimax Images from Multiple Perspective
// Views Using the Elliptical Weighted Average Filter", IEEE CG&A 6(6); Heckbert 1989,
// "Fundamentals of Texture Mapping and Image Warping", MS thesis, §3.5.8. The footprint's axes
// (J·x̂, J·ŷ, in texels) define the conic Q(du, dv) = A·du² + B·du·dv + C·dv² with
// A = vx² + vy² + 1, B = −2(ux·vx + uy·vy), C = ux² + uy² + 1 (the 1s: a unit reconstruction
// filter, so a magnified footprint still covers a texel), scaled so Q < 1 is the ellipse; the
// texels inside weigh exp(−2Q) (a Gaussian truncated at the ellipse). The shorter axis is
// lengthened to at least major/max_anisotropy, and the level is the one where it spans about a
// texel (λ = log₂ minor + lod_bias, the two levels around it blended), as the MIP-mapped EWA of
// Heckbert §3.5.8 and pbrt (3rd ed.) §10.4.5 describe.
// Failure mode: a Gaussian, not a box: softer than the pixel's box filter the ground truth is
// (a bias both ways at edges of texture detail); the cost grows with the ellipse's area.
// Inputs: texture `t` and its MIP levels, uv, `uv_footprint`, `frame.families.texture`.

// Largest half extent of the ellipse's bounding box visited, texels of the level.
const EWA_MAX_RADIUS: f32 = 32.0;

// The EWA over level `l` of texture `t` with footprint axes `ax`, `ay` in level-0 texels.
fn ewa_level(t: u32, uv: vec2<f32>, ax0: vec2<f32>, ay0: vec2<f32>, l: u32) -> vec4<f32> {
    let info = mip_level(t, l);
    let base = texture_infos[t];
    let scale = vec2<f32>(f32(info.width) / f32(base.width), f32(info.height) / f32(base.height));
    let ax = ax0 * scale;
    let ay = ay0 * scale;
    var a = ax.y * ax.y + ay.y * ay.y + 1.0;
    var b = -2.0 * (ax.x * ax.y + ay.x * ay.y);
    var c = ax.x * ax.x + ay.x * ay.x + 1.0;
    let f = a * c - 0.25 * b * b;
    a /= f;
    b /= f;
    c /= f;
    let det = 4.0 * a * c - b * b;
    let ru = min(sqrt(4.0 * c / det), EWA_MAX_RADIUS);
    let rv = min(sqrt(4.0 * a / det), EWA_MAX_RADIUS);
    let s = uv * vec2<f32>(f32(info.width), f32(info.height)) - 0.5;
    if !(all(abs(s) < vec2<f32>(1e7)) && ru == ru && rv == rv) {
        return bilinear(info, uv);
    }
    var sum = vec4<f32>(0.0);
    var weight = 0.0;
    for (var v = i32(ceil(s.y - rv)); v <= i32(floor(s.y + rv)); v++) {
        for (var u = i32(ceil(s.x - ru)); u <= i32(floor(s.x + ru)); u++) {
            count_iteration();
            let du = f32(u) - s.x;
            let dv = f32(v) - s.y;
            let q = a * du * du + b * du * dv + c * dv * dv;
            if q < 1.0 {
                let w = exp(-2.0 * q);
                sum += w * texel_wrapped(info, u, v);
                weight += w;
            }
        }
    }
    return select(bilinear(info, uv), sum / weight, weight > 0.0);
}

fn texture_ewa(t: u32, uv: vec2<f32>) -> vec4<f32> {
    let info = texture_infos[t];
    let j = footprint_texels(info);
    var major = j.xy;
    var minor = j.zw;
    if length(minor) > length(major) {
        major = j.zw;
        minor = j.xy;
    }
    let lmaj = length(major);
    var lmin = length(minor);
    if !(lmaj > 0.0 && lmaj < 1e30) {
        return texture_sample(t, uv);
    }
    // Lengthen the minor axis (perpendicular to the major one where it has none) to fit
    // max_anisotropy.
    let least = lmaj / frame.families.texture.max_anisotropy;
    if lmin < least {
        let dir = select(vec2<f32>(-major.y, major.x) / lmaj, minor / lmin, lmin > 0.0);
        minor = dir * least;
        lmin = least;
    }
    let top = f32(info.mip_count - 1u);
    let l = clamp(log2(lmin) + frame.families.texture.lod_bias, 0.0, top);
    let l0 = floor(l);
    let fl = l - l0;
    let e0 = ewa_level(t, uv, major, minor, u32(l0));
    if fl == 0.0 {
        return e0;
    }
    return mix(e0, ewa_level(t, uv, major, minor, u32(l0) + 1u), fl);
}
