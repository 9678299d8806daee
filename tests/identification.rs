//! Identification on the panel method's own semicircle data: the done-when targets of the
//! identification, checked on a sweep computed here (default panels, 120 log-spaced kR from
//! 0.01 to 4.5).

use hydrofmu::hull::Hull;
use hydrofmu::identify::{self, FitParams, FrequencyResponse};
use hydrofmu::network::NetworkForm;
use hydrofmu::sweep::{self, SweepParams};
use hydrofmu::units;
use std::f64::consts::PI;
use std::sync::OnceLock;

mod common;

const RHO: f64 = 1025.0;
const G: f64 = 9.81;

/// A sweep of the built-in semicircle (R = 1 m).
fn semicircle_sweep(params: &SweepParams) -> sweep::SweepResult {
    sweep::run(&Hull::semicircle(1.0).unwrap(), params, &|_, _| {}).unwrap()
}

fn semicircle() -> &'static FrequencyResponse {
    static DATA: OnceLock<FrequencyResponse> = OnceLock::new();
    DATA.get_or_init(|| {
        let params = SweepParams {
            kr: sweep::log_grid(0.01, 4.5, 120).unwrap(),
            ..SweepParams::default()
        };
        let result = semicircle_sweep(&params);
        assert!(result.failures.is_empty());
        FrequencyResponse::from_sweep(&result, RHO, G)
    })
}

fn omega_of(kr: f64) -> f64 {
    units::omega_from_kr(kr, 1.0, G)
}

#[test]
fn semicircle_sway_two_mass_chain_is_within_one_percent() {
    let sway = semicircle().select(&["sway"]).unwrap();
    let params = FitParams {
        form: Some(NetworkForm::SeriesChain),
        band: (omega_of(0.01) * 0.999, omega_of(4.0) * 1.001),
        order: Some(2),
        ..FitParams::default()
    };
    let report = identify::fit(&sway, &params).unwrap();
    let unit_mass = RHO * PI;
    // Target: max error <= 1 % of rho pi R^2 over kR 0.01 .. 4 (measured 0.49 %).
    assert!(
        report.max_error[(0, 0)] <= 0.01 * unit_mass,
        "{}",
        report.max_error[(0, 0)] / unit_mass
    );
    assert_eq!(report.aux_dofs, 2);
    report.network.validate().unwrap();
}

#[test]
fn semicircle_full_coupled_network_is_within_one_percent_per_entry() {
    // The fmu-pack default: all 9 DOFs, the default tolerance (1 % of sqrt(s_i s_j)), band
    // from kR 0.05 to the sweep's end (4.5 here, 5 in fmu-pack).
    let params = FitParams {
        form: Some(NetworkForm::Coupled),
        band: (omega_of(0.05) * 0.999, omega_of(4.5) * 1.001),
        ..FitParams::default()
    };
    let data = semicircle();
    let report = identify::fit(data, &params).unwrap();
    eprintln!(
        "coupled 9x9: order {}, {} auxiliary DOFs, {} branches, max relative error {:.4}",
        report.order,
        report.aux_dofs,
        report.network.branches.len(),
        report.max_relative_error
    );
    assert!(report.tolerance_met, "{}", report.max_relative_error);
    report.network.validate().unwrap();
    assert_stable(&report.network);
    // The fit splits the data into the mirror's invariant blocks: every branch moves the hull
    // symmetrically or antisymmetrically. The mirror x -> -x maps sway -> -sway,
    // heave -> heave, roll -> -roll, cb1 <-> cb4 (u), cb2 <-> -cb5 (w), cb3 <-> -cb6 (psi).
    let index = |name: &str| data.dof_names.iter().position(|d| d == name).unwrap();
    let mirror = [
        ("sway", "sway", -1.0),
        ("heave", "heave", 1.0),
        ("roll", "roll", -1.0),
        ("cb1", "cb4", 1.0),
        ("cb2", "cb5", -1.0),
        ("cb3", "cb6", -1.0),
        ("cb4", "cb1", 1.0),
        ("cb5", "cb2", -1.0),
        ("cb6", "cb3", -1.0),
    ];
    for branch in &report.network.branches {
        let d = &branch.direction;
        let mut mirrored = d.clone();
        for (from, to, sign) in mirror {
            mirrored[index(to)] = sign * d[index(from)];
        }
        // The data is mirror-symmetric to rounding; directions are unit vectors.
        let off = (&mirrored - d).amax().min((&mirrored + d).amax());
        assert!(
            off < 1e-8,
            "direction {d} is neither symmetric nor antisymmetric"
        );
    }
}

/// Every pole of the network's state space is in the closed left half plane (the exact
/// check's eigenvalues: a bounded Schur iteration, where nalgebra's own may not return on a
/// defective state matrix).
fn assert_stable(network: &hydrofmu::network::Network) {
    let check = hydrofmu::passivity::check(&network.state_space().unwrap(), 1e-9);
    assert!(check.stable, "unstable pole: {check:?}");
}

#[test]
fn net_flux_modes_with_log_divergent_added_mass_fit_within_their_band() {
    // heave, cb2 and cb5 carry net flux: A~ diverges like ln kR as kR -> 0. A finite network
    // cannot follow that below its band, but it meets the tolerance inside it and stays
    // passive (measured 0.42 % for heave, 0.33 % for cb2 with 3 added DOFs).
    for dof in ["heave", "cb2", "cb5"] {
        let data = semicircle().select(&[dof]).unwrap();
        let params = FitParams {
            form: Some(NetworkForm::SeriesChain),
            band: (omega_of(0.01) * 0.999, omega_of(4.0) * 1.001),
            ..FitParams::default()
        };
        let report = identify::fit(&data, &params).unwrap();
        assert!(report.tolerance_met, "{dof}: {}", report.max_relative_error);
        assert!(
            report.band.0 >= omega_of(0.01) * 0.999,
            "{dof}: band not honoured"
        );
        assert_stable(&report.network);
        // The network's zero-frequency mass is finite, where the data keeps growing.
        let zero = report.network.added_mass_zero()[(0, 0)];
        assert!(zero.is_finite() && zero > 0.0, "{dof}: {zero}");
    }
}

#[test]
fn submerged_circle_with_negative_added_mass_fits_within_tolerance() {
    let hull = Hull::circle(1.0, 1.1).unwrap();
    let params = SweepParams {
        kr: sweep::log_grid(0.05, 5.0, 60).unwrap(),
        panels: hydrofmu::panels::PanelParams::for_hull(&hull),
        ..SweepParams::default()
    };
    let result = sweep::run(&hull, &params, &|_, _| {}).unwrap();
    let data = FrequencyResponse::from_sweep(&result, RHO, G)
        .select(&["sway"])
        .unwrap();
    // The data does have negative added mass over a band.
    assert!(data.added_mass.iter().any(|m| m[(0, 0)].re < 0.0));
    let chain = FitParams {
        form: Some(NetworkForm::SeriesChain),
        ..FitParams::default()
    };
    let report = identify::fit(&data, &chain).unwrap();
    assert!(report.tolerance_met, "{}", report.max_relative_error);
    assert_stable(&report.network);
}

#[test]
fn irregular_frequency_spikes_never_reach_the_fitted_data() {
    // The pipeline fits the default sweep, which removes irregular frequencies; a fine scan
    // across the first two (kR = 1.8182 symmetric, 3.2523 antisymmetric) stays smooth.
    assert_eq!(
        SweepParams::default().irregular_frequencies,
        hydrofmu::bem::IrregularFrequencies::RemoveWithLid
    );
    for centre in [1.8182, 3.2523] {
        let params = SweepParams {
            kr: sweep::log_grid(centre - 0.01, centre + 0.01, 21).unwrap(),
            ..SweepParams::default()
        };
        let result = semicircle_sweep(&params);
        let worst = result
            .added_mass
            .windows(3)
            .flat_map(|w| {
                (0..2).map(move |i| (w[1][(i, i)] - (w[0][(i, i)] + w[2][(i, i)]) * 0.5).norm())
            })
            .fold(0.0, f64::max);
        // Smooth: second differences ~ (dkR)^2 |A''| ~ 1e-6; a spike measures 0.03 or more.
        assert!(worst < 1e-4, "kR {centre}: second difference {worst}");
    }
}

#[test]
fn over_fitted_orders_are_refused_and_automatic_fits_stay_resolvable() {
    // Forcing many more stages than the data needs drives one to a negligible mass with
    // extreme stiffness or damping (measured: rates of 1e10 to 1e30 1/s at orders 4 and 5),
    // which no step resolves and which made the FMU's exponential overflow. Refused with a
    // clear error; the automatic order stays far below the limit.
    let sway = semicircle().select(&["sway"]).unwrap();
    let band = (omega_of(0.05), omega_of(4.5));
    let forced = identify::fit(
        &sway,
        &FitParams {
            form: Some(NetworkForm::SeriesChain),
            band,
            order: Some(6),
            ..FitParams::default()
        },
    );
    match forced {
        Err(e) => assert!(e.to_string().contains("over-fits"), "{e}"),
        Ok(report) => assert!(
            identify::fastest_rate(&report.network) <= identify::FASTEST_RATE_OVER_BAND * band.1
        ),
    }
    for data in [&sway, semicircle()] {
        let form = if data.dof_count() == 1 {
            NetworkForm::SeriesChain
        } else {
            NetworkForm::Coupled
        };
        let report = identify::fit(
            data,
            &FitParams {
                form: Some(form),
                band,
                ..FitParams::default()
            },
        )
        .unwrap();
        // Fastest rate within 100 times the band's top: every stage is a physical time scale.
        let rate = identify::fastest_rate(&report.network);
        assert!(rate <= 100.0 * band.1, "{rate}");
    }
}

/// Vector fitting (common poles, `identify::vector_fitting`) on the semicircle against the
/// figures reported for the peers (pyvectorfit on the same data: sway 4 poles 0.20 %, 5 poles
/// 0.012 %). Unconstrained: the check shows why it is not yet the network (not passive).
#[test]
fn vector_fitting_matches_the_peers_and_its_free_fits_are_not_passive() {
    use hydrofmu::identify::vector_fitting::{vector_fit, VectorFitParams};
    let band = (omega_of(0.05) * 0.999, omega_of(4.5) * 1.001);
    let sway = semicircle().select(&["sway"]).unwrap();
    let fit_of = |response: &FrequencyResponse, pairs, real, band| {
        let params = VectorFitParams {
            complex_pairs: pairs,
            real_poles: real,
            band,
            ..VectorFitParams::default()
        };
        vector_fit(response, &params).unwrap()
    };
    // Measured 0.181 % and 0.0081 % (relative to max |A~| over the band).
    let four = fit_of(&sway, 2, 0, band);
    assert!(four.max_error < 0.0020, "{}", four.max_error);
    assert!(fit_of(&sway, 2, 1, band).max_error < 0.00012);
    // Heave over the wide band kR 0.01 .. 4.5 (log-divergent at low kR): 6 poles, measured 0.032 %.
    let heave = semicircle().select(&["heave"]).unwrap();
    let wide = (omega_of(0.01) * 0.999, omega_of(4.5) * 1.001);
    assert!(fit_of(&heave, 2, 2, wide).max_error < 0.0005);
    // The full 9 x 9 with 8 common poles: measured 0.030 %.
    assert!(fit_of(semicircle(), 4, 0, band).max_error < 0.0005);
    // The free 4-pole sway fit has a negative direct damper (K(inf) = sum of residues < 0):
    // the exact check finds the power it would create.
    let report = four.passivity(1e-9);
    assert!(report.stable);
    assert!(
        !report.passive && report.min_eigenvalue < -1e-3,
        "{report:?}"
    );
}

/// Vector fitting with the residues constrained to a passive model (poles fixed, cuts from the
/// exact check until it passes): the one-DOF targets, and the exact check run again,
/// independently, on the SI model.
#[test]
fn passive_vector_fitting_meets_the_one_dof_targets() {
    use hydrofmu::identify::vector_fitting::{passive_vector_fit, VectorFitParams};
    let band = (omega_of(0.05) * 0.999, omega_of(4.5) * 1.001);
    let wide = (omega_of(0.01) * 0.999, omega_of(4.5) * 1.001);
    let sway = semicircle().select(&["sway"]).unwrap();
    let heave = semicircle().select(&["heave"]).unwrap();
    // (data, complex pairs, real poles, band, bound on the error; measured)
    let cases = [
        (&sway, 2, 1, band, 0.0020), // 5 states: 0.094 % (target: 0.2 % with <= 6 states)
        (&sway, 3, 0, band, 0.0010), // 6 states: 0.033 %
        (&heave, 2, 2, wide, 0.0010), // kR 0.01 .. 4.5, 6 states: 0.033 %
    ];
    for (response, pairs, real, band, bound) in cases {
        let params = VectorFitParams {
            complex_pairs: pairs,
            real_poles: real,
            band,
            ..VectorFitParams::default()
        };
        let (fit, enforcement) = passive_vector_fit(response, &params).unwrap();
        assert!(enforcement.passive, "{enforcement:?}");
        assert!(fit.max_error < bound, "{pairs}+{real}: {}", fit.max_error);
        assert_eq!(fit.pole_count(), 2 * pairs + real);
        assert!(fit.poles.iter().all(|p| p.re < 0.0));
        let report = fit.passivity(1e-9);
        assert!(report.passive, "{report:?}");
    }
}

/// Passive vector fitting per invariant block over `band` with `pairs` and `real` poles per
/// block: every block passive, the whole within `tolerance` with at most `states` states, and
/// passive by the exact check run again on the SI model.
fn assert_passive_block_fit(
    band: (f64, f64),
    pairs: usize,
    real: usize,
    tolerance: f64,
    states: usize,
) {
    use hydrofmu::identify::vector_fitting::{passive_block_vector_fit, VectorFitParams};
    let params = VectorFitParams {
        complex_pairs: pairs,
        real_poles: real,
        band,
        ..VectorFitParams::default()
    };
    let (fit, enforcements) = passive_block_vector_fit(semicircle(), &params).unwrap();
    // Blocks of 2 and 3 dimensions (5 of the 9 DOFs' directions carry the data).
    assert_eq!(enforcements.len(), 2);
    assert!(enforcements.iter().all(|e| e.passive), "{enforcements:?}");
    assert!(fit.max_error < tolerance, "{}", fit.max_error);
    assert!(fit.state_count() <= states, "{}", fit.state_count());
    let report = fit.passivity(1e-9);
    assert!(report.passive, "{report:?}");
    assert_realized_as_network(&fit, band, tolerance);
}

/// The passive fit realized as a network ([`hydrofmu::identify::synthesis`]): the same states,
/// no correction beyond rounding (structure, PSD projection), the network's own error
/// against the data within `tolerance`, and the exact passivity check on its state space.
fn assert_realized_as_network(
    fit: &hydrofmu::identify::vector_fitting::RationalFit,
    band: (f64, f64),
    tolerance: f64,
) {
    let (sub, report) = hydrofmu::identify::synthesis::synthesize(fit).unwrap();
    eprintln!("{report:?}, relaxation {:e}", sub.spring_relaxation.norm());
    assert_eq!(report.springs + report.masses, fit.state_count());
    assert!(report.structure_residual < 1e-8, "{report:?}");
    // The storage function comes from a matrix sign iteration that stops at its rounding
    // level (relative 1e-8 .. 1e-6 here): the PSD projection moves that much, no more.
    assert!(report.projection < 1e-6, "{report:?}");
    let data = semicircle();
    let net = hydrofmu::network::Network::from_substructures(
        data.dof_names.clone(),
        data.added_mass_inf.clone(),
        vec![sub],
        data.rho,
        data.g,
    );
    let scales = &fit.dof_scales;
    let mut worst: f64 = 0.0;
    for (omega, target) in data.omega.iter().zip(&data.added_mass) {
        if *omega < band.0 || *omega > band.1 {
            continue;
        }
        let got = net.added_mass_tf(*omega);
        for i in 0..scales.len() {
            for j in 0..scales.len() {
                let e = (got[(i, j)] - target[(i, j)]).norm() / (scales[i] * scales[j]).sqrt();
                worst = worst.max(e);
            }
        }
    }
    eprintln!("network error {worst:e}, fit {:e}", fit.max_error);
    assert!(
        worst < tolerance && (worst - fit.max_error).abs() < 1e-5,
        "{worst:e}"
    );
    let check = hydrofmu::passivity::check(&net.state_space().unwrap(), 1e-9);
    assert!(check.passive && check.stable, "{check:?}");
}

/// The full 9 x 9: passive vector fitting per invariant block (the semicircle's symmetric and
/// antisymmetric motions, found from the data), each with its own poles. Target: at most 30
/// states at the 1 % tolerance (peer as reported: 25 states, 0.99 %). Measured 0.764 % with 25
/// states.
#[test]
fn passive_block_vector_fitting_meets_the_nine_dof_target() {
    let band = (omega_of(0.05) * 0.999, omega_of(4.5) * 1.001);
    assert_passive_block_fit(band, 2, 1, 0.01, 30);
}

/// The same over the wide band kR 0.01 .. 4.5 (this file's grid ends at 4.5; the band
/// ends at 5), where heave, cb2 and cb5 diverge logarithmically at low kR. Target: 1 % with at
/// most 40 states (peer as reported: 0.35 % with 35 states). Measured 0.456 % with 30 states.
#[test]
fn passive_block_vector_fitting_covers_the_wide_band() {
    let band = (omega_of(0.01) * 0.999, omega_of(4.5) * 1.001);
    assert_passive_block_fit(band, 2, 2, 0.01, 40);
}

/// The rational path of `fit` (passive vector fitting realized as a substructure) on the
/// default 9-DOF scene band kR 0.05 .. 4.5. Targets: at most 30 states at 1 %, passive by the
/// exact check, and no spurious slow mode: 300 s after a 1 s velocity pulse in any DOF, every
/// force is below 1e-3 of its peak.
#[test]
fn rational_fit_of_the_nine_dofs_meets_the_state_target_and_forgets_a_pulse() {
    use hydrofmu::identify::CoupledMethod;
    let params = FitParams {
        band: (omega_of(0.05) * 0.999, omega_of(4.5) * 1.001),
        coupled_method: CoupledMethod::Rational,
        ..FitParams::default()
    };
    let report = identify::fit(semicircle(), &params).unwrap();
    eprintln!(
        "rational 9x9: {} states, {:.4} %, order {}",
        report.states,
        100.0 * report.max_relative_error,
        report.order
    );
    assert!(report.tolerance_met, "{}", report.max_relative_error);
    assert!(report.states <= 30, "{}", report.states);
    // One substructure per part of the fit acting on its own motions: the symmetric and the
    // antisymmetric ones of the mirror-symmetric section.
    assert_eq!(report.network.substructures.len(), 2);
    // Deterministic: a second fit is bitwise the same.
    assert_eq!(identify::fit(semicircle(), &params).unwrap(), report);
    common::assert_passive_and_forgets_a_pulse(&report.network);
}
