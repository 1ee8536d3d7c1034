// detail/horizon.wgsl — horizon mapping: self-shadowing for normal and bump mapping.
//
// Technique: Max 1988, "Horizon Mapping: Shadows for Bump-Mapped Surfaces", The Visual
// Computer 4(2); Sloan & Cohen 2000, "Interactive Horizon Mapping", EGWR. Per texel of a
// heightfield patch the tangent of the horizon's elevation tan β_k in D azimuths
// (technique/detail/horizon_map.rs, at height multiplier 1; × k here). A light at elevation e
// above the base plane, azimuth φ (both in the patch's metric frame: the light direction's
// components along ∂p/∂u, ∂p/∂v in metres and along n), sees the point where e > β(φ), β
// interpolated linearly between the two nearest azimuths: V = 1 or 0 for a delta light, and
// for a light of angular radius α the covered fraction linearised in angle,
// V = clamp(½ + (e − β)/(2α), 0, 1) (our linearisation, as POM's self-shadowing's).
// Cost: ⌈D/4⌉ bilinear lookups (4 fetches each) per light.
// Failure modes: the horizon between two azimuths is interpolated (a ridge between them is
// missed); blockers beyond the map's reach cast nothing; the base point is shadowed, not the
// point of the displaced surface the camera would see (normal and bump mapping do not move
// it); rectangles only, as POM's self-shadowing.
// Inputs: the shape's `detail.w` (first horizon record), the family's uniforms (`height_scale`, `horizon_azimuths`).

// V of a light in unit direction `wi` with angular radius tan⁻¹(tan_alpha) at surface point
// sp under the horizon map; 1 without one (no azimuths, not a displaced rectangle).
fn horizon_visibility(f: FrameUniforms, sp: SurfacePoint, wi: vec3<f32>, tan_alpha: f32) -> f32 {
    let d = f.families.detail.horizon_azimuths;
    let s = shapes[sp.shape];
    if d == 0u || s.detail.x == NONE || s.detail.w == NONE || s.kind != SHAPE_RECTANGLE {
        return 1.0;
    }
    let n = s.normal.xyz;
    let dpdu = s.half_u.xyz * 2.0;
    let dpdv = s.half_v.xyz * 2.0;
    let base = Differential(sp.p, n, n, sp.uv, dpdu, dpdv, vec4<f32>(0.0));
    let fr = detail_frame(f, base, s);
    let v = frame_coords(fr, wi);
    // Below the base plane's horizon the cosine decides.
    if !(v.z > 0.0) {
        return 1.0;
    }
    // Metres along the patch's u and v axes per unit of wi.
    let x = v.x * length(dpdu);
    let y = v.y * length(dpdv);
    let horizontal = sqrt(x * x + y * y);
    let e = atan2(v.z, horizontal);
    var phi = atan2(y, x);
    if phi < 0.0 {
        phi += TAU;
    }
    let k = phi / TAU * f32(d);
    let k0 = u32(floor(k)) % d;
    let k1 = (k0 + 1u) % d;
    let t = k - floor(k);
    let h0 = texture_sample(s.detail.w + k0 / 4u, sp.uv)[k0 % 4u];
    let h1 = texture_sample(s.detail.w + k1 / 4u, sp.uv)[k1 % 4u];
    let beta = atan(mix(h0, h1, t) * f.families.detail.height_scale);
    if tan_alpha <= 0.0 {
        return select(0.0, 1.0, e > beta);
    }
    return clamp(0.5 + (e - beta) / (2.0 * atan(tan_alpha)), 0.0, 1.0);
}
