//! Unit tests of the roll-damping components and the cross-flow drag.

use super::*;
use std::f64::consts::PI;

fn box_section() -> RollDampingParams {
    RollDampingParams::new(20.0, 6.0, 0.95, 1.5)
}

#[test]
fn friction_matches_kato_by_hand() {
    let p = box_section();
    let (omega, phi_a) = (0.5, 0.1);
    // S_g = 1.7 * 6 + 0.95 * 20 = 29.2 m; r_f = (0.88 + 0.145 * 0.95) * 29.2 / pi.
    let girth = 29.2;
    let r_f = (0.887 + 0.145 * 0.95) * girth / PI;
    let reynolds = r_f * r_f * phi_a * phi_a * omega / 1.19e-6;
    let by_hand = 0.787
        * 1025.0
        * girth
        * r_f
        * r_f
        * (omega * 1.19e-6_f64).sqrt()
        * (1.0 + 0.00814 * reynolds.powf(0.386));
    let ours = friction(&p, omega, phi_a);
    assert!((ours.linear - by_hand).abs() < 1e-9 * by_hand);
    assert_eq!(ours.quadratic, 0.0);
}

#[test]
fn eddy_making_of_a_semicircle_about_its_centre_vanishes() {
    let radius = 3.0;
    let circle = RollDampingParams::new(2.0 * radius, radius, PI / 4.0, radius);
    let c_r_circle = eddy_coefficient(&circle).unwrap();
    let c_r_box = eddy_coefficient(&box_section()).unwrap();
    assert!(
        c_r_circle.abs() < 1e-4 * c_r_box,
        "{c_r_circle} vs {c_r_box}"
    );
}

#[test]
fn lewis_form_reproduces_breadth_and_draft() {
    let lewis = lewis_form(20.0, 6.0, 0.9).unwrap();
    assert!((lewis.radius(0.0) - 6.0).abs() < 1e-12);
    assert!((lewis.radius(0.5 * PI) - 10.0).abs() < 1e-12);
}

#[test]
fn equivalent_linear_formulas() {
    let damping = Damping {
        linear: 2.0,
        quadratic: 3.0,
    };
    let harmonic = damping.equivalent_linear(0.5, 0.2);
    assert!((harmonic - (2.0 + 8.0 / (3.0 * PI) * 0.5 * 0.2 * 3.0)).abs() < 1e-15);
    let stochastic = damping.stochastic_linear(0.1);
    assert!((stochastic - (2.0 + (8.0 / PI).sqrt() * 0.1 * 3.0)).abs() < 1e-15);
}

#[test]
fn bilge_keel_term_is_zero_without_keels_and_positive_with() {
    let mut p = box_section();
    assert_eq!(bilge_keel(&p, 0.5, 0.1), Damping::default());
    p.bilge_keels = Some(BilgeKeels {
        breadth: 0.4,
        length_fraction: 0.5,
    });
    let keels = bilge_keel(&p, 0.5, 0.1);
    assert!(keels.linear > 0.0 && keels.quadratic > 0.0);
}

#[test]
fn equivalent_damping_grows_with_amplitude() {
    let mut p = box_section();
    p.bilge_keels = Some(BilgeKeels {
        breadth: 0.4,
        length_fraction: 0.5,
    });
    let omega = 0.5;
    let equivalent: Vec<f64> = [0.05, 0.1, 0.2, 0.3]
        .iter()
        .map(|&phi_a| {
            roll_damping(&p, omega, phi_a)
                .unwrap()
                .total()
                .equivalent_linear(omega, phi_a)
        })
        .collect();
    assert!(equivalent.windows(2).all(|w| w[1] > w[0]), "{equivalent:?}");
}

#[test]
fn bad_input_names_the_field() {
    type Spoil = fn(&mut RollDampingParams);
    let cases: [(&str, Spoil); 6] = [
        ("breadth", |p| p.breadth = f64::NAN),
        ("draft", |p| p.draft = -1.0),
        ("bilge_radius", |p| p.bilge_radius = 10.5),
        ("bilge_radius", |p| p.bilge_radius = -0.1),
        ("nu", |p| p.nu = f64::INFINITY),
        ("bilge_keels.breadth", |p| {
            p.bilge_keels = Some(BilgeKeels {
                breadth: -0.2,
                length_fraction: 0.5,
            })
        }),
    ];
    for (field, spoil) in cases {
        let mut p = box_section();
        spoil(&mut p);
        let error = roll_damping(&p, 0.5, 0.1).unwrap_err();
        assert_eq!(error.field, field, "{error}");
        assert!(error.to_string().starts_with(field));
    }
    let error = roll_damping(&box_section(), 0.5, -0.1).unwrap_err();
    assert_eq!(error.field, "phi_a");
}

#[test]
fn extrapolation_warns() {
    let deep = RollDampingParams::new(10.0, 6.0, 0.95, 1.0);
    let warnings = deep.validate().unwrap();
    assert_eq!(warnings.len(), 1);
    assert_eq!(warnings[0].field, "breadth/draft");
    assert!(box_section().validate().unwrap().is_empty());
}

#[test]
fn ship_integral_of_uniform_sections_is_length_times_section() {
    let section = Damping {
        linear: 1.0,
        quadratic: 2.0,
    };
    let stations: Vec<(f64, Damping)> = (0..11).map(|i| (10.0 * i as f64, section)).collect();
    let ship = integrate_along(&stations);
    assert!((ship.linear - 100.0).abs() < 1e-12 && (ship.quadratic - 200.0).abs() < 1e-12);
}

#[test]
fn cross_flow_drag_of_sharp_and_rounded_sections() {
    // Double body 2T x B = 12 x 12 m: a square, C_D = 2.05 sharp.
    let sharp = cross_flow_drag_coefficient(12.0, 6.0, 0.0, CrossFlow::Sway);
    assert!((sharp - 2.05).abs() < 1e-12);
    let rounded = cross_flow_drag_coefficient(12.0, 6.0, 3.0, CrossFlow::Sway);
    assert!((rounded - 1.025).abs() < 1e-12);
    let force = cross_flow_force(1025.0, 1.0, 12.0, 6.0, CrossFlow::Heave, -2.0);
    assert!((force - 0.5 * 1025.0 * 12.0 * 4.0).abs() < 1e-9);
}
