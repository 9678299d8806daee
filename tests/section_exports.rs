//! A section's sweep exported per unit length (a 1 m slice) as WAMIT files and as a
//! Capytaine dataset, read back by our importer; the exported numbers against the semicircle's
//! exact limits and published values (tests/data/reference/README.md), reciprocity, damping and
//! the 2D Haskind energy relation.
//!
//! SI at rho = 1025 kg/m^3, g = 9.81 m/s^2, R = 1 m. The WAMIT files hold 10 significant
//! digits: read-back to 1e-9 of each entry's scale; the NetCDF file holds doubles: 1e-15.

use hydrofmu::database::import::{self, ImportParams};
use hydrofmu::database::section::{self, SectionDatabase};
use hydrofmu::database::Database;
use hydrofmu::hull::Hull;
use hydrofmu::sweep::{self, SweepParams, SweepResult};
use nalgebra::DMatrix;
use num_complex::Complex64;
use std::f64::consts::PI;
use std::path::PathBuf;

const RHO: f64 = 1025.0;
const G: f64 = 9.81;

/// A folder of its own per test (the tests of a binary run in parallel threads).
fn folder(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "hydrofmu-section-exports-{tag}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// kR = 0.25, 0.5, 1, 2, 4 at default panels.
fn sweep_of(hull: &Hull) -> SweepResult {
    let params = SweepParams {
        kr: sweep::log_grid(0.25, 4.0, 5).unwrap(),
        ..SweepParams::default()
    };
    sweep::run(hull, &params, &|_, _| {}).unwrap()
}

fn semicircle() -> (Hull, SweepResult, SectionDatabase) {
    let hull = Hull::semicircle(1.0).unwrap();
    let result = sweep_of(&hull);
    let section = SectionDatabase::from_sweep(&hull, &result, RHO, G).unwrap();
    (hull, result, section)
}

fn index(db: &Database, name: &str) -> usize {
    db.dof_names.iter().position(|d| d == name).unwrap()
}

/// The largest `|a_ij - b_ij| / sqrt(|b_ii b_jj|)` over the frequencies (entries of a DOF
/// with no added mass skipped), and of `A_inf`.
fn matrix_difference(a: &Database, b: &Database) -> f64 {
    let mut worst = 0.0f64;
    let complex = |m: &DMatrix<f64>| m.map(|x| Complex64::new(x, 0.0));
    let (a_inf, b_inf) = (complex(&a.added_mass_inf), complex(&b.added_mass_inf));
    let pairs = a
        .added_mass
        .iter()
        .zip(&b.added_mass)
        .chain(std::iter::once((&a_inf, &b_inf)));
    for (x, y) in pairs {
        for i in 0..x.nrows() {
            for j in 0..x.ncols() {
                let scale = (y[(i, i)].norm() * y[(j, j)].norm()).sqrt();
                if scale > 1e-8 * RHO {
                    worst = worst.max((x[(i, j)] - y[(i, j)]).norm() / scale);
                }
            }
        }
    }
    worst
}

/// The largest `|x_j - y_j|` relative to the largest `|y_j|` of the DOF (DOFs waves do not
/// excite skipped).
fn force_difference(a: &[DMatrix<Complex64>], b: &[DMatrix<Complex64>]) -> f64 {
    let rows = b[0].nrows();
    let largest: Vec<f64> = (0..rows)
        .map(|j| {
            b.iter()
                .flat_map(|m| m.row(j).iter().map(|z| z.norm()).collect::<Vec<_>>())
                .fold(0.0, f64::max)
        })
        .collect();
    let overall = largest.iter().copied().fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for (x, y) in a.iter().zip(b) {
        for (j, &scale) in largest.iter().enumerate() {
            if scale > 1e-8 * overall {
                for h in 0..y.ncols() {
                    worst = worst.max((x[(j, h)] - y[(j, h)]).norm() / scale);
                }
            }
        }
    }
    worst
}

/// `read` is `exported` to `tolerance`: names, frequencies, headings, every table.
fn assert_same(read: &Database, exported: &Database, tolerance: f64, what: &str) {
    assert_eq!(read.dof_names, exported.dof_names, "{what}");
    assert_eq!(read.headings, exported.headings, "{what}");
    assert_eq!(read.omega.len(), exported.omega.len(), "{what}");
    for (w, v) in read.omega.iter().zip(&exported.omega) {
        assert!((w - v).abs() <= tolerance * v, "{what}: omega {w} vs {v}");
    }
    assert_eq!(read.reference_length, 1.0, "{what}");
    let radiation = matrix_difference(read, exported);
    let force = force_difference(&read.excitation, &exported.excitation);
    let c = &exported.stiffness_hydrostatic;
    let c_scale = c.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let restoring = (&read.stiffness_hydrostatic - c).amax() / c_scale;
    eprintln!(
        "{what}: radiation {radiation:.1e}, excitation {force:.1e}, restoring {restoring:.1e}"
    );
    assert!(radiation <= tolerance, "{what}: radiation {radiation:e}");
    assert!(force <= tolerance, "{what}: excitation {force:e}");
    assert!(restoring <= tolerance, "{what}: restoring {restoring:e}");
    // Units of the rigid modes (generalized modes: WAMIT fixes no unit).
    for name in ["sway", "heave", "roll"] {
        let (i, j) = (index(read, name), index(exported, name));
        assert_eq!(read.dof_units[i], exported.dof_units[j], "{what}: {name}");
    }
}

#[test]
fn wamit_and_netcdf_exports_read_back_per_unit_length() {
    let (_, result, section) = semicircle();
    let exported = &section.database;
    assert_eq!(
        exported.dof_names,
        ["sway", "heave", "roll", "cb1", "cb2", "cb3", "cb4", "cb5", "cb6"]
    );
    assert_eq!(exported.headings, [-90.0, 90.0]);
    assert_eq!(exported.omega.len(), result.kr.len());
    let dir = folder("read-back");

    let files = section.wamit();
    for text in [
        &files.radiation,
        files.excitation.as_ref().unwrap(),
        &files.hydrostatics,
    ] {
        let header = text.lines().next().unwrap();
        assert!(header.contains("per unit length"), "{header}");
        assert!(
            header.contains("modes: 2=sway 3=heave 4=roll 7=cb1"),
            "{header}"
        );
    }
    std::fs::write(dir.join("semi.1"), &files.radiation).unwrap();
    std::fs::write(dir.join("semi.3"), files.excitation.as_ref().unwrap()).unwrap();
    std::fs::write(dir.join("semi.hst"), &files.hydrostatics).unwrap();
    let read = import::import(&dir.join("semi.1"), &ImportParams::new()).unwrap();
    assert!(read.failures.is_empty(), "{:?}", read.failures);
    // Ten significant digits in the file: measured 3.6e-10 of the entry scale.
    assert_same(&read, exported, 1e-9, "WAMIT");

    let nc = dir.join("semi.nc");
    section.write_netcdf(&nc).unwrap();
    let read = import::import(&nc, &ImportParams::new()).unwrap();
    assert!(read.failures.is_empty(), "{:?}", read.failures);
    // Doubles read back: measured 1.2e-16.
    assert_same(&read, exported, 1e-15, "NetCDF");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_export_is_the_sweep_in_si_with_beam_sea_headings() {
    let (hull, result, section) = semicircle();
    let db = &section.database;
    let scale = RHO * PI;
    let r = hull.reference_half_beam();
    for (k, kr) in result.kr.iter().enumerate() {
        let omega = (kr * G / r).sqrt();
        assert!((db.omega[k] - omega).abs() <= 1e-15 * omega);
        // Diagonals as swept; off-diagonals to the reciprocity the export makes exact.
        for i in 0..9 {
            let a = result.added_mass[k][(i, i)] * scale;
            assert!((db.added_mass[k][(i, i)] - a).norm() <= 1e-14 * a.norm());
            for j in 0..9 {
                let z = &db.added_mass[k];
                assert_eq!(z[(i, j)], z[(j, i)], "symmetric");
            }
        }
        // Beta = 90 - heading: 90 is heading 0 (waves towards +x = WAMIT +Y), -90 is 180.
        for (heading, column) in [(0, 1), (1, 0)] {
            for j in 0..9 {
                let e = i32::from(result.length_exponents[j]);
                let x = result.excitation[k].direct[(j, heading)] * RHO * G * r.powi(1 + e);
                assert!((db.excitation[k][(j, column)] - x).norm() <= 1e-15 * x.norm());
            }
        }
    }
    assert_eq!(section::wave_direction(0.0), 90.0);
    assert_eq!(section::wave_direction(180.0), -90.0);
}

#[test]
fn the_semicircle_s_exported_coefficients_have_their_known_values() {
    let (_, _, section) = semicircle();
    let db = &section.database;
    let (sway, heave) = (index(db, "sway"), index(db, "heave"));
    let unit = RHO * PI; // rho pi R^2 with R = 1 m, kg/m
                         // Exact limits: sway 2/pi^2 (measured error 1.4e-5), heave 1/2 (8.6e-6) of
                         // rho pi R^2; tolerances about three times the measured error.
    let inf = &db.added_mass_inf;
    assert!((inf[(sway, sway)] / unit - 2.0 / (PI * PI)).abs() < 4e-5);
    assert!((inf[(heave, heave)] / unit - 0.5).abs() < 2.5e-5);
    // Ursell's multipole values at kR = 0.5 (index 1) and 1 (index 2): a and b/omega.
    for (k, i, a, b_over_omega) in [
        (1, sway, 0.49664, 0.42561),
        (1, heave, 0.32232, 0.40575),
        (2, sway, 0.19089, 0.37360),
        (2, heave, 0.30249, 0.19817),
    ] {
        // Measured: a 3.2e-6 .. 1.3e-5, b/omega 1.1e-6 .. 2.5e-5 (the same solves as
        // tests/added_mass.rs).
        let z = db.added_mass[k][(i, i)] / unit;
        assert!((z.re - a).abs() < 4e-5, "a = {} vs {a}", z.re);
        assert!((-z.im - b_over_omega).abs() < 8e-5, "b/omega {}", -z.im);
    }
    let c = &db.stiffness_hydrostatic;
    // Heave restoring rho g B, B = 2 m; the long-wave heave force the same.
    assert!((c[(heave, heave)] - RHO * G * 2.0).abs() < 1e-9 * RHO * G);
    let long_wave = db.excitation_long_wave.as_ref().unwrap();
    assert!((long_wave[heave] - c[(heave, heave)]).abs() < 1e-6 * c[(heave, heave)]);
    for (k, omega) in db.omega.iter().enumerate() {
        let a = &db.added_mass[k];
        // Damping B = -omega Im A~: no negative eigenvalue (radiated energy) beyond 5e-4 of
        // the largest (measured: 1.5e-4 at kR = 4, below 1e-7 up to kR = 2).
        let b = a.map(|z| -z.im * omega);
        let eigen = b.clone().symmetric_eigen().eigenvalues;
        let largest = eigen.amax();
        assert!(eigen.min() >= -5e-4 * largest, "{omega}: {eigen}");
        // 2D Haskind on a symmetric section: |X_j|^2 = rho g^2 B_jj / omega per unit
        // amplitude, waves from either side (measured: below 4.3e-5 up to kR = 2, 9.5e-4 in
        // heave at kR = 4).
        for j in [sway, heave] {
            let expected = G * (RHO * b[(j, j)] / omega).sqrt();
            for h in 0..2 {
                let x = db.excitation[k][(j, h)].norm();
                assert!(
                    (x - expected).abs() < 2e-3 * expected,
                    "omega {omega} DOF {j}: |X| {x} vs {expected}"
                );
            }
        }
    }
}

#[test]
fn roll_keeps_its_sign_and_centre() {
    // A deep Lewis section, roll about the waterline: the bottom moves +x = WAMIT +Y in
    // positive roll (about +X, Y towards Z), so the sway-roll added mass is positive.
    let hull = Hull::lewis(2.0, 2.0, 0.9).unwrap();
    let result = sweep_of(&hull);
    let section = SectionDatabase::from_sweep(&hull, &result, RHO, G).unwrap();
    let db = &section.database;
    let (sway, roll) = (index(db, "sway"), index(db, "roll"));
    assert!(db.added_mass_inf[(sway, roll)] > 0.1 * db.added_mass_inf[(sway, sway)]);
    assert_eq!(section.roll_centre, Some([0.0, 0.0]));
    assert!(section.wamit().radiation.contains("(Y, Z) = (0, 0) m"));
}

#[test]
fn a_hull_file_with_elastic_modes_exports_them_as_generalized_modes() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/hulls/midship.xml");
    let hull = Hull::from_file(&path).unwrap();
    let result = sweep_of(&hull);
    let section = SectionDatabase::from_sweep(&hull, &result, RHO, G).unwrap();
    let files = section.wamit();
    let header = files.radiation.lines().next().unwrap();
    assert!(
        header.contains("roll about X through (Y, Z) = (0, -3) m"),
        "{header}"
    );
    assert!(
        header.contains("7=bottom_symmetric 8=bottom_antisymmetric 9=side_flexing"),
        "{header}"
    );
    let dir = folder("midship");
    std::fs::write(dir.join("midship.1"), &files.radiation).unwrap();
    std::fs::write(dir.join("midship.3"), files.excitation.unwrap()).unwrap();
    std::fs::write(dir.join("midship.hst"), &files.hydrostatics).unwrap();
    let read = import::import(&dir.join("midship.1"), &ImportParams::new()).unwrap();
    assert_same(&read, &section.database, 1e-9, "midship WAMIT");
    let _ = std::fs::remove_dir_all(&dir);
}
