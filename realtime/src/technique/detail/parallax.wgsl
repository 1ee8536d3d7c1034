// detail/parallax.wgsl — parallax mapping (Kaneko et al. 2001) and offset-limited parallax
// mapping (Welsh 2004): one height lookup, one uv offset.
//
// Technique: Kaneko, Takahei, Inami, Kawakami, Yanagida, Maeda & Tachi 2001, "Detailed Shape
// Representation with Parallax Mapping", ICAT: the ray is assumed to meet the surface at the
// height w(uv) seen under the base point, so uv' = uv(w) = uv + w·(a, b)/c along the camera ray
// (detail/common.wgsl), with Welsh's scale and bias w = k·s·h + b·(w_max − w_min).
// Welsh 2004, "Parallax Mapping with Offset Limiting: A Per-Pixel Approximation of Uneven
// Surfaces" (Infiscape tech. report): the offset × cos θ, i.e. the tangent-plane part of the
// unit view vector instead of its ratio to the normal part, so it never exceeds the height.
// 4 fetches for h, 4 for the normal map at uv'.
// Failure mode: exact only where h is locally constant; the offset (a, b)/c grows as 1/cos θ,
// so plain parallax swims and tears at grazing angles (the failure the view-angle study bounds
// from below) while offset limiting undershoots there; no occlusion, no self-shadowing.
// Inputs: the family's `parallax_bias`.

fn parallax_offset(f: FrameUniforms, fr: DetailFrame, duv_dw: vec2<f32>, limit: f32) -> DetailHit {
    let w = detail_height(fr, fr.uv) + f.families.detail.parallax_bias * (fr.hi - fr.lo);
    return DetailHit(true, fr.uv + duv_dw * (w * limit), w);
}
