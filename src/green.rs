//! Deep-water two-dimensional free-surface Green function (seed eq. 11-12, after Damaren 2000),
//! its gradient, its two frequency limits, the complex exponential integral `E1`, and exact
//! integrals over straight source panels.
//!
//! # Conventions
//! `x` to the right, `y` up, fluid in `y < 0`, mean free surface `y = 0`, infinite depth, time
//! factor `exp(+i omega t)`, wavenumber `k = omega^2 / g`. Points are `[x, y]`.
//!
//! # The Green function
//! Potential at the field point `x` of a unit source at `x0` (seed eq. 11-12):
//! ```text
//! G(x, x0) = (1/2pi) ln(r0/r1) - (1/pi) Re{e^{kz} E1(kz)} + i e^{kz}
//! r0 = |x - x0|,  r1 = |x - x0*|,  x0* = (x0, -y0),  z = (y + y0) - i |x - x0|
//! ```
//! `i e^{kz}` puts `e^{k(y+y0)} sin(k|x - x0|)` into the REAL part of `G`; the kinks in
//! `|x - x0|` of the two wave terms cancel, so `G` is harmonic in the fluid, satisfies
//! `dG/dy = k G` on `y = 0` and radiates outgoing waves `~ i e^{k(y+y0)} e^{-ik|x-x0|}`.
//!
//! The code uses the equivalent analytic form. With `zeta = x + iy`, `zeta0 = x0 + i y0`,
//! `u = zeta - zeta0`, `v = zeta - conj(zeta0)` and `p = i k v = k(-(y + y0) + i(x - x0))`
//! (`Re p >= 0` in the fluid):
//! ```text
//! G = (1/2pi) ln(r0/r1) + (1/pi) Re Q(p) + i Re e^{-p},   Q(p) = e^{-p} Ei(p)
//! Q(p) = -e^{-p} E1(-p) + i pi sgn(Im p) e^{-p}
//! ```
//! `Ei` is continued from the positive real axis, with its cut on the negative real axis of `p`
//! (above the free surface), so `Q` is analytic across `x = x0` where `kz` touches the cut of
//! `E1`. For an analytic `f(zeta)`, `grad Re f = (Re f', -Im f')`, and `Q'(p) = 1/p - Q(p)`,
//! which gives the gradient, the panel integrals in closed form, and all Taylor coefficients.
//!
//! # Frequency limits ([`FreeSurface`])
//! * `RigidLid` (`omega -> 0`, `dG/dy = 0` on `y = 0`): `G = (1/2pi)(ln r0 + ln r1)`.
//!   As `k -> 0`, `G_wave = G_rigid + (1/pi)(ln k + gamma) + i + O(k r1 ln(k r1))`: the constant
//!   `(1/pi)(ln k + gamma) + i` (`gamma`: Euler's constant) diverges and is DROPPED. It
//!   multiplies the net source strength, so it only matters for bodies with net flux (heave),
//!   whose `A(0)` diverges logarithmically.
//! * `Dirichlet` (`omega -> inf`, `G = 0` on `y = 0`): `G = (1/2pi)(ln r0 - ln r1)`.
//!
//! Both limits are real.
//!
//! # Panels
//! A panel runs from `a` to `b`; the body lies on the LEFT of `a -> b`, the fluid on the RIGHT;
//! its unit normal `n = (-t_y, t_x)`, `t = (b - a)/|b - a|`, points out of the fluid into the
//! body. [`GreenFunction::panel_integral`] returns `int_a^b G(x, x0) ds0` and its gradient with
//! respect to the field point, in closed form:
//! * Rankine parts `ln r0`, `ln r1`: exact formulas near the panel, a convergent multipole
//!   series about the panel centre when the distance exceeds twice the panel length;
//! * wave part: `int Q ds = [ln p + gamma - Q(p)] / (dp/ds)` between the end points (near), or
//!   the Taylor series about the panel centre, built from `Q(p_c)` and powers of `1/p_c` (far);
//! * `int e^{-p} ds = e^{-p_c} L sinh(h)/h`, `h = (dp/ds) L/2`, everywhere.
//!
//! A field point on the panel (within `1e-10` panel lengths) gets the limit from the fluid
//! side: the normal gradient component holds the jump `-1/2` plus the principal value.
//! Lid panels on `y = 0` (interior free-surface lid against irregular frequencies) work with
//! field points on `y = 0`: there `ln(r0/r1)` vanishes identically and the wave part has a
//! logarithmic singularity; the potential is exact, and the gradient is the limit from the fluid
//! below, where the coincident source and image make `d/dy int G ds = k int G ds - 1` on the
//! panel itself (`k int G ds` elsewhere on `y = 0`). The gradient is infinite at the end points
//! of the panel and, for `Wave`, at their mirror images.
//!
//! # Exponential integral, accuracy and speed
//! [`scaled_exp_integral`] (`e^z E1(z)`) uses the power series where `|z| + Re z <= 3` and
//! `|z| < 40`, else a division-free continued fraction; checked against mpmath on dense grids it
//! is within `4e-15` relative in the closed left half plane and `1e-14` elsewhere.
//! [`GreenFunction`] evaluates `Q` faster from a table of `Q` at ~1100 nodes (inner log-polar
//! grid for `1 <= |p| < 8`, outer square grid of spacing 1.2 up to `|p| = 40`), built in
//! [`GreenFunction::new`] for `Wave` (about 0.2 ms), and an at most 18-term Taylor series about
//! the nearest node (step `|h| <= 0.9`, `|h|/|p| <= 0.11`): within `5e-15 (|Q| + |F|)`.
//! Panel integrals agree with adaptive quadrature within `2e-13` of the integral of the
//! absolute integrand. On a 100-panel semicircle one wave panel integral costs about 0.2 us
//! (0.14 us for [`GreenFunction::panel_integral_beyond_dirichlet`], whose Dirichlet complement
//! does not depend on the frequency).

use num_complex::Complex64;
use std::f64::consts::PI;
use std::fmt;

/// A point `[x, y]` (y up, fluid in y < 0).
pub type Point = [f64; 2];

/// Euler's constant.
const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;

/// Boundary condition on the mean free surface `y = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FreeSurface {
    /// `omega -> 0`: `dphi/dy = 0` on `y = 0` (image source, plus sign).
    RigidLid,
    /// Linear waves of wavenumber `k = omega^2/g` (1/m), deep water.
    Wave {
        /// `k = omega^2 / g`, finite and > 0.
        wavenumber: f64,
    },
    /// `omega -> inf`: `phi = 0` on `y = 0` (image sink, minus sign).
    Dirichlet,
}

/// Invalid input to [`GreenFunction::new`].
#[derive(Clone, Debug, PartialEq)]
pub enum GreenError {
    /// The wavenumber must be finite and strictly positive.
    InvalidWavenumber(f64),
}

impl fmt::Display for GreenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GreenError::InvalidWavenumber(k) => write!(
                f,
                "wavenumber must be finite and > 0, got {k} (use FreeSurface::RigidLid or \
                 FreeSurface::Dirichlet for the limits)"
            ),
        }
    }
}

impl std::error::Error for GreenError {}

/// Integral of `G` over a straight panel and its gradient with respect to the field point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PanelIntegral {
    /// `int_panel G(x, x0) ds0`.
    pub potential: Complex64,
    /// `grad_x int_panel G(x, x0) ds0`, `[d/dx, d/dy]`.
    pub gradient: [Complex64; 2],
}

/// The free-surface Green function for one boundary condition (one frequency).
///
/// Holds a table of `e^{-p} Ei(p)` (about 23 kB, filled for `Wave` only); pass it by
/// reference in hot loops.
#[derive(Clone, Copy)]
pub struct GreenFunction {
    surface: FreeSurface,
    table: QTable,
}

impl fmt::Debug for GreenFunction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GreenFunction")
            .field("surface", &self.surface)
            .finish_non_exhaustive()
    }
}

/// A panel is "far" when the field point is at least this many panel lengths from its centre
/// (multipole series ratio `<= (1/(2*FAR_RATIO))^2`).
const FAR_RATIO: f64 = 2.0;
/// Far-field wave series only while `k L / 2` stays below this (keeps `sinh` moderate).
const FAR_WAVE_MAX_HALF_KL: f64 = 4.0;
/// Field points within this fraction of the panel length are taken on the panel.
const ON_PANEL_TOLERANCE: f64 = 1e-10;

impl GreenFunction {
    /// Green function for the given free-surface condition.
    ///
    /// # Errors
    /// [`GreenError::InvalidWavenumber`] unless the wavenumber of `Wave` is finite and > 0.
    pub fn new(surface: FreeSurface) -> Result<Self, GreenError> {
        let table = match surface {
            FreeSurface::Wave { wavenumber } => {
                if !(wavenumber.is_finite() && wavenumber > 0.0) {
                    return Err(GreenError::InvalidWavenumber(wavenumber));
                }
                QTable::new()
            }
            _ => QTable::empty(),
        };
        Ok(Self { surface, table })
    }

    /// The free-surface condition.
    pub fn surface(&self) -> FreeSurface {
        self.surface
    }

    /// `G(field, source)` and `grad_field G`, `[d/dx, d/dy]`.
    ///
    /// Both points should lie in `y <= 0`. At `field == source` (and for `Wave` at a field
    /// point that is the mirror image of the source, both on `y = 0`) the values are not
    /// finite; nothing panics.
    pub fn value_and_gradient(&self, field: Point, source: Point) -> (Complex64, [Complex64; 2]) {
        let zf = Complex64::new(field[0], field[1]);
        let z0 = Complex64::new(source[0], source[1]);
        let u = zf - z0;
        let v = zf - z0.conj();
        let (rankine, rankine_d) = match self.surface {
            FreeSurface::RigidLid => (
                (u.norm_sqr().ln() + v.norm_sqr().ln()) / (4.0 * PI),
                (u.inv() + v.inv()) / (2.0 * PI),
            ),
            FreeSurface::Wave { .. } | FreeSurface::Dirichlet => (
                log_ratio(field[1], source[1], v.norm_sqr()) / (2.0 * PI),
                Complex64::new(0.0, source[1] / PI) / (u * v),
            ),
        };
        match self.surface {
            FreeSurface::Wave { wavenumber: k } => {
                let ik = Complex64::new(0.0, k);
                let p = ik * v;
                let (q, exp) = self.table.q_and_exp(p);
                let d_re = rankine_d + ik / PI * (p.inv() - q);
                let d_im = -ik * exp;
                (
                    Complex64::new(rankine + q.re / PI, exp.re),
                    [
                        Complex64::new(d_re.re, d_im.re),
                        Complex64::new(-d_re.im, -d_im.im),
                    ],
                )
            }
            _ => (
                Complex64::new(rankine, 0.0),
                [
                    Complex64::new(rankine_d.re, 0.0),
                    Complex64::new(-rankine_d.im, 0.0),
                ],
            ),
        }
    }

    /// `int_a^b G(field, x0) ds0` over the straight panel `a -> b` and its gradient with
    /// respect to `field`.
    ///
    /// Exact for every field position (see the module docs): on the panel the gradient is the
    /// limit from the fluid side (right of `a -> b`), i.e. its normal component holds `-1/2`
    /// plus the principal value. A zero-length panel gives zeros. Non-finite input gives
    /// non-finite output.
    pub fn panel_integral(&self, field: Point, a: Point, b: Point) -> PanelIntegral {
        let zero = Complex64::new(0.0, 0.0);
        let mut out = PanelIntegral {
            potential: zero,
            gradient: [zero, zero],
        };
        let Some((panel, zf)) = Panel::new(field, a, b) else {
            return out;
        };
        // A panel lying on y = 0: r0 == r1 for every field point, ln(r0/r1) vanishes exactly.
        let lid = a[1] == 0.0 && b[1] == 0.0;
        let sign = match self.surface {
            FreeSurface::RigidLid => 1.0,
            _ => -1.0,
        };
        if sign > 0.0 || !lid {
            // Real, from an analytic integrand with complex derivative `d`.
            let (pot, d) = panel.rankine(zf, sign);
            out.potential.re = pot;
            out.gradient = [Complex64::new(d.re, 0.0), Complex64::new(-d.im, 0.0)];
        }
        if let FreeSurface::Wave { .. } = self.surface {
            self.add_wave(&panel, zf, &mut out);
        }
        out
    }

    /// Adds the wave part `(1/pi) Re Q(p) + i Re e^{-p}` of the panel integral to `out`.
    fn add_wave(&self, panel: &Panel, zf: Complex64, out: &mut PanelIntegral) {
        let FreeSurface::Wave { wavenumber } = self.surface else {
            return;
        };
        let w = panel.wave(zf, wavenumber, &self.table);
        let ik = Complex64::new(0.0, wavenumber);
        // Complex derivatives of the analytic integrands behind the real and imaginary parts.
        let d_re = ik / PI * w.dq_integral;
        let d_im = -ik * w.exp_integral;
        out.potential += Complex64::new(w.q_integral.re / PI, w.exp_integral.re);
        out.gradient[0] += Complex64::new(d_re.re, d_im.re);
        out.gradient[1] += Complex64::new(-d_re.im, -d_im.im);
    }

    /// The part of [`GreenFunction::panel_integral`] beyond the Dirichlet (`omega -> inf`)
    /// Green function: `int (G - (1/2pi) ln(r0/r1)) ds0` and its gradient. That is the wave
    /// part `(1/pi) Re Q(p) + i Re e^{-p}` for `Wave`, `(1/pi) ln r1` for `RigidLid` and zero for
    /// `Dirichlet`. The Dirichlet integrals do not depend on the frequency: a frequency sweep
    /// can compute them once and add this part per frequency.
    pub fn panel_integral_beyond_dirichlet(
        &self,
        field: Point,
        a: Point,
        b: Point,
    ) -> PanelIntegral {
        let zero = Complex64::new(0.0, 0.0);
        let mut out = PanelIntegral {
            potential: zero,
            gradient: [zero, zero],
        };
        let Some((panel, zf)) = Panel::new(field, a, b) else {
            return out;
        };
        match self.surface {
            FreeSurface::Wave { .. } => self.add_wave(&panel, zf, &mut out),
            FreeSurface::Dirichlet => {}
            FreeSurface::RigidLid => {
                let (mut pot, mut d) = panel.rankine(zf, 1.0);
                if !(a[1] == 0.0 && b[1] == 0.0) {
                    let (pot_d, d_d) = panel.rankine(zf, -1.0);
                    pot -= pot_d;
                    d -= d_d;
                }
                out.potential.re = pot;
                out.gradient = [Complex64::new(d.re, 0.0), Complex64::new(-d.im, 0.0)];
            }
        }
        out
    }
}

/// `ln(r0/r1)` without cancellation: `r1^2 - r0^2 = 4 y y0`.
fn log_ratio(y: f64, y0: f64, r1_sq: f64) -> f64 {
    0.5 * (-4.0 * y * y0 / r1_sq).ln_1p()
}

/// Geometry of a straight panel, `zeta0(s) = centre + s tau`, `s in [-half, half]`.
struct Panel {
    tau: Complex64,
    half: f64,
    centre: Complex64,
    a: Complex64,
    b: Complex64,
}

/// Integrals of the wave part over a panel.
struct WaveIntegrals {
    /// `int Q(p) ds`.
    q_integral: Complex64,
    /// `int Q'(p) ds = int (1/p - Q) ds`.
    dq_integral: Complex64,
    /// `int e^{-p} ds`.
    exp_integral: Complex64,
}

impl Panel {
    /// The panel `a -> b` and the field point as complex numbers; `None` for zero length.
    fn new(field: Point, a: Point, b: Point) -> Option<(Self, Complex64)> {
        let za = Complex64::new(a[0], a[1]);
        let zb = Complex64::new(b[0], b[1]);
        let d = zb - za;
        let len = d.norm_sqr().sqrt();
        if len == 0.0 {
            return None;
        }
        let panel = Panel {
            tau: d / len,
            half: 0.5 * len,
            centre: za + 0.5 * d,
            a: za,
            b: zb,
        };
        Some((panel, Complex64::new(field[0], field[1])))
    }

    /// `(1/2pi) int (ln r0 + sign ln r1) ds` and the complex derivative of the analytic
    /// integrand `(1/2pi) int (ln u + sign ln v) ds` (`u = zeta - zeta0`, `v = zeta - conj zeta0`).
    fn rankine(&self, zf: Complex64, sign: f64) -> (f64, Complex64) {
        let len = 2.0 * self.half;
        let far_sq = (FAR_RATIO * len) * (FAR_RATIO * len);
        let u_c = zf - self.centre;
        let v_c = zf - self.centre.conj();
        let far_direct = u_c.norm_sqr() >= far_sq;
        let far_image = v_c.norm_sqr() >= far_sq;
        let (pot, der) = if sign < 0.0 && far_direct && far_image {
            // Difference form: no cancellation between ln r0 and ln r1 far away.
            let (iu, iv) = (u_c.inv(), v_c.inv());
            let (s0, s1) = log_series(self.half * self.tau * iu);
            let (t0, t1) = log_series(self.half * self.tau.conj() * iv);
            let pot = len * (log_ratio(zf.im, self.centre.im, v_c.norm_sqr()) - (s0 - t0).re);
            let der =
                len * (Complex64::new(0.0, 2.0 * self.centre.im) * iu * iv + s1 * iu - t1 * iv);
            (pot, der)
        } else {
            let (pd, dd) = if far_direct {
                let iu = u_c.inv();
                let (s0, s1) = log_series(self.half * self.tau * iu);
                (
                    len * (0.5 * u_c.norm_sqr().ln() - s0.re),
                    len * (1.0 + s1) * iu,
                )
            } else {
                // Local frame: u = tau (w - s); fluid on the right (eta < 0).
                let (pot, der) = segment_log(self.tau.conj() * u_c, self.half, -1.0);
                (pot, self.tau.conj() * der)
            };
            let (pi, di) = if far_image {
                let iv = v_c.inv();
                let (s0, s1) = log_series(self.half * self.tau.conj() * iv);
                (
                    len * (0.5 * v_c.norm_sqr().ln() - s0.re),
                    len * (1.0 + s1) * iv,
                )
            } else {
                // v = conj(tau) (w' - s); the fluid below y = 0 has sign(eta') = -sign(tau_x).
                let side = if self.tau.re > 0.0 { -1.0 } else { 1.0 };
                let (pot, der) = segment_log(self.tau * v_c, self.half, side);
                (pot, self.tau * der)
            };
            (pd + sign * pi, dd + sign * di)
        };
        (pot / (2.0 * PI), der / (2.0 * PI))
    }

    /// Integrals of `Q(p)`, `Q'(p)`, `e^{-p}` over the panel, `p = i k (zeta - conj zeta0(s))`.
    fn wave(&self, zf: Complex64, k: f64, table: &QTable) -> WaveIntegrals {
        let len = 2.0 * self.half;
        let v_c = zf - self.centre.conj();
        if v_c.norm_sqr() < (FAR_RATIO * len) * (FAR_RATIO * len)
            || k * self.half > FAR_WAVE_MAX_HALF_KL
        {
            return self.wave_exact(zf, k, table);
        }
        // Taylor series about the centre, p = p_c + s dp/ds:
        // Q^(n)(p_c) = (-1)^n (Q - A_n), A_n = sum_{j<n} j!/p_c^{j+1}, and
        // int Q ds = L (Q sinh(h)/h - sum_{m>=1} B_m), B_m = h^{2m} A_{2m} / (2m+1)!,
        // h = (dp/ds) L/2, by a recurrence in g = h/p_c (|g| <= 1/(2 FAR_RATIO)).
        let ik = Complex64::new(0.0, k);
        let p_c = ik * v_c;
        let hh = -ik * self.tau.conj() * self.half;
        let sh = sinhc(hh);
        let (q, exp) = table.q_and_exp(p_c);
        let w = p_c.inv();
        let g = hh * w;
        let g2 = g * g;
        let hh2 = hh * hh;
        let mut b = Complex64::new(0.0, 0.0);
        let mut b_sum = Complex64::new(0.0, 0.0);
        let mut g_odd = g; // g^{2m-1}
        let tol = 1e-17 * (q.l1_norm() + w.l1_norm());
        for m in 1..SERIES_COEFFICIENTS {
            // B_m = h^2/(2m(2m+1)) B_{m-1} + (h g^{2m-1}/(2m-1) + g^{2m}) / (2m(2m+1))
            let c2 = EVEN_ODD[m];
            b = hh2 * c2 * b + (hh * g_odd * ODD[m - 1] + g_odd * g) * c2;
            b_sum += b;
            // Stop once past the sinh hump (h^2 c2 < 1/2) with a negligible term.
            if b.l1_norm() <= tol && hh2.l1_norm() * c2 < 0.5 {
                break;
            }
            g_odd *= g2;
        }
        // int ds/p = (L/p_c) atanh(g)/g.
        let (_, s1) = log_series(g);
        let main = q * sh - b_sum;
        WaveIntegrals {
            q_integral: len * main,
            dq_integral: -len * (main - (1.0 + s1) * w),
            exp_integral: exp * len * sh,
        }
    }

    /// [`Panel::wave`] from the antiderivatives at the end points (any distance).
    fn wave_exact(&self, zf: Complex64, k: f64, table: &QTable) -> WaveIntegrals {
        let ik = Complex64::new(0.0, k);
        let slope = -ik * self.tau.conj(); // dp/ds
        let (ka, qa) = wave_endpoint(ik * (zf - self.a.conj()), table);
        let (kb, qb) = wave_endpoint(ik * (zf - self.b.conj()), table);
        // int e^{-p} ds = e^{-p_c} L sinh(h)/h (no cancellation for small k L).
        let hh = slope * self.half;
        let exp_c = (-ik * (zf - self.centre.conj())).exp();
        WaveIntegrals {
            q_integral: (kb - ka) / slope,
            dq_integral: (qb - qa) / slope,
            exp_integral: exp_c * (2.0 * self.half) * sinhc(hh),
        }
    }
}

/// `int_{-h}^{h} ln|w - s| ds` and `int_{-h}^{h} ds / (w - s)` in closed form. A point on the
/// segment (`|Im w| <= tol`, `|Re w| < h`) gets the limit from the side `sign(Im w) = side`.
fn segment_log(w: Complex64, h: f64, side: f64) -> (f64, Complex64) {
    let ta = w.re + h;
    let tb = w.re - h;
    let mut eta = w.im;
    // Subtended angle arg(w + h) - arg(w - h).
    let angle = if eta.abs() <= 2.0 * ON_PANEL_TOLERANCE * h && ta > 0.0 && tb < 0.0 {
        eta = 0.0;
        -side * PI
    } else {
        (-2.0 * h * eta).atan2(ta * tb + eta * eta)
    };
    let ra2 = ta * ta + eta * eta;
    let rb2 = tb * tb + eta * eta;
    let t_ln_r = |t: f64, r2: f64| if r2 > 0.0 { 0.5 * t * r2.ln() } else { 0.0 };
    let pot = t_ln_r(ta, ra2) - t_ln_r(tb, rb2) - 2.0 * h - eta * angle;
    (pot, Complex64::new(0.5 * (ra2 / rb2).ln(), angle))
}

/// Number of precomputed series coefficients.
const SERIES_COEFFICIENTS: usize = 40;
/// `1/(2m+1)`, `m >= 0`.
const ODD: [f64; SERIES_COEFFICIENTS] = {
    let mut c = [0.0; SERIES_COEFFICIENTS];
    let mut m = 0;
    while m < SERIES_COEFFICIENTS {
        c[m] = 1.0 / (2 * m + 1) as f64;
        m += 1;
    }
    c
};
/// `1/(2m(2m+1))`, `m >= 1` (index 0 unused).
const EVEN_ODD: [f64; SERIES_COEFFICIENTS] = {
    let mut c = [0.0; SERIES_COEFFICIENTS];
    let mut m = 1;
    while m < SERIES_COEFFICIENTS {
        c[m] = 1.0 / ((2 * m) * (2 * m + 1)) as f64;
        m += 1;
    }
    c
};

/// For `|q| <= 1/4`: `(sum_{m>=1} q^{2m}/(2m(2m+1)), sum_{m>=1} q^{2m}/(2m+1))`, so that
/// `int_{-h}^{h} ln(w - s) ds = 2h (ln w - first)` and
/// `int_{-h}^{h} ds/(w - s) = (2h/w)(1 + second)` with `q = h/w`.
fn log_series(q: Complex64) -> (Complex64, Complex64) {
    let q2 = q * q;
    let mut pow = q2;
    let mut s0 = Complex64::new(0.0, 0.0);
    let mut s1 = Complex64::new(0.0, 0.0);
    for m in 1..SERIES_COEFFICIENTS {
        s1 += pow * ODD[m];
        s0 += pow * EVEN_ODD[m];
        if pow.l1_norm() <= 1e-17 {
            break;
        }
        pow *= q2;
    }
    (s0, s1)
}

/// `sinh(x)/x`.
fn sinhc(x: Complex64) -> Complex64 {
    let x2 = x * x;
    let size = x2.l1_norm();
    if size > 1.0 {
        return x.sinh() / x;
    }
    // Horner on sum_{n<=terms} x^{2n}/(2n+1)!; remainder < 1e-17.
    let terms = if size <= 1e-4 {
        3
    } else if size <= 1e-2 {
        5
    } else if size <= 0.1 {
        7
    } else {
        9
    };
    let mut acc = Complex64::new(1.0, 0.0);
    for &c in EVEN_ODD[1..=terms].iter().rev() {
        acc = 1.0 + x2 * acc * c;
    }
    acc
}

/// `e^z - 1` without cancellation for small `z`.
fn expm1_complex(z: Complex64) -> Complex64 {
    let em1 = z.re.exp_m1();
    let (s, c) = z.im.sin_cos();
    let half = (0.5 * z.im).sin();
    Complex64::new(em1 * c - 2.0 * half * half, (em1 + 1.0) * s)
}

/// Antiderivative `K(p) = ln p + gamma - Q(p)` (`K' = Q`, `K(0) = 0`) and `Q(p)`, `Re p >= 0`.
fn wave_endpoint(p: Complex64, table: &QTable) -> (Complex64, Complex64) {
    if p.re == 0.0 && p.im == 0.0 {
        return (
            Complex64::new(0.0, 0.0),
            Complex64::new(f64::NEG_INFINITY, 0.0),
        );
    }
    if p.norm_sqr() <= 1.0 {
        // K = (1 - e^{-p})(ln p + gamma) - e^{-p} S(p): no O(1) constant to cancel.
        let ln_p = p.ln() + EULER_GAMMA;
        let s = ei_series_sum(p);
        let em1 = expm1_complex(-p);
        let e = em1 + 1.0;
        (-em1 * ln_p - e * s, e * (ln_p + s))
    } else {
        let (q, _) = table.q_and_exp(p);
        (p.ln() + EULER_GAMMA - q, q)
    }
}

// ---------------------------------------------------------------------------------------------
// Table of Q(p) = e^{-p} Ei(p) with Taylor steps
// ---------------------------------------------------------------------------------------------

/// Inner log-polar grid: rings `rho_j = INNER_RHO_MIN * 1.15^j`, `j < INNER_RINGS`, and angles
/// `tan(theta_i / 2) = i / INNER_ANGLES`, `i <= INNER_ANGLES` (first quadrant).
const INNER_RHO_MIN: f64 = 1.0;
const INNER_RHO_MAX: f64 = 8.0;
const INNER_RING_RATIO: f64 = 1.15;
/// `ln(1.15)`, `ln(INNER_RHO_MIN)`.
const INNER_LN_RATIO: f64 = 0.139_761_942_375_158_63;
const INNER_LN_RHO_MIN: f64 = 0.0;
const INNER_RINGS: usize = 16;
const INNER_ANGLES: usize = 12;
const INNER_NODES: usize = INNER_RINGS * (INNER_ANGLES + 1);
/// Outer square grid `(i, j) * OUTER_SPACING`, `i, j < OUTER_SIDE`, used for
/// `INNER_RHO_MAX <= |p| < TABLE_RHO_MAX`.
const OUTER_SPACING: f64 = 1.2;
const OUTER_SIDE: usize = 35;
const OUTER_NODES: usize = OUTER_SIDE * OUTER_SIDE;
const TABLE_RHO_MAX: f64 = 40.0;
/// Taylor terms: they decay like `(|h|/|p0|)^n` and `|h|^n/n!`, below `1e-17` after 18 terms for
/// the steps of both grids (`|h| <= 0.9`, `|h|/|p0| <= 0.11`).
const TAYLOR_TERMS: usize = 18;

/// `Q` at the nodes of the inner and outer grids.
#[derive(Clone, Copy)]
struct QTable {
    inner: [Complex64; INNER_NODES],
    outer: [Complex64; OUTER_NODES],
}

impl QTable {
    fn empty() -> Self {
        Self {
            inner: [Complex64::new(0.0, 0.0); INNER_NODES],
            outer: [Complex64::new(0.0, 0.0); OUTER_NODES],
        }
    }

    fn new() -> Self {
        let mut table = Self::empty();
        for j in 0..INNER_RINGS {
            for i in 0..=INNER_ANGLES {
                let (p0, _) = inner_node(j, i);
                table.inner[j * (INNER_ANGLES + 1) + i] = scaled_ei(p0).q;
            }
        }
        for j in 0..OUTER_SIDE {
            for i in 0..OUTER_SIDE {
                let p0 = Complex64::new(i as f64 * OUTER_SPACING, j as f64 * OUTER_SPACING);
                // Only nodes nearest to some |p| in [INNER_RHO_MAX, TABLE_RHO_MAX) are used.
                let r = p0.norm_sqr().sqrt();
                if r > INNER_RHO_MAX - OUTER_SPACING && r < TABLE_RHO_MAX + OUTER_SPACING {
                    table.outer[j * OUTER_SIDE + i] = scaled_ei(p0).q;
                }
            }
        }
        table
    }

    /// `Q(p)` and `e^{-p}`.
    fn q_and_exp(&self, p: Complex64) -> (Complex64, Complex64) {
        let lower = p.im.is_sign_negative();
        let pu = if lower { p.conj() } else { p };
        let r2 = pu.norm_sqr();
        let node = if pu.re < 0.0 || r2 < INNER_RHO_MIN * INNER_RHO_MIN || r2.is_nan() {
            None // series is cheap inside, and p above the free surface is not tabulated
        } else if r2 < INNER_RHO_MAX * INNER_RHO_MAX {
            let rho = r2.sqrt();
            let j = ((0.5 * r2.ln() - INNER_LN_RHO_MIN) * (1.0 / INNER_LN_RATIO) + 0.5) as usize;
            let i = (pu.im / (rho + pu.re) * INNER_ANGLES as f64 + 0.5) as usize;
            let j = j.min(INNER_RINGS - 1);
            let (p0, w) = inner_node(j, i);
            Some((p0, w, self.inner[j * (INNER_ANGLES + 1) + i]))
        } else if r2 < TABLE_RHO_MAX * TABLE_RHO_MAX {
            let i = (pu.re / OUTER_SPACING + 0.5) as usize;
            let j = (pu.im / OUTER_SPACING + 0.5) as usize;
            let p0 = Complex64::new(i as f64 * OUTER_SPACING, j as f64 * OUTER_SPACING);
            Some((p0, p0.inv(), self.outer[j * OUTER_SIDE + i]))
        } else {
            None
        };
        let (q, exp) = match node {
            Some((p0, w, q0)) => {
                // Q^(n+1) = -Q^(n) + (-1)^n n!/p0^{n+1}: with c_n = Q^(n) h^n/n!,
                // c_{n+1} = h/(n+1) (g^n/p0 - c_n), g = -h/p0; two steps per pass so that
                // the chain c_n -> c_{n+2} = alpha + beta c_n is one multiply-add.
                let h = pu - p0;
                let h2 = h * h;
                let g = -h * w;
                let mut gw = w; // g^n / p0
                let mut c = q0;
                let mut sum = q0;
                for n in (0..TAYLOR_TERMS).step_by(2) {
                    let (r1, r2) = (RECIPROCALS[n + 1], RECIPROCALS[n + 2]);
                    let gw1 = gw * g;
                    let beta = h2 * (r1 * r2);
                    let c1 = h * r1 * (gw - c);
                    let c2 = h * r2 * gw1 - beta * gw + beta * c;
                    sum += c1 + c2;
                    // Both terms below 1e-17 (they decay geometrically here).
                    if c1.l1_norm() + c2.l1_norm() <= 1e-17 * sum.l1_norm() {
                        break;
                    }
                    gw = gw1 * g;
                    c = c2;
                }
                (sum, (-pu).exp())
            }
            None => {
                let e = scaled_ei(pu);
                (e.q, e.exp)
            }
        };
        if lower {
            (q.conj(), exp.conj())
        } else {
            (q, exp)
        }
    }
}

/// Radii of the inner rings.
const INNER_RADII: [f64; INNER_RINGS] = {
    let mut r = [INNER_RHO_MIN; INNER_RINGS];
    let mut j = 1;
    while j < INNER_RINGS {
        r[j] = r[j - 1] * INNER_RING_RATIO;
        j += 1;
    }
    r
};

/// Inner node `(j, i)`: `p0` and `1/p0`, from `tan(theta/2) = t` without trigonometry.
fn inner_node(j: usize, i: usize) -> (Complex64, Complex64) {
    let rho = INNER_RADII[j];
    let t = i as f64 * (1.0 / INNER_ANGLES as f64);
    let d = 1.0 / (1.0 + t * t);
    let unit = Complex64::new((1.0 - t * t) * d, 2.0 * t * d);
    (rho * unit, unit.conj() * (1.0 / rho))
}

// ---------------------------------------------------------------------------------------------
// Exponential integrals
// ---------------------------------------------------------------------------------------------

/// `e^z E1(z)` (principal branch of `E1`, cut on the negative real axis).
///
/// About `1e-15` relative in the closed left half plane (all the panel method uses) and
/// `1e-14` elsewhere. On the cut the sign of the zero imaginary part picks the side, as for
/// `ln`: `Im z = -0.0` gives the limit from below, `e^z (-Ei(-z) + i pi)`, `+0.0` the limit
/// from above. `z = 0` gives `+inf`; non-finite input gives NaN.
pub fn scaled_exp_integral(z: Complex64) -> Complex64 {
    scaled_ei(-z).f
}

/// `E1(z) = int_z^inf e^{-t}/t dt`, principal branch, cut on the negative real axis (the sign
/// of a zero imaginary part picks the side, see [`scaled_exp_integral`]). Overflows to
/// infinity for `Re z < -709`.
pub fn exp_integral_e1(z: Complex64) -> Complex64 {
    (-z).exp() * scaled_exp_integral(z)
}

/// Power series where `|p| - Re p <= SERIES_AXIS_DISTANCE` (cancellation below `e^3`).
const SERIES_AXIS_DISTANCE: f64 = 3.0;
/// Beyond this radius the continued fraction converges in about ten steps everywhere.
const FRACTION_RADIUS: f64 = 40.0;
/// Beyond this radius `F(z) = 1/z - 1/z^2 + 2/z^3 - 6/z^4` is exact to rounding.
const ASYMPTOTIC_RADIUS: f64 = 1e5;
const SERIES_MAX_TERMS: usize = 200;
const FRACTION_MAX_TERMS: usize = 400;

/// `1/n`, `n <= SERIES_MAX_TERMS` (index 0 unused).
const RECIPROCALS: [f64; SERIES_MAX_TERMS + 1] = {
    let mut r = [0.0; SERIES_MAX_TERMS + 1];
    let mut n = 1;
    while n <= SERIES_MAX_TERMS {
        r[n] = 1.0 / n as f64;
        n += 1;
    }
    r
};

/// `Q(p) = e^{-p} Ei(p)`, `F(-p) = e^{-p} E1(-p)` and `e^{-p}` at one point.
#[derive(Clone, Copy, Debug)]
struct ScaledEi {
    q: Complex64,
    f: Complex64,
    exp: Complex64,
}

/// `Q(p)`, `F(-p)`, `e^{-p}`; the sign of `Im p` (including a signed zero) picks the side of
/// the cuts (`Q`: negative real axis of `p`; `F(-p)`: positive real axis of `p`).
fn scaled_ei(p: Complex64) -> ScaledEi {
    if p.im.is_sign_negative() {
        let r = scaled_ei_upper(p.conj());
        ScaledEi {
            q: r.q.conj(),
            f: r.f.conj(),
            exp: r.exp.conj(),
        }
    } else {
        scaled_ei_upper(p)
    }
}

/// [`scaled_ei`] for `Im p >= +0`, where `F(-p) = -Q(p) + i pi e^{-p}`.
fn scaled_ei_upper(p: Complex64) -> ScaledEi {
    let exp = (-p).exp();
    let i_pi_exp = Complex64::new(-PI * exp.im, PI * exp.re);
    let rho = match p.norm_sqr() {
        r2 if r2.is_finite() => r2.sqrt(),
        _ => p.norm(),
    };
    if rho == 0.0 {
        return ScaledEi {
            q: Complex64::new(f64::NEG_INFINITY, 0.0),
            f: Complex64::new(f64::INFINITY, 0.0),
            exp,
        };
    }
    if !rho.is_finite() {
        let nan = Complex64::new(f64::NAN, f64::NAN);
        return ScaledEi {
            q: nan,
            f: nan,
            exp: nan,
        };
    }
    // Cancellation in the series grows like e^{|p| - Re p}.
    let series = rho < FRACTION_RADIUS && rho - p.re <= SERIES_AXIS_DISTANCE;
    if series {
        let ei = p.ln() + EULER_GAMMA + ei_series_sum(p);
        return ScaledEi {
            q: exp * ei,
            f: i_pi_exp - exp * ei,
            exp,
        };
    }
    let f = if rho >= ASYMPTOTIC_RADIUS {
        let w = (-p).inv();
        w * (1.0 - w * (1.0 - w * (2.0 - 6.0 * w)))
    } else {
        continued_fraction(-p)
    };
    if p.im == 0.0 && p.re > 0.0 {
        // On the positive real axis Q = e^{-x} Ei(x) is real.
        let q = Complex64::new(-f.re, 0.0);
        ScaledEi {
            q,
            f: i_pi_exp - q,
            exp,
        }
    } else {
        ScaledEi {
            q: i_pi_exp - f,
            f,
            exp,
        }
    }
}

/// `S(p) = sum_{n>=1} p^n / (n n!)`, so `Ei(p) = gamma + ln p + S(p)` and
/// `E1(z) = -gamma - ln z - S(-z)`.
fn ei_series_sum(p: Complex64) -> Complex64 {
    let mut term = p; // p^n / n!
    let mut sum = p;
    for &inv in &RECIPROCALS[2..] {
        term = term * p * inv;
        let add = term * inv;
        sum += add;
        if add.l1_norm() <= 1e-17 * sum.l1_norm() {
            break;
        }
    }
    sum
}

/// `e^z E1(z) = 1/(z+1- 1/(z+3- 4/(z+5- 9/(z+7- ...))))` by the division-free three-term
/// recurrence of its convergents `A_j/B_j`, stopped when the last increment
/// `prod|a_i| / |B_j B_{j-1}|` is below `3e-17` of the value or stops decreasing below `1e-15`.
fn continued_fraction(z: Complex64) -> Complex64 {
    let (mut a_prev, mut a) = (Complex64::new(1.0, 0.0), Complex64::new(0.0, 0.0));
    let (mut b_prev, mut b) = (Complex64::new(0.0, 0.0), Complex64::new(1.0, 0.0));
    // prod |a_i| divided by the square of all rescalings.
    let mut weight = 1.0;
    let mut last_increment = f64::INFINITY;
    for j in 1..=FRACTION_MAX_TERMS {
        let bj = z + (2 * j - 1) as f64;
        let aj = if j == 1 {
            1.0
        } else {
            let m = (j - 1) as f64;
            -m * m
        };
        let a_next = bj * a + a_prev * aj;
        let b_next = bj * b + b_prev * aj;
        a_prev = a;
        a = a_next;
        b_prev = b;
        b = b_next;
        weight *= aj.abs();
        // |f_j - f_{j-1}| / |f_j| (l1 norms: within a factor 2).
        let increment = weight / (a.l1_norm() * b_prev.l1_norm());
        if increment <= 3e-17 {
            break;
        }
        if increment > last_increment && last_increment < 1e-15 {
            // Rounding floor reached (near the negative real axis): keep f_{j-1}.
            return a_prev / b_prev;
        }
        last_increment = increment;
        if b.l1_norm() > 1e100 {
            a *= 1e-100;
            a_prev *= 1e-100;
            b *= 1e-100;
            b_prev *= 1e-100;
            weight *= 1e-200;
        }
    }
    a / b
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(re: f64, im: f64) -> Complex64 {
        Complex64::new(re, im)
    }

    /// Gauss-Legendre nodes and weights on [-1, 1] (Newton on the Legendre recurrence).
    fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
        (0..n)
            .map(|i| {
                let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
                let mut dp = 1.0;
                for _ in 0..100 {
                    let (mut p0, mut p1) = (1.0, x);
                    for k in 2..=n {
                        let kf = k as f64;
                        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
                        p0 = p1;
                        p1 = p2;
                    }
                    dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                    let dx = p1 / dp;
                    x -= dx;
                    if dx.abs() < 1e-16 {
                        break;
                    }
                }
                (x, 2.0 / ((1.0 - x * x) * dp * dp))
            })
            .collect()
    }

    /// Adaptive Gauss-Legendre (10 vs 20 points, bisection): the independent reference.
    struct Quadrature {
        low: Vec<(f64, f64)>,
        high: Vec<(f64, f64)>,
    }

    impl Quadrature {
        fn new() -> Self {
            Self {
                low: gauss_legendre(10),
                high: gauss_legendre(20),
            }
        }

        fn rule<const N: usize>(
            rule: &[(f64, f64)],
            f: &dyn Fn(f64) -> [Complex64; N],
            a: f64,
            b: f64,
        ) -> [Complex64; N] {
            let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
            let mut acc = [c(0.0, 0.0); N];
            for &(x, w) in rule {
                let v = f(m + h * x);
                for i in 0..N {
                    acc[i] += v[i] * (w * h);
                }
            }
            acc
        }

        /// Integral over [a, b] with an absolute error target `tol` per bisection leaf.
        fn integrate<const N: usize>(
            &self,
            f: &dyn Fn(f64) -> [Complex64; N],
            a: f64,
            b: f64,
            tol: f64,
        ) -> [Complex64; N] {
            self.adapt(f, a, b, tol, 0)
        }

        fn adapt<const N: usize>(
            &self,
            f: &dyn Fn(f64) -> [Complex64; N],
            a: f64,
            b: f64,
            tol: f64,
            depth: usize,
        ) -> [Complex64; N] {
            let lo = Self::rule(&self.low, f, a, b);
            let hi = Self::rule(&self.high, f, a, b);
            let err = (0..N).map(|i| (hi[i] - lo[i]).norm()).fold(0.0, f64::max);
            if err <= tol || depth >= 60 {
                return hi;
            }
            let m = 0.5 * (a + b);
            let l = self.adapt(f, a, m, tol, depth + 1);
            let r = self.adapt(f, m, b, tol, depth + 1);
            let mut out = l;
            for i in 0..N {
                out[i] += r[i];
            }
            out
        }
    }

    /// `e^z E1(z) = int_0^inf e^{-u}/(z + u) du` along a ray rotated away from the pole -z
    /// (for `Im z = -0.0` below the pole: the lower side of the cut).
    fn scaled_e1_by_quadrature(quad: &Quadrature, z: Complex64) -> Complex64 {
        let alpha = if z.re > 0.0 && z.im.abs() < z.re {
            0.0
        } else if z.im.is_sign_negative() {
            -PI / 4.0
        } else {
            PI / 4.0
        };
        let dir = Complex64::from_polar(1.0, alpha);
        let r_max = 50.0 / alpha.cos();
        let f = |r: f64| [(-(r * dir)).exp() * dir / (z + r * dir)];
        let scale = (1.0 / z.norm()).min(1.0);
        quad.integrate(&f, 0.0, r_max, 1e-17 * scale)[0]
    }

    /// Test points z = rho e^{i theta} over the whole plane, many in the third quadrant.
    fn e1_test_points() -> Vec<Complex64> {
        let radii = [
            1e-8, 1e-3, 0.1, 0.5, 1.0, 1.9, 2.1, 3.0, 4.5, 7.0, 12.0, 25.0, 39.0, 41.0, 80.0,
            300.0, 2e5,
        ];
        let angles = [
            -PI + 1e-9,
            -PI + 1e-3,
            -PI + 0.05,
            -PI + 0.3,
            -0.75 * PI,
            -0.6 * PI,
            -0.5 * PI,
            -0.3 * PI,
            0.0,
            0.25 * PI,
            0.5 * PI,
            0.8 * PI,
            PI - 1e-3,
        ];
        let mut pts = Vec::new();
        for &r in &radii {
            for &t in &angles {
                pts.push(Complex64::from_polar(r, t));
            }
            pts.push(c(-r, -0.0));
            pts.push(c(-r, 0.0));
            pts.push(c(0.0, -r));
        }
        pts
    }

    #[test]
    fn scaled_exp_integral_matches_quadrature() {
        let quad = Quadrature::new();
        let mut worst: f64 = 0.0;
        for z in e1_test_points() {
            if z.norm() > 1e4 {
                continue; // quadrature range too short; covered by the asymptotic test
            }
            let f = scaled_exp_integral(z);
            let r = scaled_e1_by_quadrature(&quad, z);
            let err = (f - r).norm() / r.norm();
            worst = worst.max(err);
            // Third quadrant is what the panel method uses: near machine precision there.
            let tol = if z.re <= 0.0 && z.im <= 0.0 {
                2e-15
            } else {
                1e-14
            };
            assert!(err < tol, "z = {z}: {f} vs quadrature {r} (rel {err:e})");
        }
        assert!(worst > 0.0);
    }

    #[test]
    fn scaled_exp_integral_matches_high_precision_values() {
        // mpmath 1.3 at 40 digits.
        let table = [
            ((1.0, 0.0), (0.596_347_362_323_194_1, 0.0)),
            (
                (-3.0, -0.0),
                (-0.494_576_401_348_641_2, 0.156_410_688_228_254_13),
            ),
            (
                (0.0, -3.0),
                (0.079_221_521_164_364_04, 0.291_957_710_692_078_76),
            ),
            (
                (-10.0, -2.0),
                (-0.107_071_757_402_005_63, 0.024_784_313_651_390_045),
            ),
            (
                (-0.5, -0.001),
                (-0.273_595_688_850_064_36, 1.903_746_813_913_421),
            ),
            (
                (-30.0, -1.0),
                (-0.034_485_832_885_438_425, 0.001_192_356_313_197_741_5),
            ),
            (
                (-25.0, -40.0),
                (-0.011_019_359_153_420_357, 0.018_382_462_309_309_6),
            ),
            (
                (-1e-6, -2e-6),
                (12.433_566_572_132_657, 2.034_415_034_224_708_5),
            ),
            (
                (5.0, 7.0),
                (0.069_707_655_944_815_69, -0.083_032_375_996_334_49),
            ),
            (
                (-60.0, -0.5),
                (-0.016_952_980_988_844_56, 0.000_143_756_517_087_626_58),
            ),
            (
                (-45.0, -0.0),
                (-0.022_739_607_254_528_28, 8.992867343418258e-20),
            ),
        ];
        for ((zr, zi), (fr, fi)) in table {
            let f = scaled_exp_integral(c(zr, zi));
            let r = c(fr, fi);
            assert!(
                (f - r).norm() <= 2e-15 * r.norm(),
                "z = ({zr}, {zi}): {f} vs {r}"
            );
        }
        // On the cut the imaginary part pi e^z is tiny but must still be right.
        let f = scaled_exp_integral(c(-45.0, -0.0));
        assert!((f.im - PI * (-45.0f64).exp()).abs() < 1e-14 * f.im);
    }

    /// Ei(x), x > 0, independently: positive power series, or the asymptotic series.
    fn ei_real(x: f64) -> f64 {
        if x < 40.0 {
            let (mut term, mut sum) = (1.0, 0.0);
            for n in 1..400 {
                term *= x / n as f64;
                sum += term / n as f64;
                if term < 1e-18 * sum {
                    break;
                }
            }
            EULER_GAMMA + x.ln() + sum
        } else {
            let (mut term, mut sum) = (1.0, 1.0);
            for n in 1..(x as usize) {
                term *= n as f64 / x;
                sum += term;
                if term < 1e-18 {
                    break;
                }
            }
            x.exp() / x * sum
        }
    }

    #[test]
    fn e1_on_the_negative_real_axis() {
        // E1(-x -+ i0) = -Ei(x) +- i pi (the sign of the zero picks the side).
        for x in [
            1e-6, 0.3, 1.0, 2.5, 7.0, 19.0, 33.0, 39.9, 40.1, 55.0, 120.0,
        ] {
            let ei = ei_real(x);
            for (side, im) in [(-0.0, PI), (0.0, -PI)] {
                let e1 = exp_integral_e1(c(-x, side));
                assert!(
                    (e1.re + ei).abs() <= 2e-15 * ei.abs().max(1.0),
                    "x = {x}: {} vs {}",
                    e1.re,
                    -ei
                );
                assert!((e1.im - im).abs() <= 1e-14 * PI, "x = {x}: Im {}", e1.im);
            }
        }
        // Principal branch continuity: just below the axis equals the -0.0 side.
        let below = exp_integral_e1(c(-3.0, -1e-12));
        let on = exp_integral_e1(c(-3.0, -0.0));
        assert!((below - on).norm() < 1e-10);
    }

    #[test]
    fn exp_integral_conjugate_symmetry_and_known_e1() {
        for z in e1_test_points() {
            let f = scaled_exp_integral(z);
            let g = scaled_exp_integral(z.conj());
            assert!((f.conj() - g).norm() <= 1e-15 * f.norm(), "z = {z}");
        }
        // E1(1) = 0.21938393439552027368 (Abramowitz & Stegun table 5.1).
        let e1 = exp_integral_e1(c(1.0, 0.0));
        assert!((e1.re - 0.219_383_934_395_520_27).abs() < 5e-16 && e1.im == 0.0);
        // Small |z|: E1(z) = -gamma - ln z + z + O(z^2).
        let z = c(-1e-9, -2e-9);
        let e1 = exp_integral_e1(z);
        let approx = -EULER_GAMMA - z.ln() + z;
        assert!((e1 - approx).norm() < 1e-17 * 10.0 + 1e-15 * approx.norm());
        // Large |z|: e^z E1(z) ~ 1/z - 1/z^2 + 2/z^3.
        for z in [c(-3e5, -1.0), c(0.0, -1e6), c(2e5, 3e5)] {
            let w = z.inv();
            let approx = w * (1.0 - w * (1.0 - 2.0 * w));
            assert!((scaled_exp_integral(z) - approx).norm() < 1e-15 * approx.norm());
        }
    }

    #[test]
    fn scaled_exp_integral_derivative_identity() {
        // d/dz [e^z E1(z)] = e^z E1(z) - 1/z, the derivative by the Cauchy integral on a
        // small circle (spectrally accurate): checks smoothness across method boundaries.
        let n = 48;
        for z in e1_test_points() {
            let dist = if z.re < 0.0 { z.im.abs() } else { z.norm() };
            if dist < 1e-6 || z.norm() > 1e4 {
                continue;
            }
            let r = 0.3 * dist.min(z.norm());
            let mut deriv = c(0.0, 0.0);
            let mut size: f64 = 0.0;
            for j in 0..n {
                let w = Complex64::from_polar(1.0, 2.0 * PI * j as f64 / n as f64);
                let f = scaled_exp_integral(z + r * w);
                size = size.max(f.norm());
                deriv += f / (r * w);
            }
            deriv /= n as f64;
            let expect = scaled_exp_integral(z) - z.inv();
            assert!(
                (deriv - expect).norm() <= 1e-13 * size / r,
                "z = {z}: {deriv} vs {expect}"
            );
        }
    }

    #[test]
    fn table_taylor_matches_direct_evaluation() {
        // Dense sweep over the tabulated annulus (cell edges included) and its borders.
        let table = QTable::new();
        let mut worst: f64 = 0.0;
        for ir in 0..=400 {
            let rho = 0.45 * (41.0f64 / 0.45).powf(ir as f64 / 400.0);
            for it in 0..=90 {
                let theta = (it as f64 / 90.0 - 0.5) * PI; // fourth and first quadrant
                let p = Complex64::from_polar(rho, theta);
                let (q, exp) = table.q_and_exp(p);
                let e = scaled_ei(p);
                // Relative to |F| + |Q|: Q = i pi e^{-p} - F has zeros (those of Ei).
                let err = (q - e.q).norm() / (e.q.norm() + e.f.norm());
                worst = worst.max(err);
                assert!(err < 5e-15, "p = {p}: {q} vs {} ({err:e})", e.q);
                assert!((exp - e.exp).norm() <= 1e-15 * e.exp.norm());
            }
        }
        assert!(worst > 0.0);
    }

    #[test]
    fn series_and_continued_fraction_agree_in_overlap() {
        // Both methods at points where both converge (Re p >= 0, 2 < |p| < 40).
        for rho in [2.5f64, 4.0, 8.0, 15.0, 30.0] {
            for d in [3.0, 4.0, 5.0] {
                // |p| - Re p = d
                let re = rho - d;
                let im = (rho * rho - re * re).sqrt();
                let p = c(re, im);
                let series = Complex64::new(0.0, PI) * (-p).exp()
                    - (-p).exp() * (p.ln() + EULER_GAMMA + ei_series_sum(p));
                let fraction = continued_fraction(-p);
                assert!(
                    (series - fraction).norm() <= 5e-14 * fraction.norm(),
                    "p = {p}: {series} vs {fraction}"
                );
            }
        }
    }

    #[test]
    fn non_finite_and_zero_arguments_do_not_hang_or_panic() {
        assert!(scaled_exp_integral(c(f64::NAN, 0.0)).re.is_nan());
        assert!(scaled_exp_integral(c(f64::INFINITY, 1.0)).re.is_nan());
        assert_eq!(scaled_exp_integral(c(0.0, 0.0)).re, f64::INFINITY);
    }

    // -----------------------------------------------------------------------------------------
    // Point Green function
    // -----------------------------------------------------------------------------------------

    fn wave(k: f64) -> GreenFunction {
        GreenFunction::new(FreeSurface::Wave { wavenumber: k }).unwrap()
    }

    fn all_surfaces() -> Vec<GreenFunction> {
        vec![
            GreenFunction::new(FreeSurface::RigidLid).unwrap(),
            GreenFunction::new(FreeSurface::Dirichlet).unwrap(),
            wave(0.05),
            wave(1.0),
            wave(7.0),
        ]
    }

    /// Field/source pairs in the fluid, including x = x0, points on y = 0 and far pairs.
    fn point_pairs() -> Vec<(Point, Point)> {
        vec![
            ([0.3, -0.4], [-0.2, -1.1]),
            ([0.0, -0.5], [0.0, -1.5]),
            ([1e-7, -0.5], [0.0, -1.5]),
            ([2.0, 0.0], [0.5, -0.3]),
            ([0.5, -0.3], [2.0, 0.0]),
            ([0.1, -0.02], [-0.1, -0.01]),
            ([-3.0, -2.0], [4.0, -0.5]),
            ([0.7, -4.0], [0.65, -3.5]),
            ([12.0, -0.2], [-9.0, -0.7]),
        ]
    }

    #[test]
    fn new_validates_wavenumber() {
        for k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let err = GreenFunction::new(FreeSurface::Wave { wavenumber: k }).unwrap_err();
            assert!(err.to_string().contains("wavenumber"));
        }
        let g = wave(2.0);
        assert_eq!(g.surface(), FreeSurface::Wave { wavenumber: 2.0 });
    }

    /// Seed eq. 11 literally, with F = e^z E1(z) from `scaled_exp_integral`.
    fn seed_eq_11(k: f64, x: Point, x0: Point) -> Complex64 {
        let r0 = (x[0] - x0[0]).hypot(x[1] - x0[1]);
        let r1 = (x[0] - x0[0]).hypot(x[1] + x0[1]);
        // Im z = -|x - x0| (-0.0 directly below: the lower side of the cut).
        let z = c(x[1] + x0[1], -(x[0] - x0[0]).abs());
        (r0 / r1).ln() / (2.0 * PI) - scaled_exp_integral(k * z).re / PI
            + Complex64::new(0.0, 1.0) * (k * z).exp()
    }

    #[test]
    fn value_equals_seed_equation_11() {
        for k in [0.05, 1.0, 7.0, 60.0] {
            let g = wave(k);
            for (x, x0) in point_pairs() {
                let (val, _) = g.value_and_gradient(x, x0);
                let seed = seed_eq_11(k, x, x0);
                assert!(
                    (val - seed).norm() <= 1e-14 * (1.0 + seed.norm()),
                    "k = {k}, x = {x:?}, x0 = {x0:?}: {val} vs {seed}"
                );
            }
        }
    }

    #[test]
    fn kinks_of_the_wave_terms_cancel() {
        // d/dx of -(1/pi) Re{e^{kz}E1(kz)} jumps at x = x0 (slope -k e^{kY} just right of x0),
        // e^{kY} sin(k|x-x0|) has the opposite kink; G itself is smooth: dG/dx -> 0.
        let (k, x0, y, y0) = (1.3, [0.2, -0.7], -0.4, -0.7);
        let big_y = y + y0;
        let g = wave(k);
        let e1_term = |dx: f64| -scaled_exp_integral(k * c(big_y, -dx.abs())).re / PI;
        let h = 1e-6;
        let slope_e1 = (e1_term(2.0 * h) - e1_term(h)) / h;
        let expected = -k * (k * big_y).exp();
        assert!(
            (slope_e1 - expected).abs() < 1e-5,
            "{slope_e1} vs {expected}"
        );
        for eps in [1e-9, 1e-6] {
            let (_, grad) = g.value_and_gradient([x0[0] + eps, y], x0);
            let (_, grad_left) = g.value_and_gradient([x0[0] - eps, y], x0);
            // dG/dx is odd and O(eps) (second derivative is O(1)).
            assert!(grad[0].norm() < 10.0 * eps, "eps {eps}: {}", grad[0]);
            assert!((grad[0] + grad_left[0]).norm() < 1e-14);
        }
        // One-sided finite differences of the literal seed formula agree.
        let seed = |dx: f64| seed_eq_11(k, [x0[0] + dx, y], x0);
        let one_sided = (seed(2.0 * h) - seed(h)) / h;
        assert!(one_sided.norm() < 1e-4, "{one_sided}");
    }

    fn assert_gradient_matches_fd(g: &GreenFunction, x: Point, x0: Point) {
        let (val, grad) = g.value_and_gradient(x, x0);
        let r = (x[0] - x0[0]).hypot(x[1] - x0[1]);
        let h = 1e-3 * r.min(1.0);
        let f = |dx: f64, dy: f64| g.value_and_gradient([x[0] + dx, x[1] + dy], x0).0;
        // 4th-order central differences; stay below y = 0 by using one-sided-free offsets only
        // when the point is in the fluid interior.
        let fd = |e: [f64; 2]| {
            (f(-2.0 * h * e[0], -2.0 * h * e[1]) - 8.0 * f(-h * e[0], -h * e[1])
                + 8.0 * f(h * e[0], h * e[1])
                - f(2.0 * h * e[0], 2.0 * h * e[1]))
                / (12.0 * h)
        };
        let scale = grad[0].norm() + grad[1].norm() + val.norm() / r;
        for (i, e) in [[1.0, 0.0], [0.0, 1.0]].into_iter().enumerate() {
            let d = fd(e);
            assert!(
                (d - grad[i]).norm() <= 1e-8 * scale,
                "{:?} x = {x:?} x0 = {x0:?} component {i}: {} vs fd {d}",
                g.surface(),
                grad[i]
            );
        }
    }

    #[test]
    fn gradient_matches_finite_differences() {
        for g in all_surfaces() {
            for (x, x0) in point_pairs() {
                if x[1] < -0.05 {
                    assert_gradient_matches_fd(&g, x, x0);
                }
            }
            // A denser sweep of directions and distances around one source.
            let x0 = [0.1, -0.8];
            for i in 0..24 {
                let t = 2.0 * PI * i as f64 / 24.0;
                for r in [0.05, 0.4, 0.75] {
                    let x = [x0[0] + r * t.cos(), x0[1] + r * t.sin()];
                    assert_gradient_matches_fd(&g, x, x0);
                }
            }
        }
    }

    #[test]
    fn harmonic_mean_value_and_laplacian() {
        for g in all_surfaces() {
            let x0: Point = [0.2, -0.6];
            for centre in [[0.9f64, -0.7], [0.2, -1.3], [-0.5, -0.45], [3.0, -2.0]] {
                let d_src = (centre[0] - x0[0]).hypot(centre[1] - x0[1]);
                let rad = 0.4 * d_src.min(-centre[1]);
                let n = 96;
                let mut mean = c(0.0, 0.0);
                for j in 0..n {
                    let t = 2.0 * PI * j as f64 / n as f64;
                    let x = [centre[0] + rad * t.cos(), centre[1] + rad * t.sin()];
                    mean += g.value_and_gradient(x, x0).0;
                }
                mean /= n as f64;
                let at_centre = g.value_and_gradient(centre, x0).0;
                assert!(
                    (mean - at_centre).norm() <= 1e-13 * (1.0 + at_centre.norm()),
                    "{:?} at {centre:?}: mean {mean} vs {at_centre}",
                    g.surface()
                );
                // 5-point Laplacian: O(h^2) truncation, h = 1e-3 rad.
                let h = 1e-2 * rad;
                let f =
                    |dx: f64, dy: f64| g.value_and_gradient([centre[0] + dx, centre[1] + dy], x0).0;
                let lap =
                    (f(h, 0.0) + f(-h, 0.0) + f(0.0, h) + f(0.0, -h) - 4.0 * f(0.0, 0.0)) / (h * h);
                let curvature = (f(h, 0.0) - 2.0 * f(0.0, 0.0) + f(-h, 0.0)).norm() / (h * h);
                assert!(
                    lap.norm() <= 1e-4 * (curvature + 1.0),
                    "{:?} Laplacian {lap}",
                    g.surface()
                );
            }
        }
    }

    #[test]
    fn free_surface_conditions() {
        let sources = [[0.0, -0.3], [1.0, -2.0], [-0.4, -0.05], [0.3, 0.0]];
        for k in [0.05, 1.0, 7.0] {
            let g = wave(k);
            for x0 in sources {
                for x in [-2.0, -0.1, 0.0, 0.25, 1.7, 30.0] {
                    if x == x0[0] && x0[1] == 0.0 {
                        continue;
                    }
                    let (val, grad) = g.value_and_gradient([x, 0.0], x0);
                    // dG/dy = k G on y = 0 (analytic gradient).
                    assert!(
                        (grad[1] - k * val).norm() <= 1e-13 * (grad[1].norm() + k * val.norm()),
                        "k {k} x0 {x0:?} x {x}: {} vs {}",
                        grad[1],
                        k * val
                    );
                    // One-sided 4th-order finite difference from below.
                    let h = 1e-3 * (1.0 / k).min(0.5);
                    let f = |j: f64| g.value_and_gradient([x, -j * h], x0).0;
                    let dy = (25.0 * f(0.0) - 48.0 * f(1.0) + 36.0 * f(2.0) - 16.0 * f(3.0)
                        + 3.0 * f(4.0))
                        / (12.0 * h);
                    assert!(
                        (dy - k * val).norm() <= 1e-7 * (1.0 + val.norm()) * k.max(1.0),
                        "FD k {k} x0 {x0:?} x {x}: {dy} vs {}",
                        k * val
                    );
                }
            }
        }
        let rigid = GreenFunction::new(FreeSurface::RigidLid).unwrap();
        let dirichlet = GreenFunction::new(FreeSurface::Dirichlet).unwrap();
        for x0 in sources.iter().take(3) {
            for x in [-2.0, 0.0, 0.25] {
                let (_, grad) = rigid.value_and_gradient([x, 0.0], *x0);
                assert!(grad[1].norm() < 1e-15);
                let (val, _) = dirichlet.value_and_gradient([x, 0.0], *x0);
                assert!(val.norm() < 1e-15);
            }
        }
    }

    #[test]
    fn outgoing_waves_far_away() {
        // G - i e^{kz} = (1/2pi) ln(r0/r1) - (1/pi) Re F(kz) = O(1/(k |x - x0|)).
        let k = 1.5;
        let g = wave(k);
        let x0 = [0.0, -0.5];
        for dx in [1e2, 1e3, -1e4] {
            let x = [dx, -0.2];
            let (val, _) = g.value_and_gradient(x, x0);
            let z = c(x[1] + x0[1], -dx.abs());
            let wave_part = Complex64::new(0.0, 1.0) * (k * z).exp();
            assert!((val - wave_part).norm() <= 1.1 / (PI * k * dx.abs()));
            assert!(val.norm() > 0.5 * (k * (x[1] + x0[1])).exp());
        }
    }

    #[test]
    fn reciprocity() {
        for g in all_surfaces() {
            for (x, x0) in point_pairs() {
                let a = g.value_and_gradient(x, x0).0;
                let b = g.value_and_gradient(x0, x).0;
                assert!((a - b).norm() <= 1e-14 * (1.0 + a.norm()));
            }
        }
    }

    #[test]
    fn low_frequency_limit_is_rigid_lid_plus_constant() {
        // G_wave = G_rigid + (1/pi)(ln k + gamma) + i + O(k r1 ln(k r1)).
        let rigid = GreenFunction::new(FreeSurface::RigidLid).unwrap();
        for k in [1e-4, 1e-6, 1e-9] {
            let g = wave(k);
            let constant = c((k.ln() + EULER_GAMMA) / PI, 1.0);
            for (x, x0) in point_pairs() {
                let r1 = (x[0] - x0[0]).hypot(x[1] + x0[1]);
                let bound = 2.0 * k * r1 * (1.0 + (k * r1).ln().abs());
                let (gw, dw) = g.value_and_gradient(x, x0);
                let (gr, dr) = rigid.value_and_gradient(x, x0);
                assert!((gw - constant - gr).norm() <= bound, "k {k}: {gw} {gr}");
                for i in 0..2 {
                    assert!((dw[i] - dr[i]).norm() <= 2.0 * k * (2.0 + (k * r1).ln().abs()));
                }
            }
        }
    }

    #[test]
    fn high_frequency_limit_is_dirichlet() {
        // G_wave - G_dirichlet = (1/pi) Re Q(p) + i Re e^{-p}, Q ~ 1/p: O(1/(k r1)).
        let dirichlet = GreenFunction::new(FreeSurface::Dirichlet).unwrap();
        for k in [1e4, 1e6, 1e9] {
            let g = wave(k);
            for (x, x0) in point_pairs() {
                if x[1] + x0[1] > -0.05 {
                    continue;
                }
                let r1 = (x[0] - x0[0]).hypot(x[1] + x0[1]);
                let (gw, dw) = g.value_and_gradient(x, x0);
                let (gd, dd) = dirichlet.value_and_gradient(x, x0);
                assert!((gw - gd).norm() <= 1.01 / (PI * k * r1), "k {k}: {gw} {gd}");
                for i in 0..2 {
                    assert!((dw[i] - dd[i]).norm() <= 1.01 / (PI * k * r1 * r1));
                }
            }
        }
    }

    #[test]
    fn singular_points_give_non_finite_values_without_panic() {
        let (v, _) = wave(1.0).value_and_gradient([0.3, -0.2], [0.3, -0.2]);
        assert!(!v.re.is_finite());
        let (v, _) = wave(1.0).value_and_gradient([0.3, 0.0], [0.3, 0.0]);
        assert!(!v.re.is_finite());
    }

    // -----------------------------------------------------------------------------------------
    // Panel integrals
    // -----------------------------------------------------------------------------------------

    /// Brute-force panel integral: [int G, int dG/dx, int dG/dy, int |G|, int |grad G|], split
    /// at the feet of the field point and of its mirror image.
    /// With `with_gradient = false` the gradient entries are zero (for field points on the
    /// panel, where the gradient integrand is not integrable).
    fn panel_by_quadrature(
        quad: &Quadrature,
        g: &GreenFunction,
        field: Point,
        a: Point,
        b: Point,
        with_gradient: bool,
    ) -> [Complex64; 5] {
        let t = [b[0] - a[0], b[1] - a[1]];
        let len = t[0].hypot(t[1]);
        let t = [t[0] / len, t[1] / len];
        let f = |s: f64| {
            let (v, mut d) = g.value_and_gradient(field, [a[0] + s * t[0], a[1] + s * t[1]]);
            if !with_gradient {
                d = [c(0.0, 0.0); 2];
            }
            [
                v,
                d[0],
                d[1],
                c(v.norm(), 0.0),
                c(d[0].norm() + d[1].norm(), 0.0),
            ]
        };
        let foot = |p: Point| ((p[0] - a[0]) * t[0] + (p[1] - a[1]) * t[1]).clamp(0.0, len);
        let mut cuts = vec![0.0, foot(field), foot([field[0], -field[1]]), len];
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        let mut acc = [c(0.0, 0.0); 5];
        for w in cuts.windows(2) {
            if w[1] > w[0] {
                let part = quad.integrate(&f, w[0], w[1], 1e-16 * len);
                for i in 0..5 {
                    acc[i] += part[i];
                }
            }
        }
        acc
    }

    /// Asserts agreement within `tol` of the integrals of |G| and |grad G|; returns the
    /// largest error in those units.
    fn assert_panel_matches_quadrature(
        quad: &Quadrature,
        g: &GreenFunction,
        field: Point,
        a: Point,
        b: Point,
        tol: f64,
    ) -> f64 {
        let got = g.panel_integral(field, a, b);
        let r = panel_by_quadrature(quad, g, field, a, b, true);
        let pot_err = (got.potential - r[0]).norm() / r[3].re.max(f64::MIN_POSITIVE);
        let grad_err = (got.gradient[0] - r[1])
            .norm()
            .max((got.gradient[1] - r[2]).norm())
            / r[4].re.max(f64::MIN_POSITIVE);
        assert!(
            pot_err <= tol && grad_err <= tol,
            "{:?} field {field:?} panel {a:?}->{b:?}: potential {} vs {}, gradient {:?} vs {:?}",
            g.surface(),
            got.potential,
            r[0],
            got.gradient,
            [r[1], r[2]]
        );
        pot_err.max(grad_err)
    }

    /// Panels: deep, sloping, touching the free surface, vertical, long.
    fn test_panels() -> Vec<(Point, Point)> {
        vec![
            ([0.3, -1.0], [0.5, -1.15]),
            ([1.0, 0.0], [0.97, -0.12]),
            ([-0.2, -0.4], [-0.2, -0.1]),
            ([-0.05, -0.02], [0.05, -0.03]),
            ([-1.5, -0.8], [1.0, -1.6]),
        ]
    }

    /// Field points around a panel: far, near, very near (fluid and body side), on the panel's
    /// line outside it, near an end, and on the free surface.
    fn field_points(a: Point, b: Point) -> Vec<Point> {
        let t = [b[0] - a[0], b[1] - a[1]];
        let len = t[0].hypot(t[1]);
        let (tx, ty) = (t[0] / len, t[1] / len);
        let n = [-ty, tx]; // into the body
        let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let at = |s: f64, d: f64| {
            [
                m[0] + s * len * tx + d * len * n[0],
                m[1] + s * len * ty + d * len * n[1],
            ]
        };
        let mut pts = vec![
            at(0.0, -100.0),
            at(3.0, -20.0),
            at(0.1, -4.0),
            at(1.4, -1.2),
            at(-0.2, -2.05),
            at(0.3, -1.95),
            at(0.0, -0.5),
            at(0.2, -0.1),
            at(-0.3, -0.01),
            at(0.1, -1e-3),
            at(0.25, 1e-3),
            at(0.62, 0.0),
            at(-0.5, -0.05),
            [m[0] + 0.3 * len, 0.0],
            [a[0], 0.0],
            [m[0] - 5.0 * len, 0.0],
        ];
        pts.retain(|p| p[1] <= 0.0);
        pts
    }

    #[test]
    fn panel_integral_matches_quadrature() {
        let quad = Quadrature::new();
        let mut surfaces = all_surfaces();
        surfaces.push(wave(25.0));
        let mut worst: f64 = 0.0;
        for g in &surfaces {
            for (a, b) in test_panels() {
                for field in field_points(a, b) {
                    // Skip the singular case: field at the mirror image of an end point.
                    let at_image_end = field[1] == 0.0
                        && ((field[0] == a[0] && a[1] == 0.0) || (field[0] == b[0] && b[1] == 0.0));
                    if at_image_end {
                        continue;
                    }
                    let err = assert_panel_matches_quadrature(&quad, g, field, a, b, 1e-12);
                    worst = worst.max(err);
                }
            }
        }
        println!("worst panel error / int |integrand|: {worst:e}");
    }

    #[test]
    fn panel_integral_is_additive_across_near_and_far_forms() {
        // Splitting a panel changes which closed form (exact or series) each part uses.
        for g in all_surfaces().into_iter().chain([wave(25.0)]) {
            for (a, b) in test_panels() {
                for field in field_points(a, b) {
                    if field == a || field == b {
                        continue; // gradient singular at an end point
                    }
                    let whole = g.panel_integral(field, a, b);
                    let pieces = 7;
                    let mut pot = c(0.0, 0.0);
                    let mut grad = [c(0.0, 0.0); 2];
                    let mut scale = 0.0;
                    for j in 0..pieces {
                        let s0 = j as f64 / pieces as f64;
                        let s1 = (j + 1) as f64 / pieces as f64;
                        let p = |s: f64| [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])];
                        let part = g.panel_integral(field, p(s0), p(s1));
                        pot += part.potential;
                        grad[0] += part.gradient[0];
                        grad[1] += part.gradient[1];
                        scale += part.potential.norm()
                            + part.gradient[0].norm()
                            + part.gradient[1].norm();
                    }
                    let err = (pot - whole.potential).norm()
                        + (grad[0] - whole.gradient[0]).norm()
                        + (grad[1] - whole.gradient[1]).norm();
                    if scale.is_finite() {
                        assert!(
                            err <= 1e-12 * scale,
                            "{:?} field {field:?}: err {err:e}",
                            g.surface()
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn dirichlet_part_plus_the_rest_is_the_whole() {
        let dirichlet = GreenFunction::new(FreeSurface::Dirichlet).unwrap();
        let mut panels = test_panels();
        panels.push(([-0.1, 0.0], [0.1, 0.0])); // lid
        for g in all_surfaces() {
            for &(a, b) in &panels {
                for field in field_points(a, b) {
                    let whole = g.panel_integral(field, a, b);
                    let d = dirichlet.panel_integral(field, a, b);
                    let rest = g.panel_integral_beyond_dirichlet(field, a, b);
                    let tol = 1e-14 * (whole.potential.norm() + d.potential.norm() + 1.0);
                    assert!((whole.potential - d.potential - rest.potential).norm() <= tol);
                    for i in 0..2 {
                        let sum = d.gradient[i] + rest.gradient[i];
                        if whole.gradient[i].is_finite() {
                            let tol =
                                1e-14 * (whole.gradient[i].norm() + d.gradient[i].norm() + 1.0);
                            assert!((whole.gradient[i] - sum).norm() <= tol, "{:?}", g.surface());
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn wave_far_series_matches_exact_form() {
        let table = QTable::new();
        for k in [0.01, 0.8, 3.0] {
            for (a, b) in test_panels() {
                let za = c(a[0], a[1]);
                let zb = c(b[0], b[1]);
                let d = zb - za;
                let len = d.norm();
                let panel = Panel {
                    tau: d / len,
                    half: 0.5 * len,
                    centre: za + 0.5 * d,
                    a: za,
                    b: zb,
                };
                if k * panel.half > FAR_WAVE_MAX_HALF_KL {
                    continue;
                }
                for dist in [2.0, 3.0, 10.0, 30.0] {
                    for angle in [-0.3, -1.2, -2.0, -2.9] {
                        let zf = panel.centre.conj() + Complex64::from_polar(dist * len, angle);
                        if zf.im > 0.0 {
                            continue;
                        }
                        let far = panel.wave(zf, k, &table);
                        let exact = panel.wave_exact(zf, k, &table);
                        let tol = 1e-13 * dist;
                        assert!(
                            (far.q_integral - exact.q_integral).norm()
                                <= tol * far.q_integral.norm()
                        );
                        assert!(
                            (far.dq_integral - exact.dq_integral).norm()
                                <= tol * far.dq_integral.norm()
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn on_panel_limit_from_the_fluid_side() {
        let quad = Quadrature::new();
        for g in all_surfaces() {
            for (a, b) in test_panels() {
                let t = [b[0] - a[0], b[1] - a[1]];
                let len = t[0].hypot(t[1]);
                let t = [t[0] / len, t[1] / len];
                let n = [-t[1], t[0]]; // into the body
                for frac in [0.5, 0.3] {
                    let x = [a[0] + frac * len * t[0], a[1] + frac * len * t[1]];
                    let on = g.panel_integral(x, a, b);
                    let normal = |p: &PanelIntegral| p.gradient[0] * n[0] + p.gradient[1] * n[1];
                    let tangential =
                        |p: &PanelIntegral| p.gradient[0] * t[0] + p.gradient[1] * t[1];
                    // Fluid side (right of a->b, -n) is continuous with the on-panel value,
                    // the body side differs by the jump +1.
                    let eps = 1e-8 * len;
                    let fluid = g.panel_integral([x[0] - eps * n[0], x[1] - eps * n[1]], a, b);
                    let body = g.panel_integral([x[0] + eps * n[0], x[1] + eps * n[1]], a, b);
                    assert!((normal(&fluid) - normal(&on)).norm() < 1e-6);
                    assert!((normal(&body) - normal(&fluid) - 1.0).norm() < 1e-6);
                    assert!((on.potential - fluid.potential).norm() < 1e-6 * len);
                    // On the panel: normal = -1/2 + int d/dn [G - (1/2pi) ln r0] (the PV of the
                    // own straight panel's ln r0 is zero); tangential = (1/2pi) ln(d_a/d_b) + rest.
                    let rest = |s: f64| {
                        let x0 = [a[0] + s * t[0], a[1] + s * t[1]];
                        let (_, d) = g.value_and_gradient(x, x0);
                        let rx = [x[0] - x0[0], x[1] - x0[1]];
                        let r2 = rx[0] * rx[0] + rx[1] * rx[1];
                        let d0 = [
                            d[0] - rx[0] / (2.0 * PI * r2),
                            d[1] - rx[1] / (2.0 * PI * r2),
                        ];
                        [d0[0] * n[0] + d0[1] * n[1], d0[0] * t[0] + d0[1] * t[1]]
                    };
                    let s_f = frac * len;
                    let mut r = quad.integrate(&rest, 0.0, s_f, 1e-16);
                    let r2 = quad.integrate(&rest, s_f, len, 1e-16);
                    r[0] += r2[0];
                    r[1] += r2[1];
                    let expect_n = r[0] - 0.5;
                    let expect_t = r[1] + (s_f / (len - s_f)).ln() / (2.0 * PI);
                    assert!(
                        (normal(&on) - expect_n).norm() < 1e-12,
                        "{:?} {a:?}->{b:?}: normal {} vs {expect_n}",
                        g.surface(),
                        normal(&on)
                    );
                    assert!((tangential(&on) - expect_t).norm() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn lid_panel_on_the_free_surface() {
        let quad = Quadrature::new();
        let (a, b) = ([-0.1, 0.0], [0.1, 0.0]); // fluid on the right of a->b: below
        for k in [0.3, 2.0, 15.0] {
            let g = wave(k);
            for x in [0.0, 0.043, -0.099, 0.25, -1.0, 7.0] {
                let field = [x, 0.0];
                let got = g.panel_integral(field, a, b);
                let r = panel_by_quadrature(&quad, &g, field, a, b, false);
                assert!(
                    (got.potential - r[0]).norm() <= 1e-12 * r[3].re,
                    "k {k} x {x}: {} vs {}",
                    got.potential,
                    r[0]
                );
                // Gradient: the limit from the fluid below.
                let eps = 1e-9;
                let below = g.panel_integral([x, -eps], a, b);
                for i in 0..2 {
                    assert!((got.gradient[i] - below.gradient[i]).norm() < 1e-6);
                }
                // Free-surface condition with the doubled source on the panel.
                let jump = if x.abs() < 0.1 { 1.0 } else { 0.0 };
                assert!(
                    (got.gradient[1] - k * got.potential + jump).norm() < 1e-12,
                    "k {k} x {x}: {} vs {}",
                    got.gradient[1],
                    k * got.potential - jump
                );
                // Near-singular field just below the lid: full accuracy against quadrature.
                assert_panel_matches_quadrature(&quad, &g, [x, -1e-3], a, b, 1e-12);
                assert_panel_matches_quadrature(&quad, &g, [x, -0.3], a, b, 1e-12);
            }
        }
        // Rigid lid: (1/pi) ln r0 on the lid, dG/dy = -1 on the panel from below.
        let rigid = GreenFunction::new(FreeSurface::RigidLid).unwrap();
        let on = rigid.panel_integral([0.02, 0.0], a, b);
        assert!((on.gradient[1] + 1.0).norm() < 1e-14);
        let quad_val = panel_by_quadrature(&quad, &rigid, [0.02, 0.0], a, b, false);
        assert!((on.potential - quad_val[0]).norm() < 1e-13);
        // Dirichlet: G vanishes for sources on y = 0.
        let dirichlet = GreenFunction::new(FreeSurface::Dirichlet).unwrap();
        let on = dirichlet.panel_integral([0.02, -0.3], a, b);
        assert_eq!(on.potential, c(0.0, 0.0));
    }

    #[test]
    fn degenerate_panels() {
        let g = wave(1.0);
        let p = g.panel_integral([0.0, -1.0], [0.5, -0.5], [0.5, -0.5]);
        assert_eq!(p.potential, c(0.0, 0.0));
        let p = g.panel_integral([f64::NAN, -1.0], [0.5, -0.5], [0.6, -0.5]);
        assert!(p.potential.re.is_nan());
        // Field at an end point: finite potential, no panic.
        let p = g.panel_integral([0.5, -0.5], [0.5, -0.5], [0.6, -0.5]);
        assert!(p.potential.re.is_finite());
    }

    /// Semicircle of radius 1, `n` panels, body on the left of a->b.
    fn semicircle(n: usize) -> Vec<Point> {
        (0..=n)
            .map(|i| {
                let t = PI * i as f64 / n as f64;
                [-t.cos(), -t.sin()]
            })
            .collect()
    }

    /// On-CPU time of this thread in ns (Linux schedstat), else wall time since `origin`, so
    /// that timings are not inflated by other processes on a shared machine.
    fn cpu_ns(origin: &std::time::Instant) -> f64 {
        std::fs::read_to_string("/proc/thread-self/schedstat")
            .ok()
            .and_then(|s| s.split_whitespace().next().and_then(|v| v.parse().ok()))
            .unwrap_or_else(|| origin.elapsed().as_nanos() as f64)
    }

    /// CPU ns per call of `work` (which makes `calls` calls), repeated for at least `min_ns`.
    fn measure(calls: usize, min_ns: f64, mut work: impl FnMut() -> Complex64) -> f64 {
        let origin = std::time::Instant::now();
        let mut acc = c(0.0, 0.0);
        let start = cpu_ns(&origin);
        let mut reps = 0;
        while reps == 0 || cpu_ns(&origin) - start < min_ns {
            acc += work();
            reps += 1;
        }
        std::hint::black_box(acc);
        (cpu_ns(&origin) - start) / (reps * calls) as f64
    }

    #[test]
    #[ignore = "timing by region: cargo test --release -- --ignored --nocapture timing_regions"]
    fn timing_regions() {
        let table = QTable::new();
        println!("ns per call, direct / tabulated; columns arg p = 0, 20, 45, 70, 90 deg");
        for rho in [0.1, 0.4, 0.7, 1.5, 3.0, 6.0, 12.0, 25.0, 39.0, 60.0] {
            let mut line = format!("|p| = {rho:5.1}:");
            for deg in [0.0f64, 20.0, 45.0, 70.0, 90.0] {
                let ps: Vec<Complex64> = (0..1000)
                    .map(|i| Complex64::from_polar(rho * (1.0 + 1e-5 * i as f64), deg.to_radians()))
                    .collect();
                let direct = measure(ps.len(), 3e7, || ps.iter().map(|&p| scaled_ei(p).q).sum());
                let tab = measure(ps.len(), 3e7, || {
                    ps.iter().map(|&p| table.q_and_exp(p).0).sum()
                });
                line += &format!(" {direct:4.0}/{tab:3.0}");
            }
            println!("{line}");
        }
    }

    #[test]
    #[ignore = "timing: cargo test --release -- --ignored --nocapture --test-threads=1 timing"]
    fn timing() {
        let n = 100;
        let nodes = semicircle(n);
        let centres: Vec<Point> = nodes
            .windows(2)
            .map(|w| [0.5 * (w[0][0] + w[1][0]), 0.5 * (w[0][1] + w[1][1])])
            .collect();
        let ks: Vec<f64> = (0..20)
            .map(|j| 0.05 * 200f64.powf(j as f64 / 19.0))
            .collect();
        // e^z E1(z) at the kz of all centre pairs, kR in [0.05, 10].
        let mut args = Vec::new();
        for &k in &ks {
            for x in &centres {
                for x0 in &centres {
                    args.push(c(k * (x[1] + x0[1]), -k * (x[0] - x0[0]).abs()));
                }
            }
        }
        let t = measure(args.len(), 2e8, || {
            args.iter().map(|&z| scaled_exp_integral(z)).sum()
        });
        println!("scaled_exp_integral: {t:.0} ns/call");
        let greens: Vec<GreenFunction> = ks.iter().map(|&k| wave(k)).collect();
        let t = measure(1, 2e8, || c(wave(1.0).table.inner[5].re, 0.0));
        println!(
            "GreenFunction::new (Wave, builds the table): {:.0} us",
            t * 1e-3
        );
        let table = &greens[0].table;
        let t = measure(args.len(), 2e8, || {
            args.iter().map(|&z| table.q_and_exp(-z).0).sum()
        });
        println!("tabulated Q and e^-p: {t:.0} ns/call");
        let sweep =
            |g: &GreenFunction, f: fn(&GreenFunction, Point, Point, Point) -> PanelIntegral| {
                let mut acc = c(0.0, 0.0);
                for x in &centres {
                    for w in nodes.windows(2) {
                        acc += f(g, *x, w[0], w[1]).gradient[1];
                    }
                }
                acc
            };
        let rigid = GreenFunction::new(FreeSurface::RigidLid).unwrap();
        let t = measure(n * n, 2e8, || sweep(&rigid, GreenFunction::panel_integral));
        println!("panel_integral (rigid lid): {t:.0} ns/call");
        let t = measure(ks.len() * n * n, 2e8, || {
            greens
                .iter()
                .map(|g| sweep(g, GreenFunction::panel_integral))
                .sum()
        });
        println!("panel_integral (wave, {n}-panel semicircle, kR 0.05..10): {t:.0} ns/call");
        let t = measure(ks.len() * n * n, 2e8, || {
            greens
                .iter()
                .map(|g| sweep(g, GreenFunction::panel_integral_beyond_dirichlet))
                .sum()
        });
        println!("panel_integral_beyond_dirichlet (wave): {t:.0} ns/call");
        println!(
            "-> 200 frequencies x N^2 wave parts on one core: N = 100: {:.2} s, N = 300: {:.2} s",
            t * 200.0 * 1e4 * 1e-9,
            t * 200.0 * 9e4 * 1e-9
        );
    }
}
