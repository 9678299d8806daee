//! What the command-line tests share.

use std::process::Command;

/// Runs the fmu-pack binary of this build: (success, standard output, standard error).
pub fn fmu_pack(args: &[&str]) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_fmu-pack"))
        .args(args)
        .output()
        .expect("run fmu-pack");
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}
