//! `verity` usage: help, exit statuses, and error messages that name the flag or file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn verity(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_verity"))
        .args(args)
        .output()
        .expect("run verity")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("verity-cli-usage-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn cornell_box() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/cornell-box.toml")
        .display()
        .to_string()
}

/// Exit status 2, one `error:` line naming `needle`, no panic.
fn assert_usage_error(out: &Output, needle: &str, what: &str) {
    let stderr = text(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{what}: expected exit 2; stderr:\n{stderr}"
    );
    assert!(
        stderr.starts_with("error: "),
        "{what}: stderr must start with `error: `:\n{stderr}"
    );
    assert!(
        stderr.contains(needle),
        "{what}: stderr must name `{needle}`:\n{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{what}: panicked:\n{stderr}");
}

#[test]
fn cli_help_lists_every_subcommand() {
    let out = verity(&["--help"]);
    assert_eq!(out.status.code(), Some(0));
    let stdout = text(&out.stdout);
    // Each subcommand is listed on a line of its own, its name first (clap's layout).
    for sub in [
        "render",
        "export-mitsuba",
        "crosscheck",
        "bench",
        "raster",
        "bake",
        "report",
        "diff",
    ] {
        assert!(
            stdout.lines().any(|l| l.split_whitespace().next() == Some(sub)),
            "--help must list the `{sub}` subcommand:\n{stdout}"
        );
    }
    assert!(
        stdout.contains("Exit status"),
        "--help must document exit statuses:\n{stdout}"
    );

    let out = verity(&["render", "--help"]);
    assert_eq!(out.status.code(), Some(0));
    let stdout = text(&out.stdout);
    for flag in [
        "--spp",
        "--time",
        "--target-error",
        "--integrator",
        "--max-depth",
        "--seed",
        "--resolution",
        "--ao-radius",
        "--out",
        "--exposure",
        "--checkpoint-every",
        "--resume",
        "--quiet",
    ] {
        assert!(
            stdout.contains(flag),
            "render --help must document {flag}:\n{stdout}"
        );
    }

    let out = verity(&["--version"]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(
        text(&out.stdout).trim(),
        format!("verity {}", env!("CARGO_PKG_VERSION"))
    );
}

#[test]
fn cli_no_subcommand_is_a_usage_error() {
    let out = verity(&[]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    let out = verity(&["paint"]);
    assert_usage_error(&out, "paint", "unknown subcommand");
}

#[test]
fn cli_bad_flag_values_exit_2_naming_the_flag() {
    let scene = cornell_box();
    let cases: [(&[&str], &str); 15] = [
        (&["--spp", "0"], "--spp"),
        (&["--spp", "many"], "--spp"),
        (&["--resolution", "0x5"], "--resolution"),
        (&["--resolution", "16385x16"], "--resolution"),
        (&["--resolution", "640"], "--resolution"),
        (&["--integrator", "photon"], "--integrator"),
        (&["--max-depth", "-2"], "--max-depth"),
        (&["--time", "-1"], "--time"),
        (&["--time", "inf"], "--time"),
        (&["--target-error", "0"], "--target-error"),
        (&["--ao-radius", "-1"], "--ao-radius"),
        (&["--exposure", "nan"], "--exposure"),
        (&["--checkpoint-every", "-5"], "--checkpoint-every"),
        (&["--bogus"], "--bogus"),
        (&["--out", "picture.png"], "--out"),
    ];
    for (flags, needle) in cases {
        let mut args = vec!["render", scene.as_str()];
        args.extend_from_slice(flags);
        assert_usage_error(&verity(&args), needle, &format!("{flags:?}"));
    }
    let out = verity(&["render", &scene, "--resume", "--checkpoint-every", "0"]);
    assert_usage_error(&out, "--resume", "--resume without checkpoints");
}

#[test]
fn cli_missing_or_bad_scene_exits_2_naming_the_file() {
    let dir = test_dir("scene");
    let out_exr = dir.join("out.exr").display().to_string();

    let missing = dir.join("no-such-scene.toml").display().to_string();
    let out = verity(&["render", &missing, "--out", &out_exr]);
    assert_usage_error(&out, "no-such-scene.toml", "missing scene");

    let unknown = dir.join("scene.txt");
    std::fs::write(&unknown, "camera = 1").unwrap();
    let out = verity(&["render", &unknown.display().to_string(), "--out", &out_exr]);
    assert_usage_error(&out, "scene.txt", "unknown scene type");

    let malformed = dir.join("broken.toml");
    std::fs::write(&malformed, "[camera\nfov = ").unwrap();
    let out = verity(&["render", &malformed.display().to_string(), "--out", &out_exr]);
    assert_usage_error(&out, "broken.toml", "malformed TOML");

    assert!(
        !dir.join("out.exr").exists(),
        "no output may be written for bad input"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--integrator` reads both spellings of the unshadowed integrator (the scene format's
/// `direct_unshadowed` too) and the EXR header prints one.
#[test]
fn cli_integrator_reads_either_spelling_and_prints_one() {
    let dir = test_dir("integrator");
    for spelling in ["direct-unshadowed", "direct_unshadowed"] {
        let exr = dir.join(format!("{spelling}.exr"));
        let out = verity(&[
            "render",
            &cornell_box(),
            "--integrator",
            spelling,
            "--resolution",
            "4x4",
            "--spp",
            "1",
            "-q",
            "--out",
            exr.to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(0), "{spelling}: {}", text(&out.stderr));
        let img = scenes::layered::LayeredImage::read_exr(&exr).unwrap();
        assert_eq!(
            img.attribute("integrator"),
            Some("direct-unshadowed"),
            "{spelling}"
        );
    }
}

/// `verity bake`: the atlas EXR with its channels and chart table, the summary line, and bad
/// input (a resolution of 0 or 65536, a mesh without TEXCOORD_1, an unknown dynamic shape) as
/// an error naming it with exit 2, nothing written.
#[test]
fn cli_bake_writes_the_atlas_and_refuses_what_it_cannot_bake() {
    let dir = test_dir("bake");
    let scene = dir.join("floor.toml");
    let floor = "[camera]\neye = [0, 3, 3]\ntarget = [0, 0, 0]\nfov = 40\n[film]\nwidth = 8\nheight = 8\n\
                 [[material]]\nname = \"grey\"\ntype = \"diffuse\"\nalbedo = 0.5\n\
                 [[shape]]\nname = \"floor\"\ntype = \"rectangle\"\nmaterial = \"grey\"\ncenter = [0, 0, 0]\nsize = [2, 1]\nnormal = [0, 1, 0]\n\
                 [[light]]\nname = \"bulb\"\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = 2\n";
    std::fs::write(&scene, floor).unwrap();
    let out_path = dir.join("map.exr");
    let (scene_s, out_s) = (scene.display().to_string(), out_path.display().to_string());
    let out = verity(&[
        "bake",
        &scene_s,
        "--out",
        &out_s,
        "--resolution",
        "8",
        "--spp",
        "2",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("1 chart in a")
            && stdout.contains("2 spp per texel")
            && stdout.contains("mean relative standard error"),
        "{stdout}"
    );
    let img = scenes::layered::LayeredImage::read_exr(&out_path).unwrap();
    assert!(
        img.channel("E.R").is_some()
            && img.channel("E_variance.G").is_some()
            && img.channel("covered.Y").is_some()
    );
    let table = img.attribute("verity.lightmap.charts").unwrap();
    assert!(table.starts_with("floor ") && table.ends_with(" 8 4"), "{table}");
    assert!(out_path.with_extension("png").exists());
    // Directly under the bulb, 1 m away: E = I = 2 W/m² (texels (3..5, 1..3) straddle it).
    let e = img.channel("E.R").unwrap();
    assert!(e.iter().any(|&v| v > 1.8 && v <= 2.0), "{e:?}");

    let bad = dir.join("never.exr").display().to_string();
    for (flag, value) in [("--resolution", "0"), ("--resolution", "65536")] {
        let out = verity(&["bake", &scene_s, "--out", &bad, flag, value]);
        assert_usage_error(&out, "--resolution", &format!("bake {flag} {value}"));
        assert!(text(&out.stderr).contains("1..=8192"));
    }
    let out = verity(&["bake", &scene_s, "--out", &bad, "--dynamic", "flor"]);
    assert_usage_error(
        &out,
        "dynamic shape `flor` is not in the scene",
        "bake --dynamic flor",
    );
    let ico = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/studies/scenes/shading-sphere.toml")
        .display()
        .to_string();
    let out = verity(&["bake", &ico, "--out", &bad]);
    assert_usage_error(
        &out,
        "shape `ball`: a triangle mesh without a second uv set (glTF TEXCOORD_1)",
        "bake of an icosphere",
    );
    assert!(!Path::new(&bad).exists());
}
