// energy/fdez_aguera.wgsl — `energy_fdez_aguera`.
//
// Technique: Fdez-Agüera 2019, "A Multiple-Scattering Microfacet Model for Real-Time
// Image-based Lighting" (JCGT 8(1)), §3–4, from the split-sum table alone: the single-scattering
// albedo E_ss = k(f0·A + B), the white loss E_ms = 1 − (A + B), the average Fresnel
// F_avg = k(f0 + (1 − f0)/21), and the light of the further bounces
//   F_ms = E_ss·F_avg / (1 − E_ms·F_avg)
// spread like irradiance: the paper adds F_ms·E_ms × (the cosine-weighted average radiance), a
// Lambertian lobe F_ms·E_ms/π, which lets every light of the renderer use it (the environment
// quadrature then reproduces the paper's irradiance term). Returns F_ms·E_ms·cos θi/π.
// Failure mode: the lobe is Lambertian in ωi (no forward scattering, not reciprocal); E_ss·F_avg
// mixes the single bounce's Fresnel at μo into every later bounce.
// Inputs: `energy_terms` (energy/table.wgsl).

fn fdez_aguera(alpha: f32, k: vec3<f32>, f0: vec3<f32>, cos_o: f32, cos_i: f32) -> vec3<f32> {
    let t = energy_terms(alpha, cos_o);
    let e_ss = k * (f0 * t.a + t.b);
    let e_ms = max(1.0 - t.e, 0.0);
    let f_avg = k * fresnel_average(f0);
    let f_ms = e_ss * f_avg / (1.0 - e_ms * f_avg);
    return f_ms * (e_ms * cos_i * INV_PI);
}
