//! The network XML file: writing and reading (on [`crate::xml`]).
//!
//! ```xml
//! <?xml version="1.0" encoding="UTF-8"?>
//! <network format_version="1" form="series_chain" rho="1025" g="9.81">
//!   <dof name="sway"/>
//!   <added_mass_inf>
//!     <row>230.5</row>
//!   </added_mass_inf>
//!   <branch>
//!     <direction>1</direction>
//!     <stage mass="512.3" stiffness="2100.7" damping="880.1"/>
//!     <stage mass="101.9" stiffness="4000.2" damping="120.4"/>
//!   </branch>
//! </network>
//! ```
//!
//! * `network`: attributes `format_version` (must be `1`), `form` (`series_chain`,
//!   `parallel_bank` or `coupled`), `rho` and `g` (the water density and gravity the values were
//!   made for; [`Network::scaled`] moves them). Children in this order: `dof` elements, one
//!   `added_mass_inf`, then zero or more `branch` elements.
//! * `dof name="..."`: one per hull DOF, in the order of the matrix rows.
//! * `added_mass_inf`: n `row` elements of n whitespace-separated numbers (symmetric PSD).
//! * `branch`: one `direction` (n numbers), then one or more `stage` elements with attributes
//!   `mass`, `stiffness`, `damping` (all finite and > 0), listed from the hull outwards.
//! * `substructure springs="Ns" masses="Nm"` (after the branches; [`Substructure`]):
//!   `spring_incidence` (Ns rows of Nm + n numbers), `spring_relaxation` (Ns rows of Ns) and
//!   `damping` (Nm + n rows of Nm + n), each as `row` elements.
//!
//! Units: SI per unit hull length; a DOF's generalized units carry into the matrices. Every
//! number is at most [`MAX_COEFFICIENT`] (1e100) in magnitude, and `rho`, `g` at least its
//! inverse (see there). Comments are allowed anywhere; anything else unknown (elements,
//! attributes, text) is an error that names the file and line. The full description is
//! `docs/NETWORK_FORMAT.md`.

use std::path::Path;

use nalgebra::{DMatrix, DVector};

use super::{
    Branch, Network, NetworkError, NetworkForm, Stage, Substructure, MAX_BRANCH_STAGES,
    MAX_NETWORK_DOFS, MAX_NETWORK_STATES, MAX_SUBSTRUCTURE_STATES, NETWORK_FORMAT_VERSION,
};
use crate::xml::{self, escape, Element, Notation, XmlError};

impl Network {
    /// The network as an XML file (format: `docs/NETWORK_FORMAT.md`). Numbers round-trip
    /// exactly.
    pub fn to_xml_string(&self) -> String {
        let mut out = String::new();
        out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        out.push_str(
            "<!-- Equivalent mass-spring-damper network (hydrofmu), SI units per unit hull \
             length; format: docs/NETWORK_FORMAT.md -->\n",
        );
        out.push_str(&format!(
            "<network format_version=\"{NETWORK_FORMAT_VERSION}\" form=\"{}\" rho=\"{}\" g=\"{}\">\n",
            self.form.name(),
            num(self.rho),
            num(self.g)
        ));
        for name in &self.dof_names {
            out.push_str(&format!("  <dof name=\"{}\"/>\n", escape(name)));
        }
        out.push_str("  <added_mass_inf>\n");
        for i in 0..self.added_mass_inf.nrows() {
            let row: Vec<String> = self.added_mass_inf.row(i).iter().map(|&x| num(x)).collect();
            out.push_str(&format!("    <row>{}</row>\n", row.join(" ")));
        }
        out.push_str("  </added_mass_inf>\n");
        for branch in &self.branches {
            out.push_str("  <branch>\n");
            let direction: Vec<String> = branch.direction.iter().map(|&x| num(x)).collect();
            out.push_str(&format!(
                "    <direction>{}</direction>\n",
                direction.join(" ")
            ));
            for stage in &branch.stages {
                out.push_str(&format!(
                    "    <stage mass=\"{}\" stiffness=\"{}\" damping=\"{}\"/>\n",
                    num(stage.mass),
                    num(stage.stiffness),
                    num(stage.damping)
                ));
            }
            out.push_str("  </branch>\n");
        }
        for sub in &self.substructures {
            out.push_str(&format!(
                "  <substructure springs=\"{}\" masses=\"{}\">\n",
                sub.spring_count(),
                sub.masses
            ));
            for (name, m) in [
                ("spring_incidence", &sub.spring_incidence),
                ("spring_relaxation", &sub.spring_relaxation),
                ("damping", &sub.damping),
            ] {
                out.push_str(&format!("    <{name}>\n"));
                for i in 0..m.nrows() {
                    let row: Vec<String> = m.row(i).iter().map(|&x| num(x)).collect();
                    out.push_str(&format!("      <row>{}</row>\n", row.join(" ")));
                }
                out.push_str(&format!("    </{name}>\n"));
            }
            out.push_str("  </substructure>\n");
        }
        out.push_str("</network>\n");
        out
    }

    /// Writes [`Network::to_xml_string`] to `path`.
    pub fn write_file(&self, path: impl AsRef<Path>) -> Result<(), NetworkError> {
        let path = path.as_ref();
        std::fs::write(path, self.to_xml_string()).map_err(|e| NetworkError::File {
            source: path.display().to_string(),
            line: None,
            message: format!("cannot write: {e}"),
        })
    }

    /// Reads a network file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Network, NetworkError> {
        let path = path.as_ref();
        let text = crate::input::read_bounded_text(
            path,
            crate::xml::MAX_INPUT_BYTES as u64,
            "MAX_INPUT_BYTES",
        )
        .map_err(|cause| NetworkError::File {
            source: path.display().to_string(),
            line: None,
            message: cause.to_string(),
        })?;
        Network::from_xml_str(&text, &path.display().to_string())
    }

    /// Parses and validates network XML; `source_name` names the text in error messages.
    pub fn from_xml_str(text: &str, source_name: &str) -> Result<Network, NetworkError> {
        let fail = |line: Option<usize>, message: String| NetworkError::File {
            source: source_name.to_string(),
            line,
            message,
        };
        let located = |e: XmlError| fail(Some(e.line), e.message);
        let root = xml::parse(text).map_err(located)?;
        let network = network_from_tree(&root).map_err(located)?;
        // Magnitudes first: the rules' eigenvalues then see no overflowing squares.
        check_magnitudes(&network).map_err(|m| fail(None, m))?;
        network.validate().map_err(|e| fail(None, e.to_string()))?;
        Ok(network)
    }
}

/// Largest magnitude of a number in a network file, and the inverse of the smallest `rho` and
/// `g`. Generous: the shipped networks (`examples/networks`) hold magnitudes from 3e-23 to
/// 2e17. It keeps the products the component forms from a few coefficients finite (the
/// realization `M^-1 K`, the eigenvalues of `A_inf`, the matrix exponential of a step, `C z`,
/// `z^T P z` at moderate states): a stiffness of 1e250 N/m^2 read as it was gave an infinite
/// energy after one step. Products with extreme rho, g and inputs can still overflow; the
/// component reports those as errors where they occur.
pub(crate) const MAX_COEFFICIENT: f64 = 1e100;

/// Refuses a network with a number beyond [`MAX_COEFFICIENT`] (or a reference `rho`, `g`
/// below its inverse), naming it.
fn check_magnitudes(network: &Network) -> Result<(), String> {
    let beyond = |x: f64| x.abs() > MAX_COEFFICIENT;
    let refuse = |what: String, x: f64| {
        Err(format!(
            "{what} = {x:e} exceeds {MAX_COEFFICIENT:e} in magnitude (the limit of network files)"
        ))
    };
    for (name, x) in [("rho", network.rho), ("g", network.g)] {
        if beyond(x) || x < 1.0 / MAX_COEFFICIENT {
            return Err(format!(
                "{name} = {x:e} is outside {:e} .. {MAX_COEFFICIENT:e} (the limit of network files)",
                1.0 / MAX_COEFFICIENT
            ));
        }
    }
    let matrix = |name: &str, m: &DMatrix<f64>| -> Result<(), String> {
        match m.iter().enumerate().find(|(_, x)| beyond(**x)) {
            Some((k, x)) => refuse(
                format!("{name}[{},{}]", k % m.nrows() + 1, k / m.nrows() + 1),
                *x,
            ),
            None => Ok(()),
        }
    };
    matrix("added_mass_inf", &network.added_mass_inf)?;
    for (ib, branch) in network.branches.iter().enumerate() {
        if let Some((j, x)) = branch
            .direction
            .iter()
            .enumerate()
            .find(|(_, x)| beyond(**x))
        {
            return refuse(format!("branch {}: direction[{}]", ib + 1, j + 1), *x);
        }
        for (is, stage) in branch.stages.iter().enumerate() {
            for (what, x) in [
                ("mass", stage.mass),
                ("stiffness", stage.stiffness),
                ("damping", stage.damping),
            ] {
                if beyond(x) {
                    return refuse(format!("branch {}, stage {}: {what}", ib + 1, is + 1), x);
                }
            }
        }
    }
    for (k, sub) in network.substructures.iter().enumerate() {
        for (name, m) in [
            ("spring_incidence", &sub.spring_incidence),
            ("spring_relaxation", &sub.spring_relaxation),
            ("damping", &sub.damping),
        ] {
            matrix(&format!("substructure {}: {name}", k + 1), m)?;
        }
    }
    Ok(())
}

/// Network files write numbers in [`Notation::Plain`].
fn num(x: f64) -> String {
    xml::format_number(x, Notation::Plain)
}

/// A `<row>` or `<direction>`: no attributes or children, `expected` numbers (one per DOF).
fn numbers(element: &Element, expected: usize) -> Result<Vec<f64>, XmlError> {
    element.no_children()?;
    element.only_attributes(&[])?;
    let values = element.text_numbers()?;
    if values.len() != expected {
        return Err(element.error(format!(
            "<{}> has {} numbers, expected {expected} (one per DOF)",
            element.name,
            values.len()
        )));
    }
    Ok(values)
}

/// A matrix element of `rows` `<row>` children with `cols` numbers each.
fn matrix(element: &Element, rows: usize, cols: usize) -> Result<DMatrix<f64>, XmlError> {
    element.only_attributes(&[])?;
    element.no_text()?;
    if let Some(other) = element.children.iter().find(|c| c.name != "row") {
        return Err(other.error(format!(
            "unexpected element <{}> in <{}>",
            other.name, element.name
        )));
    }
    if let Some(extra) = element.children.get(rows) {
        return Err(extra.error(format!("<{}> has more than {rows} rows", element.name)));
    }
    if element.children.len() != rows {
        return Err(element.error(format!(
            "<{}> has {} rows, expected {rows}",
            element.name,
            element.children.len()
        )));
    }
    let mut m = DMatrix::zeros(rows, cols);
    for (i, row) in element.children.iter().enumerate() {
        row.no_children()?;
        row.only_attributes(&[])?;
        let values = row.text_numbers()?;
        if values.len() != cols {
            return Err(row.error(format!(
                "a <row> of <{}> has {} numbers, expected {cols}",
                element.name,
                values.len()
            )));
        }
        for (j, v) in values.into_iter().enumerate() {
            m[(i, j)] = v;
        }
    }
    Ok(m)
}

/// A `<substructure>` on `n` DOFs.
fn substructure(element: &Element, n: usize) -> Result<Substructure, XmlError> {
    element.only_attributes(&["springs", "masses"])?;
    element.no_text()?;
    let count = |name: &str| -> Result<usize, XmlError> {
        let text = element.required(name)?;
        match text.trim().parse::<usize>() {
            Ok(k) if k <= MAX_SUBSTRUCTURE_STATES => Ok(k),
            _ => Err(element.error(format!(
                "{name}={text:?} in <substructure> is not a count from 0 to {MAX_SUBSTRUCTURE_STATES}"
            ))),
        }
    };
    let (ns, nm) = (count("springs")?, count("masses")?);
    if ns + nm > MAX_SUBSTRUCTURE_STATES {
        return Err(element.error(format!(
            "<substructure> has {} states (springs + masses), at most {MAX_SUBSTRUCTURE_STATES} are accepted",
            ns + nm
        )));
    }
    let names = ["spring_incidence", "spring_relaxation", "damping"];
    let shapes = [(ns, nm + n), (ns, ns), (nm + n, nm + n)];
    if element.children.len() != 3
        || element
            .children
            .iter()
            .zip(names)
            .any(|(c, name)| c.name != name)
    {
        return Err(element.error(
            "<substructure> holds <spring_incidence>, <spring_relaxation> and <damping>, in this order",
        ));
    }
    let mut parts = element
        .children
        .iter()
        .zip(shapes)
        .map(|(c, (rows, cols))| matrix(c, rows, cols));
    let spring_incidence = parts.next().expect("three parts")?;
    let spring_relaxation = parts.next().expect("three parts")?;
    let damping = parts.next().expect("three parts")?;
    Ok(Substructure {
        masses: nm,
        spring_incidence,
        spring_relaxation,
        damping,
    })
}

/// The refusal of a network whose states pass [`MAX_NETWORK_STATES`] at this element.
fn too_many_states(states: usize) -> String {
    format!(
        "the network has {states} states up to here, at most {MAX_NETWORK_STATES} are accepted \
         (MAX_NETWORK_STATES)"
    )
}

/// An element holding nothing but attributes.
fn leaf(element: &Element) -> Result<(), XmlError> {
    element.no_children()?;
    element.no_text()
}

fn network_from_tree(root: &Element) -> Result<Network, XmlError> {
    if root.name != "network" {
        return Err(root.error(format!(
            "root element is <{}>, expected <network>",
            root.name
        )));
    }
    root.only_attributes(&["format_version", "form", "rho", "g"])?;
    root.no_text()?;
    let version = root.required("format_version")?;
    if version.trim() != NETWORK_FORMAT_VERSION.to_string() {
        return Err(root.error(format!(
            "format_version {version:?} is not supported (this reader knows {NETWORK_FORMAT_VERSION})"
        )));
    }
    let form_name = root.required("form")?;
    let form = NetworkForm::from_name(form_name.trim()).ok_or_else(|| {
        root.error(format!(
            "unknown form {form_name:?} (series_chain, parallel_bank or coupled)"
        ))
    })?;
    let rho = root.required_number("rho")?;
    let g = root.required_number("g")?;

    let mut dof_names = Vec::new();
    let mut added_mass_inf: Option<DMatrix<f64>> = None;
    let mut branches = Vec::new();
    let mut substructures = Vec::new();
    let mut states = 0usize;
    // Order: dof*, added_mass_inf, branch*, substructure*.
    let mut phase = 0;
    for child in &root.children {
        match child.name.as_str() {
            "dof" => {
                if phase > 0 {
                    return Err(child.error("<dof> must come before <added_mass_inf>"));
                }
                child.only_attributes(&["name"])?;
                leaf(child)?;
                if dof_names.len() == MAX_NETWORK_DOFS {
                    return Err(child.error(format!(
                        "more than {MAX_NETWORK_DOFS} <dof> elements (MAX_NETWORK_DOFS)"
                    )));
                }
                dof_names.push(child.required("name")?.to_string());
            }
            "added_mass_inf" => {
                if phase > 0 {
                    return Err(child.error("more than one <added_mass_inf>"));
                }
                if dof_names.is_empty() {
                    return Err(child.error("<added_mass_inf> before any <dof>"));
                }
                phase = 1;
                let n = dof_names.len();
                let matrix = matrix(child, n, n)?;
                added_mass_inf = Some(matrix);
            }
            "substructure" => {
                if phase == 0 {
                    return Err(child.error("<substructure> before <added_mass_inf>"));
                }
                phase = 2;
                let sub = substructure(child, dof_names.len())?;
                states += sub.state_count();
                if states > MAX_NETWORK_STATES {
                    return Err(child.error(too_many_states(states)));
                }
                substructures.push(sub);
            }
            "branch" => {
                if phase == 0 {
                    return Err(child.error("<branch> before <added_mass_inf>"));
                }
                if phase == 2 {
                    return Err(child.error("<branch> after a <substructure>"));
                }
                child.only_attributes(&[])?;
                child.no_text()?;
                let n = dof_names.len();
                let mut direction = None;
                let mut stages = Vec::new();
                for part in &child.children {
                    match part.name.as_str() {
                        "direction" => {
                            if direction.is_some() || !stages.is_empty() {
                                return Err(
                                    part.error("one <direction> per branch, before its stages")
                                );
                            }
                            direction = Some(DVector::from_vec(numbers(part, n)?));
                        }
                        "stage" => {
                            part.only_attributes(&["mass", "stiffness", "damping"])?;
                            leaf(part)?;
                            if stages.len() == MAX_BRANCH_STAGES {
                                return Err(part.error(format!(
                                    "<branch> has more than {MAX_BRANCH_STAGES} stages \
                                     (MAX_BRANCH_STAGES)"
                                )));
                            }
                            stages.push(Stage {
                                mass: part.required_number("mass")?,
                                stiffness: part.required_number("stiffness")?,
                                damping: part.required_number("damping")?,
                            });
                        }
                        other => {
                            return Err(
                                part.error(format!("unexpected element <{other}> in <branch>"))
                            )
                        }
                    }
                }
                let direction =
                    direction.ok_or_else(|| child.error("<branch> has no <direction>"))?;
                if stages.is_empty() {
                    return Err(child.error("<branch> has no <stage>"));
                }
                states += 2 * stages.len();
                if states > MAX_NETWORK_STATES {
                    return Err(child.error(too_many_states(states)));
                }
                branches.push(Branch { direction, stages });
            }
            other => return Err(child.error(format!("unexpected element <{other}> in <network>"))),
        }
    }
    let added_mass_inf =
        added_mass_inf.ok_or_else(|| root.error("<network> has no <added_mass_inf>"))?;
    Ok(Network {
        dof_names,
        added_mass_inf,
        branches,
        substructures,
        rho,
        g,
        form,
    })
}
