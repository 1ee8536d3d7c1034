//! How to render: the method, forward or deferred, the resolution, supersampling and the
//! frames timed ([`RasterSettings`]), checked before anything is allocated.

use crate::error::RasterError;
use crate::gpu::COLOR_BYTES_PER_SAMPLE;
use crate::pipelines::PipelineKind;
use scenes::lightmap::ChartSurface;

use crate::technique::lightmap::{BakedMap, LightMapMethod};
use crate::technique::{Frame, Method};

pub use crate::technique::antialias::MAX_SSAA;

/// How to render.
#[derive(Clone, Debug, PartialEq)]
pub struct RasterSettings {
    /// The method (area lights, shadows, detail, environment maps) and its parameters.
    pub method: Method,
    /// Forward or deferred.
    pub pipeline: PipelineKind,
    /// Output width in pixels.
    pub width: u32,
    /// Output height in pixels.
    pub height: u32,
    /// Supersampling: k×k samples per pixel on a regular grid (box filter over the pixel).
    pub ssaa: u32,
    /// Frames rendered before timing.
    pub warmup_frames: u32,
    /// Frames timed (the reported time is their median).
    pub timed_frames: u32,
    /// Run one extra frame with the hardware-independent counters compiled in.
    pub counters: bool,
    /// The baked light map a `lightmap_*` method reads (and only such a method).
    pub lightmap: Option<BakedMap>,
}

impl RasterSettings {
    /// `width`×`height`, default method, forward, no supersampling, 2 warm-up + 5 timed
    /// frames, no counters.
    pub fn new(width: u32, height: u32) -> Self {
        RasterSettings {
            method: Method::default(),
            pipeline: PipelineKind::Forward,
            width,
            height,
            ssaa: 1,
            warmup_frames: 2,
            timed_frames: 5,
            counters: false,
            lightmap: None,
        }
    }

    /// With `method`.
    pub fn method(self, method: Method) -> Self {
        RasterSettings { method, ..self }
    }

    /// With `pipeline`.
    pub fn pipeline(self, pipeline: PipelineKind) -> Self {
        RasterSettings { pipeline, ..self }
    }

    /// With k×k supersampling.
    pub fn ssaa(self, k: u32) -> Self {
        RasterSettings { ssaa: k, ..self }
    }

    /// With `warmup` untimed and `timed` timed frames.
    pub fn frames(self, warmup: u32, timed: u32) -> Self {
        RasterSettings {
            warmup_frames: warmup,
            timed_frames: timed,
            ..self
        }
    }

    /// With or without the counting frame.
    pub fn counters(self, counters: bool) -> Self {
        RasterSettings { counters, ..self }
    }

    /// With the baked light map `map`.
    pub fn lightmap(self, map: BakedMap) -> Self {
        RasterSettings {
            lightmap: Some(map),
            ..self
        }
    }

    /// The supersampling factor of the targets: the raster's `ssaa` times `aa_ssaa`'s k.
    pub fn supersampling(&self) -> u32 {
        self.ssaa.saturating_mul(self.method.supersampling())
    }

    /// Checks the settings against the adapter's largest texture side, the MSAA sample counts
    /// it supports (for Rgba32Float targets and Depth32Float together) and the memory budget.
    pub(crate) fn check(&self, max_dimension: u32, msaa_counts: &[u32]) -> Result<(), RasterError> {
        let bad = |m: String| Err(RasterError::Settings(m));
        if self.width == 0 || self.height == 0 {
            return bad(format!("resolution {}x{} is empty", self.width, self.height));
        }
        if !(1..=MAX_SSAA).contains(&self.ssaa) {
            return bad(format!("ssaa = {} must be in 1..={MAX_SSAA}", self.ssaa));
        }
        let m = &self.method;
        m.check(&Frame {
            deferred: self.pipeline == PipelineKind::Deferred,
            max_texture_side: max_dimension,
            msaa_counts,
        })
        .or_else(bad)?;
        match (m.get::<LightMapMethod>(), &self.lightmap) {
            (Some(_), None) => {
                return bad(format!(
                    "method {m} reads a baked light map and none was given (`verity bake`, then `--lightmap FILE`)"
                ))
            }
            (None, Some(map)) => {
                return bad(format!(
                    "a light map ({}) was given but method {m} does not read one",
                    map.label
                ))
            }
            (Some(_), Some(map)) if self.pipeline != PipelineKind::Forward => {
                let mesh = map.map.layout.charts.iter().find(|c| matches!(c.surface, ChartSurface::Mesh(_)));
                if let Some(c) = mesh {
                    return bad(format!(
                        "method {m}: shape `{}` is a light-mapped mesh, whose chart coordinates (TEXCOORD_1) the \
                         deferred pipeline's G-buffer does not store; use the forward pipeline",
                        c.name
                    ));
                }
            }
            _ => {}
        }
        if self.timed_frames == 0 {
            return bad("at least one timed frame is needed".into());
        }
        let k = self.supersampling();
        if k > MAX_SSAA {
            return bad(format!(
                "method {m} with ssaa {}: {k}×{k} samples per pixel exceed {MAX_SSAA}×{MAX_SSAA}",
                self.ssaa
            ));
        }
        let samples = m.msaa_samples();
        let (w, h) = (
            u64::from(self.width) * u64::from(k),
            u64::from(self.height) * u64::from(k),
        );
        if w > u64::from(max_dimension) || h > u64::from(max_dimension) {
            return bad(format!(
                "{}x{} with {k}×{k} supersampling needs a {w}x{h} target; the adapter allows at most {max_dimension} per side",
                self.width, self.height
            ));
        }
        // The render targets (three Rgba32Float colour targets and a depth target per sample)
        // and, per output pixel, the read-back targets and the EXR's channels (about 26 f32)
        // and the shadow maps (one Depth32Float layer per light), before any is allocated.
        // MSAA adds `samples` multisampled copies; a post-process up to three more images.
        let targets = w
            .saturating_mul(h)
            .saturating_mul((u64::from(COLOR_BYTES_PER_SAMPLE) + 4) * (1 + u64::from(samples)) + 48);
        let output = u64::from(self.width) * u64::from(self.height) * (48 + 26 * 4);
        let maps = m.bytes();
        scenes::budget::check(
            targets.saturating_add(output).saturating_add(maps),
            format!(
                "resolution {}x{} with ssaa {}: the render targets and read-back",
                self.width, self.height, self.ssaa
            ),
        )
        .map_err(|e| RasterError::Settings(e.to_string()))
    }
}
