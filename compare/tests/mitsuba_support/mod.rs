//! Shared by the `mitsuba_*` tests: the built-in scenes and one cross-check with its figures
//! printed (`cargo test -- --nocapture` shows them; a failure always does).

// Each test file compiles this module on its own and uses a subset of it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use compare::mitsuba::crosscheck::{crosscheck, CrossCheck, CrossCheckOptions};
use compare::mitsuba::runner::Variant;
use scenes::{Film, Scene};

/// A built-in scene, `scenes/<name>.toml`.
pub fn builtin(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(format!("{name}.toml"));
    scenes::load(&path).unwrap_or_else(|e| panic!("loading built-in scene {name}: {e}"))
}

/// The scene at `w`×`h`.
pub fn at(mut scene: Scene, width: u32, height: u32) -> Scene {
    scene.film = Film { width, height };
    scene
}

/// Cross-checks `exported` (rendered by Mitsuba) against `oracle_scene` (rendered by the
/// oracle). Mitsuba missing is a failure that says what to install, never a skip.
pub fn check(tag: &str, exported: &Scene, oracle_scene: &Scene, spp: u32, variant: Variant) -> CrossCheck {
    let out_dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("mitsuba-{tag}"));
    let opts = CrossCheckOptions {
        spp,
        variant,
        out_dir,
        verbose: false,
    };
    let c = crosscheck(exported, oracle_scene, &opts)
        .unwrap_or_else(|e| panic!("{tag}: cross-check could not run: {e}"));
    let z = &c.ztest;
    println!(
        "{tag}: {}x{} {} spp {}: pass {} — {:.3} % of pixel-channels pass ({} fail, α′ {:.2e}), min p {:.2e}, \
         mean z² {:.3}, relMSE {:.3e} (noise {:.3e}); oracle {:.2} s, Mitsuba {:.2} s",
        c.oracle.width,
        c.oracle.height,
        c.spp,
        variant.name(),
        z.pass,
        100.0 * z.passed_fraction,
        z.failed,
        z.alpha,
        z.min_p,
        z.mean_z2,
        z.relmse,
        z.relmse_noise,
        c.oracle_seconds,
        c.mitsuba.timings.render_s
    );
    c
}
