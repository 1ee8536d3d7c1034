//! The example notebook (notebooks/error_vs_cost.ipynb) is executed headless against a fresh
//! quick report of the default study, so it cannot rot: it reads metrics.json and the EXRs,
//! redraws the error-vs-cost chart and recomputes a relMSE from the EXRs, asserting it matches.
//! Missing Python packages fail the test with the fix (./scripts/setup.sh); never a skip.

use std::path::{Path, PathBuf};
use std::process::Command;

use compare::progress::ProgressMode;
use compare::study::run::{run_study, Rasters, RunOptions};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[test]
fn the_example_notebook_runs_on_a_quick_report() {
    let ws = workspace();
    let out = ws.join("target/notebook-test/report");
    let study = compare::study::load(&ws.join(compare::study::DEFAULT_STUDY)).unwrap();
    let mut study = study;
    study.stability.flicker = None;
    let renderer = realtime::Renderer::new().unwrap_or_else(|e| panic!("no GPU adapter: {e}"));
    let opts = RunOptions {
        quick: true,
        out_dir: out.clone(),
        cache_dir: ws.join("target/notebook-test/cache"),
        progress: ProgressMode::Quiet,
        only_bounded: false,
    };
    let r = run_study(&study, &Rasters::Live(&renderer), &opts).unwrap_or_else(|e| panic!("{e}"));
    compare::report::write(&r, &out).unwrap();
    let python = std::env::var_os("VERITY_PYTHON").map_or(ws.join(".venv/bin/python"), PathBuf::from);
    let run = Command::new(&python)
        .arg(ws.join("notebooks/run_notebook.py"))
        .arg(ws.join("notebooks/error_vs_cost.ipynb"))
        .env("VERITY_REPORT", &out)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e} (run ./scripts/setup.sh)", python.display()));
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "the notebook failed (run ./scripts/setup.sh if a package is missing):\n{stdout}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(
        stdout.contains("Pareto-optimal:") && stdout.contains("recomputed from the EXRs"),
        "{stdout}"
    );
    assert!(out.join("notebook-error-vs-cost.png").exists());
}
