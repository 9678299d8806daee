//! The reduced subspace of the normalized target and its invariant blocks (see
//! [`crate::identify`]): the commutant
//!
//! ```text
//! C = { X = X^T :  X M = M X  for every M in { Re T(omega_k), Im T(omega_k) } }
//! ```
//!
//! as a null space; the eigenspaces of a generic element of `C` are the blocks.

use nalgebra::DMatrix;
use num_complex::Complex64;

use super::groups::GroupSet;
use super::weights::residual_matrix;
use crate::identify::problem::Problem;
use crate::numerics::SplitMix64;

/// Singular values of the commutator map below this fraction of the largest span the
/// commutant.
pub(in crate::identify) const COMMUTANT_THRESHOLD: f64 = 1e-6;

/// Largest coupling between invariant blocks (normalized) that the split may drop, as a
/// fraction of the tolerance.
pub(super) const BLOCK_COUPLING: f64 = 1e-3;

/// Eigenvalues of a generic commutant element closer than this fraction of their spread
/// belong to one block.
pub(in crate::identify) const BLOCK_GAP: f64 = 1e-4;

/// Eigenvalues of the target's Gram matrix below this fraction of the largest are dropped.
pub(super) const REDUCTION_TOLERANCE: f64 = 1e-12;

impl Problem {
    /// The normalized target in the subspace its entries span (rank r <= n), once.
    pub(super) fn reduce(&self) -> Reduced {
        let n = self.n();
        let mut gram = DMatrix::<f64>::zeros(n, n);
        for t in &self.target {
            let (re, im) = (t.map(|z| z.re), t.map(|z| z.im));
            gram += &re * re.transpose() + &im * im.transpose();
        }
        let eigen = crate::numerics::symmetric_eigen(&gram);
        let largest = eigen.eigenvalues.amax();
        let mut keep: Vec<usize> = (0..n)
            .filter(|&i| eigen.eigenvalues[i] > REDUCTION_TOLERANCE * largest)
            .collect();
        keep.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
        if keep.is_empty() {
            keep.push(0);
        }
        let basis = DMatrix::from_fn(n, keep.len(), |i, c| eigen.eigenvectors[(i, keep[c])]);
        let target = self
            .target
            .iter()
            .map(|t| {
                let b = basis.map(|x| Complex64::new(x, 0.0));
                let r = b.transpose() * t * &b;
                (&r + r.transpose()) * Complex64::new(0.5, 0.0)
            })
            .collect();
        Reduced { basis, target }
    }
}

/// The normalized target in the subspace `basis` (n x r, orthonormal columns) it spans.
#[derive(Clone)]
pub(super) struct Reduced {
    pub(super) basis: DMatrix<f64>,
    pub(super) target: Vec<DMatrix<Complex64>>,
}

impl Reduced {
    /// The invariant blocks of the target (see [`invariant_blocks`]), or the whole subspace
    /// if there are none or if dropping the couplings between them would cost more than
    /// [`BLOCK_COUPLING`] times the tolerance (normalized, in the original DOFs).
    pub(super) fn split(&self, tolerance: f64) -> Vec<Reduced> {
        let whole = vec![self.clone()];
        let blocks = invariant_blocks(&self.target, COMMUTANT_THRESHOLD);
        if blocks.len() < 2 {
            return whole;
        }
        let complex = |m: &DMatrix<f64>| m.map(|x| Complex64::new(x, 0.0));
        let projectors: Vec<DMatrix<Complex64>> = blocks
            .iter()
            .map(|q| complex(&(q * q.transpose())))
            .collect();
        let basis = complex(&self.basis);
        let mut dropped: f64 = 0.0;
        for t in &self.target {
            let mut rest = t.clone();
            for p in &projectors {
                rest -= p * t * p;
            }
            let rest = &basis * rest * basis.transpose();
            dropped = dropped.max(rest.iter().map(|z| z.norm()).fold(0.0, f64::max));
        }
        if dropped > BLOCK_COUPLING * tolerance {
            return whole;
        }
        blocks
            .iter()
            .map(|q| {
                let qc = complex(q);
                Reduced {
                    basis: &self.basis * q,
                    target: self
                        .target
                        .iter()
                        .map(|t| {
                            let r = qc.transpose() * t * &qc;
                            (&r + r.transpose()) * Complex64::new(0.5, 0.0)
                        })
                        .collect(),
                }
            })
            .collect()
    }

    /// Largest normalized entry error of PSD-weighted groups, in the original DOFs.
    pub(super) fn max_error(&self, nu: &[f64], groups: &GroupSet, weights: &[DMatrix<f64>]) -> f64 {
        self.frequency_errors(nu, groups, weights)
            .into_iter()
            .fold(0.0, f64::max)
    }

    /// The same per band point.
    pub(super) fn frequency_errors(
        &self,
        nu: &[f64],
        groups: &GroupSet,
        weights: &[DMatrix<f64>],
    ) -> Vec<f64> {
        let basis = self.basis.map(|x| Complex64::new(x, 0.0));
        (0..nu.len())
            .map(|k| {
                let e = residual_matrix(nu, &self.target, groups, weights, k);
                (&basis * e * basis.transpose())
                    .iter()
                    .map(|z| z.norm())
                    .fold(0.0, f64::max)
            })
            .collect()
    }
}

/// Commutant of the normalized target: an orthonormal basis (Frobenius) of the symmetric
/// `X` with `X M = M X` for `M = Re T_k, Im T_k` at every band point, the right singular
/// vectors of the stacked commutator map whose singular values are at most `threshold` times
/// the largest. Unknowns: the `r (r + 1) / 2` entries of the upper triangle.
pub(super) fn commutant(target: &[DMatrix<Complex64>], threshold: f64) -> Vec<DMatrix<f64>> {
    let r = target[0].nrows();
    // Symmetric unit matrices E_ab, orthonormal in the Frobenius product.
    let units: Vec<DMatrix<f64>> = (0..r)
        .flat_map(|b| (0..=b).map(move |a| (a, b)))
        .map(|(a, b)| {
            let mut e = DMatrix::zeros(r, r);
            if a == b {
                e[(a, a)] = 1.0;
            } else {
                e[(a, b)] = std::f64::consts::FRAC_1_SQRT_2;
                e[(b, a)] = std::f64::consts::FRAC_1_SQRT_2;
            }
            e
        })
        .collect();
    let m = units.len();
    // Rows: the commutators [E_ab, M] (antisymmetric) by their strict upper triangle, times
    // sqrt 2 (the Frobenius norm), for every M.
    let block = r * (r - 1) / 2;
    let mut map = DMatrix::<f64>::zeros(2 * target.len() * block, m);
    for (k, t) in target.iter().enumerate() {
        for (part, matrix) in [t.map(|z| z.re), t.map(|z| z.im)].iter().enumerate() {
            let offset = (2 * k + part) * block;
            for (c, e) in units.iter().enumerate() {
                let commutator = e * matrix - matrix * e;
                let mut row = offset;
                for j in 0..r {
                    for i in 0..j {
                        map[(row, c)] = commutator[(i, j)] * std::f64::consts::SQRT_2;
                        row += 1;
                    }
                }
            }
        }
    }
    // At least 3 band points and r >= 2: more rows than unknowns, so V is complete.
    let Some(svd) = crate::numerics::svd(map, false, true) else {
        return Vec::new();
    };
    let Some(v_t) = svd.v_t.filter(|v| v.nrows() == m) else {
        return Vec::new();
    };
    let largest = svd.singular_values.amax();
    (0..m)
        .filter(|&c| svd.singular_values[c] <= threshold * largest)
        .map(|c| {
            units
                .iter()
                .zip(v_t.row(c).iter())
                .fold(DMatrix::zeros(r, r), |acc, (e, x)| acc + e * *x)
        })
        .collect()
}

/// Orthogonal split of the reduced space into subspaces that every target matrix leaves
/// invariant (see the module docs): orthonormal bases (r x r_b), or one block (the identity)
/// if the data has no such structure.
pub(in crate::identify) fn invariant_blocks(
    target: &[DMatrix<Complex64>],
    threshold: f64,
) -> Vec<DMatrix<f64>> {
    invariant_blocks_with_gap(target, threshold, BLOCK_GAP)
}

/// [`invariant_blocks`] with eigenvalues of the generic element closer than `gap` times
/// their spread taken as one (noisy data: a looser threshold needs a wider gap).
pub(in crate::identify) fn invariant_blocks_with_gap(
    target: &[DMatrix<Complex64>],
    threshold: f64,
    gap: f64,
) -> Vec<DMatrix<f64>> {
    let r = target[0].nrows();
    let whole = vec![DMatrix::identity(r, r)];
    if r < 2 {
        return whole;
    }
    let null = commutant(target, threshold);
    if null.len() < 2 {
        return whole;
    }
    // A generic element: every eigenspace is invariant under the data.
    let mut rng = SplitMix64::new(0x5EED_B10C);
    let generic = null.iter().fold(DMatrix::zeros(r, r), |acc, x| {
        acc + x * (1.0 + rng.uniform())
    });
    let eigen = crate::numerics::symmetric_eigen(&generic);
    let mut order: Vec<usize> = (0..r).collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let spread = eigen.eigenvalues.max() - eigen.eigenvalues.min();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        let new = k == 0 || eigen.eigenvalues[i] - eigen.eigenvalues[order[k - 1]] > gap * spread;
        if new {
            groups.push(vec![i]);
        } else if let Some(last) = groups.last_mut() {
            last.push(i);
        }
    }
    if groups.len() < 2 {
        return whole;
    }
    groups
        .iter()
        .map(|g| DMatrix::from_fn(r, g.len(), |i, c| eigen.eigenvectors[(i, g[c])]))
        .collect()
}
