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
    // relMSE of b: half the pixels off by 0.05 at ~0.53: (0.0025/0.29)/2 ≈ 4.3e-3.
    assert_eq!(diff(&[a, b, "--fail", "1e-2"]).0, 0);
    assert_eq!(diff(&[a, b, "--fail", "1e-3"]).0, 2);
    assert_eq!(diff(&[a, b, "--warn", "1e-3"]).0, 1);
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

fn study_error(body: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/test-bad.toml");
    compare::study::load_str(body, &path).unwrap_err().to_string()
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
    ];
    for (text, want) in cases {
        let e = study_error(&text);
        assert!(
            e.contains(want) && e.contains("test-bad.toml"),
            "expected `{want}` in: {e}"
        );
    }
}
