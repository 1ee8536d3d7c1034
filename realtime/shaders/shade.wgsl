// shade.wgsl — the shading dispatcher both pipelines call: emission, delta lights, area
// lights by the pipeline's method, sun disks, the environment.
//
// Technique: the direct-light integral with visibility ignored, term by term:
// Lo = Le + Σ_delta f·|cos θi|·li + Σ_area ∫ f·|cos θi|·Le dω + ∫ f·|cos θi|·L_env dω — exactly
// what the oracle's `direct-unshadowed` integrator estimates by Monte Carlo
// (oracle/src/integrator/direct.rs), so that with `area_quadrature` the difference is the
// quadrature's (vanishing) error and with `area_representative_point` the method's error.
// The area-light method is the pipeline-overridable constant AREA_METHOD, picked here and
// nowhere else (one dispatcher, as bevy_pbr's `sample_shadow_map_*`). Under a shadow method
// (SHADOW_METHOD ≠ 0) each light's term is multiplied by its visibility V from the light's
// shadow map (shadow/visibility.wgsl) — what the oracle's `direct` integrator then measures
// exactly; the environment stays unshadowed. Under an environment-mapping method
// (ENVMAP_METHOD ≠ 0) the reflector is shaded by envmap/envmap.wgsl instead; under a
// light-map method (LIGHTMAP_METHOD ≠ 0) every shape with a chart by lightmap/lookup.wgsl.
// Emissive meshes light by `mesh_n`×`mesh_n` quadrature over each triangle
// (area/quadrature.wgsl) when the method's `mesh_n` > 0, and nothing at 0 (the default).
// Failure mode: mirror and dielectric surfaces see only the environment (environment.wgsl);
// emissive meshes cast no shadow maps (their light is unshadowed under every shadow method,
// and their cost grows with their triangle count); `max_depth` < 2 is not modelled.
// Inputs: the frame (camera, counts), the scene arrays (this dispatcher and the entry points
// are the only readers besides the leaf samplers), a surface point and ωo.

// The unshadowed `term` of light slot `slot` (area emitters first, then scene lights) at sp,
// seen through target pixel `frag`, times its visibility under the pipeline's shadow method;
// `term` itself when unshadowed.
fn shadowed(f: FrameUniforms, term: vec3<f32>, slot: u32, sp: SurfacePoint, frag: vec2<f32>) -> vec3<f32> {
    if SHADOW_METHOD == SHADOW_NONE || all(term == vec3<f32>(0.0)) {
        return term;
    }
    return term * slot_shadow_visibility(f, sp, slot, frag);
}

// `term` of a light in unit direction `wi` with angular radius tan⁻¹(tan_alpha), times the
// heightfield's own visibility under POM's self-shadowing (detail/ray_march.wgsl) or normal
// and bump mapping's horizon map (detail/horizon.wgsl); 1 otherwise.
fn self_shadowed(f: FrameUniforms, term: vec3<f32>, sp: SurfacePoint, wi: vec3<f32>, tan_alpha: f32) -> vec3<f32> {
    if all(term == vec3<f32>(0.0)) {
        return term;
    }
    if DETAIL_METHOD == DETAIL_POM {
        return term * detail_self_shadow(f, sp, wi, tan_alpha);
    }
    if DETAIL_METHOD == DETAIL_NORMAL_MAPPING || DETAIL_METHOD == DETAIL_BUMP_MAPPING {
        return term * horizon_visibility(f, sp, wi, tan_alpha);
    }
    return term;
}

// Shaded colour and the albedo AOV of a surface point.
struct Shaded {
    color: vec3<f32>,
    albedo: vec3<f32>,
}

// Light reaching ωo from the surface point `sp` (ωo = −camera ray direction) seen through
// target pixel `frag` (the shadow taps' rotation).
// The ambient occlusion of the point being shaded: what the deferred lighting pass read from
// the SSAO passes' output (1 − obscurance), 1 everywhere else. It multiplies the environment's
// light, diffuse and specular lobes alike (the environment is the ambient light; specular
// occlusion taken equal to AO), nothing else.
var<private> ambient_occlusion: f32 = 1.0;

fn shade_surface(f: FrameUniforms, sp: SurfacePoint, wo: vec3<f32>, frag: vec2<f32>) -> Shaded {
    let shape = shapes[sp.shape];
    var b = resolve_bsdf(materials[shape.material], sp.uv);
    if b.kind == MAT_GGX || b.kind == MAT_METAL_ROUGH {
        b.alpha = specular_aa_alpha(b.alpha);
    }
    var color = vec3<f32>(0.0);
    // Emission seen directly, through the pixel's footprint: the front side only unless
    // two-sided (RectangleLight::emitted).
    if shape.emission_info.x != 0u && (shape.emission_info.y != 0u || dot(sp.ng, wo) > 0.0) {
        color += eval_tex_rgb(shape.emission_info.z, shape.emission.xyz, sp.uv);
    }
    // The shading frame's normal: ns turned to the geometric normal's side (integrator `shade`).
    let n = select(sp.ns, -sp.ns, dot(sp.ns, sp.ng) < 0.0);
    if is_envmapped(sp.shape) {
        return Shaded(shade_envmapped(f, sp, b, n, wo, color), bsdf_albedo(b));
    }
    if bsdf_is_delta(b) {
        return Shaded(color + delta_environment(f, b, n, wo), bsdf_albedo(b));
    }
    // A static surface under a light-map method: its diffuse lighting, every light and every
    // bounce, from the baked map; nothing per light (lightmap/lookup.wgsl).
    // Under `specular = direct` the lights' specular lobes follow per pixel (bsdf_eval's
    // specular part alone, reset below).
    if is_lightmapped(shape) {
        count_iteration();
        color += lightmap_albedo(b) / PI * lightmap_irradiance(shape, sp.p);
        if LIGHTMAP_SPECULAR == 0u {
            return Shaded(color, bsdf_albedo(b));
        }
        bsdf_specular_only = true;
    }
    let nq = f.counts.z;
    for (var i = 0u; i < f.counts.x; i++) {
        count_iteration();
        let l = lights[i];
        let slot = f.counts.y + i;
        if is_sun_disk(l) {
            var term: vec3<f32>;
            if AREA_METHOD == AREA_REPRESENTATIVE_POINT {
                term = sun_representative(l, b, n, wo);
            } else {
                term = sun_quadrature(l, b, n, wo, nq);
            }
            let tan_alpha = sqrt(l.params.y / max(1.0 - l.params.y, 1e-12));
            term = self_shadowed(f, term, sp, l.direction.xyz, tan_alpha);
            color += shadowed(f, term, slot, sp, frag);
        } else {
            var inc = punctual_incident(l, sp.p);
            if any(inc.li > vec3<f32>(0.0)) {
                inc.li *= projected_texture(f, l, sp);
                let term = self_shadowed(f, bsdf_eval(b, n, wo, inc.wi) * inc.li, sp, inc.wi, 0.0);
                color += shadowed(f, term, slot, sp, frag);
            }
        }
    }
    for (var i = 0u; i < f.counts.y; i++) {
        count_iteration();
        let s = shapes[emitters[i]];
        var term: vec3<f32>;
        if AREA_METHOD == AREA_REPRESENTATIVE_POINT {
            term = area_light_representative(s, b, n, wo, sp.p);
        } else {
            term = area_light_quadrature(s, b, n, wo, sp.p, nq);
        }
        // Towards the light's centre, its size as the disk of equal area (a sphere's radius).
        let to_light = s.center.xyz - sp.p;
        let dist = length(to_light);
        let radius = select(sqrt(s.normal.w / PI), s.center.w, s.kind == SHAPE_SPHERE);
        term = self_shadowed(f, term, sp, to_light / max(dist, 1e-30), radius / max(dist, 1e-30));
        color += shadowed(f, term, i, sp, frag);
    }
    // Emissive meshes: every triangle by `mesh_n`×`mesh_n` quadrature (none at 0, the
    // default), unshadowed under every shadow method.
    color += emissive_mesh_quadrature(f, b, n, wo, sp.p);
    if f.env_info.x != ENV_NONE && f.env_info.z > 0u {
        color += ambient_occlusion * environment_quadrature(f, b, n, wo, f.env_info.z);
    }
    bsdf_specular_only = false;
    return Shaded(color, bsdf_albedo(b));
}
