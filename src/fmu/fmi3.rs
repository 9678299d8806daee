//! The FMI 3.0 view of a [`Layout`] and its `modelDescription.xml`.
//!
//! The value references are those of FMI 2.0, with two differences:
//! - the n x n matrices `added_mass_inf`, `damping_direct` and `stiffness_hydrostatic` are
//!   array variables (`<Dimension start="n"/>` twice), each with the value reference of its
//!   (1,1) entry; their values are the entries in row-major order (`A[i,j]` at `i n + j`);
//! - `time`, the independent variable FMI 3.0 requires, has [`VR_TIME`].
//!
//! Every scalar (parameters, `velocity.<dof>`, `force.<dof>`, ...) keeps its name, value
//! reference, unit and causality, so a master sees the same ports in both standards.

use crate::fmi::{Function, Standard};
use crate::fmu::description::{DescriptionInfo, PARAMETERS};
use crate::fmu::variables::{
    Causality, Layout, Quantity, VariablesError, WaveParameter, DRIFT_CODES,
};
use quick_xml::events::{BytesEnd, BytesStart, BytesText, Event};
use quick_xml::{Reader, Writer};
use std::fmt;

/// Value reference of `time` (FMI 3.0 only; in the range of the fixed variables).
pub const VR_TIME: u32 = 99;

/// What an FMI 3.0 value reference names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fmi3Reference {
    /// The independent variable `time`.
    Time,
    /// A scalar: the same value reference in FMI 2.0.
    Scalar(u32),
    /// An n x n matrix: the FMI 2.0 value references `first .. first + count`, row-major.
    Array {
        /// Value reference of the (1,1) entry (also the array's).
        first: u32,
        /// n * n.
        count: usize,
    },
}

/// One of the three matrices, as an FMI 3.0 array variable.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrayVariable {
    /// Name (`added_mass_inf`, ...).
    pub name: &'static str,
    /// Value reference (of the (1,1) entry).
    pub value_reference: u32,
    /// The unit of every entry, when they share one (DOFs of one length exponent).
    pub unit: Option<&'static str>,
    /// Description, naming the units when they differ.
    pub description: String,
}

/// The matrix a quantity is an entry of: its array name and (row, column).
fn matrix_entry(q: Quantity) -> Option<(&'static str, usize, usize)> {
    match q {
        Quantity::AddedMassInf(i, j) => Some(("added_mass_inf", i, j)),
        Quantity::DampingDirect(i, j) => Some(("damping_direct", i, j)),
        Quantity::StiffnessHydrostatic(i, j) => Some(("stiffness_hydrostatic", i, j)),
        _ => None,
    }
}

/// `text` (of the FMI 2.0 description) with the FMI 2.0 functions it names replaced by their
/// FMI 3.0 counterparts, and "fmi2 call" by "fmi3 call".
pub fn fmi3_function_names(text: &str) -> String {
    let mut functions: Vec<Function> = Function::ALL.to_vec();
    // Longest first: fmi2GetRealStatus before fmi2GetReal.
    functions.sort_by_key(|f| std::cmp::Reverse(f.name().len()));
    let mut out = text.replace("fmi2 call", "fmi3 call");
    for f in functions {
        let fmi3 = f.name_in(Standard::Fmi3);
        if fmi3.starts_with("fmi3") && !fmi3.contains(' ') {
            out = out.replace(f.name(), fmi3);
        }
    }
    out
}

impl Layout {
    /// What the FMI 3.0 value reference `vr` names (`None`: not a variable; an entry of a
    /// matrix other than its first is not one of its own in FMI 3.0).
    pub fn fmi3_reference(&self, vr: u32) -> Option<Fmi3Reference> {
        if vr == VR_TIME {
            return Some(Fmi3Reference::Time);
        }
        let q = self.quantity(vr)?;
        match matrix_entry(q) {
            Some((_, 0, 0)) => Some(Fmi3Reference::Array {
                first: vr,
                count: self.dof_count() * self.dof_count(),
            }),
            Some(_) => None,
            None => Some(Fmi3Reference::Scalar(vr)),
        }
    }

    /// The three matrices as array variables.
    pub fn fmi3_arrays(&self) -> Vec<ArrayVariable> {
        let mut arrays = Vec::new();
        for v in &self.variables {
            let Some((name, 0, 0)) = matrix_entry(v.quantity) else {
                continue;
            };
            // (e_i + e_j, unit) of every entry, one per exponent sum, ascending.
            let mut units: Vec<(u8, &'static str)> = self
                .variables
                .iter()
                .filter_map(|w| match matrix_entry(w.quantity) {
                    Some((m, i, j)) if m == name => Some((
                        self.dofs[i].length_exponent + self.dofs[j].length_exponent,
                        w.unit,
                    )),
                    _ => None,
                })
                .collect();
            units.sort_unstable();
            units.dedup();
            let what = match name {
                "added_mass_inf" => "Added mass at infinite frequency",
                "damping_direct" => {
                    "Direct damping (d force_i / d velocity_j = -damping_direct[i,j])"
                }
                _ => "Hydrostatic restoring (add it to the hull's stiffness matrix)",
            };
            let dofs: Vec<&str> = self.dofs.iter().map(|d| d.name.as_str()).collect();
            let mut description = format!(
                "{what}, {n} x {n}, rows and columns in the DOF order {}, row-major",
                dofs.join(" "),
                n = dofs.len()
            );
            let unit = if units.len() == 1 {
                Some(units[0].1)
            } else {
                let by_sum: Vec<String> = units
                    .iter()
                    .map(|(sum, unit)| format!("{unit} where e_i + e_j = {sum}"))
                    .collect();
                description += &format!(
                    "; SI units by entry, e the DOFs' length exponents (0 for a length, 1 for an angle or a mode amplitude): {}",
                    by_sum.join(", ")
                );
                None
            };
            arrays.push(ArrayVariable {
                name,
                value_reference: v.value_reference,
                unit,
                description,
            });
        }
        arrays
    }

    /// The FMI 3.0 modelDescription.xml: the unit definitions, log categories and default
    /// experiment of the fixed text (FMI 3.0 declares them as FMI 2.0 does), then `time`,
    /// the fixed parameters, the per-hull variables (matrices as arrays) and the
    /// `<ModelStructure>` with the same dependencies as the FMI 2.0 description.
    pub fn model_description_fmi3(
        &self,
        fixed_xml: &str,
        info: &DescriptionInfo,
    ) -> Result<String, VariablesError> {
        info.check()?;
        let err = |e: &dyn fmt::Display| VariablesError::Xml(e.to_string());
        let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
        w.write_event(Event::Decl(quick_xml::events::BytesDecl::new(
            "1.0",
            Some("UTF-8"),
            None,
        )))
        .map_err(|e| err(&e))?;
        let mut root = BytesStart::new("fmiModelDescription");
        let mut copied = Vec::new();
        // The fixed text's root attributes (model name, description, ...), then the rest.
        let mut reader = Reader::from_str(fixed_xml);
        let mut depth_copy = 0usize;
        loop {
            let event = reader.read_event().map_err(|e| err(&e))?;
            match &event {
                Event::Eof => break,
                Event::Start(e) if e.name().as_ref() == b"fmiModelDescription" => {
                    for a in e.attributes() {
                        let a = a.map_err(|e| err(&e))?;
                        let key = std::str::from_utf8(a.key.as_ref()).map_err(|e| err(&e))?;
                        let value = a.unescape_value().map_err(|e| err(&e))?.into_owned();
                        let value = match key {
                            "fmiVersion" => "3.0".to_string(),
                            "modelName" => info.model_name.clone().unwrap_or(value),
                            "description" => info.description.clone().unwrap_or(value),
                            _ => value,
                        };
                        root.push_attribute((key, value.as_str()));
                    }
                    root.push_attribute(("instantiationToken", info.guid.as_str()));
                }
                Event::Start(e)
                    if depth_copy == 0
                        && matches!(e.name().as_ref(), b"UnitDefinitions" | b"LogCategories") =>
                {
                    depth_copy = 1;
                    copied.push(event.into_owned());
                }
                Event::Empty(e) if depth_copy == 0 && e.name().as_ref() == b"DefaultExperiment" => {
                    copied.push(event.into_owned());
                }
                Event::Start(_) if depth_copy > 0 => {
                    depth_copy += 1;
                    copied.push(event.into_owned());
                }
                Event::End(e) if depth_copy > 0 => {
                    depth_copy -= 1;
                    if depth_copy == 0 && e.name().as_ref() == b"UnitDefinitions" {
                        copied.extend(self.extra_unit_events());
                    }
                    copied.push(event.into_owned());
                }
                Event::Empty(e) if depth_copy > 0 && e.name().as_ref() == b"Category" => {
                    let mut category = BytesStart::new("Category");
                    for a in e.attributes() {
                        let a = a.map_err(|e| err(&e))?;
                        let key = std::str::from_utf8(a.key.as_ref()).map_err(|e| err(&e))?;
                        let value = a.unescape_value().map_err(|e| err(&e))?;
                        let value = match key {
                            "description" => fmi3_function_names(&value),
                            _ => value.into_owned(),
                        };
                        category.push_attribute((key, value.as_str()));
                    }
                    copied.push(Event::Empty(category));
                }
                Event::Empty(_) if depth_copy > 0 => copied.push(event.into_owned()),
                _ => {}
            }
        }
        w.write_event(Event::Start(root)).map_err(|e| err(&e))?;
        w.write_event(Event::Comment(BytesText::new(
            " Written by hydrofmu fmu-pack from modelDescription/fixed.xml and the hull DOFs ",
        )))
        .map_err(|e| err(&e))?;
        let mut cs = BytesStart::new("CoSimulation");
        for (key, value) in [
            ("modelIdentifier", info.model_identifier.as_str()),
            ("canHandleVariableCommunicationStepSize", "true"),
            ("canGetAndSetFMUState", "true"),
            ("canSerializeFMUState", "true"),
            ("providesDirectionalDerivatives", "true"),
            ("canBeInstantiatedOnlyOncePerProcess", "false"),
            ("maxOutputDerivativeOrder", "1"),
            ("hasEventMode", "false"),
        ] {
            cs.push_attribute((key, value));
        }
        w.write_event(Event::Empty(cs)).map_err(|e| err(&e))?;
        for event in copied {
            w.write_event(event).map_err(|e| err(&e))?;
        }
        self.write_variables_fmi3(&mut w).map_err(|e| err(&e))?;
        self.write_structure_fmi3(&mut w, info)
            .map_err(|e| err(&e))?;
        w.write_event(Event::End(BytesEnd::new("fmiModelDescription")))
            .map_err(|e| err(&e))?;
        let mut text = String::from_utf8(w.into_inner()).map_err(|e| err(&e))?;
        text.push('\n');
        Ok(text)
    }

    fn write_variables_fmi3(&self, w: &mut Writer<Vec<u8>>) -> Result<(), quick_xml::Error> {
        w.write_event(Event::Start(BytesStart::new("ModelVariables")))?;
        let mut time = BytesStart::new("Float64");
        let vr = VR_TIME.to_string();
        for (k, v) in [
            ("name", "time"),
            ("valueReference", vr.as_str()),
            ("causality", "independent"),
            ("variability", "continuous"),
            ("unit", "s"),
            ("description", "Simulation time"),
        ] {
            time.push_attribute((k, v));
        }
        w.write_event(Event::Empty(time))?;
        for p in PARAMETERS {
            let mut e = BytesStart::new(if p.integer { "Int32" } else { "Float64" });
            let vr = p.value_reference.to_string();
            let number = |x: f64| {
                if p.integer {
                    format!("{}", x as i64)
                } else {
                    format!("{x:?}")
                }
            };
            let (start, min, max) = (number(p.start), number(p.min), number(p.max));
            e.push_attribute(("name", p.name));
            e.push_attribute(("valueReference", vr.as_str()));
            e.push_attribute(("causality", "parameter"));
            e.push_attribute(("variability", "fixed"));
            e.push_attribute(("initial", "exact"));
            e.push_attribute(("description", p.description));
            if !p.integer {
                e.push_attribute(("unit", p.unit));
            }
            e.push_attribute(("start", start.as_str()));
            if p.min.is_finite() {
                e.push_attribute(("min", min.as_str()));
            }
            if p.max.is_finite() {
                e.push_attribute(("max", max.as_str()));
            }
            w.write_event(Event::Empty(e))?;
        }
        let arrays = self.fmi3_arrays();
        let n = self.dof_count().to_string();
        for v in &self.variables {
            if v.quantity == Quantity::Wave(WaveParameter::Drift) {
                // wave.drift, the one per-hull Integer.
                let mut e = BytesStart::new("Int32");
                let vr = v.value_reference.to_string();
                let start = format!("{}", v.start.unwrap_or(0.0) as i32);
                let (min, max) = (DRIFT_CODES.0.to_string(), DRIFT_CODES.1.to_string());
                for (key, value) in [
                    ("name", v.name.as_str()),
                    ("valueReference", vr.as_str()),
                    ("causality", "parameter"),
                    ("variability", "fixed"),
                    ("initial", "exact"),
                    ("description", v.description.as_str()),
                    ("start", start.as_str()),
                    ("min", min.as_str()),
                    ("max", max.as_str()),
                ] {
                    e.push_attribute((key, value));
                }
                w.write_event(Event::Empty(e))?;
                continue;
            }
            if matches!(v.quantity, Quantity::Rho | Quantity::G | Quantity::Wave(_)) {
                continue;
            }
            if let Some(entry) = matrix_entry(v.quantity) {
                let Some(a) = arrays.iter().find(|a| (a.name, 0, 0) == entry) else {
                    continue;
                };
                let mut e = BytesStart::new("Float64");
                let vr = a.value_reference.to_string();
                e.push_attribute(("name", a.name));
                e.push_attribute(("valueReference", vr.as_str()));
                e.push_attribute(("causality", "calculatedParameter"));
                e.push_attribute(("variability", "fixed"));
                e.push_attribute(("initial", "calculated"));
                e.push_attribute(("description", a.description.as_str()));
                if let Some(unit) = a.unit {
                    e.push_attribute(("unit", unit));
                }
                w.write_event(Event::Start(e))?;
                for _ in 0..2 {
                    let mut d = BytesStart::new("Dimension");
                    d.push_attribute(("start", n.as_str()));
                    w.write_event(Event::Empty(d))?;
                }
                w.write_event(Event::End(BytesEnd::new("Float64")))?;
                continue;
            }
            let mut e = BytesStart::new("Float64");
            let vr = v.value_reference.to_string();
            e.push_attribute(("name", v.name.as_str()));
            e.push_attribute(("valueReference", vr.as_str()));
            e.push_attribute(("causality", v.causality.as_str()));
            e.push_attribute(("variability", v.variability()));
            if v.causality == Causality::CalculatedParameter {
                e.push_attribute(("initial", "calculated"));
            }
            e.push_attribute(("description", v.description.as_str()));
            e.push_attribute(("unit", v.unit));
            let start = v.start.map(|s| format!("{s:?}"));
            if let Some(s) = &start {
                e.push_attribute(("start", s.as_str()));
            }
            w.write_event(Event::Empty(e))?;
        }
        w.write_event(Event::End(BytesEnd::new("ModelVariables")))?;
        Ok(())
    }

    fn write_structure_fmi3(
        &self,
        w: &mut Writer<Vec<u8>>,
        info: &DescriptionInfo,
    ) -> Result<(), quick_xml::Error> {
        // Indices (1-based, FMI 2.0) to value references.
        let vr_of = |index: usize| self.variables[index - 1].value_reference.to_string();
        w.write_event(Event::Start(BytesStart::new("ModelStructure")))?;
        let outputs = self.output_dependencies(info);
        for (index, deps, kind) in &outputs {
            let mut u = BytesStart::new("Output");
            let vr = vr_of(*index);
            u.push_attribute(("valueReference", vr.as_str()));
            let deps_text = deps.iter().map(|d| vr_of(*d)).collect::<Vec<_>>().join(" ");
            let kinds = vec![*kind; deps.len()].join(" ");
            u.push_attribute(("dependencies", deps_text.as_str()));
            if !deps.is_empty() {
                u.push_attribute(("dependenciesKind", kinds.as_str()));
            }
            w.write_event(Event::Empty(u))?;
        }
        // Outputs and the calculated parameters (the arrays), declaration order.
        let arrays = self.fmi3_arrays();
        for v in &self.variables {
            let vr = if v.causality == Causality::Output {
                v.value_reference
            } else if let Some(a) = arrays
                .iter()
                .find(|a| a.value_reference == v.value_reference)
            {
                a.value_reference
            } else {
                continue;
            };
            let mut u = BytesStart::new("InitialUnknown");
            let vr = vr.to_string();
            u.push_attribute(("valueReference", vr.as_str()));
            w.write_event(Event::Empty(u))?;
        }
        w.write_event(Event::End(BytesEnd::new("ModelStructure")))?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmu::description::FIXED_XML;
    use crate::fmu::units::DofUnit;

    fn layout(names: &[&str], keep: bool) -> Layout {
        let dofs = names.iter().map(|n| DofUnit::builtin(n).unwrap()).collect();
        Layout::new(dofs, keep).unwrap()
    }

    #[test]
    fn an_array_is_its_first_entry_and_spans_the_fmi2_entries_row_major() {
        let l = layout(&["sway", "heave", "roll"], true);
        let a = l.value_reference(Quantity::AddedMassInf(0, 0)).unwrap();
        let Some(Fmi3Reference::Array { first, count }) = l.fmi3_reference(a) else {
            panic!("added_mass_inf is not an array");
        };
        assert_eq!((first, count), (a, 9));
        for i in 0..3 {
            for j in 0..3 {
                let q = l.quantity(first + (3 * i + j) as u32);
                assert_eq!(q, Some(Quantity::AddedMassInf(i, j)));
            }
        }
        assert_eq!(l.fmi3_reference(VR_TIME), Some(Fmi3Reference::Time));
        // An inner entry is not an FMI 3.0 variable; scalars stay.
        let inner = l.value_reference(Quantity::AddedMassInf(1, 2)).unwrap();
        assert_eq!(l.fmi3_reference(inner), None);
        let v = l.value_reference(Quantity::Velocity(2)).unwrap();
        assert_eq!(l.fmi3_reference(v), Some(Fmi3Reference::Scalar(v)));
        assert_eq!(l.fmi3_reference(98), None);
    }

    #[test]
    fn one_unit_only_where_the_dofs_share_a_length_exponent() {
        let mixed = layout(&["sway", "roll"], false).fmi3_arrays();
        assert_eq!(mixed.len(), 3);
        assert!(mixed.iter().all(|a| a.unit.is_none()));
        // Sway a length (e = 0), roll an angle (e = 1), per unit length.
        let expected = "kg/m where e_i + e_j = 0, kg where e_i + e_j = 1, kg.m where e_i + e_j = 2";
        assert!(
            mixed[0].description.ends_with(expected),
            "{}",
            mixed[0].description
        );
        let same = layout(&["sway", "heave"], false).fmi3_arrays();
        let units: Vec<_> = same.iter().map(|a| a.unit).collect();
        assert_eq!(units, [Some("kg/m"), Some("N.s/m2"), Some("N/m2")]);
    }

    #[test]
    fn description_declares_each_variable_once_with_its_structure() {
        let l = layout(&["sway", "heave", "roll"], true);
        let info = DescriptionInfo {
            model_identifier: "Test3".into(),
            guid: "{token}".into(),
            ..Default::default()
        };
        let xml = l.model_description_fmi3(FIXED_XML, &info).unwrap();
        assert!(xml.contains("fmiVersion=\"3.0\""));
        assert!(xml.contains("instantiationToken=\"{token}\""));
        assert!(xml.contains("modelIdentifier=\"Test3\""));
        let mut reader = Reader::from_str(&xml);
        let (mut names, mut vrs, mut outputs, mut initial) = (vec![], vec![], 0, 0);
        let mut dimensions = 0;
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
                        b"Float64" | b"Int32" => {
                            names.push(get("name").unwrap());
                            vrs.push(get("valueReference").unwrap());
                        }
                        b"Dimension" => dimensions += 1,
                        b"Output" => outputs += 1,
                        b"InitialUnknown" => initial += 1,
                        _ => {}
                    }
                }
                _ => {}
            }
        }
        let n = 3;
        // time, 10 fixed, velocity, force, power, energy, 3 arrays, acceleration,
        // force_radiation, force_excitation, wave.elevation.
        assert_eq!(
            names.len(),
            1 + PARAMETERS.len() + 2 * n + 2 + 3 + n + 2 * n + 1
        );
        let mut unique = vrs.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), vrs.len());
        assert_eq!(dimensions, 6);
        assert_eq!(outputs, 3 * n + 3);
        assert_eq!(initial, outputs + 3);
        assert!(names.contains(&"added_mass_inf".to_string()));
        assert!(!names.iter().any(|n| n.contains('[')));
    }
}
