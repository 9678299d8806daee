//! `fmu-pack sweep|fit|pack NAME.1`: imported WAMIT databases on the command line (the
//! checked-in WAMIT v7.2 hemisphere, tests/data/wamit/), and clear errors; a section's
//! `--wamit` and `--netcdf` exports per unit length, read back.

use std::path::{Path, PathBuf};

mod common;
use common::{fmu_pack, wamit_sphere as sphere};

#[test]
fn sweep_writes_the_whole_body_tables_of_the_database() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-database-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let excitation = dir.join("x.csv");
    let (ok, csv, err) = fmu_pack(&[
        "sweep",
        &sphere(),
        "--dofs",
        "surge,heave,pitch",
        "--excitation",
        excitation.to_str().unwrap(),
        "-o",
        "-",
    ]);
    assert!(ok, "{err}");
    assert!(csv.contains("# modes: surge heave pitch\n# convention: exp(+i omega t)\n# units: SI"));
    // 9 A_inf rows, then 9 per frequency, 7 frequencies.
    let rows: Vec<&str> = csv
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .collect();
    assert_eq!(rows.len(), 9 * 8);
    assert!(rows[..9].iter().all(|r| r.starts_with("inf,")));
    let x = std::fs::read_to_string(&excitation).unwrap();
    assert!(x.lines().any(|l| l.starts_with("omega,j,heading,re,im")));
    // One line on standard error says what was imported.
    assert!(
        err.contains("sphere: 3 DOFs (surge heave pitch), 7 frequencies"),
        "{err}"
    );
}

#[test]
fn fit_reports_and_draws_the_database() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-database-plots-{}", std::process::id()));
    let (ok, out, err) = fmu_pack(&[
        "fit",
        &sphere(),
        "--dofs",
        "heave",
        "--plots",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.starts_with("database sphere: 1 DOFs (heave)"), "{out}");
    assert!(out.contains("largest error"), "{out}");
    let figure = std::fs::read_to_string(dir.join("fit-heave-heave.svg")).unwrap();
    assert!(figure.contains("database and network") && figure.contains("omega (rad/s)"));
}

#[test]
fn mistakes_are_named() {
    let cases: [(&[&str], &str); 6] = [
        (
            &["sweep", "nowhere/box.1", "-o", "-"],
            "nowhere/box.1: cannot read the file: No such file",
        ),
        (
            &["sweep", &sphere(), "--panels", "64", "-o", "-"],
            "--panels does not apply to an imported database",
        ),
        (
            &["sweep", &sphere(), "--frequency-column", "kl", "-o", "-"],
            "--frequency-column 'kl': expected period, omega or hz",
        ),
        (
            &["sweep", &sphere(), "--length-scale=-2", "-o", "-"],
            "--length-scale -2: it must be finite and > 0 m",
        ),
        (
            &["sweep", &sphere(), "--dofs", "heave,wobble", "-o", "-"],
            "--dofs: 'wobble' is not a DOF",
        ),
        (
            &["sweep", "semicircle", "--length-scale", "2", "-o", "-"],
            "--length-scale applies to an imported database",
        ),
    ];
    for (args, expected) in cases {
        let (ok, _, err) = fmu_pack(args);
        assert!(!ok, "{args:?} succeeded");
        assert!(err.contains(expected), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}

#[test]
fn wamit_export_of_a_database_reads_back_to_the_same_table() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-database-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let prefix = dir.join("again");
    let (ok, first, err) = fmu_pack(&[
        "sweep",
        &sphere(),
        "--wamit",
        prefix.to_str().unwrap(),
        "-o",
        "-",
    ]);
    assert!(ok, "{err}");
    for ext in ["1", "3", "hst"] {
        assert!(dir.join(format!("again.{ext}")).is_file(), "again.{ext}");
    }
    let (ok, second, err) = fmu_pack(&["sweep", dir.join("again.1").to_str().unwrap(), "-o", "-"]);
    assert!(ok, "{err}");
    // Every number equal to the 10 digits written (the header names another source).
    let rows = |t: &str| -> Vec<Vec<f64>> {
        t.lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("omega"))
            .map(|l| {
                l.split(',')
                    .map(|x| {
                        if x == "inf" {
                            f64::INFINITY
                        } else {
                            x.parse().unwrap()
                        }
                    })
                    .collect()
            })
            .collect()
    };
    let (a, b) = (rows(&first), rows(&second));
    assert_eq!(a.len(), b.len());
    let scale = a
        .iter()
        .flat_map(|r| r[3..].iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    for (r, s) in a.iter().zip(&b) {
        for (x, y) in r.iter().zip(s) {
            assert!(
                x == y || (x - y).abs() <= 1e-9 * x.abs().max(1e-9 * scale),
                "{r:?} {s:?}"
            );
        }
    }
}

fn text(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The `omega = inf` row `i,j` of a table: its value.
fn inf_entry(table: &str, i: usize, j: usize) -> f64 {
    let prefix = format!("inf,{i},{j},");
    let row = table
        .lines()
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no {prefix} in\n{table}"));
    row.split(',').nth(3).unwrap().parse().unwrap()
}

#[test]
fn a_section_exports_per_unit_length_and_reads_back() {
    let dir = common::folder("database-cli-section-semicircle");
    let (prefix, nc, csv) = (dir.join("semi"), dir.join("semi.nc"), dir.join("t.csv"));
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        "semicircle",
        "--kr",
        "0.1:4:6",
        "-o",
        text(&csv),
        "--wamit",
        text(&prefix),
        "--netcdf",
        text(&nc),
    ]);
    assert!(ok, "{err}");
    assert!(!err.contains("applies to"), "{err}");
    for ext in ["1", "3", "hst"] {
        let file = dir.join(format!("semi.{ext}"));
        let first = std::fs::read_to_string(&file).unwrap();
        assert!(first.lines().next().unwrap().contains("per unit length"));
    }
    // The section's table: heave A_inf / (rho pi R^2) (R = 1 m); the read-back's in SI.
    let section = std::fs::read_to_string(&csv).unwrap();
    let heave = section
        .lines()
        .find(|l| l.starts_with("inf,2,2,"))
        .and_then(|l| l.split(',').nth(3))
        .unwrap()
        .parse::<f64>()
        .unwrap();
    assert!((heave - 0.5).abs() < 1e-3, "{heave}");
    for file in [dir.join("semi.1"), nc.clone()] {
        let (ok, table, err) = fmu_pack(&["sweep", text(&file), "-o", "-"]);
        assert!(ok, "{}: {err}", file.display());
        assert!(table.contains("# modes: sway heave roll cb1"), "{table}");
        let si = inf_entry(&table, 2, 2);
        let expected = heave * 1025.0 * std::f64::consts::PI;
        // The section table's 6 digits.
        assert!(
            (si - expected).abs() < 1e-5 * expected,
            "{si} vs {expected}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_hull_file_exports_too() {
    let dir = common::folder("database-cli-section-pontoon");
    let hull = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../examples/hulls/pontoon.xml");
    let prefix = dir.join("pontoon");
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        text(&hull),
        "--kr",
        "0.1:2:4",
        "-o",
        text(&dir.join("t.csv")),
        "--wamit",
        text(&prefix),
    ]);
    assert!(ok, "{err}");
    let (ok, table, err) = fmu_pack(&["sweep", text(&dir.join("pontoon.1")), "-o", "-"]);
    assert!(ok, "{err}");
    assert!(table.contains("# modes: sway heave roll"), "{table}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unwritable_export_paths_are_named() {
    let dir = common::folder("database-cli-section-unwritable");
    let missing = dir.join("no-such-folder");
    for (flag, path, shown) in [
        ("--wamit", missing.join("x"), missing.join("x.1")),
        ("--netcdf", missing.join("x.nc"), missing.join("x.nc")),
    ] {
        let (ok, _, err) = fmu_pack(&[
            "sweep",
            "semicircle",
            "--kr",
            "1:1:1",
            "-o",
            text(&dir.join("t.csv")),
            flag,
            text(&path),
        ]);
        assert!(!ok, "{flag}");
        assert!(
            err.contains(&format!(
                "cannot write {}: the folder {} does not exist",
                shown.display(),
                missing.display()
            )),
            "{flag}: {err}"
        );
        // Refused before the sweep: not even the table was written.
        assert!(!dir.join("t.csv").exists(), "{flag}");
    }
    // pack: the archive's folder, checked before the sweep and the fit.
    let archive = missing.join("X.fmu");
    let (ok, _, err) = fmu_pack(&["pack", "semicircle", "-o", text(&archive)]);
    assert!(!ok);
    assert!(
        err.contains(&format!("cannot write {}: the folder", archive.display())),
        "{err}"
    );
    // An elastic DOF with a WAMIT rigid mode's name: refused before the sweep, by name.
    let hull = dir.join("box.xml");
    std::fs::write(
        &hull,
        r#"<hull name="box" half_beam="1" units="m">
  <contour closed="false">
    <point x="-1" y="0"/><point x="-1" y="-1"/><point x="1" y="-1"/><point x="1" y="0"/>
  </contour>
  <mode name="pitch"><u x="0" y="0"/><u x="0" y="1"/><u x="0" y="1"/><u x="0" y="0"/></mode>
</hull>"#,
    )
    .unwrap();
    let csv = dir.join("box.csv");
    let (ok, _, err) = fmu_pack(&["sweep", text(&hull), "-o", text(&csv), "--wamit", "x"]);
    assert!(
        !ok && err.contains("box: cannot export the section: DOF 'pitch'"),
        "{err}"
    );
    assert!(!csv.exists(), "no table written");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pack_drift_takes_an_imported_drift_and_refuses_without_one() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-db-drift-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let prefix = dir.join("slice");
    // A section's 1 m slice as WAMIT files, its fixed drift in slice.9.
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        "semicircle",
        "--dofs",
        "sway,heave,roll",
        "--panels",
        "32",
        "--kr",
        "0.05:5:40",
        "-o",
        dir.join("t.csv").to_str().unwrap(),
        "--wamit",
        prefix.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(dir.join("slice.9").is_file());
    let binary = common::stand_in_binary(&dir);
    let pack = |name: &str| {
        let archive = dir.join(name);
        let out = fmu_pack(&[
            "pack",
            dir.join("slice.1").to_str().unwrap(),
            "--drift",
            "--allow-tolerance-miss",
            "--binary",
            binary.to_str().unwrap(),
            "-o",
            archive.to_str().unwrap(),
        ]);
        (archive, out)
    };
    let (archive, (ok, _, err)) = pack("Slice.fmu");
    assert!(ok, "{err}");
    let text = common::archive_member(&archive, "resources/drift.csv").unwrap();
    assert!(text.contains("\nkR,j,heading,value\n"), "{text}");
    let description = common::archive_member(&archive, "modelDescription.xml").unwrap();
    assert!(description.contains("name=\"wave.drift\""));
    assert!(description.contains("name=\"force_drift.sway\""));
    // Without the drift file: refused, saying where the drift comes from.
    std::fs::remove_file(dir.join("slice.9")).unwrap();
    let (_, (ok, _, err)) = pack("Again.fmu");
    assert!(
        !ok && err.contains("--drift: slice has no mean drift"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
