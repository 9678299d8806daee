//! `fmu-pack sweep`: the coefficient table of a hull.

pub use crate::args::SweepArgs;
use crate::output;
use crate::pipeline;
use crate::progress::Progress;
use hydrofmu::database::section::SectionDatabase;
use hydrofmu::hull::Hull;
use hydrofmu::scene::Scene;
use hydrofmu::source::Source;
use hydrofmu::sweep::{self, ExcitationPart};
use hydrofmu::xml::{format_number, Notation};
use std::path::PathBuf;
use std::time::Instant;

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
        args.drift.as_ref(),
        args.rao.as_ref(),
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
    // The mass properties before a sweep that may take minutes.
    let floating =
        crate::floating::resolve(&hull, &args.floating, args.rao.as_ref().map(|_| "--rao"))?;
    let floating = match (floating, args.viscous_amplitude) {
        (Some(floating), Some(degrees)) => Some(viscous_roll(&hull, floating, degrees)?),
        (floating, _) => floating,
    };
    let exports = args.wamit.is_some() || args.netcdf.is_some();
    if exports {
        hydrofmu::database::section::wamit_names(&hull)
            .map_err(|e| format!("{}: cannot export the section: {e}", hull.name()))?;
    }
    // The diffraction problems (and the drift, which needs them) only when a table asks.
    params.excitation = args.excitation.is_some()
        || args.froude_krylov.is_some()
        || args.drift.is_some()
        || args.rao.is_some()
        || exports;
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
    if let Some(path) = &args.drift {
        let mut text = Vec::new();
        match &floating {
            Some((floating, line)) => result
                .write_floating_drift_csv(floating, line, &mut text)
                .map_err(|e| format!("{}: the floating drift: {e}", hull.name()))?,
            None => result
                .write_drift_csv(&mut text)
                .map_err(|e| format!("cannot format the drift table: {e}"))?,
        }
        outputs.bytes(path, &text)?;
    }
    if let (Some(path), Some((floating, line))) = (&args.rao, &floating) {
        let mut text = Vec::new();
        result
            .write_rao_csv(floating, line, &mut text)
            .map_err(|e| format!("{}: the motion: {e}", hull.name()))?;
        outputs.bytes(path, &text)?;
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

/// The floating section with Ikeda's roll damping of `hull` linearized at `degrees`
/// (`--viscous-amplitude`), its table line saying so.
fn viscous_roll(
    hull: &Hull,
    (floating, line): crate::floating::FloatingSection,
    degrees: f64,
) -> Result<crate::floating::FloatingSection, String> {
    use hydrofmu::fmu::description::DEFAULT_RHO;
    if !(degrees.is_finite() && (0.0..90.0).contains(&degrees)) {
        return Err(format!(
            "--viscous-amplitude {degrees}: expected a roll amplitude in [0, 90) deg"
        ));
    }
    let roll = hydrofmu::viscous::roll_params(hull, DEFAULT_RHO)
        .map_err(|e| format!("--viscous-amplitude: {e}"))?;
    let p = roll.params;
    let floating = floating
        .with_viscous_roll(p, degrees.to_radians())
        .map_err(|e| format!("--viscous-amplitude: {}: {e}", hull.name()))?;
    let line = format!(
        "{line}; viscous roll damping added: Ikeda at zero speed (docs/VISCOUS.md) linearized \
         at roll amplitude {degrees} deg, B_eq = B_l(omega) + 8/(3 pi) omega phi_a B_q, with B \
         {} m, T {} m, sigma {}, bilge radius {} m, OG {} m ({}), {}",
        p.breadth,
        p.draft,
        p.area_coefficient,
        p.bilge_radius,
        p.roll_axis_height,
        roll.axis.describe(),
        p.bilge_keels
            .map_or("no bilge keels".to_string(), |k| format!(
                "bilge keels {} m on {} of the length",
                k.breadth, k.length_fraction
            ))
    );
    Ok((floating, line))
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
