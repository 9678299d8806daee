//! Viscous damping and current in the component: the force, its derivatives, the checks,
//! and every output bit for bit as without it at zero coefficients and no current.

use super::tests::{TWO_DOF_EXCITATION, TWO_DOF_NETWORK};
use super::viscous::{parse_csv, write_csv, Frame, Viscous};
use super::*;
use crate::fmi::{Instance, Status};
use crate::fmu::variables::WaveParameter;
use nalgebra::{DMatrix, DVector};

fn names() -> Vec<String> {
    vec!["sway".into(), "roll".into()]
}

fn linear() -> DMatrix<f64> {
    DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.3, 1.0])
}

fn quadratic() -> DVector<f64> {
    DVector::from_vec(vec![3.0, 0.7])
}

/// The two-DOF resources with the exciting force and, when given, viscous damping.
fn resources(viscous: Option<(DMatrix<f64>, DVector<f64>)>) -> Resources {
    Resources::new(TWO_DOF_NETWORK.into(), None, Resources::options_text(false))
        .unwrap()
        .with_excitation(Some(TWO_DOF_EXCITATION.into()))
        .with_viscous(viscous.map(|(l, q)| write_csv(&names(), Frame::Section, &l, &q)))
}

fn damped() -> Model {
    Model::from_resources(&resources(Some((linear(), quadratic())))).unwrap()
}

/// A JONSWAP sea (Hs 2 m, Tp 6 s) started at 0.
fn start_jonswap(m: &mut Model) {
    m.set_wave_integer(WaveParameter::Kind, 2).unwrap();
    m.set_wave_real(WaveParameter::Height, 2.0).unwrap();
    m.set_wave_real(WaveParameter::Period, 6.0).unwrap();
    m.set_start_time(0.0).unwrap();
    m.start_waves().unwrap();
}

#[test]
fn the_force_is_minus_linear_minus_quadratic_of_the_velocity_relative_to_the_current() {
    let mut m = damped();
    m.start_waves().unwrap();
    let (v, speed, heading) = ([0.2, -0.4], 1.5, 60.0_f64);
    m.set_value(Quantity::Velocity(0), v[0]).unwrap();
    m.set_value(Quantity::Velocity(1), v[1]).unwrap();
    m.set_value(Quantity::CurrentSpeed, speed).unwrap();
    m.set_value(Quantity::CurrentHeading, heading).unwrap();
    // A section's current is along its sway axis; roll sees none.
    let relative = [v[0] - speed * heading.to_radians().cos(), v[1]];
    let (bl, bq) = (linear(), quadratic());
    for i in 0..2 {
        let expected = -(bl[(i, 0)] * relative[0] + bl[(i, 1)] * relative[1])
            - bq[i] * relative[i].abs() * relative[i];
        let viscous = m.value(Quantity::ForceViscous(i)).unwrap();
        assert!(
            (viscous - expected).abs() < 1e-14,
            "{i}: {viscous} {expected}"
        );
        let radiation = m.value(Quantity::ForceRadiation(i)).unwrap();
        assert_eq!(m.value(Quantity::Force(i)).unwrap(), radiation + viscous);
    }
    assert_eq!(m.value(Quantity::CurrentSpeed).unwrap(), speed);
    assert_eq!(m.value(Quantity::DampingLinear(1, 0)).unwrap(), 0.3);
    assert_eq!(m.value(Quantity::DampingQuadratic(1)).unwrap(), 0.7);
}

#[test]
fn a_whole_body_s_sway_is_across_and_a_section_s_along_the_current_s_x_axis() {
    // A ship packed without surge still has its sway along y; a section's sway is along x.
    // Without the frame line (older archives) the DOFs decide: sway along x without surge.
    let names: Vec<String> = ["sway", "heave", "yaw"].map(String::from).to_vec();
    let current = |frame: Frame| {
        let mut v = Viscous::new(&names, frame, DMatrix::zeros(3, 3), DVector::zeros(3)).unwrap();
        v.set_current(2.0, 30.0).unwrap();
        v.current()[0]
    };
    assert!((current(Frame::Body) - 1.0).abs() < 1e-15);
    assert!((current(Frame::Section) - 3f64.sqrt()).abs() < 1e-15);
    let text = write_csv(
        &names,
        Frame::Body,
        &DMatrix::zeros(3, 3),
        &DVector::zeros(3),
    );
    assert!(text.contains("\nframe,body\n"), "{text}");
    assert_eq!(parse_csv(&text, &names).unwrap().0, Frame::Body);
    let old = text.replace("frame,body\n", "");
    assert_eq!(parse_csv(&old, &names).unwrap().0, Frame::Section);
}

#[test]
fn a_ship_sees_the_current_on_surge_and_sway() {
    let ship: Vec<String> = ["surge", "sway", "heave", "yaw"].map(String::from).to_vec();
    let mut v = Viscous::new(&ship, Frame::Body, DMatrix::zeros(4, 4), DVector::zeros(4)).unwrap();
    v.set_current(2.0, 30.0).unwrap();
    let c = v.current();
    assert!((c[0] - 2.0 * 30f64.to_radians().cos()).abs() < 1e-15);
    assert!((c[1] - 1.0).abs() < 1e-15);
    assert_eq!((c[2], c[3]), (0.0, 0.0));
}

/// `d of / d known` at `known = x` against the central difference of step `step`, within
/// `1e-6` of `max(|exact|, 1)`.
pub(super) fn assert_derivative(m: &mut Model, of: Quantity, known: Quantity, x: f64, step: f64) {
    m.set_value(known, x + step).unwrap();
    let up = m.value(of).unwrap();
    m.set_value(known, x - step).unwrap();
    let down = m.value(of).unwrap();
    m.set_value(known, x).unwrap();
    let numeric = (up - down) / (2.0 * step);
    let exact = m.partial_derivative(of, known).unwrap();
    assert!(
        (numeric - exact).abs() < 1e-6 * exact.abs().max(1.0),
        "{of:?} / {known:?}: {numeric} vs {exact}"
    );
}

#[test]
fn derivatives_match_finite_differences() {
    let mut m = damped();
    m.start_waves().unwrap();
    let inputs = [
        (Quantity::Velocity(0), 0.2),
        (Quantity::Velocity(1), -0.4),
        (Quantity::CurrentSpeed, 0.9),
        (Quantity::CurrentHeading, 25.0),
    ];
    for (q, x) in inputs {
        m.set_value(q, x).unwrap();
    }
    for (known, x) in inputs {
        let step = 1e-6 * x.abs().max(1.0);
        for of in [
            Quantity::Force(0),
            Quantity::Force(1),
            Quantity::ForceViscous(0),
        ] {
            assert_derivative(&mut m, of, known, x, step);
        }
    }
    // dF/dv = -damping_direct - B_l - 2 B_q |v_r|: with the current at the velocity, -B_l.
    m.set_value(Quantity::CurrentHeading, 0.0).unwrap();
    m.set_value(Quantity::CurrentSpeed, 0.2).unwrap();
    let direct = m.value(Quantity::DampingDirect(0, 0)).unwrap();
    let dfdv = m
        .partial_derivative(Quantity::Force(0), Quantity::Velocity(0))
        .unwrap();
    assert!((dfdv - (-direct - 2.0)).abs() < 1e-14);
    // The radiation force does not depend on the current.
    let radiation = m
        .partial_derivative(Quantity::ForceRadiation(0), Quantity::CurrentSpeed)
        .unwrap();
    assert_eq!(radiation, 0.0);
}

#[test]
fn zero_damping_and_no_current_leave_every_output_bit_for_bit() {
    let zero = Some((DMatrix::zeros(2, 2), DVector::zeros(2)));
    let mut plain = Model::from_resources(&resources(None)).unwrap();
    let mut with = Model::from_resources(&resources(zero)).unwrap();
    start_jonswap(&mut plain);
    start_jonswap(&mut with);
    for k in 0..300 {
        let t = k as f64;
        for m in [&mut plain, &mut with] {
            m.set_value(Quantity::Velocity(0), (0.3 * t).sin()).unwrap();
            m.set_value(Quantity::Velocity(1), 0.1 * (0.2 * t).cos())
                .unwrap();
            m.step(m.time(), 0.1).unwrap();
        }
        let all = [
            Quantity::Force(0),
            Quantity::Force(1),
            Quantity::ForceRadiation(0),
            Quantity::ForceRadiation(1),
            Quantity::ForceExcitation(0),
            Quantity::ForceExcitation(1),
            Quantity::WaveElevation,
            Quantity::Power,
            Quantity::Energy,
        ];
        for q in all {
            let (a, b) = (plain.value(q).unwrap(), with.value(q).unwrap());
            assert_eq!(a.to_bits(), b.to_bits(), "step {k}, {q:?}");
        }
        for q in [Quantity::Force(0), Quantity::Force(1)] {
            let (a, b) = (
                plain.output_derivative(q).unwrap(),
                with.output_derivative(q).unwrap(),
            );
            assert_eq!(a.to_bits(), b.to_bits(), "step {k}, d{q:?}/dt");
        }
        assert_eq!(with.value(Quantity::ForceViscous(0)).unwrap(), 0.0);
    }
}

#[test]
fn bad_coefficients_and_currents_are_refused_naming_them() {
    let mut m = damped();
    let message = |r: Result<(), ModelError>| r.unwrap_err().to_string();
    let e = message(m.set_value(Quantity::DampingQuadratic(1), -1.0));
    assert!(e.contains("damping_quadratic[2]"), "{e}");
    let e = message(m.set_value(Quantity::DampingLinear(0, 1), f64::NAN));
    assert!(e.contains("damping_linear[1,2]"), "{e}");
    let e = message(m.set_value(Quantity::DampingLinear(0, 0), -0.1));
    assert!(e.contains("damping_linear[1,1]"), "{e}");
    let e = message(m.set_value(Quantity::CurrentSpeed, f64::INFINITY));
    assert!(e.contains("current.speed"), "{e}");
    let e = message(m.set_value(Quantity::CurrentHeading, f64::NAN));
    assert!(e.contains("current.heading"), "{e}");
    // Nothing was changed by the refusals.
    assert_eq!(m.value(Quantity::DampingQuadratic(1)).unwrap(), 0.7);
    assert_eq!(m.value(Quantity::CurrentSpeed).unwrap(), 0.0);
    // Off-diagonal entries that make the symmetric part indefinite: refused as a whole.
    m.set_value(Quantity::DampingLinear(0, 1), 10.0).unwrap();
    let e = m.start_waves().unwrap_err().to_string();
    assert!(
        e.contains("damping_linear") && e.contains("semidefinite"),
        "{e}"
    );
    // A heading of any finite value is accepted.
    m.set_value(Quantity::CurrentHeading, -725.0).unwrap();
    // Without viscous damping the variables do not exist.
    let mut plain = Model::from_resources(&resources(None)).unwrap();
    assert!(plain.set_value(Quantity::CurrentSpeed, 1.0).is_err());
    assert!(plain.value(Quantity::ForceViscous(0)).is_err());
}

#[test]
fn the_csv_round_trips_and_bad_files_are_refused() {
    let text = write_csv(&names(), Frame::Section, &linear(), &quadratic());
    let (frame, l, q) = parse_csv(&text, &names()).unwrap();
    assert_eq!(frame, Frame::Section);
    assert_eq!((l, q), (linear(), quadratic()));
    let bad = [
        ("", "no header"),
        ("dof,quadratic,sway\n", "header"),
        ("dof,quadratic,roll,sway\n", "differ"),
        (
            "dof,quadratic,sway,roll\nsway,1,2,3\n",
            "no row for DOF roll",
        ),
        (
            "dof,quadratic,sway,roll\nsway,1,2,x\nroll,0,0,0\n",
            "'x' is not a number",
        ),
        (
            "dof,quadratic,sway,roll\nroll,1,2,3\nsway,0,0,0\n",
            "expected 'sway,'",
        ),
        (
            "dof,quadratic,sway,roll\nsway,1,2,3\nroll,0,0,0\nroll,0,0,0\n",
            "more rows",
        ),
        ("frame,ship\ndof,quadratic,sway,roll\n", "frame 'ship'"),
    ];
    for (text, expected) in bad {
        let e = parse_csv(text, &names()).unwrap_err();
        assert!(e.contains(expected) && e.contains("viscous.csv"), "{e}");
    }
    let negative = write_csv(
        &names(),
        Frame::Section,
        &linear(),
        &DVector::from_vec(vec![1.0, -2.0]),
    );
    let e = Model::from_resources(
        &Resources::new(TWO_DOF_NETWORK.into(), None, Resources::options_text(false))
            .unwrap()
            .with_viscous(Some(negative)),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("damping_quadratic[2]"), "{e}");
}

#[test]
fn the_explicit_step_bound_follows_the_derivative() {
    let mut v = Viscous::new(&names(), Frame::Section, linear(), quadratic()).unwrap();
    v.set_current(0.5, 0.0).unwrap();
    // h < 2 m / (B_l + 2 B_q |v - c|) = 2 * 10 / (2 + 2 * 3 * 1.5)
    assert!((v.step_bound(0, 10.0, 2.0) - 20.0 / 11.0).abs() < 1e-15);
    let free = Viscous::zeros(&names(), Frame::Section);
    assert_eq!(free.step_bound(1, 1.0, 3.0), f64::INFINITY);
}

#[test]
fn the_instance_declares_and_serves_the_viscous_variables() {
    let instance = || {
        Instance::from_resources(c"hull", &resources(Some((linear(), quadratic()))), false).unwrap()
    };
    let layout = crate::fmu::Layout::new(
        names()
            .iter()
            .map(|n| crate::fmu::units::DofUnit::new(n, 0, false))
            .collect(),
        false,
    )
    .unwrap()
    .with_viscous(&linear(), &quadratic())
    .unwrap();
    let vr = |q| layout.value_reference(q).unwrap();
    let mut inst = instance();
    // Parameters before initialization ends, inputs any time.
    assert_eq!(
        inst.set_real(&[vr(Quantity::DampingQuadratic(0))], &[4.0]),
        Status::Ok
    );
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    let speed = vr(Quantity::CurrentSpeed);
    assert_eq!(inst.set_real(&[speed], &[1.0]), Status::Ok);
    let mut out = [0.0; 2];
    let reads = [
        vr(Quantity::ForceViscous(0)),
        vr(Quantity::DampingQuadratic(0)),
    ];
    assert_eq!(inst.get_real(&reads, &mut out), Status::Ok);
    // At rest in a current of 1 m/s: v_r = -1, F = B_l[1,1] + B_q = 2 + 4.
    assert!((out[0] - 6.0).abs() < 1e-14, "{}", out[0]);
    assert_eq!(out[1], 4.0);
    let mut dv = [0.0];
    let status = inst.get_directional_derivative(
        &[vr(Quantity::Force(0))],
        &[vr(Quantity::Velocity(0))],
        &[1.0],
        &mut dv,
    );
    assert_eq!(status, Status::Ok);
    let direct = inst.model().system().damping_direct()[(0, 0)];
    assert!(
        (dv[0] - (-direct - 2.0 - 2.0 * 4.0)).abs() < 1e-12,
        "{}",
        dv[0]
    );
    // Refused: a parameter after initialization, bad values; each message names the variable.
    assert_eq!(
        inst.set_real(&[vr(Quantity::DampingQuadratic(0))], &[5.0]),
        Status::Error
    );
    let refusals = [
        (Quantity::DampingQuadratic(0), -4.0, "damping_quadratic[1]"),
        (
            Quantity::DampingLinear(1, 0),
            f64::NAN,
            "damping_linear[2,1]",
        ),
        (Quantity::CurrentSpeed, f64::INFINITY, "current.speed"),
    ];
    for (q, x, name) in refusals {
        let mut inst = instance();
        assert_eq!(inst.set_real(&[vr(q)], &[x]), Status::Error);
        let texts: Vec<_> = inst.take_messages().into_iter().map(|m| m.text).collect();
        assert!(texts.iter().any(|t| t.contains(name)), "{texts:?}");
    }
}

#[test]
fn a_diagonal_linear_damping_gives_the_full_products_force() {
    let diagonal = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1.0]);
    let mut fast = Viscous::new(&names(), Frame::Section, diagonal.clone(), quadratic()).unwrap();
    let mut full = Viscous::new(&names(), Frame::Section, diagonal, quadratic()).unwrap();
    // An off-diagonal entry set and reset to zero: still the same matrix, now by products.
    full.set_linear(0, 1, 1.0).unwrap();
    full.set_linear(0, 1, 0.0).unwrap();
    full.set_current(0.7, 10.0).unwrap();
    fast.set_current(0.7, 10.0).unwrap();
    let (mut a, mut b) = (DVector::zeros(2), DVector::zeros(2));
    for v in [[0.3, -0.2], [-1.1, 0.0], [0.0, 2.5]] {
        let v = DVector::from_vec(v.to_vec());
        fast.force(&v, 1025.0, &mut a);
        full.force(&v, 1025.0, &mut b);
        assert_eq!(a, b);
    }
    let mut coupled = Viscous::new(&names(), Frame::Section, linear(), quadratic()).unwrap();
    coupled.force(&DVector::from_vec(vec![1.0, 1.0]), 1025.0, &mut a);
    assert_eq!(a[0], -(2.0 + 0.5) - 3.0);
}

#[test]
fn a_saved_state_keeps_its_current() {
    // The current is an input the state carries: restored by set_state and by the state bytes.
    let mut m = damped();
    m.set_value(Quantity::CurrentSpeed, 0.8).unwrap();
    m.set_value(Quantity::CurrentHeading, 30.0).unwrap();
    m.set_value(Quantity::Velocity(0), 0.1).unwrap();
    let saved = m.state().clone();
    let bytes = m.serialize(0);
    assert_eq!(bytes.len(), m.serialized_size());
    let force = m.value(Quantity::ForceViscous(0)).unwrap();
    m.set_value(Quantity::CurrentSpeed, 0.0).unwrap();
    assert_ne!(m.value(Quantity::ForceViscous(0)).unwrap(), force);
    m.set_state(saved).unwrap();
    assert_eq!(m.value(Quantity::CurrentSpeed).unwrap(), 0.8);
    assert_eq!(m.value(Quantity::ForceViscous(0)).unwrap(), force);
    let mut fresh = damped();
    let (state, _) = fresh.deserialize(&bytes).unwrap();
    fresh.set_state(state).unwrap();
    assert_eq!(fresh.value(Quantity::CurrentHeading).unwrap(), 30.0);
    assert_eq!(fresh.value(Quantity::ForceViscous(0)).unwrap(), force);
    // A current that is not finite, checksum recomputed, is refused by name.
    let mut bad = bytes.clone();
    let at = bad.len() - 8 - 16;
    bad[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    let body = bad.len() - 8;
    let sum = super::snapshot::checksum(&bad[..body]);
    bad[body..].copy_from_slice(&sum.to_le_bytes());
    let e = fresh.deserialize(&bad).unwrap_err().to_string();
    assert!(e.contains("current.speed is NaN"), "{e}");
}
