// lights_punctual.wgsl — point, spot and delta directional lights, unshadowed.
//
// Technique: exact evaluation of delta lights (no approximation: with visibility ignored the
// reflected radiance is f(ωo, ωi)·|cos θi|·li, one term per light):
// - point: li = I/r² along ωi = (x − p)/r (inverse-square law; pbrt-v4 §12.2 PointLight);
// - spot: li = I·s(θ)/r² with Mitsuba 3's linear falloff s(θ) = 1 for θ ≤ θb,
//   (θc − θ)/(θc − θb) for θb < θ < θc, 0 beyond (Mitsuba 3 docs, "Spot light source (spot)");
// - directional: li = E along ωi = −direction (pbrt-v4 §12.3 DistantLight).
// Units as oracle/src/light/{point,spot,directional}.rs: I in W/sr, E in W/m².
// Failure mode: none — but no shadows: this is the unshadowed ground truth's counterpart.
// Inputs: one `Light` and the shading point.

// Incident light from one direction: li is intensity/r² or irradiance (zero: nothing arrives).
struct Incident {
    wi: vec3<f32>,
    li: vec3<f32>,
}

// Mitsuba's spot falloff for the unit direction `d` leaving the light (SpotLight::falloff).
fn spot_falloff(l: Light, d: vec3<f32>) -> f32 {
    let cos_t = dot(l.direction.xyz, d);
    let cos_cutoff = l.params.x;
    let cos_beam = l.params.y;
    let cutoff = l.params.z;
    let beam = l.params.w;
    if cos_t >= cos_beam || (cos_t > cos_cutoff && cutoff <= beam) {
        return 1.0;
    }
    if cos_t > cos_cutoff {
        return clamp((cutoff - acos(cos_t)) / (cutoff - beam), 0.0, 1.0);
    }
    return 0.0;
}

// The one direction from p towards a delta light and what arrives along it.
fn punctual_incident(l: Light, p: vec3<f32>) -> Incident {
    var inc = Incident(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0));
    if l.kind == LIGHT_DIRECTIONAL {
        inc.wi = l.direction.xyz;
        inc.li = l.intensity.xyz;
        return inc;
    }
    let d = l.position.xyz - p;
    let r2 = dot(d, d);
    if !(r2 > 0.0 && r2 < 1e30) {
        return inc;
    }
    inc.wi = d * inverseSqrt(r2);
    var li = l.intensity.xyz / r2;
    if l.kind == LIGHT_SPOT {
        li *= spot_falloff(l, -inc.wi);
    }
    inc.li = li;
    return inc;
}

// A directional light with an angular size (the sun disk): cone half-angle θmax about
// `direction`, params.x = 1 − cos θmax, params.y = sin²θmax, radiance L = E/(π sin²θmax).
fn is_sun_disk(l: Light) -> bool {
    return l.kind == LIGHT_DIRECTIONAL && l.params.x > 0.0;
}

fn sun_radiance(l: Light) -> vec3<f32> {
    return l.intensity.xyz / (PI * l.params.y);
}

// Radiance of a sun disk seen along unit `w` (DirectionalLight::radiance_from_direction:
// cos > 0 and |to_light × w|² ≤ sin²θmax).
fn sun_radiance_along(l: Light, w: vec3<f32>) -> vec3<f32> {
    let c = cross(l.direction.xyz, w);
    if is_sun_disk(l) && dot(w, l.direction.xyz) > 0.0 && dot(c, c) <= l.params.y {
        return sun_radiance(l);
    }
    return vec3<f32>(0.0);
}
