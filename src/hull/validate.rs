//! Checks of a hull file's contour (a polyline): points below the free surface, open ends on
//! it (snapped within a tolerance), no repeated points, no turning straight back, no
//! self-contact, a nonzero area and counter-clockwise orientation (a clockwise contour is
//! reversed with a note); and the arc-length parameter `s` of its vertices.

use super::contact::first_contact;
use super::{HullError, Point};

/// Relative tolerance (times the contour's largest extent) for waterline points on y = 0.
const WATERLINE_TOLERANCE: f64 = 1e-6;
/// Relative tolerance (times the contour's largest extent) for contour self-contact.
const CONTACT_TOLERANCE: f64 = 1e-9;

/// Arc-length parameter of each vertex (closed: one more, 1.0 at the start again) and
/// the total length.
pub(super) fn knots(points: &[Point], closed: bool) -> (Vec<f64>, f64) {
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

pub(super) fn cross(a: Point, b: Point) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

pub(super) fn sub(a: Point, b: Point) -> Point {
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

pub(super) fn segment_distance(a: Point, b: Point, c: Point, d: Point) -> f64 {
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
pub(super) fn validate_polyline(
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
    if let Some((i, j)) = first_contact(points, segments, closed, contact_tol) {
        return Err(err(
            lines[(j + 1) % n],
            format!(
                "the contour intersects itself: the segment from line {} to line {} meets the \
                 segment from line {} to line {}",
                lines[i],
                lines[(i + 1) % n],
                lines[j],
                lines[(j + 1) % n]
            ),
        ));
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
