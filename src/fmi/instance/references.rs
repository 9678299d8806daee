//! The value references a master sets and gets every step, resolved once at instantiation.
//!
//! The velocities, the accelerations (with `keep_inf_mass`) and the forces of the hull are
//! contiguous ranges of value references ([`crate::fmu::Layout`]): `first + k` is DOF k. A
//! get or set call whose references all lie in these ranges, with values that pass every
//! check of the general path, takes the direct path: one range test per reference, the
//! values written into (read from) the model's vectors. Any other call (another variable, a
//! value the general path would refuse, a force that is not finite, arrays of different
//! lengths) goes the general way, which then gives its result and its messages. The direct
//! path skips lookups, never a check, and changes nothing when it does not apply.

use super::Instance;
use crate::fmu::description::PARAMETERS;
use crate::fmu::{Layout, Quantity};
use crate::model::acceptable;

/// The value references `first .. first + count`, DOF k at `first + k`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Span {
    first: u32,
    count: u32,
}

impl Span {
    /// The DOF of `vr`, if it lies in the span.
    fn dof(self, vr: u32) -> Option<usize> {
        let k = vr.wrapping_sub(self.first);
        (k < self.count).then_some(k as usize)
    }
}

/// The per-step value references of one instance (a span is absent where the layout has no
/// such variables).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct StepReferences {
    velocity: Option<Span>,
    acceleration: Option<Span>,
    force: Option<Span>,
}

impl StepReferences {
    /// The spans of `layout`, each checked reference by reference: every one names the
    /// quantity of its DOF and none is a parameter with declared limits.
    pub(super) fn resolve(layout: &Layout) -> StepReferences {
        let n = layout.dof_count();
        let span = |quantity: fn(usize) -> Quantity| {
            let first = layout.value_reference(quantity(0))?;
            let count = u32::try_from(n).ok()?;
            let consistent = (0..count).all(|k| {
                first.checked_add(k).is_some_and(|vr| {
                    layout.quantity(vr) == Some(quantity(k as usize))
                        && PARAMETERS.iter().all(|p| p.value_reference != vr)
                })
            });
            consistent.then_some(Span { first, count })
        };
        StepReferences {
            velocity: span(Quantity::Velocity),
            acceleration: span(Quantity::Acceleration),
            force: span(Quantity::Force),
        }
    }

    /// The input `vr` names, if it is a velocity or an acceleration.
    fn input(&self, vr: u32) -> Option<Quantity> {
        if let Some(k) = self.velocity.and_then(|s| s.dof(vr)) {
            return Some(Quantity::Velocity(k));
        }
        self.acceleration
            .and_then(|s| s.dof(vr))
            .map(Quantity::Acceleration)
    }

    /// Whether every reference is an input (velocity or acceleration).
    pub(super) fn all_inputs(&self, vr: &[u32]) -> bool {
        vr.iter().all(|r| self.input(*r).is_some())
    }

    /// The DOF of the force `vr` names, if it is one.
    fn force(&self, vr: u32) -> Option<usize> {
        self.force.and_then(|s| s.dof(vr))
    }
}

impl Instance {
    /// fmi2SetReal's direct path: when every reference is an input and every value
    /// [`acceptable`] (as the general path requires), sets them and returns `Ok(true)`;
    /// otherwise changes nothing and returns `Ok(false)`.
    pub(super) fn set_inputs_directly(
        &mut self,
        vr: &[u32],
        values: &[f64],
    ) -> Result<bool, String> {
        let references = self.step_references;
        let applies = vr.len() == values.len()
            && vr
                .iter()
                .zip(values)
                .all(|(r, x)| references.input(*r).is_some() && acceptable(*x));
        if !applies {
            return Ok(false);
        }
        for (r, x) in vr.iter().zip(values) {
            if let Some(input) = references.input(*r) {
                self.model.set_value(input, *x).map_err(|e| e.to_string())?;
            }
        }
        Ok(true)
    }

    /// fmi2GetReal's direct path: when every reference is a force and every force is
    /// finite (as the general path requires), writes them and returns true; otherwise
    /// writes nothing and returns false.
    pub(super) fn get_forces_directly(&mut self, vr: &[u32], values: &mut [f64]) -> bool {
        let references = self.step_references;
        if vr.len() != values.len() || !vr.iter().all(|r| references.force(*r).is_some()) {
            return false;
        }
        let forces = self.model.forces();
        let finite = vr
            .iter()
            .all(|r| references.force(*r).is_some_and(|i| forces[i].is_finite()));
        if !finite {
            return false;
        }
        for (r, out) in vr.iter().zip(values.iter_mut()) {
            if let Some(i) = references.force(*r) {
                *out = forces[i];
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmu::description::FIRST_PER_HULL_REFERENCE;
    use crate::fmu::DofUnit;

    fn layout(n: usize, keep_inf_mass: bool) -> Layout {
        let dofs = (0..n)
            .map(|i| DofUnit::new(&format!("d{i}"), 0, false))
            .collect();
        Layout::new(dofs, keep_inf_mass).unwrap()
    }

    #[test]
    fn the_spans_name_what_the_layout_names() {
        for (n, keep) in [(1, false), (3, true), (9, false), (9, true)] {
            let layout = layout(n, keep);
            let references = StepReferences::resolve(&layout);
            assert_eq!(references.acceleration.is_some(), keep);
            let last = layout.variables().iter().map(|v| v.value_reference).max();
            for vr in 0..last.unwrap() + 3 {
                let expected = layout.quantity(vr);
                let input = references.input(vr);
                let force = references.force(vr).map(Quantity::Force);
                match expected {
                    Some(q @ (Quantity::Velocity(_) | Quantity::Acceleration(_))) => {
                        assert_eq!(input, Some(q), "{vr}");
                        assert_eq!(force, None, "{vr}");
                    }
                    Some(q @ Quantity::Force(_)) => {
                        assert_eq!((input, force), (None, Some(q)), "{vr}");
                    }
                    _ => assert_eq!((input, force), (None, None), "{vr}"),
                }
            }
        }
        let references = StepReferences::resolve(&layout(9, false));
        assert_eq!(references.force(FIRST_PER_HULL_REFERENCE + 9), Some(0));
        assert_eq!(references.force(FIRST_PER_HULL_REFERENCE + 17), Some(8));
        assert_eq!(references.force(FIRST_PER_HULL_REFERENCE + 18), None);
        assert!(references.all_inputs(&[FIRST_PER_HULL_REFERENCE + 8]));
        assert!(!references.all_inputs(&[FIRST_PER_HULL_REFERENCE + 9]));
    }
}
