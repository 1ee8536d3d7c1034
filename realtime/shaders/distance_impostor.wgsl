// distance_impostor.wgsl — localized environment-map lookups: the reflected or refracted ray
// x + R·t finds the cube texel its hit lies in from the distances the radiance cube stores in
// alpha (realtime/src/distance_impostor.rs has the maths and the method table).
//
// Technique:
// - iteration (envmap.local.x = 1; Szirmay-Kalos, Aszódi, Lazányi & Premecz 2005,
//   "Approximate Ray-Tracing on the GPU with Distance Impostors", CGF 24(3)): assume the hit
//   lies on the sphere about the capture point through the last looked-up surface point;
//   intersect the ray with it, look up the distance along the new point's direction, repeat;
// - search (envmap.local.x = 2; Umenhoffer, Patow & Szirmay-Kalos, GPU Gems 3 ch. 17, §17.2):
//   a linear search for the first sign change of g = 1/|ray point| − 1/|stored surface|, then
//   secant steps on the bracket;
// - double refraction (envmap.local.w = 1; GPU Gems 3 §17.3): the refracted ray is traced to
//   its exit in the refractor's own distance map (outward normal, distance from its centre),
//   refracted out by Snell's law and exact Fresnel, then localized in the environment's map.
// Failure mode: whatever the capture point does not see is solid behind what it does see
// (hidden surfaces; reflections passing just past a depth discontinuity land on the nearer
// surface); bilinear filtering of the distances across a discontinuity invents surfaces in
// between; the iteration oscillates where the surface is far from a sphere about the capture
// point; the linear search misses crossings thinner than a step (thin objects); the refractor
// map keeps one layer (non-star-shaped refractors lose their inner surfaces) and internal
// reflections beyond total internal reflection are dropped.
// Inputs: group 3 (envmap.wgsl's cube, whose level 0 alpha is the distance; the refractor
// cube; `envmap.local`, `envmap.capture`, `envmap.refractor`).

// envmap.local.x values.
const LOCAL_DISTANT: u32 = 0u;
const LOCAL_ITERATIONS: u32 = 1u;
const LOCAL_SEARCH: u32 = 2u;
// Internal bounces followed through a refractor before giving up (total internal reflection).
const MAX_INTERNAL_BOUNCES: u32 = 4u;

// The stored distance along unit d: the environment's (from the capture point) or the
// refractor's (from its centre). One bilinear fetch.
fn stored_distance(in_refractor: bool, d: vec3<f32>) -> f32 {
    count_fetches(4u);
    if in_refractor {
        return textureSampleLevel(envmap_refractor, envmap_sampler, d, 0.0).w;
    }
    return textureSampleLevel(envmap_cube, envmap_sampler, d, 0.0).w;
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

// g(u) = 1/|p(u)| − 1/|l′(p̂(u))|: > 0 in front of the stored surface, < 0 behind it.
fn search_g(in_refractor: bool, q: vec4<f32>) -> f32 {
    return q.w - 1.0 / max(stored_distance(in_refractor, q.xyz), 1e-6);
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
            let t = ray_sphere_exit(x, r, stored_distance(in_refractor, hit.xyz));
            let p = x + r * t;
            let len = length(p);
            if len > 0.0 {
                hit = vec4<f32>(p / len, 1.0 / len);
            }
        }
        return hit;
    }
    // Search: linear, then secant, on g(u).
    let s = max(length(x), 1e-4);
    var u_front = 0.0;
    var g_front = search_g(in_refractor, search_point(x, r, s, 0.0));
    // The ray starting on the stored surface (a refractor's entry point) is in front of it.
    g_front = select(g_front, max(g_front, 0.0), in_refractor);
    var u_back = 1.0;
    var g_back = 0.0;
    var found = false;
    let n = envmap.local.y;
    for (var i = 1u; i <= n; i++) {
        count_iteration();
        let u = f32(i) / f32(n);
        let g = search_g(in_refractor, search_point(x, r, s, u));
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
    for (var j = 0u; j < envmap.local.z; j++) {
        count_iteration();
        let u = u_front + (u_back - u_front) * g_front / max(g_front - g_back, 1e-12);
        let g = search_g(in_refractor, search_point(x, r, s, u));
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

// Radiance arriving at world point p from unit direction d, from the environment's map:
// along d itself (distant), or along the localized hit's direction.
fn localized_radiance(p: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    if envmap.local.x == LOCAL_DISTANT {
        return envmap_radiance(d, 0.0);
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
