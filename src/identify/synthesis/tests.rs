use super::*;
use crate::identify::tests::{coupled_truth, log_grid, stage, unit_mass};
use crate::identify::vector_fitting::{passive_vector_fit, VectorFitParams};
use crate::identify::FrequencyResponse;
use crate::network::{Branch, Network, NetworkForm};
use nalgebra::DVector;

/// Largest `|A~_net - A~_truth|` over `omega`, entry (i, j) divided by `sqrt(s_i s_j)`.
fn network_error(net: &Network, truth: &FrequencyResponse, scales: &DVector<f64>) -> f64 {
    let mut worst: f64 = 0.0;
    for (omega, target) in truth.omega.iter().zip(&truth.added_mass) {
        let got = net.added_mass_tf(*omega);
        for i in 0..scales.len() {
            for j in 0..scales.len() {
                worst = worst
                    .max((got[(i, j)] - target[(i, j)]).norm() / (scales[i] * scales[j]).sqrt());
            }
        }
    }
    worst
}

/// Fits `truth` passively with the given poles, realizes the fit and checks the substructure:
/// same transfer as the fit, the network made of it reproduces the data, and the exact
/// passivity check passes on its state space.
fn assert_synthesis(truth: &Network, omega: &[f64], pairs: usize, real: usize, exact: f64) {
    let data = FrequencyResponse::from_network(truth, omega);
    let params = VectorFitParams {
        complex_pairs: pairs,
        real_poles: real,
        ..VectorFitParams::default()
    };
    let (fit, enforcement) = passive_vector_fit(&data, &params).unwrap();
    assert!(enforcement.passive, "{enforcement:?}");
    let (sub, report) = synthesize(&fit).unwrap();
    assert_eq!(
        report.springs + report.masses,
        fit.state_count(),
        "{report:?}"
    );
    assert!(report.structure_residual < 1e-8, "{report:?}");
    assert!(report.projection < 1e-8, "{report:?}");
    // The realization is the fit, to the damper to the ground added for the Riccati equation:
    // 1e-8 of the impedance's scale, seen as delta / omega in the added mass, which at 0.3
    // times the slowest pole is about 1e-6 of the entry scales (measured 1.4e-6 at most).
    assert!(report.deviation < 1e-5, "{report:?}");
    let net = Network::from_substructures(
        truth.dof_names.clone(),
        truth.added_mass_inf.clone(),
        vec![sub],
        truth.rho,
        truth.g,
    );
    net.validate().unwrap();
    let error = network_error(&net, &data, &fit.dof_scales);
    assert!(
        error < exact,
        "network error {error:e}, fit {:e}",
        fit.max_error
    );
    let ss = net.state_space().unwrap();
    let passivity = crate::passivity::check(&ss, 1e-9);
    assert!(passivity.passive && passivity.stable, "{passivity:?}");
}

#[test]
fn a_coupled_network_is_realized_again_from_its_exact_fit() {
    // 4 DOFs, 5 one-stage branches with 4 distinct dynamics: 4 pairs fit it exactly.
    assert_synthesis(&coupled_truth(), &log_grid(0.2, 12.0, 60), 4, 0, 1e-6);
}

#[test]
fn overdamped_chains_give_real_poles_and_are_realized() {
    // Two DOFs; one overdamped branch (two real poles) and one two-stage chain (two pairs).
    let truth = Network {
        dof_names: vec!["sway".into(), "heave".into()],
        added_mass_inf: DMatrix::from_row_slice(2, 2, &[1.0, 0.1, 0.1, 0.8]) * unit_mass(),
        branches: vec![
            Branch {
                direction: DVector::from_row_slice(&[1.0, 0.3]),
                stages: vec![stage(0.6 * unit_mass(), 1.0, 1.8)],
            },
            Branch {
                direction: DVector::from_row_slice(&[-0.2, 1.0]),
                stages: vec![
                    stage(0.5 * unit_mass(), 2.0, 0.3),
                    stage(0.3 * unit_mass(), 4.0, 0.2),
                ],
            },
        ],
        substructures: Vec::new(),
        rho: 1025.0,
        g: 9.81,
        form: NetworkForm::Coupled,
    };
    assert_synthesis(&truth, &log_grid(0.1, 20.0, 80), 2, 2, 1e-6);
}

#[test]
fn a_fit_that_is_not_passive_has_no_storage_function() {
    // One DOF, one pair whose residue makes Re Z < 0 near the pole: G = r/(s-p) + conj with
    // r purely imaginary and of the wrong sign.
    let fit = RationalFit {
        poles: vec![Complex64::new(-0.1, 1.0)],
        residues: vec![DMatrix::from_element(1, 1, Complex64::new(0.0, 1.0))],
        dof_scales: DVector::from_element(1, 1.0),
        max_error: 0.0,
    };
    assert!(!fit.passivity(1e-9).passive);
    let err = synthesize(&fit).unwrap_err();
    assert!(matches!(err, IdentifyError::Synthesis(_)), "{err}");
}

#[test]
fn the_reciprocal_storage_stops_at_its_rounding_level() {
    // T = diag(1, 1, -1), P symmetric positive definite: Newton's sign iteration on T P, which
    // converges to P = T P^-1 T. A change below 0 is unreachable, so only the stall ends it.
    let t = DMatrix::from_diagonal(&nalgebra::DVector::from_row_slice(&[1.0, 1.0, -1.0]));
    let a = DMatrix::from_row_slice(3, 3, &[2.0, 0.3, -0.5, 0.1, 1.5, 0.4, 0.7, -0.2, 3.0]);
    let p = &a * a.transpose() + DMatrix::identity(3, 3) * 1e-3;
    for tolerance in [1e-13, 0.0] {
        let storage = reciprocal_storage(p.clone(), &t, tolerance).unwrap();
        let mirrored = &t * storage.clone().try_inverse().unwrap() * &t;
        assert!((&storage - mirrored).norm() < 1e-12 * storage.norm());
        assert!(storage.clone().cholesky().is_some());
    }
}
