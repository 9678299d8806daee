//! Craig-Bampton modes of the thin semicircular beam (seed paper, eqs. 4-6).
//!
//! w(theta) is the tangential displacement, positive towards increasing theta (unit vector
//! e_theta = (sin theta, -cos theta)); u = dw/dtheta is the radial displacement, positive
//! INWARD (unit vector (cos theta, sin theta)); psi = (w'' + w)/R is the slope. In-plane
//! equilibrium `w'''''' + 2 w'''' + w'' = 0` has the general solution
//!
//! w = C1 + C2 theta + C3 cos theta + C4 sin theta + C5 theta cos theta + C6 theta sin theta,
//!
//! and the displacement is d = u (cos theta, sin theta) + w (sin theta, -cos theta).
//! Mode `cbk` has unit value of the k-th of (u(0), w(0), psi(0), u(pi), w(pi), psi(pi)) and
//! zero for the others; the coefficients come from solving that 6x6 boundary system
//! ([`craig_bampton_coefficients`]). Rigid motions in terms of the modes (exact, tested):
//! sway = cb1 - cb4, heave = -cb2 + cb5, roll about the origin = R cb2 + cb3 + R cb5 + cb6.
//!
//! Table 1 of Schilder et al. does not match these directly: after theta -> -theta (negating
//! C2, C4, C5) its rows 1, 3, 4, 6 are -cb4, cb6, cb1, cb3 and its row 5 is cb5, while its
//! printed row 2 is exactly minus row 5, so the printed set has rank 5 and cannot be complete.
//! Row 5 with C3 = 1 added would be cb2; the test `seed_table_1_after_theta_flip` pins this.
//!
//! The built-in semicircle ([`Hull::semicircle`]) carries them as DOFs `cb1..cb6`.

#[cfg(doc)]
use super::Hull;
use super::Point;
use std::f64::consts::PI;

/// (w, u, psi) of the beam deflection with coefficients `c` = (C1..C6) at `theta`:
/// w from eq. 6, u = dw/dtheta, psi = (w'' + w)/R.
pub(crate) fn craig_bampton_fields(c: &[f64; 6], radius: f64, theta: f64) -> (f64, f64, f64) {
    let (s, co) = theta.sin_cos();
    let w = c[0] + c[1] * theta + c[2] * co + c[3] * s + theta * (c[4] * co + c[5] * s);
    let u = c[1] - c[2] * s + c[3] * co + c[4] * (co - theta * s) + c[5] * (s + theta * co);
    let psi = (c[0] + c[1] * theta - 2.0 * c[4] * s + 2.0 * c[5] * co) / radius;
    (w, u, psi)
}

/// Displacement vector of the beam deflection with coefficients `c` at `theta`:
/// u (cos theta, sin theta) + w (sin theta, -cos theta).
pub(crate) fn craig_bampton_displacement(c: &[f64; 6], radius: f64, theta: f64) -> Point {
    let (w, u, _) = craig_bampton_fields(c, radius, theta);
    let (s, co) = theta.sin_cos();
    [u * co + w * s, u * s - w * co]
}

/// Coefficients (C1..C6) of the six Craig-Bampton modes of the thin semicircular beam of
/// radius `radius`: row k-1 is mode `cbk`, the unit value of the k-th of
/// (u(0), w(0), psi(0), u(pi), w(pi), psi(pi)). Solved from the 6x6 boundary system by LU.
/// For a radius that is not positive and finite every entry is NaN.
pub(crate) fn craig_bampton_coefficients(radius: f64) -> [[f64; 6]; 6] {
    let nan = [[f64::NAN; 6]; 6];
    if !(radius.is_finite() && radius > 0.0) {
        return nan;
    }
    // Column i: end values of basis function i.
    let mut system = nalgebra::Matrix6::<f64>::zeros();
    for i in 0..6 {
        let mut unit = [0.0; 6];
        unit[i] = 1.0;
        for (end, theta) in [0.0, PI].into_iter().enumerate() {
            let (w, u, psi) = craig_bampton_fields(&unit, radius, theta);
            system[(3 * end, i)] = u;
            system[(3 * end + 1, i)] = w;
            system[(3 * end + 2, i)] = psi;
        }
    }
    let lu = system.lu();
    let mut modes = [[0.0; 6]; 6];
    for (k, mode) in modes.iter_mut().enumerate() {
        let mut rhs = nalgebra::Vector6::<f64>::zeros();
        rhs[k] = 1.0;
        match lu.solve(&rhs) {
            Some(c) => mode.iter_mut().zip(c.iter()).for_each(|(m, v)| *m = *v),
            None => return nan,
        }
    }
    modes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hull::Hull;

    fn close(a: Point, b: Point, tol: f64) -> bool {
        (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol
    }

    /// n-th theta-derivative of w from eq. 6, analytically.
    fn w_derivative(c: &[f64; 6], theta: f64, n: u32) -> f64 {
        let shifted = |k: u32| {
            let a = theta + f64::from(k) * std::f64::consts::FRAC_PI_2;
            (a.cos(), a.sin())
        };
        let (cn, sn) = shifted(n);
        let mut v = c[2] * cn + c[3] * sn + theta * (c[4] * cn + c[5] * sn);
        if n >= 1 {
            let (cm, sm) = shifted(n - 1);
            v += f64::from(n) * (c[4] * cm + c[5] * sm);
        }
        match n {
            0 => v + c[0] + c[1] * theta,
            1 => v + c[1],
            _ => v,
        }
    }

    fn end_values(c: &[f64; 6], radius: f64) -> [f64; 6] {
        let (w0, u0, p0) = craig_bampton_fields(c, radius, 0.0);
        let (w1, u1, p1) = craig_bampton_fields(c, radius, PI);
        [u0, w0, p0, u1, w1, p1]
    }

    #[test]
    fn craig_bampton_end_values_are_unit() {
        for radius in [1.0, 2.5, 40.0] {
            let modes = craig_bampton_coefficients(radius);
            for (k, c) in modes.iter().enumerate() {
                let ends = end_values(c, radius);
                for (j, v) in ends.iter().enumerate() {
                    let expected = if j == k { 1.0 } else { 0.0 };
                    // Round-off of a well-conditioned 6x6 solve.
                    assert!(
                        (v - expected).abs() < 1e-12,
                        "R {radius} mode {k} end {j}: {v}"
                    );
                }
            }
        }
        assert!(craig_bampton_coefficients(0.0)[0][0].is_nan());
        assert!(craig_bampton_coefficients(f64::NAN)[3][2].is_nan());
    }

    #[test]
    fn craig_bampton_modes_solve_the_beam_equation() {
        let radius = 1.7;
        for c in craig_bampton_coefficients(radius) {
            let scale = c.iter().map(|x| x.abs()).fold(1.0, f64::max);
            for i in 0..=40 {
                let theta = PI * f64::from(i) / 40.0;
                let residual = w_derivative(&c, theta, 6)
                    + 2.0 * w_derivative(&c, theta, 4)
                    + w_derivative(&c, theta, 2);
                assert!(residual.abs() < 1e-12 * scale, "eq. 4 residual {residual}");
                // u and psi against 6th-order central differences of w.
                let (w, u, psi) = craig_bampton_fields(&c, radius, theta);
                let h = 1e-3;
                let wf = |k: f64| craig_bampton_fields(&c, radius, theta + k * h).0;
                let d1 = (-wf(-3.0) + 9.0 * wf(-2.0) - 45.0 * wf(-1.0) + 45.0 * wf(1.0)
                    - 9.0 * wf(2.0)
                    + wf(3.0))
                    / (60.0 * h);
                let d2 = (2.0 * wf(-3.0) - 27.0 * wf(-2.0) + 270.0 * wf(-1.0) - 490.0 * w
                    + 270.0 * wf(1.0)
                    - 27.0 * wf(2.0)
                    + 2.0 * wf(3.0))
                    / (180.0 * h * h);
                // Truncation h^6 plus round-off ~1e-16 / h^2.
                assert!((u - d1).abs() < 1e-9 * scale, "u {u} vs {d1}");
                assert!((psi - (d2 + w) / radius).abs() < 1e-8 * scale, "psi");
                assert!((w - w_derivative(&c, theta, 0)).abs() < 1e-14 * scale);
                assert!((u - w_derivative(&c, theta, 1)).abs() < 1e-13 * scale);
            }
        }
    }

    #[test]
    fn craig_bampton_modes_reproduce_rigid_motions() {
        let radius = 2.0;
        let hull = Hull::semicircle(radius).unwrap();
        let cb = craig_bampton_coefficients(radius);
        // (rigid DOF index, weights of cb1..cb6)
        let cases = [
            (0, [1.0, 0.0, 0.0, -1.0, 0.0, 0.0]),
            (1, [0.0, -1.0, 0.0, 0.0, 1.0, 0.0]),
            (2, [0.0, radius, 1.0, 0.0, radius, 1.0]),
        ];
        for (dof, weights) in cases {
            // The weights are the rigid motion's own end values.
            let mut c = [0.0; 6];
            for (m, wgt) in cb.iter().zip(weights) {
                for (ci, mi) in c.iter_mut().zip(m) {
                    *ci += wgt * mi;
                }
            }
            let ends = end_values(&c, radius);
            assert!(ends.iter().zip(weights).all(|(a, b)| (a - b).abs() < 1e-12));
            for i in 0..=50 {
                let s = f64::from(i) / 50.0;
                let combined = craig_bampton_displacement(&c, radius, PI * s);
                let mut summed = [0.0; 2];
                for (k, wgt) in weights.iter().enumerate() {
                    let d = hull.displacement(3 + k, s);
                    summed = [summed[0] + wgt * d[0], summed[1] + wgt * d[1]];
                }
                let exact = hull.displacement(dof, s);
                assert!(close(combined, exact, 1e-12 * radius), "dof {dof} s {s}");
                assert!(close(summed, exact, 1e-12 * radius), "dof {dof} s {s}");
            }
        }
    }

    /// Seed Table 1, transcribed (R = 1.3), rows = modes 1..6, columns C1..C6.
    fn seed_table_1(r: f64) -> [[f64; 6]; 6] {
        let d = PI * PI - 8.0;
        [
            [-2.0 * PI / d, -4.0 / d, 2.0 * PI / d, 4.0 / d, 0.0, PI / d],
            [0.0, 0.0, 0.0, 1.0 / PI, -1.0 / PI, 0.0],
            [
                -4.0 * r / d,
                -PI * r / d,
                4.0 * r / d,
                2.0 * (PI * PI - 4.0) * r / (PI * d),
                -r / PI,
                2.0 * r / d,
            ],
            [
                2.0 * PI / d,
                4.0 / d,
                -2.0 * PI / d,
                (4.0 - PI * PI) / d,
                0.0,
                -PI / d,
            ],
            [0.0, 0.0, 0.0, -1.0 / PI, 1.0 / PI, 0.0],
            [
                (PI * PI - 4.0) * r / d,
                PI * r / d,
                -(PI * PI - 4.0) * r / d,
                -8.0 * r / (PI * d),
                -r / PI,
                -2.0 * r / d,
            ],
        ]
    }

    /// Finding: w_table(-theta) (C2, C4, C5 negated) gives rows 1..6 =
    /// (-cb4, -cb5, cb6, cb1, cb5, cb3): printed row 2 = -row 5, so cb2 is missing; row 5 with
    /// C3 = 1 added is cb2, giving the consistent pattern (-cb4, -cb5, cb6, cb1, cb2, cb3):
    /// the table's modes 1-3 sit at our theta = pi end, 4-6 at theta = 0.
    #[test]
    fn seed_table_1_after_theta_flip() {
        let r = 1.3;
        let table = seed_table_1(r);
        let cb = craig_bampton_coefficients(r);
        let flip = |c: [f64; 6]| [c[0], -c[1], c[2], -c[3], -c[4], c[5]];
        let same = |a: [f64; 6], sign: f64, b: [f64; 6]| {
            a.iter().zip(b).all(|(x, y)| (x - sign * y).abs() < 1e-12)
        };
        let expected = [(-1.0, 3), (-1.0, 4), (1.0, 5), (1.0, 0), (1.0, 4), (1.0, 2)];
        for (row, (sign, mode)) in expected.iter().enumerate() {
            assert!(
                same(flip(table[row]), *sign, cb[*mode]),
                "table row {} vs cb{}",
                row + 1,
                mode + 1
            );
        }
        // Without the flip, rows 1, 3, 4, 6 are none of our modes (either sign).
        for row in [0, 2, 3, 5] {
            let row = table[row];
            assert!(cb
                .iter()
                .all(|m| !same(row, 1.0, *m) && !same(row, -1.0, *m)));
        }
        // Printed rows 2 and 5 are negatives: the printed set has rank 5.
        assert!(same(table[1], -1.0, table[4]));
        let mut printed = nalgebra::Matrix6::<f64>::zeros();
        for (i, row) in table.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                printed[(i, j)] = *v;
            }
        }
        let singular = printed.singular_values();
        assert!(singular.min() < 1e-12 * singular.max());
        // Row 5 with C3 = 1 is our cb2 after the flip.
        let mut repaired = table[4];
        repaired[2] = 1.0;
        assert!(same(flip(repaired), 1.0, cb[1]));
    }
}
