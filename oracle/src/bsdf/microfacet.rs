//! The GGX / Trowbridge-Reitz microfacet distribution shared by [`super::ggx`] and
//! [`super::metal_rough`]: normal distribution D, Smith Λ, G1 and G2, and sampling of the
//! distribution of visible normals.
//!
//! Closed forms (local frame, z = macro normal, isotropic α):
//! - D(m) = α² / (π ((m.z)²(α² − 1) + 1)²) for m.z > 0 — Walter et al. 2007, "Microfacet
//!   Models for Refraction through Rough Surfaces" (EGSR), eq. 33.
//! - Λ(ω) = (−1 + √(1 + α² tan²θ)) / 2, G1(ω) = 1/(1 + Λ(ω)) — Walter et al. 2007, eq. 34;
//!   Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs"
//!   (JCGT 3(2)), §5 for the Λ form.
//! - G2 height-correlated = 1/(1 + Λ(ωo) + Λ(ωi)) (Heitz 2014, eq. 99); separable
//!   G2 = G1(ωo)·G1(ωi) (Heitz 2014 §6, as Mitsuba's `roughconductor`).
//! - Visible normals D_ωo(m) = G1(ωo)·max(0, ωo·m)·D(m)/ωo.z, sampled exactly by Heitz 2018,
//!   "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)); the reflected direction
//!   ωi = 2(ωo·m)m − ωo then has pdf D_ωo(m)/(4|ωo·m|) (Jacobian: Walter et al. 2007, eq. 14).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | roughness | f32 | — | perceptual, [0, 1]; α = roughness², clamped to ≥ [`MIN_ALPHA`] |

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};
use scenes::Masking;

/// Smallest α used: keeps D finite in f32 (D(z) = 1/(πα²) ≈ 3.2·10⁵) for roughness → 0.
pub const MIN_ALPHA: f32 = 1e-3;

/// Isotropic GGX / Trowbridge-Reitz distribution of microfacet normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    alpha: f32,
}

impl TrowbridgeReitz {
    /// Distribution for perceptual `roughness` ∈ [0, 1]: α = roughness², at least [`MIN_ALPHA`].
    pub fn from_roughness(roughness: f32) -> Self {
        let alpha = roughness * roughness;
        TrowbridgeReitz {
            alpha: if alpha > MIN_ALPHA { alpha } else { MIN_ALPHA },
        }
    }

    /// The width parameter α.
    pub fn alpha(&self) -> f32 {
        self.alpha
    }

    /// Normal distribution D(m) = α²/(π((m.z)²(α² − 1) + 1)²), zero for m.z ≤ 0
    /// (Walter et al. 2007, eq. 33). For unit m the denominator's (m.z)²(α² − 1) + 1 is
    /// evaluated as α²(m.z)² + (m.x)² + (m.y)², which keeps its precision near the pole
    /// (1 − (m.z)² loses all digits there when α is small).
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let t = a2 * m.z * m.z + (m.x * m.x + m.y * m.y);
        a2 / (PI * t * t)
    }

    /// Smith Λ(ω) = (−1 + √(1 + α² tan²θ))/2 (Heitz 2014 §5; Walter et al. 2007, eq. 34),
    /// with tan²θ = ((ω.x)² + (ω.y)²)/(ω.z)² for unit ω.
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 == 0.0 {
            return f32::INFINITY;
        }
        let a2_tan2 = self.alpha * self.alpha * ((w.x * w.x + w.y * w.y) / cos2);
        0.5 * ((1.0 + a2_tan2).sqrt() - 1.0)
    }

    /// Smith masking G1(ω) = 1/(1 + Λ(ω)) for a direction on the upper side.
    #[inline]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Masking-shadowing G2(ωo, ωi) for directions on the upper side: height-correlated
    /// 1/(1 + Λo + Λi) (Heitz 2014, eq. 99) or separable G1(ωo)·G1(ωi) (Heitz 2014 §6).
    #[inline]
    pub fn g2(&self, wo: Vec3, wi: Vec3, masking: Masking) -> f32 {
        match masking {
            Masking::HeightCorrelated => 1.0 / (1.0 + self.lambda(wo) + self.lambda(wi)),
            Masking::Separable => self.g1(wo) * self.g1(wi),
        }
    }

    /// Samples a microfacet normal m from the visible normals D_ωo (Heitz 2018, §3 and
    /// Appendix A), for `wo` with wo.z > 0.
    pub fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        // Stretch ωo to the configuration of the hemisphere (α = 1).
        let vh = Vec3::new(self.alpha * wo.x, self.alpha * wo.y, wo.z).normalize();
        // Orthonormal basis (T1, T2, Vh) around the stretched view direction.
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        let t2 = vh.cross(t1);
        // Uniform point on the disk, then warp its lower half to the projected hemisphere.
        let r = u.x.sqrt();
        let (sin_phi, cos_phi) = (TAU * u.y).sin_cos();
        let p1 = r * cos_phi;
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * sin_phi;
        // Lift onto the hemisphere, then unstretch the normal back to the ellipsoid.
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
        Vec3::new(self.alpha * nh.x, self.alpha * nh.y, nh.z.max(0.0)).normalize()
    }

    /// Density of visible normals D_ωo(m) = G1(ωo)·max(0, ωo·m)·D(m)/ωo.z (Heitz 2018 §2),
    /// for `wo` with wo.z > 0.
    #[inline]
    pub fn visible_normal_pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        let cos_om = wo.dot(m);
        if cos_om <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * cos_om * self.d(m) / wo.z
    }

    /// Solid-angle pdf of the reflected direction ωi = 2(ωo·m)m − ωo when m is drawn by
    /// [`Self::sample_visible`]: D_ωo(m)/(4|ωo·m|) with m the half vector
    /// (Jacobian: Walter et al. 2007, eq. 14). Both directions must be on the upper side.
    #[inline]
    pub fn reflection_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some(m) = half_vector(wo, wi) else {
            return 0.0;
        };
        let cos_om = wo.dot(m);
        if cos_om <= 0.0 {
            return 0.0;
        }
        self.visible_normal_pdf(wo, m) / (4.0 * cos_om)
    }
}

/// Reflection half vector normalize(ωo + ωi) (Walter et al. 2007, eq. 13), or `None` when
/// the two directions are opposite.
#[inline]
pub fn half_vector(wo: Vec3, wi: Vec3) -> Option<Vec3> {
    let h = wo + wi;
    let len2 = h.length_squared();
    if len2 > 0.0 {
        Some(h / len2.sqrt())
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{integrate_sphere, Pcg32};

    /// ∫ D(m) cos θm dωm = 1 (Walter et al. 2007, eq. 4) and ∫ D_ωo(m) dωm = 1 (Heitz 2018 §2),
    /// by adaptive quadrature.
    #[test]
    fn bsdf_microfacet_distributions_are_normalised() {
        for roughness in [0.05f32, 0.3, 0.8, 1.0] {
            let dist = TrowbridgeReitz::from_roughness(roughness);
            let projected = integrate_sphere(&|m| (dist.d(m) * m.z.max(0.0)) as f64);
            assert!(
                (projected - 1.0).abs() < 1e-4,
                "roughness {roughness}: ∫D cos = {projected}, expected 1"
            );
            for theta_deg in [0.0f32, 60.0, 88.0] {
                let (s, c) = theta_deg.to_radians().sin_cos();
                let wo = Vec3::new(s, 0.0, c);
                let visible = integrate_sphere(&|m| dist.visible_normal_pdf(wo, m) as f64);
                assert!(
                    (visible - 1.0).abs() < 1e-4,
                    "roughness {roughness}, θo = {theta_deg}°: ∫D_ωo = {visible}, expected 1"
                );
            }
        }
    }

    /// The visible normal density integrates to one and sampled normals face ωo.
    #[test]
    fn bsdf_microfacet_visible_normals() {
        let mut rng = Pcg32::new(7, 1);
        for roughness in [0.05f32, 0.3, 0.8] {
            let dist = TrowbridgeReitz::from_roughness(roughness);
            for theta_deg in [0.0f32, 45.0, 85.0] {
                let (s, c) = theta_deg.to_radians().sin_cos();
                let wo = Vec3::new(s, 0.0, c);
                for _ in 0..1000 {
                    let m = dist.sample_visible(wo, rng.next_vec2());
                    assert!((m.length() - 1.0).abs() < 1e-4 && m.z >= 0.0, "m = {m}");
                    assert!(wo.dot(m) >= -1e-4, "back-facing visible normal {m} for {wo}");
                }
            }
        }
    }

    /// Height-correlated G2 ≥ separable G2 (Heitz 2014 §6: correlation only removes
    /// double-counted occlusion), equal when one direction is the normal.
    #[test]
    fn bsdf_microfacet_masking_orders() {
        let dist = TrowbridgeReitz::from_roughness(0.6);
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let wi = Vec3::new(-0.28, 0.0, 0.96);
        let hc = dist.g2(wo, wi, Masking::HeightCorrelated);
        let sep = dist.g2(wo, wi, Masking::Separable);
        assert!(hc >= sep, "height-correlated {hc} < separable {sep}");
        let hc = dist.g2(wo, Vec3::Z, Masking::HeightCorrelated);
        let sep = dist.g2(wo, Vec3::Z, Masking::Separable);
        assert!((hc - sep).abs() < 1e-6, "at the normal: {hc} vs {sep}");
    }
}
