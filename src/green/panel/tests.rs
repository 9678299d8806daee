//! Tests of the panel integrals against adaptive quadrature, across the near and far forms,
//! on the panel, on the free surface and for degenerate panels.

use super::*;
use crate::green::test_support::{all_surfaces, c, wave, Quadrature};
use crate::green::{FreeSurface, GreenFunction, PanelIntegral, Point};

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
                    scale +=
                        part.potential.norm() + part.gradient[0].norm() + part.gradient[1].norm();
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
                        let tol = 1e-14 * (whole.gradient[i].norm() + d.gradient[i].norm() + 1.0);
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
                        (far.q_integral - exact.q_integral).norm() <= tol * far.q_integral.norm()
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
                let tangential = |p: &PanelIntegral| p.gradient[0] * t[0] + p.gradient[1] * t[1];
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

#[test]
fn step_series_matches_the_recurrence() {
    // sum_m B_m two ways: the series in h from the prepared T_n(g), and the recurrence in m,
    // over |g| up to the far limit 1/4, all directions, and |h| up to the series' reach.
    let mut worst: f64 = 0.0;
    for g_abs in [1e-4, 0.01, 0.1, 0.249] {
        for g_angle in [0.0, 0.7, 1.6, 2.5, -1.1, -2.9] {
            let g = Complex64::from_polar(g_abs, g_angle);
            for h_abs in [1e-6, 1e-3, 0.05, 0.16] {
                let Some(terms) = step_series_terms(h_abs) else {
                    panic!("|h| = {h_abs} should be in reach of the series");
                };
                for h_angle in [0.3, -1.3, 2.2] {
                    let hh = Complex64::from_polar(h_abs, h_angle);
                    // FarGeometry for this g: only g enters both sums.
                    let far = FarGeometry {
                        centre_ray: hh / g,
                        ray_inverse: g / hh,
                        step: hh,
                        g,
                        log_sum: Complex64::new(0.0, 0.0),
                    };
                    let series = far.step_series()[..terms]
                        .iter()
                        .rev()
                        .fold(Complex64::new(0.0, 0.0), |acc, &c| acc * hh + c);
                    let w = far.ray_inverse; // 1/p_c at k = 1
                    let recurrence = far.b_sum_recurrence(hh, 1e-19 * w.norm());
                    // Relative to |1/p_c|, the scale the integrals compare B with (measured
                    // 1.4e-17: rounding).
                    let err = (series - recurrence).norm() / w.norm();
                    worst = worst.max(err);
                    assert!(
                        err <= 2e-16,
                        "g = {g}, h = {hh}: {series} vs {recurrence} ({err:e})"
                    );
                }
            }
        }
    }
    assert!(worst > 0.0);
    // Beyond its reach the recurrence serves.
    assert_eq!(step_series_terms(0.5), None);
    assert!(step_series_terms(1e-12).is_some_and(|n| n <= 2));
}
