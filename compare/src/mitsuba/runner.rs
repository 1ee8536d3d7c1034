//! Running Mitsuba 3: the project's venv Python executes `compare/python/render_mitsuba.py`
//! (embedded in the binary and passed with `python -c`, so an installed `verity` needs no
//! source tree) as a subprocess; the image comes back as an EXR, the timings as
//! `key=value` lines.
//!
//! Python is, in order: `$VERITY_PYTHON`; `.venv/bin/python` in the current directory or
//! the nearest ancestor that has one; the venv of the source tree `verity` was built from.
//! `scripts/setup.sh` creates that venv (mitsuba==3.9.1, numpy; compare/python/requirements.txt).
//! For `llvm_ad_rgb`, Dr.Jit needs LLVM's shared library: unless `DRJIT_LIBLLVM_PATH` is set,
//! it is pointed at Debian's `libllvm19` ([`LIBLLVM_PATH`]) when that exists.

use std::path::{Path, PathBuf};
use std::process::Command;

use scenes::layered::LayeredImage;

use super::export::MITSUBA_VERSION;

/// The render script, embedded.
const SCRIPT: &str = include_str!("../../python/render_mitsuba.py");

/// LLVM library of Debian's `libllvm19` package, used by the `llvm_ad_rgb` variant.
pub const LIBLLVM_PATH: &str = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1";

/// Most samples one Mitsuba pass may hold (W·H·spp): bounds the llvm variant's wavefront
/// memory (about 1 KiB of state per sample).
pub const MAX_SAMPLES_PER_PASS: u64 = 1 << 22;

/// Passes used for the variance estimate (its degrees of freedom are passes − 1).
pub const VARIANCE_PASSES: u32 = 64;

/// A Mitsuba 3 variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// `scalar_rgb`: one ray at a time per thread.
    ScalarRgb,
    /// `llvm_ad_rgb`: wavefront, JIT-compiled to vectorised CPU code by LLVM.
    LlvmAdRgb,
}

impl Variant {
    /// Mitsuba's name.
    pub fn name(self) -> &'static str {
        match self {
            Variant::ScalarRgb => "scalar_rgb",
            Variant::LlvmAdRgb => "llvm_ad_rgb",
        }
    }
}

/// Seconds spent in each phase of a Mitsuba run (measured inside Python).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// `import mitsuba` and `set_variant`.
    pub startup_s: f64,
    /// Parsing the XML and building the acceleration structure.
    pub load_s: f64,
    /// A 1-spp warm-up render: JIT compilation in llvm variants (or a hit in Dr.Jit's
    /// kernel cache, ~/.drjit).
    pub warmup_s: f64,
    /// The render itself, after the warm-up.
    pub render_s: f64,
}

/// A finished Mitsuba render.
#[derive(Clone, Debug)]
pub struct MitsubaRender {
    /// `R,G,B` mean and `variance.R/G/B` (variance of the mean; zero with one pass).
    pub image: LayeredImage,
    /// Samples per pixel.
    pub spp: u32,
    /// Independent passes behind the variance.
    pub passes: u32,
    /// Where the time went.
    pub timings: Timings,
}

/// Why Mitsuba could not produce an image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RunnerError {
    /// Mitsuba cannot be run here (no venv, wrong version, no LLVM): says what to install.
    Unavailable(String),
    /// Mitsuba ran and failed, or its output is unreadable.
    Failed(String),
}

impl std::fmt::Display for RunnerError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunnerError::Unavailable(m) | RunnerError::Failed(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for RunnerError {}

/// How to set Mitsuba up, for error messages.
pub const SETUP_HINT: &str = "run ./scripts/setup.sh (it installs Debian's libllvm19 and creates .venv with \
     mitsuba==3.9.1 and numpy from compare/python/requirements.txt), or point VERITY_PYTHON at a Python \
     that has them";

/// A located, working Mitsuba installation.
#[derive(Clone, Debug)]
pub struct Mitsuba {
    /// The Python interpreter.
    pub python: PathBuf,
    /// `mitsuba.__version__`.
    pub version: String,
}

impl Mitsuba {
    /// Finds Python and checks that it imports mitsuba 3.9.1 and numpy.
    pub fn locate() -> Result<Self, RunnerError> {
        let python = find_python().ok_or_else(|| {
            RunnerError::Unavailable(format!(
                "Mitsuba 3 cannot be run: no Python venv found (.venv/bin/python); {SETUP_HINT}"
            ))
        })?;
        let out = Command::new(&python)
            .args(["-c", "import numpy, mitsuba; print(mitsuba.__version__)"])
            .output()
            .map_err(|e| {
                RunnerError::Unavailable(format!(
                    "Mitsuba 3 cannot be run: {}: {e}; {SETUP_HINT}",
                    python.display()
                ))
            })?;
        if !out.status.success() {
            return Err(RunnerError::Unavailable(format!(
                "Mitsuba 3 cannot be run: {} cannot import mitsuba and numpy ({}); {SETUP_HINT}",
                python.display(),
                last_line(&out.stderr)
            )));
        }
        let version = String::from_utf8_lossy(&out.stdout).trim().to_string();
        if version != MITSUBA_VERSION {
            return Err(RunnerError::Unavailable(format!(
                "{} has mitsuba {version}, the exporter is checked against {MITSUBA_VERSION}; {SETUP_HINT}",
                python.display()
            )));
        }
        Ok(Mitsuba { python, version })
    }

    /// Renders `xml` with `spp` samples in `passes` independent passes (`spp` a multiple of
    /// `passes`; see [`plan_passes`]) and writes the EXR to `out`.
    pub fn render(
        &self,
        xml: &Path,
        variant: Variant,
        spp: u32,
        passes: u32,
        seed: u64,
        out: &Path,
    ) -> Result<MitsubaRender, RunnerError> {
        let mut cmd = Command::new(&self.python);
        cmd.arg("-c").arg(SCRIPT).arg(xml);
        cmd.args(["--variant", variant.name()]);
        cmd.args(["--spp", &spp.to_string(), "--passes", &passes.to_string()]);
        cmd.args(["--seed", &(seed % (1 << 20)).to_string()])
            .arg("--out")
            .arg(out);
        let llvm_missing = variant == Variant::LlvmAdRgb
            && std::env::var_os("DRJIT_LIBLLVM_PATH").is_none()
            && !Path::new(LIBLLVM_PATH).exists();
        if variant == Variant::LlvmAdRgb && std::env::var_os("DRJIT_LIBLLVM_PATH").is_none() && !llvm_missing
        {
            cmd.env("DRJIT_LIBLLVM_PATH", LIBLLVM_PATH);
        }
        let output = cmd
            .output()
            .map_err(|e| RunnerError::Unavailable(format!("{}: {e}; {SETUP_HINT}", self.python.display())))?;
        if !output.status.success() {
            let why = last_line(&output.stderr);
            if variant == Variant::LlvmAdRgb && (llvm_missing || why.to_lowercase().contains("llvm")) {
                return Err(RunnerError::Unavailable(format!(
                    "Mitsuba's llvm_ad_rgb variant cannot start ({why}): install Debian's libllvm19 \
                     ({LIBLLVM_PATH}) or set DRJIT_LIBLLVM_PATH; {SETUP_HINT}"
                )));
            }
            return Err(RunnerError::Failed(format!(
                "Mitsuba ({}) failed on {}: {why}",
                variant.name(),
                xml.display()
            )));
        }
        let stdout = String::from_utf8_lossy(&output.stdout);
        let value = |key: &str| -> Result<f64, RunnerError> {
            stdout
                .lines()
                .find_map(|l| l.strip_prefix(key)?.strip_prefix('='))
                .and_then(|v| v.trim().parse::<f64>().ok())
                .ok_or_else(|| {
                    RunnerError::Failed(format!("Mitsuba's render script printed no `{key}`:\n{stdout}"))
                })
        };
        let timings = Timings {
            startup_s: value("startup_s")?,
            load_s: value("load_s")?,
            warmup_s: value("warmup_s")?,
            render_s: value("render_s")?,
        };
        let image = LayeredImage::read_exr(out).map_err(RunnerError::Failed)?;
        Ok(MitsubaRender {
            image,
            spp,
            passes,
            timings,
        })
    }
}

/// Samples per pixel (rounded up) and passes for a W×H render of `spp` samples: at least
/// `min_passes` passes (capped at spp), and enough that no pass holds more than
/// [`MAX_SAMPLES_PER_PASS`] samples; spp is rounded up to a multiple of the passes.
pub fn plan_passes(width: u32, height: u32, spp: u32, min_passes: u32) -> (u32, u32) {
    let spp = spp.max(1);
    let samples = u64::from(width) * u64::from(height) * u64::from(spp);
    let for_memory = samples.div_ceil(MAX_SAMPLES_PER_PASS).min(u64::from(spp)) as u32;
    let passes = min_passes.min(spp).max(for_memory).max(1);
    (spp.div_ceil(passes) * passes, passes)
}

fn find_python() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("VERITY_PYTHON") {
        return Some(PathBuf::from(p));
    }
    let venv = |dir: &Path| dir.join(".venv/bin/python");
    if let Ok(cwd) = std::env::current_dir() {
        if let Some(p) = cwd.ancestors().map(venv).find(|p| p.exists()) {
            return Some(p);
        }
    }
    let built_from = venv(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")));
    built_from.exists().then_some(built_from)
}

/// The last non-empty line of a process's stderr (Python prints `error: …` there).
fn last_line(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    text.lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("no message")
        .trim()
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_divide_spp_and_bound_memory() {
        assert_eq!(plan_passes(64, 64, 256, 64), (256, 64));
        assert_eq!(plan_passes(64, 64, 100, 64), (128, 64));
        assert_eq!(plan_passes(64, 64, 8, 64), (8, 8));
        assert_eq!(plan_passes(64, 64, 256, 1), (256, 1));
        // 1024² × 64 spp = 2^26 samples: 16 passes of 2^22.
        assert_eq!(plan_passes(1024, 1024, 64, 1), (64, 16));
        // 1024² × 50 spp: 13 passes of 4 spp (2^22 samples each); spp rounds up to 52.
        assert_eq!(plan_passes(1024, 1024, 50, 1), (52, 13));
    }
}
