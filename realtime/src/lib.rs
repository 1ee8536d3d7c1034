//! Verity's headless wgpu renderer: the real-time side of every comparison.
//!
//! It renders a [`scenes::Scene`] with the same camera, projection, pixel centres, colour
//! space, BSDFs and light units as the oracle (docs/ARCHITECTURE.md "Conventions"), so that when nothing
//! is approximated the two agree, and every approximation's measured error is its own. No
//! window or surface: an adapter is picked the way wgpu's tools pick one (`WGPU_BACKEND`,
//! `WGPU_ADAPTER_NAME`), which runs on Mesa's lavapipe in CI and unchanged on real GPUs.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let scene = scenes::load(std::path::Path::new("scenes/soft-shadow.toml"))?;
//! let renderer = realtime::Renderer::new()?;
//! let settings = realtime::RasterSettings::new(256, 256).ssaa(2);
//! let out = renderer.render(&scene, &settings)?;
//! println!("{}", out.timing.summary());
//! out.image.write_exr("out/soft-shadow-raster.exr")?;
//! # Ok(()) }
//! ```
//!
//! | module | what |
//! |---|---|
//! | [`technique`] | the techniques, one module per family (the registry [`technique::FAMILIES`] lists all eleven): parameters and their tables, GPU resources; [`Method`] and the `Family` and `Settings` traits a family plugs in by |
//! | [`settings`] | what to render: method, pipeline, resolution, supersampling, frames |
//! | [`render`] | the renderer: the frame loop, timing, read-back |
//! | `frame` | one frame: uniforms, render passes, timestamp queries |
//! | [`pipelines`] | the shader module and pipelines (forward, G-buffer, lighting, shadow, visibility AOV), forward or deferred |
//! | `targets` | colour, depth and G-buffer targets |
//! | `upload` | the scene as GPU buffers (meshes de-indexed, analytic shapes as proxies) |
//! | [`visibility`] | the per-light visibility AOV `visibility.<light>.Y` |
//! | [`gpu`], [`gpu_types`] | adapter and device selection; the uniform and vertex layouts |
//! | [`image`] | box filter over supersamples, the oracle's EXR channel layout |
//! | [`timing`] | GPU timestamps / wall time, hardware-independent counters |
//! | `shaders/*.wgsl`, `shaders/<family>/*.wgsl` | shared shading code; each technique's, headed by its paper and failure mode |
//!
//! Every method, its parameters, defaults and papers: docs/methods.md (generated from the
//! tables in [`technique`]).

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod built_once;
mod camera;
pub mod error;
mod frame;
pub mod gpu;
pub mod gpu_types;
pub mod image;
pub mod pipelines;
pub mod render;
pub mod settings;
mod specialize;
mod targets;
pub mod technique;
mod timestamps;
pub mod timing;
mod upload;
pub mod visibility;

pub use error::{RasterError, INSTALL_HINT};
pub use gpu::Gpu;
pub use pipelines::PipelineKind;
pub use render::{RasterOutput, Renderer};
pub use settings::RasterSettings;
pub use technique::area::AreaMethod;
pub use technique::detail::{Detail, DetailTechnique};
pub use technique::envmap::{EnvMapping, Parameterization};
pub use technique::shadow::{BlockerDepth, Shadow, ShadowTechnique};
pub use technique::Method;
pub use timing::{Counters, Timing, TimingSource};
