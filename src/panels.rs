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
//! uniformly in arc length. Contour vertices of hull files become panel nodes where they all
//! fit ([`PanelParams::vertex_budget`]): each takes the node nearest to it in that spacing, the
//! nodes between keep their relative spacing. Where they do not, only the corners (turning more
//! than `CORNER_ANGLE`) do and the smooth vertices lie between nodes
//! ([`Mesh::smooth_vertices_between_nodes`]); with more corners than nodes, those where the
//! contour turns least are left out and counted ([`Mesh::dropped_vertices`]). A contour
//! symmetric about a vertical line gets a mesh symmetric to rounding by construction: one half
//! is meshed and mirrored ([`Mesh::mirror_axis`]).
//!
//! For the removal of irregular frequencies, an open contour also gets an interior lid: panels
//! on the free surface `y = 0` between the two waterline points, inside the body, with the
//! same clustering toward the corners.

use crate::hull::{DofKind, Hull, RigidKind};
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
    /// The panel count whose room decides which contour vertices become nodes. Default
    /// `None`: this mesh's own count. Where all vertices fit, all become nodes; where not,
    /// only the corners (turning more than `CORNER_ANGLE`) do, and the smooth vertices lie
    /// between nodes (a finely described smooth contour is meshed like a smooth curve). A
    /// solver meshing several levels passes its coarsest count, so that every level keeps
    /// the same vertices and the extrapolation sees one geometry converging smoothly.
    pub vertex_budget: Option<usize>,
}

impl Default for PanelParams {
    fn default() -> Self {
        Self {
            body_panels: 128,
            clustering: 0.5,
            lid_density: 0.5,
            vertex_budget: None,
        }
    }
}

impl PanelParams {
    /// The default parameters for `hull`: [`PanelParams::default`], with more panels for a
    /// closed contour close to the free surface, so that the panels at its top are no longer
    /// than `GAP_FRACTION` of the gap `d` between the top and the surface:
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

/// A contour vertex turning more than this (radians, 20 degrees) is a corner: it stays a panel
/// node where smooth vertices do not fit ([`PanelParams::vertex_budget`]). A smooth curve
/// described by points turns far less per point (a Wigley section with 33 points per side
/// about 3 degrees); a box's chine turns 90.
pub(crate) const CORNER_ANGLE: f64 = 20.0 * std::f64::consts::PI / 180.0;

/// Largest panel length at the top of a submerged contour, as a fraction of its gap to the
/// free surface, in [`PanelParams::for_hull`].
pub(crate) const GAP_FRACTION: f64 = 0.125;

/// Upper bound of the automatic panel count of [`PanelParams::for_hull`].
pub(crate) const MAX_AUTOMATIC_PANELS: usize = 1024;

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
    /// Each DOF's rigid motion (kind and roll reference point), `None` for an elastic DOF.
    pub rigid: Vec<Option<(RigidKind, Point)>>,
    /// Reference half-beam R of the hull.
    pub reference_half_beam: f64,
    /// `x` of the vertical line the mesh is mirror-symmetric about (exactly: one half's
    /// nodes mirrored), for a symmetric contour; `None` for an asymmetric one.
    pub mirror_axis: Option<f64>,
    /// Contour corners that are not panel nodes (more corners than the panel count holds;
    /// those where the contour turns least are left out, cut along a chord).
    pub dropped_vertices: usize,
    /// Smooth contour vertices (turning less than `CORNER_ANGLE`) left between nodes because
    /// not all vertices fit ([`PanelParams::vertex_budget`]): the nodes lie on the contour
    /// between them, as on a smooth curve.
    pub smooth_vertices_between_nodes: usize,
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
    /// `wavenumber` (fewer than `PANELS_PER_WAVELENGTH` panels per wavelength), else `None`.
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
pub(crate) const PANELS_PER_WAVELENGTH: f64 = 10.0;

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

/// The contour parameter of node position `t` in [0, 1]: a closed contour's nodes start at
/// `offset` (opposite its top).
fn contour_parameter(closed: bool, offset: f64, t: f64) -> f64 {
    let s = t + offset;
    if closed && s >= 1.0 {
        s - 1.0
    } else {
        s
    }
}

/// The node-position offset of `hull` (see [`contour_parameter`]) and its vertices as node
/// positions strictly inside (0, 1), ascending (the ends are nodes already).
fn contour_vertices(hull: &Hull) -> (f64, Vec<f64>) {
    let closed = hull.is_closed();
    let offset = if closed {
        (highest_parameter(hull) + 0.5).fract()
    } else {
        0.0
    };
    let breakpoints = hull.breakpoints();
    // Built-in closed contours are smooth: their parameter ends 0 and 1 are no corners.
    if closed && breakpoints.len() <= 2 {
        return (offset, Vec::new());
    }
    let mut vertices: Vec<f64> = breakpoints
        .iter()
        .map(|b| {
            if closed {
                (b - offset).rem_euclid(1.0)
            } else {
                *b
            }
        })
        .filter(|&c| c > 1e-12 && c < 1.0 - 1e-12)
        .collect();
    vertices.sort_by(f64::total_cmp);
    vertices.dedup_by(|a, b| (*a - *b).abs() <= 1e-12);
    (offset, vertices)
}

/// The number of corners of `hull`'s contour (vertices turning more than `CORNER_ANGLE`)
/// off its mirror axis. A keel on the axis of a symmetric contour is a node of every mesh of
/// an even panel count, the same point at every extrapolation level, and does not disturb the
/// extrapolation (a hull-file Wigley, keel corners of 46 to 146 degrees: 64 panels and 3
/// levels within 0.19 % of 256 panels, docs/SHIPS.md); corners elsewhere (a box's chines) do.
/// A contour without any (a built-in form, or a hull file describing a smooth curve by points)
/// is meshed like a smooth curve where its points outnumber the nodes.
pub(crate) fn off_axis_corner_count(hull: &Hull) -> usize {
    let (offset, vertices) = contour_vertices(hull);
    let closed = hull.is_closed();
    let point = |t: f64| hull.point(contour_parameter(closed, offset, t));
    let symmetric = mirror_axis(&point, &vertices, hull.contour_length()).is_some();
    vertices
        .iter()
        .zip(turning_angles(&point, &vertices))
        .filter(|&(&v, a)| a > CORNER_ANGLE && !(symmetric && (v - 0.5).abs() <= 1e-12))
        .count()
}

/// Places contour vertices (`vertices`, node parameters strictly inside
/// `(nodes[lo], nodes[hi])`, ascending) onto nodes `lo + 1 .. hi - 1`, keeping `nodes[lo]`
/// and `nodes[hi]`. Each vertex takes the node its position has in the original spacing
/// (rounded), moved as little as needed to keep the order; the nodes between two placed
/// vertices keep their relative spacing. With more vertices than free nodes, the vertices
/// whose contour turns least (`turning`, radians, one per vertex) are left out. Returns the
/// number left out.
fn place_vertices(
    nodes: &mut [f64],
    lo: usize,
    hi: usize,
    vertices: &[f64],
    turning: &[f64],
) -> usize {
    let free = hi.saturating_sub(lo + 1);
    let mut kept: Vec<usize> = (0..vertices.len()).collect();
    if kept.len() > free {
        kept.sort_by(|&a, &b| turning[b].total_cmp(&turning[a]).then(a.cmp(&b)));
        kept.truncate(free);
        kept.sort_unstable();
    }
    let dropped = vertices.len() - kept.len();
    if kept.is_empty() {
        return dropped;
    }
    let original = nodes.to_vec();
    // The fractional index of a parameter in the original spacing.
    let index_of = |v: f64| -> f64 {
        let k = original[lo..=hi].partition_point(|&x| x <= v) + lo;
        let k = k.clamp(lo + 1, hi);
        let (a, b) = (original[k - 1], original[k]);
        (k - 1) as f64 + if b > a { (v - a) / (b - a) } else { 0.0 }
    };
    let mut at: Vec<usize> = kept
        .iter()
        .map(|&v| (index_of(vertices[v]).round() as usize).clamp(lo + 1, hi - 1))
        .collect();
    // Strictly increasing, inside lo + 1 ..= hi - 1 (possible: kept <= free).
    for k in 1..at.len() {
        at[k] = at[k].max(at[k - 1] + 1);
    }
    let last = at.len() - 1;
    at[last] = at[last].min(hi - 1);
    for k in (0..last).rev() {
        at[k] = at[k].min(at[k + 1] - 1);
    }
    // Anchors: the ends and the placed vertices; between two, the original spacing rescaled.
    let mut anchors: Vec<(usize, f64)> = vec![(lo, nodes[lo])];
    anchors.extend(at.iter().zip(&kept).map(|(&i, &v)| (i, vertices[v])));
    anchors.push((hi, nodes[hi]));
    for pair in anchors.windows(2) {
        let ((i0, v0), (i1, v1)) = (pair[0], pair[1]);
        let (o0, o1) = (original[i0], original[i1]);
        for i in i0 + 1..i1 {
            let f = if o1 > o0 {
                (original[i] - o0) / (o1 - o0)
            } else {
                (i - i0) as f64 / (i1 - i0) as f64
            };
            nodes[i] = v0 + f * (v1 - v0);
        }
        nodes[i1] = v1;
    }
    dropped
}

/// Whether `vertices` (interior node parameters, ascending) all become nodes of a mesh of
/// `count` panels: the free nodes of [`discretize`]'s placement (one half's for a symmetric
/// contour).
fn vertices_fit(vertices: &[f64], symmetric: bool, count: usize) -> bool {
    if symmetric {
        let below = vertices.partition_point(|&v| v < 0.5 - 1e-12);
        let free = if count % 2 == 0 {
            (count / 2).saturating_sub(1)
        } else {
            count / 2
        };
        below <= free
    } else {
        vertices.len() < count
    }
}

/// The mirror axis `x = x_c` of a contour symmetric about a vertical line, in node parameters
/// `t`: `point(1 - t)` is the mirror image of `point(t)` (to 1e-9 of the contour's size) at
/// every vertex and at 64 points between, and the vertices (ascending) come in mirrored
/// pairs. `None` for an asymmetric contour.
fn mirror_axis(point: &dyn Fn(f64) -> Point, vertices: &[f64], size: f64) -> Option<f64> {
    let (a, b) = (point(0.0), point(1.0));
    let axis = 0.5 * (a[0] + b[0]);
    let tolerance = 1e-9 * size;
    let mirrored = |t: f64| {
        let (p, q) = (point(t), point(1.0 - t));
        (p[0] + q[0] - 2.0 * axis).abs() <= tolerance && (p[1] - q[1]).abs() <= tolerance
    };
    // Sorted vertices pair up from both ends.
    let paired = vertices
        .iter()
        .zip(vertices.iter().rev())
        .all(|(&v, &w)| (v + w - 1.0).abs() <= 1e-9);
    let samples = (0..=64).map(|i| i as f64 / 128.0);
    (paired && vertices.iter().copied().chain(samples).all(mirrored)).then_some(axis)
}

/// The turning angle of the contour at each vertex (radians), from the chords to its
/// neighbouring vertices (the ends `0` and `1` stand in where there is none).
fn turning_angles(point: &dyn Fn(f64) -> Point, vertices: &[f64]) -> Vec<f64> {
    (0..vertices.len())
        .map(|k| {
            let before = if k == 0 { 0.0 } else { vertices[k - 1] };
            let after = vertices.get(k + 1).copied().unwrap_or(1.0);
            let (p, q, r) = (point(before), point(vertices[k]), point(after));
            let (u, v) = ([q[0] - p[0], q[1] - p[1]], [r[0] - q[0], r[1] - q[1]]);
            (u[0] * v[1] - u[1] * v[0])
                .atan2(u[0] * v[0] + u[1] * v[1])
                .abs()
        })
        .collect()
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
    let (offset, vertices) = contour_vertices(hull);
    let parameter = |t: f64| contour_parameter(closed, offset, t);
    let mut nodes = if closed {
        nodes_toward_the_surface(params.body_panels, params.clustering)
    } else {
        clustered_nodes(params.body_panels, params.clustering)
    };
    let point = |t: f64| hull.point(parameter(t));
    let size = hull.contour_length();
    let axis = mirror_axis(&point, &vertices, size);
    let count = params.body_panels;
    let turning_all = turning_angles(&point, &vertices);
    let vertex_count = turning_all.len();
    // Where not every vertex fits the budget, only the corners are placed.
    let budget = params.vertex_budget.unwrap_or(count).min(count);
    let (vertices, turning) = if vertices_fit(&vertices, axis.is_some(), budget) {
        (vertices, turning_all)
    } else {
        vertices
            .iter()
            .zip(&turning_all)
            .filter(|(_, &angle)| angle > CORNER_ANGLE)
            .map(|(&v, &a)| (v, a))
            .unzip()
    };
    let smooth_vertices_between_nodes = vertex_count - vertices.len();
    let dropped_vertices = if axis.is_some() {
        // One half, mirrored: nodes t and 1 - t. An even count has the node 1/2; an odd one
        // a middle panel across it, which holds a vertex on the axis inside it.
        let half = count / 2;
        // The vertices below 1/2 (ascending: a prefix).
        let below = vertices.partition_point(|&v| v < 0.5 - 1e-12);
        let on_axis = vertices.get(below).is_some_and(|&v| v <= 0.5 + 1e-12);
        let dropped_in_half = if count % 2 == 0 {
            nodes[half] = 0.5;
            place_vertices(&mut nodes, 0, half, &vertices[..below], &turning[..below])
        } else {
            let dropped = place_vertices(
                &mut nodes,
                0,
                half + 1,
                &vertices[..below],
                &turning[..below],
            );
            if nodes[half] >= 0.5 {
                // Not a vertex (those lie below 1/2): moved below the axis.
                nodes[half] = 0.5 * (nodes[half - 1] + 0.5);
            }
            dropped
        };
        for i in 0..count.div_ceil(2) {
            nodes[count - i] = 1.0 - nodes[i];
        }
        2 * dropped_in_half + usize::from(on_axis && count % 2 == 1)
    } else {
        place_vertices(&mut nodes, 0, count, &vertices, &turning)
    };
    if closed {
        nodes[0] = 0.0;
        nodes[count] = 1.0;
    }
    if nodes.windows(2).any(|w| w[1] <= w[0]) {
        return Err(PanelError::UnresolvedCorners {
            panels: params.body_panels,
            corners: vertex_count,
        });
    }
    // Node points; a symmetric contour's second half is the first one's exact mirror image.
    let mut points: Vec<Point> = nodes.iter().map(|&t| point(t)).collect();
    if let Some(x) = axis {
        if count % 2 == 0 {
            points[count / 2][0] = x;
        }
        for i in 0..count.div_ceil(2) {
            let p = points[i];
            points[count - i] = [2.0 * x - p[0], p[1]];
        }
    }
    let dof_count = hull.dof_names().len();
    let mut body = Vec::with_capacity(params.body_panels);
    let mut normal_velocity = DMatrix::zeros(params.body_panels, dof_count);
    for (l, w) in nodes.windows(2).enumerate() {
        let panel = Panel::new(points[l], points[l + 1]);
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
        let mut xs: Vec<f64> = clustered_nodes(count, params.clustering)
            .iter()
            .map(|s| right[0] + (left[0] - right[0]) * s)
            .collect();
        if let Some(x) = axis {
            for i in 0..count.div_ceil(2) {
                xs[count - i] = 2.0 * x - xs[i];
            }
            if count % 2 == 0 {
                xs[count / 2] = x;
            }
        }
        xs.windows(2)
            .map(|w| Panel::new([w[0], 0.0], [w[1], 0.0]))
            .collect()
    };
    Ok(Mesh {
        body,
        lid,
        normal_velocity,
        dof_names: hull.dof_names().iter().map(|s| s.to_string()).collect(),
        rigid: (0..dof_count)
            .map(|j| match hull.dof_kind(j) {
                Some(DofKind::Rigid { kind, reference }) => Some((kind, reference)),
                _ => None,
            })
            .collect(),
        reference_half_beam: hull.reference_half_beam(),
        mirror_axis: axis,
        dropped_vertices,
        smooth_vertices_between_nodes,
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

    /// A Wigley midship section (half-beam 1, draft 0.625) through `per_side` points on each
    /// side, keel point shared, with sway, heave and roll.
    fn wigley_section(per_side: usize) -> Hull {
        let text = crate::hull::wigley_section_xml("wigley", 1.0, 0.625, per_side);
        Hull::from_xml_str(&text, "wigley.xml").unwrap()
    }

    fn is_node(mesh: &Mesh, p: Point) -> bool {
        mesh.body
            .iter()
            .any(|q| (q.start[0] - p[0]).abs() < 1e-12 && (q.start[1] - p[1]).abs() < 1e-12)
            || mesh.body.last().is_some_and(|q| q.end == p)
    }

    #[test]
    fn a_symmetric_section_is_meshed_symmetrically_at_every_count() {
        for per_side in [5, 9, 33] {
            let hull = wigley_section(per_side);
            for panels in [16, 17, 32, 64, 128] {
                let params = PanelParams {
                    body_panels: panels,
                    ..Default::default()
                };
                let mesh = discretize(&hull, &params).unwrap();
                assert_eq!(mesh.mirror_axis, Some(0.0));
                let n = mesh.body.len();
                for (a, b) in mesh.body.iter().zip(mesh.body.iter().rev()) {
                    // Bit for bit: panel l's start mirrors panel n-1-l's end.
                    assert_eq!(a.start[0], -b.end[0], "{per_side} points, {panels} panels");
                    assert_eq!(a.start[1], b.end[1]);
                }
                assert_eq!(n, panels);
                let lid = &mesh.lid;
                for (a, b) in lid.iter().zip(lid.iter().rev()) {
                    assert_eq!(a.start[0], -b.end[0]);
                }
                // 2 (per_side - 1) - 1 interior vertices; a free node for each while they fit,
                // else the corners only (the keel on the axis; none of the sides' points turn
                // more than CORNER_ANGLE) and the smooth ones between nodes.
                let vertices = 2 * (per_side - 1) - 1;
                let off_node = mesh.dropped_vertices + mesh.smooth_vertices_between_nodes;
                if panels % 2 == 1 {
                    // The keel vertex lies on the axis, inside the middle panel.
                    assert!(off_node >= 1);
                } else if panels >= 2 * per_side - 2 {
                    assert_eq!(off_node, 0, "{per_side} points, {panels} panels");
                } else {
                    assert_eq!(mesh.smooth_vertices_between_nodes, vertices - 1);
                    assert_eq!(mesh.dropped_vertices, 0);
                    assert!(is_node(&mesh, [0.0, -0.625]), "the keel");
                }
                if off_node == 0 {
                    for k in 0..2 * per_side - 1 {
                        assert!(
                            is_node(&mesh, hull.point(hull.breakpoints()[k])),
                            "vertex {k}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn vertices_close_together_all_become_nodes() {
        // Two vertices 1e-3 apart on a box's bottom: the old nearest-node snapping gave both
        // the same node and kept the later one.
        let text = r#"<hull name="b" half_beam="1"><contour closed="false">
            <point x="-1" y="0"/><point x="-1" y="-1"/><point x="0.3" y="-1"/>
            <point x="0.301" y="-1"/><point x="1" y="-1"/><point x="1" y="0"/>
            </contour><rigid name="heave" kind="heave"/></hull>"#;
        let hull = Hull::from_xml_str(text, "b.xml").unwrap();
        for panels in [8, 16, 64] {
            let mesh = discretize(
                &hull,
                &PanelParams {
                    body_panels: panels,
                    ..Default::default()
                },
            )
            .unwrap();
            assert_eq!(mesh.dropped_vertices, 0);
            assert_eq!(mesh.mirror_axis, None);
            for &b in &hull.breakpoints() {
                assert!(
                    is_node(&mesh, hull.point(b)),
                    "{panels} panels, vertex at {b}"
                );
            }
        }
    }

    #[test]
    fn too_many_vertices_keep_the_corners() {
        // A box (two corners) with 40 collinear vertices on each side: at 8 panels only the
        // corners are kept, the collinear points (no turning) lie between nodes, counted.
        let mut text = String::from(r#"<hull name="b" half_beam="1"><contour closed="false">"#);
        let mut points = Vec::new();
        for k in 0..=40 {
            points.push((-1.0, -(k as f64) / 40.0));
        }
        for k in 1..40 {
            points.push((-1.0 + 2.0 * k as f64 / 40.0, -1.0));
        }
        for k in (0..=40).rev() {
            points.push((1.0, -(k as f64) / 40.0));
        }
        for (x, y) in &points {
            text.push_str(&format!("<point x=\"{x}\" y=\"{y}\"/>"));
        }
        text.push_str(r#"</contour><rigid name="heave" kind="heave"/></hull>"#);
        let hull = Hull::from_xml_str(&text, "b.xml").unwrap();
        let mesh = discretize(
            &hull,
            &PanelParams {
                body_panels: 8,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(mesh.smooth_vertices_between_nodes, points.len() - 2 - 2);
        assert_eq!(mesh.dropped_vertices, 0);
        assert!(is_node(&mesh, [-1.0, -1.0]) && is_node(&mesh, [1.0, -1.0]));
        assert_eq!(mesh.mirror_axis, Some(0.0));
    }

    #[test]
    fn more_corners_than_nodes_drop_the_least_turning_ones() {
        // A staircase: 12 corners of 90 degrees, 8 panels hold 7 of them.
        let mut text = String::from(r#"<hull name="s" half_beam="3"><contour closed="false">"#);
        let mut x = -3.0;
        let mut y = 0.0;
        text.push_str(&format!("<point x=\"{x}\" y=\"{y}\"/>"));
        for _ in 0..6 {
            y -= 0.5;
            text.push_str(&format!("<point x=\"{x}\" y=\"{y}\"/>"));
            x += 1.0;
            text.push_str(&format!("<point x=\"{x}\" y=\"{y}\"/>"));
        }
        text.push_str(r#"<point x="3" y="0"/></contour><rigid name="heave" kind="heave"/></hull>"#);
        let hull = Hull::from_xml_str(&text, "s.xml").unwrap();
        assert_eq!(off_axis_corner_count(&hull), 12);
        let params = PanelParams {
            body_panels: 8,
            ..Default::default()
        };
        let mesh = discretize(&hull, &params).unwrap();
        assert_eq!(mesh.dropped_vertices, 12 - 7);
        assert_eq!(mesh.smooth_vertices_between_nodes, 0);
    }

    #[test]
    fn a_vertex_budget_gives_every_level_the_same_vertices() {
        let hull = wigley_section(9); // 15 interior vertices, the keel the only corner
        assert_eq!(off_axis_corner_count(&hull), 0);
        for panels in [8, 16, 32] {
            let own = |budget| {
                discretize(
                    &hull,
                    &PanelParams {
                        body_panels: panels,
                        vertex_budget: budget,
                        ..Default::default()
                    },
                )
                .unwrap()
            };
            // Alone, 16 and 32 panels hold every vertex (7 per side), 8 do not.
            let alone = own(None);
            let expected = if panels >= 16 { 0 } else { 14 };
            assert_eq!(alone.smooth_vertices_between_nodes, expected, "{panels}");
            // With the coarsest level's budget, every level leaves the same 14 off.
            assert_eq!(own(Some(8)).smooth_vertices_between_nodes, 14, "{panels}");
            // A budget too small for any vertex: the corners only, no panic.
            assert_eq!(own(Some(0)).smooth_vertices_between_nodes, 14, "{panels}");
        }
    }
}
