//! Distance impostors: environment-mapped reflections and refractions localized by the
//! distance each cube texel's surface lies from the capture point, and their parameters.
//!
//! The radiance cube of [`crate::envmap`] also holds, in its alpha channel, the distance
//! |l′| from the capture point o to the surface seen through each texel (the background:
//! 65504, the largest f16, "infinitely far"). A reflected or refracted ray x + R·t from the
//! shading point x (relative to o) then finds the texel its hit lies in, instead of the
//! plain map's texel along R, which is right only for x = o or an infinitely distant
//! environment (`shaders/distance_impostor.wgsl`).
//!
//! | method | search (`Localization`) | parameters (default) |
//! |---|---|---|
//! | `distance_impostor` | Szirmay-Kalos, Aszódi, Lazányi & Premecz 2005, "Approximate Ray-Tracing on the GPU with Distance Impostors", CGF 24(3): k fixed-point iterations | `iterations` (1: 0..=64) |
//! | `distance_search` | Umenhoffer, Patow & Szirmay-Kalos 2007, "Robust Multiple Specular Reflections and Refractions", GPU Gems 3 ch. 17: linear search, then secant refinement | `linear_steps` (16: 1..=256), `secant_steps` (4: 0..=64), `layers` (1: 1..=4) |
//!
//! Both are `envmap_cube` (every common environment-mapping parameter) with the localized
//! lookup for mirror and dielectric reflectors, and take `double_refraction` (`off`: a
//! dielectric's refracted ray looks up the environment from its entry point, the first
//! interface only; `on`: the refracted ray is traced through the refractor to its exit by
//! the same search in the refractor's own distance map, which holds its outward normal and
//! the distance from its centre, refracted out and then localized in the environment's map:
//! the 2005 paper's "map for each refractor surface", GPU Gems 3 §17.3). Glossy and diffuse
//! lobes read the maps as `envmap_cube` does.
//!
//! **The iteration** (2005): the hit of x + R·t is approximated by assuming the surface lies
//! on the sphere about o through the last looked-up surface point. Start with the plain
//! lookup l′₀ = |l′(R)|; step k intersects the ray with the sphere of radius |l′ₖ|,
//! |x + R·t| = |l′ₖ|, t = −x·R + √((x·R)² − |x|² + |l′ₖ|²), and looks up the distance along
//! the new point's direction. `iterations = 0` is the plain cube map; 1 is the paper's
//! distance impostor (one distance fetch, then the radiance fetch at the localized
//! direction); each further iteration adds one fetch. The stored text of the 2005 paper was
//! not available to this project; this rule is the one whose fixed points are exactly the
//! ray's intersections with the stored surface (|x + R·t| = |l′| along x + R·t), which is
//! how the paper's abstract and GPU Gems 3 §17.2 describe it. It converges where the surface
//! is locally close to a sphere about o (large faces seen head-on) and oscillates or jumps
//! across depth discontinuities: the study's lower bounds.
//!
//! **The search** (GPU Gems 3 §17.2): the ray is marched so that no crossing of the stored
//! surface is missed, then refined by the secant method. Ray points are parameterized by
//! u ∈ [0, 1], t(u) = |x|·u/(1 − u) (u = 1: the point at infinity along R, whose direction is
//! R itself), and compared with the surface by g(u) = 1/|x + R·t(u)| − 1/|l′|: positive in
//! front of the stored surface, negative behind it, finite at u = 1. The linear search
//! samples u = i/`linear_steps` and stops at the first sign change; each secant step
//! replaces one end of the bracket by the root of the line through (u, g) at both ends.
//! Inverse distances keep g finite at infinity and are what GPU Gems 3 interpolates when it
//! marches in the cube map's texel space between the ray's start and end points (our u plays
//! the role of that texel-space parameter). Failure mode: a crossing thinner than one linear
//! step is missed (thin objects), and anything the capture point does not see is solid
//! behind its stored surface (hidden surfaces, depth discontinuities).
//!
//! **Layered distance maps** (GPU Gems 3 §17.2, `layers` > 1): the capture is repeated
//! `layers` − 1 times with depth peeling (Everitt 2001: each pass discards what lies no
//! further than the previous layer's surface), so layer k holds the (k+1)-th surface along
//! every direction from o. Along a direction the surfaces of closed objects alternate entry
//! and exit, so a ray point behind an odd number of stored surfaces is inside something; the
//! layered search marches as above but stops at the first sample inside something (or behind
//! every layer: what the map could not keep is solid, as in one layer), and refines by the
//! secant method on the layer it entered. Each linear step fetches every layer. Failure mode:
//! directions with more surfaces than layers, and open surfaces (a lone rectangle seen edge
//! on), for which the parity is wrong. The chapter's own formulation was not available here;
//! this is our reading of its description.

use crate::envmap::EnvMapping;

/// Largest `iterations`.
pub const MAX_ITERATIONS: u32 = 64;
/// Largest `linear_steps`.
pub const MAX_LINEAR_STEPS: u32 = 256;
/// Largest `secant_steps`.
pub const MAX_SECANT_STEPS: u32 = 64;
/// Largest `layers` (distance-map layers of `distance_search`).
pub const MAX_DISTANCE_LAYERS: u32 = 4;

/// Every distance-impostor method name.
pub const DISTANCE_IMPOSTOR_NAMES: [&str; 2] = ["distance_impostor", "distance_search"];

/// How the lookup direction of a mirror or dielectric reflector is found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Localization {
    /// The direction alone: the environment infinitely far (classic environment mapping).
    Distant,
    /// Szirmay-Kalos et al. 2005: this many fixed-point iterations (0: the plain lookup).
    Iterations(u32),
    /// GPU Gems 3 ch. 17: a linear search of this many steps, then this many secant steps.
    Search {
        /// Samples of the linear search.
        linear_steps: u32,
        /// Secant refinements of the bracket found.
        secant_steps: u32,
        /// Depth-peeled layers of the environment's distance map (1: the radiance cube alone).
        layers: u32,
    },
}

impl Localization {
    /// The method name of a localized cube map, None for `Distant`.
    pub fn name(self) -> Option<&'static str> {
        match self {
            Localization::Distant => None,
            Localization::Iterations(_) => Some(DISTANCE_IMPOSTOR_NAMES[0]),
            Localization::Search { .. } => Some(DISTANCE_IMPOSTOR_NAMES[1]),
        }
    }

    /// The method `name` with its defaults (None: not a distance-impostor method).
    pub fn by_name(name: &str) -> Option<Localization> {
        match name {
            "distance_impostor" => Some(Localization::Iterations(1)),
            "distance_search" => Some(Localization::Search {
                linear_steps: 16,
                secant_steps: 4,
                layers: 1,
            }),
            _ => None,
        }
    }

    /// `DistanceUniforms.info` of distance_impostor.wgsl: (mode, iterations or linear steps,
    /// secant steps, double refraction) — mode 0 distant, 1 iterations, 2 search.
    pub(crate) fn shader_info(self, double_refraction: bool) -> [u32; 4] {
        let d = u32::from(double_refraction);
        match self {
            Localization::Distant => [0, 0, 0, d],
            Localization::Iterations(k) => [1, k, 0, d],
            Localization::Search {
                linear_steps,
                secant_steps,
                ..
            } => [2, linear_steps, secant_steps, d],
        }
    }

    /// Layers of the environment's distance map: `layers` of a search, 1 otherwise.
    pub fn distance_layers(self) -> u32 {
        match self {
            Localization::Search { layers, .. } => layers,
            _ => 1,
        }
    }

    /// Its parameter names.
    pub(crate) fn param_names(self) -> &'static [&'static str] {
        match self {
            Localization::Distant => &[],
            Localization::Iterations(_) => &["iterations", "double_refraction"],
            Localization::Search { .. } => &["linear_steps", "secant_steps", "layers", "double_refraction"],
        }
    }

    /// Sets `key` (not `double_refraction`) from `value`; None if refused.
    pub(crate) fn set(&mut self, key: &str, value: &str) -> Option<()> {
        let v: u32 = value.parse().ok()?;
        match (key, self) {
            ("iterations", Localization::Iterations(k)) => *k = (v <= MAX_ITERATIONS).then_some(v)?,
            ("linear_steps", Localization::Search { linear_steps, .. }) => {
                *linear_steps = (1..=MAX_LINEAR_STEPS).contains(&v).then_some(v)?
            }
            ("secant_steps", Localization::Search { secant_steps, .. }) => {
                *secant_steps = (v <= MAX_SECANT_STEPS).then_some(v)?
            }
            ("layers", Localization::Search { layers, .. }) => {
                *layers = (1..=MAX_DISTANCE_LAYERS).contains(&v).then_some(v)?
            }
            _ => return None,
        }
        Some(())
    }

    /// Its parameters as `k=v` pairs, `double_refraction` included.
    pub(crate) fn params(self, e: &EnvMapping) -> Vec<(&'static str, String)> {
        let on_off = if e.double_refraction { "on" } else { "off" }.to_string();
        match self {
            Localization::Distant => Vec::new(),
            Localization::Iterations(k) => {
                vec![("iterations", k.to_string()), ("double_refraction", on_off)]
            }
            Localization::Search {
                linear_steps,
                secant_steps,
                layers,
            } => vec![
                ("linear_steps", linear_steps.to_string()),
                ("secant_steps", secant_steps.to_string()),
                ("layers", layers.to_string()),
                ("double_refraction", on_off),
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sphere iteration of the module docs, on the CPU, for a capture point o = 0 above a
    /// floor plane y = −1 (|l′(ω)| = 1/(−ω_y)): it must converge to the ray's true hit.
    #[test]
    fn sphere_iteration_converges_on_a_plane() {
        use glam::Vec3;
        let distance = |w: Vec3| if w.y < 0.0 { -1.0 / w.y } else { f32::INFINITY };
        let x = Vec3::new(0.3, -0.2, 0.1);
        let r = Vec3::new(0.6, -1.0, 0.2).normalize();
        let exact = (-1.0 - x.y) / r.y;
        let mut l = distance(r);
        let mut errors = Vec::new();
        for _ in 0..8 {
            let b = x.dot(r);
            let t = -b + (b * b - x.length_squared() + l * l).max(0.0).sqrt();
            errors.push((t - exact).abs());
            l = distance((x + r * t).normalize());
        }
        assert!(errors[0] > 0.05, "the first guess should be off: {errors:?}");
        assert!(errors[7] < 1e-3 * exact, "no convergence: {errors:?}");
        assert!(
            errors.windows(2).all(|w| w[1] <= w[0] + 1e-6),
            "not monotone: {errors:?}"
        );
    }

    #[test]
    fn parameters_round_trip() {
        let mut s = Localization::by_name("distance_search").unwrap();
        s.set("linear_steps", "64").unwrap();
        s.set("secant_steps", "0").unwrap();
        s.set("layers", "3").unwrap();
        assert_eq!(
            s,
            Localization::Search {
                linear_steps: 64,
                secant_steps: 0,
                layers: 3
            }
        );
        assert_eq!(s.distance_layers(), 3);
        assert!(s.set("linear_steps", "0").is_none());
        assert!(s.set("layers", "0").is_none());
        assert!(s.set("layers", "5").is_none());
        assert!(s.set("iterations", "2").is_none());
        let mut i = Localization::by_name("distance_impostor").unwrap();
        assert!(i.set("iterations", "65").is_none());
        assert!(i.set("layers", "2").is_none(), "layers are the search's");
        i.set("iterations", "0").unwrap();
        assert_eq!(i.shader_info(true), [1, 0, 0, 1]);
    }
}
