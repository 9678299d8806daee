//! Joint refinement of the groups' dynamics and PSD weights `W_p = L_p L_p^T`
//! (Levenberg-Marquardt on the log chain values and the factors, passive at every step),
//! aimed at the largest error by Lawson's reweighting of the band points.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::groups::GroupSet;
use super::Scope;
use crate::identify::chain::LOG_BOUND;
use crate::identify::problem::Problem;
use crate::identify::FitParams;
use crate::network::Network;

impl Problem {
    /// Network of PSD-weighted groups, after the joint refinement if the tolerance is not met
    /// yet but the error is within `gate` times it (the better of the two).
    pub(super) fn refined_network(
        &self,
        scope: &Scope,
        groups: GroupSet,
        weights: Vec<DMatrix<f64>>,
        params: &FitParams,
        tolerance: f64,
        gate: f64,
    ) -> (Network, usize) {
        let nu = &self.nu;
        let reduced = &scope.reduced;
        let network = self.coupled_network(reduced, &groups, &weights, tolerance);
        let error = self.scope_error(scope, &network);
        if error <= tolerance {
            return (network, 0);
        }
        if error > gate * tolerance {
            return (network, 0);
        }
        let frequency_errors =
            |g: &GroupSet, w: &[DMatrix<f64>]| reduced.frequency_errors(nu, g, w);
        let (groups, weights, its) = refine_coupled(
            nu,
            &reduced.target,
            &groups,
            &weights,
            params.max_iterations,
            &frequency_errors,
            0.9 * tolerance,
        );
        let refined = self.coupled_network(reduced, &groups, &weights, tolerance);
        if self.scope_error(scope, &refined) < error {
            (refined, its)
        } else {
            (network, its)
        }
    }
}

/// Largest normalized entry error per band point of PSD-weighted groups.
pub(super) type FrequencyErrors<'a> = dyn Fn(&GroupSet, &[DMatrix<f64>]) -> Vec<f64> + 'a;

/// Joint Levenberg-Marquardt refinement of the group dynamics and PSD weights
/// `W_p = L_p L_p^T` (the factors keep every iterate passive). The Gauss-Newton normal
/// equations are assembled from frequency sums of the group shapes, so their cost does not
/// grow with (frequencies x entries) x parameters.
pub(super) fn refine_coupled(
    nu: &[f64],
    target: &[DMatrix<Complex64>],
    groups: &GroupSet,
    weights: &[DMatrix<f64>],
    max_iterations: usize,
    frequency_errors: &FrequencyErrors,
    target_error: f64,
) -> (GroupSet, Vec<DMatrix<f64>>, usize) {
    let n = target[0].nrows();
    let count = groups.count();
    let sp = groups.params_per_group();
    let nt = count * sp;
    let nn = n * n;
    // Data rows [Re T(nu_i); Im T(nu_i)], columns the n^2 entries (column-major).
    let mut y = DMatrix::zeros(2 * nu.len(), nn);
    for (i, t) in target.iter().enumerate() {
        for e in 0..nn {
            y[(2 * i, e)] = t[e].re;
            y[(2 * i + 1, e)] = t[e].im;
        }
    }
    // Factors from the eigen-decomposition, significant eigenvalues only.
    let largest = weights
        .iter()
        .map(|w| w.clone().symmetric_eigenvalues().amax())
        .fold(0.0, f64::max);
    let mut factors: Vec<DMatrix<f64>> = weights
        .iter()
        .map(|w| {
            let eigen = crate::numerics::symmetric_eigen(w);
            let keep: Vec<usize> = (0..n)
                .filter(|&r| eigen.eigenvalues[r] > 1e-8 * largest)
                .collect();
            DMatrix::from_fn(n, keep.len().max(1), |i, c| match keep.get(c) {
                Some(&r) => eigen.eigenvectors[(i, r)] * eigen.eigenvalues[r].sqrt(),
                None => 0.0,
            })
        })
        .collect();
    let mut current = groups.clone();
    let stacked = |factors: &[DMatrix<f64>]| {
        let mut w = DMatrix::zeros(count, nn);
        for (p, l) in factors.iter().enumerate() {
            let wp = l * l.transpose();
            for e in 0..nn {
                w[(p, e)] = wp[e];
            }
        }
        w
    };
    // Frequency weights (Lawson): rows of frequency k scaled by root[k] = sqrt(rho_k).
    let weigh = |m: &mut DMatrix<f64>, root: &[f64]| {
        for (k, &r) in root.iter().enumerate() {
            m.row_mut(2 * k).scale_mut(r);
            m.row_mut(2 * k + 1).scale_mut(r);
        }
    };
    let mut rho = vec![1.0; nu.len()];
    let mut root = rho.clone();
    let mut y_w = y.clone();
    let cost_of =
        |groups: &GroupSet, factors: &[DMatrix<f64>], root: &[f64], y_w: &DMatrix<f64>| {
            let (mut g, _) = groups.basis(nu, false);
            weigh(&mut g, root);
            (y_w - g * stacked(factors)).norm_squared()
        };
    let offsets: Vec<usize> = factors
        .iter()
        .scan(nt, |acc, l| {
            let o = *acc;
            *acc += l.len();
            Some(o)
        })
        .collect();
    let unknowns = nt + factors.iter().map(|l| l.len()).sum::<usize>();
    let mut cost = cost_of(&current, &factors, &root, &y_w);
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut slow = 0;
    let mut history = Vec::new();
    let mut best: Option<(f64, GroupSet, Vec<DMatrix<f64>>)> = None;
    while iterations < max_iterations && cost.is_finite() {
        iterations += 1;
        let (mut g, mut d) = current.basis(nu, true);
        weigh(&mut g, &root);
        weigh(&mut d, &root);
        let w = stacked(&factors);
        let as_matrix =
            |m: &DMatrix<f64>, p: usize| DMatrix::from_fn(n, n, |i, j| m[(p, j * n + i)]);
        let wm: Vec<DMatrix<f64>> = (0..count).map(|p| as_matrix(&w, p)).collect();
        let gram = g.tr_mul(&g);
        let gram_d = g.tr_mul(&d);
        let cross = d.tr_mul(&d);
        let residual = &y_w - &g * &w;
        let corr_g = g.tr_mul(&residual);
        let corr_d = d.tr_mul(&residual);
        let inner = DMatrix::from_fn(count, count, |p, q| wm[p].dot(&wm[q]));

        let mut jtj = DMatrix::zeros(unknowns, unknowns);
        let mut jtr = DVector::zeros(unknowns);
        for p in 0..count {
            for a in 0..sp {
                let row = p * sp + a;
                for q in 0..count {
                    for b in 0..sp {
                        jtj[(row, q * sp + b)] = cross[(row, q * sp + b)] * inner[(p, q)];
                    }
                }
                jtr[row] = -wm[p].dot(&as_matrix(&corr_d, row));
            }
        }
        for p in 0..count {
            let lp = &factors[p];
            let e_p = as_matrix(&corr_g, p);
            let grad = -(&e_p + e_p.transpose()) * lp;
            let wq_lp: Vec<DMatrix<f64>> = (0..count).map(|q| &wm[q] * lp).collect();
            for l in 0..lp.ncols() {
                for k in 0..n {
                    let row = offsets[p] + l * n + k;
                    jtr[row] = grad[(k, l)];
                    for q in 0..count {
                        for b in 0..sp {
                            let v = 2.0 * gram_d[(p, q * sp + b)] * wq_lp[q][(k, l)];
                            jtj[(row, q * sp + b)] = v;
                            jtj[(q * sp + b, row)] = v;
                        }
                        let lq = &factors[q];
                        for l2 in 0..lq.ncols() {
                            let uw = lp.column(l).dot(&lq.column(l2));
                            for k2 in 0..n {
                                let mut v = 2.0 * lq[(k, l2)] * lp[(k2, l)];
                                if k == k2 {
                                    v += 2.0 * uw;
                                }
                                jtj[(row, offsets[q] + l2 * n + k2)] = gram[(p, q)] * v;
                            }
                        }
                    }
                }
            }
        }
        let diag_max = (0..unknowns).map(|i| jtj[(i, i)]).fold(0.0, f64::max);
        if diag_max == 0.0 {
            break;
        }
        let mut accepted = None;
        while lambda < 1e12 {
            let mut a = jtj.clone();
            for i in 0..unknowns {
                a[(i, i)] += lambda * jtj[(i, i)].max(1e-9 * diag_max);
            }
            let Some(ch) = a.cholesky() else {
                lambda *= 10.0;
                continue;
            };
            let step = -ch.solve(&jtr);
            let trial = GroupSet {
                stages: current.stages,
                theta: (0..nt)
                    .map(|i| (current.theta[i] + step[i]).clamp(-LOG_BOUND, LOG_BOUND))
                    .collect(),
            };
            let trial_factors: Vec<DMatrix<f64>> = factors
                .iter()
                .enumerate()
                .map(|(p, l)| {
                    DMatrix::from_fn(n, l.ncols(), |k, c| {
                        l[(k, c)] + step[offsets[p] + c * n + k]
                    })
                })
                .collect();
            let new_cost = cost_of(&trial, &trial_factors, &root, &y_w);
            if new_cost.is_finite() && new_cost < cost {
                accepted = Some((trial, trial_factors, new_cost));
                lambda = (lambda / 3.0).max(1e-12);
                break;
            }
            lambda *= 4.0;
        }
        let Some((trial, trial_factors, new_cost)) = accepted else {
            break;
        };
        let improvement = (cost - new_cost) / cost;
        current = trial;
        factors = trial_factors;
        cost = new_cost;
        slow = if improvement < 1e-9 { slow + 1 } else { 0 };
        if slow >= 3 || cost < 1e-30 {
            break;
        }
        // Every 5 iterations: stop once the tolerance is met, or when the largest error has
        // improved by less than 1 % over the last 40 iterations.
        if iterations % 5 == 0 {
            let w: Vec<DMatrix<f64>> = factors.iter().map(|l| l * l.transpose()).collect();
            let errors = frequency_errors(&current, &w);
            let error = errors.iter().copied().fold(0.0, f64::max);
            if !matches!(&best, Some((e, _, _)) if *e <= error) {
                best = Some((error, current.clone(), factors.clone()));
            }
            history.push(error);
            let plateau = history.len() > 8 && error > 0.99 * history[history.len() - 9];
            if error <= target_error || plateau {
                break;
            }
            // Lawson's reweighting towards the largest error (damped by the square root).
            if error > 0.0 {
                for (r, e) in rho.iter_mut().zip(&errors) {
                    *r *= (e / error).max(1e-3).sqrt();
                }
                let mean = rho.iter().sum::<f64>() / rho.len() as f64;
                for r in rho.iter_mut() {
                    *r = (*r / mean).max(1e-3);
                }
                root = rho.iter().map(|r| r.sqrt()).collect();
                y_w = y.clone();
                weigh(&mut y_w, &root);
                cost = cost_of(&current, &factors, &root, &y_w);
                slow = 0;
            }
        }
    }
    let (current, factors) = match best {
        Some((error, g, f))
            if {
                let w: Vec<DMatrix<f64>> = factors.iter().map(|l| l * l.transpose()).collect();
                frequency_errors(&current, &w)
                    .iter()
                    .copied()
                    .fold(0.0, f64::max)
                    > error
            } =>
        {
            (g, f)
        }
        _ => (current, factors),
    };
    let weights = factors.iter().map(|l| l * l.transpose()).collect();
    (current, weights, iterations)
}
