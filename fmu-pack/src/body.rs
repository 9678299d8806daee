//! The whole-body commands shared by ship files (strip theory, docs/SHIPS.md) and imported 3D
//! databases (docs/DATABASES.md): the tables of a [`Database`], its fit and its archive.

use crate::args::{PackArgs, SweepArgs};
use crate::output;
use crate::packing::{locate_binary, pack_network, PackError, PackSummary, PackedNetwork};
use crate::pipeline;
use hydrofmu::database::wamit::WamitFiles;
use hydrofmu::database::Database;
use hydrofmu::fmu::Body;
use hydrofmu::identify::{self, FitParams, FitReport};
use hydrofmu::scene::{whole_body, Band};
use hydrofmu::xml::{format_number, Notation};
use std::time::{Duration, Instant};

/// Writes the database's tables as `fmu-pack sweep` does (all together, or none:
/// [`output::Outputs`]), and its warnings, notes and left-out frequencies to standard error.
pub fn write_tables(database: &Database, args: &SweepArgs) -> Result<(), String> {
    if args.excitation.is_some() && database.excitation.is_empty() {
        return Err(format!(
            "--excitation: {} has no exciting force",
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

/// Stages `PREFIX.1`, `PREFIX.3` (when there is an exciting force) and `PREFIX.hst`.
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

/// A whole body's fit.
pub struct BodyFit {
    /// The database (SI, at the reference rho and g).
    pub database: Database,
    /// What the body is, in a line or more (first lines of the report).
    pub description: String,
    /// Lines appended to the report (e.g. a ship's girder modes' dry properties).
    pub appendix: String,
    /// The band fitted, rad/s.
    pub band: (f64, f64),
    /// The fit.
    pub fit: FitReport,
    /// Wall times of the sweep (or import) and the fit.
    pub times: (Duration, Duration),
}

/// The band to fit in rad/s: `band` as given (kR with R = `reference_length`, or rad/s), or
/// `default`; cut at the Nyquist frequency of `max_step`.
pub fn band(
    band: Option<&str>,
    default: Band,
    reference_length: f64,
    g: f64,
    max_step: Option<f64>,
) -> Result<(f64, f64), String> {
    let band = match band {
        Some(text) => pipeline::parse_band(text)?,
        None => default,
    };
    whole_body::band(band, reference_length, g, max_step).map_err(|e| e.0)
}

/// Fits every DOF's radiation force of `database` at once over `band` (rad/s); with
/// `length_unit` L, in DOF coordinates where a rotation counts L times its angle, so that the
/// fit does not depend on the unit of length ([`identify::fit_in_dof_units`]).
#[allow(clippy::too_many_arguments)]
pub fn fit(
    database: Database,
    description: String,
    appendix: String,
    band: (f64, f64),
    tolerance: Option<f64>,
    order: Option<usize>,
    sweep_time: Duration,
    length_unit: Option<f64>,
) -> Result<BodyFit, String> {
    whole_body::tolerance(tolerance).map_err(|e| e.0)?;
    let (lo, hi) = band;
    whole_body::frequencies_in_band(&database, band).map_err(|e| e.0)?;
    let start = Instant::now();
    let params = FitParams {
        band: (lo, hi),
        tolerance,
        order,
        noise: Some(database.noise.clone()),
        ..FitParams::default()
    };
    let report = match length_unit {
        Some(unit) => {
            let factors: Vec<f64> = database
                .dof_units
                .iter()
                .map(|d| unit.powi(i32::from(d.length_exponent)))
                .collect();
            identify::fit_in_dof_units(&database.response(), &params, &factors)
        }
        None => identify::fit(&database.response(), &params),
    }
    .map_err(|e| format!("{}: the fit failed: {e}", database.name))?;
    Ok(BodyFit {
        database,
        description,
        appendix,
        band,
        fit: report,
        times: (sweep_time, start.elapsed()),
    })
}

/// The fit in words, for the terminal and the archive's documentation.
pub fn fit_text(f: &BodyFit) -> String {
    let fit = &f.fit;
    let db = &f.database;
    let mut text = format!(
        "{}\nDOFs {}\nband {:.4} .. {:.4} rad/s ({} of {} frequencies)\n\
         network: {}, order {}, {} states\n\
         largest error {:.3} % of sqrt(|A_ii A_jj|) (tolerance {:.2} %, {})\n\
         {} {:.2} s, fit {:.2} s",
        f.description,
        db.dof_names.join(" "),
        f.band.0,
        f.band.1,
        db.omega
            .iter()
            .filter(|w| **w >= f.band.0 && **w <= f.band.1)
            .count(),
        db.omega.len(),
        fit.network.form,
        fit.order,
        fit.states,
        100.0 * fit.max_relative_error,
        100.0 * fit.tolerance,
        if fit.tolerance_met { "met" } else { "NOT met" },
        if db.body_panels.is_empty() {
            "import"
        } else {
            "sweep"
        },
        f.times.0.as_secs_f64(),
        f.times.1.as_secs_f64(),
    );
    for note in fit.notes.iter().chain(&db.notes) {
        text.push_str(&format!("\nnote: {note}"));
    }
    for (omega, reason) in &db.failures {
        text.push_str(&format!(
            "\nleft out: omega = {} rad/s: {reason}",
            format_number(*omega, Notation::Plain)
        ));
    }
    if !f.appendix.is_empty() {
        text.push('\n');
        text.push_str(f.appendix.trim_end());
    }
    text
}

/// Packs a whole body's fit into one FMU.
pub fn pack(fitted: &BodyFit, args: &PackArgs) -> Result<PackSummary, PackError> {
    if args.network.is_some() {
        return Err(PackError(
            "--network applies to a section; a whole body's network is fitted to its data".into(),
        ));
    }
    let text = fit_text(fitted);
    if !fitted.fit.tolerance_met && !args.allow_tolerance_miss {
        return Err(PackError(format!(
            "the fit misses the tolerance; no archive written. Try another --order or a \
             narrower --band, raise --tol, or pass --allow-tolerance-miss to pack it anyway\n{text}"
        )));
    }
    let body = Body::whole(&fitted.database, Some(text.clone()))?;
    let binary = locate_binary(args.binary.as_deref())?;
    let identifier = match &args.model_identifier {
        Some(id) => id.clone(),
        None => crate::packing::identifier_from_path(&args.output),
    };
    let network = PackedNetwork::from_network(fitted.fit.network.clone());
    let target = crate::packing::Target {
        binary: &binary,
        model_identifier: &identifier,
        output: &args.output,
        fmi: args.fmi,
    };
    let mut summary = pack_network(body, network, args.keep_inf_mass, &target, None)?;
    summary.fit = Some(text.replace('\n', "; "));
    Ok(summary)
}
