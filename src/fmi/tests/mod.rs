//! The C ABI exercised from Rust, with a Rust logger, including every bad call.
//!
//! Every `unsafe` block below calls the exported functions with a component made by
//! [`instantiate`] (or NULL or foreign memory where the test says so) and pointers to live
//! locals with the entry counts passed.

use super::ffi::*;
use super::phase::Phase;
use super::types::*;
use super::uri::resource_path;
use super::*;
use crate::fmu::description::{FIRST_PER_HULL_REFERENCE, LOG_CATEGORIES, VR_G, VR_RHO};
use crate::model::tests::{SEED_NETWORK, TWO_DOF_NETWORK};
use crate::model::Resources;
use std::ffi::{c_char, CStr, CString};
use std::ffi::{c_int, c_void};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Log lines: (status, category, message as received, i.e. with `%%`).
pub(super) type Log = Mutex<Vec<(i32, String, String)>>;

unsafe extern "C" fn rust_logger(
    env: fmi2ComponentEnvironment,
    _name: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    message: fmi2String,
) {
    // SAFETY: `env` is the `Log` given in `callbacks`, which outlives the instance.
    let log = unsafe { &*(env as *const Log) };
    // SAFETY: the FMU passes NUL-terminated strings.
    let text = |p: fmi2String| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned();
    log.lock()
        .unwrap()
        .push((status, text(category), text(message)));
}

/// A non-variadic test logger as the variadic `fmi2CallbackLogger`.
pub(super) fn as_fmi2_logger(
    logger: unsafe extern "C" fn(
        fmi2ComponentEnvironment,
        fmi2String,
        fmi2Status,
        fmi2String,
        fmi2String,
    ),
) -> fmi2CallbackLogger {
    // SAFETY: test only: on x86-64 System V a non-variadic callee ignores the vector
    // register count a variadic call passes; we never pass variadic arguments.
    unsafe {
        std::mem::transmute::<
            unsafe extern "C" fn(
                fmi2ComponentEnvironment,
                fmi2String,
                fmi2Status,
                fmi2String,
                fmi2String,
            ),
            fmi2CallbackLogger,
        >(logger)
    }
}

pub(super) fn callbacks(log: &Log) -> fmi2CallbackFunctions {
    fmi2CallbackFunctions {
        logger: Some(as_fmi2_logger(rust_logger)),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: log as *const Log as *mut c_void,
    }
}

static COUNTER: AtomicUsize = AtomicUsize::new(0);

/// An unpacked FMU's resources folder on disk.
pub(super) struct Unpacked {
    pub(super) dir: PathBuf,
    pub(super) guid: CString,
}

impl Unpacked {
    pub(super) fn new(network: &str, keep: bool, folder_name: &str) -> Unpacked {
        Self::with_files(network, keep, folder_name, &[])
    }

    /// As [`Unpacked::new`], with more resource files `(name, text)`.
    pub(super) fn with_files(
        network: &str,
        keep: bool,
        folder_name: &str,
        files: &[(&str, &str)],
    ) -> Unpacked {
        let dir = std::env::temp_dir().join(format!(
            "hydrofmu-fmi2-{}-{}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::SeqCst)
        ));
        let resources = dir.join(folder_name);
        std::fs::create_dir_all(&resources).unwrap();
        std::fs::write(resources.join(Resources::NETWORK_FILE), network).unwrap();
        std::fs::write(
            resources.join(Resources::OPTIONS_FILE),
            Resources::options_text(keep),
        )
        .unwrap();
        for (name, text) in files {
            std::fs::write(resources.join(name), text).unwrap();
        }
        let guid = Resources::read(&resources).unwrap().guid();
        Unpacked {
            dir: resources,
            guid: CString::new(guid).unwrap(),
        }
    }

    pub(super) fn uri(&self) -> CString {
        CString::new(format!("file://{}", self.dir.display())).unwrap()
    }
}

impl Drop for Unpacked {
    fn drop(&mut self) {
        if let Some(parent) = self.dir.parent() {
            let _ = std::fs::remove_dir_all(parent);
        }
    }
}

pub(super) fn instantiate(
    fmu: &Unpacked,
    uri: &CStr,
    functions: &fmi2CallbackFunctions,
    logging: bool,
) -> fmi2Component {
    // SAFETY: NUL-terminated strings and callbacks that outlive the call.
    unsafe {
        fmi2Instantiate(
            c"hull%1".as_ptr(),
            fmi2CoSimulation,
            fmu.guid.as_ptr(),
            uri.as_ptr(),
            functions,
            0,
            c_int::from(logging),
        )
    }
}

/// Instantiated and initialized at rho = g = 1.
pub(super) fn ready(fmu: &Unpacked, functions: &fmi2CallbackFunctions) -> fmi2Component {
    let c = instantiate(fmu, &fmu.uri(), functions, false);
    assert!(!c.is_null());
    // SAFETY: see the module docs.
    unsafe {
        set(c, &[VR_RHO, VR_G], &[1.0, 1.0]);
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2OK);
    }
    c
}

/// # Safety
/// `c` is a live component.
pub(super) unsafe fn set(c: fmi2Component, vr: &[u32], v: &[f64]) {
    assert_eq!(v.len(), vr.len());
    // SAFETY: a live component (caller) and two arrays of vr.len() entries.
    let status = unsafe { fmi2SetReal(c, vr.as_ptr(), vr.len(), v.as_ptr()) };
    assert_eq!(status, fmi2OK);
}

/// # Safety
/// `c` is a live component.
pub(super) unsafe fn get(c: fmi2Component, vr: &[u32]) -> Vec<f64> {
    let mut out = vec![0.0; vr.len()];
    // SAFETY: a live component (caller) and two arrays of vr.len() entries.
    let status = unsafe { fmi2GetReal(c, vr.as_ptr(), vr.len(), out.as_mut_ptr()) };
    assert_eq!(status, fmi2OK);
    out
}

/// # Safety
/// `c` is a live component, not in use.
unsafe fn phase(c: fmi2Component) -> Phase {
    // SAFETY: the caller's contract; a shared reference for this read only.
    unsafe { &(*(c as *const Component)).instance }.phase()
}

const VELOCITY: u32 = FIRST_PER_HULL_REFERENCE;
const FORCE: u32 = FIRST_PER_HULL_REFERENCE + 1;
const POWER: u32 = FIRST_PER_HULL_REFERENCE + 2;
const ENERGY: u32 = FIRST_PER_HULL_REFERENCE + 3;
const ADDED_MASS: u32 = FIRST_PER_HULL_REFERENCE + 4;
const DAMPING: u32 = FIRST_PER_HULL_REFERENCE + 5;

#[test]
fn version_and_platform() {
    // SAFETY: static NUL-terminated strings.
    let v = unsafe { CStr::from_ptr(fmi2GetVersion()) };
    assert_eq!(v.to_str().unwrap(), "2.0");
    // SAFETY: as above.
    let p = unsafe { CStr::from_ptr(fmi2GetTypesPlatform()) };
    assert_eq!(p.to_str().unwrap(), "default");
}

#[test]
fn a_normal_run_matches_the_network() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log = Log::default();
    let c = ready(&fmu, &callbacks(&log));
    // SAFETY: see the module docs.
    unsafe {
        // At rest: force = -c1 v, power = c1 v^2, calculated parameters at rho = g = 1.
        set(c, &[VELOCITY], &[2.0]);
        let v = get(c, &[FORCE, POWER, ENERGY, ADDED_MASS, DAMPING]);
        assert_eq!(v, vec![-0.9962 * 2.0, 0.9962 * 4.0, 0.0, 0.1153, 0.9962]);
        let mut t = 0.0;
        for _ in 0..100 {
            assert_eq!(fmi2DoStep(c, t, 0.01, 1), fmi2OK);
            t += 0.01;
        }
        let mut last = 0.0;
        assert_eq!(
            fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &mut last),
            fmi2OK
        );
        assert!((last - 1.0).abs() < 1e-12);
        let e = get(c, &[ENERGY])[0];
        assert!(e > 0.0);
        // Directional derivative d force / d velocity = -damping_direct.
        let mut d = 0.0;
        let seed = 1.0;
        assert_eq!(
            fmi2GetDirectionalDerivative(c, &FORCE, 1, &VELOCITY, 1, &seed, &mut d),
            fmi2OK
        );
        assert_eq!(d, -0.9962);
        let mut dp = 0.0;
        let order = 1;
        assert_eq!(
            fmi2GetRealOutputDerivatives(c, &FORCE, 1, &order, &mut dp),
            fmi2OK
        );
        assert!(dp.is_finite());
        let mut terminated = 1;
        assert_eq!(
            fmi2GetBooleanStatus(c, fmi2Terminated, &mut terminated),
            fmi2OK
        );
        assert_eq!(terminated, 0);
        assert_eq!(fmi2Terminate(c), fmi2OK);
        assert_eq!(get(c, &[FORCE]).len(), 1);
        fmi2FreeInstance(c);
    }
    // Nothing was logged: logging off and no errors.
    assert!(log.lock().unwrap().is_empty());
}

#[test]
fn resource_locations_in_every_accepted_spelling() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "res ources%");
    let log = Log::default();
    let f = callbacks(&log);
    let path = fmu.dir.display().to_string();
    let encoded = path.replace('%', "%25").replace(' ', "%20");
    for uri in [
        format!("file://{encoded}"),
        format!("file://{encoded}/"),
        format!("file:{encoded}"),
        format!("file://localhost{encoded}"),
        format!("file://{}", encoded.replace("/tmp", "/%74mp")),
        // URI schemes and host names are case-insensitive.
        format!("FILE://{encoded}"),
        format!("File:{encoded}"),
        format!("FILE://LOCALHOST{encoded}"),
    ] {
        let c = instantiate(&fmu, &CString::new(uri.clone()).unwrap(), &f, false);
        assert!(!c.is_null(), "{uri}: {:?}", log.lock().unwrap());
        // SAFETY: see the module docs.
        unsafe { fmi2FreeInstance(c) };
    }
    assert_eq!(
        resource_path("file:///a%20b/").unwrap(),
        PathBuf::from("/a b/")
    );
    for bad in [
        "http://example.com/resources",
        "/plain/path",
        "file://otherhost/x",
        "file:///bad%zz",
        "file:///nul%00",
        "",
    ] {
        assert!(resource_path(bad).is_err(), "{bad}");
    }
}

#[test]
fn instantiation_refuses_bad_arguments_and_logs_why() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log = Log::default();
    let f = callbacks(&log);
    let uri = fmu.uri();
    // SAFETY: see the module docs.
    unsafe {
        let wrong_guid = c"{00000000-0000-0000-0000-000000000000}";
        let cases: Vec<(fmi2String, fmi2Type, fmi2String, fmi2String)> = vec![
            (
                c"a".as_ptr(),
                fmi2ModelExchange,
                fmu.guid.as_ptr(),
                uri.as_ptr(),
            ),
            (c"a".as_ptr(), 7, fmu.guid.as_ptr(), uri.as_ptr()),
            (
                c"a".as_ptr(),
                fmi2CoSimulation,
                wrong_guid.as_ptr(),
                uri.as_ptr(),
            ),
            (
                c"a".as_ptr(),
                fmi2CoSimulation,
                std::ptr::null(),
                uri.as_ptr(),
            ),
            (
                c"a".as_ptr(),
                fmi2CoSimulation,
                fmu.guid.as_ptr(),
                std::ptr::null(),
            ),
            (
                c"a".as_ptr(),
                fmi2CoSimulation,
                fmu.guid.as_ptr(),
                c"http://x/r".as_ptr(),
            ),
            (
                c"a".as_ptr(),
                fmi2CoSimulation,
                fmu.guid.as_ptr(),
                c"file:///nonexistent/r".as_ptr(),
            ),
            (
                std::ptr::null(),
                fmi2CoSimulation,
                fmu.guid.as_ptr(),
                uri.as_ptr(),
            ),
            (
                c"".as_ptr(),
                fmi2CoSimulation,
                fmu.guid.as_ptr(),
                uri.as_ptr(),
            ),
        ];
        let count = cases.len();
        for (name, kind, guid, location) in cases {
            let c = fmi2Instantiate(name, kind, guid, location, &f, 0, 0);
            assert!(c.is_null());
        }
        assert!(fmi2Instantiate(
            c"a".as_ptr(),
            fmi2CoSimulation,
            fmu.guid.as_ptr(),
            uri.as_ptr(),
            std::ptr::null(),
            0,
            0
        )
        .is_null());
        let log = log.lock().unwrap();
        assert_eq!(log.len(), count);
        assert!(log
            .iter()
            .all(|(s, c, _)| *s == fmi2Error && c == "logStatusError"));
        assert!(log[2].2.contains("does not match"), "{}", log[2].2);
    }
    // Resources changed after packing: the GUID no longer matches.
    std::fs::write(fmu.dir.join(Resources::NETWORK_FILE), TWO_DOF_NETWORK).unwrap();
    let log = Log::default();
    let f = callbacks(&log);
    assert!(instantiate(&fmu, &uri, &f, false).is_null());
}

#[test]
fn a_null_logger_is_tolerated() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let f = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    let c = instantiate(&fmu, &fmu.uri(), &f, true);
    assert!(!c.is_null());
    // SAFETY: see the module docs.
    unsafe {
        assert_eq!(fmi2DoStep(c, 0.0, 0.1, 0), fmi2Error);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
        fmi2FreeInstance(c);
    }
}

#[test]
fn every_function_refuses_a_null_or_foreign_component() {
    let mut garbage = [0u64; 64];
    let foreign = garbage.as_mut_ptr() as fmi2Component;
    for c in [std::ptr::null_mut(), foreign] {
        // SAFETY: see the module docs.
        unsafe {
            let mut x = 0.0;
            let mut i = 0;
            let mut s: fmi2String = std::ptr::null();
            let mut st: fmi2FMUstate = std::ptr::null_mut();
            let mut size = 0usize;
            let mut status = 0;
            let r = 0u32;
            let results = [
                fmi2SetDebugLogging(c, 1, 0, std::ptr::null()),
                fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
                fmi2EnterInitializationMode(c),
                fmi2ExitInitializationMode(c),
                fmi2Terminate(c),
                fmi2Reset(c),
                fmi2GetReal(c, &r, 1, &mut x),
                fmi2GetInteger(c, &r, 1, &mut i),
                fmi2GetBoolean(c, &r, 1, &mut i),
                fmi2GetString(c, &r, 1, &mut s),
                fmi2SetReal(c, &r, 1, &x),
                fmi2SetInteger(c, &r, 1, &i),
                fmi2SetBoolean(c, &r, 1, &i),
                fmi2SetString(c, &r, 1, &s),
                fmi2GetFMUstate(c, &mut st),
                fmi2SetFMUstate(c, st),
                fmi2FreeFMUstate(c, &mut st),
                fmi2SerializedFMUstateSize(c, st, &mut size),
                fmi2SerializeFMUstate(c, st, std::ptr::null_mut(), 0),
                fmi2DeSerializeFMUstate(c, std::ptr::null(), 0, &mut st),
                fmi2GetDirectionalDerivative(c, &r, 1, &r, 1, &x, &mut x),
                fmi2SetRealInputDerivatives(c, &r, 1, &i, &x),
                fmi2GetRealOutputDerivatives(c, &r, 1, &i, &mut x),
                fmi2DoStep(c, 0.0, 0.1, 0),
                fmi2CancelStep(c),
                fmi2GetStatus(c, fmi2DoStepStatus, &mut status),
                fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &mut x),
                fmi2GetIntegerStatus(c, fmi2DoStepStatus, &mut i),
                fmi2GetBooleanStatus(c, fmi2Terminated, &mut i),
                fmi2GetStringStatus(c, fmi2DoStepStatus, &mut s),
            ];
            assert!(results.iter().all(|r| *r == fmi2Error), "{results:?}");
            fmi2FreeInstance(c);
        }
    }
    assert!(garbage.iter().all(|x| *x == 0));
}

#[test]
fn calls_in_the_wrong_phase_are_refused_without_changing_it() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log = Log::default();
    let f = callbacks(&log);
    let c = instantiate(&fmu, &fmu.uri(), &f, false);
    // SAFETY: see the module docs.
    unsafe {
        let mut x = 0.0;
        assert_eq!(fmi2DoStep(c, 0.0, 0.1, 0), fmi2Error);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2Error);
        assert_eq!(fmi2Terminate(c), fmi2Error);
        assert_eq!(fmi2GetReal(c, &FORCE, 1, &mut x), fmi2Error);
        assert_eq!(fmi2CancelStep(c), fmi2Error);
        assert_eq!(phase(c), Phase::Instantiated);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), fmi2Error);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2Error);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2OK);
        assert_eq!(fmi2Terminate(c), fmi2OK);
        assert_eq!(fmi2DoStep(c, 0.0, 0.1, 0), fmi2Error);
        assert_eq!(fmi2SetReal(c, &VELOCITY, 1, &1.0), fmi2Error);
        assert_eq!(phase(c), Phase::Terminated);
        assert_eq!(fmi2Reset(c), fmi2OK);
        assert_eq!(phase(c), Phase::Instantiated);
        fmi2FreeInstance(c);
    }
    let log = log.lock().unwrap();
    assert_eq!(log.len(), 9);
    assert!(log
        .iter()
        .all(|(_, _, m)| m.contains("not allowed in phase")));
}

#[test]
fn every_bad_call_gets_an_error_and_reset_recovers() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log = Log::default();
    let f = callbacks(&log);
    let c = ready(&fmu, &f);
    // SAFETY: see the module docs.
    unsafe {
        set(c, &[VELOCITY], &[1.0]);
        assert_eq!(fmi2DoStep(c, 0.0, 0.5, 0), fmi2OK);
        let reference = get(c, &[FORCE, ENERGY, VELOCITY]);
        let mut st: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(fmi2GetFMUstate(c, &mut st), fmi2OK);
        let one = 1;
        let two = 2;
        let unknown = 99_999u32;
        let bad: Vec<(&str, BadCall)> = vec![
            ("h = 0", Box::new(|| fmi2DoStep(c, 0.5, 0.0, 0))),
            ("h < 0", Box::new(|| fmi2DoStep(c, 0.5, -0.1, 0))),
            ("h NaN", Box::new(|| fmi2DoStep(c, 0.5, f64::NAN, 0))),
            ("wrong time", Box::new(|| fmi2DoStep(c, 0.7, 0.1, 0))),
            (
                "NaN input",
                Box::new(|| fmi2SetReal(c, &VELOCITY, 1, &f64::NAN)),
            ),
            (
                "inf input",
                Box::new(|| fmi2SetReal(c, &VELOCITY, 1, &f64::INFINITY)),
            ),
            (
                "huge input",
                Box::new(|| fmi2SetReal(c, &VELOCITY, 1, &1e300)),
            ),
            (
                "valid then huge input: refused whole",
                Box::new(|| {
                    fmi2SetReal(c, [VELOCITY, VELOCITY].as_ptr(), 2, [2.0, 1e300].as_ptr())
                }),
            ),
            (
                "huge input derivative",
                Box::new(|| fmi2SetRealInputDerivatives(c, &VELOCITY, 1, &one, &-1e300)),
            ),
            ("set output", Box::new(|| fmi2SetReal(c, &FORCE, 1, &1.0))),
            (
                "set calculated",
                Box::new(|| fmi2SetReal(c, &DAMPING, 1, &1.0)),
            ),
            (
                "set rho late",
                Box::new(|| fmi2SetReal(c, &VR_RHO, 1, &1.0)),
            ),
            ("unknown vr", Box::new(|| fmi2SetReal(c, &unknown, 1, &1.0))),
            (
                "get unknown vr",
                Box::new(|| fmi2GetReal(c, &unknown, 1, &mut 0.0)),
            ),
            (
                "NULL vr",
                Box::new(|| fmi2SetReal(c, std::ptr::null(), 1, &1.0)),
            ),
            (
                "NULL value",
                Box::new(|| fmi2GetReal(c, &FORCE, 1, std::ptr::null_mut())),
            ),
            (
                "get integer",
                Box::new(|| fmi2GetInteger(c, &VELOCITY, 1, &mut 0)),
            ),
            (
                "set boolean",
                Box::new(|| fmi2SetBoolean(c, &VELOCITY, 1, &one)),
            ),
            (
                "set string",
                Box::new(|| fmi2SetString(c, &VELOCITY, 1, &c"x".as_ptr())),
            ),
            (
                "unknown category",
                Box::new(|| fmi2SetDebugLogging(c, 1, 1, &c"100%".as_ptr())),
            ),
            (
                "input derivative order 2",
                Box::new(|| fmi2SetRealInputDerivatives(c, &VELOCITY, 1, &two, &1.0)),
            ),
            (
                "input derivative of output",
                Box::new(|| fmi2SetRealInputDerivatives(c, &FORCE, 1, &one, &1.0)),
            ),
            (
                "output derivative order 2",
                Box::new(|| fmi2GetRealOutputDerivatives(c, &FORCE, 1, &two, &mut 0.0)),
            ),
            (
                "output derivative order 0",
                Box::new(|| fmi2GetRealOutputDerivatives(c, &FORCE, 1, &0, &mut 0.0)),
            ),
            (
                "derivative wrt output",
                Box::new(|| fmi2GetDirectionalDerivative(c, &FORCE, 1, &FORCE, 1, &1.0, &mut 0.0)),
            ),
            (
                "NULL state",
                Box::new(|| fmi2SetFMUstate(c, std::ptr::null_mut())),
            ),
            (
                "corrupt bytes",
                Box::new(|| {
                    let mut s: fmi2FMUstate = std::ptr::null_mut();
                    let bytes = [7 as c_char; 64];
                    fmi2DeSerializeFMUstate(c, bytes.as_ptr(), bytes.len(), &mut s)
                }),
            ),
            (
                "wrong serialize size",
                Box::new(move || {
                    let mut buffer = [0 as c_char; 8];
                    fmi2SerializeFMUstate(c, st, buffer.as_mut_ptr(), buffer.len())
                }),
            ),
            (
                "status to NULL",
                Box::new(|| fmi2GetStatus(c, fmi2DoStepStatus, std::ptr::null_mut())),
            ),
        ];
        for (what, call) in &bad {
            assert_eq!(call(), fmi2Error, "{what}");
            assert_eq!(phase(c), Phase::Error, "{what}");
            // In the error phase outputs stay readable and unchanged.
            assert_eq!(get(c, &[FORCE, ENERGY, VELOCITY]), reference, "{what}");
            assert_eq!(fmi2DoStep(c, 0.5, 0.1, 0), fmi2Error, "{what}");
            // The saved state brings the instance back (phase included).
            assert_eq!(fmi2SetFMUstate(c, st), fmi2OK, "{what}");
            assert_eq!(phase(c), Phase::StepComplete, "{what}");
        }
        // The `%` of the category name reached the logger escaped.
        let logged = log.lock().unwrap().clone();
        assert!(logged.iter().any(|(_, _, m)| m.contains("'100%%'")));
        assert!(logged
            .iter()
            .all(|(_, cat, _)| LOG_CATEGORIES.iter().any(|(c, _)| c == cat)));
        // Reset after an error: usable again from the start values.
        assert_eq!(fmi2DoStep(c, 0.5, -1.0, 0), fmi2Error);
        assert_eq!(fmi2Reset(c), fmi2OK);
        assert_eq!(get_phase_values(c), (Phase::Instantiated, 1025.0));
        assert_eq!(fmi2FreeFMUstate(c, &mut st), fmi2OK);
        assert!(st.is_null());
        assert_eq!(fmi2FreeFMUstate(c, &mut st), fmi2OK);
        fmi2FreeInstance(c);
    }
}

/// One refused call.
type BadCall<'a> = Box<dyn Fn() -> fmi2Status + 'a>;

/// # Safety
/// `c` is a live component.
unsafe fn get_phase_values(c: fmi2Component) -> (Phase, f64) {
    // SAFETY: the caller's contract.
    let instance = unsafe { &(*(c as *const Component)).instance };
    (instance.phase(), instance.model().state().rho)
}

#[test]
fn logging_is_silent_per_step_unless_log_calls_is_on() {
    let fmu = Unpacked::new(SEED_NETWORK, false, "resources");
    let log = Log::default();
    let f = callbacks(&log);
    let c = ready(&fmu, &f);
    // SAFETY: see the module docs.
    unsafe {
        for k in 0..50 {
            assert_eq!(fmi2DoStep(c, k as f64 * 0.1, 0.1, 0), fmi2OK);
        }
        assert!(log.lock().unwrap().is_empty());
        let calls = c"logCalls".as_ptr();
        assert_eq!(fmi2SetDebugLogging(c, 1, 1, &calls), fmi2OK);
        let before = log.lock().unwrap().len();
        for k in 50..60 {
            assert_eq!(fmi2DoStep(c, k as f64 * 0.1, 0.1, 0), fmi2OK);
        }
        // Each step logged once, with its final status.
        let lines = log.lock().unwrap()[before..].to_vec();
        assert_eq!(lines.len(), 10, "{lines:?}");
        assert!(lines
            .iter()
            .all(|(status, category, message)| *status == fmi2OK
                && category == "logCalls"
                && message.starts_with("fmi2DoStep(t = ")));
        // A failed step: one call line with fmi2Error (never fmi2OK), then the reason.
        let before = log.lock().unwrap().len();
        assert_eq!(fmi2DoStep(c, 6.0, 0.0, 0), fmi2Error);
        let lines = log.lock().unwrap()[before..].to_vec();
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert_eq!((lines[0].0, lines[0].1.as_str()), (fmi2Error, "logCalls"));
        assert_eq!(
            (lines[1].0, lines[1].1.as_str()),
            (fmi2Error, "logStatusError")
        );
        // A call refused in its phase, and one refused for a NULL pointer: the same.
        for refused in [
            fmi2DoStep(c, 6.0, 0.1, 0),
            fmi2GetReal(c, &FORCE, 1, std::ptr::null_mut()),
        ] {
            assert_eq!(refused, fmi2Error);
        }
        let lines = log.lock().unwrap()[before + 2..].to_vec();
        let calls: Vec<i32> = lines
            .iter()
            .filter(|(_, category, _)| category == "logCalls")
            .map(|(status, _, _)| *status)
            .collect();
        assert_eq!(calls, [fmi2Error, fmi2Error], "{lines:?}");
        assert_eq!(fmi2Reset(c), fmi2OK);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2OK);
        assert_eq!(fmi2SetDebugLogging(c, 0, 0, std::ptr::null()), fmi2OK);
        let before = log.lock().unwrap().len();
        assert_eq!(fmi2DoStep(c, 0.0, 0.1, 0), fmi2OK);
        assert_eq!(log.lock().unwrap().len(), before);
        fmi2FreeInstance(c);
    }
    // loggingOn at instantiation turns every category on, events included.
    let log2 = Log::default();
    let c = instantiate(&fmu, &fmu.uri(), &callbacks(&log2), true);
    // SAFETY: see the module docs.
    unsafe { fmi2FreeInstance(c) };
    assert!(log2
        .lock()
        .unwrap()
        .iter()
        .any(|(_, cat, _)| cat == "logEvents"));
}

mod fmi2_state;
mod fmi3;
mod hostile;
mod viscous;
