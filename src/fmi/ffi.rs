//! What both C layers share: the component and FMU state behind the opaque pointers, their
//! magic numbers, the pointer checks, the panic guard and the forwarding of log messages.
//!
//! Each helper checks the pointers it is given (NULL, alignment, length, and the magic
//! number of a component or FMU state, so that a foreign or freed one is refused), turns
//! them into references, slices and strings, catches panics, and calls the safe
//! [`Instance`]. A call's log messages reach the master's logger after the call, when no
//! reference into the instance is alive (a logger may call back into the FMU).
//!
//! Pointer arguments are read only once the phase allows the call, so a call in the wrong
//! phase is refused whatever its pointers are.
#![deny(unsafe_op_in_unsafe_fn)]
#![deny(clippy::undocumented_unsafe_blocks)]
#![allow(non_snake_case)]

use super::fmi3::{fmi3InstanceEnvironment, fmi3LogMessageCallback};
use super::instance::{Instance, Snapshot};
use super::logging::Message;
use super::phase::{Function, Standard};
use super::types::*;
use std::ffi::{CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr::addr_of;

pub(super) const INSTANCE_MAGIC: u64 = 0x6879_6472_6f66_6d75; // "hydrofmu"
/// An instance made by fmi3InstantiateCoSimulation: fmi2 functions refuse it, and back.
pub(super) const INSTANCE_MAGIC_FMI3: u64 = 0x6879_6472_6f66_6d33; // "hydrofm3"
pub(super) const SNAPSHOT_MAGIC: u64 = 0x6879_6472_6f73_6e70; // "hydrosnp"

/// What an `fmi2Component` points to. `repr(C)` with the magic number first: checking a
/// pointer reads only its first 8 bytes.
#[repr(C)]
pub(super) struct Component {
    pub(super) magic: u64,
    pub(super) logger: Logger,
    pub(super) instance: Instance,
}

/// What an `fmi2FMUstate` points to (same layout rule as [`Component`]).
#[repr(C)]
pub(super) struct StoredState {
    pub(super) magic: u64,
    pub(super) snapshot: Option<Snapshot>,
}

/// The copied callbacks.
#[derive(Clone, Copy)]
pub(super) enum Logger {
    /// fmi2CallbackLogger: a printf-like format.
    Fmi2 {
        logger: Option<fmi2CallbackLogger>,
        environment: fmi2ComponentEnvironment,
    },
    /// fmi3LogMessageCallback: plain text, no instance name.
    Fmi3 {
        logger: Option<fmi3LogMessageCallback>,
        environment: fmi3InstanceEnvironment,
    },
}

impl Logger {
    pub(super) fn log(&self, instance_name: &CStr, message: &Message) {
        let (logger, environment) = match *self {
            Logger::Fmi2 {
                logger,
                environment,
            } => (logger, environment),
            Logger::Fmi3 {
                logger,
                environment,
            } => {
                log_fmi3(logger, environment, message);
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
pub(super) unsafe fn component_from(c: fmi2Component) -> Option<*mut Component> {
    // SAFETY: the caller's contract.
    unsafe { component_with_magic(c, INSTANCE_MAGIC) }
}

/// The component behind `c`, if it is one of ours made through the standard `magic` names.
///
/// # Safety
/// As [`component_from`].
pub(super) unsafe fn component_with_magic(c: fmi2Component, magic: u64) -> Option<*mut Component> {
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
pub(super) unsafe fn with_instance(
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
pub(super) unsafe fn with_instance_of(
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
pub(super) fn standard_of(magic: u64) -> Standard {
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
pub(super) unsafe fn with_instance_named(
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
pub(super) unsafe fn flush(component: *mut Component) {
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
pub(super) unsafe fn call(
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
pub(super) unsafe fn call_of(
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
pub(super) fn check_array<T>(ptr: *const T, n: usize, what: &str) -> Result<(), String> {
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
pub(super) unsafe fn slice<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
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
pub(super) unsafe fn slice_mut<'a, T>(
    ptr: *mut T,
    n: usize,
    what: &str,
) -> Result<&'a mut [T], String> {
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
pub(super) unsafe fn out<'a, T>(ptr: *mut T, what: &str) -> Result<&'a mut T, String> {
    // SAFETY: the caller's contract.
    let one = unsafe { slice_mut(ptr, 1, what) }?;
    Ok(&mut one[0])
}

/// A UTF-8 string (`None` for NULL or not UTF-8).
///
/// # Safety
/// Unless NULL, `ptr` is a NUL-terminated string, unchanged during the call.
pub(super) unsafe fn text<'a>(ptr: fmi2String) -> Option<&'a str> {
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
pub(super) unsafe fn stored_state(
    inst: &Instance,
    state: fmi2FMUstate,
) -> Result<*mut StoredState, String> {
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
pub(super) unsafe fn snapshot<'a>(
    inst: &Instance,
    state: fmi2FMUstate,
) -> Result<&'a Snapshot, String> {
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
pub(super) unsafe fn with_state_slot(
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
pub(super) unsafe fn free_state(
    inst: &mut Instance,
    FMUstate: *mut fmi2FMUstate,
) -> Result<Status, String> {
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

/// Passes one message to an FMI 3.0 logger (plain text, no format).
pub(super) fn log_fmi3(
    logger: Option<fmi3LogMessageCallback>,
    environment: fmi3InstanceEnvironment,
    message: &Message,
) {
    let Some(logger) = logger else { return };
    let Ok(text) = CString::new(message.text.replace('\0', " ")) else {
        return;
    };
    let Ok(category) = CString::new(message.category.name()) else {
        return;
    };
    // SAFETY: the importer gave this logger for this purpose; the strings are valid and
    // NUL-terminated for the duration of the call.
    unsafe {
        logger(
            environment,
            message.status.code(),
            category.as_ptr(),
            text.as_ptr(),
        )
    };
}

// The bodies of the FMU state functions of both standards, for a component of the standard
// `magic` names. Safety, for each: as [`with_instance`], and the pointers as the standard's
// function of the same name receives them.

/// fmi2GetFMUstate, fmi3GetFMUState.
///
/// # Safety
/// See above.
pub(super) unsafe fn get_state(
    magic: u64,
    c: fmi2Component,
    target: *mut fmi2FMUstate,
) -> fmi2Status {
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
pub(super) unsafe fn set_state(magic: u64, c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
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
pub(super) unsafe fn release_state(
    magic: u64,
    c: fmi2Component,
    target: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    let body = |inst: &mut Instance| unsafe { free_state(inst, target) };
    // SAFETY: the caller's contract.
    unsafe { call_of(magic, c, Function::FreeFmuState, body) }
}

/// fmi2SerializedFMUstateSize, fmi3SerializedFMUStateSize.
///
/// # Safety
/// See above.
pub(super) unsafe fn serialized_size(
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
pub(super) unsafe fn serialize(
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
pub(super) unsafe fn deserialize(
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
