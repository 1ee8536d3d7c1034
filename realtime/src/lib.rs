//! Verity's headless wgpu renderer: the real-time side of every comparison.
//!
//! It renders a [`scenes::Scene`] with the same camera, projection, pixel centres, colour
//! space, BSDFs and light units as the oracle (DESIGN.md "Conventions"), so that when nothing
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
//! | [`gpu`] | adapter and device selection |
//! | [`method`] | methods (`area_quadrature`, `area_representative_point`, `shadow_hard`, `pcf_*`, `pcss`, the detail methods) and parameters |
//! | [`detail`] | surface-detail methods (normal, bump, parallax, relief, POM, cone stepping) and their baked maps |
//! | [`envmap`] | environment mapping (cube, sphere, dual-paraboloid maps; prefiltered specular, irradiance) |
//! | [`distance_impostor`] | distance impostors: cube-map lookups localized by stored distances (iteration; linear + secant search; double refraction) |
//! | `envmap_build` | the capture and the filtering passes of the environment maps |
//! | [`cone_map`] | cone maps for cone step mapping (Dummer 2006; relaxed, Policarpo & Oliveira 2007) |
//! | [`render`] | settings, the frame loop, timing, read-back |
//! | `frame` | one frame: uniforms, render passes, timestamp queries |
//! | `upload` | the scene as GPU buffers (meshes de-indexed, analytic shapes as proxies) |
//! | [`pipelines`] | shader module and pipelines (forward, G-buffer, lighting, shadow, visibility AOV) |
//! | [`shadow`] | shadow maps: light frusta, the shadow uniform, the map array (Williams 1978) |
//! | [`poisson`] | the Poisson-disk tap pattern (Mitchell 1991 best candidate) |
//! | [`visibility`] | the per-light visibility AOV `visibility.<light>.Y` |
//! | [`image`] | box filter over supersamples, the oracle's EXR channel layout |
//! | [`timing`] | GPU timestamps / wall time, hardware-independent counters |
//! | `shaders/*.wgsl` | the techniques, each file headed by its paper and failure mode |

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod cone_map;
pub mod detail;
pub mod distance_impostor;
pub mod envmap;
mod envmap_build;
pub mod error;
mod frame;
pub mod gpu;
pub mod gpu_types;
pub mod image;
pub mod method;
pub mod pipelines;
pub mod poisson;
pub mod render;
pub mod shadow;
mod targets;
pub mod timing;
mod upload;
pub mod visibility;

pub use detail::{Detail, DetailTechnique};
pub use envmap::{EnvMapping, Parameterization};
pub use error::{RasterError, INSTALL_HINT};
pub use gpu::Gpu;
pub use method::{AreaMethod, BlockerDepth, Method, PipelineKind, Shadow, ShadowTechnique};
pub use render::{RasterOutput, RasterSettings, Renderer};
pub use timing::{Counters, Timing, TimingSource};
