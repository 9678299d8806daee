//! The FMI 2.0 C types and constants (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`), and
//! [`Status`], the safe form of `fmi2Status`.
#![allow(non_camel_case_types, non_snake_case, non_upper_case_globals)]

use std::ffi::{c_char, c_int, c_uint, c_void};

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

/// The outcome of a call (`fmi2Status` without `fmi2Pending`: steps are synchronous).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// `fmi2OK`.
    Ok,
    /// `fmi2Warning`.
    Warning,
    /// `fmi2Discard`.
    Discard,
    /// `fmi2Error`.
    Error,
    /// `fmi2Fatal`.
    Fatal,
}

impl Status {
    /// The C value.
    pub fn code(self) -> fmi2Status {
        match self {
            Status::Ok => fmi2OK,
            Status::Warning => fmi2Warning,
            Status::Discard => fmi2Discard,
            Status::Error => fmi2Error,
            Status::Fatal => fmi2Fatal,
        }
    }
}
