//! Shell-style name patterns, as masks and material maps use them to pick shapes by name.
//!
//! `*` matches any run of characters (also none), `?` exactly one character, every other
//! character itself (case-sensitive); the pattern must match the whole name. There is no
//! escape and no character class: shape names are free text, and `[` in a name is literal.

/// Whether `pattern` has a wildcard (`*` or `?`): without one it names exactly one name.
pub fn is_pattern(pattern: &str) -> bool {
    pattern.contains(['*', '?'])
}

/// Whether `name` matches `pattern` (module docs).
///
/// The classic greedy matcher (Krauss 2008, "Matching Wildcards: An Algorithm", Dr. Dobb's
/// Journal): it remembers the last `*` and retries from one character further on a mismatch,
/// O(|pattern| · |name|) at worst, with no recursion (a hostile pattern cannot blow the stack).
pub fn matches(pattern: &str, name: &str) -> bool {
    let (p, n): (Vec<char>, Vec<char>) = (pattern.chars().collect(), name.chars().collect());
    let (mut i, mut j) = (0, 0);
    // The last `*` seen (its index in the pattern) and where in the name it began to match.
    let mut star: Option<(usize, usize)> = None;
    while j < n.len() {
        match p.get(i) {
            Some('*') => {
                star = Some((i, j));
                i += 1;
            }
            Some(&c) if c == '?' || c == n[j] => {
                i += 1;
                j += 1;
            }
            _ => match star {
                // Let the last `*` swallow one more character and retry.
                Some((si, sj)) => {
                    star = Some((si, sj + 1));
                    i = si + 1;
                    j = sj + 1;
                }
                None => return false,
            },
        }
    }
    p[i..].iter().all(|&c| c == '*')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wildcards_match_runs_and_single_characters() {
        for (pattern, name, expected) in [
            ("floor", "floor", true),
            ("floor", "floor2", false),
            ("*", "", true),
            ("*", "anything", true),
            ("sphere_*", "sphere_m", true),
            ("sphere_*", "sphere", false),
            ("*_m", "sphere_m", true),
            ("s?here*", "sphere_rough", true),
            ("?", "", false),
            ("a*b*c", "a_b_b_c", true),
            ("a*b*c", "a_b_b_", false),
            ("**a", "ba", true),
            ("Metal*", "metal_1", false),
            ("[x]", "[x]", true),
            ("é?", "éa", true),
        ] {
            assert_eq!(matches(pattern, name), expected, "{pattern} vs {name}");
        }
        assert!(is_pattern("a*") && is_pattern("a?") && !is_pattern("a[b]"));
    }

    #[test]
    fn a_hostile_pattern_finishes() {
        let name = "a".repeat(10_000);
        let pattern = format!("{}b", "*a".repeat(1000));
        assert!(!matches(&pattern, &name));
    }

    /// Many stars against a million-character name (a hostile file's) finish quickly.
    #[test]
    fn many_stars_against_a_long_name_stay_linear() {
        let name = "a".repeat(1_000_000);
        assert!(!matches("*a*a*a*a*a*b", &name));
        assert!(matches("*a*a*a*a*a", &name));
    }
}
