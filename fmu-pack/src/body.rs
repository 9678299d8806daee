//! The whole-body commands shared by ship files (strip theory, docs/SHIPS.md) and imported 3D
//! databases (docs/DATABASES.md) on the command line: the tables of a [`Database`] written,
//! the options read, and the archive of a fit ([`hydrofmu::scene::BodyScene`]) packed.

use crate::args::{PackArgs, SweepArgs};
use crate::output;
use crate::packing::{locate_binary, pack_documented, PackError, PackSummary, PackedNetwork};
use crate::pipeline;
use hydrofmu::database::wamit::WamitFiles;
use hydrofmu::database::Database;
use hydrofmu::fmu::{Body, SceneDocumentation};
use hydrofmu::network::NetworkForm;
use hydrofmu::scene::{Band, FittedBody};
use hydrofmu::xml::{format_number, Notation};

/// Writes the database's tables as `fmu-pack sweep` does (all together, or none:
/// [`output::Outputs`]), and its warnings, notes and left-out frequencies to standard error.
pub fn write_tables(database: &Database, args: &SweepArgs) -> Result<(), String> {
    if args.excitation.is_some() && database.excitation.is_empty() {
        return Err(format!(
            "--excitation: {} has no exciting force",
            database.name
        ));
    }
    if args.drift.is_some() && database.drift.is_empty() {
        return Err(format!(
            "--drift: {} has no mean drift (a WAMIT NAME.1 takes it from NAME.8 or NAME.9 \
             beside it; see the notes for files left out)",
            database.name
        ));
    }
    let mut outputs = output::Outputs::new();
    let mut text = Vec::new();
    database
        .write_csv(&mut text)
        .map_err(|e| format!("cannot format the table: {e}"))?;
    outputs.bytes(&args.output, &text)?;
    if let Some(path) = &args.excitation {
        let mut text = Vec::new();
        database
            .write_excitation_csv(&mut text)
            .map_err(|e| format!("cannot format the excitation table: {e}"))?;
        outputs.bytes(path, &text)?;
    }
    if let Some(path) = &args.drift {
        let mut text = Vec::new();
        database
            .write_drift_csv(&mut text)
            .map_err(|e| format!("cannot format the drift table: {e}"))?;
        outputs.bytes(path, &text)?;
    }
    if let Some(path) = &args.hydrostatics {
        let mut text = Vec::new();
        database
            .write_hydrostatics_csv(&mut text)
            .map_err(|e| format!("cannot format the restoring table: {e}"))?;
        outputs.bytes(path, &text)?;
    }
    if let Some(prefix) = &args.wamit {
        stage_wamit(
            &mut outputs,
            prefix,
            &hydrofmu::database::wamit::write(database),
        )?;
    }
    if let Some(path) = &args.netcdf {
        outputs.with_path(path, |temporary| {
            hydrofmu::database::capytaine::write(database, temporary)
        })?;
    }
    outputs.commit()?;
    print_findings(database);
    Ok(())
}

/// Stages `PREFIX.1`, `PREFIX.3` (when there is an exciting force), `PREFIX.9` (when there is
/// a mean drift) and `PREFIX.hst`.
pub fn stage_wamit(
    outputs: &mut output::Outputs,
    prefix: &std::path::Path,
    files: &WamitFiles,
) -> Result<(), String> {
    let path = |ext: &str| {
        let mut name = prefix.as_os_str().to_owned();
        name.push(format!(".{ext}"));
        std::path::PathBuf::from(name)
    };
    outputs.bytes(&path("1"), files.radiation.as_bytes())?;
    if let Some(text) = &files.excitation {
        outputs.bytes(&path("3"), text.as_bytes())?;
    }
    if let Some(text) = &files.drift {
        outputs.bytes(&path("9"), text.as_bytes())?;
    }
    outputs.bytes(&path("hst"), files.hydrostatics.as_bytes())
}

/// Warnings, notes and left-out frequencies, one line each on standard error.
pub fn print_findings(database: &Database) {
    for warning in &database.warnings {
        output::stderr_line(&format!("warning: {warning}"));
    }
    for note in &database.notes {
        output::stderr_line(&format!("note: {note}"));
    }
    for (omega, reason) in &database.failures {
        output::stderr_line(&format!(
            "warning: omega = {} rad/s left out: {reason}",
            format_number(*omega, Notation::Plain)
        ));
    }
}

/// The fit options of `fmu-pack fit` and `fmu-pack pack` for a whole body.
#[derive(Clone, Copy, Debug, Default)]
pub struct FitOptions<'a> {
    /// `--band` as typed.
    pub band: Option<&'a str>,
    /// `--tol`.
    pub tolerance: Option<f64>,
    /// `--order`.
    pub order: Option<usize>,
    /// `--max-step` (s).
    pub max_step: Option<f64>,
    /// `--form`.
    pub form: Option<NetworkForm>,
}

impl<'a> FitOptions<'a> {
    /// The options of `fmu-pack pack` (its form is automatic).
    pub fn of_pack(args: &'a PackArgs) -> FitOptions<'a> {
        FitOptions {
            band: args.band.as_deref(),
            tolerance: args.tol,
            order: args.order,
            max_step: args.max_step,
            form: None,
        }
    }
}

/// The band as `--band` gives it (kR or rad/s), or `default`.
pub fn band_arg(band: Option<&str>, default: Band) -> Result<Band, String> {
    match band {
        Some(text) => pipeline::parse_band(text),
        None => Ok(default),
    }
}

/// The DOFs of `--dofs`, in their order (not yet checked against the body's).
pub fn dofs_arg(dofs: Option<&str>) -> Option<Vec<String>> {
    dofs.map(|list| list.split(',').map(|d| d.trim().to_string()).collect())
}

/// Packs a whole body's fit into one FMU: `documentation/scene.txt` holds the scene report
/// and the fit in words ([`FittedBody::scene_text`]); the summary shows the fit on a line
/// and the scene report below it.
/// `estimate`: the ship's viscous estimate (`None`: the entries given, the others 0).
pub fn pack(
    fitted: &FittedBody,
    args: &PackArgs,
    estimate: Option<crate::viscous_args::Estimate>,
) -> Result<PackSummary, PackError> {
    if args.network.is_some() {
        return Err(PackError(
            "--network applies to a section; a whole body's network is fitted to its data".into(),
        ));
    }
    let text = fitted.fit_text();
    if !fitted.fit.tolerance_met && !args.allow_tolerance_miss {
        return Err(PackError(format!(
            "the fit misses the tolerance; no archive written. Try another --order or a \
             narrower --band, raise --tol, or pass --allow-tolerance-miss to pack it anyway\n{text}"
        )));
    }
    if estimate.is_none() {
        args.viscous.refuse_estimate_options()?;
    }
    let mut body = args
        .viscous
        .apply(Body::whole(&fitted.database, None)?, estimate.as_ref())?;
    if args.drift {
        if fitted.database.drift.is_empty() {
            return Err(PackError(format!(
                "--drift: {} has no mean drift (an imported WAMIT NAME.1 takes it from NAME.8 or \
                 NAME.9 beside it)",
                fitted.database.name
            )));
        }
        let mut text = Vec::new();
        fitted
            .database
            .write_drift_table(&mut text)
            .map_err(|e| PackError(format!("cannot format the drift table: {e}")))?;
        body.drift_csv = Some(String::from_utf8_lossy(&text).into_owned());
    }
    let binary = locate_binary(args.binary.as_deref())?;
    let identifier = match &args.model_identifier {
        Some(id) => id.clone(),
        None => crate::packing::identifier_from_path(&args.output),
    };
    let network = PackedNetwork::from_network(fitted.fit.network.clone());
    let target = crate::packing::Target {
        binary: &binary,
        binary_windows: crate::packing::WindowsBinary::from_args(
            args.binary_windows.as_deref(),
            args.no_windows,
        ),
        model_identifier: &identifier,
        output: &args.output,
        fmi: args.fmi,
    };
    let documentation = SceneDocumentation {
        scene: fitted.scene_text(),
        fit: String::new(),
        plots: Vec::new(),
    };
    let mut summary = pack_documented(
        body,
        network,
        args.keep_inf_mass,
        &target,
        Some(documentation),
    )?;
    summary.fit = Some(text.replace('\n', "; "));
    summary.scene = Some(fitted.report.to_string());
    if args.viscous.viscous {
        summary.viscous = match estimate {
            Some(estimate) => estimate.lines,
            None if args.viscous.no_estimate => {
                vec!["the entries given (--no-estimate), the others 0".into()]
            }
            None => vec![
                "the entries given, the others 0 (an imported database has no geometry to \
                 estimate from)"
                    .into(),
            ],
        };
    }
    Ok(summary)
}
