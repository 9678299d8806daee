//! The rational path of the coupled form: passive vector fitting per invariant block
//! ([`super::vector_fitting::passive_block_vector_fit`]) realized as one mechanical
//! substructure ([`super::synthesis`]), the order chosen against the tolerance.
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
            "no passive residues after {} rounds ({} cuts)",
            e.rounds, e.cuts
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
    let (substructure, _) = synthesize(&fit).map_err(|e| e.to_string())?;
    let network = Network::from_substructure(
        problem.dof_names.clone(),
        problem.added_mass_inf.clone(),
        substructure,
        problem.rho,
        problem.g,
    );
    network.validate().map_err(|e| e.to_string())?;
    Ok((problem.max_relative_error(&network), network, fit))
}

/// Fits the coupled form by the rational path: `(order, network, vector fitting iterations)`.
pub(super) fn fit_rational(
    problem: &Problem,
    data: &FrequencyResponse,
    params: &FitParams,
    tolerance: f64,
) -> Result<(usize, Network, usize), IdentifyError> {
    // The data with the symmetric PSD A_inf the network gets.
    let mut data = data.clone();
    data.added_mass_inf = problem.added_mass_inf.clone();
    let band = (problem.omega[0], problem.omega[problem.omega.len() - 1]);
    let orders: Vec<usize> = match params.order {
        Some(k) => vec![k],
        None => (1..=params.max_order).collect(),
    };
    let mut best: Option<(f64, usize, Network)> = None;
    let mut iterations = 0;
    let mut last_failure = String::new();
    for k in orders {
        for (pairs, real) in layouts(k) {
            let vf = VectorFitParams {
                complex_pairs: pairs,
                real_poles: real,
                band,
                ..VectorFitParams::default()
            };
            iterations += vf.iterations;
            match candidate(problem, &data, &vf) {
                Ok((error, network, _)) => {
                    if !matches!(&best, Some((e, _, _)) if *e <= error) {
                        best = Some((error, k, network));
                    }
                }
                Err(why) => last_failure = format!("order {k} ({pairs} pairs, {real} real): {why}"),
            }
        }
        if matches!(&best, Some((e, _, _)) if *e <= tolerance) {
            break;
        }
    }
    let (_, order, network) = best.ok_or_else(|| {
        IdentifyError::Synthesis(format!("no order gave a passive network; {last_failure}"))
    })?;
    Ok((order, network, iterations))
}

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
}
