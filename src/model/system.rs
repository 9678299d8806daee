//! The realized system at one rho and g: the equivalent network of [`crate::realize`] scaled
//! to the water density and gravity in use, as a state space.
//!
//! ```text
//! z' = A z + B v,   F = C z + D v,   energy = 1/2 z^T P z,   z = [e (springs); u (aux velocities)]
//! ```
//!
//! Scaling ([`Network::scaled`]): masses and `A_inf` are proportional to rho, springs to
//! rho g, dampers to rho sqrt(g). So at a fixed state `z` the spring columns of `C` (the
//! elongations) scale with rho g, the damper columns and `D` with rho sqrt(g).

use super::{acceptable, ModelError};
use crate::discretize::LinearMap;
use crate::fmu::description::PARAMETERS;
use crate::fmu::resources::Resources;
use crate::network::Network;
use nalgebra::DMatrix;
use std::path::Path;

/// The realized system at one rho and g (immutable).
#[derive(Clone, Debug, PartialEq)]
pub struct RadiationSystem {
    pub(super) dof_names: Vec<String>,
    pub(super) keep_inf_mass: bool,
    pub(super) rho: f64,
    pub(super) g: f64,
    pub(super) added_mass_inf: DMatrix<f64>,
    pub(super) damping_direct: DMatrix<f64>,
    pub(super) a: DMatrix<f64>,
    pub(super) b: DMatrix<f64>,
    pub(super) c: DMatrix<f64>,
    pub(super) d: DMatrix<f64>,
    pub(super) energy_weight: DMatrix<f64>,
    /// Branch input matrix `B_r` (`B = B_r P`), what the stepper discretizes.
    pub(super) b_branch: DMatrix<f64>,
    /// The states of each branch and substructure (independent blocks of `A`).
    pub(super) branch_states: Vec<Vec<usize>>,
    /// The inputs (rows of `branch_projection`) of each block.
    pub(super) branch_inputs: Vec<std::ops::Range<usize>>,
    /// `P` (branch directions as rows, r x n): branch speeds `s = P v`.
    pub(super) branch_projection: DMatrix<f64>,
    /// `C_r` by non-zeros: force along each branch `f_r = C_r z`, so that
    /// `F = P^T f_r + D v` (without the A_inf term).
    pub(super) branch_force: LinearMap,
    /// Number of branch springs: the first `spring_count` states are their elongations
    /// (force columns proportional to rho g), the next as many the aux velocities, then the
    /// substructures' energy coordinates (like velocities, force columns proportional to
    /// rho sqrt(g), see [`crate::network::Substructure`]).
    pub(super) spring_count: usize,
}

/// Refuses a parameter value that is not [`acceptable`] or below its declared minimum.
pub(super) fn check_parameter(name: &'static str, value: f64) -> Result<(), ModelError> {
    let min = PARAMETERS
        .iter()
        .find(|p| p.name == name)
        .map(|p| p.min)
        .unwrap_or(0.0);
    if acceptable(value) && value >= min {
        Ok(())
    } else {
        Err(ModelError::Parameter { name, value })
    }
}

impl RadiationSystem {
    /// Loads `resources/network.xml` and realizes it at rho, g.
    pub fn load(resource_dir: &Path, rho: f64, g: f64) -> Result<Self, ModelError> {
        let resources = Resources::read(resource_dir)?;
        let network = parse_network(&resources.network_xml)?;
        Self::realize(&network, resources.keep_inf_mass, rho, g)
    }

    /// The ONE place that depends on the shape of [`crate::realize`]: scale the reference
    /// network to rho, g and take its state space.
    pub fn realize(
        network: &Network,
        keep_inf_mass: bool,
        rho: f64,
        g: f64,
    ) -> Result<Self, ModelError> {
        check_parameter("rho", rho)?;
        check_parameter("g", g)?;
        let scaled = network.scaled(rho, g);
        let ss = scaled.state_space().map_err(ModelError::Network)?;
        let system = RadiationSystem {
            spring_count: ss.elongation_damping.len(),
            branch_projection: ss.branch_directions.clone(),
            branch_force: LinearMap::new(&ss.c_branch),
            b_branch: ss.b_branch,
            branch_states: ss.branch_states,
            branch_inputs: ss.branch_inputs,
            dof_names: scaled.dof_names.clone(),
            keep_inf_mass,
            rho,
            g,
            added_mass_inf: scaled.added_mass_inf.clone(),
            damping_direct: -&ss.d,
            a: ss.a,
            b: ss.b,
            c: ss.c,
            d: ss.d,
            energy_weight: ss.energy_weight,
        };
        system.check()?;
        Ok(system)
    }

    fn check(&self) -> Result<(), ModelError> {
        let n = self.dof_names.len();
        let ns = self.a.nrows();
        let shapes = [
            ("A", &self.a, ns, ns),
            ("B", &self.b, ns, n),
            ("C", &self.c, n, ns),
            ("D", &self.d, n, n),
            ("P", &self.energy_weight, ns, ns),
            ("A_inf", &self.added_mass_inf, n, n),
            ("B_r", &self.b_branch, ns, self.branch_count()),
        ];
        if n == 0 {
            return Err(ModelError::System("no DOFs".into()));
        }
        let r = self.branch_count();
        if self.branch_projection.ncols() != n
            || self.branch_force.rows() != r
            || self.branch_force.cols() != ns
            || 2 * self.spring_count > ns
        {
            return Err(ModelError::System(format!(
                "the branch maps do not fit {n} DOFs, {r} branches and {ns} states"
            )));
        }
        for (name, m, r, c) in shapes {
            if m.nrows() != r || m.ncols() != c {
                return Err(ModelError::System(format!(
                    "{name} is {}x{}, expected {r}x{c}",
                    m.nrows(),
                    m.ncols()
                )));
            }
            if m.iter().any(|x| !x.is_finite()) {
                return Err(ModelError::System(format!("{name} is not finite")));
            }
        }
        Ok(())
    }

    /// DOF names.
    pub fn dof_names(&self) -> &[String] {
        &self.dof_names
    }
    /// Number of DOFs n.
    pub fn dof_count(&self) -> usize {
        self.dof_names.len()
    }
    /// Number of network states.
    pub fn state_size(&self) -> usize {
        self.a.nrows()
    }
    /// Number of network branches r.
    pub fn branch_count(&self) -> usize {
        self.branch_projection.nrows()
    }
    /// Whether the force includes `-A_inf a`.
    pub fn keep_inf_mass(&self) -> bool {
        self.keep_inf_mass
    }
    /// Water density.
    pub fn rho(&self) -> f64 {
        self.rho
    }
    /// Gravity.
    pub fn g(&self) -> f64 {
        self.g
    }
    /// Infinite-frequency added mass A_inf (n x n).
    pub fn added_mass_inf(&self) -> &DMatrix<f64> {
        &self.added_mass_inf
    }
    /// Direct damping `-D` (n x n).
    pub fn damping_direct(&self) -> &DMatrix<f64> {
        &self.damping_direct
    }
}

/// Parses the network text (glue to [`crate::realize`]).
pub(super) fn parse_network(text: &str) -> Result<Network, ModelError> {
    Network::from_xml_str(text, Resources::NETWORK_FILE).map_err(ModelError::Network)
}

#[cfg(test)]
mod tests {
    use crate::fmu::variables::Quantity;
    use crate::model::tests::seed;

    #[test]
    fn rho_and_g_scale_exactly() {
        // Masses scale with rho; the impulse response in time scales with sqrt(g).
        let mut a = seed(1.0, 1.0);
        let mut b = seed(2.0, 4.0);
        assert!((b.value(Quantity::DampingDirect(0, 0)).unwrap() - 0.9962 * 4.0).abs() < 1e-14);
        a.set_value(Quantity::Velocity(0), 1.0).unwrap();
        b.set_value(Quantity::Velocity(0), 1.0).unwrap();
        // F_b(t) = rho_ratio sqrt(g_ratio) F_a(sqrt(g_ratio) t) for a step velocity.
        a.step(0.0, 1.0).unwrap();
        b.step(0.0, 0.5).unwrap();
        let fa = a.value(Quantity::Force(0)).unwrap();
        let fb = b.value(Quantity::Force(0)).unwrap();
        assert!((fb - 4.0 * fa).abs() < 1e-13, "{fb} vs {fa}");
        assert!(a.set_parameters(-1.0, 1.0).is_err());
        assert!(a.set_parameters(1.0, f64::NAN).is_err());
        assert_eq!(a.state().rho, 1.0);
    }
}
