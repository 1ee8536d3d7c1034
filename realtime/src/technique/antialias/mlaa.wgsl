// Morphological anti-aliasing (Reshetov 2009, "Morphological Antialiasing", HPG), in the
// three-pass GPU form of Jimenez et al. 2011 ("Practical Morphological Antialiasing", GPU Pro
// 2), with the areas computed in the shader instead of read from a precomputed area texture:
//   1. fs_mlaa_edges: an edge between two pixels whose luma differs by more than `threshold`
//      (r: the pixel's left edge, g: its top edge);
//   2. fs_mlaa_weights: for each edge, its run is followed up to `max_search` pixels each way;
//      at each end a crossing edge on one side or the other (or none) classifies the run as an
//      L, Z or U pattern (Reshetov §2.2); the silhouette is rebuilt as the line through the
//      crossing edges' midpoints (a U as two lines meeting at the run's middle), and the area
//      between that line and the edge inside each pixel is the share of the other side's colour
//      it takes (Reshetov §2.3);
//   3. fs_mlaa_blend: each pixel mixes in its four neighbours by those shares.
// Fails where a pattern is not a straight silhouette (corners get rounded, text thickens), on
// runs longer than the search (treated as ending there), on features thinner than a pixel
// that the single sample missed, and below the threshold.
// post.p0 = (threshold, max_search, 0, 0).

fn mlaa_edges_pixel(frag: vec4<f32>) -> vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let l = luma(load_clamped(src, p).rgb);
    let t = post.p0.x;
    let left = p.x > 0 && abs(l - luma(load_clamped(src, p + vec2<i32>(-1, 0)).rgb)) > t;
    let top = p.y > 0 && abs(l - luma(load_clamped(src, p + vec2<i32>(0, -1)).rgb)) > t;
    return vec4<f32>(select(0.0, 1.0, left), select(0.0, 1.0, top), 0.0, 0.0);
}

// Edge flags (pass 1's output in `aux`), false outside the image.
fn left_edge(p: vec2<i32>) -> bool {
    return load_or_zero(aux, p).r > 0.5;
}

fn top_edge(p: vec2<i32>) -> bool {
    return load_or_zero(aux, p).g > 0.5;
}

// ∫ of a line's negative and positive parts over a width w, the line going from a to b:
// (area below the edge, area above it).
fn split_area(a: f32, b: f32, w: f32) -> vec2<f32> {
    if a * b >= 0.0 {
        let area = 0.5 * abs(a + b) * w;
        return select(vec2<f32>(0.0, area), vec2<f32>(area, 0.0), a + b < 0.0);
    }
    // The line crosses the edge at fraction f of the width.
    let f = a / (a - b);
    let first = 0.5 * abs(a) * f * w;
    let second = 0.5 * abs(b) * (1.0 - f) * w;
    return select(vec2<f32>(second, first), vec2<f32>(first, second), a < 0.0);
}

// The areas over [t0, t1] of the line from (0, h0) to (len, h1).
fn line_area(h0: f32, h1: f32, len: f32, t0: f32, t1: f32) -> vec2<f32> {
    if t1 <= t0 {
        return vec2<f32>(0.0);
    }
    let a = h0 + (h1 - h0) * t0 / len;
    let b = h0 + (h1 - h0) * t1 / len;
    return split_area(a, b, t1 - t0);
}

// (below, above): the areas between the rebuilt silhouette and the edge inside pixel i of a run
// of `len` pixels whose ends cross at heights 0.5·c0 and 0.5·c1 (c = −1 below, +1 above, 0
// no crossing).
fn pattern_area(c0: f32, c1: f32, len: f32, i: f32) -> vec2<f32> {
    let t0 = i;
    let t1 = i + 1.0;
    if c0 == 0.0 && c1 == 0.0 {
        return vec2<f32>(0.0);
    }
    if c0 * c1 > 0.0 {
        // U: two lines from the ends' crossings down to the edge at the run's middle.
        let mid = 0.5 * len;
        return line_area(0.5 * c0, 0.0, mid, t0, min(t1, mid))
            + line_area(0.0, 0.5 * c1, mid, max(t0, mid) - mid, t1 - mid);
    }
    // Z (opposite crossings) or L (one crossing): one line between the ends.
    return line_area(0.5 * c0, 0.5 * c1, len, t0, t1);
}

// Crossing of an end: −1 if only `below` crosses, +1 if only `above` does, 0 otherwise.
fn crossing(below: bool, above: bool, found: bool) -> f32 {
    if !found || below == above {
        return 0.0;
    }
    return select(1.0, -1.0, below);
}

// r: the share of the pixel above blended into this one; g: this pixel's share into the pixel
// above; b, a: the same with the pixel on the left.
fn mlaa_weights_pixel(frag: vec4<f32>) -> vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let max_search = i32(post.p0.y);
    var out = vec4<f32>(0.0);
    if top_edge(p) {
        // The run of top edges through p along the row.
        var l = 0;
        while l < max_search && top_edge(p - vec2<i32>(l + 1, 0)) {
            l += 1;
        }
        var r = 0;
        while r < max_search && top_edge(p + vec2<i32>(r + 1, 0)) {
            r += 1;
        }
        let x0 = p.x - l;
        let x1 = p.x + r + 1;
        // Crossing edges are left edges at the run's ends, in this row (below) or the one above.
        let c0 = crossing(left_edge(vec2<i32>(x0, p.y)), left_edge(vec2<i32>(x0, p.y - 1)), l < max_search);
        let c1 = crossing(left_edge(vec2<i32>(x1, p.y)), left_edge(vec2<i32>(x1, p.y - 1)), r < max_search);
        let a = pattern_area(c0, c1, f32(l + r + 1), f32(l));
        out = vec4<f32>(a.x, a.y, out.z, out.w);
    }
    if left_edge(p) {
        var u = 0;
        while u < max_search && left_edge(p - vec2<i32>(0, u + 1)) {
            u += 1;
        }
        var d = 0;
        while d < max_search && left_edge(p + vec2<i32>(0, d + 1)) {
            d += 1;
        }
        let y0 = p.y - u;
        let y1 = p.y + d + 1;
        // Crossing edges are top edges at the run's ends, in this column ("below" the edge's
        // line, on its positive side) or the one on the left.
        let c0 = crossing(top_edge(vec2<i32>(p.x, y0)), top_edge(vec2<i32>(p.x - 1, y0)), u < max_search);
        let c1 = crossing(top_edge(vec2<i32>(p.x, y1)), top_edge(vec2<i32>(p.x - 1, y1)), d < max_search);
        let a = pattern_area(c0, c1, f32(u + d + 1), f32(u));
        out = vec4<f32>(out.x, out.y, a.x, a.y);
    }
    return out;
}

fn mlaa_blend_pixel(frag: vec4<f32>) -> vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let own = load_or_zero(aux, p);
    // Shares of the four neighbours' colours in this pixel: from above and from the left by its
    // own edges, from below and from the right by theirs.
    let w = vec4<f32>(
        own.r,
        load_or_zero(aux, p + vec2<i32>(0, 1)).g,
        own.b,
        load_or_zero(aux, p + vec2<i32>(1, 0)).a,
    );
    let total = w.x + w.y + w.z + w.w;
    let centre = load_clamped(src, p);
    if total <= 0.0 {
        return centre;
    }
    let scale = select(1.0, 1.0 / total, total > 1.0);
    let mixed = w.x * load_clamped(src, p + vec2<i32>(0, -1)).rgb
        + w.y * load_clamped(src, p + vec2<i32>(0, 1)).rgb
        + w.z * load_clamped(src, p + vec2<i32>(-1, 0)).rgb
        + w.w * load_clamped(src, p + vec2<i32>(1, 0)).rgb;
    let kept = max(1.0 - total * scale, 0.0);
    return vec4<f32>(centre.rgb * kept + mixed * scale, centre.a);
}

@fragment
fn fs_mlaa_edges(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let out = mlaa_edges_pixel(frag);
    flush_taps(frag.y);
    return out;
}

@fragment
fn fs_mlaa_weights(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let out = mlaa_weights_pixel(frag);
    flush_taps(frag.y);
    return out;
}

@fragment
fn fs_mlaa_blend(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let out = mlaa_blend_pixel(frag);
    flush_taps(frag.y);
    return out;
}
