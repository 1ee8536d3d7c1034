//! glTF 2.0 metallic-roughness material.
//!
//! With h = normalize(ωo + ωi), w = (1 − |ωo·h|)⁵, α = roughness² and
//! s = D(h)·G2(ωo, ωi)/(4 cos θo cos θi) (GGX with height-correlated Smith, [`super::microfacet`]):
//! - metal = s·(c + (1 − c)·w),
//! - dielectric = mix(c/π, s, 0.04 + 0.96·w),
//! - f = mix(dielectric, metal, m), eval = f·cos θi.
//!
//! Every term is symmetric in ωo, ωi, so f is reciprocal. It is not energy conserving by
//! construction: the diffuse term is weighted by 1 − F(ωo·h) at the half vector of the
//! pair, not by what the specular lobe leaves over, so with a white base colour and m < 1
//! the albedo exceeds 1 beyond θo ≈ 40° (m = 0, roughness 0.05: 1.0004 at 45°, 1.35 at 80°,
//! 1.80 at 89°). The pure metal (m = 1) is single-scattering GGX and stays ≤ 1. Two-sided.
//!
//! Sampling is a one-sample mixture: the specular lobe (visible normals, Heitz 2018) with
//! probability p, the cosine-weighted diffuse lobe otherwise, where p is the specular share
//! of an albedo estimate at ωo (Schlick F at cos θo, Rec.709 luminance of the base colour)
//! clamped to [0.1, 0.9] (p = 1 when the diffuse term vanishes). pdf = p·pdf_spec +
//! (1 − p)·cos θi/π, weight = eval/pdf; specular directions under the horizon are lost.
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | base colour c | RGB | — | linear, [0, 1] |
//! | metallic m | f32 | — | [0, 1] |
//! | roughness | f32 | — | perceptual, [0, 1]; α = roughness² (≥ 10⁻³) |
//! | scattering | single / multiple | single | multiple: the metal scatters every order ([`super::microsurface`]) |
//!
//! **Multiple scattering** replaces the metal term by the random walk on its microsurface
//! (Heitz, Hanika, d'Eon & Dachsbacher 2016) with microfacet reflectance c + (1 − c)w; the
//! dielectric layer (diffuse and its specular) stays as the specification writes it.
//! - eval = the closed form above + m · one walk's estimate of the metal's higher orders.
//! - sample picks one of three lobes, each weighted by its own contribution only: the metal
//!   walk with probability p·m (weight = walk throughput / p), the dielectric specular lobe
//!   with p·(1 − m), the diffuse lobe with 1 − p. Counting each lobe only when it is drawn is
//!   unbiased without the walk's density, which has no closed form.
//! - pdf = the mixture pdf above (the single-scattering stand-in every caller uses for
//!   multiple importance sampling; see [`super::ggx`] for why any such density is unbiased).
//!
//! glTF 2.0 specification, Appendix B "BRDF Implementation", §B.3.5 "Metal BRDF and
//! Dielectric BRDF" (as corrected in KhronosGroup/glTF#2392, 2024).

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};
use scenes::{Masking, Rgb};

use super::fresnel::{reflect, schlick, schlick_scalar, schlick_weight};
use super::microfacet::{half_vector, TrowbridgeReitz};
use super::microsurface::{Microsurface, WalkSeed};
use super::{flip_z, sanitize_rgb, sanitize_unit, upper_pair, BsdfSample};
use crate::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};

/// Dielectric normal-incidence reflectance of the glTF model (η = 1.5).
const DIELECTRIC_F0: f32 = 0.04;
/// Bounds on the probability of sampling the specular lobe when both lobes are present.
const SPECULAR_PROBABILITY_RANGE: (f32, f32) = (0.1, 0.9);

/// glTF 2.0 metallic-roughness BRDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetalRough {
    base_color: Rgb,
    metallic: f32,
    dist: TrowbridgeReitz,
    /// `Some` for a multiple-scattering metal: the seed of this vertex's walks.
    multiple_scattering: Option<WalkSeed>,
}

impl MetalRough {
    /// Metallic-roughness BRDF; NaN and negative colour channels become 0, metallic and
    /// roughness are clamped to [0, 1].
    pub fn new(base_color: Rgb, metallic: f32, roughness: f32) -> Self {
        MetalRough {
            base_color: sanitize_rgb(base_color),
            metallic: sanitize_unit(metallic),
            dist: TrowbridgeReitz::from_roughness(sanitize_unit(roughness)),
            multiple_scattering: None,
        }
    }

    /// The same material whose metal scatters any number of times on its microsurface,
    /// its walks seeded by `seed`.
    pub fn multiple_scattering(self, seed: WalkSeed) -> Self {
        MetalRough {
            multiple_scattering: Some(seed),
            ..self
        }
    }

    /// The seed of a multiple-scattering metal's walks, `None` for single scattering.
    pub fn walk_seed(&self) -> Option<WalkSeed> {
        self.multiple_scattering
    }

    /// mix(dielectric, metal, m)·cos θi on the same side, else 0.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        match upper_pair(wo, wi) {
            Some((wo, wi)) => self.eval_upper(wo, wi),
            None => Rgb::ZERO,
        }
    }

    /// Picks the specular lobe with probability p (`u_lobe < p`), else the diffuse lobe;
    /// weight = eval/(mixture pdf).
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let flip = wo.z < 0.0;
        let wo_up = if flip { flip_z(wo) } else { wo };
        let p_spec = self.specular_probability(wo_up);
        if let Some(seed) = self.multiple_scattering {
            let (wi, weight) = self.sample_by_lobe(wo_up, p_spec, u_lobe, u, seed)?;
            return BsdfSample::reflection(wi, flip, weight, self.mixture_pdf(wo_up, wi, p_spec));
        }
        let wi = if u_lobe < p_spec {
            // Specular: reflect ωo about a visible normal.
            let m = self.dist.sample_visible(wo_up, u);
            reflect(wo_up, m)
        } else {
            // Diffuse: cosine-weighted.
            square_to_cosine_hemisphere(u)
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.mixture_pdf(wo_up, wi, p_spec);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            wi: if flip { flip_z(wi) } else { wi },
            weight: self.eval_upper(wo_up, wi) / pdf,
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    /// p·pdf_spec + (1 − p)·cos θi/π on the same side, else 0.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match upper_pair(wo, wi) {
            Some((wo, wi)) => self.mixture_pdf(wo, wi, self.specular_probability(wo)),
            None => 0.0,
        }
    }

    /// Never a delta (α ≥ 10⁻³).
    pub fn is_delta(&self) -> bool {
        false
    }

    /// The base colour.
    pub fn albedo(&self) -> Rgb {
        self.base_color
    }

    /// Multiple scattering's sample (ωo.z > 0): one lobe drawn, weighted by its own
    /// contribution over its probability (module notes); `None` below the horizon.
    fn sample_by_lobe(
        &self,
        wo: Vec3,
        p_spec: f32,
        u_lobe: f32,
        u: Vec2,
        seed: WalkSeed,
    ) -> Option<(Vec3, Rgb)> {
        let m = self.metallic;
        if u_lobe < p_spec && u_lobe < p_spec * m {
            // The metal's walk: E[throughput | ωi] = f_metal cos θi / p_walk(ωi).
            let fresnel = |c: f32| schlick(self.base_color, c);
            let (wi, throughput) =
                Microsurface::new(self.dist).sample(wo, &fresnel, &mut seed.sample_stream())?;
            return Some((wi, throughput / p_spec));
        }
        let wi = if u_lobe < p_spec {
            reflect(wo, self.dist.sample_visible(wo, u))
        } else {
            square_to_cosine_hemisphere(u)
        };
        if wi.z <= 0.0 {
            return None;
        }
        let h = half_vector(wo, wi)?;
        let f_dielectric = DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * schlick_weight(wo.dot(h).abs());
        if u_lobe < p_spec {
            // The dielectric's specular lobe, by its visible normals.
            let pdf = self.dist.reflection_pdf(wo, wi);
            if pdf.is_nan() || pdf <= 0.0 {
                return None;
            }
            let spec_cos = self.dist.d(h) * self.dist.g2(wo, wi, Masking::HeightCorrelated) / (4.0 * wo.z);
            // Drawn with probability p·(1 − m), its contribution (1 − m)·F_d·s·cos θi.
            Some((wi, Rgb::splat(f_dielectric * spec_cos / (pdf * p_spec))))
        } else {
            // The diffuse lobe: f cos θi / (cos θi/π) = (1 − m)(1 − F_d) c.
            Some((
                wi,
                self.base_color * ((1.0 - m) * (1.0 - f_dielectric) / (1.0 - p_spec)),
            ))
        }
    }

    /// eval for ωo, ωi both with z > 0.
    fn eval_upper(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let Some(h) = half_vector(wo, wi) else {
            return Rgb::ZERO;
        };
        let m = self.metallic;
        let w = schlick_weight(wo.dot(h).abs());
        // s·cos θi = D·G2/(4 cos θo), the specular BRDF times the cosine.
        let spec_cos = self.dist.d(h) * self.dist.g2(wo, wi, Masking::HeightCorrelated) / (4.0 * wo.z);
        let f_dielectric = DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * w;
        let metal_fresnel = self.base_color + (Rgb::ONE - self.base_color) * w;
        let diffuse = self.base_color * ((1.0 - m) * (1.0 - f_dielectric) * FRAC_1_PI * wi.z);
        let specular = (Rgb::splat((1.0 - m) * f_dielectric) + metal_fresnel * m) * spec_cos;
        match self.multiple_scattering {
            Some(seed) if m > 0.0 => {
                let fresnel = |c: f32| schlick(self.base_color, c);
                let higher =
                    Microsurface::new(self.dist).eval_multiple(wo, wi, &fresnel, &mut seed.eval_stream());
                diffuse + specular + higher * m
            }
            _ => diffuse + specular,
        }
    }

    /// Mixture density for ωo, ωi both with z > 0.
    fn mixture_pdf(&self, wo: Vec3, wi: Vec3, p_spec: f32) -> f32 {
        let spec = if p_spec > 0.0 {
            self.dist.reflection_pdf(wo, wi)
        } else {
            0.0
        };
        p_spec * spec + (1.0 - p_spec) * cosine_hemisphere_pdf(wi)
    }

    /// Probability of sampling the specular lobe from ωo (z > 0): the specular share of
    /// the albedo estimate spec = m·Y(F_metal) + (1 − m)·F_d, diffuse = (1 − m)(1 − F_d)·Y(c),
    /// with Schlick F at cos θo and Y the Rec.709 luminance.
    fn specular_probability(&self, wo: Vec3) -> f32 {
        let m = self.metallic;
        let f_d = schlick_scalar(DIELECTRIC_F0, wo.z);
        let diffuse = (1.0 - m) * (1.0 - f_d) * luminance(self.base_color);
        if diffuse <= 0.0 {
            return 1.0;
        }
        let spec = m * luminance(schlick(self.base_color, wo.z)) + (1.0 - m) * f_d;
        let (lo, hi) = SPECULAR_PROBABILITY_RANGE;
        (spec / (spec + diffuse)).clamp(lo, hi)
    }
}

/// Rec.709 / sRGB relative luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709-6,
/// item 3.2).
#[inline]
fn luminance(c: Rgb) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::bsdf::check::{check_stochastic, close, direction, in_plane_sweep, standard_checks, Expect};
    use crate::bsdf::{Bsdf, WalkSeed};

    /// Lobe-selection probability from the documented albedo estimate, in f64.
    fn specular_probability(c: [f64; 3], m: f64, cos_o: f64) -> f64 {
        let y = |v: [f64; 3]| 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
        let w = (1.0 - cos_o).powi(5);
        let fo = 0.04 + 0.96 * w;
        let diffuse = (1.0 - m) * (1.0 - fo) * y(c);
        let spec = m * y(c.map(|ck| ck + (1.0 - ck) * w)) + (1.0 - m) * fo;
        if diffuse > 0.0 {
            (spec / (spec + diffuse)).clamp(0.1, 0.9)
        } else {
            1.0
        }
    }

    /// Hand-derived in-plane values ([`in_plane_sweep`]) straight from glTF Appendix B:
    /// f·cos = [(1−m)(1−Fd)c/π + ((1−m)Fd + m(c + (1−c)w))·D·G2/(4 cos θo cos θi)]·cos θi,
    /// w = (1 − cos θd)⁵, Fd = 0.04 + 0.96w; pdf = p·G1(θo)D/(4 cos θo) + (1−p)cos θi/π.
    #[test]
    fn bsdf_metal_rough_closed_form_sweep() {
        let c = [0.8f64, 0.5, 0.2];
        for m in [0.0f64, 0.5, 1.0] {
            for roughness in [0.05f64, 0.3, 0.8] {
                let base = Rgb::new(c[0] as f32, c[1] as f32, c[2] as f32);
                let bsdf = Bsdf::MetalRough(MetalRough::new(base, m as f32, roughness as f32));
                in_plane_sweep((roughness * roughness).max(1e-3), |g| {
                    let (cos_o, cos_i) = (g.theta_o.cos(), g.theta_i.cos());
                    let s = g.d / ((1.0 + g.lambda_o + g.lambda_i) * 4.0 * cos_o * cos_i);
                    let w = (1.0 - g.cos_d).powi(5);
                    let fd = 0.04 + 0.96 * w;
                    let p = specular_probability(c, m, cos_o);
                    let pdf = p * g.d / ((1.0 + g.lambda_o) * 4.0 * cos_o) + (1.0 - p) * cos_i / PI;
                    let (e, actual_pdf) = (bsdf.eval(g.wo, g.wi), bsdf.pdf(g.wo, g.wi));
                    let case = format!("m {m}, r {roughness}, ωo {}, ωi {}", g.wo, g.wi);
                    for k in 0..3 {
                        let metal = c[k] + (1.0 - c[k]) * w;
                        let f = (1.0 - m) * (1.0 - fd) * c[k] / PI + ((1.0 - m) * fd + m * metal) * s;
                        assert!(
                            close(e[k], f * cos_i),
                            "{case}: eval[{k}] {} vs {}",
                            e[k],
                            f * cos_i
                        );
                    }
                    assert!(close(actual_pdf, pdf), "{case}: pdf {actual_pdf} vs {pdf}");
                });
            }
        }
        // Hand values: c = (0.8, 0.5, 0.2), m = 0.5, roughness 0.3, ωo = ωi = z (h = z, w = 0):
        // f·cos = 0.5·0.96·c/π + (0.02 + 0.5c)/(4πα²) = (4.248470, 2.728977, 1.209483);
        // p = 0.527974, pdf = p/(4πα²) + (1 − p)/π = 5.337263.
        let bsdf = Bsdf::MetalRough(MetalRough::new(Rgb::new(0.8, 0.5, 0.2), 0.5, 0.3));
        let (e, p) = (bsdf.eval(Vec3::Z, Vec3::Z), bsdf.pdf(Vec3::Z, Vec3::Z));
        let expected = Rgb::new(4.24847, 2.728_977, 1.209_483);
        assert!(
            (e - expected).abs().max_element() < 1e-4,
            "eval {e} vs {expected}"
        );
        assert!((p - 5.337_263).abs() < 1e-4, "pdf {p} vs 5.337263");
    }

    /// The energy bound holds for the pure metal (GGX alone) at every angle, and with a
    /// diffuse part only near normal incidence (θo ≤ 30°; see the module header and
    /// [`bsdf_metal_rough_exceeds_unit_albedo_at_grazing_angles`]).
    fn properties(metallic: f32, seed: u64) {
        for (k, roughness) in [0.05f32, 0.3, 0.8].into_iter().enumerate() {
            let expect = Expect {
                white: true,
                lossless: false,
                energy_max_theta_deg: if metallic < 1.0 { 30.0 } else { 90.0 },
                albedo: None,
                chi2: true,
            };
            let bsdf = Bsdf::MetalRough(MetalRough::new(Rgb::ONE, metallic, roughness));
            let name = format!("metal-rough m = {metallic}, r = {roughness}");
            standard_checks(&name, &bsdf, &expect, seed + k as u64);
        }
    }

    #[test]
    fn bsdf_metal_rough_properties_m0() {
        properties(0.0, 31);
    }

    #[test]
    fn bsdf_metal_rough_properties_m05() {
        properties(0.5, 34);
    }

    #[test]
    fn bsdf_metal_rough_properties_m1() {
        properties(1.0, 37);
    }

    /// Multiple scattering: sample (three lobes, each counted alone) and eval estimate the
    /// same BRDF ([`check_stochastic`]) for a coloured base at metalness 0.5 and 1.
    #[test]
    fn bsdf_metal_rough_multiple_scattering_consistency() {
        let base = Rgb::new(0.95, 0.64, 0.54);
        for (i, (metallic, roughness)) in [(0.5f32, 0.7f32), (1.0, 0.3), (0.0, 0.5)].into_iter().enumerate() {
            let single = MetalRough::new(base, metallic, roughness);
            let multiple = Bsdf::MetalRough(single.multiple_scattering(WalkSeed(0)));
            let name = format!("metal-rough multiple, m = {metallic}, r = {roughness}");
            check_stochastic(&name, &multiple, &Bsdf::MetalRough(single), 50 + i as u64);
        }
    }

    /// Known limitation of the glTF model (not of this implementation): with a white base
    /// colour and m < 1 the albedo exceeds 1 at grazing ωo, because the specular lobe
    /// reflects ≈ F(cos θo) (0.65 at 80°) while the diffuse term keeps 1 − F(ωo·h) ≈ 0.96 for
    /// most ωi. Measured by quadrature: m = 0, roughness 0.05: 1.0004 at 45°, 1.354 at 80°,
    /// 1.80 at 89°; m = 0.5: 1.177 at 80°. A lower bound, so an accidental "fix" that
    /// departs from the specification fails.
    #[test]
    fn bsdf_metal_rough_exceeds_unit_albedo_at_grazing_angles() {
        use crate::bsdf::chi2::integrate_sphere;
        for (metallic, roughness, theta, lower) in [
            (0.0f32, 0.05f32, 80.0f32, 1.3),
            (0.0, 0.3, 80.0, 1.2),
            (0.5, 0.05, 80.0, 1.15),
        ] {
            let bsdf = MetalRough::new(Rgb::ONE, metallic, roughness);
            let wo = direction(theta, 0.0);
            let albedo = integrate_sphere(&|w| bsdf.eval(wo, w).x as f64);
            assert!(
                albedo > lower,
                "m {metallic}, r {roughness}, θo {theta}°: albedo {albedo}, expected > {lower}"
            );
        }
        // Near normal incidence it stays ≤ 1 (also checked by the property tests).
        let bsdf = MetalRough::new(Rgb::ONE, 0.0, 0.05);
        let albedo = integrate_sphere(&|w| bsdf.eval(direction(10.0, 0.0), w).x as f64);
        assert!(albedo <= 1.0, "θo 10°: albedo {albedo}, expected ≤ 1");
    }
}
