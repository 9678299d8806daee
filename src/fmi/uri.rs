//! `fmuResourceLocation`: the `file:` URI of the unpacked `resources/` folder.
//!
//! Accepted: `file:///p`, `file:/p`, `file://localhost/p`, percent-encoded, trailing slash
//! optional. The scheme and the host name are case-insensitive (RFC 3986), so `FILE:///p`
//! and `file://LOCALHOST/p` are accepted too. Other hosts are refused.

use std::os::unix::ffi::OsStringExt;
use std::path::PathBuf;

/// The directory a `file:` URI names (module docs).
pub fn resource_path(uri: &str) -> Result<PathBuf, String> {
    let not_file =
        || format!("resource location '{uri}' is not a file: URI (file:///path/to/resources)");
    let rest = match uri.get(..5) {
        Some(scheme) if scheme.eq_ignore_ascii_case("file:") => &uri[5..],
        _ => return Err(not_file()),
    };
    let path = if let Some(r) = strip_prefix_ignore_case(rest, "//localhost/") {
        format!("/{r}")
    } else if let Some(r) = rest.strip_prefix("///") {
        format!("/{r}")
    } else if rest.starts_with("//") {
        return Err(format!(
            "resource location '{uri}' names a remote host (only local file: URIs)"
        ));
    } else if let Some(r) = rest.strip_prefix('/') {
        format!("/{r}")
    } else {
        return Err(not_file());
    };
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("resource location '{uri}': bad percent escape"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    if out.contains(&0) {
        return Err(format!("resource location '{uri}' contains NUL"));
    }
    Ok(PathBuf::from(std::ffi::OsString::from_vec(out)))
}

fn strip_prefix_ignore_case<'a>(text: &'a str, prefix: &str) -> Option<&'a str> {
    match text.get(..prefix.len()) {
        Some(head) if head.eq_ignore_ascii_case(prefix) => Some(&text[prefix.len()..]),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_local_spelling_names_the_same_folder() {
        for uri in [
            "file:///a%20b/",
            "file:/a%20b/",
            "file://localhost/a%20b/",
            "FILE:///a%20b/",
            "File:/a%20b/",
            "fIlE://LocalHost/a%20b/",
        ] {
            assert_eq!(resource_path(uri).unwrap(), PathBuf::from("/a b/"), "{uri}");
        }
    }

    #[test]
    fn remote_hosts_other_schemes_and_bad_escapes_are_refused() {
        for bad in [
            "http://example.com/resources",
            "/plain/path",
            "file://otherhost/x",
            "FILE://otherhost/x",
            "file:relative/x",
            "file:///bad%zz",
            "file:///bad%4",
            "file:///nul%00",
            "fil",
            "filé:///x",
            "",
        ] {
            assert!(resource_path(bad).is_err(), "{bad}");
        }
    }
}
