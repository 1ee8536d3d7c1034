//! What a render is asked to do and what it gives back: the job (scene, settings, stopping
//! rule, checkpointing), progress reports, the result and the errors — shared by the render
//! loop ([`crate::render`]) and its checkpoints ([`crate::checkpoint`]).

use std::path::PathBuf;
use std::time::Duration;

use scenes::layered::LayeredImage;
use scenes::{RenderSettings, Scene};

/// When to stop sampling. Rendering stops at the first rule met; `spp` always bounds it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopRule {
    /// Samples per pixel to reach.
    pub spp: u32,
    /// Stop after the pass that crosses this wall-clock budget.
    pub time: Option<Duration>,
    /// Stop when the image's mean relative standard error drops below this.
    pub target_rel_err: Option<f32>,
}

/// Periodic checkpoints of the accumulation buffers.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckpointConfig {
    /// Checkpoint file (written atomically).
    pub path: PathBuf,
    /// Write at most this often.
    pub interval: Duration,
    /// Continue from `path` if it exists and matches the job.
    pub resume: bool,
}

/// One render.
#[derive(Clone, Debug)]
pub struct RenderJob<'a> {
    /// The scene (its `film` gives the resolution).
    pub scene: &'a Scene,
    /// Integrator, depth, seed, …
    pub settings: RenderSettings,
    /// Stopping rule.
    pub stop: StopRule,
    /// Optional checkpointing.
    pub checkpoint: Option<CheckpointConfig>,
    /// Estimate the visible fraction of every named light at the first hit
    /// (`visibility.<light>.Y`): one more light sample and shadow ray per named light and
    /// camera sample. Without it the image has no visibility layers (what Mitsuba renders).
    pub light_visibility: bool,
}

/// Progress report, sent before the first pass and after every pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// Samples per pixel done.
    pub spp_done: u32,
    /// Samples per pixel aimed for.
    pub spp_target: u32,
    /// Wall time so far.
    pub elapsed: Duration,
    /// Camera paths traced so far.
    pub paths: u64,
    /// Rays traced so far (all kinds).
    pub rays: u64,
    /// Current mean relative standard error of the image.
    pub rel_err: f32,
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct RenderResult {
    /// RGB mean, `variance.*` (of the pixel mean), AOVs, and header attributes.
    pub image: LayeredImage,
    /// Samples per pixel taken.
    pub spp: u32,
    /// Wall time in seconds (this run plus any resumed checkpoint).
    pub seconds: f64,
    /// Camera paths traced.
    pub paths: u64,
    /// Rays traced.
    pub rays: u64,
    /// Samples dropped because their radiance was NaN or infinite (each is a bug or an
    /// extreme scene; the image is biased where they fell).
    pub nonfinite_samples: u64,
}

/// Why a render failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The scene cannot be rendered as given.
    #[error("{0}")]
    Scene(String),
    /// The progress callback asked to stop; a checkpoint was written if one was configured.
    #[error("render interrupted at {spp} spp (checkpoint written: {checkpointed})")]
    Interrupted {
        /// Samples per pixel done.
        spp: u32,
        /// Whether the state was saved for `--resume`.
        checkpointed: bool,
    },
    /// What the render would allocate does not fit the memory budget ([`crate::memory`]).
    #[error("{0}")]
    Memory(#[from] scenes::budget::Exceeded),
    /// A checkpoint could not be read or written.
    #[error("checkpoint {path}: {message}")]
    Checkpoint {
        /// Checkpoint file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}
