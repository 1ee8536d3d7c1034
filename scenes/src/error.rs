//! The one error type of scene loading: every message names the file, the field (with its
//! TOML line where known) and what to do about it.

use std::fmt;
use std::path::{Path, PathBuf};

/// A scene could not be loaded. Display: `FILE:LINE: field `FIELD`: MESSAGE (hint: HINT)`.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// The file at fault (the scene, or a file it references).
    pub file: PathBuf,
    /// Dotted path of the offending field, e.g. `shape[2].radius` or `camera.fov`.
    pub field: Option<String>,
    /// 1-based line in `file`, where known.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
    /// What to do about it.
    pub hint: Option<String>,
}

impl SceneError {
    /// An error about `file` as a whole.
    pub fn new(file: impl AsRef<Path>, message: impl Into<String>) -> Self {
        SceneError {
            file: file.as_ref().to_path_buf(),
            field: None,
            line: None,
            message: message.into(),
            hint: None,
        }
    }

    /// Names the offending field.
    pub fn field(mut self, field: impl Into<String>) -> Self {
        self.field = Some(field.into());
        self
    }

    /// Sets the 1-based line.
    pub fn line(mut self, line: usize) -> Self {
        self.line = Some(line);
        self
    }

    /// Adds advice.
    pub fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ": ")?;
        if let Some(field) = &self.field {
            write!(f, "field `{field}`: ")?;
        }
        write!(f, "{}", self.message)?;
        if let Some(hint) = &self.hint {
            write!(f, " (hint: {hint})")?;
        }
        Ok(())
    }
}

impl std::error::Error for SceneError {}

/// Longest text [`echo`] keeps, in characters.
pub const ECHO_CHARS: usize = 80;

/// `text` as it may appear inside a one-line message: quoted and escaped like Rust's `{:?}`
/// (so a newline, a control character or U+202E cannot break or reorder the line) and cut
/// to [`ECHO_CHARS`] characters with `…` (so a 10 MB name from a file stays short).
pub fn echo(text: &str) -> String {
    let (head, cut) = cut(text, ECHO_CHARS);
    format!("{head:?}{cut}")
}

/// `text` (a message that may quote a file's content, like a JSON parser's) on one line: every
/// character that `{:?}` would escape except quotes and backslashes (line breaks, control and
/// bidirectional-format characters) is written escaped, and the text is cut to `max_chars`
/// characters with `…`.
pub fn one_line(text: &str, max_chars: usize) -> String {
    let (head, cut) = cut(text, max_chars);
    let mut out = String::with_capacity(head.len());
    for c in head.chars() {
        if matches!(c, '"' | '\\' | '\'') || c.escape_debug().nth(1).is_none() {
            out.push(c);
        } else {
            out.extend(c.escape_debug());
        }
    }
    out + cut
}

/// The first `max_chars` characters of `text`, and `…` if that cut anything.
fn cut(text: &str, max_chars: usize) -> (&str, &'static str) {
    match text.char_indices().nth(max_chars) {
        Some((at, _)) => (&text[..at], "…"),
        None => (text, ""),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn echoed_text_stays_on_one_short_line() {
        assert_eq!(echo("Cube.001"), "\"Cube.001\"");
        assert_eq!(echo("a\nb\u{202e}c"), "\"a\\nb\\u{202e}c\"");
        let long = "x".repeat(10_000_000);
        assert_eq!(echo(&long), format!("\"{}\"…", "x".repeat(ECHO_CHARS)));
        assert_eq!(
            one_line("expected `,` at line 3\n\u{202e}", 100),
            "expected `,` at line 3\\n\\u{202e}"
        );
        assert_eq!(one_line("unknown variant `é\"`", 100), "unknown variant `é\"`");
        assert_eq!(one_line("abcdef", 3), "abc…");
    }
}
