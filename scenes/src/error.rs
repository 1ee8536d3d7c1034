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

/// Untrusted text (a name, a URI from a file) as it may be echoed in a one-line message:
/// quoted, with control characters, quotes and backslashes escaped (so a newline or U+202E
/// cannot break or reorder the line), and cut to 80 characters.
pub fn quoted(text: &str) -> String {
    const MAX_CHARS: usize = 80;
    let mut out = String::from("\"");
    for (i, c) in text.chars().enumerate() {
        if i == MAX_CHARS {
            out.push('…');
            break;
        }
        if c.is_control() || c == '"' || c == '\\' || is_bidi_control(c) {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out.push('"');
    out
}

/// Unicode bidirectional formatting characters (UAX #9, §2): they reorder what a terminal
/// shows after them.
fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{061c}' | '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
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

#[cfg(test)]
mod tests {
    use super::quoted;

    #[test]
    fn quoted_text_stays_on_one_line_in_order_and_short() {
        assert_eq!(quoted("lamp"), "\"lamp\"");
        assert_eq!(quoted("a\nb"), "\"a\\nb\"");
        assert_eq!(quoted("say \"hi\""), "\"say \\\"hi\\\"\"");
        assert_eq!(quoted("x\u{202e}y"), "\"x\\u{202e}y\"");
        let long = "n".repeat(10_000_000);
        assert_eq!(quoted(&long).chars().count(), 80 + 3);
    }
}
