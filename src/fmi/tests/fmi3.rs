//! The FMI 3.0 C functions exercised from Rust: the same numbers as the FMI 2.0 functions,
//! the arrays and `time`, and every function this FMU refuses.
//!
//! Every `unsafe` block calls the exported functions with an instance made by
//! [`instantiate3`] (or NULL or another standard's instance where the test says so) and
//! pointers to live locals with the entry counts passed.

use super::*;
use super::{callbacks, get, ready, set, Log, Unpacked};
use crate::fmi::phase::Phase;
use crate::fmu::description::{FIRST_PER_HULL_REFERENCE, VR_G, VR_RHO};
use crate::fmu::VR_TIME;
use crate::model::tests::SEED_NETWORK;
use std::ffi::c_void;
use std::sync::Mutex;

/// Log lines of an FMI 3.0 instance: (status, category, message).
type Log3 = Mutex<Vec<(i32, String, String)>>;

unsafe extern "C" fn logger3(
    env: fmi3InstanceEnvironment,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: `env` is the `Log3` given at instantiation, which outlives the instance.
    let log = unsafe { &*(env as *const Log3) };
    // SAFETY: the FMU passes NUL-terminated strings.
    let text = |p: fmi3String| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned();
    log.lock()
        .unwrap()
        .push((status, text(category), text(message)));
}

fn instantiate3(fmu: &Unpacked, token: &CStr, log: &Log3) -> fmi3Instance {
    instantiate3_logging(fmu, token, log, false)
}

fn instantiate3_logging(fmu: &Unpacked, token: &CStr, log: &Log3, on: bool) -> fmi3Instance {
    let path = CString::new(format!("{}/", fmu.dir.display())).unwrap();
    // SAFETY: NUL-terminated strings and a logger environment that outlives the instance.
    unsafe {
        fmi3InstantiateCoSimulation(
            c"hull3".as_ptr(),
            token.as_ptr(),
            path.as_ptr(),
            0,
            u8::from(on),
            0,
            0,
            std::ptr::null(),
            0,
            log as *const Log3 as *mut c_void,
            Some(logger3),
            std::ptr::null(),
        )
    }
}

/// Instantiated and initialized at rho = g = 1.
fn ready3(fmu: &Unpacked, log: &Log3) -> fmi3Instance {
    let c = instantiate3(fmu, &fmu.guid, log);
    assert!(!c.is_null(), "{:?}", log.lock().unwrap());
    // SAFETY: see the module docs.
    unsafe {
        set3(c, &[VR_RHO, VR_G], &[1.0, 1.0]);
        assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 0, 0.0), fmi3OK);
        assert_eq!(fmi3ExitInitializationMode(c), fmi3OK);
    }
    c
}

/// # Safety
/// `c` is a live FMI 3.0 instance.
unsafe fn set3(c: fmi3Instance, vr: &[u32], v: &[f64]) {
    // SAFETY: a live instance (caller) and arrays of the lengths passed.
    let status = unsafe { fmi3SetFloat64(c, vr.as_ptr(), vr.len(), v.as_ptr(), v.len()) };
    assert_eq!(status, fmi3OK);
}

/// # Safety
/// `c` is a live FMI 3.0 instance.
unsafe fn get3(c: fmi3Instance, vr: &[u32], n_values: usize) -> (fmi3Status, Vec<f64>) {
    let mut out = vec![f64::NAN; n_values];
    // SAFETY: a live instance (caller) and arrays of the lengths passed.
    let status = unsafe { fmi3GetFloat64(c, vr.as_ptr(), vr.len(), out.as_mut_ptr(), n_values) };
    (status, out)
}

/// # Safety
/// `c` is a live instance, not in use.
unsafe fn phase3(c: fmi3Instance) -> Phase {
    // SAFETY: the caller's contract; a shared reference for this read only.
    unsafe { &(*(c as *const Component)).instance }.phase()
}

const VELOCITY: u32 = FIRST_PER_HULL_REFERENCE;
const FORCE: u32 = FIRST_PER_HULL_REFERENCE + 1;
const POWER: u32 = FIRST_PER_HULL_REFERENCE + 2;

#[test]
fn version() {
    // SAFETY: a static NUL-terminated string.
    let v = unsafe { CStr::from_ptr(fmi3GetVersion()) };
    assert_eq!(v.to_str().unwrap(), "3.0");
}

#[test]
fn a_run_equals_the_fmi2_run_bit_for_bit() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let (log2, log3) = (Log::default(), Log3::default());
    let functions = callbacks(&log2);
    let c2 = ready(&fmu, &functions);
    let c3 = ready3(&fmu, &log3);
    // SAFETY: see the module docs.
    unsafe {
        let mut t: f64 = 0.0;
        for k in 0..400 {
            let v = (0.9 * t).sin() + 0.3 * (2.3 * t).cos();
            set(c2, &[VELOCITY], &[v]);
            set3(c3, &[VELOCITY], &[v]);
            assert_eq!(fmi2DoStep(c2, t, 0.01, 1), fmi2OK);
            let (mut event, mut stop, mut early, mut last) = (1u8, 1u8, 1u8, -1.0);
            let status = fmi3DoStep(c3, t, 0.01, 1, &mut event, &mut stop, &mut early, &mut last);
            assert_eq!(status, fmi3OK);
            assert_eq!((event, stop, early), (0, 0, 0));
            t = (k + 1) as f64 * 0.01;
            assert_eq!(last, t);
            let (status, f3) = get3(c3, &[FORCE, POWER, VR_TIME], 3);
            assert_eq!(status, fmi3OK);
            let f2 = get(c2, &[FORCE, POWER]);
            assert_eq!(f3[..2], f2[..], "step {k}");
            assert_eq!(f3[2], t);
        }
        // Directional and output derivatives as in FMI 2.0.
        let (seed, mut d) = (1.0, 0.0);
        let status = fmi3GetDirectionalDerivative(c3, &FORCE, 1, &VELOCITY, 1, &seed, 1, &mut d, 1);
        assert_eq!(status, fmi3OK);
        assert_eq!(d, -0.9962);
        let (order, mut d3, mut d2) = (1, 0.0, 0.0);
        assert_eq!(
            fmi3GetOutputDerivatives(c3, &FORCE, 1, &order, &mut d3, 1),
            fmi3OK
        );
        assert_eq!(
            fmi2GetRealOutputDerivatives(c2, &FORCE, 1, &order, &mut d2),
            fmi2OK
        );
        assert_eq!(d3, d2);
        assert_eq!(fmi3Terminate(c3), fmi3OK);
        fmi3FreeInstance(c3);
        fmi2FreeInstance(c2);
    }
    assert!(
        log3.lock().unwrap().is_empty(),
        "{:?}",
        log3.lock().unwrap()
    );
}

#[test]
fn matrices_are_arrays_and_their_inner_entries_are_not_variables() {
    let two = crate::model::tests::TWO_DOF_NETWORK;
    let fmu = Unpacked::new(two, true, "resources");
    let log3 = Log3::default();
    let log2 = Log::default();
    let c3 = ready3(&fmu, &log3);
    let c2 = ready(&fmu, &callbacks(&log2));
    let n = 2u32;
    let layout = crate::fmu::Layout::new(
        ["a", "b"]
            .iter()
            .map(|d| crate::fmu::DofUnit::new(d, 0, false))
            .collect(),
        true,
    )
    .unwrap();
    let first = |q| layout.value_reference(q).unwrap();
    let added = first(crate::fmu::Quantity::AddedMassInf(0, 0));
    let damping = first(crate::fmu::Quantity::DampingDirect(0, 0));
    // SAFETY: see the module docs.
    unsafe {
        let (status, values) = get3(c3, &[added, damping], (2 * n * n) as usize);
        assert_eq!(status, fmi3OK);
        let scalars: Vec<u32> = (0..n * n)
            .map(|k| added + k)
            .chain((0..n * n).map(|k| damping + k))
            .collect();
        assert_eq!(values, get(c2, &scalars));
        assert!(values.iter().any(|v| *v != 0.0));
        // Too few values for the array: refused, the instance goes to the error state.
        let (status, _) = get3(c3, &[added], 3);
        assert_eq!(status, fmi3Error);
        assert_eq!(phase3(c3), Phase::Error);
        assert_eq!(fmi3Reset(c3), fmi3OK);
        // An inner entry, time as an input, an array as an input: refused.
        for (vr, count) in [(added + 1, 1), (VR_TIME, 1), (added, 4)] {
            let v = vec![1.0; count];
            assert_eq!(
                fmi3SetFloat64(c3, &vr, 1, v.as_ptr(), count),
                fmi3Error,
                "{vr}"
            );
            assert_eq!(fmi3Reset(c3), fmi3OK);
        }
        let (status, _) = get3(c3, &[added + 1], 1);
        assert_eq!(status, fmi3Error);
        fmi3FreeInstance(c3);
        fmi2FreeInstance(c2);
    }
    let log = log3.lock().unwrap();
    assert!(
        log.iter()
            .any(|(_, _, m)| m.contains("unknown value reference")),
        "{log:?}"
    );
    assert!(
        log.iter()
            .any(|(_, _, m)| m.starts_with("fmi3SetFloat64: ")),
        "{log:?}"
    );
}

#[test]
fn standards_do_not_mix_and_bad_instantiations_give_null() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log3 = Log3::default();
    let log2 = Log::default();
    let c3 = ready3(&fmu, &log3);
    let c2 = ready(&fmu, &callbacks(&log2));
    // SAFETY: see the module docs; each call gets a live instance of the other standard,
    // which it must refuse without touching.
    unsafe {
        assert_eq!(fmi2DoStep(c3, 0.0, 0.1, 1), fmi2Error);
        let (mut a, mut b, mut e, mut t) = (0u8, 0u8, 0u8, 0.0);
        assert_eq!(
            fmi3DoStep(c2, 0.0, 0.1, 1, &mut a, &mut b, &mut e, &mut t),
            fmi3Error
        );
        assert_eq!(
            fmi3DoStep(
                std::ptr::null_mut(),
                0.0,
                0.1,
                1,
                &mut a,
                &mut b,
                &mut e,
                &mut t
            ),
            fmi3Error
        );
        fmi2FreeInstance(c3); // not an FMI 2.0 instance: ignored
        assert_eq!(phase3(c3), Phase::StepComplete);
        fmi3FreeInstance(c3);
        fmi2FreeInstance(c2);
    }
    let wrong = Log3::default();
    assert!(instantiate3(&fmu, c"{not-the-token}", &wrong).is_null());
    let lines = wrong.lock().unwrap();
    assert!(
        lines[0]
            .2
            .contains("instantiationToken {not-the-token} does not match"),
        "{lines:?}"
    );
    let refused = Log3::default();
    let env = &refused as *const Log3 as *mut c_void;
    // SAFETY: NUL-terminated strings and a logger environment that outlives the calls.
    unsafe {
        let me = fmi3InstantiateModelExchange(
            c"m".as_ptr(),
            fmu.guid.as_ptr(),
            c"/".as_ptr(),
            0,
            0,
            env,
            Some(logger3),
        );
        assert!(me.is_null());
        let null = std::ptr::null();
        let se = fmi3InstantiateScheduledExecution(
            c"s".as_ptr(),
            fmu.guid.as_ptr(),
            c"/".as_ptr(),
            0,
            0,
            env,
            Some(logger3),
            null,
            null,
            null,
        );
        assert!(se.is_null());
    }
    let lines = refused.lock().unwrap();
    assert_eq!(lines.len(), 2);
    assert!(lines[0].2.contains("co-simulation only"), "{lines:?}");
}

#[test]
fn functions_of_undeclared_features_refuse_and_leave_the_state() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log3 = Log3::default();
    let c = ready3(&fmu, &log3);
    let vr = VELOCITY;
    let mut x = 0.0;
    let mut n = 0usize;
    let mut b = 0u8;
    // SAFETY: see the module docs; refused calls read none of their pointers.
    unsafe {
        let null = std::ptr::null_mut();
        let refused = [
            fmi3EnterEventMode(c),
            fmi3EnterStepMode(c),
            fmi3EnterConfigurationMode(c),
            fmi3ExitConfigurationMode(c),
            fmi3EvaluateDiscreteStates(c),
            fmi3UpdateDiscreteStates(c, &mut b, &mut b, &mut b, &mut b, &mut b, &mut x),
            fmi3EnterContinuousTimeMode(c),
            fmi3SetTime(c, 1.0),
            fmi3GetNumberOfContinuousStates(c, &mut n),
            fmi3GetClock(c, &vr, 1, &mut b),
            fmi3GetIntervalDecimal(c, &vr, 1, &mut x, null),
            fmi3ActivateModelPartition(c, vr, 0.0),
            fmi3GetAdjointDerivative(c, &FORCE, 1, &VELOCITY, 1, &x, 1, &mut x, 1),
            fmi3GetNumberOfVariableDependencies(c, FORCE, &mut n),
        ];
        assert!(refused.iter().all(|s| *s == fmi3Error), "{refused:?}");
        assert_eq!(phase3(c), Phase::StepComplete);
        // Types without variables: an empty list succeeds, a reference does not.
        let mut i8v = 0i8;
        assert_eq!(fmi3GetInt8(c, std::ptr::null(), 0, &mut i8v, 0), fmi3OK);
        assert_eq!(fmi3GetInt8(c, &vr, 1, &mut i8v, 1), fmi3Error);
        assert_eq!(fmi3Reset(c), fmi3OK);
        // Int32: the wave parameters, as FMI 2.0's Integers.
        let kind = crate::fmu::description::VR_WAVE_KIND;
        let k = 2;
        assert_eq!(fmi3SetInt32(c, &kind, 1, &k, 1), fmi3OK);
        assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 0, 0.0), fmi3OK);
        let mut k = -1;
        assert_eq!(fmi3GetInt32(c, &kind, 1, &mut k, 1), fmi3OK);
        assert_eq!(k, 2);
        fmi3FreeInstance(c);
    }
    let log = log3.lock().unwrap();
    assert!(log.iter().any(|(_, _, m)| m == "fmi3EnterEventMode: this FMU has no event mode (hasEventMode = false) (call refused)"), "{log:?}");
    assert!(
        log.iter()
            .any(|(_, _, m)| m.contains("fmi3GetInt8: this FMU has no Int8 variables")),
        "{log:?}"
    );
}

#[test]
fn state_round_trips_through_bytes_and_a_bad_step_moves_nothing() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log3 = Log3::default();
    let c = ready3(&fmu, &log3);
    let (mut a, mut b, mut e, mut t) = (0u8, 0u8, 0u8, 0.0);
    // SAFETY: see the module docs.
    unsafe {
        set3(c, &[VELOCITY], &[1.5]);
        assert_eq!(
            fmi3DoStep(c, 0.0, 0.1, 1, &mut a, &mut b, &mut e, &mut t),
            fmi3OK
        );
        let mut state: fmi3FMUState = std::ptr::null_mut();
        assert_eq!(fmi3GetFMUState(c, &mut state), fmi3OK);
        let mut size = 0;
        assert_eq!(fmi3SerializedFMUStateSize(c, state, &mut size), fmi3OK);
        let mut bytes = vec![0u8; size];
        assert_eq!(
            fmi3SerializeFMUState(c, state, bytes.as_mut_ptr(), size),
            fmi3OK
        );
        assert_eq!(
            fmi3DoStep(c, 0.1, 0.1, 1, &mut a, &mut b, &mut e, &mut t),
            fmi3OK
        );
        let after = get3(c, &[FORCE], 1).1;
        let mut restored: fmi3FMUState = std::ptr::null_mut();
        assert_eq!(
            fmi3DeserializeFMUState(c, bytes.as_ptr(), size, &mut restored),
            fmi3OK
        );
        assert_eq!(fmi3SetFMUState(c, restored), fmi3OK);
        assert_eq!(get3(c, &[VR_TIME], 1).1, [0.1]);
        assert_eq!(
            fmi3DoStep(c, 0.1, 0.1, 1, &mut a, &mut b, &mut e, &mut t),
            fmi3OK
        );
        assert_eq!(get3(c, &[FORCE], 1).1, after);
        // A NULL output pointer of fmi3DoStep: refused before the step.
        let status = fmi3DoStep(c, 0.2, 0.1, 1, std::ptr::null_mut(), &mut b, &mut e, &mut t);
        assert_eq!(status, fmi3Error);
        assert_eq!(get3(c, &[VR_TIME], 1).1, [0.2]);
        // NaN input: refused, nothing set.
        let nan = f64::NAN;
        assert_eq!(reset_and_set_velocity(c, nan), fmi3Error);
        assert_eq!(fmi3FreeFMUState(c, &mut state), fmi3OK);
        assert!(state.is_null());
        assert_eq!(fmi3FreeFMUState(c, &mut restored), fmi3OK);
        fmi3FreeInstance(c);
    }
    let log = log3.lock().unwrap();
    assert!(
        log.iter()
            .any(|(_, _, m)| m.contains("eventHandlingNeeded")),
        "{log:?}"
    );
}

/// fmi3SetFloat64 of one velocity after a reset (a bad call left the error state).
///
/// # Safety
/// `c` is a live FMI 3.0 instance.
unsafe fn reset_and_set_velocity(c: fmi3Instance, v: f64) -> fmi3Status {
    // SAFETY: the caller's contract.
    unsafe {
        assert_eq!(fmi3Reset(c), fmi3OK);
        fmi3SetFloat64(c, &VELOCITY, 1, &v, 1)
    }
}

#[test]
fn initialization_is_one_call_with_its_start_and_stop_time() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log3 = Log3::default();
    let c = instantiate3_logging(&fmu, &fmu.guid, &log3, true);
    assert!(!c.is_null());
    let (mut a, mut b, mut e, mut t) = (0u8, 0u8, 0u8, 0.0);
    // SAFETY: see the module docs.
    unsafe {
        // A stop time before the start: refused by name, then recovered by reset.
        assert_eq!(
            fmi3EnterInitializationMode(c, 0, 0.0, 1.0, 1, 0.5),
            fmi3Error
        );
        assert_eq!(phase3(c), Phase::Error);
        assert_eq!(fmi3Reset(c), fmi3OK);
        let refused = log3.lock().unwrap().drain(..).any(|(_, _, m)| {
            m == "fmi3EnterInitializationMode: stopTime 0.5 is before startTime 1"
        });
        assert!(refused);
        assert_eq!(fmi3EnterInitializationMode(c, 1, 1e-6, 2.0, 1, 2.3), fmi3OK);
        assert_eq!(fmi3ExitInitializationMode(c), fmi3OK);
        assert_eq!(
            fmi3DoStep(c, 2.0, 0.2, 1, &mut a, &mut b, &mut e, &mut t),
            fmi3OK
        );
        assert_eq!(t, 2.2);
        // Past the stop time given at initialization: refused, time unchanged.
        assert_eq!(
            fmi3DoStep(c, 2.2, 0.2, 1, &mut a, &mut b, &mut e, &mut t),
            fmi3Error
        );
        assert_eq!(t, 2.2);
        fmi3FreeInstance(c);
    }
    let log = log3.lock().unwrap();
    let calls: Vec<&str> = log
        .iter()
        .filter(|(_, c, _)| c == "logCalls")
        .map(|(_, _, m)| m.as_str())
        .collect();
    // One line per call, named as in FMI 3.0.
    assert_eq!(calls[0], "fmi3EnterInitializationMode");
    assert_eq!(calls[1], "fmi3ExitInitializationMode");
    assert!(calls[2].starts_with("fmi3DoStep(t = 2"), "{calls:?}");
    assert_eq!(calls.len(), 4, "{calls:?}");
    assert!(
        log.iter().any(|(_, _, m)| m.contains("past the stop time")),
        "{log:?}"
    );
}

/// Calls each of the 26 typed getters or setters with one value reference; returns (name,
/// status) in the standard's order.
///
/// # Safety
/// `c` is a live FMI 3.0 instance.
unsafe fn typed_calls(c: fmi3Instance, getters: bool) -> Vec<(&'static str, fmi3Status)> {
    let vr = VELOCITY;
    let (mut f64v, mut f32v, mut i8v, mut u8v, mut i16v, mut u16v) =
        (0.0, 0f32, 0i8, 0u8, 0i16, 0u16);
    let (mut i32v, mut u32v, mut i64v, mut u64v, mut b) = (0i32, 0u32, 0i64, 0u64, 0u8);
    let mut s: fmi3String = std::ptr::null();
    let mut size = 0usize;
    let mut bytes: *const fmi3Byte = std::ptr::null();
    // SAFETY: the caller's contract; one value each, in live locals.
    unsafe {
        if getters {
            vec![
                ("fmi3GetFloat32", fmi3GetFloat32(c, &vr, 1, &mut f32v, 1)),
                ("fmi3GetFloat64", fmi3GetFloat64(c, &vr, 1, &mut f64v, 1)),
                ("fmi3GetInt8", fmi3GetInt8(c, &vr, 1, &mut i8v, 1)),
                ("fmi3GetUInt8", fmi3GetUInt8(c, &vr, 1, &mut u8v, 1)),
                ("fmi3GetInt16", fmi3GetInt16(c, &vr, 1, &mut i16v, 1)),
                ("fmi3GetUInt16", fmi3GetUInt16(c, &vr, 1, &mut u16v, 1)),
                ("fmi3GetInt32", fmi3GetInt32(c, &vr, 1, &mut i32v, 1)),
                ("fmi3GetUInt32", fmi3GetUInt32(c, &vr, 1, &mut u32v, 1)),
                ("fmi3GetInt64", fmi3GetInt64(c, &vr, 1, &mut i64v, 1)),
                ("fmi3GetUInt64", fmi3GetUInt64(c, &vr, 1, &mut u64v, 1)),
                ("fmi3GetBoolean", fmi3GetBoolean(c, &vr, 1, &mut b, 1)),
                ("fmi3GetString", fmi3GetString(c, &vr, 1, &mut s, 1)),
                (
                    "fmi3GetBinary",
                    fmi3GetBinary(c, &vr, 1, &mut size, &mut bytes, 1),
                ),
            ]
        } else {
            vec![
                ("fmi3SetFloat32", fmi3SetFloat32(c, &vr, 1, &f32v, 1)),
                ("fmi3SetFloat64", fmi3SetFloat64(c, &vr, 1, &f64v, 1)),
                ("fmi3SetInt8", fmi3SetInt8(c, &vr, 1, &i8v, 1)),
                ("fmi3SetUInt8", fmi3SetUInt8(c, &vr, 1, &u8v, 1)),
                ("fmi3SetInt16", fmi3SetInt16(c, &vr, 1, &i16v, 1)),
                ("fmi3SetUInt16", fmi3SetUInt16(c, &vr, 1, &u16v, 1)),
                ("fmi3SetInt32", fmi3SetInt32(c, &vr, 1, &i32v, 1)),
                ("fmi3SetUInt32", fmi3SetUInt32(c, &vr, 1, &u32v, 1)),
                ("fmi3SetInt64", fmi3SetInt64(c, &vr, 1, &i64v, 1)),
                ("fmi3SetUInt64", fmi3SetUInt64(c, &vr, 1, &u64v, 1)),
                ("fmi3SetBoolean", fmi3SetBoolean(c, &vr, 1, &b, 1)),
                ("fmi3SetString", fmi3SetString(c, &vr, 1, &s, 1)),
                ("fmi3SetBinary", fmi3SetBinary(c, &vr, 1, &size, &bytes, 1)),
            ]
        }
    }
}

#[test]
fn every_refused_typed_getter_and_setter_logs_its_own_name() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log3 = Log3::default();
    // Getters are refused before initialization, setters after termination.
    let instantiated = instantiate3(&fmu, &fmu.guid, &log3);
    let terminated = ready3(&fmu, &log3);
    // SAFETY: see the module docs.
    let calls = unsafe {
        assert_eq!(fmi3Terminate(terminated), fmi3OK);
        log3.lock().unwrap().clear();
        let mut calls = typed_calls(instantiated, true);
        calls.extend(typed_calls(terminated, false));
        assert_eq!(phase3(instantiated), Phase::Instantiated);
        assert_eq!(phase3(terminated), Phase::Terminated);
        fmi3FreeInstance(instantiated);
        fmi3FreeInstance(terminated);
        calls
    };
    assert_eq!(calls.len(), 26);
    let log = log3.lock().unwrap();
    assert_eq!(log.len(), 26, "{log:#?}");
    for ((name, status), (level, category, message)) in calls.iter().zip(log.iter()) {
        assert_eq!(*status, fmi3Error, "{name}");
        let phase = if name.starts_with("fmi3Get") {
            "Instantiated"
        } else {
            "Terminated"
        };
        let expected = format!("{name}: not allowed in phase {phase} (call refused)");
        assert_eq!(
            (*level, category.as_str(), message.as_str()),
            (fmi3Error, "logStatusError", expected.as_str())
        );
    }
}

#[test]
fn event_mode_is_refused_at_instantiation() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let path = CString::new(format!("{}/", fmu.dir.display())).unwrap();
    let log3 = Log3::default();
    let instantiate = |event_mode_used: u8| {
        // SAFETY: NUL-terminated strings and a logger environment that outlives the instance.
        unsafe {
            fmi3InstantiateCoSimulation(
                c"hull3".as_ptr(),
                fmu.guid.as_ptr(),
                path.as_ptr(),
                0,
                0,
                event_mode_used,
                0,
                std::ptr::null(),
                0,
                &log3 as *const Log3 as *mut c_void,
                Some(logger3),
                std::ptr::null(),
            )
        }
    };
    assert!(instantiate(1).is_null());
    {
        let log = log3.lock().unwrap();
        assert_eq!(log.len(), 1, "{log:?}");
        assert_eq!(log[0].0, fmi3Error);
        assert_eq!(
            log[0].2,
            "fmi3InstantiateCoSimulation: eventModeUsed = true: this FMU has no event mode \
             (hasEventMode = false)"
        );
    }
    let c = instantiate(0);
    assert!(!c.is_null());
    // SAFETY: a live instance.
    unsafe { fmi3FreeInstance(c) };
}

#[test]
fn an_int32_variable_is_no_float64_and_an_integer_no_real() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log3 = Log3::default();
    let log2 = Log::default();
    let c3 = ready3(&fmu, &log3);
    let c2 = ready(&fmu, &callbacks(&log2));
    let kind = crate::fmu::description::VR_WAVE_KIND;
    // SAFETY: see the module docs.
    unsafe {
        let (status, _) = get3(c3, &[kind], 1);
        assert_eq!(status, fmi3Error);
        let mut x = f64::NAN;
        assert_eq!(fmi2GetReal(c2, &kind, 1, &mut x), fmi2Error);
        // Its own getter reads it.
        assert_eq!(fmi3Reset(c3), fmi3OK);
        assert_eq!(fmi3EnterInitializationMode(c3, 0, 0.0, 0.0, 0, 0.0), fmi3OK);
        let mut k = -1;
        assert_eq!(fmi3GetInt32(c3, &kind, 1, &mut k, 1), fmi3OK);
        assert_eq!(k, 0);
        fmi3FreeInstance(c3);
        fmi2FreeInstance(c2);
    }
    let log = log3.lock().unwrap();
    assert_eq!(
        log[0].2,
        "fmi3GetFloat64: wave.kind is an Integer variable: read it with fmi3GetInt32"
    );
    let log = log2.lock().unwrap();
    assert_eq!(
        log[0].2,
        "fmi2GetReal: wave.kind is an Integer variable: read it with fmi2GetInteger"
    );
}

#[test]
fn the_fmi3_description_and_log_name_fmi3_functions() {
    use crate::fmu::description::{DescriptionInfo, FIXED_XML, LOG_CATEGORIES};
    let layout =
        crate::fmu::Layout::new(vec![crate::fmu::DofUnit::builtin("sway").unwrap()], false)
            .unwrap();
    let info = DescriptionInfo {
        model_identifier: "Test3".into(),
        guid: "{token}".into(),
        ..Default::default()
    };
    let xml = layout.model_description_fmi3(FIXED_XML, &info).unwrap();
    let root = crate::xml::parse(&xml).unwrap();
    let categories: Vec<(&str, &str)> = root
        .descendants()
        .filter(|e| e.name == "Category")
        .map(|e| {
            let get = |k| e.attribute(k).unwrap();
            (get("name"), get("description"))
        })
        .collect();
    assert_eq!(categories.len(), LOG_CATEGORIES.len());
    let text: String = categories.iter().map(|c| c.1).collect();
    assert!(!text.contains("fmi2"), "{categories:#?}");
    assert!(
        text.contains("fmi3Reset or fmi3SetFMUState recover"),
        "{text}"
    );
    assert!(text.contains("every fmi3 call"), "{text}");
    // The log of an FMI 3.0 instance: refusals that name other functions name FMI 3.0 ones.
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log3 = Log3::default();
    let c = instantiate3_logging(&fmu, &fmu.guid, &log3, true);
    let kind = crate::fmu::description::VR_WAVE_KIND;
    // SAFETY: see the module docs; the state pointer is one the instance never issued
    // (refused unread).
    unsafe {
        assert_eq!(fmi3SetFloat64(c, &kind, 1, &1.0, 1), fmi3Error);
        assert_eq!(fmi3Reset(c), fmi3OK);
        let foreign = 8usize as fmi3FMUState;
        assert_eq!(fmi3SetFMUState(c, foreign), fmi3Error);
        fmi3FreeInstance(c);
    }
    let log = log3.lock().unwrap();
    assert!(log.len() >= 4, "{log:#?}");
    for (_, _, message) in log.iter() {
        assert!(!message.contains("fmi2"), "{message}");
    }
    assert!(
        log.iter().any(|l| l.2.contains("set it with fmi3SetInt32")),
        "{log:#?}"
    );
    assert!(
        log.iter()
            .any(|l| l.2.contains("fmi3GetFMUState or fmi3DeserializeFMUState")),
        "{log:#?}"
    );
}

#[test]
fn a_call_of_the_other_standard_is_refused_with_a_line_naming_both() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let (log2, log3) = (Log::default(), Log3::default());
    let c3 = ready3(&fmu, &log3);
    let c2 = ready(&fmu, &callbacks(&log2));
    log3.lock().unwrap().clear();
    // SAFETY: see the module docs; each call gets a live instance of the other standard,
    // which it must refuse without reading its other arguments.
    unsafe {
        assert_eq!(fmi2DoStep(c3, 0.0, 0.1, 1), fmi2Error);
        let mut x = 0.0;
        assert_eq!(fmi2GetReal(c3, &FORCE, 1, &mut x), fmi2Error);
        fmi2FreeInstance(c3);
        let (mut a, mut b, mut e, mut t) = (0u8, 0u8, 0u8, 0.0);
        let status = fmi3DoStep(c2, 0.0, 0.1, 1, &mut a, &mut b, &mut e, &mut t);
        assert_eq!(status, fmi3Error);
        assert_eq!(fmi3EnterEventMode(c2), fmi3Error);
        let mut f = 0f32;
        assert_eq!(fmi3GetFloat32(c2, &FORCE, 1, &mut f, 1), fmi3Error);
        fmi3FreeInstance(c2);
        assert_eq!(phase3(c3), Phase::StepComplete);
        assert_eq!(
            (*(c2 as *const Component)).instance.phase(),
            Phase::StepComplete
        );
        fmi3FreeInstance(c3);
        fmi2FreeInstance(c2);
    }
    let made_by_3 = "this instance was made by fmi3InstantiateCoSimulation (FMI 3.0)";
    let made_by_2 = "this instance was made by fmi2Instantiate (FMI 2.0)";
    let lines3: Vec<String> = log3.lock().unwrap().iter().map(|l| l.2.clone()).collect();
    assert_eq!(
        lines3,
        [
            format!("fmi2DoStep: {made_by_3}: call fmi3DoStep instead (call refused)"),
            format!("fmi2GetReal: {made_by_3}: call fmi3GetFloat64 instead (call refused)"),
            format!("fmi2FreeInstance: {made_by_3}: call fmi3FreeInstance instead (call refused)"),
        ]
    );
    let lines2: Vec<String> = log2.lock().unwrap().iter().map(|l| l.2.clone()).collect();
    assert_eq!(
        lines2,
        [
            format!("fmi3DoStep: {made_by_2}: call fmi2DoStep instead (call refused)"),
            format!(
                "fmi3EnterEventMode: {made_by_2}: its standard has no such function (call refused)"
            ),
            format!(
                "fmi3GetFloat32: {made_by_2}: its standard has no such function (call refused)"
            ),
            format!("fmi3FreeInstance: {made_by_2}: call fmi2FreeInstance instead (call refused)"),
        ]
    );
}

#[test]
fn wave_drift_is_an_int32_and_force_drift_a_float64_of_an_fmu_with_a_drift_table() {
    use crate::fmu::variables::{Quantity, WaveParameter};
    use crate::model::drift_tests::TWO_DOF_DRIFT;
    use crate::model::tests::{TWO_DOF_EXCITATION, TWO_DOF_NETWORK};
    let fmu = Unpacked::with_files(
        TWO_DOF_NETWORK,
        false,
        "resources",
        &[
            (Resources::EXCITATION_FILE, TWO_DOF_EXCITATION),
            (Resources::DRIFT_FILE, TWO_DOF_DRIFT),
        ],
    );
    let layout = crate::fmu::Layout::new(
        ["sway", "roll"]
            .iter()
            .map(|d| crate::fmu::DofUnit::new(d, 0, false))
            .collect(),
        false,
    )
    .unwrap()
    .with_drift()
    .unwrap();
    let vr = |q| layout.value_reference(q).unwrap();
    let drift = vr(Quantity::Wave(WaveParameter::Drift));
    let parts = [
        vr(Quantity::ForceRadiation(0)),
        vr(Quantity::ForceExcitation(0)),
        vr(Quantity::ForceDrift(0)),
        vr(Quantity::Force(0)),
    ];
    // A regular wave at kR = 0.5 (rho = g = 1, R = 2 m): the table's sway drift 0.3 kR.
    let (height, omega) = (1.5, 0.5);
    let log3 = Log3::default();
    let c = instantiate3(&fmu, &fmu.guid, &log3);
    assert!(!c.is_null(), "{:?}", log3.lock().unwrap());
    // SAFETY: see the module docs.
    unsafe {
        set3(c, &[VR_RHO, VR_G], &[1.0, 1.0]);
        let kind = crate::fmu::description::VR_WAVE_KIND;
        assert_eq!(fmi3SetInt32(c, &kind, 1, &1, 1), fmi3OK);
        let wave = [
            crate::fmu::description::VR_WAVE_HEIGHT,
            crate::fmu::description::VR_WAVE_PERIOD,
        ];
        set3(c, &wave, &[height, 2.0 * std::f64::consts::PI / omega]);
        assert_eq!(fmi3SetInt32(c, &drift, 1, &1, 1), fmi3OK);
        assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 0, 0.0), fmi3OK);
        assert_eq!(fmi3ExitInitializationMode(c), fmi3OK);
        let mut code = -1;
        assert_eq!(fmi3GetInt32(c, &drift, 1, &mut code, 1), fmi3OK);
        assert_eq!(code, 1);
        let (status, values) = get3(c, &parts, 4);
        assert_eq!(status, fmi3OK);
        let expected = 0.75 * 0.75 * 0.3 * 0.5;
        assert!(
            (values[2] - expected).abs() <= 1e-12 * expected,
            "{values:?}"
        );
        assert_eq!(values[3], values[0] + values[1] + values[2]);
        fmi3FreeInstance(c);
    }
    assert!(
        log3.lock().unwrap().is_empty(),
        "{:?}",
        log3.lock().unwrap()
    );
}
