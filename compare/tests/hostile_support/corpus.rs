//! The checked-in reproducers of issue 19 (`tests/hostile/`, listed in
//! `tests/hostile/manifest.rs`): each case copies its files into a folder of its own, makes
//! what is generated (EXRs, a FIFO, large glTF and study files, corrupted checkpoints), runs
//! one `verity` command and checks the exit status and the single error line's content.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use scenes::layered::LayeredImage;

use super::judge::error_lines;
use super::process::{self, Ending};
use super::{exr, family};

/// A generated input.
#[derive(Clone, Copy, Debug)]
pub enum Make {
    /// `big.exr`: the 33 KB EXR whose header declares 65536×65536 pixels.
    HugeExr,
    /// A 4×4 RGB EXR of 0.5 everywhere but pixel 0, which holds the value given.
    Exr4x4(&'static str, f32),
    /// `fifo`, a FIFO (reading it blocks forever).
    Fifo,
    /// `prims.gltf` with `prims.bin`: this many one-triangle primitives in one mesh.
    Primitives(usize),
    /// `grid.toml`: a study whose method sweeps 64 × 1000 × 64 parameter values.
    GridStudy,
    /// `sweep.toml`: a study whose `[scene_sweep]` has 1000 values.
    SceneSweep1000,
    /// `k.exr.checkpoint` of a 2×2 render of `cornell-box.toml` (killed after its first
    /// checkpoint), then corrupted.
    Checkpoint(Corrupt),
}

/// How a checkpoint is corrupted.
#[derive(Clone, Copy, Debug)]
pub enum Corrupt {
    /// Left intact (the control: it must resume).
    Intact,
    /// The byte at `len × num / den` (clamped to the last) XORed with 0x01.
    Flip(usize, usize),
    /// The byte at this offset XORed with 0x01.
    FlipByte(usize),
    /// Cut to half its length.
    Truncate,
}

/// One reproducer.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    /// Its name (the case folder's).
    pub name: &'static str,
    /// Files of `tests/hostile/` copied into the case folder, with [`Case::subst`] applied.
    pub files: &'static [&'static str],
    /// Built-in files, relative to `scenes/`, copied into the case folder by file name.
    pub builtins: &'static [&'static str],
    /// Generated inputs.
    pub make: &'static [Make],
    /// `(placeholder, value)` replacements in the copied files. In values, `{UP}` is as many
    /// `../` as the case folder is deep (so a `..` escape really reaches `/`), `{UPENC}` the
    /// same percent-encoded, `{DIR}` the case folder.
    pub subst: &'static [(&'static str, &'static str)],
    /// `verity`'s arguments (`{DIR}` is the case folder).
    pub args: &'static [&'static str],
    /// The expected exit status.
    pub status: i32,
    /// Substrings of the one `error:` line; empty: there must be no error line.
    pub error: &'static [&'static str],
    /// Substrings stdout must contain.
    pub stdout: &'static [&'static str],
    /// Substrings neither stdout nor stderr may contain.
    pub absent: &'static [&'static str],
    /// The process timeout in seconds (a hang detector; 0: [`process::TIMEOUT`]).
    pub timeout_s: u64,
}

/// The defaults for [`Case`] literals (`Case { name, args, …, ..BASE }`).
pub const BASE: Case = Case {
    name: "",
    files: &[],
    builtins: &[],
    make: &[],
    subst: &[],
    args: &[],
    status: 2,
    error: &[],
    stdout: &[],
    absent: &[],
    timeout_s: 0,
};

/// `tests/hostile/`.
fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hostile")
}

/// Replaces the placeholders of `value` for `dir`.
fn expand(value: &str, dir: &Path) -> String {
    let depth = dir.components().count();
    value
        .replace("{UPENC}", &"%2e%2e/".repeat(depth))
        .replace("{UP}", &"../".repeat(depth))
        .replace("{DIR}", &dir.display().to_string())
}

/// A 4×4 RGB image of 0.5 with `first` at pixel 0.
fn exr4x4(path: &Path, first: f32) {
    let mut img = LayeredImage::new(4, 4);
    for c in ["R", "G", "B"] {
        let mut v = vec![0.5; 16];
        v[0] = first;
        img.push_channel(c, v);
    }
    img.write_exr(path).unwrap_or_else(|e| panic!("{e}"));
}

/// `prims.gltf` + `prims.bin`: `n` one-triangle primitives, each with its own accessor.
fn primitives(dir: &Path, n: usize) {
    let mut bin = Vec::with_capacity(36 * n);
    for i in 0..n {
        let x = (i % 200) as f32 * 0.01 - 1.0;
        let y = (i / 200) as f32 * 0.01 - 0.5;
        for v in [x, y, 0.0, x + 0.01, y, 0.0, x, y + 0.01, 0.0] {
            bin.extend_from_slice(&v.to_le_bytes());
        }
    }
    std::fs::write(dir.join("prims.bin"), &bin).unwrap_or_else(|e| panic!("{e}"));
    let prims: Vec<String> = (0..n)
        .map(|i| format!(r#"{{"attributes":{{"POSITION":{i}}}}}"#))
        .collect();
    let accessors: Vec<String> = (0..n)
        .map(|i| {
            let x = (i % 200) as f32 * 0.01 - 1.0;
            let y = (i / 200) as f32 * 0.01 - 0.5;
            format!(
                r#"{{"bufferView":0,"byteOffset":{},"componentType":5126,"count":3,"type":"VEC3","min":[{x},{y},0],"max":[{},{},0]}}"#,
                36 * i,
                x + 0.01,
                y + 0.01
            )
        })
        .collect();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{}]}}],
"buffers":[{{"byteLength":{},"uri":"prims.bin"}}],
"bufferViews":[{{"buffer":0,"byteLength":{}}}],
"accessors":[{}]}}"#,
        prims.join(","),
        bin.len(),
        bin.len(),
        accessors.join(",\n")
    );
    std::fs::write(dir.join("prims.gltf"), json).unwrap_or_else(|e| panic!("{e}"));
}

/// `count` distinct values from `from` in steps of `step`, as a TOML array.
fn values(count: usize, from: f64, step: f64) -> String {
    let v: Vec<String> = (0..count)
        .map(|i| format!("{}", from + step * i as f64))
        .collect();
    format!("[{}]", v.join(", "))
}

/// The head of a generated study over `soft-shadow.toml`.
const STUDY_HEAD: &str = "scene = \"soft-shadow.toml\"\n\n[ground_truth]\nintegrator = \"direct\"\nspp = 4\nresolution = [16, 16]\n";

/// `k.exr.checkpoint` in `dir`: a 2×2 render with checkpoints every 50 ms, killed once the
/// first is written (as a user's interrupted render).
fn checkpoint(dir: &Path) -> PathBuf {
    let path = dir.join("k.exr.checkpoint");
    let mut child = Command::new(env!("CARGO_BIN_EXE_verity"))
        .args(CHECKPOINTED)
        .args(["--spp", "100000000", "--checkpoint-every", "0.05"])
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| panic!("start verity: {e}"));
    let start = Instant::now();
    while !path.exists() {
        if let Ok(Some(status)) = child.try_wait() {
            panic!("the render ended ({status}) before writing a checkpoint");
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no checkpoint after 120 s"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    // The checkpoint is renamed into place whole (compare/README.md "Checkpoints").
    let _ = child.kill();
    let _ = child.wait();
    path
}

/// The render whose checkpoints the checkpoint cases corrupt; they resume it with
/// `--resume --time 0.001` (stop at once: the checkpoint's samples).
pub const CHECKPOINTED: &[&str] = &[
    "render",
    "cornell-box.toml",
    "--resolution",
    "2x2",
    "-q",
    "--out",
    "k.exr",
];

/// Makes `what` in `dir`.
fn make(what: Make, dir: &Path) {
    match what {
        Make::HugeExr => exr::declared_huge(&dir.join("big.exr"), 65536),
        Make::Exr4x4(name, first) => exr4x4(&dir.join(name), first),
        Make::Fifo => family::make_fifo(dir),
        Make::Primitives(n) => primitives(dir, n),
        Make::GridStudy => {
            let text = format!(
                "{STUDY_HEAD}\n[[method]]\nname = \"shadow_hard\"\nsweep = {{ bias = {}, slope_bias = {}, normal_offset = {} }}\n\n[[threshold]]\nmethod = \"shadow_hard\"\nmetric = \"relmse\"\nmax = 1.0\nreason = \"r\"\n",
                values(64, 0.001, 0.001),
                values(1000, 0.01, 0.01),
                values(64, 0.01, 0.01)
            );
            std::fs::write(dir.join("grid.toml"), text).unwrap_or_else(|e| panic!("{e}"));
        }
        Make::SceneSweep1000 => {
            // At the resolution of the built-in studies' full runs (at 16² a thousand scene
            // points fit in half a gigabyte, and the run is merely long).
            let head = STUDY_HEAD.replace("resolution = [16, 16]", "resolution = [256, 256]");
            let text = format!(
                "{head}\n[scene_sweep]\nname = \"light_size\"\nset = \"shape.light.size[0]\"\nvalues = {}\n\n[[method]]\nname = \"area_quadrature\"\nparams = {{ n = 4 }}\n\n[[threshold]]\nmethod = \"area_quadrature\"\nmetric = \"relmse\"\nmax = 1.0\nreason = \"r\"\n",
                values(1000, 0.1, 0.001)
            );
            std::fs::write(dir.join("sweep.toml"), text).unwrap_or_else(|e| panic!("{e}"));
        }
        Make::Checkpoint(corrupt) => {
            let path = checkpoint(dir);
            let mut bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{e}"));
            match corrupt {
                Corrupt::Intact => {}
                Corrupt::Flip(num, den) => {
                    let at = (bytes.len() * num / den).min(bytes.len() - 1);
                    bytes[at] ^= 0x01;
                }
                Corrupt::FlipByte(at) => {
                    let at = at.min(bytes.len() - 1);
                    bytes[at] ^= 0x01;
                }
                Corrupt::Truncate => bytes.truncate(bytes.len() / 2),
            }
            std::fs::write(&path, bytes).unwrap_or_else(|e| panic!("{e}"));
        }
    }
}

/// Runs `case`; `Err` says what is wrong.
fn run_case(case: &Case) -> Result<(), String> {
    let dir = family::fresh_dir(&["hostile-corpus", case.name]);
    for file in case.files {
        let mut text =
            std::fs::read_to_string(corpus_dir().join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        for (from, to) in case.subst {
            text = text.replace(from, &expand(to, &dir));
        }
        std::fs::write(dir.join(file), text).unwrap_or_else(|e| panic!("{e}"));
    }
    for builtin in case.builtins {
        let from = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../scenes")
            .join(builtin);
        let name = Path::new(builtin).file_name().unwrap_or_default();
        std::fs::copy(&from, dir.join(name)).unwrap_or_else(|e| panic!("{}: {e}", from.display()));
    }
    for &m in case.make {
        make(m, &dir);
    }
    let args: Vec<OsString> = case
        .args
        .iter()
        .map(|a| OsString::from(expand(a, &dir)))
        .collect();
    let timeout = match case.timeout_s {
        0 => process::TIMEOUT,
        s => Duration::from_secs(s),
    };
    let run = process::verity(&dir, &dir.join("verity"), &args, timeout);
    let context = || {
        format!(
            "\n    command: {}\n    stdout: {}\n    stderr: {}",
            process::describe(&dir, &args),
            run.stdout.lines().take(6).collect::<Vec<_>>().join(" | "),
            run.stderr.lines().take(6).collect::<Vec<_>>().join(" | ")
        )
    };
    let fail = |why: String| Err(format!("{}: {why}{}", case.name, context()));
    let code = match run.ending {
        Ending::Exit(code) => code,
        Ending::Signal(s) => return fail(format!("killed by signal {s}")),
        Ending::Timeout => return fail(format!("still running after {} s (a hang)", timeout.as_secs())),
    };
    let errors = match error_lines(&run.stderr) {
        Ok(e) => e,
        Err(why) => return fail(why),
    };
    if code != case.status {
        return fail(format!("exit {code}, expected {}", case.status));
    }
    match (case.error.is_empty(), errors.as_slice()) {
        (true, []) => {}
        (true, [first, ..]) => return fail(format!("an error line where none was expected: {first}")),
        (false, [line]) => {
            let missing: Vec<&&str> = case.error.iter().filter(|s| !line.contains(**s)).collect();
            if !missing.is_empty() {
                return fail(format!("the error line lacks {missing:?}: {line}"));
            }
        }
        (false, lines) => return fail(format!("{} `error:` lines, expected exactly one", lines.len())),
    }
    if let Some(s) = case.stdout.iter().find(|s| !run.stdout.contains(**s)) {
        return fail(format!("stdout lacks {s:?}"));
    }
    if let Some(s) = case
        .absent
        .iter()
        .find(|s| run.stdout.contains(**s) || run.stderr.contains(**s))
    {
        return fail(format!("the output contains {s:?}"));
    }
    Ok(())
}

/// Runs every case (on all cores) and panics with the list of those that fail.
pub fn run(cases: &[Case]) {
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..process::slots() {
            s.spawn(|| {
                while let Some(case) = cases.get(next.fetch_add(1, Ordering::Relaxed)) {
                    if let Err(why) = run_case(case) {
                        failures.lock().unwrap_or_else(|e| e.into_inner()).push(why);
                    }
                }
            });
        }
    });
    let mut failures = failures.into_inner().unwrap_or_else(|e| e.into_inner());
    failures.sort();
    println!(
        "hostile reproducers: {} cases, {} as expected, {} not",
        cases.len(),
        cases.len() - failures.len(),
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} of {} reproducers do not give the expected answer:\n\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n\n")
    );
}
