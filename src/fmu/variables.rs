//! The per-hull FMU variables, declared once for the FMI layer and for `fmu-pack`.
//!
//! For DOFs d_1..d_n (names from the hull) the layout is, value references counting from
//! [`FIRST_PER_HULL_REFERENCE`] (= r0):
//!
//! | variable | causality | value reference |
//! | --- | --- | --- |
//! | `velocity.<d_i>` | input, start 0 | r0 + i - 1 |
//! | `force.<d_i>` | output | r0 + n + i - 1 |
//! | `power` | output | r0 + 2n |
//! | `energy` | output | r0 + 2n + 1 |
//! | `added_mass_inf[i,j]` | calculated parameter | r0 + 2n + 2 + (i-1) n + j - 1 |
//! | `damping_direct[i,j]` | calculated parameter | r0 + 2n + 2 + n^2 + (i-1) n + j - 1 |
//! | `acceleration.<d_i>` (keep_inf_mass only) | input, start 0 | r0 + 2n + 2 + 2n^2 + i - 1 |
//! | `force_radiation.<d_i>` | output | w0 + i - 1 |
//! | `force_excitation.<d_i>` | output | w0 + n + i - 1 |
//! | `wave.elevation` | output | w0 + 2n |
//! | `stiffness_hydrostatic[i,j]` | calculated parameter | w0 + 2n + 1 + (i-1) n + j - 1 |
//!
//! | `force_drift.<d_i>` (drift table only) | output | w0 + 2n + 1 + n^2 + i - 1 |
//! | `wave.drift` (drift table only; Integer) | parameter, start 0 | w0 + 3n + 1 + n^2 |
//!
//! with `w0 = r0 + 3n + 2 + 2n^2` (after the acceleration slot, whether or not it is used),
//! plus the fixed parameters of `modelDescription/fixed.xml`: `rho`, `g` and the wave
//! parameters `wave.kind`, `wave.height`, `wave.period`, `wave.heading`, `wave.gamma`,
//! `wave.seed`, `wave.components`, `wave.ramp` (value references 0 .. 9; kind, seed and
//! components are Integers). `force` is the generalized force on the hull by the water per
//! unit length, `force_radiation + force_excitation`; `power = -force_radiation . velocity`
//! is the power the hull delivers to the water through the radiated waves; `energy` is the
//! energy stored in the equivalent network (plus `1/2 v^T A_inf v` when the FMU keeps
//! `A_inf`). In calm water (`wave.kind = 0`, the default) `force` is the radiation force, as
//! before the waves existed. An FMU packed with a drift table ([`Layout::with_drift`]) adds
//! `force_drift` (in `force` too) and its switch `wave.drift` (0 none, 1 mean, 2 slow drift
//! by Newman; [`DRIFT_CODES`]) after every other variable, so no value reference moves.
//! An FMU whose tables are for a finite water depth ([`Layout::with_depth`]) declares the fixed
//! parameter `depth` (m, start the tables' depth) last, with value reference [`VR_DEPTH`] (98,
//! in the fixed parameters' reserved range 0..99); deep water declares none.
//!
//! Units follow each DOF's length exponent ([`crate::fmu::units`]).
//! [`Layout::model_description`] ([`crate::fmu::description`]) writes the complete
//! `modelDescription.xml` from these variables.

use crate::fmu::description::{
    FIRST_PER_HULL_REFERENCE, PARAMETERS, VR_G, VR_RHO, VR_WAVE_COMPONENTS, VR_WAVE_GAMMA,
    VR_WAVE_HEADING, VR_WAVE_HEIGHT, VR_WAVE_KIND, VR_WAVE_PERIOD, VR_WAVE_RAMP, VR_WAVE_SEED,
};
use crate::fmu::units::{DofUnit, Extent};
use std::fmt;

mod viscous;

/// Why a layout or a model description could not be made.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum VariablesError {
    /// The hull has no DOF.
    NoDofs,
    /// A DOF name is not a letter followed by letters, digits or '_'.
    InvalidDofName(String),
    /// A DOF's length exponent is neither 0 nor 1.
    LengthExponent {
        /// DOF name.
        dof: String,
        /// The refused exponent.
        exponent: u8,
    },
    /// Two DOFs have the same name.
    DuplicateDof(String),
    /// More DOFs than the value references allow.
    TooManyDofs(usize),
    /// A variable without value reference (a defect of the layout).
    MissingValueReference,
    /// The model identifier is not a letter followed by letters, digits or '_'.
    InvalidModelIdentifier(String),
    /// The GUID is empty.
    EmptyGuid,
    /// The fixed XML could not be read or the description not written.
    Xml(String),
    /// The fixed XML declares another number of variables than the fixed parameters.
    FixedVariableCount {
        /// Variables in the fixed XML.
        declared: usize,
        /// Fixed parameters in the constants.
        expected: usize,
    },
    /// The fixed XML has no `</ModelVariables>`.
    NoModelVariablesEnd,
}

impl fmt::Display for VariablesError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("FMU variables: ")?;
        match self {
            VariablesError::NoDofs => write!(f, "a hull needs at least one DOF"),
            VariablesError::InvalidDofName(name) => write!(
                f,
                "DOF name '{name}' must be a letter followed by letters, digits or '_'"
            ),
            VariablesError::LengthExponent { dof, exponent } => write!(
                f,
                "DOF '{dof}': length exponent {exponent} (0 or 1 expected)"
            ),
            VariablesError::DuplicateDof(name) => write!(f, "DOF '{name}' appears twice"),
            VariablesError::TooManyDofs(n) => write!(f, "{n} DOFs is too many"),
            VariablesError::MissingValueReference => write!(f, "internal: no value reference"),
            VariablesError::InvalidModelIdentifier(id) => write!(
                f,
                "model identifier '{id}' must be a letter followed by letters, digits or '_'"
            ),
            VariablesError::EmptyGuid => write!(f, "empty GUID"),
            VariablesError::Xml(message) => write!(f, "XML: {message}"),
            VariablesError::FixedVariableCount { declared, expected } => write!(
                f,
                "the fixed XML declares {declared} variables, the constants {expected}"
            ),
            VariablesError::NoModelVariablesEnd => {
                write!(f, "the fixed XML has no </ModelVariables>")
            }
        }
    }
}

impl std::error::Error for VariablesError {}

/// A parameter of the incident waves (fixed, declared in `modelDescription/fixed.xml`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WaveParameter {
    /// `wave.kind` (Integer): 0 calm, 1 regular, 2 JONSWAP.
    Kind,
    /// `wave.height` (m).
    Height,
    /// `wave.period` (s).
    Period,
    /// `wave.heading` (deg).
    Heading,
    /// `wave.gamma`.
    Gamma,
    /// `wave.seed` (Integer).
    Seed,
    /// `wave.components` (Integer).
    Components,
    /// `wave.ramp` (s).
    Ramp,
    /// `wave.drift` (Integer): 0 none, 1 mean drift, 2 slow drift by Newman. Declared only
    /// with a drift table, after the per-hull variables (not in the fixed XML).
    Drift,
}

impl WaveParameter {
    /// `wave.kind`, `wave.seed` and `wave.components` are Integers, the others Reals.
    pub fn is_integer(self) -> bool {
        matches!(
            self,
            WaveParameter::Kind
                | WaveParameter::Seed
                | WaveParameter::Components
                | WaveParameter::Drift
        )
    }

    /// Every wave parameter of the fixed XML with its value reference ([`Self::Drift`] is
    /// per hull: [`Layout::value_reference`]).
    pub const ALL: [(WaveParameter, u32); 8] = [
        (WaveParameter::Kind, VR_WAVE_KIND),
        (WaveParameter::Height, VR_WAVE_HEIGHT),
        (WaveParameter::Period, VR_WAVE_PERIOD),
        (WaveParameter::Heading, VR_WAVE_HEADING),
        (WaveParameter::Gamma, VR_WAVE_GAMMA),
        (WaveParameter::Seed, VR_WAVE_SEED),
        (WaveParameter::Components, VR_WAVE_COMPONENTS),
        (WaveParameter::Ramp, VR_WAVE_RAMP),
    ];
}

/// What a variable is. Indices are 0-based DOF indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Water density (fixed parameter).
    Rho,
    /// Gravity (fixed parameter).
    G,
    /// A wave parameter (fixed parameter).
    Wave(WaveParameter),
    /// Hull velocity input.
    Velocity(usize),
    /// Force output.
    Force(usize),
    /// Hull acceleration input (keep_inf_mass only).
    Acceleration(usize),
    /// Infinite-frequency added mass entry (calculated parameter).
    AddedMassInf(usize, usize),
    /// Direct damping entry (calculated parameter).
    DampingDirect(usize, usize),
    /// Power the hull delivers to the water through the radiated waves,
    /// `-force_radiation . velocity` (output).
    Power,
    /// Radiation part of the force (output).
    ForceRadiation(usize),
    /// Exciting force of the waves (output).
    ForceExcitation(usize),
    /// Wave elevation at x = 0 (output).
    WaveElevation,
    /// Hydrostatic restoring entry (calculated parameter).
    StiffnessHydrostatic(usize, usize),
    /// Energy stored in the network (output).
    Energy,
    /// Wave drift force (output, only with a drift table).
    ForceDrift(usize),
    /// Viscous force (output, only with viscous damping: [`Layout::with_viscous`]).
    ForceViscous(usize),
    /// Current speed (input, m/s; only with viscous damping).
    CurrentSpeed,
    /// Current heading (input, deg; only with viscous damping).
    CurrentHeading,
    /// Linear viscous damping entry (parameter; only with viscous damping).
    DampingLinear(usize, usize),
    /// Quadratic viscous damping of a DOF (parameter; only with viscous damping).
    DampingQuadratic(usize),
    /// Water depth the tables were computed for (fixed parameter, m; only in finite depth:
    /// [`Layout::with_depth`]).
    Depth,
    /// Scale of a ship's cross-flow strips (parameter; only with them:
    /// [`Layout::with_crossflow`]).
    CrossflowDragScale,
}

/// FMI causality.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    /// `parameter`.
    Parameter,
    /// `calculatedParameter`.
    CalculatedParameter,
    /// `input`.
    Input,
    /// `output`.
    Output,
}

impl Causality {
    /// The word in modelDescription.xml.
    pub fn as_str(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::CalculatedParameter => "calculatedParameter",
            Causality::Input => "input",
            Causality::Output => "output",
        }
    }
}

/// One scalar variable.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    /// Name in the FMU.
    pub name: String,
    /// FMI value reference.
    pub value_reference: u32,
    /// What it is.
    pub quantity: Quantity,
    /// FMI causality.
    pub causality: Causality,
    /// Unit name (declared in the fixed XML).
    pub unit: &'static str,
    /// Human-readable description.
    pub description: String,
    /// Start value (inputs and parameters).
    pub start: Option<f64>,
    /// An `Integer` variable (else `Real`).
    pub integer: bool,
}

impl Variable {
    /// FMI variability: `fixed` for parameters, `continuous` otherwise.
    pub fn variability(&self) -> &'static str {
        match self.causality {
            Causality::Parameter | Causality::CalculatedParameter => "fixed",
            _ => "continuous",
        }
    }
}

/// The variables of one hull's FMU.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    pub(super) dofs: Vec<DofUnit>,
    pub(super) keep_inf_mass: bool,
    pub(super) extent: Extent,
    pub(super) variables: Vec<Variable>,
    /// `force_drift` and `wave.drift` exist ([`Layout::with_drift`]).
    pub(super) drift: bool,
    /// The viscous damping and current variables exist ([`Layout::with_viscous`]).
    pub(super) viscous: bool,
    /// The finite water depth (m) of `depth` ([`Layout::with_depth`]).
    pub(super) depth: Option<f64>,
    /// `crossflow.drag_scale` exists ([`Layout::with_crossflow`]).
    pub(super) crossflow: bool,
}

/// Value reference of `depth` ([`Layout::with_depth`]): in the range reserved for the fixed
/// parameters, so that no per-hull reference depends on it.
pub const VR_DEPTH: u32 = 98;

/// The codes `wave.drift` accepts (declared min and max).
pub const DRIFT_CODES: (i32, i32) = (0, 2);

/// Offset (from [`FIRST_PER_HULL_REFERENCE`]) of the drift variables: after the hydrostatics.
fn drift_base(n: usize) -> usize {
    waves_base(n) + 2 * n + 1 + n * n
}

/// Offset (from [`FIRST_PER_HULL_REFERENCE`]) of the wave and hydrostatics variables: after
/// the acceleration slot, whether or not the accelerations exist.
fn waves_base(n: usize) -> usize {
    3 * n + 2 + 2 * n * n
}

/// The fixed parameter of a value reference below [`FIRST_PER_HULL_REFERENCE`].
fn fixed_quantity(value_reference: u32) -> Option<Quantity> {
    if value_reference == VR_RHO {
        return Some(Quantity::Rho);
    }
    if value_reference == VR_G {
        return Some(Quantity::G);
    }
    WaveParameter::ALL
        .iter()
        .find(|(_, vr)| *vr == value_reference)
        .map(|(p, _)| Quantity::Wave(*p))
}

/// A letter, then letters, digits or `_` (DOF names, model identifiers).
pub(super) fn valid_name(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

impl Layout {
    /// The layout for these DOFs of a section (forces per unit length); `keep_inf_mass`
    /// adds the acceleration inputs.
    pub fn new(dofs: Vec<DofUnit>, keep_inf_mass: bool) -> Result<Layout, VariablesError> {
        Layout::with_extent(dofs, keep_inf_mass, Extent::PerUnitLength)
    }

    /// As [`Layout::new`], for forces per unit length or of a whole body (a ship): the value
    /// references are the same, only units and descriptions differ.
    pub fn with_extent(
        dofs: Vec<DofUnit>,
        keep_inf_mass: bool,
        extent: Extent,
    ) -> Result<Layout, VariablesError> {
        if dofs.is_empty() {
            return Err(VariablesError::NoDofs);
        }
        for (i, d) in dofs.iter().enumerate() {
            if !valid_name(&d.name) {
                return Err(VariablesError::InvalidDofName(d.name.clone()));
            }
            if d.length_exponent > 1 {
                return Err(VariablesError::LengthExponent {
                    dof: d.name.clone(),
                    exponent: d.length_exponent,
                });
            }
            if dofs[..i].iter().any(|o| o.name == d.name) {
                return Err(VariablesError::DuplicateDof(d.name.clone()));
            }
        }
        let n = dofs.len();
        if n > 1000 {
            return Err(VariablesError::TooManyDofs(n));
        }
        let mut layout = Layout {
            dofs,
            keep_inf_mass,
            extent,
            variables: Vec::new(),
            drift: false,
            viscous: false,
            depth: None,
            crossflow: false,
        };
        let mut vars = Vec::new();
        for p in PARAMETERS {
            let Some(quantity) = fixed_quantity(p.value_reference) else {
                continue;
            };
            vars.push(Variable {
                name: p.name.to_string(),
                value_reference: p.value_reference,
                quantity,
                causality: Causality::Parameter,
                unit: p.unit,
                description: p.description.to_string(),
                start: Some(p.start),
                integer: p.integer,
            });
        }
        let force_note = if keep_inf_mass {
            "including -added_mass_inf * acceleration"
        } else {
            "excluding -added_mass_inf * acceleration (add added_mass_inf to the hull's mass)"
        };
        for (i, d) in layout.dofs.iter().enumerate() {
            vars.push(Variable {
                name: format!("velocity.{}", d.name),
                value_reference: 0,
                quantity: Quantity::Velocity(i),
                causality: Causality::Input,
                unit: d.velocity_unit(),
                description: format!("Hull velocity in DOF {}", d.name),
                start: Some(0.0),
                integer: false,
            });
        }
        for (i, d) in layout.dofs.iter().enumerate() {
            vars.push(Variable {
                name: format!("force.{}", d.name),
                value_reference: 0,
                quantity: Quantity::Force(i),
                causality: Causality::Output,
                unit: extent.force_unit(d.length_exponent),
                description: format!(
                    "Generalized force on the hull by the water in DOF {}, {}, {}",
                    d.name,
                    extent.words(),
                    force_note
                ),
                start: None,
                integer: false,
            });
        }
        vars.push(Variable {
            name: "power".into(),
            value_reference: 0,
            quantity: Quantity::Power,
            causality: Causality::Output,
            unit: extent.power_unit(),
            description: "Power the hull delivers to the water through the radiated waves, \
                          -force_radiation . velocity (work of the exciting force excluded)"
                .into(),
            start: None,
            integer: false,
        });
        vars.push(Variable {
            name: "energy".into(),
            value_reference: 0,
            quantity: Quantity::Energy,
            causality: Causality::Output,
            unit: extent.energy_unit(),
            description: if keep_inf_mass {
                "Energy stored in the equivalent network, including 1/2 v.added_mass_inf.v".into()
            } else {
                "Energy stored in the equivalent network".into()
            },
            start: None,
            integer: false,
        });
        for (kind, unit_of) in [
            (0, Extent::added_mass_unit as fn(Extent, u8) -> &'static str),
            (1, Extent::damping_unit),
        ] {
            for i in 0..n {
                for j in 0..n {
                    let sum = layout.dofs[i].length_exponent + layout.dofs[j].length_exponent;
                    let (di, dj) = (&layout.dofs[i].name, &layout.dofs[j].name);
                    let (name, quantity, description) = if kind == 0 {
                        (
                            format!("added_mass_inf[{},{}]", i + 1, j + 1),
                            Quantity::AddedMassInf(i, j),
                            if keep_inf_mass {
                                format!("Added mass at infinite frequency, {di}-{dj} (already in force)")
                            } else {
                                format!("Added mass at infinite frequency, {di}-{dj}: add it to the hull's mass matrix")
                            },
                        )
                    } else {
                        (
                            format!("damping_direct[{},{}]", i + 1, j + 1),
                            Quantity::DampingDirect(i, j),
                            format!("Direct damping, {di}-{dj}: d force.{di} / d velocity.{dj} = -damping_direct"),
                        )
                    };
                    vars.push(Variable {
                        name,
                        value_reference: 0,
                        quantity,
                        causality: Causality::CalculatedParameter,
                        unit: unit_of(extent, sum),
                        description,
                        start: None,
                        integer: false,
                    });
                }
            }
        }
        for (i, d) in layout.dofs.iter().enumerate() {
            vars.push(Variable {
                name: format!("force_radiation.{}", d.name),
                value_reference: 0,
                quantity: Quantity::ForceRadiation(i),
                causality: Causality::Output,
                unit: extent.force_unit(d.length_exponent),
                description: format!(
                    "Radiation part of force.{} (the equivalent network's force)",
                    d.name
                ),
                start: None,
                integer: false,
            });
        }
        for (i, d) in layout.dofs.iter().enumerate() {
            vars.push(Variable {
                name: format!("force_excitation.{}", d.name),
                value_reference: 0,
                quantity: Quantity::ForceExcitation(i),
                causality: Causality::Output,
                unit: extent.force_unit(d.length_exponent),
                description: format!(
                    "Exciting force of the incident waves in DOF {} (0 in calm water)",
                    d.name
                ),
                start: None,
                integer: false,
            });
        }
        vars.push(Variable {
            name: "wave.elevation".into(),
            value_reference: 0,
            quantity: Quantity::WaveElevation,
            causality: Causality::Output,
            unit: "m",
            description: "Elevation of the incident waves at x = 0".into(),
            start: None,
            integer: false,
        });
        for i in 0..n {
            for j in 0..n {
                let sum = layout.dofs[i].length_exponent + layout.dofs[j].length_exponent;
                let (di, dj) = (&layout.dofs[i].name, &layout.dofs[j].name);
                vars.push(Variable {
                    name: format!("stiffness_hydrostatic[{},{}]", i + 1, j + 1),
                    value_reference: 0,
                    quantity: Quantity::StiffnessHydrostatic(i, j),
                    causality: Causality::CalculatedParameter,
                    unit: extent.stiffness_unit(sum),
                    description: format!(
                        "Hydrostatic restoring, {di}-{dj}: add it to the hull's stiffness matrix; \
                         the structural model adds the initial stress of the pre-loaded shell \
                         and the weight's -m g z_G (docs/HYDROSTATICS.md)"
                    ),
                    start: None,
                    integer: false,
                });
            }
        }
        if keep_inf_mass {
            for (i, d) in layout.dofs.iter().enumerate() {
                vars.push(Variable {
                    name: format!("acceleration.{}", d.name),
                    value_reference: 0,
                    quantity: Quantity::Acceleration(i),
                    causality: Causality::Input,
                    unit: d.acceleration_unit(),
                    description: format!("Hull acceleration in DOF {}", d.name),
                    start: Some(0.0),
                    integer: false,
                });
            }
        }
        for v in &mut vars {
            if !matches!(v.quantity, Quantity::Rho | Quantity::G | Quantity::Wave(_)) {
                v.value_reference = layout
                    .value_reference(v.quantity)
                    .ok_or(VariablesError::MissingValueReference)?;
            }
        }
        layout.variables = vars;
        Ok(layout)
    }

    /// This layout with the variables of an FMU packed with a drift table, after all the
    /// others: `force_drift.<dof>` (outputs) and `wave.drift` (Integer parameter, start 0).
    pub fn with_drift(mut self) -> Result<Layout, VariablesError> {
        if self.drift {
            return Ok(self);
        }
        self.drift = true;
        let extent = self.extent;
        for (i, d) in self.dofs.iter().enumerate() {
            self.variables.push(Variable {
                name: format!("force_drift.{}", d.name),
                value_reference: 0,
                quantity: Quantity::ForceDrift(i),
                causality: Causality::Output,
                unit: extent.force_unit(d.length_exponent),
                description: format!(
                    "Wave drift force in DOF {} (in force; 0 in calm water or with wave.drift = 0)",
                    d.name
                ),
                start: None,
                integer: false,
            });
        }
        self.variables.push(Variable {
            name: "wave.drift".into(),
            value_reference: 0,
            quantity: Quantity::Wave(WaveParameter::Drift),
            causality: Causality::Parameter,
            unit: "",
            description: "Wave drift force: 0 none, 1 mean drift, 2 slow drift by Newman's \
                          approximation (docs/WAVES.md)"
                .into(),
            start: Some(0.0),
            integer: true,
        });
        let n = self.dofs.len();
        for k in 0..=n {
            let quantity = self.variables[self.variables.len() - 1 - n + k].quantity;
            let reference = self
                .value_reference(quantity)
                .ok_or(VariablesError::MissingValueReference)?;
            let index = self.variables.len() - 1 - n + k;
            self.variables[index].value_reference = reference;
        }
        Ok(self)
    }

    /// This layout with the fixed parameter `depth` (m, start `depth`: the finite water depth
    /// the tables were computed for), declared after all the others with value reference
    /// [`VR_DEPTH`]. Deep water declares no `depth`.
    ///
    /// # Errors
    /// A depth that is not finite and > 0.
    pub fn with_depth(mut self, depth: f64) -> Result<Layout, VariablesError> {
        if !(depth.is_finite() && depth > 0.0) {
            return Err(VariablesError::Xml(format!(
                "depth = {depth}: a declared water depth is finite and > 0"
            )));
        }
        if self.depth.is_some() {
            return Ok(self);
        }
        self.depth = Some(depth);
        self.variables.push(Variable {
            name: "depth".into(),
            value_reference: VR_DEPTH,
            quantity: Quantity::Depth,
            causality: Causality::Parameter,
            unit: "m",
            description: "Water depth the tables were computed for (fixed: only this value \
                          is accepted; docs/WAVES.md)"
                .into(),
            start: Some(depth),
            integer: false,
        });
        Ok(self)
    }

    /// The finite water depth `depth` declares (m), `None` in deep water.
    pub fn depth(&self) -> Option<f64> {
        self.depth
    }

    /// Whether the drift variables exist ([`Layout::with_drift`]).
    pub fn has_drift(&self) -> bool {
        self.drift
    }

    /// The DOFs.
    pub fn dofs(&self) -> &[DofUnit] {
        &self.dofs
    }

    /// Number of DOFs n.
    pub fn dof_count(&self) -> usize {
        self.dofs.len()
    }

    /// Whether the acceleration inputs exist and the force includes `-A_inf a`.
    pub fn keep_inf_mass(&self) -> bool {
        self.keep_inf_mass
    }

    /// All variables in modelDescription order (fixed parameters first).
    pub fn variables(&self) -> &[Variable] {
        &self.variables
    }

    /// The variable with this value reference.
    pub fn variable(&self, value_reference: u32) -> Option<&Variable> {
        let q = self.quantity(value_reference)?;
        self.variables.iter().find(|v| v.quantity == q)
    }

    /// The value reference of a quantity (`None` if it does not exist in this layout).
    pub fn value_reference(&self, quantity: Quantity) -> Option<u32> {
        let n = self.dofs.len();
        let base = FIRST_PER_HULL_REFERENCE as usize;
        let offset = match quantity {
            Quantity::Depth => return self.depth.map(|_| VR_DEPTH),
            Quantity::Rho => return Some(VR_RHO),
            Quantity::G => return Some(VR_G),
            Quantity::Wave(WaveParameter::Drift) if self.drift => drift_base(n) + n,
            Quantity::Wave(w) => {
                return WaveParameter::ALL
                    .iter()
                    .find(|(p, _)| *p == w)
                    .map(|(_, vr)| *vr)
            }
            Quantity::Velocity(i) if i < n => i,
            Quantity::Force(i) if i < n => n + i,
            Quantity::Power => 2 * n,
            Quantity::Energy => 2 * n + 1,
            Quantity::AddedMassInf(i, j) if i < n && j < n => 2 * n + 2 + i * n + j,
            Quantity::DampingDirect(i, j) if i < n && j < n => 2 * n + 2 + n * n + i * n + j,
            Quantity::Acceleration(i) if i < n && self.keep_inf_mass => 2 * n + 2 + 2 * n * n + i,
            Quantity::ForceRadiation(i) if i < n => waves_base(n) + i,
            Quantity::ForceExcitation(i) if i < n => waves_base(n) + n + i,
            Quantity::WaveElevation => waves_base(n) + 2 * n,
            Quantity::StiffnessHydrostatic(i, j) if i < n && j < n => {
                waves_base(n) + 2 * n + 1 + i * n + j
            }
            Quantity::ForceDrift(i) if i < n && self.drift => drift_base(n) + i,
            q if self.viscous => viscous::offset(q, n, self.crossflow)?,
            _ => return None,
        };
        u32::try_from(base + offset).ok()
    }

    /// What the value reference refers to (constant time).
    pub fn quantity(&self, value_reference: u32) -> Option<Quantity> {
        if value_reference == VR_DEPTH && self.depth.is_some() {
            return Some(Quantity::Depth);
        }
        if value_reference < FIRST_PER_HULL_REFERENCE {
            return fixed_quantity(value_reference);
        }
        let n = self.dofs.len();
        let k = (value_reference as usize).checked_sub(FIRST_PER_HULL_REFERENCE as usize)?;
        let q = if k < n {
            Quantity::Velocity(k)
        } else if k < 2 * n {
            Quantity::Force(k - n)
        } else if k == 2 * n {
            Quantity::Power
        } else if k == 2 * n + 1 {
            Quantity::Energy
        } else if k < 2 * n + 2 + n * n {
            let r = k - 2 * n - 2;
            Quantity::AddedMassInf(r / n, r % n)
        } else if k < 2 * n + 2 + 2 * n * n {
            let r = k - 2 * n - 2 - n * n;
            Quantity::DampingDirect(r / n, r % n)
        } else if self.keep_inf_mass && k < 3 * n + 2 + 2 * n * n {
            Quantity::Acceleration(k - 2 * n - 2 - 2 * n * n)
        } else if k >= waves_base(n) && k < waves_base(n) + 2 * n + 1 + n * n {
            let r = k - waves_base(n);
            if r < n {
                Quantity::ForceRadiation(r)
            } else if r < 2 * n {
                Quantity::ForceExcitation(r - n)
            } else if r == 2 * n {
                Quantity::WaveElevation
            } else {
                let r = r - 2 * n - 1;
                Quantity::StiffnessHydrostatic(r / n, r % n)
            }
        } else if self.drift && k >= drift_base(n) && k < drift_base(n) + n {
            Quantity::ForceDrift(k - drift_base(n))
        } else if self.drift && k == drift_base(n) + n {
            Quantity::Wave(WaveParameter::Drift)
        } else if self.viscous {
            return viscous::quantity(k, n, self.crossflow);
        } else {
            return None;
        };
        Some(q)
    }

    /// 1-based index in `<ModelVariables>`.
    pub(super) fn index_of(&self, quantity: Quantity) -> usize {
        self.variables
            .iter()
            .position(|v| v.quantity == quantity)
            .map(|p| p + 1)
            .unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nine() -> Vec<DofUnit> {
        [
            "sway", "heave", "roll", "cb1", "cb2", "cb3", "cb4", "cb5", "cb6",
        ]
        .iter()
        .map(|n| DofUnit::builtin(n).unwrap())
        .collect()
    }

    #[test]
    fn value_references_round_trip_and_are_unique() {
        for keep in [false, true] {
            let layout = Layout::new(nine(), keep).unwrap();
            let mut seen = std::collections::BTreeSet::new();
            for v in layout.variables() {
                assert!(seen.insert(v.value_reference), "{}", v.name);
                assert_eq!(layout.quantity(v.value_reference), Some(v.quantity));
            }
            let n = 9;
            let fixed = crate::fmu::description::PARAMETERS.len();
            // + force_radiation, force_excitation, wave.elevation, stiffness_hydrostatic.
            let expected =
                fixed + 2 * n + 2 + 2 * n * n + if keep { n } else { 0 } + 2 * n + 1 + n * n;
            assert_eq!(layout.variables().len(), expected);
            // One past the last per-hull reference is unknown.
            let last = layout.variables().iter().map(|v| v.value_reference).max();
            assert_eq!(layout.quantity(last.unwrap() + 1), None);
            assert_eq!(layout.quantity(10), None);
            assert_eq!(
                layout.quantity(2),
                Some(Quantity::Wave(WaveParameter::Kind))
            );
        }
        // Keeping A_inf does not move the other references.
        let a = Layout::new(nine(), false).unwrap();
        let b = Layout::new(nine(), true).unwrap();
        for v in a.variables() {
            assert_eq!(b.value_reference(v.quantity), Some(v.value_reference));
        }
    }

    #[test]
    fn units_follow_the_length_exponents() {
        let layout = Layout::new(nine(), true).unwrap();
        let unit = |name: &str| {
            layout
                .variables()
                .iter()
                .find(|v| v.name == name)
                .unwrap()
                .unit
        };
        assert_eq!(unit("velocity.sway"), "m/s");
        assert_eq!(unit("velocity.roll"), "rad/s");
        assert_eq!(unit("acceleration.cb3"), "rad/s2");
        assert_eq!(unit("force.heave"), "N/m");
        assert_eq!(unit("force.roll"), "N");
        assert_eq!(unit("added_mass_inf[1,1]"), "kg/m");
        assert_eq!(unit("added_mass_inf[1,3]"), "kg");
        assert_eq!(unit("added_mass_inf[3,6]"), "kg.m");
        assert_eq!(unit("damping_direct[2,2]"), "N.s/m2");
        assert_eq!(unit("damping_direct[3,1]"), "N.s/m");
        assert_eq!(unit("damping_direct[9,9]"), "N.s");
        let elastic = Layout::new(vec![DofUnit::new("bend", 1, false)], false).unwrap();
        let fixed = crate::fmu::description::PARAMETERS.len();
        assert_eq!(elastic.variables()[fixed].unit, "1/s");
        for v in layout.variables().iter().filter(|v| !v.integer) {
            assert!(
                crate::fmu::description::UNITS.contains(&v.unit),
                "{}",
                v.unit
            );
        }
    }

    #[test]
    fn bad_dofs_are_rejected() {
        assert!(Layout::new(vec![], false).is_err());
        assert!(Layout::new(vec![DofUnit::new("a b", 0, false)], false).is_err());
        assert!(Layout::new(vec![DofUnit::new("1a", 0, false)], false).is_err());
        assert!(Layout::new(vec![DofUnit::new("a", 2, false)], false).is_err());
        let twice = vec![DofUnit::new("a", 0, false), DofUnit::new("a", 1, true)];
        assert!(Layout::new(twice, false).is_err());
    }
}
