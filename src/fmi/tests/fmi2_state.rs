//! FMU states, reset, input derivatives, threads and a re-entrant logger through the FMI 2.0
//! C functions.
//!
//! Every `unsafe` block calls the exported functions with a component made by
//! [`instantiate`] and pointers to live locals with the entry counts passed.

use super::*;
use crate::model::tests::TWO_DOF_NETWORK;
/// Runs 200 steps with a varying input and returns every force bit pattern.
///
/// # Safety
/// `c` is a live component.
unsafe fn run(c: fmi2Component, start: f64) -> Vec<u64> {
    let mut out = Vec::new();
    let h = 0.05;
    for k in 0..200 {
        let t = start + k as f64 * h;
        // SAFETY: the caller's contract.
        unsafe {
            set(c, &[VELOCITY], &[(0.7 * t).sin()]);
            assert_eq!(fmi2DoStep(c, t, h, 0), fmi2OK);
            out.push(get(c, &[FORCE])[0].to_bits());
        }
    }
    out
}

#[test]
fn reset_gives_a_bitwise_identical_second_run() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log = Log::default();
    let f = callbacks(&log);
    let c = ready(&fmu, &f);
    // SAFETY: see the module docs.
    unsafe {
        let first = run(c, 0.0);
        assert_eq!(fmi2Reset(c), fmi2OK);
        set(c, &[VR_RHO, VR_G], &[1.0, 1.0]);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2OK);
        assert_eq!(run(c, 0.0), first);
        fmi2FreeInstance(c);
    }
}

#[test]
fn serialized_state_restores_in_another_instance() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log = Log::default();
    let f = callbacks(&log);
    let a = ready(&fmu, &f);
    let b = instantiate(&fmu, &fmu.uri(), &f, false);
    // SAFETY: see the module docs.
    unsafe {
        run(a, 0.0);
        let mut st: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(fmi2GetFMUstate(a, &mut st), fmi2OK);
        let mut size = 0;
        assert_eq!(fmi2SerializedFMUstateSize(a, st, &mut size), fmi2OK);
        let mut bytes = vec![0 as c_char; size];
        assert_eq!(
            fmi2SerializeFMUstate(a, st, bytes.as_mut_ptr(), size),
            fmi2OK
        );
        // Overwrite an existing snapshot in place (FMI allows reuse of *FMUstate).
        assert_eq!(fmi2GetFMUstate(a, &mut st), fmi2OK);
        // Another instance's state, a readable buffer that is not a state and an address
        // that is not mapped are refused without being read, and left as they are.
        let fake = [0u64; 8];
        let unmapped = 0x1000 as fmi2FMUstate;
        for foreign in [st, fake.as_ptr() as fmi2FMUstate, unmapped] {
            assert_eq!(fmi2SetFMUstate(b, foreign), fmi2Error);
            let mut held = foreign;
            assert_eq!(fmi2FreeFMUstate(b, &mut held), fmi2Error);
            assert_eq!(held, foreign);
            assert_eq!(fmi2Reset(b), fmi2OK);
        }
        assert_eq!(fmi2FreeFMUstate(a, &mut st), fmi2OK);

        let mut restored: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(
            fmi2DeSerializeFMUstate(b, bytes.as_ptr(), size, &mut restored),
            fmi2OK
        );
        assert_eq!(fmi2SetFMUstate(b, restored), fmi2OK);
        assert_eq!(phase(b), Phase::StepComplete);
        assert_eq!(run(a, 10.0), run(b, 10.0));
        assert_eq!(fmi2FreeFMUstate(b, &mut restored), fmi2OK);

        // A state of another FMU is refused.
        let other = Unpacked::new(TWO_DOF_NETWORK, false, "resources");
        let o = instantiate(&other, &other.uri(), &f, false);
        let mut foreign: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(
            fmi2DeSerializeFMUstate(o, bytes.as_ptr(), size, &mut foreign),
            fmi2Error
        );
        assert!(foreign.is_null());
        // A freed state is no longer this instance's: refused, its memory not read.
        assert_eq!(fmi2GetFMUstate(a, &mut st), fmi2OK);
        let stale = st;
        assert_eq!(fmi2FreeFMUstate(a, &mut st), fmi2OK);
        assert_eq!(fmi2SetFMUstate(a, stale), fmi2Error);
        fmi2FreeInstance(o);
        fmi2FreeInstance(a);
        fmi2FreeInstance(b);
    }
}

/// Saves `from`'s state, serializes it, deserializes the bytes into `to` and sets it there;
/// returns both states (to be freed by their instances).
///
/// # Safety
/// `from` and `to` are live components of the same FMU.
unsafe fn move_state(from: fmi2Component, to: fmi2Component) -> (fmi2FMUstate, fmi2FMUstate) {
    let mut saved: fmi2FMUstate = std::ptr::null_mut();
    let mut restored: fmi2FMUstate = std::ptr::null_mut();
    // SAFETY: live components (caller); pointers to locals and a buffer of `size` bytes.
    unsafe {
        assert_eq!(fmi2GetFMUstate(from, &mut saved), fmi2OK);
        let mut size = 0;
        assert_eq!(fmi2SerializedFMUstateSize(from, saved, &mut size), fmi2OK);
        let mut bytes = vec![0 as c_char; size];
        assert_eq!(
            fmi2SerializeFMUstate(from, saved, bytes.as_mut_ptr(), size),
            fmi2OK
        );
        assert_eq!(
            fmi2DeSerializeFMUstate(to, bytes.as_ptr(), size, &mut restored),
            fmi2OK
        );
        assert_eq!(fmi2SetFMUstate(to, restored), fmi2OK);
    }
    (saved, restored)
}

#[test]
fn a_state_saved_in_a_sea_brings_the_sea_into_an_instance_only_instantiated() {
    // As fmusim's --initial-fmu-state-file does: the state of an instance in a regular sea,
    // serialized, restored into an instance that was only instantiated. Its sea must be the
    // saved one (it was lost: exciting force and elevation 0 with fmi2OK).
    use crate::fmu::variables::{Layout, Quantity};
    use crate::fmu::DofUnit;
    use crate::model::tests::TWO_DOF_EXCITATION;
    let fmu = Unpacked::with_files(
        TWO_DOF_NETWORK,
        false,
        "resources",
        &[(Resources::EXCITATION_FILE, TWO_DOF_EXCITATION)],
    );
    let dofs = ["sway", "roll"].map(|n| DofUnit::new(n, 0, false)).to_vec();
    let layout = Layout::new(dofs, false).unwrap();
    let vr = |q| layout.value_reference(q).unwrap();
    let watched = [
        vr(Quantity::ForceExcitation(0)),
        vr(Quantity::ForceExcitation(1)),
        vr(Quantity::WaveElevation),
    ];
    let log = Log::default();
    let f = callbacks(&log);
    let a = instantiate(&fmu, &fmu.uri(), &f, false);
    let b = instantiate(&fmu, &fmu.uri(), &f, false);
    // SAFETY: see the module docs.
    unsafe {
        let kind = [1]; // regular
        let kind_vr = [vr(Quantity::Wave(
            crate::fmu::variables::WaveParameter::Kind,
        ))];
        assert_eq!(
            fmi2SetInteger(a, kind_vr.as_ptr(), 1, kind.as_ptr()),
            fmi2OK
        );
        set(
            a,
            &[
                VR_RHO,
                VR_G,
                vr(Quantity::Wave(crate::fmu::variables::WaveParameter::Period)),
            ],
            &[1000.0, 9.8, 4.0],
        );
        assert_eq!(fmi2SetupExperiment(a, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
        assert_eq!(fmi2EnterInitializationMode(a), fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(a), fmi2OK);
        for k in 0..7 {
            assert_eq!(fmi2DoStep(a, 0.1 * k as f64, 0.1, 1), fmi2OK);
        }
        let saved = get(a, &watched);
        assert!(saved.iter().all(|v| *v != 0.0), "{saved:?}");
        let (st, restored) = move_state(a, b);
        assert_eq!(get(b, &watched), saved);
        assert_eq!(fmi2DoStep(a, 0.7, 0.1, 1), fmi2OK);
        assert_eq!(fmi2DoStep(b, 0.7, 0.1, 1), fmi2OK);
        assert_eq!(get(b, &watched), get(a, &watched));
        // A state saved before initialization brings that phase back (the sea is built
        // again when its initialization ends).
        let c = instantiate(&fmu, &fmu.uri(), &f, false);
        let (early, back) = move_state(c, b);
        assert_eq!(phase(b), Phase::Instantiated);
        for (inst, mut state) in [(a, st), (b, restored), (b, back), (c, early)] {
            assert_eq!(fmi2FreeFMUstate(inst, &mut state), fmi2OK);
        }
        for inst in [a, b, c] {
            fmi2FreeInstance(inst);
        }
    }
}

#[test]
fn hostile_state_bytes_and_steps_past_the_stop_time_get_fmi2error() {
    use crate::model::{tampered, StateField};
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log = Log::default();
    let f = callbacks(&log);
    let c = instantiate(&fmu, &fmu.uri(), &f, false);
    assert!(!c.is_null());
    // SAFETY: see the module docs.
    unsafe {
        // stopTimeDefined = fmi2True, stopTime = 1: a step to 1.5 is an error.
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 1.0), fmi2OK);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2OK);
        assert_eq!(fmi2DoStep(c, 0.0, 0.5, 0), fmi2OK);
        let mut st: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(fmi2GetFMUstate(c, &mut st), fmi2OK);
        assert_eq!(fmi2DoStep(c, 0.5, 1.0, 0), fmi2Error);
        assert_eq!(phase(c), Phase::Error);
        assert_eq!(fmi2SetFMUstate(c, st), fmi2OK);
        let mut size = 0;
        assert_eq!(fmi2SerializedFMUstateSize(c, st, &mut size), fmi2OK);
        let mut bytes = vec![0u8; size];
        let out = bytes.as_mut_ptr() as *mut c_char;
        assert_eq!(fmi2SerializeFMUstate(c, st, out, size), fmi2OK);
        // A step counter of 2^64 - 1 with the checksum recomputed: refused, and the state
        // given to fill is kept.
        let model = (*(c as *const Component)).instance.model();
        let bad = tampered(model, &bytes, StateField::Steps, u64::MAX.to_le_bytes());
        let input = bad.as_ptr() as *const c_char;
        assert_eq!(fmi2DeSerializeFMUstate(c, input, size, &mut st), fmi2Error);
        assert!(!st.is_null());
        assert_eq!(fmi2SetFMUstate(c, st), fmi2OK);
        let mut time = 0.0;
        assert_eq!(
            fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &mut time),
            fmi2OK
        );
        assert_eq!(time, 0.5);
        assert_eq!(fmi2DoStep(c, 0.5, 0.5, 0), fmi2OK);
        assert_eq!(fmi2FreeFMUstate(c, &mut st), fmi2OK);
        fmi2FreeInstance(c);
    }
    let log = log.lock().unwrap();
    assert!(
        log.iter()
            .any(|(_, _, m)| m.contains("past the stop time 1")),
        "{log:?}"
    );
    assert!(log.iter().any(|(_, _, m)| m.contains("steps")), "{log:?}");
}

#[test]
fn input_derivatives_give_first_order_hold() {
    // A ramp via derivatives over one step equals the same ramp over ten steps.
    let fmu = Unpacked::new(TWO_DOF_NETWORK, true, "resources");
    let log = Log::default();
    let f = callbacks(&log);
    let vr_velocity = [FIRST_PER_HULL_REFERENCE, FIRST_PER_HULL_REFERENCE + 1];
    let force = [FIRST_PER_HULL_REFERENCE + 2, FIRST_PER_HULL_REFERENCE + 3];
    // SAFETY: see the module docs.
    let result = |steps: usize| unsafe {
        let c = ready(&fmu, &f);
        set(c, &vr_velocity, &[0.2, -0.1]);
        let order = [1, 1];
        let slope = [0.5, 0.3];
        assert_eq!(
            fmi2SetRealInputDerivatives(c, vr_velocity.as_ptr(), 2, order.as_ptr(), slope.as_ptr()),
            fmi2OK
        );
        let h = 1.0 / steps as f64;
        for k in 0..steps {
            assert_eq!(fmi2DoStep(c, k as f64 * h, h, 0), fmi2OK);
        }
        let r = get(c, &force);
        let v = get(c, &vr_velocity);
        fmi2FreeInstance(c);
        (r, v)
    };
    let (f1, v1) = result(1);
    let (f10, v10) = result(10);
    assert!((v1[0] - 0.7).abs() < 1e-15 && (v10[0] - 0.7).abs() < 1e-14);
    for k in 0..2 {
        assert!(
            (f1[k] - f10[k]).abs() < 1e-9 * f1[k].abs().max(1.0),
            "{f1:?} {f10:?}"
        );
    }
    // The acceleration input feeds -A_inf a straight through.
    // SAFETY: see the module docs.
    unsafe {
        let c = ready(&fmu, &f);
        let acceleration = [
            FIRST_PER_HULL_REFERENCE + 2 * 2 + 2 + 2 * 4,
            FIRST_PER_HULL_REFERENCE + 2 * 2 + 2 + 2 * 4 + 1,
        ];
        set(c, &acceleration, &[1.0, 0.0]);
        let r = get(c, &force);
        assert_eq!(r, vec![-0.2, -0.05]);
        let mut d = [0.0; 2];
        let seed = [1.0];
        assert_eq!(
            fmi2GetDirectionalDerivative(
                c,
                force.as_ptr(),
                2,
                acceleration.as_ptr(),
                1,
                seed.as_ptr(),
                d.as_mut_ptr()
            ),
            fmi2OK
        );
        assert_eq!(d, [-0.2, -0.05]);
        fmi2FreeInstance(c);
    }
}

#[test]
fn two_instances_in_two_threads_match_sequential_runs() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let sequential = {
        let log = Log::default();
        let f = callbacks(&log);
        let c = ready(&fmu, &f);
        // SAFETY: see the module docs.
        let r = unsafe { run(c, 0.0) };
        // SAFETY: see the module docs.
        unsafe { fmi2FreeInstance(c) };
        r
    };
    let results: Vec<Vec<u64>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..2)
            .map(|_| {
                s.spawn(|| {
                    let log = Log::default();
                    let f = callbacks(&log);
                    let c = ready(&fmu, &f);
                    // SAFETY: see the module docs.
                    let r = unsafe { run(c, 0.0) };
                    // SAFETY: see the module docs.
                    unsafe { fmi2FreeInstance(c) };
                    r
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert_eq!(results[0], sequential);
    assert_eq!(results[1], sequential);
}

/// A logger that reads the force of the instance it logs for.
struct Reentry {
    component: std::sync::atomic::AtomicPtr<c_void>,
    forces: Mutex<Vec<(fmi2Status, f64)>>,
}

unsafe extern "C" fn reentrant_logger(
    env: fmi2ComponentEnvironment,
    _name: fmi2String,
    _status: fmi2Status,
    _category: fmi2String,
    _message: fmi2String,
) {
    // SAFETY: `env` is the `Reentry` of the test, which outlives the instance.
    let reentry = unsafe { &*(env as *const Reentry) };
    let c = reentry.component.load(Ordering::SeqCst);
    let mut force = f64::NAN;
    // SAFETY: the live component of the test.
    let status = unsafe { fmi2GetReal(c, &FORCE, 1, &mut force) };
    reentry.forces.lock().unwrap().push((status, force));
}

#[test]
fn a_logger_may_call_back_into_the_instance() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let reentry = Reentry {
        component: std::sync::atomic::AtomicPtr::new(std::ptr::null_mut()),
        forces: Mutex::new(Vec::new()),
    };
    let log = Log::default();
    let mut f = callbacks(&log);
    f.logger = Some(as_fmi2_logger(reentrant_logger));
    f.componentEnvironment = &reentry as *const Reentry as *mut c_void;
    let c = ready(&fmu, &f);
    reentry.component.store(c, Ordering::SeqCst);
    // SAFETY: see the module docs.
    unsafe {
        set(c, &[VELOCITY], &[2.0]);
        // The error is logged after the call; the logger's own call reads the force
        // (readable in the error phase) and logs nothing itself.
        assert_eq!(fmi2DoStep(c, 0.0, -1.0, 0), fmi2Error);
        assert_eq!(*reentry.forces.lock().unwrap(), [(fmi2OK, -0.9962 * 2.0)]);
        fmi2FreeInstance(c);
    }
}
