//! Name patterns of `[[include]] materials` keys: `*` stands for any run of characters (also
//! none), `?` for exactly one character (a Unicode scalar value), every other character for
//! itself; the pattern must cover the whole name. There is no escape: a key without `*` and
//! `?` is a plain name.
//!
//! Matching walks the name once and, on a mismatch, lets the last `*` swallow one more
//! character (the classic wildcard algorithm; Krauss 2008, "Matching Wildcards: An
//! Algorithm", Dr. Dobb's Journal): O(pattern × name) at worst, with no recursion and no
//! allocation beyond the pattern's characters, so a 10 MB name from a hostile file costs
//! linear time per pattern character.

/// Whether `key` is a pattern (holds `*` or `?`) rather than a plain name.
pub(super) fn is_pattern(key: &str) -> bool {
    key.contains(['*', '?'])
}

/// Whether `pattern` matches the whole of `name`.
pub(super) fn matches(pattern: &str, name: &str) -> bool {
    let p: Vec<char> = pattern.chars().collect();
    // i: the next pattern character; j: the byte offset of the next name character.
    let (mut i, mut j) = (0, 0);
    // After the last `*` seen: the pattern index following it, and where in the name the
    // characters it has not swallowed begin.
    let mut retry: Option<(usize, usize)> = None;
    loop {
        let c = name[j..].chars().next();
        match (p.get(i), c) {
            (Some('*'), _) => {
                i += 1;
                retry = Some((i, j));
            }
            (Some(&q), Some(c)) if q == '?' || q == c => {
                i += 1;
                j += c.len_utf8();
            }
            (None, None) => return true,
            _ => match retry {
                Some((after_star, from)) if from < name.len() => {
                    let next = from + name[from..].chars().next().map_or(1, char::len_utf8);
                    retry = Some((after_star, next));
                    (i, j) = (after_star, next);
                }
                _ => return false,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stars_and_question_marks_match_as_in_a_shell() {
        let cases = [
            ("*", "", true),
            ("*", "Metal_01", true),
            ("Metal*", "Metal_01", true),
            ("Metal*", "metal_01", false),
            ("*01", "Metal_01", true),
            ("M*l*1", "Metal_01", true),
            ("M*l*2", "Metal_01", false),
            ("Metal_0?", "Metal_01", true),
            ("Metal_0?", "Metal_0", false),
            ("?", "é", true),
            ("??", "é", false),
            ("a*b*c", "aXbYbZc", true),
            ("a*b", "aXbYc", false),
            ("", "", true),
            ("", "a", false),
            ("**x", "yyx", true),
        ];
        for (pattern, name, want) in cases {
            assert_eq!(matches(pattern, name), want, "{pattern:?} against {name:?}");
        }
        assert!(is_pattern("Metal*") && is_pattern("a?") && !is_pattern("Metal"));
    }

    /// A long name costs time linear in its length per pattern character (no exponential
    /// backtracking on many stars).
    #[test]
    fn many_stars_against_a_long_name_stay_linear() {
        let name = "a".repeat(1_000_000);
        assert!(!matches("*a*a*a*a*a*b", &name));
        assert!(matches("*a*a*a*a*a", &name));
    }
}
