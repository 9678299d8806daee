//! `--water-depth` for ship files and imported databases: the ship file's `depth` and the
//! flag that overrides it, the tables' and the archive's depth (the drift table's too), and
//! clear errors (a bad depth, a section reaching the bottom, a Capytaine dataset of another
//! depth).

use std::path::Path;

mod common;
use common::{fmu_pack, wamit_sphere as sphere};

/// A prismatic ship of semicircles (R = 1 m, keel 1 m below the surface) from x = -5 to 5 m,
/// with the root attributes `attributes`, written into `dir`.
fn ship_file(dir: &Path, attributes: &str) -> String {
    let path = dir.join("prism.xml");
    let text = format!(
        "<ship name=\"prism\"{attributes}>\n\
         <station x=\"-5\"><semicircle radius=\"1\"/></station>\n\
         <station x=\"5\"><semicircle radius=\"1\"/></station>\n</ship>\n"
    );
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

/// `fmu-pack sweep SHIP` on a small grid with `extra` options.
fn sweep(ship: &str, extra: &[&str]) -> (bool, String, String) {
    let mut args = vec![
        "sweep",
        ship,
        "--omega",
        "0.8:1.6:2",
        "--headings",
        "180",
        "--panels",
        "16",
        "--levels",
        "1",
        "--dofs",
        "heave,pitch",
        "-o",
        "-",
    ];
    args.extend_from_slice(extra);
    fmu_pack(&args)
}

/// The heave `A_inf` (SI) of a ship table.
fn heave_inf(table: &str) -> f64 {
    table
        .lines()
        .find(|l| l.starts_with("inf,1,1,"))
        .and_then(|l| l.split(',').nth(3)?.parse().ok())
        .unwrap_or_else(|| panic!("no heave A_inf in\n{table}"))
}

#[test]
fn the_flag_overrides_the_ship_files_depth_and_the_tables_carry_it() {
    let dir = common::folder("ship-depth-cli-tables");
    let ship = ship_file(&dir, " depth=\"6\"");
    let (ok, file_depth, err) = sweep(&ship, &[]);
    assert!(ok, "{err}");
    assert!(file_depth.contains("\n# depth: 6 m\n"), "{file_depth}");
    let (ok, shallow, err) = sweep(&ship, &["--water-depth", "1.5"]);
    assert!(ok, "{err}");
    assert!(shallow.contains("\n# depth: 1.5 m\n"), "{shallow}");
    let (ok, deep, err) = sweep(&ship, &["--water-depth", "inf"]);
    assert!(ok, "{err}");
    assert!(deep.contains("\n# depth: inf\n"), "{deep}");
    // The sections were solved in those depths: the bottom at h/R = 1.5 raises heave's A_inf
    // well above deep water's, at h/R = 6 a little.
    let (shallow, six, deep) = (
        heave_inf(&shallow),
        heave_inf(&file_depth),
        heave_inf(&deep),
    );
    assert!(shallow > 1.1 * deep, "{shallow} vs {deep}");
    assert!(six > deep && six < shallow, "{six}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_depths_a_keel_on_the_bottom_and_the_drift_are_refused_by_name() {
    let dir = common::folder("ship-depth-cli-errors");
    let ship = ship_file(&dir, "");
    for bad in ["0", "-2", "nan"] {
        let (ok, _, err) = sweep(&ship, &["--water-depth", bad]);
        assert!(!ok, "{bad}");
        assert!(
            err.contains("--water-depth") && err.contains("finite and > 0"),
            "{bad}: {err}"
        );
    }
    // The keel is at 1 m: 1.05 m works, 1 m is refused naming the first station.
    let (ok, table, err) = sweep(&ship, &["--water-depth", "1.05"]);
    assert!(ok && table.contains("\n# depth: 1.05 m\n"), "{err}");
    let (ok, _, err) = sweep(&ship, &["--water-depth", "1"]);
    assert!(!ok);
    assert!(
        err.contains("the section at x = -5 m") && err.contains("keel"),
        "{err}"
    );
    // The ship's drift in finite depth: a table with the depth's line and finite rows.
    let (ok, table, err) = sweep(&ship, &["--water-depth", "3", "--drift", "-"]);
    assert!(ok, "{err}");
    assert!(table.contains("\n# depth: 3 m\n"), "{table}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_ship_packed_in_finite_depth_meets_the_default_tolerance_and_declares_its_depth() {
    let dir = common::folder("ship-depth-cli-pack");
    let ship = ship_file(&dir, "");
    let archive = dir.join("prism.fmu");
    let (ok, out, err) = fmu_pack(&[
        "pack",
        &ship,
        "--dofs",
        "heave,pitch",
        "--headings",
        "180",
        "--panels",
        "32",
        "--levels",
        "2",
        "--water-depth",
        "3",
        "-o",
        archive.to_str().unwrap(),
    ]);
    // The default fit meets its tolerance in shallow water (its damping at zero frequency
    // carried by a slow pole; measured 0.63 %, 6 states): no --allow-tolerance-miss.
    assert!(ok, "{err}");
    assert!(out.contains("water depth      3 m"), "{out}");
    assert!(out.contains("(tolerance 1.00 %, met)"), "{out}");
    let (ok, inspected, err) = fmu_pack(&["inspect", archive.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(
        inspected.contains("water depth       3 m (the fixed parameter depth)"),
        "{inspected}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// WAMIT files do not state their depth: `--water-depth` gives it. A Capytaine dataset
/// states its own: the flag must agree with it.
#[test]
fn water_depth_states_a_wamit_databases_depth_and_must_agree_with_a_datasets() {
    let (ok, table, err) = fmu_pack(&["sweep", &sphere(), "--dofs", "heave", "-o", "-"]);
    assert!(ok, "{err}");
    assert!(table.contains("\n# depth: inf\n"), "{table}");
    let (ok, table, err) = fmu_pack(&[
        "sweep",
        &sphere(),
        "--dofs",
        "heave",
        "--water-depth",
        "50",
        "-o",
        "-",
    ]);
    assert!(ok, "{err}");
    assert!(table.contains("\n# depth: 50 m\n"), "{table}");
    let (ok, _, err) = fmu_pack(&["sweep", &sphere(), "--water-depth", "-1", "-o", "-"]);
    assert!(!ok && err.contains("--water-depth -1"), "{err}");
    // A section swept in 3 m of water, exported as a Capytaine dataset, keeps its depth.
    let dir = common::folder("ship-depth-cli-dataset");
    let dataset = dir.join("semi.nc");
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        "semicircle",
        "--panels",
        "16",
        "--levels",
        "1",
        "--kr",
        "0.2:2:5",
        "--water-depth",
        "3",
        "-o",
        dir.join("t.csv").to_str().unwrap(),
        "--netcdf",
        dataset.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let dataset = dataset.to_str().unwrap();
    let (ok, table, err) = fmu_pack(&["sweep", dataset, "-o", "-"]);
    assert!(ok, "{err}");
    assert!(table.contains("\n# depth: 3 m\n"), "{table}");
    let (ok, _, err) = fmu_pack(&["sweep", dataset, "--water-depth", "3", "-o", "-"]);
    assert!(ok, "{err}");
    let (ok, _, err) = fmu_pack(&["sweep", dataset, "--water-depth", "5", "-o", "-"]);
    assert!(!ok);
    assert!(
        err.contains("water_depth is 3 m but the depth given is 5 m"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
