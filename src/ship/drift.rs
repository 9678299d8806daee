//! Mean wave drift of a fixed ship by strip theory.
//!
//! The ship is held fixed: its motions belong to the multibody model that uses the FMU, which
//! adds the drift of the moving hull itself if it needs it. Each section's 2D mean drift of a
//! fixed section (`crate::bem::Drift::mean_drift`, per `rho g a^2`: far field for sway,
//! pressure integration for heave, roll and the elastic DOFs) is solved at the wave's own
//! frequency for the transverse wave of the heading's side (direction cosine
//! `sign(sin beta)`), scaled by the transverse share of the wave's momentum flux
//! `sin^2 beta`, and integrated along the ship with the strip integration's weights and
//! section coordinates `T(x)` (module docs of `crate::ship`):
//!
//! ```text
//! D_r(omega, beta) = rho g sin^2(beta) integral T_r(x)^T d_s(x, omega, sign(sin beta)) dx
//! ```
//!
//! so rigid yaw gets the sway drift's moment `integral x d_sway dx` and rigid pitch
//! `-integral x d_heave dx` (bow down positive). A long wall reflecting an oblique wave fully
//! gives `rho g a^2 sin^2(beta) / 2` per unit length (times `1 + 2kh / sinh 2kh` in water of
//! depth `h`), which this reproduces. Each section's drift is solved in its solver's depth
//! (deep water or finite, [`crate::bem::Drift`]). Strip theory has
//! no surge drift (a slender section has no force along x, and surge is no ship DOF); in head
//! and following seas every drift is zero. Valid where the waves are short against the ship
//! and not near head or following seas, away from the ends (docs/SHIPS.md).

use super::strip::{integrate_vector, Share};
use crate::bem::IrregularFrequencies;
use crate::green::FreeSurface;
use crate::sweep::Solver;
use nalgebra::DMatrix;

/// The transverse direction cosines of the 2D drift solves: column 0 the wave towards +y
/// (ship headings 0 < beta < 180), column 1 towards -y.
const SIDES: [f64; 2] = [1.0, -1.0];

/// The fixed section's 2D mean drift at `wavenumber` per `rho g a^2`: section DOFs x
/// [`SIDES`].
///
/// # Errors
/// The solve's failure, or a section too coarse for the drift (fewer than three panels).
pub(super) fn section_drift(
    solver: &Solver,
    wavenumber: f64,
    irregular: IrregularFrequencies,
) -> Result<DMatrix<f64>, String> {
    let solution = solver
        .solve_waves(FreeSurface::Wave { wavenumber }, irregular, &SIDES)
        .map_err(|e| e.to_string())?;
    solution
        .wave_forces
        .and_then(|w| w.drift)
        .map(|d| d.mean_drift())
        .ok_or_else(|| "the section's drift solve gave no mean drift".to_string())
}

/// The ship's mean drift, SI per `a^2`: ship DOFs x `headings` (see the module docs).
/// `drift[k]` is the distinct section k's [`section_drift`].
pub(super) fn integrate(
    shares: &[Share],
    dofs: usize,
    headings: &[f64],
    drift: &[DMatrix<f64>],
    rho_g: f64,
) -> DMatrix<f64> {
    let mut total = DMatrix::zeros(dofs, headings.len());
    for (h, heading) in headings.iter().enumerate() {
        let sine = heading.to_radians().sin();
        // sin(180 deg) is 1.2e-16, not 0: head and following seas have no transverse wave.
        if sine.abs() < 1e-12 {
            continue;
        }
        let side = if sine > 0.0 { 0 } else { 1 };
        let column = integrate_vector(shares, dofs, |k| {
            drift[k].column(side).iter().copied().collect()
        });
        for (r, value) in column.iter().enumerate() {
            total[(r, h)] = rho_g * sine * sine * value;
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::super::strip::{run, ShipSweepParams};
    use super::super::Ship;
    use super::*;
    use std::path::Path;

    const RHO_G: f64 = 1025.0 * 9.81;

    /// A semicircle ship of radius 1 m from x = -5 to 5 m, swept with 32 panels, 2 levels.
    fn semicircle_ship() -> (Ship, ShipSweepParams) {
        let mut text = String::from("<ship name=\"prism\">\n");
        for x in [-5.0, -2.0, 0.0, 1.0, 5.0] {
            text.push_str(&format!(
                "<station x=\"{x}\"><semicircle radius=\"1\"/></station>\n"
            ));
        }
        text.push_str("</ship>\n");
        let ship = Ship::from_xml_str(&text, "prism.xml", Path::new(".")).unwrap();
        let panels = crate::PanelParams {
            body_panels: 32,
            ..crate::PanelParams::default()
        };
        let params = ShipSweepParams {
            omega: vec![1.5, 3.0],
            headings: vec![90.0, 270.0, 30.0, 180.0, 0.0],
            panels,
            panels_with_corners: panels,
            extrapolation_levels: 2,
            levels_with_corners: 2,
            ..ShipSweepParams::for_ship(&ship)
        };
        (ship, params)
    }

    #[test]
    fn a_prismatic_ship_drifts_as_its_section_times_its_length_scaled_by_sin_squared() {
        let (ship, params) = semicircle_ship();
        let without = run(&ship, &params, &|_, _| {}).unwrap();
        assert!(without.drift.is_empty() && without.drift_headings.is_empty());
        let with = run(
            &ship,
            &ShipSweepParams {
                drift: true,
                ..params.clone()
            },
            &|_, _| {},
        )
        .unwrap();
        assert_eq!(with.drift_headings, params.headings);
        assert_eq!(with.drift.len(), 2);
        // The other tables are untouched by the drift solves.
        assert_eq!(with.added_mass, without.added_mass);
        assert_eq!(with.excitation, without.excitation);
        let hull = ship.sections()[0].ship_section(&[]).unwrap();
        let solver = Solver::new(&hull, &params.panels, 2).unwrap();
        let length = 10.0;
        for (w, omega) in params.omega.iter().enumerate() {
            let k = omega * omega / 9.81;
            let section = section_drift(&solver, k, params.irregular_frequencies).unwrap();
            let d = &with.drift[w];
            let sway_2d = section[(0, 0)];
            // A fixed section's sway drift is the reflected momentum: 0 < d <= 1/2.
            assert!(sway_2d > 1e-4 && sway_2d <= 0.5, "2D sway drift {sway_2d}");
            let scale = RHO_G * length * sway_2d.abs().max(section[(1, 0)].abs());
            let near = |a: f64, b: f64, what: &str| {
                assert!((a - b).abs() <= 1e-9 * scale, "{what}: {a} against {b}");
            };
            for j in 0..3 {
                // Beam seas: the section's drift times the length.
                near(d[(j, 0)], RHO_G * length * section[(j, 0)], "beam seas");
                // Heading 30: a quarter of the beam-sea drift.
                near(d[(j, 2)], 0.25 * d[(j, 0)], "sin^2 at 30 degrees");
            }
            // 270 mirrors 90: sway and roll change sign, heave does not.
            near(d[(0, 1)], -d[(0, 0)], "sway 270");
            near(d[(1, 1)], d[(1, 0)], "heave 270");
            near(d[(2, 1)], -d[(2, 0)], "roll 270");
            // Pitch and yaw of a ship symmetric fore and aft: zero.
            for h in 0..3 {
                near(d[(3, h)], 0.0, "pitch");
                near(d[(4, h)], 0.0, "yaw");
            }
            // Head and following seas: no transverse wave, no drift.
            for h in [3, 4] {
                for j in 0..5 {
                    assert_eq!(d[(j, h)], 0.0, "DOF {j}, heading {}", params.headings[h]);
                }
            }
        }
    }

    #[test]
    fn an_offset_ship_has_the_yaw_and_pitch_moments_of_its_sway_and_heave_drift() {
        let mut text = String::from("<ship name=\"offset\">\n");
        for x in [10.0, 14.0] {
            text.push_str(&format!(
                "<station x=\"{x}\"><semicircle radius=\"1\"/></station>\n"
            ));
        }
        text.push_str("</ship>\n");
        let ship = Ship::from_xml_str(&text, "offset.xml", Path::new(".")).unwrap();
        let (_, base) = semicircle_ship();
        let params = ShipSweepParams {
            omega: vec![2.0],
            headings: vec![90.0],
            drift: true,
            ..base
        };
        let d = &run(&ship, &params, &|_, _| {}).unwrap().drift[0];
        // A uniform section from 10 to 14 m: the moments act at x = 12 m.
        let (sway, heave, pitch, yaw) = (d[(0, 0)], d[(1, 0)], d[(3, 0)], d[(4, 0)]);
        assert!(
            (yaw - 12.0 * sway).abs() <= 1e-9 * yaw.abs(),
            "yaw {yaw}, sway {sway}"
        );
        assert!(
            (pitch + 12.0 * heave).abs() <= 1e-9 * pitch.abs(),
            "pitch {pitch}, heave {heave}"
        );
    }
}
