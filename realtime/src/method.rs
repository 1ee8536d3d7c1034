//! Methods (how area lights, sun disks and the environment are shaded, and whether lights cast
//! shadows) and their parameters, as `verity raster --method NAME --param k=v` names them.
//!
//! | method | lights | visibility V | parameters (default) |
//! |---|---|---|---|
//! | `area_quadrature` | N×N midpoint quadrature: converges to the exact unshadowed integral | 1 (unshadowed) | `n` (16), `env_n` (8) |
//! | `area_representative_point` | one representative point per light (Karis 2013) | 1 (unshadowed) | `env_n` (8) |
//! | `shadow_hard` | N×N quadrature × V | one depth comparison, nearest texel (Williams 1978) | common |
//! | `pcf_hw_2x2` | N×N quadrature × V | one hardware bilinear comparison: 2×2 PCF | common |
//! | `pcf_box` | N×N quadrature × V | k×k nearest comparisons averaged (Reeves et al. 1987) | common, `kernel` (3: 3 or 5), `receiver_plane` |
//! | `pcf_poisson` | N×N quadrature × V | N bilinear comparisons on a Poisson disk | common, `taps` (16: 1..=64), `radius` (2 texels: 0..=64), `receiver_plane`, `rotate` |
//! | `pcss` | N×N quadrature × V | Fernando 2005 blocker search + penumbra-sized PCF | common, `blocker_samples` (16: 1..=64), `filter_samples` (32: 1..=64), `light_size` (the light's), `blocker_depth` (`search` / `ignore`), `receiver_plane`, `rotate` |
//!
//! Common parameters of the shadow methods: `n` (8: 1..=64), `env_n` (0: 0..=64), `map` (shadow
//! map side, 1024: 64..=4096), `bias` (constant bias in world metres along the light ray,
//! 0.002: 0..=10), `slope_bias` (slope-scaled bias in texel footprints × tan θ, 1: 0..=100),
//! `normal_offset` (offset along the geometric normal in texel footprints, 1: 0..=100),
//! `cascades` (cascaded shadow maps per directional light, 1: 1..=[`MAX_CASCADES`]) and
//! `split_lambda` (λ of the parallel-split rule, 0.5: 0..=1).
//! `cascades = k ≥ 2` splits the camera's view depth range [n, f] of a directional light into k
//! slices by the practical split scheme of Zhang et al. 2006 ("Parallel-Split Shadow Maps for
//! Large-scale Virtual Environments", VRCIA 2006, <https://doi.org/10.1145/1128923.1128975>),
//! z_i = λ·n·(f/n)^(i/k) + (1 − λ)·(n + (f − n)·i/k), each slice with its own orthographic map
//! (Dimitrov 2007, "Cascaded Shadow Maps", NVIDIA whitepaper): λ = 0 uniform, λ = 1
//! logarithmic splits (shadow.rs, "Cascades"). `cascades = 1` is the one map over the scene;
//! other light kinds ignore both.
//! `receiver_plane` (`on` / `off`, default on) gives each tap of the multi-tap kernels the
//! depth of the receiver's tangent plane there (receiver-plane depth bias, Isidoro 2006);
//! without it wide kernels self-shadow receivers tilted to the light.
//! `rotate` (`on` / `off`, default off) rotates `pcf_poisson`'s and PCSS's Poisson taps (blocker
//! search and filter) per pixel by the angle 2π·IGN(x, y), interleaved gradient noise (Jimenez
//! 2014, shadow_map_common.wgsl): the fixed pattern's banding becomes per-pixel noise.
//! `light_size` is metres for local lights and the angular diameter in degrees for directional
//! lights; `blocker_depth = ignore` replaces the blocker search by half the receiver depth
//! (a constant penumbra of the light's size): a deliberately broken PCSS, a test device for
//! thresholds, not a technique.
//!
//! Surface-detail methods (`normal_mapping`, `bump_mapping`, `parallax`,
//! `parallax_offset_limited`, `steep_parallax`, `relief_mapping`, `pom`, `cone_step`) are
//! listed with their parameters in [`crate::detail`]; they shade by N×N quadrature, unshadowed
//! by maps, and take `n` (8), `env_n` (8) and `height_scale` (1).
//!
//! Environment-mapping methods (`envmap_cube`, `envmap_sphere`, `envmap_paraboloid`) are
//! listed with their parameters in [`crate::envmap`]; they shade one reflector from maps
//! captured at a point, the other shapes by N×N quadrature (n = 8, env_n = 8), unshadowed.
//! The distance impostors (`distance_impostor`, `distance_search`, [`crate::distance_impostor`])
//! are `envmap_cube` with lookups localized by the distances the cube also stores.
//!
//! Delta lights (point, spot, zero-diameter directional) are exact under every method, up to V.
//! The environment lights surfaces by `env_n`×`env_n` cosine-weighted midpoint quadrature under
//! every method, never shadowed (0 turns environment lighting off; the background is always
//! drawn).

use std::fmt;

use crate::detail::{Detail, DetailTechnique, DETAIL_NAMES, MAX_BINARY_STEPS, MAX_DETAIL_STEPS};
use crate::distance_impostor::{
    DISTANCE_IMPOSTOR_NAMES, MAX_DISTANCE_LAYERS, MAX_ITERATIONS, MAX_LINEAR_STEPS, MAX_SECANT_STEPS,
};
use crate::envmap::{detail_by_name, EnvMapping, ENVMAP_NAMES, ENVMAP_SIZES, MAX_FILTER_SAMPLES};

/// Largest `n` / `env_n` accepted (N² samples per light per pixel).
pub const MAX_QUADRATURE_N: u32 = 64;
/// Largest Poisson tap count (`taps`, `blocker_samples`, `filter_samples`): the size of the
/// tap table (shadow.rs `POISSON_TAPS`).
pub const MAX_SHADOW_TAPS: u32 = 64;
/// Shadow-map sides accepted.
pub const SHADOW_MAP_SIZES: std::ops::RangeInclusive<u32> = 64..=4096;
/// Most cascades per directional light (`cascades`), as Dimitrov 2007's examples (and most
/// engines) use.
pub const MAX_CASCADES: u32 = 4;

/// The area-light technique (WGSL `AREA_METHOD`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AreaMethod {
    /// N×N stratified midpoint quadrature (the reference for unshadowed area light).
    Quadrature,
    /// Karis 2013 representative point with energy normalisation (an approximation).
    RepresentativePoint,
}

impl AreaMethod {
    /// The value of the WGSL override constant `AREA_METHOD`.
    pub fn shader_code(self) -> u32 {
        match self {
            AreaMethod::Quadrature => 0,
            AreaMethod::RepresentativePoint => 1,
        }
    }
}

/// Where PCSS takes the blocker depth from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlockerDepth {
    /// The average depth of the blockers found by the search (Fernando 2005).
    Search,
    /// Half the receiver depth, whatever blocks: a constant penumbra of the light's size —
    /// the deliberately broken PCSS that the study thresholds must reject.
    Ignore,
}

/// The shadow-map filtering technique and its own parameters (WGSL `SHADOW_METHOD`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShadowTechnique {
    /// `shadow_hard`: one depth comparison at the nearest texel (Williams 1978).
    Hard,
    /// `pcf_hw_2x2`: one bilinear hardware comparison (2×2 PCF).
    PcfHw2x2,
    /// `pcf_box`: k×k nearest comparisons on the texel grid, averaged.
    PcfBox {
        /// k: 3 or 5.
        kernel: u32,
    },
    /// `pcf_poisson`: bilinear comparisons at the taps of a Poisson disk.
    PcfPoisson {
        /// Number of taps, 1..=64.
        taps: u32,
        /// Disk radius in texels.
        radius: f32,
    },
    /// `pcss`: Fernando 2005 percentage-closer soft shadows.
    Pcss {
        /// Taps of the blocker search.
        blocker_samples: u32,
        /// Taps of the penumbra-sized PCF.
        filter_samples: u32,
        /// w_light override (metres; degrees of angular diameter for directional lights);
        /// None: each light's own size.
        light_size: Option<f32>,
        /// The real blocker search, or the broken constant penumbra.
        blocker_depth: BlockerDepth,
    },
}

impl ShadowTechnique {
    /// The value of the WGSL override constant `SHADOW_METHOD` (0 is "no shadows").
    pub fn shader_code(self) -> u32 {
        match self {
            ShadowTechnique::Hard => 1,
            ShadowTechnique::PcfHw2x2 => 2,
            ShadowTechnique::PcfBox { .. } => 3,
            ShadowTechnique::PcfPoisson { .. } => 4,
            ShadowTechnique::Pcss { .. } => 5,
        }
    }

    /// The method name.
    pub fn name(self) -> &'static str {
        match self {
            ShadowTechnique::Hard => "shadow_hard",
            ShadowTechnique::PcfHw2x2 => "pcf_hw_2x2",
            ShadowTechnique::PcfBox { .. } => "pcf_box",
            ShadowTechnique::PcfPoisson { .. } => "pcf_poisson",
            ShadowTechnique::Pcss { .. } => "pcss",
        }
    }

    /// The technique called `name` with its default parameters.
    fn by_name(name: &str) -> Option<ShadowTechnique> {
        Some(match name {
            "shadow_hard" => ShadowTechnique::Hard,
            "pcf_hw_2x2" => ShadowTechnique::PcfHw2x2,
            "pcf_box" => ShadowTechnique::PcfBox { kernel: 3 },
            "pcf_poisson" => ShadowTechnique::PcfPoisson {
                taps: 16,
                radius: 2.0,
            },
            "pcss" => ShadowTechnique::Pcss {
                blocker_samples: 16,
                filter_samples: 32,
                light_size: None,
                blocker_depth: BlockerDepth::Search,
            },
            _ => return None,
        })
    }
}

/// Shadow mapping: the technique and the shadow-map parameters every technique shares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shadow {
    /// How the map is filtered into V.
    pub technique: ShadowTechnique,
    /// Shadow-map side in texels.
    pub map: u32,
    /// Constant bias, world metres along the ray towards the light.
    pub bias: f32,
    /// Slope-scaled bias: this many texel footprints × tan θ (θ between normal and light).
    pub slope_bias: f32,
    /// Offset of the lookup point along the geometric normal, in texel footprints.
    pub normal_offset: f32,
    /// Receiver-plane depth bias for the multi-tap kernels (`pcf_box`, `pcf_poisson`, `pcss`):
    /// each tap compares against the receiver's tangent plane's depth there (Isidoro 2006).
    pub receiver_plane: bool,
    /// Per-pixel rotation of the Poisson taps (`pcf_poisson`, `pcss`) by interleaved gradient
    /// noise (Jimenez 2014).
    pub rotate: bool,
    /// Cascades per directional light, 1..=[`MAX_CASCADES`] (1: one map over the scene).
    pub cascades: u32,
    /// λ of the parallel-split rule (Zhang et al. 2006), 0 (uniform) ..= 1 (logarithmic).
    pub split_lambda: f32,
}

impl Shadow {
    /// `technique` with the default map (1024²), biases (0.002 m, 1, 1), receiver-plane bias
    /// on, fixed taps, one cascade (λ = 0.5).
    pub fn new(technique: ShadowTechnique) -> Shadow {
        Shadow {
            technique,
            map: 1024,
            bias: 0.002,
            slope_bias: 1.0,
            normal_offset: 1.0,
            receiver_plane: true,
            rotate: false,
            cascades: 1,
            split_lambda: 0.5,
        }
    }

    /// Whether the technique filters with Poisson taps (`pcf_poisson`, `pcss`): the ones
    /// `rotate` applies to.
    pub fn uses_poisson_taps(&self) -> bool {
        matches!(
            self.technique,
            ShadowTechnique::PcfPoisson { .. } | ShadowTechnique::Pcss { .. }
        )
    }
}

/// A method with its parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Method {
    /// How area lights and sun disks are shaded.
    pub area: AreaMethod,
    /// N of the N×N area quadrature (ignored by the representative point).
    pub area_n: u32,
    /// N of the N×N environment quadrature; 0 = no environment lighting.
    pub env_n: u32,
    /// Shadow mapping, or None: every light unoccluded.
    pub shadow: Option<Shadow>,
    /// Surface detail on displaced shapes, or None: they are drawn flat (their base surface).
    pub detail: Option<Detail>,
    /// Environment mapping of one reflector, or None: no maps are captured.
    pub envmap: Option<EnvMapping>,
}

impl Default for Method {
    /// `area_quadrature` with n = 16, env_n = 8.
    fn default() -> Self {
        Method {
            area: AreaMethod::Quadrature,
            area_n: 16,
            env_n: 8,
            shadow: None,
            detail: None,
            envmap: None,
        }
    }
}

/// The values of an environment map's `detail`: a detail method, or none.
const ENVMAP_DETAILS: [&str; 9] = [
    "none",
    DETAIL_NAMES[0],
    DETAIL_NAMES[1],
    DETAIL_NAMES[2],
    DETAIL_NAMES[3],
    DETAIL_NAMES[4],
    DETAIL_NAMES[5],
    DETAIL_NAMES[6],
    DETAIL_NAMES[7],
];

/// A parameter's accepted values, for parsing and error messages.
enum Param {
    Whole(std::ops::RangeInclusive<u32>),
    OneOf(&'static [u32]),
    Real(f32, f32),
    Keyword(&'static [&'static str]),
    /// A shape's name.
    Name,
    /// Three numbers, `x,y,z`.
    Vector,
}

impl Param {
    fn describe(&self) -> String {
        match self {
            Param::Whole(r) => format!("a whole number in {}..={}", r.start(), r.end()),
            Param::OneOf(v) => {
                let v: Vec<String> = v.iter().map(u32::to_string).collect();
                format!("one of {}", v.join(", "))
            }
            Param::Real(lo, hi) => format!("a number in [{lo}, {hi}]"),
            Param::Keyword(k) => format!("one of {}", k.join(", ")),
            Param::Name => "a shape's name".to_string(),
            Param::Vector => "three finite numbers x,y,z".to_string(),
        }
    }
}

impl Method {
    /// Every method name `parse` accepts.
    pub const NAMES: [&'static str; 20] = [
        "area_quadrature",
        "area_representative_point",
        "shadow_hard",
        "pcf_hw_2x2",
        "pcf_box",
        "pcf_poisson",
        "pcss",
        DETAIL_NAMES[0],
        DETAIL_NAMES[1],
        DETAIL_NAMES[2],
        DETAIL_NAMES[3],
        DETAIL_NAMES[4],
        DETAIL_NAMES[5],
        DETAIL_NAMES[6],
        DETAIL_NAMES[7],
        ENVMAP_NAMES[0],
        ENVMAP_NAMES[1],
        ENVMAP_NAMES[2],
        DISTANCE_IMPOSTOR_NAMES[0],
        DISTANCE_IMPOSTOR_NAMES[1],
    ];

    /// `area_quadrature` with the given N (environment N 8).
    pub fn quadrature(n: u32) -> Self {
        Method {
            area_n: n,
            ..Method::default()
        }
    }

    /// `area_representative_point` (environment N 8).
    pub fn representative_point() -> Self {
        Method {
            area: AreaMethod::RepresentativePoint,
            ..Method::default()
        }
    }

    /// The shadow method `shadow` over N×N quadrature with the shadow methods' defaults
    /// (n = 8, env_n = 0).
    pub fn shadowed(shadow: Shadow) -> Self {
        Method {
            area: AreaMethod::Quadrature,
            area_n: 8,
            env_n: 0,
            shadow: Some(shadow),
            detail: None,
            envmap: None,
        }
    }

    /// The surface-detail method `detail` over N×N quadrature (n = 8, env_n = 8), unshadowed.
    pub fn detailed(detail: Detail) -> Self {
        Method {
            area: AreaMethod::Quadrature,
            area_n: 8,
            env_n: 8,
            shadow: None,
            detail: Some(detail),
            envmap: None,
        }
    }

    /// The environment-mapping method `envmap` over N×N quadrature (n = 8, env_n = 8),
    /// unshadowed, without surface detail.
    pub fn environment_mapped(envmap: EnvMapping) -> Self {
        Method {
            area: AreaMethod::Quadrature,
            area_n: 8,
            env_n: 8,
            shadow: None,
            detail: None,
            envmap: Some(envmap),
        }
    }

    /// The same method with environment quadrature N.
    pub fn with_env_n(self, env_n: u32) -> Self {
        Method { env_n, ..self }
    }

    /// The method called `name` with `params` (`key`, `value`) applied over its defaults.
    /// Errors name the method or parameter and list what is accepted.
    pub fn parse(name: &str, params: &[(String, String)]) -> Result<Method, String> {
        let mut m = match name {
            "area_quadrature" => Method::default(),
            "area_representative_point" => Method::representative_point(),
            _ => match (
                ShadowTechnique::by_name(name),
                DetailTechnique::by_name(name),
                EnvMapping::by_name(name),
            ) {
                (Some(t), _, _) => Method::shadowed(Shadow::new(t)),
                (None, Some(t), _) => Method::detailed(Detail::new(t)),
                (None, None, Some(e)) => Method::environment_mapped(e),
                (None, None, None) => {
                    return Err(format!(
                        "unknown method `{name}`; methods: {}",
                        Method::NAMES.join(", ")
                    ))
                }
            },
        };
        // An environment map's `detail` first: it decides which detail parameters exist.
        let (first, rest): (Vec<_>, Vec<_>) = params.iter().partition(|(k, _)| k == "detail");
        for (key, value) in first.into_iter().chain(rest) {
            let Some(spec) = m.param_spec(key) else {
                return Err(format!(
                    "method {name} has no parameter `{key}`; parameters: {}",
                    m.param_names().join(", ")
                ));
            };
            m.set(key, value.trim(), &spec)
                .ok_or_else(|| format!("parameter {key} = `{value}`: expected {}", spec.describe()))?;
        }
        Ok(m)
    }

    /// The parameter names this method accepts, in `params` order.
    fn param_names(&self) -> Vec<&'static str> {
        let mut names = Vec::new();
        if self.area == AreaMethod::Quadrature {
            names.push("n");
        }
        names.push("env_n");
        if let Some(s) = &self.shadow {
            names.extend([
                "map",
                "bias",
                "slope_bias",
                "normal_offset",
                "cascades",
                "split_lambda",
            ]);
            names.extend(match s.technique {
                ShadowTechnique::Hard | ShadowTechnique::PcfHw2x2 => &[][..],
                ShadowTechnique::PcfBox { .. } => &["kernel", "receiver_plane"],
                ShadowTechnique::PcfPoisson { .. } => &["taps", "radius", "receiver_plane", "rotate"],
                ShadowTechnique::Pcss { .. } => &[
                    "blocker_samples",
                    "filter_samples",
                    "light_size",
                    "blocker_depth",
                    "receiver_plane",
                    "rotate",
                ],
            });
        }
        if let Some(e) = &self.envmap {
            names.extend(e.param_names());
        }
        if let Some(d) = &self.detail {
            names.push("height_scale");
            names.extend(d.technique.param_names());
        }
        names
    }

    /// What parameter `key` of this method accepts, or None if it has no such parameter.
    fn param_spec(&self, key: &str) -> Option<Param> {
        if !self.param_names().contains(&key) {
            return None;
        }
        let taps = Param::Whole(1..=MAX_SHADOW_TAPS);
        Some(match key {
            "n" => Param::Whole(1..=MAX_QUADRATURE_N),
            "env_n" => Param::Whole(0..=MAX_QUADRATURE_N),
            "map" => Param::Whole(SHADOW_MAP_SIZES),
            // Parallax's scale-and-bias bias, as a fraction of the height range.
            "bias" if self.detail.is_some() => Param::Real(-1.0, 1.0),
            "bias" => Param::Real(0.0, 10.0),
            "slope_bias" | "normal_offset" => Param::Real(0.0, 100.0),
            "kernel" => Param::OneOf(&[3, 5]),
            "filter_samples" if self.envmap.is_some() => Param::Whole(1..=MAX_FILTER_SAMPLES),
            "taps" | "blocker_samples" | "filter_samples" => taps,
            "radius" => Param::Real(0.0, 64.0),
            "light_size" => Param::Real(0.0, 1e6),
            "blocker_depth" => Param::Keyword(&["search", "ignore"]),
            // true/false too: a study file's TOML booleans arrive as such.
            "receiver_plane" | "rotate" => Param::Keyword(&["on", "off", "true", "false"]),
            "cascades" => Param::Whole(1..=MAX_CASCADES),
            "split_lambda" => Param::Real(0.0, 1.0),
            "height_scale" => Param::Real(0.0, 10.0),
            "delta" => Param::Real(0.01, 16.0),
            "steps" | "min_steps" | "max_steps" | "shadow_steps" => Param::Whole(1..=MAX_DETAIL_STEPS),
            "binary_steps" => Param::Whole(0..=MAX_BINARY_STEPS),
            "self_shadow" | "relaxed" => Param::Keyword(&["on", "off", "true", "false"]),
            "size" => Param::Whole(ENVMAP_SIZES),
            "prefilter" => Param::Keyword(&["lobe", "box"]),
            "irradiance" => Param::Keyword(&["map", "sh9"]),
            "dominant_direction" | "double_refraction" => Param::Keyword(&["on", "off", "true", "false"]),
            "iterations" => Param::Whole(0..=MAX_ITERATIONS),
            "linear_steps" => Param::Whole(1..=MAX_LINEAR_STEPS),
            "secant_steps" => Param::Whole(0..=MAX_SECANT_STEPS),
            "layers" => Param::Whole(1..=MAX_DISTANCE_LAYERS),
            "seam" => Param::Keyword(&["fill", "none"]),
            "reflector" => Param::Name,
            "capture" | "sphere_view" => Param::Vector,
            "detail" => Param::Keyword(&ENVMAP_DETAILS),
            _ => return None,
        })
    }

    /// Sets parameter `key` from `value`; None if the value is not accepted.
    fn set(&mut self, key: &str, value: &str, spec: &Param) -> Option<()> {
        let whole = || -> Option<u32> {
            let v = value.parse::<u32>().ok()?;
            match spec {
                Param::Whole(r) => r.contains(&v).then_some(v),
                Param::OneOf(set) => set.contains(&v).then_some(v),
                _ => None,
            }
        };
        let real = || -> Option<f32> {
            let v = value.parse::<f32>().ok()?;
            match spec {
                Param::Real(lo, hi) => (v.is_finite() && v >= *lo && v <= *hi).then_some(v),
                _ => None,
            }
        };
        let switch = |value: &str| match value {
            "on" | "true" => Some(true),
            "off" | "false" => Some(false),
            _ => None,
        };
        match key {
            "n" => self.area_n = whole()?,
            "env_n" => self.env_n = whole()?,
            "detail" if self.envmap.is_some() => self.detail = detail_by_name(value)?,
            _ if self
                .envmap
                .as_ref()
                .is_some_and(|e| e.param_names().contains(&key)) =>
            {
                self.envmap.as_mut()?.set(key, value)?
            }
            _ if self.detail.is_some() => {
                let d = self.detail.as_mut()?;
                match (key, &mut d.technique) {
                    ("height_scale", _) => d.height_scale = real()?,
                    ("delta", DetailTechnique::BumpMapping { delta }) => *delta = real()?,
                    ("bias", DetailTechnique::Parallax { bias })
                    | ("bias", DetailTechnique::ParallaxOffsetLimited { bias }) => *bias = real()?,
                    ("steps", DetailTechnique::SteepParallax { steps })
                    | ("steps", DetailTechnique::ReliefMapping { steps, .. })
                    | ("steps", DetailTechnique::ConeStep { steps, .. }) => *steps = whole()?,
                    ("binary_steps", DetailTechnique::ReliefMapping { binary_steps, .. })
                    | ("binary_steps", DetailTechnique::ConeStep { binary_steps, .. }) => {
                        *binary_steps = whole()?
                    }
                    ("min_steps", DetailTechnique::Pom { min_steps, .. }) => *min_steps = whole()?,
                    ("max_steps", DetailTechnique::Pom { max_steps, .. }) => *max_steps = whole()?,
                    ("shadow_steps", DetailTechnique::Pom { shadow_steps, .. }) => *shadow_steps = whole()?,
                    ("self_shadow", DetailTechnique::Pom { self_shadow, .. }) => {
                        *self_shadow = switch(value)?
                    }
                    ("relaxed", DetailTechnique::ConeStep { relaxed, .. }) => *relaxed = switch(value)?,
                    _ => return None,
                }
            }
            _ => {
                let s = self.shadow.as_mut()?;
                match (key, &mut s.technique) {
                    ("map", _) => s.map = whole()?,
                    ("bias", _) => s.bias = real()?,
                    ("slope_bias", _) => s.slope_bias = real()?,
                    ("normal_offset", _) => s.normal_offset = real()?,
                    ("receiver_plane", _) => s.receiver_plane = switch(value)?,
                    ("rotate", _) => s.rotate = switch(value)?,
                    ("cascades", _) => s.cascades = whole()?,
                    ("split_lambda", _) => s.split_lambda = real()?,
                    ("kernel", ShadowTechnique::PcfBox { kernel }) => *kernel = whole()?,
                    ("taps", ShadowTechnique::PcfPoisson { taps, .. }) => *taps = whole()?,
                    ("radius", ShadowTechnique::PcfPoisson { radius, .. }) => *radius = real()?,
                    ("blocker_samples", ShadowTechnique::Pcss { blocker_samples, .. }) => {
                        *blocker_samples = whole()?
                    }
                    ("filter_samples", ShadowTechnique::Pcss { filter_samples, .. }) => {
                        *filter_samples = whole()?
                    }
                    ("light_size", ShadowTechnique::Pcss { light_size, .. }) => *light_size = Some(real()?),
                    ("blocker_depth", ShadowTechnique::Pcss { blocker_depth, .. }) => {
                        *blocker_depth = match value {
                            "search" => BlockerDepth::Search,
                            "ignore" => BlockerDepth::Ignore,
                            _ => return None,
                        }
                    }
                    _ => return None,
                }
            }
        }
        Some(())
    }

    /// Checks every parameter against the ranges `parse` accepts (for methods built in code).
    pub fn validate(&self) -> Result<(), String> {
        for (key, value) in self.params() {
            let spec = self
                .param_spec(&key)
                .ok_or_else(|| format!("method {self}: no parameter `{key}`"))?;
            let mut copy = self.clone();
            if copy.set(&key, &value, &spec).is_none() {
                return Err(format!(
                    "method {self}: parameter {key} = {value}: expected {}",
                    spec.describe()
                ));
            }
        }
        Ok(())
    }

    /// The method's name.
    pub fn name(&self) -> &'static str {
        if let Some(e) = &self.envmap {
            return e.name();
        }
        if let Some(d) = &self.detail {
            return d.technique.name();
        }
        match (self.shadow, self.area) {
            (Some(s), _) => s.technique.name(),
            (None, AreaMethod::Quadrature) => "area_quadrature",
            (None, AreaMethod::RepresentativePoint) => "area_representative_point",
        }
    }

    /// The WGSL `SHADOW_METHOD` of this method (0: unshadowed).
    pub fn shadow_code(&self) -> u32 {
        self.shadow.map_or(0, |s| s.technique.shader_code())
    }

    /// The WGSL `DETAIL_METHOD` of this method (0: displaced shapes drawn flat).
    pub fn detail_code(&self) -> u32 {
        self.detail.map_or(0, |d| d.technique.shader_code())
    }

    /// The WGSL `ENVMAP_METHOD` of this method (0: no environment map).
    pub fn envmap_code(&self) -> u32 {
        self.envmap
            .as_ref()
            .map_or(0, |e| e.parameterization.shader_code())
    }

    /// Its parameters as `k=v` pairs (for headers and the timing line).
    pub fn params(&self) -> Vec<(String, String)> {
        let mut p = Vec::new();
        let mut push = |k: &str, v: String| p.push((k.to_string(), v));
        if self.area == AreaMethod::Quadrature {
            push("n", self.area_n.to_string());
        }
        push("env_n", self.env_n.to_string());
        if let Some(s) = &self.shadow {
            push("map", s.map.to_string());
            push("bias", s.bias.to_string());
            push("slope_bias", s.slope_bias.to_string());
            push("normal_offset", s.normal_offset.to_string());
            push("cascades", s.cascades.to_string());
            push("split_lambda", s.split_lambda.to_string());
            let on_off = |b: bool| if b { "on" } else { "off" }.to_string();
            let plane = on_off(s.receiver_plane);
            match s.technique {
                ShadowTechnique::Hard | ShadowTechnique::PcfHw2x2 => {}
                ShadowTechnique::PcfBox { kernel } => {
                    push("kernel", kernel.to_string());
                    push("receiver_plane", plane);
                }
                ShadowTechnique::PcfPoisson { taps, radius } => {
                    push("taps", taps.to_string());
                    push("radius", radius.to_string());
                    push("receiver_plane", plane);
                    push("rotate", on_off(s.rotate));
                }
                ShadowTechnique::Pcss {
                    blocker_samples,
                    filter_samples,
                    light_size,
                    blocker_depth,
                } => {
                    push("blocker_samples", blocker_samples.to_string());
                    push("filter_samples", filter_samples.to_string());
                    if let Some(w) = light_size {
                        push("light_size", w.to_string());
                    }
                    let mode = match blocker_depth {
                        BlockerDepth::Search => "search",
                        BlockerDepth::Ignore => "ignore",
                    };
                    push("blocker_depth", mode.to_string());
                    push("receiver_plane", plane);
                    push("rotate", on_off(s.rotate));
                }
            }
        }
        if let Some(e) = &self.envmap {
            for (k, v) in e.params(self.detail.as_ref()) {
                push(k, v);
            }
        }
        if let Some(d) = &self.detail {
            push("height_scale", d.height_scale.to_string());
            for (k, v) in d.technique.params() {
                push(k, v);
            }
        }
        p
    }
}

impl fmt::Display for Method {
    /// `name(k=v, …)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let params: Vec<String> = self.params().iter().map(|(k, v)| format!("{k}={v}")).collect();
        write!(f, "{}({})", self.name(), params.join(", "))
    }
}

/// Forward shading or deferred shading (G-buffer + lighting pass).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum PipelineKind {
    /// Shade in the geometry pass.
    #[default]
    Forward,
    /// Write a G-buffer, then shade in a full-screen lighting pass.
    Deferred,
}

impl PipelineKind {
    /// `forward` or `deferred`.
    pub fn name(self) -> &'static str {
        match self {
            PipelineKind::Forward => "forward",
            PipelineKind::Deferred => "deferred",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kv(k: &str, v: &str) -> (String, String) {
        (k.to_string(), v.to_string())
    }

    #[test]
    fn parse_applies_parameters_over_defaults() {
        let m = Method::parse("area_quadrature", &[kv("n", "4"), kv("env_n", "0")]).unwrap();
        assert_eq!(m, Method::quadrature(4).with_env_n(0));
        assert_eq!(m.to_string(), "area_quadrature(n=4, env_n=0)");
        let r = Method::parse("area_representative_point", &[]).unwrap();
        assert_eq!(r.to_string(), "area_representative_point(env_n=8)");
    }

    #[test]
    fn parse_rejects_bad_names_and_values() {
        let e = Method::parse("pcss_fixed", &[]).unwrap_err();
        assert!(e.contains("area_quadrature") && e.contains("pcss"), "{e}");
        let e = Method::parse("area_representative_point", &[kv("n", "4")]).unwrap_err();
        assert!(e.contains("no parameter `n`") && e.contains("env_n"), "{e}");
        for bad in ["0", "65", "-1", "x", "2.5"] {
            assert!(
                Method::parse("area_quadrature", &[kv("n", bad)]).is_err(),
                "n={bad}"
            );
        }
        assert!(Method::parse("area_quadrature", &[kv("env_n", "0")]).is_ok());
        let e = Method::parse("area_quadrature", &[kv("map", "512")]).unwrap_err();
        assert!(e.contains("no parameter `map`"), "{e}");
    }

    /// Every shadow method's defaults as the method table lists them, and names round-trip.
    #[test]
    fn shadow_methods_have_the_documented_defaults() {
        let common =
            "n=8, env_n=0, map=1024, bias=0.002, slope_bias=1, normal_offset=1, cascades=1, split_lambda=0.5";
        for (name, own) in [
            ("shadow_hard", ""),
            ("pcf_hw_2x2", ""),
            ("pcf_box", ", kernel=3, receiver_plane=on"),
            ("pcf_poisson", ", taps=16, radius=2, receiver_plane=on, rotate=off"),
            (
                "pcss",
                ", blocker_samples=16, filter_samples=32, blocker_depth=search, receiver_plane=on, rotate=off",
            ),
        ] {
            let m = Method::parse(name, &[]).unwrap();
            assert_eq!(m.to_string(), format!("{name}({common}{own})"));
            assert_eq!(m.name(), name);
            assert!(m.validate().is_ok());
            // The header's parameter list parses back to the same method.
            assert_eq!(Method::parse(name, &m.params()).unwrap(), m);
            assert_eq!(m.area, AreaMethod::Quadrature);
        }
        let codes: Vec<u32> = Method::NAMES
            .iter()
            .map(|n| Method::parse(n, &[]).unwrap().shadow_code())
            .collect();
        assert_eq!(
            codes,
            [0, 0, 1, 2, 3, 4, 5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
        );
    }

    #[test]
    fn shadow_parameters_are_range_checked() {
        let ok = |name: &str, k: &str, v: &str| Method::parse(name, &[kv(k, v)]).is_ok();
        assert!(
            ok("pcf_box", "kernel", "5") && !ok("pcf_box", "kernel", "4") && !ok("pcf_box", "kernel", "7")
        );
        assert!(
            ok("pcf_poisson", "taps", "64")
                && !ok("pcf_poisson", "taps", "0")
                && !ok("pcf_poisson", "taps", "65")
        );
        assert!(ok("pcf_poisson", "radius", "0.5") && !ok("pcf_poisson", "radius", "-1"));
        assert!(ok("shadow_hard", "map", "64") && ok("shadow_hard", "map", "4096"));
        assert!(!ok("shadow_hard", "map", "32") && !ok("shadow_hard", "map", "8192"));
        assert!(
            ok("shadow_hard", "bias", "0")
                && !ok("shadow_hard", "bias", "NaN")
                && !ok("shadow_hard", "bias", "inf")
        );
        assert!(!ok("shadow_hard", "kernel", "3"), "kernel is pcf_box's");
        assert!(ok("pcss", "blocker_depth", "ignore") && !ok("pcss", "blocker_depth", "fixed"));
        let m = Method::parse("pcss", &[kv("light_size", "0.25"), kv("blocker_depth", "ignore")]).unwrap();
        assert!(
            m.to_string()
                .ends_with("light_size=0.25, blocker_depth=ignore, receiver_plane=on, rotate=off)"),
            "{m}"
        );
        assert!(ok("pcf_box", "receiver_plane", "off") && !ok("pcf_hw_2x2", "receiver_plane", "off"));
        let off = Method::parse("pcss", &[kv("receiver_plane", "false")]).unwrap();
        assert!(
            off.to_string().ends_with("receiver_plane=off, rotate=off)"),
            "{off}"
        );
        let e = Method::parse("pcf_box", &[kv("kernel", "4")]).unwrap_err();
        assert!(e.contains("kernel") && e.contains("one of 3, 5"), "{e}");
        let e = Method::parse("pcss", &[kv("radius", "1")]).unwrap_err();
        assert!(e.contains("blocker_samples") && e.contains("light_size"), "{e}");
        let mut bad = Method::parse("pcf_poisson", &[]).unwrap();
        bad.shadow = Some(Shadow::new(ShadowTechnique::PcfPoisson {
            taps: 99,
            radius: 1.0,
        }));
        assert!(bad.validate().unwrap_err().contains("taps"));
    }

    /// `cascades` and `split_lambda` on every shadow method, `rotate` on the Poisson-tap ones,
    /// each range-checked with the accepted values in the error.
    #[test]
    fn cascade_and_rotation_parameters() {
        let ok = |name: &str, k: &str, v: &str| Method::parse(name, &[kv(k, v)]).is_ok();
        for name in ["shadow_hard", "pcf_hw_2x2", "pcf_box", "pcf_poisson", "pcss"] {
            assert!(ok(name, "cascades", "1") && ok(name, "cascades", "4"), "{name}");
            assert!(!ok(name, "cascades", "0") && !ok(name, "cascades", "5"), "{name}");
            assert!(
                ok(name, "split_lambda", "0") && ok(name, "split_lambda", "1"),
                "{name}"
            );
            assert!(
                !ok(name, "split_lambda", "1.5") && !ok(name, "split_lambda", "NaN"),
                "{name}"
            );
        }
        assert!(!ok("area_quadrature", "cascades", "2"));
        for name in ["pcf_poisson", "pcss"] {
            assert!(ok(name, "rotate", "on") && ok(name, "rotate", "true") && !ok(name, "rotate", "yes"));
        }
        for name in ["shadow_hard", "pcf_hw_2x2", "pcf_box"] {
            assert!(!ok(name, "rotate", "on"), "{name} has no Poisson taps to rotate");
        }
        let e = Method::parse("pcss", &[kv("cascades", "8")]).unwrap_err();
        assert!(e.contains("cascades") && e.contains("1..=4"), "{e}");
        let e = Method::parse("pcf_box", &[kv("rotate", "on")]).unwrap_err();
        assert!(e.contains("no parameter `rotate`"), "{e}");
        let m = Method::parse(
            "pcss",
            &[kv("cascades", "3"), kv("split_lambda", "0.9"), kv("rotate", "on")],
        )
        .unwrap();
        let s = m.shadow.unwrap();
        assert_eq!((s.cascades, s.split_lambda, s.rotate), (3, 0.9, true));
        assert_eq!(Method::parse("pcss", &m.params()).unwrap(), m);
    }

    /// Every detail method parses with its defaults, round-trips through its parameter list,
    /// and range-checks its own parameters only.
    #[test]
    fn detail_methods_have_the_documented_defaults() {
        for (name, own) in [
            ("normal_mapping", ""),
            ("bump_mapping", ", delta=1"),
            ("parallax", ", bias=0"),
            ("parallax_offset_limited", ", bias=0"),
            ("steep_parallax", ", steps=16"),
            ("relief_mapping", ", steps=16, binary_steps=6"),
            (
                "pom",
                ", min_steps=8, max_steps=32, self_shadow=off, shadow_steps=16",
            ),
            ("cone_step", ", steps=32, relaxed=off, binary_steps=6"),
        ] {
            let m = Method::parse(name, &[]).unwrap();
            assert_eq!(
                m.to_string(),
                format!("{name}(n=8, env_n=8, height_scale=1{own})")
            );
            assert_eq!(m.name(), name);
            assert_eq!(Method::parse(name, &m.params()).unwrap(), m);
            assert!(m.validate().is_ok() && m.shadow.is_none() && m.detail_code() > 0);
        }
        let ok = |name: &str, k: &str, v: &str| Method::parse(name, &[kv(k, v)]).is_ok();
        assert!(ok("pom", "self_shadow", "on") && !ok("pom", "self_shadow", "soft"));
        assert!(
            ok("pom", "max_steps", "256") && !ok("pom", "max_steps", "257") && !ok("pom", "min_steps", "0")
        );
        assert!(ok("relief_mapping", "binary_steps", "0") && !ok("relief_mapping", "binary_steps", "17"));
        assert!(ok("cone_step", "relaxed", "on") && !ok("steep_parallax", "relaxed", "on"));
        assert!(ok("parallax", "bias", "-0.5") && !ok("parallax", "bias", "2"));
        assert!(
            !ok("normal_mapping", "steps", "8"),
            "normal mapping does not march"
        );
        assert!(!ok("pcss", "height_scale", "1") && !ok("parallax", "height_scale", "-1"));
        let e = Method::parse("bump_mapping", &[kv("delta", "0")]).unwrap_err();
        assert!(e.contains("delta") && e.contains("[0.01, 16]"), "{e}");
        let m = Method::parse("cone_step", &[kv("relaxed", "true"), kv("height_scale", "0.5")]).unwrap();
        let d = m.detail.unwrap();
        assert_eq!(d.height_scale, 0.5);
        assert_eq!(d.technique.cone_kind(), Some(crate::cone_map::ConeKind::Relaxed));
    }
}
