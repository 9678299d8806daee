//! Eigenvalues of a real square matrix by the real Schur decomposition (Francis QR steps) with
//! a bounded number of iterations; where nalgebra's iteration (which has no exceptional shifts)
//! stalls, faer's (LAPACK's with exceptional shifts) is used. A non-finite entry, or no finite
//! result from either, gives `None` instead of an endless loop; a 0 x 0 matrix has no
//! eigenvalues (nalgebra's Schur indexes out of bounds on it).
//!
//! The symmetric eigendecomposition `M = V diag(lambda) V^T` is checked by its residual
//! `max |M V - V diag(lambda)| <= 1e-10 n max |M|`: nalgebra's can pair an eigenvalue with
//! another's eigenvector (dimforge/nalgebra#1109; seen here on a commutant element of the
//! semicircle's data, residual 1e-3 of the matrix), and then faer's is used.

use nalgebra::{linalg::Schur, linalg::SymmetricEigen, DMatrix, DVector, Dyn};
use num_complex::Complex64;

/// Largest residual of a symmetric eigendecomposition, relative to `n max |M|`.
const SYMMETRIC_RESIDUAL: f64 = 1e-10;

/// The eigendecomposition of the symmetric part of `m` (module docs): eigenvalues in no
/// particular order, orthonormal eigenvectors as columns. nalgebra's iteration is bounded
/// ([`ITERATIONS_PER_ROW`]); where it stops or misses the residual, faer's is used. A matrix
/// with a non-finite entry gets NaN eigenvalues and eigenvectors (no iteration).
pub fn symmetric_eigen(m: &DMatrix<f64>) -> SymmetricEigen<f64, Dyn> {
    let n = m.nrows();
    let sym = (m + m.transpose()) * 0.5;
    if n == 0 || sym.iter().any(|x| !x.is_finite()) {
        return SymmetricEigen {
            eigenvalues: DVector::from_element(n, f64::NAN),
            eigenvectors: DMatrix::from_element(n, n, f64::NAN),
        };
    }
    let limit = ITERATIONS_PER_ROW * n.max(10);
    let residual = |values: &DVector<f64>, vectors: &DMatrix<f64>| {
        (&sym * vectors - vectors * DMatrix::from_diagonal(values)).amax()
    };
    let bound = SYMMETRIC_RESIDUAL * n as f64 * sym.amax();
    if let Some(eigen) = SymmetricEigen::try_new(sym.clone(), f64::EPSILON, limit) {
        if !bound.is_finite() || residual(&eigen.eigenvalues, &eigen.eigenvectors) <= bound {
            return eigen;
        }
    }
    let decomposition = faer::Mat::<f64>::from_fn(n, n, |i, j| sym[(i, j)])
        .selfadjoint_eigendecomposition(faer::Side::Lower);
    let values = decomposition.s().column_vector();
    let vectors = decomposition.u();
    SymmetricEigen {
        eigenvalues: DVector::from_fn(n, |i, _| values.read(i)),
        eigenvectors: DMatrix::from_fn(n, n, |i, j| vectors.read(i, j)),
    }
}

/// Iterations allowed per row of the matrix.
const ITERATIONS_PER_ROW: usize = 100;

/// The eigenvalues of `m`, or `None` (see the module docs).
pub fn eigenvalues(m: &DMatrix<f64>) -> Option<Vec<Complex64>> {
    if !m.is_square() || m.iter().any(|x| !x.is_finite()) {
        return None;
    }
    if m.is_empty() {
        return Some(Vec::new());
    }
    let limit = ITERATIONS_PER_ROW * m.nrows().max(10);
    if let Some(schur) = Schur::try_new(m.clone(), f64::EPSILON, limit) {
        return Some(schur.complex_eigenvalues().iter().copied().collect());
    }
    let n = m.nrows();
    let values: Vec<faer::complex_native::c64> =
        faer::Mat::<f64>::from_fn(n, n, |i, j| m[(i, j)]).eigenvalues();
    let values: Vec<Complex64> = values.iter().map(|z| Complex64::new(z.re, z.im)).collect();
    values.iter().all(|z| z.is_finite()).then_some(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenvalues_of_a_rotation_and_a_scaling() {
        // [[0, -2], [2, 0]] has +-2i; diag(3, -1) has 3 and -1.
        let m = DMatrix::from_row_slice(2, 2, &[0.0, -2.0, 2.0, 0.0]);
        let mut e = eigenvalues(&m).unwrap();
        e.sort_by(|a, b| a.im.total_cmp(&b.im));
        assert!((e[0] - Complex64::new(0.0, -2.0)).norm() < 1e-14);
        assert!((e[1] - Complex64::new(0.0, 2.0)).norm() < 1e-14);
        let d = DMatrix::from_diagonal(&nalgebra::DVector::from_row_slice(&[3.0, -1.0]));
        let mut e = eigenvalues(&d).unwrap();
        e.sort_by(|a, b| a.re.total_cmp(&b.re));
        assert_eq!(e, vec![Complex64::new(-1.0, 0.0), Complex64::new(3.0, 0.0)]);
    }

    #[test]
    fn the_symmetric_eigendecomposition_reconstructs_its_matrix_where_nalgebra_swaps_vectors() {
        // dimforge/nalgebra#1109: nalgebra 0.33's decomposition of this matrix misses it by 6.5e-6
        // of its largest entry (by 340 % when reported).
        let m = DMatrix::from_row_slice(
            4,
            4,
            &[
                -19884.07, -10.07188, 11.277279, -188560.63, -10.07188, 12.518197, 1.3770627,
                -102.97504, 11.277279, 1.3770627, 14.587362, 113.26099, -188560.63, -102.97504,
                113.26099, -1788112.3,
            ],
        );
        let e = symmetric_eigen(&m);
        let rebuilt =
            &e.eigenvectors * DMatrix::from_diagonal(&e.eigenvalues) * e.eigenvectors.transpose();
        assert!((rebuilt - &m).amax() < 1e-9 * m.amax());
        let identity = e.eigenvectors.transpose() * &e.eigenvectors;
        assert!((identity - DMatrix::identity(4, 4)).amax() < 1e-12);
    }

    #[test]
    fn a_non_finite_matrix_has_no_eigenvalues() {
        let m = DMatrix::from_row_slice(2, 2, &[1.0, f64::NAN, 0.0, 1.0]);
        assert!(eigenvalues(&m).is_none());
        let e = symmetric_eigen(&m);
        assert!(e.eigenvalues.iter().all(|x| x.is_nan()));
    }

    #[test]
    fn an_empty_matrix_has_no_eigenvalues_and_no_panic() {
        // nalgebra's Schur of a 0 x 0 matrix indexed out of bounds (a fit of order 0).
        let empty = DMatrix::<f64>::zeros(0, 0);
        assert_eq!(eigenvalues(&empty), Some(Vec::new()));
        assert_eq!(symmetric_eigen(&empty).eigenvalues.len(), 0);
    }
}
