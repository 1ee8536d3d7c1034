//! Cost: per-pass GPU timestamps where the adapter has them, otherwise wall time around
//! submit-and-wait; warm-up frames first, then the median of the timed frames; always with the
//! adapter's name and backend. Hardware-independent counters beside them.
//!
//! GPU time of a pass = (end − start) ticks × `Queue::get_timestamp_period()` ns (WebGPU
//! "timestamp-query", render-pass `timestampWrites`). The median is robust to the odd frame
//! the OS or the driver delays.

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

/// Where the frame time comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum TimingSource {
    /// Per-pass GPU timestamp queries.
    GpuTimestamps,
    /// Wall-clock time around submit and wait (the adapter has no timestamps).
    WallClock,
}

/// Median time of one pass.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PassTime {
    /// Pass label (`forward pass`, `G-buffer pass`, `lighting pass`).
    pub name: String,
    /// Median over the timed frames, milliseconds.
    pub ms: f64,
}

/// A render's cost.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    /// Adapter name as the driver reports it.
    pub adapter: String,
    /// Backend (`vulkan`, `metal`, `dx12`, …).
    pub backend: String,
    /// Driver name and version.
    pub driver: String,
    /// Timestamps or wall clock.
    pub source: TimingSource,
    /// Per-pass medians (empty without timestamps).
    pub passes: Vec<PassTime>,
    /// Median over frames of the summed pass times (timestamps only), ms.
    pub gpu_ms: Option<f64>,
    /// Median over frames of submit-to-completion wall time, ms.
    pub wall_ms: f64,
    /// Frames rendered before timing.
    pub warmup_frames: u32,
    /// Frames timed.
    pub timed_frames: u32,
}

impl Timing {
    /// The frame time reported as the cost: GPU time when measured, else wall time (ms).
    pub fn frame_ms(&self) -> f64 {
        self.gpu_ms.unwrap_or(self.wall_ms)
    }

    /// `3.21 ms/frame (GPU timestamps, median of 5 after 2 warm-up: forward pass 3.21 ms; wall
    /// 4.02 ms) on <adapter> [vulkan]`.
    pub fn summary(&self) -> String {
        let mut s = format!("{:.3} ms/frame (", self.frame_ms());
        let source = match self.source {
            TimingSource::GpuTimestamps => "GPU timestamps",
            TimingSource::WallClock => "wall clock, no GPU timestamps",
        };
        let _ = write!(
            s,
            "{source}, median of {} after {} warm-up",
            self.timed_frames, self.warmup_frames
        );
        if !self.passes.is_empty() {
            let passes: Vec<String> = self
                .passes
                .iter()
                .map(|p| format!("{} {:.3} ms", p.name, p.ms))
                .collect();
            let _ = write!(s, ": {}; wall {:.3} ms", passes.join(", "), self.wall_ms);
        }
        let _ = write!(s, ") on {} [{}]", self.adapter, self.backend);
        s
    }
}

/// Hardware-independent cost of shading each visible sample once, per final pixel (all k²
/// subsamples, background included; forward overdraw excluded, so forward and deferred count
/// the same).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Counters {
    /// Texel reads from textures (a bilinear lookup is 4; normal maps and environment lookups
    /// included).
    pub texel_fetches_per_pixel: f64,
    /// Iterations of the shading loops (lights, emitters, quadrature samples).
    pub loop_iterations_per_pixel: f64,
    /// Texel loads of the anti-aliasing passes after shading (MSAA resolve, FXAA, MLAA, TAA)
    /// of the last frame, or None without such a pass.
    #[serde(default)]
    pub post_taps_per_pixel: Option<f64>,
    /// Texture loads of the SSAO passes (G-buffer, obscurance, history) of the last frame, or
    /// None without them.
    #[serde(default)]
    pub ssao_loads_per_pixel: Option<f64>,
}

impl Counters {
    /// `0.0 texel fetches, 257.0 loop iterations per pixel` (`, 31.2 post-process taps` and
    /// `, 66.0 SSAO loads` after it when the method has such passes).
    pub fn summary(&self) -> String {
        let taps = self
            .post_taps_per_pixel
            .map_or(String::new(), |t| format!(", {t:.1} post-process taps"));
        let loads = self
            .ssao_loads_per_pixel
            .map_or(String::new(), |t| format!(", {t:.1} SSAO loads"));
        format!(
            "{:.1} texel fetches, {:.1} loop iterations per pixel{taps}{loads}",
            self.texel_fetches_per_pixel, self.loop_iterations_per_pixel
        )
    }
}

/// Median of `v` (mean of the middle two for an even count); NaN for an empty slice.
pub fn median(v: &[f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let m = s.len() / 2;
    if s.len() % 2 == 1 {
        s[m]
    } else {
        0.5 * (s[m - 1] + s[m])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn summary_names_source_adapter_and_backend() {
        let t = Timing {
            adapter: "llvmpipe".into(),
            backend: "vulkan".into(),
            driver: "Mesa".into(),
            source: TimingSource::GpuTimestamps,
            passes: vec![PassTime {
                name: "forward pass".into(),
                ms: 1.5,
            }],
            gpu_ms: Some(1.5),
            wall_ms: 2.0,
            warmup_frames: 2,
            timed_frames: 5,
        };
        let s = t.summary();
        assert!(
            s.starts_with("1.500 ms/frame (GPU timestamps, median of 5 after 2 warm-up"),
            "{s}"
        );
        assert!(
            s.contains("forward pass 1.500 ms") && s.ends_with("on llvmpipe [vulkan]"),
            "{s}"
        );
    }
}
