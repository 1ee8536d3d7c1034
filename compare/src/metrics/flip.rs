//! FLIP: a perceptual image-difference map for a rendered test image against its reference.
//!
//! Sources (cited below as the "FLIP paper" and the "HDR-FLIP paper"):
//!
//! * FLIP paper: P. Andersson, J. Nilsson, T. Akenine-Möller, M. Oskarsson, K. Åström,
//!   M. D. Fairchild, "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM Comput.
//!   Graph. Interact. Tech. (HPG) 3(2), article 15, 2020. Sections are cited by their titles:
//!   the *colour pipeline* (spatial filtering with contrast sensitivity functions, Hunt
//!   adjustment, HyAB distance, error redistribution), the *feature pipeline* (edge and point
//!   detection) and the *final error* that combines them; the paper's erratum (feature
//!   input divided by 116, not 100) is applied.
//! * HDR-FLIP paper: P. Andersson, J. Nilsson, P. Shirley, T. Akenine-Möller, "Visualizing Errors
//!   in Rendered High Dynamic Range Images", Eurographics 2021 short papers: HDR-FLIP is the
//!   per-pixel maximum of LDR-FLIP over a range of exposures of both images, each exposure
//!   tone mapped; the range is derived from the reference's luminance.
//!
//! **What it measures.** LDR-FLIP approximates, per pixel, how different two images look to
//! an observer who flips between them on a display at a given number of pixels per degree
//! of visual angle. The map is in [0, 1]: 0 for identical images, about 0.97 for black
//! against white. Its mean is the usual single number (the FLIP authors recommend the mean).
//!
//! **Inputs.** [`FlipInput`] images of linear Rec.709 RGB (the sRGB primaries), row-major,
//! row 0 at the top. [`ldr_flip`] takes display-referred *linear* values and clamps them to
//! [0, 1]; an sRGB-encoded image (an 8-bit PNG) must be decoded to linear first. [`hdr_flip`]
//! takes scene-referred linear radiance (non-negative; negative values are clamped away by
//! the tone mapping).
//!
//! **Reference implementation.** Results agree with NVIDIA's `flip-evaluator` 1.7 (the pip
//! package; LDR with `inputsRGB=False`, HDR with its defaults) to within float rounding: the
//! same defaults (ACES tone mapper, 67.02 pixels per degree), filter radii, clamp-to-edge
//! borders and single precision. Two of its behaviours are not in the papers and are
//! matched here: the automatic stop exposure is at most 24 stops above the start exposure,
//! and the median luminance is the upper median (element n/2 of the sorted values).
//!
//! **Threads and memory.** The convolutions run row by row and the per-pixel stages
//! pixel by pixel on rayon's pool; every value is computed by the same operations in the same
//! order as on one thread, so the maps are bit for bit those of a sequential run. The planes
//! of one evaluation come from a [`Planes`] pool and go back to it, so HDR-FLIP's exposures
//! reuse one set of buffers instead of allocating (and page-faulting) ~50 planes each.
//!
//! **Caveats.**
//! * The caller checks sizes: both images must have `width * height` pixels (asserted).
//! * The caller rejects NaN and ±Inf pixels; they are not diagnosed here (a NaN pixel
//!   compares as black after clamping, the reference tool's behaviour too).
//! * Where the reference tool exits with an error, these functions choose instead (never
//!   panicking on finite input): an all-black (or all non-positive) HDR reference gets the
//!   exposure range [0, 0]; a given range with start > stop is swapped; at most 256
//!   exposures are evaluated; pixels per degree outside [0.01, 10 000] (or NaN) are
//!   clamped into that range.
//! * Values above ~1.8e19 overflow the tone mapper's squares and map to black, as in the
//!   reference tool.

use rayon::prelude::*;
use std::f32::consts::PI;

/// An RGB image in linear Rec.709, row-major, row 0 at the top.
#[derive(Clone, Copy, Debug)]
pub struct FlipInput<'a> {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `width * height` linear RGB pixels.
    pub rgb: &'a [[f32; 3]],
}

/// HDR-FLIP result: the per-pixel error map, the exposure range used and the exposure count.
#[derive(Clone, Debug, PartialEq)]
pub struct HdrFlip {
    /// Per-pixel maximum of LDR-FLIP over the exposures, in [0, 1], `width * height` values.
    pub map: Vec<f32>,
    /// First exposure compensation, in stops (the image is scaled by 2^start).
    pub start_exposure: f32,
    /// Last exposure compensation, in stops.
    pub stop_exposure: f32,
    /// Exposures evaluated, evenly spaced from start to stop (at least 2).
    pub exposures: usize,
}

/// Smallest pixels-per-degree value used; smaller (or NaN) values are raised to it.
const MIN_PIXELS_PER_DEGREE: f32 = 0.01;
/// Largest pixels-per-degree value used (filter radii grow linearly with it).
const MAX_PIXELS_PER_DEGREE: f32 = 10_000.0;
/// Most exposures one HDR-FLIP evaluates (the automatic range never needs more than 25).
const MAX_EXPOSURES: usize = 256;

// ---------------------------------------------------------------------------------------
// Constants of the papers.
// ---------------------------------------------------------------------------------------

/// One channel's contrast sensitivity function in the spatial domain, a sum of two Gaussians
/// a₁√(π/b₁)·exp(−π²x²/b₁) + a₂√(π/b₂)·exp(−π²x²/b₂), x in degrees (FLIP paper, colour pipeline,
/// spatial filtering; the frequency-domain CSF is a₁e^(−b₁ρ²) + a₂e^(−b₂ρ²)).
#[derive(Clone, Copy)]
struct Csf {
    a1: f32,
    b1: f32,
    a2: f32,
    b2: f32,
}

/// Achromatic channel (Yy) CSF (FLIP paper, colour pipeline, table of CSF constants).
const CSF_ACHROMATIC: Csf = Csf {
    a1: 1.0,
    b1: 0.0047,
    a2: 0.0,
    b2: 1.0e-5,
};
/// Red-green channel (Cx) CSF.
const CSF_RED_GREEN: Csf = Csf {
    a1: 1.0,
    b1: 0.0053,
    a2: 0.0,
    b2: 1.0e-5,
};
/// Blue-yellow channel (Cz) CSF, the only one with a second Gaussian.
const CSF_BLUE_YELLOW: Csf = Csf {
    a1: 34.1,
    b1: 0.04,
    a2: 13.5,
    b2: 0.025,
};

/// Exponent q_c compressing the HyAB colour difference (FLIP paper, colour pipeline).
const COLOR_EXPONENT: f32 = 0.7;
/// p_c: fraction of the maximum colour difference where the redistribution's knee lies.
const COLOR_KNEE_FRACTION: f32 = 0.4;
/// p_t: error value assigned to the knee; differences above it share the range (p_t, 1].
const COLOR_KNEE_ERROR: f32 = 0.95;
/// w: width of the edge and point detectors in degrees (FLIP paper, feature pipeline).
const FEATURE_WIDTH_DEGREES: f32 = 0.082;
/// q_f: exponent of the feature difference (FLIP paper, feature pipeline).
const FEATURE_EXPONENT: f32 = 0.5;
const _: () = assert!(
    FEATURE_EXPONENT == 0.5,
    "feature_differences takes the square root"
);

// The XYZ constants below keep the nine significant digits they are published with (nine
// digits pin down an f32 exactly); clippy would shorten some to the fewest digits that round
// to the same f32, which changes no value but hides where they come from.

/// D65 reference white in XYZ (Y = 1) of the sRGB-to-XYZ matrix below.
#[allow(clippy::excessive_precision)]
const D65_WHITE: [f32; 3] = [0.950_428_545, 1.0, 1.088_900_371];
/// Its reciprocal, applied before the CIELAB and YCxCz non-linearities.
#[allow(clippy::excessive_precision)]
const D65_WHITE_INVERSE: [f32; 3] = [1.052_156_925, 1.0, 0.918_357_670];

/// Linear Rec.709/sRGB to CIE XYZ (D65), IEC 61966-2-1, written as the exact ratios.
const RGB_TO_XYZ: [[f32; 3]; 3] = [
    [
        10_135_552.0 / 24_577_794.0,
        8_788_810.0 / 24_577_794.0,
        4_435_075.0 / 24_577_794.0,
    ],
    [
        2_613_072.0 / 12_288_897.0,
        8_788_810.0 / 12_288_897.0,
        887_015.0 / 12_288_897.0,
    ],
    [
        1_425_312.0 / 73_733_382.0,
        8_788_810.0 / 73_733_382.0,
        70_074_185.0 / 73_733_382.0,
    ],
];
/// CIE XYZ (D65) to linear Rec.709/sRGB, the inverse of [`RGB_TO_XYZ`].
#[allow(clippy::excessive_precision)]
const XYZ_TO_RGB: [[f32; 3]; 3] = [
    [3.241_003_275, -1.537_398_934, -0.498_615_861],
    [-0.969_224_334, 1.875_930_071, 0.041_554_224],
    [0.055_639_423, -0.204_011_202, 1.057_148_933],
];

/// The ACES filmic fit of Narkowicz (2015) as a ratio of quadratics in the exposed value x,
/// (c₀x² + c₁x + c₂)/(c₃x² + c₄x + c₅), with his 0.6 pre-exposure folded in:
/// 0.6x(2.51·0.6x + 0.03)/(0.6x(2.43·0.6x + 0.59) + 0.14). HDR-FLIP paper, tone mapping; ACES
/// is the reference tool's default.
const ACES_COEFFICIENTS: [f32; 6] = [
    0.6 * 0.6 * 2.51,
    0.6 * 0.03,
    0.0,
    0.6 * 0.6 * 2.43,
    0.6 * 0.59,
    0.14,
];
/// Tone-mapped value whose exposure defines the automatic range (HDR-FLIP paper, exposure range).
const EXPOSURE_TARGET: f32 = 0.85;
/// Most stops between the automatic start and stop exposures (flip-evaluator 1.7's limit,
/// reached when at least half the reference is black).
const MAX_AUTOMATIC_STOPS: f32 = 24.0;

// ---------------------------------------------------------------------------------------
// Public API.
// ---------------------------------------------------------------------------------------

/// Pixels per degree for the standard FLIP viewing conditions (FLIP paper, viewing conditions):
/// a 0.7 m wide monitor of 3840 pixels seen from 0.7 m, ppd = d·(N/W)·π/180 ≈ 67.02.
pub fn default_pixels_per_degree() -> f32 {
    let (distance_m, width_px, width_m) = (0.7_f32, 3840.0_f32, 0.7_f32);
    distance_m * (width_px / width_m) * (PI / 180.0)
}

/// LDR-FLIP per-pixel error map in [0, 1] (`width * height` values) of `test` against
/// `reference` viewed at `pixels_per_degree` (FLIP paper, all three pipelines).
///
/// Both inputs are LINEAR display values, clamped to [0, 1] here. This equals the reference
/// tool run on the same linear data with `inputsRGB=False`; for sRGB-encoded data (what the
/// tool assumes for PNG input) decode to linear first. Panics if a pixel count differs from
/// `width * height` or the two sizes differ (the caller guarantees both).
pub fn ldr_flip(reference: FlipInput, test: FlipInput, pixels_per_degree: f32) -> Vec<f32> {
    let size = checked_size(&reference, &test);
    let clamp_all = |img: &FlipInput| -> Vec<[f32; 3]> { img.rgb.iter().map(|&c| clamp_rgb(c)).collect() };
    let ppd = sanitized_ppd(pixels_per_degree);
    ldr_flip_of_clamped(
        &clamp_all(&reference),
        &clamp_all(&test),
        size,
        &FlipFilters::new(ppd),
        &Planes::new(size.pixels()),
    )
}

/// HDR-FLIP (HDR-FLIP paper): the per-pixel maximum of LDR-FLIP over N exposures c_i of both
/// images, each scaled by 2^c_i, ACES tone mapped and clamped to [0, 1]; c_i runs evenly
/// from `start` to `stop` with N = max(2, ⌈stop − start⌉).
///
/// `exposure_range` is (start, stop) in stops; `None` derives it from the reference as the
/// paper does: start = log₂(x_max / Y_max), stop = log₂(x_max / Y_median), x_max being the
/// value ACES maps to 0.85 and Y the reference's luminances (stop capped at start + 24, as
/// in flip-evaluator 1.7). Panics on a size mismatch (the caller guarantees sizes).
pub fn hdr_flip(
    reference: FlipInput,
    test: FlipInput,
    pixels_per_degree: f32,
    exposure_range: Option<(f32, f32)>,
) -> HdrFlip {
    let size = checked_size(&reference, &test);
    let (start, stop) = match exposure_range {
        Some((a, b)) if a > b => (b, a),
        Some(range) => range,
        None => automatic_exposure_range(reference.rgb),
    };
    let exposures = exposure_count(start, stop);
    let step = (stop - start) / (exposures - 1) as f32;
    let filters = FlipFilters::new(sanitized_ppd(pixels_per_degree));
    let planes = Planes::new(size.pixels());
    let mut map = vec![0.0_f32; size.pixels()];
    let mut exposed_reference = vec![[0.0_f32; 3]; size.pixels()];
    let mut exposed_test = vec![[0.0_f32; 3]; size.pixels()];
    for i in 0..exposures {
        let exposure = start + i as f32 * step;
        expose_and_tone_map(reference.rgb, exposure, &mut exposed_reference);
        expose_and_tone_map(test.rgb, exposure, &mut exposed_test);
        let errors = ldr_flip_of_clamped(&exposed_reference, &exposed_test, size, &filters, &planes);
        map.par_iter_mut()
            .zip(&errors)
            .for_each(|(worst, &e)| *worst = worst.max(e));
        planes.give(errors);
    }
    HdrFlip {
        map,
        start_exposure: start,
        stop_exposure: stop,
        exposures,
    }
}

/// The mean of an error map (0 for an empty map), accumulated in f64.
pub fn mean(map: &[f32]) -> f32 {
    if map.is_empty() {
        return 0.0;
    }
    (map.iter().map(|&v| f64::from(v)).sum::<f64>() / map.len() as f64) as f32
}

/// The automatic exposure range (start, stop) in stops (HDR-FLIP paper, exposure range): with
/// x_max the exposed value the ACES curve maps to 0.85, start = log₂(x_max / Y_max) and
/// stop = log₂(x_max / Y_median) over the reference's Rec.709 luminances Y (upper median).
/// As in flip-evaluator 1.7, stop ≤ start + 24. A reference with no positive luminance
/// gets (0, 0) (the reference tool exits with an error there).
fn automatic_exposure_range(reference: &[[f32; 3]]) -> (f32, f32) {
    let mut luminances: Vec<f32> = reference.iter().map(|&c| luminance(c)).collect();
    if luminances.is_empty() {
        return (0.0, 0.0);
    }
    let y_max = luminances.iter().fold(-1e30_f32, |m, &y| m.max(y));
    let middle = luminances.len() / 2;
    let y_median = *luminances.select_nth_unstable_by(middle, f32::total_cmp).1;
    let x_max = exposed_value_reaching(EXPOSURE_TARGET);
    let start = (x_max / y_max).log2();
    if y_max <= 0.0 || !start.is_finite() {
        return (0.0, 0.0);
    }
    let stop = (x_max / y_median).log2();
    // f32::min ignores a NaN stop (negative median): the 24-stop limit applies then too.
    (start, stop.min(start + MAX_AUTOMATIC_STOPS))
}

// ---------------------------------------------------------------------------------------
// LDR-FLIP core.
// ---------------------------------------------------------------------------------------

/// Image dimensions.
#[derive(Clone, Copy, Debug)]
struct Size {
    width: usize,
    height: usize,
}

impl Size {
    fn pixels(self) -> usize {
        self.width * self.height
    }
}

/// The shared size of two inputs; panics if they differ or a slice has the wrong length.
fn checked_size(reference: &FlipInput, test: &FlipInput) -> Size {
    assert_eq!(
        reference.rgb.len(),
        reference.width * reference.height,
        "FLIP: reference pixel count"
    );
    assert_eq!(test.rgb.len(), test.width * test.height, "FLIP: test pixel count");
    assert_eq!(
        (reference.width, reference.height),
        (test.width, test.height),
        "FLIP: image sizes"
    );
    Size {
        width: reference.width,
        height: reference.height,
    }
}

/// `pixels_per_degree` clamped into the supported range (NaN becomes the minimum).
fn sanitized_ppd(pixels_per_degree: f32) -> f32 {
    if pixels_per_degree > MIN_PIXELS_PER_DEGREE {
        pixels_per_degree.min(MAX_PIXELS_PER_DEGREE)
    } else {
        MIN_PIXELS_PER_DEGREE
    }
}

/// Reusable planes of one image size. Every stage takes its outputs here and gives back the
/// planes it no longer needs; the contents of a plane taken are unspecified (each stage
/// overwrites every value). Used from the evaluating thread only (rayon works inside stages).
struct Planes {
    len: usize,
    free: std::cell::RefCell<Vec<Vec<f32>>>,
}

impl Planes {
    fn new(len: usize) -> Planes {
        Planes {
            len,
            free: std::cell::RefCell::new(Vec::new()),
        }
    }

    /// A plane of `len` values (a reused one when there is one).
    fn take(&self) -> Vec<f32> {
        self.free
            .borrow_mut()
            .pop()
            .unwrap_or_else(|| vec![0.0; self.len])
    }

    /// Returns `plane` to the pool.
    fn give(&self, plane: Vec<f32>) {
        debug_assert_eq!(plane.len(), self.len);
        self.free.borrow_mut().push(plane);
    }
}

/// The filters of one viewing condition: CSF kernels (colour) and detector kernels (features).
struct FlipFilters {
    spatial: SpatialKernels,
    feature: FeatureKernels,
}

impl FlipFilters {
    fn new(ppd: f32) -> FlipFilters {
        FlipFilters {
            spatial: SpatialKernels::new(ppd),
            feature: FeatureKernels::new(ppd),
        }
    }
}

/// LDR-FLIP of two images already clamped to [0, 1]: ΔE = ΔE_c^(1 − ΔE_f) per pixel
/// (FLIP paper, final error), ΔE_c from the colour pipeline and ΔE_f from the feature pipeline.
/// The map is a plane of `planes`.
fn ldr_flip_of_clamped(
    reference: &[[f32; 3]],
    test: &[[f32; 3]],
    size: Size,
    filters: &FlipFilters,
    planes: &Planes,
) -> Vec<f32> {
    if size.pixels() == 0 {
        return Vec::new();
    }
    let reference = OpponentImage::from_linear_rgb(reference, planes);
    let test = OpponentImage::from_linear_rgb(test, planes);
    let mut error = color_differences(&reference, &test, size, &filters.spatial, planes);
    let feature = feature_differences(&reference.y, &test.y, size, &filters.feature, planes);
    reference.give_to(planes);
    test.give_to(planes);
    error
        .par_iter_mut()
        .zip(&feature)
        .for_each(|(c, &f)| *c = c.powf(1.0 - f));
    planes.give(feature);
    error
}

/// An image in YyCxCz, one plane per channel.
struct OpponentImage {
    y: Vec<f32>,
    cx: Vec<f32>,
    cz: Vec<f32>,
}

impl OpponentImage {
    /// Linear RGB → XYZ → YyCxCz (FLIP paper, colour pipeline: the opponent space is the
    /// linearised CIELAB of Flohr et al., without the cube root).
    fn from_linear_rgb(rgb: &[[f32; 3]], planes: &Planes) -> OpponentImage {
        let (mut y, mut cx, mut cz) = (planes.take(), planes.take(), planes.take());
        y.par_iter_mut()
            .zip(cx.par_iter_mut())
            .zip(cz.par_iter_mut())
            .zip(rgb.par_iter())
            .for_each(|(((y, cx), cz), &c)| {
                [*y, *cx, *cz] = xyz_to_ycxcz(mat3(&RGB_TO_XYZ, c));
            });
        OpponentImage { y, cx, cz }
    }

    fn give_to(self, planes: &Planes) {
        [self.y, self.cx, self.cz]
            .into_iter()
            .for_each(|p| planes.give(p));
    }
}

// ---------------------------------------------------------------------------------------
// Colour pipeline.
// ---------------------------------------------------------------------------------------

/// Separable CSF kernels, 2r + 1 taps each, r = ⌈3·√(b_max/(2π²))·ppd⌉ (three standard
/// deviations of the widest Gaussian, b_max = 0.04; FLIP paper, colour pipeline).
struct SpatialKernels {
    achromatic: Vec<f32>,
    red_green: Vec<f32>,
    /// The blue-yellow CSF is a sum of two Gaussians, G₁(x)G₁(y) + G₂(x)G₂(y): one separable
    /// kernel per term, each term's 1D factor √(a_i√(π/b_i))·exp(−π²x²/b_i), scaled so the
    /// whole 2D filter sums to 1.
    blue_yellow: [Vec<f32>; 2],
}

impl SpatialKernels {
    fn new(ppd: f32) -> SpatialKernels {
        let pi_squared = PI * PI;
        let widest = [CSF_ACHROMATIC, CSF_RED_GREEN, CSF_BLUE_YELLOW]
            .iter()
            .flat_map(|c| [c.b1, c.b2])
            .fold(0.0_f32, f32::max);
        let radius = (3.0 * (widest / (2.0 * pi_squared)).sqrt() * ppd).ceil() as i64;
        let positions: Vec<f32> = (-radius..=radius).map(|i| i as f32 * (1.0 / ppd)).collect();
        let gaussian = |x: f32, a: f32, b: f32| a * (PI / b).sqrt() * (-pi_squared * x * x / b).exp();
        let factor = |x: f32, a: f32, b: f32| (a * (PI / b).sqrt()).sqrt() * (-pi_squared * x * x / b).exp();
        let normalized = |v: Vec<f32>| {
            let sum: f32 = v.iter().sum();
            v.into_iter().map(|w| w * (1.0 / sum)).collect::<Vec<f32>>()
        };
        let single = |c: Csf| normalized(positions.iter().map(|&x| gaussian(x, c.a1, c.b1)).collect());
        let by = CSF_BLUE_YELLOW;
        let first: Vec<f32> = positions.iter().map(|&x| factor(x, by.a1, by.b1)).collect();
        let second: Vec<f32> = positions.iter().map(|&x| factor(x, by.a2, by.b2)).collect();
        let (s1, s2): (f32, f32) = (first.iter().sum(), second.iter().sum());
        let scale = 1.0 / (s1 * s1 + s2 * s2).sqrt();
        SpatialKernels {
            achromatic: single(CSF_ACHROMATIC),
            red_green: single(CSF_RED_GREEN),
            blue_yellow: [first, second].map(|k| k.into_iter().map(|w| w * scale).collect()),
        }
    }
}

/// The CSF-filtered image, one plane per YyCxCz channel (FLIP paper, colour pipeline).
fn csf_filtered(img: &OpponentImage, size: Size, kernels: &SpatialKernels, planes: &Planes) -> [Vec<f32>; 3] {
    let separable = |plane: &[f32], k: &[f32]| {
        let rows = convolve_rows(plane, size, k, planes);
        let filtered = convolve_columns(&rows, size, k, planes);
        planes.give(rows);
        filtered
    };
    let y = separable(&img.y, &kernels.achromatic);
    let cx = separable(&img.cx, &kernels.red_green);
    let mut cz = separable(&img.cz, &kernels.blue_yellow[0]);
    let cz_second = separable(&img.cz, &kernels.blue_yellow[1]);
    cz.par_iter_mut().zip(&cz_second).for_each(|(a, b)| *a += b);
    planes.give(cz_second);
    [y, cx, cz]
}

/// Per-pixel colour error ΔE_c in [0, 1] (FLIP paper, colour pipeline): CSF filtering, back to
/// linear RGB clamped to [0, 1], CIELAB with the Hunt adjustment, HyAB distance^q_c, and the
/// redistribution with p_c, p_t against the largest distance (green against blue).
fn color_differences(
    reference: &OpponentImage,
    test: &OpponentImage,
    size: Size,
    k: &SpatialKernels,
    planes: &Planes,
) -> Vec<f32> {
    let max_distance = hyab(
        hunt_adjusted_lab([0.0, 1.0, 0.0]),
        hunt_adjusted_lab([0.0, 0.0, 1.0]),
    )
    .powf(COLOR_EXPONENT);
    let [ry, rcx, rcz] = csf_filtered(reference, size, k, planes);
    let [ty, tcx, tcz] = csf_filtered(test, size, k, planes);
    let mut error = planes.take();
    // Two passes over each chunk: the distances (plain arithmetic, which the compiler
    // vectorises across pixels), then the exponent and redistribution (a libm call each).
    error
        .par_chunks_mut(PIXEL_CHUNK)
        .enumerate()
        .for_each(|(chunk, errors)| {
            let first = chunk * PIXEL_CHUNK;
            // XYZ/white of both filtered colours, then CIELAB's f over all of them in one
            // flat loop (vectorised), then L*a*b*, Hunt and HyAB per pixel.
            let mut ratios = vec![0.0_f32; 6 * errors.len()];
            for (j, pair) in ratios.chunks_exact_mut(6).enumerate() {
                let i = first + j;
                let r = clamp_rgb(opponent_to_linear_rgb([ry[i], rcx[i], rcz[i]]));
                let t = clamp_rgb(opponent_to_linear_rgb([ty[i], tcx[i], tcz[i]]));
                pair[..3].copy_from_slice(&white_relative_xyz(r));
                pair[3..].copy_from_slice(&white_relative_xyz(t));
            }
            ratios.iter_mut().for_each(|v| *v = cielab_f(*v));
            for (e, f) in errors.iter_mut().zip(ratios.chunks_exact(6)) {
                let r = hunt_adjusted(lab_of_f([f[0], f[1], f[2]]));
                let t = hunt_adjusted(lab_of_f([f[3], f[4], f[5]]));
                *e = hyab(r, t);
            }
            for e in errors.iter_mut() {
                *e = redistribute_color_error(e.powf(COLOR_EXPONENT), max_distance);
            }
        });
    [ry, rcx, rcz, ty, tcx, tcz]
        .into_iter()
        .for_each(|p| planes.give(p));
    error
}

/// Maps a compressed colour distance d to [0, 1] (FLIP paper, colour pipeline): d < p_c·c_max
/// goes linearly to [0, p_t); the rest linearly to [p_t, 1] (1 at c_max).
fn redistribute_color_error(distance: f32, max_distance: f32) -> f32 {
    let knee = COLOR_KNEE_FRACTION * max_distance;
    if distance < knee {
        distance * (COLOR_KNEE_ERROR / knee)
    } else {
        COLOR_KNEE_ERROR + ((distance - knee) / (max_distance - knee)) * (1.0 - COLOR_KNEE_ERROR)
    }
}

/// CIELAB of a linear RGB colour with the Hunt adjustment a*, b* ← 0.01·L*·(a*, b*)
/// (FLIP paper, colour pipeline: chroma appears weaker at low lightness). L* is that of the
/// filtered, clamped colour itself.
fn hunt_adjusted_lab(linear_rgb: [f32; 3]) -> [f32; 3] {
    hunt_adjusted(xyz_to_cielab(mat3(&RGB_TO_XYZ, linear_rgb)))
}

/// The Hunt adjustment of a CIELAB colour (see [`hunt_adjusted_lab`]).
fn hunt_adjusted([l, a, b]: [f32; 3]) -> [f32; 3] {
    [l, 0.01 * l * a, 0.01 * l * b]
}

/// HyAB distance |ΔL| + √(Δa² + Δb²) (Abasi, Amani Tehran, Fairchild 2020; FLIP paper, colour
/// pipeline).
fn hyab(p: [f32; 3], q: [f32; 3]) -> f32 {
    let (da, db) = (p[1] - q[1], p[2] - q[2]);
    (p[0] - q[0]).abs() + (da * da + db * db).sqrt()
}

// ---------------------------------------------------------------------------------------
// Feature pipeline.
// ---------------------------------------------------------------------------------------

/// Separable edge/point detector kernels (FLIP paper, feature pipeline): a Gaussian of
/// σ = ½·w·ppd pixels and its first and second derivatives over 2r + 1 taps, r = ⌈3σ⌉.
/// The Gaussian sums to 1; each derivative's positive taps sum to 1 and negative to −1.
struct FeatureKernels {
    gaussian: Vec<f32>,
    first_derivative: Vec<f32>,
    second_derivative: Vec<f32>,
}

impl FeatureKernels {
    fn new(ppd: f32) -> FeatureKernels {
        let sigma = 0.5 * FEATURE_WIDTH_DEGREES * ppd;
        let radius = (3.0 * sigma).ceil() as i64;
        let xs: Vec<f32> = (-radius..=radius).map(|i| i as f32).collect();
        let g: Vec<f32> = xs
            .iter()
            .map(|&x| (-(x * x) / (2.0 * sigma * sigma)).exp())
            .collect();
        let d1: Vec<f32> = xs.iter().zip(&g).map(|(&x, &g)| -x * g).collect();
        let d2: Vec<f32> = xs
            .iter()
            .zip(&g)
            .map(|(&x, &g)| (x * x / (sigma * sigma) - 1.0) * g)
            .collect();
        let g_sum: f32 = g.iter().sum();
        FeatureKernels {
            gaussian: g.iter().map(|w| w / g_sum).collect(),
            first_derivative: balanced(&d1),
            second_derivative: balanced(&d2),
        }
    }
}

/// Scales positive taps to sum to 1 and the others to sum to −1.
fn balanced(kernel: &[f32]) -> Vec<f32> {
    let positive: f32 = kernel.iter().filter(|&&w| w > 0.0).sum();
    let negative: f32 = -kernel.iter().filter(|&&w| w <= 0.0).sum::<f32>();
    kernel
        .iter()
        .map(|&w| w / if w > 0.0 { positive } else { negative })
        .collect()
}

/// Per-pixel feature error ΔE_f in [0, 1] (FLIP paper, feature pipeline): on the achromatic
/// channel normalised to [0, 1] as (Yy + 16)/116, edge strength |∇| and point strength |∇²|
/// of each image; ΔE_f = (max(|Δedge|, |Δpoint|)/√2)^q_f.
fn feature_differences(
    reference_y: &[f32],
    test_y: &[f32],
    size: Size,
    k: &FeatureKernels,
    planes: &Planes,
) -> Vec<f32> {
    let (reference_edge, reference_point) = feature_strengths(reference_y, size, k, planes);
    let (mut edge, mut point) = feature_strengths(test_y, size, k, planes);
    let normalization = 1.0 / 2.0_f32.sqrt();
    // The test's planes become |Δedge| and then the error.
    edge.par_iter_mut()
        .zip(point.par_iter_mut())
        .zip(reference_edge.par_iter().zip(reference_point.par_iter()))
        .for_each(|((e, p), (re, rp))| {
            let edge = (re - *e).abs();
            let point = (rp - *p).abs();
            // x^q_f with q_f = ½ is the square root (exact, and cheaper than powf).
            *e = (normalization * edge.max(point)).sqrt();
        });
    [reference_edge, reference_point, point]
        .into_iter()
        .for_each(|p| planes.give(p));
    edge
}

/// (edge, point) strength per pixel: √(gx² + gy²) of the first-derivative responses and
/// √(hx² + hy²) of the second-derivative ones, each detector separable as derivative along
/// one axis times the Gaussian along the other.
/// Returns the edge and the point plane.
fn feature_strengths(
    achromatic: &[f32],
    size: Size,
    k: &FeatureKernels,
    planes: &Planes,
) -> (Vec<f32>, Vec<f32>) {
    let mut normalized = planes.take();
    normalized
        .par_iter_mut()
        .zip(achromatic)
        .for_each(|(n, &y)| *n = y * (1.0 / 116.0) + 16.0 / 116.0);
    let derivative_then_smooth = |derivative: &[f32]| {
        let rows = convolve_rows(&normalized, size, derivative, planes);
        let both = convolve_columns(&rows, size, &k.gaussian, planes);
        planes.give(rows);
        both
    };
    let mut dx = derivative_then_smooth(&k.first_derivative);
    let mut ddx = derivative_then_smooth(&k.second_derivative);
    let smooth_x = convolve_rows(&normalized, size, &k.gaussian, planes);
    let dy = convolve_columns(&smooth_x, size, &k.first_derivative, planes);
    let ddy = convolve_columns(&smooth_x, size, &k.second_derivative, planes);
    // dx and ddx become the edge and point strengths.
    dx.par_iter_mut()
        .zip(ddx.par_iter_mut())
        .zip(dy.par_iter().zip(ddy.par_iter()))
        .for_each(|((gx, hx), (gy, hy))| {
            *gx = (*gx * *gx + gy * gy).sqrt();
            *hx = (*hx * *hx + hy * hy).sqrt();
        });
    [normalized, smooth_x, dy, ddy]
        .into_iter()
        .for_each(|p| planes.give(p));
    (dx, ddx)
}

// ---------------------------------------------------------------------------------------
// Separable convolution with clamp-to-edge borders (the reference tool's border handling).
// ---------------------------------------------------------------------------------------

/// Horizontal convolution, out(x) = Σ_k kernel_k · in(clamp(x + k − r)), taps in order, into
/// a plane of `planes`.
fn convolve_rows(plane: &[f32], size: Size, kernel: &[f32], planes: &Planes) -> Vec<f32> {
    let (w, radius) = (size.width, kernel.len() / 2);
    let offsets: Vec<usize> = (0..kernel.len()).collect();
    let mut out = planes.take();
    out.par_chunks_mut(w).zip(plane.par_chunks(w)).for_each_init(
        || vec![0.0_f32; w + 2 * radius],
        |padded, (row_out, row_in)| {
            for (i, p) in padded.iter_mut().enumerate() {
                *p = row_in[i.saturating_sub(radius).min(w - 1)];
            }
            convolve_line(row_out, kernel, padded, &offsets);
        },
    );
    out
}

/// Vertical convolution, out(y) = Σ_k kernel_k · in(clamp(y + k − r)), taps in order, into a
/// plane of `planes`. The 2r + 1 source rows of one output row (≤ 41 rows of a 1080p image,
/// 300 KiB) stay in L2 for the next row, which shares all but one of them.
fn convolve_columns(plane: &[f32], size: Size, kernel: &[f32], planes: &Planes) -> Vec<f32> {
    let (w, h, radius) = (size.width, size.height, kernel.len() / 2);
    let mut out = planes.take();
    out.par_chunks_mut(w).enumerate().for_each_init(
        || vec![0_usize; kernel.len()],
        |offsets, (y, row_out)| {
            for (k, o) in offsets.iter_mut().enumerate() {
                *o = (y + k).saturating_sub(radius).min(h - 1) * w;
            }
            convolve_line(row_out, kernel, plane, offsets);
        },
    );
    out
}

/// out[x] = Σ_k kernel[k] · source[offsets[k] + x], the taps summed in order from 0 (the
/// convolutions' inner loop). Blocks of [`LANES`] outputs are accumulated in registers over
/// all taps before they are stored, which the compiler turns into vector arithmetic; each
/// value is still the same sum in the same order, so the result is bit for bit that of the
/// plain loop.
fn convolve_line(out: &mut [f32], kernel: &[f32], source: &[f32], offsets: &[usize]) {
    let whole = out.len() / LANES * LANES;
    for (block, chunk) in out[..whole].chunks_exact_mut(LANES).enumerate() {
        let x = block * LANES;
        let mut acc = [0.0_f32; LANES];
        for (&weight, &o) in kernel.iter().zip(offsets) {
            let v: &[f32; LANES] = source[o + x..o + x + LANES]
                .try_into()
                .expect("a block of LANES values");
            for (a, &value) in acc.iter_mut().zip(v) {
                *a += weight * value;
            }
        }
        chunk.copy_from_slice(&acc);
    }
    for (x, value) in out.iter_mut().enumerate().skip(whole) {
        *value = kernel
            .iter()
            .zip(offsets)
            .fold(0.0, |sum, (&weight, &o)| sum + weight * source[o + x]);
    }
}

/// Pixels per task of the per-pixel colour stage.
const PIXEL_CHUNK: usize = 4096;

/// Outputs accumulated together by [`convolve_line`] (four 4-wide or two 8-wide registers).
const LANES: usize = 16;

// ---------------------------------------------------------------------------------------
// Colour spaces.
// ---------------------------------------------------------------------------------------

/// 3×3 matrix times column vector.
fn mat3(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2])
}

/// Clamp each channel to [0, 1]; NaN becomes 0 (as the reference tool's clamp does).
fn clamp_rgb(c: [f32; 3]) -> [f32; 3] {
    c.map(|v| {
        let v = if v > 0.0 { v } else { 0.0 };
        if v > 1.0 {
            1.0
        } else {
            v
        }
    })
}

/// Rec.709 luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709).
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// XYZ → YyCxCz: with (x, y, z) = XYZ / white, Yy = 116y − 16, Cx = 500(x − y),
/// Cz = 200(y − z) (FLIP paper, colour pipeline).
fn xyz_to_ycxcz(xyz: [f32; 3]) -> [f32; 3] {
    let [x, y, z] = [0, 1, 2].map(|i| xyz[i] * D65_WHITE_INVERSE[i]);
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

/// YyCxCz → linear RGB (the inverse of [`xyz_to_ycxcz`], then [`XYZ_TO_RGB`]).
fn opponent_to_linear_rgb(ycxcz: [f32; 3]) -> [f32; 3] {
    let y = (ycxcz[0] + 16.0) / 116.0;
    let relative = [y + ycxcz[1] / 500.0, y, y - ycxcz[2] / 200.0];
    mat3(&XYZ_TO_RGB, [0, 1, 2].map(|i| relative[i] * D65_WHITE[i]))
}

/// XYZ → CIELAB (CIE 15:2004) against the D65 white: f(t) = ∛t above (6/29)³, else
/// t/(3·(6/29)²) + 4/29; L* = 116 f(y) − 16, a* = 500(f(x) − f(y)), b* = 200(f(y) − f(z)).
fn xyz_to_cielab(xyz: [f32; 3]) -> [f32; 3] {
    let [x, y, z] = xyz_ratios(xyz);
    lab_of_f([cielab_f(x), cielab_f(y), cielab_f(z)])
}

/// XYZ of a linear RGB colour relative to the D65 white, (X/Xn, Y/Yn, Z/Zn).
fn white_relative_xyz(linear_rgb: [f32; 3]) -> [f32; 3] {
    xyz_ratios(mat3(&RGB_TO_XYZ, linear_rgb))
}

fn xyz_ratios(xyz: [f32; 3]) -> [f32; 3] {
    [0, 1, 2].map(|i| xyz[i] * D65_WHITE_INVERSE[i])
}

/// CIELAB's f(t) (see [`xyz_to_cielab`]).
fn cielab_f(t: f32) -> f32 {
    let delta = 6.0_f32 / 29.0;
    if t > delta * delta * delta {
        cube_root(t)
    } else {
        t * (1.0 / (3.0 * delta * delta)) + 4.0 / 29.0
    }
}

/// L*, a*, b* from f(X/Xn), f(Y/Yn), f(Z/Zn).
fn lab_of_f([fx, fy, fz]: [f32; 3]) -> [f32; 3] {
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// ∛t for t > 0, within 1 ulp of libm's `cbrtf` and without a division: r ≈ t^(−1/3) from the
/// exponent bits (the bit pattern divided by −3 plus a bias, the inverse-cube-root analogue of
/// the fast inverse square root; Lomont 2003, "Fast Inverse Square Root"), refined by three
/// Newton steps r ← r·(4 − t·r³)/3 in f64 (each squares the relative error: ≲ 4 % → 5e-3 →
/// 7e-5 → 1e-8), then ∛t = t·r². libm's cbrtf was the colour pipeline's largest single cost
/// (6 calls per pixel and exposure); this is about 3× cheaper.
fn cube_root(t: f32) -> f32 {
    let x = f64::from(t);
    // bits/3 through f32 (exact to 2⁻²⁴ of the bits, far below the estimate's own error):
    // unlike an integer division it vectorises.
    let third = (t.to_bits() as i32 as f32 * (1.0 / 3.0)) as i32;
    let mut r = f64::from(f32::from_bits(0x54a2_fa8c_i32.wrapping_sub(third) as u32));
    for _ in 0..3 {
        r *= (4.0 - x * r * r * r) * (1.0 / 3.0);
    }
    (x * r * r) as f32
}

// ---------------------------------------------------------------------------------------
// HDR-FLIP exposure and tone mapping.
// ---------------------------------------------------------------------------------------

/// ACES (Narkowicz fit) of one exposed channel value (HDR-FLIP paper, tone mapping).
fn aces(x: f32) -> f32 {
    let c = ACES_COEFFICIENTS;
    ((x * x) * c[0] + x * c[1] + c[2]) / (x * x * c[3] + x * c[4] + c[5])
}

/// The exposed value x ≥ 0 with aces(x) = target: the larger root of
/// (c₀ − t·c₃)x² + (c₁ − t·c₄)x + (c₂ − t·c₅) = 0 (HDR-FLIP paper, exposure range).
fn exposed_value_reaching(target: f32) -> f32 {
    let c = ACES_COEFFICIENTS;
    let (a, b, q) = (c[0] - target * c[3], c[1] - target * c[4], c[2] - target * c[5]);
    if a == 0.0 {
        return -q / b;
    }
    let half = -0.5 * (b / a);
    half + (half * half - q / a).sqrt()
}

/// N = max(2, ⌈stop − start⌉) exposures (HDR-FLIP paper), at most [`MAX_EXPOSURES`].
fn exposure_count(start: f32, stop: f32) -> usize {
    let count = (stop - start).ceil().max(2.0);
    // `as` saturates (and maps NaN to 0), so any range yields a count in [2, MAX_EXPOSURES].
    (count as usize).clamp(2, MAX_EXPOSURES)
}

/// The image scaled by 2^exposure, ACES tone mapped per channel and clamped to [0, 1], into
/// `out`.
fn expose_and_tone_map(rgb: &[[f32; 3]], exposure: f32, out: &mut [[f32; 3]]) {
    let scale = 2.0_f32.powf(exposure);
    out.par_iter_mut()
        .zip(rgb)
        .for_each(|(o, c)| *o = clamp_rgb(c.map(|v| aces(v * scale))));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random image in [0, scale).
    fn pattern(width: usize, height: usize, seed: u64, scale: f32) -> Vec<[f32; 3]> {
        let mut state = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..width * height)
            .map(|_| [next() * scale, next() * scale, next() * scale])
            .collect()
    }

    fn input(width: usize, height: usize, rgb: &[[f32; 3]]) -> FlipInput<'_> {
        FlipInput { width, height, rgb }
    }

    #[test]
    fn identical_images_give_an_all_zero_map() {
        let img = pattern(40, 30, 1, 1.0);
        let map = ldr_flip(
            input(40, 30, &img),
            input(40, 30, &img),
            default_pixels_per_degree(),
        );
        assert_eq!(map.len(), 1200);
        assert!(map.iter().all(|&e| e == 0.0));
    }

    #[test]
    fn the_map_is_in_the_unit_interval() {
        let (a, b) = (pattern(37, 23, 2, 1.3), pattern(37, 23, 3, 1.3));
        for ppd in [5.0, default_pixels_per_degree(), 150.0] {
            let map = ldr_flip(input(37, 23, &a), input(37, 23, &b), ppd);
            assert!(map.iter().all(|e| (0.0..=1.0).contains(e)), "ppd {ppd}");
            assert!(mean(&map) > 0.1);
        }
    }

    #[test]
    fn black_against_white_is_a_large_error() {
        let (black, white) = (vec![[0.0; 3]; 256], vec![[1.0; 3]; 256]);
        let map = ldr_flip(
            input(16, 16, &black),
            input(16, 16, &white),
            default_pixels_per_degree(),
        );
        assert!(mean(&map) > 0.9, "mean {}", mean(&map));
    }

    #[test]
    fn hdr_flip_of_an_image_against_itself_is_zero() {
        let img = pattern(32, 16, 4, 8.0);
        let result = hdr_flip(
            input(32, 16, &img),
            input(32, 16, &img),
            default_pixels_per_degree(),
            None,
        );
        assert!(result.map.iter().all(|&e| e == 0.0));
        assert!(result.exposures >= 2 && result.start_exposure < result.stop_exposure);
    }

    /// The cube root agrees with libm's to 1 ulp over CIELAB's domain ((6/29)³ to ~1.1) and
    /// beyond.
    #[test]
    fn cube_root_is_within_one_ulp_of_libm() {
        let mut t = 1e-6_f32;
        let mut worst = 0;
        while t < 1e6 {
            let (ours, libm) = (cube_root(t), t.cbrt());
            worst = worst.max(ours.to_bits().abs_diff(libm.to_bits()));
            t *= 1.000_37;
        }
        assert!(worst <= 1, "{worst} ulp");
    }

    #[test]
    fn default_viewing_conditions_give_67_pixels_per_degree() {
        assert!((default_pixels_per_degree() - 67.020_645).abs() < 1e-4);
    }

    #[test]
    fn filters_are_normalised_and_sized_from_the_papers() {
        let ppd = default_pixels_per_degree();
        let spatial = SpatialKernels::new(ppd);
        assert_eq!(spatial.achromatic.len(), 21); // r = ⌈3·√(0.04/2π²)·67.02⌉ = 10
        assert!((spatial.achromatic.iter().sum::<f32>() - 1.0).abs() < 1e-5);
        let [first, second] = &spatial.blue_yellow;
        let total = first.iter().sum::<f32>().powi(2) + second.iter().sum::<f32>().powi(2);
        assert!((total - 1.0).abs() < 1e-5);
        let feature = FeatureKernels::new(ppd);
        assert_eq!(feature.gaussian.len(), 19); // σ = 2.75, r = 9
        let positive: f32 = feature.second_derivative.iter().filter(|w| **w > 0.0).sum();
        assert!((positive - 1.0).abs() < 1e-5);
    }

    #[test]
    fn automatic_exposures_follow_the_reference_luminance() {
        // Half the pixels at luminance 0.25, half at 1/16, one at 4: upper median 0.25.
        let mut img = vec![[0.25; 3]; 512];
        img.extend(vec![[0.0625; 3]; 512]);
        img[0] = [4.0; 3];
        let (start, stop) = automatic_exposure_range(&img);
        assert!(
            (start - (-0.916_703)).abs() < 1e-4 && (stop - 3.083_297).abs() < 1e-4,
            "{start} {stop}"
        );
        assert_eq!(exposure_count(start, stop), 4);
        // Mostly black: the stop exposure is capped 24 stops above the start.
        let mut dark = vec![[0.0; 3]; 100];
        dark[3] = [2.0; 3];
        let (start, stop) = automatic_exposure_range(&dark);
        assert!((stop - start - 24.0).abs() < 1e-5);
    }

    #[test]
    fn degenerate_inputs_do_not_panic() {
        let black = vec![[0.0; 3]; 64];
        let spot = pattern(8, 8, 5, 3.0);
        let r = hdr_flip(
            input(8, 8, &black),
            input(8, 8, &spot),
            default_pixels_per_degree(),
            None,
        );
        assert_eq!((r.start_exposure, r.stop_exposure, r.exposures), (0.0, 0.0, 2));
        let r = hdr_flip(input(8, 8, &spot), input(8, 8, &black), 0.0, Some((3.0, -1e30)));
        assert_eq!(r.exposures, MAX_EXPOSURES);
        assert!(r.map.iter().all(|e| (0.0..=1.0).contains(e)));
        assert!(ldr_flip(input(0, 5, &[]), input(0, 5, &[]), 67.0).is_empty());
        let one = [[0.5_f32; 3]];
        assert_eq!(
            ldr_flip(input(1, 1, &one), input(1, 1, &one), f32::NAN),
            vec![0.0]
        );
    }
}
