//! Hull files: reading (on [`crate::xml`]) and canonical writing.
//!
//! XML, described in `docs/HULL_FORMAT.md`; [`Hull::from_file`], [`Hull::from_xml_str`],
//! [`Hull::to_xml_string`] (canonical text, round-trips exactly). Validation is strict; every
//! error names the file, the line and the problem. A contour written clockwise is reversed
//! (points and mode vectors) and a note is recorded ([`Hull::notes`]).

use super::builtin::check_circle_depth;
use super::validate::{knots, validate_polyline};
use super::{
    check_coordinates, check_half_beam_ratio, check_length, craig_bampton_coefficients, Contour,
    Dof, Field, Hull, HullError, Point, RigidKind, MAX_CONTOUR_POINTS, MAX_DOFS, MIN_LENGTH,
};
use crate::xml::{self, escape, Element, Notation, XmlError};
use std::path::Path;

impl Hull {
    /// Reads a hull file (format: `docs/HULL_FORMAT.md`).
    pub fn from_file(path: &Path) -> Result<Hull, HullError> {
        let source = path.display().to_string();
        let text =
            crate::input::read_bounded_text(path, xml::MAX_INPUT_BYTES as u64, "MAX_INPUT_BYTES")
                .map_err(|cause| HullError::unreadable(&source, cause))?;
        Hull::from_xml_str(&text, &source)
    }

    /// Parses hull XML; `source_name` names it in errors (usually the file name).
    pub fn from_xml_str(text: &str, source_name: &str) -> Result<Hull, HullError> {
        let root = xml::parse(text).map_err(located(source_name))?;
        if let Some(element) = root.descendants().find(|e| e.has_text()) {
            return Err(HullError::new(
                source_name,
                Some(element.text_line),
                "unexpected text: values go in attributes, e.g. <point x=\"1\" y=\"-2\"/>",
            ));
        }
        build_hull(&root, source_name)
    }

    /// 64-bit FNV-1a of [`Hull::to_xml_string`], as 16 hex digits. Covers the name, the
    /// half-beam, the geometry and every DOF (name, order, field), so hulls that differ in any
    /// of these get different fingerprints.
    pub fn fingerprint(&self) -> String {
        fnv1a(&self.to_xml_string())
    }

    /// As [`Hull::fingerprint`], without the name: hulls with the same half-beam, geometry and
    /// DOFs, which solve to the same tables, get the same value (a ship's sections given by
    /// different files of the same shape are solved once).
    pub fn geometry_fingerprint(&self) -> String {
        let unnamed = Hull {
            name: String::new(),
            mass: None,
            bilge_keels: None,
            ..self.clone()
        };
        fnv1a(&unnamed.to_xml_string())
    }

    /// Canonical XML in the documented format; `from_xml_str` of it gives the same hull.
    pub fn to_xml_string(&self) -> String {
        let mut out = String::new();
        out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        let depth = self
            .water_depth
            .map_or(String::new(), |h| format!(" depth=\"{}\"", num(h)));
        out.push_str(&format!(
            "<hull name=\"{}\" half_beam=\"{}\" units=\"m\" version=\"1\"{depth}>\n",
            escape(&self.name),
            num(self.half_beam)
        ));
        match &self.contour {
            Contour::Arc { radius, depth, .. } => out.push_str(&format!(
                "  <circle radius=\"{}\" depth=\"{}\"/>\n",
                num(*radius),
                num(*depth)
            )),
            Contour::Lewis(form) => out.push_str(&format!(
                "  <lewis breadth=\"{}\" draft=\"{}\" area_coefficient=\"{}\"/>\n",
                num(form.breadth),
                num(form.draft),
                num(form.area_coefficient)
            )),
            Contour::Polyline { points, closed, .. } => {
                out.push_str(&format!("  <contour closed=\"{closed}\">\n"));
                for p in points {
                    out.push_str(&format!(
                        "    <point x=\"{}\" y=\"{}\"/>\n",
                        num(p[0]),
                        num(p[1])
                    ));
                }
                out.push_str("  </contour>\n");
            }
        }
        for dof in &self.dofs {
            let name = escape(&dof.name);
            match &dof.field {
                Field::Rigid { kind, reference } => out.push_str(&format!(
                    "  <rigid name=\"{name}\" kind=\"{}\" x=\"{}\" y=\"{}\"/>\n",
                    kind.as_str(),
                    num(reference[0]),
                    num(reference[1])
                )),
                Field::CraigBampton { mode, .. } => out.push_str(&format!(
                    "  <craig_bampton name=\"{name}\" mode=\"{mode}\"/>\n"
                )),
                Field::Vectors(v) => {
                    out.push_str(&format!("  <mode name=\"{name}\">\n"));
                    for u in v {
                        out.push_str(&format!(
                            "    <u x=\"{}\" y=\"{}\"/>\n",
                            num(u[0]),
                            num(u[1])
                        ));
                    }
                    out.push_str("  </mode>\n");
                }
            }
        }
        if let Some(mass) = &self.mass {
            out.push_str(&mass.to_xml(num));
        }
        if let Some(keels) = &self.bilge_keels {
            out.push_str(&super::keels::to_xml(keels, num));
        }
        out.push_str("</hull>\n");
        out
    }
}

/// Hull files write numbers in [`Notation::Float`] (the fingerprint hashes this text).
fn num(x: f64) -> String {
    xml::format_number(x, Notation::Float)
}

/// Places an XML error in the file `source`.
fn located(source: &str) -> impl Fn(XmlError) -> HullError + Copy + '_ {
    move |e| HullError::new(source, Some(e.line), e.message)
}

/// Points (or vectors) of `<point>`/`<u>` children, with their lines.
fn vectors(
    element: &Element,
    child_name: &str,
    source: &str,
) -> Result<(Vec<Point>, Vec<usize>), HullError> {
    let at = located(source);
    let mut values = Vec::with_capacity(element.children.len());
    let mut lines = Vec::with_capacity(element.children.len());
    for child in &element.children {
        if child.name != child_name {
            return Err(HullError::new(
                source,
                Some(child.line),
                format!(
                    "unknown element <{}> in <{}>; expected <{child_name}>",
                    child.name, element.name
                ),
            ));
        }
        child.no_children().map_err(at)?;
        let x = child.required_number("x").map_err(at)?;
        let y = child.required_number("y").map_err(at)?;
        child.only_attributes(&["x", "y"]).map_err(at)?;
        values.push([x, y]);
        lines.push(child.line);
    }
    Ok((values, lines))
}

pub(crate) fn valid_dof_name(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

pub(crate) fn valid_hull_name(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphanumeric())
        && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

enum Geometry {
    Circle {
        radius: f64,
        depth: f64,
        line: usize,
    },
    Polyline {
        points: Vec<Point>,
        lines: Vec<usize>,
        closed: bool,
        line: usize,
    },
    Lewis {
        form: super::lewis::LewisForm,
        line: usize,
    },
}

enum FileField {
    Rigid(RigidKind, Point),
    CraigBampton(usize),
    Vectors(Vec<Point>),
}

struct FileDof {
    name: String,
    field: FileField,
    line: usize,
}

fn build_hull(root: &Element, source: &str) -> Result<Hull, HullError> {
    let err = |line: usize, m: String| HullError::new(source, Some(line), m);
    let at = located(source);
    if root.name != "hull" {
        return Err(err(
            root.line,
            format!("top-level element is <{}>, expected <hull>", root.name),
        ));
    }
    let name = root.required("name").map_err(at)?;
    if !valid_hull_name(name) {
        return Err(err(
            root.line,
            format!(
                "hull name \"{name}\" must start with a letter or digit and contain only \
                 letters, digits, '_', '-' and '.'"
            ),
        ));
    }
    let half_beam = root.required_number("half_beam").map_err(at)?;
    if half_beam <= 0.0 {
        return Err(err(
            root.line,
            format!("half_beam must be positive, got {half_beam}"),
        ));
    }
    check_length("half_beam", half_beam).map_err(|m| err(root.line, m))?;
    if let Some(units) = root.attribute("units") {
        if units != "m" {
            return Err(err(
                root.line,
                format!(
                    "units=\"{units}\" is not supported: coordinates are in metres, units=\"m\""
                ),
            ));
        }
    }
    if let Some(version) = root.attribute("version") {
        if version != "1" {
            return Err(err(
                root.line,
                format!("version=\"{version}\" is not supported; this reader knows version 1"),
            ));
        }
    }
    let water_depth = match root.attribute("depth") {
        None => None,
        Some(_) => {
            let depth = root.required_number("depth").map_err(at)?;
            if !(depth.is_finite() && depth > 0.0) {
                return Err(err(
                    root.line,
                    format!(
                        "depth (the water depth, m) must be finite and > 0, got {depth} (leave \
                         it out for deep water)"
                    ),
                ));
            }
            Some(depth)
        }
    };
    root.only_attributes(&["name", "half_beam", "units", "version", "depth"])
        .map_err(at)?;

    let mut geometry: Option<Geometry> = None;
    let mut dofs: Vec<FileDof> = Vec::new();
    let mut mass_element: Option<&Element> = None;
    let mut keels: Option<(crate::viscous::BilgeKeels, usize)> = None;
    for child in &root.children {
        let line = child.line;
        if matches!(child.name.as_str(), "contour" | "circle" | "lewis") {
            if let Some(
                Geometry::Circle { line: first, .. }
                | Geometry::Polyline { line: first, .. }
                | Geometry::Lewis { line: first, .. },
            ) = &geometry
            {
                return Err(err(
                    line,
                    format!(
                        "second geometry <{}>: the contour is already given on line {first}",
                        child.name
                    ),
                ));
            }
        }
        match child.name.as_str() {
            "contour" => {
                let closed = match child.attribute("closed") {
                    None | Some("false") => false,
                    Some("true") => true,
                    Some(other) => {
                        return Err(err(
                            line,
                            format!("closed=\"{other}\" must be \"true\" or \"false\""),
                        ))
                    }
                };
                child.only_attributes(&["closed"]).map_err(at)?;
                if child.children.len() > MAX_CONTOUR_POINTS {
                    return Err(err(
                        line,
                        format!(
                            "the contour has {} points; at most {MAX_CONTOUR_POINTS} (each \
                             point becomes a panel node, and the panel count is limited to \
                             {MAX_CONTOUR_POINTS})",
                            child.children.len()
                        ),
                    ));
                }
                let (points, lines) = vectors(child, "point", source)?;
                for (p, &line) in points.iter().zip(&lines) {
                    check_coordinates("point", *p).map_err(|m| err(line, m))?;
                }
                geometry = Some(Geometry::Polyline {
                    points,
                    lines,
                    closed,
                    line,
                });
            }
            "circle" => {
                let radius = child.required_number("radius").map_err(at)?;
                let depth = child.required_number("depth").map_err(at)?;
                child.only_attributes(&["radius", "depth"]).map_err(at)?;
                child.no_children().map_err(at)?;
                if radius <= 0.0 {
                    return Err(err(line, format!("radius must be positive, got {radius}")));
                }
                check_length("radius", radius).map_err(|m| err(line, m))?;
                check_circle_depth(depth / radius).map_err(|m| err(line, m))?;
                check_coordinates("centre", [0.0, -depth]).map_err(|m| err(line, m))?;
                geometry = Some(Geometry::Circle {
                    radius,
                    depth,
                    line,
                });
            }
            "lewis" => {
                let breadth = child.required_number("breadth").map_err(at)?;
                let draft = child.required_number("draft").map_err(at)?;
                let sigma = child.required_number("area_coefficient").map_err(at)?;
                child
                    .only_attributes(&["breadth", "draft", "area_coefficient"])
                    .map_err(at)?;
                child.no_children().map_err(at)?;
                check_length("breadth", breadth).map_err(|m| err(line, m))?;
                check_length("draft", draft).map_err(|m| err(line, m))?;
                let form = super::lewis::LewisForm::new(breadth, draft, sigma)
                    .map_err(|e| err(line, e.to_string()))?;
                geometry = Some(Geometry::Lewis { form, line });
            }
            "rigid" | "craig_bampton" | "mode" => {
                let dof_name = child.required("name").map_err(at)?;
                if !valid_dof_name(dof_name) {
                    return Err(err(
                        line,
                        format!(
                            "DOF name \"{dof_name}\" must start with a letter or '_' and contain \
                             only letters, digits and '_'"
                        ),
                    ));
                }
                if dofs.len() == MAX_DOFS {
                    return Err(err(
                        line,
                        format!(
                            "DOF '{dof_name}' is one more than the {MAX_DOFS} a hull may have \
                             (the sweep's matrices grow with the square of the DOF count, the \
                             network fit with its cube)"
                        ),
                    ));
                }
                if let Some(first) = dofs.iter().find(|d| d.name == dof_name) {
                    return Err(err(
                        line,
                        format!(
                            "duplicate DOF name '{dof_name}' (first defined on line {})",
                            first.line
                        ),
                    ));
                }
                let field = match child.name.as_str() {
                    "rigid" => {
                        let word = child.required("kind").map_err(at)?;
                        let kind = RigidKind::parse(word).ok_or_else(|| {
                            err(
                                line,
                                format!("kind=\"{word}\" must be \"sway\", \"heave\" or \"roll\""),
                            )
                        })?;
                        let x = child.optional_number("x", 0.0).map_err(at)?;
                        let y = child.optional_number("y", 0.0).map_err(at)?;
                        check_coordinates("reference point", [x, y]).map_err(|m| err(line, m))?;
                        child
                            .only_attributes(&["name", "kind", "x", "y"])
                            .map_err(at)?;
                        child.no_children().map_err(at)?;
                        FileField::Rigid(kind, [x, y])
                    }
                    "craig_bampton" => {
                        let word = child.required("mode").map_err(at)?;
                        let mode = match word.trim().parse::<usize>() {
                            Ok(m) if (1..=6).contains(&m) => m,
                            _ => {
                                return Err(err(
                                    line,
                                    format!("mode=\"{word}\" must be an integer from 1 to 6"),
                                ))
                            }
                        };
                        child.only_attributes(&["name", "mode"]).map_err(at)?;
                        child.no_children().map_err(at)?;
                        FileField::CraigBampton(mode)
                    }
                    _ => {
                        child.only_attributes(&["name"]).map_err(at)?;
                        let (values, lines) = vectors(child, "u", source)?;
                        for (u, &line) in values.iter().zip(&lines) {
                            check_coordinates("displacement", *u).map_err(|m| err(line, m))?;
                        }
                        let largest = values.iter().flatten().fold(0.0f64, |a, c| a.max(c.abs()));
                        if largest > 0.0 && largest < MIN_LENGTH {
                            return Err(err(
                                line,
                                format!(
                                    "mode '{dof_name}': its largest displacement component \
                                     {largest:e} m is below {MIN_LENGTH:e} m, too small to give \
                                     meaningful numbers; scale the mode up"
                                ),
                            ));
                        }
                        FileField::Vectors(values)
                    }
                };
                dofs.push(FileDof {
                    name: dof_name.to_string(),
                    field,
                    line,
                });
            }
            "mass" => {
                if let Some(first) = mass_element {
                    return Err(err(
                        line,
                        format!(
                            "second <mass>: the mass properties are already given on line {}",
                            first.line
                        ),
                    ));
                }
                mass_element = Some(child);
            }
            "bilge_keels" => {
                if let Some((_, first)) = keels {
                    return Err(err(
                        line,
                        format!(
                            "second <bilge_keels>: the keels are already given on line {first}"
                        ),
                    ));
                }
                keels = Some((super::keels::parse(child).map_err(at)?, line));
            }
            other => {
                return Err(err(
                    line,
                    format!(
                        "unknown element <{other}> in <hull>; expected contour, circle, lewis, \
                         rigid, craig_bampton, mode, mass or bilge_keels"
                    ),
                ))
            }
        }
    }

    let geometry = geometry.ok_or_else(|| {
        err(
            root.line,
            "the hull has no geometry: add a <contour> (or a <circle> or <lewis>)".to_string(),
        )
    })?;
    if dofs.is_empty() {
        return Err(err(
            root.line,
            "the hull has no DOFs: add <rigid>, <mode> (or <craig_bampton>) elements".to_string(),
        ));
    }
    let (size, geometry_line) = match &geometry {
        Geometry::Circle { radius, line, .. } => (2.0 * radius, *line),
        Geometry::Lewis { form, line } => (form.breadth.max(form.draft), *line),
        Geometry::Polyline { points, line, .. } => {
            let extent = |k: usize| {
                let (lo, hi) = points
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
                        (a.0.min(p[k]), a.1.max(p[k]))
                    });
                hi - lo
            };
            (extent(0).max(extent(1)), *line)
        }
    };
    if size > 0.0 {
        check_length(
            "the section's size (the largest side of its bounding box)",
            size,
        )
        .map_err(|m| err(geometry_line, m))?;
        check_half_beam_ratio(half_beam, size).map_err(|m| err(root.line, m))?;
    }
    let rigid: Vec<&str> = dofs
        .iter()
        .filter(|d| matches!(d.field, FileField::Rigid(..)))
        .map(|d| d.name.as_str())
        .collect();
    let mass = mass_element
        .map(|element| super::mass::parse(element, &rigid))
        .transpose()
        .map_err(at)?;
    let mut notes = Vec::new();
    let (contour, order) = match geometry {
        Geometry::Circle { radius, depth, .. } => {
            for dof in &dofs {
                match dof.field {
                    FileField::Vectors(_) => {
                        return Err(err(
                            dof.line,
                            format!(
                                "mode '{}' gives vectors at contour points, but a <circle> has \
                                 no points; write the contour as <contour>",
                                dof.name
                            ),
                        ))
                    }
                    FileField::CraigBampton(_) if depth > 0.0 => {
                        return Err(err(
                            dof.line,
                            format!(
                                "Craig-Bampton mode '{}' needs the semicircle (depth=\"0\")",
                                dof.name
                            ),
                        ))
                    }
                    _ => {}
                }
            }
            (
                Contour::Arc {
                    radius,
                    depth,
                    depth_ratio: depth / half_beam,
                },
                None,
            )
        }
        Geometry::Lewis { form, .. } => {
            if let Some(dof) = dofs
                .iter()
                .find(|d| !matches!(d.field, FileField::Rigid(..)))
            {
                return Err(err(
                    dof.line,
                    format!(
                        "DOF '{}': a <lewis> section takes rigid DOFs only (its contour has no \
                         points for mode vectors); write the contour as <contour>",
                        dof.name
                    ),
                ));
            }
            (Contour::Lewis(form), None)
        }
        Geometry::Polyline {
            mut points,
            lines,
            closed,
            line,
        } => {
            if points.len() < 3 {
                return Err(err(
                    line,
                    format!(
                        "the contour has {} points; at least 3 are needed",
                        points.len()
                    ),
                ));
            }
            for dof in &dofs {
                match &dof.field {
                    FileField::CraigBampton(_) => {
                        return Err(err(
                            dof.line,
                            format!(
                                "Craig-Bampton mode '{}' needs the built-in semicircle \
                                 (<circle depth=\"0\">), not a <contour>",
                                dof.name
                            ),
                        ))
                    }
                    FileField::Vectors(v) if v.len() != points.len() => {
                        return Err(err(
                            dof.line,
                            format!(
                                "mode '{}' has {} vectors but the contour has {} points",
                                dof.name,
                                v.len(),
                                points.len()
                            ),
                        ))
                    }
                    FileField::Vectors(v) if v.iter().all(|u| u[0] == 0.0 && u[1] == 0.0) => {
                        return Err(err(
                            dof.line,
                            format!("mode '{}' is zero at every point", dof.name),
                        ))
                    }
                    _ => {}
                }
            }
            let order = validate_polyline(&mut points, &lines, closed, line, source, &mut notes)?;
            if let Some(order) = &order {
                points = order.iter().map(|&i| points[i]).collect();
            }
            let (knots, length) = knots(&points, closed);
            (
                Contour::Polyline {
                    points,
                    closed,
                    knots,
                    length,
                },
                order,
            )
        }
    };
    let dofs = dofs
        .into_iter()
        .map(|d| Dof {
            field: match d.field {
                FileField::Rigid(kind, reference) => Field::Rigid { kind, reference },
                FileField::CraigBampton(mode) => Field::CraigBampton {
                    mode,
                    coefficients: match contour {
                        Contour::Arc { radius, .. } => craig_bampton_coefficients(radius)[mode - 1],
                        Contour::Lewis(_) | Contour::Polyline { .. } => [f64::NAN; 6],
                    },
                },
                FileField::Vectors(v) => Field::Vectors(match &order {
                    Some(order) => order.iter().map(|&i| v[i]).collect(),
                    None => v,
                }),
            },
            name: d.name,
        })
        .collect();
    Ok(Hull {
        name: name.to_string(),
        half_beam,
        contour,
        dofs,
        notes,
        mass,
        bilge_keels: keels.map(|(k, _)| k),
        water_depth,
    })
}

/// 64-bit FNV-1a of `text`, as 16 hex digits.
fn fnv1a(text: &str) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in text.bytes() {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{hash:016x}")
}
