//! Tests of the point Green function (Schilder et al., eq. 11, gradient, harmonicity, free-surface
//! conditions, radiation, reciprocity, frequency limits) and timings.

use super::exp_integral::EULER_GAMMA;
use super::test_support::{all_surfaces, c, wave};
use super::*;

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

/// Schilder et al., eq. 11 literally, with F = e^z E1(z) from `scaled_exp_integral`.
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
            let f = |dx: f64, dy: f64| g.value_and_gradient([centre[0] + dx, centre[1] + dy], x0).0;
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

#[test]
fn prepared_pairs_match_pair_by_pair() {
    // A semicircle of 24 panels with a lid of 6 and Gauss points on three panels: the prepared
    // pairs (shared Q per argument up to conjugation, per-point exponentials, the series in h)
    // against the pair-by-pair integrals (measured: 5.6e-16 of 1 + |value| in the potential,
    // 2.6e-15 in the gradient: rounding), at wavenumbers from the series' reach of every
    // argument to beyond the far series' limit (k L/2 > 4), and at the two limits.
    let n = 24;
    let node = |j: usize| {
        let t = PI * j as f64 / n as f64;
        [-(t.cos()), -(t.sin())]
    };
    let mut panels: Vec<(Point, Point)> = (0..n).map(|j| (node(j), node(j + 1))).collect();
    panels.extend((0..6).map(|j| {
        let x = |j: usize| 1.0 - 2.0 * j as f64 / 6.0;
        ([x(j), 0.0], [x(j + 1), 0.0])
    }));
    let centre = |(a, b): (Point, Point)| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    let mut fields: Vec<Point> = panels.iter().map(|&p| centre(p)).collect();
    for &(a, b) in &panels[..3] {
        fields
            .extend([0.1, 0.5, 0.93].map(|u| [a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])]));
    }
    let list: Vec<(Point, Point, Point)> = fields
        .iter()
        .flat_map(|&x| panels.iter().map(move |&(a, b)| (x, a, b)))
        .collect();
    let pairs = PanelPairs::new(list.iter().copied());
    assert_eq!(pairs.len(), list.len());
    let mut values = Vec::new();
    let mut surfaces = vec![
        GreenFunction::new(FreeSurface::RigidLid).unwrap(),
        GreenFunction::new(FreeSurface::Dirichlet).unwrap(),
    ];
    surfaces.extend([1e-3, 0.05, 0.7, 3.0, 12.0, 40.0].map(wave));
    let (mut worst, mut worst_gradient): (f64, f64) = (0.0, 0.0);
    for g in surfaces {
        g.panel_integrals_beyond_dirichlet(&pairs, &mut values);
        assert_eq!(values.len(), list.len());
        for (&(x, a, b), prepared) in list.iter().zip(&values) {
            let direct = g.panel_integral_beyond_dirichlet(x, a, b);
            let scale = direct.potential.norm() + 1.0;
            worst = worst.max((prepared.potential - direct.potential).norm() / scale);
            assert!(
                (prepared.potential - direct.potential).norm() <= 2e-15 * scale,
                "{:?}, x = {x:?}: {} vs {}",
                g.surface(),
                prepared.potential,
                direct.potential
            );
            for i in 0..2 {
                if direct.gradient[i].is_finite() {
                    let scale = direct.gradient[i].norm() + 1.0;
                    worst_gradient = worst_gradient
                        .max((prepared.gradient[i] - direct.gradient[i]).norm() / scale);
                    assert!(
                        (prepared.gradient[i] - direct.gradient[i]).norm() <= 1e-14 * scale,
                        "{:?}, x = {x:?}, gradient {i}: {} vs {}",
                        g.surface(),
                        prepared.gradient[i],
                        direct.gradient[i]
                    );
                }
            }
        }
    }
    assert!(
        worst > 0.0,
        "the prepared path should round differently somewhere"
    );
}
