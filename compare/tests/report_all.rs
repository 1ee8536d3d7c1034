//! `verity report --all`: every study of a folder in full mode, one summary, and each study's
//! full-mode record written into its file (`--record`), then read back by `--stale`, which
//! re-runs only the studies whose record is missing, out of date or failed (issue 20).

use std::path::{Path, PathBuf};
use std::process::Command;

use compare::study::record::{self, Standing};

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("report-all")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn verity(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_verity"))
        .args(args)
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).to_string(),
        String::from_utf8_lossy(&out.stderr).to_string(),
    )
}

/// A tiny study of the Cornell box (16², 4 spp full mode) with one bound, `bound`.
fn tiny_study(bound: &str) -> String {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box.toml");
    format!(
        r#"scene = "{}"
metrics = ["relmse"]
[ground_truth]
integrator = "direct-unshadowed"
spp = 4
resolution = [16, 16]
[raster]
warmup_frames = 0
timed_frames = 1
[[method]]
name = "area_quadrature"
sweep = {{ n = [2] }}
[[threshold]]
method = "area_quadrature"
metric = "relmse"
{bound}
reason = "r"
"#,
        scene.display()
    )
}

#[test]
fn all_studies_in_full_mode_are_summarized_and_recorded_and_stale_reruns_only_what_changed() {
    let dir = tmp("case");
    let studies = dir.join("studies");
    std::fs::create_dir_all(&studies).unwrap();
    let (holds, fails) = (studies.join("holds.toml"), studies.join("fails.toml"));
    std::fs::write(&holds, tiny_study("max = 10.0")).unwrap();
    std::fs::write(&fails, tiny_study("min = 100.0")).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box.toml");
    let (out, cache) = (dir.join("out"), dir.join("cache"));
    let args = |extra: &[&str]| {
        let mut a: Vec<String> = ["report", "--all", "--record", "--studies"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        a.push(studies.display().to_string());
        a.extend(["--out".into(), out.display().to_string()]);
        a.extend(["--cache".into(), cache.display().to_string()]);
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };

    // First run: one study holds, one fails; exit 1, both summarized and recorded.
    let a = args(&[]);
    let (code, stdout, stderr) = verity(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(summary.contains("| holds | full | 0 | 1 of 1 |"), "{summary}");
    assert!(summary.contains("| fails | full | 1 | 0 of 1 |"), "{summary}");
    assert!(
        summary.contains("2 studies, 1 of 2 bounds hold, 1 failed (fails)"),
        "{summary}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["mode"], "full");
    assert!(
        json["largest_peak_memory_bytes"].as_u64().is_some_and(|b| b > 0),
        "{json}"
    );
    let metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("holds/metrics.json")).unwrap()).unwrap();
    assert_eq!(metrics["mode"], "full");
    assert_eq!(metrics["run"]["resolution"], serde_json::json!([16, 16]));
    assert_eq!(metrics["run"]["ground_truth_spp"], 4);
    let page = std::fs::read_to_string(out.join("holds/index.html")).unwrap();
    assert!(
        page.contains("<b>full mode</b>: 16×16 pixels, ground truth 4 spp"),
        "the page names its mode"
    );

    let Standing::Current(r) = record::standing(&holds, &scene).unwrap() else {
        panic!(
            "no current record in {}",
            std::fs::read_to_string(&holds).unwrap()
        )
    };
    assert_eq!((r.held, r.checked, r.date.len()), (1, 1, 10));
    assert!(r.run.starts_with("16x16, ground truth 4 spp, "), "{}", r.run);
    assert!(
        r.checks[0].starts_with("area_quadrature(n=2) relmse over all = "),
        "{:?}",
        r.checks
    );
    assert!(matches!(
        record::standing(&fails, &scene).unwrap(),
        Standing::Failed(_)
    ));

    // Fix the failing bound: --stale runs it alone, the other keeps its record.
    let text = std::fs::read_to_string(&fails)
        .unwrap()
        .replace("min = 100.0", "max = 10.0");
    std::fs::write(&fails, text).unwrap();
    assert!(matches!(
        record::standing(&fails, &scene).unwrap(),
        Standing::Stale { .. }
    ));
    let before = std::fs::read_to_string(&holds).unwrap();
    let a = args(&["--stale"]);
    let (code, stdout, stderr) = verity(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(stderr.contains("holds.toml: full-mode record of"), "{stderr}");
    assert!(stderr.contains("not re-run"), "{stderr}");
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        summary.contains("| holds | full | 0 | 1 of 1 | — | — | current ("),
        "{summary}"
    );
    assert!(summary.contains("| fails | full | 0 | 1 of 1 |"), "{summary}");
    assert_eq!(
        std::fs::read_to_string(&holds).unwrap(),
        before,
        "a current record is kept"
    );
    assert!(matches!(
        record::standing(&fails, &scene).unwrap(),
        Standing::Current(_)
    ));

    // --record needs full mode; --stale and --studies need --all.
    let (code, _, stderr) = verity(&["report", "--all", "--record", "--quick"]);
    assert_eq!(code, 2, "{stderr}");
    let (code, _, stderr) = verity(&["report", "--stale"]);
    assert_eq!(code, 2, "{stderr}");
}
