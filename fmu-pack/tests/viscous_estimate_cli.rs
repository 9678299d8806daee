//! `fmu-pack pack --viscous` without entries packs the section's estimate (Ikeda's roll
//! damping, the cross-flow drag), entries given replace it one by one; `fmu-pack sweep --rao
//! --viscous-amplitude` adds the linearized roll damping to the motion.

use hydrofmu::hull::Hull;
use hydrofmu::viscous;
use std::path::{Path, PathBuf};

mod common;
use common::fmu_pack;

/// The semicircle of radius 1 m with its nine DOFs (as `semicircle_9dof.xml`), floating with
/// G 0.3 m below the waterline, and bilge keels.
const KEELED: &str =
    "<hull name=\"keeled\" half_beam=\"1\">\n  <circle radius=\"1\" depth=\"0\"/>\n  \
     <rigid name=\"sway\" kind=\"sway\"/>\n  <rigid name=\"heave\" kind=\"heave\"/>\n  \
     <rigid name=\"roll\" kind=\"roll\"/>\n  <craig_bampton name=\"cb1\" mode=\"1\"/>\n  \
     <craig_bampton name=\"cb2\" mode=\"2\"/>\n  <craig_bampton name=\"cb3\" mode=\"3\"/>\n  \
     <craig_bampton name=\"cb4\" mode=\"4\"/>\n  <craig_bampton name=\"cb5\" mode=\"5\"/>\n  \
     <craig_bampton name=\"cb6\" mode=\"6\"/>\n  \
     <mass value=\"displaced\" x=\"0\" y=\"-0.3\" radius_of_gyration=\"0.4\"/>\n  \
     <bilge_keels breadth=\"0.05\" length_fraction=\"0.6\"/>\n</hull>\n";

fn example(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(path)
        .display()
        .to_string()
}

/// Packs `hull` with the nine-DOF network and `extra`: (success, archive, stdout, stderr).
fn pack(dir: &Path, hull: &str, name: &str, extra: &[&str]) -> (bool, PathBuf, String, String) {
    let archive = dir.join(name);
    let binary = common::stand_in_binary(dir);
    let network = example("networks/semicircle_9dof.xml");
    let mut args = vec![
        "pack",
        hull,
        "--network",
        network.as_str(),
        "--binary",
        binary.to_str().unwrap(),
        "-o",
        archive.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (ok, out, err) = fmu_pack(&args);
    (ok, archive, out, err)
}

/// `viscous.csv`'s rows by DOF: (B_q, row of B_l).
fn rows(archive: &Path) -> Vec<(String, f64, Vec<f64>)> {
    let text = common::archive_member(archive, "resources/viscous.csv").unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("dof,") && !l.starts_with("frame,"))
        .map(|line| {
            let mut fields = line.split(',');
            let dof = fields.next().unwrap().to_string();
            let numbers: Vec<f64> = fields.map(|f| f.parse().unwrap()).collect();
            (dof, numbers[0], numbers[1..].to_vec())
        })
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs().max(1e-300)
}

#[test]
fn the_estimate_is_the_default_and_entries_given_replace_it() {
    let dir = common::folder("viscous-estimate");
    let hull_path = dir.join("keeled.xml");
    std::fs::write(&hull_path, KEELED).unwrap();
    let hull_arg = hull_path.to_str().unwrap();
    let flags = [
        "--viscous",
        "--roll-frequency",
        "2",
        "--roll-amplitude",
        "15",
    ];
    let (ok, estimated, out, err) = pack(&dir, hull_arg, "Estimated.fmu", &flags);
    assert!(ok, "{err}");
    let hull = Hull::from_xml_str(KEELED, "keeled.xml").unwrap();
    let (_, damping) = viscous::hull_roll_damping(&hull, 1025.0, 2.0, 15f64.to_radians()).unwrap();
    let total = damping.total();
    let drag = viscous::section_drag(&hull, 1025.0).unwrap();
    let table = rows(&estimated);
    assert_eq!(table.len(), 9);
    assert!(close(table[0].1, drag[0].quadratic) && close(table[1].1, drag[1].quadratic));
    assert!(close(table[2].1, total.quadratic) && close(table[2].2[2], total.linear));
    assert!(total.linear > damping.friction.linear && damping.bilge_keel.quadratic > 0.0);
    // Everything else is 0: the off-diagonals, the translations' B_l, the elastic modes.
    let nonzero = table
        .iter()
        .map(|(_, q, l)| l.iter().chain([q]).filter(|v| **v != 0.0).count())
        .sum::<usize>();
    assert_eq!(nonzero, 4);
    for words in [
        "roll: Ikeda at zero speed",
        "OG 0.3000 m (the centre of gravity), bilge keels 0.05 m on 0.6 of the length",
        "at 2.0000 rad/s (--roll-frequency) and 15 deg",
        "warning: breadth/draft = 2",
        "sway: cross-flow drag, C_D 1.0250",
        "B_q = 0.5 rho C_D B",
    ] {
        assert!(out.contains(words), "{words} missing from:\n{out}");
    }

    // Entries given replace the estimate's, one by one.
    let flags = [
        "--viscous",
        "--damping-quadratic",
        "roll=5,heave=0",
        "--damping-linear",
        "sway=7",
    ];
    let (ok, replaced, out, err) = pack(&dir, hull_arg, "Replaced.fmu", &flags);
    assert!(ok, "{err}");
    assert!(
        out.contains("the roll natural frequency of <mass>"),
        "{out}"
    );
    let table = rows(&replaced);
    assert_eq!((table[2].1, table[1].1, table[0].2[0]), (5.0, 0.0, 7.0));
    assert!(close(table[0].1, drag[0].quadratic));
    let omega = viscous::roll_natural_frequency(&hull, 1025.0, 9.81).unwrap();
    let (_, at_resonance) =
        viscous::hull_roll_damping(&hull, 1025.0, omega, 10f64.to_radians()).unwrap();
    assert!(close(table[2].2[2], at_resonance.total().linear));

    // --no-estimate: the entries given, the others 0.
    let flags = ["--viscous", "--no-estimate", "--damping-linear", "roll=3"];
    let (ok, bare, out, err) = pack(&dir, hull_arg, "Bare.fmu", &flags);
    assert!(ok, "{err}");
    assert!(out.contains("--no-estimate"), "{out}");
    let table = rows(&bare);
    let nonzero = table
        .iter()
        .map(|(_, q, l)| l.iter().chain([q]).filter(|v| **v != 0.0).count())
        .sum::<usize>();
    assert_eq!((nonzero, table[2].2[2]), (1, 3.0));

    // A submerged body has no estimate; the options need --viscous; amplitudes are checked.
    let pontoon = example("hulls/pontoon.xml");
    let bad = [
        (
            pontoon.as_str(),
            &["--viscous"][..],
            "the contour is closed",
        ),
        (pontoon.as_str(), &["--viscous"][..], "--no-estimate"),
        (hull_arg, &["--roll-amplitude", "5"][..], "--viscous"),
        (
            hull_arg,
            &["--viscous", "--roll-amplitude", "95"][..],
            "expected an amplitude in (0, 90) deg",
        ),
        (
            hull_arg,
            &["--viscous", "--roll-frequency", "0"][..],
            "--roll-frequency 0",
        ),
    ];
    for (hull, flags, expected) in bad {
        let (ok, archive, _, err) = pack(&dir, hull, "Bad.fmu", flags);
        assert!(!ok && err.contains(expected), "{flags:?}: {err}");
        assert!(!archive.exists());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The largest roll RAO |xi_roll R / a| of `fmu-pack sweep HULL --rao` with `extra`, and the
/// table's text.
fn peak_roll(dir: &Path, hull: &str, name: &str, extra: &[&str]) -> (f64, String) {
    let rao = dir.join(name);
    let table = dir.join("table.csv");
    let mut args = vec![
        "sweep",
        hull,
        "--kr",
        "0.47:0.53:13",
        "--panels",
        "32",
        "--rao",
        rao.to_str().unwrap(),
        "-o",
        table.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (ok, _, err) = fmu_pack(&args);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&rao).unwrap();
    let peak = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("kR"))
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[1] == "3" && f[2] == "0")
        .map(|f| f[3].parse::<f64>().unwrap().hypot(f[4].parse().unwrap()))
        .fold(0.0, f64::max);
    (peak, text)
}

#[test]
fn viscous_roll_damping_lowers_the_roll_resonance_of_a_floating_section() {
    let dir = common::folder("viscous-rao");
    let hull = example("hulls/sundsdal_floating.xml");
    let (plain, text) = peak_roll(&dir, &hull, "plain.csv", &[]);
    assert!(!text.contains("viscous roll damping"));
    let (damped, text) = peak_roll(&dir, &hull, "damped.csv", &["--viscous-amplitude", "10"]);
    assert!(
        text.contains(
            "viscous roll damping added: Ikeda at zero speed (docs/VISCOUS.md) \
                       linearized at roll amplitude 10 deg"
        ),
        "{text}"
    );
    let (friction, _) = peak_roll(&dir, &hull, "still.csv", &["--viscous-amplitude", "0"]);
    // Measured (peak at kR 0.499): 10.73 undamped, 4.84 at 10 deg (0.45), 9.09 with friction
    // alone (0.85).
    assert!(damped < 0.5 * plain, "{damped} vs {plain}");
    assert!(
        friction > 0.8 * plain && friction < 0.9 * plain,
        "{friction} vs {plain}"
    );
    let (ok, _, err) = fmu_pack(&["sweep", &hull, "--viscous-amplitude", "10", "-o", "-"]);
    assert!(!ok && err.contains("--rao"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_ship_packs_its_sections_estimates_integrated_along_it() {
    let dir = common::folder("viscous-ship");
    let ship_path = example("ships/barge.xml");
    let archive = dir.join("Ship.fmu");
    let binary = common::stand_in_binary(&dir);
    let (ok, out, err) = fmu_pack(&[
        "pack",
        &ship_path,
        "--omega",
        "0.2:2:8",
        "--panels",
        "16",
        "--allow-tolerance-miss",
        "--viscous",
        "--roll-frequency",
        "0.7",
        "--roll-amplitude",
        "12",
        "--damping-quadratic",
        "sway=1",
        "--binary",
        binary.to_str().unwrap(),
        "-o",
        archive.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(
        out.contains("ship: its sections' estimates integrated along the stations"),
        "{out}"
    );
    let ship = hydrofmu::ship::Ship::from_file(Path::new(&ship_path)).unwrap();
    let estimate = viscous::ship_estimate(&ship, 1025.0, 0.7, 12f64.to_radians()).unwrap();
    let get = |name: &str| estimate.dofs.iter().find(|d| d.0 == name).unwrap().1;
    let table = rows(&archive);
    let row = |name: &str| table.iter().position(|r| r.0 == name).unwrap();
    let (roll, yaw, sway) = (row("roll"), row("yaw"), row("sway"));
    assert!(close(table[roll].1, get("roll").quadratic));
    assert!(close(table[roll].2[roll], get("roll").linear));
    // Yaw's drag is the cross-flow strips': its per-DOF coefficient is 0, and the strips
    // with a yaw rate alone give the estimate's yaw coefficient.
    assert_eq!(table[yaw].1, 0.0);
    let text = common::archive_member(&archive, "resources/crossflow.csv").unwrap();
    let strips = hydrofmu::model::crossflow::parse_csv(&text).unwrap();
    assert_eq!(strips, estimate.strips);
    let yaw_strips: f64 = strips
        .iter()
        .map(|s| 1025.0 * s.lateral() * s.x.abs().powi(3))
        .sum();
    assert!((yaw_strips - get("yaw").quadratic).abs() < 1e-12 * yaw_strips);
    // The entry given is added to the strips.
    assert_eq!(table[sway].1, 1.0);
    std::fs::remove_dir_all(&dir).unwrap();
}
