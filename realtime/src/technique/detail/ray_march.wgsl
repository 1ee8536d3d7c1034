// detail/ray_march.wgsl — steep parallax, relief mapping and parallax occlusion mapping: a
// linear search down the camera ray through the height range, then each its own refinement;
// POM's self-shadowing.
//
// Technique: the ray enters the slab of heights at w_max and leaves it at w_min; k layers of
// thickness (w_max − w_min)/k are tested top down until the ray is at or below the surface
// (gap = w − w(uv(w)) ≤ 0).
// - Steep parallax (McGuire & McGuire 2005, "Steep Parallax Mapping", I3D poster): the first
//   layer below the surface, unrefined.
// - Relief mapping (Policarpo, Oliveira & Comba 2005, "Real-Time Relief Mapping on Arbitrary
//   Polygonal Surfaces", I3D, §3.1): then `binary_steps` halvings of the bracketing layer.
// - Parallax occlusion mapping (Tatarchuk 2006, "Dynamic Parallax Occlusion Mapping with
//   Approximate Soft Shadows", I3D, §3): k = mix(max_steps, min_steps, cos θ) layers (more at
//   grazing angles), then the intersection of the ray with the segment joining the last two
//   height samples (the secant).
// Self-shadowing (POM's `self_shadow`, after Tatarchuk 2006 §3.3): from the hit, the ray towards
// the light climbs to w_max in `shadow_steps` samples; at a sample a distance t along it, a
// height x above the ray (x·cos of the light's elevation across it) covers the light's disk of
// radius R = t·tan α: V = min over samples of clamp(½ − ½·x⊥/R, 0, 1) — our linearisation of the
// covered fraction of the disk; for delta lights (α = 0) any sample above the ray gives V = 0.
// Cost: 4 fetches per layer (+ 4 for the normal map); relief 4 per halving; shadows 4 per sample.
// Failure mode: a layer thinner than a feature can step over it (too few steps on
// high-frequency heightfields: the bricks' grooves), showing the surface behind it; steep
// parallax's stair steps; the secant is exact only for a linear profile. Self-shadowing is
// evaluated on heightfield patches (rectangles) only: the G-buffer holds no tangent frame for a
// mesh's shading pass.
// Inputs: the family's uniforms (`steps`, `max_steps`, `binary_steps`, `shadow_steps`).

// Heights where the ray is last above the surface and first at or below it, with the gaps there.
struct Bracket {
    above: f32,
    below: f32,
    gap_above: f32,
    gap_below: f32,
}

// Gap between the ray and the surface at height w of the ray.
fn ray_gap(fr: DetailFrame, duv_dw: vec2<f32>, w: f32) -> f32 {
    return w - detail_height(fr, fr.uv + duv_dw * w);
}

fn linear_search(fr: DetailFrame, duv_dw: vec2<f32>, layers: u32) -> Bracket {
    let dw = (fr.hi - fr.lo) / f32(layers);
    var above = fr.hi;
    var gap_above = ray_gap(fr, duv_dw, above);
    if gap_above <= 0.0 {
        return Bracket(above, above, gap_above, gap_above);
    }
    for (var i = 1u; i <= layers; i++) {
        count_iteration();
        let w = select(fr.hi - dw * f32(i), fr.lo, i == layers);
        let gap = ray_gap(fr, duv_dw, w);
        if gap <= 0.0 {
            return Bracket(above, w, gap_above, gap);
        }
        above = w;
        gap_above = gap;
    }
    // Only by rounding: at w_min the ray is at or below every height.
    return Bracket(above, fr.lo, gap_above, 0.0);
}

// The ray's height between `above` (ray above the surface) and `below` (at or below it) after
// `halvings` bisections of that bracket (Policarpo, Oliveira & Comba 2005 §3.1): the middle of
// the last bracket. Relief mapping and relaxed cone stepping finish with it.
fn binary_refine(fr: DetailFrame, duv_dw: vec2<f32>, above: f32, below: f32, halvings: u32) -> f32 {
    var hi = above;
    var lo = below;
    for (var i = 0u; i < halvings; i++) {
        count_iteration();
        let mid = 0.5 * (hi + lo);
        if ray_gap(fr, duv_dw, mid) <= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (hi + lo);
}

fn ray_march(f: FrameUniforms, fr: DetailFrame, duv_dw: vec2<f32>, cos_theta: f32) -> DetailHit {
    var layers = f.families.detail.steps;
    if DETAIL_METHOD == DETAIL_POM {
        layers = u32(round(mix(f32(f.families.detail.max_steps), f32(f.families.detail.steps), cos_theta)));
    }
    let b = linear_search(fr, duv_dw, max(layers, 1u));
    var w = b.below;
    if DETAIL_METHOD == DETAIL_RELIEF_MAPPING {
        w = binary_refine(fr, duv_dw, b.above, b.below, f.families.detail.binary_steps);
    } else if DETAIL_METHOD == DETAIL_POM {
        let denom = b.gap_above - b.gap_below;
        if denom > 0.0 {
            w = b.above + (b.below - b.above) * (b.gap_above / denom);
        }
    }
    return DetailHit(true, fr.uv + duv_dw * w, w);
}

// Visibility through the heightfield of the light in unit direction `wi` from the surface
// point `sp`, `tan_alpha` the tangent of the light's angular radius (0: a delta light); 1 unless
// the pipeline is POM with self-shadowing and sp is on a displaced rectangle.
fn detail_self_shadow(f: FrameUniforms, sp: SurfacePoint, wi: vec3<f32>, tan_alpha: f32) -> f32 {
    if DETAIL_METHOD != DETAIL_POM || f.families.detail.shadow_steps == 0u {
        return 1.0;
    }
    let s = shapes[sp.shape];
    if s.detail.x == NONE || s.kind != SHAPE_RECTANGLE {
        return 1.0;
    }
    let n = s.normal.xyz;
    let w0 = dot(sp.p - s.center.xyz, n);
    let base = Differential(sp.p - n * w0, n, n, sp.uv, s.half_u.xyz * 2.0, s.half_v.xyz * 2.0, vec4<f32>(0.0));
    let fr = detail_frame(f, base, s);
    let v = frame_coords(fr, wi);
    // A light at or below the base plane's horizon is left to the cosine.
    if !(v.z > 0.0) || w0 >= fr.hi {
        return 1.0;
    }
    let duv_dw = v.xy / v.z;
    let sin_e = clamp(dot(wi, n), 0.0, 1.0);
    let cos_e = sqrt(1.0 - sin_e * sin_e);
    let samples = f.families.detail.shadow_steps;
    let dw = (fr.hi - w0) / f32(samples);
    // The hit is only as exact as the search: heights within 1 % of the range of the shadow
    // ray count as below it (without this the ray shadows its own start: acne).
    let tolerance = 0.01 * (fr.hi - fr.lo);
    var vis = 1.0;
    for (var i = 1u; i <= samples; i++) {
        count_iteration();
        let w = w0 + dw * f32(i);
        let excess = detail_height(fr, sp.uv + duv_dw * (w - w0)) - w - tolerance;
        if tan_alpha <= 0.0 {
            if excess > 0.0 {
                return 0.0;
            }
        } else {
            let radius = (w - w0) / sin_e * tan_alpha;
            vis = min(vis, clamp(0.5 - 0.5 * excess * cos_e / radius, 0.0, 1.0));
        }
    }
    return vis;
}
