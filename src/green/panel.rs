//! Closed-form integrals over a straight source panel `a -> b`: the Rankine parts
//! `ln r0`, `ln r1` (exact near the panel, multipole series about its centre far away) and the
//! wave part `int Q ds`, `int Q' ds`, `int e^{-p} ds` (antiderivative `K(p) = ln p + gamma - Q(p)`
//! at the end points near the panel, Taylor series about the centre far away).
//!
//! Panel frame: `zeta0(s) = centre + s tau`, `s in [-L/2, L/2]`; the fluid lies on the right
//! of `a -> b`; `p = i k (zeta - conj zeta0(s))`.

#[cfg(test)]
mod tests;

use super::exp_integral::{ei_series_sum, exp, ln, EULER_GAMMA};
use super::table::QTable;
use super::{log_ratio, Point};
use num_complex::Complex64;
use std::f64::consts::PI;

/// A panel is "far" when the field point is at least this many panel lengths from its centre
/// (multipole series ratio `<= (1/(2*FAR_RATIO))^2`).
const FAR_RATIO: f64 = 2.0;
/// Far-field wave series only while `k L / 2` stays below this (keeps `sinh` moderate).
pub(super) const FAR_WAVE_MAX_HALF_KL: f64 = 4.0;
/// Field points within this fraction of the panel length are taken on the panel.
const ON_PANEL_TOLERANCE: f64 = 1e-10;

/// Geometry of a straight panel, `zeta0(s) = centre + s tau`, `s in [-half, half]`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Panel {
    tau: Complex64,
    half: f64,
    centre: Complex64,
    a: Complex64,
    b: Complex64,
}

/// The part of the far series of [`Panel::wave`] that does not depend on the frequency.
#[derive(Clone, Copy, Debug)]
pub(super) struct FarGeometry {
    /// `i (zeta - conj centre)`: `p_c = k centre_ray`.
    pub(super) centre_ray: Complex64,
    /// `1 / centre_ray`.
    ray_inverse: Complex64,
    /// `-i conj(tau) L/2`: `h = (dp/ds) L/2 = k step`.
    step: Complex64,
    /// `g = h / p_c = step / centre_ray`.
    g: Complex64,
    /// `sum_{m>=1} g^{2m}/(2m+1)` (`int ds/p = (L/p_c)(1 + log_sum)`).
    log_sum: Complex64,
}

/// Coefficients of the series in `h` of the far series' sum that a prepared pair keeps
/// ([`FarGeometry::step_series`]).
pub(super) const STEP_SERIES_TERMS: usize = 10;

/// How many coefficients of [`FarGeometry::step_series`] reach `1e-17 |1/p_c|` at
/// `|h| = k L/2`; `None` beyond [`STEP_SERIES_TERMS`] (the recurrence then).
pub(super) fn step_series_terms(h_abs: f64) -> Option<usize> {
    // Term n is below (4/3) |g| |h|^n / (n+2)! = (4/3) |1/p_c| |h|^(n+1) / (n+2)!.
    let mut bound = 1.5 * h_abs / 2.0;
    for n in 0..=STEP_SERIES_TERMS {
        if bound <= 1e-17 {
            return Some(n);
        }
        bound *= h_abs / (n + 3) as f64;
    }
    None
}

impl FarGeometry {
    /// `T_n(g)`, `n < STEP_SERIES_TERMS`, with `sum_{m>=1} B_m = sum_n h^n T_n(g)`:
    /// `T_n = sum_{j >= 0, j = n+1 mod 2} g^{j+1} j! / (j+n+2)!` (independent of the frequency),
    /// the part of `U_n(g) = sum_{j >= 0} g^{j+1} j! / (j+n+2)!` of the parity of `n`. `U_n`
    /// by the recurrence `U_{n-1} = (g/(g-1)) ((n+1) U_n - 1/(n+1)!)`, stable downwards
    /// (`|g| <= 1/4`). Even `n` lose `|g|`'s digits to the parity split: at most `1e-16 |g| /
    /// (n+2)!` absolute, below the series' tolerance for `|h| <= 1`.
    pub(super) fn step_series(&self) -> [Complex64; STEP_SERIES_TERMS] {
        let plus = u_series(self.g);
        let minus = u_series(-self.g);
        std::array::from_fn(|n| {
            let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
            0.5 * (plus[n] + sign * minus[n])
        })
    }

    /// `sum_{m>=1} B_m` by the recurrence in `m`, to the absolute tolerance `tol`.
    fn b_sum_recurrence(&self, hh: Complex64, tol: f64) -> Complex64 {
        let g = self.g;
        let g2 = g * g;
        let hh2 = hh * hh;
        let mut b = Complex64::new(0.0, 0.0);
        let mut b_sum = Complex64::new(0.0, 0.0);
        let mut g_odd = g; // g^{2m-1}
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
        b_sum
    }
}

/// `U_n(x) = sum_{j >= 0} x^{j+1} j! / (j+n+2)!`, `n < STEP_SERIES_TERMS`, `|x| <= 1/4`.
fn u_series(x: Complex64) -> [Complex64; STEP_SERIES_TERMS] {
    const N: usize = STEP_SERIES_TERMS;
    // 1/(n+1)!, n < N + 1.
    const RECIPROCAL_FACTORIALS: [f64; N + 2] = {
        let mut r = [1.0; N + 2];
        let mut m = 1;
        while m < N + 2 {
            r[m] = r[m - 1] / (m + 1) as f64;
            m += 1;
        }
        r
    };
    let mut u = [Complex64::new(0.0, 0.0); N];
    // U_{N-1} directly: term ratio x (j+1)/(j+N+1).
    let mut term = x * RECIPROCAL_FACTORIALS[N];
    let mut sum = term;
    for j in 0..SERIES_COEFFICIENTS {
        term *= x * ((j + 1) as f64 / (j + N + 2) as f64);
        sum += term;
        if term.l1_norm() <= 1e-18 * sum.l1_norm() {
            break;
        }
    }
    u[N - 1] = sum;
    let ratio = x / (x - 1.0);
    for n in (1..N).rev() {
        u[n - 1] = ratio * ((n + 1) as f64 * u[n] - RECIPROCAL_FACTORIALS[n]);
    }
    u
}

/// Integrals of the wave part over a panel.
pub(super) struct WaveIntegrals {
    /// `int Q(p) ds`.
    pub(super) q_integral: Complex64,
    /// `int Q'(p) ds = int (1/p - Q) ds`.
    pub(super) dq_integral: Complex64,
    /// `int e^{-p} ds`.
    pub(super) exp_integral: Complex64,
}

impl Panel {
    /// The panel `a -> b` and the field point as complex numbers; `None` for zero length.
    pub(super) fn new(field: Point, a: Point, b: Point) -> Option<(Self, Complex64)> {
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
    pub(super) fn rankine(&self, zf: Complex64, sign: f64) -> (f64, Complex64) {
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
    pub(super) fn wave(&self, zf: Complex64, k: f64, table: &QTable) -> WaveIntegrals {
        if self.far_series_allowed(k) {
            if let Some(far) = self.far_geometry(zf) {
                let (q, exp) = table.q_and_exp(k * far.centre_ray);
                return self.wave_far(&far, k, (q, exp), self.sinhc_half_step(k), None);
            }
        }
        self.wave_exact(zf, k, table)
    }

    /// `sinh(h)/h` of `h = (dp/ds) L/2` at wavenumber `k` (the same for every field point).
    pub(super) fn sinhc_half_step(&self, k: f64) -> Complex64 {
        sinhc(Complex64::new(0.0, -k) * self.tau.conj() * self.half)
    }

    /// Whether the far series may serve at wavenumber `k` (`k L / 2` moderate).
    pub(super) fn far_series_allowed(&self, k: f64) -> bool {
        k * self.half <= FAR_WAVE_MAX_HALF_KL
    }

    /// The end points `a`, `b`.
    pub(super) fn end_points(&self) -> (Complex64, Complex64) {
        (self.a, self.b)
    }

    /// The centre.
    pub(super) fn centre(&self) -> Complex64 {
        self.centre
    }

    /// Half the panel length.
    pub(super) fn half_length(&self) -> f64 {
        self.half
    }

    /// The frequency-independent part of the far series for the field point `zf`; `None` when
    /// the point is too close to the panel's image for the series.
    pub(super) fn far_geometry(&self, zf: Complex64) -> Option<FarGeometry> {
        let len = 2.0 * self.half;
        let v_c = zf - self.centre.conj();
        if v_c.norm_sqr() < (FAR_RATIO * len) * (FAR_RATIO * len) {
            return None;
        }
        let centre_ray = Complex64::new(-v_c.im, v_c.re); // i v_c
        let ray_inverse = centre_ray.inv();
        let step = Complex64::new(0.0, -1.0) * self.tau.conj() * self.half;
        let g = step * ray_inverse;
        let (_, log_sum) = log_series(g);
        Some(FarGeometry {
            centre_ray,
            ray_inverse,
            step,
            g,
            log_sum,
        })
    }

    /// The wave integrals by the Taylor series about the centre, from `Q(p_c)` and `e^{-p_c}`,
    /// `p_c = k far.centre_ray`, and `sinh(h)/h`; `step_series`: the first coefficients of
    /// [`FarGeometry::step_series`], as many as [`step_series_terms`] asks for (`None`: the
    /// recurrence in `g`).
    pub(super) fn wave_far(
        &self,
        far: &FarGeometry,
        k: f64,
        (q, exp): (Complex64, Complex64),
        sinhc_half_step: Complex64,
        step_series: Option<&[Complex64]>,
    ) -> WaveIntegrals {
        // p = p_c + s dp/ds:
        // Q^(n)(p_c) = (-1)^n (Q - A_n), A_n = sum_{j<n} j!/p_c^{j+1}, and
        // int Q ds = L (Q sinh(h)/h - sum_{m>=1} B_m), B_m = h^{2m} A_{2m} / (2m+1)!,
        // h = (dp/ds) L/2, g = h/p_c (|g| <= 1/(2 FAR_RATIO)).
        let len = 2.0 * self.half;
        let hh = k * far.step;
        let sh = sinhc_half_step;
        let w = far.ray_inverse * (1.0 / k); // 1/p_c
        let b_sum = match step_series {
            Some(coefficients) => coefficients
                .iter()
                .rev()
                .fold(Complex64::new(0.0, 0.0), |acc, &c| acc * hh + c),
            None => far.b_sum_recurrence(hh, 1e-17 * (q.l1_norm() + w.l1_norm())),
        };
        // int ds/p = (L/p_c) atanh(g)/g.
        let main = q * sh - b_sum;
        WaveIntegrals {
            q_integral: len * main,
            dq_integral: -len * (main - (1.0 + far.log_sum) * w),
            exp_integral: exp * len * sh,
        }
    }

    /// [`Panel::wave`] from the antiderivatives at the end points (any distance).
    pub(super) fn wave_exact(&self, zf: Complex64, k: f64, table: &QTable) -> WaveIntegrals {
        let ik = Complex64::new(0.0, k);
        let slope = -ik * self.tau.conj(); // dp/ds
        let (ka, qa) = wave_endpoint(ik * (zf - self.a.conj()), table);
        let (kb, qb) = wave_endpoint(ik * (zf - self.b.conj()), table);
        // int e^{-p} ds = e^{-p_c} L sinh(h)/h (no cancellation for small k L).
        let hh = slope * self.half;
        let exp_c = exp(-ik * (zf - self.centre.conj()));
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
        let ln_p = ln(p) + EULER_GAMMA;
        let s = ei_series_sum(p);
        let em1 = expm1_complex(-p);
        let e = em1 + 1.0;
        (-em1 * ln_p - e * s, e * (ln_p + s))
    } else {
        let (q, _) = table.q_and_exp(p);
        (ln(p) + EULER_GAMMA - q, q)
    }
}
