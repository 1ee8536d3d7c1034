//! How an environment map's lookups are localized: the plain direction (the environment
//! infinitely far), or the distance impostors' searches through the distances the cube also
//! stores ([`crate::technique::distance_impostor`] has the methods, their maths and papers).

/// Largest `iterations`.
pub const MAX_ITERATIONS: u32 = 64;
/// Largest `linear_steps`.
pub const MAX_LINEAR_STEPS: u32 = 256;
/// Largest `secant_steps`.
pub const MAX_SECANT_STEPS: u32 = 64;
/// Largest `layers` (distance-map layers of `distance_search`).
pub const MAX_DISTANCE_LAYERS: u32 = 4;

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
}
