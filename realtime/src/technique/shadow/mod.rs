//! Shadow mapping: each light shaded as its unshadowed integral (N×N quadrature; delta lights
//! exact; sun disks by their cone quadrature) times a visibility factor V ∈ [0, 1] filtered
//! from the light's shadow map (Williams 1978). The ground truth is the oracle's `direct` and
//! its `visibility.<light>.Y`.
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | the methods, their parameters and tables (this file) |
//! | [`maps`] | light frusta, the shadow uniform, the map array |
//! | [`frustum`] | a map layer's projection; the orthographic fit of directional lights and cascades |
//! | [`cascades`] | cascaded maps of directional lights (Zhang et al. 2006; Dimitrov 2007) |
//! | [`poisson`] | the Poisson-disk taps of `pcf_poisson` and `pcss` (Mitchell 1991) |
//! | `technique/shadow/*.wgsl` | the map lookup, one file per filter, the `SHADOW_METHOD` switch |
//!
//! `cascades = k ≥ 2` splits the camera's view depth range [n, f] of a directional light into
//! k slices by the practical split scheme of Zhang et al. 2006,
//! z_i = λ·n·(f/n)^(i/k) + (1 − λ)·(n + (f − n)·i/k), each slice with its own orthographic map
//! ([`maps`], "Cascades"): λ = 0 uniform, λ = 1 logarithmic splits. Other light kinds ignore
//! `cascades` and `split_lambda`. `light_size` is metres for local lights and the angular
//! diameter in degrees for directional lights. `blocker_depth = ignore` replaces PCSS's blocker
//! search by half the receiver depth (a constant penumbra of the light's size): a deliberately
//! broken PCSS, a test device for thresholds, not a technique.

pub mod cascades;
pub mod frustum;
pub mod maps;
pub mod poisson;

use super::method::{wgsl_method_codes, Family, Frame, Method, MethodInfo, Override, Row, Settings};
use super::param::{Kind, MethodSpec, Param, Value};

/// Largest Poisson tap count (`taps`, `blocker_samples`, `filter_samples`): the size of the
/// tap table ([`poisson::POISSON_TAPS`]).
pub const MAX_SHADOW_TAPS: u32 = 64;
/// Shadow-map sides accepted.
pub const SHADOW_MAP_SIZES: std::ops::RangeInclusive<u32> = 64..=4096;
/// Most cascades per directional light (`cascades`), as Dimitrov 2007's examples (and most
/// engines) use.
pub const MAX_CASCADES: u32 = 4;

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
    /// The value of the WGSL override constant `SHADOW_METHOD`: 1 + its index in [`METHODS`].
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
        self.spec().name
    }

    /// Its row of [`METHODS`].
    pub fn spec(self) -> &'static MethodSpec<Shadow> {
        &METHODS[self.shader_code() as usize - 1]
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
    /// How point and sphere lights are mapped.
    pub point_maps: PointMaps,
}

/// The maps of a point or sphere light (WGSL: a slot's `slots[slot].z`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PointMaps {
    /// One perspective frustum towards the scene, at most [`maps::MAX_FOV_DEG`] wide:
    /// receivers outside it are lit.
    Frustum,
    /// A cube: six 90° frusta along ±x, ±y, ±z (Gerasimov 2004, "Omnidirectional Shadow
    /// Mapping", GPU Gems ch. 12), the receiver's face picked by the major axis of its
    /// direction from the light.
    Cube,
}

impl PointMaps {
    /// The keywords, in WGSL code order.
    const NAMES: &'static [&'static str] = &["frustum", "cube"];
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
            point_maps: PointMaps::Frustum,
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

    /// Its parameter rows: [`COMMON`], then its technique's own.
    pub fn rows(&self) -> impl Iterator<Item = &'static Param<Shadow>> {
        COMMON.iter().chain(self.technique.spec().params)
    }
}

/// The parameters every shadow method shares (`n` and `env_n` are every method's; the shadow
/// methods default to n = 8, env_n = 0).
pub static COMMON: &[Param<Shadow>] = &[
    Param {
        name: "map",
        kind: Kind::Whole(*SHADOW_MAP_SIZES.start(), *SHADOW_MAP_SIZES.end()),
        unit: "texels per side",
        doc: "side of each light's shadow map (each cascade's)",
        source: "",
        unset: "",
        get: |s| Some(Value::Whole(s.map)),
        set: |s, v| {
            s.map = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "bias",
        kind: Kind::Real(0.0, 10.0),
        unit: "m",
        doc: "constant depth bias along the ray towards the light",
        source: "",
        unset: "",
        get: |s| Some(Value::Real(s.bias)),
        set: |s, v| {
            s.bias = v.real()?;
            Some(())
        },
    },
    Param {
        name: "slope_bias",
        kind: Kind::Real(0.0, 100.0),
        unit: "texel footprints × tan θ",
        doc: "slope-scaled bias (θ between normal and light), tan θ clamped at 10",
        source: "OpenGL 1.1 glPolygonOffset (spec §3.5.5), in world units",
        unset: "",
        get: |s| Some(Value::Real(s.slope_bias)),
        set: |s, v| {
            s.slope_bias = v.real()?;
            Some(())
        },
    },
    Param {
        name: "normal_offset",
        kind: Kind::Real(0.0, 100.0),
        unit: "texel footprints",
        doc: "lookup point moved along the geometric normal",
        source: "Holbein 2011, \"Normal Offset Shadows\", GDC poster",
        unset: "",
        get: |s| Some(Value::Real(s.normal_offset)),
        set: |s, v| {
            s.normal_offset = v.real()?;
            Some(())
        },
    },
    Param {
        name: "cascades",
        kind: Kind::Whole(1, MAX_CASCADES),
        unit: "",
        doc: "cascaded maps per directional light over the camera's view depth (1: one map over the scene)",
        source: "Dimitrov 2007, \"Cascaded Shadow Maps\", NVIDIA whitepaper",
        unset: "",
        get: |s| Some(Value::Whole(s.cascades)),
        set: |s, v| {
            s.cascades = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "split_lambda",
        kind: Kind::Real(0.0, 1.0),
        unit: "",
        doc: "λ of the practical split scheme: 0 uniform, 1 logarithmic cascade splits",
        source:
            "Zhang et al. 2006, \"Parallel-Split Shadow Maps for Large-scale Virtual Environments\", VRCIA",
        unset: "",
        get: |s| Some(Value::Real(s.split_lambda)),
        set: |s, v| {
            s.split_lambda = v.real()?;
            Some(())
        },
    },
    Param {
        name: "point_maps",
        kind: Kind::Keyword(PointMaps::NAMES),
        unit: "",
        doc: "point and sphere lights: one frustum towards the scene, at most 150° wide (receivers outside it are \
              lit), or a cube of six 90° faces (every direction)",
        source: "Gerasimov 2004, \"Omnidirectional Shadow Mapping\", GPU Gems ch. 12",
        unset: "",
        get: |s| Some(Value::Keyword(PointMaps::NAMES[s.point_maps as usize])),
        set: |s, v| {
            s.point_maps = match v.keyword()? {
                "cube" => PointMaps::Cube,
                _ => PointMaps::Frustum,
            };
            Some(())
        },
    },
];

/// `receiver_plane`, a row of every multi-tap kernel.
const RECEIVER_PLANE: Param<Shadow> = Param {
    name: "receiver_plane",
    kind: Kind::Switch,
    unit: "",
    doc:
        "each tap compares against the receiver's tangent plane there; off: one depth for the whole kernel, \
          which self-shadows tilted receivers",
    source: "Isidoro 2006, \"Shadow Mapping: GPU-based Tips and Techniques\", GDC",
    unset: "",
    get: |s| Some(Value::Switch(s.receiver_plane)),
    set: |s, v| {
        s.receiver_plane = v.switch()?;
        Some(())
    },
};

/// `rotate`, a row of the Poisson-tap kernels.
const ROTATE: Param<Shadow> = Param {
    name: "rotate",
    kind: Kind::Switch,
    unit: "",
    doc: "turn the Poisson taps per pixel by 2π·IGN(x, y): banding becomes noise",
    source:
        "Jimenez 2014, \"Next Generation Post Processing in Call of Duty: Advanced Warfare\", SIGGRAPH course",
    unset: "",
    get: |s| Some(Value::Switch(s.rotate)),
    set: |s, v| {
        s.rotate = v.switch()?;
        Some(())
    },
};

/// The taps of the Poisson-disk kernels (`taps`, `blocker_samples`, `filter_samples`).
const TAPS: Kind = Kind::Whole(1, MAX_SHADOW_TAPS);

/// The shadow methods, in `SHADOW_METHOD` order (1, 2, …).
pub static METHODS: &[MethodSpec<Shadow>] = &[
    MethodSpec {
        name: "shadow_hard",
        summary: "one depth comparison at the nearest texel",
        source: "Williams 1978, \"Casting Curved Shadows on Curved Surfaces\", SIGGRAPH",
        default: || Shadow::new(ShadowTechnique::Hard),
        params: &[],
    },
    MethodSpec {
        name: "pcf_hw_2x2",
        summary: "one hardware bilinear comparison (2×2 PCF)",
        source: "Reeves, Salesin & Cook 1987, \"Rendering Antialiased Shadows with Depth Maps\", SIGGRAPH",
        default: || Shadow::new(ShadowTechnique::PcfHw2x2),
        params: &[],
    },
    MethodSpec {
        name: "pcf_box",
        summary: "k×k nearest comparisons on the texel grid, averaged",
        source: "Reeves, Salesin & Cook 1987, \"Rendering Antialiased Shadows with Depth Maps\", SIGGRAPH",
        default: || Shadow::new(ShadowTechnique::PcfBox { kernel: 3 }),
        params: &[
            Param {
                name: "kernel",
                kind: Kind::OneOf(&[3, 5]),
                unit: "texels",
                doc: "k of the k×k kernel",
                source: "",
                unset: "",
                get: |s| match s.technique {
                    ShadowTechnique::PcfBox { kernel } => Some(Value::Whole(kernel)),
                    _ => None,
                },
                set: |s, v| match &mut s.technique {
                    ShadowTechnique::PcfBox { kernel } => { *kernel = v.whole()?; Some(()) },
                    _ => None,
                },
            },
            RECEIVER_PLANE,
        ],
    },
    MethodSpec {
        name: "pcf_poisson",
        summary: "N bilinear comparisons at the taps of a Poisson disk",
        source: "Mitchell 1991, \"Spectrally Optimal Sampling for Distribution Ray Tracing\", SIGGRAPH (best-candidate taps)",
        default: || {
            Shadow::new(ShadowTechnique::PcfPoisson {
                taps: 16,
                radius: 2.0,
            })
        },
        params: &[
            Param {
                name: "taps",
                kind: TAPS,
                unit: "",
                doc: "comparisons on the disk",
                source: "",
                unset: "",
                get: |s| match s.technique {
                    ShadowTechnique::PcfPoisson { taps, .. } => Some(Value::Whole(taps)),
                    _ => None,
                },
                set: |s, v| match &mut s.technique {
                    ShadowTechnique::PcfPoisson { taps, .. } => { *taps = v.whole()?; Some(()) },
                    _ => None,
                },
            },
            Param {
                name: "radius",
                kind: Kind::Real(0.0, 64.0),
                unit: "texels",
                doc: "radius of the disk",
                source: "",
                unset: "",
                get: |s| match s.technique {
                    ShadowTechnique::PcfPoisson { radius, .. } => Some(Value::Real(radius)),
                    _ => None,
                },
                set: |s, v| match &mut s.technique {
                    ShadowTechnique::PcfPoisson { radius, .. } => { *radius = v.real()?; Some(()) },
                    _ => None,
                },
            },
            RECEIVER_PLANE,
            ROTATE,
        ],
    },
    MethodSpec {
        name: "pcss",
        summary: "blocker search, penumbra w = (d_r − d_b)·w_light/d_b, PCF over w",
        source: "Fernando 2005, \"Percentage-Closer Soft Shadows\", SIGGRAPH sketch",
        default: || {
            Shadow::new(ShadowTechnique::Pcss {
                blocker_samples: 16,
                filter_samples: 32,
                light_size: None,
                blocker_depth: BlockerDepth::Search,
            })
        },
        params: &[
            Param {
                name: "blocker_samples",
                kind: TAPS,
                unit: "",
                doc: "Poisson taps of the blocker search",
                source: "",
                unset: "",
                get: |s| match s.technique {
                    ShadowTechnique::Pcss {
                        blocker_samples, ..
                    } => Some(Value::Whole(blocker_samples)),
                    _ => None,
                },
                set: |s, v| match &mut s.technique {
                    ShadowTechnique::Pcss {
                        blocker_samples, ..
                    } => { *blocker_samples = v.whole()?; Some(()) },
                    _ => None,
                },
            },
            Param {
                name: "filter_samples",
                kind: TAPS,
                unit: "",
                doc: "Poisson taps of the penumbra-sized PCF",
                source: "",
                unset: "",
                get: |s| match s.technique {
                    ShadowTechnique::Pcss { filter_samples, .. } => Some(Value::Whole(filter_samples)),
                    _ => None,
                },
                set: |s, v| match &mut s.technique {
                    ShadowTechnique::Pcss { filter_samples, .. } => { *filter_samples = v.whole()?; Some(()) },
                    _ => None,
                },
            },
            Param {
                name: "light_size",
                kind: Kind::Real(0.0, 1e6),
                unit: "m (degrees of angular diameter for directional lights)",
                doc: "w_light of the penumbra estimate",
                source: "",
                unset: "each light's own: a rectangle's larger side, a disk's or sphere's diameter, \
                        a sun disk's angular diameter, 0 for point and spot lights",
                get: |s| match s.technique {
                    ShadowTechnique::Pcss { light_size, .. } => light_size.map(Value::Real),
                    _ => None,
                },
                set: |s, v| match &mut s.technique {
                    ShadowTechnique::Pcss { light_size, .. } => { *light_size = Some(v.real()?); Some(()) },
                    _ => None,
                },
            },
            Param {
                name: "blocker_depth",
                kind: Kind::Keyword(&["search", "ignore"]),
                unit: "",
                doc: "search: the blockers' mean depth; ignore: half the receiver depth, \
                      the deliberately broken PCSS (a test device for thresholds)",
                source: "",
                unset: "",
                get: |s| match s.technique {
                    ShadowTechnique::Pcss { blocker_depth, .. } => Some(Value::Keyword(match blocker_depth {
                        BlockerDepth::Search => "search",
                        BlockerDepth::Ignore => "ignore",
                    })),
                    _ => None,
                },
                set: |s, v| match &mut s.technique {
                    ShadowTechnique::Pcss { blocker_depth, .. } => {
                        *blocker_depth = match v.keyword()? {
                            "search" => BlockerDepth::Search,
                            _ => BlockerDepth::Ignore,
                        };
                        Some(())
                    }
                    _ => None,
                },
            },
            RECEIVER_PLANE,
            ROTATE,
        ],
    },
];

/// The shadow-mapping family.
pub struct ShadowMapping;

impl Family for ShadowMapping {
    fn title(&self) -> &'static str {
        "Shadow maps"
    }

    fn methods(&self) -> Vec<MethodInfo> {
        MethodInfo::of(METHODS)
    }

    /// Over N×N quadrature with n = 8, env_n = 0.
    fn method(&self, name: &str) -> Option<Method> {
        Method::from_table(METHODS, name, 0)
    }

    fn shared_rows(&self) -> Vec<Row> {
        Row::all(COMMON)
    }

    fn wgsl_codes(&self) -> String {
        wgsl_method_codes("SHADOW_", Some("NONE"), METHODS)
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("shadow/map_common.wgsl", include_str!("map_common.wgsl")),
            ("shadow/hard.wgsl", include_str!("hard.wgsl")),
            ("shadow/pcf.wgsl", include_str!("pcf.wgsl")),
            ("shadow/pcss.wgsl", include_str!("pcss.wgsl")),
            ("shadow/visibility.wgsl", include_str!("visibility.wgsl")),
        ]
    }
}

impl Settings for Shadow {
    fn method_name(&self) -> &'static str {
        self.technique.name()
    }

    fn rows(&self) -> Vec<Row> {
        Row::all(Shadow::rows(self))
    }

    fn overrides(&self) -> Vec<Override> {
        vec![Override::shading("SHADOW_METHOD", self.technique.shader_code())]
    }

    fn check(&self, method: &Method, frame: &Frame<'_>) -> Result<(), String> {
        if self.map > frame.max_texture_side {
            return Err(format!(
                "method {method}: map = {} exceeds the adapter's {} texels per side",
                self.map, frame.max_texture_side
            ));
        }
        Ok(())
    }

    /// One Depth32Float layer of `map`² per light (the budget check's estimate).
    fn bytes(&self) -> u64 {
        u64::from(self.map).pow(2) * 4
    }
}
