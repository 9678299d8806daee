//! Non-negative least squares (Lawson-Hanson active set), for small dense problems:
//!
//! ```text
//! min_x |A x - b|^2   subject to   x >= 0.
//! ```
//!
//! Each outer step frees the bound variable with the largest gradient `w = A^T (b - A x)`
//! above `1e-12 |A|_max |b|_max rows`, solves the unconstrained problem on the free set (SVD),
//! and steps back to the boundary while a free variable would turn negative. At most
//! `3 n + 3` outer and inner steps.

use nalgebra::{DMatrix, DVector};

/// The non-negative least-squares solution of `A x = b` (see the module docs).
pub fn nnls(a: &DMatrix<f64>, b: &DVector<f64>) -> DVector<f64> {
    let n = a.ncols();
    let mut x = DVector::zeros(n);
    let mut passive = vec![false; n];
    let tol = 1e-12 * a.amax().max(1e-300) * b.amax().max(1e-300) * a.nrows() as f64;
    let solve_passive = |passive: &[bool]| -> DVector<f64> {
        let idx: Vec<usize> = (0..n).filter(|&j| passive[j]).collect();
        let sub = DMatrix::from_fn(a.nrows(), idx.len(), |r, c| a[(r, idx[c])]);
        let mut z = DVector::zeros(n);
        let solution = crate::numerics::svd(sub, true, true).map(|svd| svd.solve(b, 1e-14));
        if let Some(Ok(sol)) = solution {
            for (c, &j) in idx.iter().enumerate() {
                z[j] = sol[c];
            }
        }
        z
    };
    for _ in 0..3 * n + 3 {
        let w = a.tr_mul(&(b - a * &x));
        let candidate = (0..n)
            .filter(|&j| !passive[j] && w[j] > tol)
            .max_by(|&i, &j| w[i].total_cmp(&w[j]));
        let Some(j) = candidate else { break };
        passive[j] = true;
        for _ in 0..3 * n + 3 {
            let z = solve_passive(&passive);
            if (0..n).all(|j| !passive[j] || z[j] > 0.0) {
                x = z;
                break;
            }
            let mut alpha: f64 = 1.0;
            for j in 0..n {
                if passive[j] && z[j] <= 0.0 {
                    alpha = alpha.min(x[j] / (x[j] - z[j]));
                }
            }
            x += (z - &x) * alpha;
            for j in 0..n {
                if passive[j] && x[j] <= 1e-15 {
                    passive[j] = false;
                    x[j] = 0.0;
                }
            }
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positive_least_squares_solution_is_kept() {
        let a = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0]);
        let x_true = DVector::from_vec(vec![0.7, 1.3]);
        let b = &a * &x_true;
        let x = nnls(&a, &b);
        assert!((&x - &x_true).amax() < 1e-12, "{x}");
    }

    #[test]
    fn negative_components_are_held_at_zero_with_the_kkt_conditions() {
        // Unconstrained solution (1, -1): the constrained one has x2 = 0.
        let a = DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
        let b = DVector::from_vec(vec![1.0, -1.0, 0.0]);
        let x = nnls(&a, &b);
        assert!(x.iter().all(|&v| v >= 0.0));
        assert_eq!(x[1], 0.0);
        // KKT: gradient w = A^T (b - A x) is zero on the free set, <= 0 on the bound set.
        let w = a.tr_mul(&(&b - &a * &x));
        assert!(w[0].abs() < 1e-12, "{w}");
        assert!(w[1] <= 1e-12, "{w}");
        assert!((x[0] - 0.5).abs() < 1e-12, "{x}");
    }

    #[test]
    fn all_negative_data_gives_zero() {
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 0.5, 0.2, 1.0]);
        let b = DVector::from_vec(vec![-1.0, -2.0]);
        assert_eq!(nnls(&a, &b), DVector::zeros(2));
    }
}
