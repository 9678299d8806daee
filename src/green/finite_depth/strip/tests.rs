//! Tests of the mesh-wide remainder and the limits: against the pair-by-pair panel integrals
//! and against direct image sums.

use super::*;
use crate::green::finite_depth::bottom_image_integral;
use crate::green::GreenFunction;

/// A ring of panels around a half-submerged section (clockwise in the fluid's sense), depth `h`.
fn section(h: f64, radius: f64, count: usize) -> (Vec<Point>, Vec<[Point; 2]>) {
    let node = |i: usize| {
        let t = PI * i as f64 / count as f64;
        [radius * t.cos(), -radius * t.sin().max(0.0) - 1e-3 * h]
    };
    let panels: Vec<[Point; 2]> = (0..count).map(|i| [node(i), node(i + 1)]).collect();
    let mut fields: Vec<Point> = panels
        .iter()
        .map(|[a, b]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])])
        .collect();
    fields.push([0.3 * radius, 0.0]);
    (fields, panels)
}

#[test]
fn separable_remainder_matches_the_pair_by_pair_panel_integrals() {
    // nu h from 0.02 to 40; the section from a third of the depth to a thousandth.
    for (nu, h, radius) in [
        (0.01, 2.0, 1.0),
        (0.5, 2.0, 1.0),
        (3.0, 2.0, 1.0),
        (10.0, 2.0, 1.0),
        (1.0, 1.3, 1.0),
        (0.7, 1000.0, 1.0),
    ] {
        let green = FiniteDepthGreen::new(nu, h).unwrap();
        let deep = GreenFunction::new(FreeSurface::Wave { wavenumber: nu }).unwrap();
        let (fields, panels) = section(h, radius, 12);
        let batch = green.remainder_integrals(&fields, &panels);
        let mut worst: f64 = 0.0;
        for (i, &field) in fields.iter().enumerate() {
            for (p, &[a, b]) in panels.iter().enumerate() {
                let full = green.panel_integral(field, a, b);
                let d = deep.panel_integral(field, a, b);
                let log = bottom_image_integral(h, field, a, b);
                let length = (b[0] - a[0]).hypot(b[1] - a[1]);
                let value = full.potential - d.potential - log.potential;
                let gradient = [0, 1].map(|c| full.gradient[c] - d.gradient[c] - log.gradient[c]);
                let scale = length * (1.0 + (full.potential.norm() / length));
                worst = worst.max((batch.value(i, p) - value).norm() / scale);
                for (batch, exact) in batch.gradient(i, p).iter().zip(gradient) {
                    worst = worst.max((batch - exact).norm() * h / scale);
                }
            }
        }
        // Measured at most 1.2e-10 (nu 10, h 2).
        assert!(worst < 2e-10, "nu {nu}, h {h}: {worst:e}");
    }
}

#[test]
fn rows_are_values_and_directional_derivatives_with_and_without_mirror_pairs() {
    let (nu, h) = (0.8, 2.0);
    let green = FiniteDepthGreen::new(nu, h).unwrap();
    let deep = GreenFunction::new(FreeSurface::Wave { wavenumber: nu }).unwrap();
    let (fields, panels) = section(h, 1.0, 12);
    let direction = [0.6, -0.8];
    let rows: Vec<RemainderRow> = fields
        .iter()
        .flat_map(|&point| {
            [None, Some(direction)].map(|direction| RemainderRow { point, direction })
        })
        .collect();
    // The whole symmetric section (mirror pairs of panels), and without its first panel.
    for panels in [&panels[..], &panels[1..]] {
        let matrix = green.remainder_rows(&rows, panels);
        let mut worst: f64 = 0.0;
        for (r, row) in rows.iter().enumerate() {
            for (p, &[a, b]) in panels.iter().enumerate() {
                let full = green.panel_integral(row.point, a, b);
                let d = deep.panel_integral(row.point, a, b);
                let log = bottom_image_integral(h, row.point, a, b);
                let length = (b[0] - a[0]).hypot(b[1] - a[1]);
                let exact = match row.direction {
                    None => full.potential - d.potential - log.potential,
                    Some([nx, ny]) => {
                        let g = [0, 1].map(|c| full.gradient[c] - d.gradient[c] - log.gradient[c]);
                        (g[0] * nx + g[1] * ny) * h
                    }
                };
                let got = matrix.get(r, p) * if row.direction.is_some() { h } else { 1.0 };
                let scale = length * (1.0 + (full.potential.norm() / length));
                worst = worst.max((got - exact).norm() / scale);
            }
        }
        assert!(worst < 2e-10, "{} panels: {worst:e}", panels.len());
    }
}

/// `(1/2pi) sum sign ln|z - image|` over the images of the strip, `2 n` periods each way,
/// less the nearest three: the limit remainder by brute force.
fn image_sum(surface: FreeSurface, h: f64, field: Point, source: Point, n: i32) -> [f64; 3] {
    let z = Complex64::new(field[0], field[1]);
    let mut sum = [0.0; 3];
    let mut add = |sign: f64, at: Complex64| {
        let d = z - at;
        sum[0] += sign * d.norm().ln();
        sum[1] += sign * d.re / d.norm_sqr();
        sum[2] += sign * d.im / d.norm_sqr();
    };
    for j in -n..=n {
        let shift = Complex64::new(0.0, 2.0 * h * f64::from(j));
        let sign = match surface {
            FreeSurface::Dirichlet if j % 2 != 0 => -1.0,
            _ => 1.0,
        };
        let image_sign = if surface == FreeSurface::Dirichlet {
            -sign
        } else {
            sign
        };
        let direct = Complex64::new(source[0], source[1]) + shift;
        let image = Complex64::new(source[0], -source[1]) + shift;
        if j != 0 {
            add(sign, direct);
        }
        if j != 0 && j != -1 {
            add(image_sign, image);
        }
    }
    sum.map(|s| s / (2.0 * PI))
}

#[test]
fn limit_remainders_are_the_image_sums() {
    let h = 1.7;
    for surface in [FreeSurface::Dirichlet, FreeSurface::RigidLid] {
        for (field, source) in [
            ([0.2, -0.3], [-0.1, -1.2]),
            ([0.0, 0.0], [0.5, -0.1]),
            ([1.0, -1.6], [-0.4, -1.65]),
        ] {
            let (value, gradient) = limit_remainder(surface, h, field, source);
            // The rigid lid's sum diverges like the channel's linear growth: compare
            // differences between two field points.
            // The truncated sums converge like 1/n: extrapolated from n and 2n.
            let brute = |p: Point| {
                let (a, b) = (
                    image_sum(surface, h, p, source, 4000),
                    image_sum(surface, h, p, source, 2000),
                );
                [0, 1, 2].map(|c| 2.0 * a[c] - b[c])
            };
            let shifted = [field[0] + 0.3, field[1] - 0.1];
            let (value_shifted, _) = limit_remainder(surface, h, shifted, source);
            let expected = brute(shifted)[0] - brute(field)[0];
            assert!(
                ((value_shifted - value) - expected).abs() < 1e-8,
                "{surface:?} {field:?}: {} against {expected}",
                value_shifted - value
            );
            let [sum, dx, dy] = brute(field);
            if surface == FreeSurface::Dirichlet {
                assert!((value - sum).abs() < 1e-8, "{field:?}");
            }
            assert!(
                (gradient[0] - dx).abs() < 1e-8,
                "{surface:?} d/dx {}",
                gradient[0] - dx
            );
            assert!(
                (gradient[1] - dy).abs() < 1e-8,
                "{surface:?} d/dy {}",
                gradient[1] - dy
            );
        }
    }
}

#[test]
fn limits_tend_to_deep_water() {
    // The remainder plus the bottom image vanishes as h -> inf.
    let h = 1e6;
    let (field, source) = ([0.3, -0.2], [-0.1, -0.7]);
    let (x, y) = (field[0] - source[0], field[1] + source[1] + 2.0 * h);
    let r2_sq = x * x + y * y;
    for surface in [FreeSurface::Dirichlet, FreeSurface::RigidLid] {
        let (value, gradient) = limit_remainder(surface, h, field, source);
        let value = value + r2_sq.ln() / (4.0 * PI);
        let gradient = [
            gradient[0] + x / (2.0 * PI * r2_sq),
            gradient[1] + y / (2.0 * PI * r2_sq),
        ];
        assert!(value.abs() < 1e-9, "{surface:?}: {value:e}");
        assert!(
            gradient.iter().all(|g| g.abs() < 1e-12),
            "{surface:?}: {gradient:?}"
        );
    }
}
