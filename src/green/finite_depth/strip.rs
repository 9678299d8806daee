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
use std::f64::consts::PI;

/// Largest phase `m |X|` a quadrature piece spans.
const REACH_PHASE: f64 = 4.0;
/// Gauss-Legendre nodes per piece on the real axis (tested: within `2e-10` of the pair-by-pair
/// panel integrals).
const SEPARABLE_NODES: usize = 8;

/// Panel integrals of `G_h - G_inf - (1/2pi) ln r2` (the finite-depth Green function minus the
/// deep-water one of the same `nu` and the bottom image) for a list of field points and
/// panels: value and gradient of `sum` over the panel, `[value, d/dx, d/dy]`.
#[derive(Clone, Debug)]
pub struct RemainderIntegrals {
    /// Rows `[values; d/dx; d/dy]` (each `fields` rows), one column per panel.
    real: Mat<f64>,
    imaginary: Mat<f64>,
    fields: usize,
}

impl RemainderIntegrals {
    /// `int G ds` of panel `p` at field point `i`.
    pub fn value(&self, i: usize, p: usize) -> Complex64 {
        Complex64::new(self.real.read(i, p), self.imaginary.read(i, p))
    }

    /// `grad int G ds` of panel `p` at field point `i`.
    pub fn gradient(&self, i: usize, p: usize) -> [Complex64; 2] {
        let (x, y) = (i + self.fields, i + 2 * self.fields);
        [
            Complex64::new(self.real.read(x, p), self.imaginary.read(x, p)),
            Complex64::new(self.real.read(y, p), self.imaginary.read(y, p)),
        ]
    }
}

/// `L e^{alpha . c} sinh(s)/s`, `s = alpha . (b - a)/2`: `int e^{alpha . x} ds` over `a -> b`.
fn exponential_integral(alpha: [Complex64; 2], shift: Complex64, a: Point, b: Point) -> Complex64 {
    let centre = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    let length = (b[0] - a[0]).hypot(b[1] - a[1]);
    let half = (alpha[0] * (b[0] - a[0]) + alpha[1] * (b[1] - a[1])) * 0.5;
    let shape = if half.norm() < 1e-4 {
        Complex64::new(1.0, 0.0) + half * half / 6.0
    } else {
        half.sinh() / half
    };
    (alpha[0] * centre[0] + alpha[1] * centre[1] + shift).exp() * (shape * length)
}

/// `(int cos(m x0) e^{beta m y0 + shift} ds, int sin(...) ds)` over `a -> b`.
fn trig_exponential(
    m: Complex64,
    beta: f64,
    shift: Complex64,
    a: Point,
    b: Point,
) -> [Complex64; 2] {
    let i = Complex64::new(0.0, 1.0);
    let plus = exponential_integral([i * m, beta * m], shift, a, b);
    let minus = exponential_integral([-i * m, beta * m], shift, a, b);
    [(plus + minus) * 0.5, (plus - minus) / (2.0 * i)]
}

/// Field factors of one node: `[f, df/dx, df/dy]` of `e^{m y} cos mx`, `e^{m y} sin mx`,
/// `e^{-m(y+h)} cos mx`, `e^{-m(y+h)} sin mx`.
fn field_factors(m: Complex64, h: f64, p: Point) -> [[Complex64; 3]; 4] {
    let (cos, sin) = ((m * p[0]).cos(), (m * p[0]).sin());
    let up = (m * p[1]).exp();
    let down = (-m * (p[1] + h)).exp();
    [
        [up * cos, -m * up * sin, m * up * cos],
        [up * sin, m * up * cos, m * up * sin],
        [down * cos, -m * down * sin, -m * down * cos],
        [down * sin, m * down * cos, -m * down * sin],
    ]
}

impl FiniteDepthGreen {
    /// `(m, weight)` of a quadrature with `R = (1/pi) Re sum weight f(m)` for every pair of
    /// points `|X| <= reach` apart and at most `span` below the surface (`f`: the near form's
    /// integrand, whose terms decay at least like `e^{-m (2h - span)}`).
    pub(crate) fn remainder_nodes(&self, reach: f64, span: f64) -> Vec<(Complex64, Complex64)> {
        let h = self.depth;
        let upper = 50.0 / (2.0 * h - span).clamp(h, 2.0 * h);
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
        let (nu, h, k) = (self.nu, self.depth, self.k0);
        let xs = fields.iter().chain(panels.iter().flatten()).map(|p| p[0]);
        let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        let span = fields
            .iter()
            .chain(panels.iter().flatten())
            .map(|p| -p[1])
            .fold(0.0, f64::max);
        let nodes = self.remainder_nodes((hi - lo).max(0.0), span);
        // Per point (field points, then panel centres): cos mx, sin mx, e^{my}, e^{-m(y+h)}.
        let centres: Vec<Point> = panels
            .iter()
            .map(|[a, b]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])])
            .collect();
        let columns: usize = nodes
            .iter()
            .map(|(m, w)| if m.im == 0.0 && w.im == 0.0 { 4 } else { 8 })
            .sum();
        let rows = 3 * fields.len();
        let mut left = Mat::<f64>::zeros(rows, columns);
        let mut right = Mat::<f64>::zeros(columns, panels.len());
        let mut constant = 0.0;
        let mut column = 0;
        for &(m, weight) in &nodes {
            let q = (-2.0 * h * m).exp();
            constant -= (weight * q / (2.0 * m)).re;
            let c = weight * (m + nu) / (2.0 * m * ((nu - m) + (nu + m) * q));
            let tau = (nu + m) / (nu - m);
            let real = m.im == 0.0 && weight.im == 0.0;
            if real {
                let (m, c) = (m.re, c.re);
                let (tau, decay, decay2) = (tau.re, (-m * h).exp(), q.re);
                let factors = |p: Point| {
                    let (s, co) = (m * p[0]).sin_cos();
                    (co, s, (m * p[1]).exp(), (-m * (p[1] + h)).exp())
                };
                for (i, &field) in fields.iter().enumerate() {
                    let (co, s, up, down) = factors(field);
                    let n = fields.len();
                    let rows = [
                        [up * co, -m * up * s, m * up * co],
                        [up * s, m * up * co, m * up * s],
                        [down * co, -m * down * s, -m * down * co],
                        [down * s, m * down * co, -m * down * s],
                    ];
                    for (t, f) in rows.iter().enumerate() {
                        for (d, v) in f.iter().enumerate() {
                            left.write(i + d * n, column + t, *v);
                        }
                    }
                }
                for (p, (&[a, b], &centre)) in panels.iter().zip(&centres).enumerate() {
                    let (co, s, up, down) = factors(centre);
                    let length = (b[0] - a[0]).hypot(b[1] - a[1]);
                    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                    let phase = Complex64::new(co, s) * (c * length);
                    // int e^{i m x0 +- m y0} ds = L e^{i m xc +- m yc} sinhc(m (i dx +- dy)/2).
                    let rising = phase * sinhc(Complex64::new(0.5 * m * dy, 0.5 * m * dx));
                    let falling = phase * sinhc(Complex64::new(-0.5 * m * dy, 0.5 * m * dx));
                    let g1 = falling * (decay * down) - rising * (tau * decay2 * up);
                    let g2 = falling * (decay2 * down) + rising * (decay * up);
                    for (t, v) in [g1.re, g1.im, g2.re, g2.im].into_iter().enumerate() {
                        right.write(column + t, p, v);
                    }
                }
                column += 4;
                continue;
            }
            for (i, &field) in fields.iter().enumerate() {
                for (t, f) in field_factors(m, h, field).iter().enumerate() {
                    for (d, v) in f.iter().enumerate() {
                        left.write(i + d * fields.len(), column + t, v.re);
                        if !real {
                            left.write(i + d * fields.len(), column + 4 + t, -v.im);
                        }
                    }
                }
            }
            for (p, &[a, b]) in panels.iter().enumerate() {
                let g1a = trig_exponential(m, -1.0, -2.0 * h * m, a, b);
                let g1b = trig_exponential(m, 1.0, -2.0 * h * m, a, b);
                let g2a = trig_exponential(m, -1.0, -3.0 * h * m, a, b);
                let g2b = trig_exponential(m, 1.0, -h * m, a, b);
                let source = [
                    c * (g1a[0] - tau * g1b[0]),
                    c * (g1a[1] - tau * g1b[1]),
                    c * (g2a[0] + g2b[0]),
                    c * (g2a[1] + g2b[1]),
                ];
                for (t, s) in source.iter().enumerate() {
                    right.write(column + t, p, s.re);
                    if !real {
                        right.write(column + 4 + t, p, s.im);
                    }
                }
            }
            column += if real { 4 } else { 8 };
        }
        let mut real = Mat::<f64>::zeros(rows, panels.len());
        faer::linalg::matmul::matmul(
            real.as_mut(),
            left.as_ref(),
            right.as_ref(),
            None,
            1.0 / PI,
            faer::Parallelism::None,
        );
        let constant = constant / PI - (2.0 * h).ln() / (2.0 * PI);
        for (p, &[a, b]) in panels.iter().enumerate() {
            let length = (b[0] - a[0]).hypot(b[1] - a[1]);
            for i in 0..fields.len() {
                real.write(i, p, real.read(i, p) + constant * length);
            }
        }
        // Imaginary part: the propagating modes, finite depth minus deep water.
        let mut left = Mat::<f64>::zeros(rows, 4);
        let mut right = Mat::<f64>::zeros(4, panels.len());
        let norm = {
            let q = (-2.0 * k * h).exp();
            4.0 * k * h * q + (1.0 - q * q)
        };
        for (i, &[x, y]) in fields.iter().enumerate() {
            let profile = (k * y).exp() + (-k * (y + 2.0 * h)).exp();
            let slope = k * ((k * y).exp() - (-k * (y + 2.0 * h)).exp());
            let deep = (nu * y).exp();
            let (s, c) = (k * x).sin_cos();
            let (sd, cd) = (nu * x).sin_cos();
            let n = fields.len();
            let values = [
                [profile * c, -k * profile * s, slope * c],
                [profile * s, k * profile * c, slope * s],
                [deep * cd, -nu * deep * sd, nu * deep * cd],
                [deep * sd, nu * deep * cd, nu * deep * sd],
            ];
            for (t, v) in values.iter().enumerate() {
                for (d, value) in v.iter().enumerate() {
                    left.write(i + d * n, t, *value);
                }
            }
        }
        for (p, &[a, b]) in panels.iter().enumerate() {
            let zero = Complex64::new(0.0, 0.0);
            let kc = Complex64::new(k, 0.0);
            let nc = Complex64::new(nu, 0.0);
            let up = trig_exponential(kc, 1.0, zero, a, b);
            let down = trig_exponential(kc, -1.0, Complex64::new(-2.0 * k * h, 0.0), a, b);
            let deep = trig_exponential(nc, 1.0, zero, a, b);
            let source = [
                (up[0] + down[0]).re / norm,
                (up[1] + down[1]).re / norm,
                -deep[0].re,
                -deep[1].re,
            ];
            for (t, s) in source.iter().enumerate() {
                right.write(t, p, *s);
            }
        }
        let mut imaginary = Mat::<f64>::zeros(rows, panels.len());
        faer::linalg::matmul::matmul(
            imaginary.as_mut(),
            left.as_ref(),
            right.as_ref(),
            None,
            1.0,
            faer::Parallelism::None,
        );
        RemainderIntegrals {
            real,
            imaginary,
            fields: fields.len(),
        }
    }
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

/// `int limit_remainder ds0` over `a -> b` and its gradient, by
/// [`PANEL_NODES`]-point Gauss-Legendre (the remainder is smooth on the scale of `h`).
pub fn limit_remainder_integral(
    surface: FreeSurface,
    depth: f64,
    field: Point,
    a: Point,
    b: Point,
) -> (f64, [f64; 2]) {
    let half = 0.5 * (b[0] - a[0]).hypot(b[1] - a[1]);
    let mut out = (0.0, [0.0, 0.0]);
    for (t, w) in gauss_legendre(PANEL_NODES) {
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
