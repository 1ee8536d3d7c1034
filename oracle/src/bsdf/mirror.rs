//! Ideal specular reflection.
//!
//! f(ωo, ωi) = R·δ(ωi − ωr)/|cos θi| with ωr = (−ωo.x, −ωo.y, ωo.z), so eval = pdf = 0 and
//! `sample` returns ωr with weight R, discrete probability 1, `delta` set. Two-sided (ωr
//! stays on ωo's side).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | reflectance R | RGB | — | [0, 1] |
//!
//! Law of reflection; as Mitsuba 3's `conductor` with `material="none"` scaled by R.

use glam::Vec3;
use scenes::Rgb;

use super::{sanitize_rgb, BsdfSample};

/// Ideal mirror with reflectance R.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    reflectance: Rgb,
}

impl Mirror {
    /// Mirror; negative or NaN channels become 0.
    pub fn new(reflectance: Rgb) -> Self {
        Mirror {
            reflectance: sanitize_rgb(reflectance),
        }
    }

    /// Zero: the lobe is a Dirac delta.
    pub fn eval(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        Rgb::ZERO
    }

    /// The mirror direction (−ωo.x, −ωo.y, ωo.z) with weight R; `None` at grazing ωo.
    pub fn sample(&self, wo: Vec3) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: self.reflectance,
            pdf: 1.0,
            delta: true,
            eta: 1.0,
        })
    }

    /// Zero: the lobe is a Dirac delta.
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    /// Always a delta.
    pub fn is_delta(&self) -> bool {
        true
    }

    /// R.
    pub fn albedo(&self) -> Rgb {
        self.reflectance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::Bsdf;
    use glam::Vec2;

    #[test]
    fn bsdf_mirror_direction_is_exact() {
        let bsdf = Bsdf::Mirror(Mirror::new(Rgb::new(0.9, 0.5, 0.1)));
        assert!(bsdf.is_delta());
        for wo in [
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::new(-0.48, 0.64, 0.6),
            Vec3::new(0.0, 0.6, -0.8),
            Vec3::Z,
        ] {
            let s = bsdf.sample(wo, 0.3, Vec2::new(0.2, 0.7)).expect("mirror sample");
            let expected = Vec3::new(-wo.x, -wo.y, wo.z);
            assert_eq!(s.wi, expected, "mirror of {wo}");
            // Angle of reflection equals angle of incidence and ωo + ωi is along the normal.
            let h = wo + s.wi;
            assert!(h.x == 0.0 && h.y == 0.0, "ωo + ωi = {h} not along z");
            assert_eq!(
                (s.weight, s.pdf, s.delta, s.eta),
                (Rgb::new(0.9, 0.5, 0.1), 1.0, true, 1.0)
            );
            assert_eq!(bsdf.eval(wo, s.wi), Rgb::ZERO);
            assert_eq!(bsdf.pdf(wo, s.wi), 0.0);
        }
        assert!(
            bsdf.sample(Vec3::X, 0.5, Vec2::splat(0.5)).is_none(),
            "grazing ωo"
        );
        assert_eq!(bsdf.albedo(), Rgb::new(0.9, 0.5, 0.1));
    }
}
