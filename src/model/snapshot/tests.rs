//! State bytes: the round trip, corrupt bytes, and bytes whose checksum was recomputed after
//! a change (each field checked for what it means).

use super::fnv1a;
use crate::fmu::variables::Quantity;
use crate::model::tests::{model, seed, SEED_NETWORK, TWO_DOF_NETWORK};
use crate::model::Model;

/// A field of the state bytes (the layout of the module docs); vectors by entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum StateField {
    Rho,
    G,
    Time,
    TimeAnchor,
    LastStep,
    Steps,
    Network(usize),
    Velocity(usize),
    VelocityDerivative(usize),
    Acceleration(usize),
    AccelerationDerivative(usize),
    StartTime,
    StopTime,
}

/// Where `field` starts in the state bytes `m` writes.
pub(crate) fn offset(m: &Model, field: StateField) -> usize {
    let n = m.dof_count();
    let ns = m.system().state_size();
    // magic, version, tag, GUID length and GUID, n, states, keep_inf_mass
    let rho = 8 + 4 + 1 + 4 + m.guid().len() + 4 + 4 + 1;
    let network = rho + 6 * 8;
    let velocity = network + 8 * ns;
    let vector = |k: usize, i: usize| velocity + 8 * (k * n + i);
    match field {
        StateField::Rho => rho,
        StateField::G => rho + 8,
        StateField::Time => rho + 16,
        StateField::TimeAnchor => rho + 24,
        StateField::LastStep => rho + 32,
        StateField::Steps => rho + 40,
        StateField::Network(i) => network + 8 * i,
        StateField::Velocity(i) => vector(0, i),
        StateField::VelocityDerivative(i) => vector(1, i),
        StateField::Acceleration(i) => vector(2, i),
        StateField::AccelerationDerivative(i) => vector(3, i),
        // After the four input vectors: the wave parameters (kind, seed, components, five
        // f64), then the start and the stop time.
        StateField::StartTime => vector(4, 0) + 12 + 5 * 8,
        StateField::StopTime => vector(4, 0) + 12 + 6 * 8,
    }
}

/// The checksum of `bytes` recomputed (what an attacker who knows the format does).
pub(crate) fn resealed(mut bytes: Vec<u8>) -> Vec<u8> {
    if bytes.len() >= 8 {
        let body = bytes.len() - 8;
        let sum = fnv1a(&bytes[..body]);
        bytes[body..].copy_from_slice(&sum.to_le_bytes());
    }
    bytes
}

/// `bytes` (written by `m`) with `field` set to `value` and the checksum recomputed.
pub(crate) fn tampered(m: &Model, bytes: &[u8], field: StateField, value: [u8; 8]) -> Vec<u8> {
    let at = offset(m, field);
    let mut bad = bytes.to_vec();
    bad[at..at + 8].copy_from_slice(&value);
    resealed(bad)
}

/// Schilder et al.'s network at rho = 1025, g = 9.81 after two steps of 0.25 s at 0.7 m/s, and its
/// state bytes (tag 2).
fn stepped() -> (Model, Vec<u8>) {
    let mut m = seed(1025.0, 9.81);
    m.set_value(Quantity::Velocity(0), 0.7).unwrap();
    m.step(0.0, 0.25).unwrap();
    m.step(0.25, 0.25).unwrap();
    let bytes = m.serialize(2);
    (m, bytes)
}

/// Each case must be refused with a message containing its text; the model is unchanged.
fn assert_refused(m: &Model, bytes: &[u8], cases: &[(StateField, [u8; 8], &str)]) {
    let before = m.state().clone();
    for (field, value, expected) in cases {
        let bad = tampered(m, bytes, *field, *value);
        match m.deserialize(&bad) {
            Ok((state, _)) => panic!("{field:?} = {value:?} accepted: {state:?}"),
            Err(e) => {
                let text = e.to_string();
                assert!(text.contains(expected), "{field:?}: {text}");
            }
        }
        assert_eq!(m.state(), &before);
    }
}

#[test]
fn serialized_state_round_trips_and_bad_bytes_are_rejected() {
    let mut m = seed(1025.0, 9.81);
    m.set_value(Quantity::Velocity(0), 0.7).unwrap();
    m.step(0.0, 0.25).unwrap();
    let bytes = m.serialize(3);
    assert_eq!(bytes.len(), m.serialized_size());
    let (state, tag) = m.deserialize(&bytes).unwrap();
    assert_eq!(tag, 3);
    assert_eq!(&state, m.state());
    // Continue identically from a restored copy.
    let mut other = model(SEED_NETWORK, false);
    other.set_state(state).unwrap();
    m.step(0.25, 0.25).unwrap();
    other.step(0.25, 0.25).unwrap();
    assert_eq!(m.state(), other.state());
    // Every single flipped byte is caught.
    for i in 0..bytes.len() {
        let mut bad = bytes.clone();
        bad[i] ^= 0x10;
        assert!(m.deserialize(&bad).is_err(), "byte {i}");
    }
    assert!(m.deserialize(&bytes[..bytes.len() - 1]).is_err());
    assert!(m.deserialize(b"").is_err());
    // A state of another FMU (other network) is refused by GUID.
    let foreign = model(TWO_DOF_NETWORK, false);
    let err = m.deserialize(&foreign.serialize(0)).unwrap_err();
    assert!(err.to_string().contains("FMU"), "{err}");
}

#[test]
fn the_test_layout_matches_the_written_bytes() {
    // The offsets the attack tests write to hold the values of the state.
    let (m, bytes) = stepped();
    let read = |field| {
        let at = offset(&m, field);
        f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap())
    };
    let s = m.state();
    assert_eq!(read(StateField::Rho), s.rho);
    assert_eq!(read(StateField::G), s.g);
    assert_eq!(read(StateField::Time), s.time);
    assert_eq!(read(StateField::TimeAnchor), s.time_anchor);
    assert_eq!(read(StateField::LastStep), s.last_step);
    assert_eq!(read(StateField::Steps).to_bits(), s.steps_since_anchor);
    assert_eq!(read(StateField::Network(3)), s.network[3]);
    assert_eq!(read(StateField::Velocity(0)), s.velocity[0]);
    assert_eq!(read(StateField::StartTime), s.start_time);
    assert_eq!(read(StateField::StopTime), f64::INFINITY);
    assert_eq!(offset(&m, StateField::StopTime) + 16, bytes.len());
    // Unchanged values give the same bytes back.
    let same = tampered(&m, &bytes, StateField::Time, s.time.to_le_bytes());
    assert_eq!(same, bytes);
}

#[test]
fn step_counters_that_break_the_time_are_refused() {
    // After two steps of 0.25 s: anchor 0, 2 steps, time 0.5. A counter of 2^64 - 1 used to
    // wrap to 0 on the next step (time back to the anchor), 2^53 jumped the time to 2^53 h.
    let (m, bytes) = stepped();
    let steps = |k: u64| (StateField::Steps, k.to_le_bytes(), "steps");
    assert_refused(
        &m,
        &bytes,
        &[
            steps(u64::MAX),
            steps((1 << 53) + 1),
            steps(1 << 53),
            steps(3),
            steps(0),
        ],
    );
}

#[test]
fn times_that_are_not_finite_or_do_not_add_up_are_refused() {
    let (m, bytes) = stepped();
    let f = |field, x: f64, expected| (field, x.to_le_bytes(), expected);
    assert_refused(
        &m,
        &bytes,
        &[
            f(StateField::Time, f64::NAN, "time is NaN"),
            f(StateField::Time, f64::INFINITY, "time is inf"),
            // Not anchor + 2 x 0.25.
            f(StateField::Time, 0.75, "time 0.75"),
            f(StateField::Time, 9e13, "time 90000000000000"),
            f(
                StateField::TimeAnchor,
                f64::NEG_INFINITY,
                "time anchor is -inf",
            ),
            f(StateField::TimeAnchor, 0.1, "time 0.5"),
            f(StateField::LastStep, f64::NAN, "last step is NaN"),
            f(StateField::LastStep, 0.0, "last step 0"),
            f(StateField::LastStep, -0.25, "last step -0.25"),
            f(StateField::StartTime, f64::NAN, "start time is NaN"),
        ],
    );
}

#[test]
fn state_values_that_are_not_finite_or_overflow_the_outputs_are_refused() {
    // Force = C z + D v, energy = 1/2 z^T P z: the first spring's stiffness at rho = 1025,
    // g = 9.81 is 2352 N/m^2, so an elongation of 1e306 m overflows the force and 1e200 m
    // the energy.
    let (m, bytes) = stepped();
    let f = |field, x: f64, expected| (field, x.to_le_bytes(), expected);
    assert_refused(
        &m,
        &bytes,
        &[
            f(StateField::Network(0), f64::NAN, "network state"),
            f(StateField::Network(3), f64::NEG_INFINITY, "network state"),
            f(StateField::Network(0), 1e306, "force.sway"),
            f(StateField::Network(0), 1e200, "energy"),
            f(StateField::Velocity(0), f64::INFINITY, "velocity.sway"),
            f(StateField::Velocity(0), 1e101, "velocity.sway"),
            f(StateField::VelocityDerivative(0), f64::NAN, "derivative"),
            f(StateField::VelocityDerivative(0), -1e300, "derivative"),
            // No accelerations without keep_inf_mass.
            f(StateField::Acceleration(0), 1.0, "acceleration"),
            f(StateField::AccelerationDerivative(0), 1.0, "acceleration"),
            f(StateField::Rho, f64::NAN, "rho"),
            f(StateField::G, -9.81, "g"),
        ],
    );
    // Large values whose outputs stay finite are a state like any other.
    let big = tampered(&m, &bytes, StateField::Network(0), 1e150f64.to_le_bytes());
    let (state, _) = m.deserialize(&big).unwrap();
    let mut restored = m.clone();
    restored.set_state(state).unwrap();
    assert!(restored.value(Quantity::Energy).unwrap().is_finite());
}

#[test]
fn the_stop_time_travels_with_the_state_and_is_checked() {
    let mut m = seed(1025.0, 9.81);
    m.set_experiment(0.0, Some(1.0)).unwrap();
    m.set_value(Quantity::Velocity(0), 0.7).unwrap();
    m.step(0.0, 0.25).unwrap();
    m.step(0.25, 0.25).unwrap();
    let bytes = m.serialize(2);
    let (state, _) = m.deserialize(&bytes).unwrap();
    assert_eq!(state.stop_time, Some(1.0));
    // Into a component without a stop time: the restored state brings it.
    let mut other = model(SEED_NETWORK, false);
    other.set_state(state).unwrap();
    assert!(other.step(0.5, 0.75).is_err());
    other.step(0.5, 0.5).unwrap();
    let f = |field, x: f64, expected| (field, x.to_le_bytes(), expected);
    assert_refused(
        &m,
        &bytes,
        &[
            f(StateField::StopTime, f64::NAN, "stop time NaN"),
            f(StateField::StopTime, f64::NEG_INFINITY, "stop time -inf"),
            f(StateField::StopTime, -1.0, "before the start time"),
            f(StateField::StopTime, 0.4, "past the stop time 0.4"),
        ],
    );
    // +inf is no stop time; one at the time itself is fine.
    for (stop, expected) in [(f64::INFINITY, None), (0.5, Some(0.5))] {
        let bytes = tampered(&m, &bytes, StateField::StopTime, stop.to_le_bytes());
        assert_eq!(m.deserialize(&bytes).unwrap().0.stop_time, expected);
    }
}
