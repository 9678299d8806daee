//! Where fmu-pack's text goes, and what happens when it cannot get there.
//!
//! * Standard output carries the product (a table, a report, a summary): a write that fails
//!   (a closed pipe, a full disk) is an error, `cannot write to standard output: <OS error>`,
//!   and the command exits with code 1. A reader that closed the pipe early (`| head`) gets the
//!   same message and exit code: fmu-pack ignores SIGPIPE like every Rust program, so it is not
//!   killed silently with 141 as C tools are.
//! * Standard error carries diagnostics (warnings, timings, the error line itself): a write
//!   that fails there is ignored, since there is nowhere left to report it, and the exit code
//!   is that of the work.
//! * Files: a failed write names the file and the OS error.

use std::io::Write;
use std::path::Path;

/// Writes `text` to standard output and flushes it.
pub fn stdout(text: &[u8]) -> Result<(), String> {
    let mut out = std::io::stdout().lock();
    out.write_all(text)
        .and_then(|()| out.flush())
        .map_err(|e| format!("cannot write to standard output: {e}"))
}

/// Writes one line to standard error, ignoring failure (see the module docs).
pub fn stderr_line(line: &str) {
    let mut err = std::io::stderr().lock();
    let _ = writeln!(err, "{line}");
    let _ = err.flush();
}

/// Checks, before any work, that the folder `path` goes in exists (`-`, standard output, and a
/// bare file name always pass): a missing folder is an error naming the file.
pub fn check_folder(path: &Path) -> Result<(), String> {
    if path.as_os_str() == "-" {
        return Ok(());
    }
    match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() && !folder.is_dir() => Err(format!(
            "cannot write {}: the folder {} does not exist",
            path.display(),
            folder.display()
        )),
        _ => Ok(()),
    }
}

/// Writes `text` to `path`; `-` is standard output.
pub fn file(path: &Path, text: &[u8]) -> Result<(), String> {
    if path.as_os_str() == "-" {
        stdout(text)
    } else {
        std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
    }
}
