//! Outputs of the component at its current state, their time derivatives and their partial
//! derivatives with respect to the knowns (inputs, rho, g).
//!
//! ```text
//! F      = C z + D v  [- A_inf a]
//! power  = -F . v
//! energy = 1/2 z^T P z  [+ 1/2 v^T A_inf v]
//! ```
//!
//! At a fixed state every output and calculated parameter is a sum of monomials in rho and g
//! ([`crate::network::Network::scaled`]): masses and `A_inf` scale with rho, springs with rho g, dampers
//! with rho sqrt(g). So `d/drho = value / rho` for all of them, and
//! `dF/dg = (F_spring + F_damper / 2) / g` with `F_spring = C_e z_e` (the elongation columns)
//! and `F_damper = C_u z_u + D v`; `d energy/dg = energy_spring / g` with
//! `energy_spring = 1/2 z_e^T P_ee z_e`; `d A_inf/dg = 0`, `d damping_direct/dg =
//! damping_direct / (2 g)`.

use super::{Model, ModelError, ModelState, RadiationSystem};
use crate::fmu::variables::Quantity;
use nalgebra::DVector;

/// The network's force `C z + D v [- A_inf a]` at state `s` into `force` (`branch_forces`:
/// scratch, one entry per branch).
pub(super) fn radiation_force(
    sys: &RadiationSystem,
    s: &ModelState,
    branch_forces: &mut DVector<f64>,
    force: &mut DVector<f64>,
) {
    sys.branch_force
        .apply(s.network.as_slice(), branch_forces.as_mut_slice());
    force.gemv(1.0, &sys.d, &s.velocity, 0.0);
    force.gemv_tr(1.0, &sys.branch_projection, branch_forces, 1.0);
    if sys.keep_inf_mass {
        force.gemv(-1.0, &sys.added_mass_inf, &s.acceleration, 1.0);
    }
    // -0.0 + 0.0 = +0.0: a force at rest reads 0, not -0.
    force.add_scalar_mut(0.0);
}

/// The stored energy `1/2 z^T P z [+ 1/2 v^T A_inf v]` at state `s` (`work`: scratch, one
/// entry per network state).
pub(super) fn stored_energy(sys: &RadiationSystem, s: &ModelState, work: &mut DVector<f64>) -> f64 {
    work.gemv(1.0, &sys.energy_weight, &s.network, 0.0);
    let mut energy = 0.5 * s.network.dot(work);
    if sys.keep_inf_mass {
        energy += 0.5 * s.velocity.dot(&(&sys.added_mass_inf * &s.velocity));
    }
    energy
}

/// Outputs computed from the state.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Outputs {
    pub(super) force: DVector<f64>,
    /// The radiation part of `force` (the network's force).
    pub(super) radiation: DVector<f64>,
    /// The exciting force of the waves (zero in calm water).
    pub(super) excitation: DVector<f64>,
    /// The drift force of the waves (zero in calm water or without drift).
    pub(super) drift: DVector<f64>,
    /// The viscous force (zero without viscous damping).
    pub(super) viscous: DVector<f64>,
    /// Wave elevation at x = 0.
    pub(super) elevation: f64,
    pub(super) power: f64,
    pub(super) energy: Option<f64>,
}

impl Outputs {
    /// Zero outputs for n DOFs (not yet computed).
    pub(super) fn zeros(n: usize) -> Outputs {
        Outputs {
            force: DVector::zeros(n),
            radiation: DVector::zeros(n),
            excitation: DVector::zeros(n),
            drift: DVector::zeros(n),
            viscous: DVector::zeros(n),
            elevation: 0.0,
            power: 0.0,
            energy: None,
        }
    }
}

impl Model {
    pub(super) fn refresh(&mut self) {
        if self.outputs_valid {
            return;
        }
        let s = &self.state;
        let out = &mut self.outputs;
        radiation_force(&self.system, s, &mut self.branch_forces, &mut out.force);
        out.power = -out.force.dot(&s.velocity) + 0.0;
        out.radiation.copy_from(&out.force);
        match &mut self.sea {
            Some((sea, scratch)) => {
                out.elevation = sea.evaluate(s.time, scratch, out.excitation.as_mut_slice());
                // Calm water leaves the force untouched (bit for bit).
                out.force += &out.excitation;
                if sea.drift_mode() != crate::waves::DriftMode::Off {
                    sea.evaluate_drift(s.time, scratch, out.drift.as_mut_slice());
                    out.force += &out.drift;
                } else {
                    out.drift.fill(0.0);
                }
            }
            None => {
                out.excitation.fill(0.0);
                out.drift.fill(0.0);
                out.elevation = 0.0;
            }
        }
        if let Some(viscous) = &mut self.viscous {
            // Zero coefficients and no current add +-0: the force stays bit for bit.
            viscous.force(&s.velocity, s.rho, &mut out.viscous);
            out.force += &out.viscous;
        }
        out.energy = None;
        self.outputs_valid = true;
    }

    /// The stored energy, computed on demand (it costs a state-size squared product).
    fn energy(&mut self) -> f64 {
        self.refresh();
        if let Some(e) = self.outputs.energy {
            return e;
        }
        let energy = stored_energy(&self.system, &self.state, &mut self.work);
        self.outputs.energy = Some(energy);
        energy
    }

    /// Reads any variable; a value that is not finite is [`ModelError::NotFinite`].
    pub fn value(&mut self, quantity: Quantity) -> Result<f64, ModelError> {
        let n = self.dof_count();
        let v = match quantity {
            Quantity::Rho => self.state.rho,
            Quantity::G => self.state.g,
            Quantity::Depth => self.depth().metres(),
            Quantity::Wave(p) => self.wave_parameter(p),
            Quantity::Velocity(i) if i < n => self.state.velocity[i],
            Quantity::Acceleration(i) if i < n && self.system.keep_inf_mass => {
                self.state.acceleration[i]
            }
            Quantity::AddedMassInf(i, j) if i < n && j < n => self.system.added_mass_inf[(i, j)],
            Quantity::DampingDirect(i, j) if i < n && j < n => self.system.damping_direct[(i, j)],
            Quantity::Force(i) if i < n => {
                self.refresh();
                self.outputs.force[i]
            }
            Quantity::Power => {
                self.refresh();
                self.outputs.power
            }
            Quantity::Energy => self.energy(),
            Quantity::ForceRadiation(i) if i < n => {
                self.refresh();
                self.outputs.radiation[i]
            }
            Quantity::ForceExcitation(i) if i < n => {
                self.refresh();
                self.outputs.excitation[i]
            }
            Quantity::WaveElevation => {
                self.refresh();
                self.outputs.elevation
            }
            Quantity::ForceDrift(i) if i < n && self.drift.is_some() => {
                self.refresh();
                self.outputs.drift[i]
            }
            Quantity::StiffnessHydrostatic(i, j) if i < n && j < n => {
                self.stiffness_hydrostatic()[(i, j)]
            }
            Quantity::ForceViscous(i) if i < n && self.viscous.is_some() => {
                self.refresh();
                self.outputs.viscous[i]
            }
            Quantity::CurrentSpeed
            | Quantity::CurrentHeading
            | Quantity::DampingLinear(..)
            | Quantity::DampingQuadratic(_)
            | Quantity::CrossflowDragScale => match &self.viscous {
                Some(v) => match quantity {
                    Quantity::CrossflowDragScale => match v.crossflow() {
                        Some(c) => c.scale(),
                        None => {
                            return Err(ModelError::Variable(format!(
                                "{quantity:?} does not exist"
                            )))
                        }
                    },
                    Quantity::CurrentSpeed => v.speed,
                    Quantity::CurrentHeading => v.heading,
                    Quantity::DampingLinear(i, j) if i < n && j < n => v.linear[(i, j)],
                    Quantity::DampingQuadratic(i) if i < n => v.quadratic[i],
                    other => return Err(ModelError::Variable(format!("{other:?} does not exist"))),
                },
                None => return Err(ModelError::Variable(format!("{quantity:?} does not exist"))),
            },
            other => return Err(ModelError::Variable(format!("{other:?} does not exist"))),
        };
        Model::finite(|| self.variable_name(quantity), v)
    }

    /// Network states: the length of the state vector `z` the component steps (spring
    /// elongations, auxiliary velocities, substructure coordinates; the hull's positions and
    /// velocities are the master's, not among them). The network's
    /// [`crate::network::Network::state_count`].
    pub fn network_states(&self) -> usize {
        self.state.network.len()
    }

    /// All forces (n entries), unchecked: where the inputs overflow an entry is not finite
    /// ([`Model::value`] refuses it).
    pub fn forces(&mut self) -> &DVector<f64> {
        self.refresh();
        &self.outputs.force
    }

    /// First time derivative of an output at the current time:
    /// `dF/dt = C (A z + B v) + D v' [- A_inf a']`, `d power/dt = -(F' . v + F . v')`,
    /// `d energy/dt` from the network equations; in waves the exciting force and the elevation
    /// add their exact rates ([`crate::waves::Sea::evaluate_rate`]). Not finite:
    /// [`ModelError::NotFinite`].
    pub fn output_derivative(&mut self, quantity: Quantity) -> Result<f64, ModelError> {
        let rate = self.output_rate(quantity)?;
        Model::finite(
            || format!("the time derivative of {}", self.variable_name(quantity)),
            rate,
        )
    }

    fn output_rate(&mut self, quantity: Quantity) -> Result<f64, ModelError> {
        let n = self.dof_count();
        self.refresh();
        let s = &self.state;
        let sys = &self.system;
        let zdot = &sys.a * &s.network + &sys.b * &s.velocity;
        let mut fdot = &sys.c * &zdot + &sys.d * &s.velocity_derivative;
        if sys.keep_inf_mass {
            fdot -= &sys.added_mass_inf * &s.acceleration_derivative;
        }
        // The sea's own rates at the current time (exact: the harmonic sum's derivative).
        let mut excitation_rate = DVector::zeros(n);
        let mut drift_rate = DVector::zeros(n);
        let mut drift_active = false;
        let elevation_rate = match &self.sea {
            Some((sea, _)) => {
                if sea.drift_mode() != crate::waves::DriftMode::Off {
                    drift_active = true;
                    sea.evaluate_drift_rate(s.time, drift_rate.as_mut_slice());
                }
                sea.evaluate_rate(s.time, excitation_rate.as_mut_slice())
            }
            None => 0.0,
        };
        // The viscous force's rate with the current held: dF/dv v'.
        let viscous_rate = match &self.viscous {
            Some(v) => v.jacobian(&s.velocity, s.rho) * &s.velocity_derivative,
            None => DVector::zeros(n),
        };
        match quantity {
            Quantity::Force(i) if i < n && self.viscous.is_some() => {
                Ok(fdot[i] + excitation_rate[i] + drift_rate[i] + viscous_rate[i])
            }
            Quantity::ForceViscous(i) if i < n && self.viscous.is_some() => Ok(viscous_rate[i]),
            Quantity::Force(i) if i < n && drift_active => {
                Ok(fdot[i] + excitation_rate[i] + drift_rate[i])
            }
            Quantity::Force(i) if i < n => Ok(fdot[i] + excitation_rate[i]),
            Quantity::ForceDrift(i) if i < n && self.drift.is_some() => Ok(drift_rate[i]),
            Quantity::ForceExcitation(i) if i < n => Ok(excitation_rate[i]),
            Quantity::WaveElevation => Ok(elevation_rate),
            Quantity::ForceRadiation(i) if i < n => Ok(fdot[i]),
            Quantity::Power => {
                Ok(-(fdot.dot(&s.velocity) + self.outputs.radiation.dot(&s.velocity_derivative)))
            }
            Quantity::Energy => {
                // d/dt 1/2 z^T P z = 1/2 (z^T P zdot + zdot^T P z)
                let p = &sys.energy_weight;
                let mut e = 0.5 * (s.network.dot(&(p * &zdot)) + zdot.dot(&(p * &s.network)));
                if sys.keep_inf_mass {
                    let m = &sys.added_mass_inf;
                    e += 0.5
                        * (s.velocity.dot(&(m * &s.velocity_derivative))
                            + s.velocity_derivative.dot(&(m * &s.velocity)));
                }
                Ok(e)
            }
            other => Err(ModelError::Variable(format!("{other:?} is not an output"))),
        }
    }

    /// Partial derivative of an output or a calculated parameter with respect to a known (an
    /// input, rho or g) at the current state. Exact: the outputs are quadratic in the inputs
    /// and sums of monomials in rho and g (see the module docs). Not finite:
    /// [`ModelError::NotFinite`].
    pub fn partial_derivative(
        &mut self,
        of: Quantity,
        with_respect_to: Quantity,
    ) -> Result<f64, ModelError> {
        let derivative = self.partial(of, with_respect_to)?;
        Model::finite(
            || {
                format!(
                    "d {} / d {}",
                    self.variable_name(of),
                    self.variable_name(with_respect_to)
                )
            },
            derivative,
        )
    }

    fn partial(&mut self, of: Quantity, with_respect_to: Quantity) -> Result<f64, ModelError> {
        let n = self.dof_count();
        let keep = self.system.keep_inf_mass;
        if matches!(with_respect_to, Quantity::Rho | Quantity::G) {
            return self.parameter_derivative(of, with_respect_to);
        }
        self.refresh();
        if let Some(value) = self.viscous_partial(of, with_respect_to)? {
            return Ok(value);
        }
        let d = &self.system.damping_direct;
        let m = &self.system.added_mass_inf;
        let v = &self.state.velocity;
        let value = match (of, with_respect_to) {
            // The exciting force is the force's only part that does not depend on the inputs.
            (Quantity::Force(i) | Quantity::ForceRadiation(i), Quantity::Velocity(j))
                if i < n && j < n =>
            {
                -d[(i, j)]
            }
            (Quantity::Force(i) | Quantity::ForceRadiation(i), Quantity::Acceleration(j))
                if i < n && j < n && keep =>
            {
                -m[(i, j)]
            }
            // The waves depend on time only.
            (Quantity::ForceExcitation(i), Quantity::Velocity(j)) if i < n && j < n => 0.0,
            (Quantity::ForceExcitation(i), Quantity::Acceleration(j)) if i < n && j < n && keep => {
                0.0
            }
            (Quantity::ForceDrift(i), Quantity::Velocity(j))
                if i < n && j < n && self.drift.is_some() =>
            {
                0.0
            }
            (Quantity::ForceDrift(i), Quantity::Acceleration(j))
                if i < n && j < n && keep && self.drift.is_some() =>
            {
                0.0
            }
            (Quantity::WaveElevation, Quantity::Velocity(j)) if j < n => 0.0,
            (Quantity::WaveElevation, Quantity::Acceleration(j)) if j < n && keep => 0.0,
            // power = -F . v: d/dv_j = -F_j - sum_i v_i dF_i/dv_j
            (Quantity::Power, Quantity::Velocity(j)) if j < n => {
                -self.outputs.radiation[j] + d.column(j).dot(v)
            }
            (Quantity::Power, Quantity::Acceleration(j)) if j < n && keep => m.column(j).dot(v),
            (Quantity::Energy, Quantity::Velocity(j)) if j < n => {
                if keep {
                    0.5 * (m.row(j).transpose().dot(v) + m.column(j).dot(v))
                } else {
                    0.0
                }
            }
            (Quantity::Energy, Quantity::Acceleration(j)) if j < n && keep => 0.0,
            // Calculated parameters depend on rho and g only.
            (
                Quantity::AddedMassInf(i, k) | Quantity::DampingDirect(i, k),
                Quantity::Velocity(j),
            ) if i < n && k < n && j < n => 0.0,
            (
                Quantity::AddedMassInf(i, k) | Quantity::DampingDirect(i, k),
                Quantity::Acceleration(j),
            ) if i < n && k < n && j < n && keep => 0.0,
            (of, wrt) => {
                return Err(ModelError::Variable(format!(
                    "no partial derivative of {of:?} with respect to {wrt:?}"
                )))
            }
        };
        Ok(value)
    }

    /// `d of / d rho` or `d of / d g` at the current state: the output or calculated
    /// parameter `of` split by its powers of rho and g (module docs).
    fn parameter_derivative(
        &mut self,
        of: Quantity,
        parameter: Quantity,
    ) -> Result<f64, ModelError> {
        let n = self.dof_count();
        if matches!(of, Quantity::ForceViscous(i) if i < n && self.viscous.is_some()) {
            // The viscous coefficients are the user's: they depend on neither; a ship's
            // cross-flow strips scale with rho.
            return Ok(match parameter {
                Quantity::Rho => self.crossflow_per_rho(of).unwrap_or(0.0),
                _ => 0.0,
            });
        }
        let exists = match of {
            Quantity::Force(i) | Quantity::ForceRadiation(i) => i < n,
            Quantity::AddedMassInf(i, j) | Quantity::DampingDirect(i, j) => i < n && j < n,
            Quantity::Power | Quantity::Energy => true,
            _ => false,
        };
        if !exists {
            return Err(ModelError::Variable(format!(
                "no partial derivative of {of:?} with respect to {parameter:?}"
            )));
        }
        if parameter == Quantity::G && self.sea.is_some() && matches!(of, Quantity::Force(_)) {
            // The exciting force depends on g through X(kR = omega^2 R / g): not provided.
            return Err(ModelError::Variable(format!(
                "{of:?}: the derivative with respect to g is not provided in waves"
            )));
        }
        let mut value = self.value(of)?;
        if let Quantity::Force(i) = of {
            value -= self.outputs.viscous[i];
        }
        if parameter == Quantity::Rho {
            // Every term is proportional to rho (a ship's cross-flow strips too).
            return Ok(match self.crossflow_per_rho(of) {
                Some(strips) => value / self.system.rho + strips,
                None => value / self.system.rho,
            });
        }
        let g = self.system.g;
        let derivative = match of {
            Quantity::AddedMassInf(..) => 0.0,
            Quantity::DampingDirect(..) => 0.5 * value / g,
            Quantity::Force(i) | Quantity::ForceRadiation(i) => self.force_g_derivative()[i],
            Quantity::Power => -self.force_g_derivative().dot(&self.state.velocity),
            _ => self.spring_energy() / g,
        };
        Ok(derivative)
    }

    /// `dF/dg = (F_spring + F_damper / 2) / g` at the current state: `F_spring = C_e z_e`
    /// (proportional to rho g), `F_damper = C_u z_u + D v` (to rho sqrt(g)); `-A_inf a`
    /// does not depend on g.
    fn force_g_derivative(&self) -> DVector<f64> {
        let sys = &self.system;
        let z = &self.state.network;
        let springs = sys.spring_count;
        let velocities = sys.state_size() - springs;
        let spring = sys.c.columns(0, springs) * z.rows(0, springs);
        let damper = sys.c.columns(springs, velocities) * z.rows(springs, velocities)
            + &sys.d * &self.state.velocity;
        (spring + damper * 0.5) / sys.g
    }

    /// Energy in the springs, `1/2 z_e^T P_ee z_e` (proportional to rho g).
    fn spring_energy(&self) -> f64 {
        let springs = self.system.spring_count;
        let z = self.state.network.rows(0, springs);
        let weight = self.system.energy_weight.view((0, 0), (springs, springs));
        0.5 * z.dot(&(weight * z))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::tests::{
        model, seed, two_dof_substructure_network, SEED_NETWORK, TWO_DOF_NETWORK,
    };

    /// The networks of the output tests: branches only, and branches with a substructure.
    fn networks() -> [String; 2] {
        [TWO_DOF_NETWORK.to_string(), two_dof_substructure_network()]
    }

    #[test]
    fn energy_balance_holds_and_dissipation_is_positive() {
        // Work done on the water (trapezoid of power with a smooth input over small steps)
        // = stored energy + dissipated >= stored energy.
        for network in networks() {
            let mut model = model(&network, false);
            model.set_parameters(1025.0, 9.81).unwrap();
            let h = 1e-3;
            let mut work = 0.0;
            let mut t = 0.0;
            let input = |t: f64| [(1.3 * t).sin() * (-0.1 * t).exp(), 0.4 * (2.1 * t).cos()];
            let mut previous_power = None;
            for k in 0..20_000 {
                let u = input(k as f64 * h);
                model.set_value(Quantity::Velocity(0), u[0]).unwrap();
                model.set_value(Quantity::Velocity(1), u[1]).unwrap();
                let p = model.value(Quantity::Power).unwrap();
                if let Some(p0) = previous_power {
                    work += 0.5 * h * (p0 + p);
                }
                previous_power = Some(p);
                model.step(t, h).unwrap();
                t = model.time();
            }
            let energy = model.value(Quantity::Energy).unwrap();
            assert!(energy > 0.0);
            let dissipated = work - energy;
            // Trapezoid error with ZOH inputs is O(h) relative; 1 % margin.
            assert!(dissipated > 0.01 * work, "work {work}, energy {energy}");
        }
    }

    #[test]
    fn energy_rate_matches_power_minus_dissipation_per_step() {
        // With the input held, over one short step: dE ~= power h - c (dv)^2 h <= power h.
        let mut model = seed(1.0, 1.0);
        model.set_value(Quantity::Velocity(0), 1.0).unwrap();
        let mut t = 0.0;
        for _ in 0..100 {
            let e0 = model.value(Quantity::Energy).unwrap();
            let p = model.value(Quantity::Power).unwrap();
            let de_dt = model.output_derivative(Quantity::Energy).unwrap();
            model.step(t, 1e-4).unwrap();
            t = model.time();
            let e1 = model.value(Quantity::Energy).unwrap();
            assert!(de_dt <= p + 1e-12, "dE/dt {de_dt} > power {p}");
            // finite difference of energy matches its derivative (O(h) error)
            assert!(((e1 - e0) / 1e-4 - de_dt).abs() < 1e-3 * (1.0 + de_dt.abs()));
        }
    }

    #[test]
    fn force_has_direct_feedthrough_and_keep_inf_mass_adds_inertia() {
        let mut model = seed(1.0, 1.0);
        model.set_value(Quantity::Velocity(0), 2.0).unwrap();
        // At rest network: F = D v = -c1 v.
        assert_eq!(model.value(Quantity::Force(0)).unwrap(), -0.9962 * 2.0);
        assert_eq!(model.value(Quantity::DampingDirect(0, 0)).unwrap(), 0.9962);
        assert!(model.set_value(Quantity::Acceleration(0), 1.0).is_err());
        let mut keep = crate::model::tests::model(SEED_NETWORK, true);
        keep.set_parameters(1.0, 1.0).unwrap();
        keep.set_value(Quantity::Acceleration(0), 3.0).unwrap();
        assert!((keep.value(Quantity::Force(0)).unwrap() + 0.1153 * 3.0).abs() < 1e-15);
        keep.set_value(Quantity::Velocity(0), 2.0).unwrap();
        let e = keep.value(Quantity::Energy).unwrap();
        assert!((e - 0.5 * 0.1153 * 4.0).abs() < 1e-15);
    }

    #[test]
    fn output_derivative_matches_finite_difference() {
        for network in networks() {
            let mut m = model(&network, false);
            m.set_value(Quantity::Velocity(0), 0.5).unwrap();
            m.set_value(Quantity::Velocity(1), -0.2).unwrap();
            m.step(0.0, 0.3).unwrap();
            m.set_input_derivative(Quantity::Velocity(0), 0.4).unwrap();
            let q = [Quantity::Force(0), Quantity::Force(1), Quantity::Power];
            let d: Vec<f64> = q.iter().map(|q| m.output_derivative(*q).unwrap()).collect();
            let before: Vec<f64> = q.iter().map(|q| m.value(*q).unwrap()).collect();
            let h = 1e-6;
            m.step(0.3, h).unwrap();
            for (k, q) in q.iter().enumerate() {
                let fd = (m.value(*q).unwrap() - before[k]) / h;
                // O(h) truncation relative to the derivative scale.
                assert!(
                    (fd - d[k]).abs() < 1e-3 * (1.0 + d[k].abs()),
                    "{q:?}: {fd} vs {}",
                    d[k]
                );
            }
        }
    }

    #[test]
    fn partial_derivatives_match_finite_differences() {
        for network in networks() {
            let mut m = model(&network, true);
            m.set_value(Quantity::Velocity(0), 0.5).unwrap();
            m.set_value(Quantity::Velocity(1), -0.2).unwrap();
            m.set_value(Quantity::Acceleration(1), 0.7).unwrap();
            m.step(0.0, 0.3).unwrap();
            let outs = [
                Quantity::Force(0),
                Quantity::Force(1),
                Quantity::Power,
                Quantity::Energy,
            ];
            let ins = [
                Quantity::Velocity(0),
                Quantity::Velocity(1),
                Quantity::Acceleration(0),
                Quantity::Acceleration(1),
            ];
            for inp in ins {
                let x0 = m.value(inp).unwrap();
                let eps = 1e-6;
                m.set_value(inp, x0 + eps).unwrap();
                let plus: Vec<f64> = outs.iter().map(|o| m.value(*o).unwrap()).collect();
                m.set_value(inp, x0 - eps).unwrap();
                let minus: Vec<f64> = outs.iter().map(|o| m.value(*o).unwrap()).collect();
                m.set_value(inp, x0).unwrap();
                for (k, o) in outs.iter().enumerate() {
                    let fd = (plus[k] - minus[k]) / (2.0 * eps);
                    let exact = m.partial_derivative(*o, inp).unwrap();
                    // central difference of a quadratic: exact to rounding, |value| 1e-16 /
                    // eps = 1e-10 |value|
                    let rounding = 1e-9 * plus[k].abs().max(minus[k].abs());
                    assert!(
                        (fd - exact).abs() < 1e-8 * (1.0 + exact.abs()) + rounding,
                        "{o:?}/{inp:?}: {fd} vs {exact}"
                    );
                }
            }
        }
    }

    #[test]
    fn derivatives_with_respect_to_rho_and_g_match_finite_differences() {
        // Central differences of the outputs after set_parameters(rho (1 +- 1e-6), g) and
        // (rho, g (1 +- 1e-6)) at a fixed non-zero state, SI units. The outputs are linear in
        // rho and smooth in g, so the difference is exact to rounding: |value| / p * 1e-10
        // (p = rho or g). Tolerance 1e-7 (|exact| + |value| / p).
        for (keep, network) in [false, true]
            .into_iter()
            .flat_map(|k| networks().map(|n| (k, n)))
        {
            let mut m = model(&network, keep);
            m.set_parameters(1025.0, 9.81).unwrap();
            m.set_value(Quantity::Velocity(0), 0.5).unwrap();
            m.set_value(Quantity::Velocity(1), -0.2).unwrap();
            m.step(0.0, 0.3).unwrap();
            m.set_value(Quantity::Velocity(0), 0.8).unwrap();
            if keep {
                m.set_value(Quantity::Acceleration(1), 0.7).unwrap();
            }
            assert!(m.state().network.amax() > 0.0);
            let mut unknowns = vec![
                Quantity::Force(0),
                Quantity::Force(1),
                Quantity::Power,
                Quantity::Energy,
            ];
            for i in 0..2 {
                for j in 0..2 {
                    unknowns.push(Quantity::AddedMassInf(i, j));
                    unknowns.push(Quantity::DampingDirect(i, j));
                }
            }
            for parameter in [Quantity::Rho, Quantity::G] {
                let p0 = m.value(parameter).unwrap();
                let values: Vec<f64> = unknowns.iter().map(|q| m.value(*q).unwrap()).collect();
                let exact: Vec<f64> = unknowns
                    .iter()
                    .map(|q| m.partial_derivative(*q, parameter).unwrap())
                    .collect();
                let eps = 1e-6 * p0;
                let mut at = |p: f64| {
                    m.set_value(parameter, p).unwrap();
                    let out: Vec<f64> = unknowns.iter().map(|q| m.value(*q).unwrap()).collect();
                    out
                };
                let plus = at(p0 + eps);
                let minus = at(p0 - eps);
                at(p0);
                for (k, q) in unknowns.iter().enumerate() {
                    let fd = (plus[k] - minus[k]) / (2.0 * eps);
                    let tolerance = 1e-7 * (exact[k].abs() + values[k].abs() / p0);
                    assert!(
                        (fd - exact[k]).abs() <= tolerance,
                        "d {q:?} / d {parameter:?} (keep {keep}): {fd} vs {}",
                        exact[k]
                    );
                }
                // The state and the values are back where they were.
                let again: Vec<f64> = unknowns.iter().map(|q| m.value(*q).unwrap()).collect();
                assert_eq!(again, values);
            }
            // g enters the force: its derivative is not just a multiple of rho's.
            let by_g = m
                .partial_derivative(Quantity::Force(0), Quantity::G)
                .unwrap();
            assert!(by_g != 0.0);
            assert_eq!(
                m.partial_derivative(Quantity::AddedMassInf(0, 0), Quantity::G)
                    .unwrap(),
                0.0
            );
            assert_eq!(
                m.partial_derivative(Quantity::DampingDirect(0, 1), Quantity::Velocity(0))
                    .unwrap(),
                0.0
            );
            assert!(m.partial_derivative(Quantity::Rho, Quantity::G).is_err());
            assert!(m
                .partial_derivative(Quantity::Velocity(0), Quantity::Rho)
                .is_err());
            assert!(m
                .partial_derivative(Quantity::Force(2), Quantity::Rho)
                .is_err());
        }
    }
}
