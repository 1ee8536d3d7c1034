//! A minimal XML tree for Mitsuba 3 scene files (Mitsuba 3 documentation, "File format"):
//! elements with attributes and children, written indented with escaped attribute values.

use std::fmt::Write as _;

use glam::Vec3;

use crate::markup::escape;

/// One XML element.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// Tag name (`shape`, `bsdf`, `float`, …).
    pub tag: String,
    /// Attributes in the order written.
    pub attributes: Vec<(String, String)>,
    /// Child elements.
    pub children: Vec<Element>,
    /// A comment written on the line before the element (no `--` allowed inside; replaced).
    pub comment: Option<String>,
}

impl Element {
    /// `<tag/>`.
    pub fn new(tag: &str) -> Self {
        Element {
            tag: tag.to_string(),
            attributes: Vec::new(),
            children: Vec::new(),
            comment: None,
        }
    }

    /// `<tag type="kind">` (Mitsuba's plugin elements).
    pub fn plugin(tag: &str, kind: &str) -> Self {
        Element::new(tag).attr("type", kind)
    }

    /// Adds an attribute.
    pub fn attr(mut self, key: &str, value: impl Into<String>) -> Self {
        self.attributes.push((key.to_string(), value.into()));
        self
    }

    /// Adds a child.
    pub fn child(mut self, child: Element) -> Self {
        self.children.push(child);
        self
    }

    /// Adds a comment line above the element.
    pub fn with_comment(mut self, comment: impl Into<String>) -> Self {
        self.comment = Some(comment.into());
        self
    }

    /// `<float name="…" value="…"/>`.
    pub fn float(name: &str, value: f32) -> Self {
        Element::new("float").attr("name", name).attr("value", num(value))
    }

    /// `<integer name="…" value="…"/>`.
    pub fn integer(name: &str, value: i64) -> Self {
        Element::new("integer")
            .attr("name", name)
            .attr("value", value.to_string())
    }

    /// `<boolean name="…" value="true|false"/>`.
    pub fn boolean(name: &str, value: bool) -> Self {
        Element::new("boolean")
            .attr("name", name)
            .attr("value", value.to_string())
    }

    /// `<string name="…" value="…"/>`.
    pub fn string(name: &str, value: &str) -> Self {
        Element::new("string").attr("name", name).attr("value", value)
    }

    /// `<rgb name="…" value="r, g, b"/>`.
    pub fn rgb(name: &str, value: Vec3) -> Self {
        Element::new("rgb")
            .attr("name", name)
            .attr("value", triple(value))
    }

    /// `<point name="…" value="x, y, z"/>`.
    pub fn point(name: &str, value: Vec3) -> Self {
        Element::new("point")
            .attr("name", name)
            .attr("value", triple(value))
    }

    /// `<vector name="…" value="x, y, z"/>`.
    pub fn vector(name: &str, value: Vec3) -> Self {
        Element::new("vector")
            .attr("name", name)
            .attr("value", triple(value))
    }

    /// `<ref id="…"/>`.
    pub fn reference(id: &str) -> Self {
        Element::new("ref").attr("id", id)
    }

    /// The element and its children, indented by two spaces per level.
    pub fn render(&self) -> String {
        let mut out = String::new();
        self.write(&mut out, 0);
        out
    }

    fn write(&self, out: &mut String, depth: usize) {
        let pad = "  ".repeat(depth);
        if let Some(c) = &self.comment {
            for line in c.lines() {
                let _ = writeln!(out, "{pad}<!-- {} -->", line.replace("--", "- -"));
            }
        }
        let _ = write!(out, "{pad}<{}", self.tag);
        for (k, v) in &self.attributes {
            let _ = write!(out, " {k}=\"{}\"", escape(v));
        }
        if self.children.is_empty() {
            out.push_str("/>\n");
            return;
        }
        out.push_str(">\n");
        for c in &self.children {
            c.write(out, depth + 1);
        }
        let _ = writeln!(out, "{pad}</{}>", self.tag);
    }
}

/// A float written so that it parses back to the same f32 (Rust's shortest round-trip
/// form); −0 is written as 0.
pub fn num(x: f32) -> String {
    if x == 0.0 {
        "0.0".to_string()
    } else {
        format!("{x:?}")
    }
}

/// `x, y, z` with round-trip floats.
pub fn triple(v: Vec3) -> String {
    format!("{}, {}, {}", num(v.x), num(v.y), num(v.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_nested_elements_with_escaping() {
        let e = Element::plugin("bsdf", "twosided")
            .attr("id", "a<&>\"'")
            .child(
                Element::plugin("bsdf", "diffuse")
                    .child(Element::rgb("reflectance", Vec3::new(0.5, 1.0, 0.1))),
            )
            .with_comment("x -- y");
        let expected = "<!-- x - - y -->\n<bsdf type=\"twosided\" id=\"a&lt;&amp;&gt;&quot;&apos;\">\n  \
                        <bsdf type=\"diffuse\">\n    <rgb name=\"reflectance\" value=\"0.5, 1.0, 0.1\"/>\n  \
                        </bsdf>\n</bsdf>\n";
        assert_eq!(e.render(), expected);
    }

    #[test]
    fn floats_round_trip() {
        for x in [0.1f32, 1.0 / 3.0, 1e-30, 17.0, -0.725, 3.4e38] {
            let s = num(x);
            assert_eq!(s.parse::<f32>().unwrap(), x, "{x} written as {s}");
        }
        assert_eq!(num(-0.0), "0.0");
    }
}
