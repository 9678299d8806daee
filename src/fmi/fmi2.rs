//! The FMI 2.0 C layer: the exported `fmi2...` functions, thin wrappers that check their
//! pointers through [`super::ffi`] and call the safe [`Instance`].
#![deny(unsafe_op_in_unsafe_fn)]
#![deny(clippy::undocumented_unsafe_blocks)]
// FMI names; the contract of every exported function is the FMI 2.0 standard's.
#![allow(non_snake_case, clippy::missing_safety_doc)]

use super::ffi::*;
use super::instance::Instance;
use super::logging::{Category, Message};
use super::phase::{Function, Standard};
use super::types::*;
use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

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
pub(super) unsafe fn refuse_free_of_other_standard(other: u64, c: fmi2Component, called: &str) {
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
pub(super) unsafe fn set_debug_logging(
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
pub(super) unsafe fn typeless<T>(
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
