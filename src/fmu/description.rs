//! The FMU interface description: the fixed part generated at build time from
//! `modelDescription/fixed.xml` (so the code and the XML cannot drift), and the writer of a
//! hull's complete `modelDescription.xml`.
//!
//! Per-hull variables (velocities, forces, added mass at infinite frequency, direct damping,
//! power, energy; [`crate::fmu::variables`]) are added by `fmu-pack`, with value references
//! from [`FIRST_PER_HULL_REFERENCE`] on. The written file is the fixed text with `guid`,
//! `modelIdentifier`, the per-hull `<ScalarVariable>`s and the `<ModelStructure>` added:
//! forces depend on the velocities (and accelerations) where `damping_direct` (`A_inf`) is
//! non-zero, power on all inputs, energy on the velocities when `A_inf` is kept.

use crate::fmu::variables::{
    valid_name, Causality, Layout, Quantity, VariablesError, WaveParameter, DRIFT_CODES,
};
use nalgebra::DMatrix;
use quick_xml::events::{BytesEnd, BytesStart, BytesText, Event};
use quick_xml::{Reader, Writer};
use std::fmt;

/// A parameter declared in `modelDescription/fixed.xml`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedParameter {
    /// Variable name in the FMU.
    pub name: &'static str,
    /// FMI value reference.
    pub value_reference: u32,
    /// An `Integer` variable (else `Real`).
    pub integer: bool,
    /// Default value.
    pub start: f64,
    /// Smallest accepted value (minus infinity when unbounded).
    pub min: f64,
    /// Largest accepted value (infinite when unbounded).
    pub max: f64,
    /// Unit name, declared in the unit definitions.
    pub unit: &'static str,
    /// Human-readable description.
    pub description: &'static str,
}

include!(concat!(env!("OUT_DIR"), "/model_description.rs"));

/// Optional facts for the model description: the structural zeros of the direct feedthrough.
#[derive(Clone, Debug, Default)]
pub struct DescriptionInfo {
    /// `modelIdentifier` (also the binary's file name).
    pub model_identifier: String,
    /// GUID (see [`crate::fmu::guid::content_guid`]).
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

impl DescriptionInfo {
    /// A valid `modelIdentifier` and a GUID.
    pub(super) fn check(&self) -> Result<(), VariablesError> {
        if !valid_name(&self.model_identifier) {
            return Err(VariablesError::InvalidModelIdentifier(
                self.model_identifier.clone(),
            ));
        }
        if self.guid.is_empty() {
            return Err(VariablesError::EmptyGuid);
        }
        Ok(())
    }
}

impl Layout {
    /// The complete modelDescription.xml: the fixed text with `guid`, `modelIdentifier`,
    /// the per-hull variables and the `<ModelStructure>` added.
    pub fn model_description(
        &self,
        fixed_xml: &str,
        info: &DescriptionInfo,
    ) -> Result<String, VariablesError> {
        info.check()?;
        let fixed_count = PARAMETERS.len();
        let err = |e: &dyn fmt::Display| VariablesError::Xml(e.to_string());
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
                Event::End(e) if e.name().as_ref() == b"UnitDefinitions" => {
                    let extra = self.extra_unit_events();
                    if !extra.is_empty() {
                        let indent = BytesText::from_escaped("  ");
                        writer
                            .write_event(Event::Text(indent))
                            .map_err(|e| err(&e))?;
                        for event in extra {
                            writer.write_event(event).map_err(|e| err(&e))?;
                        }
                        writer
                            .write_event(Event::Text(BytesText::from_escaped("\n  ")))
                            .map_err(|e| err(&e))?;
                    }
                    writer.write_event(Event::End(e)).map_err(|e| err(&e))?;
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
                        return Err(VariablesError::FixedVariableCount {
                            declared: seen_variables,
                            expected: fixed_count,
                        });
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
            return Err(VariablesError::NoModelVariablesEnd);
        }
        let mut text = String::from_utf8(writer.into_inner()).map_err(|e| err(&e))?;
        if !text.ends_with('\n') {
            text.push('\n');
        }
        Ok(text)
    }

    /// The unit definitions the variables need beyond those of the fixed XML: `kg/m2` of a
    /// section's quadratic damping ([`Layout::with_viscous`]); none otherwise, so the
    /// descriptions of FMUs without it stay as they were.
    pub(super) fn extra_unit_events(&self) -> Vec<Event<'static>> {
        if !self.variables.iter().any(|v| v.unit == "kg/m2") {
            return Vec::new();
        }
        let mut unit = BytesStart::new("Unit");
        unit.push_attribute(("name", "kg/m2"));
        let mut base = BytesStart::new("BaseUnit");
        base.push_attribute(("kg", "1"));
        base.push_attribute(("m", "-2"));
        vec![
            Event::Start(unit),
            Event::Empty(base),
            Event::End(BytesEnd::new("Unit")),
        ]
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
            if v.quantity == Quantity::Wave(WaveParameter::Drift) {
                sv.push_attribute(("initial", "exact"));
            }
            sv.push_attribute(("description", v.description.as_str()));
            w.write_event(Event::Start(sv))?;
            w.write_event(Event::Text(BytesText::from_escaped("\n      ")))?;
            if v.quantity == Quantity::Wave(WaveParameter::Drift) {
                // wave.drift, the one per-hull Integer.
                let (min, max) = (DRIFT_CODES.0.to_string(), DRIFT_CODES.1.to_string());
                let mut integer = BytesStart::new("Integer");
                let start = format!("{}", v.start.unwrap_or(0.0) as i32);
                integer.push_attribute(("start", start.as_str()));
                integer.push_attribute(("min", min.as_str()));
                integer.push_attribute(("max", max.as_str()));
                w.write_event(Event::Empty(integer))?;
                w.write_event(Event::Text(BytesText::from_escaped("\n    ")))?;
                w.write_event(Event::End(BytesEnd::new("ScalarVariable")))?;
                continue;
            }
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

    /// Every output with the inputs it depends on directly (by 1-based index) and the kind
    /// of the dependency, in index order.
    pub(super) fn output_dependencies(
        &self,
        info: &DescriptionInfo,
    ) -> Vec<(usize, Vec<usize>, &'static str)> {
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
        let mut outputs: Vec<(usize, Vec<usize>, &'static str)> = Vec::new();
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
        // The radiation force depends on the inputs as the force does; the waves on none.
        for i in 0..n {
            let deps = outputs
                .iter()
                .find(|o| o.0 == self.index_of(Quantity::Force(i)))
                .map(|o| o.1.clone())
                .unwrap_or_default();
            outputs.push((self.index_of(Quantity::ForceRadiation(i)), deps, "fixed"));
            outputs.push((
                self.index_of(Quantity::ForceExcitation(i)),
                Vec::new(),
                "fixed",
            ));
        }
        outputs.push((self.index_of(Quantity::WaveElevation), Vec::new(), "fixed"));
        if self.drift {
            for i in 0..n {
                outputs.push((self.index_of(Quantity::ForceDrift(i)), Vec::new(), "fixed"));
            }
        }
        if self.viscous {
            // The viscous force is nonlinear in the velocities and the current: it (and the
            // force) may depend on every velocity and on both current inputs.
            let mut viscous_deps = velocity.clone();
            viscous_deps.push(self.index_of(Quantity::CurrentSpeed));
            viscous_deps.push(self.index_of(Quantity::CurrentHeading));
            for i in 0..n {
                let force = self.index_of(Quantity::Force(i));
                if let Some(entry) = outputs.iter_mut().find(|o| o.0 == force) {
                    entry.1.extend(&viscous_deps);
                    entry.1.sort_unstable();
                    entry.1.dedup();
                    entry.2 = "dependent";
                }
                let index = self.index_of(Quantity::ForceViscous(i));
                outputs.push((index, viscous_deps.clone(), "dependent"));
            }
        }
        outputs.sort_by_key(|o| o.0);
        outputs
    }

    fn write_structure(
        &self,
        w: &mut Writer<Vec<u8>>,
        info: &DescriptionInfo,
    ) -> Result<(), quick_xml::Error> {
        let outputs = self.output_dependencies(info);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmu::units::DofUnit;

    #[test]
    fn fixed_parameters_have_the_documented_defaults() {
        assert_eq!(DEFAULT_RHO, 1025.0);
        assert_eq!(DEFAULT_G, 9.81);
        assert_ne!(VR_RHO, VR_G);
        assert!(PARAMETERS
            .iter()
            .all(|p| p.value_reference < FIRST_PER_HULL_REFERENCE));
        assert!(PARAMETERS.iter().all(|p| if p.integer {
            p.unit.is_empty()
        } else {
            UNITS.contains(&p.unit)
        }));
        assert!(PARAMETERS
            .iter()
            .all(|p| p.min <= p.start && p.start <= p.max));
    }

    #[test]
    fn both_descriptions_declare_the_limits_the_instance_enforces() {
        let limit = |name: &str| {
            let p = PARAMETERS.iter().find(|p| p.name == name).unwrap();
            (p.min, p.max)
        };
        assert_eq!(limit("wave.gamma"), (1.0, crate::waves::MAX_GAMMA));
        let components = crate::waves::MAX_COMPONENTS as f64;
        assert_eq!(limit("wave.components"), (1.0, components));
        assert_eq!(limit("rho").1, crate::model::MAX_INPUT);
        assert_eq!(limit("g").1, crate::model::MAX_INPUT);
        // Any finite heading is one direction (modulo 360 degrees).
        assert_eq!(limit("wave.heading"), (f64::NEG_INFINITY, f64::INFINITY));
        let layout = Layout::new(vec![DofUnit::builtin("sway").unwrap()], false).unwrap();
        let info = DescriptionInfo {
            model_identifier: "Limits".into(),
            guid: "{limits}".into(),
            ..Default::default()
        };
        for xml in [
            layout.model_description(FIXED_XML, &info).unwrap(),
            layout.model_description_fmi3(FIXED_XML, &info).unwrap(),
        ] {
            let root = crate::xml::parse(&xml).unwrap();
            for p in PARAMETERS {
                // FMI 2.0: the <Real>/<Integer> inside the variable; FMI 3.0: the variable.
                let variable = root
                    .descendants()
                    .find(|e| e.attribute("name") == Some(p.name))
                    .unwrap();
                let typed = variable.children.first().unwrap_or(variable);
                let declared = |key: &str, unbounded: f64| {
                    typed
                        .attribute(key)
                        .map_or(unbounded, |v| v.parse::<f64>().unwrap())
                };
                let found = (
                    declared("min", f64::NEG_INFINITY),
                    declared("max", f64::INFINITY),
                );
                assert_eq!(found, (p.min, p.max), "{}", p.name);
            }
        }
    }

    #[test]
    fn capabilities_match_the_product() {
        let flag = |key: &str| {
            CAPABILITIES
                .iter()
                .find(|(k, _)| *k == key)
                .map(|(_, v)| *v)
        };
        for key in [
            "canHandleVariableCommunicationStepSize",
            "canGetAndSetFMUstate",
            "canSerializeFMUstate",
            "providesDirectionalDerivative",
            "canInterpolateInputs",
            "canNotUseMemoryManagementFunctions",
        ] {
            assert_eq!(flag(key), Some("true"), "{key}");
        }
        assert_eq!(MAX_OUTPUT_DERIVATIVE_ORDER, 1);
        assert!(FIXED_XML.contains("<fmiModelDescription"));
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
        // force.sway depends on velocity.sway (after the 10 fixed parameters: index 11)
        // through damping and on both accelerations (A_inf unknown: all).
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
        let fixed = PARAMETERS.len();
        assert_eq!(force_sway.1, format!("{} {} {}", fixed + 1, acc[0], acc[1]));
        let calculated = causalities
            .iter()
            .filter(|c| *c == "calculatedParameter")
            .count();
        assert_eq!(initial.len(), output_count + calculated);
        assert!(initial.windows(2).all(|w| w[0] < w[1]));
        assert!(xml.contains("guid=\"{abc}\""));
    }
}
