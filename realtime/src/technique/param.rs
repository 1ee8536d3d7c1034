//! One row of a method's parameter table: the single source of a parameter's name, accepted
//! values, unit, one-line doc, paper, and how it is read from and written to the method.
//!
//! Every family ([`super::FAMILIES`]) writes its methods as [`MethodSpec`]s, each with the table of its own parameters, plus the table of
//! the parameters its methods share. `verity raster --method NAME --param k=v`, the study
//! files, `Method`'s printed form (`name(k=v, …)`, in headers and metrics.json), `verity
//! raster --help` and `docs/methods.md` all come from these tables
//! ([`super::markdown`], [`super::param_help`]); a test fails when the written docs drift.
//!
//! Values are typed ([`Value`]) from the moment they are parsed: a row's [`Kind`] parses and
//! range-checks text, or checks a value built in code, before its setter stores it.

use std::fmt;

use glam::Vec3;

/// What a parameter accepts.
#[derive(Clone, Copy, Debug)]
pub enum Kind {
    /// A whole number in `lo..=hi`.
    Whole(u32, u32),
    /// One of these whole numbers.
    OneOf(&'static [u32]),
    /// A finite number in `[lo, hi]`.
    Real(f32, f32),
    /// `on` / `off` (`true` / `false` accepted: TOML booleans arrive as such).
    Switch,
    /// One of these words.
    Keyword(&'static [&'static str]),
    /// A shape's name (not empty).
    Name,
    /// Three finite numbers `x,y,z` (brackets and spaces allowed: `[0, 1, 2]`).
    Vector,
}

/// A parameter's value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// [`Kind::Whole`], [`Kind::OneOf`].
    Whole(u32),
    /// [`Kind::Real`].
    Real(f32),
    /// [`Kind::Switch`].
    Switch(bool),
    /// [`Kind::Keyword`]: the word, as the row's list spells it.
    Keyword(&'static str),
    /// [`Kind::Name`].
    Name(String),
    /// [`Kind::Vector`].
    Vector(Vec3),
}

impl Kind {
    /// `text` (trimmed) as a value this kind accepts, or None.
    pub fn parse(&self, text: &str) -> Option<Value> {
        let text = text.trim();
        let value = match self {
            Kind::Whole(..) | Kind::OneOf(_) => Value::Whole(text.parse().ok()?),
            Kind::Real(..) => Value::Real(text.parse().ok()?),
            Kind::Switch => Value::Switch(match text {
                "on" | "true" => true,
                "off" | "false" => false,
                _ => return None,
            }),
            Kind::Keyword(words) => Value::Keyword(words.iter().find(|w| **w == text)?),
            Kind::Name => Value::Name(text.to_string()),
            Kind::Vector => {
                let inner = text.trim_start_matches('[').trim_end_matches(']');
                let v: Vec<f32> = inner
                    .split(',')
                    .map(|c| c.trim().parse::<f32>().ok())
                    .collect::<Option<_>>()?;
                if v.len() != 3 {
                    return None;
                }
                Value::Vector(Vec3::new(v[0], v[1], v[2]))
            }
        };
        self.accepts(&value).then_some(value)
    }

    /// Whether `value` is of this kind and in its range (NaN never is).
    pub fn accepts(&self, value: &Value) -> bool {
        match (self, value) {
            (Kind::Whole(lo, hi), Value::Whole(v)) => (lo..=hi).contains(&v),
            (Kind::OneOf(set), Value::Whole(v)) => set.contains(v),
            (Kind::Real(lo, hi), Value::Real(v)) => v.is_finite() && v >= lo && v <= hi,
            (Kind::Switch, Value::Switch(_)) => true,
            (Kind::Keyword(words), Value::Keyword(w)) => words.contains(w),
            (Kind::Name, Value::Name(n)) => !n.trim().is_empty(),
            (Kind::Vector, Value::Vector(v)) => v.is_finite(),
            _ => false,
        }
    }

    /// What it accepts, for error messages and the help: "a whole number in 1..=64", ….
    pub fn describe(&self) -> String {
        match self {
            Kind::Whole(lo, hi) => format!("a whole number in {lo}..={hi}"),
            Kind::OneOf(v) => {
                let v: Vec<String> = v.iter().map(u32::to_string).collect();
                format!("one of {}", v.join(", "))
            }
            Kind::Real(lo, hi) => format!("a number in [{lo}, {hi}]"),
            Kind::Switch => "one of on, off, true, false".to_string(),
            Kind::Keyword(k) => format!("one of {}", k.join(", ")),
            Kind::Name => "a shape's name".to_string(),
            Kind::Vector => "three finite numbers x,y,z".to_string(),
        }
    }

    /// The accepted values in a table cell: `1..=64`, `3, 5`, `[0, 10]`, `on / off`, ….
    pub fn range(&self) -> String {
        match self {
            Kind::Whole(lo, hi) => format!("{lo}..={hi}"),
            Kind::OneOf(v) => v.iter().map(u32::to_string).collect::<Vec<_>>().join(", "),
            Kind::Real(lo, hi) => format!("[{lo}, {hi}]"),
            Kind::Switch => "on / off".to_string(),
            Kind::Keyword(k) => k.join(" / "),
            Kind::Name => "a shape's name".to_string(),
            Kind::Vector => "x,y,z".to_string(),
        }
    }
}

impl fmt::Display for Value {
    /// As `name(k=v, …)` prints it: numbers as Rust prints them (`0.002`, `1`), switches
    /// `on` / `off`, vectors `x,y,z`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Whole(v) => write!(f, "{v}"),
            Value::Real(v) => write!(f, "{v}"),
            Value::Switch(b) => f.write_str(if *b { "on" } else { "off" }),
            Value::Keyword(w) => f.write_str(w),
            Value::Name(n) => f.write_str(n),
            Value::Vector(v) => write!(f, "{},{},{}", v.x, v.y, v.z),
        }
    }
}

impl Value {
    /// The number of a [`Value::Whole`] (setters are only handed values their kind accepts).
    pub fn whole(&self) -> Option<u32> {
        match self {
            Value::Whole(v) => Some(*v),
            _ => None,
        }
    }

    /// The number of a [`Value::Real`].
    pub fn real(&self) -> Option<f32> {
        match self {
            Value::Real(v) => Some(*v),
            _ => None,
        }
    }

    /// The flag of a [`Value::Switch`].
    pub fn switch(&self) -> Option<bool> {
        match self {
            Value::Switch(b) => Some(*b),
            _ => None,
        }
    }

    /// The word of a [`Value::Keyword`].
    pub fn keyword(&self) -> Option<&'static str> {
        match self {
            Value::Keyword(w) => Some(w),
            _ => None,
        }
    }

    /// The vector of a [`Value::Vector`].
    pub fn vector(&self) -> Option<Vec3> {
        match self {
            Value::Vector(v) => Some(*v),
            _ => None,
        }
    }
}

/// One parameter of the methods whose settings are a `T`.
pub struct Param<T: 'static> {
    /// `--param NAME=…`.
    pub name: &'static str,
    /// What it accepts.
    pub kind: Kind,
    /// Unit of its values ("" for counts, switches and words).
    pub unit: &'static str,
    /// One line: what it does.
    pub doc: &'static str,
    /// Where it comes from (paper, section), "" where it is the method's own.
    pub source: &'static str,
    /// What the method does while it is unset ("" for parameters that always have a value).
    pub unset: &'static str,
    /// Its value in `T` (None: unset).
    pub get: fn(&T) -> Option<Value>,
    /// Stores a value its kind accepts; None if `T` cannot take it (a value the kind accepts
    /// but the method refuses, such as a zero `sphere_view`).
    pub set: fn(&mut T, Value) -> Option<()>,
}

/// A method of a family whose settings are a `T`: its name, one line on what it does, its
/// paper, its defaults and the table of its own parameters (the family's shared ones are the
/// family's table).
pub struct MethodSpec<T: 'static> {
    /// `--method NAME`.
    pub name: &'static str,
    /// One line: what it does per pixel.
    pub summary: &'static str,
    /// The paper it implements (authors year, title, venue).
    pub source: &'static str,
    /// Its settings with every parameter at its default.
    pub default: fn() -> T,
    /// Its own parameters, in printing order after the family's.
    pub params: &'static [Param<T>],
}

/// The spec called `name` in `specs`.
pub fn spec_named<T>(specs: &'static [MethodSpec<T>], name: &str) -> Option<&'static MethodSpec<T>> {
    specs.iter().find(|s| s.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_parse_and_range_check() {
        assert_eq!(Kind::Whole(1, 64).parse(" 64 "), Some(Value::Whole(64)));
        assert_eq!(Kind::Whole(1, 64).parse("65"), None);
        assert_eq!(Kind::Whole(1, 64).parse("2.5"), None);
        assert_eq!(Kind::OneOf(&[3, 5]).parse("4"), None);
        assert_eq!(Kind::Real(0.0, 10.0).parse("0.002"), Some(Value::Real(0.002)));
        for bad in ["NaN", "inf", "-1", "11", "x"] {
            assert_eq!(Kind::Real(0.0, 10.0).parse(bad), None, "{bad}");
        }
        assert_eq!(Kind::Switch.parse("true"), Some(Value::Switch(true)));
        assert_eq!(Kind::Switch.parse("yes"), None);
        assert_eq!(
            Kind::Keyword(&["lobe", "box"]).parse("box"),
            Some(Value::Keyword("box"))
        );
        assert_eq!(Kind::Name.parse("  "), None);
        assert_eq!(
            Kind::Vector.parse("[0, 1, 2]"),
            Some(Value::Vector(Vec3::new(0.0, 1.0, 2.0)))
        );
        assert_eq!(Kind::Vector.parse("1,2"), None);
        assert_eq!(Kind::Vector.parse("1,NaN,2"), None);
        assert!(
            !Kind::Real(0.0, 1.0).accepts(&Value::Whole(1)),
            "kinds do not mix"
        );
    }

    #[test]
    fn values_print_as_they_parse() {
        for (kind, text) in [
            (Kind::Real(0.0, 10.0), "0.002"),
            (Kind::Real(0.0, 10.0), "1"),
            (Kind::Switch, "off"),
            (Kind::Vector, "0,1.5,-2"),
            (Kind::Keyword(&["fill", "none"]), "none"),
        ] {
            assert_eq!(kind.parse(text).unwrap().to_string(), text);
        }
    }
}
