//! Coupled form (n DOFs): shared chain dynamics in groups with PSD weight matrices,
//! `H = A_inf + sum_p W_p g_p(s)`, fitted in the subspace the normalized data span, block by
//! block when the data has invariant blocks, orders 1, 2, ... per block (see
//! [`crate::identify`] for the paths and the equations).
//!
//! - [`blocks`]: reduced subspace, commutant and invariant blocks.
//! - [`groups`]: the group dynamics (`GroupSet`).
//! - [`weights`]: least-squares and PSD weights of fixed groups.
//! - [`variable_projection`]: one-stage groups by variable projection.
//! - [`dictionary`]: two-stage band-pass groups from a dictionary.
//! - [`refine`]: joint minimax refinement of dynamics and weight factors.
//! - [`branches`]: branches of the network from the weights, pruning, order.

pub(in crate::identify) mod blocks;
mod branches;
mod dictionary;
mod groups;
mod refine;
#[cfg(test)]
mod tests;
mod variable_projection;
mod weights;

use nalgebra::DMatrix;
use num_complex::Complex64;

use super::problem::{keep_best, Problem};
use super::{FitParams, IdentifyError};
use crate::network::{Network, Stage};
use blocks::Reduced;
use branches::distinct_dynamics;
use groups::GroupSet;

/// Rounds of tightening the blocks' tolerance.
const BLOCK_ROUNDS: usize = 4;

/// Warm-start memory of the coupled fit across orders and chain lengths.
struct CoupledState {
    /// Whether the variable-projection path is still tried.
    variable_projection: bool,
    scope: Scope,
    bank: Option<Vec<Vec<Stage>>>,
    solutions: Vec<GroupSet>,
    /// Dictionary groups (parameters, PSD weight), most significant first.
    dictionary: Option<Vec<(Vec<f64>, DMatrix<f64>)>>,
}

impl CoupledState {
    fn new(scope: Scope) -> Self {
        CoupledState {
            variable_projection: true,
            scope,
            bank: None,
            solutions: Vec::new(),
            dictionary: None,
        }
    }

    fn solution(&self, stages: usize) -> Option<&GroupSet> {
        self.solutions.iter().find(|g| g.stages == stages)
    }

    fn store(&mut self, groups: GroupSet) {
        self.solutions.retain(|g| g.stages != groups.stages);
        self.solutions.push(groups);
    }
}

/// Where a coupled fit works: the whole data subspace, or one invariant block of it.
#[derive(Clone)]
struct Scope {
    reduced: Reduced,
    /// The whole subspace: errors against the full data, as reported. A block: errors
    /// against the block's share of the target, `basis T_b basis^T`.
    whole: bool,
}

impl Problem {
    /// Coupled form: the whole data subspace at once, or its invariant blocks one by one,
    /// their branches then joined (see the module docs). Returns the order (groups, summed
    /// over the blocks), the network and the LM iterations.
    pub(super) fn fit_coupled_network(
        &self,
        params: &FitParams,
        tolerance: f64,
    ) -> Result<(usize, Network, usize), IdentifyError> {
        let none =
            || IdentifyError::InvalidParams("no order could be fitted within max_order".into());
        let reduced = self.reduce();
        let blocks = reduced.split(tolerance);
        if blocks.len() < 2 {
            let mut state = CoupledState::new(Scope {
                reduced,
                whole: true,
            });
            let (best, iterations) = self.fit_coupled_scope(&mut state, params, tolerance, 1);
            let (_, _, network) = best.ok_or_else(none)?;
            let network = self.prune(network, tolerance);
            return Ok((distinct_dynamics(&network), network, iterations));
        }
        // The blocks' errors add up in the DOFs they share: fit every block to the
        // tolerance, then tighten the blocks' tolerance until the joined network meets it.
        let mut states: Vec<CoupledState> = blocks
            .into_iter()
            .map(|reduced| {
                CoupledState::new(Scope {
                    reduced,
                    whole: false,
                })
            })
            .collect();
        let mut fits: Vec<Option<(f64, usize, Network)>> = vec![None; states.len()];
        let mut iterations = 0;
        let mut block_tolerance = tolerance;
        let mut best: Option<(f64, usize, Network)> = None;
        for _ in 0..BLOCK_ROUNDS {
            let mut all_met = true;
            for (state, fit) in states.iter_mut().zip(fits.iter_mut()) {
                let first_order = match fit {
                    Some((error, _, _)) if *error <= block_tolerance => continue,
                    Some((_, order, _)) => *order,
                    None => 1,
                };
                let (result, its) =
                    self.fit_coupled_scope(state, params, block_tolerance, first_order);
                iterations += its;
                let result = result.ok_or_else(none)?;
                all_met &= result.0 <= block_tolerance;
                *fit = Some(result);
            }
            let network = Network {
                branches: fits
                    .iter()
                    .flatten()
                    .flat_map(|(_, _, net)| net.branches.clone())
                    .collect(),
                ..self.coupled_network_empty()
            };
            let error = self.max_relative_error(&network);
            // The order is counted after pruning.
            keep_best(&mut best, (error, 0, network));
            if error <= tolerance || !all_met {
                break;
            }
            block_tolerance *= (0.95 * tolerance / error).max(0.5);
        }
        let (_, _, network) = best.ok_or_else(none)?;
        let network = self.prune(network, tolerance);
        Ok((distinct_dynamics(&network), network, iterations))
    }

    /// Largest normalized error of a network in a coupled fit's scope: against the full data
    /// for the whole subspace, against the block's share of the target for a block.
    fn scope_error(&self, scope: &Scope, net: &Network) -> f64 {
        if scope.whole {
            return self.max_relative_error(net);
        }
        let n = self.n();
        let basis = scope.reduced.basis.map(|x| Complex64::new(x, 0.0));
        let root = self.scale.map(f64::sqrt);
        let mut worst: f64 = 0.0;
        for (k, &w) in self.omega.iter().enumerate() {
            let h = net.added_mass_tf(w);
            let share = &basis * &scope.reduced.target[k] * basis.transpose();
            for j in 0..n {
                for i in 0..n {
                    let model = (h[(i, j)] - self.added_mass_inf[(i, j)]) / (root[i] * root[j]);
                    worst = worst.max((model - share[(i, j)]).norm());
                }
            }
        }
        worst
    }

    /// Coupled form: orders 1, 2, ... of groups in `state`'s scope; the first order that meets
    /// `tolerance` there, else the most accurate. Returns (error, order, network) and the LM
    /// iterations.
    fn fit_coupled_scope(
        &self,
        state: &mut CoupledState,
        params: &FitParams,
        tolerance: f64,
        first_order: usize,
    ) -> (Option<(f64, usize, Network)>, usize) {
        let last = params.order.unwrap_or(params.max_order);
        let stage_options = match params.coupled_stages {
            Some(stages) => stages..=stages,
            None => 1..=1,
        };
        let mut iterations = 0;
        let mut best: Option<(f64, usize, Network)> = None;
        for order in first_order.min(last)..=last {
            let candidate = params.order.is_none() || order == last;
            let mut networks = Vec::new();
            let mut dictionary_error = f64::INFINITY;
            if matches!(params.coupled_stages, None | Some(2)) && candidate {
                let (network, its) = self.fit_coupled_dictionary(order, state, params, tolerance);
                iterations += its;
                if let Some(network) = network {
                    dictionary_error = self.scope_error(&state.scope, &network);
                    networks.push(network);
                }
            }
            if state.variable_projection {
                for stages in stage_options.clone() {
                    let (network, its) =
                        self.fit_coupled(order, stages, state, params, tolerance, candidate);
                    iterations += its;
                    if let Some(network) = network {
                        let error = self.scope_error(&state.scope, &network);
                        networks.push(network);
                        // Far behind the dictionary fit: not worth its time further up.
                        if error > 3.0 * dictionary_error {
                            state.variable_projection = false;
                        }
                        if error <= tolerance {
                            break;
                        }
                    }
                }
            }
            if !candidate {
                continue;
            }
            // Of this order's networks: the one with the fewest auxiliary masses that meets
            // the tolerance, else the most accurate.
            let mut met: Option<(usize, f64, Network)> = None;
            for network in networks {
                let err = self.scope_error(&state.scope, &network);
                if err <= tolerance {
                    let aux = network.aux_dof_count();
                    if !matches!(&met, Some((a, _, _)) if *a <= aux) {
                        met = Some((aux, err, network));
                    }
                } else {
                    keep_best(&mut best, (err, order, network));
                }
            }
            if let Some((_, err, network)) = met {
                best = Some((err, order, network));
                break;
            }
        }
        (best, iterations)
    }
}
