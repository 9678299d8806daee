//! Hull geometry: the wetted contour of a 2D section and its generalized degrees of freedom.
//!
//! # Conventions
//! x to the right, **y up**, mean free surface y = 0, fluid in y < 0, SI units (metres).
//! The contour is parametrized by `s` in [0, 1], proportional to arc length. It runs
//!
//! * **open** (partially submerged): from the LEFT waterline (s = 0) to the RIGHT waterline
//!   (s = 1), both ends on y = 0, everything in between strictly below y = 0;
//! * **closed** (fully submerged): once around the body, s = 1 back at the start point;
//!
//! always with the body on the LEFT of the direction of travel and the fluid on the right
//! (counter-clockwise around the body). With unit tangent t = dP/ds / |dP/ds| the unit normal
//! n = (-t_y, t_x) points out of the fluid, into the body.
//!
//! Each degree of freedom (DOF) j is a displacement field d_j(s) along the contour; the body
//! condition of the radiation problem uses its normal component n · d_j.
//!
//! * rigid `sway`: d = (1, 0); `heave`: d = (0, 1); `roll` (counter-clockwise about a reference
//!   point (x_r, y_r), for built-ins the origin on the free surface): d = (-(y - y_r), x - x_r);
//! * elastic, from a hull file: displacement vectors given at the contour points, linearly
//!   interpolated in s between them;
//! * elastic, built-in semicircle: the six Craig-Bampton modes `cb1..cb6` of a thin
//!   semicircular beam (`craig_bampton.rs`).
//!
//! # Limits
//! A hull must give meaningful numbers in double precision. The results are products of up
//! to four lengths (the added mass scales as `R^2` and as the square of a mode, the exciting
//! force as `R^(1 + e_j)`, the pressure stiffness as a mode squared), so every length stays
//! within [[`MIN_LENGTH`], [`MAX_LENGTH`]] = [1e-6, 1e6] m: the half-beam, a circle's radius
//! and depth, the section's size (the largest side of its bounding box), every coordinate
//! and reference point, every mode component, and each mode's largest displacement
//! component. Their products then stay within 1e-24 .. 1e24, where 1e154 squared would
//! overflow and 1e-160 squared underflow to zero. The half-beam, which only makes the results
//! nondimensional, lies within a factor [`MAX_HALF_BEAM_RATIO`] of the section's size either
//! way. A hull has at most [`MAX_DOFS`] DOFs: the sweep's matrices grow with their square and
//! the network fit with their cube; a contour at most [`MAX_CONTOUR_POINTS`] points.
//!
//! # Where things are
//! * `builtin.rs`: [`Hull::semicircle`] and [`Hull::circle`], exact arcs with analytic fields,
//!   and [`Hull::lewis`], the Lewis form of a ship section (`lewis.rs`);
//! * `craig_bampton.rs`: the thin-beam modes of the semicircle (seed eqs. 4-6);
//! * `file.rs`: hull files (`docs/HULL_FORMAT.md`) read with [`crate::xml`] and written back;
//!   `mass.rs` and `keels.rs` their `<mass>` and `<bilge_keels>` elements;
//! * `validate.rs`: the geometric checks of a file's contour (waterline, self-contact,
//!   orientation) and its arc-length knots.

mod builtin;
mod contact;
mod craig_bampton;
mod file;
pub(crate) use file::{valid_dof_name, valid_hull_name};
mod keels;
mod lewis;
mod mass;
pub use mass::{HullMass, Mooring, SectionMass};
mod units;
mod validate;

pub(crate) use craig_bampton::{craig_bampton_coefficients, craig_bampton_displacement};

use std::f64::consts::PI;

/// A point or vector in the section plane, `[x, y]` in metres.
pub type Point = [f64; 2];

/// Smallest length a hull may state, in metres: the half-beam, a circle's radius, the
/// section's size, and each mode's largest displacement (see the module docs, "Limits").
pub const MIN_LENGTH: f64 = 1e-6;

/// Largest magnitude of any length or coordinate of a hull, in metres (module docs, "Limits").
pub const MAX_LENGTH: f64 = 1e6;

/// The half-beam lies within this factor of the section's size, either way.
pub const MAX_HALF_BEAM_RATIO: f64 = 1e3;

/// Most DOFs of a hull.
pub const MAX_DOFS: usize = 256;

/// Most points of a `<contour>`: every point becomes a panel node, so a contour with more
/// points than [`crate::panels::MAX_BODY_PANELS`] could never be swept. The contour checks are
/// linear in the points (a grid, `contact.rs`; every pair of segments took minutes for
/// 40,000 points before) and bounded by this limit in the worst case.
pub const MAX_CONTOUR_POINTS: usize = crate::panels::MAX_BODY_PANELS;

/// A number as messages print it (plain digits, or an exponent far from 1).
fn plain(x: f64) -> String {
    crate::xml::format_number(x, crate::xml::Notation::Plain)
}

/// Checks that `value` (metres) lies within [[`MIN_LENGTH`], [`MAX_LENGTH`]]; the message
/// names `what`.
fn check_length(what: &str, value: f64) -> Result<(), String> {
    if (MIN_LENGTH..=MAX_LENGTH).contains(&value) {
        Ok(())
    } else {
        Err(format!(
            "{what} = {} m is outside [{}, {}] m, the lengths that give meaningful numbers",
            plain(value),
            plain(MIN_LENGTH),
            plain(MAX_LENGTH)
        ))
    }
}

/// Checks that every component of `p` (metres) has a magnitude of at most [`MAX_LENGTH`].
fn check_coordinates(what: &str, p: Point) -> Result<(), String> {
    if p.iter().all(|c| c.abs() <= MAX_LENGTH) {
        Ok(())
    } else {
        Err(format!(
            "{what} ({}, {}) has a component beyond {} m in magnitude, past the lengths that give \
             meaningful numbers",
            plain(p[0]),
            plain(p[1]),
            plain(MAX_LENGTH)
        ))
    }
}

/// Checks that `half_beam` lies within [`MAX_HALF_BEAM_RATIO`] of the section's `size`.
fn check_half_beam_ratio(half_beam: f64, size: f64) -> Result<(), String> {
    if half_beam <= size * MAX_HALF_BEAM_RATIO && half_beam * MAX_HALF_BEAM_RATIO >= size {
        Ok(())
    } else {
        Err(format!(
            "half_beam = {} m is more than {} times larger or smaller than the section's size \
             {} m (the largest side of its bounding box); R only makes the results \
             nondimensional, usually half the waterline beam",
            plain(half_beam),
            plain(MAX_HALF_BEAM_RATIO),
            plain(size)
        ))
    }
}

/// Why a hull could not be built: the source (file name, or built-in / hull name), the line
/// when it came from a file, and the problem.
pub type HullError = crate::input::FileError;

/// The three rigid motions of a 2D section.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RigidKind {
    /// Translation in +x.
    Sway,
    /// Translation in +y.
    Heave,
    /// Counter-clockwise rotation about the reference point.
    Roll,
}

impl RigidKind {
    /// The word used in hull files: `sway`, `heave`, `roll`.
    pub fn as_str(self) -> &'static str {
        match self {
            RigidKind::Sway => "sway",
            RigidKind::Heave => "heave",
            RigidKind::Roll => "roll",
        }
    }

    fn parse(word: &str) -> Option<RigidKind> {
        match word {
            "sway" => Some(RigidKind::Sway),
            "heave" => Some(RigidKind::Heave),
            "roll" => Some(RigidKind::Roll),
            _ => None,
        }
    }
}

/// What kind of displacement field a DOF has.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DofKind {
    /// Rigid motion.
    Rigid {
        /// Sway, heave or roll.
        kind: RigidKind,
        /// Centre of rotation for roll (kept, without effect, for sway and heave).
        reference: Point,
    },
    /// Craig-Bampton mode of the built-in semicircular beam.
    CraigBampton {
        /// 1..=6: unit u(0), w(0), psi(0), u(pi), w(pi), psi(pi).
        mode: usize,
    },
    /// Elastic mode given as displacement vectors at the contour points.
    Elastic,
}

#[derive(Clone, Debug)]
enum Field {
    Rigid { kind: RigidKind, reference: Point },
    CraigBampton { mode: usize, coefficients: [f64; 6] },
    Vectors(Vec<Point>),
}

#[derive(Clone, Debug)]
struct Dof {
    name: String,
    field: Field,
}

#[derive(Clone, Debug)]
enum Contour {
    /// depth == 0: semicircle (open, theta = pi s); depth > radius: full circle (theta = 2 pi s).
    /// `depth_ratio`: the centre depth over the reference half-beam, as given (H/R).
    Arc {
        radius: f64,
        depth: f64,
        depth_ratio: f64,
    },
    /// The Lewis form of a ship section (open, `lewis.rs`).
    Lewis(lewis::LewisForm),
    /// `knots[i]`: s at vertex i; closed contours have one more knot (1.0, back at vertex 0).
    Polyline {
        points: Vec<Point>,
        closed: bool,
        knots: Vec<f64>,
        length: f64,
    },
}

/// The wetted contour of a 2D hull section and its generalized DOFs (see the module docs).
#[derive(Clone, Debug)]
pub struct Hull {
    name: String,
    half_beam: f64,
    contour: Contour,
    dofs: Vec<Dof>,
    notes: Vec<String>,
    /// The file's `<mass>`: the section floats (absent: held fixed).
    mass: Option<HullMass>,
    /// The file's `<bilge_keels>` (viscous roll damping only).
    bilge_keels: Option<crate::viscous::BilgeKeels>,
    /// The file's `depth` attribute: the water depth (m), `None` for deep water.
    water_depth: Option<f64>,
}

fn rigid_displacement(kind: RigidKind, reference: Point, p: Point) -> Point {
    match kind {
        RigidKind::Sway => [1.0, 0.0],
        RigidKind::Heave => [0.0, 1.0],
        RigidKind::Roll => [-(p[1] - reference[1]), p[0] - reference[0]],
    }
}

impl Hull {
    /// "semicircle", "circle", or the `name` attribute of the file.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Reference half-beam R used to make coefficients nondimensional (kR, A / (rho pi R^2)).
    pub fn reference_half_beam(&self) -> f64 {
        self.half_beam
    }

    /// True for a fully submerged body (contour closed around it).
    pub fn is_closed(&self) -> bool {
        match &self.contour {
            Contour::Arc { depth, .. } => *depth > 0.0,
            Contour::Lewis(_) => false,
            Contour::Polyline { closed, .. } => *closed,
        }
    }

    /// The mass properties of the hull file's `<mass>` element, if it has one: with them the
    /// section floats ([`HullMass::properties`], [`crate::motion`]).
    pub fn mass(&self) -> Option<&HullMass> {
        self.mass.as_ref()
    }

    /// The bilge keels of the hull file's `<bilge_keels>` element, if it has one: they enter
    /// only the viscous roll damping estimate ([`crate::viscous::hull_roll_damping`]).
    pub fn bilge_keels(&self) -> Option<crate::viscous::BilgeKeels> {
        self.bilge_keels
    }

    /// The water depth of the hull file's `depth` attribute (deep water without one).
    pub fn water_depth(&self) -> crate::units::WaterDepth {
        self.water_depth.map_or(
            crate::units::WaterDepth::Infinite,
            crate::units::WaterDepth::Finite,
        )
    }

    /// This hull with the DOFs `dofs` (a subset of its own); the moorings of DOFs left out go.
    fn with_dofs(&self, dofs: Vec<Dof>) -> Hull {
        let mass = self.mass.as_ref().map(|m| HullMass {
            mooring: m
                .mooring
                .iter()
                .filter(|r| dofs.iter().any(|d| d.name == r.dof))
                .cloned()
                .collect(),
            ..m.clone()
        });
        Hull {
            dofs,
            mass,
            ..self.clone()
        }
    }

    /// Names of the DOFs, in order.
    pub fn dof_names(&self) -> Vec<&str> {
        self.dofs.iter().map(|d| d.name.as_str()).collect()
    }

    /// Number of DOFs.
    pub fn dof_count(&self) -> usize {
        self.dofs.len()
    }

    /// The kind of DOF `dof`, or `None` if out of range.
    pub fn dof_kind(&self, dof: usize) -> Option<DofKind> {
        self.dofs.get(dof).map(|d| match &d.field {
            Field::Rigid { kind, reference } => DofKind::Rigid {
                kind: *kind,
                reference: *reference,
            },
            Field::CraigBampton { mode, .. } => DofKind::CraigBampton { mode: *mode },
            Field::Vectors(_) => DofKind::Elastic,
        })
    }

    /// Notes on corrections made while reading (e.g. a reversed contour); empty for built-ins.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// The section as a ship's strip sees it: rigid `sway`, `heave` and `roll` about the origin
    /// (the ship's centreline on the free surface), then the elastic DOFs named in `elastic`,
    /// in that order. The hull's own rigid DOFs are replaced.
    ///
    /// # Errors
    /// A name in `elastic` that is not an elastic DOF of the hull, or repeated.
    pub fn ship_section(&self, elastic: &[&str]) -> Result<Hull, HullError> {
        let origin = [0.0, 0.0];
        let mut dofs: Vec<Dof> = [RigidKind::Sway, RigidKind::Heave, RigidKind::Roll]
            .into_iter()
            .map(|kind| Dof {
                name: kind.as_str().to_string(),
                field: Field::Rigid {
                    kind,
                    reference: origin,
                },
            })
            .collect();
        for (k, name) in elastic.iter().enumerate() {
            let found = self
                .dofs
                .iter()
                .find(|d| d.name == *name && !matches!(d.field, Field::Rigid { .. }));
            match found {
                Some(d) if !elastic[..k].contains(name) => dofs.push(d.clone()),
                _ => {
                    let available: Vec<&str> = self
                        .dofs
                        .iter()
                        .filter(|d| !matches!(d.field, Field::Rigid { .. }))
                        .map(|d| d.name.as_str())
                        .collect();
                    return Err(HullError::new(
                        &self.name,
                        None,
                        format!(
                            "'{name}' is not an elastic DOF of the section (or is named twice); \
                             its elastic DOFs: {}",
                            if available.is_empty() {
                                "none".to_string()
                            } else {
                                available.join(" ")
                            }
                        ),
                    ));
                }
            }
        }
        Ok(self.with_dofs(dofs))
    }

    /// A hull with only the DOFs named, in the order given. An unknown or repeated name, or an
    /// empty list, is an error that lists the available names.
    pub fn select_dofs(&self, names: &[&str]) -> Result<Hull, HullError> {
        let available = self.dof_names().join(" ");
        if names.is_empty() {
            return Err(HullError::new(
                &self.name,
                None,
                format!("no DOFs selected; available: {available}"),
            ));
        }
        let mut dofs = Vec::with_capacity(names.len());
        for (k, name) in names.iter().enumerate() {
            if names[..k].contains(name) {
                return Err(HullError::new(
                    &self.name,
                    None,
                    format!("DOF '{name}' selected twice; available: {available}"),
                ));
            }
            match self.dofs.iter().find(|d| d.name == *name) {
                Some(d) => dofs.push(d.clone()),
                None => {
                    return Err(HullError::new(
                        &self.name,
                        None,
                        format!("unknown DOF '{name}'; available: {available}"),
                    ))
                }
            }
        }
        Ok(self.with_dofs(dofs))
    }

    /// Total arc length of the contour (closed: once around), metres.
    pub fn contour_length(&self) -> f64 {
        match &self.contour {
            Contour::Arc { radius, depth, .. } if *depth > 0.0 => 2.0 * PI * radius,
            Contour::Arc { radius, .. } => PI * radius,
            Contour::Lewis(form) => form.length,
            Contour::Polyline { length, .. } => *length,
        }
    }

    /// Contour point at parameter `s` in [0, 1] (clamped), s proportional to arc length.
    pub fn point(&self, s: f64) -> Point {
        let s = s.clamp(0.0, 1.0);
        match &self.contour {
            Contour::Arc { radius, depth, .. } => {
                let (sn, cs) = arc_sin_cos(*depth, s);
                [-radius * cs, -depth - radius * sn]
            }
            Contour::Lewis(form) => form.point(s),
            Contour::Polyline { points, knots, .. } => {
                let (i, j, t) = locate(knots, points.len(), s);
                lerp(points[i], points[j], t)
            }
        }
    }

    /// Unit tangent (direction of increasing s) at `s`. On a polyline vertex the tangent of the
    /// segment towards increasing s is returned (towards decreasing s at s = 1).
    pub fn tangent(&self, s: f64) -> Point {
        let s = s.clamp(0.0, 1.0);
        match &self.contour {
            Contour::Arc { depth, .. } => {
                let (sn, cs) = arc_sin_cos(*depth, s);
                [sn, -cs]
            }
            Contour::Lewis(form) => form.tangent(s),
            Contour::Polyline { points, knots, .. } => {
                let (i, j, _) = locate(knots, points.len(), s);
                let d = [points[j][0] - points[i][0], points[j][1] - points[i][1]];
                let l = d[0].hypot(d[1]);
                [d[0] / l, d[1] / l]
            }
        }
    }

    /// Unit normal n = (-t_y, t_x) at `s`: out of the fluid, into the body.
    pub fn normal(&self, s: f64) -> Point {
        let t = self.tangent(s);
        [-t[1], t[0]]
    }

    /// Displacement field of DOF `dof` (index into [`Hull::dof_names`]) at `s`;
    /// `[NaN, NaN]` if `dof` is out of range.
    pub fn displacement(&self, dof: usize, s: f64) -> [f64; 2] {
        let Some(d) = self.dofs.get(dof) else {
            return [f64::NAN; 2];
        };
        let s = s.clamp(0.0, 1.0);
        match (&d.field, &self.contour) {
            (Field::Rigid { kind, reference }, _) => {
                rigid_displacement(*kind, *reference, self.point(s))
            }
            (Field::CraigBampton { coefficients, .. }, Contour::Arc { radius, .. }) => {
                craig_bampton_displacement(coefficients, *radius, PI * s)
            }
            (Field::Vectors(v), Contour::Polyline { points, knots, .. }) => {
                let (i, j, t) = locate(knots, points.len(), s);
                lerp(v[i], v[j], t)
            }
            // Not constructible: checked when the hull is built.
            _ => [f64::NAN; 2],
        }
    }

    /// Normal component n · d of DOF `dof` at `s` (the body boundary condition).
    pub fn normal_displacement(&self, dof: usize, s: f64) -> f64 {
        let n = self.normal(s);
        let d = self.displacement(dof, s);
        n[0] * d[0] + n[1] * d[1]
    }

    /// Parameters of contour vertices where panel nodes must fall, ascending, from 0 to 1:
    /// `[0.0, 1.0]` for the smooth built-ins; every point of a file's contour (the geometry
    /// and the mode vectors have kinks there), plus 1.0 for a closed contour.
    pub fn breakpoints(&self) -> Vec<f64> {
        match &self.contour {
            Contour::Arc { .. } | Contour::Lewis(_) => vec![0.0, 1.0],
            Contour::Polyline { knots, .. } => knots.clone(),
        }
    }
}

/// (sin theta, cos theta) of the arc angle at s (theta = pi s, or 2 pi s for a closed circle),
/// evaluated from the nearer end so that the end points are exact: the semicircle ends on
/// y = 0 and the circle closes on its start point.
fn arc_sin_cos(depth: f64, s: f64) -> (f64, f64) {
    if depth > 0.0 {
        let s = if s >= 1.0 { 0.0 } else { s };
        if s <= 0.5 {
            (2.0 * PI * s).sin_cos()
        } else {
            let (sn, cs) = (2.0 * PI * (1.0 - s)).sin_cos();
            (-sn, cs)
        }
    } else if s <= 0.5 {
        (PI * s).sin_cos()
    } else {
        let (sn, cs) = (PI * (1.0 - s)).sin_cos();
        (sn, -cs)
    }
}

/// Segment (vertex i, vertex j) containing s and the local parameter t in [0, 1].
fn locate(knots: &[f64], vertices: usize, s: f64) -> (usize, usize, f64) {
    let segments = knots.len() - 1;
    let i = knots
        .partition_point(|&k| k <= s)
        .saturating_sub(1)
        .min(segments - 1);
    let t = (s - knots[i]) / (knots[i + 1] - knots[i]);
    (i, (i + 1) % vertices, t)
}

fn lerp(a: Point, b: Point, t: f64) -> Point {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// Hull-file text of a Wigley section (tests): half-breadth `b (1 - (z / T)^2)` through
/// `per_side` points on each side, keel point shared, with the DOFs `sway heave roll`.
#[cfg(test)]
pub(crate) fn wigley_section_xml(
    name: &str,
    half_beam: f64,
    draft: f64,
    per_side: usize,
) -> String {
    let side = |k: usize| {
        let z = draft * k as f64 / (per_side - 1) as f64;
        (half_beam * (1.0 - (z / draft).powi(2)), -z)
    };
    let mut text =
        format!("<hull name=\"{name}\" half_beam=\"{half_beam}\"><contour closed=\"false\">");
    // The port side down to the keel, then starboard back up.
    for (i, k) in (0..per_side).chain((0..per_side - 1).rev()).enumerate() {
        let (x, y) = side(k);
        let x = if i < per_side { -x } else { x };
        text.push_str(&format!("<point x=\"{x}\" y=\"{y}\"/>"));
    }
    text.push_str("</contour><rigid name=\"sway\" kind=\"sway\"/>");
    text.push_str(
        "<rigid name=\"heave\" kind=\"heave\"/><rigid name=\"roll\" kind=\"roll\"/></hull>",
    );
    text
}

#[cfg(test)]
mod tests;
