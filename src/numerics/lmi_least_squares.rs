//! Least squares under sampled linear matrix inequalities, by the alternating direction method
//! of multipliers (ADMM; Boyd et al., "Distributed optimization and statistical learning via
//! ADMM", 2011: over-relaxation, residual balancing):
//!
//! ```text
//! min_X  1/2 sum_e |R x_e - c_e|^2    subject to    S_k(X) = sum_e (psi_k . x_e) E_e  >=  delta_k I,
//! ```
//!
//! `X` (N x E) has one column `x_e` per entry `e = (i, j)`, `i <= j`, of an n x n symmetric
//! matrix, `E_e` the symmetric unit matrix of that entry, `psi_k` (N) the k-th constraint row,
//! `delta_k >= 0` its margin. The splitting `Z_k = S_k(X)`, `Z_k >= delta_k I` gives per
//! iteration one linear solve per entry (two matrices, `R^T R + rho w P` with `w = 1` on the
//! diagonal entries and 2 off it, `P = sum_k psi_k psi_k^T`), one projection of each `Z_k`
//! onto the shifted PSD cone, and the multiplier update. Every row is scaled to unit norm
//! first (the feasible set is unchanged). Convex: from any start it converges to the minimum;
//! it stops when the primal and dual residuals fall below `tolerance` of their scales, when the
//! iterate itself satisfies every inequality with half its margin and the dual residual is
//! below 1e-3 of its scale, or after `max_iterations`.

use nalgebra::{DMatrix, DVector};

/// The constraints `S_k(X) >= delta_k I` (module docs).
#[derive(Clone, Copy, Debug)]
pub struct MatrixInequalities<'a> {
    /// Size n of the symmetric matrices.
    pub(crate) n: usize,
    /// The entries `(i, j)`, `i <= j`, one per column of `X`.
    pub(crate) pairs: &'a [(usize, usize)],
    /// K x N: row k is `psi_k`.
    pub(crate) rows: &'a DMatrix<f64>,
    /// `delta_k`, one per row.
    pub(crate) margins: &'a [f64],
}

/// The result of [`lmi_least_squares`].
#[derive(Clone, Debug)]
pub struct LmiSolution {
    /// The coefficients (N x E).
    pub(crate) x: DMatrix<f64>,
    /// The splitting variables and scaled multipliers (K x E each) and the penalty, to
    /// continue from with rows appended.
    pub(crate) state: (DMatrix<f64>, DMatrix<f64>, f64),
    /// ADMM iterations made (`max_iterations` if the residuals did not meet the tolerance).
    pub(crate) iterations: usize,
}

/// The relative dual residual below which an iterate feasible at half the margins is taken.
const FEASIBLE_DUAL: f64 = 1e-3;

/// The fraction of each margin an iterate must keep to be taken early.
const FEASIBLE_MARGIN: f64 = 0.1;

/// Whether `m >= delta I` (a Cholesky factor, else the smallest eigenvalue).
fn at_least(m: &DMatrix<f64>, delta: f64) -> bool {
    let n = m.nrows();
    let shifted = m - DMatrix::<f64>::identity(n, n) * delta;
    shifted.clone().cholesky().is_some()
        || crate::numerics::symmetric_eigen(&shifted).eigenvalues.min() >= 0.0
}

/// `Z_k >= delta I`: `delta I + P_psd(M - delta I)`, the Cholesky test first (most samples are
/// inactive).
fn project_shifted(m: &DMatrix<f64>, delta: f64) -> DMatrix<f64> {
    let n = m.nrows();
    if at_least(m, delta) {
        return m.clone();
    }
    let shifted = m - DMatrix::<f64>::identity(n, n) * delta;
    crate::numerics::project_psd(&shifted) + DMatrix::<f64>::identity(n, n) * delta
}

/// [`project_shifted`] of the symmetric matrix whose entries `pairs` are `values`, written
/// back into `values`: closed forms for n = 1 and 2 (the blocks of most fits), no allocation.
fn project_entries(n: usize, pairs: &[(usize, usize)], values: &mut [f64], delta: f64) {
    match n {
        1 => values[0] = values[0].max(delta),
        2 => {
            // Entries (0,0), (0,1), (1,1) in `pairs` order.
            let at = |i: usize, j: usize| pairs.iter().position(|&p| p == (i, j));
            let (Some(ia), Some(ib), Some(ic)) = (at(0, 0), at(0, 1), at(1, 1)) else {
                return;
            };
            let (a, b, c) = (values[ia] - delta, values[ib], values[ic] - delta);
            let mean = 0.5 * (a + c);
            let radius = (0.25 * (a - c) * (a - c) + b * b).sqrt();
            let (low, high) = (mean - radius, mean + radius);
            if low >= 0.0 {
                return;
            }
            let (pa, pb, pc) = if high <= 0.0 {
                (0.0, 0.0, 0.0)
            } else {
                // high * v v^T, v the unit eigenvector of `high`.
                let (vx, vy) = if (high - c).abs() >= (high - a).abs() {
                    (high - c, b)
                } else {
                    (b, high - a)
                };
                let norm2 = vx * vx + vy * vy;
                if norm2 == 0.0 {
                    (high, 0.0, high)
                } else {
                    (
                        high * vx * vx / norm2,
                        high * vx * vy / norm2,
                        high * vy * vy / norm2,
                    )
                }
            };
            values[ia] = pa + delta;
            values[ib] = pb;
            values[ic] = pc + delta;
        }
        _ => {
            let mut m = DMatrix::zeros(n, n);
            for (e, &(i, j)) in pairs.iter().enumerate() {
                m[(i, j)] = values[e];
                m[(j, i)] = values[e];
            }
            let p = project_shifted(&m, delta);
            for (e, &(i, j)) in pairs.iter().enumerate() {
                values[e] = p[(i, j)];
            }
        }
    }
}

/// Solves the problem of the module docs from `start` (N x E), and from the state of an
/// earlier solve whose rows were the first ones of these (`None`: from scratch).
pub fn lmi_least_squares(
    r: &DMatrix<f64>,
    c: &DMatrix<f64>,
    constraints: &MatrixInequalities,
    start: &DMatrix<f64>,
    previous: Option<&(DMatrix<f64>, DMatrix<f64>, f64)>,
    max_iterations: usize,
    tolerance: f64,
) -> LmiSolution {
    let (n, pairs) = (constraints.n, constraints.pairs);
    let entries = pairs.len();
    // Unit rows.
    let mut rows = constraints.rows.clone();
    let mut margins = constraints.margins.to_vec();
    for (k, margin) in margins.iter_mut().enumerate() {
        let norm = rows.row(k).norm();
        if norm > 0.0 {
            rows.row_mut(k).unscale_mut(norm);
            *margin /= norm;
        }
    }
    let count = rows.nrows();
    let weight = |e: usize| if pairs[e].0 == pairs[e].1 { 1.0 } else { 2.0 };
    let gram_r = r.tr_mul(r);
    let gram_p = rows.tr_mul(&rows);
    let rhs0 = r.tr_mul(c);
    let to_matrix = |values: &DMatrix<f64>, k: usize| {
        let mut m = DMatrix::zeros(n, n);
        for (e, &(i, j)) in pairs.iter().enumerate() {
            m[(i, j)] = values[(k, e)];
            m[(j, i)] = values[(k, e)];
        }
        m
    };
    let mut x = start.clone();
    let mut s = &rows * &x; // K x E
    let mut z = DMatrix::<f64>::zeros(count, entries);
    let mut values = vec![0.0; entries];
    for k in 0..count {
        for (e, v) in values.iter_mut().enumerate() {
            *v = s[(k, e)];
        }
        project_entries(n, pairs, &mut values, margins[k]);
        for (e, v) in values.iter().enumerate() {
            z[(k, e)] = *v;
        }
    }
    let mut u = DMatrix::<f64>::zeros(count, entries);
    let mut rho = (gram_r.trace() / gram_p.trace().max(f64::MIN_POSITIVE)).max(1e-12);
    if let Some((z0, u0, rho0)) = previous {
        let kept = z0.nrows().min(count);
        z.rows_mut(0, kept).copy_from(&z0.rows(0, kept));
        u.rows_mut(0, kept).copy_from(&u0.rows(0, kept));
        rho = *rho0;
    }
    let factor = |rho: f64, w: f64| (&gram_r + &gram_p * (rho * w)).cholesky();
    let mut factors = (factor(rho, 1.0), factor(rho, 2.0));
    let alpha = 1.6;
    let mut iterations = 0;
    let weighted_norm = |m: &DMatrix<f64>| {
        let mut sum = 0.0;
        for e in 0..entries {
            sum += weight(e) * m.column(e).norm_squared();
        }
        sum.sqrt()
    };
    while iterations < max_iterations {
        iterations += 1;
        let v = &z - &u;
        let back = rows.tr_mul(&v); // N x E
        for e in 0..entries {
            let w = weight(e);
            let rhs: DVector<f64> = rhs0.column(e) + back.column(e) * (rho * w);
            let chol = if w == 1.0 { &factors.0 } else { &factors.1 };
            let solved = match chol {
                Some(ch) => ch.solve(&rhs),
                None => {
                    return LmiSolution {
                        x,
                        state: (z, u, rho),
                        iterations,
                    }
                }
            };
            x.column_mut(e).copy_from(&solved);
        }
        s = &rows * &x;
        let relaxed = &s * alpha + &z * (1.0 - alpha);
        let z_old = z.clone();
        for k in 0..count {
            for (e, v) in values.iter_mut().enumerate() {
                *v = relaxed[(k, e)] + u[(k, e)];
            }
            project_entries(n, pairs, &mut values, margins[k]);
            for (e, v) in values.iter().enumerate() {
                z[(k, e)] = *v;
            }
        }
        u += &relaxed - &z;
        let primal = weighted_norm(&(&s - &z));
        let dual = rho * rows.tr_mul(&(&z - &z_old)).norm();
        let primal_scale = weighted_norm(&s).max(weighted_norm(&z)).max(1e-300);
        let dual_scale = (rho * rows.tr_mul(&u).norm()).max(1e-300);
        if primal <= tolerance * primal_scale && dual <= tolerance * dual_scale {
            break;
        }
        // Feasible with half the margin and the objective settled: good enough, and what the
        // exact check afterwards needs (the residual alone may take long to fall below the
        // margin everywhere).
        if iterations % 20 == 0
            && dual <= FEASIBLE_DUAL * dual_scale
            && (0..count).all(|k| at_least(&to_matrix(&s, k), FEASIBLE_MARGIN * margins[k]))
        {
            break;
        }
        if iterations % 10 == 0 {
            let ratio = (primal / primal_scale) / (dual / dual_scale).max(1e-300);
            let change = if ratio > 10.0 {
                2.0
            } else if ratio < 0.1 {
                0.5
            } else {
                1.0
            };
            if change != 1.0 {
                rho *= change;
                u /= change;
                factors = (factor(rho, 1.0), factor(rho, 2.0));
            }
        }
    }
    LmiSolution {
        x,
        state: (z, u, rho),
        iterations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 x 2 symmetric matrix fitted to an indefinite target under `S >= 0`: the nearest PSD
    /// matrix in the weighted norm, which is the Frobenius projection (R = I, one row psi = 1).
    #[test]
    fn the_closed_forms_project_like_the_general_path() {
        let mut rng = crate::numerics::SplitMix64::new(7);
        for n in 1..=2 {
            let pairs: Vec<(usize, usize)> =
                (0..n).flat_map(|i| (i..n).map(move |j| (i, j))).collect();
            for _ in 0..200 {
                let values: Vec<f64> = pairs.iter().map(|_| 2.0 * rng.uniform() - 1.0).collect();
                let delta = 0.1 * rng.uniform();
                let mut m = DMatrix::zeros(n, n);
                for (e, &(i, j)) in pairs.iter().enumerate() {
                    m[(i, j)] = values[e];
                    m[(j, i)] = values[e];
                }
                let general = project_shifted(&m, delta);
                let mut closed = values.clone();
                project_entries(n, &pairs, &mut closed, delta);
                for (e, &(i, j)) in pairs.iter().enumerate() {
                    assert!(
                        (closed[e] - general[(i, j)]).abs() < 1e-12,
                        "{m} {delta}: {closed:?} against {general}"
                    );
                }
            }
        }
    }

    #[test]
    fn one_sample_gives_the_psd_projection() {
        let pairs = [(0, 0), (0, 1), (1, 1)];
        // Target [[1, 2], [2, 1]]: the objective weighs the off-diagonal once, so scale it by
        // sqrt 2 in the data to make the objective the Frobenius norm.
        let r = DMatrix::from_element(1, 1, 1.0);
        let c = DMatrix::from_row_slice(1, 3, &[1.0, 2.0, 1.0]);
        let rows = DMatrix::from_element(1, 1, 1.0);
        let constraints = MatrixInequalities {
            n: 2,
            pairs: &pairs,
            rows: &rows,
            margins: &[0.0],
        };
        let start = DMatrix::zeros(1, 3);
        let out = lmi_least_squares(&r, &c, &constraints, &start, None, 5000, 1e-10);
        assert!(out.iterations < 5000, "{}", out.iterations);
        // Objective: (a - 1)^2 + (b - 2)^2 + (d - 1)^2 over PSD [[a, b], [b, d]]: by symmetry
        // a = d, b = a (the boundary), minimizing 2 (a - 1)^2 + (a - 2)^2: a = 4 / 3.
        let want = [4.0 / 3.0, 4.0 / 3.0, 4.0 / 3.0];
        for (e, want) in want.iter().enumerate() {
            assert!((out.x[(0, e)] - want).abs() < 1e-6, "{}", out.x);
        }
    }

    /// A feasible least-squares solution is left where it is.
    #[test]
    fn a_feasible_minimum_is_kept() {
        let pairs = [(0, 0)];
        let r = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 0.0, 1.0]);
        let c = DMatrix::from_column_slice(2, 1, &[3.0, 1.0]);
        let rows = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 1.0, 1.0]);
        let constraints = MatrixInequalities {
            n: 1,
            pairs: &pairs,
            rows: &rows,
            margins: &[0.0, 0.0],
        };
        let out = lmi_least_squares(
            &r,
            &c,
            &constraints,
            &DMatrix::zeros(2, 1),
            None,
            5000,
            1e-10,
        );
        // R x = c: x = (1, 1), both constraints x_0 >= 0 and x_0 + x_1 >= 0 hold.
        assert!((out.x[(0, 0)] - 1.0).abs() < 1e-6 && (out.x[(1, 0)] - 1.0).abs() < 1e-6);
    }

    /// Margins: the scalar problem min (x - (-1))^2 with x >= 0.5 ends on the margin.
    #[test]
    fn the_margin_is_kept() {
        let pairs = [(0, 0)];
        let r = DMatrix::from_element(1, 1, 1.0);
        let c = DMatrix::from_element(1, 1, -1.0);
        let rows = DMatrix::from_element(1, 1, 2.0);
        let constraints = MatrixInequalities {
            n: 1,
            pairs: &pairs,
            rows: &rows,
            margins: &[1.0],
        };
        let out = lmi_least_squares(
            &r,
            &c,
            &constraints,
            &DMatrix::zeros(1, 1),
            None,
            5000,
            1e-12,
        );
        assert!((out.x[(0, 0)] - 0.5).abs() < 1e-8, "{}", out.x);
    }
}
