//! Coupled path 1: one-stage (or longer) groups by variable projection. LM on the groups'
//! log parameters with the weights solved by linear least squares for every entry at once
//! (residual `(I - Q Q^T) Y`, Kaufman's Jacobian), then PSD weights and the refinement.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::groups::GroupSet;
use super::weights::{least_squares_weights, psd_weights, residual_matrix, PSD_PRECISION};
use super::CoupledState;
use crate::identify::chain::LOG_BOUND;
use crate::identify::problem::Problem;
use crate::identify::FitParams;
use crate::network::Network;
use crate::numerics::{levenberg_marquardt, LeastSquares};

/// Variable projection over shared group dynamics: residual of the best unconstrained weights.
pub(super) struct GroupModel<'a> {
    nu: &'a [f64],
    stages: usize,
    /// Target columns (upper triangle, off-diagonals weighted by sqrt 2), compressed by SVD.
    data: DMatrix<f64>,
}

impl<'a> GroupModel<'a> {
    pub(super) fn new(
        nu: &'a [f64],
        target: &[DMatrix<Complex64>],
        stages: usize,
    ) -> GroupModel<'a> {
        let n = target[0].nrows();
        let m = n * (n + 1) / 2;
        let rows = 2 * nu.len();
        let mut y = DMatrix::zeros(rows, m);
        let mut col = 0;
        for j in 0..n {
            for i in 0..=j {
                let w = if i == j {
                    1.0
                } else {
                    std::f64::consts::SQRT_2
                };
                for (k, t) in target.iter().enumerate() {
                    y[(2 * k, col)] = t[(i, j)].re * w;
                    y[(2 * k + 1, col)] = t[(i, j)].im * w;
                }
                col += 1;
            }
        }
        // |(I - Q Q^T) Y|_F = |(I - Q Q^T) U S|_F: keep the significant left singular vectors.
        let data = if m > 4 {
            match crate::numerics::svd(y.clone(), true, false) {
                Some(svd) => {
                    let u = svd.u.expect("requested");
                    let smax = svd.singular_values.amax();
                    let keep: Vec<usize> = (0..svd.singular_values.len())
                        .filter(|&i| svd.singular_values[i] > 1e-9 * smax)
                        .collect();
                    DMatrix::from_fn(rows, keep.len(), |r, c| {
                        u[(r, keep[c])] * svd.singular_values[keep[c]]
                    })
                }
                None => y,
            }
        } else {
            y
        };
        GroupModel { nu, stages, data }
    }
}

impl LeastSquares for GroupModel<'_> {
    fn residual_count(&self) -> usize {
        self.data.len()
    }

    /// Residual `(I - Q Q^T) Y` of the projection on the shapes' span, and Kaufman's
    /// Jacobian `-(I - Q Q^T) (dPhi/dtheta) Phi^+ Y`.
    fn evaluate(
        &self,
        x: &DVector<f64>,
        r: &mut DVector<f64>,
        jacobian: Option<&mut DMatrix<f64>>,
    ) {
        let groups = GroupSet {
            stages: self.stages,
            theta: x.iter().copied().collect(),
        };
        let (phi, d) = groups.basis(self.nu, jacobian.is_some());
        let Some(svd) = crate::numerics::svd(phi, true, true) else {
            r.fill(f64::NAN);
            return;
        };
        let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
            r.fill(f64::NAN);
            return;
        };
        let smax = svd.singular_values.amax();
        let keep: Vec<usize> = (0..svd.singular_values.len())
            .filter(|&i| {
                svd.singular_values[i] > 1e-12 * smax && svd.singular_values[i].is_finite()
            })
            .collect();
        let q = DMatrix::from_fn(u.nrows(), keep.len(), |row, c| u[(row, keep[c])]);
        let qty = q.tr_mul(&self.data);
        let res = &self.data - &q * &qty;
        r.copy_from_slice(res.as_slice());
        if let Some(jac) = jacobian {
            // Coefficients C = Phi^+ Y = V S^-1 Q^T Y (count x columns).
            let count = groups.count();
            let mut coef = DMatrix::<f64>::zeros(count, self.data.ncols());
            for (c, &k) in keep.iter().enumerate() {
                let scaled = qty.row(c) / svd.singular_values[k];
                for p in 0..count {
                    let vpk = v_t[(k, p)];
                    for col in 0..self.data.ncols() {
                        coef[(p, col)] += vpk * scaled[col];
                    }
                }
            }
            let sp = groups.params_per_group();
            let rows = self.data.nrows();
            for k in 0..d.ncols() {
                let p = k / sp;
                let dk = d.column(k);
                let dt = dk - &q * q.tr_mul(&dk);
                for col in 0..self.data.ncols() {
                    let c = coef[(p, col)];
                    for i in 0..rows {
                        jac[(col * rows + i, k)] = -dt[i] * c;
                    }
                }
            }
        }
    }
}

impl Problem {
    /// Fits `order` groups of `stages`-stage chains by variable projection (continuing from
    /// `state`); builds the network if `build` and the free fit is within the tolerance.
    /// Returns it and the LM iterations.
    pub(super) fn fit_coupled(
        &self,
        order: usize,
        stages: usize,
        state: &mut CoupledState,
        params: &FitParams,
        tolerance: f64,
        build: bool,
    ) -> (Option<Network>, usize) {
        let n = self.n();
        let nu = &self.nu;
        let reduced = state.scope.reduced.clone();
        let target = &reduced.target;
        let mut iterations = 0;
        let model = GroupModel::new(nu, target, stages);
        let mut starts: Vec<GroupSet> = Vec::new();
        if stages == 1 {
            // Poles of a parallel bank fitted to the mean normalized diagonal (of the
            // scope's block: its trace over its dimension).
            let mean: Vec<DMatrix<Complex64>> = if state.scope.whole {
                self.target
                    .iter()
                    .map(|m| {
                        let t = (0..n).map(|i| m[(i, i)]).sum::<Complex64>() / n as f64;
                        DMatrix::from_element(1, 1, t)
                    })
                    .collect()
            } else {
                target
                    .iter()
                    .map(|m| DMatrix::from_element(1, 1, m.trace() / m.nrows() as f64))
                    .collect()
            };
            let proxy = Problem {
                dof_names: vec!["mean".into()],
                target: mean,
                scale: DVector::from_element(1, 1.0),
                ..self.shallow_clone()
            };
            for k in state.bank.as_ref().map_or(1, |b| b.len() + 1)..=order {
                let (bank, its) =
                    proxy.fit_scalar(false, k, state.bank.as_ref(), params, f64::INFINITY, false);
                iterations += its;
                state.bank = Some(bank);
            }
            if let Some(bank) = state.bank.as_ref().filter(|b| b.len() == order) {
                starts.push(GroupSet {
                    stages: 1,
                    theta: bank
                        .iter()
                        .flat_map(|b| {
                            [
                                (b[0].stiffness / b[0].mass).ln(),
                                (b[0].damping / b[0].mass).ln(),
                            ]
                        })
                        .collect(),
                });
            }
        } else if let Some(shorter) = state.solution(stages - 1).filter(|g| g.count() == order) {
            starts.push(shorter.with_extra_stage());
        }
        // Grid: natural frequencies log-spaced across the band.
        let (nu_lo, nu_hi) = (nu[0], nu[nu.len() - 1]);
        let mut grid = GroupSet {
            stages,
            theta: Vec::new(),
        };
        for p in 0..order {
            let f = (p as f64 + 0.5) / order as f64;
            grid = grid.with_group(nu_lo.powf(1.0 - f) * nu_hi.powf(f), 0.5);
        }
        starts.push(grid);
        if let Some(prev) = state.solution(stages).filter(|g| g.count() + 1 == order) {
            let weights = least_squares_weights(nu, target, prev);
            let worst = (0..nu.len())
                .map(|k| (residual_matrix(nu, target, prev, &weights, k).norm(), k))
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .map_or(0, |(_, k)| k);
            for zeta in [0.3, 1.0] {
                starts.push(prev.with_group(nu[worst], zeta));
            }
        }
        let mut best: Option<(f64, DVector<f64>)> = None;
        for start in &starts {
            let x0 = DVector::from_vec(start.theta.clone());
            let result = levenberg_marquardt(&model, x0, params.max_iterations, LOG_BOUND);
            iterations += result.iterations;
            if !matches!(&best, Some((c, _)) if *c <= result.cost) {
                best = Some((result.cost, result.x));
            }
        }
        let Some((_, x)) = best else {
            return (None, iterations);
        };
        let groups = GroupSet {
            stages,
            theta: x.iter().copied().collect(),
        };
        state.store(groups.clone());
        if !build {
            return (None, iterations);
        }
        // The PSD constraint only adds error: skip orders whose free fit already misses.
        let free = least_squares_weights(nu, target, &groups);
        if reduced.max_error(nu, &groups, &free) > tolerance && order < params.max_order {
            return (None, iterations);
        }
        let weights = psd_weights(nu, target, &groups, PSD_PRECISION);
        // Projecting free weights onto the PSD cone can lose much; refine only if close.
        let (network, its) =
            self.refined_network(&state.scope, groups, weights, params, tolerance, 3.0);
        (Some(network), iterations + its)
    }
}
