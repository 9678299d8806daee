//! `fmu-pack sweep|fit|pack NAME.1|NAME.nc`: an imported 3D database (WAMIT files, as WAMIT,
//! Capytaine's `export_to_wamit`, BEMRosetta or HAMS write them, or a Capytaine NetCDF-3
//! dataset) to the whole-body tables, fit and FMU (docs/DATABASES.md).

use crate::args::PackArgs;
use crate::args::{HullSweepArgs, SweepArgs};
use crate::body::{self, BodyFit};
use crate::packing::{PackError, PackSummary};
use hydrofmu::database::import::{self, ImportParams};
use hydrofmu::database::wamit::FrequencyColumn;
use hydrofmu::database::Database;
use hydrofmu::scene::Band;
use std::path::Path;
use std::time::{Duration, Instant};

/// The import parameters of the command line; the section and ship options refused.
fn params(args: &HullSweepArgs) -> Result<ImportParams, String> {
    let refused = [
        ("--depth", args.depth.is_some()),
        ("--panels", args.panels.is_some()),
        ("--levels", args.levels.is_some()),
        ("--omega", args.omega.is_some()),
        ("--headings", args.headings.is_some()),
    ];
    if let Some((flag, _)) = refused.iter().find(|(_, given)| *given) {
        return Err(format!(
            "{flag} does not apply to an imported database ('{}'): its frequencies, headings and \
             mesh are the file's",
            args.hull
        ));
    }
    let mut params = ImportParams::new();
    if let Some(l) = args.length_scale {
        if !(l.is_finite() && l > 0.0) {
            return Err(format!("--length-scale {l}: it must be finite and > 0 m"));
        }
        params.wamit.length_scale = l;
    }
    if let Some(column) = &args.frequency_column {
        params.wamit.frequency_column = match column.as_str() {
            "period" => FrequencyColumn::Period,
            "omega" => FrequencyColumn::RadPerSecond,
            "hz" => FrequencyColumn::Hertz,
            other => {
                return Err(format!(
                    "--frequency-column '{other}': expected period, omega or hz"
                ))
            }
        };
        // Given on the command line, it wins over a NAME.cfg beside the files.
        params.read_cfg = false;
    }
    params.wamit.conjugate = args.conjugate;
    if args.plain {
        params.spikes = None;
    }
    Ok(params)
}

/// Imports the database of `args`, restricted to `--dofs` when given.
pub fn import(args: &HullSweepArgs) -> Result<(Database, Duration), String> {
    let params = params(args)?;
    let start = Instant::now();
    let mut database = import::import(Path::new(&args.hull), &params).map_err(|e| e.to_string())?;
    if let Some(list) = &args.dofs {
        let names: Vec<&str> = list.split(',').map(str::trim).collect();
        for (k, name) in names.iter().enumerate() {
            if !database.dof_names.iter().any(|d| d == name) || names[..k].contains(name) {
                return Err(format!(
                    "--dofs: '{name}' is not a DOF of {} or is named twice; its DOFs: {}",
                    args.hull,
                    database.dof_names.join(" ")
                ));
            }
        }
        database = database
            .select_dofs(&names)
            .ok_or_else(|| "--dofs: a DOF is missing".to_string())?;
    }
    Ok((database, start.elapsed()))
}

/// `fmu-pack sweep NAME.1`: the database's tables in the product's format and conventions.
pub fn run(args: &SweepArgs) -> Result<(), String> {
    if args.froude_krylov.is_some() {
        return Err("--froude-krylov applies to a section, not to an imported database".into());
    }
    let (database, elapsed) = import(&args.sweep)?;
    body::write_tables(&database, args)?;
    crate::output::stderr_line(&summary(&database, elapsed));
    Ok(())
}

/// One line: what was imported.
fn summary(database: &Database, elapsed: Duration) -> String {
    format!(
        "{}: {} DOFs ({}), {} frequencies {:.4} .. {:.4} rad/s ({} left out), {} headings, {:.3} s",
        database.name,
        database.dof_names.len(),
        database.dof_names.join(" "),
        database.omega.len(),
        database.omega.first().copied().unwrap_or(f64::NAN),
        database.omega.last().copied().unwrap_or(f64::NAN),
        database.failures.len(),
        database.headings.len(),
        elapsed.as_secs_f64()
    )
}

/// Imports and fits (default band: every frequency of the file).
pub fn fit(
    args: &HullSweepArgs,
    band: Option<&str>,
    tolerance: Option<f64>,
    order: Option<usize>,
    max_step: Option<f64>,
) -> Result<BodyFit, String> {
    let (database, elapsed) = import(args)?;
    let whole = Band::rad_per_second(
        database.omega[0] * (1.0 - 1e-12),
        database.omega[database.omega.len() - 1] * (1.0 + 1e-12),
    )
    .map_err(|_| format!("{}: its frequencies give no band", args.hull))?;
    let band = body::band(band, whole, database.reference_length, database.g, max_step)?;
    for warning in &database.warnings {
        crate::output::stderr_line(&format!("warning: {warning}"));
    }
    let description = format!("database {}", summary(&database, elapsed));
    // ULEN for WAMIT files: the fit is then the same at any length scale.
    let length_unit = Some(database.reference_length);
    body::fit(
        database,
        description,
        String::new(),
        band,
        tolerance,
        order,
        elapsed,
        length_unit,
    )
    .map_err(|e| format!("{}: {e}", args.hull))
}

/// `fmu-pack pack NAME.1`: one FMU for the body.
pub fn pack(args: &PackArgs) -> Result<PackSummary, PackError> {
    let fitted = fit(
        &args.sweep,
        args.band.as_deref(),
        args.tol,
        args.order,
        args.max_step,
    )?;
    body::pack(&fitted, args)
}
