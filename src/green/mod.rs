//! Deep-water two-dimensional free-surface Green function (Schilder et al., eq. 11-12, after Damaren 2000),
//! its gradient, its two frequency limits, the complex exponential integral `E1`, and exact
//! integrals over straight source panels.
//!
//! # Conventions
//! `x` to the right, `y` up, fluid in `y < 0`, mean free surface `y = 0`, infinite depth, time
//! factor `exp(+i omega t)`, wavenumber `k = omega^2 / g`. Points are `[x, y]`.
//!
//! # The Green function
//! Potential at the field point `x` of a unit source at `x0` (Schilder et al., eq. 11-12):
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
//! absolute integrand. On a 100-panel semicircle one wave panel integral costs about 0.4 us
//! (0.27 us for [`GreenFunction::panel_integral_beyond_dirichlet`], whose Dirichlet complement
//! does not depend on the frequency; `cargo bench --bench green`, 2026-11-28).
//!
//! # Many frequencies on one mesh
//! A sweep prepares its (field point, panel) pairs once, [`PanelPairs`]: per pair the far
//! series' part that does not depend on `k` (`g = h/p_c`, `int ds/p`, and the coefficients
//! `T_n(g)` of `sum_m B_m = sum_n h^n T_n(g)`, so that a frequency costs a short polynomial in
//! `h = k L/2` instead of the recurrence in `g`), and the distinct far-series arguments
//! `p_c / k`. A pair and its transpose (or its mirror image in `x = 0`) have conjugate
//! arguments, `p_c(p, i) = conj p_c(i, p)`, and `Q(conj p) = conj Q(p)`: one `Q` serves both.
//! `e^{-p_c} = e^{-i k zeta} conj(e^{-i k zeta_c})` takes one exponential per point, and
//! `ln p_c = ln k + ln(p_c / k)`. [`GreenFunction::panel_integrals_beyond_dirichlet`] gives the
//! same values as pair by pair to rounding (tested: `5.6e-16` of `1 + |value|`) at about
//! 0.1 us a pair.
//!
//! # Layout
//! * this file: [`GreenFunction`] (point values and panel integrals) for one [`FreeSurface`],
//!   and [`PanelPairs`];
//! * `panel`: closed-form panel integrals (Rankine log integrals, multipole series, wave part);
//! * `table`: the tabulated `Q(p)` with Taylor steps;
//! * `exp_integral`: `E1`, `e^z E1(z)`, `Q = e^{-p} Ei(p)` by series and continued fraction;
//! * [`finite_depth`]: the Green function in water of finite depth, built on this one.

mod exp_integral;
pub mod finite_depth;
mod panel;
mod table;
#[cfg(test)]
mod test_support;
#[cfg(test)]
mod tests;

pub use exp_integral::scaled_exp_integral;

use num_complex::Complex64;
use panel::{FarGeometry, Panel};
use std::collections::HashMap;
use std::f64::consts::PI;
use std::fmt;
use table::QTable;

/// A point `[x, y]` (y up, fluid in y < 0).
pub type Point = [f64; 2];

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
#[non_exhaustive]
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
/// Refers to the process's one table of `e^{-p} Ei(p)` (about 23 kB, independent of the
/// frequency: built at the first wave solve, read-only after), so a `GreenFunction` is cheap to
/// make per frequency.
#[derive(Clone, Copy)]
pub struct GreenFunction {
    surface: FreeSurface,
    table: &'static QTable,
}

/// The table of `Q(p)`: a function of `p` alone, the same for every frequency and instance.
fn q_table() -> &'static QTable {
    static TABLE: std::sync::OnceLock<QTable> = std::sync::OnceLock::new();
    TABLE.get_or_init(QTable::new)
}

impl fmt::Debug for GreenFunction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GreenFunction")
            .field("surface", &self.surface)
            .finish_non_exhaustive()
    }
}

impl GreenFunction {
    /// Green function for the given free-surface condition.
    ///
    /// # Errors
    /// [`GreenError::InvalidWavenumber`] unless the wavenumber of `Wave` is finite and > 0.
    pub fn new(surface: FreeSurface) -> Result<Self, GreenError> {
        if let FreeSurface::Wave { wavenumber } = surface {
            if !(wavenumber.is_finite() && wavenumber > 0.0) {
                return Err(GreenError::InvalidWavenumber(wavenumber));
            }
        }
        Ok(Self {
            surface,
            table: q_table(),
        })
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
        add_wave_integrals(wavenumber, &panel.wave(zf, wavenumber, self.table), out);
    }

    /// [`GreenFunction::panel_integral_beyond_dirichlet`] of every pair of `pairs`, in their
    /// order, into `out` (cleared first). The same values as pair by pair; for `Wave` faster,
    /// from the pairs' frequency-independent part and one `Q(p)` per distinct far-series
    /// argument (a pair and its transpose, or its mirror image, share one up to conjugation).
    pub fn panel_integrals_beyond_dirichlet(
        &self,
        pairs: &PanelPairs,
        out: &mut Vec<PanelIntegral>,
    ) {
        out.clear();
        let FreeSurface::Wave { wavenumber: k } = self.surface else {
            out.extend(pairs.pairs.iter().map(|pair| {
                let (field, a, b) = pair.points(&pairs.panels);
                self.panel_integral_beyond_dirichlet(field, a, b)
            }));
            return;
        };
        let nan = Complex64::new(f64::NAN, f64::NAN);
        let ln_k = k.ln();
        // e^{-p} = e^{-i k zeta} conj(e^{-i k centre}): one exponential per point.
        let factors: Vec<Complex64> = pairs
            .points
            .iter()
            .map(|z| exp_integral::exp(Complex64::new(k * z.im, -k * z.re)))
            .collect();
        let shared: Vec<(Complex64, Complex64)> = pairs
            .rays
            .iter()
            .map(|ray| {
                if k * ray.smallest_half > panel::FAR_WAVE_MAX_HALF_KL {
                    return (nan, nan);
                }
                let p = k * ray.ray;
                let (field, centre) = (factors[ray.field as usize], factors[ray.centre as usize]);
                let exp = if ray.conjugate {
                    field.conj() * centre
                } else {
                    field * centre.conj()
                };
                let q = if p.re >= 0.0 && p.norm_sqr() < 1.0 {
                    // The series, as the table would, with ln p = ln k + ln(p/k).
                    exp_integral::small_q(p, ray.ln_ray + ln_k, exp)
                } else {
                    self.table.q_given_exp(p, exp)
                };
                (q, exp)
            })
            .collect();
        // Per panel: sinh(h)/h and the terms of the series in h.
        let steps: Vec<(Complex64, Option<usize>)> = pairs
            .panels
            .iter()
            .map(|panel| {
                let terms = panel::step_series_terms(k * panel.half_length());
                (panel.sinhc_half_step(k), terms)
            })
            .collect();
        out.extend(pairs.pairs.iter().map(|pair| {
            let zero = Complex64::new(0.0, 0.0);
            let mut integral = PanelIntegral {
                potential: zero,
                gradient: [zero, zero],
            };
            let Some(panel) = pairs.panels.get(pair.panel as usize) else {
                return integral;
            };
            let waves = match pairs.far.get(pair.far as usize) {
                Some(far) if panel.far_series_allowed(k) => {
                    let (q, exp) = shared[far.ray as usize];
                    let values = if far.conjugate {
                        (q.conj(), exp.conj())
                    } else {
                        (q, exp)
                    };
                    let (sinhc, terms) = steps[pair.panel as usize];
                    let series = terms.map(|n| &far.step_series[..n]);
                    panel.wave_far(&far.geometry, k, values, sinhc, series)
                }
                _ => panel.wave_exact(pair.field, k, self.table),
            };
            add_wave_integrals(k, &waves, &mut integral);
            integral
        }));
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

/// Adds the wave part `(1/pi) Re Q(p) + i Re e^{-p}` from the panel's wave integrals.
fn add_wave_integrals(k: f64, w: &panel::WaveIntegrals, out: &mut PanelIntegral) {
    let ik = Complex64::new(0.0, k);
    // Complex derivatives of the analytic integrands behind the real and imaginary parts.
    let d_re = ik / PI * w.dq_integral;
    let d_im = -ik * w.exp_integral;
    out.potential += Complex64::new(w.q_integral.re / PI, w.exp_integral.re);
    out.gradient[0] += Complex64::new(d_re.re, d_im.re);
    out.gradient[1] += Complex64::new(-d_re.im, -d_im.im);
}

/// A fixed list of (field point, panel) pairs with the part of their wave integrals that does
/// not depend on the frequency, for [`GreenFunction::panel_integrals_beyond_dirichlet`]: a
/// frequency sweep on one mesh prepares it once. Points and panels lie in the fluid, `y <= 0`
/// (as for [`GreenFunction::value_and_gradient`]); about 0.3 kB a pair.
#[derive(Clone, Debug, Default)]
pub struct PanelPairs {
    pairs: Vec<Pair>,
    /// Distinct far-series arguments.
    rays: Vec<Ray>,
    /// Distinct field points and panel centres.
    points: Vec<Complex64>,
    /// Distinct panels.
    panels: Vec<Panel>,
    /// The far-series part of the pairs where it serves.
    far: Vec<FarPair>,
}

/// A far-series argument shared by pairs.
#[derive(Clone, Copy, Debug)]
struct Ray {
    /// `p_c / k`, `Im >= +0`.
    ray: Complex64,
    /// `ln(ray)`.
    ln_ray: Complex64,
    /// The smallest half panel length among the pairs that use it.
    smallest_half: f64,
    /// One pair's field point and panel centre in `points`, and whether `ray` is the conjugate
    /// of that pair's `i (zeta - conj centre)`.
    field: u32,
    centre: u32,
    conjugate: bool,
}

#[derive(Clone, Debug)]
struct Pair {
    field: Complex64,
    /// Index in `panels`; `u32::MAX` for a zero-length panel.
    panel: u32,
    /// Index in `far`; `u32::MAX` where the far series does not serve.
    far: u32,
}

/// The far-series part of a [`Pair`].
#[derive(Clone, Debug)]
struct FarPair {
    geometry: FarGeometry,
    step_series: [Complex64; panel::STEP_SERIES_TERMS],
    /// The index of its argument in `rays`, and whether the pair's argument is the conjugate
    /// of that one.
    ray: u32,
    conjugate: bool,
}

impl Pair {
    fn points(&self, panels: &[Panel]) -> (Point, Point, Point) {
        let field = [self.field.re, self.field.im];
        match panels.get(self.panel as usize) {
            Some(panel) => {
                let (a, b) = panel.end_points();
                (field, [a.re, a.im], [b.re, b.im])
            }
            None => (field, field, field),
        }
    }
}

impl PanelPairs {
    /// Prepares the pairs `(field, a, b)`: the field point and the panel `a -> b`.
    pub fn new(pairs: impl IntoIterator<Item = (Point, Point, Point)>) -> Self {
        let mut out = PanelPairs::default();
        let mut index: HashMap<(u64, u64), u32> = HashMap::new();
        let mut point_index: HashMap<(u64, u64), u32> = HashMap::new();
        let mut panel_index: HashMap<[u64; 4], u32> = HashMap::new();
        let mut point = |z: Complex64, points: &mut Vec<Complex64>| {
            *point_index
                .entry((z.re.to_bits(), z.im.to_bits()))
                .or_insert_with(|| {
                    points.push(z);
                    (points.len() - 1) as u32
                })
        };
        for (field, a, b) in pairs {
            let Some((panel, zf)) = Panel::new(field, a, b) else {
                out.pairs.push(Pair {
                    field: Complex64::new(field[0], field[1]),
                    panel: u32::MAX,
                    far: u32::MAX,
                });
                continue;
            };
            let bits = [a[0], a[1], b[0], b[1]].map(f64::to_bits);
            let panel_slot = *panel_index.entry(bits).or_insert_with(|| {
                out.panels.push(panel);
                (out.panels.len() - 1) as u32
            });
            let far = panel.far_geometry(zf).map(|far| {
                // The lower half plane by conjugation, as `QTable::q_and_exp` does it.
                let conjugate = far.centre_ray.im.is_sign_negative();
                let ray = if conjugate {
                    far.centre_ray.conj()
                } else {
                    far.centre_ray
                };
                let next = out.rays.len() as u32;
                let slot = *index
                    .entry((ray.re.to_bits(), ray.im.to_bits()))
                    .or_insert(next);
                if slot == next {
                    out.rays.push(Ray {
                        ray,
                        ln_ray: exp_integral::ln(ray),
                        smallest_half: panel.half_length(),
                        field: point(zf, &mut out.points),
                        centre: point(panel.centre(), &mut out.points),
                        conjugate,
                    });
                } else {
                    let smallest = &mut out.rays[slot as usize].smallest_half;
                    *smallest = smallest.min(panel.half_length());
                }
                out.far.push(FarPair {
                    step_series: far.step_series(),
                    geometry: far,
                    ray: slot,
                    conjugate,
                });
                (out.far.len() - 1) as u32
            });
            out.pairs.push(Pair {
                field: zf,
                panel: panel_slot,
                far: far.unwrap_or(u32::MAX),
            });
        }
        out
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    /// Whether there are no pairs.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }
}

/// `ln(r0/r1)` without cancellation: `r1^2 - r0^2 = 4 y y0`.
fn log_ratio(y: f64, y0: f64, r1_sq: f64) -> f64 {
    0.5 * (-4.0 * y * y0 / r1_sq).ln_1p()
}
