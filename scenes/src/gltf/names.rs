//! Shape and light names for a glTF asset's meshes and lights.
//!
//! Names label AOV channels (`visibility.<name>.Y`) and become parts of file names, so the
//! part that comes from the file (a node, mesh or light `name`, glTF 2.0 §5 "name": any
//! string) is reduced to letters, digits, `_` and `-`: every other character (`.` as in
//! Blender's `Cube.001`, spaces, `/`, `:`, emoji, control and bidirectional-format characters)
//! becomes `_`, and the result is cut to [`MAX_NAME_CHARS`]. The asset still loads; one note
//! says names were changed. The loader's own parts stay as before: `<name>/<primitive>` for
//! meshes, and `#2`, `#3`, … to make a name unique.
//!
//! Uniqueness costs O(1) per name however many share a base (20,000 nodes instancing one
//! mesh all want `<mesh>/0`): each base remembers the next suffix to try.

use std::collections::{HashMap, HashSet};

use crate::error::echo;

/// Longest name kept from the file, in characters.
use crate::MAX_NAME_CHARS;

/// Hands out names unique within the scene (shapes and lights share the AOV namespace).
#[derive(Default)]
pub(super) struct Names {
    used: HashSet<String>,
    /// Per base, the next `#k` suffix to try.
    next: HashMap<String, u64>,
    /// The first name that was changed, and what it became.
    changed: Option<(String, String)>,
    /// Candidate names tried so far (the work [`Names::unique`] does).
    #[cfg(test)]
    probes: u64,
}

impl Names {
    /// A name from the file reduced to `[A-Za-z0-9_-]`, at most [`MAX_NAME_CHARS`] long
    /// (`unnamed` if empty); remembered for the note when it changed.
    pub fn sanitized(&mut self, given: &str) -> String {
        let name = crate::to_identifier(given);
        if name != given && self.changed.is_none() {
            self.changed = Some((echo(given), name.clone()));
        }
        name
    }

    /// A unique name from a name in the file ([`Names::sanitized`], then [`Names::unique`]).
    pub fn named(&mut self, given: &str) -> String {
        let base = self.sanitized(given);
        self.unique(&base)
    }

    /// `base`, or `base#2`, `base#3`, … if taken.
    pub fn unique(&mut self, base: &str) -> String {
        self.probe();
        if self.used.insert(base.to_string()) {
            return base.to_string();
        }
        let mut k = self.next.get(base).copied().unwrap_or(2);
        loop {
            self.probe();
            let name = format!("{base}#{k}");
            k += 1;
            if self.used.insert(name.clone()) {
                self.next.insert(base.to_string(), k);
                return name;
            }
        }
    }

    /// The note saying names were changed, if any were.
    pub fn note(&self) -> Option<String> {
        self.changed.as_ref().map(|(from, to)| {
            format!(
                "names: node, mesh and light names were changed to letters, digits, '_' and '-' \
                 (at most {MAX_NAME_CHARS} characters) for AOV channels and file names, e.g. {from} → {to}"
            )
        })
    }

    /// Counts one candidate name (kept by test builds only).
    fn probe(&mut self) {
        #[cfg(test)]
        {
            self.probes += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_from_files_keep_only_safe_characters() {
        let mut names = Names::default();
        assert_eq!(names.named("Left Arm"), "Left_Arm");
        assert_eq!(
            names.note().unwrap().split("e.g. ").nth(1),
            Some("\"Left Arm\" → Left_Arm")
        );
        for (given, want) in [
            ("Cube.001", "Cube_001"),
            ("a/b:c*d", "a_b_c_d"),
            ("\u{202e}evil\n", "_evil_"),
            ("😀", "_"),
            ("", "unnamed"),
            ("ok_name-2", "ok_name-2"),
        ] {
            assert_eq!(names.sanitized(given), want, "{given:?}");
        }
        assert_eq!(names.sanitized(&"x".repeat(10_000_000)).len(), MAX_NAME_CHARS);
        let mut clean = Names::default();
        clean.named("Suzanne");
        assert_eq!(clean.note(), None, "nothing changed, nothing noted");
    }

    #[test]
    fn equal_bases_get_suffixes_and_skip_taken_ones() {
        let mut names = Names::default();
        assert_eq!(names.unique("a#3"), "a#3");
        let got: Vec<String> = (0..4).map(|_| names.unique("a")).collect();
        assert_eq!(got, ["a", "a#2", "a#4", "a#5"]);
    }

    /// The quadratic load of 20,000 nodes sharing a mesh came from here: each name searched
    /// `#2, #3, …` from the start. The work is counted, not timed (a count cannot flake on a
    /// loaded machine): n equal bases must cost about 2n probes, where the old search cost
    /// n²/2 (2·10⁸ here).
    #[test]
    fn uniqueness_work_grows_linearly_with_equal_bases() {
        let mut names = Names::default();
        let n = 20_000u64;
        for _ in 0..n {
            names.unique("tri/0");
        }
        assert!(names.probes <= 2 * n, "{} probes for {n} names", names.probes);
        assert!(names.used.contains("tri/0#20000"));
    }
}
