//! The floating section's tables: scale invariance, a stiff mooring recovering the fixed
//! section, the free section's energy and long-wave motion, refused input.

use crate::bem::HEADINGS;
use crate::hull::Hull;
use crate::hydrostatics;
use crate::motion::{Floating, MassProperties, MotionError};
use crate::panels::PanelParams;
use crate::sweep::{run, FloatingTableError, SweepParams, SweepResult};
use nalgebra::DMatrix;

const RHO: f64 = 1025.0;
const G: f64 = 9.81;

fn sweep(radius: f64, kr: Vec<f64>) -> (Hull, SweepResult) {
    let hull = Hull::semicircle(radius)
        .unwrap()
        .select_dofs(&["sway", "heave", "roll", "cb1"])
        .unwrap();
    let params = SweepParams {
        kr,
        panels: PanelParams {
            body_panels: 48,
            ..PanelParams::default()
        },
        ..SweepParams::default()
    };
    let result = run(&hull, &params, &|_, _| {}).unwrap();
    (hull, result)
}

/// Floating freely at radius R: the displaced mass, G at 0.2 R below the waterline, radius
/// of gyration 0.3 R; `mooring` the external stiffness over sway, heave, roll (SI).
fn floating(hull: &Hull, radius: f64, mooring: [f64; 3]) -> (Floating, MassProperties) {
    let statics = hydrostatics::stiffness(hull).unwrap();
    let properties = MassProperties {
        mass: RHO * statics.submerged_area,
        centre_of_gravity: [0.0, -0.2 * radius],
        radius_of_gyration: 0.3 * radius,
        stiffness: DMatrix::from_diagonal(&nalgebra::DVector::from_row_slice(&mooring)),
        damping: DMatrix::zeros(0, 0),
    };
    let floating = Floating::new(hull, &statics, &properties, RHO, G).unwrap();
    (floating, properties)
}

fn rows(text: &str, header: &str) -> Vec<Vec<f64>> {
    text.lines()
        .skip_while(|l| *l != header)
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

fn tables(hull: &Hull, result: &SweepResult, floating: &Floating, line: &str) -> (String, String) {
    let mut rao = Vec::new();
    result.write_rao_csv(floating, line, &mut rao).unwrap();
    let mut drift = Vec::new();
    result
        .write_floating_drift_csv(floating, line, &mut drift)
        .unwrap();
    assert_eq!(hull.dof_names(), result.dof_names);
    (
        String::from_utf8(rao).unwrap(),
        String::from_utf8(drift).unwrap(),
    )
}

#[test]
fn the_floating_tables_are_nondimensional() {
    // The same free section at R = 1 m and R = 50 m: the same values. Measured: 2e-12
    // relative; the bound allows the solver's rounding at another scale.
    let kr = vec![0.1, 0.8, 3.0];
    let table = |radius: f64| {
        let (hull, result) = sweep(radius, kr.clone());
        let (floating, properties) = floating(&hull, radius, [0.0; 3]);
        tables(&hull, &result, &floating, &properties.to_string())
    };
    let (rao_small, drift_small) = table(1.0);
    let (rao_large, drift_large) = table(50.0);
    assert!(
        rao_small.contains("\n# body: floating; mass "),
        "{rao_small}"
    );
    let (rao_small, rao_large) = (
        rows(&rao_small, "kR,j,heading,re,im"),
        rows(&rao_large, "kR,j,heading,re,im"),
    );
    // 3 frequencies x 2 headings x 3 rigid DOFs (cb1 is held).
    assert_eq!(rao_small.len(), 18);
    assert!(rao_small.iter().all(|r| r[1] <= 3.0));
    for (a, b) in rao_small.iter().zip(&rao_large) {
        for c in [3, 4] {
            let scale = a[3].hypot(a[4]).max(1e-3);
            assert!((a[c] - b[c]).abs() <= 1e-8 * scale, "{a:?} {b:?}");
        }
    }
    let (drift_small, drift_large) = (
        rows(&drift_small, "kR,j,heading,value"),
        rows(&drift_large, "kR,j,heading,value"),
    );
    // Every DOF, frequency and heading.
    assert_eq!(drift_small.len(), 24);
    for (a, b) in drift_small.iter().zip(&drift_large) {
        assert!(
            (a[3] - b[3]).abs() <= 1e-8 * a[3].abs().max(1e-3),
            "{a:?} {b:?}"
        );
    }
}

#[test]
fn a_stiff_mooring_holds_the_section_at_the_fixed_drift() {
    // Springs 1e6 times the heave restoring: the motion ~1e-6 of a free section's and the
    // drift the fixed section's. Measured: drift difference 3e-7 of rho g a^2.
    let kr = vec![0.3, 1.0, 2.0];
    let (hull, result) = sweep(1.0, kr);
    let stiff = 1e6 * RHO * G * 2.0;
    let (floating, properties) = floating(&hull, 1.0, [stiff, stiff, stiff]);
    let (rao, drift) = tables(&hull, &result, &floating, &properties.to_string());
    for row in rows(&rao, "kR,j,heading,re,im") {
        assert!(row[3].hypot(row[4]) <= 1e-5, "{row:?}");
    }
    let mut fixed = Vec::new();
    result.write_drift_csv(&mut fixed).unwrap();
    let fixed = rows(&String::from_utf8(fixed).unwrap(), "kR,j,heading,value");
    for row in rows(&drift, "kR,j,heading,value") {
        let same = fixed
            .iter()
            .find(|f| f[0] == row[0] && f[1] == row[1] && f[2] == row[2])
            .unwrap();
        assert!((row[3] - same[3]).abs() <= 1e-5, "{row:?} {same:?}");
    }
}

#[test]
fn a_free_section_conserves_energy_and_rides_long_waves() {
    // The header's energy defect is small (no external damping: nothing absorbs); in long
    // waves heave follows the elevation and the drift vanishes.
    let (hull, result) = sweep(1.0, vec![0.01, 0.5, 1.5]);
    let (floating, properties) = floating(&hull, 1.0, [0.0; 3]);
    let (rao, drift) = tables(&hull, &result, &floating, &properties.to_string());
    let energy: f64 = drift
        .lines()
        .find_map(|l| l.strip_prefix("# energy, |R|^2 + |T|^2 - 1 of the floating section"))
        .and_then(|l| l.rsplit(": ").next())
        .unwrap()
        .parse()
        .unwrap();
    let mut fixed = Vec::new();
    result.write_drift_csv(&mut fixed).unwrap();
    let fixed_energy: f64 = String::from_utf8(fixed)
        .unwrap()
        .lines()
        .find_map(|l| l.strip_prefix("# energy, |R|^2 + |T|^2 - 1 of the fixed section"))
        .and_then(|l| l.rsplit(": ").next())
        .unwrap()
        .parse()
        .unwrap();
    // Measured on 48 panels: 5.7e-4 floating, 2.9e-5 fixed: the motion amplifies the
    // radiated waves' error (src/motion/tests.rs: 1.6e-4 on 128 panels near roll resonance).
    assert!(energy <= 1e-3, "{energy}");
    assert!(fixed_energy <= 1e-4, "{fixed_energy}");
    let rao = rows(&rao, "kR,j,heading,re,im");
    let heave = rao
        .iter()
        .find(|r| r[0] == 0.01 && r[1] == 2.0 && r[2] == 0.0)
        .unwrap();
    assert!((heave[3].hypot(heave[4]) - 1.0).abs() <= 1e-3, "{heave:?}");
    let drift = rows(&drift, "kR,j,heading,value");
    // Sway vanishes; heave tends to kR (src/motion/tests.rs), roll and the held mode to 0.
    for row in drift.iter().filter(|r| r[0] == 0.01) {
        let bound = if row[1] == 2.0 { 0.011 } else { 1e-3 };
        assert!(row[3].abs() <= bound, "{row:?}");
    }
    // Waves towards +x push the free section towards +x, no harder than full reflection.
    for row in drift.iter().filter(|r| r[1] == 1.0 && r[2] == 0.0) {
        assert!(row[3] >= 0.0 && row[3] <= 0.5 + 1e-3, "{row:?}");
    }
}

#[test]
fn moorings_that_supply_energy_and_other_sweeps_are_refused() {
    let hull = Hull::semicircle(1.0).unwrap();
    let statics = hydrostatics::stiffness(&hull).unwrap();
    let base = MassProperties {
        mass: RHO * statics.submerged_area,
        centre_of_gravity: [0.0, -0.2],
        radius_of_gyration: 0.3,
        stiffness: DMatrix::zeros(0, 0),
        damping: DMatrix::zeros(0, 0),
    };
    let negative_spring = MassProperties {
        stiffness: DMatrix::from_diagonal(&nalgebra::DVector::from_row_slice(&[1.0, -2.0, 0.0])),
        ..base.clone()
    };
    let e = Floating::new(&hull, &statics, &negative_spring, RHO, G).unwrap_err();
    assert!(
        matches!(&e, MotionError::Field { field: "stiffness", reason } if reason.contains("at DOF 2")),
        "{e}"
    );
    // Positive diagonal, but the symmetric part has the eigenvalue 1 - 3 = -2.
    let feeding = MassProperties {
        damping: DMatrix::from_row_slice(3, 3, &[1.0, 3.0, 0.0, 3.0, 1.0, 0.0, 0.0, 0.0, 1.0]),
        ..base.clone()
    };
    let e = Floating::new(&hull, &statics, &feeding, RHO, G).unwrap_err();
    assert!(e.to_string().contains("negative eigenvalue -2e0"), "{e}");
    // The floating semicircle of 9 DOFs against a sweep of 4.
    let floating = Floating::new(&hull, &statics, &base, RHO, G).unwrap();
    let (_, result) = sweep(1.0, vec![1.0]);
    let e = result
        .write_rao_csv(&floating, "", &mut Vec::new())
        .unwrap_err();
    assert!(
        matches!(
            e,
            FloatingTableError::Motion(MotionError::OtherSweep {
                dofs: 4,
                expected: 9
            })
        ),
        "{e}"
    );
}

#[test]
fn the_swept_floating_drift_is_the_table_s_and_a_stiff_mooring_gives_the_fixed_one() {
    // Sway by the far field, the others by pressure integration: the table's values (R = 1);
    // under a stiff mooring the fixed section's drift in every row.
    let (hull, result) = sweep(1.0, vec![0.3, 1.0]);
    let (free, properties) = floating(&hull, 1.0, [0.0; 3]);
    let (_, table) = tables(&hull, &result, &free, &properties.to_string());
    let table = rows(&table, "kR,j,heading,value");
    let drift = free.sweep_drift(&result).unwrap();
    assert_eq!(drift.len(), 2);
    for (kr, values) in result.kr.iter().zip(&drift) {
        assert_eq!(values.shape(), (4, 2));
        for h in 0..2 {
            for j in 0..4 {
                let row = table
                    .iter()
                    .find(|r| r[0] == *kr && r[1] == (j + 1) as f64 && r[2] == HEADINGS[h])
                    .unwrap();
                assert!((values[(j, h)] - row[3]).abs() <= 1e-12, "{row:?}");
            }
        }
    }
    let stiff = 1e6 * RHO * G * 2.0;
    let (moored, _) = floating(&hull, 1.0, [stiff, stiff, stiff]);
    for (forces, values) in result
        .excitation
        .iter()
        .zip(moored.sweep_drift(&result).unwrap())
    {
        let fixed = forces.drift.as_ref().unwrap().mean_drift();
        let difference = (values - fixed).amax();
        // Measured: about 1e-7 (the motion ~1e-6 of a free section's).
        assert!(difference <= 1e-5, "{difference}");
    }
}
