//! Anti-aliasing: how many places inside each pixel the scene is sampled, and what a
//! post-process makes of the lit image afterwards. The ground truth of every method is the
//! oracle's: the box filter of the scene's radiance over each pixel's area (the integral the
//! texture filters approximate too; docs/ARCHITECTURE.md "Ground truth is defined per effect").
//!
//! | method | samples per pixel | after lighting | source |
//! |---|---|---|---|
//! | `aa_none` | 1, at the centre | — | — |
//! | `aa_ssaa` | k×k shaded, on a regular grid | the box filter of the k×k samples | — |
//! | `aa_msaa` | `samples` coverage and depth samples, shaded once per pixel (forward) or per sample at edges (deferred) | the resolve: the mean of the samples | Akeley 1993 |
//! | `aa_fxaa` | 1 | FXAA 3.11 (quality): a blend across the local edge by its estimated sub-pixel position | Lottes 2009 |
//! | `aa_mlaa` | 1 | edges → coverage of the silhouette line rebuilt from L, Z and U patterns → blend | Reshetov 2009; Jimenez et al. 2011 |
//! | `aa_taa` | 1 a frame, Halton-jittered | the frame blended into the reprojected, neighbourhood-clipped history | Karis 2014 |
//!
//! Where each fails, by construction: a post-process sees one sample per pixel, so it cannot
//! restore geometry thinner than a pixel that the sample missed (a wire, the tips of a star);
//! FXAA and MLAA only blend across edges their luma threshold finds; MSAA shades once per pixel,
//! so it does nothing for aliasing inside a surface (textures, highlights) nor for silhouettes
//! the shader decides (a sphere's or a disk's outline, traced inside a bounding proxy, is
//! alpha-tested geometry to MSAA: its coverage is the proxy's; a rectangle's proxy is the
//! rectangle, so its edges are resolved like a mesh's); TAA converges to the box filter of a static view, but under
//! motion the history it reprojects blurs and, where the view uncovers what was hidden, ghosts.

pub mod post;
pub mod taa;

use glam::Vec4;
use scenes::texture::Texture;

use super::method::{Family, Frame, Method, MethodInfo, Override, Row, Settings, UniformBlock};
use super::param::{spec_named, Kind, MethodSpec, Param, Value};
use super::texture::TextureFilter;

/// Largest supersampling factor accepted (k×k samples per pixel): the raster's `ssaa`, `aa_ssaa`'s
/// k, and their product.
pub const MAX_SSAA: u32 = 16;

/// MSAA sample counts a study may ask for (the adapter may support fewer: checked at render).
pub const MSAA_COUNTS: &[u32] = &[2, 4, 8];

/// Most history frames `aa_taa` renders before the measured one.
pub const MAX_TAA_FRAMES: u32 = 64;

/// How TAA keeps its history from ghosting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TaaClamp {
    /// The history as reprojected.
    None,
    /// Clamped per channel to the 3×3 neighbourhood's RGB bounding box.
    Aabb,
    /// Clipped towards the centre of the neighbourhood's YCoCg box (Karis 2014).
    Clip,
}

impl TaaClamp {
    const NAMES: &'static [&'static str] = &["none", "aabb", "clip"];

    fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    fn from_name(name: &str) -> Option<TaaClamp> {
        [TaaClamp::None, TaaClamp::Aabb, TaaClamp::Clip]
            .into_iter()
            .find(|c| c.name() == name)
    }
}

/// An anti-aliasing method and its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AntiAliasing {
    /// One sample at each pixel's centre.
    None,
    /// k×k shaded samples per pixel, box-filtered.
    Ssaa {
        /// Samples per axis.
        k: u32,
    },
    /// Multisampling: `samples` coverage/depth samples per pixel.
    Msaa {
        /// Samples per pixel.
        samples: u32,
    },
    /// FXAA 3.11, quality version.
    Fxaa {
        /// Least local contrast (relative to the brightest neighbour) that is an edge.
        edge_threshold: f32,
        /// Least local contrast (absolute) that is an edge: keeps dark noise unblended.
        edge_threshold_min: f32,
        /// How much of the sub-pixel aliasing estimate is blended away.
        subpixel: f32,
        /// Steps of the search along the edge (FXAA_QUALITY preset 39's step sizes).
        search_steps: u32,
    },
    /// Morphological anti-aliasing.
    Mlaa {
        /// Least luma difference that is an edge.
        threshold: f32,
        /// Most pixels searched along an edge in each direction.
        max_search: u32,
    },
    /// Temporal anti-aliasing.
    Taa {
        /// Frames rendered, the measured one last.
        frames: u32,
        /// Weight of the new frame in the exponential history.
        blend: f32,
        /// How the history is kept from ghosting.
        clamp: TaaClamp,
        /// Halton (2, 3) sub-pixel jitter, or none (every frame samples the centre).
        jitter: bool,
        /// Degrees the camera orbited per frame before the measured one (0: a still view).
        orbit_degrees: f32,
        /// Distance to the point the camera orbits, metres.
        orbit_distance: f32,
    },
    /// Geometric specular anti-aliasing: GGX α² widened by the variance of the shading normal
    /// over the pixel.
    SpecularGeometric {
        /// Screen-space variance σ² of the pixel filter.
        variance: f32,
        /// Most roughness² added (κ).
        clamp: f32,
    },
    /// Toksvig's normal-map anti-aliasing: α² widened by the spread the MIP-filtered normal
    /// map's shortened normals imply.
    SpecularToksvig,
}

impl AntiAliasing {
    /// The method's row in [`METHODS`].
    pub fn spec(&self) -> &'static MethodSpec<AntiAliasing> {
        let index = match self {
            AntiAliasing::None => 0,
            AntiAliasing::Ssaa { .. } => 1,
            AntiAliasing::Msaa { .. } => 2,
            AntiAliasing::Fxaa { .. } => 3,
            AntiAliasing::Mlaa { .. } => 4,
            AntiAliasing::Taa { .. } => 5,
            AntiAliasing::SpecularGeometric { .. } => 6,
            AntiAliasing::SpecularToksvig => 7,
        };
        &METHODS[index]
    }

    /// The parameter rows of the method, in printing order.
    pub fn rows(&self) -> impl Iterator<Item = &'static Param<AntiAliasing>> {
        self.spec().params.iter()
    }

    /// The method called `name` with its defaults.
    pub fn by_name(name: &str) -> Option<AntiAliasing> {
        spec_named(METHODS, name).map(|s| (s.default)())
    }

    /// Shaded samples per pixel axis (the supersampling factor it adds).
    pub fn ssaa(&self) -> u32 {
        match self {
            AntiAliasing::Ssaa { k } => *k,
            _ => 1,
        }
    }

    /// Multisample count of the render targets (1: none).
    pub fn msaa_samples(&self) -> u32 {
        match self {
            AntiAliasing::Msaa { samples } => *samples,
            _ => 1,
        }
    }

    /// WGSL `SPECULAR_AA`: 0 none, 1 geometric, 2 Toksvig (technique/antialias/specular.wgsl).
    pub fn specular_code(&self) -> u32 {
        match self {
            AntiAliasing::SpecularGeometric { .. } => 1,
            AntiAliasing::SpecularToksvig => 2,
            _ => 0,
        }
    }

    /// Its block of the frame uniform: σ², κ of the geometric method (zeros otherwise).
    pub fn uniforms(&self) -> SpecularAaUniforms {
        match *self {
            AntiAliasing::SpecularGeometric { variance, clamp } => SpecularAaUniforms { variance, clamp },
            _ => SpecularAaUniforms::default(),
        }
    }

    /// Whether it runs a post-process pass over the lit image.
    pub fn has_post_process(&self) -> bool {
        matches!(
            self,
            AntiAliasing::Fxaa { .. } | AntiAliasing::Mlaa { .. } | AntiAliasing::Taa { .. }
        )
    }
}

/// A normal map as `aa_specular_toksvig` reads it: every texel's tangent-space normal
/// n = 2c − 1 renormalised, c' = (n̂ + 1)/2 (alpha kept). Toksvig reads spread from |n̄| < 1, and an
/// 8-bit texel's own normal is already up to ~0.5 % short or long from quantisation alone,
/// which would read as roughness where nothing is filtered; its MIP levels are then averages
/// of unit normals (Toksvig 2005 §3 assumes exactly that). A texel of length 0 stays as it is.
pub fn toksvig_normal_map(t: &Texture) -> Texture {
    let texels = t
        .texels
        .iter()
        .map(|c| {
            let n = c.truncate() * 2.0 - 1.0;
            let l = n.length();
            if l > 0.0 && l.is_finite() {
                ((n / l + 1.0) * 0.5).extend(c.w)
            } else {
                *c
            }
        })
        .collect::<Vec<Vec4>>();
    Texture { texels, ..t.clone() }
}

macro_rules! aa_param {
    ($name:literal, $variant:ident, $field:ident, $kind:expr, $unit:literal, $doc:literal, $source:literal, $value:ident, $to:expr, $from:expr) => {
        Param {
            name: $name,
            kind: $kind,
            unit: $unit,
            doc: $doc,
            source: $source,
            unset: "",
            get: |a| match a {
                AntiAliasing::$variant { $field, .. } => Some(Value::$value($to(*$field))),
                _ => None,
            },
            set: |a, v| match a {
                AntiAliasing::$variant { $field, .. } => {
                    *$field = $from(v)?;
                    Some(())
                }
                _ => None,
            },
        }
    };
}

fn same<T>(v: T) -> T {
    v
}

const SSAA_K: Param<AntiAliasing> = aa_param!(
    "k",
    Ssaa,
    k,
    Kind::Whole(1, MAX_SSAA),
    "",
    "k×k samples per pixel on a regular grid, each shaded (the raster's `ssaa` multiplies it)",
    "",
    Whole,
    same,
    |v: Value| v.whole()
);

const MSAA_SAMPLES: Param<AntiAliasing> = aa_param!(
    "samples",
    Msaa,
    samples,
    Kind::OneOf(MSAA_COUNTS),
    "",
    "coverage and depth samples per pixel (the standard sample positions); one the adapter cannot do is an error naming those it can",
    "",
    Whole,
    same,
    |v: Value| v.whole()
);

const FXAA_EDGE_THRESHOLD: Param<AntiAliasing> = aa_param!(
    "edge_threshold",
    Fxaa,
    edge_threshold,
    Kind::Real(0.0, 1.0),
    "",
    "an edge where the 4-neighbourhood's luma range exceeds this fraction of its brightest luma (1: none)",
    "FXAA_QUALITY__EDGE_THRESHOLD",
    Real,
    same,
    |v: Value| v.real()
);

const FXAA_EDGE_THRESHOLD_MIN: Param<AntiAliasing> = aa_param!(
    "edge_threshold_min",
    Fxaa,
    edge_threshold_min,
    Kind::Real(0.0, 1.0),
    "",
    "and exceeds this much luma: darker contrast is left alone",
    "FXAA_QUALITY__EDGE_THRESHOLD_MIN",
    Real,
    same,
    |v: Value| v.real()
);

const FXAA_SUBPIXEL: Param<AntiAliasing> = aa_param!(
    "subpixel",
    Fxaa,
    subpixel,
    Kind::Real(0.0, 1.0),
    "",
    "share of the sub-pixel aliasing estimate blended away (0: edges only; 1: softest)",
    "FXAA_QUALITY__SUBPIX",
    Real,
    same,
    |v: Value| v.real()
);

const FXAA_SEARCH_STEPS: Param<AntiAliasing> = aa_param!(
    "search_steps",
    Fxaa,
    search_steps,
    Kind::Whole(1, 12),
    "",
    "steps along the edge each way, of 1, 1, 1, 1, 1, 1.5, 2, 2, 2, 2, 4, 8 pixels (preset 39)",
    "FXAA_QUALITY__PS",
    Whole,
    same,
    |v: Value| v.whole()
);

const MLAA_THRESHOLD: Param<AntiAliasing> = aa_param!(
    "threshold",
    Mlaa,
    threshold,
    Kind::Real(0.0, 1.0),
    "",
    "an edge between two pixels whose luma (√ of luminance) differs by more",
    "Jimenez et al. 2011 §1.2",
    Real,
    same,
    |v: Value| v.real()
);

const MLAA_MAX_SEARCH: Param<AntiAliasing> = aa_param!(
    "max_search",
    Mlaa,
    max_search,
    Kind::Whole(1, 64),
    "pixels",
    "how far an edge is followed each way to find its ends (longer edges are treated as ending there)",
    "",
    Whole,
    same,
    |v: Value| v.whole()
);

const TAA_FRAMES: Param<AntiAliasing> = aa_param!(
    "frames",
    Taa,
    frames,
    Kind::Whole(1, MAX_TAA_FRAMES),
    "",
    "frames rendered into the history, the measured one last (each timed; the cost is their median)",
    "",
    Whole,
    same,
    |v: Value| v.whole()
);

const TAA_BLEND: Param<AntiAliasing> = aa_param!(
    "blend",
    Taa,
    blend,
    Kind::Real(0.01, 1.0),
    "",
    "weight of the new frame: history ← (1 − blend)·history + blend·frame",
    "Karis 2014",
    Real,
    same,
    |v: Value| v.real()
);

const TAA_CLAMP: Param<AntiAliasing> = Param {
    name: "clamp",
    kind: Kind::Keyword(TaaClamp::NAMES),
    unit: "",
    doc: "the history against the 3×3 neighbourhood of the new frame: none, clamped to its RGB box, or \
          clipped towards its YCoCg box's centre",
    source: "Karis 2014",
    unset: "",
    get: |a| match a {
        AntiAliasing::Taa { clamp, .. } => Some(Value::Keyword(clamp.name())),
        _ => None,
    },
    set: |a, v| match a {
        AntiAliasing::Taa { clamp, .. } => {
            *clamp = TaaClamp::from_name(v.keyword()?)?;
            Some(())
        }
        _ => None,
    },
};

const TAA_JITTER: Param<AntiAliasing> = aa_param!(
    "jitter",
    Taa,
    jitter,
    Kind::Switch,
    "",
    "offsets each frame's samples within the pixel by the Halton (2, 3) sequence; off: every frame samples the centre",
    "",
    Switch,
    same,
    |v: Value| v.switch()
);

const TAA_ORBIT_DEGREES: Param<AntiAliasing> = aa_param!(
    "orbit_degrees",
    Taa,
    orbit_degrees,
    Kind::Real(0.0, 10.0),
    "degrees",
    "the test's motion, not the method's: the camera orbited this much per frame about world +Y before \
     arriving at the scene's view (0: a still view)",
    "",
    Real,
    same,
    |v: Value| v.real()
);

const TAA_ORBIT_DISTANCE: Param<AntiAliasing> = aa_param!(
    "orbit_distance",
    Taa,
    orbit_distance,
    Kind::Real(0.01, 1000.0),
    "m",
    "distance ahead of the camera of the point it orbits",
    "",
    Real,
    same,
    |v: Value| v.real()
);

const SPECULAR_VARIANCE: Param<AntiAliasing> = aa_param!(
    "variance",
    SpecularGeometric,
    variance,
    Kind::Real(0.0, 4.0),
    "",
    "σ² of the pixel filter in screen space (0.25: a Gaussian of σ = ½ pixel; a box pixel has 1/12): the normal's variance over the pixel is σ²·(|∂n/∂x|² + |∂n/∂y|²)",
    "Tokuyoshi & Kaplanyan 2019, Listing 1 (SIGMA2 = 0.5²)",
    Real,
    same,
    |v: Value| v.real()
);

const SPECULAR_CLAMP: Param<AntiAliasing> = aa_param!(
    "clamp",
    SpecularGeometric,
    clamp,
    Kind::Real(0.0, 1.0),
    "",
    "most α² the kernel adds (κ): keeps silhouettes and creases, whose normals jump, from turning matte",
    "Tokuyoshi & Kaplanyan 2019, Listing 1 (KAPPA)",
    Real,
    same,
    |v: Value| v.real()
);

/// The family's methods (WGSL needs no codes: each post-process is its own shader module, and
/// the specular methods' `SPECULAR_AA` is [`AntiAliasing::specular_code`]).
pub static METHODS: &[MethodSpec<AntiAliasing>] = &[
    MethodSpec {
        name: "aa_none",
        summary: "one sample at each pixel's centre: edges stair-step, sub-pixel geometry vanishes or pops",
        source: "",
        default: || AntiAliasing::None,
        params: &[],
    },
    MethodSpec {
        name: "aa_ssaa",
        summary: "k×k shaded samples per pixel, box-filtered: the ground truth's own estimator on a regular grid, \
                  at k² times the shading",
        source: "",
        default: || AntiAliasing::Ssaa { k: 4 },
        params: &[SSAA_K],
    },
    MethodSpec {
        name: "aa_msaa",
        summary: "`samples` coverage and depth samples per pixel, shaded once per pixel, resolved by their mean: \
                  geometric edges only",
        source: "Akeley 1993, \"RealityEngine Graphics\", SIGGRAPH",
        default: || AntiAliasing::Msaa { samples: 4 },
        params: &[MSAA_SAMPLES],
    },
    MethodSpec {
        name: "aa_fxaa",
        summary: "FXAA 3.11 (quality): finds the local edge from luma, searches along it for its ends and blends \
                  across it by the pixel's estimated coverage",
        source: "Lottes 2009, \"FXAA\", NVIDIA white paper",
        default: || AntiAliasing::Fxaa {
            edge_threshold: 0.166,
            edge_threshold_min: 0.0833,
            subpixel: 0.75,
            search_steps: 12,
        },
        params: &[
            FXAA_EDGE_THRESHOLD,
            FXAA_EDGE_THRESHOLD_MIN,
            FXAA_SUBPIXEL,
            FXAA_SEARCH_STEPS,
        ],
    },
    MethodSpec {
        name: "aa_mlaa",
        summary: "morphological AA: luma edges, their L/Z/U patterns traced to both ends, the silhouette line \
                  rebuilt through the crossing edges' midpoints, each pixel blended by the area it cuts",
        source: "Reshetov 2009, \"Morphological Antialiasing\", HPG; Jimenez et al. 2011, \"Practical Morphological \
                 Antialiasing\", GPU Pro 2",
        default: || AntiAliasing::Mlaa {
            threshold: 0.1,
            max_search: 16,
        },
        params: &[MLAA_THRESHOLD, MLAA_MAX_SEARCH],
    },
    MethodSpec {
        name: "aa_taa",
        summary: "temporal AA: one jittered sample a frame, blended into the history reprojected by depth and the \
                  previous camera, clipped to the new frame's neighbourhood",
        source: "Karis 2014, \"High-Quality Temporal Supersampling\", SIGGRAPH course",
        default: || AntiAliasing::Taa {
            frames: 16,
            blend: 0.1,
            clamp: TaaClamp::Clip,
            jitter: true,
            orbit_degrees: 0.0,
            orbit_distance: 5.0,
        },
        params: &[
            TAA_FRAMES,
            TAA_BLEND,
            TAA_CLAMP,
            TAA_JITTER,
            TAA_ORBIT_DEGREES,
            TAA_ORBIT_DISTANCE,
        ],
    },
    MethodSpec {
        name: "aa_specular_geometric",
        summary: "GGX α² + min(2σ²·(|∂n/∂x|² + |∂n/∂y|²), κ): the lobe widened by how much the shading normal turns \
                  across the pixel, so a highlight too small for the pixel spreads instead of flickering",
        source: "Kaplanyan, Hill, Patney & Lefohn 2016, \"Filtering Distributions of Normals for Shading Antialiasing\", \
                 HPG; Tokuyoshi & Kaplanyan 2019, \"Improved Geometric Specular Antialiasing\", I3D",
        default: || AntiAliasing::SpecularGeometric {
            variance: 0.25,
            clamp: 0.18,
        },
        params: &[SPECULAR_VARIANCE, SPECULAR_CLAMP],
    },
    MethodSpec {
        name: "aa_specular_toksvig",
        summary: "normal maps MIP-filtered (trilinear), and GGX α² + 2(1 − |n̄|)/|n̄| from the shortening of their \
                  averaged normal n̄: the bumps a pixel averages become roughness",
        source: "Toksvig 2005, \"Mipmapping Normal Maps\", JGT 10(3)",
        default: || AntiAliasing::SpecularToksvig,
        params: &[],
    },
];

/// The anti-aliasing family's block of the frame uniform (WGSL `SpecularAaUniforms`,
/// antialias/specular.wgsl; `frame.families.specular_aa`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SpecularAaUniforms {
    /// σ² of the pixel filter in screen space.
    pub variance: f32,
    /// Most α² the kernel adds (κ).
    pub clamp: f32,
}

/// The anti-aliasing family.
pub struct AntiAliasingFamily;

impl Family for AntiAliasingFamily {
    fn title(&self) -> &'static str {
        "Anti-aliasing"
    }

    fn methods(&self) -> Vec<MethodInfo> {
        MethodInfo::of(METHODS)
    }

    /// Over N×N quadrature (n = 8, env_n = 8), unshadowed; `aa_specular_toksvig` with its
    /// textures filtered trilinearly (Toksvig reads the shortening of MIP-filtered normals).
    fn uniforms(&self) -> Option<UniformBlock> {
        Some(UniformBlock {
            field: "specular_aa",
            wgsl_type: "SpecularAaUniforms",
            size: std::mem::size_of::<SpecularAaUniforms>(),
            bytes: |m| {
                let u = m
                    .get::<AntiAliasing>()
                    .map_or_else(SpecularAaUniforms::default, AntiAliasing::uniforms);
                bytemuck::bytes_of(&u).to_vec()
            },
        })
    }

    fn method(&self, name: &str) -> Option<Method> {
        let aa = AntiAliasing::by_name(name)?;
        let mut m = Method::of(aa, 8);
        if aa == AntiAliasing::SpecularToksvig {
            // The texture filter's rows print before the method's own, as they always have.
            m = Method::of(TextureFilter::by_name("tex_trilinear")?, 8).with_primary(aa);
        }
        Some(m)
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[("antialias/specular.wgsl", include_str!("specular.wgsl"))]
    }
}

impl Settings for AntiAliasing {
    fn method_name(&self) -> &'static str {
        self.spec().name
    }

    fn rows(&self) -> Vec<Row> {
        Row::all(AntiAliasing::rows(self))
    }

    /// `SPECULAR_AA` (the post-processes are passes of their own, render.rs).
    fn overrides(&self) -> Vec<Override> {
        vec![Override::shading("SPECULAR_AA", self.specular_code())]
    }

    fn check(&self, method: &Method, frame: &Frame<'_>) -> Result<(), String> {
        let samples = self.msaa_samples();
        if samples > 1 && !frame.msaa_counts.contains(&samples) {
            let counts: Vec<String> = frame.msaa_counts.iter().map(u32::to_string).collect();
            let can = if counts.is_empty() {
                "none (it lacks TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)".to_string()
            } else {
                counts.join(", ")
            };
            return Err(format!(
                "method {method}: the adapter cannot render {samples} samples per pixel to Rgba32Float and \
                 Depth32Float targets; it can do {can}"
            ));
        }
        Ok(())
    }

    fn supersampling(&self) -> u32 {
        self.ssaa()
    }

    fn msaa_samples(&self) -> u32 {
        AntiAliasing::msaa_samples(self)
    }
}
