//! Linear hydrostatic restoring of every DOF of a hull section, per unit length.
//!
//! Conventions (docs/DESIGN.md): y up, mean free surface y = 0, fluid below; the contour runs with
//! the body on its left, `n = (-t_y, t_x)` points out of the fluid into the body; a DOF is a
//! displacement field `u_j(s)` on the contour and its generalized force is
//! `F_i = integral_C p n . u_i ds`, with the hydrostatic pressure `p0 = -rho g y`.
//!
//! # Rigid DOFs: closed forms of the true rigid motion (buoyancy only)
//! With the waterline from `x_l` to `x_r` (breadth `B`), the submerged area `A` with centroid
//! `(x_B, y_B)`, and roll about the DOF's reference point `(x_c, y_c)`:
//!
//! ```text
//! C(heave, heave) = rho g B
//! C(heave, roll)  = C(roll, heave) = rho g integral_wl (x - x_c) dx
//! C(roll, roll)   = rho g [ integral_wl (x - x_c)^2 dx + A (y_B - y_c) ]
//! C(sway, .)      = C(., sway) = 0
//! ```
//!
//! (about the origin: `rho g (I_wp + A z_B)`). A closed, fully submerged contour has no
//! waterline: only `rho g A (y_B - y_c)` remains, in roll.
//!
//! # Elastic DOFs: the pressure stiffness of the displacement fields
//! Every entry with an elastic DOF (a Craig-Bampton mode or a file's mode) is the linearized
//! change of `F_i` when the contour moves by `q_j u_j`: the pressure at the displaced point
//! changes by `-rho g (u_j)_y q_j`, and the surface element `n ds = R90 dx` turns and
//! stretches by `R90 (du_j/ds) ds q_j`, `R90 (a, b) = (-b, a)`:
//!
//! ```text
//! C_ij = -dF_i/dq_j = rho g integral_C [ (u_j)_y (n . u_i) + y (R90 du_j/ds) . u_i ] ds
//! ```
//!
//! The moving waterline adds only at second order (the pressure vanishes there). The formula
//! needs both components of `u_j` on the contour; a hull file's mode given by its normal
//! component only has zero tangential displacement (docs/HULL_FORMAT.md). `C` need not be
//! symmetric for elastic DOFs.
//!
//! # What the structural model adds
//! Applied to the linear field of a rigid roll, the formula gives `rho g (I_wp - 2 A y_B)`
//! about the origin (any reference point: the same), not the rigid value: the difference
//! `rho g A (3 y_B - y_c)` is the work of the static pressure load through the second-order
//! displacement of a true rotation. For an elastic hull it is supplied by the initial-stress
//! (geometric) stiffness of the shell pre-loaded by the static pressure, which belongs to the
//! structural model; so does the weight's own restoring `-m g z_G`. The heave and sway
//! entries carry no such term. docs/HYDROSTATICS.md gives the numbers.

use crate::hull::{DofKind, Hull, RigidKind};
use nalgebra::DMatrix;
use std::fmt;

/// Sub-intervals per arc contour for the Gauss quadrature (8 points each).
const ARC_INTERVALS: usize = 64;
/// Step in the contour parameter for the derivative of a smooth (arc) displacement field.
const DERIVATIVE_STEP: f64 = 1e-4;

/// 8-point Gauss-Legendre nodes and weights on [-1, 1].
const GAUSS: [(f64, f64); 8] = crate::numerics::GAUSS_LEGENDRE_8;

/// The hydrostatic restoring of a hull, per `rho g`.
#[derive(Clone, Debug, PartialEq)]
pub struct Hydrostatics {
    /// `C / (rho g)` for the DOFs in the hull's order: multiply by `rho g` for the restoring
    /// force per unit length per unit generalized coordinate (m, m^2, m^3 for
    /// `e_i + e_j = 0, 1, 2`, like `added_mass_inf` per `rho`).
    pub stiffness_per_rho_g: DMatrix<f64>,
    /// Waterline breadth B (m; 0 for a closed contour).
    pub waterline_breadth: f64,
    /// Submerged area A (m^2).
    pub submerged_area: f64,
    /// Centroid of the submerged area (m).
    pub centre_of_buoyancy: [f64; 2],
}

impl Hydrostatics {
    /// The restoring matrix `C` in SI for water density `rho` and gravity `g`.
    pub fn stiffness(&self, rho: f64, g: f64) -> DMatrix<f64> {
        &self.stiffness_per_rho_g * (rho * g)
    }
}

/// Why the restoring could not be computed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum HydrostaticsError {
    /// An entry came out NaN or infinite (for example from a degenerate contour).
    NonFinite {
        /// The hull.
        hull: String,
        /// DOF names of the entry.
        entry: (String, String),
    },
}

impl fmt::Display for HydrostaticsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HydrostaticsError::NonFinite { hull, entry } => write!(
                f,
                "hydrostatics of hull '{hull}': the restoring {}-{} is not finite",
                entry.0, entry.1
            ),
        }
    }
}

impl std::error::Error for HydrostaticsError {}

/// The linear hydrostatic restoring of every DOF of `hull` (see the module docs).
///
/// # Errors
/// A non-finite entry.
pub fn stiffness(hull: &Hull) -> Result<Hydrostatics, HydrostaticsError> {
    let n = hull.dof_count();
    let section = Section::of(hull);
    let mut matrix = DMatrix::zeros(n, n);
    let rigid = |j: usize| match hull.dof_kind(j) {
        Some(DofKind::Rigid { kind, reference }) => Some((kind, reference)),
        _ => None,
    };
    for i in 0..n {
        for j in 0..n {
            matrix[(i, j)] = match (rigid(i), rigid(j)) {
                (Some(a), Some(b)) => section.rigid(a, b),
                _ => pressure_stiffness(hull, i, j),
            };
        }
    }
    let names = hull.dof_names();
    if let Some(k) = matrix.iter().position(|c| !c.is_finite()) {
        return Err(HydrostaticsError::NonFinite {
            hull: hull.name().to_string(),
            entry: (names[k % n].to_string(), names[k / n].to_string()),
        });
    }
    Ok(Hydrostatics {
        stiffness_per_rho_g: matrix,
        waterline_breadth: section.breadth,
        submerged_area: section.area,
        centre_of_buoyancy: section.centroid,
    })
}

/// Waterline and submerged area of a section.
struct Section {
    /// Left and right waterline x (equal for a closed contour).
    waterline: (f64, f64),
    breadth: f64,
    area: f64,
    centroid: [f64; 2],
}

impl Section {
    /// By Green's theorem along the contour (the waterline closure adds nothing):
    /// `A = integral_C x dy`, `A x_B = integral_C x^2/2 dy`, `A y_B = -integral_C y^2/2 dx`.
    fn of(hull: &Hull) -> Section {
        let (mut area, mut moment_x, mut moment_y) = (0.0, 0.0, 0.0);
        for (s, ds) in quadrature(hull) {
            let (x, t) = (hull.point(s), hull.tangent(s));
            area += x[0] * t[1] * ds;
            moment_x += 0.5 * x[0] * x[0] * t[1] * ds;
            moment_y -= 0.5 * x[1] * x[1] * t[0] * ds;
        }
        let (left, right) = if hull.is_closed() {
            (0.0, 0.0)
        } else {
            (hull.point(0.0)[0], hull.point(1.0)[0])
        };
        Section {
            waterline: (left, right),
            breadth: right - left,
            area,
            centroid: [moment_x / area, moment_y / area],
        }
    }

    /// `integral_wl (x - c)^power dx`.
    fn waterline_moment(&self, c: f64, power: i32) -> f64 {
        let (l, r) = self.waterline;
        let p = f64::from(power + 1);
        ((r - c).powi(power + 1) - (l - c).powi(power + 1)) / p
    }

    /// The closed-form rigid entry (row `a`, column `b`) per `rho g`.
    fn rigid(&self, a: (RigidKind, [f64; 2]), b: (RigidKind, [f64; 2])) -> f64 {
        use RigidKind::{Heave, Roll, Sway};
        match (a.0, b.0) {
            (Sway, _) | (_, Sway) => 0.0,
            (Heave, Heave) => self.breadth,
            (Heave, Roll) => self.waterline_moment(b.1[0], 1),
            (Roll, Heave) => self.waterline_moment(a.1[0], 1),
            (Roll, Roll) if a.1 == b.1 => {
                let c = a.1;
                self.waterline_moment(c[0], 2) + self.area * (self.centroid[1] - c[1])
            }
            // Two rolls about different points c1 (row) and c2 (column): the field of roll
            // about c2 is roll about c1 plus (y2 - y1) sway + (x1 - x2) heave, and the entry
            // is that combination of the row's entries (sway's is 0).
            (Roll, Roll) => {
                let (c1, c2) = (a.1, b.1);
                self.rigid(a, a) + (c1[0] - c2[0]) * self.waterline_moment(c1[0], 1)
            }
        }
    }
}

/// Whether the contour is smooth (the built-in circles and Lewis forms) rather than a polyline.
fn is_arc(hull: &Hull) -> bool {
    hull.breakpoints().len() == 2
}

/// The intervals of the contour parameter the quadrature runs over: each polyline segment
/// (integrands are polynomials there), or [`ARC_INTERVALS`] equal parts of an arc.
fn intervals(hull: &Hull) -> Vec<(f64, f64)> {
    if is_arc(hull) {
        (0..ARC_INTERVALS)
            .map(|k| {
                (
                    k as f64 / ARC_INTERVALS as f64,
                    (k + 1) as f64 / ARC_INTERVALS as f64,
                )
            })
            .collect()
    } else {
        hull.breakpoints()
            .windows(2)
            .map(|w| (w[0], w[1]))
            .collect()
    }
}

/// Gauss nodes `(s, ds)` along the whole contour, `ds` in metres of arc length.
fn quadrature(hull: &Hull) -> Vec<(f64, f64)> {
    let length = hull.contour_length();
    intervals(hull)
        .into_iter()
        .flat_map(|(a, b)| {
            GAUSS.map(|(t, w)| (a + 0.5 * (b - a) * (1.0 + t), 0.5 * (b - a) * length * w))
        })
        .collect()
}

/// The pressure stiffness entry (row `i`, column `j`) per `rho g` (module docs).
fn pressure_stiffness(hull: &Hull, i: usize, j: usize) -> f64 {
    let length = hull.contour_length();
    let arc = is_arc(hull);
    let mut total = 0.0;
    for (a, b) in intervals(hull) {
        // d u_j / d(arc length): exact on a straight segment (the field is linear there),
        // fourth-order central differences on a smooth arc.
        let segment_slope = (!arc).then(|| {
            let (ua, ub) = (hull.displacement(j, a), hull.displacement(j, b));
            let l = (b - a) * length;
            [(ub[0] - ua[0]) / l, (ub[1] - ua[1]) / l]
        });
        for (t, w) in GAUSS {
            let s = a + 0.5 * (b - a) * (1.0 + t);
            let ds = 0.5 * (b - a) * length * w;
            let (x, n) = (hull.point(s), hull.normal(s));
            let (ui, uj) = (hull.displacement(i, s), hull.displacement(j, s));
            let slope = segment_slope.unwrap_or_else(|| {
                let h = DERIVATIVE_STEP;
                let at = |d: f64| hull.displacement(j, s + d);
                let (p1, m1, p2, m2) = (at(h), at(-h), at(2.0 * h), at(-2.0 * h));
                let d = |k: usize| (8.0 * (p1[k] - m1[k]) - (p2[k] - m2[k])) / (12.0 * h * length);
                [d(0), d(1)]
            });
            let rotated = [-slope[1], slope[0]];
            let normal_i = n[0] * ui[0] + n[1] * ui[1];
            total += (uj[1] * normal_i + x[1] * (rotated[0] * ui[0] + rotated[1] * ui[1])) * ds;
        }
    }
    total
}

mod table;
pub use table::Table;

#[cfg(test)]
mod tests;
