//! glTF `uri` values (glTF 2.0 §2.8 "URIs": RFC 3986 URIs or relative references, resolved
//! against the glTF file's location) → a `data:` payload or a file path, before anything is
//! read.
//!
//! | form (RFC 3986) | example | result |
//! |---|---|---|
//! | `data:` scheme (RFC 2397) | `data:application/octet-stream;base64,AAAA` | [`Reference::Data`] |
//! | `file:` scheme (RFC 8089 §2: `file:` path, or `file://` with an empty or `localhost` authority) | `file:///tmp/a.bin` | [`Reference::Path`], absolute |
//! | any other scheme (§3.1: ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) then `:`) | `https://…`, `c:` | refused: not a local file |
//! | network-path reference (§4.2: starts with `//`) | `//host/a.bin` | refused: not a local file |
//! | absolute-path reference (§4.2: starts with `/`) | `/etc/passwd` | [`Reference::Path`], absolute |
//! | relative-path reference | `tex/a%20b.png` | [`Reference::Path`], relative to the asset's folder |
//!
//! The query and fragment (§3.4, §3.5: from the first `?` or `#`) are dropped, and the path
//! is percent-decoded (§2.1) after that, so `%2e%2e/` is `../` and `%2Fetc%2Fpasswd` is the
//! absolute `/etc/passwd`: whether a path stays inside the asset's folder is decided on the
//! decoded path ([`crate::access::Confinement`]). A decoded NUL byte or invalid UTF-8 is
//! refused.

use std::path::PathBuf;

/// What a `uri` names.
#[derive(Debug, PartialEq, Eq)]
pub(super) enum Reference<'a> {
    /// A `data:` URI (the whole text, for the decoder).
    Data(&'a str),
    /// A file path, percent-decoded; relative ones are relative to the asset's folder.
    Path(PathBuf),
}

/// Parses `uri`; `Err` is the reason it names no local file.
pub(super) fn parse(uri: &str) -> Result<Reference<'_>, String> {
    if let Some(scheme) = scheme(uri) {
        let rest = &uri[scheme.len() + 1..];
        return match scheme.to_ascii_lowercase().as_str() {
            "data" => Ok(Reference::Data(uri)),
            "file" => file_path(rest).map(Reference::Path),
            _ => Err(format!("the `{scheme}:` scheme does not name a local file")),
        };
    }
    if uri.starts_with("//") {
        return Err("a `//host/…` reference does not name a local file".to_string());
    }
    decode(strip_query(uri)).map(|p| Reference::Path(PathBuf::from(p)))
}

/// The scheme of `uri`, if it starts with one (RFC 3986 §3.1).
fn scheme(uri: &str) -> Option<&str> {
    let end = uri.find(':')?;
    let s = &uri[..end];
    let mut chars = s.chars();
    let first = chars.next()?;
    let valid = first.is_ascii_alphabetic()
        && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'));
    valid.then_some(s)
}

/// The path of a `file:` URI after the scheme (RFC 8089 §2): `///p`, `//localhost/p`, `/p`.
fn file_path(rest: &str) -> Result<PathBuf, String> {
    let rest = strip_query(rest);
    let path = match rest.strip_prefix("//") {
        Some(after) => {
            let slash = after.find('/').unwrap_or(after.len());
            let host = &after[..slash];
            if !(host.is_empty() || host.eq_ignore_ascii_case("localhost")) {
                return Err(format!(
                    "the `file:` URI names the host {}, not this machine",
                    crate::error::echo(host)
                ));
            }
            &after[slash..]
        }
        None => rest,
    };
    if !path.starts_with('/') {
        return Err("a `file:` URI needs an absolute path".to_string());
    }
    decode(path).map(PathBuf::from)
}

/// `s` up to its query or fragment (RFC 3986 §3.4, §3.5).
fn strip_query(s: &str) -> &str {
    s.find(['?', '#']).map_or(s, |i| &s[..i])
}

/// Percent-decodes `s` (RFC 3986 §2.1) into UTF-8 without NUL bytes.
fn decode(s: &str) -> Result<String, String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let value = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("malformed %-escape at character {i}"))?;
            out.push(value);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    if out.contains(&0) {
        return Err("the decoded path contains a NUL byte".to_string());
    }
    String::from_utf8(out).map_err(|_| "the decoded path is not UTF-8".to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path(uri: &str) -> PathBuf {
        match parse(uri) {
            Ok(Reference::Path(p)) => p,
            other => panic!("{uri}: {other:?}"),
        }
    }

    #[test]
    fn relative_references_are_percent_decoded_after_the_query_is_dropped() {
        assert_eq!(path("tex/a%20b.png"), PathBuf::from("tex/a b.png"));
        assert_eq!(
            path("%2e%2e/%2e%2e/etc/passwd"),
            PathBuf::from("../../etc/passwd")
        );
        assert_eq!(path("%2Fetc%2Fpasswd"), PathBuf::from("/etc/passwd"));
        assert_eq!(path("a.bin?v=2#x"), PathBuf::from("a.bin"));
        assert_eq!(path("caf%C3%A9.png"), PathBuf::from("café.png"));
        assert!(parse("a%2").unwrap_err().contains("malformed %-escape"));
        assert!(parse("a%00b").unwrap_err().contains("NUL"));
        assert!(parse("%ff").unwrap_err().contains("UTF-8"));
    }

    #[test]
    fn file_uris_are_absolute_paths_and_other_schemes_are_refused() {
        assert_eq!(path("file:///etc/passwd"), PathBuf::from("/etc/passwd"));
        assert_eq!(path("file://localhost/etc/passwd"), PathBuf::from("/etc/passwd"));
        assert_eq!(path("FILE:/etc/pass%77d"), PathBuf::from("/etc/passwd"));
        assert!(parse("file://evil.example/x")
            .unwrap_err()
            .contains("host \"evil.example\""));
        assert!(parse("https://example.com/a.bin")
            .unwrap_err()
            .contains("`https:` scheme"));
        assert!(parse("//host/a.bin").unwrap_err().contains("local file"));
        assert!(matches!(parse("data:x;base64,AA=="), Ok(Reference::Data(_))));
        // Not a scheme: the colon comes after a character a scheme cannot hold.
        assert_eq!(path("dir/a:b.png"), PathBuf::from("dir/a:b.png"));
    }
}
