//! What counts as a correct answer to hostile input (issue 19): exit 0, or the documented
//! failure status with exactly one `error:` line that names the file at fault — never a
//! signal, a hang, a panic (`error: internal error …`), or stderr lines that look like errors
//! but are not Verity's own one-line report.

use super::process::{Ending, Run};

/// Which exit statuses a command documents (compare/README.md "Exit status").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Statuses {
    /// `render`, `report --dry-run`: 0 success, 2 bad input. A render's 1 ("the work
    /// failed") is not an answer to a bad input file: the input must be refused at load.
    Cli,
    /// `verity diff`, idiff's: 0 pass, 1 warn, 2 fail (on stdout) or bad usage (an error
    /// line), 3 size mismatch, 4 a file cannot be read.
    Diff,
}

/// The `error:` lines of `stderr`, after checking that every other line is one Verity or clap
/// writes: notes (`FILE: note: …`, `note: …`), warnings, clap's usage hint, blank lines.
pub fn error_lines(stderr: &str) -> Result<Vec<&str>, String> {
    let mut errors = Vec::new();
    for line in stderr.lines() {
        if line.contains("internal error") || line.contains("panicked") {
            return Err(format!("a panic: {line}"));
        }
        if line.starts_with("error:") {
            errors.push(line);
            continue;
        }
        let ours = line.trim().is_empty()
            || line.starts_with("note: ")
            || line.contains(": note: ")
            || line.starts_with("warning: ")
            || line.contains(": warning: ")
            || line.starts_with("Usage: ")
            || line.starts_with("For more information, try")
            || line.starts_with("  tip: ");
        if !ours {
            return Err(format!(
                "stderr line that is not Verity's (an error must be one `error:` line): {line:?}"
            ));
        }
    }
    Ok(errors)
}

/// Whether one of `names` occurs in `line`.
fn names_one(line: &str, names: &[String]) -> bool {
    names.iter().any(|n| !n.is_empty() && line.contains(n.as_str()))
}

/// Judges `run` of a command with `statuses`; the error line must name one of `names` (the
/// mutated file, or a file it references). Returns the exit status when the answer is
/// acceptable.
pub fn judge(run: &Run, statuses: Statuses, names: &[String]) -> Result<i32, String> {
    let code = match run.ending {
        Ending::Exit(code) => code,
        Ending::Signal(s) => return Err(format!("killed by signal {s} (an abort or a crash)")),
        Ending::Timeout => return Err("ran past its timeout and was killed (a hang)".into()),
    };
    let errors = error_lines(&run.stderr)?;
    let one_error_naming_the_file = || match errors.as_slice() {
        [line] if names_one(line, names) => Ok(code),
        [line] => Err(format!(
            "exit {code}: the error line names none of {names:?}: {line}"
        )),
        _ => Err(format!(
            "exit {code} with {} `error:` lines, expected exactly one",
            errors.len()
        )),
    };
    let no_error = || {
        if errors.is_empty() {
            Ok(code)
        } else {
            Err(format!("exit {code} with an error line: {}", errors[0]))
        }
    };
    match (statuses, code) {
        (_, 0) => {
            no_error()?;
            if statuses == Statuses::Diff {
                finite_figures(&run.stdout)?;
            }
            Ok(0)
        }
        (Statuses::Cli, 2) | (Statuses::Diff, 3 | 4) => one_error_naming_the_file(),
        (Statuses::Diff, 1) => {
            no_error()?;
            finite_figures(&run.stdout).map(|()| 1)
        }
        // A failed comparison is reported on stdout; bad usage as an error line.
        (Statuses::Diff, 2) if errors.is_empty() && run.stdout.contains("FAIL") => Ok(2),
        (Statuses::Diff, 2) => one_error_naming_the_file(),
        _ => Err(format!(
            "exit {code}, which this command does not document for bad input"
        )),
    }
}

/// Every figure `verity diff` printed (`  metric  VALUE  (reference noise floor FLOOR)`) is
/// finite: a pass or a warning computed from NaN is a silent pass.
pub fn finite_figures(stdout: &str) -> Result<(), String> {
    for line in stdout.lines().filter(|l| l.contains("(reference noise floor")) {
        let figures = line
            .split(|c: char| c.is_whitespace() || c == '(' || c == ')')
            .filter(|w| w.parse::<f64>().is_ok());
        for w in figures {
            let v: f64 = w.parse().unwrap_or(f64::NAN);
            if !v.is_finite() {
                return Err(format!("a non-finite figure in a pass or warning: {line}"));
            }
        }
    }
    Ok(())
}
