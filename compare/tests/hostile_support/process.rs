//! Running `verity` on hostile input as a separate process: the way users meet it, and the
//! only way an abort, a segfault or an allocation failure is observed instead of suffered.
//!
//! Every run gets a timeout (the process is killed and the case fails when it is exceeded),
//! Verity's own memory budget (`--memory-limit`, unless the case sets its own) and, where
//! util-linux's `prlimit` exists, an address-space cap enforced by the kernel
//! (`RLIMIT_AS`), so that an allocation the budget misses fails inside the child (an abort we
//! see) instead of swapping the machine. Only commands that do not rasterise are run here:
//! the realtime renderer's LLVM JIT reserves address space freely and would trip the cap.
//!
//! At most [`slots`] children run at once across all tests of this binary (one per core),
//! whatever the number of test threads; each runs with one render thread
//! (`RAYON_NUM_THREADS=1`).

use std::ffi::OsString;
use std::fs::File;
use std::io::Read;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{Condvar, Mutex, OnceLock};
use std::time::{Duration, Instant};

/// Verity's memory budget for every hostile run (the brief: small enough that a size check
/// that works refuses the reproducers on any machine, large enough for every built-in input).
pub const MEMORY_LIMIT: &str = "1G";

/// The kernel's address-space cap on a child, in bytes: the budget plus room for code, thread
/// stacks and malloc arenas (a tiny render maps about 0.3 GiB).
const ADDRESS_SPACE: u64 = 4 << 30;

/// The default per-process timeout: generous for a tiny input on a loaded 2-core machine; a
/// hang detector, not a speed goal.
pub const TIMEOUT: Duration = Duration::from_secs(30);

/// At most this many bytes of a child's stdout or stderr are kept.
const KEEP_OUTPUT: u64 = 1 << 20;

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ending {
    /// The process exited with this status.
    Exit(i32),
    /// The process was ended by this signal (abort, segfault, the kernel's OOM killer).
    Signal(i32),
    /// The process ran past its timeout and was killed.
    Timeout,
}

/// One finished run.
#[derive(Clone, Debug)]
pub struct Run {
    /// How it ended.
    pub ending: Ending,
    /// Its standard output (at most [`KEEP_OUTPUT`] bytes, lossily decoded).
    pub stdout: String,
    /// Its standard error, likewise.
    pub stderr: String,
}

/// The command line a run executes, for failure messages (`cd DIR && verity ARGS`).
pub fn describe(dir: &Path, args: &[OsString]) -> String {
    let words: Vec<OsString> = std::iter::once(OsString::from("verity"))
        .chain(args.iter().cloned())
        .collect();
    format!("cd {} && {}", dir.display(), compare::cli::shell_words(&words))
}

/// Child slots: one per core, at least 2 (the CI machine's count) and at most 8 (each child
/// may use up to [`MEMORY_LIMIT`]).
pub fn slots() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get().clamp(2, 8))
}

/// A counting semaphore over [`slots`], shared by every test in the binary.
fn gate() -> &'static (Mutex<usize>, Condvar) {
    static GATE: OnceLock<(Mutex<usize>, Condvar)> = OnceLock::new();
    GATE.get_or_init(|| (Mutex::new(slots()), Condvar::new()))
}

/// Holds one child slot until dropped.
struct Slot;

impl Slot {
    fn take() -> Slot {
        let (free, wake) = gate();
        let mut n = free.lock().unwrap_or_else(|e| e.into_inner());
        while *n == 0 {
            n = wake.wait(n).unwrap_or_else(|e| e.into_inner());
        }
        *n -= 1;
        Slot
    }
}

impl Drop for Slot {
    fn drop(&mut self) {
        let (free, wake) = gate();
        *free.lock().unwrap_or_else(|e| e.into_inner()) += 1;
        wake.notify_one();
    }
}

/// Whether `prlimit` can run a command here.
fn have_prlimit() -> bool {
    static HAVE: OnceLock<bool> = OnceLock::new();
    *HAVE.get_or_init(|| {
        Command::new("prlimit")
            .args(["--as=unlimited", "true"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    })
}

/// Runs `verity ARGS` in `dir` under the limits above, with `timeout`. Standard output and
/// error go to `LOGS.stdout` and `LOGS.stderr` (files, so a chatty child never blocks on a
/// pipe).
pub fn verity(dir: &Path, logs: &Path, args: &[OsString], timeout: Duration) -> Run {
    let verity = env!("CARGO_BIN_EXE_verity");
    let mut command = if have_prlimit() {
        let mut c = Command::new("prlimit");
        c.arg(format!("--as={ADDRESS_SPACE}")).arg("--").arg(verity);
        c
    } else {
        Command::new(verity)
    };
    if !args
        .iter()
        .any(|a| a.to_string_lossy().starts_with("--memory-limit"))
    {
        command.args(["--memory-limit", MEMORY_LIMIT]);
    }
    let out_path = logs.with_extension("stdout");
    let err_path = logs.with_extension("stderr");
    let file = |p: &PathBuf| File::create(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    command
        .args(args)
        .current_dir(dir)
        .env_remove("VERITY_MEMORY_LIMIT")
        // One render thread per child: the slots already use every core.
        .env("RAYON_NUM_THREADS", "1")
        .stdin(Stdio::null())
        .stdout(file(&out_path))
        .stderr(file(&err_path));
    let slot = Slot::take();
    let mut child = command
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {verity}: {e}"));
    let start = Instant::now();
    let mut pause = Duration::from_millis(1);
    let ending = loop {
        match child.try_wait() {
            Ok(Some(status)) => {
                break match (status.code(), status.signal()) {
                    (Some(code), _) => Ending::Exit(code),
                    (None, Some(signal)) => Ending::Signal(signal),
                    (None, None) => Ending::Signal(0),
                }
            }
            Ok(None) if start.elapsed() > timeout => {
                let _ = child.kill();
                let _ = child.wait();
                break Ending::Timeout;
            }
            Ok(None) => {
                std::thread::sleep(pause);
                pause = (pause * 2).min(Duration::from_millis(20));
            }
            Err(e) => panic!("waiting for verity: {e}"),
        }
    };
    drop(slot);
    Run {
        ending,
        stdout: read_kept(&out_path),
        stderr: read_kept(&err_path),
    }
}

/// The first [`KEEP_OUTPUT`] bytes of a file, lossily decoded.
fn read_kept(path: &Path) -> String {
    let mut bytes = Vec::new();
    if let Ok(f) = File::open(path) {
        let _ = f.take(KEEP_OUTPUT).read_to_end(&mut bytes);
    }
    String::from_utf8_lossy(&bytes).into_owned()
}
