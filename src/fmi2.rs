//! The FMI 2.0 co-simulation C ABI: the only module with `unsafe` code.
//!
//! All 34 common and co-simulation functions are exported unprefixed (`fmi2Instantiate`,
//! `fmi2DoStep`, ...). An `fmi2Component` is a boxed [`Instance`]; there is no global
//! state. The model ([`crate::model`]) never sees FMI types.
//!
//! # Phases (FMI 2.0, section 4.2.4)
//! instantiated -> initialization mode -> step complete -> terminated, plus error and fatal.
//! A call not allowed in the current phase returns `fmi2Error`, logs why, and leaves the
//! phase alone. A call that is allowed but fails (bad pointer, unknown value reference,
//! NaN or infinite input, h <= 0, a communication point that is not the instance's time,
//! corrupt state bytes, ...) returns `fmi2Error`, leaves the model state unchanged and moves
//! the instance to the error phase, as the standard says; `fmi2Reset` or `fmi2SetFMUstate`
//! make it usable again. A panic (a bug) is caught and gives `fmi2Fatal`.
//!
//! # Resources and GUID
//! `fmuResourceLocation` is a `file:` URI (`file:///p`, `file:/p`, `file://localhost/p`,
//! percent-encoded, trailing slash optional). The GUID given by the master must equal the
//! GUID derived from the resources ([`crate::model::Resources::guid`]).
//!
//! # Logging
//! The callbacks are copied at instantiation; a NULL logger is tolerated. Messages are
//! passed as the logger's format string with `%` escaped as `%%`. Errors are always
//! logged (category `logStatusError`); warnings, events and calls only when debug logging
//! is on for their category (`fmi2SetDebugLogging`; `loggingOn` at instantiation turns all
//! on). Nothing is logged per step unless `logCalls` is on.
//!
//! # Input and output derivatives
//! `fmi2SetRealInputDerivatives` (order 1) ramps the input over the following steps
//! (first-order hold; the derivative stays set until changed). `fmi2GetRealOutputDerivatives`
//! gives order 1. `fmi2GetDirectionalDerivative`: d force / d velocity = -damping_direct,
//! d force / d acceleration = -added_mass_inf (when present), and those of power and energy.
//!
//! # Safety
//! Every exported function is `unsafe extern "C"`: the caller (an FMI master) must pass
//! pointers as FMI 2.0 specifies. Each function checks its pointers for NULL (and
//! alignment) before use, checks that the component carries this module's magic number,
//! and catches panics.
#![allow(unsafe_code)]
#![allow(
    non_camel_case_types,
    non_snake_case,
    non_upper_case_globals,
    clippy::missing_safety_doc
)]

use crate::model::{Model, ModelState, Resources};
use crate::model_description::{LOG_CATEGORIES, MAX_OUTPUT_DERIVATIVE_ORDER};
use crate::variables::{DofUnit, Layout, Quantity};
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::os::unix::ffi::OsStringExt;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

/// `fmi2Component`.
pub type fmi2Component = *mut c_void;
/// `fmi2ComponentEnvironment`.
pub type fmi2ComponentEnvironment = *mut c_void;
/// `fmi2FMUstate`.
pub type fmi2FMUstate = *mut c_void;
/// `fmi2ValueReference`.
pub type fmi2ValueReference = c_uint;
/// `fmi2Real`.
pub type fmi2Real = f64;
/// `fmi2Integer`.
pub type fmi2Integer = c_int;
/// `fmi2Boolean`.
pub type fmi2Boolean = c_int;
/// `fmi2Char`.
pub type fmi2Char = c_char;
/// `fmi2String`.
pub type fmi2String = *const fmi2Char;
/// `fmi2Byte`.
pub type fmi2Byte = c_char;
/// `fmi2Status`.
pub type fmi2Status = c_int;
/// `fmi2Type`.
pub type fmi2Type = c_int;
/// `fmi2StatusKind`.
pub type fmi2StatusKind = c_int;

/// `fmi2OK`.
pub const fmi2OK: fmi2Status = 0;
/// `fmi2Warning`.
pub const fmi2Warning: fmi2Status = 1;
/// `fmi2Discard`.
pub const fmi2Discard: fmi2Status = 2;
/// `fmi2Error`.
pub const fmi2Error: fmi2Status = 3;
/// `fmi2Fatal`.
pub const fmi2Fatal: fmi2Status = 4;
/// `fmi2ModelExchange`.
pub const fmi2ModelExchange: fmi2Type = 0;
/// `fmi2CoSimulation`.
pub const fmi2CoSimulation: fmi2Type = 1;
/// `fmi2DoStepStatus`.
pub const fmi2DoStepStatus: fmi2StatusKind = 0;
/// `fmi2PendingStatus`.
pub const fmi2PendingStatus: fmi2StatusKind = 1;
/// `fmi2LastSuccessfulTime`.
pub const fmi2LastSuccessfulTime: fmi2StatusKind = 2;
/// `fmi2Terminated`.
pub const fmi2Terminated: fmi2StatusKind = 3;

/// The logger: printf-like, `message` is the format.
pub type fmi2CallbackLogger = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    ...
);

/// `fmi2CallbackFunctions`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct fmi2CallbackFunctions {
    /// Logger (may be NULL: then nothing is logged).
    pub logger: Option<fmi2CallbackLogger>,
    /// Unused (canNotUseMemoryManagementFunctions).
    pub allocateMemory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// Unused.
    pub freeMemory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// Unused (no asynchronous steps).
    pub stepFinished: Option<unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status)>,
    /// Passed back to the logger.
    pub componentEnvironment: fmi2ComponentEnvironment,
}

const INSTANCE_MAGIC: u64 = 0x6879_6472_6f66_6d75; // "hydrofmu"
const SNAPSHOT_MAGIC: u64 = 0x6879_6472_6f73_6e70; // "hydrosnp"

/// Phase of an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Phase {
    /// After fmi2Instantiate or fmi2Reset.
    Instantiated = 0,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode = 1,
    /// Initialized; ready for fmi2DoStep.
    StepComplete = 2,
    /// After fmi2Terminate.
    Terminated = 3,
    /// After a failed call; fmi2Reset or fmi2SetFMUstate recover.
    Error = 4,
    /// After a caught panic; only fmi2FreeInstance.
    Fatal = 5,
}

impl Phase {
    fn from_tag(tag: u8) -> Option<Phase> {
        Some(match tag {
            0 => Phase::Instantiated,
            1 => Phase::InitializationMode,
            2 => Phase::StepComplete,
            3 => Phase::Terminated,
            4 => Phase::Error,
            _ => return None,
        })
    }

    fn bit(self) -> u8 {
        1 << (self as u8)
    }
}

const INSTANTIATED: u8 = 1 << 0;
const INIT_MODE: u8 = 1 << 1;
const STEP_COMPLETE: u8 = 1 << 2;
const TERMINATED: u8 = 1 << 3;
const ERROR: u8 = 1 << 4;
const NOT_FATAL: u8 = INSTANTIATED | INIT_MODE | STEP_COMPLETE | TERMINATED | ERROR;
const READABLE: u8 = INIT_MODE | STEP_COMPLETE | TERMINATED | ERROR;
const SETTABLE: u8 = INSTANTIATED | INIT_MODE | STEP_COMPLETE;

#[derive(Clone, Copy)]
enum Category {
    Warning,
    Error,
    Fatal,
    Events,
    Calls,
}

impl Category {
    fn name(self) -> &'static str {
        match self {
            Category::Warning => "logStatusWarning",
            Category::Error => "logStatusError",
            Category::Fatal => "logStatusFatal",
            Category::Events => "logEvents",
            Category::Calls => "logCalls",
        }
    }
}

/// The copied callbacks.
#[derive(Clone, Copy)]
struct Logger {
    logger: Option<fmi2CallbackLogger>,
    environment: fmi2ComponentEnvironment,
}

impl Logger {
    fn log(&self, instance_name: &CStr, status: fmi2Status, category: Category, message: &str) {
        let Some(logger) = self.logger else { return };
        let escaped = message.replace('%', "%%").replace('\0', " ");
        let Ok(text) = CString::new(escaped) else {
            return;
        };
        let Ok(category) = CString::new(category.name()) else {
            return;
        };
        // SAFETY: the master gave this logger for this purpose; all strings are valid,
        // NUL-terminated, and the format has no conversions left (every % is doubled).
        unsafe {
            logger(
                self.environment,
                instance_name.as_ptr(),
                status,
                category.as_ptr(),
                text.as_ptr(),
            )
        };
    }
}

/// One FMU instance (the `fmi2Component`).
pub struct Instance {
    magic: u64,
    name: CString,
    logger: Logger,
    logging_on: bool,
    categories: Vec<bool>,
    phase: Phase,
    model: Model,
    layout: Layout,
}

/// A saved FMU state (the `fmi2FMUstate`).
struct Snapshot {
    magic: u64,
    guid: String,
    phase: Phase,
    state: ModelState,
}

impl Instance {
    fn enabled(&self, category: Category) -> bool {
        match category {
            Category::Error | Category::Fatal => true,
            _ => {
                self.logging_on
                    && LOG_CATEGORIES
                        .iter()
                        .position(|(c, _)| *c == category.name())
                        .is_some_and(|i| self.categories[i])
            }
        }
    }

    fn log(&self, status: fmi2Status, category: Category, message: &str) {
        if self.enabled(category) {
            self.logger.log(&self.name, status, category, message);
        }
    }

    fn quantity(&self, vr: fmi2ValueReference) -> Result<Quantity, String> {
        self.layout
            .quantity(vr)
            .ok_or_else(|| format!("unknown value reference {vr}"))
    }

    fn variable_name(&self, vr: fmi2ValueReference) -> String {
        self.layout
            .variable(vr)
            .map(|v| v.name.clone())
            .unwrap_or_else(|| format!("#{vr}"))
    }
}

/// Runs `body` on the instance behind `c` if `c` is valid and the phase is allowed;
/// logs failures and catches panics.
unsafe fn call(
    c: fmi2Component,
    function: &str,
    allowed: u8,
    body: impl FnOnce(&mut Instance) -> Result<fmi2Status, String>,
) -> fmi2Status {
    let Some(instance) = instance_from(c) else {
        return fmi2Error;
    };
    let result = catch_unwind(AssertUnwindSafe(|| {
        let instance = &mut *instance;
        if instance.phase.bit() & allowed == 0 {
            instance.log(
                fmi2Error,
                Category::Error,
                &format!(
                    "{function}: not allowed in phase {:?} (call refused)",
                    instance.phase
                ),
            );
            return fmi2Error;
        }
        if instance.enabled(Category::Calls) {
            instance.log(fmi2OK, Category::Calls, function);
        }
        match body(instance) {
            Ok(status) => status,
            Err(message) => {
                instance.log(
                    fmi2Error,
                    Category::Error,
                    &format!("{function}: {message}"),
                );
                instance.phase = Phase::Error;
                fmi2Error
            }
        }
    }));
    result.unwrap_or_else(|_| {
        let instance = &mut *instance;
        instance.phase = Phase::Fatal;
        instance.log(
            fmi2Fatal,
            Category::Fatal,
            &format!("{function}: internal error (panic); the instance can only be freed"),
        );
        fmi2Fatal
    })
}

/// The instance behind a component pointer, if it is one of ours.
unsafe fn instance_from(c: fmi2Component) -> Option<*mut Instance> {
    if c.is_null() || (c as usize) % std::mem::align_of::<Instance>() != 0 {
        return None;
    }
    let instance = c as *mut Instance;
    if (*instance).magic != INSTANCE_MAGIC {
        return None;
    }
    Some(instance)
}

/// A slice from a C array; NULL is accepted only for n = 0.
unsafe fn slice<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(format!("{what} is NULL with {n} entries"));
    }
    let fits =
        matches!(n.checked_mul(std::mem::size_of::<T>()), Some(b) if b <= isize::MAX as usize);
    if (ptr as usize) % std::mem::align_of::<T>() != 0 || !fits {
        return Err(format!("{what} is misaligned or too long"));
    }
    Ok(std::slice::from_raw_parts(ptr, n))
}

unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize, what: &str) -> Result<&'a mut [T], String> {
    slice(ptr as *const T, n, what)?;
    if n == 0 {
        return Ok(&mut []);
    }
    Ok(std::slice::from_raw_parts_mut(ptr, n))
}

unsafe fn text<'a>(ptr: fmi2String) -> Option<&'a str> {
    if ptr.is_null() {
        None
    } else {
        CStr::from_ptr(ptr).to_str().ok()
    }
}

/// The directory a `file:` URI names (module docs).
pub fn resource_path(uri: &str) -> Result<PathBuf, String> {
    let rest = if let Some(r) = uri.strip_prefix("file://localhost/") {
        format!("/{r}")
    } else if let Some(r) = uri.strip_prefix("file:///") {
        format!("/{r}")
    } else if uri.starts_with("file://") {
        return Err(format!(
            "resource location '{uri}' names a remote host (only local file: URIs)"
        ));
    } else if let Some(r) = uri.strip_prefix("file:/") {
        format!("/{r}")
    } else {
        return Err(format!(
            "resource location '{uri}' is not a file: URI (file:///path/to/resources)"
        ));
    };
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("resource location '{uri}': bad percent escape"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    if out.contains(&0) {
        return Err(format!("resource location '{uri}' contains NUL"));
    }
    Ok(PathBuf::from(std::ffi::OsString::from_vec(out)))
}

fn new_instance(
    name: &CStr,
    guid: Option<&str>,
    location: Option<&str>,
    logger: Logger,
    logging_on: bool,
) -> Result<Box<Instance>, String> {
    let location = location.ok_or("fmuResourceLocation is NULL or not UTF-8")?;
    let dir = resource_path(location)?;
    let resources = Resources::read(&dir).map_err(|e| e.to_string())?;
    let expected = resources.guid();
    let guid = guid.ok_or("fmuGUID is NULL or not UTF-8")?;
    if guid != expected {
        return Err(format!(
            "GUID {guid} does not match the resources in {} (GUID {expected})",
            dir.display()
        ));
    }
    let model = Model::from_resources(&resources).map_err(|e| e.to_string())?;
    let dofs = model
        .dof_names()
        .iter()
        .map(|n| DofUnit::new(n, 0, false))
        .collect();
    let layout = Layout::new(dofs, resources.keep_inf_mass).map_err(|e| e.to_string())?;
    Ok(Box::new(Instance {
        magic: INSTANCE_MAGIC,
        name: name.to_owned(),
        logger,
        logging_on,
        categories: vec![true; LOG_CATEGORIES.len()],
        phase: Phase::Instantiated,
        model,
        layout,
    }))
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
        let callbacks = *functions;
        let logger = Logger {
            logger: callbacks.logger,
            environment: callbacks.componentEnvironment,
        };
        let unnamed = c"(unnamed)";
        let name = if instanceName.is_null() {
            unnamed
        } else {
            CStr::from_ptr(instanceName)
        };
        let fail = |message: &str| {
            logger.log(
                name,
                fmi2Error,
                Category::Error,
                &format!("fmi2Instantiate: {message}"),
            );
            std::ptr::null_mut()
        };
        if instanceName.is_null() || name.to_bytes().is_empty() {
            return fail("instanceName is NULL or empty");
        }
        if fmuType != fmi2CoSimulation {
            return fail(&format!(
                "fmuType {fmuType}: this FMU supports co-simulation only"
            ));
        }
        match new_instance(
            name,
            text(fmuGUID),
            text(fmuResourceLocation),
            logger,
            loggingOn != 0,
        ) {
            Ok(instance) => {
                instance.log(
                    fmi2OK,
                    Category::Events,
                    &format!(
                        "fmi2Instantiate: {} DOFs ({}), {} network states",
                        instance.model.dof_count(),
                        instance.model.dof_names().join(", "),
                        instance.model.system().state_size()
                    ),
                );
                Box::into_raw(instance) as fmi2Component
            }
            Err(message) => fail(&message),
        }
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// Frees an instance (allowed in every phase; NULL is ignored).
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if let Some(instance) = instance_from(c) {
            (*instance).magic = 0;
            drop(Box::from_raw(instance));
        }
    }));
}

/// Sets debug logging for all categories (n = 0) or the listed ones.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    call(c, "fmi2SetDebugLogging", NOT_FATAL, |inst| {
        let list = slice(categories, nCategories, "categories[]")?;
        let mut indices = Vec::with_capacity(list.len());
        for &p in list {
            let name = text(p).ok_or_else(|| "a category is NULL or not UTF-8".to_string())?;
            let i = LOG_CATEGORIES
                .iter()
                .position(|(c, _)| *c == name)
                .ok_or_else(|| format!("unknown log category '{name}'"))?;
            indices.push(i);
        }
        let on = loggingOn != 0;
        if indices.is_empty() {
            inst.categories.iter_mut().for_each(|c| *c = on);
            inst.logging_on = on;
        } else {
            for i in indices {
                inst.categories[i] = on;
            }
            inst.logging_on = inst.categories.iter().any(|c| *c);
        }
        Ok(fmi2OK)
    })
}

/// Sets the start time (the tolerance and stop time are not needed).
#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    call(c, "fmi2SetupExperiment", INSTANTIATED, |inst| {
        if stopTimeDefined != 0 && (stopTime.is_nan() || stopTime < startTime) {
            return Err(format!(
                "stopTime {stopTime} is before startTime {startTime}"
            ));
        }
        inst.model
            .set_start_time(startTime)
            .map_err(|e| e.to_string())?;
        Ok(fmi2OK)
    })
}

/// Enters initialization mode.
#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    call(c, "fmi2EnterInitializationMode", INSTANTIATED, |inst| {
        inst.phase = Phase::InitializationMode;
        Ok(fmi2OK)
    })
}

/// Leaves initialization mode: ready to step.
#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    call(c, "fmi2ExitInitializationMode", INIT_MODE, |inst| {
        inst.phase = Phase::StepComplete;
        inst.log(
            fmi2OK,
            Category::Events,
            &format!(
                "initialized at t = {} with rho = {}, g = {}",
                inst.model.time(),
                inst.model.state().rho,
                inst.model.state().g
            ),
        );
        Ok(fmi2OK)
    })
}

/// Ends the simulation.
#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    call(c, "fmi2Terminate", STEP_COMPLETE, |inst| {
        inst.phase = Phase::Terminated;
        Ok(fmi2OK)
    })
}

/// Back to the instantiated phase with the start values (also after an error).
#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    call(c, "fmi2Reset", NOT_FATAL, |inst| {
        inst.model.reset().map_err(|e| e.to_string())?;
        inst.phase = Phase::Instantiated;
        inst.log(
            fmi2OK,
            Category::Events,
            "fmi2Reset: back to the start values",
        );
        Ok(fmi2OK)
    })
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
    call(c, "fmi2GetReal", READABLE, |inst| {
        let vr = slice(vr, nvr, "vr[]")?;
        let value = slice_mut(value, nvr, "value[]")?;
        for (r, out) in vr.iter().zip(value.iter_mut()) {
            let q = inst.quantity(*r)?;
            *out = inst.model.value(q).map_err(|e| e.to_string())?;
        }
        Ok(fmi2OK)
    })
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
    call(c, "fmi2SetReal", SETTABLE, |inst| {
        let vr = slice(vr, nvr, "vr[]")?;
        let value = slice(value, nvr, "value[]")?;
        let before_init = matches!(inst.phase, Phase::Instantiated | Phase::InitializationMode);
        let (mut rho, mut g) = (inst.model.state().rho, inst.model.state().g);
        let mut parameters = false;
        for (r, x) in vr.iter().zip(value) {
            let q = inst.quantity(*r)?;
            match q {
                Quantity::Rho | Quantity::G if !before_init => {
                    return Err(format!(
                        "{} is a fixed parameter: set it before fmi2ExitInitializationMode",
                        inst.variable_name(*r)
                    ))
                }
                Quantity::Rho => {
                    rho = *x;
                    parameters = true;
                }
                Quantity::G => {
                    g = *x;
                    parameters = true;
                }
                Quantity::Velocity(_) | Quantity::Acceleration(_) => {
                    // Checked before anything is set: a refused call changes nothing.
                    if !crate::model::acceptable(*x) {
                        return Err(format!(
                            "{} = {x:e} is not finite or exceeds {:e} in magnitude (call refused)",
                            inst.variable_name(*r),
                            crate::model::MAX_INPUT
                        ));
                    }
                }
                _ => {
                    return Err(format!(
                        "{} is not an input or parameter and cannot be set",
                        inst.variable_name(*r)
                    ))
                }
            }
        }
        if parameters {
            inst.model
                .set_parameters(rho, g)
                .map_err(|e| e.to_string())?;
        }
        for (r, x) in vr.iter().zip(value) {
            let q = inst.quantity(*r)?;
            if !matches!(q, Quantity::Rho | Quantity::G) {
                inst.model.set_value(q, *x).map_err(|e| e.to_string())?;
            }
        }
        Ok(fmi2OK)
    })
}

fn no_variables(kind: &str, vr: &[fmi2ValueReference]) -> Result<fmi2Status, String> {
    match vr.first() {
        None => Ok(fmi2OK),
        Some(r) => Err(format!(
            "this FMU has no {kind} variables (value reference {r})"
        )),
    }
}

/// No Integer variables: only nvr = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    call(c, "fmi2GetInteger", READABLE, |_| {
        let vr = slice(vr, nvr, "vr[]")?;
        slice_mut(value, nvr, "value[]")?;
        no_variables("Integer", vr)
    })
}

/// No Boolean variables: only nvr = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    call(c, "fmi2GetBoolean", READABLE, |_| {
        let vr = slice(vr, nvr, "vr[]")?;
        slice_mut(value, nvr, "value[]")?;
        no_variables("Boolean", vr)
    })
}

/// No String variables: only nvr = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    call(c, "fmi2GetString", READABLE, |_| {
        let vr = slice(vr, nvr, "vr[]")?;
        slice_mut(value, nvr, "value[]")?;
        no_variables("String", vr)
    })
}

/// No Integer variables: only nvr = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    call(c, "fmi2SetInteger", SETTABLE, |_| {
        let vr = slice(vr, nvr, "vr[]")?;
        slice(value, nvr, "value[]")?;
        no_variables("Integer", vr)
    })
}

/// No Boolean variables: only nvr = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    call(c, "fmi2SetBoolean", SETTABLE, |_| {
        let vr = slice(vr, nvr, "vr[]")?;
        slice(value, nvr, "value[]")?;
        no_variables("Boolean", vr)
    })
}

/// No String variables: only nvr = 0 succeeds.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    call(c, "fmi2SetString", SETTABLE, |_| {
        let vr = slice(vr, nvr, "vr[]")?;
        slice(value, nvr, "value[]")?;
        no_variables("String", vr)
    })
}

// ---------------------------------------------------------------------------------------
// FMU state
// ---------------------------------------------------------------------------------------

unsafe fn snapshot_from<'a>(state: fmi2FMUstate) -> Result<&'a mut Snapshot, String> {
    if state.is_null() {
        return Err("FMUstate is NULL".to_string());
    }
    if (state as usize) % std::mem::align_of::<Snapshot>() != 0 {
        return Err("FMUstate is not a state of this FMU".to_string());
    }
    let snapshot = &mut *(state as *mut Snapshot);
    if snapshot.magic != SNAPSHOT_MAGIC {
        return Err("FMUstate is not a state of this FMU".to_string());
    }
    Ok(snapshot)
}

unsafe fn store_snapshot(
    inst: &Instance,
    target: *mut fmi2FMUstate,
    snapshot: Snapshot,
) -> Result<(), String> {
    if target.is_null() {
        return Err("FMUstate pointer is NULL".to_string());
    }
    if (*target).is_null() {
        *target = Box::into_raw(Box::new(snapshot)) as fmi2FMUstate;
    } else {
        let existing = snapshot_from(*target)?;
        if existing.guid != inst.model.guid() {
            return Err("FMUstate belongs to another FMU".to_string());
        }
        *existing = snapshot;
    }
    Ok(())
}

/// Saves the state (into a new snapshot, or overwrites `*FMUstate` if not NULL).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    call(c, "fmi2GetFMUstate", NOT_FATAL, |inst| {
        let snapshot = Snapshot {
            magic: SNAPSHOT_MAGIC,
            guid: inst.model.guid().to_string(),
            phase: inst.phase,
            state: inst.model.state().clone(),
        };
        store_snapshot(inst, FMUstate, snapshot)?;
        inst.log(
            fmi2OK,
            Category::Events,
            &format!("state saved at t = {}", inst.model.time()),
        );
        Ok(fmi2OK)
    })
}

/// Restores a saved state, including its phase (this also leaves the error phase).
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    call(c, "fmi2SetFMUstate", NOT_FATAL, |inst| {
        let snapshot = snapshot_from(FMUstate)?;
        if snapshot.guid != inst.model.guid() {
            return Err("FMUstate belongs to another FMU".to_string());
        }
        inst.model
            .set_state(snapshot.state.clone())
            .map_err(|e| e.to_string())?;
        inst.phase = snapshot.phase;
        inst.log(
            fmi2OK,
            Category::Events,
            &format!("state restored at t = {}", inst.model.time()),
        );
        Ok(fmi2OK)
    })
}

/// Frees a saved state and sets `*FMUstate` to NULL (NULL `*FMUstate` is a no-op).
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    call(c, "fmi2FreeFMUstate", NOT_FATAL, |_| {
        if FMUstate.is_null() {
            return Err("FMUstate pointer is NULL".to_string());
        }
        if (*FMUstate).is_null() {
            return Ok(fmi2OK);
        }
        let snapshot = snapshot_from(*FMUstate)?;
        snapshot.magic = 0;
        drop(Box::from_raw(snapshot as *mut Snapshot));
        *FMUstate = std::ptr::null_mut();
        Ok(fmi2OK)
    })
}

/// Size of the serialized state.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    call(c, "fmi2SerializedFMUstateSize", NOT_FATAL, |inst| {
        snapshot_from(FMUstate)?;
        let out = slice_mut(size, 1, "size")?;
        out[0] = inst.model.serialized_size();
        Ok(fmi2OK)
    })
}

/// Writes the serialized state (`size` must be exactly the serialized size).
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    call(c, "fmi2SerializeFMUstate", NOT_FATAL, |inst| {
        let snapshot = snapshot_from(FMUstate)?;
        if snapshot.guid != inst.model.guid() {
            return Err("FMUstate belongs to another FMU".to_string());
        }
        let bytes = inst
            .model
            .serialize_state(&snapshot.state, snapshot.phase as u8);
        if size != bytes.len() {
            return Err(format!(
                "size {size}, the serialized state has {} bytes",
                bytes.len()
            ));
        }
        let out = slice_mut(serializedState as *mut u8, size, "serializedState")?;
        out.copy_from_slice(&bytes);
        Ok(fmi2OK)
    })
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
    call(c, "fmi2DeSerializeFMUstate", NOT_FATAL, |inst| {
        let bytes = slice(serializedState as *const u8, size, "serializedState")?;
        let (state, tag) = inst.model.deserialize(bytes).map_err(|e| e.to_string())?;
        let phase =
            Phase::from_tag(tag).ok_or_else(|| format!("serialized phase {tag} is not valid"))?;
        let snapshot = Snapshot {
            magic: SNAPSHOT_MAGIC,
            guid: inst.model.guid().to_string(),
            phase,
            state,
        };
        store_snapshot(inst, FMUstate, snapshot)?;
        Ok(fmi2OK)
    })
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
    call(c, "fmi2GetDirectionalDerivative", READABLE, |inst| {
        let unknown = slice(vUnknown_ref, nUnknown, "vUnknown_ref[]")?;
        let known = slice(vKnown_ref, nKnown, "vKnown_ref[]")?;
        let seed = slice(dvKnown, nKnown, "dvKnown[]")?;
        let out = slice_mut(dvUnknown, nUnknown, "dvUnknown[]")?;
        let known_q = known
            .iter()
            .map(|r| inst.quantity(*r))
            .collect::<Result<Vec<_>, _>>()?;
        for (u, o) in unknown.iter().zip(out.iter_mut()) {
            let uq = inst.quantity(*u)?;
            let mut sum = 0.0;
            for (kq, s) in known_q.iter().zip(seed) {
                sum += inst
                    .model
                    .partial_derivative(uq, *kq)
                    .map_err(|e| e.to_string())?
                    * s;
            }
            *o = sum;
        }
        Ok(fmi2OK)
    })
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
    call(c, "fmi2SetRealInputDerivatives", SETTABLE, |inst| {
        let vr = slice(vr, nvr, "vr[]")?;
        let order = slice(order, nvr, "order[]")?;
        let value = slice(value, nvr, "value[]")?;
        let mut checked = Vec::with_capacity(nvr);
        for ((r, k), x) in vr.iter().zip(order).zip(value) {
            let q = inst.quantity(*r)?;
            if !matches!(q, Quantity::Velocity(_) | Quantity::Acceleration(_)) {
                return Err(format!("{} is not an input", inst.variable_name(*r)));
            }
            if *k != 1 {
                return Err(format!(
                    "derivative order {k} of {}: only order 1 is supported",
                    inst.variable_name(*r)
                ));
            }
            if !crate::model::acceptable(*x) {
                return Err(format!(
                    "derivative of {} = {x:e} is not finite or exceeds {:e} in magnitude \
                     (call refused)",
                    inst.variable_name(*r),
                    crate::model::MAX_INPUT
                ));
            }
            checked.push((q, *x));
        }
        for (q, x) in checked {
            inst.model
                .set_input_derivative(q, x)
                .map_err(|e| e.to_string())?;
        }
        Ok(fmi2OK)
    })
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
    call(
        c,
        "fmi2GetRealOutputDerivatives",
        STEP_COMPLETE | TERMINATED | ERROR,
        |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let order = slice(order, nvr, "order[]")?;
            let value = slice_mut(value, nvr, "value[]")?;
            for ((r, k), out) in vr.iter().zip(order).zip(value.iter_mut()) {
                let q = inst.quantity(*r)?;
                if *k < 1 || *k as u32 > MAX_OUTPUT_DERIVATIVE_ORDER {
                    return Err(format!(
                        "derivative order {k} of {}: only order 1 is provided",
                        inst.variable_name(*r)
                    ));
                }
                *out = inst.model.output_derivative(q).map_err(|e| e.to_string())?;
            }
            Ok(fmi2OK)
        },
    )
}

/// One communication step from `currentCommunicationPoint` (the instance's time) by h > 0.
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    call(c, "fmi2DoStep", STEP_COMPLETE, |inst| {
        if inst.enabled(Category::Calls) {
            inst.log(
                fmi2OK,
                Category::Calls,
                &format!(
                    "fmi2DoStep(t = {currentCommunicationPoint}, h = {communicationStepSize})"
                ),
            );
        }
        inst.model
            .step(currentCommunicationPoint, communicationStepSize)
            .map_err(|e| e.to_string())?;
        Ok(fmi2OK)
    })
}

/// Steps are synchronous: there is never a step to cancel.
#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    call(c, "fmi2CancelStep", 0, |_| Ok(fmi2Error))
}

const STATUS_PHASES: u8 = STEP_COMPLETE | TERMINATED;

fn status_not_available(function: &str, inst: &Instance, s: fmi2StatusKind) -> fmi2Status {
    inst.log(
        fmi2Discard,
        Category::Warning,
        &format!("{function}: status kind {s} is not available (steps are synchronous)"),
    );
    fmi2Discard
}

/// No asynchronous steps: `fmi2Discard`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Status,
) -> fmi2Status {
    call(c, "fmi2GetStatus", STATUS_PHASES, |inst| {
        slice_mut(value, 1, "value")?;
        Ok(status_not_available("fmi2GetStatus", inst, s))
    })
}

/// `fmi2LastSuccessfulTime`: the instance's time.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    call(c, "fmi2GetRealStatus", STATUS_PHASES, |inst| {
        let out = slice_mut(value, 1, "value")?;
        if s == fmi2LastSuccessfulTime {
            out[0] = inst.model.time();
            return Ok(fmi2OK);
        }
        Ok(status_not_available("fmi2GetRealStatus", inst, s))
    })
}

/// No Integer status: `fmi2Discard`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Integer,
) -> fmi2Status {
    call(c, "fmi2GetIntegerStatus", STATUS_PHASES, |inst| {
        slice_mut(value, 1, "value")?;
        Ok(status_not_available("fmi2GetIntegerStatus", inst, s))
    })
}

/// `fmi2Terminated`: false (the FMU never asks to stop).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    call(c, "fmi2GetBooleanStatus", STATUS_PHASES, |inst| {
        let out = slice_mut(value, 1, "value")?;
        if s == fmi2Terminated {
            out[0] = 0;
            return Ok(fmi2OK);
        }
        Ok(status_not_available("fmi2GetBooleanStatus", inst, s))
    })
}

/// No String status: `fmi2Discard`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2String,
) -> fmi2Status {
    call(c, "fmi2GetStringStatus", STATUS_PHASES, |inst| {
        slice_mut(value, 1, "value")?;
        Ok(status_not_available("fmi2GetStringStatus", inst, s))
    })
}

#[cfg(test)]
mod tests;
