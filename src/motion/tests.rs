//! Tests of the floating section's motion: long-wave limits, energy of a free section, a
//! stiff mooring recovering the fixed section, and refused input.

use super::*;
use crate::bem::{Drift, IrregularFrequencies};
use crate::green::FreeSurface;
use crate::hydrostatics;
use crate::panels::PanelParams;
use crate::sweep::Solver;

const RHO: f64 = 1025.0;
const G: f64 = 9.81;

/// `hull` (half-beam 1 m) floating freely: the displaced mass, G 0.2 m below the waterline,
/// radius of gyration 0.3 m.
fn floating_freely(hull: &Hull) -> Floating {
    let statics = hydrostatics::stiffness(hull).unwrap();
    let properties = MassProperties {
        mass: RHO * statics.submerged_area,
        centre_of_gravity: [0.0, -0.2],
        radius_of_gyration: 0.3,
        stiffness: DMatrix::zeros(0, 0),
        damping: DMatrix::zeros(0, 0),
    };
    Floating::new(hull, &statics, &properties, RHO, G).unwrap()
}

/// The semicircle of radius 1 m floating freely (metacentric height 0.2 m).
fn free_semicircle() -> (Hull, Floating) {
    let hull = Hull::semicircle(1.0).unwrap();
    let floating = floating_freely(&hull);
    (hull, floating)
}

/// Added mass per rho, exciting force per rho g a (one column per heading) and drift at `kr`
/// (R = 1 m).
fn solve(hull: &Hull, kr: f64) -> (DMatrix<Complex64>, Vec<Vec<Complex64>>, Drift) {
    let solver = Solver::new(hull, &PanelParams::default(), 3).unwrap();
    let solution = solver
        .solve(
            FreeSurface::Wave { wavenumber: kr },
            IrregularFrequencies::RemoveWithLid,
        )
        .unwrap();
    let forces = solution.wave_forces.unwrap();
    let excitation = (0..forces.direct.ncols())
        .map(|h| forces.direct.column(h).iter().copied().collect())
        .collect();
    (solution.added_mass, excitation, forces.drift.unwrap())
}

#[test]
fn long_waves_carry_a_free_section_with_the_water() {
    // omega -> 0: heave follows the elevation (1), sway the orbit (|1|), roll the slope (k).
    // Measured at kR 0.01: 3.4e-5, 7.4e-3 and 8.7e-4 relative.
    let (hull, floating) = free_semicircle();
    let kr = 0.01;
    let (added, excitation, _) = solve(&hull, kr);
    let xi = floating
        .rao((kr * G).sqrt(), G, &added, &excitation[0])
        .unwrap();
    assert!((xi[1].norm() - 1.0).abs() <= 1e-4, "heave {}", xi[1]);
    assert!((xi[0].norm() - 1.0).abs() <= 2e-2, "sway {}", xi[0]);
    assert!((xi[2].norm() / kr - 1.0).abs() <= 3e-3, "roll {}", xi[2]);
    assert!(xi.iter().skip(3).all(|z| *z == Complex64::new(0.0, 0.0)));
}

#[test]
fn a_free_section_without_losses_conserves_wave_energy() {
    // |R|^2 + |T|^2 = 1 with the waves the motion radiates. Measured: 1.6e-4 (kR 2, near
    // the roll resonance, roll 4 rad per m of amplitude), below 7e-6 elsewhere.
    let (hull, floating) = free_semicircle();
    for kr in [0.1, 0.3, 0.5, 1.0, 2.0, 5.0] {
        let (added, excitation, drift) = solve(&hull, kr);
        for (h, force) in excitation.iter().enumerate() {
            let xi = floating.rao((kr * G).sqrt(), G, &added, force).unwrap();
            let xi: Vec<Complex64> = xi.iter().copied().collect();
            let (r, t) = drift.coefficients_moving(h, &xi);
            let energy = r.norm_sqr() + t.norm_sqr() - 1.0;
            assert!(energy.abs() <= 5e-4, "kR {kr}, heading {h}: {energy:e}");
            let floating_drift = drift.horizontal_far_field_moving(h, &xi).abs();
            assert!(floating_drift <= 0.5, "kR {kr}: {floating_drift}");
        }
    }
}

#[test]
fn a_stiff_mooring_holds_the_section_fixed() {
    let hull = Hull::semicircle(1.0).unwrap();
    let statics = hydrostatics::stiffness(&hull).unwrap();
    let properties = MassProperties {
        mass: 1000.0,
        centre_of_gravity: [0.0, -0.3],
        radius_of_gyration: 0.4,
        stiffness: DMatrix::identity(3, 3) * 1e15,
        damping: DMatrix::zeros(3, 3),
    };
    let floating = Floating::new(&hull, &statics, &properties, RHO, G).unwrap();
    let (added, excitation, drift) = solve(&hull, 1.0);
    let xi: Vec<Complex64> = floating
        .rao(G.sqrt(), G, &added, &excitation[0])
        .unwrap()
        .iter()
        .copied()
        .collect();
    assert!(xi.iter().all(|z| z.norm() <= 1e-10));
    let (fixed, moored) = (
        drift.horizontal_far_field(0),
        drift.horizontal_far_field_moving(0, &xi),
    );
    assert!((fixed - moored).abs() <= 1e-9, "{fixed} {moored}");
    // Every row of the pressure integration too (motion 1e-11 per m of amplitude).
    let near = drift.near_field_moving(0, &xi);
    for (j, value) in near.iter().enumerate() {
        let fixed = drift.near_field[(j, 0)];
        assert!((value - fixed).abs() <= 1e-9, "row {j}: {value} {fixed}");
    }
}

#[test]
fn bad_mass_properties_are_refused_by_name() {
    let hull = Hull::semicircle(1.0).unwrap();
    let statics = hydrostatics::stiffness(&hull).unwrap();
    let good = MassProperties {
        mass: 1610.0,
        centre_of_gravity: [0.0, -0.2],
        radius_of_gyration: 0.3,
        stiffness: DMatrix::zeros(0, 0),
        damping: DMatrix::zeros(0, 0),
    };
    let cases: Vec<(MassProperties, &str)> = vec![
        (
            MassProperties {
                mass: -1.0,
                ..good.clone()
            },
            "mass",
        ),
        (
            MassProperties {
                mass: f64::NAN,
                ..good.clone()
            },
            "mass",
        ),
        (
            MassProperties {
                radius_of_gyration: f64::INFINITY,
                ..good.clone()
            },
            "radius_of_gyration",
        ),
        (
            MassProperties {
                centre_of_gravity: [0.0, -1e6],
                ..good.clone()
            },
            "y_G",
        ),
        (
            MassProperties {
                stiffness: DMatrix::zeros(2, 2),
                ..good.clone()
            },
            "stiffness is 2x2",
        ),
        (
            MassProperties {
                damping: DMatrix::from_element(3, 3, f64::NAN),
                ..good.clone()
            },
            "damping has an entry that is not finite",
        ),
    ];
    for (properties, expected) in cases {
        let error = Floating::new(&hull, &statics, &properties, RHO, G).unwrap_err();
        assert!(error.to_string().contains(expected), "{error}");
    }
    assert!(Floating::new(&hull, &statics, &good, RHO, G).is_ok());
}

/// The free semicircle's motion per unit amplitude (every DOF) and its drift at `kr`.
fn free_drift(kr: f64) -> (Vec<Vec<Complex64>>, Drift) {
    let (hull, floating) = free_semicircle();
    let (added, excitation, drift) = solve(&hull, kr);
    let motions = excitation
        .iter()
        .map(|force| {
            let xi = floating.rao((kr * G).sqrt(), G, &added, force).unwrap();
            xi.iter().copied().collect()
        })
        .collect();
    (motions, drift)
}

#[test]
fn a_free_section_s_horizontal_drift_by_pressure_equals_its_far_field() {
    // Per rho g a^2; the floating drift reaches 0.49 (kR 1.5 and 5) and falls to 0.04 at the
    // roll resonance (kR 2). Measured: 5.6e-4 (kR 5), 1.4e-4 (kR 2), below 1.2e-4 elsewhere.
    let mut worst = 0.0f64;
    for kr in [0.1, 0.3, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0] {
        let (motions, drift) = free_drift(kr);
        for (h, xi) in motions.iter().enumerate() {
            let near = drift.near_field_moving(h, xi);
            let far = drift.horizontal_far_field_moving(h, xi);
            worst = worst.max((near[near.len() - 1] - far).abs());
        }
    }
    assert!(worst <= 7e-4, "{worst:e}");
}

#[test]
fn long_waves_give_a_free_section_the_lagrangian_mean_pressure() {
    // Riding a long wave, the section's contour feels the mean pressure of the water particles
    // it moves with, rho g k a^2 / 2 (the Eulerian -rho |grad phi|^2 / 4 plus the mean of
    // X . grad p, rho g k a^2), over its breadth 2R: heave drift kR per rho g a^2, sway and
    // roll 0. Measured: heave / kR 0.993 at kR 0.01 and 0.961 at 0.05; sway and roll at most
    // 2e-8 (kR 0.05).
    for (kr, low) in [(0.01, 0.99), (0.05, 0.955)] {
        let (motions, drift) = free_drift(kr);
        let near = drift.near_field_moving(0, &motions[0]);
        let ratio = near[1] / kr;
        assert!(ratio >= low && ratio < 1.0, "kR {kr}: {ratio}");
        assert!(near[0].abs() <= 1e-6 * kr && near[2].abs() <= 1e-6 * kr);
    }
}

#[test]
fn headings_0_and_180_mirror_the_floating_drift() {
    // The symmetric free semicircle: heave drift equal, sway and roll opposite, to rounding.
    for kr in [0.5, 2.0] {
        let (motions, drift) = free_drift(kr);
        let (a, b) = (
            drift.mean_drift_moving(0, &motions[0]),
            drift.mean_drift_moving(1, &motions[1]),
        );
        let scale = a.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for (j, sign) in [(0, -1.0), (1, 1.0), (2, -1.0)] {
            assert!(
                (a[j] - sign * b[j]).abs() <= 1e-12 * scale,
                "kR {kr} DOF {j}"
            );
        }
    }
}

/// `examples/hulls/sundsdal_floating.xml` with every length times `factor`.
fn sundsdal_scaled(factor: f64) -> Hull {
    let text = include_str!("../../examples/hulls/sundsdal_floating.xml");
    let mut out = String::new();
    let mut rest = text;
    // Scales the number after each length attribute, in order of appearance.
    let keys = ["half_beam=\"", "x=\"", "y=\""];
    while let Some((i, len)) = keys
        .iter()
        .filter_map(|k| rest.find(k).map(|i| (i, k.len())))
        .min()
    {
        let start = i + len;
        let end = start + rest[start..].find('"').unwrap();
        let value: f64 = rest[start..end].parse().unwrap();
        out.push_str(&rest[..start]);
        out.push_str(&(value * factor).to_string());
        rest = &rest[end..];
    }
    out.push_str(rest);
    Hull::from_xml_str(&out, "sundsdal_floating.xml").unwrap()
}

#[test]
fn the_motion_scales_with_the_section() {
    // The Sundsdal section (roll about G, coupled to sway) at 1x and 5x, at the same kR and
    // with its mass properties scaled: the same sway and heave per unit amplitude, and a roll
    // (rad per m) 5 times smaller. Measured: 3.6e-14 relative.
    let params = crate::sweep::SweepParams {
        kr: vec![0.5, 1.0, 2.0],
        ..crate::sweep::SweepParams::default()
    };
    let raos: Vec<Vec<DMatrix<Complex64>>> = [1.0, 5.0]
        .iter()
        .map(|&factor| {
            let hull = sundsdal_scaled(factor);
            let statics = hydrostatics::stiffness(&hull).unwrap();
            let properties = MassProperties {
                mass: RHO * statics.submerged_area,
                centre_of_gravity: [0.0, -0.094 * factor],
                radius_of_gyration: 0.144 * factor,
                stiffness: DMatrix::zeros(0, 0),
                damping: DMatrix::zeros(0, 0),
            };
            let floating = Floating::new(&hull, &statics, &properties, RHO, G).unwrap();
            let sweep = crate::sweep::run(&hull, &params, &|_, _| {}).unwrap();
            floating.sweep_raos(&sweep).unwrap()
        })
        .collect();
    let mut worst = 0.0f64;
    for (small, large) in raos[0].iter().zip(&raos[1]) {
        for h in 0..small.ncols() {
            for (j, factor) in [(0, 1.0), (1, 1.0), (2, 5.0)] {
                let (a, b) = (small[(j, h)], large[(j, h)] * factor);
                worst = worst.max((a - b).norm() / a.norm());
            }
        }
    }
    assert!(worst <= 1e-9, "{worst:e}");
}

#[test]
fn the_mass_matrix_is_symmetric_about_any_roll_reference() {
    // The Sundsdal section rolls about G = (0, -0.094): no sway-roll coupling by inertia, roll
    // inertia m k^2; about the origin instead, m (y_G - y_P) couples them both ways.
    let text = include_str!("../../examples/hulls/sundsdal_floating.xml");
    for (reference, coupling) in [("y=\"-0.094\"", 0.0), ("y=\"0\"", 0.094)] {
        let text = text.replace(
            r#"kind="roll" x="0" y="-0.094""#,
            &format!("kind=\"roll\" x=\"0\" {reference}"),
        );
        let hull = Hull::from_xml_str(&text, "sundsdal_floating.xml").unwrap();
        let statics = hydrostatics::stiffness(&hull).unwrap();
        let properties = MassProperties {
            mass: 81.86,
            centre_of_gravity: [0.0, -0.094],
            radius_of_gyration: 0.144,
            stiffness: DMatrix::zeros(0, 0),
            damping: DMatrix::zeros(0, 0),
        };
        let floating = Floating::new(&hull, &statics, &properties, RHO, G).unwrap();
        let mass = &floating.mass * RHO;
        assert_eq!(mass, mass.transpose());
        assert!((mass[(0, 2)] - 81.86 * coupling).abs() <= 1e-12, "{mass}");
        let roll = 81.86 * (0.144f64.powi(2) + coupling * coupling);
        assert!((mass[(2, 2)] - roll).abs() <= 1e-12, "{mass}");
    }
}

#[test]
fn viscous_roll_damping_is_added_at_every_frequency_and_lowers_the_roll() {
    let (hull, floating) = free_semicircle();
    let params = crate::viscous::roll_params(&hull, RHO).unwrap().params;
    let kr = 1.5;
    let omega = (kr * G).sqrt();
    let (added, excitation, _) = solve(&hull, kr);
    let plain = floating.rao(omega, G, &added, &excitation[0]).unwrap();
    let amplitude = 0.2;
    let damped = floating
        .clone()
        .with_viscous_roll(params, amplitude)
        .unwrap();
    let b_eq = damped.viscous_roll_damping(omega).unwrap().unwrap();
    let by_hand = crate::viscous::equivalent_roll_damping(&params, omega, amplitude).unwrap();
    assert_eq!(b_eq, by_hand);
    assert!(b_eq > 0.0);
    let rolled = damped.rao(omega, G, &added, &excitation[0]).unwrap();
    assert!(
        rolled[2].norm() < plain[2].norm(),
        "{} vs {}",
        rolled[2],
        plain[2]
    );
    // Zero amplitude: friction alone.
    let still = floating.clone().with_viscous_roll(params, 0.0).unwrap();
    let friction = crate::viscous::friction(&params, omega, 0.0).linear;
    assert_eq!(still.viscous_roll_damping(omega).unwrap(), Some(friction));
    assert_eq!(floating.viscous_roll_damping(omega).unwrap(), None);
    // A section without roll, and a refused amplitude, name the damping.
    let unrolled = floating_freely(&hull.select_dofs(&["sway", "heave"]).unwrap());
    let e = unrolled.with_viscous_roll(params, 0.1).unwrap_err();
    assert!(e.to_string().contains("needs a rigid roll DOF"), "{e}");
    let e = floating.with_viscous_roll(params, -0.1).unwrap_err();
    assert!(e.to_string().contains("phi_a"), "{e}");
}
