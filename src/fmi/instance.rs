//! One FMU instance without pointers: the FMI 2.0 co-simulation functions as safe methods on
//! slices, with the phase checks of [`allowed`], the error rules and the log messages.
//!
//! Every method is one FMI call and returns its [`Status`]:
//! - a call outside its phases is refused (fmi2Error, logged) and the phase stays;
//! - a call that is allowed but fails (unknown value reference, NaN or infinite input,
//!   h <= 0, a communication point that is not the instance's time, a step past the stop
//!   time, corrupt or inconsistent state bytes, a value to return that is not finite, slices
//!   of different lengths, ...) returns fmi2Error, leaves the model state unchanged and moves
//!   the instance to the error phase; fmi2Reset or fmi2SetFMUstate recover;
//! - with `logCalls` on, each call is logged once, with its final status.
//!
//! Messages are collected ([`Instance::take_messages`]), never sent from here.

use super::logging::{Category, LogSwitches, Message};
use super::phase::{allowed, Function, Phase, Standard};
use super::types::{
    fmi2Boolean, fmi2CoSimulation, fmi2Integer, fmi2LastSuccessfulTime, fmi2StatusKind,
    fmi2Terminated, fmi2Type, fmi2ValueReference, Status,
};
use super::uri::{resource_path, ResourceLocationError};
use crate::fmu::description::{MAX_OUTPUT_DERIVATIVE_ORDER, PARAMETERS};
use crate::fmu::{Layout, Quantity, ResourcesError, VariablesError};
use crate::model::{Model, ModelError, ModelState, Resources};
use references::StepReferences;
use std::collections::HashSet;
use std::ffi::{CStr, CString};
use std::fmt;
use std::path::PathBuf;

/// One FMU instance (behind an `fmi2Component`).
pub struct Instance {
    name: CString,
    log: LogSwitches,
    messages: Vec<Message>,
    phase: Phase,
    model: Model,
    layout: Layout,
    /// The value references of the inputs and forces, resolved from `layout`.
    step_references: StepReferences,
    standard: Standard,
    /// Addresses of the FMU states this instance issued and has not freed: the C layer
    /// dereferences no state pointer outside this set.
    issued_states: HashSet<usize>,
}

/// A saved FMU state (behind an `fmi2FMUstate`): the model state and the phase.
#[derive(Clone, Debug)]
pub struct Snapshot {
    guid: String,
    phase: Phase,
    state: ModelState,
}

/// The result of a call's body: its status, or why it failed.
type Outcome = Result<Status, String>;

fn same_length(a: (&str, usize), b: (&str, usize)) -> Result<(), String> {
    if a.1 == b.1 {
        Ok(())
    } else {
        Err(format!("{} has {} entries, {} has {}", a.0, a.1, b.0, b.1))
    }
}

/// Refuses a value of a fixed parameter outside the min and max its model description
/// declares ([`PARAMETERS`]); other variables pass.
fn within_declared_limits(vr: fmi2ValueReference, value: f64) -> Result<(), String> {
    let Some(p) = PARAMETERS.iter().find(|p| p.value_reference == vr) else {
        return Ok(());
    };
    if value < p.min || value > p.max {
        return Err(format!(
            "{} = {value} is outside its declared range {}..={} (min and max in the model description)",
            p.name, p.min, p.max
        ));
    }
    Ok(())
}

fn no_variables(kind: &str, vr: &[fmi2ValueReference]) -> Outcome {
    match vr.first() {
        None => Ok(Status::Ok),
        Some(r) => Err(format!(
            "this FMU has no {kind} variables (value reference {r})"
        )),
    }
}

/// Why an instance could not be made: the message the C layer logs with the function's name.
#[derive(Debug)]
#[non_exhaustive]
pub enum InstantiateError {
    /// An argument is NULL, empty or not UTF-8 (its description).
    Argument(&'static str),
    /// `fmuType` is not co-simulation.
    NotCoSimulation(fmi2Type),
    /// The resource location is not a local `file:` URI.
    ResourceLocation(ResourceLocationError),
    /// The resources cannot be read.
    Resources(ResourcesError),
    /// The GUID (or FMI 3.0 instantiation token) is not the resources'.
    Guid {
        /// `fmuGUID` or `instantiationToken`.
        argument: &'static str,
        /// What the master gave.
        given: String,
        /// The resources' own.
        expected: String,
        /// The resources' folder.
        folder: PathBuf,
    },
    /// The model described by the resources is refused.
    Model(ModelError),
    /// Its variables cannot be laid out.
    Variables(VariablesError),
}

impl fmt::Display for InstantiateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InstantiateError::Argument(what) => f.write_str(what),
            InstantiateError::NotCoSimulation(kind) => {
                write!(f, "fmuType {kind}: this FMU supports co-simulation only")
            }
            InstantiateError::ResourceLocation(e) => e.fmt(f),
            InstantiateError::Resources(e) => e.fmt(f),
            InstantiateError::Guid {
                argument: "fmuGUID",
                given,
                expected,
                folder,
            } => write!(
                f,
                "GUID {given} does not match the resources in {} (GUID {expected})",
                folder.display()
            ),
            InstantiateError::Guid {
                argument,
                given,
                expected,
                folder,
            } => write!(
                f,
                "{argument} {given} does not match the resources in {} ({expected})",
                folder.display()
            ),
            InstantiateError::Model(e) => e.fmt(f),
            InstantiateError::Variables(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for InstantiateError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            InstantiateError::ResourceLocation(e) => Some(e),
            InstantiateError::Resources(e) => Some(e),
            InstantiateError::Model(e) => Some(e),
            InstantiateError::Variables(e) => Some(e),
            _ => None,
        }
    }
}

impl From<ResourceLocationError> for InstantiateError {
    fn from(e: ResourceLocationError) -> Self {
        InstantiateError::ResourceLocation(e)
    }
}

impl Instance {
    /// fmi2Instantiate: checks the arguments, reads the resources the URI names and checks
    /// the GUID against them (the GUID derived from the resources, [`Resources::guid`]).
    pub fn instantiate(
        name: Option<&CStr>,
        fmu_type: fmi2Type,
        guid: Option<&str>,
        resource_location: Option<&str>,
        logging_on: bool,
    ) -> Result<Instance, InstantiateError> {
        let name = name
            .filter(|n| !n.to_bytes().is_empty())
            .ok_or(InstantiateError::Argument("instanceName is NULL or empty"))?;
        if fmu_type != fmi2CoSimulation {
            return Err(InstantiateError::NotCoSimulation(fmu_type));
        }
        let location = resource_location.ok_or(InstantiateError::Argument(
            "fmuResourceLocation is NULL or not UTF-8",
        ))?;
        let dir = resource_path(location)?;
        let resources = Resources::read(&dir).map_err(InstantiateError::Resources)?;
        let expected = resources.guid();
        let guid = guid.ok_or(InstantiateError::Argument("fmuGUID is NULL or not UTF-8"))?;
        if guid != expected {
            return Err(InstantiateError::Guid {
                argument: "fmuGUID",
                given: guid.to_string(),
                expected,
                folder: dir,
            });
        }
        Instance::from_resources(name, &resources, logging_on)
    }

    /// An instance of the FMU these resources describe (no GUID check).
    pub fn from_resources(
        name: &CStr,
        resources: &Resources,
        logging_on: bool,
    ) -> Result<Instance, InstantiateError> {
        let model = Model::from_resources(resources).map_err(InstantiateError::Model)?;
        let layout = model.layout().map_err(InstantiateError::Variables)?;
        let mut instance = Instance {
            name: name.to_owned(),
            log: LogSwitches::new(logging_on),
            messages: Vec::new(),
            phase: Phase::Instantiated,
            model,
            step_references: StepReferences::resolve(&layout),
            layout,
            standard: Standard::Fmi2,
            issued_states: HashSet::new(),
        };
        let text = format!(
            "instantiated: {} DOFs ({}), {} network states",
            instance.model.dof_count(),
            instance.model.dof_names().join(", "),
            instance.model.network_states()
        );
        instance.log(Status::Ok, Category::Events, text);
        Ok(instance)
    }

    /// The instance name given at instantiation.
    pub fn name(&self) -> &CStr {
        &self.name
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// The model (tests look inside).
    #[cfg(test)]
    pub(crate) fn model(&self) -> &Model {
        &self.model
    }

    /// The messages collected since the last call, in order, for the master's logger.
    pub fn take_messages(&mut self) -> Vec<Message> {
        std::mem::take(&mut self.messages)
    }

    // -----------------------------------------------------------------------------------
    // Calls, errors and logging
    // -----------------------------------------------------------------------------------

    fn log(&mut self, status: Status, category: Category, text: String) {
        if self.log.enabled(category) {
            self.messages.push(Message {
                status,
                category,
                text,
            });
        }
    }

    /// The one `logCalls` line of a call, placed before the call's other messages.
    fn log_call(&mut self, first: usize, status: Status, describe: impl FnOnce() -> String) {
        if self.log.enabled(Category::Calls) {
            let line = Message {
                status,
                category: Category::Calls,
                text: describe(),
            };
            self.messages.insert(first.min(self.messages.len()), line);
        }
    }

    fn refuse(&mut self, function: Function) -> Status {
        let text = format!(
            "{}: not allowed in phase {:?} (call refused)",
            function.name_in(self.standard),
            self.phase
        );
        self.log(Status::Error, Category::Error, text);
        Status::Error
    }

    fn fail(&mut self, function: Function, message: &str) -> Status {
        let text = format!("{}: {message}", function.name_in(self.standard));
        self.log(Status::Error, Category::Error, text);
        self.phase = Phase::Error;
        Status::Error
    }

    /// One call: phase check, body, error rule, `logCalls` line.
    fn run(&mut self, function: Function, body: impl FnOnce(&mut Self) -> Outcome) -> Status {
        let standard = self.standard;
        self.run_described(
            function,
            move || function.name_in(standard).to_string(),
            body,
        )
    }

    fn run_described(
        &mut self,
        function: Function,
        describe: impl FnOnce() -> String,
        body: impl FnOnce(&mut Self) -> Outcome,
    ) -> Status {
        let first = self.messages.len();
        let status = if allowed(function).contains(self.phase) {
            body(self).unwrap_or_else(|message| self.fail(function, &message))
        } else {
            self.refuse(function)
        };
        self.log_call(first, status, describe);
        status
    }

    /// For the C layer, before it reads a call's pointer arguments: refuses the call if its
    /// phase does not allow it (as the method would).
    pub(crate) fn refuse_outside_phase(&mut self, function: Function) -> Option<Status> {
        let name = function.name_in(self.standard);
        self.refuse_outside_phase_as(function, name)
    }

    /// [`Instance::refuse_outside_phase`] for the C function `name` (one of the functions
    /// that share `function`'s phases).
    pub(crate) fn refuse_outside_phase_as(
        &mut self,
        function: Function,
        name: &str,
    ) -> Option<Status> {
        if allowed(function).contains(self.phase) {
            return None;
        }
        let first = self.messages.len();
        let text = format!(
            "{name}: not allowed in phase {:?} (call refused)",
            self.phase
        );
        self.log(Status::Error, Category::Error, text);
        self.log_call(first, Status::Error, || name.to_string());
        Some(Status::Error)
    }

    /// For the C layer: a call whose pointer arguments are unusable fails like any call.
    pub(crate) fn reject_arguments(&mut self, function: Function, message: &str) -> Status {
        let name = function.name_in(self.standard);
        self.reject_arguments_as(name, message)
    }

    /// [`Instance::reject_arguments`] for the C function `name`.
    pub(crate) fn reject_arguments_as(&mut self, name: &str, message: &str) -> Status {
        let first = self.messages.len();
        self.log(Status::Error, Category::Error, format!("{name}: {message}"));
        self.phase = Phase::Error;
        self.log_call(first, Status::Error, || name.to_string());
        Status::Error
    }

    /// For the C layer: a call of the other standard's function `called` (an fmi2 function
    /// on an instance made by fmi3InstantiateCoSimulation, or back) is refused and logged,
    /// naming `counterpart`, this standard's function, when there is one; the phase stays.
    pub(crate) fn refuse_other_standard(&mut self, called: &str, counterpart: Option<&str>) {
        let made_by = match self.standard {
            Standard::Fmi2 => "fmi2Instantiate (FMI 2.0)",
            Standard::Fmi3 => "fmi3InstantiateCoSimulation (FMI 3.0)",
        };
        let instead = match counterpart {
            Some(own) => format!("call {own} instead"),
            None => "its standard has no such function".to_string(),
        };
        let text =
            format!("{called}: this instance was made by {made_by}: {instead} (call refused)");
        let first = self.messages.len();
        self.log(Status::Error, Category::Error, text);
        self.log_call(first, Status::Error, || called.to_string());
    }

    /// For the C layer, after a caught panic (a bug): the instance can only be freed.
    pub(crate) fn enter_fatal(&mut self, function: Function) -> Status {
        self.phase = Phase::Fatal;
        let text = format!(
            "{}: internal error (panic); the instance can only be freed",
            function.name_in(self.standard)
        );
        self.log(Status::Fatal, Category::Fatal, text);
        let end = self.messages.len();
        let name = function.name_in(self.standard);
        self.log_call(end, Status::Fatal, || name.to_string());
        Status::Fatal
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

    // -----------------------------------------------------------------------------------
    // Life cycle
    // -----------------------------------------------------------------------------------

    /// fmi2SetDebugLogging: all categories (`categories` empty) or the named ones.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> Status {
        self.run(Function::SetDebugLogging, |inst| {
            inst.log.set(on, categories)?;
            Ok(Status::Ok)
        })
    }

    /// fmi2SetupExperiment: sets the start time and, if defined, the stop time: a step that
    /// would end past it is an error (FMI 2.0; within the time tolerance). fmi2Reset clears
    /// it; it is part of the FMU state (restored with it). The tolerance is not needed.
    pub fn setup_experiment(
        &mut self,
        _tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Status {
        self.run(Function::SetupExperiment, |inst| {
            inst.set_experiment(start_time, stop_time)?;
            Ok(Status::Ok)
        })
    }

    /// The start time and the optional stop time of the run (not before the start).
    fn set_experiment(&mut self, start_time: f64, stop_time: Option<f64>) -> Result<(), String> {
        if let Some(stop) = stop_time {
            if stop.is_nan() || stop < start_time {
                return Err(format!("stopTime {stop} is before startTime {start_time}"));
            }
        }
        self.model
            .set_experiment(start_time, stop_time)
            .map_err(|e| e.to_string())
    }

    /// fmi2EnterInitializationMode.
    pub fn enter_initialization_mode(&mut self) -> Status {
        self.run(Function::EnterInitializationMode, |inst| {
            inst.phase = Phase::InitializationMode;
            Ok(Status::Ok)
        })
    }

    /// fmi2ExitInitializationMode: ready to step.
    pub fn exit_initialization_mode(&mut self) -> Status {
        self.run(Function::ExitInitializationMode, |inst| {
            // The wave parameters, rho, g and the start time are final now.
            let notes = inst.model.start_waves().map_err(|e| e.to_string())?;
            for note in notes {
                inst.log(Status::Warning, Category::Warning, note);
            }
            inst.phase = Phase::StepComplete;
            let text = format!(
                "initialized at t = {} with rho = {}, g = {}",
                inst.model.time(),
                inst.model.state().rho,
                inst.model.state().g
            );
            inst.log(Status::Ok, Category::Events, text);
            Ok(Status::Ok)
        })
    }

    /// fmi2Terminate.
    pub fn terminate(&mut self) -> Status {
        self.run(Function::Terminate, |inst| {
            inst.phase = Phase::Terminated;
            Ok(Status::Ok)
        })
    }

    /// fmi2Reset: back to the instantiated phase with the start values (also after an error).
    pub fn reset(&mut self) -> Status {
        self.run(Function::Reset, |inst| {
            inst.model.reset().map_err(|e| e.to_string())?;
            inst.phase = Phase::Instantiated;
            let text = "reset: back to the start values".to_string();
            inst.log(Status::Ok, Category::Events, text);
            Ok(Status::Ok)
        })
    }

    // -----------------------------------------------------------------------------------
    // Getting and setting values
    // -----------------------------------------------------------------------------------

    /// fmi2GetReal.
    pub fn get_real(&mut self, vr: &[fmi2ValueReference], values: &mut [f64]) -> Status {
        self.run(Function::GetReal, |inst| {
            if inst.get_forces_directly(vr, values) {
                return Ok(Status::Ok);
            }
            same_length(("vr[]", vr.len()), ("value[]", values.len()))?;
            for (r, out) in vr.iter().zip(values.iter_mut()) {
                *out = inst.real_value(*r)?;
            }
            Ok(Status::Ok)
        })
    }

    /// The value of the Real variable `vr` (an Integer one is refused: it has its own getter).
    fn real_value(&mut self, vr: fmi2ValueReference) -> Result<f64, String> {
        match self.quantity(vr)? {
            Quantity::Wave(p) if p.is_integer() => Err(format!(
                "{} is an Integer variable: read it with {}",
                self.variable_name(vr),
                Function::GetInteger.name_in(self.standard)
            )),
            q => self.model.value(q).map_err(|e| e.to_string()),
        }
    }

    /// fmi2SetReal: rho and g before initialization ends, the inputs any time before
    /// termination. All values are checked before any is applied.
    pub fn set_real(&mut self, vr: &[fmi2ValueReference], values: &[f64]) -> Status {
        self.run(Function::SetReal, |inst| {
            if inst.set_inputs_directly(vr, values)? {
                return Ok(Status::Ok);
            }
            same_length(("vr[]", vr.len()), ("value[]", values.len()))?;
            let before_init = matches!(inst.phase, Phase::Instantiated | Phase::InitializationMode);
            let (mut rho, mut g) = (inst.model.state().rho, inst.model.state().g);
            let (mut parameters, mut waves) = (false, false);
            for (r, x) in vr.iter().zip(values) {
                let q = inst.quantity(*r)?;
                within_declared_limits(*r, *x)?;
                match q {
                    Quantity::Rho | Quantity::G | Quantity::Wave(_) if !before_init => {
                        return Err(format!(
                            "{} is a fixed parameter: set it before initialization mode ends",
                            inst.variable_name(*r)
                        ))
                    }
                    Quantity::Wave(p) if p.is_integer() => {
                        return Err(format!(
                            "{} is an Integer parameter: set it with {}",
                            inst.variable_name(*r),
                            Function::SetInteger.name_in(inst.standard)
                        ))
                    }
                    Quantity::Wave(_) => waves = true,
                    Quantity::Rho => {
                        rho = *x;
                        parameters = true;
                    }
                    Quantity::G => {
                        g = *x;
                        parameters = true;
                    }
                    Quantity::DampingLinear(..)
                    | Quantity::DampingQuadratic(_)
                    | Quantity::CurrentSpeed
                    | Quantity::CurrentHeading
                    | Quantity::CrossflowDragScale => {
                        crate::model::viscous::check_value(q, *x, before_init)?
                    }
                    Quantity::Depth => inst.model.check_depth(*x).map_err(|e| e.to_string())?,
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
            let saved = inst.model.state().waves.clone();
            if waves {
                for (r, x) in vr.iter().zip(values) {
                    if let Quantity::Wave(p) = inst.quantity(*r)? {
                        if let Err(e) = inst.model.set_wave_real(p, *x) {
                            inst.model.restore_waves(saved);
                            return Err(e.to_string());
                        }
                    }
                }
            }
            if parameters {
                if let Err(e) = inst.model.set_parameters(rho, g) {
                    inst.model.restore_waves(saved);
                    return Err(e.to_string());
                }
            }
            for (r, x) in vr.iter().zip(values) {
                let q = inst.quantity(*r)?;
                if !matches!(q, Quantity::Rho | Quantity::G | Quantity::Wave(_)) {
                    inst.model.set_value(q, *x).map_err(|e| e.to_string())?;
                }
            }
            Ok(Status::Ok)
        })
    }

    /// fmi2GetInteger: the Integer wave parameters.
    pub fn get_integer(&mut self, vr: &[fmi2ValueReference], values: &mut [i32]) -> Status {
        self.run(Function::GetInteger, |inst| {
            same_length(("vr[]", vr.len()), ("value[]", values.len()))?;
            for (r, out) in vr.iter().zip(values.iter_mut()) {
                match inst.quantity(*r)? {
                    Quantity::Wave(p) if p.is_integer() => {
                        // Integer parameters are stored exactly.
                        *out = inst.model.wave_parameter(p) as i32;
                    }
                    _ => {
                        return Err(format!(
                            "{} is not an Integer variable",
                            inst.variable_name(*r)
                        ))
                    }
                }
            }
            Ok(Status::Ok)
        })
    }

    /// fmi2GetBoolean: there are no Boolean variables, only an empty `vr` succeeds.
    pub fn get_boolean(&mut self, vr: &[fmi2ValueReference]) -> Status {
        self.run(Function::GetBoolean, |_| no_variables("Boolean", vr))
    }

    /// fmi2GetString: there are no String variables, only an empty `vr` succeeds.
    pub fn get_string(&mut self, vr: &[fmi2ValueReference]) -> Status {
        self.run(Function::GetString, |_| no_variables("String", vr))
    }

    /// fmi2SetInteger: the Integer wave parameters, before initialization ends. A refused
    /// call changes nothing.
    pub fn set_integer(&mut self, vr: &[fmi2ValueReference], values: &[i32]) -> Status {
        self.run(Function::SetInteger, |inst| {
            same_length(("vr[]", vr.len()), ("value[]", values.len()))?;
            let before_init = matches!(inst.phase, Phase::Instantiated | Phase::InitializationMode);
            for (r, x) in vr.iter().zip(values) {
                match inst.quantity(*r)? {
                    Quantity::Wave(p) if p.is_integer() && before_init => {
                        within_declared_limits(*r, f64::from(*x))?;
                    }
                    Quantity::Wave(p) if p.is_integer() => {
                        return Err(format!(
                            "{} is a fixed parameter: set it before initialization mode ends",
                            inst.variable_name(*r)
                        ))
                    }
                    _ => {
                        return Err(format!(
                            "{} is not an Integer parameter",
                            inst.variable_name(*r)
                        ))
                    }
                }
            }
            let saved = inst.model.state().waves.clone();
            for (r, x) in vr.iter().zip(values) {
                if let Quantity::Wave(p) = inst.quantity(*r)? {
                    if let Err(e) = inst.model.set_wave_integer(p, *x) {
                        inst.model.restore_waves(saved);
                        return Err(e.to_string());
                    }
                }
            }
            Ok(Status::Ok)
        })
    }

    /// fmi2SetBoolean: there are no Boolean variables, only an empty `vr` succeeds.
    pub fn set_boolean(&mut self, vr: &[fmi2ValueReference]) -> Status {
        self.run(Function::SetBoolean, |_| no_variables("Boolean", vr))
    }

    /// fmi2SetString: there are no String variables, only an empty `vr` succeeds.
    pub fn set_string(&mut self, vr: &[fmi2ValueReference]) -> Status {
        self.run(Function::SetString, |_| no_variables("String", vr))
    }

    /// fmi2GetDirectionalDerivative: `dv_unknown = J dv_known` for the listed unknowns and
    /// knowns (d force / d velocity = -damping_direct, d force / d acceleration =
    /// -added_mass_inf, and those of power and energy; the model supplies each partial).
    pub fn get_directional_derivative(
        &mut self,
        unknowns: &[fmi2ValueReference],
        knowns: &[fmi2ValueReference],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> Status {
        self.run(Function::GetDirectionalDerivative, |inst| {
            same_length(
                ("vKnown_ref[]", knowns.len()),
                ("dvKnown[]", dv_known.len()),
            )?;
            same_length(
                ("vUnknown_ref[]", unknowns.len()),
                ("dvUnknown[]", dv_unknown.len()),
            )?;
            let known_q = knowns
                .iter()
                .map(|r| inst.quantity(*r))
                .collect::<Result<Vec<_>, _>>()?;
            for (u, o) in unknowns.iter().zip(dv_unknown.iter_mut()) {
                let uq = inst.quantity(*u)?;
                let mut sum = 0.0;
                for (kq, s) in known_q.iter().zip(dv_known) {
                    sum += inst
                        .model
                        .partial_derivative(uq, *kq)
                        .map_err(|e| e.to_string())?
                        * s;
                }
                if !sum.is_finite() {
                    return Err(format!(
                        "the directional derivative of {} is not finite ({sum}): the seeds \
                         dvKnown or the state overflow f64",
                        inst.variable_name(*u)
                    ));
                }
                *o = sum;
            }
            Ok(Status::Ok)
        })
    }

    // -----------------------------------------------------------------------------------
    // Co-simulation
    // -----------------------------------------------------------------------------------

    /// fmi2SetRealInputDerivatives (order 1 only): first-order hold over the next steps; the
    /// derivative stays set until changed.
    pub fn set_real_input_derivatives(
        &mut self,
        vr: &[fmi2ValueReference],
        order: &[fmi2Integer],
        values: &[f64],
    ) -> Status {
        self.run(Function::SetRealInputDerivatives, |inst| {
            same_length(("vr[]", vr.len()), ("order[]", order.len()))?;
            same_length(("vr[]", vr.len()), ("value[]", values.len()))?;
            let mut checked = Vec::with_capacity(vr.len());
            for ((r, k), x) in vr.iter().zip(order).zip(values) {
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
            Ok(Status::Ok)
        })
    }

    /// fmi2GetRealOutputDerivatives: first derivatives of outputs at the current time.
    pub fn get_real_output_derivatives(
        &mut self,
        vr: &[fmi2ValueReference],
        order: &[fmi2Integer],
        values: &mut [f64],
    ) -> Status {
        self.run(Function::GetRealOutputDerivatives, |inst| {
            same_length(("vr[]", vr.len()), ("order[]", order.len()))?;
            same_length(("vr[]", vr.len()), ("value[]", values.len()))?;
            for ((r, k), out) in vr.iter().zip(order).zip(values.iter_mut()) {
                let q = inst.quantity(*r)?;
                if *k < 1 || *k as u32 > MAX_OUTPUT_DERIVATIVE_ORDER {
                    return Err(format!(
                        "derivative order {k} of {}: only order 1 is provided",
                        inst.variable_name(*r)
                    ));
                }
                *out = inst.model.output_derivative(q).map_err(|e| e.to_string())?;
            }
            Ok(Status::Ok)
        })
    }

    /// fmi2DoStep: one communication step from `current` (the instance's time) by h > 0.
    pub fn do_step(&mut self, current: f64, h: f64, _no_set_state_prior: bool) -> Status {
        let standard = self.standard;
        self.run_described(
            Function::DoStep,
            move || {
                let name = Function::DoStep.name_in(standard);
                format!("{name}(t = {current}, h = {h})")
            },
            |inst| {
                inst.model.step(current, h).map_err(|e| e.to_string())?;
                Ok(Status::Ok)
            },
        )
    }

    /// fmi2CancelStep: steps are synchronous, there is never a step to cancel.
    pub fn cancel_step(&mut self) -> Status {
        self.run(Function::CancelStep, |_| Ok(Status::Error))
    }

    fn status_not_available(&mut self, function: Function, kind: fmi2StatusKind) -> Outcome {
        let text = format!(
            "{}: status kind {kind} is not available (steps are synchronous)",
            function.name_in(self.standard)
        );
        self.log(Status::Discard, Category::Warning, text);
        Ok(Status::Discard)
    }

    /// fmi2GetStatus: no asynchronous steps, `fmi2Discard`.
    pub fn get_status(&mut self, kind: fmi2StatusKind) -> Status {
        let function = Function::GetStatus;
        self.run(function, |inst| inst.status_not_available(function, kind))
    }

    /// fmi2GetRealStatus: `fmi2LastSuccessfulTime` is the instance's time.
    pub fn get_real_status(&mut self, kind: fmi2StatusKind, value: &mut f64) -> Status {
        let function = Function::GetRealStatus;
        self.run(function, |inst| {
            if kind == fmi2LastSuccessfulTime {
                *value = inst.model.time();
                return Ok(Status::Ok);
            }
            inst.status_not_available(function, kind)
        })
    }

    /// fmi2GetIntegerStatus: no Integer status, `fmi2Discard`.
    pub fn get_integer_status(&mut self, kind: fmi2StatusKind) -> Status {
        let function = Function::GetIntegerStatus;
        self.run(function, |inst| inst.status_not_available(function, kind))
    }

    /// fmi2GetBooleanStatus: `fmi2Terminated` is false (the FMU never asks to stop).
    pub fn get_boolean_status(&mut self, kind: fmi2StatusKind, value: &mut fmi2Boolean) -> Status {
        let function = Function::GetBooleanStatus;
        self.run(function, |inst| {
            if kind == fmi2Terminated {
                *value = 0;
                return Ok(Status::Ok);
            }
            inst.status_not_available(function, kind)
        })
    }

    /// fmi2GetStringStatus: no String status, `fmi2Discard`.
    pub fn get_string_status(&mut self, kind: fmi2StatusKind) -> Status {
        let function = Function::GetStringStatus;
        self.run(function, |inst| inst.status_not_available(function, kind))
    }
}

mod fmi3;
mod references;
mod state;
#[cfg(test)]
mod tests;
