// texture/anisotropic.wgsl — `tex_anisotropic`: the adapter's own anisotropic filtering.
//
// Technique: textureSampleGrad on the scene's texture array with the pixel's footprint as the
// gradients (scaled by 2^lod_bias, which shifts λ by lod_bias), on a sampler whose
// anisotropy_clamp is max_anisotropy (EXT_texture_filter_anisotropic; WebGPU maxAnisotropy).
// How many probes the adapter takes, where, and at which level is its own business: the
// texture-filtering study measures it.
// Failure mode: whatever the driver approximates (commonly footprint assembly with up to
// max_anisotropy trilinear probes); texels are f16 (11 significant bits); the fetch counter
// counts one trilinear lookup (8), not what the hardware reads.
// Inputs: texture `t` (layer t of `scene_texture_array`), uv, `uv_footprint`, `frame.families.texture`.

fn texture_anisotropic(t: u32, uv: vec2<f32>) -> vec4<f32> {
    let info = texture_infos[t];
    let scale = exp2(frame.families.texture.lod_bias);
    let dx = uv_footprint.xy * scale;
    let dy = uv_footprint.zw * scale;
    count_fetches(8u);
    switch info.wrap & 15u {
        case 1u: {
            return textureSampleGrad(scene_texture_array, sampler_clamp, uv, t, dx, dy);
        }
        case 2u: {
            return textureSampleGrad(scene_texture_array, sampler_mirror, uv, t, dx, dy);
        }
        default: {
            return textureSampleGrad(scene_texture_array, sampler_repeat, uv, t, dx, dy);
        }
    }
}
