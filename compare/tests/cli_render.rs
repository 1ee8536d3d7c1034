//! `verity render` end to end: tiny renders of the built-in Cornell box, the EXR and PNG it
//! writes, its header, its summary line, and how checkpoints and budgets are handled.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use scenes::layered::LayeredImage;

fn verity_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_verity"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run verity")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("verity-cli-render-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn cornell_box() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box.toml");
    path.canonicalize().unwrap_or(path).display().to_string()
}

fn assert_success(out: &Output, what: &str) {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{what}: expected exit 0\nstdout:\n{}\nstderr:\n{}",
        text(&out.stdout),
        text(&out.stderr)
    );
}

/// Width and height from a PNG's IHDR chunk (PNG spec §11.2.2).
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(
        &bytes[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is not a PNG",
        path.display()
    );
    let be = |o: usize| u32::from_be_bytes(bytes[o..o + 4].try_into().unwrap());
    (be(16), be(20))
}

/// Names of every entry in `dir`, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn cli_render_tiny_cornell_box() {
    let dir = test_dir("tiny");
    let scene = cornell_box();
    let out_path = dir.join("cb.exr");
    let out_arg = out_path.display().to_string();
    let out = verity_in(
        &dir,
        &[
            "render",
            &scene,
            "--resolution",
            "16x16",
            "--spp",
            "4",
            "--seed",
            "7",
            "--out",
            &out_arg,
        ],
    );
    assert_success(&out, "tiny render");

    let stdout = text(&out.stdout);
    let prefix = format!("rendered {scene}: 16x16, 4 spp, ");
    assert!(
        stdout.starts_with(&prefix),
        "summary line must start with `{prefix}`:\n{stdout}"
    );
    assert!(
        stdout.trim_end().ends_with(&format!("Mrays/s -> {out_arg}")) && stdout.contains(" Mpaths/s, "),
        "summary line format:\n{stdout}"
    );
    let stderr = text(&out.stderr);
    assert!(
        stderr.starts_with(&format!("render {scene}: 16x16, path")),
        "start line:\n{stderr}"
    );

    let img = LayeredImage::read_exr(&out_path).unwrap();
    assert_eq!((img.width, img.height), (16, 16));
    let rgb = img.rgb("").expect("R, G, B channels");
    assert!(
        rgb.iter().all(|c| c.is_finite() && c.min_element() >= 0.0),
        "RGB must be finite and ≥ 0"
    );
    assert!(
        rgb.iter().any(|c| c.max_element() > 0.0),
        "the Cornell box is not black"
    );
    assert!(img.rgb("variance").is_some(), "variance channels");
    let expected = [
        ("spp", "4"),
        ("seed", "7"),
        ("integrator", "path"),
        ("scene", scene.as_str()),
        ("verity_version", env!("CARGO_PKG_VERSION")),
    ];
    for (key, value) in expected {
        assert_eq!(img.attribute(key), Some(value), "attribute {key}");
    }
    let command_line = img.attribute("command_line").unwrap();
    assert!(
        command_line.contains("render") && command_line.contains("--spp 4"),
        "{command_line}"
    );
    assert!(img.attribute("seconds").unwrap().parse::<f64>().unwrap() >= 0.0);

    assert_eq!(png_size(&dir.join("cb.png")), (16, 16));
    assert_eq!(
        entries(&dir),
        ["cb.exr", "cb.png"],
        "no checkpoint or temporary file may remain"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--pixel-filter box` renders exactly what the default renders (the box filter, unchanged);
/// `centre` (or `center`) with `--ssaa K` is recorded in the header, and its coverage takes
/// only the K² + 1 levels of K×K sub-pixel centres.
#[test]
fn cli_render_pixel_filter_flags() {
    let dir = test_dir("pixel-filter");
    let scene = cornell_box();
    let render = |name: &str, extra: &[&str]| {
        let out_arg = dir.join(name).display().to_string();
        let mut args = vec!["render", &scene, "--resolution", "12x10", "--spp", "8", "-q"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out", &out_arg]);
        let out = verity_in(&dir, &args);
        assert_success(&out, name);
        (LayeredImage::read_exr(dir.join(name)).unwrap(), text(&out.stderr))
    };
    let (default, _) = render("default.exr", &[]);
    let (boxed, _) = render("box.exr", &["--pixel-filter", "box"]);
    assert_eq!(
        default.channels, boxed.channels,
        "--pixel-filter box is the default"
    );
    for img in [&default, &boxed] {
        assert_eq!(img.attribute("pixel_filter"), Some("box"));
        assert_eq!(img.attribute("subpixels"), None);
    }
    let (centre, _) = render("centre.exr", &["--pixel-filter", "center"]);
    assert_eq!(centre.attribute("pixel_filter"), Some("centre"));
    assert_eq!(centre.attribute("subpixels"), None);
    let coverage = centre.channel("coverage.Y").unwrap();
    assert!(coverage.iter().all(|c| *c == 0.0 || *c == 1.0), "{coverage:?}");

    let out_arg = dir.join("k2.exr").display().to_string();
    let out = verity_in(
        &dir,
        &[
            "render",
            &scene,
            "--resolution",
            "12x10",
            "--spp",
            "8",
            "--pixel-filter",
            "centre",
            "--ssaa",
            "2",
            "--out",
            &out_arg,
        ],
    );
    assert_success(&out, "centre 2x2");
    let stderr = text(&out.stderr);
    assert!(
        stderr
            .lines()
            .next()
            .unwrap()
            .contains(", 8 spp, pixel filter centre 2x2 -> "),
        "{stderr}"
    );
    let k2 = LayeredImage::read_exr(dir.join("k2.exr")).unwrap();
    assert_eq!(
        (k2.attribute("pixel_filter"), k2.attribute("subpixels")),
        (Some("centre"), Some("2x2"))
    );
    let coverage = k2.channel("coverage.Y").unwrap();
    assert!(coverage.iter().all(|c| (c * 4.0).fract() == 0.0), "{coverage:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A bad `--pixel-filter` is clap's usage error; `--ssaa` without the centre filter and a
/// sample count the K×K centres cannot share are one-line input errors (exit 2) that write
/// nothing.
#[test]
fn cli_render_refuses_bad_pixel_filter_input() {
    let dir = test_dir("pixel-filter-bad");
    let scene = cornell_box();
    let run = |extra: &[&str]| {
        let mut args = vec!["render", &scene, "--resolution", "8x8", "--out", "x.exr"];
        args.extend_from_slice(extra);
        verity_in(&dir, &args)
    };
    let out = run(&["--pixel-filter", "gauss"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("invalid value 'gauss' for '--pixel-filter <FILTER>'")
            && stderr.contains("box, centre"),
        "{stderr}"
    );
    for (extra, expected) in [
        (
            &["--spp", "4", "--ssaa", "2"][..],
            "error: --ssaa 2: sub-pixel centres need the centre pixel filter, and this render's is box",
        ),
        (
            &["--spp", "6", "--pixel-filter", "centre", "--ssaa", "2"][..],
            "error: --spp: 6 spp is not a multiple of 4, the centre pixel filter's 2x2 sub-pixel centres \
             (each takes the same number of samples); use 4 or 8 spp",
        ),
        (
            // The scene's own spp (64) is not a multiple of 9.
            &["--pixel-filter", "centre", "--ssaa", "3"][..],
            "the scene's spp: 64 spp is not a multiple of 9",
        ),
    ] {
        let out = run(extra);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(expected), "{extra:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{extra:?}: one line: {stderr}");
    }
    assert!(
        entries(&dir).is_empty(),
        "nothing is written: {:?}",
        entries(&dir)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn cli_render_default_output_and_overrides() {
    let dir = test_dir("default-out");
    let scene = cornell_box();
    let args = [
        "render",
        &scene,
        "--resolution",
        "8x6",
        "--spp",
        "2",
        "--integrator",
        "ao",
        "--ao-radius",
        "0.5",
        "--max-depth",
        "-1",
        "--quiet",
    ];
    let out = verity_in(&dir, &args);
    assert_success(&out, "default output");
    assert_eq!(text(&out.stderr), "", "--quiet prints nothing on stderr");
    assert!(
        text(&out.stdout).contains("-> out/cornell-box.exr"),
        "{}",
        text(&out.stdout)
    );
    let img = LayeredImage::read_exr(dir.join("out/cornell-box.exr")).unwrap();
    assert_eq!((img.width, img.height), (8, 6));
    assert_eq!(img.attribute("integrator"), Some("ao"));
    assert_eq!(img.attribute("ao_radius"), Some("0.5"));
    // Ambient occlusion is a visible fraction: within [0, 1].
    for (i, c) in img.rgb("").unwrap().iter().enumerate() {
        assert!(
            c.min_element() >= 0.0 && c.max_element() <= 1.0,
            "ao pixel {i} = {c}"
        );
    }
    assert_eq!(png_size(&dir.join("out/cornell-box.png")), (8, 6));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn cli_render_time_budget_without_spp() {
    let dir = test_dir("time");
    let scene = cornell_box();
    let out = verity_in(
        &dir,
        &[
            "render",
            &scene,
            "--resolution",
            "8x8",
            "--time",
            "0.3",
            "--out",
            "t.exr",
        ],
    );
    assert_success(&out, "time budget");
    let img = LayeredImage::read_exr(dir.join("t.exr")).unwrap();
    let spp: u32 = img.attribute("spp").unwrap().parse().unwrap();
    let seconds: f64 = img.attribute("seconds").unwrap().parse().unwrap();
    assert!(spp >= 1, "spp {spp}");
    assert!(
        seconds >= 0.3,
        "stops after the pass that crosses 0.3 s, stopped at {seconds} s"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn cli_render_resume_with_a_bad_checkpoint_fails_with_exit_1() {
    let dir = test_dir("resume");
    let scene = cornell_box();
    let args = [
        "render",
        &scene,
        "--resolution",
        "8x8",
        "--spp",
        "2",
        "--out",
        "r.exr",
        "--resume",
    ];

    // No checkpoint yet: a note, then a fresh render.
    let out = verity_in(&dir, &args);
    assert_success(&out, "resume without checkpoint");
    assert!(
        text(&out.stderr).contains("no checkpoint at r.exr.checkpoint"),
        "{}",
        text(&out.stderr)
    );

    std::fs::write(dir.join("r.exr.checkpoint"), b"not a checkpoint").unwrap();
    let before = std::fs::read(dir.join("r.exr")).unwrap();
    let out = verity_in(&dir, &args);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "a render failure exits 1:\n{stderr}");
    assert!(
        stderr.ends_with(&format!(
            "error: rendering {scene}: checkpoint r.exr.checkpoint: is not a Verity checkpoint \
             (bad magic); delete it or drop --resume\n"
        )),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(
        std::fs::read(dir.join("r.exr")).unwrap(),
        before,
        "a failed render keeps the old output"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every output (EXR, PNG preview, checkpoint) is checked before rendering: when one cannot
/// be written the command fails as bad input (exit 2) with one line naming it, and nothing is
/// written, not even the outputs that could be.
#[test]
fn cli_render_checks_every_output_before_rendering() {
    let dir = test_dir("outputs");
    let scene = cornell_box();
    let render = |extra: &[&str]| {
        let args = [
            &[
                "render",
                &scene,
                "--resolution",
                "8x8",
                "--spp",
                "1",
                "--out",
                "r.exr",
            ],
            extra,
        ];
        verity_in(&dir, &args.concat())
    };
    std::fs::write(dir.join("r.exr"), b"the old EXR").unwrap();
    std::fs::create_dir(dir.join("r.png")).unwrap();
    let out = render(&[]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert_eq!(
        text(&out.stderr),
        "error: r.png: is a directory (the PNG preview beside --out r.exr); nothing was written\n"
    );
    assert_eq!(std::fs::read(dir.join("r.exr")).unwrap(), b"the old EXR");
    assert!(
        text(&out.stdout).is_empty(),
        "nothing rendered: {}",
        text(&out.stdout)
    );

    std::fs::remove_dir(dir.join("r.png")).unwrap();
    std::fs::create_dir(dir.join("r.exr.checkpoint")).unwrap();
    let out = render(&["--checkpoint-every", "1"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert_eq!(
        text(&out.stderr),
        "error: r.exr.checkpoint: is a directory (the checkpoint of --out r.exr); nothing was written\n"
    );
    assert_eq!(std::fs::read(dir.join("r.exr")).unwrap(), b"the old EXR");
    assert_eq!(entries(&dir), ["r.exr", "r.exr.checkpoint"], "nothing written");

    // With checkpoints off, the checkpoint path is not an output.
    let out = render(&["--checkpoint-every", "0", "--quiet"]);
    assert_success(&out, "no checkpoint");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--out` a symbolic link: the render replaces the link's target and keeps the link.
#[cfg(unix)]
#[test]
fn cli_render_writes_through_a_symbolic_link() {
    let dir = test_dir("symlink");
    std::fs::create_dir(dir.join("renders")).unwrap();
    std::fs::write(dir.join("renders/latest.exr"), b"the old EXR").unwrap();
    std::os::unix::fs::symlink("renders/latest.exr", dir.join("link.exr")).unwrap();
    let out = verity_in(
        &dir,
        &[
            "render",
            &cornell_box(),
            "--resolution",
            "8x8",
            "--spp",
            "1",
            "--out",
            "link.exr",
            "--quiet",
        ],
    );
    assert_success(&out, "render to a link");
    let link = std::fs::symlink_metadata(dir.join("link.exr")).unwrap();
    assert!(link.file_type().is_symlink(), "the link was replaced by a file");
    let img = LayeredImage::read_exr(dir.join("renders/latest.exr")).expect("the target is the new EXR");
    assert_eq!((img.width, img.height), (8, 8));
    assert_eq!(entries(&dir.join("renders")), ["latest.exr"]);
    assert_eq!(entries(&dir), ["link.exr", "link.png", "renders"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A render killed after its first checkpoint resumes from it and ends with exactly the bits
/// of an uninterrupted render of the same sample count.
#[test]
fn cli_render_resumes_from_checkpoint_bit_exactly() {
    use std::time::{Duration, Instant};
    let dir = test_dir("kill-resume");
    let scene = cornell_box();
    let common = ["render", scene.as_str(), "--resolution", "2x2", "--quiet"];
    let mut child = Command::new(env!("CARGO_BIN_EXE_verity"))
        .args(common)
        .args([
            "--spp",
            "100000000",
            "--checkpoint-every",
            "0.05",
            "--out",
            "k.exr",
        ])
        .current_dir(&dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("start verity");
    let checkpoint = dir.join("k.exr.checkpoint");
    let start = Instant::now();
    while !checkpoint.exists() {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the render ended ({status}) before writing a checkpoint");
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no checkpoint after 120 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();

    // A flipped byte in the accumulators is refused (exit 1, one line naming the file and
    // what to do), and the checkpoint is left for the user to delete.
    let intact = std::fs::read(&checkpoint).unwrap();
    let mut damaged = intact.clone();
    damaged[100] ^= 0x10;
    std::fs::write(&checkpoint, &damaged).unwrap();
    let out = verity_in(
        &dir,
        &[&common[..], &["--time", "0.001", "--resume", "--out", "k.exr"]].concat(),
    );
    let stderr = text(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(1),
        "a corrupt checkpoint exits 1:\n{stderr}"
    );
    assert_eq!(
        stderr
            .lines()
            .filter(|l| l.starts_with("error: "))
            .collect::<Vec<_>>(),
        [format!(
            "error: rendering {scene}: checkpoint k.exr.checkpoint: is corrupt: the SHA-256 of its \
             contents does not match the checksum it carries; delete it or drop --resume"
        )],
        "{stderr}"
    );
    assert!(
        !dir.join("k.exr").exists(),
        "nothing is written from a corrupt checkpoint"
    );
    assert_eq!(std::fs::read(&checkpoint).unwrap(), damaged);
    std::fs::write(&checkpoint, &intact).unwrap();

    // Resume with a budget already spent: the render stops at the checkpoint's spp.
    let out = verity_in(
        &dir,
        &[&common[..], &["--time", "0.001", "--resume", "--out", "k.exr"]].concat(),
    );
    assert_success(&out, "resume");
    assert!(!checkpoint.exists(), "a finished render removes its checkpoint");
    let resumed = LayeredImage::read_exr(dir.join("k.exr")).unwrap();
    let spp = resumed.attribute("spp").unwrap().to_string();
    assert!(spp.parse::<u32>().unwrap() >= 1, "spp {spp}");

    let out = verity_in(
        &dir,
        &[&common[..], &["--spp", &spp, "--out", "fresh.exr"]].concat(),
    );
    assert_success(&out, "uninterrupted");
    let fresh = LayeredImage::read_exr(dir.join("fresh.exr")).unwrap();
    for c in ["R", "G", "B", "variance.R"] {
        let bits = |img: &LayeredImage| {
            img.channel(c)
                .unwrap()
                .iter()
                .map(|v| v.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(
            bits(&resumed),
            bits(&fresh),
            "channel {c} at {spp} spp: resumed vs uninterrupted"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Renders `scene` (a path relative to the repository root) at 32×32 and 4 spp through the
/// CLI and checks the image of its glTF mesh: finite RGB, the mesh covering a good part of
/// the frame by `object_id`, and the mesh lit (its mean radiance 5 standard errors above 0).
/// Returns the mesh pixels' mean luminance, its standard error, and the CLI's stderr.
fn render_gltf_mesh(name: &str, scene: &str) -> (f64, f64, String) {
    let dir = test_dir(name);
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(scene);
    let scene_arg = scene_path.display().to_string();
    let out_path = dir.join(format!("{name}.exr"));
    let out_arg = out_path.display().to_string();
    let args = [
        "render",
        &scene_arg,
        "--resolution",
        "32x32",
        "--spp",
        "4",
        "--out",
        &out_arg,
    ];
    let out = verity_in(&dir, &args);
    assert_success(&out, scene);

    // Object ids are shape index + 1 (oracle/src/render.rs, `object_id_pass`).
    let loaded = scenes::load(&scene_path).unwrap();
    let mesh_ids: Vec<f32> = (0..loaded.shapes.len())
        .filter(|&i| matches!(loaded.shapes[i].geometry, scenes::Geometry::Mesh(_)))
        .map(|i| (i + 1) as f32)
        .collect();
    assert!(!mesh_ids.is_empty(), "{scene}: no mesh shape");

    let img = LayeredImage::read_exr(&out_path).unwrap();
    assert_eq!((img.width, img.height), (32, 32));
    assert_eq!(img.attribute("nonfinite_samples"), Some("0"), "{scene}");
    let rgb = img.rgb("").expect("R, G, B channels");
    assert!(
        rgb.iter().all(|c| c.is_finite() && c.min_element() >= 0.0),
        "{scene}: RGB must be finite and ≥ 0"
    );
    let var = img.rgb("variance").expect("variance channels");
    let ids = img.channel("object_id.Y").expect("object_id.Y");
    let on_mesh: Vec<usize> = (0..ids.len()).filter(|&i| mesh_ids.contains(&ids[i])).collect();
    let fraction = on_mesh.len() as f64 / ids.len() as f64;
    println!(
        "{scene}: mesh (ids {mesh_ids:?}) at {:.1} % of the pixel centres",
        100.0 * fraction
    );
    assert!(
        fraction >= 0.10,
        "{scene}: the mesh should cover ≥ 10 % of the pixel centres, covers {:.1} %",
        100.0 * fraction
    );
    // Mean luminance ((R+G+B)/3) over the mesh pixels; its variance is Σ var/(9·n²) with the
    // channels treated as independent (an upper bound would add covariances, all ≥ 0 here).
    let n = on_mesh.len() as f64;
    let mean = on_mesh
        .iter()
        .map(|&i| f64::from(rgb[i].element_sum()) / 3.0)
        .sum::<f64>()
        / n;
    let se = (on_mesh
        .iter()
        .map(|&i| f64::from(var[i].element_sum()))
        .sum::<f64>()
        / 9.0)
        .sqrt()
        / n;
    let lit = on_mesh.iter().filter(|&&i| rgb[i].max_element() > 0.0).count() as f64 / n;
    println!(
        "{scene}: mesh mean luminance {mean:.4} ± {se:.4}, {:.1} % of its pixels non-black",
        100.0 * lit
    );
    assert!(
        mean > 5.0 * se && mean > 0.0,
        "{scene}: the mesh is black: mean luminance {mean} ± {se}"
    );
    assert!(
        lit >= 0.95,
        "{scene}: only {:.1} % of the mesh pixels are non-black",
        100.0 * lit
    );
    std::fs::remove_dir_all(&dir).unwrap();
    (mean, se, text(&out.stderr))
}

#[test]
fn cli_render_gltf_asset_directly() {
    let (mean, se, stderr) = render_gltf_mesh("suzanne-glb", "scenes/assets/suzanne.glb");
    assert!(
        stderr.contains("lit by a uniform sky"),
        "the light-less asset must be lit by the default sky:\n{stderr}"
    );
    // Lit only by the default uniform sky (scenes::DEFAULT_SKY_RADIANCE), a passive surface
    // with an energy-conserving BSDF cannot outshine it (the white-furnace bound L ≤ max Lᵢ).
    let sky = f64::from(scenes::DEFAULT_SKY_RADIANCE);
    assert!(
        mean + 5.0 * se < sky,
        "the mesh ({mean} ± {se}) cannot be brighter than the sky ({sky}) lighting it"
    );
}

#[test]
fn cli_render_gltf_scene_file() {
    render_gltf_mesh("suzanne-toml", "scenes/suzanne.toml");
}

/// A glTF asset (one triangle) whose buffer is at `uri`, written as `<name>.gltf` in `dir`.
fn gltf_with_buffer_at(dir: &Path, name: &str, uri: &str) -> String {
    let json = format!(
        "{{\"asset\":{{\"version\":\"2.0\"}},\"buffers\":[{{\"uri\":\"{uri}\",\"byteLength\":36}}],\
         \"bufferViews\":[{{\"buffer\":0,\"byteLength\":36}}],\
         \"accessors\":[{{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]}}],\
         \"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":0}}}}]}}],\"nodes\":[{{\"mesh\":0}}]}}"
    );
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, json).unwrap();
    path.display().to_string()
}

/// Hostile buffer URIs end the render before anything is written: exit 2 and one `error:`
/// line naming the .gltf file, the field and the reason. A FIFO used to hang the load, a
/// `..` escape or `/dev/zero` (with `--allow-paths-outside`) used to be read.
#[cfg(unix)]
#[test]
fn cli_render_gltf_refuses_a_fifo_an_escape_and_a_device() {
    let dir = test_dir("gltf-hostile");
    let made = Command::new("mkfifo").arg(dir.join("pipe.bin")).status().unwrap();
    assert!(made.success(), "mkfifo");
    let cases = [
        (
            None,
            "fifo",
            "pipe.bin",
            "pipe.bin is not a regular file (it is a FIFO)",
        ),
        (
            None,
            "escape",
            "../../../../etc/passwd",
            "is refused: it resolves to /etc/passwd, outside",
        ),
        (
            Some("--allow-paths-outside"),
            "device",
            "/dev/zero",
            "/dev/zero is not a regular file (it is a device)",
        ),
    ];
    for (flag, name, uri, reason) in cases {
        let asset = gltf_with_buffer_at(&dir, name, uri);
        let out_path = dir.join(format!("{name}.exr"));
        let out_arg = out_path.display().to_string();
        let mut args: Vec<&str> = flag.into_iter().collect();
        args.extend([
            "render",
            &asset,
            "--resolution",
            "8x8",
            "--spp",
            "1",
            "--out",
            &out_arg,
        ]);
        let out = verity_in(&dir, &args);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: exit 2 expected\n{stderr}");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "{name}: one error line expected:\n{stderr}");
        let line = errors[0];
        assert!(
            line.contains(&format!("{name}.gltf")),
            "{name}: names the file: {line}"
        );
        assert!(
            line.contains("field `buffers[0].uri`"),
            "{name}: names the field: {line}"
        );
        assert!(line.contains(reason), "{name}: says why: {line}");
        assert!(!out_path.exists(), "{name}: nothing is written");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--resolution` of another shape than the glTF camera's `aspectRatio` (the scene takes the
/// asset's camera: `[[include]] camera = true`) renders as asked, with a one-line note on
/// standard error; a resolution of the camera's shape gets none.
#[test]
fn cli_render_notes_a_resolution_of_another_aspect_than_the_camera() {
    let dir = test_dir("aspect");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/include-asset.toml");
    let scene = scene.display().to_string();
    let render = |resolution: &str| {
        let out = dir.join(format!("{resolution}.exr")).display().to_string();
        let o = verity_in(
            &dir,
            &[
                "render",
                &scene,
                "--resolution",
                resolution,
                "--spp",
                "1",
                "--out",
                &out,
            ],
        );
        assert_success(&o, resolution);
        let img = LayeredImage::read_exr(&out).unwrap();
        (img.width, img.height, text(&o.stderr))
    };
    let (w, h, stderr) = render("16x16");
    assert_eq!((w, h), (16, 16));
    let note: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains("note: --resolution"))
        .collect();
    assert_eq!(note.len(), 1, "one note line expected in:\n{stderr}");
    assert!(
        note[0].ends_with(
            "include-asset.toml: note: --resolution 16x16 has the aspect ratio 1.0000, not the glTF camera's \
             aspectRatio 1.5; rendering at 1.0000 with the camera's vertical field of view"
        ),
        "{}",
        note[0]
    );
    let (w, h, stderr) = render("24x16");
    assert_eq!((w, h), (24, 16));
    assert!(!stderr.contains("note: --resolution"), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `[environment] negative = "clamp"`: the oracle's EXR header says how many texels were
/// clamped.
#[test]
fn cli_render_header_counts_clamped_environment_texels() {
    let dir = test_dir("clamped");
    let texels = [
        (0.5f32, 0.5f32, 0.5f32),
        (-0.25, 0.5, 0.5),
        (0.5, -1.0, -2.0),
        (1.0, 1.0, 1.0),
    ];
    exr::prelude::write_rgb_file(dir.join("sky.exr"), 4, 1, |x, _| texels[x]).unwrap();
    let scene = dir.join("sky.toml");
    std::fs::write(
        &scene,
        "[camera]\neye = [0, 0, 0]\ntarget = [0, 0, -1]\nfov = 60\n\n\
         [environment]\nfile = \"sky.exr\"\nnegative = \"clamp\"\n",
    )
    .unwrap();
    let out = dir.join("sky.exr.out.exr").display().to_string();
    let o = verity_in(
        &dir,
        &[
            "render",
            &scene.display().to_string(),
            "--resolution",
            "4x4",
            "--spp",
            "1",
            "--out",
            &out,
        ],
    );
    assert_success(&o, "clamped sky");
    let img = LayeredImage::read_exr(&out).unwrap();
    assert_eq!(img.attribute("environment_clamped_texels"), Some("2"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `verity render --part K/N` + `verity merge` give the EXR one `verity render` writes: every
/// channel bit for bit and every header attribute but `seconds` and `command_line`, for
/// N = 1, 2, 3, 7 (7 does not divide the 20 rows), in any order of the parts, with the box and
/// the centre (2×2) pixel filters and with light-visibility channels.
#[test]
fn cli_render_parts_merge_into_the_single_render_bit_for_bit() {
    let dir = test_dir("parts");
    let soft_shadow = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/soft-shadow.toml")
        .display()
        .to_string();
    let cases: [(&str, &[&str]); 3] = [
        (&cornell_box(), &["--spp", "8"]),
        (
            &cornell_box(),
            &["--spp", "8", "--pixel-filter", "centre", "--ssaa", "2"],
        ),
        (
            &soft_shadow,
            &["--spp", "4", "--integrator", "direct", "--seed", "3"],
        ),
    ];
    for (case, (scene, flags)) in cases.iter().enumerate() {
        let render = |extra: &[&str]| {
            let mut args = vec!["render", scene, "--resolution", "24x20", "-q"];
            args.extend_from_slice(flags);
            args.extend_from_slice(extra);
            let out = verity_in(&dir, &args);
            assert_success(&out, &format!("{args:?}"));
        };
        render(&["--out", "whole.exr"]);
        let whole = LayeredImage::read_exr(dir.join("whole.exr")).unwrap();
        for n in [1u32, 2, 3, 7] {
            let mut parts = Vec::new();
            for k in 1..=n {
                let name = format!("case{case}-{k}-of-{n}.vpart");
                render(&["--part", &format!("{k}/{n}"), "--out", &name]);
                parts.push(name);
            }
            parts.reverse();
            let mut args = vec!["merge"];
            args.extend(parts.iter().map(String::as_str));
            args.extend_from_slice(&["--out", "merged.exr"]);
            let out = verity_in(&dir, &args);
            assert_success(&out, &format!("merge of {n} parts"));
            let merged = LayeredImage::read_exr(dir.join("merged.exr")).unwrap();
            let what = format!("{scene} {flags:?}, {n} parts");
            assert_eq!(whole.channels.len(), merged.channels.len(), "{what}");
            for ((name, a), (name_b, b)) in whole.channels.iter().zip(&merged.channels) {
                assert_eq!(name, name_b, "{what}");
                let same = a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
                assert!(same, "{what}: channel {name} differs");
            }
            let header = |img: &LayeredImage| -> Vec<(String, String)> {
                let mut h: Vec<_> = img
                    .attributes
                    .iter()
                    .filter(|(k, _)| k != "seconds" && k != "command_line")
                    .cloned()
                    .collect();
                h.sort();
                h
            };
            assert_eq!(header(&whole), header(&merged), "{what}: header");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Merging refuses parts of another scene or settings, of another split, a missing or repeated
/// share, a truncated or foreign file; `--part` refuses a time or error target and a bad K/N.
/// Each is one line naming the file, exit 2, and no EXR is written.
#[test]
fn cli_merge_refuses_parts_that_do_not_make_one_render() {
    let dir = test_dir("merge-bad");
    let scene = cornell_box();
    // `--spp 4` unless `extra` gives it.
    let part = |name: &str, share: &str, extra: &[&str]| {
        let mut args = vec![
            "render",
            &scene,
            "--resolution",
            "12x10",
            "-q",
            "--part",
            share,
            "--out",
            name,
        ];
        if !extra.contains(&"--spp") {
            args.extend_from_slice(&["--spp", "4"]);
        }
        args.extend_from_slice(extra);
        verity_in(&dir, &args)
    };
    for (name, share, extra) in [
        ("a1.vpart", "1/2", &[][..]),
        ("a2.vpart", "2/2", &[]),
        ("seed.vpart", "2/2", &["--seed", "9"]),
        ("b1.vpart", "1/3", &[]),
        ("spp.vpart", "2/2", &["--spp", "8"]),
    ] {
        assert_success(&part(name, share, extra), name);
    }
    let bytes = std::fs::read(dir.join("a2.vpart")).unwrap();
    std::fs::write(dir.join("cut.vpart"), &bytes[..bytes.len() - 100]).unwrap();
    let mut flipped = bytes.clone();
    flipped[200] ^= 1;
    std::fs::write(dir.join("flipped.vpart"), flipped).unwrap();
    std::fs::write(dir.join("foreign.vpart"), b"not a part at all, just some bytes").unwrap();
    let merge = |parts: &[&str]| {
        let mut args = vec!["merge"];
        args.extend_from_slice(parts);
        args.extend_from_slice(&["--out", "m.exr"]);
        verity_in(&dir, &args)
    };
    for (parts, expected) in [
        (
            &["a1.vpart", "seed.vpart"][..],
            "seed.vpart: the scene, settings or oracle version differs from a1.vpart's",
        ),
        (
            &["a1.vpart", "b1.vpart"],
            "b1.vpart: the share count (3 against 2) differs",
        ),
        (
            &["a1.vpart", "spp.vpart"],
            "spp.vpart: the sample count (8 against 4 spp) differs",
        ),
        (&["a1.vpart"], "a1.vpart: the parts miss share 2/2 of this render"),
        (
            &["a1.vpart", "a2.vpart", "a1.vpart"],
            "a1.vpart: is share 1/2 again (also a1.vpart)",
        ),
        (&["a1.vpart", "cut.vpart"], "cut.vpart: is damaged or truncated"),
        (
            &["a1.vpart", "flipped.vpart"],
            "flipped.vpart: is damaged or truncated",
        ),
        (
            &["foreign.vpart", "a2.vpart"],
            "foreign.vpart: is not a Verity part (bad magic)",
        ),
        (&["a1.vpart", "missing.vpart"], "missing.vpart: cannot be read"),
    ] {
        let out = merge(parts);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{parts:?}: {stderr}");
        assert!(
            stderr.contains(expected),
            "{parts:?}: expected `{expected}` in: {stderr}"
        );
        assert_eq!(stderr.lines().count(), 1, "{parts:?}: one line: {stderr}");
    }
    assert!(!dir.join("m.exr").exists(), "a refused merge writes nothing");
    assert_success(&merge(&["a2.vpart", "a1.vpart"]), "the good pair");

    for (extra, expected) in [
        (
            &["--time", "5"][..],
            "--part: a part renders a fixed sample count and is not resumed; drop --time",
        ),
        (&["--target-error", "0.1"], "drop --target-error"),
    ] {
        let out = part("x.vpart", "1/2", extra);
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        assert!(text(&out.stderr).contains(expected), "{}", text(&out.stderr));
    }
    for bad in ["0/2", "3/2", "1/0", "half"] {
        let out = part("x.vpart", bad, &[]);
        assert_eq!(out.status.code(), Some(2), "--part {bad}");
        assert!(text(&out.stderr).contains("is not K/N"), "{}", text(&out.stderr));
    }
    let out = part("x.exr", "1/2", &[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("a part is written to a .vpart file"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// scripts/slurm/render-parts.sbatch, run as Slurm runs an array's tasks (the SLURM_ARRAY_*
/// variables of an array numbered 0-2), writes the three parts, whose merge is the single
/// render bit for bit.
#[test]
fn slurm_array_script_renders_the_parts_of_one_render() {
    let dir = test_dir("slurm");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/slurm/render-parts.sbatch");
    let scene = cornell_box();
    let flags = ["--resolution", "16x12", "--spp", "4"];
    for id in 0..3 {
        let out = Command::new("bash")
            .arg(&script)
            .args([scene.as_str(), "parts"])
            .args(flags)
            .current_dir(&dir)
            .env("VERITY", env!("CARGO_BIN_EXE_verity"))
            .env("SLURM_ARRAY_TASK_ID", id.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", "3")
            .env("SLURM_ARRAY_TASK_MIN", "0")
            .output()
            .unwrap();
        assert_success(&out, &format!("array task {id}"));
    }
    let out = Command::new("bash")
        .arg(&script)
        .args([scene.as_str(), "parts"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(1),
        "outside an array: {}",
        text(&out.stderr)
    );
    assert!(
        text(&out.stderr).contains("not an array task"),
        "{}",
        text(&out.stderr)
    );

    let mut args = vec!["render", &scene, "--out", "whole.exr", "-q"];
    args.extend_from_slice(&flags);
    assert_success(&verity_in(&dir, &args), "the single render");
    let parts: Vec<String> = (1..=3).map(|k| format!("parts/part-{k}-of-3.vpart")).collect();
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(String::as_str));
    args.extend_from_slice(&["--out", "merged.exr"]);
    assert_success(&verity_in(&dir, &args), "the merge");
    let (whole, merged) = (
        LayeredImage::read_exr(dir.join("whole.exr")).unwrap(),
        LayeredImage::read_exr(dir.join("merged.exr")).unwrap(),
    );
    let bits = |img: &LayeredImage| -> Vec<u32> {
        img.channels
            .iter()
            .flat_map(|(_, v)| v.iter().map(|x| x.to_bits()))
            .collect()
    };
    assert_eq!(
        bits(&whole),
        bits(&merged),
        "the merged parts are the single render"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--no-light-visibility` drops the `visibility.<light>.Y` layers and their shadow rays and
/// leaves every other layer bit for bit as it was (the visibility estimate draws from its own
/// sampler stream).
#[test]
fn cli_render_without_light_visibility_keeps_every_other_layer() {
    let dir = test_dir("no-light-visibility");
    let render = |extra: &[&str]| {
        let mut args = vec!["render", "--resolution", "24x20", "--spp", "8", "-q"];
        let scene = cornell_box();
        args.push(&scene);
        args.extend_from_slice(extra);
        let out = verity_in(&dir, &args);
        assert_success(&out, &format!("{args:?}"));
    };
    render(&["--out", "with.exr"]);
    render(&["--out", "without.exr", "--no-light-visibility"]);
    let with = LayeredImage::read_exr(dir.join("with.exr")).unwrap();
    let without = LayeredImage::read_exr(dir.join("without.exr")).unwrap();
    assert!(with.channel("visibility.light.Y").is_some());
    let mut kept = 0;
    for (name, a) in &with.channels {
        match without.channel(name) {
            Some(b) => {
                let same = a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
                assert!(same, "channel {name} differs without the visibility layers");
                kept += 1;
            }
            None => assert!(name.starts_with("visibility."), "{name} is missing"),
        }
    }
    assert_eq!(kept + 1, with.channels.len());
    assert_eq!(without.channels.len(), kept);
    let rays = |img: &LayeredImage| -> u64 {
        let v = img.attributes.iter().find(|(k, _)| k == "rays").unwrap();
        v.1.parse().unwrap()
    };
    // One shadow ray per camera sample that hits a surface fewer.
    assert!(
        rays(&without) < rays(&with),
        "{} !< {}",
        rays(&without),
        rays(&with)
    );
}

/// `--scattering multiple` renders every microfacet material with the random walk: a white
/// rough metal in a white furnace goes from single scattering's loss to 1, the header says so,
/// and a GGX material with separable masking (which the walk cannot have) is refused with one
/// line naming it (exit 2).
#[test]
fn cli_render_scattering_flag() {
    let dir = test_dir("scattering");
    let scene = "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 20\n\n[film]\nwidth = 16\nheight = 16\n\n\
                 [render]\nintegrator = \"direct\"\n\n[environment]\nradiance = 1\n\n\
                 [[material]]\nname = \"metal\"\ntype = \"metal_rough\"\nroughness = 1\n\n\
                 [[shape]]\nname = \"ball\"\ntype = \"sphere\"\nmaterial = \"metal\"\ncenter = [0, 0, 0]\nradius = 1\n";
    std::fs::write(dir.join("furnace.toml"), scene).unwrap();
    let mean_of = |flag: &str| -> (f64, String) {
        let out_name = format!("{flag}.exr");
        let args = [
            "render",
            "furnace.toml",
            "--spp",
            "64",
            "-q",
            "--scattering",
            flag,
            "--out",
            &out_name,
        ];
        let out = verity_in(&dir, &args);
        assert_success(&out, &format!("{args:?}"));
        let img = LayeredImage::read_exr(dir.join(&out_name)).unwrap();
        let r = img.channel("R").unwrap();
        // The 4×4 centre pixels: the ball seen head-on.
        let centre: Vec<f64> = (6..10)
            .flat_map(|y| (6..10).map(move |x| y * 16 + x))
            .map(|i| f64::from(r[i]))
            .collect();
        let header = img
            .attributes
            .iter()
            .find(|(k, _)| k == "scattering")
            .unwrap()
            .1
            .clone();
        (centre.iter().sum::<f64>() / centre.len() as f64, header)
    };
    let (single, h1) = mean_of("single");
    let (multiple, h2) = mean_of("multiple");
    // Single scattering at α = 1 keeps 1 − ln 2 ≈ 0.31 at normal incidence, more off-centre.
    assert!(single < 0.45, "single scattering {single}");
    assert!((multiple - 1.0).abs() < 0.03, "multiple scattering {multiple}");
    assert_eq!((h1.as_str(), h2.as_str()), ("single", "multiple"));
    let separable = scene.replace(
        "type = \"metal_rough\"\nroughness = 1",
        "type = \"ggx\"\nroughness = 1\nmasking = \"separable\"",
    );
    std::fs::write(dir.join("separable.toml"), separable).unwrap();
    let out = verity_in(
        &dir,
        &[
            "render",
            "separable.toml",
            "--spp",
            "1",
            "-q",
            "--scattering",
            "multiple",
        ],
    );
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--scattering multiple: material #0 (ggx) has separable masking")
            && stderr.trim().lines().count() == 1,
        "{stderr}"
    );
}
