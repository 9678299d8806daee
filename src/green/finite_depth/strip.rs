//! The finite-depth Green function for a whole mesh at once, and its two frequency limits.
//!
//! # Wave frequencies: the remainder as a sum of separable terms
//! The near form's remainder `R` (parent module) is a Fourier integral over `m`. With one
//! quadrature in `m` for every pair of points (pieces as in the near form for the nearest
//! images, `d = h`, and pieces short enough for the widest `|X|` of the mesh, [`REACH_PHASE`]),
//! each node's integrand splits into products of a field-point factor and a source factor:
//! ```text
//! cos m(x - x0) = cos mx cos mx0 + sin mx sin mx0
//! C S = C [ e^{m y} g1(y0) + e^{-m(y+h)} g2(y0) ],   C = (m + nu) / (2 D)
//! g1 = e^{-m(2h + y0)} - tau e^{m(y0 - 2h)},  tau = (nu + m)/(nu - m)
//! g2 = e^{-m(3h + y0)} + e^{m(y0 - h)}
//! ```
//! (`D`, `S` as in the parent module). A source factor integrates over a straight panel in
//! closed form (exponentials of a linear function of arc length), so the remainder's panel
//! integrals for all (field point, panel) pairs are one real matrix product, four columns
//! per real node and eight per complex one (the half circles over the poles). The
//! imaginary part `A0 Z0(y) Z0(y0) cos k0 X - e^{nu Y} cos nu X` (finite-depth minus
//! deep-water wave) splits the same way with four terms. The term `-e^{-2mh}/(2m)` and
//! `-(1/2pi) ln 2h` are constants.
//!
//! # Cost
//! Only the rows a caller needs ([`RemainderRow`]: a value, or one directional derivative).
//! The factors `cos mx`, `sin mx`, `e^{my}` of a point serve both as a field point and as a
//! panel's centre; `sinh(z)/z` of a panel is one series in `m^2`. Panels that are mirror
//! images in `x = 0` share their factors: the `cos m x0` terms are even in `x0`, the
//! `sin m x0` terms odd, so with `E`, `O` the two halves of the product over one panel of
//! each pair, the pair's columns are `E + O` and `E - O` (half the product's work). The
//! nodes go in blocks of [`HALF_BLOCK`] columns per parity.
//!
//! # The limits
//! `omega -> inf` (`G = 0` on `y = 0`, `dG/dy = 0` on `y = -h`): images of alternating sign
//! every `2h`, summed in closed form (`w = z - z0`, `w' = z - conj z0`, `z = x + iy`):
//! ```text
//! G = (1/2pi) [ ln|tanh(pi w / 4h)| - ln|tanh(pi w' / 4h)| ]
//! ```
//! `omega -> 0` (`dG/dy = 0` on both): images of one sign every `2h`,
//! ```text
//! G = (1/2pi) [ ln|sinh(pi w / 2h)| + ln|sinh(pi w' / 2h)| - 2 ln(pi / 2h) ]
//! ```
//! which grows like `|X| / 2h` along the channel: only distributions of zero net strength
//! (no net flux) have a finite potential at infinity, and `A(0)` exists only for entries
//! where one of the two DOFs has no net flux. Both tend to the deep-water limits as
//! `h -> inf` (the constant `-2 ln(pi/2h)` makes the rigid-lid one do so). Their remainders
//! beyond the source, its surface image and its bottom image (`ln |w' + 2ih|`, plus sign in
//! both) are smooth in the strip and are integrated over panels by Gauss-Legendre.

use super::{gauss_legendre, FiniteDepthGreen, PANEL_NODES};
use crate::green::{FreeSurface, Point};
use faer::Mat;
use num_complex::Complex64;
use std::collections::HashMap;
use std::f64::consts::PI;

/// Largest phase `m |X|` a quadrature piece spans.
const REACH_PHASE: f64 = 4.0;
/// Gauss-Legendre nodes per piece on the real axis (tested: within `2e-10` of the pair-by-pair
/// panel integrals).
const SEPARABLE_NODES: usize = 8;
/// Upper limit of the quadrature, `M = UPPER / d`: the integrand's terms fall like `e^{-m d}`,
/// `e^{-30}` is `1e-13`.
const UPPER: f64 = 30.0;

/// A row of [`FiniteDepthGreen::remainder_rows`]: the panel integrals at `point`
/// (`direction` `None`), or their derivative along `direction` there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RemainderRow {
    /// The field point, in the fluid strip.
    pub point: Point,
    /// `None`: the value; `Some(n)`: the derivative `n . grad` with respect to the field point.
    pub direction: Option<[f64; 2]>,
}

/// Panel integrals of `G_h - G_inf - (1/2pi) ln r2` (the finite-depth Green function minus the
/// deep-water one of the same `nu` and the bottom image): one row per [`RemainderRow`], one
/// column per panel.
#[derive(Clone, Debug)]
pub struct RemainderMatrix {
    real: Mat<f64>,
    imaginary: Mat<f64>,
}

impl RemainderMatrix {
    /// Row `row`, panel `p`.
    pub fn get(&self, row: usize, p: usize) -> Complex64 {
        Complex64::new(self.real.read(row, p), self.imaginary.read(row, p))
    }
}

/// Panel integrals of `G_h - G_inf - (1/2pi) ln r2` for a list of field points and
/// panels: value and gradient of `sum` over the panel, `[value, d/dx, d/dy]`.
#[derive(Clone, Debug)]
pub struct RemainderIntegrals {
    /// Rows `[values; d/dx; d/dy]` (each `fields` rows), one column per panel.
    rows: RemainderMatrix,
    fields: usize,
}

impl RemainderIntegrals {
    /// `int G ds` of panel `p` at field point `i`.
    pub fn value(&self, i: usize, p: usize) -> Complex64 {
        self.rows.get(i, p)
    }

    /// `grad int G ds` of panel `p` at field point `i`.
    pub fn gradient(&self, i: usize, p: usize) -> [Complex64; 2] {
        [
            self.rows.get(i + self.fields, p),
            self.rows.get(i + 2 * self.fields, p),
        ]
    }
}

/// Columns of each parity of the separable product computed and multiplied at a time (the
/// factors stay small, within the cache and the allocator's reused memory).
const HALF_BLOCK: usize = 32;
/// Taylor terms of `sinh(z)/z` kept where `|z| < 1/2` (error below `1e-16`).
const SINHC_TERMS: usize = 7;

/// A straight panel's centre, length and half extent `(b - a)/2`, with the Taylor
/// coefficients in `m^2` of `sinh(m u)/(m u)`, `u = half_y + i half_x`.
#[derive(Clone, Copy)]
struct Shape {
    centre: Point,
    length: f64,
    half: [f64; 2],
    /// `u^{2k}/(2k + 1)!`.
    series: [Complex64; SINHC_TERMS],
}

impl Shape {
    fn new([a, b]: [Point; 2]) -> Self {
        let half = [0.5 * (b[0] - a[0]), 0.5 * (b[1] - a[1])];
        let u2 = Complex64::new(half[1], half[0]).powi(2);
        let mut series = [Complex64::new(1.0, 0.0); SINHC_TERMS];
        for k in 1..SINHC_TERMS {
            series[k] = series[k - 1] * u2 / ((2 * k) * (2 * k + 1)) as f64;
        }
        Self {
            centre: [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])],
            length: (b[0] - a[0]).hypot(b[1] - a[1]),
            half,
            series,
        }
    }

    /// `sinh(m u)/(m u)` for real `m`; `sinh(m u')/(m u')`, `u' = -half_y + i half_x`, is
    /// its conjugate.
    fn sinhc(&self, m: f64) -> Complex64 {
        let u = Complex64::new(self.half[1], self.half[0]);
        if m * m * u.norm_sqr() < 0.25 {
            let m2 = m * m;
            self.series
                .iter()
                .rev()
                .fold(Complex64::new(0.0, 0.0), |sum, &a| sum * m2 + a)
        } else {
            sinhc(u * m)
        }
    }
}

/// The distinct points of the rows and the panels' centres: the panels' centres first,
/// then the rows' other points; and each row's index among them.
fn distinct_points(rows: &[RemainderRow], shapes: &[Shape]) -> (Vec<Point>, Vec<usize>) {
    let key = |p: Point| (p[0].to_bits(), p[1].to_bits());
    let mut points: Vec<Point> = shapes.iter().map(|s| s.centre).collect();
    let mut index: HashMap<(u64, u64), usize> = HashMap::with_capacity(points.len());
    for (i, &p) in points.iter().enumerate() {
        index.entry(key(p)).or_insert(i);
    }
    let of_row = rows
        .iter()
        .map(|row| {
            *index.entry(key(row.point)).or_insert_with(|| {
                points.push(row.point);
                points.len() - 1
            })
        })
        .collect();
    (points, of_row)
}

/// One row's entries from `[f, df/dx, df/dy]` of the four field factors.
fn row_entries<T>(direction: Option<[f64; 2]>, factors: [[T; 3]; 4]) -> [T; 4]
where
    T: Copy + std::ops::Mul<f64, Output = T> + std::ops::Add<Output = T>,
{
    match direction {
        None => factors.map(|f| f[0]),
        Some([nx, ny]) => factors.map(|f| f[1] * nx + f[2] * ny),
    }
}

/// `[f, df/dx, df/dy]` of `e^{my} cos mx`, `e^{my} sin mx`, `e^{-m(y+h)} cos mx`,
/// `e^{-m(y+h)} sin mx` from `up = e^{my}`, `down = e^{-m(y+h)}`, `cos mx`, `sin mx`.
fn field_factors<T>(m: T, up: T, down: T, cos: T, sin: T) -> [[T; 3]; 4]
where
    T: Copy + std::ops::Mul<Output = T> + std::ops::Neg<Output = T>,
{
    let (mu, md) = (m * up, m * down);
    [
        [up * cos, -(mu * sin), mu * cos],
        [up * sin, mu * cos, mu * sin],
        [down * cos, -(md * sin), -(md * cos)],
        [down * sin, md * cos, -(md * sin)],
    ]
}

impl FiniteDepthGreen {
    /// `(m, weight)` of a quadrature with `R = (1/pi) Re sum weight f(m)` for every pair of
    /// points `|X| <= reach` apart and at most `span` below the surface (`f`: the near form's
    /// integrand, whose terms decay at least like `e^{-m (2h - span)}`).
    pub(crate) fn remainder_nodes(&self, reach: f64, span: f64) -> Vec<(Complex64, Complex64)> {
        let h = self.depth;
        let upper = UPPER / (2.0 * h - span).clamp(h, 2.0 * h);
        let arcs = self.arcs(h);
        let breaks = self.break_points(upper, &arcs);
        let arcs = arcs.iter().flatten();
        let widest = REACH_PHASE / reach.max(1e-300);
        let rule = gauss_legendre(SEPARABLE_NODES);
        let mut nodes = Vec::new();
        for pair in breaks.windows(2) {
            let (lo, hi) = (pair[0], pair[1]);
            let centre = 0.5 * (lo + hi);
            if hi <= lo || arcs.clone().any(|&(c, r)| (centre - c).abs() < r) {
                continue;
            }
            let pieces = ((hi - lo) / widest).ceil().max(1.0) as usize;
            let step = (hi - lo) / pieces as f64;
            for piece in 0..pieces {
                let (centre, half) = (lo + (piece as f64 + 0.5) * step, 0.5 * step);
                for &(t, w) in &rule {
                    nodes.push((
                        Complex64::new(centre + half * t, 0.0),
                        Complex64::new(w * half, 0.0),
                    ));
                }
            }
        }
        for &(centre, radius) in arcs {
            for &(t, w) in &self.integral_rule {
                let theta = 0.5 * PI * (1.0 + t);
                let turn = Complex64::from_polar(radius, theta);
                nodes.push((centre + turn, Complex64::new(0.0, -0.5 * PI * w) * turn));
            }
        }
        nodes
    }

    /// [`RemainderIntegrals`] of every panel `a -> b` of `panels` at every point of `fields`
    /// (all in the fluid strip), by the separable form of the module docs.
    pub fn remainder_integrals(
        &self,
        fields: &[Point],
        panels: &[[Point; 2]],
    ) -> RemainderIntegrals {
        let directions = [None, Some([1.0, 0.0]), Some([0.0, 1.0])];
        let rows: Vec<RemainderRow> = directions
            .iter()
            .flat_map(|&direction| {
                fields
                    .iter()
                    .map(move |&point| RemainderRow { point, direction })
            })
            .collect();
        RemainderIntegrals {
            rows: self.remainder_rows(&rows, panels),
            fields: fields.len(),
        }
    }

    /// The panel integrals of the remainder over every panel `a -> b` of `panels` for every
    /// row of `rows` (points in the fluid strip), by the separable form of the module docs:
    /// one real matrix product, whose inner dimension is four per real node of the
    /// quadrature and eight per complex one. Consecutive rows at the same point share its
    /// factors.
    pub fn remainder_rows(&self, rows: &[RemainderRow], panels: &[[Point; 2]]) -> RemainderMatrix {
        let points = rows
            .iter()
            .map(|r| r.point)
            .chain(panels.iter().flatten().copied());
        let (lo, hi, span) = points.fold(
            (f64::INFINITY, f64::NEG_INFINITY, 0.0f64),
            |(lo, hi, span), p| (lo.min(p[0]), hi.max(p[0]), span.max(-p[1])),
        );
        let nodes = self.remainder_nodes((hi - lo).max(0.0), span);
        let shapes: Vec<Shape> = panels.iter().map(|&panel| Shape::new(panel)).collect();
        // Mirror pairs of panels: the second's columns from the first's factors.
        let partner = mirror_partners(&shapes);
        let mut is_partner = vec![false; panels.len()];
        partner.iter().flatten().for_each(|&q| is_partner[q] = true);
        let kept: Vec<usize> = (0..panels.len()).filter(|&p| !is_partner[p]).collect();
        let kept_shapes: Vec<Shape> = kept.iter().map(|&p| shapes[p]).collect();
        let (points, of_row) = distinct_points(rows, &kept_shapes);
        // Per distinct point and real node: cos mx, sin mx, e^{my}.
        let mut trig = Vec::with_capacity(points.len());
        let mut factors = Factors::new(rows.len(), kept.len());
        let mut constant = 0.0;
        for &(m, weight) in &nodes {
            let q = (-2.0 * self.depth * m).exp();
            constant -= (weight * q / (2.0 * m)).re;
            let columns = if is_real(m, weight) { 2 } else { 4 };
            if factors.column + columns > HALF_BLOCK {
                factors.accumulate();
            }
            if is_real(m, weight) {
                let m = m.re;
                trig.clear();
                trig.extend(points.iter().map(|p| {
                    let (sin, cos) = (m * p[0]).sin_cos();
                    [cos, sin, (m * p[1]).exp()]
                }));
                let node = RealNode {
                    m,
                    weight: weight.re,
                    trig: &trig,
                    of_row: &of_row,
                };
                self.real_node(&node, rows, &kept_shapes, &mut factors);
            } else {
                self.complex_node(m, weight, rows, &kept_shapes, &mut factors);
            }
            factors.column += columns;
        }
        factors.accumulate();
        // Even in x0 plus odd; the mirror image: even minus odd.
        let [even, odd] = &factors.products;
        let mut real = Mat::<f64>::zeros(rows.len(), panels.len());
        for (k, &p) in kept.iter().enumerate() {
            for r in 0..rows.len() {
                let (e, o) = (even.read(r, k), odd.read(r, k));
                real.write(r, p, e + o);
                if let Some(q) = partner[p] {
                    real.write(r, q, e - o);
                }
            }
        }
        let constant = constant / PI - (2.0 * self.depth).ln() / (2.0 * PI);
        for (p, shape) in shapes.iter().enumerate() {
            for (r, row) in rows.iter().enumerate() {
                if row.direction.is_none() {
                    real.write(r, p, real.read(r, p) + constant * shape.length);
                }
            }
        }
        RemainderMatrix {
            real,
            imaginary: self.propagating_rows(rows, &shapes),
        }
    }

    /// The two even and two odd columns of a real node.
    fn real_node(
        &self,
        node: &RealNode,
        rows: &[RemainderRow],
        shapes: &[Shape],
        factors: &mut Factors,
    ) {
        let column = factors.column;
        let (nu, h, m) = (self.nu, self.depth, node.m);
        let decay = (-m * h).exp();
        let q = decay * decay;
        let c = node.weight * (m + nu) / (2.0 * m * ((nu - m) + (nu + m) * q));
        let tau = (nu + m) / (nu - m);
        for (r, row) in rows.iter().enumerate() {
            let [cos, sin, up] = node.trig[node.of_row[r]];
            let [a, b, c, d] =
                row_entries(row.direction, field_factors(m, up, decay / up, cos, sin));
            factors.left[0].col_as_slice_mut(r)[column..column + 2].copy_from_slice(&[a, c]);
            factors.left[1].col_as_slice_mut(r)[column..column + 2].copy_from_slice(&[b, d]);
        }
        for (p, shape) in shapes.iter().enumerate() {
            let [cos, sin, up] = node.trig[p];
            let phase = Complex64::new(cos, sin) * (c * shape.length);
            // int e^{i m x0 +- m y0} ds = L e^{i m xc +- m yc} sinhc(m (i dx +- dy)/2).
            let sinhc = shape.sinhc(m);
            let (rising, falling) = (phase * sinhc, phase * sinhc.conj());
            let g1 = falling * (q / up) - rising * (tau * q * up);
            let g2 = falling * (q * decay / up) + rising * (decay * up);
            factors.right[0].col_as_slice_mut(p)[column..column + 2]
                .copy_from_slice(&[g1.re, g2.re]);
            factors.right[1].col_as_slice_mut(p)[column..column + 2]
                .copy_from_slice(&[g1.im, g2.im]);
        }
    }

    /// The four even and four odd columns of a complex node `m` (weight `weight`, on a half
    /// circle over the poles): the real and imaginary parts of the factors, `Re(a b) =
    /// Re a Re b - Im a Im b`.
    #[allow(clippy::too_many_arguments)]
    fn complex_node(
        &self,
        m: Complex64,
        weight: Complex64,
        rows: &[RemainderRow],
        shapes: &[Shape],
        factors: &mut Factors,
    ) {
        let column = factors.column;
        let (nu, h) = (self.nu, self.depth);
        let i = Complex64::new(0.0, 1.0);
        let decay = (-h * m).exp();
        let q = decay * decay;
        let c = weight * (m + nu) / (2.0 * m * ((nu - m) + (nu + m) * q));
        let tau = (nu + m) / (nu - m);
        for (r, row) in rows.iter().enumerate() {
            let [x, y] = row.point;
            let phase = (i * m * x).exp();
            let (cos, sin) = (
                (phase + phase.inv()) * 0.5,
                (phase - phase.inv()) / (2.0 * i),
            );
            let up = (m * y).exp();
            let [a, b, c, d] =
                row_entries(row.direction, field_factors(m, up, decay / up, cos, sin));
            factors.left[0].col_as_slice_mut(r)[column..column + 4]
                .copy_from_slice(&[a.re, c.re, -a.im, -c.im]);
            factors.left[1].col_as_slice_mut(r)[column..column + 4]
                .copy_from_slice(&[b.re, d.re, -b.im, -d.im]);
        }
        for (p, shape) in shapes.iter().enumerate() {
            let [xc, yc] = shape.centre;
            let [hx, hy] = shape.half;
            let phase = (i * m * xc).exp();
            let up = (m * yc).exp();
            // int e^{+-i m x0 + s m y0} ds = L e^{+-i m xc + s m yc} sinhc(m (+-i hx + s hy)),
            // sinhc even.
            let (same, opposite) = (sinhc(m * (i * hx + hy)), sinhc(m * (i * hx - hy)));
            let length = c * shape.length;
            let (plus_up, minus_up) = (phase * up * same, up / phase * opposite);
            let (plus_down, minus_down) = (phase / up * opposite, same / (phase * up));
            let trig = |plus: Complex64, minus: Complex64| {
                [
                    (plus + minus) * 0.5 * length,
                    (plus - minus) / (2.0 * i) * length,
                ]
            };
            let [cos_up, sin_up] = trig(plus_up, minus_up);
            let [cos_down, sin_down] = trig(plus_down, minus_down);
            let (g1_cos, g2_cos) = (
                q * (cos_down - tau * cos_up),
                q * decay * cos_down + decay * cos_up,
            );
            let (g1_sin, g2_sin) = (
                q * (sin_down - tau * sin_up),
                q * decay * sin_down + decay * sin_up,
            );
            factors.right[0].col_as_slice_mut(p)[column..column + 4]
                .copy_from_slice(&[g1_cos.re, g2_cos.re, g1_cos.im, g2_cos.im]);
            factors.right[1].col_as_slice_mut(p)[column..column + 4]
                .copy_from_slice(&[g1_sin.re, g2_sin.re, g1_sin.im, g2_sin.im]);
        }
    }

    /// The imaginary part: the propagating mode `A0 Z0(y) Z0(y0) cos k0 X` less the deep-water
    /// wave `e^{nu Y} cos nu X`, four separable terms.
    fn propagating_rows(&self, rows: &[RemainderRow], shapes: &[Shape]) -> Mat<f64> {
        let (nu, h, k) = (self.nu, self.depth, self.k0);
        let mut left = Mat::<f64>::zeros(4, rows.len());
        let mut right = Mat::<f64>::zeros(4, shapes.len());
        let norm = {
            let q = (-2.0 * k * h).exp();
            4.0 * k * h * q + (1.0 - q * q)
        };
        for (r, row) in rows.iter().enumerate() {
            let [x, y] = row.point;
            let profile = (k * y).exp() + (-k * (y + 2.0 * h)).exp();
            let slope = k * ((k * y).exp() - (-k * (y + 2.0 * h)).exp());
            let deep = (nu * y).exp();
            let (s, c) = (k * x).sin_cos();
            let (sd, cd) = (nu * x).sin_cos();
            let factors = [
                [profile * c, -k * profile * s, slope * c],
                [profile * s, k * profile * c, slope * s],
                [deep * cd, -nu * deep * sd, nu * deep * cd],
                [deep * sd, nu * deep * cd, nu * deep * sd],
            ];
            left.col_as_slice_mut(r)
                .copy_from_slice(&row_entries(row.direction, factors));
        }
        // int e^{i m x0 +- m y0} ds = L e^{i m xc +- m yc} sinhc(m (i dx +- dy)/2), real m:
        // cos and sin parts its real and imaginary parts.
        for (p, shape) in shapes.iter().enumerate() {
            let [xc, yc] = shape.centre;
            let (sin, cos) = (k * xc).sin_cos();
            let (sin_deep, cos_deep) = (nu * xc).sin_cos();
            let wave = Complex64::new(cos, sin) * shape.length;
            let sinhc = shape.sinhc(k);
            let up = wave * sinhc * (k * yc).exp();
            let down = wave * sinhc.conj() * (-k * (yc + 2.0 * h)).exp();
            let deep = Complex64::new(cos_deep, sin_deep)
                * (shape.sinhc(nu) * (shape.length * (nu * yc).exp()));
            right.col_as_slice_mut(p).copy_from_slice(&[
                (up + down).re / norm,
                (up + down).im / norm,
                -deep.re,
                -deep.im,
            ]);
        }
        let mut imaginary = Mat::<f64>::zeros(rows.len(), shapes.len());
        faer::linalg::matmul::matmul(
            imaginary.as_mut(),
            left.transpose(),
            right.as_ref(),
            None,
            1.0,
            faer::Parallelism::None,
        );
        imaginary
    }
}

/// A real quadrature node `m`, its weight, and per distinct point `[cos mx, sin mx, e^{my}]`
/// (the panels' centres first) with each row's point's index.
struct RealNode<'a> {
    m: f64,
    weight: f64,
    trig: &'a [[f64; 3]],
    of_row: &'a [usize],
}

/// The separable factors of a block of nodes, split by parity in `x0`: `[0]` the terms in
/// `cos m x0` (even), `[1]` those in `sin m x0` (odd), each `left^T right` summed into
/// `products` (`rows x kept panels`, times `1/pi`).
struct Factors {
    /// Transposed: column `r` holds row `r`'s field factors.
    left: [Mat<f64>; 2],
    right: [Mat<f64>; 2],
    products: [Mat<f64>; 2],
    /// Columns of the block in use.
    column: usize,
}

impl Factors {
    fn new(rows: usize, panels: usize) -> Self {
        Self {
            left: [0, 1].map(|_| Mat::zeros(HALF_BLOCK, rows)),
            right: [0, 1].map(|_| Mat::zeros(HALF_BLOCK, panels)),
            products: [0, 1].map(|_| Mat::zeros(rows, panels)),
            column: 0,
        }
    }

    /// Adds the block's products and empties it.
    fn accumulate(&mut self) {
        for k in 0..2 {
            faer::linalg::matmul::matmul(
                self.products[k].as_mut(),
                self.left[k].as_ref().subrows(0, self.column).transpose(),
                self.right[k].as_ref().subrows(0, self.column),
                Some(1.0),
                1.0 / PI,
                faer::Parallelism::None,
            );
        }
        self.column = 0;
    }
}

/// For each panel the index of its mirror image in `x = 0` among the later panels, if any
/// (centres, lengths and slopes within `1e-12` of the mesh's extent); each panel in one pair
/// at most.
fn mirror_partners(shapes: &[Shape]) -> Vec<Option<usize>> {
    let extent = shapes
        .iter()
        .map(|s| s.centre[0].abs().max(s.centre[1].abs()) + s.length)
        .fold(0.0, f64::max);
    let tolerance = 1e-12 * extent;
    let mut partner = vec![None; shapes.len()];
    let mut taken = vec![false; shapes.len()];
    for (p, a) in shapes.iter().enumerate() {
        if taken[p] {
            continue;
        }
        let mirrors = |b: &Shape| {
            let close = |u: f64, v: f64| (u - v).abs() <= tolerance;
            // The mirror image of a -> b runs from (-a_x, a_y) or, reversed, to it.
            close(b.centre[0], -a.centre[0])
                && close(b.centre[1], a.centre[1])
                && ((close(b.half[0], -a.half[0]) && close(b.half[1], a.half[1]))
                    || (close(b.half[0], a.half[0]) && close(b.half[1], -a.half[1])))
        };
        if let Some(q) = (p + 1..shapes.len()).find(|&q| !taken[q] && mirrors(&shapes[q])) {
            partner[p] = Some(q);
            taken[q] = true;
        }
    }
    partner
}

/// Whether a quadrature node lies on the real axis (four columns) or on a half circle.
fn is_real(m: Complex64, weight: Complex64) -> bool {
    m.im == 0.0 && weight.im == 0.0
}

/// `sinh(z)/z`.
fn sinhc(z: Complex64) -> Complex64 {
    if z.norm_sqr() < 0.25 {
        // Taylor to z^12: error below 1e-13 for |z| < 1/2.
        let z2 = z * z;
        let mut term = Complex64::new(1.0, 0.0);
        let mut sum = term;
        for n in 1..=6 {
            term = term * z2 / f64::from((2 * n) * (2 * n + 1));
            sum += term;
        }
        sum
    } else {
        z.sinh() / z
    }
}

/// `ln|f(a)/a|` and `f'(a)/f(a) - 1/a` for `f = tanh` (`tanh = true`) or `sinh`.
fn log_ratio_and_derivative(a: Complex64, tanh: bool) -> (f64, Complex64) {
    if a.norm() == 0.0 {
        return (0.0, Complex64::new(0.0, 0.0));
    }
    if tanh {
        let t = a.tanh();
        ((t / a).norm().ln(), 2.0 / (2.0 * a).sinh() - 1.0 / a)
    } else if a.norm() < 1.0 {
        ((a.sinh() / a).norm().ln(), a.cosh() / a.sinh() - 1.0 / a)
    } else {
        // ln|sinh a| = s Re a - ln 2 + ln|1 - e^{-2 s a}|, s = sign Re a.
        let s = if a.re >= 0.0 { 1.0 } else { -1.0 };
        let e = (-2.0 * s * a).exp();
        (
            s * a.re - 2f64.ln() + (1.0 - e).norm().ln() - a.norm().ln(),
            s * (1.0 + e) / (1.0 - e) - 1.0 / a,
        )
    }
}

/// The remainder of a frequency limit of the finite-depth Green function (`RigidLid` or
/// `Dirichlet`; zero for `Wave`) beyond `(1/2pi) (ln r0 +- ln r1 + ln r2)`: value and
/// gradient with respect to the field point. Smooth in the strip.
pub fn limit_remainder(
    surface: FreeSurface,
    depth: f64,
    field: Point,
    source: Point,
) -> (f64, [f64; 2]) {
    let zf = Complex64::new(field[0], field[1]);
    let w = zf - Complex64::new(source[0], source[1]);
    let w_image = zf - Complex64::new(source[0], -source[1]);
    let (tanh, scale, image_sign) = match surface {
        FreeSurface::Dirichlet => (true, PI / (4.0 * depth), -1.0),
        FreeSurface::RigidLid => (false, PI / (2.0 * depth), 1.0),
        FreeSurface::Wave { .. } => return (0.0, [0.0, 0.0]),
    };
    let (direct, d_direct) = log_ratio_and_derivative(scale * w, tanh);
    let (image, d_image) = log_ratio_and_derivative(scale * w_image, tanh);
    // ln|f(c w)| - ln|w| = ln|f(c w)/(c w)| + ln c: the constants ln c cancel between the
    // source and its image (and the rigid lid's -2 ln c); less the bottom image ln|w' + 2ih|.
    let bottom = w_image + Complex64::new(0.0, 2.0 * depth);
    let value = direct + image_sign * image - bottom.norm().ln();
    let derivative = scale * d_direct + image_sign * scale * d_image - bottom.inv();
    (
        value / (2.0 * PI),
        [derivative.re / (2.0 * PI), -derivative.im / (2.0 * PI)],
    )
}

/// `int limit_remainder ds0` over `a -> b` and its gradient, by Gauss-Legendre: the
/// remainder's nearest singularity lies at least `d = 2h - max |y - y0|` from the field
/// point, so `n` nodes err like `rho^{-2n}`, `rho = 4 (d - L) / L` (the Bernstein ellipse
/// through it, `L` the panel length); `n` from 2 for `rho^{-2n} < 1e-16`, at most
/// [`PANEL_NODES`].
pub fn limit_remainder_integral(
    surface: FreeSurface,
    depth: f64,
    field: Point,
    a: Point,
    b: Point,
) -> (f64, [f64; 2]) {
    let length = (b[0] - a[0]).hypot(b[1] - a[1]);
    let half = 0.5 * length;
    let reach = 2.0 * depth - (field[1] - a[1]).abs().max((field[1] - b[1]).abs());
    let rho = 4.0 * (reach - length) / length;
    let nodes = if rho > 1.0 {
        ((16.0 * 10f64.ln()) / (2.0 * rho.ln())).ceil() as usize
    } else {
        PANEL_NODES
    };
    let mut out = (0.0, [0.0, 0.0]);
    for (t, w) in gauss_legendre(nodes.clamp(2, PANEL_NODES)) {
        let s = 0.5 * (1.0 + t);
        let source = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])];
        let (v, g) = limit_remainder(surface, depth, field, source);
        out.0 += w * half * v;
        out.1[0] += w * half * g[0];
        out.1[1] += w * half * g[1];
    }
    out
}

#[cfg(test)]
mod tests;
