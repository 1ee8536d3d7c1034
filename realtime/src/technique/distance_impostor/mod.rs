//! Distance impostors: environment-mapped reflections and refractions localized by the
//! distance each cube texel's surface lies from the capture point, and their parameters.
//!
//! The radiance cube of [`super::envmap`] also holds, in its alpha channel, the distance
//! |l′| from the capture point o to the surface seen through each texel (the background:
//! 65504, the largest f16, "infinitely far"). A reflected or refracted ray x + R·t from the
//! shading point x (relative to o) then finds the texel its hit lies in, instead of the
//! plain map's texel along R, which is right only for x = o or an infinitely distant
//! environment (`technique/distance_impostor/lookup.wgsl`).
//!
//! The methods, their papers and their parameters with ranges and defaults are [`METHODS`]
//! (docs/methods.md is made from it).
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

use super::envmap::localization::{
    Localization, MAX_DISTANCE_LAYERS, MAX_ITERATIONS, MAX_LINEAR_STEPS, MAX_SECANT_STEPS,
};
use super::envmap::{self, EnvMapping, Parameterization};
use super::method::{Family, Method, MethodInfo, Override, Row, Settings};
use super::param::{Kind, MethodSpec, Param, Value};

/// `double_refraction`, a row of both methods.
const DOUBLE_REFRACTION: Param<EnvMapping> = Param {
    name: "double_refraction",
    kind: Kind::Switch,
    unit: "",
    doc: "trace a dielectric's refracted ray through the refractor's own distance map to its exit \
          (off: the first interface only)",
    source: "Szirmay-Kalos et al. 2005 (a map for each refractor surface); GPU Gems 3 §17.3",
    unset: "",
    get: |e| Some(Value::Switch(e.double_refraction)),
    set: |e, v| {
        e.double_refraction = v.switch()?;
        Some(())
    },
};

/// The search parameters of `distance_search`, read and written by name.
/// `distance_search`'s own parameters (linear_steps, secant_steps, layers), None for another
/// localization.
fn search(l: &mut Localization) -> Option<(&mut u32, &mut u32, &mut u32)> {
    match l {
        Localization::Search {
            linear_steps,
            secant_steps,
            layers,
        } => Some((linear_steps, secant_steps, layers)),
        _ => None,
    }
}

/// The distance-impostor methods: `envmap_cube` with [`Localization`] other than `Distant`,
/// after every environment-mapping parameter ([`super::envmap::COMMON`]).
pub static METHODS: &[MethodSpec<EnvMapping>] = &[
    MethodSpec {
        name: "distance_impostor",
        summary: "k fixed-point iterations on the sphere through the last looked-up distance",
        source: "Szirmay-Kalos, Aszódi, Lazányi & Premecz 2005, \"Approximate Ray-Tracing on the GPU \
                 with Distance Impostors\", CGF 24(3)",
        default: || EnvMapping {
            localization: Localization::Iterations(1),
            ..EnvMapping::new(Parameterization::Cube)
        },
        params: &[
            Param {
                name: "iterations",
                kind: Kind::Whole(0, MAX_ITERATIONS),
                unit: "",
                doc: "fixed-point iterations, one distance fetch each (0: the plain cube map)",
                source: "",
                unset: "",
                get: |e| match e.localization {
                    Localization::Iterations(k) => Some(Value::Whole(k)),
                    _ => None,
                },
                set: |e, v| match &mut e.localization {
                    Localization::Iterations(k) => {
                        *k = v.whole()?;
                        Some(())
                    }
                    _ => None,
                },
            },
            DOUBLE_REFRACTION,
        ],
    },
    MethodSpec {
        name: "distance_search",
        summary: "linear search for the first crossing of the stored surface, then secant refinement",
        source: "Umenhoffer, Patow & Szirmay-Kalos 2007, \"Robust Multiple Specular Reflections and \
                 Refractions\", GPU Gems 3 ch. 17",
        default: || EnvMapping {
            localization: Localization::Search {
                linear_steps: 16,
                secant_steps: 4,
                layers: 1,
            },
            ..EnvMapping::new(Parameterization::Cube)
        },
        params: &[
            Param {
                name: "linear_steps",
                kind: Kind::Whole(1, MAX_LINEAR_STEPS),
                unit: "",
                doc: "samples of the linear search (each fetches every layer)",
                source: "",
                unset: "",
                get: |e| search(&mut e.localization.clone()).map(|s| Value::Whole(*s.0)),
                set: |e, v| {
                    *search(&mut e.localization)?.0 = v.whole()?;
                    Some(())
                },
            },
            Param {
                name: "secant_steps",
                kind: Kind::Whole(0, MAX_SECANT_STEPS),
                unit: "",
                doc: "secant refinements of the bracket found",
                source: "",
                unset: "",
                get: |e| search(&mut e.localization.clone()).map(|s| Value::Whole(*s.1)),
                set: |e, v| {
                    *search(&mut e.localization)?.1 = v.whole()?;
                    Some(())
                },
            },
            Param {
                name: "layers",
                kind: Kind::Whole(1, MAX_DISTANCE_LAYERS),
                unit: "",
                doc: "depth-peeled layers of the environment's distance map (1: the radiance cube alone)",
                source:
                    "Everitt 2001, \"Interactive Order-Independent Transparency\", NVIDIA (depth peeling)",
                unset: "",
                get: |e| search(&mut e.localization.clone()).map(|s| Value::Whole(*s.2)),
                set: |e, v| {
                    *search(&mut e.localization)?.2 = v.whole()?;
                    Some(())
                },
            },
            DOUBLE_REFRACTION,
        ],
    },
];

/// The distance-impostor family: environment mapping with a localization.
pub struct DistanceImpostors;

impl Family for DistanceImpostors {
    fn title(&self) -> &'static str {
        "Distance impostors"
    }

    fn methods(&self) -> Vec<MethodInfo> {
        MethodInfo::of(METHODS)
    }

    /// As the environment-mapping methods: n = 8, env_n = 8, unshadowed.
    fn method(&self, name: &str) -> Option<Method> {
        Method::from_table(METHODS, name, 8)
    }

    fn shared_rows(&self) -> Vec<Row> {
        envmap::shared_rows()
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[("distance_impostor/lookup.wgsl", include_str!("lookup.wgsl"))]
    }
}

/// The settings of both families, here because a distance impostor is an environment map
/// with a [`Localization`] other than `Distant`: its method is named by the localization.
impl Settings for EnvMapping {
    fn method_name(&self) -> &'static str {
        spec_of(self).name
    }

    /// [`envmap::COMMON`], its method's own, then `detail` (the method's; a detail method's
    /// rows follow as its `Detail` part's).
    fn rows(&self) -> Vec<Row> {
        let mut rows = Row::all(self.rows(spec_of(self)));
        rows.push(Row(&envmap::DETAIL));
        rows
    }

    fn overrides(&self) -> Vec<Override> {
        vec![Override::shading(
            "ENVMAP_METHOD",
            self.parameterization.shader_code(),
        )]
    }
}

/// The environment-mapping or distance-impostor method `e` is.
fn spec_of(e: &EnvMapping) -> &'static MethodSpec<EnvMapping> {
    match e.localization {
        Localization::Distant => &envmap::METHODS[e.parameterization.shader_code() as usize - 1],
        Localization::Iterations(_) => &METHODS[0],
        Localization::Search { .. } => &METHODS[1],
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
        let search = &METHODS[1];
        let mut s = (search.default)();
        for (row, v) in search.params.iter().zip([64, 0, 3]) {
            (row.set)(&mut s, Value::Whole(v)).unwrap();
        }
        assert_eq!(
            s.localization,
            Localization::Search {
                linear_steps: 64,
                secant_steps: 0,
                layers: 3
            }
        );
        assert_eq!(s.localization.distance_layers(), 3);
        let iterations = &METHODS[0].params[0];
        assert!(
            (iterations.set)(&mut s, Value::Whole(2)).is_none(),
            "iterations are the iteration's"
        );
        let mut i = (METHODS[0].default)();
        assert!(
            (search.params[2].set)(&mut i, Value::Whole(2)).is_none(),
            "layers are the search's"
        );
        (iterations.set)(&mut i, Value::Whole(0)).unwrap();
        assert_eq!(i.localization.shader_info(true), [1, 0, 0, 1]);
    }
}
