//! The fit's report: the human-readable text and the figures of fit against data, shown by
//! `fmu-pack fit` and packed into an archive's documentation.

use crate::pipeline::Built;
use fmu_pack::plot::{self, Figure, Scale, Style};
use hydrofmu::units;
use std::fmt::Write as _;

/// The human-readable report.
pub fn text(built: &Built) -> String {
    let fit = &built.fit;
    let names = &built.response.fitted.dof_names;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "network: {} over {} DOFs ({}), order {}, {} auxiliary DOFs, {} states",
        fit.network.form,
        names.len(),
        names.join(" "),
        fit.order,
        fit.aux_dofs,
        fit.states
    );
    let _ = writeln!(
        out,
        "band: {:.4} .. {:.4} rad/s ({} points); tolerance {:.3} of sqrt(|A_ii A_jj|): {}",
        fit.band.0,
        fit.band.1,
        fit.points,
        fit.tolerance,
        if fit.tolerance_met { "met" } else { "NOT met" }
    );
    if let Some(nyquist) = built.scene.nyquist_cut() {
        let _ = writeln!(
            out,
            "band cut at the Nyquist frequency {nyquist:.4} rad/s of --max-step {:.4} s",
            std::f64::consts::PI / nyquist
        );
    }
    let _ = writeln!(
        out,
        "largest relative error {:.4}; sweep {:.3} s, fit {:.3} s ({} iterations)",
        fit.max_relative_error,
        built.sweep_time.as_secs_f64(),
        built.fit_time.as_secs_f64(),
        fit.iterations
    );
    for note in &fit.notes {
        let _ = writeln!(out, "note: {note}");
    }
    let _ = writeln!(out, "entry errors (max, rms, scale):");
    for i in 0..names.len() {
        for j in i..names.len() {
            let _ = writeln!(
                out,
                "  {:>8} {:>8}  max {:.3e}  rms {:.3e}  scale {:.3e}",
                names[i],
                names[j],
                fit.max_error[(i, j)],
                fit.rms_error[(i, j)],
                fit.error_scale[(i, j)]
            );
        }
    }
    let _ = writeln!(
        out,
        "parameters (SI, rho = {}, g = {}):",
        fit.network.rho, fit.network.g
    );
    for (b, branch) in fit.network.branches.iter().enumerate() {
        let direction: Vec<String> = branch.direction.iter().map(|d| format!("{d:.4}")).collect();
        let _ = writeln!(out, "  branch {b}: direction [{}]", direction.join(", "));
        for stage in &branch.stages {
            let _ = writeln!(
                out,
                "    m {:.6e} kg/m  k {:.6e} N/m2  c {:.6e} N.s/m2",
                stage.mass, stage.stiffness, stage.damping
            );
        }
    }
    for (k, sub) in fit.network.substructures.iter().enumerate() {
        let relaxed = sub.spring_relaxation.norm() > 0.0;
        let _ = writeln!(
            out,
            "  substructure {k}: {} unit springs{}, {} unit masses, damping over masses and \
             hull (the matrices are in the network file)",
            sub.spring_count(),
            if relaxed { " (relaxed)" } else { "" },
            sub.masses
        );
    }
    out
}

/// Plots of fit against data (as Schilder et al.'s Figure 6), one per matrix entry i <= j whose
/// scale is nonzero: data (markers) and network (lines), real and imaginary parts, against kR.
/// Returns `(file name, SVG text)` pairs.
pub fn plots(built: &Built) -> Vec<(String, String)> {
    let radius = built.sweep.reference_half_beam;
    let g = built.response.fitted.g;
    fit_plots(
        &built.response.fitted,
        &built.fit,
        "panel method",
        ("kR", &|omega| units::kr_from_omega(omega, radius, g)),
    )
}

/// [`plots`] for any fitted response: `source` names the data, `axis` the x axis (its label
/// and its value at a frequency in rad/s; logarithmic).
pub fn fit_plots(
    response: &hydrofmu::FrequencyResponse,
    fit: &hydrofmu::identify::FitReport,
    source: &str,
    axis: (&str, &dyn Fn(f64) -> f64),
) -> Vec<(String, String)> {
    let (label, x) = axis;
    let names = &response.dof_names;
    let mut out = Vec::new();
    for i in 0..names.len() {
        for j in i..names.len() {
            if fit.error_scale[(i, j)] <= 0.0 {
                continue;
            }
            let mut figure = Figure::new(
                &format!("A~({}, {}): {source} and network", names[i], names[j]),
                label,
                "A~ (SI)",
            );
            figure.x_scale = Scale::Log;
            let data = |part: fn(num_complex::Complex64) -> f64| {
                response
                    .omega
                    .iter()
                    .zip(&response.added_mass)
                    .map(|(&w, m)| (x(w), part(m[(i, j)])))
                    .collect::<Vec<_>>()
            };
            let model = |part: fn(num_complex::Complex64) -> f64| {
                response
                    .omega
                    .iter()
                    .map(|&w| (x(w), part(fit.network.added_mass_tf(w)[(i, j)])))
                    .collect::<Vec<_>>()
            };
            figure.add(&format!("Re, {source}"), data(|z| z.re), Style::Markers);
            figure.add("Re, network", model(|z| z.re), Style::Line);
            figure.add(&format!("Im, {source}"), data(|z| z.im), Style::Markers);
            figure.add("Im, network", model(|z| z.im), Style::Line);
            figure.series[1].colour = 0;
            figure.series[2].colour = 1;
            figure.series[3].colour = 1;
            let (b0, b1) = fit.band;
            figure.caption = format!(
                "fit band {label} {:.3} .. {:.3}; {}",
                x(b0),
                x(b1),
                plot::provenance("fmu-pack")
            );
            out.push((
                format!("fit-{}-{}.svg", names[i], names[j]),
                figure.to_svg(),
            ));
        }
    }
    out
}
