//! Range check of every index in a glTF document before the `gltf` crate reads it.
//!
//! glTF indices are JSON integers ≥ 0 (glTF 2.0 §3.3 "glTF Basics", §5 "glTFid": an integer
//! ≥ 0). The `gltf` crate stores them as `u32` and converts with `as`, so `4294967296` would
//! silently become index 0 (x mod 2³²) and a broken file would load. This pass streams the
//! JSON once (nothing is built), tracking the JSON path, and refuses any index field whose
//! integer does not fit in 32 bits, naming that path. Smaller indices that point past their
//! array are the crate's validator's business (it names the path too).
//!
//! Index fields, by name, as the glTF 2.0 schema and KHR_lights_punctual define them: see
//! [`INDEX_KEYS`]; plus every value of a primitive's `attributes` and of each morph target
//! (`targets[i]`), which map attribute names to accessor indices. `extras` (free-form
//! application data, §3.8.1) is skipped.

use std::fmt;

use serde::de::{DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};

/// Member names whose integer value (or, for arrays, each integer element) is an index.
const INDEX_KEYS: &[&str] = &[
    "buffer",
    "bufferView",
    "camera",
    "children",
    "index",
    "indices",
    "input",
    "inverseBindMatrices",
    "joints",
    "light",
    "material",
    "mesh",
    "node",
    "nodes",
    "output",
    "sampler",
    "scene",
    "skeleton",
    "skin",
    "source",
];

/// Largest index the loader can represent.
const MAX_INDEX: u64 = u32::MAX as u64;

/// An index that does not fit: its JSON path, value and line.
#[derive(Debug, PartialEq, Eq)]
pub(super) struct OutOfRange {
    /// JSON path, e.g. `meshes[0].primitives[0].indices`.
    pub path: String,
    /// The integer found.
    pub value: u64,
    /// 1-based line in the JSON text.
    pub line: usize,
}

/// How to read integers at a place in the document.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    /// Ordinary values.
    Plain,
    /// An index, or an array of them.
    Index,
    /// An object whose every value is an index (`attributes`, a morph target).
    IndexMap,
    /// An array of [`Role::IndexMap`] objects (`targets`).
    IndexMaps,
}

/// One step of the JSON path.
enum Segment {
    Key(String),
    Item(usize),
}

/// The walk's state: where it is, and the first index out of range.
struct Walk {
    path: Vec<Segment>,
    found: Option<(String, u64)>,
}

impl Walk {
    fn path(&self) -> String {
        let mut s = String::new();
        for seg in &self.path {
            match seg {
                Segment::Key(k) if s.is_empty() => s.push_str(k),
                Segment::Key(k) => {
                    s.push('.');
                    s.push_str(k);
                }
                Segment::Item(i) => s.push_str(&format!("[{i}]")),
            }
        }
        s
    }
}

/// Finds the first index in `json` that does not fit in 32 bits. Malformed JSON passes (the
/// `gltf` crate's parse reports it with its path).
pub(super) fn check(json: &[u8]) -> Result<(), OutOfRange> {
    let mut walk = Walk {
        path: Vec::new(),
        found: None,
    };
    let mut de = serde_json::Deserializer::from_slice(json);
    let result = Value {
        walk: &mut walk,
        role: Role::Plain,
    }
    .deserialize(&mut de);
    match (walk.found, result) {
        (Some((path, value)), Err(e)) => Err(OutOfRange {
            path,
            value,
            line: e.line(),
        }),
        _ => Ok(()),
    }
}

/// A value at the walk's current path, read in `role`.
struct Value<'w> {
    walk: &'w mut Walk,
    role: Role,
}

impl<'de> DeserializeSeed<'de> for Value<'_> {
    type Value = ();

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Value<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a glTF JSON value")
    }

    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<(), E> {
        if self.role == Role::Index && v > MAX_INDEX {
            self.walk.found = Some((self.walk.path(), v));
            return Err(E::custom("index out of range"));
        }
        Ok(())
    }

    fn visit_i64<E: serde::de::Error>(self, _: i64) -> Result<(), E> {
        Ok(())
    }

    fn visit_f64<E: serde::de::Error>(self, _: f64) -> Result<(), E> {
        Ok(())
    }

    fn visit_bool<E: serde::de::Error>(self, _: bool) -> Result<(), E> {
        Ok(())
    }

    fn visit_str<E: serde::de::Error>(self, _: &str) -> Result<(), E> {
        Ok(())
    }

    fn visit_unit<E: serde::de::Error>(self) -> Result<(), E> {
        Ok(())
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let role = match self.role {
            Role::IndexMaps => Role::IndexMap,
            Role::Index => Role::Index,
            _ => Role::Plain,
        };
        let mut i = 0;
        loop {
            self.walk.path.push(Segment::Item(i));
            let more = seq.next_element_seed(Value {
                walk: self.walk,
                role,
            })?;
            self.walk.path.pop();
            if more.is_none() {
                return Ok(());
            }
            i += 1;
        }
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        while let Some(key) = map.next_key::<String>()? {
            if key == "extras" {
                map.next_value::<IgnoredAny>()?;
                continue;
            }
            let role = match (self.role, key.as_str()) {
                (Role::IndexMap, _) => Role::Index,
                (_, "attributes") => Role::IndexMap,
                (_, "targets") => Role::IndexMaps,
                (_, k) if INDEX_KEYS.contains(&k) => Role::Index,
                _ => Role::Plain,
            };
            self.walk.path.push(Segment::Key(key));
            map.next_value_seed(Value {
                walk: self.walk,
                role,
            })?;
            self.walk.path.pop();
        }
        Ok(())
    }
}

impl fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "index {} is out of range (glTF indices here must be below 2^32)",
            self.value
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn found(json: &str) -> Option<(String, u64, usize)> {
        check(json.as_bytes()).err().map(|e| (e.path, e.value, e.line))
    }

    #[test]
    fn indices_of_2_to_the_32_and_above_are_found_with_their_path() {
        let json =
            "{\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\n\"indices\":4294967296}]}]}";
        assert_eq!(
            found(json),
            Some(("meshes[0].primitives[0].indices".into(), 1 << 32, 2))
        );
        let json = "{\"nodes\":[{\"mesh\":0},{\"children\":[1,4294967297]}]}";
        assert_eq!(
            found(json),
            Some(("nodes[1].children[1]".into(), (1 << 32) + 1, 1))
        );
        let json = "{\"meshes\":[{\"primitives\":[{\"attributes\":{\"NORMAL\":18446744073709551615}}]}]}";
        assert_eq!(
            found(json).map(|f| f.0),
            Some("meshes[0].primitives[0].attributes.NORMAL".into())
        );
        let json =
            "{\"meshes\":[{\"primitives\":[{\"attributes\":{},\"targets\":[{\"POSITION\":4294967296}]}]}]}";
        assert_eq!(
            found(json).map(|f| f.0),
            Some("meshes[0].primitives[0].targets[0].POSITION".into())
        );
        let json = "{\"nodes\":[{\"extensions\":{\"KHR_lights_punctual\":{\"light\":4294967296}}}]}";
        assert_eq!(
            found(json).map(|f| f.0),
            Some("nodes[0].extensions.KHR_lights_punctual.light".into())
        );
    }

    #[test]
    fn other_integers_extras_and_malformed_json_pass() {
        assert_eq!(
            found("{\"buffers\":[{\"byteLength\":4294967296}],\"nodes\":[{\"mesh\":4294967295}]}"),
            None
        );
        assert_eq!(found("{\"nodes\":[{\"extras\":{\"mesh\":4294967296}}]}"), None);
        assert_eq!(found("{\"nodes\":[{\"mesh\":-1},{\"mesh\":1.5}]}"), None);
        assert_eq!(found("{\"nodes\":[{,}]}"), None);
    }
}
