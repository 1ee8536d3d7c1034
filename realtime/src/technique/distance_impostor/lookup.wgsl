// distance_impostor/lookup.wgsl — localized environment-map lookups: the reflected or refracted ray
// x + R·t finds the cube texel its hit lies in from the distances the radiance cube stores in
// alpha (realtime/src/technique/distance_impostor.rs has the maths and the method table).
//
// Technique:
// - iteration (envmap.local.x = 1; Szirmay-Kalos, Aszódi, Lazányi & Premecz 2005,
//   "Approximate Ray-Tracing on the GPU with Distance Impostors", CGF 24(3)): assume the hit
//   lies on the sphere about the capture point through the last looked-up surface point;
//   intersect the ray with it, look up the distance along the new point's direction, repeat;
// - search (envmap.local.x = 2; Umenhoffer, Patow & Szirmay-Kalos, GPU Gems 3 ch. 17, §17.2):
//   a linear search for the first sign change of g = 1/|ray point| − 1/|stored surface|, then
//   secant steps on the bracket;
// - layered search (envmap.layers.x > 1; GPU Gems 3 §17.2's layered distance maps): the
//   further surfaces along each direction, depth-peeled at capture (passes.wgsl
//   `peel_distance`), so the search tells free space behind a near surface from solid;
// - double refraction (envmap.local.w = 1; GPU Gems 3 §17.3): the refracted ray is traced to
//   its exit in the refractor's own distance map (outward normal, distance from its centre),
//   refracted out by Snell's law and exact Fresnel, then localized in the environment's map.
// Failure mode: whatever the capture point does not see is solid behind what it does see
// (hidden surfaces; reflections passing just past a depth discontinuity land on the nearer
// surface); bilinear filtering of the distances across a discontinuity invents surfaces in
// between; the iteration oscillates where the surface is far from a sphere about the capture
// point; the linear search misses crossings thinner than a step (thin objects), and a layered
// one whose map has too few layers treats what is behind its deepest layer as solid; the refractor
// map keeps one layer (non-star-shaped refractors lose their inner surfaces) and internal
// reflections beyond total internal reflection are dropped.
// Inputs: group 3 (envmap/envmap.wgsl's cube, whose level 0 alpha is the distance; the further
// layers; the refractor cube; `envmap.local`, `envmap.capture`, `envmap.refractor`,
// `envmap.layers`).

// envmap.local.x values.
const LOCAL_DISTANT: u32 = 0u;
const LOCAL_ITERATIONS: u32 = 1u;
const LOCAL_SEARCH: u32 = 2u;
// Capture only: the forward pass peels away what the previous layer holds (passes.wgsl).
const LOCAL_PEEL: u32 = 3u;
// Stored distances from here up mean "no surface" (the capture's background, 65504).
const NO_SURFACE: f32 = 32768.0;
// Internal bounces followed through a refractor before giving up (total internal reflection).
const MAX_INTERNAL_BOUNCES: u32 = 4u;

// The distance map a lookup reads: layer k of the environment's (0: envmap_cube's level 0,
// from the capture point), or REFRACTOR_MAP, the refractor's (from its centre).
const REFRACTOR_MAP: u32 = 0xffffffffu;

fn map_of(in_refractor: bool) -> u32 {
    return select(0u, REFRACTOR_MAP, in_refractor);
}

// The stored distance along unit d in distance map `map`. One bilinear fetch.
fn stored_distance(map: u32, d: vec3<f32>) -> f32 {
    if map == REFRACTOR_MAP {
        count_fetches(4u);
        return textureSampleLevel(envmap_refractor, envmap_sampler, d, 0.0).w;
    }
    return layer_sample(map, d).w;
}

// Layer k of the environment's layered map along unit d: (radiance, distance). One bilinear
// fetch.
fn layer_sample(k: u32, d: vec3<f32>) -> vec4<f32> {
    count_fetches(4u);
    if k == 0u {
        return textureSampleLevel(envmap_cube, envmap_sampler, d, 0.0);
    }
    return textureSampleLevel(envmap_layers, envmap_sampler, d, i32(k - 1u), 0.0);
}

// The largest root t of |x + r·t| = radius (unit r): the ray leaving a sphere it starts in.
// Outside it, the point of the ray nearest the sphere.
fn ray_sphere_exit(x: vec3<f32>, r: vec3<f32>, radius: f32) -> f32 {
    let b = dot(x, r);
    return max(-b + sqrt(max(b * b - dot(x, x) + radius * radius, 0.0)), 0.0);
}

// Point u ∈ [0, 1] of the search's parameterization t(u) = s·u/(1 − u): (unit direction from
// the map's origin, distance; 0 at u = 1, the point at infinity along r).
fn search_point(x: vec3<f32>, r: vec3<f32>, s: f32, u: f32) -> vec4<f32> {
    if u >= 1.0 {
        return vec4<f32>(r, 0.0);
    }
    let p = x + r * (s * u / (1.0 - u));
    let len = length(p);
    if len <= 0.0 {
        return vec4<f32>(r, 0.0);
    }
    return vec4<f32>(p / len, 1.0 / len);
}

// g(u) = 1/|p(u)| − 1/|l′(p̂(u))| of distance map `map` at ray point q = p(u): > 0 in front of
// its stored surface, < 0 behind it.
fn search_g(map: u32, q: vec4<f32>) -> f32 {
    return q.w - 1.0 / max(stored_distance(map, q.xyz), 1e-6);
}

// The secant refinement of a bracket of map `map`'s surface, g(u_front) > 0 ≥ g(u_back):
// envmap.local.z steps, each replacing one end by the root of the line through both, and the
// final root (GPU Gems 3 §17.2).
fn secant_point(map: u32, x: vec3<f32>, r: vec3<f32>, s: f32, front: vec2<f32>, back: vec2<f32>) -> vec4<f32> {
    var u_front = front.x;
    var g_front = front.y;
    var u_back = back.x;
    var g_back = back.y;
    for (var j = 0u; j < envmap.local.z; j++) {
        count_iteration();
        let u = u_front + (u_back - u_front) * g_front / max(g_front - g_back, 1e-12);
        let g = search_g(map, search_point(x, r, s, u));
        if g > 0.0 {
            u_front = u;
            g_front = g;
        } else {
            u_back = u;
            g_back = g;
        }
    }
    let u = u_front + (u_back - u_front) * g_front / max(g_front - g_back, 1e-12);
    return search_point(x, r, s, u);
}

// Where ray x + r·t (x relative to the map's origin, unit r) meets the stored surface:
// (unit direction from the origin, distance; 0: at infinity).
fn localized_hit(in_refractor: bool, x: vec3<f32>, r: vec3<f32>) -> vec4<f32> {
    if envmap.local.x == LOCAL_ITERATIONS {
        var hit = vec4<f32>(r, 0.0);
        // Inside a refractor the plain lookup has no exit point: one iteration at least.
        let iterations = select(envmap.local.y, max(envmap.local.y, 1u), in_refractor);
        for (var k = 0u; k < iterations; k++) {
            count_iteration();
            let t = ray_sphere_exit(x, r, stored_distance(map_of(in_refractor), hit.xyz));
            let p = x + r * t;
            let len = length(p);
            if len > 0.0 {
                hit = vec4<f32>(p / len, 1.0 / len);
            }
        }
        return hit;
    }
    // Search: linear, then secant, on g(u).
    let map = map_of(in_refractor);
    let s = max(length(x), 1e-4);
    var u_front = 0.0;
    var g_front = search_g(map, search_point(x, r, s, 0.0));
    // The ray starting on the stored surface (a refractor's entry point) is in front of it.
    g_front = select(g_front, max(g_front, 0.0), in_refractor);
    var u_back = 1.0;
    var g_back = 0.0;
    var found = false;
    let n = envmap.local.y;
    for (var i = 1u; i <= n; i++) {
        count_iteration();
        let u = f32(i) / f32(n);
        let g = search_g(map, search_point(x, r, s, u));
        if g <= 0.0 {
            u_back = u;
            g_back = g;
            found = true;
            break;
        }
        u_front = u;
        g_front = g;
    }
    if !found {
        return vec4<f32>(r, 0.0);
    }
    return secant_point(map, x, r, s, vec2<f32>(u_front, g_front), vec2<f32>(u_back, g_back));
}

// How many stored layers lie between the capture point and ray point q (direction,
// 1/distance). The layers along a direction are its surfaces in depth order; closed surfaces
// alternate entry and exit, so q is inside something after an odd number of them.
fn layers_passed(q: vec4<f32>) -> u32 {
    var c = 0u;
    for (var k = 0u; k < envmap.layers.x; k++) {
        let d = layer_sample(k, q.xyz).w;
        if d < NO_SURFACE && q.w < 1.0 / d {
            c++;
        }
    }
    return c;
}

// Whether a ray point past `c` layers is inside something: an odd count, or every layer
// passed (what the map could not keep behind its deepest layer is solid, as in one layer).
fn is_solid(c: u32) -> bool {
    return (c & 1u) == 1u || c == envmap.layers.x;
}

// A hit in the layered map: (unit direction from the capture point, 1/distance; 0: at
// infinity) and the layer whose surface it is.
struct LayeredHit {
    q: vec4<f32>,
    layer: u32,
}

// The layered search (our reading of GPU Gems 3 §17.2's layered distance maps, which
// searches every layer; the chapter's text was not available to this project): march as the
// one-layer search does, but stop at the first sample inside something by the parity of the
// layers passed (`is_solid`); the surface entered is layer c, c the count at the last free
// sample; the secant steps then refine on that layer alone, g = 1/|p| − 1/|l′_c|. A ray that
// never enters anything leaves past every stored surface: layer c there holds the background
// (or the nearest surface the map dropped, when every layer is in use).
fn layered_hit(x: vec3<f32>, r: vec3<f32>) -> LayeredHit {
    let s = max(length(x), 1e-4);
    let layers = envmap.layers.x;
    // The ray starts in free space, on the reflector the capture left out.
    var c_front = min(layers_passed(search_point(x, r, s, 0.0)) & ~1u, layers - 1u);
    var u_front = 0.0;
    var u_back = 1.0;
    var found = false;
    let n = envmap.local.y;
    for (var i = 1u; i <= n; i++) {
        count_iteration();
        let u = f32(i) / f32(n);
        let c = layers_passed(search_point(x, r, s, u));
        if is_solid(c) {
            u_back = u;
            found = true;
            break;
        }
        u_front = u;
        c_front = c;
    }
    if !found {
        return LayeredHit(vec4<f32>(r, 0.0), c_front);
    }
    let k = c_front;
    let g_front = search_g(k, search_point(x, r, s, u_front));
    let g_back = search_g(k, search_point(x, r, s, u_back));
    // Secant only on a true bracket of layer k (a crossing that parity found but that layer's
    // distances do not show keeps the linear search's point).
    if g_front > 0.0 && g_back <= 0.0 {
        let q = secant_point(k, x, r, s, vec2<f32>(u_front, g_front), vec2<f32>(u_back, g_back));
        return LayeredHit(q, k);
    }
    return LayeredHit(search_point(x, r, s, u_back), k);
}

// Radiance arriving at world point p from unit direction d, from the environment's map:
// along d itself (distant), or along the localized hit's direction (in the hit's layer).
fn localized_radiance(p: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    if envmap.local.x == LOCAL_DISTANT {
        return envmap_radiance(d, 0.0);
    }
    if envmap.local.x == LOCAL_SEARCH && envmap.layers.x > 1u {
        let hit = layered_hit(p - envmap.capture.xyz, d);
        if hit.layer == 0u {
            return envmap_radiance(hit.q.xyz, 0.0);
        }
        return layer_sample(hit.layer, hit.q.xyz).rgb;
    }
    let hit = localized_hit(false, p - envmap.capture.xyz, d);
    return envmap_radiance(hit.xyz, 0.0);
}

// Radiance carried by a ray refracted into the refractor at world point p along unit t,
// traced to its exit through the refractor's map and out (relative index η inside/outside),
// times the exit's Fresnel transmittance.
fn double_refracted_radiance(p: vec3<f32>, t: vec3<f32>, eta: f32) -> vec3<f32> {
    let centre = envmap.refractor.xyz;
    var x = p - centre;
    var d = t;
    for (var bounce = 0u; bounce < MAX_INTERNAL_BOUNCES; bounce++) {
        let hit = localized_hit(true, x, d);
        if hit.w <= 0.0 {
            return vec3<f32>(0.0);
        }
        let exit = hit.xyz / hit.w;
        count_fetches(4u);
        var n = normalize(textureSampleLevel(envmap_refractor, envmap_sampler, hit.xyz, 0.0).xyz);
        n = select(n, -n, dot(n, hit.xyz) < 0.0);
        let cos_i = clamp(dot(n, d), 0.0, 1.0);
        let fr = fresnel_dielectric(cos_i, 1.0 / eta);
        if fr.x < 1.0 {
            // Snell's law leaving the refractor: relative index 1/η, normal n on the far side.
            let out = d * eta + n * (fr.y - eta * cos_i);
            return (1.0 - fr.x) * localized_radiance(centre + exit, normalize(out));
        }
        // Total internal reflection: follow the reflected ray inside.
        x = exit;
        d = d - n * (2.0 * dot(n, d));
    }
    return vec3<f32>(0.0);
}
