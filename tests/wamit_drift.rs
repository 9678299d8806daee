//! WAMIT mean drift files (`NAME.8`, `NAME.9`): a section's drift written and read back, the
//! scaling with ULEN, which file gives which mode, and malformed files refused or left out
//! with a note.

use hydrofmu::database::import::{self, ImportParams};
use hydrofmu::database::section::SectionDatabase;
use hydrofmu::database::wamit::{self, Source, WamitParams, WamitTexts};
use hydrofmu::database::Database;
use hydrofmu::{Hull, PanelParams, SweepParams};

/// The semicircle's 1 m slice with its fixed-section drift (coarse, 6 frequencies).
fn section() -> Database {
    let hull = Hull::semicircle(1.0)
        .unwrap()
        .select_dofs(&["sway", "heave", "roll"])
        .unwrap();
    let params = SweepParams {
        kr: vec![0.2, 0.5, 1.0, 1.5, 2.0, 3.0],
        panels: PanelParams {
            body_panels: 32,
            ..PanelParams::default()
        },
        ..SweepParams::default()
    };
    let sweep = hydrofmu::sweep::run(&hull, &params, &|_, _| {}).unwrap();
    SectionDatabase::from_sweep(&hull, &sweep, 1025.0, 9.81)
        .unwrap()
        .database
}

/// A one-mode radiation file (heave, mode 3) at periods 10 and 5 s.
const RADIATION: &str = "10.0 3 3 1.0 0.5\n5.0 3 3 1.1 0.6\n";

/// Reads `RADIATION` with the drift texts, ULEN `length`.
fn read(momentum: Option<&str>, pressure: Option<&str>, length: f64) -> Result<Database, String> {
    let params = WamitParams {
        length_scale: length,
        ..WamitParams::default()
    };
    let texts = WamitTexts {
        radiation: Source {
            name: "body.1",
            text: RADIATION,
        },
        excitation: None,
        hydrostatics: None,
    };
    let imported = wamit::read("body", texts, &params).map_err(|e| e.to_string())?;
    let mut database = imported.database;
    wamit::read_drift(
        &mut database,
        &imported.modes,
        momentum.map(|text| Source {
            name: "body.8",
            text,
        }),
        pressure.map(|text| Source {
            name: "body.9",
            text,
        }),
        &params,
    )
    .map_err(|e| e.to_string())?;
    Ok(database)
}

#[test]
fn a_sections_drift_survives_the_wamit_files() {
    let database = section();
    assert_eq!(database.drift.len(), 6);
    assert_eq!(database.drift_headings, [-90.0, 90.0]);
    let dir = std::env::temp_dir().join(format!("hydrofmu-wamit-drift-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let files = wamit::write(&database);
    std::fs::write(dir.join("slice.1"), &files.radiation).unwrap();
    std::fs::write(dir.join("slice.3"), files.excitation.as_ref().unwrap()).unwrap();
    std::fs::write(dir.join("slice.9"), files.drift.as_ref().unwrap()).unwrap();
    std::fs::write(dir.join("slice.hst"), &files.hydrostatics).unwrap();
    let read = import::import(&dir.join("slice.1"), &ImportParams::new()).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(read.drift_headings, database.drift_headings);
    assert_eq!(read.omega.len(), database.omega.len());
    let largest = database
        .drift
        .iter()
        .flat_map(|d| d.iter().map(|x| x.abs()))
        .fold(0.0, f64::max);
    // The files' 10 significant digits.
    for (a, b) in database.drift.iter().zip(&read.drift) {
        assert!((a - b).amax() <= 1e-9 * largest, "{a} {b}");
    }
    // The waves towards +y (beta 90, the section's heading 0) push it towards +y: sway.
    let sway = read.dof_names.iter().position(|d| d == "sway").unwrap();
    assert!(read
        .drift
        .iter()
        .all(|d| d[(sway, 1)] > 0.0 && d[(sway, 0)] < 0.0));
}

#[test]
fn drift_files_scale_with_ulen_and_the_momentum_file_gives_its_modes() {
    let pressure = "10.0 0.0 0.0 3 0.25 0.0 0.25 0.0\n5.0 0.0 0.0 3 0.5 180.0 -0.5 0.0\n";
    // D = Dbar rho g L^(1 + e): heave is a force (e = 0).
    let database = read(None, Some(pressure), 2.0).unwrap();
    let rho_g = 1025.0 * 9.81;
    // Frequencies ascending: 2 pi / 10 first.
    assert_eq!(database.drift[0][(0, 0)], 0.25 * rho_g * 2.0);
    assert_eq!(database.drift[1][(0, 0)], -0.5 * rho_g * 2.0);
    let momentum = "10.0 0.0 0.0 3 0.75 0.0 0.75 0.0\n5.0 0.0 0.0 3 0.5 0.0 0.5 0.0\n";
    let both = read(Some(momentum), Some(pressure), 1.0).unwrap();
    assert_eq!(both.drift[0][(0, 0)], 0.75 * rho_g);
    // Bidirectional rows and body-fixed moments are left out, said in the notes.
    let extra =
        format!("{pressure}10.0 0.0 30.0 3 0.1 0.0 0.1 0.0\n10.0 0.0 0.0 -4 0.1 0.0 0.1 0.0\n");
    let database = read(None, Some(&extra), 1.0).unwrap();
    assert_eq!(database.drift[0][(0, 0)], 0.25 * rho_g);
    let notes = database.notes.join("\n");
    assert!(notes.contains("body.9: 1 bidirectional rows"), "{notes}");
    assert!(
        notes.contains("body.9: 1 rows of body-fixed moments"),
        "{notes}"
    );
}

#[test]
fn malformed_drift_files_are_refused_or_left_out_with_a_note() {
    let refused = |text: &str| read(None, Some(text), 1.0).unwrap_err();
    let e = refused("10.0 0.0 0.0 3 0.25 0.0 0.25\n");
    assert!(e.starts_with("body.9:1:") && e.contains("7 fields"), "{e}");
    let e = refused("10.0 0.0 0.0 3 0.25 0.0 0.25 0.1\n");
    assert!(
        e.contains("field Im (column 8): 0.1 where a mean drift is real"),
        "{e}"
    );
    let e = refused("10.0 0.0 0.0 3 0.25 0.0 0.25 0.0\n10.0 0.0 0.0 3 0.25 0.0 0.25 0.0\n");
    assert!(
        e.starts_with("body.9:2:") && e.contains("written twice"),
        "{e}"
    );
    let e = refused("10.0 0.0 0.0 3 nan 0.0 0.25 0.0\n");
    assert!(e.contains("field Mod (column 5)"), "{e}");
    let e = refused("-1 0.0 0.0 3 0.25 0.0 0.25 0.0\n");
    assert!(e.contains("is a limit; the mean drift has none"), "{e}");
    // A file that misses a frequency of the radiation file: no drift, and a note says why.
    let database = read(None, Some("10.0 0.0 0.0 3 0.25 0.0 0.25 0.0\n"), 1.0).unwrap();
    assert!(database.drift.is_empty());
    assert!(
        database
            .notes
            .iter()
            .any(|n| n.contains("mean drift left out: heave lacks 1 of its 2 values")),
        "{:?}",
        database.notes
    );
}
