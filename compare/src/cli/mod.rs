//! The `verity` command line: the top-level parser and one module per subcommand.
//!
//! Exit statuses (compare/README.md): 0 success, 1 the work failed (render or writing the
//! output; `crosscheck`: the renderers disagree), 2 bad usage or bad input (unknown flag,
//! invalid value, unreadable scene, a scene Mitsuba cannot express), 3 an external tool
//! (Mitsuba 3, a GPU adapter for `raster`) cannot be run. Errors
//! are one `error: <message>` line on stderr; a panic is reported the same way, never with a
//! backtrace.

use std::ffi::OsString;
use std::panic::{self, AssertUnwindSafe};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod args;
pub mod bake;
pub mod bench;
pub mod crosscheck;
pub mod diff;
pub mod export_mitsuba;
pub mod merge;
pub mod raster;
pub mod render;
pub mod report;
pub mod report_all;
pub mod run_job;

/// Verity tells a real-time renderer how wrong it is.
#[derive(Debug, Parser)]
#[command(
    name = "verity",
    version,
    about = "Verity: measure real-time rendering approximations against a path-traced ground truth",
    after_help = "Exit status: 0 success, 1 the work failed (or crosscheck: the renderers disagree; report: a declared \
                  bound fails), 2 bad usage or input (or a scene Mitsuba cannot express), 3 Mitsuba or a GPU adapter is \
                  unavailable (see scripts/setup.sh). verity diff: 0 pass, 1 warn, 2 fail, 3 size mismatch, 4 file error."
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,

    /// Memory budget for what files and flags declare (images, meshes, displacement grids,
    /// films, study sizes), checked before allocating: bytes, 512M, 8G, or 40% of physical
    /// memory [default: $VERITY_MEMORY_LIMIT, or 50% of the smallest of physical memory,
    /// `ulimit -v` and the cgroup memory limit].
    #[arg(long, global = true, value_name = "SIZE", value_parser = scenes::budget::parse_limit)]
    pub memory_limit: Option<u64>,

    /// Let glTF assets read files outside their own folder (absolute, `file:` or `..` URIs).
    #[arg(long, global = true)]
    pub allow_paths_outside: bool,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene with the oracle (the CPU path tracer) to a layered EXR and a PNG preview.
    Render(render::RenderArgs),
    /// Export a scene as a Mitsuba 3 XML scene (+ PLY meshes, EXR images), or say what Mitsuba cannot express.
    ExportMitsuba(export_mitsuba::ExportMitsubaArgs),
    /// Render a scene with the oracle and Mitsuba 3 and z-test them per pixel (exit 0 agree, 1 disagree).
    Crosscheck(crosscheck::CrossCheckArgs),
    /// Benchmark: with --vs-mitsuba, the oracle's time to equal error against Mitsuba 3.
    Bench(bench::BenchArgs),
    /// Render a scene with the realtime (wgpu) renderer to a layered EXR and print the timing line.
    Raster(raster::RasterArgs),
    /// Bake a scene's light map (irradiance per texel of each static shape's chart) with the oracle.
    Bake(bake::BakeArgs),
    /// Run a study (default: the built-in area-light study) and write its HTML/JSON/CSV/EXR report.
    Report(report::ReportArgs),
    /// Compare two EXRs, idiff-like (exit 0 pass, 1 warn, 2 fail, 3 size mismatch, 4 file error).
    Diff(diff::DiffArgs),
    /// Assemble the parts of one render (`verity render --part K/N`) into the EXR one render writes.
    Merge(merge::MergeArgs),
    /// Run one ground-truth job of a study's job graph (`verity report STUDY --plan PLAN`).
    RunJob(run_job::RunJobArgs),
}

/// Why a command failed, which decides the exit status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    /// The work itself failed (render error, output not writable): exit status 1.
    Run,
    /// Bad usage or bad input (invalid flag value, unreadable scene): exit status 2.
    Input,
    /// A required external tool (Mitsuba 3, a GPU adapter) cannot be run here: exit status 3.
    Unavailable,
    /// A command-specific status (`verity diff`: 3 size mismatch, 4 file error).
    Status(u8),
}

impl Failure {
    /// The process exit status.
    pub fn exit_status(self) -> u8 {
        match self {
            Failure::Run => 1,
            Failure::Input => 2,
            Failure::Unavailable => 3,
            Failure::Status(code) => code,
        }
    }
}

/// A failed command: what kind of failure, and a message that names the file or flag.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CliError {
    /// Decides the exit status.
    pub failure: Failure,
    /// Printed as `error: <message>`.
    pub message: String,
}

impl CliError {
    /// Bad usage or input (exit status 2).
    pub fn input(message: impl Into<String>) -> Self {
        CliError {
            failure: Failure::Input,
            message: message.into(),
        }
    }

    /// A required external tool cannot be run (exit status 3).
    pub fn unavailable(message: impl Into<String>) -> Self {
        CliError {
            failure: Failure::Unavailable,
            message: message.into(),
        }
    }

    /// The work failed (exit status 1).
    pub fn run(message: impl Into<String>) -> Self {
        CliError {
            failure: Failure::Run,
            message: message.into(),
        }
    }
}

/// The `verity` program: parses `std::env::args_os()` and runs the subcommand.
pub fn main() -> ExitCode {
    ExitCode::from(run())
}

/// [`main`]'s exit status: the program as the `verity` binary runs it (which then ends the
/// process itself where a device was abandoned, src/bin/verity.rs).
pub fn run() -> u8 {
    realtime::gpu::quiet_headless_vulkan();
    exit_status(std::env::args_os())
}

/// Parses `args` (program name first) and runs the subcommand, printing errors on stderr.
pub fn run_from(args: impl IntoIterator<Item = OsString>) -> ExitCode {
    ExitCode::from(exit_status(args))
}

/// [`run_from`]'s exit status.
fn exit_status(args: impl IntoIterator<Item = OsString>) -> u8 {
    let args: Vec<OsString> = args.into_iter().collect();
    let cli = match Cli::try_parse_from(&args) {
        Ok(cli) => cli,
        Err(e) => {
            // clap prints `error: …` with usage for mistakes, and help/version on stdout.
            let _ = e.print();
            return e.exit_code().clamp(0, 255) as u8;
        }
    };
    let command_line = shell_words(&args);
    // A panic is a bug: report it as one error line (with its location), never a backtrace.
    panic::set_hook(Box::new(|info| {
        eprintln!("error: internal error (a bug in verity, please report it): {info}");
    }));
    let outcome = panic::catch_unwind(AssertUnwindSafe(|| dispatch(cli, &command_line)));
    let _ = panic::take_hook();
    match outcome {
        Ok(Ok(code)) => code,
        Ok(Err(e)) => {
            // One line whatever the message quotes from a file (names, paths, parser output).
            eprintln!("error: {}", scenes::error::one_line(&e.message, MAX_ERROR_CHARS));
            e.failure.exit_status()
        }
        Err(_) => Failure::Run.exit_status(),
    }
}

/// Longest error line printed, characters (messages quote files' content, cut to 80 each).
const MAX_ERROR_CHARS: usize = 4000;

/// Runs the subcommand; `Ok` carries the exit status of a command that ran to the end
/// (0, or `verity diff`'s 1 warn / 2 fail, `verity report`'s 1 when a bound fails).
fn dispatch(cli: Cli, command_line: &str) -> Result<u8, CliError> {
    match cli.memory_limit {
        Some(bytes) => scenes::budget::set_limit(bytes),
        None => {
            if let Ok(v) = std::env::var("VERITY_MEMORY_LIMIT") {
                scenes::budget::parse_limit(&v)
                    .map_err(|e| CliError::input(format!("environment variable VERITY_MEMORY_LIMIT: {e}")))?;
            }
        }
    }
    scenes::access::set_outside_allowed(cli.allow_paths_outside);
    match cli.command {
        Command::Render(args) => render::run(&args, command_line).map(|()| 0),
        Command::ExportMitsuba(args) => export_mitsuba::run(&args).map(|()| 0),
        Command::Crosscheck(args) => crosscheck::run(&args).map(|()| 0),
        Command::Bench(args) => bench::run(&args).map(|()| 0),
        Command::Raster(args) => raster::run(&args, command_line).map(|()| 0),
        Command::Bake(args) => bake::run(&args).map(|()| 0),
        Command::Report(args) => report::run(&args),
        Command::Diff(args) => diff::run(&args),
        Command::Merge(args) => merge::run(&args, command_line).map(|()| 0),
        Command::RunJob(args) => run_job::run(&args).map(|()| 0),
    }
}

/// The arguments as one line a POSIX shell would split back into them (for EXR headers):
/// words with characters outside `[A-Za-z0-9_./=:,+@%-]` are single-quoted.
pub fn shell_words(args: &[OsString]) -> String {
    let quote = |a: &OsString| {
        let s = a.to_string_lossy();
        let plain = !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || "_./=:,+@%-".contains(c));
        if plain {
            s.into_owned()
        } else {
            format!("'{}'", s.replace('\'', r"'\''"))
        }
    };
    args.iter().map(quote).collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shell_words_quotes_only_what_needs_it() {
        let args: Vec<OsString> = ["verity", "render", "my scene.toml", "--out=a.exr", "it's", ""]
            .iter()
            .map(OsString::from)
            .collect();
        assert_eq!(
            shell_words(&args),
            r"verity render 'my scene.toml' --out=a.exr 'it'\''s' ''"
        );
    }

    #[test]
    fn cli_definition_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
