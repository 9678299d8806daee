//! Least squares under linear inequality constraints (Lawson & Hanson, "Solving Least Squares
//! Problems", ch. 23), for small dense problems:
//!
//! ```text
//! min_x |A x - b|^2   subject to   G x >= h,
//! ```
//!
//! `A` (m x n, m >= n) of full column rank. With `A = Q R` and `c = Q^T b`, `y = R x - c`
//! turns it into the least-distance problem `min |y|` subject to `E y >= f`, `E = G R^-1`,
//! `f = h - E c`, whose solution comes from one non-negative least-squares problem:
//! `u = argmin_{u >= 0} |[E^T; f^T] u - (0, .., 0, 1)|`, residual `r`, `y = -r_(1..n) / r_(n+1)`
//! (`r = 0`: the constraints are inconsistent). Then `x = R^-1 (y + c)`. Deterministic.

use super::nnls;
use nalgebra::{DMatrix, DVector};

/// The constrained least-squares solution (module docs); `None` when the constraints admit
/// no point or `A` is rank deficient (a diagonal entry of `R` below 1e-13 of the largest).
/// The dense form of [`triangular_inequality_least_squares`], for the tests.
#[cfg(test)]
pub fn inequality_least_squares(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    g: &DMatrix<f64>,
    h: &DVector<f64>,
) -> Option<DVector<f64>> {
    if a.nrows() < a.ncols() || b.len() != a.nrows() {
        return None;
    }
    let qr = a.clone().qr();
    let c = qr.q().tr_mul(b);
    triangular_inequality_least_squares(&qr.r(), &c, g, h)
}

/// The same for a problem already reduced to `min |R x - c|^2` subject to `G x >= h`, `R`
/// (n x n) upper triangular (as from a QR factorization of `A`, `c = Q^T b`).
pub fn triangular_inequality_least_squares(
    r: &DMatrix<f64>,
    c: &DVector<f64>,
    g: &DMatrix<f64>,
    h: &DVector<f64>,
) -> Option<DVector<f64>> {
    let n = r.ncols();
    if r.nrows() != n || c.len() != n || g.ncols() != n || g.nrows() != h.len() {
        return None;
    }
    let largest = r.diagonal().amax();
    if largest.is_nan() || largest <= 0.0 || r.diagonal().iter().any(|d| d.abs() < 1e-13 * largest)
    {
        return None;
    }
    let unconstrained = r.solve_upper_triangular(c)?;
    if g.nrows() == 0 || (g * &unconstrained - h).iter().all(|v| *v >= 0.0) {
        return Some(unconstrained);
    }
    // E = G R^-1 (rows of G solved against R^T).
    let e = r.tr_solve_upper_triangular(&g.transpose())?.transpose();
    let f = h - &e * c;
    let p = g.nrows();
    let mut m = DMatrix::zeros(n + 1, p);
    m.view_mut((0, 0), (n, p)).copy_from(&e.transpose());
    m.row_mut(n).copy_from(&f.transpose());
    let mut d = DVector::zeros(n + 1);
    d[n] = 1.0;
    let u = nnls(&m, &d);
    let residual = &m * u - d;
    let last = residual[n];
    if residual.norm() <= 1e-12 || last.abs() <= 1e-300 {
        return None;
    }
    let y = -residual.rows(0, n) / last;
    r.solve_upper_triangular(&(y + c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_satisfied_constraint_leaves_the_least_squares_solution() {
        let a = DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
        let b = DVector::from_vec(vec![1.0, 2.0, 3.0]);
        let g = DMatrix::from_row_slice(1, 2, &[1.0, 0.0]);
        let h = DVector::from_vec(vec![-10.0]);
        let x = inequality_least_squares(&a, &b, &g, &h).unwrap();
        let plain = a.clone().svd(true, true).solve(&b, 1e-14).unwrap();
        assert!((x - plain).amax() < 1e-14);
    }

    #[test]
    fn the_closest_point_of_a_half_plane() {
        // min (x - 2)^2 + (y - 2)^2 subject to x + y <= 2: (1, 1).
        let a = DMatrix::identity(2, 2);
        let b = DVector::from_vec(vec![2.0, 2.0]);
        let g = DMatrix::from_row_slice(1, 2, &[-1.0, -1.0]);
        let h = DVector::from_vec(vec![-2.0]);
        let x = inequality_least_squares(&a, &b, &g, &h).unwrap();
        assert!((x - DVector::from_vec(vec![1.0, 1.0])).amax() < 1e-14);
    }

    #[test]
    fn inconsistent_constraints_give_none() {
        // x >= 1 and -x >= 0.
        let a = DMatrix::identity(1, 1);
        let b = DVector::from_vec(vec![0.5]);
        let g = DMatrix::from_row_slice(2, 1, &[1.0, -1.0]);
        let h = DVector::from_vec(vec![1.0, 0.0]);
        assert!(inequality_least_squares(&a, &b, &g, &h).is_none());
    }

    #[test]
    fn random_problems_satisfy_the_optimality_conditions() {
        // KKT: G x >= h; A^T (A x - b) = G^T lambda with lambda >= 0, and lambda_i = 0 where
        // constraint i is inactive. lambda from the active constraints by least squares.
        let mut rng = crate::numerics::SplitMix64::new(7);
        let (mut solved, mut constrained) = (0, 0);
        for _ in 0..50 {
            let (m, n, p) = (12, 5, 6);
            let a = DMatrix::from_fn(m, n, |_, _| rng.uniform() - 0.5);
            let b = DVector::from_fn(m, |_, _| rng.uniform() - 0.5);
            let g = DMatrix::from_fn(p, n, |_, _| rng.uniform() - 0.5);
            let h = DVector::from_fn(p, |_, _| rng.uniform() - 0.2);
            let Some(x) = inequality_least_squares(&a, &b, &g, &h) else {
                continue;
            };
            solved += 1;
            let slack = &g * &x - &h;
            assert!(slack.min() > -1e-10, "{slack}");
            let gradient = a.tr_mul(&(&a * &x - &b));
            let active: Vec<usize> = (0..p).filter(|&i| slack[i] < 1e-9).collect();
            constrained += usize::from(!active.is_empty());
            let ga = DMatrix::from_fn(n, active.len(), |r, c| g[(active[c], r)]);
            let lambda = if active.is_empty() {
                DVector::zeros(0)
            } else {
                ga.clone().svd(true, true).solve(&gradient, 1e-14).unwrap()
            };
            assert!((ga * &lambda - &gradient).amax() < 1e-9, "stationarity");
            assert!(lambda.iter().all(|l| *l > -1e-9), "{lambda}");
        }
        // Most problems are feasible, and most of those bind a constraint.
        assert!(solved >= 40 && constrained >= 20, "{solved} {constrained}");
    }
}
