//! `verity export-mitsuba`, `verity crosscheck` and `verity bench --vs-mitsuba` end to end:
//! files written, verdict printed, exit statuses (0 agree, 1 disagree, 2 bad input or not
//! expressible, 3 Mitsuba cannot be run).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn verity(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_verity"));
    cmd.args(args).current_dir(dir);
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("run verity")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn test_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("mitsuba-cli-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn builtin(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/{name}.toml"));
    path.canonicalize().unwrap_or(path).display().to_string()
}

fn assert_status(out: &Output, code: i32, what: &str) {
    assert_eq!(
        out.status.code(),
        Some(code),
        "{what}: expected exit {code}\nstdout:\n{}\nstderr:\n{}",
        text(&out.stdout),
        text(&out.stderr)
    );
}

const PHONG_SCENE: &str = r#"
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40

[[material]]
name = "shiny"
type = "phong"
reflectance = [0.5, 0.5, 0.5]
exponent = 20

[[shape]]
name = "ball"
type = "sphere"
material = "shiny"
center = [0, 0, 0]
radius = 1
"#;

#[test]
fn export_writes_the_scene_and_its_meshes() {
    let dir = test_dir("export");
    let out = verity(
        &dir,
        &[
            "export-mitsuba",
            &builtin("cornell-box"),
            "--out",
            "cb",
            "--spp",
            "32",
        ],
        &[],
    );
    assert_status(&out, 0, "export-mitsuba");
    let xml = std::fs::read_to_string(dir.join("cb/scene.xml")).expect("scene.xml written");
    assert!(
        xml.contains(r#"<integer name="sample_count" value="32"/>"#),
        "{xml}"
    );
    for mesh in ["cb/meshes/5-short_block.ply", "cb/meshes/6-tall_block.ply"] {
        assert!(dir.join(mesh).is_file(), "{mesh} not written");
    }
    assert!(
        text(&out.stdout).starts_with("exported "),
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn a_scene_mitsuba_cannot_express_is_bad_input() {
    let dir = test_dir("phong");
    std::fs::write(dir.join("phong.toml"), PHONG_SCENE).unwrap();
    for cmd in [
        &["export-mitsuba", "phong.toml"][..],
        &["crosscheck", "phong.toml"][..],
    ] {
        let out = verity(&dir, cmd, &[]);
        assert_status(&out, 2, cmd[0]);
        let err = text(&out.stderr);
        assert!(
            err.starts_with("error: phong.toml: Mitsuba 3 cannot express this scene exactly: material #0 (phong, used by `ball`)"),
            "{err}"
        );
    }
}

#[test]
fn crosscheck_agrees_and_writes_its_page() {
    let dir = test_dir("crosscheck");
    let out = verity(
        &dir,
        &[
            "crosscheck",
            &builtin("soft-shadow"),
            "--resolution",
            "24x16",
            "--spp",
            "64",
            "--out",
            "cc",
            "-q",
        ],
        &[],
    );
    assert_status(&out, 0, "crosscheck soft-shadow");
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains(": AGREE — ") && stdout.contains("relMSE oracle vs Mitsuba"),
        "{stdout}"
    );
    for f in [
        "cc/oracle.exr",
        "cc/mitsuba.exr",
        "cc/pvalue.png",
        "cc/mitsuba/scene.xml",
    ] {
        assert!(dir.join(f).is_file(), "{f} not written");
    }
    let html = std::fs::read_to_string(dir.join("cc/index.html")).expect("index.html");
    assert_eq!(
        html.matches("src=\"data:image/png;base64,").count(),
        3,
        "three embedded images"
    );
    assert!(html.contains("AGREE"));
}

#[test]
fn crosscheck_without_mitsuba_exits_3_and_says_what_to_install() {
    let dir = test_dir("no-python");
    let out = verity(
        &dir,
        &[
            "crosscheck",
            &builtin("soft-shadow"),
            "--resolution",
            "8x8",
            "--spp",
            "4",
        ],
        &[("VERITY_PYTHON", "/nonexistent/python")],
    );
    assert_status(&out, 3, "crosscheck without Python");
    let err = text(&out.stderr);
    assert!(
        err.contains("scripts/setup.sh") && err.contains("mitsuba==3.9.1"),
        "{err}"
    );
}

#[test]
fn bench_needs_vs_mitsuba_and_prints_ratios() {
    let dir = test_dir("bench");
    let out = verity(&dir, &["bench", &builtin("soft-shadow")], &[]);
    assert_status(&out, 2, "bench without --vs-mitsuba");
    assert!(text(&out.stderr).contains("--vs-mitsuba"));

    let out = verity(
        &dir,
        &[
            "bench",
            "--vs-mitsuba",
            &builtin("soft-shadow"),
            "--resolution",
            "16x16",
            "--spp",
            "16",
            "-q",
        ],
        &[],
    );
    assert_status(&out, 0, "bench --vs-mitsuba");
    let stdout = text(&out.stdout);
    for needle in [
        "oracle ",
        "mitsuba llvm_ad_rgb ",
        "mitsuba scalar_rgb ",
        "time to equal error: mitsuba llvm_ad_rgb / oracle = ",
    ] {
        assert!(stdout.contains(needle), "`{needle}` missing in\n{stdout}");
    }
}
