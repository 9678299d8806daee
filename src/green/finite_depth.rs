//! Two-dimensional free-surface Green function in water of finite depth `h`: the dispersion
//! relation, point values with their gradient, and integrals over straight source panels.
//!
//! # Conventions
//! As for the deep-water [`GreenFunction`]: `x` to the right, `y` up,
//! mean free surface `y = 0`, flat bottom `y = -h`, fluid in `-h < y < 0`, time factor
//! `exp(+i omega t)`, `nu = omega^2 / g`. `G` solves `lap G = delta(x - x0)`
//! (`G ~ (1/2pi) ln r0` at the source), `dG/dy = nu G` on `y = 0`, `dG/dy = 0` on `y = -h`,
//! and radiates outgoing waves with the deep-water phase convention, so that `G` tends to the
//! deep-water `G` of the same `nu` as `h -> inf`.
//!
//! # Dispersion ([`wavenumber`], [`evanescent_wavenumbers`])
//! The propagating wavenumber `k0` solves `nu = k0 tanh(k0 h)` (Newton in `t = k0 h` from
//! Eckart's `t = nu h / sqrt(tanh(nu h))`, inside the bracket
//! `max(nu h, sqrt(nu h)) <= t <= t_max`); the evanescent ones `k_n`, `n >= 1`, solve
//! `k_n tan(k_n h) = -nu`, `k_n h = n pi - e`, `e = atan(nu h / (n pi - e))` in `(0, pi/2)`
//! (Newton, monotone from `e = atan(nu h / (n pi))`).
//!
//! # Eigenfunction series (John 1950; Wehausen & Laitone 1960, eq. 13.19)
//! With `X = x - x0`, `Z0(y) = cosh k0(y + h)`, `Z_n(y) = cos k_n(y + h)` (orthogonal on
//! `[-h, 0]`, `int Z0^2 = (2 k0 h + sinh 2 k0 h)/(4 k0)`, `int Z_n^2 = (2 k_n h + sin 2 k_n h)/(4 k_n)`):
//! ```text
//! G = i A0 Z0(y) Z0(y0) e^{-i k0 |X|} + sum_{n>=1} A_n Z_n(y) Z_n(y0) e^{-k_n |X|}
//! A0 = 2 / (2 k0 h + sinh 2 k0 h),   A_n = -2 / (2 k_n h + sin 2 k_n h)
//! ```
//! (each mode solves `g'' -/+ k^2 g = delta(X)`). `A0 Z0 Z0 -> e^{nu (y + y0)}` as `h -> inf`:
//! the deep-water outgoing wave `i e^{k(y+y0)} e^{-ik|X|}`. The terms fall like `e^{-k_n |X|}`
//! (`k_n ~ n pi / h`); the series serves where `k_1 |X| >= 1` (at most about 40 terms).
//!
//! # Near form
//! Where `k_1 |X| < 1`: the deep-water `G_inf` of the same `nu` (free-surface image and wave
//! part in closed form), the bottom image `r2 = |x - (x0, -2h - y0)|`, and a smooth remainder:
//! ```text
//! Re G = Re G_inf + (1/2pi) ln(r2 / 2h) + R,    Im G = A0 Z0(y) Z0(y0) cos(k0 X)
//! R = (1/pi) PV int_0^inf [ cos(mX) (m + nu)/m B(m) - e^{-2mh}/(2m) ] dm
//! B = [E - T] / (2 D),  D = (nu - m) + (nu + m) e^{-2mh}
//! E = e^{-m(Y + 4h)} + e^{m(y - y0 - 2h)} + e^{-m(y - y0 + 2h)},  T = e^{m(Y - 2h)} (nu + m)/(nu - m)
//! ```
//! `Y = y + y0`. This is Wehausen & Laitone's eq. 13.18 (John's integral,
//! `(m + nu) e^{-mh} cosh m(y+h) cosh m(y0+h) / (m (nu cosh mh - m sinh mh))`) minus the Fourier
//! integrals of `G_inf - (1/2pi) ln r0` and of `(1/2pi) ln(r2/2h)`, rearranged so that every
//! exponential decays at least like `e^{-m d}`, `d = 2h - |y - y0| >= h` (the nearest images
//! left: the free-surface image reflected in the bottom and the bottom image reflected in the
//! surface). The integrand is finite at `m = 0`, real on the real axis, with simple poles at
//! `m = nu` (the subtracted deep-water wave) and `m = k0` (`D = 0`) of real residues: the
//! principal value is the real part of the integral along half circles above the poles
//! (radius `min(a/2, 1/2h)` about the pole `a`, merged when they overlap), the rest of
//! `[0, M]` on the real axis. Each piece gets 16-point Gauss-Legendre: `[0, 2/h]`, `[2/h, 4/h]`,
//! doubling up to `M = 50/d`. When `k0 d > 40` the poles are left out: their pair then
//! contributes `O(e^{-2 k0 h})`.
//!
//! # Panels
//! [`FiniteDepthGreen::panel_integral`] (same panel conventions as the deep-water one) adds the
//! deep-water closed form ([`GreenFunction::panel_integral`]),
//! the closed-form integral of `(1/2pi) ln r2` (the Rankine panel integral in the frame
//! mirrored in the bottom) and `G - G_inf - (1/2pi) ln(r2/2h)`, smooth on the panel, by
//! [`PANEL_NODES`]-point Gauss-Legendre.
//!
//! # Accuracy and cost (tests, 2026-11-29)
//! Near form against the series where both converge (`0.5 <= k_1 |X| <= 2`): within `2e-13`
//! of `1 + |G|` (value, and gradient times `h`), for `nu h` from 0.003 to 30, and as much
//! across the switch. Panel integrals against adaptive quadrature: within `1e-14` of
//! `L + |int G ds|` for panels up to `h/2` long. `G_h - G_inf` falls like `1/(nu h)^2`:
//! `3.3e-4` at `nu h = 20`. Cost (optimized build, shared machine): a point about 20-30 us in
//! the near form, 0.5 us by the series; a panel integral about 0.2 ms near its field point,
//! 12 us far from it.
//!
//! # References
//! F. John, "On the motion of floating bodies II", Comm. Pure Appl. Math. 3 (1950) 45-101.
//! J. V. Wehausen, E. V. Laitone, "Surface waves", Handbuch der Physik IX (1960), sect. 13.
//! J. N. Newman, "Algorithms for the free-surface Green function", J. Eng. Math. 19 (1985).

mod near;
mod strip;
#[cfg(test)]
mod tests;

pub use strip::{
    limit_remainder, limit_remainder_integral, RemainderIntegrals, RemainderMatrix, RemainderRow,
};

use super::panel::Panel;
use super::{FreeSurface, GreenFunction, PanelIntegral, Point};
use num_complex::Complex64;
use std::f64::consts::PI;
use std::fmt;

/// Gauss-Legendre nodes on a panel for the smooth remainder.
pub const PANEL_NODES: usize = 10;
/// The eigenfunction series serves where `k_1 |X|` reaches this.
const SERIES_SWITCH: f64 = 1.0;
/// Evanescent modes kept: up to `k_n >= SERIES_REACH k_1`, enough for `e^{-k_n |X|} < 1e-17`
/// down to `k_1 |X| = 0.5` (the overlap with the near form, tested).
const SERIES_REACH: f64 = 80.0;
const MAX_ITERATIONS: usize = 100;

/// Invalid input to the finite-depth dispersion relation or Green function.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum DepthError {
    /// The water depth (m) must be finite and strictly positive.
    InvalidDepth(f64),
    /// `nu = omega^2 / g` (1/m) must be finite and strictly positive.
    InvalidFrequency(f64),
    /// Newton's method on the dispersion relation did not converge.
    NoConvergence {
        /// `omega^2 / g` (1/m).
        nu: f64,
        /// Water depth (m).
        depth: f64,
    },
}

impl fmt::Display for DepthError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DepthError::InvalidDepth(h) => {
                write!(f, "water depth must be finite and > 0, got {h}")
            }
            DepthError::InvalidFrequency(nu) => write!(
                f,
                "frequency parameter nu = omega^2/g must be finite and > 0, got {nu}"
            ),
            DepthError::NoConvergence { nu, depth } => write!(
                f,
                "the dispersion relation did not converge for nu = {nu}, depth = {depth}"
            ),
        }
    }
}

impl std::error::Error for DepthError {}

fn validate(nu: f64, depth: f64) -> Result<(), DepthError> {
    if !(depth.is_finite() && depth > 0.0) {
        return Err(DepthError::InvalidDepth(depth));
    }
    if !(nu.is_finite() && nu > 0.0) {
        return Err(DepthError::InvalidFrequency(nu));
    }
    Ok(())
}

/// The propagating wavenumber `k` (1/m) of `nu = k tanh(k h)`, `nu = omega^2/g`, to about
/// `1e-15` relative.
///
/// # Errors
/// [`DepthError`] for a depth or `nu` not finite and > 0, or no convergence.
pub fn wavenumber(nu: f64, depth: f64) -> Result<f64, DepthError> {
    validate(nu, depth)?;
    let mu = nu * depth;
    // t tanh t = mu: t >= mu (tanh <= 1), t >= sqrt(mu) (tanh t <= t); above: t tanh t >= t - 1/e
    // for the large, t^2/(1 + t) <= t tanh t for the small.
    let mut lo = mu.max(mu.sqrt());
    let mut hi = if mu >= 1.0 {
        mu + 1.0
    } else {
        0.5 * (mu + (mu * mu + 4.0 * mu).sqrt())
    };
    let mut t = (mu / mu.tanh().sqrt()).clamp(lo, hi);
    for _ in 0..MAX_ITERATIONS {
        let th = t.tanh();
        let f = t * th - mu;
        if f == 0.0 {
            return Ok(t / depth);
        }
        if f > 0.0 {
            hi = t;
        } else {
            lo = t;
        }
        let slope = th + t * (1.0 - th * th);
        let mut next = t - f / slope;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        let step = (next - t).abs();
        t = next;
        if step <= 1e-16 * t || hi - lo <= 1e-16 * t {
            return Ok(t / depth);
        }
    }
    Err(DepthError::NoConvergence { nu, depth })
}

/// The first `count` evanescent wavenumbers `k_n` (1/m), `n = 1..=count`, of
/// `k_n tan(k_n h) = -nu`, `(n - 1/2) pi < k_n h < n pi`, to about `1e-15` relative.
///
/// # Errors
/// [`DepthError`] for a depth or `nu` not finite and > 0, or no convergence.
pub fn evanescent_wavenumbers(nu: f64, depth: f64, count: usize) -> Result<Vec<f64>, DepthError> {
    validate(nu, depth)?;
    let mu = nu * depth;
    (1..=count)
        .map(|n| {
            let n_pi = n as f64 * PI;
            // g(e) = e - atan(mu / (n pi - e)): increasing and concave, Newton from the left.
            let mut e = (mu / n_pi).atan();
            for _ in 0..MAX_ITERATIONS {
                let c = n_pi - e;
                let g = e - (mu / c).atan();
                let slope = 1.0 - mu / (c * c + mu * mu);
                let step = g / slope;
                e -= step;
                if step.abs() <= 1e-16 * n_pi {
                    return Ok((n_pi - e) / depth);
                }
            }
            Err(DepthError::NoConvergence { nu, depth })
        })
        .collect()
}

/// An evanescent mode: `A_n cos k_n(y + h) cos k_n(y0 + h) e^{-k_n |X|}`.
#[derive(Clone, Copy, Debug)]
struct Mode {
    wavenumber: f64,
    coefficient: f64,
}

/// The finite-depth free-surface Green function for one frequency and depth.
#[derive(Clone, Debug)]
pub struct FiniteDepthGreen {
    nu: f64,
    depth: f64,
    k0: f64,
    deep: GreenFunction,
    modes: Vec<Mode>,
    /// 16-point Gauss-Legendre `(node, weight)` on `[-1, 1]` (the near form's integral).
    integral_rule: Vec<(f64, f64)>,
    /// [`PANEL_NODES`]-point Gauss-Legendre on `[-1, 1]`.
    panel_rule: Vec<(f64, f64)>,
}

impl FiniteDepthGreen {
    /// The Green function for `nu = omega^2/g` (1/m) and water depth `depth` (m).
    ///
    /// # Errors
    /// [`DepthError`] for a depth or `nu` not finite and > 0, or no convergence.
    pub fn new(nu: f64, depth: f64) -> Result<Self, DepthError> {
        let k0 = wavenumber(nu, depth)?;
        let deep = GreenFunction::new(FreeSurface::Wave { wavenumber: nu })
            .map_err(|_| DepthError::InvalidFrequency(nu))?;
        // k_n h > (n - 1/2) pi and k_1 h < pi: n = 1.. up to SERIES_REACH k_1.
        let first = evanescent_wavenumbers(nu, depth, 1)?[0];
        let count = (SERIES_REACH * first * depth / PI + 1.5).ceil() as usize;
        let modes = evanescent_wavenumbers(nu, depth, count)?
            .into_iter()
            .map(|k| {
                let t = 2.0 * k * depth;
                Mode {
                    wavenumber: k,
                    coefficient: -2.0 / (t + t.sin()),
                }
            })
            .collect();
        Ok(Self {
            nu,
            depth,
            k0,
            deep,
            modes,
            integral_rule: gauss_legendre(16),
            panel_rule: gauss_legendre(PANEL_NODES),
        })
    }

    /// `nu = omega^2/g` (1/m).
    pub fn nu(&self) -> f64 {
        self.nu
    }

    /// The water depth (m).
    pub fn depth(&self) -> f64 {
        self.depth
    }

    /// The propagating wavenumber `k0` (1/m).
    pub fn wavenumber(&self) -> f64 {
        self.k0
    }

    /// `G(field, source)` and `grad_field G`, `[d/dx, d/dy]`.
    ///
    /// Both points should lie in `-h <= y <= 0`. At `field == source` (and at the images of the
    /// source on the free surface or the bottom) the values are not finite; nothing panics.
    pub fn value_and_gradient(&self, field: Point, source: Point) -> (Complex64, [Complex64; 2]) {
        if self.series_serves(field[0] - source[0]) {
            return self.series(field, source);
        }
        let (deep, deep_gradient) = self.deep.value_and_gradient(field, source);
        let (log, log_gradient) = self.bottom_log(field, source);
        let [r, r_x, r_y] = self.near_remainder(field, source);
        let x = field[0] - source[0];
        let (wave, wave_y) = self.propagating_depth_factor(field[1], source[1]);
        let (sin, cos) = (self.k0 * x).sin_cos();
        (
            Complex64::new(deep.re + log + r, wave * cos),
            [
                Complex64::new(
                    deep_gradient[0].re + log_gradient[0] + r_x,
                    -wave * self.k0 * sin,
                ),
                Complex64::new(deep_gradient[1].re + log_gradient[1] + r_y, wave_y * cos),
            ],
        )
    }

    /// `int_a^b G(field, x0) ds0` over the straight panel `a -> b` and its gradient with
    /// respect to `field`, with the conventions of
    /// [`GreenFunction::panel_integral`] (on the panel:
    /// the limit from the fluid side). A zero-length panel gives zeros.
    pub fn panel_integral(&self, field: Point, a: Point, b: Point) -> PanelIntegral {
        let mut out = self.deep.panel_integral(field, a, b);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        if len == 0.0 {
            return out;
        }
        let log = bottom_image_integral(self.depth, field, a, b);
        out.potential.re += log.potential.re - len * (2.0 * self.depth).ln() / (2.0 * PI);
        out.gradient[0].re += log.gradient[0].re;
        out.gradient[1].re += log.gradient[1].re;
        let half = 0.5 * len;
        for &(t, w) in &self.panel_rule {
            let s = 0.5 * (1.0 + t);
            let source = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])];
            let (value, gradient) = self.remainder(field, source);
            out.potential += value * (w * half);
            out.gradient[0] += gradient[0] * (w * half);
            out.gradient[1] += gradient[1] * (w * half);
        }
        out
    }

    /// `G - G_inf - (1/2pi) ln(r2/2h)` and its gradient: smooth in the closed fluid strip.
    fn remainder(&self, field: Point, source: Point) -> (Complex64, [Complex64; 2]) {
        let (deep, deep_gradient) = self.deep.value_and_gradient(field, source);
        let (log, log_gradient) = self.bottom_log(field, source);
        if self.series_serves(field[0] - source[0]) {
            let (g, gradient) = self.series(field, source);
            return (
                g - deep - log,
                [
                    gradient[0] - deep_gradient[0] - log_gradient[0],
                    gradient[1] - deep_gradient[1] - log_gradient[1],
                ],
            );
        }
        let [r, r_x, r_y] = self.near_remainder(field, source);
        let x = field[0] - source[0];
        let (wave, wave_y) = self.propagating_depth_factor(field[1], source[1]);
        let (sin, cos) = (self.k0 * x).sin_cos();
        (
            Complex64::new(r, wave * cos - deep.im),
            [
                Complex64::new(r_x, -wave * self.k0 * sin - deep_gradient[0].im),
                Complex64::new(r_y, wave_y * cos - deep_gradient[1].im),
            ],
        )
    }

    /// Whether the eigenfunction series serves at `X = x - x0`.
    fn series_serves(&self, x: f64) -> bool {
        self.modes
            .first()
            .is_some_and(|mode| mode.wavenumber * x.abs() >= SERIES_SWITCH)
    }

    /// `(1/2pi) ln(r2 / 2h)` and its gradient, `r2` the distance to the bottom image.
    fn bottom_log(&self, field: Point, source: Point) -> (f64, [f64; 2]) {
        let x = field[0] - source[0];
        let y = field[1] + source[1] + 2.0 * self.depth;
        let r2_sq = x * x + y * y;
        (
            (r2_sq.ln() - 2.0 * (2.0 * self.depth).ln()) / (4.0 * PI),
            [x / (2.0 * PI * r2_sq), y / (2.0 * PI * r2_sq)],
        )
    }

    /// `A0 Z0(y) Z0(y0)` and its `y` derivative, scaled so that nothing overflows:
    /// `e^{k0 Y} (1 + a)(1 + b) / (4 k0 h q + 1 - q^2)`, `a = e^{-2k0(y+h)}`,
    /// `b = e^{-2k0(y0+h)}`, `q = e^{-2k0 h}`.
    fn propagating_depth_factor(&self, y: f64, y0: f64) -> (f64, f64) {
        let k = self.k0;
        let h = self.depth;
        let q = (-2.0 * k * h).exp();
        let a = (-2.0 * k * (y + h)).exp();
        let b = (-2.0 * k * (y0 + h)).exp();
        let scale = (k * (y + y0)).exp() / (4.0 * k * h * q + (1.0 - q * q));
        (
            scale * (1.0 + a) * (1.0 + b),
            k * scale * (1.0 - a) * (1.0 + b),
        )
    }

    /// `G` and its gradient by the eigenfunction series (`X != 0`).
    fn series(&self, field: Point, source: Point) -> (Complex64, [Complex64; 2]) {
        let x = field[0] - source[0];
        let (ax, sign) = (x.abs(), x.signum());
        let (y, y0) = (field[1], source[1]);
        let h = self.depth;
        let k = self.k0;
        let (wave, wave_y) = self.propagating_depth_factor(y, y0);
        // i c e^{-ik|X|}: real c sin(k|X|), imaginary c cos(kX).
        let (sin, cos) = (k * ax).sin_cos();
        let mut value = Complex64::new(wave * sin, wave * cos);
        let mut d_x = Complex64::new(sign * wave * k * cos, -sign * wave * k * sin);
        let mut d_y = Complex64::new(wave_y * sin, wave_y * cos);
        for mode in &self.modes {
            let kn = mode.wavenumber;
            let decay = (-kn * ax).exp();
            if decay < 1e-18 {
                break;
            }
            let (sin_y, cos_y) = (kn * (y + h)).sin_cos();
            let term = mode.coefficient * (kn * (y0 + h)).cos() * decay;
            value.re += term * cos_y;
            d_x.re -= sign * kn * term * cos_y;
            d_y.re -= kn * term * sin_y;
        }
        (value, [d_x, d_y])
    }
}

/// `int (1/2pi) ln r2 ds0` over the panel `a -> b` and its gradient with respect to `field`,
/// `r2` the distance from `field` to the source's image in the bottom `y = -h` (real).
pub fn bottom_image_integral(depth: f64, field: Point, a: Point, b: Point) -> PanelIntegral {
    let zero = Complex64::new(0.0, 0.0);
    let mut out = PanelIntegral {
        potential: zero,
        gradient: [zero, zero],
    };
    // In the frame mirrored in the bottom (y' = -(y + h)) the bottom image is the image in
    // y' = 0 and the fluid lies below; the mirror swaps the panel's sides.
    let mirror = |p: Point| [p[0], -(p[1] + depth)];
    if let Some((panel, zf)) = Panel::new(mirror(field), mirror(b), mirror(a)) {
        let (sum, d_sum) = panel.rankine(zf, 1.0);
        let (difference, d_difference) = panel.rankine(zf, -1.0);
        out.potential.re = 0.5 * (sum - difference);
        let d_log = 0.5 * (d_sum - d_difference);
        out.gradient[0].re = d_log.re;
        // d/dy = -d/dy' = +Im of the complex derivative.
        out.gradient[1].re = d_log.im;
    }
    out
}

/// Gauss-Legendre `(node, weight)` on `[-1, 1]` (Newton on the Legendre recurrence).
pub(super) fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..MAX_ITERATIONS {
                let (mut p0, mut p1) = (1.0, x);
                for j in 2..=n {
                    let jf = j as f64;
                    let p2 = ((2.0 * jf - 1.0) * x * p1 - (jf - 1.0) * p0) / jf;
                    p0 = p1;
                    p1 = p2;
                }
                derivative = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / derivative;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * derivative * derivative))
        })
        .collect()
}
