//! The radiation component: explicit state, exact stepping, outputs, energy. No FFI types.
//!
//! The water acts on the hull through the equivalent network of [`crate::realize`]:
//!
//! ```text
//! z' = A z + B v                        (z: spring elongations and aux velocities)
//! F  = C z + D v  [- A_inf a]           (force on the hull by the water)
//! power  = -F . v                        (power the hull delivers to the water)
//! energy = 1/2 z^T P z  [+ 1/2 v^T A_inf v]
//! ```
//!
//! The bracketed terms exist only when the FMU keeps `A_inf` (`keep_inf_mass` in the
//! resources; the `acceleration.<dof>` inputs then exist). By default the master adds
//! `A_inf` (`added_mass_inf`) to its own mass matrix instead. For a passive network
//! `d energy/dt = power - dissipation`, so the work done on the water always exceeds the
//! stored energy.
//!
//! Outputs always reflect the current inputs (direct feedthrough `D = -damping_direct`).
//! A step from t to t + h is exact for inputs held over the step, or ramped
//! (`v(t + s) = v + v' s`) when the master set input derivatives; afterwards the stored
//! inputs are the ramp's end values and the derivatives stay set until the master changes
//! them. `rho` and `g` rescale the network exactly ([`crate::network::Network::scaled`]).
//!
//! Layout (Rapier style), one file each: [`RadiationSystem`] (`system`) holds the matrices at
//! one rho, g; [`Stepper`] (`stepper`) holds the discretization cache and scratch memory;
//! `outputs` computes force, power, energy and their derivatives; `snapshot` writes and reads
//! the state bytes ([`Model::serialize`]). [`ModelState`] is the explicit state. [`Model`]
//! bundles them for the FMI layer; [`Model::new`] builds it from a [`Network`].
//!
//! Time: a step must start at the component's time (relative tolerance
//! [`TIME_TOLERANCE`] times the larger of |t| and h); the new time is `anchor + k h`
//! while the master keeps one step size (no drift from repeated additions), for at most
//! [`MAX_STEPS_SINCE_ANCHOR`] steps, where `k` as an f64 is still exact. A step may not end
//! past a defined stop time ([`Model::set_experiment`]; the same tolerance), nor beyond the
//! f64 range.
//!
//! Finite values only: a value read ([`Model::value`], [`Model::output_derivative`],
//! [`Model::partial_derivative`]) that is not finite is an error
//! ([`ModelError::NotFinite`]) naming it, never a number; so is a parameter change whose
//! calculated parameters overflow. A state replaces the current one only if it meets the
//! rules of `validate` ([`Model::set_state`], [`Model::deserialize`]).

pub mod crossflow;
#[cfg(test)]
mod crossflow_tests;
#[cfg(test)]
mod depth_tests;
#[cfg(test)]
pub(crate) mod drift_tests;
mod outputs;
mod snapshot;
mod stepper;
mod system;
#[cfg(test)]
pub(crate) mod tests;
mod validate;
pub mod viscous;
#[cfg(test)]
mod viscous_tests;

#[cfg(test)]
pub(crate) use snapshot::tests::{tampered, StateField};

pub use crate::fmu::resources::Resources;
pub use stepper::Stepper;
pub use system::RadiationSystem;

use crate::discretize::DiscretizeError;
use crate::fmu::description::{DEFAULT_G, DEFAULT_RHO};
use crate::fmu::resources::ResourcesError;
use crate::fmu::units::DofUnit;
use crate::fmu::variables::{Layout, Quantity, WaveParameter};
use crate::hull::Hull;
use crate::hydrostatics;
use crate::network::{Network, NetworkError};
use crate::units::WaterDepth;
use crate::waves::{DriftMode, DriftTable, ExcitationTable, Sea, SeaScratch, WaveKind, WaveParams};
use nalgebra::DMatrix;
use nalgebra::DVector;
use outputs::Outputs;
use std::fmt;
use std::path::{Path, PathBuf};
use system::{check_parameter, parse_network};

/// Parses `resources/drift.csv` and checks its modes against the network's DOFs `names`.
pub(crate) fn drift_table(text: &str, names: &[String]) -> Result<DriftTable, ModelError> {
    let source = format!("resources/{}", Resources::DRIFT_FILE);
    let table =
        DriftTable::from_csv_str(text, &source).map_err(|e| ModelError::Waves(e.to_string()))?;
    if table.modes() != names {
        return Err(ModelError::Waves(format!(
            "{source}: modes {} differ from the network's DOFs {}",
            table.modes().join(" "),
            names.join(" ")
        )));
    }
    Ok(table)
}

/// The water depth of the FMU's tables: the excitation table's, which the drift table (when
/// both exist) must share; deep water without tables. `excitation` and `drift` are the
/// tables with their names.
///
/// # Errors
/// Tables for different depths, naming both files and both depths.
pub(crate) fn tables_depth(
    excitation: Option<(&ExcitationTable, &str)>,
    drift: Option<(&DriftTable, &str)>,
) -> Result<WaterDepth, String> {
    match (excitation, drift) {
        (Some((x, x_name)), Some((d, d_name))) if x.depth() != d.depth() => Err(format!(
            "{x_name} is for water depth {} but {d_name} for {}: the tables packed together \
             must be computed for one depth",
            x.depth(),
            d.depth()
        )),
        (Some((x, _)), _) => Ok(x.depth()),
        (None, Some((d, _))) => Ok(d.depth()),
        (None, None) => Ok(WaterDepth::Infinite),
    }
}

/// Why `wave.drift` = `mode` is refused without a drift table.
fn no_drift_table(mode: DriftMode) -> String {
    format!(
        "wave.drift = {}: this FMU was packed without a drift table (resources/{}): only 0 \
         (no drift force) is accepted",
        mode.code(),
        Resources::DRIFT_FILE
    )
}

/// Relative tolerance on the communication point (times max(|t|, h)).
pub const TIME_TOLERANCE: f64 = 1e-10;

/// Largest magnitude accepted for an input, an input derivative or a parameter (SI). Far
/// beyond anything physical, and small enough that force, power and energy stay finite
/// (they are at most quadratic in the inputs); larger values are refused like NaN.
pub const MAX_INPUT: f64 = 1e100;

/// Most equal steps counted from one time anchor: up to 2^53 the count is exact as an f64,
/// so `anchor + k h` stays the time after k steps. The stepper starts a new anchor there
/// (2^53 steps of 1 us last 285 years); a restored state with a larger count is refused.
pub const MAX_STEPS_SINCE_ANCHOR: u64 = 1 << 53;

/// A finite value within [`MAX_INPUT`]: what an input, input derivative or parameter may be.
pub fn acceptable(value: f64) -> bool {
    value.is_finite() && value.abs() <= MAX_INPUT
}

/// Why a model call was refused. The state is unchanged whenever an error is returned.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ModelError {
    /// A resource file is missing or malformed.
    Resources(ResourcesError),
    /// The network cannot be realized.
    Network(NetworkError),
    /// The realized system does not fit together (no DOFs, sizes, non-finite values).
    System(String),
    /// A parameter value is out of range.
    Parameter {
        /// Parameter name.
        name: &'static str,
        /// Refused value.
        value: f64,
    },
    /// An input value is not finite.
    Input {
        /// What was set.
        what: String,
        /// Refused value.
        value: f64,
    },
    /// A variable that cannot be set or read this way.
    Variable(String),
    /// The step was refused or failed.
    Step(String),
    /// The step's discretization failed.
    Discretize(DiscretizeError),
    /// Serialized state bytes are corrupt or belong to another FMU.
    State(String),
    /// The waves or the hydrostatics cannot be set up (the resource tables, the sea).
    Waves(String),
    /// A value to be read or used is not finite: the parameters, inputs or state overflow
    /// f64 there. Nothing was changed.
    NotFinite {
        /// What overflowed (the FMU variable's name where there is one).
        what: String,
        /// The value (inf, -inf or NaN).
        value: f64,
    },
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModelError::Resources(e) => write!(f, "resources: {}", e.detail()),
            ModelError::Network(e) => write!(f, "network: {e}"),
            ModelError::System(m) => write!(f, "network: {m}"),
            ModelError::Parameter { name, value } => {
                write!(f, "parameter {name} = {value} is out of range")
            }
            ModelError::Input { what, value } => write!(
                f,
                "input {what} = {value:e} is not finite or exceeds {MAX_INPUT:e} in magnitude"
            ),
            ModelError::Variable(m) => write!(f, "{m}"),
            ModelError::Step(m) => write!(f, "step refused: {m}"),
            ModelError::Discretize(e) => write!(f, "step refused: {e}"),
            ModelError::State(m) => write!(f, "FMU state: {m}"),
            ModelError::Waves(m) => write!(f, "waves: {m}"),
            ModelError::NotFinite { what, value } => write!(
                f,
                "{what} is not finite ({value}): the parameters, inputs or state overflow f64 \
                 there; nothing was changed"
            ),
        }
    }
}

impl std::error::Error for ModelError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ModelError::Resources(e) => Some(e),
            ModelError::Network(e) => Some(e),
            ModelError::Discretize(e) => Some(e),
            _ => None,
        }
    }
}

impl From<DiscretizeError> for ModelError {
    fn from(e: DiscretizeError) -> Self {
        ModelError::Discretize(e)
    }
}

impl From<ResourcesError> for ModelError {
    fn from(e: ResourcesError) -> Self {
        ModelError::Resources(e)
    }
}

/// How [`Model::new`] builds the component from a network.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ModelOptions {
    /// The force includes `-A_inf a` and the acceleration inputs exist (else the master adds
    /// `added_mass_inf` to its own mass matrix).
    pub keep_inf_mass: bool,
    /// The GUID of the FMU the component belongs to (states of other GUIDs are refused).
    /// `None`: the content GUID of the network's canonical text and the options text,
    /// [`Resources::for_network`] without a hull: the GUID of an FMU packed with exactly
    /// those two resource files.
    pub guid: Option<String>,
}

/// The explicit state of the component.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelState {
    /// Water density in use.
    pub rho: f64,
    /// Gravity in use.
    pub g: f64,
    /// Current time (s).
    pub time: f64,
    /// Time at which the current run of equal steps started.
    pub time_anchor: f64,
    /// Size of the last step (0 before the first).
    pub last_step: f64,
    /// Number of steps of size `last_step` since `time_anchor`.
    pub steps_since_anchor: u64,
    /// Network state z.
    pub network: DVector<f64>,
    /// Hull velocities v (inputs).
    pub velocity: DVector<f64>,
    /// dv/dt set by the master (first-order hold).
    pub velocity_derivative: DVector<f64>,
    /// Hull accelerations (inputs, keep_inf_mass only; zero otherwise).
    pub acceleration: DVector<f64>,
    /// d(acceleration)/dt set by the master.
    pub acceleration_derivative: DVector<f64>,
    /// The incident waves (parameters; calm water by default).
    pub waves: WaveParams,
    /// Start time of the run (the waves' ramp starts here).
    pub start_time: f64,
    /// Stop time of the run, if the master defined one: no step may end after it. Part of
    /// the state like the start time, so a restored state keeps the experiment it was saved in.
    pub stop_time: Option<f64>,
    /// The current `[current.speed (m/s), current.heading (deg)]` of an FMU with viscous
    /// damping (inputs, zero otherwise): a restored state sees the current it was saved with.
    pub current: [f64; 2],
}

impl ModelState {
    /// Rest at time 0 with the default rho and g.
    pub fn rest(dofs: usize, states: usize) -> ModelState {
        ModelState {
            rho: DEFAULT_RHO,
            g: DEFAULT_G,
            time: 0.0,
            time_anchor: 0.0,
            last_step: 0.0,
            steps_since_anchor: 0,
            network: DVector::zeros(states),
            velocity: DVector::zeros(dofs),
            velocity_derivative: DVector::zeros(dofs),
            acceleration: DVector::zeros(dofs),
            acceleration_derivative: DVector::zeros(dofs),
            waves: WaveParams::default(),
            start_time: 0.0,
            stop_time: None,
            current: [0.0; 2],
        }
    }

    /// The vectors in the order of the state bytes: z, v, v', a, a'.
    pub(super) fn vectors(&self) -> [&DVector<f64>; 5] {
        [
            &self.network,
            &self.velocity,
            &self.velocity_derivative,
            &self.acceleration,
            &self.acceleration_derivative,
        ]
    }
}

/// The radiation component: reference network, system at the current rho and g, stepper and
/// state.
#[derive(Clone, Debug)]
pub struct Model {
    network: Network,
    guid: String,
    system: RadiationSystem,
    stepper: Stepper,
    state: ModelState,
    outputs: Outputs,
    outputs_valid: bool,
    work: DVector<f64>,
    branch_forces: DVector<f64>,
    /// The exciting force table of `resources/excitation.csv` (DOFs in the network's order).
    excitation: Option<ExcitationTable>,
    /// The mean drift table of `resources/drift.csv` (DOFs in the network's order).
    drift: Option<DriftTable>,
    /// The viscous damping of `resources/viscous.csv` with the current.
    viscous: Option<viscous::Viscous>,
    /// `C / (rho g)` from `resources/hull.xml`, in the network's DOF order.
    hydrostatics_per_rho_g: Option<DMatrix<f64>>,
    /// The sea of the state's wave parameters, once [`Model::start_waves`] has built it
    /// (fixed by the state: rebuilt on restore); its scratch is a phasor cache only.
    sea: Option<(Sea, SeaScratch)>,
    /// Whether [`Model::start_waves`] ran (initialization ended): restored states then get
    /// their sea.
    waves_started: bool,
    /// The water depth the tables were computed for (`depth`; deep water without tables).
    depth: WaterDepth,
}

impl Model {
    /// The component for a network (at any reference rho, g), at the default rho and g.
    pub fn new(network: &Network, options: ModelOptions) -> Result<Model, ModelError> {
        let guid = match options.guid {
            Some(guid) => guid,
            None => Resources::for_network(network, None, options.keep_inf_mass).guid(),
        };
        let system =
            RadiationSystem::realize(network, options.keep_inf_mass, DEFAULT_RHO, DEFAULT_G)?;
        let stepper = Stepper::new(&system)?;
        let n = system.dof_count();
        let ns = system.state_size();
        let mut model = Model {
            network: network.clone(),
            guid,
            state: ModelState::rest(n, ns),
            stepper,
            outputs: Outputs::zeros(n),
            outputs_valid: false,
            work: DVector::zeros(ns),
            branch_forces: DVector::zeros(system.branch_count()),
            system,
            excitation: None,
            drift: None,
            viscous: None,
            hydrostatics_per_rho_g: None,
            sea: None,
            waves_started: false,
            depth: WaterDepth::Infinite,
        };
        model.refresh();
        Ok(model)
    }

    /// Loads the component from an FMU's `resources/` folder, at the default rho and g.
    pub fn load(resource_dir: &Path) -> Result<Model, ModelError> {
        let resources = Resources::read(resource_dir)?;
        Model::from_resources(&resources)
    }

    /// The component from resource texts, at the default rho and g; its GUID is
    /// [`Resources::guid`].
    pub fn from_resources(resources: &Resources) -> Result<Model, ModelError> {
        let network = parse_network(&resources.network_xml)?;
        let options = ModelOptions {
            keep_inf_mass: resources.keep_inf_mass,
            guid: Some(resources.guid()),
        };
        let mut model = Model::new(&network, options)?;
        let names = model.dof_names().to_vec();
        if let Some(text) = &resources.excitation_csv {
            let source = format!("resources/{}", Resources::EXCITATION_FILE);
            let table = ExcitationTable::from_csv_str(text, &source)
                .map_err(|e| ModelError::Waves(e.to_string()))?;
            if table.modes() != names.as_slice() {
                return Err(ModelError::Waves(format!(
                    "{source}: modes {} differ from the network's DOFs {}",
                    table.modes().join(" "),
                    names.join(" ")
                )));
            }
            model.excitation = Some(table);
        }
        if let Some(text) = &resources.drift_csv {
            model.drift = Some(drift_table(text, &names)?);
        }
        let excitation_name = format!("resources/{}", Resources::EXCITATION_FILE);
        let drift_name = format!("resources/{}", Resources::DRIFT_FILE);
        model.depth = tables_depth(
            model
                .excitation
                .as_ref()
                .map(|t| (t, excitation_name.as_str())),
            model.drift.as_ref().map(|t| (t, drift_name.as_str())),
        )
        .map_err(ModelError::Waves)?;
        if let Some(text) = &resources.viscous_csv {
            let (frame, linear, quadratic) =
                viscous::parse_csv(text, &names).map_err(ModelError::Variable)?;
            let mut damping = viscous::Viscous::new(&names, frame, linear, quadratic)
                .map_err(ModelError::Variable)?;
            if let Some(text) = &resources.crossflow_csv {
                damping = damping.with_crossflow(
                    viscous::crossflow_of(text, &names, frame).map_err(ModelError::Variable)?,
                );
            }
            model.set_viscous(Some(damping));
        } else if resources.crossflow_csv.is_some() {
            return Err(ModelError::Variable(
                "resources/crossflow.csv without resources/viscous.csv".into(),
            ));
        }
        if let Some(text) = &resources.hydrostatics_csv {
            let source = format!("resources/{}", Resources::HYDROSTATICS_FILE);
            let table = hydrostatics::Table::from_csv_str(text, &source)
                .map_err(|e| ModelError::Waves(e.to_string()))?;
            if table.modes != names {
                return Err(ModelError::Waves(format!(
                    "{source}: modes {} differ from the network's DOFs {}",
                    table.modes.join(" "),
                    names.join(" ")
                )));
            }
            model.hydrostatics_per_rho_g = Some(table.stiffness_per_rho_g);
            model.check_hydrostatics(DEFAULT_RHO, DEFAULT_G)?;
        } else if let Some(text) = &resources.hull_xml {
            let source = format!("resources/{}", Resources::HULL_FILE);
            let hull =
                Hull::from_xml_str(text, &source).map_err(|e| ModelError::Waves(e.to_string()))?;
            let restoring =
                hydrostatics::stiffness(&hull).map_err(|e| ModelError::Waves(e.to_string()))?;
            let hull_names = hull.dof_names();
            let index: Option<Vec<usize>> = names
                .iter()
                .map(|n| hull_names.iter().position(|h| h == n))
                .collect();
            // A network whose DOFs the hull does not name (packed from a network file for
            // another hull) gets no hydrostatics: `stiffness_hydrostatic` reads zeros.
            if let Some(index) = index {
                let c = &restoring.stiffness_per_rho_g;
                model.hydrostatics_per_rho_g =
                    Some(DMatrix::from_fn(names.len(), names.len(), |i, j| {
                        c[(index[i], index[j])]
                    }));
                model.check_hydrostatics(DEFAULT_RHO, DEFAULT_G)?;
            }
        }
        Ok(model)
    }

    /// Whether the sea has been started ([`Model::start_waves`]).
    pub fn waves_started(&self) -> bool {
        self.waves_started
    }

    /// Builds the sea of the wave parameters (when initialization ends: the parameters, rho,
    /// g and the start time are final). Returns the sea's notes (fallbacks, energy left
    /// out). Calm water needs no table; waves without one are an error naming the cause.
    pub fn start_waves(&mut self) -> Result<Vec<String>, ModelError> {
        if let Some(viscous) = &self.viscous {
            viscous.check().map_err(ModelError::Variable)?;
        }
        let sea = self.build_sea(&self.state)?;
        let notes = sea.as_ref().map(|s| s.notes().to_vec()).unwrap_or_default();
        self.sea = sea.map(|s| {
            let scratch = s.scratch();
            (s, scratch)
        });
        self.waves_started = true;
        self.outputs_valid = false;
        Ok(notes)
    }

    fn build_sea(&self, state: &ModelState) -> Result<Option<Sea>, ModelError> {
        if state.waves.kind == WaveKind::Calm {
            return Ok(None);
        }
        let Some(table) = &self.excitation else {
            return Err(ModelError::Waves(
                "wave.kind is not 0 (calm water), but this FMU was packed without an \
                 excitation table (resources/excitation.csv)"
                    .into(),
            ));
        };
        let sea = Sea::new(
            &state.waves,
            Some(table),
            state.rho,
            state.g,
            state.start_time,
        );
        let sea = match (&self.drift, state.waves.drift) {
            (_, DriftMode::Off) => sea,
            (Some(drift), mode) => {
                sea.and_then(|s| s.with_drift(&state.waves, drift, mode, state.rho, state.g))
            }
            (None, _) => return Err(ModelError::Waves(no_drift_table(state.waves.drift))),
        };
        sea.map(Some).map_err(|e| ModelError::Waves(e.to_string()))
    }

    /// The drift force on every DOF at the current time (zeros in calm water or with
    /// `wave.drift` = 0).
    pub fn force_drift(&mut self) -> &DVector<f64> {
        self.refresh();
        &self.outputs.drift
    }

    /// The mean drift table the FMU was packed with, if any.
    pub fn drift_table(&self) -> Option<&DriftTable> {
        self.drift.as_ref()
    }

    /// The exciting force of the waves on every DOF at the current time (zeros in calm water).
    pub fn force_excitation(&mut self) -> &DVector<f64> {
        self.refresh();
        &self.outputs.excitation
    }

    /// The radiation force on every DOF (the network's force).
    pub fn force_radiation(&mut self) -> &DVector<f64> {
        self.refresh();
        &self.outputs.radiation
    }

    /// The wave elevation at x = 0 at the current time (m).
    pub fn wave_elevation(&mut self) -> f64 {
        self.refresh();
        self.outputs.elevation
    }

    /// The exciting force table the FMU was packed with, if any.
    pub fn excitation(&self) -> Option<&ExcitationTable> {
        self.excitation.as_ref()
    }

    /// The hydrostatic restoring `C` at the current rho and g (zeros when the FMU was packed
    /// without its hull).
    pub fn stiffness_hydrostatic(&self) -> DMatrix<f64> {
        let n = self.dof_count();
        self.hydrostatics_per_rho_g.as_ref().map_or_else(
            || DMatrix::zeros(n, n),
            |c| c * (self.state.rho * self.state.g),
        )
    }

    /// Refuses rho and g at which `stiffness_hydrostatic` (`C / (rho g)` times rho g) is not
    /// finite, naming the entry.
    fn check_hydrostatics(&self, rho: f64, g: f64) -> Result<(), ModelError> {
        let Some(c) = &self.hydrostatics_per_rho_g else {
            return Ok(());
        };
        let n = c.nrows();
        match c
            .iter()
            .enumerate()
            .find(|(_, x)| !(*x * (rho * g)).is_finite())
        {
            Some((k, x)) => Err(ModelError::NotFinite {
                what: format!(
                    "stiffness_hydrostatic[{},{}] at rho = {rho:e}, g = {g:e}",
                    k % n + 1,
                    k / n + 1
                ),
                value: x * (rho * g),
            }),
            None => Ok(()),
        }
    }

    /// The FMU variables of this component (DOF length exponents 0: units are the
    /// archive's business), with the drift and viscous variables it was packed with.
    pub fn layout(&self) -> Result<Layout, crate::fmu::variables::VariablesError> {
        let dofs = self
            .dof_names()
            .iter()
            .map(|name| DofUnit::new(name, 0, false))
            .collect();
        let mut layout = Layout::new(dofs, self.system.keep_inf_mass)?;
        if self.drift.is_some() {
            layout = layout.with_drift()?;
        }
        if let Some(v) = &self.viscous {
            layout = layout.with_viscous(&v.linear, &v.quadratic)?;
            if v.crossflow().is_some() {
                layout = layout.with_crossflow()?;
            }
        }
        if let WaterDepth::Finite(depth) = self.depth {
            layout = layout.with_depth(depth)?;
        }
        Ok(layout)
    }

    /// The water depth the tables were computed for (the fixed parameter `depth`).
    pub fn depth(&self) -> WaterDepth {
        self.depth
    }

    /// Whether `depth` may be set to `value`: only the packed depth is accepted (the tables
    /// were computed for it).
    pub fn check_depth(&self, value: f64) -> Result<(), ModelError> {
        match self.depth {
            WaterDepth::Finite(depth) if value == depth => Ok(()),
            WaterDepth::Finite(depth) => Err(ModelError::Variable(format!(
                "depth = {value} m refused: the FMU's tables were computed for depth = {depth} m \
                 (a fixed parameter: pack the FMU again with --water-depth for another depth)"
            ))),
            WaterDepth::Infinite => Err(ModelError::Variable(
                "depth: this FMU is for deep water and declares no depth".into(),
            )),
        }
    }

    /// The FMU variable name of `quantity` (`force.heave`, `added_mass_inf[1,2]`, ...), for
    /// messages; its Debug form where the layout has no such variable.
    pub fn variable_name(&self, quantity: Quantity) -> String {
        self.layout()
            .ok()
            .and_then(|layout| {
                let reference = layout.value_reference(quantity)?;
                Some(layout.variable(reference)?.name.clone())
            })
            .unwrap_or_else(|| format!("{quantity:?}"))
    }

    /// `value` if it is finite, else [`ModelError::NotFinite`] naming `what`.
    fn finite(what: impl FnOnce() -> String, value: f64) -> Result<f64, ModelError> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(ModelError::NotFinite {
                what: what(),
                value,
            })
        }
    }

    /// Resource folder of an FMU from its unzipped root.
    pub fn resource_dir(fmu_root: &Path) -> PathBuf {
        fmu_root.join("resources")
    }

    /// GUID implied by the resources.
    pub fn guid(&self) -> &str {
        &self.guid
    }
    /// The system at the current rho and g.
    pub fn system(&self) -> &RadiationSystem {
        &self.system
    }
    /// The explicit state.
    pub fn state(&self) -> &ModelState {
        &self.state
    }
    /// DOF names.
    pub fn dof_names(&self) -> &[String] {
        &self.system.dof_names
    }
    /// Number of DOFs.
    pub fn dof_count(&self) -> usize {
        self.system.dof_count()
    }
    /// Current time.
    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// Replaces the state, if it meets the rules of `validate` (dimensions, finite values
    /// within their limits, a consistent time); rho or g changes re-realize. On error
    /// nothing changes.
    pub fn set_state(&mut self, state: ModelState) -> Result<(), ModelError> {
        self.set_state_and_waves(state, self.waves_started)
    }

    /// As [`Model::set_state`], with the sea started (`waves_started`: built from the state's
    /// wave parameters, as [`Model::start_waves`] does) or not: a state saved after
    /// initialization brings its sea into an instance that was only instantiated.
    pub fn set_state_and_waves(
        &mut self,
        state: ModelState,
        waves_started: bool,
    ) -> Result<(), ModelError> {
        let system = self.check_state(&state)?;
        let stepper = system.as_ref().map(Stepper::new).transpose()?;
        // The sea of the restored parameters, built before anything changes.
        let sea = if waves_started {
            self.build_sea(&state)?
        } else {
            None
        };
        self.waves_started = waves_started;
        if let (Some(system), Some(stepper)) = (system, stepper) {
            self.system = system;
            self.stepper = stepper;
        }
        self.sea = sea.map(|s| {
            let scratch = s.scratch();
            (s, scratch)
        });
        if let Some(viscous) = self.viscous.as_mut() {
            // Checked finite by check_state.
            viscous
                .set_current(state.current[0], state.current[1])
                .map_err(ModelError::State)?;
        }
        self.state = state;
        self.outputs_valid = false;
        Ok(())
    }

    /// Rest state, default rho and g, time 0.
    pub fn reset(&mut self) -> Result<(), ModelError> {
        let rest = ModelState::rest(self.dof_count(), self.system.state_size());
        self.waves_started = false;
        self.set_state(rest)
    }

    /// Sets the start time, without a stop time (only meaningful before the first step).
    pub fn set_start_time(&mut self, time: f64) -> Result<(), ModelError> {
        self.set_experiment(time, None)
    }

    /// Sets the start time and the stop time of the run (fmi2SetupExperiment; only
    /// meaningful before the first step). No step may end past a defined stop time (within
    /// [`TIME_TOLERANCE`]); `None` or +inf: no stop time.
    pub fn set_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), ModelError> {
        if !start.is_finite() {
            return Err(ModelError::Step(format!(
                "start time {start} is not finite"
            )));
        }
        let stop = stop.filter(|t| *t != f64::INFINITY);
        if let Some(stop) = stop {
            if stop.is_nan() || stop < start {
                return Err(ModelError::Step(format!(
                    "stop time {stop} is not a time at or after the start time {start}"
                )));
            }
        }
        self.state.time = start;
        self.state.start_time = start;
        self.state.stop_time = stop;
        self.state.time_anchor = start;
        self.state.last_step = 0.0;
        self.state.steps_since_anchor = 0;
        Ok(())
    }

    /// The system at rho, g, if it and `stiffness_hydrostatic` there are finite.
    fn realize_at(&self, rho: f64, g: f64) -> Result<RadiationSystem, ModelError> {
        let system = RadiationSystem::realize(&self.network, self.system.keep_inf_mass, rho, g)?;
        self.check_hydrostatics(rho, g)?;
        Ok(system)
    }

    fn rebuild(&mut self, rho: f64, g: f64) -> Result<(), ModelError> {
        let system = self.realize_at(rho, g)?;
        let stepper = Stepper::new(&system)?;
        self.system = system;
        self.stepper = stepper;
        self.outputs_valid = false;
        Ok(())
    }

    /// Sets rho and g (re-realizes the network exactly).
    pub fn set_parameters(&mut self, rho: f64, g: f64) -> Result<(), ModelError> {
        check_parameter("rho", rho)?;
        check_parameter("g", g)?;
        self.rebuild(rho, g)?;
        self.state.rho = rho;
        self.state.g = g;
        Ok(())
    }

    /// A wave parameter's value (Integer parameters as their exact f64 value).
    pub fn wave_parameter(&self, parameter: WaveParameter) -> f64 {
        let w = &self.state.waves;
        match parameter {
            WaveParameter::Kind => f64::from(w.kind.code()),
            WaveParameter::Height => w.height,
            WaveParameter::Period => w.period,
            WaveParameter::Heading => w.heading,
            WaveParameter::Gamma => w.gamma,
            WaveParameter::Seed => f64::from(w.seed),
            // At most MAX_COMPONENTS: exact in f64.
            WaveParameter::Components => w.components as f64,
            WaveParameter::Ramp => w.ramp,
            WaveParameter::Drift => f64::from(w.drift.code()),
        }
    }

    /// Sets a Real wave parameter; the parameters stay valid (`WaveParams::validate`), else
    /// nothing changes.
    pub fn set_wave_real(
        &mut self,
        parameter: WaveParameter,
        value: f64,
    ) -> Result<(), ModelError> {
        let mut waves = self.state.waves.clone();
        match parameter {
            WaveParameter::Height => waves.height = value,
            WaveParameter::Period => waves.period = value,
            WaveParameter::Heading => waves.heading = value,
            WaveParameter::Gamma => waves.gamma = value,
            WaveParameter::Ramp => waves.ramp = value,
            other => {
                return Err(ModelError::Variable(format!(
                    "{other:?} is an Integer parameter: set it with fmi2SetInteger or fmi3SetInt32"
                )))
            }
        }
        self.accept_waves(waves)
    }

    /// Sets an Integer wave parameter; as [`Model::set_wave_real`].
    pub fn set_wave_integer(
        &mut self,
        parameter: WaveParameter,
        value: i32,
    ) -> Result<(), ModelError> {
        let mut waves = self.state.waves.clone();
        match parameter {
            WaveParameter::Kind => {
                waves.kind =
                    WaveKind::from_code(value).map_err(|e| ModelError::Variable(e.to_string()))?
            }
            WaveParameter::Seed => waves.seed = value,
            WaveParameter::Drift => {
                let mode =
                    DriftMode::from_code(value).map_err(|e| ModelError::Variable(e.to_string()))?;
                if mode != DriftMode::Off && self.drift.is_none() {
                    return Err(ModelError::Variable(no_drift_table(mode)));
                }
                waves.drift = mode;
            }
            WaveParameter::Components => {
                waves.components = usize::try_from(value).map_err(|_| {
                    ModelError::Variable(format!("wave.components = {value}: must be at least 1"))
                })?
            }
            other => {
                return Err(ModelError::Variable(format!(
                    "{other:?} is a Real parameter: set it with fmi2SetReal or fmi3SetFloat64"
                )))
            }
        }
        self.accept_waves(waves)
    }

    /// Puts back wave parameters saved from [`Model::state`] (they were valid then).
    pub fn restore_waves(&mut self, waves: WaveParams) {
        self.state.waves = waves;
        self.outputs_valid = false;
    }

    fn accept_waves(&mut self, waves: WaveParams) -> Result<(), ModelError> {
        waves
            .validate()
            .map_err(|e| ModelError::Variable(e.to_string()))?;
        // A heading the excitation table lacks is refused when it is set (a section's table
        // has 0 and 180, a ship's the headings it was swept for). Only a new heading: the
        // declared start value 0 may be missing from a ship's table, and setting another wave
        // parameter first must not fail on it (the sea checks the heading it is built with).
        let heading_set = waves.heading.to_bits() != self.state.waves.heading.to_bits();
        if let Some(table) = self.excitation.as_ref().filter(|_| heading_set) {
            if table.heading_index(waves.heading).is_none() {
                return Err(ModelError::Variable(format!(
                    "wave.heading = {} deg: the excitation table has no such heading (it has \
                     {:?}, modulo 360)",
                    waves.heading,
                    table.headings()
                )));
            }
        }
        self.state.waves = waves;
        self.outputs_valid = false;
        Ok(())
    }

    /// Sets a settable variable: rho, g, a velocity or an acceleration.
    pub fn set_value(&mut self, quantity: Quantity, value: f64) -> Result<(), ModelError> {
        let n = self.dof_count();
        let refuse = |what: &str, i: usize| ModelError::Input {
            what: format!("{what}.{}", self.system.dof_names[i]),
            value,
        };
        match quantity {
            Quantity::Rho => self.set_parameters(value, self.state.g)?,
            Quantity::G => self.set_parameters(self.state.rho, value)?,
            Quantity::Depth => return self.check_depth(value),
            Quantity::Velocity(i) if i < n => {
                if !acceptable(value) {
                    return Err(refuse("velocity", i));
                }
                self.state.velocity[i] = value;
            }
            Quantity::Acceleration(i) if i < n && self.system.keep_inf_mass => {
                if !acceptable(value) {
                    return Err(refuse("acceleration", i));
                }
                self.state.acceleration[i] = value;
            }
            Quantity::CurrentSpeed
            | Quantity::CurrentHeading
            | Quantity::DampingLinear(..)
            | Quantity::DampingQuadratic(_)
            | Quantity::CrossflowDragScale
                if self.viscous.is_some() =>
            {
                self.set_viscous_value(quantity, value)?
            }
            other => {
                return Err(ModelError::Variable(format!("{other:?} cannot be set")));
            }
        }
        self.outputs_valid = false;
        Ok(())
    }

    /// Sets the first time derivative of an input (first-order hold over the next steps).
    pub fn set_input_derivative(
        &mut self,
        quantity: Quantity,
        value: f64,
    ) -> Result<(), ModelError> {
        if !acceptable(value) {
            return Err(ModelError::Input {
                what: format!("derivative of {quantity:?}"),
                value,
            });
        }
        let n = self.dof_count();
        match quantity {
            Quantity::Velocity(i) if i < n => self.state.velocity_derivative[i] = value,
            Quantity::Acceleration(i) if i < n && self.system.keep_inf_mass => {
                self.state.acceleration_derivative[i] = value
            }
            other => {
                return Err(ModelError::Variable(format!(
                    "{other:?} is not an input with derivatives"
                )))
            }
        }
        self.outputs_valid = false;
        Ok(())
    }

    /// Advances from `current` (must match the component's time) by h. On error the state
    /// is unchanged.
    pub fn step(&mut self, current: f64, h: f64) -> Result<(), ModelError> {
        self.stepper.step(&mut self.state, current, h)?;
        self.outputs_valid = false;
        Ok(())
    }
}
