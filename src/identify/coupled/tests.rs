//! Tests of the coupled form: weak couplings, invariant blocks, mirror symmetry, `A_inf`
//! cleaning.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::blocks::{invariant_blocks, COMMUTANT_THRESHOLD};
use crate::identify::problem::Problem;
use crate::identify::tests::{coupled_truth, fit_ok, log_grid, stage, unit_mass, G, RHO};
use crate::identify::{CoupledMethod, FitParams, FrequencyResponse, DEFAULT_TOLERANCE};
use crate::network::{Branch, Network, NetworkForm};

#[test]
fn coupled_network_is_reconstructed_with_weak_couplings() {
    let truth = coupled_truth();
    let omega = log_grid(0.2, 12.0, 90);
    let data = FrequencyResponse::from_network(&truth, &omega);
    let report = fit_ok(
        &data,
        &FitParams {
            coupled_method: CoupledMethod::Chains,
            form: Some(NetworkForm::Coupled),
            tolerance: Some(1e-7),
            ..FitParams::default()
        },
    );
    // Five branches with four distinct dynamics: exact at order 4, to 1e-7 of the scale
    // of every entry, the 1e-3 couplings included.
    assert!(report.tolerance_met, "{}", report.max_relative_error);
    assert!(report.order <= 4, "order {}", report.order);
    for i in 0..4 {
        for j in 0..4 {
            assert!(report.max_error[(i, j)] <= 1e-7 * report.error_scale[(i, j)]);
        }
    }
    // The network's TF is symmetric and its damping PSD off the band too.
    for w in [0.01, 50.0] {
        let h = report.network.added_mass_tf(w);
        assert!((&h - h.transpose())
            .iter()
            .all(|z| z.norm() < 1e-9 * unit_mass()));
        let b = h.map(|z| -w * z.im);
        assert!(b.symmetric_eigenvalues().min() > -1e-9 * unit_mass() * w);
    }
}

/// Orthogonal 5 x 5 matrix (Q of a fixed matrix's QR).
fn rotation() -> DMatrix<f64> {
    let m = DMatrix::from_fn(5, 5, |i, j| {
        ((3 * i + 7 * j) % 11) as f64 + 0.3 * (i * j) as f64
    });
    m.qr().q()
}

/// A network of two blocks, DOFs {0, 1} and {2, 3, 4}, seen in the basis `rotation`:
/// every direction and `A_inf` rotated.
fn rotated_block_network(rotation: &DMatrix<f64>) -> Network {
    let branches = [
        ([1.0, 0.4, 0.0, 0.0, 0.0], 0.5, 1.2, 0.5),
        ([0.3, -1.0, 0.0, 0.0, 0.0], 1.1, 2.5, 0.3),
        ([0.0, 0.0, 1.0, 0.5, 0.2], 0.7, 0.9, 0.8),
        ([0.0, 0.0, -0.2, 1.0, 0.6], 0.4, 4.0, 0.6),
        ([0.0, 0.0, 0.5, -0.3, 1.0], 0.6, 1.8, 0.4),
    ]
    .iter()
    .map(|&(d, m, w, z)| Branch {
        direction: rotation * DVector::from_row_slice(&d),
        stages: vec![stage(m * unit_mass(), w, z)],
    })
    .collect();
    let mut a = DMatrix::<f64>::zeros(5, 5);
    a.view_mut((0, 0), (2, 2))
        .copy_from(&DMatrix::from_row_slice(2, 2, &[0.9, 0.2, 0.2, 0.7]));
    a.view_mut((2, 2), (3, 3))
        .copy_from(&DMatrix::from_row_slice(
            3,
            3,
            &[1.2, -0.3, 0.1, -0.3, 0.8, 0.0, 0.1, 0.0, 0.6],
        ));
    Network {
        substructures: Vec::new(),
        dof_names: (1..=5).map(|i| format!("q{i}")).collect(),
        added_mass_inf: rotation * a * rotation.transpose() * unit_mass(),
        branches,
        rho: RHO,
        g: G,
        form: NetworkForm::Coupled,
    }
}

#[test]
fn invariant_blocks_of_a_rotated_block_diagonal_network_are_found() {
    let rotation = rotation();
    let truth = rotated_block_network(&rotation);
    let data = FrequencyResponse::from_network(&truth, &log_grid(0.2, 12.0, 40));
    let target: Vec<DMatrix<Complex64>> = data
        .added_mass
        .iter()
        .map(|a| (a - data.added_mass_inf.map(|x| Complex64::new(x, 0.0))).unscale(unit_mass()))
        .collect();
    let blocks = invariant_blocks(&target, COMMUTANT_THRESHOLD);
    let mut sizes: Vec<usize> = blocks.iter().map(|q| q.ncols()).collect();
    sizes.sort_unstable();
    assert_eq!(sizes, [2, 3]);
    let q = DMatrix::from_fn(5, 5, |i, j| {
        let (mut b, mut c) = (0, j);
        while c >= blocks[b].ncols() {
            c -= blocks[b].ncols();
            b += 1;
        }
        blocks[b][(i, c)]
    });
    // T orthogonal, to rounding.
    assert!((q.tr_mul(&q) - DMatrix::identity(5, 5)).amax() < 1e-12);
    // T^T A~ T block diagonal, to rounding of the O(1) data (per rho pi R^2).
    let first = blocks[0].ncols();
    for t in &target {
        let qc = q.map(|x| Complex64::new(x, 0.0));
        let d = qc.transpose() * t * &qc;
        for i in 0..5 {
            for j in 0..5 {
                if (i < first) != (j < first) {
                    assert!(d[(i, j)].norm() < 1e-12, "{}", d[(i, j)]);
                }
            }
        }
    }
    // The blocks span the rotated coordinate blocks: equal projectors.
    for qb in &blocks {
        let cols = if qb.ncols() == 2 { 0..2 } else { 2..5 };
        let r = rotation.columns(cols.start, cols.len());
        let difference = qb * qb.transpose() - r * r.transpose();
        assert!(difference.amax() < 1e-10, "{}", difference.amax());
    }
    // Data without that structure (1e-3 couplings) is not split.
    let weak = FrequencyResponse::from_network(&coupled_truth(), &log_grid(0.2, 12.0, 40));
    let problem = Problem::new(&weak, (0.0, f64::INFINITY)).unwrap();
    assert_eq!(problem.reduce().split(DEFAULT_TOLERANCE).len(), 1);
}

#[test]
fn mirror_symmetric_network_is_fitted_block_by_block() {
    // DOFs (x1, x2, y1, y2), the mirror swaps x_i and y_i: the symmetric and the
    // antisymmetric motions are invariant blocks in a basis rotated by 45 degrees.
    let branches = [
        ([1.0, 0.3, 1.0, 0.3], 0.5, 1.2, 0.5),
        ([0.2, 1.0, 0.2, 1.0], 0.8, 3.0, 0.3),
        ([1.0, -0.5, -1.0, 0.5], 0.6, 0.8, 0.7),
        ([0.4, 1.0, -0.4, -1.0], 0.3, 2.2, 0.4),
    ]
    .iter()
    .map(|&(d, m, w, z)| Branch {
        direction: DVector::from_row_slice(&d),
        stages: vec![stage(m * unit_mass(), w, z)],
    })
    .collect();
    let a = DMatrix::from_row_slice(
        4,
        4,
        &[
            1.0, 0.2, 0.3, 0.1, 0.2, 0.8, 0.1, -0.2, 0.3, 0.1, 1.0, 0.2, 0.1, -0.2, 0.2, 0.8,
        ],
    );
    let truth = Network {
        substructures: Vec::new(),
        dof_names: vec!["x1".into(), "x2".into(), "y1".into(), "y2".into()],
        added_mass_inf: a * unit_mass(),
        branches,
        rho: RHO,
        g: G,
        form: NetworkForm::Coupled,
    };
    let data = FrequencyResponse::from_network(&truth, &log_grid(0.2, 12.0, 60));
    let problem = Problem::new(&data, (0.0, f64::INFINITY)).unwrap();
    assert_eq!(problem.reduce().split(1e-7).len(), 2);
    let report = fit_ok(
        &data,
        &FitParams {
            coupled_method: CoupledMethod::Chains,
            form: Some(NetworkForm::Coupled),
            tolerance: Some(1e-7),
            ..FitParams::default()
        },
    );
    // Exact data of the same form: met, with the four dynamics of the truth.
    assert!(report.tolerance_met, "{}", report.max_relative_error);
    assert!(report.order <= 4, "order {}", report.order);
    // Every branch lies in one block: mirror-symmetric or antisymmetric, to rounding.
    for b in &report.network.branches {
        let d = &b.direction;
        let mirrored = DVector::from_row_slice(&[d[2], d[3], d[0], d[1]]);
        let off = (&mirrored - d).amax().min((&mirrored + d).amax());
        assert!(off < 1e-9 * d.amax(), "direction {d}");
    }
}

#[test]
fn slightly_asymmetric_or_indefinite_added_mass_inf_is_cleaned() {
    let truth = coupled_truth();
    let mut data = FrequencyResponse::from_network(&truth, &log_grid(0.2, 12.0, 40));
    data.added_mass_inf[(0, 1)] += 1e-6 * unit_mass();
    let report = fit_ok(
        &data,
        &FitParams {
            coupled_method: CoupledMethod::Chains,
            form: Some(NetworkForm::Coupled),
            ..FitParams::default()
        },
    );
    let a = &report.network.added_mass_inf;
    assert_eq!(a, &a.transpose());
    assert!(
        report.added_mass_inf_adjustment > 0.0
            && report.added_mass_inf_adjustment < 1e-6 * unit_mass()
    );
}
