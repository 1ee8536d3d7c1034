//! Lights (docs/ARCHITECTURE.md "Lights", "Environment map"): one closed set of emitters, one file per
//! kind, and which of a scene's emitters next-event estimation picks (`selection`).
//!
//! | kind | file | delta | sampled by |
//! |---|---|---|---|
//! | point | [`point`] | yes | — |
//! | spot (Mitsuba falloff) | [`spot`] | yes | — |
//! | directional / sun disk | [`directional`] | if diameter = 0 | uniform cone |
//! | rectangle | [`rectangle`] | no | solid angle (Ureña et al. 2013) |
//! | disk | [`disk`] | no | area |
//! | sphere | [`sphere`] | no | cone (outside), area (inside) |
//! | emissive mesh | [`mesh`] | no | area |
//! | environment | [`environment`] | no | uniform sphere / 2D luminance distribution |
//!
//! Conventions shared by every kind: `sample_li(p, u)` returns a unit direction ωi towards the
//! light, the distance to the sampled point (∞ for distant lights), the incident radiance
//! (intensity/r² or irradiance for delta lights) and the solid-angle pdf of ωi (1 for delta
//! lights), or `None` when the light sends nothing to p (behind a one-sided emitter, outside a
//! spot's cone, a zero-radiance sample). `pdf_li` is the density of the directions `sample_li`
//! returns, so the two agree for every sampled direction (MIS relies on it; the tests check it).
//! Area emitters are one-sided unless `two_sided`: the front is the side the geometric normal
//! points to, and callers pass the un-flipped geometric normal.

pub mod directional;
pub mod disk;
pub mod distribution;
pub mod environment;
pub mod mesh;
pub mod point;
pub mod radiance;
pub mod rectangle;
pub mod selection;
mod set;
pub mod sphere;
pub mod spot;

#[cfg(test)]
mod test_support;

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};
use scenes::Rgb;

pub use set::LightSet;

/// One direction sampled towards a light from a shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// Distance to the sampled point; `f32::INFINITY` for distant lights.
    pub dist: f32,
    /// Incident radiance (area, environment, sun disk), or intensity/r² (point, spot), or
    /// irradiance (delta directional).
    pub li: Rgb,
    /// Solid-angle pdf of `wi`, not including the light-selection probability; 1 for delta
    /// lights.
    pub pdf: f32,
    /// The light is a delta light (no other strategy can find it).
    pub delta: bool,
}

/// The closed set of emitters.
#[derive(Clone, Debug)]
pub enum Emitter {
    /// Isotropic point light.
    Point(point::PointLight),
    /// Spot light with Mitsuba's falloff.
    Spot(spot::SpotLight),
    /// Distant light, delta or sun disk.
    Directional(directional::DirectionalLight),
    /// Rectangular area light.
    Rectangle(rectangle::RectangleLight),
    /// Disk area light.
    Disk(disk::DiskLight),
    /// Spherical area light.
    Sphere(sphere::SphereLight),
    /// Emissive triangle mesh.
    Mesh(mesh::MeshLight),
    /// Distant environment.
    Environment(environment::EnvironmentLight),
}

impl Emitter {
    /// True for emitters on a convex shape (rectangle, disk, sphere): no point of the shape
    /// receives light from the shape itself (every chord leaves a convex surface on its back
    /// side, and a planar emitter's integrand vanishes in its plane), so the light is never
    /// sampled from its own surface, where solid-angle sampling is degenerate.
    pub fn is_convex_shape(&self) -> bool {
        matches!(
            self,
            Emitter::Rectangle(_) | Emitter::Disk(_) | Emitter::Sphere(_)
        )
    }

    /// Sample a direction towards the light from `p` with the 2D sample `u`.
    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        match self {
            Emitter::Point(l) => l.sample_li(p),
            Emitter::Spot(l) => l.sample_li(p),
            Emitter::Directional(l) => l.sample_li(u),
            Emitter::Rectangle(l) => l.sample_li(p, u),
            Emitter::Disk(l) => l.sample_li(p, u),
            Emitter::Sphere(l) => l.sample_li(p, u),
            Emitter::Mesh(l) => l.sample_li(p, u),
            Emitter::Environment(l) => l.sample_li(u),
        }
    }

    /// Solid-angle pdf that [`Emitter::sample_li`] from `p` yields direction `wi` hitting the
    /// light at `p_light` with geometric normal `n_light` (area emitters); for distant emitters
    /// `p_light`/`n_light` are ignored. 0 for delta lights.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, p_light: Vec3, n_light: Vec3) -> f32 {
        match self {
            Emitter::Point(_) | Emitter::Spot(_) => 0.0,
            Emitter::Directional(l) => l.pdf_li(wi),
            Emitter::Rectangle(l) => l.pdf_li(p, wi, p_light),
            Emitter::Disk(l) => l.pdf_li(p, wi, p_light),
            Emitter::Sphere(l) => l.pdf_li(p, wi, p_light, n_light),
            Emitter::Mesh(l) => l.pdf_li(p, wi, p_light, n_light),
            Emitter::Environment(l) => l.pdf_li(wi),
        }
    }

    /// Radiance leaving an area emitter at a surface point with geometric normal `n` and
    /// texture coordinate `uv` towards the unit direction `wo` (away from the light); zero on
    /// the back of one-sided emitters and for every non-area emitter.
    pub fn emitted(&self, n: Vec3, uv: Vec2, wo: Vec3) -> Rgb {
        match self {
            Emitter::Rectangle(l) => l.emitted(n, uv, wo),
            Emitter::Disk(l) => l.emitted(n, uv, wo),
            Emitter::Sphere(l) => l.emitted(n, uv, wo),
            Emitter::Mesh(l) => l.emitted(n, uv, wo),
            Emitter::Point(_) | Emitter::Spot(_) | Emitter::Directional(_) | Emitter::Environment(_) => {
                Rgb::ZERO
            }
        }
    }

    /// Radiance arriving from the distant direction `dir` (unit, pointing away from the scene):
    /// the environment, or a sun disk inside its cone; zero for every other emitter.
    pub fn radiance_from_direction(&self, dir: Vec3) -> Rgb {
        match self {
            Emitter::Directional(l) => l.radiance_from_direction(dir),
            Emitter::Environment(l) => l.radiance_from_direction(dir),
            _ => Rgb::ZERO,
        }
    }

    /// [`Emitter::radiance_from_direction`] and the [`Emitter::pdf_li`] of that direction for a
    /// distant emitter, computed together where they share work (an environment map's texture
    /// coordinates); the same values bit for bit. (0, 0) for every other emitter.
    pub fn radiance_and_pdf_from_direction(&self, dir: Vec3) -> (Rgb, f32) {
        match self {
            Emitter::Directional(l) => (l.radiance_from_direction(dir), l.pdf_li(dir)),
            Emitter::Environment(l) => l.radiance_and_pdf(dir),
            _ => (Rgb::ZERO, 0.0),
        }
    }

    /// True for lights only a light sample can find (point, spot, zero-diameter directional).
    pub fn is_delta(&self) -> bool {
        match self {
            Emitter::Point(_) | Emitter::Spot(_) => true,
            Emitter::Directional(l) => l.is_delta(),
            _ => false,
        }
    }

    /// Approximate emitted power in W (channel average), for light selection: the `Phi` of
    /// pbrt-v4's point, spot, distant, area and infinite lights (§12.2–12.5); distant lights use
    /// the scene's bounding-sphere radius.
    pub fn power(&self) -> f32 {
        match self {
            Emitter::Point(l) => l.power(),
            Emitter::Spot(l) => l.power(),
            Emitter::Directional(l) => l.power(),
            Emitter::Rectangle(l) => l.power(),
            Emitter::Disk(l) => l.power(),
            Emitter::Sphere(l) => l.power(),
            Emitter::Mesh(l) => l.power(),
            Emitter::Environment(l) => l.power(),
        }
    }
}

/// Uniform direction in the cone of half-angle θmax about +Z, parametrised by
/// h = 1 − cosθmax: returns (cosθ, sin²θ, φ). 1 − cosθ = u.x·h is uniform on [0, h], which is
/// pbrt-v4's SampleUniformCone (§A.5.4) written so that tiny cones (a 0.5° sun, a distant
/// sphere) keep full precision; pdf = 1/(2πh).
pub(crate) fn sample_cone(u: Vec2, h: f32) -> (f32, f32, f32) {
    let one_minus_cos = u.x * h;
    (
        1.0 - one_minus_cos,
        one_minus_cos * (2.0 - one_minus_cos),
        TAU * u.y,
    )
}
