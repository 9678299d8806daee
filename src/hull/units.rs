//! What a hull states about its own units: its centre depth `H/R` and the unit of each
//! generalized DOF (docs/DESIGN-NOTES.md, "Units of generalized DOFs").

use super::{Contour, DofKind, Hull, RigidKind};
use crate::fmu::DofUnit;

impl Hull {
    /// Centre depth over half-beam of a circular contour (the built-in hulls and `<circle>`
    /// files): 0 for the semicircle, `H/R` for the submerged circle. `None` for a polyline
    /// contour. The sweep table records it (`# H/R:`).
    pub fn circle_depth_ratio(&self) -> Option<f64> {
        match &self.contour {
            Contour::Arc { depth_ratio, .. } => Some(*depth_ratio),
            Contour::Lewis(_) | Contour::Polyline { .. } => None,
        }
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
}

#[cfg(test)]
mod tests {
    use super::*;

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
        // The given H/R, not one recomputed from the depth in metres.
        let three = Hull::circle(3.0, 1.1).unwrap();
        assert_eq!(three.circle_depth_ratio(), Some(1.1));
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
