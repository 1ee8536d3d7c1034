// energy/kulla_conty.wgsl — `energy_kulla_conty`.
//
// Technique: Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks" (SIGGRAPH
// course, slides 16–18). The energy a white lobe loses at μ is 1 − E(μ); a second lobe
//   f_ms(μo, μi) = (1 − E(μo))(1 − E(μi)) / (π(1 − E_avg))
// returns exactly that (its albedo at μo is 1 − E(μo)) and is reciprocal. Coloured microfacets
// reflect F_avg per bounce and let E_avg escape: summing the bounces,
//   F_ms = F_avg² E_avg / (1 − F_avg(1 − E_avg))
// scales it. Returns f_ms·F_ms·cos θi.
// Failure mode: the lobe is separable and smooth in ωi whatever ωo, while the real
// multiple scattering is lobed around the mirror direction at low roughness and forward at
// grazing angles; F_ms averages the Fresnel colour over angles.
// Inputs: `energy_terms` (energy/table.wgsl).

fn kulla_conty(alpha: f32, f_avg: vec3<f32>, cos_o: f32, cos_i: f32) -> vec3<f32> {
    let o = energy_terms(alpha, cos_o);
    let i = energy_terms(alpha, cos_i);
    let lost = 1.0 - o.e_avg;
    if lost <= 1e-6 {
        return vec3<f32>(0.0);
    }
    let f_ms = max(1.0 - o.e, 0.0) * max(1.0 - i.e, 0.0) / (PI * lost);
    let fresnel = f_avg * f_avg * o.e_avg / (1.0 - f_avg * lost);
    return fresnel * (f_ms * cos_i);
}
