// shadow/pcss.wgsl — percentage-closer soft shadows (`pcss`).
//
// Technique: Fernando 2005, "Percentage-Closer Soft Shadows", SIGGRAPH 2005 Sketches
// (https://doi.org/10.1145/1187112.1187153), in three steps, with the search region and the
// uv scaling of Bavoil 2008, "Integrating Realistic Soft Shadows into Your Game Engine"
// (NVIDIA whitepaper, PCSS_Integration.pdf):
// 1. blocker search: `blocker_samples` Poisson taps over the region of the map where a blocker
//    can hide part of the light from the receiver — the cone from the receiver (view depth z_r)
//    to the light, cut at the search near plane z_n, the closest a blocker may be (shadow/maps.rs:
//    the nearest shape wholly in front of the light): width
//    w_light·(z_r − z_n)/z_r at depth z_n for a perspective map (a light of width w_light at
//    the eye, perpendicular to the axis), (z_r − z_n)·2tan(θ/2) for a sun of angular diameter θ
//    (orthographic map); the average view depth z_b of the texels nearer than the receiver.
//    None: the receiver is lit (V = 1).
// 2. penumbra width by similar triangles, parallel planar blocker and receiver:
//    w_p = (z_r − z_b)·w_light/z_b (perspective), (z_r − z_b)·2tan(θ/2) (orthographic).
// 3. PCF with `filter_samples` bilinear comparisons on the Poisson disk of diameter w_p at the
//    receiver (shadow/pcf.wgsl `pcf_poisson`).
// Both tap sets turn by the same per-pixel rotation under `rotate` (shadow/map_common.wgsl).
// `blocker_depth = ignore` skips step 1 and takes z_b = PCSS_IGNORED_BLOCKER_FRACTION·z_r —
// a deliberately broken PCSS (constant penumbra w_p = w_light, no contact hardening), kept as
// a test device for the study thresholds, not as a technique.
// Failure mode: the average blocker depth is wrong where blockers overlap at different depths
// (the penumbra of the nearer one is sized by the mean), the search misses blockers that fewer
// than one tap lands on (thin casters), the estimate assumes planar parallel blocker and
// receiver; the search misses blockers nearer the light than z_n (parts of shapes crossing the
// light's plane), and grows without bound as z_n → 0; fixed tap patterns band (rotated ones
// are noisy instead).
// Inputs: the light's map (ShadowLight: near plane, texel footprint, light-size term), the
// receiver's lookup, the map layer and side, the two tap counts, the blocker-depth mode, the
// taps' rotation.

// z_b/z_r when the blocker search is ignored: 1/2 gives w_p = w_light (chosen here: the light's
// own size, twice the soft-shadow scene's true penumbra, so the broken method is clearly off).
const PCSS_IGNORED_BLOCKER_FRACTION: f32 = 0.5;

// World width of the penumbra behind a blocker at view depth zb, seen from a receiver at zr.
fn pcss_penumbra_width(sl: ShadowLight, zr: f32, zb: f32) -> f32 {
    let w = max(zr - zb, 0.0) * sl.light_size;
    if shadow_is_perspective(sl) {
        return w / zb;
    }
    return w;
}

// Step 1: (average blocker view depth, blockers found).
fn pcss_blocker_search(sl: ShadowLight, r: ShadowReceiver, layer: u32, samples: u32, side: f32, rot: vec2<f32>) -> vec2<f32> {
    let zn = sl.search_near;
    var width = max(r.z - zn, 0.0) * sl.light_size;
    if shadow_is_perspective(sl) {
        width /= r.z;
    }
    // World width at depth zn → map coordinates: one texel is τ(zn) wide and 1/side of the map.
    let radius_uv = 0.5 * width / (side * shadow_texel_size(sl, zn));
    var sum = 0.0;
    var found = 0.0;
    for (var k = 0u; k < samples; k++) {
        count_iteration();
        let offset = poisson_tap(k, rot) * radius_uv;
        let d = shadow_depth_nearest(layer, r.uv + offset, side);
        if d < shadow_tap_depth(r, offset) {
            sum += shadow_linear_depth(sl, d);
            found += 1.0;
        }
    }
    return vec2<f32>(sum / max(found, 1.0), found);
}

fn pcss(sl: ShadowLight, r: ShadowReceiver, layer: u32, blocker_samples: u32, filter_samples: u32, side: f32, ignore_blockers: bool, rot: vec2<f32>) -> f32 {
    var zb = PCSS_IGNORED_BLOCKER_FRACTION * r.z;
    if !ignore_blockers {
        let search = pcss_blocker_search(sl, r, layer, blocker_samples, side, rot);
        if search.y == 0.0 {
            return 1.0;
        }
        zb = search.x;
    }
    let wp = pcss_penumbra_width(sl, r.z, zb);
    let radius_uv = 0.5 * wp / (side * shadow_texel_size(sl, r.z));
    return pcf_poisson(r, layer, filter_samples, radius_uv, rot);
}
