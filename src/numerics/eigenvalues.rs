//! Eigenvalues of a real square matrix by the real Schur decomposition (Francis QR steps) with
//! a bounded number of iterations; where nalgebra's iteration (which has no exceptional shifts)
//! stalls, faer's (LAPACK's with exceptional shifts) is used. A non-finite entry, or no finite
//! result from either, gives `None` instead of an endless loop.

use nalgebra::{linalg::Schur, DMatrix};
use num_complex::Complex64;

/// Iterations allowed per row of the matrix.
const ITERATIONS_PER_ROW: usize = 100;

/// The eigenvalues of `m`, or `None` (see the module docs).
pub fn eigenvalues(m: &DMatrix<f64>) -> Option<Vec<Complex64>> {
    if !m.is_square() || m.iter().any(|x| !x.is_finite()) {
        return None;
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
    fn a_non_finite_matrix_has_no_eigenvalues() {
        let m = DMatrix::from_row_slice(2, 2, &[1.0, f64::NAN, 0.0, 1.0]);
        assert!(eigenvalues(&m).is_none());
    }
}
