//! `fmu-pack sweep SHIP.xml`: the whole-ship tables of a ship file by strip theory
//! (docs/SHIPS.md).

use crate::output;
use crate::pack::{locate_binary, pack_network, PackArgs, PackError, PackSummary, PackedNetwork};
use crate::pipeline::{self, HullInfo};
use crate::progress::Progress;
use crate::sweep_cmd::{parse_grid, HullSweepArgs, SweepArgs};
use hydrofmu::bem::IrregularFrequencies;
use hydrofmu::fmu::description::{DEFAULT_G, DEFAULT_RHO};
use hydrofmu::fmu::Extent;
use hydrofmu::identify::{self, FitParams, FitReport};
use hydrofmu::scene::Band;
use hydrofmu::database::Database;
use hydrofmu::ship::{self, Ship, ShipSweepParams};
use hydrofmu::xml::{format_number, Notation};
use std::path::Path;
use std::time::{Duration, Instant};

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

/// The ship of a ship-file argument and its sweep parameters from the shared options.
fn resolve(args: &HullSweepArgs) -> Result<(Ship, ShipSweepParams), String> {
    if args.depth.is_some() {
        return Err("--depth applies to a built-in circle, not to a ship file".to_string());
    }
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
    params.threads = args.threads;
    if args.plain {
        params.irregular_frequencies = IrregularFrequencies::Keep;
    }
    // The FMU rescales to the rho and g a master sets; the data is at the reference ones.
    params.rho = DEFAULT_RHO;
    params.g = DEFAULT_G;
    Ok((ship, params))
}

/// The ship's sweep with a progress bar, restricted to the `--dofs` of `args` when given (the
/// sections are solved whole either way).
fn sweep(
    ship: &Ship,
    params: &ShipSweepParams,
    args: &HullSweepArgs,
) -> Result<(Database, Duration), String> {
    let names: Option<Vec<&str>> = args
        .dofs
        .as_deref()
        .map(|list| list.split(',').map(str::trim).collect());
    if let Some(names) = &names {
        let available = ship.dof_names();
        for (k, name) in names.iter().enumerate() {
            if !available.contains(name) || names[..k].contains(name) {
                return Err(format!(
                    "--dofs: '{name}' is not a DOF of ship '{}' or is named twice; its DOFs: {}",
                    ship.name(),
                    available.join(" ")
                ));
            }
        }
    }
    let progress = Progress::new("ship sweep");
    let start = Instant::now();
    let mut result = ship::strip::run(ship, params, &|done, total| progress.update(done, total))
        .map_err(|e| format!("{}: {e}", args.hull))?;
    if let Some(names) = &names {
        result = result
            .select_dofs(names)
            .ok_or_else(|| format!("--dofs: not all of {} were swept", names.join(" ")))?;
    }
    Ok((result, start.elapsed()))
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
    let (ship, params) = resolve(&args.sweep)?;
    let (result, elapsed) = sweep(&ship, &params, &args.sweep)?;
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
    for line in girder_text(&ship, &result.dof_names).lines() {
        output::stderr_line(line);
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

/// A ship's fit: the band in rad/s (after the `--max-step` cut), then the identification of
/// every DOF's radiation force at once.
pub struct ShipFit {
    /// The ship.
    pub ship: Ship,
    /// Its sweep (SI, at the reference rho and g).
    pub sweep: Database,
    /// The band fitted, rad/s.
    pub band: (f64, f64),
    /// The fit.
    pub fit: FitReport,
    /// Wall times of the sweep and the fit.
    pub times: (Duration, Duration),
}

/// Sweeps and fits a ship (the band as `--band` gives it, kR with R the largest section
/// half-beam, or rad/s).
pub fn fit(
    args: &HullSweepArgs,
    band: Option<&str>,
    tolerance: Option<f64>,
    order: Option<usize>,
    max_step: Option<f64>,
) -> Result<ShipFit, String> {
    let (ship, params) = resolve(args)?;
    let band = match band {
        Some(text) => pipeline::parse_band(text)?,
        None => Band::default(),
    };
    if let Some(t) = tolerance {
        if !(t.is_finite() && t > 0.0) {
            return Err(format!("--tol {t}: the tolerance must be finite and > 0"));
        }
    }
    let radius = ship
        .sections()
        .iter()
        .map(|h| h.reference_half_beam())
        .fold(0.0, f64::max);
    let (lo, mut hi) = band.to_rad_per_second(radius, DEFAULT_G);
    if let Some(h) = max_step {
        if !(h.is_finite() && h > 0.0) {
            return Err(format!("--max-step {h}: the step must be finite and > 0 s"));
        }
        let nyquist = std::f64::consts::PI / h;
        if nyquist <= lo * 1.5 {
            return Err(format!(
                "--max-step {h}: its Nyquist frequency pi/h = {nyquist:.4} rad/s leaves nothing \
                 of the band {lo:.4} .. {hi:.4} rad/s"
            ));
        }
        hi = hi.min(nyquist);
    }
    let (swept, sweep_time) = sweep(&ship, &params, args)?;
    for warning in &swept.warnings {
        output::stderr_line(&format!("warning: {warning}"));
    }
    let inside = swept
        .omega
        .iter()
        .filter(|w| **w >= lo && **w <= hi)
        .count();
    if inside < 3 {
        return Err(format!(
            "the band {lo:.4} .. {hi:.4} rad/s holds {inside} of the sweep's frequencies; at \
             least 3 are needed (--omega, --band)"
        ));
    }
    let start = Instant::now();
    let report = identify::fit(
        &swept.response(),
        &FitParams {
            band: (lo, hi),
            tolerance,
            order,
            ..FitParams::default()
        },
    )
    .map_err(|e| format!("{}: the fit failed: {e}", args.hull))?;
    Ok(ShipFit {
        ship,
        sweep: swept,
        band: (lo, hi),
        fit: report,
        times: (sweep_time, start.elapsed()),
    })
}

/// The fit in words, for the terminal and the archive's documentation.
pub fn fit_text(f: &ShipFit) -> String {
    let fit = &f.fit;
    let girder = girder_text(&f.ship, &f.sweep.dof_names);
    format!(
        "ship {}: {} stations, {} distinct sections, DOFs {}\n\
         band {:.4} .. {:.4} rad/s ({} of {} frequencies)\n\
         network: {}, order {}, {} states\n\
         largest error {:.3} % of sqrt(|A_ii A_jj|) (tolerance {:.2} %, {})\n\
         sweep {:.2} s, fit {:.2} s{}{}",
        f.ship.name(),
        f.ship.stations().len(),
        f.ship.sections().len(),
        f.sweep.dof_names.join(" "),
        f.band.0,
        f.band.1,
        f.sweep
            .omega
            .iter()
            .filter(|w| **w >= f.band.0 && **w <= f.band.1)
            .count(),
        f.sweep.omega.len(),
        fit.network.form,
        fit.order,
        fit.states,
        100.0 * fit.max_relative_error,
        100.0 * fit.tolerance,
        if fit.tolerance_met { "met" } else { "NOT met" },
        f.times.0.as_secs_f64(),
        f.times.1.as_secs_f64(),
        if girder.is_empty() { "" } else { "\n" },
        girder.trim_end()
    )
}

/// `fmu-pack pack SHIP.xml`: one FMU for the whole ship.
pub fn pack(args: &PackArgs) -> Result<PackSummary, PackError> {
    if args.network.is_some() {
        return Err(PackError(
            "--network applies to a section; a ship's network is fitted to its sweep".into(),
        ));
    }
    let fitted = fit(
        &args.sweep,
        args.band.as_deref(),
        args.tol,
        args.order,
        args.max_step,
    )?;
    let text = fit_text(&fitted);
    if !fitted.fit.tolerance_met && !args.allow_tolerance_miss {
        return Err(PackError(format!(
            "the fit misses the tolerance; no archive written. Try another --order or a \
             narrower --band, raise --tol, or pass --allow-tolerance-miss to pack it anyway\n{text}"
        )));
    }
    let mut excitation = Vec::new();
    fitted
        .sweep
        .write_excitation_table(&mut excitation)
        .map_err(|e| format!("cannot format the excitation table: {e}"))?;
    let mut name = fitted.ship.name().to_string();
    if let Some(first) = name.get_mut(0..1) {
        first.make_ascii_uppercase();
    }
    let body = HullInfo {
        name,
        dofs: fitted
            .ship
            .dof_units()
            .into_iter()
            .filter(|u| fitted.sweep.dof_names.contains(&u.name))
            .collect(),
        xml: None,
        extent: Extent::WholeBody,
        hydrostatics_csv: Some(
            fitted
                .sweep
                .hydrostatics_table()
                .to_csv(fitted.ship.name(), "whole ship"),
        ),
        excitation_csv: Some(String::from_utf8_lossy(&excitation).into_owned()),
        report: Some(text.clone()),
    };
    let binary = locate_binary(args.binary.as_deref())?;
    let identifier = match &args.model_identifier {
        Some(id) => id.clone(),
        None => crate::pack::identifier_from_path(&args.output),
    };
    let network = PackedNetwork::from_network(fitted.fit.network.clone());
    let mut summary = pack_network(
        &body,
        &network,
        args.keep_inf_mass,
        &binary,
        &identifier,
        &args.output,
        None,
    )?;
    summary.fit = Some(text.replace('\n', "; "));
    Ok(summary)
}
