//! Weights of fixed group dynamics: the residual `T - sum_p W_p g_p`, the normal equations,
//! unconstrained least-squares weights, and PSD weights `W_p >= 0` by accelerated projected
//! gradient (convex).

use nalgebra::DMatrix;
use num_complex::Complex64;

use super::groups::GroupSet;
use crate::numerics::project_psd;

/// Relative step size at which the PSD weight iteration stops.
pub(super) const PSD_PRECISION: f64 = 1e-10;

/// The same for the dictionary screening (only a ranking is needed).
pub(super) const DICTIONARY_PRECISION: f64 = 1e-5;

/// Residual matrix `T - sum_p W_p g_p` at band point `k`.
pub(super) fn residual_matrix(
    nu: &[f64],
    target: &[DMatrix<Complex64>],
    groups: &GroupSet,
    weights: &[DMatrix<f64>],
    k: usize,
) -> DMatrix<Complex64> {
    let s = Complex64::new(0.0, nu[k]);
    let mut m = target[k].clone();
    for (p, w) in weights.iter().enumerate() {
        let g = groups.shape(p, s);
        m -= w.map(|x| g * x);
    }
    m
}

/// Gram matrix `G_pq = Re sum conj(g_p) g_q` and `B_p = Re sum conj(g_p) T` of the groups.
pub(super) fn normal_equations(
    nu: &[f64],
    target: &[DMatrix<Complex64>],
    groups: &GroupSet,
) -> (DMatrix<f64>, Vec<DMatrix<f64>>) {
    let count = groups.count();
    let n = target[0].nrows();
    let (g, _) = groups.basis(nu, false);
    let gram = g.tr_mul(&g);
    let mut rhs = vec![DMatrix::zeros(n, n); count];
    for (i, t) in target.iter().enumerate() {
        for (p, r) in rhs.iter_mut().enumerate() {
            let (re, im) = (g[(2 * i, p)], g[(2 * i + 1, p)]);
            *r += t.map(|z| re * z.re + im * z.im);
        }
    }
    (gram, rhs)
}

/// Unconstrained least-squares weights for fixed group dynamics.
pub(super) fn least_squares_weights(
    nu: &[f64],
    target: &[DMatrix<Complex64>],
    groups: &GroupSet,
) -> Vec<DMatrix<f64>> {
    let (gram, rhs) = normal_equations(nu, target, groups);
    let count = groups.count();
    let n = target[0].nrows();
    let mut weights = vec![DMatrix::zeros(n, n); count];
    let Some(svd) = crate::numerics::svd(gram, true, true) else {
        return weights;
    };
    let cutoff = 1e-12 * svd.singular_values.amax();
    if let Ok(pinv) = svd.pseudo_inverse(cutoff) {
        for (p, w) in weights.iter_mut().enumerate() {
            for (q, r) in rhs.iter().enumerate() {
                *w += r * pinv[(p, q)];
            }
        }
    }
    weights
}

/// PSD-constrained least-squares weights for fixed group dynamics (accelerated projected
/// gradient with adaptive restart; convex, so the start only affects the run time).
pub(super) fn psd_weights(
    nu: &[f64],
    target: &[DMatrix<Complex64>],
    groups: &GroupSet,
    precision: f64,
) -> Vec<DMatrix<f64>> {
    let (gram, rhs) = normal_equations(nu, target, groups);
    let count = groups.count();
    // Unit-diagonal scaling of the Gram matrix (W'_p = sigma_p W_p keeps PSD).
    let sigma: Vec<f64> = (0..count)
        .map(|p| gram[(p, p)].sqrt().max(1e-300))
        .collect();
    let g = DMatrix::from_fn(count, count, |p, q| gram[(p, q)] / (sigma[p] * sigma[q]));
    let b: Vec<DMatrix<f64>> = (0..count).map(|p| &rhs[p] / sigma[p]).collect();
    let lipschitz = 2.0 * g.clone().symmetric_eigenvalues().amax().max(1e-300);
    let start = least_squares_weights(nu, target, groups);
    let mut w: Vec<DMatrix<f64>> = (0..count)
        .map(|p| project_psd(&(&start[p] * sigma[p])))
        .collect();
    let mut y = w.clone();
    let mut t: f64 = 1.0;
    let max_iterations = if precision >= DICTIONARY_PRECISION {
        400
    } else {
        5000
    };
    for _ in 0..max_iterations {
        let mut next = Vec::with_capacity(count);
        for p in 0..count {
            let mut grad = -&b[p];
            for q in 0..count {
                grad += &y[q] * g[(p, q)];
            }
            next.push(project_psd(&(&y[p] - grad * (2.0 / lipschitz))));
        }
        let mut change = 0.0;
        let mut size = 0.0;
        let mut restart = 0.0;
        for p in 0..count {
            let d = &next[p] - &w[p];
            change += d.norm_squared();
            size += next[p].norm_squared();
            restart += (&y[p] - &next[p]).dot(&d);
        }
        let t_next = if restart > 0.0 {
            1.0
        } else {
            0.5 * (1.0 + (1.0 + 4.0 * t * t).sqrt())
        };
        let momentum = if restart > 0.0 {
            0.0
        } else {
            (t - 1.0) / t_next
        };
        y = (0..count)
            .map(|p| &next[p] + (&next[p] - &w[p]) * momentum)
            .collect();
        w = next;
        t = t_next;
        if change <= precision * precision * size.max(1e-300) {
            break;
        }
    }
    (0..count).map(|p| &w[p] / sigma[p]).collect()
}
