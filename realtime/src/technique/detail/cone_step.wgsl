// detail/cone_step.wgsl — cone step mapping (Dummer 2006) and relaxed cone stepping
// (Policarpo & Oliveira 2007).
//
// Technique: Dummer 2006, "Cone Step Mapping: An Iterative Ray-Heightfield Intersection
// Algorithm": each texel stores the ratio c (uv per metre of height) of the widest upward cone
// with its apex on the surface there that holds no surface (detail/cone_map.rs). From a ray point a gap
// d above the surface, where the ray moves r = |(a, b)/c| in uv per metre of descent, the ray
// leaves that cone after a descent δ = c·d/(c + r) (radius c·(d − δ) = r·δ), so stepping by δ
// never crosses the surface; `steps` steps from w_max. Relaxed cones (Policarpo & Oliveira
// 2007, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3, ch. 18): wider cones that a ray
// through their apex crosses at most once, so a step may end below the surface; the first step
// that does is refined by `binary_steps` halvings, as relief mapping.
// Cost: 8 fetches per step (height and cone ratio), 4 for the normal map; relaxed: 4 more to
// test the last point, 4 per halving.
// Failure mode: conservative cones converge slowly towards the surface (the ray stops short
// after `steps`, near steep walls and at grazing angles, where r ≫ c); the cone map is built
// from texel centres, which bilinear interpolation can cross (Bán, Valasek, Bálint & Vad 2024,
// "Robust Cone Step Mapping", EG short papers), and relaxed cones checked along lines through
// their apex only; a height multiplier k ≠ 1 rescales the ratios by 1/k.
// Inputs: the shape's cone map (`detail.w`), the family's uniforms (`steps`, `binary_steps`).

fn cone_step(f: FrameUniforms, fr: DetailFrame, s: Shape, duv_dw: vec2<f32>) -> DetailHit {
    let inv_k = 1.0 / max(f.families.detail.height_scale, 1e-30);
    let r = length(duv_dw);
    let relaxed = f.families.detail.binary_steps > 0u;
    var above = fr.hi;
    var w = fr.hi;
    for (var i = 0u; i < f.families.detail.steps; i++) {
        count_iteration();
        let uv = fr.uv + duv_dw * w;
        let gap = w - detail_height(fr, uv);
        if gap <= 0.0 {
            break;
        }
        let c = texture_sample(s.detail.w, uv).x * inv_k;
        above = w;
        w = max(w - select(gap, c * gap / (c + r), c + r > 0.0), fr.lo);
    }
    // (Nested, not `&&`: naga evaluates both operands, and the gap costs 4 fetches.)
    var below = false;
    if relaxed {
        below = ray_gap(fr, duv_dw, w) <= 0.0;
    }
    if below {
        w = binary_refine(fr, duv_dw, above, w, f.families.detail.binary_steps);
    }
    return DetailHit(true, fr.uv + duv_dw * w, w);
}
