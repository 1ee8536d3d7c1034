// texture/sat.wgsl — `tex_sat`: the mean over the footprint's bounding box from a summed-area
// table.
//
// Technique: Crow 1984, "Summed-Area Tables for Texture Mapping", SIGGRAPH: the exact integral
// of the nearest-texel image over an axis-aligned box (at least one texel wide, which makes
// magnification bilinear) is four reads of the continuous prefix P, itself the bilinear
// interpolation of the integer table F (technique/texture/sat.rs: the mean subtracted, Hensley
// et al. 2005). Wrap modes are exact: along each axis the prefix of the wrapped image is a
// combination of at most two prefixes of the texture (repeat: q·F(N) + F(r); mirror, period 2N:
// 2q·F(N) + F(t) or (2q + 2)·F(N) − F(2N − t); clamp: the edge texel extended).
// Failure mode: the box is the footprint's axis-aligned bounding box: a footprint diagonal to
// the texture axes (a plane seen at a grazing angle, rotated 45°) is averaged over a much larger
// area; f32 sums limit the precision of small boxes in large textures.
// Inputs: texture `t` and its table, uv, `uv_footprint`.

// Along one axis of n texels with wrap `mode`, the prefix at integer x as c0·F(i0) + c1·F(i1):
// (c0, i0, c1, i1).
fn sat_axis(x: f32, n: u32, mode: u32) -> vec4<f32> {
    let nf = f32(n);
    switch mode {
        case 1u: {
            if x <= 0.0 {
                return vec4<f32>(x, 1.0, 0.0, 0.0);
            }
            if x <= nf {
                return vec4<f32>(1.0, x, 0.0, 0.0);
            }
            return vec4<f32>(1.0 + (x - nf), nf, -(x - nf), nf - 1.0);
        }
        case 2u: {
            let q = floor(x / (2.0 * nf));
            let r = x - 2.0 * nf * q;
            if r <= nf {
                return vec4<f32>(2.0 * q, nf, 1.0, r);
            }
            return vec4<f32>(2.0 * q + 2.0, nf, -1.0, 2.0 * nf - r);
        }
        default: {
            let q = floor(x / nf);
            return vec4<f32>(q, nf, 1.0, x - nf * q);
        }
    }
}

// F(i, j) of the table record `table` (one mean texel, then (W + 1) × (H + 1)).
fn sat_at(table: TextureInfo, i: f32, j: f32) -> vec4<f32> {
    count_fetch();
    return texels[table.offset + 1u + u32(j) * table.width + u32(i)];
}

// The prefix of the wrapped image at integer (x, y): Σ over the axes' terms.
fn sat_integer(info: TextureInfo, table: TextureInfo, x: f32, y: f32) -> vec4<f32> {
    let ax = sat_axis(x, info.width, info.wrap & 15u);
    let ay = sat_axis(y, info.height, (info.wrap >> 4u) & 15u);
    var s = vec4<f32>(0.0);
    if ax.x != 0.0 && ay.x != 0.0 {
        s += ax.x * ay.x * sat_at(table, ax.y, ay.y);
    }
    if ax.z != 0.0 && ay.x != 0.0 {
        s += ax.z * ay.x * sat_at(table, ax.w, ay.y);
    }
    if ax.x != 0.0 && ay.z != 0.0 {
        s += ax.x * ay.z * sat_at(table, ax.y, ay.w);
    }
    if ax.z != 0.0 && ay.z != 0.0 {
        s += ax.z * ay.z * sat_at(table, ax.w, ay.w);
    }
    return s;
}

// The continuous prefix P(x, y): bilinear between the integer prefixes around (x, y).
fn sat_prefix(info: TextureInfo, table: TextureInfo, x: f32, y: f32) -> vec4<f32> {
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let a = mix(sat_integer(info, table, x0, y0), sat_integer(info, table, x0 + 1.0, y0), fx);
    let b = mix(sat_integer(info, table, x0, y0 + 1.0), sat_integer(info, table, x0 + 1.0, y0 + 1.0), fx);
    return mix(a, b, fy);
}

fn texture_sat(t: u32, uv: vec2<f32>) -> vec4<f32> {
    let info = texture_infos[t];
    if info.sat == NONE {
        return texture_sample(t, uv);
    }
    let table = texture_infos[info.sat];
    let j = footprint_texels(info);
    // Half extents of the bounding box of the parallelogram uv ± ½J·x̂ ± ½J·ŷ, at least half a texel.
    let h = max(0.5 * (abs(j.xy) + abs(j.zw)), vec2<f32>(0.5));
    let c = uv * vec2<f32>(f32(info.width), f32(info.height));
    if !(all(abs(c) < vec2<f32>(1e7)) && all(h < vec2<f32>(1e7))) {
        return vec4<f32>(0.0);
    }
    let lo = c - h;
    let hi = c + h;
    let sum = sat_prefix(info, table, hi.x, hi.y) - sat_prefix(info, table, lo.x, hi.y)
        - sat_prefix(info, table, hi.x, lo.y) + sat_prefix(info, table, lo.x, lo.y);
    count_fetch();
    let mean = texels[table.offset];
    return mean + sum / (4.0 * h.x * h.y);
}
