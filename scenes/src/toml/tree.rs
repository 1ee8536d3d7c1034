//! A TOML document as a tree of values that remember where they stand in the file.
//!
//! `toml::Spanned<T>` gives byte spans, but it rejects tables that have none: the implicit
//! tables that dotted keys (`emission.radiance = …`) and nested headers create. [`Node`] speaks
//! the same span protocol as `Spanned` (the `toml` crate recognises the struct name below and
//! hands over start, end and value) and falls back to "no span" where the parser has none,
//! so every TOML document parses and almost every value knows its line.

use std::fmt;
use std::ops::Range;

use serde::de::{Deserialize, Deserializer, Error as _, MapAccess, SeqAccess, Visitor};

/// The struct name and fields through which `toml` hands spans to `serde_spanned::Spanned`.
const SPANNED: &str = "$__serde_spanned_private_Spanned";
const START: &str = "$__serde_spanned_private_start";
const END: &str = "$__serde_spanned_private_end";
const VALUE: &str = "$__serde_spanned_private_value";
/// The single key of the map through which `toml` hands over a date-time.
const DATETIME: &str = "$__toml_private_datetime";

/// A value and, where the parser knows it, its byte range in the document.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Byte range in the document, where the parser knows it.
    pub span: Option<Range<usize>>,
    /// The value.
    pub value: Value,
}

/// A TOML value whose children are [`Node`]s.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// Keys in document order.
    Table(Vec<(String, Node)>),
    /// An array.
    Array(Vec<Node>),
    /// A float.
    Float(f64),
    /// An integer.
    Integer(i64),
    /// A string.
    String(String),
    /// A boolean.
    Bool(bool),
    /// A date-time, kept as written (scene files have no use for one).
    Datetime(String),
}

impl Value {
    /// "a string", "an integer", … for messages.
    pub fn kind(&self) -> &'static str {
        match self {
            Value::Table(_) => "a table",
            Value::Array(_) => "an array",
            Value::Float(_) => "a float",
            Value::Integer(_) => "an integer",
            Value::String(_) => "a string",
            Value::Bool(_) => "a boolean",
            Value::Datetime(_) => "a date-time",
        }
    }
}

/// Parses a whole document; the root is a table.
pub(crate) fn parse(text: &str) -> Result<Node, ::toml::de::Error> {
    let value: Value = ::toml::from_str(text)?;
    Ok(Node {
        span: Some(0..text.len()),
        value,
    })
}

/// 1-based line numbers of byte offsets.
pub(crate) struct Lines {
    /// Byte offset of every '\n'.
    newlines: Vec<usize>,
}

impl Lines {
    pub fn new(text: &str) -> Self {
        Lines {
            newlines: text.match_indices('\n').map(|(i, _)| i).collect(),
        }
    }

    /// Line of byte `offset`.
    pub fn line(&self, offset: usize) -> usize {
        self.newlines.partition_point(|&n| n < offset) + 1
    }
}

impl<'de> Deserialize<'de> for Node {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_struct(SPANNED, &[START, END, VALUE], NodeVisitor)
    }
}

impl<'de> Deserialize<'de> for Value {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ValueVisitor)
    }
}

fn bare(value: Value) -> Node {
    Node { span: None, value }
}

/// Reads a node: a span-carrying map from the parser, or the plain value where it has no span.
struct NodeVisitor;

impl<'de> Visitor<'de> for NodeVisitor {
    type Value = Node;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a TOML value")
    }

    fn visit_bool<E>(self, v: bool) -> Result<Node, E> {
        Ok(bare(Value::Bool(v)))
    }

    fn visit_i64<E>(self, v: i64) -> Result<Node, E> {
        Ok(bare(Value::Integer(v)))
    }

    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Node, E> {
        ValueVisitor.visit_u64(v).map(bare)
    }

    fn visit_f64<E>(self, v: f64) -> Result<Node, E> {
        Ok(bare(Value::Float(v)))
    }

    fn visit_str<E>(self, v: &str) -> Result<Node, E> {
        Ok(bare(Value::String(v.to_string())))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Node, A::Error> {
        ValueVisitor.visit_seq(seq).map(bare)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Node, A::Error> {
        let Some(first) = map.next_key::<String>()? else {
            return Ok(bare(Value::Table(Vec::new())));
        };
        if first != START {
            return read_table(first, map).map(bare);
        }
        let start: usize = map.next_value()?;
        let (mut end, mut value) = (None, None);
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                END => end = Some(map.next_value::<usize>()?),
                VALUE => value = Some(map.next_value::<Value>()?),
                _ => return Err(A::Error::custom(format!("unexpected span key `{key}`"))),
            }
        }
        match (end, value) {
            (Some(end), Some(value)) => Ok(Node {
                span: Some(start..end),
                value,
            }),
            _ => Err(A::Error::custom("incomplete span from the TOML parser")),
        }
    }
}

/// Reads a plain value whose children are nodes.
struct ValueVisitor;

impl<'de> Visitor<'de> for ValueVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a TOML value")
    }

    fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }

    fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
        Ok(Value::Integer(v))
    }

    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Value, E> {
        i64::try_from(v)
            .map(Value::Integer)
            .map_err(|_| E::custom(format!("integer {v} is out of range")))
    }

    fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
        Ok(Value::Float(v))
    }

    fn visit_str<E>(self, v: &str) -> Result<Value, E> {
        Ok(Value::String(v.to_string()))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::new();
        while let Some(item) = seq.next_element::<Node>()? {
            items.push(item);
        }
        Ok(Value::Array(items))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        match map.next_key::<String>()? {
            Some(first) => read_table(first, map),
            None => Ok(Value::Table(Vec::new())),
        }
    }
}

/// The rest of a table whose first key has been read (or a date-time in disguise).
fn read_table<'de, A: MapAccess<'de>>(first: String, mut map: A) -> Result<Value, A::Error> {
    if first == DATETIME {
        return Ok(Value::Datetime(map.next_value::<String>()?));
    }
    let mut entries = vec![(first, map.next_value::<Node>()?)];
    while let Some((key, node)) = map.next_entry::<String, Node>()? {
        entries.push((key, node));
    }
    Ok(Value::Table(entries))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(node: &Node) -> &[(String, Node)] {
        match &node.value {
            Value::Table(t) => t,
            other => panic!("expected a table, found {other:?}"),
        }
    }

    #[test]
    fn spans_cover_values_and_implicit_tables_parse() {
        let text = "[a]\nx = 1.5\n[[s]]\ne.r = [1, 2]\nd = 1979-05-27\n";
        let root = parse(text).unwrap();
        let lines = Lines::new(text);
        let top = table(&root);
        let a = table(&top[0].1);
        assert_eq!(a[0].0, "x");
        let x_span = a[0].1.span.clone().unwrap();
        assert_eq!(&text[x_span.clone()], "1.5");
        assert_eq!(lines.line(x_span.start), 2);
        let Value::Array(s) = &top[1].1.value else {
            panic!("expected an array of tables")
        };
        let s0 = table(&s[0]);
        // `e` is an implicit table (dotted key): no span, but its child has one.
        assert_eq!(s0[0].1.span, None);
        let r = &table(&s0[0].1)[0].1;
        assert_eq!(lines.line(r.span.clone().unwrap().start), 4);
        assert_eq!(s0[1].1.value, Value::Datetime("1979-05-27".into()));
    }

    #[test]
    fn lines_count_from_one() {
        let lines = Lines::new("a\nb\n\nc");
        let got: Vec<usize> = [0, 1, 2, 4, 5].iter().map(|&o| lines.line(o)).collect();
        assert_eq!(got, vec![1, 1, 2, 3, 4]);
    }
}
