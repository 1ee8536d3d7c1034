// area/representative_point.wgsl — unshadowed area lights and sun disks by a representative
// point (`area_representative_point`), the cheap approximation to be measured.
//
// Technique: Karis 2013, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course "Physically
// Based Shading in Theory and Practice", §"Area Lights": light the specular lobe from the
// single point of the light closest to the reflection ray ("representative point", sphere
// lights, eqs. 10–11), and rescale the lobe's normalisation to keep its energy when the
// light's solid angle widens it: (α/α′)² with α′ = saturate(α + R/(2d)) (eq. 14; R the source
// radius, d its distance). Rectangles and disks follow the same recipe in the form of Drobot
// 2014, "Physically Based Area Lights" (GPU Pro 5, pp. 67–100), simplified: the reflection
// ray meets the light's plane and the hit is clamped into the shape; R = √(A/π) the radius of
// the disk of equal area.
// The diffuse lobe is lit from the light's centre: for a sphere entirely above the horizon
// this is exact (a uniform sphere's irradiance equals a point light's at its centre with
// E⊥ = π·L·sin²θmax); for rectangles and disks it is the point-light approximation with
// radiant intensity L·A·|cos θl| of the centre.
// All lobes share the energy E⊥ of the centre: Lo ≈ f_d(ωc)·|cos θc|·E⊥ + N·f_s(ωr)·|cos θr|·E⊥.
// Failure mode: large lights close to the receiver (the point-light diffuse term misses the
// horizon clipping and the 1/r² variation across the light), grazing reflection rays that
// miss the light's plane, spheres straddling the horizon, textured emission (only the centre's
// radiance is used), and the camera inside a sphere light (nothing is lit from inside).
// Inputs: the emitter, the resolved BSDF, the shading normal n, ωo, the point p.

// (α/α′)² with α′ = saturate(α + R/(2d)) (Karis 2013, eq. 14); 1 without a specular lobe.
fn widened_normalization(alpha: f32, source_radius: f32, dist: f32) -> f32 {
    if alpha <= 0.0 {
        return 1.0;
    }
    let widened = clamp(alpha + source_radius / (2.0 * dist), 0.0, 1.0);
    let ratio = alpha / widened;
    return ratio * ratio;
}

// Mirror direction of ωo about n on ωo's side.
fn reflection_direction(n: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let nn = select(n, -n, dot(n, wo) < 0.0);
    return nn * (2.0 * dot(nn, wo)) - wo;
}

// Direction towards the point of a sphere (centre at offset `l`, radius `radius`) closest to
// the ray along unit r (Karis 2013, eq. 11): l + ctr·saturate(R/|ctr|), ctr = (l·r)r − l.
fn closest_on_sphere(l: vec3<f32>, radius: f32, r: vec3<f32>) -> vec3<f32> {
    let ctr = r * dot(l, r) - l;
    let c2 = dot(ctr, ctr);
    var q = l;
    if c2 > 0.0 {
        q = l + ctr * clamp(radius * inverseSqrt(c2), 0.0, 1.0);
    }
    return normalize(q);
}

fn sphere_representative(s: Shape, b: Bsdf, n: vec3<f32>, wo: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    let l = s.center.xyz - p;
    let d2 = dot(l, l);
    let radius = s.center.w;
    if !(d2 > radius * radius) {
        return vec3<f32>(0.0);
    }
    let d = sqrt(d2);
    let wc = l / d;
    let e = emitted_radiance(s, sphere_uv(-wc)) * (PI * radius * radius / d2);
    let diffuse = bsdf_eval_split(b, n, wo, wc).diffuse;
    let ws = closest_on_sphere(l, radius, reflection_direction(n, wo));
    let specular = bsdf_eval_split(b, n, wo, ws).specular * widened_normalization(specular_alpha(b), radius, d);
    return (diffuse + specular) * e;
}

// Rectangle or disk: diffuse from the centre as a point light of intensity L·A·|cos θl|,
// specular from the reflection ray's hit on the plane clamped into the shape.
fn planar_representative(s: Shape, b: Bsdf, n: vec3<f32>, wo: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    let nl = s.normal.xyz;
    let c = s.center.xyz;
    let side = dot(p - c, nl);
    if side == 0.0 || (s.emission_info.y == 0u && side < 0.0) {
        return vec3<f32>(0.0);
    }
    let l = c - p;
    let d2 = dot(l, l);
    let d = sqrt(d2);
    let wc = l / d;
    let area = s.normal.w;
    let uv_centre = select(vec2<f32>(0.5), vec2<f32>(0.0), s.kind == SHAPE_DISK);
    let e = emitted_radiance(s, uv_centre) * (area * abs(dot(nl, wc)) / d2);
    let diffuse = bsdf_eval_split(b, n, wo, wc).diffuse;
    // The reflection ray's hit on the plane, or (ray leaving the plane) the point d along it
    // projected onto the plane; then clamped into the shape.
    let r = reflection_direction(n, wo);
    let t = dot(l, nl) / dot(r, nl);
    var q = p + r * d;
    if t > 0.0 && t < 1e30 {
        q = p + r * t;
    }
    var st = plane_local(s, q);
    if s.kind == SHAPE_DISK {
        let len = length(st);
        if len > 1.0 {
            st /= len;
        }
    } else {
        st = clamp(st, vec2<f32>(-1.0), vec2<f32>(1.0));
    }
    let qs = c + s.half_u.xyz * st.x + s.half_v.xyz * st.y;
    let ws = normalize(qs - p);
    let norm = widened_normalization(specular_alpha(b), sqrt(area * INV_PI), d);
    let specular = bsdf_eval_split(b, n, wo, ws).specular * norm;
    return (diffuse + specular) * e;
}

fn area_light_representative(s: Shape, b: Bsdf, n: vec3<f32>, wo: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    if s.kind == SHAPE_SPHERE {
        return sphere_representative(s, b, n, wo, p);
    }
    return planar_representative(s, b, n, wo, p);
}

// A sun disk as a sphere at infinity: R/d = sin θmax, E⊥ = E.
fn sun_representative(l: Light, b: Bsdf, n: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let wl = l.direction.xyz;
    let sin_max = sqrt(l.params.y);
    let diffuse = bsdf_eval_split(b, n, wo, wl).diffuse;
    let ws = closest_on_sphere(wl, sin_max, reflection_direction(n, wo));
    let specular = bsdf_eval_split(b, n, wo, ws).specular * widened_normalization(specular_alpha(b), sin_max, 1.0);
    return (diffuse + specular) * l.intensity.xyz;
}
