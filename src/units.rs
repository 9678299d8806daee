//! Units and scales of the 2D radiation problem: the deep-water dispersion relation and the
//! nondimensional coefficients.
//!
//! Deep water, time factor `exp(+i omega t)`, `R` the hull's reference half-beam:
//!
//! ```text
//! k      = omega^2 / g            (wavenumber, 1/m)
//! kR     = omega^2 R / g          (nondimensional frequency)
//! omega  = sqrt(kR g / R)
//! A~_ij / (rho pi R^2)            (nondimensional added mass, both parts of A~ = a - i b / omega)
//! ```
//!
//! Each function keeps the order of its floating-point operations (the order written in its
//! doc), so results are bit for bit the same wherever it replaces an inline formula.
//!
//! This module also holds what a hull states about its own units (`impl Hull` at the bottom):
//! its centre depth `H/R` and the unit of each generalized DOF.

use crate::hull::{DofKind, Hull, RigidKind};
use crate::variables::DofUnit;

/// `omega = sqrt(kR g / R)` (rad/s), computed as `(kr * g / radius).sqrt()`.
pub fn omega_from_kr(kr: f64, radius: f64, g: f64) -> f64 {
    (kr * g / radius).sqrt()
}

/// `kR = omega^2 R / g`, computed as `omega * omega * radius / g`.
pub fn kr_from_omega(omega: f64, radius: f64, g: f64) -> f64 {
    omega * omega * radius / g
}

/// Deep-water wavenumber `k = omega^2 / g` (1/m), computed as `omega * omega / g`.
pub fn wavenumber(omega: f64, g: f64) -> f64 {
    omega * omega / g
}

/// Wavenumber of a nondimensional frequency: `k = kR / R` (1/m).
pub fn wavenumber_from_kr(kr: f64, radius: f64) -> f64 {
    kr / radius
}

/// Scale of the nondimensional added mass: `A~ = rho pi R^2 (A~ / (rho pi R^2))`, computed as
/// `rho * PI * radius * radius` (kg/m per unit of the nondimensional value). With `rho = 1`
/// it is the area `pi R^2`.
pub fn added_mass_scale(rho: f64, radius: f64) -> f64 {
    rho * std::f64::consts::PI * radius * radius
}

// ---------------------------------------------------------------------------------------------
// Hull: H/R and DOF units. These belong with the hull type; they need only its public API.
// ---------------------------------------------------------------------------------------------

impl Hull {
    /// Centre depth over half-beam of a circular contour (the built-in hulls and `<circle>`
    /// files): 0 for the semicircle, `H/R` for the submerged circle. `None` for a polyline
    /// contour. The sweep table records it (`# H/R:`).
    pub fn circle_depth_ratio(&self) -> Option<f64> {
        // A circular contour has no vertices but its ends; a polyline has at least two
        // points, three when closed (knots 0, .., 1).
        let circular = self.breakpoints().len() == 2 && (self.is_closed() || self.is_arc_open());
        if !circular {
            return None;
        }
        if !self.is_closed() {
            return Some(0.0);
        }
        // s = 0 is the circle's leftmost point, at the centre's height: (-R, -H).
        let depth = -self.point(0.0)[1];
        Some(depth / self.reference_half_beam())
    }

    /// Centre depth over half-beam `H/R`: 0 for the semicircle and any surface-piercing hull,
    /// the given `H/R` of a circle; for a closed polyline the depth of the middle of its
    /// vertical extent over the half-beam.
    pub fn depth_ratio(&self) -> f64 {
        if let Some(ratio) = self.circle_depth_ratio() {
            return ratio;
        }
        if !self.is_closed() {
            return 0.0;
        }
        let (top, bottom) = self
            .breakpoints()
            .iter()
            .map(|&s| self.point(s)[1])
            .fold((f64::NEG_INFINITY, f64::INFINITY), |(t, b), y| {
                (t.max(y), b.min(y))
            });
        -(top + bottom) / 2.0 / self.reference_half_beam()
    }

    /// Unit of DOF `dof` (see docs/DESIGN-NOTES.md, "Units of generalized DOFs"): rigid sway
    /// and heave and the displacement Craig-Bampton modes are lengths; roll and the rotation
    /// modes (`cb3`, `cb6`) are angles; elastic modes from a file are dimensionless amplitudes.
    /// `None` if `dof` is out of range.
    pub fn dof_unit(&self, dof: usize) -> Option<DofUnit> {
        let name = *self.dof_names().get(dof)?;
        Some(match self.dof_kind(dof) {
            Some(DofKind::Rigid {
                kind: RigidKind::Roll,
                ..
            }) => DofUnit::new(name, 1, true),
            Some(DofKind::Rigid { .. }) => DofUnit::new(name, 0, false),
            Some(DofKind::CraigBampton { mode }) if mode == 3 || mode == 6 => {
                DofUnit::new(name, 1, true)
            }
            Some(DofKind::CraigBampton { .. }) => DofUnit::new(name, 0, false),
            _ => DofUnit::new(name, 1, false),
        })
    }

    /// Units of every DOF, in the hull's order.
    pub fn dof_units(&self) -> Vec<DofUnit> {
        (0..self.dof_count())
            .filter_map(|j| self.dof_unit(j))
            .collect()
    }

    /// An open contour from `(-R, 0)` to `(R, 0)` through a point below the free surface at
    /// s = 1/2: with two breakpoints only, the semicircle (a straight two-point polyline
    /// between those ends stays at y = 0).
    fn is_arc_open(&self) -> bool {
        let r = self.reference_half_beam();
        self.point(0.0) == [-r, 0.0] && self.point(1.0) == [r, 0.0] && self.point(0.5)[1] < 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispersion_relation_round_trips() {
        let (g, radius) = (9.81, 2.0);
        for kr in [0.01, 0.05, 1.0, 5.0, 10.0] {
            let omega = omega_from_kr(kr, radius, g);
            assert_eq!(omega, (kr * g / radius).sqrt());
            assert!((kr_from_omega(omega, radius, g) - kr).abs() <= 1e-14 * kr);
            let k = wavenumber(omega, g);
            assert!((k - wavenumber_from_kr(kr, radius)).abs() <= 1e-14 * k);
        }
        assert_eq!(added_mass_scale(1.0, 3.0), std::f64::consts::PI * 3.0 * 3.0);
        assert_eq!(added_mass_scale(1025.0, 1.0), 1025.0 * std::f64::consts::PI);
    }

    #[test]
    fn hulls_know_their_depth_ratio() {
        let semicircle = Hull::semicircle(1.0).unwrap();
        assert_eq!(semicircle.circle_depth_ratio(), Some(0.0));
        assert_eq!(semicircle.depth_ratio(), 0.0);
        for hr in [1.1, 2.0] {
            let circle = Hull::circle(1.0, hr).unwrap();
            assert_eq!(circle.circle_depth_ratio(), Some(hr));
            assert_eq!(circle.depth_ratio(), hr);
        }
        let two = Hull::circle(2.0, 1.5).unwrap();
        assert_eq!(two.circle_depth_ratio(), Some(1.5));
        let box_xml = r#"<hull name="box" half_beam="1" units="m" version="1">
  <contour closed="true">
    <point x="-1" y="-2"/><point x="-1" y="-4"/><point x="1" y="-4"/><point x="1" y="-2"/>
  </contour>
  <rigid name="sway" kind="sway"/>
</hull>"#;
        let closed = Hull::from_xml_str(box_xml, "box").unwrap();
        assert_eq!(closed.circle_depth_ratio(), None);
        assert_eq!(closed.depth_ratio(), 3.0);
        let open_xml = r#"<hull name="barge" half_beam="1" units="m" version="1">
  <contour closed="false">
    <point x="-1" y="0"/><point x="-1" y="-1"/><point x="1" y="-1"/><point x="1" y="0"/>
  </contour>
  <rigid name="heave" kind="heave"/>
</hull>"#;
        let open = Hull::from_xml_str(open_xml, "barge").unwrap();
        assert_eq!(open.circle_depth_ratio(), None);
        assert_eq!(open.depth_ratio(), 0.0);
    }

    #[test]
    fn hulls_know_their_dof_units() {
        let hull = Hull::semicircle(1.0).unwrap();
        let units = hull.dof_units();
        assert_eq!(units.len(), 9);
        for unit in &units {
            assert_eq!(
                Some(unit),
                DofUnit::builtin(&unit.name).as_ref(),
                "{unit:?}"
            );
        }
        assert_eq!(hull.dof_unit(9), None);
    }
}
