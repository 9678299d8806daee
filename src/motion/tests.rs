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

/// The semicircle of radius 1 m floating freely: the displaced mass, G 0.2 m below the
/// waterline (metacentric height 0.2 m), radius of gyration 0.3 m.
fn free_semicircle() -> (Hull, Floating) {
    let hull = Hull::semicircle(1.0).unwrap();
    let statics = hydrostatics::stiffness(&hull).unwrap();
    let properties = MassProperties {
        mass: RHO * statics.submerged_area,
        centre_of_gravity: [0.0, -0.2],
        radius_of_gyration: 0.3,
        stiffness: DMatrix::zeros(0, 0),
        damping: DMatrix::zeros(0, 0),
    };
    let floating = Floating::new(&hull, &statics, &properties, RHO, G).unwrap();
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
    let heave = hull.select_dofs(&["sway", "heave"]).unwrap();
    let statics = hydrostatics::stiffness(&heave).unwrap();
    let properties = MassProperties {
        mass: RHO * statics.submerged_area,
        centre_of_gravity: [0.0, -0.2],
        radius_of_gyration: 0.3,
        stiffness: DMatrix::zeros(0, 0),
        damping: DMatrix::zeros(0, 0),
    };
    let unrolled = Floating::new(&heave, &statics, &properties, RHO, G).unwrap();
    let e = unrolled.with_viscous_roll(params, 0.1).unwrap_err();
    assert!(e.to_string().contains("needs a rigid roll DOF"), "{e}");
    let e = floating.with_viscous_roll(params, -0.1).unwrap_err();
    assert!(e.to_string().contains("phi_a"), "{e}");
}
