//! `fmuResourceLocation`: the `file:` URI of the unpacked `resources/` folder.
//!
//! Accepted: `file:///p`, `file:/p`, `file://localhost/p`, percent-encoded, trailing slash
//! optional. The scheme and the host name are case-insensitive (RFC 3986), so `FILE:///p`
//! and `file://LOCALHOST/p` are accepted too. Other hosts are refused.

use std::fmt;
use std::os::unix::ffi::OsStringExt;
use std::path::PathBuf;

/// Why a resource location was refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ResourceLocationError {
    /// The location as given.
    pub uri: String,
    /// What is wrong with it.
    pub kind: ResourceLocationProblem,
}

/// What is wrong with a resource location.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ResourceLocationProblem {
    /// Not a `file:` URI.
    NotFile,
    /// A `file:` URI of another host than `localhost`.
    RemoteHost,
    /// A `%` not followed by two hexadecimal digits.
    BadPercentEscape,
    /// A NUL byte, which no path holds.
    Nul,
}

impl fmt::Display for ResourceLocationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let uri = &self.uri;
        match self.kind {
            ResourceLocationProblem::NotFile => write!(
                f,
                "resource location '{uri}' is not a file: URI (file:///path/to/resources)"
            ),
            ResourceLocationProblem::RemoteHost => write!(
                f,
                "resource location '{uri}' names a remote host (only local file: URIs)"
            ),
            ResourceLocationProblem::BadPercentEscape => {
                write!(f, "resource location '{uri}': bad percent escape")
            }
            ResourceLocationProblem::Nul => write!(f, "resource location '{uri}' contains NUL"),
        }
    }
}

impl std::error::Error for ResourceLocationError {}

impl From<ResourceLocationError> for String {
    fn from(error: ResourceLocationError) -> String {
        error.to_string()
    }
}

/// The directory a `file:` URI names (module docs).
pub fn resource_path(uri: &str) -> Result<PathBuf, ResourceLocationError> {
    let refused = |kind| ResourceLocationError {
        uri: uri.to_string(),
        kind,
    };
    let not_file = || refused(ResourceLocationProblem::NotFile);
    let rest = match uri.get(..5) {
        Some(scheme) if scheme.eq_ignore_ascii_case("file:") => &uri[5..],
        _ => return Err(not_file()),
    };
    let path = if let Some(r) = strip_prefix_ignore_case(rest, "//localhost/") {
        format!("/{r}")
    } else if let Some(r) = rest.strip_prefix("///") {
        format!("/{r}")
    } else if rest.starts_with("//") {
        return Err(refused(ResourceLocationProblem::RemoteHost));
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
                .ok_or_else(|| refused(ResourceLocationProblem::BadPercentEscape))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    if out.contains(&0) {
        return Err(refused(ResourceLocationProblem::Nul));
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
        use ResourceLocationProblem::*;
        for (bad, kind) in [
            ("http://example.com/resources", NotFile),
            ("/plain/path", NotFile),
            ("file://otherhost/x", RemoteHost),
            ("FILE://otherhost/x", RemoteHost),
            ("file:relative/x", NotFile),
            ("file:///bad%zz", BadPercentEscape),
            ("file:///bad%4", BadPercentEscape),
            ("file:///nul%00", Nul),
            ("fil", NotFile),
            ("filé:///x", NotFile),
            ("", NotFile),
        ] {
            let error = resource_path(bad).unwrap_err();
            assert_eq!(error.kind, kind, "{bad}");
            assert!(error
                .to_string()
                .starts_with(&format!("resource location '{bad}'")));
        }
    }
}
