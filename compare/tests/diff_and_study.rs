//! `verity diff` exit statuses and figures, and study files' bad-input errors (file, line,
//! field).

use std::path::{Path, PathBuf};
use std::process::Command;

use scenes::layered::LayeredImage;

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("diff-and-study");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn image(path: &Path, w: u32, h: u32, f: impl Fn(usize) -> f32) -> PathBuf {
    let mut img = LayeredImage::new(w, h);
    for c in ["R", "G", "B"] {
        img.push_channel(c, (0..(w * h) as usize).map(&f).collect());
    }
    img.write_exr(path).unwrap();
    path.to_path_buf()
}

fn diff(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_verity"))
        .arg("diff")
        .args(args)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    (out.status.code().unwrap_or(-1), text)
}

#[test]
fn diff_exit_statuses_follow_idiff() {
    let a = image(&tmp("a.exr"), 16, 16, |i| 0.5 + 0.01 * (i % 7) as f32);
    let b = image(&tmp("b.exr"), 16, 16, |i| {
        0.5 + 0.01 * (i % 7) as f32 + if i % 2 == 0 { 0.05 } else { 0.0 }
    });
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    let (code, text) = diff(&[a, a]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("relmse") && text.contains("PASS"), "{text}");
    // b is 4.7 % brighter on average, which the bias test fails whatever the metric's bound;
    // the metric's own verdicts are checked with the bias test off.
    let (code, text) = diff(&[a, b, "--fail", "1e-2"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("FAIL: bias over `all`"), "{text}");
    let diff = |args: &[&str]| diff(&[args, &["--fail-bias", "none"]].concat());
    // relMSE of b: half the pixels off by 0.05 at ~0.53: (0.0025/0.29)/2 ≈ 4.3e-3.
    assert_eq!(diff(&[a, b, "--fail", "1e-2"]).0, 0);
    assert_eq!(diff(&[a, b, "--fail", "1e-3"]).0, 2);
    assert_eq!(diff(&[a, b, "--warn", "1e-3", "--fail", "1e-2"]).0, 1);
    // Without --fail, relMSE's default bound 1e-3 fails it (idiff fails by default too).
    let (code, text) = diff(&[a, b, "--warn", "1e-2"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("above the fail bound 1.000e-3 (default)"), "{text}");
    // Per-pixel rule: 50 % of pixels exceed 1e-3; allowing 60 % passes, 40 % fails.
    assert_eq!(diff(&[a, b, "--fail", "1e-3", "--fail-percent", "60"]).0, 0);
    let (code, text) = diff(&[a, b, "--fail", "1e-3", "--fail-percent", "40"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("128 pixels (50.000 %)"), "{text}");
    // PSNR is higher-is-better: failing below 60 dB.
    assert_eq!(diff(&[a, b, "--metric", "psnr", "--fail", "60"]).0, 2);
    let (_, text) = diff(&[
        a,
        b,
        "--metric",
        "ssim",
        "--metric",
        "flip_ldr",
        "--mask",
        "rect:0,0,8,8",
    ]);
    assert!(
        text.contains("ssim") && text.contains("flip_ldr") && text.contains("(64 pixels)"),
        "{text}"
    );
    let small = image(&tmp("small.exr"), 8, 16, |_| 0.5);
    assert_eq!(diff(&[a, small.to_str().unwrap()]).0, 3);
    let (code, text) = diff(&[a, "/nonexistent/b.exr"]);
    assert_eq!(code, 4, "{text}");
    assert!(text.contains("/nonexistent/b.exr"), "{text}");
    let nan = image(&tmp("nan.exr"), 16, 16, |i| if i == 3 { f32::NAN } else { 0.5 });
    let (code, text) = diff(&[a, nan.to_str().unwrap(), "--fail", "1"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("1 NaN/Inf pixels"), "{text}");
    let (code, text) = diff(&[a, b, "--mask", "rect:5,5,1,1"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("--mask rect:5,5,1,1"), "{text}");
}

/// A reference pixel of 1e20 (its square overflows f32) once made relMSE NaN, which passed
/// every `--fail`; a NaN now fails whatever the bound, a non-finite reference names its file
/// and pixel, and a file that cannot be read is named once.
#[test]
fn diff_never_passes_a_non_finite_value_and_names_the_file() {
    let huge = image(&tmp("huge-ref.exr"), 16, 16, |i| if i == 0 { 1e20 } else { 0.5 });
    let flat = image(&tmp("flat.exr"), 16, 16, |_| 0.5);
    let (huge, flat) = (huge.to_str().unwrap(), flat.to_str().unwrap());
    // One pixel of 256 with relMSE (1e20 − 0.5)²/(1e40 + 0.01) = 1: relMSE 1/256. (The
    // reference's sum is that pixel's, so the bias test, off here, fails the flat image.)
    let (code, text) = diff(&[huge, flat, "--fail", "1e-2", "--fail-bias", "none"]);
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("relmse") && text.contains("3.906250e-3") && text.contains("PASS"),
        "{text}"
    );
    let (code, text) = diff(&[huge, flat, "--fail", "1e-3", "--fail-bias", "none"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("FAIL"), "{text}");
    // NaN in the test image: every metric is NaN; the failure says which and why.
    let nan = image(
        &tmp("nan-test.exr"),
        16,
        16,
        |i| if i == 5 { f32::NAN } else { 0.5 },
    );
    let nan = nan.to_str().unwrap();
    for flags in [&["--warn", "1"][..], &["--metric", "psnr", "--fail", "10"], &[]] {
        let (code, text) = diff(&[&[flat, nan][..], flags].concat());
        assert_eq!(code, 2, "{flags:?}: {text}");
        assert!(
            text.contains("FAIL: ")
                && text.contains("is NaN: not finite (1 NaN/Inf pixels in ")
                && text.contains(nan),
            "{flags:?}: {text}"
        );
        assert!(!text.contains("PASS") && !text.contains("WARNING"), "{text}");
    }
    // Identical images: PSNR is +∞ dB, its exact value, and passes.
    let (code, text) = diff(&[flat, flat, "--metric", "psnr", "--fail", "60"]);
    assert_eq!(code, 0, "{text}");
    // A non-finite reference pixel: an error naming the file, the pixel and the channel.
    let bad_ref = image(&tmp("inf-ref.exr"), 16, 16, |i| {
        if i == 3 * 16 + 4 {
            f32::INFINITY
        } else {
            0.5
        }
    });
    let bad_ref = bad_ref.to_str().unwrap();
    let (code, text) = diff(&[bad_ref, flat]);
    assert_eq!(code, 2, "{text}");
    assert_eq!(
        text.trim(),
        format!("error: {bad_ref}: the reference has a non-finite pixel at (4, 3): R inf")
    );
    // A file that cannot be read: its path once.
    let (code, text) = diff(&[flat, "/nonexistent/b.exr"]);
    assert_eq!(code, 4, "{text}");
    assert_eq!(text.matches("/nonexistent/b.exr").count(), 1, "{text}");
    assert_eq!(text.lines().count(), 1, "{text}");
}

/// Bounds that cannot mean anything are refused before any file is read: one `error:` line
/// naming the flag, exit 2.
#[test]
fn diff_refuses_bounds_outside_the_metric_range() {
    let flat = image(&tmp("flat-flags.exr"), 16, 16, |_| 0.5);
    let flat = flat.to_str().unwrap();
    let cases: [(&[&str], &str); 14] = [
        (&["--fail", "nan"], "--fail NaN: the bound must be a finite number"),
        (&["--warn", "nan"], "--warn NaN: the bound must be a finite number"),
        (&["--fail", "inf"], "--fail inf: the bound must be a finite number"),
        (&["--fail=-1"], "--fail -1: relmse takes values in [0, ∞)"),
        (&["--metric", "ssim", "--warn", "1.5"], "--warn 1.5: ssim takes values in [-1, 1]"),
        (&["--metric", "flip_ldr", "--fail", "2"], "--fail 2: flip_ldr takes values in [0, 1]"),
        (&["--fail", "1", "--fail-percent", "nan"], "--fail-percent NaN: a percentage of pixels must be in [0, 100]"),
        (&["--fail", "1", "--fail-percent", "200"], "--fail-percent 200: a percentage of pixels must be in [0, 100]"),
        (&["--fail", "1", "--fail-percent", "-1"], "--fail-percent -1: a percentage of pixels must be in [0, 100]"),
        (
            &["--metric", "ssim", "--fail", "2.5", "--fail-percent", "5"],
            "--fail 2.5: with --fail-percent, the bound is on the per-pixel ssim error map (1 − SSIM), which takes values in [0, 2]",
        ),
        (&["--metric", "psnr", "--fail", "30", "--fail-percent", "5"], "--fail-percent needs a per-pixel metric; psnr has no map"),
        (&["--fail-bias", "-0.1"], "--fail-bias -0.1: expected a fraction ≥ 0 (0.01 allows 1 % either way) or `none`"),
        (&["--fail-bias", "nan"], "--fail-bias nan: expected a fraction ≥ 0 (0.01 allows 1 % either way) or `none`"),
        (&["--fail-bias", "1%"], "--fail-bias 1%: expected a fraction ≥ 0 (0.01 allows 1 % either way) or `none`"),
    ];
    for (flags, want) in cases {
        let (code, text) = diff(&[&[flat, flat][..], flags].concat());
        assert_eq!(code, 2, "{flags:?}: {text}");
        assert_eq!(text.trim(), format!("error: {want}"), "{flags:?}");
    }
    // In range: accepted (PSNR has no range but finiteness; SSIM's bound may be negative,
    // written as a separate word too).
    assert_eq!(diff(&[flat, flat, "--metric", "psnr", "--fail", "-5"]).0, 0);
    assert_eq!(diff(&[flat, flat, "--metric", "ssim", "--fail", "-1"]).0, 0);
    assert_eq!(diff(&[flat, flat, "--fail", "0", "--fail-percent", "0"]).0, 0);
}

/// A 64×64 reference: a smooth colour image whose `variance.*` layers state a relative
/// standard error `rel` per pixel (the variance of the pixel mean, (rel · value)²), with the
/// header `replicates` when given; and a test image of its colour × `scale`, rows reversed
/// when `flip`.
fn reference_and_scaled(
    name: &str,
    rel: f32,
    replicates: Option<&str>,
    scale: f32,
    flip: bool,
) -> (String, String) {
    let (w, h) = (64u32, 64u32);
    let n = (w * h) as usize;
    // Brighter towards the top, so that reversed rows are a large error.
    let value =
        |i: usize| 0.1 + 0.8 * (1.0 - (i / w as usize) as f32 / h as f32) + 0.05 * ((i * 37) % 11) as f32;
    let colour = |i: usize| [value(i), 0.8 * value(i), 0.5 * value(i) + 0.05];
    let mut a = LayeredImage::new(w, h);
    let mut b = LayeredImage::new(w, h);
    for (k, c) in ["R", "G", "B"].into_iter().enumerate() {
        a.push_channel(c, (0..n).map(|i| colour(i)[k]).collect());
        a.push_channel(
            format!("variance.{c}"),
            (0..n).map(|i| (rel * colour(i)[k]).powi(2)).collect(),
        );
        let row = |i: usize| {
            if flip {
                (h as usize - 1 - i / w as usize) * w as usize + i % w as usize
            } else {
                i
            }
        };
        b.push_channel(c, (0..n).map(|i| scale * colour(row(i))[k]).collect());
    }
    if let Some(r) = replicates {
        a.set_attribute("replicates", r);
    }
    let (pa, pb) = (
        tmp(&format!("{name}-reference.exr")),
        tmp(&format!("{name}-test.exr")),
    );
    a.write_exr(&pa).unwrap();
    b.write_exr(&pb).unwrap();
    (pa.display().to_string(), pb.display().to_string())
}

fn json_of(args: &[&str]) -> (i32, serde_json::Value) {
    let (code, text) = diff(&[args, &["--json", "-"]].concat());
    (
        code,
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}")),
    )
}

/// Issue 42: ground truth × 1.04 against a reference with 5 % noise per pixel passes relMSE
/// (its default bound relaxed to the reference's noise) but fails the bias test by default,
/// naming the bias; × 1.005 passes a 1 % bound. The interval is the reference's uncertainty:
/// with 100 % noise per pixel a 1.5 % bias is not significant and passes, and the same
/// reference without a noise estimate (`replicates` = 1) says so and fails it.
#[test]
fn diff_fails_a_significant_bias_by_default() {
    let (a, b) = reference_and_scaled("exposure-1.04", 0.05, None, 1.04, false);
    let (code, text) = diff(&[&a, &b]);
    assert_eq!(code, 2, "{text}");
    assert!(
        text.contains("FAIL: bias over `all`: ") && text.contains("is beyond 1 ± 0.01 (default)"),
        "{text}"
    );
    let (_, json) = json_of(&[&a, &b]);
    let criterion = &json["metrics"][0];
    assert_eq!(
        json["bounds"]["fail_source"],
        "default, relaxed to the reference's noise"
    );
    assert!(
        criterion["value"].as_f64() < json["bounds"]["fail"].as_f64(),
        "the metric test alone passes: {json}"
    );
    let bias = &json["bias"];
    assert_eq!(
        (bias["verdict"].as_str(), json["verdict"].as_str()),
        (Some("fail"), Some("fail"))
    );
    for c in ["R", "G", "B", "Y"] {
        let (low, high) = (
            bias["ratio_ci_low"][c].as_f64().unwrap(),
            bias["ratio_ci_high"][c].as_f64().unwrap(),
        );
        assert!(low < 1.04 && 1.04 < high && low > 1.01, "{c}: [{low}, {high}]");
    }
    assert_eq!(json["bias_test"]["tests"], 4);
    assert!(json["noise_estimate"]["reference"] == true && json["noise_estimate"]["test"] == false);

    let (a, b) = reference_and_scaled("exposure-1.005", 0.05, Some("8"), 1.005, false);
    for flags in [&["--fail-bias", "0.01"][..], &[]] {
        let (code, text) = diff(&[&[a.as_str(), &b][..], flags].concat());
        assert_eq!(code, 0, "{flags:?}: {text}");
        assert!(text.contains("no significant bias beyond 1 ± 0.01"), "{text}");
    }
    // Its interval, about 1.005 ± 0.0026, lies beyond a 0.1 % bound.
    let (code, text) = diff(&[&a, &b, "--fail-bias", "0.001"]);
    assert_eq!(code, 2, "{text}");

    // 100 % noise per pixel over 4096 pixels: SE ≈ 1.6 %, so 1.5 % is not significant.
    let (a, b) = reference_and_scaled("noisy-1.015", 1.0, Some("8"), 1.015, false);
    let (code, json) = json_of(&[&a, &b]);
    assert_eq!(code, 0, "{json}");
    assert!(json["bias"]["ratio_ci_low"]["Y"].as_f64() < Some(1.0), "{json}");
    // Without a noise estimate nothing is relaxed: the same images fail, and say why.
    let (a, b) = reference_and_scaled("no-estimate-1.015", 1.0, Some("1"), 1.015, false);
    let (code, text) = diff(&[&a, &b]);
    assert_eq!(code, 2, "{text}");
    assert!(
        text.contains("(no noise estimate)")
            && text.contains("the reference has no noise estimate (header `replicates` = 1")
            && text.contains("FAIL: bias over `all`"),
        "{text}"
    );
    let (_, json) = json_of(&[&a, &b]);
    assert_eq!(json["noise_estimate"]["reference"], false);
    assert!(json["noise_estimate"]["reference_missing"]
        .as_str()
        .unwrap()
        .contains("`replicates` = 1"));
    assert_eq!(json["bounds"]["fail_source"], "default");
    assert_eq!(json["bias"]["ratio_ci_low"]["Y"], json["bias"]["ratio"]["Y"]);
    // --fail-bias none reports the bias without testing it (relMSE alone: 2.2e-4 passes).
    let (code, json) = json_of(&[&a, &b, "--fail-bias", "none"]);
    assert_eq!(code, 0, "{json}");
    assert_eq!(json["bias_test"]["fail_bias"], serde_json::Value::Null);
}

/// An image whose rows are upside down fails with a hint to use --flip-y, and passes with it.
#[test]
fn diff_hints_at_flip_y_for_reversed_rows() {
    let (a, b) = reference_and_scaled("flipped", 0.05, None, 1.0, true);
    let (code, text) = diff(&[&a, &b]);
    assert_eq!(code, 2, "{text}");
    assert!(
        text.contains("hint: the test image matches far better with its rows reversed")
            && text.contains("pass --flip-y"),
        "{text}"
    );
    let (_, json) = json_of(&[&a, &b]);
    let hint = &json["flip_y_hint"];
    assert!(
        hint["relmse_rows_reversed"].as_f64().unwrap() * 4.0 < hint["relmse"].as_f64().unwrap(),
        "{json}"
    );
    let (code, json) = json_of(&[&a, &b, "--flip-y"]);
    assert_eq!(code, 0, "{json}");
    assert_eq!(json["flip_y_hint"], serde_json::Value::Null);
    // A failure that reversing the rows does not fix gets no hint.
    let (a, b) = reference_and_scaled("exposure-hint", 0.05, None, 1.04, false);
    let (code, json) = json_of(&[&a, &b]);
    assert_eq!(
        (code, &json["flip_y_hint"]),
        (2, &serde_json::Value::Null),
        "{json}"
    );
}

/// Per object: a sphere 4 % too bright over an eighth of the image passes the test over the
/// whole mask (0.5 % overall) and relMSE, and fails with --per-object, which names it; every
/// object carries its ratio, interval and verdict.
#[test]
fn diff_tests_the_bias_of_each_object() {
    let (w, h) = (32u32, 32u32);
    let n = (w * h) as usize;
    let sphere = |i: usize| i % w as usize >= 24 && i / w as usize >= 16;
    let value = |i: usize| 0.4 + 0.02 * (i % 5) as f32;
    let mut a = LayeredImage::new(w, h);
    let mut b = LayeredImage::new(w, h);
    for c in ["R", "G", "B"] {
        a.push_channel(c, (0..n).map(value).collect());
        a.push_channel(
            format!("variance.{c}"),
            (0..n).map(|i| (0.01 * value(i)).powi(2)).collect(),
        );
        b.push_channel(
            c,
            (0..n)
                .map(|i| value(i) * if sphere(i) { 1.04 } else { 1.0 })
                .collect(),
        );
    }
    a.push_channel(
        "object_id.Y",
        (0..n).map(|i| if sphere(i) { 1.0 } else { 2.0 }).collect(),
    );
    a.set_object_names(["sphere", "floor"]);
    let (pa, pb) = (tmp("objects-reference.exr"), tmp("objects-test.exr"));
    a.write_exr(&pa).unwrap();
    b.write_exr(&pb).unwrap();
    let (pa, pb) = (pa.to_str().unwrap(), pb.to_str().unwrap());
    let (code, text) = diff(&[pa, pb]);
    assert_eq!(code, 0, "{text}");
    let (code, text) = diff(&[pa, pb, "--per-object"]);
    assert_eq!(code, 2, "{text}");
    assert!(
        text.contains("FAIL: bias of object `sphere`: ") && text.contains("beyond the bias bound"),
        "{text}"
    );
    let (_, json) = json_of(&[pa, pb, "--per-object"]);
    assert_eq!(
        json["bias_test"]["tests"], 12,
        "4 channels × (the mask + 2 objects)"
    );
    let objects = json["objects"].as_array().unwrap();
    for o in objects {
        let bias = &o["bias"];
        let want = if o["name"] == "sphere" { "fail" } else { "pass" };
        assert_eq!(bias["verdict"], want, "{o}");
        let (low, ratio, high) = (
            bias["ratio_ci_low"]["Y"].as_f64().unwrap(),
            bias["ratio"]["Y"].as_f64().unwrap(),
            bias["ratio_ci_high"]["Y"].as_f64().unwrap(),
        );
        assert!(low < ratio && ratio < high, "{o}");
    }
    assert_eq!(json["bias"]["verdict"], "pass");
}

fn study_error(body: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    match compare::study::load_str(body, &path) {
        Ok(_) => panic!("accepted:\n{body}"),
        Err(e) => e.to_string(),
    }
}

const GOOD: &str = r#"scene = "../cornell-box.toml"
[ground_truth]
integrator = "direct-unshadowed"
spp = 16
[[method]]
name = "area_quadrature"
sweep = { n = [4, 2] }
[[threshold]]
method = "area_quadrature"
metric = "relmse"
max = 1.0
reason = "r"
"#;

#[test]
fn study_files_are_checked_whole_with_located_errors() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    let s = compare::study::load_str(GOOD, &path).unwrap();
    assert_eq!(s.methods[0].variants().len(), 2);
    // The scene format's spelling of the integrator is read too.
    let other =
        compare::study::load_str(&GOOD.replace("direct-unshadowed", "direct_unshadowed"), &path).unwrap();
    assert_eq!(
        other.ground_truth.integrator,
        scenes::IntegratorKind::DirectUnshadowed
    );
    // A label names the entry's variants (and their files) in place of the method.
    let twice = GOOD.replace(
        "[[threshold]]",
        "[[method]]\nname = \"area_quadrature\"\nlabel = \"coarse\"\nparams = { env_n = 2 }\nsweep = { n = [2] }\n[[threshold]]",
    );
    let t = compare::study::load_str(&twice, &path).unwrap();
    let v = &t.methods[1].variants()[0];
    assert_eq!(
        (v.label(), v.id(), v.method.as_str()),
        ("coarse(n=2)".into(), "coarse-n-2".into(), "area_quadrature")
    );
    assert_eq!(s.thresholds[0].max, Some(1.0));
    let with_vis = GOOD
        .replace("spp = 16", "spp = 16\nvisibility_of = \"light\"")
        .replace("max = 1.0", "max = 1.0\non = \"visibility\"");
    let v = compare::study::load_str(&with_vis, &path).unwrap();
    assert_eq!(v.visibility_of.as_deref(), Some("light"));
    assert_eq!(v.thresholds[0].on, compare::study::Target::Visibility);
    let cases = [
        (
            GOOD.replace("spp = 16", "spp = 16\nsamples = 4"),
            "test-bad.toml:5: field `ground_truth.samples`: unknown field",
        ),
        (
            GOOD.replace("name = \"area_quadrature\"\n", "name = \"vsm\"\n"),
            "field `method[0].name`: unknown method `vsm`",
        ),
        (
            GOOD.replace("[4, 2]", "[4, 0]"),
            "field `method[0].sweep.n[1]`: parameter n = `0`",
        ),
        (
            GOOD.replace("method = \"area_quadrature\"\nmetric", "method = \"pcf\"\nmetric"),
            "no [[method]] named `pcf`",
        ),
        (
            GOOD.replace("metric = \"relmse\"", "metric = \"l2\""),
            "unknown metric `l2`",
        ),
        (
            GOOD.replace("max = 1.0", ""),
            "needs `max` (the method holds) or `min`",
        ),
        (
            GOOD.replace("../cornell-box.toml", "missing.toml"),
            "field `scene`: scene file",
        ),
        (
            GOOD.replace("max = 1.0", "max = 1.0\nmask = \"floor\""),
            "no [[mask]] named `floor`",
        ),
        (
            GOOD.replace("[[method]]", "[[mask]]\nname = \"m\"\n[[method]]"),
            "a mask needs one of",
        ),
        (GOOD.replace("spp = 16", "spp = 0"), "field `ground_truth.spp`"),
        (
            GOOD.replace("max = 1.0", "max = 1.0\non = \"visibility\""),
            "measuring `visibility` needs `visibility_of",
        ),
        (
            GOOD.replace("max = 1.0", "max = 1.0\non = \"shadow\""),
            "field `threshold[0].on`",
        ),
        (
            GOOD.replace(
                "[[threshold]]",
                "[[method]]\nname = \"area_quadrature\"\nsweep = { n = [2] }\n[[threshold]]",
            ),
            "two [[method]] entries measure the variant `area_quadrature(n=2)`",
        ),
        (
            GOOD.replace(
                "sweep = { n = [4, 2] }",
                "label = \"a b\"\nsweep = { n = [4, 2] }",
            ),
            "invalid label `a b`",
        ),
        (
            GOOD.replace(
                "sweep = { n = [4, 2] }",
                "pipeline = \"sideways\"\nsweep = { n = [4, 2] }",
            ),
            "field `method[0].pipeline`",
        ),
    ];
    for (text, want) in cases {
        let e = study_error(&text);
        assert!(
            e.contains(want) && e.contains("test-bad.toml"),
            "expected `{want}` in: {e}"
        );
    }
}

/// A `[[method]]`'s `pipeline` overrides `[raster]`'s for its variants alone.
#[test]
fn a_method_entry_may_choose_its_pipeline() {
    use realtime::PipelineKind;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    let text = GOOD.replace(
        "[[threshold]]",
        "[[method]]\nname = \"area_quadrature\"\nlabel = \"deferred\"\npipeline = \"deferred\"\n[[threshold]]",
    );
    let study = compare::study::load_str(&text, &path).unwrap();
    let kinds: Vec<_> = study.variants().iter().map(|v| (v.label(), v.pipeline)).collect();
    assert!(
        kinds
            .iter()
            .any(|(l, p)| l == "deferred" && *p == Some(PipelineKind::Deferred)),
        "{kinds:?}"
    );
    assert!(
        kinds
            .iter()
            .filter(|(l, _)| l != "deferred")
            .all(|(_, p)| p.is_none()),
        "{kinds:?}"
    );
}

/// `[ground_truth] pixel_filter`: `box` by default and never the scene file's; `centre` (or
/// `center`) takes the study's `[raster] ssaa` K; an unknown value, and a sample count the K×K
/// centres cannot share evenly, are errors at their fields.
#[test]
fn ground_truth_pixel_filter_is_read_and_checked() {
    use scenes::PixelFilter;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    let with = |filter: &str, spp: u32, rest: &str| {
        GOOD.replace("spp = 16", &format!("spp = {spp}\npixel_filter = \"{filter}\""))
            .replacen("[[method]]", &format!("{rest}[[method]]"), 1)
    };
    let plain = compare::study::load_str(GOOD, &path).unwrap();
    assert_eq!(plain.ground_truth_filter(), PixelFilter::Box);
    // The scene file's own filter does not change the study's ground truth.
    let scene_centre = GOOD.replacen(
        "[ground_truth]",
        "[scene_set]\n\"render.pixel_filter\" = \"centre\"\n[ground_truth]",
        1,
    );
    let s = compare::study::load_str(&scene_centre, &path).unwrap();
    let (scene, settings) = compare::study::setup::prepare(&s, true, &s.scene_points()[0].overrides).unwrap();
    assert_eq!(scene.render.pixel_filter, PixelFilter::Centre { ssaa: 1 });
    assert_eq!(settings.pixel_filter, PixelFilter::Box);

    let k1 = compare::study::load_str(&with("center", 10, ""), &path).unwrap();
    assert_eq!(k1.ground_truth.pixel_filter, PixelFilter::Centre { ssaa: 1 });
    assert_eq!(k1.ground_truth_filter(), PixelFilter::Centre { ssaa: 1 });
    let k2 = compare::study::load_str(
        &with("centre", 16, "[raster]\nssaa = 2\n[quick]\nspp = 4\n"),
        &path,
    )
    .unwrap();
    assert_eq!(k2.ground_truth_filter(), PixelFilter::Centre { ssaa: 2 });
    let (_, settings) = compare::study::setup::prepare(&k2, true, &[]).unwrap();
    assert_eq!(
        (settings.pixel_filter, settings.spp),
        (PixelFilter::Centre { ssaa: 2 }, 4)
    );
    // The box filter needs no split.
    compare::study::load_str(&with("box", 10, "[raster]\nssaa = 2\n"), &path).unwrap();

    let cases = [
        (
            with("gauss", 16, ""),
            "test-bad.toml:5: field `ground_truth.pixel_filter`: unknown value \"gauss\" (hint: use one of `box`, `centre`, `center`",
        ),
        (
            with("centre", 10, "[raster]\nssaa = 2\n"),
            "test-bad.toml:4: field `ground_truth.spp`: 10 spp is not a multiple of 4, the centre pixel filter's 2x2 \
             sub-pixel centres (each takes the same number of samples); use 8 or 12 spp (hint: [raster] ssaa",
        ),
        (
            with("centre", 16, "[raster]\nssaa = 2\n[quick]\nresolution = [8, 8]\nspp = 6\n"),
            "test-bad.toml:10: field `quick.spp`: 6 spp is not a multiple of 4",
        ),
    ];
    for (text, want) in cases {
        let e = study_error(&text);
        assert!(e.contains(want), "expected `{want}` in: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}

/// A study over the soft-shadow scene with a scene sweep of its light's size.
const SWEPT: &str = r#"scene = "../soft-shadow.toml"
[scene_sweep]
name = "light_size"
set = ["shape.light.size[0]", "shape.light.size[1]"]
values = [0.25, 1.0]
[ground_truth]
integrator = "direct"
spp = 16
visibility_of = "light"
[[method]]
name = "shadow_hard"
sweep = { map = [512, 256] }
[[threshold]]
method = "shadow_hard"
scene = { light_size = 1.0 }
metric = "relmse"
max = 1.0
reason = "r"
"#;

#[test]
fn scene_sweeps_make_one_scene_per_value_and_thresholds_select_them() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    let s = compare::study::load_str(SWEPT, &path).unwrap();
    let points = s.scene_points();
    assert_eq!(points.len(), 2);
    assert_eq!(points[1].label(), "light_size=1");
    assert_eq!(points[1].suffix(), "--light_size-1");
    let variants = s.variants();
    let labels: Vec<String> = variants.iter().map(|v| v.label()).collect();
    assert_eq!(
        labels,
        [
            "shadow_hard(map=512) @ light_size=0.25",
            "shadow_hard(map=256) @ light_size=0.25",
            "shadow_hard(map=512) @ light_size=1",
            "shadow_hard(map=256) @ light_size=1",
        ]
    );
    assert_eq!(variants[3].id(), "shadow_hard-map-256--light_size-1");
    let selected: Vec<String> = variants
        .iter()
        .filter(|v| s.thresholds[0].applies_to(v))
        .map(|v| v.label())
        .collect();
    assert_eq!(selected.len(), 2);
    assert!(selected.iter().all(|l| l.ends_with("@ light_size=1")));
    // Each point's scene is the file with the fields set.
    let (scene, _) = compare::study::run::prepare(&s, true, &points[1].overrides).unwrap();
    let light = scene.shapes.iter().find(|x| x.name == "light").unwrap();
    assert!((light.geometry.bounds().1.x - light.geometry.bounds().0.x - 1.0).abs() < 1e-5);

    let cases = [
        (
            SWEPT.replace("shape.light.size[1]", "shape.lamp.size[1]"),
            "scene_sweep light_size = 0.25: the scene does not load",
        ),
        (
            SWEPT.replace("[0.25, 1.0]", "[0.25, -1.0]"),
            "scene_sweep light_size = -1: the scene does not load",
        ),
        (SWEPT.replace("[0.25, 1.0]", "[0.25]"), "at least two values"),
        (SWEPT.replace("[0.25, 1.0]", "[1.0, 1.0]"), "listed twice"),
        (
            SWEPT.replace("name = \"light_size\"", "name = \"light size\""),
            "invalid scene parameter name",
        ),
        (
            SWEPT.replace("{ light_size = 1.0 }", "{ light_size = 3.0 }"),
            "no scene-sweep point has these values",
        ),
        (
            SWEPT.replace("[ground_truth]", "[stability.flicker]\nframes = 3\nshift = \"shape.light.centre[0]\"\nstep = 0.01\n[ground_truth]"),
            "flicker frame 1: the scene does not load",
        ),
        (
            SWEPT.replace("[ground_truth]", "[stability.flicker]\nframes = 3\n[ground_truth]"),
            "a flicker needs a motion",
        ),
    ];
    for (text, want) in cases {
        let e = study_error(&text);
        assert!(
            e.contains(want) && e.contains("test-bad.toml"),
            "expected `{want}` in: {e}"
        );
    }
    // A light motion: frame k adds k·step to the field.
    let moving = SWEPT.replace(
        "[ground_truth]",
        "[stability.flicker]\nframes = 3\nshift = \"shape.light.center[0]\"\nstep = 0.01\n[ground_truth]",
    );
    let s = compare::study::load_str(&moving, &path).unwrap();
    let f = s.stability.flicker.as_ref().unwrap();
    let edits = compare::study::shifted(&f.motion, 2);
    assert_eq!(edits.len(), 1);
    assert_eq!(edits[0].edit, scenes::toml::overrides::Edit::Add(0.02));
    assert!(f
        .motion
        .describe()
        .contains("shape.light.center[0] moving by 0.01 per frame"));
}

/// `[scene_set]` edits the scene before every scene-sweep value; `within` narrows an
/// `objects` mask to a rectangle.
#[test]
fn scene_set_and_masks_within_a_rectangle() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    let set = SWEPT.replace(
        "[scene_sweep]",
        "[scene_set]\n\"shape.light.center[1]\" = 1.25\n\"camera.fov\" = 30\n[[mask]]\nname = \"right\"\nobjects = [\"floor\"]\nwithin = [0.5, 0.0, 1.0, 1.0]\n[scene_sweep]",
    );
    let s = compare::study::load_str(&set, &path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.scene_set.len(), 2);
    for point in s.scene_points() {
        let (scene, _) = compare::study::run::prepare(&s, true, &point.overrides).unwrap();
        assert_eq!(scene.camera.fov_y_deg, 30.0, "{}", point.label());
        let light = scene.shapes.iter().find(|x| x.name == "light").unwrap();
        let (lo, hi) = light.geometry.bounds();
        assert!(((lo.y + hi.y) * 0.5 - 1.25).abs() < 1e-5, "{}", point.label());
    }
    let cases = [
        (
            set.replace("\"camera.fov\" = 30", "\"camera.fov\" = 300"),
            "scene_set: the scene does not load",
        ),
        (
            set.replace("objects = [\"floor\"]\n", ""),
            "`within` narrows an `objects` mask",
        ),
        (
            set.replace("within = [0.5, 0.0, 1.0, 1.0]", "within = [0.5, 0.0, 0.4, 1.0]"),
            "0 ≤ x0 < x1 ≤ 1",
        ),
    ];
    for (text, want) in cases {
        let e = study_error(&text);
        assert!(e.contains(want), "expected `{want}` in: {e}");
    }
}

/// A study's name becomes a folder under the output directory: it must not leave it.
#[test]
fn study_names_are_file_name_safe() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    let long = "a".repeat(101);
    for bad in [
        "../../esc",
        "/tmp/abs",
        "",
        ".",
        "..",
        ".hidden",
        "a/b",
        "a..b",
        "tab\there",
        long.as_str(),
    ] {
        let body = format!("name = \"{}\"\n{GOOD}", bad.replace('\t', "\\t"));
        let e = study_error(&body);
        assert!(
            e.starts_with(&format!(
                "{}:1: field `name`: invalid study name `{bad}`: ",
                path.display()
            )),
            "{bad:?}: {e}"
        );
    }
    let ok = compare::study::load_str(&format!("name = \"shadow-v1.2_b\"\n{GOOD}"), &path).unwrap();
    assert_eq!(ok.name, "shadow-v1.2_b");
    // Without `name`, the file stem made safe: `my study.v2.toml` → `my_study_v2`.
    let stem = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/my study.v2.toml");
    assert_eq!(compare::study::load_str(GOOD, &stem).unwrap().name, "my_study_v2");
}

/// Everything a study names is checked when it is read, before any render: the scene at each
/// scene point, its lights and shapes, masks and metrics named once, bounds that can hold.
#[test]
fn study_references_are_checked_before_rendering() {
    let with_mask = |mask: &str| GOOD.replace("[[method]]", &format!("[[mask]]\n{mask}\n[[method]]"));
    let cases = [
        (
            GOOD.replace("spp = 16", "spp = 16\nvisibility_of = \"nolight\""),
            "test-bad.toml:5: field `ground_truth.visibility_of`: the scene has no light `nolight`; its lights: light",
        ),
        (
            SWEPT.replace("visibility_of = \"light\"", "visibility_of = \"lamp\""),
            "field `ground_truth.visibility_of`: the scene has no light `lamp` at scene_sweep light_size = 0.25; its lights: light",
        ),
        (
            with_mask("name = \"m\"\nobjects = [\"floor\", \"tall_blok\"]"),
            "test-bad.toml:7: field `mask[0].objects[1]`: mask `m`: the scene has no shape `tall_blok`; shapes: floor, ceiling, back,",
        ),
        (
            with_mask("name = \"m\"\nobjects = []"),
            "field `mask[0].objects`: an objects mask needs at least one shape name",
        ),
        (
            with_mask("name = \"m\"\ninterior = true\n[[mask]]\nname = \"m\"\nrectangle = [0, 0, 1, 1]"),
            "test-bad.toml:9: field `mask[1].name`: a mask named `m` is already declared, mask[0] (line 5)",
        ),
        (
            format!("metrics = [\"relmse\", \"mse\", \"relmse\"]\n{GOOD}"),
            "test-bad.toml:1: field `metrics[2]`: `relmse` is listed twice",
        ),
        (
            GOOD.replace("max = 1.0", "max = -1"),
            "test-bad.toml:11: field `threshold[0].max`: max -1 can never hold: relmse takes values in [0, ∞)",
        ),
        (
            GOOD.replace("metric = \"relmse\"\nmax = 1.0", "metric = \"ssim\"\nmin = 2"),
            "field `threshold[0].min`: min 2 can never hold: ssim takes values in [-1, 1]",
        ),
        (
            GOOD.replace("metric = \"relmse\"\nmax = 1.0", "metric = \"flip_ldr\"\nmin = 1.5"),
            "min 1.5 can never hold: flip_ldr takes values in [0, 1]",
        ),
        (GOOD.replace("max = 1.0", "max = nan"), "field `threshold[0].max`: expected a finite number"),
        (GOOD.replace("max = 1.0", "max = inf"), "field `threshold[0].max`: expected a finite number"),
        (GOOD.replace("max = 1.0", "max = 1.0\nmin = 2.0"), "field `threshold[0].min`: min 2 is above max 1"),
        (
            GOOD.replace("[[method]]", "[stability]\nmask = \"floor\"\n[[method]]"),
            "test-bad.toml:6: field `stability.mask`: no [[mask]] named `floor`",
        ),
        (
            format!("metrics = [\"mse\"]\n{}", GOOD.replace("relmse", "mse")),
            "test-bad.toml:1: field `stability.metric`: `relmse` is not in the study's `metrics`",
        ),
    ];
    for (text, want) in cases {
        let e = study_error(&text);
        assert!(e.contains(want), "expected `{want}` in: {e}");
    }
    // An `objects` entry may be a pattern (scenes::glob), as the masks are built: checked the
    // same way when the study is read, so one that matches no shape is the error, not one
    // with a wildcard.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    compare::study::load_str(
        &with_mask("name = \"blocks\"\nobjects = [\"*_block\", \"fl??r\"]"),
        &path,
    )
    .unwrap_or_else(|e| panic!("a mask of patterns: {e}"));
    let e = study_error(&with_mask("name = \"m\"\nobjects = [\"*_blok\"]"));
    assert!(
        e.contains("field `mask[0].objects[0]`: mask `m`: the scene has no shape `*_blok`"),
        "{e}"
    );
    // A scene that does not load is an error at `scene` when the study is read (it used to be
    // found by the first render).
    let broken = tmp("broken-scene.toml");
    std::fs::write(&broken, "[camera]\neye = [0, 0]\n").unwrap();
    let e = study_error(&GOOD.replace("../cornell-box.toml", broken.to_str().unwrap()));
    assert!(
        e.contains("test-bad.toml:1: field `scene`: the scene does not load: ")
            && e.contains("broken-scene.toml"),
        "{e}"
    );
}

/// A study with a shadow method swept over `bias` × `slope_bias` × `normal_offset`.
fn shadow_grid(bias: usize, slope: usize, offset: usize) -> String {
    let values = |n: usize, top: f64| {
        (0..n)
            .map(|i| format!("{}", top * (i + 1) as f64 / n as f64))
            .collect::<Vec<_>>()
            .join(", ")
    };
    SWEPT
        .replace(
            "sweep = { map = [512, 256] }",
            &format!(
                "sweep = {{ bias = [{}], slope_bias = [{}], normal_offset = [{}] }}",
                values(bias, 5.0),
                values(slope, 50.0),
                values(offset, 50.0)
            ),
        )
        .replace("scene = { light_size = 1.0 }\n", "")
}

/// Each swept value is accepted alone, but one combination is not (`max_steps` is POM's, not
/// normal mapping's): an error naming the sweep, not a panic when the variants are built.
#[test]
fn study_grids_refuse_a_combination_the_method_refuses() {
    let body = GOOD
        .replace("name = \"area_quadrature\"\nsweep = { n = [4, 2] }", "name = \"envmap_cube\"\nparams = { detail = \"pom\" }\nsweep = { detail = [\"pom\", \"normal_mapping\"], max_steps = [64] }")
        .replace("method = \"area_quadrature\"", "method = \"envmap_cube\"");
    let e = study_error(&body);
    assert!(
        e.contains(
            "test-bad.toml:8: field `method[0].sweep`: method envmap_cube has no parameter `max_steps`"
        ),
        "{e}"
    );
}

/// A grid is counted from its sweep lengths before any variant exists: 64 × 1000 × 64 is one
/// error line, not 4 million variants (6.2 GB, then an abort).
#[test]
fn study_grids_are_counted_before_they_are_built() {
    let e = study_error(&shadow_grid(1000, 64, 64));
    assert!(
        e.contains("test-bad.toml:12: field `method[0].sweep`: the study has 8192000 renders (scene points 2 × method grid points 4096000 (1000 × 64 × 64)), more than the 10000 a study may have"),
        "{e}"
    );
    // The scene sweep multiplies: 2 × 8000 is over, 2 × 4000 not.
    assert!(study_error(&shadow_grid(1000, 8, 1)).contains("the study has 16000 renders"));
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    assert!(compare::study::load_str(&shadow_grid(1000, 4, 1), &path).is_ok());
}

fn report(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_verity"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).to_string(),
        String::from_utf8_lossy(&out.stderr).to_string(),
    )
}

/// `verity report --dry-run` checks the study and prints its plan without rendering (no GPU
/// needed), and a run over the memory budget is one error naming the field and the bytes.
#[test]
fn dry_runs_print_the_plan_and_check_the_memory_budget() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let absolute = |s: &str| s.replace("\"../", &format!("\"{}/", scenes.display()));
    let quick = "[quick]\nresolution = [16, 16]\nspp = 2\n[[method]]";
    let good = tmp("dry-good.toml");
    std::fs::write(&good, absolute(&GOOD.replacen("[[method]]", quick, 1))).unwrap();
    let out_dir = tmp("dry-out");
    let _ = std::fs::remove_dir_all(&out_dir);
    let (code, stdout, stderr) = report(&[
        "report",
        good.to_str().unwrap(),
        "--quick",
        "--dry-run",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    for want in [
        "study `dry-good` (",
        "quick run: 16x16, ground truth 2 spp direct-unshadowed, ssaa 1",
        "scene points: 1",
        "variants: 2 (2 per scene point)",
        "renders: 2 raster (0 for flicker), 1 ground truths (0 for flicker)",
        "estimated memory: ",
        "dry run: the study is valid; nothing rendered",
    ] {
        assert!(stdout.contains(want), "expected `{want}` in: {stdout}");
    }
    assert!(!out_dir.exists(), "a dry run writes nothing");
    // A bad reference is the same one-line error as a real run's (exit 2).
    let bad = tmp("dry-bad.toml");
    std::fs::write(
        &bad,
        absolute(&GOOD.replace("spp = 16", "spp = 16\nvisibility_of = \"nolight\"")),
    )
    .unwrap();
    let (code, _, stderr) = report(&["report", bad.to_str().unwrap(), "--dry-run"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.starts_with("error: ")
            && stderr.contains("dry-bad.toml:5: field `ground_truth.visibility_of`"),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    // Over the budget: the scene sweep's 20 points need more than 1 MiB.
    let values: Vec<String> = (1..=20).map(|i| format!("{}", 0.05 * i as f64)).collect();
    let sweep = tmp("dry-sweep.toml");
    std::fs::write(
        &sweep,
        absolute(
            &SWEPT
                .replace("[0.25, 1.0]", &format!("[{}]", values.join(", ")))
                .replace("sweep = { map = [512, 256] }", "params = { map = 256 }")
                .replacen("[[method]]", quick, 1),
        ),
    )
    .unwrap();
    let (code, _, stderr) = report(&[
        "--memory-limit",
        "1M",
        "report",
        sweep.to_str().unwrap(),
        "--quick",
        "--dry-run",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("dry-sweep.toml:5: field `scene_sweep.values`: the quick run's 20 renders at 16x16 (scene points 20 × variants 1): ")
            && stderr.contains("over the memory limit of 1.0 MiB (--memory-limit)")
            && stderr.contains("raise the limit with --memory-limit SIZE or VERITY_MEMORY_LIMIT"),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    let (code, stdout, stderr) = report(&["report", sweep.to_str().unwrap(), "--quick", "--dry-run"]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(
        stdout.contains("scene points: 20") && stdout.contains("variants: 20 (1 per scene point)"),
        "{stdout}"
    );
}

/// A `[second_ground_truth]` is read with its own edits, refused where it cannot be compared
/// (another camera, a bound on it without it, edits that break its scene), and measured: the
/// study's scene itself as the second gives exactly the first's metrics, a changed material
/// gives others, and a bound on it is checked like any other.
#[test]
fn a_second_ground_truth_is_read_checked_and_measured() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    let with = |table: &str| GOOD.replace("[[method]]", &format!("{table}\n[[method]]"));
    let brighter = "[second_ground_truth]\nname = \"brighter walls\"\nscene_set = { \"material.white.albedo\" = [0.9, 0.9, 0.9] }";
    let s = compare::study::load_str(&with(brighter), &path).unwrap();
    let second = s.second_ground_truth.as_ref().unwrap();
    assert_eq!(second.name, "brighter walls");
    assert!(second.follows_scene_sweep);
    let point = &s.scene_points()[0];
    assert_eq!(second.overrides(&s, point).len(), 1);
    // Along a sweep it follows the values unless told not to; then one image serves all.
    let swept = SWEPT.replace(
        "[[method]]",
        "[second_ground_truth]\nname = \"n\"\nscene_set = { \"shape.floor.center[1]\" = 0.01 }\nscene_sweep = false\n[[method]]",
    );
    let s2 = compare::study::load_str(&swept, &path).unwrap();
    let points = s2.scene_points();
    let g = s2.second_ground_truth.as_ref().unwrap();
    assert_eq!(g.overrides(&s2, &points[1]).len(), 1);
    assert_eq!(g.suffix(&points[1]), "");
    let cases = [
        (
            GOOD.replace("reason = \"r\"", "reason = \"r\"\non = \"second_ground_truth\""),
            "field `threshold[0].on`: measuring against `second_ground_truth` needs a [second_ground_truth] table",
        ),
        (
            with("[second_ground_truth]\nname = \"moved\"\nscene_set = { \"camera.fov\" = 30.0 }"),
            "field `second_ground_truth.scene_set`: the second ground truth: ",
        ),
        (
            with("[second_ground_truth]\nname = \"x\"\nscene_set = { \"material.white.albedo\" = -1 }"),
            "field `second_ground_truth.scene_set`: scene_set: the scene does not load",
        ),
        (
            with("[second_ground_truth]\nname = \"x\"\nscene = \"nowhere.toml\""),
            "field `second_ground_truth.scene`: scene file",
        ),
        (
            with("[second_ground_truth]\nname = \"x\"\nspp = 4"),
            "second_ground_truth",
        ),
    ];
    for (text, want) in &cases {
        let e = study_error(text);
        assert!(
            e.contains(want) && e.contains("test-bad.toml"),
            "expected `{want}` in: {e}"
        );
    }
    assert!(study_error(&cases[1].0).contains("its camera differs"));

    // Measured: 16×16, 4 spp. The same scene as the second: the very same image (one cache
    // entry), so the same metrics; brighter walls: other metrics, and a bound on them checked.
    let run = |name: &str, table: &str, bound: &str| {
        let dir = tmp(name);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box.toml");
        let study = dir.join(format!("{name}.toml"));
        let text = with(table)
            .replace("../cornell-box.toml", scene.to_str().unwrap())
            .replace(
                "[[method]]",
                "[quick]\nspp = 4\nresolution = [16, 16]\n[[method]]",
            )
            + bound;
        std::fs::write(&study, text).unwrap();
        let out = dir.join("out");
        let (code, stdout, stderr) = report(&[
            "report",
            study.to_str().unwrap(),
            "--quick",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
            "--cache",
            dir.join("cache").to_str().unwrap(),
        ]);
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
        (code, stdout + &stderr, json, out)
    };
    let (code, text, same, out) = run("second-same", "[second_ground_truth]\nname = \"itself\"", "");
    assert_eq!(code, 0, "{text}");
    assert_eq!(
        same["second_ground_truth"]["images"][0]["exr"],
        "second_ground_truth.exr"
    );
    assert!(out.join("second_ground_truth.png").exists());
    assert!(std::fs::read_to_string(out.join("index.html"))
        .unwrap()
        .contains("Against the second ground truth: itself"));
    for v in same["variants"].as_array().unwrap() {
        assert_eq!(v["metrics"], v["second_ground_truth"], "{}", v["label"]);
    }
    let bound = "[[threshold]]\nmethod = \"area_quadrature\"\non = \"second_ground_truth\"\nmetric = \"relmse\"\nmax = 1e-9\nreason = \"brighter walls are not the scene\"\n";
    let (code, text, other, _) = run("second-brighter", brighter, bound);
    assert_ne!(code, 0, "{text}");
    assert!(
        text.contains("relmse of the second_ground_truth over `all`"),
        "{text}"
    );
    for v in other["variants"].as_array().unwrap() {
        assert_ne!(v["metrics"], v["second_ground_truth"], "{}", v["label"]);
    }
    let checks = other["thresholds"].as_array().unwrap();
    assert!(checks
        .iter()
        .any(|c| c["on"] == "second_ground_truth" && c["passed"] == false));
}

/// `metric = "bias"` bounds the luminance ratio Σ image / Σ ground truth over the mask, from
/// both sides, whatever the study's `metrics`: the value checked is the one metrics.json
/// records; against brighter walls than the method renders the ratio is lower; a `max` the
/// image exceeds fails with a message naming the bias.
#[test]
fn a_bias_threshold_bounds_the_mean_ratio() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    let bias_bound = |on: &str, bounds: &str| {
        format!("[[threshold]]\nmethod = \"area_quadrature\"\nparams = {{ n = 4 }}\non = \"{on}\"\nmetric = \"bias\"\n{bounds}\nreason = \"r\"\n")
    };
    let s = compare::study::load_str(
        &(GOOD.to_string() + &bias_bound("image", "min = 0.9\nmax = 1.1")),
        &path,
    )
    .unwrap();
    assert_eq!(s.thresholds[1].metric, compare::study::Measure::Bias);
    for (body, want) in [
        (
            GOOD.to_string() + &bias_bound("image", "max = -1"),
            "max -1 can never hold: bias takes values in [0, ∞)",
        ),
        (
            GOOD.replace("metric = \"relmse\"", "metric = \"biass\""),
            "unknown metric `biass`; metrics: mse, rmse, mae, relmse, smape, psnr, ssim, flip_ldr, flip_hdr, bias",
        ),
    ] {
        let e = study_error(&body);
        assert!(e.contains(want), "expected `{want}` in: {e}");
    }

    // Measured (16×16, 4 spp: a noisy ground truth, so the bounds are wide): the image's
    // ratio is above a half (holds) and not below it (fails); against brighter walls it is
    // lower than against the scene.
    let dir = tmp("bias-threshold");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box.toml");
    let study = dir.join("bias.toml");
    let brighter = "[second_ground_truth]\nname = \"brighter walls\"\nscene_set = { \"material.white.albedo\" = [0.95, 0.95, 0.95] }\n[quick]\nspp = 4\nresolution = [16, 16]\n[[method]]";
    let text = GOOD
        .replace("../cornell-box.toml", scene.to_str().unwrap())
        .replace("[[method]]", brighter)
        + &bias_bound("image", "min = 0.5")
        + &bias_bound("image", "max = 0.5")
        + &bias_bound("second_ground_truth", "max = 10");
    std::fs::write(&study, text).unwrap();
    let out = dir.join("out");
    let (code, stdout, stderr) = report(&[
        "report",
        study.to_str().unwrap(),
        "--quick",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
        "--cache",
        dir.join("cache").to_str().unwrap(),
    ]);
    let text = stdout + &stderr;
    assert_eq!(code, 1, "{text}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
    let variant = json["variants"]
        .as_array()
        .unwrap()
        .iter()
        .find(|v| v["label"] == "area_quadrature(n=4)")
        .unwrap();
    let recorded = |list: &str| variant[list][0]["bias"]["ratio"]["Y"].as_f64().unwrap();
    let checks: Vec<&serde_json::Value> = json["thresholds"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["metric"] == "bias")
        .collect();
    let [above, below, against_brighter] = checks[..] else {
        panic!("three bias checks: {checks:?}")
    };
    assert_eq!(above["value"].as_f64(), Some(recorded("metrics")));
    assert_eq!(
        (&above["passed"], &below["passed"]),
        (&true.into(), &false.into())
    );
    assert_eq!(
        against_brighter["value"].as_f64(),
        Some(recorded("second_ground_truth"))
    );
    assert_eq!(against_brighter["passed"], true);
    assert!(recorded("second_ground_truth") < recorded("metrics"), "{variant}");
    // metrics.csv carries the same ratio in a `bias` row per target and mask, with the
    // standard error in its noise_floor column.
    let csv = std::fs::read_to_string(out.join("metrics.csv")).unwrap();
    let bias_row = csv
        .lines()
        .find(|l| l.starts_with("\"area_quadrature(n=4)\"") && l.contains(",image,all,bias,"))
        .unwrap_or_else(|| panic!("no bias row in metrics.csv:\n{csv}"));
    let fields: Vec<&str> = bias_row.split(',').collect();
    let value: f64 = fields[7].parse().unwrap();
    assert_eq!(value, recorded("metrics"), "{bias_row}");
    let se: f64 = fields[8].parse().unwrap();
    assert_eq!(
        Some(se),
        variant["metrics"][0]["bias"]["standard_error"]["Y"].as_f64()
    );
    // The report's bias table has a cell per variant and mask holding the same ratio.
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    let table = html
        .split("<h2>Bias per mask")
        .nth(1)
        .and_then(|t| t.split("</table>").next())
        .unwrap_or_else(|| panic!("no bias table in index.html"));
    let row = table
        .split("<tr>")
        .find(|r| r.contains("area_quadrature(n=4)"))
        .unwrap_or_else(|| panic!("no row for area_quadrature(n=4): {table}"));
    assert!(
        row.contains(&format!("<td data-v=\"{}\">", recorded("metrics"))),
        "{row}"
    );
    assert!(csv.contains(",second_ground_truth,all,bias,"), "{csv}");
    assert!(
        text.contains("FAIL bias: area_quadrature(n=4) bias over `all` = ")
            && text.contains("expected ≤ 5e-1 (r)"),
        "{text}"
    );
}

/// `verity report --only-bounded` renders the variants a bound of the mode applies to and no
/// others: a scene point none of whose variants is bounded gets no ground truth, no sweep is
/// drawn, flicker is measured only where a flicker bound asks; every bound gets the value,
/// bit for bit, of the complete run, and metrics.json and the report say what was left out.
#[test]
fn only_bounded_renders_what_the_bounds_check_with_the_same_verdicts() {
    let dir = tmp("only-bounded");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let study = dir.join("only-bounded.toml");
    let text = SWEPT
        .replace("\"../soft-shadow.toml\"", &format!("\"{}\"", scenes.join("soft-shadow.toml").display()))
        .replace(
            "[[method]]",
            "[quick]\nspp = 4\nresolution = [16, 16]\n[stability]\nflicker = { frames = 2, orbit_degrees = 0.5, orbit_distance = 1.0 }\n[[method]]",
        )
        .replace("scene = { light_size = 1.0 }", "scene = { light_size = 1.0 }\nparams = { map = 256 }")
        + "[[threshold]]\nmethod = \"shadow_hard\"\nscene = { light_size = 0.25 }\nparams = { map = 512 }\nmode = \"full\"\nmetric = \"relmse\"\nmax = 1.0\nreason = \"full mode only\"\n";
    std::fs::write(&study, text).unwrap();
    let cache = dir.join("cache");
    let run = |name: &str, only: bool| {
        let out = dir.join(name);
        let mut args = vec![
            "report",
            study.to_str().unwrap(),
            "--quick",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
            "--cache",
            cache.to_str().unwrap(),
        ];
        if only {
            args.push("--only-bounded");
        }
        let (code, stdout, stderr) = report(&args);
        assert_eq!(code, 0, "{stdout}{stderr}");
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
        (json, out, stdout)
    };
    let (whole, _, _) = run("whole", false);
    let (only, out, stdout) = run("only", true);
    let labels = |j: &serde_json::Value| -> Vec<String> {
        j["variants"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v["label"].as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(labels(&whole).len(), 4);
    assert_eq!(labels(&only), ["shadow_hard(map=256) @ light_size=1"], "{stdout}");
    assert!(
        stdout.contains("1 variants on") && stdout.contains("1 of 1 bounds hold"),
        "{stdout}"
    );
    assert_eq!(only["thresholds"], whole["thresholds"]);
    assert_eq!(
        (
            only["run"]["only_bounded"].as_bool(),
            only["run"]["variants_declared"].as_u64()
        ),
        (Some(true), Some(4))
    );
    assert_eq!(whole["run"]["only_bounded"].as_bool(), Some(false));
    assert_eq!(whole["flicker"].as_array().unwrap().len(), 2);
    assert!(!whole["sweeps"].as_array().unwrap().is_empty() && whole["scene_sweep"].is_object());
    assert!(only["flicker"].as_array().unwrap().is_empty());
    assert!(only["sweeps"].as_array().unwrap().is_empty() && only["scene_sweep"].is_null());
    // The first scene point's ground truth sizes the run; the second's variant is the one rendered.
    assert!(out.join("ground_truth--light_size-1.exr").exists());
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(
        html.contains("Bounded variants only") && html.contains("1 of the 4 variants"),
        "{html}"
    );
    // A record is of the whole study: the flag refuses --record (and plans, which run every variant).
    for extra in [&["--all", "--record"][..], &["--plan", "p.json"][..]] {
        let mut args = vec!["report", "--only-bounded"];
        if extra[0] == "--plan" {
            args.push(study.to_str().unwrap());
        }
        args.extend_from_slice(extra);
        let (code, _, stderr) = report(&args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(
            stderr.contains("--only-bounded") && stderr.contains("cannot be used with"),
            "{stderr}"
        );
    }
}
