//! What the command-line tests share.

use std::io::Read;
use std::path::Path;
use std::process::Command;

/// Runs the fmu-pack binary of this build: (success, standard output, standard error).
///
/// `pack` gets a stand-in shared library through `HYDROFMU_BINARY` unless the test passes
/// `--binary`: the tests run before the release library is built (`cargo test` on a fresh
/// checkout), and they read the archive's resources, not its binary.
pub fn fmu_pack(args: &[&str]) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_fmu-pack"))
        .args(args)
        .env("HYDROFMU_BINARY", shared_stand_in())
        .output()
        .expect("run fmu-pack");
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// One stand-in library for every `pack` of this test process, written once and whole (a
/// rename), so a `pack` running in another test thread never reads it half written.
fn shared_stand_in() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("hydrofmu-stand-in-{}", std::process::id()));
    let binary = dir.join("libstand-in.so");
    if !binary.is_file() {
        let scratch =
            dir.join(format!("{:?}", std::thread::current().id()).replace(['(', ')'], ""));
        std::fs::create_dir_all(&scratch).unwrap();
        std::fs::rename(stand_in_binary(&scratch), &binary).unwrap();
    }
    binary
}

/// The text of the member `name` of the archive at `archive`; `None` when it has none.
#[allow(dead_code)] // Not every test file reads archives.
pub fn archive_member(archive: &Path, name: &str) -> Option<String> {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(archive).unwrap()).unwrap();
    let mut text = String::new();
    zip.by_name(name).ok()?.read_to_string(&mut text).unwrap();
    Some(text)
}

/// An empty folder of its own for a test named `name` (the tests run in parallel threads).
#[allow(dead_code)] // Not every test file needs one.
pub fn folder(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("hydrofmu-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A stand-in for the shared library in `dir`: `fmu-pack pack --binary` packs it unread.
pub fn stand_in_binary(dir: &Path) -> std::path::PathBuf {
    let binary = dir.join("libstand-in.so");
    std::fs::write(&binary, b"\x7fELF stand-in").unwrap();
    binary
}

/// The checked-in WAMIT v7.2 hemisphere's `.1` file (tests/data/wamit/).
#[allow(dead_code)] // Not every test file imports it.
pub fn wamit_sphere() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/wamit/sphere.1")
        .display()
        .to_string()
}
