//! A hull file's mass properties: the `<mass>` element that makes a section float.
//!
//! ```xml
//! <mass value="displaced" x="0" y="-0.2" radius_of_gyration="0.3">
//!   <mooring dof="sway" stiffness="1000" damping="50"/>
//! </mass>
//! ```
//!
//! `value` is the mass per unit length in kg/m, or `displaced` (the displaced mass at the water
//! density the table is made for: free floating); `x`, `y` the centre of gravity in the hull's
//! frame (m); `radius_of_gyration` about the centre of gravity (m). Each `<mooring>` gives a
//! rigid DOF's external stiffness (N/m per m, N m/rad per m for roll) and damping (N s/m per m,
//! N m s/rad per m), both >= 0 and 0 when absent. [`crate::motion`] solves the motion.

use super::{check_coordinates, Hull, HullError};
use crate::motion::MassProperties;
use crate::xml::{Element, XmlError};
use nalgebra::DMatrix;

/// Mass per unit length of a floating section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SectionMass {
    /// The displaced mass `rho A` at the water density of the computation.
    Displaced,
    /// A given mass per unit length, kg/m (finite, > 0).
    PerLength(f64),
}

/// One rigid DOF's external (mooring) stiffness and damping, per unit length.
#[derive(Clone, Debug, PartialEq)]
pub struct Mooring {
    /// The rigid DOF's name.
    pub dof: String,
    /// Stiffness, SI per unit length (>= 0).
    pub stiffness: f64,
    /// Damping, SI per unit length (>= 0).
    pub damping: f64,
}

/// The mass properties a hull file gives (its `<mass>` element).
#[derive(Clone, Debug, PartialEq)]
pub struct HullMass {
    /// Mass per unit length.
    pub mass: SectionMass,
    /// Centre of gravity (x, y), m.
    pub centre_of_gravity: [f64; 2],
    /// Radius of gyration about the centre of gravity, m (>= 0).
    pub radius_of_gyration: f64,
    /// External stiffness and damping of rigid DOFs, at most one entry per DOF.
    pub mooring: Vec<Mooring>,
}

impl HullMass {
    /// The mass properties over `hull`'s rigid DOFs (in its order) in water of density `rho`
    /// (kg/m^3, for `displaced`). Moorings of DOFs the hull no longer has (after
    /// [`Hull::select_dofs`]) are left out: those DOFs do not move.
    ///
    /// # Errors
    /// `displaced` of a hull whose submerged area cannot be computed.
    pub fn properties(&self, hull: &Hull, rho: f64) -> Result<MassProperties, HullError> {
        let mass = match self.mass {
            SectionMass::PerLength(m) => m,
            SectionMass::Displaced => {
                let statics = crate::hydrostatics::stiffness(hull).map_err(|e| {
                    HullError::new(
                        hull.name(),
                        None,
                        format!("<mass value=\"displaced\">: {e}"),
                    )
                })?;
                rho * statics.submerged_area
            }
        };
        let rigid: Vec<&str> = (0..hull.dof_count())
            .filter(|&j| matches!(hull.dof_kind(j), Some(super::DofKind::Rigid { .. })))
            .map(|j| hull.dof_names()[j])
            .collect();
        let n = rigid.len();
        let (mut stiffness, mut damping) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
        for m in &self.mooring {
            if let Some(k) = rigid.iter().position(|d| *d == m.dof) {
                stiffness[(k, k)] = m.stiffness;
                damping[(k, k)] = m.damping;
            }
        }
        let empty = |m: DMatrix<f64>| {
            if m.iter().all(|&v| v == 0.0) {
                DMatrix::zeros(0, 0)
            } else {
                m
            }
        };
        Ok(MassProperties {
            mass,
            centre_of_gravity: self.centre_of_gravity,
            radius_of_gyration: self.radius_of_gyration,
            stiffness: empty(stiffness),
            damping: empty(damping),
        })
    }

    /// The canonical `<mass>` element (two-space indent), as [`Hull::to_xml_string`] writes it.
    pub(super) fn to_xml(&self, num: impl Fn(f64) -> String) -> String {
        let value = match self.mass {
            SectionMass::Displaced => "displaced".to_string(),
            SectionMass::PerLength(m) => num(m),
        };
        let open = format!(
            "  <mass value=\"{value}\" x=\"{}\" y=\"{}\" radius_of_gyration=\"{}\"",
            num(self.centre_of_gravity[0]),
            num(self.centre_of_gravity[1]),
            num(self.radius_of_gyration)
        );
        if self.mooring.is_empty() {
            return format!("{open}/>\n");
        }
        let mut out = format!("{open}>\n");
        for m in &self.mooring {
            out.push_str(&format!(
                "    <mooring dof=\"{}\" stiffness=\"{}\" damping=\"{}\"/>\n",
                crate::xml::escape(&m.dof),
                num(m.stiffness),
                num(m.damping)
            ));
        }
        out.push_str("  </mass>\n");
        out
    }
}

/// A number attribute that must be finite and at least `lower`.
fn at_least(
    element: &Element,
    key: &str,
    lower: f64,
    default: Option<f64>,
) -> Result<f64, XmlError> {
    let value = match default {
        Some(d) => element.optional_number(key, d)?,
        None => element.required_number(key)?,
    };
    if value >= lower {
        Ok(value)
    } else {
        Err(element.error(format!(
            "{key}=\"{value}\" in <{}> must be >= {lower}",
            element.name
        )))
    }
}

/// Parses a `<mass>` element; `rigid` lists the file's rigid DOF names (moorings must name one).
pub(super) fn parse(element: &Element, rigid: &[&str]) -> Result<HullMass, XmlError> {
    element.only_attributes(&["value", "x", "y", "radius_of_gyration"])?;
    let word = element.required("value")?;
    let mass = if word.trim() == "displaced" {
        SectionMass::Displaced
    } else {
        let m = element.required_number("value").map_err(|_| {
            element.error(format!(
                "value=\"{word}\" in <mass> must be a mass per unit length in kg/m or \
                 \"displaced\""
            ))
        })?;
        if m <= 0.0 {
            return Err(element.error(format!("value=\"{word}\" in <mass> must be > 0 kg/m")));
        }
        SectionMass::PerLength(m)
    };
    let centre = [element.required_number("x")?, element.required_number("y")?];
    check_coordinates("centre of gravity", centre).map_err(|m| element.error(m))?;
    let radius_of_gyration = at_least(element, "radius_of_gyration", 0.0, None)?;
    let mut mooring: Vec<Mooring> = Vec::new();
    for child in &element.children {
        if child.name != "mooring" {
            return Err(child.error(format!(
                "unknown element <{}> in <mass>; expected <mooring>",
                child.name
            )));
        }
        child.only_attributes(&["dof", "stiffness", "damping"])?;
        child.no_children()?;
        let dof = child.required("dof")?;
        if !rigid.contains(&dof) {
            return Err(child.error(format!(
                "<mooring dof=\"{dof}\">: not a rigid DOF of the hull (its rigid DOFs: {})",
                if rigid.is_empty() {
                    "none".to_string()
                } else {
                    rigid.join(" ")
                }
            )));
        }
        if mooring.iter().any(|m| m.dof == dof) {
            return Err(child.error(format!("<mooring dof=\"{dof}\"> is given twice")));
        }
        if child.attribute("stiffness").is_none() && child.attribute("damping").is_none() {
            return Err(child.error(format!(
                "<mooring dof=\"{dof}\"> needs stiffness or damping (or both)"
            )));
        }
        mooring.push(Mooring {
            dof: dof.to_string(),
            stiffness: at_least(child, "stiffness", 0.0, Some(0.0))?,
            damping: at_least(child, "damping", 0.0, Some(0.0))?,
        });
    }
    Ok(HullMass {
        mass,
        centre_of_gravity: centre,
        radius_of_gyration,
        mooring,
    })
}

#[cfg(test)]
mod tests;
