//! The drift force in the component: `wave.drift`, `force_drift`, the state bytes, and every
//! output unchanged without it.

use super::tests::{TWO_DOF_EXCITATION, TWO_DOF_NETWORK};
use super::*;
use crate::fmi::{Instance, Status};
use crate::fmu::variables::WaveParameter;

/// A drift table for the two DOFs of [`TWO_DOF_EXCITATION`] (R = 2 m, heading 0, kR 0.1 .. 1):
/// sway `0.3 kR`, roll `0.05 kR`.
pub(crate) const TWO_DOF_DRIFT: &str = "# modes: sway roll\n# convention: exp(+i omega t)\n\
     # R: 2 m\n# length exponents: 0 1\nkR,j,heading,value\n\
     0.1,1,0,0.03\n0.1,2,0,0.005\n0.5,1,0,0.15\n0.5,2,0,0.025\n1,1,0,0.3\n1,2,0,0.05\n";

fn resources(drift: bool) -> Resources {
    Resources::new(TWO_DOF_NETWORK.into(), None, Resources::options_text(false))
        .unwrap()
        .with_excitation(Some(TWO_DOF_EXCITATION.into()))
        .with_drift(drift.then(|| TWO_DOF_DRIFT.to_string()))
}

/// A JONSWAP sea (Hs 2 m, Tp 6 s, ramp 10 s) started at 0, with `wave.drift` = `mode` when
/// the FMU has a drift table.
fn jonswap_model(drift: bool, mode: i32) -> Model {
    let mut m = Model::from_resources(&resources(drift)).unwrap();
    m.set_wave_integer(WaveParameter::Kind, 2).unwrap();
    m.set_wave_real(WaveParameter::Height, 2.0).unwrap();
    m.set_wave_real(WaveParameter::Period, 6.0).unwrap();
    m.set_wave_real(WaveParameter::Ramp, 10.0).unwrap();
    if drift {
        m.set_wave_integer(WaveParameter::Drift, mode).unwrap();
    }
    m.set_start_time(0.0).unwrap();
    m.start_waves().unwrap();
    m
}

/// Every output of the two DOFs after each of `steps` steps of 0.1 s with moving inputs.
fn record(m: &mut Model, steps: usize) -> Vec<[u64; 8]> {
    (0..steps)
        .map(|k| {
            m.set_value(Quantity::Velocity(0), (0.3 * k as f64).sin())
                .unwrap();
            m.set_value(Quantity::Velocity(1), 0.1 * (0.2 * k as f64).cos())
                .unwrap();
            m.step(m.time(), 0.1).unwrap();
            let mut bits = [0u64; 8];
            for j in 0..2 {
                bits[j] = m.value(Quantity::Force(j)).unwrap().to_bits();
                bits[2 + j] = m.value(Quantity::ForceExcitation(j)).unwrap().to_bits();
                bits[4 + j] = m.value(Quantity::ForceRadiation(j)).unwrap().to_bits();
            }
            bits[6] = m.value(Quantity::WaveElevation).unwrap().to_bits();
            bits[7] = m.value(Quantity::Power).unwrap().to_bits();
            bits
        })
        .collect()
}

#[test]
fn wave_drift_zero_gives_every_output_bit_for_bit_as_without_the_table() {
    let without = record(&mut jonswap_model(false, 0), 500);
    let with = record(&mut jonswap_model(true, 0), 500);
    assert_eq!(with, without);
    // The waves move the force: the comparison is not between zeros.
    assert!(without.iter().any(|b| f64::from_bits(b[2]).abs() > 100.0));
}

#[test]
fn the_force_includes_the_drift_in_both_modes() {
    for mode in [1, 2] {
        let mut m = jonswap_model(true, mode);
        let mut mean = 0.0;
        let steps = 3000;
        for _ in 0..steps {
            m.step(m.time(), 0.1).unwrap();
            let drift = m.value(Quantity::ForceDrift(0)).unwrap();
            let parts = m.value(Quantity::ForceRadiation(0)).unwrap()
                + m.value(Quantity::ForceExcitation(0)).unwrap();
            assert_eq!(m.value(Quantity::Force(0)).unwrap(), parts + drift);
            assert_eq!(m.force_drift()[0], drift);
            mean += drift / steps as f64;
        }
        // Sway drifts with the waves (heading 0, a positive table): the ramp is over at 10 s.
        let sea_mean = m.sea.as_ref().unwrap().0.mean_drift(0);
        assert!(sea_mean > 0.0);
        if mode == 1 {
            assert_eq!(m.value(Quantity::ForceDrift(0)).unwrap(), sea_mean);
        }
        // Newman's record over 300 s scatters about the mean (its slow part is random).
        assert!(
            mean > 0.2 * sea_mean && mean < 2.0 * sea_mean,
            "{mean} {sea_mean}"
        );
        // The drift does not depend on the inputs; its rate is the sea's.
        assert_eq!(
            m.partial_derivative(Quantity::ForceDrift(1), Quantity::Velocity(0))
                .unwrap(),
            0.0
        );
        let rate = m.output_derivative(Quantity::ForceDrift(0)).unwrap();
        let mut expected = [0.0; 2];
        m.sea
            .as_ref()
            .unwrap()
            .0
            .evaluate_drift_rate(m.time(), &mut expected);
        assert_eq!(rate, expected[0]);
    }
}

#[test]
fn wave_drift_is_refused_without_a_drift_table() {
    let mut m = Model::from_resources(&resources(false)).unwrap();
    for mode in [1, 2] {
        let err = m
            .set_wave_integer(WaveParameter::Drift, mode)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("without a drift table") && err.contains("drift.csv"),
            "{err}"
        );
    }
    m.set_wave_integer(WaveParameter::Drift, 0).unwrap();
    assert!(m.value(Quantity::ForceDrift(0)).is_err());
    let mut with = Model::from_resources(&resources(true)).unwrap();
    let err = with
        .set_wave_integer(WaveParameter::Drift, 3)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("wave.drift") && err.contains("0 (none)"),
        "{err}"
    );
    // A table for other DOFs is refused, naming the file.
    let swapped =
        resources(false).with_drift(Some(TWO_DOF_DRIFT.replace("sway roll", "roll sway")));
    let err = Model::from_resources(&swapped).unwrap_err().to_string();
    assert!(
        err.contains("resources/drift.csv") && err.contains("differ"),
        "{err}"
    );
}

#[test]
fn the_drift_parameter_survives_the_state_bytes_and_other_fmus_bytes_are_unchanged() {
    let mut m = jonswap_model(true, 2);
    m.step(0.0, 0.5).unwrap();
    let bytes = m.serialize(7);
    assert_eq!(bytes.len(), m.serialized_size());
    let plain = jonswap_model(false, 0);
    assert_eq!(
        plain.serialize(0).len() + 4,
        m.serialized_size() - (m.guid().len() - plain.guid().len())
    );
    let mut other = jonswap_model(true, 0);
    let (state, tag) = other.deserialize(&bytes).unwrap();
    assert_eq!((state.waves.drift, tag), (DriftMode::Newman, 7));
    other.set_state(state).unwrap();
    assert_eq!(
        other.value(Quantity::Force(0)).unwrap(),
        m.value(Quantity::Force(0)).unwrap()
    );
    assert_eq!(other.wave_parameter(WaveParameter::Drift), 2.0);
    // A drift code out of range (checksum recomputed) is refused.
    let mut tampered = bytes.clone();
    let at = tampered.len() - 12;
    tampered[at..at + 4].copy_from_slice(&9i32.to_le_bytes());
    let body = tampered.len() - 8;
    let sum = super::snapshot::checksum(&tampered[..body]);
    tampered[body..].copy_from_slice(&sum.to_le_bytes());
    let err = other.deserialize(&tampered).unwrap_err().to_string();
    assert!(err.contains("wave.drift"), "{err}");
    // A state with drift on is refused by an FMU without a table.
    let mut state = plain.state().clone();
    state.waves.drift = DriftMode::Mean;
    let mut plain = plain;
    assert!(plain.set_state(state).is_err());
}

#[test]
fn wave_drift_is_declared_and_settable_only_with_a_drift_table() {
    let drift_reference = |drift: bool| {
        let layout = crate::fmu::Layout::new(
            vec![
                crate::fmu::DofUnit::builtin("sway").unwrap(),
                crate::fmu::DofUnit::builtin("roll").unwrap(),
            ],
            false,
        )
        .unwrap();
        let layout = if drift {
            layout.with_drift().unwrap()
        } else {
            layout
        };
        layout.value_reference(Quantity::Wave(WaveParameter::Drift))
    };
    assert_eq!(drift_reference(false), None);
    let vr = drift_reference(true).unwrap();
    let mut plain = Instance::from_resources(c"hull", &resources(false), false).unwrap();
    assert_eq!(plain.set_integer(&[vr], &[1]), Status::Error);
    let mut inst = Instance::from_resources(c"hull", &resources(true), false).unwrap();
    assert_eq!(inst.set_integer(&[vr], &[2]), Status::Ok);
    assert_eq!(inst.setup_experiment(None, 0.0, None), Status::Ok);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    let mut value = [0];
    assert_eq!(inst.get_integer(&[vr], &mut value), Status::Ok);
    assert_eq!(value, [2]);
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    // In calm water the drift output reads 0 (force_drift.sway: two below wave.drift).
    let mut real = [f64::NAN];
    assert_eq!(inst.get_real(&[vr - 2], &mut real), Status::Ok);
    assert_eq!(real, [0.0]);
    // A fixed parameter after initialization; out of its declared range.
    assert_eq!(inst.set_integer(&[vr], &[1]), Status::Error);
    let mut fresh = Instance::from_resources(c"hull", &resources(true), false).unwrap();
    assert_eq!(fresh.set_integer(&[vr], &[3]), Status::Error);
}
