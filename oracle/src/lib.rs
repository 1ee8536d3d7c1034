//! The oracle: Verity's CPU path tracer, the ground truth every approximation is measured
//! against (docs/ARCHITECTURE.md "Ground truth is defined per effect").

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod bake;
pub mod bsdf;
pub mod checkpoint;
pub mod film;
pub mod frame;
pub mod geometry;
pub mod integrator;
pub mod job;
pub mod light;
pub mod memory;
pub mod part;
pub mod pixel_filter;
pub mod render;
pub mod sampler;
pub mod sampling;

pub use job::{CheckpointConfig, Progress, RenderError, RenderJob, RenderResult, StopRule};
pub use render::{render, render_part};

/// The oracle's version (part of every ground truth's cache key and EXR header).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
