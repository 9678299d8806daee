//! `fmu-pack pack` and `fmu-pack inspect`: one `.fmu` archive per hull. This module picks the
//! source ([`hydrofmu::source::Source`]): a ship or an imported database goes to its own
//! module, a section's network is computed here (or read from `--network`), and
//! [`crate::packing`] writes the archive.

use crate::args::HullSweepArgs;
pub use crate::args::{InspectArgs, PackArgs};
pub use crate::packing::{
    identifier_from_path, inspect, locate_binary, pack_network, Fitted, PackError, PackSummary,
    PackedNetwork, Target,
};
use crate::pipeline::{self, Built};
use hydrofmu::fmu::Body;
use hydrofmu::scene::{Band, Scene};
use hydrofmu::source::Source;

/// `fmu-pack pack`.
pub fn pack(args: &PackArgs) -> Result<PackSummary, PackError> {
    // The archive's folder, before the sweep and the fit.
    crate::output::check_folder(&args.output)?;
    let source = Source::from_argument(&args.sweep.hull);
    let whole_body =
        matches!(&source, Ok(Source::ShipFile(_))) || matches!(&source, Ok(s) if s.is_import());
    if whole_body && (args.floating.given() || args.floating.fixed) {
        return Err(PackError(
            "--mass, --cog, --gyradius, --mooring and --fixed choose a floating section; a ship's \
             or an imported database's drift is its own (docs/DRIFT.md)"
                .into(),
        ));
    }
    match source {
        Ok(Source::ShipFile(_)) => return crate::ship_cmd::pack(args),
        Ok(source) if source.is_import() => return crate::database_cmd::pack(args),
        // A section, or an argument that names nothing: the section's resolve says why.
        _ => {}
    }
    let (resolved, sweep_params) = args.sweep.resolve()?;
    let floating = floating_for_drift(args)?;
    let estimate = args.viscous.estimate(&resolved)?;
    let hull = args
        .viscous
        .apply(Body::section(&resolved), estimate.as_ref())?;
    let mut report = None;
    let network = match &args.network {
        Some(path) => {
            if args.band.is_some()
                || args.tol.is_some()
                || args.order.is_some()
                || args.max_step.is_some()
                || args.allow_tolerance_miss
            {
                return Err(PackError(
                    "--band, --tol, --order, --max-step and --allow-tolerance-miss shape a \
                     computed network; they cannot apply to --network FILE"
                        .into(),
                ));
            }
            let text = hydrofmu::input::read_bounded_text(
                path,
                hydrofmu::xml::MAX_INPUT_BYTES as u64,
                "MAX_INPUT_BYTES",
            )
            .map_err(|e| format!("cannot read the network {}: {e}", path.display()))?;
            PackedNetwork::from_text(text, &path.display().to_string())?
        }
        None => {
            let band = match &args.band {
                Some(text) => pipeline::parse_band(text)?,
                None => Band::default(),
            };
            // Swept whole: the report states what the left-out DOFs would have coupled.
            let whole = HullSweepArgs {
                dofs: None,
                ..args.sweep.clone()
            };
            let (whole_hull, _) = whole.resolve()?;
            let scene = Scene {
                dofs: Some(hull.dofs.iter().map(|d| d.name.clone()).collect()),
                band,
                tolerance: args.tol,
                order: args.order,
                form: None,
                max_step: args.max_step,
                sweep: sweep_params,
                ..Scene::new(whole_hull)
            };
            let built = pipeline::build_network(scene)?;
            if !built.fit.tolerance_met && !args.allow_tolerance_miss {
                return Err(PackError(tolerance_missed(&built)));
            }
            let scene = built.report();
            let network = PackedNetwork::from_network(built.fit.network.clone());
            report = Some(Fitted { built, scene });
            network
        }
    };
    let binary = locate_binary(args.binary.as_deref())?;
    let identifier = match &args.model_identifier {
        Some(id) => id.clone(),
        None => identifier_from_path(&args.output),
    };
    let target = Target {
        binary: &binary,
        binary_windows: crate::packing::WindowsBinary::from_args(
            args.binary_windows.as_deref(),
            args.no_windows,
        ),
        model_identifier: &identifier,
        output: &args.output,
        fmi: args.fmi,
    };
    let mut summary = pack_network(
        hull,
        network,
        args.keep_inf_mass,
        &target,
        report.as_ref(),
        args.drift.then_some(floating.as_ref()),
    )?;
    if args.viscous.viscous {
        summary.viscous = match estimate {
            Some(estimate) => estimate.lines,
            None => vec!["the entries given (--no-estimate), the others 0".into()],
        };
    }
    Ok(summary)
}

/// The floating section whose drift `--drift` packs (the whole hull floats, whatever DOFs the
/// network keeps), or `None` for the fixed section's drift. Mass options without `--drift`
/// are refused: they change nothing else.
fn floating_for_drift(
    args: &PackArgs,
) -> Result<Option<crate::floating::FloatingSection>, PackError> {
    if !args.drift {
        if args.floating.given() || args.floating.fixed {
            return Err(PackError(
                "--mass, --cog, --gyradius, --mooring and --fixed choose the body whose mean \
                 drift --drift packs; add --drift"
                    .into(),
            ));
        }
        return Ok(None);
    }
    let whole = HullSweepArgs {
        dofs: None,
        ..args.sweep.clone()
    };
    let (whole_hull, _) = whole.resolve()?;
    Ok(crate::floating::resolve(&whole_hull, &args.floating, None)?)
}

/// Why a fit that misses its tolerance is not packed, and what to do.
fn tolerance_missed(built: &Built) -> String {
    let fit = &built.fit;
    format!(
        "the fit misses the tolerance: largest error {:.2} % of sqrt(|A_ii A_jj|) against the \
         tolerance {:.2} % (--tol) with the {} network, order {}, {} states; no archive \
         written. Try another --order or a narrower --band, raise --tol, or pass \
         --allow-tolerance-miss to pack it anyway",
        100.0 * fit.max_relative_error,
        100.0 * fit.tolerance,
        fit.network.form,
        fit.order,
        fit.states
    )
}
