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
//!   semicircular beam (below).
//!
//! # Built-ins (exact arcs, analytic fields)
//! [`Hull::semicircle`]: radius R, centre at the origin, theta = pi s, hull point
//! P = R(-cos theta, -sin theta): theta = 0 at the left waterline (-R, 0), pi/2 at the keel,
//! pi at the right waterline (R, 0). [`Hull::circle`]: radius R, centre (0, -H) with H/R > 1,
//! theta = 2 pi s, P = (0, -H) + R(-cos theta, -sin theta), starting at the leftmost point.
//! In both, t = (sin theta, -cos theta) and n = (cos theta, sin theta).
//!
//! # Craig-Bampton modes of the thin semicircular beam (seed paper, eqs. 4-6)
//! w(theta) is the tangential displacement, positive towards increasing theta (unit vector
//! e_theta = (sin theta, -cos theta)); u = dw/dtheta is the radial displacement, positive
//! INWARD (unit vector (cos theta, sin theta)); psi = (w'' + w)/R is the slope. In-plane
//! equilibrium `w'''''' + 2 w'''' + w'' = 0` has the general solution
//!
//! w = C1 + C2 theta + C3 cos theta + C4 sin theta + C5 theta cos theta + C6 theta sin theta,
//!
//! and the displacement is d = u (cos theta, sin theta) + w (sin theta, -cos theta).
//! Mode `cbk` has unit value of the k-th of (u(0), w(0), psi(0), u(pi), w(pi), psi(pi)) and
//! zero for the others; the coefficients come from solving that 6x6 boundary system
//! ([`craig_bampton_coefficients`]). Rigid motions in terms of the modes (exact, tested):
//! sway = cb1 - cb4, heave = -cb2 + cb5, roll about the origin = R cb2 + cb3 + R cb5 + cb6.
//!
//! Table 1 of the seed paper does not match these directly: after theta -> -theta (negating
//! C2, C4, C5) its rows 1, 3, 4, 6 are -cb4, cb6, cb1, cb3 and its row 5 is cb5, while its
//! printed row 2 is exactly minus row 5, so the printed set has rank 5 and cannot be complete.
//! Row 5 with C3 = 1 added would be cb2; the test `seed_table_1_after_theta_flip` pins this.
//!
//! # Hull files
//! XML, described in `docs/HULL_FORMAT.md`; [`Hull::from_file`], [`Hull::from_xml_str`],
//! [`Hull::to_xml_string`] (canonical text, round-trips exactly). Validation is strict; every
//! error names the file, the line and the problem. A contour written clockwise is reversed
//! (points and mode vectors) and a note is recorded ([`Hull::notes`]).

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::f64::consts::PI;
use std::fmt;
use std::path::Path;

/// A point or vector in the section plane, `[x, y]` in metres.
pub type Point = [f64; 2];

/// Relative tolerance (times the contour's largest extent) for waterline points on y = 0.
const WATERLINE_TOLERANCE: f64 = 1e-6;
/// Relative tolerance (times the contour's largest extent) for contour self-contact.
const CONTACT_TOLERANCE: f64 = 1e-9;

/// Why a hull could not be built: the source (file name, or built-in / hull name), the line
/// when it came from a file, and the problem.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HullError {
    source: String,
    line: Option<usize>,
    message: String,
}

impl HullError {
    fn new(source: &str, line: Option<usize>, message: impl Into<String>) -> Self {
        HullError {
            source: source.to_string(),
            line,
            message: message.into(),
        }
    }

    /// The file name (or `built-in semicircle`, `built-in circle`, a hull's name).
    pub fn source_name(&self) -> &str {
        &self.source
    }

    /// 1-based line in the file, when the error refers to one.
    pub fn line(&self) -> Option<usize> {
        self.line
    }

    /// The problem, without the location.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for HullError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: {}", self.source, line, self.message),
            None => write!(f, "{}: {}", self.source, self.message),
        }
    }
}

impl std::error::Error for HullError {}

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
    Arc { radius: f64, depth: f64 },
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
}

// ---------------------------------------------------------------------------------------------
// Craig-Bampton modes
// ---------------------------------------------------------------------------------------------

/// (w, u, psi) of the beam deflection with coefficients `c` = (C1..C6) at `theta`:
/// w from eq. 6, u = dw/dtheta, psi = (w'' + w)/R.
pub fn craig_bampton_fields(c: &[f64; 6], radius: f64, theta: f64) -> (f64, f64, f64) {
    let (s, co) = theta.sin_cos();
    let w = c[0] + c[1] * theta + c[2] * co + c[3] * s + theta * (c[4] * co + c[5] * s);
    let u = c[1] - c[2] * s + c[3] * co + c[4] * (co - theta * s) + c[5] * (s + theta * co);
    let psi = (c[0] + c[1] * theta - 2.0 * c[4] * s + 2.0 * c[5] * co) / radius;
    (w, u, psi)
}

/// Displacement vector of the beam deflection with coefficients `c` at `theta`:
/// u (cos theta, sin theta) + w (sin theta, -cos theta).
pub fn craig_bampton_displacement(c: &[f64; 6], radius: f64, theta: f64) -> Point {
    let (w, u, _) = craig_bampton_fields(c, radius, theta);
    let (s, co) = theta.sin_cos();
    [u * co + w * s, u * s - w * co]
}

/// Coefficients (C1..C6) of the six Craig-Bampton modes of the thin semicircular beam of
/// radius `radius`: row k-1 is mode `cbk`, the unit value of the k-th of
/// (u(0), w(0), psi(0), u(pi), w(pi), psi(pi)). Solved from the 6x6 boundary system by LU.
/// For a radius that is not positive and finite every entry is NaN.
pub fn craig_bampton_coefficients(radius: f64) -> [[f64; 6]; 6] {
    let nan = [[f64::NAN; 6]; 6];
    if !(radius.is_finite() && radius > 0.0) {
        return nan;
    }
    // Column i: end values of basis function i.
    let mut system = nalgebra::Matrix6::<f64>::zeros();
    for i in 0..6 {
        let mut unit = [0.0; 6];
        unit[i] = 1.0;
        for (end, theta) in [0.0, PI].into_iter().enumerate() {
            let (w, u, psi) = craig_bampton_fields(&unit, radius, theta);
            system[(3 * end, i)] = u;
            system[(3 * end + 1, i)] = w;
            system[(3 * end + 2, i)] = psi;
        }
    }
    let lu = system.lu();
    let mut modes = [[0.0; 6]; 6];
    for (k, mode) in modes.iter_mut().enumerate() {
        let mut rhs = nalgebra::Vector6::<f64>::zeros();
        rhs[k] = 1.0;
        match lu.solve(&rhs) {
            Some(c) => mode.iter_mut().zip(c.iter()).for_each(|(m, v)| *m = *v),
            None => return nan,
        }
    }
    modes
}

// ---------------------------------------------------------------------------------------------
// Hull
// ---------------------------------------------------------------------------------------------

fn rigid(name: &str, kind: RigidKind) -> Dof {
    Dof {
        name: name.to_string(),
        field: Field::Rigid {
            kind,
            reference: [0.0, 0.0],
        },
    }
}

fn rigid_displacement(kind: RigidKind, reference: Point, p: Point) -> Point {
    match kind {
        RigidKind::Sway => [1.0, 0.0],
        RigidKind::Heave => [0.0, 1.0],
        RigidKind::Roll => [-(p[1] - reference[1]), p[0] - reference[0]],
    }
}

impl Hull {
    /// The built-in semicircle of radius `radius` (H/R = 0), centre at the origin, with DOFs
    /// `sway heave roll cb1 cb2 cb3 cb4 cb5 cb6` (roll about the origin).
    pub fn semicircle(radius: f64) -> Result<Hull, HullError> {
        let source = "built-in semicircle";
        if !(radius.is_finite() && radius > 0.0) {
            return Err(HullError::new(
                source,
                None,
                format!("radius must be positive and finite, got {radius}"),
            ));
        }
        let coefficients = craig_bampton_coefficients(radius);
        let mut dofs = vec![
            rigid("sway", RigidKind::Sway),
            rigid("heave", RigidKind::Heave),
            rigid("roll", RigidKind::Roll),
        ];
        for (k, c) in coefficients.iter().enumerate() {
            dofs.push(Dof {
                name: format!("cb{}", k + 1),
                field: Field::CraigBampton {
                    mode: k + 1,
                    coefficients: *c,
                },
            });
        }
        Ok(Hull {
            name: "semicircle".to_string(),
            half_beam: radius,
            contour: Contour::Arc { radius, depth: 0.0 },
            dofs,
            notes: Vec::new(),
        })
    }

    /// The built-in circle of radius `radius` with centre at (0, -H), H = `depth_over_radius`
    /// times the radius, closed, with DOFs `sway heave roll` (roll about the origin).
    /// H/R = 0 gives [`Hull::semicircle`]; 0 < H/R <= 1 (the circle pierces or touches the free
    /// surface) and H/R < 0 are errors.
    pub fn circle(radius: f64, depth_over_radius: f64) -> Result<Hull, HullError> {
        let source = "built-in circle";
        if !(radius.is_finite() && radius > 0.0) {
            return Err(HullError::new(
                source,
                None,
                format!("radius must be positive and finite, got {radius}"),
            ));
        }
        if depth_over_radius == 0.0 {
            return Hull::semicircle(radius);
        }
        check_circle_depth(depth_over_radius).map_err(|m| HullError::new(source, None, m))?;
        Ok(Hull {
            name: "circle".to_string(),
            half_beam: radius,
            contour: Contour::Arc {
                radius,
                depth: depth_over_radius * radius,
            },
            dofs: vec![
                rigid("sway", RigidKind::Sway),
                rigid("heave", RigidKind::Heave),
                rigid("roll", RigidKind::Roll),
            ],
            notes: Vec::new(),
        })
    }

    /// Reads a hull file (format: `docs/HULL_FORMAT.md`).
    pub fn from_file(path: &Path) -> Result<Hull, HullError> {
        let source = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| HullError::new(&source, None, format!("cannot read the file: {e}")))?;
        Hull::from_xml_str(&text, &source)
    }

    /// Parses hull XML; `source_name` names it in errors (usually the file name).
    pub fn from_xml_str(text: &str, source_name: &str) -> Result<Hull, HullError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let root = parse_tree(text, source_name)?;
        build_hull(&root, source_name)
    }

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
            Contour::Polyline { closed, .. } => *closed,
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
        Ok(Hull {
            dofs,
            ..self.clone()
        })
    }

    /// Total arc length of the contour (closed: once around), metres.
    pub fn contour_length(&self) -> f64 {
        match &self.contour {
            Contour::Arc { radius, depth } if *depth > 0.0 => 2.0 * PI * radius,
            Contour::Arc { radius, .. } => PI * radius,
            Contour::Polyline { length, .. } => *length,
        }
    }

    /// Contour point at parameter `s` in [0, 1] (clamped), s proportional to arc length.
    pub fn point(&self, s: f64) -> Point {
        let s = s.clamp(0.0, 1.0);
        match &self.contour {
            Contour::Arc { radius, depth } => {
                let (sn, cs) = arc_sin_cos(*depth, s);
                [-radius * cs, -depth - radius * sn]
            }
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
            Contour::Arc { .. } => vec![0.0, 1.0],
            Contour::Polyline { knots, .. } => knots.clone(),
        }
    }

    /// 64-bit FNV-1a of [`Hull::to_xml_string`], as 16 hex digits. Covers the name, the
    /// half-beam, the geometry and every DOF (name, order, field), so hulls that differ in any
    /// of these get different fingerprints.
    pub fn fingerprint(&self) -> String {
        let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
        for byte in self.to_xml_string().bytes() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
        }
        format!("{hash:016x}")
    }

    /// Canonical XML in the documented format; `from_xml_str` of it gives the same hull.
    pub fn to_xml_string(&self) -> String {
        let mut out = String::new();
        out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        out.push_str(&format!(
            "<hull name=\"{}\" half_beam=\"{}\" units=\"m\" version=\"1\">\n",
            escape(&self.name),
            num(self.half_beam)
        ));
        match &self.contour {
            Contour::Arc { radius, depth } => out.push_str(&format!(
                "  <circle radius=\"{}\" depth=\"{}\"/>\n",
                num(*radius),
                num(*depth)
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
        out.push_str("</hull>\n");
        out
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

fn check_circle_depth(h_over_r: f64) -> Result<(), String> {
    if !h_over_r.is_finite() || h_over_r < 0.0 {
        Err(format!(
            "depth/radius must be 0 (semicircle) or greater than 1 (submerged circle), \
             got {h_over_r}"
        ))
    } else if h_over_r > 0.0 && h_over_r <= 1.0 {
        Err(format!(
            "depth/radius = {h_over_r}: a circle with 0 < H/R <= 1 pierces or touches the free \
             surface; use H/R = 0 (semicircle) or H/R > 1 (submerged circle)"
        ))
    } else {
        Ok(())
    }
}

/// Shortest text that parses back to the same f64 (negative zero written as 0.0).
fn num(x: f64) -> String {
    let x = if x == 0.0 { 0.0 } else { x };
    format!("{x:?}")
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

// ---------------------------------------------------------------------------------------------
// XML reading
// ---------------------------------------------------------------------------------------------

#[derive(Debug)]
struct Element {
    name: String,
    attributes: Vec<(String, String)>,
    children: Vec<Element>,
    line: usize,
}

struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    fn new(text: &str) -> Self {
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex { starts }
    }

    /// 1-based line of byte offset `pos`.
    fn line(&self, pos: usize) -> usize {
        self.starts.partition_point(|&start| start <= pos).max(1)
    }
}

/// UTF-8 text of names and values: quick-xml up to 0.37 hands out bytes, later versions `str`.
fn utf8<B: AsRef<[u8]> + ?Sized>(raw: &B) -> Option<&str> {
    std::str::from_utf8(raw.as_ref()).ok()
}

fn to_usize<T: TryInto<usize>>(x: T) -> usize {
    x.try_into().unwrap_or(usize::MAX)
}

fn unescape(raw: &str) -> Option<String> {
    let mut out = String::with_capacity(raw.len());
    let mut rest = raw;
    while let Some(amp) = rest.find('&') {
        out.push_str(&rest[..amp]);
        let end = rest[amp..].find(';')? + amp;
        let entity = &rest[amp + 1..end];
        let c = match entity {
            "lt" => '<',
            "gt" => '>',
            "amp" => '&',
            "quot" => '"',
            "apos" => '\'',
            _ => {
                let code = if let Some(hex) = entity.strip_prefix("#x") {
                    u32::from_str_radix(hex, 16).ok()?
                } else if let Some(dec) = entity.strip_prefix('#') {
                    dec.parse().ok()?
                } else {
                    return None;
                };
                char::from_u32(code)?
            }
        };
        out.push(c);
        rest = &rest[end + 1..];
    }
    out.push_str(rest);
    Some(out)
}

fn make_element(start: &BytesStart, line: usize, source: &str) -> Result<Element, HullError> {
    let err = |m: String| HullError::new(source, Some(line), m);
    let name = utf8(start.name().as_ref())
        .ok_or_else(|| err("element name is not UTF-8".into()))?
        .to_string();
    let mut attributes = Vec::new();
    for attribute in start.attributes() {
        let attribute = attribute.map_err(|e| err(format!("bad attribute in <{name}>: {e}")))?;
        let key = utf8(attribute.key.as_ref())
            .ok_or_else(|| err(format!("attribute name in <{name}> is not UTF-8")))?
            .to_string();
        let raw = utf8(&*attribute.value)
            .ok_or_else(|| err(format!("attribute {key} of <{name}> is not UTF-8")))?;
        let value = unescape(raw)
            .ok_or_else(|| err(format!("bad character reference in {key}=\"{raw}\"")))?;
        attributes.push((key, value));
    }
    Ok(Element {
        name,
        attributes,
        children: Vec::new(),
        line,
    })
}

fn parse_tree(text: &str, source: &str) -> Result<Element, HullError> {
    let lines = LineIndex::new(text);
    let mut reader = Reader::from_str(text);
    reader.config_mut().trim_text(true);
    let mut stack: Vec<Element> = Vec::new();
    let mut root: Option<Element> = None;
    loop {
        let before = to_usize(reader.buffer_position()).min(text.len());
        let event = reader.read_event().map_err(|e| {
            let at = to_usize(reader.error_position()).min(text.len());
            HullError::new(source, Some(lines.line(at)), format!("malformed XML: {e}"))
        })?;
        let start = text.as_bytes()[before..]
            .iter()
            .position(|&b| b == b'<')
            .map_or(before, |k| before + k);
        let line = lines.line(start);
        let finished = match event {
            Event::Start(e) => {
                stack.push(make_element(&e, line, source)?);
                None
            }
            Event::Empty(e) => Some(make_element(&e, line, source)?),
            Event::End(_) => stack.pop(),
            Event::Text(t) => {
                let raw = utf8(&*t).unwrap_or("?").as_bytes();
                if raw.iter().all(u8::is_ascii_whitespace) {
                    None
                } else {
                    let line = lines
                        .line(before + raw.iter().take_while(|b| b.is_ascii_whitespace()).count());
                    return Err(HullError::new(
                        source,
                        Some(line),
                        "unexpected text: values go in attributes, e.g. <point x=\"1\" y=\"-2\"/>",
                    ));
                }
            }
            Event::Decl(_) | Event::Comment(_) => None,
            Event::Eof => break,
            _ => {
                return Err(HullError::new(
                    source,
                    Some(line),
                    "unsupported XML construct (CDATA, processing instruction, DOCTYPE or entity \
                     reference)",
                ))
            }
        };
        if let Some(element) = finished {
            match stack.last_mut() {
                Some(parent) => parent.children.push(element),
                None if root.is_none() => root = Some(element),
                None => {
                    return Err(HullError::new(
                        source,
                        Some(element.line),
                        format!(
                            "second top-level element <{}>: a file holds one <hull>",
                            element.name
                        ),
                    ))
                }
            }
        }
    }
    if let Some(open) = stack.last() {
        return Err(HullError::new(
            source,
            Some(open.line),
            format!("element <{}> is never closed", open.name),
        ));
    }
    root.ok_or_else(|| HullError::new(source, None, "no <hull> element"))
}

/// Attributes of one element, taken by name; `finish` rejects any left over.
struct Attributes<'a> {
    element: &'a Element,
    source: &'a str,
    taken: Vec<bool>,
}

impl<'a> Attributes<'a> {
    fn new(element: &'a Element, source: &'a str) -> Self {
        Attributes {
            element,
            source,
            taken: vec![false; element.attributes.len()],
        }
    }

    fn error(&self, message: String) -> HullError {
        HullError::new(self.source, Some(self.element.line), message)
    }

    fn optional(&mut self, key: &str) -> Option<&'a str> {
        let index = self.element.attributes.iter().position(|(k, _)| k == key)?;
        self.taken[index] = true;
        Some(self.element.attributes[index].1.as_str())
    }

    fn required(&mut self, key: &str) -> Result<&'a str, HullError> {
        self.optional(key).ok_or_else(|| {
            self.error(format!(
                "<{}> is missing the attribute {key}",
                self.element.name
            ))
        })
    }

    fn number(&self, key: &str, text: &str) -> Result<f64, HullError> {
        match text.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            Ok(_) => Err(self.error(format!(
                "{key}=\"{text}\" in <{}> is not a finite number",
                self.element.name
            ))),
            Err(_) => Err(self.error(format!(
                "{key}=\"{text}\" in <{}> is not a number",
                self.element.name
            ))),
        }
    }

    fn required_number(&mut self, key: &str) -> Result<f64, HullError> {
        let text = self.required(key)?;
        self.number(key, text)
    }

    fn optional_number(&mut self, key: &str, default: f64) -> Result<f64, HullError> {
        match self.optional(key) {
            Some(text) => self.number(key, text),
            None => Ok(default),
        }
    }

    fn finish(self, allowed: &[&str]) -> Result<(), HullError> {
        match self.taken.iter().position(|t| !t) {
            Some(i) => Err(self.error(format!(
                "unknown attribute {} in <{}>; allowed: {}",
                self.element.attributes[i].0,
                self.element.name,
                allowed.join(", ")
            ))),
            None => Ok(()),
        }
    }
}

fn no_children(element: &Element, source: &str) -> Result<(), HullError> {
    match element.children.first() {
        Some(child) => Err(HullError::new(
            source,
            Some(child.line),
            format!("<{}> cannot contain <{}>", element.name, child.name),
        )),
        None => Ok(()),
    }
}

/// Points (or vectors) of `<point>`/`<u>` children, with their lines.
fn vectors(
    element: &Element,
    child_name: &str,
    source: &str,
) -> Result<(Vec<Point>, Vec<usize>), HullError> {
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
        no_children(child, source)?;
        let mut a = Attributes::new(child, source);
        let x = a.required_number("x")?;
        let y = a.required_number("y")?;
        a.finish(&["x", "y"])?;
        values.push([x, y]);
        lines.push(child.line);
    }
    Ok((values, lines))
}

fn valid_dof_name(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

fn valid_hull_name(name: &str) -> bool {
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
    if root.name != "hull" {
        return Err(err(
            root.line,
            format!("top-level element is <{}>, expected <hull>", root.name),
        ));
    }
    let mut a = Attributes::new(root, source);
    let name = a.required("name")?;
    if !valid_hull_name(name) {
        return Err(err(
            root.line,
            format!(
                "hull name \"{name}\" must start with a letter or digit and contain only \
                 letters, digits, '_', '-' and '.'"
            ),
        ));
    }
    let half_beam = a.required_number("half_beam")?;
    if half_beam <= 0.0 {
        return Err(err(
            root.line,
            format!("half_beam must be positive, got {half_beam}"),
        ));
    }
    if let Some(units) = a.optional("units") {
        if units != "m" {
            return Err(err(
                root.line,
                format!(
                    "units=\"{units}\" is not supported: coordinates are in metres, units=\"m\""
                ),
            ));
        }
    }
    if let Some(version) = a.optional("version") {
        if version != "1" {
            return Err(err(
                root.line,
                format!("version=\"{version}\" is not supported; this reader knows version 1"),
            ));
        }
    }
    a.finish(&["name", "half_beam", "units", "version"])?;

    let mut geometry: Option<Geometry> = None;
    let mut dofs: Vec<FileDof> = Vec::new();
    for child in &root.children {
        let line = child.line;
        let mut a = Attributes::new(child, source);
        if matches!(child.name.as_str(), "contour" | "circle") {
            if let Some(
                Geometry::Circle { line: first, .. } | Geometry::Polyline { line: first, .. },
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
                let closed = match a.optional("closed") {
                    None | Some("false") => false,
                    Some("true") => true,
                    Some(other) => {
                        return Err(err(
                            line,
                            format!("closed=\"{other}\" must be \"true\" or \"false\""),
                        ))
                    }
                };
                a.finish(&["closed"])?;
                let (points, lines) = vectors(child, "point", source)?;
                geometry = Some(Geometry::Polyline {
                    points,
                    lines,
                    closed,
                    line,
                });
            }
            "circle" => {
                let radius = a.required_number("radius")?;
                let depth = a.required_number("depth")?;
                a.finish(&["radius", "depth"])?;
                no_children(child, source)?;
                if radius <= 0.0 {
                    return Err(err(line, format!("radius must be positive, got {radius}")));
                }
                check_circle_depth(depth / radius).map_err(|m| err(line, m))?;
                geometry = Some(Geometry::Circle {
                    radius,
                    depth,
                    line,
                });
            }
            "rigid" | "craig_bampton" | "mode" => {
                let dof_name = a.required("name")?;
                if !valid_dof_name(dof_name) {
                    return Err(err(
                        line,
                        format!(
                            "DOF name \"{dof_name}\" must start with a letter or '_' and contain \
                             only letters, digits and '_'"
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
                        let word = a.required("kind")?;
                        let kind = RigidKind::parse(word).ok_or_else(|| {
                            err(
                                line,
                                format!("kind=\"{word}\" must be \"sway\", \"heave\" or \"roll\""),
                            )
                        })?;
                        let x = a.optional_number("x", 0.0)?;
                        let y = a.optional_number("y", 0.0)?;
                        a.finish(&["name", "kind", "x", "y"])?;
                        no_children(child, source)?;
                        FileField::Rigid(kind, [x, y])
                    }
                    "craig_bampton" => {
                        let word = a.required("mode")?;
                        let mode = match word.trim().parse::<usize>() {
                            Ok(m) if (1..=6).contains(&m) => m,
                            _ => {
                                return Err(err(
                                    line,
                                    format!("mode=\"{word}\" must be an integer from 1 to 6"),
                                ))
                            }
                        };
                        a.finish(&["name", "mode"])?;
                        no_children(child, source)?;
                        FileField::CraigBampton(mode)
                    }
                    _ => {
                        a.finish(&["name"])?;
                        let (values, _) = vectors(child, "u", source)?;
                        FileField::Vectors(values)
                    }
                };
                dofs.push(FileDof {
                    name: dof_name.to_string(),
                    field,
                    line,
                });
            }
            other => {
                return Err(err(
                    line,
                    format!(
                        "unknown element <{other}> in <hull>; expected contour, circle, rigid, \
                         craig_bampton or mode"
                    ),
                ))
            }
        }
    }

    let geometry = geometry.ok_or_else(|| {
        err(
            root.line,
            "the hull has no geometry: add a <contour> (or a <circle>)".to_string(),
        )
    })?;
    if dofs.is_empty() {
        return Err(err(
            root.line,
            "the hull has no DOFs: add <rigid>, <mode> (or <craig_bampton>) elements".to_string(),
        ));
    }
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
            (Contour::Arc { radius, depth }, None)
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
                        Contour::Polyline { .. } => [f64::NAN; 6],
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
    })
}

fn knots(points: &[Point], closed: bool) -> (Vec<f64>, f64) {
    let n = points.len();
    let segments = if closed { n } else { n - 1 };
    let mut knots = Vec::with_capacity(segments + 1);
    let mut total = 0.0;
    knots.push(0.0);
    for i in 0..segments {
        let (a, b) = (points[i], points[(i + 1) % n]);
        total += (b[0] - a[0]).hypot(b[1] - a[1]);
        knots.push(total);
    }
    for k in knots.iter_mut() {
        *k /= total;
    }
    if let Some(last) = knots.last_mut() {
        *last = 1.0;
    }
    (knots, total)
}

fn cross(a: Point, b: Point) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1]]
}

fn point_segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let ab = sub(b, a);
    let ap = sub(p, a);
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = ((ap[0] * ab[0] + ap[1] * ab[1]) / len2).clamp(0.0, 1.0);
    let d = sub(ap, [t * ab[0], t * ab[1]]);
    d[0].hypot(d[1])
}

fn segments_cross(a: Point, b: Point, c: Point, d: Point) -> bool {
    let d1 = cross(sub(b, a), sub(c, a));
    let d2 = cross(sub(b, a), sub(d, a));
    let d3 = cross(sub(d, c), sub(a, c));
    let d4 = cross(sub(d, c), sub(b, c));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

fn segment_distance(a: Point, b: Point, c: Point, d: Point) -> f64 {
    if segments_cross(a, b, c, d) {
        return 0.0;
    }
    point_segment_distance(a, c, d)
        .min(point_segment_distance(b, c, d))
        .min(point_segment_distance(c, a, b))
        .min(point_segment_distance(d, a, b))
}

/// Checks a file contour; snaps waterline ends to y = 0; returns the vertex order that makes
/// it counter-clockwise when it was clockwise.
fn validate_polyline(
    points: &mut [Point],
    lines: &[usize],
    closed: bool,
    contour_line: usize,
    source: &str,
    notes: &mut Vec<String>,
) -> Result<Option<Vec<usize>>, HullError> {
    let err = |line: usize, m: String| HullError::new(source, Some(line), m);
    let n = points.len();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points.iter() {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let waterline_tol = WATERLINE_TOLERANCE * extent;
    let contact_tol = CONTACT_TOLERANCE * extent;

    for (i, p) in points.iter_mut().enumerate() {
        let end = !closed && (i == 0 || i == n - 1);
        let y = p[1];
        if y > waterline_tol {
            return Err(err(
                lines[i],
                format!(
                    "point ({}, {}) is above the free surface y = 0 (the fluid is y < 0)",
                    p[0], y
                ),
            ));
        }
        if end {
            if y < -waterline_tol {
                let which = if i == 0 { "first" } else { "last" };
                return Err(err(
                    lines[i],
                    format!(
                        "an open contour must end on the free surface y = 0, but its {which} \
                         point has y = {y} (use closed=\"true\" for a submerged body)"
                    ),
                ));
            }
            if y != 0.0 {
                notes.push(format!(
                    "line {}: waterline point y = {y} set to 0 (tolerance {waterline_tol:e} m)",
                    lines[i]
                ));
                p[1] = 0.0;
            }
        } else if y >= -waterline_tol {
            let problem = if closed {
                "a closed contour must stay below the free surface; a hull that pierces it is \
                 an open contour from waterline to waterline"
            } else {
                "only the two end points of an open contour may lie on y = 0"
            };
            return Err(err(
                lines[i],
                format!("point ({}, {y}) touches the free surface: {problem}", p[0]),
            ));
        }
    }

    let segments = if closed { n } else { n - 1 };
    let seg = |i: usize| (points[i], points[(i + 1) % n]);
    for i in 0..segments {
        let (a, b) = seg(i);
        if (b[0] - a[0]).hypot(b[1] - a[1]) <= contact_tol {
            let j = (i + 1) % n;
            let hint = if closed && j == 0 {
                " (a closed contour closes by itself: do not repeat the first point)"
            } else {
                ""
            };
            return Err(err(
                lines[j],
                format!("point repeats the previous point (line {}){hint}", lines[i]),
            ));
        }
    }
    // Consecutive segments must not turn straight back.
    for i in 0..segments {
        if !closed && i + 1 == segments {
            break;
        }
        let (a, b) = seg(i);
        let (_, c) = seg((i + 1) % segments);
        let (u, v) = (sub(b, a), sub(c, b));
        let turn = cross(u, v);
        let dot = u[0] * v[0] + u[1] * v[1];
        if dot < 0.0 && turn.abs() <= 1e-12 * u[0].hypot(u[1]) * v[0].hypot(v[1]) {
            let j = (i + 1) % n;
            return Err(err(
                lines[j],
                format!(
                    "the contour turns straight back on itself at point ({}, {})",
                    b[0], b[1]
                ),
            ));
        }
    }
    // Non-adjacent segments must keep apart.
    for i in 0..segments {
        for j in i + 2..segments {
            if closed && i == 0 && j == segments - 1 {
                continue;
            }
            let (a, b) = seg(i);
            let (c, d) = seg(j);
            if segment_distance(a, b, c, d) <= contact_tol {
                return Err(err(
                    lines[(j + 1) % n],
                    format!(
                        "the contour intersects itself: the segment from line {} to line {} \
                         meets the segment from line {} to line {}",
                        lines[i],
                        lines[(i + 1) % n],
                        lines[j],
                        lines[(j + 1) % n]
                    ),
                ));
            }
        }
    }

    // Orientation: signed area (an open contour closes along the free surface).
    let area: f64 = (0..n)
        .map(|i| cross(points[i], points[(i + 1) % n]))
        .sum::<f64>()
        / 2.0;
    if area.abs() <= contact_tol * extent {
        return Err(err(
            contour_line,
            "the contour encloses no area".to_string(),
        ));
    }
    if area > 0.0 {
        return Ok(None);
    }
    let order: Vec<usize> = if closed {
        std::iter::once(0).chain((1..n).rev()).collect()
    } else {
        (0..n).rev().collect()
    };
    notes.push(format!(
        "line {contour_line}: the contour ran clockwise (body on the right of the direction of \
         travel); its points and the mode vectors were reversed so that the body is on the left{}",
        if closed {
            ""
        } else {
            " and the contour runs from the left waterline to the right one"
        }
    ));
    Ok(Some(order))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5-point open section; lines: hull 2, contour 3, points 4..=8, rigid 10..=12, mode 13.
    const BOX: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<hull name="box" half_beam="2" units="m">
  <contour closed="false">
    <point x="-2" y="0"/>
    <point x="-2" y="-1"/>
    <point x="0" y="-1.5"/>
    <point x="2" y="-1"/>
    <point x="2" y="0"/>
  </contour>
  <rigid name="sway" kind="sway"/>
  <rigid name="heave" kind="heave"/>
  <rigid name="roll" kind="roll" x="0.5" y="-0.5"/>
  <mode name="bottom">
    <u x="0" y="0"/>
    <u x="0.25" y="0"/>
    <u x="0" y="1"/>
    <u x="-0.25" y="0"/>
    <u x="0" y="0"/>
  </mode>
</hull>
"#;

    /// File text with the given points (contour on line 2, points from line 3) and a mode.
    fn hull_xml(points: &[Point], closed: bool) -> String {
        let mut text = String::from("<hull name=\"t\" half_beam=\"1\">\n");
        text.push_str(&format!("<contour closed=\"{closed}\">\n"));
        for p in points {
            text.push_str(&format!("<point x=\"{}\" y=\"{}\"/>\n", p[0], p[1]));
        }
        text.push_str("</contour>\n<rigid name=\"heave\" kind=\"heave\"/>\n<mode name=\"m\">\n");
        for (i, _) in points.iter().enumerate() {
            text.push_str(&format!("<u x=\"{i}\" y=\"1\"/>\n"));
        }
        text.push_str("</mode>\n</hull>\n");
        text
    }

    fn expect_error(text: &str, line: Option<usize>, words: &str) -> HullError {
        let e = Hull::from_xml_str(text, "test.xml").expect_err("should be rejected");
        let shown = e.to_string();
        assert!(shown.starts_with("test.xml:"), "{shown}");
        assert_eq!(e.line(), line, "{shown}");
        assert!(shown.contains(words), "'{shown}' lacks '{words}'");
        e
    }

    fn close(a: Point, b: Point, tol: f64) -> bool {
        (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol
    }

    /// n-th theta-derivative of w from eq. 6, analytically.
    fn w_derivative(c: &[f64; 6], theta: f64, n: u32) -> f64 {
        let shifted = |k: u32| {
            let a = theta + f64::from(k) * std::f64::consts::FRAC_PI_2;
            (a.cos(), a.sin())
        };
        let (cn, sn) = shifted(n);
        let mut v = c[2] * cn + c[3] * sn + theta * (c[4] * cn + c[5] * sn);
        if n >= 1 {
            let (cm, sm) = shifted(n - 1);
            v += f64::from(n) * (c[4] * cm + c[5] * sm);
        }
        match n {
            0 => v + c[0] + c[1] * theta,
            1 => v + c[1],
            _ => v,
        }
    }

    fn end_values(c: &[f64; 6], radius: f64) -> [f64; 6] {
        let (w0, u0, p0) = craig_bampton_fields(c, radius, 0.0);
        let (w1, u1, p1) = craig_bampton_fields(c, radius, PI);
        [u0, w0, p0, u1, w1, p1]
    }

    #[test]
    fn craig_bampton_end_values_are_unit() {
        for radius in [1.0, 2.5, 40.0] {
            let modes = craig_bampton_coefficients(radius);
            for (k, c) in modes.iter().enumerate() {
                let ends = end_values(c, radius);
                for (j, v) in ends.iter().enumerate() {
                    let expected = if j == k { 1.0 } else { 0.0 };
                    // Round-off of a well-conditioned 6x6 solve.
                    assert!(
                        (v - expected).abs() < 1e-12,
                        "R {radius} mode {k} end {j}: {v}"
                    );
                }
            }
        }
        assert!(craig_bampton_coefficients(0.0)[0][0].is_nan());
        assert!(craig_bampton_coefficients(f64::NAN)[3][2].is_nan());
    }

    #[test]
    fn craig_bampton_modes_solve_the_beam_equation() {
        let radius = 1.7;
        for c in craig_bampton_coefficients(radius) {
            let scale = c.iter().map(|x| x.abs()).fold(1.0, f64::max);
            for i in 0..=40 {
                let theta = PI * f64::from(i) / 40.0;
                let residual = w_derivative(&c, theta, 6)
                    + 2.0 * w_derivative(&c, theta, 4)
                    + w_derivative(&c, theta, 2);
                assert!(residual.abs() < 1e-12 * scale, "eq. 4 residual {residual}");
                // u and psi against 6th-order central differences of w.
                let (w, u, psi) = craig_bampton_fields(&c, radius, theta);
                let h = 1e-3;
                let wf = |k: f64| craig_bampton_fields(&c, radius, theta + k * h).0;
                let d1 = (-wf(-3.0) + 9.0 * wf(-2.0) - 45.0 * wf(-1.0) + 45.0 * wf(1.0)
                    - 9.0 * wf(2.0)
                    + wf(3.0))
                    / (60.0 * h);
                let d2 = (2.0 * wf(-3.0) - 27.0 * wf(-2.0) + 270.0 * wf(-1.0) - 490.0 * w
                    + 270.0 * wf(1.0)
                    - 27.0 * wf(2.0)
                    + 2.0 * wf(3.0))
                    / (180.0 * h * h);
                // Truncation h^6 plus round-off ~1e-16 / h^2.
                assert!((u - d1).abs() < 1e-9 * scale, "u {u} vs {d1}");
                assert!((psi - (d2 + w) / radius).abs() < 1e-8 * scale, "psi");
                assert!((w - w_derivative(&c, theta, 0)).abs() < 1e-14 * scale);
                assert!((u - w_derivative(&c, theta, 1)).abs() < 1e-13 * scale);
            }
        }
    }

    #[test]
    fn craig_bampton_modes_reproduce_rigid_motions() {
        let radius = 2.0;
        let hull = Hull::semicircle(radius).unwrap();
        let cb = craig_bampton_coefficients(radius);
        // (rigid DOF index, weights of cb1..cb6)
        let cases = [
            (0, [1.0, 0.0, 0.0, -1.0, 0.0, 0.0]),
            (1, [0.0, -1.0, 0.0, 0.0, 1.0, 0.0]),
            (2, [0.0, radius, 1.0, 0.0, radius, 1.0]),
        ];
        for (dof, weights) in cases {
            // The weights are the rigid motion's own end values.
            let mut c = [0.0; 6];
            for (m, wgt) in cb.iter().zip(weights) {
                for (ci, mi) in c.iter_mut().zip(m) {
                    *ci += wgt * mi;
                }
            }
            let ends = end_values(&c, radius);
            assert!(ends.iter().zip(weights).all(|(a, b)| (a - b).abs() < 1e-12));
            for i in 0..=50 {
                let s = f64::from(i) / 50.0;
                let combined = craig_bampton_displacement(&c, radius, PI * s);
                let mut summed = [0.0; 2];
                for (k, wgt) in weights.iter().enumerate() {
                    let d = hull.displacement(3 + k, s);
                    summed = [summed[0] + wgt * d[0], summed[1] + wgt * d[1]];
                }
                let exact = hull.displacement(dof, s);
                assert!(close(combined, exact, 1e-12 * radius), "dof {dof} s {s}");
                assert!(close(summed, exact, 1e-12 * radius), "dof {dof} s {s}");
            }
        }
    }

    /// Seed Table 1, transcribed (R = 1.3), rows = modes 1..6, columns C1..C6.
    fn seed_table_1(r: f64) -> [[f64; 6]; 6] {
        let d = PI * PI - 8.0;
        [
            [-2.0 * PI / d, -4.0 / d, 2.0 * PI / d, 4.0 / d, 0.0, PI / d],
            [0.0, 0.0, 0.0, 1.0 / PI, -1.0 / PI, 0.0],
            [
                -4.0 * r / d,
                -PI * r / d,
                4.0 * r / d,
                2.0 * (PI * PI - 4.0) * r / (PI * d),
                -r / PI,
                2.0 * r / d,
            ],
            [
                2.0 * PI / d,
                4.0 / d,
                -2.0 * PI / d,
                (4.0 - PI * PI) / d,
                0.0,
                -PI / d,
            ],
            [0.0, 0.0, 0.0, -1.0 / PI, 1.0 / PI, 0.0],
            [
                (PI * PI - 4.0) * r / d,
                PI * r / d,
                -(PI * PI - 4.0) * r / d,
                -8.0 * r / (PI * d),
                -r / PI,
                -2.0 * r / d,
            ],
        ]
    }

    /// Finding: w_table(-theta) (C2, C4, C5 negated) gives rows 1..6 =
    /// (-cb4, -cb5, cb6, cb1, cb5, cb3): printed row 2 = -row 5, so cb2 is missing; row 5 with
    /// C3 = 1 added is cb2, giving the consistent pattern (-cb4, -cb5, cb6, cb1, cb2, cb3):
    /// the table's modes 1-3 sit at our theta = pi end, 4-6 at theta = 0.
    #[test]
    fn seed_table_1_after_theta_flip() {
        let r = 1.3;
        let table = seed_table_1(r);
        let cb = craig_bampton_coefficients(r);
        let flip = |c: [f64; 6]| [c[0], -c[1], c[2], -c[3], -c[4], c[5]];
        let same = |a: [f64; 6], sign: f64, b: [f64; 6]| {
            a.iter().zip(b).all(|(x, y)| (x - sign * y).abs() < 1e-12)
        };
        let expected = [(-1.0, 3), (-1.0, 4), (1.0, 5), (1.0, 0), (1.0, 4), (1.0, 2)];
        for (row, (sign, mode)) in expected.iter().enumerate() {
            assert!(
                same(flip(table[row]), *sign, cb[*mode]),
                "table row {} vs cb{}",
                row + 1,
                mode + 1
            );
        }
        // Without the flip, rows 1, 3, 4, 6 are none of our modes (either sign).
        for row in [0, 2, 3, 5] {
            let row = table[row];
            assert!(cb
                .iter()
                .all(|m| !same(row, 1.0, *m) && !same(row, -1.0, *m)));
        }
        // Printed rows 2 and 5 are negatives: the printed set has rank 5.
        assert!(same(table[1], -1.0, table[4]));
        let mut printed = nalgebra::Matrix6::<f64>::zeros();
        for (i, row) in table.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                printed[(i, j)] = *v;
            }
        }
        let singular = printed.singular_values();
        assert!(singular.min() < 1e-12 * singular.max());
        // Row 5 with C3 = 1 is our cb2 after the flip.
        let mut repaired = table[4];
        repaired[2] = 1.0;
        assert!(same(flip(repaired), 1.0, cb[1]));
    }

    #[test]
    fn semicircle_geometry() {
        let r = 3.0;
        let h = Hull::semicircle(r).unwrap();
        assert_eq!(h.name(), "semicircle");
        assert!(!h.is_closed());
        assert_eq!(h.reference_half_beam(), r);
        assert_eq!(
            h.dof_names(),
            ["sway", "heave", "roll", "cb1", "cb2", "cb3", "cb4", "cb5", "cb6"]
        );
        assert_eq!(h.breakpoints(), vec![0.0, 1.0]);
        assert!(close(h.point(0.0), [-r, 0.0], 1e-15));
        assert!(close(h.point(0.5), [0.0, -r], 1e-15));
        // Waterline ends exactly on y = 0.
        assert_eq!(h.point(0.0), [-r, 0.0]);
        assert_eq!(h.point(1.0), [r, 0.0]);
        assert!((h.contour_length() - PI * r).abs() < 1e-14);
        for i in 0..100 {
            let s = (f64::from(i) + 0.5) / 100.0;
            let p = h.point(s);
            assert!((p[0].hypot(p[1]) - r).abs() < 1e-14);
            // Normal into the body = towards the centre.
            assert!(close(h.normal(s), [-p[0] / r, -p[1] / r], 1e-15));
            // Arc length: |dP/ds| = pi R; tangent = dP/ds / |dP/ds|.
            let ds = 1e-6;
            let (a, b) = (h.point(s - ds), h.point(s + ds));
            let d = [(b[0] - a[0]) / (2.0 * ds), (b[1] - a[1]) / (2.0 * ds)];
            assert!((d[0].hypot(d[1]) - PI * r).abs() < 1e-6);
            let t = h.tangent(s);
            assert!(close(t, [d[0] / (PI * r), d[1] / (PI * r)], 1e-8));
            // Roll about the origin is purely tangential on the circle.
            assert!(h.normal_displacement(2, s).abs() < 1e-14);
            assert!(close(h.displacement(2, s), [-p[1], p[0]], 1e-15));
        }
        assert!(h.displacement(9, 0.5)[0].is_nan());
        assert!(Hull::semicircle(0.0).is_err());
        assert!(Hull::semicircle(f64::INFINITY).is_err());
    }

    #[test]
    fn circle_geometry_and_depth_checks() {
        let (r, hr) = (2.0, 1.5);
        let c = Hull::circle(r, hr).unwrap();
        assert_eq!(c.name(), "circle");
        assert!(c.is_closed());
        assert_eq!(c.dof_names(), ["sway", "heave", "roll"]);
        assert!(close(c.point(0.0), [-r, -hr * r], 1e-15));
        assert_eq!(c.point(1.0), c.point(0.0));
        // Mirror symmetries, with the two halves evaluated from opposite ends: the circle about
        // y = -H (P(1 - s)), the semicircle about x = 0 (P(1 - s)).
        let semi = Hull::semicircle(r).unwrap();
        for s in [0.1, 0.25, 0.4, 0.5] {
            let (p, q) = (c.point(s), c.point(1.0 - s));
            assert!((p[0] - q[0]).abs() < 1e-15 && (p[1] + q[1] + 2.0 * hr * r).abs() < 1e-14);
            let (p, q) = (semi.point(s), semi.point(1.0 - s));
            assert!((p[0] + q[0]).abs() < 1e-15 && (p[1] - q[1]).abs() < 1e-15);
        }
        let centre = [0.0, -hr * r];
        let mut area = 0.0;
        let n = 400;
        for i in 0..n {
            let s = f64::from(i) / f64::from(n);
            let (p, q) = (c.point(s), c.point(s + 1.0 / f64::from(n)));
            area += cross(p, q) / 2.0;
            let d = sub(p, centre);
            assert!((d[0].hypot(d[1]) - r).abs() < 1e-14);
            assert!(close(c.normal(s), [-d[0] / r, -d[1] / r], 1e-15));
            assert!(p[1] < 0.0);
        }
        // Counter-clockwise: positive area close to pi R^2 (polygon of 400 sides).
        assert!((area - PI * r * r).abs() < 1e-3 * PI * r * r);
        // Roll about the free-surface origin: (-y, x).
        let p = c.point(0.3);
        assert!(close(c.displacement(2, 0.3), [-p[1], p[0]], 1e-15));

        for bad in [0.5, 1.0, -1.0, f64::NAN] {
            let e = Hull::circle(r, bad).unwrap_err();
            assert_eq!(e.source_name(), "built-in circle");
            assert!(e.message().contains("depth/radius"), "{e}");
        }
        assert!(Hull::circle(r, 1.0)
            .unwrap_err()
            .to_string()
            .contains("pierces"));
        let semi = Hull::circle(r, 0.0).unwrap();
        assert_eq!(
            semi.fingerprint(),
            Hull::semicircle(r).unwrap().fingerprint()
        );
    }

    #[test]
    fn file_contour_fields() {
        let h = Hull::from_xml_str(BOX, "box.xml").unwrap();
        assert_eq!(h.name(), "box");
        assert!(h.notes().is_empty());
        assert!(!h.is_closed());
        assert_eq!(h.dof_names(), ["sway", "heave", "roll", "bottom"]);
        assert_eq!(h.dof_kind(3), Some(DofKind::Elastic));
        assert_eq!(
            h.dof_kind(2),
            Some(DofKind::Rigid {
                kind: RigidKind::Roll,
                reference: [0.5, -0.5]
            })
        );
        let side = 0.5_f64.hypot(2.0);
        let length = 2.0 + 2.0 * side;
        assert!((h.contour_length() - length).abs() < 1e-14);
        let knots = h.breakpoints();
        let expected = [0.0, 1.0, 1.0 + side, 1.0 + 2.0 * side, length].map(|k| k / length);
        assert!(knots
            .iter()
            .zip(expected)
            .all(|(a, b)| (a - b).abs() < 1e-15));
        let vertices = [
            [-2.0, 0.0],
            [-2.0, -1.0],
            [0.0, -1.5],
            [2.0, -1.0],
            [2.0, 0.0],
        ];
        for (k, v) in knots.iter().zip(vertices) {
            assert!(close(h.point(*k), v, 1e-14));
        }
        // s proportional to arc length inside a segment; linear mode interpolation.
        let (s0, s1) = (
            knots[1] + 0.1 * (knots[2] - knots[1]),
            knots[1] + 0.7 * (knots[2] - knots[1]),
        );
        let d = sub(h.point(s1), h.point(s0));
        assert!((d[0].hypot(d[1]) - (s1 - s0) * length).abs() < 1e-14);
        assert!(close(h.displacement(3, s0), [0.25 * 0.9, 0.1], 1e-14));
        assert!(close(h.displacement(3, knots[2]), [0.0, 1.0], 1e-14));
        // Normal into the body: up on the bottom, right on the left side.
        assert!(close(
            h.normal(0.5 * (knots[0] + knots[1])),
            [1.0, 0.0],
            1e-15
        ));
        assert!(h.normal(s0)[1] > 0.9);
        let p = h.point(0.3);
        assert!(close(
            h.displacement(2, 0.3),
            [-(p[1] + 0.5), p[0] - 0.5],
            1e-15
        ));
        assert!(close(h.displacement(0, 0.3), [1.0, 0.0], 0.0));
        assert!(close(h.displacement(1, 0.3), [0.0, 1.0], 0.0));
        // Out-of-range s clamps.
        assert!(close(h.point(-1.0), [-2.0, 0.0], 0.0));
        assert!(close(h.point(2.0), [2.0, 0.0], 0.0));
    }

    #[test]
    fn closed_file_contour() {
        let square = [[-1.0, -2.0], [1.0, -2.0], [1.0, -1.0], [-1.0, -1.0]];
        let h = Hull::from_xml_str(&hull_xml(&square, true), "sq.xml").unwrap();
        assert!(h.is_closed());
        assert!(h.notes().is_empty());
        let expected = [0.0, 2.0, 3.0, 5.0, 6.0].map(|k| k / 6.0);
        assert!(h
            .breakpoints()
            .iter()
            .zip(expected)
            .all(|(a, b)| (a - b).abs() < 1e-15));
        assert!(close(h.point(1.0), square[0], 0.0));
        assert!(close(h.point(11.0 / 12.0), [-1.0, -1.5], 1e-15));
        // Mode vectors wrap: between the last point (x = 3) and the first (x = 0).
        assert!(close(h.displacement(1, 11.0 / 12.0), [1.5, 1.0], 1e-15));
        assert!(close(h.normal(1.0 / 6.0), [0.0, 1.0], 1e-15));
        assert!(close(h.normal(11.0 / 12.0), [1.0, 0.0], 1e-15));
    }

    #[test]
    fn clockwise_contours_are_reversed_with_a_note() {
        let ccw = Hull::from_xml_str(BOX, "box.xml").unwrap();
        // The same section written right-to-left, with the mode vectors in the same order.
        let mut lines: Vec<&str> = BOX.lines().collect();
        lines[3..8].reverse();
        lines[13..18].reverse();
        let cw = Hull::from_xml_str(&lines.join("\n"), "box.xml").unwrap();
        assert_eq!(cw.notes().len(), 1);
        assert!(cw.notes()[0].contains("reversed"), "{:?}", cw.notes());
        assert!(ccw.notes().is_empty());
        assert_eq!(cw.fingerprint(), ccw.fingerprint());
        assert_eq!(cw.to_xml_string(), ccw.to_xml_string());

        let square = [[-1.0, -2.0], [-1.0, -1.0], [1.0, -1.0], [1.0, -2.0]];
        let h = Hull::from_xml_str(&hull_xml(&square, true), "sq.xml").unwrap();
        assert_eq!(h.notes().len(), 1);
        // Start point kept, order reversed; vectors follow their points.
        assert!(close(h.point(0.0), [-1.0, -2.0], 0.0));
        assert!(close(h.point(1.0 / 3.0), [1.0, -2.0], 1e-15));
        assert!(close(h.displacement(1, 1.0 / 3.0), [3.0, 1.0], 1e-15));
        assert!(close(h.normal(1.0 / 6.0), [0.0, 1.0], 1e-15));
    }

    #[test]
    fn waterline_points_snap_within_tolerance() {
        let text = BOX.replace(r#"<point x="2" y="0"/>"#, r#"<point x="2" y="1e-9"/>"#);
        let h = Hull::from_xml_str(&text, "box.xml").unwrap();
        assert_eq!(h.point(1.0), [2.0, 0.0]);
        assert!(h.notes()[0].contains("line 8"), "{:?}", h.notes());
        // 4 m wide section: tolerance 4 micrometres.
        let text = BOX.replace(r#"<point x="2" y="0"/>"#, r#"<point x="2" y="1e-5"/>"#);
        expect_error(&text, Some(8), "above the free surface");
    }

    #[test]
    fn rejects_points_above_the_free_surface() {
        let text = BOX.replace(r#"y="-1.5""#, r#"y="0.3""#);
        expect_error(&text, Some(6), "above the free surface");
    }

    #[test]
    fn rejects_open_ends_off_the_waterline() {
        let text = BOX.replace(r#"<point x="2" y="0"/>"#, r#"<point x="2" y="-0.2"/>"#);
        expect_error(&text, Some(8), "must end on the free surface");
        let text = BOX.replace(r#"<point x="-2" y="0"/>"#, r#"<point x="-2" y="-0.2"/>"#);
        expect_error(&text, Some(4), "first point");
    }

    #[test]
    fn rejects_contours_touching_the_free_surface_inside() {
        let pts = [
            [-2.0, 0.0],
            [-1.0, -1.0],
            [0.0, 0.0],
            [1.0, -1.0],
            [2.0, 0.0],
        ];
        expect_error(&hull_xml(&pts, false), Some(5), "only the two end points");
        let pts = [[-1.0, -2.0], [1.0, -2.0], [0.0, 0.0]];
        expect_error(
            &hull_xml(&pts, true),
            Some(5),
            "must stay below the free surface",
        );
    }

    #[test]
    fn rejects_self_intersection() {
        let pts = [
            [-2.0, 0.0],
            [1.0, -2.0],
            [1.0, -1.0],
            [-1.0, -2.0],
            [2.0, 0.0],
        ];
        expect_error(&hull_xml(&pts, false), Some(6), "intersects itself");
        // A figure of eight (closed) and a touching vertex.
        let pts = [[-1.0, -2.0], [1.0, -1.0], [1.0, -2.0], [-1.0, -1.0]];
        expect_error(&hull_xml(&pts, true), Some(6), "intersects itself");
        let pts = [
            [-2.0, 0.0],
            [0.0, -2.0],
            [1.0, -1.0],
            [0.0, -1.0],
            [0.5, -1.5],
            [2.0, 0.0],
        ];
        expect_error(&hull_xml(&pts, false), Some(7), "intersects itself");
        // Straight back along the previous segment.
        let pts = [
            [-2.0, 0.0],
            [-2.0, -2.0],
            [-2.0, -1.0],
            [2.0, -1.0],
            [2.0, 0.0],
        ];
        expect_error(&hull_xml(&pts, false), Some(4), "turns straight back");
        // A closed contour repeating its first point.
        let pts = [[-1.0, -2.0], [1.0, -2.0], [1.0, -1.0], [-1.0, -2.0]];
        expect_error(
            &hull_xml(&pts, true),
            Some(3),
            "do not repeat the first point",
        );
    }

    #[test]
    fn rejects_too_few_points() {
        expect_error(
            &hull_xml(&[[-1.0, 0.0], [1.0, 0.0]], false),
            Some(2),
            "at least 3",
        );
        expect_error(&hull_xml(&[], true), Some(2), "has 0 points");
    }

    #[test]
    fn rejects_bad_numbers() {
        for (bad, words) in [
            ("NaN", "not a finite number"),
            ("inf", "not a finite number"),
            ("-infinity", "not a finite number"),
            ("1,5", "not a number"),
            ("", "not a number"),
        ] {
            let text = BOX.replace(r#"y="-1.5""#, &format!("y=\"{bad}\""));
            let e = expect_error(&text, Some(6), words);
            assert!(e.message().contains("<point>"), "{e}");
        }
        let text = BOX.replace(r#"half_beam="2""#, r#"half_beam="two""#);
        expect_error(&text, Some(2), "half_beam=\"two\"");
        let text = BOX.replace(r#"<u x="0" y="1"/>"#, r#"<u x="0" y="nan"/>"#);
        expect_error(&text, Some(16), "not a finite number");
        let text = BOX.replace(r#"x="0.5" y="-0.5""#, r#"x="0.5" y="1e999""#);
        expect_error(&text, Some(12), "not a finite number");
    }

    #[test]
    fn rejects_wrong_mode_vector_counts() {
        let text = BOX.replace("    <u x=\"0\" y=\"1\"/>\n", "");
        expect_error(
            &text,
            Some(13),
            "mode 'bottom' has 4 vectors but the contour has 5 points",
        );
        let text = BOX.replace(
            "<u x=\"0\" y=\"1\"/>",
            "<u x=\"0\" y=\"1\"/><u x=\"0\" y=\"1\"/>",
        );
        expect_error(&text, Some(13), "has 6 vectors");
        let text = BOX
            .replace(r#"x="0.25""#, r#"x="0""#)
            .replace(r#"x="-0.25""#, r#"x="0""#)
            .replace(r#"<u x="0" y="1"/>"#, r#"<u x="0" y="0"/>"#);
        expect_error(&text, Some(13), "zero at every point");
    }

    #[test]
    fn rejects_duplicate_and_bad_dof_names() {
        let text = BOX.replace(r#"name="heave""#, r#"name="sway""#);
        expect_error(
            &text,
            Some(11),
            "duplicate DOF name 'sway' (first defined on line 10)",
        );
        let text = BOX.replace(r#"name="bottom""#, r#"name="roll""#);
        expect_error(&text, Some(13), "duplicate DOF name 'roll'");
        let text = BOX.replace(r#"name="bottom""#, r#"name="bottom plate""#);
        expect_error(&text, Some(13), "must start with a letter");
        let text = BOX.replace(r#"kind="heave""#, r#"kind="pitch""#);
        expect_error(&text, Some(11), "kind=\"pitch\"");
    }

    #[test]
    fn rejects_unknown_elements_and_attributes() {
        let text = BOX.replace(
            "  <rigid name=\"sway\"",
            "  <keel/>\n  <rigid name=\"sway\"",
        );
        expect_error(&text, Some(10), "unknown element <keel>");
        let text = BOX.replace(r#"<point x="0" y="-1.5"/>"#, r#"<pt x="0" y="-1.5"/>"#);
        expect_error(&text, Some(6), "unknown element <pt> in <contour>");
        let text = BOX.replace(r#"kind="sway""#, r#"kind="sway" z="1""#);
        expect_error(&text, Some(10), "unknown attribute z in <rigid>");
        let text = BOX.replace(r#"units="m""#, r#"units="m" colour="red""#);
        expect_error(&text, Some(2), "unknown attribute colour in <hull>");
        let text = BOX.replace(r#"units="m""#, r#"units="ft""#);
        expect_error(&text, Some(2), "units=\"ft\"");
        let text = BOX.replace(
            r#"<point x="0" y="-1.5"/>"#,
            r#"<point x="0" y="-1.5">1</point>"#,
        );
        expect_error(&text, Some(6), "unexpected text");
        let text = BOX.replace(
            r#"<point x="0" y="-1.5"/>"#,
            r#"<point x="0" x="1" y="-1.5"/>"#,
        );
        expect_error(&text, Some(6), "bad attribute");
    }

    #[test]
    fn rejects_missing_or_bad_half_beam() {
        let text = BOX.replace(r#" half_beam="2""#, "");
        expect_error(&text, Some(2), "missing the attribute half_beam");
        for bad in ["0", "-3"] {
            let text = BOX.replace(r#"half_beam="2""#, &format!("half_beam=\"{bad}\""));
            expect_error(&text, Some(2), "half_beam must be positive");
        }
    }

    #[test]
    fn rejects_malformed_xml_and_structure() {
        let text = BOX.replace("</mode>", "</mod>");
        expect_error(&text, Some(19), "malformed XML");
        let text = BOX.replace("</hull>\n", "");
        let e = Hull::from_xml_str(&text, "test.xml").unwrap_err();
        assert!(e.to_string().starts_with("test.xml"), "{e}");
        let text = format!("{BOX}<hull name=\"b\" half_beam=\"1\"/>\n");
        expect_error(&text, Some(21), "second top-level element");
        expect_error("<ship/>", Some(1), "expected <hull>");
        expect_error("<hull name=\"a\" half_beam=\"1\"/>", Some(1), "no geometry");
        let text = BOX.replace(
            "  <contour",
            "  <circle radius=\"1\" depth=\"0\"/>\n  <contour",
        );
        expect_error(&text, Some(4), "second geometry");
        let e = Hull::from_file(Path::new("/nonexistent/hull.xml")).unwrap_err();
        assert_eq!(e.source_name(), "/nonexistent/hull.xml");
        assert!(e.message().contains("cannot read"));
    }

    #[test]
    fn circle_elements_in_files() {
        let semi = Hull::semicircle(1.5).unwrap();
        let text = semi.to_xml_string();
        assert!(
            text.contains("<circle radius=\"1.5\" depth=\"0.0\"/>"),
            "{text}"
        );
        let back = Hull::from_xml_str(&text, "semi.xml").unwrap();
        assert_eq!(back.fingerprint(), semi.fingerprint());
        for dof in 0..semi.dof_count() {
            for s in [0.0, 0.13, 0.5, 0.77, 1.0] {
                assert_eq!(back.displacement(dof, s), semi.displacement(dof, s));
            }
        }
        let sub = "<hull name=\"c\" half_beam=\"1\">\n<circle radius=\"1\" depth=\"0.5\"/>\n\
                   <rigid name=\"sway\" kind=\"sway\"/>\n</hull>";
        expect_error(sub, Some(2), "pierces");
        let cb = sub.replace("0.5", "2").replace(
            "<rigid name=\"sway\" kind=\"sway\"/>",
            "<craig_bampton name=\"a\" mode=\"1\"/>",
        );
        expect_error(&cb, Some(3), "needs the semicircle");
        let text = BOX.replace(
            "<rigid name=\"sway\" kind=\"sway\"/>",
            "<craig_bampton name=\"cb1\" mode=\"1\"/>",
        );
        expect_error(&text, Some(10), "needs the built-in semicircle");
        let circle = Hull::circle(2.0, 3.0).unwrap();
        let back = Hull::from_xml_str(&circle.to_xml_string(), "c.xml").unwrap();
        assert_eq!(back.to_xml_string(), circle.to_xml_string());
        assert!(back.is_closed());
    }

    #[test]
    fn xml_round_trip_and_fingerprints() {
        let h = Hull::from_xml_str(BOX, "box.xml").unwrap();
        let text = h.to_xml_string();
        let back = Hull::from_xml_str(&text, "canonical.xml").unwrap();
        assert_eq!(back.to_xml_string(), text);
        assert_eq!(back.fingerprint(), h.fingerprint());
        assert_eq!(h.fingerprint().len(), 16);
        for s in [0.0, 0.2, 0.41, 0.9, 1.0] {
            for dof in 0..4 {
                assert_eq!(back.displacement(dof, s), h.displacement(dof, s));
            }
        }
        // Any change to the hull changes the fingerprint.
        let variants = [
            BOX.replace(r#"y="-1.5""#, r#"y="-1.5000000000000002""#),
            BOX.replace(r#"name="box""#, r#"name="box2""#),
            BOX.replace(r#"half_beam="2""#, r#"half_beam="2.5""#),
            BOX.replace(r#"x="0.5" y="-0.5""#, r#"x="0.5" y="-0.25""#),
            BOX.replace(r#"<u x="0" y="1"/>"#, r#"<u x="0" y="2"/>"#),
            BOX.replace(r#"name="bottom""#, r#"name="bottom1""#),
        ];
        let mut prints = vec![h.fingerprint()];
        for v in &variants {
            prints.push(Hull::from_xml_str(v, "v.xml").unwrap().fingerprint());
        }
        prints.push(
            h.select_dofs(&["heave", "sway", "roll", "bottom"])
                .unwrap()
                .fingerprint(),
        );
        prints.push(Hull::semicircle(1.0).unwrap().fingerprint());
        prints.push(Hull::semicircle(1.0 + 1e-15).unwrap().fingerprint());
        prints.push(Hull::circle(1.0, 2.0).unwrap().fingerprint());
        prints.push(Hull::circle(1.0, 2.5).unwrap().fingerprint());
        let count = prints.len();
        prints.sort();
        prints.dedup();
        assert_eq!(prints.len(), count);
        // Escaped characters and comments are read.
        let text = BOX
            .replace(r#"name="box""#, "name=\"box&#45;a\"")
            .replace("<contour", "<!-- written by hand -->\n  <contour");
        assert_eq!(Hull::from_xml_str(&text, "b.xml").unwrap().name(), "box-a");
    }

    #[test]
    fn select_dofs_keeps_order_and_checks_names() {
        let h = Hull::semicircle(1.0).unwrap();
        let sel = h.select_dofs(&["cb4", "sway", "cb1"]).unwrap();
        assert_eq!(sel.dof_names(), ["cb4", "sway", "cb1"]);
        assert_eq!(sel.displacement(0, 0.3), h.displacement(6, 0.3));
        assert_eq!(sel.dof_kind(0), Some(DofKind::CraigBampton { mode: 4 }));
        for (names, words) in [
            (&["sway", "pitch"][..], "unknown DOF 'pitch'"),
            (&["sway", "sway"][..], "selected twice"),
            (&[][..], "no DOFs selected"),
        ] {
            let e = h.select_dofs(names).unwrap_err();
            assert!(e.message().contains(words), "{e}");
            assert!(
                e.message()
                    .contains("sway heave roll cb1 cb2 cb3 cb4 cb5 cb6"),
                "{e}"
            );
            assert_eq!(e.source_name(), "semicircle");
        }
    }
}
