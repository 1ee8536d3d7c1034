//! Text in markup: the one escaping function the HTML report, its SVG charts, the Mitsuba
//! scene XML and the cross-check page share.

/// `s` with the five characters XML gives a meaning to replaced by their predefined entities
/// (XML 1.0 §2.4 and §4.6: `&amp;`, `&lt;`, `&gt;`, `&quot;`, `&apos;`), so it can stand as
/// text or as a quoted attribute value in XML, SVG and HTML (HTML5 knows the same five
/// named references).
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_five_special_characters_become_entities() {
        assert_eq!(
            super::escape(r#"a<b & "c" > 'd' ü"#),
            "a&lt;b &amp; &quot;c&quot; &gt; &apos;d&apos; ü"
        );
    }
}
