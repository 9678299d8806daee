//! The rational path of the coupled form: passive vector fitting per invariant block
//! ([`super::vector_fitting::Blocks`]), each part acting on its own motions realized as a
//! mechanical substructure ([`super::synthesis`]), each block's order chosen against the
//! tolerance.
//!
//! Order `k` is the number of poles of a block, a conjugate pair counted twice: `k` odd gives
//! `(k - 1) / 2` pairs and one real pole; `k` even gives `k / 2` pairs, and also `k / 2 - 1`
//! pairs with two real poles (real poles follow the logarithmic low-frequency added mass of
//! heave-like motions), the better of the two kept. Each block takes the first order whose fit
//! meets its tolerance, else keeps the one with the smallest error (a block's states: its
//! dimension times its order); the reported order is the largest block's. Orders stay below
//! the band's point count (a block's poles are common to its entries: with 7 points, at most
//! 6 poles). The passivity margin is 2 % of the tolerance and the couplings the block split
//! may drop a tenth of it, so both together cost at most 12 % of the error budget.
//!
//! Pole refinement: the relocation places a block's poles for the free fit. Where the passive
//! fit misses the block's tolerance although the free fit meets it (data whose damping
//! vanishes inside the band, as a submerged body's at its top: the constraints bind there),
//! [`Blocks::refine`] moves the poles to fit better under the constraints (at most
//! [`REFINEMENT_EVALUATIONS`] enforced fits). The circle at H/R 1.5: order 4 per block
//! goes from 1.24 % to 0.61-0.79 %, 8 states instead of 12 at order 6; a note names every
//! block so refined.
//!
//! Physical bounds: a candidate whose poles are not all within [`POLE_RANGE`] of the band
//! (below its bottom over `POLE_RANGE`, above its top times it) is refused: such a pole is a
//! spurious slow mode (a mass that acts as a spring to the ground for minutes) or a stiff one
//! that carries no information. Below the band the factor is
//! [`FitParams::pole_range_below`]: 2D data in finite depth need slow poles for their damping
//! at zero frequency ([`super::params::pole_range_below`]).

use super::problem::Problem;
use super::synthesis::synthesize;
use super::vector_fitting::{BlockFit, Blocks, RationalFit, VectorFitParams};
use super::{FitParams, FrequencyResponse, IdentifyError};
use crate::network::Network;
use num_complex::Complex64;

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

/// The network of a passive fit, its parts realized as substructures, and its largest
/// normalized error against the data.
fn network_of(problem: &Problem, fit: &RationalFit) -> Result<(f64, Network), String> {
    let substructures = independent_parts(fit)
        .iter()
        .map(|part| synthesize(part).map(|(sub, _)| sub))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| match e {
            IdentifyError::Synthesis(why) => format!("the synthesis failed: {why}"),
            other => other.to_string(),
        })?;
    let network = Network::from_substructures(
        problem.dof_names.clone(),
        problem.added_mass_inf.clone(),
        substructures,
        problem.rho,
        problem.g,
    );
    network.validate().map_err(|e| e.to_string())?;
    Ok((problem.max_relative_error(&network), network))
}

/// Why a block's fit cannot be used: not passive, or a pole outside the band by more than
/// `range_below` below it or [`POLE_RANGE`] above it.
fn refusal(fit: &BlockFit, omega_ref: f64, band: (f64, f64), range_below: f64) -> Option<String> {
    let e = &fit.enforcement;
    if !e.passive {
        return Some(format!(
            "no passive residues after {} rounds ({} constraint frequencies, {} iterations)",
            e.rounds, e.samples, e.iterations
        ));
    }
    let (lo, hi) = band;
    fit.poles
        .iter()
        .map(|p| p.norm() * omega_ref)
        .find(|&m| m < lo / range_below || m > hi * POLE_RANGE)
        .map(|m| {
            let factor = if m < lo { range_below } else { POLE_RANGE };
            format!(
                "a pole at {m:.3e} rad/s lies outside the band ({lo:.3e}, {hi:.3e}) rad/s by more \
                 than a factor {factor}"
            )
        })
}

/// Whether two pole sets agree to 1e-3 of their moduli.
fn same_poles(a: &[Complex64], b: &[Complex64]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| (p - q).norm() <= 1e-3 * p.norm().max(q.norm()))
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
/// and notes (orders that failed and why, the orders chosen when none met the tolerance).
pub(super) struct RationalOutcome {
    pub(crate) order: usize,
    pub(crate) network: Network,
    pub(crate) iterations: usize,
    pub(crate) notes: Vec<String>,
}

/// One block's order search: its current order, its best fit so far and that fit's order.
struct Search {
    next_order: usize,
    best: Option<(usize, BlockFit)>,
}

/// Enforced fits [`Blocks::refine`] may try per candidate whose free fit meets the block's
/// tolerance and whose passive fit does not (80: the midship's symmetric block at order 4
/// from 1.30 % to 0.90 %; the whole fit 8 s).
pub const REFINEMENT_EVALUATIONS: usize = 80;

/// Rounds of tightening the blocks' tolerances when their errors add up past the tolerance.
const TIGHTENING_ROUNDS: usize = 4;

/// Fits the coupled form by the rational path (module docs). Every invariant block searches
/// its own order upwards, from 1, until its fit meets the block's tolerance; a block's fit is
/// never replaced by a worse one (if no order meets it, the smallest error is kept). Blocks
/// start with the whole tolerance; while the joined network misses it, every block's tolerance
/// is scaled by `0.95 tol / error` and the blocks that miss theirs continue their search
/// (at most 4 rounds). Orders are at most `max_order` and fewer than the band's points; a
/// fixed `order` applies to every block.
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
    // One real pole: the blocks need only the band's 3 points; each fit sets its own poles.
    let base = VectorFitParams {
        complex_pairs: 0,
        real_poles: 1,
        band,
        passivity_margin: PASSIVITY_MARGIN * tolerance,
        block_coupling: BLOCK_COUPLING * tolerance,
        ..VectorFitParams::default()
    };
    let blocks = Blocks::new(&data, &base)?;
    let (first, last) = match params.order {
        Some(k) => (k, k),
        None => (1, params.max_order.min(points.saturating_sub(1)).max(1)),
    };
    let mut searches: Vec<Search> = (0..blocks.len())
        .map(|_| Search {
            next_order: first,
            best: None,
        })
        .collect();
    let mut iterations = 0;
    let mut failures: Vec<String> = Vec::new();
    let mut refinements: Vec<String> = Vec::new();
    let mut block_tolerance = tolerance;
    let mut best: Option<(f64, usize, Network)> = None;
    let mut last_failure = String::new();
    for round in 0..=TIGHTENING_ROUNDS {
        for (b, search) in searches.iter_mut().enumerate() {
            while search.next_order <= last
                && !matches!(&search.best, Some((_, f)) if f.error <= block_tolerance)
            {
                let k = search.next_order;
                search.next_order += 1;
                let mut tried: Vec<Vec<Complex64>> = Vec::new();
                for (pairs, real) in layouts(k) {
                    let vf = VectorFitParams {
                        complex_pairs: pairs,
                        real_poles: real,
                        ..base.clone()
                    };
                    iterations += vf.iterations;
                    let mut fit = blocks.fit(b, &vf);
                    // Both layouts of an even order often relocate to the same poles.
                    if tried.iter().any(|p| same_poles(p, &fit.poles)) {
                        continue;
                    }
                    tried.push(fit.poles.clone());
                    if fit.enforcement.free_error <= block_tolerance
                        && fit.error > block_tolerance
                        && fit.enforcement.passive
                    {
                        // The poles can meet the tolerance; the constraints cost the rest.
                        let refined = blocks.refine(b, &fit, &vf, REFINEMENT_EVALUATIONS);
                        if refusal(&refined, blocks.omega_ref(), band, params.pole_range_below)
                            .is_none()
                        {
                            if refined.error < fit.error {
                                refinements.push(format!(
                                    "block {} order {k} ({pairs} pairs, {real} real) {:.3} % -> \
                                     {:.3} %",
                                    b + 1,
                                    100.0 * fit.error,
                                    100.0 * refined.error
                                ));
                            }
                            fit = refined;
                        }
                    }
                    if let Some(why) =
                        refusal(&fit, blocks.omega_ref(), band, params.pole_range_below)
                    {
                        failures.push(format!(
                            "block {} ({} DOF directions), order {k} ({pairs} pairs, {real} \
                             real): {why}",
                            b + 1,
                            blocks.dimension(b)
                        ));
                        continue;
                    }
                    if !matches!(&search.best, Some((_, f)) if f.error <= fit.error) {
                        search.best = Some((k, fit));
                    }
                }
            }
        }
        let fits: Vec<&BlockFit> = searches
            .iter()
            .filter_map(|s| s.best.as_ref().map(|(_, f)| f))
            .collect();
        if fits.len() < searches.len() {
            break;
        }
        let order = searches
            .iter()
            .filter_map(|s| s.best.as_ref().map(|(k, _)| *k))
            .max()
            .unwrap_or(0);
        match network_of(problem, &blocks.assemble(&fits)) {
            Ok((error, network)) => {
                if !matches!(&best, Some((e, _, _)) if *e <= error) {
                    best = Some((error, order, network));
                }
                if error <= tolerance {
                    break;
                }
                let exhausted = searches.iter().all(|s| s.next_order > last);
                if exhausted || round == TIGHTENING_ROUNDS {
                    break;
                }
                block_tolerance *= 0.95 * tolerance / error;
            }
            Err(why) => {
                last_failure = why;
                break;
            }
        }
    }
    let mut notes = Vec::new();
    if !failures.is_empty() {
        notes.push(format!(
            "rational fit: {} candidate(s) refused: {}",
            failures.len(),
            failures.join("; ")
        ));
    }
    if !refinements.is_empty() {
        notes.push(format!(
            "rational fit: poles moved to fit better under the passivity constraints: {}",
            refinements.join("; ")
        ));
    }
    let Some((error, order, network)) = best else {
        let why = if last_failure.is_empty() {
            failures.join("; ")
        } else {
            last_failure
        };
        return Err(IdentifyError::Synthesis(format!(
            "no order gave a passive network; {why}"
        )));
    };
    if blocks.len() > 1 {
        let chosen: Vec<String> = searches
            .iter()
            .zip(0..)
            .filter_map(|(s, b)| {
                s.best.as_ref().map(|(k, f)| {
                    format!(
                        "block {} ({} DOF directions): order {k}, {} states, {:.3} %",
                        b + 1,
                        blocks.dimension(b),
                        f.states,
                        100.0 * f.error
                    )
                })
            })
            .collect();
        notes.push(format!(
            "rational fit: {} invariant blocks, each its own order: {}",
            blocks.len(),
            chosen.join("; ")
        ));
    }
    // A pole below the deep-water bound is there only because `pole_range_below` allowed it.
    let slowest = searches
        .iter()
        .filter_map(|s| s.best.as_ref())
        .flat_map(|(_, f)| f.poles.iter().map(|p| p.norm() * blocks.omega_ref()))
        .fold(f64::INFINITY, f64::min);
    if slowest < band.0 / POLE_RANGE {
        notes.push(format!(
            "rational fit: a pole at {slowest:.3e} rad/s, {:.0} times below the band: the \
             damping 2D data keep at zero frequency in finite depth, a dashpot (such poles are \
             allowed down to {:.0e} times below the band)",
            band.0 / slowest,
            params.pole_range_below
        ));
    }
    if error > tolerance {
        notes.push(format!(
            "rational fit: no order up to {last} met the tolerance; the network kept has the \
             smallest error found, {:.3} %",
            100.0 * error
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
