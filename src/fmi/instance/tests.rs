//! The safe layer driven without pointers: the state machine against the phase table, the
//! error rules, the log messages and the FMU states.

use super::*;
use crate::fmi::types::{fmi2DoStepStatus, fmi2ModelExchange};
use crate::fmu::description::{FIRST_PER_HULL_REFERENCE, VR_G, VR_RHO};
use crate::model::tests::{SEED_NETWORK, TWO_DOF_NETWORK};

const VELOCITY: u32 = FIRST_PER_HULL_REFERENCE;
const FORCE: u32 = FIRST_PER_HULL_REFERENCE + 1;
const POWER: u32 = FIRST_PER_HULL_REFERENCE + 2;
const ENERGY: u32 = FIRST_PER_HULL_REFERENCE + 3;
const ADDED_MASS: u32 = FIRST_PER_HULL_REFERENCE + 4;
const DAMPING: u32 = FIRST_PER_HULL_REFERENCE + 5;

fn instance(network: &str, keep: bool) -> Instance {
    let options = Resources::options_text(keep);
    let resources = Resources::new(network.to_string(), None, options).unwrap();
    Instance::from_resources(c"hull", &resources, false).unwrap()
}

/// Initialized at rho = g = 1, messages cleared.
fn ready(network: &str, keep: bool) -> Instance {
    let mut inst = instance(network, keep);
    assert_eq!(inst.set_real(&[VR_RHO, VR_G], &[1.0, 1.0]), Status::Ok);
    assert_eq!(inst.setup_experiment(None, 0.0, None), Status::Ok);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    inst.take_messages();
    inst
}

fn get(inst: &mut Instance, vr: &[u32]) -> Vec<f64> {
    let mut out = vec![0.0; vr.len()];
    assert_eq!(inst.get_real(vr, &mut out), Status::Ok);
    out
}

/// A fresh instance in `phase` (not Fatal), messages cleared.
fn in_phase(phase: Phase) -> Instance {
    let mut inst = match phase {
        Phase::Instantiated => instance(SEED_NETWORK, false),
        Phase::InitializationMode => {
            let mut inst = instance(SEED_NETWORK, false);
            assert_eq!(inst.enter_initialization_mode(), Status::Ok);
            inst
        }
        Phase::StepComplete => ready(SEED_NETWORK, false),
        Phase::Terminated => {
            let mut inst = ready(SEED_NETWORK, false);
            assert_eq!(inst.terminate(), Status::Ok);
            inst
        }
        Phase::Error => {
            let mut inst = ready(SEED_NETWORK, false);
            assert_eq!(inst.do_step(0.0, -1.0, false), Status::Error);
            inst
        }
        Phase::Fatal => unreachable!("only a panic leads there"),
    };
    assert_eq!(inst.phase(), phase);
    inst.take_messages();
    inst
}

/// Calls `function` with harmless arguments (empty lists, the current time).
fn call(inst: &mut Instance, function: Function, saved: &Snapshot) -> Status {
    use Function::*;
    let mut x = 0.0;
    let mut size = 0;
    let mut flag = 0;
    match function {
        SetDebugLogging => inst.set_debug_logging(false, &[]),
        SetupExperiment => inst.setup_experiment(None, 0.0, None),
        EnterInitializationMode => inst.enter_initialization_mode(),
        ExitInitializationMode => inst.exit_initialization_mode(),
        Terminate => inst.terminate(),
        Reset => inst.reset(),
        GetReal => inst.get_real(&[], &mut []),
        GetInteger => inst.get_integer(&[], &mut []),
        GetBoolean => inst.get_boolean(&[]),
        GetString => inst.get_string(&[]),
        SetReal => inst.set_real(&[], &[]),
        SetInteger => inst.set_integer(&[], &[]),
        SetBoolean => inst.set_boolean(&[]),
        SetString => inst.set_string(&[]),
        GetFmuState => inst.get_fmu_state(&mut None),
        SetFmuState => inst.set_fmu_state(saved),
        FreeFmuState => inst.free_fmu_state(None),
        SerializedFmuStateSize => inst.serialized_fmu_state_size(saved, &mut size),
        SerializeFmuState => inst.serialize_fmu_state(saved, &mut []),
        DeSerializeFmuState => inst.deserialize_fmu_state(&[], &mut None),
        GetDirectionalDerivative => inst.get_directional_derivative(&[], &[], &[], &mut []),
        SetRealInputDerivatives => inst.set_real_input_derivatives(&[], &[], &[]),
        GetRealOutputDerivatives => inst.get_real_output_derivatives(&[], &[], &mut []),
        DoStep => inst.do_step(inst.model.time(), 0.01, false),
        CancelStep => inst.cancel_step(),
        GetStatus => inst.get_status(fmi2DoStepStatus),
        GetRealStatus => inst.get_real_status(fmi2LastSuccessfulTime, &mut x),
        GetIntegerStatus => inst.get_integer_status(fmi2DoStepStatus),
        GetBooleanStatus => inst.get_boolean_status(fmi2Terminated, &mut flag),
        GetStringStatus => inst.get_string_status(fmi2DoStepStatus),
    }
}

fn refused(messages: &[Message]) -> bool {
    messages
        .iter()
        .any(|m| m.text.contains("not allowed in phase"))
}

#[test]
fn every_method_follows_the_phase_table() {
    let mut source = ready(SEED_NETWORK, false);
    let mut saved = None;
    assert_eq!(source.get_fmu_state(&mut saved), Status::Ok);
    let saved = saved.unwrap();
    for phase in [
        Phase::Instantiated,
        Phase::InitializationMode,
        Phase::StepComplete,
        Phase::Terminated,
        Phase::Error,
    ] {
        for function in Function::ALL {
            let mut inst = in_phase(phase);
            let status = call(&mut inst, function, &saved);
            let messages = inst.take_messages();
            if allowed(function).contains(phase) {
                assert!(
                    !refused(&messages),
                    "{function:?} in {phase:?}: {messages:?}"
                );
            } else {
                assert_eq!(status, Status::Error, "{function:?} in {phase:?}");
                assert_eq!(inst.phase(), phase, "{function:?} in {phase:?}");
                assert!(refused(&messages), "{function:?} in {phase:?}");
            }
        }
    }
}

#[test]
fn after_a_fatal_error_every_call_is_refused() {
    let mut source = ready(SEED_NETWORK, false);
    let mut saved = None;
    assert_eq!(source.get_fmu_state(&mut saved), Status::Ok);
    let saved = saved.unwrap();
    for function in Function::ALL {
        let mut inst = ready(SEED_NETWORK, false);
        assert_eq!(inst.enter_fatal(Function::DoStep), Status::Fatal);
        assert_eq!(call(&mut inst, function, &saved), Status::Error);
        assert_eq!(inst.phase(), Phase::Fatal);
    }
}

#[test]
fn a_normal_run_through_the_safe_api() {
    let mut inst = ready(SEED_NETWORK, false);
    assert_eq!(inst.set_real(&[VELOCITY], &[2.0]), Status::Ok);
    assert_eq!(
        get(&mut inst, &[FORCE, POWER, ENERGY, ADDED_MASS, DAMPING]),
        vec![-0.9962 * 2.0, 0.9962 * 4.0, 0.0, 0.1153, 0.9962]
    );
    let mut t = 0.0;
    for _ in 0..100 {
        assert_eq!(inst.do_step(t, 0.01, true), Status::Ok);
        t += 0.01;
    }
    let mut last = 0.0;
    assert_eq!(
        inst.get_real_status(fmi2LastSuccessfulTime, &mut last),
        Status::Ok
    );
    assert!((last - 1.0).abs() < 1e-12);
    let mut d = [0.0];
    let status = inst.get_directional_derivative(&[FORCE], &[VELOCITY], &[1.0], &mut d);
    assert_eq!((status, d), (Status::Ok, [-0.9962]));
    let mut terminated = 1;
    assert_eq!(
        inst.get_boolean_status(fmi2Terminated, &mut terminated),
        Status::Ok
    );
    assert_eq!(terminated, 0);
    assert_eq!(inst.get_status(fmi2DoStepStatus), Status::Discard);
    assert_eq!(inst.terminate(), Status::Ok);
    assert_eq!(get(&mut inst, &[FORCE]).len(), 1);
    // Logging is off and nothing failed: no messages.
    assert!(inst.take_messages().is_empty());
}

/// One call on an instance.
type Call = fn(&mut Instance) -> Status;

#[test]
fn a_failed_call_keeps_the_model_state_and_enters_the_error_phase() {
    let mut inst = ready(SEED_NETWORK, false);
    assert_eq!(inst.set_real(&[VELOCITY], &[1.0]), Status::Ok);
    assert_eq!(inst.do_step(0.0, 0.5, false), Status::Ok);
    let reference = get(&mut inst, &[FORCE, ENERGY, VELOCITY]);
    let mut saved = None;
    assert_eq!(inst.get_fmu_state(&mut saved), Status::Ok);
    let saved = saved.unwrap();
    let failures: Vec<(&str, Call)> = vec![
        ("wrong time", |i| i.do_step(0.7, 0.1, false)),
        ("NaN input", |i| i.set_real(&[VELOCITY], &[f64::NAN])),
        ("valid then huge", |i| {
            i.set_real(&[VELOCITY, VELOCITY], &[2.0, 1e300])
        }),
        ("set an output", |i| i.set_real(&[FORCE], &[1.0])),
        ("set rho late", |i| i.set_real(&[VR_RHO], &[1.0])),
        ("lengths differ", |i| i.set_real(&[VELOCITY], &[])),
        ("unknown vr", |i| i.get_real(&[99_999], &mut [0.0])),
        ("integer", |i| i.get_integer(&[VELOCITY], &mut [0])),
        ("category", |i| i.set_debug_logging(true, &["logNothing"])),
        ("order 2", |i| {
            i.set_real_input_derivatives(&[VELOCITY], &[2], &[1.0])
        }),
        ("corrupt bytes", |i| {
            i.deserialize_fmu_state(&[7; 64], &mut None)
        }),
    ];
    for (what, failing) in failures {
        assert_eq!(failing(&mut inst), Status::Error, "{what}");
        assert_eq!(inst.phase(), Phase::Error, "{what}");
        assert_eq!(
            get(&mut inst, &[FORCE, ENERGY, VELOCITY]),
            reference,
            "{what}"
        );
        let messages = inst.take_messages();
        assert!(
            messages.iter().any(|m| m.category == Category::Error),
            "{what}"
        );
        assert_eq!(inst.set_fmu_state(&saved), Status::Ok, "{what}");
        assert_eq!(inst.phase(), Phase::StepComplete, "{what}");
    }
}

#[test]
fn each_call_is_logged_once_with_its_final_status() {
    let mut inst = ready(SEED_NETWORK, false);
    assert_eq!(inst.set_debug_logging(true, &["logCalls"]), Status::Ok);
    inst.take_messages();
    let calls = |messages: &[Message]| -> Vec<(Status, String)> {
        messages
            .iter()
            .filter(|m| m.category == Category::Calls)
            .map(|m| (m.status, m.text.clone()))
            .collect()
    };
    // A good step: one line.
    assert_eq!(inst.do_step(0.0, 0.1, false), Status::Ok);
    let messages = inst.take_messages();
    assert_eq!(messages.len(), 1);
    assert_eq!(
        calls(&messages),
        [(Status::Ok, "fmi2DoStep(t = 0, h = 0.1)".to_string())]
    );
    // A failed step: one call line with the final status, then the reason.
    assert_eq!(inst.do_step(0.1, 0.0, false), Status::Error);
    let messages = inst.take_messages();
    assert_eq!(
        calls(&messages),
        [(Status::Error, "fmi2DoStep(t = 0.1, h = 0)".to_string())]
    );
    assert_eq!(messages.len(), 2);
    assert_eq!(messages[0].category, Category::Calls);
    assert_eq!(messages[1].category, Category::Error);
    // A call refused in its phase: the same.
    assert_eq!(inst.do_step(0.1, 0.1, false), Status::Error);
    let messages = inst.take_messages();
    assert_eq!(
        calls(&messages),
        [(Status::Error, "fmi2DoStep(t = 0.1, h = 0.1)".to_string())]
    );
    assert!(refused(&messages));
    // A warning: the call line carries fmi2Discard.
    let mut saved = None;
    assert_eq!(inst.reset(), Status::Ok);
    assert_eq!(inst.get_fmu_state(&mut saved), Status::Ok);
    inst.take_messages();
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    inst.take_messages();
    assert_eq!(inst.get_status(fmi2DoStepStatus), Status::Discard);
    let messages = inst.take_messages();
    assert_eq!(
        calls(&messages),
        [(Status::Discard, "fmi2GetStatus".to_string())]
    );
    // Switching logCalls off is the last call logged.
    assert_eq!(inst.set_debug_logging(false, &[]), Status::Ok);
    assert_eq!(inst.do_step(0.0, 0.1, false), Status::Ok);
    assert!(inst.take_messages().is_empty());
}

#[test]
fn fmu_states_round_trip_through_bytes_into_another_instance() {
    let mut a = ready(SEED_NETWORK, false);
    let mut b = instance(SEED_NETWORK, false);
    assert_eq!(a.set_real(&[VELOCITY], &[0.4]), Status::Ok);
    assert_eq!(a.do_step(0.0, 0.3, false), Status::Ok);
    let mut saved = None;
    assert_eq!(a.get_fmu_state(&mut saved), Status::Ok);
    let saved = saved.unwrap();
    let mut size = 0;
    assert_eq!(a.serialized_fmu_state_size(&saved, &mut size), Status::Ok);
    let mut bytes = vec![0; size];
    assert_eq!(a.serialize_fmu_state(&saved, &mut bytes), Status::Ok);
    let mut restored = None;
    assert_eq!(b.deserialize_fmu_state(&bytes, &mut restored), Status::Ok);
    assert_eq!(b.set_fmu_state(restored.as_ref().unwrap()), Status::Ok);
    assert_eq!(b.phase(), Phase::StepComplete);
    for k in 0..20 {
        let t = 0.3 + k as f64 * 0.05;
        assert_eq!(a.do_step(t, 0.05, false), Status::Ok);
        assert_eq!(b.do_step(t, 0.05, false), Status::Ok);
        let (fa, fb) = (get(&mut a, &[FORCE])[0], get(&mut b, &[FORCE])[0]);
        assert_eq!(fa.to_bits(), fb.to_bits());
    }
    // Overwriting a saved state of this FMU works; a state of another FMU is refused.
    let mut reuse = restored;
    assert_eq!(b.get_fmu_state(&mut reuse), Status::Ok);
    let mut other = ready(TWO_DOF_NETWORK, false);
    assert_eq!(other.get_fmu_state(&mut reuse), Status::Error);
    assert_eq!(other.set_fmu_state(&saved), Status::Error);
    let mut foreign = None;
    assert_eq!(other.reset(), Status::Ok);
    assert_eq!(
        other.deserialize_fmu_state(&bytes, &mut foreign),
        Status::Error
    );
    assert!(foreign.is_none());
}

#[test]
fn instantiation_checks_name_type_and_location() {
    let cases: [(Option<&CStr>, fmi2Type, Option<&str>, &str); 5] = [
        (None, fmi2CoSimulation, Some("file:///x"), "instanceName"),
        (
            Some(c""),
            fmi2CoSimulation,
            Some("file:///x"),
            "instanceName",
        ),
        (
            Some(c"a"),
            fmi2ModelExchange,
            Some("file:///x"),
            "co-simulation only",
        ),
        (Some(c"a"), fmi2CoSimulation, None, "fmuResourceLocation"),
        (
            Some(c"a"),
            fmi2CoSimulation,
            Some("http://x/r"),
            "not a file: URI",
        ),
    ];
    for (name, kind, location, why) in cases {
        let error = Instance::instantiate(name, kind, Some("{guid}"), location, false)
            .err()
            .unwrap();
        assert!(error.to_string().contains(why), "{error}");
    }
    // The cause travels with the error.
    let error = Instance::instantiate(
        Some(c"a"),
        fmi2CoSimulation,
        None,
        Some("file://h/x"),
        false,
    )
    .err()
    .unwrap();
    assert!(
        matches!(error, InstantiateError::ResourceLocation(_)),
        "{error}"
    );
    assert!(std::error::Error::source(&error).is_some());
    let error = Instance::instantiate(Some(c"a"), fmi2ModelExchange, None, None, false)
        .err()
        .unwrap();
    assert!(
        matches!(error, InstantiateError::NotCoSimulation(_)),
        "{error}"
    );
}

#[test]
fn rho_and_g_reach_the_model_as_knowns_in_initialization_mode_and_after() {
    // The FMI layer passes rho and g to the model like any known: never refused by phase.
    for after_initialization in [false, true] {
        for known in [VR_RHO, VR_G] {
            let mut inst = instance(TWO_DOF_NETWORK, true);
            assert_eq!(inst.enter_initialization_mode(), Status::Ok);
            if after_initialization {
                assert_eq!(inst.exit_initialization_mode(), Status::Ok);
            }
            inst.take_messages();
            let mut d = [0.0];
            let status = inst.get_directional_derivative(&[FORCE], &[known], &[1.0], &mut d);
            let messages = inst.take_messages();
            assert!(!refused(&messages), "{messages:?}");
            if status != Status::Ok {
                // Only the model may decline (before it supports these partials).
                assert!(
                    messages
                        .iter()
                        .any(|m| m.text.contains("partial derivative")),
                    "{messages:?}"
                );
            }
        }
    }
}

#[test]
fn directional_derivatives_with_respect_to_rho_and_g_match_finite_differences() {
    // Two DOFs with A_inf in the force: velocities 100, 101; forces 102, 103; power 104;
    // energy 105; added_mass_inf 106..109; damping_direct 110..113; accelerations 114, 115.
    let base = FIRST_PER_HULL_REFERENCE;
    let unknowns: Vec<u32> = (base + 2..base + 14).collect();
    let mut inst = instance(TWO_DOF_NETWORK, true);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    let (rho, g) = (1000.0, 9.5);
    assert_eq!(inst.set_real(&[VR_RHO, VR_G], &[rho, g]), Status::Ok);
    let inputs = [base, base + 1, base + 14, base + 15];
    assert_eq!(inst.set_real(&inputs, &[0.3, -0.2, 0.5, 0.1]), Status::Ok);
    let mut in_initialization = Vec::new();
    for (known, x0) in [(VR_RHO, rho), (VR_G, g)] {
        let eps = 1e-6 * x0;
        assert_eq!(inst.set_real(&[known], &[x0 + eps]), Status::Ok);
        let plus = get(&mut inst, &unknowns);
        assert_eq!(inst.set_real(&[known], &[x0 - eps]), Status::Ok);
        let minus = get(&mut inst, &unknowns);
        assert_eq!(inst.set_real(&[known], &[x0]), Status::Ok);
        let values = get(&mut inst, &unknowns);
        let mut exact = vec![0.0; unknowns.len()];
        let status = inst.get_directional_derivative(&unknowns, &[known], &[1.0], &mut exact);
        assert_eq!(status, Status::Ok, "{:?}", inst.take_messages());
        for k in 0..unknowns.len() {
            let difference = (plus[k] - minus[k]) / (2.0 * eps);
            let scale = exact[k].abs() + values[k].abs() / x0 + 1e-12;
            assert!(
                (difference - exact[k]).abs() < 1e-6 * scale,
                "d vr {} / d vr {known}: {difference} vs {}",
                unknowns[k],
                exact[k]
            );
        }
        in_initialization.push(exact);
    }
    // After initialization the same knowns give the same derivatives (nothing moved).
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    for (known, expected) in [VR_RHO, VR_G].into_iter().zip(in_initialization) {
        let mut exact = vec![0.0; unknowns.len()];
        let status = inst.get_directional_derivative(&unknowns, &[known], &[1.0], &mut exact);
        assert_eq!(status, Status::Ok);
        assert_eq!(exact, expected);
    }
}

#[test]
fn wave_parameters_are_set_by_type_before_initialization_ends_and_refusals_change_nothing() {
    use crate::fmu::description::{
        VR_WAVE_COMPONENTS, VR_WAVE_HEADING, VR_WAVE_HEIGHT, VR_WAVE_KIND, VR_WAVE_SEED,
    };
    let initializing = || {
        let mut inst = instance(SEED_NETWORK, false);
        assert_eq!(inst.setup_experiment(None, 0.0, None), Status::Ok);
        assert_eq!(inst.enter_initialization_mode(), Status::Ok);
        inst
    };
    let mut inst = initializing();
    // Defaults as declared.
    let mut ints = [0; 3];
    assert_eq!(
        inst.get_integer(&[VR_WAVE_KIND, VR_WAVE_SEED, VR_WAVE_COMPONENTS], &mut ints),
        Status::Ok
    );
    assert_eq!(ints, [0, 1, 64]);
    assert_eq!(
        inst.set_integer(&[VR_WAVE_KIND, VR_WAVE_SEED], &[2, -7]),
        Status::Ok
    );
    assert_eq!(
        inst.set_real(&[VR_WAVE_HEIGHT, VR_WAVE_HEADING], &[3.0, 180.0]),
        Status::Ok
    );
    assert_eq!(
        get(&mut inst, &[VR_WAVE_HEIGHT, VR_WAVE_HEADING]),
        [3.0, 180.0]
    );
    // One bad value in a call: nothing of the call is applied (seed stays -7).
    assert_eq!(
        inst.set_integer(&[VR_WAVE_SEED, VR_WAVE_KIND], &[5, 9]),
        Status::Error
    );
    let messages = inst.take_messages();
    assert!(
        messages.iter().any(|m| m.text.contains("wave.kind")),
        "{messages:?}"
    );
    assert_eq!(inst.model.state().waves.seed, -7);
    // (Without an excitation table any finite heading is accepted; a table's FMU refuses
    // the headings it lacks, tests/python/test_ships.py.)
    let mut inst = initializing();
    assert_eq!(
        inst.set_real(&[VR_WAVE_HEIGHT, VR_WAVE_HEADING], &[2.5, f64::INFINITY]),
        Status::Error
    );
    assert_eq!(inst.model.state().waves.height, 1.0);
    let mut inst = initializing();
    // Types are checked: a Real parameter through the Integer call and the other way round.
    assert_eq!(inst.set_integer(&[VR_WAVE_HEIGHT], &[1]), Status::Error);
    let mut inst = initializing();
    assert_eq!(inst.set_real(&[VR_WAVE_KIND], &[1.0]), Status::Error);
    // Fixed: refused once initialization has ended.
    let mut inst = ready(SEED_NETWORK, false);
    assert_eq!(inst.set_integer(&[VR_WAVE_KIND], &[1]), Status::Error);
    let messages = inst.take_messages();
    assert!(
        messages.iter().any(|m| m.text.contains("fixed parameter")),
        "{messages:?}"
    );
}

#[test]
fn refused_state_bytes_leave_the_instance_and_the_target_state_as_they_were() {
    use crate::model::{tampered, StateField};
    let mut inst = ready(SEED_NETWORK, false);
    assert_eq!(inst.set_real(&[VELOCITY], &[0.4]), Status::Ok);
    assert_eq!(inst.do_step(0.0, 0.25, false), Status::Ok);
    assert_eq!(inst.do_step(0.25, 0.25, false), Status::Ok);
    let mut saved = None;
    assert_eq!(inst.get_fmu_state(&mut saved), Status::Ok);
    let mut size = 0;
    let snapshot = saved.clone().unwrap();
    assert_eq!(
        inst.serialized_fmu_state_size(&snapshot, &mut size),
        Status::Ok
    );
    let mut bytes = vec![0; size];
    assert_eq!(inst.serialize_fmu_state(&snapshot, &mut bytes), Status::Ok);
    let before = inst.model().state().clone();
    let reference = get(&mut inst, &[FORCE, POWER, ENERGY]);
    let cases = [
        (StateField::Steps, u64::MAX.to_le_bytes(), "steps"),
        (StateField::Steps, (1u64 << 53).to_le_bytes(), "steps"),
        (StateField::Time, f64::NAN.to_le_bytes(), "time is NaN"),
        // At rho = g = 1 the first spring is 0.2339: energy 1e611 J/m.
        (StateField::Network(0), 1e306f64.to_le_bytes(), "energy"),
    ];
    for (field, value, expected) in cases {
        let bad = tampered(inst.model(), &bytes, field, value);
        let mut target = saved.clone();
        inst.take_messages();
        assert_eq!(
            inst.deserialize_fmu_state(&bad, &mut target),
            Status::Error,
            "{field:?}"
        );
        let messages = inst.take_messages();
        assert!(
            messages.iter().any(|m| m.text.contains(expected)),
            "{field:?}: {messages:?}"
        );
        // The target still holds the saved state, and restores the instance from the error.
        assert_eq!(inst.set_fmu_state(target.as_ref().unwrap()), Status::Ok);
        assert_eq!(inst.phase(), Phase::StepComplete);
        assert_eq!(inst.model().state(), &before, "{field:?}");
        assert_eq!(get(&mut inst, &[FORCE, POWER, ENERGY]), reference);
    }
    // The untouched bytes still restore.
    let mut target = None;
    assert_eq!(inst.deserialize_fmu_state(&bytes, &mut target), Status::Ok);
}

#[test]
fn a_defined_stop_time_ends_the_run_until_reset() {
    let initialized = |inst: &mut Instance, stop: Option<f64>| {
        assert_eq!(inst.setup_experiment(None, 0.0, stop), Status::Ok);
        assert_eq!(inst.enter_initialization_mode(), Status::Ok);
        assert_eq!(inst.exit_initialization_mode(), Status::Ok);
        inst.take_messages();
    };
    let mut inst = instance(SEED_NETWORK, false);
    initialized(&mut inst, Some(1.0));
    assert_eq!(inst.set_real(&[VELOCITY], &[0.4]), Status::Ok);
    assert_eq!(inst.do_step(0.0, 0.5, false), Status::Ok);
    let mut saved = None;
    assert_eq!(inst.get_fmu_state(&mut saved), Status::Ok);
    let saved = saved.unwrap();
    let at_half = inst.model().state().clone();
    // A step past the stop time is an error (FMI 2.0, fmi2SetupExperiment); nothing moves.
    assert_eq!(inst.do_step(0.5, 1.0, false), Status::Error);
    let messages = inst.take_messages();
    assert!(
        messages.iter().any(|m| m.text.contains("stop time 1")),
        "{messages:?}"
    );
    assert_eq!(inst.model().state(), &at_half);
    // A step that ends at the stop time to rounding is fine (time tolerance 1e-10).
    assert_eq!(inst.set_fmu_state(&saved), Status::Ok);
    assert_eq!(inst.do_step(0.5, 0.5 + 5e-11, false), Status::Ok);
    let end = inst.model().time();
    assert_eq!(inst.do_step(end, 1e-3, false), Status::Error);
    // The stop time is part of the FMU state: restored with it, also in another instance.
    let mut other = instance(SEED_NETWORK, false);
    initialized(&mut other, None);
    assert_eq!(other.set_fmu_state(&saved), Status::Ok);
    assert_eq!(other.do_step(0.5, 0.6, false), Status::Error);
    // fmi2Reset forgets it: without a stop time any step is allowed.
    assert_eq!(inst.reset(), Status::Ok);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    assert_eq!(inst.do_step(0.0, 1.5, false), Status::Ok);
}

#[test]
fn no_value_leaves_with_ok_unless_it_is_finite() {
    // rho = g = 1e100 and a velocity of 1e100 m/s are each accepted (MAX_INPUT); the force
    // -c1 rho sqrt(g) v = -1e250 N/m is finite, the power F v is not.
    let mut inst = instance(SEED_NETWORK, false);
    assert_eq!(inst.set_real(&[VR_RHO, VR_G], &[1e100, 1e100]), Status::Ok);
    assert_eq!(inst.setup_experiment(None, 0.0, None), Status::Ok);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    assert_eq!(inst.set_real(&[VELOCITY], &[1e100]), Status::Ok);
    let mut saved = None;
    assert_eq!(inst.get_fmu_state(&mut saved), Status::Ok);
    let saved = saved.unwrap();
    inst.take_messages();
    let force = get(&mut inst, &[FORCE])[0];
    assert!(force.is_finite() && force < -1e249, "{force}");
    let mut out = [0.0; 2];
    assert_eq!(inst.get_real(&[FORCE, POWER], &mut out), Status::Error);
    let messages = inst.take_messages();
    assert!(
        messages.iter().any(|m| m.text.contains("power")),
        "{messages:?}"
    );
    // d power / dt and a directional derivative seeded with 1e300 overflow too.
    assert_eq!(inst.set_fmu_state(&saved), Status::Ok);
    let mut rate = [0.0];
    assert_eq!(
        inst.get_real_output_derivatives(&[POWER], &[1], &mut rate),
        Status::Error
    );
    assert_eq!(inst.set_fmu_state(&saved), Status::Ok);
    let mut d = [0.0];
    assert_eq!(
        inst.get_directional_derivative(&[FORCE], &[VELOCITY], &[1e300], &mut d),
        Status::Error
    );
    let messages = inst.take_messages();
    assert!(
        messages.iter().any(|m| m.text.contains("force.sway")),
        "{messages:?}"
    );
    // Once the input is moderate again, everything reads.
    assert_eq!(inst.set_fmu_state(&saved), Status::Ok);
    assert_eq!(inst.set_real(&[VELOCITY], &[1.0]), Status::Ok);
    assert!(get(&mut inst, &[FORCE, POWER, ENERGY])
        .iter()
        .all(|x| x.is_finite()));
}

/// The (output, known) value-reference pairs of a model description's `<ModelStructure>`
/// `<Outputs>`: FMI 2.0 (`Unknown` by 1-based index) or FMI 3.0 (`Output` by value
/// reference).
fn declared_dependencies(description: &str) -> Vec<(u32, Vec<u32>)> {
    let root = crate::xml::parse(description).unwrap();
    let references: Vec<u32> = root
        .descendants()
        .filter(|e| e.name == "ScalarVariable")
        .map(|e| e.attribute("valueReference").unwrap().parse().unwrap())
        .collect();
    let numbers = |text: &str| -> Vec<u32> {
        text.split_whitespace()
            .map(|d| d.parse().unwrap())
            .collect()
    };
    let mut declared = Vec::new();
    if let Some(outputs) = root.descendants().find(|e| e.name == "Outputs") {
        for unknown in &outputs.children {
            let index: usize = unknown.attribute("index").unwrap().parse().unwrap();
            let deps = numbers(unknown.attribute("dependencies").unwrap());
            let deps = deps.iter().map(|&d| references[d as usize - 1]).collect();
            declared.push((references[index - 1], deps));
        }
    }
    for output in root.descendants().filter(|e| e.name == "Output") {
        let vr = output.attribute("valueReference").unwrap().parse().unwrap();
        declared.push((vr, numbers(output.attribute("dependencies").unwrap())));
    }
    declared.sort();
    declared
}

#[test]
fn every_declared_dependency_has_the_finite_difference_as_its_derivative() {
    use crate::fmu::description::{DescriptionInfo, FIXED_XML, PARAMETERS};
    use crate::fmu::Causality;
    use crate::model::tests::{two_dof_substructure_network, TWO_DOF_EXCITATION};
    let vr_of = |name: &str| {
        PARAMETERS
            .iter()
            .find(|p| p.name == name)
            .unwrap()
            .value_reference
    };
    // In a regular wave (kR = omega^2 R / g = 0.5 at rho = g = 1, R = 2 m), A_inf kept.
    let resources = Resources::new(
        two_dof_substructure_network(),
        None,
        Resources::options_text(true),
    )
    .unwrap()
    .with_excitation(Some(TWO_DOF_EXCITATION.into()));
    let mut inst = Instance::from_resources(c"hull", &resources, false).unwrap();
    let period = 2.0 * std::f64::consts::PI / 0.5;
    let parameters = [VR_RHO, VR_G, vr_of("wave.height"), vr_of("wave.period")];
    assert_eq!(
        inst.set_real(&parameters, &[1.0, 1.0, 1.5, period]),
        Status::Ok
    );
    assert_eq!(inst.set_integer(&[vr_of("wave.kind")], &[1]), Status::Ok);
    assert_eq!(inst.setup_experiment(None, 0.0, None), Status::Ok);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    let variables = inst.layout.variables().to_vec();
    let inputs: Vec<u32> = variables
        .iter()
        .filter(|v| v.causality == Causality::Input)
        .map(|v| v.value_reference)
        .collect();
    assert_eq!(inputs.len(), 4);
    let values = [0.5, -0.2, 0.7, -0.3];
    assert_eq!(inst.set_real(&inputs, &values), Status::Ok);
    assert_eq!(inst.do_step(0.0, 0.7, true), Status::Ok);
    assert!(inst.model.state().network.amax() > 0.0);
    let info = DescriptionInfo {
        model_identifier: "Test".into(),
        guid: "{test}".into(),
        damping_direct: Some(inst.model.system().damping_direct().clone()),
        added_mass_inf: Some(inst.model.system().added_mass_inf().clone()),
        ..Default::default()
    };
    let fmi2 = declared_dependencies(&inst.layout.model_description(FIXED_XML, &info).unwrap());
    let fmi3 = declared_dependencies(
        &inst
            .layout
            .model_description_fmi3(FIXED_XML, &info)
            .unwrap(),
    );
    assert_eq!(
        fmi2, fmi3,
        "the two standards declare the same dependencies"
    );
    let outputs: Vec<u32> = fmi2.iter().map(|d| d.0).collect();
    // force, force_radiation, force_excitation (2 each), power, energy, wave.elevation.
    assert_eq!(outputs.len(), 9);
    let name = |vr: u32| {
        let variable = variables.iter().find(|v| v.value_reference == vr);
        variable.unwrap().name.clone()
    };
    let names: Vec<String> = outputs.iter().map(|&o| name(o)).collect();
    assert!(
        get(&mut inst, &outputs).iter().all(|x| *x != 0.0),
        "{names:?}"
    );
    let mut checked = 0;
    for (k, &input) in inputs.iter().enumerate() {
        let eps = 1e-6;
        assert_eq!(inst.set_real(&[input], &[values[k] + eps]), Status::Ok);
        let plus = get(&mut inst, &outputs);
        assert_eq!(inst.set_real(&[input], &[values[k] - eps]), Status::Ok);
        let minus = get(&mut inst, &outputs);
        assert_eq!(inst.set_real(&[input], &[values[k]]), Status::Ok);
        for (fmi3, (o, (output, deps))) in [false, true]
            .into_iter()
            .flat_map(|s| fmi2.iter().enumerate().map(move |x| (s, x)))
        {
            let mut exact = [f64::NAN];
            let status = if fmi3 {
                inst.get_directional_derivative_fmi3(&[*output], &[input], &[1.0], &mut exact)
            } else {
                inst.get_directional_derivative(&[*output], &[input], &[1.0], &mut exact)
            };
            let what = format!("d {} / d {} (FMI 3.0: {fmi3})", names[o], name(input));
            assert_eq!(status, Status::Ok, "{what}: {:?}", inst.take_messages());
            let difference = (plus[o] - minus[o]) / (2.0 * eps);
            if deps.contains(&input) {
                // Linear or quadratic in the input: exact to rounding (|value| 1e-16 / eps).
                let rounding = 1e-9 * plus[o].abs().max(minus[o].abs());
                assert!(
                    (difference - exact[0]).abs() < 1e-8 * (1.0 + exact[0].abs()) + rounding,
                    "{what}: {difference} vs {}",
                    exact[0]
                );
                assert!(exact[0] != 0.0, "{what} declared but zero");
                checked += 1;
            } else {
                // Not declared: no dependency at all.
                assert_eq!((difference, exact[0]), (0.0, 0.0), "{what}");
            }
        }
    }
    // force and force_radiation: 2 x 2 on velocities and accelerations each, power on all
    // four inputs, energy on the velocities; twice (both standards).
    assert_eq!(checked, 2 * (2 * 2 * 4 + 4 + 2));
}

#[test]
fn every_declared_parameter_limit_is_the_enforced_one() {
    use crate::fmu::description::PARAMETERS;
    // Each parameter at its declared bounds is accepted and just beyond refused; where none
    // is declared, an extreme finite value is accepted.
    let mut probes = 0;
    for p in PARAMETERS {
        let vr = p.value_reference;
        let set = |x: f64| {
            let mut inst = instance(SEED_NETWORK, false);
            let status = if p.integer {
                inst.set_integer(&[vr], &[x as i32])
            } else {
                inst.set_real(&[vr], &[x])
            };
            (status, inst.take_messages())
        };
        let (min, max) = (p.min, p.max);
        let inside = [
            if min.is_finite() { min } else { -1e300 },
            if max.is_finite() { max } else { 1e300 },
        ];
        for x in inside {
            let (status, log) = set(x);
            assert_eq!(status, Status::Ok, "{} = {x}: {log:?}", p.name);
            probes += 1;
        }
        let below = if p.integer {
            min - 1.0
        } else {
            min.next_down()
        };
        let above = if p.integer { max + 1.0 } else { max.next_up() };
        for x in [below, above] {
            let fits_i32 = (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&x);
            if !x.is_finite() || (p.integer && !fits_i32) {
                continue;
            }
            let (status, log) = set(x);
            assert_eq!(
                status,
                Status::Error,
                "{} = {x} is outside [{min}, {max}]",
                p.name
            );
            assert!(log[0].text.contains(p.name), "{log:?}");
            probes += 1;
        }
    }
    // rho, g, height, period, ramp, gamma, kind, components: both bounds (or one) probed.
    assert!(probes >= 2 * PARAMETERS.len() + 12, "{probes}");
}

mod direct_path;
