//! Tests of the whole component, and the networks the other tests use.

use super::*;

/// Schilder et al.'s 2-DOF network (the shipped example file).
pub(crate) const SEED_NETWORK: &str = include_str!("../../examples/networks/seed_2dof.xml");

/// A coupled 2-DOF network (sway, roll) at rho = g = 1.
pub(crate) const TWO_DOF_NETWORK: &str = r#"<network format_version="1" form="coupled" rho="1" g="1">
  <dof name="sway"/>
  <dof name="roll"/>
  <added_mass_inf><row>0.2 0.05</row><row>0.05 0.1</row></added_mass_inf>
  <branch>
<direction>1 0</direction>
<stage mass="0.5" stiffness="0.3" damping="0.8"/>
<stage mass="0.2" stiffness="0.5" damping="0.2"/>
  </branch>
  <branch>
<direction>0.3 1</direction>
<stage mass="0.4" stiffness="0.7" damping="0.6"/>
  </branch>
</network>
"#;

/// The substructure of [`two_dof_substructure_network`] (one unit mass, two relaxed springs,
/// full damping).
const SUBSTRUCTURE: &str = r#"  <substructure springs="2" masses="1">
<spring_incidence><row>1 -0.7 0.2</row><row>0.4 0.3 -1.1</row></spring_incidence>
<spring_relaxation><row>0.2 0.05</row><row>0.05 0.1</row></spring_relaxation>
<damping><row>0.5 -0.2 0.1</row><row>-0.2 0.3 0</row><row>0.1 0 0.2</row></damping>
  </substructure>
"#;

/// [`TWO_DOF_NETWORK`] with a substructure added after its branches.
pub(crate) fn two_dof_substructure_network() -> String {
    TWO_DOF_NETWORK.replace("</network>", &format!("{SUBSTRUCTURE}</network>"))
}

/// An exciting force table for [`TWO_DOF_NETWORK`] (R = 2 m, head seas, kR 0.1 .. 1).
pub(crate) const TWO_DOF_EXCITATION: &str = "# modes: sway roll\n# convention: exp(+i omega t)\n\
     # R: 2 m\n# length exponents: 0 1\nkR,j,heading,re,im\n\
     0.1,1,0,0.1,0.2\n0.1,2,0,0.3,-0.1\n0.5,1,0,0.4,-0.25\n0.5,2,0,-0.2,0.6\n\
     1,1,0,0.2,0.1\n1,2,0,0.1,0.1\n";

/// The component of a network text, at the default rho and g, with the default GUID.
pub(crate) fn model(network: &str, keep_inf_mass: bool) -> Model {
    let network = Network::from_xml_str(network, "test.xml").unwrap();
    let options = ModelOptions {
        keep_inf_mass,
        guid: None,
    };
    Model::new(&network, options).unwrap()
}

/// Schilder et al.'s network at rho, g.
pub(crate) fn seed(rho: f64, g: f64) -> Model {
    let mut m = model(SEED_NETWORK, false);
    m.set_parameters(rho, g).unwrap();
    m
}

#[test]
fn seed_impulse_response_reaches_the_common_velocity() {
    // Figure 7 of Schilder et al.: body m = 1 (+ m0) with unit impulse, explicit coupling with
    // a small step; final velocity 1 / (m + m0 + m1 + m2) (momentum conservation).
    let mut model = seed(1.0, 1.0);
    let (m, m0) = (1.0, 0.1153);
    let h = 1e-3;
    let mut v = 1.0 / (m + m0);
    let mut t = 0.0;
    for _ in 0..60_000 {
        model.set_value(Quantity::Velocity(0), v).unwrap();
        let f = model.value(Quantity::Force(0)).unwrap();
        model.step(t, h).unwrap();
        t = model.time();
        v += h * f / (m + m0);
    }
    let expected = 1.0 / (m + m0 + 0.5434 + 0.1877);
    // Explicit coupling error O(h) on a 60 s run; 1e-3 of the final velocity.
    assert!((v - expected).abs() < 1e-3 * expected, "{v} vs {expected}");
}

#[test]
fn bad_steps_and_inputs_leave_the_state_unchanged() {
    let mut m = seed(1.0, 1.0);
    m.set_value(Quantity::Velocity(0), 1.0).unwrap();
    m.step(0.0, 0.1).unwrap();
    let before = m.state().clone();
    assert!(m.step(0.1, 0.0).is_err());
    assert!(m.step(0.1, -1.0).is_err());
    assert!(m.step(0.1, f64::NAN).is_err());
    assert!(m.step(0.2, 0.1).is_err());
    assert!(m.step(f64::NAN, 0.1).is_err());
    assert!(m.set_value(Quantity::Velocity(0), f64::NAN).is_err());
    assert!(m.set_value(Quantity::Velocity(0), f64::INFINITY).is_err());
    assert!(m.set_value(Quantity::Force(0), 1.0).is_err());
    assert!(m
        .set_input_derivative(Quantity::Velocity(0), f64::NAN)
        .is_err());
    // Huge but finite inputs beyond MAX_INPUT: refused, unchanged.
    assert!(m.set_value(Quantity::Velocity(0), 1e308).is_err());
    assert!(m
        .set_input_derivative(Quantity::Velocity(0), -1e101)
        .is_err());
    assert!(m.set_parameters(1e300, 9.81).is_err());
    assert_eq!(m.state(), &before);
    // At the bound, a ramp over a long step still stays finite; then back to 1 m/s.
    m.set_value(Quantity::Velocity(0), MAX_INPUT).unwrap();
    m.set_input_derivative(Quantity::Velocity(0), MAX_INPUT)
        .unwrap();
    let mut probe = m.clone();
    probe.step(0.1, 10.0).unwrap();
    assert!(probe.forces().iter().all(|f| f.is_finite()));
    assert!(probe.value(Quantity::Energy).unwrap().is_finite());
    m.set_value(Quantity::Velocity(0), 1.0).unwrap();
    m.set_input_derivative(Quantity::Velocity(0), 0.0).unwrap();
    assert_eq!(m.state(), &before);
    // A tiny time mismatch (rounding) is accepted.
    m.step(0.1 + 1e-15, 0.1).unwrap();
}

#[test]
fn new_matches_the_component_loaded_from_resources() {
    // The same network from its canonical text: same system, state and GUID; an explicit
    // GUID (what fmu-pack passes when hull.xml is packed too) is kept.
    let network = Network::from_xml_str(TWO_DOF_NETWORK, "test.xml").unwrap();
    for keep_inf_mass in [false, true] {
        let resources = Resources::for_network(&network, None, keep_inf_mass);
        let loaded = Model::from_resources(&resources).unwrap();
        let built = model(TWO_DOF_NETWORK, keep_inf_mass);
        assert_eq!(built.guid(), resources.guid());
        assert_eq!(loaded.guid(), built.guid());
        assert_eq!(loaded.system(), built.system());
        assert_eq!(loaded.state(), built.state());
    }
    let options = ModelOptions {
        keep_inf_mass: false,
        guid: Some("{given}".into()),
    };
    assert_eq!(Model::new(&network, options).unwrap().guid(), "{given}");
}

#[test]
fn bad_resources_are_refused() {
    let resources =
        Resources::new("<network/>".into(), None, Resources::options_text(false)).unwrap();
    assert!(Model::from_resources(&resources).is_err());
    let err = Model::load(Path::new("/nonexistent/resources")).unwrap_err();
    assert!(
        err.to_string().starts_with("resources: cannot read"),
        "{err}"
    );
}

#[test]
fn resources_with_a_hull_and_an_excitation_table_give_hydrostatics_and_checked_waves() {
    use std::f64::consts::PI;
    // The network's DOFs are sway and roll; the hull names them in another order, with
    // roll about (0, -0.5).
    let hull = r#"<hull name="half" half_beam="1.5" units="m" version="1">
  <circle radius="1.5" depth="0"/>
  <rigid name="roll" kind="roll" x="0" y="-0.5"/>
  <rigid name="heave" kind="heave"/>
  <rigid name="sway" kind="sway"/>
</hull>"#;
    let resources = Resources::new(
        TWO_DOF_NETWORK.to_string(),
        Some(hull.to_string()),
        Resources::options_text(false),
    )
    .unwrap();
    let mut m = Model::from_resources(&resources).unwrap();
    assert_eq!(m.dof_names(), ["sway", "roll"]);
    m.set_parameters(1000.0, 10.0).unwrap();
    // rho g [I_wp + A (y_B - y_c)] with I_wp = 2R^3/3, A = pi R^2/2, y_B = -4R/(3 pi).
    let r: f64 = 1.5;
    let roll = 2.0 * r.powi(3) / 3.0 + PI * r * r / 2.0 * (-4.0 * r / (3.0 * PI) + 0.5);
    let c = m.stiffness_hydrostatic();
    assert_eq!(c.shape(), (2, 2));
    assert!((c[(1, 1)] - 1e4 * roll).abs() < 1e-8, "{c}");
    assert!(c[(0, 0)].abs() < 1e-9 && c[(0, 1)].abs() < 1e-9 && c[(1, 0)].abs() < 1e-9);
    // A table for other DOFs is refused, naming the file.
    let table = "# modes: roll sway\n# convention: exp(+i omega t)\n# R: 1 m\n\
                 # length exponents: 1 0\nkR,j,heading,re,im\n\
                 0.1,1,0,1,0\n0.1,2,0,0,1\n1,1,0,1,0\n1,2,0,0,1\n";
    let err = Model::from_resources(&resources.clone().with_excitation(Some(table.into())))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("resources/excitation.csv") && err.contains("differ"),
        "{err}"
    );
    let ordered = table.replace("roll sway", "sway roll");
    let m = Model::from_resources(&resources.with_excitation(Some(ordered))).unwrap();
    assert_eq!(m.excitation().unwrap().modes(), ["sway", "roll"]);
}

#[test]
fn a_regular_wave_adds_the_tables_force_and_calm_water_changes_nothing() {
    use crate::fmu::variables::WaveParameter;
    let table = TWO_DOF_EXCITATION;
    let resources = Resources::new(TWO_DOF_NETWORK.into(), None, Resources::options_text(false))
        .unwrap()
        .with_excitation(Some(table.into()));
    let (rho, g, radius): (f64, f64, f64) = (1000.0, 9.8, 2.0);
    let omega = (0.5 * g / radius).sqrt();
    let build = |kind: i32| {
        let mut m = Model::from_resources(&resources).unwrap();
        m.set_parameters(rho, g).unwrap();
        m.set_wave_integer(WaveParameter::Kind, kind).unwrap();
        m.set_wave_real(WaveParameter::Height, 1.5).unwrap();
        m.set_wave_real(WaveParameter::Period, 2.0 * std::f64::consts::PI / omega)
            .unwrap();
        m.set_start_time(0.0).unwrap();
        m.start_waves().unwrap();
        m.set_value(Quantity::Velocity(0), 0.3).unwrap();
        m
    };
    let (mut calm, mut wave) = (build(0), build(1));
    let amplitude = 0.75;
    // X = (re + i im) rho g R^(1 + e).
    let x = [
        num_complex::Complex64::new(0.4, -0.25) * (rho * g * radius),
        num_complex::Complex64::new(-0.2, 0.6) * (rho * g * radius * radius),
    ];
    for _ in 0..37 {
        calm.step(calm.time(), 0.05).unwrap();
        wave.step(wave.time(), 0.05).unwrap();
        let t = wave.time();
        let phasor = num_complex::Complex64::new(0.0, omega * t).exp();
        let radiation = calm.forces().clone();
        assert_eq!(wave.force_radiation(), &radiation);
        for j in 0..2 {
            let expected = (x[j] * phasor * amplitude).re;
            let got = wave.force_excitation()[j];
            assert!(
                (got - expected).abs() < 1e-9 * x[j].norm(),
                "{j}: {got} vs {expected}"
            );
            assert_eq!(wave.value(Quantity::Force(j)).unwrap(), radiation[j] + got);
        }
        assert!((wave.wave_elevation() - amplitude * (omega * t).cos()).abs() < 1e-12);
        assert_eq!(
            calm.force_excitation().iter().copied().fold(0.0, f64::max),
            0.0
        );
        assert_eq!(calm.wave_elevation(), 0.0);
    }
    // Power and its derivatives are the radiation's; the excitation's g-derivative is refused
    // rather than wrong; its time derivative is the harmonic's, Re[i omega a X e^(i omega t)].
    assert_eq!(
        wave.value(Quantity::Power).unwrap(),
        calm.value(Quantity::Power).unwrap()
    );
    assert_eq!(
        wave.partial_derivative(Quantity::Power, Quantity::Velocity(0))
            .unwrap(),
        calm.partial_derivative(Quantity::Power, Quantity::Velocity(0))
            .unwrap()
    );
    assert_eq!(
        wave.output_derivative(Quantity::ForceRadiation(1)).unwrap(),
        calm.output_derivative(Quantity::Force(1)).unwrap()
    );
    let t = wave.time();
    let phasor = num_complex::Complex64::new(0.0, omega * t).exp();
    let radiation_rate = wave.output_derivative(Quantity::ForceRadiation(1)).unwrap();
    let excitation_rate = (num_complex::Complex64::i() * omega * x[1] * phasor * amplitude).re;
    let got = wave
        .output_derivative(Quantity::ForceExcitation(1))
        .unwrap();
    assert!((got - excitation_rate).abs() < 1e-9 * omega * x[1].norm());
    assert_eq!(
        wave.output_derivative(Quantity::Force(1)).unwrap(),
        radiation_rate + got
    );
    let elevation_rate = wave.output_derivative(Quantity::WaveElevation).unwrap();
    assert!((elevation_rate + amplitude * omega * (omega * t).sin()).abs() < 1e-12);
    assert_eq!(
        calm.output_derivative(Quantity::ForceExcitation(1))
            .unwrap(),
        0.0
    );
    assert!(wave
        .partial_derivative(Quantity::Force(0), Quantity::G)
        .is_err());
    // Waves without a table are refused when initialization ends.
    let plain =
        Resources::new(TWO_DOF_NETWORK.into(), None, Resources::options_text(false)).unwrap();
    let mut m = Model::from_resources(&plain).unwrap();
    m.set_wave_integer(WaveParameter::Kind, 2).unwrap();
    let err = m.start_waves().unwrap_err().to_string();
    assert!(err.contains("without an excitation table"), "{err}");
}

#[test]
fn outputs_that_overflow_are_errors_and_change_nothing() {
    // rho = g = 1e100, v = 1e100 m/s: each accepted; the force -c1 rho sqrt(g) v = -1e250
    // N/m is finite, power = -F v and its derivatives overflow.
    let mut m = seed(1e100, 1e100);
    m.set_value(Quantity::Velocity(0), 1e100).unwrap();
    let before = m.state().clone();
    assert!(m.value(Quantity::Force(0)).unwrap().is_finite());
    for result in [
        m.value(Quantity::Power),
        m.output_derivative(Quantity::Power),
        m.partial_derivative(Quantity::Power, Quantity::Rho),
    ] {
        let err = result.unwrap_err().to_string();
        assert!(err.contains("power") && err.contains("not finite"), "{err}");
    }
    assert_eq!(m.state(), &before);
    // A moderate input reads again.
    m.set_value(Quantity::Velocity(0), 1.0).unwrap();
    assert!(m.value(Quantity::Power).unwrap().is_finite());
}

#[test]
fn a_parameter_change_whose_hydrostatic_stiffness_overflows_is_refused() {
    // C / (rho g) of 1e120 (a hull of 1e40 m) times rho g = 1e200 overflows.
    let mut m = model(TWO_DOF_NETWORK, false);
    m.hydrostatics_per_rho_g = Some(DMatrix::from_element(2, 2, 1e120));
    let err = m.set_parameters(1e100, 1e100).unwrap_err().to_string();
    assert!(err.contains("stiffness_hydrostatic"), "{err}");
    assert_eq!((m.state().rho, m.state().g), (DEFAULT_RHO, DEFAULT_G));
    assert_eq!(m.system().rho(), DEFAULT_RHO);
    m.set_parameters(1e90, 1.0).unwrap();
    let c = m.value(Quantity::StiffnessHydrostatic(0, 1)).unwrap();
    assert_eq!(c, 1e210);
}

#[test]
fn a_step_whose_end_time_overflows_is_refused() {
    // From the largest f64, a step of 1e300 s (discretized without trouble) ends past it.
    let mut m = seed(1.0, 1.0);
    m.set_start_time(f64::MAX).unwrap();
    let before = m.state().clone();
    let err = m.step(f64::MAX, 1e300).unwrap_err().to_string();
    assert!(err.contains("time"), "{err}");
    assert_eq!(m.state(), &before);
    m.set_start_time(1e308).unwrap();
    m.step(1e308, 1e300).unwrap();
    assert_eq!(m.time(), 1e308 + 1e300);
}

#[test]
fn the_step_counter_starts_a_new_anchor_before_it_loses_exactness() {
    // 2^53 steps of 0.25 s from -2^51 s end at 0. One more counted from that anchor would be
    // (2^53 + 1) as f64 = 2^53 steps: the time would stay at 0.
    let mut m = seed(1.0, 1.0);
    let mut state = m.state().clone();
    state.time_anchor = -(2f64.powi(51));
    state.start_time = state.time_anchor;
    state.last_step = 0.25;
    state.steps_since_anchor = 1 << 53;
    state.time = 0.0;
    m.set_state(state).unwrap();
    m.step(0.0, 0.25).unwrap();
    assert_eq!(m.time(), 0.25);
    m.step(0.25, 0.25).unwrap();
    assert_eq!(m.time(), 0.5);
}

#[test]
fn a_step_past_the_stop_time_is_refused_and_reset_clears_it() {
    let mut m = seed(1.0, 1.0);
    assert!(m.set_experiment(2.0, Some(1.0)).is_err());
    assert!(m.set_experiment(0.0, Some(f64::NAN)).is_err());
    assert!(m.set_experiment(f64::NAN, None).is_err());
    // +inf: no stop time.
    m.set_experiment(0.0, Some(f64::INFINITY)).unwrap();
    assert_eq!(m.state().stop_time, None);
    m.set_experiment(0.0, Some(1.0)).unwrap();
    m.set_value(Quantity::Velocity(0), 1.0).unwrap();
    // Ten steps of 0.1 end at 1 to rounding (1e-10 of the larger of the stop time and h).
    let mut t = 0.0;
    for _ in 0..10 {
        m.step(t, 0.1).unwrap();
        t += 0.1;
    }
    let end = m.state().clone();
    let err = m.step(m.time(), 1e-9).unwrap_err().to_string();
    assert!(err.contains("past the stop time 1"), "{err}");
    assert_eq!(m.state(), &end);
    m.reset().unwrap();
    assert_eq!(m.state().stop_time, None);
    m.step(0.0, 5.0).unwrap();
}
