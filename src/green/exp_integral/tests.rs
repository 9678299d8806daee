//! Tests of the exponential integrals against adaptive quadrature, mpmath values and
//! identities.

use super::*;
use crate::green::test_support::{c, Quadrature};

/// `e^z E1(z) = int_0^inf e^{-u}/(z + u) du` along a ray rotated away from the pole -z
/// (for `Im z = -0.0` below the pole: the lower side of the cut).
fn scaled_e1_by_quadrature(quad: &Quadrature, z: Complex64) -> Complex64 {
    let alpha = if z.re > 0.0 && z.im.abs() < z.re {
        0.0
    } else if z.im.is_sign_negative() {
        -PI / 4.0
    } else {
        PI / 4.0
    };
    let dir = Complex64::from_polar(1.0, alpha);
    let r_max = 50.0 / alpha.cos();
    let f = |r: f64| [(-(r * dir)).exp() * dir / (z + r * dir)];
    let scale = (1.0 / z.norm()).min(1.0);
    quad.integrate(&f, 0.0, r_max, 1e-17 * scale)[0]
}

/// Test points z = rho e^{i theta} over the whole plane, many in the third quadrant.
fn e1_test_points() -> Vec<Complex64> {
    let radii = [
        1e-8, 1e-3, 0.1, 0.5, 1.0, 1.9, 2.1, 3.0, 4.5, 7.0, 12.0, 25.0, 39.0, 41.0, 80.0, 300.0,
        2e5,
    ];
    let angles = [
        -PI + 1e-9,
        -PI + 1e-3,
        -PI + 0.05,
        -PI + 0.3,
        -0.75 * PI,
        -0.6 * PI,
        -0.5 * PI,
        -0.3 * PI,
        0.0,
        0.25 * PI,
        0.5 * PI,
        0.8 * PI,
        PI - 1e-3,
    ];
    let mut pts = Vec::new();
    for &r in &radii {
        for &t in &angles {
            pts.push(Complex64::from_polar(r, t));
        }
        pts.push(c(-r, -0.0));
        pts.push(c(-r, 0.0));
        pts.push(c(0.0, -r));
    }
    pts
}

#[test]
fn scaled_exp_integral_matches_quadrature() {
    let quad = Quadrature::new();
    let mut worst: f64 = 0.0;
    for z in e1_test_points() {
        if z.norm() > 1e4 {
            continue; // quadrature range too short; covered by the asymptotic test
        }
        let f = scaled_exp_integral(z);
        let r = scaled_e1_by_quadrature(&quad, z);
        let err = (f - r).norm() / r.norm();
        worst = worst.max(err);
        // Third quadrant is what the panel method uses: near machine precision there.
        let tol = if z.re <= 0.0 && z.im <= 0.0 {
            2e-15
        } else {
            1e-14
        };
        assert!(err < tol, "z = {z}: {f} vs quadrature {r} (rel {err:e})");
    }
    assert!(worst > 0.0);
}

#[test]
fn scaled_exp_integral_matches_high_precision_values() {
    // mpmath 1.3 at 40 digits.
    let table = [
        ((1.0, 0.0), (0.596_347_362_323_194_1, 0.0)),
        (
            (-3.0, -0.0),
            (-0.494_576_401_348_641_2, 0.156_410_688_228_254_13),
        ),
        (
            (0.0, -3.0),
            (0.079_221_521_164_364_04, 0.291_957_710_692_078_76),
        ),
        (
            (-10.0, -2.0),
            (-0.107_071_757_402_005_63, 0.024_784_313_651_390_045),
        ),
        (
            (-0.5, -0.001),
            (-0.273_595_688_850_064_36, 1.903_746_813_913_421),
        ),
        (
            (-30.0, -1.0),
            (-0.034_485_832_885_438_425, 0.001_192_356_313_197_741_5),
        ),
        (
            (-25.0, -40.0),
            (-0.011_019_359_153_420_357, 0.018_382_462_309_309_6),
        ),
        (
            (-1e-6, -2e-6),
            (12.433_566_572_132_657, 2.034_415_034_224_708_5),
        ),
        (
            (5.0, 7.0),
            (0.069_707_655_944_815_69, -0.083_032_375_996_334_49),
        ),
        (
            (-60.0, -0.5),
            (-0.016_952_980_988_844_56, 0.000_143_756_517_087_626_58),
        ),
        (
            (-45.0, -0.0),
            (-0.022_739_607_254_528_28, 8.992867343418258e-20),
        ),
    ];
    for ((zr, zi), (fr, fi)) in table {
        let f = scaled_exp_integral(c(zr, zi));
        let r = c(fr, fi);
        assert!(
            (f - r).norm() <= 2e-15 * r.norm(),
            "z = ({zr}, {zi}): {f} vs {r}"
        );
    }
    // On the cut the imaginary part pi e^z is tiny but must still be right.
    let f = scaled_exp_integral(c(-45.0, -0.0));
    assert!((f.im - PI * (-45.0f64).exp()).abs() < 1e-14 * f.im);
}

/// Ei(x), x > 0, independently: positive power series, or the asymptotic series.
fn ei_real(x: f64) -> f64 {
    if x < 40.0 {
        let (mut term, mut sum) = (1.0, 0.0);
        for n in 1..400 {
            term *= x / n as f64;
            sum += term / n as f64;
            if term < 1e-18 * sum {
                break;
            }
        }
        EULER_GAMMA + x.ln() + sum
    } else {
        let (mut term, mut sum) = (1.0, 1.0);
        for n in 1..(x as usize) {
            term *= n as f64 / x;
            sum += term;
            if term < 1e-18 {
                break;
            }
        }
        x.exp() / x * sum
    }
}

#[test]
fn e1_on_the_negative_real_axis() {
    // E1(-x -+ i0) = -Ei(x) +- i pi (the sign of the zero picks the side).
    for x in [
        1e-6, 0.3, 1.0, 2.5, 7.0, 19.0, 33.0, 39.9, 40.1, 55.0, 120.0,
    ] {
        let ei = ei_real(x);
        for (side, im) in [(-0.0, PI), (0.0, -PI)] {
            let e1 = exp_integral_e1(c(-x, side));
            assert!(
                (e1.re + ei).abs() <= 2e-15 * ei.abs().max(1.0),
                "x = {x}: {} vs {}",
                e1.re,
                -ei
            );
            assert!((e1.im - im).abs() <= 1e-14 * PI, "x = {x}: Im {}", e1.im);
        }
    }
    // Principal branch continuity: just below the axis equals the -0.0 side.
    let below = exp_integral_e1(c(-3.0, -1e-12));
    let on = exp_integral_e1(c(-3.0, -0.0));
    assert!((below - on).norm() < 1e-10);
}

#[test]
fn exp_integral_conjugate_symmetry_and_known_e1() {
    for z in e1_test_points() {
        let f = scaled_exp_integral(z);
        let g = scaled_exp_integral(z.conj());
        assert!((f.conj() - g).norm() <= 1e-15 * f.norm(), "z = {z}");
    }
    // E1(1) = 0.21938393439552027368 (Abramowitz & Stegun table 5.1).
    let e1 = exp_integral_e1(c(1.0, 0.0));
    assert!((e1.re - 0.219_383_934_395_520_27).abs() < 5e-16 && e1.im == 0.0);
    // Small |z|: E1(z) = -gamma - ln z + z + O(z^2).
    let z = c(-1e-9, -2e-9);
    let e1 = exp_integral_e1(z);
    let approx = -EULER_GAMMA - z.ln() + z;
    assert!((e1 - approx).norm() < 1e-17 * 10.0 + 1e-15 * approx.norm());
    // Large |z|: e^z E1(z) ~ 1/z - 1/z^2 + 2/z^3.
    for z in [c(-3e5, -1.0), c(0.0, -1e6), c(2e5, 3e5)] {
        let w = z.inv();
        let approx = w * (1.0 - w * (1.0 - 2.0 * w));
        assert!((scaled_exp_integral(z) - approx).norm() < 1e-15 * approx.norm());
    }
}

#[test]
fn scaled_exp_integral_derivative_identity() {
    // d/dz [e^z E1(z)] = e^z E1(z) - 1/z, the derivative by the Cauchy integral on a
    // small circle (spectrally accurate): checks smoothness across method boundaries.
    let n = 48;
    for z in e1_test_points() {
        let dist = if z.re < 0.0 { z.im.abs() } else { z.norm() };
        if dist < 1e-6 || z.norm() > 1e4 {
            continue;
        }
        let r = 0.3 * dist.min(z.norm());
        let mut deriv = c(0.0, 0.0);
        let mut size: f64 = 0.0;
        for j in 0..n {
            let w = Complex64::from_polar(1.0, 2.0 * PI * j as f64 / n as f64);
            let f = scaled_exp_integral(z + r * w);
            size = size.max(f.norm());
            deriv += f / (r * w);
        }
        deriv /= n as f64;
        let expect = scaled_exp_integral(z) - z.inv();
        assert!(
            (deriv - expect).norm() <= 1e-13 * size / r,
            "z = {z}: {deriv} vs {expect}"
        );
    }
}

#[test]
fn series_and_continued_fraction_agree_in_overlap() {
    // Both methods at points where both converge (Re p >= 0, 2 < |p| < 40).
    for rho in [2.5f64, 4.0, 8.0, 15.0, 30.0] {
        for d in [3.0, 4.0, 5.0] {
            // |p| - Re p = d
            let re = rho - d;
            let im = (rho * rho - re * re).sqrt();
            let p = c(re, im);
            let series = Complex64::new(0.0, PI) * (-p).exp()
                - (-p).exp() * (p.ln() + EULER_GAMMA + ei_series_sum(p));
            let fraction = continued_fraction(-p);
            assert!(
                (series - fraction).norm() <= 5e-14 * fraction.norm(),
                "p = {p}: {series} vs {fraction}"
            );
        }
    }
}

#[test]
fn non_finite_and_zero_arguments_do_not_hang_or_panic() {
    assert!(scaled_exp_integral(c(f64::NAN, 0.0)).re.is_nan());
    assert!(scaled_exp_integral(c(f64::INFINITY, 1.0)).re.is_nan());
    assert_eq!(scaled_exp_integral(c(0.0, 0.0)).re, f64::INFINITY);
}
