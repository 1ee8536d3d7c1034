// texture/filter.wgsl — what the texture filters share: the pixel's footprint in texture
// space and the levels (technique/texture/mod.rs, one file per filter beside this one). The
// dispatch, `texture_filtered(t, uv)`, and TEXTURE_FILTER are generated per shader module
// for the method's filter (pipelines.rs `shader_source`).
//
// Technique: every lookup of a material texture, a normal map or the emission a camera ray
// sees goes through `texture_filtered`, which integrates the texture over the pixel's
// footprint by the method's filter. The footprint is J = (∂(u,v)/∂x, ∂(u,v)/∂y) per target
// pixel: hardware derivatives (dpdx/dpdy over the 2×2 quad, set at the fragment entry points
// in uniform control flow) or ray differentials (Igehy 1999, "Tracing Ray Differentials",
// SIGGRAPH; pbrt-v4 §10.1.1), set where the surface's differential geometry is known.
// Level of detail λ = log₂ ρ + lod_bias with ρ = max(|J·x̂|, |J·ŷ|) in level-0 texels
// (OpenGL 4.6 §8.14.1).
// Ground truth: the oracle's box filter over the pixel of the bilinear reconstruction of
// level 0; every filter here approximates that integral.
// Failure mode: hardware derivatives are wrong where the quad straddles a silhouette or a
// G-buffer edge (deferred lighting differences its stored uv); the footprint is that of the
// surface's base uv, not of a parallax-shifted one.
// Inputs: `uv_footprint` (private), the family's uniforms (`frame.families.texture`: `lod_bias`, `max_anisotropy`).

// ∂(u,v)/∂x (xy) and ∂(u,v)/∂y (zw) of the pixel being shaded, per target pixel. Zero until
// set: every filter then reads level 0 at a point.
var<private> uv_footprint: vec4<f32>;

// The family's block of the frame uniform (TextureUniforms in texture/mod.rs).
struct TextureUniforms {
    // Added to the level of detail λ, levels.
    lod_bias: f32,
    // Most probes (tex_footprint) or ellipse eccentricity (tex_ewa).
    max_anisotropy: f32,
}

// Whether the method's filter reads a footprint at all (nearest and bilinear do not).
fn filter_reads_footprint() -> bool {
    return TEXTURE_FILTER != TEX_NEAREST && TEXTURE_FILTER != TEX_BILINEAR;
}

// Hardware derivatives of `uv` over the fragment quad. Call in uniform control flow.
fn set_hardware_footprint(uv: vec2<f32>) {
    let fp = vec4<f32>(dpdx(uv), dpdy(uv));
    uv_footprint = select(vec4<f32>(0.0), fp, all(abs(fp) < vec4<f32>(1e30)));
}

// ∂p/∂x and ∂p/∂y of a surface point per target pixel.
struct PixelDifferentials {
    dpx: vec3<f32>,
    dpy: vec3<f32>,
}

// Ray differentials (Igehy 1999) at p on the tangent plane of normal n: the camera rays
// through the next target pixel in x and in y meet the plane at p + ∂p/∂x and p + ∂p/∂y.
// Non-finite where the plane is seen edge-on.
fn pixel_differentials(f: FrameUniforms, p: vec3<f32>, n: vec3<f32>) -> PixelDifferentials {
    let o = f.cam_pos.xyz;
    let d = p - o;
    // The pinhole direction as camera_ray_direction builds it before normalising (its −cam_z
    // component 1), and its change per target pixel.
    let d1 = d / dot(d, -f.cam_z.xyz);
    let ddx = f.cam_x.xyz * (2.0 * f.film.z * f.film.w / f.film.x * f.ssaa.y);
    let ddy = f.cam_y.xyz * (-2.0 * f.film.z / f.film.y * f.ssaa.y);
    let dx = d1 + ddx;
    let dy = d1 + ddy;
    return PixelDifferentials(o + dx * (dot(n, d) / dot(n, dx)) - p, o + dy * (dot(n, d) / dot(n, dy)) - p);
}

// The footprint from ray differentials at p on the tangent plane of normal n with ∂p/∂u,
// ∂p/∂v (analytic derivatives only): (du, dv) solve ∂p = ∂p/∂u·du + ∂p/∂v·dv by least
// squares (the normal equations). Zero where the plane is seen edge-on or (u, v) is degenerate.
fn set_analytic_footprint(f: FrameUniforms, p: vec3<f32>, n: vec3<f32>, dpdu: vec3<f32>, dpdv: vec3<f32>) {
    if TEXTURE_DERIVATIVES != 1u || !filter_reads_footprint() {
        return;
    }
    let pd = pixel_differentials(f, p, n);
    let dpx = pd.dpx;
    let dpy = pd.dpy;
    let a = dot(dpdu, dpdu);
    let b = dot(dpdu, dpdv);
    let c = dot(dpdv, dpdv);
    let inv = 1.0 / (a * c - b * b);
    let ux = (c * dot(dpdu, dpx) - b * dot(dpdv, dpx)) * inv;
    let vx = (a * dot(dpdv, dpx) - b * dot(dpdu, dpx)) * inv;
    let uy = (c * dot(dpdu, dpy) - b * dot(dpdv, dpy)) * inv;
    let vy = (a * dot(dpdv, dpy) - b * dot(dpdu, dpy)) * inv;
    let fp = vec4<f32>(ux, vx, uy, vy);
    uv_footprint = select(vec4<f32>(0.0), fp, all(abs(fp) < vec4<f32>(1e30)));
}

// The footprint's two axes in texels of level 0 of `info`: ∂/∂x (xy) and ∂/∂y (zw).
fn footprint_texels(info: TextureInfo) -> vec4<f32> {
    let size = vec2<f32>(f32(info.width), f32(info.height));
    return vec4<f32>(uv_footprint.xy * size, uv_footprint.zw * size);
}

// Level of detail λ = log₂ ρ + lod_bias (−∞ without a footprint: level 0).
fn level_of_detail(info: TextureInfo) -> f32 {
    let j = footprint_texels(info);
    return log2(max(length(j.xy), length(j.zw))) + frame.families.texture.lod_bias;
}

// Number of levels of a full pyramid over `n` texels (down to 1).
fn levels_over(n: u32) -> u32 {
    return firstLeadingBit(max(n, 1u)) + 1u;
}

// The record of MIP level `l` of texture `t` (level 0 is the texture; past the last, the last).
fn mip_level(t: u32, l: u32) -> TextureInfo {
    let info = texture_infos[t];
    if l == 0u || info.mips == NONE {
        return info;
    }
    return texture_infos[info.mips + min(l, info.mip_count - 1u) - 1u];
}

// Bilinear in the two MIP levels around λ, blended (Williams 1983); λ ≤ 0 is level 0.
fn trilinear_at(t: u32, uv: vec2<f32>, lambda: f32) -> vec4<f32> {
    let top = f32(texture_infos[t].mip_count - 1u);
    let l = clamp(lambda, 0.0, top);
    if !(l > 0.0) {
        return texture_sample(t, uv);
    }
    let l0 = floor(l);
    let fl = l - l0;
    let a = bilinear(mip_level(t, u32(l0)), uv);
    if fl == 0.0 {
        return a;
    }
    return mix(a, bilinear(mip_level(t, u32(l0) + 1u), uv), fl);
}
