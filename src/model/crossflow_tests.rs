//! A ship's cross-flow strips in the component: the current's sway force and yaw moment, the
//! identity with the per-DOF coefficients, the derivatives, `crossflow.drag_scale`, and the
//! files refused.

use super::crossflow::{parse_csv, write_csv, Strip, MAX_STRIPS};
use super::viscous::{self, Frame};
use super::*;
use crate::hull::Hull;
use crate::ship::{Ship, ShipDof, Station};
use nalgebra::{DMatrix, DVector};

/// A network in the ship's DOFs sway, heave, pitch and yaw (coupled through one branch).
const SHIP_NETWORK: &str = r#"<network format_version="1" form="coupled" rho="1" g="1">
  <dof name="sway"/>
  <dof name="heave"/>
  <dof name="pitch"/>
  <dof name="yaw"/>
  <added_mass_inf><row>1 0 0 0</row><row>0 1 0 0</row><row>0 0 2 0</row><row>0 0 0 2</row></added_mass_inf>
  <branch>
<direction>1 0.2 0 0.3</direction>
<stage mass="0.5" stiffness="0.3" damping="0.8"/>
  </branch>
</network>
"#;

/// sway, heave, pitch, yaw: the network's order.
const SWAY: usize = 0;
const HEAVE: usize = 1;
const PITCH: usize = 2;
const YAW: usize = 3;

fn names() -> Vec<String> {
    ["sway", "heave", "pitch", "yaw"].map(String::from).to_vec()
}

/// A 40 m ship whose stern (x < 0) is a 10 m x 4 m Lewis section and whose bow a 10 m x
/// 2.5 m one, the last station (x = 20 m) without a section: the deeper stern makes the
/// lateral area's moment negative.
fn asymmetric_ship() -> Ship {
    let stern = Hull::lewis(10.0, 4.0, 0.9).unwrap();
    let bow = Hull::lewis(10.0, 2.5, 0.85).unwrap();
    let stations = (0..=10)
        .map(|k| {
            let x = -20.0 + 4.0 * k as f64;
            let section = match k {
                10 => None,
                _ if x < 0.0 => Some(0),
                _ => Some(1),
            };
            Station { x, section }
        })
        .collect();
    let dofs = ["sway", "heave", "roll", "pitch", "yaw"]
        .iter()
        .map(|n| ShipDof {
            name: n.to_string(),
            motions: None,
        })
        .collect();
    Ship::new(
        "asymmetric",
        stations,
        vec![stern, bow],
        dofs,
        "asymmetric.xml",
    )
    .unwrap()
}

fn estimate() -> crate::viscous::ShipEstimate {
    crate::viscous::ship_estimate(&asymmetric_ship(), DEFAULT_RHO, 0.8, 0.1).unwrap()
}

/// The component of [`SHIP_NETWORK`] with per-DOF damping `quadratic` and, when given, the
/// strips.
fn ship_model(quadratic: [f64; 4], strips: Option<&[Strip]>) -> Model {
    let text = viscous::write_csv(
        &names(),
        Frame::Body,
        &DMatrix::zeros(4, 4),
        &DVector::from_row_slice(&quadratic),
    );
    let resources = Resources::new(SHIP_NETWORK.into(), None, Resources::options_text(false))
        .unwrap()
        .with_viscous(Some(text))
        .with_crossflow(strips.map(write_csv));
    let mut model = Model::from_resources(&resources).unwrap();
    model.start_waves().unwrap();
    model
}

fn viscous_force(m: &mut Model, dof: usize) -> f64 {
    m.value(Quantity::ForceViscous(dof)).unwrap()
}

#[test]
fn a_beam_current_gives_the_strips_sway_force_and_yaw_moment() {
    let strips = estimate().strips;
    let mut m = ship_model([0.0; 4], Some(&strips));
    let speed = 1.5;
    let area: f64 = strips.iter().map(|s| s.cd_sway * s.draft * s.weight).sum();
    let moment: f64 = strips
        .iter()
        .map(|s| s.x * s.cd_sway * s.draft * s.weight)
        .sum();
    // The deeper stern: the lateral area's moment is well off zero.
    assert!(moment < -0.1 * area * 20.0, "{moment} vs {area}");
    for heading in [90.0, -90.0, 30.0] {
        m.set_value(Quantity::CurrentSpeed, speed).unwrap();
        m.set_value(Quantity::CurrentHeading, heading).unwrap();
        let across = speed * f64::to_radians(heading).sin();
        let expected_force = 0.5 * DEFAULT_RHO * area * across.abs() * across;
        let expected_moment = 0.5 * DEFAULT_RHO * moment * across.abs() * across;
        let (sway, yaw) = (viscous_force(&mut m, SWAY), viscous_force(&mut m, YAW));
        // Sums of ten terms: rounding of 1e-15 relative (of 1e4 N, 1e5 N.m).
        assert!(
            (sway - expected_force).abs() < 1e-12 * expected_force.abs(),
            "{heading}: {sway} vs {expected_force}"
        );
        assert!(
            (yaw - expected_moment).abs() < 1e-12 * expected_moment.abs(),
            "{heading}: {yaw} vs {expected_moment}"
        );
        assert_eq!(viscous_force(&mut m, HEAVE), 0.0);
        assert_eq!(viscous_force(&mut m, PITCH), 0.0);
        let radiation = m.value(Quantity::ForceRadiation(YAW)).unwrap();
        assert_eq!(m.value(Quantity::Force(YAW)).unwrap(), radiation + yaw);
    }
    // With the per-DOF coefficients alone (the previous model) the current had no yaw moment.
    let get = |name: &str| estimate().dofs.iter().find(|d| d.0 == name).unwrap().1;
    let mut per_dof = ship_model(
        [
            get("sway").quadratic,
            get("heave").quadratic,
            get("pitch").quadratic,
            get("yaw").quadratic,
        ],
        None,
    );
    per_dof.set_value(Quantity::CurrentSpeed, speed).unwrap();
    per_dof.set_value(Quantity::CurrentHeading, 90.0).unwrap();
    assert_eq!(viscous_force(&mut per_dof, YAW), 0.0);
}

#[test]
fn rates_alone_give_the_per_dof_coefficients_of_the_estimate() {
    let estimate = estimate();
    let get = |name: &str| {
        estimate
            .dofs
            .iter()
            .find(|d| d.0 == name)
            .unwrap()
            .1
            .quadratic
    };
    let mut m = ship_model([0.0; 4], Some(&estimate.strips));
    // One DOF moving at a time, no current: the strips' drag is the per-DOF |x|^3 (and
    // sway, heave) coefficient times rate |rate|, to rounding.
    for (dof, name, rate) in [
        (YAW, "yaw", 0.03),
        (YAW, "yaw", -0.05),
        (PITCH, "pitch", 0.02),
        (SWAY, "sway", -0.7),
        (HEAVE, "heave", 0.4),
    ] {
        for j in 0..4 {
            m.set_value(Quantity::Velocity(j), 0.0).unwrap();
        }
        m.set_value(Quantity::Velocity(dof), rate).unwrap();
        let expected = -get(name) * rate.abs() * rate;
        let ours = viscous_force(&mut m, dof);
        assert!(
            (ours - expected).abs() < 1e-12 * expected.abs(),
            "{name}: {ours} vs {expected}"
        );
    }
    // A yaw rate also pushes sideways (the cross term the per-DOF model left out): the
    // stern, deeper, pushes more.
    for j in 0..4 {
        m.set_value(Quantity::Velocity(j), 0.0).unwrap();
    }
    m.set_value(Quantity::Velocity(YAW), 0.05).unwrap();
    assert!(viscous_force(&mut m, SWAY) > 0.0);
}

#[test]
fn a_head_current_gives_no_sway_force_and_no_yaw_moment() {
    let strips = estimate().strips;
    let mut m = ship_model([0.0; 4], Some(&strips));
    m.set_value(Quantity::CurrentSpeed, 2.0).unwrap();
    m.set_value(Quantity::CurrentHeading, 0.0).unwrap();
    for dof in 0..4 {
        assert_eq!(viscous_force(&mut m, dof), 0.0, "{dof}");
    }
    // Following current: sin(180 deg) is 1.2e-16, the cross flow 2.4e-16 m/s, its drag
    // (rho c v^2 ~ 1e4 * 6e-32 N) far below 1e-20 N.
    m.set_value(Quantity::CurrentHeading, 180.0).unwrap();
    assert!(viscous_force(&mut m, SWAY).abs() < 1e-20);
    assert!(viscous_force(&mut m, YAW).abs() < 1e-18);
}

#[test]
fn derivatives_match_finite_differences() {
    let strips = estimate().strips;
    let mut m = ship_model([10.0, 20.0, 1e3, 2e3], Some(&strips));
    let inputs = [
        (Quantity::Velocity(SWAY), 0.3),
        (Quantity::Velocity(HEAVE), -0.2),
        (Quantity::Velocity(PITCH), 0.013),
        (Quantity::Velocity(YAW), -0.02),
        (Quantity::CurrentSpeed, 0.9),
        (Quantity::CurrentHeading, 65.0),
    ];
    for (q, x) in inputs {
        m.set_value(q, x).unwrap();
    }
    for (known, x) in inputs {
        let step = 1e-6 * f64::abs(x).max(0.01);
        for dof in 0..4 {
            for of in [Quantity::Force(dof), Quantity::ForceViscous(dof)] {
                super::viscous_tests::assert_derivative(&mut m, of, known, x, step);
            }
        }
    }
    // The coupling blocks: -2 rho c |v| times [1, x; x, x^2] and [1, -x; -x, x^2].
    let d = |m: &mut Model, i, j| {
        m.partial_derivative(Quantity::ForceViscous(i), Quantity::Velocity(j))
            .unwrap()
    };
    assert!(d(&mut m, SWAY, YAW) != 0.0 && d(&mut m, HEAVE, PITCH) != 0.0);
    assert_eq!(d(&mut m, SWAY, YAW), d(&mut m, YAW, SWAY));
    assert_eq!(d(&mut m, HEAVE, PITCH), d(&mut m, PITCH, HEAVE));
    assert_eq!(d(&mut m, SWAY, HEAVE), 0.0);
    // The strips scale with rho; the per-DOF coefficients do not.
    // Yaw's per-DOF part: -B_q |r| r at r = -0.02 rad/s (no current on a rotation).
    let per_dof_yaw: f64 = -2e3 * 0.02 * -0.02;
    let strips_only = viscous_force(&mut m, YAW) - per_dof_yaw;
    let per_rho = m
        .partial_derivative(Quantity::ForceViscous(YAW), Quantity::Rho)
        .unwrap();
    assert!((per_rho - strips_only / DEFAULT_RHO).abs() < 1e-12 * per_rho.abs());
    // The output derivative with the current held: dF/dv v'.
    let rates = [0.1, -0.3, 0.02, 0.05];
    for (j, r) in rates.iter().enumerate() {
        m.set_input_derivative(Quantity::Velocity(j), *r).unwrap();
    }
    for i in 0..4 {
        let expected: f64 = (0..4).map(|j| d(&mut m, i, j) * rates[j]).sum();
        let rate = m.output_derivative(Quantity::ForceViscous(i)).unwrap();
        assert!((rate - expected).abs() <= 1e-12 * expected.abs(), "{i}");
    }
}

#[test]
fn the_drag_scale_scales_and_switches_the_strips_off() {
    let strips = estimate().strips;
    let mut m = ship_model([0.0; 4], Some(&strips));
    m.set_value(Quantity::CurrentSpeed, 1.0).unwrap();
    m.set_value(Quantity::CurrentHeading, 90.0).unwrap();
    m.set_value(Quantity::Velocity(YAW), 0.01).unwrap();
    assert_eq!(m.value(Quantity::CrossflowDragScale).unwrap(), 1.0);
    let whole = [viscous_force(&mut m, SWAY), viscous_force(&mut m, YAW)];
    m.set_value(Quantity::CrossflowDragScale, 2.0).unwrap();
    assert_eq!(viscous_force(&mut m, SWAY), 2.0 * whole[0]);
    assert_eq!(viscous_force(&mut m, YAW), 2.0 * whole[1]);
    m.set_value(Quantity::CrossflowDragScale, 0.0).unwrap();
    for dof in 0..4 {
        assert_eq!(viscous_force(&mut m, dof), 0.0);
    }
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        let e = m
            .set_value(Quantity::CrossflowDragScale, bad)
            .unwrap_err()
            .to_string();
        assert!(e.contains("crossflow.drag_scale"), "{e}");
    }
    assert_eq!(m.value(Quantity::CrossflowDragScale).unwrap(), 0.0);
    // A fixed parameter: refused once initialization mode has ended.
    let e = viscous::check_value(Quantity::CrossflowDragScale, 1.0, false).unwrap_err();
    assert!(e.contains("fixed parameter"), "{e}");
    // Without strips the parameter does not exist.
    let mut plain = ship_model([1.0; 4], None);
    assert!(plain.value(Quantity::CrossflowDragScale).is_err());
    assert!(plain.set_value(Quantity::CrossflowDragScale, 1.0).is_err());
    assert!(!plain.layout().unwrap().has_crossflow());
    let layout = m.layout().unwrap();
    let vr = layout
        .value_reference(Quantity::CrossflowDragScale)
        .unwrap();
    assert_eq!(layout.quantity(vr), Some(Quantity::CrossflowDragScale));
    // It comes after every other variable: none of them moves.
    let others = plain.layout().unwrap();
    assert!(others.variables().iter().all(|v| v.value_reference < vr));
    for v in others.variables() {
        assert_eq!(layout.value_reference(v.quantity), Some(v.value_reference));
    }
}

#[test]
fn without_strips_every_output_is_bit_for_bit_the_per_dof_model() {
    // Strips at scale 0 against none: the same outputs, bit for bit, in a current.
    let strips = estimate().strips;
    let mut with = ship_model([10.0, 20.0, 1e3, 2e3], Some(&strips));
    with.set_value(Quantity::CrossflowDragScale, 0.0).unwrap();
    let mut without = ship_model([10.0, 20.0, 1e3, 2e3], None);
    for m in [&mut with, &mut without] {
        m.set_value(Quantity::CurrentSpeed, 0.7).unwrap();
        m.set_value(Quantity::CurrentHeading, 120.0).unwrap();
        for (j, v) in [0.3, -0.1, 0.01, 0.02].iter().enumerate() {
            m.set_value(Quantity::Velocity(j), *v).unwrap();
        }
        m.step(0.0, 0.1).unwrap();
    }
    for i in 0..4 {
        for q in [Quantity::Force(i), Quantity::ForceViscous(i)] {
            assert_eq!(
                with.value(q).unwrap().to_bits(),
                without.value(q).unwrap().to_bits(),
                "{q:?}"
            );
        }
    }
}

#[test]
fn the_csv_round_trips_and_bad_files_are_refused_naming_the_line() {
    let strips = estimate().strips;
    assert_eq!(strips.len(), 10);
    let text = write_csv(&strips);
    assert!(text.starts_with("# hydrofmu cross-flow strips"));
    assert_eq!(parse_csv(&text).unwrap(), strips);
    let header = "x,weight,draft,breadth,cd_sway,cd_heave";
    let good = "-10,2,4,10,1.2,0.9";
    let cases = [
        (format!("{good}\n"), "crossflow.csv:1: header"),
        (String::from("# only a comment\n"), "no header"),
        (format!("{header}\n"), "no strips"),
        (
            format!("{header}\n{good}\n1,NaN,4,10,1,1\n"),
            ":3: weight 'NaN'",
        ),
        (format!("{header}\n1,-2,4,10,1,1\n"), ":2: weight '-2'"),
        (format!("{header}\n1,2,4,10,-1,1\n"), ":2: cd_sway '-1'"),
        (format!("{header}\ninf,2,4,10,1,1\n"), ":2: x 'inf'"),
        (format!("{header}\n1,2,4,10,1\n"), ":2: 5 fields"),
        (
            format!("{header}\n{}", format!("{good}\n").repeat(MAX_STRIPS + 1)),
            &format!(":{}: more than {MAX_STRIPS} strips", MAX_STRIPS + 2),
        ),
    ];
    for (text, expected) in cases {
        let e = parse_csv(&text).unwrap_err();
        assert!(e.contains(expected), "{e} (expected {expected})");
    }
    // The most strips allowed are read.
    let most = format!("{header}\n{}", format!("{good}\n").repeat(MAX_STRIPS));
    assert_eq!(parse_csv(&most).unwrap().len(), MAX_STRIPS);
}

#[test]
fn strips_need_a_whole_body_with_viscous_damping() {
    let strips = write_csv(&estimate().strips);
    let plain = Resources::new(SHIP_NETWORK.into(), None, Resources::options_text(false))
        .unwrap()
        .with_crossflow(Some(strips.clone()));
    let e = Model::from_resources(&plain).unwrap_err().to_string();
    assert!(e.contains("without resources/viscous.csv"), "{e}");
    let section = viscous::write_csv(
        &names(),
        Frame::Section,
        &DMatrix::zeros(4, 4),
        &DVector::zeros(4),
    );
    let e = Model::from_resources(&plain.with_viscous(Some(section)))
        .unwrap_err()
        .to_string();
    assert!(e.contains("need a whole body"), "{e}");
}

#[test]
fn the_instance_declares_and_serves_the_drag_scale_and_the_coupled_derivatives() {
    use crate::fmi::{Instance, Status};
    use crate::fmu::description::{DescriptionInfo, FIXED_XML};
    let strips = estimate().strips;
    let text = viscous::write_csv(
        &names(),
        Frame::Body,
        &DMatrix::zeros(4, 4),
        &DVector::zeros(4),
    );
    let resources = Resources::new(SHIP_NETWORK.into(), None, Resources::options_text(false))
        .unwrap()
        .with_viscous(Some(text))
        .with_crossflow(Some(write_csv(&strips)));
    let layout = Model::from_resources(&resources).unwrap().layout().unwrap();
    let vr = |q| layout.value_reference(q).unwrap();
    let instance = || Instance::from_resources(c"ship", &resources, false).unwrap();
    let scale = vr(Quantity::CrossflowDragScale);
    let mut refused = instance();
    assert_eq!(refused.set_real(&[scale], &[-0.5]), Status::Error);
    let texts: Vec<_> = refused
        .take_messages()
        .into_iter()
        .map(|m| m.text)
        .collect();
    assert!(
        texts.iter().any(|t| t.contains("crossflow.drag_scale")),
        "{texts:?}"
    );
    let mut inst = instance();
    assert_eq!(inst.set_real(&[scale], &[0.5]), Status::Ok);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    let (speed, heading) = (vr(Quantity::CurrentSpeed), vr(Quantity::CurrentHeading));
    assert_eq!(inst.set_real(&[speed, heading], &[1.0, 90.0]), Status::Ok);
    // At rest in a beam current of 1 m/s, v_y = -1 at every strip: dM_yaw/dv_sway =
    // -2 rho s sum x c_y.
    let mut dv = [0.0];
    let status = inst.get_directional_derivative(
        &[vr(Quantity::ForceViscous(YAW))],
        &[vr(Quantity::Velocity(SWAY))],
        &[1.0],
        &mut dv,
    );
    assert_eq!(status, Status::Ok);
    let moment: f64 = strips.iter().map(|s| s.x * s.lateral()).sum();
    let expected = -2.0 * DEFAULT_RHO * 0.5 * moment;
    assert!((dv[0] - expected).abs() < 1e-12 * expected.abs(), "{dv:?}");
    // A fixed parameter: refused after initialization, naming it.
    assert_eq!(inst.set_real(&[scale], &[1.0]), Status::Error);
    let texts: Vec<_> = inst.take_messages().into_iter().map(|m| m.text).collect();
    assert!(
        texts.iter().any(|t| t.contains("fixed parameter")),
        "{texts:?}"
    );
    // The description declares the parameter, unit 1, start 1, in both standards.
    let info = DescriptionInfo {
        model_identifier: "Ship".into(),
        guid: "{ship}".into(),
        ..Default::default()
    };
    for xml in [
        layout.model_description(FIXED_XML, &info).unwrap(),
        layout.model_description_fmi3(FIXED_XML, &info).unwrap(),
    ] {
        let at = xml.find("name=\"crossflow.drag_scale\"").unwrap();
        let declaration = &xml[at..at + 400];
        assert!(
            declaration.contains("causality=\"parameter\""),
            "{declaration}"
        );
        assert!(declaration.contains("start=\"1.0\""), "{declaration}");
        assert!(declaration.contains("unit=\"1\""), "{declaration}");
    }
}
