//! `verity diff` on images from other renderers: PNG, JPEG, Radiance HDR and layered EXR
//! inputs, row flips, exposure, default bounds that fail a flipped or black image, the JSON
//! report against its schema, object names in masks and the per-object table.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use scenes::layered::LayeredImage;
use scenes::srgb::linear_to_srgb;

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("diff-inputs");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn verity(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_verity"))
        .args(args)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    (out.status.code().unwrap_or(-1), text)
}

fn diff(args: &[&str]) -> (i32, String) {
    verity(&[&["diff"][..], args].concat())
}

/// An oracle render of the Cornell box (32², 1024 spp, direct lighting): the reference the
/// tests compare against, with its noise estimate (a relMSE noise floor of about 3e-4, below
/// the default bound), object ids and object names.
fn render() -> &'static Path {
    static RENDER: OnceLock<PathBuf> = OnceLock::new();
    RENDER.get_or_init(|| {
        let out = tmp("cornell.exr");
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box.toml");
        let (code, text) = verity(&[
            "render",
            scene.to_str().unwrap(),
            "--resolution",
            "32x32",
            "--spp",
            "1024",
            "--integrator",
            "direct",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{text}");
        out
    })
}

fn read(path: &Path) -> LayeredImage {
    LayeredImage::read_exr(path).unwrap()
}

/// The render's colour, mapped per pixel, as an EXR of R, G, B only.
fn derived_exr(name: &str, f: impl Fn(&LayeredImage, usize, usize) -> f32) -> PathBuf {
    let src = read(render());
    let mut img = LayeredImage::new(src.width, src.height);
    for (c, channel) in ["R", "G", "B"].into_iter().enumerate() {
        img.push_channel(channel, (0..src.pixel_count()).map(|i| f(&src, i, c)).collect());
    }
    let path = tmp(name);
    img.write_exr(&path).unwrap();
    path
}

fn colour(src: &LayeredImage, i: usize, c: usize) -> f32 {
    src.channel(["R", "G", "B"][c]).unwrap()[i]
}

#[test]
fn a_flipped_or_black_image_fails_by_default_and_the_render_itself_passes() {
    let a = render().to_str().unwrap();
    let (code, text) = diff(&[a, a]);
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("PASS: relmse 0.000000e0 is within the fail bound 1.000e-3 (default)"),
        "{text}"
    );
    // The same image read bottom-up: every row against its mirror.
    let (code, text) = diff(&[a, a, "--flip-y"]);
    assert_eq!(code, 2, "{text}");
    assert!(
        text.contains("FAIL: relmse") && text.contains("above the fail bound 1.000e-3 (default)"),
        "{text}"
    );
    let black = derived_exr("black.exr", |_, _, _| 0.0);
    let (code, text) = diff(&[a, black.to_str().unwrap()]);
    assert_eq!(code, 2, "{text}");
    // The bias names the loss: nothing of the reference's light is left.
    assert!(
        text.contains("bias      test/reference R 0.0000 G 0.0000 B 0.0000 Y 0.0000"),
        "{text}"
    );
    // Flipping a flipped image back passes.
    let w = read(render()).width as usize;
    let h = read(render()).height as usize;
    let flipped = derived_exr("flipped.exr", |s, i, c| colour(s, (h - 1 - i / w) * w + i % w, c));
    assert_eq!(diff(&[a, flipped.to_str().unwrap(), "--flip-y"]).0, 0);
    // An explicit bound still decides the metric test; the bias test fails the black image
    // unless it is off.
    let (code, text) = diff(&[a, black.to_str().unwrap(), "--fail", "2"]);
    assert_eq!(code, 2, "{text}");
    assert!(
        text.contains("FAIL: bias over `all`: Y test/reference 0.0000"),
        "{text}"
    );
    assert_eq!(
        diff(&[a, black.to_str().unwrap(), "--fail", "2", "--fail-bias", "none"]).0,
        0
    );
    // Against a black reference no ratio exists: a dim test image fails the bias test (it
    // passed as "no significant bias" with a NaN interval, issue 43); black passes black.
    let dim = derived_exr("dim.exr", |_, _, _| 1e-3);
    let b = black.to_str().unwrap();
    let (code, text) = diff(&[b, dim.to_str().unwrap(), "--fail", "2"]);
    assert_eq!(code, 2, "{text}");
    assert!(
        text.contains("FAIL: bias over `all`: Y the reference sums to 0 and the test image does not"),
        "{text}"
    );
    assert_eq!(diff(&[b, b]).0, 0);
}

#[test]
fn png_jpeg_and_hdr_inputs_are_decoded_to_linear() {
    // A display-referred reference: the render clamped to [0, 1], what an 8-bit file can hold.
    let clamped = derived_exr("clamped.exr", |s, i, c| colour(s, i, c).min(1.0));
    let a = clamped.to_str().unwrap();
    let src = read(&clamped);
    let (w, h) = (src.width, src.height);
    let rgb: Vec<[f32; 3]> = (0..src.pixel_count())
        .map(|i| [0, 1, 2].map(|c| colour(&src, i, c)))
        .collect();
    let encode8 = |v: f32| (linear_to_srgb(v.clamp(0.0, 1.0)) * 255.0).round() as u8;
    // 8-bit sRGB PNG: quantisation only, well within the default bound.
    let png = tmp("render.png");
    image::RgbImage::from_fn(w, h, |x, y| image::Rgb(rgb[(y * w + x) as usize].map(encode8)))
        .save(&png)
        .unwrap();
    let (code, text) = diff(&[a, png.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("(default)"),
        "no noise floor, no relaxed bound: {text}"
    );
    // Read as linear, the same PNG is far too bright in the darks: fails.
    assert_eq!(diff(&[a, png.to_str().unwrap(), "--linear"]).0, 2);
    // 16-bit PNG exposed by −1 stop: --exposure -1 undoes it; without it, the image is half
    // as bright.
    let png16 = tmp("render16.png");
    image::ImageBuffer::<image::Rgb<u16>, _>::from_fn(w, h, |x, y| {
        image::Rgb(rgb[(y * w + x) as usize].map(|v| (linear_to_srgb(0.5 * v) * 65535.0).round() as u16))
    })
    .save(&png16)
    .unwrap();
    let (code, text) = diff(&[a, png16.to_str().unwrap(), "--exposure", "-1", "--json", "-"]);
    assert_eq!(code, 0, "{text}");
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["test"]["format"], "ldr");
    let ratio = json["bias"]["ratio"]["Y"].as_f64().unwrap();
    assert!((ratio - 1.0).abs() < 1e-3, "{ratio}");
    let (code, text) = diff(&[a, png16.to_str().unwrap(), "--json", "-"]);
    assert_eq!(code, 2, "{text}");
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert!(
        (json["bias"]["ratio"]["Y"].as_f64().unwrap() - 0.5).abs() < 1e-3,
        "{json}"
    );
    // JPEG: lossy, but read.
    let jpeg = tmp("render.jpg");
    image::RgbImage::from_fn(w, h, |x, y| image::Rgb(rgb[(y * w + x) as usize].map(encode8)))
        .save(&jpeg)
        .unwrap();
    // Its chroma quantisation moves the mean of the small blue channel by 7 %: a real bias,
    // which a 10 % bound lets through.
    let (code, text) = diff(&[a, jpeg.to_str().unwrap(), "--fail", "0.2"]);
    assert_eq!(code, 2, "{text}");
    assert!(
        text.contains("FAIL: bias over `all`: B test/reference 1.07"),
        "{text}"
    );
    let (code, text) = diff(&[a, jpeg.to_str().unwrap(), "--fail", "0.2", "--fail-bias", "0.1"]);
    assert_eq!(code, 0, "{text}");
    // Radiance HDR: linear, RGBE-quantised (8-bit mantissas: < 1 % per pixel).
    let hdr = tmp("render.hdr");
    let pixels: Vec<image::Rgb<f32>> = rgb.iter().map(|&p| image::Rgb(p)).collect();
    let file = std::io::BufWriter::new(std::fs::File::create(&hdr).unwrap());
    image::codecs::hdr::HdrEncoder::new(file)
        .encode(&pixels, w as usize, h as usize)
        .unwrap();
    let (code, text) = diff(&[a, hdr.to_str().unwrap(), "--json", "-"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("\"format\": \"hdr\""), "{text}");
    // --exposure with no LDR input is a usage error.
    let (code, text) = diff(&[a, hdr.to_str().unwrap(), "--exposure", "1"]);
    assert_eq!(
        (code, text.trim()),
        (
            2,
            "error: --exposure applies to PNG/JPEG inputs; both images are scene-referred (OpenEXR or HDR)"
        )
    );
    // An exposure beyond ±64 stops (render's and merge's range) is a usage error: 1e30
    // stops divided a white PNG to 0, and black against it passed (issue 43).
    for stops in ["1e30", "65", "-64.5"] {
        let (code, text) = diff(&[a, hdr.to_str().unwrap(), &format!("--exposure={stops}")]);
        assert_eq!(code, 2, "{stops}: {text}");
        assert!(
            text.contains("expected a number of stops in −64..=64"),
            "{stops}: {text}"
        );
    }
    // Not an image at all: exit 4, one line naming the file once.
    let junk = tmp("junk.png");
    std::fs::write(&junk, b"this is not an image").unwrap();
    let (code, text) = diff(&[a, junk.to_str().unwrap()]);
    assert_eq!(code, 4, "{text}");
    assert_eq!(
        (text.lines().count(), text.matches(junk.to_str().unwrap()).count()),
        (1, 1),
        "{text}"
    );
}

#[test]
fn layered_exrs_are_read_by_layer() {
    let a = render().to_str().unwrap();
    let src = read(render());
    let mut layered = LayeredImage::new(src.width, src.height);
    for (prefix, scale) in [("beauty", 1.0), ("half", 0.5)] {
        for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
            let data = (0..src.pixel_count())
                .map(|i| scale * colour(&src, i, c))
                .collect();
            layered.push_channel(format!("{prefix}.{name}"), data);
        }
    }
    layered.push_channel("A", vec![1.0; src.pixel_count()]);
    let path = tmp("layered.exr");
    layered.write_exr(&path).unwrap();
    let p = path.to_str().unwrap();
    let (code, text) = diff(&[a, p]);
    assert_eq!(code, 4, "{text}");
    assert!(
        text.contains(
            "several colour layers; choose one with --layer (its layers with R, G, B: beauty, half)"
        ),
        "{text}"
    );
    assert_eq!(diff(&[a, p, "--layer", "beauty"]).0, 0);
    let (code, text) = diff(&[a, p, "--layer", "half", "--json", "-"]);
    assert_eq!(code, 2, "{text}");
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["test"]["layer"], "half");
    assert!((json["bias"]["ratio"]["G"].as_f64().unwrap() - 0.5).abs() < 1e-6);
    let (code, text) = diff(&[a, p, "--layer", "diffuse"]);
    assert_eq!(code, 4, "{text}");
    assert!(
        text.contains("no layer `diffuse` with diffuse.R, diffuse.G and diffuse.B"),
        "{text}"
    );
    // --layer on a PNG: an error, not a silent default.
    let png = tmp("layer.png");
    image::RgbImage::new(src.width, src.height).save(&png).unwrap();
    let (code, text) = diff(&[a, png.to_str().unwrap(), "--layer", "beauty"]);
    assert_eq!(code, 4, "{text}");
    assert!(
        text.contains("--layer selects a layer of an OpenEXR file"),
        "{text}"
    );
}

#[test]
fn objects_are_named_in_masks_and_in_the_per_object_table() {
    let a = render().to_str().unwrap();
    let src = read(render());
    let names = src
        .object_names()
        .unwrap()
        .expect("the oracle writes object_names");
    assert!(names.iter().any(|n| n == "tall_block"), "{names:?}");
    // Darken the tall block by 30 %: only it differs.
    let ids = src.channel("object_id.Y").unwrap().to_vec();
    let tall = 1 + names.iter().position(|n| n == "tall_block").unwrap() as u32;
    let b = derived_exr("darker-block.exr", |s, i, c| {
        colour(s, i, c) * if ids[i] as u32 == tall { 0.7 } else { 1.0 }
    });
    let b = b.to_str().unwrap();
    let (code, text) = diff(&[a, b, "--mask", "objects:tall_block"]);
    assert_eq!(code, 2, "{text}");
    let (code, text) = diff(&[a, b, "--mask", "objects:floor,back,*_red,right_?reen"]);
    assert_eq!(code, 0, "{text}");
    let (code, text) = diff(&[a, b, "--mask", "objects:pillar*"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("`pillar*` matches no object; objects: "), "{text}");
    let (code, text) = diff(&[
        a,
        b,
        "--per-object",
        "--metric",
        "relmse",
        "--metric",
        "flip_ldr",
        "--json",
        "-",
    ]);
    // Over the mask (`all`) one darker object among nine stays within the default bound and
    // its bias is not significant; the bias test of each object finds it.
    assert_eq!(code, 2, "{text}");
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["bias"]["verdict"], "pass", "{json}");
    assert!(
        json["reason"]
            .as_str()
            .unwrap()
            .starts_with("bias of object `tall_block`: Y test/reference 0.7000"),
        "{json}"
    );
    let objects = json["objects"].as_array().unwrap();
    let block = objects.iter().find(|o| o["name"] == "tall_block").unwrap();
    assert!(
        (block["bias"]["ratio"]["Y"].as_f64().unwrap() - 0.7).abs() < 1e-5,
        "{block}"
    );
    // relMSE on the block: (0.3 r)²/(r² + 0.01) ≤ 0.09; elsewhere exactly 0.
    let block_relmse = block["values"][0].as_f64().unwrap();
    assert!(block_relmse > 1e-3 && block_relmse <= 0.09, "{block}");
    for o in objects.iter().filter(|o| o["name"] != "tall_block") {
        assert_eq!(o["values"][0].as_f64(), Some(0.0), "{o}");
    }
    let total: u64 = objects.iter().map(|o| o["pixels"].as_u64().unwrap()).sum();
    assert_eq!(total, json["mask"]["pixels"].as_u64().unwrap());
}

/// The JSON report validates against compare/schema/diff.schema.json (Python `jsonschema`
/// from the project's venv), for a pass, a fail with NaN and a per-object report.
#[test]
fn the_json_report_follows_its_schema() {
    let a = render().to_str().unwrap();
    let nan = derived_exr(
        "nan.exr",
        |s, i, c| if i == 7 { f32::NAN } else { colour(s, i, c) },
    );
    let outputs = [
        (vec![a, a, "--metric", "ssim", "--metric", "flip_hdr"], 0),
        (vec![a, nan.to_str().unwrap()], 2),
        (
            vec![
                a,
                a,
                "--per-object",
                "--mask",
                "interior",
                "--fail",
                "1e-2",
                "--fail-percent",
                "5",
                "--warn",
                "1e-4",
            ],
            0,
        ),
    ];
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let python = std::env::var_os("VERITY_PYTHON").map_or(workspace.join(".venv/bin/python"), PathBuf::from);
    let schema = workspace.join("compare/schema/diff.schema.json");
    for (i, (args, want)) in outputs.into_iter().enumerate() {
        let json = tmp(&format!("report-{i}.json"));
        let (code, text) = diff(&[&args[..], &["--json", json.to_str().unwrap()]].concat());
        assert_eq!(code, want, "{args:?}: {text}");
        let report: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        assert_eq!(report["exit_status"], want);
        let check = Command::new(&python)
            .args([
                "-c",
                "import json, sys, jsonschema; jsonschema.validate(json.load(open(sys.argv[2])), json.load(open(sys.argv[1])))",
                schema.to_str().unwrap(),
                json.to_str().unwrap(),
            ])
            .output()
            .unwrap_or_else(|e| panic!("{}: {e} (run ./scripts/setup.sh)", python.display()));
        assert!(
            check.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&check.stderr)
        );
    }
    // The SSIM of the render against itself is exactly 1.
    let (_, text) = diff(&[a, a, "--metric", "ssim", "--json", "-"]);
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["metrics"][0]["value"].as_f64(), Some(1.0));
}
