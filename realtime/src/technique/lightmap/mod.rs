//! Light maps: diffuse lighting precomputed per texel of a second parameterization of every
//! static surface and looked up at render time (technique/lightmap/lookup.wgsl). The map holds
//! the irradiance E (W/m²) of each texel centre, direct and indirect, as the oracle bakes it
//! (`oracle::bake`, `verity bake`; scenes::lightmap defines the charts and the atlas); a static
//! diffuse surface of albedo ρ leaves L_o = ρ/π · E, exactly what the ground truth's `path`
//! integrator computes at a texel centre. The realtime side reads the baked file and never
//! bakes: the methods' bake parameters (resolution, samples, padding, texel offset, the
//! dynamic shapes) say which map they read, and `verity report` bakes it (cached) before the
//! render.
//!
//! Failure modes, each a study (scenes/studies/lightmap-*.toml): shadow edges finer than a
//! texel blur, and at high resolution and few samples per texel the map is noisy; a map baked
//! at the texel corners instead of the centres (`texel_offset = 0.5`, the classic half-texel
//! bug) shifts every feature by half a texel; bilinear lookups across a chart's border read
//! padding, so a surface split into two charts shows a seam; a texel that spans a thin wall
//! averages both sides (light leaks); a glossy lobe is view-dependent and not in a diffuse map;
//! a dynamic object neither is lit by the map nor shadows it (it is shaded per pixel by the
//! usual direct-light methods and lacks its indirect light).
//!
//! Lookup: bilinear (the sampler's own filter over the texels) or the bicubic B-spline
//! (Sigg & Hadwiger 2005, "Fast Third-Order Texture Filtering", GPU Gems 2 ch. 20), smoother
//! across texels but not interpolating: at a texel centre it returns (E₋₁ + 4E₀ + E₊₁)/6 along
//! each axis, a blur of one texel that shows in a shadow edge's width.

use super::method::{wgsl_method_codes, Family, Method, MethodInfo, Override, Row, Settings};
use super::param::{Kind, MethodSpec, Param, Value};

/// How the atlas is read between texel centres (WGSL `LIGHTMAP_METHOD`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LightMapFilter {
    /// Four texels, bilinear weights.
    Bilinear,
    /// Sixteen texels, cubic B-spline weights.
    Bicubic,
}

/// A light-map method: its lookup, and the bake it reads.
#[derive(Clone, Debug, PartialEq)]
pub struct LightMapMethod {
    /// The lookup.
    pub filter: LightMapFilter,
    /// Texels along each chart's longer side.
    pub resolution: u32,
    /// Samples per texel of the bake.
    pub spp: u32,
    /// Texels of padding around each chart (filled by dilation).
    pub padding: u32,
    /// Where in each texel the bake takes its irradiance, in texels from the centre.
    pub texel_offset: f32,
    /// Shapes left out of the bake (a glob over shape names, `scenes::glob`), or None: every
    /// shape is static.
    pub dynamic: Option<String>,
    /// Add the specular lobes' direct light per pixel (engines' usual complement of a diffuse
    /// light map: every light, unshadowed, as the per-pixel methods shade it).
    pub direct_specular: bool,
    /// The bake's path depth (Mitsuba semantics), not a parameter: a study's ground truth
    /// sets it (`verity report` bakes the map with the depth it measures against), so that it
    /// is part of the render request; None for a map read from a file.
    pub max_depth: Option<i32>,
}

impl LightMapMethod {
    /// The WGSL override `LIGHTMAP_METHOD`: 1 + its index in [`METHODS`] (0: no light map).
    pub fn shader_code(&self) -> u32 {
        match self.filter {
            LightMapFilter::Bilinear => 1,
            LightMapFilter::Bicubic => 2,
        }
    }

    /// The method's row in [`METHODS`].
    pub fn spec(&self) -> &'static MethodSpec<LightMapMethod> {
        &METHODS[self.shader_code() as usize - 1]
    }

    /// Its parameter rows (all shared: [`COMMON`]).
    pub fn rows(&self) -> impl Iterator<Item = &'static Param<LightMapMethod>> {
        COMMON.iter().chain(self.spec().params.iter())
    }

    fn with(filter: LightMapFilter) -> LightMapMethod {
        LightMapMethod {
            filter,
            resolution: 64,
            spp: 256,
            padding: 2,
            texel_offset: 0.0,
            dynamic: None,
            direct_specular: false,
            max_depth: None,
        }
    }
}

/// Largest chart side a light-map method names (scenes::lightmap::MAX_RESOLUTION).
const MAX_RESOLUTION: u32 = scenes::lightmap::MAX_RESOLUTION;

/// The parameters every light-map method has: those of the bake it reads.
pub static COMMON: &[Param<LightMapMethod>] = &[
    Param {
        name: "resolution",
        kind: Kind::Whole(1, MAX_RESOLUTION),
        unit: "texels",
        doc: "texels along each chart's longer side (the other side keeps the aspect ratio)",
        source: "",
        unset: "",
        get: |m| Some(Value::Whole(m.resolution)),
        set: |m, v| {
            m.resolution = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "spp",
        kind: Kind::Whole(1, 1 << 20),
        unit: "samples per texel",
        doc: "paths traced per texel by the bake (its noise is reported with it)",
        source: "",
        unset: "",
        get: |m| Some(Value::Whole(m.spp)),
        set: |m, v| {
            m.spp = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "padding",
        kind: Kind::Whole(0, 64),
        unit: "texels",
        doc: "texels around each chart in the atlas, filled by dilation from the chart's border",
        source: "",
        unset: "",
        get: |m| Some(Value::Whole(m.padding)),
        set: |m, v| {
            m.padding = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "texel_offset",
        kind: Kind::Real(0.0, 1.0),
        unit: "texels",
        doc: "where in each texel the bake takes its irradiance, from the centre a bilinear lookup reads back \
              (0.5: at the texel's corner, the classic half-texel bug)",
        source: "",
        unset: "",
        get: |m| Some(Value::Real(m.texel_offset)),
        set: |m, v| {
            m.texel_offset = v.real()?;
            Some(())
        },
    },
    Param {
        name: "specular",
        kind: Kind::Keyword(&["none", "direct"]),
        unit: "",
        doc: "the specular lobes of light-mapped surfaces: none (the map holds diffuse light only), or every light's \
              direct specular added per pixel, unshadowed (the engines' usual complement)",
        source: "",
        unset: "",
        get: |m| Some(Value::Keyword(if m.direct_specular { "direct" } else { "none" })),
        set: |m, v| {
            m.direct_specular = v.keyword()? == "direct";
            Some(())
        },
    },
    Param {
        name: "dynamic",
        kind: Kind::Name,
        unit: "",
        doc: "shapes left out of the bake (a name or glob pattern): shaded per pixel by direct light, they neither \
              receive the map's light nor cast shadows into it",
        source: "",
        unset: "every shape static",
        get: |m| m.dynamic.clone().map(Value::Name),
        set: |m, v| match v {
            Value::Name(n) => {
                m.dynamic = Some(n);
                Some(())
            }
            _ => None,
        },
    },
];

/// The light-map methods.
pub static METHODS: &[MethodSpec<LightMapMethod>] = &[
    MethodSpec {
        name: "lightmap_bilinear",
        summary: "diffuse lighting from the oracle's baked irradiance map × albedo/π, read bilinearly (specular lobes of \
                  static surfaces are lost); dynamic shapes lit per pixel by direct light",
        source: "Quake (1996) light maps; Abrash 1997, \"Graphics Programming Black Book\" ch. 68",
        default: || LightMapMethod::with(LightMapFilter::Bilinear),
        params: &[],
    },
    MethodSpec {
        name: "lightmap_bicubic",
        summary: "as lightmap_bilinear, read with the cubic B-spline over 4×4 texels: smooth across texels, \
                  blurred by one texel",
        source: "Sigg & Hadwiger 2005, \"Fast Third-Order Texture Filtering\", GPU Gems 2 ch. 20",
        default: || LightMapMethod::with(LightMapFilter::Bicubic),
        params: &[],
    },
];

/// A baked light map handed to a render ([`crate::RasterSettings::lightmap`]), with a label
/// saying where it came from (a file, or the bake's settings and scene hash): its `Debug` form
/// prints the label and a digest of the texels, not the texels.
#[derive(Clone, PartialEq)]
pub struct BakedMap {
    /// The atlas and its charts.
    pub map: std::sync::Arc<scenes::lightmap::LightMap>,
    /// Where it came from.
    pub label: String,
}

impl std::fmt::Debug for BakedMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "BakedMap({}, {}x{}, digest {:016x})",
            self.label,
            self.map.layout.width,
            self.map.layout.height,
            self.map.digest()
        )
    }
}

/// The light-map family.
pub struct LightMaps;

impl Family for LightMaps {
    fn title(&self) -> &'static str {
        "Light maps"
    }

    fn methods(&self) -> Vec<MethodInfo> {
        MethodInfo::of(METHODS)
    }

    /// Over N×N quadrature (n = 8, env_n = 8), unshadowed.
    fn method(&self, name: &str) -> Option<Method> {
        Method::from_table(METHODS, name, 8)
    }

    fn shared_rows(&self) -> Vec<Row> {
        Row::all(COMMON)
    }

    fn wgsl_codes(&self) -> String {
        wgsl_method_codes("LIGHTMAP_", Some("NONE"), METHODS)
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[("lightmap/lookup.wgsl", include_str!("lookup.wgsl"))]
    }
}

impl Settings for LightMapMethod {
    fn method_name(&self) -> &'static str {
        self.spec().name
    }

    fn rows(&self) -> Vec<Row> {
        Row::all(LightMapMethod::rows(self))
    }

    /// `LIGHTMAP_METHOD` and `LIGHTMAP_SPECULAR` (0 none, 1 direct).
    fn overrides(&self) -> Vec<Override> {
        vec![
            Override::shading("LIGHTMAP_METHOD", self.shader_code()),
            Override::shading("LIGHTMAP_SPECULAR", u32::from(self.direct_specular)),
        ]
    }
}
