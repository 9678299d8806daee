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
//! * Files: a failed write names the file and the OS error. A command's files are written
//!   together at its end or not at all ([`Outputs`]): a failure leaves the files already there
//!   as they were.

use std::io::Write;
use std::path::{Path, PathBuf};

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

/// Checks, before any work, that the folder `path` goes in exists and takes a new file (`-`,
/// standard output, and an existing target that is not a regular file, a device, always pass):
/// a missing folder, or one that is read-only or otherwise refuses a file, is an error naming
/// the file. The test writes and removes an empty file in the folder.
pub fn check_folder(path: &Path) -> Result<(), String> {
    if path.as_os_str() == "-" || std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
        return Ok(());
    }
    let folder = match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Err(format!(
            "cannot write {}: the folder {} does not exist",
            path.display(),
            folder.display()
        ));
    }
    let probe = folder.join(format!(".fmu-pack-probe-{}", std::process::id()));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(format!(
            "cannot write {}: the folder {} takes no new file ({e})",
            path.display(),
            folder.display()
        )),
    }
}

/// The files one command writes, committed together. Each is written to a temporary file
/// beside it as it comes ([`Outputs::bytes`], [`Outputs::with_path`]); [`Outputs::commit`]
/// renames them all into place once every one is written. Dropped without a commit (an error
/// on the way), the temporary files are removed and the files already there are untouched.
/// `-` is standard output, written at the commit; an existing target that is not a regular
/// file (a device such as `/dev/null`, a named pipe) is written into at the commit, not
/// replaced.
#[derive(Default)]
pub struct Outputs {
    staged: Vec<Staged>,
}

/// One output: its temporary file and where it goes.
struct Staged {
    temporary: PathBuf,
    target: PathBuf,
}

impl Outputs {
    /// No outputs yet.
    pub fn new() -> Outputs {
        Outputs::default()
    }

    /// Stages `bytes` for `path`.
    ///
    /// # Errors
    /// The temporary file cannot be written (the message names `path`).
    pub fn bytes(&mut self, path: &Path, bytes: &[u8]) -> Result<(), String> {
        self.with_path(path, |temporary| {
            std::fs::write(temporary, bytes)
                .map_err(|e| format!("cannot write {}: {e}", temporary.display()))
        })
    }

    /// Stages the file that `write` writes at the temporary path it is given, for `path`.
    ///
    /// # Errors
    /// `path` is a folder, or `write` fails (its message, the temporary path replaced by
    /// `path`).
    pub fn with_path<E>(
        &mut self,
        path: &Path,
        write: impl FnOnce(&Path) -> Result<(), E>,
    ) -> Result<(), String>
    where
        String: From<E>,
    {
        if std::fs::metadata(path).is_ok_and(|m| m.is_dir()) {
            return Err(format!("cannot write {}: it is a folder", path.display()));
        }
        let temporary = self.temporary_beside(path)?;
        let result = write(&temporary);
        // Kept in the list first, so that it is removed on failure too.
        self.staged.push(Staged {
            temporary: temporary.clone(),
            target: path.to_path_buf(),
        });
        result.map_err(|e| {
            String::from(e).replace(
                &temporary.display().to_string(),
                &path.display().to_string(),
            )
        })
    }

    /// Puts every staged file in place: standard output and devices first (the likelier to
    /// fail), then the renames.
    ///
    /// # Errors
    /// A write or rename that fails; the outputs not yet in place keep their former content.
    pub fn commit(mut self) -> Result<(), String> {
        let staged = std::mem::take(&mut self.staged);
        let (direct, renamed): (Vec<&Staged>, Vec<&Staged>) = staged.iter().partition(|s| {
            s.target.as_os_str() == "-" || std::fs::metadata(&s.target).is_ok_and(|m| !m.is_file())
        });
        let result = direct
            .iter()
            .try_for_each(|s| s.copy_into_target())
            .and_then(|()| renamed.iter().try_for_each(|s| s.rename_onto_target()));
        for s in &staged {
            let _ = std::fs::remove_file(&s.temporary);
        }
        result
    }

    /// A new temporary file's path in `path`'s folder (`.NAME.PID.N.part`; for standard
    /// output or a device, in the system's temporary folder), created empty so that no other
    /// file is taken.
    fn temporary_beside(&self, path: &Path) -> Result<PathBuf, String> {
        let direct = path.as_os_str() == "-" || std::fs::metadata(path).is_ok_and(|m| !m.is_file());
        let folder = match path.parent() {
            _ if direct => std::env::temp_dir(),
            Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let name = path
            .file_name()
            .map_or("output".into(), |n| n.to_string_lossy().into_owned());
        let temporary = folder.join(format!(
            ".{name}.{}.{}.part",
            std::process::id(),
            self.staged.len()
        ));
        std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temporary)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        Ok(temporary)
    }
}

impl Drop for Outputs {
    fn drop(&mut self) {
        for s in &self.staged {
            let _ = std::fs::remove_file(&s.temporary);
        }
    }
}

impl Staged {
    /// Writes the temporary file's content to standard output or into the existing device.
    fn copy_into_target(&self) -> Result<(), String> {
        let bytes = std::fs::read(&self.temporary)
            .map_err(|e| format!("cannot read back {}: {e}", self.temporary.display()))?;
        if self.target.as_os_str() == "-" {
            return stdout(&bytes);
        }
        std::fs::OpenOptions::new()
            .write(true)
            .open(&self.target)
            .and_then(|mut file| file.write_all(&bytes).and_then(|()| file.flush()))
            .map_err(|e| format!("cannot write {}: {e}", self.target.display()))
    }

    /// Syncs the temporary file and renames it over the target.
    fn rename_onto_target(&self) -> Result<(), String> {
        std::fs::File::open(&self.temporary)
            .and_then(|file| file.sync_all())
            .and_then(|()| std::fs::rename(&self.temporary, &self.target))
            .map_err(|e| format!("cannot write {}: {e}", self.target.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_output_is_refused_before_the_work_where_it_cannot_go() {
        let e = check_folder(Path::new("/nonexistent-folder/x.fmu")).unwrap_err();
        assert!(
            e.ends_with("the folder /nonexistent-folder does not exist"),
            "{e}"
        );
        // sysfs takes no new file, not even from root.
        let e = check_folder(Path::new("/sys/x.fmu")).unwrap_err();
        assert!(
            e.starts_with("cannot write /sys/x.fmu: the folder /sys takes no new file"),
            "{e}"
        );
        for fine in ["-", "/dev/null"] {
            assert_eq!(check_folder(Path::new(fine)), Ok(()), "{fine}");
        }
        let dir = std::env::temp_dir().join(format!("fmu-pack-folder-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert_eq!(check_folder(&dir.join("x.fmu")), Ok(()));
        // The probe leaves nothing behind.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
