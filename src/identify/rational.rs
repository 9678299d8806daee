//! The rational path of the coupled form: passive vector fitting per invariant block
//! ([`super::vector_fitting::passive_block_vector_fit`]), each part acting on its own motions
//! realized as a mechanical substructure ([`super::synthesis`]), the order chosen against the
//! tolerance.
//!
//! Order `k` is the number of poles per invariant block, a conjugate pair counted twice:
//! `k` odd gives `(k - 1) / 2` pairs and one real pole; `k` even gives `k / 2` pairs, and
//! also `k / 2 - 1` pairs with two real poles (real poles follow the logarithmic low-frequency
//! added mass of heave-like motions), the better of the two kept. The first order whose
//! network meets the tolerance is returned, else the one with the smallest error.
//!
//! Physical bounds: a candidate whose poles are not all within [`POLE_RANGE`] of the band
//! (below its bottom over `POLE_RANGE`, above its top times it) is refused: such a pole is a
//! spurious slow mode (a mass that acts as a spring to the ground for minutes) or a stiff one
//! that carries no information.

use super::problem::Problem;
use super::synthesis::synthesize;
use super::vector_fitting::{passive_block_vector_fit, RationalFit, VectorFitParams};
use super::{FitParams, FrequencyResponse, IdentifyError};
use crate::network::Network;

/// How far outside the band a pole modulus may lie (factor).
pub const POLE_RANGE: f64 = 30.0;

/// The pole layouts `(pairs, real)` of order `k` (module docs).
fn layouts(k: usize) -> Vec<(usize, usize)> {
    if k % 2 == 1 {
        vec![((k - 1) / 2, 1)]
    } else if k >= 4 {
        vec![(k / 2, 0), (k / 2 - 1, 2)]
    } else {
        vec![(k / 2, 0)]
    }
}

/// A candidate of one layout: its network and largest normalized error, or why it failed.
fn candidate(
    problem: &Problem,
    data: &FrequencyResponse,
    params: &VectorFitParams,
) -> Result<(f64, Network, RationalFit), String> {
    let (fit, enforcements) = passive_block_vector_fit(data, params).map_err(|e| e.to_string())?;
    if let Some(e) = enforcements.iter().find(|e| !e.passive) {
        return Err(format!(
            "no passive residues after {} rounds ({} constraint frequencies, {} iterations)",
            e.rounds, e.samples, e.iterations
        ));
    }
    let (lo, hi) = (problem.omega[0], problem.omega[problem.omega.len() - 1]);
    if let Some(p) = fit
        .poles
        .iter()
        .find(|p| p.norm() < lo / POLE_RANGE || p.norm() > hi * POLE_RANGE)
    {
        return Err(format!(
            "a pole at {:.3e} rad/s lies outside the band ({lo:.3e}, {hi:.3e}) rad/s by more \
             than a factor {POLE_RANGE}",
            p.norm()
        ));
    }
    let substructures = independent_parts(&fit)
        .iter()
        .map(|part| synthesize(part).map(|(sub, _)| sub))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let network = Network::from_substructures(
        problem.dof_names.clone(),
        problem.added_mass_inf.clone(),
        substructures,
        problem.rho,
        problem.g,
    );
    network.validate().map_err(|e| e.to_string())?;
    Ok((problem.max_relative_error(&network), network, fit))
}

/// Residues whose column spaces overlap less than this (relative) act on orthogonal motions.
const ORTHOGONAL_RESIDUES: f64 = 1e-9;

/// The fit split into parts whose residues act on mutually orthogonal subspaces of the DOFs
/// (for a mirror-symmetric hull: its symmetric and antisymmetric motions), the connected
/// groups of poles with `|R_i^H R_j| > ORTHOGONAL_RESIDUES |R_i| |R_j|`. Each part becomes its
/// own substructure: the sum is the same transfer function, and a step costs the parts' sizes
/// squared instead of the whole's.
fn independent_parts(fit: &RationalFit) -> Vec<RationalFit> {
    let count = fit.poles.len();
    let norms: Vec<f64> = fit.residues.iter().map(|r| r.norm()).collect();
    let mut group: Vec<usize> = (0..count).collect();
    let root = |group: &[usize], mut i: usize| {
        while group[i] != i {
            i = group[i];
        }
        i
    };
    for i in 0..count {
        for j in i + 1..count {
            let overlap = (fit.residues[i].adjoint() * &fit.residues[j]).norm();
            if overlap > ORTHOGONAL_RESIDUES * norms[i] * norms[j] {
                let (a, b) = (root(&group, i), root(&group, j));
                group[a.max(b)] = a.min(b);
            }
        }
    }
    let mut parts: Vec<(usize, RationalFit)> = Vec::new();
    for i in 0..count {
        let r = root(&group, i);
        let at = match parts.iter().position(|(k, _)| *k == r) {
            Some(at) => at,
            None => {
                parts.push((
                    r,
                    RationalFit {
                        poles: Vec::new(),
                        residues: Vec::new(),
                        dof_scales: fit.dof_scales.clone(),
                        max_error: fit.max_error,
                    },
                ));
                parts.len() - 1
            }
        };
        parts[at].1.poles.push(fit.poles[i]);
        parts[at].1.residues.push(fit.residues[i].clone());
    }
    parts.into_iter().map(|(_, part)| part).collect()
}

/// What the rational path found: the order and network chosen, vector fitting iterations,
/// and notes (orders that failed and why, the order chosen when none met the tolerance).
pub(super) struct RationalOutcome {
    pub order: usize,
    pub network: Network,
    pub iterations: usize,
    pub notes: Vec<String>,
}

/// Fits the coupled form by the rational path (module docs). Orders are tried upwards; the
/// first one whose network meets the tolerance is returned. A network is never replaced by a
/// worse one: if no order meets the tolerance, the one with the smallest error is returned.
/// Orders above the data's resolution (at least one point more than twice the poles per
/// block, per entry) are not tried.
pub(super) fn fit_rational(
    problem: &Problem,
    data: &FrequencyResponse,
    params: &FitParams,
    tolerance: f64,
) -> Result<RationalOutcome, IdentifyError> {
    // The data with the symmetric PSD A_inf the network gets.
    let mut data = data.clone();
    data.added_mass_inf = problem.added_mass_inf.clone();
    let band = (problem.omega[0], problem.omega[problem.omega.len() - 1]);
    let points = problem.omega.len();
    let orders: Vec<usize> = match params.order {
        Some(k) => vec![k],
        None => (1..=params.max_order.min(points.saturating_sub(1)).max(1)).collect(),
    };
    let mut best: Option<(f64, usize, Network)> = None;
    let mut iterations = 0;
    let mut failures: Vec<String> = Vec::new();
    let mut tried = Vec::new();
    for k in orders {
        for (pairs, real) in layouts(k) {
            let vf = VectorFitParams {
                complex_pairs: pairs,
                real_poles: real,
                band,
                passivity_margin: PASSIVITY_MARGIN * tolerance,
                block_coupling: BLOCK_COUPLING * tolerance,
                ..VectorFitParams::default()
            };
            iterations += vf.iterations;
            match candidate(problem, &data, &vf) {
                Ok((error, network, _)) => {
                    tried.push(format!("order {k}: {:.3} %", 100.0 * error));
                    if !matches!(&best, Some((e, _, _)) if *e <= error) {
                        best = Some((error, k, network));
                    }
                }
                Err(why) => failures.push(format!("order {k} ({pairs} pairs, {real} real): {why}")),
            }
        }
        if matches!(&best, Some((e, _, _)) if *e <= tolerance) {
            break;
        }
    }
    let mut notes = Vec::new();
    if !failures.is_empty() {
        notes.push(format!(
            "rational fit: {} candidate(s) failed: {}",
            failures.len(),
            failures.join("; ")
        ));
    }
    let Some((error, order, network)) = best else {
        return Err(IdentifyError::Synthesis(format!(
            "no order gave a passive network; {}",
            failures.join("; ")
        )));
    };
    if error > tolerance {
        notes.push(format!(
            "rational fit: no order met the tolerance ({}); order {order} has the smallest error",
            tried.join(", ")
        ));
    }
    Ok(RationalOutcome {
        order,
        network,
        iterations,
        notes,
    })
}

/// The passivity margin of the vector fits as a fraction of the tolerance (the damping it adds
/// costs at most this much of the error budget).
pub const PASSIVITY_MARGIN: f64 = 0.02;

/// The couplings between invariant blocks that the split may drop, as a fraction of the
/// tolerance.
pub const BLOCK_COUPLING: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orders_count_poles_with_pairs_twice() {
        for k in 1..12 {
            for (pairs, real) in layouts(k) {
                assert_eq!(2 * pairs + real, k);
            }
        }
        assert_eq!(layouts(6), vec![(3, 0), (2, 2)]);
    }

    #[test]
    fn residues_on_orthogonal_motions_make_separate_parts() {
        use nalgebra::{DMatrix, DVector};
        use num_complex::Complex64;
        // Poles 0 and 2 act on (1, 1, 0), pole 1 on (1, -1, 0) and pole 3 on (0, 0, 1) and
        // (1, -1, 0): parts {0, 2} and {1, 3}.
        let outer = |v: [f64; 3], w: [f64; 3], c: f64| {
            DMatrix::from_fn(3, 3, |i, j| {
                Complex64::new(c * (v[i] * v[j] + w[i] * w[j]), 0.5 * c * v[i] * v[j])
            })
        };
        let fit = RationalFit {
            poles: [(-1.0, 2.0), (-0.5, 0.0), (-2.0, 1.0), (-3.0, 0.0)]
                .iter()
                .map(|&(re, im)| Complex64::new(re, im))
                .collect(),
            residues: vec![
                outer([1.0, 1.0, 0.0], [0.0; 3], 1.0),
                outer([1.0, -1.0, 0.0], [0.0; 3], 2.0),
                outer([1.0, 1.0, 0.0], [0.0; 3], 3.0),
                outer([0.0, 0.0, 1.0], [1.0, -1.0, 0.0], 4.0),
            ],
            dof_scales: DVector::from_element(3, 1.0),
            max_error: 0.0,
        };
        let parts = independent_parts(&fit);
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0].poles, vec![fit.poles[0], fit.poles[2]]);
        assert_eq!(parts[1].poles, vec![fit.poles[1], fit.poles[3]]);
        // The parts sum to the fit at any frequency.
        for omega in [0.1, 1.0, 7.0] {
            let sum = parts[0].evaluate(omega) + parts[1].evaluate(omega);
            assert!((sum - fit.evaluate(omega)).norm() < 1e-12);
        }
    }
}
