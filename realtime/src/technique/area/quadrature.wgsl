// area/quadrature.wgsl — unshadowed area, sun-disk and environment light by N×N stratified
// midpoint quadrature (`area_quadrature`).
//
// Technique: the product midpoint rule on each emitter's own parametrisation — one sample at
// the centre of each of the N×N strata of the unit square, each weighted by the stratum's
// measure — so the estimate is deterministic (no noise) and converges to the exact unshadowed
// integral Lo = ∫ f(ωo, ωi)·|cos θi|·Le dωi as N grows, with error O(N⁻²) for smooth integrands
// (midpoint rule: e.g. Davis & Rabinowitz, "Methods of Numerical Integration", 2nd ed. 1984,
// §2.2 and §5.6 on product rules). Parametrisations:
// - rectangle (parallelogram c + s·h_u + t·h_v): uniform in (s, t), area measure,
//   dω = |cos θl|·dA/r², dA = A/N²;
// - disk: uniform in area via r = √u, φ = 2πv, dA = A/N²;
// - sphere seen from outside: the cone it subtends, uniform in solid angle (1 − cos θ = u·h,
//   h = 1 − cos θmax, φ = 2πv), dω = 2πh/N² (the oracle's sampling, pbrt-v4 §6.2.4); from
//   inside (two-sided only) uniform in area over the sphere;
// - sun disk: the same cone about the light's direction;
// - emissive mesh triangle p0 + b1·e1 + b2·e2: uniform in area by b1 = √u·(1 − v),
//   b2 = √u·v (the square-to-triangle warp of Shirley 1992, "Nonuniform Random Point Sets via
//   Warping", Graphics Gems III; any area-uniform map serves the midpoint rule), dA = A/N²,
//   front side only unless two-sided, as the oracle's MeshLight;
// - environment: cosine-weighted directions about the normal (Malley's method),
//   weight π/(N²·cos θi).
// Failure mode: points close to a light compared with a stratum (r ≲ light size / N) see the
// 1/r² peak undersampled (area parametrisation); the cosine-weighted environment converges
// slowly for sharp lobes (low roughness) and small bright sources; a one-sided light is cut
// only by its plane, so a receiver straddling it is shaded per point, as the oracle does.
// Inputs: the emitter (`Shape`, `Light`) or the environment, the resolved BSDF, the shading
// normal n (turned to the geometric normal's side), ωo, the point p, N.

// Emitted radiance of shape `s` at texture coordinate uv (constant or factor × texture), at
// one point of the emitter (a light sample: no pixel footprint).
fn emitted_radiance(s: Shape, uv: vec2<f32>) -> vec3<f32> {
    return eval_tex_rgb_point(s.emission_info.z, s.emission.xyz, uv);
}

// Mitsuba's sphere uv of the unit outward normal `d` (SphereLight::uv).
fn sphere_uv(d: vec3<f32>) -> vec2<f32> {
    var u = atan2(d.y, d.x) / TAU;
    if u < 0.0 {
        u += 1.0;
    }
    return vec2<f32>(u, acos(clamp(d.z, -1.0, 1.0)) / PI);
}

// Midpoint of stratum (a, c) of the N×N grid of the unit square.
fn stratum_midpoint(a: u32, c: u32, inv_n: f32) -> vec2<f32> {
    return vec2<f32>((f32(a) + 0.5) * inv_n, (f32(c) + 0.5) * inv_n);
}

// Rectangle or disk light, area measure. Nothing from the plane itself, nor from behind a
// one-sided light (RectangleLight/DiskLight::sample_li).
fn planar_quadrature(s: Shape, b: Bsdf, n: vec3<f32>, wo: vec3<f32>, p: vec3<f32>, nq: u32) -> vec3<f32> {
    let nl = s.normal.xyz;
    let side = dot(p - s.center.xyz, nl);
    if side == 0.0 || (s.emission_info.y == 0u && side < 0.0) {
        return vec3<f32>(0.0);
    }
    let inv_n = 1.0 / f32(nq);
    var sum = vec3<f32>(0.0);
    for (var a = 0u; a < nq; a++) {
        for (var c = 0u; c < nq; c++) {
            count_iteration();
            let m = stratum_midpoint(a, c, inv_n);
            var local: vec2<f32>;
            var uv: vec2<f32>;
            if s.kind == SHAPE_DISK {
                let r = sqrt(m.x);
                let phi = TAU * m.y;
                local = vec2<f32>(r * cos(phi), r * sin(phi));
                uv = vec2<f32>(r, m.y);
            } else {
                local = m * 2.0 - 1.0;
                uv = m;
            }
            let q = s.center.xyz + s.half_u.xyz * local.x + s.half_v.xyz * local.y;
            let d = q - p;
            let r2 = dot(d, d);
            let wi = d * inverseSqrt(r2);
            let f = bsdf_eval(b, n, wo, wi);
            sum += f * emitted_radiance(s, uv) * (abs(dot(nl, wi)) / r2);
        }
    }
    return sum * (s.normal.w * inv_n * inv_n);
}

// Uniform-cone quadrature about unit `axis` with h = 1 − cos θmax; `le_const` is the radiance
// unless `sphere` is given with a radiance texture (then looked up at the point the cone
// direction hits, as SphereLight::sample_li maps it).
fn cone_quadrature(
    axis: vec3<f32>,
    h: f32,
    sin2_max: f32,
    s: Shape,
    textured_sphere: bool,
    le_const: vec3<f32>,
    b: Bsdf,
    n: vec3<f32>,
    wo: vec3<f32>,
    nq: u32,
) -> vec3<f32> {
    let inv_n = 1.0 / f32(nq);
    let sin_max = sqrt(sin2_max);
    var sum = vec3<f32>(0.0);
    for (var a = 0u; a < nq; a++) {
        for (var c = 0u; c < nq; c++) {
            count_iteration();
            let m = stratum_midpoint(a, c, inv_n);
            let one_minus_cos = m.x * h;
            let cos_t = 1.0 - one_minus_cos;
            let sin2_t = one_minus_cos * (2.0 - one_minus_cos);
            let phi = TAU * m.y;
            let sin_t = sqrt(sin2_t);
            let wi = to_world(axis, vec3<f32>(sin_t * cos(phi), sin_t * sin(phi), cos_t));
            var le = le_const;
            if textured_sphere {
                // Angle at the centre between −axis and the hit point's normal.
                let cos_a = sin2_t / sin_max + cos_t * sqrt(max(1.0 - sin2_t / sin2_max, 0.0));
                let sin_a = sqrt(max(1.0 - cos_a * cos_a, 0.0));
                let nrm = -to_world(axis, vec3<f32>(sin_a * cos(phi), sin_a * sin(phi), cos_a));
                le = emitted_radiance(s, sphere_uv(nrm));
            }
            sum += bsdf_eval(b, n, wo, wi) * le;
        }
    }
    return sum * (TAU * h * inv_n * inv_n);
}

// Sphere light: the subtended cone from outside; from inside, uniform area quadrature over
// the sphere for a two-sided light, nothing for a one-sided one (SphereLight::sample_li).
fn sphere_quadrature(s: Shape, b: Bsdf, n: vec3<f32>, wo: vec3<f32>, p: vec3<f32>, nq: u32) -> vec3<f32> {
    let c = s.center.xyz;
    let r = s.center.w;
    let to_c = c - p;
    let dc2 = dot(to_c, to_c);
    let r2 = r * r;
    if dc2 > r2 {
        let sin2_max = r2 / dc2;
        let cos_max = sqrt(max(1.0 - sin2_max, 0.0));
        let h = sin2_max / (1.0 + cos_max);
        let textured = s.emission_info.z != NONE;
        return cone_quadrature(to_c * inverseSqrt(dc2), h, sin2_max, s, textured, s.emission.xyz, b, n, wo, nq);
    }
    if s.emission_info.y == 0u {
        return vec3<f32>(0.0);
    }
    let inv_n = 1.0 / f32(nq);
    var sum = vec3<f32>(0.0);
    for (var a = 0u; a < nq; a++) {
        for (var k = 0u; k < nq; k++) {
            count_iteration();
            let m = stratum_midpoint(a, k, inv_n);
            let z = 1.0 - 2.0 * m.x;
            let rho = sqrt(max(1.0 - z * z, 0.0));
            let phi = TAU * m.y;
            let nrm = vec3<f32>(rho * cos(phi), rho * sin(phi), z);
            let d = c + nrm * r - p;
            let d2 = dot(d, d);
            if d2 > 0.0 {
                let wi = d * inverseSqrt(d2);
                sum += bsdf_eval(b, n, wo, wi) * emitted_radiance(s, sphere_uv(nrm)) * (abs(dot(nrm, wi)) / d2);
            }
        }
    }
    return sum * (s.normal.w * inv_n * inv_n);
}

// Every emissive mesh triangle (upload.rs `add_emissive_triangles`: six texels a triangle in
// the table `f.mesh_lights.x` names) by N×N midpoint quadrature in area measure (N =
// `mesh_n`), unshadowed; nothing while `mesh_n` = 0.
fn emissive_mesh_quadrature(f: FrameUniforms, b: Bsdf, n: vec3<f32>, wo: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    if f.mesh_lights.x == NONE {
        return vec3<f32>(0.0);
    }
    let table = texture_infos[f.mesh_lights.x];
    let nq = f.mesh_lights.y;
    let inv_n = 1.0 / f32(nq);
    var total = vec3<f32>(0.0);
    for (var t = 0u; t < table.height; t++) {
        let base = table.offset + 6u * t;
        let r0 = texels[base];
        let e1 = texels[base + 1u];
        let e2 = texels[base + 2u];
        let nl = texels[base + 3u].xyz;
        let uv01 = texels[base + 4u];
        let uv2 = texels[base + 5u].xy;
        let two_sided = e2.w > 0.5;
        // Nothing from the triangle's plane, nor from behind a one-sided triangle.
        let side = dot(p - r0.xyz, nl);
        if side == 0.0 || (!two_sided && side < 0.0) {
            continue;
        }
        let s = shapes[bitcast<u32>(r0.w)];
        var sum = vec3<f32>(0.0);
        for (var a = 0u; a < nq; a++) {
            for (var c = 0u; c < nq; c++) {
                count_iteration();
                let m = stratum_midpoint(a, c, inv_n);
                let su = sqrt(m.x);
                let b1 = su * (1.0 - m.y);
                let b2 = su * m.y;
                let q = r0.xyz + e1.xyz * b1 + e2.xyz * b2;
                let d = q - p;
                let r2 = dot(d, d);
                if r2 > 0.0 {
                    let wi = d * inverseSqrt(r2);
                    let uv = uv01.xy * (1.0 - b1 - b2) + uv01.zw * b1 + uv2 * b2;
                    sum += bsdf_eval(b, n, wo, wi) * emitted_radiance(s, uv) * (abs(dot(nl, wi)) / r2);
                }
            }
        }
        total += sum * (e1.w * inv_n * inv_n);
    }
    return total;
}

// One emissive shape by quadrature.
fn area_light_quadrature(s: Shape, b: Bsdf, n: vec3<f32>, wo: vec3<f32>, p: vec3<f32>, nq: u32) -> vec3<f32> {
    if s.kind == SHAPE_SPHERE {
        return sphere_quadrature(s, b, n, wo, p, nq);
    }
    return planar_quadrature(s, b, n, wo, p, nq);
}

// A sun disk by cone quadrature.
fn sun_quadrature(l: Light, b: Bsdf, n: vec3<f32>, wo: vec3<f32>, nq: u32) -> vec3<f32> {
    let unused = Shape(0u, 0u, NONE, 0.0, vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0),
        vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<u32>(0u), vec4<u32>(NONE), vec4<f32>(0.0),
        vec4<u32>(NONE, 0u, 0u, 0u));
    return cone_quadrature(l.direction.xyz, l.params.x, l.params.y, unused, false, sun_radiance(l), b, n, wo, nq);
}

// The environment by cosine-weighted quadrature about the normal on ωo's side.
fn environment_quadrature(f: FrameUniforms, b: Bsdf, n: vec3<f32>, wo: vec3<f32>, nq: u32) -> vec3<f32> {
    let nn = select(n, -n, dot(n, wo) < 0.0);
    let inv_n = 1.0 / f32(nq);
    var sum = vec3<f32>(0.0);
    for (var a = 0u; a < nq; a++) {
        for (var c = 0u; c < nq; c++) {
            count_iteration();
            let m = stratum_midpoint(a, c, inv_n);
            let r = sqrt(m.x);
            let phi = TAU * m.y;
            let cos_t = sqrt(1.0 - m.x);
            let wi = to_world(nn, vec3<f32>(r * cos(phi), r * sin(phi), cos_t));
            sum += bsdf_eval(b, n, wo, wi) * environment_radiance(f, wi) / cos_t;
        }
    }
    return sum * (PI * inv_n * inv_n);
}
