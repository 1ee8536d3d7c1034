// shadow_visibility.wgsl — the one shadow dispatcher, and the per-light visibility AOV.
//
// Technique: the decomposition every shadow-map technique makes — the light's unshadowed
// integral times a visibility factor V ∈ [0, 1]: Lo ≈ V·∫ f·|cos θi|·Le dω, V from the light's
// shadow map at the shading point. The filter is the pipeline-overridable constant
// SHADOW_METHOD, picked here and nowhere else (bevy_pbr's `sample_shadow_map_*`):
// shadow_hard.wgsl, pcf.wgsl (2×2, box, Poisson), pcss.wgsl.
// The AOV `visibility.<light>.Y` follows the oracle's (oracle/src/integrator/mod.rs
// `light_visibility`): 0 where the light cannot reach the point at all (behind a one-sided
// emitter, on its plane, inside a one-sided sphere, outside a spot's cone, the emitter's own
// surface), else V — 1 for the unshadowed methods.
// Failure mode: the product is exact only when visibility and the rest of the integrand are
// uncorrelated over the light (a small light, or a penumbra whose occluded part is lit like the
// rest) — a large light half hidden, its bright part behind the blocker, is wrong even with
// the exact visible fraction; the environment is never shadowed.
// Inputs: the light slot's ShadowLight and settings, the point and its front geometric normal;
// for the AOV the emitter or light and the surface point.

// V of light slot `slot` (its map layer) at p with front geometric normal ng.
fn shadow_visibility(sl: ShadowLight, slot: u32, s: ShadowSettings, p: vec3<f32>, ng: vec3<f32>) -> f32 {
    if SHADOW_METHOD == SHADOW_NONE || sl.info.x == 0u {
        return 1.0;
    }
    let r = shadow_receiver(sl, s, p, ng);
    if !r.valid {
        return 1.0;
    }
    let side = s.bias.w;
    switch SHADOW_METHOD {
        case SHADOW_HARD: {
            return shadow_hard(r, slot);
        }
        case SHADOW_PCF_HW_2X2: {
            return pcf_hw_2x2(r, slot);
        }
        case SHADOW_PCF_BOX: {
            return pcf_box(r, slot, s.taps.x, side);
        }
        case SHADOW_PCF_POISSON: {
            return pcf_poisson(r, slot, s.taps.y, s.filtering.x / side);
        }
        default: {
            return pcss(sl, r, slot, s.taps.z, s.taps.w, side, s.filtering.y > 0.5);
        }
    }
}

// Whether emitter `s` lights p at all (Rectangle/Disk/SphereLight::sample_li give a sample).
fn emitter_reaches(s: Shape, p: vec3<f32>) -> bool {
    let two_sided = s.emission_info.y != 0u;
    if s.kind == SHAPE_SPHERE {
        let d = s.center.xyz - p;
        return two_sided || dot(d, d) > s.center.w * s.center.w;
    }
    let side = dot(p - s.center.xyz, s.normal.xyz);
    return side != 0.0 && (two_sided || side > 0.0);
}

// Whether scene light `l` lights p at all (a delta light's li ≠ 0; a sun disk always).
fn light_reaches(l: Light, p: vec3<f32>) -> bool {
    if l.kind == LIGHT_DIRECTIONAL {
        return any(l.intensity.xyz > vec3<f32>(0.0));
    }
    return any(punctual_incident(l, p).li > vec3<f32>(0.0));
}

// The AOV value of light slot `slot` at surface point sp: 0 where it cannot reach, else V.
fn light_slot_visibility(f: FrameUniforms, sp: SurfacePoint, slot: u32) -> f32 {
    var reaches: bool;
    if slot < f.counts.y {
        let shape = emitters[slot];
        reaches = shape != sp.shape && emitter_reaches(shapes[shape], sp.p);
    } else {
        reaches = light_reaches(lights[slot - f.counts.y], sp.p);
    }
    if !reaches {
        return 0.0;
    }
    return shadow_visibility(shadow.lights[slot], slot, shadow.settings, sp.p, sp.ng);
}
