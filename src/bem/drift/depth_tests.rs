//! Tests of the far field and the mean drift in finite depth: energy, the damping against
//! the radiated waves' flux at the finite-depth group velocity, near field against far field
//! (Maruo with the factor `1 + G`), the deep-water limit, a wall to near the bottom against the
//! standing wave's drift, and a moving section's two drifts. Semicircle of radius 1 m, 128
//! panels, 3 levels unless named.

use super::super::*;
use crate::hull::Hull;
use crate::units::WaterDepth;

/// Wave frequencies `nu R` of the checks, long to short waves.
const KR: [f64; 6] = [0.02, 0.1, 0.5, 1.0, 2.0, 5.0];

/// Water depths over the radius of the checks.
const DEPTHS: [f64; 3] = [1.5, 3.0, 10.0];

use super::tests::solve_in as solve;

/// The propagating wavenumber of `nu` in depth `h`.
fn wavenumber(nu: f64, h: f64) -> f64 {
    crate::green::finite_depth::wavenumber(nu, h).unwrap()
}

/// `G = 2kh / sinh 2kh`.
fn shallowness(kh: f64) -> f64 {
    2.0 * kh / (2.0 * kh).sinh()
}

#[test]
fn energy_damping_and_the_two_drifts_agree_in_finite_depth() {
    // One set of solves (h/R 1.5, 3, 10; kR 0.02 .. 5) for three identities:
    // - a fixed, lossless section: |R|^2 + |T|^2 = 1 (measured: 8.0e-5 at most);
    // - -Im A~_jj / rho = tanh(kh) (1 + G) (|K_j(+1)|^2 + |K_j(-1)|^2) / 2, the far field's
    //   rows nu K_j, relative to the DOF's largest damping over the band (measured: 9.8e-5,
    //   sway at kR 5, h/R 3; as in deep water);
    // - pressure integration against Maruo's c (1 + G)(1 + |R|^2 - |T|^2) / 4, per rho g a^2
    //   (up to (1 + G) / 2 <= 1; measured: 5.3e-4, as in deep water).
    let hull = Hull::semicircle(1.0).unwrap();
    let (mut energy, mut flux, mut methods) = (0.0f64, 0.0f64, 0.0f64);
    for h in DEPTHS {
        let solutions: Vec<_> = KR
            .iter()
            .map(|&kr| solve(&hull, 1.0, 128, kr, WaterDepth::Finite(h)))
            .collect();
        for j in 0..2 {
            let damping = |s: &RadiationSolution| -s.added_mass[(j, j)].im;
            let scale = solutions
                .iter()
                .map(|(s, _)| damping(s))
                .fold(0.0, f64::max);
            for ((s, d), nu) in solutions.iter().zip(KR) {
                let kh = wavenumber(nu, h) * h;
                let radiated = kh.tanh()
                    * (1.0 + shallowness(kh))
                    * (d.far_field[(j, 0)].norm_sqr() + d.far_field[(j, 1)].norm_sqr())
                    / (2.0 * nu * nu);
                flux = flux.max((radiated - damping(s)).abs() / scale);
            }
        }
        for ((_, d), nu) in solutions.iter().zip(KR) {
            let kh = wavenumber(nu, h) * h;
            assert!((d.momentum_factor - 1.0 - shallowness(kh)).abs() <= 1e-12);
            for heading in 0..2 {
                let (r, t) = (d.reflection(heading), d.transmission(heading));
                energy = energy.max((r.norm_sqr() + t.norm_sqr() - 1.0).abs());
                let near = d.horizontal_near_field(heading);
                methods = methods.max((near - d.horizontal_far_field(heading)).abs());
            }
        }
    }
    assert!(energy <= 4e-4, "energy: {energy:e}");
    assert!(flux <= 4e-4, "damping against the radiated flux: {flux:e}");
    assert!(
        methods <= 1.5e-3,
        "near field against far field: {methods:e}"
    );
}

#[test]
fn the_drift_tends_to_deep_water_in_deep_water() {
    // h/R = 1e3 (kh >= 100): the far field, the fixed section's drift and the moving
    // section's forms (scale 0.5 .. 1) against deep water. Measured: 3.6e-7, 9.1e-7, 1.3e-6
    // (the bottom's 1 / (nu h)^2 through the near field, docs/FINITE_DEPTH.md).
    let hull = Hull::semicircle(1.0).unwrap();
    for kr in [0.1, 1.0, 3.0] {
        let (_, deep) = solve(&hull, 1.0, 64, kr, WaterDepth::Infinite);
        let (_, finite) = solve(&hull, 1.0, 64, kr, WaterDepth::Finite(1e3));
        let largest = |m: DMatrix<Complex64>| m.iter().map(|z| z.norm()).fold(0.0, f64::max);
        let far = largest(&deep.far_field - &finite.far_field);
        let near = (&deep.near_field - &finite.near_field).amax();
        let forms = deep.motion_forms[0]
            .iter()
            .zip(&finite.motion_forms[0])
            .map(|(a, b)| largest(a - b))
            .fold(0.0, f64::max);
        assert!(
            far <= 5e-6 && near <= 5e-6 && forms <= 1e-5,
            "kR {kr}: {far:e} {near:e} {forms:e}"
        );
        assert!((finite.momentum_factor - 1.0).abs() <= 1e-12);
    }
}

#[test]
fn a_wall_to_near_the_bottom_feels_the_standing_wave_drift() {
    // A box of half-beam 1 m and draft 2.9 m in 3 m of water reflects nearly all: the
    // standing wave at a wall, psi = 2 cosh k(y + h) / cosh kh, gives D = (1 + G) / 2 per
    // rho g a^2 (the waterline's 1 less (1 - G) / 2 of the velocity squared). The gap under
    // the box lets |T|^2 through (measured: 2.5e-3 at kR 0.3, 1.7e-4 at 0.6, below 2e-6 from
    // kR 1), which takes (1 + G) |T|^2 / 2 off. Measured against (1 + G)(1 - |T|^2) / 2: far
    // field within 1.2e-5, pressure integration within 5.3e-4 (kR 2).
    let text = r#"<hull name="wall" half_beam="1"><contour closed="false">
        <point x="-1" y="0"/><point x="-1" y="-2.9"/><point x="1" y="-2.9"/>
        <point x="1" y="0"/></contour><rigid name="sway" kind="sway"/></hull>"#;
    let hull = Hull::from_xml_str(text, "wall.xml").unwrap();
    for kr in [0.3, 0.6, 1.0, 2.0] {
        let (_, d) = solve(&hull, 1.0, 128, kr, WaterDepth::Finite(3.0));
        let kh = wavenumber(kr, 3.0) * 3.0;
        let wall = (1.0 + shallowness(kh)) / 2.0;
        let transmitted = d.transmission(0).norm_sqr();
        assert!(transmitted <= 5e-3, "kR {kr}: |T|^2 {transmitted}");
        let expected = wall * (1.0 - transmitted);
        let (near, far) = (d.horizontal_near_field(0), d.horizontal_far_field(0));
        assert!(
            (far - expected).abs() <= 1e-4,
            "kR {kr}: far {far}, {expected}"
        );
        assert!(
            (near - expected).abs() <= 1e-3,
            "kR {kr}: near {near}, {expected}"
        );
    }
}

#[test]
fn a_moving_section_s_two_drifts_agree_in_the_flume_s_depth() {
    // The Sundsdal section (R = 0.2 m) in the flume's 1.0 m of water, imposed sway, heave and
    // roll together, per rho g a^2 (the largest drift about 1), worst over kR 0.1, 0.5, 2.
    // Measured: 3.3e-3 on 128 panels, 1.3e-4 on 512 (deep water: 4.8e-3 and 1.5e-4).
    let text = include_str!("../../../examples/hulls/sundsdal_floating.xml");
    let hull = Hull::from_xml_str(text, "sundsdal_floating.xml").unwrap();
    let xi: Vec<Complex64> = [(0.3, 0.2), (-0.4, 0.1), (0.5, -1.5)]
        .iter()
        .map(|&(re, im)| Complex64::new(re, im))
        .collect();
    let worst = |panels: usize| {
        let mut worst = 0.0f64;
        for kr in [0.1, 0.5, 2.0] {
            let (_, d) = solve(&hull, 0.2, panels, kr, WaterDepth::Finite(1.0));
            for h in 0..2 {
                let near = d.near_field_moving(h, &xi);
                let far = d.horizontal_far_field_moving(h, &xi);
                worst = worst.max((near[3] - far).abs());
            }
        }
        worst
    };
    let (coarse, fine) = (worst(128), worst(512));
    assert!(coarse <= 5e-3, "{coarse:e}");
    assert!(fine <= 2e-4, "{fine:e}");
}
