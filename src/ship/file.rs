//! Ship files (`docs/SHIPS.md`), read with [`crate::xml`]. Every error names the file,
//! the line, the station and the field.

use super::girder::{modes, GirderKind, GirderMode};
use super::{SectionMotion, Ship, ShipDof, ShipError, Station, MAX_ELASTIC_MODES, RIGID_DOFS};
use crate::hull::{valid_dof_name, valid_hull_name, Hull};
use crate::xml::{self, Element};
use std::path::{Path, PathBuf};

impl Ship {
    /// Reads a ship file; hull files it names are found relative to its folder.
    ///
    /// # Errors
    /// An unreadable or malformed file, or a ship that fails [`Ship::new`]'s checks.
    pub fn from_file(path: &Path) -> Result<Ship, ShipError> {
        let source = path.display().to_string();
        let text = read_bounded(path).map_err(|cause| ShipError::unreadable(&source, cause))?;
        let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Ship::from_xml_str(&text, &source, &folder)
    }

    /// A ship of rigid DOFs ([`RIGID_DOFS`]) on the stations of a PDStrip offset file's
    /// text (docs/SHIPS.md); `waterline` as the `<offsets>` element's attribute.
    ///
    /// # Errors
    /// A malformed offset file (file, line and field), or a ship that fails [`Ship::new`].
    pub fn from_offsets_str(
        name: &str,
        text: &str,
        source_name: &str,
        waterline: Option<f64>,
    ) -> Result<Ship, ShipError> {
        let read = super::pdstrip::read(text, source_name, waterline).map_err(|m| {
            // The reader's messages start with "source:line: ".
            let rest = m
                .strip_prefix(source_name)
                .and_then(|r| r.strip_prefix(':'));
            let located = rest.and_then(|r| {
                let (line, message) = r.split_once(": ")?;
                Some((line.parse().ok()?, message.to_string()))
            });
            match located {
                Some((line, message)) => ShipError::new(source_name, Some(line), message),
                None => ShipError::new(source_name, None, m),
            }
        })?;
        let (mut sections, mut fingerprints) = (Vec::new(), Vec::new());
        let stations = read
            .into_iter()
            .map(|station| Station {
                x: station.x,
                section: station
                    .hull
                    .map(|hull| distinct(hull, &mut sections, &mut fingerprints)),
            })
            .collect();
        let dofs = RIGID_DOFS
            .iter()
            .map(|name| ShipDof {
                name: name.to_string(),
                motions: None,
            })
            .collect();
        Ship::new(name, stations, sections, dofs, source_name)
    }

    /// Parses ship XML; `source_name` names it in errors, `folder` is where its hull files are.
    ///
    /// # Errors
    /// As [`Ship::from_file`].
    pub fn from_xml_str(text: &str, source_name: &str, folder: &Path) -> Result<Ship, ShipError> {
        let root =
            xml::parse(text).map_err(|e| ShipError::new(source_name, Some(e.line), e.message))?;
        build(&root, source_name, folder)
    }
}

/// The index of `hull` among the distinct `sections` (by [`Hull::geometry_fingerprint`]: a
/// section of the same shape and DOFs under another name is the same), added if new.
fn distinct(hull: Hull, sections: &mut Vec<Hull>, fingerprints: &mut Vec<String>) -> usize {
    let print = hull.geometry_fingerprint();
    match fingerprints.iter().position(|f| *f == print) {
        Some(k) => k,
        None => {
            fingerprints.push(print);
            sections.push(hull);
            sections.len() - 1
        }
    }
}

/// The text of a ship, section or offset file, within [`xml::MAX_INPUT_BYTES`].
fn read_bounded(path: &Path) -> Result<String, crate::input::ReadError> {
    crate::input::read_bounded_text(path, xml::MAX_INPUT_BYTES as u64, "MAX_INPUT_BYTES")
}

fn build(root: &Element, source: &str, folder: &Path) -> Result<Ship, ShipError> {
    let err = |line: usize, m: String| ShipError::new(source, Some(line), m);
    let at = |e: xml::XmlError| ShipError::new(source, Some(e.line), e.message);
    if root.name != "ship" {
        return Err(err(
            root.line,
            format!("top-level element is <{}>, expected <ship>", root.name),
        ));
    }
    if let Some(element) = root.descendants().find(|e| e.has_text()) {
        return Err(err(
            element.text_line,
            "unexpected text: values go in attributes, e.g. <station x=\"10\">".to_string(),
        ));
    }
    root.only_attributes(&["name", "units", "version", "depth"])
        .map_err(at)?;
    let depth = match root.attribute("depth") {
        None => crate::units::WaterDepth::Infinite,
        Some(text) => text
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|h| h.is_finite() && *h > 0.0)
            .map(crate::units::WaterDepth::Finite)
            .ok_or_else(|| {
                err(
                    root.line,
                    format!(
                        "depth=\"{text}\": the water depth in metres must be a finite number \
                         > 0 (leave it out for deep water)"
                    ),
                )
            })?,
    };
    let name = root.required("name").map_err(at)?;
    if !valid_hull_name(name) {
        return Err(err(
            root.line,
            format!(
                "ship name \"{name}\" must start with a letter or digit and contain only \
                 letters, digits, '_', '-' and '.'"
            ),
        ));
    }
    if root.attribute("units").is_some_and(|u| u != "m") {
        return Err(err(root.line, "units must be \"m\" if given".to_string()));
    }
    if root.attribute("version").is_some_and(|v| v != "1") {
        return Err(err(root.line, "version must be \"1\" if given".to_string()));
    }

    let mut stations: Vec<Station> = Vec::new();
    let mut sections: Vec<Hull> = Vec::new();
    let mut fingerprints: Vec<String> = Vec::new();
    let mut files: Vec<(PathBuf, Hull)> = Vec::new();
    let mut rigid: Option<(Vec<String>, usize)> = None;
    let mut modes: Vec<(&Element, String)> = Vec::new();
    let mut structure: Vec<[Option<f64>; 5]> = Vec::new();
    let mut girder: Option<(&Element, usize)> = None;
    let mut offsets_line: Option<usize> = None;
    for child in &root.children {
        let line = child.line;
        match child.name.as_str() {
            "station" => {
                if let Some(first) = offsets_line {
                    return Err(err(
                        line,
                        format!(
                            "<station> after <offsets> (line {first}), which gives every station"
                        ),
                    ));
                }
                if stations.len() == super::MAX_STATIONS {
                    return Err(err(
                        line,
                        format!("more than {} stations", super::MAX_STATIONS),
                    ));
                }
                child
                    .only_attributes(&[
                        "x",
                        "mass",
                        "bending_stiffness_vertical",
                        "bending_stiffness_horizontal",
                        "torsional_stiffness",
                        "roll_inertia",
                    ])
                    .map_err(at)?;
                let x = child.required_number("x").map_err(at)?;
                let number = stations.len() + 1;
                let mut data = [None; 5];
                for (slot, key) in data.iter_mut().zip(STRUCTURE) {
                    if let Some(raw) = child.attribute(key) {
                        let value = xml::parse_number(raw).unwrap_or(f64::NAN);
                        if !(value.is_finite() && value > 0.0) {
                            return Err(err(
                                line,
                                format!(
                                    "station {number} at x = {x} m: {key} = \"{raw}\" must be \
                                     a positive, finite number"
                                ),
                            ));
                        }
                        *slot = Some(value);
                    }
                }
                structure.push(data);
                if child.children.len() > 1 {
                    return Err(err(
                        child.children[1].line,
                        format!("station {number} at x = {x} m has more than one section"),
                    ));
                }
                let section = match child.children.first() {
                    None => None,
                    Some(shape) => {
                        let hull = section_of(shape, source, folder, &mut files).map_err(|m| {
                            err(shape.line, format!("station {number} at x = {x} m: {m}"))
                        })?;
                        Some(distinct(hull, &mut sections, &mut fingerprints))
                    }
                };
                stations.push(Station { x, section });
            }
            "rigid" => {
                if let Some((_, first)) = &rigid {
                    return Err(err(
                        line,
                        format!("second <rigid>: the rigid DOFs are given on line {first}"),
                    ));
                }
                child.only_attributes(&["dofs"]).map_err(at)?;
                child.no_children().map_err(at)?;
                let words: Vec<String> = child
                    .required("dofs")
                    .map_err(at)?
                    .split_whitespace()
                    .map(str::to_string)
                    .collect();
                for (k, word) in words.iter().enumerate() {
                    if !RIGID_DOFS.contains(&word.as_str()) {
                        return Err(err(
                            line,
                            format!(
                                "rigid DOF '{word}' is not one of {} (surge is left out: a \
                                 slender section has no sectional force along x)",
                                RIGID_DOFS.join(" ")
                            ),
                        ));
                    }
                    if words[..k].contains(word) {
                        return Err(err(line, format!("rigid DOF '{word}' is named twice")));
                    }
                }
                rigid = Some((words, line));
            }
            "mode" => {
                child.only_attributes(&["name"]).map_err(at)?;
                let mode_name = child.required("name").map_err(at)?;
                if !valid_dof_name(mode_name) || RIGID_DOFS.contains(&mode_name) {
                    return Err(err(
                        line,
                        format!(
                            "mode name \"{mode_name}\" must start with a letter or '_', contain \
                             only letters, digits and '_', and not be a rigid DOF's name"
                        ),
                    ));
                }
                if modes.len() == MAX_ELASTIC_MODES {
                    return Err(err(line, format!("more than {MAX_ELASTIC_MODES} modes")));
                }
                if let Some((first, _)) = modes.iter().find(|(_, n)| n == mode_name) {
                    return Err(err(
                        line,
                        format!(
                            "mode '{mode_name}' is defined twice (first on line {})",
                            first.line
                        ),
                    ));
                }
                modes.push((child, mode_name.to_string()));
            }
            "offsets" => {
                if !stations.is_empty() {
                    return Err(err(
                        line,
                        "<offsets> gives every station; the file already has <station>s"
                            .to_string(),
                    ));
                }
                child
                    .only_attributes(&["file", "format", "waterline"])
                    .map_err(at)?;
                child.no_children().map_err(at)?;
                let format = child.required("format").map_err(at)?;
                if format != "pdstrip" {
                    return Err(err(
                        line,
                        format!("format=\"{format}\": the offsets format known is \"pdstrip\""),
                    ));
                }
                let waterline = match child.attribute("waterline") {
                    Some(_) => Some(child.required_number("waterline").map_err(at)?),
                    None => None,
                };
                let file = folder.join(child.required("file").map_err(at)?);
                let text = read_bounded(&file)
                    .map_err(|m| err(line, format!("{}: {m}", file.display())))?;
                let read = super::pdstrip::read(&text, &file.display().to_string(), waterline)
                    .map_err(|m| err(line, m))?;
                for station in read {
                    let section = station
                        .hull
                        .map(|hull| distinct(hull, &mut sections, &mut fingerprints));
                    stations.push(Station {
                        x: station.x,
                        section,
                    });
                    structure.push([None; 5]);
                }
                offsets_line = Some(line);
            }
            "girder_modes" => {
                if let Some((first, _)) = girder {
                    return Err(err(
                        line,
                        format!("second <girder_modes> (first on line {})", first.line),
                    ));
                }
                child
                    .only_attributes(&["vertical", "horizontal", "torsion"])
                    .map_err(at)?;
                child.no_children().map_err(at)?;
                girder = Some((child, modes.len()));
            }
            other => {
                return Err(err(
                    line,
                    format!(
                        "unknown element <{other}> in <ship>; expected station, offsets, rigid, \
                         mode or girder_modes"
                    ),
                ))
            }
        }
    }

    let mut dofs: Vec<ShipDof> = rigid
        .map(|(words, _)| words)
        .unwrap_or_else(|| RIGID_DOFS.iter().map(|s| s.to_string()).collect())
        .into_iter()
        .map(|name| ShipDof {
            name,
            motions: None,
        })
        .collect();
    let modes_count = modes.len();
    for (element, mode_name) in modes {
        if element.children.len() != stations.len() {
            return Err(err(
                element.line,
                format!(
                    "mode '{mode_name}' has {} <at> motions but the ship has {} stations (one \
                     per station, in order)",
                    element.children.len(),
                    stations.len()
                ),
            ));
        }
        let mut motions = Vec::with_capacity(stations.len());
        for (k, (at_element, station)) in element.children.iter().zip(&stations).enumerate() {
            let line = at_element.line;
            let here = |m: String| {
                err(
                    line,
                    format!(
                        "mode '{mode_name}', station {} at x = {} m: {m}",
                        k + 1,
                        station.x
                    ),
                )
            };
            if at_element.name != "at" {
                return Err(here(format!(
                    "unknown element <{}>; expected <at>",
                    at_element.name
                )));
            }
            at_element.no_children().map_err(at)?;
            let mut motion = SectionMotion {
                sway: 0.0,
                heave: 0.0,
                roll: 0.0,
                amplitudes: Vec::new(),
            };
            for (key, value) in &at_element.attributes {
                let number = xml::parse_number(value)
                    .map_err(|m| here(format!("field {key}=\"{value}\": {m}")))?;
                match key.as_str() {
                    "x" => {
                        if (number - station.x).abs() > 1e-9 * station.x.abs().max(1.0) {
                            return Err(here(format!(
                                "x = {number} m is not the station's x = {} m",
                                station.x
                            )));
                        }
                    }
                    "v" => motion.sway = number,
                    "w" => motion.heave = number,
                    "theta" => motion.roll = number,
                    amplitude => motion.amplitudes.push((amplitude.to_string(), number)),
                }
            }
            motions.push(motion);
        }
        dofs.push(ShipDof {
            name: mode_name,
            motions: Some(motions),
        });
    }
    let mut girder_modes = Vec::new();
    if let Some((element, position)) = girder {
        let computed = girder_dofs(element, &stations, &structure, source)?;
        let at = dofs.len() - modes_count + position;
        for (k, (dof, mode)) in computed.into_iter().enumerate() {
            girder_modes.push((dof.name.clone(), mode));
            dofs.insert(at + k, dof);
        }
    }
    let mut ship = Ship::new(name, stations, sections, dofs, source).map_err(|e| {
        // Point at the ship element when Ship::new found the problem.
        ShipError::new(
            source,
            e.line().or(Some(root.line)),
            e.message().to_string(),
        )
    })?;
    ship.girder_modes = girder_modes;
    Ok(ship.with_depth(depth))
}

/// The structural data a station may carry, in the order of the reader's slots.
const STRUCTURE: [&str; 5] = [
    "mass",
    "bending_stiffness_vertical",
    "bending_stiffness_horizontal",
    "torsional_stiffness",
    "roll_inertia",
];

/// The girder modes `<girder_modes vertical horizontal torsion>` asks for, as ship DOFs
/// (`vb1.., hb1.., t1..`) with their dry properties.
fn girder_dofs(
    element: &Element,
    stations: &[Station],
    structure: &[[Option<f64>; 5]],
    source: &str,
) -> Result<Vec<(ShipDof, GirderMode)>, ShipError> {
    let err = |m: String| ShipError::new(source, Some(element.line), m);
    let at = |e: xml::XmlError| ShipError::new(source, Some(e.line), e.message);
    let count = |key: &str| -> Result<usize, ShipError> {
        let value = element.optional_number(key, 0.0).map_err(at)?;
        if !((0.0..=20.0).contains(&value) && value.fract() == 0.0) {
            return Err(err(format!(
                "{key}=\"{value}\" must be a whole number from 0 to 20"
            )));
        }
        Ok(value as usize)
    };
    let x: Vec<f64> = stations.iter().map(|s| s.x).collect();
    let field = |slot: usize| -> Result<Vec<f64>, ShipError> {
        structure
            .iter()
            .zip(stations)
            .enumerate()
            .map(|(k, (data, station))| {
                data[slot].ok_or_else(|| {
                    err(format!(
                        "station {} at x = {} m has no {}, which <girder_modes> needs",
                        k + 1,
                        station.x,
                        STRUCTURE[slot]
                    ))
                })
            })
            .collect()
    };
    let mut out = Vec::new();
    for (key, kind, prefix, inertia, stiffness) in [
        ("vertical", GirderKind::Vertical, "vb", 0, 1),
        ("horizontal", GirderKind::Horizontal, "hb", 0, 2),
        ("torsion", GirderKind::Torsion, "t", 4, 3),
    ] {
        let n = count(key)?;
        if n == 0 {
            continue;
        }
        let found = modes(kind, &x, &field(inertia)?, &field(stiffness)?, n)
            .map_err(|e| err(e.to_string()))?;
        for (k, mode) in found.into_iter().enumerate() {
            let motions = mode
                .shape
                .iter()
                .map(|&value| {
                    let (sway, heave, roll) = match kind {
                        GirderKind::Vertical => (0.0, value, 0.0),
                        GirderKind::Horizontal => (value, 0.0, 0.0),
                        GirderKind::Torsion => (0.0, 0.0, value),
                    };
                    SectionMotion {
                        sway,
                        heave,
                        roll,
                        amplitudes: Vec::new(),
                    }
                })
                .collect();
            out.push((
                ShipDof {
                    name: format!("{prefix}{}", k + 1),
                    motions: Some(motions),
                },
                mode,
            ));
        }
    }
    if out.is_empty() {
        return Err(err("<girder_modes> asks for no mode".to_string()));
    }
    Ok(out)
}

/// The section of one station: `<semicircle radius>`, `<lewis breadth draft
/// area_coefficient>` or `<hull file>` (relative to the ship file's folder).
fn section_of(
    shape: &Element,
    source: &str,
    folder: &Path,
    files: &mut Vec<(PathBuf, Hull)>,
) -> Result<Hull, String> {
    let message = |e: xml::XmlError| e.message;
    shape.no_children().map_err(message)?;
    match shape.name.as_str() {
        "semicircle" => {
            shape.only_attributes(&["radius"]).map_err(message)?;
            let radius = shape.required_number("radius").map_err(message)?;
            Hull::semicircle(radius).map_err(|e| e.message().to_string())
        }
        "lewis" => {
            shape
                .only_attributes(&["breadth", "draft", "area_coefficient"])
                .map_err(message)?;
            let breadth = shape.required_number("breadth").map_err(message)?;
            let draft = shape.required_number("draft").map_err(message)?;
            let sigma = shape.required_number("area_coefficient").map_err(message)?;
            Hull::lewis(breadth, draft, sigma).map_err(|e| e.message().to_string())
        }
        "hull" => {
            shape.only_attributes(&["file"]).map_err(message)?;
            let file = folder.join(shape.required("file").map_err(message)?);
            if let Some((_, hull)) = files.iter().find(|(p, _)| *p == file) {
                return Ok(hull.clone());
            }
            let text = read_bounded(&file).map_err(|m| format!("{}: {m}", file.display()))?;
            let hull = Hull::from_xml_str(&text, &file.display().to_string())
                .map_err(|e| format!("in the section's hull file: {e}"))?;
            files.push((file, hull.clone()));
            Ok(hull)
        }
        other => Err(format!(
            "unknown section <{other}> (in {source}); expected semicircle, lewis or hull"
        )),
    }
}
