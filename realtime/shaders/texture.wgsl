// texture.wgsl — the leaf samplers: texel fetch, bilinear lookup, equirectangular environment.
//
// Technique: manual bilinear filtering from a texel buffer, written to give exactly what the
// oracle's `scenes::texture::Texture::sample` and `scenes::environment_lookup` give: texel
// (i, j) centred at ((i + ½)/W, (j + ½)/H), v = 0 the top row, wrap per axis (repeat = Euclidean
// remainder, clamp, mirror); the texture filters (texture/*.wgsl) build on these lookups; the environment uses Mitsuba 3's `envmap` placement (columns at
// texel centres, rows at v = j/(H − 1), u wraps) measured against Mitsuba 3.9.1 (docs/ARCHITECTURE.md
// "Environment map"). No mip-mapping: both renderers point-sample the filter at one uv.
// Reference: none beyond the texture model; bilinear interpolation as in pbrt-v4 §10.4.3.
// Failure mode: magnification only — minified textures alias (as in the oracle, whose pixel
// box filter then averages the aliasing away at high sample counts; this renderer only with
// supersampling).
// Inputs: `texture_infos`, `texels` (group 0). These two functions and the environment lookup
// are the only ones that read them; each texel read counts as one fetch.

fn wrap_index(i: i32, n: i32, mode: u32) -> i32 {
    switch mode {
        case 1u: {
            return clamp(i, 0, n - 1);
        }
        case 2u: {
            let period = ((i % (2 * n)) + 2 * n) % (2 * n);
            return select(2 * n - 1 - period, period, period < n);
        }
        default: {
            return ((i % n) + n) % n;
        }
    }
}

// Texel (x, y) of the texture `info` describes, both already inside the image.
fn texel_at(info: TextureInfo, x: i32, y: i32) -> vec4<f32> {
    count_fetch();
    return texels[info.offset + u32(y) * info.width + u32(x)];
}

// Texel (i, j) of the texture `info` describes, after its wrap modes (Texture::texel).
fn texel_wrapped(info: TextureInfo, i: i32, j: i32) -> vec4<f32> {
    let x = wrap_index(i, i32(info.width), info.wrap & 15u);
    let y = wrap_index(j, i32(info.height), (info.wrap >> 4u) & 15u);
    return texel_at(info, x, y);
}

// Bilinear lookup of texture `t` at `uv` (Texture::sample): level 0, no footprint (surface
// detail's heightfield searches, emission at a light's sample points).
fn texture_sample(t: u32, uv: vec2<f32>) -> vec4<f32> {
    return bilinear(texture_infos[t], uv);
}

// Bilinear lookup of the texture or level record `info` at `uv`.
fn bilinear(info: TextureInfo, uv: vec2<f32>) -> vec4<f32> {
    let x = uv.x * f32(info.width) - 0.5;
    let y = uv.y * f32(info.height) - 0.5;
    if !(abs(x) < 1e30 && abs(y) < 1e30) {
        return vec4<f32>(0.0);
    }
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let i = i32(x0);
    let j = i32(y0);
    let top = texel_wrapped(info, i, j) * (1.0 - fx) + texel_wrapped(info, i + 1, j) * fx;
    let bottom = texel_wrapped(info, i, j + 1) * (1.0 - fx) + texel_wrapped(info, i + 1, j + 1) * fx;
    return top * (1.0 - fy) + bottom * fy;
}

// scenes::equirect_uv: φ = atan2(d.x, −d.z) wrapped to [0, 2π), u = φ/2π, v = acos(d.y)/π.
fn equirect_uv(d: vec3<f32>) -> vec2<f32> {
    var u = atan2(d.x, -d.z) / TAU;
    if u < 0.0 {
        u += 1.0;
    }
    return vec2<f32>(u, acos(clamp(d.y, -1.0, 1.0)) / PI);
}

// scenes::environment_lookup: Mitsuba's texel placement, bilinear, u wrapping, rows clamped.
fn environment_lookup(t: u32, d: vec3<f32>) -> vec4<f32> {
    let info = texture_infos[t];
    let uv = equirect_uv(d);
    let w = i32(info.width);
    let h = i32(info.height);
    let x = uv.x * f32(w) - 0.5;
    let y = select(0.0, uv.y * f32(h - 1), h > 1);
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let i = i32(x0);
    let j = clamp(i32(y0), 0, h - 1);
    let j1 = min(j + 1, h - 1);
    let i0 = wrap_index(i, w, 0u);
    let i1 = wrap_index(i + 1, w, 0u);
    let top = texel_at(info, i0, j) * (1.0 - fx) + texel_at(info, i1, j) * fx;
    let bottom = texel_at(info, i0, j1) * (1.0 - fx) + texel_at(info, i1, j1) * fx;
    return top * (1.0 - fy) + bottom * fy;
}

// A TexRgb input seen through the pixel: the constant, or factor × the filtered texture
// (texture/filter.wgsl) over the pixel's footprint about uv.
fn eval_tex_rgb(tex: u32, value: vec3<f32>, uv: vec2<f32>) -> vec3<f32> {
    if tex == NONE {
        return value;
    }
    return texture_filtered(tex, uv).xyz * value;
}

// A TexRgb input at one point (no footprint): the constant, or factor × texture(uv).
fn eval_tex_rgb_point(tex: u32, value: vec3<f32>, uv: vec2<f32>) -> vec3<f32> {
    if tex == NONE {
        return value;
    }
    return texture_sample(tex, uv).xyz * value;
}

// A TexScalar input seen through the pixel: the constant, or factor × the filtered
// texture's `channel`.
fn eval_tex_scalar(tex: u32, channel: u32, value: f32, uv: vec2<f32>) -> f32 {
    if tex == NONE {
        return value;
    }
    return texture_filtered(tex, uv)[min(channel, 3u)] * value;
}
