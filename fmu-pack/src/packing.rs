//! Writing an archive: [`hydrofmu::fmu::Archive`] (its layout and GUID are documented there)
//! from a body and its network, the binary found, the archive and the OSP description beside
//! it written together; and reading one back ([`hydrofmu::fmu::inspect`]).

use crate::args::FmiVersion;
use crate::floating::FloatingSection;
use crate::pipeline::Built;
use hydrofmu::fmu::{self, osp, Archive, ArchiveError, Body, SceneDocumentation};
use hydrofmu::scene::SceneReport;
use std::fmt;
use std::path::{Path, PathBuf};

pub use hydrofmu::fmu::{identifier_from_path, PackedNetwork};

/// Why packing or inspecting failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PackError(pub String);

impl fmt::Display for PackError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PackError {}

impl From<String> for PackError {
    fn from(s: String) -> Self {
        PackError(s)
    }
}

impl From<&str> for PackError {
    fn from(s: &str) -> Self {
        PackError(s.to_string())
    }
}

impl From<ArchiveError> for PackError {
    fn from(e: ArchiveError) -> Self {
        PackError(e.0)
    }
}

/// Which Windows DLL an archive carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WindowsBinary<'a> {
    /// [`WINDOWS_BINARY_NAME`] next to the Linux library, if there is one (the default).
    Beside,
    /// This DLL (`--binary-windows PATH`).
    Given(&'a Path),
    /// None (`--no-windows`): a Linux-only archive.
    LeftOut,
}

impl<'a> WindowsBinary<'a> {
    /// From the command line's `--binary-windows` and `--no-windows` (clap refuses both).
    pub fn from_args(given: Option<&'a Path>, left_out: bool) -> Self {
        match (given, left_out) {
            (_, true) => WindowsBinary::LeftOut,
            (Some(path), false) => WindowsBinary::Given(path),
            (None, false) => WindowsBinary::Beside,
        }
    }
}

/// Where and how an archive is written.
#[derive(Clone, Copy, Debug)]
pub struct Target<'a> {
    /// The hydrofmu shared library to pack.
    pub binary: &'a Path,
    /// The Windows DLL to pack too ([`locate_windows_binary`]).
    pub binary_windows: WindowsBinary<'a>,
    /// modelIdentifier (the binary's name in the archive).
    pub model_identifier: &'a str,
    /// The archive.
    pub output: &'a Path,
    /// Its FMI version.
    pub fmi: FmiVersion,
}

/// What was packed.
#[derive(Clone, Debug, PartialEq)]
pub struct PackSummary {
    /// Archive written.
    pub path: PathBuf,
    /// modelIdentifier.
    pub model_identifier: String,
    /// The platforms the archive carries a binary for (`linux64`, `win64`, ...).
    pub platforms: Vec<String>,
    /// GUID.
    pub guid: String,
    /// DOF names.
    pub dofs: Vec<String>,
    /// Network states: the length of the network's state vector.
    pub states: usize,
    /// Whether A_inf is kept inside.
    pub keep_inf_mass: bool,
    /// Fit summary, when the network was computed.
    pub fit: Option<String>,
    /// What the scene's FMU leaves out, when the network was computed.
    pub scene: Option<String>,
    /// The OSP model description written beside the archive.
    pub osp: Option<PathBuf>,
    /// The viscous damping packed and where it comes from, one line each.
    pub viscous: Vec<String>,
    /// The water depth the packed tables were computed for (the FMU's `depth`).
    pub depth: hydrofmu::units::WaterDepth,
}

/// A network computed for the archive: the pipeline's products and the scene report.
pub struct Fitted {
    /// Sweep and fit.
    pub built: Built,
    /// What was left out and the error it causes.
    pub scene: SceneReport,
}

impl fmt::Display for PackSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "wrote {}", self.path.display())?;
        writeln!(f, "  modelIdentifier  {}", self.model_identifier)?;
        writeln!(f, "  platforms        {}", self.platforms.join(", "))?;
        writeln!(f, "  GUID             {}", self.guid)?;
        writeln!(f, "  DOFs             {}", self.dofs.join(" "))?;
        writeln!(f, "  network states   {}", self.states)?;
        write!(
            f,
            "  A_inf            {}",
            if self.keep_inf_mass {
                "inside (acceleration inputs)"
            } else {
                "outside (add added_mass_inf to the hull's mass)"
            }
        )?;
        write!(f, "\n  water depth      {}", self.depth)?;
        if let Some(osp) = &self.osp {
            write!(f, "\n  OSP description  {}", osp.display())?;
        }
        if let Some(fit) = &self.fit {
            write!(f, "\n  fit              {fit}")?;
        }
        if !self.viscous.is_empty() {
            write!(f, "\n  viscous")?;
            for line in &self.viscous {
                write!(f, "\n    {line}")?;
            }
        }
        if let Some(scene) = &self.scene {
            write!(f, "\n  scene")?;
            for line in scene.lines() {
                write!(f, "\n    {line}")?;
            }
        }
        Ok(())
    }
}

/// Packs a network for a body into `target.output` (the lower-level entry point): the
/// section's exciting force (and with `drift` its mean drift table: of the floating section
/// given, else of the fixed one) from the fit's sweep, the scene report, the fit report and its
/// figures when a scene computed the network; the archive and its OSP description written
/// together, or neither.
pub fn pack_network(
    body: Body,
    network: PackedNetwork,
    keep_inf_mass: bool,
    target: &Target,
    fit: Option<&Fitted>,
    drift: Option<Option<&FloatingSection>>,
) -> Result<PackSummary, PackError> {
    refuse_standard_output(target.output)?;
    // A network packed from a file has no sweep: its FMU models calm water only.
    let body = match fit {
        Some(fitted) => {
            let names = &network.network().dof_names;
            let body = body.with_sweep_excitation(&fitted.built.sweep, names)?;
            match drift {
                Some(Some((floating, line))) => {
                    body.with_floating_drift(&fitted.built.sweep, names, floating, line)?
                }
                Some(None) => body.with_sweep_drift(&fitted.built.sweep, names)?,
                None => body,
            }
        }
        None if drift.is_some() => {
            return Err(PackError(
                "--drift: a network packed from a file has no sweep, so no drift table; pack \
                 the hull without --network"
                    .into(),
            ))
        }
        None => body,
    };
    let documentation = fit.map(|Fitted { built, scene }| SceneDocumentation {
        scene: scene.to_string(),
        fit: crate::fit_report::text(built),
        plots: crate::fit_report::plots(built),
    });
    let mut summary = pack_documented(body, network, keep_inf_mass, target, documentation)?;
    summary.fit = fit.map(|Fitted { built: b, .. }| {
        format!(
            "{} auxiliary DOFs, largest error {:.2} % of sqrt(|A_ii A_jj|) (tolerance {:.2} %, {}), sweep {:.2} s, fit {:.2} s",
            b.fit.aux_dofs,
            100.0 * b.fit.max_relative_error,
            100.0 * b.fit.tolerance,
            if b.fit.tolerance_met { "met" } else { "NOT met" },
            b.sweep_time.as_secs_f64(),
            b.fit_time.as_secs_f64()
        )
    });
    Ok(summary)
}

/// Refuses `-o -`: an archive is not written to standard output.
fn refuse_standard_output(output: &Path) -> Result<(), PackError> {
    if output.as_os_str() == "-" {
        return Err(PackError(
            "-o -: an archive is written to a file, not to standard output (which carries the \
             summary); name a file"
                .into(),
        ));
    }
    Ok(())
}

/// Packs a network for a body into `target.output` with its scene's documentation (the
/// archive's `documentation/scene.txt` and the sections of its index), when given; the
/// archive and its OSP description written together, or neither. The summary's `fit` is
/// left to the caller.
pub fn pack_documented(
    body: Body,
    network: PackedNetwork,
    keep_inf_mass: bool,
    target: &Target,
    documentation: Option<SceneDocumentation>,
) -> Result<PackSummary, PackError> {
    let Target {
        binary,
        binary_windows,
        model_identifier,
        output,
        fmi,
    } = *target;
    refuse_standard_output(output)?;
    let mut archive = Archive::new(body, network, model_identifier, fmu::read_binary(binary)?);
    if let Some(dll) = locate_windows_binary(binary_windows, binary)? {
        let bytes = fmu::read_binary(&dll)?;
        archive.binary_windows = Some(bytes);
    }
    archive.keep_inf_mass = keep_inf_mass;
    archive.fmi = fmi.into();
    archive.scene = documentation;
    let depth = archive.depth()?;
    let packed = archive.build()?;
    // The archive and the OSP description beside it are written together, or neither.
    let mut outputs = crate::output::Outputs::new();
    outputs.bytes(output, &packed.bytes)?;
    let osp = stage_osp_beside(
        &mut outputs,
        output,
        &packed.model_name,
        &packed.osp_description,
    )?;
    outputs.commit()?;
    Ok(PackSummary {
        path: output.to_path_buf(),
        model_identifier: model_identifier.to_string(),
        platforms: packed.platforms,
        guid: packed.guid,
        dofs: packed.dofs,
        states: packed.states,
        keep_inf_mass,
        osp,
        viscous: Vec::new(),
        depth,
        scene: packed.scene,
        fit: None,
    })
}

/// Stages the OSP description beside `archive` in `outputs` (committed with the archive) when
/// the archive goes to a regular file ([`osp::path_beside`]); returns the path it will have.
/// Replacing another hull's description is warned about.
pub fn stage_osp_beside(
    outputs: &mut crate::output::Outputs,
    archive: &Path,
    model_name: &str,
    text: &str,
) -> Result<Option<PathBuf>, String> {
    let Some(path) = osp::path_beside(archive, model_name) else {
        return Ok(None);
    };
    let limit = hydrofmu::xml::MAX_INPUT_BYTES as u64;
    if hydrofmu::input::read_bounded_text(&path, limit, "MAX_INPUT_BYTES")
        .is_ok_and(|old| old != text)
    {
        crate::output::stderr_line(&format!(
            "fmu-pack: warning: {} replaced by another hull FMU's groups (one modelName per \
             hull: keep FMUs of a hull with different DOFs in separate folders)",
            path.display()
        ));
    }
    outputs.bytes(&path, text.as_bytes())?;
    Ok(Some(path))
}

/// The hydrofmu shared library: `--binary`, else `HYDROFMU_BINARY`, else, for a release build
/// of fmu-pack, the library cargo built with it (`release/deps/libhydrofmu.so`: building
/// fmu-pack builds the library's cdylib there, only `cargo build -p hydrofmu` copies it up),
/// else `libhydrofmu.so` next to this executable. If none is there and this executable lives
/// in this workspace's target directory, the release library is built with cargo.
pub fn locate_binary(explicit: Option<&Path>) -> Result<PathBuf, PackError> {
    if let Some(p) = explicit {
        return existing(p, "--binary");
    }
    if let Some(p) = std::env::var_os("HYDROFMU_BINARY") {
        return existing(Path::new(&p), "HYDROFMU_BINARY");
    }
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate fmu-pack: {e}"))?;
    let exe_dir = exe
        .parent()
        .ok_or("fmu-pack has no parent directory")?
        .to_path_buf();
    let target_dir = exe_dir.parent().map(Path::to_path_buf);
    let in_cargo_target = target_dir
        .as_ref()
        .is_some_and(|t| t.join("CACHEDIR.TAG").is_file());
    let built_with_this = exe_dir.join("deps").join("libhydrofmu.so");
    if in_cargo_target && exe_dir.ends_with("release") && built_with_this.is_file() {
        return Ok(built_with_this);
    }
    let beside = exe_dir.join("libhydrofmu.so");
    if beside.is_file() {
        return Ok(beside);
    }
    let manifest = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../Cargo.toml"));
    if let (true, true, Some(target_dir)) = (manifest.is_file(), in_cargo_target, target_dir) {
        crate::output::stderr_line(&format!(
            "fmu-pack: {} is missing; building it: cargo build --release -p hydrofmu --lib",
            beside.display()
        ));
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let status = std::process::Command::new(cargo)
            .args([
                "build",
                "--release",
                "-p",
                "hydrofmu",
                "--lib",
                "--manifest-path",
            ])
            .arg(manifest)
            .env("CARGO_TARGET_DIR", &target_dir)
            .status()
            .map_err(|e| format!("cannot run cargo: {e}"))?;
        if !status.success() {
            return Err(PackError(format!("building hydrofmu failed ({status})")));
        }
        let built = target_dir.join("release").join("libhydrofmu.so");
        return existing(&built, "the release build");
    }
    Err(PackError(format!(
        "cannot find libhydrofmu.so: pass --binary PATH, set HYDROFMU_BINARY, or put it next to {} \
         (cargo build --release -p hydrofmu --lib)",
        exe.display()
    )))
}

/// The Windows DLL's file name that [`locate_windows_binary`] looks for.
pub const WINDOWS_BINARY_NAME: &str = "hydrofmu.dll";

/// The Windows DLL to pack with `linux` (docs/WINDOWS.md): the one given
/// (`--binary-windows`), none (`--no-windows`), or else [`WINDOWS_BINARY_NAME`] in `linux`'s
/// folder, or in its parent when that folder is cargo's `deps`; `None` when there is none. A
/// found DLL older than `linux` is packed with a warning ([`stale_windows_binary`]).
pub fn locate_windows_binary(
    choice: WindowsBinary,
    linux: &Path,
) -> Result<Option<PathBuf>, PackError> {
    match choice {
        WindowsBinary::Given(p) => return existing(p, "--binary-windows").map(Some),
        WindowsBinary::LeftOut => return Ok(None),
        WindowsBinary::Beside => {}
    }
    let folder = linux.parent().unwrap_or(Path::new("."));
    let mut candidates = vec![folder.join(WINDOWS_BINARY_NAME)];
    if folder.ends_with("deps") {
        if let Some(up) = folder.parent() {
            candidates.push(up.join(WINDOWS_BINARY_NAME));
        }
    }
    let Some(found) = candidates.into_iter().find(|c| c.is_file()) else {
        return Ok(None);
    };
    if let Some(warning) = stale_windows_binary(&found, linux) {
        crate::output::stderr_line(&warning);
    }
    Ok(Some(found))
}

/// The warning for a found DLL `dll` last modified before the Linux library `linux`: it may
/// lag the sources. `None` when it is not older, or a time cannot be read.
pub fn stale_windows_binary(dll: &Path, linux: &Path) -> Option<String> {
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    (modified(dll)? < modified(linux)?).then(|| {
        format!(
            "fmu-pack: warning: {} is older than {}: the Windows binary may lag the sources \
             (rebuild it: tools/build-windows.sh, or leave it out: --no-windows)",
            dll.display(),
            linux.display()
        )
    })
}

fn existing(p: &Path, source: &str) -> Result<PathBuf, PackError> {
    if p.is_file() {
        Ok(p.to_path_buf())
    } else {
        Err(PackError(format!(
            "{source}: {} is not a file",
            p.display()
        )))
    }
}

/// `fmu-pack inspect`. Every error starts with the archive's path.
pub fn inspect(path: &Path) -> Result<fmu::Inspection, PackError> {
    Ok(fmu::inspect(path)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Schilder et al.'s 2-DOF network (the shipped example file).
    const SEED: &str = include_str!("../../examples/networks/seed_2dof.xml");

    fn temp_dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("fmu-pack-test-{}-{tag}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn hull() -> Body {
        let hull = hydrofmu::hull::Hull::semicircle(1.0)
            .unwrap()
            .select_dofs(&["sway", "roll"])
            .unwrap();
        Body::section(&hull)
    }

    fn net() -> PackedNetwork {
        PackedNetwork::from_text(SEED.to_string(), "test network").unwrap()
    }

    #[test]
    fn the_archive_and_its_osp_description_are_written_together() {
        let dir = temp_dir("layout");
        let binary = dir.join("libfake.so");
        std::fs::write(&binary, b"\x7fELF fake").unwrap();
        let out = dir.join("Seed-1.fmu");
        let id = identifier_from_path(&out);
        let target = Target {
            binary: &binary,
            binary_windows: WindowsBinary::Beside,
            model_identifier: &id,
            output: &out,
            fmi: FmiVersion::V3,
        };
        let summary = pack_network(hull(), net(), false, &target, None, None).unwrap();
        assert_eq!(summary.dofs, vec!["sway".to_string()]);
        let found = inspect(&out).unwrap();
        assert_eq!(found.guid, summary.guid);
        assert_eq!(found.fmi_version, "3.0");
        let beside = summary.osp.clone().unwrap();
        assert_eq!(
            beside,
            dir.join("hydrofmu Semicircle_OspModelDescription.xml")
        );
        assert!(beside.is_file());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_windows_dll_beside_the_linux_library_goes_into_both_standards() {
        let dir = temp_dir("windows");
        let binary = dir.join("libhydrofmu.so");
        std::fs::write(&binary, b"\x7fELF fake").unwrap();
        let pack = |fmi, windows: WindowsBinary| {
            let out = dir.join("W.fmu");
            let target = Target {
                binary: &binary,
                binary_windows: windows,
                model_identifier: "W",
                output: &out,
                fmi,
            };
            let summary = pack_network(hull(), net(), false, &target, None, None);
            (summary, inspect(&out))
        };
        let (summary, found) = pack(FmiVersion::V2, WindowsBinary::Beside);
        assert_eq!(summary.unwrap().platforms, ["linux64"]);
        assert_eq!(found.unwrap().platforms, ["linux64"]);
        std::fs::write(dir.join(WINDOWS_BINARY_NAME), b"MZ fake").unwrap();
        let (summary, found) = pack(FmiVersion::V2, WindowsBinary::Beside);
        assert_eq!(summary.unwrap().platforms, ["linux64", "win64"]);
        let found = found.unwrap();
        assert!(found.entries.contains(&"binaries/win64/W.dll".to_string()));
        assert!(found
            .to_string()
            .contains("platforms         linux64, win64"));
        let (summary, found) = pack(FmiVersion::V3, WindowsBinary::Beside);
        assert!(summary
            .unwrap()
            .to_string()
            .contains("platforms        x86_64-linux, x86_64-windows"));
        assert!(found
            .unwrap()
            .entries
            .contains(&"binaries/x86_64-windows/W.dll".to_string()));
        // Given explicitly: it must exist and be a DLL.
        let (summary, _) = pack(FmiVersion::V2, WindowsBinary::Given(&dir.join("none.dll")));
        assert!(summary.unwrap_err().0.contains("--binary-windows"));
        let (summary, _) = pack(FmiVersion::V2, WindowsBinary::Given(&binary));
        assert!(summary.unwrap_err().0.contains("not a DLL"));
        // Left out: a Linux-only archive although a DLL is beside the library.
        let (summary, found) = pack(FmiVersion::V2, WindowsBinary::LeftOut);
        assert_eq!(summary.unwrap().platforms, ["linux64"]);
        assert!(!found
            .unwrap()
            .entries
            .iter()
            .any(|e| e.starts_with("binaries/win64")));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_dll_older_than_the_linux_library_is_packed_with_a_warning() {
        let dir = temp_dir("stale");
        let (so, dll) = (dir.join("libhydrofmu.so"), dir.join(WINDOWS_BINARY_NAME));
        std::fs::write(&so, b"\x7fELF fake").unwrap();
        std::fs::write(&dll, b"MZ fake").unwrap();
        let set = |path: &Path, seconds: u64| {
            let time = std::time::UNIX_EPOCH + std::time::Duration::from_secs(seconds);
            std::fs::File::options()
                .write(true)
                .open(path)
                .unwrap()
                .set_modified(time)
                .unwrap();
        };
        set(&so, 2_000_000_000);
        set(&dll, 1_999_999_999);
        let warning = stale_windows_binary(&dll, &so).unwrap();
        assert!(warning.contains("is older than"), "{warning}");
        assert!(warning.contains("--no-windows"), "{warning}");
        // Still packed: the warning does not refuse it.
        let found = locate_windows_binary(WindowsBinary::Beside, &so).unwrap();
        assert_eq!(found.as_deref(), Some(dll.as_path()));
        set(&dll, 2_000_000_000);
        assert_eq!(stale_windows_binary(&dll, &so), None);
        set(&dll, 2_000_000_001);
        assert_eq!(stale_windows_binary(&dll, &so), None);
        // Only a DLL found beside is checked; one missing is no warning.
        assert_eq!(stale_windows_binary(&dir.join("none.dll"), &so), None);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn mistakes_are_reported_clearly() {
        let dir = temp_dir("errors");
        let binary = dir.join("lib.so");
        std::fs::write(&binary, b"x").unwrap();
        let out = dir.join("x.fmu");
        let to = |binary: &Path, output: &Path| {
            let target = Target {
                binary,
                binary_windows: WindowsBinary::Beside,
                model_identifier: "X",
                output,
                fmi: FmiVersion::V2,
            };
            pack_network(hull(), net(), false, &target, None, None).unwrap_err()
        };
        let e = to(&dir.join("missing.so"), &out);
        assert!(e.0.contains("cannot read the binary"), "{e}");
        assert!(!out.exists());
        let e = to(&binary, Path::new("-"));
        assert!(
            e.0.starts_with("-o -: an archive is written to a file"),
            "{e}"
        );
        assert!(locate_binary(Some(&dir.join("missing.so"))).is_err());
        assert!(inspect(&binary).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn the_description_is_staged_beside_a_file_and_not_beside_a_device() {
        let dir = std::env::temp_dir().join(format!("fmu-pack-osp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let archive = dir.join("X.fmu");
        let mut outputs = crate::output::Outputs::new();
        for device in ["/dev/null", "-"] {
            assert_eq!(
                stage_osp_beside(&mut outputs, Path::new(device), "m", "x").unwrap(),
                None
            );
        }
        let staged = stage_osp_beside(&mut outputs, &archive, "hydrofmu X", "text")
            .unwrap()
            .unwrap();
        assert_eq!(staged, dir.join("hydrofmu X_OspModelDescription.xml"));
        // Staged, not yet written: nothing there until the commit.
        assert!(!staged.exists());
        outputs.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&staged).unwrap(), "text");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
