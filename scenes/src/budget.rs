//! The memory budget: every size a file or a flag declares is checked against it **before**
//! anything of that size is allocated, so that a 33 KB EXR whose header declares 65536² pixels,
//! or a `--resolution 16384x16384`, is one error line naming the file and field and the bytes
//! needed — never an abort of the process by the allocator.
//!
//! The limit is process-wide ([`limit`]): by default [`DEFAULT_FRACTION`] of the smallest of
//! the machine's physical memory (Linux's `MemTotal`; [`FALLBACK_BYTES`] where it cannot be
//! read), the process's address-space limit (`ulimit -v`, `RLIMIT_AS`) and its cgroup's memory
//! limit (v2 `memory.max`, v1 `memory.limit_in_bytes`), so that a job under a tighter limit
//! than the machine's gets one error line and not an allocation failure; changed by
//! `verity --memory-limit` ([`set_limit`]) or the environment variable `VERITY_MEMORY_LIMIT`
//! (parsed by [`parse_limit`]: bytes, `512M`, `8G`, `1.5GiB`, or `40%` of physical memory).
//!
//! A [`Ledger`] adds up what one job allocates (a scene's textures, displacement grids and
//! meshes as they load; then the renderer's film), so that many moderately large items cannot
//! exceed the limit together: each charge is checked against the limit minus what is already
//! charged. The figures are estimates of the large buffers (texels, vertices, pixels), not of
//! every allocation; the default fraction leaves the rest of the machine's memory for those.

use std::cell::Cell;
use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};

/// Fraction of physical memory the default limit allows.
pub const DEFAULT_FRACTION: f64 = 0.5;

/// The default limit where the machine's memory cannot be read (not Linux).
pub const FALLBACK_BYTES: u64 = 8 << 30;

/// The limit set by [`set_limit`]; 0 means "not set".
static LIMIT: AtomicU64 = AtomicU64::new(0);

/// Where the limit came from, for messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// [`set_limit`] (the `--memory-limit` flag).
    Flag,
    /// The `VERITY_MEMORY_LIMIT` environment variable.
    Environment,
    /// [`DEFAULT_FRACTION`] of physical memory.
    Default {
        /// The machine's physical memory in bytes.
        physical: u64,
    },
    /// [`DEFAULT_FRACTION`] of a limit on this process below physical memory.
    Process {
        /// That limit in bytes.
        bytes: u64,
        /// Which: `address-space limit (ulimit -v)` or `cgroup memory limit`.
        what: &'static str,
    },
    /// [`FALLBACK_BYTES`]: physical memory unknown.
    Fallback,
}

/// The memory limit and where it came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limit {
    /// Bytes.
    pub bytes: u64,
    /// Its origin.
    pub source: Source,
}

impl fmt::Display for Limit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "the memory limit of {}", human(self.bytes))?;
        match self.source {
            Source::Flag => write!(f, " (--memory-limit)"),
            Source::Environment => write!(f, " (VERITY_MEMORY_LIMIT)"),
            Source::Default { physical } => write!(
                f,
                " ({:.0} % of this machine's {}; raise it with --memory-limit)",
                DEFAULT_FRACTION * 100.0,
                human(physical)
            ),
            Source::Process { bytes, what } => write!(
                f,
                " ({:.0} % of this process's {what} of {})",
                DEFAULT_FRACTION * 100.0,
                human(bytes)
            ),
            Source::Fallback => write!(f, " (default; raise it with --memory-limit)"),
        }
    }
}

/// Sets the process-wide limit (the `--memory-limit` flag); it wins over the environment.
pub fn set_limit(bytes: u64) {
    LIMIT.store(bytes.max(1), Ordering::Relaxed);
}

/// The process-wide limit: [`set_limit`]'s, else `VERITY_MEMORY_LIMIT`'s, else the default.
/// An unparsable `VERITY_MEMORY_LIMIT` is ignored here; the CLI reports it (exit 2).
pub fn limit() -> Limit {
    let set = LIMIT.load(Ordering::Relaxed);
    if set > 0 {
        return Limit {
            bytes: set,
            source: Source::Flag,
        };
    }
    if let Some(bytes) = std::env::var("VERITY_MEMORY_LIMIT")
        .ok()
        .and_then(|v| parse_limit(&v).ok())
    {
        return Limit {
            bytes,
            source: Source::Environment,
        };
    }
    let process = [
        (address_space_limit(), "address-space limit (ulimit -v)"),
        (cgroup_memory_limit(), "cgroup memory limit"),
    ]
    .into_iter()
    .filter_map(|(bytes, what)| Some((bytes?, what)))
    .min_by_key(|&(bytes, _)| bytes);
    let fraction = |bytes: u64| (bytes as f64 * DEFAULT_FRACTION) as u64;
    match (physical_memory(), process) {
        (physical, Some((bytes, what))) if physical.is_none_or(|p| bytes < p) => Limit {
            bytes: fraction(bytes),
            source: Source::Process { bytes, what },
        },
        (Some(physical), _) => Limit {
            bytes: fraction(physical),
            source: Source::Default { physical },
        },
        (None, _) => Limit {
            bytes: FALLBACK_BYTES,
            source: Source::Fallback,
        },
    }
}

/// The soft address-space limit of this process (`RLIMIT_AS`, from `/proc/self/limits`), if
/// it has one.
fn address_space_limit() -> Option<u64> {
    parse_address_space_limit(&std::fs::read_to_string("/proc/self/limits").ok()?)
}

/// The soft limit of the `Max address space` row of a `/proc/PID/limits` text; `None` when
/// it is `unlimited` or absent.
fn parse_address_space_limit(limits: &str) -> Option<u64> {
    let row = limits.lines().find(|l| l.starts_with("Max address space"))?;
    row["Max address space".len()..]
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// The memory limit of this process's cgroup, if it has one (below 2⁶²: cgroup v1 writes
/// "no limit" as a number near 2⁶³).
fn cgroup_memory_limit() -> Option<u64> {
    let file = cgroup_limit_file(&std::fs::read_to_string("/proc/self/cgroup").ok()?)?;
    let bytes: u64 = std::fs::read_to_string(file).ok()?.trim().parse().ok()?;
    (bytes < 1 << 62).then_some(bytes)
}

/// The file holding the memory limit of the cgroup a `/proc/PID/cgroup` text names: v2's
/// `memory.max` (the `0::PATH` line) where the unified hierarchy has one, else v1's
/// `memory.limit_in_bytes` of the `memory` controller's line.
fn cgroup_limit_file(cgroup: &str) -> Option<std::path::PathBuf> {
    let root = std::path::Path::new("/sys/fs/cgroup");
    let mut v1 = None;
    for line in cgroup.lines() {
        let mut fields = line.splitn(3, ':');
        let (Some(id), Some(controllers), Some(path)) = (fields.next(), fields.next(), fields.next()) else {
            continue;
        };
        let path = path.trim_start_matches('/');
        if id == "0" && controllers.is_empty() {
            let file = root.join(path).join("memory.max");
            if file.exists() {
                return Some(file);
            }
        } else if controllers.split(',').any(|c| c == "memory") {
            v1 = Some(root.join("memory").join(path).join("memory.limit_in_bytes"));
        }
    }
    v1
}

/// The machine's physical memory in bytes (`MemTotal` of `/proc/meminfo`), if known.
pub fn physical_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The process's peak resident memory so far, bytes (`VmHWM` of `/proc/self/status`), if
/// known.
pub fn peak_resident_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = text.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// Parses a memory size: a whole number of bytes, a number with a binary suffix (`K`, `M`,
/// `G`, `T`, optionally followed by `iB` or `B`: `512M`, `1.5GiB`), or a percentage of
/// physical memory (`40%`). The result is at least 1 MiB and finite.
pub fn parse_limit(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let bad = || {
        format!("`{text}` is not a memory size (expected bytes, or a number with K, M, G or T, or a percentage such as 40%)")
    };
    let (number, scale) = if let Some(p) = t.strip_suffix('%') {
        let physical = physical_memory().ok_or_else(|| {
            format!(
                "`{text}`: a percentage needs the machine's memory, which cannot be read here; give bytes"
            )
        })?;
        (p, physical as f64 / 100.0)
    } else {
        let upper = t.to_ascii_uppercase();
        let stem = upper
            .strip_suffix("IB")
            .or_else(|| upper.strip_suffix('B'))
            .unwrap_or(&upper);
        let (digits, shift) = match stem.chars().last() {
            Some('K') => (&stem[..stem.len() - 1], 10),
            Some('M') => (&stem[..stem.len() - 1], 20),
            Some('G') => (&stem[..stem.len() - 1], 30),
            Some('T') => (&stem[..stem.len() - 1], 40),
            _ => (stem, 0),
        };
        (&t[..digits.len()], (1u64 << shift) as f64)
    };
    let value: f64 = number.trim().parse().map_err(|_| bad())?;
    if !value.is_finite() || value <= 0.0 {
        return Err(bad());
    }
    let bytes = value * scale;
    if bytes < (1u64 << 20) as f64 {
        return Err(format!("`{text}` is less than 1 MiB"));
    }
    if bytes >= u64::MAX as f64 {
        return Err(bad());
    }
    Ok(bytes as u64)
}

/// `n` bytes for people: `1.5 GiB`, `320 MiB`, `12 KiB`, `17 bytes`.
pub fn human(n: u64) -> String {
    const UNITS: [&str; 5] = ["bytes", "KiB", "MiB", "GiB", "TiB"];
    let mut v = n as f64;
    let mut unit = 0;
    while v >= 1024.0 && unit + 1 < UNITS.len() {
        v /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{n} bytes")
    } else {
        format!("{v:.1} {}", UNITS[unit])
    }
}

/// A size times a count, saturating (sizes declared by files can be anything).
pub fn bytes_of(count: u64, each: u64) -> u64 {
    count.saturating_mul(each)
}

/// A charge that does not fit: what needed how much, with what was already charged.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Exceeded {
    /// What was to be allocated ("4096×4096 RGBA f32 texels").
    pub what: String,
    /// Bytes it needs.
    pub needed: u64,
    /// Bytes already charged to the job.
    pub used: u64,
    /// The limit.
    pub limit: Limit,
}

impl fmt::Display for Exceeded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {} ({} bytes) needed",
            self.what,
            human(self.needed),
            self.needed
        )?;
        if self.used > 0 {
            write!(f, " on top of {} already loaded", human(self.used))?;
        }
        write!(f, ", over {}", self.limit)
    }
}

impl std::error::Error for Exceeded {}

/// What one job has allocated so far, against a limit. Not shared between threads: a job
/// loads on one thread.
#[derive(Debug)]
pub struct Ledger {
    limit: Limit,
    used: Cell<u64>,
}

impl Default for Ledger {
    fn default() -> Self {
        Ledger::new()
    }
}

impl Ledger {
    /// An empty ledger against the process-wide [`limit`].
    pub fn new() -> Ledger {
        Ledger::with_limit(limit())
    }

    /// An empty ledger against `limit`.
    pub fn with_limit(limit: Limit) -> Ledger {
        Ledger {
            limit,
            used: Cell::new(0),
        }
    }

    /// The limit.
    pub fn limit(&self) -> Limit {
        self.limit
    }

    /// Bytes charged so far.
    pub fn used(&self) -> u64 {
        self.used.get()
    }

    /// Whether `bytes` more would fit, without charging them.
    pub fn check(&self, bytes: u64, what: impl Into<String>) -> Result<(), Exceeded> {
        let used = self.used.get();
        if used.saturating_add(bytes) > self.limit.bytes {
            return Err(Exceeded {
                what: what.into(),
                needed: bytes,
                used,
                limit: self.limit,
            });
        }
        Ok(())
    }

    /// Charges `bytes` for `what` (to be allocated next), or says why it does not fit.
    pub fn charge(&self, bytes: u64, what: impl Into<String>) -> Result<(), Exceeded> {
        self.check(bytes, what)?;
        self.used.set(self.used.get() + bytes);
        Ok(())
    }
}

/// Checks one allocation of `bytes` for `what` against the process-wide limit alone.
pub fn check(bytes: u64, what: impl Into<String>) -> Result<(), Exceeded> {
    Ledger::new().check(bytes, what)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_address_space_and_cgroup_limits_are_read_from_procfs_text() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units     \n\
                      Max stack size            8388608              unlimited            bytes     \n\
                      Max address space         8192000000           unlimited            bytes     \n";
        assert_eq!(parse_address_space_limit(limits), Some(8_192_000_000));
        let unlimited = limits.replace("8192000000", "unlimited");
        assert_eq!(parse_address_space_limit(&unlimited), None);
        assert_eq!(
            cgroup_limit_file("4:memory:/job/7\n0::/\n"),
            // No unified memory.max under the test's own root: v1's file.
            std::path::Path::new("/sys/fs/cgroup/memory.max")
                .exists()
                .then(|| std::path::PathBuf::from("/sys/fs/cgroup/memory.max"))
                .or(Some(std::path::PathBuf::from(
                    "/sys/fs/cgroup/memory/job/7/memory.limit_in_bytes"
                )))
        );
        assert_eq!(cgroup_limit_file("1:cpu:/\n"), None);
    }

    fn fixed(bytes: u64) -> Limit {
        Limit {
            bytes,
            source: Source::Flag,
        }
    }

    #[test]
    fn sizes_parse_with_binary_suffixes() {
        assert_eq!(parse_limit("1048576"), Ok(1 << 20));
        assert_eq!(parse_limit("512M"), Ok(512 << 20));
        assert_eq!(parse_limit("8G"), Ok(8 << 30));
        assert_eq!(parse_limit("8GiB"), Ok(8 << 30));
        assert_eq!(parse_limit("8gb"), Ok(8 << 30));
        assert_eq!(parse_limit("1.5G"), Ok(3 << 29));
        assert_eq!(parse_limit(" 2T "), Ok(2 << 40));
        for bad in [
            "", "G", "-1G", "nan", "inf", "1e400", "0", "12K", "abc", "5 apples", "1e30T",
        ] {
            assert!(parse_limit(bad).is_err(), "{bad:?} was accepted");
        }
    }

    #[test]
    fn percentages_are_of_physical_memory() {
        if let Some(p) = physical_memory() {
            let half = parse_limit("50%").unwrap();
            assert!((half as f64 - p as f64 / 2.0).abs() < 2.0, "{half} vs {p}");
        }
    }

    #[test]
    fn a_ledger_adds_up_and_refuses_what_does_not_fit() {
        let l = Ledger::with_limit(fixed(100 << 20));
        l.charge(60 << 20, "first").unwrap();
        l.charge(30 << 20, "second").unwrap();
        let e = l.charge(20 << 20, "third texels").unwrap_err();
        assert_eq!(e.needed, 20 << 20);
        assert_eq!(e.used, 90 << 20);
        assert_eq!(l.used(), 90 << 20, "a refused charge is not recorded");
        let m = e.to_string();
        assert_eq!(
            m,
            "third texels: 20.0 MiB (20971520 bytes) needed on top of 90.0 MiB already loaded, \
             over the memory limit of 100.0 MiB (--memory-limit)"
        );
        // Saturating: a declared size of u64::MAX does not wrap around to fit.
        assert!(l.check(u64::MAX, "everything").is_err());
        assert_eq!(bytes_of(u64::MAX, 16), u64::MAX);
    }

    #[test]
    fn human_sizes() {
        assert_eq!(human(17), "17 bytes");
        assert_eq!(human(1536), "1.5 KiB");
        assert_eq!(human(45 << 30), "45.0 GiB");
    }
}
