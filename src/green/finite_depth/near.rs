//! The near form's remainder `R` (see the parent module): a principal-value integral over the
//! wavenumber `m`. The integrand is real on the real axis with simple poles at `m = nu` and
//! `m = k0` (real residues), so the principal value is the real part of the integral over a
//! half circle above the poles: no subtraction, no cancellation where the two poles nearly
//! coincide (deep water, `k0 - nu = (nu + k0) e^{-2 k0 h}`).

use super::FiniteDepthGreen;
use crate::green::Point;
use num_complex::Complex64;
use std::f64::consts::PI;

/// Upper limit of the integral: `M = UPPER / d` (`e^{-M d}` below `2e-22`).
const UPPER: f64 = 50.0;
/// The poles are left out where `k0 d` exceeds this (their pair then contributes
/// `O(e^{-2 k0 h})`, below `1e-17`); otherwise the arcs end below `M`.
const POLES_BEYOND: f64 = 40.0;

impl FiniteDepthGreen {
    /// `[R, dR/dx, dR/dy]` for the field point and the source.
    pub(super) fn near_remainder(&self, field: Point, source: Point) -> [f64; 3] {
        let h = self.depth;
        let x = field[0] - source[0];
        let (y, y0) = (field[1], source[1]);
        let decay = (2.0 * h - (y - y0).abs()).max(h);
        let upper = UPPER / decay;
        let arcs = self.arcs(decay);
        let breaks = self.break_points(upper, &arcs);
        let arcs = arcs.iter().flatten();
        let mut sum = [0.0; 3];
        for pair in breaks.windows(2) {
            let (lo, hi) = (pair[0], pair[1]);
            let (centre, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
            if hi <= lo || arcs.clone().any(|&(c, r)| (centre - c).abs() < r) {
                continue;
            }
            for &(t, w) in &self.integral_rule {
                let f = self.integrand(centre + half * t, x, y, y0);
                for (si, fi) in sum.iter_mut().zip(f) {
                    *si += w * half * fi;
                }
            }
        }
        // PV = Re of the integral over the upper half circle (real residues).
        for &(centre, radius) in arcs {
            for &(t, w) in &self.integral_rule {
                // theta from pi to 0: m = centre + radius e^{i theta}.
                let theta = 0.5 * PI * (1.0 + t);
                let turn = Complex64::from_polar(radius, theta);
                let m = centre + turn;
                let dm = Complex64::new(0.0, -0.5 * PI * w) * turn;
                let f = self.complex_integrand(m, x, y, y0);
                for (si, fi) in sum.iter_mut().zip(f) {
                    *si += (fi * dm).re;
                }
            }
        }
        sum.map(|s| s / PI)
    }

    /// Break points of `[0, upper]`: 0, 2/h, 4/h, 8/h, ... below `upper`, `upper`, the arcs'
    /// ends, and about each arc `centre +- 2^j radius` (a pole never nearer to a piece than its
    /// length); sorted.
    pub(super) fn break_points(&self, upper: f64, arcs: &[Option<(f64, f64)>; 2]) -> Vec<f64> {
        let h = self.depth;
        let mut breaks = vec![0.0, upper];
        let mut b = 2.0 / h;
        while b < upper {
            breaks.push(b);
            b *= 2.0;
        }
        for &(centre, radius) in arcs.iter().flatten() {
            let mut offset = radius;
            loop {
                if centre + offset < upper {
                    breaks.push(centre + offset);
                }
                if centre - offset > 0.0 {
                    breaks.push(centre - offset);
                }
                if offset > 2.0 / h {
                    break;
                }
                offset *= 2.0;
            }
        }
        breaks.sort_by(f64::total_cmp);
        breaks
    }

    /// The half circles over the poles, `(centre, radius)`: one over both when they are close
    /// (each within `0.3` radius of the centre), else one centred on each with a radius of at
    /// most a third of their distance; radii at most `min(centre/2, 1/2h)`. None when
    /// `k0 d > POLES_BEYOND`.
    pub(super) fn arcs(&self, decay: f64) -> [Option<(f64, f64)>; 2] {
        let (nu, k0, h) = (self.nu, self.k0, self.depth);
        if k0 * decay > POLES_BEYOND {
            return [None, None];
        }
        let radius = |a: f64| (0.5 * a).min(0.5 / h);
        let centre = 0.5 * (nu + k0);
        if 0.5 * (k0 - nu) <= 0.3 * radius(centre) {
            return [Some((centre, radius(centre))), None];
        }
        let third = (k0 - nu) / 3.0;
        [
            Some((nu, radius(nu).min(third))),
            Some((k0, radius(k0).min(third))),
        ]
    }

    /// `pi` times the integrands of `[R, dR/dx, dR/dy]` at real `m > 0`, `m != nu, k0`.
    fn integrand(&self, m: f64, x: f64, y: f64, y0: f64) -> [f64; 3] {
        let (nu, h) = (self.nu, self.depth);
        let q = (-2.0 * m * h).exp();
        let e_sum = (m * (y + y0)).exp();
        let e_difference = (m * (y - y0)).exp();
        let e1 = q * q / e_sum;
        let e2 = e_difference * q;
        let e3 = q / e_difference;
        let t = e_sum * q * (nu + m) / (nu - m);
        let common = (m + nu) / (2.0 * ((nu - m) + (nu + m) * q));
        let (sin, cos) = (m * x).sin_cos();
        let s = e1 + e2 + e3 - t;
        [
            (cos * common * s - 0.5 * q) / m,
            -sin * common * s,
            cos * common * (-e1 + e2 - e3 - t),
        ]
    }

    /// [`FiniteDepthGreen::integrand`] continued to complex `m` (on the arcs over the poles).
    fn complex_integrand(&self, m: Complex64, x: f64, y: f64, y0: f64) -> [Complex64; 3] {
        let (nu, h) = (self.nu, self.depth);
        let q = (-2.0 * h * m).exp();
        let e_sum = ((y + y0) * m).exp();
        let e_difference = ((y - y0) * m).exp();
        let e1 = q * q / e_sum;
        let e2 = e_difference * q;
        let e3 = q / e_difference;
        let t = e_sum * q * (nu + m) / (nu - m);
        let common = (m + nu) / (2.0 * ((nu - m) + (nu + m) * q));
        let (sin, cos) = ((x * m).sin(), (x * m).cos());
        let s = e1 + e2 + e3 - t;
        [
            (cos * common * s - 0.5 * q) / m,
            -sin * common * s,
            cos * common * (-e1 + e2 - e3 - t),
        ]
    }
}
