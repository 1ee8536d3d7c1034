//! Texture filtering: how a texture lookup turns a pixel's footprint in texture space into one
//! value. Every material texture (base colour, roughness, metallic, normal map) and the
//! emission a camera ray sees are looked up through the filter the method names; the
//! heightfield searches of surface detail and the emission sampled at a light's quadrature
//! points stay point lookups of level 0 (they are not a pixel's footprint).
//!
//! The ground truth of every filter is the oracle's: the pixel's box filter over the bilinear
//! reconstruction of level 0 (docs/ARCHITECTURE.md "Ground truth is defined per effect"), so
//! each filter here is measured as an approximation of that one integral.
//!
//! **The footprint** is the Jacobian of the texture coordinates with respect to the target's
//! pixel, J = (∂(u,v)/∂x, ∂(u,v)/∂y), from one of two sources (`derivatives`):
//! `hardware` — WGSL `dpdx`/`dpdy`, finite differences over the 2×2 quad of fragments (what
//! `textureSample` uses), wrong where a quad straddles a silhouette; `analytic` — ray
//! differentials (Igehy 1999, "Tracing Ray Differentials", SIGGRAPH; as pbrt-v4 §10.1.1): the
//! neighbouring pixels' camera rays meet the tangent plane at p + ∂p/∂x, p + ∂p/∂y, and
//! ∂p = ∂p/∂u·du + ∂p/∂v·dv is solved for (du, dv) by least squares.
//!
//! **Level of detail** λ = log₂ ρ + `lod_bias`, ρ = max(|J·x̂|, |J·ŷ|) in level-0 texels (the
//! OpenGL 4.6 specification §8.14.1 scale factor). Levels are box-filtered 2×2 reductions
//! (Williams 1983), averaged in linear radiance (`mip_space = linear`) or, for colour textures,
//! in their sRGB encoding (`mip_space = srgb`: the classic mistake, which darkens high-contrast
//! detail as it recedes).
//!
//! | method | lookup | source |
//! |---|---|---|
//! | `tex_nearest` | the level-0 texel under uv | — |
//! | `tex_bilinear` | bilinear at level 0 (the renderer's lookup before this family) | pbrt-v4 §10.4.3 |
//! | `tex_mip_nearest` | bilinear in the nearest level | Williams 1983 |
//! | `tex_trilinear` | bilinear in the two levels around λ, blended | Williams 1983 |
//! | `tex_sat` | the mean over the footprint's bounding box, from a summed-area table | Crow 1984 |
//! | `tex_ripmap` | trilinear in both axes of a RIP map (levels reduced in u and v separately) | — (Microsoft/HP "RIP maps") |
//! | `tex_footprint` | up to `max_anisotropy` trilinear probes along the footprint's major axis | Schilling, Knittel & Straßer 1996 |
//! | `tex_ewa` | Gaussian-weighted texels inside the footprint's ellipse, in the level its minor axis picks | Heckbert 1989; Greene & Heckbert 1986 |
//!
//! | `tex_anisotropic` | the adapter's own anisotropic filtering (`textureSampleGrad` with the footprint, a sampler of `anisotropy_clamp` = max_anisotropy) over the same MIP levels | EXT_texture_filter_anisotropic; WebGPU `maxAnisotropy` |
//!
//! `tex_anisotropic` is the one filter the project does not write: the scene's textures are
//! uploaded as one GPU texture array (`Rgba16Float`, the filterable format every adapter has:
//! texels rounded to 11 significant bits) with the levels above, and the adapter decides how
//! many probes it takes and where; its texel fetches are counted as one trilinear lookup's 8.
//! What the adapter does is measured, not assumed: the texture-filtering study sweeps
//! max_anisotropy (an adapter that ignores it gives the same image at 1 and 16).

pub mod gpu_array;
pub mod pyramid;
pub mod sat;

use super::method::{
    wgsl_method_codes, Family, Frame, Method, MethodInfo, Override, Row, Settings, UniformBlock,
};
use super::param::{spec_named, Kind, MethodSpec, Param, Value};

/// Most probes or ellipse eccentricity (`max_anisotropy`), as GPUs' 16×.
pub const MAX_ANISOTROPY: u32 = 16;

/// A texture filter (WGSL `TEXTURE_FILTER`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// `tex_nearest`.
    Nearest,
    /// `tex_bilinear`.
    Bilinear,
    /// `tex_mip_nearest`.
    MipNearest,
    /// `tex_trilinear`.
    Trilinear,
    /// `tex_sat`.
    SummedArea,
    /// `tex_ripmap`.
    RipMap,
    /// `tex_footprint`.
    FootprintAssembly,
    /// `tex_ewa`.
    Ewa,
    /// `tex_anisotropic`.
    Anisotropic,
}

/// Which levels a filter reads, besides level 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Needs {
    /// The MIP pyramid.
    pub mips: bool,
    /// The RIP map.
    pub rip: bool,
    /// The summed-area table.
    pub sat: bool,
    /// The scene's textures as a GPU texture array with their MIP levels, sampled by the
    /// adapter's own filtering.
    pub gpu: bool,
}

impl Filter {
    /// The value of the WGSL constant `TEXTURE_FILTER`: its index in [`METHODS`].
    pub fn shader_code(self) -> u32 {
        METHODS
            .iter()
            .position(|s| (s.default)().filter == self)
            .expect("every filter has a row") as u32
    }

    /// The WGSL function that performs it (`fn(t: u32, uv: vec2<f32>) -> vec4<f32>`).
    pub fn wgsl_function(self) -> &'static str {
        match self {
            Filter::Nearest => "texture_nearest",
            Filter::Bilinear => "texture_sample",
            Filter::MipNearest => "texture_mip_nearest",
            Filter::Trilinear => "texture_trilinear",
            Filter::SummedArea => "texture_sat",
            Filter::RipMap => "texture_ripmap",
            Filter::FootprintAssembly => "texture_footprint",
            Filter::Ewa => "texture_ewa",
            Filter::Anisotropic => "texture_anisotropic",
        }
    }

    /// The WGSL that selects it in a shader module: `TEXTURE_FILTER` and `texture_filtered`.
    pub fn wgsl_dispatch(self) -> String {
        format!(
            "// Generated by realtime::technique::texture::Filter::wgsl_dispatch: this module's texture filter.\n\
             const TEXTURE_FILTER: u32 = {}u;\n\
             // Texture `t` over the pixel's footprint about uv, by the method's filter.\n\
             fn texture_filtered(t: u32, uv: vec2<f32>) -> vec4<f32> {{\n    return {}(t, uv);\n}}\n",
            self.shader_code(),
            self.wgsl_function()
        )
    }

    /// The tables it reads.
    pub fn needs(self) -> Needs {
        match self {
            Filter::Nearest | Filter::Bilinear => Needs::default(),
            Filter::MipNearest | Filter::Trilinear | Filter::FootprintAssembly | Filter::Ewa => Needs {
                mips: true,
                ..Needs::default()
            },
            Filter::RipMap => Needs {
                rip: true,
                ..Needs::default()
            },
            Filter::SummedArea => Needs {
                sat: true,
                ..Needs::default()
            },
            Filter::Anisotropic => Needs {
                gpu: true,
                ..Needs::default()
            },
        }
    }
}

/// What the levels of a colour texture are averaged in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MipSpace {
    /// Linear radiance: the mean of what the texels emit or reflect.
    Linear,
    /// The sRGB encoding (IEC 61966-2-1) of colour textures, decoded after averaging.
    Srgb,
}

/// Where the footprint comes from (WGSL `TEXTURE_DERIVATIVES`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Derivatives {
    /// `dpdx`/`dpdy` over the fragment quad.
    Hardware,
    /// Ray differentials on the tangent plane.
    Analytic,
}

impl Derivatives {
    /// WGSL `TEXTURE_DERIVATIVES`.
    pub fn shader_code(self) -> u32 {
        match self {
            Derivatives::Hardware => 0,
            Derivatives::Analytic => 1,
        }
    }
}

/// A filter with its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureFilter {
    /// Which filter.
    pub filter: Filter,
    /// Added to λ (levels; negative: sharper).
    pub lod_bias: f32,
    /// Most probes (`tex_footprint`) or ellipse eccentricity (`tex_ewa`).
    pub max_anisotropy: u32,
    /// What colour textures' levels are averaged in.
    pub mip_space: MipSpace,
    /// Where the footprint comes from.
    pub derivatives: Derivatives,
}

impl TextureFilter {
    /// `filter` with every parameter at its default.
    const fn with(filter: Filter) -> TextureFilter {
        TextureFilter {
            filter,
            lod_bias: 0.0,
            max_anisotropy: 16,
            mip_space: MipSpace::Linear,
            derivatives: Derivatives::Hardware,
        }
    }

    /// The lookup every method used before this family: bilinear at level 0.
    pub const BILINEAR: TextureFilter = TextureFilter::with(Filter::Bilinear);

    /// The method called `name` with its defaults.
    pub fn by_name(name: &str) -> Option<TextureFilter> {
        spec_named(METHODS, name).map(|spec| (spec.default)())
    }

    /// Its table row.
    pub fn spec(&self) -> &'static MethodSpec<TextureFilter> {
        &METHODS[self.filter.shader_code() as usize]
    }

    /// Its parameter rows.
    pub fn rows(&self) -> impl Iterator<Item = &'static Param<TextureFilter>> {
        self.spec().params.iter()
    }

    /// Its block of the frame uniform.
    pub fn uniforms(&self) -> TextureUniforms {
        TextureUniforms {
            lod_bias: self.lod_bias,
            max_anisotropy: self.max_anisotropy as f32,
        }
    }
}

const DERIVATIVES: Param<TextureFilter> = Param {
    name: "derivatives",
    kind: Kind::Keyword(&["hardware", "analytic"]),
    unit: "",
    doc: "the footprint: hardware = dpdx/dpdy over the 2×2 fragment quad (what textureSample uses; wrong where a quad \
          straddles a silhouette); analytic = ray differentials on the tangent plane (forward pipeline only)",
    source: "Igehy 1999, \"Tracing Ray Differentials\", SIGGRAPH; pbrt-v4 §10.1.1",
    unset: "",
    get: |t| {
        Some(Value::Keyword(match t.derivatives {
            Derivatives::Hardware => "hardware",
            Derivatives::Analytic => "analytic",
        }))
    },
    set: |t, v| {
        t.derivatives = match v.keyword()? {
            "analytic" => Derivatives::Analytic,
            _ => Derivatives::Hardware,
        };
        Some(())
    },
};

const LOD_BIAS: Param<TextureFilter> = Param {
    name: "lod_bias",
    kind: Kind::Real(-4.0, 4.0),
    unit: "levels",
    doc: "added to the level of detail λ = log₂ ρ (negative: sharper and more aliased, positive: blurrier)",
    source: "OpenGL 4.6 §8.14.1",
    unset: "",
    get: |t| Some(Value::Real(t.lod_bias)),
    set: |t, v| {
        t.lod_bias = v.real()?;
        Some(())
    },
};

const MIP_SPACE: Param<TextureFilter> = Param {
    name: "mip_space",
    kind: Kind::Keyword(&["linear", "srgb"]),
    unit: "",
    doc: "what colour textures' levels average: linear radiance, or the sRGB-encoded values (the classic mistake)",
    source: "",
    unset: "",
    get: |t| {
        Some(Value::Keyword(match t.mip_space {
            MipSpace::Linear => "linear",
            MipSpace::Srgb => "srgb",
        }))
    },
    set: |t, v| {
        t.mip_space = match v.keyword()? {
            "srgb" => MipSpace::Srgb,
            _ => MipSpace::Linear,
        };
        Some(())
    },
};

const MAX_ANISOTROPY_PARAM: Param<TextureFilter> = Param {
    name: "max_anisotropy",
    kind: Kind::Whole(1, MAX_ANISOTROPY),
    unit: "",
    doc: "most probes along the major axis, or most major/minor ratio of the ellipse (longer footprints are blurred \
          across to fit)",
    source: "",
    unset: "",
    get: |t| Some(Value::Whole(t.max_anisotropy)),
    set: |t, v| {
        t.max_anisotropy = v.whole()?;
        Some(())
    },
};

/// Every texture filter, in `TEXTURE_FILTER` order.
pub static METHODS: &[MethodSpec<TextureFilter>] = &[
    MethodSpec {
        name: "tex_nearest",
        summary: "the level-0 texel under the pixel centre's uv: aliases under minification, blocky under magnification",
        source: "",
        default: || TextureFilter::with(Filter::Nearest),
        params: &[],
    },
    MethodSpec {
        name: "tex_bilinear",
        summary: "bilinear interpolation of level 0 at the pixel centre's uv: exact for magnification, aliases under \
                  minification",
        source: "pbrt-v4 §10.4.3",
        default: || TextureFilter::with(Filter::Bilinear),
        params: &[],
    },
    MethodSpec {
        name: "tex_mip_nearest",
        summary: "bilinear in the MIP level nearest λ: pops where λ crosses a half level",
        source: "Williams 1983, \"Pyramidal Parametrics\", SIGGRAPH",
        default: || TextureFilter::with(Filter::MipNearest),
        params: &[DERIVATIVES, LOD_BIAS, MIP_SPACE],
    },
    MethodSpec {
        name: "tex_trilinear",
        summary: "bilinear in the two MIP levels around λ, blended: isotropic, so blurry where the footprint is long \
                  (grazing angles)",
        source: "Williams 1983, \"Pyramidal Parametrics\", SIGGRAPH",
        default: || TextureFilter::with(Filter::Trilinear),
        params: &[DERIVATIVES, LOD_BIAS, MIP_SPACE],
    },
    MethodSpec {
        name: "tex_sat",
        summary: "the exact mean of the nearest-texel image over the footprint's axis-aligned bounding box, from a \
                  summed-area table: blurry for footprints diagonal to the texture axes",
        source: "Crow 1984, \"Summed-Area Tables for Texture Mapping\", SIGGRAPH",
        default: || TextureFilter::with(Filter::SummedArea),
        params: &[DERIVATIVES],
    },
    MethodSpec {
        name: "tex_ripmap",
        summary: "bilinear in the four RIP-map levels around (λu, λv), reduced in u and v separately: anisotropic along \
                  the texture axes only",
        source: "RIP maps (Hewlett-Packard, as described by Akenine-Möller et al., Real-Time Rendering 4th ed. §6.2.2)",
        default: || TextureFilter::with(Filter::RipMap),
        params: &[DERIVATIVES, LOD_BIAS],
    },
    MethodSpec {
        name: "tex_footprint",
        summary: "up to max_anisotropy trilinear probes along the footprint's major axis, each at the level of the \
                  major axis / probes",
        source: "Schilling, Knittel & Straßer 1996, \"Texram: A Smart Memory for Texturing\", IEEE CG&A 16(3)",
        default: || TextureFilter::with(Filter::FootprintAssembly),
        params: &[DERIVATIVES, LOD_BIAS, MIP_SPACE, MAX_ANISOTROPY_PARAM],
    },
    MethodSpec {
        name: "tex_ewa",
        summary: "elliptical weighted average: Gaussian weights over the texels inside the footprint's ellipse, in the \
                  levels its minor axis picks: the high-quality reference of real-time filtering",
        source: "Heckbert 1989, \"Fundamentals of Texture Mapping and Image Warping\", MS thesis, UC Berkeley, §3.5.8; \
                 Greene & Heckbert 1986, IEEE CG&A 6(6)",
        default: || TextureFilter::with(Filter::Ewa),
        params: &[DERIVATIVES, LOD_BIAS, MIP_SPACE, MAX_ANISOTROPY_PARAM],
    },
    MethodSpec {
        name: "tex_anisotropic",
        summary: "the adapter's own filtering: textureSampleGrad with the footprint on a sampler of anisotropy_clamp = \
                  max_anisotropy, over the same MIP levels; what it does between trilinear and 16 probes is the \
                  driver's",
        source: "EXT_texture_filter_anisotropic (Khronos 1999); WebGPU GPUSamplerDescriptor.maxAnisotropy",
        default: || TextureFilter::with(Filter::Anisotropic),
        params: &[DERIVATIVES, LOD_BIAS, MIP_SPACE, MAX_ANISOTROPY_PARAM],
    },
];

/// The texture-filtering family's block of the frame uniform (WGSL `TextureUniforms`,
/// texture/filter.wgsl; `frame.families.texture`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TextureUniforms {
    /// Added to the level of detail λ, levels.
    pub lod_bias: f32,
    /// Most probes (`tex_footprint`) or ellipse eccentricity (`tex_ewa`).
    pub max_anisotropy: f32,
}

/// The texture filter `m`'s lookups use: its `TextureFilter` part's, or bilinear at level 0.
pub fn of(m: &Method) -> TextureFilter {
    m.get::<TextureFilter>()
        .copied()
        .unwrap_or(TextureFilter::BILINEAR)
}

/// The texture-filtering family.
pub struct TextureFiltering;

impl Family for TextureFiltering {
    fn title(&self) -> &'static str {
        "Texture filtering"
    }

    fn methods(&self) -> Vec<MethodInfo> {
        MethodInfo::of(METHODS)
    }

    /// Over N×N quadrature (n = 8, env_n = 8), unshadowed, without surface detail.
    fn method(&self, name: &str) -> Option<Method> {
        TextureFilter::by_name(name).map(|t| Method::of(t, 8))
    }

    fn wgsl_codes(&self) -> String {
        wgsl_method_codes("TEX_", None, METHODS)
    }

    /// Every method's lookups filter, so every method has the block (bilinear's without a
    /// texture-filtering part).
    fn uniforms(&self) -> Option<UniformBlock> {
        Some(UniformBlock {
            field: "texture",
            wgsl_type: "TextureUniforms",
            size: std::mem::size_of::<TextureUniforms>(),
            bytes: |m| bytemuck::bytes_of(&of(m).uniforms()).to_vec(),
        })
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("texture/filter.wgsl", include_str!("filter.wgsl")),
            ("texture/nearest.wgsl", include_str!("nearest.wgsl")),
            ("texture/mip_nearest.wgsl", include_str!("mip_nearest.wgsl")),
            ("texture/trilinear.wgsl", include_str!("trilinear.wgsl")),
            ("texture/sat.wgsl", include_str!("sat.wgsl")),
            ("texture/ripmap.wgsl", include_str!("ripmap.wgsl")),
            ("texture/footprint.wgsl", include_str!("footprint.wgsl")),
            ("texture/ewa.wgsl", include_str!("ewa.wgsl")),
            ("texture/anisotropic.wgsl", include_str!("anisotropic.wgsl")),
        ]
    }
}

/// The filter itself picks the shader module (its generated `texture_filtered`,
/// pipelines.rs); the derivatives are an override.
impl Settings for TextureFilter {
    fn method_name(&self) -> &'static str {
        self.spec().name
    }

    fn rows(&self) -> Vec<Row> {
        Row::all(TextureFilter::rows(self))
    }

    fn overrides(&self) -> Vec<Override> {
        vec![Override::geometry(
            "TEXTURE_DERIVATIVES",
            self.derivatives.shader_code(),
        )]
    }

    fn check(&self, method: &Method, frame: &Frame<'_>) -> Result<(), String> {
        if self.derivatives == Derivatives::Analytic && frame.deferred {
            return Err(format!(
                "method {method}: derivatives = analytic needs the forward pipeline (the G-buffer stores no ray differentials)"
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_codes_are_positions() {
        for (i, spec) in METHODS.iter().enumerate() {
            let t = TextureFilter::by_name(spec.name).unwrap();
            assert_eq!(t.filter.shader_code() as usize, i);
            assert_eq!(t.spec().name, spec.name);
        }
        assert_eq!(TextureFilter::BILINEAR.spec().name, "tex_bilinear");
        assert!(TextureFilter::by_name("tex_aniso").is_none());
    }

    #[test]
    fn only_the_filters_with_levels_have_level_parameters() {
        for spec in METHODS {
            let t = (spec.default)();
            let has = |name: &str| t.rows().any(|r| r.name == name);
            assert_eq!(
                has("lod_bias"),
                t.filter.needs().mips || t.filter.needs().rip || t.filter.needs().gpu,
                "{}",
                spec.name
            );
            assert_eq!(
                has("derivatives"),
                t.filter.needs() != Needs::default(),
                "{}",
                spec.name
            );
        }
    }
}
