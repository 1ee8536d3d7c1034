//! Typed, located reads from the value tree: every error names the file, the dotted field
//! and the line, and says what to do.

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::tree::{Lines, Node, Value};
use crate::SceneError;

/// The file being read: its path (for messages), its directory (for relative paths) and
/// its line index.
pub struct Ctx {
    /// The file, for messages.
    pub file: PathBuf,
    /// Its directory, against which relative paths resolve.
    pub dir: PathBuf,
    lines: Lines,
}

impl Ctx {
    /// The context of `file` whose text is `text`.
    pub fn new(file: &Path, text: &str) -> Self {
        let dir = file.parent().map(Path::to_path_buf).unwrap_or_default();
        Ctx {
            file: file.to_path_buf(),
            dir,
            lines: Lines::new(text),
        }
    }

    /// Line of a byte offset.
    pub fn line_of(&self, offset: usize) -> usize {
        self.lines.line(offset)
    }

    /// A path in the scene file resolved against the scene file's directory.
    pub fn resolve(&self, relative: &str) -> PathBuf {
        self.dir.join(relative)
    }
}

/// One value of the file with its dotted path and line.
#[derive(Clone)]
pub struct Field<'a> {
    /// The file.
    pub ctx: &'a Ctx,
    /// The value.
    pub node: &'a Node,
    /// Dotted path of the field (`method[1].sweep.n`).
    pub path: String,
    /// 1-based line, where known.
    pub line: Option<usize>,
}

/// A table of the file: named entries and where the table starts.
#[derive(Clone)]
pub struct Table<'a> {
    /// The file.
    pub ctx: &'a Ctx,
    /// Dotted path of the table.
    pub path: String,
    /// 1-based line of the table, where known.
    pub line: Option<usize>,
    entries: &'a [(String, Node)],
}

/// Joins a dotted path.
fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

impl<'a> Field<'a> {
    /// The document root as a field (path empty).
    pub fn root(ctx: &'a Ctx, node: &'a Node) -> Self {
        Field {
            ctx,
            node,
            path: String::new(),
            line: Some(1),
        }
    }

    fn child(&self, node: &'a Node, path: String) -> Field<'a> {
        let line = node
            .span
            .as_ref()
            .map(|s| self.ctx.line_of(s.start))
            .or(self.line);
        Field {
            ctx: self.ctx,
            node,
            path,
            line,
        }
    }

    /// An error about this field.
    pub fn err(&self, message: impl Into<String>) -> SceneError {
        let mut e = SceneError::new(&self.ctx.file, message);
        if !self.path.is_empty() {
            e = e.field(self.path.clone());
        }
        if let Some(line) = self.line {
            e = e.line(line);
        }
        e
    }

    fn wrong_type(&self, expected: &str) -> SceneError {
        self.err(format!("expected {expected}, found {}", self.node.value.kind()))
    }

    /// A finite number (integers are accepted).
    pub fn f32(&self) -> Result<f32, SceneError> {
        let v = match self.node.value {
            Value::Float(v) => v,
            Value::Integer(v) => v as f64,
            _ => return Err(self.wrong_type("a number")),
        };
        if v.is_nan() {
            return Err(self
                .err("is NaN")
                .hint("every number in a scene file must be finite"));
        }
        let f = v as f32;
        if !f.is_finite() {
            return Err(self
                .err(format!("{v} is not a finite 32-bit float"))
                .hint("every number in a scene file must be finite (|x| < 3.4e38)"));
        }
        Ok(f)
    }

    /// A number > 0.
    pub fn positive(&self) -> Result<f32, SceneError> {
        let v = self.f32()?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(format!("must be > 0, got {v}")))
        }
    }

    /// A number >= 0.
    pub fn non_negative(&self) -> Result<f32, SceneError> {
        let v = self.f32()?;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(format!("must be >= 0, got {v}")))
        }
    }

    /// An integer.
    pub fn i64(&self) -> Result<i64, SceneError> {
        match self.node.value {
            Value::Integer(v) => Ok(v),
            _ => Err(self.wrong_type("an integer")),
        }
    }

    /// An integer in `lo..=hi`.
    pub fn int_in(&self, lo: i64, hi: i64) -> Result<i64, SceneError> {
        let v = self.i64()?;
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(self.err(format!("must be in {lo}..={hi}, got {v}")))
        }
    }

    /// A boolean.
    pub fn bool(&self) -> Result<bool, SceneError> {
        match self.node.value {
            Value::Bool(v) => Ok(v),
            _ => Err(self.wrong_type("true or false")),
        }
    }

    /// A string.
    pub fn str(&self) -> Result<&'a str, SceneError> {
        match &self.node.value {
            Value::String(s) => Ok(s),
            _ => Err(self.wrong_type("a string")),
        }
    }

    /// One of the given words; the error lists them.
    pub fn keyword(&self, allowed: &[&str]) -> Result<&'a str, SceneError> {
        let s = self.str()?;
        if allowed.contains(&s) {
            Ok(s)
        } else {
            Err(self.unknown(s, allowed))
        }
    }

    /// A string from a table of spellings and their values; otherwise the error lists the
    /// spellings, as [`Field::keyword`]'s does.
    pub fn one_of<T: Copy>(&self, table: &[(&str, T)]) -> Result<T, SceneError> {
        let s = self.str()?;
        table
            .iter()
            .find(|(name, _)| *name == s)
            .map(|(_, value)| *value)
            .ok_or_else(|| self.unknown(s, &table.iter().map(|(name, _)| *name).collect::<Vec<_>>()))
    }

    /// `s` is none of `allowed`.
    fn unknown(&self, s: &str, allowed: &[&str]) -> SceneError {
        self.err(format!("unknown value {}", crate::error::echo(s)))
            .hint(format!(
                "use one of {}{}",
                quoted(allowed),
                did_you_mean(s, allowed)
            ))
    }

    /// The elements of an array, as fields `path[i]`.
    pub fn array(&self) -> Result<Vec<Field<'a>>, SceneError> {
        match &self.node.value {
            Value::Array(items) => Ok(items
                .iter()
                .enumerate()
                .map(|(i, n)| self.child(n, format!("{}[{i}]", self.path)))
                .collect()),
            _ => Err(self.wrong_type("an array")),
        }
    }

    /// `N` finite numbers.
    pub fn floats<const N: usize>(&self) -> Result<[f32; N], SceneError> {
        let items = self
            .array()
            .map_err(|_| self.wrong_type(&format!("an array of {N} numbers")))?;
        if items.len() != N {
            return Err(self.err(format!("expected an array of {N} numbers, found {}", items.len())));
        }
        let mut out = [0.0; N];
        for (o, item) in out.iter_mut().zip(&items) {
            *o = item.f32()?;
        }
        Ok(out)
    }

    /// A 3-vector `[x, y, z]`.
    pub fn vec3(&self) -> Result<Vec3, SceneError> {
        self.floats::<3>().map(Vec3::from)
    }

    /// Checks that `path`, the file this field names, is a regular file that exists (a FIFO
    /// is never opened; what exists but is not a file is said so).
    pub fn input_file(&self, path: &Path) -> Result<(), SceneError> {
        match crate::access::regular_file(path) {
            Ok(_) => Ok(()),
            Err(crate::access::FileProblem::NotFound) => Err(self
                .err(format!("file not found: {}", path.display()))
                .hint("paths are relative to the scene file's directory")),
            Err(why) => Err(self.err(format!("{} {why}", path.display()))),
        }
    }

    /// A position or extent in metres, every component within ±[`crate::MAX_COORD`].
    pub fn position(&self) -> Result<Vec3, SceneError> {
        let v = self.vec3()?;
        if v.abs().max_element() > crate::MAX_COORD {
            return Err(self.beyond_world(&format!("{:?}", v.to_array())));
        }
        Ok(v)
    }

    /// A length in metres, |x| within [`crate::MAX_COORD`].
    pub fn length(&self) -> Result<f32, SceneError> {
        let v = self.f32()?;
        if v.abs() > crate::MAX_COORD {
            return Err(self.beyond_world(&format!("{v:?}")));
        }
        Ok(v)
    }

    /// The error for a coordinate or length beyond ±[`crate::MAX_COORD`].
    pub fn beyond_world(&self, shown: &str) -> SceneError {
        self.err(format!("{shown} is beyond ±{:e} m", crate::MAX_COORD))
            .hint("scene coordinates and lengths are limited so that products of them stay finite in f32")
    }

    /// A non-zero 3-vector, normalised.
    pub fn direction(&self) -> Result<Vec3, SceneError> {
        let v = self.vec3()?;
        v.try_normalize()
            .filter(|_| v.length() > 1e-12)
            .ok_or_else(|| self.err("must be a non-zero direction"))
    }

    /// An RGB triple, or one number for grey.
    pub fn rgb(&self) -> Result<Vec3, SceneError> {
        match self.node.value {
            Value::Float(_) | Value::Integer(_) => self.f32().map(Vec3::splat),
            Value::Array(_) => self.vec3(),
            _ => Err(self.wrong_type("an RGB triple [r, g, b] or a number")),
        }
    }

    /// This value as a table.
    pub fn table(&self) -> Result<Table<'a>, SceneError> {
        match &self.node.value {
            Value::Table(entries) => Ok(Table {
                ctx: self.ctx,
                path: self.path.clone(),
                line: self.line,
                entries,
            }),
            _ => Err(self.wrong_type("a table")),
        }
    }

    /// Is this value a table?
    pub fn is_table(&self) -> bool {
        matches!(self.node.value, Value::Table(_))
    }

    /// An array of tables (`[[name]]`), as tables `path[i]`.
    pub fn tables(&self) -> Result<Vec<Table<'a>>, SceneError> {
        if self.is_table() {
            return Err(self
                .err("expected an array of tables, found a single table")
                .hint(format!(
                    "write the header as [[{}]] (double brackets), once per entry",
                    self.path
                )));
        }
        self.array()?.iter().map(Field::table).collect()
    }
}

impl<'a> Table<'a> {
    /// The field `key`, if present.
    pub fn get(&self, key: &str) -> Option<Field<'a>> {
        let (_, node) = self.entries.iter().find(|(k, _)| k == key)?;
        let line = node
            .span
            .as_ref()
            .map(|s| self.ctx.line_of(s.start))
            .or(self.line);
        Some(Field {
            ctx: self.ctx,
            node,
            path: join(&self.path, key),
            line,
        })
    }

    /// The field `key`, which must be present.
    pub fn req(&self, key: &str) -> Result<Field<'a>, SceneError> {
        self.get(key).ok_or_else(|| {
            let mut e =
                SceneError::new(&self.ctx.file, "missing required field").field(join(&self.path, key));
            if let Some(line) = self.line {
                e = e.line(line);
            }
            if self.path.is_empty() {
                e.hint(format!("add a [{key}] section"))
            } else {
                e.hint(format!("add `{key} = …`"))
            }
        })
    }

    /// Every key in document order with its field (for tables of free-form keys).
    pub fn fields(&self) -> Vec<(&'a str, Field<'a>)> {
        self.entries
            .iter()
            .map(|(k, _)| (k.as_str(), self.get(k).expect("key comes from this table")))
            .collect()
    }

    /// Does the table have `key`?
    pub fn has(&self, key: &str) -> bool {
        self.entries.iter().any(|(k, _)| k == key)
    }

    /// The same table under another path (e.g. `shape "floor"` once its name is known).
    pub fn renamed(mut self, path: String) -> Self {
        self.path = path;
        self
    }

    /// An error about the table as a whole.
    pub fn err(&self, message: impl Into<String>) -> SceneError {
        let mut e = SceneError::new(&self.ctx.file, message);
        if !self.path.is_empty() {
            e = e.field(self.path.clone());
        }
        if let Some(line) = self.line {
            e = e.line(line);
        }
        e
    }

    /// Fails on the first key not in `allowed`; `what` names the table in the message
    /// ("a sphere", "the camera").
    pub fn only(&self, allowed: &[&str], what: &str) -> Result<(), SceneError> {
        for (key, _) in self.entries {
            if !allowed.contains(&key.as_str()) {
                let field = self.get(key).expect("key comes from this table");
                return Err(field
                    .err(format!("unknown field `{key}` for {what}"))
                    .hint(format!(
                        "known fields: {}{}",
                        quoted(allowed),
                        did_you_mean(key, allowed)
                    )));
            }
        }
        Ok(())
    }

    /// At most one of `keys` may be present; returns which one is.
    pub fn one_of<'k>(&self, keys: &[&'k str]) -> Result<Option<&'k str>, SceneError> {
        let present: Vec<&'k str> = keys.iter().copied().filter(|k| self.has(k)).collect();
        match present.as_slice() {
            [] => Ok(None),
            [k] => Ok(Some(*k)),
            [a, b, ..] => Err(self
                .get(b)
                .expect("present")
                .err(format!("`{a}` and `{b}` cannot be given together"))
                .hint("keep one of them")),
        }
    }

    /// An optional number with a default.
    pub fn f32_or(&self, key: &str, default: f32) -> Result<f32, SceneError> {
        self.get(key).map_or(Ok(default), |f| f.f32())
    }

    /// An optional boolean with a default.
    pub fn bool_or(&self, key: &str, default: bool) -> Result<bool, SceneError> {
        self.get(key).map_or(Ok(default), |f| f.bool())
    }
}

/// `"a", "b", "c"`.
fn quoted(words: &[&str]) -> String {
    words
        .iter()
        .map(|w| format!("`{w}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// "; did you mean `x`?" for the closest word within edit distance 2, else "".
pub fn did_you_mean(word: &str, candidates: &[&str]) -> String {
    candidates
        .iter()
        .map(|c| (edit_distance(word, c), c))
        .filter(|(d, _)| *d <= 2)
        .min()
        .map(|(_, c)| format!("; did you mean `{c}`?"))
        .unwrap_or_default()
}

/// Levenshtein distance (Wagner & Fischer 1974, "The string-to-string correction problem").
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            let substitution = prev[j] + usize::from(ca != *cb);
            cur[j + 1] = substitution.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distance_matches_hand_counts() {
        let cases = [
            ("radius", "radius", 0),
            ("radus", "radius", 1),
            ("kitten", "sitting", 3),
            ("", "ab", 2),
        ];
        for (a, b, want) in cases {
            assert_eq!(edit_distance(a, b), want, "edit_distance({a:?}, {b:?})");
        }
        assert_eq!(
            did_you_mean("radus", &["center", "radius"]),
            "; did you mean `radius`?"
        );
        assert_eq!(did_you_mean("zzzzzz", &["center", "radius"]), "");
    }
}
