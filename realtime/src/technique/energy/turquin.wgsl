// energy/turquin.wgsl — `energy_turquin`.
//
// Technique: Turquin 2019, "Practical multiple scattering compensation for microfacet models"
// (ILM technical report), eq. 13 with Schlick's Fresnel: the single-scattering lobe scaled by
//   1 + f0·(1 − E(μo))/E(μo),
// which makes a white lobe's albedo exactly 1 and lets a coloured one gain in proportion to f0
// (the multiple bounces' colour saturates towards f0, approximated to first order). Returns
// the added part, f_ss·cos θi · f0·(1/E(μo) − 1).
// Failure mode: the added light has the single-scattering lobe's shape (no energy where that
// lobe has none: at grazing angles the real multiple scattering leaves in other directions),
// and it is not reciprocal (the scale depends on μo alone).
// Inputs: `energy_terms` (energy/table.wgsl).

fn turquin(alpha: f32, f0: vec3<f32>, single: vec3<f32>, cos_o: f32) -> vec3<f32> {
    let e = energy_terms(alpha, cos_o).e;
    if e <= 1e-6 {
        return vec3<f32>(0.0);
    }
    return single * f0 * (1.0 / e - 1.0);
}
