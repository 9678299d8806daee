//! The FMI co-simulation interface: one safe instance and phase table, and one thin C layer
//! per standard (FMI 2.0 and FMI 3.0).
//!
//! FMI 3.0 (docs/FMI3.md): the `fmi3...` functions (`fmi3.rs`) call the same
//! [`Instance`], made through `fmi3InstantiateCoSimulation` ([`Instance::instantiate_fmi3`];
//! its messages name the FMI 3.0 functions, [`Standard`]); the matrices are array variables
//! and `time` a variable ([`crate::fmu::fmi3`]). FMI 3.0 co-simulation without event mode has
//! the FMI 2.0 state machine, so the phase table below serves both.
//!
//! - The C layers (see "C layer" below): `fmi2.rs`, the 34 common and co-simulation
//!   functions of FMI 2.0, and `fmi3.rs`, those of FMI 3.0, exported unprefixed
//!   (`fmi2Instantiate`, `fmi3DoStep`, ...), over the shared helpers of `ffi.rs` (pointer
//!   checks, panic guard, logger forwarding). These three modules are the only ones with
//!   `unsafe` code: they check the pointers the master passes, turn them into slices and
//!   strings, catch panics and call the safe layer. A component is a boxed [`Instance`]
//!   (with the copied callbacks); there is no global state.
//! - [`Instance`]: one FMU instance as safe methods on slices, one per FMI function, with
//!   the phase rules of [`allowed`] (one table, next to the FMI 2.0 state table), the error
//!   rules and the log messages. The model ([`crate::model`]) never sees FMI types.
//!
//! # Phases (FMI 2.0, section 4.2.4)
//! instantiated -> initialization mode -> step complete -> terminated, plus error and fatal.
//! A call not allowed in the current phase returns `fmi2Error`, logs why, and leaves the
//! phase alone. A call that is allowed but fails (bad pointer, unknown value reference,
//! NaN or infinite input, h <= 0, a communication point that is not the instance's time, a
//! step past the stop time of `fmi2SetupExperiment`, corrupt or inconsistent state bytes, a
//! value to return that is not finite, ...) returns `fmi2Error`, leaves the model state
//! unchanged and moves the instance to the error phase, as the standard says; `fmi2Reset`
//! or `fmi2SetFMUstate` make it usable again. No call returns a NaN or infinite number with
//! `fmi2OK`. A panic (a bug) is caught and gives `fmi2Fatal`.
//!
//! # Resources and GUID
//! `fmuResourceLocation` is a `file:` URI ([`resource_path`]). The GUID given by the master
//! must equal the GUID derived from the resources ([`crate::model::Resources::guid`]).
//!
//! # Logging
//! The callbacks are copied at instantiation; a NULL logger is tolerated. An instance
//! collects its messages during a call; the C layer passes them to the logger after the
//! call, when the instance is no longer borrowed. Messages are passed as the logger's
//! format string with `%` escaped as `%%`. Errors are always logged (category
//! `logStatusError`); warnings, events and calls only when debug logging is on for their
//! category (`fmi2SetDebugLogging`; `loggingOn` at instantiation turns all on). With
//! `logCalls` on, each call is logged once, with its final status; nothing else is logged
//! per step.
//!
//! # Input and output derivatives
//! `fmi2SetRealInputDerivatives` (order 1) ramps the input over the following steps
//! (first-order hold; the derivative stays set until changed). `fmi2GetRealOutputDerivatives`
//! gives order 1. `fmi2GetDirectionalDerivative`: d force / d velocity = -damping_direct,
//! d force / d acceleration = -added_mass_inf (when present), and those of power and energy;
//! the knowns rho and g are passed to the model as well.
//!
//! # C layer
//! Every exported function is `unsafe extern "C"`: the caller (an FMI master) must pass
//! pointers as FMI 2.0 specifies. Each function checks its pointers for NULL (and
//! alignment) before use, checks that the component or FMU state carries this module's
//! magic number (a foreign or freed one is refused), and catches panics.

#[allow(unsafe_code)]
mod ffi;
#[allow(unsafe_code)]
mod fmi2;
#[allow(unsafe_code)]
mod fmi3;
mod instance;
mod logging;
mod phase;
mod types;
mod uri;

pub use fmi2::*;
pub use fmi3::*;
pub use instance::{Instance, InstantiateError, Snapshot};
pub use logging::{Category, Message};
pub use phase::{allowed, Function, Phase, PhaseSet, Standard};
pub use types::*;
pub use uri::{resource_path, ResourceLocationError, ResourceLocationProblem};

#[cfg(test)]
#[allow(unsafe_code)]
mod tests;
