//! The C layer: the exported `fmi2...` functions, the only code with `unsafe`.
//!
//! Each function checks the pointers it is given (NULL, alignment, length, and the magic
//! number of a component or FMU state, so that a foreign or freed one is refused), turns
//! them into references, slices and strings, catches panics, and calls the safe
//! [`Instance`]. A call's log messages reach the master's logger after the call, when no
//! reference into the instance is alive (a logger may call back into the FMU).
//!
//! Pointer arguments are read only once the phase allows the call, so a call in the wrong
//! phase is refused whatever its pointers are.
#![deny(unsafe_op_in_unsafe_fn)]
#![deny(clippy::undocumented_unsafe_blocks)]
// FMI names; the contract of every exported function is the FMI 2.0 standard's.
#![allow(non_snake_case, clippy::missing_safety_doc)]

use super::instance::{Instance, Snapshot};
use super::logging::{Category, Message};
use super::phase::{Function, Standard};
use super::types::*;
use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr::addr_of;

const INSTANCE_MAGIC: u64 = 0x6879_6472_6f66_6d75; // "hydrofmu"
/// An instance made by fmi3InstantiateCoSimulation: fmi2 functions refuse it, and back.
const INSTANCE_MAGIC_FMI3: u64 = 0x6879_6472_6f66_6d33; // "hydrofm3"
const SNAPSHOT_MAGIC: u64 = 0x6879_6472_6f73_6e70; // "hydrosnp"

/// What an `fmi2Component` points to. `repr(C)` with the magic number first: checking a
/// pointer reads only its first 8 bytes.
#[repr(C)]
struct Component {
    magic: u64,
    logger: Logger,
    instance: Instance,
}

/// What an `fmi2FMUstate` points to (same layout rule as [`Component`]).
#[repr(C)]
struct StoredState {
    magic: u64,
    snapshot: Option<Snapshot>,
}

/// The copied callbacks.
#[derive(Clone, Copy)]
enum Logger {
    /// fmi2CallbackLogger: a printf-like format.
    Fmi2 {
        logger: Option<fmi2CallbackLogger>,
        environment: fmi2ComponentEnvironment,
    },
    /// fmi3LogMessageCallback: plain text, no instance name.
    Fmi3 {
        logger: Option<fmi3::fmi3LogMessageCallback>,
        environment: fmi3::fmi3InstanceEnvironment,
    },
}

impl Logger {
    fn log(&self, instance_name: &CStr, message: &Message) {
        let (logger, environment) = match *self {
            Logger::Fmi2 {
                logger,
                environment,
            } => (logger, environment),
            Logger::Fmi3 {
                logger,
                environment,
            } => {
                fmi3::log(logger, environment, message);
                return;
            }
        };
        let Some(logger) = logger else { return };
        let escaped = message.text.replace('%', "%%").replace('\0', " ");
        let Ok(text) = CString::new(escaped) else {
            return;
        };
        let Ok(category) = CString::new(message.category.name()) else {
            return;
        };
        // SAFETY: the master gave this logger for this purpose; all strings are valid,
        // NUL-terminated, and the format has no conversions left (every % is doubled).
        unsafe {
            logger(
                environment,
                instance_name.as_ptr(),
                message.status.code(),
                category.as_ptr(),
                text.as_ptr(),
            )
        };
    }
}

// ---------------------------------------------------------------------------------------
// Pointer checks
// ---------------------------------------------------------------------------------------

/// The component behind `c`, if it is one of ours.
///
/// # Safety
/// `c` is NULL or points to at least 8 readable bytes.
unsafe fn component_from(c: fmi2Component) -> Option<*mut Component> {
    // SAFETY: the caller's contract.
    unsafe { component_with_magic(c, INSTANCE_MAGIC) }
}

/// The component behind `c`, if it is one of ours made through the standard `magic` names.
///
/// # Safety
/// As [`component_from`].
unsafe fn component_with_magic(c: fmi2Component, magic: u64) -> Option<*mut Component> {
    if c.is_null() || (c as usize) % std::mem::align_of::<Component>() != 0 {
        return None;
    }
    let component = c as *mut Component;
    // SAFETY: non-null and aligned; the first 8 bytes are readable (caller) and are the
    // `magic` field of a `repr(C)` Component. No reference to the whole is made.
    let found = unsafe { addr_of!((*component).magic).read() };
    (found == magic).then_some(component)
}

/// Runs `body` on the instance behind `c`, catches a panic (the instance becomes fatal),
/// then passes the call's messages to the logger.
///
/// # Safety
/// As [`component_from`]; a component of ours is not used by another thread meanwhile
/// (FMI 2.0: one instance, one thread at a time).
unsafe fn with_instance(
    c: fmi2Component,
    function: Function,
    body: impl FnOnce(&mut Instance) -> Status,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { with_instance_of(INSTANCE_MAGIC, c, function, body) }
}

/// [`with_instance`] for a component made through the standard `magic` names.
///
/// # Safety
/// As [`with_instance`].
unsafe fn with_instance_of(
    magic: u64,
    c: fmi2Component,
    function: Function,
    body: impl FnOnce(&mut Instance) -> Status,
) -> fmi2Status {
    let called = function.name_in(standard_of(magic));
    // SAFETY: the caller's contract.
    unsafe { with_instance_named(magic, c, function, called, body) }
}

/// The standard whose functions make and take components with `magic`.
fn standard_of(magic: u64) -> Standard {
    if magic == INSTANCE_MAGIC_FMI3 {
        Standard::Fmi3
    } else {
        Standard::Fmi2
    }
}

/// [`with_instance_of`] for the function `called` (its C name): a component of the other
/// standard is refused with a log line naming both standards' functions.
///
/// # Safety
/// As [`with_instance`].
unsafe fn with_instance_named(
    magic: u64,
    c: fmi2Component,
    function: Function,
    called: &'static str,
    body: impl FnOnce(&mut Instance) -> Status,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    let Some(component) = (unsafe { component_with_magic(c, magic) }) else {
        let other = match standard_of(magic) {
            Standard::Fmi2 => INSTANCE_MAGIC_FMI3,
            Standard::Fmi3 => INSTANCE_MAGIC,
        };
        // SAFETY: the caller's contract.
        if let Some(component) = unsafe { component_with_magic(c, other) } {
            // The counterpart only where `called` is the function's own name.
            let own = called == function.name_in(standard_of(magic));
            let _ = catch_unwind(AssertUnwindSafe(|| {
                // SAFETY: a live Component of the other standard; the only reference into
                // it, dropped when the closure returns.
                let instance = unsafe { &mut (*component).instance };
                let counterpart = own.then(|| function.name_in(instance.standard()));
                instance.refuse_other_standard(called, counterpart);
            }));
            // SAFETY: a live Component and no reference into it.
            unsafe { flush(component) };
        }
        return fmi2Error;
    };
    let status = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: a live Component (magic checked, not freed: fmi2FreeInstance clears the
        // magic); the only reference into it, dropped when the closure returns.
        let instance = unsafe { &mut (*component).instance };
        body(instance)
    }))
    .unwrap_or_else(|_| {
        // SAFETY: as above; the panicked call's reference is gone.
        let instance = unsafe { &mut (*component).instance };
        instance.enter_fatal(function)
    });
    // SAFETY: a live Component and no reference into it.
    unsafe { flush(component) };
    status.code()
}

/// Passes the messages collected by the instance to the logger, holding no reference into
/// the component while the logger runs.
///
/// # Safety
/// `component` is live and nothing borrows it.
unsafe fn flush(component: *mut Component) {
    // SAFETY: the caller's contract; the reference ends with this statement.
    let (messages, logger, name) = unsafe {
        let component = &mut *component;
        let messages = component.instance.take_messages();
        if messages.is_empty() {
            return;
        }
        let name = component.instance.name().to_owned();
        (messages, component.logger, name)
    };
    for message in &messages {
        logger.log(&name, message);
    }
}

/// [`with_instance`] for a call with pointer arguments: the phase is checked first, then
/// `body` reads the pointers and calls the instance; a pointer `body` refuses makes the
/// call fail (error phase).
///
/// # Safety
/// As [`with_instance`].
unsafe fn call(
    c: fmi2Component,
    function: Function,
    body: impl FnOnce(&mut Instance) -> Result<Status, String>,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { call_of(INSTANCE_MAGIC, c, function, body) }
}

/// [`call`] for a component made through the standard `magic` names.
///
/// # Safety
/// As [`with_instance`].
unsafe fn call_of(
    magic: u64,
    c: fmi2Component,
    function: Function,
    body: impl FnOnce(&mut Instance) -> Result<Status, String>,
) -> fmi2Status {
    let checked = |instance: &mut Instance| {
        if let Some(refused) = instance.refuse_outside_phase(function) {
            return refused;
        }
        body(instance).unwrap_or_else(|message| instance.reject_arguments(function, &message))
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance_of(magic, c, function, checked) }
}

/// Checks an array pointer for `n` values of `T`: NULL is accepted only for n = 0.
fn check_array<T>(ptr: *const T, n: usize, what: &str) -> Result<(), String> {
    if n == 0 {
        return Ok(());
    }
    if ptr.is_null() {
        return Err(format!("{what} is NULL with {n} entries"));
    }
    let fits =
        matches!(n.checked_mul(std::mem::size_of::<T>()), Some(b) if b <= isize::MAX as usize);
    if (ptr as usize) % std::mem::align_of::<T>() != 0 || !fits {
        return Err(format!("{what} is misaligned or too long"));
    }
    Ok(())
}

/// A slice from a C array.
///
/// # Safety
/// Unless NULL, `ptr` points to `n` initialized values, not written during the call.
unsafe fn slice<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    check_array(ptr, n, what)?;
    if n == 0 {
        return Ok(&[]);
    }
    // SAFETY: non-null, aligned, at most isize::MAX bytes (checked); `n` readable values
    // (caller).
    Ok(unsafe { std::slice::from_raw_parts(ptr, n) })
}

/// A mutable slice from a C array.
///
/// # Safety
/// Unless NULL, `ptr` points to `n` writable values, used by nothing else during the call.
unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize, what: &str) -> Result<&'a mut [T], String> {
    check_array(ptr as *const T, n, what)?;
    if n == 0 {
        return Ok(&mut []);
    }
    // SAFETY: non-null, aligned, at most isize::MAX bytes (checked); `n` writable values
    // nothing else uses (caller). Any bit pattern is a valid value of the C types used.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
}

/// One value to write (`what` names it in the error).
///
/// # Safety
/// As [`slice_mut`] with n = 1.
unsafe fn out<'a, T>(ptr: *mut T, what: &str) -> Result<&'a mut T, String> {
    // SAFETY: the caller's contract.
    let one = unsafe { slice_mut(ptr, 1, what) }?;
    Ok(&mut one[0])
}

/// A UTF-8 string (`None` for NULL or not UTF-8).
///
/// # Safety
/// Unless NULL, `ptr` is a NUL-terminated string, unchanged during the call.
unsafe fn text<'a>(ptr: fmi2String) -> Option<&'a str> {
    if ptr.is_null() {
        return None;
    }
    // SAFETY: non-null and NUL-terminated (caller).
    unsafe { CStr::from_ptr(ptr) }.to_str().ok()
}

/// The stored state behind `state`, if `inst` issued it and has not freed it (no other
/// pointer is dereferenced: a foreign one may not be readable).
///
/// # Safety
/// A state `inst` issued is a live `StoredState` (freed ones leave the set first).
unsafe fn stored_state(inst: &Instance, state: fmi2FMUstate) -> Result<*mut StoredState, String> {
    if state.is_null() {
        return Err("FMUstate is NULL".to_string());
    }
    let standard = inst.standard();
    let not_ours = || {
        format!(
            "FMUstate is not a state of this instance ({} or {} of this instance issues them; freed ones are gone)",
            Function::GetFmuState.name_in(standard),
            Function::DeSerializeFmuState.name_in(standard)
        )
    };
    if !inst.issued_state(state as usize) {
        return Err(not_ours());
    }
    if (state as usize) % std::mem::align_of::<StoredState>() != 0 {
        return Err(not_ours());
    }
    let stored = state as *mut StoredState;
    // SAFETY: non-null and aligned; the first 8 bytes are readable (caller) and are the
    // `magic` field of a `repr(C)` StoredState.
    let magic = unsafe { addr_of!((*stored).magic).read() };
    if magic != SNAPSHOT_MAGIC {
        return Err(not_ours());
    }
    Ok(stored)
}

/// The snapshot behind `state`.
///
/// # Safety
/// As [`stored_state`]; a state of ours is not used elsewhere during the call.
unsafe fn snapshot<'a>(inst: &Instance, state: fmi2FMUstate) -> Result<&'a Snapshot, String> {
    // SAFETY: the caller's contract.
    let stored = unsafe { stored_state(inst, state) }?;
    // SAFETY: a live StoredState (magic checked; fmi2FreeFMUstate clears it), only read.
    let stored = unsafe { &*stored };
    stored
        .snapshot
        .as_ref()
        .ok_or_else(|| "FMUstate is not a state of this FMU".to_string())
}

/// Runs `save` on the slot `*target` names: a new one if `*target` is NULL (then boxed and
/// written to `*target` once filled), else the state of ours it points to.
///
/// # Safety
/// Unless NULL, `target` points to a readable and writable `fmi2FMUstate`, which is NULL or
/// as for [`stored_state`].
unsafe fn with_state_slot(
    inst: &mut Instance,
    target: *mut fmi2FMUstate,
    save: impl FnOnce(&mut Instance, &mut Option<Snapshot>) -> Status,
) -> Result<Status, String> {
    if target.is_null() {
        return Err("FMUstate pointer is NULL".to_string());
    }
    // SAFETY: non-null and readable (caller).
    let existing = unsafe { target.read() };
    if existing.is_null() {
        let mut slot = None;
        let status = save(inst, &mut slot);
        if slot.is_some() {
            let stored = Box::into_raw(Box::new(StoredState {
                magic: SNAPSHOT_MAGIC,
                snapshot: slot,
            }));
            inst.record_issued_state(stored as usize);
            // SAFETY: non-null and writable (caller).
            unsafe { target.write(stored as fmi2FMUstate) };
        }
        return Ok(status);
    }
    // SAFETY: the caller's contract.
    let stored = unsafe { stored_state(inst, existing) }?;
    // SAFETY: a live StoredState this instance issued, used by nothing else meanwhile.
    let slot = unsafe { &mut (*stored).snapshot };
    Ok(save(inst, slot))
}

/// Frees the state `*FMUstate` points to and sets it to NULL (a NULL state is a no-op).
///
/// # Safety
/// Unless NULL, `FMUstate` points to a readable and writable `fmi2FMUstate`, which is NULL or
/// as for [`stored_state`].
unsafe fn free_state(inst: &mut Instance, FMUstate: *mut fmi2FMUstate) -> Result<Status, String> {
    if FMUstate.is_null() {
        return Err("FMUstate pointer is NULL".to_string());
    }
    // SAFETY: non-null; the master passes a readable and writable fmi2FMUstate*.
    let state = unsafe { FMUstate.read() };
    if state.is_null() {
        return Ok(inst.free_fmu_state(None));
    }
    // SAFETY: checked against the states this instance issued.
    let stored = unsafe { stored_state(inst, state) }?;
    inst.forget_issued_state(state as usize);
    // SAFETY: a live StoredState made by Box::into_raw in `with_state_slot`, nothing
    // borrows it; the magic is cleared so that a second free is refused, and the
    // master's pointer is set to NULL.
    let snapshot = unsafe {
        (*stored).magic = 0;
        let stored = Box::from_raw(stored);
        FMUstate.write(std::ptr::null_mut());
        stored.snapshot
    };
    Ok(inst.free_fmu_state(snapshot))
}

// ---------------------------------------------------------------------------------------
// Inquiry and life cycle
// ---------------------------------------------------------------------------------------

/// `"default"`.
#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

/// `"2.0"`.
#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// Creates an instance (co-simulation only); NULL on any error (logged when possible).
#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: fmi2Type,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    let result = catch_unwind(AssertUnwindSafe(|| {
        if functions.is_null()
            || (functions as usize) % std::mem::align_of::<fmi2CallbackFunctions>() != 0
        {
            return std::ptr::null_mut();
        }
        // SAFETY: non-null and aligned; the master passes its callback functions.
        let callbacks = unsafe { functions.read() };
        let logger = Logger::Fmi2 {
            logger: callbacks.logger,
            environment: callbacks.componentEnvironment,
        };
        let name = if instanceName.is_null() {
            None
        } else {
            // SAFETY: non-null; the master passes a NUL-terminated string.
            Some(unsafe { CStr::from_ptr(instanceName) })
        };
        // SAFETY: the master passes NUL-terminated strings (or NULL).
        let (guid, location) = unsafe { (text(fmuGUID), text(fmuResourceLocation)) };
        match Instance::instantiate(name, fmuType, guid, location, loggingOn != 0) {
            Ok(instance) => {
                let component = Box::into_raw(Box::new(Component {
                    magic: INSTANCE_MAGIC,
                    logger,
                    instance,
                }));
                // SAFETY: just made, and nothing borrows it.
                unsafe { flush(component) };
                component as fmi2Component
            }
            Err(message) => {
                let message = Message {
                    status: Status::Error,
                    category: Category::Error,
                    text: format!("fmi2Instantiate: {message}"),
                };
                logger.log(name.unwrap_or(c"(unnamed)"), &message);
                std::ptr::null_mut()
            }
        }
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// Frees an instance (allowed in every phase; NULL is ignored).
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the master passes a component from fmi2Instantiate (or NULL).
        if let Some(component) = unsafe { component_from(c) } {
            // SAFETY: a live Component made by Box::into_raw in fmi2Instantiate, nothing
            // borrows it; the magic is cleared so that a second free is refused.
            unsafe {
                (*component).magic = 0;
                drop(Box::from_raw(component));
            }
        } else {
            // SAFETY: as above.
            unsafe { refuse_free_of_other_standard(INSTANCE_MAGIC_FMI3, c, "fmi2FreeInstance") };
        }
    }));
}

/// A free of a component of the other standard (`other`, its magic): not freed, logged to
/// its logger naming both free functions.
///
/// # Safety
/// As [`component_from`]; a component of ours is not used by another thread meanwhile.
unsafe fn refuse_free_of_other_standard(other: u64, c: fmi2Component, called: &str) {
    // SAFETY: the caller's contract.
    let Some(component) = (unsafe { component_with_magic(c, other) }) else {
        return;
    };
    let own = match standard_of(other) {
        Standard::Fmi2 => "fmi2FreeInstance",
        Standard::Fmi3 => "fmi3FreeInstance",
    };
    // SAFETY: a live Component; the only reference into it, dropped with the statement.
    unsafe { &mut (*component).instance }.refuse_other_standard(called, Some(own));
    // SAFETY: a live Component and no reference into it.
    unsafe { flush(component) };
}

/// Sets debug logging for all categories (n = 0) or the listed ones.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    let on = loggingOn != 0;
    // SAFETY: the master passes a component from fmi2Instantiate and nCategories strings.
    unsafe { set_debug_logging(INSTANCE_MAGIC, c, on, nCategories, categories) }
}

/// fmi2SetDebugLogging and fmi3SetDebugLogging for a component of the standard `magic` names.
///
/// # Safety
/// As [`with_instance`]; unless NULL, `categories` holds `n` strings (each NULL or
/// NUL-terminated).
unsafe fn set_debug_logging(
    magic: u64,
    c: fmi2Component,
    on: bool,
    n: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the caller's contract.
        let list = unsafe { slice(categories, n, "categories[]") }?;
        let names = list
            .iter()
            // SAFETY: each a NUL-terminated string (or NULL, refused).
            .map(|&p| unsafe { text(p) })
            .collect::<Option<Vec<&str>>>()
            .ok_or("a category is NULL or not UTF-8")?;
        Ok(inst.set_debug_logging(on, &names))
    };
    // SAFETY: the caller's contract.
    unsafe { call_of(magic, c, Function::SetDebugLogging, body) }
}

/// Sets the start time and, if defined, the stop time (no step may end past it).
#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    toleranceDefined: fmi2Boolean,
    tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    let tolerance = (toleranceDefined != 0).then_some(tolerance);
    let stop = (stopTimeDefined != 0).then_some(stopTime);
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe {
        with_instance(c, Function::SetupExperiment, |inst| {
            inst.setup_experiment(tolerance, startTime, stop)
        })
    }
}

/// Enters initialization mode.
#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe {
        with_instance(c, Function::EnterInitializationMode, |inst| {
            inst.enter_initialization_mode()
        })
    }
}

/// Leaves initialization mode: ready to step.
#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe {
        with_instance(c, Function::ExitInitializationMode, |inst| {
            inst.exit_initialization_mode()
        })
    }
}

/// Ends the simulation.
#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { with_instance(c, Function::Terminate, Instance::terminate) }
}

/// Back to the instantiated phase with the start values (also after an error).
#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { with_instance(c, Function::Reset, Instance::reset) }
}

// ---------------------------------------------------------------------------------------
// Getting and setting values
// ---------------------------------------------------------------------------------------

/// Reads Real variables.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes nvr value references.
        let vr = unsafe { slice(vr, nvr, "vr[]") }?;
        // SAFETY: the master passes room for nvr values.
        let value = unsafe { slice_mut(value, nvr, "value[]") }?;
        Ok(inst.get_real(vr, value))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::GetReal, body) }
}

/// Sets Real variables: rho and g before initialization ends, the inputs any time before
/// termination. All values are checked before any is applied.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes nvr value references.
        let vr = unsafe { slice(vr, nvr, "vr[]") }?;
        // SAFETY: the master passes nvr values.
        let value = unsafe { slice(value, nvr, "value[]") }?;
        Ok(inst.set_real(vr, value))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::SetReal, body) }
}

/// The body of the get and set functions for a type this FMU has no variables of: checks
/// both arrays, then lets the instance answer from the value references.
///
/// # Safety
/// `vr` and `value` as the master passes them (nvr entries each, or NULL).
unsafe fn typeless<T>(
    c: fmi2Component,
    function: Function,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const T,
    answer: fn(&mut Instance, &[fmi2ValueReference]) -> Status,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the caller's contract.
        let vr = unsafe { slice(vr, nvr, "vr[]") }?;
        check_array(value, nvr, "value[]")?;
        Ok(answer(inst, vr))
    };
    // SAFETY: the caller's contract.
    unsafe { call(c, function, body) }
}

/// Reads Integer variables (the Integer wave parameters).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes nvr value references.
        let vr = unsafe { slice(vr, nvr, "vr[]") }?;
        // SAFETY: the master passes room for nvr values.
        let value = unsafe { slice_mut(value, nvr, "value[]") }?;
        Ok(inst.get_integer(vr, value))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::GetInteger, body) }
}

/// No Boolean variables: only nvr = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    let (function, answer) = (Function::GetBoolean, Instance::get_boolean);
    // SAFETY: the master passes a component and arrays of nvr entries.
    unsafe { typeless(c, function, vr, nvr, value.cast_const(), answer) }
}

/// No String variables: only nvr = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    let (function, answer) = (Function::GetString, Instance::get_string);
    // SAFETY: the master passes a component and arrays of nvr entries.
    unsafe { typeless(c, function, vr, nvr, value.cast_const(), answer) }
}

/// Sets Integer variables (the Integer wave parameters, before initialization ends). All
/// values are checked before any is applied.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes nvr value references.
        let vr = unsafe { slice(vr, nvr, "vr[]") }?;
        // SAFETY: the master passes nvr values.
        let value = unsafe { slice(value, nvr, "value[]") }?;
        Ok(inst.set_integer(vr, value))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::SetInteger, body) }
}

/// No Boolean variables: only nvr = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    let (function, answer) = (Function::SetBoolean, Instance::set_boolean);
    // SAFETY: the master passes a component and arrays of nvr entries.
    unsafe { typeless(c, function, vr, nvr, value, answer) }
}

/// No String variables: only nvr = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    let (function, answer) = (Function::SetString, Instance::set_string);
    // SAFETY: the master passes a component and arrays of nvr entries.
    unsafe { typeless(c, function, vr, nvr, value, answer) }
}

// ---------------------------------------------------------------------------------------
// FMU state
// ---------------------------------------------------------------------------------------

/// Saves the state (into a new snapshot, or overwrites `*FMUstate` if not NULL).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the master passes a component and an fmi2FMUstate* holding NULL or a state.
    unsafe { get_state(INSTANCE_MAGIC, c, FMUstate) }
}

/// Restores a saved state, including its phase (this also leaves the error phase).
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    // SAFETY: the master passes a component and a state of this FMU.
    unsafe { set_state(INSTANCE_MAGIC, c, FMUstate) }
}

/// Frees a saved state and sets `*FMUstate` to NULL (NULL `*FMUstate` is a no-op).
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the master passes a component and an fmi2FMUstate* holding NULL or a state.
    unsafe { release_state(INSTANCE_MAGIC, c, FMUstate) }
}

/// Size of the serialized state.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    // SAFETY: the master passes a component, a state of this FMU and room for the size.
    unsafe { serialized_size(INSTANCE_MAGIC, c, FMUstate, size) }
}

/// Writes the serialized state (`size` must be exactly the serialized size).
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    let bytes = serializedState.cast::<u8>();
    // SAFETY: the master passes a component, a state of this FMU and room for `size` bytes.
    unsafe { serialize(INSTANCE_MAGIC, c, FMUstate, bytes, size) }
}

/// Reads a serialized state into a new (or the given) snapshot; corrupt or foreign bytes
/// are refused.
#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    let bytes = serializedState.cast::<u8>();
    // SAFETY: the master passes a component, `size` bytes and an fmi2FMUstate* holding NULL
    // or a state of this FMU.
    unsafe { deserialize(INSTANCE_MAGIC, c, bytes, size, FMUstate) }
}

// The bodies of the FMU state functions of both standards, for a component of the standard
// `magic` names. Safety, for each: as [`with_instance`], and the pointers as the standard's
// function of the same name receives them.

/// fmi2GetFMUstate, fmi3GetFMUState.
///
/// # Safety
/// See above.
unsafe fn get_state(magic: u64, c: fmi2Component, target: *mut fmi2FMUstate) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the caller's contract.
        unsafe { with_state_slot(inst, target, |inst, slot| inst.get_fmu_state(slot)) }
    };
    // SAFETY: the caller's contract.
    unsafe { call_of(magic, c, Function::GetFmuState, body) }
}

/// fmi2SetFMUstate, fmi3SetFMUState.
///
/// # Safety
/// See above.
unsafe fn set_state(magic: u64, c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the caller's contract.
        let saved = unsafe { snapshot(inst, state) }?;
        Ok(inst.set_fmu_state(saved))
    };
    // SAFETY: the caller's contract.
    unsafe { call_of(magic, c, Function::SetFmuState, body) }
}

/// fmi2FreeFMUstate, fmi3FreeFMUState.
///
/// # Safety
/// See above.
unsafe fn release_state(magic: u64, c: fmi2Component, target: *mut fmi2FMUstate) -> fmi2Status {
    // SAFETY: the caller's contract.
    let body = |inst: &mut Instance| unsafe { free_state(inst, target) };
    // SAFETY: the caller's contract.
    unsafe { call_of(magic, c, Function::FreeFmuState, body) }
}

/// fmi2SerializedFMUstateSize, fmi3SerializedFMUStateSize.
///
/// # Safety
/// See above.
unsafe fn serialized_size(
    magic: u64,
    c: fmi2Component,
    state: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the caller's contract.
        let saved = unsafe { snapshot(inst, state) }?;
        // SAFETY: the caller's contract.
        let size = unsafe { out(size, "size") }?;
        Ok(inst.serialized_fmu_state_size(saved, size))
    };
    // SAFETY: the caller's contract.
    unsafe { call_of(magic, c, Function::SerializedFmuStateSize, body) }
}

/// fmi2SerializeFMUstate, fmi3SerializeFMUState.
///
/// # Safety
/// See above.
unsafe fn serialize(
    magic: u64,
    c: fmi2Component,
    state: fmi2FMUstate,
    buffer: *mut u8,
    size: usize,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the caller's contract.
        let saved = unsafe { snapshot(inst, state) }?;
        // SAFETY: the caller's contract.
        let bytes = unsafe { slice_mut(buffer, size, "serializedState") }?;
        Ok(inst.serialize_fmu_state(saved, bytes))
    };
    // SAFETY: the caller's contract.
    unsafe { call_of(magic, c, Function::SerializeFmuState, body) }
}

/// fmi2DeSerializeFMUstate, fmi3DeserializeFMUState.
///
/// # Safety
/// See above.
unsafe fn deserialize(
    magic: u64,
    c: fmi2Component,
    buffer: *const u8,
    size: usize,
    target: *mut fmi2FMUstate,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the caller's contract.
        let bytes = unsafe { slice(buffer, size, "serializedState") }?;
        // SAFETY: the caller's contract.
        unsafe {
            with_state_slot(inst, target, |inst, slot| {
                inst.deserialize_fmu_state(bytes, slot)
            })
        }
    };
    // SAFETY: the caller's contract.
    unsafe { call_of(magic, c, Function::DeSerializeFmuState, body) }
}

/// Directional derivatives of outputs with respect to inputs.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    vUnknown_ref: *const fmi2ValueReference,
    nUnknown: usize,
    vKnown_ref: *const fmi2ValueReference,
    nKnown: usize,
    dvKnown: *const fmi2Real,
    dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes nUnknown value references.
        let unknown = unsafe { slice(vUnknown_ref, nUnknown, "vUnknown_ref[]") }?;
        // SAFETY: the master passes nKnown value references.
        let known = unsafe { slice(vKnown_ref, nKnown, "vKnown_ref[]") }?;
        // SAFETY: the master passes nKnown seed values.
        let seed = unsafe { slice(dvKnown, nKnown, "dvKnown[]") }?;
        // SAFETY: the master passes room for nUnknown values.
        let result = unsafe { slice_mut(dvUnknown, nUnknown, "dvUnknown[]") }?;
        Ok(inst.get_directional_derivative(unknown, known, seed, result))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::GetDirectionalDerivative, body) }
}

// ---------------------------------------------------------------------------------------
// Co-simulation
// ---------------------------------------------------------------------------------------

/// Sets first derivatives of inputs (order 1 only): first-order hold over the next steps.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes nvr value references.
        let vr = unsafe { slice(vr, nvr, "vr[]") }?;
        // SAFETY: the master passes nvr orders.
        let order = unsafe { slice(order, nvr, "order[]") }?;
        // SAFETY: the master passes nvr values.
        let value = unsafe { slice(value, nvr, "value[]") }?;
        Ok(inst.set_real_input_derivatives(vr, order, value))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::SetRealInputDerivatives, body) }
}

/// First derivatives of outputs at the current time.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *mut fmi2Real,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes nvr value references.
        let vr = unsafe { slice(vr, nvr, "vr[]") }?;
        // SAFETY: the master passes nvr orders.
        let order = unsafe { slice(order, nvr, "order[]") }?;
        // SAFETY: the master passes room for nvr values.
        let value = unsafe { slice_mut(value, nvr, "value[]") }?;
        Ok(inst.get_real_output_derivatives(vr, order, value))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::GetRealOutputDerivatives, body) }
}

/// One communication step from `currentCommunicationPoint` (the instance's time) by h > 0.
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    let (t, h) = (currentCommunicationPoint, communicationStepSize);
    let no_set_prior = noSetFMUStatePriorToCurrentPoint != 0;
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { with_instance(c, Function::DoStep, |inst| inst.do_step(t, h, no_set_prior)) }
}

/// Steps are synchronous: there is never a step to cancel.
#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { with_instance(c, Function::CancelStep, Instance::cancel_step) }
}

/// No asynchronous steps: `fmi2Discard`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Status,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes room for one status.
        unsafe { out(value, "value") }?;
        Ok(inst.get_status(s))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::GetStatus, body) }
}

/// `fmi2LastSuccessfulTime`: the instance's time.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes room for one value.
        let value = unsafe { out(value, "value") }?;
        Ok(inst.get_real_status(s, value))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::GetRealStatus, body) }
}

/// No Integer status: `fmi2Discard`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Integer,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes room for one value.
        unsafe { out(value, "value") }?;
        Ok(inst.get_integer_status(s))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::GetIntegerStatus, body) }
}

/// `fmi2Terminated`: false (the FMU never asks to stop).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes room for one value.
        let value = unsafe { out(value, "value") }?;
        Ok(inst.get_boolean_status(s, value))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::GetBooleanStatus, body) }
}

/// No String status: `fmi2Discard`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2String,
) -> fmi2Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the master passes room for one string pointer.
        unsafe { out(value, "value") }?;
        Ok(inst.get_string_status(s))
    };
    // SAFETY: the master passes a component from fmi2Instantiate.
    unsafe { call(c, Function::GetStringStatus, body) }
}

mod fmi3;
pub use fmi3::*;

#[cfg(test)]
mod fmi3_tests;
#[cfg(test)]
mod hostile_tests;
#[cfg(test)]
mod tests;
