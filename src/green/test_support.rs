//! Shared by the tests of the Green function: adaptive Gauss-Legendre quadrature (the
//! independent reference), the test surfaces and a CPU-time measurement.

use super::finite_depth::gauss_legendre;
use super::{FreeSurface, GreenFunction};
use num_complex::Complex64;

pub(super) fn c(re: f64, im: f64) -> Complex64 {
    Complex64::new(re, im)
}

/// Adaptive Gauss-Legendre (10 vs 20 points, bisection): the independent reference.
pub(super) struct Quadrature {
    low: Vec<(f64, f64)>,
    high: Vec<(f64, f64)>,
}

impl Quadrature {
    pub(super) fn new() -> Self {
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
    pub(super) fn integrate<const N: usize>(
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

pub(super) fn wave(k: f64) -> GreenFunction {
    GreenFunction::new(FreeSurface::Wave { wavenumber: k }).unwrap()
}

pub(super) fn all_surfaces() -> Vec<GreenFunction> {
    vec![
        GreenFunction::new(FreeSurface::RigidLid).unwrap(),
        GreenFunction::new(FreeSurface::Dirichlet).unwrap(),
        wave(0.05),
        wave(1.0),
        wave(7.0),
    ]
}
