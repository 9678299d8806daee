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
//!
//! plus the fixed parameters `rho`, `g` of `modelDescription/fixed.xml`. `force` is the
//! generalized force on the hull by the water per unit length; `power = -force . velocity`
//! is the power the hull delivers to the water; `energy` is the energy stored in the
//! equivalent network (plus `1/2 v^T A_inf v` when the FMU keeps `A_inf`).
//!
//! Units follow each DOF's length exponent e (0: a translation, generalized coordinate in m;
//! 1: a rotation or a dimensionless mode amplitude): velocity m/s, rad/s or 1/s; force N/m
//! or N; `added_mass_inf[i,j]` kg/m, kg, kg.m and `damping_direct[i,j]` N.s/m2, N.s/m, N.s
//! for e_i + e_j = 0, 1, 2.
//!
//! [`Layout::model_description`] writes the complete `modelDescription.xml` from the fixed
//! text ([`crate::model_description::FIXED_XML`]); [`content_guid`] derives the GUID from the
//! packed resources, so the FMI layer can check it against them at instantiation.

use crate::model_description::{FIRST_PER_HULL_REFERENCE, PARAMETERS, VR_G, VR_RHO};
use nalgebra::DMatrix;
use quick_xml::events::{BytesEnd, BytesStart, BytesText, Event};
use quick_xml::{Reader, Writer};
use std::fmt;

/// Why a layout or a model description could not be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VariablesError(pub String);

impl fmt::Display for VariablesError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "FMU variables: {}", self.0)
    }
}

impl std::error::Error for VariablesError {}

/// Unit information of one DOF, filled from the hull by `fmu-pack`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DofUnit {
    /// DOF name (a letter, then letters, digits or `_`).
    pub name: String,
    /// 0: the generalized coordinate is a length (m); 1: it is an angle or a dimensionless
    /// mode amplitude, and the generalized force carries one more metre.
    pub length_exponent: u8,
    /// For `length_exponent` 1: the coordinate is an angle (rad) rather than dimensionless.
    pub is_angle: bool,
}

impl DofUnit {
    /// A DOF with the given unit information.
    pub fn new(name: &str, length_exponent: u8, is_angle: bool) -> DofUnit {
        DofUnit {
            name: name.to_string(),
            length_exponent,
            is_angle,
        }
    }

    /// Unit information of the built-in DOF names: `sway`, `heave`, `cb1`, `cb2`, `cb4`,
    /// `cb5` are displacements (e = 0); `roll`, `cb3`, `cb6` are angles (e = 1).
    pub fn builtin(name: &str) -> Option<DofUnit> {
        match name {
            "sway" | "heave" | "cb1" | "cb2" | "cb4" | "cb5" => Some(DofUnit::new(name, 0, false)),
            "roll" | "cb3" | "cb6" => Some(DofUnit::new(name, 1, true)),
            _ => None,
        }
    }

    /// Unit of the velocity input.
    pub fn velocity_unit(&self) -> &'static str {
        match (self.length_exponent, self.is_angle) {
            (0, _) => "m/s",
            (_, true) => "rad/s",
            _ => "1/s",
        }
    }

    /// Unit of the acceleration input.
    pub fn acceleration_unit(&self) -> &'static str {
        match (self.length_exponent, self.is_angle) {
            (0, _) => "m/s2",
            (_, true) => "rad/s2",
            _ => "1/s2",
        }
    }

    /// Unit of the generalized force per unit length.
    pub fn force_unit(&self) -> &'static str {
        if self.length_exponent == 0 {
            "N/m"
        } else {
            "N"
        }
    }
}

fn added_mass_unit(exponent_sum: u8) -> &'static str {
    ["kg/m", "kg", "kg.m"][exponent_sum.min(2) as usize]
}

fn damping_unit(exponent_sum: u8) -> &'static str {
    ["N.s/m2", "N.s/m", "N.s"][exponent_sum.min(2) as usize]
}

/// What a variable is. Indices are 0-based DOF indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Water density (fixed parameter).
    Rho,
    /// Gravity (fixed parameter).
    G,
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
    /// Power the hull delivers to the water (output).
    Power,
    /// Energy stored in the network (output).
    Energy,
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

/// Optional facts for the model description: the structural zeros of the direct feedthrough.
#[derive(Clone, Debug, Default)]
pub struct DescriptionInfo {
    /// `modelIdentifier` (also the binary's file name).
    pub model_identifier: String,
    /// GUID (see [`content_guid`]).
    pub guid: String,
    /// Replaces the fixed `modelName` when given.
    pub model_name: Option<String>,
    /// Replaces the fixed `description` when given.
    pub description: Option<String>,
    /// Direct damping at the reference rho, g: force_i depends on velocity_j only where the
    /// entry is non-zero (all, when `None`).
    pub damping_direct: Option<DMatrix<f64>>,
    /// A_inf: force_i depends on acceleration_j only where non-zero (all, when `None`).
    pub added_mass_inf: Option<DMatrix<f64>>,
}

/// The variables of one hull's FMU.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    dofs: Vec<DofUnit>,
    keep_inf_mass: bool,
    variables: Vec<Variable>,
}

fn valid_name(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

impl Layout {
    /// The layout for these DOFs; `keep_inf_mass` adds the acceleration inputs.
    pub fn new(dofs: Vec<DofUnit>, keep_inf_mass: bool) -> Result<Layout, VariablesError> {
        if dofs.is_empty() {
            return Err(VariablesError("a hull needs at least one DOF".into()));
        }
        for (i, d) in dofs.iter().enumerate() {
            if !valid_name(&d.name) {
                return Err(VariablesError(format!(
                    "DOF name '{}' must be a letter followed by letters, digits or '_'",
                    d.name
                )));
            }
            if d.length_exponent > 1 {
                return Err(VariablesError(format!(
                    "DOF '{}': length exponent {} (0 or 1 expected)",
                    d.name, d.length_exponent
                )));
            }
            if dofs[..i].iter().any(|o| o.name == d.name) {
                return Err(VariablesError(format!("DOF '{}' appears twice", d.name)));
            }
        }
        let n = dofs.len();
        if n > 1000 {
            return Err(VariablesError(format!("{n} DOFs is too many")));
        }
        let mut layout = Layout {
            dofs,
            keep_inf_mass,
            variables: Vec::new(),
        };
        let mut vars = Vec::new();
        for p in PARAMETERS {
            let quantity = if p.value_reference == VR_RHO {
                Quantity::Rho
            } else if p.value_reference == VR_G {
                Quantity::G
            } else {
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
            });
        }
        for (i, d) in layout.dofs.iter().enumerate() {
            vars.push(Variable {
                name: format!("force.{}", d.name),
                value_reference: 0,
                quantity: Quantity::Force(i),
                causality: Causality::Output,
                unit: d.force_unit(),
                description: format!(
                    "Generalized force on the hull by the water in DOF {}, per unit length, {}",
                    d.name, force_note
                ),
                start: None,
            });
        }
        vars.push(Variable {
            name: "power".into(),
            value_reference: 0,
            quantity: Quantity::Power,
            causality: Causality::Output,
            unit: "W/m",
            description: "Power the hull delivers to the water, -force . velocity".into(),
            start: None,
        });
        vars.push(Variable {
            name: "energy".into(),
            value_reference: 0,
            quantity: Quantity::Energy,
            causality: Causality::Output,
            unit: "J/m",
            description: if keep_inf_mass {
                "Energy stored in the equivalent network, including 1/2 v.added_mass_inf.v".into()
            } else {
                "Energy stored in the equivalent network".into()
            },
            start: None,
        });
        for (kind, unit_of) in [
            (0, added_mass_unit as fn(u8) -> &'static str),
            (1, damping_unit),
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
                        unit: unit_of(sum),
                        description,
                        start: None,
                    });
                }
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
                });
            }
        }
        for v in &mut vars {
            if !matches!(v.quantity, Quantity::Rho | Quantity::G) {
                v.value_reference = layout
                    .value_reference(v.quantity)
                    .ok_or_else(|| VariablesError("internal: no value reference".into()))?;
            }
        }
        layout.variables = vars;
        Ok(layout)
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
            Quantity::Rho => return Some(VR_RHO),
            Quantity::G => return Some(VR_G),
            Quantity::Velocity(i) if i < n => i,
            Quantity::Force(i) if i < n => n + i,
            Quantity::Power => 2 * n,
            Quantity::Energy => 2 * n + 1,
            Quantity::AddedMassInf(i, j) if i < n && j < n => 2 * n + 2 + i * n + j,
            Quantity::DampingDirect(i, j) if i < n && j < n => 2 * n + 2 + n * n + i * n + j,
            Quantity::Acceleration(i) if i < n && self.keep_inf_mass => 2 * n + 2 + 2 * n * n + i,
            _ => return None,
        };
        u32::try_from(base + offset).ok()
    }

    /// What the value reference refers to (constant time).
    pub fn quantity(&self, value_reference: u32) -> Option<Quantity> {
        if value_reference == VR_RHO {
            return Some(Quantity::Rho);
        }
        if value_reference == VR_G {
            return Some(Quantity::G);
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
        } else {
            return None;
        };
        Some(q)
    }

    /// 1-based index in `<ModelVariables>`.
    fn index_of(&self, quantity: Quantity) -> usize {
        self.variables
            .iter()
            .position(|v| v.quantity == quantity)
            .map(|p| p + 1)
            .unwrap_or(0)
    }

    /// The complete modelDescription.xml: the fixed text with `guid`, `modelIdentifier`,
    /// the per-hull variables and the `<ModelStructure>` added.
    pub fn model_description(
        &self,
        fixed_xml: &str,
        info: &DescriptionInfo,
    ) -> Result<String, VariablesError> {
        if !valid_name(&info.model_identifier) {
            return Err(VariablesError(format!(
                "model identifier '{}' must be a letter followed by letters, digits or '_'",
                info.model_identifier
            )));
        }
        if info.guid.is_empty() {
            return Err(VariablesError("empty GUID".into()));
        }
        let fixed_count = PARAMETERS.len();
        let err = |e: &dyn fmt::Display| VariablesError(format!("XML: {e}"));
        let mut reader = Reader::from_str(fixed_xml);
        let mut writer = Writer::new(Vec::new());
        let mut seen_variables = 0usize;
        let mut in_variables = false;
        let mut done = false;
        let mut pending: Option<BytesText<'static>> = None;
        loop {
            let event = reader.read_event().map_err(|e| err(&e))?;
            if let Event::Text(t) = &event {
                if t.iter().all(|b| b.is_ascii_whitespace()) {
                    pending = Some(t.clone().into_owned());
                    continue;
                }
            }
            // Whitespace before the template's comment and before </ModelVariables> goes.
            let skip_pending = matches!(&event, Event::Comment(_))
                || matches!(&event, Event::End(e) if e.name().as_ref() == b"ModelVariables");
            if let Some(t) = pending.take() {
                if !skip_pending {
                    writer.write_event(Event::Text(t)).map_err(|e| err(&e))?;
                }
            }
            match event {
                Event::Eof => break,
                Event::Comment(_) => {}
                Event::Start(e) if e.name().as_ref() == b"fmiModelDescription" => {
                    let mut root = BytesStart::new("fmiModelDescription");
                    for a in e.attributes() {
                        let a = a.map_err(|e| err(&e))?;
                        let key = a.key.as_ref();
                        let replace = match key {
                            b"modelName" => info.model_name.as_deref(),
                            b"description" => info.description.as_deref(),
                            _ => None,
                        };
                        match replace {
                            Some(v) => root.push_attribute((
                                std::str::from_utf8(key).map_err(|e| err(&e))?,
                                v,
                            )),
                            None => root.push_attribute(a),
                        }
                    }
                    root.push_attribute(("guid", info.guid.as_str()));
                    root.push_attribute(("numberOfEventIndicators", "0"));
                    writer
                        .write_event(Event::Start(root))
                        .map_err(|e| err(&e))?;
                    writer
                        .write_event(Event::Text(BytesText::from_escaped("\n  ")))
                        .map_err(|e| err(&e))?;
                    writer
                        .write_event(Event::Comment(BytesText::new(
                            " Written by hydrofmu fmu-pack from modelDescription/fixed.xml and the hull DOFs ",
                        )))
                        .map_err(|e| err(&e))?;
                }
                Event::Empty(e) if e.name().as_ref() == b"CoSimulation" => {
                    let mut cs = BytesStart::new("CoSimulation");
                    cs.push_attribute(("modelIdentifier", info.model_identifier.as_str()));
                    for a in e.attributes() {
                        cs.push_attribute(a.map_err(|e| err(&e))?);
                    }
                    writer.write_event(Event::Empty(cs)).map_err(|e| err(&e))?;
                }
                Event::Start(e) if e.name().as_ref() == b"ModelVariables" => {
                    in_variables = true;
                    writer.write_event(Event::Start(e)).map_err(|e| err(&e))?;
                }
                Event::Start(e) if in_variables && e.name().as_ref() == b"ScalarVariable" => {
                    seen_variables += 1;
                    writer.write_event(Event::Start(e)).map_err(|e| err(&e))?;
                }
                Event::End(e) if e.name().as_ref() == b"ModelVariables" => {
                    if seen_variables != fixed_count {
                        return Err(VariablesError(format!(
                            "the fixed XML declares {seen_variables} variables, the constants {fixed_count}"
                        )));
                    }
                    self.write_variables(&mut writer, fixed_count)
                        .map_err(|e| err(&e))?;
                    writer
                        .write_event(Event::Text(BytesText::from_escaped("\n  ")))
                        .map_err(|e| err(&e))?;
                    writer.write_event(Event::End(e)).map_err(|e| err(&e))?;
                    self.write_structure(&mut writer, info)
                        .map_err(|e| err(&e))?;
                    in_variables = false;
                    done = true;
                }
                other => writer.write_event(other).map_err(|e| err(&e))?,
            }
        }
        if !done {
            return Err(VariablesError(
                "the fixed XML has no </ModelVariables>".into(),
            ));
        }
        let mut text = String::from_utf8(writer.into_inner()).map_err(|e| err(&e))?;
        if !text.ends_with('\n') {
            text.push('\n');
        }
        Ok(text)
    }

    fn write_variables(
        &self,
        w: &mut Writer<Vec<u8>>,
        fixed_count: usize,
    ) -> Result<(), quick_xml::Error> {
        for (index, v) in self.variables.iter().enumerate().skip(fixed_count) {
            w.write_event(Event::Text(BytesText::from_escaped("\n    ")))?;
            w.write_event(Event::Comment(BytesText::new(&format!(
                " index {} ",
                index + 1
            ))))?;
            w.write_event(Event::Text(BytesText::from_escaped("\n    ")))?;
            let mut sv = BytesStart::new("ScalarVariable");
            let vr = v.value_reference.to_string();
            sv.push_attribute(("name", v.name.as_str()));
            sv.push_attribute(("valueReference", vr.as_str()));
            sv.push_attribute(("causality", v.causality.as_str()));
            sv.push_attribute(("variability", v.variability()));
            if v.causality == Causality::CalculatedParameter {
                sv.push_attribute(("initial", "calculated"));
            }
            sv.push_attribute(("description", v.description.as_str()));
            w.write_event(Event::Start(sv))?;
            w.write_event(Event::Text(BytesText::from_escaped("\n      ")))?;
            let mut real = BytesStart::new("Real");
            let start = v.start.map(|s| format!("{s:?}"));
            if let Some(s) = &start {
                real.push_attribute(("start", s.as_str()));
            }
            real.push_attribute(("unit", v.unit));
            w.write_event(Event::Empty(real))?;
            w.write_event(Event::Text(BytesText::from_escaped("\n    ")))?;
            w.write_event(Event::End(BytesEnd::new("ScalarVariable")))?;
        }
        Ok(())
    }

    fn write_structure(
        &self,
        w: &mut Writer<Vec<u8>>,
        info: &DescriptionInfo,
    ) -> Result<(), quick_xml::Error> {
        let n = self.dofs.len();
        let nonzero = |m: &Option<DMatrix<f64>>, i: usize, j: usize| match m {
            Some(m) if m.nrows() == n && m.ncols() == n => m[(i, j)] != 0.0,
            _ => true,
        };
        let velocity: Vec<usize> = (0..n)
            .map(|j| self.index_of(Quantity::Velocity(j)))
            .collect();
        let acceleration: Vec<usize> = if self.keep_inf_mass {
            (0..n)
                .map(|j| self.index_of(Quantity::Acceleration(j)))
                .collect()
        } else {
            Vec::new()
        };
        let mut outputs: Vec<(usize, Vec<usize>, &str)> = Vec::new();
        for i in 0..n {
            let mut deps: Vec<usize> = (0..n)
                .filter(|&j| nonzero(&info.damping_direct, i, j))
                .map(|j| velocity[j])
                .collect();
            for (j, &index) in acceleration.iter().enumerate() {
                if nonzero(&info.added_mass_inf, i, j) {
                    deps.push(index);
                }
            }
            deps.sort_unstable();
            outputs.push((self.index_of(Quantity::Force(i)), deps, "fixed"));
        }
        let all_inputs: Vec<usize> = {
            let mut v: Vec<usize> = velocity.iter().chain(&acceleration).copied().collect();
            v.sort_unstable();
            v
        };
        outputs.push((
            self.index_of(Quantity::Power),
            all_inputs.clone(),
            "dependent",
        ));
        let energy_deps = if self.keep_inf_mass {
            velocity.clone()
        } else {
            Vec::new()
        };
        outputs.push((self.index_of(Quantity::Energy), energy_deps, "dependent"));
        outputs.sort_by_key(|o| o.0);

        let text = |w: &mut Writer<Vec<u8>>, s: &str| {
            w.write_event(Event::Text(BytesText::from_escaped(s)))
        };
        text(w, "\n  ")?;
        w.write_event(Event::Start(BytesStart::new("ModelStructure")))?;
        text(w, "\n    ")?;
        w.write_event(Event::Start(BytesStart::new("Outputs")))?;
        for (index, deps, kind) in &outputs {
            text(w, "\n      ")?;
            let mut u = BytesStart::new("Unknown");
            let index = index.to_string();
            u.push_attribute(("index", index.as_str()));
            let deps_text = deps
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(" ");
            let kinds = vec![*kind; deps.len()].join(" ");
            u.push_attribute(("dependencies", deps_text.as_str()));
            if !deps.is_empty() {
                u.push_attribute(("dependenciesKind", kinds.as_str()));
            }
            w.write_event(Event::Empty(u))?;
        }
        text(w, "\n    ")?;
        w.write_event(Event::End(BytesEnd::new("Outputs")))?;
        text(w, "\n    ")?;
        w.write_event(Event::Start(BytesStart::new("InitialUnknowns")))?;
        // Outputs and calculated parameters, ascending index; no `dependencies`: they may
        // depend on every known (inputs, rho, g).
        for (index, v) in self.variables.iter().enumerate() {
            if matches!(
                v.causality,
                Causality::Output | Causality::CalculatedParameter
            ) {
                text(w, "\n      ")?;
                let mut u = BytesStart::new("Unknown");
                let index = (index + 1).to_string();
                u.push_attribute(("index", index.as_str()));
                w.write_event(Event::Empty(u))?;
            }
        }
        text(w, "\n    ")?;
        w.write_event(Event::End(BytesEnd::new("InitialUnknowns")))?;
        text(w, "\n  ")?;
        w.write_event(Event::End(BytesEnd::new("ModelStructure")))?;
        Ok(())
    }
}

/// The GUID of an FMU, derived from the resources it carries: SHA-256 over each part's
/// name and bytes (length-prefixed), shown as a UUID (`{8-4-4-4-12}` hex digits).
pub fn content_guid(parts: &[(&str, &[u8])]) -> String {
    let mut data = Vec::new();
    data.extend_from_slice(b"hydrofmu-guid-v1");
    for (name, bytes) in parts {
        data.extend_from_slice(&(name.len() as u64).to_le_bytes());
        data.extend_from_slice(name.as_bytes());
        data.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
        data.extend_from_slice(bytes);
    }
    let digest = sha256(&data);
    let hex: String = digest[..16].iter().map(|b| format!("{b:02x}")).collect();
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}

/// SHA-256 (FIPS 180-4).
pub fn sha256(data: &[u8]) -> [u8; 32] {
    const K: [u32; 64] = [
        0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4,
        0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe,
        0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f,
        0x4a7484aa, 0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7,
        0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85, 0x2e1b2138, 0x4d2c6dfc,
        0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b,
        0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116,
        0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
        0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7,
        0xc67178f2,
    ];
    let mut h: [u32; 8] = [
        0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab,
        0x5be0cd19,
    ];
    let mut message = data.to_vec();
    message.push(0x80);
    while message.len() % 64 != 56 {
        message.push(0);
    }
    message.extend_from_slice(&((data.len() as u64).wrapping_mul(8)).to_be_bytes());
    for block in message.chunks_exact(64) {
        let mut w = [0u32; 64];
        for (i, word) in block.chunks_exact(4).enumerate() {
            w[i] = u32::from_be_bytes([word[0], word[1], word[2], word[3]]);
        }
        for i in 16..64 {
            let s0 = w[i - 15].rotate_right(7) ^ w[i - 15].rotate_right(18) ^ (w[i - 15] >> 3);
            let s1 = w[i - 2].rotate_right(17) ^ w[i - 2].rotate_right(19) ^ (w[i - 2] >> 10);
            w[i] = w[i - 16]
                .wrapping_add(s0)
                .wrapping_add(w[i - 7])
                .wrapping_add(s1);
        }
        let mut v = h;
        for i in 0..64 {
            let s1 = v[4].rotate_right(6) ^ v[4].rotate_right(11) ^ v[4].rotate_right(25);
            let ch = (v[4] & v[5]) ^ (!v[4] & v[6]);
            let t1 = v[7]
                .wrapping_add(s1)
                .wrapping_add(ch)
                .wrapping_add(K[i])
                .wrapping_add(w[i]);
            let s0 = v[0].rotate_right(2) ^ v[0].rotate_right(13) ^ v[0].rotate_right(22);
            let maj = (v[0] & v[1]) ^ (v[0] & v[2]) ^ (v[1] & v[2]);
            let t2 = s0.wrapping_add(maj);
            v[7] = v[6];
            v[6] = v[5];
            v[5] = v[4];
            v[4] = v[3].wrapping_add(t1);
            v[3] = v[2];
            v[2] = v[1];
            v[1] = v[0];
            v[0] = t1.wrapping_add(t2);
        }
        for (hi, vi) in h.iter_mut().zip(v) {
            *hi = hi.wrapping_add(vi);
        }
    }
    let mut out = [0u8; 32];
    for (i, word) in h.iter().enumerate() {
        out[4 * i..4 * i + 4].copy_from_slice(&word.to_be_bytes());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model_description::FIXED_XML;

    fn hex(d: &[u8]) -> String {
        d.iter().map(|b| format!("{b:02x}")).collect()
    }

    fn nine() -> Vec<DofUnit> {
        [
            "sway", "heave", "roll", "cb1", "cb2", "cb3", "cb4", "cb5", "cb6",
        ]
        .iter()
        .map(|n| DofUnit::builtin(n).unwrap())
        .collect()
    }

    #[test]
    fn sha256_matches_the_standard_test_vectors() {
        assert_eq!(
            hex(&sha256(b"")),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
        assert_eq!(
            hex(&sha256(b"abc")),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!(
            hex(&sha256(
                b"abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"
            )),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1"
        );
    }

    #[test]
    fn guid_depends_on_every_part() {
        let a = content_guid(&[("network.xml", b"x"), ("hull.xml", b"y")]);
        let b = content_guid(&[("network.xml", b"x"), ("hull.xml", b"z")]);
        let c = content_guid(&[("network.xml", b"xy"), ("hull.xml", b"")]);
        assert_ne!(a, b);
        assert_ne!(a, c);
        assert_eq!(a.len(), 38);
        assert_eq!(
            a,
            content_guid(&[("network.xml", b"x"), ("hull.xml", b"y")])
        );
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
            let expected = 2 + 2 * n + 2 + 2 * n * n + if keep { n } else { 0 };
            assert_eq!(layout.variables().len(), expected);
            // One past the last per-hull reference is unknown.
            let last = layout.variables().iter().map(|v| v.value_reference).max();
            assert_eq!(layout.quantity(last.unwrap() + 1), None);
            assert_eq!(layout.quantity(2), None);
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
        assert_eq!(elastic.variables()[2].unit, "1/s");
        for v in layout.variables() {
            assert!(
                crate::model_description::UNITS.contains(&v.unit),
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

    #[test]
    fn model_description_is_well_formed_and_complete() {
        let layout = Layout::new(
            vec![
                DofUnit::builtin("sway").unwrap(),
                DofUnit::builtin("roll").unwrap(),
            ],
            true,
        )
        .unwrap();
        let mut damping = DMatrix::zeros(2, 2);
        damping[(0, 0)] = 1.0;
        damping[(1, 1)] = 2.0;
        let info = DescriptionInfo {
            model_identifier: "Test_1".into(),
            guid: "{abc}".into(),
            damping_direct: Some(damping),
            ..Default::default()
        };
        let xml = layout.model_description(FIXED_XML, &info).unwrap();
        // Parse it back: every variable appears once, in order, and ModelStructure indices
        // point at outputs.
        let mut reader = Reader::from_str(&xml);
        let mut names = Vec::new();
        let mut causalities = Vec::new();
        let mut outputs = Vec::new();
        let mut initial = Vec::new();
        let mut section = "";
        let mut model_identifier = None;
        loop {
            match reader.read_event().unwrap() {
                Event::Eof => break,
                Event::Start(e) | Event::Empty(e) => {
                    let get = |k: &str| {
                        e.attributes()
                            .map(|a| a.unwrap())
                            .find(|a| a.key.as_ref() == k.as_bytes())
                            .map(|a| a.unescape_value().unwrap().into_owned())
                    };
                    match e.name().as_ref() {
                        b"ScalarVariable" => {
                            names.push(get("name").unwrap());
                            causalities.push(get("causality").unwrap());
                        }
                        b"CoSimulation" => model_identifier = get("modelIdentifier"),
                        b"Outputs" => section = "outputs",
                        b"InitialUnknowns" => section = "initial",
                        b"Unknown" => {
                            let index: usize = get("index").unwrap().parse().unwrap();
                            let deps = get("dependencies").unwrap_or_default();
                            if section == "outputs" {
                                outputs.push((index, deps));
                            } else {
                                initial.push(index);
                            }
                        }
                        _ => {}
                    }
                }
                _ => {}
            }
        }
        assert_eq!(model_identifier.as_deref(), Some("Test_1"));
        let expected: Vec<&str> = layout.variables().iter().map(|v| v.name.as_str()).collect();
        assert_eq!(names, expected);
        let output_count = causalities.iter().filter(|c| *c == "output").count();
        assert_eq!(outputs.len(), output_count);
        for (index, _) in &outputs {
            assert_eq!(causalities[index - 1], "output");
        }
        // force.sway (index 7: rho g v v f f) depends on velocity.sway (3) through damping
        // and on both accelerations (A_inf unknown: all).
        let force_sway = outputs
            .iter()
            .find(|o| names[o.0 - 1] == "force.sway")
            .unwrap();
        let acc: Vec<usize> = names
            .iter()
            .enumerate()
            .filter(|(_, n)| n.starts_with("acceleration."))
            .map(|(i, _)| i + 1)
            .collect();
        assert_eq!(force_sway.1, format!("3 {} {}", acc[0], acc[1]));
        let calculated = causalities
            .iter()
            .filter(|c| *c == "calculatedParameter")
            .count();
        assert_eq!(initial.len(), output_count + calculated);
        assert!(initial.windows(2).all(|w| w[0] < w[1]));
        assert!(xml.contains("guid=\"{abc}\""));
    }
}
