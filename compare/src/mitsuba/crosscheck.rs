//! One cross-check: export a scene, render it with Mitsuba and with the oracle at the same
//! sample count, and z-test the two images ([`super::ztest`]).
//!
//! Both per-pixel variances are unbiased estimates of the variance of the pixel mean: Mitsuba's
//! from its independent passes, the oracle's (with its default scrambled Sobol sampler) from
//! its independent replicates; the test refers them to Student's t ([`super::ztest`]).
//! The oracle may render a different in-memory scene than the one exported (the tests
//! perturb it to prove the test fails); normally both are the same.

use std::path::PathBuf;

use oracle::{RenderJob, StopRule};
use scenes::layered::LayeredImage;
use scenes::{SamplerKind, Scene};

use super::export::{self, NotExpressible};
use super::runner::{plan_passes, Mitsuba, MitsubaRender, RunnerError, Variant, VARIANCE_PASSES};
use super::ztest::{z_test, Estimate, ZTestConfig, ZTestResult};

/// What to render.
#[derive(Clone, Debug, PartialEq)]
pub struct CrossCheckOptions {
    /// Samples per pixel for both renderers (rounded up to a multiple of Mitsuba's passes).
    pub spp: u32,
    /// Mitsuba variant.
    pub variant: Variant,
    /// Directory for the export (`mitsuba/`) and the two EXRs.
    pub out_dir: PathBuf,
    /// Print a line per stage on stderr.
    pub verbose: bool,
}

/// A finished cross-check.
#[derive(Clone, Debug)]
pub struct CrossCheck {
    /// The verdict and its figures (oracle tested against Mitsuba).
    pub ztest: ZTestResult,
    /// The oracle's image (`R,G,B`, `variance.*`, AOVs).
    pub oracle: LayeredImage,
    /// The oracle's render time in seconds.
    pub oracle_seconds: f64,
    /// Mitsuba's render.
    pub mitsuba: MitsubaRender,
    /// Samples per pixel of both renders.
    pub spp: u32,
    /// Where the oracle's EXR went.
    pub oracle_exr: PathBuf,
    /// Where Mitsuba's EXR went.
    pub mitsuba_exr: PathBuf,
    /// The exported scene file.
    pub scene_xml: PathBuf,
}

/// Why a cross-check could not be made (a disagreement is not an error: see
/// [`ZTestResult::pass`]).
#[derive(Debug)]
pub enum CrossCheckError {
    /// The scene has features Mitsuba 3 cannot express.
    NotExpressible(NotExpressible),
    /// Mitsuba cannot be run, or failed.
    Mitsuba(RunnerError),
    /// The oracle failed.
    Oracle(String),
    /// Writing the outputs failed.
    Io(String),
}

impl std::fmt::Display for CrossCheckError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CrossCheckError::NotExpressible(e) => write!(f, "{e}"),
            CrossCheckError::Mitsuba(e) => write!(f, "{e}"),
            CrossCheckError::Oracle(m) | CrossCheckError::Io(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for CrossCheckError {}

/// Exports `scene`, renders it with Mitsuba and `oracle_scene` with the oracle (the same
/// scene unless a test perturbs it), both at `opts.spp` with the scene's settings, and
/// tests the oracle against Mitsuba.
pub fn crosscheck(
    scene: &Scene,
    oracle_scene: &Scene,
    opts: &CrossCheckOptions,
) -> Result<CrossCheck, CrossCheckError> {
    let note = |s: String| {
        if opts.verbose {
            eprintln!("{s}");
        }
    };
    let (w, h) = (scene.film.width, scene.film.height);
    let (spp, passes) = plan_passes(w, h, opts.spp, VARIANCE_PASSES);
    let mut scene = scene.clone();
    scene.render.spp = spp;
    let exported = export::export(&scene).map_err(CrossCheckError::NotExpressible)?;
    // Fail early, before the oracle's render, when Mitsuba cannot run here.
    let mitsuba = Mitsuba::locate().map_err(CrossCheckError::Mitsuba)?;
    let io = |e: std::io::Error| CrossCheckError::Io(e.to_string());
    let scene_xml = exported.write(&opts.out_dir.join("mitsuba")).map_err(io)?;

    note(format!(
        "crosscheck: Mitsuba {} {}: {w}x{h}, {spp} spp in {passes} passes",
        mitsuba.version,
        opts.variant.name()
    ));
    let mitsuba_exr = opts.out_dir.join("mitsuba.exr");
    let m = mitsuba
        .render(
            &scene_xml,
            opts.variant,
            spp,
            passes,
            scene.render.seed,
            &mitsuba_exr,
        )
        .map_err(CrossCheckError::Mitsuba)?;
    note(format!(
        "crosscheck: Mitsuba took {:.2} s (+ {:.2} s startup, {:.2} s load, {:.2} s warm-up)",
        m.timings.render_s, m.timings.startup_s, m.timings.load_s, m.timings.warmup_s
    ));

    note(format!("crosscheck: oracle: {w}x{h}, {spp} spp"));
    // The oracle's default sampler: its variance of the mean comes from independent replicates
    // (oracle/src/sampler.rs), unbiased for scrambled Sobol points too, so the test is as
    // strong as the oracle's own noise allows.
    let (oracle, oracle_seconds) = render_oracle(oracle_scene, w, h, spp, oracle_scene.render.sampler)?;
    let oracle_exr = opts.out_dir.join("oracle.exr");
    oracle.write_exr(&oracle_exr).map_err(io)?;
    note(format!("crosscheck: oracle took {oracle_seconds:.2} s"));

    let a = Estimate::from_oracle(&oracle, spp)
        .map_err(|e| CrossCheckError::Oracle(format!("oracle image: {e}")))?;
    let b = Estimate::from_layered(&m.image, spp, m.passes.saturating_sub(1)).map_err(|e| {
        CrossCheckError::Mitsuba(RunnerError::Failed(format!("{}: {e}", mitsuba_exr.display())))
    })?;
    let ztest = z_test(&a, &b, &ZTestConfig::default()).map_err(|e| {
        CrossCheckError::Mitsuba(RunnerError::Failed(format!("{}: {e}", mitsuba_exr.display())))
    })?;
    Ok(CrossCheck {
        ztest,
        oracle,
        oracle_seconds,
        mitsuba: m,
        spp,
        oracle_exr,
        mitsuba_exr,
        scene_xml,
    })
}

/// Renders `scene` with the oracle at W×H and `spp` with the `sampler` given and the scene's
/// other settings, and what Mitsuba renders: no per-light visibility layers
/// ([`RenderJob::light_visibility`] off); returns the image and the render time.
pub fn render_oracle(
    scene: &Scene,
    w: u32,
    h: u32,
    spp: u32,
    sampler: SamplerKind,
) -> Result<(LayeredImage, f64), CrossCheckError> {
    let mut scene = scene.clone();
    scene.film.width = w;
    scene.film.height = h;
    scene.render.sampler = sampler;
    let job = RenderJob {
        light_visibility: false,
        scene: &scene,
        settings: scene.render,
        stop: StopRule {
            spp,
            time: None,
            target_rel_err: None,
        },
        checkpoint: None,
    };
    let result = oracle::render(&job, &mut |_| true)
        .map_err(|e| CrossCheckError::Oracle(format!("oracle on {}: {e}", scene.source.display())))?;
    Ok((result.image, result.seconds))
}
