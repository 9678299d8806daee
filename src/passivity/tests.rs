use super::*;
use crate::network::Network;

const SEED: &str = include_str!("../../examples/networks/seed_2dof.xml");
const NINE_DOF: &str = include_str!("../../examples/networks/semicircle_9dof.xml");
const NINE_DOF_CHAINS: &str = include_str!("../../examples/networks/semicircle_9dof_chains.xml");
const TWO_DOF: &str = include_str!("../../examples/networks/two-dof-sway-heave.xml");

fn system(text: &str) -> StateSpace {
    Network::from_xml_str(text, "test.xml")
        .unwrap()
        .state_space()
        .unwrap()
}

/// The smallest eigenvalue of Re Z(i omega) (real symmetric for these reciprocal networks).
fn smallest(system: &StateSpace, omega: f64) -> f64 {
    let z = -system.transfer(Complex64::new(0.0, omega));
    let re = (&z + z.adjoint()).map(|x| x.re) * 0.5;
    re.symmetric_eigenvalues().min()
}

#[test]
fn fitted_networks_are_passive_at_every_frequency() {
    for (name, text) in [
        ("seed", SEED),
        ("9 DOF", NINE_DOF),
        ("9 DOF chains", NINE_DOF_CHAINS),
        ("2 DOF", TWO_DOF),
    ] {
        let s = system(text);
        let report = check(&s, 1e-9);
        assert!(report.stable, "{name}");
        assert!(report.passive, "{name}: {report:?}");
        // A dense sample agrees: nothing below -1e-12 of the scale.
        for k in 0..2000 {
            let omega = 1e-3 * 1e7f64.powf(k as f64 / 1999.0);
            assert!(
                smallest(&s, omega) >= -1e-12 * report.scale,
                "{name} at {omega}"
            );
        }
    }
}

#[test]
fn a_negative_damping_is_found_with_its_crossing_frequencies() {
    // Z - delta I: Re Z(omega) = b(omega) of Schilder et al.'s sway chain rises from 0 (omega = 0) to
    // its first damper at high frequency; below delta it is negative. The crossings are where
    // b(omega) = delta, found here by bisection on the transfer function.
    let mut s = system(SEED);
    let report = check(&s, 1e-9);
    assert!(report.passive);
    let high = smallest(&s, 1e4);
    let delta = 0.3 * high;
    s.d += DMatrix::identity(1, 1) * delta;
    let report = check(&s, 1e-9);
    assert!(!report.passive, "{report:?}");
    assert!(report.min_eigenvalue < -0.1 * delta / report.scale);
    // Every sign change of Re Z - delta on a dense grid is a reported crossing (to 1e-6).
    let grid: Vec<f64> = (0..4000)
        .map(|k| 1e-3 * 1e6f64.powf(k as f64 / 3999.0))
        .collect();
    let mut expected = Vec::new();
    for pair in grid.windows(2) {
        let (mut a, mut b) = (pair[0], pair[1]);
        if smallest(&s, a).signum() == smallest(&s, b).signum() {
            continue;
        }
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            if smallest(&s, m).signum() == smallest(&s, a).signum() {
                a = m;
            } else {
                b = m;
            }
        }
        expected.push(0.5 * (a + b));
    }
    assert!(!expected.is_empty());
    for w in &expected {
        assert!(
            report.crossings.iter().any(|c| (c - w).abs() <= 1e-6 * w),
            "{w} not in {:?}",
            report.crossings
        );
    }
}

#[test]
fn an_unstable_network_is_not_passive() {
    let mut s = system(SEED);
    // Flip the sign of the damping terms of the state matrix: energy grows.
    let n = s.state_count();
    for i in 0..n {
        s.a[(i, i)] = s.a[(i, i)].abs() + 1e-3;
    }
    let report = check(&s, 1e-9);
    assert!(!report.stable && !report.passive);
}

#[test]
fn a_negative_direct_damper_is_found_at_infinite_frequency() {
    // A damper of -c straight to the hull (no states): Re Z = -c at every frequency.
    let mut s = system(SEED);
    s.d = DMatrix::from_element(1, 1, 1.0);
    let report = check(&s, 1e-9);
    assert!(!report.passive);
    assert!(report.min_eigenvalue < 0.0);
}

#[test]
fn a_realization_without_states_is_checked_without_panic() {
    // A fit of order 0 (A_inf only): nalgebra's Schur of the 0 x 0 state matrix indexed out of
    // bounds. A positive direct damper alone is passive.
    let empty = DMatrix::<f64>::zeros(0, 0);
    let (b, c) = (DMatrix::zeros(0, 1), DMatrix::zeros(1, 0));
    let d = DMatrix::from_element(1, 1, -2.0);
    let report = check_realization(
        &Realization {
            a: &empty,
            b: &b,
            c: &c,
            d: &d,
        },
        1e-9,
    );
    assert!(report.stable && report.passive, "{report:?}");
    assert!(report.slowest_pole.is_none());
}
