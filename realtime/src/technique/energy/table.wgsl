// energy/table.wgsl — the energy-compensation table shared by the three methods.
//
// Technique: one bilinear, clamped lookup of the table realtime/src/technique/energy/tables.rs
// generates and upload.rs appends to the scene's textures (record `frame.energy.y`): texel
// (i, j) of the N × N table at cos θo = i/(N − 1) and perceptual roughness √α = j/(N − 1), the
// split-sum scale A and bias B of
// single-scattering GGX with height-correlated masking (Karis 2013, "Real Shading in Unreal
// Engine 4"; E(μ) = A + B for F = 1) and E_avg = 2∫E(μ)μ dμ of the row.
// Failure mode: the table's resolution (`lut`): between texels E is interpolated linearly.
// Inputs: `ENERGY_METHOD`, `frame.energy`, `texture_infos`, `texels` (through `bilinear`).

// The method (ENERGY_*), a pipeline constant like the other families' methods, so a pipeline
// carries only its own method's lookups (each inlined at every BSDF evaluation; pipelines.rs).
override ENERGY_METHOD: u32 = 0u;

struct EnergyTerms {
    // E(μ) = A + B: the directional albedo of the lobe without Fresnel.
    e: f32,
    a: f32,
    b: f32,
    e_avg: f32,
}

fn energy_terms(alpha: f32, mu: f32) -> EnergyTerms {
    let info = texture_infos[frame.energy.y];
    // Texel i's centre (i + ½)/N holds the value at i/(N − 1).
    let n = f32(info.width);
    let at = (vec2<f32>(clamp(mu, 0.0, 1.0), sqrt(alpha)) * (n - 1.0) + 0.5) / n;
    let t = bilinear(info, at);
    return EnergyTerms(t.x + t.y, t.x, t.y, t.z);
}

// Schlick's Fresnel averaged over the cosine-weighted hemisphere: f0 + (1 − f0)/21, as
// 2∫(1 − μ)⁵μ dμ = 1/21 (Kulla & Conty 2017, slide "Fresnel").
fn fresnel_average(f0: vec3<f32>) -> vec3<f32> {
    return f0 + (1.0 - f0) / 21.0;
}

// What the method adds to a microfacet lobe whose microfacet reflectance is k·F, F Schlick's
// with normal-incidence f0, and whose single-scattering value f_ss·cos θi is `single`; the
// cosines are those of the upper-side pair. 0 under ENERGY_NONE or without a table.
fn energy_compensation(alpha: f32, k: vec3<f32>, f0: vec3<f32>, single: vec3<f32>, cos_o: f32, cos_i: f32) -> vec3<f32> {
    if ENERGY_METHOD == ENERGY_NONE || frame.energy.y == NONE {
        return vec3<f32>(0.0);
    }
    switch ENERGY_METHOD {
        case ENERGY_KULLA_CONTY: {
            return kulla_conty(alpha, k * fresnel_average(f0), cos_o, cos_i);
        }
        case ENERGY_TURQUIN: {
            return turquin(alpha, k * f0, single, cos_o);
        }
        default: {
            return fdez_aguera(alpha, k, f0, cos_o, cos_i);
        }
    }
}
