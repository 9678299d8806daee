//! `fmuResourceLocation`: the `file:` URI of the unpacked `resources/` folder.
//!
//! Accepted: `file:///p`, `file:/p`, `file://localhost/p`, percent-encoded, trailing slash
//! optional. The scheme and the host name are case-insensitive (RFC 3986), so `FILE:///p`
//! and `file://LOCALHOST/p` are accepted too.
//!
//! The decoded path is spelled for the platform the library runs on ([`PathStyle::HOST`]):
//!
//! | URI                               | Unix               | Windows              |
//! |-----------------------------------|--------------------|----------------------|
//! | `file:///home/a%20b/res`          | `/home/a b/res`    | `\home\a b\res`      |
//! | `file:///C:/dir` (or `/C\|/dir`)  | `/C:/dir`          | `C:\dir`             |
//! | `file://server/share/dir`         | refused (remote)   | `\\server\share\dir` |
//! | `file:////server/share/dir`       | `//server/share/dir` | `\\server\share\dir` |
//! | `file:///C:\dir\res`              | `/C:\dir\res`      | `C:\dir\res`         |
//!
//! On Unix a path is bytes, so any percent-encoded byte is kept; on Windows a path is
//! Unicode, so the decoded bytes must be UTF-8 (`%C3%B8` is `ø`). Backslashes are
//! separators on Windows only. A NUL byte is refused everywhere.

use std::fmt;
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
    /// A `file:` URI of another host than `localhost` (Unix: no UNC paths).
    RemoteHost,
    /// A `%` not followed by two hexadecimal digits.
    BadPercentEscape,
    /// A NUL byte, which no path holds.
    Nul,
    /// Decoded bytes that are not UTF-8, on a platform whose paths are Unicode (Windows).
    NotUtf8,
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
            ResourceLocationProblem::NotUtf8 => write!(
                f,
                "resource location '{uri}': percent escapes that are not UTF-8"
            ),
        }
    }
}

impl std::error::Error for ResourceLocationError {}

impl From<ResourceLocationError> for String {
    fn from(error: ResourceLocationError) -> String {
        error.to_string()
    }
}

/// How a platform spells a local path (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathStyle {
    /// `/`-separated bytes; a host other than `localhost` is refused.
    Unix,
    /// Drive letters, UNC `\\server\share`, `\` separators, Unicode.
    Windows,
}

impl PathStyle {
    /// The style of the platform this library is built for.
    pub const HOST: PathStyle = if cfg!(windows) {
        PathStyle::Windows
    } else {
        PathStyle::Unix
    };
}

/// The directory a `file:` URI names, on this platform (module docs).
pub fn resource_path(uri: &str) -> Result<PathBuf, ResourceLocationError> {
    let bytes = resource_path_bytes(uri, PathStyle::HOST)?;
    Ok(path_from_bytes(bytes))
}

/// The directory a `file:` URI names, spelled for `style`: bytes on Unix, UTF-8 on Windows.
pub fn resource_path_bytes(uri: &str, style: PathStyle) -> Result<Vec<u8>, ResourceLocationError> {
    let refused = |kind| ResourceLocationError {
        uri: uri.to_string(),
        kind,
    };
    let rest = match uri.get(..5) {
        Some(scheme) if scheme.eq_ignore_ascii_case("file:") => &uri[5..],
        _ => return Err(refused(ResourceLocationProblem::NotFile)),
    };
    // `//authority/path` or `/path`.
    let (host, path) = if let Some(after) = rest.strip_prefix("//") {
        let end = after.find('/').unwrap_or(after.len());
        (&after[..end], &after[end..])
    } else if rest.starts_with('/') {
        ("", rest)
    } else {
        return Err(refused(ResourceLocationProblem::NotFile));
    };
    let host =
        percent_decode(host).ok_or_else(|| refused(ResourceLocationProblem::BadPercentEscape))?;
    let path =
        percent_decode(path).ok_or_else(|| refused(ResourceLocationProblem::BadPercentEscape))?;
    if host.contains(&0) || path.contains(&0) {
        return Err(refused(ResourceLocationProblem::Nul));
    }
    let local = host.is_empty() || host.eq_ignore_ascii_case(b"localhost");
    if local && path.is_empty() {
        return Err(refused(ResourceLocationProblem::NotFile));
    }
    match style {
        PathStyle::Unix if local => Ok(path),
        PathStyle::Unix => Err(refused(ResourceLocationProblem::RemoteHost)),
        PathStyle::Windows => {
            let host = String::from_utf8(host);
            let path = String::from_utf8(path);
            let (Ok(host), Ok(path)) = (host, path) else {
                return Err(refused(ResourceLocationProblem::NotUtf8));
            };
            Ok(windows_path(if local { "" } else { &host }, &path).into_bytes())
        }
    }
}

/// The Windows spelling of a decoded `file:` URI's host (empty: local) and path.
fn windows_path(host: &str, path: &str) -> String {
    let path = path.replace('/', "\\");
    if !host.is_empty() {
        // `file://C:/dir`, a common misspelling of `file:///C:/dir`.
        if is_drive(host) {
            return format!("{}:{path}", &host[..1]);
        }
        return format!("\\\\{host}{path}");
    }
    if path.starts_with("\\\\") {
        // `file:////server/share`: UNC with an empty authority.
        return path;
    }
    match path.strip_prefix('\\') {
        Some(rest) if is_drive(rest.get(..2).unwrap_or("")) => {
            format!("{}:{}", &rest[..1], &rest[2..])
        }
        _ => path,
    }
}

/// `C:` or the legacy `C|`.
fn is_drive(text: &str) -> bool {
    let b = text.as_bytes();
    b.len() == 2 && b[0].is_ascii_alphabetic() && (b[1] == b':' || b[1] == b'|')
}

/// The bytes percent escapes stand for; `None` for a `%` without two hexadecimal digits.
fn percent_decode(text: &str) -> Option<Vec<u8>> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let digits = bytes.get(i + 1..i + 3)?;
            if !digits.iter().all(u8::is_ascii_hexdigit) {
                return None;
            }
            let high = (digits[0] as char).to_digit(16)?;
            let low = (digits[1] as char).to_digit(16)?;
            out.push((high * 16 + low) as u8);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    Some(out)
}

#[cfg(unix)]
fn path_from_bytes(bytes: Vec<u8>) -> PathBuf {
    use std::os::unix::ffi::OsStringExt;
    PathBuf::from(std::ffi::OsString::from_vec(bytes))
}

/// Bytes that [`resource_path_bytes`] checked to be UTF-8 ([`PathStyle::Windows`]).
#[cfg(not(unix))]
fn path_from_bytes(bytes: Vec<u8>) -> PathBuf {
    PathBuf::from(String::from_utf8_lossy(&bytes).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn windows(uri: &str) -> String {
        String::from_utf8(resource_path_bytes(uri, PathStyle::Windows).unwrap()).unwrap()
    }

    fn unix(uri: &str) -> Vec<u8> {
        resource_path_bytes(uri, PathStyle::Unix).unwrap()
    }

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
            assert_eq!(unix(uri), b"/a b/", "{uri}");
            assert_eq!(windows(uri), "\\a b\\", "{uri}");
        }
    }

    #[test]
    fn the_host_platform_path_is_the_style_it_is_built_for() {
        let path = resource_path("file:///d%C3%A9j%C3%A0/resources").unwrap();
        let expected = match PathStyle::HOST {
            PathStyle::Unix => "/déjà/resources",
            PathStyle::Windows => "\\déjà\\resources",
        };
        assert_eq!(path, PathBuf::from(expected));
        assert_eq!(PathStyle::HOST == PathStyle::Windows, cfg!(windows));
    }

    #[test]
    fn a_drive_letter_becomes_a_windows_drive_path() {
        for uri in [
            "file:///C:/dir",
            "file:/C:/dir",
            "file://localhost/C:/dir",
            "FILE:///C%3A/dir",
            "file:///C|/dir",
            "file://C:/dir",
        ] {
            assert_eq!(windows(uri), "C:\\dir", "{uri}");
        }
        assert_eq!(
            windows("file:///c:/Program%20Files/x/"),
            "c:\\Program Files\\x\\"
        );
        assert_eq!(windows("file:///C:/"), "C:\\");
        // On Unix the same text is an ordinary absolute path.
        assert_eq!(unix("file:///C:/dir"), b"/C:/dir");
    }

    #[test]
    fn a_server_name_becomes_a_unc_path_on_windows_only() {
        for uri in [
            "file://server/share/dir",
            "file:////server/share/dir",
            "FILE://server/share/dir",
        ] {
            assert_eq!(windows(uri), "\\\\server\\share\\dir", "{uri}");
        }
        let refused = resource_path_bytes("file://server/share/dir", PathStyle::Unix);
        assert_eq!(
            refused.unwrap_err().kind,
            ResourceLocationProblem::RemoteHost
        );
        assert_eq!(unix("file:////server/share/dir"), b"//server/share/dir");
    }

    #[test]
    fn backslashes_are_separators_on_windows_and_bytes_on_unix() {
        assert_eq!(windows("file:///C:\\dir\\res"), "C:\\dir\\res");
        assert_eq!(windows("file:///C:/dir%5Cres/"), "C:\\dir\\res\\");
        assert_eq!(unix("file:///a%5Cb"), b"/a\\b");
    }

    #[test]
    fn percent_encoded_non_ascii_is_decoded_as_utf8() {
        let uri = "file:///C:/Users/J%C3%B8rgen/r%C3%A9sultats%20%E6%B5%B7/resources";
        assert_eq!(windows(uri), "C:\\Users\\Jørgen\\résultats 海\\resources");
        assert_eq!(unix("file:///home/J%C3%B8rgen"), "/home/Jørgen".as_bytes());
        // Unencoded non-ASCII is taken as it is.
        assert_eq!(windows("file:///C:/Jørgen"), "C:\\Jørgen");
        // Bytes that are not UTF-8: a Unix path, never a Windows one.
        assert_eq!(unix("file:///x%FF"), b"/x\xff");
        let error = resource_path_bytes("file:///C:/x%FF", PathStyle::Windows).unwrap_err();
        assert_eq!(error.kind, ResourceLocationProblem::NotUtf8);
    }

    #[test]
    fn remote_hosts_other_schemes_and_bad_escapes_are_refused() {
        use ResourceLocationProblem::*;
        for (bad, kind) in [
            ("http://example.com/resources", NotFile),
            ("/plain/path", NotFile),
            ("C:\\plain\\path", NotFile),
            ("file://otherhost/x", RemoteHost),
            ("FILE://otherhost/x", RemoteHost),
            ("file:relative/x", NotFile),
            ("file://localhost", NotFile),
            ("file:///bad%zz", BadPercentEscape),
            ("file:///bad%4", BadPercentEscape),
            ("file:///bad%+1", BadPercentEscape),
            ("file://bad%zzhost/x", BadPercentEscape),
            ("file:///nul%00", Nul),
            ("fil", NotFile),
            ("filé:///x", NotFile),
            ("", NotFile),
        ] {
            let error = resource_path_bytes(bad, PathStyle::Unix).unwrap_err();
            assert_eq!(error.kind, kind, "{bad}");
            assert!(error
                .to_string()
                .starts_with(&format!("resource location '{bad}'")));
            if kind != RemoteHost {
                let on_windows = resource_path_bytes(bad, PathStyle::Windows).unwrap_err();
                assert_eq!(on_windows.kind, kind, "{bad} (Windows)");
            }
        }
    }
}
