// texture/mip_nearest.wgsl — `tex_mip_nearest`: bilinear in the MIP level nearest λ.
//
// Technique: Williams 1983, "Pyramidal Parametrics", SIGGRAPH, with the level rounded
// (OpenGL's LINEAR_MIPMAP_NEAREST).
// Failure mode: isotropic (blurry at grazing angles, like trilinear), and the level jumps where
// λ crosses a half level: visible bands on a receding plane and popping under motion.
// Inputs: texture `t` and its MIP levels, uv, `uv_footprint`.

fn texture_mip_nearest(t: u32, uv: vec2<f32>) -> vec4<f32> {
    let info = texture_infos[t];
    let l = clamp(level_of_detail(info), 0.0, f32(info.mip_count - 1u));
    if !(l >= 0.5) {
        return texture_sample(t, uv);
    }
    return bilinear(mip_level(t, u32(round(l))), uv);
}
