//! `fmu-pack sweep SHIP.xml`: the whole-ship tables of docs/DESIGN.md ("Ships") and clear errors.

use std::path::PathBuf;

mod common;
use common::fmu_pack;

fn example(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/ships")
        .join(name)
        .display()
        .to_string()
}

/// The barge's table in SI: the header of docs/DESIGN.md, `A_inf` rows first, every entry of
/// every frequency, and the heave restoring `rho g L B` of the 100 m x 10 m waterplane.
#[test]
fn sweep_of_a_ship_file_writes_the_whole_ship_tables() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-ship-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let restoring = dir.join("c.csv");
    let excitation = dir.join("x.csv");
    let (ok, csv, err) = fmu_pack(&[
        "sweep",
        &example("barge.xml"),
        "--omega",
        "0.3:1.5:4",
        "--headings",
        "180,90",
        "--panels",
        "32",
        "--levels",
        "2",
        "--hydrostatics",
        restoring.to_str().unwrap(),
        "--excitation",
        excitation.to_str().unwrap(),
        "-o",
        "-",
    ]);
    assert!(ok, "{err}");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("# hull: barge"));
    assert_eq!(lines.next(), Some("# modes: sway heave roll pitch yaw vb1"));
    assert_eq!(lines.next(), Some("# convention: exp(+i omega t)"));
    assert_eq!(lines.next(), Some("# units: SI"));
    let rows: Vec<&str> = csv
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("omega"))
        .collect();
    assert_eq!(
        rows.len(),
        36 * 5,
        "A_inf and 4 frequencies of 6 x 6 entries"
    );
    assert!(rows[0].starts_with("inf,1,1,"));
    let heave: f64 = std::fs::read_to_string(&restoring)
        .unwrap()
        .lines()
        .find(|l| l.starts_with("2,2,"))
        .and_then(|l| l.rsplit(',').next()?.parse().ok())
        .unwrap();
    let expected = 1025.0 * 9.81 * 100.0 * 10.0;
    assert!((heave - expected).abs() < 1e-9 * expected, "{heave}");
    let forces = std::fs::read_to_string(&excitation).unwrap();
    assert!(forces.contains("omega,j,heading,re,im"));
    assert_eq!(
        forces
            .lines()
            .filter(|l| !l.starts_with(['#', 'o']))
            .count(),
        4 * 6 * 2
    );
    assert!(err.contains("11 stations, 1 distinct sections"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--dofs` keeps the ship DOFs named, in that order (the sections are solved whole).
#[test]
fn dofs_select_the_ship_dofs() {
    let (ok, csv, err) = fmu_pack(&[
        "sweep",
        &example("barge.xml"),
        "--dofs",
        "vb1,heave",
        "--omega",
        "0.5:1:2",
        "--panels",
        "32",
        "--levels",
        "1",
        "-o",
        "-",
    ]);
    assert!(ok, "{err}");
    assert!(csv.contains("# modes: vb1 heave\n"), "{csv}");
    assert_eq!(
        csv.lines().filter(|l| !l.starts_with(['#', 'o'])).count(),
        4 * 3
    );
}

#[test]
fn ship_errors_name_the_file_and_the_option() {
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        &example("barge.xml"),
        "--dofs",
        "heave,surge",
        "-o",
        "-",
    ]);
    assert!(
        !ok && err.contains("--dofs: 'surge' is not a DOF of ship 'barge'"),
        "{err}"
    );
    let (ok, _, err) = fmu_pack(&["sweep", &example("barge.xml"), "--depth", "2", "-o", "-"]);
    assert!(
        !ok && err.contains("--depth applies to a built-in circle"),
        "{err}"
    );
    let (ok, _, err) = fmu_pack(&["sweep", "semicircle", "--omega", "1:2:3", "-o", "-"]);
    assert!(
        !ok && err.contains("--omega and --headings apply to ship files"),
        "{err}"
    );
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        &example("barge.xml"),
        "--headings",
        "0,x",
        "-o",
        "-",
    ]);
    assert!(!ok && err.contains("--headings: 'x'"), "{err}");
    // One direction twice would make an archive that does not instantiate: no archive.
    let archive = std::env::temp_dir().join(format!("hydrofmu-360-{}.fmu", std::process::id()));
    let (ok, _, err) = fmu_pack(&[
        "pack",
        &example("barge.xml"),
        "--headings",
        "0,360",
        "-o",
        archive.to_str().unwrap(),
    ]);
    assert!(
        !ok && err.contains("headings 0 and 360 are the same direction"),
        "{err}"
    );
    assert!(!archive.exists());
}

/// `--drift`: the fixed ship's mean drift by strip theory, as a CSV (`sweep`) and as the
/// archive's drift table with its outputs (`pack`).
#[test]
fn a_ship_s_mean_drift_goes_to_its_table_and_its_archive() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-ship-drift-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let drift = dir.join("d.csv");
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        &example("barge.xml"),
        "--omega",
        "0.6:1.2:3",
        "--headings",
        "180,90",
        "--panels",
        "32",
        "--levels",
        "2",
        "--drift",
        drift.to_str().unwrap(),
        "-o",
        "-",
    ]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&drift).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("omega"))
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 3 * 6 * 2, "3 frequencies x 6 DOFs x 2 headings");
    // Beam seas push the barge towards +y; head seas not at all.
    for row in &rows {
        let (j, heading, value) = (row[1], row[2], row[3]);
        if j == 1.0 && heading == 90.0 {
            assert!(value > 0.0, "{row:?}");
        }
        if heading == 180.0 {
            assert_eq!(value, 0.0, "{row:?}");
        }
    }
    let binary = common::stand_in_binary(&dir);
    let archive = dir.join("Barge.fmu");
    let (ok, _, err) = fmu_pack(&[
        "pack",
        &example("barge.xml"),
        "--dofs",
        "sway,heave",
        "--headings",
        "90",
        "--panels",
        "32",
        "--levels",
        "2",
        "--drift",
        "--allow-tolerance-miss",
        "--binary",
        binary.to_str().unwrap(),
        "-o",
        archive.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let table = common::archive_member(&archive, "resources/drift.csv").unwrap();
    assert!(table.contains("\nkR,j,heading,value\n"), "{table}");
    let description = common::archive_member(&archive, "modelDescription.xml").unwrap();
    assert!(description.contains("name=\"wave.drift\""));
    assert!(description.contains("name=\"force_drift.sway\""));
    let _ = std::fs::remove_dir_all(&dir);
}
