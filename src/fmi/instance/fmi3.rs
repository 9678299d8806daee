//! The FMI 3.0 calls that differ from FMI 2.0 in their arguments: value references of arrays
//! and `time` ([`crate::fmu::fmi3`]), the instantiation from a resource directory, and the
//! functions of interface types and features this FMU does not have.
//!
//! Everything else (phases, error rule, state, stepping) is the FMI 2.0 instance's: FMI 3.0
//! co-simulation without event mode has the same state machine (its "Step Mode" is FMI 2.0's
//! "stepComplete").

use super::{same_length, Instance, InstantiateError};
use crate::fmi::logging::Category;
use crate::fmi::phase::{Function, Standard};
use crate::fmi::types::Status;
use crate::fmu::Fmi3Reference;
use crate::model::Resources;
use std::ffi::CStr;
use std::path::Path;

impl Instance {
    /// fmi3InstantiateCoSimulation: reads the resources in `resource_dir` (a directory path,
    /// FMI 3.0's `resourcePath`) and checks the instantiation token against them.
    pub fn instantiate_fmi3(
        name: Option<&CStr>,
        token: Option<&str>,
        resource_dir: Option<&str>,
        logging_on: bool,
    ) -> Result<Instance, InstantiateError> {
        let name = name
            .filter(|n| !n.to_bytes().is_empty())
            .ok_or(InstantiateError::Argument("instanceName is NULL or empty"))?;
        let dir = resource_dir.ok_or(InstantiateError::Argument(
            "resourcePath is NULL or not UTF-8",
        ))?;
        // A file: URI is accepted too (some importers pass one).
        let dir = if dir.starts_with("file:") {
            crate::fmi::resource_path(dir)?
        } else {
            Path::new(dir).to_path_buf()
        };
        let resources = Resources::read(&dir).map_err(InstantiateError::Resources)?;
        let expected = resources.guid();
        let token = token.ok_or(InstantiateError::Argument(
            "instantiationToken is NULL or not UTF-8",
        ))?;
        if token != expected {
            return Err(InstantiateError::Guid {
                argument: "instantiationToken",
                given: token.to_string(),
                expected,
                folder: dir,
            });
        }
        let mut instance = Instance::from_resources(name, &resources, logging_on)?;
        instance.standard = Standard::Fmi3;
        Ok(instance)
    }

    /// fmi3EnterInitializationMode: the start and stop time (as fmi2SetupExperiment) and
    /// initialization mode, in one call. The tolerance is not needed.
    pub fn enter_initialization_mode_fmi3(
        &mut self,
        _tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Status {
        self.run(Function::EnterInitializationMode, |inst| {
            inst.set_experiment(start_time, stop_time)?;
            inst.phase = crate::fmi::Phase::InitializationMode;
            Ok(Status::Ok)
        })
    }

    /// The standard this instance was made through.
    pub fn standard(&self) -> Standard {
        self.standard
    }

    /// The instance's time (fmi3DoStep's `lastSuccessfulTime`).
    pub fn time(&self) -> f64 {
        self.model.time()
    }

    /// What an FMI 3.0 value reference names, or why it names nothing.
    fn reference(&self, vr: u32) -> Result<Fmi3Reference, String> {
        self.layout.fmi3_reference(vr).ok_or_else(|| {
            format!("unknown value reference {vr} (an array is read or set as a whole, by its own)")
        })
    }

    /// Checks that every reference is a scalar (no `time`, no array): the FMI 2.0 value
    /// references are then the same, and the FMI 2.0 call takes them as they are.
    fn scalars_only(&self, vr: &[u32], what: &str) -> Result<(), String> {
        for &r in vr {
            if !matches!(self.reference(r)?, Fmi3Reference::Scalar(_)) {
                return Err(format!(
                    "only {what} are accepted here (value reference {r} is time or an array)"
                ));
            }
        }
        Ok(())
    }

    /// fmi3GetFloat64: scalars, `time` and the arrays (row-major). No allocation.
    pub fn get_float64(&mut self, vr: &[u32], values: &mut [f64]) -> Status {
        self.run(Function::GetReal, |inst| {
            // Forces are scalars, the same references as in FMI 2.0.
            if inst.get_forces_directly(vr, values) {
                return Ok(Status::Ok);
            }
            let mut count = 0usize;
            for &r in vr {
                count += match inst.reference(r)? {
                    Fmi3Reference::Array { count, .. } => count,
                    _ => 1,
                };
            }
            same_length(("values of vr[]", count), ("nValues", values.len()))?;
            let mut at = 0;
            for &r in vr {
                match inst.reference(r)? {
                    Fmi3Reference::Time => values[at] = inst.model.time(),
                    Fmi3Reference::Scalar(r) => values[at] = inst.real_value(r)?,
                    Fmi3Reference::Array { first, count } => {
                        // count = n^2 <= 10^6 references, all existing (layout invariant).
                        for k in 0..count {
                            values[at + k] = inst.real_value(first + k as u32)?;
                        }
                        at += count;
                        continue;
                    }
                }
                at += 1;
            }
            Ok(Status::Ok)
        })
    }

    /// fmi3SetFloat64: as fmi2SetReal; `time` and the arrays cannot be set.
    pub fn set_float64(&mut self, vr: &[u32], values: &[f64]) -> Status {
        // Inputs are scalars, the same references as in FMI 2.0.
        if self.step_references.all_inputs(vr) {
            return self.set_real(vr, values);
        }
        match self.scalars_only(vr, "parameters and inputs") {
            Ok(()) => self.set_real(vr, values),
            Err(message) => self.run(Function::SetReal, |_| Err(message)),
        }
    }

    /// fmi3GetDirectionalDerivative: `sensitivity = J seed` (as fmi2GetDirectionalDerivative).
    pub fn get_directional_derivative_fmi3(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Status {
        let checked = self
            .scalars_only(unknowns, "scalar unknowns")
            .and_then(|()| self.scalars_only(knowns, "scalar knowns"));
        match checked {
            Ok(()) => self.get_directional_derivative(unknowns, knowns, seed, sensitivity),
            Err(message) => self.run(Function::GetDirectionalDerivative, |_| Err(message)),
        }
    }

    /// fmi3GetOutputDerivatives (order 1): as fmi2GetRealOutputDerivatives.
    pub fn get_output_derivatives(
        &mut self,
        vr: &[u32],
        orders: &[i32],
        values: &mut [f64],
    ) -> Status {
        match self.scalars_only(vr, "scalar outputs") {
            Ok(()) => self.get_real_output_derivatives(vr, orders, values),
            Err(message) => self.run(Function::GetRealOutputDerivatives, |_| Err(message)),
        }
    }

    /// A call of a type this FMU has no variables of (`like` gives the phases: a getter or a
    /// setter): only an empty `vr` succeeds.
    pub fn no_variables_fmi3(&mut self, name: &'static str, like: Function, vr: &[u32]) -> Status {
        let refuse = !crate::fmi::allowed(like).contains(self.phase);
        let first = self.messages.len();
        let status = if refuse {
            self.log(
                Status::Error,
                Category::Error,
                format!(
                    "{name}: not allowed in phase {:?} (call refused)",
                    self.phase
                ),
            );
            Status::Error
        } else if let Some(r) = vr.first() {
            let kind = name
                .trim_start_matches("fmi3Get")
                .trim_start_matches("fmi3Set");
            let message = format!("{name}: this FMU has no {kind} variables (value reference {r})");
            self.log(Status::Error, Category::Error, message);
            self.phase = crate::fmi::Phase::Error;
            Status::Error
        } else {
            Status::Ok
        };
        self.log_call(first, status, || name.to_string());
        status
    }

    /// A function of an interface type or feature this FMU does not declare (model
    /// exchange, scheduled execution, event mode, clocks, configuration mode, adjoint
    /// derivatives, ...): refused with fmi3Error, the phase stays.
    pub fn unsupported_fmi3(&mut self, name: &'static str, why: &str) -> Status {
        let first = self.messages.len();
        self.log(
            Status::Error,
            Category::Error,
            format!("{name}: {why} (call refused)"),
        );
        self.log_call(first, Status::Error, || name.to_string());
        Status::Error
    }
}
