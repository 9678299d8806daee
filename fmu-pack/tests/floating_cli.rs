//! A floating section from its hull file's `<mass>` element: the same tables as the command
//! line's mass options, options that replace the file's fields, `--fixed`, and the floating
//! drift packed into an archive.

mod common;
use common::fmu_pack;
use std::path::{Path, PathBuf};

/// The semicircle of R = 1 m with rigid DOFs and `mass` (a `<mass>` element or nothing).
fn write_hull(dir: &Path, mass: &str) -> PathBuf {
    let path = dir.join("float.xml");
    std::fs::write(
        &path,
        format!(
            "<hull name=\"semicircle\" half_beam=\"1\">\n  <circle radius=\"1\" depth=\"0\"/>\n  \
             <rigid name=\"sway\" kind=\"sway\"/>\n  <rigid name=\"heave\" kind=\"heave\"/>\n  \
             <rigid name=\"roll\" kind=\"roll\"/>\n{mass}</hull>\n"
        ),
    )
    .unwrap();
    path
}

const MOORED: &str =
    "  <mass value=\"displaced\" x=\"0\" y=\"-0.2\" radius_of_gyration=\"0.3\">\n    \
     <mooring dof=\"sway\" stiffness=\"100\"/>\n  </mass>\n";

/// Runs `fmu-pack sweep HULL --kr 0.01:1:3 --panels 32 --rao R --drift D EXTRA..` and returns
/// (rao, drift) texts.
fn sweep(dir: &Path, hull: &str, extra: &[&str]) -> Result<(String, String), String> {
    let (rao, drift) = (dir.join("rao.csv"), dir.join("drift.csv"));
    let mut args = vec![
        "sweep",
        hull,
        "--kr",
        "0.01:1:3",
        "--panels",
        "32",
        "-o",
        "/dev/null",
        "--rao",
        rao.to_str().unwrap(),
        "--drift",
        drift.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (ok, _, err) = fmu_pack(&args);
    if !ok {
        return Err(err);
    }
    Ok((
        std::fs::read_to_string(rao).unwrap(),
        std::fs::read_to_string(drift).unwrap(),
    ))
}

/// The `# body:` line and the rows after the column line.
fn body_and_rows(text: &str) -> (String, Vec<String>) {
    let body = text
        .lines()
        .find(|l| l.starts_with("# body:"))
        .unwrap_or_default()
        .to_string();
    let rows = text
        .lines()
        .skip_while(|l| !l.starts_with("kR,"))
        .map(str::to_string)
        .collect();
    (body, rows)
}

#[test]
fn a_hull_files_mass_gives_the_tables_of_the_same_command_line_options() {
    let dir = common::folder("floating-file");
    let hull = write_hull(&dir, MOORED);
    let from_file = sweep(&dir, hull.to_str().unwrap(), &[]).unwrap();
    let options = [
        "--mass",
        "displaced",
        "--cog",
        "0,-0.2",
        "--gyradius",
        "0.3",
        "--mooring",
        "sway=100",
    ];
    let from_options = sweep(
        &dir,
        "semicircle",
        &[&["--dofs", "sway,heave,roll"], &options[..]].concat(),
    )
    .unwrap();
    for (file, option) in [
        (&from_file.0, &from_options.0),
        (&from_file.1, &from_options.1),
    ] {
        let (body, rows) = body_and_rows(file);
        assert!(body.starts_with("# body: floating; mass "), "{body}");
        assert!(body.contains("external stiffness 1,1=100;"), "{body}");
        assert_eq!((body, rows), body_and_rows(option));
    }
    // An option replaces the file's field: a stiffer mooring, another motion.
    let (rao, _) = sweep(&dir, hull.to_str().unwrap(), &["--mooring", "sway=5000"]).unwrap();
    let (body, rows) = body_and_rows(&rao);
    assert!(body.contains("external stiffness 1,1=5000;"), "{body}");
    assert!(body.contains("centre of gravity (0, -0.2) m"), "{body}");
    assert_ne!(rows, body_and_rows(&from_file.0).1);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn fixed_holds_a_section_whose_file_gives_mass_and_refuses_mass_options() {
    let dir = common::folder("floating-fixed");
    let hull = write_hull(&dir, MOORED);
    let hull = hull.to_str().unwrap();
    let drift = dir.join("drift.csv");
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        hull,
        "--kr",
        "0.5:1:2",
        "--panels",
        "32",
        "-o",
        "/dev/null",
        "--drift",
        drift.to_str().unwrap(),
        "--fixed",
    ]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&drift).unwrap();
    assert!(text.contains("\n# body: fixed;"), "{text}");
    for (extra, message) in [
        (
            &["--fixed", "--mass", "10"][..],
            "--fixed holds the section",
        ),
        (
            &["--fixed", "--rao", "/dev/null"][..],
            "--rao is the motion of a floating section; --fixed holds it",
        ),
    ] {
        let mut args = vec!["sweep", hull, "--kr", "1:1:1", "-o", "/dev/null"];
        args.extend_from_slice(extra);
        let (ok, _, err) = fmu_pack(&args);
        assert!(!ok && err.contains(message), "{extra:?}: {err}");
    }
    // A bad element names the file, its line and the field.
    let bad = write_hull(
        &dir,
        "<mass value=\"displaced\" x=\"0\" y=\"-0.2\" radius_of_gyration=\"-1\"/>\n",
    );
    let (ok, _, err) = fmu_pack(&["sweep", bad.to_str().unwrap(), "-o", "/dev/null"]);
    assert!(
        !ok && err.contains("float.xml:6: radius_of_gyration=\"-1\" in <mass> must be >= 0"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pack_drift_packs_the_floating_sections_drift() {
    let dir = common::folder("floating-pack");
    let hull = write_hull(&dir, MOORED);
    let binary = common::stand_in_binary(&dir);
    let pack = |dofs: &str, extra: &[&str]| {
        let archive = dir.join("Float.fmu");
        let mut args = vec![
            "pack",
            hull.to_str().unwrap(),
            "--dofs",
            dofs,
            "--panels",
            "32",
            "--allow-tolerance-miss",
            "--binary",
            binary.to_str().unwrap(),
            "-o",
            archive.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (ok, _, err) = fmu_pack(&args);
        if !ok {
            return Err(err);
        }
        Ok(common::archive_member(&archive, "resources/drift.csv").unwrap())
    };
    let floating = pack("sway", &["--drift"]).unwrap();
    assert!(
        floating.contains("\n# body: floating; mass ") && floating.contains("# modes: sway\n"),
        "{floating}"
    );
    let fixed = pack("sway", &["--drift", "--fixed"]).unwrap();
    assert!(fixed.contains("\n# body: fixed;"), "{fixed}");
    // The floating section's sway drift differs from the fixed one's.
    assert_ne!(body_and_rows(&floating).1, body_and_rows(&fixed).1);
    let err = pack("sway", &["--mass", "10"]).unwrap_err();
    assert!(err.contains("add --drift"), "{err}");
    // A ship's drift is its own: mass options are refused, not ignored.
    let barge = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/ships/barge.xml");
    let archive = dir.join("Barge.fmu");
    let (ok, _, err) = fmu_pack(&[
        "pack",
        barge,
        "--drift",
        "--mass",
        "10",
        "-o",
        archive.to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("choose a floating section"), "{err}");
    // Heave and roll drift of the moving section by its pressure integration.
    let all = pack("sway,heave,roll", &["--drift"]).unwrap();
    assert!(
        all.contains("\n# body: floating; mass ") && all.contains("# modes: sway heave roll\n"),
        "{all}"
    );
    let (_, rows) = body_and_rows(&all);
    let (_, sway_rows) = body_and_rows(&floating);
    // The sway rows are the sway-only archive's (the same motion of the whole hull).
    let sway_of_all: Vec<&String> = rows
        .iter()
        .skip(1)
        .filter(|l| l.split(',').nth(1) == Some("1"))
        .collect();
    assert_eq!(sway_of_all, sway_rows.iter().skip(1).collect::<Vec<_>>());
    assert_eq!(rows.len() - 1, 3 * (sway_rows.len() - 1));
    assert!(rows
        .iter()
        .skip(1)
        .all(|l| l.split(',').all(|v| v.parse::<f64>().unwrap().is_finite())));
    let _ = std::fs::remove_dir_all(&dir);
}
