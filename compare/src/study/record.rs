//! Full-mode records: every study file carries, in a comment block at its end, the date and
//! figures of its last full-mode run and a fingerprint of what decides its bounds. Bounds set
//! in quick mode (64²–96², few spp) and never run at the size users run them mislead; the
//! record says they were, and a test (`tests/tests/studies.rs`) fails when a study has no
//! record, when the record says a bound failed, or when the study or its scene changed since
//! (the fingerprint no longer matches). `verity report --all --record` (what
//! `scripts/full-studies.sh` runs) writes the records.
//!
//! The block, written and read by this module:
//!
//! ```text
//! # --- full-mode record (verity report --all --record; checked by tests/tests/studies.rs) ---
//! # date: 2026-12-03
//! # fingerprint: 0123456789abcdef
//! # oracle: 89abcdef01234567
//! # bounds: 7 of 7 hold
//! # run: 256x256, ground truth 64 spp, 205.9 s, peak memory 2.3 GiB, llvmpipe (LLVM 15.0.6, 256 bits)
//! #   envmap_cube(size=128) relmse over ball = 2.31e-4 (max 1e-3) [line 60]
//! ```
//!
//! The fingerprint is the first 16 hex digits of SHA-256 over the study file's and its scene
//! file's lines, comments (`#` lines, this block among them), blank lines and trailing white
//! space left out: editing a bound, a sweep, a setting or the scene invalidates the record;
//! rewording a comment does not. Files the scene references (textures, glTF assets) and the
//! renderers' code are not covered: a change there is verified by running the full studies
//! again before the change lands.
//!
//! The `oracle` line is the hash of the oracle's source that rendered the run's ground truths
//! (the one the ground-truth cache keys on; absent from records older than the line). A record
//! made with another oracle stands as [`Standing::OtherOracle`]: `--stale` runs its study
//! again, and the studies test lists it without failing. An oracle change is judged by the
//! analytic tests and the Mitsuba z-tests, which hold its expected values; what it can move in
//! a record is the ground truth's noise (its sample sets), so the record is due again, not
//! wrong.

use std::path::Path;

use sha2::{Digest, Sha256};

use serde_json::Value;

/// The first line of a record block.
pub const BEGIN: &str =
    "# --- full-mode record (verity report --all --record; checked by tests/tests/studies.rs) ---";

/// A study file's record of its last full-mode run.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// `YYYY-MM-DD` (UTC).
    pub date: String,
    /// [`fingerprint`] of the study and scene when the run was made.
    pub fingerprint: String,
    /// The oracle's source hash ([`oracle_now`]) of the run; `None` in records made before
    /// the field.
    pub oracle: Option<String>,
    /// Bounds that held.
    pub held: usize,
    /// Bounds checked.
    pub checked: usize,
    /// One line about the run: resolution, samples, time, memory, adapter.
    pub run: String,
    /// One line per bound checked: variant, metric, mask, value, bound, line.
    pub checks: Vec<String>,
}

/// The study and scene text that decides the bounds: lines without comments, blank lines
/// and trailing white space.
fn significant(text: &str) -> impl Iterator<Item = &str> {
    text.lines()
        .map(str::trim_end)
        .filter(|l| !l.is_empty() && !l.trim_start().starts_with('#'))
}

/// The fingerprint of a study file and its scene file (module header).
pub fn fingerprint(study_text: &str, scene_text: &str) -> String {
    let mut h = Sha256::new();
    for (tag, text) in [("study", study_text), ("scene", scene_text)] {
        h.update(tag.as_bytes());
        for line in significant(text) {
            h.update(line.as_bytes());
            h.update(b"\n");
        }
    }
    h.finalize().iter().take(8).map(|b| format!("{b:02x}")).collect()
}

/// The fingerprint of the study file at `study` and its scene `scene`, read from disk.
pub fn fingerprint_files(study: &Path, scene: &Path) -> std::io::Result<String> {
    let read = |p: &Path| {
        std::fs::read_to_string(p).map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", p.display())))
    };
    Ok(fingerprint(&read(study)?, &read(scene)?))
}

/// The hash of the oracle's source this build renders ground truths with (compare/build.rs).
pub fn oracle_now() -> &'static str {
    env!("VERITY_ORACLE_SOURCE_HASH")
}

/// The record block of a study file's text, if it has one.
pub fn read(text: &str) -> Option<Record> {
    let mut lines = text
        .lines()
        .skip_while(|l| l.trim_end() != BEGIN)
        .skip(1)
        .peekable();
    let mut field = |key: &str| {
        let prefix = format!("# {key}: ");
        lines
            .next_if(|l| l.starts_with(&prefix))
            .map(|l| l[prefix.len()..].to_string())
    };
    let date = field("date")?;
    let fingerprint = field("fingerprint")?;
    let oracle = field("oracle");
    let bounds = field("bounds")?;
    let run = field("run")?;
    let (held, checked) = bounds.strip_suffix(" hold")?.split_once(" of ")?;
    let checks = lines
        .take_while(|l| l.starts_with("#   "))
        .map(|l| l["#   ".len()..].to_string())
        .collect();
    Some(Record {
        date,
        fingerprint,
        oracle,
        held: held.parse().ok()?,
        checked: checked.parse().ok()?,
        run,
        checks,
    })
}

/// Where a study stands against its full-mode record.
#[derive(Clone, Debug, PartialEq)]
pub enum Standing {
    /// The file has no record block.
    Missing,
    /// The study or its scene changed since the record was made: the fingerprint it carries
    /// (`recorded`) is no longer the files' (`now`).
    Stale {
        /// The fingerprint in the record.
        recorded: String,
        /// The fingerprint of the files as they are.
        now: String,
    },
    /// The record is of the study as it is, but a bound failed in that run.
    Failed(Record),
    /// The record is of the study as it is and every bound held, but its ground truths were
    /// rendered by another oracle (module header): due to be run again.
    OtherOracle(Record),
    /// The record is of the study as it is, and every bound held.
    Current(Record),
}

impl Standing {
    /// One line for messages and summaries.
    pub fn describe(&self) -> String {
        match self {
            Standing::Missing => "no full-mode record".into(),
            Standing::Stale { recorded, now } => format!(
                "full-mode record out of date (fingerprint {recorded}, the files now {now}): the study or its scene changed since"
            ),
            Standing::Failed(r) | Standing::Current(r) => format!(
                "full-mode record of {}: {} of {} bounds held",
                r.date, r.held, r.checked
            ),
            Standing::OtherOracle(r) => format!(
                "full-mode record of {}: {} of {} bounds held, with the ground truths of another oracle ({}; now {})",
                r.date,
                r.held,
                r.checked,
                r.oracle.as_deref().unwrap_or("from before records named it"),
                oracle_now()
            ),
        }
    }
}

/// The standing of the study file at `study` (scene file `scene`) against its record.
pub fn standing(study: &Path, scene: &Path) -> std::io::Result<Standing> {
    let text = std::fs::read_to_string(study)
        .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", study.display())))?;
    let Some(r) = read(&text) else {
        return Ok(Standing::Missing);
    };
    let now = fingerprint_files(study, scene)?;
    Ok(if r.fingerprint != now {
        Standing::Stale {
            recorded: r.fingerprint,
            now,
        }
    } else if r.held < r.checked || r.checked == 0 {
        Standing::Failed(r)
    } else if r.oracle.as_deref() != Some(oracle_now()) {
        Standing::OtherOracle(r)
    } else {
        Standing::Current(r)
    })
}

/// The record block's lines for `record`.
pub fn block(record: &Record) -> String {
    let mut s = format!(
        "{BEGIN}\n# date: {}\n# fingerprint: {}\n",
        record.date, record.fingerprint
    );
    if let Some(oracle) = &record.oracle {
        s += &format!("# oracle: {oracle}\n");
    }
    s += &format!(
        "# bounds: {} of {} hold\n# run: {}\n",
        record.held, record.checked, record.run
    );
    for c in &record.checks {
        s += &format!("#   {c}\n");
    }
    s
}

/// `text` with its record block (if any) replaced by `record`'s, at the end of the file.
pub fn with_record(text: &str, record: &Record) -> String {
    let kept: Vec<&str> = match text.lines().position(|l| l.trim_end() == BEGIN) {
        Some(start) => {
            let after = text
                .lines()
                .skip(start + 1)
                .take_while(|l| l.starts_with("# "))
                .count();
            let lines: Vec<&str> = text.lines().collect();
            lines[..start]
                .iter()
                .chain(&lines[start + 1 + after..])
                .copied()
                .collect()
        }
        None => text.lines().collect(),
    };
    let mut body = kept.join("\n");
    while body.ends_with('\n') {
        body.pop();
    }
    format!("{body}\n\n{}", block(record))
}

/// The record of a finished full-mode run, from its `metrics.json` (compare/README.md), of a
/// study whose files have `fingerprint`, dated `date`, made by this build (its oracle is
/// [`oracle_now`]); `None` for a quick run or a file that lacks the fields.
pub fn from_metrics(json: &Value, fingerprint: String, date: String) -> Option<Record> {
    let run = &json["run"];
    if run["mode"] != "full" {
        return None;
    }
    let res = run["resolution"].as_array()?;
    let peak = run["peak_memory_bytes"]
        .as_u64()
        .map(|b| format!(", peak memory {}", scenes::budget::human(b)))
        .unwrap_or_default();
    let thresholds = json["thresholds"].as_array()?;
    let checks = thresholds.iter().map(check_line).collect();
    Some(Record {
        date,
        fingerprint,
        oracle: Some(oracle_now().to_string()),
        held: thresholds.iter().filter(|t| t["passed"] == true).count(),
        checked: thresholds.len(),
        run: format!(
            "{}x{}, ground truth {} spp, {:.1} s{peak}, {}",
            res.first()?.as_u64()?,
            res.get(1)?.as_u64()?,
            run["ground_truth_spp"].as_u64()?,
            run["wall_seconds"].as_f64()?,
            json["adapter"]["name"].as_str()?
        ),
        checks,
    })
}

/// One bound checked, as a record line: `variant [visibility |second_ground_truth ]metric over mask = value
/// (min …, max …)[ FAILED] [line N]`.
fn check_line(t: &Value) -> String {
    let text = |k: &str| t[k].as_str().unwrap_or("?").to_string();
    let mut bound = Vec::new();
    if let Some(lo) = t["min"].as_f64() {
        bound.push(format!("min {lo:e}"));
    }
    if let Some(hi) = t["max"].as_f64() {
        bound.push(format!("max {hi:e}"));
    }
    let value = t["value"]
        .as_f64()
        .map_or("NaN".to_string(), |v| format!("{v:.3e}"));
    let location = text("location");
    format!(
        "{} {}{} over {} = {value} ({}){} [line {}]",
        text("variant"),
        match t["on"].as_str() {
            Some("visibility") => "visibility ",
            Some("second_ground_truth") => "second_ground_truth ",
            _ => "",
        },
        text("metric"),
        text("mask"),
        bound.join(", "),
        if t["passed"] == true { "" } else { " FAILED" },
        location.rsplit(':').next().unwrap_or("?"),
    )
}

/// Today's date in UTC, `YYYY-MM-DD`: days since 1970-01-01 to the proleptic Gregorian
/// calendar by Hinnant's `civil_from_days` ("chrono-Compatible Low-Level Date Algorithms",
/// 2013).
pub fn today() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    civil_date((secs / 86_400) as i64)
}

/// `YYYY-MM-DD` of day `z` after 1970-01-01 (Hinnant's `civil_from_days`).
fn civil_date(z: i64) -> String {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_follow_the_gregorian_calendar() {
        assert_eq!(civil_date(0), "1970-01-01");
        assert_eq!(civil_date(11_016), "2000-02-29");
        assert_eq!(civil_date(20_790), "2026-12-03");
        assert_eq!(civil_date(-1), "1969-12-31");
    }

    #[test]
    fn the_fingerprint_follows_bounds_not_comments() {
        let study = "scene = \"s.toml\"\n[[threshold]]\nmax = 1e-3\n";
        let scene = "[camera]\nfov = 40\n";
        let f = fingerprint(study, scene);
        assert_eq!(f.len(), 16);
        assert_eq!(
            f,
            fingerprint(&format!("# a comment\n{study}\n\n# another  \n"), scene)
        );
        assert_ne!(f, fingerprint(&study.replace("1e-3", "2e-3"), scene));
        assert_ne!(f, fingerprint(study, &scene.replace("40", "41")));
    }

    #[test]
    fn a_record_comes_from_a_full_runs_metrics() {
        let json: Value = serde_json::from_str(
            r#"{"run": {"mode": "full", "resolution": [256, 256], "ground_truth_spp": 64,
                        "wall_seconds": 205.85, "peak_memory_bytes": 2469884000},
                "adapter": {"name": "llvmpipe (LLVM 15.0.6, 256 bits)"},
                "thresholds": [
                  {"variant": "envmap_cube(size=128)", "metric": "relmse", "on": "image", "mask": "ball",
                   "value": 0.000231, "max": 0.001, "min": null, "passed": true, "location": "s.toml:60"},
                  {"variant": "envmap_sphere(size=314)", "metric": "relmse", "on": "visibility", "mask": "ball",
                   "value": null, "max": 0.001, "min": 0.0001, "passed": false, "location": "s.toml:68"}]}"#,
        )
        .unwrap();
        let r = from_metrics(&json, "f".repeat(16), "2026-12-03".into()).unwrap();
        assert_eq!((r.held, r.checked), (1, 2));
        assert_eq!(
            r.run,
            "256x256, ground truth 64 spp, 205.8 s, peak memory 2.3 GiB, llvmpipe (LLVM 15.0.6, 256 bits)"
        );
        assert_eq!(
            r.checks[0],
            "envmap_cube(size=128) relmse over ball = 2.310e-4 (max 1e-3) [line 60]"
        );
        assert_eq!(
            r.checks[1],
            "envmap_sphere(size=314) visibility relmse over ball = NaN (min 1e-4, max 1e-3) FAILED [line 68]"
        );
        let mut quick = json.clone();
        quick["run"]["mode"] = "quick".into();
        assert!(
            from_metrics(&quick, String::new(), String::new()).is_none(),
            "only full runs are recorded"
        );
    }

    #[test]
    fn a_study_stands_by_its_record_until_its_bounds_change() {
        let dir = std::env::temp_dir().join(format!("verity-record-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (study, scene) = (dir.join("s.toml"), dir.join("scene.toml"));
        let text = "scene = \"scene.toml\"\n[[threshold]]\nmax = 1e-3\n";
        std::fs::write(&study, text).unwrap();
        std::fs::write(&scene, "[camera]\nfov = 40\n").unwrap();
        assert_eq!(standing(&study, &scene).unwrap(), Standing::Missing);
        let r = Record {
            date: "2026-12-04".into(),
            fingerprint: fingerprint_files(&study, &scene).unwrap(),
            oracle: Some(oracle_now().into()),
            held: 1,
            checked: 1,
            run: "256x256".into(),
            checks: vec![],
        };
        std::fs::write(&study, with_record(text, &r)).unwrap();
        assert_eq!(standing(&study, &scene).unwrap(), Standing::Current(r.clone()));
        let failed = Record { held: 0, ..r.clone() };
        std::fs::write(&study, with_record(text, &failed)).unwrap();
        assert_eq!(standing(&study, &scene).unwrap(), Standing::Failed(failed));
        // Made with another oracle, or before records named it: due again.
        for oracle in [Some("0000000000000000".to_string()), None] {
            let other = Record { oracle, ..r.clone() };
            std::fs::write(&study, with_record(text, &other)).unwrap();
            assert_eq!(standing(&study, &scene).unwrap(), Standing::OtherOracle(other));
        }
        std::fs::write(&study, with_record(&text.replace("1e-3", "2e-3"), &r)).unwrap();
        assert!(matches!(
            standing(&study, &scene).unwrap(),
            Standing::Stale { .. }
        ));
        std::fs::write(&study, with_record(text, &r)).unwrap();
        std::fs::write(&scene, "[camera]\nfov = 41\n").unwrap();
        assert!(matches!(
            standing(&study, &scene).unwrap(),
            Standing::Stale { .. }
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_record_block_reads_back_and_replaces_the_old_one() {
        let r = Record {
            date: "2026-12-03".into(),
            fingerprint: "0123456789abcdef".into(),
            oracle: Some("89abcdef01234567".into()),
            held: 2,
            checked: 3,
            run: "256x256, ground truth 64 spp, 12.0 s, llvmpipe".into(),
            checks: vec!["a relmse over all = 1.000e-3 (max 1e-2) [line 9]".into()],
        };
        let text = "title = \"t\"\n# a comment\n";
        let once = with_record(text, &r);
        assert!(
            once.starts_with("title = \"t\"\n# a comment\n\n# --- full-mode record"),
            "{once}"
        );
        assert_eq!(read(&once), Some(r.clone()));
        let newer = Record { held: 3, ..r.clone() };
        let twice = with_record(&once, &newer);
        assert_eq!(twice.matches(BEGIN).count(), 1, "{twice}");
        assert_eq!(read(&twice), Some(newer));
        // A record from before the oracle line reads with none.
        let old = once.replace("# oracle: 89abcdef01234567\n", "");
        assert_eq!(
            read(&old),
            Some(Record {
                oracle: None,
                ..r.clone()
            })
        );
        assert!(read(text).is_none());
        assert_eq!(
            fingerprint(&twice, ""),
            fingerprint(text, ""),
            "the block is a comment"
        );
    }
}
