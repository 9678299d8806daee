//! The singular value decomposition `M = U diag(sigma) V^T` with a bounded number of
//! iterations. nalgebra's `svd` iterates until convergence and loops without end on some
//! badly scaled matrices (a vector fit of frequencies 6e-300 and 6e300 rad/s); here the
//! implicit-shift QR iteration stops after [`ITERATIONS_PER_VALUE`] steps per singular value,
//! and an empty matrix, a non-finite entry or no convergence gives `None`.

use nalgebra::{linalg::SVD, ComplexField, DMatrix, Dyn};

/// Iterations allowed per singular value (convergence takes two or three on average).
pub const ITERATIONS_PER_VALUE: usize = 100;

/// The convergence threshold of nalgebra's `svd` (5 machine epsilons).
const CONVERGENCE: f64 = 5.0 * f64::EPSILON;

/// The SVD of `m` (real or complex; singular values in descending order), or `None` (module
/// docs).
pub fn svd<T: ComplexField<RealField = f64>>(
    m: DMatrix<T>,
    compute_u: bool,
    compute_v: bool,
) -> Option<SVD<T, Dyn, Dyn>> {
    if m.is_empty() || m.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let limit = ITERATIONS_PER_VALUE * m.nrows().min(m.ncols()).max(10);
    let svd = SVD::try_new(m, compute_u, compute_v, CONVERGENCE, limit)?;
    svd.singular_values
        .iter()
        .all(|s| s.is_finite())
        .then_some(svd)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bounded_svd_reconstructs_its_matrix() {
        let m = DMatrix::from_row_slice(3, 2, &[3.0, 1.0, -2.0, 4.0, 0.5, -1.0]);
        let d = svd(m.clone(), true, true).unwrap();
        let rebuilt = d.u.as_ref().unwrap()
            * DMatrix::from_diagonal(&d.singular_values)
            * d.v_t.as_ref().unwrap();
        assert!((rebuilt - &m).amax() < 1e-14 * m.amax());
        assert!(d.singular_values[0] >= d.singular_values[1]);
    }

    #[test]
    fn the_vector_fits_matrix_that_kept_nalgebras_svd_iterating_has_none() {
        // The relocation system of a vector fit over 6.3e-300 .. 6.3e300 rad/s (WAMIT periods
        // 1e300 and 1e-300 s): its columns' norms overflow and the scaled entries become NaN;
        // nalgebra's `svd` on it did not return within 60 s.
        let nan = f64::NAN;
        let mut rows = vec![vec![f64::INFINITY, nan, nan, nan, nan, nan]];
        for x in [
            3.158e-300, 1.234e-300, 7.896e-301, 5.483e-301, 3.084e-301, 0.0,
        ] {
            rows.push(vec![x, 0.0, nan, nan, 0.0, nan]);
        }
        rows.push(vec![nan, nan, nan, nan, nan, 0.0]);
        for x in [-25.13, -15.71, -12.57, -10.47, -7.854, 0.0] {
            rows.push(vec![x, 0.0, nan, nan, 0.0, 0.0]);
        }
        let m = DMatrix::from_fn(rows.len(), 6, |i, j| rows[i][j]);
        assert!(svd(m, true, true).is_none());
    }

    #[test]
    fn empty_and_non_finite_matrices_have_no_svd() {
        assert!(svd(DMatrix::<f64>::zeros(0, 3), true, true).is_none());
        let m = DMatrix::from_row_slice(2, 2, &[1.0, f64::INFINITY, 0.0, 1.0]);
        assert!(svd(m, true, true).is_none());
    }
}
