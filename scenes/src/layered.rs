//! Multi-layer float32 images: the EXR layout both renderers write and `compare` reads.

/// A float32 image made of named channels (`R`, `variance.R`, `normal.X`, …).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LayeredImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Channels in insertion order; each holds width×height values, row 0 at the top.
    pub channels: Vec<(String, Vec<f32>)>,
    /// Header attributes (scene, integrator, spp, seconds, seed, version, …).
    pub attributes: Vec<(String, String)>,
}
