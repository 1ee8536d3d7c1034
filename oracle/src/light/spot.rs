//! Spot light with Mitsuba 3's linear falloff.
//!
//! A delta light at `position` pointing along unit `direction` with on-axis intensity I (W/sr).
//! At angle θ from the axis the intensity is I·s(θ) with the falloff of Mitsuba 3's `spot`
//! emitter (Mitsuba 3 documentation, "Spot light source (spot)": "The intensity linearly ramps
//! up from cutoff_angle to beam_width, after which it remains at the maximum value"):
//!
//! s(θ) = 1 for θ ≤ θb;  (θc − θ)/(θc − θb) for θb < θ < θc;  0 for θ ≥ θc.
//!
//! Seen from p at distance r: li = I·s(θ)·T(uv(−ωi))/r² along ωi = (position − p)/r, T = 1
//! unless the spot projects a texture (a cookie: [`scenes::projection`], whose uv(ω) is
//! evaluated exactly at every shading point and the texture bilinearly there). Emitted power
//! Φ = 2π·I·∫₀^π s(θ) sinθ dθ = 2π·I·[1 − (sin θc − sin θb)/(θc − θb)], which tends to
//! 2π·I·(1 − cos θc) as θb → θc (integrating the ramp by parts; the same quantity as pbrt-v4
//! §12.2.1 SpotLight::Phi, there for a smoothstep falloff).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | `position` | point | — | m |
//! | `direction` | unit vector, the axis the spot points along | — | — |
//! | `intensity` | RGB, finite, ≥ 0 | — | W/sr |
//! | `cutoff_deg` θc | f32 ∈ (0, 90] | — | degrees |
//! | `beam_width_deg` θb | f32 ∈ [0, θc] | — | degrees |
//! | projection | texture T, up (optional) | none | — |

use std::f32::consts::TAU;

use glam::Vec3;
use scenes::Rgb;

use glam::Vec2;

use super::radiance::{average, check_direction, check_rgb, check_vec, is_black, Radiance};
use super::LightSample;

/// Spot light with linear-in-angle falloff.
#[derive(Clone, Debug)]
pub struct SpotLight {
    /// Position.
    pub position: Vec3,
    /// Unit axis.
    pub direction: Vec3,
    /// On-axis radiant intensity, W/sr.
    pub intensity: Rgb,
    /// θc in radians.
    cutoff: f32,
    /// θb in radians.
    beam: f32,
    /// cos θc.
    cos_cutoff: f32,
    /// cos θb.
    cos_beam: f32,
    /// The projected texture, the light's right and image-up axes and tan θc.
    projection: Option<(Radiance, (Vec3, Vec3), f32)>,
}

impl SpotLight {
    /// Checks the inputs (angles in degrees: 0 < cutoff ≤ 90, 0 ≤ beam width ≤ cutoff).
    pub fn new(
        position: Vec3,
        direction: Vec3,
        intensity: Rgb,
        cutoff_deg: f32,
        beam_width_deg: f32,
    ) -> Result<Self, String> {
        check_vec("position", position)?;
        let direction = check_direction("direction", direction)?;
        check_rgb("intensity", intensity)?;
        if !(cutoff_deg > 0.0 && cutoff_deg <= 90.0) {
            return Err(format!("cutoff_deg = {cutoff_deg} must be in (0, 90]"));
        }
        if !(beam_width_deg >= 0.0 && beam_width_deg <= cutoff_deg) {
            return Err(format!(
                "beam_width_deg = {beam_width_deg} must be in [0, cutoff_deg = {cutoff_deg}]"
            ));
        }
        let (cutoff, beam) = (cutoff_deg.to_radians(), beam_width_deg.to_radians());
        Ok(SpotLight {
            position,
            direction,
            intensity,
            cutoff,
            beam,
            cos_cutoff: cutoff.cos(),
            cos_beam: beam.cos(),
            projection: None,
        })
    }

    /// The same spot projecting `texture` with the image's `up` ([`scenes::projection`]).
    pub fn projecting(mut self, texture: Radiance, up: Vec3) -> Result<Self, String> {
        let frame = scenes::projection::frame(self.direction, up)
            .ok_or_else(|| format!("up = {up} is along the spot's axis {}", self.direction))?;
        self.projection = Some((texture, frame, self.cutoff.tan()));
        Ok(self)
    }

    /// T(uv(d)) for the unit direction `d` leaving the light (1 without a projection).
    fn projected(&self, d: Vec3) -> Rgb {
        match &self.projection {
            None => Vec3::ONE,
            Some((texture, frame, tan)) => scenes::projection::uv(self.direction, *frame, *tan, d)
                .map_or(Vec3::ZERO, |uv: Vec2| texture.eval(uv)),
        }
    }

    /// Falloff s(θ) for the unit direction `d` leaving the light.
    pub fn falloff(&self, d: Vec3) -> f32 {
        let cos_theta = self.direction.dot(d);
        if cos_theta >= self.cos_beam || (cos_theta > self.cos_cutoff && self.cutoff <= self.beam) {
            1.0
        } else if cos_theta > self.cos_cutoff {
            ((self.cutoff - cos_theta.acos()) / (self.cutoff - self.beam)).clamp(0.0, 1.0)
        } else {
            // Outside the cutoff cone (or a NaN direction).
            0.0
        }
    }

    /// The one direction towards the light with li = I·s(θ)/r²; `None` outside the cone or at
    /// the light's position.
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        let d = self.position - p;
        let r2 = d.length_squared();
        if !(r2 > 0.0 && r2.is_finite()) {
            return None;
        }
        let dist = r2.sqrt();
        let wi = d / dist;
        let li = self.intensity * self.projected(-wi) * (self.falloff(-wi) / r2);
        if is_black(li) {
            return None;
        }
        Some(LightSample {
            wi,
            dist,
            li,
            pdf: 1.0,
            delta: true,
        })
    }

    /// Φ = 2π·I·[1 − (sin θc − sin θb)/(θc − θb)] (channel average), times the projected
    /// texture's mean (an estimate for light selection: the texels' mean, not their mean over
    /// the solid angle).
    pub fn power(&self) -> f32 {
        // (sin θc − sin θb)/(θc − θb) = cos m · sin h / h with m = (θc + θb)/2, h = (θc − θb)/2
        // (sum-to-product), which stays exact as the ramp vanishes.
        let (m, h) = (0.5 * (self.cutoff + self.beam), 0.5 * (self.cutoff - self.beam));
        let sinc = if h > 1e-3 { h.sin() / h } else { 1.0 - h * h / 6.0 };
        let solid = 1.0 - m.cos() * sinc;
        let mean = self
            .projection
            .as_ref()
            .map_or(Vec3::ONE, |(texture, _, _)| texture.mean());
        TAU * average(self.intensity * mean) * solid
    }
}

#[cfg(test)]
mod tests {
    use std::f32::consts::PI;

    use super::*;
    use crate::frame::Frame;

    fn spot() -> SpotLight {
        // At the origin, pointing down −Y; beam 20°, cutoff 40°.
        SpotLight::new(Vec3::ZERO, -Vec3::Y, Vec3::new(10.0, 5.0, 1.0), 40.0, 20.0).unwrap()
    }

    #[test]
    fn spot_light_irradiance_inside_ramp_and_outside() {
        let light = spot();
        let h = 2.0f32;
        // Receivers on the plane y = −h facing up, at polar angle θ from the axis.
        for (theta_deg, falloff) in [
            (0.0f32, 1.0f32),
            (15.0, 1.0),
            (30.0, 0.5),
            (35.0, 0.25),
            (45.0, 0.0),
        ] {
            let theta = theta_deg.to_radians();
            let p = Vec3::new(h * theta.tan(), -h, 0.0);
            let r2 = p.length_squared();
            let want = 10.0 * falloff * theta.cos() / r2;
            let got = light
                .sample_li(p)
                .map_or(0.0, |s| s.li.x * s.wi.dot(Vec3::Y) / s.pdf);
            assert!(
                (got - want).abs() <= 1e-5 * want.max(1e-3),
                "θ = {theta_deg}°: E = {got}, expected {want}"
            );
        }
    }

    #[test]
    fn spot_light_power_matches_integrated_intensity() {
        // Midpoint quadrature of Φ = ∫ I·s(θ) dω over the sphere, pbrt's TEST(SpotLight, Power).
        for (cutoff, beam) in [(40.0f32, 20.0f32), (90.0, 0.0), (30.0, 30.0), (10.0, 9.99)] {
            let light = SpotLight::new(Vec3::ZERO, Vec3::Z, Vec3::ONE, cutoff, beam).unwrap();
            let frame = Frame::from_normal(Vec3::Z);
            let n = 20_000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let theta = (i as f32 + 0.5) / n as f32 * PI;
                let d = frame.to_world(Vec3::new(theta.sin(), 0.0, theta.cos()));
                sum += (light.falloff(d) * theta.sin()) as f64;
            }
            let want = (TAU as f64 * sum * (PI as f64 / n as f64)) as f32;
            let got = light.power();
            assert!(
                (got - want).abs() < 2e-3 * want,
                "cutoff {cutoff}°, beam {beam}°: Φ = {got}, quadrature {want}"
            );
        }
    }

    /// A 2×2 cookie (top-left 1, top-right 2, bottom-left 3, bottom-right 4, clamped) on a
    /// spot pointing down −Z with up +Y: the image stands upright behind the light, its texel
    /// centres at uv (¼, ¼) … (¾, ¾), i.e. tan(direction) = ±½·tan θc right and up.
    #[test]
    fn a_projected_texture_multiplies_the_intensity_upright_behind_the_light() {
        use scenes::texture::{Texture, WrapMode};
        use std::sync::Arc;
        let texels = [1.0, 2.0, 3.0, 4.0]
            .map(|v| glam::Vec4::new(v, v, v, 1.0))
            .to_vec();
        let texture = Arc::new(Texture::from_texels(2, 2, texels, [WrapMode::Clamp; 2]));
        let image = Radiance::Image {
            texture,
            factor: Vec3::new(1.0, 0.5, 0.25),
        };
        let spot = SpotLight::new(Vec3::ZERO, -Vec3::Z, Vec3::splat(2.0), 40.0, 40.0)
            .unwrap()
            .projecting(image, Vec3::Y)
            .unwrap();
        let t = 0.5 * 40f32.to_radians().tan();
        for (x, y, texel) in [(-t, t, 1.0), (t, t, 2.0), (-t, -t, 3.0), (t, -t, 4.0)] {
            let p = Vec3::new(x, y, -1.0) * 3.0;
            let s = spot.sample_li(p).unwrap();
            let want = Vec3::new(1.0, 0.5, 0.25) * (2.0 * texel / p.length_squared());
            assert!(
                (s.li - want).length() < 1e-5 * want.length(),
                "({x}, {y}): {} vs {want}",
                s.li
            );
        }
        // Along the axis: the mean of the four texels (bilinear at the centre).
        let s = spot.sample_li(-Vec3::Z).unwrap();
        assert!((s.li.x - 2.0 * 2.5).abs() < 1e-5, "{}", s.li);
        assert!(SpotLight::new(Vec3::ZERO, Vec3::Y, Vec3::ONE, 30.0, 10.0)
            .unwrap()
            .projecting(Radiance::Constant(Vec3::ONE), Vec3::Y)
            .is_err());
    }

    #[test]
    fn spot_light_rejects_bad_angles() {
        let e = SpotLight::new(Vec3::ZERO, Vec3::Z, Vec3::ONE, 30.0, 40.0).unwrap_err();
        assert!(e.contains("beam_width_deg"), "{e}");
        let e = SpotLight::new(Vec3::ZERO, Vec3::ZERO, Vec3::ONE, 30.0, 10.0).unwrap_err();
        assert!(e.contains("direction"), "{e}");
        let e = SpotLight::new(Vec3::ZERO, Vec3::Z, Vec3::ONE, f32::NAN, 10.0).unwrap_err();
        assert!(e.contains("cutoff_deg"), "{e}");
    }
}
