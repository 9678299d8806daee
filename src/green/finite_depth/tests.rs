//! Tests of the finite-depth Green function: the dispersion relation, the deep-water limit,
//! the defining identities by finite differences, the near form against the eigenfunction
//! series, the far field's energy flux, and the panel integrals against adaptive quadrature.

use super::*;
use crate::green::test_support::{c, Quadrature};

fn green(nu: f64, depth: f64) -> FiniteDepthGreen {
    FiniteDepthGreen::new(nu, depth).unwrap()
}

/// `(nu, depth)`: shallow, intermediate and deep water.
const CASES: [(f64, f64); 4] = [(0.05, 2.0), (1.0, 1.0), (0.8, 3.0), (4.0, 2.5)];

/// Field and source points as fractions of the depth (`y/h` in `[-1, 0]`).
const POINTS: [([f64; 2], [f64; 2]); 7] = [
    ([0.1, -0.3], [0.0, -0.5]),
    ([0.05, -0.05], [-0.02, -0.1]),
    ([-0.2, -0.9], [0.1, -0.7]),
    ([0.3, -0.6], [0.0, -0.2]),
    ([0.7, -0.4], [0.0, -0.5]),
    ([1.5, -0.1], [0.2, -0.95]),
    ([-4.0, -0.5], [0.0, -0.3]),
];

fn scaled(p: [f64; 2], depth: f64) -> Point {
    [p[0] * depth, p[1] * depth]
}

#[test]
fn dispersion_known_values() {
    // nu h = 1: k h = 1.19967864025773...
    let k = wavenumber(1.0, 1.0).unwrap();
    assert!((k - 1.199_678_640_257_734).abs() < 2e-15, "{k}");
    assert!((wavenumber(0.5, 2.0).unwrap() * 2.0 - k).abs() < 4e-15);
    for mu in [1e-10, 1e-6, 1e-3, 0.1, 1.0, 3.0, 10.0, 30.0, 1e3, 1e8] {
        let t = wavenumber(mu, 1.0).unwrap();
        assert!((t * t.tanh() - mu).abs() <= 3e-16 * mu, "mu {mu}: {t}");
    }
    // Long waves: k ~ omega / sqrt(g h), t = sqrt(mu) (1 + mu/6 + O(mu^2)).
    for mu in [1e-12, 1e-8, 1e-5] {
        let t = wavenumber(mu, 1.0).unwrap();
        let long = mu.sqrt() * (1.0 + mu / 6.0);
        assert!(
            (t - long).abs() <= 1e-14 * long + mu.powf(2.5),
            "{mu}: {t} {long}"
        );
    }
    // Deep water: k = nu once tanh(nu h) = 1 in doubles.
    assert_eq!(wavenumber(2.0, 20.0).unwrap(), 2.0);
    // Evanescent roots: k_n tan(k_n h) = -nu, (n - 1/2) pi < k_n h < n pi.
    for mu in [1e-6, 0.3, 1.0, 7.0, 500.0] {
        let roots = evanescent_wavenumbers(mu, 1.0, 60).unwrap();
        for (n, t) in (1..).zip(roots) {
            let n_pi = n as f64 * PI;
            assert!(t > n_pi - 0.5 * PI && t < n_pi, "mu {mu} n {n}: {t}");
            // Residual in the form t sin t + mu cos t; one rounding of t moves it by
            // about eps t (t + 1 + mu).
            let residual = t * t.sin() + mu * t.cos();
            assert!(
                residual.abs() <= 2e-15 * t * (t + 1.0 + mu),
                "mu {mu} n {n}: {residual}"
            );
        }
    }
}

#[test]
fn invalid_input_is_named() {
    let depth = wavenumber(1.0, 0.0).unwrap_err();
    assert_eq!(depth, DepthError::InvalidDepth(0.0));
    assert!(depth.to_string().contains("depth"));
    for nu in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let err = FiniteDepthGreen::new(nu, 1.0).unwrap_err();
        assert!(err.to_string().contains("nu"), "{err}");
    }
    for h in [-2.0, f64::INFINITY, f64::NAN] {
        let err = evanescent_wavenumbers(1.0, h, 3).unwrap_err();
        assert!(err.to_string().contains("depth"), "{err}");
    }
    let failed = DepthError::NoConvergence {
        nu: 1.0,
        depth: 2.0,
    };
    assert!(failed.to_string().contains("did not converge"));
}

/// Largest difference of value and gradient between `G_h` and the deep-water `G`.
fn deep_water_difference(nu: f64, depth: f64) -> f64 {
    let g = green(nu, depth);
    let deep = GreenFunction::new(FreeSurface::Wave { wavenumber: nu }).unwrap();
    let mut worst: f64 = 0.0;
    for (field, source) in [
        ([0.3, -0.2], [0.0, -0.5]),
        ([-1.0, -1.2], [0.5, -0.1]),
        ([2.5, -0.4], [0.0, -0.8]),
        ([0.1, 0.0], [0.0, -0.3]),
    ] {
        let (v, gr) = g.value_and_gradient(field, source);
        let (d, dg) = deep.value_and_gradient(field, source);
        worst = worst
            .max((v - d).norm())
            .max((gr[0] - dg[0]).norm())
            .max((gr[1] - dg[1]).norm());
    }
    worst
}

#[test]
fn deep_water_limit() {
    // The bottom's effect on the non-wave part falls like 1/(nu h)^2 (measured 3.3e-4 at
    // nu h = 20, 7.7e-5 at 40, 1.9e-5 at 80); the wave part's like e^{-2 nu h}.
    let at_20 = deep_water_difference(1.0, 20.0);
    let at_40 = deep_water_difference(1.0, 40.0);
    let at_80 = deep_water_difference(1.0, 80.0);
    eprintln!("deep limit: {at_20:e} {at_40:e} {at_80:e}");
    assert!(at_20 < 4e-4, "{at_20}");
    assert!(
        at_40 < 0.3 * at_20 && at_80 < 0.3 * at_40,
        "{at_40} {at_80}"
    );
    // Panel integrals tend to the deep-water closed form in the same way.
    let g = green(1.0, 20.0);
    let deep = GreenFunction::new(FreeSurface::Wave { wavenumber: 1.0 }).unwrap();
    let mut worst: f64 = 0.0;
    for (field, a, b) in [
        ([0.3, -0.2], [0.0, -0.5], [0.2, -0.6]),
        ([0.1, -0.55], [0.0, -0.5], [0.2, -0.6]),
        ([2.0, 0.0], [-0.5, -0.1], [-0.6, -0.9]),
    ] {
        let p = g.panel_integral(field, a, b);
        let d = deep.panel_integral(field, a, b);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        worst = worst.max((p.potential - d.potential).norm() / len);
        for i in 0..2 {
            worst = worst.max((p.gradient[i] - d.gradient[i]).norm() / len);
        }
    }
    eprintln!("deep limit panels: {worst:e}");
    assert!(worst < 2.5e-4, "{worst}");
}

#[test]
fn identities_by_finite_differences() {
    let mut worst = [0.0f64; 5];
    for (nu, h) in CASES {
        let g = green(nu, h);
        let value = |p: Point, s: Point| g.value_and_gradient(p, s).0;
        for (f, s) in POINTS {
            let (field, source) = (scaled(f, h), scaled(s, h));
            let (v, grad) = g.value_and_gradient(field, source);
            let scale = 1.0 + v.norm();
            // Reciprocity.
            let (swapped, _) = g.value_and_gradient(source, field);
            worst[0] = worst[0].max((v - swapped).norm() / scale);
            // Gradient against 4th-order central differences, inside the fluid; steps and
            // errors scaled by the shortest length: the distance to the source, the depth,
            // the wavelength / 2 pi.
            let r0 = (field[0] - source[0]).hypot(field[1] - source[1]);
            let length = r0.min(h).min(1.0 / g.wavenumber());
            let step = 1e-3 * length;
            if field[1] < -2.0 * step && field[1] > -h + 2.0 * step {
                let at = |dx: f64, dy: f64| value([field[0] + dx, field[1] + dy], source);
                let fd = |e: [f64; 2]| {
                    (at(-2.0 * step * e[0], -2.0 * step * e[1])
                        - 8.0 * at(-step * e[0], -step * e[1])
                        + 8.0 * at(step * e[0], step * e[1])
                        - at(2.0 * step * e[0], 2.0 * step * e[1]))
                        / (12.0 * step)
                };
                for (i, e) in [[1.0, 0.0], [0.0, 1.0]].into_iter().enumerate() {
                    let d = (fd(e) - grad[i]).norm() * length / scale;
                    worst[1] = worst[1].max(d);
                }
                // Laplace, 5-point.
                let laplace = (at(step, 0.0) + at(-step, 0.0) + at(0.0, step) + at(0.0, -step)
                    - 4.0 * v)
                    / (step * step);
                worst[2] = worst[2].max(laplace.norm() * length * length / scale);
            }
            // Free surface and bottom, at the field point's x.
            let (top, top_grad) = g.value_and_gradient([field[0], 0.0], source);
            worst[3] = worst[3].max((top_grad[1] - nu * top).norm() * h / (1.0 + top.norm()));
            let (bottom, bottom_grad) = g.value_and_gradient([field[0], -h], source);
            worst[4] = worst[4].max(bottom_grad[1].norm() * h / (1.0 + bottom.norm()));
        }
    }
    eprintln!("identities (reciprocity, gradient, laplace, surface, bottom): {worst:?}");
    // Measured: 1e-16, 2.3e-13, 1.3e-7 (5-point truncation), 1.3e-15, 1.5e-14.
    let limits = [1e-15, 1e-12, 3e-7, 5e-15, 5e-14];
    for (w, l) in worst.iter().zip(limits) {
        assert!(w < &l, "{worst:?}");
    }
}

#[test]
fn near_form_matches_series_in_the_overlap() {
    let mut worst: f64 = 0.0;
    let mut jump: f64 = 0.0;
    // nu h from 0.003 to 30.
    for (nu, h) in CASES.into_iter().chain([(0.001, 3.0), (10.0, 3.0)]) {
        let g = green(nu, h);
        let k1 = g.modes[0].wavenumber;
        for (y, y0) in [
            (-0.3, -0.6),
            (0.0, -0.1),
            (-1.0, -0.95),
            (-0.5, 0.0),
            (0.0, 0.0),
        ] {
            let (y, y0) = (y * h, y0 * h);
            for ratio in [0.5, 0.7, 1.0, 1.5, 2.0] {
                let x = ratio / k1;
                let (field, source) = ([x, y], [0.0, y0]);
                let [r, r_x, r_y] = g.near_remainder(field, source);
                let (deep, deep_grad) = g.deep.value_and_gradient(field, source);
                let (log, log_grad) = g.bottom_log(field, source);
                let (s, s_grad) = g.series(field, source);
                let scale = 1.0 + s.norm();
                worst = worst
                    .max((deep.re + log + r - s.re).abs() / scale)
                    .max((deep_grad[0].re + log_grad[0] + r_x - s_grad[0].re).abs() * h / scale)
                    .max((deep_grad[1].re + log_grad[1] + r_y - s_grad[1].re).abs() * h / scale);
            }
            // Continuity across the switch: the last X of the near form and the first of the
            // series, one unit in the last place apart.
            let mut first = SERIES_SWITCH / k1;
            while !g.series_serves(first) {
                first = f64::from_bits(first.to_bits() + 1);
            }
            let last = f64::from_bits(first.to_bits() - 1);
            assert!(!g.series_serves(last));
            let (below, below_grad) = g.value_and_gradient([last, y], [0.0, y0]);
            let (above, above_grad) = g.value_and_gradient([first, y], [0.0, y0]);
            let scale = 1.0 + above.norm();
            jump = jump
                .max((below - above).norm() / scale)
                .max((below_grad[0] - above_grad[0]).norm() * h / scale)
                .max((below_grad[1] - above_grad[1]).norm() * h / scale);
        }
    }
    eprintln!("overlap: {worst:e}, jump at the switch {jump:e}");
    // Measured 1.6e-13 for both.
    assert!(worst < 3e-13, "{worst}");
    assert!(jump < 3e-13, "{jump}");
}

#[test]
fn far_field_is_the_outgoing_propagating_mode() {
    // Green's identity with conj(G) around the source: Im G(x0, x0) = 2 k0 int |a(y)|^2 dy,
    // the flux of the two outgoing waves G ~ i a(y) e^{-i k0 |X|}. With the surface amplitude
    // a(0): 2 k0 int a^2 dy = 2 tanh(k0 h) (c_g/c_p) a(0)^2, c_g/c_p = (1 + 2k0h/sinh 2k0h)/2.
    for (nu, h) in CASES {
        let g = green(nu, h);
        let k0 = g.wavenumber();
        for y0 in [-0.1 * h, -0.5 * h, -0.9 * h] {
            let far = 30.0 * h;
            let (top, top_grad) = g.value_and_gradient([far, 0.0], [0.0, y0]);
            // Outgoing: dG/dX = -i k0 G.
            let radiation = top_grad[0] + Complex64::new(0.0, k0) * top;
            assert!(radiation.norm() < 1e-14 * k0 * top.norm(), "{radiation}");
            // Only the propagating mode: |G| does not vary along X.
            let (further, _) = g.value_and_gradient([far + 0.37 * h, 0.0], [0.0, y0]);
            assert!((further.norm() - top.norm()).abs() < 1e-14 * top.norm());
            let group = 0.5 * (1.0 + 2.0 * k0 * h / (2.0 * k0 * h).sinh());
            let flux = 2.0 * (k0 * h).tanh() * group * top.norm_sqr();
            let (at_source, _) = g.value_and_gradient([1e-9 * h, y0], [0.0, y0]);
            assert!(
                (at_source.im - flux).abs() < 1e-14 * flux,
                "nu {nu} h {h}: {} vs {flux}",
                at_source.im
            );
            // The same flux from the far field by quadrature over the depth.
            let quadrature = Quadrature::new();
            let [flux_integral] = quadrature.integrate(
                &|y| {
                    let (v, grad) = g.value_and_gradient([far, y], [0.0, y0]);
                    // Im(G dconj(G)/dX) = k0 |a|^2 for the outgoing wave.
                    [c((v * grad[0].conj()).im, 0.0)]
                },
                -h,
                0.0,
                1e-15,
            );
            let expected = 0.5 * at_source.im;
            assert!(
                (flux_integral.re - expected).abs() < 1e-13 * expected,
                "{} vs {expected}",
                flux_integral.re
            );
        }
    }
}

/// `int_a^b G ds0` and its gradient by adaptive quadrature of `G_h - G_inf` plus the
/// deep-water closed form.
fn reference_panel_integral(
    g: &FiniteDepthGreen,
    field: Point,
    a: Point,
    b: Point,
) -> [Complex64; 3] {
    let quadrature = Quadrature::new();
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let difference = quadrature.integrate(
        &|t| {
            let s = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            let (v, grad) = g.value_and_gradient(field, s);
            let (d, d_grad) = g.deep.value_and_gradient(field, s);
            [
                (v - d) * len,
                (grad[0] - d_grad[0]) * len,
                (grad[1] - d_grad[1]) * len,
            ]
        },
        0.0,
        1.0,
        1e-16,
    );
    let deep = g.deep.panel_integral(field, a, b);
    [
        deep.potential + difference[0],
        deep.gradient[0] + difference[1],
        deep.gradient[1] + difference[2],
    ]
}

#[test]
fn panel_integrals_match_adaptive_quadrature() {
    for (nu, h) in CASES {
        let g = green(nu, h);
        let mut worst = [0.0f64; 3];
        for (length, index) in [(0.05, 0), (0.25, 1), (0.5, 2)] {
            for (f, s) in POINTS {
                let a = scaled(s, h);
                let dir = [0.6, -0.8];
                let mut b = [a[0] + length * h * dir[0], a[1] + length * h * dir[1]];
                b[1] = b[1].max(-h);
                let field = scaled(f, h);
                let p = g.panel_integral(field, a, b);
                let r = reference_panel_integral(&g, field, a, b);
                let len = (b[0] - a[0]).hypot(b[1] - a[1]);
                let scale = len * (1.0 + r[0].norm() / len);
                let error = (p.potential - r[0])
                    .norm()
                    .max((p.gradient[0] - r[1]).norm() * h)
                    .max((p.gradient[1] - r[2]).norm() * h);
                worst[index] = worst[index].max(error / scale);
            }
        }
        eprintln!("panels nu {nu} h {h}: L/h = 0.05, 0.25, 0.5: {worst:?}");
        // Measured at most 8.6e-15 (10 nodes).
        assert!(worst.iter().all(|&w| w < 2e-14), "{worst:?}");
    }
}

#[test]
fn panel_on_the_field_point_and_near_the_bottom() {
    let g = green(1.0, 1.0);
    // Field point on the panel's centre: the normal gradient holds -1/2 (as in deep water).
    let (a, b) = ([0.0, -0.3], [0.2, -0.5]);
    let on = g.panel_integral([0.1, -0.4], a, b);
    let normal = [-(b[1] - a[1]), b[0] - a[0]];
    let len = normal[0].hypot(normal[1]);
    let off = |eps: f64| {
        // A point eps into the fluid (right of a -> b).
        g.panel_integral(
            [0.1 - eps * normal[0] / len, -0.4 - eps * normal[1] / len],
            a,
            b,
        )
    };
    let near = off(1e-9);
    assert!((on.potential - near.potential).norm() < 1e-8);
    for i in 0..2 {
        assert!((on.gradient[i] - near.gradient[i]).norm() < 1e-6, "{i}");
    }
    // A panel close to the bottom and a field point between it and the bottom.
    let (a, b) = ([0.0, -0.96], [0.1, -0.97]);
    let field = [0.05, -0.99];
    let p = g.panel_integral(field, a, b);
    let r = reference_panel_integral(&g, field, a, b);
    let error = (p.potential - r[0])
        .norm()
        .max((p.gradient[0] - r[1]).norm())
        .max((p.gradient[1] - r[2]).norm());
    eprintln!("near the bottom: {error:e}");
    assert!(error < 1e-13, "{error}");
}
