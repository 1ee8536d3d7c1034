//! Screen-space ambient occlusion: a G-buffer post-pass (docs/ARCHITECTURE.md "Passes of one
//! frame", stage 3) that estimates, from depth and normals alone, how much of each visible
//! point's hemisphere is open within a radius r, and that the deferred lighting multiplies into
//! the environment's light (the ambient term). Passes and pipelines: [`passes`]; WGSL:
//! technique/ssao/, one file per technique.
//!
//! Ground truth: the oracle's `ao` integrator with the same radius, `ao_radius` = r:
//! AO(x) = (1/π) ∫ V_r(x, ω) cos θ dω, V_r = 1 when no surface lies within r along ω — the
//! cosine-weighted visibility within r (Zhukov et al. 1998 with a hard cut-off). GTAO estimates
//! exactly that quantity (under a depth layer of infinite thickness). The others estimate their
//! own, each measured against that closest exact quantity:
//! - Crytek's, the fraction of the ball of radius r around x in front of the depth buffer,
//!   doubled so that a flat open surface reads 1;
//! - the normal-oriented hemisphere's, the fraction of points of cosine-distributed segments of
//!   length r that lie in front of the depth buffer (a segment partly behind it counts
//!   partly, where V_r counts the whole ray as blocked);
//! - HBAO's, the solid-angle (not cosine) weighted fraction of the hemisphere above the
//!   horizon.
//!
//! `falloff` is how an occluder's weight fades with its distance d from x: `cutoff` (1 within
//! r, 0 beyond: the oracle's definition), `quadratic` (1 − d²/r², Bavoil et al.'s attenuation)
//! or `none` (no distance test: whatever the search reaches on screen occludes, however far
//! behind in depth — the dark halos around foreground objects).
//!
//! Failure modes, each a study (scenes/studies/ssao-*.toml): what is off screen or behind the
//! front depth layer does not occlude (screen edges, occluders hidden behind others), the depth
//! layer is taken as infinitely thick (a thin pole occludes everything behind it), a few samples
//! per pixel are noise that the blur trades for bias, and the noise pattern is fixed to the
//! screen, so it swims under camera motion.

pub mod passes;

use super::method::{Family, Frame, Method, MethodInfo, Override, Row, Settings, UniformBlock};
use super::param::{Kind, MethodSpec, Param, Value};

/// The estimator of an SSAO method (each a shader module of its own, passes.rs: no WGSL code
/// selects it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SsaoTechnique {
    /// Depth-only point samples in a ball (Mittring 2007).
    Crytek,
    /// Point samples in the normal's hemisphere (Filion & McNaughton 2008).
    Hemisphere,
    /// Horizon angles along screen directions, solid-angle weighted (Bavoil et al. 2008).
    Hbao,
    /// Horizon angles per slice, cosine weighted (Jimenez et al. 2016).
    Gtao,
}

/// How an occluder's weight fades with its distance from the shaded point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Falloff {
    /// No distance test.
    None,
    /// 1 within the radius, 0 beyond.
    Cutoff,
    /// 1 − d²/r².
    Quadratic,
}

impl Falloff {
    const WORDS: &'static [&'static str] = &["none", "cutoff", "quadratic"];

    /// Its position in [`Falloff::WORDS`] (the shaders' code).
    pub fn code(self) -> u32 {
        match self {
            Falloff::None => 0,
            Falloff::Cutoff => 1,
            Falloff::Quadratic => 2,
        }
    }
}

/// What the lighting pass writes under an SSAO method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SsaoOutput {
    /// The shaded image, the environment's light multiplied by AO.
    Shaded,
    /// The AO factor itself (R = G = B; background 0, as the oracle's `ao` writes it).
    AoFactor,
}

/// An SSAO method with its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AmbientOcclusion {
    /// The estimator.
    pub technique: SsaoTechnique,
    /// The radius r in metres, or None: the scene's `[render] ao_radius`, the one its ground
    /// truth (the oracle's `ao`) uses.
    pub radius: Option<f32>,
    /// How an occluder's weight fades with its distance.
    pub falloff: Falloff,
    /// Height above the tangent plane (horizon methods) or depth behind the depth buffer
    /// (point methods) an occluder needs, as a fraction of the radius.
    pub bias: f32,
    /// Point samples per pixel (Crytek, hemisphere).
    pub samples: u32,
    /// Screen directions (HBAO) or slices (GTAO, each searched both ways) per pixel.
    pub directions: u32,
    /// Samples along each direction (each side of a GTAO slice).
    pub steps: u32,
    /// Compute at half the resolution in each axis, then upsample guided by depth and normals.
    pub half_res: bool,
    /// Radius in texels of the separable cross-bilateral blur (0: none).
    pub blur: u32,
    /// Frames of temporal accumulation, each with its own sample rotation, the history
    /// reprojected into the next (0: none).
    pub temporal: u32,
    /// Degrees the camera orbited per frame of the accumulation before the measured one (the
    /// test's motion: [`camera`]).
    pub orbit_degrees: f32,
    /// Distance ahead of the camera of the point it orbits, metres.
    pub orbit_distance: f32,
    /// What the lighting writes.
    pub output: SsaoOutput,
}

impl AmbientOcclusion {
    /// 1 + its index in [`METHODS`].
    pub fn shader_code(&self) -> u32 {
        match self.technique {
            SsaoTechnique::Crytek => 1,
            SsaoTechnique::Hemisphere => 2,
            SsaoTechnique::Hbao => 3,
            SsaoTechnique::Gtao => 4,
        }
    }

    /// The method's row in [`METHODS`].
    pub fn spec(&self) -> &'static MethodSpec<AmbientOcclusion> {
        &METHODS[self.shader_code() as usize - 1]
    }

    /// Its parameter rows: [`COMMON`], then its own.
    pub fn rows(&self) -> impl Iterator<Item = &'static Param<AmbientOcclusion>> {
        COMMON.iter().chain(self.spec().params.iter())
    }

    /// The camera of frame `i` of the temporal accumulation, from the scene's `camera` (the last
    /// frame's): (temporal − 1 − i)·orbit_degrees before it, so the measured frame is the scene's
    /// own view and its ground truth the study's.
    pub fn camera(&self, camera: &scenes::Camera, i: u32) -> scenes::Camera {
        let behind = self.temporal.saturating_sub(1 + i) as f32;
        camera.orbited(-behind * self.orbit_degrees, self.orbit_distance)
    }

    fn with(technique: SsaoTechnique, directions: u32, steps: u32) -> AmbientOcclusion {
        AmbientOcclusion {
            technique,
            radius: None,
            falloff: Falloff::Cutoff,
            bias: 0.02,
            samples: 16,
            directions,
            steps,
            half_res: false,
            blur: 0,
            temporal: 0,
            orbit_degrees: 0.0,
            orbit_distance: 5.0,
            output: SsaoOutput::Shaded,
        }
    }
}

/// The parameters every SSAO method has.
pub static COMMON: &[Param<AmbientOcclusion>] = &[
    Param {
        name: "radius",
        kind: Kind::Real(1e-3, 1e3),
        unit: "m",
        doc: "the occlusion radius r: occluders further than r from the point do not count",
        source: "",
        unset: "the scene's `[render] ao_radius`, its ground truth's",
        get: |a| a.radius.map(Value::Real),
        set: |a, v| {
            a.radius = Some(v.real()?);
            Some(())
        },
    },
    Param {
        name: "falloff",
        kind: Kind::Keyword(Falloff::WORDS),
        unit: "",
        doc: "an occluder's weight against its distance d: cutoff (1 within r, the ground truth's definition), \
              quadratic (1 − d²/r²), none (no distance test: halos behind foreground objects)",
        source: "quadratic: Bavoil, Sainz & Dimitrov 2008, §2",
        unset: "",
        get: |a| Some(Value::Keyword(Falloff::WORDS[a.falloff.code() as usize])),
        set: |a, v| {
            a.falloff = match v.keyword()? {
                "none" => Falloff::None,
                "cutoff" => Falloff::Cutoff,
                _ => Falloff::Quadratic,
            };
            Some(())
        },
    },
    Param {
        name: "bias",
        kind: Kind::Real(0.0, 0.5),
        unit: "× radius",
        doc: "what an occluder needs to count: height above the tangent plane (HBAO, GTAO) or depth behind the depth \
              buffer (Crytek, hemisphere), against self-occlusion of flat and tessellated surfaces",
        source: "",
        unset: "",
        get: |a| Some(Value::Real(a.bias)),
        set: |a, v| {
            a.bias = v.real()?;
            Some(())
        },
    },
    Param {
        name: "half_res",
        kind: Kind::Switch,
        unit: "",
        doc: "compute AO on every second pixel in each axis (a quarter of the cost), then upsample with weights from \
              depth and normals (joint bilateral upsampling)",
        source: "Kopf, Cohen, Lischinski & Uyttendaele 2007, \"Joint Bilateral Upsampling\", SIGGRAPH",
        unset: "",
        get: |a| Some(Value::Switch(a.half_res)),
        set: |a, v| {
            a.half_res = v.switch()?;
            Some(())
        },
    },
    Param {
        name: "blur",
        kind: Kind::Whole(0, 16),
        unit: "texels",
        doc: "radius of the separable cross-bilateral blur over the AO (Gaussian σ = radius/2, weighted by view depth \
              and normal); separable, so not the 2-D bilateral filter across diagonal edges",
        source: "Tomasi & Manduchi 1998, \"Bilateral Filtering for Gray and Color Images\", ICCV; separable: Pham & \
                 van Vliet 2005, ICME",
        unset: "no blur",
        get: |a| (a.blur > 0).then_some(Value::Whole(a.blur)),
        set: |a, v| {
            a.blur = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "temporal",
        kind: Kind::Whole(0, 64),
        unit: "frames",
        doc: "temporal accumulation: this many frames, each with the per-pixel rotation advanced, the AO averaged \
              with the history reprojected from the previous frame (its mean until `temporal` frames, then an \
              exponential average of weight 1/temporal), the history dropped where its depth differs by 2 % \
              (disocclusion)",
        source: "Jimenez, Wu, Pesce & Jarabo 2016, §5 (temporal accumulation of the rotations); Nehab et al. 2007, \
                 \"Accelerating Real-Time Shading with Reverse Reprojection Caching\", Graphics Hardware",
        unset: "no accumulation",
        get: |a| (a.temporal > 0).then_some(Value::Whole(a.temporal)),
        set: |a, v| {
            a.temporal = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "orbit_degrees",
        kind: Kind::Real(0.0, 10.0),
        unit: "degrees",
        doc: "the test's motion, not the method's (needs temporal): the camera orbited this much per frame about \
              world +Y before arriving at the scene's view",
        source: "",
        unset: "0: a still view",
        get: |a| (a.orbit_degrees > 0.0).then_some(Value::Real(a.orbit_degrees)),
        set: |a, v| {
            a.orbit_degrees = v.real()?;
            Some(())
        },
    },
    Param {
        name: "orbit_distance",
        kind: Kind::Real(0.01, 1000.0),
        unit: "m",
        doc: "distance ahead of the camera of the point it orbits (with orbit_degrees)",
        source: "",
        unset: "5, used with orbit_degrees",
        get: |a| (a.orbit_degrees > 0.0).then_some(Value::Real(a.orbit_distance)),
        set: |a, v| {
            a.orbit_distance = v.real()?;
            Some(())
        },
    },
    Param {
        name: "output",
        kind: Kind::Keyword(&["shaded", "ao"]),
        unit: "",
        doc: "shaded: the image, the environment's light × AO; ao: the AO factor itself (R = G = B, background 0), \
              the oracle's `ao` integrator's quantity",
        source: "",
        unset: "",
        get: |a| {
            Some(Value::Keyword(match a.output {
                SsaoOutput::Shaded => "shaded",
                SsaoOutput::AoFactor => "ao",
            }))
        },
        set: |a, v| {
            a.output = match v.keyword()? {
                "ao" => SsaoOutput::AoFactor,
                _ => SsaoOutput::Shaded,
            };
            Some(())
        },
    },
];

/// Largest number of samples, directions or steps.
const MAX_SAMPLES: u32 = 256;

const SAMPLES: Param<AmbientOcclusion> = Param {
    name: "samples",
    kind: Kind::Whole(1, MAX_SAMPLES),
    unit: "per pixel",
    doc: "point samples per pixel, a low-discrepancy set rotated per pixel",
    source: "",
    unset: "",
    get: |a| Some(Value::Whole(a.samples)),
    set: |a, v| {
        a.samples = v.whole()?;
        Some(())
    },
};

const DIRECTIONS: Param<AmbientOcclusion> = Param {
    name: "directions",
    kind: Kind::Whole(1, 64),
    unit: "per pixel",
    doc: "screen-space directions (HBAO) or slices searched both ways (GTAO), rotated per pixel",
    source: "",
    unset: "",
    get: |a| Some(Value::Whole(a.directions)),
    set: |a, v| {
        a.directions = v.whole()?;
        Some(())
    },
};

const STEPS: Param<AmbientOcclusion> = Param {
    name: "steps",
    kind: Kind::Whole(1, 64),
    unit: "per direction",
    doc: "depth samples along each direction out to the radius's projection, the first jittered per pixel",
    source: "",
    unset: "",
    get: |a| Some(Value::Whole(a.steps)),
    set: |a, v| {
        a.steps = v.whole()?;
        Some(())
    },
};

/// The SSAO methods.
pub static METHODS: &[MethodSpec<AmbientOcclusion>] = &[
    MethodSpec {
        name: "ssao_crytek",
        summary: "depth only: the fraction of point samples in the ball of radius r that lie in front of the depth \
                  buffer, doubled (a flat open surface reads 1)",
        source: "Mittring 2007, \"Finding Next Gen: CryEngine 2\", SIGGRAPH course, §8.5.4.3",
        default: || AmbientOcclusion::with(SsaoTechnique::Crytek, 0, 0),
        params: &[SAMPLES],
    },
    MethodSpec {
        name: "ssao_hemisphere",
        summary: "point samples in the normal's hemisphere (cosine-distributed directions, distances up to r), \
                  occluded where the depth buffer is in front of them",
        source: "Filion & McNaughton 2008, \"StarCraft II: Effects & Techniques\", SIGGRAPH course, §5.4",
        default: || AmbientOcclusion::with(SsaoTechnique::Hemisphere, 0, 0),
        params: &[SAMPLES],
    },
    MethodSpec {
        name: "ssao_hbao",
        summary: "horizon-based: the highest elevation above the tangent plane along screen directions, AO = 1 − \
                  mean of the attenuated sin(horizon) increments (solid-angle weighted)",
        source: "Bavoil, Sainz & Dimitrov 2008, \"Image-Space Horizon-Based Ambient Occlusion\", SIGGRAPH talk",
        default: || AmbientOcclusion::with(SsaoTechnique::Hbao, 8, 6),
        params: &[DIRECTIONS, STEPS],
    },
    MethodSpec {
        name: "ssao_gtao",
        summary: "ground-truth-based: two horizons per view-aligned slice, the cosine-weighted visibility between \
                  them integrated in closed form over the projected normal's hemisphere",
        source: "Jimenez, Wu, Pesce & Jarabo 2016, \"Practical Real-Time Strategies for Accurate Indirect \
                 Occlusion\", SIGGRAPH course, §4",
        default: || AmbientOcclusion::with(SsaoTechnique::Gtao, 4, 8),
        params: &[DIRECTIONS, STEPS],
    },
];

/// The SSAO family's block of the frame uniform (WGSL `AmbientOcclusionUniforms`,
/// ssao/lighting.wgsl; `frame.families.ambient_occlusion`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct AmbientOcclusionUniforms {
    /// What the lighting writes: 0 the shaded image, 1 the AO factor (`output = ao`).
    pub output: u32,
}

/// The screen-space ambient occlusion family.
pub struct AmbientOcclusionFamily;

impl Family for AmbientOcclusionFamily {
    fn title(&self) -> &'static str {
        "Screen-space ambient occlusion"
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

    fn uniforms(&self) -> Option<UniformBlock> {
        Some(UniformBlock {
            field: "ambient_occlusion",
            wgsl_type: "AmbientOcclusionUniforms",
            size: std::mem::size_of::<AmbientOcclusionUniforms>(),
            bytes: |m| {
                let output = m
                    .get::<AmbientOcclusion>()
                    .is_some_and(|a| a.output == SsaoOutput::AoFactor);
                bytemuck::bytes_of(&AmbientOcclusionUniforms {
                    output: u32::from(output),
                })
                .to_vec()
            },
        })
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[("ssao/lighting.wgsl", include_str!("lighting.wgsl"))]
    }
}

impl Settings for AmbientOcclusion {
    fn method_name(&self) -> &'static str {
        self.spec().name
    }

    fn rows(&self) -> Vec<Row> {
        Row::all(AmbientOcclusion::rows(self))
    }

    /// None: its passes are compute passes of their own (passes.rs).
    fn overrides(&self) -> Vec<Override> {
        Vec::new()
    }

    fn check(&self, method: &Method, frame: &Frame<'_>) -> Result<(), String> {
        if self.orbit_degrees > 0.0 && self.temporal == 0 {
            return Err(format!(
                "method {method}: orbit_degrees = {} moves the camera between the frames of a temporal accumulation; \
                 set temporal (frames) too",
                self.orbit_degrees
            ));
        }
        if !frame.deferred {
            return Err(format!(
                "method {method}: screen-space ambient occlusion reads the G-buffer; use the deferred pipeline \
                 (`--pipeline deferred`; in a study, `pipeline = \"deferred\"`)"
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shader_codes_follow_the_table() {
        for (i, spec) in METHODS.iter().enumerate() {
            assert_eq!((spec.default)().shader_code() as usize, i + 1, "{}", spec.name);
            assert_eq!((spec.default)().spec().name, spec.name);
        }
    }

    #[test]
    fn falloff_words_follow_the_codes() {
        for f in [Falloff::None, Falloff::Cutoff, Falloff::Quadratic] {
            let mut a = (METHODS[0].default)();
            (COMMON[1].set)(&mut a, Value::Keyword(Falloff::WORDS[f.code() as usize]));
            assert_eq!(a.falloff, f);
        }
    }
}
