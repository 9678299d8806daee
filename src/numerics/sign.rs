//! The matrix sign function by Newton's iteration with determinant scaling (Higham, Functions
//! of Matrices, 5.3 and 5.5):
//!
//! ```text
//! X_0 = M,   X_(k+1) = (mu_k X_k + (mu_k X_k)^-1) / 2,   mu_k = |det X_k|^(-1/n),
//! sign(M) = lim X_k   (sign(M)^2 = I; -I on the stable, +I on the unstable invariant subspace)
//! ```
//!
//! Defined when `M` has no eigenvalue on the imaginary axis. Convergence is quadratic once the
//! eigenvalues are near +-1; the scaling brings them there from any magnitude.

use nalgebra::DMatrix;

/// Largest number of Newton steps of [`matrix_sign`].
const MAX_STEPS: usize = 100;

/// Below this relative change, a change that no longer halves ends the iteration (quadratic
/// convergence would have shrunk it far more): the rounding level is reached.
const STALL: f64 = 1e-5;

/// `sign(M)`, or `None` when an iterate is singular or the iteration has not converged (an
/// eigenvalue on or numerically at the imaginary axis).
pub fn matrix_sign(m: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = m.nrows();
    if n == 0 || m.ncols() != n {
        return (n == 0 && m.ncols() == 0).then(|| m.clone());
    }
    let mut x = m.clone();
    let mut scaled = true;
    let mut previous = f64::INFINITY;
    for _ in 0..MAX_STEPS {
        let lu = x.clone().lu();
        let inverse = lu.try_inverse()?;
        let mu = if scaled {
            let log_det: f64 = lu.u().diagonal().iter().map(|d| d.abs().ln()).sum();
            (-log_det / n as f64).exp()
        } else {
            1.0
        };
        if !mu.is_finite() {
            return None;
        }
        let next = (&x * mu + inverse / mu) * 0.5;
        let change = (&next - &x).norm() / next.norm();
        x = next;
        // Scaling only speeds up the early steps; near convergence it only adds rounding.
        if change < 1e-2 {
            scaled = false;
        }
        // Converged, or converged to the rounding level of an ill-conditioned sign (the
        // change stops falling once it is small).
        if change < 1e-13 || (change < STALL && change > 0.5 * previous) {
            return x.iter().all(|v| v.is_finite()).then_some(x);
        }
        previous = change;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sign_of_a_diagonalizable_matrix_reconstructs_from_its_eigenvalues() {
        // M = V diag(-3, 0.01, 50, -0.2) V^-1: sign(M) = V diag(-1, 1, 1, -1) V^-1.
        let v = DMatrix::from_row_slice(
            4,
            4,
            &[
                1.0, 0.2, -0.3, 0.0, 0.5, 1.0, 0.1, 0.4, -0.2, 0.3, 1.0, 0.2, 0.1, 0.0, 0.6, 1.0,
            ],
        );
        let vi = v.clone().try_inverse().unwrap();
        let d = |x: &[f64]| DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(x));
        let m = &v * d(&[-3.0, 0.01, 50.0, -0.2]) * &vi;
        let expected = &v * d(&[-1.0, 1.0, 1.0, -1.0]) * &vi;
        let s = matrix_sign(&m).unwrap();
        assert!((&s - &expected).norm() < 1e-12, "{s}");
        assert!((&s * &s - DMatrix::identity(4, 4)).norm() < 1e-12);
    }

    #[test]
    fn an_eigenvalue_on_the_imaginary_axis_has_no_sign() {
        // Eigenvalues +-i (a rotation): the iteration cannot converge.
        let m = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]);
        assert!(matrix_sign(&m).is_none());
    }
}
