//! Self-contact of a contour: the first pair of non-adjacent segments closer than a
//! tolerance, found through a uniform grid of cells about one mean segment long.
//!
//! Each segment is entered in the cells its bounding box (grown by the tolerance) covers, and
//! only segments that share a cell are compared: O(n) work for the contours of real hulls,
//! whose segments are of comparable length. Inputs that crowd many long segments into the
//! same cells (more than [`GRID_WORK_PER_SEGMENT`] entries or pairs per segment) are compared
//! pair by pair instead, which the contour's point limit bounds.

use super::validate::segment_distance;
use super::Point;

/// Grid entries and candidate pairs allowed per segment before the pairwise comparison is
/// used instead.
const GRID_WORK_PER_SEGMENT: usize = 64;

/// The first pair `(i, j)`, `i < j` in lexicographic order, of segments that are not
/// neighbours along the contour (`j >= i + 2`, and for a closed contour not the first and the
/// last) and lie within `tolerance` of each other. Segment `k` runs from `points[k]` to
/// `points[(k + 1) % n]`; there are `segments` of them.
pub(super) fn first_contact(
    points: &[Point],
    segments: usize,
    closed: bool,
    tolerance: f64,
) -> Option<(usize, usize)> {
    let contour = Segments {
        points,
        segments,
        closed,
        tolerance,
    };
    grid_contact(&contour).unwrap_or_else(|| {
        (0..segments).find_map(|i| {
            (i + 2..segments)
                .find(|&j| contour.touch(i, j))
                .map(|j| (i, j))
        })
    })
}

/// The segments of a contour and the contact tolerance.
struct Segments<'a> {
    points: &'a [Point],
    segments: usize,
    closed: bool,
    tolerance: f64,
}

impl Segments<'_> {
    /// Segment `k`: its start and end.
    fn segment(&self, k: usize) -> (Point, Point) {
        let n = self.points.len();
        (self.points[k], self.points[(k + 1) % n])
    }

    /// Segments `i < j` are not neighbours along the contour and lie within the tolerance.
    fn touch(&self, i: usize, j: usize) -> bool {
        let neighbours = j < i + 2 || (self.closed && i == 0 && j + 1 == self.segments);
        let ((a, b), (c, d)) = (self.segment(i), self.segment(j));
        !neighbours && segment_distance(a, b, c, d) <= self.tolerance
    }
}

/// [`first_contact`] through the grid, or `None` when the grid would exceed its work budget
/// (or the contour is too small to need one).
fn grid_contact(contour: &Segments) -> Option<Option<(usize, usize)>> {
    let (segments, tolerance) = (contour.segments, contour.tolerance);
    let seg = |k: usize| contour.segment(k);
    let touch = |i: usize, j: usize| contour.touch(i, j);
    if segments < 16 {
        return None;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut length = 0.0;
    for k in 0..segments {
        let (a, b) = seg(k);
        length += (b[0] - a[0]).hypot(b[1] - a[1]);
        for c in 0..2 {
            lo[c] = lo[c].min(a[c].min(b[c]) - tolerance);
            hi[c] = hi[c].max(a[c].max(b[c]) + tolerance);
        }
    }
    let span = [hi[0] - lo[0], hi[1] - lo[1]];
    // Cells about one mean segment long, at most about 4 per segment.
    let area_cell = (span[0] * span[1] / (4 * segments) as f64).sqrt();
    let cell = (length / segments as f64).max(area_cell);
    if !(cell.is_finite() && cell > 0.0) {
        return None;
    }
    let count = |c: usize| ((span[c] / cell).floor() as usize).saturating_add(1);
    let (columns, rows) = (count(0), count(1));
    let budget = GRID_WORK_PER_SEGMENT.saturating_mul(segments);
    if columns.saturating_mul(rows) > budget {
        return None;
    }
    let index = |x: f64, c: usize, limit: usize| {
        (((x - lo[c]) / cell).floor().max(0.0) as usize).min(limit - 1)
    };
    let mut cells: Vec<Vec<usize>> = vec![Vec::new(); columns * rows];
    let mut entries = 0usize;
    for k in 0..segments {
        let (a, b) = seg(k);
        let (x0, x1) = (a[0].min(b[0]) - tolerance, a[0].max(b[0]) + tolerance);
        let (y0, y1) = (a[1].min(b[1]) - tolerance, a[1].max(b[1]) + tolerance);
        let (c0, c1) = (index(x0, 0, columns), index(x1, 0, columns));
        let (r0, r1) = (index(y0, 1, rows), index(y1, 1, rows));
        entries += (c1 - c0 + 1) * (r1 - r0 + 1);
        if entries > budget {
            return None;
        }
        for r in r0..=r1 {
            for c in c0..=c1 {
                cells[r * columns + c].push(k);
            }
        }
    }
    let pairs: usize = cells.iter().map(|c| c.len() * c.len() / 2).sum();
    if pairs > budget {
        return None;
    }
    let mut first: Option<(usize, usize)> = None;
    for members in &cells {
        for (x, &i) in members.iter().enumerate() {
            for &j in &members[x + 1..] {
                let pair = (i.min(j), i.max(j));
                if first.is_some_and(|f| f <= pair) {
                    continue;
                }
                if touch(pair.0, pair.1) {
                    first = Some(pair);
                }
            }
        }
    }
    Some(first)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed polygon of `n` points on a circle of radius 1.
    fn circle(n: usize) -> Vec<Point> {
        (0..n)
            .map(|k| {
                let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                [t.cos(), t.sin() - 2.0]
            })
            .collect()
    }

    /// The closed contour of `points` at the tolerance 1e-9.
    fn contour(points: &[Point]) -> Segments<'_> {
        Segments {
            points,
            segments: points.len(),
            closed: true,
            tolerance: 1e-9,
        }
    }

    /// The plain comparison of every pair, for reference.
    fn every_pair(
        points: &[Point],
        segments: usize,
        closed: bool,
        tol: f64,
    ) -> Option<(usize, usize)> {
        let n = points.len();
        let seg = |k: usize| (points[k], points[(k + 1) % n]);
        (0..segments).find_map(|i| {
            (i + 2..segments)
                .filter(|&j| !(closed && i == 0 && j + 1 == segments))
                .find(|&j| {
                    let ((a, b), (c, d)) = (seg(i), seg(j));
                    segment_distance(a, b, c, d) <= tol
                })
                .map(|j| (i, j))
        })
    }

    #[test]
    fn the_grid_finds_the_same_first_contact_as_every_pair() {
        let mut rng = crate::numerics::SplitMix64::new(7);
        for case in 0..200 {
            let n = 16 + case % 60;
            let mut points = circle(n);
            // Pull a few points across the polygon so that segments meet (or nearly).
            for _ in 0..case % 4 {
                let k = (rng.uniform() * n as f64) as usize % n;
                points[k] = [rng.uniform() * 2.0 - 1.0, rng.uniform() * 2.0 - 3.0];
            }
            for closed in [true, false] {
                let segments = if closed { n } else { n - 1 };
                for tol in [1e-9, 0.05] {
                    assert_eq!(
                        first_contact(&points, segments, closed, tol),
                        every_pair(&points, segments, closed, tol),
                        "case {case}, closed {closed}, tolerance {tol}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_contour_of_the_largest_size_is_checked_in_linear_work() {
        // 10,000 points: every pair would be 5e7 distance evaluations; the grid compares a few
        // neighbours per segment (at most GRID_WORK_PER_SEGMENT: it answers, no fallback).
        let points = circle(10_000);
        assert_eq!(grid_contact(&contour(&points)), Some(None));
        // A contact across the contour is found, the same as by every pair (which, the contact
        // being among the first segments, stops early).
        let mut points = points;
        points[10] = points[5_000];
        let found = grid_contact(&contour(&points)).unwrap().unwrap();
        assert_eq!(found, every_pair(&points, 10_000, true, 1e-9).unwrap());
    }
}
