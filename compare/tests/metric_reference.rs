//! Verity's LDR-FLIP and HDR-FLIP (compare::metrics::flip) agree with NVIDIA's reference
//! implementation, the pip package flip-evaluator 1.7, and its SSIM (compare::metrics::ssim)
//! with scikit-image 0.26's `structural_similarity` under the same settings, each run by
//! compare/python/metric_reference.py in the project's venv (`$VERITY_PYTHON` if set, else `.venv/bin/python` at the workspace
//! root; ./scripts/setup.sh installs it). No fixture files: every pair is built here, from the
//! HDR environment map scenes/assets/potsdamer_platz_512.exr and from a synthetic LDR chart,
//! written to EXR and handed to both implementations.
//!
//! Tolerances: the mean FLIP within 1e-3 and every pixel within 1e-2 of the reference, for
//! LDR-FLIP (linear input clamped to [0, 1]) and HDR-FLIP (same exposure range and count);
//! SSIM within 1e-4, mean and every pixel, over the pixels at least 5 from the border (where
//! skimage reflects the image and Verity truncates the window).
//! A missing Python or package fails the test (it never skips).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use compare::metrics::flip::{self, FlipInput};
use compare::metrics::ssim;

/// Largest allowed |mean(Verity) − mean(reference)|.
const MEAN_TOLERANCE: f64 = 1e-3;
/// Largest allowed per-pixel |Verity − reference|.
const PIXEL_TOLERANCE: f32 = 1e-2;
/// Largest allowed |Verity − scikit-image| of SSIM, mean and per pixel.
const SSIM_TOLERANCE: f64 = 1e-4;
/// The reference package versions checked against.
const FLIP_EVALUATOR_VERSION: &str = "1.7";
const SCIKIT_IMAGE_VERSION: &str = "0.26.0";

/// A linear RGB image, row-major, row 0 at the top.
#[derive(Clone)]
struct Image {
    width: usize,
    height: usize,
    rgb: Vec<[f32; 3]>,
}

impl Image {
    fn input(&self) -> FlipInput<'_> {
        FlipInput {
            width: self.width,
            height: self.height,
            rgb: &self.rgb,
        }
    }

    fn map(&self, f: impl Fn(usize, usize, [f32; 3]) -> [f32; 3]) -> Image {
        let rgb = (0..self.rgb.len())
            .map(|i| f(i % self.width, i / self.width, self.rgb[i]))
            .collect();
        Image {
            width: self.width,
            height: self.height,
            rgb,
        }
    }
}

/// Options passed identically to both implementations.
#[derive(Clone, Copy, Default)]
struct Options {
    ppd: Option<f32>,
    exposures: Option<(f32, f32)>,
}

/// What metric_reference.py reports.
struct Reference {
    map: Vec<f32>,
    mean: f64,
    start_exposure: Option<f64>,
    stop_exposure: Option<f64>,
    exposures: Option<usize>,
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The venv Python, checked once to exist and to have flip-evaluator 1.7, scikit-image 0.26.0,
/// OpenEXR and numpy.
fn python() -> &'static Path {
    static PYTHON: OnceLock<PathBuf> = OnceLock::new();
    PYTHON.get_or_init(|| {
        let python = std::env::var_os("VERITY_PYTHON")
            .map(PathBuf::from)
            .unwrap_or_else(|| workspace_root().join(".venv/bin/python"));
        let setup = "run ./scripts/setup.sh (it installs compare/python/requirements.txt into .venv)";
        assert!(python.exists(), "no Python at {}: {setup}", python.display());
        let probe = "import importlib.metadata as m, numpy, OpenEXR, flip_evaluator, skimage; \
                     print(m.version('flip-evaluator'), m.version('scikit-image'))";
        let out = Command::new(&python).args(["-c", probe]).output().unwrap_or_else(|e| {
            panic!("cannot run {}: {e}; {setup}", python.display());
        });
        let version = String::from_utf8_lossy(&out.stdout).trim().to_string();
        assert!(
            out.status.success() && version == format!("{FLIP_EVALUATOR_VERSION} {SCIKIT_IMAGE_VERSION}"),
            "{} lacks flip-evaluator=={FLIP_EVALUATOR_VERSION}, scikit-image=={SCIKIT_IMAGE_VERSION}, OpenEXR or \
             numpy (found `{version}`; {}): {setup}",
            python.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        );
        python
    })
}

fn read_exr(path: &Path) -> Image {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| (size.width(), vec![[0.0_f32; 3]; size.width() * size.height()]),
        |(width, pixels): &mut (usize, Vec<[f32; 3]>), at, (r, g, b, _a): (f32, f32, f32, f32)| {
            pixels[at.y() * *width + at.x()] = [r, g, b];
        },
    )
    .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let (width, rgb) = image.layer_data.channel_data.pixels;
    Image {
        width,
        height: rgb.len() / width.max(1),
        rgb,
    }
}

fn write_exr(path: &Path, img: &Image) {
    exr::prelude::write_rgb_file(path, img.width, img.height, |x, y| {
        let [r, g, b] = img.rgb[y * img.width + x];
        (r, g, b)
    })
    .unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
}

/// The number after `"key":` in a flat JSON object, or None for `null`.
fn json_number(json: &str, key: &str) -> Option<f64> {
    let pattern = format!("\"{key}\":");
    let start = json
        .find(&pattern)
        .unwrap_or_else(|| panic!("no {key} in {json}"))
        + pattern.len();
    let value = json[start..].split([',', '}']).next().unwrap().trim();
    (value != "null").then(|| value.parse().unwrap_or_else(|e| panic!("{key} = {value}: {e}")))
}

fn run_reference(dir: &Path, mode: &str, options: Options) -> Reference {
    let out = dir.join(format!("reference-{mode}.exr"));
    let mut cmd = Command::new(python());
    cmd.arg(workspace_root().join("compare/python/metric_reference.py"))
        .arg(dir.join("reference.exr"))
        .arg(dir.join("test.exr"))
        .args(["--mode", mode, "--out"])
        .arg(&out);
    if let (Some(ppd), "ldr" | "hdr") = (options.ppd, mode) {
        cmd.args(["--ppd", &ppd.to_string()]);
    }
    if let (Some((start, stop)), "hdr") = (options.exposures, mode) {
        cmd.args([
            "--start-exposure",
            &start.to_string(),
            "--stop-exposure",
            &stop.to_string(),
        ]);
    }
    let result = cmd.output().expect("run metric_reference.py");
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(
        result.status.success(),
        "metric_reference.py failed ({}): {}{}; run ./scripts/setup.sh if a package is missing",
        result.status,
        stdout,
        String::from_utf8_lossy(&result.stderr)
    );
    let json = stdout.lines().last().unwrap_or_default();
    let map = read_exr(&out).rgb.iter().map(|c| c[0]).collect();
    Reference {
        map,
        mean: json_number(json, "mean").expect("mean"),
        start_exposure: json_number(json, "start_exposure"),
        stop_exposure: json_number(json, "stop_exposure"),
        exposures: json_number(json, "exposures").map(|n| n as usize),
    }
}

/// Asserts both tolerances for one mode and prints the numbers.
fn assert_maps_agree(what: &str, ours: &[f32], reference: &Reference, width: usize) {
    assert_eq!(ours.len(), reference.map.len(), "{what}: map sizes");
    let mean = flip::mean(ours) as f64;
    let (worst, at) = ours
        .iter()
        .zip(&reference.map)
        .map(|(a, b)| (a - b).abs())
        .enumerate()
        .fold(
            (0.0_f32, 0),
            |best, (i, d)| if d > best.0 { (d, i) } else { best },
        );
    println!(
        "{what}: mean {mean:.6} vs reference {:.6} (|Δ| {:.2e}); max |Δpixel| {worst:.2e} at ({}, {})",
        reference.mean,
        (mean - reference.mean).abs(),
        at % width,
        at / width
    );
    assert!(
        (mean - reference.mean).abs() <= MEAN_TOLERANCE,
        "{what}: mean FLIP {mean:.6} differs from the reference's {:.6} by more than {MEAN_TOLERANCE}",
        reference.mean
    );
    assert!(
        worst <= PIXEL_TOLERANCE,
        "{what}: pixel ({}, {}) is {} here and {} in the reference (|Δ| {worst:.2e} > {PIXEL_TOLERANCE})",
        at % width,
        at / width,
        ours[at],
        reference.map[at]
    );
}

/// Runs LDR-FLIP, HDR-FLIP and SSIM on one pair in Verity and the reference implementations
/// and checks agreement.
fn check_pair(name: &str, reference: &Image, test: &Image, options: Options) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("metric-reference")
        .join(name);
    std::fs::create_dir_all(&dir).expect("create the pair's directory");
    write_exr(&dir.join("reference.exr"), reference);
    write_exr(&dir.join("test.exr"), test);
    let ppd = options.ppd.unwrap_or_else(flip::default_pixels_per_degree);

    let ldr = flip::ldr_flip(reference.input(), test.input(), ppd);
    assert_maps_agree(
        &format!("{name} LDR"),
        &ldr,
        &run_reference(&dir, "ldr", options),
        reference.width,
    );

    let hdr = flip::hdr_flip(reference.input(), test.input(), ppd, options.exposures);
    let expected = run_reference(&dir, "hdr", options);
    let exposures = (expected.start_exposure.unwrap(), expected.stop_exposure.unwrap());
    assert!(
        (f64::from(hdr.start_exposure) - exposures.0).abs() < 1e-4
            && (f64::from(hdr.stop_exposure) - exposures.1).abs() < 1e-4
            && Some(hdr.exposures) == expected.exposures,
        "{name} HDR: exposures {} to {} in {} steps here, {} to {} in {:?} in the reference",
        hdr.start_exposure,
        hdr.stop_exposure,
        hdr.exposures,
        exposures.0,
        exposures.1,
        expected.exposures
    );
    assert_maps_agree(&format!("{name} HDR"), &hdr.map, &expected, reference.width);

    check_ssim(name, reference, test, &run_reference(&dir, "ssim", options));
}

/// Verity's SSIM map against scikit-image's over the pixels at least the window radius (5)
/// from the border, and the mean over them against skimage's own mean.
fn check_ssim(name: &str, reference: &Image, test: &Image, expected: &Reference) {
    let rgb = |img: &Image| {
        let pixels = img.rgb.iter().map(|&c| glam::Vec3::from_array(c)).collect();
        compare::metrics::RgbImage::new(img.width, img.height, pixels)
    };
    let ours = ssim::ssim_map(&rgb(reference), &rgb(test));
    let (w, h) = (reference.width, reference.height);
    const BORDER: usize = 5;
    let inner: Vec<usize> = (BORDER..h - BORDER)
        .flat_map(|y| (BORDER..w - BORDER).map(move |x| y * w + x))
        .collect();
    let mean = inner.iter().map(|&i| f64::from(ours[i])).sum::<f64>() / inner.len() as f64;
    let (worst, at) = inner
        .iter()
        .map(|&i| (f64::from((ours[i] - expected.map[i]).abs()), i))
        .fold((0.0, 0), |best, d| if d.0 > best.0 { d } else { best });
    println!(
        "{name} SSIM: mean {mean:.7} vs scikit-image {:.7} (|Δ| {:.2e}); max |Δpixel| {worst:.2e} at ({}, {})",
        expected.mean,
        (mean - expected.mean).abs(),
        at % w,
        at / w
    );
    assert!(
        (mean - expected.mean).abs() <= SSIM_TOLERANCE && worst <= SSIM_TOLERANCE,
        "{name}: SSIM mean {mean:.7} vs scikit-image's {:.7}, pixel ({}, {}) {} vs {} (tolerance {SSIM_TOLERANCE})",
        expected.mean,
        at % w,
        at / w,
        ours[at],
        expected.map[at]
    );
}

// ----------------------------------------------------------------------------------------
// The image pairs.
// ----------------------------------------------------------------------------------------

fn environment_map() -> Image {
    read_exr(&workspace_root().join("scenes/assets/potsdamer_platz_512.exr"))
}

/// A deterministic uniform number in [0, 1) for (seed, index): SplitMix64's finaliser.
fn uniform(seed: u64, index: u64) -> f32 {
    let mut z = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ index.wrapping_add(0x632B_E59B_D9B4_E019);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
}

/// A standard normal number for (seed, index) (Box–Muller).
fn normal(seed: u64, index: u64) -> f32 {
    let u1 = uniform(seed, 2 * index).max(1e-7);
    let u2 = uniform(seed, 2 * index + 1);
    (-2.0 * u1.ln()).sqrt() * (std::f32::consts::TAU * u2).cos()
}

/// Binomial [1 4 6 4 1]/16 blur in x and y, clamp-to-edge.
fn blurred(img: &Image) -> Image {
    const TAPS: [f32; 5] = [1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0];
    let pass = |src: &Image, dx: isize, dy: isize| {
        src.map(|x, y, _| {
            let mut sum = [0.0_f32; 3];
            for (k, w) in TAPS.iter().enumerate() {
                let o = k as isize - 2;
                let sx = (x as isize + o * dx).clamp(0, src.width as isize - 1) as usize;
                let sy = (y as isize + o * dy).clamp(0, src.height as isize - 1) as usize;
                let c = src.rgb[sy * src.width + sx];
                (0..3).for_each(|i| sum[i] += w * c[i]);
            }
            sum
        })
    };
    pass(&pass(img, 1, 0), 0, 1)
}

/// Monte Carlo-like noise: a relative Gaussian error of 50 % per channel and rare fireflies.
fn monte_carlo_noise(img: &Image, seed: u64) -> Image {
    img.map(|x, y, c| {
        let i = (y * img.width + x) as u64;
        let firefly = if uniform(seed ^ 0xF1F1, i) < 0.003 {
            30.0 * uniform(seed ^ 0xABCD, i)
        } else {
            0.0
        };
        [0, 1, 2].map(|k| (c[k] * (1.0 + 0.5 * normal(seed, 3 * i + k as u64))).max(0.0) + firefly)
    })
}

/// 8-bit quantisation of the sRGB-encoded values (the curve extended above 1).
fn quantised_8_bit(img: &Image) -> Image {
    let encode = |v: f32| {
        if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        }
    };
    let decode = |e: f32| {
        if e <= 0.040_45 {
            e / 12.92
        } else {
            ((e + 0.055) / 1.055).powf(2.4)
        }
    };
    img.map(|_, _, c| c.map(|v| decode((encode(v.max(0.0)) * 255.0).round() / 255.0)))
}

/// The image moved one pixel to the right (wrapping around, as a latitude-longitude map does).
fn shifted_one_pixel(img: &Image) -> Image {
    img.map(|x, y, _| img.rgb[y * img.width + (x + img.width - 1) % img.width])
}

/// A 256×128 LDR chart: colour gradients under a 16-pixel checkerboard and a thin grid.
fn synthetic_chart() -> Image {
    let (width, height) = (256, 128);
    let rgb = (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let (u, v) = (x as f32 / (width - 1) as f32, y as f32 / (height - 1) as f32);
            let check = if (x / 16 + y / 16) % 2 == 0 { 0.8 } else { 0.3 };
            let line = if x % 32 == 0 || y % 32 == 0 { 0.0 } else { 1.0 };
            [u * check * line, (0.2 + 0.6 * v) * line, (1.0 - u) * check]
        })
        .collect();
    Image { width, height, rgb }
}

/// The chart with Gaussian noise of σ = 0.05, clamped to [0, 1].
fn noisy_chart(chart: &Image) -> Image {
    chart.map(|x, y, c| {
        let i = (y * chart.width + x) as u64;
        [0, 1, 2].map(|k| (c[k] + 0.05 * normal(7, 3 * i + k as u64)).clamp(0.0, 1.0))
    })
}

#[test]
fn environment_map_against_a_blurred_copy() {
    let env = environment_map();
    check_pair("env-blurred", &env, &blurred(&env), Options::default());
}

#[test]
fn environment_map_against_monte_carlo_noise() {
    let env = environment_map();
    check_pair("env-noisy", &env, &monte_carlo_noise(&env, 1), Options::default());
}

#[test]
fn environment_map_against_a_brighter_exposure() {
    let env = environment_map();
    check_pair(
        "env-exposure-1.2",
        &env,
        &env.map(|_, _, c| c.map(|v| 1.2 * v)),
        Options::default(),
    );
}

#[test]
fn environment_map_against_8_bit_quantisation() {
    let env = environment_map();
    check_pair("env-quantised", &env, &quantised_8_bit(&env), Options::default());
}

#[test]
fn environment_map_against_a_one_pixel_shift() {
    let env = environment_map();
    check_pair("env-shifted", &env, &shifted_one_pixel(&env), Options::default());
}

#[test]
fn environment_map_with_given_viewing_distance_and_exposures() {
    let env = environment_map();
    let options = Options {
        ppd: Some(40.0),
        exposures: Some((-3.0, 2.5)),
    };
    check_pair("env-noisy-40ppd", &env, &monte_carlo_noise(&env, 2), options);
}

#[test]
fn synthetic_chart_against_a_noisy_copy() {
    let chart = synthetic_chart();
    check_pair("chart-noisy", &chart, &noisy_chart(&chart), Options::default());
}

#[test]
fn synthetic_chart_against_a_shifted_blurred_copy() {
    let chart = synthetic_chart();
    check_pair(
        "chart-shifted-blurred",
        &chart,
        &blurred(&shifted_one_pixel(&chart)),
        Options::default(),
    );
}
