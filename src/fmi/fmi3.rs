//! The FMI 3.0 C layer: every function `fmi3FunctionTypes.h` of FMI 3.0.1 declares, over the
//! same [`Instance`] as the FMI 2.0 functions.
//!
//! Co-simulation works as in FMI 2.0 (`fmi3EnterInitializationMode` takes the arguments of
//! `fmi2SetupExperiment`; `fmi3DoStep` never asks for event handling, to terminate, or
//! returns early). The matrices are array variables and `time` is a variable
//! ([`crate::fmu::fmi3`]). The functions of model exchange, scheduled execution, event mode,
//! configuration mode, clocks, adjoint derivatives and variable dependencies exist and
//! refuse with fmi3Error (the model description declares none of them); the instantiation
//! functions of the other interface types return NULL.
//!
//! An instance made by `fmi3InstantiateCoSimulation` carries its own magic number: the
//! FMI 2.0 functions refuse it and the FMI 3.0 functions refuse an FMI 2.0 component.
#![deny(unsafe_op_in_unsafe_fn)]
#![deny(clippy::undocumented_unsafe_blocks)]
#![allow(
    non_camel_case_types,
    non_upper_case_globals,
    non_snake_case,
    clippy::missing_safety_doc
)]

use super::ffi::*;
use super::fmi2::*;
use super::instance::Instance;
use super::logging::{Category, Message};
use super::phase::Function;
use super::types::*;
use std::ffi::{c_char, c_void, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// `fmi3Instance`.
pub type fmi3Instance = *mut c_void;
/// `fmi3InstanceEnvironment`.
pub type fmi3InstanceEnvironment = *mut c_void;
/// `fmi3FMUState`.
pub type fmi3FMUState = *mut c_void;
/// `fmi3ValueReference`.
pub type fmi3ValueReference = u32;
/// `fmi3Float64`.
pub type fmi3Float64 = f64;
/// `fmi3Int32`.
pub type fmi3Int32 = i32;
/// `fmi3Boolean` (C `bool`, one byte; read as a byte so that any value is safe).
pub type fmi3Boolean = u8;
/// `fmi3String`.
pub type fmi3String = *const c_char;
/// `fmi3Byte`.
pub type fmi3Byte = u8;
/// `fmi3Status`.
pub type fmi3Status = std::ffi::c_int;
/// `fmi3OK`.
pub const fmi3OK: fmi3Status = 0;
/// `fmi3Error`.
pub const fmi3Error: fmi3Status = 3;

/// `fmi3LogMessageCallback`.
pub type fmi3LogMessageCallback = unsafe extern "C" fn(
    instanceEnvironment: fmi3InstanceEnvironment,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
);

/// [`call_of`] for an FMI 3.0 instance.
///
/// # Safety
/// `c` is NULL or points to at least 8 readable bytes; an instance of ours is not used by
/// another thread meanwhile.
unsafe fn call3(
    c: fmi3Instance,
    function: Function,
    body: impl FnOnce(&mut Instance) -> Result<Status, String>,
) -> fmi3Status {
    // SAFETY: the caller's contract.
    unsafe { call_of(INSTANCE_MAGIC_FMI3, c, function, body) }
}

/// [`with_instance_of`] for an FMI 3.0 instance.
///
/// # Safety
/// As [`call3`].
unsafe fn with3(
    c: fmi3Instance,
    function: Function,
    body: impl FnOnce(&mut Instance) -> Status,
) -> fmi3Status {
    // SAFETY: the caller's contract.
    unsafe { with_instance_of(INSTANCE_MAGIC_FMI3, c, function, body) }
}

/// A function this FMU does not provide: logged, fmi3Error, the phase stays.
///
/// # Safety
/// As [`call3`].
unsafe fn unsupported(c: fmi3Instance, name: &'static str, why: &'static str) -> fmi3Status {
    // SAFETY: the caller's contract. CancelStep's row allows no phase: it only names a
    // panic, which `unsupported_fmi3` does not raise.
    unsafe {
        with_instance_named(INSTANCE_MAGIC_FMI3, c, Function::CancelStep, name, |inst| {
            inst.unsupported_fmi3(name, why)
        })
    }
}

const NO_MODEL_EXCHANGE: &str =
    "this FMU is for co-simulation only (no model exchange, no continuous states)";
const NO_EVENT_MODE: &str = "this FMU has no event mode (hasEventMode = false)";
const NO_CLOCKS: &str = "this FMU has no clocks";
const NO_CONFIGURATION: &str = "this FMU has no structural parameters (no configuration mode)";

/// An outgoing boolean.
///
/// # Safety
/// As [`out`].
unsafe fn write_bool(ptr: *mut fmi3Boolean, what: &str, value: bool) -> Result<(), String> {
    // SAFETY: the caller's contract.
    *unsafe { out(ptr, what) }? = u8::from(value);
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Inquiry, creation and destruction
// ---------------------------------------------------------------------------------------

/// `"3.0"`.
#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

/// Sets debug logging for all categories (n = 0) or the listed ones.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    let on = loggingOn != 0;
    // SAFETY: the importer passes an instance and nCategories strings.
    unsafe { set_debug_logging(INSTANCE_MAGIC_FMI3, instance, on, nCategories, categories) }
}

/// Logs why an instantiation is refused, to the importer's logger if it gave one.
fn refuse_instantiation(
    logger: Option<fmi3LogMessageCallback>,
    environment: fmi3InstanceEnvironment,
    name: &str,
    text: String,
) -> fmi3Instance {
    let message = Message {
        status: Status::Error,
        category: Category::Error,
        text: format!("{name}: {text}"),
    };
    log_fmi3(logger, environment, &message);
    std::ptr::null_mut()
}

/// Model exchange is not provided: NULL (logged).
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
) -> fmi3Instance {
    let refuse = || {
        let why = NO_MODEL_EXCHANGE.to_string();
        refuse_instantiation(
            logMessage,
            instanceEnvironment,
            "fmi3InstantiateModelExchange",
            why,
        )
    };
    catch_unwind(AssertUnwindSafe(refuse)).unwrap_or(std::ptr::null_mut())
}

/// Creates a co-simulation instance; NULL on any error (logged when possible).
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    _earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    _nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
    _intermediateUpdate: *const c_void,
) -> fmi3Instance {
    let result = catch_unwind(AssertUnwindSafe(|| {
        let logger = Logger::Fmi3 {
            logger: logMessage,
            environment: instanceEnvironment,
        };
        let name = if instanceName.is_null() {
            None
        } else {
            // SAFETY: non-null; the importer passes a NUL-terminated string.
            Some(unsafe { CStr::from_ptr(instanceName) })
        };
        if eventModeUsed != 0 {
            return refuse_instantiation(
                logMessage,
                instanceEnvironment,
                "fmi3InstantiateCoSimulation",
                format!("eventModeUsed = true: {NO_EVENT_MODE}"),
            );
        }
        // SAFETY: the importer passes NUL-terminated strings (or NULL).
        let (token, resources) = unsafe { (text(instantiationToken), text(resourcePath)) };
        match Instance::instantiate_fmi3(name, token, resources, loggingOn != 0) {
            Ok(instance) => {
                let component = Box::into_raw(Box::new(Component {
                    magic: INSTANCE_MAGIC_FMI3,
                    logger,
                    instance,
                }));
                // SAFETY: just made, and nothing borrows it.
                unsafe { flush(component) };
                component as fmi3Instance
            }
            Err(message) => refuse_instantiation(
                logMessage,
                instanceEnvironment,
                "fmi3InstantiateCoSimulation",
                message.to_string(),
            ),
        }
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// Scheduled execution is not provided: NULL (logged).
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
    _clockUpdate: *const c_void,
    _lockPreemption: *const c_void,
    _unlockPreemption: *const c_void,
) -> fmi3Instance {
    let refuse = || {
        let why = "this FMU is for co-simulation only (no scheduled execution)".to_string();
        refuse_instantiation(
            logMessage,
            instanceEnvironment,
            "fmi3InstantiateScheduledExecution",
            why,
        )
    };
    catch_unwind(AssertUnwindSafe(refuse)).unwrap_or(std::ptr::null_mut())
}

/// Frees an instance (allowed in every state; NULL is ignored).
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation (or NULL).
        if let Some(component) = unsafe { component_with_magic(instance, INSTANCE_MAGIC_FMI3) } {
            // SAFETY: a live Component made by Box::into_raw, nothing borrows it; the magic
            // is cleared so that a second free is refused.
            unsafe {
                (*component).magic = 0;
                drop(Box::from_raw(component));
            }
        } else {
            // SAFETY: as above.
            unsafe { refuse_free_of_other_standard(INSTANCE_MAGIC, instance, "fmi3FreeInstance") };
        }
    }));
}

// ---------------------------------------------------------------------------------------
// Life cycle
// ---------------------------------------------------------------------------------------

/// Sets the start time and, if defined, the stop time, and enters initialization mode.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: fmi3Instance,
    toleranceDefined: fmi3Boolean,
    tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    let tolerance = (toleranceDefined != 0).then_some(tolerance);
    let stop = (stopTimeDefined != 0).then_some(stopTime);
    let body =
        |inst: &mut Instance| inst.enter_initialization_mode_fmi3(tolerance, startTime, stop);
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { with3(instance, Function::EnterInitializationMode, body) }
}

/// Leaves initialization mode: Step Mode (no event mode).
#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: fmi3Instance) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe {
        with3(instance, Function::ExitInitializationMode, |inst| {
            inst.exit_initialization_mode()
        })
    }
}

/// No event mode: refused.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterEventMode(instance: fmi3Instance) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3EnterEventMode", NO_EVENT_MODE) }
}

/// Ends the simulation.
#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { with3(instance, Function::Terminate, Instance::terminate) }
}

/// Back to the instantiated state with the start values (also after an error).
#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { with3(instance, Function::Reset, Instance::reset) }
}

// ---------------------------------------------------------------------------------------
// Getting and setting values
// ---------------------------------------------------------------------------------------

/// The body of a typed getter: the value references and room for `n_values` values, then
/// `answer` (the instance's method for the type).
///
/// # Safety
/// As [`call3`]; `vr` and `values` as the importer passes them (the counts given, or NULL).
unsafe fn get_typed<T>(
    instance: fmi3Instance,
    function: Function,
    (vr, n_vr): (*const fmi3ValueReference, usize),
    (values, n_values): (*mut T, usize),
    answer: fn(&mut Instance, &[u32], &mut [T]) -> Status,
) -> fmi3Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the caller's contract.
        let vr = unsafe { slice(vr, n_vr, "valueReferences[]") }?;
        // SAFETY: the caller's contract.
        let values = unsafe { slice_mut(values, n_values, "values[]") }?;
        Ok(answer(inst, vr, values))
    };
    // SAFETY: the caller's contract.
    unsafe { call3(instance, function, body) }
}

/// The body of a typed setter (as [`get_typed`]).
///
/// # Safety
/// As [`get_typed`].
unsafe fn set_typed<T>(
    instance: fmi3Instance,
    function: Function,
    (vr, n_vr): (*const fmi3ValueReference, usize),
    (values, n_values): (*const T, usize),
    answer: fn(&mut Instance, &[u32], &[T]) -> Status,
) -> fmi3Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the caller's contract.
        let vr = unsafe { slice(vr, n_vr, "valueReferences[]") }?;
        // SAFETY: the caller's contract.
        let values = unsafe { slice(values, n_values, "values[]") }?;
        Ok(answer(inst, vr, values))
    };
    // SAFETY: the caller's contract.
    unsafe { call3(instance, function, body) }
}

/// Reads Float64 variables: scalars, `time`, the matrices (row-major).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    let (vr, out) = ((valueReferences, nValueReferences), (values, nValues));
    // SAFETY: the importer passes an instance and arrays of the counts given.
    unsafe { get_typed(instance, Function::GetReal, vr, out, Instance::get_float64) }
}

/// Sets Float64 variables: rho, g and the wave parameters before initialization ends, the
/// inputs any time before termination. All values are checked before any is applied.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    let (vr, new) = ((valueReferences, nValueReferences), (values, nValues));
    // SAFETY: the importer passes an instance and arrays of the counts given.
    unsafe { set_typed(instance, Function::SetReal, vr, new, Instance::set_float64) }
}

/// Reads Int32 variables (the integer wave parameters).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetInt32(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3Int32,
    nValues: usize,
) -> fmi3Status {
    let (vr, out) = ((valueReferences, nValueReferences), (values, nValues));
    // SAFETY: the importer passes an instance and arrays of the counts given.
    unsafe {
        get_typed(
            instance,
            Function::GetInteger,
            vr,
            out,
            Instance::get_integer,
        )
    }
}

/// Sets Int32 variables (the integer wave parameters, before initialization ends).
#[no_mangle]
pub unsafe extern "C" fn fmi3SetInt32(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3Int32,
    nValues: usize,
) -> fmi3Status {
    let (vr, new) = ((valueReferences, nValueReferences), (values, nValues));
    // SAFETY: the importer passes an instance and arrays of the counts given.
    unsafe {
        set_typed(
            instance,
            Function::SetInteger,
            vr,
            new,
            Instance::set_integer,
        )
    }
}

/// The body of the get and set functions of a type this FMU has no variables of.
///
/// # Safety
/// As [`call3`]; `vr` as the importer passes it (n entries, or NULL).
unsafe fn typeless3(
    instance: fmi3Instance,
    name: &'static str,
    like: Function,
    vr: *const fmi3ValueReference,
    n: usize,
) -> fmi3Status {
    let body = |inst: &mut Instance| {
        if let Some(refused) = inst.refuse_outside_phase_as(like, name) {
            return refused;
        }
        // SAFETY: the caller's contract.
        match unsafe { slice(vr, n, "valueReferences[]") } {
            Ok(vr) => inst.no_variables_fmi3(name, like, vr),
            Err(message) => inst.reject_arguments_as(name, &message),
        }
    };
    // SAFETY: the caller's contract.
    unsafe { with_instance_named(INSTANCE_MAGIC_FMI3, instance, like, name, body) }
}

/// Getters and setters of the types without variables: only an empty list succeeds.
macro_rules! typeless_functions {
    ($($name:ident, $like:ident, $value:ty;)*) => {$(
        #[doc = concat!("No variables of this type: only nValueReferences = 0 succeeds (`", stringify!($name), "`).")]
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            _values: $value,
            _nValues: usize,
        ) -> fmi3Status {
            // SAFETY: the importer passes an instance and nValueReferences references.
            unsafe {
                typeless3(instance, stringify!($name), Function::$like, valueReferences, nValueReferences)
            }
        }
    )*};
}

typeless_functions! {
    fmi3GetFloat32, GetBoolean, *mut f32;
    fmi3GetInt8, GetBoolean, *mut i8;
    fmi3GetUInt8, GetBoolean, *mut u8;
    fmi3GetInt16, GetBoolean, *mut i16;
    fmi3GetUInt16, GetBoolean, *mut u16;
    fmi3GetUInt32, GetBoolean, *mut u32;
    fmi3GetInt64, GetBoolean, *mut i64;
    fmi3GetUInt64, GetBoolean, *mut u64;
    fmi3GetBoolean, GetBoolean, *mut fmi3Boolean;
    fmi3GetString, GetString, *mut fmi3String;
    fmi3SetFloat32, SetBoolean, *const f32;
    fmi3SetInt8, SetBoolean, *const i8;
    fmi3SetUInt8, SetBoolean, *const u8;
    fmi3SetInt16, SetBoolean, *const i16;
    fmi3SetUInt16, SetBoolean, *const u16;
    fmi3SetUInt32, SetBoolean, *const u32;
    fmi3SetInt64, SetBoolean, *const i64;
    fmi3SetUInt64, SetBoolean, *const u64;
    fmi3SetBoolean, SetBoolean, *const fmi3Boolean;
    fmi3SetString, SetString, *const fmi3String;
}

/// No Binary variables: only nValueReferences = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _valueSizes: *mut usize,
    _values: *mut *const fmi3Byte,
    _nValues: usize,
) -> fmi3Status {
    let (name, like) = ("fmi3GetBinary", Function::GetBoolean);
    // SAFETY: the importer passes an instance and nValueReferences references.
    unsafe { typeless3(instance, name, like, valueReferences, nValueReferences) }
}

/// No Binary variables: only nValueReferences = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _valueSizes: *const usize,
    _values: *const *const fmi3Byte,
    _nValues: usize,
) -> fmi3Status {
    let (name, like) = ("fmi3SetBinary", Function::SetBoolean);
    // SAFETY: the importer passes an instance and nValueReferences references.
    unsafe { typeless3(instance, name, like, valueReferences, nValueReferences) }
}

/// No clocks: refused.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetClock(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _values: *mut fmi3Boolean,
) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3GetClock", NO_CLOCKS) }
}

/// No clocks: refused.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetClock(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _values: *const fmi3Boolean,
) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3SetClock", NO_CLOCKS) }
}

// ---------------------------------------------------------------------------------------
// Variable dependencies
// ---------------------------------------------------------------------------------------

/// Not provided (the model description's `<ModelStructure>` lists the dependencies).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(
    instance: fmi3Instance,
    _valueReference: fmi3ValueReference,
    _nDependencies: *mut usize,
) -> fmi3Status {
    let why = "not provided: the dependencies are in the model description's ModelStructure";
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3GetNumberOfVariableDependencies", why) }
}

/// Not provided (the model description's `<ModelStructure>` lists the dependencies).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetVariableDependencies(
    instance: fmi3Instance,
    _dependent: fmi3ValueReference,
    _elementIndicesOfDependent: *mut usize,
    _independents: *mut fmi3ValueReference,
    _elementIndicesOfIndependents: *mut usize,
    _dependencyKinds: *mut std::ffi::c_int,
    _nDependencies: usize,
) -> fmi3Status {
    let why = "not provided: the dependencies are in the model description's ModelStructure";
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3GetVariableDependencies", why) }
}

// ---------------------------------------------------------------------------------------
// FMU state (the same snapshots as FMI 2.0)
// ---------------------------------------------------------------------------------------

/// Saves the state (into a new snapshot, or overwrites `*FMUState` if not NULL).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: the importer passes an instance and an fmi3FMUState* holding NULL or a state.
    unsafe { get_state(INSTANCE_MAGIC_FMI3, instance, FMUState) }
}

/// Restores a saved state, including its phase (this also leaves the error state).
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    // SAFETY: the importer passes an instance and a state of this FMU.
    unsafe { set_state(INSTANCE_MAGIC_FMI3, instance, FMUState) }
}

/// Frees a saved state and sets `*FMUState` to NULL (NULL `*FMUState` is a no-op).
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: the importer passes an instance and an fmi3FMUState* holding NULL or a state.
    unsafe { release_state(INSTANCE_MAGIC_FMI3, instance, FMUState) }
}

/// Size of the serialized state.
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    // SAFETY: the importer passes an instance, a state of this FMU and room for the size.
    unsafe { serialized_size(INSTANCE_MAGIC_FMI3, instance, FMUState, size) }
}

/// Writes the serialized state (`size` must be exactly the serialized size).
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    // SAFETY: the importer passes an instance, a state of this FMU and room for `size` bytes.
    unsafe {
        serialize(
            INSTANCE_MAGIC_FMI3,
            instance,
            FMUState,
            serializedState,
            size,
        )
    }
}

/// Reads a serialized state into a new (or the given) snapshot; corrupt or foreign bytes
/// are refused.
#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: usize,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: the importer passes an instance, `size` bytes and an fmi3FMUState* holding
    // NULL or a state of this FMU.
    unsafe {
        deserialize(
            INSTANCE_MAGIC_FMI3,
            instance,
            serializedState,
            size,
            FMUState,
        )
    }
}

// ---------------------------------------------------------------------------------------
// Derivatives
// ---------------------------------------------------------------------------------------

/// Directional derivatives of outputs with respect to inputs: `sensitivity = J seed`.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
    instance: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    nUnknowns: usize,
    knowns: *const fmi3ValueReference,
    nKnowns: usize,
    seed: *const fmi3Float64,
    nSeed: usize,
    sensitivity: *mut fmi3Float64,
    nSensitivity: usize,
) -> fmi3Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the importer passes nUnknowns value references.
        let unknowns = unsafe { slice(unknowns, nUnknowns, "unknowns[]") }?;
        // SAFETY: the importer passes nKnowns value references.
        let knowns = unsafe { slice(knowns, nKnowns, "knowns[]") }?;
        // SAFETY: the importer passes nSeed values.
        let seed = unsafe { slice(seed, nSeed, "seed[]") }?;
        // SAFETY: the importer passes room for nSensitivity values.
        let result = unsafe { slice_mut(sensitivity, nSensitivity, "sensitivity[]") }?;
        Ok(inst.get_directional_derivative_fmi3(unknowns, knowns, seed, result))
    };
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { call3(instance, Function::GetDirectionalDerivative, body) }
}

/// Not provided (providesAdjointDerivatives = false).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetAdjointDerivative(
    instance: fmi3Instance,
    _unknowns: *const fmi3ValueReference,
    _nUnknowns: usize,
    _knowns: *const fmi3ValueReference,
    _nKnowns: usize,
    _seed: *const fmi3Float64,
    _nSeed: usize,
    _sensitivity: *mut fmi3Float64,
    _nSensitivity: usize,
) -> fmi3Status {
    let why = "not provided (providesAdjointDerivatives = false); use fmi3GetDirectionalDerivative";
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3GetAdjointDerivative", why) }
}

// ---------------------------------------------------------------------------------------
// Configuration mode, clocks, discrete states: not declared
// ---------------------------------------------------------------------------------------

/// No structural parameters: refused.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterConfigurationMode(instance: fmi3Instance) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3EnterConfigurationMode", NO_CONFIGURATION) }
}

/// No structural parameters: refused.
#[no_mangle]
pub unsafe extern "C" fn fmi3ExitConfigurationMode(instance: fmi3Instance) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3ExitConfigurationMode", NO_CONFIGURATION) }
}

/// Clock functions: refused (this FMU has no clocks).
macro_rules! clock_functions {
    ($($name:ident($($arg:ident: $ty:ty),*);)*) => {$(
        #[doc = concat!("No clocks: refused (`", stringify!($name), "`).")]
        #[no_mangle]
        pub unsafe extern "C" fn $name(instance: fmi3Instance, $($arg: $ty),*) -> fmi3Status {
            $(let _ = $arg;)*
            // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
            unsafe { unsupported(instance, stringify!($name), NO_CLOCKS) }
        }
    )*};
}

clock_functions! {
    fmi3GetIntervalDecimal(vr: *const fmi3ValueReference, n: usize, intervals: *mut f64, qualifiers: *mut std::ffi::c_int);
    fmi3GetIntervalFraction(vr: *const fmi3ValueReference, n: usize, counters: *mut u64, resolutions: *mut u64, qualifiers: *mut std::ffi::c_int);
    fmi3GetShiftDecimal(vr: *const fmi3ValueReference, n: usize, shifts: *mut f64);
    fmi3GetShiftFraction(vr: *const fmi3ValueReference, n: usize, counters: *mut u64, resolutions: *mut u64);
    fmi3SetIntervalDecimal(vr: *const fmi3ValueReference, n: usize, intervals: *const f64);
    fmi3SetIntervalFraction(vr: *const fmi3ValueReference, n: usize, counters: *const u64, resolutions: *const u64);
    fmi3SetShiftDecimal(vr: *const fmi3ValueReference, n: usize, shifts: *const f64);
    fmi3SetShiftFraction(vr: *const fmi3ValueReference, n: usize, counters: *const u64, resolutions: *const u64);
    fmi3ActivateModelPartition(clockReference: fmi3ValueReference, activationTime: f64);
}

/// No discrete states to evaluate: refused (event mode only).
#[no_mangle]
pub unsafe extern "C" fn fmi3EvaluateDiscreteStates(instance: fmi3Instance) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3EvaluateDiscreteStates", NO_EVENT_MODE) }
}

/// No event mode: refused.
#[no_mangle]
pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
    instance: fmi3Instance,
    _discreteStatesNeedUpdate: *mut fmi3Boolean,
    _terminateSimulation: *mut fmi3Boolean,
    _nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
    _valuesOfContinuousStatesChanged: *mut fmi3Boolean,
    _nextEventTimeDefined: *mut fmi3Boolean,
    _nextEventTime: *mut fmi3Float64,
) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3UpdateDiscreteStates", NO_EVENT_MODE) }
}

// ---------------------------------------------------------------------------------------
// Model exchange: not provided
// ---------------------------------------------------------------------------------------

/// Model exchange functions: refused (no instance of that type exists).
macro_rules! model_exchange_functions {
    ($($name:ident($($arg:ident: $ty:ty),*);)*) => {$(
        #[doc = concat!("Model exchange only: refused (`", stringify!($name), "`).")]
        #[no_mangle]
        pub unsafe extern "C" fn $name(instance: fmi3Instance, $($arg: $ty),*) -> fmi3Status {
            $(let _ = $arg;)*
            // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
            unsafe { unsupported(instance, stringify!($name), NO_MODEL_EXCHANGE) }
        }
    )*};
}

model_exchange_functions! {
    fmi3EnterContinuousTimeMode();
    fmi3CompletedIntegratorStep(noSetFMUStatePriorToCurrentPoint: fmi3Boolean, enterEventMode: *mut fmi3Boolean, terminateSimulation: *mut fmi3Boolean);
    fmi3SetTime(time: f64);
    fmi3SetContinuousStates(continuousStates: *const f64, nContinuousStates: usize);
    fmi3GetContinuousStateDerivatives(derivatives: *mut f64, nContinuousStates: usize);
    fmi3GetEventIndicators(eventIndicators: *mut f64, nEventIndicators: usize);
    fmi3GetContinuousStates(continuousStates: *mut f64, nContinuousStates: usize);
    fmi3GetNominalsOfContinuousStates(nominals: *mut f64, nContinuousStates: usize);
    fmi3GetNumberOfEventIndicators(nEventIndicators: *mut usize);
    fmi3GetNumberOfContinuousStates(nContinuousStates: *mut usize);
}

// ---------------------------------------------------------------------------------------
// Co-simulation
// ---------------------------------------------------------------------------------------

/// Step Mode is entered from event mode only, which this FMU does not have: refused.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterStepMode(instance: fmi3Instance) -> fmi3Status {
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { unsupported(instance, "fmi3EnterStepMode", NO_EVENT_MODE) }
}

/// First derivatives of outputs at the current time (order 1).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetOutputDerivatives(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    orders: *const fmi3Int32,
    values: *mut fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    let body = |inst: &mut Instance| {
        // SAFETY: the importer passes nValueReferences value references.
        let vr = unsafe { slice(valueReferences, nValueReferences, "valueReferences[]") }?;
        // SAFETY: the importer passes nValueReferences orders.
        let orders = unsafe { slice(orders, nValueReferences, "orders[]") }?;
        // SAFETY: the importer passes room for nValues values.
        let values = unsafe { slice_mut(values, nValues, "values[]") }?;
        Ok(inst.get_output_derivatives(vr, orders, values))
    };
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { call3(instance, Function::GetRealOutputDerivatives, body) }
}

/// One communication step from `currentCommunicationPoint` (the instance's time) by h > 0;
/// never asks for event handling or to terminate, never returns early.
#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    instance: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    let (t, h) = (currentCommunicationPoint, communicationStepSize);
    let no_set_prior = noSetFMUStatePriorToCurrentPoint != 0;
    let body = |inst: &mut Instance| {
        // The outputs are checked before the step: a step with bad pointers does not move.
        check_array(eventHandlingNeeded.cast_const(), 1, "eventHandlingNeeded")?;
        check_array(terminateSimulation.cast_const(), 1, "terminateSimulation")?;
        check_array(earlyReturn.cast_const(), 1, "earlyReturn")?;
        check_array(lastSuccessfulTime.cast_const(), 1, "lastSuccessfulTime")?;
        let status = inst.do_step(t, h, no_set_prior);
        // SAFETY: checked above; the importer passes room for one value each.
        unsafe {
            write_bool(eventHandlingNeeded, "eventHandlingNeeded", false)?;
            write_bool(terminateSimulation, "terminateSimulation", false)?;
            write_bool(earlyReturn, "earlyReturn", false)?;
            *out(lastSuccessfulTime, "lastSuccessfulTime")? = inst.time();
        }
        Ok(status)
    };
    // SAFETY: the importer passes an instance from fmi3InstantiateCoSimulation.
    unsafe { call3(instance, Function::DoStep, body) }
}
