//! Discretization of a hull's wetted contour into straight source panels.
//!
//! Panel `l` runs from `start` to `end` (body on its left, fluid on its right), with centre
//! `x_l`, length `L_l` and unit normal `n_l = (-t_y, t_x)` pointing out of the fluid into the
//! body. The normal velocity of DOF `j` at panel `l` is the normal component of the DOF's
//! displacement field at the panel centre,
//!
//! ```text
//! n_j(x_l) = u_j(s_l) . n_l
//! ```
//!
//! so that the body condition of the radiation problem reads `d(phi_j)/dn = n_j`.
//!
//! Open contours (partially submerged hulls) are clustered toward the two waterline corners,
//! where the potential is least smooth and the error of constant-strength panels concentrates:
//! node parameters blend a uniform and a cosine spacing,
//!
//! ```text
//! s_i = (1 - beta) i/N + beta (1 - cos(pi i / N)) / 2,   i = 0..N,
//! ```
//!
//! with `beta` = [`PanelParams::clustering`]. Closed contours (submerged hulls) are spaced
//! uniformly in arc length. Contour vertices of hull files always become panel nodes.
//!
//! For the removal of irregular frequencies, an open contour also gets an interior lid: panels
//! on the free surface `y = 0` between the two waterline points, inside the body, with the
//! same clustering toward the corners.

use crate::hull::Hull;
use crate::xml::{format_number, Notation};
use nalgebra::DMatrix;
use std::fmt;

/// A point `[x, y]` in metres.
pub type Point = [f64; 2];

/// Tuning parameters of the discretization.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PanelParams {
    /// Number of panels on the wetted contour. Default 128; at least 4.
    pub body_panels: usize,
    /// Blend between uniform (0) and cosine (1) spacing toward the waterline corners of open
    /// contours. Default 0.5.
    pub clustering: f64,
    /// Lid panels per body panel length: the lid gets
    /// `ceil(lid_density * beam / mean body panel length)` panels (at least 4). Default 0.5:
    /// the lid only has to remove the interior resonances; finer lids cost time without
    /// changing the result beyond the discretization error (docs/VALIDATION.md).
    pub lid_density: f64,
}

impl Default for PanelParams {
    fn default() -> Self {
        Self {
            body_panels: 128,
            clustering: 0.5,
            lid_density: 0.5,
        }
    }
}

impl PanelParams {
    /// The default parameters for `hull`: [`PanelParams::default`], with more panels for a
    /// closed contour close to the free surface, so that the panels at its top are no longer
    /// than [`GAP_FRACTION`] of the gap `d` between the top and the surface:
    /// `N >= perimeter (1 - clustering) / (GAP_FRACTION d)`, rounded up to a multiple of 4 (the
    /// extrapolation halves N twice).
    pub fn for_hull(hull: &Hull) -> Self {
        let mut params = Self::default();
        if !hull.is_closed() {
            return params;
        }
        const SAMPLES: usize = 1024;
        let points: Vec<Point> = (0..=SAMPLES)
            .map(|i| hull.point(i as f64 / SAMPLES as f64))
            .collect();
        let perimeter: f64 = points
            .windows(2)
            .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
            .sum();
        let gap = -points
            .iter()
            .map(|p| p[1])
            .fold(f64::NEG_INFINITY, f64::max);
        if gap > 0.0 {
            let needed = perimeter * (1.0 - params.clustering) / (GAP_FRACTION * gap);
            let needed = ((needed / 4.0).ceil() as usize).saturating_mul(4);
            params.body_panels = params.body_panels.max(needed.min(MAX_AUTOMATIC_PANELS));
        }
        params
    }
}

/// Largest panel length at the top of a submerged contour, as a fraction of its gap to the
/// free surface, in [`PanelParams::for_hull`].
pub const GAP_FRACTION: f64 = 0.125;

/// Upper bound of the automatic panel count of [`PanelParams::for_hull`].
pub const MAX_AUTOMATIC_PANELS: usize = 1024;

/// Most body panels [`discretize`] accepts. The panel method's system is dense: memory grows
/// as `N^2` and the factorization as `N^3`. Measured for one frequency on one thread
/// (semicircle, no extrapolation, 2 cores): 1024 panels 1.5 s and 0.11 GB, 2048 panels 11 s
/// and 0.43 GB, 4096 panels 43 s and 1.7 GB; 8192 panels therefore need about 7 GB and
/// minutes per frequency and thread, and 16384 about 27 GB, more than the 24 GB machines the
/// project is run on.
pub const MAX_BODY_PANELS: usize = 8192;

/// Most interior lid panels [`discretize`] accepts (they join the body panels in the dense
/// system, see [`MAX_BODY_PANELS`]). The default lid density gives fewer than half as many lid
/// panels as body panels, so only a raised [`PanelParams::lid_density`] can reach it.
pub const MAX_LID_PANELS: usize = 4096;

/// One straight constant-strength source panel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel {
    /// First node.
    pub start: Point,
    /// Second node.
    pub end: Point,
    /// Collocation point: the middle of the panel.
    pub centre: Point,
    /// Length in metres.
    pub length: f64,
    /// Unit normal, out of the fluid into the body.
    pub normal: [f64; 2],
}

impl Panel {
    fn new(start: Point, end: Point) -> Self {
        let dx = end[0] - start[0];
        let dy = end[1] - start[1];
        let length = dx.hypot(dy);
        Self {
            start,
            end,
            centre: [0.5 * (start[0] + end[0]), 0.5 * (start[1] + end[1])],
            length,
            normal: [-dy / length, dx / length],
        }
    }
}

/// The discretized hull: body panels, optional lid panels, and the normal velocity of every
/// DOF at every body panel.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Panels on the wetted contour, in contour order.
    pub body: Vec<Panel>,
    /// Panels of the interior free-surface lid (empty for closed contours).
    pub lid: Vec<Panel>,
    /// `normal_velocity[(l, j)] = n_j(x_l)`: body panel `l`, DOF `j`.
    pub normal_velocity: DMatrix<f64>,
    /// DOF names, in column order.
    pub dof_names: Vec<String>,
    /// Reference half-beam R of the hull.
    pub reference_half_beam: f64,
}

impl Mesh {
    /// The longest body panel, in metres.
    pub fn max_panel_length(&self) -> f64 {
        self.body.iter().map(|p| p.length).fold(0.0, f64::max)
    }

    /// Net flux of each DOF through the contour, `integral n_j ds` (m per unit DOF velocity).
    /// A DOF with nonzero flux has a logarithmically divergent added mass as omega -> 0.
    pub fn net_flux(&self) -> Vec<f64> {
        (0..self.dof_names.len())
            .map(|j| {
                self.body
                    .iter()
                    .enumerate()
                    .map(|(l, p)| self.normal_velocity[(l, j)] * p.length)
                    .sum()
            })
            .collect()
    }

    /// A physics sanity warning when the longest panel is too coarse for the wavelength at
    /// `wavenumber` (fewer than [`PANELS_PER_WAVELENGTH`] panels per wavelength), else `None`.
    pub fn wavelength_warning(&self, wavenumber: f64) -> Option<String> {
        let wavelength = 2.0 * std::f64::consts::PI / wavenumber;
        let longest = self.max_panel_length();
        let per_wavelength = wavelength / longest;
        (per_wavelength < PANELS_PER_WAVELENGTH).then(|| {
            format!(
                "panels too coarse for the wavelength at kR = {:.4}: the longest panel ({:.4} m) \
                 is {:.1} panels per wavelength ({:.4} m), fewer than {}; raise the panel count",
                wavenumber * self.reference_half_beam,
                longest,
                per_wavelength,
                wavelength,
                PANELS_PER_WAVELENGTH
            )
        })
    }
}

/// Fewest panels per wavelength before [`Mesh::wavelength_warning`] warns.
pub const PANELS_PER_WAVELENGTH: f64 = 10.0;

/// Why a hull cannot be discretized.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum PanelError {
    /// Fewer than 4 body panels requested.
    TooFewPanels {
        /// The requested body panel count.
        requested: usize,
    },
    /// More body panels than [`MAX_BODY_PANELS`] requested.
    TooManyPanels {
        /// The requested body panel count.
        requested: usize,
    },
    /// The lid density asks for more lid panels than [`MAX_LID_PANELS`].
    TooManyLidPanels {
        /// The lid panel count the density gives (before rounding, it may exceed any integer).
        requested: f64,
        /// The lid density.
        lid_density: f64,
    },
    /// The clustering parameter lies outside [0, 1].
    Clustering(f64),
    /// The lid density is not finite and positive.
    LidDensity(f64),
    /// Corners of the contour fall between too few panels.
    UnresolvedCorners {
        /// The requested body panel count.
        panels: usize,
        /// The contour's corner count.
        corners: usize,
    },
    /// A panel of zero (or non-finite) length.
    ZeroLengthPanel(usize),
}

impl fmt::Display for PanelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("panel discretization: ")?;
        match self {
            PanelError::TooFewPanels { requested } => {
                write!(f, "{requested} panels requested; at least 4 are needed")
            }
            PanelError::TooManyPanels { requested } => write!(
                f,
                "{requested} panels requested; at most {MAX_BODY_PANELS} (the dense panel system \
                 needs memory growing as N^2 and time as N^3: about 7 GB and minutes per \
                 frequency at the limit)"
            ),
            PanelError::TooManyLidPanels {
                requested,
                lid_density,
            } => write!(
                f,
                "lid density {} gives {} lid panels; at most {MAX_LID_PANELS} (they join the \
                 dense panel system)",
                format_number(*lid_density, Notation::Plain),
                format_number(requested.ceil(), Notation::Plain)
            ),
            PanelError::Clustering(c) => write!(f, "clustering {c} is outside [0, 1]"),
            PanelError::LidDensity(d) => write!(f, "lid density {d} must be positive"),
            PanelError::UnresolvedCorners { panels, corners } => write!(
                f,
                "{panels} panels cannot resolve the hull's {corners} contour corners; raise the panel count"
            ),
            PanelError::ZeroLengthPanel(l) => write!(f, "panel {l} has zero length"),
        }
    }
}

impl std::error::Error for PanelError {}

/// Node parameters in [0, 1], clustered toward both ends when `clustering > 0`.
fn clustered_nodes(count: usize, clustering: f64) -> Vec<f64> {
    (0..=count)
        .map(|i| {
            let u = i as f64 / count as f64;
            let cosine = 0.5 * (1.0 - (std::f64::consts::PI * u).cos());
            (1.0 - clustering) * u + clustering * cosine
        })
        .collect()
}

/// The highest point of a closed contour (closest to the free surface), as a contour
/// parameter.
fn highest_parameter(hull: &Hull) -> f64 {
    const SAMPLES: usize = 4096;
    (0..SAMPLES)
        .map(|i| i as f64 / SAMPLES as f64)
        .max_by(|a, b| hull.point(*a)[1].total_cmp(&hull.point(*b)[1]))
        .unwrap_or(0.0)
}

/// Node positions `t` in [0, 1] of a closed contour, measured from the point opposite its
/// top (contour parameter `s = (t + s_top + 1/2) mod 1`), denser toward the top where the
/// wave interaction varies fastest: `t_i = u + a sin(2 pi u) / (2 pi)`, `u = i/N`, with
/// `a = clustering < 1`, so the panel length scales with `1 + a cos(2 pi u)` and is smallest
/// at the top (u = 1/2). The nodes are symmetric about the top.
fn nodes_toward_the_surface(count: usize, clustering: f64) -> Vec<f64> {
    let a = clustering.min(0.9);
    let two_pi = 2.0 * std::f64::consts::PI;
    (0..=count)
        .map(|i| {
            let u = i as f64 / count as f64;
            if i == 0 || i == count {
                u
            } else {
                u + a * (two_pi * u).sin() / two_pi
            }
        })
        .collect()
}

/// Moves the node nearest to each breakpoint onto it, so contour corners are panel nodes.
fn snap_to_breakpoints(nodes: &mut [f64], breakpoints: &[f64]) {
    for &b in breakpoints {
        if let Some((i, _)) = nodes
            .iter()
            .enumerate()
            .min_by(|a, c| (a.1 - b).abs().total_cmp(&(c.1 - b).abs()))
        {
            nodes[i] = b;
        }
    }
}

/// Discretizes `hull` into panels.
///
/// # Errors
/// Fewer than 4 or more than [`MAX_BODY_PANELS`] body panels, a clustering outside [0, 1], a
/// nonpositive lid density or one that gives more than [`MAX_LID_PANELS`] lid panels, or a
/// contour that degenerates into zero-length panels. The counts are checked before anything
/// is allocated.
pub fn discretize(hull: &Hull, params: &PanelParams) -> Result<Mesh, PanelError> {
    if params.body_panels < 4 {
        return Err(PanelError::TooFewPanels {
            requested: params.body_panels,
        });
    }
    if params.body_panels > MAX_BODY_PANELS {
        return Err(PanelError::TooManyPanels {
            requested: params.body_panels,
        });
    }
    if !(0.0..=1.0).contains(&params.clustering) {
        return Err(PanelError::Clustering(params.clustering));
    }
    if !(params.lid_density.is_finite() && params.lid_density > 0.0) {
        return Err(PanelError::LidDensity(params.lid_density));
    }
    let closed = hull.is_closed();
    // Node positions t are monotone in [0, 1]; `parameter(t)` is the contour parameter.
    let offset = if closed {
        (highest_parameter(hull) + 0.5).fract()
    } else {
        0.0
    };
    let parameter = |t: f64| {
        let s = t + offset;
        if closed && s >= 1.0 {
            s - 1.0
        } else {
            s
        }
    };
    let mut nodes = if closed {
        nodes_toward_the_surface(params.body_panels, params.clustering)
    } else {
        clustered_nodes(params.body_panels, params.clustering)
    };
    let breakpoints = hull.breakpoints();
    // Built-in closed contours are smooth: their parameter ends 0 and 1 are no corners.
    let corners: Vec<f64> = if closed && breakpoints.len() <= 2 {
        Vec::new()
    } else {
        breakpoints
            .iter()
            .map(|b| {
                if closed {
                    (b - offset).rem_euclid(1.0)
                } else {
                    *b
                }
            })
            .collect()
    };
    snap_to_breakpoints(&mut nodes, &corners);
    if closed {
        // A corner snapped onto one end must hold the other end too.
        nodes[0] = 0.0;
        let last = nodes.len() - 1;
        nodes[last] = 1.0;
    }
    if nodes.windows(2).any(|w| w[1] <= w[0]) {
        return Err(PanelError::UnresolvedCorners {
            panels: params.body_panels,
            corners: breakpoints.len(),
        });
    }
    let dof_count = hull.dof_names().len();
    let mut body = Vec::with_capacity(params.body_panels);
    let mut normal_velocity = DMatrix::zeros(params.body_panels, dof_count);
    for (l, w) in nodes.windows(2).enumerate() {
        let panel = Panel::new(hull.point(parameter(w[0])), hull.point(parameter(w[1])));
        if !(panel.length > 0.0 && panel.length.is_finite()) {
            return Err(PanelError::ZeroLengthPanel(l));
        }
        let s_mid = parameter(0.5 * (w[0] + w[1]));
        for j in 0..dof_count {
            let u = hull.displacement(j, s_mid);
            normal_velocity[(l, j)] = u[0] * panel.normal[0] + u[1] * panel.normal[1];
        }
        body.push(panel);
    }
    let lid = if closed {
        Vec::new()
    } else {
        let left = hull.point(0.0);
        let right = hull.point(1.0);
        let beam = (right[0] - left[0]).abs();
        let mean_length = body.iter().map(|p| p.length).sum::<f64>() / body.len() as f64;
        let count = (params.lid_density * beam / mean_length).ceil().max(4.0);
        if count > MAX_LID_PANELS as f64 {
            return Err(PanelError::TooManyLidPanels {
                requested: count,
                lid_density: params.lid_density,
            });
        }
        // An integer from 4 to MAX_LID_PANELS: the conversion is exact.
        let count = count as usize;
        // The lid runs from the right waterline to the left one, so the body (below it, seen
        // from the air) is on its left like every other panel.
        clustered_nodes(count, params.clustering)
            .windows(2)
            .map(|w| {
                let x = |s: f64| right[0] + (left[0] - right[0]) * s;
                Panel::new([x(w[0]), 0.0], [x(w[1]), 0.0])
            })
            .collect()
    };
    Ok(Mesh {
        body,
        lid,
        normal_velocity,
        dof_names: hull.dof_names().iter().map(|s| s.to_string()).collect(),
        reference_half_beam: hull.reference_half_beam(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn semicircle_panels_close_the_waterline_and_point_into_the_body() {
        let hull = Hull::semicircle(1.0).unwrap();
        let mesh = discretize(&hull, &PanelParams::default()).unwrap();
        assert_eq!(mesh.body.len(), 128);
        let first = mesh.body.first().unwrap();
        let last = mesh.body.last().unwrap();
        assert!((first.start[0] + 1.0).abs() < 1e-12 && first.start[1].abs() < 1e-12);
        assert!((last.end[0] - 1.0).abs() < 1e-12 && last.end[1].abs() < 1e-12);
        for p in &mesh.body {
            // Into the body = toward the circle's centre at the origin.
            let inward = -(p.normal[0] * p.centre[0] + p.normal[1] * p.centre[1]);
            assert!(inward > 0.99 * p.centre[0].hypot(p.centre[1]));
        }
        // Clustering: the waterline panels are shorter than the keel panels.
        assert!(first.length < 0.5 * mesh.body[64].length);
        // Sum of chords approaches the half circumference pi R from below.
        let total: f64 = mesh.body.iter().map(|p| p.length).sum();
        assert!(total < std::f64::consts::PI && total > std::f64::consts::PI - 1e-3);
    }

    #[test]
    fn net_flux_is_the_waterplane_for_heave_and_zero_for_sway() {
        let hull = Hull::semicircle(1.0).unwrap();
        let mesh = discretize(&hull, &PanelParams::default()).unwrap();
        let flux = mesh.net_flux();
        let sway = mesh.dof_names.iter().position(|d| d == "sway").unwrap();
        let heave = mesh.dof_names.iter().position(|d| d == "heave").unwrap();
        // Exact: integral of n_heave ds over the contour = beam 2R (the waterplane); the
        // polygon reproduces it to rounding since rigid fields are linear.
        assert!(flux[sway].abs() < 1e-12, "{}", flux[sway]);
        assert!((flux[heave] - 2.0).abs() < 1e-12, "{}", flux[heave]);
    }

    #[test]
    fn lid_spans_the_waterplane_and_closed_hulls_have_none() {
        let semicircle =
            discretize(&Hull::semicircle(2.0).unwrap(), &PanelParams::default()).unwrap();
        let span: f64 = semicircle.lid.iter().map(|p| p.length).sum();
        assert!((span - 4.0).abs() < 1e-12);
        assert!(semicircle.lid.iter().all(|p| p.centre[1] == 0.0));
        let circle = discretize(&Hull::circle(1.0, 2.0).unwrap(), &PanelParams::default()).unwrap();
        assert!(circle.lid.is_empty());
    }

    #[test]
    fn submerged_contours_near_the_surface_get_more_panels() {
        let semicircle = Hull::semicircle(1.0).unwrap();
        assert_eq!(PanelParams::for_hull(&semicircle), PanelParams::default());
        let deep = PanelParams::for_hull(&Hull::circle(1.0, 2.0).unwrap());
        assert_eq!(deep.body_panels, 128);
        // Gap 0.1 R: perimeter 2 pi R, half clustering: 2 pi * 0.5 / (0.125 * 0.1) = 251.3.
        let shallow = PanelParams::for_hull(&Hull::circle(1.0, 1.1).unwrap());
        assert_eq!(shallow.body_panels, 252);
    }

    #[test]
    fn bad_parameters_are_refused_with_a_reason() {
        let hull = Hull::semicircle(1.0).unwrap();
        let few = PanelParams {
            body_panels: 3,
            ..Default::default()
        };
        let err = discretize(&hull, &few).unwrap_err();
        assert!(err.to_string().contains("at least 4"), "{err}");
        let bad = PanelParams {
            clustering: 1.5,
            ..Default::default()
        };
        assert!(discretize(&hull, &bad).is_err());
    }

    #[test]
    fn coarse_panels_warn_at_short_waves() {
        let hull = Hull::semicircle(1.0).unwrap();
        let mesh = discretize(
            &hull,
            &PanelParams {
                body_panels: 16,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(mesh.wavelength_warning(0.5).is_none());
        let warning = mesh.wavelength_warning(20.0).unwrap();
        assert!(warning.contains("too coarse"), "{warning}");
    }
}
