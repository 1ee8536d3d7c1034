//! Deterministic mutations: byte-level (any file) and structure-aware (TOML text, JSON
//! values), with the hostile values of issue 19 — numbers at and beyond the f32 and u32
//! ranges, NaN/inf, paths that leave the scene's folder or name what is not a regular file,
//! names with separators, control characters, emoji and U+202E, very long strings.
//!
//! Each mutation returns a description that, with the case's seed, tells a reader what was
//! done (printed with a failure).

use std::path::Path;

use serde_json::Value;

use super::rng::Rng;

/// Number literals that break ranges and arithmetic: f32 overflow (3e38 squared, 1e30 in a
/// dot product), u32 wrap (2³², 2³²+1), i64 overflow, the film/texture bounds (16384, 65536),
/// subnormal-ish, zero, negatives, and what TOML accepts as special floats.
pub const NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1",
    "1e30",
    "3e38",
    "-3e38",
    "1e-30",
    "4294967296",
    "4294967297",
    "65536",
    "16384",
    "2147483648",
    "9223372036854775807",
    "18446744073709551616",
    "1e400",
    "-0.0",
    "0.5",
    "nan",
    "inf",
    "-inf",
];

/// Numbers for JSON, whose grammar has no NaN or infinity (`NaN` and `Infinity` are there to
/// test that a parser refuses them with a line).
const JSON_NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1",
    "1e30",
    "3e38",
    "-3e38",
    "1e-30",
    "4294967296",
    "4294967297",
    "65536",
    "16384",
    "2147483648",
    "18446744073709551616",
    "1e400",
    "-0",
    "0.5",
    "3.0",
    "NaN",
    "Infinity",
];

/// The hostile strings for inputs whose relative paths resolve in `dir`: escapes (absolute,
/// `file:`, `..` — once as the issue wrote it and once with as many `..` as `dir` is deep,
/// so that it really reaches `/etc/passwd` —, percent-encoded), special files (`/dev/zero`,
/// `/proc/self/environ`, a FIFO `dir/fifo` the caller creates, directories), a very long
/// string, and names no file or channel should carry.
pub fn hostile_strings(dir: &Path) -> Vec<String> {
    let depth = dir.components().count();
    let up = "../".repeat(depth);
    let up_encoded = "%2e%2e/".repeat(depth);
    let mut v: Vec<String> = [
        "/etc/passwd",
        "file:///etc/passwd",
        "../../../../etc/passwd",
        "%2e%2e/%2e%2e/etc/passwd",
        "%2Fetc%2Fpasswd",
        "/dev/zero",
        "/proc/self/environ",
        "fifo",
        ".",
        "/",
        "..",
        "",
        " ",
        "a/b",
        "a:b",
        "a*b",
        "a.b",
        "a\nb",
        "a\u{0}b",
        "\u{1F642}",
        "\u{202E}gnp.exe",
        "C:\\Windows\\win.ini",
        "data:application/octet-stream;base64,AAAA",
        "data:,",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    v.push(format!("{up}etc/passwd"));
    v.push(format!("{up_encoded}etc/passwd"));
    v.push(dir.join("fifo").display().to_string());
    v.push(dir.display().to_string());
    v.push("x".repeat(100_000));
    v.push(format!("{}.png", "a/".repeat(2_000)));
    v
}

/// One byte-level mutation of `data`: flip bits, overwrite, insert, delete, duplicate a chunk,
/// or truncate.
pub fn bytes(rng: &mut Rng, data: &mut Vec<u8>) -> String {
    if data.is_empty() {
        data.push(rng.next_u64() as u8);
        return "byte inserted into an empty file".into();
    }
    let len = data.len();
    let at = rng.below(len);
    match rng.below(6) {
        0 => {
            let n = 1 + rng.below(8);
            for _ in 0..n {
                let i = rng.below(len);
                data[i] ^= 1 << rng.below(8);
            }
            format!("{n} bit(s) flipped")
        }
        1 => {
            let any = rng.next_u64() as u8;
            let v = *rng.pick(&[0x00, 0xff, 0x7f, 0x80, 0x01, any]);
            let n = 1 + rng.below(8);
            let end = (at + n).min(len);
            data[at..end].fill(v);
            format!("bytes {at}..{end} overwritten with {v:#04x}")
        }
        2 => {
            let n = 1 + rng.below(16);
            let junk: Vec<u8> = (0..n).map(|_| rng.next_u64() as u8).collect();
            data.splice(at..at, junk);
            format!("{n} random bytes inserted at {at}")
        }
        3 => {
            let end = (at + 1 + rng.below(64)).min(len);
            data.drain(at..end);
            format!("bytes {at}..{end} deleted")
        }
        4 => {
            let end = (at + 1 + rng.below(256)).min(len);
            let chunk = data[at..end].to_vec();
            let to = rng.below(len);
            data.splice(to..to, chunk);
            format!("bytes {at}..{end} duplicated at {to}")
        }
        _ => {
            data.truncate(at);
            format!("truncated to {at} bytes")
        }
    }
}

/// `s` as a TOML basic string (TOML 1.0 "String": `\\`, `\"`, `\n`, `\uXXXX` escapes).
pub fn toml_quote(s: &str) -> String {
    let mut q = String::with_capacity(s.len() + 2);
    q.push('"');
    for c in s.chars() {
        match c {
            '"' => q.push_str("\\\""),
            '\\' => q.push_str("\\\\"),
            '\n' => q.push_str("\\n"),
            c if c.is_control() => q.push_str(&format!("\\u{:04X}", c as u32)),
            c => q.push(c),
        }
    }
    q.push('"');
    q
}

/// A token of TOML text: its byte range and kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Token {
    Number(usize, usize),
    Str(usize, usize),
}

/// The number and string tokens of TOML text (a light scanner: comments, basic and literal
/// strings, multi-line forms; a number is a run of number characters where a value starts).
fn toml_tokens(text: &str) -> Vec<Token> {
    let b = text.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    let mut last = b'\n';
    while i < b.len() {
        let c = b[i];
        if c == b'#' {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if c == b'"' || c == b'\'' {
            let start = i;
            let triple = b[i..].starts_with(if c == b'"' { b"\"\"\"" } else { b"'''" });
            i += if triple { 3 } else { 1 };
            while i < b.len() {
                if c == b'"' && b[i] == b'\\' {
                    i += 2;
                    continue;
                }
                if b[i] == c && (!triple || b[i..].starts_with(&[c, c, c])) {
                    i += if triple { 3 } else { 1 };
                    break;
                }
                if !triple && b[i] == b'\n' {
                    break;
                }
                i += 1;
            }
            let end = i.min(b.len());
            tokens.push(Token::Str(start, end));
            last = c;
            continue;
        }
        let starts_value = matches!(last, b'=' | b'[' | b',' | b'{');
        let numberish = |x: u8| x.is_ascii_alphanumeric() || matches!(x, b'.' | b'+' | b'-' | b'_');
        if starts_value
            && (c.is_ascii_digit()
                || ((c == b'-' || c == b'+') && b.get(i + 1).is_some_and(u8::is_ascii_digit)))
        {
            let start = i;
            while i < b.len() && numberish(b[i]) {
                i += 1;
            }
            tokens.push(Token::Number(start, i));
            last = b'0';
            continue;
        }
        if !c.is_ascii_whitespace() {
            last = c;
        }
        i += 1;
    }
    tokens
}

/// The byte ranges of the lines of `text` (each with its newline).
fn lines(text: &str) -> Vec<(usize, usize)> {
    let mut v = Vec::new();
    let mut start = 0;
    for (i, c) in text.char_indices() {
        if c == '\n' {
            v.push((start, i + 1));
            start = i + 1;
        }
    }
    if start < text.len() {
        v.push((start, text.len()));
    }
    v
}

/// The byte ranges of the tables of `text`: from a `[header]` line to the next one.
fn tables(text: &str) -> Vec<(usize, usize)> {
    let ls = lines(text);
    let heads: Vec<usize> = ls
        .iter()
        .filter(|(s, _)| text[*s..].starts_with('['))
        .map(|(s, _)| *s)
        .collect();
    heads
        .iter()
        .enumerate()
        .map(|(k, &s)| (s, heads.get(k + 1).copied().unwrap_or(text.len())))
        .collect()
}

/// Values that confuse types where a number, string or table was.
const CONFUSIONS: &[&str] = &[
    "true",
    "[]",
    "{}",
    "\"x\"",
    "0",
    "[[]]",
    "{ a = 1 }",
    "[1, \"a\"]",
];

/// One structure-aware mutation of TOML `text`, with `strings` as the hostile strings.
pub fn toml(rng: &mut Rng, text: &mut String, strings: &[String]) -> String {
    let tokens = toml_tokens(text);
    let numbers: Vec<(usize, usize)> = tokens
        .iter()
        .filter_map(|t| match *t {
            Token::Number(s, e) => Some((s, e)),
            Token::Str(..) => None,
        })
        .collect();
    let quoted: Vec<(usize, usize)> = tokens
        .iter()
        .filter_map(|t| match *t {
            Token::Str(s, e) => Some((s, e)),
            Token::Number(..) => None,
        })
        .collect();
    let ls = lines(text);
    let ts = tables(text);
    let choice = rng.below(10);
    let replace = |text: &mut String, (s, e): (usize, usize), with: &str, what: &str| {
        let old: String = text[s..e].chars().take(40).collect();
        text.replace_range(s..e, with);
        let new: String = with.chars().take(40).collect();
        format!("{what} {old:?} at byte {s} -> {new:?}")
    };
    match choice {
        0..=2 if !numbers.is_empty() => {
            let n = *rng.pick(&numbers);
            let with = *rng.pick(NUMBERS);
            replace(text, n, with, "number")
        }
        3 | 4 if !quoted.is_empty() => {
            let q = *rng.pick(&quoted);
            let with = toml_quote(rng.pick(strings).as_str());
            replace(text, q, &with, "string")
        }
        5 if !tokens.is_empty() => {
            let (s, e) = match *rng.pick(&tokens) {
                Token::Number(s, e) | Token::Str(s, e) => (s, e),
            };
            let with = *rng.pick(CONFUSIONS);
            replace(text, (s, e), with, "value")
        }
        6 if !ls.is_empty() => {
            let (s, e) = *rng.pick(&ls);
            if rng.chance(1, 2) {
                let line = text[s..e].to_string();
                text.insert_str(e, &line);
                format!("line at byte {s} duplicated: {:?}", line.trim_end())
            } else {
                let line: String = text[s..e].chars().take(60).collect();
                text.replace_range(s..e, "");
                format!("line at byte {s} deleted: {:?}", line.trim_end())
            }
        }
        7 if !ts.is_empty() => {
            let (s, e) = *rng.pick(&ts);
            let head: String = text[s..e].lines().next().unwrap_or("").to_string();
            if rng.chance(1, 2) {
                let table = text[s..e].to_string();
                text.insert_str(e, &table);
                format!("table {head} duplicated")
            } else {
                text.replace_range(s..e, "");
                format!("table {head} deleted")
            }
        }
        8 if !ls.is_empty() => {
            let (s, _) = *rng.pick(&ls);
            let key = rng.pick(&[
                "zzz = 1\n",
                "\"a\\u0000b\" = 1\n",
                "[zzz]\n",
                "[[zzz]]\n",
                "name = \"\"\n",
            ]);
            text.insert_str(s, key);
            format!("{:?} inserted at byte {s}", key.trim_end())
        }
        _ => {
            let mut cut = rng.below(text.len().max(1));
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            text.truncate(cut);
            format!("text truncated to {cut} bytes")
        }
    }
}

/// A step of a path into a JSON value.
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

/// Every path in `v` (the root first), depth first.
fn paths(v: &Value, here: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    out.push(here.clone());
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                here.push(Step::Key(k.clone()));
                paths(x, here, out);
                here.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                here.push(Step::Index(i));
                paths(x, here, out);
                here.pop();
            }
        }
        _ => {}
    }
}

/// The value at `path`.
fn get<'a>(v: &'a Value, path: &[Step]) -> Option<&'a Value> {
    path.iter().try_fold(v, |v, s| match s {
        Step::Key(k) => v.get(k.as_str()),
        Step::Index(i) => v.get(*i),
    })
}

/// The value at `path`, to change it.
fn at<'a>(v: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    path.iter().try_fold(v, |v, s| match s {
        Step::Key(k) => v.get_mut(k.as_str()),
        Step::Index(i) => v.get_mut(*i),
    })
}

/// `path` as a JSON pointer-like string for descriptions.
fn show(path: &[Step]) -> String {
    let mut s = String::new();
    for step in path {
        match step {
            Step::Key(k) => {
                s.push('/');
                s.extend(k.chars().take(40));
            }
            Step::Index(i) => s.push_str(&format!("/{i}")),
        }
    }
    if s.is_empty() {
        s.push('/');
    }
    s
}

/// A JSON document under structure-aware mutation: raw literals (numbers JSON cannot hold
/// exactly, or not at all) are parked as marker strings and spliced in by [`Json::finish`].
pub struct Json {
    value: Value,
    raw: Vec<String>,
}

impl Json {
    /// Parses `bytes`, or `None` when they are not JSON.
    pub fn parse(bytes: &[u8]) -> Option<Json> {
        serde_json::from_slice(bytes).ok().map(|value| Json {
            value,
            raw: Vec::new(),
        })
    }

    /// A marker string standing for raw literal `literal`.
    fn raw(&mut self, literal: &str) -> Value {
        self.raw.push(literal.to_string());
        Value::String(format!("\u{1}RAW{}\u{1}", self.raw.len() - 1))
    }

    /// One mutation: a number or string replaced by a hostile one, a value of another type, a
    /// member or element deleted, an element duplicated, an unknown member added.
    pub fn mutate(&mut self, rng: &mut Rng, strings: &[String]) -> String {
        let mut all = Vec::new();
        paths(&self.value, &mut Vec::new(), &mut all);
        let numbers: Vec<&Vec<Step>> = all
            .iter()
            .filter(|p| get(&self.value, p).is_some_and(|v| v.is_number()))
            .collect();
        let texts: Vec<&Vec<Step>> = all
            .iter()
            .filter(|p| get(&self.value, p).is_some_and(|v| v.is_string()))
            .collect();
        let choice = rng.below(8);
        let (path, new): (Vec<Step>, Value) = match choice {
            0..=2 if !numbers.is_empty() => {
                let p = (*rng.pick(&numbers)).clone();
                let lit = *rng.pick(JSON_NUMBERS);
                (p, self.raw(lit))
            }
            3 | 4 if !texts.is_empty() => {
                let p = (*rng.pick(&texts)).clone();
                (p, Value::String(rng.pick(strings).clone()))
            }
            5 => {
                let p = rng.pick(&all).clone();
                let v = rng
                    .pick(&[
                        Value::Null,
                        Value::Bool(true),
                        Value::Array(Vec::new()),
                        Value::Object(Default::default()),
                        Value::String("x".into()),
                        Value::from(0),
                    ])
                    .clone();
                (p, v)
            }
            6 if all.len() > 1 => {
                let p = rng.pick(&all[1..]).clone();
                let (last, parent) = p
                    .split_last()
                    .map(|(l, r)| (l.clone(), r.to_vec()))
                    .unwrap_or((Step::Index(0), Vec::new()));
                let described = show(&p);
                if let Some(parent) = at(&mut self.value, &parent) {
                    match (parent, last) {
                        (Value::Object(m), Step::Key(k)) => {
                            m.remove(&k);
                        }
                        (Value::Array(a), Step::Index(i)) if rng.chance(1, 2) => {
                            a.remove(i);
                        }
                        (Value::Array(a), Step::Index(i)) => {
                            let copy = a[i].clone();
                            a.push(copy);
                            return format!("json {described} duplicated at the end of its array");
                        }
                        _ => {}
                    }
                }
                return format!("json {described} deleted");
            }
            _ => {
                let objects: Vec<&Vec<Step>> = all
                    .iter()
                    .filter(|p| get(&self.value, p).is_some_and(|v| v.is_object()))
                    .collect();
                if objects.is_empty() {
                    return "json unchanged (no object)".into();
                }
                let p = (*rng.pick(&objects)).clone();
                let described = show(&p);
                let key = rng
                    .pick(&["zzz", "extensions", "extras", "uri", "name"])
                    .to_string();
                let value = Value::String(rng.pick(strings).clone());
                if let Some(Value::Object(m)) = at(&mut self.value, &p) {
                    m.insert(key.clone(), value);
                }
                return format!("json {described}: member {key:?} added");
            }
        };
        let described = show(&path);
        let shown = match &new {
            Value::String(s) if s.starts_with('\u{1}') => self.raw.last().cloned().unwrap_or_default(),
            v => v.to_string().chars().take(40).collect(),
        };
        if let Some(slot) = at(&mut self.value, &path) {
            *slot = new;
        }
        format!("json {described} -> {shown}")
    }

    /// The document as text, raw literals spliced in.
    pub fn finish(self) -> Vec<u8> {
        let mut text = self.value.to_string();
        for (i, lit) in self.raw.iter().enumerate() {
            text = text.replace(&format!("\"\\u0001RAW{i}\\u0001\""), lit);
        }
        text.into_bytes()
    }
}
