//! A ship's viscous damping from its sections' estimates (strip theory, zero speed).
//!
//! Each station's section is seen as a ship's strip sees it (rigid sway, heave and roll about the
//! centreline on the free surface, [`Hull::ship_section`]; `OG` from the section file's `<mass>`
//! when it has one, else 0); stations without a section contribute nothing. With the
//! trapezoidal rule over the stations (`integrate_along`):
//!
//! ```text
//! roll:  B_l = int B_l,section(x) dx,   B_q = int B_q,section(x) dx
//! sway:  B_q = int 0.5 rho C_D T(x) dx            heave: B_q = int 0.5 rho C_D B(x) dx
//! yaw:   B_q = int 0.5 rho C_D T(x) |x|^3 dx      pitch: B_q = int 0.5 rho C_D B(x) |x|^3 dx
//! ```
//!
//! Yaw and pitch: a rotation rate `r` moves the strip at `x` by `x r`, its drag
//! `-0.5 rho C_D D |x r| x r` has the moment `-r |r| int 0.5 rho C_D D |x| x^2 dx` about the
//! origin. These per-DOF coefficients leave out the drag's sway-yaw and heave-pitch cross
//! terms and the current's yaw moment; [`ShipEstimate::strips`] carries them: one
//! [`Strip`] per station with a section (its trapezoid weight `w`, draft, breadth and the
//! sway and heave `C_D`), whose drag the FMU sums strip by strip ([`crate::model::crossflow`]).
//! With a yaw rate alone the strips give exactly the yaw coefficient above:
//! `sum w 0.5 rho C_D T |x|^3 = int 0.5 rho C_D T |x|^3 dx` by the same trapezoidal rule.

use super::hull::{hull_roll_damping, section_drag, HullDampingError};
use super::{integrate_along, CrossFlow, Damping, Warning};
use crate::model::crossflow::Strip;
use crate::ship::Ship;

/// The ship's estimated damping per rigid DOF: `(name, Damping)`, and the sections' warnings.
#[derive(Clone, Debug, PartialEq)]
pub struct ShipEstimate {
    /// `roll`, `sway`, `heave`, `yaw`, `pitch` with their damping (N, m, s, rad).
    pub dofs: Vec<(&'static str, Damping)>,
    /// Ikeda's validity warnings of the sections, with the station's x.
    pub warnings: Vec<(f64, Warning)>,
    /// The cross-flow strips: one per station with a section (module docs).
    pub strips: Vec<Strip>,
}

/// The trapezoidal rule's weight of each of the abscissae `x` (m): half the distance between
/// its neighbours (one neighbour at the ends).
fn trapezoid_weights(x: &[f64]) -> Vec<f64> {
    (0..x.len())
        .map(|k| {
            let before = if k > 0 { x[k] - x[k - 1] } else { 0.0 };
            let after = x.get(k + 1).map_or(0.0, |next| next - x[k]);
            0.5 * (before + after)
        })
        .collect()
}

/// The estimate of `ship` at roll frequency `omega` (rad/s) and amplitude `phi_a` (rad), in
/// water of density `rho` (module docs).
///
/// # Errors
/// A section that gives no estimate (named with its station).
pub fn ship_estimate(
    ship: &Ship,
    rho: f64,
    omega: f64,
    phi_a: f64,
) -> Result<ShipEstimate, HullDampingError> {
    let mut roll = Vec::new();
    let mut drag: [Vec<(f64, Damping)>; 4] = Default::default();
    let mut warnings = Vec::new();
    let mut strips = Vec::new();
    let stations: Vec<f64> = ship.stations().iter().map(|s| s.x).collect();
    let weights = trapezoid_weights(&stations);
    for (station, weight) in ship.stations().iter().zip(weights) {
        let x = station.x;
        let Some(index) = station.section else {
            roll.push((x, Damping::default()));
            for column in &mut drag {
                column.push((x, Damping::default()));
            }
            continue;
        };
        let located = |e: HullDampingError| HullDampingError {
            reason: format!("station x = {x} m: {}", e.reason),
            ..e
        };
        let section = ship.sections()[index]
            .ship_section(&[])
            .map_err(|e| HullDampingError {
                hull: ship.name().to_string(),
                reason: e.to_string(),
            })?;
        let (_, damping) = hull_roll_damping(&section, rho, omega, phi_a).map_err(located)?;
        warnings.extend(damping.warnings.iter().map(|w| (x, w.clone())));
        roll.push((x, damping.total()));
        let mut strip = Strip {
            x,
            weight,
            draft: 0.0,
            breadth: 0.0,
            cd_sway: 0.0,
            cd_heave: 0.0,
        };
        for d in section_drag(&section, rho).map_err(located)? {
            let quadratic = |weight: f64| Damping {
                linear: 0.0,
                quadratic: d.quadratic * weight,
            };
            // B_q = 0.5 rho C_D D: the projected depth D back from it.
            let projected = d.quadratic / (0.5 * rho * d.drag_coefficient);
            let (along, moment) = match d.flow {
                CrossFlow::Sway => {
                    (strip.draft, strip.cd_sway) = (projected, d.drag_coefficient);
                    (0, 2)
                }
                CrossFlow::Heave => {
                    (strip.breadth, strip.cd_heave) = (projected, d.drag_coefficient);
                    (1, 3)
                }
            };
            drag[along].push((x, quadratic(1.0)));
            drag[moment].push((x, quadratic(x.abs().powi(3))));
        }
        strips.push(strip);
    }
    let names = ["sway", "heave", "yaw", "pitch"];
    let mut dofs = vec![("roll", integrate_along(&roll))];
    dofs.extend(
        names
            .iter()
            .zip(&drag)
            .map(|(n, c)| (*n, integrate_along(c))),
    );
    Ok(ShipEstimate {
        dofs,
        warnings,
        strips,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hull::Hull;
    use crate::ship::{ShipDof, Station};

    /// A barge of `length` m with the Lewis section 10 m x 3 m, sigma 0.95, everywhere.
    fn barge(length: f64) -> (Ship, Hull) {
        let section = Hull::lewis(10.0, 3.0, 0.95).unwrap();
        let stations = (0..=10)
            .map(|k| Station {
                x: -0.5 * length + length * k as f64 / 10.0,
                section: Some(0),
            })
            .collect();
        let dofs = ["sway", "heave", "roll", "pitch", "yaw"]
            .iter()
            .map(|n| ShipDof {
                name: n.to_string(),
                motions: None,
            })
            .collect();
        let ship = Ship::new("barge", stations, vec![section.clone()], dofs, "barge.xml").unwrap();
        (ship, section)
    }

    #[test]
    fn a_prismatic_ship_is_its_length_times_the_section() {
        let length = 20.0;
        let (ship, section) = barge(length);
        let estimate = ship_estimate(&ship, 1025.0, 0.8, 0.1).unwrap();
        let (_, per_metre) = hull_roll_damping(&section, 1025.0, 0.8, 0.1).unwrap();
        let get = |name: &str| estimate.dofs.iter().find(|d| d.0 == name).unwrap().1;
        let roll = get("roll");
        let expected = per_metre.total();
        assert!((roll.linear - length * expected.linear).abs() < 1e-9 * roll.linear);
        assert!((roll.quadratic - length * expected.quadratic).abs() < 1e-9 * roll.quadratic);
        let sway = section_drag(&section, 1025.0).unwrap()[0].quadratic;
        assert!((get("sway").quadratic - length * sway).abs() < 1e-9 * sway * length);
        // Yaw: int |x|^3 dx over -10..10 is 2 * 10^4 / 4 = 5000 m^4; the trapezoidal rule on
        // 11 stations 2 m apart gives 2 (2 (8 + 64 + 216 + 512 + 1000) - 1000) = 5200.
        let yaw = get("yaw").quadratic / sway;
        assert!((yaw - 5200.0).abs() < 1e-9 * yaw, "{yaw}");
        assert!(get("pitch").quadratic > get("yaw").quadratic);
    }
}
