//! GGX / Trowbridge-Reitz microfacet reflection with Schlick Fresnel.
//!
//! f(ωo, ωi) = k·F(ωi·h)·D(h)·G2(ωo, ωi)/(4 cos θo cos θi), h = normalize(ωo + ωi),
//! F = f0 + (1 − f0)(1 − ωi·h)⁵ (Schlick), k the reflectance multiplier; eval = f·cos θi.
//! D, Λ and G2 (height-correlated or separable Smith) are in [`super::microfacet`].
//! Sampling draws h from the visible normals D_ωo and reflects ωo:
//! pdf = D_ωo(h)/(4|ωo·h|) = G1(ωo)·D(h)/(4 cos θo), weight = k·F·G2/G1(ωo).
//! Directions reflected under the horizon are lost (`None`). Reciprocal. Two-sided.
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | reflectance k | RGB | — | multiplier, [0, 1] (Mitsuba's `specular_reflectance`) |
//! | f0 | RGB | — | Schlick normal-incidence reflectance, [0, 1]; 1 gives F ≡ 1 |
//! | conductor η, k | RGB, RGB | none | instead of Schlick: the exact Fresnel of a conductor of index η + ik ([`super::fresnel::conductor`]) |
//! | roughness | f32 | — | perceptual, [0, 1]; α = roughness² (≥ 10⁻³) |
//! | masking | [`Masking`] | height-correlated | Smith G2 variant |
//!
//! | scattering | single / multiple | single | multiple: every order, by the random walk of [`super::microsurface`] |
//!
//! Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces" (EGSR),
//! eq. 20 for f; Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4))
//! for sampling.
//!
//! **Multiple scattering** (Heitz, Hanika, d'Eon & Dachsbacher 2016): the microfacets are
//! mirrors of reflectance k·F, and light may bounce between them any number of times.
//! - eval = the closed form above (the first bounce) + one walk's estimate of the higher
//!   orders ([`super::microsurface::Microsurface::eval_multiple`]): unbiased, not exact.
//! - sample = one walk from ωo; its exit direction, weight = product of the k·F met.
//! - pdf = the single-scattering pdf above, for every caller: the walk's own density has no
//!   closed form, and multiple importance sampling only needs weights that sum to one over
//!   the strategies at every direction (Veach 1997, thesis §9.2.2), which any deterministic
//!   stand-in density positive wherever f is gives (Heitz et al. 2016, §6.3). The sample's
//!   weight is not eval/pdf then, and the integrators never assume it is.

use glam::{Vec2, Vec3};
use scenes::{ComplexIor, Masking, Rgb};

use super::fresnel::{conductor, reflect, schlick};
use super::microfacet::{half_vector, TrowbridgeReitz};
use super::microsurface::{Microsurface, WalkSeed};
use super::{flip_z, sanitize_rgb, sanitize_unit, upper_pair, BsdfSample};

/// GGX reflection lobe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    reflectance: Rgb,
    f0: Rgb,
    dist: TrowbridgeReitz,
    masking: Masking,
    /// `Some`: a conductor's exact Fresnel instead of Schlick's with `f0`.
    conductor: Option<ComplexIor>,
    /// `Some` for multiple scattering: the seed of this vertex's walks.
    multiple_scattering: Option<WalkSeed>,
}

impl Ggx {
    /// GGX lobe; negative or NaN colour channels become 0, roughness is clamped to [0, 1].
    pub fn new(reflectance: Rgb, f0: Rgb, roughness: f32, masking: Masking) -> Self {
        Ggx {
            reflectance: sanitize_rgb(reflectance),
            f0: sanitize_rgb(f0),
            dist: TrowbridgeReitz::from_roughness(sanitize_unit(roughness)),
            masking,
            conductor: None,
            multiple_scattering: None,
        }
    }

    /// The same lobe with the exact Fresnel reflectance of a conductor of index `ior`
    /// ([`conductor`]) instead of Schlick's.
    pub fn with_conductor(self, ior: ComplexIor) -> Self {
        Ggx {
            conductor: Some(ior),
            ..self
        }
    }

    /// The same lobe scattering any number of times on its microsurface (height-correlated
    /// masking, which the walk implies), its walks seeded by `seed`.
    pub fn multiple_scattering(self, seed: WalkSeed) -> Self {
        Ggx {
            masking: Masking::HeightCorrelated,
            multiple_scattering: Some(seed),
            ..self
        }
    }

    /// The seed of a multiple-scattering lobe's walks, `None` for single scattering.
    pub fn walk_seed(&self) -> Option<WalkSeed> {
        self.multiple_scattering
    }

    /// k·F·D·G2/(4 cos θo) on the same side, else 0.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let Some((wo, wi)) = upper_pair(wo, wi) else {
            return Rgb::ZERO;
        };
        let Some(h) = half_vector(wo, wi) else {
            return Rgb::ZERO;
        };
        let d = self.dist.d(h);
        let g = self.dist.g2(wo, wi, self.masking);
        let single = self.fresnel(wi.dot(h)) * (d * g / (4.0 * wo.z));
        match self.multiple_scattering {
            None => single,
            Some(seed) => {
                let fresnel = |c: f32| self.fresnel(c);
                let higher =
                    Microsurface::new(self.dist).eval_multiple(wo, wi, &fresnel, &mut seed.eval_stream());
                single + higher
            }
        }
    }

    /// Reflects ωo about a visible normal (Heitz 2018); weight k·F·G2/G1(ωo). Multiple
    /// scattering: one walk from ωo (`u` unused).
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let flip = wo.z < 0.0;
        let wo_up = if flip { flip_z(wo) } else { wo };
        if let Some(seed) = self.multiple_scattering {
            let fresnel = |c: f32| self.fresnel(c);
            let (wi, weight) =
                Microsurface::new(self.dist).sample(wo_up, &fresnel, &mut seed.sample_stream())?;
            return BsdfSample::reflection(wi, flip, weight, self.dist.reflection_pdf(wo_up, wi));
        }
        // Sample ωm from the visible normals, reflect ωo about it.
        let m = self.dist.sample_visible(wo_up, u);
        let cos_om = wo_up.dot(m);
        let wi = reflect(wo_up, m);
        if cos_om <= 0.0 || wi.z <= 0.0 {
            return None;
        }
        let pdf = self.dist.visible_normal_pdf(wo_up, m) / (4.0 * cos_om);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let g1 = self.dist.g1(wo_up);
        let g2 = self.dist.g2(wo_up, wi, self.masking);
        Some(BsdfSample {
            wi: if flip { flip_z(wi) } else { wi },
            weight: self.fresnel(cos_om) * (g2 / g1),
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    /// D_ωo(h)/(4|ωo·h|) on the same side, else 0.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match upper_pair(wo, wi) {
            Some((wo, wi)) => self.dist.reflection_pdf(wo, wi),
            None => 0.0,
        }
    }

    /// Never a delta (α ≥ 10⁻³).
    pub fn is_delta(&self) -> bool {
        false
    }

    /// The specular colour at normal incidence, k·F(0°).
    pub fn albedo(&self) -> Rgb {
        self.fresnel(1.0)
    }

    /// k·(f0 + (1 − f0)(1 − cos θd)⁵), or k·F_conductor(cos θd).
    fn fresnel(&self, cos_d: f32) -> Rgb {
        match self.conductor {
            Some(ior) => self.reflectance * conductor(cos_d, ior.eta, ior.k),
            None => self.reflectance * schlick(self.f0, cos_d),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::check::{check_stochastic, close, direction, in_plane_sweep, standard_checks, Expect};
    use crate::bsdf::{Bsdf, WalkSeed};

    /// Hand-derived in-plane values ([`in_plane_sweep`]): eval = k F(θd) D G2/(4 cos θo),
    /// pdf = G1(θo) D/(4 cos θo), G2 = 1/(1 + Λo + Λi) or 1/((1 + Λo)(1 + Λi)).
    #[test]
    fn bsdf_ggx_closed_form_sweep() {
        let (k, f0) = (0.9f64, 0.04f64);
        for masking in [Masking::HeightCorrelated, Masking::Separable] {
            for roughness in [0.05f64, 0.3, 0.8] {
                let (k32, f032) = (Rgb::splat(k as f32), Rgb::splat(f0 as f32));
                let bsdf = Bsdf::Ggx(Ggx::new(k32, f032, roughness as f32, masking));
                in_plane_sweep((roughness * roughness).max(1e-3), |c| {
                    let g2 = match masking {
                        Masking::HeightCorrelated => 1.0 / (1.0 + c.lambda_o + c.lambda_i),
                        Masking::Separable => 1.0 / ((1.0 + c.lambda_o) * (1.0 + c.lambda_i)),
                    };
                    let f = f0 + (1.0 - f0) * (1.0 - c.cos_d).powi(5);
                    let eval = k * f * c.d * g2 / (4.0 * c.theta_o.cos());
                    let pdf = c.d / ((1.0 + c.lambda_o) * 4.0 * c.theta_o.cos());
                    let (e, p) = (bsdf.eval(c.wo, c.wi).x, bsdf.pdf(c.wo, c.wi));
                    assert!(
                        close(e, eval) && close(p, pdf),
                        "{masking:?}, r {roughness}, ωo {}, ωi {}: eval {e} vs {eval}, pdf {p} vs {pdf}",
                        c.wo,
                        c.wi
                    );
                });
            }
        }
        // Hand values, roughness 0.3 (α = 0.09), f0 = 1, k = 1 at normal incidence: D/4 =
        // 1/(4πα²) = 9.824379 for eval and pdf. f0 = 0.04, θo = θi = 45° opposite (h = z):
        // Λ = 0.00202092, F = 0.04206927, eval = F D G2/(4 cos 45°) = 0.5821479 (height-correlated),
        // 0.5821455 (separable), pdf = D/((1 + Λ) 4 cos 45°) = 13.865749.
        let white = Bsdf::Ggx(Ggx::new(Rgb::ONE, Rgb::ONE, 0.3, Masking::HeightCorrelated));
        let (e, p) = (white.eval(Vec3::Z, Vec3::Z).x, white.pdf(Vec3::Z, Vec3::Z));
        assert!(
            (e - 9.824_379).abs() < 1e-4 && (p - 9.824_379).abs() < 1e-4,
            "eval {e}, pdf {p}"
        );
        for (masking, expected) in [
            (Masking::HeightCorrelated, 0.582_147_9),
            (Masking::Separable, 0.582_145_5),
        ] {
            let b = Bsdf::Ggx(Ggx::new(Rgb::ONE, Rgb::splat(0.04), 0.3, masking));
            let (wo, wi) = (direction(45.0, 0.0), direction(45.0, std::f32::consts::PI));
            let (e, p) = (b.eval(wo, wi).x, b.pdf(wo, wi));
            assert!(
                (e - expected).abs() < 1e-5 && (p - 13.865_749).abs() < 1e-3,
                "{masking:?}: eval {e} vs {expected}, pdf {p} vs 13.865749"
            );
        }
    }

    fn properties(roughness: f32, seed: u64) {
        for (masking, chi2) in [(Masking::HeightCorrelated, true), (Masking::Separable, false)] {
            let expect = Expect {
                white: true,
                lossless: false,
                energy_max_theta_deg: 90.0,
                albedo: None,
                chi2,
            };
            let bsdf = Bsdf::Ggx(Ggx::new(Rgb::ONE, Rgb::ONE, roughness, masking));
            standard_checks(&format!("GGX r = {roughness}, {masking:?}"), &bsdf, &expect, seed);
        }
        // Coloured Schlick Fresnel: consistency and reciprocity with F varying per channel.
        let expect = Expect {
            white: true,
            lossless: false,
            energy_max_theta_deg: 90.0,
            albedo: None,
            chi2: false,
        };
        let bsdf = Bsdf::Ggx(Ggx::new(
            Rgb::new(0.9, 0.8, 1.0),
            Rgb::new(0.95, 0.6, 0.04),
            roughness,
            Masking::HeightCorrelated,
        ));
        standard_checks(
            &format!("GGX r = {roughness}, coloured"),
            &bsdf,
            &expect,
            seed + 100,
        );
    }

    #[test]
    fn bsdf_ggx_properties_r005() {
        properties(0.05, 21);
    }

    #[test]
    fn bsdf_ggx_properties_r03() {
        properties(0.3, 22);
    }

    #[test]
    fn bsdf_ggx_properties_r08() {
        properties(0.8, 23);
    }

    /// A conductor's exact Fresnel (gold) in place of Schlick's: eval = k·F_conductor(ωi·h)·D·G2/(4 cos θo)
    /// against the closed form, and the property checks (sampling, reciprocity, energy, χ²).
    #[test]
    fn bsdf_ggx_conductor() {
        let gold = ComplexIor {
            eta: Rgb::new(0.166, 0.433, 1.51),
            k: Rgb::new(3.15, 2.32, 1.88),
        };
        let lobe = Ggx::new(Rgb::splat(0.9), Rgb::ONE, 0.4, Masking::HeightCorrelated).with_conductor(gold);
        let plain = Ggx::new(Rgb::splat(0.9), Rgb::ONE, 0.4, Masking::HeightCorrelated);
        for (wo, wi) in [
            (direction(30.0, 0.0), direction(50.0, 2.5)),
            (direction(70.0, 1.0), direction(10.0, 3.0)),
        ] {
            let h = (wo + wi).normalize();
            let expected = conductor(wi.dot(h), gold.eta, gold.k) * plain.eval(wo, wi);
            let e = lobe.eval(wo, wi);
            assert!(
                (e - expected).abs().max_element() < 1e-5 * expected.max_element(),
                "{e} vs {expected}"
            );
            assert_eq!(lobe.pdf(wo, wi), plain.pdf(wo, wi));
        }
        let expect = Expect {
            white: true,
            lossless: false,
            energy_max_theta_deg: 90.0,
            albedo: None,
            chi2: false,
        };
        standard_checks("GGX gold conductor", &Bsdf::Ggx(lobe), &expect, 60);
        // And under multiple scattering, its walk's Fresnel is the same function.
        check_stochastic(
            "GGX gold conductor, multiple",
            &Bsdf::Ggx(lobe.multiple_scattering(WalkSeed(0))),
            &Bsdf::Ggx(lobe),
            61,
        );
    }

    /// Multiple scattering: sample and eval estimate the same BRDF with coloured k·F
    /// ([`check_stochastic`]), at a rough and a smooth surface.
    #[test]
    fn bsdf_ggx_multiple_scattering_consistency() {
        let (k, f0) = (Rgb::new(0.9, 0.8, 1.0), Rgb::new(0.95, 0.6, 0.04));
        for (i, roughness) in [0.2f32, 0.9].into_iter().enumerate() {
            let single = Ggx::new(k, f0, roughness, Masking::HeightCorrelated);
            let multiple = Bsdf::Ggx(single.multiple_scattering(WalkSeed(0)));
            let name = format!("GGX multiple, r = {roughness}");
            check_stochastic(&name, &multiple, &Bsdf::Ggx(single), 40 + i as u64);
        }
    }
}
