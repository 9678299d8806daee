//! Complex exponential integrals: `E1(z)`, the scaled `F(z) = e^z E1(z)` and
//! `Q(p) = e^{-p} Ei(p) = -F(-p) + i pi sgn(Im p) e^{-p}`.
//!
//! ```text
//! Ei(p) = gamma + ln p + S(p),   S(p) = sum_{n>=1} p^n / (n n!)
//! F(z)  = 1/(z+1- 1/(z+3- 4/(z+5- 9/(z+7- ...))))
//! ```
//! The power series where `|p| - Re p <= 3` and `|p| < 40`, else the continued fraction (and
//! the asymptotic series beyond `|p| = 1e5`). Principal branch of `E1`, cut on the negative
//! real axis; the sign of a zero imaginary part picks the side.

#[cfg(test)]
mod tests;

use num_complex::Complex64;
use std::f64::consts::PI;

/// Euler's constant.
pub(super) const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;

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
#[cfg(test)]
pub(super) fn exp_integral_e1(z: Complex64) -> Complex64 {
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
pub(super) const RECIPROCALS: [f64; SERIES_MAX_TERMS + 1] = {
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
pub(super) struct ScaledEi {
    pub(super) q: Complex64,
    pub(super) f: Complex64,
    pub(super) exp: Complex64,
}

/// `Q(p)`, `F(-p)`, `e^{-p}`; the sign of `Im p` (including a signed zero) picks the side of
/// the cuts (`Q`: negative real axis of `p`; `F(-p)`: positive real axis of `p`).
pub(super) fn scaled_ei(p: Complex64) -> ScaledEi {
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
    scaled_ei_upper_given_exp(p, exp(-p))
}

/// [`scaled_ei`] for `Im p >= +0`, given `exp = e^{-p}`.
pub(super) fn scaled_ei_upper_given_exp(p: Complex64, exp: Complex64) -> ScaledEi {
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
        let ei = ln(p) + EULER_GAMMA + ei_series_sum(p);
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

/// `ln z` by `ln |z|^2 / 2` and one `atan2` (no `hypot`); `z.ln()` where `|z|^2` would
/// overflow, underflow or is not finite.
#[inline]
pub(super) fn ln(z: Complex64) -> Complex64 {
    let r2 = z.norm_sqr();
    if r2.is_normal() && r2 < f64::MAX {
        Complex64::new(0.5 * r2.ln(), z.im.atan2(z.re))
    } else {
        z.ln()
    }
}

/// `e^z` with one `sin_cos`; `z.exp()` for non-finite `z`.
#[inline]
pub(super) fn exp(z: Complex64) -> Complex64 {
    if z.re.is_finite() && z.im.is_finite() {
        let (sin, cos) = z.im.sin_cos();
        let r = z.re.exp();
        Complex64::new(r * cos, r * sin)
    } else {
        z.exp()
    }
}

/// `Q(p)` by the power series, for `|p| < 1`, `Re p >= 0`, `Im p >= +0`, given `ln p` and
/// `exp = e^{-p}` (as [`scaled_ei`] there, without its logarithm and exponential).
pub(super) fn small_q(p: Complex64, ln_p: Complex64, exp: Complex64) -> Complex64 {
    exp * (ln_p + EULER_GAMMA + ei_series_sum(p))
}

/// `S(p) = sum_{n>=1} p^n / (n n!)`, so `Ei(p) = gamma + ln p + S(p)` and
/// `E1(z) = -gamma - ln z - S(-z)`.
pub(super) fn ei_series_sum(p: Complex64) -> Complex64 {
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
