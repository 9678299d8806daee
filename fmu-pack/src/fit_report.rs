//! The fit's report: the human-readable text and the figures of fit against data, shown by
//! `fmu-pack fit` and packed into an archive's documentation.

use crate::pipeline::Built;
use fmu_pack::plot::{self, Figure, Scale, Style};
use hydrofmu::fmu::{DofUnit, Extent};
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
    let dofs = built.scene.scene().hull.dof_units();
    fit_plots(
        &built.response.fitted,
        &built.fit,
        "panel method",
        ("kR", &|omega| units::kr_from_omega(omega, radius, g)),
        (&dofs, Extent::PerUnitLength),
    )
}

/// The unit of `A~_ij` (SI) for DOFs of length exponents `e_i`, `e_j` (their sum 0, 1, 2:
/// translation-translation, rotation-translation, rotation-rotation; a mode amplitude counts
/// as a rotation): `kg`, `kg.m`, `kg.m2` of a whole body, or per metre of a section (`kg/m`,
/// `kg.m/m`, `kg.m2/m`).
pub fn added_mass_unit(i: &DofUnit, j: &DofUnit, extent: Extent) -> String {
    let whole = Extent::WholeBody.added_mass_unit(i.length_exponent + j.length_exponent);
    match extent {
        Extent::WholeBody => whole.to_string(),
        Extent::PerUnitLength => format!("{whole}/m"),
    }
}

/// [`plots`] for any fitted response: `source` names the data, `axis` the x axis (its label
/// and its value at a frequency in rad/s; logarithmic), `units` the DOFs' units (found by
/// name) and whether the data is per unit length.
pub fn fit_plots(
    response: &hydrofmu::FrequencyResponse,
    fit: &hydrofmu::identify::FitReport,
    source: &str,
    axis: (&str, &dyn Fn(f64) -> f64),
    units: (&[DofUnit], Extent),
) -> Vec<(String, String)> {
    let (label, x) = axis;
    let (dofs, extent) = units;
    let unit_of = |name: &str| dofs.iter().find(|d| d.name == name);
    let names = &response.dof_names;
    let mut out = Vec::new();
    for i in 0..names.len() {
        for j in i..names.len() {
            if fit.error_scale[(i, j)] <= 0.0 {
                continue;
            }
            let y_label = match (unit_of(&names[i]), unit_of(&names[j])) {
                (Some(a), Some(b)) => format!(
                    "A~({}, {}) ({})",
                    names[i],
                    names[j],
                    added_mass_unit(a, b, extent)
                ),
                _ => format!("A~({}, {}) (SI)", names[i], names[j]),
            };
            let mut figure = Figure::new(
                &format!("A~({}, {}): {source} and network", names[i], names[j]),
                label,
                &y_label,
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

#[cfg(test)]
mod tests {
    use super::*;
    use hydrofmu::identify::{self, FitParams};
    use hydrofmu::{Branch, FrequencyResponse, Network, NetworkForm, Stage};
    use nalgebra::{DMatrix, DVector};

    /// A roll-only response from one mass-spring-damper stage, and its fit.
    fn roll_fit() -> (FrequencyResponse, hydrofmu::FitReport) {
        let (mass, omega_n) = (2.0e3, 1.2);
        let network = Network {
            dof_names: vec!["roll".into()],
            added_mass_inf: DMatrix::from_element(1, 1, 5.0e2),
            branches: vec![Branch {
                direction: DVector::from_element(1, 1.0),
                stages: vec![Stage {
                    mass,
                    stiffness: mass * omega_n * omega_n,
                    damping: 0.6 * omega_n * mass,
                }],
            }],
            substructures: Vec::new(),
            rho: 1025.0,
            g: 9.81,
            form: NetworkForm::SeriesChain,
        };
        let omega: Vec<f64> = (0..40).map(|k| 0.2 * 1.06f64.powi(k)).collect();
        let response = FrequencyResponse::from_network(&network, &omega);
        let params = FitParams {
            band: (omega[0], omega[omega.len() - 1]),
            form: Some(NetworkForm::SeriesChain),
            ..FitParams::default()
        };
        let fit = identify::fit(&response, &params).unwrap();
        (response, fit)
    }

    #[test]
    fn a_rotation_rotation_entry_is_plotted_in_its_unit() {
        let (response, fit) = roll_fit();
        let roll = [DofUnit::builtin("roll").unwrap()];
        let axis: (&str, &dyn Fn(f64) -> f64) = ("omega (rad/s)", &|omega| omega);
        for (extent, unit) in [
            (Extent::PerUnitLength, "(kg.m2/m)"),
            (Extent::WholeBody, "(kg.m2)"),
        ] {
            let figures = fit_plots(&response, &fit, "data", axis, (&roll, extent));
            assert_eq!(figures.len(), 1);
            let (name, svg) = &figures[0];
            assert_eq!(name, "fit-roll-roll.svg");
            let y_label = format!("A~(roll, roll) {unit}");
            assert!(svg.contains(&y_label), "{y_label} missing:\n{svg}");
            assert!(svg.contains(">omega (rad/s)<"), "{svg}");
        }
    }

    #[test]
    fn added_mass_units_follow_the_length_exponents() {
        let sway = DofUnit::builtin("sway").unwrap();
        let roll = DofUnit::builtin("roll").unwrap();
        let mode = DofUnit::new("vb1", 1, false);
        let section = Extent::PerUnitLength;
        assert_eq!(added_mass_unit(&sway, &sway, section), "kg/m");
        assert_eq!(added_mass_unit(&sway, &roll, section), "kg.m/m");
        assert_eq!(added_mass_unit(&roll, &roll, section), "kg.m2/m");
        assert_eq!(added_mass_unit(&sway, &sway, Extent::WholeBody), "kg");
        assert_eq!(added_mass_unit(&mode, &sway, Extent::WholeBody), "kg.m");
        assert_eq!(added_mass_unit(&mode, &mode, Extent::WholeBody), "kg.m2");
    }
}
