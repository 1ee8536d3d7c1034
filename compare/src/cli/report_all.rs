//! `verity report --all [--quick] [--record] [--stale] [--studies FOLDER]`: every study of
//! `scenes/studies` (or FOLDER), each in its own `verity report` process (so that each one's
//! peak memory is its own), into `DIR/<study>/`, then one summary of them all:
//! `DIR/summary.md` and `DIR/summary.json` (study, mode, exit status, bounds held, wall
//! time, peak memory). `scripts/full-studies.sh` runs it in full mode with `--record`, which
//! writes each study's full-mode record into its study file ([`crate::study::record`]);
//! `--stale` runs only the studies whose record is missing, out of date or failed, so a full
//! run that was cut off resumes where it stopped.
//!
//! Exit status: 0 when every study ran and every bound held; otherwise the worst of the
//! studies' statuses (1 a bound failed or a run failed, 2 bad input, 3 no GPU adapter).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use serde_json::Value;

use super::CliError;
use crate::study::{self, record};

/// The flags of `verity report` that `--all` runs with.
pub struct AllOptions {
    /// `--quick`.
    pub quick: bool,
    /// `--record`.
    pub record: bool,
    /// `--stale`.
    pub stale: bool,
    /// `--only-bounded`.
    pub only_bounded: bool,
    /// `--out DIR`.
    pub out: Option<PathBuf>,
    /// `--cache DIR`.
    pub cache: Option<PathBuf>,
}

/// One study's line of the summary.
struct Row {
    study: String,
    status: u8,
    held: usize,
    checked: usize,
    wall_seconds: Option<f64>,
    peak_memory_bytes: Option<u64>,
    /// What became of the study's full-mode record: `written`, `current (DATE), not re-run`
    /// with --stale, or `—`.
    record: String,
}

/// The study files of `dir`, sorted.
fn study_files(dir: &Path) -> Result<Vec<PathBuf>, CliError> {
    let entries = std::fs::read_dir(dir).map_err(|e| CliError::input(format!("{}: {e}", dir.display())))?;
    let mut files: Vec<PathBuf> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    Ok(files)
}

/// Runs every study of `dir` (module header).
pub fn run(args: &AllOptions, dir: &Path) -> Result<u8, CliError> {
    let out = args.out.clone().unwrap_or_else(|| {
        PathBuf::from(if args.quick {
            "out/all-studies-quick"
        } else {
            "out/all-studies"
        })
    });
    let files = study_files(dir)?;
    // Every study must load before hours of rendering start.
    let studies = files
        .iter()
        .map(|f| study::load(f).map_err(|e| CliError::input(e.to_string())))
        .collect::<Result<Vec<_>, _>>()?;
    let exe =
        std::env::current_exe().map_err(|e| CliError::run(format!("cannot find the verity binary: {e}")))?;
    let mut rows = Vec::new();
    for (i, s) in studies.iter().enumerate() {
        if args.stale {
            let standing = record::standing(&s.path, &s.scene).map_err(|e| CliError::input(e.to_string()))?;
            if let record::Standing::Current(r) = &standing {
                eprintln!(
                    "report --all: [{}/{}] {}: {}, not re-run",
                    i + 1,
                    studies.len(),
                    s.path.display(),
                    standing.describe()
                );
                rows.push(Row {
                    study: s.name.clone(),
                    status: 0,
                    held: r.held,
                    checked: r.checked,
                    wall_seconds: None,
                    peak_memory_bytes: None,
                    record: format!("current ({}), not re-run", r.date),
                });
                continue;
            }
        }
        let folder = out.join(&s.name);
        let metrics = folder.join("metrics.json");
        // A stale metrics.json must not stand for this run.
        let _ = std::fs::remove_file(&metrics);
        eprintln!("report --all: [{}/{}] {}", i + 1, studies.len(), s.path.display());
        let status = child(&exe, args, &s.path, &folder)?;
        let json = std::fs::read_to_string(&metrics)
            .ok()
            .and_then(|t| serde_json::from_str::<Value>(&t).ok());
        let mut row = summarize(&s.name, status, json.as_ref());
        if let (true, Some(json)) = (args.record, &json) {
            if write_record(s, json)? {
                row.record = "written".into();
            }
        }
        rows.push(row);
    }
    write_summary(&out, args, &rows)?;
    let worst = rows.iter().map(|r| r.status).max().unwrap_or(0);
    Ok(worst)
}

/// Runs `verity report STUDY` as a child with this process's global flags; its exit status.
fn child(exe: &Path, args: &AllOptions, study: &Path, folder: &Path) -> Result<u8, CliError> {
    let mut c = Command::new(exe);
    let limit = scenes::budget::limit();
    if limit.source == scenes::budget::Source::Flag {
        c.args(["--memory-limit", &limit.bytes.to_string()]);
    }
    if scenes::access::outside_allowed() {
        c.arg("--allow-paths-outside");
    }
    c.arg("report").arg(study).arg("--out").arg(folder).arg("--quiet");
    if args.quick {
        c.arg("--quick");
    }
    if args.only_bounded {
        c.arg("--only-bounded");
    }
    if let Some(cache) = &args.cache {
        c.arg("--cache").arg(cache);
    }
    let status = c
        .stdin(Stdio::null())
        .status()
        .map_err(|e| CliError::run(format!("cannot run {}: {e}", exe.display())))?;
    // A signal (no code) counts as a failed run.
    Ok(status.code().map_or(1, |c| c.clamp(0, 255) as u8))
}

/// The summary row of one study from its metrics.json (absent when the run did not finish).
fn summarize(name: &str, status: u8, json: Option<&Value>) -> Row {
    let thresholds = json
        .and_then(|j| j["thresholds"].as_array())
        .map_or(&[][..], Vec::as_slice);
    let run = json.map(|j| &j["run"]);
    Row {
        study: name.to_string(),
        status,
        held: thresholds.iter().filter(|t| t["passed"] == true).count(),
        checked: thresholds.len(),
        wall_seconds: run.and_then(|r| r["wall_seconds"].as_f64()),
        peak_memory_bytes: run.and_then(|r| r["peak_memory_bytes"].as_u64()),
        record: "—".into(),
    }
}

/// Writes `s`'s full-mode record from its run's metrics.json; false when there is nothing to
/// record (the run did not finish).
fn write_record(s: &study::Study, json: &Value) -> Result<bool, CliError> {
    let fail = |e: std::io::Error| CliError::run(format!("{}: {e}", s.path.display()));
    let fingerprint = record::fingerprint_files(&s.path, &s.scene).map_err(fail)?;
    let Some(r) = record::from_metrics(json, fingerprint, record::today()) else {
        return Ok(false);
    };
    let text = std::fs::read_to_string(&s.path).map_err(fail)?;
    scenes::layered::write_atomic(&s.path, record::with_record(&text, &r).as_bytes()).map_err(fail)?;
    Ok(true)
}

/// `DIR/summary.md` and `DIR/summary.json`, and the table on standard output.
fn write_summary(out: &Path, args: &AllOptions, rows: &[Row]) -> Result<(), CliError> {
    let mode = if args.quick { "quick" } else { "full" };
    let only = if args.only_bounded {
        ", bounded variants only (--only-bounded)"
    } else {
        ""
    };
    let mut md = format!(
        "# All studies, {mode} mode{only}\n\n| study | mode | exit | bounds held | wall time | peak memory | record |\n|---|---|---|---|---|---|---|\n"
    );
    let mut json = Vec::new();
    for r in rows {
        md += &format!(
            "| {} | {mode} | {} | {} of {} | {} | {} | {} |\n",
            r.study,
            r.status,
            r.held,
            r.checked,
            r.wall_seconds.map_or("—".into(), |t| format!("{t:.1} s")),
            r.peak_memory_bytes.map_or("—".into(), scenes::budget::human),
            r.record
        );
        json.push(serde_json::json!({
            "study": r.study, "mode": mode, "exit": r.status, "bounds_held": r.held,
            "bounds_checked": r.checked, "wall_seconds": r.wall_seconds,
            "peak_memory_bytes": r.peak_memory_bytes, "recorded": r.record == "written",
            "record": r.record,
        }));
    }
    let total: f64 = rows.iter().filter_map(|r| r.wall_seconds).sum();
    let peak = rows.iter().filter_map(|r| r.peak_memory_bytes).max();
    let held: usize = rows.iter().map(|r| r.held).sum();
    let checked: usize = rows.iter().map(|r| r.checked).sum();
    let failed: Vec<&str> = rows
        .iter()
        .filter(|r| r.status != 0)
        .map(|r| r.study.as_str())
        .collect();
    let last = format!(
        "{} studies, {held} of {checked} bounds hold, {} failed{}, {:.1} min in all, largest peak memory {}",
        rows.len(),
        failed.len(),
        if failed.is_empty() {
            String::new()
        } else {
            format!(" ({})", failed.join(", "))
        },
        total / 60.0,
        peak.map_or("—".into(), scenes::budget::human)
    );
    md += &format!("\n{last}\n");
    let summary = serde_json::json!({ "mode": mode, "studies": json, "total_wall_seconds": total,
        "largest_peak_memory_bytes": peak, "bounds_held": held, "bounds_checked": checked });
    std::fs::create_dir_all(out).map_err(|e| CliError::run(format!("{}: {e}", out.display())))?;
    let write = |name: &str, bytes: &[u8]| {
        scenes::layered::write_atomic(out.join(name), bytes)
            .map_err(|e| CliError::run(format!("{}: {e}", out.join(name).display())))
    };
    write("summary.md", md.as_bytes())?;
    write(
        "summary.json",
        serde_json::to_string_pretty(&summary)
            .unwrap_or_default()
            .as_bytes(),
    )?;
    print!("{md}");
    println!("-> {}", out.join("summary.md").display());
    Ok(())
}
