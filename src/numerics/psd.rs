//! Projection of a symmetric matrix onto the cone of positive semi-definite matrices (nearest
//! in the Frobenius norm):
//!
//! ```text
//! P(M) = V max(Lambda, 0) V^T,   sym(M) = (M + M^T) / 2 = V Lambda V^T,
//! ```
//!
//! symmetrized once more against rounding. A matrix whose Cholesky factor exists is returned
//! as `sym(M)` unchanged.

use nalgebra::DMatrix;

/// The PSD projection `P(M)` of the module docs.
pub fn project_psd(m: &DMatrix<f64>) -> DMatrix<f64> {
    let sym = (m + m.transpose()) * 0.5;
    if sym.is_empty() || sym.clone().cholesky().is_some() {
        return sym;
    }
    let eigen = crate::numerics::symmetric_eigen(&sym);
    let clipped = eigen.eigenvalues.map(|l| l.max(0.0));
    let v = &eigen.eigenvectors;
    let out = v * DMatrix::from_diagonal(&clipped) * v.transpose();
    (&out + out.transpose()) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positive_definite_matrices_are_only_symmetrized() {
        let m = DMatrix::from_row_slice(2, 2, &[2.0, 0.4, 0.6, 1.0]);
        let p = project_psd(&m);
        assert_eq!(p, DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]));
    }

    #[test]
    fn negative_eigenvalues_are_clipped_to_zero() {
        // Eigenvalues 3 and -1 along (1, 1) / sqrt 2 and (1, -1) / sqrt 2.
        let m = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        let p = project_psd(&m);
        let want = DMatrix::from_row_slice(2, 2, &[1.5, 1.5, 1.5, 1.5]);
        assert!((&p - &want).amax() < 1e-14, "{p}");
        assert_eq!(p, p.transpose());
        // Nearest: the difference is orthogonal to the projection.
        assert!((&m - &p).dot(&p).abs() < 1e-13);
    }

    #[test]
    fn negative_definite_matrices_project_to_zero() {
        let m = DMatrix::from_row_slice(2, 2, &[-1.0, 0.2, 0.2, -3.0]);
        assert!(project_psd(&m).amax() < 1e-15);
    }
}
