//! `fmu-pack sweep SHIP.xml`: the whole-ship tables of a ship file by strip theory
//! (docs/SHIPS.md).

use crate::output;
use crate::progress::Progress;
use crate::sweep_cmd::{parse_grid, SweepArgs};
use hydrofmu::bem::IrregularFrequencies;
use hydrofmu::ship::{self, Ship, ShipSweepParams};
use hydrofmu::xml::{format_number, Notation};
use std::path::Path;
use std::time::Instant;

/// True when `argument` names a file whose top-level element is `<ship>`.
pub fn is_ship_file(argument: &str) -> bool {
    let path = Path::new(argument);
    let small = std::fs::metadata(path)
        .is_ok_and(|m| m.is_file() && m.len() <= hydrofmu::xml::MAX_INPUT_BYTES as u64);
    small
        && std::fs::read_to_string(path)
            .ok()
            .and_then(|text| hydrofmu::xml::parse(&text).ok())
            .is_some_and(|root| root.name == "ship")
}

/// Comma-separated headings in degrees.
fn parse_headings(text: &str) -> Result<Vec<f64>, String> {
    text.split(',')
        .map(|word| {
            hydrofmu::xml::parse_number(word.trim())
                .map_err(|m| format!("--headings: '{word}': {m}"))
        })
        .collect()
}

/// Runs the ship's sweep and writes its tables.
pub fn run(args: &SweepArgs) -> Result<(), String> {
    let section_only = [
        ("--depth", args.sweep.depth.is_some()),
        ("--dofs", args.sweep.dofs.is_some()),
        ("--froude-krylov", args.froude_krylov.is_some()),
    ];
    if let Some((flag, _)) = section_only.iter().find(|(_, given)| *given) {
        return Err(format!("{flag} applies to a section, not to a ship file"));
    }
    let ship = Ship::from_file(Path::new(&args.sweep.hull)).map_err(|e| e.to_string())?;
    let mut params = ShipSweepParams::for_ship(&ship);
    if let Some(omega) = &args.omega {
        params.omega = parse_grid(omega).map_err(|m| format!("--omega: {m}"))?;
    }
    if let Some(headings) = &args.headings {
        params.headings = parse_headings(headings)?;
    }
    if let Some(panels) = args.sweep.panels {
        params.panels.body_panels = panels;
    }
    params.extrapolation_levels = args.sweep.levels;
    params.threads = args.sweep.threads;
    if args.sweep.plain {
        params.irregular_frequencies = IrregularFrequencies::Keep;
    }
    let progress = Progress::new("ship sweep");
    let start = Instant::now();
    let result = ship::strip::run(&ship, &params, &|done, total| progress.update(done, total))
        .map_err(|e| format!("{}: {e}", args.sweep.hull))?;
    let elapsed = start.elapsed();
    let mut text = Vec::new();
    result
        .write_csv(&mut text)
        .map_err(|e| format!("cannot format the table: {e}"))?;
    output::file(&args.output, &text)?;
    if let Some(path) = &args.excitation {
        let mut text = Vec::new();
        result
            .write_excitation_csv(&mut text)
            .map_err(|e| format!("cannot format the excitation table: {e}"))?;
        output::file(path, &text)?;
    }
    if let Some(path) = &args.hydrostatics {
        let mut text = Vec::new();
        result
            .write_hydrostatics_csv(&mut text)
            .map_err(|e| format!("cannot format the restoring table: {e}"))?;
        output::file(path, &text)?;
    }
    for warning in &result.warnings {
        output::stderr_line(&format!("warning: {warning}"));
    }
    for (omega, reason) in &result.failures {
        output::stderr_line(&format!(
            "warning: omega = {} rad/s failed and is left out: {reason}",
            format_number(*omega, Notation::Plain)
        ));
    }
    output::stderr_line(&format!(
        "{}: {} stations, {} distinct sections ({} body panels each at most), {} DOFs, {} \
         frequencies ({} failed), {} headings, {:.3} s wall",
        result.ship_name,
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
