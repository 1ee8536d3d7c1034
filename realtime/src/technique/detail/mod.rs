//! Surface detail: the techniques that imitate a displaced surface (scenes `displacement`) on
//! its flat base, their parameters, and the maps they precompute from the height texture.
//!
//! Every technique reads the shape's own height texture h (the oracle traces exactly the
//! surface p + s·h·n it defines, docs/ARCHITECTURE.md "Ground truth is defined per effect", surface detail), in metres
//! w = k·s·h with s the displacement's `scale` and k the method's `height_scale` (1: the true
//! heights). The base surface is drawn as it is; per fragment the technique finds the point
//! of the displaced surface the camera ray sees (or pretends to) and its normal
//! (`technique/detail/*.wgsl`, one file per kind of search).
//!
//! The methods, their papers and their parameters with ranges and defaults are [`METHODS`]
//! and [`COMMON`], the tables `verity raster --help` and docs/methods.md are made from.
//!
//! Shapes without displacement are drawn as
//! under `area_quadrature`; displaced shapes under any other method are drawn flat (their
//! base surface), the "no detail" baseline. Shadow maps are not combined with detail methods:
//! self-shadowing is the heightfield's own (`pom`'s `self_shadow`).

use std::collections::HashMap;
use std::fmt;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex};

use scenes::texture::Texture;

use super::method::{wgsl_method_codes, Family, Method, MethodInfo, Override, Row, Settings, UniformBlock};
use super::param::{spec_named, Kind, MethodSpec, Param, Value};
use cone_map::{cone_map, ConeKind};
use horizon_map::{horizon_maps, MAX_HORIZON_DIRECTIONS};

pub mod cone_map;
pub mod horizon_map;

/// Most linear-search steps (`steps`, `min_steps`, `max_steps`, `shadow_steps`).
pub const MAX_DETAIL_STEPS: u32 = 256;
/// Most binary-search halvings (`binary_steps`).
pub const MAX_BINARY_STEPS: u32 = 16;

/// A surface-detail technique and its own parameters (WGSL `DETAIL_METHOD`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DetailTechnique {
    /// `normal_mapping`: the derivative map of h, bilinearly filtered.
    NormalMapping,
    /// `bump_mapping`: h differenced at run time.
    BumpMapping {
        /// Forward-difference step in texels.
        delta: f32,
    },
    /// `parallax`: Kaneko et al. 2001, with Welsh's scale and bias.
    Parallax {
        /// Bias as a fraction of the height range (w + bias·(w_max − w_min)).
        bias: f32,
    },
    /// `parallax_offset_limited`: Welsh 2004.
    ParallaxOffsetLimited {
        /// As [`DetailTechnique::Parallax`].
        bias: f32,
    },
    /// `steep_parallax`: McGuire & McGuire 2005.
    SteepParallax {
        /// Layers of the linear search.
        steps: u32,
    },
    /// `relief_mapping`: Policarpo, Oliveira & Comba 2005.
    ReliefMapping {
        /// Layers of the linear search.
        steps: u32,
        /// Halvings of the binary search.
        binary_steps: u32,
    },
    /// `pom`: Tatarchuk 2006.
    Pom {
        /// Layers at normal incidence.
        min_steps: u32,
        /// Layers at grazing incidence.
        max_steps: u32,
        /// Trace the heightfield towards each light.
        self_shadow: bool,
        /// Samples of that shadow ray.
        shadow_steps: u32,
    },
    /// `cone_step`: Dummer 2006; relaxed cones Policarpo & Oliveira 2007.
    ConeStep {
        /// Cone steps.
        steps: u32,
        /// Relaxed cones (then a binary search) instead of conservative ones.
        relaxed: bool,
        /// Halvings of the relaxed variant's binary search.
        binary_steps: u32,
    },
}

impl DetailTechnique {
    /// The value of the WGSL override constant `DETAIL_METHOD`: 1 + its index in [`METHODS`]
    /// (0 is "flat base").
    pub fn shader_code(self) -> u32 {
        match self {
            DetailTechnique::NormalMapping => 1,
            DetailTechnique::BumpMapping { .. } => 2,
            DetailTechnique::Parallax { .. } => 3,
            DetailTechnique::ParallaxOffsetLimited { .. } => 4,
            DetailTechnique::SteepParallax { .. } => 5,
            DetailTechnique::ReliefMapping { .. } => 6,
            DetailTechnique::Pom { .. } => 7,
            DetailTechnique::ConeStep { .. } => 8,
        }
    }

    /// The method name.
    pub fn name(self) -> &'static str {
        self.spec().name
    }

    /// Its row of [`METHODS`].
    pub fn spec(self) -> &'static MethodSpec<Detail> {
        &METHODS[self.shader_code() as usize - 1]
    }

    /// The cone map this technique reads, if any.
    pub fn cone_kind(self) -> Option<ConeKind> {
        match self {
            DetailTechnique::ConeStep { relaxed: true, .. } => Some(ConeKind::Relaxed),
            DetailTechnique::ConeStep { relaxed: false, .. } => Some(ConeKind::Conservative),
            _ => None,
        }
    }
}

/// A surface-detail method: the technique and the height multiplier every technique shares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detail {
    /// How the displaced surface is imitated.
    pub technique: DetailTechnique,
    /// k in w = k·s·h (1: the displacement's own heights).
    pub height_scale: f32,
    /// Azimuths of the horizon map that shadows `normal_mapping` and `bump_mapping` (Max
    /// 1988; 0: none).
    pub horizon: u32,
}

impl Detail {
    /// `technique` at the true heights.
    pub fn new(technique: DetailTechnique) -> Detail {
        Detail {
            technique,
            height_scale: 1.0,
            horizon: 0,
        }
    }

    /// The method called `name` with its defaults.
    pub fn by_name(name: &str) -> Option<Detail> {
        spec_named(METHODS, name).map(|spec| (spec.default)())
    }

    /// Its parameter rows: [`COMMON`], then its technique's own.
    pub fn rows(&self) -> impl Iterator<Item = &'static Param<Detail>> {
        COMMON.iter().chain(self.technique.spec().params)
    }

    /// Its block of the frame uniform.
    pub fn uniforms(&self) -> DetailUniforms {
        let base = DetailUniforms {
            height_scale: self.height_scale,
            ..DetailUniforms::FLAT
        };
        match self.technique {
            DetailTechnique::NormalMapping => DetailUniforms {
                horizon_azimuths: self.horizon,
                ..base
            },
            DetailTechnique::BumpMapping { delta } => DetailUniforms {
                bump_delta: delta,
                horizon_azimuths: self.horizon,
                ..base
            },
            DetailTechnique::Parallax { bias } | DetailTechnique::ParallaxOffsetLimited { bias } => {
                DetailUniforms {
                    parallax_bias: bias,
                    ..base
                }
            }
            DetailTechnique::SteepParallax { steps } => DetailUniforms {
                steps,
                max_steps: steps,
                ..base
            },
            DetailTechnique::ReliefMapping { steps, binary_steps } => DetailUniforms {
                steps,
                max_steps: steps,
                binary_steps,
                ..base
            },
            DetailTechnique::Pom {
                min_steps,
                max_steps,
                self_shadow,
                shadow_steps,
            } => DetailUniforms {
                steps: min_steps,
                max_steps,
                shadow_steps: if self_shadow { shadow_steps } else { 0 },
                ..base
            },
            DetailTechnique::ConeStep {
                steps,
                relaxed,
                binary_steps,
            } => DetailUniforms {
                steps,
                max_steps: steps,
                binary_steps: if relaxed { binary_steps } else { 0 },
                ..base
            },
        }
    }
}

/// The surface-detail family's block of the frame uniform (WGSL `DetailUniforms`,
/// detail/common.wgsl; `frame.families.detail`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct DetailUniforms {
    /// k in w = k·s·h.
    pub height_scale: f32,
    /// Parallax mapping's bias, in units of the height range.
    pub parallax_bias: f32,
    /// Bump mapping's finite-difference step, texels.
    pub bump_delta: f32,
    /// Azimuths of the horizon map (0: none).
    pub horizon_azimuths: u32,
    /// Linear steps (POM: at normal incidence; cone stepping: its cone steps).
    pub steps: u32,
    /// POM's steps at grazing incidence (the others: `steps`).
    pub max_steps: u32,
    /// Halvings of the binary search (cone stepping: relaxed cones when > 0).
    pub binary_steps: u32,
    /// POM's self-shadow samples (0: no self-shadowing).
    pub shadow_steps: u32,
}

impl DetailUniforms {
    /// A method without surface detail: displaced shapes drawn flat.
    pub const FLAT: DetailUniforms = DetailUniforms {
        height_scale: 1.0,
        parallax_bias: 0.0,
        bump_delta: 1.0,
        horizon_azimuths: 0,
        steps: 0,
        max_steps: 0,
        binary_steps: 0,
        shadow_steps: 0,
    };
}

impl fmt::Display for Detail {
    /// `name` (the technique's; its parameters are listed by [`crate::Method`]).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.technique.name())
    }
}

/// The parameter every detail method shares (`n` and `env_n` are every method's; the detail
/// methods default to n = 8, env_n = 8).
pub static COMMON: &[Param<Detail>] = &[Param {
    name: "height_scale",
    kind: Kind::Real(0.0, 10.0),
    unit: "",
    doc: "k in w = k·s·h: multiplies the displacement's heights (1: the true surface)",
    source: "",
    unset: "",
    get: |d| Some(Value::Real(d.height_scale)),
    set: |d, v| {
        d.height_scale = v.real()?;
        Some(())
    },
}];

/// `steps` of the searching techniques.
fn steps(d: &Detail) -> Option<Value> {
    match d.technique {
        DetailTechnique::SteepParallax { steps }
        | DetailTechnique::ReliefMapping { steps, .. }
        | DetailTechnique::ConeStep { steps, .. } => Some(Value::Whole(steps)),
        _ => None,
    }
}

fn set_steps(d: &mut Detail, v: Value) -> Option<()> {
    match &mut d.technique {
        DetailTechnique::SteepParallax { steps }
        | DetailTechnique::ReliefMapping { steps, .. }
        | DetailTechnique::ConeStep { steps, .. } => *steps = v.whole()?,
        _ => return None,
    }
    Some(())
}

/// `binary_steps` of relief mapping and relaxed cone stepping.
const BINARY_STEPS: Param<Detail> = Param {
    name: "binary_steps",
    kind: Kind::Whole(0, MAX_BINARY_STEPS),
    unit: "",
    doc: "halvings of the final binary search",
    source: "",
    unset: "",
    get: |d| match d.technique {
        DetailTechnique::ReliefMapping { binary_steps, .. }
        | DetailTechnique::ConeStep { binary_steps, .. } => Some(Value::Whole(binary_steps)),
        _ => None,
    },
    set: |d, v| {
        match &mut d.technique {
            DetailTechnique::ReliefMapping { binary_steps, .. }
            | DetailTechnique::ConeStep { binary_steps, .. } => *binary_steps = v.whole()?,
            _ => return None,
        }
        Some(())
    },
};

/// `horizon` of the methods that keep the base point (normal and bump mapping).
const HORIZON: Param<Detail> = Param {
    name: "horizon",
    kind: Kind::Whole(0, MAX_HORIZON_DIRECTIONS),
    unit: "azimuths",
    doc: "self-shadowing from a precomputed horizon map: per texel the horizon's elevation in this many azimuths, \
          interpolated between them; heightfield patches (rectangles) only",
    source: "Max 1988, \"Horizon Mapping: Shadows for Bump-Mapped Surfaces\"; Sloan & Cohen 2000, EGWR",
    unset: "0: no self-shadowing",
    get: |d| match d.technique {
        DetailTechnique::NormalMapping | DetailTechnique::BumpMapping { .. } if d.horizon > 0 => {
            Some(Value::Whole(d.horizon))
        }
        _ => None,
    },
    set: |d, v| match d.technique {
        DetailTechnique::NormalMapping | DetailTechnique::BumpMapping { .. } => {
            d.horizon = v.whole()?;
            Some(())
        }
        _ => None,
    },
};

/// `bias` of the parallax offsets.
const PARALLAX_BIAS: Param<Detail> = Param {
    name: "bias",
    kind: Kind::Real(-1.0, 1.0),
    unit: "of the height range",
    doc: "Welsh's scale-and-bias bias: heights read as w + bias·(w_max − w_min)",
    source: "Welsh 2004",
    unset: "",
    get: |d| match d.technique {
        DetailTechnique::Parallax { bias } | DetailTechnique::ParallaxOffsetLimited { bias } => {
            Some(Value::Real(bias))
        }
        _ => None,
    },
    set: |d, v| {
        match &mut d.technique {
            DetailTechnique::Parallax { bias } | DetailTechnique::ParallaxOffsetLimited { bias } => {
                *bias = v.real()?
            }
            _ => return None,
        }
        Some(())
    },
};

/// The linear-search layer counts.
const STEPS: Kind = Kind::Whole(1, MAX_DETAIL_STEPS);

/// The POM parameters, read and written by name.
/// `pom`'s own parameters (min_steps, max_steps, self_shadow, shadow_steps), None for another
/// technique.
fn pom(d: &mut Detail) -> Option<(&mut u32, &mut u32, &mut bool, &mut u32)> {
    match &mut d.technique {
        DetailTechnique::Pom {
            min_steps,
            max_steps,
            self_shadow,
            shadow_steps,
        } => Some((min_steps, max_steps, self_shadow, shadow_steps)),
        _ => None,
    }
}

/// The surface-detail methods, in `DETAIL_METHOD` order (1, 2, …).
pub static METHODS: &[MethodSpec<Detail>] = &[
    MethodSpec {
        name: "normal_mapping",
        summary: "the base point, shaded with the normal of a normal map baked from h (a derivative map); 4 fetches",
        source: "Mikkelsen 2010, \"Bump Mapping Unparametrized Surfaces on the GPU\", JGT 15(1)",
        default: || Detail::new(DetailTechnique::NormalMapping),
        params: &[HORIZON],
    },
    MethodSpec {
        name: "bump_mapping",
        summary: "the base point, normal from forward differences of h; 12 fetches",
        source: "Blinn 1978, \"Simulation of Wrinkled Surfaces\", SIGGRAPH",
        default: || Detail::new(DetailTechnique::BumpMapping { delta: 1.0 }),
        params: &[Param {
            name: "delta",
            kind: Kind::Real(0.01, 16.0),
            unit: "texels",
            doc: "forward-difference step",
            source: "",
            unset: "",
            get: |d| match d.technique {
                DetailTechnique::BumpMapping { delta } => Some(Value::Real(delta)),
                _ => None,
            },
            set: |d, v| match &mut d.technique {
                DetailTechnique::BumpMapping { delta } => {
                    *delta = v.real()?;
                    Some(())
                }
                _ => None,
            },
        }, HORIZON],
    },
    MethodSpec {
        name: "parallax",
        summary: "uv + the offset to the height seen at uv, scale and bias; 8 fetches",
        source: "Kaneko et al. 2001, \"Detailed Shape Representation with Parallax Mapping\", ICAT",
        default: || Detail::new(DetailTechnique::Parallax { bias: 0.0 }),
        params: &[PARALLAX_BIAS],
    },
    MethodSpec {
        name: "parallax_offset_limited",
        summary: "the parallax offset × cos θ, bounded by the height; 8 fetches",
        source: "Welsh 2004, \"Parallax Mapping with Offset Limiting\", Infiscape technical report",
        default: || Detail::new(DetailTechnique::ParallaxOffsetLimited { bias: 0.0 }),
        params: &[PARALLAX_BIAS],
    },
    MethodSpec {
        name: "steep_parallax",
        summary: "linear search, the first layer below the surface; 4·(k + 1) + 4 fetches",
        source: "McGuire & McGuire 2005, \"Steep Parallax Mapping\", I3D poster",
        default: || Detail::new(DetailTechnique::SteepParallax { steps: 16 }),
        params: &[Param {
            name: "steps",
            kind: STEPS,
            unit: "",
            doc: "layers of the linear search",
            source: "",
            unset: "",
            get: steps,
            set: set_steps,
        }],
    },
    MethodSpec {
        name: "relief_mapping",
        summary: "linear then binary search; 4·(k + b + 1) + 4 fetches",
        source: "Policarpo, Oliveira & Comba 2005, \"Real-Time Relief Mapping on Arbitrary Polygonal Surfaces\", I3D",
        default: || {
            Detail::new(DetailTechnique::ReliefMapping {
                steps: 16,
                binary_steps: 6,
            })
        },
        params: &[
            Param {
                name: "steps",
                kind: STEPS,
                unit: "",
                doc: "layers of the linear search",
                source: "",
                unset: "",
                get: steps,
                set: set_steps,
            },
            BINARY_STEPS,
        ],
    },
    MethodSpec {
        name: "pom",
        summary: "view-dependent linear search, secant between the last two samples, optional self-shadowing; \
                  4·(k + 1) + 4 fetches (+ shadows)",
        source: "Tatarchuk 2006, \"Dynamic Parallax Occlusion Mapping with Approximate Soft Shadows\", I3D",
        default: || {
            Detail::new(DetailTechnique::Pom {
                min_steps: 8,
                max_steps: 32,
                self_shadow: false,
                shadow_steps: 16,
            })
        },
        params: &[
            Param {
                name: "min_steps",
                kind: STEPS,
                unit: "",
                doc: "layers at normal incidence",
                source: "",
                unset: "",
                get: |d| pom(&mut d.clone()).map(|p| Value::Whole(*p.0)),
                set: |d, v| {
                    *pom(d)?.0 = v.whole()?;
                    Some(())
                },
            },
            Param {
                name: "max_steps",
                kind: STEPS,
                unit: "",
                doc: "layers at grazing incidence",
                source: "",
                unset: "",
                get: |d| pom(&mut d.clone()).map(|p| Value::Whole(*p.1)),
                set: |d, v| {
                    *pom(d)?.1 = v.whole()?;
                    Some(())
                },
            },
            Param {
                name: "self_shadow",
                kind: Kind::Switch,
                unit: "",
                doc: "trace the heightfield towards each light (soft for sun disks and area lights; patches only)",
                source: "",
                unset: "",
                get: |d| pom(&mut d.clone()).map(|p| Value::Switch(*p.2)),
                set: |d, v| {
                    *pom(d)?.2 = v.switch()?;
                    Some(())
                },
            },
            Param {
                name: "shadow_steps",
                kind: STEPS,
                unit: "",
                doc: "samples of that shadow ray",
                source: "",
                unset: "",
                get: |d| pom(&mut d.clone()).map(|p| Value::Whole(*p.3)),
                set: |d, v| {
                    *pom(d)?.3 = v.whole()?;
                    Some(())
                },
            },
        ],
    },
    MethodSpec {
        name: "cone_step",
        summary: "steps to the edge of empty cones from a cone map; relaxed cones then a binary search; \
                  8·k + 4 fetches (relaxed: + 4·(b + 1))",
        source: "Dummer 2006, \"Cone Step Mapping: An Iterative Ray-Heightfield Intersection Algorithm\"; \
                 relaxed: Policarpo & Oliveira 2007, GPU Gems 3 ch. 18",
        default: || {
            Detail::new(DetailTechnique::ConeStep {
                steps: 32,
                relaxed: false,
                binary_steps: 6,
            })
        },
        params: &[
            Param {
                name: "steps",
                kind: STEPS,
                unit: "",
                doc: "cone steps",
                source: "",
                unset: "",
                get: steps,
                set: set_steps,
            },
            Param {
                name: "relaxed",
                kind: Kind::Switch,
                unit: "",
                doc: "relaxed cones (then the binary search) instead of conservative ones",
                source: "Policarpo & Oliveira 2007",
                unset: "",
                get: |d| match d.technique {
                    DetailTechnique::ConeStep { relaxed, .. } => Some(Value::Switch(relaxed)),
                    _ => None,
                },
                set: |d, v| match &mut d.technique {
                    DetailTechnique::ConeStep { relaxed, .. } => {
                        *relaxed = v.switch()?;
                        Some(())
                    }
                    _ => None,
                },
            },
            BINARY_STEPS,
        ],
    },
];

/// The normal map of `normal_mapping`, baked from channel `channel` of a height texture: per
/// texel the central differences (∂h/∂u, ∂h/∂v) ≈ ((h[i+1] − h[i−1])·W/2, (h[j+1] − h[j−1])·H/2)
/// in units of h per unit of uv (RG; B = 0, A = 1), neighbours taken under the texture's wrap
/// modes. Stored as derivatives rather than unit normals (a derivative map, Mikkelsen 2010,
/// "Bump Mapping Unparametrized Surfaces on the GPU", JGT 15(1)) so that one map serves every
/// uv scale and height multiplier; the shader turns it into a normal by Blinn's formula.
pub fn derivative_map(height: &Texture, channel: usize) -> Texture {
    let (w, h) = (height.width as i64, height.height as i64);
    let mut texels = Vec::with_capacity((w * h) as usize);
    for j in 0..h {
        for i in 0..w {
            let at = |a: i64, b: i64| height.texel(a, b)[channel];
            let du = (at(i + 1, j) - at(i - 1, j)) * 0.5 * w as f32;
            let dv = (at(i, j + 1) - at(i, j - 1)) * 0.5 * h as f32;
            texels.push(glam::Vec4::new(du, dv, 0.0, 1.0));
        }
    }
    Texture::from_texels(height.width, height.height, texels, height.wrap)
}

/// The cone map of channel `channel` of a height texture under displacement `scale` (metres
/// per unit h): [`cone_map`] of w = scale·h, one ratio (uv per metre) per texel in R (GBA 0, 1).
pub fn cone_texture(height: &Texture, channel: usize, scale: f32, kind: ConeKind) -> Texture {
    let w: Vec<f32> = height.texels.iter().map(|t| t[channel] * scale).collect();
    let ratios = cone_map(&w, height.width, height.height, height.wrap, kind);
    let texels = ratios
        .iter()
        .map(|&c| glam::Vec4::new(c, 0.0, 0.0, 1.0))
        .collect();
    Texture::from_texels(height.width, height.height, texels, height.wrap)
}

/// Cone and horizon maps already built, keyed by a hash of the heights and arguments they were
/// built from, so that a study rendering one scene many times pays for each map once (a 512²
/// cone map takes seconds).
#[derive(Default)]
pub struct ConeCache {
    maps: Mutex<HashMap<u64, Arc<Vec<Texture>>>>,
}

impl ConeCache {
    /// The maps `build` makes from channel `channel` of `height`, built on first use for these
    /// `arguments` (every input besides the heights, as bits).
    fn cached(
        &self,
        height: &Texture,
        channel: usize,
        arguments: &[u32],
        build: impl FnOnce() -> Vec<Texture>,
    ) -> Arc<Vec<Texture>> {
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        (
            height.width,
            height.height,
            format!("{:?}", height.wrap),
            channel,
            arguments,
        )
            .hash(&mut hasher);
        for t in &height.texels {
            t[channel].to_bits().hash(&mut hasher);
        }
        let key = hasher.finish();
        let mut maps = self.maps.lock().unwrap_or_else(|e| e.into_inner());
        maps.entry(key).or_insert_with(|| Arc::new(build())).clone()
    }

    /// The [`cone_texture`] of these arguments.
    pub fn get(&self, height: &Texture, channel: usize, scale: f32, kind: ConeKind) -> Arc<Vec<Texture>> {
        self.cached(height, channel, &[0, scale.to_bits(), kind as u32], || {
            vec![cone_texture(height, channel, scale, kind)]
        })
    }

    /// The [`horizon_maps`] of these arguments.
    pub fn horizon(
        &self,
        height: &Texture,
        channel: usize,
        scale: f32,
        size: glam::Vec2,
        directions: u32,
    ) -> Arc<Vec<Texture>> {
        let arguments = [1, scale.to_bits(), size.x.to_bits(), size.y.to_bits(), directions];
        self.cached(height, channel, &arguments, || {
            horizon_maps(height, channel, scale, size, directions)
        })
    }
}

/// The surface-detail family.
pub struct SurfaceDetail;

impl Family for SurfaceDetail {
    fn title(&self) -> &'static str {
        "Surface detail"
    }

    fn methods(&self) -> Vec<MethodInfo> {
        MethodInfo::of(METHODS)
    }

    /// Over N×N quadrature (n = 8, env_n = 8), unshadowed.
    fn method(&self, name: &str) -> Option<Method> {
        Detail::by_name(name).map(|d| Method::of(d, 8))
    }

    fn shared_rows(&self) -> Vec<Row> {
        Row::all(COMMON)
    }

    fn wgsl_codes(&self) -> String {
        wgsl_method_codes("DETAIL_", Some("FLAT"), METHODS)
    }

    fn uniforms(&self) -> Option<UniformBlock> {
        Some(UniformBlock {
            field: "detail",
            wgsl_type: "DetailUniforms",
            size: std::mem::size_of::<DetailUniforms>(),
            bytes: |m| {
                let u = m.get::<Detail>().map_or(DetailUniforms::FLAT, Detail::uniforms);
                bytemuck::bytes_of(&u).to_vec()
            },
        })
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("detail/common.wgsl", include_str!("common.wgsl")),
            ("detail/normal.wgsl", include_str!("normal.wgsl")),
            ("detail/parallax.wgsl", include_str!("parallax.wgsl")),
            ("detail/ray_march.wgsl", include_str!("ray_march.wgsl")),
            ("detail/cone_step.wgsl", include_str!("cone_step.wgsl")),
            ("detail/horizon.wgsl", include_str!("horizon.wgsl")),
        ]
    }
}

impl Settings for Detail {
    fn method_name(&self) -> &'static str {
        self.technique.name()
    }

    fn rows(&self) -> Vec<Row> {
        Row::all(Detail::rows(self))
    }

    /// `DETAIL_METHOD`, in every pipeline that draws the view: it moves the surface.
    fn overrides(&self) -> Vec<Override> {
        vec![Override::geometry("DETAIL_METHOD", self.technique.shader_code())]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;
    use scenes::WrapMode;

    #[test]
    fn names_round_trip_and_codes_are_distinct() {
        for (k, spec) in METHODS.iter().enumerate() {
            let d = Detail::by_name(spec.name).unwrap();
            assert_eq!(d.technique.name(), spec.name);
            assert_eq!(d.technique.shader_code() as usize, k + 1);
            // Every row has a default, or says what unset means.
            for row in d.rows() {
                assert!(
                    (row.get)(&d).is_some() || !row.unset.is_empty(),
                    "{}: {} has no default",
                    spec.name,
                    row.name
                );
            }
        }
        assert!(Detail::by_name("displacement").is_none());
    }

    /// The derivative map of a linear ramp h = a·u + b·v (away from the wrap seam) is (a, b).
    #[test]
    fn derivative_map_of_a_ramp_is_its_slope() {
        let (w, h) = (8u32, 4u32);
        let texels = (0..w * h)
            .map(|k| {
                let u = ((k % w) as f32 + 0.5) / w as f32;
                let v = ((k / w) as f32 + 0.5) / h as f32;
                let x = 0.3 * u - 0.7 * v;
                Vec4::new(x, x, x, 1.0)
            })
            .collect();
        let t = Texture::from_texels(w, h, texels, [WrapMode::Clamp; 2]);
        let d = derivative_map(&t, 0);
        let inner = d.texel(3, 2);
        assert!(
            (inner.x - 0.3).abs() < 1e-5 && (inner.y + 0.7).abs() < 1e-5,
            "{inner}"
        );
        // At a clamped border the difference is one-sided over two texel spacings: half slope.
        let edge = d.texel(0, 2);
        assert!((edge.x - 0.15).abs() < 1e-5, "{edge}");
    }
}
