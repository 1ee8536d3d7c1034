//! `verity report --all`: every study of a folder in full mode, one summary, and each study's
//! full-mode record written into its file (`--record`), then read back by `--stale`, which
//! re-runs only the studies whose record is missing, out of date or failed (issue 20). And a
//! study run as a job graph (`--plan`, `run-job`, `--from`; issue 27).

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

/// A study as a job graph: `--plan` lists one job per ground truth (the scene point and each
/// flicker frame but the first, which is the point's), one per variant's raster renders and
/// the report; `run-job` renders each, once (a second run says it is done); `--from` refuses
/// to run before they are done and then gives the single-process report, rendering nothing:
/// every metric, threshold and flicker value equal.
#[test]
fn a_study_run_as_a_job_graph_gives_the_single_process_report() {
    let (dir, plan, single, graph, out) = single_run_and_plan("job-graph", "graph.toml", 1);
    let path = |p: &Path| p.display().to_string();
    assert!(out.contains("plan graph: 5 jobs"), "{out}");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&plan).unwrap()).unwrap();
    let ids: Vec<String> = json["jobs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j["id"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(ids[..3], ["ground_truth", "flicker-frame-1", "flicker-frame-2"]);
    assert!(
        ids[3].starts_with("raster-area_quadrature") && ids[4] == "report",
        "{ids:?}"
    );
    let raster = &json["jobs"][3];
    assert_eq!(
        raster["outputs"].as_array().unwrap().len(),
        2 * 4,
        "the measured render and one per flicker frame, each an EXR and its checksum: {raster}"
    );
    let report = &json["jobs"][4];
    assert_eq!(report["depends_on"].as_array().unwrap().len(), 4);
    assert_eq!(
        report["inputs"].as_array().unwrap().len(),
        2 + 3 * 2 + 4 * 2,
        "the study, its scene, and each ground truth's and raster's EXR and checksum: {report}"
    );
    assert!(json["jobs"][0]["inputs"][0]
        .as_str()
        .unwrap()
        .ends_with("graph.toml"));

    let (code, _, err) = verity(&["report", "--from", &path(&plan), "-q"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&format!(
            "jobs not done yet: ground_truth, flicker-frame-1, flicker-frame-2, {}",
            ids[3]
        )),
        "{err}"
    );
    // The first job by hand, the others as scripts/slurm/study-jobs.sbatch runs them: tasks
    // 2 and 3 of an array 1-3 of the ground truths (the default kind), task 1 of an array of
    // the raster jobs.
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/slurm/study-jobs.sbatch");
    for (i, id) in ids[..4].iter().enumerate() {
        let (code, out, err) = if i == 0 {
            verity(&["run-job", &path(&plan), id, "-q"])
        } else {
            let (task, kind) = if i < 3 { (i + 1, None) } else { (1, Some("raster")) };
            let out = Command::new("bash")
                .arg(&script)
                .arg(&plan)
                .args(kind)
                .env("VERITY", env!("CARGO_BIN_EXE_verity"))
                .env("SLURM_ARRAY_TASK_ID", task.to_string())
                .env("SLURM_ARRAY_TASK_MIN", "1")
                .output()
                .unwrap();
            (
                out.status.code().unwrap_or(-1),
                String::from_utf8_lossy(&out.stdout).to_string(),
                String::from_utf8_lossy(&out.stderr).to_string(),
            )
        };
        assert_eq!(code, 0, "{id}: {err}");
        assert!(
            out.contains(&format!("job {id} of")) && out.contains("rendered"),
            "{out}"
        );
    }
    for id in ["flicker-frame-1", ids[3].as_str()] {
        let (code, out, _) = verity(&["run-job", &path(&plan), id, "-q"]);
        assert!(code == 0 && out.contains("already done"), "{out}");
    }
    for (job, expected) in [
        ("report", "job `report` is the report"),
        ("nope", "no job `nope` in the plan"),
    ] {
        let (code, _, err) = verity(&["run-job", &path(&plan), job]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(expected), "{err}");
    }
    // The report job measures the recorded rasters: it needs no adapter at all.
    let out = Command::new(env!("CARGO_BIN_EXE_verity"))
        .args(["report", "--from", &path(&plan), "-q"])
        .env("WGPU_BACKEND", "gl")
        .env("WGPU_ADAPTER_NAME", "no such adapter")
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    assert_eq!(
        report_values(&single),
        report_values(&graph),
        "the job graph's report is the single run's"
    );
    let graph_metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(graph.join("metrics.json")).unwrap()).unwrap();
    assert_eq!(
        graph_metrics["ground_truth"]["cached"], true,
        "the report job found its ground truth in the cache"
    );

    // A raster recorded for another scene or settings is refused, naming the job to rerun.
    let study = dir.join("graph.toml");
    let text = std::fs::read_to_string(&study).unwrap();
    std::fs::write(&study, text.replace("timed_frames = 1", "timed_frames = 2")).unwrap();
    let (code, _, err) = verity(&["report", "--from", &path(&plan), "-q"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("rendered for another scene or settings")
            && err.contains("raster job of `area_quadrature"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// compare/python/run_plan.py on `plan` with `args` (after `--verity`) and `env`, bounded in
/// time (a hung cluster fails the test with exit 124 instead of stalling CI); asserts exit 0
/// and returns stdout and stderr.
fn run_driver(plan: &Path, args: &[&str], env: &[(&str, &std::ffi::OsStr)]) -> (String, String) {
    let driver = Path::new(env!("CARGO_MANIFEST_DIR")).join("python/run_plan.py");
    let out = Command::new("timeout")
        .arg("300")
        .arg(venv_python())
        .arg(&driver)
        .arg(plan)
        .args(["--verity", env!("CARGO_BIN_EXE_verity")])
        .args(args)
        .envs(env.iter().copied())
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout).to_string(),
        String::from_utf8_lossy(&out.stderr).to_string(),
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "run_plan.py {args:?} (exit 3: run ./scripts/setup.sh for the venv; 124: timed out after 300 s):\n{stdout}\n{stderr}"
    );
    (stdout, stderr)
}

/// The project's venv Python (`$VERITY_PYTHON`, else `.venv/bin/python`), which
/// scripts/setup.sh fills from compare/python/requirements.txt.
fn venv_python() -> PathBuf {
    let python = std::env::var_os("VERITY_PYTHON")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../.venv/bin/python"));
    assert!(
        python.exists(),
        "no Python at {}: run ./scripts/setup.sh (it installs compare/python/requirements.txt into .venv)",
        python.display()
    );
    python
}

/// compare/python/run_plan.py runs the job graph, its ground truths split into two shares
/// each, on a local Dask cluster of two worker processes (127.0.0.1) and makes the report; one
/// worker dies abruptly in its first job (the driver's fault injection) and the job is run
/// again elsewhere. The report equals the single-process one in every metric, threshold and
/// flicker value, and the merged ground truths are the single run's, bit for bit.
#[test]
fn a_study_job_graph_runs_on_a_local_dask_cluster_that_loses_a_worker() {
    let (dir, plan, single, graph, out) = single_run_and_plan("dask", "dask.toml", 2);
    assert!(
        out.contains("plan dask: 11 jobs"),
        "3 ground truths of 2 parts each, 1 raster job, the report: {out}"
    );
    let died = dir.join("a-worker-died");
    let (stdout, stderr) = run_driver(
        &plan,
        &["--local", "2"],
        &[("VERITY_DASK_DIE_ONCE", died.as_os_str())],
    );
    assert!(died.exists(), "the fault injection did not run: {stderr}");
    for job in [
        "ground_truth.part-2-of-2",
        "ground_truth",
        "flicker-frame-1",
        "flicker-frame-2",
    ] {
        assert!(stdout.contains(&format!("job {job} of")), "{job}: {stdout}");
    }
    assert!(stdout.contains("merged from its parts"), "{stdout}");
    assert_eq!(report_values(&single), report_values(&graph));
    assert_same_ground_truths(&dir.join("cache-single"), &dir.join("cache-graph"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// dask-jobqueue's Slurm cluster, as on a real cluster but for the queue: stand-ins for
/// `sbatch` (runs the job script it is given in the background and prints its job id) and
/// `scancel` (kills it) on the PATH, three ground-truth shares each. The report equals the
/// single-process one and the merged ground truths are the single run's, bit for bit.
#[test]
fn a_study_job_graph_runs_on_slurm_workers_through_dask_jobqueue() {
    let (dir, plan, single, graph, _) = single_run_and_plan("jobqueue", "jobqueue.toml", 3);
    let bin = dir.join("fake-slurm");
    std::fs::create_dir_all(&bin).unwrap();
    let jobs = dir.join("slurm-jobs");
    std::fs::write(
        bin.join("sbatch"),
        format!(
            r#"#!/bin/sh
# A stand-in for Slurm's sbatch: the job script runs now, in the background, in its own
# process group; the job id is its process id.
mkdir -p {jobs}
script=$(mktemp {jobs}/job-XXXXXX)
cp "$1" "$script"
setsid sh -c 'exec bash "$0" > "$0.log" 2>&1' "$script" < /dev/null &
echo "Submitted batch job $!"
"#,
            jobs = jobs.display()
        ),
    )
    .unwrap();
    std::fs::write(
        bin.join("scancel"),
        "#!/bin/sh\nkill -TERM -- -\"$1\" 2>/dev/null || true\n",
    )
    .unwrap();
    for f in ["sbatch", "scancel"] {
        Command::new("chmod").arg("+x").arg(bin.join(f)).status().unwrap();
    }
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let args = [
        "--jobqueue",
        "slurm",
        "--jobs",
        "2",
        "--cores",
        "1",
        "--memory",
        "2GB",
        "--host",
        "127.0.0.1",
    ];
    let (stdout, _) = run_driver(&plan, &args, &[("PATH", std::ffi::OsStr::new(&path))]);
    let scripts: Vec<String> = std::fs::read_dir(&jobs)
        .unwrap()
        .filter_map(|e| std::fs::read_to_string(e.unwrap().path()).ok())
        .filter(|t| t.contains("#SBATCH"))
        .collect();
    assert_eq!(scripts.len(), 2, "two batch jobs submitted");
    assert!(
        scripts.iter().all(|t| t.contains("--resources verity=1")),
        "each worker runs one Verity job at a time: {}",
        scripts[0]
    );
    assert!(stdout.contains("job ground_truth.part-3-of-3 of"), "{stdout}");
    assert_eq!(report_values(&single), report_values(&graph));
    assert_same_ground_truths(&dir.join("cache-single"), &dir.join("cache-graph"));

    // A part cut short is refused by its merge, which names the job to run again; that job
    // renders it again (it is not done) and the merge then succeeds.
    let plan_json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&plan).unwrap()).unwrap();
    let job = |id: &str| {
        plan_json["jobs"]
            .as_array()
            .unwrap()
            .iter()
            .find(|j| j["id"] == id)
            .unwrap_or_else(|| panic!("no job {id}"))
            .clone()
    };
    let (part, truth) = (job("ground_truth.part-1-of-3"), job("ground_truth"));
    let part_file = PathBuf::from(part["outputs"][0].as_str().unwrap());
    let bytes = std::fs::read(&part_file).unwrap();
    std::fs::write(&part_file, &bytes[..bytes.len() / 2]).unwrap();
    for output in truth["outputs"].as_array().unwrap() {
        std::fs::remove_file(output.as_str().unwrap()).unwrap();
    }
    let plan_arg = plan.display().to_string();
    let (code, _, err) = verity(&["run-job", &plan_arg, "ground_truth", "-q"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("run job `ground_truth.part-1-of-3` again"), "{err}");
    for (job, did) in [
        ("ground_truth.part-1-of-3", "rendered"),
        ("ground_truth.part-2-of-3", "already done"),
        ("ground_truth", "merged from its parts"),
        ("ground_truth.part-3-of-3", "already done"),
    ] {
        let (code, out, err) = verity(&["run-job", &plan_arg, job, "-q"]);
        assert!(code == 0 && out.contains(did), "{job}: {out}{err}");
    }
    assert_same_ground_truths(&dir.join("cache-single"), &dir.join("cache-graph"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every ground truth in the cache `single` is in `graph` under the same key with the same
/// channels, bit for bit, and the same header but for the render time.
fn assert_same_ground_truths(single: &Path, graph: &Path) {
    let mut seen = 0;
    for e in std::fs::read_dir(single).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "exr") {
            continue;
        }
        let other = graph.join(p.file_name().unwrap());
        let (a, b) = (
            scenes::layered::LayeredImage::read_exr(&p).unwrap(),
            scenes::layered::LayeredImage::read_exr(&other).unwrap_or_else(|e| panic!("{e}")),
        );
        assert_eq!(a.channels.len(), b.channels.len());
        for ((name, x), (other_name, y)) in a.channels.iter().zip(&b.channels) {
            assert_eq!(name, other_name);
            let bits = |c: &[f32]| c.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert!(bits(x) == bits(y), "{}: channel {name}", other.display());
        }
        let header = |i: &scenes::layered::LayeredImage| {
            i.attributes
                .iter()
                .filter(|(k, _)| k != "seconds")
                .cloned()
                .collect::<Vec<_>>()
        };
        assert_eq!(header(&a), header(&b), "{}", other.display());
        seen += 1;
    }
    assert_eq!(seen, 3, "the scene point's ground truth and two flicker frames'");
}

/// What a report measured, without what depends on the run (timings, paths, cache state):
/// every variant's metrics, every threshold's value, the flicker results, the ground truth's
/// cache key.
fn report_values(
    dir: &Path,
) -> (
    Vec<serde_json::Value>,
    Vec<serde_json::Value>,
    serde_json::Value,
    serde_json::Value,
) {
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("metrics.json")).unwrap()).unwrap();
    let each = |key: &str, field: &str| -> Vec<serde_json::Value> {
        m[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v[field].clone())
            .collect()
    };
    let (variants, thresholds) = (each("variants", "metrics"), each("thresholds", "value"));
    assert!(
        !variants.is_empty() && !thresholds.is_empty(),
        "{}: an empty report",
        dir.display()
    );
    (
        variants,
        thresholds,
        m["flicker"].clone(),
        m["ground_truth"]["hash"].clone(),
    )
}

/// In a fresh folder `name`: the tiny study (file `file`, with three flicker frames) run in
/// one process into `single/`, and its plan written to `plan.json`, ground truths in `parts`
/// shares, for a job-graph run into `graph/` (separate caches, `cache-single/` and
/// `cache-graph/`). Returns the folder, the plan, the two report folders and what `--plan`
/// printed.
fn single_run_and_plan(name: &str, file: &str, parts: u32) -> (PathBuf, PathBuf, PathBuf, PathBuf, String) {
    let dir = tmp(name);
    let study = dir.join(file);
    let text = tiny_study("max = 10.0")
        + "[stability]\nmetric = \"relmse\"\nflicker = { frames = 3, orbit_degrees = 0.5, orbit_distance = 1.0 }\n";
    std::fs::write(&study, text).unwrap();
    let path = |p: &Path| p.display().to_string();
    let (single, graph, plan) = (dir.join("single"), dir.join("graph"), dir.join("plan.json"));
    let (code, _, err) = verity(&[
        "report",
        &path(&study),
        "-q",
        "--out",
        &path(&single),
        "--cache",
        &path(&dir.join("cache-single")),
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = verity(&[
        "report",
        &path(&study),
        "--plan",
        &path(&plan),
        "--out",
        &path(&graph),
        "--cache",
        &path(&dir.join("cache-graph")),
        "--parts",
        &parts.to_string(),
    ]);
    assert_eq!(code, 0, "{err}");
    (dir, plan, single, graph, out)
}
