use super::*;
use std::f64::consts::PI;

/// An asymmetric five-point section with roll about (0.3, -0.4) and one elastic mode.
const ASYMMETRIC: &str = r#"<hull name="asym" half_beam="2" units="m" version="1">
  <contour closed="false">
    <point x="-2" y="0"/>
    <point x="-1.6" y="-1.2"/>
    <point x="0.2" y="-1.7"/>
    <point x="2.1" y="-0.9"/>
    <point x="2.4" y="0"/>
  </contour>
  <rigid name="sway" kind="sway"/>
  <rigid name="heave" kind="heave"/>
  <rigid name="roll" kind="roll" x="0.3" y="-0.4"/>
  <mode name="panel">
    <u x="0" y="0.1"/>
    <u x="0.2" y="0.3"/>
    <u x="-0.1" y="1"/>
    <u x="-0.3" y="0.2"/>
    <u x="0" y="-0.1"/>
  </mode>
</hull>"#;

fn asymmetric() -> Hull {
    Hull::from_xml_str(ASYMMETRIC, "asym.xml").unwrap()
}

/// The contour's vertices as a polygon (an arc sampled at `m` points).
fn polygon(hull: &Hull, m: usize) -> Vec<[f64; 2]> {
    let mut s: Vec<f64> = if is_arc(hull) {
        (0..=m).map(|k| k as f64 / m as f64).collect()
    } else {
        hull.breakpoints()
    };
    if hull.is_closed() {
        s.pop();
    }
    s.iter().map(|&s| hull.point(s)).collect()
}

/// Area and first moments of the part of a closed polygon below y = 0 (Sutherland-Hodgman).
fn submerged(points: &[[f64; 2]]) -> (f64, f64, f64) {
    let mut clipped = Vec::new();
    for k in 0..points.len() {
        let (a, b) = (points[k], points[(k + 1) % points.len()]);
        if a[1] <= 0.0 {
            clipped.push(a);
        }
        if (a[1] < 0.0) != (b[1] < 0.0) && a[1] != b[1] {
            let t = a[1] / (a[1] - b[1]);
            clipped.push([a[0] + t * (b[0] - a[0]), 0.0]);
        }
    }
    let (mut area2, mut mx, mut my) = (0.0, 0.0, 0.0);
    for k in 0..clipped.len() {
        let (a, b) = (clipped[k], clipped[(k + 1) % clipped.len()]);
        let cross = a[0] * b[1] - b[0] * a[1];
        area2 += cross;
        mx += (a[0] + b[0]) * cross;
        my += (a[1] + b[1]) * cross;
    }
    (area2 / 2.0, mx / 6.0, my / 6.0)
}

/// Buoyancy per rho g of the body moved rigidly: (vertical force, moment about `centre`),
/// after a heave `h` and a rotation `theta` about `centre` (which moves with the heave).
fn buoyancy(points: &[[f64; 2]], h: f64, theta: f64, centre: [f64; 2]) -> (f64, f64) {
    let (sn, cs) = theta.sin_cos();
    let moved: Vec<[f64; 2]> = points
        .iter()
        .map(|p| {
            let (dx, dy) = (p[0] - centre[0], p[1] - centre[1]);
            [
                centre[0] + cs * dx - sn * dy,
                centre[1] + sn * dx + cs * dy + h,
            ]
        })
        .collect();
    let (area, mx, _) = submerged(&moved);
    (area, mx - area * centre[0])
}

#[test]
fn semicircle_closed_forms() {
    let radius = 1.5;
    let hull = Hull::semicircle(radius).unwrap();
    let h = stiffness(&hull).unwrap();
    let c = &h.stiffness_per_rho_g;
    let tolerance = 1e-12 * radius.powi(3);
    assert!((h.waterline_breadth - 2.0 * radius).abs() < tolerance);
    assert!((h.submerged_area - PI * radius * radius / 2.0).abs() < tolerance);
    assert!(h.centre_of_buoyancy[0].abs() < tolerance);
    assert!((h.centre_of_buoyancy[1] + 4.0 * radius / (3.0 * PI)).abs() < tolerance);
    // sway, heave, roll about the origin: rho g diag(0, 2R, 0); roll's buoyancy part
    // I_wp + A z_B = 2R^3/3 - 2R^3/3 vanishes (the metacentre is the centre).
    for i in 0..3 {
        for j in 0..3 {
            let expected = if (i, j) == (1, 1) { 2.0 * radius } else { 0.0 };
            assert!(
                (c[(i, j)] - expected).abs() < tolerance,
                "{i} {j}: {}",
                c[(i, j)]
            );
        }
    }
    assert!((h.stiffness(1025.0, 9.81)[(1, 1)] - 1025.0 * 9.81 * 3.0).abs() < 1e-9);
}

#[test]
fn rigid_closed_forms_match_finite_differences_of_the_true_motion() {
    // A fine polygon of the semicircle, the asymmetric section, and a submerged circle.
    let cases = [
        (Hull::semicircle(1.0).unwrap(), 20_000),
        (asymmetric(), 0),
        (Hull::circle(1.0, 2.0).unwrap(), 20_000),
    ];
    for (hull, samples) in cases {
        let h = stiffness(&hull).unwrap();
        let c = &h.stiffness_per_rho_g;
        let mut points = polygon(&hull, samples);
        if !hull.is_closed() {
            // Close the open contour above the water so tilting keeps the body whole.
            let (first, last) = (points[0], *points.last().unwrap());
            points.push([last[0], 1.0]);
            points.push([first[0], 1.0]);
        }
        let Some(DofKind::Rigid { reference, .. }) = hull.dof_kind(2) else {
            panic!("roll is DOF 2");
        };
        let step = 1e-6;
        let (f_up, m_up) = buoyancy(&points, step, 0.0, reference);
        let (f_down, m_down) = buoyancy(&points, -step, 0.0, reference);
        let (f_ccw, m_ccw) = buoyancy(&points, 0.0, step, reference);
        let (f_cw, m_cw) = buoyancy(&points, 0.0, -step, reference);
        // Restoring = -d(force or moment)/d(coordinate).
        let heave_heave = -(f_up - f_down) / (2.0 * step);
        let roll_heave = -(m_up - m_down) / (2.0 * step);
        let heave_roll = -(f_ccw - f_cw) / (2.0 * step);
        let roll_roll = -(m_ccw - m_cw) / (2.0 * step);
        // Central differences of exact polygon integrals: error ~ 1e-12 / step.
        let tolerance = 1e-6 * h.waterline_breadth.max(1.0).powi(3);
        for (name, fd, closed) in [
            ("heave-heave", heave_heave, c[(1, 1)]),
            ("roll-heave", roll_heave, c[(2, 1)]),
            ("heave-roll", heave_roll, c[(1, 2)]),
            ("roll-roll", roll_roll, c[(2, 2)]),
        ] {
            // The polygon of the arcs differs from the arc by ~ (pi/20000)^2.
            assert!(
                (fd - closed).abs() < tolerance + 1e-7,
                "{} {name}: finite difference {fd}, closed form {closed}",
                hull.name()
            );
        }
    }
}

#[test]
fn the_pressure_formula_on_rigid_fields_gives_the_closed_forms_but_for_the_initial_stress() {
    for hull in [
        asymmetric(),
        Hull::semicircle(1.3).unwrap(),
        Hull::circle(1.0, 1.5).unwrap(),
    ] {
        let h = stiffness(&hull).unwrap();
        let c = &h.stiffness_per_rho_g;
        let Some(DofKind::Rigid { reference, .. }) = hull.dof_kind(2) else {
            panic!("roll is DOF 2");
        };
        let scale = h.submerged_area * hull.reference_half_beam();
        for i in 0..3 {
            for j in 0..3 {
                let linear = pressure_stiffness(&hull, i, j);
                // Only roll-roll carries the static load's work through the rotation's
                // second-order displacement: rho g A (3 y_B - y_c).
                let initial_stress = if (i, j) == (2, 2) {
                    h.submerged_area * (3.0 * h.centre_of_buoyancy[1] - reference[1])
                } else {
                    0.0
                };
                assert!(
                    (linear + initial_stress - c[(i, j)]).abs() < 1e-10 * scale,
                    "{} ({i}, {j}): linear {linear}, closed {}",
                    hull.name(),
                    c[(i, j)]
                );
            }
        }
    }
}

/// Generalized force per rho g on DOF `i` when the contour of a polyline hull moves by
/// `q u_j`: exact integrals of the clipped pressure `max(0, -y)` over the moved segments.
fn generalized_force(hull: &Hull, i: usize, j: usize, q: f64) -> f64 {
    let knots = hull.breakpoints();
    let mut total = 0.0;
    for w in knots.windows(2) {
        let (sa, sb) = (w[0], w[1]);
        let moved = |s: f64| {
            let (x, u) = (hull.point(s), hull.displacement(j, s));
            [x[0] + q * u[0], x[1] + q * u[1]]
        };
        let (a, b) = (moved(sa), moved(sb));
        let d = [b[0] - a[0], b[1] - a[1]];
        // n ds = R90 dx along the moved segment.
        let normal_length = [-d[1], d[0]];
        // Split where the moved segment crosses y = 0; Gauss on each wetted part.
        let mut cuts = vec![0.0, 1.0];
        if (a[1] < 0.0) != (b[1] < 0.0) && a[1] != b[1] {
            cuts.insert(1, a[1] / (a[1] - b[1]));
        }
        for c in cuts.windows(2) {
            for (t, weight) in GAUSS {
                let r = c[0] + 0.5 * (c[1] - c[0]) * (1.0 + t);
                let y = a[1] + r * d[1];
                let pressure = (-y).max(0.0);
                let ui = hull.displacement(i, sa + r * (sb - sa));
                let work = normal_length[0] * ui[0] + normal_length[1] * ui[1];
                total += pressure * work * 0.5 * (c[1] - c[0]) * weight;
            }
        }
    }
    total
}

#[test]
fn the_pressure_stiffness_matches_finite_differences_of_the_displaced_contour() {
    for hull in [
        asymmetric(),
        Hull::from_file(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/hulls/midship.xml"
        )))
        .unwrap(),
    ] {
        let h = stiffness(&hull).unwrap();
        let n = hull.dof_count();
        let elastic: Vec<usize> = (0..n)
            .filter(|&j| matches!(hull.dof_kind(j), Some(DofKind::Elastic)))
            .collect();
        assert!(!elastic.is_empty());
        let q = 1e-6;
        let scale = h.waterline_breadth.powi(2);
        for &j in &elastic {
            for i in 0..n {
                let fd = -(generalized_force(&hull, i, j, q) - generalized_force(&hull, i, j, -q))
                    / (2.0 * q);
                let computed = h.stiffness_per_rho_g[(i, j)];
                // The waterline's second-order term leaves an O(q) error.
                assert!(
                    (fd - computed).abs() < 1e-5 * scale,
                    "{} ({i}, {j}): finite difference {fd}, formula {computed}",
                    hull.name()
                );
            }
        }
    }
}

#[test]
fn craig_bampton_modes_excited_by_rigid_end_values_give_the_rigid_pressure_stiffness() {
    let radius = 2.0;
    let hull = Hull::semicircle(radius).unwrap();
    let h = stiffness(&hull).unwrap();
    let c = &h.stiffness_per_rho_g;
    // Weights of cb1..cb6 (DOFs 3..8) reproducing sway, heave, roll (their end values).
    let weights = [
        [1.0, 0.0, 0.0, -1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0, 0.0, 1.0, 0.0],
        [0.0, radius, 1.0, 0.0, radius, 1.0],
    ];
    for a in 0..3 {
        for b in 0..3 {
            let mut combined = 0.0;
            for (k, wa) in weights[a].iter().enumerate() {
                for (l, wb) in weights[b].iter().enumerate() {
                    combined += wa * wb * c[(3 + k, 3 + l)];
                }
            }
            let rigid_field = pressure_stiffness(&hull, a, b);
            assert!(
                (combined - rigid_field).abs() < 1e-9 * radius.powi(3),
                "({a}, {b}): modes {combined}, rigid field {rigid_field}"
            );
        }
    }
    // Sway and heave need nothing from the structure: the modes give the closed forms.
    for (a, b) in [(0, 0), (1, 1), (0, 1), (1, 0)] {
        assert!((pressure_stiffness(&hull, a, b) - c[(a, b)]).abs() < 1e-10);
    }
}

#[test]
fn a_submerged_circle_has_no_waterplane() {
    let hull = Hull::circle(1.0, 2.0).unwrap();
    let h = stiffness(&hull).unwrap();
    assert_eq!(h.waterline_breadth, 0.0);
    assert!((h.submerged_area - PI).abs() < 1e-12);
    assert!((h.centre_of_buoyancy[1] + 2.0).abs() < 1e-12);
    let c = &h.stiffness_per_rho_g;
    // Roll about the origin, above the centre: rho g A (y_B - 0) = -2 pi rho g.
    assert!((c[(2, 2)] + 2.0 * PI).abs() < 1e-10, "{}", c[(2, 2)]);
    assert!(c[(1, 1)].abs() < 1e-12 && c[(1, 2)].abs() < 1e-12);
}
