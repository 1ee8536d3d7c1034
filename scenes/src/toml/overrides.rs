//! Fields of a scene file changed from outside it before it is read: the scene-parameter
//! sweeps and the light motion of study files (compare/README.md, "Study files").
//!
//! A field is named by a dotted path through the document. Keys select table fields,
//! `[i]` selects an array element (0-based), and a key that meets an array of tables
//! (`[[shape]]`, `[[light]]`, `[[material]]`) selects the entry with that `name`:
//!
//! | path | field |
//! |---|---|
//! | `shape.light.size[0]` | the first side of the shape named `light` |
//! | `shape.blocker.center[1]` | the height of the shape named `blocker` |
//! | `light.sun.angular_diameter` | the sun's angular diameter (added if the file omits it) |
//! | `camera.eye[2]` | the camera position's z |
//!
//! The edited document is read exactly as the file would be, so an edit that makes the scene
//! invalid (a negative size) fails with the scene reader's own message, and every field keeps
//! the line it has in the file.

use super::tree::{Node, Value};

/// What an override does to its field.
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// Replace the value (or add the field, if the table lacks it).
    Set(Value),
    /// Add a number to a numeric field.
    Add(f64),
}

/// One field changed.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// Dotted path (module docs).
    pub path: String,
    /// The change.
    pub edit: Edit,
}

/// One step of a path: a key, then array indices.
struct Segment<'a> {
    key: &'a str,
    indices: Vec<usize>,
}

/// Splits `a.b[1][2].c` into segments; errors say what is malformed.
fn segments(path: &str) -> Result<Vec<Segment<'_>>, String> {
    let malformed = |why: &str| format!("malformed scene field path `{path}`: {why}");
    if path.is_empty() {
        return Err(malformed("empty"));
    }
    path.split('.')
        .map(|part| {
            let (key, mut rest) = match part.find('[') {
                Some(i) => (&part[..i], &part[i..]),
                None => (part, ""),
            };
            if key.is_empty() {
                return Err(malformed("an empty key"));
            }
            let mut indices = Vec::new();
            while !rest.is_empty() {
                let close = rest
                    .find(']')
                    .filter(|_| rest.starts_with('['))
                    .ok_or_else(|| malformed("expected `[index]`"))?;
                let index = rest[1..close]
                    .parse()
                    .map_err(|_| malformed(&format!("`{}` is not an index", &rest[1..close])))?;
                indices.push(index);
                rest = &rest[close + 1..];
            }
            Ok(Segment { key, indices })
        })
        .collect()
}

/// The `name` of an array-of-tables entry, if it has one.
fn entry_name(node: &Node) -> Option<&str> {
    match &node.value {
        Value::Table(fields) => fields.iter().find_map(|(k, v)| match (&**k, &v.value) {
            ("name", Value::String(s)) => Some(s.as_str()),
            _ => None,
        }),
        _ => None,
    }
}

/// Applies `o` to the document `root`; the error names the path and what is missing there.
pub fn apply(root: &mut Node, o: &Override) -> Result<(), String> {
    let segs = segments(&o.path)?;
    let mut node = root;
    let mut at = String::new();
    for (s, seg) in segs.iter().enumerate() {
        let last = s + 1 == segs.len() && seg.indices.is_empty();
        let here = if at.is_empty() {
            seg.key.to_string()
        } else {
            format!("{at}.{}", seg.key)
        };
        let kind = node.value.kind();
        let of_tables = matches!(&node.value, Value::Array(items)
            if items.iter().all(|n| matches!(n.value, Value::Table(_))));
        node = match &mut node.value {
            Value::Table(fields) => {
                let found = fields.iter().position(|(k, _)| k == seg.key);
                match (found, &o.edit) {
                    (Some(i), _) => &mut fields[i].1,
                    (None, Edit::Set(_)) if last => {
                        fields.push((
                            seg.key.to_string(),
                            Node {
                                span: None,
                                value: Value::Bool(false),
                            },
                        ));
                        &mut fields.last_mut().expect("just pushed").1
                    }
                    (None, _) => {
                        let keys: Vec<&str> = fields.iter().map(|(k, _)| k.as_str()).collect();
                        return Err(format!(
                            "scene field `{here}` does not exist ({} has {})",
                            if at.is_empty() { "the file" } else { &at },
                            if keys.is_empty() {
                                "no fields".to_string()
                            } else {
                                keys.join(", ")
                            }
                        ));
                    }
                }
            }
            Value::Array(items) if of_tables => {
                let names: Vec<String> = items
                    .iter()
                    .filter_map(|n| entry_name(n).map(str::to_string))
                    .collect();
                match items.iter_mut().find(|n| entry_name(n) == Some(seg.key)) {
                    Some(n) => n,
                    None => {
                        return Err(format!(
                            "`{at}` has no entry named `{}`; names: {}",
                            seg.key,
                            if names.is_empty() {
                                "none".to_string()
                            } else {
                                names.join(", ")
                            }
                        ))
                    }
                }
            }
            _ => return Err(format!("`{at}` is {kind}, it has no field `{}`", seg.key)),
        };
        at = here;
        for &i in &seg.indices {
            at = format!("{at}[{i}]");
            node = match &mut node.value {
                Value::Array(items) => {
                    let n = items.len();
                    items
                        .get_mut(i)
                        .ok_or_else(|| format!("`{at}`: index out of range (the array has {n} values)"))?
                }
                v => return Err(format!("`{at}`: {} cannot be indexed", v.kind())),
            };
        }
    }
    match &o.edit {
        Edit::Set(v) => node.value = v.clone(),
        Edit::Add(d) => {
            let x = match node.value {
                Value::Float(x) => x,
                Value::Integer(i) => i as f64,
                ref v => return Err(format!("`{}` is {}, not a number to add to", o.path, v.kind())),
            };
            node.value = Value::Float(x + d);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOC: &str = r#"
[camera]
eye = [0.0, 1.0, 3.0]

[[shape]]
name = "floor"
size = [4.0, 4.0]

[[shape]]
name = "light"
size = [0.5, 0.5]
center = [0, 1, 0]
"#;

    fn doc() -> Node {
        super::super::tree::parse(DOC).unwrap()
    }

    fn set(path: &str, v: f64) -> Override {
        Override {
            path: path.into(),
            edit: Edit::Set(Value::Float(v)),
        }
    }

    fn get<'a>(root: &'a Node, section: &str, name: &str, key: &str) -> &'a Value {
        let Value::Table(f) = &root.value else { panic!() };
        let Value::Array(items) = &f.iter().find(|(k, _)| k == section).unwrap().1.value else {
            panic!()
        };
        let entry = items.iter().find(|n| entry_name(n) == Some(name)).unwrap();
        let Value::Table(f) = &entry.value else { panic!() };
        &f.iter().find(|(k, _)| k == key).unwrap().1.value
    }

    #[test]
    fn named_entries_indices_and_additions() {
        let mut root = doc();
        apply(&mut root, &set("shape.light.size[1]", 2.0)).unwrap();
        let Value::Array(size) = get(&root, "shape", "light", "size") else {
            panic!()
        };
        assert_eq!(size[0].value, Value::Float(0.5));
        assert_eq!(size[1].value, Value::Float(2.0));
        // The edited element keeps its place in the file (its line).
        assert!(size[1].span.is_some());
        // Adding to an integer gives a float; the floor is untouched.
        let add = Override {
            path: "shape.light.center[1]".into(),
            edit: Edit::Add(0.25),
        };
        apply(&mut root, &add).unwrap();
        let Value::Array(c) = get(&root, "shape", "light", "center") else {
            panic!()
        };
        assert_eq!(c[1].value, Value::Float(1.25));
        let Value::Array(floor) = get(&root, "shape", "floor", "size") else {
            panic!()
        };
        assert_eq!(floor[1].value, Value::Float(4.0));
        // A missing last key is added by `Set`.
        apply(&mut root, &set("shape.floor.roughness", 0.3)).unwrap();
        assert_eq!(get(&root, "shape", "floor", "roughness"), &Value::Float(0.3));
    }

    #[test]
    fn errors_name_what_is_missing() {
        let mut root = doc();
        let e = apply(&mut root, &set("shape.lamp.size[0]", 1.0)).unwrap_err();
        assert!(
            e.contains("no entry named `lamp`") && e.contains("floor, light"),
            "{e}"
        );
        let e = apply(&mut root, &set("shape.light.size[2]", 1.0)).unwrap_err();
        assert!(
            e.contains("shape.light.size[2]") && e.contains("has 2 values"),
            "{e}"
        );
        let e = apply(&mut root, &set("camera.eye[0].x", 1.0)).unwrap_err();
        assert!(e.contains("a float"), "{e}");
        let e = apply(&mut root, &set("shape.light.size[x]", 1.0)).unwrap_err();
        assert!(e.contains("malformed") && e.contains("`x`"), "{e}");
        let add = Override {
            path: "shape.light.name".into(),
            edit: Edit::Add(1.0),
        };
        let e = apply(&mut root, &add).unwrap_err();
        assert!(e.contains("a string, not a number"), "{e}");
        let add = Override {
            path: "film.width".into(),
            edit: Edit::Add(1.0),
        };
        let e = apply(&mut root, &add).unwrap_err();
        assert!(
            e.contains("`film` does not exist") && e.contains("camera, shape"),
            "{e}"
        );
    }
}
