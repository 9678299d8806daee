//! `fmu-pack fit`: identify the equivalent network of a hull and report it.

use crate::fit_report::{fit_plots, plots, text};
use crate::pipeline::{self, Built};
use clap::Args;
use hydrofmu::hull::Hull;
use hydrofmu::network::NetworkForm;
use hydrofmu::scene::Scene;
use hydrofmu::source::Source;
use hydrofmu::sweep::SweepParams;
use std::path::PathBuf;

/// Arguments of `fmu-pack fit`.
#[derive(Args, Debug, Clone)]
pub struct FitArgs {
    /// The hull and the sweep settings.
    #[command(flatten)]
    pub sweep: crate::args::HullSweepArgs,
    /// Frequency band to fit: `MIN:MAX` in kR, or `MIN:MAXrad/s` (default: 0.05:5 in kR; an
    /// imported database: all its frequencies).
    #[arg(long, allow_hyphen_values = true)]
    pub band: Option<String>,
    /// Tolerance: largest error as a fraction of sqrt(|A_ii A_jj|) (default 0.01).
    #[arg(long = "tol")]
    pub tolerance: Option<f64>,
    /// Fixed order (auxiliary DOFs of a chain; for the coupled network, poles per invariant
    /// block, a complex pair counted twice).
    #[arg(long)]
    pub order: Option<usize>,
    /// Largest communication step the master will use, in s: the band is cut at its
    /// Nyquist frequency pi / max-step.
    #[arg(long, value_name = "SECONDS")]
    pub max_step: Option<f64>,
    /// Network form: series_chain, parallel_bank (one DOF), coupled (any number of DOFs;
    /// the only form for several DOFs of a ship file or an imported database).
    #[arg(long)]
    pub form: Option<String>,
    /// Write the network file (XML) here.
    #[arg(long, value_name = "FILE")]
    pub network_out: Option<PathBuf>,
    /// Write one SVG plot of fit against data per matrix entry into this folder.
    #[arg(long, value_name = "DIR")]
    pub plots: Option<PathBuf>,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Parses a network form name.
pub fn parse_form(name: &str) -> Result<NetworkForm, String> {
    NetworkForm::from_name(name)
        .ok_or_else(|| format!("--form '{name}': expected series_chain, parallel_bank or coupled"))
}

/// The scene of `fmu-pack fit`: every DOF of `hull` (the `--dofs` of the hull argument
/// already applied), with the band and fit options as the command line gives them.
pub fn scene(
    hull: Hull,
    sweep: SweepParams,
    band: &str,
    tolerance: Option<f64>,
    order: Option<usize>,
    form: Option<&str>,
    max_step: Option<f64>,
) -> Result<Scene, String> {
    Ok(Scene {
        band: pipeline::parse_band(band)?,
        tolerance,
        order,
        form: form.map(parse_form).transpose()?,
        max_step,
        sweep,
        ..Scene::new(hull)
    })
}

/// The band of a section's fit when `--band` is not given (kR).
const DEFAULT_BAND: &str = "0.05:5";

/// Runs the sweep and the fit, and reports.
pub fn run(args: &FitArgs) -> Result<(), String> {
    let whole_body = match Source::from_argument(&args.sweep.hull) {
        Ok(Source::ShipFile(_)) => Some(false),
        Ok(source) if source.is_import() => Some(true),
        _ => None,
    };
    if let Some(imported) = whole_body {
        return run_whole_body(args, imported);
    }
    let (hull, sweep_params) = args.sweep.resolve()?;
    let scene = scene(
        hull,
        sweep_params,
        args.band.as_deref().unwrap_or(DEFAULT_BAND),
        args.tolerance,
        args.order,
        args.form.as_deref(),
        args.max_step,
    )?;
    let built = pipeline::build_network(scene)?;
    let mut outputs = crate::output::Outputs::new();
    if let Some(path) = &args.network_out {
        outputs.bytes(path, built.fit.network.to_xml_string().as_bytes())?;
    }
    if let Some(dir) = &args.plots {
        stage_figures(&mut outputs, plots(&built), dir)?;
    }
    outputs.commit()?;
    let report = if args.json {
        format!("{}\n", json(&built))
    } else {
        text(&built)
    };
    crate::output::stdout(report.as_bytes())
}

/// A ship file's or an imported database's fit (`imported`), reported: the fit in words
/// and the scene report, or JSON.
fn run_whole_body(args: &FitArgs, imported: bool) -> Result<(), String> {
    let options = crate::body::FitOptions {
        band: args.band.as_deref(),
        tolerance: args.tolerance,
        order: args.order,
        max_step: args.max_step,
        form: args.form.as_deref().map(parse_form).transpose()?,
    };
    let fitted = if imported {
        crate::database_cmd::fit(&args.sweep, &options)
    } else {
        crate::ship_cmd::fit(&args.sweep, &options)
    }?;
    // The network and the figures together, or none (output::Outputs).
    let mut outputs = crate::output::Outputs::new();
    if let Some(path) = &args.network_out {
        outputs.bytes(path, fitted.fit.network.to_xml_string().as_bytes())?;
    }
    if let Some(dir) = &args.plots {
        let source = if imported { "database" } else { "strip theory" };
        let figures = fit_plots(
            &fitted.database.response(),
            &fitted.fit,
            source,
            ("omega (rad/s)", &|omega| omega),
            (&fitted.database.dof_units, hydrofmu::fmu::Extent::WholeBody),
        );
        stage_figures(&mut outputs, figures, dir)?;
    }
    outputs.commit()?;
    let text = if args.json {
        json_report(
            &fitted.fit,
            &fitted.database.dof_names,
            fitted.times.0.as_secs_f64(),
            fitted.times.1.as_secs_f64(),
            &fitted.database.notes,
        )
    } else {
        format!("{}\n\n{}", fitted.fit_text(), fitted.report)
    };
    crate::output::stdout(format!("{text}\n").as_bytes())
}

/// The report as JSON.
pub fn json(built: &Built) -> String {
    json_report(
        &built.fit,
        &built.response.fitted.dof_names,
        built.sweep_time.as_secs_f64(),
        built.fit_time.as_secs_f64(),
        &[],
    )
}

/// A fit as JSON: `names` its DOFs, the sweep's (or import's) and the fit's seconds, and
/// notes of the data beside the fit's own (`notes` lists both, the fit's first).
pub fn json_report(
    fit: &hydrofmu::FitReport,
    names: &[String],
    sweep_seconds: f64,
    fit_seconds: f64,
    data_notes: &[String],
) -> String {
    let matrix = |m: &nalgebra::DMatrix<f64>| {
        let rows: Vec<String> = (0..m.nrows())
            .map(|i| {
                let row: Vec<String> = (0..m.ncols()).map(|j| number(m[(i, j)])).collect();
                format!("[{}]", row.join(","))
            })
            .collect();
        format!("[{}]", rows.join(","))
    };
    let branches: Vec<String> = fit
        .network
        .branches
        .iter()
        .map(|b| {
            let direction: Vec<String> = b.direction.iter().map(|d| number(*d)).collect();
            let stages: Vec<String> = b
                .stages
                .iter()
                .map(|s| {
                    format!(
                        "{{\"mass\":{},\"stiffness\":{},\"damping\":{}}}",
                        number(s.mass),
                        number(s.stiffness),
                        number(s.damping)
                    )
                })
                .collect();
            format!(
                "{{\"direction\":[{}],\"stages\":[{}]}}",
                direction.join(","),
                stages.join(",")
            )
        })
        .collect();
    let substructures: Vec<String> = fit
        .network
        .substructures
        .iter()
        .map(|sub| {
            format!(
                "{{\"springs\":{},\"masses\":{},\"spring_incidence\":{},\
                 \"spring_relaxation\":{},\"damping\":{}}}",
                sub.spring_count(),
                sub.masses,
                matrix(&sub.spring_incidence),
                matrix(&sub.spring_relaxation),
                matrix(&sub.damping)
            )
        })
        .collect();
    let dofs: Vec<String> = names.iter().map(|n| json_string(n)).collect();
    // The exact check (hydrofmu::passivity) of the network as the FMU will step it.
    let passive = fit
        .network
        .state_space()
        .map(|ss| hydrofmu::passivity::check(&ss, 1e-9).passive)
        .unwrap_or(false);
    let notes: Vec<String> = fit
        .notes
        .iter()
        .chain(data_notes)
        .map(|n| json_string(n))
        .collect();
    format!(
        "{{\"dofs\":[{}],\"form\":\"{}\",\"order\":{},\"aux_dofs\":{},\"band_rad_per_s\":[{},{}],\
         \"points\":{},\"tolerance\":{},\"tolerance_met\":{},\"max_relative_error\":{},\
         \"max_error\":{},\"rms_error\":{},\"error_scale\":{},\"added_mass_inf\":{},\
         \"rho\":{},\"g\":{},\"branches\":[{}],\"substructures\":[{}],\"states\":{},\"sweep_seconds\":{},\"fit_seconds\":{},\"iterations\":{},\"passive\":{},\"notes\":[{}]}}",
        dofs.join(","),
        fit.network.form,
        fit.order,
        fit.aux_dofs,
        number(fit.band.0),
        number(fit.band.1),
        fit.points,
        number(fit.tolerance),
        fit.tolerance_met,
        number(fit.max_relative_error),
        matrix(&fit.max_error),
        matrix(&fit.rms_error),
        matrix(&fit.error_scale),
        matrix(&fit.network.added_mass_inf),
        number(fit.network.rho),
        number(fit.network.g),
        branches.join(","),
        substructures.join(","),
        fit.states,
        number(sweep_seconds),
        number(fit_seconds),
        fit.iterations,
        passive,
        notes.join(",")
    )
}

/// A JSON string literal (quotes, backslashes and control characters escaped).
fn json_string(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn number(x: f64) -> String {
    if x.is_finite() {
        hydrofmu::xml::format_number(x, hydrofmu::xml::Notation::Scientific)
    } else {
        "null".into()
    }
}

/// Stages `(file name, SVG)` pairs in `dir` (created).
fn stage_figures(
    outputs: &mut crate::output::Outputs,
    figures: Vec<(String, String)>,
    dir: &std::path::Path,
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    figures
        .iter()
        .try_for_each(|(name, svg)| outputs.bytes(&dir.join(name), svg.as_bytes()))
}
