// environment.wgsl — radiance from the distant environment, and the environment reflection
// the Dirac-delta materials (mirror, dielectric) get in place of their specular chains.
//
// Technique: L(ω) = constant, or scale × the equirectangular lookup of `texture.wgsl`
// (Mitsuba 3 `envmap` orientation and texel placement, docs/ARCHITECTURE.md "Environment map"); sun
// disks add their radiance inside their cones (DirectionalLight::radiance_from_direction).
// Camera rays that hit nothing see exactly this (the background matches the oracle's).
// Mirror and dielectric: classic environment mapping — Blinn & Newell 1976, "Texture and
// Reflection in Computer Generated Images" (CACM 19(10)) — with the exact unpolarised Fresnel
// reflectance for the dielectric (Born & Wolf, "Principles of Optics", §1.5.2) and Snell
// refraction at the first interface only.
// Failure mode: the delta materials are an approximation, not part of the parity contract:
// nearby geometry is not reflected (the environment is assumed infinitely far), and light
// leaving a dielectric through its far side is replaced by the environment along the first
// refracted direction, without the (η_o/η_i)² radiance scaling. The oracle follows the chains.
// Inputs: the frame's environment description, the lights (sun disks), a unit direction.

// Environment radiance along unit d.
fn environment_radiance(f: FrameUniforms, d: vec3<f32>) -> vec3<f32> {
    switch f.env_info.x {
        case ENV_CONSTANT: {
            return f.env_radiance.xyz;
        }
        case ENV_MAP: {
            return environment_lookup(f.env_info.y, d).xyz * f.env_radiance.x;
        }
        default: {
            return vec3<f32>(0.0);
        }
    }
}

// Radiance arriving along a ray that leaves the scene in direction d: the environment and
// every sun disk containing d (the oracle's `escaped` with no MIS, as for camera rays).
fn distant_radiance(f: FrameUniforms, d: vec3<f32>) -> vec3<f32> {
    var l = environment_radiance(f, d);
    for (var i = 0u; i < f.counts.x; i++) {
        count_iteration();
        l += sun_radiance_along(lights[i], d);
    }
    return l;
}

// Exact unpolarised Fresnel reflectance for cos θi ≥ 0 and relative index η = η_t/η_i
// (Born & Wolf §1.5.2); 1 under total internal reflection. Returns (F, cos θt).
fn fresnel_dielectric(cos_i: f32, eta: f32) -> vec2<f32> {
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return vec2<f32>(1.0, 0.0);
    }
    let cos_t = sqrt(1.0 - sin2_t);
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return vec2<f32>(0.5 * (rs * rs + rp * rp), cos_t);
}

// Environment seen through a mirror or dielectric at a point with normal n (turned to the
// outside) for the view direction ωo.
fn delta_environment(f: FrameUniforms, b: Bsdf, n: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let c = dot(n, wo);
    let nn = select(n, -n, c < 0.0);
    let cos_o = abs(c);
    let r = nn * (2.0 * cos_o) - wo;
    if b.kind == MAT_MIRROR {
        return b.color * distant_radiance(f, r);
    }
    // Relative index seen from ωo's side: η inside/outside when entering.
    let eta = select(1.0 / b.eta, b.eta, c >= 0.0);
    let fr = fresnel_dielectric(min(cos_o, 1.0), eta);
    var l = fr.x * distant_radiance(f, r);
    if fr.x < 1.0 {
        let t = -wo / eta + nn * (cos_o / eta - fr.y);
        l += (1.0 - fr.x) * distant_radiance(f, normalize(t));
    }
    return l;
}
