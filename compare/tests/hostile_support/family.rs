//! A mutation family: seeded mutations of every built-in input of one kind, each run through
//! `verity` as its own process and judged ([`super::judge`]), on all cores.
//!
//! Case `i` mutates original `i mod N` with the generator [`Rng::for_case`]`(seed, i)`, so a
//! failure is reproduced from the family's seed and the case number alone:
//! `VERITY_HOSTILE_CASE=<tag>:<i> cargo test -p compare --test hostile_input` runs just that
//! case. A failing input is kept in `target/tmp/hostile-failures/<tag>/case-<i>/` with a
//! `case.txt` that says what was mutated, the command and why it failed. Failures are grouped
//! by their kind (a signal, a hang, a second stderr line, …) and reported with a few
//! examples of each; a family stops after [`MAX_FAILURES`] failures or [`MAX_HANGS`] hangs:
//! enough to diagnose, without waiting out a timeout per case.

use std::collections::BTreeMap;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use super::judge::{judge, Statuses};
use super::process::{self, Run};
use super::rng::Rng;
use super::{exr, gltf, mutate};

/// A family stops after this many failures…
pub const MAX_FAILURES: usize = 40;

/// …or this many hangs (each costs a whole timeout).
pub const MAX_HANGS: usize = 4;

/// Examples kept of each kind of failure.
const EXAMPLES: usize = 3;

/// How inputs of a family are mutated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// TOML text (scenes, studies): structure-aware text edits, sometimes bytes.
    Toml,
    /// glTF JSON or GLB.
    Gltf,
    /// OpenEXR.
    Exr,
    /// A binary file of Verity's own (a part): byte-level mutations.
    Binary,
}

/// A family of mutation cases.
pub struct Family {
    /// For people ("scene TOML").
    pub name: &'static str,
    /// For folders and `VERITY_HOSTILE_CASE` ("scene").
    pub tag: &'static str,
    /// The family's seed.
    pub seed: u64,
    /// Number of cases.
    pub cases: usize,
    /// How to mutate.
    pub kind: Kind,
    /// Which exit statuses the command documents.
    pub statuses: Statuses,
}

/// What one case needs to run and be judged.
pub struct Plan {
    /// The folder to run in.
    pub dir: PathBuf,
    /// `verity`'s arguments.
    pub args: Vec<OsString>,
}

/// A fresh, empty folder `target/tmp/<parts…>`.
pub fn fresh_dir(parts: &[&str]) -> PathBuf {
    let mut d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    d.extend(parts);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
    d
}

/// Creates the FIFO `dir/fifo` (coreutils `mkfifo`: no unsafe code in the test). Opening it
/// for reading blocks until a writer comes, which none does: a reader that does not check the
/// file type first hangs.
pub fn make_fifo(dir: &Path) {
    let status = std::process::Command::new("mkfifo")
        .arg(dir.join("fifo"))
        .status()
        .unwrap_or_else(|e| panic!("mkfifo: {e}"));
    assert!(status.success(), "mkfifo {}/fifo failed", dir.display());
}

/// The case `VERITY_HOSTILE_CASE=<tag>:<i>` asks for: `None` runs every case; `Some(None)` none
/// of this family; `Some(Some(i))` only case `i`.
fn selected(tag: &str) -> Option<Option<usize>> {
    let want = std::env::var("VERITY_HOSTILE_CASE").ok()?;
    let (t, i) = want.split_once(':')?;
    Some(if t == tag { i.parse().ok() } else { None })
}

/// A failed case, kept for the report.
struct Failure {
    index: usize,
    kind: String,
    text: String,
}

/// The kind of a failure: its reason up to the first `:` or `(`, without digits ("exit 1,
/// which this command does not document" and "exit 3, …" are one kind).
fn kind_of(why: &str) -> String {
    let head = why.split([':', '(']).next().unwrap_or(why);
    head.chars()
        .filter(|c| !c.is_ascii_digit())
        .collect::<String>()
        .trim()
        .to_string()
}

/// Mutates `data` (the content of `original`) for case `rng`: one to three mutations of the
/// family's kind. Returns their descriptions.
fn mutate_input(kind: Kind, rng: &mut Rng, data: &mut Vec<u8>, strings: &[String]) -> Vec<String> {
    let rounds = 1 + usize::from(rng.chance(1, 4)) + usize::from(rng.chance(1, 8));
    (0..rounds)
        .map(|_| match kind {
            Kind::Toml if rng.chance(3, 4) => {
                let mut text = String::from_utf8_lossy(data).into_owned();
                let what = mutate::toml(rng, &mut text, strings);
                *data = text.into_bytes();
                what
            }
            Kind::Gltf => gltf::mutate(rng, data, strings),
            Kind::Exr if rng.chance(3, 4) => exr::mutate(rng, data),
            _ => mutate::bytes(rng, data),
        })
        .collect()
}

/// Runs the family over `originals`. For each case, the mutated copy of an original is
/// written beside it as `mut-w<worker>-<name>` (so its relative references resolve), `plan`
/// turns (mutated file, worker folder) into the command, and the run must pass
/// [`judge`] (naming the mutated file or one of `names`) and `extra` (a family's own
/// rule on an accepted run). Unmutated originals are run first: each must exit 0, or the
/// harness itself is wrong. Panics with every failure; prints the counts.
pub fn run(
    family: &Family,
    originals: &[PathBuf],
    names: &[String],
    plan: &(dyn Fn(&Path, &Path) -> Plan + Sync),
    extra: &(dyn Fn(&Path, &Run, i32) -> Result<(), String> + Sync),
) {
    assert!(!originals.is_empty(), "{}: no inputs", family.name);
    let only = selected(family.tag);
    if only == Some(None) {
        println!("{}: skipped by VERITY_HOSTILE_CASE", family.name);
        return;
    }
    let work = fresh_dir(&["hostile", family.tag, "work"]);
    let failures_dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("hostile-failures")
        .join(family.tag);
    let _ = std::fs::remove_dir_all(&failures_dir);
    let started = Instant::now();

    // The originals themselves: exit 0 (a mutation of a broken input proves nothing).
    for (k, original) in originals.iter().enumerate() {
        let worker = work.join(format!("original-{k}"));
        std::fs::create_dir_all(&worker).unwrap_or_else(|e| panic!("{e}"));
        let p = plan(original, &worker);
        let r = process::verity(&p.dir, &worker.join("log"), &p.args, process::TIMEOUT);
        let code = judge(&r, family.statuses, names);
        assert_eq!(
            code,
            Ok(0),
            "{}: the unmutated input {} must pass\n{}\nstdout:\n{}\nstderr:\n{}",
            family.name,
            original.display(),
            process::describe(&p.dir, &p.args),
            r.stdout,
            r.stderr
        );
    }

    let indices: Vec<usize> = match only {
        Some(Some(i)) => vec![i],
        _ => (0..family.cases).collect(),
    };
    let next = AtomicUsize::new(0);
    let statuses: Mutex<BTreeMap<i32, usize>> = Mutex::new(BTreeMap::new());
    let failures: Mutex<Vec<Failure>> = Mutex::new(Vec::new());
    let strings_by_dir: Mutex<BTreeMap<PathBuf, Vec<String>>> = Mutex::new(BTreeMap::new());
    std::thread::scope(|s| {
        for w in 0..process::slots() {
            let (next, statuses, failures, indices, work) = (&next, &statuses, &failures, &indices, &work);
            let (failures_dir, strings_by_dir) = (&failures_dir, &strings_by_dir);
            s.spawn(move || loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(&index) = indices.get(k) else { break };
                {
                    let f = failures.lock().unwrap_or_else(|e| e.into_inner());
                    let hangs = f.iter().filter(|f| f.kind.contains("timeout")).count();
                    if f.len() >= MAX_FAILURES || hangs >= MAX_HANGS {
                        break;
                    }
                }
                let original = &originals[index % originals.len()];
                let dir = original.parent().unwrap_or(Path::new("."));
                let strings = strings_by_dir
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .entry(dir.to_path_buf())
                    .or_insert_with(|| mutate::hostile_strings(dir))
                    .clone();
                let mut rng = Rng::for_case(family.seed, index as u64);
                let mut data = std::fs::read(original).unwrap_or_else(|e| panic!("{}: {e}", original.display()));
                let what = mutate_input(family.kind, &mut rng, &mut data, &strings);
                let file_name = original.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                let mutated = dir.join(format!("mut-w{w}-{file_name}"));
                std::fs::write(&mutated, &data).unwrap_or_else(|e| panic!("{}: {e}", mutated.display()));
                let worker = work.join(format!("w{w}"));
                let _ = std::fs::create_dir_all(&worker);
                let p = plan(&mutated, &worker);
                let r = process::verity(&p.dir, &worker.join("log"), &p.args, process::TIMEOUT);
                let mut names = names.to_vec();
                names.push(format!("mut-w{w}-{file_name}"));
                let verdict = judge(&r, family.statuses, &names).and_then(|code| extra(&mutated, &r, code).map(|()| code));
                match verdict {
                    Ok(code) => {
                        *statuses.lock().unwrap_or_else(|e| e.into_inner()).entry(code).or_default() += 1;
                    }
                    Err(why) => {
                        let keep = failures_dir.join(format!("case-{index}"));
                        let _ = std::fs::create_dir_all(&keep);
                        let _ = std::fs::write(keep.join(format!("mut-w{w}-{file_name}")), &data);
                        let text = format!(
                            "{} case {index} (seed {:#x}): {}\n  mutations of {}: {}\n  command: {}\n  input kept in {}\n  stderr: {}",
                            family.name,
                            family.seed,
                            why,
                            original.display(),
                            what.join("; "),
                            process::describe(&p.dir, &p.args),
                            keep.display(),
                            r.stderr.lines().take(5).collect::<Vec<_>>().join(" | ")
                        );
                        let _ = std::fs::write(keep.join("case.txt"), &text);
                        let kind = kind_of(&why);
                        failures.lock().unwrap_or_else(|e| e.into_inner()).push(Failure { index, kind, text });
                    }
                }
            });
        }
    });
    let statuses = statuses.into_inner().unwrap_or_else(|e| e.into_inner());
    let mut failures = failures.into_inner().unwrap_or_else(|e| e.into_inner());
    failures.sort_by_key(|f| f.index);
    let passed: usize = statuses.values().sum();
    let by_status: Vec<String> = statuses.iter().map(|(c, n)| format!("{n} exit {c}")).collect();
    println!(
        "hostile mutations, {}: {} cases from {} inputs (seed {:#x}), {} passed ({}), {} failed, {:.1} s",
        family.name,
        passed + failures.len(),
        originals.len(),
        family.seed,
        passed,
        by_status.join(", "),
        failures.len(),
        started.elapsed().as_secs_f64()
    );
    if !failures.is_empty() {
        let ran = passed + failures.len();
        let stopped = if ran < indices.len() {
            format!(" (stopped after {ran} of {} cases)", indices.len())
        } else {
            String::new()
        };
        let mut kinds: BTreeMap<&str, Vec<&Failure>> = BTreeMap::new();
        for f in &failures {
            kinds.entry(f.kind.as_str()).or_default().push(f);
        }
        let report: Vec<String> = kinds
            .iter()
            .map(|(kind, fs)| {
                let examples: Vec<&str> = fs.iter().take(EXAMPLES).map(|f| f.text.as_str()).collect();
                format!("== {} × {kind}\n\n{}", fs.len(), examples.join("\n\n"))
            })
            .collect();
        panic!(
            "{}: {} of {ran} cases failed{stopped}, {} kinds of failure (a few examples of each; every failing input is kept in {}):\n\n{}",
            family.name,
            failures.len(),
            kinds.len(),
            failures_dir.display(),
            report.join("\n\n")
        );
    }
    assert!(
        only.is_some() || passed >= family.cases,
        "{}: only {passed} of {} cases ran",
        family.name,
        family.cases
    );
}

/// A copy of the built-in scenes, studies and assets (`scenes/*.toml` but the crate's
/// `Cargo.toml`, `displacement/`,
/// `studies/`, `studies/scenes/`, `assets/`) in `target/tmp/hostile/<tag>/scenes`, with a
/// FIFO `fifo` in every folder, so that mutated copies resolve their references as the
/// originals do. Returns the copy's root.
pub fn mirror_scenes(tag: &str) -> PathBuf {
    let root = fresh_dir(&["hostile", tag, "scenes"]);
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    for sub in ["", "displacement", "studies", "studies/scenes", "assets"] {
        let to = root.join(sub);
        std::fs::create_dir_all(&to).unwrap_or_else(|e| panic!("{}: {e}", to.display()));
        let entries = std::fs::read_dir(source.join(sub)).unwrap_or_else(|e| panic!("{sub}: {e}"));
        for entry in entries.flatten() {
            let path = entry.path();
            let keep = path.is_file()
                && (sub == "assets" || path.extension().is_some_and(|e| e == "toml"))
                && !path
                    .extension()
                    .is_some_and(|e| e == "py" || e == "sh" || e == "md")
                && entry.file_name() != "Cargo.toml";
            if keep {
                std::fs::copy(&path, to.join(entry.file_name()))
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            }
        }
        make_fifo(&to);
    }
    root
}

/// The `.toml` files of `dir` (not recursive, not mutated copies), sorted.
pub fn tomls(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter(|p| {
            !p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("mut-"))
        })
        .collect();
    v.sort();
    v
}

/// The file names of every file under `root`: the names an error line may use for the file
/// at fault (the mutated file's own, or one it references).
pub fn file_names(root: &Path) -> Vec<String> {
    let mut names = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.is_file() {
                names.push(entry.file_name().to_string_lossy().into_owned());
            }
        }
    }
    names.sort();
    names
}
