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
//! them. `rho` and `g` rescale the network exactly ([`crate::realize::Network::scaled`]).
//!
//! Layout (Rapier style): [`RadiationSystem`] holds the matrices at one rho, g;
//! [`Stepper`] holds the discretization cache and scratch memory; [`ModelState`] is the
//! explicit state. [`Model`] bundles them for the FMI layer.
//!
//! Time: a step must start at the component's time (relative tolerance
//! [`TIME_TOLERANCE`] times the larger of |t| and h); the new time is `anchor + k h`
//! while the master keeps one step size (no drift from repeated additions).
//!
//! State bytes ([`Model::serialize`]): little-endian, `HYDROFMU`, format version, an owner's
//! tag byte, the GUID, the dimensions, rho, g, the time bookkeeping, z, the inputs and their
//! derivatives, then an FNV-1a 64 checksum of everything before it.

use crate::discretize::{BlockDiscretizationCache, DiscretizeError, LinearMap};
use crate::model_description::{DEFAULT_G, DEFAULT_RHO, PARAMETERS};
use crate::realize::Network;
use crate::variables::{content_guid, Quantity};
use nalgebra::{DMatrix, DVector};
use std::fmt;
use std::ops::Not;
use std::path::{Path, PathBuf};

/// Relative tolerance on the communication point (times max(|t|, h)).
pub const TIME_TOLERANCE: f64 = 1e-10;

/// Largest magnitude accepted for an input, an input derivative or a parameter (SI). Far
/// beyond anything physical, and small enough that force, power and energy stay finite
/// (they are at most quadratic in the inputs); larger values are refused like NaN.
pub const MAX_INPUT: f64 = 1e100;

/// A finite value within [`MAX_INPUT`]: what an input, input derivative or parameter may be.
pub fn acceptable(value: f64) -> bool {
    value.is_finite() && value.abs() <= MAX_INPUT
}

/// Why a model call was refused. The state is unchanged whenever an error is returned.
#[derive(Clone, Debug, PartialEq)]
pub enum ModelError {
    /// A resource file is missing or malformed.
    Resources(String),
    /// The network cannot be used.
    Network(String),
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
    /// Serialized state bytes are corrupt or belong to another FMU.
    State(String),
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModelError::Resources(m) => write!(f, "resources: {m}"),
            ModelError::Network(m) => write!(f, "network: {m}"),
            ModelError::Parameter { name, value } => {
                write!(f, "parameter {name} = {value} is out of range")
            }
            ModelError::Input { what, value } => write!(
                f,
                "input {what} = {value:e} is not finite or exceeds {MAX_INPUT:e} in magnitude"
            ),
            ModelError::Variable(m) => write!(f, "{m}"),
            ModelError::Step(m) => write!(f, "step refused: {m}"),
            ModelError::State(m) => write!(f, "FMU state: {m}"),
        }
    }
}

impl std::error::Error for ModelError {}

impl From<DiscretizeError> for ModelError {
    fn from(e: DiscretizeError) -> Self {
        ModelError::Step(e.to_string())
    }
}

/// The files in an FMU's `resources/` folder.
#[derive(Clone, Debug, PartialEq)]
pub struct Resources {
    /// Text of `network.xml`.
    pub network_xml: String,
    /// Text of `hull.xml`, when the hull is known.
    pub hull_xml: Option<String>,
    /// Text of `options.xml`.
    pub options_xml: String,
    /// Whether the force includes `-A_inf a` (from `options.xml`).
    pub keep_inf_mass: bool,
}

impl Resources {
    /// The network file.
    pub const NETWORK_FILE: &'static str = "network.xml";
    /// The hull file (optional).
    pub const HULL_FILE: &'static str = "hull.xml";
    /// The options file.
    pub const OPTIONS_FILE: &'static str = "options.xml";

    /// The options file text for these flags.
    pub fn options_text(keep_inf_mass: bool) -> String {
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<hydrofmu_options format=\"1\" keep_inf_mass=\"{keep_inf_mass}\"/>\n"
        )
    }

    /// Resources from their texts (checks the options file).
    pub fn new(
        network_xml: String,
        hull_xml: Option<String>,
        options_xml: String,
    ) -> Result<Resources, ModelError> {
        let keep_inf_mass = parse_options(&options_xml)?;
        Ok(Resources {
            network_xml,
            hull_xml,
            options_xml,
            keep_inf_mass,
        })
    }

    /// Reads the resources folder.
    pub fn read(dir: &Path) -> Result<Resources, ModelError> {
        let read = |name: &str| {
            std::fs::read_to_string(dir.join(name)).map_err(|e| {
                ModelError::Resources(format!("cannot read {}: {e}", dir.join(name).display()))
            })
        };
        let network = read(Self::NETWORK_FILE)?;
        let options = read(Self::OPTIONS_FILE)?;
        let hull_path = dir.join(Self::HULL_FILE);
        let hull = if hull_path.exists() {
            Some(read(Self::HULL_FILE)?)
        } else {
            None
        };
        Resources::new(network, hull, options)
    }

    /// The GUID these resources imply ([`content_guid`]).
    pub fn guid(&self) -> String {
        let mut parts: Vec<(&str, &[u8])> = vec![(Self::NETWORK_FILE, self.network_xml.as_bytes())];
        if let Some(h) = &self.hull_xml {
            parts.push((Self::HULL_FILE, h.as_bytes()));
        }
        parts.push((Self::OPTIONS_FILE, self.options_xml.as_bytes()));
        content_guid(&parts)
    }
}

fn parse_options(text: &str) -> Result<bool, ModelError> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(text);
    loop {
        match reader.read_event() {
            Err(e) => return Err(ModelError::Resources(format!("options.xml: {e}"))),
            Ok(Event::Eof) => {
                return Err(ModelError::Resources(
                    "options.xml has no <hydrofmu_options>".into(),
                ))
            }
            Ok(Event::Start(e)) | Ok(Event::Empty(e))
                if e.name().as_ref() == b"hydrofmu_options" =>
            {
                let mut keep = None;
                let mut format = None;
                for a in e.attributes() {
                    let a = a.map_err(|e| ModelError::Resources(format!("options.xml: {e}")))?;
                    let value = String::from_utf8_lossy(&a.value).into_owned();
                    match a.key.as_ref() {
                        b"keep_inf_mass" => keep = Some(value),
                        b"format" => format = Some(value),
                        _ => {}
                    }
                }
                if format.as_deref() != Some("1") {
                    return Err(ModelError::Resources(format!(
                        "options.xml: format {format:?}, expected \"1\""
                    )));
                }
                return match keep.as_deref() {
                    Some("true") => Ok(true),
                    Some("false") => Ok(false),
                    other => Err(ModelError::Resources(format!(
                        "options.xml: keep_inf_mass = {other:?}, expected true or false"
                    ))),
                };
            }
            Ok(_) => {}
        }
    }
}

/// The realized system at one rho and g (immutable).
#[derive(Clone, Debug, PartialEq)]
pub struct RadiationSystem {
    dof_names: Vec<String>,
    keep_inf_mass: bool,
    rho: f64,
    g: f64,
    added_mass_inf: DMatrix<f64>,
    damping_direct: DMatrix<f64>,
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    c: DMatrix<f64>,
    d: DMatrix<f64>,
    energy_weight: DMatrix<f64>,
    /// Branch input matrix `B_r` (`B = B_r P`), what the stepper discretizes.
    b_branch: DMatrix<f64>,
    /// The states of each branch (independent blocks of `A`).
    branch_states: Vec<Vec<usize>>,
    /// `P` (branch directions as rows, r x n): branch speeds `s = P v`.
    branch_projection: DMatrix<f64>,
    /// `C_r` by non-zeros: force along each branch `f_r = C_r z`, so that
    /// `F = P^T f_r + D v` (without the A_inf term).
    branch_force: LinearMap,
}

fn check_parameter(name: &'static str, value: f64) -> Result<(), ModelError> {
    let min = PARAMETERS
        .iter()
        .find(|p| p.name == name)
        .map(|p| p.min)
        .unwrap_or(0.0);
    if acceptable(value) && value >= min {
        Ok(())
    } else {
        Err(ModelError::Parameter { name, value })
    }
}

impl RadiationSystem {
    /// Loads `resources/network.xml` and realizes it at rho, g.
    pub fn load(resource_dir: &Path, rho: f64, g: f64) -> Result<Self, ModelError> {
        let resources = Resources::read(resource_dir)?;
        let network = parse_network(&resources.network_xml)?;
        Self::realize(&network, resources.keep_inf_mass, rho, g)
    }

    /// The ONE place that depends on the shape of [`crate::realize`]: scale the reference
    /// network to rho, g and take its state space.
    pub fn realize(
        network: &Network,
        keep_inf_mass: bool,
        rho: f64,
        g: f64,
    ) -> Result<Self, ModelError> {
        check_parameter("rho", rho)?;
        check_parameter("g", g)?;
        let scaled = network.scaled(rho, g);
        let ss = scaled
            .state_space()
            .map_err(|e| ModelError::Network(e.to_string()))?;
        let system = RadiationSystem {
            branch_projection: ss.branch_directions.clone(),
            branch_force: LinearMap::new(&ss.c_branch),
            b_branch: ss.b_branch,
            branch_states: ss.branch_states,
            dof_names: scaled.dof_names.clone(),
            keep_inf_mass,
            rho,
            g,
            added_mass_inf: scaled.added_mass_inf.clone(),
            damping_direct: -&ss.d,
            a: ss.a,
            b: ss.b,
            c: ss.c,
            d: ss.d,
            energy_weight: ss.energy_weight,
        };
        system.check()?;
        Ok(system)
    }

    fn check(&self) -> Result<(), ModelError> {
        let n = self.dof_names.len();
        let ns = self.a.nrows();
        let shapes = [
            ("A", &self.a, ns, ns),
            ("B", &self.b, ns, n),
            ("C", &self.c, n, ns),
            ("D", &self.d, n, n),
            ("P", &self.energy_weight, ns, ns),
            ("A_inf", &self.added_mass_inf, n, n),
            ("B_r", &self.b_branch, ns, self.branch_count()),
        ];
        if n == 0 {
            return Err(ModelError::Network("no DOFs".into()));
        }
        let r = self.branch_count();
        if self.branch_projection.ncols() != n
            || self.branch_force.rows() != r
            || self.branch_force.cols() != ns
        {
            return Err(ModelError::Network(format!(
                "the branch maps do not fit {n} DOFs, {r} branches and {ns} states"
            )));
        }
        for (name, m, r, c) in shapes {
            if m.nrows() != r || m.ncols() != c {
                return Err(ModelError::Network(format!(
                    "{name} is {}x{}, expected {r}x{c}",
                    m.nrows(),
                    m.ncols()
                )));
            }
            if m.iter().any(|x| !x.is_finite()) {
                return Err(ModelError::Network(format!("{name} is not finite")));
            }
        }
        Ok(())
    }

    /// DOF names.
    pub fn dof_names(&self) -> &[String] {
        &self.dof_names
    }
    /// Number of DOFs n.
    pub fn dof_count(&self) -> usize {
        self.dof_names.len()
    }
    /// Number of network states.
    pub fn state_size(&self) -> usize {
        self.a.nrows()
    }
    /// Number of network branches r.
    pub fn branch_count(&self) -> usize {
        self.branch_projection.nrows()
    }
    /// Whether the force includes `-A_inf a`.
    pub fn keep_inf_mass(&self) -> bool {
        self.keep_inf_mass
    }
    /// Water density.
    pub fn rho(&self) -> f64 {
        self.rho
    }
    /// Gravity.
    pub fn g(&self) -> f64 {
        self.g
    }
    /// Infinite-frequency added mass A_inf (n x n).
    pub fn added_mass_inf(&self) -> &DMatrix<f64> {
        &self.added_mass_inf
    }
    /// Direct damping `-D` (n x n).
    pub fn damping_direct(&self) -> &DMatrix<f64> {
        &self.damping_direct
    }
}

/// Parses the network text (glue to [`crate::realize`]).
fn parse_network(text: &str) -> Result<Network, ModelError> {
    Network::from_xml_str(text, Resources::NETWORK_FILE)
        .map_err(|e| ModelError::Network(e.to_string()))
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
        }
    }

    fn vectors(&self) -> [&DVector<f64>; 5] {
        [
            &self.network,
            &self.velocity,
            &self.velocity_derivative,
            &self.acceleration,
            &self.acceleration_derivative,
        ]
    }
}

/// True when no entry is NaN or infinite (all exponent bits set). One pass of integer
/// operations without an early exit, so it vectorizes.
fn all_finite(values: &[f64]) -> bool {
    const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
    values
        .iter()
        .fold(false, |bad, x| bad | (x.to_bits() & EXPONENT == EXPONENT))
        .not()
}

/// Steps a [`ModelState`] exactly; holds the discretization cache and scratch memory.
///
/// The branches see the hull only through their speeds `s = P v`, so the stepper
/// discretizes `z' = A z + B_r s` and one step is `z+ = [Phi | Gamma0 | Gamma1] [z; P v; P v']`
/// with block-diagonal `Phi` (one block per branch): O(r n + states) work.
#[derive(Clone, Debug)]
pub struct Stepper {
    cache: BlockDiscretizationCache,
    projection: DMatrix<f64>,
    next: DVector<f64>,
    speed: DVector<f64>,
    rate: DVector<f64>,
}

impl Stepper {
    /// A stepper for this system.
    pub fn new(system: &RadiationSystem) -> Result<Stepper, ModelError> {
        let r = system.branch_count();
        Ok(Stepper {
            cache: BlockDiscretizationCache::new(
                &system.a,
                &system.b_branch,
                &system.branch_states,
            )?,
            projection: system.branch_projection.clone(),
            next: DVector::zeros(system.state_size()),
            speed: DVector::zeros(r),
            rate: DVector::zeros(r),
        })
    }

    /// Advances `state` from `current` (must match `state.time`) by h. On error the state
    /// is unchanged.
    pub fn step(&mut self, state: &mut ModelState, current: f64, h: f64) -> Result<(), ModelError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(ModelError::Step(format!(
                "step size {h} must be finite and > 0"
            )));
        }
        if !current.is_finite()
            || (current - state.time).abs() > TIME_TOLERANCE * state.time.abs().max(h)
        {
            return Err(ModelError::Step(format!(
                "communication point {current} does not match the component's time {}",
                state.time
            )));
        }
        // The network state is checked through `next` below; the inputs here.
        let inputs = [
            &state.velocity,
            &state.velocity_derivative,
            &state.acceleration,
            &state.acceleration_derivative,
        ];
        if inputs.iter().any(|v| !all_finite(v.as_slice())) {
            return Err(ModelError::Step("non-finite input".into()));
        }
        let d = self.cache.get(h)?;
        // Per branch b: next_b = Phi_b z_b + Gamma0_b (d_b . v) + Gamma1_b (d_b . v').
        self.speed.gemv(1.0, &self.projection, &state.velocity, 0.0);
        let ramp = state
            .velocity_derivative
            .as_slice()
            .iter()
            .any(|x| *x != 0.0);
        if ramp {
            self.rate
                .gemv(1.0, &self.projection, &state.velocity_derivative, 0.0);
        } else {
            self.rate.fill(0.0);
        }
        d.apply(
            state.network.as_slice(),
            self.speed.as_slice(),
            self.rate.as_slice(),
            self.next.as_mut_slice(),
        );
        if !all_finite(self.next.as_slice()) {
            return Err(ModelError::Step(
                "the network state is not finite after the step".into(),
            ));
        }
        let acceleration_ramp = state
            .acceleration_derivative
            .as_slice()
            .iter()
            .any(|x| *x != 0.0);
        let ramp_ok = |x: &DVector<f64>, dx: &DVector<f64>| {
            x.iter()
                .zip(dx.iter())
                .all(|(x, dx)| (x + dx * h).is_finite())
        };
        if (ramp && !ramp_ok(&state.velocity, &state.velocity_derivative))
            || (acceleration_ramp && !ramp_ok(&state.acceleration, &state.acceleration_derivative))
        {
            return Err(ModelError::Step(
                "the extrapolated inputs are not finite".into(),
            ));
        }
        std::mem::swap(&mut state.network, &mut self.next);
        if ramp {
            state.velocity.axpy(h, &state.velocity_derivative, 1.0);
        }
        if acceleration_ramp {
            state
                .acceleration
                .axpy(h, &state.acceleration_derivative, 1.0);
        }
        if h.to_bits() == state.last_step.to_bits() && state.steps_since_anchor > 0 {
            state.steps_since_anchor += 1;
        } else {
            state.time_anchor = current;
            state.last_step = h;
            state.steps_since_anchor = 1;
        }
        state.time = state.time_anchor + state.steps_since_anchor as f64 * h;
        Ok(())
    }
}

/// Outputs computed from the state.
#[derive(Clone, Debug, PartialEq)]
struct Outputs {
    force: DVector<f64>,
    power: f64,
    energy: Option<f64>,
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
}

const MAGIC: &[u8; 8] = b"HYDROFMU";
const FORMAT_VERSION: u32 = 1;

fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf29ce484222325u64, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x100000001b3)
    })
}

struct ByteReader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl ByteReader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], ModelError> {
        let end = self.at.checked_add(n).filter(|e| *e <= self.bytes.len());
        let end = end.ok_or_else(|| ModelError::State("the bytes end too early".into()))?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8, ModelError> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, ModelError> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn u64(&mut self) -> Result<u64, ModelError> {
        let mut a = [0u8; 8];
        a.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(a))
    }
    fn f64(&mut self) -> Result<f64, ModelError> {
        Ok(f64::from_bits(self.u64()?))
    }
    fn vector(&mut self, n: usize) -> Result<DVector<f64>, ModelError> {
        let mut v = DVector::zeros(n);
        for x in v.iter_mut() {
            *x = self.f64()?;
        }
        Ok(v)
    }
}

impl Model {
    /// Loads the component from an FMU's `resources/` folder, at the default rho and g.
    pub fn load(resource_dir: &Path) -> Result<Model, ModelError> {
        let resources = Resources::read(resource_dir)?;
        Model::from_resources(&resources)
    }

    /// The component from resource texts, at the default rho and g.
    pub fn from_resources(resources: &Resources) -> Result<Model, ModelError> {
        let network = parse_network(&resources.network_xml)?;
        let system =
            RadiationSystem::realize(&network, resources.keep_inf_mass, DEFAULT_RHO, DEFAULT_G)?;
        let stepper = Stepper::new(&system)?;
        let n = system.dof_count();
        let ns = system.state_size();
        let mut model = Model {
            network,
            guid: resources.guid(),
            state: ModelState::rest(n, ns),
            stepper,
            outputs: Outputs {
                force: DVector::zeros(n),
                power: 0.0,
                energy: None,
            },
            outputs_valid: false,
            work: DVector::zeros(ns),
            branch_forces: DVector::zeros(system.branch_count()),
            system,
        };
        model.refresh();
        Ok(model)
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

    /// Replaces the state (dimensions and values checked; rho or g changes re-realize).
    pub fn set_state(&mut self, state: ModelState) -> Result<(), ModelError> {
        let n = self.dof_count();
        let ns = self.system.state_size();
        let dims = [ns, n, n, n, n];
        for (v, d) in state.vectors().iter().zip(dims) {
            if v.len() != d {
                return Err(ModelError::State(format!(
                    "a vector has {} entries, expected {d}",
                    v.len()
                )));
            }
            if v.iter().any(|x| !x.is_finite()) {
                return Err(ModelError::State("non-finite values".into()));
            }
        }
        if !state.time.is_finite() || !state.time_anchor.is_finite() || !state.last_step.is_finite()
        {
            return Err(ModelError::State("non-finite time".into()));
        }
        if state.rho != self.system.rho || state.g != self.system.g {
            self.rebuild(state.rho, state.g)?;
        }
        self.state = state;
        self.outputs_valid = false;
        Ok(())
    }

    /// Rest state, default rho and g, time 0.
    pub fn reset(&mut self) -> Result<(), ModelError> {
        let rest = ModelState::rest(self.dof_count(), self.system.state_size());
        self.set_state(rest)
    }

    /// Sets the start time (only meaningful before the first step).
    pub fn set_start_time(&mut self, time: f64) -> Result<(), ModelError> {
        if !time.is_finite() {
            return Err(ModelError::Step(format!("start time {time} is not finite")));
        }
        self.state.time = time;
        self.state.time_anchor = time;
        self.state.last_step = 0.0;
        self.state.steps_since_anchor = 0;
        Ok(())
    }

    fn rebuild(&mut self, rho: f64, g: f64) -> Result<(), ModelError> {
        let system = RadiationSystem::realize(&self.network, self.system.keep_inf_mass, rho, g)?;
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

    fn refresh(&mut self) {
        if self.outputs_valid {
            return;
        }
        let s = &self.state;
        let sys = &self.system;
        let out = &mut self.outputs;
        sys.branch_force
            .apply(s.network.as_slice(), self.branch_forces.as_mut_slice());
        out.force.gemv(1.0, &sys.d, &s.velocity, 0.0);
        out.force
            .gemv_tr(1.0, &sys.branch_projection, &self.branch_forces, 1.0);
        if sys.keep_inf_mass {
            out.force
                .gemv(-1.0, &sys.added_mass_inf, &s.acceleration, 1.0);
        }
        // -0.0 + 0.0 = +0.0: a force at rest reads 0, not -0.
        out.force.add_scalar_mut(0.0);
        out.power = -out.force.dot(&s.velocity) + 0.0;
        out.energy = None;
        self.outputs_valid = true;
    }

    /// The stored energy, computed on demand (it costs a state-size squared product).
    fn energy(&mut self) -> f64 {
        self.refresh();
        if let Some(e) = self.outputs.energy {
            return e;
        }
        let s = &self.state;
        let sys = &self.system;
        self.work.gemv(1.0, &sys.energy_weight, &s.network, 0.0);
        let mut energy = 0.5 * s.network.dot(&self.work);
        if sys.keep_inf_mass {
            energy += 0.5 * s.velocity.dot(&(&sys.added_mass_inf * &s.velocity));
        }
        self.outputs.energy = Some(energy);
        energy
    }

    /// Reads any variable.
    pub fn value(&mut self, quantity: Quantity) -> Result<f64, ModelError> {
        let n = self.dof_count();
        let v = match quantity {
            Quantity::Rho => self.state.rho,
            Quantity::G => self.state.g,
            Quantity::Velocity(i) if i < n => self.state.velocity[i],
            Quantity::Acceleration(i) if i < n && self.system.keep_inf_mass => {
                self.state.acceleration[i]
            }
            Quantity::AddedMassInf(i, j) if i < n && j < n => self.system.added_mass_inf[(i, j)],
            Quantity::DampingDirect(i, j) if i < n && j < n => self.system.damping_direct[(i, j)],
            Quantity::Force(i) if i < n => {
                self.refresh();
                self.outputs.force[i]
            }
            Quantity::Power => {
                self.refresh();
                self.outputs.power
            }
            Quantity::Energy => self.energy(),
            other => return Err(ModelError::Variable(format!("{other:?} does not exist"))),
        };
        Ok(v)
    }

    /// All forces (n entries).
    pub fn forces(&mut self) -> &DVector<f64> {
        self.refresh();
        &self.outputs.force
    }

    /// First time derivative of an output at the current time:
    /// `dF/dt = C (A z + B v) + D v' [- A_inf a']`, `d power/dt = -(F' . v + F . v')`,
    /// `d energy/dt` from the network equations.
    pub fn output_derivative(&mut self, quantity: Quantity) -> Result<f64, ModelError> {
        let n = self.dof_count();
        self.refresh();
        let s = &self.state;
        let sys = &self.system;
        let zdot = &sys.a * &s.network + &sys.b * &s.velocity;
        let mut fdot = &sys.c * &zdot + &sys.d * &s.velocity_derivative;
        if sys.keep_inf_mass {
            fdot -= &sys.added_mass_inf * &s.acceleration_derivative;
        }
        match quantity {
            Quantity::Force(i) if i < n => Ok(fdot[i]),
            Quantity::Power => {
                Ok(-(fdot.dot(&s.velocity) + self.outputs.force.dot(&s.velocity_derivative)))
            }
            Quantity::Energy => {
                // d/dt 1/2 z^T P z = 1/2 (z^T P zdot + zdot^T P z)
                let p = &sys.energy_weight;
                let mut e = 0.5 * (s.network.dot(&(p * &zdot)) + zdot.dot(&(p * &s.network)));
                if sys.keep_inf_mass {
                    let m = &sys.added_mass_inf;
                    e += 0.5
                        * (s.velocity.dot(&(m * &s.velocity_derivative))
                            + s.velocity_derivative.dot(&(m * &s.velocity)));
                }
                Ok(e)
            }
            other => Err(ModelError::Variable(format!("{other:?} is not an output"))),
        }
    }

    /// Partial derivative of an output with respect to an input at the current state.
    pub fn partial_derivative(
        &mut self,
        of: Quantity,
        with_respect_to: Quantity,
    ) -> Result<f64, ModelError> {
        let n = self.dof_count();
        let keep = self.system.keep_inf_mass;
        self.refresh();
        let d = &self.system.damping_direct;
        let m = &self.system.added_mass_inf;
        let v = &self.state.velocity;
        let value = match (of, with_respect_to) {
            (Quantity::Force(i), Quantity::Velocity(j)) if i < n && j < n => -d[(i, j)],
            (Quantity::Force(i), Quantity::Acceleration(j)) if i < n && j < n && keep => -m[(i, j)],
            // power = -F . v: d/dv_j = -F_j - sum_i v_i dF_i/dv_j
            (Quantity::Power, Quantity::Velocity(j)) if j < n => {
                -self.outputs.force[j] + d.column(j).dot(v)
            }
            (Quantity::Power, Quantity::Acceleration(j)) if j < n && keep => m.column(j).dot(v),
            (Quantity::Energy, Quantity::Velocity(j)) if j < n => {
                if keep {
                    0.5 * (m.row(j).transpose().dot(v) + m.column(j).dot(v))
                } else {
                    0.0
                }
            }
            (Quantity::Energy, Quantity::Acceleration(j)) if j < n && keep => 0.0,
            (of, wrt) => {
                return Err(ModelError::Variable(format!(
                    "no partial derivative of {of:?} with respect to {wrt:?}"
                )))
            }
        };
        Ok(value)
    }

    /// Advances from `current` (must match the component's time) by h. On error the state
    /// is unchanged.
    pub fn step(&mut self, current: f64, h: f64) -> Result<(), ModelError> {
        self.stepper.step(&mut self.state, current, h)?;
        self.outputs_valid = false;
        Ok(())
    }

    /// The state as self-describing bytes; `tag` is kept for the owner (the FMI layer
    /// stores its phase there).
    pub fn serialize(&self, tag: u8) -> Vec<u8> {
        self.serialize_state(&self.state, tag)
    }

    /// Like [`Model::serialize`], for a state saved earlier (same dimensions).
    pub fn serialize_state(&self, s: &ModelState, tag: u8) -> Vec<u8> {
        let mut b = Vec::with_capacity(self.serialized_size());
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        b.push(tag);
        b.extend_from_slice(&(self.guid.len() as u32).to_le_bytes());
        b.extend_from_slice(self.guid.as_bytes());
        b.extend_from_slice(&(self.dof_count() as u32).to_le_bytes());
        b.extend_from_slice(&(self.system.state_size() as u32).to_le_bytes());
        b.push(u8::from(self.system.keep_inf_mass));
        for x in [s.rho, s.g, s.time, s.time_anchor, s.last_step] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        b.extend_from_slice(&s.steps_since_anchor.to_le_bytes());
        for v in s.vectors() {
            for x in v.iter() {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        let sum = fnv1a(&b);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// Length of [`Model::serialize`]'s output.
    pub fn serialized_size(&self) -> usize {
        let n = self.dof_count();
        let ns = self.system.state_size();
        8 + 4 + 1 + 4 + self.guid.len() + 4 + 4 + 1 + 5 * 8 + 8 + 8 * (ns + 4 * n) + 8
    }

    /// Reads state bytes written by [`Model::serialize`] of an FMU with the same GUID.
    /// Returns the state and the owner's tag; does not change the model.
    pub fn deserialize(&self, bytes: &[u8]) -> Result<(ModelState, u8), ModelError> {
        if bytes.len() < 8 + 4 + 8 || &bytes[..8] != MAGIC {
            return Err(ModelError::State(
                "not a hydrofmu state (wrong magic bytes)".into(),
            ));
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        let mut r = ByteReader { bytes: body, at: 8 };
        let version = r.u32()?;
        if version != FORMAT_VERSION {
            return Err(ModelError::State(format!(
                "format version {version}, this FMU reads {FORMAT_VERSION}"
            )));
        }
        let mut s = [0u8; 8];
        s.copy_from_slice(sum);
        if u64::from_le_bytes(s) != fnv1a(body) {
            return Err(ModelError::State(
                "checksum mismatch (corrupt bytes)".into(),
            ));
        }
        let tag = r.u8()?;
        let guid_len = r.u32()? as usize;
        if guid_len > 1024 {
            return Err(ModelError::State("GUID too long".into()));
        }
        let guid = String::from_utf8_lossy(r.take(guid_len)?).into_owned();
        if guid != self.guid {
            return Err(ModelError::State(format!(
                "state of FMU {guid}, this FMU is {}",
                self.guid
            )));
        }
        let n = r.u32()? as usize;
        let ns = r.u32()? as usize;
        let keep = r.u8()? != 0;
        if n != self.dof_count()
            || ns != self.system.state_size()
            || keep != self.system.keep_inf_mass
        {
            return Err(ModelError::State(format!(
                "dimensions {n} DOFs, {ns} states do not match this FMU"
            )));
        }
        let state = ModelState {
            rho: r.f64()?,
            g: r.f64()?,
            time: r.f64()?,
            time_anchor: r.f64()?,
            last_step: r.f64()?,
            steps_since_anchor: r.u64()?,
            network: r.vector(ns)?,
            velocity: r.vector(n)?,
            velocity_derivative: r.vector(n)?,
            acceleration: r.vector(n)?,
            acceleration_derivative: r.vector(n)?,
        };
        if r.at != body.len() {
            return Err(ModelError::State("trailing bytes".into()));
        }
        check_parameter("rho", state.rho).map_err(|e| ModelError::State(e.to_string()))?;
        check_parameter("g", state.g).map_err(|e| ModelError::State(e.to_string()))?;
        Ok((state, tag))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The seed paper's 2-DOF network (the shipped example file).
    pub(crate) const SEED_NETWORK: &str = include_str!("../examples/networks/seed_2dof.xml");

    pub(crate) const TWO_DOF_NETWORK: &str = r#"<network format_version="1" form="coupled" rho="1" g="1">
  <dof name="sway"/>
  <dof name="roll"/>
  <added_mass_inf><row>0.2 0.05</row><row>0.05 0.1</row></added_mass_inf>
  <branch>
    <direction>1 0</direction>
    <stage mass="0.5" stiffness="0.3" damping="0.8"/>
    <stage mass="0.2" stiffness="0.5" damping="0.2"/>
  </branch>
  <branch>
    <direction>0.3 1</direction>
    <stage mass="0.4" stiffness="0.7" damping="0.6"/>
  </branch>
</network>
"#;

    pub(crate) fn resources(network: &str, keep: bool) -> Resources {
        Resources::new(network.into(), None, Resources::options_text(keep)).unwrap()
    }

    fn seed(rho: f64, g: f64) -> Model {
        let mut m = Model::from_resources(&resources(SEED_NETWORK, false)).unwrap();
        m.set_parameters(rho, g).unwrap();
        m
    }

    #[test]
    fn seed_impulse_response_reaches_the_common_velocity() {
        // Figure 7 of the seed: body m = 1 (+ m0) with unit impulse, explicit coupling with
        // a small step; final velocity 1 / (m + m0 + m1 + m2) (momentum conservation).
        let mut model = seed(1.0, 1.0);
        let (m, m0) = (1.0, 0.1153);
        let h = 1e-3;
        let mut v = 1.0 / (m + m0);
        let mut t = 0.0;
        for _ in 0..60_000 {
            model.set_value(Quantity::Velocity(0), v).unwrap();
            let f = model.value(Quantity::Force(0)).unwrap();
            model.step(t, h).unwrap();
            t = model.time();
            v += h * f / (m + m0);
        }
        let expected = 1.0 / (m + m0 + 0.5434 + 0.1877);
        // Explicit coupling error O(h) on a 60 s run; 1e-3 of the final velocity.
        assert!((v - expected).abs() < 1e-3 * expected, "{v} vs {expected}");
    }

    #[test]
    fn energy_balance_holds_and_dissipation_is_positive() {
        // Work done on the water (trapezoid of power with a smooth input over small steps)
        // = stored energy + dissipated >= stored energy.
        let mut model = Model::from_resources(&resources(TWO_DOF_NETWORK, false)).unwrap();
        model.set_parameters(1025.0, 9.81).unwrap();
        let h = 1e-3;
        let mut work = 0.0;
        let mut t = 0.0;
        let input = |t: f64| [(1.3 * t).sin() * (-0.1 * t).exp(), 0.4 * (2.1 * t).cos()];
        let mut previous_power = None;
        for k in 0..20_000 {
            let u = input(k as f64 * h);
            model.set_value(Quantity::Velocity(0), u[0]).unwrap();
            model.set_value(Quantity::Velocity(1), u[1]).unwrap();
            let p = model.value(Quantity::Power).unwrap();
            if let Some(p0) = previous_power {
                work += 0.5 * h * (p0 + p);
            }
            previous_power = Some(p);
            model.step(t, h).unwrap();
            t = model.time();
        }
        let energy = model.value(Quantity::Energy).unwrap();
        assert!(energy > 0.0);
        let dissipated = work - energy;
        // Trapezoid error with ZOH inputs is O(h) relative; 1 % margin.
        assert!(dissipated > 0.01 * work, "work {work}, energy {energy}");
    }

    #[test]
    fn energy_rate_matches_power_minus_dissipation_per_step() {
        // With the input held, over one short step: dE ~= power h - c (dv)^2 h <= power h.
        let mut model = seed(1.0, 1.0);
        model.set_value(Quantity::Velocity(0), 1.0).unwrap();
        let mut t = 0.0;
        for _ in 0..100 {
            let e0 = model.value(Quantity::Energy).unwrap();
            let p = model.value(Quantity::Power).unwrap();
            let de_dt = model.output_derivative(Quantity::Energy).unwrap();
            model.step(t, 1e-4).unwrap();
            t = model.time();
            let e1 = model.value(Quantity::Energy).unwrap();
            assert!(de_dt <= p + 1e-12, "dE/dt {de_dt} > power {p}");
            // finite difference of energy matches its derivative (O(h) error)
            assert!(((e1 - e0) / 1e-4 - de_dt).abs() < 1e-3 * (1.0 + de_dt.abs()));
        }
    }

    #[test]
    fn force_has_direct_feedthrough_and_keep_inf_mass_adds_inertia() {
        let mut model = seed(1.0, 1.0);
        model.set_value(Quantity::Velocity(0), 2.0).unwrap();
        // At rest network: F = D v = -c1 v.
        assert_eq!(model.value(Quantity::Force(0)).unwrap(), -0.9962 * 2.0);
        assert_eq!(model.value(Quantity::DampingDirect(0, 0)).unwrap(), 0.9962);
        assert!(model.set_value(Quantity::Acceleration(0), 1.0).is_err());
        let mut keep = Model::from_resources(&resources(SEED_NETWORK, true)).unwrap();
        keep.set_parameters(1.0, 1.0).unwrap();
        keep.set_value(Quantity::Acceleration(0), 3.0).unwrap();
        assert!((keep.value(Quantity::Force(0)).unwrap() + 0.1153 * 3.0).abs() < 1e-15);
        keep.set_value(Quantity::Velocity(0), 2.0).unwrap();
        let e = keep.value(Quantity::Energy).unwrap();
        assert!((e - 0.5 * 0.1153 * 4.0).abs() < 1e-15);
    }

    #[test]
    fn rho_and_g_scale_exactly() {
        // Masses scale with rho; the impulse response in time scales with sqrt(g).
        let mut a = seed(1.0, 1.0);
        let mut b = seed(2.0, 4.0);
        assert!((b.value(Quantity::DampingDirect(0, 0)).unwrap() - 0.9962 * 4.0).abs() < 1e-14);
        a.set_value(Quantity::Velocity(0), 1.0).unwrap();
        b.set_value(Quantity::Velocity(0), 1.0).unwrap();
        // F_b(t) = rho_ratio sqrt(g_ratio) F_a(sqrt(g_ratio) t) for a step velocity.
        a.step(0.0, 1.0).unwrap();
        b.step(0.0, 0.5).unwrap();
        let fa = a.value(Quantity::Force(0)).unwrap();
        let fb = b.value(Quantity::Force(0)).unwrap();
        assert!((fb - 4.0 * fa).abs() < 1e-13, "{fb} vs {fa}");
        assert!(a.set_parameters(-1.0, 1.0).is_err());
        assert!(a.set_parameters(1.0, f64::NAN).is_err());
        assert_eq!(a.state().rho, 1.0);
    }

    #[test]
    fn result_is_independent_of_the_step_split_with_first_order_hold() {
        // A ramp input: one step of 0.8 s equals 8 steps of 0.1 s (exact discretization).
        let run = |steps: usize| {
            let mut m = seed(1025.0, 9.81);
            m.set_value(Quantity::Velocity(0), 0.3).unwrap();
            m.set_input_derivative(Quantity::Velocity(0), -0.7).unwrap();
            let h = 0.8 / steps as f64;
            for k in 0..steps {
                m.step(k as f64 * h, h).unwrap();
            }
            (m.value(Quantity::Force(0)).unwrap(), m.state().clone())
        };
        let (f1, s1) = run(1);
        let (f8, s8) = run(8);
        assert!((f1 - f8).abs() < 1e-10 * f1.abs().max(1.0));
        assert!((s1.velocity[0] - s8.velocity[0]).abs() < 1e-14);
        assert!((s1.network - s8.network).amax() < 1e-10);
    }

    #[test]
    fn output_derivative_matches_finite_difference() {
        let mut m = Model::from_resources(&resources(TWO_DOF_NETWORK, false)).unwrap();
        m.set_value(Quantity::Velocity(0), 0.5).unwrap();
        m.set_value(Quantity::Velocity(1), -0.2).unwrap();
        m.step(0.0, 0.3).unwrap();
        m.set_input_derivative(Quantity::Velocity(0), 0.4).unwrap();
        let q = [Quantity::Force(0), Quantity::Force(1), Quantity::Power];
        let d: Vec<f64> = q.iter().map(|q| m.output_derivative(*q).unwrap()).collect();
        let before: Vec<f64> = q.iter().map(|q| m.value(*q).unwrap()).collect();
        let h = 1e-6;
        m.step(0.3, h).unwrap();
        for (k, q) in q.iter().enumerate() {
            let fd = (m.value(*q).unwrap() - before[k]) / h;
            // O(h) truncation relative to the derivative scale.
            assert!(
                (fd - d[k]).abs() < 1e-3 * (1.0 + d[k].abs()),
                "{q:?}: {fd} vs {}",
                d[k]
            );
        }
    }

    #[test]
    fn partial_derivatives_match_finite_differences() {
        let mut m = Model::from_resources(&resources(TWO_DOF_NETWORK, true)).unwrap();
        m.set_value(Quantity::Velocity(0), 0.5).unwrap();
        m.set_value(Quantity::Velocity(1), -0.2).unwrap();
        m.set_value(Quantity::Acceleration(1), 0.7).unwrap();
        m.step(0.0, 0.3).unwrap();
        let outs = [
            Quantity::Force(0),
            Quantity::Force(1),
            Quantity::Power,
            Quantity::Energy,
        ];
        let ins = [
            Quantity::Velocity(0),
            Quantity::Velocity(1),
            Quantity::Acceleration(0),
            Quantity::Acceleration(1),
        ];
        for inp in ins {
            let x0 = m.value(inp).unwrap();
            let eps = 1e-6;
            m.set_value(inp, x0 + eps).unwrap();
            let plus: Vec<f64> = outs.iter().map(|o| m.value(*o).unwrap()).collect();
            m.set_value(inp, x0 - eps).unwrap();
            let minus: Vec<f64> = outs.iter().map(|o| m.value(*o).unwrap()).collect();
            m.set_value(inp, x0).unwrap();
            for (k, o) in outs.iter().enumerate() {
                let fd = (plus[k] - minus[k]) / (2.0 * eps);
                let exact = m.partial_derivative(*o, inp).unwrap();
                // central difference of a quadratic: exact to rounding (~1e-10)
                assert!(
                    (fd - exact).abs() < 1e-8 * (1.0 + exact.abs()),
                    "{o:?}/{inp:?}: {fd} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn bad_steps_and_inputs_leave_the_state_unchanged() {
        let mut m = seed(1.0, 1.0);
        m.set_value(Quantity::Velocity(0), 1.0).unwrap();
        m.step(0.0, 0.1).unwrap();
        let before = m.state().clone();
        assert!(m.step(0.1, 0.0).is_err());
        assert!(m.step(0.1, -1.0).is_err());
        assert!(m.step(0.1, f64::NAN).is_err());
        assert!(m.step(0.2, 0.1).is_err());
        assert!(m.step(f64::NAN, 0.1).is_err());
        assert!(m.set_value(Quantity::Velocity(0), f64::NAN).is_err());
        assert!(m.set_value(Quantity::Velocity(0), f64::INFINITY).is_err());
        assert!(m.set_value(Quantity::Force(0), 1.0).is_err());
        assert!(m
            .set_input_derivative(Quantity::Velocity(0), f64::NAN)
            .is_err());
        // Huge but finite inputs beyond MAX_INPUT: refused, unchanged.
        assert!(m.set_value(Quantity::Velocity(0), 1e308).is_err());
        assert!(m
            .set_input_derivative(Quantity::Velocity(0), -1e101)
            .is_err());
        assert!(m.set_parameters(1e300, 9.81).is_err());
        assert_eq!(m.state(), &before);
        // At the bound, a ramp over a long step still stays finite; then back to 1 m/s.
        m.set_value(Quantity::Velocity(0), MAX_INPUT).unwrap();
        m.set_input_derivative(Quantity::Velocity(0), MAX_INPUT)
            .unwrap();
        let mut probe = m.clone();
        probe.step(0.1, 10.0).unwrap();
        assert!(probe.forces().iter().all(|f| f.is_finite()));
        assert!(probe.value(Quantity::Energy).unwrap().is_finite());
        m.set_value(Quantity::Velocity(0), 1.0).unwrap();
        m.set_input_derivative(Quantity::Velocity(0), 0.0).unwrap();
        assert_eq!(m.state(), &before);
        // A tiny time mismatch (rounding) is accepted.
        m.step(0.1 + 1e-15, 0.1).unwrap();
    }

    #[test]
    fn time_does_not_drift_over_many_equal_steps() {
        let mut m = seed(1.0, 1.0);
        let h = 0.1;
        let mut t = 0.0;
        for _ in 0..10_000 {
            m.step(t, h).unwrap();
            t += h; // a master that accumulates (drifts by ~1e-10 after 1e4 steps)
        }
        assert_eq!(m.time(), 10_000.0 * h);
        assert!((t - m.time()).abs() < 1e-9);
    }

    #[test]
    fn serialized_state_round_trips_and_bad_bytes_are_rejected() {
        let mut m = seed(1025.0, 9.81);
        m.set_value(Quantity::Velocity(0), 0.7).unwrap();
        m.step(0.0, 0.25).unwrap();
        let bytes = m.serialize(3);
        assert_eq!(bytes.len(), m.serialized_size());
        let (state, tag) = m.deserialize(&bytes).unwrap();
        assert_eq!(tag, 3);
        assert_eq!(&state, m.state());
        // Continue identically from a restored copy.
        let mut other = Model::from_resources(&resources(SEED_NETWORK, false)).unwrap();
        other.set_state(state).unwrap();
        m.step(0.25, 0.25).unwrap();
        other.step(0.25, 0.25).unwrap();
        assert_eq!(m.state(), other.state());
        // Every single flipped byte is caught.
        for i in 0..bytes.len() {
            let mut bad = bytes.clone();
            bad[i] ^= 0x10;
            assert!(m.deserialize(&bad).is_err(), "byte {i}");
        }
        assert!(m.deserialize(&bytes[..bytes.len() - 1]).is_err());
        assert!(m.deserialize(b"").is_err());
        // A state of another FMU (other network) is refused by GUID.
        let foreign = Model::from_resources(&resources(TWO_DOF_NETWORK, false)).unwrap();
        let err = m.deserialize(&foreign.serialize(0)).unwrap_err();
        assert!(err.to_string().contains("FMU"), "{err}");
    }

    #[test]
    fn resources_are_checked() {
        assert!(Resources::new(SEED_NETWORK.into(), None, "<x/>".into()).is_err());
        assert!(Resources::new(
            SEED_NETWORK.into(),
            None,
            "<hydrofmu_options format=\"1\" keep_inf_mass=\"yes\"/>".into()
        )
        .is_err());
        let a = resources(SEED_NETWORK, false);
        let b = resources(SEED_NETWORK, true);
        assert_ne!(a.guid(), b.guid());
        assert!(Model::from_resources(&resources("<network/>", false)).is_err());
        assert!(Model::load(Path::new("/nonexistent/resources")).is_err());
    }
}
