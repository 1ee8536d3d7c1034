//! Where the oracle's camera rays cross a pixel: the pixel filter of a render
//! (docs/ARCHITECTURE.md "Camera" and "Ground truth is defined per effect").
//!
//! Pixel (x, y) is the raster square [x, x+1] × [y, y+1], row 0 at the top. The estimate of
//! pixel (x, y) is I = ∫ w(p) L(p) dp over raster positions p, L(p) the radiance arriving
//! through p (itself an integral over light transport), with the filter weight w:
//!
//! | filter | w(p) | what the oracle integrates |
//! |---|---|---|
//! | `box` | 1 on the pixel square | the pixel area, light transport (pbrt-v4 §5.4.2, the box filter) |
//! | `centre`, K = 1 | δ(p − (x + ½, y + ½)) | light transport through the pixel centre only |
//! | `centre`, K > 1 | (1/K²) Σᵢⱼ δ(p − pᵢⱼ), pᵢⱼ = (x + (i + ½)/K, y + (j + ½)/K) | light transport through the K×K sub-pixel centres, equal weights |
//!
//! `centre` is what a rasteriser computes: it samples the pixel centre, or with K×K
//! supersampling the centres of the K×K sub-pixels and box-filters them (realtime's `--ssaa
//! K`: `film_position` in realtime/shaders/common.wgsl). Against a `centre` ground truth a
//! real-time method's error is its shading error alone; against `box` it includes the edge
//! aliasing of sampling pixel centres, which is what anti-aliasing studies measure.

/// The pixel filter of a render ([module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PixelFilter {
    /// Each sample through a uniformly jittered point of the pixel square: the pixel-area
    /// integral. The default, and the truth of anti-aliasing studies.
    #[default]
    Box,
    /// Each sample through one of the `ssaa`×`ssaa` sub-pixel centres, each centre taking
    /// the same number of samples: the positions a rasteriser samples with `ssaa`×`ssaa`
    /// supersampling (`ssaa` = 1: the pixel centre).
    Centre {
        /// K, the sub-pixel centres per side, ≥ 1 (realtime's `--ssaa K`).
        ssaa: u32,
    },
}

impl PixelFilter {
    /// Every spelling read wherever a pixel filter is named (scene TOML `[render]
    /// pixel_filter`, study `[ground_truth] pixel_filter`; `verity render --pixel-filter` reads
    /// the same words): the one Verity prints ([`PixelFilter::name`]) and the American
    /// `center`. `centre` reads as the pixel centre (K = 1); K comes from `--ssaa` or the
    /// study's `[raster] ssaa`.
    pub const SPELLINGS: [(&'static str, PixelFilter); 3] = [
        ("box", PixelFilter::Box),
        ("centre", PixelFilter::Centre { ssaa: 1 }),
        ("center", PixelFilter::Centre { ssaa: 1 }),
    ];

    /// The one spelling Verity prints (EXR headers, metrics.json, progress lines): `box` or
    /// `centre`.
    pub fn name(self) -> &'static str {
        match self {
            PixelFilter::Box => "box",
            PixelFilter::Centre { .. } => "centre",
        }
    }

    /// This filter with K×K sub-pixel centres if it is `centre`; `box` stays `box` (it
    /// integrates the whole pixel area whatever the rasteriser's supersampling).
    pub fn with_ssaa(self, k: u32) -> PixelFilter {
        match self {
            PixelFilter::Box => PixelFilter::Box,
            PixelFilter::Centre { .. } => PixelFilter::Centre { ssaa: k },
        }
    }

    /// The number of positions a pixel's samples are shared between, each taking the same
    /// number: K² for `centre` with K×K sub-pixels, 1 otherwise (the box filter's jittered
    /// samples need no split). A sample count must be a multiple of it.
    pub fn subpixels(self) -> u32 {
        match self {
            PixelFilter::Box => 1,
            PixelFilter::Centre { ssaa } => ssaa.saturating_mul(ssaa),
        }
    }

    /// `centre 2x2` for K > 1, else [`PixelFilter::name`].
    pub fn describe(self) -> String {
        match self {
            PixelFilter::Centre { ssaa } if ssaa > 1 => format!("centre {ssaa}x{ssaa}"),
            _ => self.name().to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spellings_print_as_one_name() {
        for (spelling, filter) in PixelFilter::SPELLINGS {
            assert_eq!(filter.name(), spelling.replace("center", "centre"));
        }
        assert_eq!(PixelFilter::default(), PixelFilter::Box);
    }

    #[test]
    fn ssaa_applies_to_centre_only() {
        let centre = PixelFilter::Centre { ssaa: 1 };
        assert_eq!(centre.with_ssaa(3), PixelFilter::Centre { ssaa: 3 });
        assert_eq!(centre.with_ssaa(3).subpixels(), 9);
        assert_eq!(centre.with_ssaa(3).describe(), "centre 3x3");
        assert_eq!(centre.describe(), "centre");
        assert_eq!(PixelFilter::Box.with_ssaa(3), PixelFilter::Box);
        assert_eq!(PixelFilter::Box.subpixels(), 1);
    }
}
