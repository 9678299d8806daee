//! `fmu-pack sweep|fit|pack NAME.1|NAME.nc`: an imported 3D database (WAMIT files, as WAMIT,
//! Capytaine's `export_to_wamit`, BEMRosetta or HAMS write them, or a Capytaine NetCDF-3
//! dataset) to the whole-body tables, fit and FMU (docs/DATABASES.md).

use crate::args::PackArgs;
use crate::args::{HullSweepArgs, SweepArgs};
use crate::body::{self, FitOptions};
use crate::packing::{PackError, PackSummary};
use hydrofmu::database::import::{self, ImportParams};
use hydrofmu::database::wamit::FrequencyColumn;
use hydrofmu::database::Database;
use hydrofmu::scene::{all_frequencies, whole_body, BodyScene, FittedBody};
use hydrofmu::units::WaterDepth;
use std::path::Path;
use std::time::{Duration, Instant};

/// The import parameters of the command line (`--water-depth`: the depth of WAMIT files, which
/// do not state it; a Capytaine dataset's own must agree); the section and ship options
/// refused.
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
    if let Some(metres) = args.water_depth {
        // WAMIT files do not state their depth; a Capytaine dataset's must agree.
        params.depth = Some(
            WaterDepth::new(metres)
                .map_err(|e| format!("--water-depth {metres}: {e} (`inf` for deep water)"))?,
        );
    }
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

/// Imports the whole database of `args`, and the `--dofs` asked for (checked against its
/// DOFs).
fn import_whole(args: &HullSweepArgs) -> Result<(Database, Option<Vec<String>>, Duration), String> {
    let params = params(args)?;
    let start = Instant::now();
    let database = import::import(Path::new(&args.hull), &params).map_err(|e| e.to_string())?;
    let elapsed = start.elapsed();
    let dofs = body::dofs_arg(args.dofs.as_deref());
    if let Some(names) = &dofs {
        let list: Vec<&str> = names.iter().map(String::as_str).collect();
        whole_body::dofs(&list, &args.hull, &database.dof_names).map_err(|e| e.to_string())?;
    }
    Ok((database, dofs, elapsed))
}

/// Imports the database of `args`, restricted to `--dofs` when given.
pub fn import(args: &HullSweepArgs) -> Result<(Database, Duration), String> {
    let (mut database, dofs, elapsed) = import_whole(args)?;
    if let Some(names) = &dofs {
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        database = database
            .select_dofs(&names)
            .ok_or_else(|| "--dofs: a DOF is missing".to_string())?;
    }
    Ok((database, elapsed))
}

/// `fmu-pack sweep NAME.1`: the database's tables in the product's format and conventions.
pub fn run(args: &SweepArgs) -> Result<(), String> {
    if args.froude_krylov.is_some() {
        return Err("--froude-krylov applies to a section, not to an imported database".into());
    }
    if args.floats() {
        return Err(format!(
            "--rao, --mass, --cog, --gyradius and --mooring make a section float; {} is not \
             a section",
            "an imported database"
        ));
    }
    let (database, elapsed) = import(&args.sweep)?;
    body::write_tables(&database, args)?;
    crate::output::stderr_line(&summary(&database, &database.dof_names, elapsed));
    Ok(())
}

/// One line: what was imported, of the DOFs `dofs`.
fn summary(database: &Database, dofs: &[String], elapsed: Duration) -> String {
    format!(
        "{}: {} DOFs ({}), {} frequencies {:.4} .. {:.4} rad/s ({} left out), {} headings, {:.3} s",
        database.name,
        dofs.len(),
        dofs.join(" "),
        database.omega.len(),
        database.omega.first().copied().unwrap_or(f64::NAN),
        database.omega.last().copied().unwrap_or(f64::NAN),
        database.failures.len(),
        database.headings.len(),
        elapsed.as_secs_f64()
    )
}

/// Imports and fits (default band: every frequency of the file).
pub fn fit(args: &HullSweepArgs, options: &FitOptions) -> Result<FittedBody, String> {
    let (database, dofs, elapsed) = import_whole(args)?;
    let whole = all_frequencies(&database)
        .ok_or_else(|| format!("{}: its frequencies give no band", args.hull))?;
    let band = body::band_arg(options.band, whole)?;
    whole_body::band(
        band,
        database.reference_length,
        database.g,
        options.max_step,
    )
    .map_err(|e| e.to_string())?;
    for warning in &database.warnings {
        crate::output::stderr_line(&format!("warning: {warning}"));
    }
    let kept = dofs.clone().unwrap_or_else(|| database.dof_names.clone());
    let description = format!("database {}", summary(&database, &kept, elapsed));
    let scene = BodyScene {
        dofs,
        band,
        tolerance: options.tolerance,
        max_step: options.max_step,
        form: options.form,
        order: options.order,
        // ULEN for WAMIT files: the fit is then the same at any length scale.
        length_unit: Some(database.reference_length),
        description,
        acquisition_time: elapsed,
        ..BodyScene::new(database)
    };
    scene.fit().map_err(|e| format!("{}: {e}", args.hull))
}

/// `fmu-pack pack NAME.1`: one FMU for the body.
pub fn pack(args: &PackArgs) -> Result<PackSummary, PackError> {
    let fitted = fit(&args.sweep, &FitOptions::of_pack(args))?;
    body::pack(&fitted, args, None)
}
