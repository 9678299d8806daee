//! The OSP model description (OSP Interface Specification, `OspModelDescription.xml`) of a
//! packed FMU: the units of its force and velocity variables and the variable groups by which
//! libcosim connects it to other models (`VariableGroupConnection` in `OspSystemStructure.xml`).
//!
//! libcosim reads `<modelName>_OspModelDescription.xml` (the modelName of the FMU's
//! `modelDescription.xml`, not the file name) from the folder of the `.fmu` file, else from the
//! folder of `OspSystemStructure.xml`; it never looks inside the archive. [`crate::fmu::Archive`]
//! therefore writes the file beside the archive, and ships a copy in the archive under
//! [`ARCHIVE_DIR`] so that it travels with the FMU.
//!
//! Groups, by DOF (d in the hull's order):
//!
//! | group | kind | members |
//! | --- | --- | --- |
//! | `translation` | LinearMechanicalPort | Force `translation.force` = `force.d`, LinearVelocity `translation.velocity` = `velocity.d` for d in surge, sway, heave |
//! | `rotation` | AngularMechanicalPort | Torque `rotation.torque`, AngularVelocity `rotation.velocity` for d in roll, pitch, yaw |
//! | `mode_d` | one port per other DOF | LinearMechanicalPort (a length coordinate), AngularMechanicalPort (an angle), else Generic [`force.d`, `velocity.d`] |
//! | `force`, `force_radiation`, `force_excitation` | Generic | the outputs of every DOF |
//! | `velocity` (`acceleration`) | Generic | the inputs of every DOF |
//!
//! libcosim connects two groups member by member in order, each pair from its output to its
//! input, so a partner's port lists its force inputs and velocity outputs in the same DOF order.
//! In the file the groups stand in the order the OSP-IS 1.0 schema requires: the `Generic`
//! groups first, then the linear ports, then the angular ones.

use crate::fmu::{Layout, Quantity};
use crate::xml::escape;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// XML namespace of OSP-IS 1.0 model descriptions (as in the OSP demo cases).
pub const NAMESPACE: &str = "https://open-simulation-platform.com/OspModelDescription/1.0.0";

/// Folder of the copy inside the archive.
pub const ARCHIVE_DIR: &str = "extra/com.open-simulation-platform";

/// Exponents of kg, m, s and rad of the units the groups reference.
const UNITS: [(&str, [i8; 4]); 9] = [
    ("m/s", [0, 1, -1, 0]),
    ("rad/s", [0, 0, -1, 1]),
    ("1/s", [0, 0, -1, 0]),
    ("m/s2", [0, 1, -2, 0]),
    ("rad/s2", [0, 0, -2, 1]),
    ("1/s2", [0, 0, -2, 0]),
    ("N/m", [1, 0, -2, 0]),
    ("N", [1, 1, -2, 0]),
    ("N.m", [1, 2, -2, 0]),
];

/// A variable group: a kind (the XML element), a name, member variables and nested groups.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    /// Element name: `LinearMechanicalPort`, `Force`, `Generic`, ...
    pub kind: &'static str,
    /// Group name, unique in the file.
    pub name: String,
    /// Variables (name, unit) in connection order.
    pub variables: Vec<(String, &'static str)>,
    /// Nested groups, in connection order.
    pub groups: Vec<Group>,
}

impl Group {
    fn leaf(kind: &'static str, name: String, variables: Vec<(String, &'static str)>) -> Group {
        Group {
            kind,
            name,
            variables,
            groups: Vec::new(),
        }
    }

    fn port(kind: &'static str, name: &str, effort: Group, flow: Group) -> Group {
        Group {
            kind,
            name: name.to_string(),
            variables: Vec::new(),
            groups: vec![effort, flow],
        }
    }
}

/// The variable groups of a layout.
pub fn groups(layout: &Layout) -> Vec<Group> {
    let dofs = layout.dofs();
    let by_quantity: HashMap<Quantity, (String, &'static str)> = layout
        .variables()
        .iter()
        .map(|v| (v.quantity, (v.name.clone(), v.unit)))
        .collect();
    let member = |q: Quantity| by_quantity.get(&q).cloned();
    let pick = |filter: &dyn Fn(usize) -> bool, of: fn(usize) -> Quantity| {
        (0..dofs.len())
            .filter(|&i| filter(i))
            .filter_map(|i| member(of(i)))
            .collect::<Vec<_>>()
    };
    let translational = |i: usize| {
        matches!(dofs[i].name.as_str(), "surge" | "sway" | "heave") && dofs[i].length_exponent == 0
    };
    let rotational = |i: usize| {
        matches!(dofs[i].name.as_str(), "roll" | "pitch" | "yaw")
            && dofs[i].length_exponent == 1
            && dofs[i].is_angle
    };
    let mut out = Vec::new();
    let forces = pick(&translational, Quantity::Force);
    if !forces.is_empty() {
        out.push(Group::port(
            "LinearMechanicalPort",
            "translation",
            Group::leaf("Force", "translation.force".into(), forces),
            Group::leaf(
                "LinearVelocity",
                "translation.velocity".into(),
                pick(&translational, Quantity::Velocity),
            ),
        ));
    }
    let torques = pick(&rotational, Quantity::Force);
    if !torques.is_empty() {
        out.push(Group::port(
            "AngularMechanicalPort",
            "rotation",
            Group::leaf("Torque", "rotation.torque".into(), torques),
            Group::leaf(
                "AngularVelocity",
                "rotation.velocity".into(),
                pick(&rotational, Quantity::Velocity),
            ),
        ));
    }
    for (i, d) in dofs.iter().enumerate() {
        if translational(i) || rotational(i) {
            continue;
        }
        let name = format!("mode_{}", d.name);
        let (Some(force), Some(velocity)) =
            (member(Quantity::Force(i)), member(Quantity::Velocity(i)))
        else {
            continue;
        };
        let (port, effort, flow) = match (d.length_exponent, d.is_angle) {
            (0, _) => ("LinearMechanicalPort", "Force", "LinearVelocity"),
            (_, true) => ("AngularMechanicalPort", "Torque", "AngularVelocity"),
            _ => {
                out.push(Group::leaf("Generic", name, vec![force, velocity]));
                continue;
            }
        };
        out.push(Group::port(
            port,
            &name,
            Group::leaf(effort, format!("{name}.force"), vec![force]),
            Group::leaf(flow, format!("{name}.velocity"), vec![velocity]),
        ));
    }
    let all = |of: fn(usize) -> Quantity| pick(&|_| true, of);
    for (name, of) in [
        ("force", Quantity::Force as fn(usize) -> Quantity),
        ("force_radiation", Quantity::ForceRadiation),
        ("force_excitation", Quantity::ForceExcitation),
        ("velocity", Quantity::Velocity),
        ("acceleration", Quantity::Acceleration),
    ] {
        let variables = all(of);
        if !variables.is_empty() {
            out.push(Group::leaf("Generic", name.into(), variables));
        }
    }
    // The schema's sequence fixes the order of the kinds; the order within a kind stays.
    out.sort_by_key(|g| schema_rank(g.kind));
    out
}

/// The group kinds used here, in the order of the OSP-IS 1.0 schema's `VariableGroupsType`
/// sequence (`OspModelDescription-1.0.0.xsd`): all `Generic` groups first, ports last.
const SCHEMA_ORDER: [&str; 7] = [
    "Generic",
    "Force",
    "Torque",
    "LinearVelocity",
    "AngularVelocity",
    "LinearMechanicalPort",
    "AngularMechanicalPort",
];

/// Position of a group kind in [`SCHEMA_ORDER`] (an unknown kind last).
fn schema_rank(kind: &str) -> usize {
    SCHEMA_ORDER
        .iter()
        .position(|k| *k == kind)
        .unwrap_or(SCHEMA_ORDER.len())
}

fn write_group(out: &mut String, group: &Group, depth: usize) {
    let pad = "  ".repeat(depth);
    let _ = writeln!(
        out,
        "{pad}<{} name=\"{}\">",
        group.kind,
        escape(&group.name)
    );
    for (name, unit) in &group.variables {
        if UNITS.iter().any(|(u, _)| u == unit) {
            let _ = writeln!(
                out,
                "{pad}  <Variable ref=\"{}\" unit=\"{}\"/>",
                escape(name),
                escape(unit)
            );
        } else {
            let _ = writeln!(out, "{pad}  <Variable ref=\"{}\"/>", escape(name));
        }
    }
    for nested in &group.groups {
        write_group(out, nested, depth + 1);
    }
    let _ = writeln!(out, "{pad}</{}>", group.kind);
}

fn used_units(groups: &[Group], into: &mut Vec<&'static str>) {
    for g in groups {
        for (_, unit) in &g.variables {
            if !into.contains(unit) {
                into.push(unit);
            }
        }
        used_units(&g.groups, into);
    }
}

/// The OSP model description of a layout.
pub fn model_description(layout: &Layout) -> String {
    let groups = groups(layout);
    let mut units = Vec::new();
    used_units(&groups, &mut units);
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        out,
        "<OspModelDescription xmlns=\"{NAMESPACE}\" version=\"1.0\">"
    );
    out.push_str("  <UnitDefinitions>\n");
    for (name, [kg, m, s, rad]) in UNITS.iter().filter(|(u, _)| units.contains(u)) {
        let _ = writeln!(
            out,
            "    <Unit name=\"{}\">\n      <BaseUnit kg=\"{kg}\" m=\"{m}\" s=\"{s}\" A=\"0\" K=\"0\" \
             mol=\"0\" cd=\"0\" rad=\"{rad}\" factor=\"1.0\" offset=\"0.0\"/>\n    </Unit>",
            escape(name)
        );
    }
    out.push_str("  </UnitDefinitions>\n  <VariableGroups>\n");
    for g in &groups {
        write_group(&mut out, g, 2);
    }
    out.push_str("  </VariableGroups>\n</OspModelDescription>\n");
    out
}

/// `<modelName>_OspModelDescription.xml`, the name libcosim looks for; `None` for a model
/// name that cannot be a file name or an archive entry (a separator, `..`, a control).
pub fn file_name(model_name: &str) -> Option<String> {
    let bad = model_name.is_empty()
        || model_name == "."
        || model_name.contains("..")
        || model_name
            .chars()
            .any(|c| c == '/' || c == '\\' || c.is_control());
    (!bad).then(|| format!("{model_name}_OspModelDescription.xml"))
}

/// Where the description goes beside an archive written to `archive`: the archive's folder,
/// under [`file_name`]; `None` when the archive goes to standard output (`-`) or to an existing
/// target that is not a regular file (a device), or when the model name cannot name a file.
pub fn path_beside(archive: &Path, model_name: &str) -> Option<PathBuf> {
    if archive.as_os_str() == "-" || std::fs::metadata(archive).is_ok_and(|m| !m.is_file()) {
        return None;
    }
    let name = file_name(model_name)?;
    let dir = archive
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    Some(dir.join(name))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmu::{Causality, DofUnit, Extent};
    use crate::xml::{parse, Element};

    fn ship(keep: bool) -> Layout {
        let dofs = ["surge", "sway", "heave", "roll", "pitch", "yaw"]
            .iter()
            .map(|n| {
                let angle = matches!(*n, "roll" | "pitch" | "yaw");
                DofUnit::new(n, u8::from(angle), angle)
            })
            .chain([
                DofUnit::new("bend", 1, false),
                DofUnit::new("cb1", 0, false),
            ])
            .collect();
        Layout::with_extent(dofs, keep, Extent::WholeBody).unwrap()
    }

    fn section() -> Layout {
        let dofs = ["sway", "heave", "roll", "cb3"]
            .iter()
            .map(|n| DofUnit::builtin(n).unwrap())
            .collect();
        Layout::new(dofs, false).unwrap()
    }

    /// DOF names like the group names, and many modes.
    fn odd() -> Layout {
        let mut dofs: Vec<DofUnit> = ["force", "velocity", "translation", "mode_x", "x", "yaw"]
            .iter()
            .map(|n| DofUnit::new(n, 0, false))
            .collect();
        dofs.extend((0..200).map(|i| DofUnit::new(&format!("m{i}"), 1, i % 2 == 0)));
        Layout::new(dofs, true).unwrap()
    }

    fn find<'a>(root: &'a Element, kind: &str, name: &str) -> &'a Element {
        root.descendants()
            .find(|e| e.name == kind && e.attribute("name") == Some(name))
            .unwrap_or_else(|| panic!("no {kind} {name}"))
    }

    fn refs(group: &Element) -> Vec<String> {
        group
            .children
            .iter()
            .filter(|e| e.name == "Variable")
            .map(|e| e.attribute("ref").unwrap().to_string())
            .collect()
    }

    #[test]
    fn every_reference_exists_with_its_causality_and_a_declared_unit() {
        for layout in [ship(false), ship(true), section(), odd()] {
            let text = model_description(&layout);
            let root = parse(&text).unwrap();
            assert_eq!(root.name, "OspModelDescription");
            assert_eq!(root.attribute("xmlns"), Some(NAMESPACE));
            let declared: Vec<&str> = root
                .descendants()
                .filter(|e| e.name == "Unit")
                .map(|e| e.attribute("name").unwrap())
                .collect();
            let mut names = std::collections::BTreeSet::new();
            for e in root.descendants() {
                if let Some(name) = e.attribute("name").filter(|_| e.name != "Unit") {
                    assert!(names.insert(name.to_string()), "group {name} twice");
                }
                if e.name != "Variable" {
                    continue;
                }
                let name = e.attribute("ref").unwrap();
                let v = layout.variables().iter().find(|v| v.name == name).unwrap();
                assert_eq!(e.attribute("unit"), Some(v.unit), "{name}");
                assert!(declared.contains(&v.unit), "{}", v.unit);
                let expected = if name.starts_with("velocity.") || name.starts_with("acceleration.")
                {
                    Causality::Input
                } else {
                    Causality::Output
                };
                assert_eq!(v.causality, expected, "{name}");
            }
            for unit in root.descendants().filter(|e| e.name == "BaseUnit") {
                for key in [
                    "kg", "m", "s", "A", "K", "mol", "cd", "rad", "factor", "offset",
                ] {
                    assert!(unit.attribute(key).is_some(), "{key}");
                }
            }
        }
    }

    #[test]
    fn rigid_dofs_form_ports_and_other_dofs_their_own() {
        let root = parse(&model_description(&ship(true))).unwrap();
        let t = find(&root, "LinearMechanicalPort", "translation");
        let kinds: Vec<&str> = t.children.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(kinds, ["Force", "LinearVelocity"]);
        assert_eq!(
            refs(find(&root, "Force", "translation.force")),
            ["force.surge", "force.sway", "force.heave"]
        );
        assert_eq!(
            refs(find(&root, "AngularVelocity", "rotation.velocity")),
            ["velocity.roll", "velocity.pitch", "velocity.yaw"]
        );
        assert_eq!(
            refs(find(&root, "Generic", "mode_bend")),
            ["force.bend", "velocity.bend"]
        );
        assert_eq!(refs(find(&root, "Force", "mode_cb1.force")), ["force.cb1"]);
        assert_eq!(refs(find(&root, "Generic", "acceleration")).len(), 8);
        assert_eq!(refs(find(&root, "Generic", "force_excitation")).len(), 8);
        // Section roll is an angle (a torque per unit length, in N).
        let root = parse(&model_description(&section())).unwrap();
        let torque = find(&root, "Torque", "rotation.torque");
        assert_eq!(refs(torque), ["force.roll"]);
        assert_eq!(torque.children[0].attribute("unit"), Some("N"));
        assert_eq!(
            refs(find(&root, "AngularVelocity", "mode_cb3.velocity")),
            ["velocity.cb3"]
        );
        assert!(!model_description(&ship(false)).contains("acceleration"));
        // A yaw that is a length is no rotation: its own linear port.
        let root = parse(&model_description(&odd())).unwrap();
        assert_eq!(refs(find(&root, "Force", "mode_yaw.force")), ["force.yaw"]);
        assert!(!root
            .descendants()
            .any(|e| e.attribute("name") == Some("translation")));
        assert_eq!(
            refs(find(&root, "Generic", "mode_m1")),
            ["force.m1", "velocity.m1"]
        );
    }

    /// The OSP-IS 1.0 schema (tests/data/osp/README.md names its source).
    const SCHEMA: &str = include_str!("../../tests/data/osp/OspModelDescription-1.0.0.xsd");

    /// The `xs:sequence` of the schema's complex type `name`: (element, type without prefix,
    /// minOccurs, maxOccurs) in order; `None` for a type the schema does not define or gives no
    /// sequence.
    fn sequence(schema: &Element, name: &str) -> Option<Vec<(String, String, usize, usize)>> {
        let complex = schema
            .children
            .iter()
            .find(|e| e.name == "xs:complexType" && e.attribute("name") == Some(name))?;
        // No sequence of its own (attributes only, or an extension of fmi2Unit.xsd's
        // `fmi2Unit`): its content is left to the full validation (tests/python).
        let sequence = complex.descendants().find(|e| e.name == "xs:sequence")?;
        let occurs = |e: &Element, key: &str| match e.attribute(key) {
            Some("unbounded") => usize::MAX,
            Some(n) => n.parse().unwrap(),
            None => 1,
        };
        // A repeated sequence (UnitDefinitions) repeats its elements.
        let repeated = occurs(sequence, "maxOccurs") > 1;
        Some(
            sequence
                .children
                .iter()
                .filter(|e| e.name == "xs:element")
                .map(|e| {
                    let kind = e.attribute("type").unwrap_or("");
                    let kind = kind.strip_prefix("osp:").unwrap_or(kind).to_string();
                    let max = if repeated {
                        usize::MAX
                    } else {
                        occurs(e, "maxOccurs")
                    };
                    let min = if repeated { 0 } else { occurs(e, "minOccurs") };
                    (e.attribute("name").unwrap().to_string(), kind, min, max)
                })
                .collect(),
        )
    }

    /// The schema's rules of content that an element of type `kind` breaks: children not
    /// in its sequence, out of its order, or more or fewer than it allows; recursively.
    fn violations(schema: &Element, element: &Element, kind: &str, into: &mut Vec<String>) {
        let Some(sequence) = sequence(schema, kind) else {
            return;
        };
        let mut last = 0;
        for child in &element.children {
            let Some(at) = sequence.iter().position(|(n, ..)| *n == child.name) else {
                into.push(format!("{} in {} ({kind})", child.name, element.name));
                continue;
            };
            if at < last {
                into.push(format!(
                    "{} after {} in {} ({kind}): out of the schema's order",
                    child.name, sequence[last].0, element.name
                ));
            }
            last = last.max(at);
            violations(schema, child, &sequence[at].1, into);
        }
        for (name, _, min, max) in &sequence {
            let count = element.children.iter().filter(|c| c.name == *name).count();
            if count < *min || count > *max {
                into.push(format!(
                    "{count} {name} in {} ({kind}): {min}..={max} allowed",
                    element.name
                ));
            }
        }
    }

    #[test]
    fn descriptions_follow_the_osp_schema_order() {
        let schema = parse(SCHEMA).unwrap();
        assert_eq!(
            schema.attribute("targetNamespace"),
            Some(NAMESPACE),
            "the schema of the namespace written"
        );
        let groups = sequence(&schema, "VariableGroupsType").unwrap();
        assert!(groups.len() > 40, "{}", groups.len());
        for kind in SCHEMA_ORDER {
            assert!(groups.iter().any(|g| g.0 == kind), "{kind}");
        }
        for layout in [ship(false), ship(true), section(), odd()] {
            let root = parse(&model_description(&layout)).unwrap();
            let mut found = Vec::new();
            violations(&schema, &root, "OspModelDescriptionType", &mut found);
            assert!(found.is_empty(), "{found:#?}");
        }
    }

    #[test]
    fn file_names_follow_the_model_name() {
        assert_eq!(
            file_name("hydrofmu Semicircle").as_deref(),
            Some("hydrofmu Semicircle_OspModelDescription.xml")
        );
        for bad in ["", "a/b", "..", "a..b", "a\\b", "a\nb"] {
            assert_eq!(file_name(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn the_description_goes_beside_a_file_and_not_beside_a_device() {
        for device in ["/dev/null", "-"] {
            assert_eq!(path_beside(Path::new(device), "m"), None, "{device}");
        }
        let dir = Path::new("some/folder");
        assert_eq!(path_beside(&dir.join("X.fmu"), "a/b"), None);
        assert_eq!(
            path_beside(&dir.join("X.fmu"), "hydrofmu X"),
            Some(dir.join("hydrofmu X_OspModelDescription.xml"))
        );
        assert_eq!(
            path_beside(Path::new("X.fmu"), "m"),
            Some(Path::new(".").join("m_OspModelDescription.xml"))
        );
    }
}
