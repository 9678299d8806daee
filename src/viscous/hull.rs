//! Ikeda's input from a section hull, and the estimates an FMU packs by default.
//!
//! From the hull (docs/VISCOUS.md, "From a hull"):
//!
//! - `B`: the waterline breadth, `T`: the depth of the contour's lowest point (sampled at every
//!   breakpoint and at 4096 even steps of `s`), `sigma = A / (B T)` with the submerged area `A`
//!   ([`crate::hydrostatics`]);
//! - the bilge radius from the area a rounded rectangle misses: two bilges of radius `R` take
//!   `(2 - pi/2) R^2` from `B T`, so `R = sqrt(2 B T (1 - sigma) / (4 - pi))`, clipped to
//!   `min(B/2, T)` (exact for a rounded box and for a semicircle);
//! - `OG = -y_G` with the centre of gravity of the file's `<mass>` (a floating section rolls
//!   about it), else `OG = -y_P` with the roll DOF's reference point `P` (y up, waterline
//!   y = 0; `OG` positive below the water);
//! - the keels of the file's `<bilge_keels>`.
//!
//! The roll natural frequency of a hull with `<mass>`: `omega_n = sqrt(C / I)` about `P`, with
//! `C = rho g C_44/(rho g) - m g (y_G - y_P)` and the dry inertia `I = m (k^2 + |G - P|^2)`
//! (uncoupled; the added mass, left out, lowers the true value).
//!
//! Cross-flow drag of a sway DOF: `B_q = 0.5 rho C_D T` per metre; of a heave DOF:
//! `B_q = 0.5 rho C_D B`, with `C_D` of [`super::cross_flow_drag_coefficient`].

use super::{
    cross_flow_drag_coefficient, roll_damping, CrossFlow, RollDamping, RollDampingParams,
    ViscousError,
};
use crate::hull::{DofKind, Hull, RigidKind};
use std::f64::consts::PI;
use std::fmt;

/// Even steps of `s` sampled for the draft (besides the contour's breakpoints).
const DRAFT_SAMPLES: usize = 4096;

/// Why a hull gives no estimate.
#[derive(Clone, Debug, PartialEq)]
pub struct HullDampingError {
    /// The hull's name.
    pub hull: String,
    /// What is missing or refused.
    pub reason: String,
}

impl HullDampingError {
    fn new(hull: &Hull, reason: impl Into<String>) -> Self {
        HullDampingError {
            hull: hull.name().to_string(),
            reason: reason.into(),
        }
    }
}

impl fmt::Display for HullDampingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "viscous estimate of hull '{}': {}",
            self.hull, self.reason
        )
    }
}

impl std::error::Error for HullDampingError {}

/// The roll axis Ikeda's `OG` is taken from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RollAxis {
    /// The centre of gravity of the hull file's `<mass>`.
    CentreOfGravity,
    /// The roll DOF's reference point.
    ReferencePoint,
}

impl RollAxis {
    /// Words for summaries.
    pub fn describe(self) -> &'static str {
        match self {
            RollAxis::CentreOfGravity => "the centre of gravity",
            RollAxis::ReferencePoint => "the roll reference point",
        }
    }
}

/// A hull's roll-damping input.
#[derive(Clone, Debug, PartialEq)]
pub struct HullRoll {
    /// Ikeda's input (water density `rho`, sea water's viscosity).
    pub params: RollDampingParams,
    /// The hull's roll DOF (its first rigid roll).
    pub dof: usize,
    /// Where `OG` comes from.
    pub axis: RollAxis,
}

/// Breadth, draft, area coefficient and bilge radius of an open contour.
fn section_shape(hull: &Hull) -> Result<[f64; 4], HullDampingError> {
    if hull.is_closed() {
        return Err(HullDampingError::new(
            hull,
            "the contour is closed (a submerged body): Ikeda's method needs a surface-piercing \
             section; give the damping entries yourself",
        ));
    }
    let statics = crate::hydrostatics::stiffness(hull)
        .map_err(|e| HullDampingError::new(hull, e.to_string()))?;
    let breadth = statics.waterline_breadth;
    let samples = (0..=DRAFT_SAMPLES).map(|k| k as f64 / DRAFT_SAMPLES as f64);
    let draft = hull
        .breakpoints()
        .into_iter()
        .chain(samples)
        .map(|s| -hull.point(s)[1])
        .fold(0.0, f64::max);
    if !(breadth > 0.0 && draft > 0.0) {
        return Err(HullDampingError::new(
            hull,
            format!("waterline breadth {breadth} m and draft {draft} m: not a floating section"),
        ));
    }
    let sigma = statics.submerged_area / (breadth * draft);
    Ok([
        breadth,
        draft,
        sigma,
        bilge_radius_from_area(breadth, draft, sigma),
    ])
}

/// The bilge radius of a rounded rectangle of breadth `B`, draft `T` and area coefficient
/// `sigma`: `sqrt(2 B T (1 - sigma) / (4 - pi))`, clipped to `[0, min(B/2, T)]`.
pub fn bilge_radius_from_area(breadth: f64, draft: f64, sigma: f64) -> f64 {
    let deficit = (1.0 - sigma).max(0.0);
    (2.0 * breadth * draft * deficit / (4.0 - PI))
        .sqrt()
        .min(0.5 * breadth)
        .min(draft)
}

/// The first rigid DOF of `kind` and its reference point.
fn rigid_dof(hull: &Hull, wanted: RigidKind) -> Option<(usize, [f64; 2])> {
    (0..hull.dof_count()).find_map(|j| match hull.dof_kind(j) {
        Some(DofKind::Rigid { kind, reference }) if kind == wanted => Some((j, reference)),
        _ => None,
    })
}

/// Ikeda's input of a section hull in water of density `rho` (module docs).
///
/// # Errors
/// A hull without a rigid roll DOF, a closed (submerged) contour, no waterline, a displaced
/// mass that cannot be computed, or an input Ikeda's formulas refuse (e.g. `sigma > 1` of a
/// flared section, the axis at or below the keel).
pub fn roll_params(hull: &Hull, rho: f64) -> Result<HullRoll, HullDampingError> {
    let Some((dof, reference)) = rigid_dof(hull, RigidKind::Roll) else {
        return Err(HullDampingError::new(
            hull,
            format!(
                "no rigid roll DOF (its DOFs: {}): roll damping needs one",
                hull.dof_names().join(" ")
            ),
        ));
    };
    let [breadth, draft, sigma, bilge_radius] = section_shape(hull)?;
    let (axis_y, axis) = match hull.mass() {
        Some(mass) => (mass.centre_of_gravity[1], RollAxis::CentreOfGravity),
        None => (reference[1], RollAxis::ReferencePoint),
    };
    let params = RollDampingParams {
        // + 0.0: an axis on the waterline is OG = 0, not -0.
        roll_axis_height: -axis_y + 0.0,
        bilge_keels: hull.bilge_keels(),
        rho,
        ..RollDampingParams::new(breadth, draft, sigma, bilge_radius)
    };
    params.validate().map_err(|e| refused(hull, &e))?;
    Ok(HullRoll { params, dof, axis })
}

fn refused(hull: &Hull, e: &ViscousError) -> HullDampingError {
    HullDampingError::new(hull, format!("Ikeda's method refuses {e}"))
}

/// The roll damping components of a section hull at `omega` (rad/s) and amplitude `phi_a`
/// (rad), with the input they were computed from.
///
/// # Errors
/// As [`roll_params`]; a frequency or amplitude that is not finite and positive.
pub fn hull_roll_damping(
    hull: &Hull,
    rho: f64,
    omega: f64,
    phi_a: f64,
) -> Result<(HullRoll, RollDamping), HullDampingError> {
    let roll = roll_params(hull, rho)?;
    let damping = roll_damping(&roll.params, omega, phi_a).map_err(|e| refused(hull, &e))?;
    Ok((roll, damping))
}

/// The uncoupled roll natural frequency (rad/s) of a hull with `<mass>` about its roll
/// reference point (module docs); `None` without `<mass>`, without a roll DOF, or without
/// positive restoring.
pub fn roll_natural_frequency(hull: &Hull, rho: f64, g: f64) -> Option<f64> {
    let (dof, [xp, yp]) = rigid_dof(hull, RigidKind::Roll)?;
    let properties = hull.mass()?.properties(hull, rho).ok()?;
    let statics = crate::hydrostatics::stiffness(hull).ok()?;
    let (m, [xg, yg], k) = (
        properties.mass,
        properties.centre_of_gravity,
        properties.radius_of_gyration,
    );
    let restoring = rho * g * statics.stiffness_per_rho_g[(dof, dof)] - m * g * (yg - yp);
    let inertia = m * (k * k + (xg - xp).powi(2) + (yg - yp).powi(2));
    (restoring > 0.0 && inertia > 0.0).then(|| (restoring / inertia).sqrt())
}

/// The quadratic cross-flow drag of one translation DOF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionDrag {
    /// The hull's DOF.
    pub dof: usize,
    /// Sway or heave.
    pub flow: CrossFlow,
    /// The estimated drag coefficient.
    pub drag_coefficient: f64,
    /// `B_q = 0.5 rho C_D D` (kg/m^2), `D` = T in sway and B in heave.
    pub quadratic: f64,
}

/// The cross-flow drag of every rigid sway and heave DOF of an open section hull.
///
/// # Errors
/// A closed contour or no waterline.
pub fn section_drag(hull: &Hull, rho: f64) -> Result<Vec<SectionDrag>, HullDampingError> {
    let [breadth, draft, _, bilge_radius] = section_shape(hull)?;
    Ok((0..hull.dof_count())
        .filter_map(|dof| match hull.dof_kind(dof) {
            Some(DofKind::Rigid {
                kind: RigidKind::Sway,
                ..
            }) => Some((dof, CrossFlow::Sway, draft)),
            Some(DofKind::Rigid {
                kind: RigidKind::Heave,
                ..
            }) => Some((dof, CrossFlow::Heave, breadth)),
            _ => None,
        })
        .map(|(dof, flow, projected)| {
            let drag_coefficient = cross_flow_drag_coefficient(breadth, draft, bilge_radius, flow);
            SectionDrag {
                dof,
                flow,
                drag_coefficient,
                quadratic: 0.5 * rho * drag_coefficient * projected,
            }
        })
        .collect())
}

/// The viscous damping a section hull gets by default: Ikeda's roll damping (when it has a roll
/// DOF) at `omega` and `phi_a`, and the cross-flow drag of its sway and heave DOFs.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionEstimate {
    /// The roll input and components, if the hull has a roll DOF.
    pub roll: Option<(HullRoll, RollDamping)>,
    /// The drag of the sway and heave DOFs.
    pub drag: Vec<SectionDrag>,
}

/// [`SectionEstimate`] of `hull` in water of density `rho`.
///
/// # Errors
/// As [`section_drag`], and as [`hull_roll_damping`] for a hull with a roll DOF.
pub fn section_estimate(
    hull: &Hull,
    rho: f64,
    omega: f64,
    phi_a: f64,
) -> Result<SectionEstimate, HullDampingError> {
    let drag = section_drag(hull, rho)?;
    let roll = match rigid_dof(hull, RigidKind::Roll) {
        Some(_) => Some(hull_roll_damping(hull, rho, omega, phi_a)?),
        None => None,
    };
    Ok(SectionEstimate { roll, drag })
}

#[cfg(test)]
mod tests;
