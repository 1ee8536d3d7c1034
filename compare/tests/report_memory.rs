//! Memory that does not grow with the number of renders (issue 26, part 4): a study of 200
//! raster renders peaks under 2 GB. The scene is soft-shadow.toml, analytic shapes only, the
//! case in which lavapipe kept about 16 MB per forward frame while the analytic shapes'
//! pipeline (which writes frag_depth) drew first in the pass: this study then peaked at 4.2 GB;
//! with the background drawn first (realtime/src/pipelines.rs `stages`) it peaks at 0.72 GB.
//! The peak is the report's own `run.peak_memory_bytes` (Linux VmHWM of the process).

use std::path::Path;
use std::process::Command;

#[test]
fn a_study_of_200_renders_stays_under_2_gb() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-memory");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/soft-shadow.toml");
    let n: Vec<String> = (1..=50).map(|i| i.to_string()).collect();
    let mut study = format!(
        "scene = \"{}\"\nmetrics = [\"relmse\"]\n[ground_truth]\nintegrator = \"direct\"\nspp = 4\n\
         resolution = [32, 32]\n[raster]\nwarmup_frames = 0\ntimed_frames = 1\n",
        scene.display()
    );
    for method in ["area_quadrature", "shadow_hard", "pcf_box", "pcss"] {
        study += &format!(
            "[[method]]\nname = \"{method}\"\nsweep = {{ n = [{}] }}\n",
            n.join(", ")
        );
    }
    let file = dir.join("memory.toml");
    std::fs::write(&file, study).unwrap();
    let out_dir = dir.join("out");
    let out = Command::new(env!("CARGO_BIN_EXE_verity"))
        .args([
            "report",
            file.to_str().unwrap(),
            "--out",
            out_dir.to_str().unwrap(),
            "-q",
        ])
        .arg("--cache")
        .arg(dir.join("cache"))
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("metrics.json")).unwrap()).unwrap();
    assert_eq!(metrics["variants"].as_array().map(Vec::len), Some(200));
    let peak = metrics["run"]["peak_memory_bytes"]
        .as_u64()
        .expect("the report measures its peak memory (Linux VmHWM)");
    assert!(
        peak < 2 << 30,
        "200 renders peaked at {:.2} GB",
        peak as f64 / f64::from(1u32 << 30)
    );
}
