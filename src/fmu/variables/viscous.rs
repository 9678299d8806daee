//! The viscous damping and current variables ([`Layout::with_viscous`]), declared after all
//! the others so that no value reference moves. With `v0 = w0 + 3n + 2 + n^2` (after the
//! drift slot, whether or not the drift variables exist):
//!
//! | variable | causality | value reference |
//! | --- | --- | --- |
//! | `force_viscous.<d_i>` | output | v0 + i - 1 |
//! | `current.speed` (m/s) | input, start 0 | v0 + n |
//! | `current.heading` (deg) | input, start 0 | v0 + n + 1 |
//! | `damping_quadratic[i]` | parameter | v0 + n + 2 + i - 1 |
//! | `damping_linear[i,j]` | parameter | v0 + 2n + 2 + (i-1) n + j - 1 |
//! | `crossflow.drag_scale` (a ship's strips only) | parameter, start 1 | v0 + 2n + 2 + n^2 |

use super::{drift_base, Causality, Layout, Quantity, Variable, VariablesError};
use nalgebra::{DMatrix, DVector};

/// Offset (from the first per-hull reference) of the viscous variables.
fn viscous_base(n: usize) -> usize {
    drift_base(n) + n + 1
}

/// The offset of a viscous quantity (`None`: not one, or out of range).
pub(super) fn offset(quantity: Quantity, n: usize, crossflow: bool) -> Option<usize> {
    let base = viscous_base(n);
    Some(match quantity {
        Quantity::ForceViscous(i) if i < n => base + i,
        Quantity::CurrentSpeed => base + n,
        Quantity::CurrentHeading => base + n + 1,
        Quantity::DampingQuadratic(i) if i < n => base + n + 2 + i,
        Quantity::DampingLinear(i, j) if i < n && j < n => base + 2 * n + 2 + i * n + j,
        Quantity::CrossflowDragScale if crossflow => base + 2 * n + 2 + n * n,
        _ => return None,
    })
}

/// The viscous quantity at offset `k` (`None`: not one).
pub(super) fn quantity(k: usize, n: usize, crossflow: bool) -> Option<Quantity> {
    let r = k.checked_sub(viscous_base(n))?;
    Some(if r < n {
        Quantity::ForceViscous(r)
    } else if r == n {
        Quantity::CurrentSpeed
    } else if r == n + 1 {
        Quantity::CurrentHeading
    } else if r < 2 * n + 2 {
        Quantity::DampingQuadratic(r - n - 2)
    } else if r < 2 * n + 2 + n * n {
        let r = r - 2 * n - 2;
        Quantity::DampingLinear(r / n, r % n)
    } else if crossflow && r == 2 * n + 2 + n * n {
        Quantity::CrossflowDragScale
    } else {
        return None;
    })
}

impl Layout {
    /// This layout with the variables of an FMU packed with viscous damping, after all the
    /// others: `force_viscous.<dof>` (outputs, in `force`), `current.speed` and
    /// `current.heading` (inputs, start 0), `damping_quadratic[i]` and
    /// `damping_linear[i,j]` (fixed parameters whose start values are the packed
    /// coefficients `quadratic` and `linear`, n and n x n).
    pub fn with_viscous(
        mut self,
        linear: &DMatrix<f64>,
        quadratic: &DVector<f64>,
    ) -> Result<Layout, VariablesError> {
        let n = self.dofs.len();
        if linear.shape() != (n, n) || quadratic.len() != n {
            return Err(VariablesError::Xml(format!(
                "viscous damping: {}x{} linear and {} quadratic coefficients for {n} DOFs",
                linear.nrows(),
                linear.ncols(),
                quadratic.len()
            )));
        }
        if self.viscous {
            return Ok(self);
        }
        self.viscous = true;
        let extent = self.extent;
        let mut vars = Vec::new();
        for (i, d) in self.dofs.iter().enumerate() {
            vars.push(Variable {
                name: format!("force_viscous.{}", d.name),
                value_reference: 0,
                quantity: Quantity::ForceViscous(i),
                causality: Causality::Output,
                unit: extent.force_unit(d.length_exponent),
                description: format!(
                    "Viscous force in DOF {}, -damping_linear v_r - damping_quadratic |v_r| v_r \
                     with v_r the velocity relative to the current (in force)",
                    d.name
                ),
                start: None,
                integer: false,
            });
        }
        let current = [
            (
                "current.speed",
                Quantity::CurrentSpeed,
                "m/s",
                "Speed of the current (docs/CURRENT.md)",
            ),
            (
                "current.heading",
                Quantity::CurrentHeading,
                "deg",
                "Heading of the current: 0 towards +x (a section: along its sway axis)",
            ),
        ];
        for (name, quantity, unit, description) in current {
            vars.push(Variable {
                name: name.into(),
                value_reference: 0,
                quantity,
                causality: Causality::Input,
                unit,
                description: description.into(),
                start: Some(0.0),
                integer: false,
            });
        }
        for (i, d) in self.dofs.iter().enumerate() {
            vars.push(Variable {
                name: format!("damping_quadratic[{}]", i + 1),
                value_reference: 0,
                quantity: Quantity::DampingQuadratic(i),
                causality: Causality::Parameter,
                unit: extent.quadratic_damping_unit(d.length_exponent),
                description: format!(
                    "Quadratic viscous damping of DOF {} (>= 0): force -damping_quadratic |v_r| v_r",
                    d.name
                ),
                start: Some(quadratic[i]),
                integer: false,
            });
        }
        for i in 0..n {
            for j in 0..n {
                let sum = self.dofs[i].length_exponent + self.dofs[j].length_exponent;
                let (di, dj) = (&self.dofs[i].name, &self.dofs[j].name);
                vars.push(Variable {
                    name: format!("damping_linear[{},{}]", i + 1, j + 1),
                    value_reference: 0,
                    quantity: Quantity::DampingLinear(i, j),
                    causality: Causality::Parameter,
                    unit: extent.damping_unit(sum),
                    description: format!(
                        "Linear viscous damping, {di}-{dj} (symmetric part positive \
                         semidefinite): force.{di} gets -damping_linear v_r.{dj}"
                    ),
                    start: Some(linear[(i, j)]),
                    integer: false,
                });
            }
        }
        for v in &mut vars {
            v.value_reference = self
                .value_reference(v.quantity)
                .ok_or(VariablesError::MissingValueReference)?;
        }
        self.variables.extend(vars);
        Ok(self)
    }

    /// This layout with `crossflow.drag_scale` (fixed parameter, start 1), after the viscous
    /// variables ([`Layout::with_viscous`] first): a ship packed with its cross-flow strips.
    pub fn with_crossflow(mut self) -> Result<Layout, VariablesError> {
        if !self.viscous {
            return Err(VariablesError::Xml(
                "crossflow.drag_scale needs the viscous variables".into(),
            ));
        }
        if self.crossflow {
            return Ok(self);
        }
        self.crossflow = true;
        let quantity = Quantity::CrossflowDragScale;
        self.variables.push(Variable {
            name: "crossflow.drag_scale".into(),
            value_reference: self
                .value_reference(quantity)
                .ok_or(VariablesError::MissingValueReference)?,
            quantity,
            causality: Causality::Parameter,
            unit: "1",
            description: "Scale of the ship's cross-flow strips' drag (>= 0; 0 switches them \
                          off; docs/CURRENT.md)"
                .into(),
            start: Some(1.0),
            integer: false,
        });
        Ok(self)
    }

    /// Whether `crossflow.drag_scale` exists ([`Layout::with_crossflow`]).
    pub fn has_crossflow(&self) -> bool {
        self.crossflow
    }

    /// Whether the viscous variables exist ([`Layout::with_viscous`]).
    pub fn has_viscous(&self) -> bool {
        self.viscous
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmu::units::DofUnit;

    fn dofs() -> Vec<DofUnit> {
        ["sway", "heave", "roll"]
            .iter()
            .map(|n| DofUnit::builtin(n).unwrap())
            .collect()
    }

    #[test]
    fn viscous_variables_come_after_all_others_and_round_trip() {
        for drift in [false, true] {
            let mut plain = Layout::new(dofs(), true).unwrap();
            if drift {
                plain = plain.with_drift().unwrap();
            }
            let linear = DMatrix::from_fn(3, 3, |i, j| (i * 3 + j) as f64);
            let quadratic = DVector::from_vec(vec![1.0, 2.0, 3.0]);
            let viscous = plain.clone().with_viscous(&linear, &quadratic).unwrap();
            assert!(viscous.has_viscous() && !plain.has_viscous());
            // Every existing reference stays; the new ones are above them all.
            let top = plain.variables().iter().map(|v| v.value_reference).max();
            for v in plain.variables() {
                assert_eq!(viscous.value_reference(v.quantity), Some(v.value_reference));
            }
            let mut seen = std::collections::BTreeSet::new();
            for v in viscous.variables() {
                assert!(seen.insert(v.value_reference), "{}", v.name);
                assert_eq!(viscous.quantity(v.value_reference), Some(v.quantity));
            }
            let added = &viscous.variables()[plain.variables().len()..];
            assert_eq!(added.len(), 3 + 2 + 3 + 9);
            assert!(added.iter().all(|v| Some(v.value_reference) > top));
            let last = added.iter().map(|v| v.value_reference).max().unwrap();
            assert_eq!(viscous.quantity(last + 1), None);
            let start = |name: &str| added.iter().find(|v| v.name == name).unwrap().start;
            assert_eq!(start("damping_linear[2,3]"), Some(5.0));
            assert_eq!(start("damping_quadratic[3]"), Some(3.0));
            let unit = |name: &str| added.iter().find(|v| v.name == name).unwrap().unit;
            assert_eq!(unit("damping_quadratic[1]"), "kg/m2");
            assert_eq!(unit("damping_quadratic[3]"), "kg.m");
            assert_eq!(unit("damping_linear[3,3]"), "N.s");
        }
        let wrong = Layout::new(dofs(), false)
            .unwrap()
            .with_viscous(&DMatrix::zeros(2, 2), &DVector::zeros(3));
        assert!(wrong.is_err());
    }

    #[test]
    fn both_descriptions_declare_the_variables_and_the_extra_unit() {
        use crate::fmu::description::{DescriptionInfo, FIXED_XML};
        let info = DescriptionInfo {
            model_identifier: "Viscous".into(),
            guid: "{viscous}".into(),
            ..Default::default()
        };
        let plain = Layout::new(dofs(), false).unwrap();
        let viscous = plain
            .clone()
            .with_viscous(&DMatrix::identity(3, 3), &DVector::from_element(3, 2.0))
            .unwrap();
        for fmi3 in [false, true] {
            let write = |layout: &Layout| match fmi3 {
                false => layout.model_description(FIXED_XML, &info).unwrap(),
                true => layout.model_description_fmi3(FIXED_XML, &info).unwrap(),
            };
            let (without, with) = (write(&plain), write(&viscous));
            assert!(!without.contains("kg/m2") && !without.contains("current.speed"));
            let root = crate::xml::parse(&with).unwrap();
            let units: Vec<_> = root
                .descendants()
                .filter(|e| e.name == "Unit")
                .filter_map(|e| e.attribute("name"))
                .collect();
            assert_eq!(units.iter().filter(|u| **u == "kg/m2").count(), 1);
            for name in [
                "current.heading",
                "force_viscous.roll",
                "damping_linear[3,3]",
            ] {
                assert!(with.contains(&format!("name=\"{name}\"")), "{name}");
            }
        }
    }
}
