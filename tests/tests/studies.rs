//! Study thresholds: every study under scenes/studies runs in quick mode and each declared
//! bound — upper bounds where a method holds, lower bounds where it is known to fail — is
//! asserted, naming the study, method, parameters and metric on failure. A method broken on
//! purpose must make the bounds fail with that message.

use std::path::{Path, PathBuf};

use compare::progress::ProgressMode;
use compare::study::result::StudyResult;
use compare::study::run::{run_study, Rasters, RunOptions};
use compare::study::{self, Study};
use realtime::Renderer;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A renderer of its own for each study run: its device, shader modules and pipeline cache
/// are released with it. One shared across the ~40 studies kept every pipeline any study
/// compiled (lavapipe's JIT code with it) and grew past 24 GB.
fn renderer() -> Renderer {
    Renderer::new().unwrap_or_else(|e| panic!("no GPU adapter: {e} (run ./scripts/setup.sh)"))
}

/// Runs `study` in quick mode into target/study-tests/<name>.
fn run_quick(study: &Study, tag: &str) -> StudyResult {
    let out = workspace()
        .join("target/study-tests")
        .join(format!("{}{tag}", study.name));
    let opts = RunOptions {
        quick: true,
        out_dir: out.clone(),
        cache_dir: workspace().join("target/study-tests/cache"),
        progress: ProgressMode::Quiet,
        only_bounded: true,
    };
    let r = run_study(study, &Rasters::Live(&renderer()), &opts)
        .unwrap_or_else(|e| panic!("{}: {e}", study.path.display()));
    compare::report::write(&r, &out).expect("report written");
    r
}

fn studies() -> Vec<PathBuf> {
    let dir = workspace().join("scenes/studies");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    v.sort();
    v
}

#[test]
fn every_study_holds_its_declared_bounds_in_quick_mode() {
    let paths = studies();
    assert!(!paths.is_empty(), "no study under scenes/studies");
    for path in &paths {
        let s = study::load(path).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            !s.thresholds.is_empty(),
            "{}: a study without thresholds tests nothing",
            path.display()
        );
        assert!(
            s.thresholds.iter().any(|t| t.min.is_some()),
            "{}: needs at least one lower bound where a method is known to fail",
            path.display()
        );
    }
    // Several children at once: one study keeps about one core busy (lavapipe's queue
    // thread waits on its raster threads and the readbacks), so two at a time fill a 2-core
    // machine (with a cold ground-truth cache, as in CI: 36 min one at a time, 21–23 two). At
    // most MAX_CHILDREN: each peaks near 2 GB. Studies that share a ground truth may both
    // render it; the cache's entries are written atomically (study::cache), so the second
    // write replaces the first with an equal image.
    let jobs = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, MAX_CHILDREN);
    // Even workers take studies from the front of the sorted list, odd ones from its back, so
    // that two children seldom run studies of one family at once: those build the same
    // pipelines, and lavapipe gets a pipeline's machine code from Mesa's shader cache only
    // once another process has finished compiling it (cold in CI).
    let queue = std::sync::Mutex::new(
        paths
            .iter()
            .enumerate()
            .collect::<std::collections::VecDeque<_>>(),
    );
    let mut results: Vec<(usize, Result<Vec<String>, String>)> = std::thread::scope(|scope| {
        let queue = &queue;
        let workers: Vec<_> = (0..jobs)
            .map(|w| {
                scope.spawn(move || {
                    let mut done = Vec::new();
                    loop {
                        let next = {
                            let mut q = queue.lock().unwrap_or_else(|p| p.into_inner());
                            if w % 2 == 0 {
                                q.pop_front()
                            } else {
                                q.pop_back()
                            }
                        };
                        let Some((i, path)) = next else { break done };
                        done.push((i, run_quick_in_child(path)));
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("a study worker thread"))
            .collect()
    });
    results.sort_by_key(|(i, _)| *i);
    let mut failures = Vec::new();
    let mut crashed = Vec::new();
    for (_, r) in results {
        match r {
            Ok(f) => failures.extend(f),
            Err(e) => crashed.push(e),
        }
    }
    assert!(crashed.is_empty(), "{}", crashed.join("\n"));
    assert!(
        failures.is_empty(),
        "declared bounds fail:\n{}",
        failures.join("\n")
    );
    // The quick study of issue 43's memory report: 1.50 GB then (every pipeline carried the
    // whole shading module), 0.51 GB since. The child runs the study as `verity report
    // --quick` does, and its report records the process's peak (Linux VmHWM).
    let metrics = workspace().join("target/study-tests/shadow-light-size/metrics.json");
    let text = std::fs::read_to_string(&metrics).unwrap_or_else(|e| panic!("{}: {e}", metrics.display()));
    let json: serde_json::Value =
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", metrics.display()));
    let peak = json["run"]["peak_memory_bytes"]
        .as_u64()
        .expect("the report measures its peak memory (Linux VmHWM)");
    assert!(
        peak < 700 << 20,
        "the quick shadow-light-size study peaked at {} MB",
        peak >> 20
    );
}

/// The most study processes run at once.
const MAX_CHILDREN: usize = 4;

/// The environment variable naming the study [`one_study_in_quick_mode`] runs.
const CHILD_STUDY: &str = "VERITY_TEST_STUDY";

/// Runs the study at `path` in quick mode in a child process of this test binary
/// ([`one_study_in_quick_mode`]) and returns the messages of its failed bounds. One process
/// per study: what the realtime renderer leaves behind per render (lavapipe's compiled
/// pipelines among it; issue 26 measures it) goes with the process, where one process for
/// all ~40 studies grew past 24 GB. Its output is printed in one piece when it ends; a
/// child that fails (a panic, an error) comes back as `Err` with its output.
fn run_quick_in_child(path: &Path) -> Result<Vec<String>, String> {
    let out = std::process::Command::new(std::env::current_exe().expect("the test binary"))
        .args([
            "one_study_in_quick_mode",
            "--exact",
            "--ignored",
            "--nocapture",
            "--test-threads",
            "1",
        ])
        .env(CHILD_STUDY, path)
        .output()
        .expect("the test binary runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    print!("{stdout}");
    if !out.status.success() {
        return Err(format!(
            "{}: the quick run failed:\n{stdout}\n{}",
            path.display(),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(stdout
        .lines()
        .filter_map(|l| l.strip_prefix("FAILS ").map(str::to_string))
        .collect())
}

/// The child of [`every_study_holds_its_declared_bounds_in_quick_mode`]: runs the study
/// `VERITY_TEST_STUDY` names, prints `holds …` / `FAILS …` per bound and checks that every
/// bound of quick mode applies to a variant. Ignored when run on its own: it is that test's
/// per-study process, started with `--ignored`.
#[test]
#[ignore = "the per-study child process of every_study_holds_its_declared_bounds_in_quick_mode"]
fn one_study_in_quick_mode() {
    let path =
        PathBuf::from(std::env::var(CHILD_STUDY).expect("started by the parent test with VERITY_TEST_STUDY"));
    let s = study::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let r = run_quick(&s, "");
    for t in &r.thresholds {
        println!(
            "{} {}",
            if t.passed { "holds" } else { "FAILS" },
            t.message(&s.name)
        );
    }
    // Every bound checked in quick mode applies to at least one variant; bounds declared for
    // full mode only (`mode = "full"`) are checked by the full-mode records.
    for t in s
        .thresholds
        .iter()
        .filter(|t| t.checked_in(study::RunMode::Quick))
    {
        assert!(
            r.thresholds.iter().any(|c| c.location == t.location),
            "{}: the bound at {} applies to no variant in quick mode",
            path.display(),
            t.location
        );
    }
}

#[test]
fn a_method_broken_on_purpose_fails_its_bound_with_a_clear_message() {
    // Hold N = 1 quadrature (a point light at the light's centre) to the converged N = 16
    // bound: it must fail, and say which study, variant, metric and declaration.
    let path = workspace().join(compare::study::DEFAULT_STUDY);
    let mut s = study::load(&path).unwrap();
    s.name = "area-lights-broken".into();
    s.stability.flicker = None;
    let converged = s
        .thresholds
        .iter()
        .position(|t| {
            t.max.is_some()
                && t.params == [("n".to_string(), "16".to_string())]
                && t.metric.name() == "relmse"
        })
        .expect("the default study bounds quadrature n = 16 from above");
    s.thresholds = vec![s.thresholds[converged].clone()];
    s.thresholds[0].params = vec![("n".into(), "1".into())];
    let r = run_quick(&s, "");
    let failures = r.failures();
    assert_eq!(failures.len(), 1, "the broken method must fail its bound");
    let msg = failures[0].message(&s.name);
    assert!(
        msg.starts_with("area-lights-broken: area_quadrature(n=1) relmse over `interior` = ")
            && msg.contains("expected ≤ 1e-3")
            && msg.contains("area-lights.toml:"),
        "{msg}"
    );
}

#[test]
fn a_pcss_ignoring_the_blocker_depth_fails_the_shadow_bounds() {
    // PCSS with `blocker_depth = ignore` uses a constant penumbra instead of Fernando's
    // (d_r − d_b)·w_light/d_b: the deliberately broken PCSS of the soft-shadow issue. Held to
    // the real PCSS's visibility bound, it must fail, naming the study, variant and bound.
    let path = workspace().join("scenes/studies/soft-shadows.toml");
    let mut s = study::load(&path).unwrap();
    s.name = "soft-shadows-broken".into();
    s.methods.retain(|m| m.name == "pcss");
    let mut params = s.methods[0].params().to_vec();
    params.push(("blocker_depth".into(), "ignore".into()));
    s.methods[0]
        .set_params(params, vec![("map".into(), vec!["1024".into()])])
        .unwrap();
    s.thresholds
        .retain(|t| t.method == "pcss" && t.max.is_some() && t.on == study::Target::Visibility);
    assert_eq!(
        s.thresholds.len(),
        1,
        "the soft-shadow study bounds PCSS's visibility from above"
    );
    let r = run_quick(&s, "");
    let failures = r.failures();
    assert_eq!(failures.len(), 1, "the broken PCSS must fail its bound");
    let msg = failures[0].message(&s.name);
    assert!(
        msg.starts_with("soft-shadows-broken: pcss(map=1024) relmse of the visibility over `interior` = ")
            && msg.contains("soft-shadows.toml:"),
        "{msg}"
    );
}

/// Every study's full run fits the default memory budget of a 24 GB machine (half of it)
/// by its own estimate (`compare::study::plan`), so `verity report STUDY` runs where CI does.
#[test]
fn every_study_full_run_fits_a_24_gb_machine() {
    scenes::budget::set_limit(12 << 30);
    for path in studies() {
        let s = study::load(&path).unwrap_or_else(|e| panic!("{e}"));
        compare::study::plan::plan(&s, false).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
}

/// Studies whose first full-mode run has not been made yet (issue 20 stays open while this
/// list is not empty; `./scripts/full-studies.sh --stale` runs exactly these and the ones whose
/// record went stale). The list only shrinks: the test below fails when a listed study has a
/// current record, and when an unlisted one has none.
const AWAITING_FIRST_FULL_RUN: &[&str] = &[];

/// Every study holds at the size users run it: its file ends with the record of a full-mode
/// run (`./scripts/full-studies.sh`, i.e. `verity report --all --record`) of the study and
/// scene as they are now, in which every bound held. CI runs quick mode only; this test is
/// what keeps a bound set at 64² from standing unchecked at 256² (compare::study::record).
/// A record whose ground truths another oracle rendered is listed, not failed: the analytic
/// and Mitsuba tests hold the oracle's expected values, so such a record is due, not wrong
/// (`--stale` runs it again; compare::study::record's header).
#[test]
fn every_study_carries_a_current_full_mode_record_with_every_bound_held() {
    use compare::study::record::{self, Standing};
    let mut wrong = Vec::new();
    let mut awaiting = Vec::new();
    let mut other_oracle = Vec::new();
    for path in studies() {
        let s = study::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let standing =
            record::standing(&s.path, &s.scene).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let listed = AWAITING_FIRST_FULL_RUN.contains(&s.name.as_str());
        match (&standing, listed) {
            (Standing::Current(_), false) => {}
            (Standing::OtherOracle(_), false) => other_oracle.push(s.name.clone()),
            (Standing::Missing, true) => awaiting.push(s.name.clone()),
            (Standing::Current(_), true) => wrong.push(format!(
                "{}: has a current full-mode record: take `{}` off AWAITING_FIRST_FULL_RUN",
                path.display(),
                s.name
            )),
            _ => wrong.push(format!("{}: {}", path.display(), standing.describe())),
        }
    }
    for name in AWAITING_FIRST_FULL_RUN {
        assert!(
            studies()
                .iter()
                .any(|p| study::load(p).is_ok_and(|s| s.name == *name)),
            "AWAITING_FIRST_FULL_RUN names `{name}`, which is no study"
        );
    }
    println!(
        "{} studies still await their first full-mode run: {}",
        awaiting.len(),
        awaiting.join(", ")
    );
    println!(
        "{} full-mode records hold another oracle's ground truths (oracle now {}; \
         ./scripts/full-studies.sh --stale runs them again): {}",
        other_oracle.len(),
        record::oracle_now(),
        other_oracle.join(", ")
    );
    assert!(
        wrong.is_empty(),
        "run ./scripts/full-studies.sh --stale (full mode; writes each study's record):\n{}",
        wrong.join("\n")
    );
}
