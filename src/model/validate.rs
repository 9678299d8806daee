//! The rules a state must meet to replace the component's state ([`Model::set_state`], and
//! [`Model::deserialize`] for state bytes). Restored bytes are untrusted input: their
//! checksum catches accidents, not a changed field with the checksum recomputed. So every
//! field is checked for what it means, and a state is refused with the field named:
//!
//! - dimensions: `z` has the network's states, `v`, `v'`, `a`, `a'` one entry per DOF;
//! - `rho`, `g`: as fmi2SetReal checks them (finite, at least the declared minimum, at most
//!   [`MAX_INPUT`]), and the network realized there finite (also `stiffness_hydrostatic`);
//! - inputs `v`, `v'`, `a`, `a'`: finite and within [`MAX_INPUT`], as fmi2SetReal and
//!   fmi2SetRealInputDerivatives check them; `a`, `a'` zero unless the FMU keeps `A_inf`
//!   (only then do they exist);
//! - network state `z`: finite; for state bytes also small enough that force, power and
//!   energy at the state are finite (`check_outputs`). They are computed once: no
//!   bound on `z` alone would do for every network (`C z` and `z^T P z` scale with the
//!   network's coefficients). A state saved in memory skips this rule: one reached by this
//!   component's own calls has overflowing outputs only through inputs accepted one by one
//!   (rho = g = v = 1e100), whose reads fail already, and it must restore as it was;
//! - time: `time`, `time_anchor`, `start_time` finite; `last_step` finite, >= 0, and > 0 once
//!   steps are counted; the count at most [`MAX_STEPS_SINCE_ANCHOR`] (where it is exact as
//!   an f64); and `time = time_anchor + steps last_step` within [`TIME_TOLERANCE`], the
//!   stepper's own formula, so that the next step continues from `time`: a count of 2^64 - 1
//!   used to wrap to 0 (time back to the anchor), one of 2^53 to jump to `2^53 h`;
//! - stop time: none, or finite, not before the start time, and `time` not past it (within
//!   the tolerance);
//! - wave parameters: valid ([`crate::waves::WaveParams::validate`]).

use super::outputs::{radiation_force, stored_energy};
use super::system::check_parameter;
use super::{
    acceptable, Model, ModelError, ModelState, RadiationSystem, MAX_INPUT, MAX_STEPS_SINCE_ANCHOR,
    TIME_TOLERANCE,
};
use crate::fmu::variables::Quantity;
use nalgebra::DVector;

fn refuse<T>(message: String) -> Result<T, ModelError> {
    Err(ModelError::State(message))
}

impl Model {
    /// Checks `state` against the rules of the module docs. Returns the system at the
    /// state's rho and g when they differ from the current ones (realized for the check).
    pub(super) fn check_state(
        &self,
        state: &ModelState,
    ) -> Result<Option<RadiationSystem>, ModelError> {
        let n = self.dof_count();
        let names = [
            "network state",
            "velocity",
            "velocity derivative",
            "acceleration",
            "acceleration derivative",
        ];
        let sizes = [self.system.state_size(), n, n, n, n];
        for ((name, v), size) in names.into_iter().zip(state.vectors()).zip(sizes) {
            if v.len() != size {
                return refuse(format!("{name} has {} entries, expected {size}", v.len()));
            }
        }
        for (name, value) in [("rho", state.rho), ("g", state.g)] {
            check_parameter(name, value).map_err(|e| ModelError::State(e.to_string()))?;
        }
        self.check_times(state)?;
        self.check_inputs(state)?;
        for (name, value) in ["current.speed", "current.heading"]
            .iter()
            .zip(state.current)
        {
            if !value.is_finite() {
                return refuse(format!("{name} is {value}"));
            }
        }
        if let Some(i) = state.network.iter().position(|x| !x.is_finite()) {
            return refuse(format!(
                "network state z[{}] is {}",
                i + 1,
                state.network[i]
            ));
        }
        state
            .waves
            .validate()
            .map_err(|e| ModelError::State(format!("wave parameters: {e}")))?;
        if state.waves.drift != crate::waves::DriftMode::Off && self.drift.is_none() {
            return refuse(format!(
                "wave.drift = {}: this FMU has no drift table",
                state.waves.drift.code()
            ));
        }
        // A sea is built with a heading of the table; calm water keeps any heading (the
        // declared start value 0 may be missing from a ship's table).
        let sea = state.waves.kind != crate::waves::WaveKind::Calm;
        if let Some(table) = self.excitation.as_ref().filter(|_| sea) {
            if table.heading_index(state.waves.heading).is_none() {
                return refuse(format!(
                    "wave heading {} deg is not one of the excitation table's {:?}",
                    state.waves.heading,
                    table.headings()
                ));
            }
        }
        let realized = if (state.rho, state.g) == (self.system.rho, self.system.g) {
            None
        } else {
            let system = self.realize_at(state.rho, state.g).map_err(|e| {
                ModelError::State(format!("rho = {:e}, g = {:e}: {e}", state.rho, state.g))
            })?;
            Some(system)
        };
        Ok(realized)
    }

    /// The time fields (module docs).
    fn check_times(&self, s: &ModelState) -> Result<(), ModelError> {
        let times = [
            ("time", s.time),
            ("time anchor", s.time_anchor),
            ("start time", s.start_time),
            ("last step", s.last_step),
        ];
        if let Some((name, value)) = times.iter().find(|(_, x)| !x.is_finite()) {
            return refuse(format!("{name} is {value}"));
        }
        let k = s.steps_since_anchor;
        if k > MAX_STEPS_SINCE_ANCHOR {
            return refuse(format!(
                "{k} steps since the time anchor: more than 2^53, where the count stops being \
                 exact as an f64"
            ));
        }
        if s.last_step < 0.0 || (k > 0 && s.last_step == 0.0) {
            return refuse(format!(
                "last step {} after {k} steps: a step is > 0",
                s.last_step
            ));
        }
        let expected = s.time_anchor + k as f64 * s.last_step;
        let mismatch = (s.time - expected).abs();
        if mismatch.is_nan() || mismatch > TIME_TOLERANCE * s.time.abs().max(s.last_step) {
            return refuse(format!(
                "time {} is not time anchor {} + {k} steps x last step {} = {expected}",
                s.time, s.time_anchor, s.last_step
            ));
        }
        if let Some(stop) = s.stop_time {
            if !stop.is_finite() || stop < s.start_time {
                return refuse(format!(
                    "stop time {stop} is not finite or before the start time {}",
                    s.start_time
                ));
            }
            if s.time > stop + TIME_TOLERANCE * stop.abs().max(s.last_step) {
                return refuse(format!("time {} is past the stop time {stop}", s.time));
            }
        }
        Ok(())
    }

    /// The inputs and their derivatives (module docs).
    fn check_inputs(&self, s: &ModelState) -> Result<(), ModelError> {
        let keep = self.system.keep_inf_mass;
        for (i, (&v, &dv)) in s.velocity.iter().zip(&s.velocity_derivative).enumerate() {
            let name = self.variable_name(Quantity::Velocity(i));
            for (what, x) in [(name.clone(), v), (format!("derivative of {name}"), dv)] {
                if !acceptable(x) {
                    return refuse(format!(
                        "{what} = {x:e} is not finite or exceeds {MAX_INPUT:e} in magnitude"
                    ));
                }
            }
        }
        for (i, (&a, &da)) in s
            .acceleration
            .iter()
            .zip(&s.acceleration_derivative)
            .enumerate()
        {
            let dof = &self.dof_names()[i];
            if !keep && (a != 0.0 || da != 0.0) {
                return refuse(format!(
                    "acceleration of {dof} = {a:e} (derivative {da:e}): this FMU has no \
                     acceleration inputs"
                ));
            }
            if !acceptable(a) || !acceptable(da) {
                return refuse(format!(
                    "acceleration of {dof} = {a:e} (derivative {da:e}) is not finite or \
                     exceeds {MAX_INPUT:e} in magnitude"
                ));
            }
        }
        Ok(())
    }

    /// Force, power and energy at the state, with `system` (at the state's rho and g):
    /// finite.
    pub(super) fn check_outputs(
        &self,
        s: &ModelState,
        system: &RadiationSystem,
    ) -> Result<(), ModelError> {
        let n = self.dof_count();
        let mut force = DVector::zeros(n);
        let mut branch_forces = DVector::zeros(system.branch_count());
        radiation_force(system, s, &mut branch_forces, &mut force);
        let power = -force.dot(&s.velocity);
        let mut work = DVector::zeros(system.state_size());
        let energy = stored_energy(system, s, &mut work);
        let named = (0..n)
            .map(|i| (Quantity::Force(i), force[i]))
            .chain([(Quantity::Power, power), (Quantity::Energy, energy)]);
        for (quantity, value) in named {
            if !value.is_finite() {
                return refuse(format!(
                    "{} = {value} at this state: its values are too large",
                    self.variable_name(quantity)
                ));
            }
        }
        Ok(())
    }
}
