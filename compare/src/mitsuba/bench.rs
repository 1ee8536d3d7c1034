//! Time to equal error: the oracle against Mitsuba 3 (`llvm_ad_rgb` and `scalar_rgb`) on the
//! same scene and machine (docs/ARCHITECTURE.md "Quality bar").
//!
//! 1. A reference: Mitsuba `llvm_ad_rgb` (the fastest here) at a high sample count, in 64
//!    independent passes so that its own noise is known per pixel.
//! 2. The oracle at N spp (its own sampler, as `verity render` uses it): its relMSE against
//!    the reference is the target error E, its render time the oracle's time to E.
//! 3. Each Mitsuba variant: a pilot render at N/8 spp gives its relMSE; since relMSE ∝ 1/spp
//!    for independent samples, E needs spp = pilot spp × pilot relMSE / E; that render's time
//!    t and relMSE e give the time to E as t·e/E (a small first-order correction, t ∝ spp).
//!
//! Every relMSE has the reference's own noise subtracted: mean of σ²_ref/(ref² + 0.01), the
//! part of (x − ref)²/(ref² + 0.01) the reference's noise contributes (docs/ARCHITECTURE.md "Comparison").
//! Render times exclude start-up; Mitsuba's start-up (import, variant), scene load and warm-up
//! (the 1-spp render that JIT-compiles the llvm kernels) are reported separately.

use std::path::PathBuf;

use glam::Vec3;
use scenes::Scene;

use super::crosscheck::{render_oracle, CrossCheckError};
use super::export;
use super::runner::{plan_passes, Mitsuba, MitsubaRender, RunnerError, Timings, Variant, VARIANCE_PASSES};
use super::ztest::relmse;

/// What to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchOptions {
    /// The oracle's samples per pixel; its error is the target.
    pub spp: u32,
    /// Samples per pixel of the reference.
    pub reference_spp: u32,
    /// Directory for the export and the EXRs.
    pub out_dir: PathBuf,
    /// Print a line per stage on stderr.
    pub verbose: bool,
}

/// One renderer's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// `oracle`, `mitsuba llvm_ad_rgb`, `mitsuba scalar_rgb`.
    pub renderer: String,
    /// Samples per pixel of the timed render.
    pub spp: u32,
    /// Its relMSE against the reference, reference noise removed.
    pub relmse: f64,
    /// Its render time in seconds.
    pub render_s: f64,
    /// Estimated seconds to reach the target relMSE.
    pub time_to_target_s: f64,
    /// Mitsuba's start-up, load and warm-up (none for the oracle, which runs in-process).
    pub overhead: Option<Timings>,
}

/// The benchmark's figures.
#[derive(Clone, Debug, PartialEq)]
pub struct Bench {
    /// The target relMSE (the oracle's at `spp`).
    pub target_relmse: f64,
    /// The reference's own noise, as relMSE.
    pub reference_noise: f64,
    /// Samples per pixel of the reference.
    pub reference_spp: u32,
    /// Oracle first, then `llvm_ad_rgb`, then `scalar_rgb`.
    pub entries: Vec<Entry>,
}

/// Runs the benchmark on `scene` at its film size.
pub fn bench(scene: &Scene, opts: &BenchOptions) -> Result<Bench, CrossCheckError> {
    let note = |s: String| {
        if opts.verbose {
            eprintln!("{s}");
        }
    };
    let (w, h) = (scene.film.width, scene.film.height);
    let exported = export::export(scene).map_err(CrossCheckError::NotExpressible)?;
    let mitsuba = Mitsuba::locate().map_err(CrossCheckError::Mitsuba)?;
    let xml = exported
        .write(&opts.out_dir.join("mitsuba"))
        .map_err(|e| CrossCheckError::Io(e.to_string()))?;
    let render_mitsuba = |variant: Variant, spp: u32, min_passes: u32, seed: u64, name: &str| {
        let (spp, passes) = plan_passes(w, h, spp, min_passes);
        note(format!(
            "bench: Mitsuba {} {w}x{h}, {spp} spp ({name})",
            variant.name()
        ));
        mitsuba
            .render(
                &xml,
                variant,
                spp,
                passes,
                seed,
                &opts.out_dir.join(format!("{name}.exr")),
            )
            .map_err(CrossCheckError::Mitsuba)
    };

    let reference = render_mitsuba(
        Variant::LlvmAdRgb,
        opts.reference_spp,
        VARIANCE_PASSES,
        1000,
        "reference",
    )?;
    let ref_rgb = rgb(&reference)?;
    let ref_var = reference.image.rgb("variance").ok_or_else(|| {
        CrossCheckError::Mitsuba(RunnerError::Failed("the reference has no variance".into()))
    })?;
    let reference_noise = noise_relmse(&ref_rgb, &ref_var);
    let error = |img: &[Vec3]| (relmse(img, &ref_rgb) - reference_noise).max(1e-12);

    note(format!("bench: oracle {w}x{h}, {} spp", opts.spp));
    let (oracle_img, oracle_s) = render_oracle(scene, w, h, opts.spp, scene.render.sampler)?;
    let oracle_rgb = oracle_img
        .rgb("")
        .ok_or_else(|| CrossCheckError::Oracle("the oracle's image has no R, G, B".into()))?;
    let target = error(&oracle_rgb);
    let mut entries = vec![Entry {
        renderer: "oracle".into(),
        spp: opts.spp,
        relmse: target,
        render_s: oracle_s,
        time_to_target_s: oracle_s,
        overhead: None,
    }];

    for variant in [Variant::LlvmAdRgb, Variant::ScalarRgb] {
        let pilot_spp = (opts.spp / 8).max(4);
        let pilot = render_mitsuba(variant, pilot_spp, 1, 2000, &format!("{}-pilot", variant.name()))?;
        let pilot_err = error(&rgb(&pilot)?);
        let spp = ((f64::from(pilot.spp) * pilot_err / target).ceil() as u32).clamp(1, 1 << 20);
        let timed = render_mitsuba(variant, spp, 1, 3000, variant.name())?;
        let e = error(&rgb(&timed)?);
        entries.push(Entry {
            renderer: format!("mitsuba {}", variant.name()),
            spp: timed.spp,
            relmse: e,
            render_s: timed.timings.render_s,
            time_to_target_s: timed.timings.render_s * e / target,
            overhead: Some(timed.timings),
        });
    }
    Ok(Bench {
        target_relmse: target,
        reference_noise,
        reference_spp: reference.spp,
        entries,
    })
}

fn rgb(r: &MitsubaRender) -> Result<Vec<Vec3>, CrossCheckError> {
    r.image
        .rgb("")
        .ok_or_else(|| CrossCheckError::Mitsuba(RunnerError::Failed("Mitsuba's image has no R, G, B".into())))
}

/// The relMSE the reference's own noise adds: mean of σ²/(ref² + 0.01).
fn noise_relmse(reference: &[Vec3], variance: &[Vec3]) -> f64 {
    let n = reference.len().max(1) as f64;
    let total: f64 = reference
        .iter()
        .zip(variance)
        .flat_map(|(r, v)| (0..3).map(move |c| f64::from(v[c]) / (f64::from(r[c]).powi(2) + 0.01)))
        .sum();
    total / (3.0 * n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_noise_is_the_variance_term_of_relmse() {
        // σ² = 0.01 at r = 0.3: 0.01/(0.09 + 0.01) = 0.1.
        let got = noise_relmse(&[Vec3::splat(0.3)], &[Vec3::splat(0.01)]);
        assert!((got - 0.1).abs() < 1e-7, "expected 0.1, got {got}");
    }
}
