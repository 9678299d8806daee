//! `fmu-pack sweep SHIP.xml`: the whole-ship tables of a ship file by strip theory
//! (docs/SHIPS.md).

use crate::args::PackArgs;
use crate::args::{parse_grid, HullSweepArgs, SweepArgs};
use crate::body::{self, FitOptions};
use crate::output;
use crate::packing::{PackError, PackSummary};
use crate::progress::Progress;
use hydrofmu::bem::IrregularFrequencies;
use hydrofmu::database::Database;
use hydrofmu::fmu::description::{DEFAULT_G, DEFAULT_RHO};
use hydrofmu::scene::{whole_body, Band, BodyScene, FittedBody};
use hydrofmu::ship::{self, Ship, ShipSweepParams};
use std::path::Path;
use std::time::{Duration, Instant};

/// Comma-separated headings in degrees.
fn parse_headings(text: &str) -> Result<Vec<f64>, String> {
    text.split(',')
        .map(|word| {
            hydrofmu::xml::parse_number(word.trim())
                .map_err(|m| format!("--headings: '{word}': {m}"))
        })
        .collect()
}

/// The ship of a ship-file argument and its sweep parameters from the shared options.
fn resolve(args: &HullSweepArgs) -> Result<(Ship, ShipSweepParams), String> {
    if args.depth.is_some() {
        return Err("--depth applies to a built-in circle, not to a ship file".to_string());
    }
    args.refuse_import_options()?;
    let ship = Ship::from_file(Path::new(&args.hull)).map_err(|e| e.to_string())?;
    let mut params = ShipSweepParams::for_ship(&ship);
    if let Some(omega) = &args.omega {
        params.omega = parse_grid(omega).map_err(|m| format!("--omega: {m}"))?;
    }
    if let Some(headings) = &args.headings {
        params.headings = parse_headings(headings)?;
    }
    if let Some(panels) = args.panels {
        params.panels.body_panels = panels;
        params.panels_with_corners.body_panels = panels;
    }
    if let Some(levels) = args.levels {
        params.extrapolation_levels = levels;
        params.levels_with_corners = levels;
    }
    if let Some(metres) = args.water_depth {
        // The command line overrides the file's `depth`.
        params.depth = hydrofmu::units::WaterDepth::new(metres)
            .map_err(|e| format!("--water-depth {metres}: {e} (`inf` for deep water)"))?;
    }
    params.threads = args.threads;
    if args.plain {
        params.irregular_frequencies = IrregularFrequencies::Keep;
    }
    // The FMU rescales to the rho and g a master sets; the data is at the reference ones.
    params.rho = DEFAULT_RHO;
    params.g = DEFAULT_G;
    Ok((ship, params))
}

/// The `--dofs` of `args`, checked against the ship's DOFs (before its sweep).
fn requested_dofs(ship: &Ship, args: &HullSweepArgs) -> Result<Option<Vec<String>>, String> {
    let Some(names) = body::dofs_arg(args.dofs.as_deref()) else {
        return Ok(None);
    };
    let list: Vec<&str> = names.iter().map(String::as_str).collect();
    let available: Vec<String> = ship.dof_names().iter().map(|d| d.to_string()).collect();
    whole_body::dofs(&list, &format!("ship '{}'", ship.name()), &available)
        .map_err(|e| e.to_string())?;
    Ok(Some(names))
}

/// The ship's sweep of every DOF with a progress bar.
fn sweep(
    ship: &Ship,
    params: &ShipSweepParams,
    args: &HullSweepArgs,
) -> Result<(Database, Duration), String> {
    let progress = Progress::new("ship sweep");
    let start = Instant::now();
    let result = ship::strip::run(ship, params, &|done, total| progress.update(done, total))
        .map_err(|e| format!("{}: {e}", args.hull))?;
    Ok((result, start.elapsed()))
}

/// `database` restricted to `dofs` when given.
fn selected(database: Database, dofs: Option<&[String]>) -> Result<Database, String> {
    let Some(names) = dofs else {
        return Ok(database);
    };
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    database
        .select_dofs(&names)
        .ok_or_else(|| format!("--dofs: not all of {} were swept", names.join(" ")))
}

/// The computed girder modes' dry properties, one line each (empty without `<girder_modes>`):
/// what the master's structural model of these modes needs.
pub fn girder_text(ship: &Ship, dofs: &[String]) -> String {
    ship.girder_modes()
        .iter()
        .filter(|(name, _)| dofs.contains(name))
        .map(|(name, mode)| {
            format!(
                "girder mode {name}: dry natural frequency {:.4} rad/s, modal mass {:.6e}, modal \
                 stiffness {:.6e} (per unit amplitude squared; unit amplitude = 1 m or 1 rad \
                 at the largest station)\n",
                mode.natural_frequency, mode.modal_mass, mode.modal_stiffness
            )
        })
        .collect()
}

/// Runs the ship's sweep and writes its tables.
pub fn run(args: &SweepArgs) -> Result<(), String> {
    if args.froude_krylov.is_some() {
        return Err("--froude-krylov applies to a section, not to a ship file".to_string());
    }
    if args.floats() {
        return Err(format!(
            "--rao, --mass, --cog, --gyradius and --mooring make a section float; {} is not \
             a section",
            "a ship"
        ));
    }
    let (ship, mut params) = resolve(&args.sweep)?;
    // The fixed ship's mean drift by strip theory (docs/SHIPS.md) only when a table asks.
    params.drift = args.drift.is_some();
    let dofs = requested_dofs(&ship, &args.sweep)?;
    let (result, elapsed) = sweep(&ship, &params, &args.sweep)?;
    let result = selected(result, dofs.as_deref())?;
    body::write_tables(&result, args)?;
    for line in girder_text(&ship, &result.dof_names).lines() {
        output::stderr_line(line);
    }
    output::stderr_line(&format!(
        "{}: {} stations, {} distinct sections ({} body panels each at most), {} DOFs, {} \
         frequencies ({} failed), {} headings, {:.3} s wall",
        result.name,
        ship.stations().len(),
        ship.sections().len(),
        result.body_panels.iter().max().copied().unwrap_or(0),
        result.dof_names.len(),
        result.omega.len(),
        result.failures.len(),
        result.headings.len(),
        elapsed.as_secs_f64()
    ));
    Ok(())
}

/// Sweeps and fits a ship (the band as `--band` gives it, kR with R the largest section
/// half-beam, or rad/s; default [`Band::default`]). The band, tolerance, DOFs and form are
/// checked before the sweep.
pub fn fit(args: &HullSweepArgs, options: &FitOptions) -> Result<FittedBody, String> {
    fit_with_drift(args, options, false)
}

/// [`fit`], with the fixed ship's mean drift in the database when `drift`.
fn fit_with_drift(
    args: &HullSweepArgs,
    options: &FitOptions,
    drift: bool,
) -> Result<FittedBody, String> {
    let (ship, mut params) = resolve(args)?;
    params.drift = drift;
    let radius = ship
        .sections()
        .iter()
        .map(|h| h.reference_half_beam())
        .fold(0.0, f64::max);
    let band = body::band_arg(options.band, Band::default())?;
    whole_body::band(band, radius, DEFAULT_G, options.max_step).map_err(|e| e.to_string())?;
    whole_body::tolerance(options.tolerance).map_err(|e| e.to_string())?;
    let dofs = requested_dofs(&ship, args)?;
    let count = dofs.as_ref().map_or(ship.dof_names().len(), Vec::len);
    whole_body::form(options.form, count).map_err(|e| e.to_string())?;
    let (swept, sweep_time) = sweep(&ship, &params, args)?;
    for warning in &swept.warnings {
        output::stderr_line(&format!("warning: {warning}"));
    }
    let kept = dofs.clone().unwrap_or_else(|| swept.dof_names.clone());
    let scene = BodyScene {
        dofs,
        band,
        band_length: radius,
        g: DEFAULT_G,
        tolerance: options.tolerance,
        max_step: options.max_step,
        form: options.form,
        order: options.order,
        description: format!(
            "ship {}: {} stations, {} distinct sections",
            ship.name(),
            ship.stations().len(),
            ship.sections().len()
        ),
        appendix: girder_text(&ship, &kept),
        acquisition_time: sweep_time,
        ..BodyScene::new(swept)
    };
    scene.fit().map_err(|e| format!("{}: {e}", args.hull))
}

/// `fmu-pack pack SHIP.xml`: one FMU for the whole ship.
pub fn pack(args: &PackArgs) -> Result<PackSummary, PackError> {
    if args.network.is_some() {
        return Err(PackError(
            "--network applies to a section; a ship's network is fitted to its sweep".into(),
        ));
    }
    // The viscous estimate before a sweep that may take minutes.
    let estimate = match args.viscous.viscous && !args.viscous.no_estimate {
        true => Some(crate::viscous_args::ship_estimate(
            &args.viscous,
            &resolve(&args.sweep)?.0,
        )?),
        false => None,
    };
    let fitted = fit_with_drift(&args.sweep, &FitOptions::of_pack(args), args.drift)?;
    body::pack(&fitted, args, estimate)
}
