// shadow/visibility.wgsl — the one shadow dispatcher, and the per-light visibility AOV.
//
// Technique: the decomposition every shadow-map technique makes — the light's unshadowed
// integral times a visibility factor V ∈ [0, 1]: Lo ≈ V·∫ f·|cos θi|·Le dω, V from the light's
// shadow map at the shading point. The filter is the pipeline-overridable constant
// SHADOW_METHOD, picked here and nowhere else (bevy_pbr's `sample_shadow_map_*`):
// shadow/hard.wgsl, shadow/pcf.wgsl (2×2, box, Poisson), shadow/pcss.wgsl.
// The AOV `visibility.<light>.Y` follows the oracle's (oracle/src/integrator/mod.rs
// `light_visibility`): 0 where the light cannot reach the point at all (behind a one-sided
// emitter, on its plane, inside a one-sided sphere, outside a spot's cone, the emitter's own
// surface), else V — 1 for the unshadowed methods.
// Failure mode: the product is exact only when visibility and the rest of the integrand are
// uncorrelated over the light (a small light, or a penumbra whose occluded part is lit like the
// rest) — a large light half hidden, its bright part behind the blocker, is wrong even with
// the exact visible fraction; the environment is never shadowed.
// Each light slot's map is its one layer, or under cascades the layer `shadow_layer` picks by
// the point's camera view depth, or under a cube the face it picks by the point's direction
// from the light (shadow/map_common.wgsl).
// Inputs: the map layer's ShadowLight and settings, the point and its front geometric normal,
// the Poisson taps' rotation; for the AOV the emitter or light and the surface point.

// V from map layer `layer` (projection sl) at p with front geometric normal ng, the Poisson
// taps turned by `rot`.
fn shadow_visibility(sl: ShadowLight, layer: u32, s: ShadowSettings, p: vec3<f32>, ng: vec3<f32>, rot: vec2<f32>) -> f32 {
    if SHADOW_METHOD == SHADOW_NONE || sl.shadowed == 0u {
        return 1.0;
    }
    let r = shadow_receiver(sl, s, p, ng);
    if !r.valid {
        return 1.0;
    }
    let side = s.map_side;
    switch SHADOW_METHOD {
        case SHADOW_HARD: {
            return shadow_hard(r, layer);
        }
        case SHADOW_PCF_HW_2X2: {
            return pcf_hw_2x2(r, layer);
        }
        case SHADOW_PCF_BOX: {
            return pcf_box(r, layer, s.kernel, side);
        }
        case SHADOW_PCF_POISSON: {
            return pcf_poisson(r, layer, s.taps, s.radius / side, rot);
        }
        default: {
            return pcss(sl, r, layer, s.blocker_samples, s.filter_samples, side, s.ignore_blocker_depth != 0u, rot);
        }
    }
}

// V of light slot `slot` at the surface point sp seen through target pixel `frag`: its map
// layer picked by sp's camera view depth, the taps' rotation by the pixel.
fn slot_shadow_visibility(f: FrameUniforms, sp: SurfacePoint, slot: u32, frag: vec2<f32>) -> f32 {
    let layer = shadow_layer(slot, sp.p, view_depth(f, sp.p));
    let s = shadow.settings;
    return shadow_visibility(shadow.layers[layer], layer, s, sp.p, sp.ng, shadow_tap_rotation(s, frag));
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

// The AOV value of light slot `slot` at surface point sp (target pixel `frag`): 0 where it
// cannot reach, else V.
fn light_slot_visibility(f: FrameUniforms, sp: SurfacePoint, slot: u32, frag: vec2<f32>) -> f32 {
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
    return slot_shadow_visibility(f, sp, slot, frag);
}
