// FXAA 3.11, quality version (Lottes 2009, "FXAA", NVIDIA white paper; the algorithm of its
// FXAA_PC path, written here from its description). One sample per pixel in, one out:
//   1. local contrast: the luma range of the centre and its 4 neighbours; below
//      max(edge_threshold_min, edge_threshold · brightest) the pixel is left alone;
//   2. sub-pixel aliasing: how far the centre stands out of its 3×3 low-pass, relative to the
//      range, shaped by smoothstep² and scaled by `subpixel`;
//   3. the edge's orientation from second differences across rows and across columns, and its
//      side (the neighbour with the steeper gradient);
//   4. a search along the edge, half a pixel towards that side (bilinear lookups average both
//      rows), for where the luma leaves the edge's local average by a quarter of the gradient,
//      with preset 39's step sizes;
//   5. the pixel's distance to the nearer end gives its coverage by the other side: it is
//      resampled that far (≤ ½ pixel) across the edge, or by the sub-pixel amount if larger.
// Fails where it cannot know: a feature thinner than a pixel that the one sample missed, and
// edges of less contrast than the threshold (edge_threshold = 1 finds none).
// post.p0 = (edge_threshold, edge_threshold_min, subpixel, search_steps).

const FXAA_STEP: array<f32, 12> = array<f32, 12>(1.0, 1.0, 1.0, 1.0, 1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0);

fn luma_at(p: vec2<i32>) -> f32 {
    return luma(load_clamped(src, p).rgb);
}

fn fxaa_pixel(frag: vec4<f32>) -> vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let centre = load_clamped(src, p);
    let m = luma(centre.rgb);
    // Image rows run downwards: n is the row above.
    let n = luma_at(p + vec2<i32>(0, -1));
    let s = luma_at(p + vec2<i32>(0, 1));
    let e = luma_at(p + vec2<i32>(1, 0));
    let w = luma_at(p + vec2<i32>(-1, 0));
    let hi = max(m, max(max(n, s), max(e, w)));
    let lo = min(m, min(min(n, s), min(e, w)));
    let range = hi - lo;
    if range < max(post.p0.y, hi * post.p0.x) {
        return centre;
    }
    let nw = luma_at(p + vec2<i32>(-1, -1));
    let ne = luma_at(p + vec2<i32>(1, -1));
    let sw = luma_at(p + vec2<i32>(-1, 1));
    let se = luma_at(p + vec2<i32>(1, 1));

    // 2. Sub-pixel aliasing.
    let low_pass = (2.0 * (n + s + e + w) + (nw + ne + sw + se)) / 12.0;
    let sub = smoothstep(0.0, 1.0, clamp(abs(low_pass - m) / range, 0.0, 1.0));
    let sub_offset = sub * sub * post.p0.z;

    // 3. A horizontal edge changes luma down the columns.
    let down = abs(nw + sw - 2.0 * w) + 2.0 * abs(n + s - 2.0 * m) + abs(ne + se - 2.0 * e);
    let across = abs(nw + ne - 2.0 * n) + 2.0 * abs(w + e - 2.0 * m) + abs(sw + se - 2.0 * s);
    let horizontal = down >= across;
    let l_neg = select(w, n, horizontal);
    let l_pos = select(e, s, horizontal);
    let g_neg = l_neg - m;
    let g_pos = l_pos - m;
    let to_neg = abs(g_neg) >= abs(g_pos);
    let side = select(1.0, -1.0, to_neg);
    let gradient = 0.25 * max(abs(g_neg), abs(g_pos));
    let local_average = 0.5 * (m + select(l_pos, l_neg, to_neg));
    let across_dir = select(vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0), horizontal);
    let along = select(vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0), horizontal);

    // 4. The search for both ends.
    let start = frag.xy + across_dir * (0.5 * side);
    var p1 = start - along * FXAA_STEP[0];
    var p2 = start + along * FXAA_STEP[0];
    var e1 = luma(bilinear(src, p1).rgb) - local_average;
    var e2 = luma(bilinear(src, p2).rgb) - local_average;
    var done1 = abs(e1) >= gradient;
    var done2 = abs(e2) >= gradient;
    let steps = u32(post.p0.w);
    for (var i = 1u; i < steps && !(done1 && done2); i += 1u) {
        if !done1 {
            p1 -= along * FXAA_STEP[i];
            e1 = luma(bilinear(src, p1).rgb) - local_average;
            done1 = abs(e1) >= gradient;
        }
        if !done2 {
            p2 += along * FXAA_STEP[i];
            e2 = luma(bilinear(src, p2).rgb) - local_average;
            done2 = abs(e2) >= gradient;
        }
    }

    // 5. Coverage from the nearer end, if the edge there bends towards this pixel.
    let d1 = dot(frag.xy - p1, along);
    let d2 = dot(p2 - frag.xy, along);
    let nearer_is_1 = d1 < d2;
    let end_delta = select(e2, e1, nearer_is_1);
    let bends_here = (end_delta < 0.0) != (m - local_average < 0.0);
    let edge_offset = select(0.0, 0.5 - min(d1, d2) / (d1 + d2), bends_here);
    let offset = max(edge_offset, sub_offset);
    return vec4<f32>(bilinear(src, frag.xy + across_dir * (side * offset)).rgb, centre.a);
}

@fragment
fn fs_fxaa(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let out = fxaa_pixel(frag);
    flush_taps(frag.y);
    return out;
}
