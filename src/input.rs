//! Reading the user's files within a bound: regular files only, and at most a stated number of
//! bytes, so that `/dev/zero` cannot exhaust memory and a named pipe cannot block forever.

use std::io::Read;
use std::path::Path;

/// The bytes of the regular file `path`, of at most `max_bytes`; `limit_name` names the limit
/// (its constant) in the error. A named pipe, a device, a socket or a folder is refused before
/// it is opened; the read stops at `max_bytes + 1` bytes (a file that grows while read).
///
/// # Errors
/// The file cannot be read, is not a regular file, or holds more than `max_bytes` bytes. The
/// message does not name the file: the caller does.
pub fn read_bounded(path: &Path, max_bytes: u64, limit_name: &str) -> Result<Vec<u8>, String> {
    let too_large =
        |found: String| format!("{found}, larger than the limit {limit_name} = {max_bytes} bytes");
    let metadata = std::fs::metadata(path).map_err(|e| format!("cannot read the file: {e}"))?;
    if !metadata.is_file() {
        return Err(format!(
            "not a regular file ({}): only regular files are read",
            kind(&metadata)
        ));
    }
    if metadata.len() > max_bytes {
        return Err(too_large(format!("{} bytes", metadata.len())));
    }
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read the file: {e}"))?;
    let mut bytes = Vec::new();
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read the file: {e}"))?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large("more bytes than its length said".to_string()));
    }
    Ok(bytes)
}

/// As [`read_bounded`], for UTF-8 text.
///
/// # Errors
/// As [`read_bounded`], and text that is not UTF-8 (the byte offset named).
pub fn read_bounded_text(path: &Path, max_bytes: u64, limit_name: &str) -> Result<String, String> {
    String::from_utf8(read_bounded(path, max_bytes, limit_name)?).map_err(|e| {
        format!(
            "not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        )
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
        let e = read_bounded(Path::new("/dev/zero"), 1 << 20, "LIMIT").unwrap_err();
        assert!(e.contains("not a regular file (a device)"), "{e}");
    }

    #[test]
    fn a_folder_is_refused() {
        let dir = scratch("folder");
        let e = read_bounded(&dir, 10, "LIMIT").unwrap_err();
        assert!(e.contains("not a regular file (a folder)"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_file_one_byte_over_the_limit_is_refused_and_one_at_it_read() {
        let dir = scratch("limit");
        let path = dir.join("sparse");
        let file = std::fs::File::create(&path).unwrap();
        file.set_len(1001).unwrap();
        let e = read_bounded(&path, 1000, "LIMIT").unwrap_err();
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
        assert!(e.contains("offset 2"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
