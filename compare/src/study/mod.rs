//! Study files: a scene, its ground truth, the methods with their parameter grids, the metrics,
//! the masks and the thresholds (format reference: compare/README.md, "Study files").
//!
//! A study is read once and checked whole before anything renders: unknown fields, unknown
//! methods, parameters or metrics, thresholds that name no method or mask or can never hold,
//! duplicate masks or metrics, sweeps with no values, a grid larger than [`plan::MAX_RENDERS`],
//! and — with the scene loaded at every scene point ([`scene_check`]) — a `visibility_of` that
//! names no light or a mask object that names no shape are errors naming the file, the field
//! and its line (the scene files' located reader, `scenes::toml::read`). The run's size and
//! memory are checked against the budget by [`plan`] before the first render. Running it is
//! [`run`]; what it produces is [`result`].
//!
//! | module | what |
//! |---|---|
//! | [`model`] | the study as read: scene points, ground truth, methods and variants, masks, thresholds, stability |
//! | `parse` | the file's fields into the model, each located ([`load`], [`load_str`]) |
//! | `check` | whole-study checks: unique masks and labels, thresholds that select variants |
//! | `scene_check` | checks that need the scene loaded at every scene point |
//! | [`plan`] | renders and memory, checked against the budget before the first render |
//! | [`setup`] | what a run and its sweeps share: options, the ground truths and their cache key |
//! | [`run`] | the run: ground truths, every variant, metrics, bounds |
//! | [`rasters`] | the raster images of a run: rendered live, or recorded by raster jobs |
//! | [`lightmap`] | the light maps `lightmap_*` variants read: baked by the oracle, cached |
//! | [`stability`] | sweeps' flicker over frames |
//! | [`result`] | what a run produces and the bounds' verdicts |
//! | [`record`] | full-mode records in study files |
//! | [`cache`] | the content-addressed ground-truth cache |
//! | [`jobs`] | the study as a job graph: ground-truth shares, ground truths, raster renders, the report |

pub mod cache;
mod check;
pub mod jobs;
pub mod lightmap;
pub mod model;
mod parse;
pub mod plan;
pub mod rasters;
pub mod record;
pub mod result;
pub mod run;
mod scene_check;
pub mod setup;
pub mod stability;

pub use model::*;
pub use parse::{load, load_str, MAX_NAME_LEN};
