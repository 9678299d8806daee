//! The coupled network from PSD-weighted groups: one branch per significant eigenvalue of
//! each weight, then pruning; the order is the number of distinct chain dynamics left.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::blocks::Reduced;
use super::groups::GroupSet;
use crate::identify::problem::{branch_rate, Problem};
use crate::identify::single_dof::chain_dynamic_mass;
use crate::network::{Branch, Network, NetworkForm, Stage};

impl Problem {
    /// Branches from PSD weights (in the reduced subspace): one per significant eigenvalue,
    /// in physical units.
    pub(super) fn coupled_network(
        &self,
        reduced: &Reduced,
        groups: &GroupSet,
        weights: &[DMatrix<f64>],
        tolerance: f64,
    ) -> Network {
        let n = self.n();
        let drop_below = 1e-4 * tolerance.min(1.0);
        let w_ref = self.omega_ref;
        let mut branches = Vec::new();
        for (p, w) in weights.iter().enumerate() {
            let chain = groups.normalized_stages(p);
            let peak = self
                .nu
                .iter()
                .map(|&v| groups.shape(p, Complex64::new(0.0, v)).norm())
                .fold(0.0, f64::max);
            let eigen = crate::numerics::symmetric_eigen(w);
            for r in 0..w.nrows() {
                let lambda = eigen.eigenvalues[r];
                if lambda.is_nan() || lambda * peak <= drop_below {
                    continue;
                }
                let v = &reduced.basis * eigen.eigenvectors.column(r);
                let mut d = DVector::from_fn(n, |i, _| v[i] * self.scale[i].sqrt());
                let norm2 = d.norm_squared();
                d /= norm2.sqrt();
                let factor = lambda * norm2;
                branches.push(Branch {
                    direction: d,
                    stages: chain
                        .iter()
                        .map(|st| Stage {
                            mass: factor * st.mass,
                            stiffness: factor * st.stiffness * w_ref * w_ref,
                            damping: factor * st.damping * w_ref,
                        })
                        .collect(),
                });
            }
        }
        Network {
            substructures: Vec::new(),
            dof_names: self.dof_names.clone(),
            added_mass_inf: self.added_mass_inf.clone(),
            branches,
            rho: self.rho,
            g: self.g,
            form: NetworkForm::Coupled,
        }
    }

    /// A coupled network without branches (`A_inf` only).
    pub(super) fn coupled_network_empty(&self) -> Network {
        Network {
            substructures: Vec::new(),
            dof_names: self.dof_names.clone(),
            added_mass_inf: self.added_mass_inf.clone(),
            branches: Vec::new(),
            rho: self.rho,
            g: self.g,
            form: NetworkForm::Coupled,
        }
    }

    /// Drops the branches that do not matter: first every over-fitted one (rates beyond
    /// [`FASTEST_RATE_OVER_BAND`], no information in the band), then, in order of their
    /// largest normalized contribution `max_band |G_b| max_i d_i^2 / s_i`, each one whose
    /// removal keeps the error within the tolerance (or, if it is not met, does not raise it).
    pub(super) fn prune(&self, mut network: Network, tolerance: f64) -> Network {
        let limit = self.rate_limit();
        network.branches.retain(|b| branch_rate(b) <= limit);
        let error = self.max_relative_error(&network);
        let allowed = error.max(tolerance);
        let contribution = |b: &Branch| {
            let reach = (0..self.n())
                .map(|i| b.direction[i] * b.direction[i] / self.scale[i])
                .fold(0.0, f64::max);
            let peak = self
                .omega
                .iter()
                .map(|&w| {
                    chain_dynamic_mass(std::slice::from_ref(&b.stages), Complex64::new(0.0, w))
                        .norm()
                })
                .fold(0.0, f64::max);
            reach * peak
        };
        let mut ranked: Vec<(f64, Branch)> = network
            .branches
            .drain(..)
            .map(|b| (contribution(&b), b))
            .collect();
        ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
        network.branches = ranked.into_iter().map(|(_, b)| b).collect();
        let mut k = 0;
        while k < network.branches.len() {
            let branch = network.branches.remove(k);
            if self.max_relative_error(&network) <= allowed {
                continue;
            }
            network.branches.insert(k, branch);
            k += 1;
        }
        network
    }
}

/// Number of distinct chain dynamics among a coupled network's branches (branches of one
/// group have proportional stage values): the order of the coupled form.
pub(super) fn distinct_dynamics(network: &Network) -> usize {
    let shape = |b: &Branch| -> Vec<f64> {
        let m = b.stages.first().map_or(1.0, |s| s.mass);
        b.stages
            .iter()
            .flat_map(|s| [s.mass / m, s.stiffness / m, s.damping / m])
            .collect()
    };
    let same = |a: &[f64], b: &[f64]| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() <= 1e-9 * x.abs().max(y.abs()))
    };
    let mut seen: Vec<Vec<f64>> = Vec::new();
    for branch in &network.branches {
        let s = shape(branch);
        if !seen.iter().any(|t| same(t, &s)) {
            seen.push(s);
        }
    }
    seen.len()
}
