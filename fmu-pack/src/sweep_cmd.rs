//! `fmu-pack sweep`: the coefficient table of a hull.

use crate::hull_arg;
use crate::output;
use crate::pipeline;
use crate::progress::Progress;
use clap::Args;
use hydrofmu::bem::IrregularFrequencies;
use hydrofmu::database::section::SectionDatabase;
use hydrofmu::hull::Hull;
use hydrofmu::panels::PanelParams;
use hydrofmu::scene::Scene;
use hydrofmu::source::Source;
use hydrofmu::sweep::{self, ExcitationPart, SweepParams};
use hydrofmu::xml::{format_number, Notation};
use std::path::PathBuf;
use std::time::Instant;

/// The hull and the sweep settings, shared by `fmu-pack sweep` and `fmu-pack fit`.
#[derive(Args, Debug, Clone)]
pub struct HullSweepArgs {
    /// The input, chosen by the file: `semicircle` or `circle` (built-in sections), a hull
    /// file (section XML, docs/HULL_FORMAT.md), a ship file (XML with a `<ship>` root, strip
    /// theory, docs/SHIPS.md), WAMIT files `NAME.1` (with `NAME.3` and `NAME.hst` beside) or a
    /// Capytaine NetCDF-3 dataset `NAME.nc` (imported 3D databases, docs/DATABASES.md).
    pub hull: String,
    /// Centre depth over radius H/R of the built-in circle (> 1; 0 gives the semicircle).
    #[arg(long = "depth", value_name = "H_OVER_R")]
    pub depth: Option<f64>,
    /// Radius R of the built-in hulls, in metres.
    #[arg(long, default_value_t = 1.0)]
    pub radius: f64,
    /// Panels on the wetted contour (default: 128, more for a submerged hull close to the
    /// surface; see docs/DESIGN-NOTES.md).
    #[arg(long)]
    pub panels: Option<usize>,
    /// Log-spaced grid of kR.
    #[arg(
        long,
        value_name = "MIN:MAX:COUNT",
        default_value = "0.01:10:201",
        allow_hyphen_values = true
    )]
    pub kr: String,
    /// Comma-separated DOFs to keep (default: all of the hull's).
    #[arg(long, value_name = "a,b,..")]
    pub dofs: Option<String>,
    /// The seed's plain source method: do not remove irregular frequencies.
    #[arg(long)]
    pub plain: bool,
    /// Discretization levels (N, N/2, N/4, ...) extrapolated to zero panel size; 1 gives the
    /// plain N-panel result. Default 3 (a ship's sections with corners: 2, docs/SHIPS.md).
    #[arg(long)]
    pub levels: Option<usize>,
    /// Worker threads (at most 1024).
    #[arg(long, default_value_t = default_threads())]
    pub threads: usize,
    /// Ship files only: log-spaced grid of wave frequencies omega in rad/s (default: 100
    /// points from kR = 0.01 to 5, R the largest section half-beam).
    #[arg(long, value_name = "MIN:MAX:COUNT", allow_hyphen_values = true)]
    pub omega: Option<String>,
    /// Ship files only: wave headings in degrees, comma-separated (0 following seas, 90 from
    /// starboard towards port, 180 head seas). Default 0,45,90,135,180.
    #[arg(long, value_name = "DEG,DEG,..", allow_hyphen_values = true)]
    pub headings: Option<String>,
    /// Imported WAMIT files only: the length scale ULEN of their nondimensional values, in
    /// metres (default 1, as Capytaine and BEMRosetta write them).
    #[arg(long, value_name = "METRES")]
    pub length_scale: Option<f64>,
    /// Imported WAMIT files only: what their first column holds: `period` (s, WAMIT's
    /// default), `omega` (rad/s) or `hz` (default: what `NAME.cfg` beside them declares with
    /// `IPEROUT`, else the period).
    #[arg(long, value_name = "period|omega|hz")]
    pub frequency_column: Option<String>,
    /// Imported files only: their exciting force is in exp(-i omega t) (older HAMS builds):
    /// conjugate it.
    #[arg(long)]
    pub conjugate: bool,
}

impl HullSweepArgs {
    /// Refuses the options of imported databases for a section or a ship.
    pub fn refuse_import_options(&self) -> Result<(), String> {
        let given = [
            ("--length-scale", self.length_scale.is_some()),
            ("--frequency-column", self.frequency_column.is_some()),
            ("--conjugate", self.conjugate),
        ];
        match given.iter().find(|(_, g)| *g) {
            Some((flag, _)) => Err(format!(
                "{flag} applies to an imported database (NAME.1), not to '{}'",
                self.hull
            )),
            None => Ok(()),
        }
    }
}

/// One worker thread per core, within [`sweep::MAX_THREADS`].
fn default_threads() -> usize {
    std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(sweep::MAX_THREADS)
}

impl HullSweepArgs {
    /// The hull and the sweep parameters.
    pub fn resolve(&self) -> Result<(Hull, SweepParams), String> {
        self.refuse_import_options()?;
        if self.omega.is_some() || self.headings.is_some() {
            return Err(
                "--omega and --headings apply to ship files (docs/SHIPS.md); a \
                        section's grid is --kr"
                    .to_string(),
            );
        }
        let hull = hull_arg::resolve(&self.hull, self.radius, self.depth, self.dofs.as_deref())?;
        let params = SweepParams {
            kr: parse_grid(&self.kr)?,
            panels: panel_params(&hull, self.panels),
            irregular_frequencies: if self.plain {
                IrregularFrequencies::Keep
            } else {
                IrregularFrequencies::RemoveWithLid
            },
            extrapolation_levels: self
                .levels
                .unwrap_or(SweepParams::default().extrapolation_levels),
            threads: self.threads,
            excitation: true,
        };
        Ok((hull, params))
    }
}

/// Arguments of `fmu-pack sweep`.
#[derive(Args, Debug, Clone)]
pub struct SweepArgs {
    /// The hull and the sweep settings.
    #[command(flatten)]
    pub sweep: HullSweepArgs,
    /// Output CSV file (`-` for standard output).
    #[arg(short = 'o', long = "output", value_name = "FILE.csv")]
    pub output: PathBuf,
    /// Also write the exciting force of regular waves from headings 0 and 180 (direct
    /// diffraction solve, checked by the Haskind relation), `kR,j,heading,re,im` with
    /// `X_j / (rho g a R^(1 + e_j))` (docs/WAVES.md).
    #[arg(long, value_name = "FILE.csv")]
    pub excitation: Option<PathBuf>,
    /// Also write the Froude-Krylov part of the exciting force alone, in the same format.
    #[arg(long = "froude-krylov", value_name = "FILE.csv")]
    pub froude_krylov: Option<PathBuf>,
    /// Also write the hydrostatic restoring `C / (rho g)` of the DOFs (docs/HYDROSTATICS.md),
    /// `i,j,value` in SI per unit length (a ship: `C` itself, whole-ship SI, `i,j,c`).
    #[arg(long, value_name = "FILE.csv")]
    pub hydrostatics: Option<PathBuf>,
    /// Also write the tables as WAMIT files PREFIX.1, PREFIX.3 (with an exciting force) and
    /// PREFIX.hst, ULEN = 1 m; a section's per unit length, as a 1 m slice in beam seas
    /// (docs/DATABASES.md, "Export").
    #[arg(long, value_name = "PREFIX")]
    pub wamit: Option<PathBuf>,
    /// Also write the tables as a Capytaine dataset in NetCDF-3; a section's per unit length
    /// (docs/DATABASES.md, "Export").
    #[arg(long, value_name = "FILE.nc")]
    pub netcdf: Option<PathBuf>,
}

/// The hydrostatic restoring table: header comments, then `i,j,value` with
/// `value = C_ij / (rho g)` (m, m^2, m^3 for `e_i + e_j = 0, 1, 2`).
pub fn hydrostatics_csv(hull: &Hull) -> Result<String, String> {
    let h = hydrofmu::hydrostatics::stiffness(hull).map_err(|e| e.to_string())?;
    let mut out = String::new();
    out.push_str(&format!("# hull: {}\n", hull.name()));
    out.push_str(&format!("# modes: {}\n", hull.dof_names().join(" ")));
    out.push_str(&format!(
        "# waterline breadth: {} m; submerged area: {} m2; centre of buoyancy: ({}, {}) m\n",
        h.waterline_breadth, h.submerged_area, h.centre_of_buoyancy[0], h.centre_of_buoyancy[1]
    ));
    out.push_str(
        "# values: C_ij / (rho g), per unit length; rigid DOFs: buoyancy part of the rigid \
         motion; elastic DOFs: pressure stiffness. The structural model adds the initial stress \
         of the pre-loaded shell and the weight's restoring -m g z_G (docs/HYDROSTATICS.md).\n",
    );
    out.push_str("i,j,value\n");
    let c = &h.stiffness_per_rho_g;
    for i in 0..c.nrows() {
        for j in 0..c.ncols() {
            // + 0.0: a zero entry prints as 0, not -0.
            out.push_str(&format!("{},{},{:e}\n", i + 1, j + 1, c[(i, j)] + 0.0));
        }
    }
    Ok(out)
}

/// Parses `MIN:MAX:COUNT`.
pub fn parse_grid(text: &str) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let [min, max, count] = parts.as_slice() else {
        return Err(format!("--kr '{text}': expected MIN:MAX:COUNT"));
    };
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .map_err(|_| format!("--kr '{text}': '{s}' is not a number"))
    };
    let count = count
        .trim()
        .parse::<usize>()
        .map_err(|_| format!("--kr '{text}': COUNT '{count}' is not a positive integer"))?;
    sweep::log_grid(number(min)?, number(max)?, count).map_err(|e| pipeline::sweep_message(&e))
}

/// The panel parameters for `hull`: the automatic default, or the count given.
pub fn panel_params(hull: &Hull, panels: Option<usize>) -> PanelParams {
    let automatic = PanelParams::for_hull(hull);
    PanelParams {
        body_panels: panels.unwrap_or(automatic.body_panels),
        ..automatic
    }
}

/// Runs the sweep and writes the CSV.
pub fn run(args: &SweepArgs) -> Result<(), String> {
    // Every output's folder, before a sweep that may take minutes.
    let wamit = args.wamit.as_ref().map(|prefix| {
        let mut name = prefix.as_os_str().to_owned();
        name.push(".1");
        PathBuf::from(name)
    });
    for path in [
        Some(&args.output),
        args.excitation.as_ref(),
        args.froude_krylov.as_ref(),
        args.hydrostatics.as_ref(),
        wamit.as_ref(),
        args.netcdf.as_ref(),
    ]
    .into_iter()
    .flatten()
    {
        output::check_folder(path)?;
    }
    match Source::from_argument(&args.sweep.hull) {
        Ok(Source::ShipFile(_)) => return crate::ship_cmd::run(args),
        Ok(source) if source.is_import() => return crate::database_cmd::run(args),
        // A section, or an argument that names nothing: the section's resolve says why.
        _ => {}
    }
    let (hull, mut params) = args.sweep.resolve()?;
    let exports = args.wamit.is_some() || args.netcdf.is_some();
    if exports {
        hydrofmu::database::section::wamit_names(&hull)
            .map_err(|e| format!("{}: cannot export the section: {e}", hull.name()))?;
    }
    // The diffraction problems only when a table asks for them.
    params.excitation = args.excitation.is_some() || args.froude_krylov.is_some() || exports;
    let scene = Scene {
        sweep: params,
        ..Scene::new(hull.clone())
    };
    let progress = Progress::new("sweep");
    let start = Instant::now();
    let result = scene
        .sweep(&|done, total| progress.update(done, total))
        .map_err(pipeline::message)?;
    let elapsed = start.elapsed();
    let mut text = Vec::new();
    result
        .write_csv(&mut text)
        .map_err(|e| format!("cannot format the table: {e}"))?;
    // Every output together at the end, or none (output::Outputs).
    let mut outputs = output::Outputs::new();
    outputs.bytes(&args.output, &text)?;
    if let Some(path) = &args.hydrostatics {
        outputs.bytes(path, hydrostatics_csv(&hull)?.as_bytes())?;
    }
    for (path, part) in [
        (&args.excitation, ExcitationPart::Total),
        (&args.froude_krylov, ExcitationPart::FroudeKrylov),
    ] {
        if let Some(path) = path {
            let mut text = Vec::new();
            result
                .write_excitation_csv(&mut text, part)
                .map_err(|e| format!("cannot format the excitation table: {e}"))?;
            outputs.bytes(path, &text)?;
        }
    }
    let section_notes = if exports {
        stage_section_exports(&mut outputs, &hull, &result, args)?
    } else {
        Vec::new()
    };
    outputs.commit()?;
    for note in &section_notes {
        output::stderr_line(&format!("note: {note}"));
    }
    for note in &result.notes {
        output::stderr_line(&format!("note: {note}"));
    }
    for warning in &result.warnings {
        output::stderr_line(&format!("warning: {warning}"));
    }
    for (kr, reason) in &result.failures {
        output::stderr_line(&format!(
            "warning: kR = {} failed and is left out: {reason}",
            format_number(*kr, Notation::Plain)
        ));
    }
    output::stderr_line(&format!(
        "time summed over threads: influence (Green function, panel integrals) {:.3} s, \
         assembly {:.3} s, factorization {:.3} s",
        result.times.influence.as_secs_f64(),
        result.times.assembly.as_secs_f64(),
        result.times.factorization.as_secs_f64()
    ));
    let worst_reciprocity = result
        .reciprocity_residual
        .iter()
        .copied()
        .fold(0.0, f64::max);
    output::stderr_line(&format!(
        "{}: {} DOFs, {} frequencies ({} failed), {} body + {} lid panels, {:.3} s wall, \
         max reciprocity residual {:.1e}",
        result.hull_name,
        result.dof_names.len(),
        result.kr.len(),
        result.failures.len(),
        result.panel_counts.0,
        result.panel_counts.1,
        elapsed.as_secs_f64(),
        worst_reciprocity
    ));
    if args.excitation.is_some() {
        let difference = result
            .haskind_direct_difference()
            .iter()
            .copied()
            .fold(0.0, f64::max);
        output::stderr_line(&format!(
            "exciting force: direct diffraction solve; the Haskind relation agrees to {difference:.1e} \
             of the largest |X_j| (max over kR and DOFs)"
        ));
    }
    Ok(())
}

/// Stages `--wamit` and `--netcdf` of a section: its 1 m slice per unit length at the
/// reference rho and g (docs/DATABASES.md, "Export"). Returns the export's notes.
fn stage_section_exports(
    outputs: &mut output::Outputs,
    hull: &Hull,
    result: &sweep::SweepResult,
    args: &SweepArgs,
) -> Result<Vec<String>, String> {
    use hydrofmu::fmu::description::{DEFAULT_G, DEFAULT_RHO};
    let section = SectionDatabase::from_sweep(hull, result, DEFAULT_RHO, DEFAULT_G)
        .map_err(|e| format!("{}: cannot export the section: {e}", hull.name()))?;
    if let Some(prefix) = &args.wamit {
        crate::body::stage_wamit(outputs, prefix, &section.wamit())?;
    }
    if let Some(path) = &args.netcdf {
        outputs.with_path(path, |temporary| section.write_netcdf(temporary))?;
    }
    Ok(section.database.notes.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hydrostatics_table_lists_every_entry() {
        let hull = Hull::semicircle(2.0).unwrap();
        let text = hydrostatics_csv(&hull).unwrap();
        assert!(text.contains("# modes: sway heave roll cb1 cb2 cb3 cb4 cb5 cb6\n"));
        let rows: Vec<&str> = text
            .lines()
            .skip_while(|l| *l != "i,j,value")
            .skip(1)
            .collect();
        assert_eq!(rows.len(), 81);
        // Heave: rho g B with B = 2R = 4 m.
        let heave: f64 = rows[10].split(',').nth(2).unwrap().parse().unwrap();
        assert!((heave - 4.0).abs() < 1e-12, "{}", rows[10]);
        assert!(rows[0].starts_with("1,1,0e0"));
    }
}
