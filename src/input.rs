//! Reading the user's files within a bound: regular files only, and at most a stated number of
//! bytes, so that `/dev/zero` cannot exhaust memory and a named pipe cannot block forever.
//!
//! Errors: [`ReadError`] says why a file could not be read (without naming it: the caller
//! does); [`FileError`] is a refused input file of any kind (a hull, a ship, a database), with
//! its name, the line when there is one, the message, and the read failure behind it when the
//! file could not be read. Its text is `file:line: message` (or `file: message`).

use std::fmt;
use std::io::Read;
use std::path::Path;

/// Why a file could not be read. The text does not name the file: the caller does.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReadError {
    /// The file system refused it (absent, no permission, ...).
    Io {
        /// The error's kind.
        kind: std::io::ErrorKind,
        /// The operating system's words.
        message: String,
    },
    /// A folder, a named pipe, a device or a socket.
    NotRegular {
        /// What it is, in words (`a folder`, `a named pipe`, ...).
        what: &'static str,
    },
    /// More bytes than the limit.
    TooLarge {
        /// How many were found, in words.
        found: String,
        /// The limit's name (its constant).
        limit_name: String,
        /// The limit, in bytes.
        max_bytes: u64,
    },
    /// Text that is not UTF-8.
    NotUtf8 {
        /// Byte offset of the first invalid byte.
        offset: usize,
    },
}

impl ReadError {
    fn io(error: &std::io::Error) -> ReadError {
        ReadError::Io {
            kind: error.kind(),
            message: error.to_string(),
        }
    }
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadError::Io { message, .. } => write!(f, "cannot read the file: {message}"),
            ReadError::NotRegular { what } => {
                write!(
                    f,
                    "not a regular file ({what}): only regular files are read"
                )
            }
            ReadError::TooLarge {
                found,
                limit_name,
                max_bytes,
            } => write!(
                f,
                "{found}, larger than the limit {limit_name} = {max_bytes} bytes"
            ),
            ReadError::NotUtf8 { offset } => {
                write!(f, "not UTF-8 text (invalid byte at offset {offset})")
            }
        }
    }
}

impl std::error::Error for ReadError {}

impl From<ReadError> for String {
    fn from(error: ReadError) -> String {
        error.to_string()
    }
}

/// An input file that cannot be used: which file, which line (when one), and why.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct FileError {
    /// The file as the user named it (or `built-in semicircle`, a hull's name, ...).
    pub file: String,
    /// 1-based line, when the problem has one.
    pub line: Option<usize>,
    /// What is wrong, naming the field.
    pub message: String,
    /// The read failure behind it, when the file could not be read.
    pub cause: Option<ReadError>,
}

impl FileError {
    /// A problem at `line` (when one) of `file`.
    pub fn new(file: &str, line: Option<usize>, message: impl Into<String>) -> FileError {
        FileError {
            file: file.to_string(),
            line,
            message: message.into(),
            cause: None,
        }
    }

    /// A problem of the whole file.
    pub fn file(file: &str, message: String) -> FileError {
        FileError::new(file, None, message)
    }

    /// A problem at a line.
    pub fn at(file: &str, line: usize, message: String) -> FileError {
        FileError::new(file, Some(line), message)
    }

    /// `file` could not be read.
    pub fn unreadable(file: &str, cause: ReadError) -> FileError {
        FileError {
            message: cause.to_string(),
            cause: Some(cause),
            ..FileError::new(file, None, String::new())
        }
    }

    /// The file name (or `built-in semicircle`, a hull's name, ...).
    pub fn source_name(&self) -> &str {
        &self.file
    }

    /// 1-based line in the file, when the error refers to one.
    pub fn line(&self) -> Option<usize> {
        self.line
    }

    /// The problem, without the location.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{line}: {}", self.file, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for FileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.cause
            .as_ref()
            .map(|c| c as &(dyn std::error::Error + 'static))
    }
}

impl From<FileError> for String {
    fn from(error: FileError) -> String {
        error.to_string()
    }
}

/// The bytes of the regular file `path`, of at most `max_bytes`; `limit_name` names the limit
/// (its constant) in the error. A named pipe, a device, a socket or a folder is refused before
/// it is opened; the read stops at `max_bytes + 1` bytes (a file that grows while read). The
/// error's text does not name the file: the caller does (`String::from` keeps its text).
///
/// # Errors
/// [`ReadError`]: the file cannot be read, is not a regular file, or holds more than
/// `max_bytes` bytes.
pub fn read_bounded(path: &Path, max_bytes: u64, limit_name: &str) -> Result<Vec<u8>, ReadError> {
    let too_large = |found: String| ReadError::TooLarge {
        found,
        limit_name: limit_name.to_string(),
        max_bytes,
    };
    let metadata = std::fs::metadata(path).map_err(|e| ReadError::io(&e))?;
    if !metadata.is_file() {
        return Err(ReadError::NotRegular {
            what: kind(&metadata),
        });
    }
    if metadata.len() > max_bytes {
        return Err(too_large(format!("{} bytes", metadata.len())));
    }
    let file = std::fs::File::open(path).map_err(|e| ReadError::io(&e))?;
    let mut bytes = Vec::new();
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| ReadError::io(&e))?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large("more bytes than its length said".to_string()));
    }
    Ok(bytes)
}

/// As [`read_bounded`], for UTF-8 text.
///
/// # Errors
/// As [`read_bounded`], and text that is not UTF-8 (the byte offset named).
pub fn read_bounded_text(
    path: &Path,
    max_bytes: u64,
    limit_name: &str,
) -> Result<String, ReadError> {
    String::from_utf8(read_bounded(path, max_bytes, limit_name)?).map_err(|e| ReadError::NotUtf8 {
        offset: e.utf8_error().valid_up_to(),
    })
}

/// What a file that is not regular is, in words.
fn kind(metadata: &std::fs::Metadata) -> &'static str {
    if metadata.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let file_type = metadata.file_type();
        if file_type.is_fifo() {
            return "a named pipe";
        }
        if file_type.is_char_device() || file_type.is_block_device() {
            return "a device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    "not a file"
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("hydrofmu-input-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_device_is_refused_without_reading() {
        let e = read_bounded(Path::new("/dev/zero"), 1 << 20, "LIMIT")
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a regular file (a device)"), "{e}");
    }

    #[test]
    fn a_folder_is_refused() {
        let dir = scratch("folder");
        let e = String::from(read_bounded(&dir, 10, "LIMIT").unwrap_err());
        assert!(e.contains("not a regular file (a folder)"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_file_one_byte_over_the_limit_is_refused_and_one_at_it_read() {
        let dir = scratch("limit");
        let path = dir.join("sparse");
        let file = std::fs::File::create(&path).unwrap();
        file.set_len(1001).unwrap();
        let e = read_bounded(&path, 1000, "LIMIT").unwrap_err().to_string();
        assert!(
            e.contains("1001 bytes") && e.contains("LIMIT = 1000 bytes"),
            "{e}"
        );
        file.set_len(1000).unwrap();
        assert_eq!(read_bounded(&path, 1000, "LIMIT").unwrap().len(), 1000);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn text_that_is_not_utf8_names_the_offset() {
        let dir = scratch("utf8");
        let path = dir.join("latin1");
        std::fs::write(&path, b"ab\xe9").unwrap();
        let e = read_bounded_text(&path, 10, "LIMIT").unwrap_err();
        assert_eq!(e, ReadError::NotUtf8 { offset: 2 });
        assert!(e.to_string().contains("offset 2"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn read_errors_name_their_cause() {
        let e = read_bounded(Path::new("/dev/zero"), 1 << 20, "LIMIT").unwrap_err();
        assert_eq!(e, ReadError::NotRegular { what: "a device" });
        let missing =
            read_bounded_text(Path::new("/nonexistent/hydrofmu"), 10, "LIMIT").unwrap_err();
        assert!(
            matches!(missing, ReadError::Io { kind, .. } if kind == std::io::ErrorKind::NotFound),
            "{missing:?}"
        );
        assert!(missing.to_string().starts_with("cannot read the file: "));
    }

    #[test]
    fn a_file_error_reads_as_file_line_message_and_keeps_its_cause() {
        assert_eq!(
            FileError::at("a.1", 7, "short row".to_string()).to_string(),
            "a.1:7: short row"
        );
        let e = FileError::unreadable("a.1", ReadError::NotUtf8 { offset: 3 });
        assert_eq!(
            e.to_string(),
            "a.1: not UTF-8 text (invalid byte at offset 3)"
        );
        let cause = std::error::Error::source(&e).map(|c| c.to_string());
        assert_eq!(
            cause.as_deref(),
            Some("not UTF-8 text (invalid byte at offset 3)")
        );
        assert_eq!(
            String::from(e),
            "a.1: not UTF-8 text (invalid byte at offset 3)"
        );
    }
}
